"""Sizes from a band (issue 13): what Mechanism.sized chooses for the paper's Table I link at a
band of 300 rad/s, held clamped-free, clamped-clamped and free-free, with consistent and lumped
element mass, against the exact Timoshenko frequencies (phmech.timoshenko), beside the fewest
elements that meet the tolerance and the per-link choice of Mechanism(band=...)
(phmech.mesh.choose_elements, the free link's estimate). Thread CPU of one sized() call each.

    OPENBLAS_NUM_THREADS=1 .venv/bin/python benchmarks/sizing.py

Writes benchmarks/results/sizing.json and sizing.png."""
import os
import sys
import time
import warnings

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, "..", "tests"))
import run as B  # noqa: E402
import test_mesh as T  # noqa: E402  (held(), support_error(): the tests' own references)

import phmech as ph  # noqa: E402
from phmech import mesh  # noqa: E402


def main() -> dict:
    rows = []
    for mass in ("consistent", "lumped"):
        for tol in (1e-2, 1e-3):
            t = time.thread_time()
            per_link = mesh.choose_elements(1.0, ph.table1_properties(), T.BAND, tol, mass=mass)
            c_link = time.thread_time() - t
            for support in T.SUPPORTS:
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore", ph.UnattachedWarning)   # free-free: on purpose
                    m = T.held(4, support, mass)
                    t = time.thread_time()
                    m2 = m.sized(band=T.BAND, tolerance=tol)
                    cpu = time.thread_time() - t
                N = m2.sizing.elements["beam"]
                fewest = next(n for n in range(2, 400) if T.support_error(n, support, mass) <= tol)
                row = dict(mass=mass, tolerance=tol, support=support, sized=N,
                           exact_error=T.support_error(N, support, mass),
                           error_bound=m2.sizing.estimated_error, fewest=fewest, ratio=N / fewest,
                           sized_cpu_s=cpu, per_link_choice=per_link.elements,
                           per_link_exact_error=T.support_error(per_link.elements, support, mass),
                           per_link_cpu_s=c_link, meshes_built=m2.sizing.tried)
                rows.append(row)
                print(f"{mass:10s} {support:16s} {tol:g}: sized {N} (exact {row['exact_error']:.2e}, "
                      f"bound {row['error_bound']:.2e}, {cpu:.3f} s), fewest {fewest} (ratio "
                      f"{row['ratio']:.2f}); Mechanism(band=) per link {per_link.elements} "
                      f"({c_link:.2f} s)", flush=True)
    out = dict(problem="Table I link (table1_properties(1.0)), band 300 rad/s, modes against the exact "
                       "Timoshenko frequencies of each support", machine=B.machine(), rows=rows)
    B.write_json("sizing", out)
    plot(rows)
    return out


def plot(rows) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(8, 4))
    labels = [f"{r['support']}\n{r['mass'][:4]} {r['tolerance']:g}" for r in rows]
    x = np.arange(len(rows))
    ax.bar(x - 0.27, [r["fewest"] for r in rows], 0.27, label="fewest meeting the tolerance")
    ax.bar(x, [r["sized"] for r in rows], 0.27, label="m.sized()")
    ax.bar(x + 0.27, [r["per_link_choice"] for r in rows], 0.27, label="Mechanism(band=) per link")
    ax.set_xticks(x, labels, fontsize=6, rotation=90)
    ax.set_ylabel("elements")
    ax.set_title("Table I link, band 300 rad/s: elements chosen")
    ax.legend(fontsize=7)
    fig.tight_layout()
    path = os.path.join(B.RESULTS, "sizing.png")
    fig.savefig(path, dpi=120)
    print(f"wrote {path}")


if __name__ == "__main__":
    main()

"""The paper's Table I, recomputed: a cantilever Timoshenko beam (L = 1 m, rhoA = 873 kg/m,
rhoI = 2.1797 kg m, EI = 5143 N m^2, kGA = 656625 N), first five natural frequencies.

Columns: exact (Huang's frequency equation), Golo's mixed element (the paper's, N = 9 and 21)
and phmech's nonlinear se3 link linearized (N = 9 and 21), with relative errors; then a
convergence study N = 2..200 for both (error against N and against the number of states, with
the observed order), saved as a plot.

    python examples/timoshenko_table.py            # table, study, plot
    python examples/timoshenko_table.py --json     # one JSON object on stdout
    python examples/timoshenko_table.py --quick    # a shorter study (N up to 50)
"""
from __future__ import annotations

import argparse
import json
import os
import sys
import time

import numpy as np

from phmech import studies


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--json", action="store_true", help="print one JSON object to stdout")
    ap.add_argument("--quick", action="store_true", help="convergence study up to N = 50 only")
    ap.add_argument("--plot", default=os.path.join("examples", "output", "timoshenko_convergence.png"),
                    help="where to save the convergence plot ('' for none)")
    args = ap.parse_args(argv)

    exact = studies.exact_frequencies(5)
    table = {"mixed": {}, "se3": {}}
    for N in (9, 21):
        table["mixed"][str(N)] = studies.mixed_frequencies(N).tolist()
        table["se3"][str(N)] = studies.se3_frequencies(N).tolist()
    errors = {d: {N: ((np.array(v) - exact) / exact).tolist() for N, v in table[d].items()}
              for d in table}

    Ns = [2, 3, 4, 6, 9, 13, 21, 30, 50] + ([] if args.quick else [75, 100, 150, 200])
    t0 = time.perf_counter()
    study = {d: studies.convergence(d, Ns) for d in ("mixed", "se3")}
    study_s = time.perf_counter() - t0

    result = {"exact": exact.tolist(), "mixed": table["mixed"], "se3": table["se3"],
              "relative_error": errors, "convergence": study, "study_wall_s": study_s,
              "units": "rad/s", "parameters": studies.TABLE1}

    if args.plot:
        plot(study, args.plot)
        result["plot"] = args.plot
    if args.json:
        json.dump(result, sys.stdout)
        print()
    else:
        print_table(exact, table, errors)
        for d in ("mixed", "se3"):
            order = ", ".join(f"{o:.2f}" for o in study[d]["order"])
            print(f"observed convergence order ({d}, N = {Ns[0]}..{Ns[-1]}, modes 1-5): {order}")
        if args.plot:
            print(f"plot saved to {args.plot}")
    return result


def print_table(exact, table, errors) -> None:
    head = f"{'mode':>4} {'exact':>12}" + "".join(
        f" {d + ' N=' + N:>14} {'err':>8}" for d in ("mixed", "se3") for N in ("9", "21"))
    print("Table I: cantilever Timoshenko beam, natural frequencies [rad/s]")
    print(head)
    for k in range(5):
        row = f"{k + 1:>4} {exact[k]:>12.4f}"
        for d in ("mixed", "se3"):
            for N in ("9", "21"):
                row += f" {table[d][N][k]:>14.4f} {100 * errors[d][N][k]:>7.2f}%"
        print(row)


def plot(study: dict, path: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import phmech.plot as pp

    os.makedirs(os.path.dirname(path) or ".", exist_ok=True)
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    styles = {"mixed": "--", "se3": "-"}
    for i, (d, s) in enumerate(study.items()):
        E = np.array(s["errors"])
        # colour = mode, line style = element: one legend entry per mode, one per element
        labels = [f"mode {k + 1}" for k in range(E.shape[1])] if i == 0 else None
        pp.convergence(s["N"], E, ax=axes[0], labels=labels, style=styles[d],
                       ylabel="|relative frequency error|")
        pp.convergence(s["states"], E, ax=axes[1], style=styles[d],
                       xlabel="first-order states (mixed: planar 4N; se3: 3-D 12N)",
                       ylabel="|relative frequency error|")
    for d, what in (("mixed", "mixed (planar, linear)"), ("se3", "se3 (3-D, nonlinear)")):
        axes[0].plot([], [], "k" + styles[d], label=what)
    axes[0].legend(fontsize=7, ncol=2, handlelength=3)
    fig.suptitle("Table I cantilever: convergence of the first five frequencies")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


if __name__ == "__main__":
    main()

"""Before/after element scaling of the default integrator (issue 31, "Large models"): the hanging
riser of benchmarks/bench_large.py (its ``--point``: fresh interpreter, defaults, T = 5 s, the
full run's span, whose steps are set by the accuracy, not the band) run by two installations of
phmech, interleaved point by point (before, after, before, after, ...) so that both see the
same load of a shared machine; CPU per simulated second, steps, Newton iterations and peak RSS per
N, the exponents over N = 30 ... 10 000 and 100 ... 10 000 and the local slopes.

    python benchmarks/scaling_ab.py --before /path/to/old/checkout [--after DIR] [--smoke]
    python benchmarks/scaling_ab.py --from-jsonl points.jsonl      # fit points already run

DIR: a checkout with its own ``.venv`` (``make build`` there); ``--after`` defaults to this
checkout. Each point's line of ``bench_large.py --point`` gets a ``variant`` ("before"/"after").
Writes ``benchmarks/results/scaling_ab.json`` (``--smoke``: N = 30, 100 over 0.2 s, this
checkout as both, ``scaling_ab_smoke.json``; tests/test_benchmarks_smoke.py).
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from bench_large import EXPONENT_RANGES as RANGES, fit_exponent, local_slopes  # noqa: E402
from run import machine, write_json  # noqa: E402

SIZES = (30, 100, 300, 1000, 3000, 10000)
T_FULL = 5.0


def point(checkout: str, N: int, T: float) -> dict:
    # this checkout: this interpreter; another: its own .venv's
    py = sys.executable if os.path.samefile(checkout, os.path.dirname(HERE)) else os.path.join(checkout, ".venv", "bin", "python")
    pr = subprocess.run([py, os.path.join(checkout, "benchmarks", "bench_large.py"), "--point", "phmech", str(N), repr(T), "0.0"],
                        capture_output=True, text=True, cwd=checkout, check=True)
    r = json.loads(pr.stdout.strip().splitlines()[-1])
    for k in ("t", "points"):
        r.pop(k, None)
    return r


def fits(runs: list) -> dict:
    """Per variant: exponents over RANGES (least squares in log-log), local slopes, and per N
    CPU/s, steps, Newton iterations, peak RSS (the last run of each N when repeated)."""
    out = {}
    for v in ("before", "after"):
        by_n = {r["N"]: r for r in runs if r["variant"] == v}
        rs = [by_n[n] for n in sorted(by_n)]
        if not rs:
            continue
        out[v] = dict(
            exponents={f"{lo}-{hi}": dict(exponent=fit_exponent([r for r in rs if lo <= r["N"] <= hi]),
                                          fitted_on=[r["N"] for r in rs if lo <= r["N"] <= hi]) for lo, hi in RANGES},
            local_slopes=local_slopes(rs),
            points={str(r["N"]): dict(cpu_per_sim_s=r["cpu_per_sim_s"], steps=r["steps"],
                                      newton_iterations=r["newton_iterations"], jacobians=r.get("jacobians"),
                                      maxrss_MB=r["maxrss_MB"], static_cpu_s=r["static_cpu_s"],
                                      us_per_element_step=1e6 * r["sim_cpu_s"] / (r["steps"] * r["N"])) for r in rs})
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--before", help="checkout (with .venv) of the code before")
    ap.add_argument("--after", default=os.path.dirname(HERE), help="checkout of the code after (default: this one)")
    ap.add_argument("--from-jsonl", help="fit these points (one bench_large --point line each, with 'variant')")
    ap.add_argument("--smoke", action="store_true", help="N = 30, 100 over 0.2 s, this checkout as both")
    ap.add_argument("--note", default="", help="stored with the result (e.g. the machine's load)")
    a = ap.parse_args()
    w0 = time.time()
    if a.from_jsonl:
        with open(a.from_jsonl) as f:
            runs = [json.loads(line) for line in f if line.strip()]
        sizes, T = sorted({r["N"] for r in runs}), runs[0]["T"]
    else:
        sizes, T = ((30, 100), 0.2) if a.smoke else (SIZES, T_FULL)
        before = a.after if a.smoke else a.before
        if not before:
            ap.error("--before is needed (or --smoke, or --from-jsonl)")
        runs = []
        for N in sizes:
            for v, ck in (("before", before), ("after", a.after)):
                r = point(ck, N, T)
                r["variant"] = v
                runs.append(r)
                print(f"{v:6s} N={N:6d}: CPU/s {r['cpu_per_sim_s']:.4g}, steps {r['steps']}, Newton "
                      f"{r['newton_iterations']}, RSS {r['maxrss_MB']:.0f} MB", flush=True)
    out = dict(problem="benchmarks/bench_large.py's riser, phmech defaults (bench_large.py --point phmech N T 0)",
               T=T, sizes=list(sizes), interleaved=not a.from_jsonl or "as in the file",
               load_average=list(os.getloadavg()), note=a.note, machine=machine(), fits=fits(runs), runs=runs,
               smoke=a.smoke, wall_s=time.time() - w0)
    write_json("scaling_ab_smoke" if a.smoke else "scaling_ab", out)
    print(json.dumps(out["fits"], indent=1))


if __name__ == "__main__":
    main()

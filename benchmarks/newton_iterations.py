"""Newton iterations per step of the default integrator on the released Table I cantilever
(issue 12; docs/integrators.md, "Newton iterations").

The scene of benchmarks/run.py's transient study: ``table1_properties(1.0)``, N elements, clamped,
bent by the static tip force 3 EI / 4 (world -z, ``static(steps=4)``) and released at rest;
``simulate(T, 0.005, initial=...)`` with the defaults (band 100 Hz, steps of 0.5 ms). Prints the
steps, Newton iterations (linear solves, rejected attempts included), Jacobians, Newton
failures, the ledger, the simulation's CPU (``time.thread_time``, median of ``--repeat`` runs
after a warm-up) and the largest tip error against IDA (configuration error test, rtol 1e-9).

    python benchmarks/newton_iterations.py [--N 100] [--T 0.2] [--repeat 5] [--no-reference]
"""
from __future__ import annotations

import argparse
import json
import os
import statistics
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

import numpy as np  # noqa: E402

from run import DT_OUT, F_TIP, phmech_cantilever  # noqa: E402

REFERENCE = dict(integrator="ida", error_test="configuration", rtol=1e-9, atol=1e-11, linear_solver="klu")


def released(N: int, T: float, **options):
    """(simulation CPU [s], result, link): the cantilever released from its static bend."""
    m, b = phmech_cantilever(N)
    st = m.static(loads=[(b.end, (0, 0, 0, 0, 0, -F_TIP), "world")], steps=4)
    t0 = time.thread_time()
    r = m.simulate(T, DT_OUT, initial=st, **options)
    return time.thread_time() - t0, r, b


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--N", type=int, default=100)
    ap.add_argument("--T", type=float, default=0.2)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--no-reference", action="store_true")
    ap.add_argument("--json", help="write the figures to this file")
    a = ap.parse_args()
    released(a.N, a.T)  # warm-up
    cpus = []
    for _ in range(a.repeat):
        c, r, b = released(a.N, a.T)
        cpus.append(c)
    s = r.stats
    out = dict(N=a.N, T=a.T, steps=s["steps"], newton_iters=s["nonlinear_iters"],
               newton_iters_per_step=s["newton_iters_per_step"], jacobian_evals=s["jacobian_evals"],
               newton_failures=s.get("nonlinear_conv_fails"), error_test_failures=s.get("error_test_fails"),
               ledger_relative=s["ledger_relative"], numerical_dissipation=s["numerical_dissipation"],
               cpu_median=statistics.median(cpus), cpu_runs=cpus)
    if not a.no_reference:
        cr, rr, br = released(a.N, a.T, **REFERENCE)
        tip, tip_r = r.tip(b)[:, [0, 2]], rr.tip(br)[:, [0, 2]]
        out["tip_error_m"] = float(np.max(np.hypot(*(tip - tip_r).T)))
        out["tip_amplitude_m"] = float(np.max(np.abs(tip_r[:, 1])))
        out["reference_cpu"] = cr
    for k, v in out.items():
        print(f"{k:24s} {v}")
    if a.json:
        with open(a.json, "w") as f:
            json.dump(out, f, indent=1)


if __name__ == "__main__":
    main()

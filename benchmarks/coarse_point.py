"""The per-call cost of a small scene: issue 13's coarsest transient point (benchmarks/run.py),
split into build, static solve and simulate, thread-CPU medians after a warm-up.

The released Table I cantilever with 3 elements of consistent mass: static tip force in one load
step, then 1 s with the fixed-step generalized-alpha (10 ms, landing on the 5 ms outputs: 200
steps), in-plane. Run: OPENBLAS_NUM_THREADS=1 .venv/bin/python benchmarks/coarse_point.py [REPS]
(default 300). Measured 2026-11-27 (docs/performance.md, session 12): build 0.20, static 0.36,
simulate 1.29, total 1.88 ms (2.94 ms before that session)."""
import os
import statistics
import sys
import time
import warnings

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
warnings.simplefilter("ignore")
import run as B  # noqa: E402


def one():
    t0 = time.thread_time()
    m, b = B.phmech_cantilever(3, "consistent")
    t1 = time.thread_time()
    st = m.static(loads=[(b.end, (0, 0, 0, 0, 0, -B.F_TIP), "world")], steps=1)
    t2 = time.thread_time()
    r = m.simulate(1.0, B.DT_OUT, rtol=1e-4, initial=st, linear_solver="klu",
                   integrator="generalized-alpha", step=1e-2, rho_inf=0.9)
    t3 = time.thread_time()
    return (t1 - t0, t2 - t1, t3 - t2), r


def main():
    reps = int(sys.argv[1]) if len(sys.argv) > 1 else 300
    for _ in range(20):
        one()
    rows = [one() for _ in range(reps)]
    med = [statistics.median(x[0][i] for x in rows) * 1e3 for i in range(3)]
    st = rows[-1][1].stats
    print("build %.3f ms, static %.3f ms, simulate %.3f ms (core %.3f ms), total %.3f ms; "
          "%d steps, %d Newton iterations, planar %s"
          % (*med, st["wall_time"] * 1e3, sum(med), st["steps"], st["nonlinear_iters"], st["planar"]))


if __name__ == "__main__":
    main()

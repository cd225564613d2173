"""CPU(planar)/CPU(3-D) of Mechanism.simulate on the released Table I cantilever (benchmarks/run.py's
transient: static tip force F_TIP, released at rest, dt_out 5 ms; bending in x-z, plane normal y):
thread_time medians of 5 repetitions, N = 20 and 100 elements, the default integrator and IDA
(rtol 1e-6, KLU, planar=True: planar=None keeps IDA in 3-D).

    .venv/bin/python benchmarks/bench_planar.py [T_END, default 1.0]

Measured 2026-11-27 (T = 1 s; IDA's KLU with AMD on the planar DAE): generalized-alpha 0.847
(N = 20) and 0.838 (N = 100); IDA 0.700 and 0.798; tips within 8e-9 L of the 3-D solve's,
ledgers equal to two digits (generalized-alpha) or within 10 % (IDA)."""
import sys, time, statistics, numpy as np, warnings
sys.path.insert(0, "benchmarks")
warnings.simplefilter("ignore")
import run as B
T = float(sys.argv[1]) if len(sys.argv) > 1 else 1.0
for N in (20, 100):
    m, b = B.phmech_cantilever(N)
    st = m.static(loads=[(b.end, (0, 0, 0, 0, 0, -B.F_TIP), "world")], steps=4)
    for integ, kw in (("generalized-alpha", {}), ("ida", dict(rtol=1e-6, linear_solver="klu"))):
        cpu, res = {}, {}
        for pl in (False, True):
            ts = []
            for rep in range(5):
                t0 = time.thread_time()
                r = m.simulate(T, B.DT_OUT, initial=st, integrator=integ, planar=pl, **kw)
                ts.append(time.thread_time() - t0)
            cpu[pl], res[pl] = statistics.median(ts), r
        d = np.max(np.abs(res[True].tip(b) - res[False].tip(b))) / B.TABLE1["L"]
        print(f"N={N} {integ} {kw}: CPU 3-D {cpu[False]:.4f} s, planar {cpu[True]:.4f} s, ratio {cpu[True]/cpu[False]:.3f}; "
              f"steps {res[False].stats['steps']}/{res[True].stats['steps']}, max tip diff {d:.2e} L, "
              f"ledger {res[False].stats['ledger_relative']:.2e}/{res[True].stats['ledger_relative']:.2e}", flush=True)

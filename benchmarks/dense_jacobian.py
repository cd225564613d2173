"""IDA with the dense LU against IDA with KLU: CPU, steps, Jacobians, residuals and how far apart
the two runs end (docs/integrators.md, "IDA's linear solvers: one Jacobian").

The cases: the Fig. 3 manipulator (examples/manipulator.py, 8 elements per link, 0.05 s) and the
scenes of benchmarks/scenes.py over short horizons (IDA with every state in its error test
resolves the meshes' vibrations, so the scenes' own horizons would take minutes to hours), at
rtol 1e-6 and 1e-8. CPU is the thread's (time.thread_time: IDA runs in the calling thread),
median of --repeat runs, with OPENBLAS_NUM_THREADS=1.

    OPENBLAS_NUM_THREADS=1 python benchmarks/dense_jacobian.py [--repeat 3] [--only NAME ...]
                                                               [--json PATH]

Agreement: the largest difference over the outputs of every carrier's position (m) and of the
scene's band quantities relative to their scale (benchmarks/scenes.py). The runs before and
after the dense LU took the closed-form Jacobian: benchmarks/results/dense_jacobian.json.
"""
from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse  # noqa: E402
import json  # noqa: E402
import statistics  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
import warnings  # noqa: E402

import numpy as np  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(os.path.dirname(HERE), "examples"))

import phmech as ph  # noqa: E402
import scenes  # noqa: E402


def _manipulator():
    import manipulator as mp
    m = mp.build(mp.ManipulatorParams())[0]
    return m, lambda r: {}


# name -> (build, t_end, dt_out, scale); the scenes' horizons chosen so that a KLU run at rtol 1e-8
# takes about a second of CPU or less
CASES = {"manipulator (8 el.)": (_manipulator, 0.05, 1e-3, {})}
_HORIZON = {"double pendulum": 0.005, "leaf spring": 0.2, "manipulator": 0.05, "four-bar": 0.5,
            "cantilever + tip mass, impulse": 0.02, "slider-crank, flexible rod": 0.01,
            "flexible arm, torque profile": 0.01}
for _sc in scenes.SCENES:
    CASES[_sc.name] = (_sc.build, _HORIZON[_sc.name], min(_sc.dt_out, _HORIZON[_sc.name] / 20), _sc.scale)


def run(build, t_end, dt_out, rtol, solver, repeat):
    cpu, res = [], None
    for _ in range(repeat):
        m, measure = build()
        c0 = time.thread_time()
        res = m.simulate(t_end, dt_out, rtol=rtol, integrator="ida", linear_solver=solver)
        cpu.append(time.thread_time() - c0)
    s = res.stats
    return dict(cpu_s=statistics.median(cpu), cpu_runs=cpu, steps=int(s["steps"]),
                jacobian_evals=int(s["jacobian_evals"]), residual_evals=int(s["residual_evals"]),
                nonlinear_iters=int(s["nonlinear_iters"]), error_test_fails=int(s["error_test_fails"]),
                nonlinear_conv_fails=int(s["nonlinear_conv_fails"]),
                ledger_relative=float(s["ledger_relative"])), res, measure(res)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--only", nargs="*", help="case names (substrings)")
    ap.add_argument("--rtol", nargs="*", type=float, default=[1e-6, 1e-8])
    ap.add_argument("--solvers", nargs="*", default=["dense", "klu"])
    ap.add_argument("--json", help="write the rows here")
    a = ap.parse_args(argv)
    warnings.simplefilter("ignore")
    rows = []
    for name, (build, t_end, dt_out, scale) in CASES.items():
        if a.only and not any(o in name for o in a.only):
            continue
        for rtol in a.rtol:
            row = dict(case=name, t_end=t_end, rtol=rtol)
            out = {}
            for solver in a.solvers:
                try:
                    row[solver], res, q = run(build, t_end, dt_out, rtol, solver, a.repeat)
                    out[solver] = (res, q)
                except ph.SolverError as e:
                    row[solver] = dict(error=str(e).splitlines()[0])
            if len(out) == 2:
                (rd, qd), (rk, qk) = out["dense"], out["klu"]
                row["position_diff_m"] = float(np.abs(rd.poses[:, :, :3, 3] - rk.poses[:, :, :3, 3]).max())
                row["band_diff_relative"] = max([float(np.abs(qd[k] - qk[k]).max()) / scale[k] for k in qd],
                                                default=None)
            rows.append(row)
            fmt = lambda r: (f"{r['cpu_s']:.3f} s, {r['steps']} steps, {r['jacobian_evals']} J, "
                             f"{r['residual_evals']} F" if "cpu_s" in r else r["error"])
            print(f"{name:32s} rtol {rtol:.0e} t {t_end:g}: " + " | ".join(f"{s} {fmt(row[s])}" for s in a.solvers)
                  + f" | diff {row.get('position_diff_m', float('nan')):.2e} m", flush=True)
    if a.json:
        with open(a.json, "w") as f:
            json.dump(dict(phmech=ph.__version__, rows=rows), f, indent=1)


if __name__ == "__main__":
    main()

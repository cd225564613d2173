"""Per-call overhead of modes(), static() and simulate() on small models (issue 31, item 5).

    python benchmarks/bench_overhead.py [--quick | --smoke]

Each analysis is called 2 x REPS times on one mechanism (after a warm-up call): a plain call
for the total, then one whose calls into the C core -- ``phmech._core``'s ``model_*``
functions -- are timed (benchmarks/setup_time.py's Split, on ``time.process_time``); the rest of
a call is Python (checks, marshalling, labels, results). Reported per case: the medians over the
calls of the total CPU (``time.process_time``), of the core's part and of the wall time
(``time.perf_counter``), and ``ratio`` = median total / median core (1 would be no overhead;
the issue asks <= 1.2). CPU, not
wall, is the measure: on a loaded machine a wall-clock call of 0.4 ms is preempted every ~10th
time for ~4 ms (measured), which a median hides and a mean does not.

Models:

- ``cantilever N`` (N = 3, 5, 9): ``modes(5)`` on the Table I cantilever of benchmarks/run.py's
  modes benchmark (``phmech.studies.se3_cantilever``: consistent mass, no gravity);
  ``static()`` and ``simulate(0.01, 0.005)`` on setup_time.py's cantilever (Table I section,
  under gravity, a tip body welded to its end);
- ``double pendulum``: two rigid bars on revolutes hanging under gravity (an equilibrium), the
  first swinging at 1 rad/s: ``modes(2)``, ``static()``, ``simulate(0.01, 0.005)``.

Against Exudyn's GE2D (``ObjectBeamGeometricallyExact2D``, as benchmarks/run.py's
``exudyn_frequencies``) at N = 3, 5, 9: per call, ``ComputeODE2Eigenvalues`` on the assembled
system against ``modes(5)`` on the built mechanism; and build + solve (what run.py's modes
benchmark times: ``exudyn_frequencies`` against ``phmech.studies.se3_frequencies``).

Writes benchmarks/results/bench_overhead.json (``_quick``/``_smoke``: bench_overhead_quick.json)
and bench_overhead.png.
"""
from __future__ import annotations

import argparse
import os
import statistics
import sys
import time
import warnings

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

import phmech as ph  # noqa: E402
from phmech import se3, studies  # noqa: E402
from run import RESULTS, have, machine, write_json  # noqa: E402
from setup_time import Split, cantilever  # noqa: E402

NS = (3, 5, 9)
T_END, DT_OUT = 0.01, 0.005


def double_pendulum() -> ph.Mechanism:
    """Two 0.5 m bars of 1 kg on revolutes about y, hanging along -z under gravity (the initial
    configuration is an equilibrium), the first swinging at 1 rad/s."""
    m = ph.Mechanism(gravity=(0.0, 0.0, -9.81))
    J = np.diag([0.5 ** 2 / 12, 0.5 ** 2 / 12, 1e-4])
    a = m.add_rigid_body("a", 1.0, J, com=(0.0, 0.0, -0.25))
    b = m.add_rigid_body("b", 1.0, J, com=(0.0, 0.0, -0.25))
    m.add_pair("k1", ph.Revolute("y"), m.ground, a, xdot0=1.0)
    m.add_pair("k2", ph.Revolute("y"), ph.Frame(a.carrier, se3.translation([0.0, 0.0, -0.5])), b)
    return m


def per_call(fn, reps: int) -> dict:
    """Medians over ``reps`` calls of fn() (after one warm-up call): total CPU and wall of a
    plain call, and the core's CPU (model_* functions) and its split by function in a second
    call, under Split, made right after it (Split's wrappers cost ~2 us of CPU per core call,
    which would count as overhead on calls of 10-100 us); ``split_cpu_s``: that call's total."""
    fn()
    tot, core, wall, by, split = [], [], [], [], []
    for _ in range(reps):
        c0, w0 = time.process_time(), time.perf_counter()
        fn()
        c1, w1 = time.process_time(), time.perf_counter()
        tot.append(c1 - c0)
        wall.append(w1 - w0)
        with Split(clock=time.process_time) as s:
            c0 = time.process_time()
            fn()
            split.append(time.process_time() - c0)
        core.append(sum(s.core.values()))
        by.append(dict(s.core))
    names = sorted({k for b in by for k in b})
    med = lambda xs: float(statistics.median(xs))  # noqa: E731
    out = dict(reps=reps, cpu_s=med(tot), core_cpu_s=med(core), wall_s=med(wall),
               mean_cpu_s=float(np.mean(tot)), split_cpu_s=med(split),
               core_by_function_s={k: med([b.get(k, 0.0) for b in by]) for k in names})
    out["ratio"] = out["cpu_s"] / out["core_cpu_s"] if out["core_cpu_s"] > 0 else None
    return out


def cpu_median(fn, reps: int) -> float:
    """Median CPU [s] of fn() over ``reps`` calls after one warm-up."""
    fn()
    ts = []
    for _ in range(reps):
        c0 = time.process_time()
        fn()
        ts.append(time.process_time() - c0)
    return float(statistics.median(ts))


def cases() -> list:
    """(model, analysis, mechanism factory, call) of every case."""
    out = []
    for N in NS:
        out += [(f"cantilever N={N}", "modes(5)", lambda N=N: studies.se3_cantilever(N)[0], lambda m: m.modes(5)),
                (f"cantilever N={N}", "static()", lambda N=N: cantilever(N), lambda m: m.static()),
                (f"cantilever N={N}", "simulate", lambda N=N: cantilever(N),
                 lambda m: m.simulate(T_END, DT_OUT))]
    out += [("double pendulum", "modes(2)", double_pendulum, lambda m: m.modes(2)),
            ("double pendulum", "static()", double_pendulum, lambda m: m.static()),
            ("double pendulum", "simulate", double_pendulum, lambda m: m.simulate(T_END, DT_OUT))]
    return out


def versus_exudyn(reps: int) -> list:
    """phmech modes(5) against Exudyn GE2D's eigenvalues at N = 3, 5, 9: per call and build +
    solve (CPU medians)."""
    import exudyn.solver
    import run
    rows = []
    for N in NS:
        m, _ = studies.se3_cantilever(N)
        _, mbs, _, _ = run.exudyn_beam(N, axial=1e4 * run.EA1, clamp=False)
        ph_call = cpu_median(lambda: m.modes(5), reps)
        ex_call = cpu_median(lambda: exudyn.solver.ComputeODE2Eigenvalues(mbs, constrainedCoordinates=[0, 1, 2]), reps)
        ph_build = cpu_median(lambda: studies.se3_frequencies(N, 5, mass="consistent"), reps)
        ex_build = cpu_median(lambda: run.exudyn_frequencies(N, 5), reps)
        rows.append(dict(N=N, phmech_call_cpu_s=ph_call, exudyn_call_cpu_s=ex_call,
                         call_ratio=ph_call / ex_call, phmech_build_solve_cpu_s=ph_build,
                         exudyn_build_solve_cpu_s=ex_build, build_solve_ratio=ph_build / ex_build))
        print(f"modes(5) N={N}: per call phmech {ph_call * 1e3:.3f} ms, Exudyn GE2D {ex_call * 1e3:.3f} ms "
              f"(ratio {ph_call / ex_call:.2f}); build + solve phmech {ph_build * 1e3:.3f} ms, "
              f"Exudyn {ex_build * 1e3:.3f} ms (ratio {ph_build / ex_build:.2f})", flush=True)
    return rows


def plot(out: dict, path: str) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    rs = out["runs"]
    fig, ax = plt.subplots(1, 2, figsize=(12, 4.5), gridspec_kw=dict(width_ratios=[3, 1]))
    x = np.arange(len(rs))
    ax[0].bar(x - 0.2, [r["cpu_s"] * 1e3 for r in rs], 0.4, label="total (CPU)")
    ax[0].bar(x + 0.2, [r["core_cpu_s"] * 1e3 for r in rs], 0.4, label="core (model_* calls)")
    for i, r in enumerate(rs):
        ax[0].annotate(f"{r['ratio']:.2f}" if r["ratio"] else "", (i, r["cpu_s"] * 1e3), ha="center",
                       va="bottom", fontsize=7)
    ax[0].set_xticks(x, [f"{r['model']}\n{r['analysis']}" for r in rs], fontsize=6, rotation=60)
    ax[0].set(yscale="log", ylabel="CPU per call [ms] (median)", title="per-call total vs core (labels: ratio)")
    ax[0].legend(fontsize=8)
    ex = out.get("exudyn") or []
    if ex:
        N = [r["N"] for r in ex]
        ax[1].plot(N, [r["phmech_call_cpu_s"] * 1e3 for r in ex], "o-", label="phmech modes(5)")
        ax[1].plot(N, [r["exudyn_call_cpu_s"] * 1e3 for r in ex], "s-", label="Exudyn GE2D eig")
        ax[1].plot(N, [r["phmech_build_solve_cpu_s"] * 1e3 for r in ex], "o--", label="phmech build+modes")
        ax[1].plot(N, [r["exudyn_build_solve_cpu_s"] * 1e3 for r in ex], "s--", label="Exudyn build+eig")
        ax[1].set(xlabel="elements N", ylabel="CPU [ms] (median)", title="Table I cantilever modes", yscale="log")
        ax[1].legend(fontsize=7)
    for a in ax:
        a.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    print("wrote", path)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer calls per case")
    ap.add_argument("--smoke", action="store_true", help="seconds: 3 calls per case (tests/test_benchmarks_smoke.py)")
    a = ap.parse_args(argv)
    reps = 3 if a.smoke else 40 if a.quick else 300
    runs = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ph.CostWarning)
        for model, analysis, make, call in cases():
            m = make()
            r = per_call(lambda: call(m), max(3, reps // 5) if analysis == "simulate" else reps)
            runs.append(dict(model=model, analysis=analysis, **r))
            print(f"{model:17s} {analysis:9s}: CPU {r['cpu_s'] * 1e3:8.3f} ms, core {r['core_cpu_s'] * 1e3:8.3f} ms "
                  f"(ratio {r['ratio']:.2f}), wall {r['wall_s'] * 1e3:8.3f} ms  "
                  + ", ".join(f"{k} {v * 1e3:.3f}" for k, v in r["core_by_function_s"].items()), flush=True)
        ex = versus_exudyn(reps) if have("exudyn") else None
    name = "bench_overhead" + ("_quick" if a.quick or a.smoke else "")
    out = dict(problem="per-call overhead of modes(), static(), simulate() on small models (issue 31, item 5)",
               clock="time.process_time (CPU); core = phmech._core.model_* calls",
               smoke=a.smoke, quick=a.quick, runs=runs, exudyn=ex, machine=machine())
    write_json(name, out)
    plot(out, os.path.join(RESULTS, name + ".png"))


if __name__ == "__main__":
    main()

"""Large models (issue 31, item 4): a hanging steel riser of N = 30 ... 10 000 elements driven
at its top, run with phmech's defaults; CPU per simulated second, peak memory, steps, Newton
iterations, error, the scaling exponents over N = 30 ... 10 000 and 100 ... 10 000, static()'s
CPU, and Exudyn's figures on the same problem (the JSON's ``summary``: both at N = 100, 1000,
10 000).

    python benchmarks/bench_large.py [--quick | --smoke] [--budget S] [--no-exudyn]

Problem: a steel riser (solid circle d = 0.02 m, E = 210 GPa, nu = 0.3, 7850 kg/m^3), L = 100 m,
hanging under gravity from its top, which is clamped to a slider driven horizontally by
x(t) = A (1 - cos 2 pi f t), A = 1 m, f = 0.5 Hz (rest at t = 0; the wave needs 2 sqrt(L/g) =
6.4 s to reach the free end). phmech: ``add_flexible_link(..., elements=N)`` (se3, consistent
mass), a driven ``Prismatic`` pair, ``m.static()`` for the hanging equilibrium, then
``m.simulate(T, DT_OUT, initial=static)``: no solver option (the default integrator, rtol 1e-4,
its default band max(1 / (2 DT_OUT), 50 / T)). Every point runs in a fresh interpreter (peak
memory = ``ru_maxrss`` of that process; the baseline of an interpreter that imported numpy and
phmech (and Exudyn) is stored).

Figures per N: CPU of the model building, of ``static()`` and of ``simulate()``; CPU per
simulated second = simulate CPU / T (its set-up is in it: small, see ``setup``); steps, Newton
iterations, iteration-matrix refreshes; peak RSS; two errors, each the largest distance of the
four material points s = L/4, L/2, 3L/4, L from their reference over the outputs, divided by L:

- ``error`` (the integrator's, at this mesh): against the same N run at rtol REF_RTOL (the same
  defaults otherwise) over the first T_REF seconds; the reference's own error is estimated at
  the smallest N by a run at REF_RTOL / 10 (``reference_check``).
- ``mesh_error`` (the discretization's): against the finest N of the run (its defaults) over
  the whole span.

Exudyn (``--no-exudyn``: not run): ``ObjectBeamGeometricallyExact2D`` (the same section values,
planar Simo-Reissner: the like-for-like element) with its sparse solver (EigenSparse), from the
analytic hanging equilibrium (its SolveStatic does not converge here), generalized-alpha
(spectral radius 0.9, as phmech's default rho_inf) at a fixed step, Newton relative tolerance
EX_NEWTON_RTOL (EX_NEWTON_RTOL_LARGE from N = 10 000 on: below it, its Newton stalls); top coordinates held by CoordinateConstraints, x driven through an
``offsetUserFunction`` (as benchmarks/run.py's whipped rod). Matched error: at N_CAL the steps
EX_STEPS are run over T_REF and the largest whose error (against phmech's reference at that N)
is at most phmech's default's is used for every N.

Writes ``benchmarks/results/bench_large.json`` (``--quick``: ``bench_large_quick.json``) and a
PNG beside it. ``--quick``: N = 100, 300 over 1 s; ``--smoke``: N = 100 over 0.2 s, one Exudyn step
(tests/test_benchmarks_smoke.py).
"""
from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from run import RESULTS, cpu_at_error, exudyn_stats, have, machine, pareto, write_json  # noqa: E402

L = 100.0                      # riser length [m]
D = 0.02                       # diameter [m]
E, NU, RHO = 2.1e11, 0.3, 7850.0
G = 9.81
A_TOP, F_TOP = 1.0, 0.5        # top stroke amplitude [m], frequency [Hz]
DT_OUT = 0.1                   # output period [s]
REF_RTOL = 1e-6
POINTS = (0.25, 0.5, 0.75, 1.0)          # material points (fractions of L) the errors look at
EX_STEPS = (1e-2, 5e-3, 2e-3, 1e-3)      # Exudyn steps tried at N_CAL [s]
EX_RHO = 0.9
EX_NEWTON_RTOL = 1e-6                    # Exudyn's Newton tolerance (its default 1e-8 stalls)
EX_NEWTON_RTOL_LARGE = (10000, 1e-5)     # from this N on (there 1e-6 stalls too)
EXPONENT_RANGES = ((30, 10000), (100, 10000))   # the CPU/s exponents reported (issue 31)
SUMMARY_SIZES = (100, 1000, 10000)              # the sizes of the JSON's summary
BAND_BOUND_FACTOR = 1.1    # a run within 10 % of band_cap_steps is band-bound (its steps set by T)


def properties():
    import phmech as ph
    return ph.BeamProperties.from_material(ph.Section.circle(D), ph.Material(E=E, nu=NU, density=RHO))


def top_law():
    """x(t) = A (1 - cos 2 pi f t) as a phmech Sine: offset A, amplitude -A, phase pi/2."""
    import phmech as ph
    return ph.Sine(-A_TOP, F_TOP, np.pi / 2, A_TOP)


def top_x(t: float) -> float:
    return A_TOP * (1.0 - np.cos(2 * np.pi * F_TOP * t))


def phmech_riser(N: int, T: float, rtol: float | None = None) -> dict:
    """Build, static(), simulate() with the defaults (``rtol``: only for the reference)."""
    import phmech as ph
    c0 = time.process_time()
    m = ph.Mechanism(gravity=(0, 0, -G))
    # the slider's frame on the ground: its x along -z (the riser hangs along its start frame's
    # x), so its z is the world's x, the direction the top is driven in
    hang = np.eye(4)
    hang[:3, :3] = [[0, 0, 1], [0, 1, 0], [-1, 0, 0]]
    b = m.add_flexible_link("riser", L, properties(), elements=N)
    m.add_pair("top", ph.Prismatic("z"), ph.Frame(-1, hang), b.start, driven=top_law())
    c1 = time.process_time()
    st = m.static()
    c2 = time.process_time()
    r = m.simulate(T, DT_OUT, initial=st, **({} if rtol is None else {"rtol": rtol}))
    c3 = time.process_time()
    nodes = [int(round(p * N)) for p in POINTS]
    pts = np.stack([r.position(b.node(k))[:, [0, 2]] for k in nodes], axis=1)   # (nt, 4, 2): x, z
    s = r.stats
    cap = band_cap_steps(T, float(s["band"]))
    return dict(build_cpu_s=c1 - c0, static_cpu_s=c2 - c1, sim_cpu_s=c3 - c2, t=r.t.tolist(),
                points=pts.tolist(), steps=int(s["steps"]), newton_iterations=int(s["nonlinear_iters"]),
                jacobians=int(s["jacobian_evals"]), band_hz=float(s["band"]), band_cap_steps=cap,
                band_bound=bool(s["steps"] <= BAND_BOUND_FACTOR * cap),
                error_sum=float(s.get("error_sum", float("nan"))), static_lowest_omega=float(st.lowest_omega))


def band_cap_steps(T: float, band: float) -> int:
    """The steps of a run whose every step is the default integrator's largest, 1/(BAND_MAX_STEPS
    band) (python/phmech/_run.py): its step count when the band, not the accuracy, sets the steps.
    The default band is at least BAND_PER_SPAN / T, so such a run takes ~600 steps whatever T (the
    smoke's 0.2 s: 607) and its CPU per simulated second measures the band, not the problem; the
    full run's 5 s takes ~7000-7500 accuracy-bound steps at every N (benchmarks/results/bench_large.json)"""
    from phmech import _run
    return int(np.ceil(T * _run.BAND_MAX_STEPS * band - 1e-9))


def exudyn_newton_rtol(N: int) -> float:
    """Exudyn's Newton relative tolerance at N elements: EX_NEWTON_RTOL, or from
    EX_NEWTON_RTOL_LARGE's N on its looser value (at N = 10 000 its Newton stalls at 1.05e-6
    relative from t = 0.016 s, its steps then cut to 1.2e-7 s: the run did not finish)."""
    return EX_NEWTON_RTOL_LARGE[1] if N >= EX_NEWTON_RTOL_LARGE[0] else EX_NEWTON_RTOL


def exudyn_riser(N: int, T: float, h: float) -> dict:
    """Exudyn GE2D riser along -y, gravity -y, top node clamped, x driven; (x, y) of the points."""
    import exudyn as exu
    import exudyn.solver
    from exudyn.beams import GenerateBeamElementsAlongLine
    from exudyn.itemInterface import (CoordinateConstraint, MarkerNodeCoordinate, NodePointGround, ObjectBeamGeometricallyExact2D,
                                      SensorNode, VObjectBeamGeometricallyExact2D)
    p = properties()
    c0 = time.process_time()
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    tmpl = ObjectBeamGeometricallyExact2D(
        massPerLength=p.rhoA, crossSectionInertia=p.rhoI_y, bendingStiffness=p.EI_y,
        axialStiffness=p.EA, shearStiffness=p.GA_z, visualization=VObjectBeamGeometricallyExact2D(show=False))
    # gravity: a LoadMassProportional per element (Exudyn's helper)
    nodes = GenerateBeamElementsAlongLine(mbs, [0, 0, 0], [0, -L, 0], N, tmpl, gravity=[0, -G, 0])["nodes"]
    gnd = mbs.AddNode(NodePointGround(referenceCoordinates=[0, 0, 0]))
    mg = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=gnd, coordinate=0))
    for c in range(3):
        mc = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=nodes[0], coordinate=c))
        kw = dict(offsetUserFunction=lambda mbs_, t, item, off: top_x(t)) if c == 0 else {}
        mbs.AddObject(CoordinateConstraint(markerNumbers=[mg, mc], **kw))
    sens = [mbs.AddSensor(SensorNode(nodeNumber=nodes[int(round(q * N))], storeInternal=True,
                                     outputVariableType=exu.OutputVariableType.Position)) for q in POINTS]
    mbs.Assemble()
    ss = exu.SimulationSettings()
    ss.solution.file.write = False
    ss.solution.sensors.writePeriod = DT_OUT
    ss.show.computationTime = False
    ss.linearSolver.solverType = exu.LinearSolverType.EigenSparse
    ss.timeIntegration.verboseMode = int(os.environ.get("EXUDYN_VERBOSE", "0"))
    # Newton: its default relative tolerance 1e-8 is below the round-off of this stiff cable's
    # residual from N = 300 on (it stalls at 1.5e-8; the step is then cut to 6e-8 s and the run
    # would take hours)
    ss.timeIntegration.newton.relativeTolerance = exudyn_newton_rtol(N)
    c1 = time.process_time()
    # the initial state: the hanging equilibrium, axial displacement u(s) = w (L s - s^2 / 2) / EA
    # (w the weight per length), exact at the nodes of linear elements under a distributed load
    # (phmech's static() gives it to 1e-12 m). Exudyn's SolveStatic does not converge here: its
    # Newton stalls at the round-off of this stiff cable's residual (relative 2e-7 at N = 100,
    # 4e-5 at N = 1000, above its tolerance 1e-8 and 1e-5)
    q = np.asarray(mbs.systemData.GetODE2Coordinates(), dtype=float)
    sn = np.linspace(0.0, L, N + 1)
    q[1:3 * (N + 1):3] = -p.rhoA * G * (L * sn - sn ** 2 / 2) / p.EA
    mbs.systemData.SetODE2Coordinates(q, configuration=exu.ConfigurationType.Initial)
    c2 = time.process_time()
    ss.timeIntegration.endTime = T
    ss.timeIntegration.numberOfSteps = int(round(T / h))
    ss.timeIntegration.generalizedAlpha.spectralRadius = EX_RHO
    exudyn.solver.SolveDynamic(mbs, ss)
    c3 = time.process_time()
    d = [np.asarray(mbs.GetSensorStoredData(s)) for s in sens]
    pts = np.stack([x[:, 1:3] for x in d], axis=1)       # (nt, 4, 2): x, y
    return dict(build_cpu_s=c1 - c0, static_cpu_s=c2 - c1, sim_cpu_s=c3 - c2, t=d[0][:, 0].tolist(),
                points=pts.tolist(), h=h, newton_rtol=exudyn_newton_rtol(N), **exudyn_stats(mbs, T, h))


def point(code: str, N: int, T: float, setting: float) -> dict:
    """One point in this (fresh) process."""
    import phmech  # noqa: F401
    if code == "exudyn":
        import exudyn  # noqa: F401
    w0 = time.time()
    r = exudyn_riser(N, T, setting) if code == "exudyn" else \
        phmech_riser(N, T, None if setting <= 0 else setting)
    r.update(code=code, N=N, T=T, setting=setting, wall_s=time.time() - w0,
             cpu_per_sim_s=r["sim_cpu_s"] / T,
             maxrss_MB=resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0)
    return r


def run_point(code: str, N: int, T: float, setting: float, budget: float) -> dict:
    pr = subprocess.run([sys.executable, os.path.abspath(__file__), "--point", code, str(N), repr(T), repr(setting)],
                        capture_output=True, text=True, timeout=budget)
    if pr.returncode != 0:
        raise RuntimeError(" | ".join(pr.stderr.strip().splitlines()[-3:]))
    return json.loads(pr.stdout.strip().splitlines()[-1])


def baseline_rss(mods: str) -> float:
    pr = subprocess.run([sys.executable, "-c", f"import resource, {mods}; "
                         "print(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024)"],
                        capture_output=True, text=True, check=True)
    return float(pr.stdout.strip())


def deviation(a: dict, ref: dict, t_max: float) -> float:
    """max over outputs t <= t_max (common to both) and the material points of |a - ref| / L."""
    ta, tr = np.asarray(a["t"]), np.asarray(ref["t"])
    pa, pr = np.asarray(a["points"]), np.asarray(ref["points"])
    dev = 0.0
    for i, t in enumerate(tr):
        if t > t_max + 1e-9:
            break
        j = int(np.argmin(np.abs(ta - t)))
        if abs(ta[j] - t) > 1e-6:
            continue
        dev = max(dev, float(np.max(np.linalg.norm(pa[j] - pr[i], axis=1))))
    return dev / L


def fit_exponent(rs: list) -> float | None:
    if len(rs) < 2:
        return None
    return float(np.polyfit(np.log([r["N"] for r in rs]), np.log([r["cpu_per_sim_s"] for r in rs]), 1)[0])


def local_slopes(rs: list) -> list:
    """d log(CPU/s) / d log N between consecutive runs of ``rs`` (sorted by N)."""
    return [float(np.log(b["cpu_per_sim_s"] / a["cpu_per_sim_s"]) / np.log(b["N"] / a["N"]))
            for a, b in zip(rs, rs[1:])]


def slim(r: dict) -> dict:
    """A point without its trajectories (the JSON keeps the errors, not the samples)."""
    return {k: v for k, v in r.items() if k not in ("t", "points")}


def fit_all(runs: list, base: dict) -> dict:
    """Per code: the CPU/s exponent over all its N (least squares in log-log), over each of
    EXPONENT_RANGES (``cpu_exponents``, "30-10000": the fit on the runs within; None with fewer
    than two, ``fitted_on`` names them), the local slopes between neighbouring N and the
    exponent of the peak RSS above the baseline."""
    fits = {}
    for code in ("phmech", "exudyn"):
        rs = sorted((r for r in runs if r["code"] == code), key=lambda r: r["N"])
        if len(rs) >= 2:
            ranges = {f"{lo}-{hi}": [r for r in rs if lo <= r["N"] <= hi] for lo, hi in EXPONENT_RANGES}
            fits[code] = dict(cpu_exponent=fit_exponent(rs), fitted_on=[r["N"] for r in rs],
                              # a band-bound run's steps are set by T, not by the problem's accuracy
                              band_bound_runs=[r["N"] for r in rs if r.get("band_bound")],
                              cpu_exponents={k: dict(exponent=fit_exponent(v), fitted_on=[r["N"] for r in v])
                                             for k, v in ranges.items()},
                              local_slopes=local_slopes(rs),
                              memory_exponent_above_baseline=fit_exponent(
                                  [dict(N=r["N"], cpu_per_sim_s=max(r["maxrss_MB"] - base[code], 1e-3)) for r in rs]))
    return fits


def summary(runs: list) -> dict:
    """Per code, at each of SUMMARY_SIZES it ran: CPU per simulated s, peak RSS [MB], static
    CPU [s] (for Exudyn: setting its initial state), steps and Newton iterations."""
    out = {}
    for code in ("phmech", "exudyn"):
        at = {str(r["N"]): dict(cpu_per_sim_s=r["cpu_per_sim_s"], maxrss_MB=r["maxrss_MB"], static_cpu_s=r["static_cpu_s"],
                                steps=r["steps"], newton_iterations=r.get("newton_iterations"))
              for r in runs if r["code"] == code and r["N"] in SUMMARY_SIZES}
        if at:
            out[code] = dict(sorted(at.items(), key=lambda kv: int(kv[0])))
    return out


def merge_point(code: str, N: int, budget: float) -> None:
    """Run one more point (the JSON's T and, for Exudyn, its step) and add it to
    benchmarks/results/bench_large.json without its errors (they need the trajectories of the
    reference, not stored): for a size whose reference would not fit the budget of a full run."""
    path = os.path.join(RESULTS, "bench_large.json")
    with open(path) as f:
        d = json.load(f)
    r = slim(run_point(code, N, d["T"], d["exudyn_h"] if code == "exudyn" else 0.0, budget))
    r["added_by"] = f"bench_large.py --merge-point {code} {N} ({time.strftime('%Y-%m-%d %H:%M', time.gmtime())} UTC)"
    d["runs"] = [x for x in d["runs"] if not (x["code"] == code and x["N"] == N)] + [r]
    d["skipped"] = [x for x in d["skipped"] if not (x["code"] == code and x["N"] == N)]
    d["fits"] = fit_all(d["runs"], d["baseline_rss_MB"])
    d["summary"] = summary(d["runs"])
    write_json("bench_large", d)
    plot(d, "bench_large")
    print(f"{code} N={N}: CPU/s {r['cpu_per_sim_s']:.4g}, static {r['static_cpu_s']:.3g} s, steps {r['steps']}, "
          f"Newton {r.get('newton_iterations')}, RSS {r['maxrss_MB']:.0f} MB; fits {json.dumps(d['fits'])}", flush=True)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="N = 100, 300 over 1 s")
    ap.add_argument("--smoke", action="store_true", help="N = 100 over 0.2 s (tests/test_benchmarks_smoke.py)")
    ap.add_argument("--budget", type=float, default=600.0, help="wall-time cap per point [s]")
    ap.add_argument("--no-exudyn", action="store_true", help="phmech only")
    ap.add_argument("--sizes", type=int, nargs="+", help="override the sizes N")
    ap.add_argument("--point", nargs=4, help=argparse.SUPPRESS)
    ap.add_argument("--merge-point", nargs=2, metavar=("CODE", "N"),
                    help="run one point (phmech or exudyn) and add it to the stored bench_large.json, without errors")
    a = ap.parse_args()
    if a.merge_point:
        merge_point(a.merge_point[0], int(a.merge_point[1]), a.budget)
        return
    if a.point:
        code, n, T, s = a.point
        print(json.dumps(point(code, int(n), float(T), float(s))))
        return
    w0 = time.time()
    if a.smoke:
        Ns, T, T_ref, N_cal = [100], 0.2, 0.2, 100
    elif a.quick:
        Ns, T, T_ref, N_cal = [100, 300], 1.0, 0.5, 100
    else:
        Ns, T, T_ref, N_cal = [30, 100, 300, 1000, 3000, 10000], 5.0, 1.0, 300
    Ns = a.sizes or Ns
    ex = have("exudyn") and not a.no_exudyn
    base = dict(phmech=baseline_rss("numpy, phmech"))
    if ex:
        base["exudyn"] = baseline_rss("numpy, phmech, exudyn")
    runs, refs, skipped = [], {}, []

    def skip_over_budget(code, N, last):
        """Whether N is skipped: its wall time predicted from the last point (N0, wall0) as
        wall0 (N / N0)^1.2 exceeds the budget; recorded in ``skipped`` and printed."""
        if last is None or last[1] * (N / last[0]) ** 1.2 <= a.budget:
            return False
        skipped.append(dict(code=code, N=N, reason=f"predicted wall > budget {a.budget:.0f} s"))
        print(f"  {code} N={N}: skipped ({skipped[-1]['reason']})", flush=True)
        return True

    def show(r, what=""):
        print(f"  {r['code']:7s} N={r['N']:6d} {what}: CPU/s {r['cpu_per_sim_s']:.4g}, static {r['static_cpu_s']:.3g} s, "
              f"build {r['build_cpu_s']:.3g} s, steps {r['steps']}, Newton {r.get('newton_iterations')}, "
              f"RSS {r['maxrss_MB']:.0f} MB, {r['wall_s']:.0f} s wall", flush=True)

    print(f"phmech defaults over T = {T} s; references at rtol {REF_RTOL} over {T_ref} s", flush=True)
    last = None          # (N, wall of its default run [s])
    ref_ratio = None     # the last reference's wall over its default run's
    for N in Ns:
        if skip_over_budget("phmech", N, last):
            continue
        try:
            r = run_point("phmech", N, T, 0.0, a.budget)
        except (RuntimeError, subprocess.TimeoutExpired) as e:
            skipped.append(dict(code="phmech", N=N, reason=str(e)[-300:]))
            print(f"  phmech N={N}: failed ({skipped[-1]['reason']})", flush=True)
            continue
        runs.append(r)
        last = (N, r["wall_s"])
        # its reference (rtol REF_RTOL over T_ref): skipped when predicted over the budget from
        # the last one's wall ratio; the point keeps its figures and its error against the
        # common reference, without a time error
        ref, why = None, None
        if ref_ratio is not None and r["wall_s"] * ref_ratio > a.budget:
            why = f"predicted wall {r['wall_s'] * ref_ratio:.0f} s > budget {a.budget:.0f} s"
        else:
            try:
                ref = run_point("phmech", N, T_ref, REF_RTOL, a.budget)
            except (RuntimeError, subprocess.TimeoutExpired) as e:
                why = str(e)[-300:]
        if ref is None:
            skipped.append(dict(code="phmech reference", N=N, reason=f"{why}: no time error at this N"))
            show(r, f"no reference ({why})")
            continue
        r["time_error"] = deviation(r, ref, T_ref)
        refs[N] = ref
        ref_ratio = ref["wall_s"] / max(r["wall_s"], 1e-3)
        show(r, f"time error {r['time_error']:.2e} L" + (" (band-bound steps)" if r["band_bound"] else ""))
        show(ref, f"reference (rtol {REF_RTOL}, {T_ref} s)")
    ph_runs = [r for r in runs if r["code"] == "phmech"]
    finest = max(ph_runs, key=lambda r: r["N"]) if ph_runs else None
    ref_N = max(refs) if refs else None
    ref = refs[ref_N] if refs else None        # the common reference: the finest N's that has one
    for r in ph_runs:
        r["mesh_error"] = deviation(r, finest, T) if r is not finest else None
        r["error"] = deviation(r, ref, T_ref) if ref is not None else None
    check = None
    if ph_runs and not a.smoke and ph_runs[0]["N"] in refs:
        n0 = ph_runs[0]["N"]
        tight = run_point("phmech", n0, T_ref, REF_RTOL / 10, a.budget)
        check = dict(N=n0, rtol=REF_RTOL / 10, reference_vs_tighter=deviation(refs[n0], tight, T_ref),
                     sim_cpu_s=tight["sim_cpu_s"], steps=tight["steps"])
        print(f"  reference check N={n0}: rtol {REF_RTOL} vs {REF_RTOL / 10}: {check['reference_vs_tighter']:.2e} L",
              flush=True)

    ex_h, cal, cal_points = None, [], {}
    if ex and ref is not None:
        for h in (EX_STEPS[1:2] if a.smoke else EX_STEPS[::-1]):
            try:
                c = run_point("exudyn", N_cal, T_ref, h, a.budget)
            except (RuntimeError, subprocess.TimeoutExpired) as e:
                cal.append(dict(h=h, failed=str(e)[-300:]))
                continue
            c["error"] = deviation(c, ref, T_ref)
            cal.append(slim(c))
            cal_points[h] = c
            print(f"  exudyn calibration N={N_cal} h={h:g}: error {c['error']:.2e} L, CPU/s {c['cpu_per_sim_s']:.4g}",
                  flush=True)
        # the largest step whose error is within 10 % of the smallest step's: its time error is
        # below its mesh's, what a user would choose
        ok = [c for c in cal if "error" in c]
        if ok:
            e0 = ok[0]["error"]
            ex_h = max(c["h"] for c in ok if abs(c["error"] - e0) <= 0.1 * e0)
        else:
            ex_h = EX_STEPS[-1]
        print(f"  exudyn: step {ex_h:g} s", flush=True)
        last = None
        for N in Ns:
            if skip_over_budget("exudyn", N, last):
                continue
            try:
                # the calibration's point when it is this one (the smoke: N_cal, T = T_ref)
                same = (N, T) == (N_cal, T_ref) and ex_h in cal_points
                r = dict(cal_points[ex_h]) if same else run_point("exudyn", N, T, ex_h, a.budget)
            except (RuntimeError, subprocess.TimeoutExpired) as e:
                skipped.append(dict(code="exudyn", N=N, reason=str(e)[-300:]))
                print(f"  exudyn N={N}: failed ({skipped[-1]['reason']})", flush=True)
                last = (N, 2 * a.budget)
                continue
            r["error"] = deviation(r, ref, T_ref)
            if finest is not None:
                r["mesh_error"] = deviation(r, finest, T)
            runs.append(r)
            show(r, f"h {ex_h:g}, error {r.get('error', float('nan')):.2e} L")
            last = (N, r["wall_s"])

    # matched error: Exudyn's CPU/s at each phmech point's error (log-log interpolation on its
    # Pareto front, benchmarks/run.py's cpu_at_error; None outside the errors it reached)
    ex_runs = [r for r in runs if r["code"] == "exudyn" and "error" in r]
    front = pareto([r["cpu_per_sim_s"] for r in ex_runs], [r["error"] for r in ex_runs])
    for r in ph_runs:
        c = cpu_at_error(front, r["error"]) if r["error"] else None
        if c is None and front and r["error"] and r["error"] >= front[0][1]:
            c = front[0][0]              # at or above Exudyn's coarsest error: its cheapest point
        r["exudyn_cpu_per_sim_s_at_error"] = c
        r["ratio_to_exudyn"] = None if c is None else r["cpu_per_sim_s"] / c
    fits = fit_all(runs, base)
    out = dict(
        problem=f"steel riser, solid circle d = {D} m (E {E:g} Pa, nu {NU}, {RHO} kg/m^3), L = {L} m, hanging under "
                f"gravity {G} m/s^2 from its top, clamped to a slider driven horizontally by x(t) = {A_TOP} (1 - cos 2 pi "
                f"{F_TOP} t) m; from the static equilibrium; outputs every {DT_OUT} s over T = {T} s",
        phmech_call="m.static(); m.simulate(T, dt_out, initial=static): defaults (default integrator, rtol 1e-4)",
        exudyn_setting=f"ObjectBeamGeometricallyExact2D, EigenSparse, initial state the analytic hanging equilibrium "
                       f"(its SolveStatic does not converge here), generalized-alpha spectral radius {EX_RHO}, Newton "
                       f"relative tolerance {EX_NEWTON_RTOL} (its default 1e-8 stalls; {EX_NEWTON_RTOL_LARGE[1]:g} from N = "
                       f"{EX_NEWTON_RTOL_LARGE[0]} on, where 1e-6 stalls), fixed step h = {ex_h} s (the "
                       f"largest of {list(EX_STEPS)} whose error at N = {N_cal} over {T_ref} s is within 10 % of the "
                       f"smallest step's)" if ex else None,
        error=f"max over outputs t <= {T_ref} s and the material points s/L = {list(POINTS)} of |p - p_ref| / L, p_ref: "
              f"phmech at the finest N with a reference ({ref_N}), rtol {REF_RTOL} (both codes)",
        time_error=f"the same against phmech at the same N, rtol {REF_RTOL}",
        mesh_error=f"the same over the whole span against the finest N ({finest['N'] if finest else None}) with defaults",
        rate="CPU per simulated s = simulate() CPU / T (time.process_time; its set-up included)",
        T=T, T_ref=T_ref, dt_out=DT_OUT, N_cal=N_cal, exudyn_h=ex_h, exudyn_calibration=cal,
        reference_check=check, baseline_rss_MB=base, machine=machine(), runs=[slim(r) for r in runs],
        references=[slim(r) for r in refs.values()], skipped=skipped, fits=fits, summary=summary(runs),
        quick=a.quick, smoke=a.smoke,
        wall_s=time.time() - w0)
    name = "bench_large" + ("_smoke" if a.smoke else "_quick" if a.quick else "")
    write_json(name, out)
    plot(out, name)
    print(f"fits: {json.dumps(fits)}")
    print(f"summary: {json.dumps(out['summary'])}")
    print(f"bench_large done in {time.time() - w0:.0f} s wall", flush=True)


def plot(out: dict, name: str) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(1, 3, figsize=(15, 4.5))
    for code, mk in (("phmech", "o-"), ("exudyn", "s--")):
        rs = sorted((r for r in out["runs"] if r["code"] == code), key=lambda r: r["N"])
        if not rs:
            continue
        f = out["fits"].get(code, {})
        lab = code + (f" (~N^{f['cpu_exponent']:.2f})" if f.get("cpu_exponent") is not None else "")
        Ns = [r["N"] for r in rs]
        ax[0].loglog(Ns, [r["cpu_per_sim_s"] for r in rs], mk, label=lab)
        ax[1].loglog(Ns, [r["maxrss_MB"] for r in rs], mk, label=code)
        ax[2].loglog(Ns, [r.get("error") or np.nan for r in rs], mk, label=code + " vs the reference")
        if code == "phmech":
            ax[2].loglog(Ns, [r.get("time_error") or np.nan for r in rs], "o-.", label="phmech time error")
            ax[2].loglog(Ns, [r.get("mesh_error") or np.nan for r in rs], "o:", label="phmech mesh error (whole span)")
    ax[0].set(xlabel="elements N", ylabel="CPU s per simulated s", title=f"hanging riser, top driven, T = {out['T']} s")
    ax[1].set(xlabel="elements N", ylabel="peak RSS [MB]", title="memory (fresh process per point)")
    ax[2].set(xlabel="elements N", ylabel="max |p - p_ref| / L",
              title=f"error (reference: finest N, rtol 1e-6, first {out['T_ref']} s)")
    for x in ax:
        x.grid(True, which="both", alpha=0.3)
        if x.get_legend_handles_labels()[0]:
            x.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(RESULTS, name + ".png"), dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    main()

"""Work-precision benchmarks of phmech against its peers (issue 6), same machine, same run.

    python benchmarks/run.py [--quick | --smoke] [--only modes transient whip]

1. ``modes``: first five cantilever frequencies of the paper's Table I beam: relative error
   against the Timoshenko frequency equation (``phmech.timoshenko.frequencies``) vs number of
   first-order states and vs CPU time, for phmech ``se3`` (3-D), phmech ``mixed`` (planar, linear),
   Exudyn's 2-D and 3-D geometrically exact beams, its ANCF cable and MuJoCo's cable (the last two
   against their own continuum models; benchmarks/peers.py); phmech ``se3`` with lumped
   (``mass="lumped"``) and with consistent element mass (the default).
2. ``transient``: the Table I cantilever (``table1_properties(1.0)``) bent by a static tip force
   3 EI / (4 L^2) (tip ~ 0.24 L) and released at rest; tip (x, z) over ``T`` seconds sampled every
   5 ms; error = max over samples of |tip - reference| / L. Reference: phmech ``se3``, IDA at rtol 1e-10
   on N_ref/2 and N_ref elements, Richardson-extrapolated (second order in h); its self-convergence
   is stored. Sweeps: phmech N x rtol with IDA (every state in the error test; the configuration
   error test) and N x step with the fixed-step generalized-alpha integrator, the last two with
   lumped and with consistent element mass; Exudyn's 2-D beam N x step size (generalized-alpha,
   spectral radius 1 and 0.9) and N x tolerance (DOPRI5, automatic step), each with its dense and
   its sparse solver; its 3-D beam and ANCF cable; MuJoCo's cable (RK4, implicitfast, Euler);
   PyElastica's Cosserat rod (position Verlet). ``cheapest_at_level``: per error level the
   cheapest measured point of each code reaching it (benchmarks/report.py prints the table).
3. ``whip``: the same rod straight at rest, its base driven transversally by a cycloidal stroke
   (0.3 m in 0.15 s), tip over 0.5 s against phmech's IDA reference (rtol 1e-10, Richardson):
   phmech (default integrator, IDA configuration test), Exudyn GE2D (base through an
   offsetUserFunction), PyElastica (a driven-clamp constraint).

Scaling with the number of elements and bodies: benchmarks/bench_scaling.py; the leaf-spring
mechanism: benchmarks/bench_leaf_spring.py (all three run by ``make bench``).

CPU time is ``time.process_time`` (median of 3 repetitions for the cheap eigenvalue points).
Each benchmark writes ``benchmarks/results/<name>.json`` (machine, versions, command, date,
every point) and a PNG work-precision plot (``BENCH_RESULTS``: another folder). The peers are
installed into .venv from benchmarks/requirements.txt when missing (``BENCH_NO_INSTALL=1``: not;
a missing peer's points are then skipped). ``--smoke``: one coarse point per code, seconds
(tests/test_benchmarks_smoke.py).
"""
from __future__ import annotations

import argparse
import json
import os
import platform
import subprocess
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
# BENCH_RESULTS: another folder for the JSON and PNG (tests/test_benchmarks_smoke.py writes there,
# so a smoke run never overwrites the stored results)
RESULTS = os.environ.get("BENCH_RESULTS") or os.path.join(HERE, "results")
TABLE1 = dict(L=1.0, rhoA=873.0, rhoI=2.1797, EI=5143.0, kGA=656625.0)
EA1 = TABLE1["EI"] * TABLE1["rhoA"] / TABLE1["rhoI"]      # axial stiffness of table1_properties(1.0)
F_TIP = 0.25 * 3 * TABLE1["EI"]                             # static tip force [N] (as validate_energy_drift)
DT_OUT = 0.005                                              # tip sampling period [s]


# ------------------------------------------------------------------ environment
def ensure_peers() -> None:
    """Install the peers (benchmarks/requirements.txt: Exudyn, MuJoCo, PyElastica) into this venv
    if missing (BENCH_NO_INSTALL=1: never; a script then fails on a missing Exudyn or MuJoCo
    and skips a missing PyElastica)."""
    if os.environ.get("BENCH_NO_INSTALL"):
        return
    try:
        import exudyn  # noqa: F401
        import mujoco  # noqa: F401
        import elastica  # noqa: F401
    except ImportError:
        req = os.path.join(HERE, "requirements.txt")
        print(f"installing {req} into {sys.prefix}", flush=True)
        subprocess.check_call([sys.executable, "-m", "pip", "install", "-q", "-r", req])


def have(module: str) -> bool:
    """True if ``module`` (a peer: "exudyn", "mujoco", "elastica") is installed; a benchmark skips
    the points of a missing peer (so its smoke in tests/test_benchmarks_smoke.py runs without them).
    BENCH_WITHOUT="exudyn,mujoco,elastica" hides installed peers (to check that path)."""
    import importlib.util
    if module in os.environ.get("BENCH_WITHOUT", "").split(","):
        return False
    return importlib.util.find_spec(module) is not None


def exudyn_stats(mbs, T: float, h: float) -> dict:
    """The fixed-step Exudyn run's steps over T [s] at step h [s], and its Newton iterations and
    Jacobians when its solver exposes them (informative only)."""
    st = {"steps": int(round(T / h))}
    try:
        it = mbs.sys["dynamicSolver"].it
        st.update(newton_iterations=int(it.newtonStepsCount), jacobians=int(it.newtonJacobiCount))
    except Exception:  # noqa: BLE001 -- informative only
        pass
    return st


def machine() -> dict:
    import phmech
    from importlib.metadata import PackageNotFoundError, version
    info = {"platform": platform.platform(), "processor": platform.processor(),
            "cpus": os.cpu_count(), "python": platform.python_version(),
            "numpy": np.__version__, "phmech": phmech.__version__,
            "blas_threads": phmech.blas_threads(),
            "date_utc": time.strftime("%Y-%m-%d %H:%M", time.gmtime()),
            "command": " ".join([os.path.basename(sys.argv[0])] + sys.argv[1:])}
    for dist in ("exudyn", "mujoco", "pyelastica", "numba"):
        try:
            info[dist] = version(dist)
        except PackageNotFoundError:
            info[dist] = None
    try:
        info["git_head"] = subprocess.run(["git", "-C", HERE, "rev-parse", "--short", "HEAD"],
                                          capture_output=True, text=True).stdout.strip()
    except OSError:
        pass
    try:
        with open("/proc/cpuinfo") as f:
            info["cpu_model"] = next(l.split(":", 1)[1].strip() for l in f if l.startswith("model name"))
    except (OSError, StopIteration):
        pass
    try:
        info.update({f"phmech_{k}": str(v) for k, v in phmech._core.build_info().items()})
    except Exception:  # noqa: BLE001 -- informative only
        pass
    return info


def write_json(name: str, data: dict) -> str:
    os.makedirs(RESULTS, exist_ok=True)
    path = os.path.join(RESULTS, name + ".json")
    with open(path, "w") as f:
        json.dump(data, f, indent=1)
    print(f"wrote {path}", flush=True)
    return path


def cpu_median(fn, reps: int):
    out, ts = None, []
    for _ in range(reps):
        t0 = time.process_time()
        out = fn()
        ts.append(time.process_time() - t0)
    return out, float(np.median(ts))


def median_of_three(run, once: bool = False):
    """run() -> (cpu_s, sim_cpu_s, ...): the first call's outputs with the medians of three
    calls' CPU; one call when ``once`` or when it takes more than a second."""
    first = run()
    if once or first[0] > 1.0:
        return first
    calls = [first] + [run() for _ in range(2)]
    return (float(np.median([r[0] for r in calls])), float(np.median([r[1] for r in calls])),
            *first[2:])


def pareto(cpu, err):
    """Lower envelope: points sorted by CPU, keeping those that improve the error."""
    pts = sorted((c, e) for c, e in zip(cpu, err) if np.isfinite(e) and e > 0)
    front, best = [], np.inf
    for c, e in pts:
        if e < best:
            front.append((c, e))
            best = e
    return front


def cpu_at_error(front, e):
    """CPU time to reach error ``e`` by log-log interpolation on a Pareto front (None outside)."""
    if len(front) < 2:
        return None
    c = np.log([p[0] for p in front])
    er = np.log([p[1] for p in front])   # decreasing
    le = np.log(e)
    if le > er[0] or le < er[-1]:
        return None
    return float(np.exp(np.interp(le, er[::-1], c[::-1])))


def ratios(front_ph, front_ex, levels):
    out = {}
    for e in levels:
        a, b = cpu_at_error(front_ph, e), cpu_at_error(front_ex, e)
        out[f"{e:.0e}"] = None if a is None or b is None else dict(phmech_cpu_s=a, exudyn_cpu_s=b, ratio=a / b)
    return out


# ------------------------------------------------------------------ models
def exudyn_line_beam(template, N: int, tip_force: float, clamp) -> tuple:
    """Exudyn system of N elements of ``template`` along x from 0 to L, the first node's
    coordinates ``clamp`` (list of 0/1, or None) fixed to ground, a tip force -tip_force along y
    and a position sensor on the tip; assembled. Returns (SC, mbs, load, sensor)."""
    import exudyn as exu
    from exudyn.beams import GenerateBeamElementsAlongLine
    from exudyn.itemInterface import LoadForceVector, MarkerNodePosition, SensorNode
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    info = GenerateBeamElementsAlongLine(mbs, [0, 0, 0], [TABLE1["L"], 0, 0], N, template,
                                         groundConstraintsStart=clamp)
    tip = info["nodes"][-1]
    mk = mbs.AddMarker(MarkerNodePosition(nodeNumber=tip))
    ld = mbs.AddLoad(LoadForceVector(markerNumber=mk, loadVector=[0, -tip_force, 0]))
    sens = mbs.AddSensor(SensorNode(nodeNumber=tip, storeInternal=True,
                                    outputVariableType=exu.OutputVariableType.Position))
    mbs.Assemble()
    return SC, mbs, ld, sens


def exudyn_beam(N: int, axial: float = EA1, tip_force: float = 0.0, clamp: bool = True, sparse=False):
    """Exudyn cantilever of N ObjectBeamGeometricallyExact2D elements along x (bending in x-y)."""
    from exudyn.itemInterface import ObjectBeamGeometricallyExact2D, VObjectBeamGeometricallyExact2D
    tmpl = ObjectBeamGeometricallyExact2D(
        massPerLength=TABLE1["rhoA"], crossSectionInertia=TABLE1["rhoI"],
        bendingStiffness=TABLE1["EI"], axialStiffness=axial, shearStiffness=TABLE1["kGA"],
        visualization=VObjectBeamGeometricallyExact2D(show=False))
    return exudyn_line_beam(tmpl, N, tip_force, [1, 1, 1] if clamp else None)


def exudyn_settings(sparse: bool):
    import exudyn as exu
    ss = exu.SimulationSettings()
    ss.solution.file.write = False
    ss.solution.sensors.writePeriod = DT_OUT
    ss.show.computationTime = False
    ss.show.statistics = False
    ss.linearSolver.solverType = exu.LinearSolverType.EigenSparse if sparse else exu.LinearSolverType.EXUdense
    ss.staticSolver.verboseMode = 0
    ss.staticSolver.numberOfLoadSteps = 4
    ss.timeIntegration.verboseMode = 0
    return ss


def phmech_cantilever(N: int, mass: str = "lumped"):
    import phmech as ph
    from phmech.section import table1_properties
    m = ph.Mechanism()
    b = m.add_flexible_link("b", TABLE1["L"], table1_properties(1.0), elements=N, mass=mass)
    m.add_pair("clamp", ph.Fixed(), m.ground, b.start)
    return m, b


# ------------------------------------------------------------------ 1. modes
def exudyn_frequencies(N: int, n: int = 5) -> np.ndarray:
    """First n bending frequencies [rad/s]; axial stiffness x 1e4 (as phmech's se3_frequencies
    uses table1_properties() with stiff_factor 1e4) so that no axial mode falls among them."""
    import exudyn.solver
    _, mbs, _, _ = exudyn_beam(N, axial=1e4 * EA1, clamp=False)
    ev, _ = exudyn.solver.ComputeODE2Eigenvalues(mbs, constrainedCoordinates=[0, 1, 2])
    om = np.sqrt(np.abs(np.sort(np.asarray(ev))))
    return om[:n]


def bench_modes(quick: bool, smoke: bool = False) -> dict:
    from phmech import studies
    import peers
    exact = studies.exact_frequencies(5)
    # peers without shear are measured against their own continuum model (peers.py)
    ref = {"exudyn_ancf": peers.euler_bernoulli_frequencies(5), "mujoco_cable": peers.rayleigh_frequencies(5)}
    Ns = [3, 5] if smoke else [3, 5, 9, 15, 21, 40, 80] if quick else [3, 5, 9, 15, 21, 40, 80, 160]
    reps = 1 if quick else 3   # (1 for N >= 80, see below)
    fns = {"phmech_se3": (lambda N, n: studies.se3_frequencies(N, n, mass="lumped"), lambda N: 12 * N),
           "phmech_se3_consistent": (lambda N, n: studies.se3_frequencies(N, n, mass="consistent"),
                                     lambda N: 12 * N),
           "phmech_mixed": (studies.mixed_frequencies, lambda N: 4 * N),
           "exudyn_ge2d": (exudyn_frequencies, lambda N: 6 * N),
           "exudyn_ge3d": (peers.exudyn_ge3d_frequencies, lambda N: 12 * N),
           "exudyn_ancf": (peers.exudyn_ancf_frequencies, lambda N: 8 * N),
           "mujoco_cable": (peers.mujoco_cable_frequencies, lambda N: 6 * N)}
    fns = {nm: v for nm, v in fns.items() if have(nm.split("_")[0]) or nm.startswith("phmech")}
    runs = {nm: [] for nm in fns}
    for N in Ns:
        for name, (fn, states) in fns.items():
            k = min(5, 2 * N)
            om, cpu = cpu_median(lambda: fn(N, k), 1 if N >= 80 else reps)
            k = min(k, len(om))            # the cable has N in-plane modes
            e = np.full(5, np.nan)
            x = ref.get(name, exact)
            e[:k] = (np.asarray(om)[:k] - x[:k]) / x[:k]
            runs[name].append(dict(N=N, states=states(N), cpu_s=cpu, omega=np.asarray(om).tolist(),
                                   rel_errors=e.tolist(),
                                   max_abs_rel_error=float(np.max(np.abs(e))) if k == 5 else None))
        print(f"modes N={N:4d}: " + ", ".join(
            f"{nm} {runs[nm][-1]['max_abs_rel_error'] or float('nan'):.2e} ({runs[nm][-1]['cpu_s'] * 1e3:.1f} ms)"
            for nm in runs), flush=True)
    fronts = {nm: pareto([r["cpu_s"] for r in rs], [r["max_abs_rel_error"] or np.nan for r in rs])
              for nm, rs in runs.items()}
    levels = [1e-1, 3e-2, 1e-2, 3e-3, 1e-3]
    # consistent mass: the max error over modes 1-5 is not monotone in N (modes 3-5 go from above
    # the exact value on coarse meshes to below it on fine ones, so one coarse mesh can sit near
    # that crossing); its front is also given over the meshes from which the error only decreases
    fronts = {nm: fronts.get(nm, []) for nm in ("exudyn_ge2d", "exudyn_ge3d", "exudyn_ancf", "mujoco_cable")} | fronts
    rs_c = runs["phmech_se3_consistent"]
    e_c = [r["max_abs_rel_error"] or np.inf for r in rs_c]
    tail = next(i for i in range(len(e_c)) if all(a > b for a, b in zip(e_c[i:], e_c[i + 1:])))
    front_c_tail = pareto([r["cpu_s"] for r in rs_c[tail:]], e_c[tail:])

    def over(peer):   # CPU(se3) / CPU(peer) at equal error (each against its own reference)
        r = {}
        for e in levels:
            a, b = cpu_at_error(fronts["phmech_se3"], e), cpu_at_error(fronts[peer], e)
            r[f"{e:.0e}"] = None if a is None or b is None else dict(phmech_cpu_s=a, peer_cpu_s=b, ratio=a / b)
        return r
    mj_version = machine()["mujoco"]
    out = dict(problem="Table I cantilever, first five frequencies", exact_rad_s=exact.tolist(),
               error="max over modes 1..5 of |omega_h - omega| / omega",
               error_reference={"default": "Timoshenko (exact_rad_s)",
                                "exudyn_ancf": "Euler-Bernoulli (no shear, no rotary inertia): "
                                               + str(ref["exudyn_ancf"].tolist()),
                                "mujoco_cable": "Rayleigh beam (rotary inertia, no shear): "
                                                + str(ref["mujoco_cable"].tolist())},
               mass_note="phmech_se3: lumped element mass (mass=\"lumped\"); phmech_se3_consistent (the default): "
                         "add_flexible_link(mass='consistent') (docs/mass_matrix_study.md, d6)",
               states_note="first-order states: se3 12 per free node (3-D), mixed 4N (planar), "
                           "Exudyn GE2D 6 per free node (planar), Exudyn GE3D 12 per free node (3-D), "
                           "Exudyn ANCF cable 8 per free node (planar), MuJoCo cable 6 per segment (3 ball dofs)",
               exudyn_note="ObjectBeamGeometricallyExact2D, axial stiffness x1e4 (as se3_frequencies); "
                           "ComputeODE2Eigenvalues dense, clamp by constrainedCoordinates",
               peers_note="see benchmarks/peers.py and docs/perf_peers.md: exudyn_ge3d = ObjectBeamGeometricallyExact "
                          "(Rxyz nodes, table1_properties(1e4) section); exudyn_ancf = ObjectANCFCable2D (EA x1e4); "
                          "mujoco_cable = MuJoCo " + str(mj_version) + " composite cable + elasticity.cable plugin, "
                          "frequencies by linearization (mj_fullM, central differences of qfrc_passive in Python, "
                          "in-plane dofs), so its CPU time is of that script, not of a MuJoCo modal solver",
               machine=machine(), runs=runs,
               cpu_ratio_at_equal_error={"se3_over_exudyn": ratios(fronts["phmech_se3"], fronts["exudyn_ge2d"], levels),
                                         "se3_consistent_over_exudyn": ratios(fronts["phmech_se3_consistent"],
                                                                              fronts["exudyn_ge2d"], levels),
                                         "se3_consistent_over_exudyn_monotone_meshes": dict(
                                             ratios(front_c_tail, fronts["exudyn_ge2d"], levels),
                                             N_from=rs_c[tail]["N"]),
                                         "mixed_over_exudyn": ratios(fronts["phmech_mixed"], fronts["exudyn_ge2d"], levels),
                                         "se3_over_exudyn_ge3d": over("exudyn_ge3d"),
                                         "se3_over_exudyn_ancf_vs_EB": over("exudyn_ancf"),
                                         "se3_over_mujoco_cable_vs_Rayleigh": over("mujoco_cable")})
    write_json("bench_modes", out)
    plot_modes(out)
    return out


def plot_modes(out):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(1, 2, figsize=(11, 4))
    vs = {"exudyn_ancf": " (vs EB)", "mujoco_cable": " (vs Rayleigh)"}
    for nm, rs in out["runs"].items():
        ok = [r for r in rs if r["max_abs_rel_error"]]
        e = [r["max_abs_rel_error"] for r in ok]
        ax[0].loglog([r["states"] for r in ok], e, "o-", label=nm + vs.get(nm, ""))
        ax[1].loglog([r["cpu_s"] for r in ok], e, "o-", label=nm + vs.get(nm, ""))
    ax[0].set(xlabel="first-order states", ylabel="max rel. error, modes 1-5", title="Table I cantilever")
    ax[1].set(xlabel="CPU time [s]", ylabel="max rel. error, modes 1-5", title="work-precision")
    for a in ax:
        a.grid(True, which="both", alpha=0.3)
        a.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(RESULTS, "bench_modes.png"), dpi=120)
    plt.close(fig)


# ------------------------------------------------------------------ 2. transient
def phmech_transient(N: int, rtol: float, solver: str, T: float, mass: str = "lumped", **options):
    """(cpu_s incl. static, simulation cpu_s, t, tip (nt, 2) = (x, z), stats); ``mass`` is the
    link's element mass; ``options`` go to ``Mechanism.simulate`` (error_test, integrator, step,
    rho_inf)."""
    t0 = time.process_time()
    m, b = phmech_cantilever(N, mass)
    # one load step, as Exudyn's SolveStatic (numberOfLoadSteps 1): 2 Newton iterations here,
    # the equilibrium of 4 steps to 1e-12 m (measured N = 3-80)
    st = m.static(loads=[(b.end, (0, 0, 0, 0, 0, -F_TIP), "world")], steps=1)
    t1 = time.process_time()
    r = m.simulate(T, DT_OUT, rtol=rtol, initial=st, linear_solver=solver, **options)
    t2 = time.process_time()
    tip = r.tip(b)[:, [0, 2]]
    return t2 - t0, t2 - t1, r.t, tip, dict(r.stats)


def exudyn_transient(N: int, h: float, T: float, rho: float, sparse: bool = False,
                     dopri5_rtol: float | None = None):
    """Exudyn GE2D released cantilever: (cpu_s incl. build and static, simulation cpu_s, t, tip, stats).
    ``sparse``: Exudyn's EigenSparse linear solver (else its dense one); ``dopri5_rtol``: DOPRI5
    with Exudyn's error-controlled step size at this tolerance (``h`` the largest step) instead of
    the fixed-step generalized-alpha (spectral radius ``rho``)."""
    from peers import exudyn_release
    t0 = time.process_time()
    _, mbs, ld, sens = exudyn_beam(N, tip_force=F_TIP)
    d, stats = exudyn_release(mbs, ld, sens, h, T, rho, sparse, dopri5_rtol=dopri5_rtol)
    return time.process_time() - t0, stats["sim_cpu_s"], d[:, 0], d[:, 1:3], stats


def tip_error(t, tip, ref_t, ref_tip):
    x = np.interp(ref_t, t, tip[:, 0])
    z = np.interp(ref_t, t, tip[:, 1])
    return float(np.max(np.hypot(x - ref_tip[:, 0], z - ref_tip[:, 1])) / TABLE1["L"])


def bench_transient(quick: bool, smoke: bool = False) -> dict:
    T = 0.1 if smoke else 0.5 if quick else 1.0
    Nref = 8 if smoke else 40 if quick else 80
    rref = 1e-10
    print(f"transient: reference phmech se3 N={Nref // 2},{Nref} IDA rtol {rref:g} over {T} s ...", flush=True)
    # IDA with every state in its error test: rtol then bounds the time error (the default
    # integrator's steps stop at its band's floor, 1/(20 band) = 0.5 ms here, whatever rtol)
    ref = {}
    for N in (Nref // 2, Nref):
        c, _, t, tip, stats = phmech_transient(N, rref, "klu", T, integrator="ida")
        ref[N] = (t, tip, c, stats)
        print(f"  N={N}: CPU {c:.1f} s, {stats['steps']} steps", flush=True)
    c, _, t, tip_r8, _ = phmech_transient(Nref, 1e-8, "klu", T, integrator="ida")
    # an independent discretization of the same beam: consistent element mass on N_ref elements
    _, _, t_c, tip_c, _ = phmech_transient(Nref, rref, "klu", T, "consistent", integrator="ida")
    t_ref = ref[Nref][0]
    ref_tip = ref[Nref][1] + (ref[Nref][1] - ref[Nref // 2][1]) / 3.0      # Richardson, order 2
    selfconv = dict(
        space_N_half_vs_N=tip_error(ref[Nref // 2][0], ref[Nref // 2][1], t_ref, ref[Nref][1]),
        richardson_correction=tip_error(t_ref, ref[Nref][1], t_ref, ref_tip),
        time_rtol_1em8_vs_1em10=tip_error(t_ref, tip_r8, t_ref, ref[Nref][1]),
        consistent_mass_N_vs_reference=tip_error(t_c, tip_c, t_ref, ref_tip))
    print(f"  self-convergence: {selfconv}", flush=True)

    runs = []
    ph_N = [4] if smoke else [5, 10, 20] if quick else [5, 10, 20, 40]
    rtols_all = [1e-4] if smoke else [1e-3, 1e-4, 1e-6, 1e-8]
    rtols_cfg = [1e-4] if smoke else [1e-3, 1e-4, 1e-5, 1e-6]
    ga_N = [3] if smoke else [3, 4] + ph_N + ([] if quick else [80])
    ga_h = [1e-2] if smoke else [1e-2, 5e-3, 2e-3, 1e-3, 5e-4]
    ga_rtol = [1e-4] if smoke else [1e-4, 1e-6]

    def phmech_point(variant, N, rtol, solver="klu", mass="lumped", **options):
        # as Exudyn's points (below): medians of three calls, one in quick and smoke runs
        c, cs, t, tip, stats = median_of_three(
            lambda: phmech_transient(N, rtol, solver, T, mass, **options), once=quick or smoke)
        e = tip_error(t, tip, t_ref, ref_tip)
        runs.append(dict(code="phmech", variant=variant, N=N, rtol=rtol, mass=mass, cpu_s=c, sim_cpu_s=cs,
                         error=e, stats=stats, **options))
        print(f"  phmech {variant:25s} N={N:3d} rtol {rtol:.0e} {options.get('step', '')}: err {e:.2e}, "
              f"CPU {c:.3f} s, {stats['steps']} steps, {stats['nonlinear_iters']} Newton, "
              f"{stats['jacobian_evals']} jac", flush=True)

    # IDA, every state in the error test (its default)
    for N in ph_N:
        for rtol in rtols_all:
            for solver in (["klu", "dense"] if N <= 10 and rtol == 1e-6 else ["klu"]):
                phmech_point(f"se3-ida-{solver}", N, rtol, solver, integrator="ida")
    # phmech's two best routes (the next two) also with consistent element mass, on the same
    # grids, each consistent point right after its lumped twin (the same machine load)
    masses = (("lumped", ""), ("consistent", "-consistent"))
    # IDA, twists out of the error test (BDF order <= 2)
    for N in ph_N:
        for rtol in rtols_cfg:
            for mass, suffix in masses:
                phmech_point("se3-ida-config" + suffix, N, rtol, mass=mass, error_test="configuration",
                             integrator="ida")
    # the default integrator (adaptive generalized-alpha, rtol alone): what a user gets without
    # solver options. It holds every state to rtol and resolves every mode in its band (raised
    # for the release), more than this tip error asks
    for N in ph_N:
        for rtol in ([1e-4] if smoke else [1e-2, 1e-3, 1e-4]):
            for mass, suffix in masses:
                phmech_point("se3-default" + suffix, N, rtol, mass=mass)
    # fixed-step generalized-alpha (rho_inf 0.9, as Exudyn's default); rtol = Newton tolerance
    # (steps land on the outputs: h = 10 ms runs 5 ms steps). From N = 3: with consistent mass 3
    # elements are within 1e-2 L (9.2e-3)
    for N in ga_N:
        for h in ga_h:
            for rtol in ga_rtol:
                for mass, suffix in masses:
                    phmech_point("se3-galpha" + suffix, N, rtol, mass=mass, integrator="generalized-alpha",
                                 step=h, rho_inf=0.9)
                # the same consistent route in the 3-D model (planar=False), issue 12's measure
                phmech_point("se3-galpha-consistent-3d", N, rtol, mass="consistent",
                             integrator="generalized-alpha", step=h, rho_inf=0.9, planar=False)
    # Exudyn GE2D at its best documented settings: fixed-step generalized-alpha (spectral radius 1
    # and its default 0.9) and DOPRI5 with its error-controlled step size (Exudyn's only adaptive
    # stepping: automaticStepSize works for its explicit integrators), each with its dense and
    # its sparse (EigenSparse) linear solver, the two back to back (the same machine load); the
    # Exudyn front is taken over all of them, so at each error level the faster one counts
    ex_N = [4] if smoke else [5, 10, 20, 40] if quick else [5, 10, 20, 40, 80]
    ex_h = [5e-3] if smoke else [5e-3, 1e-3, 2.5e-4] if quick else [5e-3, 2e-3, 1e-3, 5e-4, 2.5e-4, 1e-4]
    # DOPRI5 does not converge to the reference here (docs/performance.md) and costs 10-30 s per
    # point at N = 80: its grid stops at N = 40 and rtol 1e-6
    ex_dopri = [1e-4] if smoke else [1e-3, 1e-4, 1e-5, 1e-6]

    def exudyn_point(variant, N, h, rho, dopri5_rtol=None):
        for sparse in (False, True):
            reps = []
            for _ in range(1 if quick or smoke or N * T / h > 2e5 else 3):
                try:
                    reps.append(exudyn_transient(N, h, T, rho, sparse, dopri5_rtol))
                except Exception as e:  # noqa: BLE001 -- a failed point is a result too
                    runs.append(dict(code="exudyn", variant=f"{variant}-{'sparse' if sparse else 'dense'}",
                                     N=N, h=h, rtol=dopri5_rtol, failed=f"{type(e).__name__}: {e}"))
                    print(f"  exudyn {variant} N={N:3d} h={h:.1e}: FAILED ({e})", flush=True)
                    break
            if not reps:
                continue
            c = float(np.median([r[0] for r in reps]))
            _, cs, t, tip, stats = reps[0]
            e = tip_error(t, tip, t_ref, ref_tip)       # Exudyn's y is phmech's z (both downward negative)
            v = f"{variant}-{'sparse' if sparse else 'dense'}"
            runs.append(dict(code="exudyn", variant=v, N=N, h=h, rtol=dopri5_rtol, cpu_s=c,
                             sim_cpu_s=float(np.median([r[1] for r in reps])), error=e, stats=stats))
            print(f"  exudyn {v:28s} N={N:3d} h={h:.1e} {'' if dopri5_rtol is None else f'rtol {dopri5_rtol:.0e}'}: "
                  f"err {e:.2e}, CPU {c:.3f} s", flush=True)

    for N in (ex_N if have("exudyn") else []):
        for h in ex_h:
            exudyn_point("ge2d-galpha-rho1", N, h, 1.0)
            if h in (1e-3, 2.5e-4):
                exudyn_point("ge2d-galpha-rho0.9", N, h, 0.9)
        for tol in (ex_dopri if N <= 40 else []):
            exudyn_point("ge2d-dopri5", N, 1e-2, 1.0, tol)

    # more peers (benchmarks/peers.py): Exudyn's 3-D beam (like-for-like), its ANCF cable
    # (Euler-Bernoulli), MuJoCo's cable (Rayleigh, inextensible: each of its integrators, the
    # front over them picks the fastest at each error level) and PyElastica's Cosserat rod
    # (explicit position Verlet; shear, extension, rotary inertia as phmech's beam): the ANCF
    # cable and MuJoCo converge to other beam models, so their error against this reference
    # stops at the model difference
    import peers
    mj = ([("mujoco", f"cable-{i.lower()}", lambda N, h, T, i=i: peers.mujoco_cable_transient(N, h, T, integrator=i),
            [5, 10, 20], hs) for i, hs in (("RK4", [5e-4] if quick else [1e-3, 5e-4]),
                                            ("implicitfast", [2.5e-4, 1e-4] if quick else [5e-4, 2.5e-4, 1e-4]),
                                            ("Euler", [1e-4, 5e-5]))])
    # PyElastica converges at first order in N here (its static tip: module doc of peers.py), so
    # its meshes go further than the others'
    el = [("pyelastica", "cosserat-verlet", peers.pyelastica_transient,
           [5, 10, 20, 40, 80, 160] if quick else [5, 10, 20, 40, 80, 160, 320], [None])]
    peer_grid = ([("exudyn", "ge3d-galpha-rho1", peers.exudyn_ge3d_transient,
                   [5, 10, 20, 40] if quick else [5, 10, 20, 40, 80],
                   [5e-3, 1e-3] if quick else [5e-3, 2e-3, 1e-3, 5e-4]),
                  ("exudyn", "ancf-galpha-rho1", peers.exudyn_ancf_transient, [5, 10, 20], [5e-3, 1e-3])] + mj + el)
    if smoke:
        peer_grid = [("exudyn", "ge3d-galpha-rho1", peers.exudyn_ge3d_transient, [4], [5e-3]),
                     ("mujoco", "cable-rk4", peers.mujoco_cable_transient, [4], [1e-3]),
                     ("pyelastica", "cosserat-verlet", peers.pyelastica_transient, [4], [None])]
    for code, variant, fn, Ns, hs in peer_grid:
        if not have({"pyelastica": "elastica"}.get(code, code)):
            print(f"  {code} not installed: skipped", flush=True)
            continue
        for N in Ns:
            for h in hs:
                try:
                    c, t, tip, info = fn(N, h, T)
                except Exception as e:  # noqa: BLE001 -- a failed point is a result too
                    runs.append(dict(code=code, variant=variant, N=N, h=h, failed=f"{type(e).__name__}: {e}"))
                    print(f"  {code} {variant} N={N:3d} h={h}: FAILED ({e})", flush=True)
                    continue
                e = tip_error(t, tip, t_ref, ref_tip)
                h = info.get("h", h)
                runs.append(dict(code=code, variant=variant, N=N, h=h, cpu_s=c, error=e,
                                 sim_cpu_s=info.get("sim_cpu_s"),
                                 stats={k: v for k, v in info.items() if isinstance(v, (int, float, str))}))
                print(f"  {code} {variant} N={N:3d} h={h:.1e}: err {e:.2e}, CPU {c:.3f} s", flush=True)

    def front(pred):
        rs = [r for r in runs if pred(r) and "error" in r]
        return pareto([r["cpu_s"] for r in rs], [r["error"] for r in rs])
    # phmech's best front over its lumped mass (the default before session 12), as in the
    # earlier runs; consistent (the default now) apart
    fph = front(lambda r: r["code"] == "phmech" and r["mass"] == "lumped")
    fph_c = front(lambda r: r["code"] == "phmech" and r["mass"] == "consistent"
                  and not r["variant"].endswith("-3d"))
    # phmech's best over every route that solved the 3-D DAE (IDA's, and the generalized-alpha's
    # with planar=False)
    fph_3d = front(lambda r: r["code"] == "phmech" and r["stats"].get("planar") is None)
    fex = front(lambda r: r["code"] == "exudyn" and r["variant"].startswith("ge2d"))
    levels = [3e-2, 1e-2, 3e-3, 1e-3, 3e-4]
    by_variant = {}
    for v in sorted({r["variant"] for r in runs if r["code"] == "phmech"}):
        by_variant[v] = ratios(front(lambda r, v=v: r["variant"] == v), fex, levels)
    # what consistent mass costs on the same grid point (N, rtol, step), consistent / lumped
    key = lambda r: (r["N"], r["rtol"], r.get("step"))                           # noqa: E731
    same_grid = {}
    for v in ("se3-ida-config", "se3-galpha"):
        lumped = {key(r): r for r in runs if r["variant"] == v}
        pairs = [(lumped[key(r)], r) for r in runs if r["variant"] == v + "-consistent" and key(r) in lumped]
        same_grid[v] = {q: float(np.median([c[q] / a[q] for a, c in pairs])) for q in ("cpu_s", "sim_cpu_s")}
        same_grid[v].update(steps=float(np.median([c["stats"]["steps"] / a["stats"]["steps"] for a, c in pairs])),
                            pairs=len(pairs))
    by_peer = {f"{code}-{variant}": ratios(fph, front(lambda r, v=variant: r["variant"] == v), levels)
               for code, variant, *_ in peer_grid}
    by_peer["mujoco-cable-best"] = ratios(fph, front(lambda r: r["code"] == "mujoco"), levels)
    def at_most(f):
        """Levels above a front's least accurate point: that point's CPU bounds the ratio."""
        return {f"{e:.0e}": dict(phmech_cpu_s=f[0][0], phmech_error=f[0][1],
                                 exudyn_cpu_s=cpu_at_error(fex, e), ratio_at_most=f[0][0] / cpu_at_error(fex, e))
                for e in levels if f and e > f[0][1] and cpu_at_error(fex, e) is not None}
    table = level_table(runs, TRANSIENT_GROUPS, [1e-2, 3e-3, 1e-3, 3e-4])
    out = dict(problem=f"Table I cantilever (table1_properties(1.0)) released from static tip force "
                       f"{F_TIP:.1f} N; tip (x,z) every {DT_OUT} s over {T} s",
               error="max_t |tip - tip_ref| / L",
               reference=dict(code="phmech se3 KLU", integrator="ida", error_test="all", N=[Nref // 2, Nref], rtol=rref,
                              atol="rtol * 1e-2 (phmech default)",
                              extrapolation="Richardson, tip_ref = tip_N + (tip_N - tip_N/2)/3",
                              cpu_s=[ref[Nref // 2][2], ref[Nref][2]], self_convergence=selfconv),
               cpu_note="cpu_s includes model build and the static solution; sim_cpu_s the time integration "
                        "only; phmech's and Exudyn's: medians of three calls (one in quick runs, or when a "
                        "call takes more than 1 s for phmech, more than 2e5 element-steps for Exudyn)",
               machine=machine(), runs=runs, pareto_phmech=fph, pareto_phmech_consistent=fph_c,
               pareto_exudyn=fex,
               cpu_ratio_at_equal_error=ratios(fph, fex, levels),
               cpu_ratio_at_equal_error_consistent=ratios(fph_c, fex, levels),
               # levels above the consistent front's least accurate point have no ratio (None):
               # that point already reaches them, so its CPU bounds the ratio from above
               cpu_ratio_at_equal_error_consistent_at_most=at_most(fph_c),
               # phmech's best in the 3-D DAE (IDA, generalized-alpha with planar=False): issue
               # 12's "in the 3-D model"; the generalized-alpha routes above solve in-plane
               pareto_phmech_3d=fph_3d,
               cpu_ratio_at_equal_error_3d=ratios(fph_3d, fex, levels),
               cpu_ratio_at_equal_error_3d_at_most=at_most(fph_3d),
               cpu_ratio_at_equal_error_by_phmech_variant=by_variant,
               consistent_over_lumped_same_grid_median=same_grid,
               cpu_ratio_phmech_best_over_peer=by_peer,
               # the headline table (benchmarks/report.py prints it): per error level the cheapest
               # measured point of each group that reaches it, by total CPU and by integration CPU
               cheapest_at_level=table,
               cheapest_note="cheapest measured point with error <= level (no interpolation); groups: "
                             + "; ".join(f"{k}: {v[1]}" for k, v in TRANSIENT_GROUPS.items())
                             + ". Totals: phmech and Exudyn include build and the static solution (a Newton "
                               "solve in both); MuJoCo's total includes this script's Python Newton statics "
                               "and PyElastica's is its integration only (it has no static solver: the initial "
                               "state comes from a damped relaxation whose CPU is in the run's stats), so "
                               "compare those two on integration CPU (sim_cpu_s).",
               smoke=smoke, quick=quick,
               ratio_note="cpu_ratio_at_equal_error* are phmech / Exudyn GE2D (ratio > 1: phmech slower); "
                          "cpu_ratio_at_equal_error and pareto_phmech: phmech's lumped-mass routes (mass='lumped'), "
                          "*_consistent: its consistent-mass routes (the default mass; variants *-consistent); "
                          "*_3d: every route that solved the 3-D DAE; "
                          "cpu_ratio_phmech_best_over_peer compares phmech's best lumped front with each other peer")
    write_json("bench_transient", out)
    plot_transient(out, t_ref, ref_tip)
    return out


#: the groups of the transient's level table: name -> (predicate on a run, description)
TRANSIENT_GROUPS = {
    "phmech": (lambda r: r["code"] == "phmech", "every phmech route (IDA, IDA configuration test, "
               "generalized-alpha; lumped and consistent mass; in-plane and 3-D)"),
    "phmech-default": (lambda r: r["code"] == "phmech" and r["variant"].startswith("se3-default"),
                       "phmech's default integrator (adaptive generalized-alpha, rtol alone; either mass)"),
    "phmech-3d": (lambda r: r["code"] == "phmech" and r["stats"].get("planar") is None,
                  "phmech routes that solved the 3-D DAE"),
    "exudyn-ge2d": (lambda r: r["code"] == "exudyn" and r["variant"].startswith("ge2d"),
                    "Exudyn GE2D, its best of generalized-alpha (rho 1, 0.9) and DOPRI5 with automatic step, "
                    "dense or sparse solver"),
    "exudyn-ge2d-dense": (lambda r: r["code"] == "exudyn" and r["variant"].startswith("ge2d")
                          and r["variant"].endswith("-dense"), "Exudyn GE2D, dense solver only"),
    "exudyn-ge2d-sparse": (lambda r: r["code"] == "exudyn" and r["variant"].startswith("ge2d")
                           and r["variant"].endswith("-sparse"), "Exudyn GE2D, sparse solver only"),
    "exudyn-ge3d": (lambda r: r["code"] == "exudyn" and r["variant"].startswith("ge3d"),
                    "Exudyn 3-D geometrically exact beam (Rxyz nodes), generalized-alpha"),
    "mujoco-cable": (lambda r: r["code"] == "mujoco", "MuJoCo cable, its fastest of RK4, implicitfast, Euler "
                     "(a Rayleigh beam: stops at the model difference)"),
    "pyelastica": (lambda r: r["code"] == "pyelastica", "PyElastica Cosserat rod, position Verlet at half "
                   "its stability-limit step"),
}


def level_table(runs, groups, levels) -> dict:
    """Per level (key f"{e:.0e}") and group: the cheapest measured point with error <= level, by
    total CPU (``cpu_s``) and by integration CPU (``sim_cpu_s``), with its setting."""
    out = {}
    for e in levels:
        row = {}
        for g, (pred, _) in groups.items():
            ok = [r for r in runs if "error" in r and r["error"] <= e and pred(r)]
            cell = {}
            for key in ("cpu_s", "sim_cpu_s"):
                ok_k = [r for r in ok if r.get(key) is not None]
                if ok_k:
                    b = min(ok_k, key=lambda r: r[key])
                    cell[key] = b[key]
                    cell[key + "_point"] = {k: b.get(k) for k in ("variant", "N", "h", "rtol", "step", "mass", "error")
                                            if b.get(k) is not None}
            row[g] = cell or None
        out[f"{e:.0e}"] = row
    return out


# ------------------------------------------------------------------ 3. whip (driven base)
WHIP_A, WHIP_D = 0.3, 0.15     # base stroke [m] along the transverse axis and its duration [s]


def whip_base(t: float) -> tuple:
    """The base's transverse position and speed: phmech's Cycloidal(WHIP_A, 0, WHIP_D) (C2)."""
    u = min(max(t / WHIP_D, 0.0), 1.0)
    return (WHIP_A * (u - np.sin(2 * np.pi * u) / (2 * np.pi)),
            WHIP_A / WHIP_D * (1 - np.cos(2 * np.pi * u)) if t < WHIP_D else 0.0)


def phmech_whip(N: int, rtol: float, T: float, mass: str = "consistent", **options):
    """Table I rod, straight at rest, its base driven along z (phmech's transverse axis of the
    cantilever's bending) by a Prismatic pair with the Cycloidal stroke: (cpu_s, sim_cpu_s, t,
    tip (x, z), stats)."""
    import phmech as ph
    from phmech.section import table1_properties
    t0 = time.process_time()
    m = ph.Mechanism()
    b = m.add_flexible_link("b", TABLE1["L"], table1_properties(1.0), elements=N, mass=mass)
    m.add_pair("base", ph.Prismatic("z"), m.ground, b.start, driven=ph.Cycloidal(WHIP_A, 0.0, WHIP_D))
    t1 = time.process_time()
    r = m.simulate(T, DT_OUT, rtol=rtol, linear_solver="klu", **options)
    t2 = time.process_time()
    return t2 - t0, t2 - t1, r.t, r.tip(b)[:, [0, 2]], dict(r.stats)


def exudyn_whip(N: int, h: float, T: float, rho: float = 1.0, sparse: bool = False):
    """Exudyn GE2D rod, its first node's x and rotation held by CoordinateConstraints and its y
    driven through an offsetUserFunction (a Python function per evaluation: Exudyn's documented
    way to prescribe a coordinate): (cpu_s, sim_cpu_s, t, tip (x, y), stats)."""
    import exudyn as exu
    import exudyn.solver
    from exudyn.itemInterface import CoordinateConstraint, MarkerNodeCoordinate, NodePointGround
    t0 = time.process_time()
    SC, mbs, _, sens = exudyn_beam(N, clamp=False)
    first = 0
    gnd = mbs.AddNode(NodePointGround(referenceCoordinates=[0, 0, 0]))
    mg = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=gnd, coordinate=0))
    for c in range(3):
        mc = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=first, coordinate=c))
        kw = dict(offsetUserFunction=lambda mbs_, t, item, off: whip_base(t)[0]) if c == 1 else {}
        mbs.AddObject(CoordinateConstraint(markerNumbers=[mg, mc], **kw))
    mbs.Assemble()
    ss = exudyn_settings(sparse)
    ss.timeIntegration.endTime = T
    ss.timeIntegration.numberOfSteps = int(round(T / h))
    ss.timeIntegration.generalizedAlpha.spectralRadius = rho
    t1 = time.process_time()
    exudyn.solver.SolveDynamic(mbs, ss)
    t2 = time.process_time()
    d = np.asarray(mbs.GetSensorStoredData(sens))
    return t2 - t0, t2 - t1, d[:, 0], d[:, 1:3].copy(), dict(steps=int(round(T / h)))


def bench_whip(quick: bool, smoke: bool = False) -> dict:
    """The rod whipped by its driven base: phmech, Exudyn GE2D, PyElastica at matched error
    against phmech's IDA reference (rtol 1e-10, N_ref/2 and N_ref, Richardson)."""
    import peers
    T = 0.1 if smoke else 0.5
    Nref = 8 if smoke else 40 if quick else 80
    print(f"whip: reference phmech se3 N={Nref // 2},{Nref} IDA rtol 1e-10 over {T} s ...", flush=True)
    ref = {}
    for N in (Nref // 2, Nref):
        c, _, t, tip, st = phmech_whip(N, 1e-10, T, integrator="ida")
        ref[N] = (t, tip, c)
        print(f"  N={N}: CPU {c:.1f} s, {st['steps']} steps", flush=True)
    t_ref = ref[Nref][0]
    ref_tip = ref[Nref][1] + (ref[Nref][1] - ref[Nref // 2][1]) / 3.0
    selfconv = dict(space_N_half_vs_N=tip_error(ref[Nref // 2][0], ref[Nref // 2][1], t_ref, ref[Nref][1]),
                    richardson_correction=tip_error(t_ref, ref[Nref][1], t_ref, ref_tip))
    runs = []

    def add(code, variant, N, c, cs, t, tip, **kw):
        e = tip_error(t, tip, t_ref, ref_tip)
        runs.append(dict(code=code, variant=variant, N=N, cpu_s=c, sim_cpu_s=cs, error=e, **kw))
        print(f"  {code} {variant:26s} N={N:3d} {kw}: err {e:.2e}, CPU {c:.3f} s", flush=True)

    Ns = [4] if smoke else [5, 10, 20] if quick else [5, 10, 20, 40]
    for N in Ns:
        for rtol in ([1e-4] if smoke else [1e-3, 1e-4, 1e-5, 1e-6]):
            c, cs, t, tip, st = median_of_three(lambda: phmech_whip(N, rtol, T), smoke)
            add("phmech", "se3-default-consistent", N, c, cs, t, tip, rtol=rtol, steps=st["steps"])
            c, cs, t, tip, st = median_of_three(lambda: phmech_whip(
                N, rtol, T, integrator="ida", error_test="configuration"), smoke)
            add("phmech", "se3-ida-config-consistent", N, c, cs, t, tip, rtol=rtol, steps=st["steps"])
        # the fixed-step generalized-alpha, the transient's cheapest route and Exudyn's scheme,
        # on Exudyn's steps (rho_inf 0.9; rtol = Newton's tolerance), with either element mass
        for h in ([5e-3] if smoke else [5e-3, 1e-3, 2.5e-4]):
            for mass, suffix in (("lumped", ""), ("consistent", "-consistent")):
                c, cs, t, tip, st = median_of_three(lambda: phmech_whip(
                    N, 1e-4, T, mass, integrator="generalized-alpha", step=h, rho_inf=0.9), smoke)
                add("phmech", "se3-galpha" + suffix, N, c, cs, t, tip, step=h, mass=mass,
                    steps=st["steps"])
        if have("exudyn"):
            for h in ([5e-3] if smoke else [5e-3, 1e-3, 2.5e-4]):
                for sparse in (False, True):
                    try:
                        c, cs, t, tip, st = median_of_three(
                            lambda: exudyn_whip(N, h, T, 1.0, sparse), smoke)
                    except Exception as ex:  # noqa: BLE001 -- a failed point is a result too
                        runs.append(dict(code="exudyn", N=N, h=h, failed=f"{type(ex).__name__}: {ex}"))
                        continue
                    add("exudyn", f"ge2d-galpha-rho1-{'sparse' if sparse else 'dense'}", N, c, cs, t, tip, h=h)
    if have("elastica"):
        for N in ([4] if smoke else [5, 10, 20, 40, 80, 160] if quick else [5, 10, 20, 40, 80, 160, 320]):
            c, t, tip, info = peers.pyelastica_whip(N, None, T)   # one call: ~2 s at N = 320
            add("pyelastica", "cosserat-verlet", N, c, c, t, tip, h=info["h"], steps=info["steps"])
    groups = {k: v for k, v in TRANSIENT_GROUPS.items()
              if k in ("phmech", "exudyn-ge2d", "exudyn-ge2d-dense", "exudyn-ge2d-sparse", "pyelastica")}
    out = dict(problem=f"Table I rod (table1_properties(1.0)) straight at rest, base driven transversally by a "
                       f"cycloidal stroke of {WHIP_A} m over {WHIP_D} s (clamped orientation); tip every {DT_OUT} s "
                       f"over {T} s",
               error="max_t |tip - tip_ref| / L",
               reference=dict(code="phmech se3 KLU, IDA, every state in the error test", N=[Nref // 2, Nref],
                              rtol=1e-10, extrapolation="Richardson (order 2)", cpu_s=[ref[Nref // 2][2], ref[Nref][2]],
                              self_convergence=selfconv),
               machine=machine(), runs=runs, cheapest_at_level=level_table(runs, groups, [1e-2, 3e-3, 1e-3, 3e-4]),
               cpu_note="phmech's and Exudyn's CPU: medians of three calls (one when a call takes "
                        "more than 1 s); PyElastica's: one call",
               cheapest_note="cheapest measured point with error <= level; PyElastica's cpu_s is its integration "
                             "(it starts at rest: nothing else to count)",
               smoke=smoke, quick=quick)
    write_json("bench_whip", out)
    return out


def plot_transient(out, t_ref, ref_tip):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(1, 2, figsize=(12, 4.2))
    # every point as a marker, each variant's Pareto front as a line
    variants = sorted({(r["code"], r["variant"]) for r in out["runs"]})
    for k, (code, var) in enumerate(variants):
        rs = [r for r in out["runs"] if r["variant"] == var and r["code"] == code and "error" in r]
        col = plt.cm.tab20(k % 20)
        ph = code == "phmech"
        ax[0].loglog([r["cpu_s"] for r in rs], [r["error"] for r in rs], "o" if ph else "s",
                     color=col, ms=3, alpha=0.5)
        p = np.array(pareto([r["cpu_s"] for r in rs], [r["error"] for r in rs]))
        if len(p):
            ax[0].loglog(p[:, 0], p[:, 1], "-" if ph else "--", color=col, lw=1.8, label=f"{code} {var}")
    ax[0].set(xlabel="CPU time [s] (build + static + integration)", ylabel="max tip error / L",
              title="released cantilever: work-precision (lines: Pareto fronts)")
    ax[0].grid(True, which="both", alpha=0.3)
    ax[0].legend(fontsize=7)
    ax[1].plot(t_ref, ref_tip[:, 1], "k")
    ax[1].set(xlabel="t [s]", ylabel="tip z [m]", title="reference tip deflection")
    ax[1].grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(RESULTS, "bench_transient.png"), dpi=120)
    plt.close(fig)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer points, shorter transient (~ a few minutes)")
    ap.add_argument("--only", nargs="+", choices=["modes", "transient", "whip"],
                    default=["modes", "transient", "whip"])
    ap.add_argument("--smoke", action="store_true",
                    help="seconds: one coarse point per code, 0.1 s simulated (tests/test_benchmarks_smoke.py)")
    a = ap.parse_args()
    ensure_peers()
    t0 = time.time()
    if "modes" in a.only:
        bench_modes(a.quick, a.smoke)
    if "transient" in a.only:
        bench_transient(a.quick or a.smoke, a.smoke)
    if "whip" in a.only:
        bench_whip(a.quick or a.smoke, a.smoke)
    print(f"benchmarks done in {time.time() - t0:.0f} s wall", flush=True)


if __name__ == "__main__":
    main()

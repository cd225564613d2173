"""Scaling of phmech against peers (GitHub issue 6, item 4): CPU time per simulated second and
peak memory against problem size, with fitted exponents.

    python benchmarks/bench_scaling.py [--quick] [--budget S] [--only elements chain]

1. ``elements``: the paper's Table I cantilever (``table1_properties(1.0)``), straight and at rest,
   tip force F_TIP (downward) applied at t = 0, simulated T seconds; N = 10 ... 1000 elements.
   phmech ``se3``: the default integrator (``phmech-default``, rtol 1e-4), IDA with KLU (rtol
   1e-4, every state in its error test: ``phmech-klu``; ``error_test="configuration"``:
   ``phmech-klu-cfg``) and the fixed-step ``integrator="generalized-alpha"`` with h = 1e-3,
   rho_inf = 1 (``phmech-klu-galpha``); Exudyn
   ``ObjectBeamGeometricallyExact2D`` (planar Simo-Reissner), ``ObjectBeamGeometricallyExact``
   (3-D, Euler-parameter nodes, like-for-like with phmech's 3-D model) and ``ObjectANCFCable2D``
   (planar ANCF Euler-Bernoulli cable, same EI, EA, rhoA); Exudyn: generalized-alpha
   (spectral radius 1), h = 1e-3, sparse LU for N > 40.
2. ``chain``: n identical slender rigid links (0.1 m, 0.1 kg, uniform-rod inertia) joined by
   revolute pairs with parallel axes (z), first pivot to ground, released from horizontal under
   gravity -y, simulated T = 0.5 s (short: the multi-link chain is chaotic). phmech
   ``Mechanism`` (the default integrator at rtol 1e-4, ``chain-phmech-default``; IDA with KLU and
   dense, rtol 1e-6; ``integrator="tree"``, joint coordinates and Dormand-Prince 5(4), rtol 1e-6,
   ``chain-phmech-tree``), Exudyn (3-D rigid bodies with Euler parameters +
   revolute joints, redundant coordinates, generalized-alpha h = 1e-4, spectral radius 0.8,
   Newton tolerance 1e-10),
   MuJoCo (hinge chain in minimal coordinates, RK4 at dt = 1e-3 and 4e-3, Euler and implicitfast
   at 1e-4: docs/perf_scaling.md compares phmech with the cheapest one at or below its error);
   outside ``--smoke`` also ladders for matched error across levels (benchmarks/report.py
   interpolates them): MuJoCo RK4 at 0.5 and 2 ms, phmech's default at rtol 1e-3 and 1e-5, IDA
   (KLU) at rtol 1e-5 and 1e-8, the tree integrator at rtol 1e-3, 1e-4, 1e-5 and 1e-7; the JSON's
   ``chain_at_matched_error`` holds each ladder's rate at fixed error levels and its ratio to
   MuJoCo RK4's. Accuracy: largest error over the
   links' free-end positions at T against MuJoCo RK4 with dt = 1e-5 (checked against phmech at
   rtol 1e-10 for n <= 10); for long chains the end link is still nearly in free fall at T.

The output period is fixed (ELEM_DT_OUT, CHAIN_DT_OUT) whatever T, so the default integrator's
band (1 / (2 dt_out)) is the same for the T and the T/5 run (it was tied to T before: both runs
then took the same steps and the rate was meaningless).

CPU per simulated second = (cpu(T) - cpu(T/5)) / (0.8 T) (free of set-up cost), measured in a
fresh subprocess per point (median over 3 repetitions where a run is cheap); peak RSS =
``ru_maxrss`` of that subprocess, which imports numpy, phmech, Exudyn and MuJoCo (the baseline is
stored). A point whose predicted or actual wall time exceeds ``--budget`` is recorded as skipped.
Writes ``benchmarks/results/bench_scaling.json`` and ``.png``; with ``--only`` the other part's
points are kept from the existing JSON.
"""
from __future__ import annotations

import argparse
import inspect
import json
import os
import resource
import subprocess
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from run import (EA1, F_TIP, RESULTS, TABLE1, ensure_peers, exudyn_beam, exudyn_stats,  # noqa: E402
                 exudyn_settings, have, machine, phmech_cantilever, write_json)

# chain of rigid links
LINK_L, LINK_M, LINK_R = 0.1, 0.1, 0.005                       # [m], [kg], rod radius [m]
LINK_I = (0.5 * LINK_M * LINK_R ** 2, LINK_M * LINK_L ** 2 / 12, LINK_M * LINK_L ** 2 / 12)
G = 9.81
CHAIN_T = 0.5
ELEM_T = 0.1
# output periods, the same for every T, and the default integrator's band given explicitly as
# 1/(2 dt_out) (200 Hz for the beam, above its fifth bending mode; 25 Hz for the chain): left to
# itself the band is at least 50 / T (docs/integrators.md), which ties it to T again
ELEM_DT_OUT = 2.5e-3
CHAIN_DT_OUT = 0.02
EX_H_BEAM = 1e-3
EX_H_CHAIN = 1e-4
EX_RHO_CHAIN = 0.8     # with 1.0 Exudyn's Newton fails for n = 100 at t = 0.48 s (step size hits its minimum)
MJ_DT = 1e-3
MJ_DT_REF = 1e-5


def has_error_test() -> bool:
    import phmech
    return "error_test" in inspect.signature(phmech.Mechanism.simulate).parameters


def has_galpha() -> bool:
    import phmech
    return "integrator" in inspect.signature(phmech.Mechanism.simulate).parameters


# ------------------------------------------------------------------ element models (tip at T)
def ph_beam(N: int, T: float, rtol: float, solver: str, error_test: str | None = None,
            ga_step: float | None = None, default: bool = False):
    """phmech se3 cantilever, tip force at t = 0; returns (cpu_s of simulate, tip (x, z) at T, stats).
    IDA (``error_test``: None = every state); ``ga_step``: phmech's fixed-step generalized-alpha
    (rho_inf 1, as Exudyn here); ``default``: the default integrator (step-size controlled
    generalized-alpha) at ``rtol``."""
    import phmech as ph
    m, b = phmech_cantilever(N)
    m.add_wrench("tip", b.end, (0, 0, 0, 0, 0, -F_TIP), law=ph.Constant(1.0))
    kw = dict(integrator="ida", **({} if error_test is None else {"error_test": error_test}))
    if default:
        kw = {"band": 0.5 / ELEM_DT_OUT}
    if ga_step is not None:
        kw = dict(integrator="generalized-alpha", step=ga_step, rho_inf=1.0)
        rtol = 1e-6
    t0 = time.process_time()
    r = m.simulate(T, ELEM_DT_OUT, rtol=rtol, linear_solver=solver, **kw)
    c = time.process_time() - t0
    return c, r.tip(b)[-1, [0, 2]], dict(r.stats)


def _ex_solve(mbs, ss, T: float, h: float, sparse: bool, rho: float = 1.0):
    import exudyn as exu
    import exudyn.solver
    ss.timeIntegration.endTime = T
    ss.timeIntegration.numberOfSteps = int(round(T / h))
    ss.timeIntegration.generalizedAlpha.spectralRadius = rho
    ss.linearSolver.solverType = exu.LinearSolverType.EigenSparse if sparse else exu.LinearSolverType.EXUdense
    t0 = time.process_time()
    exudyn.solver.SolveDynamic(mbs, ss)
    return time.process_time() - t0


def ex_ge2d(N: int, T: float, h: float):
    """Exudyn ObjectBeamGeometricallyExact2D (as run.py's exudyn_beam); tip (x, y)."""
    _, mbs, _, sens = exudyn_beam(N, tip_force=F_TIP)
    ss = exudyn_settings(N > 40)
    ss.solution.sensors.writePeriod = T / 4
    c = _ex_solve(mbs, ss, T, h, N > 40)
    return c, np.asarray(mbs.GetSensorStoredData(sens))[-1, 1:3], exudyn_stats(mbs, T, h)


def ex_ancf(N: int, T: float, h: float):
    """Exudyn ObjectANCFCable2D (Euler-Bernoulli, same EI, EA, rhoA), clamped: x, y, slope_y fixed
    (the model of benchmarks/peers.py)."""
    from peers import exudyn_ancf_beam
    _, mbs, _, sens = exudyn_ancf_beam(N, EA1, tip_force=F_TIP)
    ss = exudyn_settings(N > 40)
    ss.solution.sensors.writePeriod = T / 4
    c = _ex_solve(mbs, ss, T, h, N > 40)
    return c, np.asarray(mbs.GetSensorStoredData(sens))[-1, 1:3], exudyn_stats(mbs, T, h)


def ex_ge3d(N: int, T: float, h: float):
    """Exudyn 3-D ObjectBeamGeometricallyExact on Euler-parameter nodes, section of
    table1_properties(1.0): stiffness diag(EA, kGA, kGA, GJ, EI, EI), inertia diag(rhoJ, rhoI, rhoI);
    clamped by a GenericJoint to a ground node; tip force -y; tip (x, y)."""
    import exudyn as exu
    from exudyn.itemInterface import (GenericJoint, LoadForceVector, MarkerNodePosition, MarkerNodeRigid,
                                      NodePointGround, NodeRigidBodyEP, ObjectBeamGeometricallyExact,
                                      SensorNode, VObjectBeamGeometricallyExact, VObjectJointGeneric)
    from phmech.section import table1_properties
    p = table1_properties(1.0)
    sec = exu.BeamSection()
    K, M = np.diag(p.stiffness), np.diag(p.inertia)        # phmech: (angular; linear) order
    sec.stiffnessMatrix = np.diag([K[3], K[4], K[5], K[0], K[1], K[2]])   # Exudyn: (n; m)
    sec.inertia = np.diag(M[:3])
    sec.massPerLength = float(M[3])
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    le = TABLE1["L"] / N
    nodes = [mbs.AddNode(NodeRigidBodyEP(referenceCoordinates=[le * i, 0, 0, 1, 0, 0, 0])) for i in range(N + 1)]
    for i in range(N):
        mbs.AddObject(ObjectBeamGeometricallyExact(nodeNumbers=[nodes[i], nodes[i + 1]], length=le,
                                                   sectionData=sec,
                                                   visualization=VObjectBeamGeometricallyExact(show=False)))
    g = mbs.AddNode(NodePointGround(referenceCoordinates=[0, 0, 0]))
    mbs.AddObject(GenericJoint(markerNumbers=[mbs.AddMarker(MarkerNodeRigid(nodeNumber=g)),
                                              mbs.AddMarker(MarkerNodeRigid(nodeNumber=nodes[0]))],
                               visualization=VObjectJointGeneric(show=False)))
    mbs.AddLoad(LoadForceVector(markerNumber=mbs.AddMarker(MarkerNodePosition(nodeNumber=nodes[-1])),
                                loadVector=[0, -F_TIP, 0]))
    sens = mbs.AddSensor(SensorNode(nodeNumber=nodes[-1], storeInternal=True,
                                    outputVariableType=exu.OutputVariableType.Position))
    mbs.Assemble()
    ss = exudyn_settings(N > 40)
    ss.solution.sensors.writePeriod = T / 4
    c = _ex_solve(mbs, ss, T, h, N > 40)
    return c, np.asarray(mbs.GetSensorStoredData(sens))[-1, 1:3], exudyn_stats(mbs, T, h)


# ------------------------------------------------------------------ chain models (tip of end link at T)
def ph_chain(n: int, T: float, rtol: float, solver: str, default: bool = False, tree: bool = False):
    """phmech chain: IDA (every state in its error test) at ``rtol``, the default integrator, or
    (``tree``) the tree integrator (joint coordinates, articulated-body algorithm, Dormand-Prince
    5(4): csrc/integrate/tree.c) without its error check (``error_check=False``: runs at rtol/10,
    /100 ... that estimate the result's error and keep it within rtol; here the error is measured
    against the reference, as MuJoCo's, and the check would cost 2-7x the run's CPU)."""
    import phmech as ph
    from phmech import se3
    m = ph.Mechanism(gravity=(0, -G, 0))
    prev, ends = ph.Frame(-1, np.eye(4)), []
    for i in range(n):
        b = m.add_rigid_body(f"l{i}", LINK_M, np.diag(LINK_I), com=(LINK_L / 2, 0, 0))
        m.add_pair(f"k{i}", ph.Revolute("z"), prev, b, x0=0.0)
        prev = ph.Frame(b.carrier, se3.translation([LINK_L, 0, 0]))
        ends.append(prev)
    t0 = time.process_time()
    r = m.simulate(T, CHAIN_DT_OUT, rtol=rtol, **(dict(integrator="tree", error_check=False) if tree else dict(
        linear_solver=solver, **(dict(band=0.5 / CHAIN_DT_OUT) if default else dict(integrator="ida")))))
    c = time.process_time() - t0
    return c, np.array([r.position(e)[-1, :2] for e in ends]), dict(r.stats)


def ex_chain(n: int, T: float, h: float):
    import exudyn as exu
    from exudyn.itemInterface import SensorBody
    from exudyn.rigidBodyUtilities import RigidBodyInertia
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    prev, bodies = mbs.CreateGround(show=False), []
    for i in range(n):
        b = mbs.CreateRigidBody(inertia=RigidBodyInertia(LINK_M, np.diag(LINK_I)),
                                referencePosition=[LINK_L * (i + 0.5), 0, 0], gravity=[0, -G, 0], show=False)
        mbs.CreateRevoluteJoint(itemNumbers=[prev, b], position=[LINK_L * i, 0, 0], axis=[0, 0, 1],
                                useGlobalFrame=True, show=False)
        prev = b
        bodies.append(b)
    mbs.Assemble()
    ss = exudyn_settings(n > 10)
    ss.solution.sensors.writePeriod = T / 5
    ss.timeIntegration.newton.relativeTolerance = 1e-10
    c = _ex_solve(mbs, ss, T, h, n > 10, EX_RHO_CHAIN)
    ends = np.array([mbs.GetObjectOutputBody(b, exu.OutputVariableType.Position, localPosition=[LINK_L / 2, 0, 0])[:2]
                     for b in bodies])
    return c, ends, exudyn_stats(mbs, T, h)


def mj_chain(n: int, T: float, dt: float, integrator: str = "RK4"):
    import mujoco
    body = "".join(f'<body pos="{0 if i == 0 else LINK_L} 0 0"><joint type="hinge" axis="0 0 1"/>'
                   f'<inertial pos="{LINK_L / 2} 0 0" mass="{LINK_M}" '
                   f'diaginertia="{LINK_I[0]!r} {LINK_I[1]!r} {LINK_I[2]!r}"/>' for i in range(n))
    xml = (f'<mujoco><option timestep="{dt!r}" integrator="{integrator}" gravity="0 {-G} 0">'
           f'<flag contact="disable"/></option><worldbody>{body}<site name="tip" pos="{LINK_L} 0 0"/>'
           + "</body>" * n + "</worldbody></mujoco>")
    # body k's origin is the pivot at the end of link k - 1
    M = mujoco.MjModel.from_xml_string(xml)
    D = mujoco.MjData(M)
    k = int(round(T / dt))
    t0 = time.process_time()
    for _ in range(k):
        mujoco.mj_step(M, D)
    c = time.process_time() - t0
    mujoco.mj_kinematics(M, D)
    ends = np.vstack([D.xpos[2:n + 1, :2], D.site_xpos[:1, :2]])     # xpos[0] = world, xpos[1] = pivot 0
    return c, ends, {"steps": k, "integrator": integrator}


def runner(code: str, size: int, setting: float):
    """fn(T) -> (cpu_s, tip, stats) for one code."""
    if code == "phmech-default":
        return lambda T: ph_beam(size, T, setting, "klu", default=True)
    if code == "phmech-klu":
        return lambda T: ph_beam(size, T, setting, "klu")
    if code == "phmech-klu-cfg":
        return lambda T: ph_beam(size, T, setting, "klu", "configuration")
    if code == "phmech-klu-galpha":
        return lambda T: ph_beam(size, T, setting, "klu", ga_step=setting)
    if code == "exudyn-ge2d":
        return lambda T: ex_ge2d(size, T, setting)
    if code == "exudyn-ge3d":
        return lambda T: ex_ge3d(size, T, setting)
    if code == "exudyn-ancf2d":
        return lambda T: ex_ancf(size, T, setting)
    if code.startswith("chain-phmech-default"):    # chain-phmech-default[-rtol<r>]: the setting is rtol
        return lambda T: ph_chain(size, T, setting, "klu", default=True)
    if code.startswith("chain-phmech-tree"):      # chain-phmech-tree[-rtol<r>]: the setting is rtol
        return lambda T: ph_chain(size, T, setting, "", tree=True)
    if code.startswith(("chain-phmech-klu", "chain-phmech-dense")):   # [-rtol<r>]
        return lambda T: ph_chain(size, T, setting, code.split("-")[2])
    if code == "chain-exudyn":
        return lambda T: ex_chain(size, T, setting)
    if code == "chain-mujoco":
        return lambda T: mj_chain(size, T, setting)
    if code.startswith("chain-mujoco-"):       # chain-mujoco-<integrator>[-<tag>]
        integ = {"rk4": "RK4", "euler": "Euler", "implicitfast": "implicitfast"}[code.split("-")[2]]
        return lambda T: mj_chain(size, T, setting, integ)
    raise ValueError(code)


def point(code: str, size: int, T: float, setting: float) -> dict:
    """One point in this (fresh) process: rate from cpu(T) - cpu(T/5), median of up to 3."""
    import phmech  # noqa: F401 -- every point loads all codes: one RSS baseline
    for peer in PEERS:
        __import__(peer)
    run = runner(code, size, setting)
    w0 = time.time()
    rates, runs = [], 0
    while True:
        c1, _, st5 = run(T / 5)
        cT, tip, stats = run(T)
        rates.append(max(cT - c1, 1e-9) / (0.8 * T))
        runs += 1
        if runs >= 3 or time.time() - w0 > 3.0:
            break
    rate = float(np.median(rates))
    ru = resource.getrusage(resource.RUSAGE_SELF)
    tip = np.asarray(tip)
    extra = {} if tip.ndim == 1 else {"link_ends": tip.tolist()}
    tip = tip if tip.ndim == 1 else tip[-1]
    return dict(code=code, size=size, T=T, setting=setting, cpu_T_s=cT, cpu_per_sim_s=rate, **extra,
                steps_T5=st5.get("steps"),
                rate_repetitions=runs, setup_cpu_s=max(cT - rate * T, 0.0), tip_end=tip.tolist(),
                maxrss_MB=ru.ru_maxrss / 1024.0, stats=stats)


# ------------------------------------------------------------------ driver
CODES = None     # --codes filter


#: the peers installed (a missing one's series are skipped)
PEERS = [p for p in ("exudyn", "mujoco") if have(p)]


def sweep(cases, budget_s: float, runs: list, skipped: list) -> None:
    for code, setting, T, sizes in cases:
        if CODES and code not in CODES:
            continue
        peer = code.replace("chain-", "").split("-")[0]
        if peer in ("exudyn", "mujoco") and peer not in PEERS:
            print(f"  {code}: {peer} not installed, skipped", flush=True)
            continue
        last = None          # (size, wall)
        for s in sizes:
            if last is not None:
                # predicted wall ~ size^2 (measured CPU exponents here are <= 2 except ANCF)
                p = 2.0
                pred = last[1] * (s / last[0]) ** p
                if pred > budget_s:
                    skipped.append(dict(code=code, size=s, reason=f"predicted wall {pred:.0f} s "
                                        f"(from {last[0]}: {last[1]:.0f} s, ~size^{p:g}) > budget {budget_s:.0f} s"))
                    print(f"  {code} {s}: skipped ({skipped[-1]['reason']})", flush=True)
                    continue
            t0 = time.time()
            try:
                pr = subprocess.run([sys.executable, os.path.abspath(__file__), "--point", code, str(s), repr(T),
                                     repr(setting)], capture_output=True, text=True, timeout=budget_s)
            except subprocess.TimeoutExpired:
                skipped.append(dict(code=code, size=s, reason=f"exceeded budget {budget_s:.0f} s wall"))
                print(f"  {code} {s}: {skipped[-1]['reason']}", flush=True)
                last = (s, 2 * budget_s)
                continue
            wall = time.time() - t0
            if pr.returncode != 0:
                skipped.append(dict(code=code, size=s, reason="failed: " + " | ".join(pr.stderr.strip().splitlines()[-2:])))
                print(f"  {code} {s}: {skipped[-1]['reason']}", flush=True)
                continue
            r = json.loads(pr.stdout.strip().splitlines()[-1])
            r["wall_s"] = wall
            runs.append(r)
            last = (s, wall)
            print(f"  {code:18s} {s:5d}: {r['cpu_per_sim_s']:.4g} CPU s/s (x{r['rate_repetitions']}), "
                  f"set-up {r['setup_cpu_s']:.2g} s, RSS {r['maxrss_MB']:.0f} MB, steps {r['stats'].get('steps')}, "
                  f"tip {np.round(r['tip_end'], 6).tolist()} ({wall:.0f} s wall)", flush=True)


def fit(rs, baseline, lo):
    rs = [r for r in rs if r["size"] >= lo]
    if len(rs) < 2:
        return None
    x = np.log([r["size"] for r in rs])
    mem = [r["maxrss_MB"] - baseline for r in rs]
    out = dict(fitted_on=[r["size"] for r in rs],
               cpu_exponent=float(np.polyfit(x, np.log([r["cpu_per_sim_s"] for r in rs]), 1)[0]))
    if min(mem) > 1.0:
        out["memory_exponent_above_baseline"] = float(np.polyfit(x, np.log(mem), 1)[0])
    else:
        out["memory_exponent_above_baseline"] = None
        out["memory_note"] = f"RSS within {max(abs(m) for m in mem):.1f} MB of baseline at some fitted size"
    return out


def chain_reference(n: int, T: float) -> dict:
    """MuJoCo RK4 at dt 1e-5; for n <= 10 also phmech IDA (KLU) at rtol 1e-10 (cross-check).
    Without MuJoCo: phmech IDA at rtol 1e-10."""
    if "mujoco" not in PEERS:
        c0 = time.process_time()
        _, tp, _ = ph_chain(n, T, 1e-10, "klu")
        return dict(size=n, link_ends=tp.tolist(), code="phmech IDA rtol 1e-10 (MuJoCo not installed)",
                    cpu_s=time.process_time() - c0)
    c, ends, _ = mj_chain(n, T, MJ_DT_REF)
    ref = dict(size=n, link_ends=ends.tolist(), code="mujoco RK4 dt 1e-5", cpu_s=c)
    if n <= 10:
        _, tp, _ = ph_chain(n, T, 1e-10, "klu")
        ref["phmech_rtol1e-10_vs_ref_m"] = float(np.max(np.linalg.norm(tp - ends, axis=1)))
    return ref


def bench_elements(quick: bool, budget: float, runs, skipped, smoke: bool = False) -> dict:
    Ns = [10] if smoke else [10, 30, 100] if quick else [10, 30, 100, 300, 1000]
    T = 0.0125 if smoke else 0.05 if quick else ELEM_T
    cases = [("phmech-default", 1e-4, T, Ns), ("phmech-klu", 1e-4, T, Ns)]
    if has_error_test():
        cases.append(("phmech-klu-cfg", 1e-4, T, Ns))
    if has_galpha():
        cases.append(("phmech-klu-galpha", EX_H_BEAM, T, Ns))
    cases += [("exudyn-ge2d", EX_H_BEAM, T, Ns), ("exudyn-ancf2d", EX_H_BEAM, T, Ns),
              ("exudyn-ge3d", EX_H_BEAM, T, Ns)]
    sweep(cases, budget, runs, skipped)
    cases = [c for c in cases if not CODES or c[0] in CODES]
    return {c: dict(setting=s, T=T, meaning="rtol" if c.startswith("phmech") and "galpha" not in c else
                    "step size h [s], spectral radius 1" + (" (phmech Newton rtol 1e-6)" if "galpha" in c else ""))
            for c, s, T, _ in cases}


def bench_chain(quick: bool, budget: float, runs, skipped, smoke: bool = False) -> tuple:
    ns = [3] if smoke else [1, 3, 10, 30] if quick else [1, 3, 10, 30, 100]
    T = 0.1 if smoke else CHAIN_T
    cases = [("chain-phmech-default", 1e-4, T, ns), ("chain-phmech-klu", 1e-6, T, ns),
             ("chain-phmech-dense", 1e-6, T, ns), ("chain-phmech-tree", 1e-6, T, ns),
             ("chain-exudyn", EX_H_CHAIN, T, ns), ("chain-mujoco", MJ_DT, T, ns),
             # MuJoCo's other integrators and steps: the table picks, per n, the cheapest that
             # reaches phmech's error (docs/perf_scaling.md)
             ("chain-mujoco-rk4-4ms", 4e-3, T, ns), ("chain-mujoco-euler", 1e-4, T, ns),
             ("chain-mujoco-implicitfast", 1e-4, T, ns)]
    if not smoke:
        # ladders, so that each code is compared with the others at matched error across error
        # levels (benchmarks/report.py interpolates each ladder in log-log at fixed levels):
        # MuJoCo RK4 (its best here: error ~ dt^4) at 0.5 / 1 / 2 / 4 ms, phmech's default at
        # rtol 1e-3 / 1e-4 / 1e-5, IDA (KLU) at rtol 1e-5 / 1e-6 / 1e-8
        cases += [("chain-mujoco-rk4-0.5ms", 5e-4, T, ns), ("chain-mujoco-rk4-2ms", 2e-3, T, ns),
                  ("chain-phmech-default-rtol1e-3", 1e-3, T, ns),
                  ("chain-phmech-default-rtol1e-5", 1e-5, T, ns),
                  ("chain-phmech-klu-rtol1e-5", 1e-5, T, ns), ("chain-phmech-klu-rtol1e-8", 1e-8, T, ns),
                  # the tree integrator (error ~ 3e-3 rtol m at n = 100): rtol 1e-3 ... 1e-7
                  ("chain-phmech-tree-rtol1e-3", 1e-3, T, ns), ("chain-phmech-tree-rtol1e-4", 1e-4, T, ns),
                  ("chain-phmech-tree-rtol1e-5", 1e-5, T, ns), ("chain-phmech-tree-rtol1e-7", 1e-7, T, ns)]
    sweep(cases, budget, runs, skipped)
    cases = [c for c in cases if not CODES or c[0] in CODES]
    refs = {}
    for n in ns:
        refs[n] = chain_reference(n, T)
        print(f"  chain reference n={n}: {refs[n]}", flush=True)
    for r in runs:
        if r["code"].startswith("chain-") and r["size"] in refs:
            d = np.linalg.norm(np.asarray(r["link_ends"]) - refs[r["size"]]["link_ends"], axis=1)
            r["error_m"] = float(np.max(d))
            r["end_link_error_m"] = float(d[-1])
    settings = {c: dict(setting=s, T=T, meaning="rtol" if "phmech" in c else
                        f"step size h [s], spectral radius {EX_RHO_CHAIN}" if c == "chain-exudyn" else
                        "RK4 step [s]" if c == "chain-mujoco" else f"MuJoCo {c.split('-')[2]} step [s]")
                for c, s, T, _ in cases}
    return settings, list(refs.values())


def plot(out):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(2, 2, figsize=(12, 8.5))
    for row, (prefix, xlabel) in enumerate((("", "elements N"), ("chain-", "bodies n"))):
        codes = sorted({r["code"] for r in out["runs"] if r["code"].startswith("chain-") == (prefix == "chain-")})
        for code in codes:
            rs = sorted((r for r in out["runs"] if r["code"] == code), key=lambda r: r["size"])
            f = out["fits"].get(code) or {}
            lab = code + (f" (CPU ~ size^{f['cpu_exponent']:.2f})" if f.get("cpu_exponent") is not None else "")
            ax[row, 0].loglog([r["size"] for r in rs], [r["cpu_per_sim_s"] for r in rs], "o-", label=lab)
            me = f.get("memory_exponent_above_baseline")
            ax[row, 1].loglog([r["size"] for r in rs], [max(r["maxrss_MB"] - out["baseline_rss_MB"], 0.1) for r in rs],
                              "o-", label=code + (f" (~ size^{me:.2f})" if me is not None else ""))
        ax[row, 0].set(xlabel=xlabel, ylabel="CPU s per simulated s",
                       title="Table I cantilever, tip force step" if row == 0 else
                       f"rigid chain released under gravity, T = {CHAIN_T} s")
        ax[row, 1].set(xlabel=xlabel, ylabel=f"peak RSS - baseline {out['baseline_rss_MB']:.0f} MB [MB]")
    for a in ax.flat:
        a.grid(True, which="both", alpha=0.3)
        if a.get_legend_handles_labels()[0]:
            a.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(RESULTS, "bench_scaling.png"), dpi=110)
    plt.close(fig)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="sizes up to 100 / 30, shorter beam run (< 4 min)")
    ap.add_argument("--only", nargs="+", choices=["elements", "chain"], default=["elements", "chain"])
    ap.add_argument("--budget", type=float, default=300.0, help="wall-time cap per point [s]")
    ap.add_argument("--codes", nargs="+", help="run only these series (others kept from the existing JSON)")
    ap.add_argument("--point", nargs=4, help=argparse.SUPPRESS)
    ap.add_argument("--smoke", action="store_true",
                    help="seconds: one small size per series (tests/test_benchmarks_smoke.py)")
    a = ap.parse_args()
    ensure_peers()
    global CODES
    CODES = a.codes
    if a.point:
        code, s, T, st = a.point
        print(json.dumps(point(code, int(s), float(T), float(st))))
        return
    t0 = time.time()
    base = subprocess.run([sys.executable, "-c", "import resource, numpy, phmech" + "".join(", " + p for p in PEERS) + "; "
                           "print(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss/1024)"],
                          capture_output=True, text=True, check=True)
    baseline = float(base.stdout.strip())
    runs, skipped, settings, refs = [], [], {}, []
    if "elements" in a.only:
        print("elements:", flush=True)
        settings.update(bench_elements(a.quick, a.budget, runs, skipped, a.smoke))
    if "chain" in a.only:
        print("chain:", flush=True)
        s, refs = bench_chain(a.quick, a.budget, runs, skipped, a.smoke)
        settings.update(s)
    old = os.path.join(RESULTS, "bench_scaling.json")
    if (set(a.only) != {"elements", "chain"} or a.codes) and os.path.exists(old):
        with open(old) as f:
            prev = json.load(f)
        done = set(settings)
        keep = lambda c: c not in done  # noqa: E731
        runs += [r for r in prev.get("runs", []) if keep(r["code"])]
        skipped += [r for r in prev.get("skipped", []) if keep(r["code"])]
        settings.update({c: v for c, v in prev.get("settings", {}).items() if keep(c)})
        if "chain" not in a.only:
            refs = prev.get("chain_reference", [])
    fits = {}
    for code in sorted({r["code"] for r in runs}):
        rs = sorted((r for r in runs if r["code"] == code), key=lambda r: r["size"])
        f = fit(rs, baseline, 30 if not code.startswith("chain-") else 10)
        if f:
            fits[code] = f
    info = machine()
    out = dict(
        elements_problem=f"Table I cantilever (table1_properties(1.0)) straight at rest, tip force {F_TIP:.1f} N "
                         "applied at t = 0; tip_end = tip (x, deflection) at T [m] (phmech (x, z), Exudyn (x, y))",
        chain_problem=f"n links {LINK_L} m, {LINK_M} kg, inertia diag{LINK_I} kg m^2 about the centre, revolute "
                      f"pairs about z, first to ground, released horizontal under gravity (0, -{G}, 0); tip_end = "
                      "(x, y) of the end link's free end at T [m]; link_ends = the free ends of all links; error_m = max over links of "
                      "|link end - reference| [m], end_link_error_m the same for the end link only",
        rate="CPU per simulated s = (cpu(T) - cpu(T/5)) / (0.8 T), median of up to 3 repetitions; "
             "setup_cpu_s = cpu(T) - rate T",
        settings=settings, baseline_rss_MB=baseline,
        note="RSS of a fresh interpreter per point that imported numpy, phmech, exudyn and mujoco (baseline); "
             "exponents by least squares in log-log for size >= 30 (elements) / >= 10 (chain)",
        chain_reference=refs, machine=info, runs=runs, skipped=skipped, fits=fits,
        wall_s=time.time() - t0, quick=a.quick, smoke=a.smoke,
        dt_out=dict(elements=ELEM_DT_OUT, chain=CHAIN_DT_OUT))
    # the chain at matched error: each ladder's CPU s/s interpolated at fixed error levels, and
    # its ratio to MuJoCo RK4's (benchmarks/report.py, chain_levels)
    from report import CHAIN_PEER as mj, chain_levels
    out["chain_at_matched_error"] = [
        dict(size=n, error_m=lev, cpu_per_sim_s=row,
             ratio_to_mujoco_rk4={g: row[g] / row[mj] for g in row if g != mj and row.get(g) and row.get(mj)})
        for n, lev, row in chain_levels(out)]
    write_json("bench_scaling", out)
    plot(out)
    print(f"fits: {json.dumps(fits, indent=1)}")
    print(f"bench_scaling done in {time.time() - t0:.0f} s wall", flush=True)


if __name__ == "__main__":
    main()

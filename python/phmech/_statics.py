"""Mechanism.static: the static equilibrium under the mechanism's loads (and extra ones) by the
core's load-stepped Newton (``_core.model_static``), its stability (the lowest frequency about
it), and, when no equilibrium exists, the free motions that the loads drive (FreeMotion)."""
from __future__ import annotations

import math
import warnings
from typing import Optional, Sequence

import numpy as np

from . import _core, _model, _run
from ._checks import array, choice, integer, positive, real
from ._errors import ModelError, SolverError, StabilityWarning, outside_stacklevel
from .frames import frame_of
from .laws import Constant
from .results import FreeMotion, StaticResult



def static(mech, loads: Sequence = (), steps: int = 10, time: float = 0.0,
           tol: float = 1e-10, start: Optional[StaticResult] = None,
           check_stability: bool = True, progress: bool = False, spin=None) -> StaticResult:
    """Mechanism.static of the builder ``mech`` (python/phmech/mechanism.py: its docstring
    gives the arguments, their units and what is returned)."""
    mech._refuse_stateful_components("static")
    S = None if spin is None else _model.spin_twist(mech, spin)
    extra = []
    if not isinstance(loads, (list, tuple)):
        raise ModelError(f"static loads: expected a list of (target, wrench, frame) tuples "
                         f"(got {type(loads).__name__})")
    for i, ld in enumerate(loads):
        if not isinstance(ld, (list, tuple)) or len(ld) != 3:
            raise ModelError(f"static load {i}: expected a (target, wrench, frame) tuple "
                             f"(got {ld!r})")
        target, wrench, frame = ld
        f = frame_of(target, mech._desc, f"static load {i}, target")
        if f.carrier < 0:
            raise ModelError(f"static load {i}: cannot load the ground")
        choice(f"static load {i}: frame", frame, ("world", "body"))
        w = array(f"static load {i}: wrench", wrench, (6,), "6 finite numbers (tau [N m], f [N])")
        if frame == "body":
            R = f.T[:3, :3]
            w = np.concatenate([R @ w[:3], R @ w[3:]])
        extra.append(dict(carrier=f.carrier, world=frame == "world", point=f.T[:3, 3], w=w,
                          law=Constant(1.0)))
    steps = min(integer("steps", steps, 1), 2 ** 31 - 1)
    time, tol = real("time", time), positive("tol", tol)
    poses = None if start is None else _model.start_poses(mech, start, "start")
    model = _model.build(mech, extra)

    def solve(n_steps: int) -> StaticResult:
        """_solve with a steady rotation (docs/method.md 7.6) set on the model, and unset after
        (a model may be kept for later analyses)."""
        if S is None:
            return _solve(n_steps)
        _core.model_set_spin(model, S)
        try:
            return _solve(n_steps)
        finally:
            _core.model_set_spin(model, np.zeros(6))

    def _solve(n_steps: int) -> StaticResult:
        monitor = _run.StaticMonitor() if progress else None
        try:
            P, lam, it = _core.model_static(model, poses, time, n_steps, tol, monitor)
        except SolverError as e:
            if not hasattr(e, "partial"):
                raise
            P, lam, it, reached = e.partial
            e.result = StaticResult(P, lam, it, mech._links, tuple(extra), steps=n_steps,
                                    load_factor=reached)
            e.free_motions = _free_motions(mech, model, P, time, extra)
            msg = _no_equilibrium(e.free_motions) if e.free_motions else e.args[0]
            e.args = (f"{msg} (the last converged state, at load factor {reached:.6g}, "
                      f"is in this error's 'result' attribute)",)
            raise
        finally:
            if monitor is not None:
                monitor.close()
        st = StaticResult(P, lam, it, mech._links, tuple(extra), steps=n_steps)
        # with components the tangent's modes leave their stiffness out: no verdict
        if check_stability and _model.potential_loads_only(mech, extra) and \
                not mech._desc.components:
            st.lowest_omega = _lowest_omega(mech, model, P, lam, time)
            st.stable = bool(st.lowest_omega >= 0)
        return st

    st = solve(steps)
    if st.stable is False:
        more = min(10 * steps, 2 ** 31 - 1)
        again = solve(more) if more > steps else st
        if again.stable:
            return again
        warnings.warn(f"static(): the equilibrium found is unstable: its lowest linearized "
                      f"mode has omega = {st.lowest_omega:.4g} rad/s (negative: the tangent "
                      f"stiffness has a negative eigenvalue), also with {more} load steps. "
                      f"Under these loads the mechanism buckles or falls away from here; a "
                      f"stable equilibrium may be found from a perturbed start (start=) or "
                      f"by simulating with damping", StabilityWarning, stacklevel=outside_stacklevel())
    return st

def _free_motions(mech, model, P, time: float, extra: Sequence[dict]) -> list:
    """The motions nothing resists on which the loads do work at poses P
    (_core.model_static_free, csrc/analyze/static_free.c), as FreeMotion rows named from the
    description; [] when none is found."""
    try:
        raw = _core.model_static_free(model, P, time)
    except (SolverError, ModelError):
        return []
    return [_free_motion(mech, r, extra) for r in raw]

def _free_motion(mech, r: dict, extra: Sequence[dict]) -> FreeMotion:
    """One row of _core.model_static_free as a FreeMotion, its sentence included."""
    def axis(u):
        u = u / np.linalg.norm(u)
        for k, nm in enumerate("xyz"):
            if abs(u[k]) > 1 - 1e-9:
                return nm if u[k] > 0 else "-" + nm
        return "(" + ", ".join(f"{a:.3g}" for a in u) + ")"
    # the bodies and links that move, in the order of their carriers
    moving = [f"{'body' if nm in mech._bodies else 'link'} {nm!r}"
              for nm, cs in sorted(mech._desc.groups(), key=lambda g: min(g[1]))
              if r["moving"][cs].any()]
    om, v = r["twist"][:3], r["twist"][3:]
    rot = bool(np.any(om != 0))
    ip, j = r["pair"], r["coord"]
    if ip >= 0:
        e = mech._pairs[ip]
        unit = "N" if e["pair"]._type.units[j] == "m" else "N m"
    else:
        unit = "N m" if rot else "N"
    sources = {}
    if r["effort"] != 0:
        acts = [a["name"] for a in mech._acts if a["pair"] == ip]
        sources["effort of actuator " + " and ".join(map(repr, acts))] = float(r["effort"])
    if r["gravity"] != 0:
        sources[f"gravity on {r['mass']:.4g} kg"] = float(r["gravity"])
    names = [ld["name"] for ld in mech._loads] + [f"static load {i}" for i in range(len(extra))]
    for nm, wk in zip(names, r["load_work"]):
        if wk != 0:   # a distributed load's nodes ("q[3]") as one
            key = "wrench " + repr(nm.split("[")[0] if nm.endswith("]") else nm)
            sources[key] = sources.get(key, 0.0) + float(wk)
    parts = ", ".join(f"{k}: {w:.4g} {unit}" for k, w in sources.items())
    F = r["force"]
    if ip >= 0:
        kind = type(e["pair"]).__name__.lower()
        where = f"about {axis(om)}" if rot else f"along {axis(v)}"
        coord = f", coordinate {j} {where}" if e["k"] > 1 else f" {where}"
        text = (f"pair {e['name']!r} ({kind}{coord}) {'turns' if rot else 'slides'} freely "
                f"under {F:.4g} {unit} ({parts}), carrying {', '.join(moving)}")
    else:
        them = "it" if len(moving) == 1 else "them"
        push = f"turn {them} about {axis(om)}" if rot else f"push {them} along {axis(v)}"
        text = (f"{', '.join(moving)} {'is' if len(moving) == 1 else 'are'} held by nothing "
                f"(no pair, element, spring or interaction links {them} to the ground) and the "
                f"loads {push} with {F:.4g} {unit} ({parts})")
    return FreeMotion(e["name"] if ip >= 0 else None, j if ip >= 0 else None, float(F), unit,
                      sources, np.array(r["twist"]), tuple(moving), text)

def _no_equilibrium(motions: Sequence[FreeMotion]) -> str:
    """The SolverError message of a static solve under loads that do work on motions nothing
    resists (Mechanism._free_motions)."""
    hold = []
    if any(f.pair is not None for f in motions):
        hold.append("a spring or a PD actuator on the pair, a driven coordinate, a Fixed pair")
    if any(f.pair is None for f in motions):
        hold.append("a pair or a spring to the ground")
    return ("no static equilibrium: the loads do work on a motion nothing resists: " +
            "; ".join(f.text for f in motions) + f". Hold it ({'; '.join(hold)}) or simulate() "
            "instead")

def _lowest_omega(mech, model, P, lam, time: float) -> float:
    """The lowest linearized frequency [rad/s] at poses P and multipliers lam, negative for a
    negative eigenvalue of the tangent stiffness; a value below round-off of the next mode's
    (|omega_1|^2 < 1e-8 omega_2^2) counts as zero (a neutral mode), and so do negative values
    below round-off of a higher mode (up to the 24th), or all below 1e-6 rad/s; inf when
    nothing can move (no degree of freedom: csrc/analyze/modes.c refuses to count modes)."""
    try:
        om = _core.model_modes(model, min(2, 6 * len(mech._car)), P, lam, time)[0]
    except ModelError as e:
        if "has no degree of freedom" in str(e):
            return math.inf
        raise
    if len(om) > 1 and om[0] < 0 and om[0] ** 2 < 1e-8 * om[1] ** 2:
        return 0.0
    if om[0] < 0:
        # several round-off zeros: the motions nothing resists of an equilibrium that is not
        # unique (a free body or link, a revolute without load: 6, 6 and 1 of them, measured
        # at -1e-8 .. -4e-3 rad/s). Zeros when a mode above them is 1e4 times higher (modes
        # come in ascending omega^2: none below them), or when all are below 1e-6 rad/s
        # (nothing to compare with; a time constant of 12 days)
        om = _core.model_modes(model, min(24, 6 * len(mech._car)), P, lam, time)[0]
        if any(om[k] ** 2 > 1e8 * np.max(om[:k] ** 2) for k in range(1, len(om))):
            return 0.0
        if np.max(np.abs(om)) < 1e-6:
            return 0.0
    return float(om[0])

"""The built model of a mechanism: its initial configuration (python/phmech/topology.py, once
per description until the next add_*), the warnings and tables it publishes on the mechanism
(``redundant_constraints``, ``initial_adjustments``, ``unattached``), the core model at it, and
the linearization point the linear analyses share (modes, linearize, static). Functions of a
builder (``mech``: a phmech.Mechanism, or the _builder.Builder a link-alone analysis makes)."""
from __future__ import annotations

import warnings
import weakref
from typing import Optional, Sequence

import numpy as np

from . import _marshal, topology
from ._checks import array, real
from ._errors import (AccuracyWarning, InitialValueWarning, ModelError, RedundantConstraintWarning,
                      StabilityWarning, UnattachedWarning, outside_stacklevel)
from .results import StaticResult


#: largest ratio of carrier masses whose modes a linearization resolves to 1e-3: the
#: eigensolvers' backward error (eps times the norm of M) perturbs a carrier of mass m by
#: eps m_max / m relative
MASS_RATIO_RESOLVED = 1e-3 / np.finfo(float).eps


#: what the analyses build from a mechanism's initial configuration and keep between calls
#: (builder -> dict; see built): weak keys, so a mechanism is freed (and pickled) without it
_BUILT: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()


def built(mech) -> dict:
    """What the analyses built from the mechanism's current initial configuration
    (``mech._state``, dropped by every add_*) and gravity, kept between calls: ``model``, the
    core model without extra loads (build), the messages of the moves (_report) and of the
    linearization's warnings (linearization_point_kept), and what other layers store
    (simulate's planar model; modes' equilibrium check, labels with their frequencies, element
    geometry, link and body tables). A new, empty dict when the
    state, the gravity or the description's rows changed since (``ModelDescription.version``:
    a sampled controller's run sets its output laws in place) -- nothing stale is reused."""
    desc = mech._desc
    g = np.asarray(desc.gravity, dtype=float).tobytes()
    c = _BUILT.get(mech)
    if c is None or c["_state"] is not mech._state or c["_gravity"] != g or \
            c["_version"] != desc.version:
        c = {"_state": mech._state, "_gravity": g, "_version": desc.version}
        _BUILT[mech] = c
    return c


def initial_state(mech, extra_loads: Sequence[dict] = ()):
    """The initial configuration (topology.initial_state), found once per description and
    kept until the next add_*; returns (InitialState, model), ``model`` the core model the
    steps built (with ``extra_loads``) when it is the analysis's, else None. Sets
    ``redundant_constraints`` and ``initial_adjustments`` and warns or, if ``strict``, raises
    on moves beyond tolerance, at every call. Overflow in these steps (given lengths,
    positions, x0 or rates beyond what double precision can square) is a ModelError, never
    a NaN passed on."""
    return _initial_state(mech, extra_loads)[:2]

def _initial_state(mech, extra_loads: Sequence[dict]) -> tuple:
    """initial_state's (InitialState, model) and the mechanism's ``built`` dict."""
    if not mech._car:
        raise ModelError("the mechanism is empty")
    model = None
    if mech._state is None:
        try:
            with np.errstate(over="raise", invalid="raise"):
                mech._state, model = topology.initial_state(mech._desc, extra_loads)
        except FloatingPointError as e:
            raise ModelError(f"initial configuration: {e} while placing the carriers and closing "
                             f"the loops: the model's lengths, positions, x0 or xdot0 are beyond "
                             f"what double precision can handle") from None
    keep = built(mech)
    _report(mech, mech._state, keep)
    if model is not None and not extra_loads:
        keep["model"] = model
    return mech._state, model, keep

def _report(mech, state: topology.InitialState, keep: dict) -> None:
    """Publish the redundant rows, the adjustments and the free groups of ``state``; warn
    about them (once per distinct message) or raise ModelError with ``strict`` (moves only:
    a free body may be meant). ``keep``: the mechanism's ``built`` dict, where the message
    about the moves is kept."""
    mech.redundant_constraints = list(state.redundant)
    mech.initial_adjustments = list(state.adjustments)
    _warn_unattached(mech, state.unattached)
    msg = keep.get("moves_message")
    if msg is None:
        msg = keep["moves_message"] = _moves_message(state)
    if msg:
        if mech.strict:
            raise ModelError(msg + " (Mechanism(strict=True))")
        if mech._warned_initial != msg:
            mech._warned_initial = msg
            warnings.warn(msg, InitialValueWarning, stacklevel=outside_stacklevel())
    dropped = state.redundant
    if dropped and mech._warned != dropped:
        mech._warned = list(dropped)
        warnings.warn(f"hyperconstrained mechanism: {len(dropped)} redundant constraint "
                      f"directions left out of the DAE (pair, direction in F_b): {dropped}",
                      RedundantConstraintWarning, stacklevel=outside_stacklevel())

def _moves_message(state: topology.InitialState) -> str:
    """The message about the given initial values that closing the loops moved beyond their
    tolerance ("" when none did)."""
    moved = [a for a in state.adjustments if a.exceeds]
    if not moved:
        return ""
    return ("initial configuration: closing the loops moved given initial values beyond "
            "their tolerance: " + "; ".join(str(a) for a in moved) +
            ". Give consistent x0, xdot0 and poses; Mechanism.initial_adjustments lists every "
            "given value and how far it moved")

def _warn_unattached(mech, groups: list) -> None:
    """Publish the free groups (topology.FreeGroup rows) in ``unattached`` and warn about
    them (UnattachedWarning, pointing at the caller outside phmech), once per distinct set
    of groups."""
    mech.unattached = [g.names for g in groups] if groups else []
    if mech.unattached and mech._warned_unattached != mech.unattached:
        mech._warned_unattached = mech.unattached
        warnings.warn(topology.unattached_message(mech._desc, groups), UnattachedWarning,
                      stacklevel=outside_stacklevel())

def initial(mech) -> tuple:
    """Copies of the initial poses, twists, the pairs' x0 rows and drop masks."""
    state, _ = initial_state(mech)
    return state.poses.copy(), state.twists.copy(), state.x0.copy(), list(state.drop_masks)

def build(mech, extra_loads: Sequence[dict] = ()):
    """The core model of this mechanism at its initial configuration, with ``extra_loads``
    (load rows) after its own: without extra loads, built once per initial configuration and
    gravity (kept in ``built(mech)``; analyses only read it: one that changes a model, as
    simulate's planar one, works on its own); with them, once per call (or none when finding
    the initial configuration built it)."""
    return _build(mech, extra_loads)[0]

def _warn_modal_gravity(mech) -> None:
    """build's AccuracyWarnings about modal links under gravity (their condensed weight, their
    preload left out), at every build."""
    if (mech._modal_gravity_miss or mech._modal_preload) and np.any(mech._desc.gravity):
        for nm, miss in mech._modal_gravity_miss.items():
            if miss > mech.frequency_tolerance:
                warnings.warn(f"modal link {nm!r} under gravity: two point masses carry its "
                              f"condensed weight (a curved or pre-twisted link's is not that "
                              f"of any point), which puts its end, held at its start, "
                              f"{miss:.2g} off the full link's sag; use fidelity='nonlinear' "
                              f"for it if that matters", AccuracyWarning, stacklevel=outside_stacklevel())
        gmax = float(np.max(np.abs(mech._desc.gravity)))   # |g| without overflowing
        g = gmax * float(np.linalg.norm(mech._desc.gravity / gmax)) if mech._modal_preload else 0.0
        for nm, entry in mech._modal_preload.items():
            if entry[1] is None:
                entry[1] = entry[0]()
            if entry[1] * g > mech.frequency_tolerance:
                warnings.warn(f"modal link {nm!r} under gravity: its weight along it (tension "
                              f"or compression) moves its first frequency held at its start by "
                              f"about {100 * entry[1] * g:.2g} % in the full link (geometric "
                              f"stiffness), which a modal link leaves out (its gravity points "
                              f"even shift it the other way); use fidelity='nonlinear' for it "
                              f"if it hangs or stands", AccuracyWarning, stacklevel=outside_stacklevel())

def _build(mech, extra_loads: Sequence[dict]) -> tuple:
    """build's model and the mechanism's ``built`` dict (looked up once: an analysis called
    again and again on a small model pays for every lookup)."""
    _warn_modal_gravity(mech)
    state, model, keep = _initial_state(mech, extra_loads)
    if extra_loads:
        if model is None:
            model = _marshal.core_model(mech._desc, state.poses, state.twists, state.x0,
                                        state.drop_masks, state.frames_a, extra_loads)
        return model, keep
    if model is None:
        model = keep.get("model")
        if model is None:
            model = keep["model"] = _marshal.core_model(mech._desc, state.poses, state.twists,
                                                        state.x0, state.drop_masks,
                                                        state.frames_a, ())
    return model, keep

def linearization_point(mech, at: Optional[StaticResult]) -> tuple:
    """(core model, poses, constraint wrenches) of a linearization at the initial state (poses
    and wrenches None) or at the static equilibrium ``at``, with the extra loads it was
    found under."""
    return linearization_point_kept(mech, at)[:3]

def linearization_point_kept(mech, at: Optional[StaticResult]) -> tuple:
    """linearization_point's (model, poses, constraint wrenches) and the mechanism's ``built``
    dict (for what the caller keeps there, without looking it up again)."""
    if at is not None and not isinstance(at, StaticResult):
        raise ModelError(f"at must be a StaticResult (Mechanism.static) or None (got "
                         f"{type(at).__name__})")
    model, keep = _build(mech, () if at is None else at.loads)
    # the follower loads' names and the masses' message: made once per initial configuration
    # (what they are made from, the load rows and the carriers' masses, change only with it);
    # the warnings issued at every call
    warns = keep.get("linearization_warnings")
    if warns is None:
        warns = keep["linearization_warnings"] = _linearization_warnings(mech)
    for msg, category in warns:
        warnings.warn(msg, category, stacklevel=outside_stacklevel())
    if at is None:
        return model, None, None, keep
    poses = start_poses(mech, at, "at")
    lam = array("at.constraint_wrenches", at.constraint_wrenches,
                np.shape(at.constraint_wrenches))
    return model, poses, lam, keep

def _linearization_warnings(mech) -> list:
    """(message, category) of the warnings every linearization of this initial configuration
    issues: follower loads (StabilityWarning) and unresolvable masses (AccuracyWarning)."""
    out = []
    followers = follower_loads(mech)
    if followers:
        out.append((f"the follower loads {followers} (body-frame wrenches) have a "
                    "non-symmetric load stiffness, which the linearization (modes(), "
                    "linearize()) symmetrizes: it treats them as dead loads and cannot show "
                    "flutter; simulate to see how the mechanism moves under them",
                    StabilityWarning))
    masses = _unresolvable_masses(mech)
    if masses:
        out.append((masses, AccuracyWarning))
    return out

def _unresolvable_masses(mech) -> str:
    """The AccuracyWarning of a linearization when the carriers' masses span more than
    MASS_RATIO_RESOLVED (4.5e12): the modes of the lightest carriers are then below what double
    precision resolves (a link of density 1e-300 hinged to a 1 kg body gave 1.4e9 rad/s for
    bending modes of ~1e153 rad/s, without a word: tests/test_fuzz_findings.py); "" when the
    masses are resolved."""
    # massless carriers have no modes of their own: left out
    masses = np.array([c["mass"] if c["mass"] > 0 else np.inf for c in mech._car] + [np.inf])
    light = int(np.argmin(masses))
    heavy = masses[np.isfinite(masses)].max(initial=0.0)
    if not heavy > MASS_RATIO_RESOLVED * masses[light]:
        return ""
    return (f"the carriers' masses span {heavy:.3g} kg to {masses[light]:.3g} kg "
            f"(lightest: {mech._desc.carrier_name(light)}), a ratio above "
            f"{MASS_RATIO_RESOLVED:.2g}: double precision cannot resolve the lightest "
            "carriers' modes next to the heaviest (their frequencies and shapes may be "
            "wrong by orders of magnitude); give the light parts physical masses, or leave "
            "them out")

def follower_loads(mech) -> list:
    """Names of the wrenches given in body axes (they turn with their carrier)."""
    return [ld["name"] for ld in mech._loads if not ld["world"]]

def potential_loads_only(mech, extra: Sequence[dict]) -> bool:
    """Whether every applied wrench has a potential, so that a symmetric tangent stiffness
    judges stability: dead forces (world axes, no moment, on one carrier). Follower loads, a
    moment of fixed direction (in 3-D its work depends on the path of the rotation) and
    interactions between two carriers are not judged."""
    return all(ld["world"] and not ld.get("interaction") and not np.any(ld["w"][:3])
               for ld in [*mech._loads, *extra])

def check_linearization_time(mech, what: str, time: float,
                              at: Optional[StaticResult]) -> None:
    """ModelError when ``time`` asks a linearization about the initial configuration
    (``at`` None) at a time where a driven pair's law has moved on: the initial
    configuration holds the driven coordinates at s(0) with rate s'(0), and the linearization
    has no way to know where the rest of the mechanism is at s(time) (nor does it include
    the motion's rate). A driven law's value or rate at ``time`` differing from t = 0's by
    more than 1e-9 (relative, 1e-12 absolute) is refused, naming the pair, the values and
    the remedy (the law advanced to that time: ``law.shifted(-time)``)."""
    if time == 0.0 or at is not None:
        return
    for e in mech._pairs:
        laws = [(None, e["law"])] if e["law"] is not None else \
            list(enumerate(e["xlaws"] or []))
        for c, lw in laws:
            if lw is None:
                continue
            (s0, v0, _), (s1, v1, _) = lw.derivatives(np.array([0.0, time]))
            if abs(s1 - s0) > 1e-9 * max(abs(s0), abs(s1)) + 1e-12 or \
                    abs(v1 - v0) > 1e-9 * max(abs(v0), abs(v1)) + 1e-12:
                unit = "" if c is None else " " + e["pair"]._units[c]
                coord = "its motion" if c is None else f"coordinate {c}"
                raise ModelError(
                    f"{what}(time={time:g}): pair {e['name']!r} is driven, and its law moves "
                    f"{coord} from s(0) = {s0:.6g}{unit} (rate {v0:.6g}{unit}/s) to "
                    f"s({time:g}) = {s1:.6g}{unit} (rate {v1:.6g}{unit}/s), but {what} works "
                    f"about the initial configuration, where the pair is at s(0): it would "
                    f"return the t = 0 figures. For the configuration of that time drive the "
                    f"pair with the law advanced to it, driven=law.shifted({-time:g}) "
                    f"(s(t + {time:g})), and call {what} at time 0; a linearization is about "
                    f"rest: the driven motion's rate (and the centrifugal stiffening of a "
                    f"spin) is not in it, simulate() has it")


def start_poses(mech, start, what) -> np.ndarray:
    """The poses of a StaticResult used as a starting point, checked against this mechanism."""
    if not isinstance(start, StaticResult):
        raise ModelError(f"{what} must be a StaticResult (Mechanism.static) or None (got "
                         f"{type(start).__name__})")
    return array(f"{what}.poses", start.poses, (len(mech._car), 4, 4),
                 f"finite poses of this mechanism's {len(mech._car)} carriers, shape "
                 f"({len(mech._car)}, 4, 4)")


def spin_twist(mech, spin) -> np.ndarray:
    """The world twist S (omega [rad/s], v [m/s] at the world origin) of a steady rotation
    ``spin`` = (name of a revolute pair on the ground, Omega [rad/s]) about the pair's axis
    (docs/method.md section 7.6); ModelError when the pair is not a revolute on the ground, or
    gravity is not along the axis (the motion would not be steady)."""
    if not isinstance(spin, (tuple, list)) or len(spin) != 2 or not isinstance(spin[0], str):
        raise ModelError(f"spin: expected (revolute pair name, Omega [rad/s]) (got {spin!r})")
    name, om = spin[0], real("spin: Omega", spin[1])
    rows = [r for r in mech._desc.pairs if r["name"] == name]
    if not rows:
        raise ModelError(f"spin: unknown pair {name!r}")
    row = rows[0]
    if type(row["pair"]).__name__ != "Revolute" or (row["a"] >= 0 and row["b"] >= 0):
        raise ModelError(f"spin: pair {name!r} must be a Revolute pair on the ground (the "
                         f"mechanism turns about its axis)")
    T = np.asarray(row["Ta"] if row["a"] < 0 else row["Tb"], dtype=float)
    e, p = T[:3, 2], T[:3, 3]
    g = np.asarray(mech._desc.gravity, dtype=float)
    if np.linalg.norm(np.cross(g, e)) > 1e-12 * max(np.linalg.norm(g), 1e-300):
        raise ModelError(f"spin: gravity {g.tolist()} is not along the axis of {name!r} "
                         f"{e.tolist()}: a turning mechanism would not be in a steady state")
    w = om * e
    return np.concatenate([w, np.cross(p, w)])

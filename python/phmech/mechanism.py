"""Mechanisms of rigid bodies and flexible links: model building, simulation, modes, statics.

Thin layer over the C core (``phmech._core``): it lays out carriers (rigid bodies and beam nodes),
``se3`` beam elements, kinematic pairs and applied wrenches as flat arrays; everything numerical
runs in C (SUNDIALS IDA for time integration, LAPACK for modes and statics).

Conventions: SI units; twist (omega, v) and wrench (tau, f), angular part first; poses 4x4.
A beam's local x axis is its centre line; its section axes are y and z.
"""
from __future__ import annotations

import dataclasses
import os
import warnings
from typing import Callable, NamedTuple, Optional, Sequence, Union

import numpy as np

from . import _core, _run, se3, topology
from .graphs import MechanismGraph, Incidence
from ._checks import array, integer, positive, real
from ._core import ModelError, SolverError

#: the adaptive generalized-alpha's default local error tolerance and spectral radius at
#: infinity (docs/integrators.md: measured on benchmarks/scenes.py)
DEFAULT_RTOL = 1e-4
DEFAULT_RHO_INF = 0.9
#: steps an integrator takes at most between two output times (csrc/phmech.h, phm_sim_options
#: max_steps: its default)
MAX_STEPS = 1_000_000

__all__ = ["Mechanism", "Frame", "Body", "FlexibleLink", "Fixed", "Revolute", "Prismatic",
           "Helical", "Cylindrical", "Universal", "Spherical", "Planar", "Free", "Effort", "PD",
           "Spring", "Motion", "Constant", "Step", "Pulse", "Sine", "Table", "Cycloidal",
           "SimulationResult", "ModesResult", "StaticResult", "Graphs", "RedundantConstraintWarning",
           "InitialValueWarning", "InitialAdjustment", "InitialConfiguration", "Momentum"]


class RedundantConstraintWarning(UserWarning):
    """The mechanism is hyperconstrained: some constraint rows are dependent at the initial
    configuration and were left out of the DAE (see ``Mechanism.redundant_constraints``)."""


class InitialValueWarning(UserWarning):
    """The loop closure of the initial configuration moved a given joint coordinate (``x0``) or
    a given pose beyond its tolerance (see ``Mechanism.initial_adjustments``; with
    ``Mechanism(strict=True)`` this is a ModelError instead)."""


@dataclasses.dataclass(frozen=True)
class InitialAdjustment:
    """How far the consistent initial configuration moved one given initial value.

    ``name``: the pair (joint coordinates) or the body / flexible link (poses). ``quantity``:
    ``"x"`` (``"x[i]"`` for pairs with several coordinates), ``"xdot"`` (``"xdot[i]"``) for a
    given rate, or ``"position"`` / ``"orientation"`` of a body or link (for a link the largest
    over its nodes). ``given``/``reached``: the given ``x0`` (``xdot0``) and the initial value
    [rad or m, per s for rates] (None for poses). ``moved``: |reached - given| [same units]; for
    poses the distance an origin moved [m] or the angle a frame turned [rad].
    ``tolerance``: ``moved`` beyond it is reported (see Mechanism)."""
    name: str
    quantity: str
    given: Optional[float]
    reached: Optional[float]
    moved: float
    unit: str
    tolerance: float

    @property
    def exceeds(self) -> bool:
        """True when ``moved`` is beyond ``tolerance``."""
        return self.moved > self.tolerance

    def __str__(self) -> str:
        if self.given is not None:
            q = "" if self.quantity == "x" else " " + self.quantity
            return (f"joint {self.name!r}{q} given {self.given:.6g} {self.unit}, closed at "
                    f"{self.reached:.6g} {self.unit} (moved {self.moved:.3g} {self.unit})")
        return f"pose of {self.name!r}: {self.quantity} moved {self.moved:.3g} {self.unit}"


@dataclasses.dataclass
class InitialConfiguration:
    """The initial configuration an analysis starts from: ``poses`` (ncarriers, 4, 4), body
    ``twists`` (ncarriers, 6), ``adjustments`` (list of InitialAdjustment: every given ``x0``
    coordinate and every given pose kept by the tree placement, with how far the loop closure
    moved it) and ``redundant_constraints``."""
    poses: np.ndarray
    twists: np.ndarray
    adjustments: list
    redundant_constraints: list


@dataclasses.dataclass(frozen=True)
class Graphs:
    """The mechanism's graphs (paper Sec. IV, DESIGN.md §5). Vertices ``G_B``: "0" (ground), the
    rigid bodies by name in the order added, then "<link>L", "<link>R" per flexible link (and
    "<link>[k]" for interior nodes used by a pair). Edges (name, l, r): ``G_K`` pairs, ``G_F``
    links, ``G_I`` interactions (add_interaction, whose reaction defaults to the ground, and
    spring-dampers). ``B_K``/``B_I``: incidence matrices with labels (-1 at l(e), +1 at r(e));
    ``B_K_r`` etc. are their rigid and flexible row blocks, as in the paper's (24)-(25)."""
    graph: MechanismGraph
    B_K: Incidence
    B_I: Incidence

    G_B = property(lambda self: ["0"] + self.graph.vertices())
    G_K = property(lambda self: list(self.graph.pairs))
    G_F = property(lambda self: self.graph.flexible_edges())
    G_I = property(lambda self: list(self.graph.interactions))
    B_K_r = property(lambda self: self.B_K.rigid)
    B_K_f = property(lambda self: self.B_K.flexible)
    B_I_r = property(lambda self: self.B_I.rigid)
    B_I_f = property(lambda self: self.B_I.flexible)

    def loops(self) -> list:
        """One independent loop per loop-closing edge (lists of pair and link names)."""
        return self.graph.loops()

_LAW_CONSTANT, _LAW_STEP, _LAW_PULSE, _LAW_SINE, _LAW_TABLE, _LAW_CYCLOIDAL = range(6)
ENERGY_NAMES = ("kinetic", "elastic", "gravity", "dissipated", "supplied", "total", "ledger")


# ------------------------------------------------------------------ time laws
class _Law:
    def _tuple(self):
        raise NotImplementedError


_LAW_NAMES = "Constant, Step, Pulse, Sine, Table or Cycloidal"


def _law_tuple(law, what: str, numbers: bool = False):
    """The core's tuple of a time law; a clear ModelError for anything else (a plain Python
    function cannot be a law: laws are evaluated in C, see csrc/phmech.h). ``numbers``: a
    number c also stands for Constant(c)."""
    if isinstance(law, _Law):
        return law._tuple()
    if numbers and isinstance(law, (int, float, np.integer, np.floating)) and not isinstance(law, bool):
        return Constant(real(what, law))._tuple()
    accepted = f"a time law ({_LAW_NAMES}{', or a number' if numbers else ''})"
    if callable(law):
        fname = getattr(law, "__name__", type(law).__name__)
        raise ModelError(f"{what}: got the Python function {fname!r}, expected {accepted}; laws are "
                         "evaluated in the C core, so a Python function cannot be one: tabulate it "
                         "with Table(times, values)")
    raise ModelError(f"{what}: expected {accepted} (got {type(law).__name__})")



@dataclasses.dataclass(frozen=True)
class Constant(_Law):
    """s(t) = value."""
    value: float = 1.0

    def _tuple(self):
        return (_LAW_CONSTANT, real("Constant value", self.value), 0.0, 0.0, 0.0, 0.0, 0.0, None)


@dataclasses.dataclass(frozen=True)
class Step(_Law):
    """s(t) = value for t >= t0 [s], else 0."""
    t0: float = 0.0
    value: float = 1.0

    def _tuple(self):
        return (_LAW_STEP, real("Step value", self.value), real("Step t0", self.t0), 0.0, 0.0, 0.0, 0.0, None)


@dataclasses.dataclass(frozen=True)
class Pulse(_Law):
    """Rectangular pulse ('impulse'): s(t) = value for t0 <= t < t0 + duration [s], else 0.
    Its impulse is value * duration."""
    t0: float = 0.0
    duration: float = 1e-3
    value: float = 1.0

    def _tuple(self):
        d = real("Pulse duration", self.duration)
        if d <= 0:
            raise ModelError(f"Pulse duration must be > 0 (got {d} s)")
        return (_LAW_PULSE, real("Pulse value", self.value), real("Pulse t0", self.t0), d, 0.0, 0.0, 0.0, None)


@dataclasses.dataclass(frozen=True)
class Sine(_Law):
    """s(t) = offset + amplitude * sin(2 pi frequency t + phase); frequency in Hz, phase in rad."""
    amplitude: float = 1.0
    frequency: float = 1.0
    phase: float = 0.0
    offset: float = 0.0

    def _tuple(self):
        return (_LAW_SINE, real("Sine amplitude", self.amplitude), 0.0, 0.0,
                real("Sine frequency", self.frequency), real("Sine phase", self.phase),
                real("Sine offset", self.offset), None)


@dataclasses.dataclass(frozen=True)
class Table(_Law):
    """Piecewise linear through points (t_i [s], s_i), held constant outside."""
    times: Sequence[float]
    values: Sequence[float]

    def _tuple(self):
        t = _numbers("Table times", self.times)
        v = _numbers("Table values", self.values)
        if t.size < 1 or t.size != v.size:
            raise ModelError(f"Table needs as many values as times, at least one (got {t.size} "
                             f"times and {v.size} values)")
        if not (np.all(np.isfinite(t)) and np.all(np.isfinite(v))):
            raise ModelError("Table entries must be finite")
        if np.any(np.diff(t) <= 0):
            raise ModelError("Table times must be strictly increasing")
        return (_LAW_TABLE, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, np.column_stack([t, v]))


@dataclasses.dataclass(frozen=True)
class Cycloidal(_Law):
    """Smooth (C2) ramp from 0 to value over [t0, t0 + duration] [s]."""
    value: float = 1.0
    t0: float = 0.0
    duration: float = 1.0

    def _tuple(self):
        d = real("Cycloidal duration", self.duration)
        if d <= 0:
            raise ModelError(f"Cycloidal duration must be > 0 (got {d} s)")
        return (_LAW_CYCLOIDAL, real("Cycloidal value", self.value), real("Cycloidal t0", self.t0), d, 0.0, 0.0, 0.0, None)


@dataclasses.dataclass(frozen=True)
class Motion:
    """Prescribed relative motion of a driven pair: r(t) = exp(law(t) * axis), axis a twist
    (omega, v) in the pair's frame on b, e.g. (0,0,1,0,0,0) with an angle law [rad], or
    (0,0,0,0,1,0) with a displacement law [m]."""
    axis: Sequence[float]
    law: _Law


# ------------------------------------------------------------------ pair types
# Conventions (C core, phm_pair_type): joint axis = local z of both pair frames F_a = H_a T_a and
# F_b = H_b T_b; relative pose h = F_a^-1 F_b. The classes below orient z along ``axis`` by
# rotating both frames by the same rotation Q (T <- T [Q, 0; 0, 1]).

def _axis_rotation(axis, what: str) -> np.ndarray:
    """A rotation Q with Q e_z = axis ("x", "y", "z" or a nonzero 3-vector)."""
    if isinstance(axis, str):
        table = {"x": [[0, 0, 1], [1, 0, 0], [0, 1, 0]], "y": [[0, 1, 0], [0, 0, 1], [1, 0, 0]],
                 "z": np.eye(3)}
        if axis not in table:
            raise ModelError(f"{what}: axis must be 'x', 'y', 'z' or a 3-vector (got {axis!r})")
        return np.array(table[axis], dtype=float)
    z = _unit(axis, what)
    h = np.array([1.0, 0, 0]) if abs(z[0]) < 0.9 else np.array([0, 1.0, 0])
    x = h - z * (h @ z)
    x /= np.linalg.norm(x)
    return np.column_stack([x, np.cross(z, x), z])


def _unit(v, what):
    if isinstance(v, str):
        d = {"x": [1.0, 0, 0], "y": [0, 1.0, 0], "z": [0, 0, 1.0]}
        if v not in d:
            raise ModelError(f"{what}: axis must be 'x', 'y', 'z' or a 3-vector (got {v!r})")
        return np.array(d[v])
    expected = "'x', 'y', 'z' or a finite nonzero 3-vector"
    a = array(f"{what}: axis", v, (3,), expected)
    n = np.max(np.abs(a))
    if n == 0:
        raise ModelError(f"{what}: axis must be {expected} (got {v!r})")
    a = a / n   # first to a unit max-norm: |a| of 1e300 entries would overflow
    return a / np.linalg.norm(a)


class _Pair:
    _code = -1
    k = 0
    _units = ()   # unit of each joint coordinate ("rad" or "m")

    def _rotation(self) -> np.ndarray:
        return np.eye(3)

    def _pitch(self) -> float:
        return 0.0

    def _fk(self, x) -> np.ndarray:
        """Relative pose h(x) of the pair frames at joint coordinates x."""
        return np.eye(4)

    def _coords(self, h) -> np.ndarray:
        """Joint coordinates x of a relative pose h of the pair frames (the inverse of _fk on
        the pair's allowed motions; the part of h it cannot produce is fk(x)^-1 h)."""
        return np.zeros(0)


def _ez(*v):
    return np.array(v, dtype=float)


def _angle_z(h) -> float:
    """Angle [rad] of a relative pose's rotation about z, in (-pi, pi]."""
    return float(np.arctan2(h[1, 0], h[0, 0]))


@dataclasses.dataclass(frozen=True)
class Fixed(_Pair):
    """Fixed (welded) pair: 6 constraints, relative pose = identity (or the driven motion)."""
    _code = 0
    k = 0


@dataclasses.dataclass(frozen=True)
class Revolute(_Pair):
    """Revolute pair about ``axis`` (of both pair frames); x = angle [rad], multi-turn."""
    axis: object = "z"
    _code = 1
    k = 1
    _units = ("rad",)

    def _rotation(self):
        return _axis_rotation(self.axis, "Revolute")

    def _fk(self, x):
        return se3.exp(_ez(0, 0, x[0], 0, 0, 0))

    def _coords(self, h):
        return np.array([_angle_z(h)])


@dataclasses.dataclass(frozen=True)
class Prismatic(_Pair):
    """Prismatic pair along ``axis``; x = displacement [m]."""
    axis: object = "z"
    _code = 2
    k = 1
    _units = ("m",)

    def _rotation(self):
        return _axis_rotation(self.axis, "Prismatic")

    def _fk(self, x):
        return se3.exp(_ez(0, 0, 0, 0, 0, x[0]))

    def _coords(self, h):
        return np.array([h[2, 3]])


@dataclasses.dataclass(frozen=True)
class Helical(_Pair):
    """Helical (screw) pair about ``axis``: translation = ``pitch`` [m/rad] x angle; x = angle."""
    axis: object = "z"
    pitch: float = 0.0
    _code = 3
    k = 1
    _units = ("rad",)

    def _rotation(self):
        return _axis_rotation(self.axis, "Helical")

    def _pitch(self):
        return real("Helical pitch", self.pitch)

    def _fk(self, x):
        return se3.exp(_ez(0, 0, x[0], 0, 0, self._pitch() * x[0]))

    def _coords(self, h):
        a, p = _angle_z(h), self._pitch()
        if p != 0:   # the turn whose translation pitch * angle is nearest to h's
            with np.errstate(over="ignore"):
                turn = a + 2 * np.pi * np.round((h[2, 3] / p - a) / (2 * np.pi))
            # ... unless that angle is beyond 1e15 rad, where a double no longer tells one turn
            # from the next (a pitch of 1e-244 m/rad picked 1e226 turns out of round-off in the
            # translation); the pose check then reports what the pair cannot reach
            if abs(turn) <= 1e15:
                a = turn
        return np.array([a])


@dataclasses.dataclass(frozen=True)
class Cylindrical(_Pair):
    """Cylindrical pair along ``axis``; x = (angle [rad], displacement [m])."""
    axis: object = "z"
    _code = 4
    k = 2
    _units = ("rad", "m")

    def _rotation(self):
        return _axis_rotation(self.axis, "Cylindrical")

    def _fk(self, x):
        return se3.exp(_ez(0, 0, x[0], 0, 0, x[1]))

    def _coords(self, h):
        return np.array([_angle_z(h), h[2, 3]])


@dataclasses.dataclass(frozen=True)
class Universal(_Pair):
    """Universal (Cardan) pair: first axis ``axis1`` fixed in F_a, second ``axis2`` fixed in F_b
    (perpendicular when both frames coincide); x = (angle about axis1, angle about axis2) [rad],
    h = Rx(x0) Ry(x1) in the pair frames (x = axis1, y = axis2)."""
    axis1: object = "x"
    axis2: object = "y"
    _code = 5
    k = 2
    _units = ("rad", "rad")

    def _rotation(self):
        a, b = _unit(self.axis1, "Universal axis1"), _unit(self.axis2, "Universal axis2")
        if abs(a @ b) > 1e-9:
            raise ModelError("Universal: axis1 and axis2 must be perpendicular")
        return np.column_stack([a, b, np.cross(a, b)])

    def _fk(self, x):
        return se3.exp(_ez(x[0], 0, 0, 0, 0, 0)) @ se3.exp(_ez(0, x[1], 0, 0, 0, 0))

    def _coords(self, h):
        return np.array([np.arctan2(h[2, 1], h[1, 1]), np.arctan2(h[0, 2], h[0, 0])])


@dataclasses.dataclass(frozen=True)
class Spherical(_Pair):
    """Spherical (ball) pair; x = rotation vector of F_b in F_a [rad], xdot = angular velocity
    (in F_b) -- a quasi-velocity, not dx/dt."""
    _code = 6
    k = 3
    _units = ("rad",) * 3

    def _fk(self, x):
        return se3.exp(_ez(x[0], x[1], x[2], 0, 0, 0))

    def _coords(self, h):
        return np.asarray(se3.log(np.ascontiguousarray(h[:3, :3])), dtype=float)


@dataclasses.dataclass(frozen=True)
class Planar(_Pair):
    """Planar pair with plane ``normal``; x = (angle [rad], p_x, p_y [m]) with p the position of
    F_b's origin in F_a (x, y of the frame whose z is the normal)."""
    normal: object = "z"
    _code = 7
    k = 3
    _units = ("rad", "m", "m")

    def _rotation(self):
        return _axis_rotation(self.normal, "Planar")

    def _fk(self, x):
        H = se3.exp(_ez(0, 0, x[0], 0, 0, 0))
        H[0, 3], H[1, 3] = x[1], x[2]
        return H

    def _coords(self, h):
        return np.array([_angle_z(h), h[0, 3], h[1, 3]])


@dataclasses.dataclass(frozen=True)
class Free(_Pair):
    """Free pair (no constraint): x = (rotation vector, position of F_b in F_a); xdot = (angular
    velocity in F_b, dp/dt in F_a). Useful to measure or actuate a relative motion."""
    _code = 8
    k = 6
    _units = ("rad",) * 3 + ("m",) * 3

    def _fk(self, x):
        H = se3.exp(_ez(x[0], x[1], x[2], 0, 0, 0))
        H[:3, 3] = x[3:6]
        return H

    def _coords(self, h):
        return np.concatenate([se3.log(np.ascontiguousarray(h[:3, :3])), h[:3, 3]])


# ------------------------------------------------------------------ actuators
_ACT_EFFORT, _ACT_PD, _ACT_SPRING = range(3)


def _numbers(what, v) -> np.ndarray:
    """A number or a (nested) sequence of numbers, flattened; ModelError for anything else."""
    try:
        raw = np.asarray(v)
    except (TypeError, ValueError):
        raw = np.asarray(None)
    if v is None or isinstance(v, (str, bytes)) or raw.dtype.kind not in "biuf":
        raise ModelError(f"{what}: expected real numbers, got {v!r}")
    return raw.astype(float).ravel()


def _choice(what, value, options) -> str:
    """``value`` if it is one of the strings ``options``, else ModelError naming them."""
    if not isinstance(value, str) or value not in options:
        raise ModelError(f"{what} must be {' or '.join(map(repr, options))} (got {value!r})")
    return value


def _kvec(v, k, what, default=1.0):
    if v is None:
        return np.full(k, float(default))
    expected = f"a number or {k} finite number{'s' if k != 1 else ''}"
    try:
        a = _numbers(what, v)
    except ModelError:
        raise ModelError(f"{what}: expected {expected}, got {v!r}") from None
    if a.size == 1:
        a = np.full(k, float(a[0]))
    if a.shape != (k,) or not np.all(np.isfinite(a)):
        raise ModelError(f"{what}: expected {expected}, got {v!r}")
    return a


@dataclasses.dataclass(frozen=True)
class Effort:
    """Effort source u(t) = law(t) * direction on the pair's joint coordinates (torque [N m] for
    angles, force [N] for displacements); power u . xdot."""
    law: object = None
    direction: object = None


@dataclasses.dataclass(frozen=True)
class PD:
    """PD control to a set-point trajectory: u = -kp (x - x_ref) - kd (xdot - xdot_ref), with
    x_ref(t) = offset + target(t) * direction and xdot_ref = target'(t) * direction. ``target``: a
    time law or a number; gains: numbers or one per coordinate."""
    kp: object
    kd: object
    target: object = 0.0
    direction: object = None
    offset: object = None


@dataclasses.dataclass(frozen=True)
class Spring:
    """Joint spring-damper: u = -k (x - rest) - c xdot; ``rest`` defaults to the pair's x0 (or 0)."""
    k: object
    c: object = 0.0
    rest: object = None


# ------------------------------------------------------------------ frames, bodies, links
@dataclasses.dataclass(frozen=True)
class Frame:
    """A frame with fixed offset ``T`` (4x4) on a carrier (``carrier`` = -1 for the ground)."""
    carrier: int
    T: np.ndarray
    name: str = ""


@dataclasses.dataclass
class Body:
    name: str
    carrier: int

    @property
    def frame(self) -> Frame:
        return Frame(self.carrier, np.eye(4), self.name)


@dataclasses.dataclass
class FlexibleLink:
    """A beam discretized into ``elements`` se3 elements; ``nodes`` are carrier indices;
    ``mesh``: what phmech.mesh.choose_elements chose when the count came from a band (else
    None)."""
    name: str
    length: float
    elements: int
    nodes: list
    mesh: Optional["MeshChoice"] = None

    @property
    def start(self) -> Frame:
        return Frame(self.nodes[0], np.eye(4), self.name + ".start")

    @property
    def end(self) -> Frame:
        return Frame(self.nodes[-1], np.eye(4), self.name + ".end")

    def node(self, k: int) -> Frame:
        """The frame of node ``k``, 0 (start) .. ``elements`` (end), at distance k L / elements
        from the start; Python-style negative k counts from the end (-1 is the end node)."""
        n = len(self.nodes)
        if isinstance(k, bool) or not isinstance(k, (int, np.integer)):
            raise ModelError(f"link {self.name!r}: node index must be an integer (got {k!r})")
        if not -n <= k < n:
            raise ModelError(f"link {self.name!r} has nodes 0..{n - 1} ({self.elements} elements; "
                             f"negative indices -{n}..-1 count from the end); got node({k})")
        k = int(k) % n
        return Frame(self.nodes[k], np.eye(4), f"{self.name}.node{k}")


def _frame_of(x, mech: "Mechanism", what: str) -> Frame:
    """``x`` (a Frame, Body, 'ground' or a body's name) as a Frame of ``mech``; ``what`` names
    the argument in error messages."""
    if isinstance(x, Frame):
        c = x.carrier
        nm = repr(x.name) if x.name else "(unnamed)"
        if isinstance(c, bool) or not isinstance(c, (int, np.integer)) or c < -1 or c >= len(mech._car):
            raise ModelError(f"{what}: the frame {nm} is on carrier {c!r}, which this mechanism does not "
                             f"have (carriers -1 = the ground, 0..{len(mech._car) - 1}); take frames from "
                             f"this mechanism's bodies and links (body.frame, link.start, .end, "
                             f".node(k)) or ph.Frame(carrier, T) with such a carrier index")
        return Frame(int(c), _pose(x.T, f"{what}: the offset T of frame {nm}"), x.name)
    if isinstance(x, Body):
        if mech._bodies.get(x.name) != x:
            raise ModelError(f"{what}: body {x.name!r} (carrier {x.carrier!r}) is not a body of this "
                             f"mechanism (bodies: {', '.join(map(repr, mech._bodies)) or 'none'})")
        return x.frame
    if isinstance(x, FlexibleLink):
        raise ModelError(f"{what}: give a frame of link {x.name!r} (.start, .end or .node(k))")
    if isinstance(x, str):
        if x == "ground":
            return mech.ground
        if x in mech._bodies:
            return mech._bodies[x].frame
        if x in mech._links:
            raise ModelError(f"{what}: {x!r} is a flexible link; give one of its frames "
                             f"(.start, .end or .node(k))")
        raise ModelError(f"{what}: unknown body {x!r}, neither 'ground' nor a body of this mechanism "
                         f"(bodies: {', '.join(map(repr, mech._bodies)) or 'none'})")
    raise ModelError(f"{what}: expected a Frame, Body or 'ground' (got {type(x).__name__})")


def _pose(x, what):
    """A rigid pose [[R, p], [0, 0, 0, 1]] (R orthonormal with det +1 within 1e-6, the core's
    test), or ModelError naming ``what``."""
    H = array(what, x, (4, 4), "a finite 4x4 pose")
    R = H[:3, :3]
    big = np.max(np.abs(R)) > 2   # not a rotation (and R^T R could overflow)
    err = np.inf if big else float(np.max(np.abs(R.T @ R - np.eye(3))))
    det = np.inf if big else float(np.linalg.det(R))
    if not (err <= 1e-6 and det > 0):
        why = f"entries up to {np.max(np.abs(R)):.3g}" if big else f"|R^T R - I| = {err:.2g}, det R = {det:.3g}"
        raise ModelError(f"{what}: expected a rigid 4x4 pose [[R, p], [0, 0, 0, 1]], but its R is "
                         f"not a rotation ({why})")
    if np.max(np.abs(H[3] - [0, 0, 0, 1])) > 1e-12:
        raise ModelError(f"{what}: expected a rigid 4x4 pose, but its last row is {H[3].tolist()}, "
                         f"not [0, 0, 0, 1]")
    return H


def _positive_definite(A, cholesky=False) -> bool:
    """A (finite) is symmetric positive definite: its eigenvalues, scaled by its largest entry,
    are positive; with ``cholesky`` the test the core applies (a Cholesky factorization, no
    tolerance)."""
    scale = np.max(np.abs(A))
    if not (np.isfinite(scale) and scale > 0):
        return False
    B = 0.5 * (A / scale + A.T / scale)   # scaled first: A + A^T may overflow
    if cholesky:
        try:
            np.linalg.cholesky(A)
        except np.linalg.LinAlgError:
            return False
    return bool(np.all(np.linalg.eigvalsh(B) > 0))


def _mat6(x, what, spd=True):
    return array(what, x, (6, 6), "a finite 6x6 matrix")


def _carrier_name(c: int, bodies: dict, links: dict) -> str:
    """'the ground', "body 'b'" or "node k of link 'L'" for carrier index c."""
    if c < 0:
        return "the ground"
    for b in bodies.values():
        if b.carrier == c:
            return f"body {b.name!r}"
    for lk in links.values():
        if c in lk.nodes:
            return f"node {lk.nodes.index(c)} of link {lk.name!r}"
    return f"carrier {c}"


# ------------------------------------------------------------------ results
def _result_link(links: dict, link) -> "FlexibleLink":
    """A link of the result's mechanism, given by itself or its name."""
    lk = links.get(link) if isinstance(link, str) else link
    if not isinstance(lk, FlexibleLink) or links.get(lk.name) != lk:
        raise ModelError(f"expected a flexible link of this mechanism or its name (links: "
                         f"{', '.join(map(repr, links)) or 'none'}), got {link!r}")
    return lk


class Momentum(NamedTuple):
    """World-frame momentum along a trajectory (SimulationResult.momentum): ``linear`` (nt, 3)
    [kg m/s] and ``angular`` (nt, 3) [kg m^2/s] about the point asked for."""
    linear: np.ndarray
    angular: np.ndarray


@dataclasses.dataclass
class SimulationResult:
    """Sampled solution. ``poses`` (nt, ncarriers, 4, 4), ``twists`` (nt, ncarriers, 6) body
    twists, ``constraint_wrenches`` (nt, nconstraints), ``energy`` dict of (nt,) arrays [J]
    (kinetic, elastic, gravity, dissipated, supplied, total, ledger = E - E0 - (supplied -
    dissipated)), ``stats`` (IDA steps, residual/Jacobian evaluations, wall time [s]),
    ``interrupted`` (stopped by Ctrl-C or the callback).

    ``port_energy``: dict port name -> (nt,) energy supplied through that port [J] (actuators:
    int u . xdot; interactions and wrenches: int w . t; spring-dampers: minus their dissipated
    energy). Supplied = sum over actuators and wrenches (+ power of driven pairs); the ledger
    residual is ``energy["ledger"]``. ``joint(name)`` gives a pair's coordinates and efforts.

    Conserved quantities: ``momentum(x=None, about=(0, 0, 0))`` is the world-frame linear
    momentum P [kg m/s] and angular momentum L [kg m^2/s] about a world point, of the whole
    mechanism or of bodies/links, as ``Momentum(linear, angular)``, each (nt, 3). Every carrier
    (rigid body or beam node) contributes its body momentum M t (M its 6x6 spatial inertia about
    its frame, t its body twist), moved to the world frame by the dual adjoint Ad*_{H^-1}:
    P = sum R P_b, L = sum R L_b + (p - about) x R P_b, i.e. sum of r x m v over the mass,
    right-handed. Free mechanisms without loads keep both constant; gravity g changes P at the
    rate ``mass() * g``. ``mass(x=None)`` [kg] and ``centre_of_mass(x=None)`` (nt, 3) [m] go with
    it. All three need the poses and twists of the carriers asked for: after
    ``simulate(record=...)`` only what was recorded can be asked for (ModelError otherwise)."""
    t: np.ndarray
    poses: np.ndarray
    twists: np.ndarray
    constraint_wrenches: np.ndarray
    energy: dict
    stats: dict
    interrupted: bool
    _links: dict
    port_energy: dict = dataclasses.field(default_factory=dict)
    joints: np.ndarray = None
    joint_rates: np.ndarray = None
    efforts: np.ndarray = None
    pair_wrenches: np.ndarray = None
    _pairs: dict = dataclasses.field(default_factory=dict)
    #: (pair, direction) rows left out of the DAE as redundant; when non-empty,
    #: ``constraint_wrenches`` holds the minimum-norm multipliers of ALL rows (see
    #: Mechanism._min_norm_multipliers) and ``pair_wrenches`` the matching pair wrenches.
    redundant_constraints: list = dataclasses.field(default_factory=list)
    #: carrier index of each column of ``poses``/``twists`` (all carriers unless ``record=`` chose)
    carriers: np.ndarray = None
    _frame: Callable = None  # resolves a body, frame or name to a Frame (set by simulate)
    #: every carrier's 6x6 spatial inertia (body frame), mass and centre of mass (body
    #: coordinates) as the model had them (set by simulate; momentum, mass, centre_of_mass)
    _inertia: np.ndarray = None
    _mass: np.ndarray = None
    _com: np.ndarray = None
    _bodies: dict = dataclasses.field(default_factory=dict)

    def pose(self, x) -> np.ndarray:
        """World pose of a body or frame (a Frame, Body, link end, or a body's name), (nt, 4, 4)."""
        f = self._frame(x)
        if f.carrier < 0:
            return np.broadcast_to(f.T, (len(self.t), 4, 4)).copy()
        return self.poses[:, self._columns([f.carrier])[0]] @ f.T

    def position(self, x) -> np.ndarray:
        """World position of a body's or frame's origin [m], (nt, 3)."""
        return self.pose(x)[:, :3, 3]

    def orientation(self, x) -> np.ndarray:
        """World orientation (rotation matrix) of a body or frame, (nt, 3, 3)."""
        return self.pose(x)[:, :3, :3]

    def twist(self, x) -> np.ndarray:
        """Body twist (omega [rad/s], v [m/s]) of a body or frame in its own axes, (nt, 6):
        Ad_{T^-1} of the carrier's twist, T the frame's offset on it."""
        f = self._frame(x)
        if f.carrier < 0:
            return np.zeros((len(self.t), 6))
        t = self.twists[:, self._columns([f.carrier])[0]]
        return t @ se3.Ad(se3.inverse(f.T)).T

    def _columns(self, carriers) -> list:
        """Columns of ``poses`` holding these carriers; ModelError if one was not recorded."""
        if self.carriers is None:
            return list(carriers)
        where = {int(c): i for i, c in enumerate(self.carriers)}
        missing = [c for c in carriers if c not in where]
        if missing:
            raise ModelError(f"carriers {missing} were not recorded (simulate(record=...))")
        return [where[c] for c in carriers]

    def joint(self, name: str) -> dict:
        """Pair ``name``: ``x`` (nt, k) joint coordinates (exact, multi-turn), ``xdot`` (nt, k)
        rates, ``effort`` (nt, k) sum of its actuators' efforts u, ``lambda`` (nt, m) constraint
        multipliers (W^C coordinates), ``wrench`` (nt, 6) constraint wrench W^C lambda on b in
        frame F_b (tau [N m], f [N])."""
        if not isinstance(name, str) or name not in self._pairs:
            raise ModelError(f"joint: unknown pair {name!r} (pairs: "
                             f"{', '.join(map(repr, self._pairs)) or 'none'})")
        row, m, j, k = self._pairs[name]["layout"]
        ip = self._pairs[name]["index"]
        return dict(x=self.joints[:, j:j + k], xdot=self.joint_rates[:, j:j + k],
                    effort=self.efforts[:, j:j + k], **{"lambda": self.constraint_wrenches[:, row:row + m]},
                    wrench=self.pair_wrenches[:, ip])

    def positions(self, link: Union[str, FlexibleLink]) -> np.ndarray:
        """Node positions of a link [m], shape (nt, nnodes, 3)."""
        lk = _result_link(self._links, link)
        return self.poses[:, self._columns(lk.nodes)][..., :3, 3]

    def tip(self, link: Union[str, FlexibleLink]) -> np.ndarray:
        """Position of the link's end node [m], shape (nt, 3)."""
        return self.positions(link)[:, -1, :]

    # ---------------------------------------------------------- conserved quantities

    def _mass_carriers(self, x, need_motion: bool, what: str) -> list:
        """Carrier indices of ``x`` (None: all; a Body, FlexibleLink, a body's or link's name,
        or a list of these); with ``need_motion``, ModelError unless all were recorded."""
        if self._mass is None:
            raise ModelError(f"{what}: this result carries no inertia data (made by simulate?)")
        if x is None:
            carriers, whom = list(range(len(self._mass))), "the whole mechanism"
        else:
            items = list(x) if isinstance(x, (list, tuple)) else [x]
            carriers, names = [], []
            for it in items:
                if isinstance(it, str):
                    it = self._links.get(it, self._bodies.get(it, it))
                if isinstance(it, Body) and self._bodies.get(it.name) == it:
                    cs = [it.carrier]
                elif isinstance(it, FlexibleLink) and self._links.get(it.name) is it:
                    cs = list(it.nodes)
                elif isinstance(it, (str, Body, FlexibleLink)):
                    nm = it if isinstance(it, str) else it.name
                    raise ModelError(f"{what}: {nm!r} is not a body or link of this mechanism "
                                     f"(bodies: {', '.join(map(repr, self._bodies)) or 'none'}; "
                                     f"links: {', '.join(map(repr, self._links)) or 'none'})")
                else:
                    raise ModelError(f"{what}: expected None (the whole mechanism), a Body, a "
                                     f"FlexibleLink, a body's or link's name, or a list of these "
                                     f"(got {type(it).__name__}; a frame or the ground has no mass "
                                     f"of its own)")
                carriers += [c for c in cs if c not in carriers]
                names.append(repr(it.name))
            whom = ", ".join(names)
            if not carriers:
                raise ModelError(f"{what}: an empty selection (None is the whole mechanism)")
            if max(carriers) >= len(self._mass):
                raise ModelError(f"{what}: {whom} was added to the mechanism after this simulation")
        if need_motion and self.carriers is not None:
            kept = {int(c) for c in self.carriers}
            missing = [c for c in carriers if c not in kept]
            if missing:
                full = [repr(b.name) for b in self._bodies.values() if b.carrier in kept]
                full += [repr(lk.name) for lk in self._links.values() if all(c in kept for c in lk.nodes)]
                lost = ", ".join(_carrier_name(c, self._bodies, self._links) for c in missing[:5])
                lost += f" and {len(missing) - 5} more" if len(missing) > 5 else ""
                raise ModelError(
                    f"{what} of {whom} needs the poses and twists of every carrier in it, but "
                    f"simulate(record=...) did not record {lost}. It can be computed for what was "
                    f"recorded in full ({', '.join(full) or 'nothing'}); simulate without record= "
                    f"(or record these too) for the rest")
        return carriers

    def momentum(self, x=None, about=(0.0, 0.0, 0.0)) -> "Momentum":
        """World-frame linear and angular momentum of the whole mechanism (``x`` None) or of a
        body, a flexible link (all its nodes), a body's or link's name, or a list of these:
        ``Momentum(linear, angular)``, each (nt, 3), in kg m/s and kg m^2/s.

        Each carrier (a rigid body, or a beam node with its lumped inertia) contributes its body
        momentum (L_b, P_b) = M t, M its 6x6 spatial inertia about the carrier frame (centre of
        mass possibly offset) and t = (omega, v) its body twist, moved to the world frame by the
        dual adjoint, (L, P) = Ad*_{H^-1} (L_b, P_b) with H = (R, p) the carrier's pose:
        P = R P_b, L = R L_b + (p - about) x P. So ``linear`` is sum m v_com and ``angular`` the
        moment of momentum sum (r - about) x m v + I_com omega about the world point ``about``
        (right-handed: positive about an axis when the mass turns counterclockwise seen from
        its tip), with the absolute (world) velocities. ``about``: a fixed world point (3,), one
        point per output (nt, 3) (e.g. a moving pivot), or ``"com"``: the selection's own centre
        of mass at each output (its spin angular momentum).

        Without external wrenches (no gravity, loads, or pairs, springs or actuators to the
        ground) both are constant; under gravity alone d(linear)/dt = mass(x) g. After
        ``simulate(record=...)``, ``x`` must be bodies/links whose carriers were all recorded
        (ModelError naming what is missing otherwise); the whole mechanism needs every carrier."""
        cars = self._mass_carriers(x, True, "momentum")
        nt = len(self.t)
        if isinstance(about, str):
            if about != "com":
                raise ModelError(f"momentum: about must be a world point (3,), points (nt, 3) or "
                                 f"'com' (got {about!r})")
            a = self.centre_of_mass(x)
        else:
            a = np.asarray(about, dtype=float)
            if a.shape not in ((3,), (nt, 3)) or not np.all(np.isfinite(a)):
                raise ModelError(f"momentum: about must be a finite world point (3,) or one point "
                                 f"per output ({nt}, 3) [m] (got shape {a.shape})")
        cols = self._columns(cars)
        P = np.zeros((nt, 3))
        L = np.zeros((nt, 3))
        for c, j in zip(cars, cols):          # per carrier, vectorized over time
            mb = self.twists[:, j] @ self._inertia[c].T         # body momentum (L_b, P_b)
            R = self.poses[:, j, :3, :3]
            Pw = np.einsum("nij,nj->ni", R, mb[:, 3:])
            P += Pw
            L += np.einsum("nij,nj->ni", R, mb[:, :3]) + np.cross(self.poses[:, j, :3, 3] - a, Pw)
        return Momentum(P, L)

    def mass(self, x=None) -> float:
        """Mass [kg] of the whole mechanism (``x`` None) or of bodies/links (as in momentum): the
        sum of the carriers' masses (a link's node masses add up to its mass per length times its
        length). Needs no recorded motion."""
        return float(np.sum(self._mass[self._mass_carriers(x, False, "mass")]))

    def centre_of_mass(self, x=None) -> np.ndarray:
        """World position of the centre of mass [m], (nt, 3), of the whole mechanism (``x``
        None) or of bodies/links (as in momentum): sum m_i (p_i + R_i c_i) / sum m_i over the
        carriers, c_i the centre of mass in carrier coordinates (the masses and centres of mass
        gravity acts on). Needs the recorded poses of those carriers (see momentum)."""
        cars = self._mass_carriers(x, True, "centre_of_mass")
        cols = self._columns(cars)
        H = self.poses[:, cols]                                   # (nt, k, 4, 4)
        r = np.einsum("nkij,kj->nki", H[..., :3, :3], self._com[cars]) + H[..., :3, 3]
        m = self._mass[cars]
        return np.einsum("k,nki->ni", m, r) / m.sum()


@dataclasses.dataclass
class ModesResult:
    """Linearized modes: ``omega`` [rad/s], ``frequency`` [Hz], ``damping_ratio``, ``shapes``
    (n, ncarriers, 6) tangent displacements (rotation, translation) per carrier, mass-normalized."""
    omega: np.ndarray
    frequency: np.ndarray
    damping_ratio: np.ndarray
    shapes: np.ndarray


@dataclasses.dataclass
class StaticResult:
    """Static equilibrium: ``poses`` (ncarriers, 4, 4), ``constraint_wrenches``, Newton
    ``iterations``."""
    poses: np.ndarray
    constraint_wrenches: np.ndarray
    iterations: int
    _links: dict

    def positions(self, link: Union[str, FlexibleLink]) -> np.ndarray:
        """Node positions of a link [m], shape (nodes, 3)."""
        lk = _result_link(self._links, link)
        return self.poses[lk.nodes, :3, 3]


# ------------------------------------------------------------------ the mechanism
class Mechanism:
    """A mechanism under construction: add links, bodies, pairs and wrenches, then simulate,
    compute modes or static equilibria. ``gravity`` [m/s^2] in world coordinates.

    ``strict``: when the loop closure of the initial configuration moves a given joint
    coordinate (``x0``) or a given pose beyond its tolerance, raise ModelError instead of warning
    (InitialValueWarning). Tolerances: 1e-6 rad for angles (1e-6 |x0| for |x0| > 1 rad), 1e-6 L
    for lengths, L the mechanism's size (topology.length_scale: the largest of the link lengths,
    the pair frames' offsets and the extent of the carriers' initial origins). Either way the
    moves are listed in ``initial_adjustments`` once a model has been built.

    ``band`` [Hz] and ``frequency_tolerance``: the frequencies the model must resolve; every
    flexible link added without ``elements=`` gets the number of elements that puts its modes up
    to ``band`` within ``frequency_tolerance`` of the converged ones (phmech.mesh.choose_elements;
    ``link.mesh`` says what was chosen and the estimated error). Without a band a link gets 10
    elements. (The integrator's band, ``simulate(band=)``, is separate: what the steps resolve.)"""

    def __init__(self, gravity: Sequence[float] = (0.0, 0.0, 0.0), strict: bool = False,
                 band: Optional[float] = None, frequency_tolerance: float = 1e-3):
        g = array("gravity", gravity, (3,), "3 finite numbers [m/s^2]")
        if not isinstance(strict, (bool, np.bool_)):
            raise ModelError(f"strict must be True or False (got {strict!r})")
        if band is not None and not (real("band", band) > 0):
            raise ModelError(f"band must be a frequency > 0 [Hz] or None (got {band!r})")
        tol = real("frequency_tolerance", frequency_tolerance)
        if not 0 < tol < 1:
            raise ModelError(f"frequency_tolerance must be in (0, 1) (got {frequency_tolerance!r})")
        self.gravity = g
        self.strict = bool(strict)
        self.band = None if band is None else real("band", band)
        self.frequency_tolerance = tol
        self.ground = Frame(-1, np.eye(4), "ground")
        self._car = []      # dicts: M, mass, com, H0, t0
        self._el = []       # dicts: a, b, h, K, D, eps
        self._pairs = []    # dicts: name, type, a, b, Ta, Tb, driven
        self._loads = []    # dicts: name, carrier, world, point, w, law, reaction
        self._acts = []     # dicts: name, pair, kind, vec, kp, kd, xset, law
        self._springs = []  # dicts: name, a, b, pa, pb, kcd
        self._links = {}
        self._bodies = {}
        self._names = set()
        self._el_first = {}     # link name -> index of its first element
        self._given = {}        # carrier -> the pose the user gave it (4x4), if any
        self._twist_given = set()  # carriers whose twist the user gave (add_rigid_body(twist=))
        self._warned = None
        self._warned_initial = None
        #: (pair name, constraint direction) rows found redundant at the initial configuration and
        #: left out of the DAE (set when the core model is built: simulate, modes, static, ...)
        self.redundant_constraints: list = []
        #: InitialAdjustment rows: how far the loop closure moved each given x0 coordinate and
        #: each given pose (set when the core model is built, like redundant_constraints)
        self.initial_adjustments: list = []

    # -------------------------------------------------------------- building
    def _check_name(self, name):
        """ModelError unless ``name`` is a new non-empty string."""
        if not isinstance(name, str) or not name:
            raise ModelError(f"name must be a non-empty string (got {name!r})")
        if name in self._names:
            raise ModelError(f"name {name!r} is already used")

    def _new_name(self, name):
        self._check_name(name)
        self._names.add(name)

    def add_flexible_link(self, name: str, length: float, properties, elements: Optional[int] = None,
                          pose=None, curvature=None, discretization: str = "se3",
                          band: Optional[float] = None,
                          frequency_tolerance: Optional[float] = None) -> FlexibleLink:
        """A flexible link of ``length`` [m] along the local x axis of ``pose`` (4x4, the frame of
        its start). ``properties``: object with 6x6 ``stiffness`` (section stiffness, order
        (torsion, bending y, bending z, axial, shear y, shear z) strains), ``inertia`` (per unit
        length) and ``damping`` (viscous section damping, may be absent). ``curvature``: the
        unstressed curvature (kappa_x, kappa_y, kappa_z) [1/m], or None (straight).

        ``pose`` given: the link's initial pose is honoured -- the pairs on its nodes take their
        reference from it (a Fixed clamp or weld holds the relative orientation its frames have
        at the given poses, e.g. a root rotated about x selects the other bending axis), and
        given poses that violate a pair (frame origins apart, a revolute's axes not parallel)
        raise ModelError; only a pair with ``x0`` places the link elsewhere. ``pose=None``: the
        link is placed from its pairs. See add_pair and docs/user_guide.md.

        ``elements``: the number of se3 elements; None: chosen from ``band`` [Hz] and
        ``frequency_tolerance`` (default: the Mechanism's; see Mechanism and phmech.mesh), or 10
        without a band."""
        if not isinstance(discretization, str) or discretization != "se3":
            raise ModelError(f"unknown discretization {discretization!r} (available: 'se3')")
        L = real("length", length)
        if L <= 0:
            raise ModelError(f"length must be > 0 (got {L} m)")
        if elements is not None and (isinstance(elements, (bool, np.bool_)) or not isinstance(elements, (int, np.integer))
                                     or elements < 1):
            raise ModelError(f"elements must be an integer >= 1 or None (got {elements!r})")
        if elements is not None and band is not None:
            raise ModelError(f"link {name!r}: give elements= or band=, not both")
        K = _mat6(getattr(properties, "stiffness", None), "properties.stiffness")
        I = _mat6(getattr(properties, "inertia", None), "properties.inertia")
        Dp = getattr(properties, "damping", None)
        Dm = np.zeros((6, 6)) if Dp is None else _mat6(Dp, "properties.damping")
        if not _positive_definite(K):
            raise ModelError("properties.stiffness must be symmetric positive definite")
        if not _positive_definite(I):
            raise ModelError("properties.inertia (per unit length) must be symmetric positive definite")
        H = np.eye(4) if pose is None else _pose(pose, "pose")
        kap = np.zeros(3) if curvature is None else \
            array("curvature", curvature, (3,), "3 finite numbers [1/m] or None")
        self._check_name(name)
        choice = None
        if elements is None:
            band = self.band if band is None else band
            tol = self.frequency_tolerance if frequency_tolerance is None else frequency_tolerance
            if band is not None:
                from .mesh import choose_elements
                choice = choose_elements(L, properties, band, tol, curvature=kap)
        N = int(elements) if elements is not None else choice.elements if choice else 10
        h = L / N
        eps = np.concatenate([kap, [1.0, 0.0, 0.0]])
        with np.errstate(over="ignore", under="ignore", divide="ignore", invalid="ignore"):
            scales = (I * h, K / h, Dm / h, L * eps)   # node inertias, element stiffness, shape
        if not (h > 0 and all(np.all(np.isfinite(x)) for x in scales)):
            raise ModelError(f"link {name!r}: length {L:g} m in {N} elements with these properties "
                             f"gives node inertias or element stiffnesses that are not finite in "
                             f"double precision")
        try:   # the unstressed shape: node k at H exp(k h eps_hat)
            with np.errstate(over="raise", invalid="raise"):
                H0 = [H @ se3.exp(k * h * eps) for k in range(N + 1)]
        except (ValueError, FloatingPointError):   # se3 refuses a non-finite result (ModelError)
            H0 = None
        if H0 is None or not np.all(np.isfinite(H0)):
            raise ModelError(f"link {name!r}: curvature {kap.tolist()} 1/m over length {L:g} m gives "
                             f"node poses that are not finite in double precision")
        self._new_name(name)
        first = len(self._car)
        self._el_first[name] = len(self._el)
        for k in range(N + 1):
            share = h if 0 < k < N else h / 2
            Mk = I * share
            self._car.append(dict(M=Mk, mass=float(Mk[3, 3]), com=np.zeros(3), H0=H0[k],
                                  t0=np.zeros(6)))
        for k in range(N):
            self._el.append(dict(a=first + k, b=first + k + 1, h=h, K=K, D=Dm, eps=eps))
        if pose is not None:
            for k in range(N + 1):
                self._given[first + k] = np.array(self._car[first + k]["H0"])
        link = FlexibleLink(name, L, N, list(range(first, first + N + 1)), choice)
        self._links[name] = link
        return link

    def add_rigid_body(self, name: str, mass: float, inertia, com=(0.0, 0.0, 0.0), pose=None,
                       twist=None) -> Body:
        """A rigid body: ``mass`` [kg], ``inertia`` 3x3 about the centre of mass in body axes
        [kg m^2], ``com`` in body coordinates [m], initial ``pose`` (4x4) and body ``twist``
        (omega [rad/s], v [m/s]; None: moving with its pairs and their ``xdot0``, at rest if free).
        A given ``pose`` is honoured by the pairs on the body like a flexible link's (see
        add_flexible_link, add_pair); ``pose=None``: placed from its pairs."""
        m = real("mass", mass)
        if m <= 0:
            raise ModelError(f"mass must be > 0 (got {m} kg)")
        spd = "a symmetric positive definite 3x3 matrix [kg m^2]"
        J = array("inertia", inertia, (3, 3), spd)
        if not _positive_definite(J):
            raise ModelError(f"inertia: expected {spd}")
        c = array("com", com, (3,), "3 finite numbers [m]")
        tw = np.zeros(6) if twist is None else array("twist", twist, (6,), "6 finite numbers (omega [rad/s], v [m/s]) or None")
        H0 = np.eye(4) if pose is None else _pose(pose, "pose")
        C = np.array([[0, -c[2], c[1]], [c[2], 0, -c[0]], [-c[1], c[0], 0]])
        M = np.zeros((6, 6))
        with np.errstate(over="ignore", invalid="ignore"):
            M[:3, :3] = J - m * C @ C
            M[:3, 3:] = m * C
            M[3:, :3] = -m * C
            M[3:, 3:] = m * np.eye(3)
        if not (np.all(np.isfinite(M)) and _positive_definite(M, cholesky=True)):
            raise ModelError(f"body {name!r}: mass {m:g} kg, inertia (largest {np.max(np.abs(J)):.3g} "
                             f"kg m^2) and com {c.tolist()} m give a spatial inertia that is not "
                             f"finite and positive definite in double precision")
        self._new_name(name)
        self._car.append(dict(M=M, mass=m, com=c, H0=H0, t0=tw))
        b = Body(name, len(self._car) - 1)
        if pose is not None:
            self._given[b.carrier] = np.array(self._car[b.carrier]["H0"])
        if twist is not None:
            self._twist_given.add(b.carrier)
        self._bodies[name] = b
        return b

    def add_pair(self, name: str, pair, a, b, driven: Optional[Motion] = None, actuator=None,
                 x0=None, xdot0=None) -> None:
        """A kinematic pair ``pair`` (Fixed, Revolute, Prismatic, Helical, Cylindrical, Universal,
        Spherical, Planar, Free) from frame ``a`` to frame ``b`` (edge (a, b)).

        ``driven``: a prescribed relative motion (Motion; Fixed pairs only). ``actuator``: an
        Effort, PD or Spring on the pair's joint coordinates (its port is named after the pair; add
        more with add_actuator). ``x0``/``xdot0``: initial joint coordinates [rad or m] and rates;
        when ``b`` is a rigid body it is placed there relative to ``a``'s current initial pose and
        twist (add pairs from the ground outwards).

        Initial configuration (docs/user_guide.md): walking from the ground, the carrier beyond
        the pair is placed from it at ``x0`` when ``x0`` is given or when that carrier has no
        given pose (x = 0 without ``x0``). Otherwise the given poses are the reference: the
        pair's coordinates are those of its two frames at the given poses, the weld of a Fixed
        pair holds the relative orientation of its frames there (if neither frame offset has a
        rotation of its own; a rotated offset must agree with the poses), and given poses that
        violate the pair's constrained directions -- frame origins apart [m] or constrained axes
        turned [rad] beyond 1e-6 (1e-6 times the mechanism's size in m) -- raise ModelError
        naming the pair, its frames and the mismatch. Loops are then closed by a Newton
        projection; how far it moved a given ``x0`` or pose is in ``initial_adjustments`` and
        warned about (InitialValueWarning; ModelError with ``Mechanism(strict=True)``)."""
        if not isinstance(pair, _Pair):
            raise ModelError(f"pair {name!r}: unsupported pair type {type(pair).__name__} (available: "
                             "Fixed, Revolute, Prismatic, Helical, Cylindrical, Universal, Spherical, Planar, Free)")
        fa, fb = _frame_of(a, self, f"pair {name!r}, argument a"), _frame_of(b, self, f"pair {name!r}, argument b")
        if fa.carrier == fb.carrier:
            raise ModelError(f"pair {name!r}: both frames are on the same carrier (a body cannot be paired with itself)")
        try:
            Q = np.eye(4)
            Q[:3, :3] = pair._rotation()
            pitch = pair._pitch()
        except ModelError as e:
            raise ModelError(f"pair {name!r}: {e}") from None
        Ta, Tb = fa.T @ Q, fb.T @ Q
        law, axis = None, np.zeros(6)
        if driven is not None:
            if not isinstance(driven, Motion):
                raise ModelError(f"pair {name!r}: driven must be a Motion")
            if not isinstance(pair, Fixed):
                raise ModelError(f"pair {name!r}: only Fixed pairs take a prescribed Motion; drive a "
                                 f"{type(pair).__name__} pair with a PD actuator")
            axis = array(f"pair {name!r}: motion axis", driven.axis, (6,), "6 finite numbers (omega, v)")
            law = _law_tuple(driven.law, f"pair {name!r}: Motion law")
        k = pair.k
        xv = np.zeros(6)
        if x0 is not None:
            if k == 0:
                raise ModelError(f"pair {name!r}: a fixed pair has no joint coordinates (x0)")
            xv[:k] = _kvec(x0, k, f"pair {name!r}: x0")
        xd = None if xdot0 is None else _kvec(xdot0, k, f"pair {name!r}: xdot0")
        if xdot0 is not None and k == 0:
            raise ModelError(f"pair {name!r}: a fixed pair has no joint rates (xdot0)")
        self._check_name(name)
        xdv = np.zeros(6)
        if xd is not None:
            xdv[:k] = xd
        entry = dict(name=name, type=pair._code, a=fa.carrier, b=fb.carrier, Ta=Ta, Tb=Tb,
                     fa_name=self._describe(fa), fb_name=self._describe(fb),
                     driven=driven is not None, axis=axis, law=law, pitch=pitch, k=k,
                     x0=xv, has_x0=x0 is not None, pair=pair, xdot0=xdv,
                     has_xdot0=xdot0 is not None)
        # everything that can fail before anything is changed: a failed call adds nothing
        act = None if actuator is None else self._actuator_entry(name, entry, len(self._pairs), actuator)
        place = None
        if (x0 is not None or xdot0 is not None) and fb.carrier in self._body_carriers():
            place = self._placed(entry, xv[:k], np.zeros(k) if xd is None else xd)
        self._new_name(name)
        self._pairs.append(entry)
        if place is not None:
            self._car[entry["b"]]["H0"], self._car[entry["b"]]["t0"] = place
        if act is not None:
            self._acts.append(act)

    def _carrier_name(self, c: int) -> str:
        return _carrier_name(c, self._bodies, self._links)

    def _describe(self, f: Frame) -> str:
        """A frame's name in quotes, or where an unnamed frame sits."""
        return repr(f.name) if f.name else f"(unnamed frame on {self._carrier_name(f.carrier)})"

    def _body_carriers(self):
        return {b.carrier for b in self._bodies.values()}

    def _placed(self, e, x, xd):
        """Pose H_a T_a h(x) T_b^-1 of carrier b and its twist (that of a plus the joint rate);
        ModelError when x0 or xdot0 are beyond what double precision can place."""
        pair = e["pair"]
        Ha = np.eye(4) if e["a"] < 0 else self._car[e["a"]]["H0"]
        ta = np.zeros(6) if e["a"] < 0 else self._car[e["a"]]["t0"]
        try:
            with np.errstate(over="raise", invalid="raise"):
                h = pair._fk(x)
                Hb = Ha @ e["Ta"] @ h @ se3.inverse(e["Tb"])
                # relative twist t_rel = psi(x) xdot, psi by central differences of h(x)
                trel = np.zeros(6)
                eps = 1e-6
                hi = se3.inverse(h)
                for i in range(len(x)):
                    d = np.zeros(len(x))
                    d[i] = eps
                    trel += xd[i] * (se3.log(hi @ pair._fk(x + d)) - se3.log(hi @ pair._fk(x - d))) / (2 * eps)
                tA = se3.Ad(se3.inverse(e["Ta"])) @ ta               # body twist of F_a
                tB = se3.Ad(hi) @ tA + trel                          # body twist of F_b
                tb = se3.Ad(e["Tb"]) @ tB
        except (ValueError, FloatingPointError):   # se3 refuses non-finite input (ModelError)
            tb = Hb = np.full(6, np.nan)
        if not (np.all(np.isfinite(Hb)) and np.all(np.isfinite(tb))):
            raise ModelError(f"pair {e['name']!r}: x0 {x.tolist()} and xdot0 {xd.tolist()} give a "
                             f"non-finite initial pose or twist of {self._carrier_name(e['b'])} "
                             f"in double precision")
        return Hb, tb

    def _pair_entry(self, pair):
        for e in self._pairs:
            if e["name"] == pair:
                return e
        raise ModelError(f"unknown pair {pair!r}")

    def add_actuator(self, name: str, pair: str, actuator) -> None:
        """An actuator (Effort, PD or Spring) named ``name`` on the pair named ``pair``."""
        if not isinstance(pair, str):
            raise ModelError(f"actuator {name!r}: pair must be given by its name (got {pair!r})")
        e = self._pair_entry(pair)
        self._check_name(name)
        act = self._actuator_entry(name, e, self._pairs.index(e), actuator)
        self._new_name(name)
        self._acts.append(act)

    def _actuator_entry(self, name, e, index, act):
        """The actuator's row (pair entry e, at position index): validated, not yet added."""
        k = e["k"]
        what = f"actuator {name!r}"
        if k == 0:
            raise ModelError(f"{what}: a fixed pair has no allowed direction to actuate")
        z = np.zeros(6)
        vec, kp, kd, xs, law = z.copy(), z.copy(), z.copy(), z.copy(), None
        if isinstance(act, Effort):
            kind = _ACT_EFFORT
            law = _law_tuple(Constant(1.0) if act.law is None else act.law, f"{what}: Effort law",
                             numbers=True)
            vec[:k] = _kvec(act.direction, k, f"{what}: direction")
        elif isinstance(act, PD):
            kind = _ACT_PD
            kp[:k] = _kvec(act.kp, k, f"{what}: kp")
            kd[:k] = _kvec(act.kd, k, f"{what}: kd")
            d = _kvec(act.direction, k, f"{what}: direction")
            xs[:k] = _kvec(act.offset, k, f"{what}: offset", default=0.0)
            if isinstance(act.target, _Law) or callable(act.target):
                law = _law_tuple(act.target, f"{what}: PD target")
                vec[:k] = d
            else:
                with np.errstate(over="ignore", invalid="ignore"):   # checked below
                    xs[:k] += _kvec(act.target, k, f"{what}: target") * (d if act.direction is not None else 1.0)
                law = Constant(0.0)._tuple()
        elif isinstance(act, Spring):
            kind = _ACT_SPRING
            kp[:k] = _kvec(act.k, k, f"{what}: k")
            kd[:k] = _kvec(act.c, k, f"{what}: c")
            xs[:k] = e["x0"][:k] if act.rest is None else _kvec(act.rest, k, f"{what}: rest")
        else:
            raise ModelError(f"{what}: expected Effort, PD or Spring (got {type(act).__name__})")
        if kind != _ACT_EFFORT and (np.any(kp[:k] < 0) or np.any(kd[:k] < 0)):
            raise ModelError(f"{what}: gains must be >= 0")
        if not np.all(np.isfinite(xs)):
            raise ModelError(f"{what}: the set point (offset + target times direction) is not "
                             f"finite in double precision: {xs[:k].tolist()}")
        return dict(name=name, pair=index, kind=kind, vec=vec, kp=kp, kd=kd, xset=xs, law=law)

    def add_spring_damper(self, name: str, a, b, k: float, c: float = 0.0,
                          rest_length: Optional[float] = None, point_a=(0.0, 0.0, 0.0),
                          point_b=(0.0, 0.0, 0.0)) -> None:
        """Point-to-point spring-damper between ``point_a`` of frame ``a`` and ``point_b`` of frame
        ``b`` (frame coordinates [m]; the ground's points are world points): tension
        k (d - rest_length) + c dd/dt [N], ``rest_length`` defaulting to the initial distance.
        Its elastic energy is part of the total energy, its dissipation a port of the ledger."""
        fa, fb = _frame_of(a, self, f"spring {name!r}, argument a"), _frame_of(b, self, f"spring {name!r}, argument b")
        if fa.carrier == fb.carrier:
            raise ModelError(f"spring {name!r}: both ends are on the same carrier")
        kk, cc = real(f"spring {name!r}: k", k), real(f"spring {name!r}: c", c)
        if kk < 0 or cc < 0:
            raise ModelError(f"spring {name!r}: k and c must be >= 0")
        pa = array(f"spring {name!r}: point_a", point_a, (3,), "3 finite numbers [m]")
        pb = array(f"spring {name!r}: point_b", point_b, (3,), "3 finite numbers [m]")
        pa = fa.T[:3, :3] @ pa + fa.T[:3, 3]
        pb = fb.T[:3, :3] @ pb + fb.T[:3, 3]
        d0 = None if rest_length is None else real(f"spring {name!r}: rest_length", rest_length)
        if d0 is not None and d0 < 0:
            raise ModelError(f"spring {name!r}: rest_length must be >= 0")
        self._new_name(name)
        self._springs.append(dict(name=name, a=fa.carrier, b=fb.carrier, pa=pa, pb=pb, kcd=(kk, cc, d0)))

    def add_interaction(self, name: str, target, wrench, law: _Law = Constant(1.0),
                        frame: str = "world", point=(0.0, 0.0, 0.0), reaction=None) -> None:
        """An external wrench law(t) * (tau [N m], f [N]) on ``target`` at ``point`` (target frame
        coordinates [m]), in "world" or "body" (target frame) axes; the opposite wrench acts on
        ``reaction`` (a frame or body; None = the ground) through the same point. Its injected
        power is a port of the ledger."""
        load = self._wrench_entry(name, target, wrench, law, frame, point)
        if reaction is not None:
            fr = _frame_of(reaction, self, f"interaction {name!r}, argument reaction")
            if fr.carrier == load["carrier"]:
                raise ModelError(f"interaction {name!r}: target and reaction are on the same carrier")
            load["reaction"] = fr.carrier
        load["interaction"] = True
        self._new_name(name)
        self._loads.append(load)

    def add_wrench(self, name: str, target, wrench, law: _Law = Constant(1.0),
                   frame: str = "world", point=(0.0, 0.0, 0.0)) -> None:
        """An applied wrench law(t) * (tau [N m], f [N]) on ``target`` (a Frame or Body), in
        ``frame`` "world" or "body" axes, applied at ``point`` (body coordinates [m])."""
        load = self._wrench_entry(name, target, wrench, law, frame, point)
        self._new_name(name)
        self._loads.append(load)

    def _wrench_entry(self, name, target, wrench, law, frame, point, what=None) -> dict:
        """The load row of add_wrench, validated, not yet added."""
        what = what or f"wrench {name!r}"
        self._check_name(name)
        f = _frame_of(target, self, f"{what}, argument target")
        if f.carrier < 0:
            raise ModelError(f"{what}: cannot load the ground")
        _choice(f"{what}: frame", frame, ("world", "body"))
        w = array(f"{what}: wrench", wrench, (6,), "6 finite numbers (tau [N m], f [N])")
        p = array(f"{what}: point", point, (3,), "3 finite numbers [m]")
        law = _law_tuple(law, f"{what}: law")
        # the offset of a frame on its carrier moves the point of application
        pt = f.T[:3, :3] @ p + f.T[:3, 3]
        if frame == "body":
            R = f.T[:3, :3]
            w = np.concatenate([R @ w[:3], R @ w[3:]])
        return dict(name=name, carrier=f.carrier, world=frame == "world", point=pt, w=w, law=law,
                    reaction=-1)

    def add_distributed_load(self, name: str, link: FlexibleLink, force_per_length,
                             law: _Law = Constant(1.0), frame: str = "world") -> None:
        """Distributed force [N/m] on a link, lumped on its nodes (h/2 at the ends, h inside)."""
        self._check_name(name)
        if not isinstance(link, FlexibleLink) or self._links.get(link.name) != link:
            raise ModelError(f"distributed load {name!r}: link must be a flexible link of this "
                             f"mechanism (links: {', '.join(map(repr, self._links)) or 'none'}), "
                             f"got {link!r}")
        q = array(f"distributed load {name!r}: force_per_length", force_per_length, (3,),
                  "3 finite numbers [N/m]")
        h = link.length / link.elements
        loads = []
        for k, c in enumerate(link.nodes):
            share = h if 0 < k < link.elements else h / 2
            loads.append(self._wrench_entry(f"{name}[{k}]", Frame(c, np.eye(4)),
                                            np.concatenate([np.zeros(3), q * share]), law, frame,
                                            (0.0, 0.0, 0.0), f"distributed load {name!r}"))
        for ld in loads:   # all validated: add them all
            self._new_name(ld["name"])
            self._loads.append(ld)

    # -------------------------------------------------------------- core model
    # -------------------------------------------------------------- graphs, initial configuration
    def _vertex(self, carrier: int, inner: dict) -> str:
        if carrier < 0:
            return "0"
        for b in self._bodies.values():
            if b.carrier == carrier:
                return b.name
        for lk in self._links.values():
            if carrier in lk.nodes:
                k = lk.nodes.index(carrier)
                if k == 0:
                    return lk.name + "L"
                if k == lk.elements:
                    return lk.name + "R"
                lab = f"{lk.name}[{k}]"
                if (k, lab) not in inner.setdefault(lk.name, []):
                    inner[lk.name].append((k, lab))
                return lab
        raise ModelError(f"carrier {carrier} belongs to no body or link")

    def graphs(self) -> Graphs:
        """G_B, G_K, G_F, G_I and the incidence matrices B_K,r, B_K,f, B_I,r, B_I,f with row and
        column labels (DESIGN.md §5). A pair or interaction added between a and b, in that order,
        is the edge (a, b): -1 at row a, +1 at row b."""
        inner: dict = {}
        g = MechanismGraph(rigid=list(self._bodies), flexible=list(self._links), inner=inner)
        for e in self._pairs:
            g.pairs.append((e["name"], self._vertex(e["a"], inner), self._vertex(e["b"], inner)))
        for ld in self._loads:
            if ld.get("interaction"):
                g.interactions.append((ld["name"], self._vertex(ld["carrier"], inner),
                                       self._vertex(ld["reaction"], inner)))
        for q in self._springs:
            g.interactions.append((q["name"], self._vertex(q["a"], inner), self._vertex(q["b"], inner)))
        return Graphs(g, g.incidence_pairs(), g.incidence_interactions())

    def _loops_through(self, pairs: list) -> list:
        loops = self.graphs().loops()
        hit = [lp for lp in loops if set(lp) & set(pairs)]
        return hit or loops

    def _initial(self):
        """Tree placement, loop closure and redundancy (see phmech.topology): returns poses,
        twists, the pairs' x0 rows and drop masks; sets ``redundant_constraints`` and
        ``initial_adjustments`` (warns or, if ``strict``, raises on moves beyond tolerance).
        Overflow in these steps (given lengths, positions, x0 or rates beyond what double
        precision can square) is a ModelError, never a NaN passed on."""
        try:
            with np.errstate(over="raise", invalid="raise"):
                return self._initial_steps()
        except FloatingPointError as e:
            raise ModelError(f"initial configuration: {e} while placing the carriers and closing "
                             f"the loops: the model's lengths, positions, x0 or xdot0 are beyond "
                             f"what double precision can handle") from None

    def _initial_steps(self):
        H, T, tree = topology.place_tree(self)
        x0 = np.array([p["x0"] for p in self._pairs]).reshape(-1, 6)
        adjustments = []
        if self._pairs:
            model = self._core_model(H, T, x0, None, ())
            H_tree = H.copy()
            H = topology.close_loops(self, model, H, tree, None, self._loops_through)
            T, rates = topology.close_rates(self, model, H, T, tree, None)
            # joint coordinates reached (on the branch of x0): the core checks x0 at the start
            x = _core.model_joints(model, H, None)
            lay = _core.model_sizes(model)[4]
            adjustments = self._adjustments(H_tree, H, x, lay, rates)
            for ip, e in enumerate(self._pairs):
                _, _, j, k = lay[ip]
                if e["has_x0"] and k:
                    x0[ip, :k] = x[j:j + k]
            _, G, _ = _core.model_constraints_full(model, H, None, 0.0)
            masks, dropped = topology.redundant_rows(self, G, tree)
        else:
            masks, dropped = [], []
        self.redundant_constraints = dropped
        self.initial_adjustments = adjustments
        self._drop_masks = masks
        moved = [a for a in adjustments if a.exceeds]
        if moved:
            msg = ("initial configuration: closing the loops moved given initial values beyond "
                   "their tolerance: " + "; ".join(str(a) for a in moved) +
                   ". Give consistent x0, xdot0 and poses; Mechanism.initial_adjustments lists every "
                   "given value and how far it moved")
            if self.strict:
                raise ModelError(msg + " (Mechanism(strict=True))")
            if self._warned_initial != msg:
                self._warned_initial = msg
                warnings.warn(msg, InitialValueWarning, stacklevel=3)
        if dropped and self._warned != dropped:
            self._warned = list(dropped)
            warnings.warn(f"hyperconstrained mechanism: {len(dropped)} redundant constraint "
                          f"directions left out of the DAE (pair, direction in F_b): {dropped}",
                          RedundantConstraintWarning, stacklevel=3)
        return H, T, x0, masks

    def _adjustments(self, H_tree, H, x, lay, rates) -> list:
        """InitialAdjustment rows: every given x0 (xdot0) coordinate against the reached x
        (``rates``: joint row -> reached rate), and every given pose the tree placement kept
        against the closed poses H."""
        L = topology.length_scale(self)
        tol_m, tol_r = topology.POSE_TOL * L, topology.POSE_TOL
        rows = []
        for ip, e in enumerate(self._pairs):
            _, _, j, k = lay[ip]
            for c in range(k):
                unit = e["pair"]._units[c]
                for key, given, now, u in (("x0", "has_x0", x, unit), ("xdot0", "has_xdot0", rates, unit + "/s")):
                    if not e.get(given, False):
                        continue
                    g, reached = float(e[key][c]), float(now[j + c])
                    tol = tol_r * max(1.0, abs(g)) if unit == "rad" else tol_m * max(1.0, abs(g) / L)
                    q = "x" if key == "x0" else "xdot"
                    rows.append(InitialAdjustment(e["name"], q if k == 1 else f"{q}[{c}]", g,
                                                  reached, abs(reached - g), u, tol))

        def moves(Ha, Hb):
            return (float(np.linalg.norm(Hb[:3, 3] - Ha[:3, 3])),
                    topology._rot_angle(Ha[:3, :3].T @ Hb[:3, :3]))

        groups = [(b.name, [b.carrier]) for b in self._bodies.values()] + \
                 [(lk.name, list(lk.nodes)) for lk in self._links.values()]
        for name, cs in groups:
            if not all(c in self._given for c in cs):
                continue
            tree = [moves(self._given[c], H_tree[c]) for c in cs]
            if max(d for d, _ in tree) > tol_m or max(a for _, a in tree) > tol_r:
                continue   # placed by an x0 up the tree: its pose is not the given one by request
            now = [moves(self._given[c], H[c]) for c in cs]
            rows.append(InitialAdjustment(name, "position", None, None, max(d for d, _ in now), "m", tol_m))
            rows.append(InitialAdjustment(name, "orientation", None, None, max(a for _, a in now), "rad", tol_r))
        return rows

    def initial_configuration(self) -> InitialConfiguration:
        """The initial configuration the analyses start from (tree placement from the given
        poses and x0, loop closure; see docs/user_guide.md): poses, twists, the
        InitialAdjustment table (also left in ``initial_adjustments``) and the redundant
        constraints. Warns (InitialValueWarning) or, with ``strict``, raises ModelError like
        the analyses when the loop closure moved a given value beyond its tolerance."""
        if not self._car:
            raise ModelError("the mechanism is empty")
        H, T, _, _ = self._initial()
        return InitialConfiguration(H, T, list(self.initial_adjustments), list(self.redundant_constraints))

    def _build(self, extra_loads=()):
        if not self._car:
            raise ModelError("the mechanism is empty")
        H, T, x0, masks = self._initial()
        return self._core_model(H, T, x0, masks, extra_loads)

    def _core_model(self, H, T, x0, masks, extra_loads):
        car, el, pr, ac, sp = self._car, self._el, self._pairs, self._acts, self._springs
        loads = list(self._loads) + list(extra_loads)

        def world(c_, p_):
            return p_ if c_ < 0 else H[c_][:3, :3] @ p_ + H[c_][:3, 3]
        with np.errstate(over="ignore", invalid="ignore"):   # checked below
            kcd = [(q["kcd"][0], q["kcd"][1], np.linalg.norm(world(q["b"], q["pb"]) - world(q["a"], q["pa"]))
                    if q["kcd"][2] is None else q["kcd"][2]) for q in sp]
        for q, (_, _, d0) in zip(sp, kcd):
            if not np.isfinite(d0):
                raise ModelError(f"spring {q['name']!r}: the initial distance between its points "
                                 f"(its default rest length) is not finite in double precision")
        return _core.model_new(
            M=np.array([c["M"] for c in car]), mass=np.array([c["mass"] for c in car]),
            com=np.array([c["com"] for c in car]), H0=np.asarray(H),
            t0=np.asarray(T),
            el_ab=np.array([[e["a"], e["b"]] for e in el], dtype=float).reshape(-1, 2),
            el_h=np.array([e["h"] for e in el], dtype=float),
            el_K=np.array([e["K"] for e in el]).reshape(-1, 6, 6),
            el_D=np.array([e["D"] for e in el]).reshape(-1, 6, 6),
            el_eps=np.array([e["eps"] for e in el]).reshape(-1, 6),
            pr_type=np.array([p["type"] for p in pr], dtype=float),
            pr_ab=np.array([[p["a"], p["b"]] for p in pr], dtype=float).reshape(-1, 2),
            pr_Ta=np.array([p.get("Ta_eff", p["Ta"]) for p in pr]).reshape(-1, 4, 4),
            pr_Tb=np.array([p["Tb"] for p in pr]).reshape(-1, 4, 4),
            pr_driven=np.array([float(p["driven"]) for p in pr]),
            pr_axis=np.array([p["axis"] for p in pr]).reshape(-1, 6),
            pr_law=[p["law"] for p in pr],
            ld_carrier=np.array([l["carrier"] for l in loads], dtype=float),
            ld_world=np.array([float(l["world"]) for l in loads]),
            ld_point=np.array([l["point"] for l in loads]).reshape(-1, 3),
            ld_w=np.array([l["w"] for l in loads]).reshape(-1, 6),
            ld_law=[l["law"] for l in loads],
            gravity=self.gravity,
            pr_pitch=np.array([p["pitch"] for p in pr], dtype=float),
            pr_x0=np.asarray(x0, dtype=float).reshape(-1, 6),
            pr_drop=None if masks is None else np.array(masks, dtype=float),
            pr_has_x0=np.array([float(p["has_x0"]) for p in pr]),
            ld_reaction=np.array([l.get("reaction", -1) for l in loads], dtype=float),
            ac_pair=np.array([a["pair"] for a in ac], dtype=float),
            ac_kind=np.array([a["kind"] for a in ac], dtype=float),
            ac_vec=np.array([a["vec"] for a in ac]).reshape(-1, 6),
            ac_kp=np.array([a["kp"] for a in ac]).reshape(-1, 6),
            ac_kd=np.array([a["kd"] for a in ac]).reshape(-1, 6),
            ac_xset=np.array([a["xset"] for a in ac]).reshape(-1, 6),
            ac_law=[a["law"] for a in ac],
            sp_ab=np.array([[q["a"], q["b"]] for q in sp], dtype=float).reshape(-1, 2),
            sp_pa=np.array([q["pa"] for q in sp]).reshape(-1, 3),
            sp_pb=np.array([q["pb"] for q in sp]).reshape(-1, 3),
            sp_kcd=np.array(kcd, dtype=float).reshape(-1, 3))

    # -------------------------------------------------------------- analyses
    def simulate(self, t_end: float, dt_out: float, rtol: Optional[float] = None,
                 atol: Optional[float] = None, linear_solver: str = "auto",
                 initial: Optional[StaticResult] = None, t_start: float = 0.0,
                 callback: Optional[Callable[[float, int], bool]] = None, max_step: float = 0.0,
                 max_order: Optional[int] = None, record=None, progress: bool = False,
                 error_test: str = "all", integrator: str = "generalized-alpha",
                 step: Optional[float] = None, rho_inf: Optional[float] = None,
                 band: Optional[float] = None) -> SimulationResult:
        """Integrate from ``t_start`` to ``t_end`` [s], sampling every ``dt_out`` [s].

        The defaults are meant to be right and fast; ``simulate(t_end, dt_out)`` is the intended
        call. The default integrator is the generalized-alpha method with step-size control: its
        local error estimate covers the configuration (poses, joint coordinates) and its steps
        resolve the frequency ``band`` [Hz] (default: 1/(2 dt_out), the highest frequency the
        output can show); vibrations above the band (the axial and shear modes of a flexible
        link's mesh, kHz to MHz) are damped by the method's numerical dissipation instead of being
        resolved (spectral radius at infinity ``rho_inf`` = 0.9 by default), so no step goes
        below 1/(20 band) for accuracy's sake. ``rtol`` (default 1e-4)
        and ``atol`` [m, rad; default rtol * 1e-2] are its local error tolerances. Pass a larger
        ``band=`` to see faster vibrations than dt_out shows, or a smaller one to save time.
        docs/integrators.md says what the default does, what it was measured against, and when
        to change it.

        ``initial``: start from these poses (e.g. a StaticResult) at rest instead of the
        modelled initial state. ``callback(t, i)`` is called at each output; return True to
        stop. Ctrl-C, or SIGTERM (a batch system's time limit), stops the run and returns what
        was computed (``interrupted`` = True). A solver failure raises ``phmech.SolverError``
        whose ``result`` attribute holds the trajectory computed up to the failure. ``record``:
        bodies, links (all their nodes) or frames whose poses and twists are stored (default:
        every carrier); energies, joints and ports are always stored. ``progress``: a progress
        line on stderr (simulated time, elapsed, ETA, steps and steps per second). A
        ``phmech.CostWarning`` is issued when the steps are far smaller than the band needs and
        the run is on course to take long (it says why and what to do).

        Limits: both integrators take at most 10^6 steps between two output times (a run whose
        ``max_step``, ``step`` or ``band`` already implies more raises ModelError at once, any
        other SolverError), and the outputs may take at most half the machine's memory. No
        result holds a NaN or inf: a non-finite value (the model's numbers overflowing double
        precision) raises SolverError with the finite part of the trajectory.

        ``result.stats`` reports what the run cost and how good it is: steps, evaluations, wall
        time, ``band`` [Hz], ``error_estimate`` (adaptive generalized-alpha: the sum of the local
        error estimates of the configuration, a bound without error propagation), ``floor_steps``
        (steps accepted at the band's smallest step with their estimate above the tolerance:
        motion above the band), ``energy_scale`` [J], ``ledger_relative`` (largest |energy
        ledger residual| / energy_scale) and ``numerical_dissipation`` [J] (energy the
        integrator removed, from the ledger).

        Other integrators (docs/integrators.md):

        - ``integrator="generalized-alpha", step=h``: fixed step ``h`` [s] (no error estimate;
          ``rtol``/``atol``, default 1e-8 and rtol * 1e-2, are then its Newton tolerances).
          ``rho_inf`` in [0, 1] (default 0.9) is the spectral
          radius at infinity: 1 has no numerical dissipation (then stiff vibrations a step does not resolve
          are not damped and Newton may converge badly), smaller values damp what the step does
          not resolve. Steps are shortened evenly to land on the output times and the breakpoints
          of the time laws; after the start and each breakpoint a failing first step is redone as
          one backward-Euler step.
        - ``integrator="ida"``: SUNDIALS IDA, variable-order BDF with local error control on
          ``rtol`` (default 1e-8) and ``atol``. ``error_test="all"`` (default) puts every
          differential state in the error test, so the step resolves every vibration present,
          however fast (accurate and energy-consistent, and costly when flexible links are
          excited: minutes to hours where the default takes seconds). ``"configuration"``
          leaves the twists out and needs ``max_order`` <= 2 (default 5 with "all", 2 with
          "configuration"). ``max_step`` [s] bounds the steps (IDA and adaptive
          generalized-alpha).

        ``linear_solver``: ``"auto"`` (KLU sparse for 6 or more carriers, else dense),
        ``"dense"`` or ``"klu"``."""
        t0, t1, dt = (real("t_start", t_start), real("t_end", t_end), real("dt_out", dt_out))
        if t1 <= t0:
            raise ModelError(f"t_end must be > t_start (got {t1} <= {t0})")
        if dt <= 0:
            raise ModelError(f"dt_out must be > 0 (got {dt})")
        solvers = {"dense": 0, "klu": 1}
        if isinstance(linear_solver, str) and linear_solver == "auto":
            linear_solver = "klu" if len(self._car) >= 6 else "dense"
        if not isinstance(linear_solver, str) or linear_solver not in solvers:
            raise ModelError(f"unknown linear_solver {linear_solver!r} (available: 'auto', 'dense', 'klu')")
        integrators = {"ida": 0, "generalized-alpha": 1}
        if not isinstance(integrator, str) or integrator not in integrators:
            raise ModelError(f"unknown integrator {integrator!r} (available: {', '.join(map(repr, integrators))})")
        adaptive = integrator == "generalized-alpha" and step is None
        band = 0.5 / dt if band is None else positive("band", band)
        if integrator == "generalized-alpha":
            if step is not None:
                step = positive("step", step)
            rho_inf = DEFAULT_RHO_INF if rho_inf is None else real("rho_inf", rho_inf)
            if not 0.0 <= rho_inf <= 1.0:
                raise ModelError(f"rho_inf must be in [0, 1] (got {rho_inf})")
            if not (isinstance(error_test, str) and error_test == "all") or max_order is not None:
                raise ModelError("error_test and max_order apply to integrator='ida' only")
            if max_step is not None and not (isinstance(max_step, (int, float)) and max_step == 0) \
                    and not adaptive:
                raise ModelError("max_step applies to integrator='ida' and to the adaptive "
                                 "generalized-alpha (without step=)")
        elif step is not None:
            raise ModelError("step= applies to integrator='generalized-alpha' (IDA chooses its own steps; "
                             "use max_step to bound them)")
        tests = {"all": 0, "configuration": 1}
        if not isinstance(error_test, str) or error_test not in tests:
            raise ModelError(f"unknown error_test {error_test!r} (available: 'all', 'configuration')")
        if max_order is None:
            max_order = 2 if error_test == "configuration" else 5
        if isinstance(max_order, (bool, np.bool_)) or not isinstance(max_order, (int, np.integer)) or not 1 <= max_order <= 5:
            raise ModelError(f"max_order must be an integer 1..5 (got {max_order!r})")
        if error_test == "configuration" and max_order > 2:
            raise ModelError(f"error_test='configuration' needs max_order 1 or 2 (got {max_order}): "
                             "without the twists in the error test, BDF orders 3-5 let unresolved "
                             "vibrations grow")
        max_step = 0.0 if max_step is None or (isinstance(max_step, (int, float)) and max_step == 0) \
            else positive("max_step", max_step)
        # the integrators stop after MAX_STEPS steps between two outputs: fail now, not then
        h = min([x for x in (max_step, step, 1.0 / (_run.BAND_MAX_STEPS * band) if adaptive else 0.0)
                 if x and x > 0] or [np.inf])
        if dt / h > MAX_STEPS:
            raise ModelError(f"simulate: steps of at most {h:.3g} s (" +
                             ("max_step" if h == max_step else "step" if h == step else
                              f"the {band:.4g} Hz band") +
                             f") would take {dt / h:.3g} steps per output interval dt_out = {dt:g} s; "
                             f"the integrators stop at {MAX_STEPS:.0e} steps between two outputs: "
                             f"use a smaller dt_out, or longer steps")
        rtol = (DEFAULT_RTOL if adaptive else 1e-8) if rtol is None else real("rtol", rtol)
        atol = rtol * 1e-2 if atol is None else real("atol", atol)
        if rtol <= 0 or atol <= 0:
            raise ModelError("rtol and atol must be > 0")
        if callback is not None and not callable(callback):
            raise ModelError(f"callback must be a function callback(t, i) or None (got {callback!r})")
        if initial is not None and not isinstance(initial, StaticResult):
            raise ModelError(f"initial must be a StaticResult (Mechanism.static) or None (got "
                             f"{type(initial).__name__})")
        with np.errstate(over="ignore"):
            span = (t1 - t0) / dt
        self._check_outputs(span, record)
        n = int(np.floor(span + 1e-9))
        tout = t0 + dt * np.arange(n + 1)
        if tout[-1] < t1 - 1e-12 * max(1.0, abs(t1)):
            tout = np.append(tout, t1)
        rec = None if record is None else self._record_carriers(record)
        model = self._build()   # finds the redundant constraints
        if rec is not None and self.redundant_constraints:
            raise ModelError("record= cannot be combined with redundant constraints yet: the "
                             "minimum-norm multipliers need every carrier's pose")
        poses = None if initial is None else self._start_poses(initial, "initial")
        twists = None if initial is None else np.zeros((len(self._car), 6))
        monitor = _run.RunMonitor(t0, t1, band, integrator, progress, callback)
        with _run.sigterm_as_interrupt(monitor):
            r = _core.model_simulate(model, tout, rtol, atol, solvers[linear_solver], poses, twists,
                                     monitor.on_output, float(max_step), int(max_order), rec,
                                     tests[error_test], integrators[integrator], float(step or 0.0),
                                     float(1.0 if rho_inf is None else rho_inf), adaptive=int(adaptive),
                                     band=float(band if adaptive else 0.0), monitor=monitor)
        monitor.finish(r["stats"]["steps"])
        k = r["nout"]
        e = r["energy"][:k]
        energy = {nm: e[:, i].copy() for i, nm in enumerate(ENERGY_NAMES)}
        names = [a["name"] for a in self._acts] + [l["name"] for l in self._loads] + \
            [q["name"] for q in self._springs]
        ports = {nm: r["ports"][:k, i].copy() for i, nm in enumerate(names)}
        layout = _core.model_sizes(model)[4]
        lam, pw = r["lambda"][:k], r["pair_wrenches"][:k]
        if self.redundant_constraints and k > 0:
            lam, pw, layout = self._min_norm_multipliers(model, r["poses"][:k], r["joints"][:k], lam, tout[:k])
        pairs = {p["name"]: dict(index=i, layout=layout[i]) for i, p in enumerate(self._pairs)}
        stats = {**r["stats"], "linear_solver": linear_solver, "integrator": integrator,
                 "adaptive": adaptive, "rtol": rtol, "atol": atol,
                 **_run.quality(energy, band)}
        if not adaptive:
            del stats["error_estimate"], stats["floor_steps"]
        result = SimulationResult(t=tout[:k], poses=r["poses"][:k], twists=r["twists"][:k],
                                  constraint_wrenches=lam, energy=energy, stats=stats,
                                  interrupted=bool(r["interrupted"]) or monitor.terminated,
                                  _links=self._links, port_energy=ports, joints=r["joints"][:k],
                                  joint_rates=r["jrates"][:k], efforts=r["efforts"][:k],
                                  pair_wrenches=pw, _pairs=pairs,
                                  redundant_constraints=list(self.redundant_constraints),
                                  carriers=None if rec is None else np.array(rec),
                                  _frame=lambda x: _frame_of(x, self, "result"),
                                  _inertia=np.array([c["M"] for c in self._car], dtype=float),
                                  _mass=np.array([c["mass"] for c in self._car], dtype=float),
                                  _com=np.array([c["com"] for c in self._car], dtype=float),
                                  _bodies=dict(self._bodies))
        if r["error"]:
            t_last = f"{result.t[-1]:.6g} s" if k else "the start"
            err = SolverError(f"{r['error']} (the trajectory up to {t_last} is in this error's "
                              f"'result' attribute)")
            err.result = result
            raise err
        return result

    def _check_outputs(self, span: float, record) -> None:
        """ModelError when (t_end - t_start) / dt_out output times would take more than half the
        machine's memory (an accidental t_end / dt_out of 1e10 would otherwise allocate 75 GB,
        or fail inside NumPy)."""
        nc = len(self._car)
        # per output: pose and twist of each recorded carrier; per pair at most 6 multipliers, 6
        # pair wrench entries, 6 joint coordinates, rates and efforts; 7 energies; the ports; t
        per = 8 * (22 * nc + 30 * len(self._pairs) + 7 + len(self._acts) + len(self._loads)
                   + len(self._springs) + 1)
        if record is not None:
            per = max(8 * 30, per - 8 * 22 * (nc - 1))   # at least one carrier recorded
        try:
            limit = 0.5 * os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
        except (AttributeError, ValueError, OSError):
            limit = 8e9
        if not (span * per <= limit):
            raise ModelError(f"simulate: (t_end - t_start) / dt_out = {span:.3g} output times would "
                             f"take about {span * per / 1e9:.3g} GB, more than half this machine's "
                             f"memory ({2 * limit / 1e9:.3g} GB); use a larger dt_out, a shorter run "
                             f"or record= fewer carriers")

    def _start_poses(self, start, what) -> np.ndarray:
        """The poses of a StaticResult used as a starting point, checked against this mechanism."""
        if not isinstance(start, StaticResult):
            raise ModelError(f"{what} must be a StaticResult (Mechanism.static) or None (got "
                             f"{type(start).__name__})")
        return array(f"{what}.poses", start.poses, (len(self._car), 4, 4),
                     f"finite poses of this mechanism's {len(self._car)} carriers, shape "
                     f"({len(self._car)}, 4, 4)")

    def _record_carriers(self, record) -> list:
        """Carrier indices for simulate(record=...): bodies, links, frames or their names."""
        if isinstance(record, (str, FlexibleLink, Body, Frame)):
            items = [record]
        elif isinstance(record, (list, tuple)):
            items = list(record)
        else:
            raise ModelError(f"record: expected a body, link, frame, a name, or a list of them "
                             f"(got {type(record).__name__})")
        out = []
        for x in items:
            if isinstance(x, str) and x in self._links:
                x = self._links[x]
            if isinstance(x, FlexibleLink):
                if self._links.get(x.name) != x:
                    raise ModelError(f"record: link {x.name!r} is not a link of this mechanism")
                out += [c for c in x.nodes if c not in out]
                continue
            c = _frame_of(x, self, "record").carrier
            if c < 0:
                raise ModelError("record: the ground has no recorded pose")
            if c not in out:
                out.append(c)
        if not out:
            raise ModelError("record: nothing to record")
        return out

    def _full_layout(self):
        lay, row, j = [], 0, 0
        for e in self._pairs:
            m = len(topology.DIRECTIONS[e["type"]])
            lay.append((row, m, j, 6 - m))
            row += m
            j += 6 - m
        return lay

    def _min_norm_multipliers(self, model, poses, joints, lam, times):
        """Hyperconstrained mechanisms: the DAE's multipliers (independent rows only) mapped to
        the minimum-norm multipliers of ALL rows giving the same generalized constraint forces,
        lambda_full = argmin |l| s.t. G_full^T l = G_kept^T lambda; pair wrenches W^C lambda_full."""
        full = self._full_layout()
        keep = []
        for ip, e in enumerate(self._pairs):
            row, m, _, _ = full[ip]
            keep += [row + r for r in range(m) if not (self._drop_masks[ip] >> r) & 1]
        nf = full[-1][0] + full[-1][1] if full else 0
        lam_f = np.zeros((len(poses), nf))
        pw = np.zeros((len(poses), len(self._pairs), 6))
        for i in range(len(poses)):
            _, G, W = _core.model_constraints_full(model, poses[i], joints[i], float(times[i]))
            f = G[keep].T @ lam[i]
            lam_f[i] = np.linalg.lstsq(G.T, f, rcond=None)[0]
            for ip in range(len(self._pairs)):
                row, m, _, _ = full[ip]
                pw[i, ip] = W[ip][:, :m] @ lam_f[i, row:row + m]
        return lam_f, pw, full

    def stress_resultants(self, result: "SimulationResult", link: Union[str, FlexibleLink]) -> np.ndarray:
        """Section stress resultants of each element of ``link`` along a simulation, shape
        (nt, elements, 6): sigma = K (eps - eps_hat) + D eps_dot in the element's own frame, in
        the strain order (torsion, bending y, bending z [N m], axial, shear y, shear z [N]);
        eps = log(H_k^-1 H_k+1) / h and h eps_dot = dexp_{-X}^-1 t_k+1 - dexp_X^-1 t_k, the
        same constant-strain element the core integrates (DESIGN.md section 4)."""
        lk = self._link("stress_resultants", link)
        if not isinstance(result, SimulationResult):
            raise ModelError(f"stress_resultants: result must be a SimulationResult (got "
                             f"{type(result).__name__})")
        cols = result._columns(lk.nodes)
        H, T = result.poses[:, cols], result.twists[:, cols]
        els = [e for e in self._el if e["a"] in lk.nodes]
        K = np.array([e["K"] for e in els])
        D = np.array([e["D"] for e in els])
        eps_hat = np.array([e["eps"] for e in els])
        h = np.array([e["h"] for e in els])[:, None]
        X = se3.log(se3.compose(se3.inverse(H[:, :-1]), H[:, 1:]))         # (nt, N, 6)
        rate = (np.einsum("...ij,...j->...i", se3.dexp_inv(-X), T[:, 1:])
                - np.einsum("...ij,...j->...i", se3.dexp_inv(X), T[:, :-1])) / h
        return (np.einsum("kij,tkj->tki", K, X / h - eps_hat)
                + np.einsum("kij,tkj->tki", D, rate))

    def _link(self, what, link) -> FlexibleLink:
        """A link of this mechanism given by itself or its name."""
        lk = self._links.get(link) if isinstance(link, str) else link
        if not isinstance(lk, FlexibleLink) or self._links.get(lk.name) != lk:
            raise ModelError(f"{what}: expected a flexible link of this mechanism or its name "
                             f"(links: {', '.join(map(repr, self._links)) or 'none'}), got {link!r}")
        return lk

    def constraint_residuals(self, result: "SimulationResult") -> dict:
        """Position and velocity constraint residuals of EVERY pair row (redundant rows included)
        along a simulation: ``position`` (nt,) max |g(H)| [rad or m], ``velocity`` (nt,) max |G t|
        [rad/s or m/s] (prescribed rates of driven pairs subtracted)."""
        if not isinstance(result, SimulationResult):
            raise ModelError(f"constraint_residuals: result must be a SimulationResult (got "
                             f"{type(result).__name__})")
        if result.carriers is not None:
            raise ModelError("constraint_residuals needs every carrier's pose: simulate without record=")
        model = self._build()
        nt = len(result.t)
        pos, vel = np.zeros(nt), np.zeros(nt)
        for i in range(nt):
            g, G, _ = _core.model_constraints_full(model, result.poses[i], result.joints[i], float(result.t[i]))
            gv = G @ result.twists[i].ravel()
            if any(e["driven"] for e in self._pairs):   # subtract the prescribed rates by differencing g
                dt = 1e-7
                g2 = _core.model_constraints_full(model, result.poses[i], result.joints[i], float(result.t[i]) + dt)[0]
                gv = gv + (g2 - g) / dt
            pos[i] = np.max(np.abs(g)) if g.size else 0.0
            vel[i] = np.max(np.abs(gv)) if gv.size else 0.0
        return dict(position=pos, velocity=vel)

    def modes(self, n: int = 5, at: Optional[StaticResult] = None, time: float = 0.0) -> ModesResult:
        """The ``n`` lowest linearized modes at the initial configuration, or at a static
        equilibrium ``at`` (its constraint wrenches give the geometric stiffness)."""
        n = integer("n", n, 1)
        time = real("time", time)
        if at is not None and not isinstance(at, StaticResult):
            raise ModelError(f"at must be a StaticResult (Mechanism.static) or None (got "
                             f"{type(at).__name__})")
        model = self._build()
        poses = None if at is None else self._start_poses(at, "at")
        lam = None if at is None else array("at.constraint_wrenches", at.constraint_wrenches,
                                            np.shape(at.constraint_wrenches))
        # at most 6 per carrier exist: asking for more allocates no more than that
        om, ze, sh, nf = _core.model_modes(model, min(n, 6 * len(self._car)), poses, lam, time)
        return ModesResult(om[:nf], om[:nf] / (2 * np.pi), ze[:nf], sh[:nf])

    def static(self, loads: Sequence = (), steps: int = 10, time: float = 0.0,
               tol: float = 1e-10, start: Optional[StaticResult] = None) -> StaticResult:
        """Static equilibrium under gravity, the mechanism's wrenches at ``time`` and extra
        constant ``loads`` = [(target, wrench (tau, f), frame "world"|"body"), ...], reached in
        ``steps`` load steps (halved on failure); Newton tolerance ``tol`` on the tangent step."""
        extra = []
        if not isinstance(loads, (list, tuple)):
            raise ModelError(f"static loads: expected a list of (target, wrench, frame) tuples "
                             f"(got {type(loads).__name__})")
        for i, ld in enumerate(loads):
            if not isinstance(ld, (list, tuple)) or len(ld) != 3:
                raise ModelError(f"static load {i}: expected a (target, wrench, frame) tuple "
                                 f"(got {ld!r})")
            target, wrench, frame = ld
            f = _frame_of(target, self, f"static load {i}, target")
            if f.carrier < 0:
                raise ModelError(f"static load {i}: cannot load the ground")
            _choice(f"static load {i}: frame", frame, ("world", "body"))
            w = array(f"static load {i}: wrench", wrench, (6,), "6 finite numbers (tau [N m], f [N])")
            if frame == "body":
                R = f.T[:3, :3]
                w = np.concatenate([R @ w[:3], R @ w[3:]])
            extra.append(dict(carrier=f.carrier, world=frame == "world", point=f.T[:3, 3], w=w,
                              law=Constant(1.0)._tuple()))
        steps = min(integer("steps", steps, 1), 2 ** 31 - 1)
        time, tol = real("time", time), positive("tol", tol)
        poses = None if start is None else self._start_poses(start, "start")
        model = self._build(extra)
        P, lam, it = _core.model_static(model, poses, time, steps, tol)
        return StaticResult(P, lam, it, self._links)

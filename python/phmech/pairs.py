"""Kinematic pairs: one table of pair types (``PAIR_TYPES``) and the classes made from it.

Each row of the table says everything Python needs about a type of the C core's pair table
(csrc/model/pair.c, ``pair_table``; phm_pair_type_info in csrc/include/phmech_types.h): its type
code, its parameters (the fields of its class), the unit of each joint coordinate (their number
is k), the names of its constraint directions (the columns of W^C, m = 6 - k of them), whether
it can be driven, its docstring, its forward kinematics h(x) and the joint coordinates of a
relative pose. The classes Fixed, Revolute, ... are generated from the rows, so adding a pair type
on the Python side is adding a row. The rows mirror the core's table, which the extension exports
(``_core.pair_types``, with ``pair_pose`` and ``pair_coordinates`` for the kinematics): a row can
be made from it instead of written here.

Conventions (C core, phm_pair_type): the joint axis is the local z of both pair frames
F_a = H_a T_a and F_b = H_b T_b; relative pose h = F_a^-1 F_b. A pair with an ``axis`` (or
``normal``) orients z along it by rotating both frames by the same rotation Q (T <- T [Q, 0; 0, 1]).
"""
from __future__ import annotations

import dataclasses
from typing import Callable

import numpy as np

from . import se3
from ._checks import array, real
from ._core import ModelError

__all__ = ["Fixed", "Revolute", "Prismatic", "Helical", "Cylindrical", "Universal", "Spherical",
           "Planar", "Free"]


# ------------------------------------------------------------------ axes and frames
def _unit(v, what: str) -> np.ndarray:
    """A unit 3-vector from "x", "y", "z" or a finite nonzero 3-vector."""
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


def _cardan_rotation(axis1, axis2) -> np.ndarray:
    """Universal pair: the rotation whose x is ``axis1`` and y ``axis2`` (perpendicular)."""
    a, b = _unit(axis1, "Universal axis1"), _unit(axis2, "Universal axis2")
    if abs(a @ b) > 1e-9:
        raise ModelError("Universal: axis1 and axis2 must be perpendicular")
    return np.column_stack([a, b, np.cross(a, b)])


# ------------------------------------------------------------------ kinematics of the types
def _twist(*v) -> np.ndarray:
    return np.array(v, dtype=float)


def _angle_z(h) -> float:
    """Angle [rad] of a relative pose's rotation about z, in (-pi, pi]."""
    return float(np.arctan2(h[1, 0], h[0, 0]))


def _rotation_vector(h) -> np.ndarray:
    return np.asarray(se3.log(np.ascontiguousarray(h[:3, :3])), dtype=float)


def _helical_angle(h, pitch: float) -> np.ndarray:
    a = _angle_z(h)
    if pitch != 0:   # the turn whose translation pitch * angle is nearest to h's
        with np.errstate(over="ignore"):
            turn = a + 2 * np.pi * np.round((h[2, 3] / pitch - a) / (2 * np.pi))
        # ... unless that angle is beyond 1e15 rad, where a double no longer tells one turn
        # from the next (a pitch of 1e-244 m/rad picked 1e226 turns out of round-off in the
        # translation); the pose check then reports what the pair cannot reach
        if abs(turn) <= 1e15:
            a = turn
    return np.array([a])


def _planar_pose(x, pitch) -> np.ndarray:
    H = se3.exp(_twist(0, 0, x[0], 0, 0, 0))
    H[0, 3], H[1, 3] = x[1], x[2]
    return H


def _free_pose(x, pitch) -> np.ndarray:
    H = se3.exp(_twist(x[0], x[1], x[2], 0, 0, 0))
    H[:3, 3] = x[3:6]
    return H


# ------------------------------------------------------------------ THE table
@dataclasses.dataclass(frozen=True)
class PairType:
    """One pair type of the core (csrc/model/pair.c).

    ``code``: its phm_pair_type value. ``name``: its class's name. ``parameters``: (field, type,
    default) of its class. ``units``: "rad" or "m" for each joint coordinate (k of them).
    ``directions``: the names of the constraint-wrench directions W^C in F_b (6 - k), the order
    of the constraint rows. ``drivable``: its relative motion can be prescribed (Motion).
    ``doc``: the class's docstring. ``fk(x, pitch)``: the relative pose h(x) of the pair frames
    (4x4; pitch [m/rad]). ``coords(h, pitch)``: the joint coordinates x (k,) of a relative pose h
    (the inverse of fk on the allowed motions; the part of h the type cannot produce is
    fk(x)^-1 h)."""
    code: int
    name: str
    parameters: tuple
    units: tuple
    directions: tuple
    drivable: bool
    doc: str
    fk: Callable[[np.ndarray, float], np.ndarray]
    coords: Callable[[np.ndarray, float], np.ndarray]

    @property
    def k(self) -> int:
        """Number of joint coordinates (allowed directions)."""
        return len(self.units)


_AXIS = (("axis", object, "z"),)

PAIR_TYPES = (
    PairType(0, "Fixed", (), (), ("tau_x", "tau_y", "tau_z", "f_x", "f_y", "f_z"), True,
             "Fixed (welded) pair: 6 constraints, relative pose = identity (or the driven motion).",
             lambda x, p: np.eye(4), lambda h, p: np.zeros(0)),
    PairType(1, "Revolute", _AXIS, ("rad",), ("tau_x", "tau_y", "f_x", "f_y", "f_z"), False,
             "Revolute pair about ``axis`` (of both pair frames); x = angle [rad], multi-turn.",
             lambda x, p: se3.exp(_twist(0, 0, x[0], 0, 0, 0)), lambda h, p: np.array([_angle_z(h)])),
    PairType(2, "Prismatic", _AXIS, ("m",), ("tau_x", "tau_y", "tau_z", "f_x", "f_y"), False,
             "Prismatic pair along ``axis``; x = displacement [m].",
             lambda x, p: se3.exp(_twist(0, 0, 0, 0, 0, x[0])), lambda h, p: np.array([h[2, 3]])),
    PairType(3, "Helical", _AXIS + (("pitch", float, 0.0),), ("rad",),
             ("tau_x", "tau_y", "f_x", "f_y", "f_z-pitch*tau_z"), False,
             "Helical (screw) pair about ``axis``: translation = ``pitch`` [m/rad] x angle; "
             "x = angle.",
             lambda x, p: se3.exp(_twist(0, 0, x[0], 0, 0, p * x[0])), _helical_angle),
    PairType(4, "Cylindrical", _AXIS, ("rad", "m"), ("tau_x", "tau_y", "f_x", "f_y"), False,
             "Cylindrical pair along ``axis``; x = (angle [rad], displacement [m]).",
             lambda x, p: se3.exp(_twist(0, 0, x[0], 0, 0, x[1])),
             lambda h, p: np.array([_angle_z(h), h[2, 3]])),
    PairType(5, "Universal", (("axis1", object, "x"), ("axis2", object, "y")), ("rad", "rad"),
             ("tau_n", "f_x", "f_y", "f_z"), False,   # tau_n: the torque about axis1 x axis2
             "Universal (Cardan) pair: first axis ``axis1`` fixed in F_a, second ``axis2`` fixed "
             "in F_b\n    (perpendicular when both frames coincide); x = (angle about axis1, angle "
             "about axis2) [rad],\n    h = Rx(x0) Ry(x1) in the pair frames (x = axis1, y = axis2).",
             lambda x, p: se3.exp(_twist(x[0], 0, 0, 0, 0, 0)) @ se3.exp(_twist(0, x[1], 0, 0, 0, 0)),
             lambda h, p: np.array([np.arctan2(h[2, 1], h[1, 1]), np.arctan2(h[0, 2], h[0, 0])])),
    PairType(6, "Spherical", (), ("rad",) * 3, ("f_x", "f_y", "f_z"), False,
             "Spherical (ball) pair; x = rotation vector of F_b in F_a [rad], xdot = angular "
             "velocity\n    (in F_b) -- a quasi-velocity, not dx/dt.",
             lambda x, p: se3.exp(_twist(x[0], x[1], x[2], 0, 0, 0)), lambda h, p: _rotation_vector(h)),
    PairType(7, "Planar", (("normal", object, "z"),), ("rad", "m", "m"), ("tau_x", "tau_y", "f_z"),
             False,
             "Planar pair with plane ``normal``; x = (angle [rad], p_x, p_y [m]) with p the "
             "position of\n    F_b's origin in F_a (x, y of the frame whose z is the normal).",
             _planar_pose, lambda h, p: np.array([_angle_z(h), h[0, 3], h[1, 3]])),
    PairType(8, "Free", (), ("rad",) * 3 + ("m",) * 3, (), False,
             "Free pair (no constraint): x = (rotation vector, position of F_b in F_a); xdot = "
             "(angular\n    velocity in F_b, dp/dt in F_a). Useful to measure or actuate a "
             "relative motion.",
             _free_pose, lambda h, p: np.concatenate([_rotation_vector(h), h[:3, 3]])),
)

#: Names of the constraint-wrench directions W^C of each pair type, by type code, in the pair
#: frame F_b whose z axis is the joint axis (Universal: x = axis1, y = axis2).
DIRECTIONS = {t.code: t.directions for t in PAIR_TYPES}


# ------------------------------------------------------------------ the classes
class _Pair:
    """A kinematic pair of one of the PAIR_TYPES (its class attribute ``_type``)."""
    _type: PairType

    def _rotation(self) -> np.ndarray:
        """The rotation Q that turns both pair frames so that z is the joint axis."""
        fields = {f.name for f in dataclasses.fields(self)}
        if "axis1" in fields:
            return _cardan_rotation(self.axis1, self.axis2)
        for name in ("axis", "normal"):
            if name in fields:
                return _axis_rotation(getattr(self, name), self._type.name)
        return np.eye(3)

    def _pitch(self) -> float:
        """Translation per rotation [m/rad] (Helical), else 0."""
        return real("Helical pitch", self.pitch) if hasattr(self, "pitch") else 0.0

    def _fk(self, x) -> np.ndarray:
        """Relative pose h(x) of the pair frames at joint coordinates x."""
        return self._type.fk(x, self._pitch())

    def _coords(self, h) -> np.ndarray:
        """Joint coordinates x of a relative pose h of the pair frames (the inverse of _fk on
        the pair's allowed motions; the part of h it cannot produce is fk(x)^-1 h)."""
        return self._type.coords(h, self._pitch())


def _pair_class(t: PairType) -> type:
    """The frozen dataclass of pair type ``t``: its parameters are its fields; ``_code``, ``k``
    and ``_units`` are class attributes."""
    cls = dataclasses.make_dataclass(
        t.name, [(name, kind, dataclasses.field(default=default)) for name, kind, default in t.parameters],
        bases=(_Pair,), frozen=True,
        namespace=dict(__doc__=t.doc, _type=t, _code=t.code, k=t.k, _units=t.units))
    cls.__module__ = __name__
    return cls


Fixed, Revolute, Prismatic, Helical, Cylindrical, Universal, Spherical, Planar, Free = \
    (_pair_class(t) for t in PAIR_TYPES)
assert [c.__name__ for c in (Fixed, Revolute, Prismatic, Helical, Cylindrical, Universal, Spherical,
                             Planar, Free)] == [t.name for t in PAIR_TYPES]

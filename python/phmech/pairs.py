"""Kinematic pairs: the classes Fixed, Revolute, ... made from the core's pair table.

The core's table (csrc/model/pair_types.c, the only place where pair types are defined; exported as
``_core.pair_types()``) gives every type's code, parameters, joint-coordinate units, constraint
directions, whether it can be driven and its docstring; ``PAIR_TYPES`` holds those rows and a
class is generated for each, with the kinematics h(x) and x(h) taken from the core
(``_core.pair_pose``, ``_core.pair_coordinates``). Adding a pair type in C adds its class here.

Conventions (C core): the joint axis is the local z of both pair frames F_a = H_a T_a and
F_b = H_b T_b; relative pose h = F_a^-1 F_b. A pair with an ``axis`` (or ``normal``) orients z
along it by rotating both frames by the same rotation Q (T <- T [Q, 0; 0, 1]); a pair with
``axis1``/``axis2`` (Universal) makes them x and y.
"""
from __future__ import annotations

import dataclasses
import numpy as np

from . import _codes
from ._checks import array, real
from ._errors import ModelError


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


# ------------------------------------------------------------------ THE table (from the core)
@dataclasses.dataclass(frozen=True)
class PairType:
    """One pair type of the core's pair table (csrc/model/pair_types.c, exported as
    ``_core.pair_types()``).

    ``code``: its type code. ``name``: its class's name. ``parameters``: (field, type, default)
    of its class. ``units``: "rad" or "m" for each joint coordinate (k of them). ``directions``:
    the names of the constraint-wrench directions W^C in F_b (6 - k), the order of the constraint
    rows. ``drivable``: its relative motion can be prescribed (Motion). ``xdrivable``: for each
    joint coordinate, whether it can follow a time law (add_pair(driven=...)). ``doc``: the
    class's docstring."""
    code: int
    name: str
    parameters: tuple
    units: tuple
    directions: tuple
    drivable: bool
    xdrivable: tuple
    doc: str

    @property
    def k(self) -> int:
        """Number of joint coordinates (allowed directions)."""
        return len(self.units)

    def fk(self, x, pitch: float) -> np.ndarray:
        """The relative pose h(x) of the pair frames (4x4) at joint coordinates x (pitch [m/rad])."""
        return _codes.pair_pose(self.code, pitch, np.asarray(x, dtype=float)[:self.k])

    def coords(self, h, pitch: float) -> np.ndarray:
        """The joint coordinates x (k,) of a relative pose h: the inverse of fk on the allowed
        motions (the part of h the type cannot produce is fk(x)^-1 h); principal angles (a
        helical pair: the turn nearest to h's translation)."""
        return _codes.pair_coordinates(self.code, pitch, np.ascontiguousarray(h, dtype=float))


def _parameters(spec: str) -> tuple:
    """(field, type, default) of "axis=z,pitch=0": an axis is a name or a 3-vector, a number a float."""
    out = []
    for item in filter(None, spec.split(",")):
        name, default = item.split("=")
        try:
            out.append((name, float, float(default)))
        except ValueError:
            out.append((name, object, default))
    return tuple(out)


PAIR_TYPES = tuple(
    PairType(row["code"], row["name"].capitalize(), _parameters(row["params"]), tuple(row["units"]),
             tuple(row["directions"]), bool(row["drivable"]),
             tuple(bool(row["xdrivable"] >> c & 1) for c in range(row["k"])), row["doc"])
    for row in _codes.pair_types())

#: Names of the constraint-wrench directions W^C of each pair type, by type code, in the pair
#: frame F_b whose z axis is the joint axis (Universal: x = axis1, y = axis2).
DIRECTIONS = {t.code: t.directions for t in PAIR_TYPES}


def row_names(e: dict) -> tuple:
    """The names of the constraint rows of a pair's description row ``e`` (type, xlaws), in
    the core's order: its type's W^C directions, then one "drive x[c]" ("drive x" for a pair
    with one coordinate) per joint coordinate that follows a law."""
    xl = e.get("xlaws") or ()
    k = len(xl)
    return tuple(DIRECTIONS[e["type"]]) + tuple(
        "drive x" if k == 1 else f"drive x[{c}]" for c, lw in enumerate(xl) if lw is not None)

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


# every type of the core's table becomes a class of this module: a new pair type in
# csrc/model/pair_types.c needs no Python change (docs/architecture.md, "Adding a pair type")
globals().update({t.name: _pair_class(t) for t in PAIR_TYPES})
__all__ = [t.name for t in PAIR_TYPES]

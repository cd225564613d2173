"""Time laws s(t): the scalar factors of applied wrenches, prescribed motions, driven joint
coordinates and actuators.

Laws are evaluated in the C core (csrc/util/law.c; phm_law in csrc/include/phmech_types.h):
value and first two time derivatives, which drivers need. A law is one of the classes here:
the built-in shapes (Constant, Step, Pulse, Sine, Table, Cycloidal, Linear), smooth piecewise
polynomials (Spline, a C2 cubic spline through samples; PiecewisePolynomial), compositions
(``a + b``, ``a - b``, ``a * b``, ``2.0 * a``, ``-a``, ``a.shifted(dt)``: Sum, Product, flattened
into one postfix expression that the core evaluates without allocating), or a Python function of
t (Function; a plain function given as a law is wrapped in one): the core then calls back into
Python, with the GIL, at every evaluation -- see Function for the cost. ``phmech._marshal`` hands
laws to the core. Times in s; a law's value carries the unit of whatever it scales (rad or m
for a motion or a driven joint coordinate, N or N m for a load).

Every class is a frozen dataclass whose fields are its constructor arguments, so a law is plain
data: ``law.to_data()`` gives a dict of them (nested laws as dicts, a Function's callables by
their importable names) and ``law_from_data`` rebuilds the law.

The algebra every law shares (the base class, composition, Constant, Sum, Product, Function and
the core's law tuples) is in ``_lawbase.py``; this module adds the shapes, the piecewise
polynomials and ``law_from_data``. A new law is a frozen dataclass here with ``_checked``,
``shifted`` and ``_core_leaf`` (its core form), named in ``_CLASSES`` and ``__all__``."""
from __future__ import annotations

import dataclasses
import importlib
from typing import Sequence

import numpy as np

from ._checks import real, real_numbers
from ._errors import ModelError
from ._lawbase import _NO, Constant, Function, Product, Sum, _Law, checked_law, core_tuple

__all__ = ["Constant", "Step", "Pulse", "Sine", "Table", "Cycloidal", "Linear", "Trapezoidal",
           "Spline", "PiecewisePolynomial", "Sum", "Product", "Function", "Motion", "law_from_data"]

# (_Law, checked_law and core_tuple: the builder's modules and _marshal import them from here)


def law_from_data(data: dict) -> _Law:
    """The law of ``data`` (from ``_Law.to_data``); ModelError for anything else."""
    if not isinstance(data, dict) or data.get("law") not in _CLASSES:
        raise ModelError(f"law_from_data: expected a dict with 'law' one of {sorted(_CLASSES)} (got {data!r})")
    cls = _CLASSES[data["law"]]
    kw = {k: v for k, v in data.items() if k != "law"}
    if cls in (Sum, Product):
        kw = {k: tuple(law_from_data(x) for x in v) for k, v in kw.items()}
    if cls is Function:
        kw = {k: (_import(v) if k in ("fn", "derivative", "second_derivative") and v is not None else v)
              for k, v in kw.items()}
    try:
        return cls(**kw)
    except TypeError as e:
        raise ModelError(f"law_from_data: {data['law']}: {e}") from None


def _import(name: str):
    """The object named "module:qualified.name"."""
    if not isinstance(name, str) or ":" not in name:
        raise ModelError(f"law_from_data: a Function's callable must be named 'module:name' (got {name!r})")
    mod, qual = name.split(":", 1)
    obj = importlib.import_module(mod)
    for part in qual.split("."):
        obj = getattr(obj, part)
    return obj


def _positive_duration(kind: str, duration) -> float:
    d = real(f"{kind} duration", duration)
    if d <= 0:
        raise ModelError(f"{kind} duration must be > 0 (got {d} s)")
    return d


@dataclasses.dataclass(frozen=True)
class Step(_Law):
    """s(t) = value for t >= t0 [s], else 0."""
    t0: float = 0.0
    value: float = 1.0

    def _checked(self) -> "Step":
        value = real("Step value", self.value)
        return Step(real("Step t0", self.t0), value)

    def start_value(self) -> float:
        return self.value if 0.0 >= self.t0 else 0.0

    def shifted(self, dt: float) -> "Step":
        return Step(self.t0 + real("shift", dt), self.value)

    def _core_leaf(self) -> tuple:
        return "step", (self.value, self.t0, 0.0, 0.0, 0.0, 0.0), None, 0


@dataclasses.dataclass(frozen=True)
class Pulse(_Law):
    """Rectangular pulse ('impulse'): s(t) = value for t0 <= t < t0 + duration [s], else 0.
    Its impulse is value * duration."""
    t0: float = 0.0
    duration: float = 1e-3
    value: float = 1.0

    def _checked(self) -> "Pulse":
        d = _positive_duration("Pulse", self.duration)
        value = real("Pulse value", self.value)
        return Pulse(real("Pulse t0", self.t0), d, value)

    def start_value(self) -> float:
        return self.value if self.t0 <= 0.0 < self.t0 + self.duration else 0.0

    def shifted(self, dt: float) -> "Pulse":
        return Pulse(self.t0 + real("shift", dt), self.duration, self.value)

    def _core_leaf(self) -> tuple:
        return "pulse", (self.value, self.t0, self.duration, 0.0, 0.0, 0.0), None, 0


@dataclasses.dataclass(frozen=True)
class Sine(_Law):
    """s(t) = offset + amplitude * sin(2 pi frequency t + phase); frequency in Hz, phase in rad."""
    amplitude: float = 1.0
    frequency: float = 1.0
    phase: float = 0.0
    offset: float = 0.0

    def _checked(self) -> "Sine":
        return Sine(real("Sine amplitude", self.amplitude), real("Sine frequency", self.frequency),
                    real("Sine phase", self.phase), real("Sine offset", self.offset))

    def start_value(self) -> float:
        return self.offset + self.amplitude * np.sin(self.phase)

    def shifted(self, dt: float) -> "Sine":
        return Sine(self.amplitude, self.frequency,
                    self.phase - 2 * np.pi * self.frequency * real("shift", dt), self.offset)

    def _core_leaf(self) -> tuple:
        return "sine", (self.amplitude, 0.0, 0.0, self.frequency, self.phase, self.offset), None, 0


@dataclasses.dataclass(frozen=True)
class Table(_Law):
    """Piecewise linear through points (t_i [s], s_i), held constant outside."""
    times: Sequence[float]
    values: Sequence[float]

    def _checked(self) -> "Table":
        t = real_numbers("Table times", self.times)
        v = real_numbers("Table values", self.values)
        if t.size < 1 or t.size != v.size:
            raise ModelError(f"Table needs as many values as times, at least one (got {t.size} "
                             f"times and {v.size} values)")
        if not (np.all(np.isfinite(t)) and np.all(np.isfinite(v))):
            raise ModelError("Table entries must be finite")
        if np.any(np.diff(t) <= 0):
            raise ModelError("Table times must be strictly increasing")
        return Table(tuple(t.tolist()), tuple(v.tolist()))

    def start_value(self) -> float:
        return float(np.interp(0.0, self.times, self.values))

    def shifted(self, dt: float) -> "Table":
        return Table(tuple((np.asarray(self.times, dtype=float) + real("shift", dt)).tolist()), self.values)

    def _core_leaf(self) -> tuple:
        return "table", _NO, np.column_stack([self.times, self.values]).ravel(), 0


@dataclasses.dataclass(frozen=True)
class Cycloidal(_Law):
    """Smooth (C2) ramp from 0 to value over [t0, t0 + duration] [s]."""
    value: float = 1.0
    t0: float = 0.0
    duration: float = 1.0

    def _checked(self) -> "Cycloidal":
        d = _positive_duration("Cycloidal", self.duration)
        value = real("Cycloidal value", self.value)
        return Cycloidal(value, real("Cycloidal t0", self.t0), d)

    def start_value(self) -> float:
        if 0.0 <= self.t0:
            return 0.0
        u = min(1.0, (0.0 - self.t0) / self.duration)
        return self.value * (u - np.sin(2 * np.pi * u) / (2 * np.pi))

    def shifted(self, dt: float) -> "Cycloidal":
        return Cycloidal(self.value, self.t0 + real("shift", dt), self.duration)

    def _core_leaf(self) -> tuple:
        return "cycloidal", (self.value, self.t0, self.duration, 0.0, 0.0, 0.0), None, 0


@dataclasses.dataclass(frozen=True)
class Linear(_Law):
    """s(t) = offset + rate * t: a ramp without end (constant speed: the angle law
    Linear(omega) of a revolute turning at omega [rad/s])."""
    rate: float = 1.0
    offset: float = 0.0

    def _checked(self) -> "Linear":
        return Linear(real("Linear rate", self.rate), real("Linear offset", self.offset))

    def start_value(self) -> float:
        return self.offset

    def shifted(self, dt: float) -> "Linear":
        return Linear(self.rate, self.offset - self.rate * real("shift", dt))

    def _core_leaf(self) -> tuple:
        return "linear", (self.rate, 0.0, 0.0, 0.0, 0.0, self.offset), None, 0


def _increasing(name: str, t: np.ndarray, v: np.ndarray, least: int) -> None:
    """ModelError unless times t (finite, strictly increasing, at least ``least``) and values v
    (finite, as many) fit."""
    if t.ndim != 1 or t.size < least or v.shape[:1] != t.shape:
        raise ModelError(f"{name} needs as many values as times, at least {least} (got {t.size} "
                         f"times and {v.shape[0] if v.ndim else 0} values)")
    bad = np.flatnonzero(~np.isfinite(t))
    if bad.size:
        raise ModelError(f"{name} time {bad[0]} is not finite ({t[bad[0]]})")
    bad = np.flatnonzero(~np.all(np.isfinite(v.reshape(v.shape[0], -1)), axis=1))
    if bad.size:
        raise ModelError(f"{name} value {bad[0]} (at t = {t[bad[0]]:g} s) is not finite "
                         f"({v[bad[0]]})")
    bad = np.flatnonzero(np.diff(t) <= 0)
    if bad.size:
        i = bad[0]
        raise ModelError(f"{name} times must be strictly increasing: t[{i}] = {t[i]:g} s, "
                         f"t[{i + 1}] = {t[i + 1]:g} s")


@dataclasses.dataclass(frozen=True)
class PiecewisePolynomial(_Law):
    """Piecewise polynomial: on [breaks[i], breaks[i+1]) s(t) = sum_j coefficients[i][j]
    (t - breaks[i])^(order - 1 - j) (highest power first, as scipy.interpolate.PPoly's c.T);
    before the first break the first piece continues, after the last the last one. ``order``
    (coefficients per piece) at most 8. Breaks where s, s' or s'' jump are breakpoints of the
    integrators (consistent restart); where the law is C2 they are stepped across."""
    breaks: Sequence[float]
    coefficients: Sequence[Sequence[float]]

    def _checked(self) -> "PiecewisePolynomial":
        x = real_numbers("PiecewisePolynomial breaks", self.breaks)
        c = real_numbers("PiecewisePolynomial coefficients", self.coefficients)
        try:
            c = c.reshape(np.shape(self.coefficients))
        except ValueError:
            raise ModelError("PiecewisePolynomial coefficients must be an (n, order) array") from None
        if c.ndim != 2 or x.ndim != 1 or c.shape[0] + 1 != x.size or c.shape[0] < 1 or \
                not 1 <= c.shape[1] <= 8:
            raise ModelError(f"PiecewisePolynomial needs n + 1 breaks and coefficients of shape "
                             f"(n, order) with n >= 1 and order <= 8 (got {x.shape} breaks and "
                             f"{c.shape} coefficients)")
        _increasing("PiecewisePolynomial", x, np.zeros(x.size), 2)
        if not np.all(np.isfinite(c)):
            raise ModelError("PiecewisePolynomial coefficients must be finite")
        return PiecewisePolynomial(tuple(x.tolist()), tuple(map(tuple, c.tolist())))

    def shifted(self, dt: float) -> "PiecewisePolynomial":
        return PiecewisePolynomial(tuple((np.asarray(self.breaks, dtype=float) + real("shift", dt)).tolist()),
                                   self.coefficients)

    def antiderivative(self, at: float = None) -> "PiecewisePolynomial":
        """The integral of s, zero at time ``at`` [s] (default: the first break): e.g. a
        driven angle from a speed profile."""
        p = self._checked()
        x, c = np.asarray(p.breaks), np.asarray(p.coefficients)
        n, k = c.shape
        if k + 1 > 8:
            raise ModelError("PiecewisePolynomial.antiderivative: the order would exceed 8")
        ci = np.zeros((n, k + 1))
        ci[:, :k] = c / np.arange(k, 0, -1)
        h = np.diff(x)
        ends = np.array([np.polyval(ci[i], h[i]) for i in range(n)])
        ci[1:, k] = np.cumsum(ends[:-1])
        out = PiecewisePolynomial(tuple(x.tolist()), tuple(map(tuple, ci.tolist())))
        t0 = x[0] if at is None else real("antiderivative at", at)
        ci[:, k] -= float(out.derivatives(t0)[0])
        return PiecewisePolynomial(tuple(x.tolist()), tuple(map(tuple, ci.tolist())))

    def _core_leaf(self) -> tuple:
        return "ppoly", _NO, np.concatenate([np.asarray(self.breaks, dtype=float),
                                            np.asarray(self.coefficients, dtype=float).ravel()]), \
            len(self.coefficients[0])


_SPLINE_BCS = ("not-a-knot", "natural", "clamped")


@dataclasses.dataclass(frozen=True)
class Spline(_Law):
    """C2 cubic spline through (times [s], values), as scipy.interpolate.CubicSpline with
    ``bc_type`` = ``bc``: "not-a-knot" (default), "natural" (s'' = 0 at both ends), "clamped"
    (s' = 0 at both ends), or a pair (s'(t_0), s'(t_n)) of end slopes. Outside the samples
    ``extrapolate``: "linear" (the end value and slope continue: C2 for a natural spline, a jump
    of s'' at the ends otherwise, which the integrators treat as a breakpoint) or "cubic" (the
    end pieces continue, as CubicSpline). Evaluated in the core as a PiecewisePolynomial: no
    breakpoint inside the samples, so the integrators step across them (unlike a dense Table,
    whose every point is a restart)."""
    times: Sequence[float]
    values: Sequence[float]
    bc: object = "not-a-knot"
    extrapolate: str = "linear"

    def _checked(self) -> "Spline":
        t = real_numbers("Spline times", self.times)
        v = real_numbers("Spline values", self.values)
        _increasing("Spline", t, v, 2)
        if v.ndim != 1:
            raise ModelError(f"Spline values must be one number per time (got shape {v.shape})")
        bc = self.bc
        if isinstance(bc, str):
            if bc not in _SPLINE_BCS:
                raise ModelError(f"Spline bc must be one of {_SPLINE_BCS} or a pair of end slopes (got {bc!r})")
        else:
            try:
                d = [real("Spline end slope", x) for x in bc]
            except TypeError:
                raise ModelError(f"Spline bc must be one of {_SPLINE_BCS} or a pair of end slopes "
                                 f"(got {bc!r})") from None
            if len(d) != 2:
                raise ModelError(f"Spline bc: a pair of end slopes (got {len(d)} numbers)")
            bc = tuple(d)
        if self.extrapolate not in ("linear", "cubic"):
            raise ModelError(f"Spline extrapolate must be 'linear' or 'cubic' (got {self.extrapolate!r})")
        return Spline(tuple(t.tolist()), tuple(v.tolist()), bc, self.extrapolate)

    def shifted(self, dt: float) -> "Spline":
        return Spline(tuple((np.asarray(self.times, dtype=float) + real("shift", dt)).tolist()),
                      self.values, self.bc, self.extrapolate)

    def _coefficients(self) -> np.ndarray:
        """(n, 4) cubic coefficients of the n pieces between the samples (highest power first),
        from the second derivatives m_i: h_{i-1} m_{i-1} + 2 (h_{i-1} + h_i) m_i + h_i m_{i+1} =
        6 (slope_i - slope_{i-1}) inside, the end conditions at the ends (a banded solve)."""
        from scipy.linalg import solve_banded
        x, y = np.asarray(self.times, dtype=float), np.asarray(self.values, dtype=float)
        n = x.size - 1
        h = np.diff(x)
        sl = np.diff(y) / h
        bc = self.bc
        if n == 1 and bc == "not-a-knot":
            bc = "natural"   # two points: the straight line (as CubicSpline)
        if n == 2 and bc == "not-a-knot":   # three points: the parabola through them
            m = np.full(3, 2 * (sl[1] - sl[0]) / (x[2] - x[0]))
        else:
            ab = np.zeros((5, n + 1))   # solve_banded's layout for (l, u) = (2, 2)
            r = np.zeros(n + 1)

            def put(i, j, v):
                ab[2 + i - j, j] = v
            for i in range(1, n):
                put(i, i - 1, h[i - 1])
                put(i, i, 2 * (h[i - 1] + h[i]))
                put(i, i + 1, h[i])
                r[i] = 6 * (sl[i] - sl[i - 1])
            if bc == "natural":
                put(0, 0, 1.0)
                put(n, n, 1.0)
            elif bc == "not-a-knot":   # third derivative continuous at t_1 and t_{n-1}
                put(0, 0, h[1])
                put(0, 1, -(h[0] + h[1]))
                put(0, 2, h[0])
                put(n, n - 2, h[n - 1])
                put(n, n - 1, -(h[n - 2] + h[n - 1]))
                put(n, n, h[n - 2])
            else:
                d0, dn = (0.0, 0.0) if bc == "clamped" else bc
                put(0, 0, 2 * h[0])
                put(0, 1, h[0])
                r[0] = 6 * (sl[0] - d0)
                put(n, n - 1, h[n - 1])
                put(n, n, 2 * h[n - 1])
                r[n] = 6 * (dn - sl[n - 1])
            m = solve_banded((2, 2), ab, r)
        c = np.empty((n, 4))
        c[:, 0] = (m[1:] - m[:-1]) / (6 * h)
        c[:, 1] = m[:-1] / 2
        c[:, 2] = sl - h * (2 * m[:-1] + m[1:]) / 6
        c[:, 3] = y[:-1]
        return c

    def piecewise(self) -> PiecewisePolynomial:
        """The spline as the PiecewisePolynomial the core evaluates (with the pieces outside the
        samples that ``extrapolate`` asks for)."""
        p = self._checked()
        x, y = np.asarray(p.times, dtype=float), np.asarray(p.values, dtype=float)
        c = p._coefficients()
        if p.extrapolate == "cubic":
            return PiecewisePolynomial(tuple(x.tolist()), tuple(map(tuple, c.tolist())))
        L = x[-1] - x[0]
        h = x[-1] - x[-2]
        d0 = c[0, 2]
        dn = (3 * c[-1, 0] * h + 2 * c[-1, 1]) * h + c[-1, 2]
        left = [0.0, 0.0, d0, y[0] - d0 * L]     # s = y_0 + d0 (t - t_0), about t_0 - L
        right = [0.0, 0.0, dn, y[-1]]
        xs = np.concatenate([[x[0] - L], x, [x[-1] + L]])
        cs = np.vstack([left, c, right])
        return PiecewisePolynomial(tuple(xs.tolist()), tuple(map(tuple, cs.tolist())))

    def antiderivative(self, at: float = None) -> PiecewisePolynomial:
        """The integral of the spline, zero at ``at`` [s] (default: the first sample time): the
        angle law of a speed profile given as a spline."""
        t0 = self._checked().times[0] if at is None else at
        return self.piecewise().antiderivative(t0)

    def _core_leaf(self) -> tuple:
        return self.piecewise()._core_leaf()


@dataclasses.dataclass(frozen=True)
class Trapezoidal(_Law):
    """Rest-to-rest move by ``distance`` from t0 [s] with a trapezoidal velocity profile: constant
    acceleration ``max_acceleration`` up to ``max_velocity``, a cruise at it, constant deceleration
    to rest. Units: those of what the law drives -- m, m/s, m/s^2 for a displacement, rad, rad/s,
    rad/s^2 for an angle. Too short a move to reach ``max_velocity`` is a triangular profile (peak
    velocity sqrt(abs(distance) max_acceleration)). s = 0 before t0 and ``distance`` after the move
    (``duration()`` [s] long); s and s' are continuous, s'' jumps at the start and end of each
    ramp, where the integrators restart (breakpoints). A negative distance moves backwards.
    Evaluated in the core as its PiecewisePolynomial (``piecewise()``)."""
    distance: float = 1.0
    max_velocity: float = 1.0
    max_acceleration: float = 1.0
    t0: float = 0.0

    def _checked(self) -> "Trapezoidal":
        d = real("Trapezoidal distance", self.distance)
        v, a = real("Trapezoidal max_velocity", self.max_velocity), real("Trapezoidal max_acceleration",
                                                                            self.max_acceleration)
        if not (v > 0 and a > 0):
            raise ModelError(f"Trapezoidal max_velocity and max_acceleration must be > 0 (got {v}, {a})")
        return Trapezoidal(d, v, a, real("Trapezoidal t0", self.t0))

    def shifted(self, dt: float) -> "Trapezoidal":
        return dataclasses.replace(self, t0=self.t0 + real("shift", dt))

    def phases(self) -> tuple:
        """(ramp, cruise): how long each of the two ramps and the cruise last [s] (cruise 0 for a
        triangular profile)."""
        p = self._checked()
        dist, v, a = abs(p.distance), p.max_velocity, p.max_acceleration
        if dist * a >= v * v:
            return v / a, dist / v - v / a
        return (dist / a) ** 0.5, 0.0

    def duration(self) -> float:
        """How long the move lasts [s]: two ramps and the cruise."""
        ramp, cruise = self.phases()
        return 2 * ramp + cruise

    def piecewise(self) -> PiecewisePolynomial:
        """The move as the PiecewisePolynomial the core evaluates: rest, ramp up, cruise (when
        there is one), ramp down, rest (the first and last pieces continue outside)."""
        p = self._checked()
        ramp, cruise = p.phases()
        a = p.max_acceleration if p.distance >= 0 else -p.max_acceleration
        if ramp == 0.0:   # no move
            return PiecewisePolynomial((p.t0, p.t0 + 1.0), ((0.0,),))
        vp, s1 = a * ramp, 0.5 * a * ramp * ramp   # the peak velocity, the distance of a ramp
        t1, t2 = p.t0 + ramp, p.t0 + ramp + cruise
        breaks, coefficients = [p.t0 - 1.0, p.t0, t1], [(0.0, 0.0, 0.0), (0.5 * a, 0.0, 0.0)]
        if t1 < t2 < t2 + ramp:
            breaks.append(t2)
            coefficients.append((0.0, vp, s1))
        end = breaks[-1] + ramp
        breaks += [end, end + 1.0]
        coefficients += [(-0.5 * a, vp, p.distance - s1), (0.0, 0.0, p.distance)]
        return PiecewisePolynomial(tuple(breaks), tuple(coefficients))

    def _core_leaf(self) -> tuple:
        return self.piecewise()._core_leaf()


@dataclasses.dataclass(frozen=True)
class Motion:
    """Prescribed relative motion of a driven Fixed pair: r(t) = exp(law(t) * axis), axis a
    twist (omega, v) in the pair's frame on b, e.g. (0,0,1,0,0,0) with an angle law [rad], or
    (0,0,0,0,1,0) with a displacement law [m]. Pairs with joint coordinates are driven by laws
    of their coordinates instead (Mechanism.add_pair(driven=law))."""
    axis: Sequence[float]
    law: _Law


_CLASSES = {c.__name__: c for c in (Constant, Step, Pulse, Sine, Table, Cycloidal, Linear, Trapezoidal,
                                    Spline, PiecewisePolynomial, Sum, Product, Function)}

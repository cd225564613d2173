"""Time laws s(t): the scalar factors of applied wrenches, prescribed motions and actuators.

Laws are evaluated in the C core (csrc/util/law.c; phm_law in csrc/include/phmech_types.h), so a
law is one of the classes here, never a Python function; ``phmech._marshal`` hands them to the
core. Times in s; a law's value
carries the unit of whatever it scales (rad or m for a Motion, N or N m for a load)."""
from __future__ import annotations

import dataclasses
from typing import Sequence

import numpy as np

from ._checks import real, real_numbers
from ._core import ModelError

__all__ = ["Constant", "Step", "Pulse", "Sine", "Table", "Cycloidal", "Motion"]

_LAW_NAMES = "Constant, Step, Pulse, Sine, Table or Cycloidal"


class _Law:
    """A time law. ``_checked`` returns the law with every parameter validated and converted to
    float (ModelError otherwise); ``start_value`` is s(0)."""

    def _checked(self) -> "_Law":
        raise NotImplementedError

    def start_value(self) -> float:
        """s(0), in the unit of what the law scales."""
        raise NotImplementedError


def checked_law(law, what: str, numbers_too: bool = False) -> _Law:
    """``law`` validated (a copy with float parameters, see _Law); a clear ModelError for
    anything else (a plain Python function cannot be a law: laws are evaluated in C, see
    csrc/util/law.c). ``numbers_too``: a number c also stands for Constant(c)."""
    if isinstance(law, _Law):
        return law._checked()
    if numbers_too and isinstance(law, (int, float, np.integer, np.floating)) and not isinstance(law, bool):
        return Constant(real(what, law))._checked()
    accepted = f"a time law ({_LAW_NAMES}{', or a number' if numbers_too else ''})"
    if callable(law):
        fname = getattr(law, "__name__", type(law).__name__)
        raise ModelError(f"{what}: got the Python function {fname!r}, expected {accepted}; laws are "
                         "evaluated in the C core, so a Python function cannot be one: tabulate it "
                         "with Table(times, values)")
    raise ModelError(f"{what}: expected {accepted} (got {type(law).__name__})")


def _positive_duration(kind: str, duration) -> float:
    d = real(f"{kind} duration", duration)
    if d <= 0:
        raise ModelError(f"{kind} duration must be > 0 (got {d} s)")
    return d


@dataclasses.dataclass(frozen=True)
class Constant(_Law):
    """s(t) = value."""
    value: float = 1.0

    def _checked(self) -> "Constant":
        return Constant(real("Constant value", self.value))

    def start_value(self) -> float:
        return self.value


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


@dataclasses.dataclass(frozen=True)
class Motion:
    """Prescribed relative motion of a driven pair: r(t) = exp(law(t) * axis), axis a twist
    (omega, v) in the pair's frame on b, e.g. (0,0,1,0,0,0) with an angle law [rad], or
    (0,0,0,0,1,0) with a displacement law [m]."""
    axis: Sequence[float]
    law: _Law

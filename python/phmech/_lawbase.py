"""The algebra of time laws (python/phmech/laws.py holds the public classes and says what a law
is): the base class ``_Law`` (evaluation by the C core, composition by ``+``, ``-``, ``*``, plain
data), the laws composition makes (Constant, Sum, Product), a Python function of t as a law
(Function, and ``_FunctionCall``, what the core calls back), ``checked_law`` (what the builder
accepts as a law) and the core's law tuples (``core_tuple``: a leaf's from its ``_core_leaf``, a
Sum or Product as one postfix expression). Times in s; a law's value carries the unit of what it
scales."""
from __future__ import annotations

import dataclasses
import math
import numbers
from typing import Optional, Sequence

import numpy as np

from ._checks import real, real_numbers
from ._codes import LAW_KINDS, law_eval
from ._errors import ModelError

_NO = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0)   # the six scalar fields of a law that uses none of them

_LAW_NAMES = ("Constant, Step, Pulse, Sine, Table, Cycloidal, Linear, Spline, "
              "PiecewisePolynomial, Function, or a sum or product of them")


class _Law:
    """A time law. ``_checked`` returns the law with every parameter validated and converted to
    float (ModelError otherwise); ``start_value`` is s(0). Laws compose: ``a + b``, ``a - b``,
    ``a * b``, ``c * a`` (c a number), ``-a``, ``a.shifted(dt)`` (s(t - dt))."""

    def _checked(self) -> "_Law":
        raise NotImplementedError

    def start_value(self) -> float:
        """s(0), in the unit of what the law scales."""
        return float(self.derivatives(0.0)[0])

    def shifted(self, dt: float) -> "_Law":
        """The law delayed by ``dt`` [s]: t -> s(t - dt) (same class; parameters moved)."""
        raise NotImplementedError

    def _core_leaf(self) -> tuple:
        """The core's form of a leaf law (not a Sum, Product or Function): its phm_law_kind name
        (_codes.LAW_KINDS), its (amplitude, t0, duration, frequency, phase, offset) fields of
        phm_law, its data array (or None) and order (ppoly). A law the core has no kind for
        gives the form of the law it is evaluated as (Spline: its PiecewisePolynomial)."""
        raise NotImplementedError

    # ---- evaluation by the core (csrc/util/law.c)
    def derivatives(self, t) -> np.ndarray:
        """s, ds/dt, d2s/dt2 at times ``t`` [s], evaluated by the C core: shape t.shape + (3,).
        At a time where a piecewise law jumps, the piece that starts there."""
        tt = np.asarray(t, dtype=float)
        out = law_eval(core_tuple(self._checked()), tt.reshape(-1))
        return out.reshape(tt.shape + (3,))

    def evaluate(self, t):
        """s(t) at times ``t`` [s] (the core's evaluation), shape t.shape."""
        return self.derivatives(t)[..., 0]

    # ---- composition
    def __add__(self, other):
        return _composed(other, lambda o: Sum((self, o)))

    def __radd__(self, other):
        return _composed(other, lambda o: Sum((o, self)))

    def __sub__(self, other):
        return _composed(other, lambda o: Sum((self, Product((Constant(-1.0), o)))))

    def __rsub__(self, other):
        return _composed(other, lambda o: Sum((o, Product((Constant(-1.0), self)))))

    def __mul__(self, other):
        return _composed(other, lambda o: Product((self, o)))

    def __rmul__(self, other):
        return _composed(other, lambda o: Product((o, self)))

    def __neg__(self):
        return Product((Constant(-1.0), self))

    # ---- plain data
    def to_data(self) -> dict:
        """The law as plain data: {"law": class name, field: value, ...}; nested laws as dicts,
        arrays as lists. ``law_from_data`` inverts it."""
        out = {"law": type(self).__name__}
        for f in dataclasses.fields(self):
            out[f.name] = _plain(getattr(self, f.name))
        return out


def _plain(v):
    """A field value as plain data (see _Law.to_data)."""
    if isinstance(v, _Law):
        return v.to_data()
    if isinstance(v, (tuple, list)):
        return [_plain(x) for x in v]
    if isinstance(v, np.ndarray):
        return v.tolist()
    if isinstance(v, (np.floating, np.integer)):
        return v.item()
    return v


def _composed(other, make):
    """``make(o)`` with ``other`` as an operand ``o`` (_operand), or NotImplemented when it is
    not one (Python then tries the other side's operator)."""
    o = _operand(other)
    return NotImplemented if o is None else make(o)


def _operand(v):
    """A law, a real number as Constant, a Python function of t as Function, or None (not an
    operand)."""
    if isinstance(v, _Law):
        return v
    if isinstance(v, (numbers.Real, np.integer, np.floating)) and not isinstance(v, (bool, np.bool_)):
        return Constant(float(v))
    if callable(v) and not isinstance(v, type):
        return Function(v)
    return None


def checked_law(law, what: str, numbers_too: bool = False) -> _Law:
    """``law`` validated (a copy with float parameters, see _Law); a clear ModelError for
    anything else. A Python function of t becomes a Function law (evaluated by calls into
    Python: see Function). ``numbers_too``: a number c also stands for Constant(c)."""
    if isinstance(law, _Law):
        try:
            return law._checked()
        except ModelError as e:
            raise ModelError(f"{what}: {e}") from e.__cause__
    if numbers_too and isinstance(law, (int, float, np.integer, np.floating)) and not isinstance(law, bool):
        return Constant(real(what, law))._checked()
    if callable(law) and not isinstance(law, type):
        try:
            return Function(law)._checked()
        except ModelError as e:
            raise ModelError(f"{what}: {e}") from e.__cause__
    accepted = f"a time law ({_LAW_NAMES}{', or a number' if numbers_too else ''})"
    raise ModelError(f"{what}: expected {accepted} (got {type(law).__name__})")


@dataclasses.dataclass(frozen=True)
class Constant(_Law):
    """s(t) = value."""
    value: float = 1.0

    def _checked(self) -> "Constant":
        return Constant(real("Constant value", self.value))

    def start_value(self) -> float:
        return self.value

    def shifted(self, dt: float) -> "Constant":
        return self

    def _core_leaf(self) -> tuple:
        return "constant", (self.value, 0.0, 0.0, 0.0, 0.0, 0.0), None, 0


@dataclasses.dataclass(frozen=True)
class Sum(_Law):
    """s(t) = sum of the ``terms`` (laws or numbers); ``a + b`` makes one."""
    terms: Sequence[object]

    def _checked(self) -> "Sum":
        return Sum(_checked_operands("Sum", self.terms))

    def shifted(self, dt: float) -> "Sum":
        return Sum(tuple(t.shifted(dt) for t in _checked_operands("Sum", self.terms)))


@dataclasses.dataclass(frozen=True)
class Product(_Law):
    """s(t) = product of the ``factors`` (laws or numbers); ``a * b`` and ``2.0 * a`` make one.
    Derivatives by the Leibniz rule."""
    factors: Sequence[object]

    def _checked(self) -> "Product":
        return Product(_checked_operands("Product", self.factors))

    def shifted(self, dt: float) -> "Product":
        return Product(tuple(t.shifted(dt) for t in _checked_operands("Product", self.factors)))


def _checked_operands(kind: str, items) -> tuple:
    """The checked laws of a Sum or Product (numbers as Constant); at least one."""
    if isinstance(items, (_Law, str)) or not hasattr(items, "__iter__"):
        raise ModelError(f"{kind} takes a sequence of laws (got {type(items).__name__})")
    out = []
    for i, x in enumerate(items):
        o = _operand(x)
        if o is None:
            raise ModelError(f"{kind} operand {i}: expected a time law or a number (got {type(x).__name__})")
        out.append(o._checked())
    if not out:
        raise ModelError(f"{kind} needs at least one operand")
    return tuple(out)


def _callable_name(f) -> str:
    return getattr(f, "__name__", type(f).__name__)


@dataclasses.dataclass(frozen=True, eq=False)
class Function(_Law):
    """A Python function of time, s = fn(t - shift) [t in s], as a law. The core calls back into
    Python (taking the GIL) at every evaluation of the law: once per residual evaluation of the
    integrator (and per column group of its finite-difference Jacobian), about a microsecond
    each -- where a Spline or Table through samples of it costs nothing. A driven coordinate and
    a PD target also need s' and s'': ``derivative`` and ``second_derivative`` (functions of t)
    when given, else central differences of fn with step ``step`` [s] (two more calls; s' to
    ~1e-8 and s'' to ~1e-6 relative for a law that varies on a time scale of 1 s: give the
    derivatives when it varies faster; one-sided forward differences where fn raises or is not
    finite at t - step, e.g. sqrt(t) at t = 0). ``breakpoints``: times [s] where s, s' or s'' jump (the
    integrators stop and restart there). fn must return a finite real number: anything else, or
    an exception, stops the run and is raised as a ModelError naming the function and the time
    (its cause: the original exception). Plain data (to_data) when the callables are importable
    module-level functions."""
    fn: object
    derivative: object = None
    second_derivative: object = None
    breakpoints: Sequence[float] = ()
    shift: float = 0.0
    step: float = 1e-4

    def _checked(self) -> "Function":
        for name in ("fn", "derivative", "second_derivative"):
            f = getattr(self, name)
            if (f is not None or name == "fn") and (not callable(f) or isinstance(f, (type, _Law))):
                raise ModelError(f"Function {name}: expected a Python function of t (got {type(f).__name__})")
        bp = real_numbers("Function breakpoints", self.breakpoints).reshape(-1)
        if bp.size and (not np.all(np.isfinite(bp)) or np.any(np.diff(bp) <= 0)):
            raise ModelError("Function breakpoints must be finite and strictly increasing")
        step = real("Function step", self.step)
        if step <= 0:
            raise ModelError(f"Function step must be > 0 (got {step} s)")
        out = Function(self.fn, self.derivative, self.second_derivative, tuple(bp.tolist()),
                       real("Function shift", self.shift), step)
        call = _FunctionCall(out)
        given = out.derivative is not None or out.second_derivative is not None
        if call(0.0, 2 if given else 0) is None:   # one evaluation at t = 0 now: a bad
            raise call.error                      # function fails at add_*
        return out

    def shifted(self, dt: float) -> "Function":
        d = real("shift", dt)
        return dataclasses.replace(self, shift=self.shift + d,
                                   breakpoints=tuple(b + d for b in self.breakpoints))

    def to_data(self) -> dict:
        out = super().to_data()
        for name in ("fn", "derivative", "second_derivative"):
            f = getattr(self, name)
            if f is None:
                continue
            mod, qual = getattr(f, "__module__", None), getattr(f, "__qualname__", "")
            if not mod or "<" in qual:
                raise ModelError(f"Function {name} {_callable_name(f)!r} is not an importable "
                                 "module-level function: it cannot be saved as data")
            out[name] = f"{mod}:{qual}"
        return out


class _FunctionCall:
    """What the core calls for a Function law (csrc/pyext/py_laws.c, law_callback):
    ``(t, nder) -> (s, s', s'')``, or None when the function failed, the ModelError then kept in
    ``error`` (the binding raises it when the core returns; later calls fail at once)."""

    def __init__(self, law: Function):
        self.law = law
        self.error = None

    def _real(self, f, t, what):
        v = f(t - self.law.shift)
        if isinstance(v, np.ndarray) and v.ndim == 0:
            v = v[()]
        if not isinstance(v, (numbers.Real, np.integer, np.floating)) or isinstance(v, (bool, np.bool_)):
            raise ModelError(f"time law: the function {_callable_name(f)!r}{what} returned "
                             f"{type(v).__name__} {v!r} at t = {t:.9g} s, not a real number")
        v = float(v)
        if not math.isfinite(v):
            raise ModelError(f"time law: the function {_callable_name(f)!r}{what} returned {v} at "
                             f"t = {t:.9g} s")
        return v

    def __call__(self, t: float, nder: int):
        if self.error is not None:
            return None
        law = self.law
        try:
            s = self._real(law.fn, t, "")
            d1 = d2 = 0.0
            if nder >= 1:
                h = law.step
                if law.derivative is not None:
                    d1 = self._real(law.derivative, t, " (derivative)")
                if law.derivative is None or (nder >= 2 and law.second_derivative is None):
                    sp = self._real(law.fn, t + h, "")
                    try:   # central differences; one-sided forward ones where fn is not
                        with np.errstate(all="ignore"):   # defined before t (e.g. t < 0)
                            sm = law.fn(t - h - law.shift)
                        central = math.isfinite(float(sm))
                    except Exception:   # noqa: BLE001 -- then the forward differences
                        central = False
                    if central:
                        fd1, fd2 = (sp - float(sm)) / (2 * h), (sp - 2 * s + float(sm)) / (h * h)
                    else:
                        s2 = self._real(law.fn, t + 2 * h, "")
                        fd1, fd2 = (-3 * s + 4 * sp - s2) / (2 * h), (s - 2 * sp + s2) / (h * h)
                    if law.derivative is None:
                        d1 = fd1
                    if nder >= 2 and law.second_derivative is None:
                        d2 = fd2
                if nder >= 2 and law.second_derivative is not None:
                    d2 = self._real(law.second_derivative, t, " (second derivative)")
            return (s, d1, d2)
        except ModelError as e:
            self.error = e
        except Exception as e:   # noqa: BLE001 -- any error of the user's function is reported
            err = ModelError(f"time law: the function {_callable_name(law.fn)!r} raised "
                             f"{type(e).__name__} at t = {t:.9g} s: {e}")
            err.__cause__ = e
            self.error = err
        return None


# ---- the core's law tuples (csrc/pyext/py_laws.c, phm_py_parse_law): evaluation here
# (_Law.derivatives) and the model's columns (phmech._marshal); a leaf's own from _core_leaf

_EXPR, _SUM, _PRODUCT, _CALLBACK = (LAW_KINDS[k] for k in ("expr", "sum", "product", "callback"))

def _leaf(law: _Law) -> tuple:
    """The core's tuple of a leaf law (not a Sum or Product)."""
    if isinstance(law, Function):   # the core calls back (csrc/pyext/py_laws.c, law_callback)
        bp = np.asarray(law.breakpoints, dtype=float) if law.breakpoints else None
        # a function that answers the core's (t, nder) itself, checked (python/phmech/controllers.py,
        # Hold: a held value), else the checks of _FunctionCall
        fast = getattr(law.fn, "core_call", None) if law.shift == 0 else None
        return (_CALLBACK, *_NO, bp, 0, None, fast or _FunctionCall(law))
    kind, params, data, order = law._core_leaf()
    return (LAW_KINDS[kind], *params, data, order, None, None)


def _postfix(law: _Law, out: list) -> None:
    """Append the nodes of ``law`` in postfix order: a Sum or Product of n operands is its
    operands joined by n - 1 operators."""
    if isinstance(law, (Sum, Product)):
        items = law.terms if isinstance(law, Sum) else law.factors
        op = (_SUM if isinstance(law, Sum) else _PRODUCT, *_NO, None, 0, None, None)
        for i, x in enumerate(items):
            _postfix(x, out)
            if i:
                out.append(op)
    else:
        out.append(_leaf(law))


def core_tuple(law: Optional[_Law]) -> Optional[tuple]:
    """The core's law tuple (kind, amplitude, t0, duration, frequency, phase, offset, data,
    order, nodes, fn) (csrc/pyext/py_laws.c, phm_py_parse_law) of a checked law (checked_law),
    or None: a leaf's own, or for a Sum or Product an expression (kind EXPR) whose nodes are
    the leaves and operators in postfix order."""
    if law is None:
        return None
    if not isinstance(law, (Sum, Product)):
        return _leaf(law)
    nodes: list = []
    _postfix(law, nodes)
    return (_EXPR, *_NO, None, 0, nodes, None)

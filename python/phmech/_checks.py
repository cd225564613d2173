"""Argument checks shared by the Python layer: one message style for every bad number or array.

Every value a user passes is converted here (or in the C binding, which applies the same rules),
never by a bare ``float()`` or ``np.asarray(..., dtype=float)``: those accept strings ("1.5"),
drop imaginary parts with a warning, and raise NumPy's own TypeError/ValueError for junk."""
from __future__ import annotations

import math
import numbers

import numpy as np

from ._core import ModelError


def _kind(value) -> str:
    """A short description of what was given, for messages."""
    if isinstance(value, np.ndarray):
        return f"an array of shape {value.shape} and dtype {value.dtype}"
    return type(value).__name__


def real(name: str, value) -> float:
    """``value`` as a finite float, or ModelError naming ``name``. Accepts Python and NumPy real
    numbers (bool included) and 0-d real arrays; refuses strings, complex numbers and arrays."""
    if isinstance(value, np.ndarray) and value.ndim == 0 and value.dtype.kind in "biuf":
        value = value[()]
    if not isinstance(value, (numbers.Real, np.bool_)) or isinstance(value, (str, bytes)):
        raise ModelError(f"{name} must be a real number, got {value!r}")
    try:
        v = float(value)
    except (TypeError, ValueError, OverflowError):
        raise ModelError(f"{name} must be a real number, got {value!r}") from None
    if not math.isfinite(v):
        raise ModelError(f"{name} must be finite, got {v!r}")
    return v


def positive(name: str, value) -> float:
    """``value`` as a positive finite float, or ModelError naming ``name``."""
    v = real(name, value)
    if v <= 0.0:
        raise ModelError(f"{name} must be positive and finite, got {v!r}")
    return v


def integer(name: str, value, minimum: int = None) -> int:
    """``value`` as an int (Python or NumPy integer, not bool), >= ``minimum`` if given."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer)) or \
            (minimum is not None and value < minimum):
        at_least = f" >= {minimum}" if minimum is not None else ""
        raise ModelError(f"{name} must be an integer{at_least} (got {value!r})")
    return int(value)


def array(name: str, value, shape: tuple, expected: str = None, finite: bool = True) -> np.ndarray:
    """``value`` as a new float64 array of ``shape``, or ModelError naming ``name`` and saying
    what was ``expected`` (default: "an array of shape ..."). Refuses strings, None, complex
    numbers, objects, ragged sequences and (when ``finite``) NaN and inf."""
    expected = expected or f"an array of real numbers of shape {shape}"
    if value is None or isinstance(value, (str, bytes)):
        raise ModelError(f"{name}: expected {expected}, got {value!r}")
    try:
        raw = np.asarray(value)
    except (TypeError, ValueError):   # ragged nested sequences, objects numpy cannot read
        raise ModelError(f"{name}: expected {expected}, got {_kind(value)} that is not a "
                         f"regular array of numbers") from None
    if raw.dtype.kind not in "biuf":
        what = {"c": "complex numbers", "U": "strings", "S": "bytes", "O": "objects (e.g. None "
                "or mixed types)"}.get(raw.dtype.kind, f"values of dtype {raw.dtype}")
        raise ModelError(f"{name}: expected {expected}, got {what}")
    if raw.shape != tuple(shape):
        raise ModelError(f"{name}: expected {expected}, got shape {raw.shape}")
    a = raw.astype(np.float64)   # a copy: the caller may keep it
    if finite and not np.all(np.isfinite(a)):
        raise ModelError(f"{name}: expected {expected}, got a non-finite value (NaN or inf)")
    return a

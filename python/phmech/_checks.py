"""Argument checks shared by the Python layer: one message style for every bad number."""
from __future__ import annotations

import math

from ._core import ModelError


def real(name: str, value) -> float:
    """``value`` as a finite float, or ModelError naming ``name``."""
    try:
        v = float(value)
    except (TypeError, ValueError):
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

"""Oscillation analysis of sampled signals: spectra and dominant frequencies."""
from __future__ import annotations

import numpy as np

from ._core import ModelError

__all__ = ["spectrum", "dominant_frequency"]


def _uniform(t, x) -> tuple[np.ndarray, np.ndarray, float]:
    t = np.asarray(t, dtype=float)
    x = np.asarray(x, dtype=float)
    if t.ndim != 1 or x.shape != t.shape or t.size < 8:
        raise ModelError("t and x must be 1-D arrays of the same length (at least 8 samples)")
    if not (np.all(np.isfinite(t)) and np.all(np.isfinite(x))):
        raise ModelError("t and x must be finite")
    dt = np.diff(t)
    if np.any(dt <= 0) or np.ptp(dt) > 1e-6 * dt.mean():
        raise ModelError("t must be uniformly spaced and increasing")
    return t, x, float(dt.mean())


def spectrum(t, x, pad: int = 8) -> tuple[np.ndarray, np.ndarray]:
    """Amplitude spectrum of ``x(t)`` (mean removed, Hann window, zero-padded ``pad`` times).

    Returns ``(f [Hz], |X|)``; the magnitude is scaled so that a sinusoid of amplitude A shows a
    peak of about A.
    """
    t, x, dt = _uniform(t, x)
    w = np.hanning(x.size)
    n = int(pad) * x.size
    X = np.abs(np.fft.rfft((x - x.mean()) * w, n)) * 2.0 / w.sum()
    return np.fft.rfftfreq(n, dt), X


def dominant_frequency(t, x, fmin: float = 0.0, fmax: float = np.inf, pad: int = 16) -> float:
    """Frequency [Hz] of the largest spectral peak of ``x(t)`` in ``[fmin, fmax]``.

    The peak of the zero-padded Hann spectrum is refined by a parabola through the logarithms of
    its three highest bins; for a clean sinusoid over many periods this is accurate to a small
    fraction of the bin width 1/(pad T).
    """
    f, X = spectrum(t, x, pad)
    band = np.nonzero((f >= fmin) & (f <= fmax))[0]
    band = band[(band > 0) & (band < f.size - 1)]
    if band.size == 0:
        raise ModelError("no spectral bin inside [fmin, fmax]")
    k = band[np.argmax(X[band])]
    a, b, c = np.log(X[k - 1:k + 2] + 1e-300)
    denom = a - 2 * b + c
    shift = 0.5 * (a - c) / denom if denom != 0 else 0.0
    return float(f[k] + shift * (f[1] - f[0]))

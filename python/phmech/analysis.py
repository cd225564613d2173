"""Oscillation analysis: spectra and dominant frequencies of sampled signals, and the energy of
each linearized mode along a simulated trajectory."""
from __future__ import annotations

import numpy as np

from ._core import ModelError

__all__ = ["spectrum", "dominant_frequency", "modal_energy"]


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


def modal_energy(mechanism, result, modes) -> np.ndarray:
    """Energy [J] of each linearized mode along a trajectory: (nt, nmodes).

    ``modes``: ``mechanism.modes(n)`` at the configuration ``result`` started from (its shapes are
    mass-normalized tangent displacements). Each carrier's displacement is the tangent
    d = log(H(0)^-1 H(t)) and its rate the body twist; the modal coordinate is q_k = phi_k^T M d
    (M: the carriers' lumped 6x6 mass matrices) and the modal energy 1/2 (qdot_k^2 + omega_k^2
    q_k^2). Meaningful for small motions about the start (vibrations): the sum over the modes
    is then the mechanical energy. Large rotations and the axial shortening of bending (second
    order in the deflection) are not modal motions: they show as spurious energy in the stiff
    axial modes, so compare modes one by one, or the total of the modes you trust, over time.
    Typical use: which modes the integrator's numerical dissipation takes energy from
    (docs/integrators.md, "Where the numerical dissipation goes")."""
    from . import se3
    poses, twists = np.asarray(result.poses), np.asarray(result.twists)
    M = np.array([c["M"] for c in mechanism._car])
    phi = np.asarray(modes.shapes)
    if poses.ndim != 4 or poses.shape[1] != M.shape[0] or phi.shape[1:] != (M.shape[0], 6):
        raise ModelError("modal_energy: the result must record every carrier of the mechanism "
                         "(simulate without record=) and the modes must be this mechanism's")
    H0inv = np.array([se3.inverse(H) for H in poses[0]])
    d = np.array([[se3.log(H0inv[c] @ Hc) for c, Hc in enumerate(Ht)] for Ht in poses])
    q = np.einsum("kcj,cji,nci->nk", phi, M, d)
    qdot = np.einsum("kcj,cji,nci->nk", phi, M, twists)
    return 0.5 * (qdot ** 2 + np.asarray(modes.omega) ** 2 * q ** 2)

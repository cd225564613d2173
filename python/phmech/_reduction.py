"""The link-alone analyses behind a modal link (phmech.fidelity; docs/method.md, "Modal links"):
the link's own se3 chain built on a bare Builder and analysed in the core -- linearized and
condensed onto its ends (static_reduction), and the shift of its first frequency under its
own weight (gravity_preload_sensitivity). Above the analyses (python/phmech/_linearize.py,
_modes.py, _statics.py) and below the Mechanism that adds modal links (python/phmech/_modal.py).
Units: SI; frequencies in rad/s unless named in Hz."""
from __future__ import annotations

import warnings

import numpy as np
from scipy.linalg import eigh
from threadpoolctl import threadpool_limits

from . import _linearize, _modes, _statics, se3
from ._builder import Builder
from ._errors import UnattachedWarning
from .fidelity import chain_weights, gravity_points, gravity_sag_error
from .pairs import Fixed


def static_reduction(length: float, properties, elements: int, eps: np.ndarray, mass: str) -> dict:
    """The modal link of a flexible link (module doc): its ``elements``-element se3 chain, free and
    unstressed, linearized by phmech (stiffness K, damping D, mass M in the nodes' body
    perturbations), condensed onto its end nodes by the static modes T = [I; -K_ii^-1 K_ib]:
    K_B = T^T K T, D_B, M_B (12 x 12 on (start, end)). K_c, D_c = the (end, end) blocks: the end's
    stiffness and damping against the start held, in the perturbation xi = log(T0^-1 H_a^-1 H_b)
    of the end relative to the start carried rigidly (T0 = exp(X0), X0 = length eps). One se3
    element of length L with unstressed strain eps has, at the unstressed shape, the strain
    L d(eps) = dexp_{-X0}^-1 d(xi); so its section stiffness K = L dexp_{-X0}^T K_c dexp_{-X0}
    (and D likewise) gives it exactly K_c. Returns the element's ``K``, ``D``, the carriers'
    inertias ``M_start``, ``M_end`` (M_B's diagonal blocks) and the coupling ``Mc`` (M_B less
    them), and the condensed matrices ``K_B``, ``M_B``."""
    with threadpool_limits(limits=1, user_api="blas"):
        return _static_reduction(length, properties, elements, eps, mass)

def _static_reduction(length, properties, elements, eps, mass) -> dict:
    """static_reduction's work, with one BLAS thread: its matrices are small (6 (elements + 1)),
    and NumPy's multithreaded BLAS spun on them. Measured at 64 elements: 33 ms single-threaded
    against 48-150 ms of CPU (and 0.26 s of wall time at 32 elements) with two threads on two
    cores another job was using."""
    m = Builder()
    kap = np.asarray(eps[:3], dtype=float)
    m.add_flexible_link("link", length, properties, elements=elements, mass=mass,
                        curvature=None if not np.any(kap) else kap)
    with warnings.catch_warnings():   # the link alone, free in space on purpose
        warnings.simplefilter("ignore", UnattachedWarning)
        lin = _linearize.linearize(m)
    K, D, M = lin.stiffness, lin.damping, lin.mass
    n = K.shape[0]
    b = np.r_[0:6, n - 6:n]
    i = np.r_[6:n - 6]
    T = np.zeros((n, 12))
    T[b, np.arange(12)] = 1.0
    if i.size:
        T[i] = -np.linalg.solve(K[np.ix_(i, i)], K[np.ix_(i, b)])
    sym = lambda X: 0.5 * (X + X.T)
    K_B, D_B, M_B = (sym(T.T @ X @ T) for X in (K, D, M))
    X0 = length * np.asarray(eps, dtype=float)
    E = se3.dexp(-X0)
    Mc = M_B.copy()
    Mc[:6, :6] = 0.0
    Mc[6:, 6:] = 0.0
    # the link's first frequency held at its start: the scale of its validity (modal_validity)
    ev = eigh(K[6:, 6:], M[6:, 6:], eigvals_only=True, subset_by_index=[0, 0])
    gravity = gravity_points(m, T, X0)
    sag = gravity_sag_error(m, K, gravity, K_B[6:, 6:], length)
    return dict(K=sym(length * E.T @ K_B[6:, 6:] @ E), D=sym(length * E.T @ D_B[6:, 6:] @ E),
                M_start=M_B[:6, :6].copy(), M_end=M_B[6:, 6:].copy(), Mc=Mc, K_B=K_B, M_B=M_B,
                omega_clamped=float(np.sqrt(max(ev[0], 0.0))), gravity=gravity,
                gravity_sag_error=sag, chain=dict(K=K, D=D, M=M, T=T, interior=i, desc=m._desc,
                                                  weights=np.array([chain_weights(m._car, np.eye(3)[j])
                                                                    for j in range(3)]).T))

def gravity_preload_sensitivity(length: float, properties, elements: int, eps: np.ndarray,
                                mass: str) -> float:
    """How much the link's own weight along its axis moves its first frequency held at its start,
    relative, per m/s^2 of gravity: its chain (nonlinear) clamped at the start under 1 m/s^2
    along its axis (tension), modes at that equilibrium against the unloaded ones. A modal link
    has no geometric stiffness (and its end's gravity point even shifts it the other way), so
    this is the error a gravity preload adds to it (Mechanism._build warns)."""
    kap = np.asarray(eps[:3], dtype=float)
    f = []
    for g in (0.0, 1.0):
        m = Builder(gravity=(g, 0.0, 0.0))
        lk = m.add_flexible_link("link", length, properties, elements=elements, mass=mass,
                                 curvature=None if not np.any(kap) else kap)
        m.add_pair("clamp", Fixed(), m.ground, lk.start)
        with threadpool_limits(limits=1, user_api="blas"):
            f.append(_modes.modes(m, 1, at=_statics.static(m) if g else None).frequency[0])
    return float(abs(f[1] / f[0] - 1.0))

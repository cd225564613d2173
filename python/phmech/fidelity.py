"""Per-link fidelity (docs/user_guide.md, "Model only what a scene needs"): what a flexible link
becomes when it is modelled at a lower fidelity than the se3 chain.

``fidelity="rigid"``: the link is ONE rigid carrier whose frame is the link's start frame. Its
spatial inertia is the section inertia integrated along the unstressed shape (straight, or the
arc of a constant unstressed curvature), its node frames are fixed offsets on it at the places
the se3 chain's nodes have on the undeformed link, and a distributed load is its resultant
wrench (docs/method.md, "Rigid links"). Everything here is exact for a rigid body up to the
quadrature, which is exact for a straight link and converged to round-off for a curved one.

A modal (Craig-Bampton) fidelity would add its own builder here: a carrier for the boundary
frames plus modal coordinates, with the same FlexibleLink face (``nodes`` + ``offsets``).
"""
from __future__ import annotations

import numpy as np

from . import se3

#: the fidelities add_flexible_link accepts
FIDELITIES = ("nonlinear", "rigid")

# composite Gauss-Legendre: 5 points per segment, segments of at most _MAX_TURN rad of the
# unstressed curvature (error ~ (0.2)^10 / 10! of the integrand: round-off)
_GAUSS = np.polynomial.legendre.leggauss(5)
_MAX_TURN = 0.2


def _quadrature(L: float, eps: np.ndarray) -> tuple:
    """Points s (n,) in [0, L] and weights w (n,) integrating functions of exp(s eps_hat)."""
    turn = float(np.linalg.norm(eps[:3])) * L
    nseg = max(1, int(np.ceil(turn / _MAX_TURN)))
    x, w = _GAUSS
    edges = np.linspace(0.0, L, nseg + 1)
    a, b = edges[:-1, None], edges[1:, None]
    s = (0.5 * (b - a) * x[None, :] + 0.5 * (a + b)).ravel()
    ws = (0.5 * (b - a) * w[None, :]).ravel()
    return s, ws


def rigid_link_inertia(L: float, inertia: np.ndarray, eps: np.ndarray) -> tuple:
    """The rigid link's spatial inertia M (6x6, about its start frame, (omega, v) order), mass
    [kg] and centre of mass [m, start-frame coordinates]: M = int_0^L Ad_{g(s)^-1}^T I Ad_{g(s)^-1}
    ds, g(s) = exp(s eps_hat) the section frame at arc length s on the unstressed shape, I the
    section inertia per unit length (the kinetic energy of every section moving with the body
    twist t: its twist is Ad_{g^-1} t)."""
    s, w = _quadrature(L, eps)
    A = se3.Ad(se3.inverse(se3.exp(s[:, None] * eps[None, :])))       # (n, 6, 6)
    M = np.einsum("n,nji,jk,nkl->il", w, A, inertia, A)
    M = 0.5 * (M + M.T)
    mass = float(np.trace(M[3:, 3:]) / 3.0)
    C = M[:3, 3:] / mass                 # = hat(com) (add_rigid_body's layout)
    com = np.array([C[2, 1] - C[1, 2], C[0, 2] - C[2, 0], C[1, 0] - C[0, 1]]) / 2.0
    return M, mass, com


def node_offsets(L: float, elements: int, eps: np.ndarray) -> np.ndarray:
    """Offsets (elements + 1, 4, 4) of the node frames on the start frame: exp(k h eps_hat)."""
    h = L / elements
    return se3.exp(np.arange(elements + 1)[:, None] * h * eps[None, :])


def distributed_resultant(L: float, eps: np.ndarray, q: np.ndarray, world: bool) -> tuple:
    """A uniform distributed force q [N/m] on a rigid link as one wrench row: (w (tau, f), point
    [m, start-frame coordinates]). ``world``: q in world axes, applied at the centroid of the
    centre line (a uniform world force has no moment about it); else q in each section's axes
    (a follower load), its resultant in start-frame axes at the start frame's origin:
    (int p(s) x R(s) q ds, int R(s) q ds)."""
    s, w = _quadrature(L, eps)
    G = se3.exp(s[:, None] * eps[None, :])
    p = G[:, :3, 3]
    if world:
        return np.concatenate([np.zeros(3), q * L]), np.einsum("n,ni->i", w, p) / L
    f = np.einsum("nij,j->ni", G[:, :3, :3], q)
    return np.concatenate([np.einsum("n,ni->i", w, np.cross(p, f)), w @ f]), np.zeros(3)

"""Golo's mixed finite element for the linear planar Timoshenko beam (the paper's element,
refs [49], [51], [52]; Table I).

The beam (length ``L`` [m], bending stiffness ``EI`` [N m^2], shear stiffness ``kGA`` [N], mass
per length ``rhoA`` [kg/m], rotary inertia per length ``rhoI`` [kg m]) is split into ``N`` equal
elements. On each element the energy variables (transverse momentum, shear strain, angular
momentum, curvature) are constant and the co-energy variables (velocity ``v``, shear force ``Q``,
angular velocity ``omega``, moment ``M``) linear; the element efforts are tied to the node values
with Golo's weights ``alpha`` / ``1 - alpha`` (``alpha = 1/2``: the paper's symmetric element).
Each element takes the flows ``(v, omega)`` at its left node and the efforts ``(Q, M)`` at its
right node as inputs, and the elements are interconnected through these node ports.

The result is the finite-dimensional port-Hamiltonian system (state ``x``: the element integrals
of the energy variables, ``4 N`` of them, ordered ``(P_t, E_s, P_r, K)`` per element)::

    dx/dt = J Q x + B u,   y = B^T Q x + D u,   H = x^T Q x / 2,   dH/dt = u^T y,

with boundary ports ``u = (v(0), omega(0), Q(L), M(L))`` and ``y = (-Q(0), -M(0), v(L),
omega(L))``; ``J`` and ``D`` are skew, ``Q`` is diagonal positive. The derivation is in the
header comment of ``csrc/model/mixed.c``.
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np

from . import _core

__all__ = ["BOUNDARY_CONDITIONS", "MixedMatrices", "matrices", "frequencies"]

#: Supported boundary conditions (left end at s = 0, right end at s = L).
BOUNDARY_CONDITIONS = ("clamped-free", "clamped-clamped", "pinned-pinned", "clamped-pinned")


class MixedMatrices(NamedTuple):
    """Matrices of the discretized beam (row-major float64 arrays).

    ``J`` (4N x 4N, skew), ``Q`` (4N x 4N, diagonal positive), ``B`` (4N x 4) and ``D`` (4 x 4,
    skew) describe the open chain with the four boundary ports. Under the boundary condition,
    ports whose input is prescribed zero are dropped, and ports whose output is prescribed zero
    become constraints: ``dx/dt = J Q x + G lam``, ``G^T Q x = 0``, with ``G`` (4N x k) the
    columns of ``B`` listed in ``constrained``. For ``clamped-free`` ``G`` is empty and the
    closed system is just ``dx/dt = J Q x``.
    """

    J: np.ndarray
    Q: np.ndarray
    B: np.ndarray
    D: np.ndarray
    G: np.ndarray
    constrained: tuple


def matrices(N: int, L: float, EI: float, kGA: float, rhoA: float, rhoI: float,
             bc: str = "clamped-free", alpha: float = 0.5) -> MixedMatrices:
    """Assemble the mixed-finite-element model of the beam (see the module docstring).

    Units: L [m], EI [N m^2], kGA [N], rhoA [kg/m], rhoI [kg m]. ``1 <= N <= 1000``,
    ``0 <= alpha < 1``. Raises :class:`phmech.ModelError` (a ValueError) on bad input.
    """
    J, Q, B, D = _core.mixed_matrices(N, L, EI, kGA, rhoA, rhoI, alpha)
    constrained = tuple(i for i, c in enumerate(_core.mixed_bc_ports(bc)) if c)
    G = np.ascontiguousarray(B[:, list(constrained)])
    return MixedMatrices(J, Q, B, D, G, constrained)


def frequencies(n: int, N: int, L: float, EI: float, kGA: float, rhoA: float, rhoI: float,
                bc: str = "clamped-free", alpha: float = 0.5) -> np.ndarray:
    """The first ``n`` natural frequencies [rad/s] of the beam discretized with ``N`` mixed
    elements, ascending (zero frequencies of rigid or constraint modes are skipped).

    ``bc`` is one of :data:`BOUNDARY_CONDITIONS`. Cost: a dense eigenvalue problem of size 4N.
    Raises :class:`phmech.ModelError` (a ValueError) on bad input.
    """
    return _core.mixed_frequencies(n, N, L, EI, kGA, rhoA, rhoI, bc, alpha)

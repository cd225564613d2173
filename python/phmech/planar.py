"""Planar scenes (issue 13): is a mechanism's motion confined to one plane, and which of its
constraint rows does the planar DAE keep?

A scene is planar about the world axis k (its plane's normal) when, at the initial configuration,
every carrier rotates about k and moves across it, and nothing can push it out: gravity lies in
the plane; every carrier's inertia, every element's stiffness, damping and masses and every
inertial coupling keep the in-plane components (omega_k and the two velocities / strains across
k) apart from the out-of-plane ones; the unstressed curvature is about k only; loads and springs
act in the plane (no lever arm along k); a carrier's weight has no lever arm along k; actuated
and driven pairs move in the plane; and every constraint row is either in-plane or out-of-plane
(the latter are dropped). Then the out-of-plane states keep their initial values, and the core
integrates only the in-plane ones (csrc/dae/planar.c).

Every check is one of exact zeros, taken as zero up to 1e-12 (PHM_PLANAR_ZERO) of the scale of its array (the
round-off of a static solution or a closed loop): of a twist, wrench, strain or point per item,
of a matrix per matrix, of a constraint row per row.

The checks are the core's (csrc/model/planarity.c, phm_planar_check), one implementation:
Mechanism.simulate asks it of its model (_core.model_planar); check and out_of_plane_rows ask it
of the columns of _marshal.components and a dense constraint matrix."""
from __future__ import annotations

from typing import Optional

import numpy as np

from . import _core

AXES = "xyz"


def inplane(k: int) -> np.ndarray:
    """The in-plane components of a twist, wrench or strain (omega/kappa first) for normal k."""
    return np.array([k] + [3 + i for i in range(3) if i != k])


def check(comp: dict, poses, twists, G, layout, names, k: int) -> Optional[str]:
    """None if the scene (``comp``: _marshal.components; ``poses``, ``twists``: the start; ``G``:
    all constraint rows at the start, with ``layout`` (row, m, joint, k) per pair named
    ``names``) is planar about axis k; else the first check that fails, in words."""
    return _core.planar_check(comp, poses, np.asarray(twists, dtype=float).reshape(-1, 6), G,
                              layout, list(names), k)


def out_of_plane_rows(G, layout, nc: int, k: int) -> list:
    """Per pair the drop mask of its rows without an in-plane component (check() passed)."""
    return _core.planar_rows(G, layout, nc, k)

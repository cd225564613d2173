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

Every check is one of exact zeros, taken as zero up to 1e-12 of the scale of its array (the
round-off of a static solution or a closed loop)."""
from __future__ import annotations

from functools import lru_cache
from typing import Optional

import numpy as np

ZERO = 1e-12
AXES = "xyz"


def inplane(k: int) -> np.ndarray:
    """The in-plane components of a twist, wrench or strain (omega/kappa first) for normal k."""
    return np.array([k] + [3 + i for i in range(3) if i != k])


def outplane(k: int) -> np.ndarray:
    return np.array([i for i in range(3) if i != k] + [3 + k])


def _zero(x, scale=None) -> bool:
    """Every entry of x is zero up to ZERO times the largest entry of ``scale`` (exactly zero
    without a scale, or when the scale is all zeros)."""
    s = float(np.max(np.abs(scale))) if scale is not None and np.size(scale) else 0.0
    return bool(np.all(np.abs(np.asarray(x, dtype=float)) <= ZERO * s))


def _zero_each(x, scale) -> np.ndarray:
    """_zero of each x[i] against scale[i] (arrays of n items), as n booleans."""
    x, scale = np.asarray(x, dtype=float), np.asarray(scale, dtype=float)
    n = len(x)
    if n == 0:
        return np.ones(0, dtype=bool)
    s = np.abs(scale.reshape(n, -1)).max(axis=1) if scale[0].size else np.zeros(n)
    return np.all(np.abs(x.reshape(n, -1)) <= ZERO * s[:, None], axis=1)


@lru_cache(maxsize=None)
def _coupling_mask(k: int, nblk: int) -> np.ndarray:
    """The entries of a (6 nblk)-square matrix that couple in-plane with out-of-plane components."""
    inside = np.isin(np.arange(6 * nblk) % 6, inplane(k))
    return inside[:, None] != inside[None, :]


def _decoupled_each(M, k: int, nblk: int = 1) -> np.ndarray:
    """Per matrix of M (n, 6 nblk, 6 nblk): no entry couples the in-plane components with the
    out-of-plane ones (zero up to ZERO times the matrix's largest entry)."""
    A = np.abs(np.asarray(M, dtype=float).reshape(-1, 6 * nblk, 6 * nblk))
    if len(A) == 0:
        return np.ones(0, dtype=bool)
    s = ZERO * A.max(axis=(1, 2))
    return np.all(A[:, _coupling_mask(k, nblk)] <= s[:, None], axis=1)


def _first(checks):
    """The message of the first failing item, items in order and each item's checks in the
    order given: ``checks`` = [(ok per item, message(i)), ...]."""
    if all(ok.all() for ok, _ in checks):
        return None
    failing = [np.flatnonzero(~ok) for ok, _ in checks]
    first = min(f[0] for f in failing if len(f))
    for (ok, message), f in zip(checks, failing):
        if len(f) and f[0] == first:
            return message(int(first))


def check(comp: dict, poses, twists, G, layout, names, k: int) -> Optional[str]:
    """None if the scene (``comp``: _marshal.components; ``poses``, ``twists``: the start; ``G``:
    all constraint rows at the start, with ``layout`` (row, m, joint, k) per pair named
    ``names``) is planar about axis k; else the first check that fails, in words."""
    ax = AXES[k]
    O = outplane(k)
    g = comp["gravity"]
    if abs(g[k]) > ZERO * max(abs(float(x)) for x in g):
        return f"gravity {tuple(g)} has a component along {ax}"
    car = comp["carriers"]
    H = np.asarray(poses, dtype=float).reshape(-1, 4, 4)
    T = np.asarray(twists, dtype=float).reshape(-1, 6)
    nc = len(H)
    R = H[:, :3, :3]
    off = np.array([i for i in range(3) if i != k])
    about_k = (np.abs(R[:, k, k] - 1.0) <= ZERO) & np.all(np.abs(R[:, k, off]) <= ZERO, axis=1) & \
        np.all(np.abs(R[:, off, k]) <= ZERO, axis=1)
    if not about_k.all():   # first and alone: it rejects the other axes of most planar scenes
        return f"carrier {int(np.flatnonzero(~about_k)[0])}'s initial rotation is not about {ax}"
    # the twists' scale: the scene's (a carrier at rest: round-off)
    still = np.all(np.abs(T[:, O]) <= ZERO * np.max(np.abs(T)), axis=1) if T.any() else \
        np.ones(nc, dtype=bool)
    com = np.asarray(car["com"], dtype=float).reshape(-1, 3)
    weightless = (np.asarray(car["mass"], dtype=float) <= 0) | (not np.any(g)) | _zero_each(com[:, k], com)
    el, cp = comp["elements"], comp["couplings"]
    eps = np.asarray(el["eps_hat"], dtype=float).reshape(-1, 6)
    ne = len(eps)
    # every 6x6 matrix in one test, and every 12x12 one: carriers' M, elements' K, D, Ms; Mc
    inertia, K, D, Ms = np.split(_decoupled_each(np.concatenate(
        [np.reshape(car["M"], (-1, 6, 6))] + [el[key] for key in ("K", "D", "Ms")]), k),
        [nc, nc + ne, nc + 2 * ne])
    element_mass, couplings = np.split(_decoupled_each(np.concatenate([el["Mc"], cp["Mc"]]), k, 2), [ne])
    why = _first([
        (still, lambda c: f"carrier {c}'s initial twist has out-of-plane components {T[c][O]}"),
        (inertia, lambda c: f"carrier {c}'s inertia couples in-plane and out-of-plane motion"),
        (weightless, lambda c: f"carrier {c}'s centre of mass is off the plane (its weight would tilt it)")])
    if why:
        return why
    why = _first([(ok, lambda e, key=key: f"element {e}'s {key} couples in-plane and out-of-plane strains")
                  for ok, key in zip((K, D, Ms), ("K", "D", "Ms"))] + [
        (element_mass, lambda e: f"element {e}'s consistent mass couples in-plane and out-of-plane motion"),
        (_zero_each(eps[:, O], eps), lambda e: f"element {e}'s unstressed curvature is not about {ax}")])
    if why:
        return why
    why = _first([(couplings, lambda c: f"inertial coupling {c} couples in-plane and out-of-plane motion")])
    if why:
        return why
    ld = comp["loads"]
    w = np.asarray(ld["w"], dtype=float).reshape(-1, 6)
    point = np.asarray(ld["point"], dtype=float).reshape(-1, 3)
    no_arm = ~np.any(w[:, 3:] != 0, axis=1) | _zero_each(point[:, k], point)
    why = _first([(_zero_each(w[:, O], w), lambda i: f"load {i} has out-of-plane components {w[i][O]}"),
                  (no_arm, lambda i: f"load {i} acts at a point off the plane")])
    if why:
        return why
    sp = comp["springs"]
    for i, (a, b) in enumerate(np.asarray(sp["carriers"], dtype=int).reshape(-1, 2)):
        pa, pb = sp["pa"][i], sp["pb"][i]
        wa = poses[a][:3, :3] @ pa + poses[a][:3, 3] if a >= 0 else pa
        wb = poses[b][:3, :3] @ pb + poses[b][:3, 3] if b >= 0 else pb
        if (a >= 0 and not _zero(pa[k], pa)) or (b >= 0 and not _zero(pb[k], pb)) or \
                not _zero(wa[k] - wb[k], np.concatenate([wa, wb])):
            return f"spring {i} has its points off the plane"
    pr = comp["pairs"]
    actuated = set(int(p) for p in comp["actuators"]["pair"])
    for ip, (a, b) in enumerate(np.asarray(pr["carriers"], dtype=int).reshape(-1, 2)):
        if ip in actuated or pr["driven"][ip] or pr["xlaws"][ip] is not None:
            row, _, _, kk = layout[ip]
            if kk != 1:
                return f"pair {names[ip]!r} is actuated or driven along more than one coordinate"
            # the direction its effort or law moves: the null space of its type's 5 rows on one
            # of its carriers (a carrier's body axes: rotated about k, so in and out of the plane
            # as the world's); a driven coordinate's row, dropped as out-of-plane, would
            # silently leave the law undone
            c = b if b >= 0 else a
            free = np.linalg.svd(G[row:row + 5, 6 * c:6 * c + 6])[2][-1]
            if not _zero(free[O], free):
                return f"pair {names[ip]!r} is actuated or driven along an out-of-plane axis"
    if layout:
        inside, outside = _row_parts(G, nc, k)
        mixed = ~inside & ~outside
        for ip, (row, m, _, _) in enumerate(layout):
            r = np.flatnonzero(mixed[row:row + m])
            if len(r):
                return f"pair {names[ip]!r}'s constraint row {r[0]} mixes in-plane and out-of-plane motion"
    return None


@lru_cache(maxsize=64)
def _inplane_columns(k: int, nc: int) -> np.ndarray:
    """The columns of a constraint matrix over nc carriers' twists that are in-plane (bool)."""
    return np.tile(np.isin(np.arange(6), inplane(k)), nc)


def _row_parts(G, nc: int, k: int):
    """Per constraint row of G: (no in-plane component, no out-of-plane component), each zero
    up to ZERO times the row's largest entry."""
    A = np.abs(np.asarray(G, dtype=float))
    s = ZERO * A.max(axis=1, initial=0.0)[:, None]
    cols = _inplane_columns(k, nc)
    return np.all(A[:, cols] <= s, axis=1), np.all(A[:, ~cols] <= s, axis=1)


def out_of_plane_rows(G, layout, nc: int, k: int) -> list:
    """Per pair the drop mask of its rows without an in-plane component (check() passed)."""
    no_in = _row_parts(G, nc, k)[0] if layout else None
    return [int(sum(1 << r for r in range(m) if no_in[row + r])) for row, m, _, _ in layout]

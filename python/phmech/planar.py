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
    x = np.asarray(x, dtype=float)
    s = float(np.max(np.abs(scale))) if scale is not None and np.size(scale) else 0.0
    return bool(np.all(np.abs(x) <= ZERO * s)) if s > 0 else bool(np.all(x == 0))


def _decoupled(M, k: int, nblk: int = 1) -> bool:
    """M (6 nblk square) has no entry coupling the in-plane components with the out-of-plane."""
    M = np.asarray(M, dtype=float)
    i = np.concatenate([inplane(k) + 6 * b for b in range(nblk)])
    o = np.concatenate([outplane(k) + 6 * b for b in range(nblk)])
    return _zero(M[np.ix_(i, o)], M) and _zero(M[np.ix_(o, i)], M)


def check(comp: dict, poses, twists, G, layout, names, k: int) -> Optional[str]:
    """None if the scene (``comp``: _marshal.components; ``poses``, ``twists``: the start; ``G``:
    all constraint rows at the start, with ``layout`` (row, m, joint, k) per pair named
    ``names``) is planar about axis k; else the first check that fails, in words."""
    ax = AXES[k]
    I, O = inplane(k), outplane(k)
    g = comp["gravity"]
    if not _zero(g[k], g):
        return f"gravity {tuple(g)} has a component along {ax}"
    car = comp["carriers"]
    for c, (H, t) in enumerate(zip(poses, twists)):
        R = H[:3, :3]
        off = [(k, i) for i in range(3) if i != k] + [(i, k) for i in range(3) if i != k]
        if not (abs(R[k, k] - 1.0) <= ZERO and all(abs(R[a, b]) <= ZERO for a, b in off)):
            return f"carrier {c}'s initial rotation is not about {ax}"
        if not _zero(t[O], twists):   # the scale: the scene's twists (a carrier at rest: round-off)
            return f"carrier {c}'s initial twist has out-of-plane components {t[O]}"
        if not _decoupled(car["M"][c], k):
            return f"carrier {c}'s inertia couples in-plane and out-of-plane motion"
        if car["mass"][c] > 0 and np.any(g) and not _zero(car["com"][c][k], car["com"][c]):
            return f"carrier {c}'s centre of mass is off the plane (its weight would tilt it)"
    el = comp["elements"]
    for e in range(len(el["h"])):
        for key in ("K", "D", "Ms"):
            if not _decoupled(el[key][e], k):
                return f"element {e}'s {key} couples in-plane and out-of-plane strains"
        if not _decoupled(el["Mc"][e], k, 2):
            return f"element {e}'s consistent mass couples in-plane and out-of-plane motion"
        if not _zero(el["eps_hat"][e][O], el["eps_hat"][e]):
            return f"element {e}'s unstressed curvature is not about {ax}"
    for c, Mc in enumerate(comp["couplings"]["Mc"]):
        if not _decoupled(Mc, k, 2):
            return f"inertial coupling {c} couples in-plane and out-of-plane motion"
    ld = comp["loads"]
    for i in range(len(ld["carrier"])):
        w = ld["w"][i]
        if not _zero(w[O], w):
            return f"load {i} has out-of-plane components {w[O]}"
        if np.any(w[3:]) and not _zero(ld["point"][i][k], ld["point"][i]):
            return f"load {i} acts at a point off the plane"
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
    nc = len(poses)
    ci = np.concatenate([I + 6 * c for c in range(nc)]) if nc else np.zeros(0, int)
    co = np.concatenate([O + 6 * c for c in range(nc)]) if nc else np.zeros(0, int)
    for ip, (row, m, _, _) in enumerate(layout):
        for r in range(row, row + m):
            gi, go = G[r, ci], G[r, co]
            if not _zero(gi, G[r]) and not _zero(go, G[r]):
                return f"pair {names[ip]!r}'s constraint row {r - row} mixes in-plane and out-of-plane motion"
    return None


def out_of_plane_rows(G, layout, nc: int, k: int) -> list:
    """Per pair the drop mask of its rows without an in-plane component (check() passed)."""
    ci = np.concatenate([inplane(k) + 6 * c for c in range(nc)]) if nc else np.zeros(0, int)
    masks = []
    for row, m, _, _ in layout:
        mask = 0
        for r in range(m):
            if _zero(G[row + r, ci], G[row + r]):
                mask |= 1 << r
        masks.append(mask)
    return masks

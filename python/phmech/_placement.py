"""The tree placement of the initial configuration (step 1 of python/phmech/topology.py's
docstring): each carrier placed from the ground across the pairs of a spanning tree, from the
given poses and joint coordinates (``x0``), before any loop is closed. NumPy only, on a model
description (no core model): the builder places ``start=``/``at=`` frames with it
(Mechanism.world_pose), and topology.initial_state starts from it. Units: m, rad; poses 4x4."""
from __future__ import annotations

from collections import deque
from typing import Optional

import numpy as np

from . import se3
from ._errors import ModelError
from .description import ModelDescription
from .pairs import PAIR_TYPES

POSE_TOL = 1e-6      # given poses vs pairs [rad], and [m] times length_scale(desc)


def pose_across(e: dict, x, xd, Ha, ta, forward: bool = True, Ta: Optional[np.ndarray] = None):
    """Pose and body twist of the far carrier of pair row ``e`` at joint coordinates x and rates
    xd, the near carrier being at pose Ha with twist ta (``forward``: near = a, far = b); ``Ta``:
    the pair's frame offset on a (default: the row's). The relative twist is psi(x) xd, psi by
    central differences of h(x)."""
    pair = e["pair"]
    h = pair._fk(x)
    hi = se3.inverse(h)
    trel = np.zeros(6)
    eps = 1e-6
    for i in range(len(x)):
        if xd[i] == 0:
            continue
        d = np.zeros(len(x))
        d[i] = eps
        trel += xd[i] * (se3.log(hi @ pair._fk(x + d)) - se3.log(hi @ pair._fk(x - d))) / (2 * eps)
    Ta = e["Ta"] if Ta is None else Ta
    if forward:   # near = a, far = b
        Fb = Ha @ Ta @ h
        tFa = se3.Ad(se3.inverse(Ta)) @ ta
        tFb = se3.Ad(hi) @ tFa + trel
        return Fb @ se3.inverse(e["Tb"]), se3.Ad(e["Tb"]) @ tFb
    Fa = Ha @ e["Tb"] @ hi                          # here Ha is H_b
    tFb = se3.Ad(se3.inverse(e["Tb"])) @ ta
    tFa = se3.Ad(h) @ (tFb - trel)
    return Fa @ se3.inverse(Ta), se3.Ad(Ta) @ tFa


def length_scale(desc: ModelDescription) -> float:
    """The mechanism's size L [m] that sets the position tolerances (POSE_TOL * L): the largest
    of the link lengths, the pair frames' offsets and the extent (bounding-box diagonal) of the
    carriers' initial origins, with the world origin when a pair or carrier uses the ground;
    1 m when all of these are zero."""
    pts = [np.asarray(c["H0"])[:3, 3] for c in desc.carriers]
    if any(e["a"] < 0 or e["b"] < 0 for e in desc.pairs):
        pts.append(np.zeros(3))
    L = 0.0
    if pts:
        P = np.array(pts)
        L = float(np.linalg.norm(P.max(axis=0) - P.min(axis=0)))
    for lk in desc.links.values():
        L = max(L, float(lk.length))
    for e in desc.pairs:
        L = max(L, float(np.linalg.norm(e["Ta"][:3, 3])), float(np.linalg.norm(e["Tb"][:3, 3])))
    return L if L > 0 else 1.0


def rotation_angle(R) -> float:
    """Rotation angle [rad] of a rotation matrix, in [0, pi]."""
    return float(np.linalg.norm(se3.log(np.ascontiguousarray(R))))


def pair_reference(e: dict, Ga, Gb, tol_m: float):
    """Check pair row ``e`` against the given poses Ga, Gb (4x4) of its carriers; return the
    joint coordinates x (k,) of its frames' relative pose h = (Ga Ta)^-1 (Gb Tb) and the pair's
    frame offset on a.

    Part of h the pair type cannot produce (its constrained directions: fk(x)^-1 h) beyond
    POSE_TOL (``tol_m`` in m) raises ModelError naming the pair, its frames and the mismatch.
    A Fixed pair instead takes the relative orientation of its frames as the weld's (the offset
    returned is Ta R), when neither frame offset has a rotation of its own and the pair is not
    driven; a rotated frame offset that disagrees with the given poses is an error, because the
    frames and the poses then state two different welds."""
    h = se3.inverse(Ga @ e["Ta"]) @ (Gb @ e["Tb"])
    pair = e["pair"]
    kind = type(pair).__name__
    x = pair._coords(h)
    E = se3.inverse(pair._fk(x)) @ h
    if e["driven"]:   # a driven weld starts at r(0) = exp(s(0) axis)
        E = se3.inverse(se3.exp(e["law"].start_value() * np.asarray(e["axis"]))) @ h
    dist = float(np.linalg.norm(E[:3, 3]))
    ang = rotation_angle(E[:3, :3])
    names = f"{e['fa_name']} and {e['fb_name']}"
    hint = ("give poses that satisfy the pair, or give the far carrier no pose (pose=None) so "
            "that it is placed from the pair")
    if dist > tol_m:
        # a pair whose constraint wrenches hold all three forces holds its frames' origins together
        what = "origins" if {"f_x", "f_y", "f_z"} <= set(PAIR_TYPES[e["type"]].directions) else \
            "origins (less the pair's free translation)"
        raise ModelError(f"pair {e['name']!r} ({kind}): at the given poses its frames {names} are "
                         f"{dist:.6g} m apart ({what}; tolerance {tol_m:.2g} m) and {ang:.6g} rad "
                         f"apart in orientation; {hint}")
    if ang > POSE_TOL:
        if kind == "Fixed" and not e["driven"] and _plain(e["Ta"]) and _plain(e["Tb"]):
            R = np.eye(4)
            R[:3, :3] = h[:3, :3]
            return x, e["Ta"] @ R
        if kind == "Fixed":
            why = ("the pair is driven" if e["driven"] else
                   "a frame offset has a rotation of its own, so the frames and the given poses "
                   "state two different welds")
            raise ModelError(f"pair {e['name']!r} (Fixed): at the given poses its frames {names} are "
                             f"{ang:.6g} rad apart in orientation (tolerance {POSE_TOL:g} rad) and {why}; "
                             f"give poses that agree with the frames, frames without a rotated "
                             f"offset (the weld then holds the given relative orientation), or "
                             f"give the far carrier no pose (pose=None)")
        raise ModelError(f"pair {e['name']!r} ({kind}): at the given poses its frames {names} are "
                         f"{ang:.6g} rad apart in a constrained rotation (tolerance {POSE_TOL:g} "
                         f"rad; origins {dist:.6g} m apart); {hint}")
    return x, e["Ta"]


def _plain(T) -> bool:
    """A frame offset without a rotation of its own."""
    return bool(np.max(np.abs(np.asarray(T)[:3, :3] - np.eye(3))) <= 1e-12)


def place_tree(desc: ModelDescription):
    """Step 1: poses H (nc, 4, 4) and twists t (nc, 6) from the tree walk; returns (H, t,
    tree_pairs, frames_a): tree_pairs the set of pair indices used as tree edges, frames_a every
    pair's frame offset on a (with a Fixed pair's weld orientation taken from the given poses,
    see pair_reference). Raises ModelError when given poses violate a pair."""
    nc = len(desc.carriers)
    H = np.array([c["H0"] for c in desc.carriers], dtype=float).reshape(nc, 4, 4)
    T = np.array([c["t0"] for c in desc.carriers], dtype=float).reshape(nc, 6)
    given = desc.given
    tol_m = POSE_TOL * length_scale(desc)
    frames_a = [e["Ta"] for e in desc.pairs]
    link_of = {}
    for lk in desc.links.values():
        if lk.rigid:   # one carrier: placed like a body
            continue
        for k, c in enumerate(lk.nodes):
            link_of[c] = (lk, k)
    adj = {c: [] for c in range(-1, nc)}
    for ip, e in enumerate(desc.pairs):
        adj[e["a"]].append((ip, e["b"], True))
        adj[e["b"]].append((ip, e["a"], False))
    placed = {-1}
    tree_pairs = set()

    def G(c):
        """The pose the user gave carrier c (the ground: identity), else its placed pose."""
        return np.eye(4) if c < 0 else given.get(c, H[c])

    def place_link_from(c):
        lk, k = link_of[c]
        h = lk.length / lk.elements
        eps = desc.link_unstressed_strain(lk)
        out = []
        for j, cj in enumerate(lk.nodes):
            if cj == c:
                continue
            E = se3.exp((j - k) * h * eps)
            H[cj] = H[c] @ E
            T[cj] = se3.Ad(se3.inverse(E)) @ T[c] if T[c].any() else 0.0   # (a link at rest)
            placed.add(cj)
            out.append(cj)
        return out

    roots = [-1] + [c for c in range(nc)]
    for root in roots:
        if root in placed and root != -1:
            continue
        if root != -1:
            placed.add(root)
        queue = deque([root])
        if root in link_of:
            queue.extend(place_link_from(root))
        while queue:
            c = queue.popleft()
            for ip, w, forward in adj[c]:
                if w in placed or ip in tree_pairs:
                    continue
                e = desc.pairs[ip]
                tree_pairs.add(ip)
                k = e["k"]
                has_xd = e.get("has_xdot0", False)
                xd = e["xdot0"][:k] if has_xd else np.zeros(k)
                Hn = np.eye(4) if c < 0 else H[c]
                tn = np.zeros(6) if c < 0 else T[c]
                if e["has_x0"] or w not in given:
                    # placed from the pair at x0 (x = 0 if not given), moving with the near carrier
                    # at the rates xdot0 (0 if not given), unless the body's own twist was given
                    # (add_rigid_body(twist=...)) and the pair's rates were not: that twist is kept,
                    # as below (a Free pair's body given v = 1 m/s started at rest without a word)
                    H[w], Tw = pose_across(e, e["x0"][:k], xd, Hn, tn, forward, frames_a[ip])
                    if k == 0 or has_xd or w not in desc.twist_given:
                        T[w] = Tw
                else:
                    # the given poses are the reference: the pair's coordinates (Fixed: its weld
                    # orientation) are those of its frames at the given poses, and w keeps its
                    # pose relative to c (exactly its given pose when c kept its own)
                    x, frames_a[ip] = pair_reference(e, G(e["a"]), G(e["b"]), tol_m)
                    _, Tw = pose_across(e, x, xd, Hn, tn, forward, frames_a[ip])
                    H[w] = Hn @ se3.inverse(G(c)) @ given[w]
                    # rates: xdot0 (0 if not given) like the branch above; only a twist the
                    # user gave (add_rigid_body(twist=...)) is kept as given
                    if k == 0 or has_xd or w not in desc.twist_given:
                        T[w] = Tw
                placed.add(w)
                queue.append(w)
                if w in link_of:
                    queue.extend(place_link_from(w))
    # loop-closing pairs between two given poses: the same check (and a Fixed pair's reference)
    for ip, e in enumerate(desc.pairs):
        if ip in tree_pairs:
            continue
        if (e["a"] < 0 or e["a"] in given) and (e["b"] < 0 or e["b"] in given):
            _, frames_a[ip] = pair_reference(e, G(e["a"]), G(e["b"]), tol_m)
    return H, T, tree_pairs, frames_a

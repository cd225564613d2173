"""Initial configuration and redundant constraints of a mechanism (paper Sec. V, DESIGN.md §5-6).

Three steps, run by :class:`phmech.Mechanism` each time it builds its core model:

1. **Tree placement.** A breadth-first walk of the kinematic graph G_K ∪ G_F from the ground
   places every carrier it reaches: across a pair (a, b) the far frame sits at
   F_b = F_a exp(sum x_i psi_i) (or F_a = F_b h(x)^-1 when the walk goes from b to a), with the
   pair's joint coordinates ``x0`` and rates ``xdot0``; a flexible link is placed unstressed (its
   unstressed shape, moving rigidly) from whichever node the walk reaches first.
   *Rule:* a pair *fixes* the relative pose when it is a Fixed pair (k = 0) or when ``x0`` was
   given; then the tree placement wins over any pose given for the carrier it reaches. Across a
   pair without ``x0`` the carrier keeps the pose (and twist) it was given -- or, if it was given
   none, is placed at x = 0. Carriers not connected to the ground keep their given poses (a free
   body is allowed; it may also be tied to the ground with ``ph.Free()``).
2. **Loop closure.** Loop-closing pairs are then met by a Newton projection: all constraint rows
   g(H) = 0 and the links' unstressed shape are hard equations; the joint coordinates of the
   pairs are soft targets (those given through ``x0`` weigh 10^3 times more than the tree's
   own values); the correction is the minimum-norm one on the tangent space among the solutions.
   If the residual stays above 1e-9 the loop cannot close and a ModelError names it (its pairs
   and links, from :meth:`MechanismGraph.loops`).
3. **Redundant constraints.** At the closed configuration the rank of the full constraint
   Jacobian G is found from its singular values (tolerance 1e-9 times the largest); rows are taken
   greedily -- tree pairs first, loop-closing pairs last -- and a row whose component outside the
   span of the rows already taken is below that tolerance is redundant. Redundant rows are named
   (pair, direction) and dropped from the DAE, so IDA's iteration matrix stays nonsingular.
"""
from __future__ import annotations

from collections import deque

import numpy as np

from . import _core, se3
from ._core import ModelError

#: Names of the constraint-wrench directions W^C of each pair type (core phm_pair_type order),
#: in the pair frame F_b whose z axis is the joint axis (Universal: x = axis1, y = axis2).
DIRECTIONS = {
    0: ("tau_x", "tau_y", "tau_z", "f_x", "f_y", "f_z"),     # fixed
    1: ("tau_x", "tau_y", "f_x", "f_y", "f_z"),              # revolute
    2: ("tau_x", "tau_y", "tau_z", "f_x", "f_y"),            # prismatic
    3: ("tau_x", "tau_y", "f_x", "f_y", "f_z-pitch*tau_z"),  # helical
    4: ("tau_x", "tau_y", "f_x", "f_y"),                     # cylindrical
    5: ("tau_n", "f_x", "f_y", "f_z"),                       # universal (tau_n = axis1 x axis2)
    6: ("f_x", "f_y", "f_z"),                                # spherical
    7: ("tau_x", "tau_y", "f_z"),                            # planar
    8: (),                                                   # free
}

CLOSURE_TOL = 1e-9   # max |g| accepted after the loop-closure projection
RANK_TOL = 1e-9      # relative to the largest singular value of G


def _twist_across(e, pair, x, xd, Ha, ta, forward):
    """Pose and twist of the far carrier of pair entry e, the near one being at (Ha, ta)."""
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
    if forward:   # near = a, far = b
        Fb = Ha @ e["Ta"] @ h
        tFa = se3.Ad(se3.inverse(e["Ta"])) @ ta
        tFb = se3.Ad(hi) @ tFa + trel
        return Fb @ se3.inverse(e["Tb"]), se3.Ad(e["Tb"]) @ tFb
    Fa = Ha @ e["Tb"] @ hi                          # here Ha is H_b
    tFb = se3.Ad(se3.inverse(e["Tb"])) @ ta
    tFa = se3.Ad(h) @ (tFb - trel)
    return Fa @ se3.inverse(e["Ta"]), se3.Ad(e["Ta"]) @ tFa


def place_tree(mech):
    """Step 1: poses H (nc, 4, 4) and twists t (nc, 6) from the tree walk; returns (H, t,
    tree_pairs) with tree_pairs the set of pair indices used as tree edges."""
    nc = len(mech._car)
    H = np.array([c["H0"] for c in mech._car], dtype=float).reshape(nc, 4, 4)
    T = np.array([c["t0"] for c in mech._car], dtype=float).reshape(nc, 6)
    link_of = {}
    for lk in mech._links.values():
        for k, c in enumerate(lk.nodes):
            link_of[c] = (lk, k)
    adj = {c: [] for c in range(-1, nc)}
    for ip, e in enumerate(mech._pairs):
        adj[e["a"]].append((ip, e["b"], True))
        adj[e["b"]].append((ip, e["a"], False))
    placed = {-1}
    tree_pairs = set()

    def place_link_from(c):
        lk, k = link_of[c]
        h = lk.length / lk.elements
        eps = mech._el[mech._el_first[lk.name]]["eps"]
        out = []
        for j, cj in enumerate(lk.nodes):
            if cj == c:
                continue
            E = se3.exp((j - k) * h * np.asarray(eps))
            H[cj] = H[c] @ E
            T[cj] = se3.Ad(se3.inverse(E)) @ T[c]
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
                e = mech._pairs[ip]
                tree_pairs.add(ip)
                k = e["k"]
                fixes = k == 0 or e["has_x0"] or e.get("has_xdot0", False)
                if fixes or not mech._pose_given.get(w, False):
                    x = e["x0"][:k]
                    xd = e["xdot0"][:k] if e.get("has_xdot0", False) else np.zeros(k)
                    Hn = np.eye(4) if c < 0 else H[c]
                    tn = np.zeros(6) if c < 0 else T[c]
                    H[w], T[w] = _twist_across(e, e["pair"], x, xd, Hn, tn, forward)
                placed.add(w)
                queue.append(w)
                if w in link_of:
                    queue.extend(place_link_from(w))
    return H, T, tree_pairs


def _element_residual(mech, H):
    """Unstressed-shape residual log(H_a^-1 H_b) - h eps_hat of every element and its Jacobian."""
    nc = len(mech._car)
    ne = len(mech._el)
    r = np.zeros(6 * ne)
    J = np.zeros((6 * ne, 6 * nc))
    for i, el in enumerate(mech._el):
        X = se3.log(se3.inverse(H[el["a"]]) @ H[el["b"]])
        r[6 * i:6 * i + 6] = X - el["h"] * np.asarray(el["eps"])
        J[6 * i:6 * i + 6, 6 * el["a"]:6 * el["a"] + 6] = -se3.dexp_inv(X)
        J[6 * i:6 * i + 6, 6 * el["b"]:6 * el["b"] + 6] = se3.dexp_inv(-X)
    return r, J


def _retract_all(H, delta):
    out = H.copy()
    for c in range(H.shape[0]):
        d = delta[6 * c:6 * c + 6]
        if np.any(d):
            out[c] = H[c] @ se3.exp(d)
    return out


def _joint_jacobian(model, H, xref, rows):
    nc = H.shape[0]
    Jx = np.zeros((len(rows), 6 * nc))
    eps = 1e-7
    for col in range(6 * nc):
        d = np.zeros(6 * nc)
        d[col] = eps
        Jx[:, col] = (_core.model_joints(model, _retract_all(H, d), xref)[rows] -
                      _core.model_joints(model, _retract_all(H, -d), xref)[rows]) / (2 * eps)
    return Jx


def close_loops(mech, model, H, tree_pairs, xref, loops_of):
    """Step 2: Newton projection onto g(H) = 0 with the links unstressed (see the module doc).
    ``xref``: joint branch references (nj); ``loops_of(bad_pairs)``: loop descriptions for the
    error message. Returns the closed poses. The given x0 are first held exactly (hard
    equations); if the loops cannot close so, they become soft targets of weight 10^3."""
    g, G, _ = _core.model_constraints_full(model, H, xref, 0.0)
    if g.size == 0 or np.max(np.abs(g)) < 1e-12:
        return H
    try:
        return _close(mech, model, H, tree_pairs, xref, loops_of, hard_x0=True)
    except ModelError:
        return _close(mech, model, H, tree_pairs, xref, loops_of, hard_x0=False)


def _close(mech, model, H, tree_pairs, xref, loops_of, hard_x0):
    nc = H.shape[0]
    # soft targets: joint coordinates of pairs with x0 (weight 1e3) and of tree pairs (weight 1)
    sizes = _core.model_sizes(model)[4]
    rows, target, weight, hard_rows, hard_target = [], [], [], [], []
    x_now = _core.model_joints(model, H, xref)
    for ip, e in enumerate(mech._pairs):
        _, _, j, k = sizes[ip]
        if k == 0:
            continue
        if e["has_x0"] and hard_x0:
            hard_rows += [j + c for c in range(k)]
            hard_target += list(e["x0"][:k])
        elif e["has_x0"] or ip in tree_pairs:
            w = 1e3 if e["has_x0"] else 1.0
            for c in range(k):
                rows.append(j + c)
                target.append(e["x0"][c] if e["has_x0"] else x_now[j + c])
                weight.append(w)
    rows, target, weight = np.array(rows, dtype=int), np.array(target), np.array(weight)
    hard_rows, hard_target = np.array(hard_rows, dtype=int), np.array(hard_target)
    best = None
    for it in range(40):
        g, G, _ = _core.model_constraints_full(model, H, xref, 0.0)
        re, Je = _element_residual(mech, H)
        A = np.vstack([G, Je])
        r = np.concatenate([g, re])
        if hard_rows.size:
            A = np.vstack([A, _joint_jacobian(model, H, xref, hard_rows)])
            r = np.concatenate([r, _core.model_joints(model, H, xref)[hard_rows] - hard_target])
        gn = np.max(np.abs(r)) if r.size else 0.0
        best = gn
        dp = -np.linalg.lstsq(A, r, rcond=None)[0]
        if rows.size:
            U, s, Vt = np.linalg.svd(A)
            rank = int(np.sum(s > RANK_TOL * s[0])) if s.size else 0
            N = Vt[rank:].T
            x0 = _core.model_joints(model, H, xref)
            Jx = _joint_jacobian(model, H, xref, rows)
            e = weight * (target - x0[rows])
            Wj = weight[:, None] * Jx
            M = np.vstack([Wj @ N, 1e-6 * np.eye(N.shape[1])])
            z = np.linalg.lstsq(M, np.concatenate([e - Wj @ dp, np.zeros(N.shape[1])]), rcond=None)[0]
            delta = dp + N @ z
        else:
            delta = dp
        H = _retract_all(H, delta)
        if gn < 1e-12 and np.max(np.abs(delta)) < 1e-10:
            break
    g, G, _ = _core.model_constraints_full(model, H, xref, 0.0)
    re, _ = _element_residual(mech, H)
    gn = max(np.max(np.abs(g)) if g.size else 0.0, np.max(np.abs(re)) if re.size else 0.0)
    if hard_rows.size:
        gn = max(gn, np.max(np.abs(_core.model_joints(model, H, xref)[hard_rows] - hard_target)))
    if not gn <= CLOSURE_TOL:
        # name the pairs still violated and the loops through them
        bad = []
        row = 0
        for e in mech._pairs:
            m = len(DIRECTIONS[e["type"]])
            if m and np.max(np.abs(g[row:row + m])) > CLOSURE_TOL:
                bad.append(e["name"])
            row += m
        raise ModelError(f"initial configuration: loop cannot close (|g| = {gn:.3e} after the "
                         f"Newton projection; pairs still violated: {bad}); loops: "
                         f"{loops_of(bad)}; check the pairs' frames and x0 along the loop")
    return H


def redundant_rows(mech, G, tree_pairs):
    """Step 3: the drop mask of each pair and the list of (pair name, direction) dropped."""
    order = []   # (row, pair index, local row), tree pairs first
    rowf = 0
    spans = []
    for ip, e in enumerate(mech._pairs):
        m = len(DIRECTIONS[e["type"]])
        spans.append((rowf, m))
        rowf += m
    for pref in (True, False):
        for ip, e in enumerate(mech._pairs):
            if (ip in tree_pairs) == pref:
                r0, m = spans[ip]
                order += [(r0 + r, ip, r) for r in range(m)]
    masks = [0] * len(mech._pairs)
    if G.shape[0] == 0:
        return masks, []
    s = np.linalg.svd(G, compute_uv=False)
    if s.size == 0 or s[0] == 0:
        return masks, []
    tol = RANK_TOL * s[0]
    rank = int(np.sum(s > tol))
    Q = np.zeros((0, G.shape[1]))
    keep = []
    for row, ip, r in order:
        v = G[row].copy()
        for _ in range(2):
            v -= Q.T @ (Q @ v)
        nv = np.linalg.norm(v)
        if nv > tol:
            Q = np.vstack([Q, v / nv])
            keep.append(row)
    if len(keep) != rank:   # borderline conditioning: fall back to pivoted QR (LAPACK dgeqp3)
        import scipy.linalg
        _, _, piv = scipy.linalg.qr(G.T, mode="economic", pivoting=True)
        keep = list(piv[:rank])
    keep = set(keep)
    dropped = []
    for row, ip, r in sorted(order):
        if row not in keep:
            masks[ip] |= 1 << r
            dropped.append((mech._pairs[ip]["name"], DIRECTIONS[mech._pairs[ip]["type"]][r]))
    return masks, dropped

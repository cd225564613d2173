"""Initial configuration and redundant constraints of a mechanism (paper Sec. V).

It works on a model description (phmech.description.ModelDescription) and never changes it.
Three steps (``initial_state``), run once per description by :class:`phmech.Mechanism`, which
keeps the result until the next ``add_*`` call:

1. **Tree placement.** A breadth-first walk of the kinematic graph G_K ∪ G_F from the ground
   places every carrier it reaches: across a pair (a, b) the far frame sits at
   F_b = F_a exp(sum x_i psi_i) (or F_a = F_b h(x)^-1 when the walk goes from b to a), with the
   pair's joint coordinates and rates; a flexible link is placed unstressed (its unstressed
   shape, moving rigidly) from whichever node the walk reaches first.
   *Rule* (docs/user_guide.md, "Initial configuration"): the poses the user gave (``pose=``;
   the ground is always given) are a reference configuration.
   - Across a pair with ``x0``, or to a carrier without a given pose, the far carrier is placed
     from the pair at ``x0`` (x = 0 if not given), with rates ``xdot0``: ``x0`` wins over a
     given pose.
   - Across a pair without ``x0`` to a carrier with a given pose, the pair's coordinates are
     those of its two frames at the given poses (pair_reference; for a carrier without a given
     pose its placed pose counts), and the far carrier keeps its given pose relative to the
     near one -- exactly its given pose unless an ``x0`` up the tree moved the near one. A
     Fixed pair welds its frames in their relative orientation at the given poses (its frame
     offset on a, ``InitialState.frames_a``) when neither frame offset has a rotation of its
     own. Given poses that violate a pair's constrained directions (origins apart, a
     revolute's axes not parallel, a rotated Fixed frame that disagrees) raise ModelError
     naming the pair, its frames and the mismatch in m and rad; tolerance POSE_TOL (rad) and
     POSE_TOL * L (m), L = length_scale(desc). Loop-closing pairs between two given poses are
     checked the same way.
   Carriers not connected to the ground keep their given poses (a free body is allowed; it may
   also be tied to the ground with ``ph.Free()``). A group of carriers that no pair or
   spring-damper joins to the ground (``free_groups``) is reported, since a forgotten pair leaves
   one (Mechanism warns, UnattachedWarning, unless a ``ph.Free()`` pair says it is meant).
2. **Loop closure.** Loop-closing pairs are then met by a Newton projection: all constraint rows
   g(H) = 0 and the links' unstressed shape are hard equations; the joint coordinates of the
   pairs are soft targets (those given through ``x0`` weigh 10^3 times more than the tree's
   own values); the correction is the minimum-norm one on the tangent space among the solutions.
   If the residual stays above 1e-9 the loop cannot close and a ModelError names it (its pairs
   and links, from :meth:`MechanismGraph.loops`). How far this moved each given x0 and each
   given pose the tree kept is ``initial_adjustments``; Mechanism reports it (a warning, or a
   ModelError with ``strict=True``).
3. **Redundant constraints.** At the closed configuration the rank of the full constraint
   Jacobian G is found from its singular values (tolerance 1e-9 times the largest); rows are taken
   greedily -- tree pairs first, loop-closing pairs last -- and a row whose component outside the
   span of the rows already taken is below that tolerance is redundant. Redundant rows are named
   (pair, direction) and dropped from the DAE, so IDA's iteration matrix stays nonsingular.
"""
from __future__ import annotations

import dataclasses
import re
from typing import Optional

import numpy as np

from . import _core, _marshal, se3
from ._errors import ConstraintError, ModelError
from .description import ModelDescription
from .frames import Frame
from .graphs import mechanism_graphs
from .pairs import row_names
from ._placement import POSE_TOL, length_scale, place_tree, rotation_angle
from .results import InitialAdjustment

CLOSURE_TOL = 1e-9   # max |g| accepted after the loop-closure projection
RANK_TOL = 1e-9      # relative to the largest singular value of G


#: the pairs' position tolerance during a simulation (csrc/dae/dae.h, DAE_CONSTRAINT_TOL): rad,
#: and m times the mechanism's size (csrc/dae/watch.c, dae_length_scale)
CONSTRAINT_TOL = 1e-6

_OPENED = re.compile(r"constraint opened: pair #(\d+) row (\d+) \((redundant at the start, not held|held)\): "
                     r"position residual (\S+) (m|rad) above the tolerance (\S+) (?:m|rad) at t = (\S+) s")


def constraint_error(desc: ModelDescription, message: str) -> Optional[ConstraintError]:
    """The ConstraintError of a core failure message that reports an opened pair (csrc/dae/watch.c),
    with the pair and its row named; None for any other message."""
    mt = _OPENED.search(message)
    if mt is None:
        return None
    ip, r = int(mt.group(1)), int(mt.group(2))
    e = desc.pairs[ip]
    names = row_names(e)
    direction = names[r] if r < len(names) else f"row {r}"
    redundant = mt.group(3).startswith("redundant")
    res, unit, tol, t = float(mt.group(4)), mt.group(5), float(mt.group(6)), float(mt.group(7))
    why = ("left out as redundant at the initial configuration, it is not redundant here: the "
           "mechanism cannot move as its pairs say (remove the over-constraint, e.g. a spherical or "
           "cylindrical pair instead of a revolute, or make a link flexible)" if redundant else
           "a row the integrator holds: the step could not keep it (tighten rtol/atol, or look for "
           "a singular configuration)")
    err = ConstraintError(f"pair '{e['name']}' came apart at t = {t:.6g} s: its {direction} "
                          f"constraint is off by {res:.3g} {unit}, tolerance {tol:.3g} {unit}; {why}")
    err.pair, err.direction, err.redundant = e["name"], direction, redundant
    err.residual, err.tolerance, err.unit, err.time = res, tol, unit, t
    return err


@dataclasses.dataclass
class InitialState:
    """What the three steps give for a description: the closed ``poses`` (nc, 4, 4) and body
    ``twists`` (nc, 6); ``x0`` (npairs, 6), the pairs' joint coordinates (given x0 replaced by
    the coordinates reached, on their branch); ``drop_masks``, per pair the bits of its
    redundant constraint rows; ``frames_a``, every pair's frame offset on a (a Fixed pair's weld
    orientation taken from the given poses); ``redundant``, the (pair name, direction) rows
    dropped; ``adjustments``, the InitialAdjustment rows; ``tree``, the pairs that are tree edges
    (place_tree); ``unattached``, the FreeGroup rows (free_groups)."""
    poses: np.ndarray
    twists: np.ndarray
    x0: np.ndarray
    drop_masks: list
    frames_a: list
    redundant: list
    adjustments: list
    tree: frozenset = frozenset()
    unattached: list = dataclasses.field(default_factory=list)


def _element_strains(desc: ModelDescription, H) -> np.ndarray:
    """X_i = log(H_a^-1 H_b) of every element i, (ne, 6)."""
    return np.array([se3.log(se3.inverse(H[el["a"]]) @ H[el["b"]]) for el in desc.elements]).reshape(-1, 6)


def _element_residual(desc: ModelDescription, H):
    """Unstressed-shape residual log(H_a^-1 H_b) - h eps_hat of every element and its Jacobian
    (dense, (6 ne, 6 nc))."""
    nc = len(desc.carriers)
    ne = len(desc.elements)
    r = np.zeros(6 * ne)
    J = np.zeros((6 * ne, 6 * nc))
    for i, (el, X) in enumerate(zip(desc.elements, _element_strains(desc, H))):
        r[6 * i:6 * i + 6] = X - el["h"] * np.asarray(el["eps"])
        J[6 * i:6 * i + 6, 6 * el["a"]:6 * el["a"] + 6] = -se3.dexp_inv(X)
        J[6 * i:6 * i + 6, 6 * el["b"]:6 * el["b"] + 6] = se3.dexp_inv(-X)
    return r, J


def _element_rates(desc: ModelDescription, H, t) -> np.ndarray:
    """The elements' strain rates times h, Je t = dexp_{-X}^-1 t_b - dexp_X^-1 t_a (6 ne,),
    without forming Je (the rows of _element_residual's Jacobian times the twists t (6 nc,))."""
    if not desc.elements:
        return np.zeros(0)
    X = _element_strains(desc, H)
    tw = t.reshape(-1, 6)
    a = [el["a"] for el in desc.elements]
    b = [el["b"] for el in desc.elements]
    return (np.einsum("nij,nj->ni", se3.dexp_inv(-X), tw[b])
            - np.einsum("nij,nj->ni", se3.dexp_inv(X), tw[a])).ravel()


def _retract_all(H, delta):
    out = H.copy()
    for c in range(H.shape[0]):
        d = delta[6 * c:6 * c + 6]
        if np.any(d):
            out[c] = H[c] @ se3.exp(d)
    return out


def _joint_jacobian(model, H, xref, rows, carriers=None):
    """d(joint coordinates[rows]) / d(carrier twists) (len(rows), 6 nc) by central differences.
    ``carriers``: the carriers of the pairs owning ``rows`` (None: all); the other columns are
    zero (a pair's coordinates depend on its two carriers' poses alone), so only these are
    perturbed, one carrier at a time: O(nc) instead of O(nc^2) (a 1000-element cable's
    initial state took 30 s here), the same numbers."""
    nc = H.shape[0]
    Jx = np.zeros((len(rows), 6 * nc))
    eps = 1e-7
    Hd = H.copy()
    for c in (range(nc) if carriers is None else sorted({c for c in carriers if c >= 0})):
        for k in range(6):
            d = np.zeros(6)
            d[k] = eps
            Hd[c] = H[c] @ se3.exp(d)
            jp = _core.model_joints(model, Hd, xref)[rows]
            Hd[c] = H[c] @ se3.exp(-d)
            Jx[:, 6 * c + k] = (jp - _core.model_joints(model, Hd, xref)[rows]) / (2 * eps)
        Hd[c] = H[c]
    return Jx


def _pair_carriers(desc: ModelDescription, pairs) -> list:
    """The carriers (>= 0) the pairs with indices ``pairs`` connect."""
    return [c for ip in pairs for c in (desc.pairs[ip]["a"], desc.pairs[ip]["b"]) if c >= 0]


def _loops_through(desc: ModelDescription, pairs: list) -> list:
    """The loops (lists of pair and link names) through any of ``pairs``; all loops if none."""
    loops = mechanism_graphs(desc).loops()
    hit = [lp for lp in loops if set(lp) & set(pairs)]
    return hit or loops


def close_loops(desc: ModelDescription, model, H, tree_pairs, xref):
    """Step 2: Newton projection onto g(H) = 0 with the links unstressed (see the module doc).
    ``xref``: joint branch references (nj). Returns the closed poses (H itself when it already
    closes). The given x0 are first held exactly (hard equations); if the loops cannot close
    so, they become soft targets of weight 10^3."""
    g, G, _ = _core.model_constraints_full(model, H, xref, 0.0)
    if g.size == 0 or np.max(np.abs(g)) < 1e-12:
        return H
    try:
        return _close(desc, model, H, tree_pairs, xref, hard_x0=True)
    except ModelError:
        return _close(desc, model, H, tree_pairs, xref, hard_x0=False)


def _close(desc: ModelDescription, model, H, tree_pairs, xref, hard_x0):
    # soft targets: joint coordinates of pairs with x0 (weight 1e3) and of tree pairs (weight 1)
    sizes = _core.model_sizes(model)[4]
    rows, target, weight, hard_rows, hard_target = [], [], [], [], []
    hard_pairs, soft_pairs = [], []
    x_now = _core.model_joints(model, H, xref)
    for ip, e in enumerate(desc.pairs):
        _, _, j, k = sizes[ip]
        if k == 0:
            continue
        if e["has_x0"] and hard_x0:
            hard_rows += [j + c for c in range(k)]
            hard_target += list(e["x0"][:k])
            hard_pairs.append(ip)
        elif e["has_x0"] or ip in tree_pairs:
            soft_pairs.append(ip)
            w = 1e3 if e["has_x0"] else 1.0
            for c in range(k):
                rows.append(j + c)
                target.append(e["x0"][c] if e["has_x0"] else x_now[j + c])
                weight.append(w)
    rows, target, weight = np.array(rows, dtype=int), np.array(target), np.array(weight)
    hard_rows, hard_target = np.array(hard_rows, dtype=int), np.array(hard_target)
    for it in range(40):
        g, G, _ = _core.model_constraints_full(model, H, xref, 0.0)
        re, Je = _element_residual(desc, H)
        A = np.vstack([G, Je])
        r = np.concatenate([g, re])
        if hard_rows.size:
            A = np.vstack([A, _joint_jacobian(model, H, xref, hard_rows, _pair_carriers(desc, hard_pairs))])
            r = np.concatenate([r, _core.model_joints(model, H, xref)[hard_rows] - hard_target])
        gn = np.max(np.abs(r)) if r.size else 0.0
        dp = -np.linalg.lstsq(A, r, rcond=None)[0]
        if rows.size:
            U, s, Vt = np.linalg.svd(A)
            rank = int(np.sum(s > RANK_TOL * s[0])) if s.size else 0
            N = Vt[rank:].T
            x0 = _core.model_joints(model, H, xref)
            Jx = _joint_jacobian(model, H, xref, rows, _pair_carriers(desc, soft_pairs))
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
    re, _ = _element_residual(desc, H)
    gn = max(np.max(np.abs(g)) if g.size else 0.0, np.max(np.abs(re)) if re.size else 0.0)
    if hard_rows.size:
        gn = max(gn, np.max(np.abs(_core.model_joints(model, H, xref)[hard_rows] - hard_target)))
    if not gn <= CLOSURE_TOL:
        # name the pairs still violated and the loops through them
        bad = []
        row = 0
        for e in desc.pairs:
            m = len(row_names(e))
            if m and np.max(np.abs(g[row:row + m])) > CLOSURE_TOL:
                bad.append(e["name"])
            row += m
        raise ModelError(f"initial configuration: loop cannot close (|g| = {gn:.3e} after the "
                         f"Newton projection; pairs still violated: {bad}); loops: "
                         f"{_loops_through(desc, bad)}; check the pairs' frames and x0 along the loop")
    return H


def close_rates(desc: ModelDescription, model, H, T, tree_pairs, xref):
    """Step 2b: twists T (nc, 6) meeting every pair's velocity constraint with the links moving
    rigidly (strain rates zero), closest to the tree's joint rates. The tree walk gives rates
    that ignore loop-closing pairs (a slider-crank's rod turns with its crank); projected later
    carrier by carrier (the core's minimum-norm velocity projection), the correction would land
    on the nodes a pair touches only, a velocity jump along a flexible link that strikes its
    mesh modes (a slider-crank's 0.3 m steel rod got 13 mJ of elastic energy in 1 ms, which the
    integrator's dissipation of the unresolved band then removed: 1.4 % of the energy). Hard:
    the pairs' velocity rows G t = -dg/dt (driven pairs' rates included), the elements' rates
    Je t = 0 and the given xdot0 (if they cannot all hold, the xdot0 become soft targets of
    weight 10^3, as the given x0 in close_loops); soft: the tree pairs' joint rates (weight 1),
    the correction being the minimum-norm one among the solutions. Returns (T, reached): T
    unchanged (the same array) when it already meets the hard rows (to 1e-12); reached: joint
    row -> the initial rate of every given xdot0 (for initial_adjustments)."""
    eps = 1e-6
    g, G, _ = _core.model_constraints_full(model, H, xref, 0.0)
    gp = _core.model_constraints_full(model, H, xref, eps)[0]
    gm = _core.model_constraints_full(model, H, xref, -eps)[0]
    rate_g = -(gp - gm) / (2 * eps)
    t = T.reshape(-1)
    scale = max(1.0, float(np.max(np.abs(t)))) if t.size else 1.0
    sizes = _core.model_sizes(model)[4]
    given, given_rate, tree, given_pairs, tree_pairs_k = [], [], [], [], []
    for ip, e in enumerate(desc.pairs):
        _, _, j, k = sizes[ip]
        if k and e.get("has_xdot0", False):
            given += [j + c for c in range(k)]
            given_rate += list(e["xdot0"][:k])
            given_pairs.append(ip)
        elif k and ip in tree_pairs:
            tree += [j + c for c in range(k)]
            tree_pairs_k.append(ip)
    given, given_rate, tree = np.array(given, dtype=int), np.array(given_rate), np.array(tree, dtype=int)
    Jg = _joint_jacobian(model, H, xref, given, _pair_carriers(desc, given_pairs)) if given.size else np.zeros((0, t.size))

    def reached(t):
        return dict(zip(given.tolist(), (Jg @ t).tolist()))

    # the hard rows already hold: checked without forming the elements' (dense) Jacobian
    # (Je t is linear in t: zero for a scene at rest, without evaluating the elements)
    Je_t = _element_rates(desc, H, t) if np.any(t) else np.zeros(6 * len(desc.elements))
    miss = np.concatenate([rate_g - G @ t, Je_t])
    if (miss.size == 0 or np.max(np.abs(miss)) <= 1e-12 * scale) and \
            np.all(np.abs(Jg @ t - given_rate) <= 1e-12 * scale):
        return T, reached(t)
    _, Je = _element_residual(desc, H)
    A = np.vstack([G, Je])
    rhs = np.concatenate([rate_g, np.zeros(Je.shape[0])])
    Jt = _joint_jacobian(model, H, xref, tree, _pair_carriers(desc, tree_pairs_k)) if tree.size else np.zeros((0, t.size))
    for hard in (True, False):
        if hard:
            Ah, bh = np.vstack([A, Jg]), np.concatenate([rhs, given_rate])
            Js, target, weight = Jt, Jt @ t, np.ones(tree.size)
        else:
            Ah, bh = A, rhs
            Js = np.vstack([Jg, Jt])
            target = np.concatenate([given_rate, Jt @ t])
            weight = np.concatenate([np.full(given.size, 1e3), np.ones(tree.size)])
        r = bh - Ah @ t
        dp = np.linalg.lstsq(Ah, r, rcond=None)[0]
        if Js.shape[0]:
            _, sv, Vt = np.linalg.svd(Ah)
            rank = int(np.sum(sv > RANK_TOL * sv[0])) if sv.size else 0
            N = Vt[rank:].T
            Wj = weight[:, None] * Js
            M = np.vstack([Wj @ N, 1e-6 * np.eye(N.shape[1])])
            z = np.linalg.lstsq(M, np.concatenate([weight * (target - Js @ t) - Wj @ dp,
                                                   np.zeros(N.shape[1])]), rcond=None)[0]
            dp = dp + N @ z
        if not hard or np.max(np.abs(bh - Ah @ (t + dp))) <= 1e-9 * scale:
            return (t + dp).reshape(T.shape), reached(t + dp)


def redundant_rows(desc: ModelDescription, G, tree_pairs):
    """Step 3: the drop mask of each pair and the list of (pair name, direction) dropped.

    Greedy in the order tree pairs, then loop-closing pairs (module doc). The rows of the tree
    pairs are independent (each tree pair holds its own child carrier: ordered by depth, their
    child columns make G block-triangular with the pair's full-rank rows on the diagonal), so
    only the loop-closing rows are tested: each against the span of the tree rows (a sparse
    solve with G_t G_t^T, O(N) for a chain or a tree) and of the loop rows kept before it. The
    dense SVD of the whole G this replaces took 24 s for a chain of 200 bodies."""
    import scipy.linalg
    import scipy.sparse
    import scipy.sparse.linalg

    masks = [0] * len(desc.pairs)
    if G.shape[0] == 0:
        return masks, []
    spans, rowf = [], 0
    for e in desc.pairs:
        m = len(row_names(e))
        spans.append((rowf, m))
        rowf += m
    order = [(r0 + r, ip, r) for pref in (True, False) for ip, (r0, m) in enumerate(spans)
             if (ip in tree_pairs) == pref for r in range(m)]
    n_tree = sum(ip in tree_pairs for _, ip, _ in order)
    if n_tree == len(order):   # no loop-closing row: nothing to test (a tree, a chain)
        return masks, []
    Gs = scipy.sparse.csr_matrix(G)
    tol = RANK_TOL * _largest_singular_value(Gs)
    if not tol > 0:
        return masks, []
    # the candidates: the loop rows, less their components in the span of the tree rows
    cand = order[n_tree:]
    Gl = Gs[[row for row, _, _ in cand]].toarray()
    R = Gl
    if n_tree:
        Gt = Gs[[row for row, _, _ in order[:n_tree]]]
        try:
            lu = scipy.sparse.linalg.splu((Gt @ Gt.T).tocsc())
            R = Gl - (Gt.T @ lu.solve(Gt @ Gl.T)).T
        except RuntimeError:  # singular: tree rows dependent after all; every row a candidate
            cand, R = order, G[[row for row, _, _ in order]]
    # greedy Gram-Schmidt among them, in order; the count checked against their numerical rank
    Q, keep = np.zeros((0, G.shape[1])), []
    for i, v in enumerate(R):
        v = v.copy()
        for _ in range(2):
            v -= Q.T @ (Q @ v)
        nv = np.linalg.norm(v)
        if nv > tol:
            Q = np.vstack([Q, v / nv])
            keep.append(i)
    s = np.linalg.svd(R, compute_uv=False)
    rank = int(np.sum(s > tol))
    if len(keep) != rank:   # borderline conditioning: pivoted QR (LAPACK dgeqp3) instead
        _, _, piv = scipy.linalg.qr(R.T, mode="economic", pivoting=True)
        keep = list(piv[:rank])
    keep = set(keep)
    dropped = []
    for i, (row, ip, r) in sorted(enumerate(cand), key=lambda t: t[1][0]):
        if i not in keep:
            masks[ip] |= 1 << r
            dropped.append((desc.pairs[ip]["name"], row_names(desc.pairs[ip])[r]))
    return masks, dropped


def _largest_singular_value(Gs) -> float:
    """The largest singular value of the sparse G (power iteration on G^T G; 1e-6 relative is
    plenty for a rank tolerance)."""
    x = np.random.default_rng(0).standard_normal(Gs.shape[1])   # deterministic, generic
    sig = 0.0
    for _ in range(500):
        y = Gs.T @ (Gs @ x)
        ny = np.linalg.norm(y)
        if ny == 0:
            return 0.0
        x = y / ny
        if abs(np.sqrt(ny) - sig) <= 1e-6 * np.sqrt(ny):
            return float(np.sqrt(ny))
        sig = np.sqrt(ny)
    return float(sig)


def initial_adjustments(desc: ModelDescription, H_tree, H, x, layout, rates) -> list:
    """InitialAdjustment rows: every given x0 (xdot0) coordinate against the reached x
    (``rates``: joint row -> reached rate), and every given pose the tree placement kept
    (H_tree) against the closed poses H. ``layout``: (row, m, joint, k) per pair (the core's)."""
    L = length_scale(desc)
    tol_m, tol_r = POSE_TOL * L, POSE_TOL
    rows = []
    for ip, e in enumerate(desc.pairs):
        _, _, j, k = layout[ip]
        for c in range(k):
            unit = e["pair"]._units[c]
            for key, given, now, u in (("x0", "has_x0", x, unit), ("xdot0", "has_xdot0", rates, unit + "/s")):
                if not e.get(given, False):
                    continue
                g, reached = float(e[key][c]), float(now[j + c])
                tol = tol_r * max(1.0, abs(g)) if unit == "rad" else tol_m * max(1.0, abs(g) / L)
                q = "x" if key == "x0" else "xdot"
                rows.append(InitialAdjustment(e["name"], q if k == 1 else f"{q}[{c}]", g,
                                              reached, abs(reached - g), u, tol))

    def moves(Ha, Hb):
        return (float(np.linalg.norm(Hb[:3, 3] - Ha[:3, 3])),
                rotation_angle(Ha[:3, :3].T @ Hb[:3, :3]))

    for name, cs in desc.groups():
        if not all(c in desc.given for c in cs):
            continue
        tree = [moves(desc.given[c], H_tree[c]) for c in cs]
        if max(d for d, _ in tree) > tol_m or max(a for _, a in tree) > tol_r:
            continue   # placed by an x0 up the tree: its pose is not the given one by request
        now = [moves(desc.given[c], H[c]) for c in cs]
        rows.append(InitialAdjustment(name, "position", None, None, max(d for d, _ in now), "m", tol_m))
        rows.append(InitialAdjustment(name, "orientation", None, None, max(a for _, a in now), "rad", tol_r))
    return rows


@dataclasses.dataclass(frozen=True)
class FreeGroup:
    """Bodies and links joined to one another (by pairs, links and spring-dampers) but not to
    the ground: ``names``, in the order they were added; ``missing``, the likely missing pair
    as (frame on the part joined to the ground, frame of this group, why: "start", "at" or
    "coincide"), or None (free_groups)."""
    names: tuple
    missing: Optional[tuple] = None


def free_groups(desc: ModelDescription, H) -> list:
    """The groups of carriers that no chain of pairs, links (their elements) and spring-dampers
    joins to the ground, as FreeGroup rows in the order added; ``H`` (nc, 4, 4): the tree's
    poses (place_tree). A modal link's mode sliders are pairs on its start, so they go with it.
    Loads and interactions join nothing: they are given wrenches.

    A group's likely missing pair: the frame that ``start=`` or ``at=`` placed one of its links
    or bodies at, when that frame is on the part joined to the ground (``desc.placed_at``); else
    a frame of the joined part (a body frame, a link node, the ground's origin) whose origin
    coincides with a body frame or a link end of the group, within POSE_TOL * length_scale (the
    tolerance of the given poses against the pairs)."""
    nc = len(desc.carriers)
    root = list(range(nc + 1))   # union-find over the carriers: carrier c at c + 1, ground at 0

    def find(i):
        while root[i] != i:
            root[i] = root[root[i]]
            i = root[i]
        return i

    for row in (*desc.pairs, *desc.elements, *desc.springs):
        root[find(row["a"] + 1)] = find(row["b"] + 1)

    def joined(c):
        return find(c + 1) == find(0)

    owners = sorted(desc.groups(), key=lambda g: min(g[1]))   # (name, carriers), order added
    parts: dict = {}
    for name, cs in owners:
        if not joined(cs[0]):
            parts.setdefault(find(cs[0] + 1), []).append(name)
    if not parts:
        return []
    # a body's frame, a link's start and end: the frames a pair most likely joins (the first is
    # the one at= or start= placed)
    ends = {b.name: [b.frame] for b in desc.bodies.values()}
    ends.update({lk.name: [lk.start, lk.end] for lk in desc.links.values()})
    anchors = [f for name, cs in owners if joined(cs[0])
               for f in (ends[name] if name in desc.bodies else
                         [desc.links[name].node(k) for k in range(len(desc.links[name].nodes))])]
    anchors.append(Frame(-1, np.eye(4), "ground"))
    tol = POSE_TOL * length_scale(desc)

    def origin(f):
        return f.T[:3, 3] if f.carrier < 0 else (H[f.carrier] @ f.T)[:3, 3]

    out = []
    for names in parts.values():
        placed = ((desc.placed_at.get(ends[nm][0].carrier), ends[nm][0],
                   "at" if nm in desc.bodies else "start") for nm in names)
        missing = next((p for p in placed if p[0] is not None and joined(p[0].carrier)), None)
        if missing is None:
            mine = [f for nm in names for f in ends[nm]]
            missing = next(((a, f, "coincide") for f in mine for a in anchors
                            if np.linalg.norm(origin(f) - origin(a)) <= tol), None)
        out.append(FreeGroup(tuple(names), missing))
    return out


def frame_words(desc: ModelDescription, f: Frame) -> str:
    """A frame as a message names it: "the ground", "the ground at (0, 0, 1)", "'hub'",
    "'hub' at (0.3, 0, 0)", "'arm'.start"; a frame the user named: "'elbow' (on body 'hub')"."""
    owner = "ground" if f.carrier < 0 else \
        next(nm for nm, cs in desc.groups() if f.carrier in cs)
    name = f.name or ""
    if name == owner or name.startswith((owner + " ", owner + ".")):
        return ("the ground" if f.carrier < 0 else repr(owner)) + name[len(owner):]
    return f"{name!r} (on {desc.carrier_name(f.carrier)})" if name else desc.carrier_name(f.carrier)


def unattached_message(desc: ModelDescription, groups: list) -> str:
    """The UnattachedWarning text for the FreeGroup rows ``groups``: who is free, how to say it
    is meant (a Free pair), and the likely missing pairs."""
    many = len(groups) > 1
    text = (f"bodies/links {' and '.join(str(list(g.names)) for g in groups)} are not connected to "
            f"the ground by any pair or spring-damper: they fly freely (under gravity they fall). "
            f"If that is intended, join {'each group' if many else 'them'} to the ground with "
            f"ph.Free() (no constraint) to say so; if not, add the missing pair")
    why = {"start": "where start= placed it", "at": "where at= placed it",
           "coincide": "which coincide"}
    hints = [f"between {frame_words(desc, g.missing[0])} and {frame_words(desc, g.missing[1])}, "
             f"{why[g.missing[2]]}" for g in groups if g.missing]
    if hints:
        text += ", likely one (a Fixed, a Revolute, ...) " + "; and one ".join(hints)
    return text + "."


def initial_state(desc: ModelDescription, extra_loads=()):
    """The three steps for ``desc``: returns (InitialState, model). Placing the tree needs no
    model; closing the loops and finding the redundant rows use a core model built at the
    tree's poses (with ``extra_loads``, as the analysis will). ``model`` is that model moved to
    the closed state (_marshal.with_initial), ready for the analysis, or None (no pairs, or a
    spring whose default rest length changed: build it from the state). Raises ModelError when
    given poses violate a pair or a loop cannot close; floating-point overflow raises
    FloatingPointError (see Mechanism)."""
    H, T, tree, frames_a = place_tree(desc)
    free = free_groups(desc, H)
    x0 = np.array([p["x0"] for p in desc.pairs]).reshape(-1, 6)
    if not desc.pairs:
        return InitialState(H, T, x0, [], frames_a, [], [], frozenset(tree), free), None
    model = _marshal.core_model(desc, H, T, x0, None, frames_a, extra_loads)
    H_tree = H.copy()
    H = close_loops(desc, model, H, tree, None)
    T, rates = close_rates(desc, model, H, T, tree, None)
    # joint coordinates reached (on the branch of x0): the core checks x0 at the start
    x = _core.model_joints(model, H, None)
    layout = _core.model_sizes(model)[4]
    adjustments = initial_adjustments(desc, H_tree, H, x, layout, rates)
    for ip, e in enumerate(desc.pairs):
        _, _, j, k = layout[ip]
        if e["has_x0"] and k:
            x0[ip, :k] = x[j:j + k]
    _, G, _ = _core.model_constraints_full(model, H, None, 0.0)
    masks, dropped = redundant_rows(desc, G, tree)
    state = InitialState(H, T, x0, masks, frames_a, dropped, adjustments, frozenset(tree), free)
    return state, _marshal.with_initial(model, desc, H_tree, H, T, x0, masks)

"""Quantities derived from a simulation after the run: section stress resultants of the flexible
links, constraint residuals of every pair row, and the minimum-norm multipliers of a
hyperconstrained mechanism. Each reads a SimulationResult and the model description it came
from (and, for the constraint rows, the core model); none changes them.

Conventions: strain and stress-resultant order (torsion, bending y, bending z, axial, shear y,
shear z): moments [N m] first, then forces [N], as twists and wrenches."""
from __future__ import annotations

import numpy as np

from . import _core, se3
from ._errors import ModelError
from .description import ModelDescription
from .frames import FlexibleLink
from .pairs import row_names
from .results import SimulationResult


def simulation_result(result, what: str) -> SimulationResult:
    """``result`` if it is a SimulationResult, else ModelError naming ``what``."""
    if not isinstance(result, SimulationResult):
        raise ModelError(f"{what}: result must be a SimulationResult (got {type(result).__name__})")
    return result


def stress_resultants(desc: ModelDescription, model, result: SimulationResult, link: FlexibleLink) -> np.ndarray:
    """Section stress resultants of each element of ``link`` along a simulation, shape
    (nt, elements, 6): sigma = K (eps - eps_hat) + D eps_dot in the element's own frame, in the
    strain order (torsion, bending y, bending z [N m], axial, shear y, shear z [N]); computed by
    the core's element (csrc/model/element.c; docs/method.md section 4.2), the one the simulation
    integrated. ``model``: the core model of ``desc``."""
    result = simulation_result(result, "stress_resultants")
    if link.rigid:
        raise ModelError(f"stress_resultants: link {link.name!r} is rigid (fidelity='rigid'): it "
                         f"has no strain, so no stress resultants; the pairs' constraint wrenches "
                         f"(result.joint(name)['wrench']) give the forces at its ends")
    if link.fidelity == "modal":
        raise ModelError(f"stress_resultants: link {link.name!r} is modal (reduced onto its ends): "
                         f"its one element's strain is the end-to-end deformation, not a section's; "
                         f"the pairs' constraint wrenches (result.joint(name)['wrench']) give the "
                         f"forces at its ends")
    cols = result._columns(link.nodes)
    nt, nc = len(result.t), len(desc.carriers)
    first = desc.first_element[link.name]
    out = np.empty((nt, link.elements, 6))
    # the core evaluates every carrier's elements: the carriers not recorded sit at the identity
    # and only this link's elements (whose nodes are all recorded) are kept; in chunks of time,
    # so that a long recorded run needs no full-size copy
    for t0 in range(0, nt, 256):
        t1 = min(nt, t0 + 256)
        H = np.broadcast_to(np.eye(4), (t1 - t0, nc, 4, 4)).copy()
        T = np.zeros((t1 - t0, nc, 6))
        H[:, link.nodes], T[:, link.nodes] = result.poses[t0:t1, cols], result.twists[t0:t1, cols]
        out[t0:t1] = _core.model_stress_resultants(model, H, T)[:, first:first + link.elements]
    return out


def constraint_residuals(desc: ModelDescription, model, result: SimulationResult) -> dict:
    """Position and velocity constraint residuals of EVERY pair row (redundant rows included)
    along a simulation: ``position`` (nt,) max ``|g(H)|`` [rad or m], ``velocity`` (nt,) max ``|G t|``
    [rad/s or m/s] (prescribed rates of driven pairs subtracted, by differencing g over 1e-7 s).
    ``model``: the core model of ``desc`` (any initial state)."""
    nt = len(result.t)
    pos, vel = np.zeros(nt), np.zeros(nt)
    driven = any(e["driven"] or e.get("xlaws") for e in desc.pairs)
    for i in range(nt):
        H, x, t = result.poses[i], result.joints[i], float(result.t[i])
        g, G, _ = _core.model_constraints_full(model, H, x, t)
        gv = G @ result.twists[i].ravel()
        if driven:   # subtract the prescribed rates by differencing g
            dt = 1e-7
            gv = gv + (_core.model_constraints_full(model, H, x, t + dt)[0] - g) / dt
        pos[i] = np.max(np.abs(g)) if g.size else 0.0
        vel[i] = np.max(np.abs(gv)) if gv.size else 0.0
    return dict(position=pos, velocity=vel)


def full_layout(desc: ModelDescription) -> list:
    """(first row, rows m, first joint coordinate, k) of every pair with all its constraint rows
    kept (redundant ones included), as the core's layout would be without drop masks."""
    lay, row, j = [], 0, 0
    for e in desc.pairs:
        m, k = len(row_names(e)), e["k"]
        lay.append((row, m, j, k))
        row += m
        j += k
    return lay


def kept_rows(layout: list, drop_masks) -> list:
    """The rows of ``layout`` (full_layout: every pair's rows) that ``drop_masks`` (per pair, the
    bits of its dropped rows) keep, in order: the DAE's multipliers are these rows'."""
    return [row + r for ip, (row, m, _, _) in enumerate(layout) for r in range(m)
            if not (drop_masks[ip] >> r) & 1]


def min_norm_multipliers(desc: ModelDescription, model, drop_masks, poses, joints, lam, times):
    """Hyperconstrained mechanisms: the DAE's multipliers (independent rows only) mapped to the
    minimum-norm multipliers of ALL rows giving the same generalized constraint forces,
    lambda_full = argmin |l| s.t. G_full^T l = G_kept^T lambda; pair wrenches W^C lambda_full.
    Returns (lambda_full (nt, nfull), pair wrenches (nt, npairs, 6), full_layout)."""
    full = full_layout(desc)
    keep = kept_rows(full, drop_masks)
    nf = full[-1][0] + full[-1][1] if full else 0
    lam_f = np.zeros((len(poses), nf))
    pw = np.zeros((len(poses), len(desc.pairs), 6))
    for i in range(len(poses)):
        _, G, W = _core.model_constraints_full(model, poses[i], joints[i], float(times[i]))
        f = G[keep].T @ lam[i]
        lam_f[i] = np.linalg.lstsq(G.T, f, rcond=None)[0]
        for ip in range(len(desc.pairs)):
            row, m, _, _ = full[ip]
            pw[i, ip] = W[ip][:, :m] @ lam_f[i, row:row + m]
    return lam_f, pw, full

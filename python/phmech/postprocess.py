"""Quantities derived from a simulation after the run: section stress resultants of the flexible
links, constraint residuals of every pair row, and the minimum-norm multipliers of a
hyperconstrained mechanism. Each reads a SimulationResult and the model description it came
from (and, for the constraint rows, the core model); none changes them.

Conventions: strain and stress-resultant order (torsion, bending y, bending z, axial, shear y,
shear z): moments [N m] first, then forces [N], as twists and wrenches."""
from __future__ import annotations

import numpy as np

from . import _core, se3
from ._core import ModelError
from .description import ModelDescription
from .frames import FlexibleLink
from .pairs import DIRECTIONS
from .results import SimulationResult


def simulation_result(result, what: str) -> SimulationResult:
    """``result`` if it is a SimulationResult, else ModelError naming ``what``."""
    if not isinstance(result, SimulationResult):
        raise ModelError(f"{what}: result must be a SimulationResult (got {type(result).__name__})")
    return result


def stress_resultants(desc: ModelDescription, result: SimulationResult, link: FlexibleLink) -> np.ndarray:
    """Section stress resultants of each element of ``link`` along a simulation, shape
    (nt, elements, 6): sigma = K (eps - eps_hat) + D eps_dot in the element's own frame, in the
    strain order (torsion, bending y, bending z [N m], axial, shear y, shear z [N]);
    eps = log(H_k^-1 H_k+1) / h and h eps_dot = dexp_{-X}^-1 t_k+1 - dexp_X^-1 t_k, the same
    constant-strain element the core integrates (csrc/model/element.c; docs/method.md section 4.2)."""
    result = simulation_result(result, "stress_resultants")
    cols = result._columns(link.nodes)
    H, T = result.poses[:, cols], result.twists[:, cols]
    els = desc.link_elements(link)
    K = np.array([e["K"] for e in els])
    D = np.array([e["D"] for e in els])
    eps_hat = np.array([e["eps"] for e in els])
    h = np.array([e["h"] for e in els])[:, None]
    X = se3.log(se3.compose(se3.inverse(H[:, :-1]), H[:, 1:]))         # (nt, N, 6)
    rate = (np.einsum("...ij,...j->...i", se3.dexp_inv(-X), T[:, 1:])
            - np.einsum("...ij,...j->...i", se3.dexp_inv(X), T[:, :-1])) / h
    return (np.einsum("kij,tkj->tki", K, X / h - eps_hat)
            + np.einsum("kij,tkj->tki", D, rate))


def constraint_residuals(desc: ModelDescription, model, result: SimulationResult) -> dict:
    """Position and velocity constraint residuals of EVERY pair row (redundant rows included)
    along a simulation: ``position`` (nt,) max |g(H)| [rad or m], ``velocity`` (nt,) max |G t|
    [rad/s or m/s] (prescribed rates of driven pairs subtracted, by differencing g over 1e-7 s).
    ``model``: the core model of ``desc`` (any initial state)."""
    nt = len(result.t)
    pos, vel = np.zeros(nt), np.zeros(nt)
    driven = any(e["driven"] for e in desc.pairs)
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
        m = len(DIRECTIONS[e["type"]])
        lay.append((row, m, j, 6 - m))
        row += m
        j += 6 - m
    return lay


def min_norm_multipliers(desc: ModelDescription, model, drop_masks, poses, joints, lam, times):
    """Hyperconstrained mechanisms: the DAE's multipliers (independent rows only) mapped to the
    minimum-norm multipliers of ALL rows giving the same generalized constraint forces,
    lambda_full = argmin |l| s.t. G_full^T l = G_kept^T lambda; pair wrenches W^C lambda_full.
    Returns (lambda_full (nt, nfull), pair wrenches (nt, npairs, 6), full_layout)."""
    full = full_layout(desc)
    keep = []
    for ip in range(len(desc.pairs)):
        row, m, _, _ = full[ip]
        keep += [row + r for r in range(m) if not (drop_masks[ip] >> r) & 1]
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

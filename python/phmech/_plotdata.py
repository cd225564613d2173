"""What phmech.plot draws, in world coordinates and without matplotlib: the points of links,
bodies and pairs at given poses, the poses of a result at an instant or of a mode shape, and
the frames of an animation (NumPy only). Units: m; poses 4x4."""
from __future__ import annotations

from typing import Optional

import numpy as np

from . import se3
from ._errors import ModelError
from .results import ModesResult, SimulationResult, StaticResult


def pair_rows(mechanism):
    return [] if mechanism is None else list(mechanism._desc.pairs)

def geometry(links: dict, bodies: dict, pairs: list, poses: np.ndarray) -> dict:
    """World points of what is drawn at ``poses`` (ncarriers, 4, 4)."""
    def point(c, T):
        H = np.eye(4) if c < 0 else poses[c]
        return (H @ np.asarray(T))[:3, 3]
    frames = {lk.name: lk.node_poses(poses[lk.nodes]) for lk in links.values()}
    g = dict(links=[(nm, F[:, :3, 3]) for nm, F in frames.items()],
             bodies=[], pairs=[],
             sections=[F[:, :3, 1] for F in frames.values()])  # local y axes
    attach = {b.carrier: [] for b in bodies.values()}
    for p in pairs:
        pa = point(p["a"], p["Ta"])
        g["pairs"].append((p["name"], pa))
        for c, T in ((p["a"], p["Ta"]), (p["b"], p["Tb"])):
            if c in attach:
                attach[c].append(point(c, T))
    for b in bodies.values():
        o = poses[b.carrier][:3, 3]
        g["bodies"].append((b.name, o, attach[b.carrier]))
    return g

def all_points(g) -> list:
    return [P for _, P in g["links"]] + [o for _, o, _ in g["bodies"]] + \
        [q for _, _, pts in g["bodies"] for q in pts] + [q for _, q in g["pairs"]]

def poses_of(mechanism, state, time):
    """(poses, text) of what to draw: a SimulationResult at ``time`` (nearest output; None: the
    last), a StaticResult, an array of poses, or None (the initial configuration)."""
    if state is None:
        return mechanism.initial_configuration().poses, "initial configuration"
    if isinstance(state, SimulationResult):
        if state.carriers is not None:
            raise ModelError("draw: the result must record every carrier (simulate without record=)")
        i = len(state.t) - 1 if time is None else int(np.argmin(np.abs(state.t - float(time))))
        return state.poses[i], f"t = {state.t[i]:.4g} s"
    if isinstance(state, StaticResult):
        return state.poses, "static equilibrium"
    P = np.asarray(state, dtype=float)
    if P.ndim != 3 or P.shape[1:] != (4, 4):
        raise ModelError(f"draw: expected a SimulationResult, StaticResult, poses (ncarriers, 4, "
                         f"4) or None (got {type(state).__name__})")
    return P, ""

def mode_poses(modes: ModesResult, k: int, amp: float) -> np.ndarray:
    return modes.poses @ se3.exp(amp * modes.shapes[k])

def mode_amplitude(modes: ModesResult, k: int, size: float, scale: Optional[float]) -> float:
    if scale is not None:
        return float(scale)
    d = np.linalg.norm(modes.shapes[k, :, 3:], axis=1).max()           # largest translation
    r = np.linalg.norm(modes.shapes[k, :, :3], axis=1).max() * size    # rotations (as lengths)
    if d > 0.05 * r:
        return 0.15 * size / max(d, 1e-300)
    return 0.6 / max(r / size, 1e-300)       # rotations alone (torsion): 0.6 rad at most

def frames(result: SimulationResult, fps: float, t_max: Optional[float], speed: float) -> list:
    t1 = result.t[-1] if t_max is None else min(float(t_max), result.t[-1])
    times = np.arange(result.t[0], t1 + 1e-12, speed / fps)
    return sorted(set(int(np.argmin(np.abs(result.t - t))) for t in times))

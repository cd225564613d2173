"""Reusable validation studies: the paper's Table I (cantilever Timoshenko beam) and its
convergence, for both discretizations. Used by ``examples/timoshenko_table.py``, the tests and the
benchmarks, so that all three measure the same thing.
"""
from __future__ import annotations

import time

import numpy as np

from . import mixed, timoshenko
from .mechanism import Mechanism
from .pairs import Fixed
from .section import BeamProperties, table1_properties

#: Table I of the paper (docs/method.md section 8.1): L [m], rhoA [kg/m], rhoI [kg m], EI [N m^2], kGA [N].
TABLE1 = dict(L=1.0, rhoA=873.0, rhoI=2.1797, EI=5143.0, kGA=656625.0)


def exact_frequencies(n: int = 5, beam: dict = TABLE1) -> np.ndarray:
    """First ``n`` cantilever frequencies [rad/s] from the Timoshenko frequency equation."""
    return timoshenko.frequencies(n, beam["L"], beam["EI"], beam["kGA"], beam["rhoA"], beam["rhoI"],
                                  bc="clamped-free")


def mixed_frequencies(N: int, n: int = 5, beam: dict = TABLE1) -> np.ndarray:
    """First ``n`` cantilever frequencies [rad/s] of Golo's mixed element (alpha = 1/2), N elements."""
    return mixed.frequencies(n, N, beam["L"], beam["EI"], beam["kGA"], beam["rhoA"], beam["rhoI"],
                             bc="clamped-free", alpha=0.5)


def se3_cantilever(N: int, properties: BeamProperties | None = None, length: float = 1.0,
                   damping: np.ndarray | None = None, mass: str = "consistent") -> tuple[Mechanism, object]:
    """A cantilever of the nonlinear ``se3`` link along x, clamped at its start to the ground.

    ``properties`` default to :func:`phmech.table1_properties` (bending in the x-z plane carries
    Table I; the other directions are made much stiffer); ``mass`` is the link's mass model
    (``"lumped"`` or ``"consistent"``, :meth:`Mechanism.add_flexible_link`). Returns
    ``(mechanism, link)``.
    """
    props = table1_properties() if properties is None else properties
    if damping is not None:
        props = BeamProperties(stiffness=props.stiffness, inertia=props.inertia, damping=damping)
    m = Mechanism()
    link = m.add_flexible_link("beam", length, props, elements=N, mass=mass)
    m.add_pair("clamp", Fixed(), m.ground, link.start)
    return m, link


def se3_frequencies(N: int, n: int = 5, mass: str = "consistent") -> np.ndarray:
    """First ``n`` cantilever frequencies [rad/s] of the ``se3`` link (Table I), N elements, with
    the element mass ``mass`` (``"lumped"`` or ``"consistent"``).

    The 3-D model's lowest modes are the x-z bending modes of Table I because the other
    directions of :func:`phmech.table1_properties` are 10^4 times stiffer; this is checked: every
    returned mode must be dominated by z translation and y rotation.
    """
    m, _ = se3_cantilever(N, mass=mass)
    res = m.modes(n)
    shapes = res.shapes  # (n, ncarriers, 6): (rx, ry, rz, x, y, z)
    in_plane = np.sum(shapes[:, :, [1, 5]] ** 2, axis=(1, 2)) / np.sum(shapes ** 2, axis=(1, 2))
    if np.any(in_plane < 0.99):
        raise RuntimeError(f"se3 cantilever: a low mode is not x-z bending (share {in_plane})")
    return res.omega


def convergence(discretization: str, Ns, n: int = 5) -> dict:
    """Relative frequency errors against the exact values for each N, with CPU times.

    Returns ``{"N": [...], "states": [...], "errors": (len(Ns), n) list, "cpu_s": [...],
    "order": [per-mode least-squares slope of log error against log N]}``. A mesh too coarse to
    have mode k (mixed: 2N modes; se3: 2N in-plane bending modes) gets NaN there, and the slope
    uses the meshes that have it. ``states`` counts first-order states of the model actually
    solved (mixed: 4N, planar; se3: 12 per free node, 3-D)."""
    exact = exact_frequencies(n)
    fn = {"mixed": mixed_frequencies, "se3": se3_frequencies}[discretization]
    errs, cpu, states = [], [], []
    for N in Ns:
        k = min(n, 2 * int(N))
        t0 = time.process_time()
        om = fn(int(N), k)
        cpu.append(time.process_time() - t0)
        e = np.full(n, np.nan)
        e[:k] = (om - exact[:k]) / exact[:k]
        errs.append(e.tolist())
        states.append(4 * int(N) if discretization == "mixed" else 12 * int(N))
    E = np.abs(np.array(errs))
    logN = np.log(np.asarray(Ns, dtype=float))
    order = []
    for k in range(n):
        ok = np.isfinite(E[:, k]) & (E[:, k] > 0)
        order.append(float(-np.polyfit(logN[ok], np.log(E[ok, k]), 1)[0]))
    return {"N": [int(N) for N in Ns], "states": states, "errors": errs, "cpu_s": cpu,
            "order": order}

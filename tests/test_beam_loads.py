"""Distributed load, gravity, curved unstressed shape, driven end.
References: linear Timoshenko statics, equality of gravity and the equivalent distributed load,
the geometry of a circular arc, the energy ledger of a driven clamp."""
import numpy as np
import pytest

import phmech as ph
from phmech.section import TABLE1, table1_properties

L, EI, kGA, rhoA = TABLE1["L"], TABLE1["EI"], TABLE1["kGA"], TABLE1["rhoA"]


def cantilever(N, gravity=(0, 0, 0), curvature=None, props=None):
    m = ph.Mechanism(gravity=gravity)
    b = m.add_flexible_link("b", L, table1_properties(1.0) if props is None else props,
                            elements=N, curvature=curvature)
    m.add_pair("clamp", ph.Fixed(), m.ground, b.start)
    return m, b


def uniform_load_tip(N, q):
    m, b = cantilever(N)
    m.add_distributed_load("q", b, (0, 0, q))
    return m.static(steps=1).positions(b)[-1, 2]


def test_distributed_load_matches_timoshenko_statics():
    # The constant-strain element with the load lumped on the nodes is nodally exact for the
    # linear static cantilever (measured: the error does not depend on N), so what remains is
    # the geometric nonlinearity, of order (w/L)^2 ~ 1e-10 for this small load.
    q = 1e-4 * EI  # tip ~1e-5 L
    exact = q * L**4 / (8 * EI) + q * L**2 / (2 * kGA)
    e = {N: abs(uniform_load_tip(N, q) / exact - 1) for N in (3, 10, 40)}
    assert max(e.values()) < 1e-8, e


def test_gravity_equals_the_equivalent_distributed_load():
    g = 0.5
    m1, b1 = cantilever(12, gravity=(0, 0, -g))
    m2, b2 = cantilever(12)
    m2.add_distributed_load("w", b2, (0, 0, -rhoA * g))
    x1 = m1.static(steps=2).positions(b1)
    x2 = m2.static(steps=2).positions(b2)
    assert np.max(np.abs(x1 - x2)) < 1e-12 + 1e-9 * np.max(np.abs(x1[:, 2]))
    assert x1[-1, 2] < 0  # it sags


def test_curved_unstressed_shape_is_a_circular_arc_at_rest():
    kappa = np.pi / 2 / L  # a quarter circle in the x-z plane (bending about y)
    m, b = cantilever(16, curvature=(0, -kappa, 0))
    r = 1 / kappa
    res = m.simulate(0.05, 0.01, rtol=1e-8, integrator="ida")
    x = res.positions(b)
    # nodes on the circle of radius r through the origin, tangent to x there
    centre = np.array([0, 0, r])
    dist = np.linalg.norm(x[0] - centre, axis=1)
    assert np.max(np.abs(dist - r)) < 1e-12
    assert np.allclose(x[0, -1], [r, 0, r], atol=1e-12)  # quarter circle ends at (r, 0, r)
    # unstressed: no elastic energy, stays at rest
    assert res.energy["elastic"][0] < 1e-20
    assert np.max(np.abs(res.twists)) < 1e-10
    # and it bends like the straight beam does: modes exist and are positive
    assert np.all(m.modes(3).omega > 0)


def test_driven_clamp_follows_its_law():
    m = ph.Mechanism()
    b = m.add_flexible_link("b", L, table1_properties(1.0), elements=10)
    A, f = 0.01, 2.0
    m.add_pair("shaker", ph.Fixed(), m.ground, b.start,
               driven=ph.Motion(axis=(0, 0, 0, 0, 0, 1), law=ph.Sine(amplitude=A, frequency=f)))
    res = m.simulate(0.5, 0.01, rtol=1e-8, linear_solver="klu", integrator="ida")
    np.testing.assert_allclose(res.positions(b)[:, 0, 2], A * np.sin(2 * np.pi * f * res.t), atol=1e-9)


def test_driven_clamp_follows_its_law_and_the_ledger_closes():
    m = ph.Mechanism()
    b = m.add_flexible_link("b", L, table1_properties(1.0), elements=10)
    A, f = 0.01, 2.0  # 1 cm at 2 Hz, near-resonant with mode 1 (1.33 Hz)
    m.add_pair("shaker", ph.Fixed(), m.ground, b.start,
               driven=ph.Motion(axis=(0, 0, 0, 0, 0, 1), law=ph.Sine(amplitude=A, frequency=f)))
    res = m.simulate(1.0, 0.01, rtol=1e-8, linear_solver="klu", integrator="ida")
    z0 = res.positions(b)[:, 0, 2]
    np.testing.assert_allclose(z0, A * np.sin(2 * np.pi * f * res.t), atol=1e-9)
    e = res.energy
    scale = np.max(np.abs(e["total"]))
    assert scale > 1e-3 and np.max(np.abs(e["supplied"])) > 0.1 * scale  # the shaker does work
    assert np.max(np.abs(e["ledger"])) < 1e-6 * scale, np.max(np.abs(e["ledger"])) / scale

"""Mechanism.linearize: the linear port-Hamiltonian model (J, R, Q, B, C, D) on the constraint
manifold, checked against modes(), against a nonlinear simulation of a small force step, for
passivity, and for its ports (docs/method.md section 7.4)."""
import os
import sys

import numpy as np
import pytest
from scipy.linalg import eigh, expm

import phmech as ph
from phmech import se3

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "examples"))
import leaf_spring as ls  # noqa: E402  (examples/leaf_spring.py)

F_STEP = 1e-3   # N, see test_step_response_matches_simulate
T_STEP = 0.01   # s


@pytest.fixture(scope="module")
def leaf():
    """The leaf spring (4 elements per leaf, beta = 1e-5 s) with a force step F_STEP along
    world x on the platform R1 from T_STEP (zero at the linearization time 0)."""
    m, h = ls.build(ls.default_params(), elements=4, pulse=ph.Step(t0=T_STEP, value=F_STEP))
    return m, h, m.linearize(inputs=["w_x"])


def test_frequencies_equal_modes_and_passive(leaf):
    m, h, lin = leaf
    mo = m.modes(8)
    np.testing.assert_allclose(lin.frequencies()[:8], mo.frequency, rtol=1e-8)
    # and the eigenvalues of (J - R) Q without R: +-i omega, the same frequencies
    A0 = lin.J @ lin.Q
    w = np.sort(np.abs(np.linalg.eigvals(A0).imag))[::2] / (2 * np.pi)
    np.testing.assert_allclose(w[:3], mo.frequency[:3], rtol=1e-6)   # eig of a nonsymmetric A
    # one coordinate per null-space direction: 6 per carrier (2 x 5 nodes, 3 bodies) minus the
    # 36 rows of the six welds (none redundant: docs/leaf_spring.md)
    assert lin.basis.shape == (6 * 13, lin.nr) and lin.nr == 6 * 13 - 36
    chk = lin.passivity()
    assert chk.passive
    assert chk.J_skew == 0.0 and chk.R_min >= -1e-9 and chk.Q_min > 1e-12 and chk.collocation < 1e-9
    # R's damping block gives the modes' damping ratio: zeta = y^T Dr y / (2 omega), y the first
    # mode with unit modal mass (from the shift-inverted pencil: the lowest mode accurately)
    K, M, D = lin.stiffness, lin.mass, lin.damping
    th, Y = eigh(M, K + M)
    y = Y[:, np.argmax(th)]
    y = y / np.sqrt(y @ M @ y)
    zeta1 = y @ D @ y / (2 * np.sqrt(y @ K @ y))
    np.testing.assert_allclose(zeta1, mo.damping_ratio[0], rtol=1e-6)


def test_step_response_matches_simulate(leaf):
    """A force step F on R1 along x: the exact discretization of the linear model (input
    piecewise constant between outputs, x_{k+1} = e^{A dt} x_k + A^-1 (e^{A dt} - I) B u_k)
    against the nonlinear simulation, over 1 s (3.5 periods), to 1e-4 of the peak.

    Why F = 1 mN is small enough: the guide's x stiffness is k = m_R (2 pi f1)^2 ~ 1.1e3 N/m, so
    the peak displacement is 2 F / k ~ 1.8 um, delta / L ~ 2e-5 of the 0.1 m leaves. The leaf
    guide's force-displacement law is odd in delta (the cubic term is relative (delta/L)^2 ~
    4e-10); the largest neglected terms are quadratic -- the platform's drop delta^2 / L and
    the exponential coordinates' map p = R0 V(omega) v ~ v (1 + |omega|/2) -- at most delta/L ~
    2e-5 relative, 5x below the tolerance; the simulation's own error (rtol 1e-7, atol 1e-12 m)
    is below 1e-6 of the peak."""
    m, h, lin = leaf
    res = m.simulate(1.0, 1e-3, rtol=1e-7, atol=1e-12)
    dt = res.t[1] - res.t[0]
    A, B = lin.A, lin.B[:, 0]
    Phi = expm(A * dt)
    Gam = np.linalg.solve(A, (Phi - np.eye(len(A))) @ B)
    X = np.zeros((len(res.t), len(A)))
    for k in range(1, len(res.t)):
        u = F_STEP if res.t[k - 1] >= T_STEP - 1e-12 else 0.0
        X[k] = Phi @ X[k - 1] + Gam * u
    c = h["R1"].carrier
    x_lin = lin.displacement(X)[:, c, 3]                   # R1 starts world-aligned: body x = world x
    x_nl = res.position("R1")[:, 0] - res.position("R1")[0, 0]
    peak = np.abs(x_nl).max()
    assert 1.5e-6 < peak < 2.2e-6                          # ~2 F / k: the step's overshoot
    assert np.abs(x_lin - x_nl).max() < 1e-4 * peak
    # the collocated output is R1's velocity along the force
    v_lin = (X @ lin.C.T)[:, 0]
    v_nl = res.twist("R1")[:, 3]
    assert np.abs(v_lin - v_nl).max() < 1e-4 * np.abs(v_nl).max()


def test_ports_pair_frame_and_statespace():
    """A pendulum on a revolute joint (ports: the joint effort, the bob's frame): B^T is the
    collocated output map, the transfer function from torque to joint rate at s = i w is
    i w / (J (w0^2 - w^2)) with J = m l^2 (point mass) and w0^2 = g / l, and the frame port's
    outputs are the bob's twist."""
    mass, l, g = 0.7, 0.4, 9.81
    m = ph.Mechanism(gravity=(0.0, 0.0, -g))
    bob = m.add_rigid_body("bob", mass, 1e-9 * np.eye(3), pose=se3.translation([0.0, 0.0, -l]))
    m.add_pair("hinge", ph.Revolute(axis="y"), m.ground,
               ph.Frame(bob.carrier, se3.translation([0.0, 0.0, l])))
    lin = m.linearize(inputs=["hinge"])
    assert lin.nr == 1 and lin.inputs == ["hinge"] and lin.outputs == ["hinge.rate"]
    w0 = np.sqrt(g / l)
    np.testing.assert_allclose(lin.frequencies(), [w0 / (2 * np.pi)], rtol=1e-6)
    ss = lin.to_statespace()
    w = 2.0
    Hs = (ss.C @ np.linalg.solve(1j * w * np.eye(2) - ss.A, ss.B) + ss.D)[0, 0]
    np.testing.assert_allclose(Hs, 1j * w / (mass * l ** 2 * (w0 ** 2 - w ** 2)), rtol=1e-6)
    lf = m.linearize(inputs=["hinge"], outputs=["bob"])
    assert lf.outputs == [f"bob.{c}" for c in ("omega_x", "omega_y", "omega_z", "v_x", "v_y", "v_z")]
    # a unit joint rate turns the bob about y at 1 rad/s, moving it along x at l m/s (body axes)
    v = lf.Cq[:, 0] / lin.Bq[0, 0]                 # reduced velocity of a unit joint rate
    np.testing.assert_allclose(v, [0, 1, 0, -l, 0, 0], atol=1e-9)
    assert np.isnan(lf.passivity().collocation)


def test_to_control():
    control = pytest.importorskip("control")
    m = ph.Mechanism(gravity=(0.0, 0.0, -9.81))
    bob = m.add_rigid_body("bob", 1.0, 1e-9 * np.eye(3), pose=se3.translation([0.0, 0.0, -1.0]))
    m.add_pair("hinge", ph.Revolute(axis="y"), m.ground, ph.Frame(bob.carrier, se3.translation([0, 0, 1.0])))
    sys_ = m.linearize(inputs=["hinge", "bob"]).to_control()
    assert isinstance(sys_, control.StateSpace)
    assert sys_.ninputs == 7 and sys_.input_labels[1] == "bob_tau_x"
    np.testing.assert_allclose(np.sort(np.abs(sys_.poles().imag)), [np.sqrt(9.81)] * 2, rtol=1e-6)


def test_bad_port_names(leaf):
    m, h, lin = leaf
    with pytest.raises(ph.ModelError, match=r"unknown port 'w_y'.*'w_x'.*'R1'"):
        m.linearize(inputs=["w_y"])
    with pytest.raises(ph.ModelError, match="Fixed pair"):
        m.linearize(inputs=["tip1"])
    with pytest.raises(ph.ModelError, match="unknown port"):
        m.linearize(inputs=["w_x"], outputs=["nothing"])
    with pytest.raises(ph.ModelError, match="at must be a StaticResult"):
        m.linearize(at=3.0, inputs=["w_x"])


def _cantilever(elements=6):
    steel = ph.Material(E=210e9, nu=0.3, density=7850.0)
    props = ph.BeamProperties.from_material(ph.Section.rectangle(0.02, 0.001), steel)
    m = ph.Mechanism()
    leaf = m.add_flexible_link("leaf", 0.2, props, elements=elements)
    m.add_pair("clamp", ph.Fixed(), m.ground, leaf.start)
    return m, leaf


def test_at_static_equilibrium_and_distributed_load():
    """About a static equilibrium under an axial compressive tip load (geometric stiffness:
    lower frequencies) the export's frequencies are modes(at=)'s; a distributed load is one
    input (all its nodes together), and the static response K^-1 B u of the linear model is the
    nonlinear static deflection under a small load (1 N/m: tip deflection ~1e-3 of the length,
    nonlinear terms ~1e-6 relative)."""
    m, leaf = _cantilever()
    m.add_distributed_load("q", leaf, (0.0, 0.0, 1.0), law=ph.Step(t0=1.0))   # off at time 0
    st = m.static(loads=[(leaf.end, (0, 0, 0, -2.0, 0, 0), "world")])
    lin = m.linearize(at=st, inputs=["q"])
    f0 = m.modes(3).frequency
    fa = m.modes(3, at=st).frequency
    np.testing.assert_allclose(lin.frequencies()[:3], fa, rtol=1e-8)
    assert np.all(fa < f0)
    assert lin.inputs == ["q"] and lin.Bq.shape == (lin.nr, 1)
    lin0 = m.linearize(inputs=["q"])
    q = np.linalg.solve(lin0.stiffness, lin0.Bq[:, 0])
    w_lin = lin0.displacement(np.concatenate([q, 0 * q]))[leaf.nodes[-1], 5]
    w_nl = m.static(time=2.0).positions(leaf)[-1, 2]
    assert 1e-4 < w_nl < 1e-3
    np.testing.assert_allclose(w_lin, w_nl, rtol=1e-5)

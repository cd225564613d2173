"""Initial rates of a closed chain (phmech.topology.close_rates): the mechanism starts moving as
its kinematics say, flexible links rigidly, not with a velocity jump along a link.

Reference: the rigid slider-crank's velocity analysis. At crank angle 0 (crank, rod and slider on
the x axis: the outer dead centre) a crank of radius r turning at w moves the crank pin at r w
across the line, the slider is at rest, and the rod turns about the wrist pin at -w r / l."""
import warnings

import numpy as np
import pytest

import phmech as ph
from phmech import se3

STEEL = ph.Material(E=210e9, nu=0.3, density=7850.0)
R, L, W = 0.15, 0.3, 2 * np.pi      # crank radius, rod length [m], crank rate [rad/s]
ELEMENTS = 6


def slider_crank():
    props = ph.BeamProperties.from_material(ph.Section.rectangle(0.005, 0.02), STEEL)
    m = ph.Mechanism()
    crank = m.add_rigid_body("crank", 0.5, np.diag([1e-4, 1e-3, 1e-3]), com=(R / 2, 0, 0))
    m.add_pair("motor", ph.Revolute("z"), m.ground, crank, x0=0.0, xdot0=W)
    rod = m.add_flexible_link("rod", L, props, elements=ELEMENTS, pose=se3.translation([R, 0, 0]))
    m.add_pair("crankpin", ph.Revolute("z"), ph.Frame(crank.carrier, se3.translation([R, 0, 0])),
               rod.start)
    slider = m.add_rigid_body("slider", 0.5, np.diag([1e-4, 1e-4, 1e-4]),
                              pose=se3.translation([R + L, 0, 0]))
    m.add_pair("wristpin", ph.Revolute("z"), rod.end, slider)
    m.add_pair("guide", ph.Prismatic("x"), m.ground, slider)
    return m, crank, rod, slider


@pytest.fixture(scope="module")
def run():
    m, crank, rod, slider = slider_crank()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ph.RedundantConstraintWarning)
        res = m.simulate(0.3, 1e-3)
    return m, crank, rod, slider, res


def test_every_rod_node_starts_turning_with_the_rod_about_the_wrist_pin(run):
    m, crank, rod, slider, res = run
    w_rod = -W * R / L
    for k, c in enumerate(rod.nodes):
        H, tw = res.poses[0, c], res.twists[0, c]
        # world velocity of node k: the rod turning about the wrist pin at (R + L, 0)
        x = R + L * k / ELEMENTS
        v_expected = np.array([0.0, w_rod * (x - (R + L)), 0.0])
        assert tw[:3] == pytest.approx([0, 0, w_rod], abs=1e-9)
        assert H[:3, :3] @ tw[3:] == pytest.approx(v_expected, abs=1e-9)
    assert res.twists[0, slider.carrier] == pytest.approx(np.zeros(6), abs=1e-9)


def test_the_start_carries_the_kinetic_energy_of_the_rigid_kinematics(run):
    """Crank about its pivot plus the rod about the wrist pin: 110.1 mJ (a start that left the
    rod at rest had 80.3 mJ and a velocity jump at the crank pin). The rod's inertia about the
    pin is its chain's: with consistent mass (the default) the continuum's m L^2/3 exactly (its
    elements' fields and the link's rigid-rotation coupling, docs/method.md section 4.2,
    "Mass"; before the coupling m L^2/3 + m h^2/12); lumped mass, the trapezoid share of
    its mass (half a share at each end), has m L^2/3 + m h^2/6 (110.6 mJ), the continuum
    110.1 mJ."""
    m, crank, rod, slider, res = run
    J_crank = 1e-3 + 0.5 * (R / 2) ** 2
    mrod = STEEL.density * 0.005 * 0.02 * L
    I_rod = mrod * L ** 2 / 3
    expected = 0.5 * J_crank * W ** 2 + 0.5 * I_rod * (W * R / L) ** 2
    # the rotary inertia of the rod's cross-sections adds ~1e-5 of it
    assert res.energy["kinetic"][0] == pytest.approx(expected, rel=1e-4)


def test_no_shock_so_the_ledger_closes(run):
    """With a rigid start the rod's elastic energy stays at the inertial load's (< 1e-4 of the
    kinetic) and the undamped run keeps its energy ledger: 1.3e-5 of the energy scale over 1 s
    (measured; 1.4e-2 with the velocity jump, lost in the mesh modes the steps do not resolve)."""
    m, crank, rod, slider, res = run
    assert np.max(res.energy["elastic"]) < 1e-4 * res.energy["kinetic"][0]
    assert res.stats["ledger_relative"] <= 1e-4


def fourbar(rocker_rate=None):
    """A planar crank-rocker (0.2/0.6/0.5 m bars, ground link 0.5 m), crank at 0.6 rad, 4 rad/s."""
    m = ph.Mechanism()
    bars = [m.add_rigid_body(n, 1.0, np.diag([1e-4, 1e-2, 1e-2]), com=(Lb / 2, 0, 0))
            for n, Lb in (("crank", 0.2), ("coupler", 0.6), ("rocker", 0.5))]
    T = lambda x: se3.translation([x, 0, 0])
    m.add_pair("k1", ph.Revolute("z"), m.ground, bars[0], x0=0.6, xdot0=4.0)
    m.add_pair("k2", ph.Revolute("z"), ph.Frame(bars[0].carrier, T(0.2)), bars[1])
    m.add_pair("k3", ph.Revolute("z"), ph.Frame(bars[1].carrier, T(0.6)), ph.Frame(bars[2].carrier, T(0.5)))
    m.add_pair("k4", ph.Revolute("z"), ph.Frame(-1, T(0.5)), bars[2], xdot0=rocker_rate)
    return m


def test_a_given_rate_is_kept_and_the_loop_moves_with_it():
    """The rocker's rate from the four-bar's velocity loop equations (independent: the planar
    vector loop a e^{i q1} + b e^{i q2} = d + c e^{i q4} differentiated) equals the simulated one."""
    m = fourbar()
    with warnings.catch_warnings():
        warnings.simplefilter("error", ph.InitialValueWarning)
        warnings.simplefilter("ignore", ph.RedundantConstraintWarning)
        res = m.simulate(1e-3, 1e-3)
    q1, q4 = res.joint("k1")["x"][0, 0], res.joint("k4")["x"][0, 0]
    w1, w4 = res.joint("k1")["xdot"][0, 0], res.joint("k4")["xdot"][0, 0]
    a, b, c, d = 0.2, 0.6, 0.5, 0.5
    P = a * np.exp(1j * q1)                         # crank pin
    Q = d + c * np.exp(1j * q4)                     # rocker pin
    th2 = np.angle(Q - P)                           # coupler angle
    # a w1 i e^{i q1} + b w2 i e^{i th2} = c w4 i e^{i q4}: two real equations in (w2, w4)
    M = np.array([[np.real(1j * b * np.exp(1j * th2)), -np.real(1j * c * np.exp(1j * q4))],
                  [np.imag(1j * b * np.exp(1j * th2)), -np.imag(1j * c * np.exp(1j * q4))]])
    rhs = -w1 * np.array([np.real(1j * a * np.exp(1j * q1)), np.imag(1j * a * np.exp(1j * q1))])
    w2_ref, w4_ref = np.linalg.solve(M, rhs)
    assert w1 == pytest.approx(4.0, rel=1e-8)   # the joint Jacobian is a central difference (1e-9)
    assert w4 == pytest.approx(w4_ref, rel=1e-7)


def test_contradicting_rates_are_reported_not_silently_changed():
    m = fourbar(rocker_rate=0.0)     # the crank turns at 4 rad/s: the rocker cannot stand still
    with pytest.warns(ph.InitialValueWarning, match=r"'k4' xdot given 0"):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ph.RedundantConstraintWarning)
            m.simulate(1e-3, 1e-3)
    moved = {(a.name, a.quantity): a for a in m.initial_adjustments if a.exceeds}
    assert ("k4", "xdot") in moved and ("k1", "xdot") in moved
    strict = fourbar(rocker_rate=0.0)
    strict.strict = True
    with pytest.raises(ph.ModelError, match="xdot given 0"):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ph.RedundantConstraintWarning)
            strict.simulate(1e-3, 1e-3)

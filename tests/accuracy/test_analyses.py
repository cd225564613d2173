"""Trap suite, issue 27 item 7: analyses in their domain. ``linearize()`` about a configuration
that is not an equilibrium warns as ``modes()`` does; the passivity check tells round-off from
a negative stiffness; ``modes(time=)`` / ``linearize(time=)`` on a mechanism whose driven pair
has moved on by then refuses with the pair and its values instead of returning the t = 0
figures."""
import warnings

import numpy as np
import pytest

import phmech as ph
from phmech import se3

G, L, MASS = 9.81, 1.0, 1.0


def pendulum():
    """A point-like 1 kg bob on a 1 m arm about y, starting horizontal (gravity -z): not an
    equilibrium; its linearized stiffness there is zero (gravity has no restoring moment)."""
    m = ph.Mechanism(gravity=(0, 0, -G))
    b = m.add_rigid_body("bob", MASS, np.eye(3) * 1e-4, com=(L, 0, 0))
    m.add_pair("pivot", ph.Revolute(axis="y"), m.ground, b)
    return m


def test_linearize_off_equilibrium_warns_as_modes_does():
    m = pendulum()
    with pytest.warns(ph.EquilibriumWarning, match=r"linearize: the configuration is not a "
                      r"static equilibrium \(a static solve from it moves body 'bob' by .* m and "
                      r"1.57 rad\).*linearize\(at=m.static"):   # to hanging: pi/2
        lin = m.linearize(inputs=["pivot"])
    with pytest.warns(ph.EquilibriumWarning, match="modes: the configuration is not"):
        m.modes(1)
    # horizontal: gravity's moment m g L cos(theta) has zero derivative -> K = 0 (exactly, up
    # to round-off of the gravity stiffness), M = m L^2 + J_yy
    assert abs(lin.stiffness[0, 0]) <= 1e-12 * MASS * G * L
    assert lin.mass[0, 0] == pytest.approx(MASS * L ** 2 + 1e-4, rel=1e-12)


def test_linearize_at_equilibrium_does_not_warn_and_is_passive():
    m = pendulum()
    st = m.static()
    with warnings.catch_warnings():
        warnings.simplefilter("error", ph.EquilibriumWarning)
        lin = m.linearize(at=st, inputs=["pivot"])
    # hanging: K = m g L (independent closed form), omega^2 = K / M
    assert lin.stiffness[0, 0] == pytest.approx(MASS * G * L, rel=1e-9)
    chk = lin.passivity()
    assert chk.passive and chk.Q_definite


def test_passivity_judges_round_off_as_zero():
    """Off equilibrium the horizontal pendulum's K is zero (Q_min = 0.0 here; the issue's scene
    gave a round-off -8.9e-18) and passive read False (it needed Q_min > 1000 eps); Q >= 0
    within round-off is passive (the energy x^T Q x / 2 is >= 0), only not definite. A real
    negative stiffness (the inverted pendulum) stays not passive."""
    m = pendulum()
    with pytest.warns(ph.EquilibriumWarning):
        chk = m.linearize(inputs=["pivot"]).passivity()
    assert abs(chk.Q_min) <= ph.linear.Q_RESOLVED
    assert chk.passive and not chk.Q_definite
    inv = ph.Mechanism(gravity=(0, 0, -G))
    b = inv.add_rigid_body("bob", MASS, np.eye(3) * 1e-4, com=(L, 0, 0))
    inv.add_pair("pivot", ph.Revolute(axis="y"), inv.ground, b, x0=-np.pi / 2)   # bob on top
    lin = inv.linearize(at=inv.static(check_stability=False), inputs=["pivot"])
    chk = lin.passivity()
    # K = -m g L: relative eigenvalue -1 of the K block
    assert lin.stiffness[0, 0] == pytest.approx(-MASS * G * L, rel=1e-9)
    assert chk.Q_min == pytest.approx(-1.0, rel=1e-9) and not chk.passive


#: the spin-up: angle 2.5 t^2 up to 2 s (speed 5 t), then 10 + 10 (t - 2) rad
SPIN_UP = ph.PiecewisePolynomial([0.0, 2.0, 100.0], [[2.5, 0.0, 0.0], [0.0, 10.0, 10.0]])


def spin_up(law=SPIN_UP):
    """A hub driven by ``law`` (default the spin-up: speed ramping to 10 rad/s over 2 s, then
    constant) with a steel strip clamped to it, no gravity."""
    m = ph.Mechanism()
    hub = m.add_rigid_body("hub", 1.0, np.diag([1e-3, 1e-3, 1e-3]))
    m.add_pair("motor", ph.Revolute("z"), m.ground, hub, driven=law)
    props = ph.BeamProperties.from_material(ph.Section.rectangle(0.004, 0.02),
                                            ph.Material(E=210e9, nu=0.3, density=7850.0))
    arm = m.add_flexible_link("arm", 0.5, props, elements=4)
    m.add_pair("root", ph.Fixed(), hub, arm.start)
    return m, law


def test_modes_at_a_time_the_driven_pair_has_moved_refuses():
    m, law = spin_up()
    s4, v4, _ = law.derivatives(4.0)
    assert s4 == pytest.approx(30.0) and v4 == pytest.approx(10.0)   # 10 + 10 (4 - 2) rad
    for call in (lambda: m.modes(3, time=4.0), lambda: m.linearize(inputs=["motor"], time=4.0)):
        with pytest.raises(ph.ModelError, match=r"time=4\): pair 'motor' is driven, and its law "
                           r"moves coordinate 0 from s\(0\) = 0 rad \(rate 0 rad/s\) to s\(4\) = "
                           r"30 rad \(rate 10 rad/s\)"):
            call()
    # at t = 0 (and at times where the law has not moved) the analyses run as before
    f0 = m.modes(3).frequency
    assert np.all(np.isfinite(f0))


def test_modes_at_time_with_the_law_advanced_to_it():
    """The remedy the message gives: the law advanced to that time, law.shifted(-4), puts the
    initial configuration where the driven pair is at t = 4 (30 rad), and modes() runs there.
    The strip clamped to the hub (no gravity) has the same frequencies wherever the hub stands:
    they agree with t = 0's to 1e-9."""
    m, law = spin_up()
    f0 = m.modes(3).frequency
    m4, _ = spin_up(SPIN_UP.shifted(-4.0))
    modes4 = m4.modes(3)
    hub = m4.bodies["hub"].carrier
    ang = np.arctan2(modes4.poses[hub][1, 0], modes4.poses[hub][0, 0])
    assert ang == pytest.approx(np.mod(30.0 + np.pi, 2 * np.pi) - np.pi, abs=1e-9)
    np.testing.assert_allclose(modes4.frequency, f0, rtol=1e-9)


def hanging_double_pendulum(component: bool):
    """Two uniform 1 m, 1 kg rods on revolutes about y, hanging along -z (an equilibrium), with
    a viscous friction component on the first joint or none."""
    m = ph.Mechanism(gravity=(0, 0, -G))
    J = np.diag([1 / 12, 1 / 12, 1e-4])
    a = m.add_rigid_body("a", 1.0, J, com=(0, 0, -0.5))
    b = m.add_rigid_body("b", 1.0, J, com=(0, 0, -0.5))
    m.add_pair("p1", ph.Revolute(axis="y"), m.ground, a)
    m.add_pair("p2", ph.Revolute(axis="y"), a.frame_at((0, 0, -1.0)), b)
    if component:
        m.add_component("friction", "p1", ph.ViscousFriction(0.01))
    return m


@pytest.mark.parametrize("component", [False, True])
def test_modes_at_the_initial_equilibrium_hold_the_constraint_forces(component):
    """A pendulum's gravity stiffness comes through its joints' reactions: at the initial
    configuration (no at=) the linearization left them out, and the hanging double pendulum gave
    0 and 0.653 Hz (0 and 0.0024 Hz with a friction component) with equilibrium True and no
    warning, against 0.4266 and 1.1441 Hz. Reference: the small-oscillation eigenproblem
    K v = w^2 M v of the two rods in joint angles, M = [[1/3 + 1, 1/2], [1/2, 1/3]] kg m^2,
    K = g diag(3/2, 1/2) N m (measured now: equal to 1e-7 and to modes(at=m.static()))."""
    from scipy.linalg import eigh
    M = np.array([[1 / 3 + 1, 0.5], [0.5, 1 / 3]])
    exact = np.sqrt(eigh(G * np.diag([1.5, 0.5]), M, eigvals_only=True)) / (2 * np.pi)
    m = hanging_double_pendulum(component)
    with warnings.catch_warnings():
        warnings.simplefilter("error", ph.EquilibriumWarning)
        f = m.modes(2).frequency
        lin = m.linearize()
    tol = 1e-5 if component else 1e-6   # the friction's damping moves |s| by 5e-7
    np.testing.assert_allclose(f, exact, rtol=tol)
    poles = np.sort(np.abs(np.linalg.eigvals(lin.A)))[::2] / (2 * np.pi)
    np.testing.assert_allclose(poles, exact, rtol=tol)


def test_modes_of_a_loaded_strip_at_its_start_are_those_of_its_equilibrium():
    """A steel strip (0.3 m, 20 x 1 mm, 10 elements) clamped at its top and hanging, 1 kg welded
    to its end: the unstretched start is within the equilibrium check's bounds (its stretch is
    7e-7 m), but its elements carry no tension there, and modes() read 9.0986 rad/s for the
    8.8053 that the stretched equilibrium has (3.3 % high, no warning; a kicked simulation of it
    oscillates at 8.805 rad/s: the accuracy audit of 2026-12-07). modes() and linearize() now
    linearize at the equilibrium the check found (measured: equal to 1e-9)."""
    props = ph.BeamProperties.from_material(ph.Section.strip(width=0.02, thickness=0.001),
                                            ph.Material(E=210e9, nu=0.3, density=7850.0))
    m = ph.Mechanism(gravity=(0, 0, -G))
    f = m.ground.frame_at((0, 0, 0), ph.rotation("y", np.pi / 2))   # the strip along -z
    s = m.add_flexible_link("strip", 0.3, props, elements=10, start=f)
    m.add_pair("clamp", ph.Fixed(), f, s.start)
    tip = m.add_rigid_body("tip", 1.0, 1e-5 * np.eye(3), at=s.end)
    m.add_pair("weld", ph.Fixed(), s.end, tip)
    with warnings.catch_warnings():
        warnings.simplefilter("error", ph.EquilibriumWarning)
        start = m.modes(2).omega
        lin = m.linearize()
    at_rest = m.modes(2, at=m.static()).omega
    np.testing.assert_allclose(start, at_rest, rtol=1e-7)
    assert abs(start[0] - 8.8053) < 1e-3
    poles = np.sort(np.abs(np.linalg.eigvals(lin.A)))[::2][:2]
    np.testing.assert_allclose(poles, at_rest, rtol=1e-6)

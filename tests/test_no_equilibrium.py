"""Mechanism.static() of a mechanism without a static equilibrium: the loads do work on a motion
that nothing resists (csrc/analyze/static_free.c, docs/method.md section 7.3, "No equilibrium").
The solve stops at Newton's first failure with a SolverError that names the pair or part, what
moves and the generalized force; and every mechanism that has an equilibrium still solves, also
those whose tangent at the start has a zero-stiffness direction with a load along it.

The numbers asserted come from the loads as given: an actuator's torque, m |g|, a wrench's
component along a slider's axis, a screw's weight times its pitch, P L^3 / (3 EI) + P L / kGA."""
import os
import sys
import warnings

import numpy as np
import pytest

import phmech as ph
from phmech import se3

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "benchmarks"))
import scenes  # noqa: E402

J = np.diag([1e-3, 1e-3, 1e-3])
G = (0.0, 0.0, -9.81)
STEEL = ph.Material(E=210e9, nu=0.3, density=7850.0)
STRIP = ph.BeamProperties.from_material(ph.Section.strip(width=0.02, thickness=0.001), STEEL)


def refused(m, **kw) -> ph.SolverError:
    """The SolverError of m.static(**kw), which must say that no equilibrium exists."""
    with pytest.raises(ph.SolverError, match="^no static equilibrium: the loads do work on a "
                                             "motion nothing resists: ") as e:
        m.static(**kw)
    return e.value


def test_flexible_arm_names_the_motor_and_its_torque():
    # benchmarks/scenes.py: a hub on a revolute about z driven by 0.3 N m (the Table law's value
    # at t = 0), a flexible arm, no gravity. It took 1133 Newton iterations (0.033 s) to fail
    # with "Newton failed at load factor 1.2207e-05 ..."; now its first failure (the first load
    # step, after the unloaded start's tangent) names the motion
    m, _ = scenes.flexible_arm()
    e = refused(m)
    msg = str(e)
    assert ("pair 'motor' (revolute about z) turns freely under 0.3 N m (effort of actuator "
            "'motor': 0.3 N m), carrying body 'hub', link 'arm'") in msg
    assert "Hold it (a spring or a PD actuator on the pair, a driven coordinate, a Fixed pair)" in msg
    (f,) = e.free_motions
    assert isinstance(f, ph.FreeMotion) and (f.pair, f.coordinate, f.unit) == ("motor", 0, "N m")
    assert f.force == pytest.approx(0.3, abs=1e-12)
    assert f.sources == {"effort of actuator 'motor'": pytest.approx(0.3, abs=1e-12)}
    np.testing.assert_allclose(f.twist, [0, 0, 1, 0, 0, 0], atol=1e-15)
    assert f.moving == ("body 'hub'", "link 'arm'")
    # the last converged state is still attached: the unloaded start
    assert e.result.load_factor == 0 and e.result.iterations <= 13
    np.testing.assert_allclose(e.result.poses, m.initial_configuration().poses, atol=1e-12)


# bodies held by nothing are the point here (static() names them "held by nothing"); a
# ph.Free() pair would turn that into a pair's motion (tested too)
@pytest.mark.filterwarnings("ignore::phmech.UnattachedWarning")
def test_free_body_and_free_link_under_gravity():
    m = ph.Mechanism(gravity=G)
    m.add_rigid_body("box", 2.0, J)
    e = refused(m)
    assert ("body 'box' is held by nothing (no pair, element, spring or interaction links it to the "
            "ground) and the loads push it along -z with 19.62 N (gravity on 2 kg: 19.62 N)") in str(e)
    assert "Hold it (a pair or a spring to the ground)" in str(e)
    (f,) = e.free_motions
    assert f.pair is None and f.force == pytest.approx(2.0 * 9.81, rel=1e-14)
    np.testing.assert_allclose(f.twist, [0, 0, 0, 0, 0, -1], atol=1e-15)
    # a steel strip 0.2 m x 20 mm x 1 mm: m g = 7850 * 2e-5 * 0.2 * 9.81 N, whatever its mesh
    m = ph.Mechanism(gravity=G)
    m.add_flexible_link("leaf", 0.2, STRIP, elements=10)
    (f,) = refused(m).free_motions
    assert f.moving == ("link 'leaf'",)
    assert f.force == pytest.approx(7850 * 0.02 * 0.001 * 0.2 * 9.81, rel=1e-12)


def test_slider_under_a_constant_force():
    # a 5 N force at 53 degrees to the guide: its component along the guide, 3 N, is unresisted
    m = ph.Mechanism()
    s = m.add_rigid_body("slider", 0.5, J)
    m.add_pair("guide", ph.Prismatic("x"), m.ground, s)
    m.add_wrench("push", s, (0, 0, 0, 3.0, 4.0, 0), frame="world")
    e = refused(m)
    assert ("pair 'guide' (prismatic along x) slides freely under 3 N (wrench 'push': 3 N), "
            "carrying body 'slider'") in str(e)
    (f,) = e.free_motions
    assert f.force == pytest.approx(3.0, rel=1e-14) and f.unit == "N"


# bodies held by nothing are the point here (static() names them "held by nothing"); a
# ph.Free() pair would turn that into a pair's motion (tested too)
@pytest.mark.filterwarnings("ignore::phmech.UnattachedWarning")
def test_other_free_motions_and_their_forces():
    # a screw about z with pitch 0.01 m/rad: its nut's weight does m g p = -0.0981 N m per rad
    m = ph.Mechanism(gravity=G)
    nut = m.add_rigid_body("nut", 1.0, J)
    m.add_pair("screw", ph.Helical("z", pitch=0.01), m.ground, nut)
    (f,) = refused(m).free_motions
    assert f.force == pytest.approx(-9.81 * 0.01, rel=1e-12)
    # a motor about the vertical, gravity along its axis: gravity does no work, the torque does
    m = ph.Mechanism(gravity=G)
    r = m.add_rigid_body("rotor", 1.0, J, com=(0.2, 0, 0))
    m.add_pair("motor", ph.Revolute("z"), m.ground, r, actuator=ph.Effort(law=ph.Constant(0.5)))
    (f,) = refused(m).free_motions
    assert f.force == pytest.approx(0.5, abs=1e-12) and list(f.sources) == ["effort of actuator 'motor'"]
    # two revolutes in series, each with its own torque: both motions, each with its own torque
    # (the second's reaction on the first body is internal to the first motion)
    m = ph.Mechanism()
    a = m.add_rigid_body("a", 1.0, J)
    b = m.add_rigid_body("b", 1.0, J, pose=se3.translation([0.3, 0, 0]))
    m.add_pair("j1", ph.Revolute("z"), m.ground, a, actuator=ph.Effort(law=ph.Constant(1.0)))
    m.add_pair("j2", ph.Revolute("z"), a.frame_at((0.3, 0, 0)), b, actuator=ph.Effort(law=ph.Constant(-2.0)))
    f1, f2 = refused(m).free_motions
    assert (f1.pair, f1.force, f1.moving) == ("j1", 1.0, ("body 'a'", "body 'b'"))
    assert (f2.pair, f2.force, f2.moving) == ("j2", -2.0, ("body 'b'",))
    # a body held by nothing under a pure world moment turns about it
    m = ph.Mechanism()
    b = m.add_rigid_body("spin", 1.0, J)
    m.add_wrench("M", b, (0, 0.2, 0, 0, 0, 0), frame="world")
    e = refused(m)
    assert "the loads turn it about y with 0.2 N m (wrench 'M': 0.2 N m)" in str(e)


# ------------------------------------------------------------------ mechanisms that have one
def test_pendulum_under_gravity_solves():
    # started 0.5 rad below the horizontal; hangs with its centre straight below the pivot
    m = ph.Mechanism(gravity=G)
    arm = m.add_rigid_body("arm", 1.0, np.diag([1e-4, 0.0075, 0.0075]), com=(0.15, 0, 0))
    m.add_pair("pivot", ph.Revolute("y"), m.ground, arm, x0=0.5)
    st = m.static()
    np.testing.assert_allclose(st.poses[arm.carrier][:3, :3] @ [1, 0, 0], [0, 0, -1], atol=1e-9)
    assert st.stable


def test_cantilever_under_a_tip_load_solves():
    # small load: Timoshenko's P L^3/(3 EI) + P L/kGA less the constant-strain elements' exact
    # discretization error P L^3/(12 EI N^2) (tests/test_statics.py)
    from phmech.section import TABLE1, table1_properties
    L, EI, kGA, N = TABLE1["L"], TABLE1["EI"], TABLE1["kGA"], 10
    P = 1e-5 * EI / L**2
    m = ph.Mechanism()
    b = m.add_flexible_link("b", L, table1_properties(1.0), elements=N)
    m.add_pair("clamp", ph.Fixed(), m.ground, b.start)
    st = m.static(loads=[(b.end, (0, 0, 0, 0, 0, P), "world")])
    w = P * L**3 / (3 * EI) + P * L / kGA - P * L**3 / (12 * EI * N**2)
    assert st.positions(b)[-1][2] == pytest.approx(w, rel=1e-9)


def test_zero_stiffness_with_a_load_along_it_is_not_refused():
    # benchmarks/scenes.py's double pendulum starts horizontal: its tangent there has two
    # zero-stiffness directions with gravity's torque along them (what a test on the tangent
    # alone would refuse), and it hangs at an equilibrium (an unstable one at 10 load steps, as
    # before: StabilityWarning)
    m, _ = scenes.double_pendulum()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ph.StabilityWarning)
        st = m.static()
    assert st.load_factor == 1.0
    # a world force across a revolute: it turns until the arm lines up with the force
    m = ph.Mechanism()
    r = m.add_rigid_body("r", 1.0, J)
    m.add_pair("p", ph.Revolute("z"), m.ground, r)
    st = m.static(loads=[(r.frame_at((0.1, 0, 0)), (0, 0, 0, 0, 1.0, 0), "world")])
    np.testing.assert_allclose(st.poses[r.carrier][:3, 0], [0, 1, 0], atol=1e-9)


@pytest.mark.parametrize("case", ["motor on a cantilever under gravity", "spring at rest length"])
def test_no_claim_where_the_structure_does_not_prove_one(case):
    # a motor on a cantilever's tip under gravity along its axis: the cantilever can tilt the
    # axis, and gravity then does work on the rotor; a body on a spring at its rest length pushed
    # sideways: no stiffness across the spring at first, but the spring turns and holds it. Both
    # have an equilibrium; static() may fail to find it (it does today), but must not say none exists
    m = ph.Mechanism(gravity=G if case.startswith("motor") else (0, 0, 0))
    if case.startswith("motor"):
        leaf = m.add_flexible_link("leaf", 0.2, STRIP, elements=6)
        m.add_pair("clamp", ph.Fixed(), m.ground, leaf.start)
        rotor = m.add_rigid_body("rotor", 0.1, J, pose=se3.translation([0.2, 0, 0]), com=(0.05, 0, 0))
        m.add_pair("motor", ph.Revolute("z"), leaf.end, rotor, actuator=ph.Effort(law=ph.Constant(0.01)))
    else:
        bob = m.add_rigid_body("bob", 1.0, J, pose=se3.translation([0, 0, -1.0]))
        m.add_spring_damper("s", m.ground, bob, k=100.0)
        m.add_wrench("side", bob, (0, 0, 0, 1.0, 0, 0), frame="world")
    try:
        m.static()
    except ph.SolverError as e:
        assert e.free_motions == [] and "no static equilibrium" not in str(e)


def test_a_free_pair_from_the_ground_is_named_as_the_motion():
    """UnattachedWarning's advice for an intended free body is a ph.Free() pair: static() then
    names that pair's coordinate along gravity, with the weight m g = 2 * 9.81 N."""
    m = ph.Mechanism(gravity=(0.0, 0.0, -9.81))
    box = m.add_rigid_body("box", 2.0, np.eye(3) * 1e-2)
    m.add_pair("float", ph.Free(), m.ground, box)
    with pytest.raises(ph.SolverError, match=r"pair 'float' \(free, coordinate 5 along z\)") as e:
        m.static()
    assert abs(abs(e.value.free_motions[0].force) - 2 * 9.81) < 1e-9

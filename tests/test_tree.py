"""integrator="tree" (csrc/integrate/tree.c, tree_aba.c): a rigid tree in joint coordinates,
articulated-body dynamics and Dormand-Prince 5(4). Checked against a closed form (the large-
amplitude pendulum), against IDA (a 10-link chain), by its energy ledger, and by the models it
refuses."""
import warnings

import numpy as np
import pytest
from scipy.special import ellipj, ellipk

import phmech as ph
from phmech import se3

G = 9.81


def chain(n: int, L: float = 0.1, mass: float = 0.1, axes: str = "z"):
    """n slender links (the chain of benchmarks/bench_scaling.py), horizontal at the start,
    gravity -y, link i's revolute axis axes[i % len(axes)]; returns the mechanism and the links'
    end frames."""
    m = ph.Mechanism(gravity=(0, -G, 0))
    prev, ends = ph.Frame(-1, np.eye(4)), []
    inertia = np.diag((0.5 * mass * 0.005 ** 2, mass * L ** 2 / 12, mass * L ** 2 / 12))
    for i in range(n):
        b = m.add_rigid_body(f"l{i}", mass, inertia, com=(L / 2, 0, 0))
        m.add_pair(f"k{i}", ph.Revolute(axes[i % len(axes)]), prev, b, x0=0.0)
        prev = ph.Frame(b.carrier, se3.translation([L, 0, 0]))
        ends.append(prev)
    return m, ends


def pendulum_170():
    """The physical pendulum released from rest 170 deg from hanging, and its exact angle and
    rate (theta(t) = 2 asin(k sn(K - w0 t | k^2)), k = sin(theta0 / 2), w0^2 = m g d /
    I_pivot), its period [s] and w0 [rad/s]."""
    mass, d, Ic = 2.0, 0.7, 0.03
    m = ph.Mechanism(gravity=(0, -G, 0))
    b = m.add_rigid_body("bob", mass, np.diag((0.01, 0.02, Ic)), com=(d, 0, 0))
    th0 = np.radians(170.0)
    m.add_pair("pivot", ph.Revolute("z"), ph.Frame(-1, np.eye(4)), b, x0=th0 - np.pi / 2)
    w0 = np.sqrt(mass * G * d / (Ic + mass * d ** 2))
    k = np.sin(th0 / 2)
    K = ellipk(k ** 2)

    def exact(t):
        sn, cn, dn, _ = ellipj(K - w0 * t, k ** 2)
        return 2 * np.arcsin(k * sn), -2 * k * w0 * cn   # d/dt 2 asin(k sn(u)), u' = -w0
    return m, exact, 4 * K / w0, w0


def errors_over_tolerance(r, exact, rtol: float) -> float:
    """The 170 deg pendulum's largest error of its joint coordinate (the angle from hanging
    minus pi/2) and of its rate, each over rtol times its largest magnitude plus atol
    (rtol / 100): the contract's figure."""
    theta, rate = exact(r.t)
    x, atol = theta - np.pi / 2, rtol / 100
    return max(np.abs(r.joints[:, 0] - x).max() / (rtol * np.abs(x).max() + atol),
               np.abs(r.joint_rates[:, 0] - rate).max() / (rtol * np.abs(rate).max() + atol))


@pytest.mark.parametrize("rtol", [1e-6, 1e-8])
def test_the_error_check_keeps_the_result_within_its_tolerance(rtol):
    """The tree integrator controls each step's local error: over 1.5 periods of the 170 deg
    pendulum its result was ~100x its tolerance off, and nothing said so (error_check=False
    still runs so). The error check (Mechanism.simulate's error_check) estimates a run's error
    by its difference from a run at rtol/10 and, above the tolerance, checks that run in turn:
    the result is the first run within it. Measured (true error over the tolerance, unchecked
    and checked; the estimate; the rtol of the run returned): rtol 1e-6: 120 and 0.87; 0.79;
    1e-8; rtol 1e-8: 87 and 0.78; 0.70; 1e-10."""
    m, exact, period, _ = pendulum_170()
    with warnings.catch_warnings():
        warnings.simplefilter("error", ph.AccuracyWarning)
        raw = m.simulate(1.5 * period, period / 40, rtol=rtol, integrator="tree",
                         error_check=False)
        r = m.simulate(1.5 * period, period / 40, rtol=rtol, integrator="tree")
    assert raw.stats["global_error_estimate"] is None
    assert errors_over_tolerance(raw, exact, rtol) > 30
    true = errors_over_tolerance(r, exact, rtol)
    assert true <= 1.0 and r.stats["global_error_estimate"] <= 1.0, (true, r.stats)
    assert r.stats["rtol"] == rtol and r.stats["integration_rtol"] < rtol
    assert r.stats["error_check_rtol"] == pytest.approx(r.stats["integration_rtol"] / 10)
    assert r.stats["global_error_state"] in ("joint coordinate 0 of pair 'pivot'",
                                             "joint rate 0 of pair 'pivot'")
    with pytest.raises(ph.ModelError, match="error_check applies to integrator=.tree. and .ida."):
        m.simulate(0.1, 0.05, error_check=True)


def test_the_error_check_says_when_it_cannot_keep_the_tolerance():
    """A chaotic motion outgrows 10 000x tighter steps: a double pendulum of two 0.5 m links
    released horizontal, 10 s at rtol 1e-6. The check warns with its figure (measured 1907,
    refined to rtol 1e-10)."""
    m, _ = chain(2, L=0.5, mass=1.0)
    with pytest.warns(ph.AccuracyWarning, match="integrator='tree' is probably not"):
        r = m.simulate(10.0, 0.01, rtol=1e-6, integrator="tree")
    assert r.stats["global_error_estimate"] > 100
    assert r.stats["integration_rtol"] == pytest.approx(1e-10)


def test_ida_checks_its_result_on_request():
    """IDA controls each step's local error too, and is not checked unless asked: the 170 deg
    pendulum at rtol 1e-6 ends 167x its tolerance off, silently. With error_check=True the same
    refinement: four runs to rtol 1e-10 return a result 0.37x its tolerance off, and warn,
    since the estimate at the last run (3.6: the run before it's error) is above 1. A flexible
    link refuses the check (its nodes have no joint coordinates)."""
    m, exact, period, _ = pendulum_170()
    with warnings.catch_warnings():
        warnings.simplefilter("error", ph.AccuracyWarning)
        raw = m.simulate(1.5 * period, period / 40, rtol=1e-6, integrator="ida")
    assert "global_error_estimate" not in raw.stats
    assert errors_over_tolerance(raw, exact, 1e-6) > 100
    with pytest.warns(ph.AccuracyWarning, match="integrator='ida' is probably not"):
        r = m.simulate(1.5 * period, period / 40, rtol=1e-6, integrator="ida", error_check=True)
    assert errors_over_tolerance(r, exact, 1e-6) < 1.0
    assert r.stats["integration_rtol"] == pytest.approx(1e-10)
    assert r.stats["global_error_estimate"] > 1
    steel = ph.Material(E=210e9, nu=0.3, density=7850.0)
    flex = ph.Mechanism()
    flex.add_flexible_link("rod", 0.3, ph.BeamProperties.from_material(
        ph.Section.strip(width=0.02, thickness=0.002), steel), elements=2)
    with pytest.raises(ph.ModelError, match="rigid mechanisms only"):
        flex.simulate(0.01, 0.005, integrator="ida", error_check=True)


def test_an_error_check_that_cannot_run_says_so(monkeypatch):
    """A check run that stops (here made to, by the core's second call returning an error)
    leaves the result unchecked, and an AccuracyWarning says so."""
    from phmech import _simulate
    real, calls = _simulate._core.model_simulate, []

    def second_fails(*args, **kw):
        out = real(*args, **kw)
        calls.append(1)
        if len(calls) == 2:
            out["error"] = "made to fail"
        return out
    monkeypatch.setattr(_simulate._core, "model_simulate", second_fails)
    m, _ = chain(2)
    with pytest.warns(ph.AccuracyWarning,
                      match="error check of integrator=.tree. could not run.*made to fail"):
        r = m.simulate(0.2, 0.05, integrator="tree")
    assert r.stats["global_error_estimate"] is None and len(calls) == 2


def test_pendulum_at_170_degrees_matches_the_elliptic_closed_form():
    """A physical pendulum released from rest 170 deg from hanging (pendulum_170) against its
    elliptic closed form over 1.5 periods."""
    m, exact, period, w0 = pendulum_170()
    errs = []
    for rtol in (1e-8, 1e-10):
        r = m.simulate(1.5 * period, period / 40, rtol=rtol, integrator="tree")
        theta_exact, rate_exact = exact(r.t)
        theta = r.joints[:, 0] + np.pi / 2
        assert np.ptp(theta) > 2 * np.radians(170.0) * 0.99   # through the bottom to -170 deg
        errs.append(np.abs(theta - theta_exact).max())
        assert np.abs(r.joint_rates[:, 0] - rate_exact).max() < 1e3 * rtol * w0
    # measured 3.5e-6 and 3.2e-8 rad (IDA at the same rtol: 3.0e-4 and 2.0e-6): the error
    # follows the tolerance
    assert errs[0] < 1e-5 and errs[1] < 1e-7, errs


def test_ten_link_chain_matches_ida():
    """The tree integrator and IDA on the same 10-link chain at rtol 1e-10: every link's end,
    the twists and the multipliers."""
    m, ends = chain(10)
    ri = m.simulate(0.3, 0.02, rtol=1e-10, integrator="ida")
    rt = m.simulate(0.3, 0.02, rtol=1e-10, integrator="tree")
    pi = np.array([ri.position(e) for e in ends])
    pt = np.array([rt.position(e) for e in ends])
    assert np.ptp(pt[-1, :, 1]) > 0.1                  # the chain falls
    # measured 1.8e-11 m, 5.2e-10 rad, lambda 3.9e-8 of its largest
    assert np.abs(pi - pt).max() < 1e-9
    assert np.abs(ri.joints - rt.joints).max() < 1e-8
    lam_i, lam_t = ri.constraint_wrenches, rt.constraint_wrenches
    assert np.abs(lam_i - lam_t).max() < 1e-6 * np.abs(lam_i).max()


def test_conservative_chain_keeps_its_ledger():
    """No dissipation and no sources: the ledger residual (energy drift) stays at the
    integrator's error, nothing dissipated or supplied."""
    m, _ = chain(5, axes="zy")      # axes z, y, z, ...: a spatial motion
    r = m.simulate(1.0, 0.01, rtol=1e-9, integrator="tree")
    E = r.energy
    scale = np.abs(E["gravity"]).max()
    assert np.abs(E["kinetic"]).max() > 0.1 * scale            # it moves
    # measured 1.7e-9 J of 1.2 J
    assert np.abs(E["ledger"]).max() < 1e-8 * scale, np.abs(E["ledger"]).max() / scale
    assert np.abs(E["dissipated"]).max() == 0 and np.abs(E["supplied"]).max() == 0


def test_a_damped_joint_dissipates_what_the_ledger_counts():
    """A joint damper (a viscous component without states): the energy it takes is the
    ledger's dissipated energy, and the run is IDA's."""
    m, _ = chain(3)
    m.add_component("damper", "k1", ph.ViscousFriction(0.002))
    r = m.simulate(0.5, 0.01, rtol=1e-9, integrator="tree")
    ri = m.simulate(0.5, 0.01, rtol=1e-10, integrator="ida")
    assert r.energy["dissipated"][-1] > 1e-4 * np.abs(r.energy["gravity"]).max()
    # measured: 0.016 J dissipated, ledger 2.9e-11 J, 6.5e-11 J from IDA's
    assert np.abs(r.energy["ledger"]).max() < 1e-9
    assert abs(r.energy["dissipated"][-1] - ri.energy["dissipated"][-1]) < 1e-9
    assert abs(r.energy["total"][-1] - ri.energy["total"][-1]) < 1e-8


@pytest.mark.filterwarnings("ignore::phmech.RedundantConstraintWarning")   # the loop's
@pytest.mark.parametrize("build, reason", [
    ("flexible", "beam element"),
    ("spherical", "spherical, whose motion subspace is not constant"),
    ("loop", "closed loop"),
])
def test_ineligible_models_are_refused_with_their_reason(build, reason):
    m = ph.Mechanism(gravity=(0, -G, 0))
    g = ph.Frame(-1, np.eye(4))
    if build == "flexible":
        from phmech.section import TABLE1, table1_properties
        link = m.add_flexible_link("beam", TABLE1["L"], table1_properties(), elements=2)
        m.add_pair("root", ph.Fixed(), m.ground, link.start)
    elif build == "spherical":
        b = m.add_rigid_body("b", 1.0, np.eye(3) * 1e-3, com=(0.5, 0, 0))
        m.add_pair("s", ph.Spherical(), g, b)
    else:   # a four-bar: a closed loop
        m, _ = chain(3)
        m.add_pair("close", ph.Revolute("z"), ph.Frame(2, se3.translation([0.1, 0, 0])),
                   ph.Frame(-1, se3.translation([0.3, 0, 0])))
    with pytest.raises(ValueError, match=reason):
        m.simulate(0.1, 0.01, integrator="tree")


def test_options_that_do_not_apply_are_refused():
    m, _ = chain(2)
    with pytest.raises(ValueError, match="ida"):
        m.simulate(0.1, 0.01, integrator="tree", error_test="configuration")
    with pytest.raises(ValueError, match="planar"):
        m.simulate(0.1, 0.01, integrator="tree", planar=True)
    with pytest.raises(ValueError, match="step="):
        m.simulate(0.1, 0.01, integrator="tree", step=1e-3)


def test_every_supported_pair_type_matches_ida():
    """A spatial tree with each pair type the tree integrator takes -- revolute, prismatic,
    cylindrical, helical, fixed -- and a branch (two children on one body), a joint spring on
    the prismatic, against IDA at rtol 1e-10."""
    m = ph.Mechanism(gravity=(0, -G, 0))
    g = ph.Frame(-1, np.eye(4))
    J = np.diag((2e-3, 3e-3, 4e-3))
    b0 = m.add_rigid_body("b0", 1.0, J, com=(0.1, 0.02, 0))
    m.add_pair("r0", ph.Revolute("z"), g, b0, x0=0.3)
    b1 = m.add_rigid_body("b1", 0.5, J, com=(0.05, 0, 0.01))
    m.add_pair("p1", ph.Prismatic("x"), ph.Frame(b0.carrier, se3.translation([0.2, 0, 0])), b1,
               x0=0.05)
    m.add_actuator("spring", "p1", ph.Spring(50.0, 0.1, rest=0.05))
    b2 = m.add_rigid_body("b2", 0.4, J, com=(0.0, 0.05, 0.02))
    m.add_pair("c2", ph.Cylindrical("y"), ph.Frame(b1.carrier, se3.translation([0.1, 0, 0])), b2,
               x0=[0.2, 0.01])
    b3 = m.add_rigid_body("b3", 0.3, J, com=(0.03, 0, 0.03))
    m.add_pair("h3", ph.Helical("x", pitch=0.02), ph.Frame(b0.carrier, se3.translation([0, 0.1, 0])),
               b3, x0=0.5)
    b4 = m.add_rigid_body("b4", 0.2, J, com=(0.02, 0.02, 0))
    m.add_pair("f4", ph.Fixed(), ph.Frame(b3.carrier, se3.translation([0.1, 0, 0.05])), b4)
    ri = m.simulate(0.3, 0.05, rtol=1e-10, integrator="ida")
    rt = m.simulate(0.3, 0.05, rtol=1e-10, integrator="tree")
    assert np.ptp(rt.joints, axis=0).min() > 1e-3, np.ptp(rt.joints, axis=0)   # every joint moves
    # measured 3.2e-10 (joints), 2.8e-9 (twists), lambda 5.3e-9 of its largest
    assert np.abs(ri.joints - rt.joints).max() < 1e-8
    assert np.abs(ri.twists - rt.twists).max() < 1e-7
    lam_i, lam_t = ri.constraint_wrenches, rt.constraint_wrenches
    assert np.abs(lam_i - lam_t).max() < 1e-7 * np.abs(lam_i).max()


def test_laws_with_breakpoints_match_ida():
    """An effort pulse on the second joint and a PD set point stepping on the first: the steps
    land on the laws' breakpoints (a new piece each), as IDA's restarts do; the supplied energy is
    the ledger's."""
    m, ends = chain(3)
    m.add_actuator("kick", "k1", ph.Effort(ph.Pulse(0.05, 0.1, 0.02)))
    m.add_actuator("hold", "k0", ph.PD(2.0, 0.05, ph.Step(0.17, -0.3)))
    ri = m.simulate(0.4, 0.02, rtol=1e-10, integrator="ida")
    rt = m.simulate(0.4, 0.02, rtol=1e-10, integrator="tree")
    # measured: -0.139 J supplied, joints 2.5e-9 rad and supplied 3.4e-11 J from IDA's, ledger 2e-12 J
    assert abs(rt.energy["supplied"][-1]) > 1e-3
    assert np.abs(ri.joints - rt.joints).max() < 1e-8
    assert abs(ri.energy["supplied"][-1] - rt.energy["supplied"][-1]) < 1e-9
    assert np.abs(rt.energy["ledger"]).max() < 1e-9


def test_a_callback_stops_the_run_at_an_output():
    """The outputs go through the DAE's output routine: a callback that asks to stop ends the
    run there, with the outputs so far (as IDA's and the generalized-alpha's)."""
    m, _ = chain(3)
    seen = []
    r = m.simulate(0.5, 0.05, integrator="tree", callback=lambda t, i: seen.append(t) or i >= 3)
    assert len(r.t) == 4 and np.allclose(r.t, [0, 0.05, 0.1, 0.15])
    assert np.allclose(seen, r.t)


def test_sampled_controllers_are_refused():
    m = ph.Mechanism(gravity=(0, -G, 0))
    b = m.add_rigid_body("bob", 1.0, np.diag([0.02, 0.02, 0.02]), com=(0, -0.5, 0))
    m.add_pair("hinge", ph.Revolute("z"), m.ground, b, x0=[0.01])
    m.add_sensor("q", ph.JointSensor("hinge"))
    m.add_controller("p", ph.SampledController(lambda t, y, s: ((-5 * y[0],), s), 100.0,
                                               inputs=["q"], outputs=["hinge"]))
    with pytest.raises(ValueError, match="tree integrator takes no sampled controllers"):
        m.simulate(0.1, 0.01, integrator="tree")


def test_bodies_listed_before_their_parents_with_a_spring_and_initial_rates():
    """The tree's order is found, not assumed (carrier 0 is the grandchild); a damped
    point-to-point spring between two bodies, skewed axes and initial joint rates; against IDA
    at rtol 1e-10."""
    m = ph.Mechanism(gravity=(0, -G, 0))
    J = np.diag((2e-3, 3e-3, 4e-3))
    b2 = m.add_rigid_body("b2", 0.3, J, com=(0.05, 0.01, 0))
    b1 = m.add_rigid_body("b1", 0.5, J, com=(0.1, 0, 0.02))
    b0 = m.add_rigid_body("b0", 1.0, J, com=(0.1, 0, 0))
    m.add_pair("r0", ph.Revolute("x"), m.ground, b0, x0=0.4, xdot0=1.0)
    m.add_pair("r1", ph.Revolute("y"), ph.Frame(b0.carrier, se3.translation([0.2, 0, 0])), b1,
               x0=-0.3, xdot0=-2.0)
    m.add_pair("r2", ph.Revolute("z"), ph.Frame(b1.carrier, se3.translation([0.2, 0.05, 0])), b2,
               x0=0.7)
    m.add_spring_damper("s", ph.Frame(b2.carrier, np.eye(4)), ph.Frame(b0.carrier, np.eye(4)),
                        30.0, 0.2, point_a=(0.1, 0, 0), point_b=(0.05, 0.02, 0))
    ri = m.simulate(0.5, 0.05, rtol=1e-10, integrator="ida")
    rt = m.simulate(0.5, 0.05, rtol=1e-10, integrator="tree")
    assert np.allclose(rt.joint_rates[0], [1.0, -2.0, 0.0], atol=1e-12)
    assert np.ptp(rt.joints, axis=0).min() > 1.0
    # measured 2.1e-9 rad, 2.0e-8 (twists), lambda 1.0e-8 of its largest, ledger 1.8e-11 J,
    # dissipated 0.0198 J, 4.6e-12 J from IDA's
    assert np.abs(ri.joints - rt.joints).max() < 1e-8
    assert np.abs(ri.twists - rt.twists).max() < 1e-7
    lam_i, lam_t = ri.constraint_wrenches, rt.constraint_wrenches
    assert np.abs(lam_i - lam_t).max() < 1e-7 * np.abs(lam_i).max()
    assert np.abs(rt.energy["ledger"]).max() < 1e-9
    assert abs(rt.energy["dissipated"][-1] - ri.energy["dissipated"][-1]) < 1e-9


def test_an_output_at_a_breakpoint_reads_the_piece_that_ends_there():
    """An effort stepping on at an output time: that output's effort and multipliers are the
    left limit's, the piece that ends there, as IDA's (which restarts after that output); the
    next output has the new effort."""
    m, _ = chain(2)
    m.add_actuator("push", "k1", ph.Effort(ph.Step(0.1, 0.05)))
    ri = m.simulate(0.2, 0.05, rtol=1e-10, integrator="ida")
    rt = m.simulate(0.2, 0.05, rtol=1e-10, integrator="tree")
    assert np.isclose(rt.t[2], 0.1) and rt.efforts[2, 1] == 0.0 and rt.efforts[3, 1] == 0.05
    assert np.abs(ri.efforts - rt.efforts).max() == 0.0
    lam_i, lam_t = ri.constraint_wrenches, rt.constraint_wrenches
    assert np.abs(lam_i - lam_t).max() < 1e-7 * np.abs(lam_i).max()


def test_random_trees_match_ida():
    """Random trees of five bodies: random pair types among those taken (axes x, y or z),
    random frames, random inertias and centres of mass, bodies in random order, joint springs
    on the prismatic and cylindrical pairs; against IDA at rtol 1e-10. Measured over the first
    12 trees of this sequence (4 run here): poses within 4.9e-10, twists 1.3e-8, lambda 6.0e-8
    of its largest, ledger 6.2e-11 J."""
    rng = np.random.default_rng(1)
    types = [lambda ax: ph.Revolute(ax), lambda ax: ph.Prismatic(ax),
             lambda ax: ph.Helical(ax, pitch=0.05), lambda ax: ph.Cylindrical(ax), lambda ax: ph.Fixed()]
    for trial in range(4):
        m = ph.Mechanism(gravity=(0, -G, 0))
        bodies = []
        for i in range(5):
            R = se3.exp(np.concatenate([rng.normal(size=3), np.zeros(3)]))[:3, :3]
            J = R @ np.diag(rng.uniform(2e-3, 3e-3, 3)) @ R.T
            bodies.append(m.add_rigid_body(f"b{i}", rng.uniform(0.2, 1.0), J,
                                           com=rng.uniform(-0.1, 0.1, 3)))
        perm = rng.permutation(5)
        for k, i in enumerate(perm):
            parent = -1 if k == 0 else perm[rng.integers(0, k)]
            T = se3.exp(np.concatenate([rng.uniform(-1, 1, 3), rng.uniform(-0.2, 0.2, 3)]))
            a = ph.Frame(-1 if parent < 0 else bodies[parent].carrier, T)
            ti = rng.integers(0, 4 if k == 0 else 5)   # the root moves
            m.add_pair(f"p{i}", types[ti](rng.choice(["x", "y", "z"])), a, bodies[i])
            if ti == 1:
                m.add_actuator(f"s{i}", f"p{i}", ph.Spring(20.0, 0.1))
            elif ti == 3:
                m.add_actuator(f"s{i}", f"p{i}", ph.Spring([20.0, 20.0], [0.1, 0.1]))
        ri = m.simulate(0.3, 0.05, rtol=1e-10, integrator="ida")
        rt = m.simulate(0.3, 0.05, rtol=1e-10, integrator="tree")
        assert np.abs(ri.poses - rt.poses).max() < 1e-8, trial
        assert np.abs(ri.twists - rt.twists).max() < 1e-7, trial
        lam_i, lam_t = ri.constraint_wrenches, rt.constraint_wrenches
        assert np.abs(lam_i - lam_t).max() < 1e-6 * np.abs(lam_i).max(), trial
        assert np.abs(rt.energy["ledger"]).max() < 1e-8, trial


"""Port-Hamiltonian controllers (python/phmech/components.py, PortHamiltonianController;
csrc/model/component.c, PHM_COMP_PH; docs/method.md section 4.11): a passive controller whose
energy is stored and whose losses are dissipated, so the energy ledger closes with it.

- The paper's Fig. 3 manipulator (examples/manipulator.py: three flexible and three rigid links,
  a flexible parallelogram forearm, gravity), its four PD actuators replaced by energy-shaping +
  damping-injection controllers (one state each: a virtual spring to the set point, a damper),
  with the example's gravity-compensation torques: the joints reach the set points (the
  controllers' springs relax) to 2.6e-6 rad, each controller state stays its joint's
  coordinate (the Casimir) to 1.5e-11 rad, the trajectory is the PD actuators' (the same
  law, another implementation: csrc/model/applied.c) to 2.8e-9 rad, and the ledger, with the
  controllers' energy, closes to 2.0e-8 J of 25.9 J (held to 1e-6 J; IDA rtol 1e-9).
- A disc under a two-state controller with R > 0 (a dissipative spring-damper in series, a
  Maxwell element): the energy balance of the controller alone, and the closed loop's poles
  (linearize) against the hand-written matrix.
- Bad input is named.
"""
import os
import sys
import warnings

import numpy as np
import pytest

import phmech as ph

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "examples"))
import manipulator as man                                       # noqa: E402


@pytest.fixture(scope="module")
def manipulator_run():
    p = man.ManipulatorParams()
    ff, _ = man.gravity_compensation(p, elements=4)
    pd, _ = man.build(p, elements=4, ff=ff, knock=False)
    m, _ = man.build(p, elements=4, ff=ff, kp=[0.0] * 4, kd=[0.0] * 4, knock=False)
    for name, kp, kd, x in zip(man.ACTUATED, p.kp, p.kd, p.target):
        m.add_component(name + ".ph", name, ph.PortHamiltonianController(
            Q=[[kp]], damping=kd, target=[x], x0=[0.0]))         # xc(0) = x(0) = 0: a Casimir
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ph.RedundantConstraintWarning)
        res = m.simulate(6.0, 0.01, integrator="ida", rtol=1e-9)
        ref = pd.simulate(6.0, 0.01, integrator="ida", rtol=1e-9)
    return p, m, res, ref


def test_manipulator_reaches_the_set_point(manipulator_run):
    p, m, res, ref = manipulator_run
    assert np.max(np.abs(res.joints - ref.joints)) < 1e-6       # the PD actuators' motion
    x = man.planar_joint_angles(m, res.poses[-1])
    err = max(abs(x[n] - t) for n, t in zip(man.ACTUATED, p.target))
    assert err < 1e-4
    for n in man.ACTUATED:                      # xc - x stays at its initial 0 (the Casimir)
        xc = res.components[n + ".ph"]["x0"]
        assert abs(xc[-1] - res.joint(n)["x"][-1, 0]) < 1e-6


def test_manipulator_ledger_closes(manipulator_run):
    _, _, res, _ = manipulator_run
    e = res.energy
    assert np.max(np.abs(e["ledger"])) < 1e-6


def test_maxwell_controller_poles_and_ledger():
    """xc1' = v (a Casimir: spring k1 to the target), xc2' = -r k2 xc2 + v (spring k2 in series
    with a damper 1/r): u = -k1 xc1 - k2 xc2 - d v."""
    from scipy.linalg import eigvals
    Jd, k1, k2, r, d, th0 = 0.05, 3.0, 5.0, 2.0, 0.05, 0.2
    m = ph.Mechanism(gravity=(0, 0, 0))
    disc = m.add_rigid_body("disc", 1.0, np.diag([0.03, 0.03, Jd]))
    m.add_pair("hub", ph.Revolute("z"), m.ground, disc, x0=th0)
    m.add_component("ctl", "hub", ph.PortHamiltonianController(
        J=np.zeros((2, 2)), R=np.diag([0.0, r]), Q=np.diag([k1, k2]), B=[1.0, 1.0], damping=d,
        x0=[th0, 0.0]))
    A = np.array([[0, 1, 0, 0], [0, -d / Jd, -k1 / Jd, -k2 / Jd], [0, 1, 0, 0],
                  [0, 1, 0, -r * k2]])
    ref = eigvals(A)
    m0 = ph.Mechanism(gravity=(0, 0, 0))               # linearized about its rest (theta = 0)
    disc0 = m0.add_rigid_body("disc", 1.0, np.diag([0.03, 0.03, Jd]))
    m0.add_pair("hub", ph.Revolute("z"), m0.ground, disc0)
    m0.add_component("ctl", "hub", ph.PortHamiltonianController(
        J=np.zeros((2, 2)), R=np.diag([0.0, r]), Q=np.diag([k1, k2]), B=[1.0, 1.0], damping=d))
    lin = m0.linearize()
    p = lin.poles()
    assert max(np.min(np.abs(q - p)) / max(abs(q), 1.0) for q in ref) < 1e-10
    res = m.simulate(5.0, 0.01, integrator="ida", rtol=1e-10)
    e = res.energy
    assert np.max(np.abs(e["ledger"])) < 1e-8
    assert abs(res.joints[-1, 0]) < 0.05 * th0           # to the target 0
    # the controller's energy is stored: (k1 xc1^2 + k2 xc2^2)/2 at t = 0
    assert e["elastic"][0] == pytest.approx(0.5 * k1 * th0 ** 2, rel=1e-9)


def test_bad_port_hamiltonian_controllers_are_named():
    m = ph.Mechanism(gravity=(0, 0, 0))
    b = m.add_rigid_body("b", 1.0, np.eye(3))
    m.add_pair("hub", ph.Revolute("z"), m.ground, b)
    with pytest.raises(ph.ModelError, match="component 'c'.*J must be skew"):
        m.add_component("c", "hub", ph.PortHamiltonianController(J=[[1.0]]))
    with pytest.raises(ph.ModelError, match="component 'c'.*Q must be symmetric positive"):
        m.add_component("c", "hub", ph.PortHamiltonianController(Q=[[-1.0]]))
    with pytest.raises(ph.ModelError, match="component 'c'.*damping must be >= 0"):
        m.add_component("c", "hub", ph.PortHamiltonianController(damping=-1.0))
    with pytest.raises(ph.ModelError, match="component 'c'.*1 to 2"):
        m.add_component("c", "hub", ph.PortHamiltonianController(
            J=np.zeros((3, 3)), R=np.zeros((3, 3)), Q=np.eye(3), B=np.ones(3)))

"""Sensors as outputs of ``Mechanism.linearize`` (python/phmech/linear.py, ``sensor_rows``):
joint coordinates and rates, frames' poses, positions, twists and velocities, tip deflections,
link strains and component states, each row checked against an independent route.

- Displacement outputs: the static compliance C K^-1 B of a tip force against central finite
  differences of ``static()`` (the nonlinear equilibrium, tol 1e-13) at +-1e-3 N: about the
  undeformed arm and about an equilibrium under a 3-D tip preload of (0, 30, 8) N (tip rotated
  0.37 rad, the hub 3 rad), so that the logarithms' first order (se3.dexp_inv) is exercised away
  from the identity. The hub angle is read from the hub's pose (atan2), the others with the
  sensors' own functions (phmech.sensors.sensor_values) on the equilibrium poses. Measured:
  1.1e-8 of the largest value about the undeformed arm, 8.8e-10 about the preloaded one (the
  central differences' O(F^2) and the solves' tolerance); bound 1e-6.
- Rate outputs: the linear model's response (scipy.signal.lsim) to a 1e-3 N tip force ramped
  up over 50 ms against ``simulate`` (rtol 1e-8) of the nonlinear arm: the joint rate (sensor
  and port), the tip frame's twist and world velocity, and the displacements again, within 1e-4
  of their peaks (measured 3.6e-5 at most, the tip's angular rate; 1.1e-5 the hub's: the
  integrator's error and the motion's own nonlinearity, its amplitude ~ 1e-4 rad).
- A component state (a DC motor's current) against simulate: the motor on a rigid hub is linear,
  so its current decays exactly as the linear model's (to the integrator's tolerance).
- The rows the notebook notebooks/controller_tuning.ipynb builds from ``lin.basis`` by hand
  (hub angle, TipDeflection[:, 4]) are the sensors' rows, exactly.
"""
import numpy as np
import pytest
from scipy import signal

import phmech as ph
from phmech.sensors import sensor_values

STEEL = ph.Material(E=210e9, nu=0.3, density=7850.0)
STRIP = ph.BeamProperties.from_material(
    ph.Section.strip(width=0.02, thickness=0.002, thin_along="y"), STEEL)
L = 0.5
DISP = ["q", "tip", "pos", "pose", "strain"]


def arm(spring=5.0):
    """A hub on a revolute about z (a torsion spring ``spring`` N m/rad, or none) and a steel
    strip clamped to it along x, 4 elements, no gravity; its sensors."""
    m = ph.Mechanism(gravity=(0, 0, 0))
    hub = m.add_rigid_body("hub", 1.0, np.diag([3e-3, 3e-3, 5e-3]))
    m.add_pair("joint", ph.Revolute("z"), m.ground, hub,
               actuator=None if spring is None else ph.Spring(k=spring, rest=0.0))
    link = m.add_flexible_link("strip", L, STRIP, elements=4, start=hub.frame)
    m.add_pair("clamp", ph.Fixed(), hub, link.start)
    m.add_sensor("q", ph.JointSensor("joint"))                  # [rad]
    m.add_sensor("qd", ph.JointSensor("joint", rate=True))      # [rad/s]
    m.add_sensor("tip", ph.TipDeflection(link))                 # [rad, m]
    m.add_sensor("pos", ph.FrameSensor(link.end, "position"))   # [m]
    m.add_sensor("pose", ph.FrameSensor(link.end, "pose"))      # [-, m]
    m.add_sensor("twist", ph.FrameSensor(link.end, "twist"))    # [rad/s, m/s]
    m.add_sensor("vel", ph.FrameSensor(link.end, "velocity"))   # [m/s]
    m.add_sensor("strain", ph.LinkStrain(link, 0.1))            # [1/m, -]
    return m, link


def values(m, poses):
    """The displacement sensors' values at the poses of an equilibrium; the hub angle from the
    hub's pose."""
    n = len(poses)
    r = {"poses": poses[None], "joints": np.zeros((1, 1)), "twists": np.zeros((1, n, 6))}
    col = {c: c for c in range(n)}
    out = [np.array([np.arctan2(poses[0][1, 0], poses[0][0, 0])])]
    out += [sensor_values(m._desc.sensors[s], r, col, {}).ravel() for s in DISP[1:]]
    return np.concatenate(out)


@pytest.mark.parametrize("preload", [(0.0, 0.0), (30.0, 8.0)])
def test_displacement_outputs_against_finite_differences_of_static(preload):
    m, link = arm()
    pre = np.array([0.0, 0.0, 0.0, 0.0, *preload])
    st = m.static(loads=[(link.end, tuple(pre), "world")], tol=1e-13, steps=20) \
        if any(preload) else None
    lin = m.linearize(at=st, inputs=[link.end], outputs=DISP)
    assert lin.outputs[:3] == ["q", "tip[0]", "tip[1]"] and lin.outputs[-1] == "strain[5]"
    assert np.all(lin.Cq == 0) and lin.C.shape == (1 + 6 + 3 + 16 + 6, 2 * lin.nr)
    R = (m.static(tol=1e-13).poses if st is None else st.poses)[link.end.carrier] @ link.end.T
    F, worst = 1e-3, 0.0
    for d in (4, 5):            # world f_y, f_z at the tip: in the tip frame's axes for B
        e = np.zeros(6)
        e[d] = 1.0
        w = np.concatenate([R[:3, :3].T @ e[:3], R[:3, :3].T @ e[3:]])
        pred = lin.C[:, :lin.nr] @ np.linalg.solve(lin.stiffness, lin.Bq @ w)
        ends = [m.static(loads=[(link.end, tuple(pre + s * F * e), "world")], tol=1e-13,
                         steps=20 if st is None else 1, start=st) for s in (1, -1)]
        fd = (values(m, ends[0].poses) - values(m, ends[1].poses)) / (2 * F)
        worst = max(worst, np.abs(pred - fd).max() / np.abs(fd).max())
        if not any(preload) and d == 4:
            assert fd[0] == pytest.approx(L / 5.0, rel=1e-6)      # hub: F L / k per N
    assert worst < 1e-6, worst


def test_rate_outputs_against_simulate():
    m, link = arm()
    lin = m.linearize(inputs=[link.end], outputs=["qd", "twist", "vel", "joint", "q", "tip"])
    F, T = 1e-3, 0.05
    # world f_y, ramped up smoothly over T (a step would ring the strip's kHz modes, which the
    # integrator damps: its error, not the model's)
    m.add_wrench("push", link.end, (0, 0, 0, 0, F, 0), law=ph.Cycloidal(1.0, 0.0, T))
    t = np.linspace(0.0, 0.3, 301)
    res = m.simulate(t[-1], t[1], rtol=1e-8)
    tf = np.linspace(0.0, 0.3, 6001)                               # lsim interpolates u linearly
    tau = np.clip(tf / T, 0.0, 1.0)
    u = np.zeros((tf.size, 6))
    u[:, 4] = F * (tau - np.sin(2 * np.pi * tau) / (2 * np.pi))
    _, y, _ = signal.lsim(lin.to_statespace(), u, tf)
    y = y[::20]
    sim = np.column_stack([res.sensors["qd"], res.sensors["twist"], res.sensors["vel"],
                           res.joint("joint")["xdot"], res.sensors["q"], res.sensors["tip"]])
    err = np.abs(sim - y).max(axis=0) / np.abs(y).max(axis=0).clip(1e-300)
    big = np.abs(y).max(axis=0) > 1e-6 * np.abs(y).max()           # the outputs that move
    assert big[[0, 3, 8, 11, 14, 16]].all()
    assert err[big].max() < 1e-4, err
    np.testing.assert_allclose(lin.C[0], lin.C[10], rtol=0, atol=0)   # "qd" = "joint.rate"


def test_component_state_output_against_simulate():
    m = ph.Mechanism(gravity=(0, 0, 0))
    b = m.add_rigid_body("load", 1.0, np.diag([0.03, 0.03, 0.05]))
    m.add_pair("hub", ph.Revolute("z"), m.ground, b)
    m.add_component("motor", "hub", ph.DCMotor(L=2e-3, R=1.0, k=0.5, voltage=0.0))
    lin = m.linearize(outputs=[ph.ComponentState("motor", "i"), ph.JointSensor("hub", rate=True)])
    assert lin.outputs == ["motor.i", "hub.rate"]
    assert lin.C[0, 2 * lin.nr + lin.states.index("motor.i")] == 1.0
    i0 = 0.1
    m2 = ph.Mechanism(gravity=(0, 0, 0))
    b2 = m2.add_rigid_body("load", 1.0, np.diag([0.03, 0.03, 0.05]))
    m2.add_pair("hub", ph.Revolute("z"), m2.ground, b2)
    m2.add_component("motor", "hub", ph.DCMotor(L=2e-3, R=1.0, k=0.5, voltage=0.0, i0=i0))
    m2.add_sensor("i", ph.ComponentState("motor", "i"))
    res = m2.simulate(0.05, 1e-3, rtol=1e-10, integrator="ida")
    x0 = np.zeros(2 * lin.nr + lin.nz)
    x0[2 * lin.nr + lin.states.index("motor.i")] = i0
    _, y, _ = signal.lsim(lin.to_statespace(), np.zeros((res.t.size, 0)), res.t, X0=x0)
    sim = np.column_stack([res.sensors["i"][:, 0], res.joint("hub")["xdot"][:, 0]])
    assert np.abs(sim - y).max(axis=0).max() < 1e-7 * i0 * 10, np.abs(sim - y).max(axis=0)


def test_the_notebooks_hand_built_rows_are_the_sensors():
    m, link = arm(spring=None)
    lin = m.linearize(inputs=["joint"], outputs=["q", "tip", ph.JointSensor("joint")])
    Z, s, e = lin.basis, link.nodes[0], link.nodes[-1]
    assert lin.outputs == ["q"] + [f"tip[{i}]" for i in range(6)] + ["joint.x"]
    np.testing.assert_array_equal(lin.C[0, :lin.nr], Z[2])            # the hub's rotation about z
    np.testing.assert_array_equal(lin.C[5, :lin.nr], Z[6 * e + 4] - Z[6 * s + 4] - L * Z[6 * s + 2])
    np.testing.assert_array_equal(lin.C[7], lin.C[0])


def test_outputs_that_are_not_states_are_refused():
    m, link = arm()
    m.add_sensor("w", ph.PairWrench("clamp"))
    with pytest.raises(ph.ModelError, match="'w' \\(PairWrench\\).*no state of the linear model"):
        m.linearize(outputs=["w"])
    with pytest.raises(ph.ModelError, match="unknown port 'nope'.*its sensors.*'tip'"):
        m.linearize(outputs=["nope"])
    r = ph.Mechanism(gravity=(0, 0, 0))
    hub = r.add_rigid_body("hub", 1.0, np.diag([0.1, 0.1, 0.1]))
    r.add_pair("spin", ph.Revolute("z"), r.ground, hub, driven=ph.Linear(rate=2.0))
    r.add_sensor("a", ph.JointSensor("spin"))
    with pytest.raises(ph.ModelError, match="steady rotation"):
        r.linearize(outputs=["a"], spin=("spin", 2.0))

"""Components with internal states (python/phmech/components.py, csrc/model/component.c,
docs/method.md section 4.11): friction and DC motors, each against an independent reference.

- LuGre stick-slip, the example of Canudas de Wit, Olsson, Astrom and Lischinsky (IEEE TAC 40(3),
  1995): 1 kg on a prismatic pair, a 2 N/m spring whose far end moves at 0.1 m/s. The limit
  cycle's period and peak friction force against SciPy's Radau (rtol 1e-10, atol 1e-12) on the
  same three ODEs: measured 1.0e-6 and 2.7e-7 relative (IDA, rtol 1e-8; 0.06 s CPU); held to
  1e-4 (the issue's bound is 1 %).
- DC motor on a rigid inertia: current and speed step responses against the closed-form solution
  of the second-order linear system (matrix exponential): measured 5.6e-10 A and 1.4e-9 rad/s
  (IDA, rtol 1e-10); held to 1e-6. The ledger (electrical energy in = kinetic + magnetic + copper
  and gear losses) closes to 1.4e-10 J; held to 1e-6 J.
- Viscous friction: the exponential decay; Stribeck friction against SciPy; bad input.
"""
import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.linalg import expm
from scipy.signal import find_peaks

import phmech as ph

S0, S1, S2, FC, FS, VS = 1e5, np.sqrt(1e5), 0.4, 1.0, 1.5, 1e-3


def _g(v):
    return FC + (FS - FC) * np.exp(-(v / VS) ** 2)


def _lugre_force(v, z):
    zd = v - S0 * np.abs(v) * z / _g(v)
    return S0 * z + S1 * zd + S2 * v


def _peaks(t, F):
    """(time, value) of each friction-force peak above 1.2 N, refined by a parabola through the
    three samples around it."""
    out = []
    for i in find_peaks(F, height=1.2)[0]:
        a, b, c = F[i - 1], F[i], F[i + 1]
        d = 0.5 * (a - c) / (a - 2 * b + c)
        out.append((t[i] + d * (t[1] - t[0]), b - 0.25 * (a - c) * d))
    return np.array(out)


def _stick_slip():
    m = ph.Mechanism(gravity=(0, 0, 0))
    b = m.add_rigid_body("block", 1.0, np.eye(3) * 1e-2)
    # the spring to the moving end: -2 x from a joint spring, + 2 (0.1 t) from an effort source
    m.add_pair("slide", ph.Prismatic("x"), m.ground, b, actuator=ph.Spring(k=2.0, rest=0.0))
    m.add_actuator("pull", "slide", ph.Effort(ph.Linear(rate=0.2)))
    m.add_component("friction", "slide", ph.LuGreFriction(S0, S1, S2, FC, FS, VS))
    return m


@pytest.fixture(scope="module")
def lugre_reference():
    def rhs(t, y):
        x, v, z = y
        zd = v - S0 * abs(v) * z / _g(v)
        return [v, 2.0 * (0.1 * t - x) - (S0 * z + S1 * zd + S2 * v), zd]
    t = np.arange(0.0, 30.0 + 1e-9, 1e-3)
    sol = solve_ivp(rhs, (0, 30), [0, 0, 0], method="Radau", rtol=1e-10, atol=1e-12, t_eval=t)
    assert sol.status == 0
    return _peaks(t, _lugre_force(sol.y[1], sol.y[2]))


def test_lugre_stick_slip_matches_scipy(lugre_reference):
    r = _stick_slip().simulate(30.0, 1e-3, integrator="ida", rtol=1e-8)
    p = _peaks(r.t, _lugre_force(r.joint_rates[:, 0], r.components["friction"]["z"]))
    ref = lugre_reference
    assert len(p) == len(ref) == 4            # stick phases end at 7.40, 13.77, 20.13, 26.49 s
    period, period_ref = np.diff(p[:, 0]).mean(), np.diff(ref[:, 0]).mean()
    assert period_ref == pytest.approx(6.3627, abs=1e-3)
    assert abs(period / period_ref - 1) < 1e-4
    assert abs(p[:, 1].max() / ref[:, 1].max() - 1) < 1e-4
    assert ref[:, 1].max() == pytest.approx(1.4766, abs=1e-3)   # below Fs = 1.5 N


def test_lugre_ledger_closes_with_the_bristles():
    """The bristles' storage (with the elastic energy) and the friction's dissipation close the
    ledger: measured 7.9e-7 of the energy moved (8.7e-7 J; IDA, rtol 1e-9; 1.5e-7 at 1e-10)."""
    r = _stick_slip().simulate(15.0, 1e-3, integrator="ida", rtol=1e-9)
    assert r.stats["ledger_relative"] < 5e-6
    assert r.energy["dissipated"][-1] > 1.0


def test_motor_step_response_is_the_second_order_solution():
    L, R, k, n, eta, Jr, Jl, V0 = 0.5, 1.0, 0.5, 2.0, 0.9, 0.01, 0.05, 1.0
    m = ph.Mechanism(gravity=(0, 0, 0))
    b = m.add_rigid_body("load", 1.0, np.diag([0.03, 0.03, Jl]))
    m.add_pair("hub", ph.Revolute("z"), m.ground, b)
    m.add_component("motor", "hub", ph.DCMotor(L=L, R=R, k=k, J=Jr, ratio=n, efficiency=eta,
                                               voltage=V0))
    r = m.simulate(5.0, 1e-3, integrator="ida", rtol=1e-10)
    Jt = Jl + Jr * n * n          # the rotor's inertia reflected through the gear
    A = np.array([[-R / L, -k * n / L], [eta * n * k / Jt, 0.0]])
    bb = np.array([V0 / L, 0.0])
    # x(t) = (exp(A t) - I) A^-1 b, through A's eigenvectors (checked against expm at the end)
    lam, V = np.linalg.eig(A)
    c = np.linalg.solve(V, np.linalg.solve(A, bb))
    exact = ((np.exp(np.outer(r.t, lam)) - 1.0) * c) @ V.T
    exact = exact.real
    assert np.allclose(exact[-1], (expm(A * r.t[-1]) - np.eye(2)) @ np.linalg.solve(A, bb), atol=1e-13)
    i, w = r.components["motor"]["i"], r.joint_rates[:, 0]
    assert np.max(np.abs(i - exact[:, 0])) < 1e-6
    assert np.max(np.abs(w - exact[:, 1])) < 1e-6
    assert np.max(w) > 1.4                # underdamped: it overshoots V0 / (k n) = 1 rad/s
    E = r.energy
    assert np.max(np.abs(E["ledger"])) < 1e-6
    # the parts: kinetic (load and rotor), magnetic L i^2 / 2 (with the elastic energy)
    assert np.allclose(E["kinetic"], 0.5 * Jt * w ** 2, atol=1e-9)
    assert np.allclose(E["elastic"], 0.5 * L * i ** 2, atol=1e-12)
    # electrical energy in = stored + copper and gear losses, both integrated here too
    P_in, P_loss = V0 * i, R * i ** 2 + (1 - eta) * n * k * i * w
    trap = lambda f: np.concatenate([[0], np.cumsum(0.5 * (f[1:] + f[:-1]) * np.diff(r.t))])
    assert np.max(np.abs(E["supplied"] - trap(P_in))) < 1e-6     # the trapezoidal rule's error
    assert np.max(np.abs(E["dissipated"] - trap(P_loss))) < 1e-6


def test_current_driven_motor_has_no_state():
    m = ph.Mechanism(gravity=(0, 0, 0))
    b = m.add_rigid_body("load", 1.0, np.diag([0.03, 0.03, 0.05]))
    m.add_pair("hub", ph.Revolute("z"), m.ground, b)
    m.add_component("motor", "hub", ph.DCMotor(L=0.0, R=1.0, k=0.5, ratio=3.0, current=2.0))
    r = m.simulate(1.0, 0.1, integrator="ida", rtol=1e-10)
    assert "motor" not in r.components
    assert np.allclose(r.joint_rates[:, 0], 3.0 * 0.5 * 2.0 * r.t / 0.05, rtol=1e-8)
    assert np.max(np.abs(r.energy["ledger"])) < 1e-6


def test_viscous_friction_decays_exponentially():
    m = ph.Mechanism(gravity=(0, 0, 0))
    b = m.add_rigid_body("disc", 1.0, np.diag([0.05, 0.05, 0.1]))
    m.add_pair("hub", ph.Revolute("z"), m.ground, b, xdot0=2.0)
    m.add_component("damper", "hub", ph.ViscousFriction(0.3))
    r = m.simulate(2.0, 0.05, integrator="ida", rtol=1e-10)
    assert np.allclose(r.joint_rates[:, 0], 2.0 * np.exp(-3.0 * r.t), rtol=1e-7)
    assert r.energy["dissipated"][-1] == pytest.approx(0.1 * (4 - r.joint_rates[-1, 0] ** 2) / 2, rel=1e-7)


def test_stribeck_friction_matches_scipy():
    Fc, Fs, vs, c, vr = 1.0, 1.5, 0.05, 0.2, 1e-3
    m = ph.Mechanism(gravity=(0, 0, 0))
    b = m.add_rigid_body("block", 2.0, np.eye(3) * 1e-2)
    m.add_pair("slide", ph.Prismatic("x"), m.ground, b, xdot0=1.0)
    m.add_component("f", "slide", ph.StribeckFriction(Fc, Fs, vs, c, vr))
    r = m.simulate(0.8, 0.01, integrator="ida", rtol=1e-10)

    def rhs(t, y):
        v = y[0]
        return [-((Fc + (Fs - Fc) * np.exp(-(v / vs) ** 2)) * np.tanh(v / vr) + c * v) / 2.0]
    sol = solve_ivp(rhs, (0, 0.8), [1.0], method="Radau", rtol=1e-11, atol=1e-13, t_eval=r.t)
    assert np.max(np.abs(r.joint_rates[:, 0] - sol.y[0])) < 1e-6


def test_bad_components_are_named():
    m = ph.Mechanism(gravity=(0, 0, 0))
    b = m.add_rigid_body("b", 1.0, np.eye(3))
    m.add_pair("ball", ph.Spherical(), m.ground, b)
    with pytest.raises(ph.ModelError, match="component 'f'.*revolute and prismatic"):
        m.add_component("f", "ball", ph.ViscousFriction(1.0))
    m2 = ph.Mechanism(gravity=(0, 0, 0))
    b2 = m2.add_rigid_body("b", 1.0, np.eye(3))
    m2.add_pair("hub", ph.Revolute("z"), m2.ground, b2)
    with pytest.raises(ph.ModelError, match="component 'mot'.*'R' is missing"):
        m2.add_component("mot", "hub", ph.DCMotor(L=1e-3, k=0.1, voltage=1.0))
    with pytest.raises(ph.ModelError, match="component 'mot'.*exactly one input"):
        m2.add_component("mot", "hub", ph.DCMotor(L=1e-3, R=1.0, k=0.1))
    with pytest.raises(ph.ModelError, match="component 'lg'.*out of range"):
        m2.add_component("lg", "hub", ph.LuGreFriction(-1.0, 1, 1, 1, 1, 1))
    m2.add_component("d", "hub", ph.ViscousFriction(1.0))
    m2.static()                                   # stateless: zero at rest
    m2.add_component("z", "hub", ph.LuGreFriction(1e3, 1.0, 0.1, 1.0, 1.5, 1e-3))
    with pytest.raises(ph.ModelError, match="static: the components 'z' have states"):
        m2.static()


def test_components_are_saved_in_model_files(tmp_path):
    m = _stick_slip()
    path = tmp_path / "stick_slip.json"
    m.save(path)
    again = ph.load(path)
    a = m.simulate(8.0, 0.01, integrator="ida", rtol=1e-8)
    b = again.simulate(8.0, 0.01, integrator="ida", rtol=1e-8)
    assert np.array_equal(a.components["friction"]["z"], b.components["friction"]["z"])
    a.to_netcdf(tmp_path / "run.nc")             # results keep the states too
    back = ph.load_result(tmp_path / "run.nc")
    assert np.array_equal(back.components["friction"]["z"], a.components["friction"]["z"])


def test_linear_controller_closed_loop_poles_match_scipy():
    """A PI controller with a filtered proportional path (two states) on a rigid disc: the
    closed loop's poles, fitted from the simulated states (the one-step map of the sampled
    trajectory, least squares), against scipy.linalg.eigvals of the closed-loop matrix: measured
    6.8e-10 relative; the trajectory against expm 1e-9 rad/s (IDA, rtol 1e-10)."""
    from scipy.linalg import eigvals
    J, kp, kd, ki, kf, a = 0.05, 4.0, 0.3, 2.0, 1.0, 20.0
    A, B, C, D = [[0, 0], [0, -a]], [[1, 0], [a, 0]], [-ki, -kf], [-kp, -kd]
    m = ph.Mechanism(gravity=(0, 0, 0))
    b = m.add_rigid_body("disc", 1.0, np.diag([0.03, 0.03, J]))
    m.add_pair("hub", ph.Revolute("z"), m.ground, b, x0=0.1)
    m.add_component("ctrl", "hub", ph.LinearController(A, B, C, D))
    dt = 0.01
    r = m.simulate(5.0, dt, integrator="ida", rtol=1e-10)
    Acl = np.zeros((4, 4))
    Acl[0, 1] = 1.0
    Acl[1] = [D[0] / J, D[1] / J, C[0] / J, C[1] / J]
    Acl[2:, :2], Acl[2:, 2:] = np.array(B), np.array(A)
    S = np.column_stack([r.joints[:, 0], r.joint_rates[:, 0], r.components["ctrl"]["x0"],
                         r.components["ctrl"]["x1"]])
    exact = np.array([expm(Acl * t) @ S[0] for t in r.t])
    assert np.max(np.abs(S - exact)) < 1e-7
    Phi = np.linalg.lstsq(S[:-1], S[1:], rcond=None)[0].T
    fitted = np.log(np.linalg.eigvals(Phi).astype(complex)) / dt
    poles = eigvals(Acl)
    assert max(np.min(np.abs(q - poles)) / abs(q) for q in fitted) < 1e-6
    assert np.max(np.abs(r.energy["ledger"])) < 1e-8    # its power u v is supplied


def test_non_collocated_controller_matches_scipy():
    """Two coaxial discs, a hub and an elbow revolute with joint springs; a controller drives the
    hub from the elbow's angle and a filtered elbow rate (sensor="elbow"): the closed loop (5
    states) is unstable (poles 0.907 +- 12.74j), and the poles fitted from the simulation match
    scipy.linalg.eigvals: measured 4.4e-9 relative; the trajectory against expm 3.8e-8 of its
    amplitude (IDA, rtol 1e-10)."""
    from scipy.linalg import eigvals
    J1, J2, k1, k, kp, kd, a, dt = 0.05, 0.02, 1.0, 3.0, 2.0, 0.1, 30.0, 0.005
    m = ph.Mechanism(gravity=(0, 0, 0))
    d1 = m.add_rigid_body("d1", 1.0, np.diag([0.03, 0.03, J1]))
    d2 = m.add_rigid_body("d2", 1.0, np.diag([0.015, 0.015, J2]))
    m.add_pair("hub", ph.Revolute("z"), m.ground, d1, actuator=ph.Spring(k=k1, rest=0.0))
    m.add_pair("elbow", ph.Revolute("z"), d1, d2, x0=0.1, actuator=ph.Spring(k=k, rest=0.0))
    m.add_component("ctrl", "hub", ph.LinearController(A=[[-a]], B=[[0, a]], C=[-kd],
                                                       D=[-kp, 0.0], sensor="elbow"))
    r = m.simulate(3.0, dt, integrator="ida", rtol=1e-10)
    # (x1, x2, v1, v2, xc): M (v1, v2)' = (u - k1 x1, -k x2), u = -kp x2 - kd xc
    Mi = np.linalg.inv([[J1 + J2, J2], [J2, J2]])
    Acl = np.zeros((5, 5))
    Acl[0, 2] = Acl[1, 3] = 1.0
    Acl[2:4] = Mi @ np.array([[-k1, -kp, 0, 0, -kd], [0, -k, 0, 0, 0]])
    Acl[4] = [0, 0, 0, a, -a]
    S = np.column_stack([r.joints, r.joint_rates, r.components["ctrl"]["x0"]])
    exact = np.array([expm(Acl * t) @ S[0] for t in r.t])
    assert np.max(np.abs(S - exact)) < 1e-6 * np.max(np.abs(S))
    Phi = np.linalg.lstsq(S[:-1], S[1:], rcond=None)[0].T
    fitted = np.log(np.linalg.eigvals(Phi).astype(complex)) / dt
    poles = eigvals(Acl)
    assert max(np.min(np.abs(q - poles)) / abs(q) for q in fitted) < 1e-6
    assert np.max(poles.real) == pytest.approx(0.9074, abs=1e-3)     # unstable

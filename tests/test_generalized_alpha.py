"""simulate(integrator="generalized-alpha"): fixed-step generalized-alpha (Jansen-Whiting-Hulbert,
first-order form) on the DAE. References: IDA at rtol 1e-11 on the same model (its own error is
~1e-10 here), the compound pendulum's energy, the circle-intersection four-bar of
test_closed_chains (constraint residuals of every row), and the order of accuracy itself."""
import warnings

import numpy as np
import pytest

import phmech as ph
from phmech.section import table1_properties
from test_closed_chains import fourbar


def pendulum(effort=None):
    """1 kg point-like body on a 1 m arm, pivot about y, released horizontal (gravity -z)."""
    m = ph.Mechanism(gravity=(0, 0, -9.81))
    b = m.add_rigid_body("b", mass=1.0, inertia=np.eye(3) * 0.01, com=(1.0, 0, 0))
    m.add_pair("j", ph.Revolute(axis=(0, 1, 0)), m.ground, b, actuator=effort)
    return m


@pytest.fixture(scope="module")
def pendulum_ref():
    m = pendulum()
    return m, m.simulate(2.0, 0.01, rtol=1e-11, integrator="ida").joint("j")["x"][:, 0]


@pytest.mark.parametrize("rho", [1.0, 0.8])
def test_pendulum_second_order(pendulum_ref, rho):
    m, xref = pendulum_ref
    err, dE = [], []
    for h in (1e-2, 5e-3, 2.5e-3):
        r = m.simulate(2.0, 0.01, rtol=1e-10, integrator="generalized-alpha", step=h, rho_inf=rho)
        assert r.stats["steps"] == round(2.0 / h)
        err.append(np.max(np.abs(r.joint("j")["x"][:, 0] - xref)))
        e = r.energy["total"]
        dE.append(np.max(np.abs(e - e[0])) / 9.81)
    # measured (rho 1 / 0.8): 3.49e-4 / 3.69e-4, 8.7e-5 / 9.2e-5, 2.2e-5 / 2.3e-5 rad: ratio 4.00
    assert err[1] < 1.5e-4
    for a, b in zip(err, err[1:]):
        assert 3.8 < a / b < 4.2
    # energy error of m g d, also second order (measured 5.9e-4, 1.5e-4, 3.7e-5 at rho 1)
    for a, b in zip(dE, dE[1:]):
        assert 3.5 < a / b < 4.5


def test_fourbar_constraints_hold_at_every_output():
    m = fourbar()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ph.RedundantConstraintWarning)
        ref = m.simulate(1.0, 0.01, rtol=1e-10, integrator="ida")
        r = m.simulate(1.0, 0.01, rtol=1e-8, integrator="generalized-alpha", step=1e-3, rho_inf=1.0)
        res = m.constraint_residuals(r)
    # steps land on the outputs, so outputs are solutions, not interpolations:
    # measured max |g| 3.5e-11, max |G t| 4.9e-9 (Newton tolerance 1e-8) over every row
    assert res["position"].max() < 1e-9
    assert res["velocity"].max() < 1e-7
    err = np.max(np.abs(r.joint("k1")["x"] - ref.joint("k1")["x"]))
    assert err < 5e-4   # measured 1.3e-4 rad at h = 1 ms over 1 s


def test_released_cantilever_converges_to_ida():
    m = ph.Mechanism()
    b = m.add_flexible_link("b", 1.0, table1_properties(1.0), elements=8)
    m.add_pair("clamp", ph.Fixed(), m.ground, b.start)
    st = m.static(loads=[(b.end, (0, 0, 0, 0, 0, -0.75 * 5143.0), "world")], steps=4)
    ref = m.simulate(0.5, 0.01, rtol=1e-10, initial=st, linear_solver="klu", integrator="ida").tip(b)[:, :3]
    err = []
    for h in (1e-2 / 2, 1e-2 / 8, 1e-2 / 32):
        r = m.simulate(0.5, 0.01, rtol=1e-6, initial=st, linear_solver="klu",
                       integrator="generalized-alpha", step=h)
        err.append(np.max(np.linalg.norm(r.tip(b)[:, :3] - ref, axis=1)))
    # the release excites axial/shear vibrations the coarse steps do not resolve (they are damped,
    # rho_inf 0.9); the error falls as they get resolved (measured 1.27e-3, 1.69e-4, 2.75e-5 m)
    assert err[0] > err[1] > err[2]
    assert err[2] < 2e-4


def test_lands_on_law_breakpoints():
    """A torque step at t0 = 0.0123 s (between steps of 5 ms) vs IDA with the same breakpoint."""
    m = pendulum(ph.Effort(ph.Step(t0=0.0123, value=5.0)))
    ref = m.simulate(0.5, 0.01, rtol=1e-11, integrator="ida").joint("j")["x"][:, 0]
    err, ledger = [], []
    for h in (5e-3, 2.5e-3):
        r = m.simulate(0.5, 0.01, rtol=1e-10, integrator="generalized-alpha", step=h)
        assert r.stats["steps"] == round(0.5 / h) + 1   # one step split at the jump
        err.append(np.max(np.abs(r.joint("j")["x"][:, 0] - ref)))
        ledger.append(abs(r.energy["ledger"][-1]) / r.energy["supplied"][-1])
    # still second order across the jump (a step straddling it would be first order):
    # measured 3.94e-5 and 9.82e-6 rad (ratio 4.01); ledger 2.7e-5 and 6.6e-6 of the supplied energy
    assert err[0] < 1e-4 and 3.6 < err[0] / err[1] < 4.4
    assert ledger[0] < 1e-4 and 3.6 < ledger[0] / ledger[1] < 4.4


def test_callback_stops_the_run():
    m = pendulum()
    r = m.simulate(1.0, 0.01, integrator="generalized-alpha", step=1e-3,
                   callback=lambda t, i: t >= 0.2)
    assert abs(r.t[-1] - 0.2) < 1e-12 and len(r.t) == 21


@pytest.mark.parametrize("kw, match", [
    (dict(integrator="euler"), "unknown integrator"),
    (dict(integrator="generalized-alpha", band=-5.0), "band must be positive"),
    (dict(integrator="generalized-alpha", step=1e-3, max_step=1e-4), "max_step applies to"),
    (dict(integrator="generalized-alpha", step=-1e-3), "step must be positive"),
    (dict(integrator="generalized-alpha", step=1e-3, rho_inf=1.5), r"rho_inf must be in \[0, 1\]"),
    (dict(integrator="generalized-alpha", step=1e-3, error_test="configuration"), "integrator='ida' only"),
    (dict(integrator="ida", step=1e-3), "step= applies to integrator='generalized-alpha'"),
])
def test_bad_integrator_options(kw, match):
    with pytest.raises(ph.ModelError, match=match):
        pendulum().simulate(0.1, 0.01, **kw)


def test_step_load_with_uneven_output_spacing():
    """Regression: the first step's predictor read an uninitialized history vector (0 * NaN), which
    made 'singular iteration matrix at t = 0' depending on the heap (30 elements, dt_out = T/4 not
    a multiple of the step). Reference: IDA at rtol 1e-9."""
    m = ph.Mechanism()
    b = m.add_flexible_link("b", 1.0, table1_properties(1.0), elements=30)
    m.add_pair("clamp", ph.Fixed(), m.ground, b.start)
    m.add_wrench("tip", b.end, (0, 0, 0, 0, 0, -0.75 * 5143.0), law=ph.Constant(1.0))
    ref = m.simulate(0.021, 0.021 / 4, rtol=1e-9, linear_solver="klu", integrator="ida").tip(b)
    for rho in (1.0, 0.9):
        r = m.simulate(0.021, 0.021 / 4, rtol=1e-6, linear_solver="klu",
                       integrator="generalized-alpha", step=1e-3, rho_inf=rho)
        assert np.abs(r.tip(b) - ref).max() < 1e-4   # measured 2.7e-5 m (rho 1)


def test_restart_with_huge_initial_acceleration_falls_back_to_euler():
    """The Fig. 3 manipulator (4 elements per link): consistent initial values give a joint torque
    on a light link node an acceleration ~1e9 rad/s^2; the generalized-alpha step built on it
    made the finite-difference Jacobian singular ('singular iteration matrix at t = 0'). The first
    step is then redone as backward Euler. Reference: IDA at rtol 1e-7."""
    import sys
    import warnings
    from pathlib import Path
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "examples"))
    import manipulator as M
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ph.RedundantConstraintWarning)
        p = M.ManipulatorParams()
        ff, _ = M.gravity_compensation(p, elements=4)
        m, _ = M.build(p, elements=4, ff=ff)
        ref = m.simulate(0.2, 2e-3, rtol=1e-7, atol=1e-8, linear_solver="klu", integrator="ida").poses[:, :, :3, 3]
        err = [np.abs(m.simulate(0.2, 2e-3, rtol=1e-8, linear_solver="klu", integrator="generalized-alpha",
                                 step=h).poses[:, :, :3, 3] - ref).max() for h in (1e-3, 5e-4)]
    # measured 6.6e-6 and 1.6e-6 m (the reference is the generalized-alpha's at step 3.1e-5 s to
    # 3.9e-8 m). Newton's tolerance rtol 1e-8: at 1e-6 (fixed steps: Newton's alone) its error
    # was 9.3e-6 and 9.6e-6 m with consistent mass (6.3e-6 and 2.5e-6 with lumped)
    assert err[0] < 2e-5 and err[1] < err[0]


@pytest.mark.parametrize("options, advice", [
    (dict(integrator="generalized-alpha", step=0.1, rho_inf=0.0), "use a smaller step= or rtol="),
    (dict(integrator="ida", rtol=0.1), "with IDA this means its tolerances are too loose"),
])
def test_energy_drift_warning_gives_the_route_s_advice(options, advice):
    """The pendulum with a step of 0.1 s that damps everything (rho_inf 0: ledger 4.5e-2 of its
    energy, measured), or IDA at rtol 0.1 (1.1e-1): the AccuracyWarning says what to change for
    that integrator, not the default one's dt_out / band."""
    m = pendulum()
    with pytest.warns(ph.AccuracyWarning, match=advice):
        r = m.simulate(2.0, 0.1, **options)
    assert r.stats["ledger_relative"] > 0.01


def test_a_fixed_step_lands_on_every_output_and_keeps_its_matrix():
    """A 2 ms step with outputs every 5 ms lands on each (three 1.67 ms steps per output) and
    keeps its iteration matrix: measured 1200 steps and 1 Jacobian (a trial that passed outputs
    closer than the step alternated 1.67 and 2 ms steps, and each switch refreshed it: 795)."""
    m = pendulum()
    r = m.simulate(2.0, 0.005, rtol=1e-10, integrator="generalized-alpha", step=2e-3)
    assert r.stats["steps"] == 1200
    assert r.stats["jacobian_evals"] <= 3

"""Time laws (python/phmech/laws.py, evaluated by csrc/util/law.c): compositions against NumPy
evaluations of the same expressions and their derivatives against finite differences, the C2
spline against scipy.interpolate.CubicSpline, Python functions as laws (values, derivatives,
errors raised from inside a run), clear errors for bad laws, and the plain-data round trip."""
import numpy as np
import pytest
from scipy.interpolate import CubicSpline

import phmech as ph

T = np.linspace(-0.7, 2.9, 181)


def numpy_sine(a, f, ph_, off, t):
    w = 2 * np.pi * f
    return np.stack([off + a * np.sin(w * t + ph_), a * w * np.cos(w * t + ph_),
                     -a * w * w * np.sin(w * t + ph_)], axis=-1)


def numpy_cycloidal(A, t0, d, t):
    u = np.clip((t - t0) / d, 0, 1)
    inside = (t >= t0) & (t < t0 + d)
    s = A * (u - np.sin(2 * np.pi * u) / (2 * np.pi))
    return np.stack([s, np.where(inside, A / d * (1 - np.cos(2 * np.pi * u)), 0.0),
                     np.where(inside, A / d ** 2 * 2 * np.pi * np.sin(2 * np.pi * u), 0.0)], axis=-1)


def leibniz(a, b):
    return np.stack([a[..., 0] * b[..., 0], a[..., 1] * b[..., 0] + a[..., 0] * b[..., 1],
                     a[..., 2] * b[..., 0] + 2 * a[..., 1] * b[..., 1] + a[..., 0] * b[..., 2]], axis=-1)


def test_compositions_match_numpy_and_finite_differences():
    sine, lin, cyc = ph.Sine(0.7, 1.3, 0.2, 0.1), ph.Linear(2.0, 0.5), ph.Cycloidal(1.5, 0.2, 1.0)
    dt = 0.3
    law = (sine * lin + 3.0 * cyc - sine).shifted(dt) + 0.25
    ts = T - dt
    S = numpy_sine(0.7, 1.3, 0.2, 0.1, ts)
    L = np.stack([0.5 + 2.0 * ts, np.full_like(ts, 2.0), np.zeros_like(ts)], axis=-1)
    ref = leibniz(S, L) + 3.0 * numpy_cycloidal(1.5, 0.2, 1.0, ts) - S
    ref[:, 0] += 0.25
    got = law.derivatives(T)
    scale = np.max(np.abs(ref), axis=0)
    assert np.max(np.abs(got - ref) / scale) < 1e-13
    # derivatives against central differences inside the cycloid's pieces
    h = 1e-5
    t = np.array([-0.3, 0.1, 0.9, 1.3, 2.5])
    fd1 = (law.evaluate(t + h) - law.evaluate(t - h)) / (2 * h)
    fd2 = (law.derivatives(t + h)[:, 1] - law.derivatives(t - h)[:, 1]) / (2 * h)
    d = law.derivatives(t)
    assert np.max(np.abs(d[:, 1] - fd1)) < 1e-8 * scale[1]
    assert np.max(np.abs(d[:, 2] - fd2)) < 1e-8 * scale[2]
    # the expression is a plain Sum of Products: its classes and numbers
    assert isinstance(law, ph.Sum) and isinstance(2.0 * sine, ph.Product)
    assert ph.law_from_data(law.to_data()) == law._checked()


def test_shifted_laws_are_delays_of_every_kind():
    laws = [ph.Constant(2.0), ph.Step(0.3, 1.5), ph.Pulse(0.2, 0.5, -1.0), ph.Sine(1.0, 0.8, 0.3, 0.2),
            ph.Table([0.0, 0.5, 1.5], [0.0, 2.0, 1.0]), ph.Cycloidal(1.0, 0.1, 0.7), ph.Linear(-1.5, 0.4),
            ph.Spline([0.0, 0.4, 1.0, 1.7], [0.0, 0.3, -0.2, 0.5]),
            ph.Function(lambda t: np.cos(3 * t), breakpoints=(0.5,))]
    t = np.array([-0.31, 0.12, 0.77, 1.23, 2.05])   # away from every breakpoint
    for law in laws:
        np.testing.assert_allclose(law.shifted(0.37).derivatives(t), law.derivatives(t - 0.37),
                                   rtol=1e-12, atol=1e-8 if isinstance(law, ph.Function) else 1e-13,
                                   err_msg=type(law).__name__)


@pytest.mark.parametrize("bc", ["not-a-knot", "natural", "clamped", (0.5, -1.0)])
def test_spline_matches_scipy_cubic_spline(bc):
    rng = np.random.default_rng(7)
    t = np.sort(rng.uniform(0, 2, 14))
    y = np.sin(3 * t) + 0.1 * rng.normal(size=t.size)
    ref = CubicSpline(t, y, bc_type=bc if isinstance(bc, str) else ((1, bc[0]), (1, bc[1])))
    x = np.concatenate([np.linspace(t[0] - 0.3, t[-1] + 0.3, 997), t])
    got = ph.Spline(t, y, bc=bc, extrapolate="cubic").derivatives(x)
    for k in range(3):
        want = ref(x, k)
        assert np.max(np.abs(got[:, k] - want)) <= 1e-12 * np.max(np.abs(want)), (bc, k)
    # linear extrapolation: inside the same, outside the end value and slope
    lin = ph.Spline(t, y, bc=bc).derivatives(x)
    inside = (x >= t[0]) & (x < t[-1])   # at t_n the extrapolation starts (s'' jumps)
    assert np.max(np.abs(lin[inside] - got[inside])) <= 1e-12 * np.max(np.abs(got[inside]))
    out = x > t[-1]
    np.testing.assert_allclose(lin[out, 0], y[-1] + ref(t[-1], 1) * (x[out] - t[-1]), rtol=1e-12, atol=1e-12)
    assert np.all(lin[out, 2] == 0)


def test_short_splines_and_antiderivative_match_scipy():
    for t, y in (([0.0, 1.0], [1.0, 3.0]), ([0.0, 0.5, 2.0], [1.0, -1.0, 2.0])):
        ref = CubicSpline(t, y)
        x = np.linspace(0, t[-1], 50)
        np.testing.assert_allclose(ph.Spline(t, y, extrapolate="cubic").evaluate(x), ref(x), rtol=1e-13, atol=1e-13)
    # a speed profile w(t) (rest -> 4 rad/s, zero acceleration at both ends) and its angle
    t = np.linspace(0.0, 1.0, 6)
    w = 4.0 * (1 - np.cos(np.pi * t)) / 2
    speed = ph.Spline(t, w, bc="clamped")
    angle = speed.antiderivative()
    ref = CubicSpline(t, w, bc_type="clamped").antiderivative()
    x = np.linspace(0, 1, 201)
    d = angle.derivatives(x)
    np.testing.assert_allclose(d[:, 0], ref(x), atol=1e-13)
    np.testing.assert_allclose(d[:, 1], ref(x, 1), atol=1e-12)
    np.testing.assert_allclose(d[:, 2], ref(x, 2), atol=1e-11)
    # beyond the samples: constant speed, angle linear
    after = angle.derivatives(np.array([1.5, 2.0]))
    np.testing.assert_allclose(after[:, 1], 4.0, rtol=1e-13)
    np.testing.assert_allclose(after[:, 0], ref(1.0) + 4.0 * np.array([0.5, 1.0]), rtol=1e-13)
    assert np.all(np.abs(after[:, 2]) < 1e-12)


def test_function_law_values_derivatives_and_a_failure_inside_a_run():
    f = ph.Function(lambda t: np.sin(2 * t), derivative=lambda t: 2 * np.cos(2 * t))
    t = np.array([0.1, 0.8])
    mixed = ph.Linear(2.0) * (lambda t: t * t)           # a plain function in an expression
    np.testing.assert_allclose(mixed.derivatives(t)[:, 0], 2 * t ** 3, rtol=1e-15)
    np.testing.assert_allclose(mixed.derivatives(t)[:, 1], 6 * t ** 2, rtol=1e-7)
    d = f.derivatives(t)
    np.testing.assert_allclose(d[:, 0], np.sin(2 * t), rtol=1e-15)
    np.testing.assert_allclose(d[:, 1], 2 * np.cos(2 * t), rtol=1e-15)
    np.testing.assert_allclose(d[:, 2], -4 * np.sin(2 * t), rtol=1e-6)   # central differences
    # a function failing at t = 0.05 s stops a run: its error, not the solver's
    m = ph.Mechanism()
    body = m.add_rigid_body("b", 1.0, np.eye(3))
    m.add_pair("slide", ph.Prismatic("x"), m.ground, body)

    def push(t):
        if t > 0.05:
            raise RuntimeError("sensor lost")
        return 1.0

    m.add_wrench("push", body, (0, 0, 0, 1.0, 0, 0), law=push)
    with pytest.raises(ph.ModelError, match=r"the function 'push' raised RuntimeError at t = 0\.05\d* s: "
                                            r"sensor lost") as e:
        m.simulate(0.1, 0.01)
    assert isinstance(e.value.__cause__, RuntimeError)
    # ... with the trajectory up to it (it was dropped before): outputs 0 ... 0.05 s, the body
    # pushed by 1 N from rest, x = t^2 / 2
    res = e.value.result
    assert "the trajectory up to 0.05 s is in this error's 'result' attribute" in str(e.value)
    np.testing.assert_allclose(res.t, np.arange(6) * 0.01, atol=1e-15)
    np.testing.assert_allclose(res.joint("slide")["x"][:, 0], res.t**2 / 2, rtol=1e-4, atol=1e-9)


def test_bad_laws_are_refused_clearly():
    m = ph.Mechanism()
    body = m.add_rigid_body("b", 1.0, np.eye(3))
    cases = [
        (ph.Spline([0.0, 1.0, 0.5], [0.0, 1.0, 2.0]), r"Spline times must be strictly increasing: "
                                                       r"t\[1\] = 1 s, t\[2\] = 0\.5 s"),
        (ph.Spline([0.0, 1.0, 2.0], [0.0, np.nan, 2.0]), r"Spline value 1 \(at t = 1 s\) is not finite"),
        (ph.Spline([0.0, 1.0], [0.0, 1.0], bc="periodic"), r"Spline bc must be one of"),
        (ph.Spline([0.0], [0.0]), r"Spline needs as many values as times, at least 2"),
        (ph.PiecewisePolynomial([0.0, 1.0], [[1.0] * 9]), r"PiecewisePolynomial needs .* order <= 8"),
        (ph.Sum(("a", 1.0)), r"Sum operand 0: expected a time law or a number \(got str\)"),
        (ph.Function(lambda t: [1.0, 2.0]), r"time law: the function '<lambda>' returned list \[1\.0, 2\.0\] at t = 0 s, not a real number"),
        (ph.Function(lambda t: 1.0, step=0.0), r"Function step must be > 0"),
    ]
    for i, (law, msg) in enumerate(cases):
        with pytest.raises(ph.ModelError, match=r"wrench 'w%d': law: " % i + msg):
            m.add_wrench(f"w{i}", body, (0, 0, 0, 1.0, 0, 0), law=law)
    with pytest.raises(TypeError):
        ph.Sine() + "x"
    # a function with a lambda cannot be saved as data; a module-level one can
    with pytest.raises(ph.ModelError, match="not an importable module-level function"):
        ph.Function(lambda t: t).to_data()
    data = ph.Function(np.cos, breakpoints=(1.0,)).to_data()
    assert data["fn"] == "numpy:cos"
    np.testing.assert_allclose(ph.law_from_data(data).evaluate([0.3]), np.cos(0.3), rtol=1e-15)


def test_function_defined_from_zero_on_gets_forward_differences_there():
    law = ph.Function(np.sqrt)      # sqrt(t - 1e-4) is nan at t = 5e-5: one-sided there
    d = law.derivatives(np.array([5e-5, 1.0]))
    np.testing.assert_allclose(d[1], [1.0, 0.5, -0.25], rtol=1e-6)
    assert np.isfinite(d[0]).all()


def trapezoid_reference(D, v, a, t0, t):
    """s, s', s'' of a rest-to-rest move by D with a trapezoidal velocity profile, from its
    definition: the time to reach v at a, the cruise that covers the rest, or a triangle (peak
    sqrt(|D| a)) when |D| < v^2 / a."""
    sg, D = np.sign(D), abs(D)
    if D >= v * v / a:
        ramp, cruise = v / a, (D - v * v / a) / v
    else:
        ramp, cruise = np.sqrt(D / a), 0.0
        v = a * ramp
    T, tau = 2 * ramp + cruise, t - t0
    up, flat, down = (tau >= 0) & (tau < ramp), (tau >= ramp) & (tau < ramp + cruise), \
        (tau >= ramp + cruise) & (tau < T)
    s = np.select([tau < 0, up, flat, down], [0.0, a * tau ** 2 / 2, a * ramp ** 2 / 2 + v * (tau - ramp),
                                              D - a * (T - tau) ** 2 / 2], D)
    ds = np.select([up, flat, down], [a * tau, v, a * (T - tau)], 0.0)
    dds = np.select([up, flat, down], [a, 0.0, -a], 0.0)
    return sg * np.stack([s, ds, dds], axis=-1), T


@pytest.mark.parametrize("D, v, a, t0", [(2.0, 1.0, 2.0, 0.5), (-0.1, 1.0, 2.0, 0.0),
                                         (0.75, 0.5, 4.0, -0.3), (1.0, 1.0, 1.0, 0.2)])
def test_trapezoidal_move_matches_its_closed_form(D, v, a, t0):
    """Trapezoidal (evaluated by the core as a piecewise polynomial) against the profile written
    from its definition: s, s', s'' everywhere but at the ramps' ends (where s'' jumps), the peak
    velocity (max_velocity, or sqrt(|D| a) for a triangle), the duration and the end at rest."""
    law = ph.Trapezoidal(D, v, a, t0)
    t = np.linspace(t0 - 0.5, t0 + 4.0, 1237)
    ref, dur = trapezoid_reference(D, v, a, t0, t)
    ramp, cruise = law.phases()
    ends = t0 + np.array([0, ramp, ramp + cruise, dur])
    away = np.min(np.abs(t[:, None] - ends), axis=1) > 1e-9
    np.testing.assert_allclose(law.derivatives(t)[away], ref[away], rtol=1e-12, atol=1e-12)
    assert law.duration() == pytest.approx(dur, rel=1e-14)
    peak = min(v, np.sqrt(abs(D) * a))   # the cruise's velocity, or a triangle's top
    assert abs(law.derivatives(t0 + ramp + cruise / 2)[1]) == pytest.approx(peak, rel=1e-12)
    assert np.max(np.abs(law.derivatives(t)[:, 1])) <= peak * (1 + 1e-12)
    np.testing.assert_allclose(law.derivatives([t0 + dur, t0 + dur + 10.0]), [[D, 0, 0], [D, 0, 0]],
                               atol=1e-14)
    np.testing.assert_allclose(law.shifted(0.25).derivatives(t + 0.25), law.derivatives(t),
                               atol=1e-13)
    assert ph.law_from_data(law.to_data()) == law


def test_trapezoidal_drives_a_slider_and_refuses_bad_limits():
    """A prismatic pair driven by a Trapezoidal move follows it (the restarts at the ramps' ends
    included) and is at rest at distance after it; non-positive limits are refused."""
    law = ph.Trapezoidal(0.2, 0.25, 1.0, 0.05)
    m = ph.Mechanism()
    body = m.add_rigid_body("slider", 0.7, np.eye(3) * 0.01)
    m.add_pair("rail", ph.Prismatic("x"), m.ground, body, driven=law)
    r = m.simulate(1.2, 0.01)
    x = r.joint("rail")["x"][:, 0]
    np.testing.assert_allclose(x, law.evaluate(r.t), atol=1e-7)
    assert abs(x[-1] - 0.2) < 1e-7 and abs(r.joint("rail")["xdot"][-1, 0]) < 1e-6
    for bad in (dict(max_velocity=0.0), dict(max_acceleration=-1.0)):
        with pytest.raises(ph.ModelError, match="Trapezoidal max_velocity and max_acceleration"):
            m.add_pair("rail2", ph.Prismatic("x"), m.ground, body, driven=ph.Trapezoidal(**bad))


@pytest.mark.parametrize("integrator, rtol", [("tree", 1e-8), ("ida", 1e-10), ("generalized-alpha", 1e-6)])
def test_a_breakpoint_at_the_last_output(integrator, rtol):
    """A law switching at t_end: the outputs i dt put simulate(0.3, 0.05)'s last at
    0.30000000000000004, 5.6e-17 s after the breakpoint the steps land on; that output is the
    breakpoint's (its left limit: the torque still 0). Before, the tree integrator stopped with
    "step size 5.55e-17 too small" and IDA with IDA_ILL_INPUT (tout too close to t0). Against
    the free pendulum's motion (SciPy DOP853): I theta'' = -m g c cos(theta), I = 0.01 + 0.25
    kg m^2, m g c = 4.905 N m; measured 1.2e-9 (tree), 8.4e-10 (IDA) and 1.9e-7 rad (the default
    integrator at rtol 1e-6, whose contract is rtol max|x| + atol: 8.4e-7 rad here)."""
    from scipy.integrate import solve_ivp
    m = ph.Mechanism(gravity=(0, -9.81, 0))
    b = m.add_rigid_body("bob", 1.0, np.diag((1e-2,) * 3), com=(0.5, 0, 0))
    m.add_pair("hinge", ph.Revolute("z"), m.ground, b, x0=0.0)
    m.add_actuator("push", "hinge", ph.Effort(ph.Step(0.3, 0.05)))
    r = m.simulate(0.3, 0.05, rtol=rtol, integrator=integrator)
    assert len(r.t) == 7 and not r.interrupted
    ex = solve_ivp(lambda _, s: [s[1], -4.905 * np.cos(s[0]) / 0.26], (0, r.t[-1]), [0.0, 0.0],
                   t_eval=r.t, rtol=1e-12, atol=1e-14, method="DOP853").y[0]
    err = np.abs(r.joint("hinge")["x"][:, 0] - ex).max()
    bound = rtol * np.abs(ex).max() + rtol / 100 if integrator == "generalized-alpha" else 1e-7
    assert err <= bound, (err, bound)

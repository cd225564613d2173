"""Static cantilever under a tip load.

References (independent of phmech):
- small load: linear Timoshenko tip deflection P L^3/(3 EI) + P L/kGA, and the closed-form
  discretization error of the constant-strain se3 element (see below);
- large load: the elastica (inextensible, shear-rigid Euler beam under a dead tip load), solved by
  shooting with scipy (solve_ivp + brentq).
"""
import warnings

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

import phmech as ph
from phmech.section import TABLE1, table1_properties

L, EI, kGA = TABLE1["L"], TABLE1["EI"], TABLE1["kGA"]


def cantilever_tip(props, N, P, steps=1):
    """Tip position [m] of a clamped link (x axis) under a dead tip force P [N] along world z."""
    m = ph.Mechanism()
    b = m.add_flexible_link("b", L, props, elements=N)
    m.add_pair("clamp", ph.Fixed(), m.ground, b.start)
    s = m.static(loads=[(b.end, (0, 0, 0, 0, 0, P), "world")], steps=steps)
    return s.positions(b)[-1]


# ------------------------------------------------------------------ small load, Table I beam
def test_small_tip_load_vs_timoshenko_with_closed_form_discretization_error():
    # NOT nodally exact for a tip load (unlike the distributed load of test_beam_loads): with one
    # constant curvature per element the tip deflection is the midpoint rule applied to
    # w_tip = int_0^L kappa(s) (L - s) ds with kappa = P (L - s)/EI, whose error is exactly
    # h^2/24 * int f'' = P L^3 / (12 EI N^2) (f quadratic); the shear part P L/kGA (constant
    # shear strain) is exact. Measured: relative error -6.1e-2 (N=2) ... -9.8e-5 (N=50), and the
    # difference from this closed form below 1e-9 of the tip deflection (the geometric
    # nonlinearity at P L^2/EI = 1e-5 is of order 1e-10).
    P = 1e-5 * EI / L**2
    w_lin = P * L**3 / (3 * EI) + P * L / kGA
    props = table1_properties(1.0)
    rel = {}
    for N in (2, 3, 5, 10, 20, 50):
        w = cantilever_tip(props, N, P)[2]
        predicted = w_lin - P * L**3 / (12 * EI * N**2)
        rel[N] = (w - w_lin) / w_lin
        assert abs(w - predicted) <= 1e-9 * w_lin, (N, (w - predicted) / w_lin)
    # second-order convergence towards the Timoshenko value, and the N=50 accuracy
    assert all(rel[N] < 0 for N in rel)
    assert abs(rel[50]) < 1e-4 and abs(rel[2]) > 0.05
    np.testing.assert_allclose(rel[10] / rel[20], 4.0, rtol=1e-6)


# ------------------------------------------------------------------ large load vs the elastica
def elastica_tip(lam):
    """Tip (x, z, theta) of the inextensible, shear-rigid cantilever of length L under a dead
    tip load P = lam EI/L^2 along -z: EI theta'' = -P cos(theta), theta(0) = 0, theta'(L) = 0,
    x' = cos(theta), z' = -sin(theta). Shooting on theta'(0) in [0, P L/EI] (theta'(L) is
    -P L/EI at 0 and >= 0 at P L/EI since int cos <= L)."""
    a = lam / L**2

    def shoot(k0):
        s = solve_ivp(lambda _, y: [y[1], -a * np.cos(y[0]), np.cos(y[0]), -np.sin(y[0])],
                      (0.0, L), [0.0, k0, 0.0, 0.0], rtol=1e-12, atol=1e-14)
        return s.y[:, -1]

    k0 = brentq(lambda k: shoot(k)[1], 0.0, a * L, xtol=1e-15, rtol=1e-15)
    th, _, x, z = shoot(k0)
    return x, z, th


STIFF = 1e7   # EA = GA = 1e7 EI/L^2: axial and shear compliance effects ~ P/EA <= 1e-6


@pytest.fixture(scope="module")
def stiff_props():
    EIs = 1.0
    return ph.BeamProperties.from_values(EA=STIFF, GA_y=STIFF, GA_z=STIFF, GJ=EIs, EI_y=EIs,
                                         EI_z=EIs, rhoA=1.0, rhoI_y=1e-3, rhoI_z=1e-3)


@pytest.mark.parametrize("lam", [1.0, 3.0, 10.0])
def test_large_tip_load_matches_the_elastica(stiff_props, lam):
    # EI = 1 N m^2, L = 1 m, P = lam. Measured (lam = 10): tip error vs elastica (dx, dz) =
    # (6.3e-3, 1.1e-2) at N=4, (1.5e-3, 2.6e-3) at N=8, (3.8e-4, 6.5e-4) at N=16: second order,
    # no shear locking although GA/(EI/h^2) = 1e7/256 at N=16 (a locking element would be
    # too stiff by a factor growing with that ratio, and would not converge at this rate).
    P = lam * 1.0 / L**2
    xe, ze, _ = elastica_tip(lam)
    Ns = (4, 8, 16)
    tips = {N: cantilever_tip(stiff_props, N, -P, steps=10) for N in Ns}
    err = {N: np.hypot(tips[N][0] - xe, tips[N][2] - ze) for N in Ns}
    w_lin = P * L**3 / 3
    for N in Ns:
        x, y, z = tips[N]
        assert x < L - 0.05 * lam / 10           # tip shortening (elastica: 0.944, 0.746, 0.445)
        assert abs(y) < 1e-12
        assert -z < w_lin                          # stiffening: less than the linear deflection
    # errors fall at second order with N (measured ratios 3.9-4.1)
    for a, b in zip(Ns, Ns[1:]):
        assert 3.5 < err[a] / err[b] < 4.5, err
    assert err[16] < 1e-3 * L
    # Richardson extrapolation of N = 8, 16 agrees with the elastica up to the axial/shear
    # compliance (P/EA ~ 1e-6) and the O(N^-4) remainder: measured <= 1e-6, asserted 1e-5 L
    rich = (4 * tips[16] - tips[8]) / 3
    assert abs(rich[0] - xe) < 1e-5 * L and abs(rich[2] - ze) < 1e-5 * L, (rich[0] - xe, rich[2] - ze)


def test_elastica_reference_small_load_limit():
    # the shooting solver itself against the linear Euler value for lam -> 0 (check of the reference)
    lam = 1e-4
    _, z, th = elastica_tip(lam)
    np.testing.assert_allclose(-z, lam * L / 3, rtol=1e-4)
    np.testing.assert_allclose(th, lam / 2, rtol=1e-4)



# ------------------------------------------------------------------ stability of the equilibrium
def _pendulum(com_z: float, g: float = 9.81):
    """A rigid pendulum (1 kg, 0.01 kg m^2 about its centre) on a y-axis revolute at the origin,
    its centre at (0, 0, com_z) [m]: hanging (com_z < 0) or inverted (com_z > 0)."""
    m = ph.Mechanism(gravity=(0, 0, -g))
    b = m.add_rigid_body("b", 1.0, 0.01 * np.eye(3), com=(0, 0, com_z))
    m.add_pair("r", ph.Revolute(axis=(0, 1, 0)), m.ground, b.frame)
    return m


def test_static_reports_the_stability_of_the_equilibrium():
    # small oscillations about the pivot: omega^2 = m g l / (I_c + m l^2); the inverted pendulum
    # is an equilibrium with omega^2 of the opposite sign, and static() must say it is unstable
    omega = np.sqrt(9.81 * 0.5 / (0.01 + 0.25))
    import warnings
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        st = _pendulum(-0.5).static()
    assert st.stable is True and st.steps == 10
    assert st.lowest_omega == pytest.approx(omega, rel=1e-6)
    with pytest.warns(ph.StabilityWarning, match="unstable.*-4.343 rad/s.*100 load steps"):
        st = _pendulum(0.5).static()
    assert st.stable is False and st.lowest_omega == pytest.approx(-omega, rel=1e-6)
    st = _pendulum(0.5).static(check_stability=False)
    assert st.stable is None and np.isnan(st.lowest_omega)


def test_follower_loads_are_not_judged_and_modes_warns():
    # a body-frame wrench turns with its carrier: its load stiffness is not symmetric, so neither
    # static()'s check nor modes() can judge stability (Beck's column: tests/hard)
    m = ph.Mechanism()
    b = m.add_flexible_link("b", L, table1_properties(1.0), elements=4)
    m.add_pair("clamp", ph.Fixed(), m.ground, b.start)
    m.add_wrench("push", b.end, (0, 0, 0, -1.0, 0, 0), frame="body")
    st = m.static()
    assert st.stable is None
    with pytest.warns(ph.StabilityWarning, match="follower loads \\['push'\\]"):
        m.modes(2, at=st)


def test_static_from_a_horizontal_pendulum_finds_it_hanging():
    # started horizontal, gravity has no stiffness (the tangent is singular) and Newton's load
    # steps all fail; pseudo-transient continuation (csrc/analyze/statics.c, ptc) lets it fall to
    # the stable equilibrium: centre straight below the pivot, omega^2 = m g l / (I_c + m l^2)
    m = ph.Mechanism(gravity=(0, 0, -9.81))
    arm = m.add_rigid_body("arm", 1.0, np.diag([1e-4, 0.0075, 0.0075]), com=(0.15, 0, 0))
    m.add_pair("shoulder", ph.Revolute(axis="y"), m.ground, arm, x0=0.0)
    st = m.static()
    np.testing.assert_allclose(st.poses[arm.carrier][:3, :3] @ [1, 0, 0], [0, 0, -1], atol=1e-9)
    assert st.stable and st.lowest_omega == pytest.approx(np.sqrt(9.81 * 0.15 / 0.03), rel=1e-9)


def test_a_failed_static_solve_carries_its_last_equilibrium():
    # the deep arch of tests/hard (20 elements) has its limit point at P R^2/EI = 9.137
    # (docs/validation.md); loaded with 2000 (P R^2/EI = 20) load control fails there, and the
    # error's result is the last converged state: an equilibrium under the load factor it reports
    import sys, os
    sys.path.insert(0, os.path.join(os.path.dirname(__file__), "hard"))
    import _scenes as S
    m, _ = S._arch(20, 2000.0)
    with pytest.raises(ph.SolverError, match="last converged state, at load factor 0.45") as e:
        m.static()
    part = e.value.result
    assert isinstance(part, ph.StaticResult) and 0.45 < part.load_factor < 0.46
    m2, _ = S._arch(20, 2000.0 * part.load_factor)
    st = m2.static()
    # measured 1.4e-12 m (of a 100 m arch; 6.4e-10 m while ptc() restored newton()'s start, not its own)
    np.testing.assert_allclose(st.poses[:, :3, 3], part.poses[:, :3, 3], atol=1e-7)


def test_free_motions_without_load_leave_an_equilibrium_in_place():
    # a body held by nothing, a body on a revolute, a free strip: no load, so every pose is an
    # equilibrium (not unique); static() returns the start, neutral (lowest_omega a round-off
    # zero: 0, or 3e-6 rad/s for the link, whose first bending mode is 49 rad/s). Before, the
    # exactly singular tangent failed Newton and static() raised; the stability check took the
    # free link's six round-off zeros (-4e-3 rad/s) for an instability
    def free_body(m):
        m.add_rigid_body("box", 2.0, np.diag([1e-3, 1e-3, 1e-3]))

    def revolute(m):
        r = m.add_rigid_body("r", 1.0, np.diag([1e-3, 1e-3, 1e-3]), com=(0.1, 0, 0))
        m.add_pair("p", ph.Revolute("z"), m.ground, r)

    def free_link(m):
        m.add_flexible_link("leaf", L, table1_properties(1.0), elements=10)

    for build in (free_body, revolute, free_link):
        m = ph.Mechanism()
        build(m)
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            # held by nothing on purpose (the free body and the free link)
            warnings.simplefilter("ignore", ph.UnattachedWarning)
            st = m.static()
        np.testing.assert_allclose(st.poses, m.initial_configuration().poses, atol=1e-12)
        assert st.stable is True and abs(st.lowest_omega) < 1e-4, build.__name__

"""Golo's mixed finite element (the paper's element) for the linear Timoshenko beam, Table I.

References used here, all independent of the element: the exact Timoshenko frequency equation
(phmech.timoshenko, Huang 1961), the closed-form simply-supported spectrum, statics of a cantilever
under a tip force, NumPy eigenvalues of the returned matrices, and the port-Hamiltonian identities.
"""
import math

import numpy as np
import pytest

import phmech
from phmech import mixed, timoshenko

# Table I: L = 1 m, rhoA = 873 kg/m, rhoI = 2.1797 kg m, EI = 5143 N m^2, kGA = 656625 N.
P = dict(L=1.0, EI=5143.0, kGA=656625.0, rhoA=873.0, rhoI=2.1797)


def rel_err(N, bc="clamped-free", n=5, alpha=0.5):
    exact = timoshenko.frequencies(n, bc=bc, **P)
    return (mixed.frequencies(n, N, bc=bc, alpha=alpha, **P) - exact) / exact


@pytest.mark.parametrize("N,alpha", [(1, 0.5), (4, 0.5), (9, 0.5), (6, 0.3), (5, 0.0)])
def test_structure(N, alpha):
    m = mixed.matrices(N, alpha=alpha, **P)
    n = 4 * N
    assert m.J.shape == (n, n) and m.Q.shape == (n, n) and m.B.shape == (n, 4)
    assert m.D.shape == (4, 4)
    np.testing.assert_array_equal(m.J, -m.J.T)          # skew, exactly
    np.testing.assert_array_equal(m.D, -m.D.T)
    np.testing.assert_array_equal(m.Q, m.Q.T)
    assert np.linalg.eigvalsh(m.Q).min() > 0            # positive definite
    # element energy: Q = diag(1/(rhoA h), kGA/h, 1/(rhoI h), EI/h)
    h = P["L"] / N
    np.testing.assert_allclose(np.diag(m.Q)[:4],
                               [1 / (P["rhoA"] * h), P["kGA"] / h, 1 / (P["rhoI"] * h), P["EI"] / h],
                               rtol=1e-15)


@pytest.mark.parametrize("N,alpha", [(1, 0.5), (7, 0.5), (8, 0.2)])
def test_power_balance(N, alpha):
    """dH/dt = (Qx)^T (J Q x + B u) equals u^T y with y = B^T Q x + D u; zero for u = 0."""
    m = mixed.matrices(N, alpha=alpha, **P)
    rng = np.random.default_rng(N)
    for _ in range(5):
        x = rng.standard_normal(4 * N)
        u = rng.standard_normal(4)
        e = m.Q @ x
        dH = e @ (m.J @ e + m.B @ u)
        y = m.B.T @ e + m.D @ u
        scale = np.abs(e).max() * (np.abs(m.J @ e).max() + np.abs(m.B @ u).max()) * 4 * N
        assert abs(dH - u @ y) <= 1e-13 * scale
        assert abs(e @ (m.J @ e)) <= 1e-13 * scale       # closed system: lossless


def test_static_tip_force():
    """Cantilever with a tip shear force F: equilibrium 0 = J e + B u gives, exactly, v = omega = 0,
    shear force F on every element and moment F (L - s) at element mid-points (alpha = 1/2 is the
    mean of the linear interpolant, exact for the linear moment)."""
    N, F = 7, 123.0
    m = mixed.matrices(N, **P)
    e = np.linalg.solve(m.J, -m.B @ np.array([0.0, 0.0, F, 0.0]))
    h = P["L"] / N
    mid = (np.arange(N) + 0.5) * h
    np.testing.assert_allclose(e[0::4], 0.0, atol=1e-12 * F)
    np.testing.assert_allclose(e[2::4], 0.0, atol=1e-12 * F)
    np.testing.assert_allclose(e[1::4], F, rtol=1e-12)
    np.testing.assert_allclose(e[3::4], F * (P["L"] - mid), rtol=1e-12)


def _numpy_frequencies(m, n):
    """Frequencies from the returned matrices with NumPy: z = Q^1/2 x, A = Q^1/2 J Q^1/2,
    restricted to the orthogonal complement of the constraint directions Q^1/2 G."""
    s = np.sqrt(np.diag(m.Q))
    A = s[:, None] * m.J * s[None, :]
    if m.G.shape[1]:
        Z = np.linalg.svd(s[:, None] * m.G, full_matrices=True)[0][:, m.G.shape[1]:]
        A = Z.T @ A @ Z
    w = np.linalg.eigvals(A).imag
    return np.sort(w[w > 1e-8 * np.abs(w).max()])[:n]


@pytest.mark.parametrize("bc", mixed.BOUNDARY_CONDITIONS)
def test_frequencies_match_numpy_eig(bc):
    m = mixed.matrices(12, bc=bc, **P)
    np.testing.assert_allclose(mixed.frequencies(6, 12, bc=bc, **P), _numpy_frequencies(m, 6),
                               rtol=1e-10)


def test_constraint_ports():
    assert mixed.matrices(3, bc="clamped-free", **P).G.shape == (12, 0)
    m = mixed.matrices(3, bc="pinned-pinned", **P)
    assert m.constrained == (1, 2)                       # M(0) = 0 and v(L) = 0 as constraints
    np.testing.assert_array_equal(m.G, m.B[:, [1, 2]])
    assert mixed.matrices(3, bc="clamped-clamped", **P).constrained == (2, 3)


def test_table1_paper_statements():
    """Sec. VIII-B2: with N = 9 the third mode is off by about 10 %; with N = 21 all five modes are
    within 5 %, omega_5 being the worst."""
    e9 = rel_err(9)
    e21 = rel_err(21)
    assert 0.08 < abs(e9[2]) < 0.12, e9
    assert np.all(np.abs(e9[:2]) < 0.05), e9
    assert np.all(np.abs(e21) < 0.05), e21
    assert np.argmax(np.abs(e21)) == 4, e21


def test_second_order_convergence_cantilever():
    errs = {N: np.abs(rel_err(N)) for N in (25, 50, 100)}
    for a, b in ((25, 50), (50, 100)):
        order = np.log(errs[a] / errs[b]) / math.log(b / a)
        assert np.all(order > 1.95) and np.all(order < 2.1), order
    assert np.all(errs[100] < 2.5e-3)


@pytest.mark.parametrize("bc", ["clamped-clamped", "pinned-pinned"])
def test_other_boundary_conditions_converge(bc):
    e50, e100 = np.abs(rel_err(50, bc)), np.abs(rel_err(100, bc))
    assert np.all(e100 < 3e-3), e100
    order = np.log(e50 / e100) / math.log(2)
    assert np.all(order > 1.95) and np.all(order < 2.1), order


def test_pinned_pinned_closed_form():
    """Simply supported: w = W sin(k s), phi = Phi cos(k s), k = j pi / L; both branches of the
    2x2 determinant. Independent of phmech.timoshenko."""
    L, EI, kGA, rhoA, rhoI = (P[k] for k in ("L", "EI", "kGA", "rhoA", "rhoI"))
    roots = []
    for j in range(1, 30):
        k = j * math.pi / L
        a, b = rhoA * rhoI, -(rhoA * (EI * k * k + kGA) + rhoI * kGA * k * k)
        c = kGA * EI * k ** 4
        d = math.sqrt(b * b - 4 * a * c)
        roots += [math.sqrt((-b - d) / (2 * a)), math.sqrt((-b + d) / (2 * a))]
    exact = np.sort(roots)[:5]
    w = mixed.frequencies(5, 200, bc="pinned-pinned", **P)
    np.testing.assert_allclose(w, exact, rtol=1e-3)


def test_alpha_other_than_half_converges_first_order():
    """Golo's family with alpha != 1/2 is consistent but only first order (the higher modes'
    errors change sign near N = 50-100, so the order is read on the first two)."""
    e50, e100 = np.abs(rel_err(50, alpha=0.25)), np.abs(rel_err(100, alpha=0.25))
    order = np.log(e50[:2] / e100[:2]) / math.log(2)
    assert np.all(e100 < 0.02), e100
    assert np.all(order > 0.9) and np.all(order < 1.1), order


@pytest.mark.parametrize("kw", [
    dict(N=0), dict(N=-3), dict(N=2.5), dict(N=1001), dict(EI=0.0), dict(kGA=-1.0),
    dict(rhoA=float("nan")), dict(rhoI=float("inf")), dict(L="one"), dict(alpha=1.0),
    dict(alpha=-0.1), dict(alpha=float("nan")), dict(bc="free-floating"), dict(bc=3),
    dict(n=0), dict(n=100), dict(alpha=0.9, N=20),
])
def test_bad_input(kw):
    args = dict(n=3, N=10, bc="clamped-free", alpha=0.5, **P)
    args.update(kw)
    with pytest.raises(phmech.ModelError):
        mixed.frequencies(**args)
    assert issubclass(phmech.ModelError, ValueError)

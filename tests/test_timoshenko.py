"""Exact Timoshenko frequencies (phmech.timoshenko) against independent references:

- a Chebyshev spectral collocation of the Timoshenko equations with the boundary conditions,
  solved with scipy.linalg.eigvals (no use of the frequency equation), to 1e-7 relative;
- the Euler-Bernoulli limit (roots of 1 + cos cosh = 0 etc. found here with brentq);
- the pinned-pinned closed form, including a pair of nearly coincident roots.
"""
import math

import numpy as np
import pytest
import scipy.linalg
from scipy.optimize import brentq

import phmech
from phmech import timoshenko as tim

BCS = ("clamped-free", "clamped-clamped", "pinned-pinned", "free-free")

# The paper's Table I beam (docs/method.md section 8.1)
TABLE1 = dict(L=1.0, EI=5143.0, kGA=656625.0, rhoA=873.0, rhoI=2.1797)
# A thick beam (rectangle h/L = 0.5, E/(kG) = 3.12): several of the first 8 modes lie above
# the cut-off sqrt(kGA/rhoI).
_b = 0.5**2 / 12.0
THICK = dict(L=0.8, EI=2.0e4, kGA=2.0e4 / (3.12 * _b * 0.8**2), rhoA=30.0, rhoI=30.0 * _b * 0.8**2)


# ---------------------------------------------------------------------------------------------
# independent reference: Chebyshev collocation

def _cheb(N):
    """Chebyshev points cos(j pi / N) and differentiation matrix on [-1, 1] (Trefethen 2000)."""
    x = np.cos(np.pi * np.arange(N + 1) / N)
    c = np.ones(N + 1)
    c[0] = c[-1] = 2.0
    c *= (-1.0) ** np.arange(N + 1)
    dX = x[:, None] - x[None, :]
    D = np.outer(c, 1.0 / c) / (dX + np.eye(N + 1))
    D -= np.diag(D.sum(axis=1))
    return D, x


def collocation_frequencies(N, L, EI, kGA, rhoA, rhoI, bc):
    """Circular frequencies from collocating
    -kGA (w'' - psi') = om^2 rhoA w,  -EI psi'' - kGA (w' - psi) = om^2 rhoI psi
    on N+1 Chebyshev points of [0, L]; the 4 boundary conditions replace the equations at the
    end nodes and the end values are eliminated (a standard eigenproblem on the interior)."""
    Dx, _ = _cheb(N)
    D1 = -2.0 / L * Dx            # node 0 is x = 0, node N is x = L
    D2 = D1 @ D1
    n = N + 1
    A = np.block([[-kGA * D2, kGA * D1], [-kGA * D1, -EI * D2 + kGA * np.eye(n)]])
    M = np.concatenate([np.full(n, rhoA), np.full(n, rhoI)])

    def row(kind, j):
        r = np.zeros(2 * n)
        if kind == "w":
            r[j] = 1.0
        elif kind == "psi":
            r[n + j] = 1.0
        elif kind == "moment":          # EI psi'
            r[n:] = D1[j]
        elif kind == "shear":           # kGA (w' - psi)
            r[:n] = D1[j]
            r[n + j] -= 1.0
        return r

    ends = {"clamped": ("w", "psi"), "free": ("moment", "shear"), "pinned": ("w", "moment")}
    left, right = {"clamped-free": ("clamped", "free"), "clamped-clamped": ("clamped", "clamped"),
                   "pinned-pinned": ("pinned", "pinned"), "free-free": ("free", "free")}[bc]
    G = np.array([row(k, 0) for k in ends[left]] + [row(k, N) for k in ends[right]])
    B = np.array([0, N, n, n + N])
    I = np.setdiff1d(np.arange(2 * n), B)
    T = -np.linalg.solve(G[:, B], G[:, I])
    K = A[np.ix_(I, I)] + A[np.ix_(I, B)] @ T
    lam = scipy.linalg.eigvals(K / M[I][:, None])
    if bc == "free-free":   # the two rigid-body modes: zero up to round-off, left out
        rigid = np.argsort(np.abs(lam))[:2]
        assert np.all(np.abs(lam[rigid]) <= 1e-6 * np.sort(np.abs(lam))[2])
        lam = np.delete(lam, rigid)
    lam = lam[(np.abs(lam.imag) <= 1e-8 * np.abs(lam)) & (lam.real > 0)].real
    return np.sqrt(np.sort(lam))


# ---------------------------------------------------------------------------------------------

@pytest.mark.parametrize("bc", BCS)
@pytest.mark.parametrize("beam,n", [(TABLE1, 5), (THICK, 8)], ids=["table1", "thick"])
def test_against_collocation(beam, n, bc):
    exact = tim.frequencies(n, bc=bc, **beam)
    assert exact.shape == (n,) and np.all(np.diff(exact) > 0)
    ref = collocation_frequencies(48, bc=bc, **beam)[:n]
    rel = np.abs(exact / ref - 1.0)
    assert rel.max() < 1e-7, (bc, rel)
    if beam is THICK:   # the case must exercise the second spectrum
        wc = tim.cutoff_frequency(beam["kGA"], beam["rhoI"])
        assert np.sum(exact > wc) >= 3


def test_table1_values_and_alias():
    w = tim.frequencies(5, 1.0, 5143.0, 656625.0, 873.0, 2.1797, bc="free-clamped")
    np.testing.assert_array_equal(w, tim.frequencies(5, bc="clamped-free", **TABLE1))
    # all five below the cut-off, and below the Euler-Bernoulli values (shear + rotary inertia
    # soften); (beta L)^2 of the clamped-free Euler-Bernoulli beam, to 9 digits
    eb = np.array([3.51601527, 22.0344916, 61.6972124, 120.901916, 199.859530])
    eb *= math.sqrt(5143.0 / 873.0)
    assert np.all(w < eb) and np.all(w > 0.5 * eb)
    assert w[-1] < tim.cutoff_frequency(656625.0, 2.1797)


def _eb_roots(f, n, lo=0.5):
    """First n positive roots of f on a fine grid (independent of phmech)."""
    x = np.linspace(lo, (n + 2) * math.pi, 20000)
    y = f(x)
    idx = np.nonzero(np.sign(y[:-1]) != np.sign(y[1:]))[0][:n]
    return np.array([brentq(f, x[i], x[i + 1], xtol=1e-15) for i in idx])


@pytest.mark.parametrize("bc", BCS)
def test_euler_bernoulli_limit(bc):
    """a = EI/(kGA L^2), b = rhoI/(rhoA L^2) -> 0: Omega = omega L^2 sqrt(rhoA/EI) -> (beta L)^2.
    The first-order correction is -(a+b)(beta L)^2/2 relative for pinned-pinned; we check
    the error is below 2 (a+b) (beta L)^2, that it is a decrease and that it is linear in a+b."""
    n, L, EI, rhoA = 6, 2.0, 3.0, 5.0
    if bc == "clamped-free":
        beta = _eb_roots(lambda x: 1.0 + np.cos(x) * np.cosh(x), n)
    elif bc in ("clamped-clamped", "free-free"):   # the same frequency equation
        beta = _eb_roots(lambda x: np.cos(x) * np.cosh(x) - 1.0, n, lo=1.0)
    else:
        beta = math.pi * np.arange(1, n + 1)
    errs = []
    for eps in (1e-6, 1e-7):
        a = b = eps
        Om = tim.frequencies(n, L, EI, EI / (a * L * L), rhoA, b * rhoA * L * L, bc) * L * L \
            * math.sqrt(rhoA / EI)
        err = 1.0 - Om / beta**2
        assert np.all(err > 0), (bc, err)
        assert np.all(err < 2.0 * (a + b) * beta**2), (bc, err)
        errs.append(err)
    np.testing.assert_allclose(errs[0] / errs[1], 10.0, rtol=1e-3)


@pytest.mark.parametrize("beam", [TABLE1, THICK], ids=["table1", "thick"])
def test_pinned_determinant_matches_closed_form(beam):
    """The determinant search (used for the other bc) reproduces the pinned closed form,
    including the n = 0 second-spectrum mode at exactly omega_c."""
    a = beam["EI"] / (beam["kGA"] * beam["L"] ** 2)
    b = beam["rhoI"] / (beam["rhoA"] * beam["L"] ** 2)
    closed = tim._pinned_closed_form(12, a, b)
    det = tim._determinant_roots(12, a, b, "pinned-pinned")
    np.testing.assert_allclose(det, closed, rtol=1e-13)
    assert np.any(np.isclose(closed, 1.0 / math.sqrt(a * b), rtol=1e-15))


@pytest.mark.parametrize("split", [1e-7, 1e-4])
def test_close_roots_are_both_found(split):
    """Tune b so that the first-branch root of n = 3 and the second-branch root of n = 1 of the
    pinned beam nearly coincide: the grid alone sees no sign change between them."""
    a = 0.0645

    def gap(b):
        lo, _ = tim._omega_sq_of_beta(np.array([3 * math.pi]), a, b)
        _, hi = tim._omega_sq_of_beta(np.array([math.pi]), a, b)
        return lo[0] - hi[0]

    b = brentq(gap, 1e-3, 0.1, xtol=1e-17) * (1.0 + split)
    closed = tim._pinned_closed_form(10, a, b)
    assert np.min(np.diff(closed)) < 1e-3 * closed.max()
    np.testing.assert_allclose(tim._determinant_roots(10, a, b, "pinned-pinned"), closed,
                               rtol=1e-12)


@pytest.mark.parametrize("bc", ["clamped-free", "free-clamped", "clamped-clamped"])
def test_mode_shape_satisfies_equations(bc):
    beam = THICK
    L, EI, kGA, rhoA, rhoI = (beam[k] for k in ("L", "EI", "kGA", "rhoA", "rhoI"))
    k = 4                                  # above the cut-off
    om = tim.frequencies(k + 1, bc=bc, **beam)[k]
    x = np.linspace(0.0, L, 4001)
    w, psi = tim.mode_shape(k, x, bc=bc, **beam)
    assert np.max(np.abs(w)) == pytest.approx(1.0) and w[np.argmax(np.abs(w))] > 0
    h = x[1] - x[0]
    d = lambda f: np.gradient(f, h, edge_order=2)  # noqa: E731
    r1 = kGA * (d(d(w)) - d(psi)) + rhoA * om**2 * w
    r2 = EI * d(d(psi)) + kGA * (d(w) - psi) + rhoI * om**2 * psi
    scale1 = rhoA * om**2 * np.max(np.abs(w))
    scale2 = rhoI * om**2 * np.max(np.abs(psi))
    assert np.max(np.abs(r1[2:-2])) < 1e-4 * scale1
    assert np.max(np.abs(r2[2:-2])) < 1e-4 * scale2
    clamp = -1 if bc == "free-clamped" else 0
    free = 0 if bc == "free-clamped" else -1
    assert abs(w[clamp]) < 1e-9 and abs(psi[clamp]) < 1e-9 * np.max(np.abs(psi))
    if bc != "clamped-clamped":
        assert abs(d(psi)[free]) < 1e-4 * np.max(np.abs(d(psi)))
        assert abs(d(w)[free] - psi[free]) < 1e-4 * np.max(np.abs(psi))


@pytest.mark.parametrize("kwargs", [
    dict(n=0), dict(n=2.5), dict(n=True), dict(L=-1.0), dict(EI=0.0), dict(kGA=float("nan")),
    dict(rhoA=float("inf")), dict(rhoI="x"), dict(bc="free-pinned"), dict(bc=None),
])
def test_bad_input(kwargs):
    args = dict(n=3, bc="clamped-free", **TABLE1)
    args.update(kwargs)
    with pytest.raises(phmech.ModelError) as e:
        tim.frequencies(**args)
    assert isinstance(e.value, ValueError)
    name = next(iter(kwargs))
    assert name in str(e.value)

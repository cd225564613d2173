"""Exact natural frequencies of a uniform Timoshenko beam (reference for the finite elements).

The linear Timoshenko beam in one plane, deflection ``w(x, t)`` [m] and cross-section rotation
``psi(x, t)`` [rad], ``0 <= x <= L``::

    rhoA * w_tt   = kGA * (w'' - psi')
    rhoI * psi_tt = EI * psi'' + kGA * (w' - psi)

with bending stiffness ``EI`` [N m^2], shear stiffness ``kGA`` [N], mass per length ``rhoA``
[kg/m] and rotary inertia per length ``rhoI`` [kg m]. Boundary conditions: clamped ``w = psi = 0``;
pinned ``w = 0, EI psi' = 0``; free ``EI psi' = 0, kGA (w' - psi) = 0``.

Frequency equation (Huang 1961; Traill-Nash & Collar 1953). With ``xi = x/L``, the dimensionless
frequency ``Omega = omega L^2 sqrt(rhoA/EI)`` (the Euler-Bernoulli ``(beta L)^2``) and the shear and
rotary parameters ``a = EI/(kGA L^2)``, ``b = rhoI/(rhoA L^2)``, a solution ``exp(lambda xi)``
needs ``s = lambda^2`` to be a root of::

    s^2 + Omega^2 (a + b) s + Omega^2 (Omega^2 a b - 1) = 0,

whose two roots ``s1 > s2`` are real and distinct for ``Omega > 0`` (discriminant
``Omega^4 (a-b)^2 + 4 Omega^2``). ``s2 < 0`` always; ``s1 > 0`` below the cut-off frequency
``omega_c = sqrt(kGA/rhoI)`` (``Omega_c = 1/sqrt(a b)``) and ``s1 < 0`` above it, where the
hyperbolic wavenumber turns into a second trigonometric one (the "second spectrum").

Pole-free formulation used here. For each root ``s`` the two functions::

    C(s, xi) = cosh(sqrt(s) xi),   S(s, xi) = sinh(sqrt(s) xi)/sqrt(s)

are entire in ``s`` and real (``cos(sqrt(-s) xi)``, ``sin(sqrt(-s) xi)/sqrt(-s)`` for ``s < 0``), so the
same code is valid on both sides of the cut-off and at it. With ``r = Omega^2 a`` the two solutions
per root are ``(w/L, psi) = (C, (s+r) S)`` and ``(s S, (s+r) C)`` (they satisfy ``psi' = (s+r) w/L``).
Four boundary conditions give a 4x4 determinant that is a continuous function of ``Omega`` with
no poles (no division by a vanishing wavenumber and no ratio of trigonometric functions), so a sign
change is a root. For a hyperbolic root ``s1 = alpha^2 > 1`` the pair is replaced by the
exponentials decaying from either end, ``exp(-alpha xi)`` and ``exp(alpha (xi - 1))`` (a change of
basis with positive determinant, applied back as a positive factor), which keeps the matrix well
conditioned for slender beams and high modes (checked against 50-digit arithmetic: 1e-16).

Roots are bracketed on a grid that moves each trigonometric wavenumber by at most ``pi/48``
between nodes (the roots of each branch are about ``pi`` apart). A node where ``|det|`` has a
local minimum without a sign change is searched for a hidden pair of close roots (one of each
branch) or a double root; a double root, or two roots closer than about 1e-8 relative, is
returned twice with about 1e-8 relative accuracy (the square-root loss of a tangency). Every
bracket is refined with :func:`scipy.optimize.brentq` to machine precision.

Pinned-pinned has the closed form ``w = sin(n pi xi)``: for ``n = 1, 2, ...`` the two roots ``Omega^2``
of ``a b Omega^4 - Omega^2 (1 + (a+b) (n pi)^2) + (n pi)^4 = 0`` (first and second spectrum), plus the
``n = 0`` second-spectrum mode ``w = 0, psi = const`` at exactly ``omega_c``.
"""
from __future__ import annotations

import math

import numpy as np
from scipy.optimize import brentq, minimize_scalar

from ._checks import positive
from ._errors import ModelError

__all__ = ["frequencies", "mode_shape", "cutoff_frequency", "BOUNDARY_CONDITIONS"]

#: Accepted values of ``bc`` (``"free-clamped"`` is the same beam mirrored: same spectrum).
BOUNDARY_CONDITIONS = ("clamped-free", "free-clamped", "clamped-clamped", "pinned-pinned",
                       "free-free")

_ALIASES = {"free-clamped": "clamped-free"}
_POINTS_PER_PI = 48          # grid nodes per pi of each wavenumber
_GRID_OFFSET = 0.381966011250105  # (3 - sqrt 5)/2: keeps nodes off beta = m pi




def _check(L, EI, kGA, rhoA, rhoI, bc):
    L = positive("L", L)
    EI = positive("EI", EI)
    kGA = positive("kGA", kGA)
    rhoA = positive("rhoA", rhoA)
    rhoI = positive("rhoI", rhoI)
    if not isinstance(bc, str) or bc not in BOUNDARY_CONDITIONS:
        raise ModelError(f"bc must be one of {BOUNDARY_CONDITIONS}, got {bc!r}")
    a = EI / (kGA * L * L)
    b = rhoI / (rhoA * L * L)
    scale = math.sqrt(EI / rhoA) / (L * L)          # omega = scale * Omega
    return a, b, scale, _ALIASES.get(bc, bc)


def cutoff_frequency(kGA: float, rhoI: float) -> float:
    """Second-spectrum cut-off ``omega_c = sqrt(kGA/rhoI)`` [rad/s] (``kGA`` [N], ``rhoI`` [kg m])."""
    return math.sqrt(positive("kGA", kGA) / positive("rhoI", rhoI))


# ----------------------------------------------------------------------------------------------
# dimensionless kernel

def _roots(Om: float, a: float, b: float) -> tuple[float, float]:
    """The two roots s1 > s2 of the characteristic quadratic, computed without cancellation."""
    O2 = Om * Om
    D = math.sqrt(O2 * O2 * (a - b) ** 2 + 4.0 * O2)
    s2 = -0.5 * (O2 * (a + b) + D)
    s1 = O2 * (O2 * a * b - 1.0) / s2
    return s1, s2


def _CS(s: float, xi: float) -> tuple[float, float]:
    """C = cosh(sqrt(s) xi), S = sinh(sqrt(s) xi)/sqrt(s) (entire in s), for xi >= 0."""
    if s >= 0.0:
        z = math.sqrt(s) * xi
        c = math.cosh(z)
        sh = math.sinh(z) / z if z > 1e-8 else 1.0 + z * z / 6.0
    else:
        z = math.sqrt(-s) * xi
        c = math.cos(z)
        sh = math.sin(z) / z if z > 1e-8 else 1.0 - z * z / 6.0
    return c, xi * sh


def _columns(Om: float, a: float, b: float, xi: float):
    """Values at xi of (w/L, psi, L psi', L w' - psi) for the four basis solutions (4x4 array),
    and the positive factor by which their determinant must be multiplied (see _det)."""
    r = Om * Om * a
    out = np.empty((4, 4))
    factor = 1.0
    for j, s in enumerate(_roots(Om, a, b)):
        if s > 1.0:
            # hyperbolic root with alpha = sqrt(s) > 1: the pair (C, s S) becomes numerically
            # parallel at xi = 1 (both ~ e^alpha), so use the exponentials decaying from either
            # end, U1 = exp(-alpha xi), U2 = exp(alpha (xi - 1)), with psi = (s+r)/lambda * w.
            # (A, B) = (U1, U2) T with det T = alpha e^alpha / 2 > 0: the sign is unchanged and
            # the factor below makes the determinant equal to the scaled one of the other branch.
            al = math.sqrt(s)
            e1, e2 = math.exp(-al * xi), math.exp(al * (xi - 1.0))
            out[:, 2 * j] = e1 * np.array([1.0, -(s + r) / al, s + r, r / al])
            out[:, 2 * j + 1] = e2 * np.array([1.0, (s + r) / al, s + r, -r / al])
            em = math.exp(-al)
            factor *= 2.0 * al * em / (1.0 + em * em) ** 2
            continue
        sc = 1.0 / math.cosh(math.sqrt(s)) if s > 0.0 else 1.0
        C, S = _CS(s, xi)
        # solution A: w = C, psi = (s+r) S ;  solution B: w = s S, psi = (s+r) C
        out[:, 2 * j] = sc * np.array([C, (s + r) * S, (s + r) * C, -r * S])
        out[:, 2 * j + 1] = sc * np.array([s * S, (s + r) * C, (s + r) * s * S, -r * C])
    return out, factor


_ROWS = {  # rows of _columns() imposed at (xi = 0, xi = 1)
    "clamped-free": ((0, 1), (2, 3)),
    "clamped-clamped": ((0, 1), (0, 1)),
    "pinned-pinned": ((0, 2), (0, 2)),
    "free-free": ((2, 3), (2, 3)),
}


def _matrix(Om: float, a: float, b: float, bc: str) -> tuple[np.ndarray, float]:
    r0, r1 = _ROWS[bc]
    c0, factor = _columns(Om, a, b, 0.0)
    c1, _ = _columns(Om, a, b, 1.0)
    return np.vstack([c0[list(r0)], c1[list(r1)]]), factor


def _det(Om: float, a: float, b: float, bc: str) -> float:
    """Boundary-condition determinant: continuous in Omega, no poles, sign-consistent."""
    m, factor = _matrix(Om, a, b, bc)
    return factor * float(np.linalg.det(m))


def _omega_sq_of_beta(beta: np.ndarray, a: float, b: float):
    """Omega^2 at which a root equals s = -beta^2: the lower (first branch) and upper
    (second branch, above cut-off) roots of a b W^2 - W (1 + (a+b) beta^2) + beta^4 = 0."""
    beta2 = beta * beta
    p = 1.0 + (a + b) * beta2
    disc = np.sqrt(p * p - 4.0 * a * b * beta2 * beta2)
    upper = (p + disc) / (2.0 * a * b)
    lower = beta2 * beta2 / (a * b * upper)
    return lower, upper


def _pinned_closed_form(n: int, a: float, b: float) -> np.ndarray:
    """First n dimensionless frequencies Omega of the pinned-pinned beam (both spectra)."""
    cands = [1.0 / math.sqrt(a * b)]                  # n = 0 second spectrum: omega = omega_c
    m = 1
    while True:
        lo, hi = _omega_sq_of_beta(np.array([m * math.pi]), a, b)
        cands += [math.sqrt(lo[0]), math.sqrt(hi[0])]
        cands.sort()
        # every frequency of any larger mode number exceeds this mode's first-branch one
        if len(cands) >= n and cands[n - 1] <= math.sqrt(lo[0]):
            return np.array(cands[:n])
        m += 1


def _determinant_roots(n: int, a: float, b: float, bc: str) -> np.ndarray:
    """First n dimensionless frequencies Omega from the determinant (any bc)."""
    beta_max = (n + 2) * math.pi
    while True:
        # wavenumber grid, offset by an irrational fraction of a step so that no node falls on
        # a closed-form root (beta = m pi) of the pinned beam
        k = np.arange(int(beta_max / math.pi * _POINTS_PER_PI) + 1) + _GRID_OFFSET
        beta = k * (math.pi / _POINTS_PER_PI)
        lo, hi = _omega_sq_of_beta(beta, a, b)
        grid = np.sort(np.sqrt(np.concatenate([lo, hi[hi < lo[-1]]])))
        keep = np.concatenate([[True], np.diff(grid) > 1e-9 * grid[1:]])
        roots = _roots_on_grid(grid[keep], a, b, bc)
        if len(roots) >= n:
            return np.array(roots[:n])
        if beta_max > 1e4:  # pragma: no cover - would need thousands of modes
            raise ModelError("Timoshenko frequency search did not find the requested roots")
        beta_max *= 2.0


def _roots_on_grid(grid: np.ndarray, a: float, b: float, bc: str) -> list[float]:
    """All roots of the determinant in [grid[0], grid[-1]], ascending, multiple roots repeated.

    A cell with a sign change holds one root (each wavenumber moves by at most pi/48 per cell,
    the roots of each branch are about pi apart, so a cell holds at most one root of each
    branch). A node where |det| has a local minimum without a sign change may hide two close
    roots (one of each branch) or a double root: the extremum of det between its neighbours is
    located; if det changes sign there, both roots are refined, if |det| is zero to 1e-10 of
    its neighbours' values the root is counted twice."""
    g = lambda x: _det(x, a, b, bc)  # noqa: E731
    f = np.array([g(x) for x in grid])
    af = np.abs(f)
    eps = np.finfo(float).eps

    def refine(x0, x1):
        return brentq(g, x0, x1, xtol=4 * eps * x1, rtol=4 * eps, maxiter=200)

    roots: list[float] = []
    for i in range(len(grid) - 1):
        if f[i] == 0.0:
            roots.append(grid[i])
        elif f[i] * f[i + 1] < 0.0:
            roots.append(refine(grid[i], grid[i + 1]))
        if (0 < i < len(grid) - 1 and f[i - 1] * f[i] > 0.0 and f[i] * f[i + 1] > 0.0
                and af[i] < af[i - 1] and af[i] < af[i + 1]):
            sgn = math.copysign(1.0, f[i])
            x0, x1 = grid[i - 1], grid[i + 1]
            res = minimize_scalar(lambda x: sgn * g(x), bounds=(x0, x1), method="bounded",
                                  options={"xatol": 1e-14 * x1})
            xm, fm = float(res.x), sgn * float(res.fun)
            if sgn * fm > af[i]:  # the bounded search missed the node's own value
                xm, fm = grid[i], f[i]
            if fm * f[i] < 0.0:
                roots += [refine(x0, xm), refine(xm, x1)]
            elif abs(fm) <= 1e-10 * max(af[i - 1], af[i + 1]):
                roots += [xm, xm]
    roots.sort()
    return roots


# ----------------------------------------------------------------------------------------------
# public API

def frequencies(n: int, L: float, EI: float, kGA: float, rhoA: float, rhoI: float,
                bc: str = "clamped-free") -> np.ndarray:
    """First ``n`` natural circular frequencies [rad/s] of a uniform Timoshenko beam.

    Parameters
    ----------
    n : int
        Number of frequencies (positive); both spectra are included, in ascending order.
    L : float
        Length [m].
    EI : float
        Bending stiffness [N m^2].
    kGA : float
        Shear stiffness (shear coefficient times G A) [N].
    rhoA : float
        Mass per unit length [kg/m].
    rhoI : float
        Rotary inertia per unit length (density times second moment of area) [kg m].
    bc : str
        ``"clamped-free"`` (alias ``"free-clamped"``), ``"clamped-clamped"``,
        ``"pinned-pinned"`` or ``"free-free"`` (its elastic modes: the two rigid-body ones, at
        zero, are not counted).

    Returns
    -------
    numpy.ndarray
        Shape (n,), ascending [rad/s]. Exact roots of the frequency equation (relative
        accuracy about 1e-14); pinned-pinned from its closed form. Valid below and above the
        cut-off ``sqrt(kGA/rhoI)`` (see the module docstring).

    Raises
    ------
    ModelError
        (a ValueError) on a non-positive/non-finite parameter, bad ``n`` or unknown ``bc``.
    """
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 1:
        raise ModelError(f"n must be a positive integer, got {n!r}")
    a, b, scale, bc = _check(L, EI, kGA, rhoA, rhoI, bc)
    if bc == "pinned-pinned":
        Om = _pinned_closed_form(int(n), a, b)
    else:
        Om = _determinant_roots(int(n), a, b, bc)
    return scale * Om


def mode_shape(k: int, x, L: float, EI: float, kGA: float, rhoA: float, rhoI: float,
               bc: str = "clamped-free") -> tuple[np.ndarray, np.ndarray]:
    """Shape of mode ``k`` (0-based, in the order of :func:`frequencies`) at positions ``x`` [m].

    Returns ``(w, psi)``, arrays shaped like ``x``: deflection (dimensionless, scaled so that the
    largest ``|w|`` along the beam is 1 and positive) and section rotation in the same scaling
    [1/m]. A mode with no deflection (the pinned-pinned
    mode at the cut-off) is scaled so that ``L * max|psi| = 1`` instead. For
    ``bc="free-clamped"`` the clamp is at ``x = L`` (the clamped-free shape mirrored).
    """
    if isinstance(k, bool) or not isinstance(k, (int, np.integer)) or k < 0:
        raise ModelError(f"k must be a non-negative integer, got {k!r}")
    a, b, scale, bcn = _check(L, EI, kGA, rhoA, rhoI, bc)
    xs = np.asarray(x, dtype=float)
    if not np.all(np.isfinite(xs)) or np.any(xs < 0) or np.any(xs > L):
        raise ModelError("x must be finite positions within [0, L]")
    Om = frequencies(int(k) + 1, L, EI, kGA, rhoA, rhoI, bc)[-1] / scale
    _, _, vt = np.linalg.svd(_matrix(Om, a, b, bcn)[0])
    coef = vt[-1]

    def shape(xi_arr):
        xi_arr = np.atleast_1d(xi_arr)
        out = np.array([_columns(Om, a, b, xi)[0][:2] @ coef for xi in xi_arr.ravel()])
        return out[:, 0] * L, out[:, 1]      # w [m per unit coefficient], psi [rad]

    xi = xs / L
    if bc == "free-clamped":
        xi = 1.0 - xi
    w, psi = shape(xi)
    if bc == "free-clamped":
        psi = -psi
    grid = np.linspace(0.0, 1.0, 401)
    wf, pf = shape(grid)
    if np.max(np.abs(wf)) > 1e-8 * L * np.max(np.abs(pf)):
        vals, comp, sc = wf, 0, 1.0
    else:                                  # no deflection: normalize the rotation
        vals, comp, sc = pf, 1, L
    i = int(np.argmax(np.abs(vals)))
    sgn = math.copysign(1.0, vals[i])
    res = minimize_scalar(lambda t: -sgn * shape(t)[comp][0], method="bounded",
                          bounds=(grid[max(i - 1, 0)], grid[min(i + 1, len(grid) - 1)]),
                          options={"xatol": 1e-10})
    norm = sc * max(-res.fun, abs(vals[i])) * sgn
    w, psi = w / norm, psi / norm
    return w.reshape(xs.shape), psi.reshape(xs.shape)

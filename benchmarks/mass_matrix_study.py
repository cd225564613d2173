"""Mass-matrix / strain-correction study for the linearized `se3` beam (planar bending).

Linearized about the straight configuration, phmech's `se3` beam (N constant-strain SE(3)
elements, lumped nodal inertia) is the linear Timoshenko element with linear interpolation and
one-point (reduced) integration.  Per element, DOFs (w1, phi1, w2, phi2):

    gamma = (w2 - w1)/h - (phi1 + phi2)/2,   kappa = (phi2 - phi1)/h,
    V_e   = h/2 (kGA' gamma^2 + EI kappa^2),   1/kGA' = 1/kGA + beta h^2/EI  (beta = 0: phmech).

Mass treatments (per element, w and phi blocks; alpha = weight of the consistent matrix):

    M_w   = rhoA h [(1 - alpha_w) diag(1/2, 1/2) + alpha_w [[1/3, 1/6], [1/6, 1/3]]]
    M_phi = rhoI h [ same with alpha_phi ]
    "helix": consistent mass of the element's own kinematics, i.e. the linearization of the
             constant-strain pose field H(s) = H_k exp(s X / h):
             w(xi) = (1-xi) w1 + xi w2 + (h/2) xi (1-xi) (phi1 - phi2),  phi linear.
    "helix_avg": helix mass + (lumped - consistent)/2 (both w and phi blocks).

Reference: phmech.timoshenko.frequencies (exact), cantilever clamped at s = 0.

Second part (rigid_inertia_study, docs/mass_matrix_study.md "Exact rigid inertia with c = 0"):
d6 against d6 + the link-level subtraction and the helix mass + a strain-difference stiffness
(beta = 1/12) with several end rules: Bloch c, clamped-free / clamped-clamped / free-free
frequencies at N = 4 ... 100, cantilever statics, rigid-motion checks.
Third part (transient_proxy, "The released cantilever, linearized"): each treatment's mesh
error on the linearized transient of benchmarks/run.py, exact in time.
A Bloch-wave (infinite lattice) dispersion check measures the leading error coefficient
c in  omega_h/omega - 1 = c theta^2 + O(theta^4),  theta = k h, for several (a, b).

Run:  .venv/bin/python benchmarks/mass_matrix_study.py
Writes benchmarks/results/mass_matrix_study.json, the full study that docs/mass_matrix_study.md
reports (``--quick`` runs the same study: it is short); ``--smoke`` writes
mass_matrix_study_smoke.json, never the full run's file.
"""
from __future__ import annotations

import json
import math
import os
import pathlib

import numpy as np
from scipy.linalg import eigh
from scipy.optimize import minimize_scalar

from phmech.timoshenko import frequencies as exact_frequencies

NS = (9, 21, 50, 100)
NMODES = 5

# Beams: (name, L, EI, kGA, rhoA, rhoI).  a = EI/(kGA L^2), b = rhoI/(rhoA L^2).
BEAMS = {
    "tableI":  (1.0, 5143.0, 656625.0, 873.0, 2.1797),          # a = 7.83e-3, b = 2.50e-3
    "slender": (1.0, 5143.0, 656625.0 * 100, 873.0, 2.1797 / 100),  # a, b 100x smaller
    "thick":   (1.0, 5143.0, 656625.0 / 3, 873.0, 2.1797 * 3),    # a, b 3x larger
}

# Treatments: name -> (alpha_w, alpha_phi, beta, helix, rationale)
TREATMENTS = {
    "a_lumped": (0.0, 0.0, 0.0, False, "phmech today: half-share lumped inertia"),
    "b_consistent": (1.0, 1.0, 0.0, False, "consistent mass of linear interpolation"),
    "c_average": (0.5, 0.5, 0.0, False, "average lumped/consistent (4th order for a wave eq.)"),
    "d1_rotary_consistent": (0.0, 1.0, 0.0, False, "translational lumped, rotary consistent"),
    "d2_lumped_rbf": (0.0, 0.0, 1.0 / 12, False,
                      "lumped + MacNeal residual bending flexibility 1/kGA' = 1/kGA + h^2/(12 EI)"),
    "d3_average_2rbf": (0.5, 0.5, 1.0 / 6, False,
                        "average mass + 1/kGA' = 1/kGA + h^2/(6 EI): rotary-free dispersion 4th order"),
    "d4_helix": (None, None, 0.0, True, "consistent mass of the constant-strain (helicoidal) field"),
    "d5_helix_rbf": (None, None, 1.0 / 12, True, "helix mass + MacNeal correction"),
    "d6_helix_avg": (None, None, 0.0, "avg",
                     "helix mass + (lumped - consistent)/2: cancels the helix mass's uniform "
                     "theta^2/24 dispersion error for every (a, b)"),
}


def element_matrices(h, EI, kGA, rhoA, rhoI, alpha_w, alpha_phi, beta, helix):
    kGAe = 1.0 / (1.0 / kGA + beta * h * h / EI)
    bg = np.array([-1.0 / h, -0.5, 1.0 / h, -0.5])
    bk = np.array([0.0, -1.0 / h, 0.0, 1.0 / h])
    K = h * (kGAe * np.outer(bg, bg) + EI * np.outer(bk, bk))
    if helix == "avg":
        # M_helix + (M_lumped - M_consistent)/2 = M_helix + h/12 (rhoA [[1,-1],[-1,1]] on w,
        # rhoI [[1,-1],[-1,1]] on phi): positive definite (adds a PSD term).
        _, Mh = element_matrices(h, EI, kGA, rhoA, rhoI, None, None, beta, True)
        d = np.array([[1.0, -1.0], [-1.0, 1.0]]) * h / 12.0
        Mh[np.ix_([0, 2], [0, 2])] += rhoA * d
        Mh[np.ix_([1, 3], [1, 3])] += rhoI * d
        return K, Mh
    if helix:
        xg, wg = np.polynomial.legendre.leggauss(4)
        xg, wg = 0.5 * (xg + 1.0), 0.5 * wg
        M = np.zeros((4, 4))
        for x, wt in zip(xg, wg):
            nw = np.array([1 - x, 0.5 * h * x * (1 - x), x, -0.5 * h * x * (1 - x)])
            nphi = np.array([0.0, 1 - x, 0.0, x])
            M += h * wt * (rhoA * np.outer(nw, nw) + rhoI * np.outer(nphi, nphi))
        return K, M
    lump = np.diag([0.5, 0.5])
    cons = np.array([[1.0, 0.5], [0.5, 1.0]]) / 3.0
    mw = rhoA * h * ((1 - alpha_w) * lump + alpha_w * cons)
    mp = rhoI * h * ((1 - alpha_phi) * lump + alpha_phi * cons)
    M = np.zeros((4, 4))
    M[np.ix_([0, 2], [0, 2])] = mw
    M[np.ix_([1, 3], [1, 3])] = mp
    return K, M


def fe_frequencies(N, beam, treat, nmodes=NMODES):
    L, EI, kGA, rhoA, rhoI = beam
    aw, ap, beta, helix = treat[:4]
    h = L / N
    nd = 2 * (N + 1)
    K = np.zeros((nd, nd))
    M = np.zeros((nd, nd))
    Ke, Me = element_matrices(h, EI, kGA, rhoA, rhoI, aw, ap, beta, helix)
    for e in range(N):
        idx = slice(2 * e, 2 * e + 4)
        K[idx, idx] += Ke
        M[idx, idx] += Me
    free = slice(2, nd)  # clamped at s = 0
    lam = eigh(K[free, free], M[free, free], eigvals_only=True, subset_by_index=[0, nmodes - 1])
    return np.sqrt(lam)


def errors(beam, treat, ref):
    out = {}
    for N in NS:
        out[N] = (fe_frequencies(N, beam, treat) / ref - 1.0) * 100.0
    return out


def orders(err):
    res = []
    for n1, n2 in zip(NS[:-1], NS[1:]):
        e1, e2 = np.abs(err[n1]), np.abs(err[n2])
        res.append(np.log(e1 / e2) / np.log(n2 / n1))
    return res


def dispersion_coefficient(treat, a, b, theta=0.02):
    """Leading coefficient c of omega_h/omega - 1 ~ c theta^2 on the lowest (bending) branch
    of the infinite uniform lattice (L = 1 scale: EI = 1, rhoA = 1, kGA = 1/a, rhoI = b),
    evaluated at a fixed physical wavenumber k = 3 with h = theta/k (Richardson on 2 thetas)."""
    k = 3.0

    def ratio(th):
        h = th / k
        Ke, Me = element_matrices(h, 1.0, 1.0 / a, 1.0, b, *treat[:4])
        # Bloch reduction: node j couples to j+1 with phase e^{i th}.
        T = np.zeros((4, 2), complex)
        T[0, 0] = T[1, 1] = 1.0
        T[2, 0] = T[3, 1] = np.exp(1j * th)
        Kb = T.conj().T @ Ke @ T
        Mb = T.conj().T @ Me @ T
        wd = np.sqrt(np.min(eigh(Kb, Mb, eigvals_only=True)))
        # continuum Timoshenko
        Kc = np.array([[k * k / a, -1j * k / a], [1j * k / a, 1.0 / a + k * k]])
        Mc = np.diag([1.0, b])
        wc = np.sqrt(np.min(eigh(Kc, Mc, eigvals_only=True)))
        return wd / wc - 1.0

    r1, r2 = ratio(theta), ratio(theta / 2)
    c1, c2 = r1 / theta**2, r2 / (theta / 2) ** 2
    return (4 * c2 - c1) / 3.0  # remove the theta^4 part


# -------------------------------------------------------------------------------------------------
# Exact rigid inertia with c = 0: a stiffness-side correction (issue 27, "rigid_inertia" entry)
# -------------------------------------------------------------------------------------------------
# d6's blend term (h/12) d^T Ms d is not zero for a rigid turn (d = omega h per element): the link
# gets rhoA L h^2/12 too much rotational inertia.  "d6_link" is the link-level fix (subtract
# (h/(12 N)) rhoA (v_N - v_0)^2 on the end nodes' transverse velocities: rigid motion exact, but
# the mean of the d_e loses its correction).  The alternative measured here keeps the helix mass
# (exact for rigid motion) and moves the dispersion correction to the stiffness, as a term that
# vanishes for rigid motion AND for uniform strain:
#
#     V = sum_e h/2 eps_e^T C eps_e - beta h/2 [ sum_(e=0..N-2) (eps_(e+1) - eps_e)^T C (eps_(e+1) - eps_e)
#                                              + (s_0 - 1) eps_0^T C eps_0 + (s_1 - 1) eps_(N-1)^T C eps_(N-1) ],
#
# i.e. the strain-space stiffness C (x) (I - beta A_s), A_s the 1-D Laplacian whose two corner
# entries are s_0, s_1 (any s keeps it symmetric: only the diagonal corners differ).  A Bloch wave
# multiplies the stiffness symbol by 1 - 4 beta sin^2(theta/2) ~ 1 - beta theta^2, and the helix
# mass multiplies omega^2 by 1 + theta^2/12 for every (a, b): beta = 1/12 gives c = 0.
# End rules s (the strain "ghost" beyond the end): 1 "none" (only the interior pairs; a mirrored
# ghost eps_(-1) = eps_0 gives the same), 0 "off" (the end element's own term removed), 2 "zero"
# (ghost eps_(-1) = 0), 3 "antisym" (ghost eps_(-1) = -eps_0: the stress through zero at the end,
# a free end's).  Only s = 1 keeps A_s 1 = 0, i.e. the patch test (a uniform strain is uniform).
# A second end parameter that keeps it: the weight w of the end pair ((eps_1 - eps_0) counted w
# times; w = 2 is the energy of a linearly extrapolated ghost, w = 0 drops the end elements).
# END_RULES: name -> (s, w).
BETA = 1.0 / 12.0
END_RULES = {"none": (1.0, 1.0), "off": (0.0, 1.0), "zero": (2.0, 1.0), "antisym": (3.0, 1.0),
             "drop": (1.0, 0.0), "pair4/3": (1.0, 4.0 / 3.0), "pair1.5": (1.0, 1.5)}
NS_R = (4, 10, 21, 50, 100)
NS_STATIC = (1, 2, 4, 10, 21)
BCS = ("clamped-free", "clamped-clamped", "free-free")

# name -> (mass, beta, end rule at a clamped end, end rule at a free end, link-level fix, rationale)
RIGID_TREATMENTS = {
    "d4_helix": ("helix", 0.0, "none", "none", False, "helix mass alone: rigid-exact, c = +1/24"),
    "d6": ("d6", 0.0, "none", "none", False, "phmech's consistent mass: helix + (h/12) d^T Ms d"),
    "d6_link": ("d6", 0.0, "none", "none", True,
                "d6 - (h/(12N)) rhoA (v_N - v_0)^2: the link-level fix (branch inertia)"),
    "d7_helix_strainrate": ("helix_rate", 0.0, "none", "none", False,
                            "control: helix + (h/12) (h de/dt)^T Ms (h de/dt), the rigid-invariant "
                            "(transported) form of d6's term"),
    "e1_none": ("helix", BETA, "none", "none", False,
                "helix + strain-difference stiffness, interior pairs only (s = 1 both ends)"),
    "e1_off": ("helix", BETA, "off", "off", False, "as e1, the end elements' own terms removed (s = 0)"),
    "e1_zero": ("helix", BETA, "zero", "zero", False, "as e1, zero ghost strain beyond each end (s = 2)"),
    "e1_antisym": ("helix", BETA, "antisym", "antisym", False,
                   "as e1, antisymmetric ghost strain beyond each end (s = 3)"),
    "e1_free_antisym": ("helix", BETA, "none", "antisym", False,
                        "as e1, s = 1 at a clamped end, s = 3 at a free end (by support)"),
    "e1_drop": ("helix", BETA, "drop", "drop", False,
                "as e1, the end pairs dropped (w = 0): end elements uncorrected"),
    "e2_pair4/3": ("helix", BETA, "pair4/3", "pair4/3", False,
                   "as e1, the end pairs weighted w = 4/3 (patch test kept; w* measured 1.31-1.34 for "
                   "mode 1 on every beam and support, N = 60: it nearly cancels the ends' h^3 term)"),
    "e2_pair1.5": ("helix", BETA, "pair1.5", "pair1.5", False,
                   "as e1, the end pairs weighted w = 1.5 (patch test kept; better on modes 3-5 at N = 21)"),
}


def strain_operator(N: int, h: float) -> np.ndarray:
    """B (2N x 2(N+1)): the element strains (gamma_e, kappa_e) [-, 1/m] of the nodal (w, phi) [m, rad]."""
    B = np.zeros((2 * N, 2 * N + 2))
    for e in range(N):
        B[2 * e, 2 * e:2 * e + 4] = (-1.0 / h, -0.5, 1.0 / h, -0.5)
        B[2 * e + 1, 2 * e + 1] = -1.0 / h
        B[2 * e + 1, 2 * e + 3] = 1.0 / h
    return B


def strain_smoothing(N: int, beta: float, end0=(1.0, 1.0), end1=(1.0, 1.0)) -> np.ndarray:
    """I - beta A (N x N): A the Laplacian of the interior strain differences, each end's pair
    weighted w and its corner moved by s - 1 (end = (s, w); (1, 1): the plain interior pairs)."""
    A = np.zeros((N, N))
    for e in range(N - 1):
        w = 1.0
        if e == 0 or e == N - 2:
            w = 0.5 * (end0[1] + end1[1]) if N == 2 else (end0[1] if e == 0 else end1[1])
        A[e:e + 2, e:e + 2] += w * np.array([[1.0, -1.0], [-1.0, 1.0]])
    A[0, 0] += end0[0] - 1.0
    A[N - 1, N - 1] += end1[0] - 1.0
    return np.eye(N) - beta * A


def assemble(N: int, beam: tuple, treat: tuple,
             supports: tuple = ("clamped", "free")) -> tuple[np.ndarray, np.ndarray]:
    """Global K [N/m, N, N m] and M [kg, kg m, kg m^2] (dofs w_0 [m], phi_0 [rad], ..., w_N, phi_N)
    of a RIGID_TREATMENTS entry; the end rules follow the supports (start, end) of the beam."""
    L, EI, kGA, rhoA, rhoI = beam
    mass, beta, s_clamped, s_free, link_fix = treat[:5]
    h = L / N
    rule = {"clamped": END_RULES[s_clamped], "free": END_RULES[s_free]}
    B = strain_operator(N, h)
    K = h * B.T @ np.kron(strain_smoothing(N, beta, rule[supports[0]], rule[supports[1]]),
                          np.diag([kGA, EI])) @ B
    Me = element_mass(h, beam, mass)
    M = np.zeros_like(K)
    for e in range(N):
        M[2 * e:2 * e + 4, 2 * e:2 * e + 4] += Me
    if link_fix:
        c = rhoA * h / (12.0 * N)
        M[np.ix_([0, 2 * N], [0, 2 * N])] -= c * np.array([[1.0, -1.0], [-1.0, 1.0]])
    return K, M


def element_mass(h: float, beam: tuple, mass: str) -> np.ndarray:
    """Element mass (4x4, dofs w1, phi1, w2, phi2) of "helix", "d6", "helix_rate" or "lumped"."""
    L, EI, kGA, rhoA, rhoI = beam
    if mass == "lumped":   # phmech's mass="lumped": half of each element's inertia on each node
        return element_matrices(h, EI, kGA, rhoA, rhoI, 0.0, 0.0, 0.0, False)[1]
    _, Me = element_matrices(h, EI, kGA, rhoA, rhoI, None, None, 0.0, "avg" if mass == "d6" else True)
    if mass == "helix_rate":
        Be = strain_operator(1, h)  # (gamma, kappa) of the element; h Be v = the transported difference
        Me = Me + (h / 12.0) * (h * Be).T @ np.diag([rhoA, rhoI]) @ (h * Be)
    return Me


def bc_frequencies(N: int, beam: tuple, treat: tuple, bc: str, nmodes: int = NMODES) -> np.ndarray:
    """The first nmodes non-zero frequencies [rad/s] of the beam under bc (free-free: after the
    two rigid modes)."""
    sup = {"clamped-free": ("clamped", "free"), "clamped-clamped": ("clamped", "clamped"),
           "free-free": ("free", "free")}[bc]
    K, M = assemble(N, beam, treat, sup)
    n = 2 * N + 2
    keep = {"clamped-free": range(2, n), "clamped-clamped": range(2, n - 2), "free-free": range(n)}[bc]
    skip = 2 if bc == "free-free" else 0
    keep = list(keep)
    lam = eigh(K[np.ix_(keep, keep)], M[np.ix_(keep, keep)], eigvals_only=True,
               subset_by_index=[0, skip + nmodes - 1])
    return np.sqrt(np.abs(lam[skip:]))


def bloch_error(treat: tuple, a: float, b: float, theta: float) -> float:
    """omega_h/omega - 1 on the bending branch of the infinite lattice at theta = k h (k = 3; L = 1
    scale: EI = 1, rhoA = 1, kGA = 1/a, rhoI = b) for a RIGID_TREATMENTS entry: the strain
    differences multiply the stiffness symbol by 1 - 4 beta sin^2(theta/2); the link-level fix is
    O(1/N), nothing on the infinite lattice."""
    k = 3.0
    h = theta / k
    Ke, _ = element_matrices(h, 1.0, 1.0 / a, 1.0, b, 0.0, 0.0, 0.0, False)
    Me = element_mass(h, (1.0, 1.0, 1.0 / a, 1.0, b), treat[0])
    T = np.zeros((4, 2), complex)
    T[0, 0] = T[1, 1] = 1.0
    T[2, 0] = T[3, 1] = np.exp(1j * theta)
    Kb = T.conj().T @ Ke @ T * (1.0 - 4.0 * treat[1] * math.sin(theta / 2) ** 2)
    wd = np.sqrt(np.min(eigh(Kb, T.conj().T @ Me @ T, eigvals_only=True)))
    Kc = np.array([[k * k / a, -1j * k / a], [1j * k / a, 1.0 / a + k * k]])
    wc = np.sqrt(np.min(eigh(Kc, np.diag([1.0, b]), eigvals_only=True)))
    return wd / wc - 1.0


def dispersion_coefficient_r(treat: tuple, a: float, b: float, theta: float = 0.02) -> float:
    """c of omega_h/omega - 1 ~ c theta^2 (as dispersion_coefficient: Richardson on 2 thetas)."""
    c1 = bloch_error(treat, a, b, theta) / theta**2
    c2 = bloch_error(treat, a, b, theta / 2) / (theta / 2) ** 2
    return (4 * c2 - c1) / 3.0


def cantilever_statics(N: int, beam: tuple, treat: tuple, load: str) -> tuple[float, float]:
    """Relative errors (tip deflection, tip rotation) of the cantilever clamped at s = 0 under a unit
    tip force ("tip_force"), tip moment ("tip_moment"), force at node N // 2 ("mid_force") or uniform
    load on lumped nodal shares ("uniform", phmech's gravity: node masses) or consistent with the
    helix field ("uniform_helix": the same plus end moments +-h^2/12 per unit load), against the
    exact Timoshenko solution."""
    L, EI, kGA, rhoA, rhoI = beam
    K, _ = assemble(N, beam, treat, ("clamped", "free"))
    h, n = L / N, 2 * N + 2
    f = np.zeros(n)
    if load == "tip_force":
        f[2 * N] = 1.0
        exact = (L**3 / (3 * EI) + L / kGA, L**2 / (2 * EI))
    elif load == "tip_moment":
        f[2 * N + 1] = 1.0
        exact = (L**2 / (2 * EI), L / EI)
    elif load == "mid_force":  # at node N // 2: a jump of the shear inside the link
        a = (N // 2) * h
        f[2 * (N // 2)] = 1.0
        exact = (a * a * (3 * L - a) / (6 * EI) + a / kGA, a * a / (2 * EI))
    else:
        f[0::2] = h
        f[0] = f[2 * N] = h / 2
        if load == "uniform_helix":  # the load consistent with the helix field: end moments +-h^2/12
            f[1], f[2 * N + 1] = h * h / 12, -h * h / 12
        exact = (L**4 / (8 * EI) + L**2 / (2 * kGA), L**3 / (6 * EI))
    u = np.zeros(n)
    u[2:] = np.linalg.solve(K[2:, 2:], f[2:])
    return u[2 * N] / exact[0] - 1.0, u[2 * N + 1] / exact[1] - 1.0


def rigid_checks(N: int, beam: tuple, treat: tuple) -> dict:
    """Rigid-motion exactness: relative excess of the kinetic energy of a unit translation and of a
    unit turn about s = 0 and about the middle (exact: rhoA L, rhoA L^3/3 + rhoI L, rhoA L^3/12 + rhoI L),
    and max |K v| of the rigid motions over the stiffness scale (free-free)."""
    L, EI, kGA, rhoA, rhoI = beam
    K, M = assemble(N, beam, treat, ("free", "free"))
    x = np.linspace(0.0, L, N + 1)
    out = {}
    for name, v, ex in (("translation", np.ravel(np.column_stack([np.ones(N + 1), np.zeros(N + 1)])), rhoA * L),
                        ("turn_about_end", np.ravel(np.column_stack([x, np.ones(N + 1)])),
                         rhoA * L**3 / 3 + rhoI * L),
                        ("turn_about_middle", np.ravel(np.column_stack([x - L / 2, np.ones(N + 1)])),
                         rhoA * L**3 / 12 + rhoI * L)):
        out[name] = float(v @ M @ v / ex - 1.0)
        out[name + "_Kv"] = float(np.max(np.abs(K @ v)) / np.max(np.abs(K)))
    return out


def rigid_inertia_study(smoke: bool) -> dict:
    """The measured comparison of the treatments of RIGID_TREATMENTS (section "Exact rigid inertia
    with c = 0" of docs/mass_matrix_study.md)."""
    ns = (4, 10) if smoke else NS_R
    beams = {"tableI": BEAMS["tableI"]} if smoke else BEAMS
    names = ("d6", "d6_link", "e1_none", "e2_pair4/3") if smoke else tuple(RIGID_TREATMENTS)
    treats = {k: RIGID_TREATMENTS[k] for k in names}
    res = {"description": "helix mass + strain-difference stiffness (beta = 1/12) vs d6 and d6 + the "
                          "link-level subtraction; errors in percent, static errors relative",
           "beta": BETA, "end_rules_s_w": END_RULES, "N": list(ns), "N_static": list(NS_STATIC),
           "treatments": {k: {"mass": t[0], "beta": t[1], "clamped_end": t[2], "free_end": t[3],
                              "link_fix": t[4], "rationale": t[5]} for k, t in treats.items()},
           "dispersion": {}, "bloch_theta4": {}, "frequencies": {}, "statics": {}, "rigid": {}}
    cases = [(1e-6, 1e-6), (1e-6, 0.1), (0.1, 1e-6), (0.1, 0.1), (1.0, 1.0), (0.01, 0.003)]
    print("\n=== exact rigid inertia with c = 0 ===\nBloch c (theta^2 coefficient) at (a, b):")
    print(f"{'':22s}" + " ".join(f"a={a:.0e},b={b:.0e}" for a, b in cases))
    for tname, t in treats.items():
        cs = [dispersion_coefficient_r(t, a, b) for a, b in cases]
        res["dispersion"][tname] = {f"a={a},b={b}": c for (a, b), c in zip(cases, cs)}
        res["bloch_theta4"][tname] = {f"theta={th}": 100 * bloch_error(t, 0.0078, 0.0025, th)
                                      for th in (0.5, 1.0, 1.5)}
        print(f"{tname:22s}" + " ".join(f"{c:+15.5f}" for c in cs)
              + "  | Table I err % at theta .5/1/1.5: "
              + " ".join(f"{x:+.3f}" for x in res["bloch_theta4"][tname].values()))
    for bname, beam in beams.items():
        L, EI, kGA, rhoA, rhoI = beam
        res["frequencies"][bname] = {}
        for bc in (("clamped-free",) if smoke else BCS):
            ref = exact_frequencies(NMODES, L, EI, kGA, rhoA, rhoI, bc=bc)
            rb = res["frequencies"][bname][bc] = {"exact_rad_s": ref.tolist(), "treatments": {}}
            print(f"\n{bname} {bc}: errors % (N = " + ", ".join(map(str, ns)) + "), order of the last pair")
            for tname, t in treats.items():
                err = {N: (bc_frequencies(N, beam, t, bc) / ref - 1.0) * 100.0 for N in ns}
                od = {f"{n1}-{n2}": (np.log(np.abs(err[n1]) / np.abs(err[n2])) / np.log(n2 / n1)).tolist()
                      for n1, n2 in zip(ns[:-1], ns[1:])}
                rb["treatments"][tname] = {"errors_percent": {str(N): err[N].tolist() for N in ns},
                                           "orders": od,
                                           "max_abs_percent": {str(N): float(np.max(np.abs(err[N]))) for N in ns}}
                for N in ns:
                    if N in (4, 10, 21) or N == ns[-1]:
                        print(f"  {tname:20s} N={N:3d}: " + " ".join(f"{x:+8.3f}" for x in err[N])
                              + (f"  order {ns[-2]}->{ns[-1]}: " + " ".join(f"{x:4.1f}" for x in od[list(od)[-1]])
                                 if N == ns[-1] else ""))
    beam = BEAMS["tableI"]
    print("\nTable I cantilever statics: relative errors (tip deflection, tip rotation)")
    for tname, t in treats.items():
        res["statics"][tname] = {}
        for load in ("tip_force", "tip_moment", "mid_force", "uniform", "uniform_helix"):
            e = {N: cantilever_statics(N, beam, t, load) for N in NS_STATIC if N >= 2 or load != "mid_force"}
            res["statics"][tname][load] = {str(N): list(v) for N, v in e.items()}
            print(f"  {tname:20s} {load:10s} "
                  + "  ".join(f"N={N}: {v[0]:+.2e} {v[1]:+.2e}" for N, v in e.items()))
        res["rigid"][tname] = {str(N): rigid_checks(N, beam, t) for N in (1, 2, 4, 10)}
        # the strain-space stiffness I - beta A stays positive definite: its smallest eigenvalue
        res["rigid"][tname]["min_eig_strain_stiffness_N100"] = float(np.min(np.linalg.eigvalsh(
            strain_smoothing(100, t[1], END_RULES[t[2]], END_RULES[t[3]]))))
    print("\nRigid motion (Table I): relative excess of the turn-about-end inertia at N = 1, 2, 4, 10; "
          "max |K v_rigid|/max|K|")
    for tname in treats:
        r = res["rigid"][tname]
        print(f"  {tname:20s} " + " ".join(f"{r[str(N)]['turn_about_end']:+.2e}" for N in (1, 2, 4, 10))
              + f"   translation {r['10']['translation']:+.1e}   Kv "
              + f"{max(v for n in ('1', '2', '4', '10') for k, v in r[n].items() if k.endswith('_Kv')):.1e}"
              + f"   min eig(I - beta A), N = 100: {r['min_eig_strain_stiffness_N100']:.3f}")
    return res


# -------------------------------------------------------------------------------------------------
# The released cantilever, linearized: what each treatment's mesh error is on benchmarks/run.py's
# transient (docs/mass_matrix_study.md, "The released cantilever, linearized")
# -------------------------------------------------------------------------------------------------
#: benchmarks/run.py's transient: the Table I cantilever held by a tip force 0.75 EI / L^2 and
#: released, its tip sampled every 5 ms over 1 s; its error levels [L]
PROXY_FORCE, PROXY_T, PROXY_DT = 0.75 * BEAMS["tableI"][1], 1.0, 0.005
PROXY_LEVELS = (1e-2, 3e-3, 1e-3, 3e-4)
PROXY_N = (3, 4, 5, 6, 8, 10, 14, 20, 28, 40, 56, 80)
PROXY_TREATMENTS = {"lumped": ("lumped", 0.0, "none", "none", False, "phmech's mass='lumped'"),
                    **{k: RIGID_TREATMENTS[k] for k in ("d6", "d6_link", "e2_pair4/3")}}


def released_tip(N: int, treat: tuple, t: np.ndarray) -> np.ndarray:
    """Tip deflection w(t) [m] of the linear cantilever (mesh N, treatment ``treat`` of
    RIGID_TREATMENTS' form) released at t = 0 from its static deflection under PROXY_FORCE at
    the tip: exact in time (modal superposition), so the mesh's error alone."""
    K, M = assemble(N, BEAMS["tableI"], treat)
    free = list(range(2, 2 * N + 2))
    K, M = K[np.ix_(free, free)], M[np.ix_(free, free)]
    f = np.zeros(len(free))
    f[-2] = PROXY_FORCE
    lam, V = eigh(K, M)
    q0 = V.T @ (M @ np.linalg.solve(K, f))   # modal coordinates of the static deflection
    return np.cos(np.outer(t, np.sqrt(lam))) @ (V[-2] * q0)


def transient_proxy(smoke: bool) -> dict:
    """Each treatment's largest tip error [L] over the released cantilever's 1 s against a fine
    mesh (N = 400, e2; checked against d6_link's N = 400), and the smallest N reaching each of
    benchmarks/run.py's error levels. Its calibration, the nonlinear run's errors at the same N,
    is in benchmarks/results/bench_transient.json (docs/mass_matrix_study.md)."""
    t = np.arange(0.0, PROXY_T + 1e-12, PROXY_DT)
    L = BEAMS["tableI"][0]
    nref = 100 if smoke else 400
    ref = released_tip(nref, RIGID_TREATMENTS["e2_pair4/3"], t)
    check = float(np.max(np.abs(released_tip(nref, RIGID_TREATMENTS["d6_link"], t) - ref)) / L)
    ns = (3, 4, 10) if smoke else PROXY_N
    out = {"problem": "linear Table I cantilever released from its static deflection under a tip "
                      f"force {PROXY_FORCE:g} N, tip every {PROXY_DT} s over {PROXY_T} s, exact in time",
           "error": "max_t |w_tip - w_tip_ref| / L", "reference_N": nref,
           "reference_check_d6_link_vs_e2": check, "N": list(ns), "errors": {}, "smallest_N": {}}
    print(f"\n=== the released cantilever, linearized: tip error / L against N = {nref} "
          f"(d6_link there: {check:.1e}) ===")
    for name, treat in PROXY_TREATMENTS.items():
        err = {N: float(np.max(np.abs(released_tip(N, treat, t) - ref)) / L) for N in ns}
        out["errors"][name] = {str(N): e for N, e in err.items()}
        out["smallest_N"][name] = {f"{lv:.0e}": next((N for N in ns if err[N] <= lv), None)
                                   for lv in PROXY_LEVELS}
        print(f"  {name:12s} " + " ".join(f"N={N}: {e:.2e}" for N, e in err.items()))
        print(f"  {'':12s} smallest N at " + ", ".join(f"{k} L: {v}" for k, v in out["smallest_N"][name].items()))
    return out


def main():
    import argparse
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="accepted for make bench (the study is short)")
    ap.add_argument("--smoke", action="store_true",
                    help="one beam, meshes 9 and 21; the rigid-inertia part on the cantilever at "
                         "N = 4 and 10, four treatments (tests/test_benchmarks_smoke.py)")
    a = ap.parse_args()
    global NS, BEAMS
    if a.smoke:
        NS, BEAMS = (9, 21), {"tableI": BEAMS["tableI"]}
    results = {"description": __doc__.split("\n\n")[0], "N": list(NS), "beams": {}, "dispersion": {}}
    for bname, beam in BEAMS.items():
        L, EI, kGA, rhoA, rhoI = beam
        ref = exact_frequencies(NMODES, L, EI, kGA, rhoA, rhoI, bc="clamped-free")
        # independent sanity check of the reference: a fine consistent-mass mesh converges to it
        fine = fe_frequencies(100 if a.smoke else 1000, beam, TREATMENTS["c_average"])
        bres = {"params": dict(L=L, EI=EI, kGA=kGA, rhoA=rhoA, rhoI=rhoI,
                               a=EI / (kGA * L * L), b=rhoI / (rhoA * L * L)),
                "exact_rad_s": ref.tolist(),
                "fine_mesh_check_rel": (fine / ref - 1.0).tolist(),
                "treatments": {}}
        print(f"\n=== {bname}: a = {EI/(kGA*L*L):.3e}, b = {rhoI/(rhoA*L*L):.3e}; exact [rad/s] "
              + " ".join(f"{x:.4f}" for x in ref)
              + f"; N=1000 check max rel {np.max(np.abs(fine/ref-1)):.1e}")
        for tname, treat in TREATMENTS.items():
            err = errors(beam, treat, ref)
            od = orders(err)
            bres["treatments"][tname] = {
                "errors_percent": {str(N): err[N].tolist() for N in NS},
                "orders": {f"{n1}-{n2}": o.tolist() for (n1, n2), o in zip(zip(NS[:-1], NS[1:]), od)},
                "max_abs_error_N21_percent": float(np.max(np.abs(err[21]))),
            }
            print(f"{tname:22s} N=21: " + " ".join(f"{x:+7.3f}" for x in err[21])
                  + f"  | max {np.max(np.abs(err[21])):.3f}%  | order (finest pair): "
                  + " ".join(f"{x:4.2f}" for x in od[-1]))
        # optimal single blend weight (alpha_w = alpha_phi = alpha), minimising max |err| at N = 21
        def obj(al):
            return float(np.max(np.abs(fe_frequencies(21, beam, (al, al, 0.0, False)) / ref - 1)))
        opt = minimize_scalar(obj, bounds=(-1.0, 1.5), method="bounded", options={"xatol": 1e-4})
        err_opt = errors(beam, (opt.x, opt.x, 0.0, False), ref)
        bres["optimal_blend"] = {"alpha": float(opt.x), "note": "TUNED to this beam at N=21",
                                 "errors_percent": {str(N): err_opt[N].tolist() for N in NS}}
        print(f"{'optimal blend a='+format(opt.x, '.3f'):22s} N=21: "
              + " ".join(f"{x:+7.3f}" for x in err_opt[21]) + "  (tuned)")
        results["beams"][bname] = bres

    print("\nBloch dispersion: omega_h/omega - 1 = c theta^2, c at (a, b) [k L = 3]")
    cases = [(1e-6, 1e-6), (1e-6, 0.1), (0.1, 1e-6), (0.1, 0.1), (1.0, 1.0), (0.01, 0.003)]
    print(f"{'':22s}" + " ".join(f"a={a:.0e},b={b:.0e}" for a, b in cases))
    for tname, treat in TREATMENTS.items():
        cs = [dispersion_coefficient(treat, a, b) for a, b in cases]
        results["dispersion"][tname] = {f"a={a},b={b}": c for (a, b), c in zip(cases, cs)}
        print(f"{tname:22s}" + " ".join(f"{c:+15.5f}" for c in cs))
    results["rigid_inertia"] = rigid_inertia_study(a.smoke)
    results["transient_proxy"] = transient_proxy(a.smoke)

    # the smoke's coarse meshes into their own file: the full run's is the one the docs report
    out = pathlib.Path(os.environ.get("BENCH_RESULTS") or pathlib.Path(__file__).resolve().parent / "results") \
        / ("mass_matrix_study_smoke.json" if a.smoke else "mass_matrix_study.json")
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps(results, indent=1))
    print(f"\nwrote {out}")


if __name__ == "__main__":
    main()

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
A Bloch-wave (infinite lattice) dispersion check measures the leading error coefficient
c in  omega_h/omega - 1 = c theta^2 + O(theta^4),  theta = k h, for several (a, b).

Run:  .venv/bin/python benchmarks/mass_matrix_study.py
Writes benchmarks/results/mass_matrix_study.json
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


def main():
    import argparse
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="accepted for make bench (the study is short)")
    ap.add_argument("--smoke", action="store_true", help="one beam, meshes 9 and 21 (tests/test_benchmarks_smoke.py)")
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

    out = pathlib.Path(os.environ.get("BENCH_RESULTS") or pathlib.Path(__file__).resolve().parent / "results") \
        / "mass_matrix_study.json"
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps(results, indent=1))
    print(f"\nwrote {out}")


if __name__ == "__main__":
    main()

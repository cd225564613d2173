"""Leaf-spring mechanism (paper Sec. VIII-D): frequency error against CPU time (GitHub issue 6).

    python benchmarks/bench_leaf_spring.py [--quick]

The model is ``examples/leaf_spring.py``'s :func:`build` (two steel leaves, stage R1, default
parameters, beta = 1e-5 s, a 0.05 N s rectangular pulse of 10 ms at t = 0.1 s on R1).

1. Reference: the first linearized frequency (``Mechanism.modes``) at N = 20, 40, 80 (, 160)
   elements per leaf, Richardson-extrapolated with the second-order rate (the observed order is
   stored); f_ref is the extrapolation from the two finest meshes.
2. FFT route: for N x rtol (IDA, KLU, default atol = rtol/100) simulate the pulse response to
   T_END and take ``phmech.analysis.dominant_frequency`` of R1's x over t >= T_FFT (the example's
   estimator and window start; the band is 0.3..3 x the paper's formula frequency instead of the
   modal frequency, so that the route needs no eigenvalue solve). CPU = build + simulate.
   Error = |f_fft - f_ref| / f_ref; also |f_fft - f_modal(N)| / f_modal(N) (time integration +
   FFT + amplitude effects alone).
3. Modal route: build + ``modes(1)`` at each N (median CPU of 3), error against f_ref.
4. FFT floor: the same estimator on synthetic sines of known frequency with the same sampling,
   window and length (frequencies around f_ref, several phases, with and without the model's
   damping).
5. If ``Mechanism.simulate`` accepts ``error_test``, the FFT sweep again with
   ``error_test="configuration"``.
6. If ``Mechanism.simulate`` accepts ``integrator``, the FFT route with the fixed-step
   ``integrator="generalized-alpha"`` (rho_inf = GA_RHO, Newton rtol = GA_RTOL): N x step h
   (h divides DT_OUT, so the output stays uniform for the FFT; every output is a step).

Writes benchmarks/results/bench_leaf_spring.{json,png}. CPU time is ``time.process_time``.
"""
from __future__ import annotations

import argparse
import inspect
import math
import os
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(os.path.dirname(HERE), "examples"))

import phmech as ph  # noqa: E402
import leaf_spring as ls  # noqa: E402
from run import RESULTS, cpu_at_error, cpu_median, machine, pareto, write_json  # noqa: E402

T_END = 6.0          # simulated time [s]
T_FFT = 2.0          # FFT window start [s] (as the example)
DT_OUT = 2e-3        # output sampling [s] (as the example)
IMPULSE, DURATION, T0 = 0.05, 0.01, 0.1   # N s, s, s (as the example)
BETA = 1e-5          # material damping [s] (the example's default)
LEVELS = (1e-2, 1e-3, 1e-4)
MIN_AMPLITUDE_RATIO = 0.1
GA_RHO = 0.9         # generalized-alpha spectral radius at infinity (1.0: Newton fails, see the doc)
GA_RTOL = 1e-6       # generalized-alpha Newton tolerance


def band(p) -> tuple[float, float]:
    fa = ls.f_analytic(p)
    return 0.3 * fa, 3.0 * fa


# ------------------------------------------------------------------ reference
def _modal_f(p, N: int):
    def modal():
        m, _ = ls.build(p, elements=N, beta=BETA)
        return float(m.modes(1).frequency[0])
    return cpu_median(modal, 1 if N >= 80 else 3)


def reference(p, Ns, Ns_check) -> dict:
    """f_ref from the three meshes ``Ns`` (N, 2N, 4N); ``Ns_check``: further meshes whose
    (N, 2N) Richardson values, together with the extrapolation at the observed order, give the
    uncertainty."""
    pts = {}
    for N in sorted(set(Ns) | set(Ns_check)):
        f, cpu = _modal_f(p, N)
        pts[N] = dict(N=N, f_modal=f, cpu_s=cpu)
        print(f"reference modes N={N:4d}: f = {f:.9f} Hz, CPU {cpu:.3f} s", flush=True)
    f = {N: q["f_modal"] for N, q in pts.items()}
    triples = [(N, 2 * N, 4 * N) for N in sorted(f) if 2 * N in f and 4 * N in f]
    orders = [dict(N=list(t), order=math.log2((f[t[0]] - f[t[1]]) / (f[t[1]] - f[t[2]]))) for t in triples]
    rich = [dict(N_coarse=N, N_fine=2 * N, f=f[2 * N] + (f[2 * N] - f[N]) / 3.0)
            for N in sorted(f) if 2 * N in f]
    a, b, c = Ns
    p_obs = math.log2((f[a] - f[b]) / (f[b] - f[c]))
    f_ref = f[c] + (f[c] - f[b]) / 3.0
    f_obs = f[c] + (f[c] - f[b]) / (2 ** p_obs - 1)
    unc = max([abs(r["f"] - f_ref) for r in rich if r["N_coarse"] >= b] + [abs(f_obs - f_ref)])
    return dict(points=list(pts.values()), Ns_for_f_ref=list(Ns), observed_order=p_obs,
                observed_orders=orders, richardson_p2=rich, richardson_observed_order=f_obs,
                f_ref=f_ref, f_ref_uncertainty=unc, f_ref_rel_uncertainty=unc / f_ref,
                derivation=(f"f_ref = f_{c} + (f_{c} - f_{b}) / 3 (second-order Richardson); observed order "
                            f"log2((f_{a} - f_{b}) / (f_{b} - f_{c})); uncertainty = max |f_ref - x| over x = the "
                            f"Richardson values of the pairs (N, 2N) with N >= {b} and the extrapolation "
                            f"with the observed order"),
                f_analytic_paper=ls.f_analytic(p), f_euler_bernoulli=ls.f_euler_bernoulli(p))


# ------------------------------------------------------------------ FFT floor
def fft_floor(f_ref: float, zeta: float, p) -> dict:
    """Relative error of the estimator on x = sin(2 pi f t + phi) exp(-zeta 2 pi f t) sampled as the
    simulation output on [T_FFT, T_END]."""
    t = np.arange(0.0, T_END + 0.5 * DT_OUT, DT_OUT)
    sel = t >= T_FFT
    lo, hi = band(p)
    out = {}
    for name, z in (("undamped", 0.0), ("damped", zeta)):
        errs = []
        for f in f_ref * np.linspace(0.98, 1.02, 41):
            for phi in np.linspace(0.0, 2 * np.pi, 12, endpoint=False):
                x = 1e-3 * np.sin(2 * np.pi * f * t + phi) * np.exp(-z * 2 * np.pi * f * t)
                fe = ph.analysis.dominant_frequency(t[sel], x[sel], fmin=lo, fmax=hi)
                errs.append(abs(fe - f) / f)
        errs = np.array(errs)
        out[name] = dict(max_rel_error=float(errs.max()), median_rel_error=float(np.median(errs)),
                         zeta=z)
    out["window_s"] = T_END - T_FFT
    out["bin_width_hz"] = 1.0 / (T_END - T_FFT)
    out["padded_bin_width_hz"] = 1.0 / (16 * (T_END - T_FFT))
    out["test_frequencies"] = "f_ref x [0.98, 1.02], 41 values, 12 phases each, amplitude 1 mm"
    return out


# ------------------------------------------------------------------ sweep points
def fft_point(p, N: int, rtol: float, f_ref: float, f_modal_N: float, error_test=None,
              impulse: float = IMPULSE, step=None, rho_inf: float = GA_RHO) -> dict:
    """One simulation + FFT. ``step`` given: ``integrator="generalized-alpha"`` with that fixed
    step and ``rho_inf`` (``rtol`` is then its Newton tolerance); else IDA with ``error_test``."""
    lo, hi = band(p)
    c0 = time.process_time()
    pulse = ph.Pulse(t0=T0, duration=DURATION, value=impulse / DURATION)
    m, h = ls.build(p, elements=N, beta=BETA, pulse=pulse)
    c1 = time.process_time()
    kw = dict(integrator="ida", **({} if error_test is None else dict(error_test=error_test)))
    tag = dict(error_test=error_test or "all")
    if step is not None:
        kw = dict(integrator="generalized-alpha", step=step, rho_inf=rho_inf)
        tag = dict(integrator="generalized-alpha", step=step, rho_inf=rho_inf)
    try:
        res = m.simulate(t_end=T_END, dt_out=DT_OUT, rtol=rtol, linear_solver="klu", **kw)
    except Exception as e:  # noqa: BLE001 -- a failed point is a result too
        return dict(N=N, rtol=rtol, **tag, failed=f"{type(e).__name__}: {e}",
                    cpu_build_s=c1 - c0, cpu_s=time.process_time() - c0)
    c2 = time.process_time()
    x = res.poses[:, h["R1"].carrier, 0, 3]
    x = x - x[0]
    sel = res.t >= T_FFT
    f = ph.analysis.dominant_frequency(res.t[sel], x[sel], fmin=lo, fmax=hi)
    c3 = time.process_time()
    # stats hold numbers, strings, bools and None (e.g. "planar" of an IDA run)
    st = {k: (v if v is None or isinstance(v, (str, int)) else float(v)) for k, v in res.stats.items()}
    return dict(N=N, rtol=rtol, atol=rtol * 1e-2, **tag, impulse_Ns=impulse, f_fft=f,
                rel_error=abs(f - f_ref) / f_ref, signed_rel_error=(f - f_ref) / f_ref,
                f_modal_N=f_modal_N, rel_error_vs_modal_N=abs(f - f_modal_N) / f_modal_N,
                mesh_rel_error=abs(f_modal_N - f_ref) / f_ref,
                amplitude_m=float(np.abs(x[sel]).max()),
                cpu_build_s=c1 - c0, cpu_simulate_s=c2 - c1, cpu_fft_s=c3 - c2, cpu_s=c3 - c0,
                stats=st)


def modal_point(p, N: int, f_ref: float) -> dict:
    f, cpu = _modal_f(p, N)
    return dict(N=N, f_modal=f, rel_error=abs(f - f_ref) / f_ref, signed_rel_error=(f - f_ref) / f_ref,
                cpu_s=cpu)


def cheapest(points, levels=LEVELS) -> dict:
    """Per error level: the cheapest point with rel_error <= level, and the cheapest whose mesh
    error |f_modal(N) - f_ref| plus its time-integration/FFT error |f_fft - f_modal(N)| (measured
    separately) is <= level, i.e. which meets the level without relying on the two cancelling."""
    def pick(q):
        return None if q is None else {k: q[k] for k in ("N", "rtol", "step", "rel_error", "cpu_s") if k in q}
    out = {}
    for e in levels:
        ok = [q for q in points if "failed" not in q and q["rel_error"] <= e]
        best = min(ok, key=lambda q: q["cpu_s"]) if ok else None
        bound = [q for q in ok if q.get("mesh_rel_error", 0.0) + q.get("rel_error_vs_modal_N", 0.0) <= e]
        bc = min(bound, key=lambda q: q["cpu_s"]) if bound else None
        out[f"{e:.0e}"] = dict(cheapest=pick(best), cheapest_without_cancellation=pick(bc))
    return out


def amplitude_ratio(q: dict, p) -> float:
    """Response amplitude over t >= T_FFT relative to the undamped linear estimate impulse /
    (m_R omega): about 1 for a resolved oscillation, << 1 where the integrator damped it out."""
    return q["amplitude_m"] / (q.get("impulse_Ns", IMPULSE) / (p.m_R * 2 * np.pi * q["f_modal_N"]))


def summarize(out: dict, p) -> None:
    """Validity flags, Pareto fronts and cheapest settings (in place). A point whose amplitude
    ratio is below MIN_AMPLITUDE_RATIO measures no oscillation: it is kept in the points but not
    used for the fronts."""
    for r, d in out["fft_routes"].items():
        for q in d["points"]:
            if "failed" not in q:
                q["amplitude_ratio"] = amplitude_ratio(q, p)
                q["valid"] = q["amplitude_ratio"] >= MIN_AMPLITUDE_RATIO
        ok = [q for q in d["points"] if q.get("valid")]
        front = pareto([q["cpu_s"] for q in ok], [q["rel_error"] for q in ok])
        key = {(q["cpu_s"], q["rel_error"]): (q["N"], q["rtol"]) for q in ok}
        extra = {}
        if any("step" in q for q in ok):   # generalized-alpha: the setting is the step
            ks = {(q["cpu_s"], q["rel_error"]): (q["N"], q["step"]) for q in ok}
            extra = dict(pareto_N_step=[ks[c] for c in front])
        d.update(pareto=front, pareto_N_rtol=[key[c] for c in front], cheapest=cheapest(ok), **extra,
                 cpu_at_error={f"{e:.0e}": cpu_at_error(front, e) for e in LEVELS})
    mo = out["modal_route"]
    mo.update(pareto=pareto([q["cpu_s"] for q in mo["points"]], [q["rel_error"] for q in mo["points"]]),
              cheapest=cheapest(mo["points"]))
    out["setup"]["valid_point"] = (f"amplitude over the FFT window >= {MIN_AMPLITUDE_RATIO} x impulse / "
                                   f"(m_R 2 pi f_modal(N)) (else the integrator damped the oscillation out)")


# ------------------------------------------------------------------ plot
def plot(out) -> str:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(1, 2, figsize=(13, 7))
    Ns = sorted({q["N"] for r in out["fft_routes"].values() for q in r["points"]})
    cmap = plt.get_cmap("viridis")
    col = {N: cmap(i / max(1, len(Ns) - 1)) for i, N in enumerate(Ns)}
    styles = {"all": ("o", "-"), "configuration": ("s", "--"), "generalized-alpha": ("D", "-.")}
    fcol = {"all": "red", "configuration": "blue", "generalized-alpha": "green"}
    for route, r in out["fft_routes"].items():
        mk, ls_ = styles.get(route, ("x", ":"))
        for N in Ns:
            q = [q for q in r["points"] if q["N"] == N and q.get("valid")]
            bad = [q for q in r["points"] if q["N"] == N and "failed" not in q and not q.get("valid")]
            if bad:
                ax[0].loglog([a["cpu_s"] for a in bad], [a["rel_error"] for a in bad], "x", color=col[N], ms=7)
            if not q:
                continue
            lab = (f"FFT, N={N}, generalized-alpha rho {q[0]['rho_inf']}" if "step" in q[0]
                   else f"FFT, N={N}, IDA error_test={route}")
            ax[0].loglog([a["cpu_s"] for a in q], [a["rel_error"] for a in q], mk + ls_, color=col[N],
                         label=lab, ms=5)
            ax[1].loglog([a["cpu_s"] for a in q], [a["rel_error_vs_modal_N"] for a in q], mk + ls_,
                         color=col[N], label=lab, ms=5)
            for a in q:
                txt = f"h={a['step']:.1e}" if "step" in a else f"{a['rtol']:.0e}"
                ax[0].annotate(txt, (a["cpu_s"], a["rel_error"]), fontsize=6, alpha=0.6)
        fr = r["pareto"]
        if fr:
            ax[0].loglog([c for c, _ in fr], [e for _, e in fr], "-", color=fcol.get(route, "grey"), lw=4, alpha=0.25,
                         label=f"Pareto front, FFT ({route})")
    mo = out["modal_route"]["points"]
    ax[0].loglog([q["cpu_s"] for q in mo], [q["rel_error"] for q in mo], "^-k", label="modal route (build + modes(1))")
    for q in mo:
        ax[0].annotate(f"N={q['N']}", (q["cpu_s"], q["rel_error"]), fontsize=7)
    floor = out["fft_floor"]["undamped"]["max_rel_error"]
    for a in ax:
        a.axhline(floor, color="grey", ls=":", label="FFT estimator floor (synthetic sine, max)")
        a.set_xlabel("CPU time [s] (build + simulate / build + modes)")
        a.grid(True, which="both", alpha=0.3)
    ax[0].plot([], [], "xk", label="oscillation damped out (amplitude < 10 %)")
    ax[0].axhline(out["reference"]["f_ref_rel_uncertainty"], color="k", ls="--", lw=0.8,
                  label="f_ref uncertainty (relative)")
    ax[0].set_ylabel("|f - f_ref| / f_ref")
    ax[0].set_title(f"leaf spring: error vs mesh-converged f_ref = {out['reference']['f_ref']:.6f} Hz")
    ax[1].set_ylabel("|f_fft - f_modal(N)| / f_modal(N)")
    ax[1].set_title("time integration + FFT error alone (same N)")
    h, lab = ax[0].get_legend_handles_labels()
    fig.legend(h, lab, loc="lower center", ncol=4, fontsize=7)
    fig.tight_layout(rect=(0, 0.2, 1, 1))
    path = os.path.join(RESULTS, "bench_leaf_spring.png")
    fig.savefig(path, dpi=120)
    plt.close(fig)
    print(f"wrote {path}", flush=True)
    return path


# ------------------------------------------------------------------ main
def git_state() -> dict:
    """Commit of the source tree (the installed build is assumed to match it)."""
    import subprocess
    root = os.path.dirname(HERE)
    try:
        head = subprocess.run(["git", "-C", root, "rev-parse", "HEAD"], capture_output=True, text=True).stdout.strip()
        dirty = subprocess.run(["git", "-C", root, "status", "--porcelain", "--untracked-files=no"],
                               capture_output=True, text=True).stdout.split("\n")
        return dict(commit=head, modified_files=[l[3:] for l in dirty if l.strip()])
    except OSError:
        return {}


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer points (< 3 min)")
    ap.add_argument("--smoke", action="store_true",
                    help="a few seconds: coarse meshes, 2.5 s simulated (tests/test_benchmarks_smoke.py)")
    ap.add_argument("--budget", type=float, default=1050.0,
                    help="full run: skip N = 40 points once this many CPU seconds are spent [s]")
    ap.add_argument("--replot", action="store_true",
                    help="recompute the summary and the plot from the existing JSON (no new measurement)")
    a = ap.parse_args(argv)
    if a.replot:
        import json
        with open(os.path.join(RESULTS, "bench_leaf_spring.json")) as f:
            out = json.load(f)
        out["summary_recomputed_by_replot"] = True
        finish(out, ls.default_params())
        return out
    t_wall, t_cpu = time.time(), time.process_time()
    git_start = git_state()
    p = ls.default_params()
    global T_END, T_FFT
    if a.smoke:
        T_END, T_FFT = 2.5, 1.0
        Ns_ref, Ns_check, Ns, rtols, Ns_extra = [4, 8, 16], [], [2], [1e-3], []
        amp_check = dict(Ns=[2], rtol=1e-3)
        steps = [2e-3]
    elif a.quick:
        Ns_ref, Ns_check, Ns, rtols, Ns_extra = [20, 40, 80], [30, 60], [2, 5, 10], [1e-3, 1e-4, 1e-5], []
        amp_check = dict(Ns=[2], rtol=1e-5)
        steps = [2e-3, 5e-4]
    else:
        Ns_ref, Ns_check = [20, 40, 80], [30, 60, 120, 160, 240]
        Ns, rtols, Ns_extra = [2, 3, 5, 10, 20], [1e-3, 1e-4, 1e-5, 1e-6, 1e-7], [40]
        amp_check = dict(Ns=[2, 5], rtol=1e-7)
        steps = [2e-3, 1e-3, 5e-4, 2.5e-4]
    for h in steps:   # uniform output for the FFT: every output time must be a step
        if abs(DT_OUT / h - round(DT_OUT / h)) > 1e-9:
            raise SystemExit(f"step {h} does not divide DT_OUT = {DT_OUT}")
    # error_test="configuration" (BDF order <= 2) is far cheaper per rtol: one more decade for it
    route_rtols = {"all": rtols, "configuration": rtols + [rtols[-1] * 0.1]}
    # generalized-alpha: the swept setting is the fixed step (Newton rtol GA_RTOL)
    route_rtols["generalized-alpha"] = steps
    ref = reference(p, Ns_ref, Ns_check)
    f_ref = ref["f_ref"]
    orders = ", ".join(f"{o['N']}: {o['order']:.3f}" for o in ref["observed_orders"])
    print(f"f_ref = {f_ref:.9f} Hz (+- {ref['f_ref_rel_uncertainty']:.1e} rel), observed orders {orders}",
          flush=True)

    rp = {q["N"]: q for q in ref["points"]}
    modal = [dict(N=N, f_modal=rp[N]["f_modal"], rel_error=abs(rp[N]["f_modal"] - f_ref) / f_ref,
                  signed_rel_error=(rp[N]["f_modal"] - f_ref) / f_ref, cpu_s=rp[N]["cpu_s"]) if N in rp
             else modal_point(p, N, f_ref) for N in sorted(set(Ns + Ns_extra + Ns_ref + Ns_check))]
    for q in modal:
        print(f"modal N={q['N']:4d}: f = {q['f_modal']:.7f} Hz, err {q['rel_error']:.2e}, CPU {q['cpu_s']:.3f} s",
              flush=True)
    fmod = {q["N"]: q["f_modal"] for q in modal}
    zeta = 0.0
    m0, _ = ls.build(p, elements=10, beta=BETA)
    zeta = float(m0.modes(1).damping_ratio[0])
    floor = fft_floor(f_ref, zeta, p)
    print(f"FFT floor (synthetic sine, window {floor['window_s']} s): max {floor['undamped']['max_rel_error']:.1e}, "
          f"median {floor['undamped']['median_rel_error']:.1e}; damped (zeta {zeta:.2e}) max "
          f"{floor['damped']['max_rel_error']:.1e}", flush=True)

    has_et = "error_test" in inspect.signature(ph.Mechanism.simulate).parameters
    has_ga = "integrator" in inspect.signature(ph.Mechanism.simulate).parameters
    routes = ["all"] + (["configuration"] if has_et else []) + (["generalized-alpha"] if has_ga else [])
    if not has_et:
        print("Mechanism.simulate has no error_test parameter: the error_test='configuration' sweep is skipped",
              flush=True)
    if not has_ga:
        print("Mechanism.simulate has no integrator parameter: the generalized-alpha sweep is skipped", flush=True)
    pts = {r: [] for r in routes}
    skipped = []
    cost = {}   # (route, N, rtol or step) -> cpu, for the N = 40 budget estimate
    for Nset, budgeted in ((Ns, False), (Ns_extra, True)):
        for route in (routes[::-1] if budgeted else routes):   # budgeted: the cheap route first
            for N in Nset:
                for rtol in route_rtols[route]:
                    ga = route == "generalized-alpha"
                    what = f"h={rtol:.1e}" if ga else f"rtol={rtol:.0e}"
                    if budgeted:
                        prev = cost.get((route, Ns[-1], rtol), 60.0) * N / Ns[-1] * 1.2
                        if time.process_time() - t_cpu + prev > a.budget:
                            skipped.append(dict(N=N, **({"step": rtol} if ga else {"rtol": rtol}), route=route,
                                                predicted_cpu_s=prev))
                            print(f"skip {route:13s} N={N:3d} {what} (predicted {prev:.0f} s "
                                  f"exceeds the budget)", flush=True)
                            continue
                    if ga:
                        q = fft_point(p, N, GA_RTOL, f_ref, fmod[N], step=rtol, rho_inf=GA_RHO)
                    else:
                        q = fft_point(p, N, rtol, f_ref, fmod[N], None if route == "all" else route)
                    pts[route].append(q)
                    cost[(route, N, rtol)] = q["cpu_s"]
                    if "failed" in q:
                        print(f"{route:13s} N={N:3d} {what}: FAILED {q['failed']}", flush=True)
                        continue
                    print(f"{route:13s} N={N:3d} {what}: f_fft {q['f_fft']:.7f} Hz, err {q['rel_error']:.2e}"
                          f" (vs modal(N) {q['rel_error_vs_modal_N']:.2e}), CPU {q['cpu_s']:6.2f} s "
                          f"(build {q['cpu_build_s']:.2f}), steps {q['stats']['steps']}", flush=True)

    # amplitude effect: the same run with a 10x smaller impulse (linear regime)
    amp = []
    for N in amp_check["Ns"]:
        big = next((q for q in pts["all"] if q["N"] == N and q["rtol"] == amp_check["rtol"]
                    and "failed" not in q), None)
        small = fft_point(p, N, amp_check["rtol"], f_ref, fmod[N], None, impulse=IMPULSE / 10)
        if big is None or "failed" in small:
            continue
        d = (big["f_fft"] - small["f_fft"]) / small["f_fft"]
        amp.append(dict(N=N, rtol=amp_check["rtol"], impulse_Ns=[IMPULSE, IMPULSE / 10],
                        amplitude_m=[big["amplitude_m"], small["amplitude_m"]],
                        f_fft=[big["f_fft"], small["f_fft"]], f_modal_N=fmod[N], rel_shift=d,
                        small_rel_error_vs_modal_N=small["rel_error_vs_modal_N"]))
        print(f"amplitude check N={N} rtol={amp_check['rtol']:.0e}: f_fft {big['f_fft']:.7f} (impulse {IMPULSE}) "
              f"vs {small['f_fft']:.7f} (impulse {IMPULSE / 10}): shift {d:+.2e}; small vs modal(N) "
              f"{small['rel_error_vs_modal_N']:.2e}", flush=True)

    fft_routes = {r: dict(points=pts[r]) for r in routes}
    out = dict(
        benchmark="bench_leaf_spring", quick=a.quick, smoke=a.smoke, machine=machine(), git=dict(start=git_start, end=git_state()),
        setup=dict(model="examples/leaf_spring.py build(default_params(), elements=N, beta=1e-5, pulse)",
                   params=p.as_dict(), t_end_s=T_END, fft_window_s=[T_FFT, T_END], dt_out_s=DT_OUT,
                   impulse_Ns=IMPULSE, pulse_duration_s=DURATION, pulse_t0_s=T0, beta_s=BETA,
                   linear_solver="klu", atol="default (rtol * 1e-2)",
                   fft_estimator="phmech.analysis.dominant_frequency(pad=16), Hann, log-parabola peak",
                   fft_band_hz=list(band(p)), cpu="time.process_time, build + simulate (+ FFT)",
                   error="|f - f_ref| / f_ref", error_test_available=has_et,
                   generalized_alpha=(dict(steps_s=steps, rho_inf=GA_RHO, newton_rtol=GA_RTOL,
                                           newton_atol="default (rtol * 1e-2)",
                                           note="fixed step; every output (dt_out) is a step")
                                      if has_ga else None)),
        reference=ref, fft_floor=floor, modal_route=dict(points=modal),
        fft_routes=fft_routes, skipped=skipped, amplitude_check=amp,
        total_cpu_s=time.process_time() - t_cpu, total_wall_s=time.time() - t_wall)
    finish(out, p)
    return out


def finish(out: dict, p) -> None:
    summarize(out, p)
    write_json("bench_leaf_spring", out)
    plot(out)
    for r, d in out["fft_routes"].items():
        for lev, c in d["cheapest"].items():
            print(f"cheapest FFT ({r}) reaching {lev}: {c['cheapest']}; without cancellation: "
                  f"{c['cheapest_without_cancellation']}", flush=True)
    for lev, c in out["modal_route"]["cheapest"].items():
        print(f"cheapest modal reaching {lev}: {c['cheapest']}", flush=True)
    print(f"done: CPU {out['total_cpu_s']:.0f} s, wall {out['total_wall_s']:.0f} s", flush=True)


if __name__ == "__main__":
    main()

"""Parameter sweeps on Dask: a tip-mass grid of a cantilever and a Monte-Carlo of the leaf spring.

(i) A steel cantilever (200 x 20 x 1 mm) carrying a point mass at its tip: its first three
    bending frequencies over a grid of tip masses, next to the Euler-Bernoulli frequency
    equation of a cantilever with a tip mass.
(ii) The leaf-spring guide of examples/leaf_spring.py with a scattered leaf thickness (normal,
    2 % standard deviation) and platform mass (normal, 5 %): the distribution of its first
    frequency (modes) and of the peak platform displacement after a force pulse (a 1 s nonlinear
    simulation per sample), printed and plotted to examples/output/sweeps_montecarlo.png.

Both run on a local Dask cluster (one single-threaded worker process per core) through
``phmech.sweep``; ``--scheduler tcp://host:8786`` runs them on a real cluster, ``--serial`` in
this process. ``--speedup`` times the Monte-Carlo on 1 and on 2 workers (``--repeat`` times
each, medians).

    python examples/sweeps.py [--quick] [--samples 64] [--workers N] [--scheduler ADDR]
                              [--serial] [--speedup] [--repeat 3] [--no-plot] [--json]
"""
from __future__ import annotations

import functools
import json
import math
import os
import statistics
import sys

import numpy as np

import phmech as ph

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import leaf_spring as ls  # noqa: E402  (examples/leaf_spring.py: parameters and model)
from _cli import example_parser  # noqa: E402

STEEL = dict(E=210e9, nu=0.3, density=7850.0)
CANTILEVER = dict(L=0.2, width=0.02, thickness=0.001)


# ------------------------------------------------------------------------------- (i) cantilever
def cantilever(tip_mass: float, elements: int = 16) -> ph.Mechanism:
    """A clamped steel cantilever (CANTILEVER, along x, bending about y in the x-z plane) with a
    rigid point mass ``tip_mass`` [kg] welded to its free end (rotary inertia negligible:
    1e-9 kg m^2)."""
    steel = ph.Material(**STEEL)
    props = ph.BeamProperties.from_material(
        ph.Section.rectangle(CANTILEVER["width"], CANTILEVER["thickness"]), steel)
    m = ph.Mechanism()
    leaf = m.add_flexible_link("leaf", CANTILEVER["L"], props, elements=elements)
    m.add_pair("clamp", ph.Fixed(), m.ground, leaf.start)
    tip = m.add_rigid_body("tip", tip_mass, 1e-9 * np.eye(3),
                           pose=ph.se3.translation([CANTILEVER["L"], 0.0, 0.0]))
    m.add_pair("weld", ph.Fixed(), leaf.end, tip)
    return m


def bending_frequencies(m: ph.Mechanism, n: int = 3) -> dict:
    """The first ``n`` bending frequencies [Hz] in the x-z plane (the modes whose shape is
    dominated by z translation: a 1 mm x 20 mm leaf also has in-plane and torsion modes)."""
    mo = m.modes(4 * n)
    sh = mo.shapes
    zmove = np.abs(sh[:, :, 5]).max(axis=1) > np.abs(sh[:, :, 4]).max(axis=1)
    zrot = np.abs(sh[:, :, 1]).max(axis=1) > np.abs(sh[:, :, 0]).max(axis=1)
    f = mo.frequency[zmove & zrot][:n]
    return {"frequency": f}


def euler_bernoulli_tip_mass(tip_mass: float, n: int = 3) -> np.ndarray:
    """First ``n`` frequencies [Hz] of an Euler-Bernoulli cantilever with a tip point mass M:
    roots x = beta L of 1 + cos x cosh x + mu x (cos x sinh x - sin x cosh x) = 0, mu = M / (rho A L)."""
    from scipy.optimize import brentq

    L, b, t = CANTILEVER["L"], CANTILEVER["width"], CANTILEVER["thickness"]
    rhoA = STEEL["density"] * b * t
    EI = STEEL["E"] * b * t ** 3 / 12
    mu = tip_mass / (rhoA * L)

    def det(x):
        return 1 + math.cos(x) * math.cosh(x) + mu * x * (math.cos(x) * math.sinh(x) - math.sin(x) * math.cosh(x))

    xs, grid = [], np.linspace(0.05, 4 * n + 4, 4000)
    vals = [det(x) for x in grid]
    for a, c, fa, fc in zip(grid[:-1], grid[1:], vals[:-1], vals[1:]):
        if fa * fc < 0:
            xs.append(brentq(det, a, c, xtol=1e-14))
        if len(xs) == n:
            break
    return np.array(xs) ** 2 / L ** 2 * math.sqrt(EI / rhoA) / (2 * math.pi)


# ------------------------------------------------------------------------------- (ii) leaf spring
def leaf_spring(thickness: float, plate_mass: float, elements: int = 6) -> ph.Mechanism:
    """The leaf-spring guide of examples/leaf_spring.py (default parameters) with leaves of
    ``thickness`` [m] and a platform R1 of ``plate_mass`` [kg] (its thickness follows), hit by
    the example's force pulse (0.05 N s over 10 ms from t = 0.1 s) along x."""
    p = ls.default_params()
    p.thickness = thickness
    p.plate_t = plate_mass / (p.density * p.plate_x * p.plate_y)
    m, _ = ls.build(p, elements=elements, pulse=ph.Pulse(t0=0.1, duration=0.01, value=5.0))
    return m


def leaf_response(m: ph.Mechanism, t_end: float = 1.0) -> dict:
    """First frequency [Hz] (modes) and, when ``t_end`` > 0, the peak x displacement [m] of the
    platform R1 over a ``t_end`` [s] simulation of the pulse response."""
    out = {"f1": float(m.modes(1).frequency[0])}
    if t_end > 0:
        res = m.simulate(t_end, 2e-3, record=["R1"])
        x = res.position("R1")[:, 0]
        out["peak"] = float(np.abs(x - x[0]).max())
    return out


def monte_carlo_samples(n: int, seed: int = 1) -> dict:
    """``n`` samples of (thickness [m], plate_mass [kg]) around the example's nominal values."""
    p = ls.default_params()
    rng = np.random.default_rng(seed)
    return {"thickness": p.thickness * (1 + 0.02 * rng.standard_normal(n)),
            "plate_mass": p.m_plate * (1 + 0.05 * rng.standard_normal(n))}


def f_formula(thickness, plate_mass) -> np.ndarray:
    """The paper's formula with the leaves' mass correction (examples/leaf_spring.py) [Hz]."""
    out = []
    for t, mp in zip(np.atleast_1d(thickness), np.atleast_1d(plate_mass)):
        p = ls.default_params()
        p.thickness = float(t)
        p.plate_t = float(mp) / (p.density * p.plate_x * p.plate_y)
        out.append(ls.f_analytic_mass_corrected(p))
    return np.array(out)


# ------------------------------------------------------------------------------- main
def main(argv=None) -> dict:
    ap = example_parser(__doc__, "3 tip masses, 16 samples, 0.5 s simulations")
    ap.add_argument("--samples", type=int, default=None, help="Monte-Carlo samples (default 64)")
    ap.add_argument("--workers", type=int, default=None, help="local workers (default: one per core)")
    ap.add_argument("--scheduler", default=None, help="address of a running Dask scheduler")
    ap.add_argument("--serial", action="store_true", help="run in this process (debugging)")
    ap.add_argument("--speedup", action="store_true", help="time the Monte-Carlo on 1 and 2 workers (interleaved)")
    ap.add_argument("--repeat", type=int, default=3, help="timings per worker count (--speedup)")
    args = ap.parse_args(argv)
    nsamp = args.samples or (16 if args.quick else 64)
    t_end = args.t_end if args.t_end is not None else (0.5 if args.quick else 1.0)
    elements = args.elements or 6          # per leaf of the leaf spring; the cantilever: 16
    run = dict(client="serial") if args.serial else dict(scheduler=args.scheduler, workers=args.workers)
    out: dict = {}

    # (i) tip-mass grid
    masses = np.array([0.005, 0.02, 0.05]) if args.quick else np.linspace(0.01, 0.1, 10)
    ds = ph.sweep(functools.partial(cantilever, elements=args.elements or 16), {"tip_mass": masses},
                  bending_frequencies, **run)
    ref = np.array([euler_bernoulli_tip_mass(M) for M in masses])
    f = ds["frequency"].values
    print("(i) cantilever with a tip mass: first bending frequencies [Hz], phmech / Euler-Bernoulli")
    for M, fi, ri in zip(masses, f, ref):
        print(f"  M = {M:6.3f} kg: " + "  ".join(f"{a:9.3f} / {b:9.3f}" for a, b in zip(fi, ri)))
    out["cantilever"] = dict(tip_mass=masses.tolist(), frequency=f.tolist(), euler_bernoulli=ref.tolist(),
                             max_rel_diff_f1=float(np.max(np.abs(f[:, 0] / ref[:, 0] - 1))),
                             failed=ds.attrs["failed"], wall_time=ds.attrs["wall_time"])

    # (ii) Monte-Carlo
    smp = monte_carlo_samples(nsamp)
    build = functools.partial(leaf_spring, elements=elements)
    analysis = functools.partial(leaf_response, t_end=t_end)
    mc = ph.sweep(build, smp, analysis, samples=True, **run)
    f1 = mc["f1"].values
    fref = f_formula(smp["thickness"], smp["plate_mass"])
    print(f"(ii) leaf spring, {nsamp} samples (thickness +-2 %, platform mass +-5 %), "
          f"{mc.attrs['workers']} workers, {mc.attrs['wall_time']:.1f} s, {mc.attrs['failed']} failed")
    print(f"  f1 = {np.nanmean(f1):.4f} +- {np.nanstd(f1):.4f} Hz (min {np.nanmin(f1):.4f}, max "
          f"{np.nanmax(f1):.4f}); formula with leaf mass: {fref.mean():.4f} +- {fref.std():.4f} Hz")
    rel = 100 * (f1 / fref - 1)
    print(f"  phmech / formula - 1 = {np.nanmean(rel):+.3f} +- {np.nanstd(rel):.3f} %: the discretization "
          f"error of {elements} elements per leaf (it falls as 1/N^2: examples/leaf_spring.py)")
    print(f"  peak platform displacement after the pulse: {1e3 * np.nanmean(mc['peak'].values):.4f} "
          f"+- {1e3 * np.nanstd(mc['peak'].values):.4f} mm")
    out["montecarlo"] = dict(samples=nsamp, f1_mean=float(np.nanmean(f1)), f1_std=float(np.nanstd(f1)),
                             formula_mean=float(fref.mean()), formula_std=float(fref.std()),
                             peak_mean=float(np.nanmean(mc["peak"].values)),
                             failed=mc.attrs["failed"], wall_time=mc.attrs["wall_time"])

    if args.speedup:
        from distributed import Client, LocalCluster

        # both clusters up at once and their runs interleaved, so that the load of a shared
        # machine weighs on both alike
        times, cpu = {1: [], 2: []}, {1: [], 2: []}
        clusters = {nw: LocalCluster(n_workers=nw, threads_per_worker=1, processes=True,
                                     dashboard_address=":0") for nw in (1, 2)}
        clients = {nw: Client(cl) for nw, cl in clusters.items()}
        try:
            for c in clients.values():                # warm-up: imports on the workers
                ph.sweep(build, {k: v[:2] for k, v in smp.items()}, analysis, samples=True,
                         client=c, progress=False)
            for _ in range(args.repeat):
                for nw, c in clients.items():
                    r = ph.sweep(build, smp, analysis, samples=True, client=c, progress=False)
                    times[nw].append(r.attrs["wall_time"])
                    cpu[nw].append(r.attrs["cpu_time"])
        finally:
            for x in (*clients.values(), *clusters.values()):
                x.close()
        med = {k: statistics.median(v) for k, v in times.items()}
        print(f"  speed-up 1 -> 2 workers ({nsamp} samples, {args.repeat} runs each, medians): "
              f"{med[1]:.2f} s -> {med[2]:.2f} s, x{med[1] / med[2]:.2f}  (all: {times})")
        share = {nw: statistics.median(c / (t * nw) for c, t in zip(cpu[nw], times[nw])) for nw in times}
        print(f"  share of the workers' cores the points had (CPU / (wall x workers), medians): "
              f"1 worker {share[1]:.2f}, 2 workers {share[2]:.2f}; the points' CPU time "
              f"{statistics.median(cpu[1]):.2f} s / {statistics.median(cpu[2]):.2f} s")
        out["speedup"] = dict(times=times, cpu=cpu, median=med, speedup=med[1] / med[2], share=share)

    if not args.no_plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        import phmech.plot as pp

        os.makedirs(args.outdir, exist_ok=True)
        fig, ax = plt.subplots(1, 3, figsize=(13, 3.8))
        first = ds.isel({d: 0 for d in ds["frequency"].dims if d != "tip_mass"})
        pp.sweep(first, "frequency", ax=ax[0], reference=ref[:, 0])
        ax[0].set(xlabel="tip mass [kg]", ylabel="first frequency [Hz]", title="(i) cantilever")
        pp.sweep(mc, "f1", ax=ax[1])
        ax[1].axvline(fref.mean(), color="k", ls="--", label="formula, mean")
        ax[1].set(xlabel="first frequency [Hz]", title="(ii) leaf spring")
        ax[1].legend()
        mm = mc.assign(thickness_mm=1e3 * mc["thickness"])
        mm["f1"].attrs["units"] = "Hz"
        pp.sweep(mm, "f1", ax=ax[2], x="thickness_mm", y="plate_mass")
        ax[2].set(xlabel="leaf thickness [mm]", ylabel="platform mass [kg]")
        fig.tight_layout()
        path = os.path.join(args.outdir, "sweeps_montecarlo.png")
        fig.savefig(path, dpi=110)
        print(f"  plot: {path}")
    if args.json:
        print(json.dumps(out, default=float))
    return out


if __name__ == "__main__":
    main()

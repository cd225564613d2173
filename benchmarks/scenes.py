"""Ordinary scenes run with phmech's defaults: ``simulate(t_end, dt_out)`` and nothing else.

Each scene is a model a user would build, a horizon, an output interval and the quantities a user
would look at (positions, joint angles, a dominant frequency). The reference is the same model and
mesh integrated by an independent, slower, tighter route: SUNDIALS IDA (BDF) at rtol 1e-9 with the
configuration error test (IDA with every state in its error test resolves the meshes' kHz-MHz
vibrations: the double pendulum would take ~35 min), cross-checked where affordable.

    python benchmarks/scenes.py [--quick] [--only NAME ...]

writes benchmarks/results/scenes.json and scenes.png (the table of docs/integrators.md). The short
versions run in tests/test_scenes.py.
"""
from __future__ import annotations

import argparse
import json
import math
import os
import sys
import time
from dataclasses import dataclass
from typing import Callable, Optional

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(os.path.dirname(HERE), "examples"))

import phmech as ph  # noqa: E402
from phmech import se3  # noqa: E402

STEEL = ph.Material(E=210e9, nu=0.3, density=7850.0)
REFERENCE = dict(integrator="ida", error_test="configuration", max_order=2, rtol=1e-9, atol=1e-11,
                 linear_solver="klu")


@dataclass
class Scene:
    """``build()`` -> (mechanism, measure) with ``measure(result)`` -> dict name -> (nt, k) array
    of band quantities; ``scale``: dict name -> what that quantity's errors are relative to [m
    or rad]; ``frequency``: a quantity name whose dominant frequency is compared too."""
    name: str
    build: Callable
    t_end: float
    dt_out: float
    t_quick: float
    scale: dict
    note: str = ""
    frequency: Optional[str] = None
    reference: Optional[dict] = None  # simulate options of the reference (None: REFERENCE)
    modal: bool = False               # compare the FFT frequency with modes() too


def _bar(m, name, L, mass=1.0, axis_y=False):
    J = np.diag([1e-4, mass * L**2 / 12, mass * L**2 / 12])
    return m.add_rigid_body(name, mass, J, com=(L / 2, 0, 0))


def double_pendulum():
    """A 0.3 m rigid link (1 kg) and a 0.3 m steel strip (20 x 2 mm, 8 elements) in series on
    revolutes about y, released horizontal under gravity."""
    props = ph.BeamProperties.from_material(ph.Section.rectangle(0.02, 0.002), STEEL)
    m = ph.Mechanism(gravity=(0, 0, -9.81))
    link = _bar(m, "link", 0.3)
    m.add_pair("shoulder", ph.Revolute(axis="y"), m.ground, link)
    strip = m.add_flexible_link("strip", 0.3, props, elements=8, pose=se3.translation([0.3, 0, 0]))
    m.add_pair("elbow", ph.Revolute(axis="y"), ph.Frame(link.carrier, se3.translation([0.3, 0, 0])),
               strip.start)
    return m, lambda r: dict(tip=r.tip(strip)[:, [0, 2]],
                             angles=np.column_stack([r.joint("shoulder")["x"][:, 0],
                                                     r.joint("elbow")["x"][:, 0]]))


def leaf_spring():
    """The paper's leaf-spring guide (examples/leaf_spring.py, its run()): two steel leaves, three
    welded bodies, material damping 1e-5 s, a 0.05 N s impulse (5 N x 10 ms) on the platform."""
    import leaf_spring as ls
    p = ls.default_params()
    m, h = ls.build(p, elements=10, beta=1e-5, pulse=ph.Pulse(t0=0.1, duration=0.01, value=5.0))
    return m, lambda r: dict(x=r.position(h["R1"])[:, :1] - r.position(h["R1"])[0, 0])


def manipulator():
    """The Fig. 3 manipulator (examples/manipulator.py, 4 elements per link): PD joints with
    gravity compensation, knocked at 0.5 s."""
    import manipulator as mp
    p = mp.ManipulatorParams()
    ff, _ = mp.gravity_compensation(p, elements=4)
    m, h = mp.build(p, elements=4, ff=ff)
    return m, lambda r: dict(hand=r.position(h["R3"])[:, :2])


def fourbar():
    """A rigid crank-rocker four-bar (0.2/0.6/0.5/0.5 m bars of 1 kg) under gravity, crank
    started at 4 rad/s (3-D revolutes: redundant constraints, dropped)."""
    m = ph.Mechanism(gravity=(0, -9.81, 0))
    A, B, C, D = 0.2, 0.6, 0.5, 0.5
    crank, cp, rocker = _bar(m, "crank", A), _bar(m, "coupler", B), _bar(m, "rocker", C)
    T = lambda x: se3.translation([x, 0, 0])
    m.add_pair("k1", ph.Revolute("z"), m.ground, crank, x0=0.6, xdot0=4.0)
    m.add_pair("k2", ph.Revolute("z"), ph.Frame(crank.carrier, T(A)), cp)
    m.add_pair("k3", ph.Revolute("z"), ph.Frame(cp.carrier, T(B)), ph.Frame(rocker.carrier, T(C)))
    m.add_pair("k4", ph.Revolute("z"), ph.Frame(-1, T(D)), rocker)
    return m, lambda r: dict(crank=r.joint("k1")["x"][:, :1], rocker=r.joint("k4")["x"][:, :1])


def cantilever_tip_mass():
    """A 0.5 m steel strip (30 x 3 mm, 10 elements) clamped, with a 0.2 kg tip mass, hit at the
    tip by a 20 N x 2 ms impulse across its thin side."""
    props = ph.BeamProperties.from_material(ph.Section.rectangle(0.03, 0.003), STEEL)
    m = ph.Mechanism()
    b = m.add_flexible_link("strip", 0.5, props, elements=10)
    m.add_pair("clamp", ph.Fixed(), m.ground, b.start)
    mass = m.add_rigid_body("mass", 0.2, np.diag([2e-5, 2e-5, 2e-5]), pose=se3.translation([0.5, 0, 0]))
    m.add_pair("weld", ph.Fixed(), b.end, mass)
    m.add_wrench("hit", mass, (0, 0, 0, 0, 0, 20.0), law=ph.Pulse(t0=0.01, duration=2e-3, value=1.0),
                 frame="world")
    return m, lambda r: dict(tip=r.position(mass)[:, 2:3])


def slider_crank():
    """A slider-crank: a 0.15 m rigid crank (0.5 kg) coasting from 2 pi rad/s, a 0.3 m steel
    connecting rod (20 x 5 mm, bending in the plane of motion, 6 elements), a 0.5 kg slider on a
    prismatic guide; no gravity, no damping (3-D revolutes: redundant constraints, dropped)."""
    props = ph.BeamProperties.from_material(ph.Section.rectangle(0.005, 0.02), STEEL)
    m = ph.Mechanism()
    crank = m.add_rigid_body("crank", 0.5, np.diag([1e-4, 1e-3, 1e-3]), com=(0.075, 0, 0))
    m.add_pair("motor", ph.Revolute("z"), m.ground, crank, x0=0.0, xdot0=2 * np.pi)
    rod = m.add_flexible_link("rod", 0.3, props, elements=6, pose=se3.translation([0.15, 0, 0]))
    m.add_pair("crankpin", ph.Revolute("z"), ph.Frame(crank.carrier, se3.translation([0.15, 0, 0])),
               rod.start)
    slider = m.add_rigid_body("slider", 0.5, np.diag([1e-4, 1e-4, 1e-4]), pose=se3.translation([0.45, 0, 0]))
    m.add_pair("wristpin", ph.Revolute("z"), rod.end, slider)
    m.add_pair("guide", ph.Prismatic("x"), m.ground, slider)
    return m, lambda r: dict(slider=r.position(slider)[:, :1], crank=r.joint("motor")["x"][:, :1])


def flexible_arm():
    """A 0.6 m aluminium arm (40 x 4 mm, 8 elements) on a motor revolute about z, driven by a
    0.3 N m torque for 0.5 s then -0.3 N m for 0.5 s (rest-to-rest bang-bang), no gravity."""
    alu = ph.Material(E=70e9, nu=0.33, density=2700.0)
    props = ph.BeamProperties.from_material(ph.Section.rectangle(0.004, 0.04), alu)
    m = ph.Mechanism()
    hub = m.add_rigid_body("hub", 0.5, np.diag([1e-3, 1e-3, 1e-3]))
    m.add_pair("motor", ph.Revolute("z"), m.ground, hub,
               actuator=ph.Effort(law=ph.Table([0.0, 0.5, 0.5 + 1e-9, 1.0, 1.0 + 1e-9, 10.0],
                                               [0.3, 0.3, -0.3, -0.3, 0.0, 0.0])))
    arm = m.add_flexible_link("arm", 0.6, props, elements=8)
    m.add_pair("root", ph.Fixed(), hub, arm.start)
    return m, lambda r: dict(tip=r.tip(arm)[:, :2], angle=r.joint("motor")["x"][:, :1])


SCENES = [
    Scene("double pendulum", double_pendulum, 2.0, 1e-3, 0.5, dict(tip=0.6, angles=2 * math.pi),
          note="chaotic after ~1 s: errors over 2 s are within the horizon where two tight routes agree"),
    Scene("leaf spring", leaf_spring, 10.0, 2e-3, 2.0, dict(x=1e-3), frequency="x", modal=True,
          note="x scale: the platform's amplitude (~1 mm); reference: IDA with every state in its "
               "error test (the configuration test crawls at 1e-8 s steps here)",
          reference=dict(integrator="ida", rtol=1e-8, atol=1e-10, linear_solver="klu")),
    Scene("manipulator", manipulator, 6.0, 2e-3, 1.0, dict(hand=0.75)),
    Scene("four-bar", fourbar, 2.0, 1e-3, 0.5, dict(crank=2 * math.pi, rocker=2 * math.pi),
          note="reference: IDA with every state in its error test (rigid: no mesh vibrations to "
               "resolve); the configuration test at rtol 1e-9 was 8.4e-4 rad off the crank angle "
               "here (every state, BDF order 5, rtol 1e-11: 5.7e-9 rad from rtol 1e-12)",
          reference=dict(integrator="ida", rtol=1e-11, atol=1e-13, linear_solver="klu")),
    Scene("cantilever + tip mass, impulse", cantilever_tip_mass, 1.0, 1e-3, 0.3, dict(tip=4.1e-3),
          frequency="tip", note="tip scale: the tip's amplitude (4.1 mm)"),
    Scene("slider-crank, flexible rod", slider_crank, 1.0, 1e-3, 0.3, dict(slider=0.3, crank=2 * math.pi),
          note="the reference (IDA, configuration test, rtol 1e-9) takes ~130 s of CPU for 1 s"),
    Scene("flexible arm, torque profile", flexible_arm, 2.0, 1e-3, 1.0, dict(tip=0.6, angle=2 * math.pi)),
]


@dataclass
class Reference:
    """A cached reference: output times and band quantities."""
    t: np.ndarray
    quantities: dict


def dominant_frequency(t, x):
    return ph.analysis.dominant_frequency(t, x - np.mean(x))


def run_scene(sc: Scene, t_end: float, reference: bool = True, cache: Optional[str] = None,
              **options) -> dict:
    """The default run, then the reference; errors of each band quantity (max over time,
    relative to the scene's scale), CPU, steps, ledger. ``cache``: an .npz path where the
    reference's band quantities are kept (read if it exists, written otherwise)."""
    import warnings
    warnings.simplefilter("ignore", ph.RedundantConstraintWarning)
    m, measure = sc.build()
    c0 = time.process_time()
    res = m.simulate(t_end, sc.dt_out, **options)
    cpu = time.process_time() - c0
    out = dict(scene=sc.name, t_end=t_end, dt_out=sc.dt_out, cpu_s=cpu, cpu_per_s=cpu / t_end,
               steps=int(res.stats["steps"]), floor_steps=int(res.stats["floor_steps"]),
               ledger_relative=res.stats["ledger_relative"],
               numerical_dissipation_relative=res.stats["numerical_dissipation_relative"],
               error_estimate=res.stats["error_estimate"], esum=res.stats.get("error_sum"), scale=sc.scale, note=sc.note)
    if reference:
        if cache and os.path.exists(cache):
            z = np.load(cache)
            qr = {k[2:]: z[k] for k in z.files if k.startswith("q_")}
            ref = Reference(z["t"], qr)
            out["reference_cpu_s"], out["reference_ledger_relative"] = float(z["cpu"]), float(z["ledger"])
        else:
            m2, _ = sc.build()
            c0 = time.process_time()
            with warnings.catch_warnings():   # the reference is slow on purpose
                warnings.simplefilter("ignore", ph.CostWarning)
                ref = m2.simulate(t_end, sc.dt_out, **(sc.reference or REFERENCE))
            out["reference_cpu_s"] = time.process_time() - c0
            out["reference_ledger_relative"] = ref.stats["ledger_relative"]
            qr = measure(ref)
            if cache:
                np.savez(cache, t=ref.t, cpu=out["reference_cpu_s"], ledger=out["reference_ledger_relative"],
                         **{"q_" + k: v for k, v in qr.items()})
        q = measure(res)
        err = {k: float(np.max(np.abs(q[k] - qr[k]))) for k in q}
        out["errors"] = {k: e / sc.scale[k] for k, e in err.items()}
        out["error"] = max(out["errors"].values())
        # the accuracy contract's figure (docs/user_guide.md, "Accuracy contract"): the error over
        # rtol times the quantity's scale plus atol; <= 1 keeps the contract
        rt, at = res.stats["rtol"], res.stats["atol"]
        out["error_vs_tolerance"] = max(e / (rt * sc.scale[k] + at) for k, e in err.items())
        if sc.frequency:
            f, fr = (dominant_frequency(r.t, x[sc.frequency][:, 0]) for r, x in ((res, q), (ref, qr)))
            out["frequency_hz"], out["reference_frequency_hz"] = f, fr
            out["frequency_error"] = abs(f - fr) / fr
            if sc.modal:
                fm = float(m.modes(1).frequency[0])
                out["modal_frequency_hz"], out["frequency_error_vs_modes"] = fm, abs(f - fm) / fm
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="the short horizons of tests/test_scenes.py")
    ap.add_argument("--only", nargs="*", default=None)
    ap.add_argument("--smoke", action="store_true",
                    help="the first scene only, its short horizon (tests/test_benchmarks_smoke.py)")
    ap.add_argument("--options", default="", help="simulate options to try, e.g. 'rho_inf=0.6'")
    a = ap.parse_args(argv)
    options = eval(f"dict({a.options})")
    rows = []
    if a.smoke:
        a.quick, a.only = True, [SCENES[0].name]
    for sc in SCENES:
        if a.only and sc.name not in a.only:
            continue
        r = run_scene(sc, sc.t_quick if a.quick else sc.t_end, **options)
        rows.append(r)
        fe = f", f err {r['frequency_error']:.1e}" if "frequency_error" in r else ""
        fe += f" (vs modes {r['frequency_error_vs_modes']:.1e})" if "frequency_error_vs_modes" in r else ""
        print(f"{sc.name:34s} t {r['t_end']:5.1f} s  CPU {r['cpu_s']:6.2f} s ({r['cpu_per_s']:.2f} s/s)  "
              f"steps {r['steps']:6d}  err/scale {r['error']:.1e}{fe}  ledger {r['ledger_relative']:.1e}  "
              f"(ref CPU {r['reference_cpu_s']:.1f} s)", flush=True)
    res = os.environ.get("BENCH_RESULTS") or os.path.join(HERE, "results")
    os.makedirs(res, exist_ok=True)
    path = os.path.join(res, "scenes_quick.json" if a.quick else "scenes.json")
    if options:
        return rows
    with open(path, "w") as f:
        sys.path.insert(0, HERE)
        from run import machine
        json.dump(dict(rtol=ph._simulate.DEFAULT_RTOL, reference=REFERENCE, scenes=rows, machine=machine(),
                       quick=a.quick, smoke=a.smoke), f, indent=1)
    print(f"results: {path}")
    return rows


if __name__ == "__main__":
    main()

"""Per-link fidelity: a pendulum made of one link, modelled rigid or nonlinear, against the exact
compound-pendulum period, and what a very stiff nonlinear link costs against a rigid one.

The link (a 0.5 m steel bar, 10 x 20 mm) hangs from a hinge about world y and is released at
``theta0``. The exact period is 4 sqrt(I_O / (m g d)) K(sin^2(theta0 / 2)) (complete elliptic
integral K), I_O = rhoA L^3/3 + rhoI_y L about the hinge, m g d = rhoA L g L/2. Printed per model
and element count: the period's relative error, the CPU time [s] of one period, the default
integrator's steps and its energy-ledger residual (relative to the run's energy scale).

``--stiff bending`` multiplies the bending stiffnesses EI by 1e4 (first flexible mode ~1.2 kHz,
the pendulum swings at 0.8 Hz), ``--stiff all`` the whole section stiffness (axial and shear
too), ``--stiff none`` leaves steel as it is. docs/user_guide.md, "Model only what a scene
needs"; tests/test_fidelity.py asserts the same scene.

    python examples/fidelity.py [--quick] [--json] [--stiff bending|all|none] [--theta0 1.0]
"""
from __future__ import annotations

import json
import sys
import time
import types
import warnings

import numpy as np
from scipy.special import ellipk

import phmech as ph
from _cli import example_parser

STEEL = ph.Material(E=210e9, nu=0.3, density=7850.0)
PROPS = ph.BeamProperties.from_material(ph.Section.rectangle(0.01, 0.02), STEEL)
L, G = 0.5, 9.81


def stiffened(which: str, factor: float = 1e4, props=PROPS):
    """The section properties with the bending stiffnesses (``"bending"``), the whole stiffness
    (``"all"``) or nothing (``"none"``) multiplied by ``factor``."""
    K = props.stiffness.copy()
    if which == "bending":
        K[1, 1] *= factor
        K[2, 2] *= factor
    elif which == "all":
        K *= factor
    elif which != "none":
        raise ValueError(f"stiff: 'bending', 'all' or 'none' (got {which!r})")
    return types.SimpleNamespace(stiffness=K, inertia=props.inertia, damping=None)


def pendulum(fidelity: str, theta0: float, props=PROPS, elements: int = 8, mass: str = "consistent"):
    """A link hanging from a hinge about world y at the origin, released at ``theta0`` [rad],
    with element ``mass`` ("consistent" or "lumped"); returns (mechanism, link)."""
    m = ph.Mechanism(gravity=(0, 0, -G))
    down = m.ground.frame_at((0, 0, 0), ph.rotation("y", np.pi / 2))   # local x = world -z
    lk = m.add_flexible_link("rod", L, props, elements=elements, start=down, fidelity=fidelity,
                             mass=mass)
    m.add_pair("hinge", ph.Revolute(axis="y"), down, lk.start, x0=theta0)
    return m, lk


def compound_period(theta0: float, props=PROPS) -> tuple:
    """(exact period, small-amplitude period) [s] of the link as a compound pendulum (the
    section's own rotary inertia about the hinge axis included)."""
    rhoA, rhoIy = props.inertia[3, 3], props.inertia[1, 1]
    w2 = (rhoA * L ** 2 * G / 2) / (rhoA * L ** 3 / 3 + rhoIy * L)
    return 4 / np.sqrt(w2) * ellipk(np.sin(theta0 / 2) ** 2), 2 * np.pi / np.sqrt(w2)


def measured_period(res) -> float:
    """Mean period [s] from the upward zero crossings of the hinge angle (linear interpolation);
    nan with fewer than two crossings."""
    x, t = res.joint("hinge")["x"][:, 0], res.t
    i = np.nonzero((x[:-1] < 0) & (x[1:] >= 0))[0]
    tc = t[i] - x[i] * (t[i + 1] - t[i]) / (x[i + 1] - x[i])
    return float(np.mean(np.diff(tc))) if len(tc) >= 2 else float("nan")


def run(stiff: str = "bending", theta0: float = 1.0, counts=(4, 8, 16)) -> list:
    """One row per model: fidelity, elements, period error, CPU [s] per period, steps, ledger."""
    props = stiffened(stiff)
    T = compound_period(theta0, props)[0]
    rows = []
    for fid, N in [("rigid", counts[0])] + [("nonlinear", n) for n in counts]:
        m, _ = pendulum(fid, theta0, props, N)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", ph.AccuracyWarning)
            c0 = time.process_time()
            res = m.simulate(2.2 * T, T / 200)
            cpu = (time.process_time() - c0) / 2.2
        rows.append(dict(fidelity=fid, elements=N, period_error=measured_period(res) / T - 1,
                         cpu_per_period_s=cpu, steps=int(res.stats["steps"]),
                         ledger_relative=float(res.stats["ledger_relative"]),
                         accuracy_warning=any(issubclass(w.category, ph.AccuracyWarning)
                                              for w in caught)))
    return rows


def main(argv=None) -> list:
    ap = example_parser(__doc__, "4 and 8 elements only")
    ap.add_argument("--stiff", default="bending", choices=("bending", "all", "none"))
    ap.add_argument("--theta0", type=float, default=1.0, help="release angle [rad]")
    a = ap.parse_args(argv)
    rows = run(a.stiff, a.theta0, (4, 8) if a.quick else (4, 8, 16))
    if a.json:
        print(json.dumps(rows))
        return rows
    print(f"pendulum of one 0.5 m steel link, released at {a.theta0:g} rad, stiffness x1e4: {a.stiff}")
    print(f"{'model':>16} {'period error':>13} {'CPU/period [s]':>15} {'steps':>7} {'ledger':>9}")
    for r in rows:
        name = "rigid" if r["fidelity"] == "rigid" else f"nonlinear N={r['elements']}"
        print(f"{name:>16} {r['period_error']:13.2e} {r['cpu_per_period_s']:15.4f} {r['steps']:7d} "
              f"{r['ledger_relative']:9.2e}" + ("  (AccuracyWarning)" if r["accuracy_warning"] else ""))
    return rows


if __name__ == "__main__":
    main(sys.argv[1:])

"""Issue 3 validation: undamped free vibration of a cantilever released from a large deflection
(tip >= 20 % of L): relative drift of the total energy over many periods, for several rtol.

    python benchmarks/validate_energy_drift.py [--periods 100] [--rtol 1e-6 1e-8 1e-10] [--elements 21]

Writes benchmarks/results/energy_drift.json (and prints a table). The Table I beam with
``table1_properties(1.0)`` (axial and torsion not stiffened), clamped at s = 0, a static tip force
3 EI / 4 bends it to ~0.235 L, then it is released at rest.
"""
from __future__ import annotations

import argparse
import json
import os
import platform
import time

import numpy as np

import phmech as ph
from phmech.section import TABLE1, table1_properties


def run(periods: float, rtol: float, N: int, solver: str) -> dict:
    m = ph.Mechanism()
    b = m.add_flexible_link("b", TABLE1["L"], table1_properties(1.0), elements=N)
    m.add_pair("clamp", ph.Fixed(), m.ground, b.start)
    F = 0.25 * 3 * TABLE1["EI"]
    st = m.static(loads=[(b.end, (0, 0, 0, 0, 0, -F), "world")], steps=4)
    tip0 = -st.positions(b)[-1, 2] / TABLE1["L"]
    # the large-amplitude period is measured from the run itself; 0.75 s is the nominal one
    T = periods * 0.75
    t0 = time.process_time()
    r = m.simulate(T, 0.01, rtol=rtol, initial=st, linear_solver=solver)
    cpu = time.process_time() - t0
    E = r.energy["total"]
    z = r.tip(b)[:, 2]
    crossings = np.nonzero((z[:-1] < 0) & (z[1:] >= 0))[0]
    measured_periods = len(crossings)
    return dict(rtol=rtol, N=N, solver=solver, t_end=float(r.t[-1]), tip_deflection_over_L=float(tip0),
                periods_completed=int(measured_periods), E0=float(E[0]),
                max_rel_drift=float(np.max(np.abs(E - E[0])) / E[0]),
                final_rel_drift=float((E[-1] - E[0]) / E[0]), cpu_s=cpu, steps=int(r.stats["steps"]))


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--periods", type=float, default=100.0)
    ap.add_argument("--rtol", type=float, nargs="+", default=[1e-6, 1e-8, 1e-10])
    ap.add_argument("--elements", type=int, default=21)
    ap.add_argument("--solver", default="klu")
    ap.add_argument("--out", default=os.path.join("benchmarks", "results", "energy_drift.json"))
    a = ap.parse_args()
    rows = []
    for rtol in a.rtol:
        row = run(a.periods, rtol, a.elements, a.solver)
        rows.append(row)
        print(f"rtol {rtol:.0e}: {row['periods_completed']} periods, max drift {row['max_rel_drift']:.2e}, "
              f"final {row['final_rel_drift']:+.2e}, {row['steps']} steps, CPU {row['cpu_s']:.1f} s", flush=True)
    os.makedirs(os.path.dirname(a.out), exist_ok=True)
    with open(a.out, "w") as f:
        json.dump(dict(machine=platform.platform(), processor=platform.processor(),
                       phmech=ph.__version__, runs=rows), f, indent=1)
    print(f"wrote {a.out}")


if __name__ == "__main__":
    main()

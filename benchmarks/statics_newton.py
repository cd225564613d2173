"""Static Newton iteration counts and CPU against the number of elements (issue 12's statics
claims): a Table I cantilever under a dead tip load P L^2/EI = 3 (10 load steps) at N = 20 and
1000, the same with 1e4 times stiffer off-plane, axial and shear stiffness (N = 200), and the
roll-up under an end moment 2 pi EI (8 load steps) at N = 21 and 200, soft and stiff.
Writes benchmarks/results/statics_newton.json. Run: .venv/bin/python benchmarks/statics_newton.py"""
import json
import pathlib
import time

import numpy as np

import phmech as ph
from phmech.section import TABLE1, table1_properties

L, EI = TABLE1["L"], TABLE1["EI"]
CASES = [("tip load P L^2/EI = 3", 1.0, 20, "tip", 10), ("tip load P L^2/EI = 3", 1.0, 1000, "tip", 10),
         ("tip load, stiff 1e4", 1e4, 200, "tip", 10), ("roll-up 2 pi EI", 1.0, 21, "moment", 8),
         ("roll-up 2 pi EI", 1.0, 200, "moment", 8), ("roll-up 2 pi EI, stiff 1e4", 1e4, 21, "moment", 8)]


def run_case(name, stiff, n, load, steps) -> dict:
    m = ph.Mechanism()
    b = m.add_flexible_link("b", L, table1_properties(stiff), elements=n)
    m.add_pair("clamp", ph.Fixed(), m.ground, b.start)
    ld = ((b.end, (0, 0, 0, 0, 0, 3 * EI / L**2), "world") if load == "tip"
          else (b.end, (0, -2 * np.pi * EI, 0, 0, 0, 0), "body"))
    t0 = time.process_time()
    s = m.static(loads=[ld], steps=steps)
    return dict(case=name, stiff_factor=stiff, elements=n, load_steps=steps, iterations=int(s.iterations),
                cpu_s=time.process_time() - t0, tip=s.positions(b)[-1].tolist())


def main() -> None:
    rows = []
    for case in CASES:
        rows.append(run_case(*case))
        r = rows[-1]
        print(f"{r['case']:<28} N = {r['elements']:5d}: {r['iterations']:5d} iterations, {r['cpu_s']:.3f} s CPU")
    out = pathlib.Path(__file__).parent / "results" / "statics_newton.json"
    out.parent.mkdir(exist_ok=True)
    out.write_text(json.dumps(rows, indent=1))
    print("wrote", out)


if __name__ == "__main__":
    main()

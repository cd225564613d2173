"""CPU of modes(5) against the number of elements, dense LAPACK on the reduced problem against
subspace iteration on the sparse KKT system (csrc/analyze/modes_sparse.c), on the Table I cantilever
(table1_properties(), clamped), with the error of each against the exact Timoshenko frequencies
and the dense-sparse difference (the crossover, which sets PHM_SPARSE_MODES_MIN, is measured by
benchmarks/modes_crossover.py, from smaller models). Writes
benchmarks/results/modes_scaling.json. Run: .venv/bin/python benchmarks/modes_scaling.py [--quick]"""
import json
import pathlib
import sys
import time

import numpy as np

import phmech as ph
from phmech import _core, timoshenko
from phmech.section import TABLE1, table1_properties
from phmech import _model

L = TABLE1["L"]
REF = timoshenko.frequencies(5, L, TABLE1["EI"], TABLE1["kGA"], TABLE1["rhoA"], TABLE1["rhoI"])
DENSE, SPARSE = 1, 2


def cpu_median(f, repeat=3):
    ts = []
    for _ in range(repeat):
        t0 = time.process_time()
        out = f()
        ts.append(time.process_time() - t0)
    return float(np.median(ts)), out


def main() -> None:
    quick = "--quick" in sys.argv
    sizes = [25, 50, 100, 150, 200, 300] if quick else [25, 50, 100, 150, 200, 300, 500, 1000]
    rows = []
    for n in sizes:
        m = ph.Mechanism()
        b = m.add_flexible_link("b", L, table1_properties(), elements=n)
        m.add_pair("clamp", ph.Fixed(), m.ground, b.start)
        model = _model.build(m)
        row = dict(elements=n, carrier_coordinates=6 * (n + 1))
        for name, method in (("dense", DENSE), ("sparse", SPARSE)):
            if name == "dense" and n > 500:
                continue   # minutes of CPU, O(N^3)
            cpu, r = cpu_median(lambda: _core.model_modes(model, 5, None, None, 0.0, method))
            row[f"{name}_cpu_s"] = cpu
            row[f"{name}_omega"] = r[0][:5].tolist()
            row[f"{name}_error_max"] = float(np.max(np.abs(r[0][:5] / REF - 1)))
        if "dense_omega" in row:
            row["dense_sparse_rel_diff"] = float(np.max(np.abs(np.array(row["sparse_omega"]) / row["dense_omega"] - 1)))
        rows.append(row)
        print(f"N = {n:5d}: dense {row.get('dense_cpu_s', float('nan')):.4f} s, sparse {row['sparse_cpu_s']:.4f} s, "
              f"error dense {row.get('dense_error_max', float('nan')):.3e} sparse {row['sparse_error_max']:.3e}, "
              f"difference {row.get('dense_sparse_rel_diff', float('nan')):.2e}", flush=True)
    out = pathlib.Path(__file__).parent / "results" / "modes_scaling.json"
    out.parent.mkdir(exist_ok=True)
    out.write_text(json.dumps(rows, indent=1))
    print("wrote", out)


if __name__ == "__main__":
    main()

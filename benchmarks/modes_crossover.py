"""Where the sparse modes path (subspace iteration on the KKT system with its count of the
eigenvalues below the shift, csrc/analyze/modes_sparse.c) becomes faster than the dense one: core-only CPU
of phm_modes by method, dense (1) and sparse (2) called alternately, medians of
time.thread_time(), on the Table I cantilever (benchmarks/run.py's phmech_cantilever(N), 6 (N + 1)
carrier coordinates) and a hanging chain of rigid bars at its static equilibrium (6 per bar),
for 2, 5, 10 and 20 modes. The crossover sets PHM_SPARSE_MODES_MIN (csrc/include/phmech_types.h).
Run with OPENBLAS_NUM_THREADS=1: .venv/bin/python benchmarks/modes_crossover.py [--quick]"""
import sys
import time
import warnings

import numpy as np

import phmech as ph
from phmech import _core, se3
from phmech import _model

from run import phmech_cantilever

DENSE, SPARSE = 1, 2


def chain(n):
    """A hanging chain of n bars (0.3 m, 1 kg) on revolute pairs, at its static equilibrium."""
    m, prev = ph.Mechanism(gravity=(9.81, 0, 0)), None
    for i in range(n):
        b = m.add_rigid_body(f"b{i}", 1.0, np.diag([1e-4, 0.0075, 0.0075]), com=(0.15, 0, 0))
        a = m.ground if prev is None else ph.Frame(prev.carrier, se3.translation([0.3, 0, 0]))
        m.add_pair(f"p{i}", ph.Revolute(), a, b)
        prev = b
    st = m.static(check_stability=False)
    return _model.build(m), st.poses, st.constraint_wrenches, 6 * n


def cantilever(n):
    m, _ = phmech_cantilever(n)
    return _model.build(m), None, None, 6 * (n + 1)


def cpu(model, poses, lam, n, method):
    t0 = time.thread_time()
    _core.model_modes(model, n, poses, lam, 0.0, method)
    return time.thread_time() - t0


def main() -> None:
    quick = "--quick" in sys.argv
    reps = 7 if quick else 21
    cases = [("cantilever", cantilever, [8, 10, 11, 12, 13, 14, 15, 20, 30, 49]),
             ("chain", chain, [20, 26, 40, 60])]
    for name, make, sizes in cases:
        for size in sizes[::3] if quick else sizes:
            model, poses, lam, coords = make(size)
            for n in (2, 5, 10, 20):
                td, ts = [], []
                for _ in range(reps):
                    td.append(cpu(model, poses, lam, n, DENSE))
                    ts.append(cpu(model, poses, lam, n, SPARSE))
                d, s = 1e3 * np.median(td), 1e3 * np.median(ts)
                od = _core.model_modes(model, n, poses, lam, 0.0, DENSE)[0]
                osp = _core.model_modes(model, n, poses, lam, 0.0, SPARSE)[0]
                print(f"{name:10s} {size:3d} ({coords:4d} coordinates), {n:2d} modes: dense {d:8.3f} ms, "
                      f"sparse {s:8.3f} ms ({d / s:5.2f}x), differ by {np.max(np.abs(osp / od - 1)):.1e}",
                      flush=True)


if __name__ == "__main__":
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ph.StabilityWarning)
        main()

"""Model set-up time at N = 1000 elements (issue 11): a cantilever of N se3 elements clamped to
the ground by a Fixed pair, a rigid tip body welded to its free end, under gravity.

    python benchmarks/setup_time.py [--elements N] [--reps R] [--calls simulate static modes]
                                    [--label NAME]

Times, each a median over R fresh mechanisms (wall clock and process CPU):

- ``simulate``: ``m.simulate(1e-3, 1e-3)`` (one output interval: set-up dominates);
- ``static``: ``m.static()``;
- ``modes``: ``m.modes(3)`` (at N = 1000 this is minutes of LAPACK's dense dsygvx on the reduced
  6000 x 6000 problem with the reference BLAS, not set-up: ``--reps-modes``, default 1).

and splits each call into the C core (every call into ``phmech._core``, by function:
``model_new`` is phm_model_create; ``model_simulate`` holds the DAE set-up -- dae_init,
consistent initial values, the sparsity pattern and colouring of csrc/dae/jacobian.c -- and the
one output interval), the Python topology (``phmech.topology``'s entry points, less the core calls
they make) and the rest of Python (marshalling, checks, results). Writes
``benchmarks/results/setup_time[_LABEL].json``; with ``--calls`` the other calls' entries are kept
from the existing file (as bench_scaling.py's ``--only``).
"""
from __future__ import annotations

import argparse
import functools
import json
import os
import statistics
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
RESULTS = os.path.join(HERE, "results")

import phmech as ph  # noqa: E402
from phmech import _core, topology  # noqa: E402
from phmech.section import table1_properties  # noqa: E402


class Split:
    """Wall time spent in the core's functions and in the topology's entry points (``clock``:
    another clock, e.g. ``time.process_time``: benchmarks/bench_overhead.py)."""

    def __init__(self, clock=time.perf_counter):
        self.core, self.topo, self.topo_core, self._in_topo = {}, 0.0, 0.0, 0
        self._saved = []
        self.clock = clock

    def _wrap_core(self, name, fn):
        @functools.wraps(fn)
        def timed(*a, **k):
            t0 = self.clock()
            try:
                return fn(*a, **k)
            finally:
                dt = self.clock() - t0
                self.core[name] = self.core.get(name, 0.0) + dt
                if self._in_topo:
                    self.topo_core += dt
        return timed

    def _wrap_topo(self, fn):
        @functools.wraps(fn)
        def timed(*a, **k):
            outer = self._in_topo == 0
            self._in_topo += 1
            t0 = self.clock()
            try:
                return fn(*a, **k)
            finally:
                self._in_topo -= 1
                if outer:
                    self.topo += self.clock() - t0
        return timed

    def __enter__(self):
        for name in dir(_core):
            fn = getattr(_core, name)
            if name.startswith("model_") and callable(fn):
                self._saved.append((_core, name, fn))
                setattr(_core, name, self._wrap_core(name, fn))
        for name in ("place_tree", "close_loops", "close_rates", "redundant_rows"):
            fn = getattr(topology, name, None)
            if fn is not None:
                self._saved.append((topology, name, fn))
                setattr(topology, name, self._wrap_topo(fn))
        return self

    def __exit__(self, *exc):
        for mod, name, fn in reversed(self._saved):
            setattr(mod, name, fn)


def cantilever(N: int):
    m = ph.Mechanism(gravity=(0.0, 0.0, -9.81))
    link = m.add_flexible_link("beam", 1.0, table1_properties(1.0), elements=N)
    m.add_pair("clamp", ph.Fixed(), m.ground, link.start)
    tip = m.add_rigid_body("tip", 0.05, np.diag([1e-5, 1e-5, 1e-5]))
    m.add_pair("weld", ph.Fixed(), link.end, tip)
    return m


CALLS = {"simulate": lambda m: m.simulate(1e-3, 1e-3),
         "static": lambda m: m.static(),
         "modes": lambda m: m.modes(3)}


def measure(N: int, calls, reps: int, reps_modes: int) -> dict:
    out = {}
    for name in calls:
        call, runs = CALLS[name], []
        for rep in range(reps_modes if name == "modes" else reps):
            t0 = time.perf_counter()
            m = cantilever(N)
            build = time.perf_counter() - t0
            with Split() as s:
                w0, c0 = time.perf_counter(), time.process_time()
                call(m)
                wall, cpu = time.perf_counter() - w0, time.process_time() - c0
            core = sum(s.core.values())
            runs.append(dict(wall_s=wall, cpu_s=cpu, build_mechanism_s=build, core_s=core,
                             core_by_function_s=dict(s.core), topology_python_s=s.topo - s.topo_core,
                             other_python_s=wall - core - (s.topo - s.topo_core)))
            print(f"  {name} run {rep + 1}: wall {wall:.3f} s, core {core:.3f} s", flush=True)
        med = {k: statistics.median(r[k] for r in runs)
               for k in ("wall_s", "cpu_s", "build_mechanism_s", "core_s", "topology_python_s",
                         "other_python_s")}
        names = sorted({k for r in runs for k in r["core_by_function_s"]})
        med["core_by_function_s"] = {k: statistics.median(r["core_by_function_s"].get(k, 0.0) for r in runs)
                                     for k in names}
        out[name] = dict(median=med, runs=runs)
        print(f"{name:9s} wall {med['wall_s']:.3f} s (cpu {med['cpu_s']:.3f}): core {med['core_s']:.3f} "
              f"[" + ", ".join(f"{k} {v:.3f}" for k, v in med["core_by_function_s"].items()) + "], "
              f"topology (Python) {med['topology_python_s']:.3f}, other Python {med['other_python_s']:.3f}",
              flush=True)
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--elements", type=int, default=1000)
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--reps-modes", type=int, default=1)
    ap.add_argument("--calls", nargs="*", default=list(CALLS), choices=list(CALLS))
    ap.add_argument("--label", default="", help="suffix of the JSON file (e.g. before, after)")
    a = ap.parse_args()
    path = os.path.join(RESULTS, "setup_time" + (f"_{a.label}" if a.label else "") + ".json")
    load0 = os.getloadavg()
    calls = measure(a.elements, a.calls, a.reps, a.reps_modes)
    for name, entry in calls.items():
        entry.update(load_average_before=load0, load_average_after=os.getloadavg())
    if os.path.exists(path):
        with open(path) as f:
            old = json.load(f)
        if old.get("elements") == a.elements:
            calls = {**old["calls"], **calls}
    res = dict(elements=a.elements, reps=a.reps, reps_modes=a.reps_modes, cpus=os.cpu_count(),
               phmech=ph.__version__, calls={k: calls[k] for k in CALLS if k in calls})
    os.makedirs(RESULTS, exist_ok=True)
    with open(path, "w") as f:
        json.dump(res, f, indent=1)
    print(f"wrote {path}")


if __name__ == "__main__":
    sys.exit(main())

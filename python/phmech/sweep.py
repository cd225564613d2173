"""Parameter sweeps on Dask: one mechanism per point of a grid or of a list of samples, built and
analysed on the workers of a local or remote Dask cluster (or in-process), collected into an
xarray.Dataset with the error message of every failed point (docs/user_guide.md, "Parameter
sweeps")."""
from __future__ import annotations

import functools
import itertools
import os
import time
from typing import Any, Callable, Mapping, Optional, Sequence, Union

import numpy as np

from ._errors import ModelError

__all__ = ["sweep"]

#: the value of ``client=`` that runs the points one after another in this process
SERIAL = "serial"


def _run_point(build: Callable, analysis: Callable, point: dict) -> tuple:
    """One point: ``analysis(build(**point))`` -> (True, {name: float/complex array}, CPU s) or
    (False, "ErrorType: message", CPU s). Runs on a worker; never raises for the point's own
    errors."""
    c0 = time.process_time()
    ok, val = _evaluate(build, analysis, point)
    return ok, val, time.process_time() - c0


def _evaluate(build: Callable, analysis: Callable, point: dict) -> tuple:
    try:
        out = analysis(build(**point))
        if not isinstance(out, Mapping):
            out = {"result": out}
        vals = {}
        for k, v in out.items():
            a = np.asarray(v)
            if a.dtype.kind not in "biufc":
                raise TypeError(f"analysis returned {k!r} = {v!r}: expected numbers or arrays of numbers")
            vals[str(k)] = a.astype(complex if a.dtype.kind == "c" else float)
        return True, vals
    except Exception as e:  # noqa: BLE001 -- every error of a point is recorded, none is lost
        return False, f"{type(e).__name__}: {e}"


def _points(params, samples: bool) -> tuple:
    """(points, dims, coords, shape): the list of point dicts in C order, the dimension names, the
    coordinate arrays and the result shape, for a grid or for samples."""
    if isinstance(params, (list, tuple)):          # a list of dicts: samples
        if not params or not all(isinstance(p, Mapping) for p in params):
            raise ModelError("sweep: params as a list must be a non-empty list of dicts "
                             "(name -> value), one per sample")
        names = list(params[0])
        for i, p in enumerate(params):
            if list(p) != names:
                raise ModelError(f"sweep: sample {i} has parameters {sorted(p)}, sample 0 has "
                                 f"{sorted(names)}")
        cols = {n: np.asarray([p[n] for p in params]) for n in names}
        return [dict(p) for p in params], ["sample"], {"sample": np.arange(len(params)), **{n: ("sample", c) for n, c in cols.items()}}, (len(params),)
    if not isinstance(params, Mapping) or not params:
        raise ModelError("sweep: params must be a non-empty dict name -> values (a grid, or "
                         "equal-length arrays with samples=True) or a list of dicts (samples)")
    names = [str(n) for n in params]
    cols = {}
    for n, v in params.items():
        a = np.asarray(v)
        if a.ndim != 1 or a.size == 0:
            raise ModelError(f"sweep: parameter {n!r} needs a non-empty 1-D sequence of values "
                             f"(got shape {a.shape})")
        cols[str(n)] = a
    if samples:
        sizes = {n: c.size for n, c in cols.items()}
        if len(set(sizes.values())) != 1:
            raise ModelError(f"sweep: with samples=True every parameter needs the same number of "
                             f"values (got {sizes})")
        n = next(iter(sizes.values()))
        pts = [{k: c[i].item() for k, c in cols.items()} for i in range(n)]
        return pts, ["sample"], {"sample": np.arange(n), **{k: ("sample", c) for k, c in cols.items()}}, (n,)
    pts = [dict(zip(names, (x.item() for x in combo)))
           for combo in itertools.product(*(cols[n] for n in names))]
    return pts, names, dict(cols), tuple(c.size for c in cols.values())


def _client_for(client, scheduler, workers):
    """(client, owned objects to close): the user's Client, one connected to ``scheduler``, or a
    new local cluster of ``workers`` single-threaded processes."""
    from distributed import Client, LocalCluster

    if client is not None:
        if not isinstance(client, Client):
            raise ModelError(f"sweep: client must be a distributed.Client, {SERIAL!r} or None "
                             f"(got {client!r})")
        if scheduler is not None:
            raise ModelError("sweep: give client= or scheduler=, not both")
        return client, []
    if scheduler is not None:
        c = Client(scheduler)
        return c, [c]
    n = workers or os.cpu_count() or 1
    cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                           dashboard_address=":0")
    c = Client(cluster)
    return c, [c, cluster]


def sweep(build: Callable[..., Any], params: Union[Mapping[str, Sequence], Sequence[Mapping]],
          analysis: Callable[[Any], Any], *, samples: bool = False, client=None,
          scheduler: Optional[str] = None, workers: Optional[int] = None,
          progress: bool = True):
    """Run ``analysis(build(**point))`` at every point of a parameter study; return an
    ``xarray.Dataset``.

    ``params``: a grid ``{name: values}`` (the Cartesian product: one dimension per parameter,
    in the dict's order, with the values as coordinates); with ``samples=True``, a dict of
    equal-length arrays, one sample per index; or a list of dicts, one per sample. Samples have
    one dimension ``sample`` (0, 1, ...) with the parameters as coordinates along it.

    ``build(**point)`` returns a Mechanism, ``analysis(mechanism)`` a number, an array or a dict
    name -> number/array (same shapes at every point); a non-dict result is the variable
    ``result``. An array's own axes become dimensions ``<name>_dim_0``, ... Both functions run on
    the workers: Dask pickles them with cloudpickle (functions of ``__main__``, lambdas and
    closures by value, functions of modules by reference, so a remote worker must be able to
    import those modules; a local cluster's workers share this process's ``sys.path``).

    Where to run: ``client=None`` and ``scheduler=None`` start a ``distributed.LocalCluster``
    of ``workers`` (default: one per core) single-threaded worker processes for this call and
    close it afterwards; ``scheduler="tcp://host:8786"`` connects to a running cluster;
    ``client=`` an existing ``distributed.Client`` is used as is (keep one for many sweeps: a
    local cluster takes seconds to start); ``client="serial"`` runs the points one after another
    in this process (debugging: breakpoints and tracebacks work).

    A point that raises is recorded, never lost with the others: the variable ``error`` holds
    ``"ErrorType: message"`` for it ("" for the points that succeeded) and its numbers are NaN;
    a worker that dies on a point is recorded the same way. ``progress``: a tqdm progress bar
    (terminal or Jupyter). ``attrs``: ``failed`` (number of failed points), ``wall_time`` [s],
    ``workers``."""
    import xarray as xr
    from tqdm.auto import tqdm

    if not callable(build) or not callable(analysis):
        raise ModelError("sweep: build and analysis must be callables (build(**point) -> "
                         "Mechanism, analysis(mechanism) -> numbers)")
    pts, dims, coords, shape = _points(params, samples)
    n = len(pts)
    run = functools.partial(_run_point, build, analysis)
    results: list = [None] * n
    t0 = time.perf_counter()
    bar = tqdm(total=n, disable=not progress, desc="sweep", unit="point")
    try:
        if isinstance(client, str):
            if client != SERIAL:
                raise ModelError(f"sweep: client must be a distributed.Client, {SERIAL!r} or "
                                 f"None (got {client!r})")
            nworkers = 0
            for i, p in enumerate(pts):
                results[i] = run(p)
                bar.update(1)
        else:
            from distributed import as_completed

            cl, owned = _client_for(client, scheduler, workers)
            try:
                nworkers = len(cl.scheduler_info().get("workers", {}))
                futures = cl.map(run, pts, pure=False)
                index = {f.key: i for i, f in enumerate(futures)}
                for fut in as_completed(futures):
                    i = index[fut.key]
                    try:
                        results[i] = fut.result()
                    except Exception as e:  # noqa: BLE001 -- a killed worker, an unpicklable result
                        results[i] = (False, f"{type(e).__name__}: {e}", 0.0)
                    bar.update(1)
                    fut.release()
            finally:
                for o in owned:
                    o.close()
    finally:
        bar.close()
    wall = time.perf_counter() - t0
    return _dataset(xr, results, dims, coords, shape, wall, nworkers)


def _dataset(xr, results, dims, coords, shape, wall, nworkers):
    """The Dataset of the points' results (C order over ``shape``)."""
    cpu = float(sum(r[2] for r in results))
    results = [r[:2] for r in results]
    n = len(results)
    shapes: dict = {}                               # variable -> {shape: count, dtype}
    for ok, v in results:
        if ok:
            for k, a in v.items():
                c = shapes.setdefault(k, {})
                c[a.shape] = c.get(a.shape, 0) + 1
    # the most common shape of each variable is its shape; points that differ have failed
    templ = {k: np.zeros(max(c, key=c.get)) for k, c in shapes.items()}
    for ok, v in results:
        if ok:
            for k, a in v.items():
                if a.dtype.kind == "c":
                    templ[k] = templ[k].astype(complex)
    errors = [("" if ok else v) for ok, v in results]
    data = {}
    for k, a0 in templ.items():
        out = np.full((n,) + a0.shape, np.nan, dtype=a0.dtype if a0.dtype.kind == "c" else float)
        for i, (ok, v) in enumerate(results):
            if not ok:
                continue
            a = v.get(k)
            if a is None or a.shape != a0.shape:
                errors[i] = (f"ValueError: analysis returned {k!r} with shape "
                             f"{None if a is None else a.shape}, other points {a0.shape}")
                continue
            out[i] = a
        data[k] = out
    for k, out in data.items():                     # points found inconsistent: no numbers
        for i, e in enumerate(errors):
            if e:
                out[i] = np.nan
    ds = xr.Dataset(
        {k: (list(dims) + [f"{k}_dim_{j}" for j in range(out.ndim - 1)], out.reshape(shape + out.shape[1:]))
         for k, out in data.items()},
        coords=coords)
    ds["error"] = (list(dims), np.array(errors, dtype=str).reshape(shape))
    ds.attrs.update(failed=int(sum(bool(e) for e in errors)), wall_time=wall, cpu_time=cpu,
                    workers=nworkers)
    return ds

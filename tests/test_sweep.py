"""phmech.sweep: grids and samples on a local Dask cluster (one for the module), failing points
recorded without losing the others, the xarray layout, and the serial mode as the reference.

The studies are tiny versions of examples/sweeps.py: a cantilever's first bending frequency
against the Euler-Bernoulli frequency equation with a tip mass, and a Monte-Carlo of the leaf
spring's first frequency against the paper's formula corrected for the leaves' mass."""
import functools
import os
import sys

import numpy as np
import pytest

import phmech as ph

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "examples"))
import sweeps  # noqa: E402  (examples/sweeps.py)

distributed = pytest.importorskip("distributed")
xr = pytest.importorskip("xarray")


@pytest.fixture(scope="module")
def client():
    """Two single-threaded worker processes, shared by the module's tests (they inherit
    sys.path, so examples/sweeps.py imports on them)."""
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=":0") as cl, distributed.Client(cl) as c:
        yield c


def f1_only(m):
    return float(m.modes(1).frequency[0])


def test_grid_cantilever_tip_mass(client):
    """A 2-D grid (tip mass x elements): one dimension per parameter with its values as
    coordinates; the first frequency converges to the Euler-Bernoulli root (second order in the
    element size: 16 elements within 0.2 %, closer than 8) and equals a direct modes() call."""
    masses = [0.005, 0.02, 0.05]
    ds = ph.sweep(sweeps.cantilever, {"tip_mass": masses, "elements": [8, 16]},
                  sweeps.bending_frequencies, client=client, progress=False)
    assert isinstance(ds, xr.Dataset)
    assert ds["frequency"].dims == ("tip_mass", "elements", "frequency_dim_0")
    assert ds["frequency"].shape == (3, 2, 3)
    np.testing.assert_array_equal(ds["tip_mass"].values, masses)
    np.testing.assert_array_equal(ds["elements"].values, [8, 16])
    assert ds["error"].dims == ("tip_mass", "elements") and (ds["error"].values == "").all()
    assert ds.attrs["failed"] == 0 and ds.attrs["workers"] == 2
    assert 0 < ds.attrs["cpu_time"] < 2 * ds.attrs["wall_time"] + 1.0    # two workers at most
    ref = np.array([sweeps.euler_bernoulli_tip_mass(M, 1)[0] for M in masses])
    err8 = np.abs(ds["frequency"].sel(elements=8)[:, 0] / ref - 1)
    err16 = np.abs(ds["frequency"].sel(elements=16)[:, 0] / ref - 1)
    assert np.all(err16 < 2e-3) and np.all(err16 < err8)
    direct = sweeps.bending_frequencies(sweeps.cantilever(0.02, 16))["frequency"]
    np.testing.assert_allclose(ds["frequency"].sel(tip_mass=0.02, elements=16), direct, rtol=1e-12)


def test_failing_point_recorded_others_equal_serial(client):
    """A negative tip mass makes add_rigid_body raise ModelError on the worker: that point's
    error holds the type and the message and its numbers are NaN; the other points are there and
    equal to an in-process (client="serial") run of the same sweep."""
    params = {"tip_mass": [0.01, -1.0, 0.03]}
    build = functools.partial(sweeps.cantilever, elements=6)
    ds = ph.sweep(build, params, f1_only, client=client, progress=False)
    ser = ph.sweep(build, params, f1_only, client="serial", progress=False)
    err = ds["error"].values
    assert err[0] == "" and err[2] == ""
    assert err[1].startswith("ModelError: ") and "mass" in err[1]
    assert ds.attrs["failed"] == 1
    assert np.isnan(ds["result"].values[1])
    np.testing.assert_array_equal(ds["result"].values[[0, 2]], ser["result"].values[[0, 2]])
    np.testing.assert_array_equal(ser["error"].values, err)
    assert ds["result"].values[0] > ds["result"].values[2] > 0        # heavier tip: lower frequency


def test_samples_leaf_spring_montecarlo(client):
    """Samples as a dict of equal-length arrays: one `sample` dimension with the parameters as
    coordinates along it; the leaf spring's first frequency follows the paper's formula with
    the leaves' mass correction (examples/leaf_spring.py) within 1 % at every sample (10
    elements per leaf: 0.5 % at the nominal values, docs/leaf_spring.md), by the same factor at
    every sample (the mesh's error is a fixed factor of the frequency: spread below 1e-3), and
    samples given as a list of dicts give the same dataset."""
    smp = sweeps.monte_carlo_samples(4, seed=3)
    analysis = functools.partial(sweeps.leaf_response, t_end=0.0)
    build = functools.partial(sweeps.leaf_spring, elements=10)
    ds = ph.sweep(build, smp, analysis, samples=True, client=client, progress=False)
    assert ds["f1"].dims == ("sample",) and ds["error"].dims == ("sample",)
    np.testing.assert_array_equal(ds["sample"].values, np.arange(4))
    np.testing.assert_array_equal(ds["thickness"].values, smp["thickness"])
    assert ds["thickness"].dims == ("sample",)
    ref = sweeps.f_formula(smp["thickness"], smp["plate_mass"])
    ratio = ds["f1"].values / ref
    assert np.all(np.abs(ratio - 1) < 0.01) and np.ptp(ratio) < 1e-3
    # the frequency spread follows the parameters: thicker leaves, higher frequency
    order = np.argsort(ref)
    assert np.all(np.diff(ds["f1"].values[order]) > 0)
    as_list = [dict(thickness=t, plate_mass=mp) for t, mp in zip(smp["thickness"], smp["plate_mass"])]
    ds2 = ph.sweep(build, as_list, analysis, client=client, progress=False)
    xr.testing.assert_identical(ds.drop_attrs(), ds2.drop_attrs())


def test_arguments_refused():
    with pytest.raises(ph.ModelError, match="same number of values"):
        ph.sweep(sweeps.cantilever, {"tip_mass": [1, 2], "elements": [3]}, f1_only, samples=True,
                 client="serial")
    with pytest.raises(ph.ModelError, match="client must be"):
        ph.sweep(sweeps.cantilever, {"tip_mass": [1]}, f1_only, client="threads")
    with pytest.raises(ph.ModelError, match="1-D"):
        ph.sweep(sweeps.cantilever, {"tip_mass": [[1, 2]]}, f1_only, client="serial")


def test_inconsistent_result_shape_is_an_error():
    """A point whose analysis returns another shape than the others is recorded as failed."""
    def analysis(m):
        n = 2 if m.modes(1).frequency[0] > 10 else 3
        return {"f": m.modes(n).frequency}

    ds = ph.sweep(functools.partial(sweeps.cantilever, elements=4), {"tip_mass": [0.005, 0.5]},
                  analysis, client="serial", progress=False)
    assert ds["error"].values[0] == "" and "shape" in ds["error"].values[1]
    assert np.all(np.isfinite(ds["f"].values[0])) and np.all(np.isnan(ds["f"].values[1]))


def test_scheduler_address(client):
    """scheduler= connects a client of its own to a running cluster: the same numbers."""
    params = {"tip_mass": [0.01, 0.03]}
    build = functools.partial(sweeps.cantilever, elements=6)
    a = ph.sweep(build, params, f1_only, scheduler=client.scheduler.address, progress=False)
    b = ph.sweep(build, params, f1_only, client="serial", progress=False)
    np.testing.assert_array_equal(a["result"].values, b["result"].values)
    assert a.attrs["workers"] == 2 and b.attrs["workers"] == 0

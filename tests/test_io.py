"""Saving and loading models (JSON), results out (xarray, netCDF, pandas, pickle) and
checkpoints (python/phmech/io.py, docs/user_guide.md "Saving, loading and exporting").

The reference of a round trip is the original itself: a loaded model must give bit-identical
results (np.array_equal, not a tolerance), a result read back must equal the one written. The
models are the paper's case studies, built by the examples' own builders (as tests/paper does)."""
import json
import os
import pickle
import shutil
import sys
import warnings

import numpy as np
import pytest

import phmech as ph

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "examples"))
import leaf_spring as ls  # noqa: E402
import manipulator as M  # noqa: E402


def manipulator():
    m, _ = M.build(M.ManipulatorParams(), elements=2, ff=(1.0, 0.5, 0.5, 0.1))
    return m


def leaf_spring():
    m, _ = ls.build(ls.default_params(), elements=3, pulse=ph.Pulse(0.0, 0.01, 50.0),
                    mounting="revolute")
    return m


def pendulum(torque_at=None):
    """A rigid pendulum on a revolute joint; ``torque_at`` [s]: a 1e30 N m torque from then on,
    which makes every integrator fail there (tests/test_default_integrator.py)."""
    m = ph.Mechanism(gravity=(0, 0, -9.81))
    b = m.add_rigid_body("b", 1.0, np.diag([1e-3, 1e-2, 1e-2]), com=(0.5, 0, 0))
    act = None if torque_at is None else ph.Effort(
        law=ph.Table([0, torque_at, torque_at + 1e-9, 1], [0, 0, 1e30, 1e30]))
    m.add_pair("j", ph.Revolute("y"), m.ground, b, actuator=act, x0=0.3)
    return m


def assert_same(a, b, what=""):
    """Two results (or their parts) equal: arrays bit for bit, dicts, lists, dataclasses."""
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        assert np.shape(a) == np.shape(b) and np.array_equal(a, b), what
    elif isinstance(a, dict):
        assert list(a) == list(b), what
        for k in a:
            assert_same(a[k], b[k], f"{what}[{k!r}]")
    elif isinstance(a, (list, tuple)):
        assert type(a) is type(b) and len(a) == len(b), what
        for i, (x, y) in enumerate(zip(a, b)):
            assert_same(x, y, f"{what}[{i}]")
    elif hasattr(a, "__dataclass_fields__"):
        assert type(a) is type(b), what
        for f in a.__dataclass_fields__:
            assert_same(getattr(a, f), getattr(b, f), f"{what}.{f}")
    elif isinstance(a, float) and isinstance(b, float) and np.isnan(a):
        assert np.isnan(b), what      # NaN: not computed (StaticResult.lowest_omega)
    else:
        assert a == b, what


def analyses(m):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return (m.simulate(0.02, 0.01), m.modes(4), m.static(steps=2))


@pytest.mark.parametrize("build", [manipulator, leaf_spring], ids=["manipulator", "leaf_spring"])
def test_saved_model_gives_bit_identical_results(build, tmp_path):
    m = build()
    path = tmp_path / "model.json"
    m.save(path)
    doc = json.loads(path.read_text())
    assert doc["format"] == "phmech-model" and doc["schema_version"] == ph.io.SCHEMA_VERSION
    loaded = ph.load(path)
    sim, modes, static = analyses(m)
    sim2, modes2, static2 = analyses(loaded)
    for name in ("t", "poses", "twists", "constraint_wrenches", "joints", "joint_rates", "efforts",
                 "pair_wrenches"):
        assert np.array_equal(getattr(sim, name), getattr(sim2, name)), name
    assert_same(sim.energy, sim2.energy) and assert_same(sim.port_energy, sim2.port_energy)
    assert len(sim.t) == 3 and sim.stats["energy_scale"] > 0   # it moved
    for name in ("omega", "damping_ratio", "shapes"):
        assert np.array_equal(getattr(modes, name), getattr(modes2, name)), name
    assert np.array_equal(static.poses, static2.poses)
    assert np.array_equal(static.constraint_wrenches, static2.constraint_wrenches)
    # and the loaded model saves to the same file
    loaded.save(tmp_path / "again.json")
    assert json.loads((tmp_path / "again.json").read_text()) == doc


def test_settings_and_arguments_are_recorded_as_given(tmp_path):
    m = ph.Mechanism(gravity=(0, 0, -9.81))
    leaf = m.add_flexible_link("leaf", 0.3, ph.BeamProperties.from_material(
        ph.Section.tube(0.02, 0.018), ph.Material(70e9, 0.33, 2700.0)), elements=3)
    m.add_pair("clamp", ph.Fixed(), "ground", leaf.start)
    b = m.add_rigid_body("b", 0.5, np.eye(3) * 1e-3)
    m.add_pair("p", ph.Prismatic(axis=(1.0, 1.0, 0.0)), leaf.node(-1), b, x0=0.01,
               actuator=ph.Spring(k=100.0, c=0.5))
    m.add_spring_damper("s", "ground", b, 10.0, point_a=(0.1, 0, 0))
    m.add_distributed_load("q", leaf, (0.0, 0.0, -3.0), law=ph.Cycloidal(1.0, 0.0, 0.05))
    m.gravity = (0.0, -1.0, 0.0)   # a setting changed after the calls
    m.strict = True
    m.save(tmp_path / "m.json")
    loaded = ph.load(tmp_path / "m.json")
    assert np.array_equal(loaded.gravity, [0.0, -1.0, 0.0]) and loaded.strict
    r1, r2 = m.simulate(0.01, 0.005), loaded.simulate(0.01, 0.005)
    assert np.array_equal(r1.poses, r2.poses) and np.array_equal(r1.joints, r2.joints)
    text = (tmp_path / "m.json").read_text()
    assert '"$type": "Frame"' in text and '"link": "leaf"' in text and '"node": 3' in text


def test_newer_schema_and_other_files_are_refused(tmp_path):
    m = pendulum()
    m.save(tmp_path / "m.json")
    doc = json.loads((tmp_path / "m.json").read_text())
    doc["schema_version"] = ph.io.SCHEMA_VERSION + 1
    (tmp_path / "new.json").write_text(json.dumps(doc))
    with pytest.raises(ph.ModelError, match=rf"schema version {ph.io.SCHEMA_VERSION + 1}.*reads "
                                            rf"schema versions up to {ph.io.SCHEMA_VERSION}"):
        ph.load(tmp_path / "new.json")
    (tmp_path / "other.json").write_text('{"hello": 1}')
    with pytest.raises(ph.ModelError, match="not a phmech model"):
        ph.load(tmp_path / "other.json")
    (tmp_path / "text.json").write_text("not json")
    with pytest.raises(ph.ModelError, match="not a phmech model"):
        ph.load(tmp_path / "text.json")
    doc["schema_version"] = 1
    doc["calls"].append({"method": "__init__", "args": {}})   # only builder methods replay
    (tmp_path / "evil.json").write_text(json.dumps(doc))
    with pytest.raises(ph.ModelError, match="unknown method '__init__'"):
        ph.load(tmp_path / "evil.json")


def test_what_cannot_be_saved_is_refused_at_save_time(tmp_path):
    class Props:   # a duck-typed properties object: accepted by the builder, not by a file
        stiffness = np.diag([1.0, 1.0, 1.0, 1e6, 1e6, 1e6])
        inertia = np.diag([1e-6, 1e-6, 1e-6, 0.1, 0.1, 0.1])
    m = ph.Mechanism()
    m.add_flexible_link("leaf", 0.2, Props(), elements=2)
    with pytest.raises(ph.ModelError, match=r"add_flexible_link\('leaf'\): argument 'properties' "
                                            r"is a .*Props object"):
        m.save(tmp_path / "m.json")
    assert not (tmp_path / "m.json").exists()
    # a description changed behind the builder's back would load as something else: refused
    m = pendulum()
    m._car[0]["mass"] = 2.0
    with pytest.raises(ph.ModelError, match=r"different model \(description.carriers\[0\]\['mass'\]\)"):
        m.save(tmp_path / "m.json")
    assert not (tmp_path / "m.json").exists()
    with pytest.raises(ph.io.Unsaveable, match="Python callable 'len'"):
        ph.io.encode_value(len)


def assert_results_equal(a, b):
    for f in a.__dataclass_fields__:
        assert_same(getattr(a, f), getattr(b, f), f)


def test_netcdf_round_trip_and_xarray_layout(tmp_path):
    m = manipulator()
    r = m.simulate(0.02, 0.005, record=["R1", "F1"])
    r.to_netcdf(tmp_path / "r.nc")
    back = ph.load_result(tmp_path / "r.nc")
    assert_results_equal(r, back)
    np.testing.assert_array_equal(back.position("R1"), r.position("R1"))
    ds = r.to_xarray()
    assert ds["poses"].dims == ("time", "carrier", "row", "col")
    assert ds["twists"].dims == ("time", "carrier", "component")
    assert list(ds["carrier_name"].values) == ["R1", "F1.node0", "F1.node1", "F1.node2"]
    assert list(ds["joint"].values) == list(M.PAIRS) and set(ds["joint_unit"].values) == {"rad"}
    assert ds["energy"].attrs["units"] == "J" and ds["time"].attrs["units"] == "s"
    assert ds.attrs["stats_steps"] == r.stats["steps"] > 0
    np.testing.assert_array_equal(ds["joints"].sel(joint="k2"), r.joint("k2")["x"][:, 0])
    np.testing.assert_array_equal(ds["energy"].sel(energy_kind="ledger"), r.energy["ledger"])
    df = r.to_dataframe()
    np.testing.assert_array_equal(df.index, r.t)
    np.testing.assert_array_equal(df["k4.effort"], r.joint("k4")["effort"][:, 0])
    np.testing.assert_array_equal(df["port.i1"], r.port_energy["i1"])
    np.testing.assert_array_equal(df["energy.kinetic"], r.energy["kinetic"])
    # modes and statics
    md, st = m.modes(3), m.static(steps=2)
    md.to_netcdf(tmp_path / "m.nc")
    st.to_netcdf(tmp_path / "s.nc")
    assert_results_equal(md, ph.load_result(tmp_path / "m.nc"))
    assert_results_equal(st, ph.load_result(tmp_path / "s.nc"))
    assert md.to_xarray()["shapes"].dims == ("mode", "carrier", "component")
    # a newer result schema, and a file that is no result, are refused
    ds = r.to_xarray()
    ds.attrs["schema_version"] = ph._resultfile.RESULT_SCHEMA_VERSION + 1
    ds.to_netcdf(tmp_path / "new.nc", engine="h5netcdf")
    with pytest.raises(ph.ModelError, match=rf"result schema versions up to {ph._resultfile.RESULT_SCHEMA_VERSION}"):
        ph.load_result(tmp_path / "new.nc")
    (tmp_path / "x.nc").write_text("hello")
    with pytest.raises(ph.ModelError, match="not a phmech result"):
        ph.load_result(tmp_path / "x.nc")


def test_a_missing_array_is_none_only_when_the_writer_held_none(tmp_path):
    # load_result: an array the written result did not hold reads as None (a file from a phmech
    # before that quantity of the core: the result schema version does not change when one is
    # added); one its writer held (the file's "held" list; before the list, the five every
    # phmech wrote) is a damaged file: ModelError naming it (it read as None, or a KeyError)
    r = manipulator().simulate(0.02, 0.005)
    ds = r.to_xarray()
    meta = json.loads(ds.attrs["phmech_meta"])
    assert meta["held"] == [f.name for f in ph._resultfile.HELD_FIELDS]
    del meta["held"]
    old = ds.drop_vars(["strain_energy", "constraint_residual"])
    old.attrs["phmech_meta"] = json.dumps(meta)    # an older file: no list, no newer quantities
    old.to_netcdf(tmp_path / "old.nc", engine="h5netcdf")
    back = ph.load_result(tmp_path / "old.nc")
    assert back.strain_energy is None and back.constraint_residual is None
    np.testing.assert_array_equal(back.poses, r.poses)
    for name, what in (("strain_energy", ds), ("poses", old), ("inertia", ds)):
        what.drop_vars(name).to_netcdf(tmp_path / f"no_{name}.nc", engine="h5netcdf")
        with pytest.raises(ph.ModelError, match=f"no variable '{name}', which its writer wrote"):
            ph.load_result(tmp_path / f"no_{name}.nc")
    md = manipulator().modes(3)
    md.to_xarray().drop_vars("omega").to_netcdf(tmp_path / "m.nc", engine="h5netcdf")
    with pytest.raises(ph.ModelError, match="modes result file has no variable 'omega'"):
        ph.load_result(tmp_path / "m.nc")

def test_results_pickle(tmp_path):
    m = pendulum()
    for r in (m.simulate(0.02, 0.01), m.modes(1), m.static(steps=1)):
        assert_results_equal(r, pickle.loads(pickle.dumps(r)))
    r = pickle.loads(pickle.dumps(m.simulate(0.02, 0.01)))
    assert r.pose("b").shape == (3, 4, 4) and r.momentum().linear.shape == (3, 3)
    with pytest.raises(ph.SolverError) as e:
        pendulum(torque_at=0.02).simulate(0.1, 0.01)
    err = pickle.loads(pickle.dumps(e.value))
    assert isinstance(err, ph.SolverError) and len(err.result.t) == 3
    assert_results_equal(e.value.result, err.result)


def test_checkpoint_is_the_prefix_of_the_final_result(tmp_path):
    path = tmp_path / "run.nc"
    seen = {}

    def grab(t, i):   # runs after the checkpoint of output i was written
        if i == 2:
            shutil.copy(path, tmp_path / "at2.nc")
            seen["files"] = sorted(os.listdir(tmp_path))
        return False

    r = pendulum().simulate(0.03, 0.01, checkpoint=path, checkpoint_every=0, callback=grab)
    part = ph.load_result(tmp_path / "at2.nc")
    assert part.stats["checkpoint"] and len(part.t) == 3 and len(r.t) == 4
    for f in ("t", "poses", "twists", "constraint_wrenches", "joints", "joint_rates", "efforts",
              "pair_wrenches"):
        assert np.array_equal(getattr(part, f), getattr(r, f)[:3]), f
    for k in r.energy:
        assert np.array_equal(part.energy[k], r.energy[k][:3]), k
    assert seen["files"] == ["at2.nc", "run.nc"]     # no temporary file left behind
    assert_results_equal(r, ph.load_result(path))   # the file ends as the run did
    # a failed run leaves its partial result
    with pytest.raises(ph.SolverError) as e:
        pendulum(torque_at=0.02).simulate(0.1, 0.01, checkpoint=path)
    assert_results_equal(e.value.result, ph.load_result(path))
    # one that fails at its first output leaves an empty result, which loads
    m = pendulum()
    m.add_spring_damper("s", "ground", "b", 100.0, rest_length=1e154)   # an infinite energy
    with pytest.raises(ph.SolverError, match="non-finite energies at t = 0 s"):
        m.simulate(2e-3, 1e-3, checkpoint=path)
    empty = ph.load_result(path)
    assert len(empty.t) == 0 and empty.poses.shape == (0, 1, 4, 4)
    with pytest.raises(ph.ModelError, match="checkpoint_every must be >= 0"):
        pendulum().simulate(0.03, 0.01, checkpoint=path, checkpoint_every=-1)
    with pytest.raises(ph.ModelError, match="checkpoint_every applies with checkpoint"):
        pendulum().simulate(0.03, 0.01, checkpoint_every=1)


def test_composed_laws_and_splines_round_trip_and_python_functions_are_refused(tmp_path):
    # the law kinds of phmech.laws that are data (sums, products, splines, ramps) save and load
    # to a bit-identical run; a Python function (code) is refused at save, naming the call
    m = ph.Mechanism(gravity=(0, 0, -9.81))
    b = m.add_rigid_body("arm", 1.0, np.diag([0.01, 0.21, 0.21]), com=(0.3, 0, 0))
    law = 0.5 * ph.Spline([0, 0.5, 1.0, 2.0], [0, 0.2, 1.0, 3.0], bc="natural") \
        + ph.Linear(0.1, 0.0) * ph.Sine(0.1, 1.0)
    m.add_pair("j", ph.Revolute("y"), m.ground, b, driven=law)
    m.save(tmp_path / "m.json")
    a, c = m.simulate(0.3, 0.05), ph.load(tmp_path / "m.json").simulate(0.3, 0.05)
    assert np.array_equal(a.poses, c.poses) and np.array_equal(a.joints, c.joints)
    f = ph.Mechanism()
    fb = f.add_rigid_body("a", 1.0, np.eye(3))
    f.add_pair("j", ph.Revolute("z"), f.ground, fb, driven=ph.Function(lambda t: 0.1 * t))
    with pytest.raises(ph.ModelError, match="add_pair\\('j'\\).*driven.*Python function"):
        f.save(tmp_path / "f.json")
    assert not (tmp_path / "f.json").exists()


def test_a_version_1_files_links_keep_their_lumped_mass(tmp_path):
    """Schema 2 changed the flexible links' default element mass to "consistent": a version-1
    file's links without mass= load with lumped mass, the default they were saved under, and a
    link that named its mass keeps it."""
    m = ph.Mechanism()
    a = m.add_flexible_link("a", 1.0, ph.table1_properties(), elements=6)
    m.add_flexible_link("b", 1.0, ph.table1_properties(), elements=6, mass="consistent",
                        pose=ph.se3.translation([0, 2.0, 0]))
    m.add_pair("clamp", ph.Fixed(), m.ground, a.start)
    m.save(tmp_path / "m.json")
    doc = json.loads((tmp_path / "m.json").read_text())
    assert doc["schema_version"] == 2
    doc["schema_version"] = 1
    (tmp_path / "v1.json").write_text(json.dumps(doc))
    old, new = ph.load(tmp_path / "v1.json"), ph.load(tmp_path / "m.json")
    assert [e["mass"] for e in old._el] == ["lumped"] * 6 + ["consistent"] * 6
    assert [e["mass"] for e in new._el] == ["consistent"] * 12


def test_modes_poles_round_trip(tmp_path):
    """ModesResult.poles (with components or a spin: complex, s [1/s]) is written as its real and
    imaginary parts and read back bit for bit; a result without poles reads back None."""
    m = ph.Mechanism(gravity=(0, 0, 0))
    b = m.add_rigid_body("b", 2.0, np.diag([1e-3, 1e-3, 1e-3]))
    m.add_pair("slide", ph.Prismatic("x"), m.ground, b, actuator=ph.Spring(k=200.0, rest=0.0))
    m.add_component("damper", "slide", ph.ViscousFriction(4.0))
    md = m.modes(1)
    # the damped oscillator m s^2 + c s + k = 0: s = -c/2m +- i sqrt(k/m - (c/2m)^2)
    assert md.poles is not None and np.iscomplexobj(md.poles)
    assert md.poles[0].real == pytest.approx(-1.0, rel=1e-9)
    assert abs(md.poles[0].imag) == pytest.approx(np.sqrt(99.0), rel=1e-9)
    md.to_netcdf(tmp_path / "p.nc")
    back = ph.load_result(tmp_path / "p.nc")
    assert_results_equal(md, back)
    assert back.poles.dtype == complex and np.array_equal(back.poles, md.poles)
    ds = md.to_xarray()
    assert ds["poles"].dims == ("pole", "complex_part") and ds["poles"].attrs["units"] == "1/s"
    np.testing.assert_array_equal(ds["poles"].sel(complex_part="imag"), md.poles.imag)
    plain = ph.Mechanism(gravity=(0, 0, 0))
    c = plain.add_rigid_body("c", 2.0, np.diag([1e-3, 1e-3, 1e-3]))
    plain.add_pair("slide", ph.Prismatic("x"), plain.ground, c, actuator=ph.Spring(k=200.0, rest=0.0))
    mp = plain.modes(1)
    assert mp.poles is None
    mp.to_netcdf(tmp_path / "q.nc")
    assert ph.load_result(tmp_path / "q.nc").poles is None and "poles" not in mp.to_xarray()

"""Result files: SimulationResult, ModesResult and StaticResult as xarray Datasets (netCDF-4 through
h5netcdf) and pandas DataFrames, with the names, units and layouts a file needs to be read back
(``phmech.load_result``, python/phmech/results.py). See python/phmech/io.py, "Results"."""
from __future__ import annotations

import dataclasses
import json

import numpy as np

from ._codes import RESULT_FIELDS
from ._errors import ModelError, __version__
from .frames import FlexibleLink, MeshChoice, ModalChoice
from .io import atomic_write, encode_value

#: the result-file format and the schema this phmech writes and the newest it reads
RESULT_FORMAT = "phmech-result"
RESULT_SCHEMA_VERSION = 2   # 2: the element mass couplings (consistent and modal links)


def _version() -> str:
    return __version__


#: the core's arrays a SimulationResult assembles itself (python/phmech/_simulate.py): dicts by
#: name, and the multipliers and pair wrenches of every row when some are left out as redundant
ASSEMBLED = ("constraint_wrenches", "energy", "pair_wrenches", "port_energy", "components")
#: the others, which it holds as the core wrote them: one attribute and one file variable each,
#: named, shaped and described by the table of result quantities (csrc/include/phmech_results.h)
HELD_FIELDS = tuple(f for f in RESULT_FIELDS if f.name not in ASSEMBLED)
#: the held arrays every result file has had (each written unconditionally before the table of
#: result quantities): required in a file that does not list its own (phmech_meta "held")
ALWAYS_HELD = ("poses", "twists", "joints", "joint_rates", "efforts")


def _attrs(name: str) -> dict:
    """The netCDF attributes of the core's array ``name``: its unit and text from the table."""
    f = next(f for f in RESULT_FIELDS if f.name == name)
    return dict(units=f.unit, long_name=f.text)

#: the six components of a twist (omega, v) or a wrench (tau, f): angular part first
COMPONENTS = ("ang_x", "ang_y", "ang_z", "lin_x", "lin_y", "lin_z")


def _carrier_names(n: int, bodies: dict, links: dict) -> list:
    """A label per carrier: the body's name, or "link.nodeK"."""
    names = [f"carrier{c}" for c in range(n)]
    for b in bodies.values():
        if 0 <= b.carrier < n:
            names[b.carrier] = b.name
    for lk in links.values():
        for k, c in enumerate(lk.nodes):
            if 0 <= c < n:
                names[c] = lk.name if lk.rigid else f"{lk.name}.node{k}"
    return names


def _pair_labels(pairs: dict, nj: int, nrows: int) -> tuple:
    """Labels, pair and unit of each joint coordinate, and labels of the constraint rows."""
    joint, jpair, junit = [f"joint{j}" for j in range(nj)], [""] * nj, [""] * nj
    rows = [f"row{r}" for r in range(nrows)]
    for name, p in pairs.items():
        row, m, j, k = p["layout"]
        units = p.get("units", ("",) * k)
        for i in range(k):
            if j + i < nj:
                joint[j + i] = name if k == 1 else f"{name}[{i}]"
                jpair[j + i], junit[j + i] = name, units[i]
        for i in range(m):
            if row + i < nrows:
                rows[row + i] = f"{name}[{i}]"
    return joint, jpair, junit, rows


def _links_meta(links: dict) -> dict:
    return {lk.name: dict(length=lk.length, elements=lk.elements, nodes=list(lk.nodes),
                          mesh=None if lk.mesh is None else dataclasses.asdict(lk.mesh),
                          fidelity=lk.fidelity,
                          offsets=None if lk.offsets is None else np.asarray(lk.offsets).tolist(),
                          reduced_from=lk.reduced_from, clamped_frequency=lk.clamped_frequency,
                          sliders=list(lk.sliders),
                          modal_choice=None if lk.modal_choice is None else dataclasses.asdict(lk.modal_choice),
                          modal_peaks=lk.modal_peaks)
            for lk in links.values()}


def _links_from(meta: dict) -> dict:
    out = {}
    for name, d in meta.items():
        mesh = d["mesh"]
        if mesh is not None:
            mesh = MeshChoice(**{**mesh, "frequencies": tuple(mesh["frequencies"])})
        offsets = d.get("offsets")
        out[name] = FlexibleLink(name, d["length"], d["elements"], list(d["nodes"]), mesh,
                                 d.get("fidelity", "nonlinear"),
                                 None if offsets is None else np.array(offsets, dtype=float),
                                 d.get("reduced_from"), d.get("clamped_frequency"),
                                 list(d.get("sliders", [])),
                                 None if d.get("modal_choice") is None else ModalChoice(**d["modal_choice"]),
                                 d.get("modal_peaks"))
    return out


def _header(kind: str, meta: dict) -> dict:
    return {"format": RESULT_FORMAT, "schema_version": RESULT_SCHEMA_VERSION,
            "phmech_version": _version(), "kind": kind, "phmech_meta": json.dumps(meta)}


def simulation_dataset(res):
    """SimulationResult -> xarray.Dataset (SimulationResult.to_xarray)."""
    import xarray as xr
    nt = len(res.t)
    ncar = len(res._mass) if res._mass is not None else res.poses.shape[1]
    names = _carrier_names(ncar, res._bodies, res._links)
    rec = np.arange(res.poses.shape[1]) if res.carriers is None else np.asarray(res.carriers)
    nj = res.joints.shape[1]
    joint, jpair, junit, rows = _pair_labels(res._pairs, nj, res.constraint_wrenches.shape[1])
    pair_names = sorted(res._pairs, key=lambda n: res._pairs[n]["index"])
    ports = list(res.port_energy)
    data = {
        "constraint_wrenches": (("time", "constraint"), res.constraint_wrenches,
                                _attrs("constraint_wrenches")),
        "pair_wrenches": (("time", "pair", "component"), res.pair_wrenches, _attrs("pair_wrenches")),
        "port_energy": (("time", "port"), np.column_stack([res.port_energy[p] for p in ports])
                        if ports else np.zeros((nt, 0)), _attrs("port_energy")),
        "inertia": (("model_carrier", "inertia_row", "inertia_col"), res._inertia,
                    dict(units="kg m^2, kg m, kg", long_name="6x6 spatial inertia, carrier frame")),
        "mass": (("model_carrier",), res._mass, dict(units="kg")),
        "com": (("model_carrier", "xyz"), res._com,
                dict(units="m", long_name="centre of mass in carrier coordinates")),
    }
    for f in HELD_FIELDS:   # None: a file from before the quantity
        if getattr(res, f.name) is not None:
            data[f.name] = (("time",) + f.dims, getattr(res, f.name), _attrs(f.name))
    if res._couplings is not None and len(res._couplings):
        data["coupled_nodes"] = (("coupled_element", "end"), res._coupled_nodes,
                                 dict(long_name="node carriers of the consistent-mass elements"))
        data["couplings"] = (("coupled_element", "twist_row", "twist_col"), res._couplings,
                             dict(units="kg m^2, kg m, kg", long_name="consistent-mass couplings "
                                  "in the nodes' body twists (phm_element_mass)"))
    if res._couplings is not None and len(res._couplings) and res._coupled_fields is not None:
        data["coupled_fields"] = (("coupled_element", "field"), res._coupled_fields,
                                  dict(units="m, kg/m, m", long_name="consistent elements' length, "
                                       "section mass per length and centre of mass (zeros: none)"))
    kinds = list(res.energy)
    data["energy"] = (("time", "energy_kind"),
                      np.column_stack([res.energy[k] for k in kinds]) if kinds else np.zeros((nt, 0)),
                      _attrs("energy"))
    coords = {
        "time": ("time", res.t, dict(units="s")),
        "carrier": ("carrier", rec), "carrier_name": ("carrier", [names[c] for c in rec]),
        "component": ("component", list(COMPONENTS)),
        "energy_kind": ("energy_kind", kinds), "joint": ("joint", joint), "joint_pair": ("joint", jpair), "joint_unit": ("joint", junit),
        "constraint": ("constraint", rows), "pair": ("pair", pair_names), "port": ("port", ports),
        "model_carrier": ("model_carrier", np.arange(ncar)),
        "model_carrier_name": ("model_carrier", names),
    }
    states = [(n, q) for n, d in res.components.items() for q in d]
    if states:   # the components' internal states (python/phmech/components.py), when any
        data["component_states"] = (("time", "component_state"),
                                    np.column_stack([res.components[n][q] for n, q in states]),
                                    dict(long_name="components' internal states (A, m, rad, ...)"))
        coords["component_state"] = ("component_state", [f"{n}.{q}" for n, q in states])
    if res.sensors:   # the sensors' values (python/phmech/sensors.py), flattened per output
        data["sensor_values"] = (("time", "sensor_value"), np.column_stack(
            [np.asarray(v).reshape(nt, -1) for v in res.sensors.values()]),
            dict(long_name="sensor values, in each sensor's units (python/phmech/sensors.py)"))
        coords["sensor_value"] = ("sensor_value", [f"{n}[{i}]" for n, v in res.sensors.items()
                                                   for i in range(int(np.prod(np.shape(v)[1:])))])
    for i, (n, c) in enumerate(res.controllers.items()):   # a sampled controller's samples
        data[f"controller{i}_t"] = ((f"controller{i}_sample",), c["t"],
                                    dict(units="s", long_name=f"sample times of controller {n}"))
        data[f"controller{i}_y"] = ((f"controller{i}_sample", f"controller{i}_input"), c["y"],
                                    dict(long_name=f"inputs of controller {n} (its sensors')"))
        data[f"controller{i}_u"] = ((f"controller{i}_sample", f"controller{i}_output"), c["u"],
                                    dict(units="N m, N or wrench factor",
                                         long_name=f"outputs of controller {n}"))
    meta = dict(stats=encode_value(dict(res.stats)), interrupted=bool(res.interrupted),
                held=[f.name for f in HELD_FIELDS if getattr(res, f.name) is not None],
                sensors={n: list(np.shape(v)[1:]) for n, v in res.sensors.items()},
                controllers=list(res.controllers),
                recorded=res.carriers is not None,
                pairs=encode_value(res._pairs), redundant=encode_value(res.redundant_constraints),
                links=_links_meta(res._links), bodies={b.name: b.carrier for b in res._bodies.values()})
    attrs = _header("simulation", meta)
    attrs["interrupted"] = int(bool(res.interrupted))
    for k, v in res.stats.items():   # the statistics, readable without phmech
        if isinstance(v, (bool, np.bool_)):
            attrs[f"stats_{k}"] = int(v)
        elif isinstance(v, (int, float, str, np.number)):
            attrs[f"stats_{k}"] = v
    return xr.Dataset(data, coords, attrs)


def modes_dataset(res):
    """ModesResult -> xarray.Dataset (ModesResult.to_xarray)."""
    import xarray as xr
    n, nc = res.shapes.shape[:2]
    data = {"omega": (("mode",), res.omega, dict(units="rad/s")),
            "frequency": (("mode",), res.frequency, dict(units="Hz")),
            "damping_ratio": (("mode",), res.damping_ratio, dict(units="1")),
            "shapes": (("mode", "carrier", "component"), res.shapes,
                       dict(units="mass-normalized", long_name="tangent displacement (rotation, "
                            "translation) per carrier"))}
    if res.strain_fractions is not None:
        data["strain_fractions"] = (("mode", "strain_kind"), res.strain_fractions,
                                    dict(units="1", long_name="share of the links' strain energy"))
        data["elastic_fraction"] = (("mode",), res.elastic_fraction,
                                    dict(units="1", long_name="share of the mode's energy in strain"))
    if res.poses is not None:
        data["poses"] = (("carrier", "row", "col"), res.poses,
                         dict(units="1 (rotation), m (translation)", long_name="configuration"))
    coords = {"mode": np.arange(n), "carrier": np.arange(nc), "component": list(COMPONENTS)}
    if res.poles is not None:   # complex: its real and imaginary parts (netCDF has no complex)
        s = np.asarray(res.poles, dtype=complex)
        data["poles"] = (("pole", "complex_part"), np.column_stack([s.real, s.imag]),
                         dict(units="1/s", long_name="poles s (Re, Im) with components or a spin"))
        coords["complex_part"] = ["real", "imag"]
    if res.strain_fractions is not None:
        coords["strain_kind"] = ["torsion", "bending-y", "bending-z", "axial"]
    meta = dict(kind=list(res.kind), participation=res.participation,
                strain_participation=res.strain_participation, equilibrium=bool(res.equilibrium),
                links=_links_meta(res._links),
                bodies={b.name: b.carrier for b in res._bodies.values()})
    return xr.Dataset(data, coords, _header("modes", meta))


def complex_of(parts: np.ndarray) -> np.ndarray:
    """Complex values from their (n, 2) real and imaginary parts, as modes_dataset stores the
    poles (bit for bit)."""
    out = np.empty(parts.shape[0], dtype=complex)
    out.real, out.imag = parts[:, 0], parts[:, 1]
    return out


def static_dataset(res):
    """StaticResult -> xarray.Dataset (StaticResult.to_xarray)."""
    import xarray as xr
    nc = res.poses.shape[0]
    data = {"poses": (("carrier", "row", "col"), res.poses,
                      dict(units="1 (rotation), m (translation)")),
            "constraint_wrenches": (("constraint",), np.asarray(res.constraint_wrenches),
                                    dict(units="N m or N"))}
    coords = {"carrier": np.arange(nc)}
    meta = dict(links=_links_meta(res._links), loads=encode_value(list(res.loads)),
                steps=int(res.steps), stable=res.stable, lowest_omega=float(res.lowest_omega),
                load_factor=float(res.load_factor))
    attrs = _header("static", meta)
    attrs["iterations"] = int(res.iterations)
    return xr.Dataset(data, coords, attrs)


def write_result(res, path) -> None:
    """Write a result (its ``to_xarray()``: SimulationResult, ModesResult or StaticResult) to the
    netCDF-4 file ``path`` (h5netcdf), atomically."""
    to_xarray = getattr(res, "to_xarray", None)
    if to_xarray is None:
        raise ModelError(f"expected a SimulationResult, ModesResult or StaticResult (got "
                         f"{type(res).__name__})")
    ds = to_xarray()
    atomic_write(path, lambda tmp: ds.to_netcdf(tmp, engine="h5netcdf"))


def simulation_dataframe(res):
    """SimulationResult -> pandas.DataFrame of its scalar series (SimulationResult.to_dataframe)."""
    import pandas as pd
    cols = {f"energy.{k}": v for k, v in res.energy.items()}
    cols.update({f"port.{k}": v for k, v in res.port_energy.items()})
    joint, _, _, _ = _pair_labels(res._pairs, res.joints.shape[1], 0)
    for q, arr in (("x", res.joints), ("xdot", res.joint_rates), ("effort", res.efforts)):
        for j, label in enumerate(joint):
            cols[f"{label}.{q}"] = arr[:, j]
    return pd.DataFrame(cols, index=pd.Index(res.t, name="time"))


def sensors_and_controllers(read, meta: dict) -> tuple:
    """(sensors, controllers) of a dataset, as SimulationResult holds them (none in older
    files); ``read(name)``: a variable's values, or ModelError naming it when the file lacks it
    (the file's metadata lists these sensors and controllers, so their variables were written)."""
    sensors, ctrls, j = {}, {}, 0
    for n, shape in meta.get("sensors", {}).items():
        size = int(np.prod(shape))
        v = np.asarray(read("sensor_values"))[:, j:j + size]
        sensors[n] = np.ascontiguousarray(v.reshape((v.shape[0], *shape)))
        j += size
    for i, n in enumerate(meta.get("controllers", [])):
        ctrls[n] = {q: np.ascontiguousarray(read(f"controller{i}_{q}")) for q in "tyu"}
    return sensors, ctrls


def component_states(ds) -> dict:
    """name -> {state: values} of a dataset's component states (none in older files)."""
    out: dict = {}
    if "component_states" in ds:
        zs = np.asarray(ds["component_states"].values)
        for j, label in enumerate(ds["component_state"].values):
            n, q = str(label).rsplit(".", 1)
            out.setdefault(n, {})[q] = zs[:, j].copy()
    return out

"""Mechanisms as FMUs: ``export_fmu`` writes an FMI 2.0 (or 3.0) co-simulation FMU for Linux x86-64.

The FMU holds ``modelDescription.xml``; ``binaries/linux64/<modelIdentifier>.so`` (FMI 3.0:
``binaries/x86_64-linux/``), phmech's C
core with an FMI wrapper (csrc/fmi/: fmu.c, fmi2.c, fmi3.c, built by meson as ``phmech_fmi2.so`` beside this
module) and, beside it, the shared libraries it loads that are not part of glibc (SUNDIALS,
KLU/SuiteSparse, LAPACK/BLAS, the Fortran runtime), found with ``ldd`` and reached through the
wrapper's RPATH ``$ORIGIN``; and ``resources/model.phm``, the model: the exact arrays phmech hands
to ``phm_model_create`` at the consistent initial configuration (python/phmech/_marshal.py), the
integrator's options and the FMU's variables. The wrapper rebuilds the model from that file: the
FMU runs without Python.

Inputs (held constant over each communication step) are the amplitudes of Effort actuators (the
actuator's effort is input times its direction: N m or N) and of applied wrenches and
interactions (the wrench is input times its wrench vector); each input replaces the law of its
component. Outputs: the joint coordinates and rates of named pairs, the world position of named
frames or bodies, and the energies (kinetic, elastic, gravity, their sum) [J].

A model file is a sequence of records ``key NUL | uint64 n | n float64`` (little-endian); a time
law is flattened by ``_law_numbers``.
"""
from __future__ import annotations

import datetime
import os
import re
import shutil
import struct
import subprocess
import sys
import tempfile
import uuid
import warnings
import zipfile
from pathlib import Path
from typing import Optional, Sequence
from xml.sax.saxutils import quoteattr

import numpy as np

from . import _marshal, _model
from ._errors import CostWarning, ModelError, __version__, outside_stacklevel
from ._simulate import DEFAULT_RHO_INF, DEFAULT_RTOL
from .frames import frame_of
from .mechanism import Mechanism
from .pairs import PAIR_TYPES

__all__ = ["export_fmu"]

#: output kinds of the model file (csrc/fmi/fmu.h, OUT_*)
_OUT_JOINT, _OUT_RATE, _OUT_POSITION, _OUT_ENERGY = 0, 1, 2, 3
#: input kinds (csrc/fmi/fmu.h, IN_*)
_IN_ACTUATOR, _IN_LOAD = 0, 1
_CALLBACK = 8            # phm_law_kind of a Python-function law (csrc/include/phmech_types.h)
_ENERGIES = ("kinetic", "elastic", "gravity", "total")
_UNITS = {"rad": {"rad": 1}, "m": {"m": 1}, "rad/s": {"rad": 1, "s": -1}, "m/s": {"m": 1, "s": -1},
          "J": {"kg": 1, "m": 2, "s": -2}}
#: libraries of glibc and the compiler runtime every Linux x86-64 system has (as auditwheel's
#: manylinux policies): not bundled
_SYSTEM_LIBS = ("linux-vdso", "ld-linux", "libc.so", "libm.so", "libdl.so", "libpthread.so",
                "librt.so", "libgcc_s.so", "libutil.so", "libresolv.so")
_WRAPPER = "phmech_fmi2.so"


def _law_numbers(law, what: str) -> list:
    """The flat numbers of a core law tuple (python/phmech/laws.py, core_tuple) or None (no law):
    kind, amplitude, t0, duration, frequency, phase, offset, order, ndata, data..., nnodes,
    nodes...; ModelError naming ``what`` for a Python-function law."""
    if law is None:
        return [-1.0] + [0.0] * 9
    kind, a, t0, d, f, ph, off, data, order, nodes, fn = law
    if kind == _CALLBACK or fn is not None:
        raise ModelError(f"{what} is a Python function (phmech.Function), which an FMU cannot "
                         f"carry (it runs without Python): give it as a Table, Spline or "
                         f"piecewise polynomial law, or make it an FMU input")
    data = [] if data is None else [float(x) for x in np.asarray(data, dtype=float).ravel()]
    out = [float(kind), a, t0, d, f, ph, off, float(order), float(len(data)), *data]
    nodes = nodes or []
    out.append(float(len(nodes)))
    for n in nodes:
        out += _law_numbers(n, what)
    return out


#: the columns of _marshal.components that csrc/fmi/fmu.c (build_desc) reads, per component
#: kind: a column phmech adds later must be read there too (export_fmu refuses it until then)
_READ = {"carriers": {"M", "mass", "com", "H0", "t0"},
         "elements": {"h", "nodes", "K", "D", "eps_hat", "mass", "Ms", "Mc"},
         "pairs": {"type", "carriers", "Ta", "Tb", "driven", "axis", "law", "xlaws", "pitch", "x0",
                   "has_x0", "drop"},
         "loads": {"carrier", "world", "point", "w", "law", "reaction"},
         "actuators": {"pair", "kind", "vec", "kp", "kd", "x_set", "law"},
         "springs": {"carriers", "pa", "pb", "k", "c", "rest_length"},
         "couplings": {"Mc", "carriers"}}


def _records(comp: dict, names: dict, input_rows: set) -> list:
    """(key, array) records of the components of ``_marshal.components``; ``names``: kind ->
    component names for messages; ``input_rows``: (kind, index) whose law an input replaces."""
    out = []
    kinds = ("carriers", "elements", "pairs", "loads", "actuators", "springs", "couplings")
    sizes = []
    for kind in kinds:
        cols = comp[kind]
        unread = set(cols) - _READ[kind]
        if unread or set(comp) - set(kinds) - {"gravity"}:
            raise ModelError(f"export_fmu: the model has {kind} columns {sorted(unread)} (or components "
                             f"{sorted(set(comp) - set(kinds) - {'gravity'})}) that the FMU wrapper "
                             f"csrc/fmi/fmu.c does not read: it must learn them first")
        first = next(iter(cols.values()))
        sizes.append(len(first))
        for key, v in cols.items():
            if key in ("law", "xlaws"):
                nums = []
                for i, law in enumerate(v):
                    what = f"{kind[:-1]} {names[kind][i]!r}"
                    if key == "xlaws":
                        laws = (law or []) + [None] * (6 - len(law or []))
                        for c, x in enumerate(laws):
                            nums += _law_numbers(x, f"{what}: the law of its joint coordinate {c}")
                    elif (kind, i) in input_rows:
                        nums += _law_numbers(None, what)
                    else:
                        nums += _law_numbers(law, f"{what}: its time law")
                out.append((f"{kind}.{key}", np.array(nums, dtype=float)))
            else:
                out.append((f"{kind}.{key}", np.asarray(v, dtype=float).ravel()))
    out.append(("sizes", np.array(sizes, dtype=float)))
    out.append(("gravity", np.asarray(comp["gravity"], dtype=float)))
    return out


def _write_records(path: Path, records: list) -> None:
    with open(path, "wb") as f:
        for key, v in records:
            v = np.ascontiguousarray(v, dtype="<f8")
            f.write(key.encode("ascii") + b"\0" + struct.pack("<Q", v.size) + v.tobytes())


def _options(mechanism, integrator: str, rtol: Optional[float], atol: Optional[float],
             step: Optional[float], rho_inf: Optional[float], band: Optional[float]) -> tuple:
    """The integrator options (phm_sim_options' fields, in the model file's order) and a dict
    of them for the model description."""
    if integrator == "ida":
        if step is not None or band is not None or rho_inf is not None:
            raise ModelError("export_fmu: step, band and rho_inf apply to integrator='generalized-alpha'")
        rtol = 1e-8 if rtol is None else float(rtol)
        atol = rtol * 1e-2 if atol is None else float(atol)
        solver = 1 if len(mechanism._desc.carriers) >= 6 else 0   # simulate()'s "auto"
        vals = [0, rtol, atol, solver, 0.0, 5, 0, 0.0, 1.0, 0, 0.0]
    elif integrator == "generalized-alpha":
        adaptive = step is None
        if adaptive and band is None:
            raise ModelError("export_fmu: the adaptive generalized-alpha needs band= [Hz] (the highest "
                             "frequency to resolve; simulate's default is 1/(2 dt_out), at least 50 / span, "
                             "raised below rtol 1e-4 with flexible links), or give step=")
        rtol = (DEFAULT_RTOL if adaptive else 1e-8) if rtol is None else float(rtol)
        atol = rtol * 1e-2 if atol is None else float(atol)
        rho = DEFAULT_RHO_INF if rho_inf is None else float(rho_inf)
        vals = [1, rtol, atol, 1, 0.0, 5, 0, float(step or 0.0), rho, int(adaptive),
                float(band) if adaptive else 0.0]
    else:
        raise ModelError(f"export_fmu: unknown integrator {integrator!r} (available: 'ida', "
                         f"'generalized-alpha')")
    if not (rtol > 0 and atol > 0):
        raise ModelError("export_fmu: rtol and atol must be > 0")
    return vals, dict(integrator=integrator, rtol=rtol, atol=atol)


def _inputs(mechanism, inputs: Sequence[str]) -> list:
    """(name, kind, index, description, unit) of each input name."""
    desc = mechanism._desc
    acts = {a["name"]: i for i, a in enumerate(desc.actuators)}
    loads = {ld["name"]: i for i, ld in enumerate(desc.loads)}
    out = []
    for name in inputs:
        if not isinstance(name, str):
            raise ModelError(f"export_fmu: inputs are names of Effort actuators and wrenches (got {name!r})")
        if name in acts:
            a = desc.actuators[acts[name]]
            if a["kind"] != "effort":
                raise ModelError(f"export_fmu: input {name!r} is a {a['kind']!r} actuator; only Effort "
                                 f"actuators' efforts (and wrenches' amplitudes) can be FMU inputs")
            units = PAIR_TYPES[desc.pairs[a["pair"]]["type"]].units
            unit = "N.m" if set(units) == {"rad"} else "N" if set(units) == {"m"} else None
            out.append((name, _IN_ACTUATOR, acts[name], "effort amplitude of actuator " + name, unit))
        elif name in loads:
            out.append((name, _IN_LOAD, loads[name], "amplitude of wrench " + name + " (times its wrench)", None))
        elif any(p["name"] == name for p in desc.pairs):
            raise ModelError(f"export_fmu: input {name!r} is a pair: add an Effort actuator on it "
                             f"(m.add_actuator(name, {name!r}, ph.Effort())) and make that the input; "
                             f"driven coordinates are not FMU inputs")
        else:
            raise ModelError(f"export_fmu: unknown input {name!r} (Effort actuators: "
                             f"{', '.join(repr(k) for k, i in acts.items() if desc.actuators[i]['kind'] == 'effort') or 'none'}; "
                             f"wrenches: {', '.join(map(repr, loads)) or 'none'})")
    if len(set(inputs)) != len(inputs):
        raise ModelError("export_fmu: an input is named twice")
    return out


def _outputs(mechanism, outputs) -> list:
    """(name, kind, index, comp, T, unit, description) of each FMU output variable."""
    desc = mechanism._desc
    pairs = {p["name"]: i for i, p in enumerate(desc.pairs)}
    first_joint, j = [], 0
    for p in desc.pairs:
        first_joint.append(j)
        j += PAIR_TYPES[p["type"]].k
    if outputs is None:
        outputs = list(pairs) + ["energy"]
    out = []
    for o in outputs:
        if isinstance(o, str) and o == "energy":
            for c, e in enumerate(_ENERGIES):
                out.append((f"energy.{e}", _OUT_ENERGY, 0, c, np.eye(4), "J", f"{e} energy"))
        elif isinstance(o, str) and o in pairs:
            ip = pairs[o]
            units = PAIR_TYPES[desc.pairs[ip]["type"]].units
            for c, u in enumerate(units):
                sfx = "" if len(units) == 1 else f"[{c + 1}]"
                out.append((f"{o}.x{sfx}", _OUT_JOINT, first_joint[ip] + c, 0, np.eye(4), u,
                            f"joint coordinate {c} of pair {o}"))
                out.append((f"{o}.xdot{sfx}", _OUT_RATE, first_joint[ip] + c, 0, np.eye(4), u + "/s",
                            f"joint rate {c} of pair {o}"))
        else:
            try:
                f = frame_of(o, desc, "export_fmu: output")
            except ModelError:
                raise ModelError(f"export_fmu: unknown output {o!r} (pairs: "
                                 f"{', '.join(map(repr, pairs)) or 'none'}; bodies: "
                                 f"{', '.join(map(repr, desc.bodies)) or 'none'}; a Frame; or "
                                 f"'energy')") from None
            if f.carrier < 0:
                raise ModelError(f"export_fmu: output {o!r} is on the ground, which does not move")
            nm = o if isinstance(o, str) else (f.name or f"frame{len(out)}")
            for c in range(3):
                out.append((f"{nm}.p[{c + 1}]", _OUT_POSITION, f.carrier, c, f.T, "m",
                            f"world position {'xyz'[c]} of {nm}"))
    names = [x[0] for x in out]
    if len(set(names)) != len(names):
        raise ModelError("export_fmu: an output is named twice")
    return out


def _bundle(lib: Path, dest: Path) -> list:
    """Copy the shared libraries ``lib`` loads (ldd), except glibc's and the compiler runtime's,
    into ``dest``; their names."""
    try:
        txt = subprocess.run(["ldd", str(lib)], capture_output=True, text=True, check=True).stdout
    except (OSError, subprocess.CalledProcessError) as e:
        raise ModelError(f"export_fmu: ldd could not list the libraries of {lib}: {e}") from None
    copied = []
    for line in txt.splitlines():
        m = re.match(r"\s*(\S+)\s+=>\s+(\S+)", line)
        if not m:
            continue
        name, where = m.groups()
        if any(name.startswith(s) for s in _SYSTEM_LIBS):
            continue
        if where == "not":
            raise ModelError(f"export_fmu: {lib.name} needs {name}, which the loader does not find")
        shutil.copy2(where, dest / name)
        copied.append(name)
    return copied


def _patchelf() -> Optional[str]:
    exe = Path(sys.executable).parent / "patchelf"
    return str(exe) if exe.exists() else shutil.which("patchelf")


def _xml(model_name: str, ident: str, guid: str, ins: list, outs: list, opts: dict,
         description: str, start_time: float, stop_time: float, step_size: float) -> str:
    units = sorted({u for *_, u in ins if u} | {x[5] for x in outs})
    base = dict(_UNITS, **{"N.m": {"kg": 1, "m": 2, "s": -2}, "N": {"kg": 1, "m": 1, "s": -2}})
    lines = ['<?xml version="1.0" encoding="UTF-8"?>',
             f'<fmiModelDescription fmiVersion="2.0" modelName={quoteattr(model_name)} guid="{guid}"'
             f' description={quoteattr(description)}'
             f' generationTool="phmech {__version__}" generationDateAndTime='
             f'"{datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ")}"'
             f' variableNamingConvention="flat" numberOfEventIndicators="0">',
             f'  <CoSimulation modelIdentifier="{ident}" canHandleVariableCommunicationStepSize="true"'
             f' canNotUseMemoryManagementFunctions="true" canGetAndSetFMUstate="false"'
             f' canSerializeFMUstate="false" providesDirectionalDerivative="false"/>',
             '  <UnitDefinitions>']
    for u in units:
        b = " ".join(f'{k}="{v}"' for k, v in base.get(u, {}).items())
        lines.append(f'    <Unit name="{u}"><BaseUnit {b}/></Unit>' if b else f'    <Unit name="{u}"/>')
    lines += ['  </UnitDefinitions>', _default_experiment(start_time, stop_time, step_size, opts),
              '  <ModelVariables>']
    lines += _variables(ins, outs, "ScalarVariable", lambda causality, unit: (
        f'><Real start="0.0"{_unit(unit)}/></ScalarVariable>' if causality == "input"
        else f'><Real unit="{unit}"/></ScalarVariable>'))
    idx = [len(ins) + 1 + i for i in range(len(outs))]
    lines += ['  </ModelVariables>', '  <ModelStructure>', '    <Outputs>']
    lines += [f'      <Unknown index="{i}"/>' for i in idx]
    lines += ['    </Outputs>', '    <InitialUnknowns>']
    lines += [f'      <Unknown index="{i}"/>' for i in idx]
    lines += ['    </InitialUnknowns>', '  </ModelStructure>', '</fmiModelDescription>', '']
    return "\n".join(lines)


def _default_experiment(start_time: float, stop_time: float, step_size: float, opts: dict) -> str:
    """The model description's DefaultExperiment line (times [s], the run's rtol)."""
    return (f'  <DefaultExperiment startTime="{start_time!r}" stopTime="{stop_time!r}"'
            f' stepSize="{step_size!r}" tolerance="{opts["rtol"]!r}"/>')


def _unit(unit: str) -> str:
    """An input's unit attribute, or nothing for a unitless one."""
    return f' unit="{unit}"' if unit else ""


def _variables(ins: list, outs: list, tag: str, tail) -> list:
    """The model description's variable lines, FMI 2.0's or 3.0's by ``tag`` and ``tail(causality,
    unit)`` (the end of an element): the inputs, then the outputs, value references 0, 1, ... in
    that order (csrc/fmi/fmi2.c reads them so)."""
    rows = [(name, doc, unit, "input") for name, _, _, doc, unit in ins]
    rows += [(name, doc, unit, "output") for name, *_, unit, doc in outs]
    initial = {"input": "", "output": ' initial="calculated"'}
    return [f'    <{tag} name={quoteattr(name)} valueReference="{vr}" causality="{causality}"'
            f' variability="continuous"{initial[causality]} description={quoteattr(doc)}'
            f'{tail(causality, unit)}'
            for vr, (name, doc, unit, causality) in enumerate(rows)]


def _xml3(model_name: str, ident: str, guid: str, ins: list, outs: list, opts: dict,
          description: str, start_time: float, stop_time: float, step_size: float) -> str:
    """The FMI 3.0 model description of the same variables (all Float64)."""
    two = _xml(model_name, ident, guid, ins, outs, opts, description, start_time, stop_time, step_size)
    head = two.split("<CoSimulation", 1)[0].replace('fmiVersion="2.0"', 'fmiVersion="3.0"')
    head = head.replace(f'guid="{guid}"', f'instantiationToken="{guid}"')
    head = head.replace(' numberOfEventIndicators="0"', "")
    units = two.split("<UnitDefinitions>", 1)[1].split("</UnitDefinitions>", 1)[0]
    lines = [head.rstrip(),
             f'  <CoSimulation modelIdentifier="{ident}" canHandleVariableCommunicationStepSize="true"'
             f' canGetAndSetFMUState="false" canSerializeFMUState="false"'
             f' providesDirectionalDerivatives="false" providesAdjointDerivatives="false"'
             f' providesIntermediateUpdate="false" hasEventMode="false"/>',
             "  <UnitDefinitions>" + units + '  <Unit name="s"><BaseUnit s="1"/></Unit>\n'
             "  </UnitDefinitions>",
             _default_experiment(start_time, stop_time, step_size, opts),
             "  <ModelVariables>"]
    lines += _variables(ins, outs, "Float64", lambda causality, unit: (
        f' start="0.0"{_unit(unit)}/>' if causality == "input" else f' unit="{unit}"/>'))
    vr = len(ins) + len(outs)
    lines.append(f'    <Float64 name="time" valueReference="{vr}" causality="independent"'
                 f' variability="continuous" description="simulated time" unit="s"/>')
    refs = range(len(ins), len(ins) + len(outs))
    lines += ["  </ModelVariables>", "  <ModelStructure>"]
    lines += [f'    <Output valueReference="{r}"/>' for r in refs]
    lines += [f'    <InitialUnknown valueReference="{r}"/>' for r in refs]
    lines += ["  </ModelStructure>", "</fmiModelDescription>", ""]
    return "\n".join(lines)


def export_fmu(mechanism, path, inputs: Sequence[str] = (), outputs: Optional[Sequence] = None, *,
               model_name: Optional[str] = None, integrator: str = "ida",
               rtol: Optional[float] = None, atol: Optional[float] = None,
               step: Optional[float] = None, rho_inf: Optional[float] = None,
               band: Optional[float] = None, start_time: float = 0.0, stop_time: float = 1.0,
               step_size: float = 1e-3, description: str = "", fmi_version: str = "2.0") -> Path:
    """Write ``mechanism`` as an FMI 2.0 co-simulation FMU for Linux x86-64 to ``path`` (a
    ``.fmu`` file) and return its path.

    ``inputs``: names of Effort actuators (input = the effort amplitude, N m or N times the
    actuator's direction) and of applied wrenches or interactions (input = the factor of the
    wrench vector); each replaces its component's time law, starts at 0 and is held constant over
    a communication step. ``outputs``: names of pairs (variables ``<pair>.x`` [rad or m] and
    ``<pair>.xdot`` [rad/s or m/s], ``x[1]``, ``x[2]``... for pairs with several coordinates),
    bodies or frames (``<name>.p[1..3]``, the world position of the origin [m]) and
    ``"energy"`` (``energy.kinetic``, ``.elastic``, ``.gravity``, ``.total`` [J]); None: every
    pair and the energies. Variable references: the inputs first, then the outputs, in the
    order given.

    The FMU starts from the initial configuration ``simulate()`` starts from and integrates each
    communication step from the state the previous one reached with ``integrator``: "ida"
    (default; ``rtol`` 1e-8, ``atol`` rtol * 1e-2 [m, rad]) or "generalized-alpha" (``step`` [s]:
    fixed step; else adaptive, which needs ``band`` [Hz]), as ``simulate()`` reads these
    arguments. ``start_time``, ``stop_time`` and ``step_size`` [s] go into the model
    description's DefaultExperiment. ``model_name`` (default: the file's stem) names the model;
    its modelIdentifier is that name with every character other than ASCII letters, digits and
    "_" replaced by "_".

    ModelError for an unknown input or output name, an input that is not an Effort actuator or
    a wrench, and a model the FMU cannot carry: a time law given as a Python function
    (phmech.Function) anywhere but on an input. The 3-D DAE is integrated (no planar reduction);
    ``fmi_version``: "2.0" (default) or "3.0" (the same wrapper's fmi3* functions, co-simulation
    without event mode; binaries in ``binaries/x86_64-linux/``). Model exchange, FMU state
    get/set, clocks and directional derivatives are not provided.
    CostWarning for IDA on a mechanism with flexible links (its restart at every communication
    step is slow there: use the fixed-step generalized-alpha)."""
    if not isinstance(mechanism, Mechanism):
        raise ModelError(f"export_fmu: expected a phmech.Mechanism (got {type(mechanism).__name__})")
    path = Path(path)
    if path.suffix != ".fmu":
        raise ModelError(f"export_fmu: the path must end in .fmu (got {str(path)!r})")
    name = model_name or path.stem
    ident = re.sub(r"\W", "_", name, flags=re.ASCII)
    if not ident or ident[0].isdigit():
        ident = "m_" + ident
    if not (step_size > 0 and stop_time > start_time):
        raise ModelError("export_fmu: step_size must be > 0 and stop_time > start_time")
    if fmi_version not in ("2.0", "3.0"):
        raise ModelError(f"export_fmu: fmi_version must be '2.0' or '3.0' (got {fmi_version!r})")
    lib = Path(__file__).with_name(_WRAPPER)
    if not lib.exists():
        raise ModelError(f"export_fmu: the FMI wrapper {lib} is missing from this phmech installation "
                         f"(it is built by meson from csrc/fmi/)")
    if not sys.platform.startswith("linux") or os.uname().machine != "x86_64":
        raise ModelError("export_fmu writes Linux x86-64 FMUs and runs on Linux x86-64 only")
    if integrator == "ida" and mechanism._desc.elements:
        warnings.warn(f"export_fmu: the FMU restarts IDA at every communication step, and with "
                      f"flexible links ({len(mechanism._desc.elements)} elements here) each restart "
                      f"costs thousands of steps (measured: a 3-element arm swung by a torque step, "
                      f"rtol 1e-8: 0.9 s of CPU per 0.01 s communication step, its error test "
                      f"failing on the elements' stiff modes); use integrator='generalized-alpha' "
                      f"with step= (fixed step; 2.8e-3 s of CPU per communication step at "
                      f"step=1e-4 on that arm), which restarts at no cost",
                      CostWarning, stacklevel=outside_stacklevel())
    ins = _inputs(mechanism, list(inputs))
    outs = _outputs(mechanism, outputs)
    opt_vals, opts = _options(mechanism, integrator, rtol, atol, step, rho_inf, band)
    _model.build(mechanism)                  # the initial configuration simulate() starts from
    state = mechanism._state
    comp = _marshal.components(mechanism._desc, state.poses, state.twists, state.x0,
                               state.drop_masks, state.frames_a)
    if mechanism._desc.components:   # csrc/fmi/fmu.c does not read them yet
        raise ModelError("export_fmu: the components (friction, motors: "
                         f"{[r['name'] for r in mechanism._desc.components]}) are not in the FMU "
                         "wrapper csrc/fmi/fmu.c yet")
    del comp["components"]
    d = mechanism._desc
    names = {"carriers": [d.carrier_name(i) for i in range(len(d.carriers))],
             "elements": [str(i) for i in range(len(d.elements))],
             "pairs": [p["name"] for p in d.pairs], "loads": [x["name"] for x in d.loads],
             "actuators": [a["name"] for a in d.actuators],
             "springs": [s["name"] for s in d.springs], "couplings": [str(i) for i in range(len(d.couplings))]}
    input_rows = {("actuators" if k == _IN_ACTUATOR else "loads", i) for _, k, i, _, _ in ins}
    records = _records(comp, names, input_rows)
    records.append(("inputs", np.array([[k, i, 0.0] for _, k, i, _, _ in ins], dtype=float).reshape(-1)))
    records.append(("outputs", np.array([[k, i, c, *np.asarray(T, dtype=float).ravel()]
                                         for _, k, i, c, T, _, _ in outs], dtype=float).reshape(-1)))
    records.append(("options", np.array(opt_vals, dtype=float)))
    guid = "{" + str(uuid.uuid4()) + "}"
    with tempfile.TemporaryDirectory() as tmp:
        root = Path(tmp)
        platform = "linux64" if fmi_version == "2.0" else "x86_64-linux"
        (root / "binaries" / platform).mkdir(parents=True)
        (root / "resources").mkdir()
        (root / "documentation").mkdir()
        so = root / "binaries" / platform / f"{ident}.so"
        shutil.copy2(lib, so)
        bundled = _bundle(lib, so.parent)
        pe = _patchelf()
        if pe:   # a wheel's wrapper points at phmech.libs (auditwheel): $ORIGIN inside the FMU
            for f in [so] + [so.parent / b for b in bundled]:
                os.chmod(f, 0o755)
                subprocess.run([pe, "--force-rpath", "--set-rpath", "$ORIGIN", str(f)], check=True)
        _write_records(root / "resources" / "model.phm", records)
        (root / "modelDescription.xml").write_text(
            (_xml if fmi_version == "2.0" else _xml3)(name, ident, guid, ins, outs, opts, description or f"{name} (phmech {__version__})",
                 float(start_time), float(stop_time), float(step_size)), encoding="utf-8")
        (root / "documentation" / "index.txt").write_text(
            f"{name}: a phmech {__version__} mechanism as an FMI {fmi_version} co-simulation FMU (Linux x86-64).\n"
            f"Integrator: {opts['integrator']}, rtol {opts['rtol']:g}, atol {opts['atol']:g}; inputs "
            f"held over each communication step. Bundled libraries: {', '.join(bundled) or 'none'}.\n"
            f"FMI headers: Modelica Association, 2-clause BSD licence.\n", encoding="utf-8")
        path.parent.mkdir(parents=True, exist_ok=True)
        tmpzip = path.with_name(path.name + ".part")
        with zipfile.ZipFile(tmpzip, "w", zipfile.ZIP_DEFLATED) as z:
            for f in sorted(root.rglob("*")):
                if f.is_file():
                    z.write(f, f.relative_to(root).as_posix())
        os.replace(tmpzip, path)
    return path

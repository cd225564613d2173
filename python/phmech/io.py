"""Saving and loading: model files (JSON), results as xarray / netCDF / pandas.

Model files
-----------
``Mechanism.save(path)`` writes, and ``phmech.load(path)`` reads, a JSON document::

    {"format": "phmech-model", "schema_version": 2, "phmech_version": "0.1.0",
     "calls": [{"method": "set", "args": {"gravity": [0, 0, -9.81], "strict": false, ...}},
               {"method": "add_rigid_body", "args": {"name": "b", "mass": 1.0, ...}}, ...]}

A Mechanism records every builder call that succeeded (``add_rigid_body``, ``add_flexible_link``,
``add_pair``, ``add_actuator``, ``add_spring_damper``, ``add_wrench``, ``add_interaction``,
``add_distributed_load``: the methods decorated ``@_recorded`` in phmech/mechanism.py) with its
arguments as given, and the mechanism's settings (gravity, strict, band, frequency_tolerance) as
a ``set`` entry whenever they changed; loading replays the calls on a new Mechanism, so the
loaded mechanism goes through the same validation and builds the same description, hence the
same core model: ``simulate``, ``modes`` and ``static`` give bit-identical results. Saving
replays the file it is about to write and compares the two descriptions row by row, so a
mechanism that a file would not reproduce (one changed other than through its ``add_*``
methods) is refused with the first difference named, never written.

Arguments are written through ONE registry of types (``register``, ``register_dataclass``
below); each value is recorded when its call is made (later changes to an array the caller
passed do not leak in):

- None, bool, int, float, str: JSON's own (Python writes floats with ``repr``, which reads back
  to the same double; non-finite numbers as NaN/Infinity, which Python's json reads);
- list: a JSON list; tuple, dict: ``{"$type": "tuple", "items": [...]}``,
  ``{"$type": "dict", "items": {...}}`` (string keys); NumPy arrays:
  ``{"$type": "ndarray", "dtype": "float64", "shape": [...], "data": nested lists}``;
- frames as references, ``{"$type": "Frame", "on": {"body": "b"} | {"link": "L", "node": k} |
  "ground", "T": ..., "name": ...}``; bodies and links by name (``{"$type": "Body", "name":
  "b"}``);
- dataclasses by their fields: the laws (Constant ... Cycloidal, Motion), the pair classes
  (Fixed ... Free), the actuators (Effort, PD, Spring), Material, Section, BeamProperties:
  ``{"$type": "Sine", "amplitude": ..., ...}``.

Anything else (a Python function, an object of a type not registered) cannot be saved: ``save``
raises ModelError naming the call, the component and the argument; loading never calls methods
or builds types other than these.

**Adding a type** (a frame with an offset, a pair driver; a new law kind is registered from
``laws._CLASSES``, a new pair type from the pair table): a dataclass whose fields are themselves
saveable needs one line here, ``register_dataclass(NewType)`` (its tag is the class name; it is
rebuilt as ``NewType(**fields)``). Any other type:
``register(cls, tag, encode, decode)`` with ``encode(obj, mech) -> dict`` of JSON-able fields
(call ``encode_value`` on the values inside) and ``decode(fields, mech) -> obj`` (call
``decode_value``); ``mech`` is the Mechanism being saved or rebuilt (frames look up their
carrier there). A new builder method is saved once it carries ``@_recorded`` (python/phmech/_builder.py).
A change that makes old files read differently bumps ``SCHEMA_VERSION`` (old files keep
loading: ``load`` accepts every version up to it; a newer one is refused naming both).

Results (python/phmech/_resultfile.py writes them, ``phmech.load_result`` in
python/phmech/results.py reads them)
-------
``SimulationResult.to_xarray()``, ``ModesResult.to_xarray()``, ``StaticResult.to_xarray()``
give ``xarray.Dataset``s with named dimensions and coordinates and a ``units`` attribute on
every variable; ``to_netcdf(path)`` writes one (netCDF-4 through h5netcdf and h5py: both install
as wheels and need no system netCDF library) and ``phmech.load_result(path)`` reads it back
equal (every array bit for bit, the statistics, names and layouts from a JSON attribute).
``SimulationResult.to_dataframe()``: the scalar series (energies, ports, joint coordinates,
rates and efforts) as a pandas DataFrame indexed by time.
"""
from __future__ import annotations

import dataclasses
import functools
import inspect
import json
import math
import os
import warnings
from typing import Any, Callable, Optional

import numpy as np

from . import actuators, components, controllers, laws, pairs, section, sensors
from ._errors import ModelError, __version__
from .frames import Body, FlexibleLink, Frame

__all__ = ["save", "load", "register", "register_dataclass", "encode_value",
           "decode_value", "model_to_dict", "model_from_dict", "SCHEMA_VERSION"]

FORMAT = "phmech-model"
#: the model-file schema this phmech writes and the newest it reads (2: a flexible link's default
#: element mass is "consistent"; a version-1 file's links without mass= keep "lumped")
SCHEMA_VERSION = 2


def _version() -> str:
    return __version__


# ---------------------------------------------------------------------------- the registry
class Unsaveable(Exception):
    """A value no registered type can write (turned into a ModelError naming the call at save)."""


@dataclasses.dataclass(frozen=True)
class Codec:
    """How one type is written: ``encode(obj, mech) -> dict`` of JSON-able fields and
    ``decode(fields, mech) -> obj``; ``tag`` is its ``$type``."""
    cls: type
    tag: str
    encode: Callable[[Any, Any], dict]
    decode: Callable[[dict, Any], Any]


_BY_TYPE: dict = {}
_BY_TAG: dict = {}
_RESERVED = {"tuple", "dict", "ndarray"}


def register(cls: type, tag: Optional[str] = None, encode: Optional[Callable] = None,
             decode: Optional[Callable] = None) -> type:
    """Make instances of ``cls`` (exactly that type, not subclasses) saveable under ``$type`` =
    ``tag`` (default: the class name). See the module doc. Returns ``cls``."""
    tag = cls.__name__ if tag is None else tag
    if tag in _RESERVED or (tag in _BY_TAG and _BY_TAG[tag].cls is not cls):
        raise ValueError(f"register: the tag {tag!r} is taken")
    if encode is None or decode is None:
        raise ValueError("register: give encode and decode (or use register_dataclass)")
    codec = Codec(cls, tag, encode, decode)
    _BY_TYPE[cls] = _BY_TAG[tag] = codec
    return cls


def register_dataclass(cls: type, tag: Optional[str] = None) -> type:
    """Register a dataclass written as its ``__init__`` fields and rebuilt as ``cls(**fields)``."""
    names = [f.name for f in dataclasses.fields(cls) if f.init]

    def enc(obj, mech):
        return {n: encode_value(getattr(obj, n), mech) for n in names}

    def dec(fields, mech):
        unknown = set(fields) - set(names)
        if unknown:
            raise ModelError(f"{cls.__name__}: unknown fields {sorted(unknown)} (known: {names})")
        return cls(**{n: decode_value(v, mech) for n, v in fields.items()})

    return register(cls, tag, enc, dec)


def encode_value(x, mech=None):
    """``x`` as JSON-able data (see the module doc); Unsaveable if no registered type fits.
    ``mech``: the Mechanism the value belongs to (frames are written relative to it)."""
    if x is None or isinstance(x, (bool, str)):
        return x
    if isinstance(x, np.bool_):
        return bool(x)
    if isinstance(x, (int, np.integer)):
        return int(x)
    if isinstance(x, (float, np.floating)):
        return float(x)
    if isinstance(x, list):
        return [encode_value(v, mech) for v in x]
    if type(x) is tuple:
        return {"$type": "tuple", "items": [encode_value(v, mech) for v in x]}
    if isinstance(x, dict):
        bad = [k for k in x if not isinstance(k, str)]
        if bad:
            raise Unsaveable(f"a dict with a key that is not a string ({bad[0]!r})")
        return {"$type": "dict", "items": {k: encode_value(v, mech) for k, v in x.items()}}
    if isinstance(x, np.ndarray):
        if x.dtype.kind not in "biuf":
            raise Unsaveable(f"a NumPy array of dtype {x.dtype} (only booleans, integers and "
                             f"real numbers can be saved)")
        return {"$type": "ndarray", "dtype": x.dtype.str, "shape": list(x.shape),
                "data": x.tolist()}
    codec = _BY_TYPE.get(type(x))
    if codec is not None:
        return {"$type": codec.tag, **codec.encode(x, mech)}
    if isinstance(x, laws.Function):
        raise Unsaveable("a Python function as a law (phmech.Function), which a model file cannot "
                         "hold (a file holds data, not code): a Spline through samples of it can be "
                         "saved")
    if callable(x):
        nm = getattr(x, "__qualname__", getattr(x, "__name__", type(x).__name__))
        raise Unsaveable(f"the Python callable {nm!r}, which a model file cannot hold (a file "
                         f"holds data, not code)")
    raise Unsaveable(f"a {type(x).__module__}.{type(x).__qualname__} object, a type no model file "
                     f"can hold (phmech.io.register adds one)")


def decode_value(d, mech=None):
    """The value ``encode_value`` wrote as ``d`` (``mech``: the Mechanism being rebuilt)."""
    if isinstance(d, list):
        return [decode_value(v, mech) for v in d]
    if not isinstance(d, dict):
        return d
    tag = d.get("$type")
    fields = {k: v for k, v in d.items() if k != "$type"}
    if tag == "tuple":
        return tuple(decode_value(v, mech) for v in d["items"])
    if tag == "dict":
        return {k: decode_value(v, mech) for k, v in d["items"].items()}
    if tag == "ndarray":
        dt = np.dtype(d["dtype"])
        if dt.kind not in "biuf":
            raise ModelError(f"model file: arrays of dtype {dt} are not read")
        return np.array(d["data"], dtype=dt).reshape(d["shape"])
    if tag not in _BY_TAG:
        raise ModelError(f"model file: unknown type {tag!r} (this phmech {_version()} reads: "
                         f"{', '.join(sorted(_BY_TAG))})")
    return _BY_TAG[tag].decode(fields, mech)


# frames, bodies and links: references into the mechanism being saved or rebuilt
def _carrier_ref(c: int, mech):
    if c < 0:
        return "ground"
    for b in mech._bodies.values():
        if b.carrier == c:
            return {"body": b.name}
    for lk in mech._links.values():
        if c in lk.nodes:
            return {"link": lk.name, "node": lk.nodes.index(c)}
    raise Unsaveable(f"a frame on carrier {c}, which is neither a body nor a node of a link")


def _carrier_of(ref, mech) -> int:
    if ref == "ground":
        return -1
    if isinstance(ref, dict) and "body" in ref and ref["body"] in mech._bodies:
        return mech._bodies[ref["body"]].carrier
    if isinstance(ref, dict) and "link" in ref and ref["link"] in mech._links:
        nodes = mech._links[ref["link"]].nodes
        k = ref.get("node")
        if isinstance(k, int) and 0 <= k < len(nodes):
            return nodes[k]
    raise ModelError(f"model file: a frame on {ref!r}, which the mechanism does not have (yet)")


_FRAME_FIELDS = [f.name for f in dataclasses.fields(Frame) if f.init and f.name != "carrier"]
register(Frame, "Frame",
         lambda f, mech: {"on": _carrier_ref(int(f.carrier), mech),
                          **{n: encode_value(getattr(f, n), mech) for n in _FRAME_FIELDS}},
         lambda d, mech: Frame(carrier=_carrier_of(d["on"], mech),
                               **{n: decode_value(d[n], mech) for n in _FRAME_FIELDS if n in d}))


def _named(kind: str, table: str):
    def dec(d, mech):
        items = getattr(mech, table)
        if d.get("name") not in items:
            raise ModelError(f"model file: unknown {kind} {d.get('name')!r}")
        return items[d["name"]]
    return lambda obj, mech: {"name": obj.name}, dec


register(Body, "Body", *_named("body", "_bodies"))
register(FlexibleLink, "FlexibleLink", *_named("flexible link", "_links"))
# every law class of laws._CLASSES but Function, left out on purpose: a Python callable is code,
# not data (save refuses it)
for _cls in (*(c for c in laws._CLASSES.values() if c is not laws.Function),
             laws.Motion, actuators.Effort, actuators.PD, actuators.Spring, section.Material,
             section.Section, section.BeamProperties, components.ViscousFriction,
             components.CoulombFriction, components.StribeckFriction, components.LuGreFriction,
             components.DCMotor, components.LinearController, components.CallbackController,
             components.PortHamiltonianController,
             sensors.JointSensor,
             sensors.FrameSensor, sensors.TipDeflection, sensors.LinkStrain,
             sensors.PairWrench, sensors.ComponentState,
             controllers.SampledController, controllers.EffortOutput, controllers.WrenchOutput,
             controllers.MotorVoltageOutput,
             *(getattr(pairs, t.name) for t in pairs.PAIR_TYPES)):
    register_dataclass(_cls)


# ---------------------------------------------------------------------------- recording calls
#: the Mechanism methods a model file may call (those decorated @_recorded), filled by it
RECORDED: set = set()


def _settings(mech) -> dict:
    return dict(gravity=[float(g) for g in mech.gravity], strict=bool(mech.strict),
                band=mech.band, frequency_tolerance=float(mech.frequency_tolerance))


def recorded(method: Callable) -> Callable:
    """Decorator of a Mechanism builder method: a call that returns (did not raise) is recorded
    with its arguments as given, encoded at once (or the reason they cannot be saved, raised by
    ``save``), after a ``set`` entry if the mechanism's settings changed since the last call."""
    sig = inspect.signature(method)
    RECORDED.add(method.__name__)
    # the call succeeded, so its arguments bind: by name, in the signature's order (cheaper
    # than sig.bind, which a builder method with *args or **kwargs would need)
    names = list(sig.parameters)[1:]
    if any(p.kind in (p.VAR_POSITIONAL, p.VAR_KEYWORD) for p in sig.parameters.values()):
        raise TypeError(f"@recorded {method.__name__}: *args and **kwargs are not supported")

    @functools.wraps(method)
    def wrapper(self, *args, **kwargs):
        outer = not self._recording
        self._recording = True
        try:
            out = method(self, *args, **kwargs)
        finally:
            if outer:
                self._recording = False
        if outer:
            given = dict(zip(names, args))
            if kwargs:
                given.update(kwargs)
                given = {n: given[n] for n in names if n in given}
            _log(self, method.__name__, given)
        return out

    return wrapper


def _log(mech, method: str, given: dict) -> None:
    s = _settings(mech)
    if s != mech._last_settings:
        mech._calls.append({"method": "set", "args": s})
        mech._last_settings = s
    try:
        args = {k: encode_value(v, mech) for k, v in given.items()}
        entry = {"method": method, "args": args}
    except Unsaveable:
        entry = {"method": method, "name": given.get("name"), "unsaveable": _why(given, mech)}
    mech._calls.append(entry)


def _why(given: dict, mech) -> str:
    for k, v in given.items():
        try:
            encode_value(v, mech)
        except Unsaveable as e:
            return f"argument {k!r} is {e}"
    return "an argument cannot be saved"


# ---------------------------------------------------------------------------- model files
def model_to_dict(mech) -> dict:
    """The model-file document of ``mech`` (JSON-able), checked: replaying it gives the same
    description (ModelError naming what cannot be saved or what would differ)."""
    for e in mech._calls:
        if "unsaveable" in e:
            raise ModelError(f"cannot save this mechanism: {e['method']}"
                             f"({_component(e)}): {e['unsaveable']}")
    calls = list(mech._calls)
    s = _settings(mech)
    if s != mech._last_settings:
        calls.append({"method": "set", "args": s})
    doc = {"format": FORMAT, "schema_version": SCHEMA_VERSION, "phmech_version": _version(),
           "calls": calls}
    doc = json.loads(json.dumps(doc))   # what a file holds, exactly
    with warnings.catch_warnings():   # the replay warns as the original did
        warnings.simplefilter("ignore")
        again = model_from_dict(doc, type(mech))
    where = _difference(mech._desc, again._desc, "description") or \
        _difference(_settings(mech), _settings(again), "settings")
    if where:
        raise ModelError(f"cannot save this mechanism: replaying its add_* calls gives a different "
                         f"model ({where}); was it changed other than through its add_* methods "
                         f"and settings?")
    return doc


def _component(entry: dict) -> str:
    name = entry.get("name")
    return repr(name) if isinstance(name, str) else "..."


def model_from_dict(doc: dict, cls: type):
    """The mechanism (of class ``cls``, phmech.Mechanism) a model-file document describes
    (ModelError for anything else)."""
    if not isinstance(doc, dict) or doc.get("format") != FORMAT:
        raise ModelError(f"not a phmech model (expected a JSON object with \"format\": "
                         f"\"{FORMAT}\")")
    v = doc.get("schema_version")
    if isinstance(v, bool) or not isinstance(v, int) or v < 1:
        raise ModelError(f"phmech model: schema_version must be an integer >= 1 (got {v!r})")
    if v > SCHEMA_VERSION:
        raise ModelError(f"this model file has schema version {v} (written by phmech "
                         f"{doc.get('phmech_version', '?')}); this phmech {_version()} reads "
                         f"schema versions up to {SCHEMA_VERSION}: upgrade phmech to load it")
    calls = doc.get("calls")
    if not isinstance(calls, list):
        raise ModelError("phmech model: \"calls\" must be a list")
    m, version = cls(), v
    for i, e in enumerate(calls):
        meth = e.get("method") if isinstance(e, dict) else None
        args = e.get("args") if isinstance(e, dict) else None
        if not isinstance(args, dict):
            raise ModelError(f"phmech model: call {i}: expected {{\"method\": ..., \"args\": {{...}}}}")
        if meth == "set":
            try:
                s = cls(**{k: decode_value(v) for k, v in args.items()})   # validates them
            except TypeError as e:
                raise ModelError(f"phmech model: call {i} (set): {e}") from None
            m.gravity, m.strict, m.band = s.gravity, s.strict, s.band
            m.frequency_tolerance = s.frequency_tolerance
            continue
        if meth not in RECORDED:
            raise ModelError(f"phmech model: call {i}: unknown method {meth!r} (known: "
                             f"{', '.join(sorted(RECORDED))})")
        kwargs = {k: decode_value(v, m) for k, v in args.items()}
        if version < 2 and meth == "add_flexible_link":
            kwargs.setdefault("mass", "lumped")     # that file's default (SCHEMA_VERSION)
        try:
            getattr(m, meth)(**kwargs)
        except TypeError as e:   # an argument the method does not take
            raise ModelError(f"phmech model: call {i} ({meth}): {e}") from None
    return m


def save(mech, path) -> None:
    """Write ``mech`` to the JSON model file ``path`` (see the module doc); atomically."""
    text = json.dumps(model_to_dict(mech), indent=1) + "\n"

    def write(tmp):
        with open(tmp, "w", encoding="utf-8") as f:
            f.write(text)
    atomic_write(path, write)


def load(path, cls: type):
    """The mechanism (of class ``cls``, phmech.Mechanism) saved in the model file ``path``
    (Mechanism.save). ModelError when the file is not a phmech model or has a newer schema
    version than this phmech reads."""
    try:
        with open(path, encoding="utf-8") as f:
            doc = json.load(f)
    except (UnicodeDecodeError, json.JSONDecodeError) as e:
        raise ModelError(f"{os.fspath(path)}: not a phmech model (not JSON: {e})") from None
    try:
        return model_from_dict(doc, cls)
    except ModelError as e:
        raise ModelError(f"{os.fspath(path)}: {e}") from None


def _difference(a, b, path: str) -> Optional[str]:
    """Where two descriptions (rows of numbers, arrays, dicts, lists, dataclasses) differ, or
    None: numbers by value (0.0 == -0.0 aside, bit for bit), arrays entry by entry."""
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        x, y = np.asarray(a), np.asarray(b)
        if x.shape != y.shape or not np.array_equal(x, y, equal_nan=x.dtype.kind == "f"):
            return path
        return None
    if isinstance(a, (bool, np.bool_)) or isinstance(b, (bool, np.bool_)):
        return None if a == b else path
    if isinstance(a, (int, float, np.number)) and isinstance(b, (int, float, np.number)):
        return None if (a == b or (math.isnan(a) and math.isnan(b))) else path
    if isinstance(a, dict) and isinstance(b, dict):
        if set(a) != set(b):
            return f"{path}: keys {sorted(map(str, set(a) ^ set(b)))}"
        for k in a:
            w = _difference(a[k], b[k], f"{path}[{k!r}]")
            if w:
                return w
        return None
    if isinstance(a, (list, tuple)) and isinstance(b, (list, tuple)):
        if len(a) != len(b):
            return f"{path}: {len(a)} vs {len(b)} entries"
        for i, (x, y) in enumerate(zip(a, b)):
            w = _difference(x, y, f"{path}[{i}]")
            if w:
                return w
        return None
    if dataclasses.is_dataclass(a) and not isinstance(a, type):
        if type(a) is not type(b):
            return path
        for f in dataclasses.fields(a):
            if not f.compare:   # a cache (ModelDescription.columns), not the model
                continue
            w = _difference(getattr(a, f.name), getattr(b, f.name), f"{path}.{f.name}")
            if w:
                return w
        return None
    return None if a == b else path


def atomic_write(path, write: Callable[[str], Any]) -> None:
    """``write(tmp)`` into a temporary file beside ``path``, then rename it to ``path``: a reader
    never sees a half-written file, and a failure leaves ``path`` as it was."""
    path = os.fspath(path)
    tmp = f"{path}.{os.getpid()}.tmp"
    try:
        write(tmp)
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise

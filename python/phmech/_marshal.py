"""The one place that knows how a model description reaches the C core (``_core.model_new``).

``model_new(carriers, elements, pairs, loads, actuators, springs, gravity, couplings)`` takes one
description per component kind: a dict of columns, each column an array whose first axis runs
over the components of that kind (laws: a list with one law tuple, or None, per component). The
columns are the fields of the core's description structs (csrc/include/phmech_types.h,
phm_*_desc), which the binding (csrc/pyext/py_model.c, COMPONENTS) fills column by column and
checks (shapes, finite values, whole-number indices); the core then validates the model
(phm_model_create). ``with_initial`` moves a model to another initial state without rebuilding it
(``_core.model_set_initial``).
"""
from __future__ import annotations

from typing import Optional, Sequence

import numpy as np

from . import _core
from ._errors import ModelError
from .components import MAXZ, NPAR
from .description import ModelDescription
from ._codes import ACTUATOR_KINDS, MASS_KINDS
from .laws import core_tuple


def _column(rows: list, key: str, shape: tuple = ()) -> np.ndarray:
    """The column ``key`` of ``rows`` as a float array of shape (len(rows), *shape)."""
    return np.array([r[key] for r in rows], dtype=float).reshape(-1, *shape)


def _ends(rows: list) -> np.ndarray:
    """The carriers (a, b) of each row, as a float array (n, 2) (-1 = the ground)."""
    return np.array([[r["a"], r["b"]] for r in rows], dtype=float).reshape(-1, 2)


def _rest_lengths(desc: ModelDescription, poses: np.ndarray) -> np.ndarray:
    """Each spring's rest length [m]: the one given, else the distance of its points at
    ``poses``; ModelError when that distance is not finite."""
    def world(c, p):
        return p if c < 0 else poses[c][:3, :3] @ p + poses[c][:3, 3]
    out = []
    for q in desc.springs:
        d0 = q["kcd"][2]
        if d0 is None:
            with np.errstate(over="ignore", invalid="ignore"):   # checked below
                d0 = np.linalg.norm(world(q["b"], q["pb"]) - world(q["a"], q["pa"]))
            if not np.isfinite(d0):
                raise ModelError(f"spring {q['name']!r}: the initial distance between its points "
                                 f"(its default rest length) is not finite in double precision")
        out.append(d0)
    return np.array(out, dtype=float)


def _description_columns(desc: ModelDescription) -> dict:
    """The columns of ``components`` that depend on the description alone (not on the initial
    state nor on extra loads), made once per description (ModelDescription.columns, dropped by
    ModelDescription.changed)."""
    if desc.columns is not None:
        return desc.columns
    car, el, pr, ac, sp, ld = desc.carriers, desc.elements, desc.pairs, desc.actuators, desc.springs, desc.loads
    desc.columns = dict(
        carriers=dict(M=_column(car, "M", (6, 6)), mass=_column(car, "mass"), com=_column(car, "com", (3,))),
        elements=dict(h=_column(el, "h"), nodes=_ends(el), K=_column(el, "K", (6, 6)),
                      D=_column(el, "D", (6, 6)), eps_hat=_column(el, "eps", (6,)),
                      mass=np.array([MASS_KINDS[e.get("mass", "lumped")] for e in el], dtype=float),
                      Ms=np.array([e.get("Ms", np.zeros((6, 6))) for e in el],
                                  dtype=float).reshape(-1, 6, 6),
                      Mc=np.array([e.get("Mc", np.zeros((12, 12))) for e in el],
                                  dtype=float).reshape(-1, 12, 12)),
        pairs=dict(type=_column(pr, "type"), carriers=_ends(pr), Tb=_column(pr, "Tb", (4, 4)),
                   driven=_column(pr, "driven"), axis=_column(pr, "axis", (6,)),
                   law=[core_tuple(p["law"]) if p["driven"] else None for p in pr],
                   xlaws=[None if p.get("xlaws") is None else [core_tuple(x) for x in p["xlaws"]] for p in pr],
                   pitch=_column(pr, "pitch"), has_x0=_column(pr, "has_x0")),
        loads=_load_columns(ld),
        actuators=dict(pair=_column(ac, "pair"),
                       kind=np.array([ACTUATOR_KINDS[a["kind"]] for a in ac], dtype=float),
                       vec=_column(ac, "vec", (6,)), kp=_column(ac, "kp", (6,)),
                       kd=_column(ac, "kd", (6,)), x_set=_column(ac, "xset", (6,)),
                       law=[core_tuple(a["law"]) for a in ac]),
        springs=dict(carriers=_ends(sp), pa=_column(sp, "pa", (3,)), pb=_column(sp, "pb", (3,)),
                     k=np.array([q["kcd"][0] for q in sp], dtype=float),
                     c=np.array([q["kcd"][1] for q in sp], dtype=float)),
        couplings=dict(Mc=np.array([c["Mc"] for c in desc.couplings], dtype=float).reshape(-1, 12, 12),
                       carriers=np.array([[c["a"], c["b"]] for c in desc.couplings],
                                         dtype=float).reshape(-1, 2)),
        components=_component_columns(desc.components))
    for kind in desc.columns.values():   # shared by every later call: nobody may write them
        for v in kind.values():
            if isinstance(v, np.ndarray):
                v.setflags(write=False)
    return desc.columns


def _component_columns(rows: Sequence[dict]) -> dict:
    """The component rows' columns of ``components`` (python/phmech/components.py)."""
    return dict(kind=np.array([r["code"] for r in rows], dtype=float), pair=_column(rows, "pair"),
                coord=_column(rows, "coord"), par=_column(rows, "par", (NPAR,)),
                input=_column(rows, "input"), nx=_column(rows, "nstates"),
                spair=_column(rows, "spair"), scoord=_column(rows, "scoord"),
                z0=_column(rows, "z0", (MAXZ,)),
                law=[core_tuple(r["law"]) for r in rows])


def _load_columns(loads: Sequence[dict]) -> dict:
    """The load rows' columns of ``components``."""
    return dict(carrier=_column(loads, "carrier"), world=_column(loads, "world"),
                point=_column(loads, "point", (3,)), w=_column(loads, "w", (6,)),
                law=[core_tuple(ld["law"]) for ld in loads],
                reaction=np.array([ld.get("reaction", -1) for ld in loads], dtype=float))


def components(desc: ModelDescription, poses: np.ndarray, twists: np.ndarray, x0: np.ndarray,
               drop_masks: Optional[Sequence[int]] = None, frames_a: Optional[Sequence] = None,
               extra_loads: Sequence[dict] = ()) -> dict:
    """The arguments of ``_core.model_new`` for ``desc`` at initial ``poses`` (nc, 4, 4) and body
    ``twists`` (nc, 6), with the pairs' joint coordinates ``x0`` (npairs, 6), their
    redundant-row masks ``drop_masks`` (None: none dropped) and frame offsets on carrier a
    ``frames_a`` (None: the rows' Ta; see topology.place_tree), and ``extra_loads`` (load rows)
    after the description's own loads: one dict of columns per component kind, and gravity.
    The dicts and lists are new; the arrays of the description's own columns are shared between
    calls (read-only)."""
    cols = {kind: {key: list(v) if isinstance(v, list) else v for key, v in d.items()}
            for kind, d in _description_columns(desc).items()}
    pr = desc.pairs
    frames_a = [p["Ta"] for p in pr] if frames_a is None else frames_a
    loads = cols["loads"]
    if extra_loads:
        more = _load_columns(extra_loads)
        loads = {k: (v + more[k]) if isinstance(v, list) else np.concatenate([v, more[k]])
                 for k, v in loads.items()}
    return dict(
        carriers=dict(cols["carriers"], H0=np.asarray(poses, dtype=float),
                      t0=np.asarray(twists, dtype=float)),
        elements=cols["elements"],
        pairs=dict(cols["pairs"], Ta=np.array(frames_a, dtype=float).reshape(-1, 4, 4),
                   x0=np.asarray(x0, dtype=float).reshape(-1, 6),
                   drop=np.zeros(len(pr)) if drop_masks is None else np.array(drop_masks, dtype=float)),
        loads=loads,
        actuators=cols["actuators"],
        springs=dict(cols["springs"], rest_length=_rest_lengths(desc, poses)),
        gravity=np.asarray(desc.gravity, dtype=float),
        couplings=cols["couplings"], components=cols["components"])


def core_model(desc: ModelDescription, poses: np.ndarray, twists: np.ndarray, x0: np.ndarray,
               drop_masks: Optional[Sequence[int]] = None, frames_a: Optional[Sequence] = None,
               extra_loads: Sequence[dict] = ()):
    """A core model (capsule) of ``desc`` at an initial state (the arguments of components).
    Raises ModelError when the core refuses the model."""
    return _core.model_new(**components(desc, poses, twists, x0, drop_masks, frames_a, extra_loads))


def with_initial(model, desc: ModelDescription, built_at: np.ndarray, poses: np.ndarray,
                 twists: np.ndarray, x0: np.ndarray, drop_masks: Sequence[int]):
    """``model`` (made by core_model of ``desc`` at poses ``built_at``) moved to a new initial
    state -- poses, twists, x0, drop masks, as in core_model -- without rebuilding it
    (``_core.model_set_initial``); None when that state needs a new model: a spring's default
    rest length (its initial distance) differs at ``poses``."""
    if not np.array_equal(_rest_lengths(desc, built_at), _rest_lengths(desc, poses)):
        return None
    _core.model_set_initial(model, np.asarray(poses, dtype=float), np.asarray(twists, dtype=float),
                            np.asarray(x0, dtype=float).reshape(-1, 6),
                            np.array(drop_masks, dtype=float).reshape(-1))
    return model


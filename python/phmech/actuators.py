"""Actuators on a pair's joint coordinates: effort sources, PD control and joint spring-dampers.

Each acts with a generalized effort u (k,) power-conjugate to the joint rates xdot: torques
[N m] on angles, forces [N] on displacements (csrc/include/phmech_types.h, phm_actuator_desc). Its power
u . xdot is a port of the energy ledger, named after the actuator."""
from __future__ import annotations

import dataclasses

import numpy as np

from ._checks import per_coordinate
from ._errors import ModelError
from .laws import Constant, _Law, checked_law

__all__ = ["Effort", "PD", "Spring"]


@dataclasses.dataclass(frozen=True)
class Effort:
    """Effort source u(t) = law(t) * direction on the pair's joint coordinates (torque [N m] for
    angles, force [N] for displacements); power u . xdot."""
    law: object = None
    direction: object = None


@dataclasses.dataclass(frozen=True)
class PD:
    """PD control to a set-point trajectory: u = -kp (x - x_ref) - kd (xdot - xdot_ref), with
    x_ref(t) = offset + target(t) * direction and xdot_ref = target'(t) * direction. ``target``: a
    time law or a number; gains: numbers or one per coordinate."""
    kp: object
    kd: object
    target: object = 0.0
    direction: object = None
    offset: object = None


@dataclasses.dataclass(frozen=True)
class Spring:
    """Joint spring-damper: u = -k (x - rest) - c xdot; ``rest`` defaults to the pair's x0 (or 0)."""
    k: object
    c: object = 0.0
    rest: object = None


def actuator_row(name: str, pair_row: dict, index: int, act) -> dict:
    """The description row of actuator ``act`` named ``name`` on the pair row ``pair_row`` (at
    position ``index`` among the pairs), validated (ModelError otherwise): kind ("effort", "pd"
    or "spring"), vec, kp, kd, xset (6 entries, the first k used) and law."""
    k = pair_row["k"]
    what = f"actuator {name!r}"
    if k == 0:
        raise ModelError(f"{what}: a fixed pair has no allowed direction to actuate")
    z = np.zeros(6)
    vec, kp, kd, xs, law = z.copy(), z.copy(), z.copy(), z.copy(), None
    if isinstance(act, Effort):
        kind = "effort"
        law = checked_law(Constant(1.0) if act.law is None else act.law, f"{what}: Effort law",
                          numbers_too=True)
        vec[:k] = per_coordinate(act.direction, k, f"{what}: direction")
    elif isinstance(act, PD):
        kind = "pd"
        kp[:k] = per_coordinate(act.kp, k, f"{what}: kp")
        kd[:k] = per_coordinate(act.kd, k, f"{what}: kd")
        d = per_coordinate(act.direction, k, f"{what}: direction")
        xs[:k] = per_coordinate(act.offset, k, f"{what}: offset", default=0.0)
        if isinstance(act.target, _Law) or callable(act.target):
            law = checked_law(act.target, f"{what}: PD target")
            vec[:k] = d
        else:
            with np.errstate(over="ignore", invalid="ignore"):   # checked below
                target = per_coordinate(act.target, k, f"{what}: target")
                xs[:k] += target * (d if act.direction is not None else 1.0)
            law = Constant(0.0)
    elif isinstance(act, Spring):
        kind = "spring"
        kp[:k] = per_coordinate(act.k, k, f"{what}: k")
        kd[:k] = per_coordinate(act.c, k, f"{what}: c")
        xs[:k] = pair_row["x0"][:k] if act.rest is None else per_coordinate(act.rest, k, f"{what}: rest")
    else:
        raise ModelError(f"{what}: expected Effort, PD or Spring (got {type(act).__name__})")
    if kind != "effort" and (np.any(kp[:k] < 0) or np.any(kd[:k] < 0)):
        raise ModelError(f"{what}: gains must be >= 0")
    if not np.all(np.isfinite(xs)):
        raise ModelError(f"{what}: the set point (offset + target times direction) is not "
                         f"finite in double precision: {xs[:k].tolist()}")
    return dict(name=name, pair=index, kind=kind, vec=vec, kp=kp, kd=kd, xset=xs, law=law)

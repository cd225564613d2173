"""Sampled (digital) controllers with a zero-order hold.

``SampledController(f, rate_hz, inputs, outputs, delay=0.0, state=None, u0=None)``: at the sample
instants t_k = t_start + k / rate_hz of a run, ``f(t_k, y_k, state) -> (u_k, state)`` is called
with y_k the concatenated values of the sensors named in ``inputs`` (``phmech.sensors``,
``Mechanism.add_sensor``) at t_k; u_k (one number per output) is held from t_k + delay until the
next value takes over. Each output is the effort on one joint coordinate of a pair
(``EffortOutput``, or the pair's name: its coordinate 0; a torque [N m] or force [N]), a wrench
``u_j * wrench`` on a frame (``WrenchOutput``; wrench (tau [N m], f [N]) per unit of u), or a DC
motor's voltage [V] (``MotorVoltageOutput``). The efforts' and wrenches' powers are ports of the
energy ledger, named ``name[j]``; a motor's electrical power is its own supplied energy.

How a run holds u (python/phmech/_sampled.py): the sample and switch instants are output times
of the run (the result keeps only the asked ones) and breakpoints of the outputs' laws, so the
integrator stops at each one, the controller is called between the output and the restart, and
the integrator restarts there from consistent values with the new u (the generalized-alpha
integrator only: IDA restarts before its output). ``Mechanism.add_controller(name,
controller)`` adds one; ``res.controllers[name]`` holds its sample times, inputs and outputs."""
from __future__ import annotations

import dataclasses
from typing import Callable, Optional, Sequence

import numpy as np

from ._checks import per_coordinate, real
from ._errors import ModelError

__all__ = ["SampledController", "EffortOutput", "WrenchOutput", "MotorVoltageOutput",
           "controller_row"]


@dataclasses.dataclass(frozen=True)
class EffortOutput:
    """A controller output driving the effort on joint coordinate ``coordinate`` of the pair
    named ``pair`` (a torque [N m] on an angle, a force [N] on a displacement)."""
    pair: str
    coordinate: int = 0


@dataclasses.dataclass(frozen=True)
class WrenchOutput:
    """A controller output u applying the wrench u * ``wrench`` (tau [N m], f [N] per unit of u)
    on ``target`` (a Frame or Body) at ``point`` (target frame coordinates [m]), in "world" or
    "body" axes (as ``Mechanism.add_wrench``)."""
    target: object
    wrench: Sequence[float]
    frame: str = "world"
    point: Sequence[float] = (0.0, 0.0, 0.0)


@dataclasses.dataclass(frozen=True)
class MotorVoltageOutput:
    """A controller output driving the voltage [V] of the DC motor named ``motor``
    (``phmech.DCMotor`` with ``voltage=``, added before the controller; the controller's
    output replaces its voltage law): a digital drive."""
    motor: str


@dataclasses.dataclass(frozen=True)
class SampledController:
    """A digital controller at ``rate_hz`` [Hz] with a zero-order hold: ``f(t, y, state) -> (u,
    state)``, t [s] the sample instant, y (ny,) the concatenated values of the sensors named
    in ``inputs`` (in their units: ``phmech.sensors``), u (nu,) one number per entry of
    ``outputs`` (``EffortOutput``, a pair name, or ``WrenchOutput``), ``state`` any Python
    object the controller keeps (``state`` here: its initial value). ``delay`` [s], 0 <= delay
    < 1 / rate_hz: the computation delay, u_k acts from t_k + delay; ``u0`` (nu,) what acts
    before the first u does (zeros). The rate must divide the run: (t_end - t_start) * rate_hz
    a whole number."""
    f: Callable
    rate_hz: float
    inputs: Sequence[str] = ()
    outputs: Sequence[object] = ()
    delay: float = 0.0
    state: object = None
    u0: Optional[Sequence[float]] = None


def controller_row(name: str, ctrl, sensors: dict) -> dict:
    """The validated row of controller ``ctrl`` named ``name`` (ModelError naming it
    otherwise), ``sensors`` the mechanism's sensor rows by name: f, rate, period, delay, state,
    inputs (sensor names), ny, outputs (EffortOutput or WrenchOutput), u0."""
    what = f"controller {name!r}"
    if not isinstance(ctrl, SampledController):
        raise ModelError(f"{what}: expected a SampledController (got {type(ctrl).__name__})")
    if not callable(ctrl.f) or isinstance(ctrl.f, type):
        raise ModelError(f"{what}: f must be a function f(t, y, state) -> (u, state) (got "
                         f"{type(ctrl.f).__name__})")
    if ctrl.rate_hz is None:
        raise ModelError(f"{what}: rate_hz is missing")
    rate = real(f"{what}: rate_hz", ctrl.rate_hz)
    if not rate > 0:
        raise ModelError(f"{what}: rate_hz must be > 0 [Hz] (got {rate})")
    delay = real(f"{what}: delay", ctrl.delay)
    if not 0.0 <= delay < 1.0 / rate:
        raise ModelError(f"{what}: delay must be in [0, 1/rate_hz) = [0, {1.0 / rate:g}) s "
                         f"(got {delay})")
    inputs = [ctrl.inputs] if isinstance(ctrl.inputs, str) else list(ctrl.inputs or ())
    for s in inputs:
        if not isinstance(s, str) or s not in sensors:
            raise ModelError(f"{what}: input {s!r} is not a sensor of this mechanism (sensors: "
                             f"{', '.join(map(repr, sensors)) or 'none'}; Mechanism.add_sensor)")
    outputs = [ctrl.outputs] if isinstance(ctrl.outputs, (str, EffortOutput, WrenchOutput,
                                                          MotorVoltageOutput)) \
        else list(ctrl.outputs or ())
    if not outputs:
        raise ModelError(f"{what}: no outputs (give pair names, EffortOutput or WrenchOutput)")
    outs = []
    for o in outputs:
        if isinstance(o, str):
            o = EffortOutput(o)
        if not isinstance(o, (EffortOutput, WrenchOutput, MotorVoltageOutput)):
            raise ModelError(f"{what}: output {o!r} is not a pair name, EffortOutput, "
                             f"WrenchOutput or MotorVoltageOutput")
        outs.append(o)
    u0 = per_coordinate(ctrl.u0, len(outs), f"{what}: u0", default=0.0)
    return dict(name=name, f=ctrl.f, rate=rate, period=1.0 / rate, delay=delay,
                state=ctrl.state, inputs=inputs, ny=sum(sensors[s]["size"] for s in inputs),
                outputs=outs, u0=np.array(u0[:len(outs)], dtype=float))


def voltage_input(desc, name: str, j: int, o: MotorVoltageOutput, taken: list) -> dict:
    """The component row of the DC motor whose voltage output ``j`` of controller ``name``
    drives (a voltage-input motor of ``desc`` no controller drives yet, nor one of ``taken``,
    this controller's other outputs); ModelError otherwise."""
    c = [r for r in desc.components if r["name"] == o.motor]
    if not c or c[0]["kind"] != "motor" or c[0]["input"] != 0:
        raise ModelError(f"controller {name!r}: output {j} drives {o.motor!r}, which "
                         f"is not a DC motor with a voltage input of this mechanism")
    if any(c[0] is r for rr in desc.controllers for r in rr["law_rows"]) or \
            any(c[0] is r for r in taken):
        raise ModelError(f"controller {name!r}: motor {o.motor!r} already has a "
                         f"controller's voltage")
    return c[0]


def zero(t: float) -> float:
    """The time derivatives of a held value [per s] (a controller output's law)."""
    return 0.0


class Hold:
    """The values a controller's outputs hold, read by their laws (``value(j)``): one per
    output, changed only between an output of the run and the integrator's restart."""

    def __init__(self, u0: np.ndarray):
        self.u = np.array(u0, dtype=float)

    def law_fn(self, j: int) -> Callable[[float], float]:
        """The function of time a Function law of output j calls: the held value (the run's
        breakpoints make the integrator restart where it changes)."""
        return _Held(self.u, j)


class _Held:
    """Output j's held value as a function of time; ``core_call`` answers the core's law
    callback (csrc/pyext/py_laws.c: (t, nder) -> (s, s', s'')) without the checks of a user's
    Function (phmech.laws._FunctionCall): the value is finite, checked when it was set
    (python/phmech/_sampled.py). Measured on a pendulum at 1 kHz: 14462 calls in 1 s of
    simulated time; a call 0.20 against 2.7 us from Python (timeit, 2026-12-06)."""

    def __init__(self, u: np.ndarray, j: int):
        self.u, self.j = u, j

    def __call__(self, t: float) -> float:
        return float(self.u[self.j])

    def core_call(self, t: float, nder: int) -> tuple:
        return (float(self.u[self.j]), 0.0, 0.0)

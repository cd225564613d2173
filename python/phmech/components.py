"""Components with internal states on a pair's joint coordinate: friction and DC motors.

Each is a port-Hamiltonian system (docs/method.md section 4.11) whose mechanical port is the
effort u and the rate v = xdot of one coordinate of a revolute or prismatic pair (a torque [N m]
and an angular rate [rad/s], or a force [N] and a speed [m/s]); its internal states (a LuGre
bristle deflection z, a motor current i) are states of the DAE, integrated with the mechanism.
Its stored energy is counted with the elastic energy of ``res.energy``, its losses in the
dissipated and its sources (a motor's electrical power) in the supplied energy, so the ledger
closes over the components too. ``Mechanism.add_component(name, pair, component)`` adds one;
``res.components[name]`` holds its states over the run.

Friction laws (v the joint rate, g(v) = Fc + (Fs - Fc) exp(-(v/vs)^2) the Stribeck curve):

- ``ViscousFriction(c)``: u = -c v;
- ``CoulombFriction(Fc, v_reg)``: u = -Fc tanh(v / v_reg), Coulomb's law regularized over
  v_reg (stateless; sticking is a slow creep at abs(v) << v_reg: use ``LuGreFriction`` for true
  stiction, whose bristles hold the load without creep);
- ``StribeckFriction(Fc, Fs, vs, viscous, v_reg)``: u = -g(v) tanh(v / v_reg) - viscous v;
- ``LuGreFriction(sigma0, sigma1, sigma2, Fc, Fs, vs)``: the dynamic model of Canudas de Wit,
  Olsson, Astrom and Lischinsky (IEEE TAC 40(3), 1995): z' = v - sigma0 abs(v) z / g(v),
  u = -(sigma0 z + sigma1 z' + sigma2 v), storage sigma0 z^2 / 2.

``DCMotor(L, R, k, J, ratio, efficiency, voltage=law | current=law)``: armature
L i' = V(t) - R i - k n v, joint effort u = efficiency n k i, rotor inertia J reflected to the
joint as J n^2 (n the gear ratio, motor speed n v); storage L i^2 / 2, supplied power V i,
dissipated R i^2 + (1 - efficiency) n k i v (copper and gear losses).

``LinearController(A, B, C, D, reference)``: a linear state-space controller on the coordinate's
error and rate, its states in the DAE (a compiled route for feedback: no Python call per
residual).

``CallbackController(f, jacobian=None, step=1e-7)``: u = f(t, y), y = (x, v) the coordinate and
its rate, a Python function called inside the DAE (once per residual, and with its derivatives
per Jacobian); a source like LinearController.

``PortHamiltonianController(J, R, Q, B, damping, target, x0)``: a passive controller given as a
port-Hamiltonian system (energy shaping and damping injection): states xc, energy
H = (xc - target)^T Q (xc - target) / 2, xc' = (J - R) Q (xc - target) + B v,
u = -B^T Q (xc - target) - damping v; its energy is stored (in ``res.energy``), its losses
dissipated, and it supplies nothing: the ledger closes with it."""
from __future__ import annotations

import dataclasses
from typing import Optional

import numpy as np

from ._checks import real
from ._errors import ControllerError, ModelError
from .laws import Function, checked_law

__all__ = ["ViscousFriction", "CoulombFriction", "StribeckFriction", "LuGreFriction", "DCMotor",
           "LinearController", "CallbackController", "PortHamiltonianController",
           "component_row"]

#: the core's component kinds (csrc/include/phmech_types.h, phm_component_kind)
_KINDS = {"viscous": 0, "coulomb": 1, "stribeck": 2, "lugre": 3, "motor": 4, "linear": 5,
          "callback": 6, "ph": 7}
#: parameters and internal states per component, at most (PHM_COMP_NPAR, PHM_COMP_MAXZ), and a
#: port-Hamiltonian controller's states (PHM_COMP_PH_MAXZ)
NPAR, MAXZ, PH_MAXZ = 32, 4, 2


@dataclasses.dataclass(frozen=True)
class ViscousFriction:
    """Viscous friction u = -c v; c [N s/m or N m s/rad] >= 0."""
    c: float


@dataclasses.dataclass(frozen=True)
class CoulombFriction:
    """Coulomb friction regularized over ``v_reg``: u = -Fc tanh(v / v_reg); Fc [N or N m] >= 0,
    v_reg [m/s or rad/s] > 0."""
    Fc: float
    v_reg: float = 1e-3


@dataclasses.dataclass(frozen=True)
class StribeckFriction:
    """Stribeck friction u = -(Fc + (Fs - Fc) exp(-(v/vs)^2)) tanh(v / v_reg) - viscous v."""
    Fc: float
    Fs: float
    vs: float
    viscous: float = 0.0
    v_reg: float = 1e-4


@dataclasses.dataclass(frozen=True)
class LuGreFriction:
    """LuGre friction (Canudas de Wit et al. 1995) with its bristle deflection z [m or rad] as a
    state: z' = v - sigma0 abs(v) z / g(v), u = -(sigma0 z + sigma1 z' + sigma2 v). sigma0
    [N/m] > 0 bristle stiffness, sigma1 [N s/m] >= 0 bristle damping, sigma2 [N s/m] >= 0
    viscous, Fc <= Fs [N] Coulomb and static levels, vs [m/s] > 0 Stribeck speed; z0 the
    initial deflection."""
    sigma0: float
    sigma1: float
    sigma2: float
    Fc: float
    Fs: float
    vs: float
    z0: float = 0.0


@dataclasses.dataclass(frozen=True)
class DCMotor:
    """A DC motor with gearbox on the joint: L [H] inductance, R [ohm] resistance, k [N m/A =
    V s/rad] torque constant, J [kg m^2] rotor inertia (reflected as J n^2), ratio n (motor
    angle per joint coordinate), efficiency in (0, 1] (the joint gets efficiency n k i). Input:
    ``voltage`` V(t) [V] (a law or a number; the current i [A] is then a state, from i0) or
    ``current`` i(t) [A] (no state)."""
    L: Optional[float] = None
    R: Optional[float] = None
    k: Optional[float] = None
    J: float = 0.0
    ratio: float = 1.0
    efficiency: float = 1.0
    voltage: object = None
    current: object = None
    i0: float = 0.0


@dataclasses.dataclass(frozen=True)
class LinearController:
    """A linear state-space controller on the pair's coordinate, its states xc (at most 4) in
    the DAE: with the measurement y = (x - reference(t), v) (the coordinate's error [m or rad]
    and its rate),

        xc' = A xc + B y,     u = C xc + D y       (u: the effort on the coordinate, N or N m).

    A (n, n), B (n, 2), C (n,), D (2,); n = 0 (A, B, C empty) is a static gain, e.g. a PD
    D = (-kp, -kd); an integral action is a state xc' = x - r with C = -ki. ``reference``: a
    law or a number [m or rad]; ``x0``: the initial states (zeros). The controller is a source:
    its power u v is supplied energy (as an actuator's), and its states store none.
    ``sensor``: the name of another pair (of any type) whose coordinate ``sensor_coordinate``
    it measures instead of its own (non-collocated feedback; None: the pair it drives)."""
    A: object = ()
    B: object = ()
    C: object = ()
    D: object = (0.0, 0.0)
    reference: object = 0.0
    x0: object = None
    sensor: Optional[str] = None
    sensor_coordinate: int = 0


@dataclasses.dataclass(frozen=True)
class CallbackController:
    """A continuous feedback u = f(t, y) on the pair's coordinate, evaluated inside the DAE: t
    [s], y = (x, v) the coordinate [m or rad] and its rate [m/s or rad/s] (a tuple), u the effort
    [N or N m] (a real number). The Jacobian needs du/dx and du/dv: ``jacobian(t, y) -> (du/dx,
    du/dv)`` when given, else central differences of f with steps ``step`` * max(1, abs(x)) and
    ``step`` * max(1, abs(v)) (four more calls). The core calls back into Python, with the GIL,
    at every residual (one call) and Jacobian (one call, or five with the differences):
    measured about 1.5 us per call on a pendulum (docs/user_guide.md, "Continuous Python
    controllers"); ``LinearController`` is the compiled route. Collocated: it measures the
    coordinate it drives. A source: its power u v is supplied energy. When f raises or returns
    something other than a finite real number the run stops with a ControllerError naming the
    component and the time, its ``result`` the trajectory up to the last output before."""
    f: object
    jacobian: object = None
    step: float = 1e-7


class _ControlCall:
    """What the core calls for a CallbackController (csrc/pyext/py_laws.c,
    phm_py_control_callback): ``control(t, x, v, nder) -> (u, du/dx, du/dv)`` (zeros for the
    derivatives with nder 0), or None after a failure, kept in ``failure``. It travels to the
    core as the callable of its component's law (``core_call``: python/phmech/laws.py), which the
    core never evaluates as a law."""

    def __init__(self, name: str, comp: CallbackController):
        self.name, self.f, self.jacobian = name, comp.f, comp.jacobian
        self.step = comp.step
        self.failure = None

    @property
    def core_call(self) -> "_ControlCall":
        return self

    def __call__(self, t: float) -> float:   # as a law's function (checked once: 0)
        return 0.0

    def _fail(self, t: float, msg: str, cause: Optional[BaseException] = None) -> None:
        err = ControllerError(f"component {self.name!r} at t = {t:.9g} s: {msg}")
        err.component, err.time = self.name, t
        if cause is not None:
            err.__cause__ = cause
        self.failure = err
        return None

    def _u(self, f, t: float, y: tuple, what: str) -> float:
        u = f(t, y)
        if isinstance(u, np.ndarray) and u.size == 1:
            u = u.reshape(())[()]
        if isinstance(u, (bool, np.bool_)) or not isinstance(u, (int, float, np.integer,
                                                                  np.floating)):
            raise _Bad(f"{what} returned {type(u).__name__} {u!r:.60}, not a real number")
        u = float(u)
        if not np.isfinite(u):
            raise _Bad(f"{what} returned {u}")
        return u

    def control(self, t: float, x: float, v: float, nder: int):
        if self.failure is not None:
            return None
        try:
            u = self._u(self.f, t, (x, v), "its function")
            if not nder:
                return (u, 0.0, 0.0)
            if self.jacobian is not None:
                d = self.jacobian(t, (x, v))
                d = np.asarray(d, dtype=float).reshape(-1) if d is not None else np.zeros(0)
                if d.shape != (2,) or not np.all(np.isfinite(d)):
                    raise _Bad(f"its jacobian must return two finite numbers (du/dx, du/dv), "
                               f"got {d.tolist()}")
                return (u, float(d[0]), float(d[1]))
            hx, hv = self.step * max(1.0, abs(x)), self.step * max(1.0, abs(v))
            f = self.f
            ux = (self._u(f, t, (x + hx, v), "its function") -
                  self._u(f, t, (x - hx, v), "its function")) / (2 * hx)
            uv = (self._u(f, t, (x, v + hv), "its function") -
                  self._u(f, t, (x, v - hv), "its function")) / (2 * hv)
            return (u, ux, uv)
        except _Bad as e:
            return self._fail(t, str(e))
        except Exception as e:   # noqa: BLE001 -- the user's function: reported with the result
            return self._fail(t, f"its function raised {type(e).__name__}: {e}", e)


class _Bad(Exception):
    """A callback controller's malformed answer (reported as a ControllerError)."""


@dataclasses.dataclass(frozen=True)
class PortHamiltonianController:
    """A passive controller on the pair's coordinate given as a port-Hamiltonian system
    (docs/method.md section 4.11; energy shaping and damping injection, control by
    interconnection): its n states xc (n = 1 or 2) store H = (xc - target)^T Q (xc - target) / 2
    and, with the coordinate's rate v [m/s or rad/s] at its port,

        xc' = (J - R) Q (xc - target) + B v,     u = -B^T Q (xc - target) - damping v

    (u the effort on the coordinate, N or N m). J (n, n) skew-symmetric, R (n, n) and Q (n, n)
    symmetric positive semidefinite, B (n,), damping >= 0 [N s/m or N m s/rad]: a damper
    injected at the port. Its power balance dH/dt = -u v - P_d, P_d = (Q e)^T R (Q e) + damping
    v^2 >= 0: H is stored energy (with the elastic energy of ``res.energy``), P_d dissipated,
    nothing supplied. With n = 1, J = R = 0, Q = kp, B = 1 and x0 the coordinate's initial
    value, xc follows the coordinate (a Casimir: xc - x is constant) and the controller is a
    virtual spring kp to ``target`` with the damper: a PD whose spring energy is in the ledger.
    ``x0``: the initial states (zeros); ``target``: xc* (zeros)."""
    J: object = ((0.0,),)
    R: object = ((0.0,),)
    Q: object = ((1.0,),)
    B: object = (1.0,)
    damping: float = 0.0
    target: object = None
    x0: object = None


def _ph_row(what: str, comp) -> tuple:
    """(par, z0, nstates) of a PortHamiltonianController; ModelError naming ``what``."""
    Q = np.asarray(comp.Q, dtype=float) if np.size(comp.Q) else np.zeros((0, 0))
    n = int(round(np.sqrt(Q.size)))
    if not 1 <= n <= PH_MAXZ:
        raise ModelError(f"{what}: {n} controller states; a port-Hamiltonian controller has 1 "
                         f"to {PH_MAXZ}")
    J = _matrix(f"{what}: J", comp.J, (n, n))
    R = _matrix(f"{what}: R", comp.R, (n, n))
    Q = _matrix(f"{what}: Q", comp.Q, (n, n))
    B = _matrix(f"{what}: B", comp.B, (n,))
    d = real(f"{what}: damping", comp.damping)
    tol = 1e-12
    if np.abs(J + J.T).max() > tol * max(np.abs(J).max(), 1.0):
        raise ModelError(f"{what}: J must be skew-symmetric")
    for nm, X in (("R", R), ("Q", Q)):
        if np.abs(X - X.T).max() > tol * max(np.abs(X).max(), 1.0) or \
                np.linalg.eigvalsh(0.5 * (X + X.T)).min() < -tol * max(np.abs(X).max(), 1.0):
            raise ModelError(f"{what}: {nm} must be symmetric positive semidefinite")
    if d < 0:
        raise ModelError(f"{what}: damping must be >= 0 (got {d})")
    xs = np.zeros(n) if comp.target is None else _matrix(f"{what}: target", comp.target, (n,))
    z0 = np.zeros(MAXZ)
    if comp.x0 is not None:
        z0[:n] = _matrix(f"{what}: x0", comp.x0, (n,))
    par = np.zeros(NPAR)
    p = [*J.ravel(), *R.ravel(), *Q.ravel(), *B, d, *xs]
    par[:len(p)] = p
    return par, z0, n


def _matrix(what: str, v, shape: tuple) -> np.ndarray:
    """``v`` as a finite float array of ``shape``; ModelError naming ``what`` otherwise."""
    try:
        a = np.asarray(v, dtype=float)
    except (TypeError, ValueError):
        raise ModelError(f"{what}: expected numbers of shape {shape}") from None
    if a.size == 0 and 0 in shape:
        return a.reshape(shape)
    if a.shape != shape:
        try:
            a = a.reshape(shape)
        except ValueError:
            raise ModelError(f"{what}: expected shape {shape}, got {np.shape(v)}") from None
    if not np.all(np.isfinite(a)):
        raise ModelError(f"{what}: not finite")
    return a


def _params(what: str, comp, names: tuple) -> list:
    """The named parameters of ``comp`` as floats; ModelError naming a missing one."""
    out = []
    for nm in names:
        v = getattr(comp, nm)
        if v is None:
            raise ModelError(f"{what}: parameter {nm!r} is missing")
        out.append(real(f"{what}: {nm}", v))
    return out


def component_row(name: str, pair_row: dict, index: int, comp,
                  sensor: Optional[tuple] = None) -> dict:
    """The description row of component ``comp`` named ``name`` on the pair row ``pair_row`` (at
    position ``index`` among the pairs), validated (ModelError naming the component otherwise):
    kind, pair, coord, par (NPAR), input, z0 (MAXZ), law, nstates, states (their names), spair,
    scoord. ``sensor``: (index, k) of a LinearController's sensor pair (add_component finds it
    by name), None for its own."""
    what = f"component {name!r}"
    tname = type(pair_row["pair"]).__name__.lower()
    if tname not in ("revolute", "prismatic"):
        raise ModelError(f"{what}: friction and motors act on revolute and prismatic pairs only "
                         f"(pair {pair_row['name']!r} is {type(pair_row['pair']).__name__})")
    par, z0, law, inp, states = np.zeros(NPAR), np.zeros(MAXZ), None, 0, ()
    if isinstance(comp, LinearController):
        A = np.asarray(comp.A, dtype=float) if np.size(comp.A) else np.zeros((0, 0))
        n = int(round(np.sqrt(A.size)))
        if n > MAXZ:
            raise ModelError(f"{what}: {n} controller states, at most {MAXZ}")
        A = _matrix(f"{what}: A", comp.A, (n, n))
        B = _matrix(f"{what}: B", comp.B, (n, 2))
        C = _matrix(f"{what}: C", comp.C, (n,))
        D = _matrix(f"{what}: D", comp.D, (2,))
        p = [*A.ravel(), *B.ravel(), *C, *D]
        par[:len(p)] = p
        if comp.x0 is not None:
            z0[:n] = _matrix(f"{what}: x0", comp.x0, (n,))
        law = checked_law(comp.reference, f"{what}: reference", numbers_too=True)
        states = tuple(f"x{j}" for j in range(n))
        spair, scoord = -1, 0
        if comp.sensor is not None:
            spair, ks = sensor
            scoord = comp.sensor_coordinate
            if not isinstance(scoord, (int, np.integer)) or not 0 <= scoord < ks:
                raise ModelError(f"{what}: sensor_coordinate {scoord!r} is not one of the sensor "
                                 f"pair's {ks} coordinates")
        return dict(name=name, kind="linear", code=_KINDS["linear"], pair=index, coord=0,
                    par=par, input=0, z0=z0, law=law, nstates=n, states=states,
                    spair=spair, scoord=int(scoord))
    if isinstance(comp, CallbackController):
        if not callable(comp.f) or isinstance(comp.f, type):
            raise ModelError(f"{what}: f must be a function f(t, y) -> u (got "
                             f"{type(comp.f).__name__})")
        if comp.jacobian is not None and not callable(comp.jacobian):
            raise ModelError(f"{what}: jacobian must be a function jacobian(t, y) -> (du/dx, "
                             f"du/dv) or None")
        if not real(f"{what}: step", comp.step) > 0:
            raise ModelError(f"{what}: step must be > 0 (got {comp.step})")
        call = _ControlCall(name, comp)
        return dict(name=name, kind="callback", code=_KINDS["callback"], pair=index, coord=0,
                    par=par, input=0, z0=z0, law=checked_law(Function(call), what), nstates=0,
                    states=(), spair=-1, scoord=0, call=call)
    if isinstance(comp, PortHamiltonianController):
        par, z0, n = _ph_row(what, comp)
        return dict(name=name, kind="ph", code=_KINDS["ph"], pair=index, coord=0, par=par,
                    input=0, z0=z0, law=None, nstates=n, states=tuple(f"x{j}" for j in range(n)),
                    spair=-1, scoord=0)
    if isinstance(comp, ViscousFriction):
        kind, p = "viscous", _params(what, comp, ("c",))
        ok = p[0] >= 0
    elif isinstance(comp, CoulombFriction):
        kind, p = "coulomb", _params(what, comp, ("Fc", "v_reg"))
        ok = p[0] >= 0 and p[1] > 0
    elif isinstance(comp, StribeckFriction):
        kind, p = "stribeck", _params(what, comp, ("Fc", "Fs", "vs", "viscous", "v_reg"))
        ok = p[0] >= 0 and p[1] >= 0 and p[2] > 0 and p[3] >= 0 and p[4] > 0
    elif isinstance(comp, LuGreFriction):
        kind, p = "lugre", _params(what, comp, ("sigma0", "sigma1", "sigma2", "Fc", "Fs", "vs"))
        ok = p[0] > 0 and p[1] >= 0 and p[2] >= 0 and p[3] > 0 and p[4] > 0 and p[5] > 0
        z0[0] = real(f"{what}: z0", comp.z0)
    elif isinstance(comp, DCMotor):
        kind = "motor"
        if (comp.voltage is None) == (comp.current is None):
            raise ModelError(f"{what}: give exactly one input, voltage= or current=")
        inp = 0 if comp.voltage is not None else 1
        p = _params(what, comp, ("L", "R", "k", "ratio", "efficiency", "J"))
        ok = (p[0] > 0 if inp == 0 else p[0] >= 0) and p[1] >= 0 and p[2] > 0 and p[3] != 0 \
            and 0 < p[4] <= 1 and p[5] >= 0
        law = checked_law(comp.voltage if inp == 0 else comp.current,
                          f"{what}: {'voltage' if inp == 0 else 'current'}", numbers_too=True)
        z0[0] = real(f"{what}: i0", comp.i0)
    else:
        raise ModelError(f"{what}: expected ViscousFriction, CoulombFriction, StribeckFriction, "
                         f"LuGreFriction, DCMotor, LinearController, CallbackController or "
                         f"PortHamiltonianController (got {type(comp).__name__})")
    if not ok:
        raise ModelError(f"{what}: a parameter is out of range ({kind}: {p}; see "
                         f"phmech.components for each one's range)")
    par[:len(p)] = p
    states = {"lugre": ("z",), "motor": ("i",) if inp == 0 else ()}.get(kind, ())
    return dict(name=name, kind=kind, code=_KINDS[kind], pair=index, coord=0, par=par,
                input=inp, z0=z0, law=law, nstates=len(states), states=states, spair=-1, scoord=0)


def state_layout(rows: list) -> dict:
    """Each component's slice of the core's internal states (grouped by pair in the given order
    within a pair, as csrc/model/component.c lays them out): name -> (first, count)."""
    out, z = {}, 0
    for i in sorted(range(len(rows)), key=lambda i: rows[i]["pair"]):
        out[rows[i]["name"]] = (z, rows[i]["nstates"])
        z += rows[i]["nstates"]
    return out

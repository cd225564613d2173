"""Sampled controllers in a run (python/phmech/controllers.py): the instants, the laws that hold
their outputs, the calls at each sample, and the sensors and samples in the result.

The design: every sample instant t_k = t_start + k / rate (and with a delay, every switch
instant t_k + delay) is an output time of the core's run and a breakpoint of the controller's
output laws (Function laws returning the held value, ``controllers.Hold``). The
generalized-alpha integrator lands on it, emits the output (whose callback, ``Sampler.on_output``,
reads the sensors from the output arrays, calls f and sets the held value) and then restarts
at the breakpoint from consistent values with the new value (csrc/integrate/galpha.c, run_galpha:
a breakpoint at an output is restarted after it). The first sample, at t_start, is taken in a
one-output run before the run (``initial_sample``), so that the run's consistent initial values
already hold u_0. The result keeps only the outputs asked for (``Plan.user``)."""
from __future__ import annotations

from typing import Optional

import numpy as np

from ._errors import ControllerError, ModelError
from .components import state_layout
from .controllers import zero
from .laws import Function
from .sensors import sensor_values


class Plan:
    """The output times of a run with sampled controllers: ``tout`` (the user's and the
    instants, merged), ``user`` (per output, its index among the user's, or -1), per controller
    ``samples`` and ``switches`` (the outputs where sample k is taken and where it takes over;
    -1 beyond the run) and ``breakpoints`` (switch times after t_start)."""

    def __init__(self, ctrls: list, tout: np.ndarray):
        t0, t1 = float(tout[0]), float(tout[-1])
        tol = 1e-9 * min(c["period"] for c in ctrls)
        inst = []   # per controller: the sample times and switch times
        for c in ctrls:
            n = (t1 - t0) * c["rate"]
            N = int(round(n))
            if abs(n - N) > 1e-6 * max(1.0, n) or N < 1:
                raise ModelError(f"controller {c['name']!r}: its rate {c['rate']:g} Hz does not "
                                 f"divide the run from t = {t0:g} s to t = {t1:g} s ({n:.9g} "
                                 f"periods of {c['period']:g} s); choose t_end = t_start + a "
                                 f"whole number of periods")
            s = t0 + np.arange(N) * c["period"]
            inst.append((s, s + c["delay"]))
        times = np.concatenate([np.asarray(tout, float)] + [x for p in inst for x in p])
        order = np.argsort(times, kind="stable")   # the user's times first among equals
        merged, first = [], []
        for i in order:
            if merged and times[i] - merged[-1] <= tol:
                first.append(len(merged) - 1)
            else:
                merged.append(times[i])
                first.append(len(merged) - 1)
        where = np.empty(len(times), dtype=int)
        where[order] = first
        self.tout = np.array(merged)
        nu = len(tout)
        self.tout[where[:nu]] = tout   # a merged instant takes the user's output time
        self.user = np.full(len(merged), -1)
        self.user[where[:nu]] = np.arange(nu)
        off = nu
        self.samples, self.switches, self.breakpoints = [], [], []
        for s, w in inst:
            self.samples.append(where[off:off + len(s)])
            sw = where[off + len(s):off + 2 * len(s)]
            off += 2 * len(s)
            self.switches.append(sw)
            bt = self.tout[sw]
            self.breakpoints.append(tuple(float(b) for b in bt if b > t0 + tol and b < t1 - tol))


def plan(mech, tout: np.ndarray, integrator: str, checkpoint) -> Optional[Plan]:
    """The Plan of a run of ``mech`` at the output times ``tout``, or None without controllers;
    sets each controller's output laws for it (breakpoints at its switch times) and its held
    values to u0. ModelError for what sampled controllers do not run with."""
    ctrls = mech._desc.controllers
    if not ctrls:
        return None
    names = ", ".join(repr(c["name"]) for c in ctrls)
    if integrator != "generalized-alpha":
        why = ("the tree integrator takes no sampled controllers" if integrator == "tree" else
               "IDA restarts at a breakpoint before its output, where the controller would set "
               "its new value")
        raise ModelError(f"controllers {names}: sampled controllers run with "
                         f"integrator='generalized-alpha' ({why})")
    if checkpoint is not None:
        raise ModelError(f"controllers {names}: checkpoint= is not supported with sampled "
                         f"controllers yet")
    p = Plan(ctrls, tout)
    for c, bp in zip(ctrls, p.breakpoints):
        c["hold"].u[:] = c["u0"]
        for j, row in enumerate(c["law_rows"]):
            # every output switches at the same instants: one law carries the breakpoints
            row["law"] = Function(c["hold"].law_fn(j), zero, zero, bp if j == 0 else ())
    mech._desc.changed()   # the laws' columns (python/phmech/_marshal.py) are rebuilt
    return p


def release(mech) -> None:
    """After a run: the controllers' outputs hold u0 again (what the linear and static
    analyses see: the controllers open, their outputs inputs at u0)."""
    for c in mech._desc.controllers:
        c["hold"].u[:] = c["u0"]


def sensor_carriers(mech) -> list:
    """The carriers whose poses and twists the mechanism's sensors read."""
    out = []
    for row in mech._desc.sensors.values():
        out += [c for c in row["carriers"] if c not in out]
    return out


#: the output arrays sensors read (_core.model_simulate's names)
_ARRAYS = ("joints", "joint_rates", "poses", "twists", "pair_wrenches", "components")


def _first_states(mech) -> dict:
    """Component name -> its first column among the components' states."""
    return {n: z for n, (z, _) in state_layout(mech._desc.components).items()}


def _columns(rec, ncar: int) -> dict:
    return {c: c for c in range(ncar)} if rec is None else {c: i for i, c in enumerate(rec)}


class Sampler:
    """The controllers' calls during a run: ``on_output(t, i)`` at each output i of the plan
    (the output arrays ``arrays(d)`` gave); ``error`` the ControllerError that stopped it."""

    def __init__(self, mech, p: Plan, rec):
        self.ctrls = mech._desc.controllers
        self.sensors = mech._desc.sensors
        self.plan = p
        self.col = _columns(rec, len(mech._desc.carriers))
        self.states = _first_states(mech)
        self.error = None
        self.r = None
        self.state = [c["state"] for c in self.ctrls]
        self.pending = [None] * len(self.ctrls)
        # per output index: (controller, sample k) taken there, (controller, k) switching there
        self.at_sample, self.at_switch = {}, {}
        for ic, (s, w) in enumerate(zip(p.samples, p.switches)):
            for k, (i, j) in enumerate(zip(s, w)):
                self.at_sample.setdefault(int(i), []).append((ic, k))
                if self.ctrls[ic]["delay"] > 0:
                    self.at_switch.setdefault(int(j), []).append((ic, k))
        self.log = [dict(t=[], y=[], u=[]) for _ in self.ctrls]
        self.done0 = False   # the samples at t_start were taken (initial_sample)

    def arrays(self, d: dict) -> None:
        """The run's output arrays, before the run (_core.model_simulate(arrays=))."""
        self.r = d

    def _y(self, c: dict, r: dict, i: int) -> np.ndarray:
        sl = slice(i, i + 1)
        ri = {k: r[k][sl] for k in _ARRAYS}
        vals = [sensor_values(self.sensors[s], ri, self.col, self.states)[0].reshape(-1)
                for s in c["inputs"]]
        return np.concatenate(vals) if vals else np.zeros(0)

    def _call(self, ic: int, t: float, y: np.ndarray) -> Optional[np.ndarray]:
        c = self.ctrls[ic]
        what = f"controller {c['name']!r} at t = {t:.9g} s"
        nu = len(c["outputs"])
        try:
            out = c["f"](t, y.copy(), self.state[ic])
        except Exception as e:   # noqa: BLE001 -- the user's function: reported, with the result
            err = ControllerError(f"{what}: its function raised {type(e).__name__}: {e}")
            err.__cause__ = e
            return self._fail(err, c["name"], t)
        if not isinstance(out, tuple) or len(out) != 2:
            return self._fail(ControllerError(
                f"{what}: its function must return (u, state), a pair; it returned "
                f"{type(out).__name__} {out!r:.80}"), c["name"], t)
        try:
            u = np.asarray(out[0], dtype=float).reshape(-1)
        except (TypeError, ValueError):
            u = None
        if u is None or u.size != nu:
            return self._fail(ControllerError(
                f"{what}: its u must be {nu} number{'s' if nu != 1 else ''} (one per output), "
                f"got {out[0]!r:.80}"), c["name"], t)
        if not np.all(np.isfinite(u)):
            return self._fail(ControllerError(f"{what}: its u is not finite: {u.tolist()}"),
                              c["name"], t)
        self.state[ic] = out[1]
        lg = self.log[ic]
        lg["t"].append(t)
        lg["y"].append(y)
        lg["u"].append(u)
        return u

    def _fail(self, err: ControllerError, name: str, t: float) -> None:
        err.component, err.time = name, t
        self.error = err
        return None

    def sample(self, r: dict, i: int, t: float, only_first: bool = False) -> bool:
        """The samples and switches at output i of arrays r; True: stop (an error)."""
        for ic, k in self.at_sample.get(i, ()):
            if only_first and k:
                continue
            if k == 0 and self.done0:
                continue
            c = self.ctrls[ic]
            u = self._call(ic, t, self._y(c, r, i))
            if u is None:
                return True
            if c["delay"] > 0:
                self.pending[ic] = u
            else:
                c["hold"].u[:] = u
        if only_first:
            self.done0 = True
            return False
        for ic, k in self.at_switch.get(i, ()):
            if self.pending[ic] is not None:
                self.ctrls[ic]["hold"].u[:] = self.pending[ic]
        return False

    def on_output(self, t: float, i: int) -> bool:
        """At output i (time t) of the run: the controllers' samples and switches there. True:
        stop the run (a controller failed: ``error``)."""
        return self.sample(self.r, i, t)

    def controllers(self) -> dict:
        """name -> {t (ns,) [s], y (ns, ny), u (ns, nu)}: each controller's samples."""
        out = {}
        for c, lg in zip(self.ctrls, self.log):
            out[c["name"]] = dict(t=np.array(lg["t"]),
                                  y=np.array(lg["y"]).reshape(len(lg["t"]), c["ny"]),
                                  u=np.array(lg["u"]).reshape(len(lg["t"]), len(c["outputs"])))
        return out


def keep(r: dict, idx: np.ndarray, n: int) -> dict:
    """The arrays of ``r`` (a run's, ``n`` outputs) at the outputs ``idx``; the rest as is."""
    return {key: (v[idx] if isinstance(v, np.ndarray) and v.ndim and v.shape[0] == n else v)
            for key, v in r.items()}


def result_sensors(mech, res, rec) -> dict:
    """name -> values (nt, *shape) of every sensor of ``mech`` over the result ``res``."""
    col = _columns(rec, len(mech._desc.carriers))
    states = _first_states(mech)
    zs = np.zeros((len(res.t), sum(c["nstates"] for c in mech._desc.components)))
    for n, z in states.items():
        for j, v in enumerate(res.components.get(n, {}).values()):
            zs[:, z + j] = v
    r = dict(joints=res.joints, joint_rates=res.joint_rates, poses=res.poses, twists=res.twists,
             pair_wrenches=res.pair_wrenches, components=zs)
    out = {}
    for name, row in mech._desc.sensors.items():
        v = sensor_values(row, r, col, states)
        out[name] = v.reshape((len(res.t),) + row["shape"])
    return out

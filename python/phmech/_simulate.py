"""Mechanism.simulate: its options resolved (integrator, tolerances, band, step, linear solver,
planarity, recording), the run in the C core (``_core.model_simulate``) under a RunMonitor
(python/phmech/_run.py), and the SimulationResult assembled and checked (accuracy, plausibility
of the strains). Conventions: SI units, times in s, poses 4x4, twists (omega, v)."""
from __future__ import annotations

import functools
import os
import warnings
from typing import Callable, Optional

import numpy as np

from . import (_core, _marshal, _model, _modes, planar as _planar, postprocess, _run, _sampled,
               se3, topology)
from ._checks import fibre_strain, positive, real, strain_bound
from ._codes import INTEGRATORS
from ._errors import (AccuracyWarning, ModelError, PlausibilityWarning, SolverError,
                      outside_stacklevel)
from .components import state_layout
from .fidelity import modal_validity
from .frames import Body, FlexibleLink, Frame, frame_of
from ._resultfile import HELD_FIELDS
from .results import ENERGY_NAMES, SimulationResult, StaticResult



#: the adaptive generalized-alpha's default local error tolerance and spectral radius at
#: infinity (docs/integrators.md: measured on benchmarks/scenes.py)
DEFAULT_RTOL = 1e-4
#: the rtol below which the default band stops growing (see simulate: the band)
RTOL_BAND_FLOOR = 1e-6
DEFAULT_RHO_INF = 0.9
#: steps an integrator takes at most between two output times (csrc/include/phmech_types.h,
#: phm_sim_options max_steps: its default)
MAX_STEPS = 1_000_000


def simulate(mech, t_end: float, dt_out: float, *, rtol: Optional[float], atol: Optional[float],
             linear_solver: str, initial: Optional[StaticResult], t_start: float,
             callback: Optional[Callable[[float, int], bool]], max_step: float,
             max_order: Optional[int], record, progress: bool, error_test: str, integrator: str,
             step: Optional[float], rho_inf: Optional[float], band: Optional[float], checkpoint,
             checkpoint_every: Optional[float], planar: Optional[bool],
             error_check: Optional[bool] = None) -> SimulationResult:
    """Mechanism.simulate of the builder ``mech``, every option given: their defaults, units and
    meaning are Mechanism.simulate's (python/phmech/mechanism.py), the one place they are set."""
    t0, t1, dt = (real("t_start", t_start), real("t_end", t_end), real("dt_out", dt_out))
    if t1 <= t0:
        raise ModelError(f"t_end must be > t_start (got {t1} <= {t0})")
    if dt <= 0:
        raise ModelError(f"dt_out must be > 0 (got {dt})")
    solvers = {"dense": 0, "klu": 1}
    if isinstance(linear_solver, str) and linear_solver == "auto":
        # the generalized-alpha's KLU matrix drops its exact zeros (dae_jacobian_prune): KLU
        # is then faster than the dense LU from one carrier on (measured 2026-11-27: a
        # pendulum 7.5 against 12.4 ms, the four-bar of benchmarks/scenes.py 51 against 94
        # ms, a 3-carrier modal-link pendulum 0.19 against 0.52 s); IDA keeps its rule, though
        # KLU was faster there too with both on the closed-form Jacobian (a pendulum 1.6
        # against 2.3 ms, five bars 4.8 against 27.7 ms: docs/integrators.md, "IDA's linear
        # solvers: one Jacobian"): a switch moves every small IDA run at the tolerance's level
        linear_solver = "klu" if integrator == "generalized-alpha" or len(mech._car) >= 6 \
            else "dense"
    if not isinstance(linear_solver, str) or linear_solver not in solvers:
        raise ModelError(f"unknown linear_solver {linear_solver!r} (available: 'auto', 'dense', 'klu')")
    #: the core's integrators by their one name (_codes.INTEGRATORS: "ida", "generalized-alpha",
    #: "tree")
    integrators = INTEGRATORS
    if not isinstance(integrator, str) or integrator not in integrators:
        raise ModelError(f"unknown integrator {integrator!r} (available: {', '.join(map(repr, integrators))})")
    adaptive = integrator == "generalized-alpha" and step is None
    rtol = (DEFAULT_RTOL if adaptive else 1e-8) if rtol is None else real("rtol", rtol)
    atol = rtol * 1e-2 if atol is None else real("atol", atol)
    if rtol <= 0 or atol <= 0:
        raise ModelError("rtol and atol must be > 0")
    # the default band: what the outputs can show, but never below BAND_PER_SPAN / span
    # (docs/user_guide.md, "Accuracy contract"): outputs are samples, not steps; and, for the
    # adaptive generalized-alpha on a mechanism with elements, (DEFAULT_RTOL / rtol)^(1/3) times
    # higher below the default rtol: the modes above the band are damped, not resolved, and what
    # that leaves in the resolved motion must shrink with the tolerance too (the README's arm +
    # strip: rtol 1e-4 -> 1e-6 gained 23x on the tip with a 500 Hz band at both, 63x with 2.3 kHz
    # at 1e-6). A rigid mechanism's estimate sees all its motion whatever the band, whose only
    # role there, the twists' absolute tolerance (galpha_scheme.c), it would loosen (the 2 deg
    # pendulum at rtol 1e-6: 1.11 -> 1.48x its tolerance). No higher than rtol 1e-6's 4.6x: a
    # band that takes in a mesh mode whose rates the estimate does not see resolves it badly
    # (tests/test_linearize_outputs.py's arm at rtol 1e-8 against its linear model: 2.4e-5 with
    # bands of 2 and 4.6 kHz, 9.4e-5 at 7 kHz, 2.4e-3 at 10.8 kHz, (1e-4/1e-8)^(1/3) x 500 Hz)
    # band_from: where the band came from, for the message of a run its steps could not finish
    if band is None:
        band = max(0.5 / dt, _run.BAND_PER_SPAN / (t1 - t0))
        band_from = (f"1/(2 dt_out), dt_out = {dt:g} s" if 0.5 / dt >= band else
                     f"{_run.BAND_PER_SPAN:g} / span, the default's floor")
        if adaptive and rtol < DEFAULT_RTOL and mech._desc.elements:
            band *= (DEFAULT_RTOL / max(rtol, RTOL_BAND_FLOOR)) ** (1.0 / 3.0)
            band_from = f"the default's, raised for rtol {rtol:g}"
    else:
        band = positive("band", band)
        band_from = "band="
    if adaptive and (initial is None or isinstance(initial, StaticResult)):
        # the modes a start away from equilibrium (a release, a start at rest) and the loads'
        # steps ring in
        raised = _modes.ringing_band(mech, initial, t0, t1, band, rtol, atol, band_from == "band=")
        if raised is not None:
            band, band_from = raised
    if integrator == "generalized-alpha":
        if step is not None:
            step = positive("step", step)
        rho_inf = DEFAULT_RHO_INF if rho_inf is None else real("rho_inf", rho_inf)
        if not 0.0 <= rho_inf <= 1.0:
            raise ModelError(f"rho_inf must be in [0, 1] (got {rho_inf})")
        if not (isinstance(error_test, str) and error_test == "all") or max_order is not None:
            raise ModelError("error_test and max_order apply to integrator='ida' only")
        if max_step is not None and not (isinstance(max_step, (int, float)) and max_step == 0) \
                and not adaptive:
            raise ModelError("max_step applies to integrator='ida' and to the adaptive "
                             "generalized-alpha (without step=)")
    elif step is not None:
        raise ModelError("step= applies to integrator='generalized-alpha' (IDA and tree choose "
                         "their own steps; use max_step to bound them)")
    if error_check not in (None, True, False):
        raise ModelError(f"error_check must be None, True or False (got {error_check!r})")
    if error_check is not None and integrator not in ("tree", "ida"):
        raise ModelError("error_check applies to integrator='tree' and 'ida' (the default "
                         "integrator estimates its global error as it runs: "
                         "stats['global_error_estimate'])")
    if error_check and integrator == "ida" and mech._desc.elements:
        raise ModelError("error_check with integrator='ida' compares joint coordinates and "
                         "rates: rigid mechanisms only (a flexible link's nodes have none)")
    # on by default for the tree integrator, asked for IDA
    error_check = (error_check is not False) if integrator == "tree" else bool(error_check)
    if integrator == "tree":
        # a tree of rigid bodies in joint coordinates (csrc/integrate/tree.c): explicit
        # Dormand-Prince 5(4) on rtol, atol; the core refuses the models it does not take
        if not (isinstance(error_test, str) and error_test == "all") or max_order is not None:
            raise ModelError("error_test and max_order apply to integrator='ida' only")
        if planar is True:
            raise ModelError("planar=True does not apply to integrator='tree' (it integrates "
                             "the joint coordinates of the 3-D model)")
    tests = {"all": 0, "configuration": 1}
    if not isinstance(error_test, str) or error_test not in tests:
        raise ModelError(f"unknown error_test {error_test!r} (available: 'all', 'configuration')")
    if max_order is None:
        max_order = 2 if error_test == "configuration" else 5
    if isinstance(max_order, (bool, np.bool_)) or not isinstance(max_order, (int, np.integer)) or not 1 <= max_order <= 5:
        raise ModelError(f"max_order must be an integer 1..5 (got {max_order!r})")
    if error_test == "configuration" and max_order > 2:
        raise ModelError(f"error_test='configuration' needs max_order 1 or 2 (got {max_order}): "
                         "without the twists in the error test, BDF orders 3-5 let unresolved "
                         "vibrations grow")
    max_step = 0.0 if max_step is None or (isinstance(max_step, (int, float)) and max_step == 0) \
        else positive("max_step", max_step)
    # the integrators stop after MAX_STEPS steps between two outputs: fail now, not then
    h = min([x for x in (max_step, step, 1.0 / (_run.BAND_MAX_STEPS * band) if adaptive else 0.0)
             if x and x > 0] or [np.inf])
    if dt / h > MAX_STEPS:
        raise ModelError(f"simulate: steps of at most {h:.3g} s (" +
                         ("max_step" if h == max_step else "step" if h == step else
                          f"the {band:.4g} Hz band") +
                         f") would take {dt / h:.3g} steps per output interval dt_out = {dt:g} s; "
                         f"the integrators stop at {MAX_STEPS:.0e} steps between two outputs: "
                         f"use a smaller dt_out, or longer steps")
    if callback is not None and not callable(callback):
        raise ModelError(f"callback must be a function callback(t, i) or None (got {callback!r})")
    if initial is not None and not isinstance(initial, StaticResult):
        raise ModelError(f"initial must be a StaticResult (Mechanism.static) or None (got "
                         f"{type(initial).__name__})")
    with np.errstate(over="ignore"):
        span = (t1 - t0) / dt
    _check_outputs(mech, span, record)
    n = int(np.floor(span + 1e-9))
    tout = t0 + dt * np.arange(n + 1)
    if tout[-1] < t1 - 1e-12 * max(1.0, abs(t1)):
        tout = np.append(tout, t1)
    rec = None if record is None else _record_carriers(mech, record)
    if rec is not None:   # the sensors read their carriers' poses and twists
        rec += [c for c in _sampled.sensor_carriers(mech) if c not in rec]
    # sampled controllers: their instants are outputs too (python/phmech/_sampled.py)
    ctl = _sampled.plan(mech, tout, integrator, checkpoint)
    run_tout = tout if ctl is None else ctl.tout
    if ctl is not None:
        _check_outputs(mech, len(run_tout) - 1.0, record)
    model = _model.build(mech)   # finds the redundant constraints
    drop_masks = mech._state.drop_masks
    if rec is not None and mech.redundant_constraints:
        raise ModelError("record= cannot be combined with redundant constraints yet: the "
                         "minimum-norm multipliers need every carrier's pose")
    poses = None if initial is None else _model.start_poses(mech, initial, "initial")
    twists = None if initial is None else np.zeros((len(mech._car), 6))
    if planar not in (None, True, False):
        raise ModelError(f"planar must be None, True or False (got {planar!r})")
    # planar=None leaves IDA in 3-D: with the planar DAE and KLU's pivoting for 3-D it failed
    # the flexible slider-crank of tests/test_flexible_loop.py at rtol 1e-8 (IDA_CONV_FAIL;
    # csrc/integrate/ida.c: it runs with AMD and full pivoting, a remedy measured on that one
    # scene), and with the dense LU the spline-driven revolute of
    # tests/test_driven_pairs.py ended its spin-up 1.6e-4 N m off in its torque (3-D 6.7e-5,
    # the test's bound 1.3e-4: where IDA's steps land near the breakpoint)
    auto_ok = integrator == "generalized-alpha"
    plane = None if planar is False or (planar is None and not auto_ok) else \
        _plane(mech, model, poses, twists, planar is True)
    if plane is not None:   # the run and its result read the planar model
        model = plane[2]
    run = dict(linear_solver=None if integrator == "tree" else linear_solver,
               integrator=integrator, adaptive=adaptive,
               rtol=rtol, atol=atol, planar=None if plane is None else _planar.AXES[plane[0]])
    sim_model = model if plane is None else plane[2]

    def assemble(r, k, stats, interrupted, times=tout) -> SimulationResult:
        return _simulation_result(mech, r, k, times, model, drop_masks, rec, band,
                                       {**stats, **run}, interrupted, plane)

    def simulate_core(times, per_output, monitor, arrays, tighter=1.0, tree=False):
        # tighter: rtol and atol times this (the error check of the tree integrator and IDA);
        # tree: the tree integrator on the 3-D model instead (whether it takes the mechanism)
        return _core.model_simulate(_model.build(mech) if tree else sim_model, times,
                                    rtol * tighter, atol * tighter, solvers[linear_solver], poses,
                                    twists, per_output, float(max_step), int(max_order), rec,
                                    tests[error_test], integrators["tree" if tree else integrator],
                                    float(step or 0.0), float(1.0 if rho_inf is None else rho_inf),
                                    adaptive=int(adaptive and not tree),
                                    band=float(band if adaptive and not tree else 0.0),
                                    monitor=monitor, arrays=arrays,
                                    planar=0 if plane is None or tree else plane[0] + 1)

    sampler = None
    if ctl is not None:
        # the first samples, at t_start, from a one-output run: the run's consistent initial
        # values then hold their u
        sampler = _sampled.Sampler(mech, ctl, rec)
        r0 = simulate_core(run_tout[:1], None, None, None)
        if not r0["error"] and sampler.sample(r0, 0, float(run_tout[0]), only_first=True):
            _sampled.release(mech)
            err = sampler.error
            err.result = _with_samples(mech, assemble(r0, 1, r0["stats"], True), sampler, rec)
            raise err
        user_callback = callback

        def callback(t: float, i: int) -> bool:   # the samples, then the user's outputs
            if sampler.on_output(t, i):
                return True
            u = int(ctl.user[i])
            return bool(user_callback(t, u)) if user_callback is not None and u >= 0 else False

    saver = None
    if checkpoint is not None:
        saver = _run.Checkpoint(checkpoint, checkpoint_every,
                                lambda arrays, k, stats: assemble(arrays, k, stats, False))
    elif checkpoint_every is not None:
        raise ModelError("checkpoint_every applies with checkpoint=path only")
    monitor = _run.RunMonitor(t0, t1, band, integrator, progress, callback, checkpoint=saver)
    calls = [c["call"] for c in mech._desc.components if c["kind"] == "callback"]
    for call in calls:   # python/phmech/components.py, CallbackController
        call.failure = None
    try:
        with _run.sigterm_as_interrupt(monitor):
            r = simulate_core(run_tout, monitor.per_output, monitor,
                              sampler.arrays if sampler is not None else
                              None if saver is None else saver.arrays_ready)
    finally:   # the other analyses see the controllers' outputs at u0
        _sampled.release(mech)
    monitor.finish(r["stats"]["steps"])
    if sampler is None:
        result = assemble(r, r["nout"], r["stats"],
                          bool(r["interrupted"]) or monitor.stopped or monitor.terminated)
    elif sampler.error is not None:   # the outputs up to the failed sample, all of them
        result = _with_samples(mech, assemble(r, r["nout"], r["stats"], True, run_tout),
                               sampler, rec)
        sampler.error.result = result
        raise sampler.error
    else:   # the outputs asked for
        idx = np.flatnonzero(ctl.user[:r["nout"]] >= 0)
        result = _with_samples(mech, assemble(_sampled.keep(r, idx, len(run_tout)), len(idx),
                                              r["stats"], bool(r["interrupted"]) or
                                              monitor.stopped or monitor.terminated), sampler, rec)
    if sampler is None and mech._desc.sensors:
        result.sensors = _sampled.result_sensors(mech, result, rec)
    if error_check or integrator == "tree":
        if error_check and not r["error"] and not result.interrupted:
            checked, figures = _error_check(mech, model, simulate_core, run_tout, r, rtol, atol,
                                            integrator)
            if checked is not r:   # a tighter run: the result is its own
                result = assemble(checked, checked["nout"], checked["stats"], False)
                if mech._desc.sensors:
                    result.sensors = _sampled.result_sensors(mech, result, rec)
            result.stats.update(figures)
        else:
            result.stats.update(global_error_estimate=None, global_error_time=None,
                                global_error_state=None)
    if sampler is not None and result.stats.get("global_error_estimate") is not None:
        # the linearized steps hold the sampled inputs: they miss the loop's feedback, which
        # acts at the samples (measured: a sampled PD loop of tests/test_controllers.py read 20
        # tolerances with its local estimates summed to 0.002)
        result.stats.update(dict.fromkeys(GLOBAL_ERROR_KEYS))
    unsaved = ""
    if saver is not None:   # the file ends as the run did (a failed run: its partial result)
        try:
            saver.write(result)
        except Exception as e:   # not to hide the solver's error and its partial result
            if not r["error"]:
                raise
            unsaved = f"; the checkpoint could not be written: {e}"
    failed = [call.failure for call in calls if call.failure is not None]
    if failed:   # a callback controller's function failed: its error, with the trajectory
        failed[0].result = result
        raise failed[0]
    law_error = r.get("law_error")
    if law_error is not None:   # a Function law raised: its error, with the trajectory up to it
        raise _with_partial(law_error, result, unsaved)
    if not r["error"]:
        _run.warn_if_inaccurate(result.stats)
        warn_implausible_strain(mech, result, model)
        _run.warn_if_above_tolerance(result.stats)
        _run.warn_if_global_error(result.stats, tree=_tree_applies(
            result.stats, lambda: simulate_core(np.array([t0, t0 + 1e-6 * (t1 - t0)]), None,
                                                None, None, tree=True)))
        for lk in mech._links.values():
            if lk.fidelity == "modal":
                T0 = se3.exp(lk.length * mech._desc.link_unstressed_strain(lk))
                for msg in modal_validity(result, lk, T0, mech.frequency_tolerance):
                    warnings.warn(msg, AccuracyWarning, stacklevel=outside_stacklevel())
    if r["error"]:
        why = ""   # the output interval bounds the steps: say so
        if integrator == "ida":
            why = (f"; IDA takes at most {MAX_STEPS:.0e} steps between two outputs (dt_out = "
                   f"{dt:g} s): a smaller dt_out, or a looser rtol" +
                   (", or error_test='configuration' for flexible links"
                    if error_test == "all" else "")) if "TOO_MUCH_WORK" in r["error"] else ""
        elif adaptive:
            why = (f"; the steps were at most {1.0 / (_run.BAND_MAX_STEPS * band):.3g} s, from "
                   f"the {band:.4g} Hz band ({band_from}): a higher band= shortens them")
        err = topology.constraint_error(mech._desc, r["error"]) or SolverError(r["error"])
        raise _with_partial(err, result, unsaved + why)
    return result

def _error_check(mech, model, simulate_core, times, r: dict, rtol: float, atol: float,
                 integrator: str) -> tuple:
    """(run, stats) of the error check (Mechanism.simulate's error_check: the tree integrator,
    IDA on a rigid mechanism) of the run ``r`` at ``rtol``, ``atol``: a run at
    _run.ERROR_CHECK_TIGHTER its tolerances estimates ``r``'s error by their difference
    (_joint_difference, against rtol and atol as asked); within them, ``r`` is returned, else
    the check run is checked in turn, up to _run.ERROR_CHECK_RUNS runs, and the
    first within them is returned (at the limit the last, most accurate, run, its estimate
    that of the run before it: larger than its own). stats: ``global_error_estimate``,
    ``global_error_time``, ``global_error_state`` (None when a check run stopped),
    ``integration_rtol`` (the returned run's rtol) and ``error_check_rtol`` (its check's);
    an AccuracyWarning when a check run stops (the result is then unchecked)."""
    run, factor, out = r, 1.0, {}
    tighter = _run.ERROR_CHECK_TIGHTER
    for _ in range(_run.ERROR_CHECK_RUNS):
        c = simulate_core(times, None, None, None, tighter=factor * tighter)
        if c["error"] or int(c["nout"]) < len(times):
            warnings.warn(f"simulate: the error check of integrator={integrator!r} could not "
                          f"run: its run at rtol {rtol * factor * tighter:.3g} stopped "
                          f"({c['error'] or 'early'}), so the result (at rtol "
                          f"{rtol * factor:.3g}) is unchecked",
                          AccuracyWarning, stacklevel=outside_stacklevel())
            return run, dict(global_error_estimate=None, global_error_time=None,
                             global_error_state=None, integration_rtol=rtol * factor,
                             error_check_rtol=rtol * factor * tighter)
        out = dict(_joint_difference(mech, model, times, run, c, rtol, atol),
                   integration_rtol=rtol * factor, error_check_rtol=rtol * factor * tighter)
        if out["global_error_estimate"] <= _run.GLOBAL_ERROR_WARN:
            return run, out
        run, factor = c, factor * tighter
    out["integration_rtol"] = rtol * factor
    return run, out

def _tree_applies(stats: dict, probe: Callable[[], dict]) -> bool:
    """Whether the tree integrator takes the mechanism: ``probe()`` runs it on the 3-D model
    over the first 1e-6 of the span (its refusals are ModelErrors: csrc/integrate/tree_aba.c).
    Asked only of a default run whose global error estimate warns, for the warning's remedy."""
    g = stats.get("global_error_estimate")
    if not (_run.default_integrator(stats) and g is not None and g > _run.GLOBAL_ERROR_WARN):
        return False
    try:
        return not probe()["error"]
    except (ModelError, SolverError):
        return False

def _joint_difference(mech, model, times, a: dict, b: dict, rtol: float, atol: float) -> dict:
    """The largest difference of two runs' joint coordinates and rates, each over rtol times
    its largest magnitude in ``b`` plus atol, as stats' ``global_error_estimate``, with its
    time [s] and ``global_error_state``."""
    worst, when, name = 0.0, None, None
    for key, what in (("joints", "joint coordinate"), ("joint_rates", "joint rate")):
        x, y = a[key][:len(times)], b[key][:len(times)]
        if not x.size:
            continue
        ratio = np.abs(x - y) / (rtol * np.abs(y).max(axis=0) + atol)
        k = np.unravel_index(int(np.argmax(ratio)), ratio.shape)
        if ratio[k] > worst:
            worst, when, name = float(ratio[k]), float(times[k[0]]), (what, int(k[1]))
    state = None
    if name is not None:
        state = _joint_name(zip((p["name"] for p in mech._pairs), _core.model_sizes(model)[4]),
                            name[1], name[0])
    return dict(global_error_estimate=worst, global_error_time=when, global_error_state=state)

def _with_partial(err: Exception, result: SimulationResult, more: str = "") -> Exception:
    """``err`` carrying the trajectory computed before it (``err.result``), its message saying
    so (``more``: what follows, e.g. the remedy)."""
    t_last = f"{result.t[-1]:.6g} s" if len(result.t) else "the start"
    err.args = (f"{err.args[0]} (the trajectory up to {t_last} is in this error's 'result' "
                f"attribute{more})",) + tuple(err.args[1:])
    err.result = result
    return err

def _with_samples(mech, result: SimulationResult, sampler, rec) -> SimulationResult:
    """``result`` with its sensors' values and the controllers' samples."""
    result.sensors = _sampled.result_sensors(mech, result, rec)
    result.controllers = sampler.controllers()
    return result

def _plane(mech, model, poses, twists, require: bool):
    """(axis, drop masks, core model) of the planar DAE when the scene is planar at its
    start (``model``: the mechanism's 3-D model, only read; ``poses``, ``twists``: the
    run's, None for the initial configuration's), else
    None, or with ``require`` ModelError naming the first check that fails per axis. The
    masks drop the out-of-plane constraint rows and the in-plane rows redundant among the
    in-plane ones. From the initial configuration the answer is kept (_model.built) until the
    mechanism changes, from given poses and twists the last answer with them, and the planar
    model of each set of masks."""
    keep = _model.built(mech)
    start = poses is None and twists is None
    if start and "plane" in keep and (keep["plane"] is not None or not require):
        return keep["plane"]
    # from given poses and twists (a StaticResult's): the last answer, kept with them (a sweep
    # of runs from one static state asks again with the same ones)
    given = None if start else tuple(None if x is None else np.asarray(x, dtype=float).tobytes()
                                     for x in (poses, twists))
    last = keep.get("plane_given")
    if given is not None and last is not None and last[0] == given and \
            (last[1] is not None or not require):
        return last[1]
    plane = _find_plane(mech, model, poses, twists, require)
    if plane is not None:
        k, masks = plane
        models = keep.setdefault("planar_models", {})
        if tuple(masks) not in models:
            models[tuple(masks)] = _planar_model(mech, masks, keep, model)
        plane = (k, masks, models[tuple(masks)])
    if start:
        keep["plane"] = plane
    else:
        keep["plane_given"] = (given, plane)
    return plane

def _planar_model(mech, masks, keep: dict, model):
    """A core model of the mechanism at its initial configuration with the drop masks
    ``masks``: ``model``, the 3-D one kept in ``keep`` (_model.built), is taken out of it and
    moved to those masks (the next analysis that needs the 3-D model builds it again), or a
    new one when it is not kept there."""
    state = mech._state
    if keep.get("model") is model:
        del keep["model"]
    else:
        model = _marshal.core_model(mech._desc, state.poses, state.twists, state.x0,
                                    state.drop_masks, state.frames_a)
    return _marshal.with_initial(model, mech._desc, state.poses, state.poses, state.twists,
                                 state.x0, masks)

def _find_plane(mech, model, poses, twists, require: bool):
    """(axis, drop masks) of _plane, or None."""
    state = mech._state
    H = state.poses if poses is None else np.asarray(poses, dtype=float)
    T = state.twists if twists is None else np.asarray(twists, dtype=float)
    # the checks and the out-of-plane rows (csrc/model/planarity.c, phmech.planar)
    k, masks, why = _core.model_planar(model, H, T, [p["name"] for p in mech._desc.pairs])
    if k is None:
        if require:
            raise ModelError("planar=True: the scene is not planar (" + "; ".join(
                f"about {_planar.AXES[k]}: {why[k]}" for k in (2, 1, 0)) + ")")
        return None
    # the in-plane rows redundant among the in-plane ones: only loop-closing pairs' rows can
    # be (topology.redundant_rows: a tree's rows are independent)
    if any(ip not in state.tree for ip in range(len(masks))):
        layout = postprocess.full_layout(mech._desc)
        _, G, _ = _core.model_constraints_full(model, H, None, 0.0)
        keep = np.zeros(G.shape[0], dtype=bool)
        keep[postprocess.kept_rows(layout, masks)] = True
        red, _ = topology.redundant_rows(mech._desc, G * keep[:, None], state.tree)
        masks = [a | b for a, b in zip(masks, red)]
    return k, masks

def _simulation_result(mech, r: dict, k: int, tout, model, drop_masks, rec, band: float,
                       stats: dict, interrupted: bool, plane=None) -> SimulationResult:
    """The SimulationResult of the first ``k`` outputs in the arrays ``r`` of
    ``_core.model_simulate`` (the whole run, or a checkpoint's part of it while it runs),
    ``stats`` the core's statistics and the run's options."""
    # one copy, each energy a row of it
    energy = dict(zip(ENERGY_NAMES, r["energy"][:k].T.copy()))
    ports = {nm: r["port_energy"][:k, i].copy() for i, nm in enumerate(mech._desc.port_names())}
    layout = _core.model_sizes(model)[4]
    lam, pw = r["constraint_wrenches"][:k], r["pair_wrenches"][:k]
    if plane is not None and mech.redundant_constraints and k > 0:
        lam, pw, layout = postprocess.min_norm_multipliers(
            mech._desc, plane[2], plane[1], r["poses"][:k], r["joints"][:k], lam, tout[:k])
    elif plane is not None:   # the 3-D layout has every row: the dropped ones carry 0
        layout, keep = _planar_rows(mech, plane[1])
        full = np.zeros((lam.shape[0], layout[-1][0] + layout[-1][1] if layout else 0))
        full[:, keep] = lam
        lam = full
    elif mech.redundant_constraints and k > 0:
        lam, pw, layout = postprocess.min_norm_multipliers(
            mech._desc, model, drop_masks, r["poses"][:k], r["joints"][:k], lam, tout[:k])
    pairs = {p["name"]: dict(index=i, layout=layout[i], units=p["pair"]._type.units)
             for i, p in enumerate(mech._pairs)}
    stats = {**stats, **_run.quality(energy, band)}
    # Newton iterations (linear solves) per step, the issue-12 measure (docs/integrators.md,
    # "Newton iterations"); rejected step attempts count in the iterations, not the steps.
    # Not in a checkpoint's mid-run stats, which hold no counters
    if "nonlinear_iters" in stats:
        stats["newton_iters_per_step"] = stats["nonlinear_iters"] / max(1, stats["steps"])
    if not stats["adaptive"]:
        # no band applies: IDA, the tree integrator and the fixed step choose their steps
        # otherwise (it read the unused default, 50 Hz at dt_out 0.01)
        stats["band"] = None
        for key in ("error_estimate", "error_sum", "error_sum_max", "floor_steps", "error_ratio",
                    "error_ratio_time", "noise_steps", "min_step", "newton_rtol",
                    *GLOBAL_ERROR_KEYS):
            stats.pop(key, None)
    elif stats.get("global_error_estimate", 0.0) < 0:   # flexible links: not estimated
        stats.update(dict.fromkeys(GLOBAL_ERROR_KEYS))
    elif "global_error_state" in stats:
        stats["global_error_state"] = _state_name(mech, int(stats["global_error_state"]),
                                                  None if plane is None else plane[0], pairs)
        g = stats["global_error_estimate"]   # the state's error over its tolerance
        stats["global_error_tolerance"] = stats["global_error_absolute"] / g if g > 0 else None
    return SimulationResult(t=tout[:k], constraint_wrenches=lam, energy=energy, stats=stats,
                            interrupted=interrupted, _links=dict(mech._links),
                            port_energy=ports, pair_wrenches=pw, _pairs=pairs,
                            **{f.name: r[f.name][:k] for f in HELD_FIELDS},
                            redundant_constraints=list(mech.redundant_constraints),
                            carriers=None if rec is None else np.array(rec),
                            **dict(zip(("_inertia", "_mass", "_com"),
                                       mech._desc.carrier_arrays())),
                            _bodies=dict(mech._bodies),
                            components=_component_states(mech, r["components"][:k]),
                            **mech._desc.mass_couplings())


def _planar_rows(mech, masks) -> tuple:
    """(postprocess.full_layout, the rows postprocess.kept_rows keeps under the drop ``masks``)
    of the mechanism, kept per set of masks (_model.built) until it changes."""
    kept = _model.built(mech).setdefault("planar_rows", {})
    key = tuple(masks)
    if key not in kept:
        layout = postprocess.full_layout(mech._desc)
        kept[key] = (layout, postprocess.kept_rows(layout, masks))
    return kept[key]

def _strain_rows(mech) -> list:
    """(link, its first element, section stiffness K, strain bound, the bound's reason, the
    strain energy an element needs to reach it: 0 when K is not diagonal) of each nonlinear
    flexible link, for warn_implausible_strain; made once per initial configuration and kept
    (_model.built)."""
    keep = _model.built(mech)
    rows = keep.get("strain_rows")
    if rows is None:
        rows = []
        for lk in mech._links.values():
            if lk.fidelity != "nonlinear":
                continue
            first = mech._desc.first_element[lk.name]
            el = mech._el[first]
            K = el["K"]
            bound, why = strain_bound(K, el["Ms"])
            diagonal = not np.any(K - np.diag(np.diagonal(K)))
            rows.append((lk, first, K, bound, why,
                         K[3, 3] * el["h"] * bound ** 2 / 14 if diagonal else 0.0))
        keep["strain_rows"] = rows
    return rows

#: the default integrator's global error estimate in stats (csrc/integrate/galpha_global.c):
#: the largest over the run in tolerances, when, in which state, that state's estimated error,
#: its tolerance (the error over the estimate) and its largest |value| so far (its units), and
#: the blocks propagated as stiff
GLOBAL_ERROR_KEYS = ("global_error_estimate", "global_error_time", "global_error_state",
                     "global_error_absolute", "global_error_tolerance", "global_error_scale",
                     "global_error_stiff_blocks")


def _state_name(mech, i: int, plane_axis: Optional[int], pairs: dict) -> str:
    """What state ``i`` of the core's DAE is (csrc/dae/dae.h: per carrier its quaternion,
    position and twist, then the joint coordinates, then the components' states), in words; a
    twist's component named (its angular rate about, or velocity along, one of the carrier's
    axes). ``plane_axis``: the planar DAE's normal (0, 1, 2; its twist is the in-plane components
    of phmech.planar.inplane, as csrc/dae/planar.c keeps them), None for the 3-D DAE."""
    planar = plane_axis is not None
    ns, parts = (7, ((0, 2, "orientation"), (2, 4, "position"), (4, 7, "twist"))) if planar else \
        (13, ((0, 4, "orientation"), (4, 7, "position"), (7, 13, "twist")))
    nc = len(mech._car)
    if i < nc * ns:
        c, k = divmod(i, ns)
        names = {b.carrier: f"body {nm!r}" for nm, b in mech._bodies.items()}
        for nm, lk in mech._links.items():
            names.update({cc: f"link {nm!r} node {j}" for j, cc in enumerate(lk.carriers)})
        a, _, what = next(p for p in parts if p[0] <= k < p[1])
        out = f"the {what} of {names.get(c, f'carrier {c}')}"
        if what == "twist":   # component j of the body twist (omega, v)
            j = k - a
            if planar:
                j = int(_planar.inplane(plane_axis)[j])
            out += (f" (its angular rate about its {'xyz'[j]} axis)" if j < 3 else
                    f" (its velocity along its {'xyz'[j - 3]} axis)")
        return out
    return _joint_name(((nm, p["layout"]) for nm, p in pairs.items()), i - nc * ns,
                       "joint coordinate") or "an internal state of a component"

def _joint_name(layouts, j: int, what: str) -> Optional[str]:
    """``what`` (e.g. "joint coordinate") of column ``j`` of the joint arrays in words, e.g.
    "joint coordinate 0 of pair 'hinge'", from the pairs' (name, core layout row: its joint
    columns at [2:4], start and count); None past the pairs' columns."""
    for nm, row in layouts:
        jj, kk = row[2:4]
        if jj <= j < jj + kk:
            return f"{what} {j - jj} of pair {nm!r}"
    return None


def _component_states(mech, zs: np.ndarray) -> dict:
    """name -> {state name: its values over the outputs} of every component with internal
    states (python/phmech/components.py), from the core's state array ``zs`` (nout, nz)."""
    rows = mech._desc.components
    if not any(r["nstates"] for r in rows):
        return {}
    lay = state_layout(rows)
    return {r["name"]: {sn: zs[:, lay[r["name"]][0] + j].copy()
                        for j, sn in enumerate(r["states"])}
            for r in rows if r["nstates"]}

def _check_outputs(mech, span: float, record) -> None:
    """ModelError when (t_end - t_start) / dt_out output times would take more than half the
    machine's memory (an accidental t_end / dt_out of 1e10 would otherwise allocate 75 GB,
    or fail inside NumPy)."""
    nc = len(mech._car)
    # per output: pose and twist of each recorded carrier; per pair at most 6 multipliers, 6
    # pair wrench entries, 6 joint coordinates, rates and efforts; 7 energies; the ports; t
    per = 8 * (22 * nc + 30 * len(mech._pairs) + 7 + len(mech._acts) + len(mech._loads)
               + len(mech._springs) + 1)
    if record is not None:
        per = max(8 * 30, per - 8 * 22 * (nc - 1))   # at least one carrier recorded
    limit = _output_memory_limit()
    if not (span * per <= limit):
        raise ModelError(f"simulate: (t_end - t_start) / dt_out = {span:.3g} output times would "
                         f"take about {span * per / 1e9:.3g} GB, more than half this machine's "
                         f"memory ({2 * limit / 1e9:.3g} GB); use a larger dt_out, a shorter run "
                         f"or record= fewer carriers")


@functools.lru_cache(maxsize=None)
def _output_memory_limit() -> float:
    """Half the machine's physical memory [bytes] (8e9 where it cannot be read), asked once."""
    try:
        return 0.5 * os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (AttributeError, ValueError, OSError):
        return 8e9


def _record_carriers(mech, record) -> list:
    """Carrier indices for simulate(record=...): bodies, links, frames or their names."""
    if isinstance(record, (str, FlexibleLink, Body, Frame)):
        items = [record]
    elif isinstance(record, (list, tuple)):
        items = list(record)
    else:
        raise ModelError(f"record: expected a body, link, frame, a name, or a list of them "
                         f"(got {type(record).__name__})")
    out = []
    for x in items:
        if isinstance(x, str) and x in mech._links:
            x = mech._links[x]
        if isinstance(x, FlexibleLink):
            if mech._links.get(x.name) != x:
                raise ModelError(f"record: link {x.name!r} is not a link of this mechanism")
            out += [c for c in x.carriers if c not in out]   # a modal link's sliders too
            continue
        c = frame_of(x, mech._desc, "record").carrier
        if c < 0:
            raise ModelError("record: the ground has no recorded pose")
        if c not in out:
            out.append(c)
    if not out:
        raise ModelError("record: nothing to record")
    return out

def warn_implausible_strain(mech, result: SimulationResult, model) -> None:
    """PlausibilityWarning, once per run, when a nonlinear flexible link's largest fibre
    strain over the run (phmech._checks.fibre_strain of its stress resultants) exceeds its
    bound (phmech._checks.strain_bound: 1 % for a metal-like speed of sound, 10 % below),
    naming the link, the strain, where and when. The resultants are read only at the outputs
    where some element stores the strain energy its bound needs (one core call per 256 such
    outputs, every link at once; most runs: none). Runs with ``record=`` (not every carrier
    stored) are not checked."""
    if result.carriers is not None or not len(result.t):
        return
    rows = _strain_rows(mech)
    if not rows:
        return
    # an element of length h whose fibre strain is e stores at least EA h e^2 / 14 (the
    # least of (EA e_a^2 + EI_y k_y^2 + EI_z k_z^2) h / 2 with e_a + c_z k_y + c_y k_z = e,
    # c = sqrt(3 EI/EA), for a diagonal section stiffness): at an output where no element of
    # a link stores that much (result.strain_energy, each element's), none of them reached
    # its bound, and its stress resultants are not needed there
    energy = result.strain_energy
    hot = np.zeros(len(result.t), dtype=bool)
    for lk, first, K, bound, why, need in rows:
        if energy is None or need <= 0.0:
            hot[:] = True
        else:
            hot |= np.max(energy[:, first:first + lk.elements], axis=1) >= need
    outputs = np.flatnonzero(hot)
    if not len(outputs):
        return
    worst = (0.0, None, 0, 0, 0.0)   # strain / bound, row, output, element, strain
    for k0 in range(0, len(outputs), 256):
        at = outputs[k0:k0 + 256]
        S = _core.model_stress_resultants(model, result.poses[at], result.twists[at])
        for row in rows:
            lk, first, K, bound = row[:4]
            eps = fibre_strain(S[:, first:first + lk.elements], K)
            i = int(np.argmax(eps))
            if eps.flat[i] / bound > worst[0]:
                worst = (float(eps.flat[i]) / bound, row, int(at[i // lk.elements]),
                         i % lk.elements, float(eps.flat[i]))
    ratio, row, it, el, strain = worst
    if ratio > 1.0:
        lk, _, _, bound, why, _ = row
        warnings.warn(f"simulate: link {lk.name!r} strains {100 * strain:.3g} % at its "
                      f"fibres (element {el}, t = {result.t[it]:.4g} s; axial plus bending, "
                      f"extreme fibre at sqrt(3 EI/EA)), above {100 * bound:g} %: {why}. "
                      f"Check the units of its properties (E in Pa, sections in m) and the "
                      f"loads, and whether the part would yield or break",
                      PlausibilityWarning, stacklevel=outside_stacklevel())

"""Watching a running simulation: the progress bar (tqdm), the cost warning, SIGTERM, and the quality
figures a result reports about itself (docs/integrators.md explains the default integrator)."""
from __future__ import annotations

import contextlib
import os
import signal
import sys
import threading
import time
import warnings
from typing import Callable, Optional

import numpy as np

from ._checks import real
from ._errors import AccuracyWarning, CostWarning, ModelError, outside_stacklevel

#: steps per period of the band's highest frequency at the adaptive integrator's smallest and
#: largest step (csrc/include/phmech_types.h, PHM_BAND_STEPS and PHM_BAND_MAX_STEPS)
BAND_STEPS = 20
BAND_MAX_STEPS = 12
#: how far below the band's floor a step above the tolerance is refined (PHM_REFINE_MAX)
REFINE_MAX = 1000.0
#: the default band is at least this many hertz per second of run: 1/(2 dt_out) alone let a
#: long dt_out set the accuracy (a pendulum run over 1 s with dt_out = 2 s, band 0.25 Hz)
BAND_PER_SPAN = 50.0


#: ledger residual / energy_scale (``quality``: the largest of the kinetic energy, the change of
#: kinetic plus elastic energy, the work supplied and dissipated) above which a run warns
#: (AccuracyWarning).
#: Measured with the defaults (docs/user_guide.md, "Energy ledger"): the scenes of
#: benchmarks/scenes.py stay at or below 1.65e-4 (the manipulator; the others below 5e-6;
#: 6.3e-4 before issue 27's fixes of the default integrator; measured 2026-12-07); the
#: steel strip swinging at dt_out = 0.05 s (tests/hard, finding 5 of docs/validation.md) reaches
#: 3.2e-2 with 186 times its stretch, a pendulum at a fixed 0.05 s step with rho_inf 0 loses
#: 1.9e-2 of its energy (tests/accuracy/test_ledger.py). The issue-27 four-bar (0.14 J lost, 10 J
#: supplied, a former scale of 40.7 J: at most 30.7 J of kinetic energy) reads at least 4.6e-3
LEDGER_WARN = 4e-3

#: With the adaptive default integrator the energy the integrator removed or added by the end of
#: the run (``numerical_dissipation_relative``, the final ledger residual over the energy scale)
#: is also held to the run's own tolerance: above LEDGER_RTOL_WARN rtol a run warns. A motion
#: within rtol changes the energy by a few rtol of the scale; a drift beyond that means the motion
#: is off, or the mesh's modes above the band took that much from it by numerical damping
#: (docs/user_guide.md, "Energy ledger"). The final residual, not the largest: a stiff mesh's
#: modes above the band ring with a spurious elastic energy that comes and goes (the stiffened
#: strip of tests/accuracy/test_flexible_link_inertia.py: largest 2e3 rtol, final 0.2 rtol, its
#: angle 0.35x its tolerance). Measured, final: benchmarks/scenes.py's scenes over their short
#: horizons at rtol 1e-4, 1e-6, 1e-7: at most 5.9 rtol (the leaf spring at 1e-7); that stiffened
#: strip at N = 1 .. 8, rtol 1e-6 .. 1e-8: at most 3.8 rtol; the stiffened arm + strip at rtol
#: 1e-7: 26 rtol, its strip 3.1e-5 rad off the rigid double pendulum (100x its tolerance),
#: without another warning.
LEDGER_RTOL_WARN = 20.0


def default_integrator(stats: dict) -> bool:
    """Whether a run's ``stats`` are the default integrator's (the adaptive generalized-alpha),
    the one whose error estimate the warnings below read."""
    return bool(stats.get("adaptive")) and stats.get("integrator") == "generalized-alpha"


def warn_if_inaccurate(stats: dict, stacklevel: Optional[int] = None) -> None:
    """AccuracyWarning when ``stats['ledger_relative']`` (from :func:`quality`) exceeds
    LEDGER_WARN, or, with the adaptive default integrator, when the energy it removed or added
    by the end of the run exceeds LEDGER_RTOL_WARN rtol of the energy scale; with what to
    change."""
    x = stats.get("ledger_relative", 0.0)
    if x > LEDGER_WARN:
        if stats.get("integrator") == "generalized-alpha" and not stats.get("adaptive", True):
            advice = (f"with a fixed step this means the step is too large for the motion (or "
                      f"rho_inf damps too much), or the Newton tolerance rtol "
                      f"({stats.get('rtol', 0.0):.3g}) is too loose: use a smaller step= or rtol=")
        elif stats.get("integrator") in ("ida", "tree"):
            advice = (f"with {'IDA' if stats.get('integrator') == 'ida' else 'the tree integrator'} "
                      f"this means its tolerances are too loose: use a smaller rtol=")
        else:
            advice = (f"with the default integrator this means the outputs, and so the band "
                      f"({stats['band']:.3g} Hz), are too coarse for the motion (stiff links "
                      f"swinging fast stretch spuriously): use a smaller dt_out or a higher band=")
        scale = stats["energy_scale"]
        warnings.warn(
            f"simulate: the energy ledger drifted by {x * scale:.3g} J, {x:.3g} of the energy the "
            f"run moved and exchanged ({scale:.3g} J: the largest of the kinetic energy, the "
            f"change of kinetic plus elastic energy, the work supplied and the work dissipated), "
            f"above the bound {LEDGER_WARN:g}: "
            f"the integrator created or destroyed that much energy, so the trajectory is "
            f"doubtful; {advice}", AccuracyWarning, stacklevel=stacklevel or outside_stacklevel())
        return
    if not default_integrator(stats):
        return
    rtol = stats.get("rtol") or 0.0
    drift = stats.get("numerical_dissipation_relative") or 0.0
    if rtol > 0 and abs(drift) > LEDGER_RTOL_WARN * rtol:
        scale = stats["energy_scale"]
        warnings.warn(
            f"simulate: the integrator {'removed' if drift > 0 else 'added'} "
            f"{abs(drift) * scale:.3g} J by the end of the run "
            f"(stats['numerical_dissipation']), {abs(drift):.3g} of the energy the run moved and "
            f"exchanged ({scale:.3g} J), {abs(drift) / rtol:.3g} times rtol ({rtol:.3g}); a "
            f"motion within rtol changes the energy by a few rtol (the bound is "
            f"{LEDGER_RTOL_WARN:g} rtol), so the motion is probably off by more than its "
            f"tolerance" + (f", or the modes above the band ({stats['band']:.4g} Hz) took "
                            f"that energy from it by numerical damping: a higher band= (e.g. "
                            f"band={4 * stats['band']:.4g}) resolves more of them, a tighter rtol "
                            f"shortens the steps" if stats.get("global_error_estimate") is None
                            else ": a tighter rtol shortens the steps"),
            AccuracyWarning, stacklevel=stacklevel or outside_stacklevel())


#: stats['error_sum'] (the accepted steps' local error estimates summed, in tolerances) above
#: which a run warns: the steps the generalized-alpha accepts at Newton's noise level carry a
#: systematic Newton error that adds up. Newton's tolerance is tightened while the sum runs
#: ahead of its share (csrc/integrate/galpha.c, newton_min), so the sum stays below 1 unless that
#: tolerance reaches its floor, a relative 1e-11 (rtol 1e-8: a compound pendulum at 30 deg over
#: 5 s sums to 1.47 and ends 0.91x rtol amp off, warned), or the run is on course for more than
#: 3e5 steps, where it is not tightened.
ERROR_SUM_WARN = 1.0

#: stats['error_sum_max'] (each accepted step's largest configuration state's local estimate
#: in its own tolerance, summed over the run) above which a run without a global error estimate
#: (flexible links, sampled controllers) warns. error_sum averages each step's estimates over
#: every state, so states that barely move dilute it: a compound pendulum beside an idle steel
#: rod of 160 elements ended 14.8x its tolerance with error_sum 0.47 (error_sum_max 11.6; 40
#: elements: 6.5x, 6.06). The contract allows a single state "a few times" its tolerance
#: (docs/user_guide.md, "Accuracy contract": 6.2x on a 30-link chain); the scenes of
#: benchmarks/scenes.py reach 4.4 at rtol 1e-4 and 1e-6 (the double pendulum, whose strip's
#: quaternion component through zero ends 3.9x; the manipulator at 1e-6). Measured 2026-12-07.
ERROR_SUM_MAX_WARN = 6.0


def warn_if_above_tolerance(stats: dict, stacklevel: Optional[int] = None) -> None:
    """The default integrator's AccuracyWarnings on its summed local estimates
    (docs/user_guide.md, "Accuracy contract"): ``stats['error_sum']`` above ERROR_SUM_WARN;
    ``stats['error_sum_max']`` above ERROR_SUM_MAX_WARN where no global estimate is made; and
    steps accepted above the tolerance at the refinement's limit (``stats['floor_steps']``: a
    step 1/(REFINE_MAX BAND_STEPS band) long) when they take error_sum above ERROR_SUM_WARN,
    naming the estimate reached, the tolerance asked, when, and the remedy."""
    if not default_integrator(stats):
        return
    acc = stats.get("error_sum") or 0.0
    if acc > ERROR_SUM_WARN:
        warnings.warn(
            f"simulate: the local error estimates of the {stats['steps']} steps add up to "
            f"{acc:.3g} times the tolerance (rtol {stats['rtol']:.3g}, atol {stats['atol']:.3g}; "
            f"stats['error_sum']), above {ERROR_SUM_WARN:g}: {stats.get('noise_steps', 0)} steps "
            f"were accepted at the level of Newton's convergence tolerance (a relative "
            f"{stats.get('newton_rtol') or 0:.3g} at the end), whose error adds up step after "
            f"step, so the result is probably not within rtol. integrator='ida' controls every "
            f"state's error (a looser rtol asks less)", AccuracyWarning,
            stacklevel=stacklevel or outside_stacklevel())
    worst = stats.get("error_sum_max") or 0.0
    if worst > ERROR_SUM_MAX_WARN and stats.get("global_error_estimate") is None:
        warnings.warn(
            f"simulate: the largest configuration state's local error estimates add up to "
            f"{worst:.3g} times its tolerance (rtol {stats['rtol']:.3g}, atol "
            f"{stats['atol']:.3g}; stats['error_sum_max']), above {ERROR_SUM_MAX_WARN:g}, while "
            f"all the states' root-mean-square adds up to {acc:.3g} (stats['error_sum']): the "
            f"error is in a few states and the many that barely move (an idle or slow "
            f"flexible link's nodes) hide it from the step control, so some coordinates are "
            f"probably several times their tolerance off. rtol={stats['rtol'] / worst:.2g} "
            f"brings them within it", AccuracyWarning,
            stacklevel=stacklevel or outside_stacklevel())
    n = stats.get("floor_steps") or 0
    if n <= 0 or acc <= ERROR_SUM_WARN:
        # the floor steps' estimates are in error_sum: within 1, the run kept its contract (a
        # pendulum over 60 s at dt_out 1.0, band 0.83 Hz: 3238 floor steps at 60 us, error_sum
        # 0.67, its true error 0.65x: one of the floor warnings on runs within tolerance that
        # the accuracy audit of 2026-12-07 found)
        return
    warnings.warn(
        f"simulate: {n} of {stats['steps']} steps kept an error estimate above the tolerance "
        f"(rtol {stats['rtol']:.3g}, atol {stats['atol']:.3g}) at the shortest step allowed, "
        f"{band_floor(stats['band']) / REFINE_MAX:.3g} s (1/{REFINE_MAX:.0f} of the "
        f"{stats['band']:.4g} Hz band's floor): the largest reached {stats['error_ratio']:.3g} "
        f"times the tolerance, at t = {stats['error_ratio_time']:.6g} s, and with them the "
        f"estimates add up to {acc:.3g} tolerances, so the result is not within rtol. A higher "
        f"band= lowers that limit (and resolves more of the motion "
        f"instead of damping it), a looser rtol asks less; integrator='ida' controls every "
        f"state's error", AccuracyWarning,
        stacklevel=stacklevel or outside_stacklevel())


#: stats['global_error_estimate'] (the local estimates carried along the linearized motion,
#: csrc/integrate/galpha_global.c: the largest over the run of a configuration state's error
#: over rtol times its largest magnitude plus atol) above which a run warns. Measured on a compound pendulum over 5 s
#: (tests/accuracy/test_integrator_contract.py; true error over rtol amp + atol, estimate):
#: 2 deg rtol 1e-4 0.86 and 0.98; 30 deg 0.63 and 0.71; 2 deg rtol 1e-6 1.11 and 1.09 (warned);
#: 170 deg rtol 1e-4 7.8 and 24.6 (warned; 13.4 when propagated step by step, not in blocks of 8).
GLOBAL_ERROR_WARN = 1.0
#: the error check of the tree integrator and IDA (python/phmech/_simulate.py, _error_check):
#: each check run at this times the last run's rtol and atol, at most ERROR_CHECK_RUNS of them
ERROR_CHECK_TIGHTER = 0.1
ERROR_CHECK_RUNS = 4


def warn_if_global_error(stats: dict, stacklevel: Optional[int] = None,
                         tree: bool = False) -> None:
    """AccuracyWarning when the adaptive generalized-alpha's global error estimate
    (``stats['global_error_estimate']``, rigid mechanisms) exceeds GLOBAL_ERROR_WARN, naming the
    estimate, the tolerance, when, and the rtol that would bring the error within this run's
    tolerance (docs/user_guide.md, "Accuracy contract"); for the tree integrator and IDA, their
    error check's figure (python/phmech/_simulate.py, _error_check). ``tree``: the mechanism is
    a rigid tree the tree integrator takes, which the remedy then names."""
    g = stats.get("global_error_estimate")
    if g is None or not g > GLOBAL_ERROR_WARN:
        return
    rtol, atol = stats["rtol"], stats["atol"]
    where = stats.get("global_error_state")
    if stats.get("integrator") in ("tree", "ida"):
        warnings.warn(
            f"simulate: the result of integrator={stats['integrator']!r} is probably not "
            f"within rtol: refined to a "
            f"local rtol of {stats['integration_rtol']:.3g} (stats['integration_rtol']), its "
            f"last two runs still differ by {g:.3g} times the tolerance (rtol {rtol:.3g}, atol "
            f"{atol:.3g}: |error| <= rtol max|y| + atol per joint coordinate and rate) at t = "
            f"{stats['global_error_time']:.6g} s, in {where} (stats['global_error_estimate'], "
            f"an upper estimate of the result's error): the motion amplifies the steps' errors "
            f"beyond what {ERROR_CHECK_TIGHTER ** -ERROR_CHECK_RUNS:.0f} times tighter steps "
            f"resolve (or they reach round-off). A looser rtol asks less; a chaotic motion (a "
            f"double pendulum's) is followed at no rtol beyond a few of its Lyapunov times",
            AccuracyWarning,
            stacklevel=stacklevel or outside_stacklevel())
        return
    if not default_integrator(stats):
        return
    warnings.warn(
        f"simulate: the estimated global error reached {g:.3g} times the tolerance (rtol "
        f"{rtol:.3g}, atol {atol:.3g}: |error| <= rtol max|y| + atol per coordinate) at t = "
        f"{stats['global_error_time']:.6g} s" + (f", in {where}" if where else "") +
        _near_zero(stats) +
        f" (stats['global_error_estimate']: the steps' local error estimates carried along the "
        f"linearized motion, which amplifies them; summed without it they reach "
        f"{stats.get('error_sum') or 0:.3g}, stats['error_sum']), so the result is probably not "
        f"within rtol. The step control holds the summed local errors to a share of rtol and "
        f"the motion multiplies them, so the error scales with rtol: rtol={rtol / (3 * g):.2g} "
        f"and atol={atol / (3 * g):.2g} should bring it within this run's tolerance (that run "
        f"then measures its own estimate against its tighter one)" + (
            ". This mechanism is a rigid tree: integrator='tree' (joint coordinates, explicit "
            "Dormand-Prince; its error check keeps the result within rtol) is often faster "
            "and within it, unless stiff springs or friction make its steps short"
            if tree else ""),
        AccuracyWarning, stacklevel=stacklevel or outside_stacklevel())


def _near_zero(stats: dict) -> str:
    """For warn_if_global_error: the coordinate's estimated error and largest size when its
    tolerance is mostly its absolute part (a coordinate that stays near zero, as a
    parallelogram's coupler's angular rate: it is held to atol, not to rtol of its motion),
    else ""."""
    err, tol, size = (stats.get(k) for k in ("global_error_absolute", "global_error_tolerance",
                                             "global_error_scale"))
    if not (err and tol and size is not None) or stats["rtol"] * size > 0.5 * tol:
        return ""
    return (f"; an error of about {err:.2g} there, in a coordinate whose largest size over "
            f"the run is {size:.2g}: it stays near zero, so its tolerance, {tol:.2g}, is mostly "
            f"the absolute part, set by atol (if an error of that size is small against the "
            f"motion's other coordinates, a larger atol= accepts it)")


def band_floor(band: float) -> float:
    """The smallest step [s] the adaptive integrator takes for accuracy's sake, for a band [Hz]."""
    return 1.0 / (BAND_STEPS * band)


class RunMonitor:
    """Called by the core every ~100 steps and at each output: updates the progress bar (when
    ``progress``; tqdm.auto, on ``out``, default stderr), warns once when the run is on course to cost far more than the band needs, and
    chains the user's per-output ``callback``.

    The cost warning fires when, after at least 1 s of CPU, the mean step is below 1/30 of the
    band's floor step and the projected CPU time of the whole run exceeds 30 s."""

    def __init__(self, t_start: float, t_end: float, band: float, integrator: str,
                 progress: bool = False, user: Optional[Callable[[float, int], bool]] = None,
                 out=None, checkpoint: Optional["Checkpoint"] = None):
        self.t_start, self.t_end, self.band, self.integrator = t_start, t_end, band, integrator
        self.progress, self.user, self.out = progress, user, out if out is not None else sys.stderr
        self.wall0 = self.last_print = time.perf_counter()
        self.cpu0 = time.process_time()
        self.t, self.steps, self.h = t_start, 0, 0.0
        self.warned = False
        self.printed = False
        self.bar = None          # the tqdm progress bar, made at the first update
        self.terminated = False  # set by SIGTERM (sigterm_as_interrupt)
        self.stopped = False     # the user's callback returned True
        self.checkpoint = checkpoint

    # core -> Python: between outputs
    def __call__(self, t: float, steps: int, h: float) -> bool:
        self.t, self.steps, self.h = t, steps, h
        self._check_cost()
        self._maybe_print()
        return self.terminated

    @property
    def per_output(self):
        """``on_output`` when an output has something to do in Python (a progress bar, a
        checkpoint, the user's callback), else None: the core then reads ``terminated`` itself
        at each output (csrc/pyext/py_run.c, phm_py_interrupt_cb), without a call."""
        return self.on_output if self.progress or self.checkpoint is not None or \
            self.user is not None else None

    # core -> Python: at each output
    def on_output(self, t: float, i: int) -> bool:
        self.t = t
        if self.progress:   # (tested here: a call less at every output of a run without a bar)
            self._maybe_print()
        if self.checkpoint is not None:   # before the user's callback: it sees the file up to i
            self.checkpoint.output(i, self.steps, time.perf_counter() - self.wall0)
        if self.terminated:
            return True
        if self.user is not None and self.user(t, i):
            self.stopped = True
        return self.stopped

    def _fraction(self) -> float:
        return (self.t - self.t_start) / (self.t_end - self.t_start)

    def _check_cost(self) -> None:
        if self.warned or self.steps < 200:
            return
        cpu = time.process_time() - self.cpu0
        frac = self._fraction()
        if cpu < 1.0 or frac <= 0:
            return
        mean_h = (self.t - self.t_start) / self.steps
        floor = band_floor(self.band)
        projected = cpu / frac
        if mean_h < floor / 30 and projected > 30.0:
            self.warned = True
            f_res = 1.0 / (BAND_STEPS * mean_h)
            if self.integrator == "tree":
                why = (f"the tree integrator's explicit steps follow the model's fastest motion "
                       f"(about {_hz(f_res)}: a stiff spring, a friction's regularization)")
                advice = ("The implicit integrators (the default, or integrator='ida') take "
                          "stiff models with longer steps.")
            elif self.integrator == "ida":
                why = (f"the integrator is resolving vibrations up to about {_hz(f_res)}, far "
                       f"above what the output can show")
                advice = ("The default integrator (integrator='generalized-alpha' without step=) "
                          "damps vibrations above the band instead of resolving them.")
            else:
                # the error estimate sets these steps: they resolve the motion it sees (a fast
                # one, or a long run: the local errors are summed over the whole run, so for
                # the same motion the steps shrink as 1 / sqrt(span))
                why = (f"the error estimate asks for them to keep rtol over the whole run "
                       f"({_duration(self.t_end - self.t_start)} simulated; at {BAND_STEPS} steps "
                       f"per period they would resolve {_hz(f_res)})")
                advice = ("Such steps come from motion faster than the band, a long run (the "
                          "local errors are summed over the run: for the same motion the steps "
                          "shrink as 1/sqrt(t_end - t_start), and the phase of an oscillation is "
                          "held over every period), a tight rtol/atol, or options that ask for "
                          "them (a small max_step or step, a large band=): a looser rtol, or a "
                          "band= that covers the motion, costs less (docs/user_guide.md, "
                          "\"Accuracy contract\").")
            warnings.warn(
                f"simulate: the mean step so far is {mean_h:.2g} s, {floor / mean_h:.0f}x smaller "
                f"than the {floor:.2g} s that the {self.band:.4g} Hz band needs: {why}. At this "
                f"rate the run will take about {_duration(projected)} of CPU. "
                + advice, CostWarning, stacklevel=outside_stacklevel())

    def _maybe_print(self) -> None:
        if not self.progress:
            return
        now = time.perf_counter()
        if now - self.last_print >= 0.2:
            self.last_print = now
            self._update()

    def _update(self) -> None:
        """The tqdm bar (tqdm.auto: a text bar on a terminal, a widget in Jupyter) over the
        simulated time, with elapsed time, ETA, steps, steps per second and the last step."""
        if self.bar is None:
            from tqdm.auto import tqdm
            span = self.t_end - self.t_start
            self.bar = tqdm(total=span, unit="s", unit_scale=False, desc="phmech simulate",
                            file=self.out, dynamic_ncols=True, leave=True,
                            bar_format="{desc}: {percentage:3.0f}%|{bar}| t = {n:.4g}/{total:.4g} s "
                                       "[{elapsed}<{remaining}{postfix}]")
        wall = time.perf_counter() - self.wall0
        rate = self.steps / wall if wall > 0 else 0.0
        self.bar.n = min(self.t - self.t_start, self.bar.total)
        last = f", step {self.h:.2g} s" if self.h > 0 else ""
        self.bar.set_postfix_str(f"{self.steps} steps, {rate:.3g}/s{last}", refresh=False)
        self.bar.refresh()
        self.printed = True

    def finish(self, steps: int) -> None:
        if self.progress:
            self.steps = steps
            self._update()
            self.bar.close()


class StaticMonitor:
    """Progress of Mechanism.static's load stepping: a tqdm bar (tqdm.auto) over the load factor
    0..1, with the Newton iterations so far and the current load step; called by the core after
    each accepted load step."""

    def __init__(self, out=None):
        from tqdm.auto import tqdm
        self.bar = tqdm(total=1.0, desc="phmech static", file=out if out is not None else sys.stderr,
                        dynamic_ncols=True,
                        bar_format="{desc}: {percentage:3.0f}%|{bar}| load factor {n:.3g}/1 "
                                   "[{elapsed}<{remaining}{postfix}]")

    def __call__(self, s: float, iterations: int, ds: float) -> bool:
        self.bar.n = min(s, 1.0)
        self.bar.set_postfix_str(f"{iterations} Newton iterations, load step {ds:.3g}", refresh=False)
        self.bar.refresh()
        return False

    def close(self) -> None:
        self.bar.close()


class Checkpoint:
    """``simulate(checkpoint=path, checkpoint_every=seconds)``: the result so far written to
    ``path`` (netCDF, ``phmech.load_result`` reads it) at the first output after every
    ``checkpoint_every`` seconds of WALL-CLOCK time (default 60 s; 0: at every output), and the
    final result when the run ends, also when it was interrupted (Ctrl-C, SIGTERM, the callback)
    or failed (the partial result of the SolverError). Wall time, not simulated time, because a
    checkpoint is there to bound the work a crash or a batch system's kill loses. Each write
    goes to a temporary file beside ``path``, renamed over it once complete, so ``path`` always
    holds a whole result. A checkpoint's arrays are the final result's first outputs; its
    ``stats`` hold what is known mid-run (steps, wall_time, ``checkpoint`` True, the options and
    quality figures so far)."""

    def __init__(self, path, every: Optional[float], make: Callable):
        if not isinstance(path, (str, os.PathLike)):
            raise ModelError(f"checkpoint must be a file path (got {type(path).__name__})")
        every = 60.0 if every is None else real("checkpoint_every", every)
        if not every >= 0:
            raise ModelError(f"checkpoint_every must be >= 0 seconds of wall time (got {every})")
        self.path, self.every, self.make = path, every, make
        self.arrays = None
        self.last = time.perf_counter()

    def arrays_ready(self, arrays: dict) -> None:
        """The core's output arrays, before the run (filled output by output)."""
        self.arrays = arrays

    def output(self, i: int, steps: int, wall: float) -> None:
        """Output ``i`` is stored: write outputs 0..i if the interval has passed."""
        if time.perf_counter() - self.last < self.every or self.arrays is None:
            return
        self.write(self.make(self.arrays, i + 1, dict(steps=steps, wall_time=wall, checkpoint=True)))

    def write(self, result) -> None:
        """Write ``result`` to the path, atomically."""
        result.to_netcdf(self.path)
        self.last = time.perf_counter()


def _duration(s: float) -> str:
    if not np.isfinite(s):
        return "?"
    if s < 120:
        return f"{s:.1f} s"
    if s < 7200:
        return f"{s / 60:.0f} min"
    return f"{s / 3600:.1f} h"


def _hz(f: float) -> str:
    for unit, scale in (("MHz", 1e6), ("kHz", 1e3)):
        if f >= scale:
            return f"{f / scale:.3g} {unit}"
    return f"{f:.3g} Hz"


@contextlib.contextmanager
def sigterm_as_interrupt(monitor: RunMonitor):
    """While a run is on, SIGTERM (a batch system's time limit) stops it like Ctrl-C: the run
    returns what it computed (``interrupted`` True). The handler only sets
    ``monitor.terminated`` (raising from it could land inside a user's callback); the monitor
    stops the run at its next call (every ~100 steps and at each output). Only in the main
    thread, where Python handles signals; the previous handler is restored afterwards."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def handler(signum, frame):
        monitor.terminated = True

    try:   # signal.signal returns the handler it replaces (None: not one set from Python)
        previous = signal.signal(signal.SIGTERM, handler)
    except (AttributeError, ValueError):
        yield
        return
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous if previous is not None else signal.SIG_DFL)


#: energy scale [J] below which a run is taken as at rest (a clamped leaf that never moves has
#: a round-off energy scale of 1e-23 J; its ledger "ratio" was 0.74; the leaf-spring guide of
#: examples/sweeps.py at rest before its pulse, 1.1e-18 J, ratio 1). A mechanism that really
#: moves with less than a femtojoule (a MEMS part) gets no ledger ratio: scale its units.
STILL = 1e-15
#: ... and relative to the size of the energies: a cantilever held still under a tip load
#: stores 3e-3 J, whose round-off (2e-18 J) made an energy scale and a ledger "ratio" of 0.63
#: (tests/test_stress_resultants.py); 1e4 machine epsilons leave room for the sums of a run
ROUND_OFF = 1e4 * np.finfo(float).eps


def quality(energy: dict, band: float) -> dict:
    """Figures a result reports about its own accuracy (added to ``stats``):

    - ``band`` [Hz]: the highest frequency the run was asked to resolve;
    - ``energy_scale`` [J]: what the run actually moved and exchanged, the energy the ledger
      residual is measured against: the largest of the kinetic energy, the change of the
      kinetic plus elastic energy |(T + V_el)(t) - (T + V_el)(0)| (gravity's work shows in
      it), |the work supplied| through the ports and the work dissipated, over the run. (It
      was once the sum of the largest kinetic energy, the range of the potential energy and
      the largest supplied and dissipated work, which counts the same joules two to four
      times: a four-bar's 0.14 J ledger error on 10 J of supplied work read 3.5e-3 of a
      40.7 J "scale" and did not warn.) The elastic energy a structure holds under a static
      load is not in it: a small vibration about a loaded state is judged against its own
      energy;
    - ``ledger_relative``: the largest |ledger residual| over the run / energy_scale (0 when
      what changed -- the largest range of the kinetic, elastic and gravity energies and of the
      supplied and dissipated work -- is below ``STILL`` J or below ``ROUND_OFF`` times the
      energies' size (the largest sum of their absolute values): nothing was exchanged (a
      structure held still keeps its elastic energy), and a ratio of round-offs would mean
      nothing). :func:`warn_if_inaccurate` warns above ``LEDGER_WARN``;
    - ``numerical_dissipation`` [J]: minus the final ledger residual (energy the integrator
      removed; positive = lost), with ``numerical_dissipation_relative`` the same / energy_scale.
    """
    led = energy["ledger"]
    scale = lmax = size = changed = 0.0
    if len(led):
        # rows kinetic, elastic, gravity, supplied, dissipated, ledger and kinetic + elastic:
        # one array, few calls (|x|'s largest and the ranges from each row's extremes)
        kin, el = energy["kinetic"], energy["elastic"]
        E = np.array([kin, el, energy["gravity"], energy["supplied"], energy["dissipated"], led,
                      kin + el])
        hi, lo = E.max(axis=1).tolist(), E.min(axis=1).tolist()
        s0 = float(E[6, 0])
        scale = max(hi[0], -lo[0], hi[6] - s0, s0 - lo[6], hi[3], -lo[3], hi[4], -lo[4])
        lmax = max(hi[5], -lo[5])
        size = float(np.abs(E[:5]).sum(axis=0).max())
        changed = max(h - l for h, l in zip(hi[:5], lo[:5]))
    moved = changed > max(STILL, ROUND_OFF * size)
    q = dict(band=band, energy_scale=scale, ledger_relative=lmax / scale if moved else 0.0,
             numerical_dissipation=float(-led[-1]) if len(led) else 0.0)
    q["numerical_dissipation_relative"] = q["numerical_dissipation"] / scale if moved else 0.0
    return q

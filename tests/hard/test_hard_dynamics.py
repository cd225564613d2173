"""Hard cases, dynamics: published multibody and flexible-beam problems run with
simulate(t_end, dt_out) and no solver option (short versions; the long ones run from
benchmarks/hard_cases.py). Scenes, references and tolerances: tests/hard/_scenes.py; table and
notes: docs/validation.md."""
import functools

import warnings

import pytest

import phmech as ph

import _scenes as S


@functools.lru_cache(maxsize=None)
def outcome(name: str) -> S.Outcome:
    with S.no_redundancy_warning():
        o = getattr(S, name)(long=False)
    print(f"\n{o.case}: {o.value} (reference {o.reference}); error {o.error:.3g} {o.unit} "
          f"(tolerance {o.tolerance:g}); CPU {o.cpu:.2f} s; ledger {o.ledger:.2e}; {o.notes}")
    return o


FOUR_BAR = ("measured: with the defaults the N = 2 four-bar (A02) runs through its singular "
            "configurations (all rods horizontal, every 0.5-1.4 s; it stopped at the first, t = "
            "0.714 s, before the constraint rows of loops were regularized, csrc/dae/watch.c) to "
            "t_end = 10 s, but B0 ends 1.84e-3 m off the exact motion (limit 1e-3 m; 7.2e-5 m "
            "over the first 2 s). The deviation is the default integrator's phase error at dt_out "
            "0.05 s (steps up to 1/(12 band) = 8 ms): with a fixed step of 0.2 ms it is 1.7e-4 m "
            "over 20 s, 7.7e-4 m at 1 ms, and rtol does not tighten it (issue 27, item 1). "
            "Strict: a build that passes must say so here")


@pytest.mark.parametrize("name", [
    "andrews", "rotating_beam", "tip_mass", "beck", "impulse", "pendulum_hour",
    pytest.param("four_bar", marks=pytest.mark.xfail(strict=True, reason=FOUR_BAR))])
def test_reference(name):
    o = outcome(name)
    assert o.passed, o.row()


def test_four_bar_runs_through_its_singular_configurations():
    # the whole run (10 s, about 11 flat positions) with the defaults, no failure; within the
    # benchmark's 1e-3 m of the exact motion over the first two (measured 7.2e-5 m)
    o = outcome("four_bar")
    assert o.extra["reached"] == o.extra["t_end"] and not o.extra["failure"]
    assert o.extra["deviation_2s"] <= 1e-3


LEDGER = {
    "beck": "measured 1.26e-3 of the energy scale (the released column below flutter, 20 s; the "
            "scale is the vibration's 2.9e-7 J, the residual 3.8e-10 J)",
    "impulse": "measured 2.9e-3: the 1 ms pulse puts energy far above the 50 Hz band of "
               "dt_out = 10 ms, which the default integrator damps (0.0139 J of 1.97 J "
               "supplied); with dt_out = 1 ms it is 6e-6 (long version)"}


@pytest.mark.parametrize("name", [
    pytest.param(n, marks=pytest.mark.xfail(strict=True, reason=LEDGER[n])) if n in LEDGER else n
    for n in ("andrews", "four_bar", "rotating_beam", "tip_mass", "beck", "impulse",
              "pendulum_hour")])
def test_energy_ledger(name):
    # the ledger residual over the run relative to its energy scale (res.stats)
    assert outcome(name).ledger <= S.LEDGER_TOL


def test_andrews_initial_values_are_consistent():
    # the test set's initial angles close the three loops: the projection moves none of them
    assert outcome("andrews").extra["initial_moved"] < 1e-12


def test_one_hour_with_flat_memory():
    o = outcome("pendulum_hour")
    assert o.extra["rss_growth_mb"] <= o.extra["rss_allowed_mb"], o.extra


@pytest.mark.xfail(strict=True, reason=(
    "measured: modes(2, at=static()) of Beck's column under the follower load P = 10 EI/L^2 "
    "gives omega = (-0.604, 11.40) rad/s, i.e. divergence as if the load were dead; the "
    "simulated column vibrates stably at 5.18 rad/s there, and flutters only above 20.05"))
def test_beck_modes_below_flutter():
    omega = S.beck_modes(10.0)
    assert omega[0] > 0 and abs(omega[0] / S.beck_simulated_frequency(10.0) - 1) < 0.02


@pytest.mark.xfail(strict=True, reason=(
    "measured: the steel strip pendulum (10 elements) released from 2 rad with dt_out = 0.05 s "
    "stretches by 1.26e-5 m at the bottom of its swing, 18 times the physical 7.0e-7 m (elastic "
    "energy 3.6e-3 J, ledger 2.3e-4; before issue 27's default band of at least 50 / span: "
    "1.30e-4 m, 186 times, 0.357 J, ledger 1.7e-2); dt_out 0.01 s: 1.14e-5 m (before 5.9e-6)"))
def test_swinging_strip_does_not_stretch():
    s = S.swinging_strip(0.05)
    print(s)
    assert s["stretch"] <= 10 * s["physical"]


def test_swinging_strip_is_not_silent():
    # until the stretch itself is right (above), the run must not pass silently. Before issue 27
    # its ledger (1.66e-2) exceeded the AccuracyWarning threshold and it warned; since the
    # default band is at least 50 / span (45 Hz here, was 10 Hz from dt_out) the ledger is
    # 2.3e-4 of the former energy scale (measured), 1.5e-3 of the energy the run moved and
    # exchanged (the ledger's figure since issue 27, a smaller denominator: same joules). The
    # contract: within LEDGER_WARN, or an AccuracyWarning
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        s = S.swinging_strip(0.05)
    warned = [x for x in w if issubclass(x.category, ph.AccuracyWarning)]
    if s["ledger"] > ph._run.LEDGER_WARN:
        assert warned
    else:
        assert not warned

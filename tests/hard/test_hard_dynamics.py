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


@pytest.mark.parametrize("name", [
    "andrews", "rotating_beam", "tip_mass", "beck", "impulse", "pendulum_hour", "four_bar"])
def test_reference(name):
    # four_bar (A02, N = 2): B0 2.6e-4 m off the exact motion over the benchmark's 20 s (limit
    # 1e-3 m; 1.93e-3 before the loops' constraint wrenches were made workless at the default
    # integrator's stage, csrc/dae/residual.c), with AccuracyWarnings: 5678 steps at the
    # refinement's limit near its singular configurations, where a coupler's twist is off
    o = outcome(name)
    assert o.passed, o.row()


def test_four_bar_runs_through_its_singular_configurations():
    # the whole run (20 s, 20 flat positions) with the defaults, no failure; within the
    # benchmark's 1e-3 m of the exact motion over the first two (measured 3.1e-6 m; 7.2e-5 m
    # before the loops' wrenches were made workless at the stage)
    o = outcome("four_bar")
    assert o.extra["reached"] == o.extra["t_end"] and not o.extra["failure"]
    assert o.extra["deviation_2s"] <= 1e-3


@pytest.mark.parametrize("name", ["andrews", "four_bar", "rotating_beam", "tip_mass", "beck",
                                  "impulse", "pendulum_hour"])
def test_energy_ledger(name):
    # the ledger residual over the run relative to its energy scale (res.stats). Measured: beck
    # 7.6e-4 (1.26e-3 before issue 27's fixes of the default integrator), impulse 1.3e-5 (2.9e-3)
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


def test_swinging_strip_does_not_stretch():
    """The steel strip pendulum (10 elements) released from 2 rad with dt_out = 0.05 s: measured
    stretch 6.9e-6 m at the bottom of its swing, 9.8 times the physical 7.0e-7 m (elastic energy
    1.1e-3 J, ledger 9.0e-5). It was 1.26e-5 m (18 times) before the step grew only on three
    estimates (csrc/integrate/galpha.c, galpha_accept), and 1.30e-4 m (186 times) before the
    default band of at least 50 / span."""
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

"""Short versions of benchmarks/scenes.py: ordinary scenes run with simulate(t_end, dt_out) and
nothing else agree with an independent tight reference (IDA, BDF) on the quantities a user looks
at, and their energy ledgers close. The full horizons and the CPU table: `make bench`
(benchmarks/scenes.py) and docs/integrators.md."""
import os
import sys

import pytest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "benchmarks"))
import scenes  # noqa: E402


QUICK = scenes.SCENES


@pytest.mark.parametrize("scene", QUICK, ids=[s.name for s in QUICK])
def test_scene_with_the_defaults_matches_its_reference(scene):
    r = scenes.run_scene(scene, scene.t_quick)
    # band quantities (positions, joint angles) within 1e-3 of their scale (the scale is the
    # motion's amplitude for the leaf spring and the cantilever, the mechanism's size otherwise;
    # measured: <= 7.0e-4, the cantilever's tip 2.9 um of its 4.1 mm over 0.3 s)
    assert r["error"] <= 1e-3, r["errors"]
    # energy: ledger residual (numerical dissipation and integration error) <= 1e-3 of the
    # energy scale (measured <= 1.8e-4)
    assert r["ledger_relative"] <= 1e-3, r["ledger_relative"]
    if "frequency_error" in r:     # dominant frequency of the band quantity (measured <= 4.1e-6)
        assert r["frequency_error"] <= 5e-4, r
    if "frequency_error_vs_modes" in r:   # the leaf spring: FFT vs modes() (1.9e-4 over 2 s)
        assert r["frequency_error_vs_modes"] <= 5e-4, r

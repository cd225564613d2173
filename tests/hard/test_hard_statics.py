"""Hard cases, statics: published large-deformation beam problems (short versions; the long ones
run from benchmarks/hard_cases.py). Scenes, references and tolerances: tests/hard/_scenes.py;
table and notes: docs/validation.md."""
import functools

import numpy as np
import pytest

import _scenes as S


@functools.lru_cache(maxsize=None)
def outcome(name: str) -> S.Outcome:
    o = getattr(S, name)(long=False)
    print(f"\n{o.case}: {o.value} (reference {o.reference}); error {o.error:.3g} {o.unit} "
          f"(tolerance {o.tolerance:g}); CPU {o.cpu:.2f} s; {o.notes}")
    return o


@pytest.mark.parametrize("name", ["rollup", "mattiasson", "bathe_bend", "dadeppo_arch", "elastica"])
def test_reference(name):
    o = outcome(name)
    assert o.passed, o.row()


def test_arch_limit_is_a_limit_point():
    # the last load with an equilibrium is where the lowest linearized mode goes soft: measured
    # 0.027 rad/s there against 0.18 rad/s unloaded (N = 40)
    assert 0 < outcome("dadeppo_arch").extra["omega1"] < 0.05


def test_elastica_table_is_the_elliptic_solution():
    # the 3-digit table (Timoshenko & Gere 1961, Table 2-7) against the elliptic integrals
    for alpha, (ratio, x, y) in S.ELASTICA.items():
        np.testing.assert_allclose(S.elastica_exact(alpha), (ratio, x, y), atol=1.5e-3)


def test_elastica_default_load_steps():
    # static()'s default 10 load steps jump to the unstable, nearly straight branch (tip rotation
    # -0.29 deg, lowest mode -1.44 rad/s: measured with check_stability=False); the stability
    # check sees the negative eigenvalue and repeats the solve with 100 steps, which follow the
    # loading path to the elastica
    o = S.elastica_default_steps()
    assert o["stable"] and o["steps"] == 100 and o["lowest_omega"] > 0
    assert abs(o["rotation_deg"] - 60.0) < 1.0


def test_modes_at_a_loaded_equilibrium():
    # modes(at=st) linearizes with the loads static(loads=...) found st under (it ignored them:
    # omega1 = +3.61 rad/s, stable, for the column on its straight branch at 1.152 Pcr; with
    # add_wrench -1.44)
    o = S.elastica_default_steps(check_stability=False)
    assert o["steps"] == 10 and o["stable"] is None and abs(o["rotation_deg"]) < 1.0
    assert o["omega1"] < 0

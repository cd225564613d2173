"""The Fig. 3 manipulator (examples/manipulator.py, paper Sec. VIII-C) in its --quick setting:
topology vs the paper's (25), set point, energy ledger, constraint residuals, large deflections."""
import json
import sys
from pathlib import Path

import numpy as np
import pytest

import phmech as ph


sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "examples"))
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))   # tests/: the paper's incidence matrices
from test_graphs import B_K_f, B_K_r  # noqa: E402
import manipulator as M  # noqa: E402

# IDA at rtol 1e-6: the ledger assertions below are IDA's precision (each port integrated on
# its own agrees to 1e-6); tests/test_scenes.py runs the manipulator with the defaults
QUICK = dict(elements=4, t_end=3.0, integrator="ida", rtol=1e-6, atol=1e-7)


@pytest.fixture(scope="module")
def quick():
    return M.run(M.ManipulatorParams(), **QUICK)


def test_graphs_reproduce_paper_eq25():
    m, _ = M.build(M.ManipulatorParams(), elements=2)
    g = m.graphs()
    np.testing.assert_array_equal(g.B_K_r, B_K_r)
    np.testing.assert_array_equal(g.B_K_f, B_K_f)
    np.testing.assert_array_equal(g.B_I_r, [[0], [0], [-1]])      # i1 = (3, 0)
    np.testing.assert_array_equal(g.B_I_f, np.zeros((6, 1)))
    assert g.B_K.rigid_rows == ("R1", "R2", "R3")
    assert g.B_K.flexible_rows == ("F1L", "F1R", "F2L", "F2R", "F3L", "F3R")
    assert g.B_K.columns == tuple(f"k{i}" for i in range(1, 8))
    assert len(g.loops()) == 1


def test_gravity_compensated_equilibrium_is_the_target(quick):
    # Newton statics of the controlled arm (PD + constant compensation torques) vs the target
    for n, e in quick["summary"]["static_joint_error_rad"].items():
        assert abs(e) < 1e-6, n


def test_quick_run_reaches_set_point(quick):
    s = quick["summary"]
    tol = 0.02 * max(abs(x) for x in M.ManipulatorParams().target)   # 2 % of the largest step
    for n, e in s["final_joint_error_rad"].items():
        assert abs(e) < 5e-3, (n, e)           # at t = 3 s, within 5 mrad of the target
    assert s["settle_tol_rad"] == pytest.approx(tol)
    assert s["settling_time_s"]["all"] < QUICK["t_end"]
    # joint angles from the core vs angles recomputed from the poses (independent)
    res, m = quick["res"], quick["m"]
    ang = M.planar_joint_angles(m, res.poses[-1])
    for n in M.PAIRS:
        assert np.angle(np.exp(1j * (quick["joints"][n][-1] - ang[n]))) == pytest.approx(0, abs=1e-8)


def test_energy_ledger(quick):
    res = quick["res"]
    E = res.energy
    # supplied energy = sum of the port energies (4 PD, 4 compensation efforts, the knock i1);
    # each is its own integrated quantity, so they agree to the integration tolerance (rtol 1e-6;
    # measured 1.1e-7 J of 2.3 J)
    ports = sum(v for v in res.port_energy.values())
    assert len(res.port_energy) == 9
    np.testing.assert_allclose(ports, E["supplied"], rtol=0, atol=1e-6 * np.max(np.abs(E["supplied"])))
    # E(t) - E(0) = supplied - dissipated, to a small fraction of the energy exchanged
    scale = np.max(np.abs(E["total"] - E["total"][0]))
    resid = (E["total"] - E["total"][0]) - (E["supplied"] - E["dissipated"])
    assert np.max(np.abs(resid)) < 1e-3 * scale
    assert quick["summary"]["energy"]["ledger_rel"] < 1e-3
    # the knock injects energy, the PD damping and the material damping take it out
    assert E["dissipated"][-1] > 0


def test_constraint_residuals_and_no_redundant_rows(quick):
    c = quick["summary"]["constraint_residuals"]
    assert c["position_max"] < 1e-8          # rad or m
    assert c["velocity_max"] < 1e-5          # rad/s or m/s
    # the planar loop R1-F2-R2-F3 contains flexible links: not kinematically redundant
    assert quick["summary"]["redundant_constraints"] == []


def test_large_deflections_appear(quick):
    s = quick["summary"]
    assert s["max_deflection_rel_all"] > 0.10
    # the deflection is elastic: the static one at the target is smaller than the transient peak
    for k, v in s["static_deflection_rel"].items():
        assert v < s["max_deflection_rel"][k]


def test_cli_json(capsys):
    s = M.main(["--quick", "--json", "--no-plot", "--t-end", "0.5"])
    out = json.loads(capsys.readouterr().out)
    assert out["settings"]["elements"] == 4 and out["settings"]["t_end"] == 0.5
    assert set(out["settling_time_s"]) == {"k1", "k2", "k4", "k7", "all"}
    assert out["energy"]["ledger_rel"] == pytest.approx(s["energy"]["ledger_rel"])

"""simulate(record=...): only the chosen carriers are stored, with the same values as a full run."""
import numpy as np
import pytest

import phmech as ph
from phmech.section import table1_properties
from phmech import _model


def model():
    m = ph.Mechanism(gravity=(0, 0, -9.81))
    b = m.add_flexible_link("b", 1.0, table1_properties(1.0), elements=6)
    m.add_pair("clamp", ph.Fixed(), m.ground, b.start)
    tip = m.add_rigid_body("tip", 2.0, np.eye(3) * 1e-3, pose=ph.se3.translation([1.0, 0, 0]))
    m.add_pair("weld", ph.Fixed(), b.end, tip)
    return m, b, tip


def test_record_stores_only_the_chosen_carriers_with_identical_values():
    m, b, tip = model()
    full = m.simulate(0.2, 0.01, rtol=1e-8, integrator="ida")
    part = m.simulate(0.2, 0.01, rtol=1e-8, record=[tip, "b"], integrator="ida")
    assert full.poses.shape[1] == 8 and part.poses.shape[1] == 8  # 7 nodes + tip, reordered
    part_tip = m.simulate(0.2, 0.01, rtol=1e-8, record=tip, integrator="ida")
    assert part_tip.poses.shape == (len(full.t), 1, 4, 4)
    assert part_tip.twists.shape == (len(full.t), 1, 6)
    np.testing.assert_array_equal(part_tip.poses[:, 0], full.poses[:, tip.carrier])
    np.testing.assert_array_equal(part.positions(b), full.positions(b))
    np.testing.assert_array_equal(part_tip.energy["total"], full.energy["total"])
    with pytest.raises(ph.ModelError, match="not recorded"):
        part_tip.positions(b)
    with pytest.raises(ph.ModelError, match="record"):
        m.constraint_residuals(part_tip)


def test_record_bad_input():
    m, b, tip = model()
    with pytest.raises(ph.ModelError, match="ground"):
        m.simulate(0.02, 0.01, record=[m.ground], integrator="ida")
    with pytest.raises(ph.ModelError):
        m.simulate(0.02, 0.01, record=["nobody"], integrator="ida")
    with pytest.raises(ph.ModelError, match="out of range"):
        ph._core.model_simulate(_model.build(m), np.array([0.0, 0.01]), 1e-6, 1e-8, 0, None, None,
                                None, 0.0, 5, [99])


def test_progress_is_printed_to_stderr(capsys):
    m, b, tip = model()
    calls = []
    r = m.simulate(0.05, 0.01, progress=True, callback=lambda t, i: calls.append(t) and False, integrator="ida")
    err = capsys.readouterr().err
    assert "phmech simulate: 100%" in err and "t = 0.05/0.05 s" in err
    assert len(calls) == len(r.t)  # the user's callback still runs at every output


def test_pose_position_orientation_twist_of_bodies_and_frames():
    m, b, tip = model()
    r = m.simulate(0.1, 0.01, rtol=1e-8, integrator="ida", linear_solver="dense")
    np.testing.assert_array_equal(r.pose(tip), r.poses[:, tip.carrier])
    np.testing.assert_array_equal(r.pose("tip"), r.poses[:, tip.carrier])
    np.testing.assert_array_equal(r.position(b.end), r.tip(b))
    # a frame offset 0.5 m along the tip body's x axis: pose = H T, twist = Ad_{T^-1} t
    T = ph.se3.translation([0.5, 0, 0])
    f = ph.Frame(tip.carrier, T)
    np.testing.assert_allclose(r.pose(f), r.poses[:, tip.carrier] @ T, atol=1e-15)
    w, v = r.twists[:, tip.carrier, :3], r.twists[:, tip.carrier, 3:]
    np.testing.assert_allclose(r.twist(f)[:, 3:], v + np.cross(w, [0.5, 0, 0]), atol=1e-12)
    np.testing.assert_allclose(r.orientation(f), r.poses[:, tip.carrier, :3, :3], atol=1e-15)
    assert r.stats["linear_solver"] == "dense"

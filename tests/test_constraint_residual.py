"""Each pair's position constraint residual over a simulation (``SimulationResult.
constraint_residual``, computed by the core at each output: csrc/dae/output.c) against a
recomputation from the pose outputs by another path of the core (``_core.model_constraints_full``,
every row of every pair) and against ``Mechanism.constraint_residuals``; the same numbers when
only some carriers are recorded, and through a result file."""
import numpy as np
import pytest

import phmech as ph
from phmech import _core, _model, postprocess


def chain():
    """A spatial chain without redundant rows: a spherical pendulum, a revolute elbow, a slider
    along the second link and a free pair that constrains nothing (its residual is 0)."""
    m = ph.Mechanism()
    inertia = np.diag([0.02, 0.02, 0.004])
    a = m.add_rigid_body("upper", 1.0, inertia, com=(0.0, 0.0, -0.25))
    b = m.add_rigid_body("lower", 0.8, inertia, com=(0.0, 0.0, -0.2))   # placed from the pairs
    c = m.add_rigid_body("slider", 0.3, np.eye(3) * 1e-3)
    m.add_pair("shoulder", ph.Spherical(), m.ground, a, x0=(0.3, 0.1, 0.0), xdot0=(0.0, 1.0, 2.0))
    m.add_pair("elbow", ph.Revolute("x"), a.frame_at((0.0, 0.0, -0.5)), b, xdot0=(1.5,))
    m.add_pair("rail", ph.Prismatic("z"), b, c.frame_at((0.0, 0.0, 0.2)), xdot0=(0.2,))
    m.add_pair("watch", ph.Free(), m.ground, c)
    return m


@pytest.fixture(scope="module")
def runs():
    m = chain()
    return m, m.simulate(0.4, 0.01, rtol=1e-6), m.simulate(0.4, 0.01, rtol=1e-6, record=["slider"])


def test_residual_is_each_pairs_largest_row_of_the_pose_outputs(runs):
    m, r, _ = runs
    res = r.constraint_residual
    assert res.shape == (len(r.t), 4) and np.all(res >= 0)
    assert np.all(res[:, 3] == 0.0)   # the free pair has no row
    assert 0 < res[:, :3].max() < 1e-4   # held by the integrator, not exactly
    model = _model.build(m)
    layout = postprocess.full_layout(m._desc)   # no redundant row: every row is kept
    for i, t in enumerate(r.t):
        g = _core.model_constraints_full(model, r.poses[i], r.joints[i], float(t))[0]
        expect = [np.max(np.abs(g[row:row + rows]), initial=0.0) for row, rows, _, _ in layout]
        np.testing.assert_allclose(res[i], expect, rtol=1e-12, atol=1e-300)
    np.testing.assert_allclose(res.max(axis=1), m.constraint_residuals(r)["position"], rtol=1e-12,
                               atol=1e-300)


def test_residual_needs_no_recorded_poses_and_survives_a_file(runs, tmp_path):
    _, r, rec = runs
    np.testing.assert_array_equal(rec.constraint_residual, r.constraint_residual)
    r.to_netcdf(tmp_path / "chain.nc")
    back = ph.load_result(tmp_path / "chain.nc")
    np.testing.assert_array_equal(back.constraint_residual, r.constraint_residual)

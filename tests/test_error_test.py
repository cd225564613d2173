"""simulate(error_test="configuration"): twists out of IDA's local error test, BDF order <= 2.

Reference: the same discrete model integrated with every state in the error test at rtol 1e-10
(its own time error is ~1e-9 m here). Problem: the Table I cantilever (8 elements) bent by a
static tip force of 3 EI / 4 (tip ~0.24 L) and released, 0.5 s (the benchmark's transient)."""
import numpy as np
import pytest

import phmech as ph
from phmech.section import table1_properties

L, EI = 1.0, 5143.0
F_TIP = 0.75 * EI


@pytest.fixture(scope="module")
def released():
    m = ph.Mechanism()
    b = m.add_flexible_link("b", L, table1_properties(1.0), elements=8)
    m.add_pair("clamp", ph.Fixed(), m.ground, b.start)
    st = m.static(loads=[(b.end, (0, 0, 0, 0, 0, -F_TIP), "world")], steps=4)

    def run(rtol, **kw):
        r = m.simulate(0.5, 0.01, rtol=rtol, initial=st, linear_solver="klu", **kw, integrator="ida")
        return r, r.tip(b)[:, :3]

    ref, ref_tip = run(1e-10)
    return run, ref_tip


# at rtol 1e-3 the run loses 1.3e-2 of its energy (measured): an AccuracyWarning, rightly
@pytest.mark.filterwarnings("ignore::phmech.AccuracyWarning")
def test_configuration_error_test_converges_and_takes_fewer_steps(released):
    run, ref_tip = released
    err, steps, loss = {}, {}, {}
    for rtol in (1e-3, 1e-4, 1e-5):
        r, tip = run(rtol, error_test="configuration")
        err[rtol] = np.max(np.linalg.norm(tip - ref_tip, axis=1)) / L
        steps[rtol] = r.stats["steps"]
        e = r.energy["total"]
        loss[rtol] = (e[0] - e[-1]) / e[0]
        assert r.stats["last_order"] <= 2
    # measured: 4.2e-3, 9.1e-4, 1.5e-4 of L (second order in the step: ~rtol^(1/2)..rtol^(2/3))
    assert err[1e-4] < 2e-3
    assert err[1e-3] > 10 * err[1e-5]
    # the integrator dissipates what it does not resolve: energy goes down, less at tighter rtol
    # (measured 2.6e-2, 2.3e-3, 4.4e-4 of the initial energy)
    assert all(v > 0 for v in loss.values())
    assert loss[1e-3] > loss[1e-4] > loss[1e-5]
    r_all, tip_all = run(1e-4)
    # every state in the test: the fast shear/axial vibrations set the step (measured 1184 vs 299)
    assert steps[1e-4] < 0.5 * r_all.stats["steps"]
    assert np.max(np.linalg.norm(tip_all - ref_tip, axis=1)) / L < 1e-4   # measured 5.7e-6


@pytest.mark.parametrize("kw, match", [
    (dict(error_test="velocities"), "unknown error_test"),
    (dict(error_test="configuration", max_order=3), "max_order 1 or 2"),
    (dict(max_order=0), "max_order must be an integer"),
    (dict(max_order=2.5), "max_order must be an integer"),
])
def test_bad_error_test_options(kw, match):
    m = ph.Mechanism()
    body = m.add_rigid_body("b", mass=1.0, inertia=np.eye(3) * 0.1)
    m.add_pair("j", ph.Revolute(), m.ground, body)
    with pytest.raises(ph.ModelError, match=match):
        m.simulate(0.1, 0.01, **{"integrator": "ida", **kw})

"""IDA's two linear solvers take the same Jacobian: the closed form of csrc/dae/jacobian.c, into
KLU's sparse matrix or copied into the dense LU's (csrc/integrate/ida.c, ida_jac_dense). The dense LU
used to take IDA's own difference quotients, one residual per state for each Jacobian: over the
runs below 3002 (four-bar), 1978 (the same, planar), 16744 (manipulator) and 52615 (slider-crank,
planar) residuals beyond Newton's, where KLU spends none (measured before the change). Both
solvers now spend one residual per Newton iteration and nothing else, and their runs agree to
well within the solver's tolerance. The scenes are benchmarks/scenes.py's (rtol 1e-8, every state
in the error test); benchmarks/dense_jacobian.py measures CPU and the longer runs."""
import os
import sys
import warnings

import numpy as np
import pytest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "benchmarks"))
import scenes  # noqa: E402

# (scene name prefix, t_end [s], planar, the largest position difference allowed [m], measured
# after / before the change (difference quotients))
CASES = [
    ("four-bar", 0.5, False, 1e-7, "4.9e-8 / 3.4e-8"),
    ("four-bar", 0.5, True, 1e-7, "6.7e-9 / 2.8e-8"),
    ("manipulator", 0.02, False, 1e-10, "1.8e-11 / 1.8e-10"),
    ("slider-crank", 0.005, True, 1e-11, "2.6e-13 / 1.9e-13"),
]
IDS = [f"{c[0]}{'-planar' if c[2] else ''}" for c in CASES]


@pytest.fixture(scope="module")
def runs():
    """Each case run once per solver, kept for both tests."""
    cache = {}

    def get(case):
        name, t_end, planar, _, _ = case
        if case not in cache:
            sc = next(s for s in scenes.SCENES if s.name.startswith(name))
            out = {}
            for solver in ("dense", "klu"):
                m, _ = sc.build()
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    out[solver] = m.simulate(t_end, t_end / 20, rtol=1e-8, integrator="ida",
                                             linear_solver=solver, planar=planar)
            cache[case] = out
        return cache[case]
    return get


@pytest.mark.parametrize("case", CASES, ids=IDS)
def test_dense_lu_spends_no_residual_on_its_jacobian(runs, case):
    r = runs(case)
    # IDA counts one residual per Newton iteration; a difference-quotient Jacobian adds one per
    # state (43 .. 322 here) for each Jacobian
    extra = {s: r[s].stats["residual_evals"] - r[s].stats["nonlinear_iters"] for s in r}
    assert r["dense"].stats["jacobian_evals"] > 0
    assert extra["dense"] <= extra["klu"], extra


@pytest.mark.parametrize("case", CASES, ids=IDS)
def test_dense_lu_and_klu_agree(runs, case):
    _, _, planar, tol, measured = case
    r = runs(case)
    rd, rk = r["dense"], r["klu"]
    assert rd.stats["planar"] == rk.stats["planar"] == ("z" if planar else None)
    diff = np.abs(rd.poses[:, :, :3, 3] - rk.poses[:, :, :3, 3]).max()
    assert diff <= tol, (diff, measured)
    # the joint coordinates too (the pairs' integrated angles and slides): the same tolerance in
    # rad per 0.1 m of lever (the shortest link here is the 0.15 m crank)
    assert np.abs(rd.joints - rk.joints).max() <= 10 * tol

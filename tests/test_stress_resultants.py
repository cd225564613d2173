"""Stress resultants of a flexible link against the statics of a cantilever under a tip load."""
import numpy as np

import phmech as ph
from phmech.section import TABLE1, table1_properties


def test_cantilever_tip_load_moment_and_shear():
    N, L, P = 10, TABLE1["L"], 10.0  # small load: linear range
    m = ph.Mechanism()
    b = m.add_flexible_link("b", L, table1_properties(1.0), elements=N)
    m.add_pair("clamp", ph.Fixed(), m.ground, b.start)
    st = m.static(loads=[(b.end, (0, 0, 0, 0, 0, P), "world")], steps=1)
    m.add_wrench("hold", b.end, (0, 0, 0, 0, 0, P))  # keep it loaded: the state stays static
    r = m.simulate(0.01, 0.005, rtol=1e-10, initial=st, integrator="ida")
    sigma = m.stress_resultants(r, b)
    assert sigma.shape == (len(r.t), N, 6)
    # held still: its energy scale (2.3e-18 J, measured) is round-off of the 3e-3 J it stores,
    # so no ledger ratio (it was 0.63, and warned) -- phmech._run.quality
    assert r.stats["ledger_relative"] == 0.0
    s_mid = (np.arange(N) + 0.5) * L / N
    # equilibrium of the free part beyond each element: bending moment about y of magnitude
    # P (L - s), transverse shear force P; nothing else (to the small geometric nonlinearity)
    M_y, Q_z = sigma[0, :, 1], sigma[0, :, 5]
    np.testing.assert_allclose(np.abs(M_y), P * (L - s_mid), rtol=1e-4)
    np.testing.assert_allclose(np.abs(Q_z), P, rtol=1e-4)
    assert np.max(np.abs(sigma[0, :, [0, 2, 4]])) < 1e-6 * P
    # static: the viscous part is zero and the resultants do not change in time
    np.testing.assert_allclose(sigma[-1], sigma[0], atol=1e-6 * P)


def test_resultants_match_an_independent_evaluation_with_damping_and_record():
    # the core's element (csrc/model/element.c) against the strain formula written out with the
    # NumPy SE(3) functions: eps = log(H_k^-1 H_k+1)/h, h eps' = dexp_{-X}^-1 t_k+1 - dexp_X^-1 t_k
    from phmech import se3
    P = table1_properties(1.0)
    D = 1e-4 * np.asarray(P.stiffness)
    props = ph.BeamProperties(P.stiffness, P.inertia, D)
    m = ph.Mechanism(gravity=(0, 0, -9.81))
    b = m.add_flexible_link("b", TABLE1["L"], props, elements=6)
    m.add_pair("clamp", ph.Fixed(), m.ground, b.start)
    r = m.simulate(0.02, 0.005)
    rr = m.simulate(0.02, 0.005, record=[b])
    H, T = r.poses[:, b.nodes], r.twists[:, b.nodes]
    h = TABLE1["L"] / 6
    X = se3.log(se3.compose(se3.inverse(H[:, :-1]), H[:, 1:]))
    rate = (np.einsum("...ij,...j->...i", se3.dexp_inv(-X), T[:, 1:])
            - np.einsum("...ij,...j->...i", se3.dexp_inv(X), T[:, :-1])) / h
    eps_hat = np.array([0, 0, 0, 1.0, 0, 0])
    ref = np.einsum("ij,tkj->tki", P.stiffness, X / h - eps_hat) + np.einsum("ij,tkj->tki", D, rate)
    got = m.stress_resultants(r, b)
    scale = np.abs(ref).max()
    assert np.max(np.abs(got - ref)) < 1e-9 * scale
    assert np.max(np.abs(D @ rate[-1, 0])) > 1e-6 * scale   # the damping part is really there
    np.testing.assert_array_equal(m.stress_resultants(rr, b), got)

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
    s_mid = (np.arange(N) + 0.5) * L / N
    # equilibrium of the free part beyond each element: bending moment about y of magnitude
    # P (L - s), transverse shear force P; nothing else (to the small geometric nonlinearity)
    M_y, Q_z = sigma[0, :, 1], sigma[0, :, 5]
    np.testing.assert_allclose(np.abs(M_y), P * (L - s_mid), rtol=1e-4)
    np.testing.assert_allclose(np.abs(Q_z), P, rtol=1e-4)
    assert np.max(np.abs(sigma[0, :, [0, 2, 4]])) < 1e-6 * P
    # static: the viscous part is zero and the resultants do not change in time
    np.testing.assert_allclose(sigma[-1], sigma[0], atol=1e-6 * P)

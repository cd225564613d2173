"""The FFT of the tip motion after a small impulse gives the linearized first frequency
(within 0.1 %) -- time integration (IDA) and linearization (LAPACK) checked against each other."""
import numpy as np

import phmech as ph


def test_fft_of_tip_after_small_pulse_matches_first_mode():
    steel = ph.Material(E=210e9, nu=0.3, density=7850.0)
    el = ph.BeamProperties.from_material(ph.Section.rectangle(0.02, 0.001), steel)
    props = ph.BeamProperties(el.stiffness, el.inertia, 1e-6 * el.stiffness)  # zeta_1 ~ 7e-5
    m = ph.Mechanism()
    leaf = m.add_flexible_link("leaf", 0.2, props, elements=6)
    m.add_pair("clamp", ph.Fixed(), m.ground, leaf.start)
    f1 = m.modes(1).frequency[0]
    # 1 ms pulse of 0.05 N at the tip: a tip amplitude ~ 1e-4 L, deep in the linear range
    m.add_wrench("tap", leaf.end, (0, 0, 0, 0, 0, 0.05), law=ph.Pulse(t0=0.0, duration=1e-3))
    res = m.simulate(t_end=30 / f1, dt_out=1 / (32 * f1), rtol=1e-7, linear_solver="klu", integrator="ida")
    z = res.tip(leaf)[:, 2]
    assert 1e-6 < np.abs(z).max() < 1e-4
    f_fft = ph.analysis.dominant_frequency(res.t, z)
    assert abs(f_fft / f1 - 1) < 1e-3, (f_fft, f1)

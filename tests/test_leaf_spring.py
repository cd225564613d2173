"""Issue 5: the paper's leaf-spring mechanism (Sec. VIII-D), examples/leaf_spring.py in quick mode.

References computed here independently of the example and of phmech: the paper's formula
f = (1/pi) sqrt(6 E I_y / (m_R L^3)) for two guided-clamped leaves (stiffness 12 E I / L^3 each)
and its Rayleigh correction for the leaves' mass (13/35 of each leaf's mass)."""
import math
import os
import sys

import numpy as np
import pytest

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "examples"))
import leaf_spring as ls  # noqa: E402


def _references(p):
    I = p.width * p.thickness ** 3 / 12.0
    m_R = p.density * (p.plate_x * p.plate_y * p.plate_t + 2 * p.block ** 3)
    m_leaf = p.density * p.L * p.width * p.thickness
    k = 2 * 12 * p.E * I / p.L ** 3                         # two guided-clamped leaves [N/m]
    f_a = math.sqrt(k / m_R) / (2 * math.pi)
    f_c = math.sqrt(k / (m_R + 2 * 13 / 35 * m_leaf)) / (2 * math.pi)
    return f_a, f_c


def test_parameters_reproduce_the_paper_formula():
    p = ls.default_params()
    f_a, f_c = _references(p)
    assert f_a == pytest.approx(3.369, rel=1e-9)           # paper's 3.369 Hz by construction
    assert ls.f_analytic(p) == pytest.approx(f_a, rel=1e-12)
    assert ls.f_analytic_mass_corrected(p) == pytest.approx(f_c, rel=1e-12)
    # the exact continuous Euler-Bernoulli frequency lies just below the Rayleigh bound
    f_eb = ls.f_euler_bernoulli(p)
    assert f_eb <= f_c * (1 + 1e-12) and f_eb == pytest.approx(f_c, rel=1e-5)


def test_pulse_response_fft_modes_and_analytic():
    p = ls.default_params()
    f_a, f_c = _references(p)
    out = ls.run(p, t_end=5.0, elements=10)                 # quick: 5 s, FFT over 2..5 s
    # done-when targets: FFT within 0.5 % of the linearized frequency, which is within 1 % of
    # the analytic formula (N = 10 se3 elements per leaf: measured +0.37 %)
    assert abs(out["f_fft"] / out["f_modal"] - 1) < 5e-3, (out["f_fft"], out["f_modal"])
    assert abs(out["f_modal"] / f_a - 1) < 1e-2, (out["f_modal"], f_a)
    # the response is a ~1 mm oscillation of R1 in x (impulse 0.05 N s on m_R: v/omega)
    amp = 0.05 / p.m_R / (2 * math.pi * f_c)
    assert out["amplitude"] == pytest.approx(amp, rel=0.05)
    # the second mode is far above: the FFT peak is the x translation
    assert out["modes"][1] > 5 * out["modes"][0]


def test_mesh_refinement_approaches_the_mass_corrected_formula():
    # the se3 element converges at second order from above: N = 20 is closer to the
    # mass-corrected formula than N = 10, and both are above it
    p = ls.default_params()
    _, f_c = _references(p)
    f10, f20 = ls.f_modal(p, elements=10), ls.f_modal(p, elements=20)
    assert f_c < f20 < f10
    assert (f10 - f_c) / (f20 - f_c) > 3.0, (f10, f20, f_c)
    # Richardson extrapolation of the N^-2 error lands on the formula within 0.05 %
    assert abs((f20 + (f20 - f10) / 3) / f_c - 1) < 5e-4

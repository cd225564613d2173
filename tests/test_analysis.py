"""FFT helpers against synthetic signals of known frequency."""
import numpy as np
import pytest

import phmech as ph


@pytest.mark.parametrize("f0", [1.3274, 20.85, 47.0])
def test_dominant_frequency_of_a_damped_sinusoid(f0):
    t = np.arange(0, 40 / f0, 1 / (40 * f0))  # 40 periods, 40 samples per period
    x = 0.3 * np.exp(-0.01 * t * f0) * np.sin(2 * np.pi * f0 * t + 0.4) + 0.01 * np.sin(2 * np.pi * 3.7 * f0 * t)
    assert abs(ph.analysis.dominant_frequency(t, x) / f0 - 1) < 2e-4


def test_spectrum_amplitude_and_band():
    t = np.linspace(0, 10, 2001)
    x = 2.0 * np.sin(2 * np.pi * 5.0 * t) + 0.5 * np.sin(2 * np.pi * 17.0 * t)
    f, X = ph.analysis.spectrum(t, x)
    assert X[np.argmin(abs(f - 5.0))] == pytest.approx(2.0, rel=0.02)
    assert ph.analysis.dominant_frequency(t, x, fmin=10) == pytest.approx(17.0, rel=1e-3)


def test_bad_input():
    with pytest.raises(ValueError, match="uniformly"):
        ph.analysis.dominant_frequency([0, 1, 3, 4, 5, 6, 7, 8], np.ones(8))
    with pytest.raises(ValueError, match="same length"):
        ph.analysis.spectrum(np.arange(10.0), np.ones(9))
    with pytest.raises(ValueError, match="finite"):
        ph.analysis.spectrum(np.arange(10.0), np.r_[np.ones(9), np.nan])

"""Sizes from a band (phmech.mesh.choose_elements, Mechanism(band=...)): the chosen number of
elements keeps a link's modes in the band within the asked frequency tolerance, checked against
the exact Timoshenko frequencies of the paper's Table I cantilever, and is not wasteful: at most
1.5 times the smallest number of elements that meets the tolerance."""
import numpy as np
import pytest

import phmech as ph
from phmech import mesh, studies

BAND = 300.0 / (2 * np.pi)        # 300 rad/s [Hz]: Table I's first five cantilever modes
EXACT = studies.exact_frequencies(6)
IN_BAND = int(np.sum(EXACT <= 2 * np.pi * BAND))


def cantilever_error(N: int) -> float:
    """Largest relative error of the se3 cantilever's in-band modes against the exact ones."""
    try:
        f = studies.se3_frequencies(N, IN_BAND)
    except RuntimeError:          # too coarse: a low mode is not the x-z bending one
        return np.inf
    return float(np.max(np.abs(f / EXACT[:IN_BAND] - 1)))


@pytest.mark.parametrize("tolerance", [1e-2, 1e-3])
def test_the_choice_meets_the_tolerance_with_at_most_half_again_the_fewest_elements(tolerance):
    """Measured: 25 elements for 1e-2 (error 4.9e-3; the fewest that do: 18), 78 for 1e-3
    (5.0e-4; 56): ratios 1.39 and 1.39 (the free-free estimate is about twice the cantilever's
    error)."""
    assert IN_BAND == 5
    choice = mesh.choose_elements(1.0, ph.table1_properties(), BAND, tolerance)
    assert cantilever_error(choice.elements) <= tolerance
    fewest = next(N for N in range(2, 400) if cantilever_error(N) <= tolerance)
    assert choice.elements <= 1.5 * fewest
    assert choice.estimated_error <= tolerance and choice.modes_in_band == 4   # free-free modes


def test_the_mechanism_band_sizes_every_link_added_without_elements():
    m = ph.Mechanism(band=BAND, frequency_tolerance=1e-2)
    a = m.add_flexible_link("a", 1.0, ph.table1_properties())
    b = m.add_flexible_link("b", 1.0, ph.table1_properties(), elements=7)
    c = m.add_flexible_link("c", 0.5, ph.table1_properties())     # half as long: stiffer modes
    assert a.mesh is not None and a.elements == a.mesh.elements == 25
    assert b.mesh is None and b.elements == 7
    assert c.elements < a.elements and "modes up to" in str(c.mesh)
    assert ph.Mechanism().add_flexible_link("d", 1.0, ph.table1_properties()).elements == 10


def test_bad_bands_and_tolerances_are_refused():
    props = ph.table1_properties()
    with pytest.raises(ph.ModelError, match="band must be"):
        ph.Mechanism(band=0.0)
    with pytest.raises(ph.ModelError, match="frequency_tolerance"):
        ph.Mechanism(band=10.0, frequency_tolerance=0.0)
    with pytest.raises(ph.ModelError, match="not both"):
        ph.Mechanism().add_flexible_link("a", 1.0, props, elements=4, band=10.0)
    with pytest.raises(ph.ModelError, match="no mesh of at most 8 elements"):
        mesh.choose_elements(1.0, props, BAND, 1e-3, max_elements=8)
    with pytest.raises(ph.ModelError, match="band must be"):
        mesh.choose_elements(1.0, props, -1.0)

"""Each beam element's elastic strain energy over a simulation (``SimulationResult.strain_energy``,
computed by the core at each output: csrc/dae/output.c): it adds up to the elastic energy of the
energy ledger, splits it between the links in the order they were added, concentrates at a
clamped root in the first bending mode, and survives a result file."""
import numpy as np
import pytest

import phmech as ph
from phmech.section import table1_properties


def two_links():
    """A clamped flexible link (6 elements) with a second one (4 elements) welded to its tip,
    bent by gravity from straight: both store strain energy, the root element most."""
    m = ph.Mechanism(gravity=(0.0, 0.0, -9.81))
    props = table1_properties()
    a = m.add_flexible_link("a", 0.6, props, elements=6)
    b = m.add_flexible_link("b", 0.4, props, elements=4, start=a.end)
    m.add_pair("clamp", ph.Fixed(), m.ground, a.start)
    m.add_pair("weld", ph.Fixed(), a.end, b.start)
    return m


@pytest.fixture(scope="module")
def run():
    m = two_links()
    return m, m.simulate(0.05, 0.005, rtol=1e-6)


def test_the_elements_add_up_to_the_elastic_energy(run):
    m, r = run
    assert r.strain_energy.shape == (len(r.t), 10)
    assert np.all(r.strain_energy >= 0)
    np.testing.assert_allclose(r.strain_energy.sum(axis=1), r.energy["elastic"], rtol=1e-12,
                               atol=1e-300)
    assert r.energy["elastic"][-1] > 0   # gravity bent the links


def test_each_link_owns_its_elements_and_the_root_stores_most(run):
    m, r = run
    first = m._desc.first_element
    assert (first["a"], first["b"]) == (0, 6)
    a, b = r.strain_energy[-1, :6], r.strain_energy[-1, 6:]
    assert a.sum() > b.sum() > 0
    assert np.argmax(a) == 0   # the bending moment is largest at the clamp


def test_strain_energy_survives_a_file_and_a_recorded_subset(run, tmp_path):
    m, r = run
    r.to_netcdf(tmp_path / "links.nc")
    back = ph.load_result(tmp_path / "links.nc")
    np.testing.assert_array_equal(back.strain_energy, r.strain_energy)
    assert back.to_xarray()["strain_energy"].dims == ("time", "element")
    rec = m.simulate(0.05, 0.005, rtol=1e-6, record=["a"])
    np.testing.assert_array_equal(rec.strain_energy, r.strain_energy)

"""Each beam element's elastic strain energy over a simulation (``SimulationResult.strain_energy``,
computed by the core at each output: csrc/dae/output.c): it adds up to the elastic energy of the
energy ledger, splits it between the links in the order they were added, concentrates at a
clamped root in the first bending mode, and survives a result file. The ledger's elastic energy
comes from the same kernel (phm_element_energy, csrc/model/element.c), so the sum is checked
independently too: a cantilever under a static tip load against the Timoshenko beam's strain
energy with the element's closed-form discretization error."""
import numpy as np
import pytest

import phmech as ph
from phmech.section import TABLE1, table1_properties


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


def test_a_tip_loaded_cantilever_stores_the_timoshenko_strain_energy():
    # the Table I cantilever under a small static tip load P (P L^2 / EI = 1e-5: linear, the
    # geometric nonlinearity ~1e-10): U = P^2 L^3 / (6 EI) + P^2 L / (2 kGA), the shear term
    # 2.3 % of the bending one. The se3 element's curvature is constant per element: by Clapeyron
    # U_h = P w_h / 2 with w_h's closed-form error -P L^3 / (12 EI N^2) (tests/test_statics.py),
    # so U_h = U - P^2 L^3 / (24 EI N^2), relative -2.4e-3 at N = 10 and -6.1e-4 at N = 20 (the
    # shear term is 10 and 40 times that: dropped, this fails). Measured: U_h within 1.7e-11 of
    # U of that closed form at both meshes, at the output at t = 0 of a simulation from the
    # static equilibrium
    L, EI, kGA = TABLE1["L"], TABLE1["EI"], TABLE1["kGA"]
    P = 1e-5 * EI / L**2
    exact = P**2 * L**3 / (6 * EI) + P**2 * L / (2 * kGA)
    rel = {}
    for N in (10, 20):
        m = ph.Mechanism()
        b = m.add_flexible_link("b", L, table1_properties(1.0), elements=N)
        m.add_pair("clamp", ph.Fixed(), m.ground, b.start)
        m.add_wrench("tip", b.end, (0, 0, 0, 0, 0, P))
        st = m.static()
        U = m.simulate(1e-6, 1e-6, initial=st).strain_energy[0].sum()
        discretization = -P**2 * L**3 / (24 * EI * N**2)
        assert abs(U - (exact + discretization)) < 1e-9 * exact, (N, (U - exact - discretization) / exact)
        rel[N] = (U - exact) / exact
    # second order in the element length, within the bending part's 1 / (4 N^2)
    np.testing.assert_allclose(rel[10] / rel[20], 4.0, rtol=1e-6)
    assert all(-1 / (4 * N**2) < rel[N] < 0 for N in rel), rel

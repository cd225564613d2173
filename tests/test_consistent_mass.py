"""Consistent element mass (``add_flexible_link(mass="consistent")``, csrc/model/element.c,
docs/method.md section 4.2 "Mass"): the helix kinetic energy of each element blended half-way
with the lumped one, as a constant coupling of its nodes' body twists.

References: the exact Timoshenko frequencies (phmech.timoshenko, the frequency equation), an
impulse's momentum (F T), the conservation laws of a free body, and the energy ledger."""
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

import phmech as ph
from phmech import se3, studies
from phmech.section import table1_properties

sys.path.insert(0, str(Path(__file__).parent))
sys.path.insert(0, str(Path(__file__).parent.parent / "examples"))
from test_momentum import KICK_F, KICK_T, KICK_TAU, STRIP, drift   # noqa: E402
sys.path.insert(0, str(Path(__file__).parent / "accuracy"))
from test_flexible_link_inertia import (STIFF_STEEL, STRIP_T, STRIP_W,   # noqa: E402
                                        table1_cantilever)


def test_frequencies_converge_at_second_order_on_the_sparse_path_too():
    """N = 60 has 366 manifold coordinates: modes() takes the sparse shift-invert path, whose
    mass is the block-sparse one with the couplings. Second order from N = 21: the error falls
    towards (60/21)^2 = 8.2 (measured on mode 5: 0.0659 -> 0.0100 %, 6.6x; mode 1 0.0374 ->
    0.0046 %, 8.1x; modes 2-5 all fall)."""
    exact = studies.exact_frequencies(5)
    e21 = np.abs(table1_cantilever(21, "consistent")[0].modes(5).omega / exact - 1)
    e60 = np.abs(table1_cantilever(60, "consistent")[0].modes(5).omega / exact - 1)
    ratio = e21[4] / e60[4]
    assert 6.0 <= ratio <= 10.0
    assert np.all(e60[1:] < e21[1:])


def kicked_beam(mass):
    m = ph.Mechanism()
    H = se3.rotation("z", 0.3) @ se3.rotation("y", 0.2)
    beam = m.add_flexible_link("beam", 0.5, STRIP, elements=8, pose=H, mass=mass)
    m.add_wrench("kick", beam.end, (0, 0, 0, *KICK_F), law=ph.Pulse(t0=0.0, duration=KICK_T),
                 frame="world")
    m.add_wrench("twist", beam.start, (*KICK_TAU, 0, 0, 0), law=ph.Pulse(t0=0.0, duration=KICK_T),
                 frame="world")
    return m, beam


@pytest.mark.filterwarnings("ignore::phmech.UnattachedWarning")   # free on purpose
def test_a_free_beam_takes_the_impulse_and_conserves_momentum_and_energy():
    """IDA at rtol 1e-9 over the kick and 4 ms after: the linear momentum (with the couplings'
    share, SimulationResult.momentum) equals the impulse F T and then stays, the angular one
    about the origin stays, and the energy ledger closes (measured: 2.2e-14, 1.8e-14, 1.1e-14,
    ledger 1.6e-12 J of 0.042 J). Without the couplings' share the momentum would be off by
    the consistent mass's redistribution (checked: > 1e-3 of the impulse)."""
    m, beam = kicked_beam("consistent")
    r = m.simulate(0.006, 1e-3, integrator="ida", rtol=1e-9)
    after = r.t >= KICK_T - 1e-12
    P, L = (X[after] for X in r.momentum())
    assert drift(P[:1], KICK_T * KICK_F) <= 1e-10
    assert drift(P) <= 1e-10
    assert drift(L) <= 1e-10
    assert np.max(np.abs(r.energy["ledger"])) <= 1e-9 * r.energy["kinetic"][-1]
    lumped_share = r._couplings
    r._couplings = np.zeros_like(lumped_share)
    assert drift(r.momentum().linear[after][:1], KICK_T * KICK_F) >= 1e-3
    r._couplings = lumped_share


@pytest.mark.filterwarnings("ignore::phmech.UnattachedWarning")   # free on purpose
def test_with_the_default_integrator_momentum_is_conserved():
    """The defaults over 1 s (measured: P drift 8.7e-6, L about the origin 3.9e-6)."""
    m, beam = kicked_beam("consistent")
    r = m.simulate(1.0, 1e-3)
    after = r.t >= KICK_T - 1e-12
    P, L = (X[after] for X in r.momentum())
    assert drift(P[:1], KICK_T * KICK_F) <= 1e-6
    assert drift(P) <= 3e-5
    assert drift(L) <= 3e-5


def test_transient_converges_at_second_order():
    """A clamped Table I beam released straight under gravity oscillates about its sag; tip
    height over 0.1 s against lumped N = 80 (itself 9.6e-5 of the tip's range from lumped
    N = 160 with IDA at rtol 1e-9, measured). Measured: 5.70e-3 (N = 10) and 1.45e-3 (N = 20) of
    the range, ratio 3.9; lumped 5.35e-3 and 1.37e-3. Before the link's rigid-rotation coupling
    consistent mass was 3.15e-3 at N = 10: the coupling takes the blend's correction off the
    mean of the elements' velocity differences, which this first-mode response is mostly
    (docs/method.md section 4.2, "Mass": the first frequency +0.165 % at N = 10)."""
    def run(N, mass):
        m = ph.Mechanism(gravity=(0, 0, -9.81))
        link = m.add_flexible_link("beam", 1.0, table1_properties(), elements=N, mass=mass)
        m.add_pair("clamp", ph.Fixed(), m.ground, link.start)
        r = m.simulate(0.1, 1e-3)
        return r.poses[:, link.nodes[-1], 2, 3]
    ref = run(80, "lumped")
    scale = np.ptp(ref)
    e10 = np.max(np.abs(run(10, "consistent") - ref)) / scale
    e20 = np.max(np.abs(run(20, "consistent") - ref)) / scale
    assert e10 < 1e-2 and 3.0 < e10 / e20 < 5.0, (e10, e20)


def rigid_energies(props, L, N, t0):
    """(kinetic energy of the rigid twist t0 at the start of a straight link of N elements,
    carried to every node (node k at x = k L / N: t_k = Ad_(g_k^-1) t0), from its carriers and
    couplings (ModelDescription.mass_times); the same twist's energy in the rigid link,
    fidelity='rigid', the integral of the section inertia) [J]."""
    m = ph.Mechanism()
    lk = m.add_flexible_link("s", L, props, elements=N)
    rigid = ph.Mechanism()
    M_rigid = rigid._car[rigid.add_flexible_link("s", L, props, elements=N, fidelity="rigid").nodes[0]]["M"]
    v = np.zeros((len(m._car), 6))
    for k, c in enumerate(lk.nodes):
        v[c] = se3.Ad(se3.inverse(se3.translation([k * L / N, 0, 0]))) @ t0
    return 0.5 * np.sum(v * m._desc.mass_times(v)), 0.5 * t0 @ M_rigid @ t0


def test_the_links_mass_is_exact_for_every_rigid_motion():
    """Round-off patch test of the mass itself: for rigid twists of a straight 5-element link
    (a random body twist at its start carried to every node), the kinetic energy from its
    carriers and couplings (ModelDescription.mass_times) equals the rigid link's
    (fidelity='rigid', the integral of the section inertia) to 1e-12; a bending-like motion
    keeps a positive energy."""
    rng = np.random.default_rng(3)
    props = ph.BeamProperties.from_material(ph.Section.rectangle(STRIP_W, STRIP_T), STIFF_STEEL)
    for _ in range(5):
        T, T_rigid = rigid_energies(props, 0.3, 5, rng.standard_normal(6))
        assert T == pytest.approx(T_rigid, rel=1e-12)
    m = ph.Mechanism()
    lk = m.add_flexible_link("s", 0.3, props, elements=5)
    v = np.zeros((len(m._car), 6))
    v[lk.nodes, 5] = np.sin(np.linspace(0, 3, len(lk.nodes)))
    assert np.sum(v * m._desc.mass_times(v)) > 0


@pytest.mark.parametrize("N", [1, 2, 4])
def test_a_section_off_its_axis_keeps_the_mass_positive_definite_and_rigid_motions_exact(N):
    """A section whose centre of mass is 0.05 m off the axis (1 kg/m): the rigid-rotation
    coupling must keep its rotations' coupling to the transverse translations (a transverse
    block alone left the mass indefinite: ModelError at this offset, a negative eigenvalue of
    linearize's mass at 0.015 m). Checked: the model builds, the linearized mass is positive
    definite, and a rigid twist's kinetic energy is the rigid link's to 1e-12."""
    c = 0.05
    I = np.diag([2e-4 + c**2, 1e-4, 1e-4 + c**2, 1.0, 1.0, 1.0])
    I[:3, 3:] = se3.hat([0.0, c, 0.0])          # M = [[J - m hat(c)^2, m hat(c)], [m hat(c)^T, m]]
    I[3:, :3] = I[:3, 3:].T
    props = ph.BeamProperties(np.diag([10.0, 20.0, 20.0, 1e4, 1e4, 1e4]), I)
    m = ph.Mechanism()
    lk = m.add_flexible_link("s", 1.0, props, elements=N)
    m.add_pair("float", ph.Free(), m.ground, lk.start)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        M = m.linearize().mass
    assert np.linalg.eigvalsh(M).min() > 0
    T, T_rigid = rigid_energies(props, 1.0, N, np.array([0.3, -0.7, 1.1, 0.2, 0.5, -0.4]))
    assert T == pytest.approx(T_rigid, rel=1e-12)


def test_save_and_load_keep_the_mass_model(tmp_path):
    m, _ = table1_cantilever(6, "consistent")
    m.save(tmp_path / "m.json")
    m2 = ph.load(tmp_path / "m.json")
    np.testing.assert_array_equal(m.modes(3).omega, m2.modes(3).omega)


@pytest.mark.filterwarnings("ignore::phmech.UnattachedWarning")   # free on purpose
def test_a_result_file_keeps_the_couplings_for_momentum(tmp_path):
    m, beam = kicked_beam("consistent")
    r = m.simulate(0.004, 1e-3)
    r.to_netcdf(tmp_path / "r.nc")
    back = ph.load_result(tmp_path / "r.nc")
    np.testing.assert_array_equal(back._couplings, r._couplings)
    np.testing.assert_array_equal(back.momentum().linear, r.momentum().linear)


def test_an_unknown_mass_model_is_refused():
    m = ph.Mechanism()
    with pytest.raises(ph.ModelError, match="unknown mass 'cosistent'"):
        m.add_flexible_link("beam", 1.0, table1_properties(), elements=4, mass="cosistent")


def test_the_manipulator_with_consistent_links_starts_with_the_defaults():
    """The Fig. 3 manipulator (examples/manipulator.py) starts with joint torques on light nodes
    (initial accelerations up to 4.5e8 rad/s^2 with consistent masses). Its first step failed
    at every size down to 1e-7 s ("Newton failed at t = 0"): SUNDIALS's KLU refactored the
    backward-Euler retry's matrix on the pivot order of the first matrix and hit a zero pivot;
    the generalized-alpha now refactors afresh once (csrc/integrate/galpha.c). Measured: 0.05 s in
    173 steps."""
    import manipulator as M
    orig = ph.Mechanism.add_flexible_link

    def consistent(self, *a, **k):
        return orig(self, *a, **{**k, "mass": "consistent"})
    ph.Mechanism.add_flexible_link = consistent
    try:
        m, h = M.build(M.ManipulatorParams())
    finally:
        ph.Mechanism.add_flexible_link = orig
    assert all(e["mass"] == "consistent" for e in m._desc.elements)
    r = m.simulate(0.05, 2e-3)
    assert r.t[-1] == pytest.approx(0.05)
    assert np.all(np.isfinite(r.poses))


def test_mode_energies_use_the_coupled_mass():
    """The modes are mass-normalized with the coupled mass; their kinetic shares (analysis.
    mode_energies, which elastic_fraction and the labels read) sum to 1 with it (they were
    1.007-1.020 with the carriers' blocks alone at N = 6, per the review)."""
    m, _ = table1_cantilever(6, "consistent")
    md = m.modes(5)
    e = ph.analysis.mode_energies(m._desc, md.poses if md.poses is not None else
                                  np.array([c["H0"] for c in m._car]), md.shapes)
    np.testing.assert_allclose(e["kinetic"].sum(axis=1), 1.0, rtol=1e-9)

"""Modal links (``add_flexible_link(fidelity="modal")``, phmech._reduction.static_reduction): a
flexible link statically reduced (Guyan) onto its two ends, kept as one se3 element with the
condensed stiffness, damping and mass.

References: the full se3 link it was reduced from (its statics and the leaf spring's first
frequency), the converged leaf-spring frequency of docs/perf_leaf_spring.md (f_ref), an impulse's
momentum and the conservation laws of a free body, the energy ledger."""
import sys
from pathlib import Path

import numpy as np
import pytest

import phmech as ph
from phmech import se3
from phmech.section import table1_properties

sys.path.insert(0, str(Path(__file__).parent.parent / "examples"))
import leaf_spring as LS  # noqa: E402

F_REF = 3.3645021   # Hz, the leaf spring's converged first frequency (docs/perf_leaf_spring.md)


def test_leaf_spring_with_modal_leaves_has_the_full_leaves_frequency():
    """Each leaf reduced from 16 elements: the first frequency equals the 16-element nonlinear
    leaves' (measured 9.6e-8 relative: the static shapes carry the leaves' inertia); reduced
    from 64 elements it is within 0.1 % of the converged f_ref (measured 1.24e-4)."""
    p = LS.default_params()
    full = LS.build(p, elements=16, beta=0.0)[0].modes(1).frequency[0]
    modal = LS.build(p, elements=16, beta=0.0, fidelity="modal")[0].modes(1).frequency[0]
    assert abs(modal / full - 1) <= 1e-6
    fine = LS.build(p, elements=64, beta=0.0, fidelity="modal")[0].modes(1).frequency[0]
    assert abs(fine / F_REF - 1) <= 1e-3


def test_leaf_spring_transient_with_modal_leaves_rings_at_f_ref():
    """10 s of the pulse response (examples/leaf_spring.py's pulse, beta = 1e-5) with the
    integrator's band at 10 Hz: the FFT frequency of the stage's x after 2 s is within 0.1 % of
    f_ref (measured -2.7e-5, in 0.13 s of CPU) and the energy ledger closes to 3e-4 of the
    energy held and exchanged (measured 1.0e-4; the same residual read 3.3e-5 of the former
    energy scale, a sum three times larger, against a bound of 1e-4: the bound in joules is
    unchanged)."""
    p = LS.default_params()
    m, h = LS.build(p, elements=64, beta=1e-5, fidelity="modal",
                    pulse=ph.Pulse(t0=0.1, duration=0.01, value=5.0))
    r = m.simulate(10.0, 2e-3, band=10.0)
    x = r.poses[:, h["R1"].carrier, 0, 3]
    sel = r.t >= 2.0
    f = ph.analysis.dominant_frequency(r.t[sel], x[sel] - x[0], fmin=1.0, fmax=10.0)
    assert abs(f / F_REF - 1) <= 1e-3
    assert r.stats["ledger_relative"] <= 3e-4


def cantilever(fidelity, load):
    m = ph.Mechanism()
    lk = m.add_flexible_link("b", 1.0, table1_properties(), elements=20, fidelity=fidelity,
                             pose=se3.rotation("z", 0.4))
    m.add_pair("clamp", ph.Fixed(), m.ground, lk.start)
    st = m.static(loads=[(lk.end, (0, 0, 0, 0, 0, -load), "world")])
    return (st.poses[lk.end.carrier] @ lk.end.T)[:3, 3], lk


def test_a_modal_cantilever_has_the_full_links_linear_statics():
    """The static modes are exact for loads at the interfaces: the tip under a small force
    equals the 20-element nonlinear link's to 2.5e-8 of the deflection (measured at 0.01 N;
    10 N gives 2.5e-5: the nonlinear link's geometric terms, second order in the load)."""
    full, _ = cantilever("nonlinear", 0.01)
    modal, lk = cantilever("modal", 0.01)
    rest = np.array([np.cos(0.4), np.sin(0.4), 0.0])
    deflection = np.linalg.norm(full - rest)
    assert np.linalg.norm(modal - full) <= 1e-6 * deflection
    assert lk.elements == 1 and lk.reduced_from == 20 and len(lk.carriers) == 2


def kicked_modal_strip():
    """A 0.5 m steel strip (reduced from 8 elements), free in space, kicked at its end by a 2 ms
    force pulse and at its start by a torque pulse: it drifts, tumbles and vibrates (elastic
    energy a third of the kinetic)."""
    strip = ph.BeamProperties.from_material(ph.Section.rectangle(0.02, 0.002),
                                            ph.Material(E=210e9, nu=0.3, density=7850.0))
    m = ph.Mechanism()
    lk = m.add_flexible_link("s", 0.5, strip, elements=8, fidelity="modal",
                             pose=se3.rotation("z", 0.3) @ se3.rotation("y", 0.2))
    m.add_wrench("kick", lk.end, (0, 0, 0, *KICK_F), law=ph.Pulse(t0=0.0, duration=KICK_T))
    m.add_wrench("twist", lk.start, (0.02, 0, 0, 0, 0, 0), law=ph.Pulse(t0=0.0, duration=KICK_T))
    return m


KICK_F, KICK_T = np.array([3.0, 25.0, 10.0]), 2e-3


@pytest.mark.filterwarnings("ignore::phmech.UnattachedWarning")   # free on purpose
def test_a_free_modal_link_takes_an_impulse_and_conserves_momentum():
    """IDA at rtol 1e-10: after the kick the linear momentum (the coupling's share included) is
    the impulse and the angular momentum stays, to 1e-10 (measured 1.3e-11 and 3.3e-12; the
    link reduced from consistent mass, the default). What is left is the integrator's: at rtol
    1e-9 1.4e-10 and 1.1e-10, at 1e-11 1.6e-12 and 1.1e-12 (reduced from lumped mass: below
    1e-12 at rtol 1e-9)."""
    def errors(rtol):
        r = kicked_modal_strip().simulate(0.02, 1e-3, integrator="ida", rtol=rtol)
        after = r.t >= KICK_T - 1e-12
        P, L = (X[after] for X in r.momentum())
        return (np.max(np.linalg.norm(P - KICK_F * KICK_T, axis=1)) / np.linalg.norm(KICK_F * KICK_T),
                np.max(np.linalg.norm(L - L[0], axis=1)) / np.linalg.norm(L[0]))
    fine = errors(1e-10)
    assert max(fine) <= 1e-10
    assert errors(1e-9)[0] >= 3 * fine[0]                 # it falls with the tolerance


@pytest.mark.filterwarnings("ignore::phmech.UnattachedWarning")   # free on purpose
def test_a_free_modal_link_conserves_energy_as_the_step_shrinks():
    """Its energy balance is exact in the model: the ledger of the generalized-alpha without
    numerical dissipation (rho_inf = 1) over 6 ms falls with the fixed step, 5.6e-10, 1.7e-11,
    1.5e-13 J (of 0.050 J) at 4e-6, 4e-7, 1e-7 s (measured, reduced from consistent mass; from
    lumped 5.3e-10 and 2.5e-12 J at the first two); at 4e-8 s the round-off of 150 000 steps
    brings it back to 6.8e-12 J. Asserted: at least second order from 4e-7 to 1e-7 s (16x;
    measured 116x), and below 1e-10 of the energy."""
    led = []
    for h in (4e-7, 1e-7):
        r = kicked_modal_strip().simulate(0.006, 1e-3, step=h, rho_inf=1.0)
        led.append(np.max(np.abs(r.energy["ledger"])))
    E = r.energy["kinetic"][-1] + r.energy["elastic"][-1]
    assert led[1] <= led[0] / 16
    assert led[1] <= 1e-10 * E


def test_save_and_load_keep_a_modal_link(tmp_path):
    m = LS.build(LS.default_params(), elements=8, fidelity="modal")[0]
    m.save(tmp_path / "m.json")
    np.testing.assert_array_equal(m.modes(2).omega, ph.load(tmp_path / "m.json").modes(2).omega)


def gravity_sag(fidelity, curvature=None):
    m = ph.Mechanism(gravity=(0, 0, -9.81e-3))
    lk = m.add_flexible_link("b", 1.0, table1_properties(), elements=16, fidelity=fidelity,
                             curvature=curvature, pose=se3.rotation("x", 0.3))
    m.add_pair("clamp", ph.Fixed(), m.ground, lk.start)
    st = m.static()
    return (st.poses[lk.end.carrier] @ lk.end.T)[:3, 3] - m.world_pose(lk.end)[:3, 3]


def test_a_straight_modal_links_weight_is_the_condensed_weight_of_its_chain():
    """Gravity acts on two point masses whose weights and end moments are the chain's weight
    condensed (for a straight uniform link: half the mass each, at L/6 from the ends, the
    consistent load's w L^2 / 12): the sag of a clamped Table I link equals the 16-element
    nonlinear link's to 1.1e-5 (measured: the nonlinear link's second-order terms)."""
    full, modal = gravity_sag("nonlinear"), gravity_sag("modal")
    assert np.linalg.norm(modal - full) <= 1e-4 * np.linalg.norm(full)


def test_a_curved_modal_link_under_gravity_warns():
    """A curved link's condensed end moments are not those of any point: its sag is off (6.2 %
    at 1 rad of arc, measured) and phmech says so."""
    with pytest.warns(ph.AccuracyWarning, match="modal link 'b' under gravity: two point masses"):
        gravity_sag("modal", curvature=(0, 0, 1.0))


def test_what_a_modal_link_cannot_do_is_refused():
    m = ph.Mechanism()
    lk = m.add_flexible_link("b", 1.0, table1_properties(), elements=6, fidelity="modal")
    m.add_pair("clamp", ph.Fixed(), m.ground, lk.start)
    with pytest.raises(ph.ModelError, match="its frames are its interfaces"):
        lk.node(3)
    with pytest.raises(ph.ModelError, match="is modal"):
        m.add_distributed_load("q", lk, (0, 0, -1.0))
    r = m.simulate(0.01, 1e-3)
    with pytest.raises(ph.ModelError, match="is modal"):
        m.stress_resultants(r, lk)


def kane_spin_up(fidelity, t_end=10.0):
    """Kane, Ryan & Banerjee's spin-up beam (J. Guid. Control Dyn. 10 (1987)): a 10 m beam
    (rhoA 1.2 kg/m, EI 14 000 N m^2, EA 2.8e7 N) clamped to a hub driven from rest to 6 rad/s in
    15 s along omega(t) = (6/15) (t - (15 / 2 pi) sin(2 pi t / 15)): faster than its first
    frequency held at the hub, 3.80 rad/s. Returns the tip's in-plane deflection in the hub's
    frame at the outputs, and the AccuracyWarnings of the run."""
    import warnings
    TS, WS = 15.0, 6.0
    th = lambda t: WS / TS * (t * t / 2 + (TS / (2 * np.pi)) ** 2 * (np.cos(2 * np.pi * t / TS) - 1))
    om = lambda t: WS / TS * (t - TS / (2 * np.pi) * np.sin(2 * np.pi * t / TS))
    al = lambda t: WS / TS * (1 - np.cos(2 * np.pi * t / TS))
    props = ph.BeamProperties.from_values(EA=2.8e7, GA_y=1e9, GA_z=1e9, GJ=1e4, EI_y=1.4e4,
                                          EI_z=1.4e4, rhoA=1.2, rhoI_y=1e-6, rhoI_z=1e-6,
                                          rhoJ=2e-6)
    m = ph.Mechanism()
    hub = m.add_rigid_body("hub", 1.0, 0.1 * np.eye(3))
    m.add_pair("spin", ph.Revolute("z"), m.ground, hub.frame, driven=ph.Function(th, om, al))
    lk = m.add_flexible_link("beam", 10.0, props, elements=8, fidelity=fidelity, start=hub.frame)
    m.add_pair("clamp", ph.Fixed(), hub.frame, lk.start)
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        r = m.simulate(t_end, 0.05, band=5.0)
    Hh, He = r.poses[:, hub.carrier], r.poses[:, lk.end.carrier] @ lk.end.T
    tip = np.einsum("nji,nj->ni", Hh[:, :3, :3], He[:, :3, 3] - Hh[:, :3, 3])
    return r.t, tip[:, 1], [str(x.message) for x in w if issubclass(x.category, ph.AccuracyWarning)]


def test_a_spin_up_shows_the_modal_links_error_and_phmech_warns():
    """Kane's spin-up: the modal beam lacks centrifugal stiffening; at 10 s its tip lags by
    more than the nonlinear beam's (measured with 8 elements: -0.560 against -0.361 m; lumped
    mass: -0.562 against -0.364 m), and simulate warns that it spins faster (4.83 rad/s at
    10 s) than its first frequency held at the hub (3.81 rad/s with 8 elements, the exact
    3.80; lumped mass 3.77; 3.80 before the link's rigid-rotation coupling, docs/method.md
    section 4.2) and deflects beyond its linear range. The nonlinear beam gets neither
    warning."""
    t, y_modal, w_modal = kane_spin_up("modal")
    _, y_full, w_full = kane_spin_up("nonlinear")
    i = np.searchsorted(t, 10.0)
    assert abs(y_modal[i] - y_full[i]) >= 0.25 * abs(y_full[i])
    assert any("spins at up to 4.8" in m and "first frequency held at its start (3.81 rad/s" in m
               for m in w_modal)
    assert any("deflects by up to" in m for m in w_modal)
    assert not any("modal link" in m for m in w_full)


def test_a_modal_links_centre_of_mass_is_the_links():
    """At rest a curved modal link's centre of mass (its two gravity points, constrained to it)
    is that of the weights of the chain it was reduced from, which gravity pulls with either
    element mass: the lumped nonlinear link's, to round-off; and its mass the link's. A
    consistent nonlinear link's centre of mass lies along its elements' fields, here arcs: the
    exact arc integral of the rigid link (measured 3e-16 m). The chain's weights differ from it
    by their lumped quadrature: 2.2e-3 m at 8 elements over 2 rad, measured."""
    props = table1_properties()
    out = {}
    for fid, mass in (("modal", "consistent"), ("modal", "lumped"), ("nonlinear", "lumped"),
                      ("nonlinear", "consistent"), ("rigid", "consistent")):
        m = ph.Mechanism()
        lk = m.add_flexible_link("c", 1.0, props, elements=8, fidelity=fid, curvature=(0, 0, 2.0),
                                 mass=mass)
        m.add_pair("float", ph.Free(), m.ground, lk.start)   # it flies freely, and says so
        r = m.simulate(0.002, 1e-3)
        out[fid, mass] = (r.centre_of_mass()[0], r.mass())
    for mass in ("consistent", "lumped"):
        np.testing.assert_allclose(out["modal", mass][0], out["nonlinear", "lumped"][0], rtol=0,
                                   atol=1e-11)
        assert out["modal", mass][1] == pytest.approx(out["rigid", "consistent"][1], rel=1e-10)
    np.testing.assert_allclose(out["nonlinear", "consistent"][0], out["rigid", "consistent"][0],
                               rtol=0, atol=1e-12)
    assert np.linalg.norm(out["modal", "consistent"][0] - out["rigid", "consistent"][0]) <= 3e-3


def test_a_modal_link_without_modes_and_with_its_own_modes_in_the_band_warns():
    """A free Table I link sized for a 30 Hz band has two of its own modes in it (7.85 and
    18.9 Hz with the nonlinear link): a modal link told to keep no fixed-interface mode drops
    them, and says so (the band alone chooses modes: tests/test_modal_modes.py)."""
    m = ph.Mechanism(band=30.0)
    with pytest.warns(ph.AccuracyWarning, match="has 2 of its own .* modes in the band 30 Hz"):
        lk = m.add_flexible_link("b", 1.0, table1_properties(), fidelity="modal", modes=0)
    assert lk.mesh is None and lk.reduced_from > 1


@pytest.mark.filterwarnings("ignore::phmech.UnattachedWarning")   # free on purpose
def test_a_result_file_keeps_the_modal_link(tmp_path):
    m = kicked_modal_strip()
    r = m.simulate(0.004, 1e-3)
    r.to_netcdf(tmp_path / "r.nc")
    back = ph.load_result(tmp_path / "r.nc")
    lk = m._links["s"]
    np.testing.assert_array_equal(back.positions(lk), r.positions(lk))
    np.testing.assert_array_equal(back.momentum(lk).linear, r.momentum(lk).linear)


@pytest.mark.filterwarnings("ignore::phmech.UnattachedWarning")   # free on purpose
def test_a_modal_link_reduced_from_a_consistent_chain_conserves_momentum():
    strip = ph.BeamProperties.from_material(ph.Section.rectangle(0.02, 0.002),
                                            ph.Material(E=210e9, nu=0.3, density=7850.0))
    m = ph.Mechanism()
    lk = m.add_flexible_link("s", 0.5, strip, elements=8, fidelity="modal", mass="consistent")
    m.add_wrench("kick", lk.end, (0, 0, 0, *KICK_F), law=ph.Pulse(t0=0.0, duration=KICK_T))
    r = m.simulate(0.01, 1e-3, integrator="ida", rtol=1e-9)
    P = r.momentum().linear[r.t >= KICK_T - 1e-12]
    assert np.max(np.linalg.norm(P - KICK_F * KICK_T, axis=1)) <= 1e-9 * np.linalg.norm(KICK_F * KICK_T)


def test_spin_about_a_modal_links_own_axis_is_not_warned():
    """Spin about the link's own axis does not stiffen its bending: a modal shaft turned about
    its axis at 40 rad/s, almost five times its first frequency held at the hub (8.3 rad/s),
    gets no spin warning (it did when the whole angular velocity was counted)."""
    import warnings
    m = ph.Mechanism()
    hub = m.add_rigid_body("hub", 1.0, 0.1 * np.eye(3))
    m.add_pair("spin", ph.Revolute("x"), m.ground, hub.frame, driven=ph.Linear(40.0))
    lk = m.add_flexible_link("shaft", 1.0, table1_properties(), elements=8, fidelity="modal",
                             start=hub.frame)
    m.add_pair("clamp", ph.Fixed(), hub.frame, lk.start)
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        m.simulate(0.2, 1e-2)
    assert not any("spins at" in str(x.message) for x in w)

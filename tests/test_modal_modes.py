"""Modal links with fixed-interface modes (``add_flexible_link(fidelity="modal", modes=...)``,
phmech.fidelity.modal_sliders; docs/method.md section 4.10): the static shapes plus the chain's
modes with both ends held (Craig-Bampton), each mode a slider on the link's start.

References: the full se3 link each modal link is reduced from (its modes and its centre of mass
under gravity), conservation laws of a free body, the energy ledger."""
import warnings

import numpy as np
import pytest

import phmech as ph
from phmech import se3
from phmech.section import table1_properties


def cantilever(fidelity, elements=20, gravity=(0.0, 0.0, 0.0), **kw):
    m = ph.Mechanism(gravity=gravity)
    lk = m.add_flexible_link("b", 1.0, table1_properties(), elements=elements, fidelity=fidelity,
                             pose=se3.rotation("z", 0.4), **kw)
    m.add_pair("clamp", ph.Fixed(), m.ground, lk.start)
    return m, lk


def test_a_modal_cantilever_has_the_five_frequencies_of_the_link_it_was_reduced_from():
    """Table I link of 20 elements (114 interior degrees of freedom), clamped at its start: the
    first five frequencies of the modal link with 40 fixed-interface modes equal the full link's
    to 1e-8 (measured 8e-11 to 2e-10 between runs of the eigensolver); without modes (Guyan)
    the first is 0.69 % off and the fifth 27x, and the error falls as modes are added (Ritz: 5
    modes 8.8e-3, 20 modes 2.3e-4 on the fifth)."""
    full = cantilever("nonlinear")[0].modes(5).frequency
    worst = []
    for n in (0, 5, 20, 40):
        f = cantilever("modal", modes=n)[0].modes(5).frequency
        worst.append(np.max(np.abs(f / full - 1.0)))
        assert np.all(f >= full * (1 - 1e-9))   # a Ritz reduction never undershoots
    assert worst[-1] <= 1e-8
    assert worst[0] > 1.0 and all(b < a for a, b in zip(worst, worst[1:]))


def test_the_band_chooses_the_modes_and_keeps_the_chains_frequencies_in_it():
    """A free Table I link sized for a 30 Hz band (free-free modes at 7.8 and 18.9 Hz): the band
    chooses its fixed-interface modes, link.modal_choice says how many and the error, and the
    free modal link's frequencies below 30 Hz are the full link's within the tolerance 1e-3
    (measured: 9 modes of a 57-element chain, error 8.3e-4)."""
    m = ph.Mechanism(band=30.0)
    lk = m.add_flexible_link("b", 1.0, table1_properties(), fidelity="modal")
    m.add_pair("float", ph.Free(), m.ground, lk.start)   # free: a Free pair holds nothing
    ch = lk.modal_choice
    assert ch.chosen and ch.modes >= 1 and ch.error <= 1e-3 and ch.band == 30.0
    assert len(lk.sliders) == ch.modes
    full = ph.Mechanism()
    f = full.add_flexible_link("b", 1.0, table1_properties(), elements=lk.reduced_from)
    full.add_pair("float", ph.Free(), full.ground, f.start)
    f_full = full.modes(10).frequency
    f_full = f_full[(f_full > 1e-3) & (f_full <= 30.0)]
    f_mod = m.modes(10).frequency
    f_mod = f_mod[f_mod > 1e-3][:len(f_full)]
    assert len(f_full) == 2        # the in-plane bending modes (the other plane is stiffer)
    assert np.max(np.abs(f_mod / f_full - 1.0)) <= 1e-3


def test_modes_are_checked():
    """modes: an integer from 0 to the chain's interior degrees of freedom, on modal links."""
    m = ph.Mechanism()
    p = table1_properties()
    with pytest.raises(ph.ModelError, match="at most 24 fixed-interface modes"):
        m.add_flexible_link("a", 1.0, p, elements=5, fidelity="modal", modes=25)
    with pytest.raises(ph.ModelError, match="modes must be an integer >= 0"):
        m.add_flexible_link("b", 1.0, p, elements=5, fidelity="modal", modes=-1)
    with pytest.raises(ph.ModelError, match="modes= is for fidelity='modal' links"):
        m.add_flexible_link("c", 1.0, p, elements=5, modes=3)
    with pytest.raises(ph.ModelError, match="give elements= or band=, not both"):
        m.add_flexible_link("d", 1.0, p, elements=5, band=10.0)
    lk = m.add_flexible_link("e", 1.0, p, elements=5, fidelity="modal", modes=24)
    assert len(lk.sliders) == 24 and lk.modal_choice is None


def strip(**kw):
    return ph.BeamProperties.from_material(ph.Section.rectangle(0.02, 0.002),
                                           ph.Material(E=210e9, nu=0.3, density=7850.0), **kw)


KICK_F, KICK_T = np.array([3.0, 25.0, 10.0]), 2e-3


def kicked(modes=4):
    """A free 0.5 m steel strip reduced from 8 elements with its first fixed-interface modes,
    kicked at its end by a 2 ms force pulse and at its start by a torque pulse."""
    m = ph.Mechanism()
    lk = m.add_flexible_link("s", 0.5, strip(), elements=8, fidelity="modal", modes=modes,
                             pose=se3.rotation("z", 0.3) @ se3.rotation("y", 0.2))
    m.add_wrench("kick", lk.end, (0, 0, 0, *KICK_F), law=ph.Pulse(t0=0.0, duration=KICK_T))
    m.add_wrench("twist", lk.start, (0.02, 0, 0, 0, 0, 0), law=ph.Pulse(t0=0.0, duration=KICK_T))
    return m, lk


@pytest.mark.filterwarnings("ignore::phmech.UnattachedWarning")   # free on purpose
def test_a_free_modal_link_with_modes_conserves_momentum_and_energy():
    """IDA at rtol 1e-9: after the kick the linear momentum (sliders and couplings included) is
    the impulse and the angular momentum stays, to 2e-10 (measured 5.6e-11 and 3.2e-11: the
    IDA tolerance, the sliders' states in its error test); its modes are excited, and the
    ledger closes to 1e-7 of the energy (measured 8.9e-9)."""
    m, lk = kicked()
    r = m.simulate(0.02, 1e-3, integrator="ida", rtol=1e-9)
    after = r.t >= KICK_T - 1e-12
    P, L = (X[after] for X in r.momentum())
    assert np.max(np.linalg.norm(P - KICK_F * KICK_T, axis=1)) <= 2e-10 * np.linalg.norm(KICK_F * KICK_T)
    assert np.max(np.linalg.norm(L - L[0], axis=1)) <= 2e-10 * np.linalg.norm(L[0])
    E = r.energy["kinetic"][-1] + r.energy["elastic"][-1]
    assert np.max(np.abs(r.energy["ledger"])) <= 1e-7 * E
    # the modes hold a share of the link's strain energy: 1/2 k s^2 in their sliders' springs
    k = {q["name"]: q["kcd"][0] for q in m._desc.springs}
    U = sum(0.5 * k[f"s.mode{j + 1}.spring"] * r.joint(f"s.mode{j + 1}")["x"][:, 0] ** 2
            for j in range(4))
    assert np.max(U / np.maximum(r.energy["elastic"], 1e-300)) > 1e-3


def test_a_damped_modal_cantilever_under_a_load_closes_its_power_balance():
    """Section damping D = 1e-4 K (its modes keep their own damping exactly), a sine force at
    the tip, 8 fixed-interface modes: the supplied work equals the change of energy plus the
    dissipated energy to 1e-6 of the supplied work with IDA at rtol 1e-8 (measured 9.7e-8; with the
    defaults 1.7e-6), and the dissipation is positive (14 % of the supplied work)."""
    p = strip()
    p = ph.BeamProperties(p.stiffness, p.inertia, 1e-4 * p.stiffness)
    m = ph.Mechanism()
    lk = m.add_flexible_link("s", 0.5, p, elements=12, fidelity="modal", modes=8)
    m.add_pair("clamp", ph.Fixed(), m.ground, lk.start)
    m.add_wrench("shake", lk.end, (0, 0, 0, 0, 0, 1.0), law=ph.Sine(frequency=20.0, amplitude=1.0))
    r = m.simulate(0.5, 1e-3, integrator="ida", rtol=1e-8)
    e = r.energy
    supplied = np.max(np.abs(e["supplied"]))
    assert e["dissipated"][-1] > 0
    assert np.max(np.abs(e["ledger"])) <= 1e-6 * supplied


def test_the_modes_carry_the_links_weight_inside():
    """A clamped Table I link under a weak gravity (linear): the centre of mass of the modal link
    sags as the full link's when its modes are kept (1e-6 with 20 modes; measured 4.2e-8; 5
    modes 1.2e-5), where the static shapes alone miss the interior's sag (measured 3.8 % off).
    Gravity acts on the chain's node weights with either element mass, so the equilibrium is
    the same, and the modal link's two gravity points carry those weights: the full link's
    centre of mass compared is theirs (mass="lumped"; a consistent link's centre_of_mass lies
    along its elements' fields, tests/test_momentum.py)."""
    g = (0.0, 0.0, -9.81e-3)

    def com_sag(fidelity, **kw):
        """z of the link's centre of mass at equilibrium (it starts in the plane z = 0)."""
        m, lk = cantilever(fidelity, elements=16, gravity=g, **kw)
        r = m.simulate(1e-4, 1e-4, initial=m.static())
        return float(r.centre_of_mass(lk)[0, 2])

    full = com_sag("nonlinear", mass="lumped")
    assert abs(com_sag("modal", modes=0) / full - 1.0) > 0.02
    assert abs(com_sag("modal", modes=20) / full - 1.0) <= 1e-6


def test_manipulator_with_a_modal_link_with_modes():
    """The Fig. 3 manipulator (examples/manipulator.py) with F1 modal, two fixed-interface modes,
    and F2, F3 nonlinear: the graphs keep F1 as its edge (its sliders inside), the arm reaches its
    set point (k1 0.044 rad off at 1.2 s, as with F1 nonlinear; tolerance 0.1 of the 0.5 rad
    step), the energy ledger closes to 1e-3 of its scale (tests/test_scenes.py's bound; measured
    9.0e-5), k1 at 1.2 s is the all-nonlinear arm's within 1e-4 rad (measured 1.6e-7), and
    simulate warns that F1 deflects beyond a modal link's linear range (0.155 rad)."""
    import sys
    from pathlib import Path
    sys.path.insert(0, str(Path(__file__).parent.parent / "examples"))
    import manipulator as M
    p = M.ManipulatorParams()
    m, h = M.build(p, elements=4, fidelity={"F1": {"fidelity": "modal", "modes": 2}})
    assert len(h["F1"].sliders) == 2
    g = m.graphs()
    assert g.B_K.rigid_rows == ("R1", "R2", "R3")
    assert g.B_K.flexible_rows == ("F1L", "F1R", "F2L", "F2R", "F3L", "F3R")
    with pytest.warns(ph.AccuracyWarning, match="modal link 'F1' deflects"):
        res = m.simulate(1.2, 2e-3)
    assert res.stats["ledger_relative"] <= 1e-3
    assert abs(res.joint("k1")["x"][-1, 0] - p.target[0]) < 0.1
    full = M.build(p, elements=4)[0].simulate(1.2, 2e-3)
    assert abs(res.joint("k1")["x"][-1, 0] - full.joint("k1")["x"][-1, 0]) <= 1e-4


@pytest.mark.filterwarnings("ignore::phmech.UnattachedWarning")   # free on purpose
def test_a_result_file_keeps_the_modal_links_modes(tmp_path):
    """The sliders travel with a result file: the link's momentum and its modes' amplitudes read
    back equal, and the link (with its modal choice) compares equal."""
    m, lk = kicked(modes=3)
    with pytest.warns(ph.AccuracyWarning, match="modal link 's' (spins|deflects)"):
        r = m.simulate(0.004, 1e-3)
    r.to_netcdf(tmp_path / "r.nc")
    back = ph.load_result(tmp_path / "r.nc")
    assert back._links["s"] == lk and back._links["s"].sliders == lk.sliders
    np.testing.assert_array_equal(back.momentum(lk).linear, r.momentum(lk).linear)
    np.testing.assert_array_equal(back.joint("s.mode2")["x"], r.joint("s.mode2")["x"])


@pytest.mark.filterwarnings("ignore::phmech.UnattachedWarning")   # free on purpose
def test_a_modal_link_warns_when_its_modes_leave_their_linear_range():
    """A free strip whose two ends are kicked alike (50 N for 2 ms): its interior lags, and its
    modes deflect it inside by 0.025 of its length and 0.081 rad (measured), beyond the square
    root of the tolerance 1e-3: simulate says so (the interior check of
    fidelity.modal_validity), besides the ends' deflection and the spin."""
    m = ph.Mechanism()
    lk = m.add_flexible_link("s", 0.5, strip(), elements=8, fidelity="modal", modes=2)
    for end in ("start", "end"):
        m.add_wrench(end, getattr(lk, end), (0, 0, 0, 0, 0, 50.0), law=ph.Pulse(t0=0.0, duration=2e-3))
    with pytest.warns(ph.AccuracyWarning) as record:
        m.simulate(0.02, 1e-3)
    assert any("of its length inside, in its fixed-interface modes" in str(w.message) for w in record)


def test_curved_modal_links_with_many_modes_keep_the_chains_frequencies():
    """Modes whose weight is small but not zero (a curved link's) once made the sliders badly
    scaled and the frequencies 10 % off without a word; the slider scaling is bounded and the
    built model is checked against the Craig-Bampton mass. Curvature 0.01 /m with 40 modes and
    1 /m with 90 modes (16 elements): the five cantilever frequencies equal the full link's to
    1e-8 (measured 3.1e-10 and 8.4e-10)."""
    for kappa, n in ((0.01, 40), (1.0, 90)):
        fl = ph.Mechanism()
        f = fl.add_flexible_link("b", 1.0, table1_properties(), elements=16, curvature=(0, kappa, 0))
        fl.add_pair("c", ph.Fixed(), fl.ground, f.start)
        m = ph.Mechanism()
        lk = m.add_flexible_link("b", 1.0, table1_properties(), elements=16, curvature=(0, kappa, 0),
                                 fidelity="modal", modes=n)
        m.add_pair("c", ph.Fixed(), m.ground, lk.start)
        err = m.modes(5).frequency / fl.modes(5).frequency - 1.0
        assert np.max(np.abs(err)) <= 1e-8, (kappa, n, err)


def test_a_modal_links_modes_are_labelled_by_their_strain():
    """modes() labels a modal link's modes by where their strain energy sits, its sliders'
    springs included (each split by its fixed-interface mode's strain kinds): the clamped Table I
    link with the modes a 30 Hz band chooses has the full link's labels, and all the strain is
    the link's."""
    m = ph.Mechanism(band=30.0)
    lk = m.add_flexible_link("b", 1.0, table1_properties(), fidelity="modal")
    m.add_pair("c", ph.Fixed(), m.ground, lk.start)
    fl = ph.Mechanism()
    f = fl.add_flexible_link("b", 1.0, table1_properties(), elements=lk.reduced_from)
    fl.add_pair("c", ph.Fixed(), fl.ground, f.start)
    r, rf = m.modes(4), fl.modes(4)
    assert r.kind == rf.kind == ["bending-y"] * 4
    assert all(abs(d["b"] - 1.0) <= 1e-9 for d in r.strain_participation)


def test_a_modal_link_under_its_own_weight_along_it_warns():
    """A modal link hanging from a pivot: its weight along it stiffens the full link (its first
    frequency held at its start moves by 11 % at 9.81 m/s^2 for the Table I link), which a modal
    link leaves out; phmech says so. The same link lying in a weightless scene does not warn."""
    m = ph.Mechanism(gravity=(0, 0, -9.81))
    lk = m.add_flexible_link("b", 1.0, table1_properties(), elements=16, fidelity="modal", modes=4,
                             pose=se3.rotation("y", np.pi / 2))
    m.add_pair("h", ph.Revolute(axis="y"), m.ground, lk.start)
    with pytest.warns(ph.AccuracyWarning, match="its weight along it .* by about 11 %"):
        m.static()
    m0, _ = cantilever("modal", modes=4)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        m0.modes(2)


@pytest.mark.filterwarnings("ignore::phmech.UnattachedWarning")   # free on purpose
def test_record_of_a_modal_link_keeps_its_sliders():
    """simulate(record=link) records a modal link's sliders with its ends: its momentum is the
    full record's."""
    m, lk = kicked(modes=2)
    with pytest.warns(ph.AccuracyWarning):
        full = m.simulate(0.004, 1e-3)
        part = m.simulate(0.004, 1e-3, record=lk)
    np.testing.assert_allclose(part.momentum(lk).linear, full.momentum(lk).linear, rtol=0, atol=1e-15)


def test_damping_that_couples_the_modes_is_warned():
    """Section damping on bending only (not proportional to the stiffness) couples the modes with
    the ends (correlation 0.88, measured): phmech warns that a modal link leaves that out; a
    stiffness-proportional damping does not warn."""
    p = table1_properties()
    bending = ph.BeamProperties(p.stiffness, p.inertia, np.diag([0, 1.0, 1.0, 0, 0, 0]))
    with pytest.warns(ph.AccuracyWarning, match="section damping couples its modes"):
        ph.Mechanism().add_flexible_link("b", 1.0, bending, elements=16, fidelity="modal", modes=10)
    prop = ph.BeamProperties(p.stiffness, p.inertia, 1e-4 * p.stiffness)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        ph.Mechanism().add_flexible_link("b", 1.0, prop, elements=16, fidelity="modal", modes=10)


def test_a_modal_link_whose_mode_names_are_taken_is_refused_whole():
    """The sliders' pair and spring names are checked before anything is added: a clear error,
    and the mechanism is as it was (a link under another name then builds and has modes)."""
    m = ph.Mechanism()
    body = m.add_rigid_body("r", 1.0, np.eye(3))
    m.add_pair("b.mode2", ph.Fixed(), m.ground, body)
    with pytest.raises(ph.ModelError, match="its mode 2 needs the name 'b.mode2'"):
        m.add_flexible_link("b", 1.0, table1_properties(), elements=5, fidelity="modal", modes=3)
    assert len(m._car) == 1 and not m._desc.couplings and "b" not in m._desc.links
    lk = m.add_flexible_link("c", 1.0, table1_properties(), elements=5, fidelity="modal", modes=3,
                             start=body.frame)
    m.add_pair("weld", ph.Fixed(), body, lk.start)
    assert len(lk.sliders) == 3 and m.modes(2).frequency[0] > 0

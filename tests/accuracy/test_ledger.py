"""Trap suite, issue 27 item 5: the energy ledger cannot hide an error. ``ledger_relative`` is the
largest ledger residual over the energy the run moved and exchanged (the largest of the kinetic
energy, the change of kinetic plus elastic energy, the supplied and the dissipated work:
phmech._run.quality), not over a sum that counts the same joules two to four times; above
``LEDGER_WARN`` (4e-3) an AccuracyWarning gives the figures and the remedy. Good runs stay far
below (benchmarks/scenes.py with the defaults: at most 6.3e-4, docs/user_guide.md "Energy
ledger")."""
import warnings

import numpy as np
import pytest

import phmech as ph
from phmech import se3
from phmech._run import LEDGER_WARN, quality

G, L, MASS, J_YY = 9.81, 1.0, 1.0, 0.01
#: the former bound, on the former ratio (old_ratio)
FORMER_WARN = 1e-2


def pendulum():
    """A 1 kg bob on a 1 m arm (J_yy 0.01 kg m^2 about its centre) about y, released
    horizontal under gravity -z."""
    m = ph.Mechanism(gravity=(0, 0, -G))
    b = m.add_rigid_body("b", mass=MASS, inertia=np.eye(3) * J_YY, com=(L, 0, 0))
    m.add_pair("j", ph.Revolute(axis=(0, 1, 0)), m.ground, b)
    return m


def energy_from_state(res):
    """The pendulum's energy from its joint state alone (independent of the ledger):
    (m L^2 + J_yy) theta'^2 / 2 + m g z_com [J]."""
    rate = res.joint("j")["v"][:, 0] if "v" in res.joint("j") else res.joint_rates[:, 0]
    com = np.einsum("tij,j->ti", res.poses[:, 0], [L, 0, 0, 1])
    return 0.5 * (MASS * L ** 2 + J_YY) * rate ** 2 + MASS * G * com[:, 2]


def old_ratio(E):
    """The former ratio: ledger / (max kinetic + range of the potential + max |supplied| + max
    |dissipated|)."""
    pot = E["elastic"] + E["gravity"]
    scale = np.abs(E["kinetic"]).max() + np.ptp(pot) + np.abs(E["supplied"]).max() \
        + np.abs(E["dissipated"]).max()
    return np.abs(E["ledger"]).max() / scale


def test_a_pendulum_losing_two_percent_warns_where_the_old_ratio_hid_it():
    """Fixed 0.05 s steps with rho_inf = 0 (all numerical damping): the pendulum loses 0.19 J
    of the 9.8 J it swings with (measured 0.186 J, from its own joint state too). The former
    ratio read 9.6e-3 (below 1e-2: no warning); against its largest kinetic energy 1.9e-2."""
    m = pendulum()
    with pytest.warns(ph.AccuracyWarning, match=r"the energy ledger drifted by 0\.18\d J, 0\.019\d "
                      r"of the energy the run moved and exchanged \(9\.\d+ J.*above the bound "
                      r"0\.004"
                      r".*use a smaller step= or rtol="):
        r = m.simulate(2.0, 0.1, integrator="generalized-alpha", step=0.05, rho_inf=0.0)
    E = r.energy
    lost = energy_from_state(r)
    lost = lost[0] - lost
    # the ledger is the energy the integrator lost, measured independently from the state
    np.testing.assert_allclose(-E["ledger"], lost, atol=1e-9 * MASS * G * L)
    held = E["kinetic"].max()   # the largest kinetic energy: here the energy the run moved
    assert r.stats["energy_scale"] == pytest.approx(held, rel=1e-12)
    assert held <= MASS * G * L   # at most the drop's energy (less what was lost)
    assert r.stats["ledger_relative"] == pytest.approx(np.abs(lost).max() / held, rel=1e-6)
    assert r.stats["ledger_relative"] > LEDGER_WARN
    assert old_ratio(E) < FORMER_WARN   # what hid it


def test_the_same_pendulum_resolved_stays_far_below_the_bound():
    """The defaults (dt_out 0.01 s): energy conserved to 1e-4 of m g L, no warning."""
    m = pendulum()
    with warnings.catch_warnings():
        warnings.simplefilter("error", ph.AccuracyWarning)
        r = m.simulate(2.0, 0.01)
    e = energy_from_state(r)
    assert np.abs(e - e[0]).max() <= 1e-4 * MASS * G * L
    assert r.stats["ledger_relative"] <= 1e-4


def test_the_issue_s_four_bar_figures_now_warn():
    """The issue's four-bar (a flexible steel coupler driven by 0.2 N m): a 0.14 J ledger error
    on 10 J of supplied work, against a 40.7 J "energy scale" (the former sum) read 3.5e-3. Its
    scene is not reproduced here (its details are not in the issue; the flexible four-bar below
    keeps its ledger near 1e-4). Whatever its history, its kinetic energy and the change of its
    kinetic plus elastic energy were at most 40.7 - 10 = 30.7 J, so it
    reads at least 4.6e-3 now, above LEDGER_WARN; a history with those figures -- the work
    supplied going into kinetic energy, gravity exchanging 10 J with it, 0.14 J lost -- reads
    1.04e-2 and warns with the figures."""
    t = np.linspace(0.0, 1.0, 201)
    supplied = 10.0 * t
    ledger = -0.14 * t
    gravity = 10.0 * np.sin(np.pi * t) ** 2 - 10.0 * np.sin(2 * np.pi * t) ** 2 + 10.0
    kinetic = supplied + ledger - (gravity - gravity[0])
    E = dict(kinetic=kinetic, elastic=np.zeros_like(t), gravity=gravity, supplied=supplied,
             dissipated=np.zeros_like(t), ledger=ledger)
    q = quality(E, 1.0)
    assert q["energy_scale"] == pytest.approx(max(kinetic.max(), 10.0))
    assert q["ledger_relative"] == pytest.approx(0.14 / q["energy_scale"])
    assert q["ledger_relative"] > LEDGER_WARN and old_ratio(E) == pytest.approx(3.5e-3, rel=0.05)
    with pytest.warns(ph.AccuracyWarning, match=r"drifted by 0\.14 J, 0\.010\d of the energy the "
                      r"run moved and exchanged \(13\.\d J.*above the bound 0\.004"):
        ph._run.warn_if_inaccurate(dict(q, integrator="generalized-alpha", adaptive=True))


STEEL = ph.Material(E=210e9, nu=0.3, density=7850.0)


def flexible_fourbar(torque=0.2):
    """A crank-rocker four-bar (0.2 / 0.6 / 0.5 / 0.5 m; 1 kg rigid crank and rocker) whose
    coupler is a 0.6 m steel strip (20 x 2 mm, bending in the plane of motion, 6 elements),
    the crank driven by a constant ``torque`` [N m], no gravity."""
    m = ph.Mechanism()
    A, B, C, D = 0.2, 0.6, 0.5, 0.5
    T = lambda x: se3.translation([x, 0, 0])
    bar = lambda nm, l: m.add_rigid_body(nm, 1.0, np.diag([1e-4, l ** 2 / 12, l ** 2 / 12]),
                                         com=(l / 2, 0, 0))
    crank, rocker = bar("crank", A), bar("rocker", C)
    m.add_pair("k1", ph.Revolute("z"), m.ground, crank, x0=0.6,
               actuator=ph.Effort(law=ph.Constant(torque)))
    props = ph.BeamProperties.from_material(ph.Section.rectangle(0.002, 0.02), STEEL)
    cp = m.add_flexible_link("coupler", B, props, elements=6, start=ph.Frame(crank.carrier, T(A)))
    m.add_pair("k2", ph.Revolute("z"), ph.Frame(crank.carrier, T(A)), cp.start)
    m.add_pair("k4", ph.Revolute("z"), ph.Frame(-1, T(D)), rocker)
    m.add_pair("k3", ph.Revolute("z"), cp.end, ph.Frame(rocker.carrier, T(C)))
    return m


def test_driven_flexible_fourbar_ratio_is_against_the_supplied_work():
    """The flexible four-bar driven by 0.2 N m over 1 s with the defaults: the energy
    moved and exchanged is the supplied work (the mechanism starts at rest; kinetic plus
    elastic energy equals it up to the ledger), the ratio is the ledger over it, and the run
    is good: below the bound, no warning (measured 4e-5 over 1 s)."""
    m = flexible_fourbar()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ph.RedundantConstraintWarning)
        warnings.simplefilter("ignore", ph.InitialValueWarning)
        warnings.simplefilter("error", ph.AccuracyWarning)
        r = m.simulate(1.0, 1e-3)
    E = r.energy
    stored = E["kinetic"] + E["elastic"]
    scale = max(E["kinetic"].max(), np.abs(stored - stored[0]).max(), np.abs(E["supplied"]).max())
    assert r.stats["energy_scale"] == pytest.approx(scale, rel=1e-12)
    assert scale == pytest.approx(np.abs(E["supplied"]).max(), rel=1e-3)
    assert r.stats["ledger_relative"] == pytest.approx(np.abs(E["ledger"]).max() / scale, rel=1e-12)
    assert r.stats["ledger_relative"] < LEDGER_WARN / 10
    # the supplied work is the torque times the crank's turn (independent of the ledger)
    turn = r.joint("k1")["x"][-1, 0] - r.joint("k1")["x"][0, 0]
    assert E["supplied"][-1] == pytest.approx(0.2 * turn, rel=1e-6)


def test_a_run_that_exchanges_nothing_is_judged_against_the_energy_it_holds():
    """A rigid crank coasting at 2 pi rad/s on a revolute (no gravity): nothing is supplied,
    dissipated or exchanged, the kinetic energy I w^2 / 2 is kept; the ratio is the ledger
    over it (not a ratio of round-offs, not 0)."""
    m = ph.Mechanism()
    I_zz = 1e-3
    crank = m.add_rigid_body("crank", 0.5, np.diag([1e-4, I_zz, I_zz]))
    m.add_pair("motor", ph.Revolute("z"), m.ground, crank, xdot0=2 * np.pi)
    r = m.simulate(1.0, 1e-2)
    held = 0.5 * I_zz * (2 * np.pi) ** 2
    assert r.stats["energy_scale"] == pytest.approx(held, rel=1e-6)
    assert r.stats["ledger_relative"] == pytest.approx(np.abs(r.energy["ledger"]).max() / held,
                                                       rel=1e-6)
    assert r.stats["ledger_relative"] < 1e-8

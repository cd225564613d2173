"""Labelled modes (phmech.analysis.label_modes via Mechanism.modes), the MAC, and the warning
for modes away from an equilibrium.

References: the exact Timoshenko frequencies (phmech.timoshenko) and the closed-form torsion
and axial frequencies of a clamped-free bar tell which of the Table I cantilever's first ten
modes bends in which plane, twists or stretches; the leaf-spring guide's modes are identified
by the motion of its stage and by textbook frequencies of its leaves."""
import math
import os
import sys
import warnings

import numpy as np
import pytest

import phmech as ph
from phmech import studies

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "examples"))


def test_table1_cantilever_first_ten_modes_labelled():
    f = 4.0   # x-y plane sqrt(f) = 2x stiffer; torsion and axial fall among the bending modes
    m, _ = studies.se3_cantilever(40, ph.table1_properties(f))
    r = m.modes(10)
    B = studies.TABLE1
    k = np.arange(1, 11)
    xz = ph.timoshenko.frequencies(10, B["L"], B["EI"], B["kGA"], B["rhoA"], B["rhoI"], "clamped-free")
    ref = sorted([(w, "bending-y") for w in xz] + [(2 * w, "bending-z") for w in xz]
                 + [(w, "torsion") for w in (2 * k - 1) * math.pi / 2 * math.sqrt(f * B["EI"] / (2 * B["rhoI"]))]
                 + [(w, "axial") for w in (2 * k - 1) * math.pi / 2 * math.sqrt(f * B["EI"] / B["rhoI"])])[:10]
    # frequencies within the 40-element discretization error (0.2 %), and no two reference
    # frequencies closer than 4 %, so the order is the reference's
    np.testing.assert_allclose(r.omega, [w for w, _ in ref], rtol=2e-3)
    assert min(np.diff([w for w, _ in ref]) / [w for w, _ in ref][1:]) > 0.04
    assert r.kind == [kd for _, kd in ref]
    assert np.all(r.strain_fractions.max(axis=1) > 0.99)
    np.testing.assert_allclose(r.elastic_fraction, 1.0, rtol=1e-3)   # all strain energy
    assert r.labels[0] == "bending about y (local x-z plane), beam"
    assert all(p["beam"] == pytest.approx(1.0) for p in r.participation)
    assert r.equilibrium


def test_leaf_spring_modes_labelled():
    import leaf_spring as ls
    p = ls.default_params()
    m, h = ls.build(p, elements=10)
    r = m.modes(10)
    R1 = h["R1"].carrier
    x_stage = [abs(r.shapes[k, R1, 3]) / np.linalg.norm(r.shapes[k, R1]) for k in range(10)]
    z_stage = [abs(r.shapes[k, R1, 5]) / np.linalg.norm(r.shapes[k, R1]) for k in range(10)]
    # mode 1: the stage translates along x (world), the leaves bend in their thin direction,
    # about their local y axis (ls.build: local z = world -x); paper's formula within 1 %
    assert r.kind[0] == "bending-y" and x_stage[0] > 0.999
    assert r.frequency[0] == pytest.approx(ls.f_analytic(p), rel=0.01)
    # modes 2, 3: the stage rocks about x and yaws about z: the leaves bend across their width
    assert r.kind[1:3] == ["bending-z", "bending-z"]
    # the first leaf-local modes: clamped-clamped leaves in their thin direction,
    # 22.373 / (2 pi) sqrt(E I / (rho A L^4)), the stage still (leaves carry > 99 % of the motion)
    f_cc = 22.373 / (2 * math.pi) * math.sqrt(p.E * p.I_y / (p.density * p.width * p.thickness * p.L ** 4))
    for k in (3, 4):
        assert r.kind[k] == "bending-y"
        assert r.frequency[k] == pytest.approx(f_cc, rel=0.03)
        assert r.participation[k]["F1"] + r.participation[k]["F2"] > 0.99
    # the stage bouncing along z on the leaves' axial stiffness 2 E A / L
    ax = [k for k in range(10) if z_stage[k] > 0.99]
    f_ax = math.sqrt(2 * p.E * p.width * p.thickness / p.L / p.m_R) / (2 * math.pi)
    assert len(ax) == 1 and r.kind[ax[0]] == "axial"
    assert r.frequency[ax[0]] == pytest.approx(f_ax, rel=0.03)
    assert r.kind[9] == "torsion"
    assert "rigid-body" not in r.kind


def test_rigid_body_modes_and_mac():
    steel = ph.Material(E=210e9, nu=0.3, density=7850.0)
    props = ph.BeamProperties.from_material(ph.Section.rectangle(0.02, 0.002), steel)
    m = ph.Mechanism()
    body = m.add_rigid_body("hub", 2.0, np.diag([0.01, 0.01, 0.01]))
    m.add_pair("hinge", ph.Revolute("z"), m.ground, body,
               actuator=ph.Spring(k=1.0, c=0.0, rest=0.0))        # a soft joint spring
    arm = m.add_flexible_link("arm", 0.3, props, elements=8)
    m.add_pair("weld", ph.Fixed(), body, arm.start)
    r = m.modes(3)
    # the hub turning on its soft spring with the arm carried along: rigid-body
    assert r.kind[0] == "rigid-body" and r.elastic_fraction[0] < 0.05
    assert r.kind[1] != "rigid-body"
    M = r.mac()
    np.testing.assert_allclose(np.diag(M), 1.0, rtol=1e-12)
    # mass-orthogonal shapes are not Euclidean-orthogonal, but a shape against its negative
    # and scaled copy is parallel
    np.testing.assert_allclose(ph.analysis.mac(r.shapes[:1], -3.0 * r.shapes[:1]), [[1.0]])
    assert ph.analysis.mac(np.array([[1.0, 0.0]]), np.array([[0.0, 2.0]]))[0, 0] == 0.0
    with pytest.raises(ph.ModelError):
        ph.analysis.mac(r.shapes, np.zeros((2, 5)))


def test_modes_away_from_equilibrium_warn():
    m, leaf = studies.se3_cantilever(10)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert m.modes(2).equilibrium        # unloaded, no gravity: an equilibrium
    m.gravity = (0.0, 0.0, -9.81)
    with pytest.warns(ph.EquilibriumWarning, match="not a static equilibrium.*negative frequenc"):
        r = m.modes(2)
    assert not r.equilibrium
    st = m.static()
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert m.modes(2, at=st).equilibrium

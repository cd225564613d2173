"""When the loop closure of the initial configuration moves a
given joint coordinate (x0) or a given pose, phmech reports how far (Mechanism.initial_adjustments,
an InitialValueWarning, or a ModelError with Mechanism(strict=True)).

Reference: the four-bar of tests/test_closed_chains.py (crank 0.2 m, coupler 0.6 m, rocker
0.5 m, ground link 0.5 m); its closures at a crank angle come from the intersection of two
circles (test_closed_chains.rocker_angles), and every angle below is read from the poses with
atan2, independently of the core's joint coordinates.
"""
import warnings

import numpy as np
import pytest

import phmech as ph
from phmech import se3

from test_closed_chains import A, B, C, D, bar, rocker_angles


def fourbar(k4_x0=None, rocker_pose=None, strict=False):
    m = ph.Mechanism(strict=strict)
    crank, cp = bar(m, "crank", A), bar(m, "coupler", B)
    rocker = m.add_rigid_body("rocker", 1.0, np.diag([1e-4, C**2 / 12, C**2 / 12]), com=(C / 2, 0, 0),
                              pose=rocker_pose)
    T = lambda x: se3.translation([x, 0, 0])
    m.add_pair("k1", ph.Revolute("z"), m.ground, crank, x0=0.6)
    m.add_pair("k2", ph.Revolute("z"), ph.Frame(crank.carrier, T(A)), cp)
    m.add_pair("k3", ph.Revolute("z"), ph.Frame(cp.carrier, T(B)), ph.Frame(rocker.carrier, T(C)))
    m.add_pair("k4", ph.Revolute("z"), ph.Frame(-1, T(D)), rocker, x0=k4_x0)
    return m, crank, rocker


def angle(H):
    return float(np.arctan2(H[1, 0], H[0, 0]))


def initial(m):
    """initial_configuration() with the warnings it gave (redundant rows left out)."""
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        ic = m.initial_configuration()
    return ic, [x for x in w if issubclass(x.category, ph.InitialValueWarning)]


def rows(ic):
    return {(a.name, a.quantity): a for a in ic.adjustments}


def test_consistent_fourbar_reports_nothing():
    m, crank, _ = fourbar()
    ic, warned = initial(m)
    assert warned == []
    a = rows(ic)[("k1", "x")]
    assert a.given == 0.6 and a.unit == "rad" and not a.exceeds
    assert a.moved < 1e-12 and abs(a.reached - angle(ic.poses[crank.carrier])) < 1e-12


def test_inconsistent_rocker_angle_is_projected_and_reported():
    phi = rocker_angles(0.6)[0] + 0.2       # 1.48786 rad: 0.2 rad off the closure at x0 = 0.6
    m, crank, rocker = fourbar(k4_x0=phi)
    ic, warned = initial(m)
    H = ic.poses
    th, ph_ = angle(H[crank.carrier]), angle(H[rocker.carrier])
    # the projection is kept: the loop is closed (circle intersection at the closed crank angle)
    assert abs(ph_ - rocker_angles(th)[0]) < 1e-9
    # the table: given x0, reached value (= the angle in the poses), and how far it moved
    r = rows(ic)
    k1, k4 = r[("k1", "x")], r[("k4", "x")]
    assert abs(k1.reached - th) < 1e-9 and abs(k4.reached - ph_) < 1e-9
    assert k1.moved == pytest.approx(abs(th - 0.6), abs=1e-12)
    assert k4.moved == pytest.approx(abs(ph_ - phi), abs=1e-12)
    # measured: the equal-weight soft targets share the misfit unevenly (the rocker angle is
    # nearly stationary in the crank angle here): k1 0.6 -> 0.590215 (moved 0.00979 rad),
    # k4 1.48786 -> 1.28829 (moved 0.200 rad)
    assert 0.005 < k1.moved < 0.02 and 0.19 < k4.moved < 0.21
    assert k1.exceeds and k4.exceeds
    # one warning, in plain words, naming both pairs and the amounts
    assert len(warned) == 1
    msg = str(warned[0].message)
    assert f"joint 'k4' given {phi:.6g} rad, closed at {ph_:.6g} rad (moved {k4.moved:.3g} rad)" in msg
    assert f"joint 'k1' given 0.6 rad, closed at {th:.6g} rad" in msg
    print(f"four-bar: k1 0.6 -> {th:.6f} rad (moved {k1.moved:.3g}), k4 {phi:.6f} -> {ph_:.6f} rad "
          f"(moved {k4.moved:.3g})")


def test_strict_raises_instead_of_warning():
    phi = rocker_angles(0.6)[0] + 0.2
    m, _, _ = fourbar(k4_x0=phi, strict=True)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ph.RedundantConstraintWarning)
        with pytest.raises(ph.ModelError, match=r"joint 'k4' given 1\.48786 rad, closed at 1\.28829 rad.*strict=True"):
            m.modes(1)
    # a consistent model passes in strict mode
    m, _, _ = fourbar(strict=True)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ph.RedundantConstraintWarning)
        assert m.modes(1).frequency.shape == (1,)
    with pytest.raises(ph.ModelError, match="strict must be True or False"):
        ph.Mechanism(strict="yes")


def test_given_pose_moved_by_the_loop_closure_is_reported():
    # the rocker given at 1.0 rad about its pivot (k4 without x0: the pose is honoured by the
    # tree), the crank held at x0 = 0.6: closing the loop turns the rocker to the closure
    # 1.28786 rad (circle intersection), 0.28786 rad from the given pose; its origin stays
    phi = rocker_angles(0.6)[0]
    m, crank, rocker = fourbar(rocker_pose=se3.translation([D, 0, 0]) @ se3.rotation("z", 1.0))
    ic, warned = initial(m)
    assert abs(angle(ic.poses[crank.carrier]) - 0.6) < 1e-12       # the x0 is held exactly
    assert abs(angle(ic.poses[rocker.carrier]) - phi) < 1e-9
    r = rows(ic)
    assert r[("rocker", "orientation")].moved == pytest.approx(phi - 1.0, abs=1e-9)
    assert r[("rocker", "position")].moved < 1e-12
    assert len(warned) == 1 and "pose of 'rocker': orientation moved 0.288 rad" in str(warned[0].message)

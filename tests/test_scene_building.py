"""Scenes built without hand-made matrices (python/phmech/frames.py, Frame.frame_at, Body.frame_at,
phmech.rotation; python/phmech/mechanism.py, add_flexible_link(start=), add_rigid_body(at=),
Mechanism.world_pose; python/phmech/section.py, Section.strip).

References: the same scenes built with explicit 4x4 poses and ph.Frame offsets (the model rows and
the simulation must be identical, bit for bit), the offset composed by hand with NumPy, the period
of a physical pendulum sqrt(I_O / (m g d)) (small amplitude), the Euler-Bernoulli + Timoshenko
cantilever P L^3 / (3 E I) + P L / (k G A) with the second moments written out (w t^3 / 12).
"""
import numpy as np
import pytest

import phmech as ph
from phmech import se3

STEEL = ph.Material(E=210e9, nu=0.3, density=7850.0)
J_ARM = np.diag([1e-4, 0.3**2 / 12, 0.3**2 / 12])


def double_pendulum(explicit: bool, x0=None):
    """The rigid + flexible double pendulum of docs/user_guide.md: a 0.3 m rigid arm (1 kg) on a
    revolute about y hung 1 m above the origin, a 0.3 m steel strip (20 x 2 mm, 8 elements) on
    a revolute about y at the arm's end. ``explicit``: built with 4x4 poses and ph.Frame
    offsets by hand, else with frame_at and start=."""
    props = ph.BeamProperties.from_material(ph.Section.strip(width=0.02, thickness=0.002), STEEL)
    m = ph.Mechanism(gravity=(0, 0, -9.81))
    arm = m.add_rigid_body("arm", 1.0, J_ARM, com=(0.15, 0, 0))
    if explicit:
        hinge = ph.Frame(-1, se3.translation([0.0, 0.0, 1.0]), "hinge")
        elbow = ph.Frame(arm.carrier, se3.translation([0.3, 0.0, 0.0]), "elbow")
    else:
        hinge = m.ground.frame_at((0, 0, 1.0), name="hinge")
        elbow = arm.frame_at((0.3, 0, 0), name="elbow")
    m.add_pair("shoulder", ph.Revolute(axis="y"), hinge, arm, x0=x0)
    if explicit:
        start = se3.translation([0.0, 0.0, 1.0])
        if x0 is not None:
            start = start @ se3.rotation("y", x0)
        strip = m.add_flexible_link("strip", 0.3, props, elements=8,
                                    pose=start @ se3.translation([0.3, 0.0, 0.0]))
    else:
        strip = m.add_flexible_link("strip", 0.3, props, elements=8, start=elbow)
    m.add_pair("elbow", ph.Revolute(axis="y"), elbow, strip.start)
    return m, arm, strip, elbow


def _rows_equal(a, b):
    """Model description rows equal entry by entry (arrays bit for bit)."""
    assert len(a) == len(b)
    for ra, rb in zip(a, b):
        assert ra.keys() == rb.keys()
        for k in ra:
            if k in ("pair", "law"):
                assert type(ra[k]) is type(rb[k])
            elif isinstance(ra[k], np.ndarray):
                assert np.array_equal(ra[k], rb[k]), k
            elif k not in ("fa_name", "fb_name"):
                assert ra[k] == rb[k], k


def test_double_pendulum_from_frames_is_the_one_from_explicit_poses():
    (ma, _, sa, _), (mb, _, sb, _) = double_pendulum(False), double_pendulum(True)
    da, db = ma._desc, mb._desc
    for rows in ("carriers", "elements", "pairs"):
        _rows_equal(getattr(da, rows), getattr(db, rows))
    assert da.given.keys() == db.given.keys()
    assert all(np.array_equal(da.given[c], db.given[c]) for c in da.given)
    ra, rb = ma.simulate(0.2, 0.01), mb.simulate(0.2, 0.01)
    assert ra.stats["steps"] == rb.stats["steps"] > 0
    for name in ("poses", "twists", "constraint_wrenches", "joints"):
        assert np.array_equal(getattr(ra, name), getattr(rb, name)), name
    assert np.array_equal(ra.energy["total"], rb.energy["total"])
    # the strip swung: the comparison is not between two scenes at rest
    assert np.ptp(ra.tip(sa)[:, 2]) > 0.05


def test_start_follows_the_frame_placed_by_an_earlier_pair():
    """start= takes the frame's pose in the tree placement so far (the shoulder's x0 turns the
    arm before the strip is added): the strip starts at the arm's end, along the arm."""
    x0 = 0.4
    m, arm, strip, elbow = double_pendulum(False, x0=x0)
    expected = se3.translation([0, 0, 1.0]) @ se3.rotation("y", x0) @ se3.translation([0.3, 0, 0])
    np.testing.assert_allclose(m.world_pose(elbow), expected, rtol=0, atol=1e-14)
    np.testing.assert_allclose(m.world_pose(strip.start), expected, rtol=0, atol=1e-14)
    # the nodes along the frame's x axis, 0.3 / 8 apart
    ic = m.initial_configuration()
    p = ic.poses[strip.nodes][:, :3, 3]
    ref = expected[:3, 3] + np.outer(np.arange(9) * 0.3 / 8, expected[:3, 0])
    np.testing.assert_allclose(p, ref, rtol=0, atol=1e-12)
    assert all(not a.exceeds for a in m.initial_adjustments)
    mb = double_pendulum(True, x0=x0)[0]
    np.testing.assert_allclose(ic.poses, mb.initial_configuration().poses, rtol=0, atol=1e-14)


def test_frame_at_composes_offsets():
    m = ph.Mechanism()
    b = m.add_rigid_body("b", 1.0, np.eye(3))
    R1, R2 = ph.rotation("z", 0.3), ph.rotation([1, 1, 0], -1.1)
    f1 = b.frame_at((0.1, 0.2, 0.3), R1)
    f2 = f1.frame_at((0.0, -0.5, 0.0), R2, name="tool")
    T1 = np.block([[R1, np.array([[0.1], [0.2], [0.3]])], [np.zeros((1, 3)), np.ones((1, 1))]])
    T2 = np.block([[R2, np.array([[0.0], [-0.5], [0.0]])], [np.zeros((1, 3)), np.ones((1, 1))]])
    assert f1.carrier == f2.carrier == b.carrier
    np.testing.assert_allclose(f2.T, T1 @ T2, rtol=0, atol=1e-15)
    assert f1.name == "b at (0.1, 0.2, 0.3) rotated" and f2.name == "tool"
    assert b.frame_at((1, 2, 3)).name == "b at (1, 2, 3)"
    # ph.rotation: right-handed, the 3x3 block of se3.rotation
    np.testing.assert_allclose(ph.rotation("z", np.pi / 2) @ [1, 0, 0], [0, 1, 0], atol=1e-15)
    np.testing.assert_allclose(ph.rotation("x", np.pi / 2) @ [0, 1, 0], [0, 0, 1], atol=1e-15)
    assert np.array_equal(ph.rotation("y", 0.7), se3.rotation("y", 0.7)[:3, :3])


@pytest.mark.parametrize("kwargs, match", [
    (dict(point=(0, 0)), "point"),
    (dict(point="abc"), "point"),
    (dict(rotation=np.eye(4)), r"3x3 rotation matrix .* got shape \(4, 4\)"),
    (dict(rotation=np.diag([1.0, 1.0, -1.0])), "not a rotation"),
    (dict(rotation=2 * np.eye(3)), "not a rotation"),
    (dict(name=3), "name"),
])
def test_frame_at_refuses_bad_input(kwargs, match):
    m = ph.Mechanism()
    b = m.add_rigid_body("b", 1.0, np.eye(3))
    with pytest.raises(ph.ModelError, match=match):
        b.frame_at(**kwargs)
    with pytest.raises(ph.ModelError, match="axis"):
        ph.rotation("w", 1.0)


def test_pose_and_at_are_exclusive():
    m = ph.Mechanism()
    b = m.add_rigid_body("b", 1.0, np.eye(3))
    with pytest.raises(ph.ModelError, match="pose= or at="):
        m.add_rigid_body("c", 1.0, np.eye(3), pose=np.eye(4), at=b.frame_at((1, 0, 0)))
    props = ph.BeamProperties.from_material(ph.Section.circle(0.01), STEEL)
    with pytest.raises(ph.ModelError, match="pose= or start="):
        m.add_flexible_link("l", 1.0, props, pose=np.eye(4), start=b.frame)
    assert "c" not in m._bodies and "l" not in m._links


def test_body_at_a_link_end():
    """A tip body placed at the end of a link whose start sits on a rotated ground frame."""
    props = ph.BeamProperties.from_material(ph.Section.circle(0.01), STEEL)
    m = ph.Mechanism()
    root = m.ground.frame_at((0, 0, 0.5), ph.rotation("y", -np.pi / 2))   # x up
    link = m.add_flexible_link("post", 0.4, props, elements=4, start=root)
    m.add_pair("clamp", ph.Fixed(), root, link.start)
    tip = m.add_rigid_body("tip", 0.1, 1e-4 * np.eye(3), at=link.end.frame_at((0, 0, 0.05)))
    m.add_pair("weld", ph.Fixed(), link.end.frame_at((0, 0, 0.05)), tip)
    H = m.initial_configuration().poses[tip.carrier]
    # turned -90 deg about y, the post's local x is world +z and its local z world -x
    np.testing.assert_allclose(H[:3, 3], [-0.05, 0, 0.9], rtol=0, atol=1e-14)
    np.testing.assert_allclose(H[:3, :3], ph.rotation("y", -np.pi / 2), rtol=0, atol=1e-15)


def test_offset_frames_in_pairs_loads_springs_record_and_results():
    """A rigid pendulum (uniform 0.4 m bar, 2 kg) hung from a rotated ground frame, loaded
    through an offset frame; the small-amplitude period is that of a physical pendulum."""
    Lb, mass, g = 0.4, 2.0, 9.81
    Jc = mass * Lb**2 / 12
    m = ph.Mechanism(gravity=(0, 0, -g))
    # the hinge axis z of the frame turned +90 deg about x is world -y; the bar hangs along
    # world -z from its body frame at the hinge: body x is down
    bar = m.add_rigid_body("bar", mass, np.diag([1e-4, Jc, Jc]), com=(Lb / 2, 0, 0))
    hinge = m.ground.frame_at((0, 0, 2.0), ph.rotation("x", np.pi / 2))
    on_bar = bar.frame_at((0, 0, 0), ph.rotation("y", -np.pi / 2) @ ph.rotation("x", np.pi / 2))
    m.add_pair("hinge", ph.Revolute("z"), hinge, on_bar, x0=0.02)
    # a zero wrench through an offset frame and a slack spring through two offset frames: the
    # rows must be those of the same loads given with point= / point_a=, point_b=
    tipf = bar.frame_at((Lb, 0, 0), ph.rotation("z", 0.3), name="tip")
    m.add_wrench("w", tipf, (0, 0, 0, 1.0, 0, 0), law=ph.Constant(0.0), frame="body")
    m.add_spring_damper("s", tipf, m.ground.frame_at((0, 0, 1.0)), k=0.0)
    ld, sp = m._loads[0], m._springs[0]
    np.testing.assert_allclose(ld["point"], [Lb, 0, 0], atol=1e-15)
    np.testing.assert_allclose(ld["w"][3:], [np.cos(0.3), np.sin(0.3), 0], atol=1e-15)
    np.testing.assert_allclose(sp["pa"], [Lb, 0, 0], atol=1e-15)
    np.testing.assert_allclose(sp["pb"], [0, 0, 1.0], atol=1e-15)

    r = m.simulate(2.0, 0.005, record=[tipf], integrator="ida", rtol=1e-9)
    assert list(r.carriers) == [bar.carrier]
    # pose() of an offset frame: the carrier's pose times the offset
    np.testing.assert_allclose(r.pose(tipf), r.pose(bar) @ tipf.T, rtol=0, atol=1e-15)
    z = r.position(tipf)[:, 2]
    assert abs(z[0] - (2.0 - Lb * np.cos(0.02))) < 1e-12
    # period from the zero crossings of x (the swing is in the world x-z plane)
    x = r.position(tipf)[:, 0]
    s = np.nonzero(np.diff(np.sign(x)))[0]
    tc = r.t[s] - x[s] * (r.t[s + 1] - r.t[s]) / (x[s + 1] - x[s])
    period = 2 * np.mean(np.diff(tc))
    ref = 2 * np.pi * np.sqrt((Jc + mass * (Lb / 2) ** 2) / (mass * g * Lb / 2))
    # amplitude 0.02 rad: the period exceeds the linear one by theta0^2 / 16 = 2.5e-5 (measured
    # 1.03595430 s against 1.03592838 s linear: +2.502e-5)
    ref *= 1 + 0.02**2 / 16
    assert abs(period / ref - 1) < 1e-6, (period, ref)
    assert np.max(np.abs(r.position(tipf)[:, 1])) < 1e-12
    # static load through an offset frame: a horizontal world force F at the tip turns the bar
    # to tan(theta) = F Lb / (m g Lb / 2)
    F = 5.0
    st = m.static(loads=[(tipf, (0, 0, 0, F, 0, 0), "world")], steps=2)
    th = np.arctan(2 * F / (mass * g))
    p = st.poses[bar.carrier] @ tipf.T
    np.testing.assert_allclose(p[:3, 3], [Lb * np.sin(th), 0, 2.0 - Lb * np.cos(th)], atol=1e-9)
    print(f"pendulum on offset frames: period {period:.8f} s, reference {ref:.8f} s; static "
          f"angle {np.arctan2(p[0, 3], 2.0 - p[2, 3]):.10f} rad, reference {th:.10f} rad")


def _tip_deflections(section, elements=20):
    """Static tip displacement (y, z) [m] of a 0.3 m cantilever along x under 0.02 N along y,
    then along z."""
    props = ph.BeamProperties.from_material(section, STEEL)
    out = []
    for load in ((0, 0.02, 0), (0, 0, 0.02)):
        m = ph.Mechanism()
        s = m.add_flexible_link("s", 0.3, props, elements=elements)
        m.add_pair("clamp", ph.Fixed(), m.ground, s.start)
        st = m.static(loads=[(s.end, (0, 0, 0, *load), "world")], steps=2)
        out.append(st.positions(s)[-1][1 + int(load[2] != 0)])
    return np.array(out), props


@pytest.mark.parametrize("thin", ["z", "y"])
def test_strip_is_soft_across_its_thickness(thin):
    w, t, L, P = 0.02, 0.001, 0.3, 0.02
    sec = ph.Section.strip(width=w, thickness=t, thin_along=thin)
    d, props = _tip_deflections(sec)
    E, G = STEEL.E, STEEL.G
    k = 10 * (1 + STEEL.nu) / (12 + 11 * STEEL.nu)        # Cowper, rectangle
    soft = P * L**3 / (3 * E * w * t**3 / 12) + P * L / (k * G * w * t)
    stiff = P * L**3 / (3 * E * t * w**3 / 12) + P * L / (k * G * w * t)
    ref = np.array([stiff, soft] if thin == "z" else [soft, stiff])
    # se3 mesh error at 20 elements ~1e-3; the soft and stiff directions differ by (w/t)^2 = 400
    np.testing.assert_allclose(d, ref, rtol=3e-3)
    same = ph.Section.rectangle(w, t) if thin == "z" else ph.Section.rectangle(t, w)
    assert sec == same
    with pytest.raises(ph.ModelError, match="thin_along"):
        ph.Section.strip(w, t, thin_along="x")

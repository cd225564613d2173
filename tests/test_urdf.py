"""Robots from URDF (phmech.load_urdf, python/phmech/urdf.py).

References: Pinocchio's forward dynamics and free swings of UR5 and Panda stored in
tests/data/urdf/*_reference.json (tests/data/urdf/make_reference.py made them; `make validate`
runs the full check, benchmarks/validate_urdf.py); closed forms of a pendulum, a slider and a
cantilever written here as URDF; forward kinematics by se3 products. Bad files: a ModelError
naming the element."""
import json
import os
import subprocess
import sys
import warnings

import numpy as np
import pytest

import phmech as ph
from phmech import se3

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data", "urdf")
EXAMPLES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "examples")
ROBOTS = {"ur5": ("ur5_robot.urdf", {}), "panda": ("panda.urdf", {"mimic": "free"})}
# Pinocchio's aba has no joint damping (Panda's URDF has some); limits are not the point here
KW = dict(limits="ignore", joint_damping=False)


def reference(name):
    with open(os.path.join(DATA, f"{name}_reference.json")) as fh:
        return json.load(fh)


# ------------------------------------------------------------------ against Pinocchio
@pytest.mark.parametrize("name", ROBOTS)
def test_forward_dynamics_matches_pinocchio(name):
    fname, opts = ROBOTS[name]
    ref = reference(name)
    path = os.path.join(DATA, fname)
    assert list(ph.load_urdf(path, **KW, **opts).joints) == ref["joints"]
    for s in ref["states"]:
        a = ph.urdf.forward_dynamics(path, s["q"], s["qdot"], s["tau"], **KW, **opts)
        a_pin = np.array(s["qddot"])
        assert np.max(np.abs(a - a_pin)) <= 1e-8 * np.max(np.abs(a_pin)), (a, a_pin)


@pytest.mark.parametrize("name", ROBOTS)
def test_free_swing_matches_pinocchio(name):
    """0.5 s under gravity from rest (the stored solve_ivp of pinocchio.aba at rtol 1e-12):
    within 1e-6 rad at every 0.05 s (IDA at rtol 1e-10; measured 6e-11 rad)."""
    fname, opts = ROBOTS[name]
    sw = reference(name)["swing"]
    robot = ph.load_urdf(os.path.join(DATA, fname), q0=dict(zip(sw["joints"], sw["q0"])),
                         driven=sw["locked"] or None, **KW, **opts)
    t = np.array(sw["t"])
    res = robot.mechanism.simulate(t[-1], t[1] - t[0], integrator="ida", rtol=1e-10)
    x = np.hstack([res.joint(n)["x"] for n in sw["joints"]])
    np.testing.assert_allclose(res.t, t, atol=1e-12)
    assert np.max(np.abs(x - np.array(sw["q"]))) < 1e-6
    assert np.max(np.abs(x - x[0])) > 1.0     # it does swing


# ------------------------------------------------------------------ closed forms
PENDULUM = """<robot name="pendulum">
  <link name="base"/>
  <joint name="hinge" type="{jtype}">
    <parent link="base"/><child link="bob"/>
    <origin xyz="0.1 0.2 0.3" rpy="{rpy}"/>
    <axis xyz="{axis}"/>
    <limit lower="-1" upper="1" effort="10" velocity="1"/>
  </joint>
  <link name="bob">
    <inertial>
      <origin xyz="{com}" rpy="0.3 -0.2 0.5"/>
      <mass value="{mass}"/>
      <inertia ixx="0.02" ixy="0.001" ixz="0.0" iyy="0.03" iyz="0.002" izz="0.04"/>
    </inertial>
  </link>
</robot>"""


def write(tmp_path, text, name="robot.urdf"):
    p = tmp_path / name
    p.write_text(text)
    return str(p)


def inertia_about_axis(rpy_inertial, I, com, axis):
    """Moment of inertia of the bob about the joint axis through the joint origin."""
    R = se3.rotation("z", rpy_inertial[2]) @ se3.rotation("y", rpy_inertial[1]) @ \
        se3.rotation("x", rpy_inertial[0])
    Ic = R[:3, :3] @ I @ R[:3, :3].T
    d = com - axis * (com @ axis)
    return axis @ Ic @ axis, d @ d


def test_pendulum_inverse_dynamics_is_the_closed_form(tmp_path):
    """A revolute about a tilted axis through a rotated joint origin, its inertial offset and
    rotated (rpy): tau = J a + m g . (axis x r) with J about the axis (parallel-axis theorem)."""
    com, axis, mass = np.array([0.2, -0.1, 0.05]), np.array([0.0, 0.6, 0.8]), 1.7
    path = write(tmp_path, PENDULUM.format(jtype="revolute", rpy="0.4 0 0", axis="0 0.6 0.8",
                                           com="0.2 -0.1 0.05", mass=mass))
    I = np.array([[0.02, 0.001, 0], [0.001, 0.03, 0.002], [0, 0.002, 0.04]])
    Jc, d2 = inertia_about_axis((0.3, -0.2, 0.5), I, com, axis)
    J = Jc + mass * d2
    g = np.array([0, 0, -9.81])
    Rj = se3.rotation("x", 0.4)[:3, :3]   # the joint frame in the world
    for q, qd, a in ((0.3, 0.0, 2.0), (-1.1, 0.7, -0.4)):
        tau = ph.urdf.inverse_dynamics(path, [q], [qd], [a], limits="ignore")[0]
        Rq = se3.rotation(axis, q)[:3, :3]
        r = Rj @ Rq @ com                     # the centre of mass from the joint origin, world
        w = Rj @ axis                         # the axis in the world
        # gravity's moment about the axis is m (r x g) . w; the drive balances it
        expected = J * a - mass * np.cross(r, g) @ w
        assert tau == pytest.approx(expected, rel=1e-9, abs=1e-12)


def test_slider_inverse_dynamics_is_the_closed_form(tmp_path):
    path = write(tmp_path, PENDULUM.format(jtype="prismatic", rpy="0 0 0", axis="0 0 2",
                                           com="0.2 -0.1 0.05", mass=1.7))
    tau = ph.urdf.inverse_dynamics(path, [0.1], [0.5], [3.0], limits="ignore")[0]
    assert tau == pytest.approx(1.7 * (3.0 + 9.81), rel=1e-10)   # m (a + g), along +z


def test_forward_kinematics_honours_origins_and_axes():
    """Every UR5 link frame at q0 where the product of the URDF's origins and joint rotations
    puts it."""
    import yourdfpy
    path = os.path.join(DATA, "ur5_robot.urdf")
    q = {"shoulder_pan_joint": 0.3, "shoulder_lift_joint": -0.7, "elbow_joint": 1.1,
         "wrist_1_joint": -0.4, "wrist_2_joint": 0.9, "wrist_3_joint": 0.2}
    robot = ph.load_urdf(path, q0=q, limits="ignore")
    u = yourdfpy.URDF.load(path, build_scene_graph=False, load_meshes=False).robot
    children = {j.child for j in u.joints}
    pose = {lk.name: np.eye(4) for lk in u.links if lk.name not in children}   # the root
    assert len(pose) == 1
    pending = list(u.joints)
    for _ in range(len(pending)):
        for j in list(pending):
            if j.parent in pose:
                motion = se3.rotation(np.array(j.axis), q[j.name]) if j.name in q else np.eye(4)
                pose[j.child] = pose[j.parent] @ j.origin @ motion
                pending.remove(j)
    assert not pending
    for link, H in pose.items():
        np.testing.assert_allclose(robot.mechanism.world_pose(robot.frames[link]), H, atol=1e-12)


def test_fixed_joints_lump_links_into_one_body(tmp_path):
    """Two links welded by a fixed joint: one body with the sum of the masses, their centre of
    mass and the parallel-axis inertia; a massless frame link welded on adds nothing."""
    path = write(tmp_path, """<robot name="r">
  <link name="base"/>
  <joint name="j" type="continuous"><parent link="base"/><child link="a"/><axis xyz="0 0 1"/></joint>
  <link name="a"><inertial><mass value="2"/><origin xyz="0.1 0 0"/>
    <inertia ixx="0.01" iyy="0.02" izz="0.03" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="w" type="fixed"><parent link="a"/><child link="b"/><origin xyz="0.5 0 0" rpy="0 0 1.5707963267948966"/></joint>
  <link name="b"><inertial><mass value="1"/><origin xyz="0.1 0 0"/>
    <inertia ixx="0.01" iyy="0.02" izz="0.03" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="tool" type="fixed"><parent link="b"/><child link="tcp"/><origin xyz="0 0.2 0"/></joint>
  <link name="tcp"/>
</robot>""")
    robot = ph.load_urdf(path)
    assert robot.bodies == {"a": ("a", "b", "tcp")}
    assert list(robot.joints) == ["j"]
    # about the joint axis z: 0.03 + 2 0.1^2 + 0.03 + 1 (0.5^2 + 0.1^2) (b's com at (0.5, 0.1))
    Jz = 0.03 + 2 * 0.01 + 0.03 + 1 * (0.25 + 0.01)
    tau = ph.urdf.inverse_dynamics(path, [0.0], [0.0], [1.0])[0]
    assert tau == pytest.approx(Jz, rel=1e-10)
    np.testing.assert_allclose(robot.mechanism.world_pose(robot.frames["tcp"])[:3, 3],
                               [0.5 - 0.2, 0.0, 0.0], atol=1e-14)


def test_flexible_link_is_a_cantilever(tmp_path):
    """A link replaced by a flexible steel rod, its joint held (driven by a constant), a tip
    link of 1 mg welded on, no gravity: its first bending frequency is the Euler-Bernoulli
    cantilever's 1.8751^2 sqrt(EI / (rho A L^4)) / (2 pi) (slender: shear and rotary inertia
    below 1e-4), within 1e-3."""
    path = write(tmp_path, """<robot name="r">
  <link name="base"/>
  <joint name="root" type="revolute"><parent link="base"/><child link="rod"/>
    <axis xyz="0 0 1"/><origin rpy="0 0 0.3"/></joint>
  <link name="rod"><inertial><mass value="5"/><inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="tip" type="fixed"><parent link="rod"/><child link="tipmass"/><origin xyz="0 0.6 0.8"/></joint>
  <link name="tipmass"><inertial><mass value="1e-6"/><inertia ixx="1e-12" iyy="1e-12" izz="1e-12" ixy="0" ixz="0" iyz="0"/></inertial></link>
</robot>""")
    steel = ph.Material(E=210e9, nu=0.3, density=7850.0)
    sec = ph.Section.circle(0.01)
    robot = ph.load_urdf(path, {"rod": dict(section=sec, material=steel, elements=20)},
                         gravity=(0, 0, 0), driven={"root": 0.0})
    lk = robot.flexible["rod"]
    assert lk.length == pytest.approx(1.0, rel=1e-14)
    assert robot.replaced_mass["rod"] == pytest.approx((5.0, 7850 * sec.A), rel=1e-12)
    # the rod runs from the joint to the tip joint's origin
    H = robot.mechanism.world_pose(lk.end)
    np.testing.assert_allclose(H[:3, 3], se3.rotation("z", 0.3)[:3, :3] @ [0, 0.6, 0.8], atol=1e-14)
    np.testing.assert_allclose(robot.mechanism.world_pose(robot.frames["tipmass"])[:3, 3], H[:3, 3],
                               atol=1e-14)
    f = robot.mechanism.modes(1).frequency[0]
    f_eb = 1.875104 ** 2 * np.sqrt(steel.E * sec.I_y / (steel.density * sec.A)) / (2 * np.pi)
    assert f == pytest.approx(f_eb, rel=1e-3)


def test_ur5_with_a_flexible_forearm_runs_with_the_defaults():
    """The flexible-forearm robot in three lines: it simulates with the defaults and its
    forearm is the link the URDF says (0.39225 m, from the elbow to the wrist)."""
    tube = (ph.Section.tube(0.09, 0.082), ph.Material(E=70e9, nu=0.33, density=2700.0))
    robot = ph.load_urdf(os.path.join(DATA, "ur5_robot.urdf"), flexible={"forearm_link": tube},
                         limits="ignore", q0={"shoulder_lift_joint": -1.2})
    res = robot.mechanism.simulate(0.2, 0.01)
    assert robot.flexible["forearm_link"].length == pytest.approx(0.39225, rel=1e-14)
    assert res.stats["ledger_relative"] < 1e-3
    rigid = ph.load_urdf(os.path.join(DATA, "ur5_robot.urdf"), limits="ignore",
                         q0={"shoulder_lift_joint": -1.2})
    for link in ("forearm_link", "wrist_1_link", "ee_link"):   # the same geometry at rest
        np.testing.assert_allclose(robot.mechanism.world_pose(robot.frames[link]),
                                   rigid.mechanism.world_pose(rigid.frames[link]), atol=1e-12)


ONE_BODY = """<robot name="r">
  <link name="base"/>
  <joint name="j" type="{jtype}"><parent link="base"/><child link="b"/>
    <origin xyz="0.1 0.2 0.3" rpy="0.2 0.1 -0.3"/><axis xyz="{axis}"/></joint>
  <link name="b"><inertial><mass value="2"/>
    <inertia ixx="0.01" iyy="0.02" izz="0.03" ixy="0" ixz="0" iyz="0"/></inertial></link>
</robot>"""


def test_joints_in_depth_first_order(tmp_path):
    """A branched tree: the joints depth-first from the root, in file order at each link (the
    order Pinocchio numbers them: rA, AA1, rB)."""
    link = '<inertial><mass value="1"/><inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial>'
    joint = '<joint name="{}" type="continuous"><parent link="{}"/><child link="{}"/></joint>'
    path = write(tmp_path, '<robot name="t"><link name="r"/>' + joint.format("rA", "r", "A") +
                 joint.format("rB", "r", "B") + joint.format("AA1", "A", "A1") +
                 "".join(f'<link name="{n}">{link}</link>' for n in ("A", "B", "A1")) + "</robot>")
    assert list(ph.load_urdf(path).joints) == ["rA", "AA1", "rB"]


def test_floating_joint_falls_freely(tmp_path):
    """A floating joint (Free pair: x = rotation vector, position in the joint frame): from a
    given position and velocity the body falls as p0 + v t + g t^2 / 2 (in the joint frame),
    turning at its constant angular velocity about its principal axis z."""
    path = write(tmp_path, ONE_BODY.format(jtype="floating", axis="1 0 0"))
    p0, v0, w = np.array([0.3, -0.2, 0.5]), np.array([1.0, 0.5, 2.0]), 3.0
    robot = ph.load_urdf(path, q0={"j": [0, 0, 0, *p0]}, qdot0={"j": [0, 0, w, *v0]})
    assert robot.joints["j"].k == 6
    res = robot.mechanism.simulate(0.5, 0.05, integrator="ida", rtol=1e-10)
    t = res.t[:, None]
    Rj = (se3.rotation("z", -0.3) @ se3.rotation("y", 0.1) @ se3.rotation("x", 0.2))[:3, :3]
    g = Rj.T @ np.array([0, 0, -9.81])            # gravity in the joint frame
    x = res.joint("j")["x"]
    np.testing.assert_allclose(x[:, 3:], p0 + v0 * t + 0.5 * g * t ** 2, atol=1e-8)
    np.testing.assert_allclose(x[:, :3], np.column_stack([0 * t, 0 * t, w * t]), atol=1e-8)


def test_planar_joint_moves_in_its_plane(tmp_path):
    """A planar joint with normal z (Planar pair: x = angle, p_x, p_y), no gravity: the body
    slides at its initial in-plane velocity and turns at its initial rate."""
    path = write(tmp_path, ONE_BODY.format(jtype="planar", axis="0 0 1"))
    robot = ph.load_urdf(path, q0={"j": [0.1, 0.2, -0.1]}, qdot0={"j": [1.5, 0.4, -0.3]},
                         gravity=(0, 0, 0))
    res = robot.mechanism.simulate(1.0, 0.1, integrator="ida", rtol=1e-10)
    x, t = res.joint("j")["x"], res.t
    # the body's centre of mass sits on the pair frames' origin: p moves in the joint frame at
    # the initial velocity dp/dt expressed in F_a, whatever the rotation
    np.testing.assert_allclose(x[:, 0], 0.1 + 1.5 * t, atol=1e-8)
    np.testing.assert_allclose(x[:, 1], 0.2 + 0.4 * t, atol=1e-8)
    np.testing.assert_allclose(x[:, 2], -0.1 - 0.3 * t, atol=1e-8)


def test_floating_base_centre_of_mass_falls_as_a_point():
    """The UR5 on a floating base, placed by base_pose, its joints moving: its centre of mass
    falls exactly as a point mass, c0 + g t^2 / 2 (momentum: gravity is the only external
    force)."""
    H = se3.translation([1.0, 2.0, 3.0]) @ se3.rotation("x", 0.3)
    robot = ph.load_urdf(os.path.join(DATA, "ur5_robot.urdf"), base="floating", base_pose=H,
                         limits="ignore", qdot0={"elbow_joint": 2.0, "wrist_1_joint": -1.0})
    m = robot.mechanism
    np.testing.assert_allclose(m.world_pose(robot.frames["base_link"]), H, atol=1e-14)
    # the root link (UR5's "world") and the links welded to it are the base body
    assert robot.bodies["world"] == ("world", "base_link", "base")
    res = m.simulate(0.3, 0.05, integrator="ida", rtol=1e-10)
    c = res.centre_of_mass()
    v0 = res.momentum().linear[0] / res.mass()
    assert np.linalg.norm(v0) > 0.01          # the joints' motion moves the centre of mass
    t = res.t[:, None]
    np.testing.assert_allclose(c, c[0] + v0 * t + 0.5 * np.array([0, 0, -9.81]) * t ** 2, atol=1e-8)


def test_the_imported_robot_saves_and_reloads_bit_identically(tmp_path):
    """load_urdf uses only the builder's add_* calls: the model file replays them without the
    URDF (Mechanism.save's promise: bit-identical results)."""
    robot = ph.load_urdf(os.path.join(DATA, "panda.urdf"), mimic="free", limits="ignore",
                         q0={"panda_joint2": 0.5})
    robot.mechanism.save(tmp_path / "panda.json")
    a = robot.mechanism.simulate(0.1, 0.05)
    b = ph.load(tmp_path / "panda.json").simulate(0.1, 0.05)
    assert np.array_equal(a.joints, b.joints) and np.max(np.abs(a.joints[-1] - a.joints[0])) > 1e-3


# ------------------------------------------------------------------ options and warnings
def test_limits_warn_by_default_and_can_be_refused():
    path = os.path.join(DATA, "ur5_robot.urdf")
    with pytest.warns(ph.AccuracyWarning, match=r"6 joints have position limits.*elbow_joint \[-3.14159, 3.14159\]") as w:
        ph.load_urdf(path)
    assert w[0].filename == __file__            # the warning points at the user's line
    with pytest.raises(ph.ModelError, match="joint 'shoulder_pan_joint' has position limits"):
        ph.load_urdf(path, limits="error")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        ph.load_urdf(path, limits="ignore")


def test_joint_friction_is_warned_about(tmp_path):
    text = two_link(joint_type="continuous").replace(
        '<axis xyz="0 0 1"/></joint>', '<axis xyz="0 0 1"/><dynamics damping="0.5" friction="0.2"/></joint>')
    with pytest.warns(ph.AccuracyWarning, match=r"friction> of 1 joints is not modelled.*j1 \(0.2\)"):
        robot = ph.load_urdf(write(tmp_path, text), gravity=(0, 0, 0), qdot0={"j1": 1.0})
    # the damping is there: -0.5 N m s/rad times the rate
    res = robot.mechanism.simulate(0.01, 0.01)
    assert res.joint("j1")["effort"][0, 0] == pytest.approx(-0.5, rel=1e-12)


def test_mimic_joints_are_refused_unless_free():
    path = os.path.join(DATA, "panda.urdf")
    with pytest.raises(ph.ModelError, match="joint 'panda_finger_joint2' mimics joint "
                                            "'panda_finger_joint1'.*mimic='free'"):
        ph.load_urdf(path, limits="ignore")
    robot = ph.load_urdf(path, limits="ignore", mimic="free", qdot0={"panda_joint1": 2.0})
    assert robot.dof == 9
    # Panda's <dynamics damping value="0.003"/> as a damper on each joint: effort -0.003 qdot
    res = robot.mechanism.simulate(0.01, 0.01)
    assert res.joint("panda_joint1")["effort"][0, 0] == pytest.approx(-0.006, rel=1e-12)


# ------------------------------------------------------------------ bad files
GOOD_LINK = ('<inertial><mass value="1"/><inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" '
             'iyz="0"/></inertial>')


def two_link(joint_type="revolute", child_inertial=GOOD_LINK, parent="base", extra=""):
    return f"""<robot name="bad">
  <link name="base"/>
  <joint name="j1" type="{joint_type}"><parent link="{parent}"/><child link="arm"/><axis xyz="0 0 1"/></joint>
  <link name="arm">{child_inertial}</link>
  {extra}
</robot>"""


@pytest.mark.parametrize("text, message", [
    (two_link(child_inertial=""), r"link 'arm' has no <inertial>, but it moves \(joint 'j1'\)"),
    (two_link(child_inertial=GOOD_LINK.replace('value="1"', 'value="0"')),
     r"link 'arm' has zero mass, but it moves \(joint 'j1'\)"),
    (two_link(joint_type="ball"), r"joint 'j1' has unknown type 'ball'"),
    (two_link(parent="nowhere"), r"joint 'j1' names parent link 'nowhere', which is not a link"),
    (two_link(extra='<joint name="j2" type="revolute"><parent link="base"/><child link="arm"/>'
                    '<axis xyz="1 0 0"/></joint>'),
     r"link 'arm' is the child of two joints, 'j1' and 'j2': a closed loop"),
    (two_link(extra='<link name="loose"/>'), r"2 root links \('base', 'loose'\)"),
    (two_link(child_inertial=GOOD_LINK.replace('ixx="0.1"', 'ixx="0"')),
     r"link 'arm': its inertia about the centre of mass .* is not positive definite"),
])
def test_bad_urdf_gets_a_model_error_naming_the_element(tmp_path, text, message):
    with pytest.raises(ph.ModelError, match=message):
        ph.load_urdf(write(tmp_path, text))


def test_a_loop_through_the_root_is_named(tmp_path):
    text = """<robot name="bad">
  <link name="a">""" + GOOD_LINK + """</link><link name="b">""" + GOOD_LINK + """</link>
  <joint name="ab" type="revolute"><parent link="a"/><child link="b"/></joint>
  <joint name="ba" type="revolute"><parent link="b"/><child link="a"/></joint>
</robot>"""
    with pytest.raises(ph.ModelError, match="closed loop"):
        ph.load_urdf(write(tmp_path, text))


def test_bad_arguments(tmp_path):
    path = os.path.join(DATA, "ur5_robot.urdf")
    with pytest.raises(ph.ModelError, match="no such file"):
        ph.load_urdf(str(tmp_path / "missing.urdf"))
    with pytest.raises(ph.ModelError, match="cannot be parsed"):
        ph.load_urdf(write(tmp_path, "<robot name='x'><link name='a'>"))
    with pytest.raises(ph.ModelError, match="q0: 'elbow' is not a movable joint"):
        ph.load_urdf(path, q0={"elbow": 1.0}, limits="ignore")
    with pytest.raises(ph.ModelError, match="flexible: 'forearm' is not a link"):
        ph.load_urdf(path, flexible={"forearm": None}, limits="ignore")
    with pytest.raises(ph.ModelError, match="link 'ee_link' has zero mass, but it is a body of its "
                                            "own: joint 'ee_fixed_joint' welds it to flexible link "
                                            "'wrist_3_link'"):
        ph.load_urdf(path, flexible={"wrist_3_link": (ph.Section.circle(0.05),
                                                      ph.Material(70e9, 0.3, 2700.0))},
                     limits="ignore")
    with pytest.raises(ph.ModelError, match="flexible link 'ee_link' has 0 child joints"):
        ph.load_urdf(path, flexible={"ee_link": (ph.Section.circle(0.05),
                                                 ph.Material(70e9, 0.3, 2700.0))}, limits="ignore")


# ------------------------------------------------------------------ the example
def test_example_runs_quick():
    out = subprocess.run([sys.executable, os.path.join(EXAMPLES, "urdf_robot.py"), "--quick", "--json"],
                         capture_output=True, text=True, check=True).stdout
    d = json.loads(out)
    assert d["rigid"]["ledger_relative"] < 1e-4 and d["rigid"]["error_estimate"] <= 1.0
    f = d["flexible"]["modes_hz_joints_held"]
    assert len(f) == 4 and 10 < f[0] < 1e3 and f == sorted(f)

"""Kinematic pairs, actuators, spring-dampers, interactions and the per-port ledger, against
analytic references (elliptic-integral pendulum period, Newton/Euler, damped oscillator)."""
import numpy as np
import pytest
from scipy.special import ellipk
from scipy.optimize import brentq

import phmech as pm   # the public names
from phmech import se3

G = 9.81


def pendulum(I_c=0.05, gravity=True, **pair_kw):
    m = pm.Mechanism(gravity=(0, 0, -G) if gravity else (0, 0, 0))
    b = m.add_rigid_body("b", 1.0, np.diag([0.03, I_c, 0.04]), com=(1.0, 0, 0))
    m.add_pair("j", pm.Revolute(axis="y"), m.ground, b, **pair_kw)
    return m, 1.0 + I_c  # I_O = I_c + m d^2


def crossings(t, y):
    """Times where y crosses zero, by a cubic through the 4 nearest samples."""
    out = []
    for i in np.nonzero(np.sign(y[:-1]) * np.sign(y[1:]) < 0)[0]:
        lo = max(i - 1, 0)
        ts, ys = t[lo:lo + 4], y[lo:lo + 4]
        c = np.polyfit(ts - t[i], ys, len(ts) - 1)
        r = np.roots(c)
        r = r[np.isreal(r)].real
        r = r[(r >= 0) & (r <= t[i + 1] - t[i])]
        out.append(t[i] + r[0])
    return np.array(out)


def test_compound_pendulum_period_and_energy():
    m, IO = pendulum(x0=0.0)
    T = 4 * np.sqrt(IO / (1.0 * G * 1.0)) * ellipk(np.sin(np.pi / 4) ** 2)
    n = 20
    r = m.simulate(n * T, 2e-3, rtol=1e-10, integrator="ida")
    xd = r.joint("j")["xdot"][:, 0]
    tc = crossings(r.t, xd)            # extremes: every half period
    periods = np.diff(tc[::2])
    assert len(periods) >= n - 2
    assert abs(periods.mean() / T - 1) < 1e-6
    drift = np.max(np.abs(r.energy["total"] - r.energy["total"][0])) / (1.0 * G * 1.0)
    assert drift < 1e-5
    assert np.max(np.abs(r.energy["ledger"])) < 1e-5 * G
    # the angle swings between 0 and pi (released from horizontal), multi-turn continuous
    x = r.joint("j")["x"][:, 0]
    assert abs(x.max() - np.pi) < 1e-5 and abs(x.min()) < 1e-5


# (pair, allowed body wrench, constrained body wrench, expected x(t) for mass 2, J = diag(.2,.3,.4))
MASS, J = 2.0, np.array([0.2, 0.3, 0.4])
CASES = {
    "revolute": (pm.Revolute(), [0, 0, .3, 0, 0, 0], [.5, 0, 0, 2, 0, 0], lambda t: [.3 * t**2 / (2 * J[2])]),
    "prismatic": (pm.Prismatic(), [0, 0, 0, 0, 0, 2], [0, 0, .4, 1, 0, 0], lambda t: [2 * t**2 / (2 * MASS)]),
    "helical": (pm.Helical(pitch=0.05), [0, 0, .3, 0, 0, 0], [0, 0, 0, 1, 0, 0],
                lambda t: [.3 * t**2 / (2 * (J[2] + MASS * 0.05**2))]),
    "cylindrical": (pm.Cylindrical(), [0, 0, .3, 0, 0, 2], [.2, 0, 0, 1, 0, 0],
                    lambda t: [.3 * t**2 / (2 * J[2]), 2 * t**2 / (2 * MASS)]),
    "universal": (pm.Universal(), [.3, 0, 0, 0, 0, 0], [0, 0, .2, 0, 1, 0], lambda t: [.3 * t**2 / (2 * J[0]), 0]),
    "spherical": (pm.Spherical(), [0, 0, .3, 0, 0, 0], [0, 0, 0, 1, 0, 0], lambda t: [0, 0, .3 * t**2 / (2 * J[2])]),
    "planar": (pm.Planar(), [0, 0, 0, 2, 0, 0], [.3, 0, 0, 0, 0, 1], lambda t: [0, 2 * t**2 / (2 * MASS), 0]),
    "free": (pm.Free(), [0, 0, 0, 0, 2, 0], [0] * 6, lambda t: [0, 0, 0, 0, 2 * t**2 / (2 * MASS), 0]),
}


@pytest.mark.parametrize("kind", list(CASES))
def test_pair_allowed_motion_is_free_and_constraints_hold(kind):
    pair, wa, wc, expect = CASES[kind]
    m = pm.Mechanism()
    H0 = se3.translation([0.1, -0.2, 0.3])
    b = m.add_rigid_body("b", MASS, np.diag(J))
    m.add_pair("j", pair, pm.Frame(-1, H0), b, x0=np.zeros(pair.k))   # places b at H0
    m.add_wrench("w", b, np.add(wa, wc), frame="body")
    r = m.simulate(1.0, 0.1, rtol=1e-10, integrator="ida")
    x = r.joint("j")["x"]
    ref = np.array([expect(t) for t in r.t])
    assert np.max(np.abs(x - ref)) <= 1e-6 * max(1.0, np.max(np.abs(ref)))
    # constrained directions: the pose equals the forward kinematics of the extracted coordinates
    err = max(np.max(np.abs(se3.log(np.linalg.inv(H0 @ pair._fk(xi)) @ H)))
              for xi, H in zip(x, r.poses[:, 0]))
    assert err <= 1e-8
    assert np.max(np.abs(r.energy["ledger"])) <= 1e-7 * max(1e-3, r.energy["kinetic"].max())


def test_pd_revolute_reaches_set_point_and_ledger():
    m = pm.Mechanism()
    b = m.add_rigid_body("b", 1.0, np.diag([0.1, 0.1, 0.1]), com=(0.5, 0, 0))
    m.add_pair("j", pm.Revolute(), m.ground, b, x0=0.0,
               actuator=pm.PD(kp=20.0, kd=4.0, target=pm.Cycloidal(value=1.0, duration=1.0)))
    r = m.simulate(6.0, 0.01, rtol=1e-9, integrator="ida")
    jt = r.joint("j")
    assert abs(jt["x"][-1, 0] - 1.0) < 1e-4 and abs(jt["xdot"][-1, 0]) < 1e-3
    scale = r.energy["kinetic"].max()
    assert np.max(np.abs(r.energy["ledger"])) <= 1e-6 * scale
    # independent: E(t) - E(0) equals the actuator port energy; and the port power is u . xdot
    E = r.energy["total"]
    assert np.max(np.abs(E - E[0] - r.port_energy["j"])) <= 1e-6 * scale
    P = np.gradient(r.port_energy["j"], r.t)
    assert np.max(np.abs(P - jt["effort"][:, 0] * jt["xdot"][:, 0])[5:-5]) < 1e-2 * np.max(np.abs(P))


def test_spring_damper_oscillator():
    k, c, mass, a0 = 400.0, 2.0, 1.5, 0.05
    m = pm.Mechanism()
    b = m.add_rigid_body("b", mass, np.eye(3) * 0.01, pose=se3.translation([0, 0, 1.0 + a0]))
    m.add_pair("slide", pm.Prismatic(), m.ground, b, x0=1.0 + a0)
    m.add_spring_damper("s", m.ground, b, k=k, c=c, rest_length=1.0)
    r = m.simulate(2.0, 1e-3, rtol=1e-10, integrator="ida")
    z = r.joint("slide")["x"][:, 0] - 1.0
    w0, zeta = np.sqrt(k / mass), c / (2 * np.sqrt(k * mass))
    wd = w0 * np.sqrt(1 - zeta**2)
    ref = a0 * np.exp(-zeta * w0 * r.t) * (np.cos(wd * r.t) + zeta * w0 / wd * np.sin(wd * r.t))
    assert np.max(np.abs(z - ref)) < 1e-7
    tc = crossings(r.t, z)
    assert abs(np.mean(np.diff(tc[::2])) / (2 * np.pi / wd) - 1) < 1e-6
    E = r.energy["total"]
    assert np.max(np.abs(E - E[0] - r.port_energy["s"])) < 1e-7 * E[0]
    assert np.max(np.abs(r.energy["ledger"])) < 1e-7 * E[0]


def test_joint_spring_modes_and_statics():
    # modes: revolute with a joint spring, no gravity: omega = sqrt(k / I_O)
    m, IO = pendulum(gravity=False, x0=0.0, actuator=pm.Spring(k=30.0))
    mo = m.modes(1)
    assert abs(mo.omega[0] / np.sqrt(30.0 / IO) - 1) < 1e-6
    # statics with gravity: k theta = m g d cos(theta) (rotation about y lowers the body)
    m, IO = pendulum(x0=0.0, actuator=pm.Spring(k=30.0))
    st = m.static(steps=5)
    R = st.poses[0, :3, :3]
    th = np.arctan2(-R[2, 0], R[0, 0])
    ref = brentq(lambda t: 30.0 * t - G * np.cos(t), 0, np.pi / 2)
    assert abs(th - ref) < 1e-8
    # modes at the hanging equilibrium of the plain pendulum: omega = sqrt(m g d / I_O)
    m, IO = pendulum(x0=np.pi / 2)
    mo = m.modes(1, at=m.static())
    assert abs(mo.omega[0] / np.sqrt(G / IO) - 1) < 1e-6


def test_interaction_between_bodies_is_internal():
    m = pm.Mechanism()
    b1 = m.add_rigid_body("b1", 1.0, np.eye(3) * 0.1)
    b2 = m.add_rigid_body("b2", 3.0, np.eye(3) * 0.1, pose=se3.translation([1.0, 0, 0]))
    m.add_pair("s1", pm.Prismatic(axis="x"), m.ground, b1, x0=0.0)
    m.add_pair("s2", pm.Prismatic(axis="x"), m.ground, b2, x0=1.0)
    m.add_interaction("push", b2, (0, 0, 0, 2.0, 0, 0), law=pm.Pulse(0.0, 0.5, 1.0), reaction=b1)
    r = m.simulate(1.0, 0.01, rtol=1e-10, integrator="ida")
    v1, v2 = r.joint("s1")["xdot"][:, 0], r.joint("s2")["xdot"][:, 0]
    assert np.max(np.abs(1.0 * v1 + 3.0 * v2)) < 1e-9            # momentum of the pair conserved
    assert abs(v2[-1] - 2.0 * 0.5 / 3.0) < 1e-9                   # impulse / mass
    assert abs(r.port_energy["push"][-1] - r.energy["kinetic"][-1]) < 1e-9


def test_multiturn_spin_and_helical_coordinates():
    m = pm.Mechanism()
    b = m.add_rigid_body("b", 1.0, np.diag([0.1, 0.1, 0.2]))
    m.add_pair("h", pm.Helical(axis="x", pitch=0.01), m.ground, b, x0=0.0, xdot0=20.0)
    r = m.simulate(2.0, 0.01, rtol=1e-10, integrator="ida")
    x = r.joint("h")["x"][:, 0]
    assert abs(x[-1] - 40.0) < 1e-6                               # 6+ turns, continuous
    assert np.max(np.abs(r.poses[:, 0, 0, 3] - 0.01 * x)) < 1e-9   # translation = pitch * angle


@pytest.mark.parametrize("build, msg", [
    (lambda m, b: m.add_pair("p", pm.Revolute(), m.ground, "nobody"), "unknown"),
    (lambda m, b: m.add_pair("p", pm.Revolute(), b, b), "same carrier"),
    (lambda m, b: m.add_pair("b", pm.Revolute(), m.ground, b), "already used"),
    (lambda m, b: m.add_pair("p", pm.Revolute(axis="w"), m.ground, b), "axis"),
    (lambda m, b: m.add_pair("p", pm.Helical(pitch=float("nan")), m.ground, b), "finite"),
    (lambda m, b: m.add_pair("p", pm.Revolute(), m.ground, b, actuator=pm.PD(kp=float("nan"), kd=1)), "finite"),
    (lambda m, b: m.add_spring_damper("s", m.ground, b, k=-1.0), ">= 0"),
    (lambda m, b: m.add_pair("p", pm.Revolute(), m.ground, b, driven=pm.Motion([0, 0, 1, 0, 0, 0], pm.Constant(1))), "Fixed"),
])
def test_model_errors(build, msg):
    m = pm.Mechanism()
    b = m.add_rigid_body("b", 1.0, np.eye(3))
    with pytest.raises(pm.ModelError, match=msg):
        build(m, b)


def test_x0_places_a_link_through_the_spanning_tree():
    # The initial configuration walks the tree from the ground (docs/method.md section 5.3): a
    # link hinged to the ground with x0 = 0.5 rad about z starts rotated by 0.5 rad, unstressed.
    m = pm.Mechanism()
    lk_props = type("P", (), dict(stiffness=np.eye(6) * 1e3, inertia=np.eye(6) * 0.1))
    lk = m.add_flexible_link("L", 1.0, lk_props, elements=2)
    m.add_pair("p", pm.Revolute(), m.ground, lk.start, x0=0.5)
    r = m.simulate(0.01, 0.01, integrator="ida")
    np.testing.assert_allclose(r.tip(lk)[0], [np.cos(0.5), np.sin(0.5), 0.0], atol=1e-12)
    assert r.energy["elastic"][0] < 1e-20
    np.testing.assert_allclose(r.joint("p")["x"][0], 0.5, atol=1e-12)


def _bindings_of_package_init() -> dict:
    """Each name that phmech/__init__.py binds at its top level -> the list of places that bind
    it: ("module", its name) for ``from .m import a`` and ``from . import m``, the module's
    ``__all__`` for ``from .m import *``, ("phmech", line) for its own defs and assignments."""
    import ast
    import importlib
    tree = ast.parse(open(pm.__file__, encoding="utf-8").read())
    out: dict = {}
    for node in tree.body:
        if isinstance(node, ast.ImportFrom) and node.level == 1:
            for al in node.names:
                if al.name == "*":
                    mod = importlib.import_module(f"phmech.{node.module}")
                    for n in mod.__all__:
                        out.setdefault(n, []).append((node.module, n))
                elif node.module is None:   # from . import m [as n]
                    out.setdefault(al.asname or al.name, []).append((al.name, None))
                else:
                    out.setdefault(al.asname or al.name, []).append((node.module, al.name))
        elif isinstance(node, (ast.FunctionDef, ast.ClassDef)):
            out.setdefault(node.name, []).append(("phmech", node.lineno))
        elif isinstance(node, ast.Assign):
            for t in node.targets:
                if isinstance(t, ast.Name):
                    out.setdefault(t.id, []).append(("phmech", node.lineno))
    return out


def test_no_public_name_is_bound_twice():
    # phmech/__init__.py takes the pair classes with `from .pairs import *` (a pair type added to
    # the core's table, csrc/model/pair_types.c, needs no line there): a pair class named like
    # another public name (a law's "Linear", a component's "DCMotor") would silently replace it,
    # or be replaced by a later import. Every top-level name of the package is bound once, each
    # public one listed once in __all__, and is its module's object
    import collections
    import importlib
    twice = {n: w for n, w in _bindings_of_package_init().items() if len(w) > 1}
    assert not twice, f"phmech/__init__.py binds these names more than once: {twice}"
    listed = [n for n, c in collections.Counter(pm.__all__).items() if c > 1]
    assert not listed, f"listed more than once in phmech.__all__: {listed}"
    for name, [(module, attr)] in _bindings_of_package_init().items():
        if module != "phmech" and attr is not None:
            assert getattr(pm, name) is getattr(importlib.import_module(f"phmech.{module}"), attr), name
    # the pair classes are all exported, under their own names
    assert set(pm.pairs.__all__) <= set(pm.__all__)

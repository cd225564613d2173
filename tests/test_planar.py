"""Planar scenes (issue 13): simulate solves the in-plane DAE (csrc/dae/planar.c) when every
carrier moves in one plane, with the 3-D solve's results; other scenes stay 3-D or are refused."""
import numpy as np
import pytest

import phmech as ph
from phmech import se3
from phmech.section import table1_properties

L = 1.0


def cantilever(N=8):
    """The released Table I cantilever of benchmarks/run.py (bending in x-z: normal y)."""
    m = ph.Mechanism()
    b = m.add_flexible_link("b", L, table1_properties(1.0), elements=N)
    m.add_pair("clamp", ph.Fixed(), m.ground, b.start)
    st = m.static(loads=[(b.end, (0, 0, 0, 0, 0, -0.5), "world")], steps=4)
    return m, b, st


def fourbar():
    """benchmarks/scenes.py's rigid crank-rocker under gravity (3-D: redundant rows dropped)."""
    m = ph.Mechanism(gravity=(0, -9.81, 0))
    A, B, C, D = 0.2, 0.6, 0.5, 0.5
    bars = []
    for nm, l in (("crank", A), ("coupler", B), ("rocker", C)):
        J = np.diag([1e-4, l**2 / 12, l**2 / 12])
        bars.append(m.add_rigid_body(nm, 1.0, J, com=(l / 2, 0, 0)))
    crank, cp, rocker = bars
    T = lambda x: se3.translation([x, 0, 0])
    m.add_pair("k1", ph.Revolute("z"), m.ground, crank, x0=0.6, xdot0=4.0)
    m.add_pair("k2", ph.Revolute("z"), ph.Frame(crank.carrier, T(A)), cp)
    m.add_pair("k3", ph.Revolute("z"), ph.Frame(cp.carrier, T(B)), ph.Frame(rocker.carrier, T(C)))
    m.add_pair("k4", ph.Revolute("z"), ph.Frame(-1, T(D)), rocker)
    return m


@pytest.mark.parametrize("integrator", ["generalized-alpha", "ida"])
def test_cantilever_planar_matches_3d(integrator):
    m, b, st = cantilever()
    r3 = m.simulate(0.5, 5e-3, initial=st, integrator=integrator, planar=False)
    rp = m.simulate(0.5, 5e-3, initial=st, integrator=integrator, planar=None if integrator != "ida" else True)
    assert r3.stats["planar"] is None and rp.stats["planar"] == "y"
    # measured 2026-11-27: tip 3.3e-8 L (generalized-alpha, rtol 1e-4), 2.2e-10 L (IDA, 1e-8)
    tol = 1e-6 if integrator == "generalized-alpha" else 1e-8
    assert np.max(np.abs(rp.tip(b) - r3.tip(b))) <= tol * L
    assert rp.poses.shape == r3.poses.shape
    assert rp.stats["ledger_relative"] <= 2 * r3.stats["ledger_relative"] + 1e-9


def test_the_planarity_of_a_given_start_is_asked_of_each_start():
    """simulate keeps its planarity check of the last StaticResult it started from (a sweep of
    runs from one static state asks again with the same poses): a start bent out of the plane
    is 3-D, and planar=True from it is refused, whichever start ran before."""
    m, b, st = cantilever(4)
    bent = m.static(loads=[(b.end, (0, 0, 0, 0, 0.5, -0.5), "world")], steps=4)
    assert abs(bent.poses[-1][1, 3]) > 1e-6            # the tip left the x-z plane
    runs = [(st, "y"), (st, "y"), (bent, None), (bent, None), (st, "y")]
    for start, plane in runs:
        assert m.simulate(0.01, 5e-3, initial=start).stats["planar"] == plane
    with pytest.raises(ph.ModelError, match="planar=True: the scene is not planar"):
        m.simulate(0.01, 5e-3, initial=bent, planar=True)
    assert m.simulate(0.01, 5e-3, initial=st, planar=True).stats["planar"] == "y"


def test_fourbar_planar_matches_3d():
    m = fourbar()
    r3 = m.simulate(1.0, 1e-2, integrator="ida", rtol=1e-9, planar=False)
    rp = m.simulate(1.0, 1e-2, integrator="ida", rtol=1e-9, planar=True)
    assert rp.stats["planar"] == "z"
    x3, xp = r3.joint("k1")["x"][:, 0], rp.joint("k1")["x"][:, 0]
    assert np.max(np.abs(xp - x3)) <= 1e-6       # measured 2026-11-27: see the report
    assert rp.constraint_wrenches.shape == r3.constraint_wrenches.shape
    assert np.allclose(rp.pair_wrenches, r3.pair_wrenches, atol=1e-4 * np.abs(r3.pair_wrenches).max())
    assert rp.stats["ledger_relative"] <= 10 * r3.stats["ledger_relative"] + 1e-9


def test_non_planar_scene_is_3d_or_refused():
    m = ph.Mechanism(gravity=(0, 0, -9.81))
    J = np.diag([1e-3, 1e-2, 1e-2])
    b = m.add_rigid_body("b", 1.0, J, com=(0.2, 0, 0))
    m.add_pair("s", ph.Spherical(), m.ground, b)
    m.add_wrench("push", b, (0, 0, 0, 0, 1.0, 0.0))
    r = m.simulate(0.1, 1e-2)
    assert r.stats["planar"] is None
    with pytest.raises(ph.ModelError, match="planar=True: the scene is not planar"):
        m.simulate(0.1, 1e-2, planar=True)
    with pytest.raises(ph.ModelError, match="planar must be"):
        m.simulate(0.1, 1e-2, planar="yes")


@pytest.mark.parametrize("drive", ["law", "effort"])
def test_a_pair_driven_or_actuated_out_of_the_plane_keeps_the_scene_3d(drive):
    """A revolute about x (out of the x-y plane) whose angle follows a law, or which an effort
    drives, under a body and link lying in that plane: the scene is not planar (it once was
    taken as planar about z, the driven row dropped as out-of-plane and the law silently not
    followed: the angle stayed 0 where the 3-D solve reached the law's 0.5 rad)."""
    m = ph.Mechanism()
    b = m.add_rigid_body("b", 1.0, np.eye(3) * 0.01)
    if drive == "law":
        m.add_pair("h", ph.Revolute(axis="x"), m.ground, b, driven=ph.Cycloidal(0.5, 0.01, 0.1))
    else:
        m.add_pair("h", ph.Revolute(axis="x"), m.ground, b, actuator=ph.Effort(ph.Constant(1.0)))
    lk = m.add_flexible_link("l", 1.0, table1_properties(4.0), elements=3, start=b.frame)
    m.add_pair("w", ph.Fixed(), b, lk.start)
    r = m.simulate(0.2, 1e-2)
    assert r.stats["planar"] is None
    assert abs(r.joint("h")["x"][-1, 0]) > (0.1 if drive == "law" else 1e-3)
    with pytest.raises(ph.ModelError, match="'h' is actuated or driven along an out-of-plane axis"):
        m.simulate(0.2, 1e-2, planar=True)


def test_a_long_non_ascii_pair_name_in_a_planar_check_message():
    """The core cuts a name in a message at a byte count, which may split a UTF-8 character: it
    becomes U+FFFD, not an error (it was a SystemError in every simulate of such a scene)."""
    name = "a" + "\u00e9" * 200      # 401 bytes
    m = ph.Mechanism()
    b = m.add_rigid_body("b", 1.0, np.eye(3) * 0.01)
    m.add_pair(name, ph.Revolute(axis="x"), m.ground, b, actuator=ph.Effort(ph.Constant(1.0)))
    lk = m.add_flexible_link("l", 1.0, table1_properties(4.0), elements=3, start=b.frame)
    m.add_pair("w", ph.Fixed(), b, lk.start)
    assert m.simulate(0.02, 1e-2).stats["planar"] is None
    with pytest.raises(ph.ModelError, match="'a\u00e9+.*is actuated or driven along an out-of-plane axis"):
        m.simulate(0.02, 1e-2, planar=True)


def _planar_about_z(n=3):
    """A synthetic scene (planar.check's arguments) planar about z: n carriers, n elements,
    n couplings, n loads, one pair row in-plane and one out-of-plane."""
    rng = np.random.default_rng(1)

    def decoupled(size):   # random symmetric with no in-plane / out-of-plane entries
        A = rng.standard_normal((size, size))
        A = A + A.T
        inp = np.concatenate([ph.planar.inplane(2) + 6 * b for b in range(size // 6)])
        mask = np.isin(np.arange(size), inp)
        A[np.ix_(mask, ~mask)] = A[np.ix_(~mask, mask)] = 0.0
        return A
    c = np.cos(0.3 * np.arange(n))
    s = np.sin(0.3 * np.arange(n))
    H = np.tile(np.eye(4), (n, 1, 1))
    H[:, 0, 0], H[:, 0, 1], H[:, 1, 0], H[:, 1, 1] = c, -s, s, c
    H[:, :2, 3] = rng.standard_normal((n, 2))
    T = np.zeros((n, 6))
    T[:, [2, 3, 4]] = rng.standard_normal((n, 3))
    comp = dict(
        gravity=np.array([0.0, -9.81, 0.0]),
        carriers=dict(M=np.array([decoupled(6) for _ in range(n)]), mass=np.ones(n),
                      com=np.c_[rng.standard_normal((n, 2)), np.zeros(n)]),
        elements=dict(h=np.ones(n), K=np.array([decoupled(6) for _ in range(n)]),
                      D=np.array([decoupled(6) for _ in range(n)]), Ms=np.array([decoupled(6) for _ in range(n)]),
                      Mc=np.array([decoupled(12) for _ in range(n)]),
                      eps_hat=np.c_[np.zeros((n, 2)), np.ones(n), np.ones(n), np.zeros((n, 2))]),
        couplings=dict(Mc=np.array([decoupled(12) for _ in range(n)])),
        loads=dict(carrier=np.arange(n), w=np.c_[np.zeros((n, 2)), np.ones((n, 3)), np.zeros(n)],
                   point=np.c_[np.ones((n, 2)), np.zeros(n)]),
        springs=dict(carriers=np.zeros((0, 2)), pa=np.zeros((0, 3)), pb=np.zeros((0, 3))),
        pairs=dict(carriers=np.array([[-1, 0]]), driven=np.zeros(1), xlaws=[None]),
        actuators=dict(pair=np.zeros(0)))
    G = np.zeros((2, 6 * n))
    G[0, [2, 3]] = 1.0              # omega_z, v_x: in-plane
    G[1, [0, 5]] = 1.0              # omega_x, v_z: out-of-plane
    return comp, H, T, G, [(0, 2, 0, 0)], ["p"]


@pytest.mark.parametrize("spoil, message", [
    (None, None),
    (lambda c, H, T, G: H.__setitem__((2, 0, 2), 1e-3), "carrier 2's initial rotation is not about z"),
    (lambda c, H, T, G: T.__setitem__((2, 5), 1e-3), "carrier 2's initial twist has out-of-plane"),
    (lambda c, H, T, G: c["carriers"]["M"].__setitem__((2, 0, 2), 1e-3), "carrier 2's inertia couples"),
    (lambda c, H, T, G: c["carriers"]["com"].__setitem__((2, 2), 1e-3), "carrier 2's centre of mass is off"),
    (lambda c, H, T, G: c["elements"]["D"].__setitem__((2, 5, 3), 1e-3), "element 2's D couples"),
    (lambda c, H, T, G: c["elements"]["Mc"].__setitem__((2, 6, 8), 1e-3), "element 2's consistent mass"),
    (lambda c, H, T, G: c["elements"]["eps_hat"].__setitem__((2, 0), 1e-3), "element 2's unstressed curvature"),
    (lambda c, H, T, G: c["couplings"]["Mc"].__setitem__((2, 9, 0), 1e-3), "inertial coupling 2 couples"),
    (lambda c, H, T, G: c["loads"]["w"].__setitem__((2, 5), 1e-3), "load 2 has out-of-plane components"),
    (lambda c, H, T, G: c["loads"]["point"].__setitem__((2, 2), 1e-3), "load 2 acts at a point off the plane"),
    (lambda c, H, T, G: G.__setitem__((1, 6 * 2 + 4), 1e-3), "pair 'p''s constraint row 1 mixes"),
])
def test_planar_check_finds_every_out_of_plane_item(spoil, message):
    """Each check of python/phmech/planar.py, failed by the last item only (1e-3 against entries
    of order 1, far above its 1e-12 round-off allowance), names that item; unspoiled the scene is
    planar about z (and about no other axis)."""
    comp, H, T, G, layout, names = _planar_about_z()
    if spoil is not None:
        spoil(comp, H, T, G)
    why = ph.planar.check(comp, H, T, G, layout, names, 2)
    if message is None:
        assert why is None
        assert ph.planar.out_of_plane_rows(G, layout, len(H), 2) == [0b10]
        assert all(ph.planar.check(comp, H, T, G, layout, names, k) for k in (0, 1))
    else:
        assert why is not None and message in why, why

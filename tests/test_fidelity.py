"""Per-link fidelity (add_flexible_link(fidelity="rigid")): a rigid link against the compound
pendulum (exact small-amplitude period, and the large-amplitude one by the complete elliptic
integral), against a very stiff nonlinear link, its mass properties against closed forms, mixed
fidelities in the Fig. 3 manipulator, its API (frames, loads, results, save/load, drawing) and
bad input. docs/user_guide.md, "Model only what a scene needs"; docs/method.md, "Rigid links"."""
import sys
from pathlib import Path

import numpy as np
import pytest

import phmech as ph

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "examples"))
import manipulator as M  # noqa: E402

# the scene and its exact period: examples/fidelity.py (which prints the CPU comparison)
from fidelity import L, PROPS, compound_period, measured_period, pendulum, stiffened  # noqa: E402


# ---------------------------------------------------------------- (a) compound pendulum
@pytest.mark.parametrize("theta0", [1e-3, 1.0])
def test_rigid_link_pendulum_period(theta0):
    """The default integrator's period agrees with the exact one to 2e-5 (measured with the
    default rtol 1e-4: 2.4e-6 at 1e-3 rad against the small-amplitude formula, exact there to
    theta0^2/16 = 6e-8; 1.7e-6 at 1 rad against the elliptic-integral period, 6.6 % longer).
    The section's own rotary inertia (rhoI_y L, 4e-4 of I_O) changes T by 2e-4: the tolerance
    sees it. The ledger of an ordinary rigid body closes to 1e-5 (measured 1.6e-8, 8.5e-7)."""
    T_exact, T_small = compound_period(theta0)
    m, lk = pendulum("rigid", theta0)
    res = m.simulate(3.5 * T_exact, T_exact / 200)
    T = measured_period(res)
    ref = T_small if theta0 < 0.01 else T_exact
    assert abs(T / ref - 1) < 2e-5, (T, ref)
    if theta0 >= 0.01:   # the large-amplitude period differs from the small one: the test sees it
        assert abs(T_exact / T_small - 1) > 0.05
    assert res.stats["ledger_relative"] < 1e-5


# ---------------------------------------------------------------- (b) very stiff nonlinear link
def test_stiff_nonlinear_link_tends_to_the_rigid_link():
    """The same pendulum (1 rad, half a period) with a nonlinear link whose bending stiffness
    EI is 1e4 times steel's (first flexible mode 1.2 kHz, against 0.8 Hz swinging) against
    fidelity="rigid". With consistent mass (the default) the se3 chain's inertia is the rigid
    link's exactly (its elements' fields and the link's rigid-rotation coupling, docs/method.md
    section 4.2): measured max tip distance 5.7e-6 L (N = 4) and 5.0e-6 L (N = 8), the
    flexibility's. (Before the coupling, 0.0142 L and 0.0036 L: I_O too large by 1/(4 N^2).)
    Lumped mass keeps its trapezoid inertia, I_O + rhoA L h^2/6: 0.028 L and 0.0072 L, ratio
    3.95, the second-order convergence that says the difference is the discretization's."""
    stiff = stiffened("bending")
    T = compound_period(1.0)[0]
    diff = {}
    for mass in ("consistent", "lumped"):
        for N in (4, 8):
            tips = {}
            for fid in ("rigid", "nonlinear"):
                m, lk = pendulum(fid, 1.0, stiff, N, mass=mass)
                res = m.simulate(T / 2, T / 100)
                assert res.stats["ledger_relative"] < 3e-3
                tips[fid] = res.tip(lk)
            diff[mass, N] = np.max(np.linalg.norm(tips["rigid"] - tips["nonlinear"], axis=1)) / L
    assert diff["consistent", 4] < 1e-4 and diff["consistent", 8] < 1e-4, diff
    assert 3.0 < diff["lumped", 4] / diff["lumped", 8] < 5.0, diff


def test_nonlinear_period_is_the_rigid_links_period():
    """Steel as it is (first flexible mode ~120 Hz): examples/fidelity.py's run. The rigid
    link's period is exact (to 2e-5, measured 1.7e-6); so is the nonlinear link's with
    consistent mass (the default), whose inertia about the pivot is the continuum's exactly
    (docs/method.md section 4.2, "Mass"): measured 1.0e-6 (N = 4) and 1.5e-6 (N = 8). Before the
    link's rigid-rotation coupling the chain's inertia I_O + rhoA L h^2/12 made the period
    7.8e-3 and 1.95e-3 too long."""
    from fidelity import run
    rows = run("none", 1.0, (4, 8))
    assert rows[0]["fidelity"] == "rigid" and abs(rows[0]["period_error"]) < 2e-5
    for r in rows[1:]:
        assert abs(r["period_error"]) < 2e-5, r
        assert r["ledger_relative"] < 1e-3


# ---------------------------------------------------------------- (c) mass properties
def _carrier_inertia(m, lk):
    c = m._car[lk.nodes[0]]
    return c["M"], c["mass"], c["com"]


def test_straight_rigid_link_mass_properties():
    """Uniform rod: mass rhoA L, centre of mass at L/2, inertia about the centre
    diag(rhoJ L, rhoA L^3/12 + rhoI_y L, rhoA L^3/12 + rhoI_z L) (the section's own rotary
    inertia included); the spatial inertia about the start is add_rigid_body's of these."""
    m = ph.Mechanism()
    lk = m.add_flexible_link("rod", L, PROPS, elements=5, fidelity="rigid")
    Mb, mass, com = _carrier_inertia(m, lk)
    rhoA, rhoJ, rhoIy, rhoIz = (PROPS.inertia[i, i] for i in (3, 0, 1, 2))
    assert mass == pytest.approx(rhoA * L, rel=1e-14)
    np.testing.assert_allclose(com, [L / 2, 0, 0], atol=1e-15)
    J = np.diag([rhoJ * L, rhoA * L ** 3 / 12 + rhoIy * L, rhoA * L ** 3 / 12 + rhoIz * L])
    ref = ph.Mechanism()
    b = ref.add_rigid_body("b", rhoA * L, J, com=(L / 2, 0, 0))
    np.testing.assert_allclose(Mb, ref._car[b.carrier]["M"], rtol=1e-13, atol=1e-16)
    m.add_pair("float", ph.Free(), m.ground, lk.start)   # the rod flies freely, and says so
    res = m.simulate(0.01, 0.01)
    assert res.mass(lk) == pytest.approx(rhoA * L, rel=1e-14)


def test_curved_rigid_link_mass_properties():
    """A quarter circle (curvature kappa_z = pi/(2 L)): p(s) = (sin ks/k, (1 - cos ks)/k, 0);
    mass rhoA L, centroid ((1 - cos kL)/(k^2 L), (L - sin(kL)/k)/(k L), 0), and the inertia
    about the start's z axis rhoA (2 L - 2 sin(kL)/k)/k^2 + rhoI_z L (section z stays world z).
    The node frames lie on the arc, tangent to it; a follower distributed load is its exact
    resultant."""
    k = np.pi / (2 * L)
    m = ph.Mechanism()
    lk = m.add_flexible_link("arc", L, PROPS, elements=6, curvature=(0, 0, k), fidelity="rigid")
    Mb, mass, com = _carrier_inertia(m, lk)
    rhoA, rhoIz = PROPS.inertia[3, 3], PROPS.inertia[2, 2]
    assert mass == pytest.approx(rhoA * L, rel=1e-13)
    np.testing.assert_allclose(com, [(1 - np.cos(k * L)) / (k * k * L),
                                     (L - np.sin(k * L) / k) / (k * L), 0], rtol=1e-12, atol=1e-15)
    assert Mb[2, 2] == pytest.approx(rhoA * (2 * L - 2 * np.sin(k * L) / k) / k ** 2 + rhoIz * L,
                                     rel=1e-12)
    end = lk.end.T
    np.testing.assert_allclose(end[:3, 3], [1 / k, 1 / k, 0], atol=1e-14)
    np.testing.assert_allclose(end[:3, 0], [0, 1, 0], atol=1e-14)     # tangent at the end
    # a follower load q along each section's y (towards the centre): resultant force
    # q ((cos kL - 1)/k, sin(kL)/k, 0) = q (-1/k, 1/k, 0), moment about the start q (1 - cos kL)/k^2
    m.add_distributed_load("p", lk, (0, 2.0, 0), frame="body")
    ld = m._loads[-1]
    assert not ld["world"]
    np.testing.assert_allclose(ld["w"], 2.0 * np.array([0, 0, 1 / k ** 2, -1 / k, 1 / k, 0]),
                               rtol=1e-12, atol=1e-14)
    np.testing.assert_allclose(ld["point"], 0, atol=0)


# ---------------------------------------------------------------- (d) mixed fidelities
def test_manipulator_with_one_rigid_link():
    """The Fig. 3 manipulator with F1 rigid and F2, F3 nonlinear: F1 is one carrier and one
    rigid vertex of the graphs, the arm moves to its set point, and the energy ledger closes
    to 1e-3 of its scale (tests/test_scenes.py's bound for the default integrator; measured
    2.0e-4 over these 1.2 s, all links nonlinear 1.5e-4; the joint k1 is 0.04 rad from its
    target at 1.2 s, tolerance 0.1: the set-point step is 0.5 rad)."""
    p = M.ManipulatorParams()
    m, h = M.build(p, elements=4, fidelity={"F1": "rigid"})
    assert h["F1"].carriers == [h["F1"].start.carrier] and len(set(h["F2"].carriers)) == 5
    g = m.graphs()
    assert g.B_K.rigid_rows == ("F1", "R1", "R2", "R3")
    assert g.B_K.flexible_rows == ("F2L", "F2R", "F3L", "F3R")
    res = m.simulate(1.2, 2e-3)
    assert res.stats["ledger_relative"] <= 1e-3, res.stats["ledger_relative"]
    assert abs(res.joint("k1")["x"][-1, 0] - p.target[0]) < 0.1
    # F1 stays straight: its end frame at L1 along its start's x axis
    Hs, He = res.pose(h["F1"].start), res.pose(h["F1"].end)
    rel = np.einsum("nji,nj->ni", Hs[:, :3, :3], He[:, :3, 3] - Hs[:, :3, 3])
    np.testing.assert_allclose(rel, np.tile([p.L1, 0, 0], (len(res.t), 1)), atol=1e-12)
    assert M.deflection(res, h["F1"]).max() < 1e-12


# ---------------------------------------------------------------- the same face
def test_rigid_link_frames_loads_results_io_and_drawing(tmp_path):
    """node(k) frames sit where the nonlinear link's nodes are on the undeformed link; a
    distributed load is its resultant (statics: the hinge torque q L^2/2 of a horizontal
    cantilever on a stiff revolute spring); record=, positions, tip, pose, momentum, modes'
    labels, stress resultants (a clear error), save/load, drawing."""
    q = 30.0
    built = {}
    for fid in ("rigid", "nonlinear"):
        m = ph.Mechanism()
        lk = m.add_flexible_link("rod", L, PROPS, elements=4, fidelity=fid)
        m.add_pair("hinge", ph.Revolute(axis="y"), m.ground, lk.start, actuator=ph.Spring(k=1e4))
        m.add_distributed_load("q", lk, (0, 0, -q))
        built[fid] = (m, lk)
    (m, lk), (mn, lkn) = built["rigid"], built["nonlinear"]
    assert lk.elements == 4 and len(lk.nodes) == 5 and lk.rigid and not lkn.rigid
    P0 = m.initial_configuration().poses
    Pn = mn.initial_configuration().poses
    for k in range(5):
        np.testing.assert_allclose(P0[lk.node(k).carrier] @ lk.node(k).T, Pn[lkn.nodes[k]], atol=1e-15)
    st = m.static()
    # the spring holds the load's moment about the hinge: k theta = q L^2 cos(theta) / 2
    theta = 0.0
    for _ in range(20):
        theta = q * L ** 2 * np.cos(theta) / 2 / 1e4
    tip = st.positions(lk)[-1]
    np.testing.assert_allclose(tip, [L * np.cos(theta), 0, -L * np.sin(theta)], rtol=1e-9, atol=1e-12)
    assert m._loads[-1]["name"] == "q" and "q" in m._desc.port_names()
    res = m.simulate(0.05, 0.01, record=[lk])
    assert res.positions(lk).shape == (len(res.t), 5, 3)
    np.testing.assert_allclose(res.tip(lk), res.position(lk.end), atol=0)
    np.testing.assert_allclose(res.positions(lk)[:, 2], res.position(lk.node(2)), atol=0)
    mom = res.momentum(lk)
    assert mom.linear.shape == (len(res.t), 3)
    with pytest.raises(ph.ModelError, match="rigid .*no stress resultants"):
        m.stress_resultants(res, lk)
    modes = m.modes(1, at=st)
    assert modes.kind == ["rigid-body"] and modes.participation[0]["rod"] == pytest.approx(1.0)
    # save / load: the same description, the same results
    path = tmp_path / "rigid.json"
    m.save(path)
    m2 = ph.load(path)
    lk2 = m2._links["rod"]
    assert lk2.rigid and np.array_equal(lk2.offsets, lk.offsets)
    r1, r2 = m.simulate(0.05, 0.01), m2.simulate(0.05, 0.01)
    np.testing.assert_array_equal(r1.poses, r2.poses)
    rpath = tmp_path / "res.nc"
    r1.to_netcdf(rpath)
    back = ph.load_result(rpath)
    np.testing.assert_array_equal(back.positions("rod"), r1.positions(lk))
    # drawing: the polyline through the node frames
    pytest.importorskip("matplotlib")
    import matplotlib
    matplotlib.use("Agg")
    import phmech.plot as pp
    ax = pp.draw(m, r1, time=0.05)
    pts = [ln.get_data_3d() if hasattr(ln, "get_data_3d") else ln.get_data() for ln in ax.get_lines()]
    assert any(np.asarray(d[0]).size == 5 for d in pts)


# ---------------------------------------------------------------- (e) bad input
def test_fidelity_bad_input():
    m = ph.Mechanism()
    with pytest.raises(ph.ModelError, match="unknown fidelity 'model'.*'nonlinear', 'rigid', 'modal'"):
        m.add_flexible_link("a", L, PROPS, fidelity="model")
    with pytest.raises(ph.ModelError, match="unknown fidelity"):
        m.add_flexible_link("a", L, PROPS, fidelity=None)
    with pytest.raises(ph.ModelError, match="elements must be an integer >= 1"):
        m.add_flexible_link("a", L, PROPS, elements=0, fidelity="rigid")
    assert not m._car and not m._links            # nothing added by failed calls
    lk = m.add_flexible_link("a", L, PROPS, elements=3, fidelity="rigid")   # elements: frames
    assert len(lk.nodes) == 4 and len(m._car) == 1
    np.testing.assert_allclose(lk.node(1).T[:3, 3], [L / 3, 0, 0], atol=1e-16)
    with pytest.raises(ph.ModelError, match="has nodes 0..3"):
        lk.node(4)
    with pytest.raises(ph.ModelError, match="give a frame of link"):
        m.add_wrench("w", lk, (0, 0, 0, 1, 0, 0))
    # the frames of a rigid link do not move relative to each other
    with pytest.raises(ph.ModelError, match="same carrier, rigid link 'a'"):
        m.add_pair("p", ph.Revolute(), lk.start, lk.end)
    with pytest.raises(ph.ModelError, match="same carrier, rigid link 'a'"):
        m.add_spring_damper("s", lk.start, lk.node(2), 10.0)
    m.add_pair("float", ph.Free(), m.ground, lk.start)   # the link flies freely, and says so
    with pytest.raises(ph.ModelError, match="rigid .*no stress resultants"):
        m.stress_resultants(m.simulate(0.01, 0.01), "a")

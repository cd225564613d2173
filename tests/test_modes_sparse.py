"""Modes by subspace iteration on the sparse KKT system (csrc/analyze/modes_sparse.c) against the dense
reduced problem and against independent references: the exact Timoshenko frequencies with the
se3 element's second-order convergence, six rigid-body modes of a free beam, repeated bending
frequencies of a square section, a closed loop with a flexible link, damping ratios. The method
is chosen through the core binding (method 1 dense, 2 sparse; the default picks sparse from
PHM_SPARSE_MODES_MIN + 6 n carrier coordinates on, n modes), and the sparse path's count of the
eigenvalues below its shift (phm_modes_count) against the dense reduced problem's."""
import warnings

import numpy as np
import pytest

import phmech as ph
from phmech import _core, _model, timoshenko
from phmech.section import TABLE1, table1_properties

DENSE, SPARSE = 1, 2
L = TABLE1["L"]
REF = timoshenko.frequencies(5, L, TABLE1["EI"], TABLE1["kGA"], TABLE1["rhoA"], TABLE1["rhoI"])


def cantilever(n, props=None, mass="consistent"):
    m = ph.Mechanism()
    b = m.add_flexible_link("b", L, props if props is not None else table1_properties(), elements=n,
                            mass=mass)
    m.add_pair("clamp", ph.Fixed(), m.ground, b.start)
    return m


def modes(m, n, method):
    om, ze, sh, nf, _ = _core.model_modes(_model.build(m), n, None, None, 0.0, method)
    assert nf == n
    return om, ze, sh


def test_sparse_matches_dense_on_the_table1_cantilever():
    m = cantilever(60)
    od, _, sd = modes(m, 8, DENSE)
    os_, _, ss = modes(m, 8, SPARSE)
    # measured 4.6e-8: the dense path's round-off (eps |K| against the lowest eigenvalues of a
    # model whose axial stiffness is 1e4 times the bending one); with equal stiffnesses 2.5e-11
    assert np.max(np.abs(os_ / od - 1)) < 1e-6
    # the shapes agree up to sign (these modes are simple): normalized overlap 1
    for k in range(8):
        d, s = sd[k].ravel(), ss[k].ravel()
        assert abs(d @ s) / (np.linalg.norm(d) * np.linalg.norm(s)) > 1 - 1e-6, k


def test_sparse_keeps_second_order_convergence_on_fine_meshes():
    # the se3 element's frequency error is O(h^2): halving h divides it by 4; the dense path's
    # round-off broke this at N = 200 (ratio 3.4 for mode 1) and N = 500 (error 5.4e-5 instead of
    # 1.2e-5); the sparse path keeps it. Lumped mass: its error is a clean h^2 term from the
    # interior (measured ratios 4.000 ... 3.998); the consistent mass's error, its ends', is not
    # yet purely h^2 at N = 100 (ratios 4.005, 3.966 ... 3.977), which would hide round-off
    e100 = modes(cantilever(100, mass="lumped"), 5, SPARSE)[0] / REF - 1
    e200 = modes(cantilever(200, mass="lumped"), 5, SPARSE)[0] / REF - 1
    ratio = e100 / e200
    assert np.all(np.abs(ratio - 4) < 0.02), ratio


def test_free_beam_rigid_modes_and_repeated_frequencies():
    props = ph.BeamProperties.from_material(ph.Section.rectangle(0.01, 0.01), ph.Material(210e9, 0.3, 7850))
    m = ph.Mechanism()
    b = m.add_flexible_link("b", 0.5, props, elements=40)
    m.add_pair("float", ph.Free(), m.ground, b.start)   # free: a Free pair holds nothing
    od = modes(m, 12, DENSE)[0]
    os_ = modes(m, 12, SPARSE)[0]
    # six rigid-body modes (zero up to the finite-difference stiffness's noise), then bending
    # pairs of equal frequency (square section) that one Krylov vector would find only once
    assert np.all(np.abs(os_[:6]) < 1e-4 * os_[6])
    assert np.all(np.abs(os_[6:] / od[6:] - 1) < 1e-9)
    assert abs(os_[7] / os_[6] - 1) < 1e-9 and abs(os_[9] / os_[8] - 1) < 1e-9
    # free-free Euler-Bernoulli first frequency 22.373 sqrt(EI/(rhoA L^4)): a slender beam, within 1 %
    w1 = 22.373 * np.sqrt(props.EI_y / (props.rhoA * 0.5**4))
    assert abs(os_[6] / w1 - 1) < 0.01


def test_closed_loop_with_a_flexible_link():
    import test_flexible_loop as fl   # the slider-crank with a flexible rod
    m = fl.build(N=60)
    od = modes(m, 6, DENSE)[0]
    os_ = modes(m, 6, SPARSE)[0]
    # mode 0 is the mechanism's own motion (no gravity, no stiffness along it): zero up to the
    # finite-difference stiffness's noise in both (measured 7.7e-4 and 4.1e-4 rad/s); then the
    # rod's bending modes agree (measured 1.2e-7 rad/s at 385-1656 rad/s)
    assert abs(os_[0]) < 1e-5 * os_[1] and abs(od[0]) < 1e-5 * od[1]
    assert np.max(np.abs(os_[1:] / od[1:] - 1)) < 1e-8, (od, os_)


def test_damping_ratios_agree():
    P = table1_properties(1.0)
    damped = type("P", (), dict(stiffness=P.stiffness, inertia=P.inertia, damping=1e-4 * np.asarray(P.stiffness)))()
    m = cantilever(60, damped)
    _, zd, _ = modes(m, 6, DENSE)
    _, zs, _ = modes(m, 6, SPARSE)
    assert np.all(zd > 0)
    assert np.max(np.abs(zs / zd - 1)) < 1e-6


def test_default_picks_sparse_on_large_models():
    m = cantilever(200)
    auto = _core.model_modes(_model.build(m), 5, None, None, 0.0)[0]
    sparse = modes(m, 5, SPARSE)[0]
    assert np.array_equal(auto, sparse)


def test_default_takes_sparse_from_ten_plus_n_carriers():
    # PHM_SPARSE_MODES_MIN + 6 n coordinates (n modes), where the sparse path becomes the faster
    # (measured, core only: 2 modes at N = 11, 72 coordinates, 0.22 / 0.21 ms dense / sparse; 5
    # modes at N = 14, 90 coordinates, 0.48 / 0.42 ms): one carrier fewer is dense
    for n, N in ((2, 11), (5, 14)):
        for elements, method in ((N, SPARSE), (N - 1, DENSE)):
            model = _model.build(cantilever(elements))
            auto = _core.model_modes(model, n, None, None, 0.0)[0]
            assert np.array_equal(auto, modes(cantilever(elements), n, method)[0]), (n, elements)


def test_unknown_method_is_refused():
    with pytest.raises(ph.ModelError, match="unknown modes method"):
        _core.model_modes(_model.build(cantilever(4)), 2, None, None, 0.0, 7)


def _bar_chain(kinds, gravity):
    """Rigid bars (0.3 m, 1 kg) in a chain from the ground, one pair type per joint."""
    from phmech import se3
    m, prev = ph.Mechanism(gravity=gravity), None
    for i, kind in enumerate(kinds):
        b = m.add_rigid_body(f"b{i}", 1.0, np.diag([1e-4, 0.0075, 0.0075]), com=(0.15, 0, 0))
        a = m.ground if prev is None else ph.Frame(prev.carrier, se3.translation([0.3, 0, 0]))
        m.add_pair(f"p{i}", kind(), a, b)
        prev = b
    return m


def _modes_at(m, st, n, method):
    """The core's n lowest frequencies [rad/s] at the static equilibrium st, by method."""
    return _core.model_modes(_model.build(m), n, st.poses, st.constraint_wrenches, 0.0, method)[0]


def test_few_degrees_of_freedom_on_many_coordinates_take_the_dense_path():
    # was, on the sparse path (method 2; by default then from 300 coordinates, e.g. 50 bodies with
    # fewer than 9 degrees of freedom), before its block was bounded by the manifold: a hanging
    # chain of 10 bars, alternately revolute and welded (60 coordinates, 5 degrees of freedom),
    # showed -1.9e8 rad/s for its 2.18 rad/s mode -- round-off vectors of a block larger than the
    # manifold. Reference: the dense reduced problem
    m = _bar_chain([ph.Revolute, ph.Fixed] * 5, gravity=(9.81, 0, 0))
    st = m.static()
    dense = _modes_at(m, st, 1, DENSE)
    for method in (0, SPARSE):
        np.testing.assert_allclose(_modes_at(m, st, 1, method), dense, rtol=1e-12)
    assert 2.0 < dense[0] < 2.4          # measured 2.1769 rad/s
    # a 60-bar hanging chain (360 coordinates, 60 degrees of freedom) takes the sparse path
    m = _bar_chain([ph.Revolute] * 60, gravity=(9.81, 0, 0))
    st = m.static()
    np.testing.assert_allclose(_modes_at(m, st, 5, SPARSE), _modes_at(m, st, 5, DENSE), rtol=1e-10)


def test_unstable_modes_come_in_ascending_order_from_both_paths():
    # an upright chain of 30 bars at its (unstable) static equilibrium: negative eigenvalues only
    # among the lowest; each path lists them ascending (the sparse path listed its negative ones
    # in descending order). The sparse path's were the unstable modes nearest its shift
    # (-19.9, -17.7, -15.6 rad/s) where the dense path's are the most unstable (-96.7, -88.0,
    # -81.1): docs/validation.md, finding 9. Its count of the eigenvalues below the shift (30,
    # more than its block holds) now sends it lower (spectrum slicing): the same modes, measured
    # within 2.5e-14
    m = _bar_chain([ph.Revolute] * 30, gravity=(-9.81, 0, 0))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ph.StabilityWarning)
        st = m.static()
    d, s = _modes_at(m, st, 3, DENSE), _modes_at(m, st, 3, SPARSE)
    for om in (d, s):
        assert np.all(om < 0) and np.all(np.diff(om) > 0), om
    np.testing.assert_allclose(s, d, rtol=1e-12)


def test_an_unstable_sparse_result_is_the_most_unstable():
    # an upright chain of 60 bars (360 coordinates: sparse by default) at its unstable
    # equilibrium: the sparse path alone gave -13.0 rad/s (the unstable mode nearest its shift),
    # where the lowest is -142.9 rad/s (measured); the default (redone densely) and the sparse
    # method (the spectrum sliced: shift-invert below the lowest eigenvalue) now give it, and
    # static()'s stability check reads the same value
    m = _bar_chain([ph.Revolute] * 60, gravity=(-9.81, 0, 0))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ph.StabilityWarning)
        st = m.static()
    d, s, auto = (_modes_at(m, st, 3, method) for method in (DENSE, SPARSE, 0))
    np.testing.assert_allclose(auto, d, rtol=1e-12)
    np.testing.assert_allclose(s, d, rtol=1e-12)   # measured 1.0e-14
    assert st.stable is False and st.lowest_omega == pytest.approx(d[0], rel=1e-9)


def _chain_with_inverted_pendulums(n, arms):
    """A hanging chain of n bars (0.3 m, 1 kg) ending in short inverted pendulums: a 1 kg point
    mass on an arm of each length in `arms` [m], hinged at the chain's end, standing up against
    gravity."""
    from phmech import se3
    m = _bar_chain([ph.Revolute] * n, gravity=(9.81, 0, 0))
    end = ph.Frame(m._bodies[f"b{n - 1}"].carrier, se3.translation([0.3, 0, 0]))
    for i, arm in enumerate(arms):
        p = m.add_rigid_body(f"inverted{i}", 1.0, 1e-6 * np.eye(3), com=(-arm, 0, 0))
        m.add_pair(f"hinge{i}", ph.Revolute(), end, p)
    return m


@pytest.mark.parametrize("arms", [(0.01,), (0.3, 0.01)])
def test_a_strong_instability_beyond_the_stable_modes_is_not_missed(arms):
    # docs/validation.md, finding 9: shift-invert finds the eigenvalues nearest its shift (~0);
    # a hanging chain of 60 bars has dozens of stable modes below 10 rad/s, and a 1 cm inverted
    # pendulum at its end falls at -63.1 rad/s, farther from the shift than the block's stable
    # modes. Before the count of eigenvalues below the shift, modes() returned (0.881, 2.029,
    # ...) rad/s by every method but the dense one, and static() reported the configuration
    # stable (lowest_omega 0.881): an unstable equilibrium called stable. Now the sparse path's
    # count (1 below its shift, none found) sends AUTO to the dense path and the sparse method
    # lower (spectrum slicing), where it finds the missed mode, before the stable ones it had.
    # With a second, 30 cm pendulum (-5.7 rad/s, near the shift: found) 2 are below, 1 found.
    # 366 and 372 coordinates, sparse by default
    m = _chain_with_inverted_pendulums(60, arms)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ph.StabilityWarning)
        st = m.static()
    assert 6 * len(m._car) >= 300   # sparse by default before the count too
    d, s, auto = (_modes_at(m, st, 5, method) for method in (DENSE, SPARSE, 0))
    assert -64 < d[0] < -62 and np.sum(d < 0) == len(arms)   # measured -63.06 (-5.72) rad/s
    np.testing.assert_allclose(auto, d, rtol=1e-12)
    np.testing.assert_allclose(s, d, rtol=1e-11)             # measured 1.8e-13
    below = _core.model_modes_count(_model.build(m), -1e-6, st.poses, st.constraint_wrenches)[0]
    assert below == len(arms)
    assert st.stable is False and st.lowest_omega == pytest.approx(d[0], rel=1e-9)


def _dense_eigenvalues(model, poses, lam):
    """Every eigenvalue lambda = omega^2 of the reduced problem (the dense path's Kr, Mr)."""
    import scipy.linalg
    K, _, M, _, _, (nr, _) = _core.model_linear(model, [], poses, lam, 0.0)
    return scipy.linalg.eigh(K[:nr * nr].reshape(nr, nr), M[:nr * nr].reshape(nr, nr), eigvals_only=True)


def _count_scenes(rng):
    """(name, model, poses, constraint wrenches): stable, unstable and non-equilibrium
    configurations of rigid chains, compressed columns and a free beam."""
    from phmech import se3
    for trial in range(4):
        n = int(rng.integers(20, 50))
        lens, masses = rng.uniform(0.05, 0.5, n), rng.uniform(0.1, 5, n)
        axes = rng.choice(["y", "z"], n)
        for g in ((9.81, 0, 0), (-9.81, 0, 0), tuple(9.81 * rng.normal(size=3))):
            m, prev = ph.Mechanism(gravity=g), None
            for i in range(n):
                # a rod of radius L/20 (an axial moment of 1e-3 m^2 per kg, as before, broke
                # the triangle inequality of bodies shorter than 0.11 m: refused now)
                J = masses[i] * np.diag([lens[i] ** 2 / 800, lens[i] ** 2 / 12, lens[i] ** 2 / 12])
                b = m.add_rigid_body(f"b{i}", masses[i], J, com=(lens[i] / 2, 0, 0))
                a = m.ground if prev is None else ph.Frame(prev.carrier, se3.translation([lens[i - 1], 0, 0]))
                m.add_pair(f"p{i}", ph.Revolute(axes[i]), a, b)
                prev = b
            if g[0] == 9.81 or g[0] == -9.81:   # hanging (stable), upright (unstable)
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore", ph.StabilityWarning)
                    st = m.static(check_stability=False)
                yield f"chain {n} g {g}", _model.build(m), st.poses, st.constraint_wrenches
            else:                               # gravity askew: not an equilibrium
                yield f"chain {n} g askew", _model.build(m), None, None
    Pcr = np.pi ** 2 * TABLE1["EI"] / (4 * L ** 2)
    for N, mass in ((30, "lumped"), (60, "consistent")):
        for P in (0.5, 1 - 1e-4, 3.0, 30.0):    # times the first buckling load
            m = ph.Mechanism()
            b = m.add_flexible_link("b", L, table1_properties(1.0), elements=N, mass=mass)
            m.add_pair("clamp", ph.Fixed(), m.ground, b.start)
            load = [(b.end, (0, 0, 0, -P * Pcr, 0, 0), "world")]
            st = m.static(loads=load, steps=1, check_stability=False)
            yield f"column {N} P {P}", _model.build(m, st.loads), st.poses, st.constraint_wrenches
    props = ph.BeamProperties.from_material(ph.Section.rectangle(0.01, 0.01), ph.Material(210e9, 0.3, 7850))
    m = ph.Mechanism()
    b = m.add_flexible_link("b", 0.5, props, elements=40)
    m.add_pair("float", ph.Free(), m.ground, b.start)   # free: a Free pair holds nothing
    yield "free beam", _model.build(m), None, None


def test_the_count_below_a_shift_is_the_dense_count():
    # phm_modes_count (the KKT matrix's inertia, csrc/analyze/linearize.c) against the dense
    # reduced problem's eigenvalues, at random shifts through the lowest part of the spectrum
    # and at the sparse path's own shift (-1e-9 of the mean), kept 1e-6 of the spectrum's scale
    # away from every eigenvalue (closer, the dense eigenvalues' own round-off decides): a
    # certified count (certificate below PHM_INERTIA_CHECK = 0.1) is the dense one. Measured: 268
    # counts, all certified and right; certificates up to 1e-6, but 0.04 on a chain with gravity
    # askew (not an equilibrium) 6e-4 of its scale from a neutral mode (pivot growth, which the
    # certificate measures)
    rng = np.random.default_rng(5)
    counts = certified = 0
    for name, model, poses, lam in _count_scenes(rng):
        ev = _dense_eigenvalues(model, poses, lam)
        scale = np.abs(ev).max()
        shifts = [-1e-9 * np.abs(ev).mean()] + list(rng.uniform(ev[0] - abs(ev[0]) - 1, ev[min(12, len(ev) - 1)], 8))
        for k in rng.integers(0, min(8, len(ev)), 2):
            shifts += [ev[k] + 1e-5 * scale, ev[k] - 1e-5 * scale]
        for shift in shifts:
            if np.min(np.abs(ev - shift)) < 1e-6 * scale:
                continue
            count, check = _core.model_modes_count(model, float(shift), poses, lam)
            counts += 1
            if check < 0.1:
                certified += 1
                assert count == np.sum(ev < shift), (name, shift, count, np.sum(ev < shift), check)
    assert counts > 250 and certified >= 0.95 * counts, (counts, certified)


def test_shift_moves_towards_the_lowest_modes_of_a_fine_hanging_cable():
    # a steel riser (d = 0.02 m, 100 m, 200 elements) hanging under low gravity: its first
    # shift, -1e-9 tr K / tr M = -0.147 (rad/s)^2, is 100 times its lowest eigenvalue (1.4e-3),
    # so the sparse path moves it to -4 lam1 (sparse_reshift, csrc/analyze/modes_sparse.c;
    # 10 000 elements at 9.81 m/s^2: 391 iterations before, a few now). Same modes as the dense
    # path within round-off (eps cond K ~ 1e-5 here; measured 3.8e-6, 6.1e-6 with the shift kept
    # where it starts): the frequencies alone cannot tell whether the shift moved, the solver's
    # statistics (phm_modes_stats) do
    props = ph.BeamProperties.from_material(ph.Section.circle(0.02), ph.Material(2.1e11, 0.3, 7850))
    m = ph.Mechanism(gravity=(0, 0, -0.0981))
    b = m.add_flexible_link("riser", 100.0, props, elements=200)
    hang = np.eye(4)
    hang[:3, :3] = [[0, 0, 1], [0, 1, 0], [-1, 0, 0]]
    m.add_pair("top", ph.Revolute("y"), ph.Frame(-1, hang), b.start)
    model = _model.build(m)
    P, lam, _ = _core.model_static(model, None, 0.0, 10, 1e-10, None)
    od = _core.model_modes(model, 4, P, lam, 0.0, DENSE)[0]
    os_, _, _, _, stats = _core.model_modes(model, 4, P, lam, 0.0, SPARSE)
    assert np.max(np.abs(os_ / od - 1)) < 2e-5, (od, os_)
    # the shift moved once, from -103 lam1 to -4 times the Ritz estimate of lam1 then (an upper
    # bound of lam1: Courant-Fischer), measured -5.85 lam1; 6 iterations (without the move: 8)
    lam1 = od[0] ** 2
    assert stats["method"] == SPARSE and stats["shift0"] < -50 * lam1, stats
    assert stats["reshifts"] == 1, stats
    assert -10 * lam1 < stats["shift"] <= -4 * lam1, (stats, lam1)
    assert stats["iterations"] <= 10, stats
    # the lowest mode: a hanging chain's (2.405 / 2) sqrt(g / L) = 0.03766 rad/s, the bending
    # stiffness adding 0.35 %
    assert abs(os_[0] / 0.0377913 - 1) < 1e-4

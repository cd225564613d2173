"""Modes by subspace iteration on the sparse KKT system (csrc/solve/modes.c) against the dense
reduced problem and against independent references: the exact Timoshenko frequencies with the
se3 element's second-order convergence, six rigid-body modes of a free beam, repeated bending
frequencies of a square section, a closed loop with a flexible link, damping ratios. The method
is chosen through the core binding (method 1 dense, 2 sparse; the default picks sparse from
PHM_SPARSE_MODES_MIN carrier coordinates on)."""
import warnings

import numpy as np
import pytest

import phmech as ph
from phmech import _core, timoshenko
from phmech.section import TABLE1, table1_properties

DENSE, SPARSE = 1, 2
L = TABLE1["L"]
REF = timoshenko.frequencies(5, L, TABLE1["EI"], TABLE1["kGA"], TABLE1["rhoA"], TABLE1["rhoI"])


def cantilever(n, props=None):
    m = ph.Mechanism()
    b = m.add_flexible_link("b", L, props if props is not None else table1_properties(), elements=n)
    m.add_pair("clamp", ph.Fixed(), m.ground, b.start)
    return m


def modes(m, n, method):
    om, ze, sh, nf = _core.model_modes(m._build(), n, None, None, 0.0, method)
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
    # 1.2e-5); the sparse path keeps it
    e100 = modes(cantilever(100), 5, SPARSE)[0] / REF - 1
    e200 = modes(cantilever(200), 5, SPARSE)[0] / REF - 1
    ratio = e100 / e200
    assert np.all(np.abs(ratio - 4) < 0.02), ratio


def test_free_beam_rigid_modes_and_repeated_frequencies():
    props = ph.BeamProperties.from_material(ph.Section.rectangle(0.01, 0.01), ph.Material(210e9, 0.3, 7850))
    m = ph.Mechanism()
    m.add_flexible_link("b", 0.5, props, elements=40)
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
    auto = _core.model_modes(m._build(), 5, None, None, 0.0)[0]
    sparse = modes(m, 5, SPARSE)[0]
    assert np.array_equal(auto, sparse)


def test_unknown_method_is_refused():
    with pytest.raises(ph.ModelError, match="unknown modes method"):
        _core.model_modes(cantilever(4)._build(), 2, None, None, 0.0, 7)


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
    return _core.model_modes(m._build(), n, st.poses, st.constraint_wrenches, 0.0, method)[0]


def test_few_degrees_of_freedom_on_many_coordinates_take_the_dense_path():
    # was, on the sparse path (method 2; by default from 300 coordinates, e.g. 50 bodies with
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
    # in descending order). The sparse path's are the unstable modes nearest the shift (measured
    # -19.9, -17.7, -15.6 rad/s), the dense path's the most unstable (-96.7, -88.0, -81.1): see
    # docs/validation.md, finding 9
    m = _bar_chain([ph.Revolute] * 30, gravity=(-9.81, 0, 0))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ph.StabilityWarning)
        st = m.static()
    d, s = _modes_at(m, st, 3, DENSE), _modes_at(m, st, 3, SPARSE)
    for om in (d, s):
        assert np.all(om < 0) and np.all(np.diff(om) > 0), om
    assert d[0] < s[0]


def test_default_redoes_an_unstable_sparse_result_densely():
    # an upright chain of 60 bars (360 coordinates: sparse by default) at its unstable
    # equilibrium: the sparse path alone gives -13.0 rad/s (the unstable mode nearest its shift),
    # the default redoes it densely and reports the most unstable, -142.9 rad/s (measured);
    # static()'s stability check reads the same value
    m = _bar_chain([ph.Revolute] * 60, gravity=(-9.81, 0, 0))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ph.StabilityWarning)
        st = m.static()
    d, s, auto = (_modes_at(m, st, 3, method) for method in (DENSE, SPARSE, 0))
    assert s[0] > 0.5 * d[0]                      # the sparse path's nearest unstable mode
    np.testing.assert_allclose(auto, d, rtol=1e-12)
    assert st.stable is False and st.lowest_omega == pytest.approx(d[0], rel=1e-9)

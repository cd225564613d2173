"""Modes by subspace iteration on the sparse KKT system (csrc/solve/modes.c) against the dense
reduced problem and against independent references: the exact Timoshenko frequencies with the
se3 element's second-order convergence, six rigid-body modes of a free beam, repeated bending
frequencies of a square section, a closed loop with a flexible link, damping ratios. The method
is chosen through the core binding (method 1 dense, 2 sparse; the default picks sparse from
PHM_SPARSE_MODES_MIN carrier coordinates on)."""
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

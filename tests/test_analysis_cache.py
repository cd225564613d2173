"""What the analyses keep between calls on an unchanged mechanism (python/phmech/_model.py,
``built``: the core model, simulate's planarity and planar model, modes' equilibrium check and
labels) is never stale: a change after a call -- any add_*, a new gravity -- is honoured, and the
numbers after it are those of a mechanism built with the change from the start, bit for bit."""
import warnings

import numpy as np
import pytest

import phmech as ph
from phmech import _core, se3, studies


def cantilever(N=4, gravity=(0.0, 0.0, 0.0), tip=False):
    m, link = studies.se3_cantilever(N)
    m.gravity = gravity
    if tip:
        add_tip(m, link)
    return m, link


def add_tip(m, link):
    b = m.add_rigid_body("tip", 500.0, np.diag([1.0, 1.0, 1.0]))
    m.add_pair("weld", ph.Fixed(), link.end, b)


def same_modes(a, b):
    for f in ("omega", "damping_ratio", "shapes", "strain_fractions", "elastic_fraction"):
        np.testing.assert_array_equal(getattr(a, f), getattr(b, f))
    assert a.kind == b.kind and a.participation == b.participation
    assert a.strain_participation == b.strain_participation and a.equilibrium == b.equilibrium


@pytest.fixture
def model_new(monkeypatch):
    """The number of core models made (_core.model_new calls)."""
    n = [0]
    f = _core.model_new

    def counting(*a, **k):
        n[0] += 1
        return f(*a, **k)
    monkeypatch.setattr(_core, "model_new", counting)
    return n


def test_repeated_analyses_share_one_model_and_give_the_same_numbers(model_new):
    m, _ = cantilever()
    first = m.modes(5)
    for _ in range(3):
        same_modes(m.modes(5), first)
    st = m.static()
    np.testing.assert_array_equal(m.static().poses, st.poses)
    r = m.simulate(0.01, 0.005)
    np.testing.assert_array_equal(m.simulate(0.01, 0.005).poses, r.poses)
    # one model for modes and static; the first planar simulation takes it, moved to the
    # planar rows, and keeps it; the next analysis builds the 3-D one again, once
    assert r.stats["planar"] == "z" and model_new[0] == 2
    for _ in range(2):
        same_modes(m.modes(5), first)
        np.testing.assert_array_equal(m.simulate(0.01, 0.005).poses, r.poses)
    assert model_new[0] == 2


def test_an_add_after_a_call_is_honoured():
    m, link = cantilever()
    before = m.modes(3)
    m.static()
    m.simulate(0.01, 0.005)
    add_tip(m, link)
    fresh, _ = cantilever(tip=True)
    after = m.modes(3)
    assert after.omega[0] < 0.8 * before.omega[0]      # 500 kg at the tip of an 873 kg beam
    same_modes(after, fresh.modes(3))
    np.testing.assert_array_equal(m.simulate(0.01, 0.005).poses, fresh.simulate(0.01, 0.005).poses)


def test_a_gravity_change_after_a_call_is_honoured():
    m, _ = cantilever(tip=True)
    st0 = m.static()
    r0 = m.simulate(0.01, 0.005)
    m.modes(3)
    m.gravity = (0.0, 0.0, -9.81)
    fresh, _ = cantilever(gravity=(0.0, 0.0, -9.81), tip=True)
    st = m.static()
    assert st.poses[-1][2, 3] < st0.poses[-1][2, 3] - 1e-4          # it sags now
    np.testing.assert_array_equal(st.poses, fresh.static().poses)
    r = m.simulate(0.01, 0.005)
    assert not np.array_equal(r.poses, r0.poses)
    np.testing.assert_array_equal(r.poses, fresh.simulate(0.01, 0.005).poses)
    # the equilibrium check is made again: the straight beam is no equilibrium under gravity
    with pytest.warns(ph.EquilibriumWarning):
        a = m.modes(3)
    with pytest.warns(ph.EquilibriumWarning):
        b = fresh.modes(3)
    same_modes(a, b)
    assert not a.equilibrium


def test_a_kept_check_still_warns_at_every_call():
    m, _ = cantilever(gravity=(0.0, 0.0, -9.81))
    for _ in range(2):
        with pytest.warns(ph.EquilibriumWarning):
            assert not m.modes(2).equilibrium
    # and at another time the check is its own (here the same answer)
    with pytest.warns(ph.EquilibriumWarning):
        m.modes(2, time=1.0)


def test_changing_a_result_changes_neither_the_kept_labels_nor_the_next_result():
    m, _ = cantilever()
    a = m.modes(3)
    ref = m.modes(3)
    a.kind[0] = "changed"
    a.participation[0].clear()
    a.strain_participation[0]["beam"] = -1.0
    a.strain_fractions[:] = 7.0
    a.elastic_fraction[:] = 7.0
    same_modes(m.modes(3), ref)


def test_modes_at_a_static_result_are_not_taken_from_the_initial_configuration():
    m, _ = cantilever(gravity=(0.0, 0.0, -9.81), tip=True)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ph.EquilibriumWarning)
        m.modes(3)
    st = m.static()
    at = m.modes(3, at=st)
    assert at.equilibrium
    fresh, _ = cantilever(gravity=(0.0, 0.0, -9.81), tip=True)
    same_modes(at, fresh.modes(3, at=fresh.static()))


def test_planar_choice_is_kept_per_start_and_a_required_plane_still_fails():
    m = ph.Mechanism(gravity=(0.0, 0.0, -9.81))
    J = np.diag([0.02, 0.02, 1e-4])
    a = m.add_rigid_body("a", 1.0, J, com=(0.0, 0.0, -0.25))
    m.add_pair("k1", ph.Revolute("y"), m.ground, a, xdot0=1.0)
    r = m.simulate(0.02, 0.01)
    assert r.stats["planar"] == "y"
    assert m.simulate(0.02, 0.01).stats["planar"] == "y"
    # a body spinning about another axis: the scene is no longer planar, and planar=True says so
    b = m.add_rigid_body("b", 1.0, np.diag([0.02, 0.03, 0.04]), twist=(1.0, 0.0, 1.0, 0.0, 0.0, 0.0),
                         pose=se3.translation([1.0, 0.0, 0.0]))
    m.add_pair("k2", ph.Free(), m.ground, b)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ph.UnattachedWarning)
        assert m.simulate(0.02, 0.01).stats["planar"] is None
        for _ in range(2):
            with pytest.raises(ph.ModelError, match="not planar"):
                m.simulate(0.02, 0.01, planar=True)


def test_modes_at_static_results_keep_their_own_checks_and_labels():
    import dataclasses
    m, link = cantilever(gravity=(0.0, 0.0, -9.81), tip=True)
    fresh, flink = cantilever(gravity=(0.0, 0.0, -9.81), tip=True)
    st = m.static()
    a = m.modes(3, at=st)
    same_modes(m.modes(3, at=st), a)
    same_modes(a, fresh.modes(3, at=fresh.static()))
    # another equilibrium (an extra tip load): its own numbers, as a fresh mechanism's
    load = [(link.end, (0.0, 0.0, 0.0, 0.0, 0.0, -2e3), "world")]
    b = m.modes(3, at=m.static(loads=load))
    fload = [(flink.end, (0.0, 0.0, 0.0, 0.0, 0.0, -2e3), "world")]
    same_modes(b, fresh.modes(3, at=fresh.static(loads=fload)))
    assert not np.array_equal(a.omega, b.omega)
    # poses that are no equilibrium, after the check passed at the static result's own
    bent = st.poses.copy()
    bent[-1][2, 3] += 0.05
    off = dataclasses.replace(st, poses=bent)
    with pytest.warns(ph.EquilibriumWarning):
        assert not m.modes(3, at=off).equilibrium
    with pytest.warns(ph.EquilibriumWarning):
        assert not m.modes(3, at=off).equilibrium
    assert m.modes(3, at=st).equilibrium


def double_pendulum(gravity=(0.0, 0.0, -9.81)):
    """benchmarks/bench_overhead.py's double pendulum: two bars hanging along -z on revolutes
    about y (an equilibrium under that gravity)."""
    m = ph.Mechanism(gravity=gravity)
    J = np.diag([0.5 ** 2 / 12, 0.5 ** 2 / 12, 1e-4])
    a = m.add_rigid_body("a", 1.0, J, com=(0.0, 0.0, -0.25))
    b = m.add_rigid_body("b", 1.0, J, com=(0.0, 0.0, -0.25))
    m.add_pair("k1", ph.Revolute("y"), m.ground, a)
    m.add_pair("k2", ph.Revolute("y"), ph.Frame(a.carrier, se3.translation([0.0, 0.0, -0.5])), b)
    return m, b


def warned(call):
    """call()'s result and the categories of the warnings it gave."""
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        out = call()
    return out, {x.category for x in w}


def test_a_gravity_changed_in_place_after_a_call_is_honoured():
    m, _ = double_pendulum()
    first, cats = warned(lambda: m.modes(2))
    assert first.equilibrium and not cats
    m.gravity[:] = (-9.81, 0.0, 0.0)   # in place: the array the mechanism holds
    fresh, _ = double_pendulum(gravity=(-9.81, 0.0, 0.0))
    for _ in range(2):
        with pytest.warns(ph.EquilibriumWarning):
            a = m.modes(2)
        assert not a.equilibrium
    with pytest.warns(ph.EquilibriumWarning):
        same_modes(a, fresh.modes(2))
    assert not np.array_equal(a.omega, first.omega)


def test_changed_arguments_after_a_call_are_checked_again():
    m, b = double_pendulum()
    two = m.modes(2)
    one = m.modes(1)        # other frequencies: other labels, not the kept ones
    assert one.omega.shape == (1,) and len(one.kind) == len(one.participation) == 1
    same_modes(m.modes(2), two)
    with pytest.raises(ph.ModelError, match="n must be an integer >= 1"):
        m.modes(0)
    with pytest.raises(ph.ModelError, match="time must be finite"):
        m.modes(2, time=float("nan"))
    with pytest.raises(ph.ModelError, match="at must be a StaticResult"):
        m.modes(2, at="initial")
    # a driven pair whose law has moved by the time asked is refused after a call at t = 0
    c = m.add_rigid_body("c", 1.0, np.diag([1e-3, 1e-3, 1e-3]))
    m.add_pair("k3", ph.Revolute("z"), ph.Frame(b.carrier, se3.translation([0.0, 0.0, -0.5])), c,
               driven=ph.Linear(rate=1.0))
    m.modes(2)
    with pytest.raises(ph.ModelError, match=r"modes\(time=1\): pair 'k3' is driven"):
        m.modes(2, time=1.0)


def test_the_linearization_warnings_follow_an_add_after_a_call_and_come_at_every_call():
    m, b = double_pendulum()
    _, cats = warned(lambda: m.modes(2))
    assert not cats
    m.add_wrench("push", b, (0.0, 0.0, 0.0, 0.0, 0.0, -1.0), frame="body")   # along the bar
    for _ in range(2):
        with pytest.warns(ph.StabilityWarning, match=r"follower loads \['push'\]"):
            m.modes(2)
    # a body light beyond what double precision resolves next to the bars
    dust = m.add_rigid_body("dust", 1e-15, np.diag([1e-18, 1e-18, 1e-18]))
    m.add_pair("k3", ph.Revolute("y"), ph.Frame(b.carrier, se3.translation([0.0, 0.0, -0.5])), dust)
    def modes_of_the_unresolvable():
        # its stiffness, from the joints' reactions (the linearization's constraint wrenches),
        # is round-off of either sign next to the bars': the eigensolve may fail, as
        # modes(at=m.static()) does here; the warnings come first, at every call
        try:
            m.modes(2)
        except ph.SolverError as e:
            assert "eigenproblem failed" in str(e)

    for _ in range(2):
        _, cats = warned(modes_of_the_unresolvable)
        assert {ph.StabilityWarning, ph.AccuracyWarning} <= cats


def test_strict_set_after_a_call_raises_on_the_moves_it_warned_about():
    from test_closed_chains import rocker_angles
    from test_initial_adjustments import fourbar
    m, _, _ = fourbar(k4_x0=rocker_angles(0.6)[0] + 0.2)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ph.RedundantConstraintWarning)
        with pytest.warns(ph.InitialValueWarning, match="joint 'k4' given 1.48786 rad"):
            first = m.modes(1)
        m.strict = True
        with pytest.raises(ph.ModelError, match=r"joint 'k4' given 1\.48786 rad.*strict=True"):
            m.modes(1)
        m.strict = False
        same_modes(m.modes(1), first)


def test_a_result_keeps_the_tables_of_its_own_call():
    m, b = double_pendulum()
    first = m.modes(2)
    c = m.add_rigid_body("c", 1.0, np.diag([1e-3, 1e-3, 1e-3]))
    m.add_pair("k3", ph.Revolute("y"), ph.Frame(b.carrier, se3.translation([0.0, 0.0, -0.5])), c)
    after = m.modes(2)
    assert set(first._bodies) == {"a", "b"} and set(after._bodies) == {"a", "b", "c"}
    assert set(first.participation[0]) == {"a", "b"} and set(after.participation[0]) == {"a", "b", "c"}


def test_modes_builds_its_result_in_the_field_order_of_modes_result():
    # _modes.modes passes ModesResult's fields positionally (keywords cost ~1 us a call), the
    # labels in _modes.LABEL_FIELDS' order: both must stay those of the dataclass and of
    # analysis.label_modes
    import dataclasses
    from phmech import _modes, analysis
    from phmech.results import ModesResult
    assert [f.name for f in dataclasses.fields(ModesResult)] == [
        "omega", "frequency", "damping_ratio", "shapes", *_modes.LABEL_FIELDS, "poses",
        "equilibrium", "poles", "_links", "_bodies"]
    m, _ = cantilever(N=2)
    r = m.modes(2)
    lab = analysis.label_modes(m._desc, r.poses, r.omega, r.shapes)
    assert set(lab) == set(_modes.LABEL_FIELDS)
    for k in _modes.LABEL_FIELDS:
        assert type(getattr(r, k)) is type(lab[k])

"""Model set-up: a Mechanism finds its initial configuration (python/phmech/topology.py) once
per description, keeps it until the next add_*, and keeps one core model for it between the analyses; the
model the loop closure worked on, moved to the closed state (_core.model_set_initial), is the
model a fresh build at that state gives."""
import warnings

import numpy as np
import pytest

import phmech as ph
from phmech import _core, _marshal, _model, _placement, se3, topology


def fourbar(spring: bool = False) -> ph.Mechanism:
    """A planar four-bar of 3-D revolutes (a loop, 3 redundant rows), started with a crank angle
    that the tree walk leaves open; optionally a spring with its default rest length (the
    distance at the closed configuration) on the rocker."""
    m = ph.Mechanism(gravity=(0, -9.81, 0))
    bars = [m.add_rigid_body(n, 1.0, np.diag([1e-4, L ** 2 / 12, L ** 2 / 12]), com=(L / 2, 0, 0))
            for n, L in (("crank", 0.2), ("coupler", 0.6), ("rocker", 0.5))]
    T = lambda x: se3.translation([x, 0, 0])
    m.add_pair("k1", ph.Revolute("z"), m.ground, bars[0], x0=0.6, xdot0=4.0)
    m.add_pair("k2", ph.Revolute("z"), ph.Frame(bars[0].carrier, T(0.2)), bars[1])
    m.add_pair("k3", ph.Revolute("z"), ph.Frame(bars[1].carrier, T(0.6)), ph.Frame(bars[2].carrier, T(0.5)))
    m.add_pair("k4", ph.Revolute("z"), ph.Frame(-1, T(0.5)), bars[2])
    if spring:
        m.add_spring_damper("s", ph.Frame(-1, T(0.2)), ph.Frame(bars[2].carrier, T(0.5)), 50.0)
    return m


@pytest.fixture
def counted(monkeypatch):
    """Counts of topology.initial_state runs and _core.model_new calls."""
    calls = {"initial_state": 0, "model_new": 0}

    def counting(name, f):
        def g(*a, **k):
            calls[name] += 1
            return f(*a, **k)
        return g
    monkeypatch.setattr(topology, "initial_state", counting("initial_state", topology.initial_state))
    monkeypatch.setattr(_core, "model_new", counting("model_new", _core.model_new))
    return calls


def test_initial_configuration_is_found_once_and_one_model_is_built_per_configuration(counted):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ph.RedundantConstraintWarning)
        # static() from x0 = 0.6 ends with the crank near the top (1.60 rad), an unstable
        # equilibrium (lowest mode -6.36 rad/s: measured), and says so
        warnings.simplefilter("ignore", ph.StabilityWarning)
        m = fourbar()
        first = m.initial_configuration()
        assert counted == {"initial_state": 1, "model_new": 1}
        r = m.simulate(0.01, 0.005, integrator="ida")
        m.modes(2)
        m.static(steps=2)
        m.constraint_residuals(r)
        # one model per initial configuration, kept between the analyses (_model.built)
        assert counted == {"initial_state": 1, "model_new": 1}
        again = m.initial_configuration()
        np.testing.assert_array_equal(again.poses, first.poses)
        again.poses[:] = 0                     # a copy: the kept state is not changed
        np.testing.assert_array_equal(m.initial_configuration().poses, first.poses)
        # any add_* changes the description: the initial configuration is found again
        m.add_rigid_body("extra", 1.0, np.eye(3))
        m.add_pair("float", ph.Free(), m.ground, "extra")   # it flies freely, and says so
        m.modes(2)
        assert counted == {"initial_state": 2, "model_new": 2}
    assert sorted(m.redundant_constraints) == [("k3", "f_z"), ("k3", "tau_x"), ("k3", "tau_y")]


def test_first_analysis_builds_one_model_unless_a_default_rest_length_moved(counted):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ph.RedundantConstraintWarning)
        fourbar().simulate(0.01, 0.005)
        assert counted["model_new"] == 1
        fourbar(spring=True).simulate(0.01, 0.005)   # the spring's rest length: closed poses
        assert counted["model_new"] == 1 + 2


def test_model_moved_to_the_closed_state_equals_a_fresh_build():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ph.RedundantConstraintWarning)
        m = fourbar()
        state, moved = _model.initial_state(m)
    desc = m._desc
    H, T, _, frames_a = _placement.place_tree(desc)
    assert not np.array_equal(H, state.poses)     # the loop closure moved the poses
    fresh = _marshal.core_model(desc, state.poses, state.twists, state.x0, state.drop_masks, frames_a)
    assert _core.model_sizes(moved) == _core.model_sizes(fresh)
    runs = [_core.model_simulate(model, np.array([0.0, 0.01, 0.02]), 1e-8, 1e-10, 0)
            for model in (moved, fresh)]
    for key in ("poses", "twists", "constraint_wrenches", "joints", "energy"):
        np.testing.assert_array_equal(runs[0][key], runs[1][key])


@pytest.mark.parametrize("args,message", [
    (lambda s: (np.zeros((2, 4, 4)), s.twists, s.x0, s.drop_masks), r"carrier poses: expected shape \(3, 4, 4\)"),
    (lambda s: (s.poses, s.twists, s.x0, [0.5, 0, 0, 0]), r"drop mask of pair 0: expected a whole number"),
    (lambda s: (s.poses, s.twists, s.x0, [0, 0, 64, 0]), r"pair 2: drop mask 64 names rows beyond"),
    (lambda s: (s.poses, np.full((3, 6), np.nan), s.x0, s.drop_masks), r"carrier twists: contains a non-finite"),
    (lambda s: (s.poses, s.twists, "x0", s.drop_masks), r"pair initial coordinates: expected an array"),
])
def test_set_initial_refuses_a_bad_state(args, message):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ph.RedundantConstraintWarning)
        m = fourbar()
        state, model = _model.initial_state(m)
    with pytest.raises(ph.ModelError, match=message):
        _core.model_set_initial(model, *args(state))

"""The model description handed to the core (python/phmech/_marshal.py) and the binding's checks
of it (csrc/pyext/py_model.c, model_new: one dict of columns per component kind): a valid
description builds a model; a missing, unknown, misshapen or non-finite column, a fractional
index, a bad law or drop mask is a ModelError naming it, never a crash."""
import numpy as np
import pytest

import phmech as ph
from phmech import _core, _marshal, _model


def described():
    """A mechanism with every component kind (a driven pair, an actuated one, a link, a load, a
    spring) and the arguments of model_new at its initial configuration."""
    m = ph.Mechanism(gravity=(0, 0, -9.81))
    props = ph.BeamProperties.from_material(ph.Section.rectangle(0.02, 0.002),
                                            ph.Material(E=210e9, nu=0.3, density=7850.0))
    link = m.add_flexible_link("l", 0.5, props, elements=2)
    b = m.add_rigid_body("b", 1.0, np.eye(3) * 1e-3)
    m.add_pair("clamp", ph.Fixed(), m.ground, link.start,
               driven=ph.Motion((0, 0, 1, 0, 0, 0), ph.Table([0, 1], [0, 0.1])))
    m.add_pair("hinge", ph.Revolute("z"), link.end, b, actuator=ph.PD(kp=10.0, kd=1.0))
    m.add_wrench("w", b, (0, 0, 0, 1.0, 0, 0), law=ph.Sine(frequency=2.0))
    m.add_spring_damper("s", "ground", b, 100.0)
    state, _ = _model.initial_state(m)
    kw = _marshal.components(m._desc, state.poses, state.twists, state.x0, state.drop_masks,
                             state.frames_a)
    # writable copies of the arrays the description shares read-only (the tests break them)
    return {kind: {c: np.array(v) if isinstance(v, np.ndarray) else v for c, v in d.items()}
            if isinstance(d, dict) else d for kind, d in kw.items()}


def test_a_valid_description_builds_a_model():
    kw = described()
    sizes = _core.model_sizes(_core.model_new(**kw))
    assert sizes[0] == 4 and sizes[3] == 3   # carriers; ports: actuator, load, spring


def test_couplings_are_optional():
    """model_new's couplings: left out, None or an empty set of columns are the same (no coupling
    without an element); a coupling between carriers that are not there is refused by the core.
    The described link has one: its ends' rigid-rotation coupling (description.py)."""
    kw = described()
    assert kw["couplings"]["Mc"].shape == (1, 12, 12)
    empty = dict(Mc=np.zeros((0, 12, 12)), carriers=np.zeros((0, 2)))
    for couplings in ("absent", None, empty):
        args = {k: v for k, v in kw.items() if k != "couplings"}
        if couplings != "absent":
            args["couplings"] = couplings
        assert _core.model_sizes(_core.model_new(**args))[0] == 4
    bad = dict(kw, couplings=dict(Mc=np.zeros((1, 12, 12)), carriers=np.array([[0.0, 9.0]])))
    with pytest.raises(ph.ModelError, match="coupling 0: carriers \\(0, 9\\) out of range"):
        _core.model_new(**bad)


@pytest.mark.parametrize("kind,key", [(k, c) for k in ("carriers", "pairs", "springs")
                                      for c in ("mass", "type", "carriers", "law", "rest_length")
                                      if c in described()[k]])
def test_missing_column_is_named(kind, key):
    kw = described()
    del kw[kind][key]
    with pytest.raises(ph.ModelError, match=rf"{kind}: missing the column '{key}'"):
        _core.model_new(**kw)


@pytest.mark.parametrize("change,message", [
    (lambda kw: kw["pairs"].update(typo=np.zeros(2)), r"pairs: unknown column 'typo'"),
    (lambda kw: kw.update(loads=[1, 2]), r"loads: expected a dict of columns, one row per load"),
    (lambda kw: kw["carriers"].update(mass=np.ones((4, 1))), r"carrier masses: expected a 1-D array"),
    (lambda kw: kw["carriers"].update(H0=np.zeros((3, 4, 4))), r"carrier poses: expected shape \(4, 4, 4\)"),
    (lambda kw: kw["elements"]["K"].__setitem__((0, 0, 0), np.nan), r"element stiffness: contains a non-finite"),
    (lambda kw: kw["elements"]["nodes"].__setitem__((1, 0), 1.5),
     r"element 1: expected a whole number, got 1.5"),
    (lambda kw: kw["pairs"]["type"].__setitem__(0, 1e20), r"pair type of pair 0: expected a whole number"),
    (lambda kw: kw["pairs"]["drop"].__setitem__(1, 70.0), r"pair 1: drop mask must be an integer in \[0, 64\)"),
    (lambda kw: kw["pairs"].update(law=[None]), r"pair laws: expected a list with one law per pair"),
    (lambda kw: kw["pairs"]["law"].__setitem__(0, None), r"pair motion law: a time law must be a tuple"),
    (lambda kw: kw["pairs"]["law"].__setitem__(0, (4, 0, 0, 0, 0, 0, 0, np.zeros(3), 0, None, None)),
     r"pair motion law: table must have shape \(n, 2\)"),
    (lambda kw: kw["pairs"]["law"].__setitem__(0, (4, 0, 0, 0, 0, 0, 0, np.zeros(4))),
     r"pair motion law: a time law must be a tuple \(kind, .*, data, order, nodes, fn\)"),
    (lambda kw: kw["pairs"]["law"].__setitem__(0, (9, 0, 0, 0, 0, 0, 0, None, 0, [(10, 0, 0, 0, 0, 0, 0, None, 0, None, None)], None)),
     r"pair 0: expression law: operator at node 0 has fewer than two operands"),
    (lambda kw: kw["pairs"]["law"].__setitem__(0, (8, 0, 0, 0, 0, 0, 0, None, 0, None, 3.0)),
     r"pair motion law: a callback law's fn must be callable"),
    (lambda kw: kw["loads"]["law"].__setitem__(0, None), r"load law: a time law must be a tuple"),
    (lambda kw: kw["actuators"].update(kind=["pd"]), r"actuator kinds: expected an array of real numbers"),
    (lambda kw: kw["springs"].update(rest_length=[np.inf]), r"spring rest lengths: contains a non-finite"),
    (lambda kw: kw.update(gravity=(0, 0)), r"gravity: expected shape \(3\)"),
])
def test_bad_description_is_a_model_error(change, message):
    kw = described()
    change(kw)
    with pytest.raises(ph.ModelError, match=message):
        _core.model_new(**kw)


def test_core_validation_still_applies():
    kw = described()
    kw["pairs"]["carriers"][1, 1] = 99   # no such carrier: refused by phm_model_create
    with pytest.raises(ph.ModelError, match="carrier"):
        _core.model_new(**kw)


def test_the_description_columns_are_shared_read_only_and_dropped_on_a_change():
    """_marshal.components makes the description's own columns once (ModelDescription.columns)
    and hands them out read-only in new dicts and lists; adding a component drops them, so the
    next model has it."""
    m = ph.Mechanism(gravity=(0, 0, -9.81))
    b = m.add_rigid_body("b", 1.0, np.eye(3))
    m.add_pair("hinge", ph.Revolute("y"), m.ground, b)
    state, _ = _model.initial_state(m)
    args = (m._desc, state.poses, state.twists, state.x0, state.drop_masks, state.frames_a)
    first, second = _marshal.components(*args), _marshal.components(*args)
    assert first["carriers"]["M"] is second["carriers"]["M"]
    assert first["pairs"] is not second["pairs"] and first["pairs"]["law"] is not second["pairs"]["law"]
    with pytest.raises(ValueError, match="read-only"):
        first["carriers"]["mass"][0] = 2.0
    del first["pairs"]["type"]
    assert "type" in _marshal.components(*args)["pairs"]
    c = m.add_rigid_body("c", 2.0, np.eye(3))
    m.add_pair("float", ph.Free(), m.ground, c)   # c flies freely, and says so
    state, _ = _model.initial_state(m)
    third = _marshal.components(m._desc, state.poses, state.twists, state.x0, state.drop_masks,
                                state.frames_a)
    np.testing.assert_array_equal(third["carriers"]["mass"], [1.0, 2.0])
    assert _core.model_sizes(_core.model_new(**third))[0] == 2

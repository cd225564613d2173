"""The core's code tables (``_core.codes()``, csrc/util/codes.c and the pair table of
csrc/model/pair_types.c): Python reads every code from them (python/phmech/_codes.py), each law class
names a kind the core has, and the result fields are the arrays a simulation returns."""
import numpy as np

from phmech import _codes, _core, _lawbase, laws
from phmech.laws import (Constant, Cycloidal, Linear, PiecewisePolynomial, Pulse, Sine, Spline, Step,
                         Table)

from test_marshal import described


def test_codes_has_every_table():
    codes = _core.codes()
    assert set(codes) == {"pair_types", "law_kinds", "integrators", "actuator_kinds", "component_kinds",
                          "mass_kinds", "result_fields"}
    for name, table in codes.items():
        names = table if name == "result_fields" else list(table)
        assert all(n == n.lower() for n in names), name
        if name != "result_fields":
            assert len(set(table.values())) == len(table), name


def test_pair_types_match_the_pair_table():
    assert _core.codes()["pair_types"] == {row["name"]: row["code"] for row in _core.pair_types()}


def test_every_law_class_has_a_core_kind():
    kinds = _core.codes()["law_kinds"]
    leaves = {Constant: "constant", Step: "step", Pulse: "pulse", Sine: "sine", Table: "table",
              Cycloidal: "cycloidal", Linear: "linear", PiecewisePolynomial: "ppoly"}
    examples = {Table: Table((0.0, 1.0), (0.0, 1.0)), Spline: Spline((0.0, 1.0), (0.0, 1.0)),
                PiecewisePolynomial: PiecewisePolynomial((0.0, 1.0), ((1.0, 0.0),))}
    for cls, name in leaves.items():   # each core kind's own class
        law = examples[cls] if cls in examples else cls()
        assert law._core_leaf()[0] == name, cls.__name__
        assert laws.core_tuple(law._checked())[0] == kinds[name], cls.__name__
    for cls in laws._CLASSES.values():   # every other leaf is evaluated as one of them (Spline: ppoly)
        if cls not in (laws.Sum, laws.Product, laws.Function):
            law = examples[cls] if cls in examples else cls()
            assert law._core_leaf()[0] in leaves.values(), cls.__name__
    assert (_lawbase._EXPR, _lawbase._SUM, _lawbase._PRODUCT, _lawbase._CALLBACK) == \
        (kinds["expr"], kinds["sum"], kinds["product"], kinds["callback"])


def test_python_reads_its_codes_from_the_core():
    codes = _core.codes()
    assert dict(_codes.PAIR_TYPES) == codes["pair_types"]
    assert dict(_codes.LAW_KINDS) == codes["law_kinds"]
    assert dict(_codes.INTEGRATORS) == codes["integrators"]
    assert dict(_codes.ACTUATOR_KINDS) == codes["actuator_kinds"]
    assert dict(_codes.MASS_KINDS) == codes["mass_kinds"]
    assert [f.name for f in _codes.RESULT_FIELDS] == codes["result_fields"]


def test_result_fields_are_the_arrays_simulate_returns():
    fields = _core.codes()["result_fields"]
    model = _core.model_new(**described())
    seen = {}
    r = _core.model_simulate(model, np.array([0.0, 1e-3]), 1e-6, 1e-8, 0,
                             integrator=_core.codes()["integrators"]["ida"],
                             arrays=lambda d: seen.update(d))
    arrays = [k for k, v in r.items() if isinstance(v, np.ndarray) and k != "t"]
    assert arrays == fields
    assert list(seen) == ["t"] + fields
    assert all(seen[k] is r[k] for k in seen)

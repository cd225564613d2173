"""The core's code tables (``_core.codes()``, csrc/util/codes.c and the pair table of
csrc/model/pair.c): Python reads every code from them (python/phmech/_codes.py), each law class
names a kind the core has, and the result fields are the arrays a simulation returns."""
import numpy as np

from phmech import _codes, _core, laws
from phmech.laws import (Constant, Cycloidal, Linear, PiecewisePolynomial, Pulse, Sine, Step,
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
    assert {cls: name for cls, (name, _) in laws._LAWS.items()} == leaves
    for cls in (Constant, Step, Pulse, Sine, Cycloidal, Linear):
        assert laws.core_tuple(cls())[0] == kinds[leaves[cls]], cls.__name__
    assert (laws._EXPR, laws._SUM, laws._PRODUCT, laws._CALLBACK) == \
        (kinds["expr"], kinds["sum"], kinds["product"], kinds["callback"])


def test_python_reads_its_codes_from_the_core():
    codes = _core.codes()
    assert dict(_codes.PAIR_TYPES) == codes["pair_types"]
    assert dict(_codes.LAW_KINDS) == codes["law_kinds"]
    assert dict(_codes.INTEGRATORS) == codes["integrators"]
    assert dict(_codes.ACTUATOR_KINDS) == codes["actuator_kinds"]
    assert dict(_codes.MASS_KINDS) == codes["mass_kinds"]
    assert list(_codes.RESULT_FIELDS) == codes["result_fields"]


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

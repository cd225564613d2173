"""The core's code tables (``_core.codes()``, csrc/util/codes.c and the pair table of
csrc/model/pair.c) against the codes Python still types by hand (python/phmech/_marshal.py), and
the result fields against the arrays a simulation returns: every hand-typed value must equal the
core's, so that Python can read them from the core instead."""
import numpy as np

from phmech import _core, _marshal
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


def test_marshal_law_kinds_match_the_core():
    kinds = _core.codes()["law_kinds"]
    leaves = {Constant: "constant", Step: "step", Pulse: "pulse", Sine: "sine", Table: "table",
              Cycloidal: "cycloidal", Linear: "linear", PiecewisePolynomial: "ppoly"}
    assert set(_marshal._LAWS) == set(leaves)
    for cls, name in leaves.items():
        assert _marshal._LAWS[cls][0] == kinds[name], cls.__name__
    assert (_marshal._EXPR, _marshal._SUM, _marshal._PRODUCT, _marshal._CALLBACK) == \
        (kinds["expr"], kinds["sum"], kinds["product"], kinds["callback"])


def test_marshal_actuator_and_mass_kinds_match_the_core():
    codes = _core.codes()
    assert _marshal._ACTUATOR_KINDS == codes["actuator_kinds"]
    assert _marshal._MASS_KINDS == codes["mass_kinds"]


def test_integrators_match_the_core():
    # python/phmech/mechanism.py, simulate: {"ida": 0, "generalized-alpha": 1}
    assert _core.codes()["integrators"] == {"ida": 0, "galpha": 1}


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

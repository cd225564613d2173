"""The core's code tables, read from the core (``_core.codes()``, csrc/util/codes.c and the pair
table of csrc/model/pair_types.c): no code crosses the boundary typed by hand. Each table maps the
name of an enum value of csrc/include/phmech_types.h (lower case) to its code.

Also the core's stateless kernels that the describe layer calls (pair kinematics, time-law
evaluation, an element's consistent mass): through here, so that only the modules of the core
layer import ``phmech._core`` (docs/architecture.md, "Python layers")."""
from __future__ import annotations

from types import MappingProxyType
from typing import NamedTuple

from . import _core
from ._core import element_mass, law_eval, pair_coordinates, pair_pose, pair_types

__all__ = ["PAIR_TYPES", "LAW_KINDS", "INTEGRATORS", "ACTUATOR_KINDS", "MASS_KINDS",
           "ResultField", "RESULT_FIELDS", "element_mass", "law_eval", "pair_coordinates", "pair_pose",
           "pair_types"]

_CODES = _core.codes()

#: pair type name -> phm_pair_type (csrc/model/pair_types.c)
PAIR_TYPES = MappingProxyType(dict(_CODES["pair_types"]))
#: time-law kind name -> phm_law_kind ("constant", ..., "ppoly", "callback", "expr", "sum", "product")
LAW_KINDS = MappingProxyType(dict(_CODES["law_kinds"]))
#: integrator name -> phm_integrator ("ida", "generalized-alpha", "tree")
INTEGRATORS = MappingProxyType(dict(_CODES["integrators"]))
#: actuator kind name -> phm_actuator_kind ("effort", "pd", "spring")
ACTUATOR_KINDS = MappingProxyType(dict(_CODES["actuator_kinds"]))
#: element mass kind name -> phm_element_mass_kind ("lumped", "consistent", "given")
MASS_KINDS = MappingProxyType(dict(_CODES["mass_kinds"]))


class ResultField(NamedTuple):
    """One row of the table of result quantities (csrc/include/phmech_results.h): the array
    ``name`` a simulation returns, ``dims`` the names of one output's dimensions (e.g.
    ``("pair", "component")``), its ``unit``, the ``noun`` messages name it by and ``text``, one
    line saying what it holds."""
    name: str
    dims: tuple
    unit: str
    noun: str
    text: str


#: the arrays a simulation returns, in phm_sim_output's order (_core.result_fields())
RESULT_FIELDS = tuple(ResultField(**f) for f in _core.result_fields())

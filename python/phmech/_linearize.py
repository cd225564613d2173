"""Mechanism.linearize: the linear port-Hamiltonian model (phmech.linear) about the initial
configuration or a static equilibrium, from the core's reduced stiffness, damping and mass on the
constraint manifold (``_core.model_linear``) and the input matrix of the chosen ports; with
components, their linearized laws and states (the closed loop, docs/method.md section 7.5)."""
from __future__ import annotations

import warnings
from typing import Optional, Sequence


from . import _core, linear, _model, _modes
from ._checks import real
from ._errors import EquilibriumWarning, outside_stacklevel
from .results import StaticResult


def linearize(mech, at: Optional[StaticResult] = None, inputs: Sequence = (),
              outputs: Optional[Sequence] = None, time: float = 0.0, spin=None):
    """Mechanism.linearize of the builder ``mech`` (python/phmech/mechanism.py: its docstring
    gives the arguments, their units and what is returned)."""
    time = real("time", time)
    _model.check_linearization_time(mech, "linearize", time, at)
    model, poses, lam, keep = _model.linearization_point_kept(mech, at)
    eq = None
    if spin is None:   # spun_point finds the relative equilibrium instead
        poses, lam, eq = _modes.equilibrium_point(mech, keep, model, poses, lam, time, at)
        if mech._desc.components:   # their verdict is the linear model's (rest_check)
            eq = None
    try:
        poses, lam = _modes.spun_point(mech, model, spin, at, time, poses, lam)
        lin = linear.build(_core, model, mech._desc, list(inputs) if not isinstance(inputs, str)
                           else [inputs], outputs, poses, lam, time, spin=spin is not None,
                           point_poses=mech._state.poses)
    finally:
        if spin is not None:
            _core.model_set_spin(model, [0.0] * 6)
    if eq is None:
        eq = _modes.rest_check(lin)
    if not eq:
        warnings.warn(f"linearize: the configuration is not a static equilibrium "
                      f"({eq.reason}): the model's stiffness K is the tangent there and "
                      f"its state x = 0 is not a rest state (the loads' unbalanced "
                      f"generalized forces are left out), so its responses are not small "
                      f"motions about the mechanism's rest. Linearize about an equilibrium: "
                      f"linearize(at=m.static(...))",
                      EquilibriumWarning, stacklevel=outside_stacklevel())
    return lin

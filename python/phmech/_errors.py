"""The exceptions and warning classes of phmech, and where its warnings point.

The bottom of the Python layer (docs/architecture.md, "Python layers"): every other module takes
its errors from here, so that only the modules that call the C core import ``phmech._core``.
ModelError (a model or an argument the core or phmech refuses) and SolverError (an analysis that
failed) are the core's own (csrc/pyext); the others are phmech's."""
from __future__ import annotations

import os
import sys
import warnings
from typing import Sequence

from ._core import ModelError, SolverError, __version__

__all__ = ["ModelError", "SolverError", "__version__", "CostWarning", "AccuracyWarning",
           "PlausibilityWarning", "EquilibriumWarning", "StabilityWarning",
           "RedundantConstraintWarning", "ConstraintError", "UnattachedWarning",
           "InitialValueWarning", "ControllerError"]


class CostWarning(UserWarning):
    """A simulation is spending far more steps than the frequency band it was asked to resolve
    needs: it is following vibrations above that band (typically the axial and shear modes of a
    flexible link's mesh), which the output interval cannot even show."""


class AccuracyWarning(UserWarning):
    """A result is less accurate than phmech's contract: a finished simulation's energy ledger
    (E - E0 - supplied + dissipated) drifted by more than ``LEDGER_WARN`` of the energy the run
    moved and exchanged (the integrator created or destroyed that much energy, so the trajectory
    itself is doubtful), its error estimate stayed above the tolerance (warn_if_above_tolerance),
    or an analysis whose figures double precision or the model cannot resolve. The message gives
    the measured figure, the bound and the remedy."""


class PlausibilityWarning(UserWarning):
    """A model that runs but is implausible for a physical mechanism: a value that looks like a
    unit slip (Young's modulus in GPa, a section in mm, a density in g/cm^3, an angle in
    degrees), or a run whose flexible links strain beyond a few per cent or are stressed far
    beyond what their material can carry. The message gives the measured value, the bound and
    what was probably meant (docs/user_guide.md, "Plausibility checks")."""


class EquilibriumWarning(UserWarning):
    """Mechanism.modes was asked for modes at a configuration that is not a static equilibrium:
    the values are then eigenvalues of the tangent there, not vibration frequencies."""


class StabilityWarning(UserWarning):
    """A static equilibrium is unstable (its tangent stiffness has a negative eigenvalue), or a
    linearization cannot judge stability (follower loads)."""


class RedundantConstraintWarning(UserWarning):
    """The mechanism is hyperconstrained: some constraint rows are dependent at the initial
    configuration and were left out of the DAE (see ``Mechanism.redundant_constraints``)."""


class ConstraintError(SolverError):
    """A pair came apart during a simulation: the position residual of one of its constraint
    rows went beyond the tolerance the integrators hold every pair to (``CONSTRAINT_TOL`` rad and
    ``CONSTRAINT_TOL`` times the mechanism's size in m, with IDA its ``rtol`` where that is
    larger, or ``atol`` if larger still; checked after every step of the generalized-alpha, at
    every output of IDA; docs/user_guide.md, "Constraints"). Typically a row left out as redundant at the initial configuration that is
    no longer redundant (a spatial loop whose axes were dependent only there). Attributes:
    ``pair`` (name), ``direction`` (the row's constraint-wrench direction in the pair's frame
    F_b), ``redundant`` (the row was left out at the start), ``residual`` and ``tolerance`` (m or
    rad, ``unit``), ``time`` [s], ``result`` (the trajectory up to the last output before)."""
    pair: str
    direction: str
    redundant: bool
    residual: float
    tolerance: float
    unit: str
    time: float


class ControllerError(ModelError):
    """A sampled controller failed during a run (python/phmech/_sampled.py): its function
    raised, returned something other than (u, state), a u of the wrong shape or not finite.
    Attributes: ``component`` (the controller's name), ``time`` [s] (the sample instant),
    ``result`` (the trajectory up to and including that instant); the function's own exception,
    if any, is the ``__cause__``."""
    component: str
    time: float


class UnattachedWarning(UserWarning):
    """Some bodies or links are not connected to the ground by any pair or spring-damper: they
    fly freely (under gravity they fall), which is what a forgotten pair gives
    (``start=``/``at=`` only place a link or body, they do not join it). Join an intended free
    group to the ground with a ``ph.Free()`` pair (no constraint) to say so; see
    ``Mechanism.unattached`` and docs/user_guide.md, "Initial configuration", "Free bodies"."""


class InitialValueWarning(UserWarning):
    """The loop closure of the initial configuration moved a given joint coordinate (``x0``) or
    a given pose beyond its tolerance (see ``Mechanism.initial_adjustments``; with
    ``Mechanism(strict=True)`` this is a ModelError instead)."""


def outside_stacklevel() -> int:
    """The ``stacklevel`` that makes a warning issued by this function's caller point at the
    first frame outside phmech: the user's line (simulate, modes, ...), however deep inside
    phmech it was found. (Python 3.12's ``skip_file_prefixes`` does this; pyproject.toml
    supports 3.10.)"""
    here = os.path.dirname(__file__)
    frame, level = sys._getframe(1), 1
    while frame is not None and os.path.dirname(frame.f_code.co_filename) == here:
        frame, level = frame.f_back, level + 1
    return level


def warn_plausibility(messages: Sequence[str]) -> None:
    """Each message (phmech._checks: a value that looks like a unit slip) as a
    PlausibilityWarning at the user's line."""
    for msg in messages:
        warnings.warn(msg, PlausibilityWarning, stacklevel=outside_stacklevel())

"""phmech: port-Hamiltonian, graph-based simulation of mechanisms with rigid bodies and
flexible links (geometrically nonlinear beams), with a C core and SUNDIALS IDA.

Conventions: SI units; twist t = (omega, v) and wrench w = (tau, f), angular part first;
poses are 4x4 homogeneous matrices; arrays returned are C-ordered float64.
"""
from __future__ import annotations

import os
import sys

from . import _core
from ._errors import (AccuracyWarning, ConstraintError, CostWarning, EquilibriumWarning,
                      InitialValueWarning, ModelError, PlausibilityWarning, RedundantConstraintWarning,
                      SolverError, StabilityWarning, UnattachedWarning, ControllerError,
                      __version__)   # __version__: meson.build's project() version
from . import analysis, fmu, graphs, io, linear, mechanism, mesh, mixed, se3, timoshenko, urdf
from .actuators import PD, Effort, Spring
from . import components
from .components import (CallbackController, CoulombFriction, DCMotor, LinearController,
                         LuGreFriction, PortHamiltonianController, StribeckFriction,
                         ViscousFriction)
from . import controllers, sensors
from .controllers import EffortOutput, MotorVoltageOutput, SampledController, WrenchOutput
from .fmu import export_fmu
from .frames import Body, FlexibleLink, Frame, rotation
from .graphs import Graphs
from .laws import (Constant, Cycloidal, Function, Linear, Motion, PiecewisePolynomial, Product,
                   Pulse, Sine, Spline, Step, Sum, Table, Trapezoidal, law_from_data)
from .linear import LinearPortHamiltonian, Passivity
from .mechanism import Mechanism, load
from . import pairs as _pairs
# every pair type of the core's table (csrc/model/pair_types.c), by its class name: a new type
# needs no line here
from .pairs import *  # noqa: F401,F403
from .results import (FreeMotion, InitialAdjustment, InitialConfiguration, ModesResult, Momentum,
                      SimulationResult, StaticResult, load_result)
from .sensors import (ComponentState, FrameSensor, JointSensor, LinkStrain, PairWrench,
                      TipDeflection)
from .section import BeamProperties, Material, Section, table1_properties
from .sweep import sweep
from .urdf import URDFRobot, load_urdf

#: the public names, each once (docs/api.rst documents them in this order; docs/conf.py)
__all__ = ["ModelError", "SolverError", "CostWarning", "info", "blas_threads", "__version__",
           "se3", "graphs", "mesh", "mixed", "timoshenko", "analysis", "load", "load_result",
           "sweep", "linear", "LinearPortHamiltonian", "Passivity", "urdf", "load_urdf", "URDFRobot",
           "fmu", "export_fmu",
           "Material", "Section", "BeamProperties", "table1_properties",
           "Mechanism", "Frame", "Body", "FlexibleLink", "rotation", *_pairs.__all__, "Effort", "PD",
           "Spring", "Motion", "Constant", "Step", "Pulse", "Sine", "Table", "Cycloidal", "Linear",
           "Trapezoidal", "Spline", "PiecewisePolynomial", "Sum", "Product", "Function", "law_from_data",
           "SimulationResult", "ModesResult", "StaticResult", "Graphs", "RedundantConstraintWarning",
           "ConstraintError", "InitialValueWarning", "InitialAdjustment", "InitialConfiguration",
           "Momentum", "StabilityWarning", "AccuracyWarning", "PlausibilityWarning",
           "EquilibriumWarning", "FreeMotion", "UnattachedWarning", "components",
           "ViscousFriction", "CoulombFriction", "StribeckFriction", "LuGreFriction", "DCMotor",
           "LinearController", "PortHamiltonianController", "sensors", "JointSensor",
           "FrameSensor", "TipDeflection", "LinkStrain", "PairWrench", "ComponentState",
           "CallbackController", "controllers", "SampledController", "EffortOutput",
           "WrenchOutput", "MotorVoltageOutput", "ControllerError"]

def __getattr__(name: str):
    """``phmech.plot`` is imported on first use, so that ``import phmech`` does not import
    matplotlib."""
    if name == "plot":
        import importlib
        return importlib.import_module(".plot", __name__)
    raise AttributeError(f"module 'phmech' has no attribute {name!r}")


def blas_threads(n: int = 0):
    """Set (``n`` >= 1) and return the number of threads of the OpenBLAS library phmech's C core
    uses for its dense LAPACK work (statics, modes, initial values); ``None`` if that library is
    not OpenBLAS (the reference BLAS is single-threaded). phmech sets 1 at import, or the value of
    the environment variable ``PHMECH_BLAS_THREADS``: OpenBLAS threads spin while they wait, and on
    these problem sizes they cost more CPU than they save (measured: a 10-element static solve
    takes 0.17 s CPU with the default two threads, 0.014 s with one). NumPy's own BLAS is not
    affected."""
    if isinstance(n, bool) or not isinstance(n, int) or n < 0:
        raise ModelError(f"blas_threads: n must be an integer >= 0 (got {n!r})")
    return _core.blas_threads(n)


def _default_blas_threads() -> int:
    v = os.environ.get("PHMECH_BLAS_THREADS", "1")
    try:
        return max(1, int(v))
    except ValueError:
        raise ModelError(f"PHMECH_BLAS_THREADS must be an integer >= 1 (got {v!r})") from None


blas_threads(_default_blas_threads())


def info(file=None) -> dict:
    """Print and return the versions of phmech and of the libraries its C core uses.

    Returns a dict with keys ``phmech``, ``phmech_core``, ``sundials``, ``linear_solvers``,
    ``lapack``, ``blas_threads``, ``compiler``, ``python`` and ``numpy``.
    """
    import numpy

    d = {"phmech": __version__, **_core.build_info(), "blas_threads": _core.blas_threads(0),
         "python": sys.version.split()[0], "numpy": numpy.__version__}
    out = file if file is not None else sys.stdout
    width = max(len(k) for k in d)
    for k, v in d.items():
        print(f"{k:<{width}} : {v}", file=out)
    return d

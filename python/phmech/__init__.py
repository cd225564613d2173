"""phmech: port-Hamiltonian, graph-based simulation of mechanisms with rigid bodies and
flexible links (geometrically nonlinear beams), with a C core and SUNDIALS IDA.

Conventions: SI units; twist t = (omega, v) and wrench w = (tau, f), angular part first;
poses are 4x4 homogeneous matrices; arrays returned are C-ordered float64.
"""
from __future__ import annotations

import sys

from . import _core
from ._core import ModelError, SolverError
from . import analysis, graphs, mixed, se3, timoshenko
from .section import BeamProperties, Material, Section, table1_properties
from . import mechanism
from .mechanism import *  # noqa: F401,F403  (names listed in mechanism.__all__)

__version__ = "0.1.0"

__all__ = ["ModelError", "SolverError", "info", "__version__",
           "se3", "graphs", "mixed", "timoshenko", "analysis",
           "Material", "Section", "BeamProperties", "table1_properties", *mechanism.__all__]


def info(file=None) -> dict:
    """Print and return the versions of phmech and of the libraries its C core uses.

    Returns a dict with keys ``phmech``, ``phmech_core``, ``sundials``, ``linear_solvers``,
    ``lapack``, ``compiler``, ``python`` and ``numpy``.
    """
    import numpy

    d = {"phmech": __version__, **_core.build_info(),
         "python": sys.version.split()[0], "numpy": numpy.__version__}
    out = file if file is not None else sys.stdout
    width = max(len(k) for k in d)
    for k, v in d.items():
        print(f"{k:<{width}} : {v}", file=out)
    return d

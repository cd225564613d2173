"""The Mechanism builder and its analyses: simulation, modes, statics.

A Mechanism collects rigid bodies, flexible links (``se3`` beam elements), kinematic pairs,
actuators and applied wrenches into a model description (phmech.description), finds the initial
configuration from it (phmech.topology, once until the next ``add_*``) and runs the analyses in
the C core (``phmech._core``; phmech._marshal hands the description over): SUNDIALS IDA or the
generalized-alpha method for time integration, LAPACK for modes and statics.

Conventions: SI units; twist (omega, v) and wrench (tau, f), angular part first; poses 4x4.
A beam's local x axis is its centre line; its section axes are y and z.

The classes a model is built from live in their own modules and are re-exported here and from
``phmech``: laws (Constant, ..., Motion), pairs (Fixed, ..., Free), actuators (Effort, PD,
Spring), frames (Frame, Body, FlexibleLink, rotation), results (SimulationResult, ...), graphs (Graphs).
"""
from __future__ import annotations

import math
import os
import numbers
import sys
import warnings
from typing import Callable, Optional, Sequence, Union

import numpy as np

from . import _core, _marshal, _run, analysis, io, planar as _planar, postprocess, se3, topology
from ._checks import (ANGLE_SLIP, array, choice, fibre_strain, inertia_triangle,
                      integer, per_coordinate, positive, positive_definite, real, rigid_pose,
                      section_slips, strain_bound)
from ._core import ModelError, SolverError
from .actuators import PD, Effort, Spring, actuator_row
from .description import ModelDescription
from .fidelity import (FIDELITIES, ModalChoice, choose_modes, distributed_resultant,
                       gravity_preload_sensitivity, interior_modes, modal_sliders,
                       modal_validity, node_offsets,
                       mass_centre, reduction_error, rigid_link_inertia, static_reduction)
from .frames import Body, FlexibleLink, Frame, frame_of, link_of, rotation
from .graphs import Graphs, mechanism_graphs
from .laws import (Constant, Cycloidal, Function, Linear, Motion, PiecewisePolynomial, Product,
                   Pulse, Sine, Spline, Step, Sum, Table, _Law, checked_law, law_from_data)
from .pairs import (Cylindrical, Fixed, Free, Helical, Planar, Prismatic, Revolute, Spherical,
                    Universal, _Pair)
from .results import (ENERGY_NAMES, FreeMotion, InitialAdjustment, InitialConfiguration, ModesResult,
                      Momentum, SimulationResult, StabilityWarning, StaticResult)
from .section import BeamProperties
from ._run import AccuracyWarning, PlausibilityWarning
from .topology import ConstraintError, InitialValueWarning, RedundantConstraintWarning, UnattachedWarning

_recorded = io.recorded   # a builder call a model file replays (phmech/io.py)

#: the adaptive generalized-alpha's default local error tolerance and spectral radius at
#: infinity (docs/integrators.md: measured on benchmarks/scenes.py)
DEFAULT_RTOL = 1e-4
DEFAULT_RHO_INF = 0.9
#: steps an integrator takes at most between two output times (csrc/include/phmech_types.h,
#: phm_sim_options max_steps: its default)
MAX_STEPS = 1_000_000

__all__ = ["Mechanism", "Frame", "Body", "FlexibleLink", "rotation", "Fixed", "Revolute", "Prismatic",
           "Helical", "Cylindrical", "Universal", "Spherical", "Planar", "Free", "Effort", "PD",
           "Spring", "Motion", "Constant", "Step", "Pulse", "Sine", "Table", "Cycloidal", "Linear",
           "Spline", "PiecewisePolynomial", "Sum", "Product", "Function", "law_from_data",
           "SimulationResult", "ModesResult", "StaticResult", "Graphs", "RedundantConstraintWarning", "ConstraintError",
           "InitialValueWarning", "InitialAdjustment", "InitialConfiguration", "Momentum",
           "StabilityWarning", "AccuracyWarning", "PlausibilityWarning", "EquilibriumWarning", "FreeMotion",
           "UnattachedWarning"]


class EquilibriumWarning(UserWarning):
    """Mechanism.modes was asked for modes at a configuration that is not a static equilibrium:
    the values are then eigenvalues of the tangent there, not vibration frequencies."""


def _outside_stacklevel() -> int:
    """The ``stacklevel`` that makes a warning issued by this function's caller point at the
    first frame outside phmech: the user's line (simulate, modes, ...), however deep inside
    phmech it was found. (Python 3.12's ``skip_file_prefixes`` does this; pyproject.toml
    supports 3.10.)"""
    here = os.path.dirname(__file__)
    frame, level = sys._getframe(1), 1
    while frame is not None and os.path.dirname(frame.f_code.co_filename) == here:
        frame, level = frame.f_back, level + 1
    return level


def _warn_plausibility(messages: Sequence[str]) -> None:
    """Each message (phmech._checks: a value that looks like a unit slip) as a
    PlausibilityWarning at the user's line."""
    for msg in messages:
        warnings.warn(msg, PlausibilityWarning, stacklevel=_outside_stacklevel())


def _frame_of(x, mech: "Mechanism", what: str) -> Frame:
    """``x`` (a Frame, Body, 'ground' or a body's name) as a Frame of ``mech`` (frames.frame_of)."""
    return frame_of(x, mech._desc, what)


class Mechanism:
    """A mechanism under construction: add links, bodies, pairs and wrenches, then simulate,
    compute modes or static equilibria. ``gravity`` [m/s^2] in world coordinates.

    ``strict``: when the loop closure of the initial configuration moves a given joint
    coordinate (``x0``) or a given pose beyond its tolerance, raise ModelError instead of warning
    (InitialValueWarning). Tolerances: 1e-6 rad for angles (1e-6 ``|x0|`` for ``|x0|`` > 1 rad), 1e-6 L
    for lengths, L the mechanism's size (topology.length_scale: the largest of the link lengths,
    the pair frames' offsets and the extent of the carriers' initial origins). Either way the
    moves are listed in ``initial_adjustments`` once a model has been built.

    ``band`` [Hz] and ``frequency_tolerance``: the frequencies the model must resolve; every
    flexible link added without ``elements=`` gets the number of elements that puts its modes up
    to ``band`` within ``frequency_tolerance`` of the converged ones (phmech.mesh.choose_elements;
    ``link.mesh`` says what was chosen and the estimated error). Without a band a link gets 10
    elements. (The integrator's band, ``simulate(band=)``, is separate: what the steps resolve.)
    That choice sizes each link free in space; :meth:`sized` sizes the finished mechanism by its
    own modes (supports and couplings included)."""

    def __init__(self, gravity: Sequence[float] = (0.0, 0.0, 0.0), strict: bool = False,
                 band: Optional[float] = None, frequency_tolerance: float = 1e-3):
        g = array("gravity", gravity, (3,), "3 finite numbers [m/s^2]")
        if not isinstance(strict, (bool, np.bool_)):
            raise ModelError(f"strict must be True or False (got {strict!r})")
        if band is not None and not (real("band", band) > 0):
            raise ModelError(f"band must be a frequency > 0 [Hz] or None (got {band!r})")
        tol = real("frequency_tolerance", frequency_tolerance)
        if not 0 < tol < 1:
            raise ModelError(f"frequency_tolerance must be in (0, 1) (got {frequency_tolerance!r})")
        self.strict = bool(strict)
        self.band = None if band is None else real("band", band)
        self.frequency_tolerance = tol
        self.ground = Frame(-1, np.eye(4), "ground")
        self._desc = ModelDescription(g)
        self._names = set()
        #: the initial configuration of the description as it is (topology.InitialState), or
        #: None until an analysis needs it; every add_* drops it
        self._state: Optional[topology.InitialState] = None
        self._warned = None
        self._warned_initial = None
        self._warned_unattached = None
        #: (pair name, constraint direction) rows found redundant at the initial configuration and
        #: left out of the DAE (set when the core model is built: simulate, modes, static, ...)
        self.redundant_constraints: list = []
        #: InitialAdjustment rows: how far the loop closure moved each given x0 coordinate and
        #: each given pose (set when the core model is built, like redundant_constraints)
        self.initial_adjustments: list = []
        #: the groups of bodies and links (tuples of names) that no pair or spring-damper joins
        #: to the ground: they fly freely (set when the core model is built; UnattachedWarning)
        self.unattached: list = []
        #: the builder calls made so far, as a model file holds them (phmech.io: save, load)
        self._calls: list = []
        self._last_settings = None
        self._recording = False
        #: modal link name -> how far its gravity point masses put its end off the full link's
        #: sag (relative; phmech.fidelity.static_reduction), warned about under gravity
        self._modal_gravity_miss: dict = {}
        #: modal link name -> [its chain's arguments, the relative shift of its first frequency
        #: held at its start per m/s^2 of gravity along it (fidelity.gravity_preload_sensitivity;
        #: None until a build under gravity asks)]
        self._modal_preload: dict = {}

    @property
    def gravity(self) -> np.ndarray:
        """Gravitational acceleration [m/s^2] in world coordinates, (3,)."""
        return self._desc.gravity

    @gravity.setter
    def gravity(self, g) -> None:
        self._desc.gravity = array("gravity", g, (3,), "3 finite numbers [m/s^2]")

    # the description's rows under the names tests and examples read (see description.py)
    _car = property(lambda self: self._desc.carriers)
    _el = property(lambda self: self._desc.elements)
    _pairs = property(lambda self: self._desc.pairs)
    _loads = property(lambda self: self._desc.loads)
    _acts = property(lambda self: self._desc.actuators)
    _springs = property(lambda self: self._desc.springs)
    _links = property(lambda self: self._desc.links)
    _bodies = property(lambda self: self._desc.bodies)
    _given = property(lambda self: self._desc.given)

    @property
    def links(self) -> dict:
        """The flexible links by name (a copy of the table: a FlexibleLink per name), e.g. to
        take a loaded or ``sized()`` mechanism's links: ``m.links["arm"].end``."""
        return dict(self._desc.links)

    @property
    def bodies(self) -> dict:
        """The rigid bodies by name (a copy of the table: a Body per name)."""
        return dict(self._desc.bodies)

    # -------------------------------------------------------------- building
    def _check_name(self, name):
        """ModelError unless ``name`` is a new non-empty string."""
        if not isinstance(name, str) or not name:
            raise ModelError(f"name must be a non-empty string (got {name!r})")
        if name in self._names:
            raise ModelError(f"name {name!r} is already used")

    def _new_name(self, name):
        """Claim ``name`` for the component an add_* call is about to add: the description
        changes, so the initial configuration found for it so far is dropped."""
        self._check_name(name)
        self._names.add(name)
        self._state = None
        self._desc.changed()

    @_recorded
    def add_flexible_link(self, name: str, length: float, properties, elements: Optional[int] = None,
                          pose=None, curvature=None, discretization: str = "se3",
                          band: Optional[float] = None,
                          frequency_tolerance: Optional[float] = None, *,
                          start=None, fidelity: str = "nonlinear",
                          mass: str = "consistent", modes: Optional[int] = None) -> FlexibleLink:
        """A flexible link of ``length`` [m] along the local x axis of its start frame, placed by
        ``start`` (a frame: the link's start coincides with it, its axis along the frame's x,
        e.g. ``start=body.frame_at((0.3, 0, 0))``) or ``pose`` (4x4, the pose of its start; give
        one or neither). ``start=frame`` is ``pose=`` the pose that frame has in the initial
        configuration of the mechanism as built so far (its carrier placed by the pairs added
        before, see :meth:`world_pose`). ``properties``: object with 6x6 ``stiffness`` (section stiffness, order
        (torsion, bending y, bending z, axial, shear y, shear z) strains), ``inertia`` (per unit
        length) and ``damping`` (viscous section damping, may be absent). ``curvature``: the
        unstressed curvature (kappa_x, kappa_y, kappa_z) [1/m], or None (straight).

        ``pose`` or ``start`` given: the link's initial pose is honoured -- the pairs on its nodes take their
        reference from it (a Fixed clamp or weld holds the relative orientation its frames have
        at the given poses, e.g. a root rotated about x selects the other bending axis), and
        given poses that violate a pair (frame origins apart, a revolute's axes not parallel)
        raise ModelError; only a pair with ``x0`` places the link elsewhere. ``pose=None``: the
        link is placed from its pairs. See add_pair and docs/user_guide.md.

        ``elements``: the number of se3 elements; None: chosen from ``band`` [Hz] and
        ``frequency_tolerance`` (default: the Mechanism's; see Mechanism and phmech.mesh), or 10
        without a band.

        ``fidelity``: ``"nonlinear"`` (the se3 chain above) or ``"rigid"``: the link is ONE rigid
        body with the link's mass properties (the section inertia integrated along the
        unstressed shape, curvature included; phmech.fidelity), its frame the start frame, and
        the same face: ``start``, ``end`` and ``node(k)`` are frames on it where the nonlinear
        link's nodes sit on the undeformed link (``elements`` or the band set how many, as for a
        nonlinear link, so that switching fidelity keeps every frame), pairs, loads, springs,
        ``record=`` and results take them alike; a distributed load becomes its resultant
        wrench. Right for a link whose first flexible frequency is far above the band of
        interest (docs/user_guide.md, "Model only what a scene needs"); it has no strain, so no
        stress resultants, and its ``properties``' stiffness and damping do not act (they are
        still checked, so that one properties object serves both fidelities).

        ``fidelity="modal"``: the link reduced onto its two ends (interface frames ``start``
        and ``end``; no ``node(k)`` inside): its ``elements``-element se3 chain (the band chooses
        it as for a nonlinear link) linearized at the unstressed shape and condensed by its
        static modes (Guyan reduction; phmech.fidelity, docs/method.md "Modal links"), kept as
        one element whose stiffness, damping and mass are the condensed ones. Exact for the
        link's linear statics between its ends and for any large rigid motion; its dynamics
        carry the link's inertia through the static shapes, right while the link's own modes
        lie well above the band (measured: the leaf spring's first frequency within 1e-7 of the
        full links', docs/user_guide.md); no geometric stiffening (keep "nonlinear" for large
        deflections, fast spin; simulate warns), gravity on two point masses carrying its
        condensed weight (exact for a straight uniform link, a warning for a curved one), no
        distributed load (ModelError).

        ``modes`` (modal links): how many of the link's fixed-interface modes (its chain's modes
        with both ends held) join the static shapes (Craig-Bampton). None: chosen from ``band``
        (the link's or the Mechanism's; a modal link takes ``elements=`` and ``band=`` together,
        the band then choosing its modes only): the fewest with which the link's own frequencies below
        the band, free and held at its start, are those of the chain within
        ``frequency_tolerance`` (``link.modal_choice`` says how many and the error); 0 without
        a band. Each mode is a slider on the link's start frame (a prismatic pair
        ``"<link>.mode<j>"``, whose joint coordinate is the mode's scaled amplitude, and a
        spring-damper ``"<link>.mode<j>.spring"``; docs/method.md "Modal links"): every analysis
        carries it.

        ``mass`` (a nonlinear link's, or the discretization a modal one is reduced from; a rigid
        link's inertia is exact whatever it says): ``"consistent"`` (the default: the kinetic
        energy of each element's constant-strain field at the unstressed shape, blended half-way
        with the lumped one, which couples neighbouring nodes; docs/method.md section 4.2,
        "Mass") or ``"lumped"`` (each node carries the section inertia of half of each adjacent
        element; for comparison). Consistent mass has no interior (dispersion) h^2 error, only
        its ends': at equal N its frequencies are several times more accurate (the Table I
        cantilever at N = 21: within 0.085 % on five modes where lumped is 0.69 % off; clamped at
        both ends 0.32 % against 0.39 %, free 0.44 % against 1.3 %), its energy balance stays
        exact and momentum is conserved; its inertia for a rigid turn about a point is the
        continuum's plus rhoA L h^2/12 (lumped: h^2/6); a run costs 9-17 % more at equal N
        (docs/performance.md, "Consistent element mass"). ``centre_of_mass`` places its mass
        along the elements' fields (SimulationResult.centre_of_mass); gravity acts on the node
        masses, as with lumped mass."""
        if not isinstance(fidelity, str) or fidelity not in FIDELITIES:
            raise ModelError(f"link {name!r}: unknown fidelity {fidelity!r} (available: "
                             f"{', '.join(map(repr, FIDELITIES))})")
        if not isinstance(mass, str) or mass not in ("lumped", "consistent"):
            raise ModelError(f"link {name!r}: unknown mass {mass!r} (available: 'lumped', "
                             f"'consistent')")
        if not isinstance(discretization, str) or discretization != "se3":
            raise ModelError(f"unknown discretization {discretization!r} (available: 'se3')")
        L = real("length", length)
        if L <= 0:
            raise ModelError(f"length must be > 0 (got {L} m)")
        if elements is not None and (isinstance(elements, (bool, np.bool_)) or not isinstance(elements, (int, np.integer))
                                     or elements < 1):
            raise ModelError(f"elements must be an integer >= 1 or None (got {elements!r})")
        if elements is not None and band is not None and fidelity != "modal":
            raise ModelError(f"link {name!r}: give elements= or band=, not both (a modal link "
                             f"takes both: its chain's elements, and the band its modes keep)")
        mat6 = "a finite 6x6 matrix"
        K = array("properties.stiffness", getattr(properties, "stiffness", None), (6, 6), mat6)
        I = array("properties.inertia", getattr(properties, "inertia", None), (6, 6), mat6)
        Dp = getattr(properties, "damping", None)
        Dm = np.zeros((6, 6)) if Dp is None else array("properties.damping", Dp, (6, 6), mat6)
        if not isinstance(properties, BeamProperties):   # (one checked both: section._matrix6)
            if not positive_definite(K):
                raise ModelError("properties.stiffness must be symmetric positive definite")
            if not positive_definite(I):
                raise ModelError("properties.inertia (per unit length) must be symmetric positive definite")
        slips = section_slips(f"link {name!r}", K, I, L)   # warned once the link is added
        given = self._given_pose(pose, start, "start", f"link {name!r}")
        placed = None if start is None else frame_of(start, self._desc, f"link {name!r}: start")
        H = np.eye(4) if given is None else given
        kap = np.zeros(3) if curvature is None else \
            array("curvature", curvature, (3,), "3 finite numbers [1/m] or None")
        self._check_name(name)
        choice = None
        if elements is None:
            band = self.band if band is None else band
            tol = self.frequency_tolerance if frequency_tolerance is None else frequency_tolerance
            if band is not None:
                from .mesh import choose_elements
                choice = choose_elements(L, properties, band, tol, curvature=kap, mass=mass)
        N = int(elements) if elements is not None else choice.elements if choice else 10
        h = L / N
        eps = np.concatenate([kap, [1.0, 0.0, 0.0]])
        with np.errstate(over="ignore", under="ignore", divide="ignore", invalid="ignore"):
            scales = (I * h, K / h, Dm / h, L * eps)   # node inertias, element stiffness, shape
        if not (h > 0 and all(np.all(np.isfinite(x)) for x in scales)):
            raise ModelError(f"link {name!r}: length {L:g} m in {N} elements with these properties "
                             f"gives node inertias or element stiffnesses that are not finite in "
                             f"double precision")
        try:   # the unstressed shape: node k at H exp(k h eps_hat)
            with np.errstate(over="raise", invalid="raise"):
                H0 = [H @ se3.exp(k * h * eps) for k in range(N + 1)]
        except (ValueError, FloatingPointError):   # se3 refuses a non-finite result (ModelError)
            H0 = None
        if H0 is None or not np.all(np.isfinite(H0)):
            raise ModelError(f"link {name!r}: curvature {kap.tolist()} 1/m over length {L:g} m gives "
                             f"node poses that are not finite in double precision")
        if fidelity == "rigid":
            with np.errstate(over="ignore", under="ignore", invalid="ignore"):
                M, mass, com = rigid_link_inertia(L, I, eps)
            if not (np.all(np.isfinite(M)) and positive_definite(M, cholesky=True)):
                raise ModelError(f"link {name!r}: the rigid link's spatial inertia (length {L:g} m, "
                                 f"these properties) is not finite and positive definite in "
                                 f"double precision")
            c = self._start_link(name, eps, placed)
            self._car.append(dict(M=M, mass=mass, com=com, H0=H0[0], t0=np.zeros(6)))
            if given is not None:
                self._given[c] = np.array(H0[0])
            link = FlexibleLink(name, L, N, [c] * (N + 1), choice, fidelity="rigid",
                                offsets=node_offsets(L, N, eps))
            self._links[name] = link
            _warn_plausibility(slips)
            return link
        if modes is not None and fidelity != "modal":
            raise ModelError(f"link {name!r}: modes= is for fidelity='modal' links (this one is "
                             f"{fidelity!r})")
        if fidelity == "modal":
            band = self.band if band is None else band
            tol = self.frequency_tolerance if frequency_tolerance is None else frequency_tolerance
            link = self._add_modal_link(name, L, properties, N, eps, I, H0, given, choice, mass,
                                        modes, band, tol, placed)
            _warn_plausibility(slips)
            return link
        first = self._start_link(name, eps, placed)
        # every node's share of the section, with the section's centre of mass (off the axis
        # in an unsymmetric section): where gravity acts on it
        com = mass_centre(I, float(I[3, 3]))
        for k in range(N + 1):
            share = h if 0 < k < N else h / 2
            Mk = I * share
            self._car.append(dict(M=Mk, mass=float(Mk[3, 3]), com=com.copy(), H0=H0[k],
                                  t0=np.zeros(6)))
        for k in range(N):
            self._el.append(dict(a=first + k, b=first + k + 1, h=h, K=K, D=Dm, eps=eps,
                                 mass=mass, Ms=I))
        if given is not None:
            for k in range(N + 1):
                self._given[first + k] = np.array(self._car[first + k]["H0"])
        link = FlexibleLink(name, L, N, list(range(first, first + N + 1)), choice)
        self._links[name] = link
        _warn_plausibility(slips)
        return link

    def _start_link(self, name: str, eps: np.ndarray, placed: Optional[Frame]) -> int:
        """Claim a link's name and record where its elements start, its unstressed strain and
        the frame ``start=`` placed it at (``placed``, or None); returns the index its first
        carrier will have."""
        self._new_name(name)
        self._desc.first_element[name] = len(self._el)
        self._desc.link_strain[name] = eps
        if placed is not None:
            self._desc.placed_at[len(self._car)] = placed
        return len(self._car)

    def _add_modal_link(self, name, L, properties, N, eps, I, H0, given, choice, mass, modes,
                        band, tol, placed) -> FlexibleLink:
        """add_flexible_link(fidelity="modal"): two carriers (start, end) and one se3 element
        carrying the link's statically reduced stiffness, damping and mass (phmech.fidelity), and
        a slider per fixed-interface mode kept (modal_sliders)."""
        with np.errstate(over="ignore", under="ignore", invalid="ignore", divide="ignore"):
            try:
                red = static_reduction(L, properties, N, eps, mass)
            except np.linalg.LinAlgError:
                red = None
        ok = red is not None and all(np.all(np.isfinite(red[k])) for k in ("K", "D", "Mc", "M_start", "M_end"))
        if not (ok and positive_definite(red["K"], cholesky=True) and positive_definite(red["M_B"], cholesky=True)
                and positive_definite(red["M_start"], cholesky=True) and positive_definite(red["M_end"], cholesky=True)):
            raise ModelError(f"link {name!r}: its static reduction ({N} elements onto its ends) is not "
                             f"finite and positive definite in double precision (length {L:g} m with "
                             f"these properties)")
        interior = len(red["chain"]["interior"])
        modal_choice = None
        if modes is not None:
            if isinstance(modes, (bool, np.bool_)) or not isinstance(modes, (int, np.integer)) \
                    or modes < 0:
                raise ModelError(f"link {name!r}: modes must be an integer >= 0 or None (got {modes!r})")
            if modes > interior:
                raise ModelError(f"link {name!r}: modes={modes} but its {N}-element chain has "
                                 f"{interior} interior degrees of freedom, so at most {interior} "
                                 f"fixed-interface modes (more elements=, or fewer modes)")
            n = int(modes)
            shapes = interior_modes(red, n)
            if band is not None:
                err, _ = reduction_error(red, shapes, band)
                modal_choice = ModalChoice(n, band, tol, err, False)
        elif band is not None:
            n, err, shapes = choose_modes(red, band, tol)
            modal_choice = ModalChoice(n, band, tol, err, True)
        else:
            n, shapes = 0, interior_modes(red, 0)
        for j in range(n):   # the sliders' names, before anything is added
            for nm in (f"{name}.mode{j + 1}", f"{name}.mode{j + 1}.spring"):
                if nm in self._names:
                    raise ModelError(f"link {name!r}: its mode {j + 1} needs the name {nm!r}, which "
                                     f"is already used")
        sl = modal_sliders(red, shapes, L)
        if sl["mismatch"] > 1e-8:
            raise ModelError(f"link {name!r}: its {n} fixed-interface modes as sliders reproduce the "
                             f"Craig-Bampton mass only to {sl['mismatch']:.2g} (ill-conditioned in "
                             f"double precision); keep fewer modes")
        if n and sl["damping_coupling"] > tol:
            warnings.warn(f"link {name!r}: its section damping couples its modes with each other "
                          f"and with its ends (correlation {sl['damping_coupling']:.2g}); a modal "
                          f"link keeps only each mode's own damping (exact for a damping "
                          f"proportional to the stiffness)", AccuracyWarning, stacklevel=_outside_stacklevel())
        first = self._start_link(name, eps, placed)
        # gravity's point masses: the chain's weights condensed onto the ends (phmech.fidelity;
        # also what centre_of_mass() reads); the start's gives the sliders theirs
        (m_a, c_a, _), (m_b, c_b, _) = red["gravity"]
        m_keep = m_a - sl["gravity_taken"]
        self._car.append(dict(M=sl["M_start"], mass=m_keep, com=c_a * (m_a / m_keep), H0=H0[0],
                              t0=np.zeros(6)))
        self._car.append(dict(M=sl["M_end"], mass=m_b, com=c_b, H0=H0[N], t0=np.zeros(6)))
        self._modal_gravity_miss[name] = red["gravity_sag_error"]
        self._modal_preload[name] = [(L, properties, N, eps, mass), None]   # measured when needed
        self._el.append(dict(a=first, b=first + 1, h=L, K=red["K"], D=red["D"], eps=eps,
                             mass="given", Mc=sl["Mc"], Ms=I))
        sliders = list(range(first + 2, first + 2 + n))
        for j, s in enumerate(sl["sliders"]):
            self._car.append(dict(M=s["M"], mass=s["gravity_mass"], com=np.zeros(3), H0=H0[0],
                                  t0=np.zeros(6)))
            ends = {"start": first, "end": first + 1}
            for other, C in s["couplings"].items():
                a = ends[other] if isinstance(other, str) else first + 2 + other
                self._desc.couplings.append(dict(a=a, b=first + 2 + j, Mc=C))
        if given is not None:
            self._given[first] = np.array(H0[0])
            self._given[first + 1] = np.array(H0[N])
            for c in sliders:
                self._given[c] = np.array(H0[0])
        link = FlexibleLink(name, L, 1, [first, first + 1], None, fidelity="modal", reduced_from=N,
                            clamped_frequency=red["omega_clamped"] / (2.0 * np.pi),
                            sliders=sliders, modal_choice=modal_choice,
                            modal_peaks=[list(s["peak"]) for s in sl["sliders"]])
        self._links[name] = link
        reach = 10.0 * L
        for j, (c, s) in enumerate(zip(sliders, sl["sliders"])):
            on_start = Frame(first, np.eye(4), f"{name}.start")
            on_slider = Frame(c, np.eye(4), f"{name}.mode{j + 1}")
            self.add_pair(f"{name}.mode{j + 1}", Prismatic(axis=s["axis"]), on_start, on_slider)
            # collinear with the slide: tension k (d - reach) = k s exactly
            self.add_spring_damper(f"{name}.mode{j + 1}.spring", on_start, on_slider, s["k"], s["c"],
                                   rest_length=reach, point_a=-reach * s["axis"])
            # its energy is the link's strain energy, of its mode's kinds (analysis.label_modes)
            self._springs[-1].update(link=name, kinds=np.asarray(s["kinds"], dtype=float))
        if choice is not None and choice.modes_in_band > 0 and n == 0:
            warnings.warn(f"link {name!r} is modal but has {choice.modes_in_band} of its own "
                          f"(free-free) modes in the band {choice.band:g} Hz, from "
                          f"{choice.frequencies[0]:.4g} Hz: with modes=0 a modal link keeps only "
                          f"its static shapes, so it drops them; leave modes=None to have them "
                          f"chosen from the band", AccuracyWarning, stacklevel=_outside_stacklevel())
        return link

    @_recorded
    def add_rigid_body(self, name: str, mass: float, inertia, com=(0.0, 0.0, 0.0), pose=None,
                       twist=None, *, at=None) -> Body:
        """A rigid body: ``mass`` [kg], ``inertia`` 3x3 about the centre of mass in body axes
        [kg m^2], ``com`` in body coordinates [m], initial ``pose`` (4x4) or ``at`` (a frame the
        body frame coincides with, e.g. ``at=link.end`` or ``at=m.ground.frame_at((0, 0, 1))``:
        the pose that frame has in the initial configuration as built so far, see
        :meth:`world_pose`; give one or neither) and body ``twist`` (omega [rad/s], v [m/s];
        None: moving with its pairs and their ``xdot0``, at rest if free). A given ``pose`` or
        ``at`` is honoured by the pairs on the body like a flexible link's (see
        add_flexible_link, add_pair); neither: placed from its pairs."""
        m = real("mass", mass)
        if m <= 0:
            raise ModelError(f"mass must be > 0 (got {m} kg)")
        spd = "a symmetric positive definite 3x3 matrix [kg m^2]"
        J = array("inertia", inertia, (3, 3), spd)
        if not positive_definite(J):
            raise ModelError(f"inertia: expected {spd}")
        inertia_triangle(f"body {name!r}", J)
        c = array("com", com, (3,), "3 finite numbers [m]")
        tw = np.zeros(6) if twist is None else array("twist", twist, (6,), "6 finite numbers (omega [rad/s], v [m/s]) or None")
        given = self._given_pose(pose, at, "at", f"body {name!r}")
        placed = None if at is None else frame_of(at, self._desc, f"body {name!r}: at")
        H0 = np.eye(4) if given is None else given
        C = np.array([[0, -c[2], c[1]], [c[2], 0, -c[0]], [-c[1], c[0], 0]])
        M = np.zeros((6, 6))
        with np.errstate(over="ignore", invalid="ignore"):
            M[:3, :3] = J - m * C @ C
            M[:3, 3:] = m * C
            M[3:, :3] = -m * C
            M[3:, 3:] = m * np.eye(3)
        if not (np.all(np.isfinite(M)) and positive_definite(M, cholesky=True)):
            raise ModelError(f"body {name!r}: mass {m:g} kg, inertia (largest {np.max(np.abs(J)):.3g} "
                             f"kg m^2) and com {c.tolist()} m give a spatial inertia that is not "
                             f"finite and positive definite in double precision")
        self._new_name(name)
        self._car.append(dict(M=M, mass=m, com=c, H0=H0, t0=tw))
        b = Body(name, len(self._car) - 1)
        if given is not None:
            self._given[b.carrier] = np.array(self._car[b.carrier]["H0"])
        if twist is not None:
            self._desc.twist_given.add(b.carrier)
        if placed is not None:
            self._desc.placed_at[b.carrier] = placed
        self._bodies[name] = b
        return b

    def _given_pose(self, pose, frame, keyword: str, what: str) -> Optional[np.ndarray]:
        """The initial pose a carrier is given by ``pose`` (4x4) or by ``frame`` (the keyword
        ``keyword``: the frame's world pose, :meth:`world_pose`), None for neither."""
        if frame is None:
            return None if pose is None else rigid_pose(pose, "pose")
        if pose is not None:
            raise ModelError(f"{what}: give pose= or {keyword}=, not both")
        return self.world_pose(frame, f"{what}: {keyword}")

    def world_pose(self, frame, what: str = "world_pose") -> np.ndarray:
        """The world pose (4x4) of ``frame`` (a Frame, Body, 'ground' or a body's name) in the
        initial configuration of the mechanism as built so far: its carrier placed by the tree
        walk from the ground across the pairs added so far (their ``x0``; given poses kept; see
        docs/user_guide.md, "Initial configuration"), before any loop is closed. This is where
        ``add_flexible_link(start=frame)`` and ``add_rigid_body(at=frame)`` put what they add."""
        f = frame_of(frame, self._desc, what)
        if f.carrier < 0:
            return f.T.copy()
        H = topology.place_tree(self._desc)[0]
        return H[f.carrier] @ f.T

    @_recorded
    def add_pair(self, name: str, pair, a, b, driven=None, actuator=None,
                 x0=None, xdot0=None) -> None:
        """A kinematic pair ``pair`` (Fixed, Revolute, Prismatic, Helical, Cylindrical, Universal,
        Spherical, Planar, Free) from frame ``a`` to frame ``b`` (edge (a, b)).

        ``driven``: a Fixed pair takes a prescribed relative motion (Motion); a pair with joint
        coordinates takes time laws of them: one law (a pair with one coordinate: the angle of a
        Revolute or Helical [rad], the displacement of a Prismatic [m]) or a sequence of k
        entries, a law or None (not driven) per coordinate (Cylindrical, Universal, Planar; the
        translations of a Free pair). A driven coordinate is constrained to its law, x_c = s(t)
        (its multiplier is the driving torque or force, its power supplied work in the energy
        ledger); its initial value and rate are s(0) and s'(0) (given x0, xdot0 must agree).
        A speed profile w(t) drives through its integral (Spline.antiderivative, Linear for a
        constant speed). ``actuator``: an
        Effort, PD or Spring on the pair's joint coordinates (its port is named after the pair; add
        more with add_actuator). ``x0``/``xdot0``: initial joint coordinates [rad or m] and rates;
        when ``b`` is a rigid body it is placed there relative to ``a``'s current initial pose and
        twist (add pairs from the ground outwards).

        Initial configuration (docs/user_guide.md): walking from the ground, the carrier beyond
        the pair is placed from it at ``x0`` when ``x0`` is given or when that carrier has no
        given pose (x = 0 without ``x0``). Otherwise the given poses are the reference: the
        pair's coordinates are those of its two frames at the given poses, the weld of a Fixed
        pair holds the relative orientation of its frames there (if neither frame offset has a
        rotation of its own; a rotated offset must agree with the poses), and given poses that
        violate the pair's constrained directions -- frame origins apart [m] or constrained axes
        turned [rad] beyond 1e-6 (1e-6 times the mechanism's size in m) -- raise ModelError
        naming the pair, its frames and the mismatch. Loops are then closed by a Newton
        projection; how far it moved a given ``x0`` or pose is in ``initial_adjustments`` and
        warned about (InitialValueWarning; ModelError with ``Mechanism(strict=True)``)."""
        if not isinstance(pair, _Pair):
            raise ModelError(f"pair {name!r}: unsupported pair type {type(pair).__name__} (available: "
                             "Fixed, Revolute, Prismatic, Helical, Cylindrical, Universal, Spherical, Planar, Free)")
        fa = frame_of(a, self._desc, f"pair {name!r}, argument a")
        fb = frame_of(b, self._desc, f"pair {name!r}, argument b")
        if fa.carrier == fb.carrier:
            raise ModelError(f"pair {name!r}: both frames are on the same carrier, "
                             f"{self._desc.carrier_name(fa.carrier)} (a body or rigid link cannot "
                             f"be paired with itself)")
        try:
            Q = np.eye(4)
            Q[:3, :3] = pair._rotation()
            pitch = pair._pitch()
        except ModelError as e:
            raise ModelError(f"pair {name!r}: {e}") from None
        Ta, Tb = fa.T @ Q, fb.T @ Q
        law, axis, xlaws = None, np.zeros(6), None
        k = pair.k
        if isinstance(driven, Motion):
            if not pair._type.drivable:
                raise ModelError(f"pair {name!r}: a Motion drives Fixed pairs only; drive a "
                                 f"{type(pair).__name__} pair's joint coordinates with time laws "
                                 f"(driven=law, or one law or None per coordinate)")
            axis = array(f"pair {name!r}: motion axis", driven.axis, (6,), "6 finite numbers (omega, v)")
            law = checked_law(driven.law, f"pair {name!r}: Motion law")
        elif driven is not None:
            xlaws = self._joint_laws(name, pair, driven)
        xv = np.zeros(6)
        if x0 is not None:
            if k == 0:
                raise ModelError(f"pair {name!r}: a fixed pair has no joint coordinates (x0)")
            xv[:k] = per_coordinate(x0, k, f"pair {name!r}: x0")
        # warned once the pair is added
        slips = [f"pair {name!r}: x0[{c}] = {xv[c]:g} rad is {abs(xv[c]) / (2 * np.pi):.3g} "
                 f"turns (more than one, {ANGLE_SLIP:.4g} rad): an angle in degrees? {xv[c]:g} "
                 f"degrees is {np.radians(xv[c]):.4g} rad (np.radians)"
                 for c in range(k) if x0 is not None and pair._units[c] == "rad"
                 and abs(xv[c]) > ANGLE_SLIP]
        xd = None if xdot0 is None else per_coordinate(xdot0, k, f"pair {name!r}: xdot0")
        if xdot0 is not None and k == 0:
            raise ModelError(f"pair {name!r}: a fixed pair has no joint rates (xdot0)")
        self._check_name(name)
        xdv = np.zeros(6)
        if xd is not None:
            xdv[:k] = xd
        has_x0, has_xd = x0 is not None, xdot0 is not None
        if xlaws is not None:   # driven coordinates start at s(0) with rate s'(0)
            for c, lw in enumerate(xlaws):
                if lw is None:
                    continue
                s0, ds0, _ = (float(v) for v in lw.derivatives(0.0))
                unit = pair._units[c]
                for given, key, v, what in ((has_x0, x0, s0, "x0"), (has_xd, xdot0, ds0, "xdot0")):
                    g = (xv if what == "x0" else xdv)[c]
                    if given and abs(g - v) > 1e-9 * max(1.0, abs(v)):
                        raise ModelError(f"pair {name!r}: {what}[{c}] = {g:.9g} {unit}"
                                         f"{'/s' if what == 'xdot0' else ''} disagrees with its "
                                         f"driving law, which gives {v:.9g} at t = 0; leave it out")
                xv[c], xdv[c] = s0, ds0
            if all(lw is not None for lw in xlaws):
                has_x0 = has_xd = True
        entry = dict(name=name, type=pair._code, a=fa.carrier, b=fb.carrier, Ta=Ta, Tb=Tb,
                     fa_name=self._describe(fa), fb_name=self._describe(fb),
                     driven=law is not None, axis=axis, law=law, pitch=pitch, k=k,
                     x0=xv, has_x0=has_x0, pair=pair, xdot0=xdv,
                     has_xdot0=has_xd, xlaws=xlaws)
        # everything that can fail before anything is changed: a failed call adds nothing
        act = None if actuator is None else actuator_row(name, entry, len(self._pairs), actuator)
        place = None
        if (x0 is not None or xdot0 is not None or xlaws is not None) and \
                fb.carrier in self._desc.body_carriers():
            place = self._placed(entry, xv[:k], xdv[:k])
        self._new_name(name)
        self._pairs.append(entry)
        if place is not None:
            self._car[entry["b"]]["H0"], self._car[entry["b"]]["t0"] = place
        if act is not None:
            self._acts.append(act)
        _warn_plausibility(slips)

    @staticmethod
    def _joint_laws(name: str, pair, driven) -> list:
        """The checked laws (or None) of a pair's k joint coordinates from ``driven`` (one law
        for a pair with one coordinate, or k entries), refusing coordinates the core's pair
        table does not let follow a law."""
        k, what = pair.k, f"pair {name!r}: driven"
        if k == 0:
            raise ModelError(f"{what}: a Fixed pair is driven by a Motion (it has no joint coordinates)")
        one = isinstance(driven, (_Law, numbers.Real)) or (callable(driven) and not isinstance(driven, type))
        if one:
            if k != 1:
                raise ModelError(f"{what}: a {type(pair).__name__} pair has {k} joint coordinates; "
                                 f"give one law or None per coordinate")
            items = [driven]
        else:
            try:
                items = list(driven)
            except TypeError:
                raise ModelError(f"{what}: expected a time law (or one law or None per joint "
                                 f"coordinate), got {type(driven).__name__}") from None
            if len(items) != k:
                raise ModelError(f"{what}: a {type(pair).__name__} pair has {k} joint coordinates; "
                                 f"got {len(items)} entries")
        out = []
        for c, lw in enumerate(items):
            if lw is None:
                out.append(None)
                continue
            if not pair._type.xdrivable[c]:
                raise ModelError(f"{what}: joint coordinate {c} of a {type(pair).__name__} pair "
                                 f"cannot follow a law (its rate is an angular velocity, not the "
                                 f"time derivative of the coordinate); drive it with a PD actuator")
            out.append(checked_law(lw, f"{what} (coordinate {c})" if k > 1 else what, numbers_too=True))
        if all(x is None for x in out):
            return None
        return out

    def _describe(self, f: Frame) -> str:
        """A frame's name in quotes, or where an unnamed frame sits."""
        return repr(f.name) if f.name else f"(unnamed frame on {self._desc.carrier_name(f.carrier)})"

    def _placed(self, e, x, xd):
        """Pose H_a T_a h(x) T_b^-1 of carrier b and its twist (that of a plus the joint rate);
        ModelError when x0 or xdot0 are beyond what double precision can place."""
        Ha = np.eye(4) if e["a"] < 0 else self._car[e["a"]]["H0"]
        ta = np.zeros(6) if e["a"] < 0 else self._car[e["a"]]["t0"]
        try:
            with np.errstate(over="raise", invalid="raise"):
                Hb, tb = topology.pose_across(e, x, xd, Ha, ta)
        except (ValueError, FloatingPointError):   # se3 refuses non-finite input (ModelError)
            tb = Hb = np.full(6, np.nan)
        if not (np.all(np.isfinite(Hb)) and np.all(np.isfinite(tb))):
            raise ModelError(f"pair {e['name']!r}: x0 {x.tolist()} and xdot0 {xd.tolist()} give a "
                             f"non-finite initial pose or twist of {self._desc.carrier_name(e['b'])} "
                             f"in double precision")
        return Hb, tb

    def _pair_entry(self, pair):
        for e in self._pairs:
            if e["name"] == pair:
                return e
        raise ModelError(f"unknown pair {pair!r}")

    @_recorded
    def add_actuator(self, name: str, pair: str, actuator) -> None:
        """An actuator (Effort, PD or Spring) named ``name`` on the pair named ``pair``."""
        if not isinstance(pair, str):
            raise ModelError(f"actuator {name!r}: pair must be given by its name (got {pair!r})")
        e = self._pair_entry(pair)
        self._check_name(name)
        act = actuator_row(name, e, self._pairs.index(e), actuator)
        self._new_name(name)
        self._acts.append(act)

    @_recorded
    def add_spring_damper(self, name: str, a, b, k: float, c: float = 0.0,
                          rest_length: Optional[float] = None, point_a=(0.0, 0.0, 0.0),
                          point_b=(0.0, 0.0, 0.0)) -> None:
        """Point-to-point spring-damper between ``point_a`` of frame ``a`` and ``point_b`` of frame
        ``b`` (frame coordinates [m]; the ground's points are world points): tension
        k (d - rest_length) + c dd/dt [N], ``rest_length`` defaulting to the initial distance.
        Its elastic energy is part of the total energy, its dissipation a port of the ledger."""
        fa = frame_of(a, self._desc, f"spring {name!r}, argument a")
        fb = frame_of(b, self._desc, f"spring {name!r}, argument b")
        if fa.carrier == fb.carrier:
            raise ModelError(f"spring {name!r}: both ends are on the same carrier, "
                             f"{self._desc.carrier_name(fa.carrier)}")
        kk, cc = real(f"spring {name!r}: k", k), real(f"spring {name!r}: c", c)
        if kk < 0 or cc < 0:
            raise ModelError(f"spring {name!r}: k and c must be >= 0")
        pa = array(f"spring {name!r}: point_a", point_a, (3,), "3 finite numbers [m]")
        pb = array(f"spring {name!r}: point_b", point_b, (3,), "3 finite numbers [m]")
        pa = fa.T[:3, :3] @ pa + fa.T[:3, 3]
        pb = fb.T[:3, :3] @ pb + fb.T[:3, 3]
        d0 = None if rest_length is None else real(f"spring {name!r}: rest_length", rest_length)
        if d0 is not None and d0 < 0:
            raise ModelError(f"spring {name!r}: rest_length must be >= 0")
        self._new_name(name)
        self._springs.append(dict(name=name, a=fa.carrier, b=fb.carrier, pa=pa, pb=pb, kcd=(kk, cc, d0)))

    @_recorded
    def add_interaction(self, name: str, target, wrench, law: _Law = Constant(1.0),
                        frame: str = "world", point=(0.0, 0.0, 0.0), reaction=None) -> None:
        """An external wrench law(t) * (tau [N m], f [N]) on ``target`` at ``point`` (target frame
        coordinates [m]), in "world" or "body" (target frame) axes; the opposite wrench acts on
        ``reaction`` (a frame or body; None = the ground) through the same point. Its injected
        power is a port of the ledger."""
        load = self._wrench_entry(name, target, wrench, law, frame, point)
        if reaction is not None:
            fr = frame_of(reaction, self._desc, f"interaction {name!r}, argument reaction")
            if fr.carrier == load["carrier"]:
                raise ModelError(f"interaction {name!r}: target and reaction are on the same carrier")
            load["reaction"] = fr.carrier
        load["interaction"] = True
        self._new_name(name)
        self._loads.append(load)

    @_recorded
    def add_wrench(self, name: str, target, wrench, law: _Law = Constant(1.0),
                   frame: str = "world", point=(0.0, 0.0, 0.0)) -> None:
        """An applied wrench law(t) * (tau [N m], f [N]) on ``target`` (a Frame or Body), in
        ``frame`` "world" or "body" axes, applied at ``point`` (body coordinates [m])."""
        load = self._wrench_entry(name, target, wrench, law, frame, point)
        self._new_name(name)
        self._loads.append(load)

    def _wrench_entry(self, name, target, wrench, law, frame, point, what=None) -> dict:
        """The load row of add_wrench, validated, not yet added."""
        what = what or f"wrench {name!r}"
        self._check_name(name)
        f = frame_of(target, self._desc, f"{what}, argument target")
        if f.carrier < 0:
            raise ModelError(f"{what}: cannot load the ground")
        choice(f"{what}: frame", frame, ("world", "body"))
        w = array(f"{what}: wrench", wrench, (6,), "6 finite numbers (tau [N m], f [N])")
        p = array(f"{what}: point", point, (3,), "3 finite numbers [m]")
        law = checked_law(law, f"{what}: law")
        # the offset of a frame on its carrier moves the point of application
        pt = f.T[:3, :3] @ p + f.T[:3, 3]
        if frame == "body":
            R = f.T[:3, :3]
            w = np.concatenate([R @ w[:3], R @ w[3:]])
        return dict(name=name, carrier=f.carrier, world=frame == "world", point=pt, w=w, law=law,
                    reaction=-1)

    @_recorded
    def add_distributed_load(self, name: str, link: FlexibleLink, force_per_length,
                             law: _Law = Constant(1.0), frame: str = "world") -> None:
        """Distributed force [N/m] on a link (``frame`` "world" axes, or "body": each section's
        axes), lumped on its nodes (h/2 at the ends, h inside; one port per node, ``name[k]``);
        on a rigid link, its resultant wrench (one port, ``name``)."""
        self._check_name(name)
        if not isinstance(link, FlexibleLink) or self._links.get(link.name) != link:
            raise ModelError(f"distributed load {name!r}: link must be a flexible link of this "
                             f"mechanism (links: {', '.join(map(repr, self._links)) or 'none'}), "
                             f"got {link!r}")
        q = array(f"distributed load {name!r}: force_per_length", force_per_length, (3,),
                  "3 finite numbers [N/m]")
        if link.fidelity == "modal":
            raise ModelError(f"distributed load {name!r}: link {link.name!r} is modal (reduced onto "
                             f"its ends): a distributed load on it would act only at its two ends; "
                             f"use fidelity='nonlinear' for it")
        if link.rigid:   # its resultant wrench, exact for a rigid body (phmech.fidelity)
            w, pt = distributed_resultant(link.length, self._desc.link_unstressed_strain(link), q,
                                          frame == "world")
            ld = self._wrench_entry(name, link.start, w, law, frame, pt,
                                    f"distributed load {name!r}")
            self._new_name(name)
            self._loads.append(ld)
            return
        h = link.length / link.elements
        loads = []
        for k, c in enumerate(link.nodes):
            share = h if 0 < k < link.elements else h / 2
            loads.append(self._wrench_entry(f"{name}[{k}]", Frame(c, np.eye(4)),
                                            np.concatenate([np.zeros(3), q * share]), law, frame,
                                            (0.0, 0.0, 0.0), f"distributed load {name!r}"))
        for ld in loads:   # all validated: add them all
            self._new_name(ld["name"])
            self._loads.append(ld)

    def save(self, path) -> None:
        """Write this mechanism to the JSON model file ``path``; ``phmech.load(path)`` rebuilds
        it, and the rebuilt mechanism's simulate, modes and static results are bit-identical.
        The file holds the ``add_*`` calls made, with their arguments, and the settings
        (gravity, strict, band, frequency_tolerance); ModelError, and no file, when something
        cannot be saved (a Python function as an argument, say) or the file would not rebuild
        this mechanism. Format and how to extend it: phmech/io.py, docs/user_guide.md."""
        io.save(self, path)

    # -------------------------------------------------------------- graphs, initial configuration
    def graphs(self) -> Graphs:
        """G_B, G_K, G_F, G_I and the incidence matrices B_K,r, B_K,f, B_I,r, B_I,f with row and
        column labels (paper Sec. IV). A pair or interaction added between a and b, in that
        order, is the edge (a, b): -1 at row a, +1 at row b."""
        return mechanism_graphs(self._desc)

    def _initial_state(self, extra_loads: Sequence[dict] = ()):
        """The initial configuration (topology.initial_state), found once per description and
        kept until the next add_*; returns (InitialState, model), ``model`` the core model the
        steps built (with ``extra_loads``) when it is the analysis's, else None. Sets
        ``redundant_constraints`` and ``initial_adjustments`` and warns or, if ``strict``, raises
        on moves beyond tolerance, at every call. Overflow in these steps (given lengths,
        positions, x0 or rates beyond what double precision can square) is a ModelError, never
        a NaN passed on."""
        if not self._car:
            raise ModelError("the mechanism is empty")
        model = None
        if self._state is None:
            try:
                with np.errstate(over="raise", invalid="raise"):
                    self._state, model = topology.initial_state(self._desc, extra_loads)
            except FloatingPointError as e:
                raise ModelError(f"initial configuration: {e} while placing the carriers and closing "
                                 f"the loops: the model's lengths, positions, x0 or xdot0 are beyond "
                                 f"what double precision can handle") from None
        self._report(self._state)
        return self._state, model

    def _report(self, state: topology.InitialState) -> None:
        """Publish the redundant rows, the adjustments and the free groups of ``state``; warn
        about them (once per distinct message) or raise ModelError with ``strict`` (moves only:
        a free body may be meant)."""
        self.redundant_constraints = list(state.redundant)
        self.initial_adjustments = list(state.adjustments)
        self._warn_unattached(state.unattached)
        moved = [a for a in state.adjustments if a.exceeds]
        if moved:
            msg = ("initial configuration: closing the loops moved given initial values beyond "
                   "their tolerance: " + "; ".join(str(a) for a in moved) +
                   ". Give consistent x0, xdot0 and poses; Mechanism.initial_adjustments lists every "
                   "given value and how far it moved")
            if self.strict:
                raise ModelError(msg + " (Mechanism(strict=True))")
            if self._warned_initial != msg:
                self._warned_initial = msg
                warnings.warn(msg, InitialValueWarning, stacklevel=_outside_stacklevel())
        dropped = state.redundant
        if dropped and self._warned != dropped:
            self._warned = list(dropped)
            warnings.warn(f"hyperconstrained mechanism: {len(dropped)} redundant constraint "
                          f"directions left out of the DAE (pair, direction in F_b): {dropped}",
                          RedundantConstraintWarning, stacklevel=_outside_stacklevel())

    def _warn_unattached(self, groups: list) -> None:
        """Publish the free groups (topology.FreeGroup rows) in ``unattached`` and warn about
        them (UnattachedWarning, pointing at the caller outside phmech), once per distinct set
        of groups."""
        self.unattached = [g.names for g in groups]
        if self.unattached and self._warned_unattached != self.unattached:
            self._warned_unattached = self.unattached
            warnings.warn(topology.unattached_message(self._desc, groups), UnattachedWarning,
                          stacklevel=_outside_stacklevel())

    def _initial(self) -> tuple:
        """Copies of the initial poses, twists, the pairs' x0 rows and drop masks."""
        state, _ = self._initial_state()
        return state.poses.copy(), state.twists.copy(), state.x0.copy(), list(state.drop_masks)

    def initial_configuration(self) -> InitialConfiguration:
        """The initial configuration the analyses start from (tree placement from the given
        poses and x0, loop closure; see docs/user_guide.md): poses, twists, the
        InitialAdjustment table (also left in ``initial_adjustments``) and the redundant
        constraints. Warns (InitialValueWarning) or, with ``strict``, raises ModelError like
        the analyses when the loop closure moved a given value beyond its tolerance."""
        H, T, _, _ = self._initial()
        return InitialConfiguration(H, T, list(self.initial_adjustments), list(self.redundant_constraints))

    def _build(self, extra_loads: Sequence[dict] = ()):
        """The core model of this mechanism at its initial configuration, with ``extra_loads``
        (load rows) after its own: built once per call, or none when finding the initial
        configuration built it."""
        if np.any(self._desc.gravity):
            for nm, miss in self._modal_gravity_miss.items():
                if miss > self.frequency_tolerance:
                    warnings.warn(f"modal link {nm!r} under gravity: two point masses carry its "
                                  f"condensed weight (a curved or pre-twisted link's is not that "
                                  f"of any point), which puts its end, held at its start, "
                                  f"{miss:.2g} off the full link's sag; use fidelity='nonlinear' "
                                  f"for it if that matters", AccuracyWarning, stacklevel=_outside_stacklevel())
            gmax = float(np.max(np.abs(self._desc.gravity)))   # |g| without overflowing
            g = gmax * float(np.linalg.norm(self._desc.gravity / gmax)) if self._modal_preload else 0.0
            for nm, entry in self._modal_preload.items():
                if entry[1] is None:
                    entry[1] = gravity_preload_sensitivity(*entry[0])
                if entry[1] * g > self.frequency_tolerance:
                    warnings.warn(f"modal link {nm!r} under gravity: its weight along it (tension "
                                  f"or compression) moves its first frequency held at its start by "
                                  f"about {100 * entry[1] * g:.2g} % in the full link (geometric "
                                  f"stiffness), which a modal link leaves out (its gravity points "
                                  f"even shift it the other way); use fidelity='nonlinear' for it "
                                  f"if it hangs or stands", AccuracyWarning, stacklevel=_outside_stacklevel())
        state, model = self._initial_state(extra_loads)
        if model is None:
            model = _marshal.core_model(self._desc, state.poses, state.twists, state.x0,
                                        state.drop_masks, state.frames_a, extra_loads)
        return model

    # -------------------------------------------------------------- analyses
    def simulate(self, t_end: float, dt_out: float, rtol: Optional[float] = None,
                 atol: Optional[float] = None, linear_solver: str = "auto",
                 initial: Optional[StaticResult] = None, t_start: float = 0.0,
                 callback: Optional[Callable[[float, int], bool]] = None, max_step: float = 0.0,
                 max_order: Optional[int] = None, record=None, progress: bool = False,
                 error_test: str = "all", integrator: str = "generalized-alpha",
                 step: Optional[float] = None, rho_inf: Optional[float] = None,
                 band: Optional[float] = None, checkpoint=None,
                 checkpoint_every: Optional[float] = None,
                 planar: Optional[bool] = None) -> SimulationResult:
        """Integrate from ``t_start`` to ``t_end`` [s], sampling every ``dt_out`` [s].

        The defaults are meant to be right and fast; ``simulate(t_end, dt_out)`` is the intended
        call. The default integrator is the generalized-alpha method with step-size control.
        What it promises (docs/user_guide.md, "Accuracy contract"):

        - ``rtol`` (default 1e-4) and ``atol`` [m, rad; default rtol * 1e-2]: the configuration
          (carrier positions and quaternions, joint coordinates) is kept within
          ``rtol |y| + atol`` per coordinate, in the RMS norm over the coordinates: every
          accepted step's local error estimate times the number of such steps in the run is at
          most that tolerance (a step above it is redone shorter, down to 1/1000 of the band's
          floor 1/(20 band)). A run that could not keep it warns (``phmech.AccuracyWarning``:
          the estimate reached, the tolerance, when, the remedy).
        - ``dt_out`` [s]: the output times. The steps land on them (no interpolation); it does
          not set the accuracy.
        - ``band`` [Hz] (default 1/(2 dt_out), at least 50 / (t_end - t_start)): the steps are at
          most 1/(12 band). With flexible links, the error estimate sees the motion through a
          low-pass filter at the band: the mesh's vibrations above it (axial, shear and high
          bending modes, kHz to MHz) are damped by the method's numerical dissipation
          (spectral radius at infinity ``rho_inf`` = 0.9 by default) instead of resolved, and
          their effect on the in-band motion is outside the estimate; pass a larger ``band=``
          to resolve them. Rigid mechanisms: the estimate sees every motion.

        docs/integrators.md says what the default does, what it was measured against, and when
        to change it.

        ``initial``: start from these poses (e.g. a StaticResult) at rest instead of the
        modelled initial state. ``callback(t, i)`` is called at each output; return True to
        stop. Ctrl-C, or SIGTERM (a batch system's time limit), stops the run and returns what
        was computed (``interrupted`` = True). A solver failure raises ``phmech.SolverError``
        whose ``result`` attribute holds the trajectory computed up to the failure. ``record``:
        bodies, links (all their nodes) or frames whose poses and twists are stored (default:
        every carrier); energies, joints and ports are always stored. ``progress``: a progress
        line on stderr (simulated time, elapsed, ETA, steps and steps per second).
        ``checkpoint``: a file path; the result so far is written there (netCDF, atomically;
        ``phmech.load_result`` reads it) at the first output after every ``checkpoint_every``
        seconds of wall-clock time (default 60; 0: every output), and the final (or partial,
        on failure) result at the end (phmech._run.Checkpoint, docs/user_guide.md). A
        ``phmech.CostWarning`` is issued when the steps are far smaller than the band needs and
        the run is on course to take long (it says why and what to do).

        Limits: both integrators take at most 10^6 steps between two output times (a run whose
        ``max_step``, ``step`` or ``band`` already implies more raises ModelError at once, any
        other SolverError), and the outputs may take at most half the machine's memory. No
        result holds a NaN or inf: a non-finite value (the model's numbers overflowing double
        precision) raises SolverError with the finite part of the trajectory.

        ``result.stats`` reports what the run cost and how good it is: steps, evaluations
        (``residual_evals``, ``jacobian_evals``: iteration-matrix refreshes, ``nonlinear_iters``:
        Newton iterations, ``newton_iters_per_step``), wall time, ``band`` [Hz]; adaptive
        generalized-alpha only: ``error_estimate`` (the sum of the local error estimates of the
        configuration, max norm: a bound without error propagation), ``error_ratio`` (the
        largest local estimate of an accepted step over its tolerance, per unit step: <= 1
        keeps the contract) and ``error_ratio_time`` [s] (when that step ended), ``floor_steps``
        (steps accepted above the tolerance at the refinement's limit; > 0 warns),
        ``noise_steps`` (steps accepted above the tolerance per unit step where a shorter step
        did not lower the estimate, in a rigid mechanism, or the estimate was within Newton's
        tolerance: docs/user_guide.md, "Accuracy contract"), ``error_sum`` (the accepted steps'
        local estimates summed, in tolerances: above 1 the errors of the noise-accepted steps
        may have added up beyond rtol, and an AccuracyWarning says so), ``newton_rtol``
        (Newton's relative tolerance at the end: 1e-7, or min(rtol, 1e-7), tightened 10x at a
        time down to 1e-11 while error_sum runs ahead of its share of the tolerance, in a run on
        course for at most 3e5 steps),
        ``min_step`` [s] (the shortest step); and ``energy_scale`` [J], ``ledger_relative`` (the largest absolute
        energy ledger residual / energy_scale), ``numerical_dissipation`` [J] (energy the
        integrator removed, from the ledger) and ``max_mu`` (the largest multiplier of the
        position constraints at the outputs, a velocity correction [m/s, rad/s] that is zero for
        the exact motion: docs/method.md section 6.2).

        Other integrators (docs/integrators.md):

        - ``integrator="generalized-alpha", step=h``: fixed step ``h`` [s] (no error estimate;
          ``rtol``/``atol``, default 1e-8 and rtol * 1e-2, are then its Newton tolerances).
          ``rho_inf`` in [0, 1] (default 0.9) is the spectral
          radius at infinity: 1 has no numerical dissipation (then stiff vibrations a step does not resolve
          are not damped and Newton may converge badly), smaller values damp what the step does
          not resolve. Steps are shortened evenly to land on the output times and the breakpoints
          of the time laws (outputs closer than ``h`` shorten the steps to their spacing); after
          the start and each breakpoint a failing first step is redone as one backward-Euler
          step.
        - ``integrator="ida"``: SUNDIALS IDA, variable-order BDF with local error control on
          ``rtol`` (default 1e-8) and ``atol``. ``error_test="all"`` (default) puts every
          differential state in the error test, so the step resolves every vibration present,
          however fast (accurate and energy-consistent, and costly when flexible links are
          excited: minutes to hours where the default takes seconds). ``"configuration"``
          leaves the twists out and needs ``max_order`` <= 2 (default 5 with "all", 2 with
          "configuration"); it controls only the poses' local error, so its global error can
          be far above ``rtol``: a rigid four-bar at rtol 1e-9 ended 8.4e-4 rad off in its
          crank angle after 2 s ("all": 2.8e-6 at order 2, 7.6e-7 at order 5). Keep it for
          flexible links whose mesh vibrations "all" would resolve. ``max_step`` [s] bounds
          the steps (IDA and adaptive generalized-alpha).

        ``linear_solver``: ``"auto"`` (KLU sparse for the generalized-alpha, and for IDA with 6
        or more carriers, else dense), ``"dense"`` or ``"klu"``; both factor the same
        closed-form Jacobian.

        ``planar``: when every carrier moves in one plane normal to a world axis (phmech.planar
        says what is checked, at the initial configuration), the integrator solves a DAE of the
        in-plane states alone (7 of a carrier's 13; out-of-plane constraint rows dropped), with
        the same results. None (default): so when the checks pass, with the generalized-alpha
        (IDA stays 3-D unless asked: see the comment in simulate); True: require it (ModelError
        naming the first check that fails); False: the 3-D DAE. ``result.stats["planar"]`` is
        the plane's normal axis ("x", "y", "z") or None."""
        t0, t1, dt = (real("t_start", t_start), real("t_end", t_end), real("dt_out", dt_out))
        if t1 <= t0:
            raise ModelError(f"t_end must be > t_start (got {t1} <= {t0})")
        if dt <= 0:
            raise ModelError(f"dt_out must be > 0 (got {dt})")
        solvers = {"dense": 0, "klu": 1}
        if isinstance(linear_solver, str) and linear_solver == "auto":
            # the generalized-alpha's KLU matrix drops its exact zeros (dae_jacobian_prune): KLU
            # is then faster than the dense LU from one carrier on (measured 2026-11-27: a
            # pendulum 7.5 against 12.4 ms, the four-bar of benchmarks/scenes.py 51 against 94
            # ms, a 3-carrier modal-link pendulum 0.19 against 0.52 s); IDA keeps its rule, though
            # KLU was faster there too with both on the closed-form Jacobian (a pendulum 1.6
            # against 2.3 ms, five bars 4.8 against 27.7 ms: docs/integrators.md, "IDA's linear
            # solvers: one Jacobian"): a switch moves every small IDA run at the tolerance's level
            linear_solver = "klu" if integrator == "generalized-alpha" or len(self._car) >= 6 \
                else "dense"
        if not isinstance(linear_solver, str) or linear_solver not in solvers:
            raise ModelError(f"unknown linear_solver {linear_solver!r} (available: 'auto', 'dense', 'klu')")
        integrators = {"ida": 0, "generalized-alpha": 1}
        if not isinstance(integrator, str) or integrator not in integrators:
            raise ModelError(f"unknown integrator {integrator!r} (available: {', '.join(map(repr, integrators))})")
        adaptive = integrator == "generalized-alpha" and step is None
        band_given = band is not None
        # the default band: what the outputs can show, but never below BAND_PER_SPAN / span
        # (docs/user_guide.md, "Accuracy contract"): outputs are samples, not steps
        band = max(0.5 / dt, _run.BAND_PER_SPAN / (t1 - t0)) if band is None else positive("band", band)
        if integrator == "generalized-alpha":
            if step is not None:
                step = positive("step", step)
            rho_inf = DEFAULT_RHO_INF if rho_inf is None else real("rho_inf", rho_inf)
            if not 0.0 <= rho_inf <= 1.0:
                raise ModelError(f"rho_inf must be in [0, 1] (got {rho_inf})")
            if not (isinstance(error_test, str) and error_test == "all") or max_order is not None:
                raise ModelError("error_test and max_order apply to integrator='ida' only")
            if max_step is not None and not (isinstance(max_step, (int, float)) and max_step == 0) \
                    and not adaptive:
                raise ModelError("max_step applies to integrator='ida' and to the adaptive "
                                 "generalized-alpha (without step=)")
        elif step is not None:
            raise ModelError("step= applies to integrator='generalized-alpha' (IDA chooses its own steps; "
                             "use max_step to bound them)")
        tests = {"all": 0, "configuration": 1}
        if not isinstance(error_test, str) or error_test not in tests:
            raise ModelError(f"unknown error_test {error_test!r} (available: 'all', 'configuration')")
        if max_order is None:
            max_order = 2 if error_test == "configuration" else 5
        if isinstance(max_order, (bool, np.bool_)) or not isinstance(max_order, (int, np.integer)) or not 1 <= max_order <= 5:
            raise ModelError(f"max_order must be an integer 1..5 (got {max_order!r})")
        if error_test == "configuration" and max_order > 2:
            raise ModelError(f"error_test='configuration' needs max_order 1 or 2 (got {max_order}): "
                             "without the twists in the error test, BDF orders 3-5 let unresolved "
                             "vibrations grow")
        max_step = 0.0 if max_step is None or (isinstance(max_step, (int, float)) and max_step == 0) \
            else positive("max_step", max_step)
        # the integrators stop after MAX_STEPS steps between two outputs: fail now, not then
        h = min([x for x in (max_step, step, 1.0 / (_run.BAND_MAX_STEPS * band) if adaptive else 0.0)
                 if x and x > 0] or [np.inf])
        if dt / h > MAX_STEPS:
            raise ModelError(f"simulate: steps of at most {h:.3g} s (" +
                             ("max_step" if h == max_step else "step" if h == step else
                              f"the {band:.4g} Hz band") +
                             f") would take {dt / h:.3g} steps per output interval dt_out = {dt:g} s; "
                             f"the integrators stop at {MAX_STEPS:.0e} steps between two outputs: "
                             f"use a smaller dt_out, or longer steps")
        rtol = (DEFAULT_RTOL if adaptive else 1e-8) if rtol is None else real("rtol", rtol)
        atol = rtol * 1e-2 if atol is None else real("atol", atol)
        if rtol <= 0 or atol <= 0:
            raise ModelError("rtol and atol must be > 0")
        if callback is not None and not callable(callback):
            raise ModelError(f"callback must be a function callback(t, i) or None (got {callback!r})")
        if initial is not None and not isinstance(initial, StaticResult):
            raise ModelError(f"initial must be a StaticResult (Mechanism.static) or None (got "
                             f"{type(initial).__name__})")
        with np.errstate(over="ignore"):
            span = (t1 - t0) / dt
        self._check_outputs(span, record)
        n = int(np.floor(span + 1e-9))
        tout = t0 + dt * np.arange(n + 1)
        if tout[-1] < t1 - 1e-12 * max(1.0, abs(t1)):
            tout = np.append(tout, t1)
        rec = None if record is None else self._record_carriers(record)
        model = self._build()   # finds the redundant constraints
        drop_masks = self._state.drop_masks
        if rec is not None and self.redundant_constraints:
            raise ModelError("record= cannot be combined with redundant constraints yet: the "
                             "minimum-norm multipliers need every carrier's pose")
        poses = None if initial is None else self._start_poses(initial, "initial")
        twists = None if initial is None else np.zeros((len(self._car), 6))
        if planar not in (None, True, False):
            raise ModelError(f"planar must be None, True or False (got {planar!r})")
        # planar=None leaves IDA in 3-D: with the planar DAE and KLU's pivoting for 3-D it failed
        # the flexible slider-crank of tests/test_flexible_loop.py at rtol 1e-8 (IDA_CONV_FAIL;
        # csrc/solve/ida.c: it runs with AMD and full pivoting, a remedy measured on that one
        # scene), and with the dense LU the spline-driven revolute of
        # tests/test_driven_pairs.py ended its spin-up 1.6e-4 N m off in its torque (3-D 6.7e-5,
        # the test's bound 1.3e-4: where IDA's steps land near the breakpoint)
        auto_ok = integrator != "ida"
        plane = None if planar is False or (planar is None and not auto_ok) else \
            self._plane(model, poses, twists, planar is True)
        run = dict(linear_solver=linear_solver, integrator=integrator, adaptive=adaptive,
                   rtol=rtol, atol=atol, planar=None if plane is None else _planar.AXES[plane[0]])
        sim_model = model if plane is None else plane[2]

        def assemble(r, k, stats, interrupted) -> SimulationResult:
            return self._simulation_result(r, k, tout, model, drop_masks, rec, band,
                                           {**stats, **run}, interrupted, plane)

        saver = None
        if checkpoint is not None:
            saver = _run.Checkpoint(checkpoint, checkpoint_every,
                                    lambda arrays, k, stats: assemble(arrays, k, stats, False))
        elif checkpoint_every is not None:
            raise ModelError("checkpoint_every applies with checkpoint=path only")
        monitor = _run.RunMonitor(t0, t1, band, integrator, progress, callback, checkpoint=saver)
        with _run.sigterm_as_interrupt(monitor):
            r = _core.model_simulate(sim_model, tout, rtol, atol, solvers[linear_solver], poses, twists,
                                     monitor.per_output, float(max_step), int(max_order), rec,
                                     tests[error_test], integrators[integrator], float(step or 0.0),
                                     float(1.0 if rho_inf is None else rho_inf), adaptive=int(adaptive),
                                     band=float(band if adaptive else 0.0), monitor=monitor,
                                     arrays=None if saver is None else saver.arrays_ready,
                                     planar=0 if plane is None else plane[0] + 1)
        monitor.finish(r["stats"]["steps"])
        result = assemble(r, r["nout"], r["stats"], bool(r["interrupted"]) or monitor.terminated)
        unsaved = ""
        if saver is not None:   # the file ends as the run did (a failed run: its partial result)
            try:
                saver.write(result)
            except Exception as e:   # not to hide the solver's error and its partial result
                if not r["error"]:
                    raise
                unsaved = f"; the checkpoint could not be written: {e}"
        if not r["error"]:
            _run.warn_if_inaccurate(result.stats)
            self._warn_implausible_strain(result, model)
            _run.warn_if_above_tolerance(result.stats)
            for lk in self._links.values():
                if lk.fidelity == "modal":
                    T0 = se3.exp(lk.length * self._desc.link_unstressed_strain(lk))
                    for msg in modal_validity(result, lk, T0, self.frequency_tolerance):
                        warnings.warn(msg, AccuracyWarning, stacklevel=_outside_stacklevel())
        if r["error"]:
            t_last = f"{result.t[-1]:.6g} s" if len(result.t) else "the start"
            why = ""   # the output interval bounds the steps: say so
            if integrator == "ida":
                why = (f"; IDA takes at most {MAX_STEPS:.0e} steps between two outputs (dt_out = "
                       f"{dt:g} s): a smaller dt_out, or a looser rtol" +
                       (", or error_test='configuration' for flexible links"
                        if error_test == "all" else "")) if "TOO_MUCH_WORK" in r["error"] else ""
            elif adaptive:
                why = (f"; the steps were at most {1.0 / (_run.BAND_MAX_STEPS * band):.3g} s, from "
                       f"the {band:.4g} Hz band (" + ("band=" if band_given else
                       f"1/(2 dt_out), dt_out = {dt:g} s" if 0.5 / dt >= band else
                       f"{_run.BAND_PER_SPAN:g} / span, the default's floor") + "): a higher band= shortens them")
            err = topology.constraint_error(self._desc, r["error"]) or SolverError(r["error"])
            err.args = (f"{err.args[0]} (the trajectory up to {t_last} is in this error's "
                        f"'result' attribute{unsaved}{why})",)
            err.result = result
            raise err
        return result

    def _plane(self, model, poses, twists, require: bool):
        """(axis, drop masks, core model) of the planar DAE when the scene is planar at its
        start (``model``: this analysis's, made planar in place; ``poses``, ``twists``: the
        run's, None for the initial configuration's), else
        None, or with ``require`` ModelError naming the first check that fails per axis. The
        masks drop the out-of-plane constraint rows and the in-plane rows redundant among the
        in-plane ones."""
        state = self._state
        H = state.poses if poses is None else np.asarray(poses, dtype=float)
        T = state.twists if twists is None else np.asarray(twists, dtype=float)
        # the checks and the out-of-plane rows (csrc/model/planarity.c, phmech.planar)
        k, masks, why = _core.model_planar(model, H, T, [p["name"] for p in self._desc.pairs])
        if k is None:
            if require:
                raise ModelError("planar=True: the scene is not planar (" + "; ".join(
                    f"about {_planar.AXES[k]}: {why[k]}" for k in (2, 1, 0)) + ")")
            return None
        # the in-plane rows redundant among the in-plane ones: only loop-closing pairs' rows can
        # be (topology.redundant_rows: a tree's rows are independent)
        if any(ip not in state.tree for ip in range(len(masks))):
            layout = postprocess.full_layout(self._desc)
            _, G, _ = _core.model_constraints_full(model, H, None, 0.0)
            keep = np.zeros(G.shape[0], dtype=bool)
            keep[postprocess.kept_rows(layout, masks)] = True
            red, _ = topology.redundant_rows(self._desc, G * keep[:, None], state.tree)
            masks = [a | b for a, b in zip(masks, red)]
        # this analysis's model, moved to the planar drop masks (no second model)
        model = _marshal.with_initial(model, self._desc, state.poses, state.poses, state.twists,
                                      state.x0, masks)
        return k, masks, model

    def _simulation_result(self, r: dict, k: int, tout, model, drop_masks, rec, band: float,
                           stats: dict, interrupted: bool, plane=None) -> SimulationResult:
        """The SimulationResult of the first ``k`` outputs in the arrays ``r`` of
        ``_core.model_simulate`` (the whole run, or a checkpoint's part of it while it runs),
        ``stats`` the core's statistics and the run's options."""
        e = r["energy"][:k]
        energy = {nm: e[:, i].copy() for i, nm in enumerate(ENERGY_NAMES)}
        ports = {nm: r["ports"][:k, i].copy() for i, nm in enumerate(self._desc.port_names())}
        layout = _core.model_sizes(model)[4]
        lam, pw = r["lambda"][:k], r["pair_wrenches"][:k]
        if plane is not None and self.redundant_constraints and k > 0:
            lam, pw, layout = postprocess.min_norm_multipliers(
                self._desc, plane[2], plane[1], r["poses"][:k], r["joints"][:k], lam, tout[:k])
        elif plane is not None:   # the 3-D layout has every row: the dropped ones carry 0
            layout = postprocess.full_layout(self._desc)
            keep = postprocess.kept_rows(layout, plane[1])
            full = np.zeros((lam.shape[0], layout[-1][0] + layout[-1][1] if layout else 0))
            full[:, keep] = lam
            lam = full
        elif self.redundant_constraints and k > 0:
            lam, pw, layout = postprocess.min_norm_multipliers(
                self._desc, model, drop_masks, r["poses"][:k], r["joints"][:k], lam, tout[:k])
        pairs = {p["name"]: dict(index=i, layout=layout[i], units=p["pair"]._type.units)
                 for i, p in enumerate(self._pairs)}
        stats = {**stats, **_run.quality(energy, band)}
        # Newton iterations (linear solves) per step, the issue-12 measure (docs/integrators.md,
        # "Newton iterations"); rejected step attempts count in the iterations, not the steps.
        # Not in a checkpoint's mid-run stats, which hold no counters
        if "nonlinear_iters" in stats:
            stats["newton_iters_per_step"] = stats["nonlinear_iters"] / max(1, stats["steps"])
        if not stats["adaptive"]:
            for key in ("error_estimate", "error_sum", "floor_steps", "error_ratio", "error_ratio_time",
                        "noise_steps", "min_step", "newton_rtol"):
                stats.pop(key, None)
        return SimulationResult(t=tout[:k], poses=r["poses"][:k], twists=r["twists"][:k],
                                constraint_wrenches=lam, energy=energy, stats=stats,
                                interrupted=interrupted, _links=dict(self._links),
                                port_energy=ports, joints=r["joints"][:k],
                                joint_rates=r["jrates"][:k], efforts=r["efforts"][:k],
                                pair_wrenches=pw, _pairs=pairs,
                                redundant_constraints=list(self.redundant_constraints),
                                carriers=None if rec is None else np.array(rec),
                                _inertia=np.array([c["M"] for c in self._car], dtype=float),
                                _mass=np.array([c["mass"] for c in self._car], dtype=float),
                                _com=np.array([c["com"] for c in self._car], dtype=float),
                                _bodies=dict(self._bodies),
                                **self._desc.mass_couplings())

    def _check_outputs(self, span: float, record) -> None:
        """ModelError when (t_end - t_start) / dt_out output times would take more than half the
        machine's memory (an accidental t_end / dt_out of 1e10 would otherwise allocate 75 GB,
        or fail inside NumPy)."""
        nc = len(self._car)
        # per output: pose and twist of each recorded carrier; per pair at most 6 multipliers, 6
        # pair wrench entries, 6 joint coordinates, rates and efforts; 7 energies; the ports; t
        per = 8 * (22 * nc + 30 * len(self._pairs) + 7 + len(self._acts) + len(self._loads)
                   + len(self._springs) + 1)
        if record is not None:
            per = max(8 * 30, per - 8 * 22 * (nc - 1))   # at least one carrier recorded
        try:
            limit = 0.5 * os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
        except (AttributeError, ValueError, OSError):
            limit = 8e9
        if not (span * per <= limit):
            raise ModelError(f"simulate: (t_end - t_start) / dt_out = {span:.3g} output times would "
                             f"take about {span * per / 1e9:.3g} GB, more than half this machine's "
                             f"memory ({2 * limit / 1e9:.3g} GB); use a larger dt_out, a shorter run "
                             f"or record= fewer carriers")

    def _start_poses(self, start, what) -> np.ndarray:
        """The poses of a StaticResult used as a starting point, checked against this mechanism."""
        if not isinstance(start, StaticResult):
            raise ModelError(f"{what} must be a StaticResult (Mechanism.static) or None (got "
                             f"{type(start).__name__})")
        return array(f"{what}.poses", start.poses, (len(self._car), 4, 4),
                     f"finite poses of this mechanism's {len(self._car)} carriers, shape "
                     f"({len(self._car)}, 4, 4)")

    def _record_carriers(self, record) -> list:
        """Carrier indices for simulate(record=...): bodies, links, frames or their names."""
        if isinstance(record, (str, FlexibleLink, Body, Frame)):
            items = [record]
        elif isinstance(record, (list, tuple)):
            items = list(record)
        else:
            raise ModelError(f"record: expected a body, link, frame, a name, or a list of them "
                             f"(got {type(record).__name__})")
        out = []
        for x in items:
            if isinstance(x, str) and x in self._links:
                x = self._links[x]
            if isinstance(x, FlexibleLink):
                if self._links.get(x.name) != x:
                    raise ModelError(f"record: link {x.name!r} is not a link of this mechanism")
                out += [c for c in x.carriers if c not in out]   # a modal link's sliders too
                continue
            c = frame_of(x, self._desc, "record").carrier
            if c < 0:
                raise ModelError("record: the ground has no recorded pose")
            if c not in out:
                out.append(c)
        if not out:
            raise ModelError("record: nothing to record")
        return out

    def _warn_implausible_strain(self, result: SimulationResult, model) -> None:
        """PlausibilityWarning, once per run, when a nonlinear flexible link's largest fibre
        strain over the run (phmech._checks.fibre_strain of its stress resultants, all outputs,
        one core call per 256 outputs for every link at once; skipped when the run's elastic
        energy is too small for any element to reach its bound) exceeds its bound
        (phmech._checks.strain_bound: 1 % for a metal-like speed of sound, 10 % below), naming
        the link, the strain, where and when. Runs with ``record=`` (not every carrier stored)
        are not checked."""
        links = [lk for lk in self._links.values() if lk.fidelity == "nonlinear"]
        if not links or result.carriers is not None or not len(result.t):
            return
        # an element of length h whose fibre strain is e stores at least EA h e^2 / 14 (the
        # least of (EA e_a^2 + EI_y k_y^2 + EI_z k_z^2) h / 2 with e_a + c_z k_y + c_y k_z = e,
        # c = sqrt(3 EI/EA), for a diagonal section stiffness): when the run's whole elastic
        # energy stays below that for every link, no element reached its bound, and the
        # stress resultants are not needed (most runs: no cost)
        elastic = float(np.max(result.energy["elastic"]))
        rows = []
        for lk in links:
            first = self._desc.first_element[lk.name]
            el = self._el[first]
            K = el["K"]
            bound, why = strain_bound(K, el["Ms"])
            diagonal = not np.any(K - np.diag(np.diagonal(K)))
            need = K[3, 3] * el["h"] * bound ** 2 / 14 if diagonal else 0.0
            rows.append((lk, first, K, bound, why, need))
        if elastic < min(r[5] for r in rows):
            return
        worst = (0.0, None, 0, 0, 0.0)   # strain / bound, row, output, element, strain
        for t0 in range(0, len(result.t), 256):
            t1 = min(len(result.t), t0 + 256)
            S = _core.model_stress_resultants(model, result.poses[t0:t1], result.twists[t0:t1])
            for row in rows:
                lk, first, K, bound = row[:4]
                eps = fibre_strain(S[:, first:first + lk.elements], K)
                i = int(np.argmax(eps))
                if eps.flat[i] / bound > worst[0]:
                    worst = (float(eps.flat[i]) / bound, row, t0 + i // lk.elements,
                             i % lk.elements, float(eps.flat[i]))
        ratio, row, it, el, strain = worst
        if ratio > 1.0:
            lk, _, _, bound, why, _ = row
            warnings.warn(f"simulate: link {lk.name!r} strains {100 * strain:.3g} % at its "
                          f"fibres (element {el}, t = {result.t[it]:.4g} s; axial plus bending, "
                          f"extreme fibre at sqrt(3 EI/EA)), above {100 * bound:g} %: {why}. "
                          f"Check the units of its properties (E in Pa, sections in m) and the "
                          f"loads, and whether the part would yield or break",
                          PlausibilityWarning, stacklevel=_outside_stacklevel())

    def stress_resultants(self, result: SimulationResult, link: Union[str, FlexibleLink]) -> np.ndarray:
        """Section stress resultants of each element of ``link`` along a simulation, shape
        (nt, elements, 6), in the strain order (torsion, bending y, bending z [N m], axial,
        shear y, shear z [N]); see phmech.postprocess.stress_resultants."""
        lk = link_of(self._links, link, "stress_resultants")
        return postprocess.stress_resultants(self._desc, self._build(), result, lk)

    def constraint_residuals(self, result: SimulationResult) -> dict:
        """Position and velocity constraint residuals of EVERY pair row (redundant rows included)
        along a simulation: ``position`` (nt,) max ``|g(H)|`` [rad or m], ``velocity`` (nt,) max ``|G t|``
        [rad/s or m/s] (prescribed rates of driven pairs subtracted); see
        phmech.postprocess.constraint_residuals."""
        result = postprocess.simulation_result(result, "constraint_residuals")
        if result.carriers is not None:
            raise ModelError("constraint_residuals needs every carrier's pose: simulate without record=")
        return postprocess.constraint_residuals(self._desc, self._build(), result)

    def _linearization_point(self, at: Optional[StaticResult]) -> tuple:
        """(core model, poses, constraint wrenches) of a linearization at the initial state (poses
        and wrenches None) or at the static equilibrium ``at``, with the extra loads it was
        found under."""
        if at is not None and not isinstance(at, StaticResult):
            raise ModelError(f"at must be a StaticResult (Mechanism.static) or None (got "
                             f"{type(at).__name__})")
        model = self._build(() if at is None else at.loads)
        followers = self._follower_loads()
        if followers:
            warnings.warn(f"the follower loads {followers} (body-frame wrenches) have a "
                          "non-symmetric load stiffness, which the linearization (modes(), "
                          "linearize()) symmetrizes: it treats them as dead loads and cannot show "
                          "flutter; simulate to see how the mechanism moves under them",
                          StabilityWarning, stacklevel=_outside_stacklevel())
        self._warn_unresolvable_masses()
        poses = None if at is None else self._start_poses(at, "at")
        lam = None if at is None else array("at.constraint_wrenches", at.constraint_wrenches,
                                            np.shape(at.constraint_wrenches))
        return model, poses, lam

    #: largest ratio of carrier masses whose modes a linearization resolves to 1e-3: the
    #: eigensolvers' backward error (eps times the norm of M) perturbs a carrier of mass m by
    #: eps m_max / m relative
    MASS_RATIO_RESOLVED = 1e-3 / np.finfo(float).eps

    def _warn_unresolvable_masses(self) -> None:
        """AccuracyWarning when the carriers' masses span more than MASS_RATIO_RESOLVED (4.5e12):
        the modes of the lightest carriers are then below what double precision resolves (a link
        of density 1e-300 hinged to a 1 kg body gave 1.4e9 rad/s for bending modes of ~1e153
        rad/s, without a word: tests/test_fuzz_findings.py)."""
        # massless carriers have no modes of their own: left out
        masses = np.array([c["mass"] if c["mass"] > 0 else np.inf for c in self._car] + [np.inf])
        light = int(np.argmin(masses))
        heavy = masses[np.isfinite(masses)].max(initial=0.0)
        if not heavy > self.MASS_RATIO_RESOLVED * masses[light]:
            return
        warnings.warn(f"the carriers' masses span {heavy:.3g} kg to {masses[light]:.3g} kg "
                      f"(lightest: {self._desc.carrier_name(light)}), a ratio above "
                      f"{self.MASS_RATIO_RESOLVED:.2g}: double precision cannot resolve the lightest "
                      "carriers' modes next to the heaviest (their frequencies and shapes may be "
                      "wrong by orders of magnitude); give the light parts physical masses, or leave "
                      "them out", AccuracyWarning, stacklevel=_outside_stacklevel())

    def sized(self, band: Optional[float] = None, tolerance: Optional[float] = None,
              max_elements: int = 256) -> "Mechanism":
        """A copy of this mechanism, rebuilt from its add_* calls (as save/load do), whose
        nonlinear flexible links have the fewest elements with which ITS OWN modes up to ``band``
        [Hz] are within ``tolerance`` (relative) of the converged ones: supports, bodies and
        couplings included, which the per-link choice of ``Mechanism(band=...)`` cannot know
        (it sizes each link free in space, the support with the largest error).

        ``band`` and ``tolerance`` default to the Mechanism's ``band`` and
        ``frequency_tolerance``. The links' counts grow together, in proportion to how many
        wavelengths of the band each spans (phmech.mesh). A reference is refined (8, 16, 32, ...
        elements on the widest link) until it settles within ``tolerance`` / 10; then meshes
        from 1 element up are compared with it, and the first whose modes in the band are within
        ``tolerance`` (its difference plus the reference's error) is kept: the choice is
        measured, not predicted, and is the fewest on that path. Modes below 1e-3 of the band
        (rigid motions) are not compared; modes are those of ``modes()`` (the initial
        configuration). ``result.sizing`` (phmech.mesh.MechanismMeshChoice) says what was chosen
        and the error bound. This mechanism is not changed: take the new one's links, bodies and
        frames by name (``result.links["arm"]``). Raises ModelError when the mechanism cannot be
        rebuilt from its calls (save() would refuse it too), a frame sits inside a link (another
        mesh would move it) or ``max_elements`` are not enough."""
        from .mesh import size_mechanism
        band = self.band if band is None else band
        if band is None:
            raise ModelError("sized(): give band= (the highest frequency to resolve, Hz) or set "
                             "Mechanism(band=...)")
        tol = self.frequency_tolerance if tolerance is None else tolerance
        return size_mechanism(self, band, tol, max_elements)[0]

    def modes(self, n: int = 5, at: Optional[StaticResult] = None, time: float = 0.0) -> ModesResult:
        """The ``n`` lowest linearized modes at the initial configuration, or at a static
        equilibrium ``at``: its constraint wrenches give the geometric stiffness, and the extra
        loads it was found under (``static(loads=...)``) act as they did there.

        Each mode is labelled (``kind``: bending-y, bending-z, torsion, axial or rigid-body, with
        energy shares and participations; phmech.analysis.label_modes, ModesResult). When the
        configuration is not a static equilibrium (a static solve from it moves it), an
        EquilibriumWarning says so: the values are then eigenvalues of the tangent stiffness,
        negative ones shown as negative frequencies.

        ``time`` [s]: the loads act as at that time. When a driven pair's law has moved by then
        (its value or rate differs from t = 0's) a ModelError names the pair and the values:
        the initial configuration holds it at s(0), and modes there would be the t = 0 ones
        (drive it with ``law.shifted(-time)`` and call modes() at time 0 instead)."""
        n = integer("n", n, 1)
        time = real("time", time)
        self._check_linearization_time("modes", time, at)
        model, poses, lam = self._linearization_point(at)
        # at most 6 per carrier exist: asking for more allocates no more than that
        om, ze, sh, nf = _core.model_modes(model, min(n, 6 * len(self._car)), poses, lam, time)
        where = self._state.poses if poses is None else poses
        eq = self._equilibrium_check(model, where, time, at is not None)
        if not eq and np.any(om[:nf] < 0):
            neg = "; its negative eigenvalues lambda show as negative frequencies -sqrt(-lambda)"
        else:
            neg = ("; a negative eigenvalue lambda of the tangent would show as a negative "
                   "frequency -sqrt(-lambda)")
        if not eq:
            warnings.warn(f"modes: the configuration is not a static equilibrium ({eq.reason}): "
                          f"the values are the eigenvalues of the tangent stiffness there, not the "
                          f"frequencies of small vibrations about a rest state" + neg +
                          ". For vibrations about the equilibrium use modes(at=m.static(...)).",
                          EquilibriumWarning, stacklevel=_outside_stacklevel())
        lab = analysis.label_modes(self._desc, where, om[:nf], sh[:nf])
        return ModesResult(om[:nf], om[:nf] / (2 * np.pi), ze[:nf], sh[:nf], poses=np.array(where),
                           equilibrium=bool(eq), _links=dict(self._links),
                           _bodies=dict(self._bodies), **lab)

    def _equilibrium_check(self, model, poses, time, at_given: bool):
        """Whether ``poses`` is a static equilibrium: a static solve at the full load started there
        (no load steps: Newton, else pseudo-transient continuation) must not move any carrier by
        more than 1e-6 of the mechanism's size [m] or 1e-6 rad.
        Returns a truthy/falsy object with a ``reason``. A solve that fails (a free mechanism is
        singular) tells nothing: then the check passes."""
        class _Eq:
            def __init__(self, ok, reason=""):
                self.ok, self.reason = ok, reason

            def __bool__(self):
                return self.ok
        try:
            P, _, _ = _core.model_static(model, poses, time, 0, 1e-10)
        except (SolverError, ModelError):
            return _Eq(True)
        size = max([1.0] + [lk.length for lk in self._links.values()])
        dp = np.linalg.norm(P[:, :3, 3] - poses[:, :3, 3], axis=1)
        rel = np.einsum("cji,cjk->cik", poses[:, :3, :3], P[:, :3, :3])
        dth = np.arccos(np.clip((np.trace(rel, axis1=1, axis2=2) - 1) / 2, -1, 1))
        c = int(np.argmax(dp / size + dth))
        if dp[c] <= 1e-6 * size and dth[c] <= 1e-6:
            return _Eq(True)
        return _Eq(False, f"a static solve from it moves {self._desc.carrier_name(c)} by "
                          f"{dp[c]:.3g} m and {dth[c]:.3g} rad")

    def _follower_loads(self) -> list:
        """Names of the wrenches given in body axes (they turn with their carrier)."""
        return [ld["name"] for ld in self._loads if not ld["world"]]

    def _potential_loads_only(self, extra: Sequence[dict]) -> bool:
        """Whether every applied wrench has a potential, so that a symmetric tangent stiffness
        judges stability: dead forces (world axes, no moment, on one carrier). Follower loads, a
        moment of fixed direction (in 3-D its work depends on the path of the rotation) and
        interactions between two carriers are not judged."""
        return all(ld["world"] and not ld.get("interaction") and not np.any(ld["w"][:3])
                   for ld in [*self._loads, *extra])

    def linearize(self, at: Optional[StaticResult] = None, inputs: Sequence = (),
                  outputs: Optional[Sequence] = None, time: float = 0.0):
        """The linear port-Hamiltonian model (phmech.linear.LinearPortHamiltonian: J, R, Q, B,
        C, D, passivity(), to_statespace(), to_control()) about the initial configuration, or
        about a static equilibrium ``at`` (its constraint wrenches give the geometric stiffness
        and its extra loads act, as in ``modes``), on the constraint manifold: the reduced
        coordinates are the null space of the constraint Jacobian that ``modes`` uses, so the
        model's undamped frequencies are the modes' (docs/method.md section 7.4).

        ``inputs``: port names -- a pair with joint coordinates or an actuator (the k joint
        efforts [N m or N]), a wrench, interaction or distributed load (the value of its law:
        u = 1 applies the wrench as given), a body's name or a Frame/Body object (a wrench
        (tau [N m], f [N]) in the frame's axes at its origin). ``outputs``: None for the
        collocated outputs (the inputs' power conjugates: joint rates, the load's velocity along
        its wrench, the frame's body twist (omega, v); y^T u is the power supplied), or port
        names as for inputs (their power-conjugate velocities). The inputs perturb the loads
        acting at ``time`` (whose stiffness, e.g. of a world-fixed force on a rotating body, is
        in K); a driven pair whose law has moved by ``time`` is refused as in :meth:`modes`.
        About a configuration that is not a static equilibrium an EquilibriumWarning says so,
        as :meth:`modes` does: K is the tangent there and x = 0 is no rest state."""
        from . import linear

        time = real("time", time)
        self._check_linearization_time("linearize", time, at)
        model, poses, lam = self._linearization_point(at)
        lin = linear.build(_core, model, self._desc, list(inputs) if not isinstance(inputs, str)
                           else [inputs], outputs, poses, lam, time)
        where = self._state.poses if poses is None else poses
        eq = self._equilibrium_check(model, where, time, at is not None)
        if not eq:
            warnings.warn(f"linearize: the configuration is not a static equilibrium "
                          f"({eq.reason}): the model's stiffness K is the tangent there and "
                          f"its state x = 0 is not a rest state (the loads' unbalanced "
                          f"generalized forces are left out), so its responses are not small "
                          f"motions about the mechanism's rest. Linearize about an equilibrium: "
                          f"linearize(at=m.static(...))",
                          EquilibriumWarning, stacklevel=_outside_stacklevel())
        return lin

    def _check_linearization_time(self, what: str, time: float,
                                  at: Optional[StaticResult]) -> None:
        """ModelError when ``time`` asks a linearization about the initial configuration
        (``at`` None) at a time where a driven pair's law has moved on: the initial
        configuration holds the driven coordinates at s(0) with rate s'(0), and the linearization
        has no way to know where the rest of the mechanism is at s(time) (nor does it include
        the motion's rate). A driven law's value or rate at ``time`` differing from t = 0's by
        more than 1e-9 (relative, 1e-12 absolute) is refused, naming the pair, the values and
        the remedy (the law advanced to that time: ``law.shifted(-time)``)."""
        if time == 0.0 or at is not None:
            return
        for e in self._pairs:
            laws = [(None, e["law"])] if e["law"] is not None else \
                list(enumerate(e["xlaws"] or []))
            for c, lw in laws:
                if lw is None:
                    continue
                (s0, v0, _), (s1, v1, _) = lw.derivatives(np.array([0.0, time]))
                if abs(s1 - s0) > 1e-9 * max(abs(s0), abs(s1)) + 1e-12 or \
                        abs(v1 - v0) > 1e-9 * max(abs(v0), abs(v1)) + 1e-12:
                    unit = "" if c is None else " " + e["pair"]._units[c]
                    coord = "its motion" if c is None else f"coordinate {c}"
                    raise ModelError(
                        f"{what}(time={time:g}): pair {e['name']!r} is driven, and its law moves "
                        f"{coord} from s(0) = {s0:.6g}{unit} (rate {v0:.6g}{unit}/s) to "
                        f"s({time:g}) = {s1:.6g}{unit} (rate {v1:.6g}{unit}/s), but {what} works "
                        f"about the initial configuration, where the pair is at s(0): it would "
                        f"return the t = 0 figures. For the configuration of that time drive the "
                        f"pair with the law advanced to it, driven=law.shifted({-time:g}) "
                        f"(s(t + {time:g})), and call {what} at time 0; a linearization is about "
                        f"rest: the driven motion's rate (and the centrifugal stiffening of a "
                        f"spin) is not in it, simulate() has it")

    def static(self, loads: Sequence = (), steps: int = 10, time: float = 0.0,
               tol: float = 1e-10, start: Optional[StaticResult] = None,
               check_stability: bool = True, progress: bool = False) -> StaticResult:
        """Static equilibrium under gravity, the mechanism's wrenches at ``time`` and extra
        constant ``loads`` = [(target, wrench (tau, f), frame "world"|"body"), ...], reached in
        load increments of 1/``steps`` (halved when Newton fails, grown back after fast
        convergence); Newton tolerance ``tol`` (rad, and element lengths) on the tangent step. The
        result's ``iterations`` counts Newton iterations (tangents and factorizations).

        With ``check_stability`` (the default) the equilibrium's lowest linearized mode is
        computed (``StaticResult.lowest_omega``, ``stable``). An unstable equilibrium usually
        means the load steps jumped off the loading path (past buckling, say): the solve is
        repeated once with ten times as many steps (from the same start), and the stable
        equilibrium it finds is returned (``StaticResult.steps`` says how many were used). If it
        is still unstable (an inverted pendulum is an equilibrium, and an unstable one), a
        StabilityWarning says so. The check needs loads with a potential (gravity, springs,
        actuators on pairs, dead forces); under follower loads (body-frame wrenches), moments
        (a moment of fixed direction does path-dependent work in 3-D) or interactions the load
        stiffness is not symmetric, the check would not be valid and is skipped: ``stable`` is
        None.

        ``progress``: a progress bar (tqdm, on stderr or in Jupyter) over the load factor, with
        the Newton iterations so far. Ctrl-C stops the solve (KeyboardInterrupt).

        A failure raises SolverError with the last converged state in its ``result``. When the
        loads do work on a motion that nothing resists (a revolute turned by a constant torque, a
        slider pushed along its guide, a body held by nothing under gravity) no equilibrium
        exists: the solve stops at Newton's first failure and the message names the pair or
        part, what moves and the generalized force; the error's ``free_motions`` lists them
        (FreeMotion; docs/method.md section 7.3, "No equilibrium"). A motion nothing resists on
        which the loads do no work leaves the equilibrium not unique: one is returned."""
        extra = []
        if not isinstance(loads, (list, tuple)):
            raise ModelError(f"static loads: expected a list of (target, wrench, frame) tuples "
                             f"(got {type(loads).__name__})")
        for i, ld in enumerate(loads):
            if not isinstance(ld, (list, tuple)) or len(ld) != 3:
                raise ModelError(f"static load {i}: expected a (target, wrench, frame) tuple "
                                 f"(got {ld!r})")
            target, wrench, frame = ld
            f = frame_of(target, self._desc, f"static load {i}, target")
            if f.carrier < 0:
                raise ModelError(f"static load {i}: cannot load the ground")
            choice(f"static load {i}: frame", frame, ("world", "body"))
            w = array(f"static load {i}: wrench", wrench, (6,), "6 finite numbers (tau [N m], f [N])")
            if frame == "body":
                R = f.T[:3, :3]
                w = np.concatenate([R @ w[:3], R @ w[3:]])
            extra.append(dict(carrier=f.carrier, world=frame == "world", point=f.T[:3, 3], w=w,
                              law=Constant(1.0)))
        steps = min(integer("steps", steps, 1), 2 ** 31 - 1)
        time, tol = real("time", time), positive("tol", tol)
        poses = None if start is None else self._start_poses(start, "start")
        model = self._build(extra)

        def solve(n_steps: int) -> StaticResult:
            monitor = _run.StaticMonitor() if progress else None
            try:
                P, lam, it = _core.model_static(model, poses, time, n_steps, tol, monitor)
            except SolverError as e:
                if not hasattr(e, "partial"):
                    raise
                P, lam, it, reached = e.partial
                e.result = StaticResult(P, lam, it, self._links, tuple(extra), steps=n_steps,
                                        load_factor=reached)
                e.free_motions = self._free_motions(model, P, time, extra)
                msg = self._no_equilibrium(e.free_motions) if e.free_motions else e.args[0]
                e.args = (f"{msg} (the last converged state, at load factor {reached:.6g}, "
                          f"is in this error's 'result' attribute)",)
                raise
            finally:
                if monitor is not None:
                    monitor.close()
            st = StaticResult(P, lam, it, self._links, tuple(extra), steps=n_steps)
            if check_stability and self._potential_loads_only(extra):
                st.lowest_omega = self._lowest_omega(model, P, lam, time)
                st.stable = bool(st.lowest_omega >= 0)
            return st

        st = solve(steps)
        if st.stable is False:
            more = min(10 * steps, 2 ** 31 - 1)
            again = solve(more) if more > steps else st
            if again.stable:
                return again
            warnings.warn(f"static(): the equilibrium found is unstable: its lowest linearized "
                          f"mode has omega = {st.lowest_omega:.4g} rad/s (negative: the tangent "
                          f"stiffness has a negative eigenvalue), also with {more} load steps. "
                          f"Under these loads the mechanism buckles or falls away from here; a "
                          f"stable equilibrium may be found from a perturbed start (start=) or "
                          f"by simulating with damping", StabilityWarning, stacklevel=_outside_stacklevel())
        return st

    def _free_motions(self, model, P, time: float, extra: Sequence[dict]) -> list:
        """The motions nothing resists on which the loads do work at poses P
        (_core.model_static_free, csrc/solve/static_free.c), as FreeMotion rows named from the
        description; [] when none is found."""
        try:
            raw = _core.model_static_free(model, P, time)
        except (SolverError, ModelError):
            return []
        return [self._free_motion(r, extra) for r in raw]

    def _free_motion(self, r: dict, extra: Sequence[dict]) -> FreeMotion:
        """One row of _core.model_static_free as a FreeMotion, its sentence included."""
        def axis(u):
            u = u / np.linalg.norm(u)
            for k, nm in enumerate("xyz"):
                if abs(u[k]) > 1 - 1e-9:
                    return nm if u[k] > 0 else "-" + nm
            return "(" + ", ".join(f"{a:.3g}" for a in u) + ")"
        # the bodies and links that move, in the order of their carriers
        moving = [f"{'body' if nm in self._bodies else 'link'} {nm!r}"
                  for nm, cs in sorted(self._desc.groups(), key=lambda g: min(g[1]))
                  if r["moving"][cs].any()]
        om, v = r["twist"][:3], r["twist"][3:]
        rot = bool(np.any(om != 0))
        ip, j = r["pair"], r["coord"]
        if ip >= 0:
            e = self._pairs[ip]
            unit = "N" if e["pair"]._type.units[j] == "m" else "N m"
        else:
            unit = "N m" if rot else "N"
        sources = {}
        if r["effort"] != 0:
            acts = [a["name"] for a in self._acts if a["pair"] == ip]
            sources["effort of actuator " + " and ".join(map(repr, acts))] = float(r["effort"])
        if r["gravity"] != 0:
            sources[f"gravity on {r['mass']:.4g} kg"] = float(r["gravity"])
        names = [ld["name"] for ld in self._loads] + [f"static load {i}" for i in range(len(extra))]
        for nm, wk in zip(names, r["load_work"]):
            if wk != 0:   # a distributed load's nodes ("q[3]") as one
                key = "wrench " + repr(nm.split("[")[0] if nm.endswith("]") else nm)
                sources[key] = sources.get(key, 0.0) + float(wk)
        parts = ", ".join(f"{k}: {w:.4g} {unit}" for k, w in sources.items())
        F = r["force"]
        if ip >= 0:
            kind = type(e["pair"]).__name__.lower()
            where = f"about {axis(om)}" if rot else f"along {axis(v)}"
            coord = f", coordinate {j} {where}" if e["k"] > 1 else f" {where}"
            text = (f"pair {e['name']!r} ({kind}{coord}) {'turns' if rot else 'slides'} freely "
                    f"under {F:.4g} {unit} ({parts}), carrying {', '.join(moving)}")
        else:
            them = "it" if len(moving) == 1 else "them"
            push = f"turn {them} about {axis(om)}" if rot else f"push {them} along {axis(v)}"
            text = (f"{', '.join(moving)} {'is' if len(moving) == 1 else 'are'} held by nothing "
                    f"(no pair, element, spring or interaction links {them} to the ground) and the "
                    f"loads {push} with {F:.4g} {unit} ({parts})")
        return FreeMotion(e["name"] if ip >= 0 else None, j if ip >= 0 else None, float(F), unit,
                          sources, np.array(r["twist"]), tuple(moving), text)

    @staticmethod
    def _no_equilibrium(motions: Sequence[FreeMotion]) -> str:
        """The SolverError message of a static solve under loads that do work on motions nothing
        resists (Mechanism._free_motions)."""
        hold = []
        if any(f.pair is not None for f in motions):
            hold.append("a spring or a PD actuator on the pair, a driven coordinate, a Fixed pair")
        if any(f.pair is None for f in motions):
            hold.append("a pair or a spring to the ground")
        return ("no static equilibrium: the loads do work on a motion nothing resists: " +
                "; ".join(f.text for f in motions) + f". Hold it ({'; '.join(hold)}) or simulate() "
                "instead")

    def _lowest_omega(self, model, P, lam, time: float) -> float:
        """The lowest linearized frequency [rad/s] at poses P and multipliers lam, negative for a
        negative eigenvalue of the tangent stiffness; a value below round-off of the next mode's
        (|omega_1|^2 < 1e-8 omega_2^2) counts as zero (a neutral mode), and so do negative values
        below round-off of a higher mode (up to the 24th), or all below 1e-6 rad/s; inf when
        nothing can move (no degree of freedom: csrc/solve/modes.c refuses to count modes)."""
        try:
            om = _core.model_modes(model, min(2, 6 * len(self._car)), P, lam, time)[0]
        except ModelError as e:
            if "has no degree of freedom" in str(e):
                return math.inf
            raise
        if len(om) > 1 and om[0] < 0 and om[0] ** 2 < 1e-8 * om[1] ** 2:
            return 0.0
        if om[0] < 0:
            # several round-off zeros: the motions nothing resists of an equilibrium that is not
            # unique (a free body or link, a revolute without load: 6, 6 and 1 of them, measured
            # at -1e-8 .. -4e-3 rad/s). Zeros when a mode above them is 1e4 times higher (modes
            # come in ascending omega^2: none below them), or when all are below 1e-6 rad/s
            # (nothing to compare with; a time constant of 12 days)
            om = _core.model_modes(model, min(24, 6 * len(self._car)), P, lam, time)[0]
            if any(om[k] ** 2 > 1e8 * np.max(om[:k] ** 2) for k in range(1, len(om))):
                return 0.0
            if np.max(np.abs(om)) < 1e-6:
                return 0.0
        return float(om[0])


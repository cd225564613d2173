"""Flexible links on the builder: add_flexible_link (nonlinear se3 chains and rigid links
here; modal links and a band's mesh through the hooks phmech.Mechanism fills: _modal.py,
phmech.mesh). A base class of _builder.Builder, whose rows, names and checks it uses.

Conventions: SI units; a link's local x axis is its centre line, its section axes y and z;
strains (kappa [1/m], 1, 0, 0); poses 4x4."""
from __future__ import annotations

from typing import Optional

import numpy as np

from . import io, se3
from ._checks import array, positive_definite, real, section_slips
from .description import mass_centre, rigid_rotation_coupling
from ._errors import ModelError, warn_plausibility
from .fidelity import FIDELITIES, node_offsets, rigid_link_inertia
from .frames import FlexibleLink, Frame, frame_of
from .section import BeamProperties




_recorded = io.recorded   # a builder call a model file replays (phmech/io.py)


class LinkBuilder:
    """The flexible-link half of _builder.Builder (its rows and names: see there)."""

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
        with the lumped one, which couples neighbouring nodes, and on a straight link a coupling
        of its ends that makes it exact for the link's rigid motions; docs/method.md section
        4.2, "Mass") or ``"lumped"`` (each node carries the section inertia of half of each adjacent
        element; for comparison). Consistent mass has no interior (dispersion) h^2 error, only
        its ends': at equal N its frequencies are several times more accurate (the Table I
        cantilever at N = 21: within 0.066 % on five modes where lumped is 0.69 % off; clamped at
        both ends 0.32 % against 0.39 %, free 0.43 % against 1.3 %), its energy balance stays
        exact and momentum is conserved; its inertia for a rigid turn about a point is the
        continuum's (lumped: plus rhoA L h^2/6); a run costs 9-17 % more at equal N
        (docs/user_guide.md, "Consistent mass (the default) and lumped mass").
        ``centre_of_mass`` places its mass along the elements' fields
        (SimulationResult.centre_of_mass); gravity acts on the node masses, as with lumped mass."""
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
                choice = self._choose_elements(L, properties, band, tol, kap, mass)
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
            warn_plausibility(slips)
            return link
        if modes is not None and fidelity != "modal":
            raise ModelError(f"link {name!r}: modes= is for fidelity='modal' links (this one is "
                             f"{fidelity!r})")
        if fidelity == "modal":
            band = self.band if band is None else band
            tol = self.frequency_tolerance if frequency_tolerance is None else frequency_tolerance
            link = self._add_modal_link(name, L, properties, N, eps, I, H0, given, choice, mass,
                                        modes, band, tol, placed)
            warn_plausibility(slips)
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
        if mass == "consistent" and not np.any(kap):
            # the elements' dispersion correction less its rigid-rotation part, exact rigid inertia
            self._desc.couplings.append(dict(a=first, b=first + N, Mc=rigid_rotation_coupling(h, N, I)))
        if given is not None:
            for k in range(N + 1):
                self._given[first + k] = np.array(self._car[first + k]["H0"])
        link = FlexibleLink(name, L, N, list(range(first, first + N + 1)), choice)
        self._links[name] = link
        warn_plausibility(slips)
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

    # -------------------------------------------------------------- what phmech.Mechanism adds
    # -------------------------------------------------------------- what phmech.Mechanism adds
    def _choose_elements(self, length: float, properties, band: float, tolerance: float,
                         curvature: np.ndarray, mass: str):
        """The mesh a link without ``elements=`` gets from a band (phmech.mesh.choose_elements,
        MeshChoice): phmech.Mechanism's; a bare Builder takes ``elements=``."""
        raise ModelError("a band chooses a link's elements in a phmech.Mechanism; give elements=")

    def _add_modal_link(self, name, L, properties, N, eps, I, H0, given, choice, mass, modes,
                        band, tol, placed) -> FlexibleLink:
        """add_flexible_link(fidelity="modal"): phmech.Mechanism's (python/phmech/_modal.py)."""
        raise ModelError("modal links are built by a phmech.Mechanism")

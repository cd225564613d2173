"""Frames on carriers: rigid bodies, flexible links and their nodes, and resolving what a user
passes for a frame (a Frame, a Body, 'ground' or a body's name) against a model description.

A carrier is a rigid body or a beam node (csrc/include/phmech_types.h, phm_carrier_desc); carrier -1 is the
ground. A frame is a fixed offset T (4x4, translation in m) on a carrier. Frames with an offset
are made without a hand-made matrix by ``frame_at`` (on a Frame, a Body, ``Mechanism.ground``,
``link.start``, ``link.end`` and ``link.node(k)``) from a point and a rotation (:func:`rotation`)."""
from __future__ import annotations

import dataclasses
from typing import Optional

import numpy as np

from . import se3
from ._checks import array, not_rotation, rigid_pose
from ._errors import ModelError

__all__ = ["Frame", "Body", "FlexibleLink", "rotation"]


def rotation(axis, angle: float) -> np.ndarray:
    """The 3x3 rotation matrix of a rotation by ``angle`` [rad] (right hand) about ``axis``
    (``'x'``, ``'y'``, ``'z'`` or a non-zero 3-vector), e.g. for ``frame_at(point, rotation=...)``.
    Rotations compose by matrix product: ``rotation('z', a) @ rotation('x', b)`` turns about x
    first, then about the turned z. (:func:`phmech.se3.rotation` gives the 4x4 pose.)"""
    try:
        return np.ascontiguousarray(se3.rotation(axis, angle)[:3, :3])
    except ValueError as e:   # ModelError is a ValueError: keep its text
        raise ModelError(str(e)) from None


def _offset(point, rotation, what: str) -> np.ndarray:
    """The 4x4 offset [[R, p], [0, 1]] of ``frame_at`` from a point [m] and a 3x3 rotation
    matrix (or None); ModelError naming ``what``."""
    T = np.eye(4)
    T[:3, 3] = array(f"{what}: point", point, (3,), "3 finite numbers [m]")
    if rotation is None:
        return T
    expected = "a 3x3 rotation matrix (e.g. ph.rotation('z', angle)) or None"
    R = array(f"{what}: rotation", rotation, (3, 3), expected)
    why = not_rotation(R)
    if why:
        raise ModelError(f"{what}: rotation: expected {expected}, got a matrix that is not a "
                         f"rotation ({why})")
    T[:3, :3] = R
    return T


def _fmt(v) -> str:
    return "(" + ", ".join(f"{x:g}" for x in v) + ")"


@dataclasses.dataclass(frozen=True)
class Frame:
    """A frame with fixed offset ``T`` (4x4; rotation, translation [m]) on a carrier (``carrier``
    = -1 for the ground); ``name`` appears in error messages. Make offset frames with
    :meth:`frame_at` rather than by hand."""
    carrier: int
    T: np.ndarray
    name: str = ""

    def frame_at(self, point=(0.0, 0.0, 0.0), rotation=None, name: Optional[str] = None) -> "Frame":
        """A frame fixed to this one: its origin at ``point`` (this frame's coordinates [m]), its
        axes turned by ``rotation`` (3x3 rotation matrix, e.g. ``ph.rotation('z', angle)``,
        relative to this frame's axes; None: parallel to them). It moves with this frame's
        carrier and is accepted wherever a frame is (pairs, loads, springs, ``record=``,
        ``result.pose()``, ``start=``/``at=`` placement). ``name`` defaults to this frame's name
        with the point (and "rotated" when turned).

        ``m.ground.frame_at((0, 0, 1))`` is a world frame 1 m above the origin;
        ``link.end.frame_at((0, 0, 0.01))`` a frame 1 cm off the end node of a flexible link,
        along its section axis z."""
        base = self.name or "frame"
        off = _offset(point, rotation, f"{base}.frame_at")
        if name is None:
            name = f"{base} at {_fmt(off[:3, 3])}" + ("" if rotation is None else " rotated")
        elif not isinstance(name, str):
            raise ModelError(f"{base}.frame_at: name must be a string or None (got {name!r})")
        return Frame(self.carrier, self.T @ off, name)


@dataclasses.dataclass
class Body:
    """A rigid body of a mechanism (Mechanism.add_rigid_body): its ``name`` and carrier index."""
    name: str
    carrier: int

    @property
    def frame(self) -> Frame:
        """The body frame (the frame its pose, ``com`` and inertia refer to)."""
        return Frame(self.carrier, np.eye(4), self.name)

    def frame_at(self, point=(0.0, 0.0, 0.0), rotation=None, name: Optional[str] = None) -> Frame:
        """A frame fixed to the body at ``point`` (body coordinates [m]), turned by ``rotation``
        (3x3, relative to the body axes; None: body axes): ``body.frame.frame_at(...)``, see
        :meth:`Frame.frame_at`."""
        return self.frame.frame_at(point, rotation, name)


@dataclasses.dataclass(frozen=True)
class MeshChoice:
    """What :func:`phmech.mesh.choose_elements` chose: ``elements``; ``band`` [Hz] and ``tolerance`` (relative
    frequency error) asked for; ``modes_in_band``: the link's free-free elastic modes up to the
    band; ``estimated_error``: the largest relative frequency error estimated over them at
    ``elements`` (Richardson from twice and four times as many; 0 when no elastic mode is in the band);
    ``frequencies`` [Hz]: those modes at twice as many elements."""
    elements: int
    band: float
    tolerance: float
    modes_in_band: int
    estimated_error: float
    frequencies: tuple

    def __str__(self) -> str:
        return (f"{self.elements} elements: {self.modes_in_band} modes up to {self.band:g} Hz, "
                f"estimated frequency error {self.estimated_error:.2g} (asked {self.tolerance:g})")


@dataclasses.dataclass(frozen=True)
class ModalChoice:
    """How many fixed-interface modes a modal link keeps (``modes``) for the ``band`` [Hz] and
    ``tolerance`` (relative frequency error) asked for; ``error``: the largest relative error
    of its own frequencies below the band against the chain it was reduced from, free and held
    at its start (reduction_error); ``chosen``: whether the band chose ``modes`` (else the
    user gave it)."""
    modes: int
    band: float
    tolerance: float
    error: float
    chosen: bool

    def __str__(self) -> str:
        how = "chosen" if self.chosen else "given"
        return (f"{self.modes} fixed-interface modes ({how}): frequency error {self.error:.2g} "
                f"below {self.band:g} Hz against the chain reduced from (asked {self.tolerance:g})")


@dataclasses.dataclass
class FlexibleLink:
    """A flexible link: ``elements`` se3 elements between ``elements + 1`` nodes; ``nodes`` are
    the carrier indices of the nodes; ``mesh``: what phmech.mesh.choose_elements chose when the
    count came from a band (else None).

    ``fidelity`` (phmech.fidelity): ``"nonlinear"``, every node its own carrier (``offsets``
    None: each node frame is its carrier's frame), or ``"rigid"``, the whole link ONE carrier
    (every entry of ``nodes`` the same index) and the node frames fixed ``offsets``
    (elements + 1, 4, 4) on it, where the nonlinear link's nodes sit on the undeformed link, or
    ``"modal"``, the link statically reduced onto its ends: two carriers, one element
    (``elements`` = 1, ``reduced_from`` the discretization reduced). Results read a node's pose as its carrier's pose times its offset (:meth:`node_poses`),
    so they need not tell the two apart."""
    name: str
    length: float
    elements: int
    nodes: list
    mesh: Optional["MeshChoice"] = None
    fidelity: str = "nonlinear"
    offsets: Optional[np.ndarray] = dataclasses.field(default=None, compare=False)
    #: a modal link: the number of se3 elements it was reduced from (its face is ONE element
    #: between its two interface frames, start and end; phmech.fidelity)
    reduced_from: Optional[int] = None
    #: a modal link: its first frequency [Hz] held at its start (the scale against which
    #: Mechanism.simulate checks its spin; phmech.fidelity.modal_validity)
    clamped_frequency: Optional[float] = None
    #: a modal link: the carriers of its fixed-interface modes' sliders (phmech.fidelity,
    #: modal_sliders), after its two interface carriers
    sliders: list = dataclasses.field(default_factory=list)
    #: a modal link: how many fixed-interface modes it keeps and why (fidelity.ModalChoice;
    #: None when neither a band nor modes= was given)
    modal_choice: Optional[object] = None
    #: a modal link: per slider, the largest displacement [m] and rotation [rad] its mode puts
    #: inside the link per metre of its coordinate (fidelity.modal_validity's interior check)
    modal_peaks: Optional[list] = dataclasses.field(default=None, compare=False)

    @property
    def rigid(self) -> bool:
        """Whether the link is one rigid carrier (fidelity "rigid")."""
        return self.fidelity == "rigid"

    @property
    def carriers(self) -> list:
        """The link's distinct carrier indices, from its start (one for a rigid link; a modal
        link's sliders after its two ends)."""
        return list(dict.fromkeys(self.nodes)) + list(self.sliders)

    def offset(self, k: int) -> np.ndarray:
        """The 4x4 offset of node ``k``'s frame on its carrier (identity for a nonlinear link)."""
        return np.eye(4) if self.offsets is None else np.array(self.offsets[k])

    def node_poses(self, P: np.ndarray) -> np.ndarray:
        """World poses of the node frames, (..., nodes, 4, 4), from ``P`` (..., nodes, 4, 4), the
        poses of the nodes' carriers (``poses[..., link.nodes]``)."""
        return P if self.offsets is None else P @ np.asarray(self.offsets)

    @property
    def start(self) -> Frame:
        return Frame(self.nodes[0], self.offset(0), self.name + ".start")

    @property
    def end(self) -> Frame:
        return Frame(self.nodes[-1], self.offset(len(self.nodes) - 1), self.name + ".end")

    def node(self, k: int) -> Frame:
        """The frame of node ``k``, 0 (start) .. ``elements`` (end), at distance k L / elements
        from the start; Python-style negative k counts from the end (-1 is the end node)."""
        n = len(self.nodes)
        if isinstance(k, bool) or not isinstance(k, (int, np.integer)):
            raise ModelError(f"link {self.name!r}: node index must be an integer (got {k!r})")
        if not -n <= k < n and self.fidelity == "modal":
            raise ModelError(f"link {self.name!r} is modal: its frames are its interfaces, start "
                             f"(node 0) and end (node 1); got node({k}) (a frame inside it needs "
                             f"fidelity='nonlinear')")
        if not -n <= k < n:
            raise ModelError(f"link {self.name!r} has nodes 0..{n - 1} ({self.elements} elements; "
                             f"negative indices -{n}..-1 count from the end); got node({k})")
        k = int(k) % n
        return Frame(self.nodes[k], self.offset(k), f"{self.name}.node{k}")


def frame_of(x, desc: "ModelDescription", what: str) -> Frame:
    """``x`` (a Frame, Body, 'ground' or a body's name) as a Frame of the mechanism described by
    ``desc`` (of which only ``carriers``' length, ``bodies`` and ``links`` are read: a result
    passes just these); ``what`` names the argument in error messages."""
    ncar = len(desc.carriers)
    if isinstance(x, Frame):
        c = x.carrier
        nm = repr(x.name) if x.name else "(unnamed)"
        if isinstance(c, bool) or not isinstance(c, (int, np.integer)) or c < -1 or c >= ncar:
            raise ModelError(f"{what}: the frame {nm} is on carrier {c!r}, which this mechanism does not "
                             f"have (carriers -1 = the ground, 0..{ncar - 1}); take frames from "
                             f"this mechanism's bodies and links (body.frame, link.start, .end, "
                             f".node(k)) or ph.Frame(carrier, T) with such a carrier index")
        return Frame(int(c), rigid_pose(x.T, f"{what}: the offset T of frame {nm}"), x.name)
    if isinstance(x, Body):
        if desc.bodies.get(x.name) != x:
            raise ModelError(f"{what}: body {x.name!r} (carrier {x.carrier!r}) is not a body of this "
                             f"mechanism (bodies: {', '.join(map(repr, desc.bodies)) or 'none'})")
        return x.frame
    if isinstance(x, FlexibleLink):
        raise ModelError(f"{what}: give a frame of link {x.name!r} (.start, .end or .node(k))")
    if isinstance(x, str):
        if x == "ground":
            return Frame(-1, np.eye(4), "ground")
        if x in desc.bodies:
            return desc.bodies[x].frame
        if x in desc.links:
            raise ModelError(f"{what}: {x!r} is a flexible link; give one of its frames "
                             f"(.start, .end or .node(k))")
        raise ModelError(f"{what}: unknown body {x!r}, neither 'ground' nor a body of this mechanism "
                         f"(bodies: {', '.join(map(repr, desc.bodies)) or 'none'})")
    raise ModelError(f"{what}: expected a Frame, Body or 'ground' (got {type(x).__name__})")


def carrier_name(c: int, bodies: dict, links: dict) -> str:
    """'the ground', "body 'b'" or "node k of link 'L'" or "rigid link 'L'" for carrier index
    c."""
    if c < 0:
        return "the ground"
    for b in bodies.values():
        if b.carrier == c:
            return f"body {b.name!r}"
    for lk in links.values():
        if c in lk.nodes:
            return f"rigid link {lk.name!r}" if lk.rigid else f"node {lk.nodes.index(c)} of link {lk.name!r}"
        if c in lk.sliders:
            return f"mode {lk.sliders.index(c) + 1} of modal link {lk.name!r}"
    return f"carrier {c}"


def link_of(links: dict, link, what: str) -> FlexibleLink:
    """A link of ``links`` (name -> FlexibleLink) given by itself or its name; ModelError
    starting with ``what`` (if any) otherwise."""
    lk = links.get(link) if isinstance(link, str) else link
    if not isinstance(lk, FlexibleLink) or links.get(lk.name) != lk:
        lead = f"{what}: expected" if what else "expected"
        raise ModelError(f"{lead} a flexible link of this mechanism or its name (links: "
                         f"{', '.join(map(repr, links)) or 'none'}), got {link!r}")
    return lk

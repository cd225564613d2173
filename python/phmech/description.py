"""The model description: what a Mechanism has collected, as plain rows, before any analysis.

The builder (phmech.mechanism) appends validated rows; the initial configuration
(phmech.topology) reads them and the marshalling (phmech._marshal) hands them to the C core.
Neither changes them. Rows are dicts (units: SI, poses 4x4, twists (omega, v), wrenches (tau, f)):

- carriers: M (6x6 spatial inertia at the carrier frame), mass [kg], com [m, body coordinates],
  H0 (initial pose), t0 (initial body twist)
- elements: a, b (carriers of nodes k, k+1), h [m], K, D (6x6 section stiffness and damping),
  eps (unstressed strain (kappa [1/m], 1, 0, 0)), mass ("lumped", "consistent" or "given"), Ms
  (6x6 section inertia per length, which a consistent element's coupling reads), Mc (12x12, a
  "given" element's coupling: a modal link's condensed mass)
- pairs: name, type (pairs.PairType code), pair (the Fixed, Revolute, ... object), k, a, b
  (carriers, -1 = ground), Ta, Tb (frame offsets, already turned to the joint axis), fa_name,
  fb_name (for messages), driven (a Motion), axis (twist), law (laws._Law or None), xlaws (None
  or k entries, a law or None: the joint coordinates that follow laws), pitch [m/rad], x0,
  has_x0, xdot0, has_xdot0 (joint coordinates and rates, 6 entries of which k are used)
- loads: name, carrier, world (axes of w), point [m, carrier coordinates], w, law, reaction
  (carrier, -1 = ground), interaction (True for add_interaction)
- actuators: name, pair (index), kind ("effort", "pd", "spring"), vec, kp, kd, xset (6 entries
  of which k are used), law (or None)
- springs: name, a, b, pa, pb [m, frame coordinates], kcd (k [N/m], c [N s/m], rest length [m]
  or None for the initial distance)
- couplings: a, b (carriers), Mc (12x12 kinetic coupling of their body twists without an
  element: a modal link's modes with its ends, phmech.fidelity.modal_sliders; a straight
  consistent-mass link's first and last node, rigid_rotation_coupling)
"""
from __future__ import annotations

import dataclasses

import numpy as np

from ._codes import element_mass
from .frames import FlexibleLink, carrier_name


@dataclasses.dataclass
class ModelDescription:
    """A mechanism's components as rows (see the module doc), its bodies and links by name, the
    poses and twists the user gave, and ``gravity`` [m/s^2] in world coordinates."""
    gravity: np.ndarray
    carriers: list = dataclasses.field(default_factory=list)
    elements: list = dataclasses.field(default_factory=list)
    pairs: list = dataclasses.field(default_factory=list)
    loads: list = dataclasses.field(default_factory=list)
    actuators: list = dataclasses.field(default_factory=list)
    springs: list = dataclasses.field(default_factory=list)
    couplings: list = dataclasses.field(default_factory=list)
    #: components with internal states (python/phmech/components.py, component_row)
    components: list = dataclasses.field(default_factory=list)
    #: sensors by name (python/phmech/sensors.py, sensor_row), in the order added
    sensors: dict = dataclasses.field(default_factory=dict, compare=False)
    #: sampled controllers (python/phmech/controllers.py, controller_row); their outputs are
    #: actuator and load rows whose laws the run sets (python/phmech/_sampled.py)
    controllers: list = dataclasses.field(default_factory=list, compare=False)
    bodies: dict = dataclasses.field(default_factory=dict)     # name -> Body
    links: dict = dataclasses.field(default_factory=dict)      # name -> FlexibleLink
    #: link name -> index of its first element (its elements are consecutive)
    first_element: dict = dataclasses.field(default_factory=dict)
    #: link name -> its unstressed strain eps_hat (6,): (kappa [1/m], 1, 0, 0)
    link_strain: dict = dataclasses.field(default_factory=dict)
    #: carrier -> the pose (4x4) the user gave it (add_rigid_body or add_flexible_link pose=)
    given: dict = dataclasses.field(default_factory=dict)
    #: carriers whose twist the user gave (add_rigid_body(twist=))
    twist_given: set = dataclasses.field(default_factory=set)
    #: carrier -> the Frame that add_flexible_link(start=) (the link's start carrier) or
    #: add_rigid_body(at=) placed it at: where a forgotten pair most likely belongs
    #: (topology.free_groups). A hint for messages, not the model: a model file may rebuild
    #: the frame under another name, so it is left out of the comparison save makes (io.py)
    placed_at: dict = dataclasses.field(default_factory=dict, compare=False)
    #: the rows' columns for the core (phmech._marshal), made at the first analysis and kept
    #: until the next change (``changed``)
    columns: dict = dataclasses.field(default=None, compare=False, repr=False)
    #: mass_couplings(), kept as columns
    _mass_couplings: dict = dataclasses.field(default=None, compare=False, repr=False)
    #: carrier_arrays(), kept like columns
    _carrier_arrays: tuple = dataclasses.field(default=None, compare=False, repr=False)
    #: counts the changes (changed()): what was built from an older version is stale
    #: (_model.built keys on it)
    version: int = dataclasses.field(default=0, compare=False, repr=False)

    def changed(self) -> None:
        """A component was (or is about to be) added, or a row was changed in place (the laws
        of sampled controllers, python/phmech/_sampled.py): what was made from the rows is
        stale."""
        self.version += 1
        self.columns = None
        self._mass_couplings = None
        self._carrier_arrays = None

    def carrier_name(self, c: int) -> str:
        """'the ground', "body 'b'" or "node k of link 'L'" for carrier index c."""
        return carrier_name(c, self.bodies, self.links)

    def link_unstressed_strain(self, link: FlexibleLink) -> np.ndarray:
        """The unstressed strain eps_hat (6,) of a link (its elements', for a nonlinear one)."""
        return np.asarray(self.link_strain[link.name])

    def rigid_carriers(self) -> dict:
        """Carrier index -> name of every rigid carrier: the bodies and the rigid links."""
        out = {b.carrier: b.name for b in self.bodies.values()}
        out.update({lk.nodes[0]: lk.name for lk in self.links.values() if lk.rigid})
        return dict(sorted(out.items()))

    def body_carriers(self) -> set:
        """Carrier indices of the rigid bodies."""
        return {b.carrier for b in self.bodies.values()}

    def groups(self) -> list:
        """(name, carriers) of every body and every link, bodies first, in the order added."""
        return [(b.name, [b.carrier]) for b in self.bodies.values()] + \
            [(lk.name, lk.carriers) for lk in self.links.values()]

    def link_elements(self, link: FlexibleLink) -> list:
        """The element rows of a link, from its start (none for a rigid link)."""
        if link.rigid:
            return []
        first = self.first_element[link.name]
        return self.elements[first:first + link.elements]

    def mass_couplings(self) -> dict:
        """The consistent-mass elements' node carriers ``_coupled_nodes`` (ne, 2) and couplings
        ``_couplings`` (ne, 12, 12) in their nodes' body twists, then the couplings without an
        element (a modal link's modes, a straight link's rigid-rotation coupling), from the
        core's kernel (phm_element_mass; what the simulation integrated), for a result's
        momentum; and
        ``_coupled_fields`` (ne, 5): a consistent element's length h, section mass per length and
        section centre of mass (3), whose constant-strain field places the element's mass for
        ``centre_of_mass`` (zeros for a given coupling: its mass stays on its carriers). Made
        once per description, read-only."""
        if self._mass_couplings is None:
            rows = [e for e in self.elements if e.get("mass", "lumped") != "lumped"] + self.couplings
            fields = np.zeros((len(rows), 5))
            for row, e in zip(fields, rows):
                if e.get("mass", "given") == "consistent":
                    ms = e["Ms"][3, 3]
                    row[:] = e["h"], ms, *mass_centre(e["Ms"], ms)
            cp = dict(_coupled_nodes=np.array([[e["a"], e["b"]] for e in rows], dtype=int).reshape(-1, 2),
                      _couplings=np.array([e["Mc"] if e.get("mass", "given") == "given" else
                                           element_mass(e["h"], e["Ms"], e["eps"]) for e in rows],
                                          dtype=float).reshape(-1, 12, 12),
                      _coupled_fields=fields)
            for arr in cp.values():   # shared by every result until the next change
                arr.setflags(write=False)
            self._mass_couplings = cp
        return dict(self._mass_couplings)

    def carrier_arrays(self) -> tuple:
        """The carriers' 6x6 inertias (nc, 6, 6) [kg, kg m, kg m^2], masses (nc,) [kg] and
        centres of mass (nc, 3) [m, in each carrier's frame], stacked once per version and
        read-only (results share them)."""
        if self._carrier_arrays is None:
            arrays = tuple(np.array([c[k] for c in self.carriers], dtype=float)
                           for k in ("M", "mass", "com"))
            for a in arrays:
                a.setflags(write=False)
            self._carrier_arrays = arrays
        return self._carrier_arrays

    def mass_times(self, v: np.ndarray) -> np.ndarray:
        """M v for tangent vectors v (..., ncarriers, 6) (body frames): every carrier's 6x6
        inertia on its own block plus the consistent and given elements' couplings (what the
        core's mass is; docs/method.md section 4.2, "Mass")."""
        v = np.asarray(v, dtype=float)
        out = np.einsum("cij,...cj->...ci", self.carrier_arrays()[0], v)
        cp = self.mass_couplings()
        ab = cp["_coupled_nodes"]
        if len(ab) and v.ndim in (2, 3):
            # all couplings at once, each element's product as the loop below makes it (its
            # rows times Mc^T: the same numbers, bit for bit) and added in the loop's order
            x = np.moveaxis(np.concatenate([v[..., ab[:, 0], :], v[..., ab[:, 1], :]], axis=-1), -2, 0)
            McT = cp["_couplings"].transpose(0, 2, 1)
            u = np.matmul(x[:, None, :], McT)[:, 0, :] if v.ndim == 2 else np.matmul(x, McT)
            u = np.moveaxis(u, 0, -2)
            np.add.at(out, (Ellipsis, ab.reshape(-1), slice(None)),
                      u.reshape(*u.shape[:-2], 2 * len(ab), 6))
            return out
        for (a, b), Mc in zip(cp["_coupled_nodes"], cp["_couplings"]):
            u = np.concatenate([v[..., a, :], v[..., b, :]], axis=-1) @ Mc.T
            out[..., a, :] += u[..., :6]
            out[..., b, :] += u[..., 6:]
        return out

    def port_names(self) -> list:
        """Names of the ports in the core's order: actuators, loads, springs."""
        return [a["name"] for a in self.actuators] + [ld["name"] for ld in self.loads] + \
            [q["name"] for q in self.springs]


def rigid_rotation_coupling(h: float, elements: int, Ms: np.ndarray) -> np.ndarray:
    """The kinetic coupling (12x12, body twists of a straight link's first and last node) that
    makes the consistent mass exact for the link's rigid motions [kg m^2, kg m, kg].

    Each consistent element adds (h/12) d^T Ms d to twice its kinetic energy, d its nodes'
    twist difference (csrc/model/element.c, phm_element_mass): it cancels the helix field's
    leading dispersion error, but a rigid rotation omega gives every element the same
    d = (0, omega x h e_x) and so a rotational inertia of rho A L h^2 / 12 too many (a 0.3 m
    strip of 1 element swinging as a rigid rod ran 0.88 rad off it after 1 s). On a straight
    uniform link the d telescope: their sum is D = t_last - t_first, and subtracting
    (h / (12 N)) D^T W D leaves the elements' sum minus N times the square of their mean, zero
    for a rigid motion, where d reaches only the transverse translations (docs/method.md
    section 4.2, "Mass"). W is Ms without its block on (omega, v_x): the transverse block a
    rigid d needs, and, for a section whose centre of mass is off the axis, its coupling to the
    rotations, without which the rest would be indefinite. The link's form is then N times the
    variance of the d on Ms plus (1/N) D^T S D, S = Ms's (omega, v_x) block: >= 0, so the mass
    stays positive definite."""
    W = np.array(Ms, dtype=float)
    W[:4, :4] = 0.0
    c = -h / (12.0 * elements)
    return np.block([[c * W, -c * W], [-c * W, c * W]])


def mass_centre(M: np.ndarray, mass: float) -> np.ndarray:
    """The centre of mass [m] of a 6x6 spatial inertia M ((omega, v) order) of ``mass`` [kg]:
    M[:3, 3:] = mass hat(c) (add_rigid_body's layout), c from its skew part."""
    C = np.asarray(M)[:3, 3:] / mass
    return np.array([C[2, 1] - C[1, 2], C[0, 2] - C[2, 0], C[1, 0] - C[0, 1]]) / 2.0

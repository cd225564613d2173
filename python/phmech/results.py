"""What the analyses return: simulation, modes and static results, and the initial
configuration an analysis starts from (with how far it moved the given initial values).

Conventions: SI units; twist (omega [rad/s], v [m/s]) and wrench (tau [N m], f [N]), angular
part first; poses 4x4; arrays indexed by carrier (rigid bodies and beam nodes, in the order
added; csrc/include/phmech_types.h, phm_carrier_desc)."""
from __future__ import annotations

import dataclasses
import json
import os
import types
from typing import NamedTuple, Optional, Union

import numpy as np

from . import _resultfile, se3
from ._resultfile import HELD_FIELDS
from .io import decode_value
from .analysis import MODE_KIND_TEXT, mac
from ._errors import ModelError
from .frames import Body, FlexibleLink, Frame, carrier_name, frame_of, link_of

#: 6-point Gauss-Legendre on [0, 1] (points, weights): a consistent element's mass along its
#: field, as csrc/model/element.c integrates its kinetic energy
_FIELD_GAUSS = tuple(a / 2 + b for a, b in zip(np.polynomial.legendre.leggauss(6), (0.5, 0.0)))

__all__ = ["SimulationResult", "ModesResult", "StaticResult", "Momentum", "InitialAdjustment",
           "InitialConfiguration", "FreeMotion"]

#: the energies of SimulationResult.energy, in the order the core writes them
ENERGY_NAMES = ("kinetic", "elastic", "gravity", "dissipated", "supplied", "total", "ledger")

@dataclasses.dataclass(frozen=True)
class InitialAdjustment:
    """How far the consistent initial configuration moved one given initial value.

    ``name``: the pair (joint coordinates) or the body / flexible link (poses). ``quantity``:
    ``"x"`` (``"x[i]"`` for pairs with several coordinates), ``"xdot"`` (``"xdot[i]"``) for a
    given rate, or ``"position"`` / ``"orientation"`` of a body or link (for a link the largest
    over its nodes). ``given``/``reached``: the given ``x0`` (``xdot0``) and the initial value
    [rad or m, per s for rates] (None for poses). ``moved``: ``|reached - given|`` [same units]; for
    poses the distance an origin moved [m] or the angle a frame turned [rad].
    ``tolerance``: ``moved`` beyond it is reported (see Mechanism)."""
    name: str
    quantity: str
    given: Optional[float]
    reached: Optional[float]
    moved: float
    unit: str
    tolerance: float

    @property
    def exceeds(self) -> bool:
        """True when ``moved`` is beyond ``tolerance``."""
        return self.moved > self.tolerance

    def __str__(self) -> str:
        if self.given is not None:
            q = "" if self.quantity == "x" else " " + self.quantity
            return (f"joint {self.name!r}{q} given {self.given:.6g} {self.unit}, closed at "
                    f"{self.reached:.6g} {self.unit} (moved {self.moved:.3g} {self.unit})")
        return f"pose of {self.name!r}: {self.quantity} moved {self.moved:.3g} {self.unit}"


@dataclasses.dataclass
class InitialConfiguration:
    """The initial configuration an analysis starts from: ``poses`` (ncarriers, 4, 4), body
    ``twists`` (ncarriers, 6), ``adjustments`` (list of InitialAdjustment: every given ``x0``
    coordinate and every given pose kept by the tree placement, with how far the loop closure
    moved it) and ``redundant_constraints``."""
    poses: np.ndarray
    twists: np.ndarray
    adjustments: list
    redundant_constraints: list


class Momentum(NamedTuple):
    """World-frame momentum along a trajectory (SimulationResult.momentum): ``linear`` (nt, 3)
    [kg m/s] and ``angular`` (nt, 3) [kg m^2/s] about the point asked for."""
    linear: np.ndarray
    angular: np.ndarray


#: The core's arrays a SimulationResult holds as the core wrote them, one attribute each, named
#: by the table of result quantities (csrc/include/phmech_results.h; _resultfile.HELD_FIELDS):
#: a new quantity of the core is an attribute, a file variable and a line of the docs with no
#: change here. None: not computed (a file from before the quantity).
_CoreArrays = dataclasses.make_dataclass(
    "_CoreArrays", [(f.name, Optional[np.ndarray], dataclasses.field(default=None))
                    for f in HELD_FIELDS], kw_only=True)
_CoreArrays.__module__ = __name__


def _core_arrays_doc() -> str:
    """The docstring's list of the core's arrays, from the table (its dims, unit and text)."""
    rows = [f"    - ``{f.name}`` (time, {', '.join(f.dims)}) [{f.unit}]: {f.text}" for f in HELD_FIELDS]
    return ("\n\n    The arrays as the core computes them at each output (csrc/include/"
            "phmech_results.h), None\n    when not computed:\n\n" + "\n".join(rows) + "\n")


@dataclasses.dataclass
class SimulationResult(_CoreArrays):
    """Sampled solution. ``poses`` (nt, ncarriers, 4, 4), ``twists`` (nt, ncarriers, 6) body
    twists, ``constraint_wrenches`` (nt, nconstraints), ``energy`` dict of (nt,) arrays [J]
    (kinetic, elastic, gravity, dissipated, supplied, total, ledger = E - E0 - (supplied -
    dissipated)), ``stats`` (IDA steps, residual/Jacobian evaluations, wall time [s]),
    ``interrupted`` (stopped by Ctrl-C or the callback).

    ``port_energy``: dict port name -> (nt,) energy supplied through that port [J] (actuators:
    int u . xdot; interactions and wrenches: int w . t; spring-dampers: minus their dissipated
    energy). Supplied = sum over actuators and wrenches (+ power of driven pairs); the ledger
    residual is ``energy["ledger"]``. ``joint(name)`` gives a pair's coordinates and efforts.

    Conserved quantities: ``momentum(x=None, about=(0, 0, 0))`` is the world-frame linear
    momentum P [kg m/s] and angular momentum L [kg m^2/s] about a world point, of the whole
    mechanism or of bodies/links, as ``Momentum(linear, angular)``, each (nt, 3). Every carrier
    (rigid body or beam node) contributes its body momentum M t (M its 6x6 spatial inertia about
    its frame, t its body twist), moved to the world frame by the dual adjoint Ad*_{H^-1}:
    P = sum R P_b, L = sum R L_b + (p - about) x R P_b, i.e. sum of r x m v over the mass,
    right-handed. Free mechanisms without loads keep both constant; gravity g changes P at the
    rate ``mass() * g``. ``mass(x=None)`` [kg] and ``centre_of_mass(x=None)`` (nt, 3) [m] go with
    it. All three need the poses and twists of the carriers asked for: after
    ``simulate(record=...)`` only what was recorded can be asked for (ModelError otherwise)."""
    t: np.ndarray
    constraint_wrenches: np.ndarray
    energy: dict
    stats: dict
    interrupted: bool
    _links: dict
    port_energy: dict = dataclasses.field(default_factory=dict)
    #: component name -> {state name: values over the outputs} (python/phmech/components.py)
    components: dict = dataclasses.field(default_factory=dict)
    #: sensor name -> its values over the outputs, (nt, size) or a pose (nt, 4, 4), in the
    #: sensor's units (python/phmech/sensors.py)
    sensors: dict = dataclasses.field(default_factory=dict)
    #: sampled controller name -> {"t": sample times (ns,) [s], "y": its inputs (ns, ny), "u":
    #: its outputs (ns, nu)} (python/phmech/controllers.py)
    controllers: dict = dataclasses.field(default_factory=dict)
    pair_wrenches: np.ndarray = None
    _pairs: dict = dataclasses.field(default_factory=dict)
    #: (pair, direction) rows left out of the DAE as redundant; when non-empty,
    #: ``constraint_wrenches`` holds the minimum-norm multipliers of ALL rows (see
    #: postprocess.min_norm_multipliers) and ``pair_wrenches`` the matching pair wrenches.
    redundant_constraints: list = dataclasses.field(default_factory=list)
    #: carrier index of each column of ``poses``/``twists`` (all carriers unless ``record=`` chose)
    carriers: np.ndarray = None
    #: every carrier's 6x6 spatial inertia (body frame), mass and centre of mass (body
    #: coordinates) as the model had them (set by simulate; momentum, mass, centre_of_mass)
    _inertia: np.ndarray = None
    _mass: np.ndarray = None
    _com: np.ndarray = None
    _bodies: dict = dataclasses.field(default_factory=dict)
    #: consistent-mass elements: their node carriers (ne, 2) and mass couplings Mc (ne, 12, 12)
    #: in the nodes' body twists (csrc/model/element.c, phm_element_mass; momentum adds them)
    _coupled_nodes: np.ndarray = None
    _couplings: np.ndarray = None
    #: per coupling: a consistent element's h, section mass per length and centre of mass (3),
    #: zeros for a given one (description.mass_couplings; centre_of_mass places its mass)
    _coupled_fields: np.ndarray = None
    __doc__ = (__doc__ or "") + _core_arrays_doc()   # python -OO strips docstrings

    def _frame(self, x) -> Frame:
        """A body, frame, link end or body's name as a Frame of the simulated mechanism."""
        n = len(self._mass) if self._mass is not None else self.poses.shape[1]
        scope = types.SimpleNamespace(carriers=range(n), bodies=self._bodies, links=self._links)
        return frame_of(x, scope, "result")

    def pose(self, x) -> np.ndarray:
        """World pose of a body or frame (a Frame, Body, link end, or a body's name), (nt, 4, 4)."""
        f = self._frame(x)
        if f.carrier < 0:
            return np.broadcast_to(f.T, (len(self.t), 4, 4)).copy()
        return self.poses[:, self._columns([f.carrier])[0]] @ f.T

    def position(self, x) -> np.ndarray:
        """World position of a body's or frame's origin [m], (nt, 3)."""
        return self.pose(x)[:, :3, 3]

    def orientation(self, x) -> np.ndarray:
        """World orientation (rotation matrix) of a body or frame, (nt, 3, 3)."""
        return self.pose(x)[:, :3, :3]

    def twist(self, x) -> np.ndarray:
        """Body twist (omega [rad/s], v [m/s]) of a body or frame in its own axes, (nt, 6):
        Ad_{T^-1} of the carrier's twist, T the frame's offset on it."""
        f = self._frame(x)
        if f.carrier < 0:
            return np.zeros((len(self.t), 6))
        t = self.twists[:, self._columns([f.carrier])[0]]
        return t @ se3.Ad(se3.inverse(f.T)).T

    def _columns(self, carriers) -> list:
        """Columns of ``poses`` holding these carriers; ModelError if one was not recorded."""
        if self.carriers is None:
            return list(carriers)
        where = {int(c): i for i, c in enumerate(self.carriers)}
        missing = [c for c in carriers if c not in where]
        if missing:
            raise ModelError(f"carriers {missing} were not recorded (simulate(record=...))")
        return [where[c] for c in carriers]

    def joint(self, name: str) -> dict:
        """Pair ``name``: ``x`` (nt, k) joint coordinates (exact, multi-turn), ``xdot`` (nt, k)
        rates, ``effort`` (nt, k) sum of its actuators' efforts u, ``lambda`` (nt, m) constraint
        multipliers (W^C coordinates), ``wrench`` (nt, 6) constraint wrench W^C lambda on b in
        frame F_b (tau [N m], f [N])."""
        if not isinstance(name, str) or name not in self._pairs:
            raise ModelError(f"joint: unknown pair {name!r} (pairs: "
                             f"{', '.join(map(repr, self._pairs)) or 'none'})")
        row, m, j, k = self._pairs[name]["layout"]
        ip = self._pairs[name]["index"]
        return dict(x=self.joints[:, j:j + k], xdot=self.joint_rates[:, j:j + k],
                    effort=self.efforts[:, j:j + k], **{"lambda": self.constraint_wrenches[:, row:row + m]},
                    wrench=self.pair_wrenches[:, ip])

    def positions(self, link: Union[str, FlexibleLink]) -> np.ndarray:
        """Node positions of a link [m], shape (nt, nnodes, 3)."""
        lk = link_of(self._links, link, "")
        return lk.node_poses(self.poses[:, self._columns(lk.nodes)])[..., :3, 3]

    def tip(self, link: Union[str, FlexibleLink]) -> np.ndarray:
        """Position of the link's end node [m], shape (nt, 3)."""
        return self.positions(link)[:, -1, :]

    # ---------------------------------------------------------- conserved quantities

    def _mass_carriers(self, x, need_motion: bool, what: str) -> list:
        """Carrier indices of ``x`` (None: all; a Body, FlexibleLink, a body's or link's name,
        or a list of these); with ``need_motion``, ModelError unless all were recorded."""
        if self._mass is None:
            raise ModelError(f"{what}: this result carries no inertia data (made by simulate?)")
        if x is None:
            carriers, whom = list(range(len(self._mass))), "the whole mechanism"
        else:
            items = list(x) if isinstance(x, (list, tuple)) else [x]
            carriers, names = [], []
            for it in items:
                if isinstance(it, str):
                    it = self._links.get(it, self._bodies.get(it, it))
                if isinstance(it, Body) and self._bodies.get(it.name) == it:
                    cs = [it.carrier]
                elif isinstance(it, FlexibleLink) and self._links.get(it.name) == it:
                    cs = it.carriers
                elif isinstance(it, (str, Body, FlexibleLink)):
                    nm = it if isinstance(it, str) else it.name
                    raise ModelError(f"{what}: {nm!r} is not a body or link of this mechanism "
                                     f"(bodies: {', '.join(map(repr, self._bodies)) or 'none'}; "
                                     f"links: {', '.join(map(repr, self._links)) or 'none'})")
                else:
                    raise ModelError(f"{what}: expected None (the whole mechanism), a Body, a "
                                     f"FlexibleLink, a body's or link's name, or a list of these "
                                     f"(got {type(it).__name__}; a frame or the ground has no mass "
                                     f"of its own)")
                carriers += [c for c in cs if c not in carriers]
                names.append(repr(it.name))
            whom = ", ".join(names)
            if not carriers:
                raise ModelError(f"{what}: an empty selection (None is the whole mechanism)")
            if max(carriers) >= len(self._mass):
                raise ModelError(f"{what}: {whom} was added to the mechanism after this simulation")
        if need_motion and self.carriers is not None:
            kept = {int(c) for c in self.carriers}
            missing = [c for c in carriers if c not in kept]
            if missing:
                full = [repr(b.name) for b in self._bodies.values() if b.carrier in kept]
                full += [repr(lk.name) for lk in self._links.values() if all(c in kept for c in lk.carriers)]
                lost = ", ".join(carrier_name(c, self._bodies, self._links) for c in missing[:5])
                lost += f" and {len(missing) - 5} more" if len(missing) > 5 else ""
                raise ModelError(
                    f"{what} of {whom} needs the poses and twists of every carrier in it, but "
                    f"simulate(record=...) did not record {lost}. It can be computed for what was "
                    f"recorded in full ({', '.join(full) or 'nothing'}); simulate without record= "
                    f"(or record these too) for the rest")
        return carriers

    def momentum(self, x=None, about=(0.0, 0.0, 0.0)) -> "Momentum":
        """World-frame linear and angular momentum of the whole mechanism (``x`` None) or of a
        body, a flexible link (all its nodes), a body's or link's name, or a list of these:
        ``Momentum(linear, angular)``, each (nt, 3), in kg m/s and kg m^2/s.

        Each carrier (a rigid body, or a beam node with its own inertia) contributes its body
        momentum (L_b, P_b) = M t (plus, for the nodes of ``mass="consistent"`` elements, their
        share Mc [t_a; t_b] of the element's coupling, and likewise for a modal link's two
        carriers), M its 6x6 spatial inertia about the carrier frame (centre of
        mass possibly offset) and t = (omega, v) its body twist, moved to the world frame by the
        dual adjoint, (L, P) = Ad*_{H^-1} (L_b, P_b) with H = (R, p) the carrier's pose:
        P = R P_b, L = R L_b + (p - about) x P. So ``linear`` is sum m v_com and ``angular`` the
        moment of momentum sum (r - about) x m v + I_com omega about the world point ``about``
        (right-handed: positive about an axis when the mass turns counterclockwise seen from
        its tip), with the absolute (world) velocities. ``about``: a fixed world point (3,), one
        point per output (nt, 3) (e.g. a moving pivot), or ``"com"``: the selection's own centre
        of mass at each output (its spin angular momentum).

        Without external wrenches (no gravity, loads, or pairs, springs or actuators to the
        ground) both are constant; under gravity alone d(linear)/dt = mass(x) g. After
        ``simulate(record=...)``, ``x`` must be bodies/links whose carriers were all recorded
        (ModelError naming what is missing otherwise); the whole mechanism needs every carrier."""
        cars = self._mass_carriers(x, True, "momentum")
        nt = len(self.t)
        if isinstance(about, str):
            if about != "com":
                raise ModelError(f"momentum: about must be a world point (3,), points (nt, 3) or "
                                 f"'com' (got {about!r})")
            a = self.centre_of_mass(x)
        else:
            a = np.asarray(about, dtype=float)
            if a.shape not in ((3,), (nt, 3)) or not np.all(np.isfinite(a)):
                raise ModelError(f"momentum: about must be a finite world point (3,) or one point "
                                 f"per output ({nt}, 3) [m] (got shape {a.shape})")
        cols = self._columns(cars)
        col = dict(zip(cars, cols))
        body = {c: self.twists[:, j] @ self._inertia[c].T for c, j in col.items()}
        nodes = np.zeros((0, 2), int) if self._coupled_nodes is None else self._coupled_nodes
        for (na, nb), Mc in zip(nodes, self._couplings if len(nodes) else ()):
            if na in col and nb in col:   # a consistent element's share of its nodes' momenta
                u = np.concatenate([self.twists[:, col[na]], self.twists[:, col[nb]]], 1) @ Mc.T
                body[na] = body[na] + u[:, :6]
                body[nb] = body[nb] + u[:, 6:]
        P = np.zeros((nt, 3))
        L = np.zeros((nt, 3))
        for c, j in col.items():              # per carrier, vectorized over time
            mb = body[c]                      # body momentum (L_b, P_b)
            R = self.poses[:, j, :3, :3]
            Pw = np.einsum("nij,nj->ni", R, mb[:, 3:])
            P += Pw
            L += np.einsum("nij,nj->ni", R, mb[:, :3]) + np.cross(self.poses[:, j, :3, 3] - a, Pw)
        return Momentum(P, L)

    def mass(self, x=None) -> float:
        """Mass [kg] of the whole mechanism (``x`` None) or of bodies/links (as in momentum): the
        sum of the carriers' masses (a link's node masses add up to its mass per length times its
        length). Needs no recorded motion."""
        return float(np.sum(self._mass[self._mass_carriers(x, False, "mass")]))

    def centre_of_mass(self, x=None) -> np.ndarray:
        """World position of the centre of mass [m], (nt, 3), of the whole mechanism (``x``
        None) or of bodies/links (as in momentum): sum m_i (p_i + R_i c_i) / sum m_i over the
        carriers, c_i the centre of mass in carrier coordinates (the masses and centres of mass
        gravity acts on), except that a ``mass="consistent"`` element's mass (its nodes' shares
        h/2 each) lies along its constant-strain field H_a exp(xi X), X = log(H_a^-1 H_b), xi in
        [0, 1], the helix whose kinetic energy its mass is (docs/method.md section 4.2, "Mass").
        Its rate is then the linear momentum over the mass (``momentum``) exactly while each
        element is at its unstressed shape; a deformed element's mass keeps the unstressed
        shape's, which no position can match exactly (the momentum is not the rate of any
        function of the configuration), so there the rate differs by a term proportional to the
        deformation (measured: tests/test_momentum.py). Needs the recorded poses of those
        carriers (see momentum)."""
        cars = self._mass_carriers(x, True, "centre_of_mass")
        cols = self._columns(cars)
        H = self.poses[:, cols]                                   # (nt, k, 4, 4)
        r = np.einsum("nkij,kj->nki", H[..., :3, :3], self._com[cars]) + H[..., :3, 3]
        m = self._mass[cars]
        first = np.einsum("k,nki->ni", m, r)
        col = dict(zip(cars, cols))
        nodes = np.zeros((0, 2), int) if self._coupled_nodes is None else self._coupled_nodes
        fields = np.zeros((len(nodes), 5)) if self._coupled_fields is None else self._coupled_fields
        for (na, nb), (h, ms, *c) in zip(nodes, fields):
            if h > 0 and na in col and nb in col:   # its mass from the nodes to its field
                Ha, Hb = self.poses[:, col[na]], self.poses[:, col[nb]]
                X = se3.log(se3.inverse(Ha) @ Hb)
                ch = np.append(c, 1.0)
                for xi, w in zip(*_FIELD_GAUSS):
                    first += (w * ms * h) * (Ha @ se3.exp(xi * X) @ ch)[:, :3]
                for Hk, k in ((Ha, na), (Hb, nb)):       # what the node carried of it
                    first -= (0.5 * ms * h) * (Hk @ np.append(self._com[k], 1.0))[:, :3]
        return first / m.sum()

    # ---------------------------------------------------------- export (phmech/io.py)

    def to_xarray(self):
        """The result as an ``xarray.Dataset``: dimensions time x carrier x component (and
        joint, constraint, pair, port), coordinates with the carriers', joints' and ports'
        names, a ``units`` attribute per variable and the solver statistics as attributes
        (``stats_*``); see docs/user_guide.md, "Saving, loading and exporting"."""
        return _resultfile.simulation_dataset(self)

    def to_netcdf(self, path) -> None:
        """Write the result to the netCDF-4 file ``path`` (atomically); ``phmech.load_result``
        reads it back equal."""
        _resultfile.write_result(self, path)

    def to_dataframe(self):
        """The scalar series as a ``pandas.DataFrame`` indexed by time [s]: ``energy.<name>``
        [J], ``port.<name>`` [J], and ``<joint>.x``, ``.xdot``, ``.effort`` per joint coordinate
        (``<pair>`` or ``<pair>[i]``; rad or m, per s, N m or N)."""
        return _resultfile.simulation_dataframe(self)


@dataclasses.dataclass
class ModesResult:
    """Linearized modes: ``omega`` [rad/s], ``frequency`` [Hz], ``damping_ratio``, ``shapes``
    (n, ncarriers, 6) tangent displacements (rotation, translation) per carrier in its body
    axes (H exp(phi)), mass-normalized. A negative ``omega``/``frequency`` is -sqrt(-lambda) for
    a negative eigenvalue lambda of the tangent: an unstable direction (or, away from an
    equilibrium, a direction in which the tangent stiffness is negative).

    Labels (phmech.analysis.label_modes, set by Mechanism.modes): ``kind`` one of
    ``"bending-y"`` (sections rotating about the link's local y axis, deflection along local z:
    bending in the local x-z plane), ``"bending-z"`` (about local z, deflection along local y:
    the x-y plane), ``"torsion"``, ``"axial"`` (by the largest share of the links' strain
    energy, ``strain_fractions`` (n, 4) in that order) or ``"rigid-body"`` (the links store less
    than half the mode's energy: ``elastic_fraction`` < 0.5); ``participation``: per mode, each
    body's and link's share of the kinetic energy; ``strain_participation``: each link's share of
    the strain energy. ``labels`` are readable forms, ``mac(other)`` the modal assurance
    criterion, ``table()`` a text summary."""
    omega: np.ndarray
    frequency: np.ndarray
    damping_ratio: np.ndarray
    shapes: np.ndarray
    kind: list = dataclasses.field(default_factory=list)
    strain_fractions: np.ndarray = None
    elastic_fraction: np.ndarray = None
    participation: list = dataclasses.field(default_factory=list)
    strain_participation: list = dataclasses.field(default_factory=list)
    #: poses (ncarriers, 4, 4) the modes were computed at (phmech.plot draws shapes on them)
    poses: np.ndarray = None
    #: False when modes() found the configuration away from a static equilibrium (it warned)
    equilibrium: bool = True
    #: with components (controllers, motors, friction) or a spin: the poles s [1/s], one per
    #: mode (omega = abs(s), damping_ratio = -Re(s)/abs(s)); None otherwise
    poles: np.ndarray = None
    _links: dict = dataclasses.field(default_factory=dict, repr=False)
    _bodies: dict = dataclasses.field(default_factory=dict, repr=False)

    @property
    def labels(self) -> list:
        """Readable kind of each mode, with the link or body that dominates it, e.g.
        ``"bending about y (local x-z plane), leaf"``."""
        out = []
        for k, kd in enumerate(self.kind):
            src = self.strain_participation[k] if kd != "rigid-body" else self.participation[k]
            who = max(src, key=src.get) if src else ""
            if src and kd != "rigid-body" and sum(v > 0.25 for v in src.values()) > 1:
                who = ", ".join(nm for nm, v in src.items() if v > 0.25)
            out.append(MODE_KIND_TEXT[kd] + (f", {who}" if who else ""))
        return out

    def mac(self, other=None) -> np.ndarray:
        """Modal assurance criterion (n, n_other) against another ModesResult of the same
        mechanism (or an array of shapes); None: against itself (phmech.analysis.mac)."""
        return mac(self, other)

    def table(self) -> str:
        """One line per mode: number, frequency [Hz], kind and where it sits."""
        lines = [f"{'mode':>4} {'f [Hz]':>12}  kind"]
        for k, lab in enumerate(self.labels or [""] * len(self.omega)):
            lines.append(f"{k + 1:4d} {self.frequency[k]:12.5g}  {lab}")
        return "\n".join(lines)

    def to_xarray(self):
        """The modes as an ``xarray.Dataset`` (dimensions mode x carrier x component)."""
        return _resultfile.modes_dataset(self)

    def to_netcdf(self, path) -> None:
        """Write the modes to the netCDF-4 file ``path``; ``phmech.load_result`` reads them."""
        _resultfile.write_result(self, path)


@dataclasses.dataclass(frozen=True)
class FreeMotion:
    """A motion that nothing resists and on which the loads do work at the same rate in every
    configuration, so that no static equilibrium exists: ``Mechanism.static`` raises SolverError
    with a list of them in its ``free_motions`` attribute (csrc/analyze/static_free.c).

    ``pair``: the pair whose joint ``coordinate`` moves the part on its side away from the
    ground, or None for a part that nothing links to the ground (moving rigidly). ``force``: the
    generalized force of the loads along it, per unit of the motion (``unit``: "N m" per rad,
    "N" per m), at load factor 1; ``sources``: its parts, by what applies them (actuators,
    gravity, wrenches). ``twist``: the motion per unit, a world twist (omega, v) at the state of
    the error's ``result``. ``moving``: the bodies and links that move. ``text``: the sentence
    of the error message."""
    pair: Optional[str]
    coordinate: Optional[int]
    force: float
    unit: str
    sources: dict
    twist: np.ndarray
    moving: tuple
    text: str


@dataclasses.dataclass
class StaticResult:
    """Static equilibrium: ``poses`` (ncarriers, 4, 4), ``constraint_wrenches``, Newton
    ``iterations``; ``loads``: the extra loads it was found under (``static(loads=...)``), which
    ``modes(at=...)`` linearizes with; ``steps``: the load steps used; ``stable``: whether the
    lowest linearized mode there is stable (None when not checked: ``check_stability=False``, or
    loads without a potential: see Mechanism.static), and ``lowest_omega`` [rad/s] that mode's
    frequency (negative: unstable; inf for a mechanism that cannot move)."""
    poses: np.ndarray
    constraint_wrenches: np.ndarray
    iterations: int
    _links: dict
    loads: tuple = ()
    steps: int = 0
    stable: Optional[bool] = None
    lowest_omega: float = float("nan")
    #: the load factor this state is in equilibrium under: 1, or less for the partial result of
    #: a failed solve (SolverError.result)
    load_factor: float = 1.0

    def positions(self, link: Union[str, FlexibleLink]) -> np.ndarray:
        """Node positions of a link [m], shape (nodes, 3)."""
        lk = link_of(self._links, link, "")
        return lk.node_poses(self.poses[lk.nodes])[:, :3, 3]

    def to_xarray(self):
        """The equilibrium as an ``xarray.Dataset`` (poses: carrier x row x col)."""
        return _resultfile.static_dataset(self)

    def to_netcdf(self, path) -> None:
        """Write the equilibrium to the netCDF-4 file ``path``; ``phmech.load_result`` reads it."""
        _resultfile.write_result(self, path)


def load_result(path):
    """The SimulationResult, ModesResult or StaticResult in the netCDF file ``path`` (written by
    ``to_netcdf`` or a checkpoint), equal to the one written. ModelError when the file is not a
    phmech result, has a newer result schema than this phmech reads, or lacks a variable that
    its writer wrote (a damaged file; the error names the variable).

    An array the result did not hold when written reads as None, as it was: a SimulationResult's
    core array from a file written by a phmech before that quantity (e.g. ``strain_energy``,
    ``constraint_residual``; the result schema version does not change when the core adds one),
    a ModesResult's ``poses``, ``poles``, ``strain_fractions`` and ``elastic_fraction`` when it
    had none. A file names the core arrays it holds (its ``phmech_meta`` "held"); one from before
    that list must hold ``poses``, ``twists``, ``joints``, ``joint_rates`` and ``efforts``, which
    every phmech wrote."""
    import xarray as xr
    p = os.fspath(path)
    try:
        with xr.open_dataset(p, engine="h5netcdf") as ds:
            ds = ds.load()
    except (OSError, ValueError) as e:
        raise ModelError(f"{p}: not a phmech result (cannot be read as netCDF-4: {e})") from None
    if ds.attrs.get("format") != _resultfile.RESULT_FORMAT:
        raise ModelError(f"{p}: not a phmech result (no \"format\": \"{_resultfile.RESULT_FORMAT}\" attribute)")
    v = ds.attrs.get("schema_version")
    if v is None or int(v) > _resultfile.RESULT_SCHEMA_VERSION:
        raise ModelError(f"{p}: this result file has schema version {v} (written by phmech "
                         f"{ds.attrs.get('phmech_version', '?')}); this phmech {_resultfile._version()} reads "
                         f"result schema versions up to {_resultfile.RESULT_SCHEMA_VERSION}: upgrade phmech")
    kind = ds.attrs.get("kind")
    meta = json.loads(ds.attrs.get("phmech_meta", "{}"))

    def a(name: str) -> np.ndarray:
        if name not in ds:
            raise ModelError(f"{p}: this {kind} result file has no variable {name!r}, which its "
                             f"writer wrote (a damaged file?)")
        return np.ascontiguousarray(ds[name].values)
    if kind == "modes":
        opt = lambda name: a(name) if name in ds else None   # noqa: E731
        return ModesResult(a("omega"), a("frequency"), a("damping_ratio"), a("shapes"),
                           kind=meta.get("kind", []), strain_fractions=opt("strain_fractions"),
                           elastic_fraction=opt("elastic_fraction"),
                           participation=meta.get("participation", []),
                           strain_participation=meta.get("strain_participation", []),
                           poses=opt("poses"), equilibrium=meta.get("equilibrium", True),
                           poles=_resultfile.complex_of(a("poles")) if "poles" in ds else None,
                           _links=_resultfile._links_from(meta.get("links", {})),
                           _bodies={n: Body(n, c) for n, c in meta.get("bodies", {}).items()})
    if kind == "static":
        return StaticResult(a("poses"), a("constraint_wrenches"), int(ds.attrs["iterations"]),
                            _resultfile._links_from(meta["links"]), tuple(decode_value(meta["loads"])),
                            steps=meta["steps"], stable=meta["stable"],
                            lowest_omega=meta["lowest_omega"],
                            load_factor=meta.get("load_factor", 1.0))
    if kind != "simulation":
        raise ModelError(f"{p}: unknown result kind {kind!r}")
    bodies = {n: Body(n, c) for n, c in meta["bodies"].items()}
    held = meta.get("held", _resultfile.ALWAYS_HELD)
    ports = [str(x) for x in a("port")]
    sensors, ctrls = _resultfile.sensors_and_controllers(a, meta)
    return SimulationResult(
        t=a("time"), constraint_wrenches=a("constraint_wrenches"),
        energy={str(k): a("energy")[:, i].copy() for i, k in enumerate(ds["energy_kind"].values)},
        stats=decode_value(meta["stats"]),
        interrupted=bool(meta["interrupted"]), _links=_resultfile._links_from(meta["links"]),
        port_energy={p_: a("port_energy")[:, i].copy() for i, p_ in enumerate(ports)},
        pair_wrenches=a("pair_wrenches"), _pairs=decode_value(meta["pairs"]),
        # an array the writer did not hold: None (a file from before its quantity)
        **{f.name: a(f.name) if f.name in ds or f.name in held else None for f in HELD_FIELDS},
        redundant_constraints=decode_value(meta["redundant"]),
        carriers=a("carrier") if meta["recorded"] else None,
        _inertia=a("inertia"), _mass=a("mass"), _com=a("com"), _bodies=bodies,
        _coupled_nodes=a("coupled_nodes").astype(int) if "coupled_nodes" in ds
        else np.zeros((0, 2), dtype=int),
        _couplings=a("couplings") if "couplings" in ds else np.zeros((0, 12, 12)),
        # a file from before the fields (or without couplings): the masses on their carriers
        _coupled_fields=a("coupled_fields") if "coupled_fields" in ds
        else np.zeros((ds.sizes.get("coupled_element", 0), 5)),
        components=_resultfile.component_states(ds), sensors=sensors, controllers=ctrls)

"""Sensors: named measurements of a mechanism, read by sampled controllers during a run
(``phmech.controllers``) and returned over the outputs in ``res.sensors[name]``.

``Mechanism.add_sensor(name, sensor)`` adds one of:

- ``JointSensor(pair, rate=False, coordinate=None)``: a pair's joint coordinates [rad or m]
  (multi-turn) or, with ``rate=True``, their rates [rad/s or m/s]; all k coordinates, or the one
  ``coordinate``;
- ``FrameSensor(frame, quantity)``: a frame's (a Frame, Body, link end or a body's name)
  ``"pose"`` (4x4, world), ``"position"`` (3, world) [m], ``"twist"`` (6, its body twist
  (omega [rad/s], v [m/s]) in its own axes) or ``"velocity"`` (3, its origin's world velocity
  [m/s]);
- ``TipDeflection(link)``: a flexible link's end relative to where its start would put it were
  the link rigid (its unstressed shape carried by the start frame): 6 values, the rotation
  vector [rad] then the displacement [m], both in the start frame's axes (for a straight link
  along x, entries 4 and 5 are the deflections along y and z);
- ``LinkStrain(link, station)``: the strain eps - eps_hat (6: curvatures [1/m] about x, y, z,
  then axial and shear strains [-]) of the element of a nonlinear link that holds ``station``
  [m from its start], eps = log(H_a^-1 H_b) / h (csrc/model/element.c: an element's strain is
  constant along it);
- ``PairWrench(pair)``: the constraint wrench (tau [N m], f [N]) a pair applies on its frame b, in
  F_b (``res.joint(pair)["wrench"]``; with redundant constraints the run's own multipliers, the
  result's minimum-norm ones);
- ``ComponentState(component, state)``: an internal state of a component (a motor's current
  "i" [A], a LuGre bristle deflection "z" [m or rad], a linear controller's "x0", ...).

A sensor's value is a flat array; ``res.sensors[name]`` is (nt, size) (a pose (nt, 4, 4)).
Values come from the run's outputs (``sensor_values``): NumPy on the poses, twists and joint
arrays, no call into the core.

Sensors (by name, or sensor objects) are also outputs of ``Mechanism.linearize``: their rows of
C (``sensor_rows``), the first order of their values in H = H0 exp(xi) -- displacements (joint
coordinates, poses, positions, tip deflections, strains) over the reduced coordinates q, rates
(joint rates, twists, velocities) over dq/dt, component states over z; a PairWrench is no state
of the linear model and is refused."""
from __future__ import annotations

import dataclasses
from typing import Optional

import numpy as np

from . import se3
from ._errors import ModelError
from .frames import FlexibleLink, frame_of

__all__ = ["JointSensor", "FrameSensor", "TipDeflection", "LinkStrain", "PairWrench",
           "ComponentState", "sensor_row", "sensor_values", "sensor_rows"]

#: FrameSensor quantities -> their size
_FRAME_QUANTITIES = {"pose": 16, "position": 3, "twist": 6, "velocity": 3}


@dataclasses.dataclass(frozen=True)
class JointSensor:
    """A pair's joint coordinates [rad or m] (``rate=False``) or rates [rad/s or m/s]; all its
    k coordinates (``coordinate=None``) or one."""
    pair: str
    rate: bool = False
    coordinate: Optional[int] = None


@dataclasses.dataclass(frozen=True)
class FrameSensor:
    """A frame's ``quantity``: "pose" (4x4 world pose), "position" (world [m]), "twist" (body
    twist (omega [rad/s], v [m/s]) in the frame's axes) or "velocity" (its origin's world
    velocity [m/s])."""
    frame: object
    quantity: str = "pose"


@dataclasses.dataclass(frozen=True)
class TipDeflection:
    """A flexible link's end relative to the rigid motion of its start (rotation vector [rad],
    displacement [m]; start-frame axes): 6 values."""
    link: object


@dataclasses.dataclass(frozen=True)
class LinkStrain:
    """Strain eps - eps_hat (curvatures [1/m], axial and shear strains [-]) of the element of a
    nonlinear link holding ``station`` [m from its start]: 6 values."""
    link: object
    station: float = 0.0


@dataclasses.dataclass(frozen=True)
class PairWrench:
    """The constraint wrench (tau [N m], f [N]) of the pair named ``pair`` on its frame b, in
    F_b: 6 values."""
    pair: str


@dataclasses.dataclass(frozen=True)
class ComponentState:
    """The internal state ``state`` of the component named ``component`` (added before the
    sensor; ``phmech.components``): 1 value in the state's unit."""
    component: str
    state: str


def _link(desc, x, what: str) -> FlexibleLink:
    nm = x.name if isinstance(x, FlexibleLink) else x
    if not isinstance(nm, str) or nm not in desc.links or \
            (isinstance(x, FlexibleLink) and desc.links[nm] != x):
        raise ModelError(f"{what}: {x!r} is not a flexible link of this mechanism (links: "
                         f"{', '.join(map(repr, desc.links)) or 'none'})")
    return desc.links[nm]


def sensor_row(name: str, sensor, desc) -> dict:
    """The validated row of ``sensor`` named ``name`` on the description ``desc`` (ModelError
    naming the sensor otherwise): kind, size, shape (of one value), unit, carriers (whose poses
    and twists it reads) and what it needs to evaluate."""
    what = f"sensor {name!r}"
    if isinstance(sensor, JointSensor):
        rows = {p["name"]: (i, p) for i, p in enumerate(desc.pairs)}
        if not isinstance(sensor.pair, str) or sensor.pair not in rows:
            raise ModelError(f"{what}: unknown pair {sensor.pair!r} (pairs: "
                             f"{', '.join(map(repr, rows)) or 'none'})")
        ip, p = rows[sensor.pair]
        k = p["k"]
        if k == 0:
            raise ModelError(f"{what}: pair {sensor.pair!r} has no joint coordinates")
        j0 = sum(q["k"] for q in desc.pairs[:ip])
        cs = list(range(k))
        if sensor.coordinate is not None:
            c = sensor.coordinate
            if isinstance(c, bool) or not isinstance(c, (int, np.integer)) or not 0 <= c < k:
                raise ModelError(f"{what}: coordinate {c!r} is not one of pair {sensor.pair!r}'s "
                                 f"{k} coordinates")
            cs = [int(c)]
        units = p["pair"]._type.units
        unit = ", ".join(units[c] + ("/s" if sensor.rate else "") for c in cs)
        return dict(name=name, kind="joint", cols=[j0 + c for c in cs], rate=bool(sensor.rate),
                    size=len(cs), shape=(len(cs),), unit=unit, carriers=[])
    if isinstance(sensor, FrameSensor):
        f = frame_of(sensor.frame, desc, f"{what}: frame")
        q = sensor.quantity
        if not isinstance(q, str) or q not in _FRAME_QUANTITIES:
            raise ModelError(f"{what}: quantity {q!r} is not one of "
                             f"{', '.join(map(repr, _FRAME_QUANTITIES))}")
        unit = {"pose": "- (rotation), m (position)", "position": "m",
                "twist": "rad/s (omega), m/s (v)", "velocity": "m/s"}[q]
        return dict(name=name, kind="frame", frame=f, quantity=q, size=_FRAME_QUANTITIES[q],
                    shape=(4, 4) if q == "pose" else (_FRAME_QUANTITIES[q],), unit=unit,
                    carriers=[f.carrier] if f.carrier >= 0 else [])
    if isinstance(sensor, TipDeflection):
        lk = _link(desc, sensor.link, what)
        T0 = se3.exp(lk.length * desc.link_unstressed_strain(lk))
        return dict(name=name, kind="tip", start=lk.start, end=lk.end, T0=T0, size=6, shape=(6,),
                    unit="rad (rotation), m (displacement)",
                    carriers=[lk.nodes[0], lk.nodes[-1]])
    if isinstance(sensor, LinkStrain):
        lk = _link(desc, sensor.link, what)
        if lk.fidelity != "nonlinear":
            raise ModelError(f"{what}: link {lk.name!r} is {lk.fidelity}; strains are those of "
                             f"a nonlinear link's elements")
        try:
            s = float(sensor.station)
        except (TypeError, ValueError):
            s = float("nan")
        if not 0.0 <= s <= lk.length:
            raise ModelError(f"{what}: station {sensor.station!r} is not within link "
                             f"{lk.name!r} (0 .. {lk.length:g} m)")
        h = lk.length / lk.elements
        e = min(int(s / h), lk.elements - 1)
        return dict(name=name, kind="strain", a=lk.nodes[e], b=lk.nodes[e + 1], h=h,
                    eps_hat=np.array(desc.link_unstressed_strain(lk), dtype=float), size=6,
                    shape=(6,), unit="1/m (curvatures), - (axial and shear)",
                    carriers=[lk.nodes[e], lk.nodes[e + 1]])
    if isinstance(sensor, PairWrench):
        rows = [p["name"] for p in desc.pairs]
        if not isinstance(sensor.pair, str) or sensor.pair not in rows:
            raise ModelError(f"{what}: unknown pair {sensor.pair!r} (pairs: "
                             f"{', '.join(map(repr, rows)) or 'none'})")
        return dict(name=name, kind="wrench", pair=rows.index(sensor.pair), size=6, shape=(6,),
                    unit="N m (tau), N (f)", carriers=[])
    if isinstance(sensor, ComponentState):
        comps = {c["name"]: c for c in desc.components}
        c = comps.get(sensor.component) if isinstance(sensor.component, str) else None
        if c is None:
            raise ModelError(f"{what}: unknown component {sensor.component!r} (components: "
                             f"{', '.join(map(repr, comps)) or 'none'})")
        if sensor.state not in c["states"]:
            raise ModelError(f"{what}: component {sensor.component!r} has no state "
                             f"{sensor.state!r} (its states: "
                             f"{', '.join(map(repr, c['states'])) or 'none'})")
        return dict(name=name, kind="state", component=sensor.component,
                    index=list(c["states"]).index(sensor.state), size=1, shape=(1,),
                    unit="the state's (A, m, rad, ...)", carriers=[])
    raise ModelError(f"{what}: expected JointSensor, FrameSensor, TipDeflection, LinkStrain, "
                     f"PairWrench or ComponentState (got {type(sensor).__name__})")


def sensor_values(row: dict, r: dict, column: dict, states: dict) -> np.ndarray:
    """The values (n, size) of sensor ``row`` at n outputs of the output arrays ``r``
    (``joints``, ``joint_rates`` (n, ncoords), ``poses`` (n, ncols, 4, 4), ``twists`` (n, ncols,
    6), ``pair_wrenches`` (n, npairs, 6), ``components`` (n, nz): as _core.model_simulate
    returns them), ``column`` carrier index -> its column in ``poses`` (all carriers, or those
    recorded), ``states`` component name -> its first column in ``components``."""
    joints, poses, twists = r["joints"], r["poses"], r["twists"]
    n = joints.shape[0]
    kind = row["kind"]
    if kind == "joint":
        return r["joint_rates" if row["rate"] else "joints"][:, row["cols"]].copy()
    if kind == "wrench":
        return r["pair_wrenches"][:, row["pair"]].copy()
    if kind == "state":
        return r["components"][:, states[row["component"]] + row["index"]][:, None].copy()

    def pose(f):
        if f.carrier < 0:
            return np.broadcast_to(f.T, (n, 4, 4))
        return poses[:, column[f.carrier]] @ f.T

    if kind == "frame":
        f, q = row["frame"], row["quantity"]
        if q in ("pose", "position"):
            H = pose(f)
            return H.reshape(n, 16).copy() if q == "pose" else H[:, :3, 3].copy()
        tw = np.zeros((n, 6)) if f.carrier < 0 else \
            twists[:, column[f.carrier]] @ se3.Ad(se3.inverse(f.T)).T
        if q == "twist":
            return tw
        return np.einsum("nij,nj->ni", pose(f)[:, :3, :3], tw[:, 3:])
    if kind == "tip":
        Hs, He = pose(row["start"]), pose(row["end"])
        rel = se3.inverse(Hs @ row["T0"]) @ He          # the end in its rigid position's frame
        R0 = row["T0"][:3, :3]
        rot = R0 @ se3.log(rel[:, :3, :3]).reshape(n, 3, 1)   # start-frame axes
        d = np.einsum("nji,nj->ni", Hs[:, :3, :3], He[:, :3, 3] - Hs[:, :3, 3]) - row["T0"][:3, 3]
        return np.concatenate([rot.reshape(n, 3), d], axis=1)
    # strain: log(Ha^-1 Hb) / h - eps_hat
    Ha, Hb = poses[:, column[row["a"]]], poses[:, column[row["b"]]]
    return se3.log(se3.inverse(Ha) @ Hb) / row["h"] - row["eps_hat"]


# ------------------------------------------------ as outputs of Mechanism.linearize (linear.py)
SENSOR_TYPES = (JointSensor, FrameSensor, TipDeflection, LinkStrain, PairWrench, ComponentState)


def output_row(desc, x) -> Optional[tuple]:
    """(row, labels) of an output item that is a sensor -- an added sensor's name or a sensor
    object (phmech.sensors) -- or None for a port."""
    if isinstance(x, str) and x in desc.sensors:
        row = desc.sensors[x]
        return row, [x] if row["size"] == 1 else [f"{x}[{i}]" for i in range(row["size"])]
    if not isinstance(x, SENSOR_TYPES):
        return None
    row = sensor_row(f"{type(x).__name__} output", x, desc)
    if isinstance(x, JointSensor):
        k = next(p["k"] for p in desc.pairs if p["name"] == x.pair)
        first = row["cols"][0] - (x.coordinate or 0)
        end = ".rate" if x.rate else ".x"
        return row, [(x.pair if k == 1 else f"{x.pair}[{c - first}]") + end for c in row["cols"]]
    base = {FrameSensor: lambda: f"{row['frame'].name or 'frame'}.{x.quantity}",
            TipDeflection: lambda: f"{desc.links[_link_name(x.link)].name}.tip",
            LinkStrain: lambda: f"{desc.links[_link_name(x.link)].name}.strain",
            PairWrench: lambda: f"{x.pair}.wrench",
            ComponentState: lambda: f"{x.component}.{x.state}"}[type(x)]()
    return row, [base] if row["size"] == 1 else [f"{base}[{i}]" for i in range(row["size"])]


def _link_name(link) -> str:
    return link if isinstance(link, str) else link.name


def joint_pair(desc, col: int) -> tuple:
    """(pair name, its first joint column) of the joint column ``col``."""
    j0 = 0
    for p in desc.pairs:
        if j0 <= col < j0 + p["k"]:
            return p["name"], j0
        j0 += p["k"]
    raise ModelError(f"joint column {col} is in no pair")       # pragma: no cover


def _frame_disp(f, Z: np.ndarray) -> np.ndarray:
    """The tangent displacements (6, nr) of frame ``f`` per reduced coordinate, in its own axes:
    Ad(T^-1) Z_c (H_c exp(xi) T = H_c T exp(Ad(T^-1) xi)); zero on the ground."""
    if f.carrier < 0:
        return np.zeros((6, Z.shape[1]))
    return se3.Ad(se3.inverse(f.T)) @ Z[6 * f.carrier:6 * f.carrier + 6]


def sensor_rows(row: dict, poses: np.ndarray, Z: np.ndarray, pair_rows: Optional[np.ndarray],
                state_col: Optional[int]) -> tuple:
    """(kind, rows) of a sensor's linearization at ``poses`` (ncarriers, 4, 4) on the reduced
    coordinates Z (6 nc x nr): kind "q" (its change is rows @ dq: a displacement), "v" (rows @
    dq/dt: a rate) or "z" (the component state ``state_col``). ``pair_rows`` (ncoords of the
    pair, nr): a JointSensor's pair's joint-rate map, which is also its coordinates' tangent.
    Frames, tips and strains: first order in H = H0 exp(xi) (se3.dexp for the logarithms)."""
    kind = row["kind"]
    if kind == "joint":
        return ("v" if row["rate"] else "q"), pair_rows
    if kind == "state":
        return "z", state_col
    if kind == "wrench":
        raise ModelError(f"linearize outputs: {row['name']!r} (PairWrench): a constraint wrench "
                         f"is no state of the linear model; outputs are joint coordinates and "
                         f"rates, frames' poses, positions, twists and velocities, tip "
                         f"deflections, strains and component states")

    def pose(f):
        return f.T if f.carrier < 0 else poses[f.carrier] @ f.T
    if kind == "frame":
        f, q = row["frame"], row["quantity"]
        x, H = _frame_disp(f, Z), pose(f)
        if q == "twist":
            return "v", x
        if q == "velocity":
            return "v", H[:3, :3] @ x[3:]
        if q == "position":
            return "q", H[:3, :3] @ x[3:]
        return "q", np.einsum("ij,njk->nik", H, se3.hat(x.T)).reshape(-1, 16).T   # pose
    if kind == "tip":
        Hs, He = pose(row["start"]), pose(row["end"])
        xs, xe = _frame_disp(row["start"], Z), _frame_disp(row["end"], Z)
        rel = se3.inverse(Hs @ row["T0"]) @ He
        d = se3.Ad(se3.inverse(He) @ Hs) @ xs            # the start's motion in the end's axes
        phi = se3.log(rel[:3, :3])
        rot = row["T0"][:3, :3] @ se3.dexp_inv(-phi) @ (xe[:3] - d[:3])
        r = Hs[:3, :3].T @ (He[:3, 3] - Hs[:3, 3])       # the end from the start, start axes
        disp = se3.hat(r) @ xs[:3] + Hs[:3, :3].T @ He[:3, :3] @ xe[3:] - xs[3:]
        return "q", np.vstack([rot, disp])
    # strain: log(Ha^-1 Hb) / h - eps_hat
    Ha, Hb = poses[row["a"]], poses[row["b"]]
    za, zb = Z[6 * row["a"]:6 * row["a"] + 6], Z[6 * row["b"]:6 * row["b"] + 6]
    G = se3.inverse(Ha) @ Hb
    phi = se3.log(G)
    return "q", se3.dexp_inv(-phi) @ (zb - se3.Ad(se3.inverse(G)) @ za) / row["h"]

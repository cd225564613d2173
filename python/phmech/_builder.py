"""The builder: what a Mechanism collects -- rigid bodies, flexible links, pairs, actuators,
spring-dampers, applied wrenches and distributed loads -- checked and appended as rows of its
model description (phmech.description), each call recorded for its model file (phmech.io).
phmech.Mechanism is this builder with the analyses (python/phmech/mechanism.py); a link-alone
analysis (python/phmech/_reduction.py, phmech.mesh) builds on a bare Builder. NumPy only: the
builder never calls the C core except through its stateless kernels (phmech._codes).

Conventions: SI units; twist (omega, v) and wrench (tau, f), angular part first; poses 4x4.
A beam's local x axis is its centre line; its section axes are y and z."""
from __future__ import annotations

import numbers
from typing import Optional, Sequence

import numpy as np

from . import io, _placement
from .actuators import Effort, actuator_row
from .components import component_row
from .controllers import (EffortOutput, Hold, MotorVoltageOutput, controller_row, voltage_input,
                          zero)
from ._checks import (ANGLE_SLIP, array, choice, inertia_triangle, per_coordinate,
                      positive_definite, real, rigid_pose)
from .description import ModelDescription
from ._errors import ModelError, warn_plausibility
from .fidelity import distributed_resultant
from ._links import LinkBuilder
from .frames import Body, FlexibleLink, Frame, frame_of
from .graphs import Graphs, mechanism_graphs
from .laws import Constant, Function, Motion, _Law, checked_law
from .pairs import PAIR_TYPES, _Pair
from .sensors import sensor_row



_recorded = io.recorded   # a builder call a model file replays (phmech/io.py)


class Builder(LinkBuilder):
    """A model description under construction (the builder half of phmech.Mechanism, whose
    docstring gives the arguments): every ``add_*`` checks its arguments, appends rows to the
    description and drops the initial configuration found so far."""

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
        self._state = None
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
        #: sag (relative; phmech._reduction.static_reduction), warned about under gravity
        self._modal_gravity_miss: dict = {}
        #: modal link name -> [a function measuring the relative shift of its first frequency
        #: held at its start per m/s^2 of gravity along it (_reduction.gravity_preload_sensitivity;
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
        H = _placement.place_tree(self._desc)[0]
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
                             f"{', '.join(t.name for t in PAIR_TYPES)})")
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
        warn_plausibility(slips)

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
                Hb, tb = _placement.pose_across(e, x, xd, Ha, ta)
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

    def _refuse_stateful_components(self, what: str) -> None:
        """ModelError: static includes the components without states (friction, which is zero
        at rest; a current-driven motor's torque; a static-gain LinearController's effort), not
        yet those with states (LuGre, a voltage-driven motor, dynamic controllers), whose rest
        value the states decide (modes and linearize include them, linearized; simulate
        integrates them)."""
        stateful = [r for r in self._desc.components if r["nstates"]]
        if stateful:
            names = ", ".join(repr(r["name"]) for r in stateful)
            raise ModelError(f"{what}: the components {names} have states (LuGre bristles, a "
                             f"motor current, controller states) and are not part of the static "
                             f"analysis yet; simulate() includes them, and modes() and "
                             f"linearize() linearized about the initial state")

    @_recorded
    def add_component(self, name: str, pair: str, component) -> None:
        """A component with internal states (``phmech.components``: ViscousFriction,
        CoulombFriction, StribeckFriction, LuGreFriction, DCMotor, LinearController) named
        ``name`` on the revolute or prismatic pair named ``pair``; its states are in
        ``res.components[name]``."""
        if not isinstance(pair, str):
            raise ModelError(f"component {name!r}: pair must be given by its name (got {pair!r})")
        e = self._pair_entry(pair)
        self._check_name(name)
        sensor = getattr(component, "sensor", None)
        if sensor is not None:   # a controller measuring another pair
            se = self._pair_entry(sensor)
            sensor = (self._pairs.index(se), se["k"])
        row = component_row(name, e, self._pairs.index(e), component, sensor)
        self._new_name(name)
        self._desc.components.append(row)

    @_recorded
    def add_sensor(self, name: str, sensor) -> None:
        """A sensor (``phmech.sensors``: JointSensor, FrameSensor, TipDeflection, LinkStrain)
        named ``name``: a sampled controller's input, and ``res.sensors[name]`` over a run's
        outputs (in the sensor's units)."""
        self._check_name(name)
        row = sensor_row(name, sensor, self._desc)
        self._new_name(name)
        self._desc.sensors[name] = row

    @_recorded
    def add_controller(self, name: str, controller) -> None:
        """A sampled controller with a zero-order hold (``phmech.SampledController``) named
        ``name``: its inputs are sensors added before it, its outputs efforts on pairs or wrenches,
        each an actuator or wrench named ``name[j]`` (a port of the ledger) whose value the run
        holds between samples; ``res.controllers[name]`` holds its samples."""
        self._check_name(name)
        row = controller_row(name, controller, self._desc.sensors)
        hold = Hold(row["u0"])
        acts, loads, motors = [], [], []
        for j, o in enumerate(row["outputs"]):
            nm = f"{name}[{j}]"
            self._check_name(nm)
            law = checked_law(Function(hold.law_fn(j), zero, zero), f"controller {name!r}")
            if isinstance(o, MotorVoltageOutput):
                motors.append((voltage_input(self._desc, name, j, o, [r for r, _ in motors]), law))
            elif isinstance(o, EffortOutput):
                if not isinstance(o.pair, str) or o.pair not in [p["name"] for p in self._pairs]:
                    raise ModelError(f"controller {name!r}: output {j} is on the unknown pair "
                                     f"{o.pair!r} (pairs: "
                                     f"{', '.join(repr(p['name']) for p in self._pairs) or 'none'})")
                e = self._pair_entry(o.pair)
                k, c = e["k"], o.coordinate
                if isinstance(c, bool) or not isinstance(c, (int, np.integer)) or not 0 <= c < k:
                    raise ModelError(f"controller {name!r}: output {j} drives coordinate {c!r} "
                                     f"of pair {o.pair!r}, which has {k}")
                d = np.zeros(k)
                d[c] = 1.0
                acts.append(actuator_row(nm, e, self._pairs.index(e), Effort(law, d)))
            else:
                loads.append(self._wrench_entry(nm, o.target, o.wrench, law, o.frame, o.point,
                                                f"controller {name!r}, output {j}"))
        self._new_name(name)
        for r in acts:
            self._new_name(r["name"])
            self._acts.append(r)
        for r in loads:
            self._new_name(r["name"])
            self._loads.append(r)
        for r, law in motors:   # the motor's voltage is the held value from now on
            r["law"] = law
        # law_rows in the outputs' order (each row's law reads hold.u[j], j its output)
        rows = iter(acts), iter(loads), iter(r for r, _ in motors)
        order = [rows[2 if isinstance(o, MotorVoltageOutput) else 0 if isinstance(o, EffortOutput)
                      else 1] for o in row["outputs"]]
        self._desc.controllers.append(dict(row, hold=hold, law_rows=[next(it) for it in order]))

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



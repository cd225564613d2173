"""Robots from URDF: :func:`load_urdf` builds a :class:`phmech.Mechanism` from a URDF file with
the public builder API (``add_rigid_body``, ``add_flexible_link``, ``add_pair``,
``add_actuator``) and nothing else, so it is a leaf module: it imports the builder, and only
``phmech/__init__.py`` imports it (for the export).

Parser: ``yourdfpy`` (PyPI), chosen over ``urdfdom-py`` (the ROS ``urdf_parser_py``): both
are maintained pure-Python parsers on lxml (yourdfpy's last release January 2026, urdfdom-py's
June 2025), but yourdfpy hands over what an importer needs ready to use -- every ``<origin>``
as a 4x4 matrix, the inertia as a 3x3 matrix, ``<limit>``, ``<mimic>`` and ``<dynamics>`` as
dataclasses -- where urdfdom-py gives xyz/rpy lists to convert, and it reads a file without
loading meshes or building a scene graph when asked not to (``load_meshes=False,
build_scene_graph=False``); its own dependencies (trimesh, six) are pure Python. It checks
none of the kinematic structure, and it recovers silently from malformed XML: this module
parses strictly first and checks the structure itself (missing links, several parents, loops,
several roots, unknown joint types, missing or zero inertials), with a ModelError naming the
element.

Mapping (URDF -> phmech):

- the root link (the one link that is no joint's child) and every link welded to it by
  ``fixed`` joints are the ground (``base="fixed"``, the default), or one rigid body on a
  ``Free`` pair to the ground (``base="floating"``);
- every other group of links welded together by ``fixed`` joints is ONE rigid body named after
  its top link (the child of the movable joint above it), its mass, centre of mass and inertia
  the group's (each link's ``<inertial>``: mass, inertia about the inertial origin in the
  axes of its rotation, turned into the body axes and moved by the parallel-axis theorem);
  the body frame is the top link's URDF frame; ``URDFRobot.frames`` gives every link's frame;
- movable joints become pairs named after them, between the parent link's joint frame (the
  joint ``<origin>`` on the parent's body) and the child link's frame, the joint axis the
  pair's axis: ``revolute`` and ``continuous`` -> ``Revolute``, ``prismatic`` ->
  ``Prismatic``, ``floating`` -> ``Free`` (x = rotation vector, position), ``planar`` ->
  ``Planar`` with the axis as its normal (x = angle, p_x, p_y in the joint frame whose z is the
  axis); the joint coordinate is the URDF's q (same sign and zero);
- ``<limit>``: position, velocity and effort limits are not enforced (phmech has no joint
  stops): ``limits="warn"`` (default) warns once (AccuracyWarning) naming the limited joints,
  ``"ignore"`` is silent, ``"error"`` refuses them; ``<mimic>``: no coupling between pairs
  exists, ``mimic="error"`` (default) refuses, ``mimic="free"`` imports the joint as an
  independent one; ``<dynamics damping>``: a PD actuator with kp = 0 and kd = damping
  (``"<joint>.damping"``; ``joint_damping=False`` leaves it out), ``friction`` is not modelled
  (warned);
- ``flexible={"link": ...}``: that link becomes a flexible link (add_flexible_link) from its
  URDF frame's origin straight to the origin of its one child joint, its own section inertia
  replacing the URDF inertial. Its section axes: x along the link, y = normalised (e - (e.x)x)
  with e the URDF link frame's x axis (its z axis when the link runs along x).

Visual and collision meshes are not read (``phmech.plot`` draws links and bodies as it does for
any mechanism).
"""
from __future__ import annotations

import dataclasses
import os
import warnings
from typing import Optional

import numpy as np

from . import _urdfparse
from .actuators import PD
from ._errors import AccuracyWarning, ModelError, outside_stacklevel
from .laws import PiecewisePolynomial
from .mechanism import Mechanism
from .pairs import Fixed, Free, Planar, Prismatic, Revolute

__all__ = ["load_urdf", "URDFRobot", "URDFJoint", "inverse_dynamics", "forward_dynamics"]


@dataclasses.dataclass(frozen=True)
class URDFJoint:
    """A movable URDF joint as imported: its ``type`` (URDF), the ``parent`` and ``child`` link,
    its ``axis`` (joint frame), the number ``k`` of joint coordinates, its ``limit`` (lower,
    upper [rad or m], velocity, effort; None if absent) and ``mimic`` (joint, multiplier,
    offset; None if absent)."""
    name: str
    type: str
    parent: str
    child: str
    axis: tuple
    k: int
    limit: Optional[tuple] = None
    mimic: Optional[tuple] = None


@dataclasses.dataclass
class URDFRobot:
    """What :func:`load_urdf` built: the ``mechanism``; the robot's ``name``; its movable
    ``joints`` (name -> URDFJoint, in the tree's depth-first order, the order of
    :meth:`joint_coordinates` and of Pinocchio's joints; fixed joints at a flexible link's ends
    are there too, with k = 0); ``frames``: every link's URDF frame (name -> Frame, on the body,
    flexible link or ground that carries it); ``bodies``: body name -> the links merged into it;
    ``flexible``: link name -> FlexibleLink; ``replaced_mass``: link name -> (URDF mass, the
    flexible link's mass) [kg]."""
    mechanism: Mechanism
    name: str
    joints: dict
    frames: dict
    bodies: dict
    flexible: dict
    replaced_mass: dict

    @property
    def dof(self) -> int:
        """The number of joint coordinates of the movable joints."""
        return sum(j.k for j in self.joints.values())

    def joint_coordinates(self, result) -> np.ndarray:
        """The movable joints' coordinates x (nt, dof) of a SimulationResult, joint after joint
        in the order of ``joints`` [rad or m]."""
        return np.hstack([result.joint(n)["x"] for n in self.joints])

    def joint_rates(self, result) -> np.ndarray:
        """The movable joints' rates (nt, dof) of a SimulationResult, as joint_coordinates."""
        return np.hstack([result.joint(n)["xdot"] for n in self.joints])


def load_urdf(path, flexible: Optional[dict] = None, *, gravity=(0.0, 0.0, -9.81),
              base: str = "fixed", base_pose=None, q0: Optional[dict] = None,
              qdot0: Optional[dict] = None, driven: Optional[dict] = None,
              limits: str = "warn", mimic: str = "error", joint_damping: bool = True,
              mechanism: Optional[Mechanism] = None) -> URDFRobot:
    """A robot from the URDF file ``path`` as a phmech Mechanism (the module docstring of
    phmech.urdf gives the mapping and docs/user_guide.md, "Robots from URDF", an example).

    ``flexible``: link name -> its flexible replacement: a BeamProperties, a (Section,
    Material) pair, or a dict of ``properties=`` (or ``section=`` and ``material=``) and
    add_flexible_link's ``elements``, ``band``, ``frequency_tolerance``, ``fidelity``, ``mass``,
    ``modes``. The link runs straight from its frame's origin to its one child joint's origin
    and carries its own section inertia instead of the URDF inertial
    (``URDFRobot.replaced_mass`` gives both masses).

    ``gravity`` [m/s^2] (world axes; URDF's z is up). ``base``: ``"fixed"`` (the root link is
    the ground) or ``"floating"`` (the root link's group is a body on a Free pair
    ``"<root>.base"`` to the ground). ``base_pose``: the root link frame's world pose (4x4;
    default identity). ``q0``, ``qdot0``: initial joint coordinates [rad, m] and rates by joint
    name (a number, or k numbers for floating and planar joints); default 0. ``driven``: joint
    name -> time law of its coordinate (add_pair(driven=)). ``limits``: ``"warn"``, ``"ignore"``
    or ``"error"`` for joints with a ``<limit>`` (not enforced). ``mimic``: ``"error"`` or
    ``"free"`` (an independent joint). ``joint_damping``: the ``<dynamics damping>`` of each
    joint as a damper (PD with kp = 0) on its pair. ``mechanism``: add the robot to this
    Mechanism (its gravity is then left as it is) instead of a new one.

    Raises ModelError naming the element for a URDF phmech cannot build: a joint naming a
    missing link, a link with two parents or a loop, several root links, an unknown joint type,
    a moving link group without ``<inertial>`` or with zero mass, an inertia that is not
    positive definite, a mimic joint (with ``mimic="error"``)."""
    path = os.fspath(path) if isinstance(path, os.PathLike) else path
    for nm, v, ok in (("base", base, ("fixed", "floating")), ("limits", limits, ("warn", "ignore", "error")),
                      ("mimic", mimic, ("error", "free"))):
        if not isinstance(v, str) or v not in ok:
            raise ModelError(f"load_urdf: {nm} must be one of {', '.join(map(repr, ok))} (got {v!r})")
    robot = _urdfparse.parse(path)
    root, children, parent_of, links = _urdfparse.tree(robot, path)
    flexible = {} if flexible is None else flexible
    if not isinstance(flexible, dict):
        raise ModelError(f"load_urdf: flexible must be a dict link name -> properties (got "
                         f"{type(flexible).__name__})")
    for n in flexible:
        if n not in links:
            raise ModelError(f"load_urdf: flexible: {n!r} is not a link of the URDF")
        if n == root:
            raise ModelError(f"load_urdf: flexible: {n!r} is the root link (the base)")

    # the depth-first order of the joints, and each link's group: the top link of the group of
    # links welded to it by fixed joints, and its pose in the top link's frame
    order, top, T_in_top = [], {}, {}
    stack = [(root, None)]
    while stack:
        n, j = stack.pop()
        if j is None:
            top[n], T_in_top[n] = n, np.eye(4)
        else:
            order.append(j)
            T = _urdfparse.origin(j.origin, f"URDF {path!r}: joint {j.name!r}")
            if j.type == "fixed" and j.parent not in flexible and n not in flexible:
                top[n] = top[j.parent]
                T_in_top[n] = T_in_top[j.parent] @ T
            else:
                top[n] = n
                T_in_top[n] = np.eye(4)
        stack.extend((c.child, c) for c in reversed(children[n]))
    groups = {}
    for n in top:   # depth-first: a group's top link first
        groups.setdefault(top[n], []).append(n)

    joints = {}
    for j in order:
        if j.type == "fixed" and top[j.child] == top[j.parent]:
            continue
        ax = np.array([1.0, 0, 0]) if j.axis is None else np.array(j.axis, dtype=float)
        if ax.shape != (3,) or not np.all(np.isfinite(ax)) or not np.any(ax):
            raise ModelError(f"URDF {path!r}: joint {j.name!r}: <axis> must be a non-zero 3-vector "
                             f"(got {j.axis!r})")
        ax = ax / np.linalg.norm(ax)
        lim = None
        if j.limit is not None and j.type not in ("continuous", "fixed", "floating", "planar"):
            lim = tuple(None if v is None else _urdfparse.number(v, f"joint {j.name!r} <limit>")
                        for v in (j.limit.lower, j.limit.upper, j.limit.velocity, j.limit.effort))
        mim = None
        if j.mimic is not None:
            mim = (j.mimic.joint, _urdfparse.number(j.mimic.multiplier if j.mimic.multiplier is not None else 1.0,
                                         f"joint {j.name!r} <mimic>"),
                   _urdfparse.number(j.mimic.offset if j.mimic.offset is not None else 0.0, f"joint {j.name!r} <mimic>"))
        k = {"floating": 6, "planar": 3, "fixed": 0}.get(j.type, 1)
        joints[j.name] = URDFJoint(j.name, j.type, j.parent, j.child, tuple(ax), k, lim, mim)

    mimics = [jn for jn, jj in joints.items() if jj.mimic is not None]
    if mimics and mimic == "error":
        jj = joints[mimics[0]]
        raise ModelError(f"URDF {path!r}: joint {jj.name!r} mimics joint {jj.mimic[0]!r} (q = "
                         f"{jj.mimic[1]:g} q_{jj.mimic[0]} + {jj.mimic[2]:g}); phmech has no coupling "
                         f"between pairs: pass mimic='free' to import it (and "
                         f"{len(mimics) - 1} other mimic joints) as an independent joint")
    limited = [jn for jn, jj in joints.items() if jj.limit is not None and
               (jj.limit[0] is not None or jj.limit[1] is not None) and jj.limit[0] != jj.limit[1]]
    if limited and limits == "error":
        lo, hi = joints[limited[0]].limit[:2]
        raise ModelError(f"URDF {path!r}: joint {limited[0]!r} has position limits [{lo:g}, {hi:g}] "
                         f"(and {len(limited) - 1} more joints have limits), which phmech does not "
                         f"enforce; pass limits='warn' or 'ignore' to import them without")
    q0s = _urdfparse.per_joint(q0, joints, "q0")
    qd0s = _urdfparse.per_joint(qdot0, joints, "qdot0")
    drv = {} if driven is None else dict(driven)
    for n in drv:
        if n not in joints:
            raise ModelError(f"load_urdf: driven: {n!r} is not a movable joint of the URDF")

    # the bodies' mass properties (the root group's only with a floating base)
    mass_of = {}
    for t, members in groups.items():
        if t in flexible or (t == root and base == "fixed"):
            continue
        parts, missing = [], []
        for n in members:
            mi = _urdfparse.inertia(links[n], path)
            if mi is None:
                missing.append(n)
                continue
            T = T_in_top[n]
            R = T[:3, :3]
            parts.append((mi[0], R @ mi[1] + T[:3, 3], R @ mi[2] @ R.T))
        M, c, J = _urdfparse.merge(parts)
        what = f"URDF {path!r}: link {t!r}" + (f" (with the links welded to it: "
                                               f"{', '.join(map(repr, members[1:]))})" if len(members) > 1 else "")
        if M <= 0:
            lack = "has no <inertial>" if len(missing) == len(members) else "has zero mass"
            pj = parent_of.get(t)
            if pj is not None and pj.type == "fixed":   # welded to a flexible link
                raise ModelError(f"{what} {lack}, but it is a body of its own: joint {pj.name!r} "
                                 f"welds it to flexible link {pj.parent!r}; give it a mass and an "
                                 f"inertia")
            mover = f"joint {pj.name!r}" if pj is not None else "the floating base"
            raise ModelError(f"{what} {lack}, but it moves ({mover}): give it a mass and an "
                             f"inertia, or weld it to a massive link with a fixed joint")
        if np.min(np.linalg.eigvalsh(J)) <= 1e-12 * max(np.max(np.abs(J)), 1e-300):
            raise ModelError(f"{what}: its inertia about the centre of mass (eigenvalues "
                             f"{np.linalg.eigvalsh(J).tolist()} kg m^2) is not positive definite; a "
                             f"rigid body needs one")
        mass_of[t] = (M, c, J)

    m = Mechanism(gravity=gravity) if mechanism is None else mechanism
    if not isinstance(m, Mechanism):
        raise ModelError(f"load_urdf: mechanism must be a phmech.Mechanism or None (got "
                         f"{type(m).__name__})")
    H_base = np.eye(4) if base_pose is None else np.array(base_pose, dtype=float)
    frames = {}        # link -> Frame of its URDF frame
    body_frame = {}    # group top -> the Frame of the top link's URDF frame
    flex = {}
    replaced = {}
    if base == "fixed":
        body_frame[root] = m.ground.frame_at(H_base[:3, 3], H_base[:3, :3], name=root)
    else:
        M, c, J = mass_of[root]
        b = m.add_rigid_body(root, M, J, com=c, pose=H_base)
        m.add_pair(f"{root}.base", Free(), m.ground.frame_at(H_base[:3, 3], H_base[:3, :3]), b)
        body_frame[root] = b.frame
    for n in groups[root]:
        frames[n] = body_frame[root].frame_at(T_in_top[n][:3, 3], T_in_top[n][:3, :3], name=n)

    flex_start = {}    # flexible link -> (rotation R0 of its start in the link frame, its end frame)
    limited_info = []
    friction = []
    for j in order:
        if j.name not in joints:
            continue
        jj = joints[j.name]
        ptop = top[j.parent]
        T = T_in_top[j.parent] @ _urdfparse.origin(j.origin, f"URDF {path!r}: joint {j.name!r}")
        if j.parent in flexible:   # at the end of the flexible link, turned as the URDF says
            R0, d = flex_start[j.parent]
            jf = flex[j.parent].end.frame_at((0, 0, 0), R0.T @ T[:3, :3], name=f"{j.name}.parent")
        else:
            jf = body_frame[ptop].frame_at(T[:3, 3], T[:3, :3], name=f"{j.name}.parent")
        x = q0s.get(j.name, np.zeros(jj.k))
        ax = np.array(jj.axis)
        if j.child in flexible:
            props, kw = _urdfparse.beam_properties(flexible[j.child], j.child)
            kids = children[j.child]
            if len(kids) != 1:
                raise ModelError(f"load_urdf: flexible link {j.child!r} has {len(kids)} child joints; "
                                 f"a flexible link runs from its frame to the origin of its one child "
                                 f"joint (weld other links to that child)")
            d = _urdfparse.origin(kids[0].origin, f"URDF {path!r}: joint {kids[0].name!r}")[:3, 3]
            L = float(np.linalg.norm(d))
            if L <= 0:
                raise ModelError(f"load_urdf: flexible link {j.child!r}: its child joint "
                                 f"{kids[0].name!r} is at its origin (length 0)")
            R0 = _urdfparse.beam_rotation(d)
            Hj = m.world_pose(jf) @ _urdfparse.joint_transform(j.type, ax, x)
            start = np.eye(4)
            start[:3, :3] = R0
            lk = m.add_flexible_link(j.child, L, props, pose=Hj @ start, **kw)
            flex[j.child], flex_start[j.child] = lk, (R0, d)
            child_frame = lk.start.frame_at((0, 0, 0), R0.T, name=j.child)
            frames[j.child] = child_frame
            um = _urdfparse.inertia(links[j.child], path)
            rho_a = float(props.inertia[3, 3])
            replaced[j.child] = (0.0 if um is None else um[0], rho_a * L)
        else:
            M, c, J = mass_of[j.child]
            b = m.add_rigid_body(j.child, M, J, com=c)
            child_frame = b.frame
            body_frame[j.child] = b.frame
            for n in groups[j.child]:
                frames[n] = b.frame.frame_at(T_in_top[n][:3, 3], T_in_top[n][:3, :3], name=n)
        pair = {"revolute": Revolute, "continuous": Revolute, "prismatic": Prismatic}.get(j.type)
        if pair is not None:
            pr = pair(axis=ax)
        elif j.type == "planar":
            pr = Planar(normal=ax)
        elif j.type == "floating":
            pr = Free()
        else:   # a fixed joint onto or off a flexible link
            pr = Fixed()
        kw = {}
        if jj.k:
            kw = dict(x0=x, xdot0=qd0s.get(j.name, np.zeros(jj.k)))
        if j.name in drv:
            kw = dict(driven=drv[j.name])
        m.add_pair(j.name, pr, jf, child_frame, **kw)
        if jj.limit is not None and j.name in limited:
            limited_info.append(f"{j.name} [{jj.limit[0]:g}, {jj.limit[1]:g}]")
        dyn = j.dynamics
        if dyn is not None and jj.k:
            damping = 0.0 if dyn.damping is None else _urdfparse.number(dyn.damping, f"joint {j.name!r} <dynamics damping>")
            fr = 0.0 if dyn.friction is None else _urdfparse.number(dyn.friction, f"joint {j.name!r} <dynamics friction>")
            if damping < 0 or fr < 0:
                raise ModelError(f"URDF {path!r}: joint {j.name!r}: <dynamics> damping and friction "
                                 f"must be >= 0")
            if damping > 0 and joint_damping:
                m.add_actuator(f"{j.name}.damping", j.name, PD(kp=0.0, kd=damping))
            if fr > 0:
                friction.append(f"{j.name} ({fr:g})")
    if limited_info and limits == "warn":
        warnings.warn(f"URDF {path!r}: {len(limited_info)} joints have position limits phmech does "
                      f"not enforce (no joint stops; velocity and effort limits neither): "
                      f"{', '.join(limited_info)}; check result.joint(name)['x'] against them, or "
                      f"pass limits='ignore' to silence this", AccuracyWarning,
                      stacklevel=outside_stacklevel())
    if friction:
        warnings.warn(f"URDF {path!r}: the <dynamics friction> of {len(friction)} joints is not "
                      f"modelled (Coulomb friction; {', '.join(friction)} N m or N): the joints "
                      f"move without it; add a PD damper (add_actuator) if a viscous substitute "
                      f"will do", AccuracyWarning, stacklevel=outside_stacklevel())
    bodies = {t: tuple(groups[t]) for t in groups if t in body_frame and not (t == root and base == "fixed")}
    return URDFRobot(m, robot.name, joints, frames, bodies, flex, replaced)


def _driven_robot(path, q, qdot, qddot, kwargs: dict) -> tuple:
    """(URDFRobot with every movable joint driven by q + qdot t + qddot t^2 / 2, its joint names);
    ModelError for a joint that is not one drivable coordinate."""

    for k in ("driven", "q0", "qdot0"):
        if k in kwargs:
            raise ModelError(f"inverse_dynamics: {k}= is set from q, qdot, qddot")
    # the joint names first (a robot without drives), then the one with them
    names = list(load_urdf(path, **{**kwargs, "limits": "ignore"}).joints)
    q, qdot, qddot = (np.asarray(v, dtype=float).reshape(-1) for v in (q, qdot, qddot))
    if not q.shape == qdot.shape == qddot.shape == (len(names),):
        raise ModelError(f"inverse_dynamics: q, qdot and qddot need {len(names)} entries each "
                         f"(the movable joints {names})")
    laws = {n: PiecewisePolynomial([0.0, 1.0], [[qddot[i] / 2, qdot[i], q[i]]])
            for i, n in enumerate(names)}
    robot = load_urdf(path, driven=laws, **kwargs)
    bad = [n for n, j in robot.joints.items() if j.k != 1]
    if bad:
        raise ModelError(f"inverse_dynamics: joints {bad} have several coordinates; only robots "
                         f"of revolute, continuous and prismatic joints")
    return robot, names


def inverse_dynamics(path, q, qdot, qddot, **kwargs) -> np.ndarray:
    """The joint efforts tau [N m or N] (one per movable joint, in ``URDFRobot.joints`` order)
    that move the URDF robot at ``path`` with accelerations ``qddot`` at joint coordinates ``q``
    and rates ``qdot`` (revolute, continuous and prismatic joints, fixed base): phmech's own
    dynamics, read from the DAE's consistent initial values -- every joint driven by the law
    q + qdot t + qddot t^2 / 2, the drives' multipliers at t = 0 solved at the acceleration
    level (csrc/dae/initial.c). ``kwargs`` go to :func:`load_urdf` (gravity, mimic,
    joint_damping, limits, flexible is refused)."""
    if kwargs.get("flexible"):
        raise ModelError("inverse_dynamics: a robot with flexible links has no joint-space "
                         "dynamics of its joints alone")
    robot, names = _driven_robot(path, q, qdot, qddot, kwargs)
    # only the consistent initial values are needed: stop at the first output, t = 0
    r = robot.mechanism.simulate(1e-6, 1e-6, integrator="ida", rtol=1e-10, callback=lambda t, i: True)
    return np.array([r.joint(n)["lambda"][0, -1] for n in names])


def forward_dynamics(path, q, qdot, tau, **kwargs) -> np.ndarray:
    """The joint accelerations qddot (one per movable joint) of the URDF robot at ``path`` at
    joint coordinates ``q`` and rates ``qdot`` under joint efforts ``tau``: phmech's dynamics
    solved for them, through :func:`inverse_dynamics`, which is affine in qddot: its columns at
    qddot = e_i less its value at 0 are the joint-space mass matrix M, qddot = M^-1 (tau - ID(0)),
    then one correction qddot += M^-1 (tau - ID(qddot)) for round-off (n + 2 evaluations for n
    joints). ``kwargs`` as inverse_dynamics."""
    tau = np.asarray(tau, dtype=float).reshape(-1)
    n = tau.size
    z = np.zeros(n)
    b = inverse_dynamics(path, q, qdot, z, **kwargs)
    M = np.column_stack([inverse_dynamics(path, q, qdot, e, **kwargs) - b for e in np.eye(n)])
    a = np.linalg.solve(M, tau - b)
    return a + np.linalg.solve(M, tau - inverse_dynamics(path, q, qdot, a, **kwargs))

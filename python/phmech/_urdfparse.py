"""Reading a URDF file for phmech.urdf.load_urdf: the file parsed (yourdfpy), the kinematic
tree, numbers and origins, inertias merged onto the bodies welded together, joint frames, and
the beam properties and per-joint options of the links made flexible. No phmech model is built
here. Units: SI (URDF's own: m, kg, kg m^2, rad); poses 4x4."""
from __future__ import annotations

import os

import numpy as np

from . import se3
from ._errors import ModelError
from .pairs import Free, Planar, Prismatic, Revolute
from .section import BeamProperties, Material, Section

#: URDF joint types and the phmech pair each becomes (None: welded, no pair)
JOINT_TYPES = {"revolute": Revolute, "continuous": Revolute, "prismatic": Prismatic,
               "fixed": None, "floating": Free, "planar": Planar}


def parse(path):
    """The yourdfpy Robot of the URDF file ``path`` (no meshes, no scene graph)."""
    try:
        import yourdfpy
    except ImportError:   # a dependency of phmech (pyproject.toml): only a broken install lacks it
        raise ModelError("load_urdf needs the package 'yourdfpy' (pip install yourdfpy)") from None
    if not isinstance(path, (str, os.PathLike)):
        raise ModelError(f"load_urdf: path must be a file name (got {type(path).__name__})")
    if not os.path.isfile(path):
        raise ModelError(f"load_urdf: no such file {os.fspath(path)!r}")
    from lxml import etree   # yourdfpy's XML library
    try:   # strictly: yourdfpy falls back to a recovering parser that accepts a truncated file
        etree.parse(os.fspath(path))
    except etree.XMLSyntaxError as e:
        raise ModelError(f"URDF {os.fspath(path)!r} cannot be parsed: {e}") from None
    try:
        u = yourdfpy.URDF.load(os.fspath(path), build_scene_graph=False, load_meshes=False,
                               build_collision_scene_graph=False, load_collision_meshes=False)
    except Exception as e:   # lxml's syntax errors, yourdfpy's own ValueErrors
        raise ModelError(f"URDF {os.fspath(path)!r} cannot be parsed: {type(e).__name__}: {e}") from None
    return u.robot

def number(v, what: str) -> float:
    try:
        x = float(v)
    except (TypeError, ValueError):
        raise ModelError(f"{what}: expected a number (got {v!r})") from None
    if not np.isfinite(x):
        raise ModelError(f"{what}: expected a finite number (got {v!r})")
    return x

def origin(T, what: str) -> np.ndarray:
    T = np.eye(4) if T is None else np.array(T, dtype=float)
    if T.shape != (4, 4) or not np.all(np.isfinite(T)):
        raise ModelError(f"{what}: <origin> is not a finite pose")
    return T

def tree(robot, path) -> tuple:
    """(root link, {link: [joints whose parent it is]}, {link: joint above it}) of the URDF,
    checked: unique names, joints between existing links, one parent per link, one root, no
    loop, known joint types."""
    links = {}
    for lk in robot.links:
        if lk.name in links:
            raise ModelError(f"URDF {path!r}: link {lk.name!r} is defined twice")
        links[lk.name] = lk
    if not links:
        raise ModelError(f"URDF {path!r} has no link")
    parent_of, children, names = {}, {n: [] for n in links}, set()
    for j in robot.joints:
        if j.name in names:
            raise ModelError(f"URDF {path!r}: joint {j.name!r} is defined twice")
        names.add(j.name)
        if j.type not in JOINT_TYPES:
            raise ModelError(f"URDF {path!r}: joint {j.name!r} has unknown type {j.type!r} "
                             f"(URDF types: {', '.join(JOINT_TYPES)})")
        for role, ln in (("parent", j.parent), ("child", j.child)):
            if ln not in links:
                raise ModelError(f"URDF {path!r}: joint {j.name!r} names {role} link {ln!r}, which "
                                 f"is not a link of the file")
        if j.child in parent_of:
            raise ModelError(f"URDF {path!r}: link {j.child!r} is the child of two joints, "
                             f"{parent_of[j.child].name!r} and {j.name!r}: a closed loop, which "
                             f"URDF (a tree) cannot describe; build the loop-closing pair with "
                             f"Mechanism.add_pair after the import")
        parent_of[j.child] = j
        children[j.parent].append(j)
    roots = [n for n in links if n not in parent_of]
    if len(roots) != 1:
        if not roots:
            raise ModelError(f"URDF {path!r}: every link is some joint's child: the joints form a "
                             f"closed loop (no root link)")
        raise ModelError(f"URDF {path!r}: {len(roots)} root links ({', '.join(map(repr, roots))}): "
                         f"a robot has one; join them by a joint")
    seen, stack = set(), [roots[0]]
    while stack:
        n = stack.pop()
        seen.add(n)
        stack.extend(j.child for j in children[n])
    lost = [n for n in links if n not in seen]
    if lost:
        j = parent_of[lost[0]]
        raise ModelError(f"URDF {path!r}: links {', '.join(map(repr, lost))} are not reached from "
                         f"the root {roots[0]!r}: joint {j.name!r} closes a loop")
    return roots[0], children, parent_of, links

def inertia(lk, path) -> tuple:
    """(mass [kg], com (3,), inertia about the com (3, 3)) of link ``lk`` in its URDF frame,
    or None without <inertial>."""
    ine = lk.inertial
    if ine is None:
        return None
    what = f"URDF {path!r}: link {lk.name!r} <inertial>"
    m = number(ine.mass if ine.mass is not None else 0.0, f"{what} mass")
    if m < 0:
        raise ModelError(f"{what}: negative mass {m:g} kg")
    I = np.zeros((3, 3)) if ine.inertia is None else np.array(ine.inertia, dtype=float)
    if I.shape != (3, 3) or not np.all(np.isfinite(I)):
        raise ModelError(f"{what}: <inertia> is not 6 finite numbers")
    T = origin(ine.origin, what)
    R = T[:3, :3]
    return m, T[:3, 3].copy(), R @ I @ R.T

def merge(parts) -> tuple:
    """(mass, com, inertia about com) of parts (mass, com, inertia about its com), all in one
    frame (parallel-axis theorem)."""
    M = sum(p[0] for p in parts)
    if M <= 0:
        return 0.0, np.zeros(3), np.zeros((3, 3))
    c = sum(p[0] * p[1] for p in parts) / M
    J = np.zeros((3, 3))
    for m, ci, Ii in parts:
        d = ci - c
        J += Ii + m * (d @ d * np.eye(3) - np.outer(d, d))
    return M, c, 0.5 * (J + J.T)

def joint_transform(jt: str, axis: np.ndarray, x: np.ndarray) -> np.ndarray:
    """The URDF joint motion (child frame in the joint frame) at coordinates x."""
    if jt in ("revolute", "continuous"):
        return se3.rotation(axis, float(x[0]))
    if jt == "prismatic":
        return se3.translation(axis * float(x[0]))
    if jt == "fixed":
        return np.eye(4)
    if jt == "floating":
        T = np.eye(4)
        T[:3, :3] = se3.exp(np.concatenate([x[:3], np.zeros(3)]))[:3, :3]
        T[:3, 3] = x[3:6]
        return T
    # planar: angle about the normal, p_x, p_y in the frame whose z is the normal
    Q = np.eye(4)
    Q[:3, :3] = frame_with_z(axis)
    return Q @ se3.translation([x[1], x[2], 0.0]) @ se3.rotation("z", float(x[0])) @ se3.inverse(Q)

def frame_with_z(z: np.ndarray) -> np.ndarray:
    """The rotation whose z is the unit vector z that phmech's pairs use for an axis (so that a
    planar joint's p_x, p_y here are the pair's): phmech.pairs' rule."""
    h = np.array([1.0, 0, 0]) if abs(z[0]) < 0.9 else np.array([0, 1.0, 0])
    xx = h - z * (h @ z)
    xx /= np.linalg.norm(xx)
    return np.column_stack([xx, np.cross(z, xx), z])

def beam_rotation(d: np.ndarray) -> np.ndarray:
    """The start-frame rotation of a flexible link along d (link-frame coordinates): x along d,
    y the link frame's x (z when d runs along x) made normal to it."""
    x = d / np.linalg.norm(d)
    e = np.array([1.0, 0, 0]) if abs(x[0]) < 0.9 else np.array([0, 0, 1.0])
    y = e - x * (e @ x)
    y /= np.linalg.norm(y)
    return np.column_stack([x, y, np.cross(x, y)])

def beam_properties(spec, name: str) -> tuple:
    """(BeamProperties, keyword arguments of add_flexible_link) from a ``flexible=`` entry."""
    what = f"load_urdf: flexible[{name!r}]"
    if isinstance(spec, BeamProperties):
        return spec, {}
    if isinstance(spec, tuple) and len(spec) == 2 and isinstance(spec[0], Section) \
            and isinstance(spec[1], Material):
        return BeamProperties.from_material(*spec), {}
    if isinstance(spec, dict):
        kw = dict(spec)
        props = kw.pop("properties", None)
        sec, mat = kw.pop("section", None), kw.pop("material", None)
        if props is None:
            if not isinstance(sec, Section) or not isinstance(mat, Material):
                raise ModelError(f"{what}: a dict needs properties= (BeamProperties) or section= "
                                 f"(Section) and material= (Material)")
            props = BeamProperties.from_material(sec, mat)
        bad = set(kw) - {"elements", "band", "frequency_tolerance", "fidelity", "mass", "modes"}
        if bad:
            raise ModelError(f"{what}: unknown keys {sorted(bad)} (add_flexible_link's elements, "
                             f"band, frequency_tolerance, fidelity, mass, modes)")
        return props, kw
    raise ModelError(f"{what}: expected BeamProperties, (Section, Material) or a dict "
                     f"(got {type(spec).__name__})")

def per_joint(values, joints: dict, what: str) -> dict:
    """{joint: array (k,)} from a dict joint -> number or sequence (unknown names refused)."""
    if values is None:
        return {}
    if not isinstance(values, dict):
        raise ModelError(f"load_urdf: {what} must be a dict joint name -> value (got "
                         f"{type(values).__name__})")
    out = {}
    for n, v in values.items():
        if n not in joints:
            raise ModelError(f"load_urdf: {what}: {n!r} is not a movable joint of the URDF "
                             f"(movable joints: {', '.join(map(repr, joints)) or 'none'})")
        x = np.atleast_1d(np.asarray(v, dtype=float))
        if x.shape != (joints[n].k,) or not np.all(np.isfinite(x)):
            raise ModelError(f"load_urdf: {what}[{n!r}]: expected {joints[n].k} finite number(s) "
                             f"(got {v!r})")
        out[n] = x
    return out

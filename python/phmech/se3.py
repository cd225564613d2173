"""SE(3) algebra: rotations, poses, twists and the maps between them.

Conventions (docs/method.md section 3):

* a twist is ``x = (omega, v)`` [rad/s, m/s] (or, as exponential coordinates, [rad, m]),
  a wrench is ``(tau, f)`` [N m, N]: angular part first;
* a pose is the 4x4 homogeneous matrix ``H = [[R, p], [0, 1]]`` (``p`` in m); the body-frame
  twist of a moving pose is ``H^-1 dH/dt = hat(x)``;
* ``ad_x = [[hat(omega), 0], [hat(v), hat(omega)]]``, ``Ad_H = [[R, 0], [hat(p) R, R]]``;
  wrenches transform with the transposes ``ad_dual = ad^T``, ``Ad_dual = Ad^T``;
* ``dexp_x = sum_k ad_x^k / (k+1)!``; if ``H = H0 exp(hat x)`` then ``H^-1 dH/dt = dexp_{-x} dx/dt``;
* quaternions are scalar first, ``q = (w, x, y, z)`` (scipy's ``Rotation.as_quat`` is scalar last).

Every function accepts one element or a stack of them (leading dimensions ``...``) and returns
C-ordered float64 arrays. Inputs must be real, finite numbers of the stated trailing shape;
anything else raises ``ValueError`` (``phmech.ModelError``, a ValueError, from the C binding).
Results are finite: an input beyond a function's range in double precision (the exponential of a
1e300 rad rotation, a product of poses with 1e200 entries) raises ModelError instead of returning
NaN or inf. The numerics are in the C core (``csrc/util/se3.c``, quaternions ``csrc/util/quat.c``): exp/log use series near angle 0 and
a symmetric-part axis near angle pi.
"""
from __future__ import annotations

from typing import Union

import numpy as np
from numpy.typing import ArrayLike, NDArray

from . import _core

__all__ = ["hat", "vee", "exp", "log", "Ad", "Ad_dual", "ad", "ad_dual", "dexp", "dexp_inv",
           "compose", "inverse", "quat_to_rot", "rot_to_quat", "translation", "rotation", "pose"]

Array = NDArray[np.float64]


def _shape_of(a: ArrayLike, name: str) -> tuple:
    if isinstance(a, (str, bytes)) or a is None:
        raise ValueError(f"{name}: expected an array of real numbers, got {type(a).__name__}")
    try:
        return np.shape(a)
    except ValueError as e:  # ragged nested sequences
        raise ValueError(f"{name}: not a regular array of numbers ({e})") from None


def _vec_kind(x: ArrayLike, name: str) -> int:
    s = _shape_of(x, name)
    if len(s) >= 1 and s[-1] in (3, 6):
        return s[-1]
    raise ValueError(f"{name}: expected shape (..., 3) or (..., 6), got {s}")


def _mat_kind(X: ArrayLike, name: str) -> int:
    s = _shape_of(X, name)
    if len(s) >= 2 and s[-2:] in ((3, 3), (4, 4)):
        return s[-1]
    raise ValueError(f"{name}: expected shape (..., 3, 3) or (..., 4, 4), got {s}")


def hat(x: ArrayLike) -> Array:
    """Matrix form of a vector.

    ``x`` of shape (..., 3): the skew matrix ``hat(w)`` with ``hat(w) a = w x a``, (..., 3, 3).
    ``x`` of shape (..., 6): the twist ``(omega, v)`` as ``[[hat(omega), v], [0, 0]]``, (..., 4, 4).
    """
    return _core.so3_hat(x) if _vec_kind(x, "hat") == 3 else _core.se3_hat(x)


def vee(X: ArrayLike) -> Array:
    """Inverse of :func:`hat`: (..., 3, 3) -> (..., 3) (skew part), (..., 4, 4) -> (..., 6)."""
    return _core.so3_vee(X) if _mat_kind(X, "vee") == 3 else _core.se3_vee(X)


def exp(x: ArrayLike) -> Array:
    """Exponential map.

    ``x`` (..., 3), a rotation vector [rad] -> rotation matrix (..., 3, 3) (Rodrigues).
    ``x`` (..., 6), twist coordinates ``(omega [rad], v [m])`` -> pose ``exp(hat x)`` (..., 4, 4).
    """
    return _core.so3_exp(x) if _vec_kind(x, "exp") == 3 else _core.se3_exp(x)


def log(X: ArrayLike) -> Array:
    """Logarithm, the inverse of :func:`exp` with rotation angle ``|omega|`` in [0, pi].

    ``X`` (..., 3, 3), a rotation matrix -> rotation vector (..., 3) [rad].
    ``X`` (..., 4, 4), a pose -> twist coordinates ``(omega [rad], v [m])`` (..., 6).
    At angle exactly pi the sign of ``omega`` is arbitrary (both give the same rotation).
    """
    return _core.so3_log(X) if _mat_kind(X, "log") == 3 else _core.se3_log(X)


def Ad(H: ArrayLike) -> Array:
    """Adjoint of a pose (..., 4, 4) -> (..., 6, 6): ``[[R, 0], [hat(p) R, R]]`` (maps twists)."""
    return _core.se3_Ad(H)


def Ad_dual(H: ArrayLike) -> Array:
    """``Ad_H^T`` (..., 6, 6), which maps wrenches ``(tau, f)`` the dual way."""
    return _core.se3_Ad_dual(H)


def ad(x: ArrayLike) -> Array:
    """Adjoint of a twist (..., 6) -> (..., 6, 6): ``[[hat(omega), 0], [hat(v), hat(omega)]]``.

    ``ad_x y`` is the Lie bracket: ``hat(ad_x y) = hat(x) hat(y) - hat(y) hat(x)``.
    """
    return _core.se3_ad(x)


def ad_dual(x: ArrayLike) -> Array:
    """``ad_x^T`` (..., 6, 6); a body's momentum m obeys ``dm/dt = ad_dual(t) m + w``."""
    return _core.se3_ad_dual(x)


def dexp(x: ArrayLike) -> Array:
    """Derivative of the exponential, ``sum_k ad_x^k/(k+1)!``.

    ``x`` (..., 6) -> (..., 6, 6), ``[[A, 0], [B, A]]``; if ``H = H0 exp(hat x)`` then the
    body twist is ``H^-1 dH/dt = dexp(-x) dx/dt``.
    ``x`` (..., 3) -> the SO(3) left Jacobian ``A = sum_k hat(w)^k/(k+1)!`` (..., 3, 3).
    """
    return _core.so3_jac(x) if _vec_kind(x, "dexp") == 3 else _core.se3_dexp(x)


def dexp_inv(x: ArrayLike) -> Array:
    """Inverse of :func:`dexp` (6-vectors) or of the SO(3) left Jacobian (3-vectors).

    Singular at rotation angles ``|omega|`` = 2 pi k, k >= 1; accurate for ``|omega|`` <= pi.
    """
    return _core.so3_jac_inv(x) if _vec_kind(x, "dexp_inv") == 3 else _core.se3_dexp_inv(x)


def compose(A: ArrayLike, B: ArrayLike) -> Array:
    """Pose product ``A B`` of (..., 4, 4) stacks, broadcasting their leading dimensions."""
    sa, sb = _shape_of(A, "compose: A"), _shape_of(B, "compose: B")
    if len(sa) < 2 or sa[-2:] != (4, 4):
        raise ValueError(f"compose: A: expected shape (..., 4, 4), got {sa}")
    if len(sb) < 2 or sb[-2:] != (4, 4):
        raise ValueError(f"compose: B: expected shape (..., 4, 4), got {sb}")
    if sa[:-2] == sb[:-2]:
        return _core.se3_compose(A, B)
    try:
        lead = np.broadcast_shapes(sa[:-2], sb[:-2])
    except ValueError:
        raise ValueError(f"compose: stacks of shapes {sa} and {sb} do not broadcast") from None
    # dtype is checked here, finiteness by the C binding.
    a = np.broadcast_to(_as_real(A, "compose: A"), lead + (4, 4))
    b = np.broadcast_to(_as_real(B, "compose: B"), lead + (4, 4))
    return _core.se3_compose(np.ascontiguousarray(a), np.ascontiguousarray(b))


def _as_real(a: ArrayLike, name: str) -> Array:
    arr = np.asarray(a)
    if arr.dtype.kind not in "biuf":
        raise ValueError(f"{name}: expected an array of real numbers, got dtype {arr.dtype}")
    return arr.astype(np.float64, copy=False)


def inverse(H: ArrayLike) -> Array:
    """Inverse pose (..., 4, 4): ``[[R^T, -R^T p], [0, 1]]``."""
    return _core.se3_inverse(H)


def quat_to_rot(q: ArrayLike) -> Array:
    """Rotation matrix (..., 3, 3) of a quaternion ``(w, x, y, z)`` (scalar first), (..., 4).

    ``q`` is normalized first; a zero quaternion raises ValueError.
    """
    return _core.quat_to_rot(q)


def rot_to_quat(R: ArrayLike) -> Array:
    """Unit quaternion ``(w, x, y, z)`` (scalar first, ``w >= 0``) of rotations (..., 3, 3).

    Shepperd's method. (scipy's ``Rotation.from_quat`` expects scalar last: use ``q[..., [1, 2, 3, 0]]``.)
    """
    return _core.quat_from_rot(R)


def translation(p: ArrayLike) -> Array:
    """Pose (..., 4, 4) of a pure translation by ``p`` [m], (..., 3)."""
    return _core.se3_exp(np.concatenate(np.broadcast_arrays(np.zeros(3), _vec3(p, "translation: p")),
                                        axis=-1))


def _vec3(p: ArrayLike, name: str) -> Array:
    s = _shape_of(p, name)
    if len(s) < 1 or s[-1] != 3:
        raise ValueError(f"{name}: expected shape (..., 3), got {s}")
    arr = _as_real(p, name)
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name}: contains a non-finite value (NaN or inf)")
    return arr


_AXES = {"x": (1.0, 0.0, 0.0), "y": (0.0, 1.0, 0.0), "z": (0.0, 0.0, 1.0)}


def rotation(axis: Union[str, ArrayLike], angle: ArrayLike) -> Array:
    """Pose (..., 4, 4) of a rotation by ``angle`` [rad] (right hand) about ``axis``.

    ``axis`` is ``'x'``, ``'y'``, ``'z'`` or a non-zero 3-vector (normalized here; a stack (..., 3)
    is allowed); ``angle`` is a scalar or an array broadcasting against the axis stack.
    """
    if isinstance(axis, str):
        if axis.lower() not in _AXES:
            raise ValueError(f"rotation: axis must be 'x', 'y', 'z' or a 3-vector, got {axis!r}")
        n = np.array(_AXES[axis.lower()])
    else:
        n = _vec3(axis, "rotation: axis")
        # scaled by the largest entry first: the norm of a (1e300, 1e300, 0) axis overflows to
        # inf and the axis would become 0 (the identity, silently)
        big = np.max(np.abs(n), axis=-1, keepdims=True)
        if np.any(big == 0.0):
            raise ValueError("rotation: axis has zero length")
        n = n / big
        n = n / np.linalg.norm(n, axis=-1, keepdims=True)
    if isinstance(angle, (str, bytes)) or angle is None:
        raise ValueError(f"rotation: angle: expected real numbers, got {type(angle).__name__}")
    th = _as_real(angle, "rotation: angle")
    if not np.all(np.isfinite(th)):
        raise ValueError("rotation: angle: contains a non-finite value (NaN or inf)")
    w = n * th[..., None]
    x = np.concatenate([w, np.zeros_like(w)], axis=-1)
    return _core.se3_exp(x)


def pose(R: ArrayLike, p: ArrayLike) -> Array:
    """Pose (..., 4, 4) ``[[R, p], [0, 1]]`` from rotations (..., 3, 3) and positions [m] (..., 3).

    Leading dimensions broadcast. ``R`` is not re-orthonormalized.
    """
    sR = _shape_of(R, "pose: R")
    if len(sR) < 2 or sR[-2:] != (3, 3):
        raise ValueError(f"pose: R: expected shape (..., 3, 3), got {sR}")
    Ra = _as_real(R, "pose: R")
    pa = _vec3(p, "pose: p")
    if not np.all(np.isfinite(Ra)):
        raise ValueError("pose: R: contains a non-finite value (NaN or inf)")
    try:
        lead = np.broadcast_shapes(Ra.shape[:-2], pa.shape[:-1])
    except ValueError:
        raise ValueError(f"pose: R {Ra.shape} and p {pa.shape} do not broadcast") from None
    H = np.zeros(lead + (4, 4))
    H[..., :3, :3] = Ra
    H[..., :3, 3] = pa
    H[..., 3, 3] = 1.0
    return H

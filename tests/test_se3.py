"""phmech.se3 against independent references: scipy.linalg.expm/logm, scipy Rotation,
central finite differences, power series and group identities, on thousands of random
elements including rotation angles within 1e-8 of 0 and of pi. Worst errors are printed at
the end of the session (run with -s)."""
import numpy as np
import pytest
from scipy.linalg import expm, logm
from scipy.spatial.transform import Rotation

import phmech
from phmech import _core
from phmech import se3

WORST: dict = {}


def record(name: str, err: float, tol: float) -> None:
    WORST[name] = max(WORST.get(name, 0.0), float(err))
    assert err <= tol, f"{name}: error {err:.3e} > tolerance {tol:.1e}"


@pytest.fixture(scope="module", autouse=True)
def report_worst():
    yield
    print("\nphmech.se3 worst identity errors:")
    for k, v in WORST.items():
        print(f"  {k:<55s} {v:.3e}")


def rand_angles(rng, n):
    """n angles in [0, pi]: a quarter uniform, a quarter within 1e-8 of 0 (some exactly 0),
    a quarter within 1e-8 of pi, a quarter uniform again."""
    th = rng.uniform(0, np.pi, n)
    q = n // 4
    th[:q] = 1e-8 * rng.uniform(0, 1, q)
    th[:q:10] = 0.0
    th[q:2 * q] = np.pi - 1e-8 * rng.uniform(1e-3, 1, q)
    return th


def rand_axes(rng, n):
    a = rng.normal(size=(n, 3))
    return a / np.linalg.norm(a, axis=1, keepdims=True)


def rand_twists(rng, n, vscale=2.0):
    w = rand_axes(rng, n) * rand_angles(rng, n)[:, None]
    return np.concatenate([w, vscale * rng.normal(size=(n, 3))], axis=1)


def ref_poses(rng, n, exact_pi=False):
    """Poses built by scipy (Rotation.from_rotvec), independent of phmech."""
    w = rand_axes(rng, n) * rand_angles(rng, n)[:, None]
    if exact_pi:
        w[::7] = np.pi * rand_axes(rng, len(w[::7]))
    H = np.zeros((n, 4, 4))
    H[:, :3, :3] = Rotation.from_rotvec(w).as_matrix()
    H[:, :3, 3] = 3.0 * rng.normal(size=(n, 3))
    H[:, 3, 3] = 1.0
    return H


def hat_ref(x):
    """Independent hat: 3-vectors -> skew, 6-vectors -> 4x4."""
    x = np.asarray(x, float)
    W = np.zeros(x.shape[:-1] + (3, 3))
    W[..., 0, 1], W[..., 0, 2], W[..., 1, 2] = -x[..., 2], x[..., 1], -x[..., 0]
    W[..., 1, 0], W[..., 2, 0], W[..., 2, 1] = x[..., 2], -x[..., 1], x[..., 0]
    if x.shape[-1] == 3:
        return W
    X = np.zeros(x.shape[:-1] + (4, 4))
    X[..., :3, :3] = W
    X[..., :3, 3] = x[..., 3:6]
    return X


# ------------------------------------------------------------------ exp / log


def test_exp_log_roundtrip_SE3():
    rng = np.random.default_rng(1)
    H = ref_poses(rng, 8000, exact_pi=True)
    H2 = se3.exp(se3.log(H))
    record("SE3 exp(log H) = H", np.abs(H2 - H).max(), 1e-12)
    x = se3.log(H)
    assert np.all(np.linalg.norm(x[:, :3], axis=1) <= np.pi + 1e-15)


def test_exp_log_roundtrip_SO3():
    rng = np.random.default_rng(2)
    R = ref_poses(rng, 8000, exact_pi=True)[:, :3, :3]
    record("SO3 exp(log R) = R", np.abs(se3.exp(se3.log(R)) - R).max(), 1e-12)


def test_log_exp_roundtrip():
    rng = np.random.default_rng(3)
    x = rand_twists(rng, 8000)  # |omega| < pi strictly (>= 1e-11 below pi)
    y = se3.log(se3.exp(x))
    rel = np.abs(y - x).max(axis=1) / (1.0 + np.abs(x[:, 3:]).max(axis=1))
    record("SE3 log(exp x) = x (relative to 1+|v|)", rel.max(), 1e-12)
    record("SO3 log(exp w) = w", np.abs(se3.log(se3.exp(x[:, :3])) - x[:, :3]).max(), 1e-12)


def test_exp_log_vs_scipy_expm_logm():
    rng = np.random.default_rng(4)
    x = rand_twists(rng, 300)
    H = se3.exp(x)
    e = max(np.abs(H[i] - expm(hat_ref(x[i]))).max() for i in range(len(x)))
    record("SE3 exp vs scipy expm", e, 1e-13)
    R = se3.exp(x[:, :3])
    e = max(np.abs(R[i] - expm(hat_ref(x[i, :3]))).max() for i in range(len(x)))
    record("SO3 exp vs scipy expm", e, 1e-13)
    # logm: away from pi, where the principal logarithm is unique and logm is well conditioned
    th = np.linalg.norm(x[:, :3], axis=1)
    sel = th < 3.0
    L = np.array([logm(H[i]).real for i in np.flatnonzero(sel)])
    e = np.abs(hat_ref(se3.log(H[sel])) - L).max()
    record("SE3 log vs scipy logm (angle < 3)", e, 1e-10)


def test_SO3_vs_scipy_rotation():
    rng = np.random.default_rng(5)
    w = rand_axes(rng, 4000) * rand_angles(rng, 4000)[:, None]
    rot = Rotation.from_rotvec(w)
    record("SO3 exp vs Rotation.as_matrix", np.abs(se3.exp(w) - rot.as_matrix()).max(), 1e-14)
    record("SO3 log vs Rotation.as_rotvec", np.abs(se3.log(rot.as_matrix()) - rot.as_rotvec()).max(),
           1e-13)
    # quaternions: scipy is scalar last
    q = se3.rot_to_quat(rot.as_matrix())
    qs = rot.as_quat(canonical=True)[:, [3, 0, 1, 2]]
    assert np.all(q[:, 0] >= 0.0)
    # at w = 0 (angle pi) q and -q both qualify
    d = np.minimum(np.abs(q - qs).max(axis=1), np.abs(q + qs).max(axis=1))
    record("rot_to_quat vs Rotation.as_quat", d.max(), 1e-14)
    qr = rng.normal(size=(4000, 4)) * rng.uniform(0.1, 10, (4000, 1))  # not normalized
    R = se3.quat_to_rot(qr)
    record("quat_to_rot vs Rotation.from_quat", np.abs(R - Rotation.from_quat(qr[:, [1, 2, 3, 0]])
                                                       .as_matrix()).max(), 1e-14)
    record("quat round trip", np.abs(se3.quat_to_rot(se3.rot_to_quat(R)) - R).max(), 1e-14)


def test_near_zero_no_cancellation():
    """At tiny angles the results equal the first terms of the series to rounding."""
    rng = np.random.default_rng(6)
    x = rng.normal(size=(500, 6)) * np.array([1e-9] * 3 + [1.0] * 3)
    H = se3.exp(x)
    W = hat_ref(x[:, :3])
    R1 = np.eye(3) + W + 0.5 * W @ W
    record("SO3 exp at |w|<1e-8 vs 2nd-order series", np.abs(H[:, :3, :3] - R1).max(), 1e-16)
    p1 = x[:, 3:] + 0.5 * np.cross(x[:, :3], x[:, 3:])
    record("SE3 exp p at |w|<1e-8 vs 1st-order series", np.abs(H[:, :3, 3] - p1).max(), 1e-15)
    # log of a rotation by 1e-10 rad: relative accuracy of the angle
    w = rand_axes(rng, 500) * 1e-10
    R = Rotation.from_rotvec(w).as_matrix()
    record("SO3 log at 1e-10 rad (relative)", (np.abs(se3.log(R) - w).max() / 1e-10), 1e-6)


# ------------------------------------------------------------------ adjoints


def test_Ad_homomorphism_and_inverse():
    rng = np.random.default_rng(7)
    A, B = ref_poses(rng, 4000), ref_poses(rng, 4000)
    AB = se3.compose(A, B)
    record("compose = A @ B", np.abs(AB - A @ B).max(), 1e-14)
    lhs, rhs = se3.Ad(AB), se3.Ad(A) @ se3.Ad(B)
    rel = np.abs(lhs - rhs).max(axis=(1, 2)) / np.abs(rhs).max(axis=(1, 2))
    record("Ad(AB) = Ad(A)Ad(B) (relative)", rel.max(), 1e-14)
    Ai = se3.inverse(A)
    rel = np.abs(A @ Ai - np.eye(4)).max(axis=(1, 2)) / (1.0 + np.abs(A[:, :3, 3]).max(axis=1))
    record("H inverse(H) = I (relative to 1+|p|)", rel.max(), 1e-14)
    record("Ad(H^-1) = Ad(H)^-1", np.abs(se3.Ad(Ai) @ se3.Ad(A) - np.eye(6)).max(), 1e-13)
    assert np.array_equal(se3.Ad_dual(A), np.swapaxes(se3.Ad(A), -1, -2))
    # Ad_H y = vee(H hat(y) H^-1)
    y = rng.normal(size=(4000, 6))
    e = np.abs(np.einsum("nij,nj->ni", se3.Ad(A), y) - se3.vee(A @ hat_ref(y) @ Ai)).max()
    record("Ad_H y = vee(H y^ H^-1)", e, 1e-13)


def test_Ad_exp_equals_expm_ad():
    rng = np.random.default_rng(8)
    x = rand_twists(rng, 300)
    Ad, ad = se3.Ad(se3.exp(x)), se3.ad(x)
    e = max(np.abs(Ad[i] - expm(ad[i])).max() for i in range(len(x)))
    record("Ad(exp x) = expm(ad x)", e, 1e-12)


def test_ad_bracket_and_dual():
    rng = np.random.default_rng(9)
    x, y = rng.normal(size=(2000, 6)), rng.normal(size=(2000, 6))
    X, Y = hat_ref(x), hat_ref(y)
    e = np.abs(hat_ref(np.einsum("nij,nj->ni", se3.ad(x), y)) - (X @ Y - Y @ X)).max()
    record("hat(ad_x y) = [hat x, hat y]", e, 1e-14)
    assert np.array_equal(se3.ad_dual(x), np.swapaxes(se3.ad(x), -1, -2))
    # docs/method.md section 3.4: with m = (L, P), ad*_t m = (-w x L - v x P, -w x P)
    m = rng.normal(size=(2000, 6))
    r = np.einsum("nij,nj->ni", se3.ad_dual(x), m)
    ref = np.concatenate([-np.cross(x[:, :3], m[:, :3]) - np.cross(x[:, 3:], m[:, 3:]),
                          -np.cross(x[:, :3], m[:, 3:])], axis=1)
    record("ad_dual momentum convention", np.abs(r - ref).max(), 1e-14)
    assert np.array_equal(se3.vee(se3.hat(x)), x)
    assert np.array_equal(se3.vee(se3.hat(x[:, :3])), x[:, :3])
    assert np.array_equal(se3.hat(x), hat_ref(x))


# ------------------------------------------------------------------ dexp


def test_dexp_finite_differences():
    """H^-1 dH = hat(dexp_{-x} dx) (docs/method.md section 3.6), central differences with h = 1e-6."""
    rng = np.random.default_rng(10)
    x = rand_twists(rng, 400)
    h = 1e-6
    Hi = se3.inverse(se3.exp(x))
    D = se3.dexp(-x)
    err = 0.0
    for k in range(6):
        e = np.zeros(6)
        e[k] = h
        dH = (se3.exp(x + e) - se3.exp(x - e)) / (2 * h)
        g = se3.vee(Hi @ dH)
        err = max(err, np.abs(g - D[:, :, k]).max())
    record("dexp_{-x} vs finite differences of exp", err, 1e-8)
    # SO(3): R^T dR = hat(A(-w) dw)
    w = x[:, :3]
    Rt = np.swapaxes(se3.exp(w), -1, -2)
    A = se3.dexp(-w)
    err = 0.0
    for k in range(3):
        e = np.zeros(3)
        e[k] = h
        g = se3.vee(Rt @ (se3.exp(w + e) - se3.exp(w - e)) / (2 * h))
        err = max(err, np.abs(g - A[:, :, k]).max())
    record("SO3 jac(-w) vs finite differences", err, 1e-8)


def test_dexp_series_and_inverse():
    rng = np.random.default_rng(11)
    x = rand_twists(rng, 4000)
    D, Di = se3.dexp(x), se3.dexp_inv(x)
    record("dexp dexp_inv = I", np.abs(D @ Di - np.eye(6)).max(), 1e-13)
    J, Ji = se3.dexp(x[:, :3]), se3.dexp_inv(x[:, :3])
    record("SO3 jac jac_inv = I", np.abs(J @ Ji - np.eye(3)).max(), 1e-14)
    assert np.array_equal(J, D[:, :3, :3]) and np.array_equal(J, D[:, 3:, 3:])
    # power series sum_k ad^k/(k+1)!, 60 terms (|ad| is at most ~15 here)
    xs = x[::8]  # all angle classes
    ad = se3.ad(xs)
    S, T = np.broadcast_to(np.eye(6), ad.shape).copy(), np.broadcast_to(np.eye(6), ad.shape).copy()
    for k in range(1, 60):
        T = T @ ad / (k + 1)
        S += T
    record("dexp = sum ad^k/(k+1)!", np.abs(D[::8] - S).max(), 1e-13)


# ------------------------------------------------------------------ constructors, stacks


def test_constructors():
    rng = np.random.default_rng(12)
    th = rng.uniform(-4, 4, 50)
    for ax in "xyz":
        H = se3.rotation(ax, th)
        record("rotation(axis) vs Rotation.from_euler",
               np.abs(H[:, :3, :3] - Rotation.from_euler(ax, th[:, None]).as_matrix()).max(), 1e-15)
        assert np.array_equal(H[:, :3, 3], np.zeros((50, 3)))
    n = rng.normal(size=(50, 3))
    H = se3.rotation(n, th)
    ref = Rotation.from_rotvec(n / np.linalg.norm(n, axis=1, keepdims=True) * th[:, None])
    record("rotation(vector) vs Rotation.from_rotvec",
           np.abs(H[:, :3, :3] - ref.as_matrix()).max(), 1e-14)
    assert se3.rotation("z", 0.3).shape == (4, 4)
    p = rng.normal(size=(7, 3))
    T = se3.translation(p)
    assert np.array_equal(T[:, :3, 3], p) and np.array_equal(T[:, :3, :3], np.broadcast_to(np.eye(3), (7, 3, 3)))
    P = se3.pose(ref.as_matrix(), p[0])
    assert P.shape == (50, 4, 4) and np.array_equal(P[:, :3, 3], np.broadcast_to(p[0], (50, 3)))
    assert np.array_equal(P[:, 3], np.broadcast_to([0, 0, 0, 1.0], (50, 4)))


def test_stacks_and_output_layout():
    rng = np.random.default_rng(13)
    x = rng.normal(size=(2, 3, 6))
    H = se3.exp(x)
    assert H.shape == (2, 3, 4, 4) and H.dtype == np.float64 and H.flags.c_contiguous
    assert np.array_equal(H[1, 2], se3.exp(x[1, 2]))
    assert se3.log(H).shape == (2, 3, 6)
    assert se3.exp(np.asfortranarray(x[0])).flags.c_contiguous
    assert np.array_equal(se3.exp(np.asfortranarray(x[0])), se3.exp(x[0]))
    assert np.array_equal(se3.exp([0, 0, 0]), np.eye(3))  # integer input
    assert se3.exp(np.zeros((0, 6))).shape == (0, 4, 4)
    A, B = se3.exp(rng.normal(size=(5, 1, 6))), se3.exp(rng.normal(size=(3, 6)))
    C = se3.compose(A, B)
    assert C.shape == (5, 3, 4, 4)
    record("compose broadcasting", np.abs(C - A @ B).max(), 1e-14)
    assert se3.compose(np.eye(4), B).shape == (3, 4, 4)
    for f, a in [(se3.Ad, H), (se3.Ad_dual, H), (se3.inverse, H), (se3.ad, x), (se3.ad_dual, x),
                 (se3.dexp, x), (se3.dexp_inv, x), (se3.rot_to_quat, H[..., :3, :3]),
                 (se3.quat_to_rot, x[..., :4]), (se3.vee, H), (se3.hat, x)]:
        r = f(a)
        assert r.dtype == np.float64 and r.flags.c_contiguous and r.shape[:2] == (2, 3)


# ------------------------------------------------------------------ bad input

JUNK = [
    ("a string", "abc", "real numbers"),
    ("numeric strings", ["1", "2", "3"], "real numbers"),
    ("bytes", b"123", "real numbers"),
    ("complex", [1j, 0, 0], "complex"),
    ("None", None, "real numbers"),
    ("object array", np.array([1.0, 2.0, 3.0], dtype=object), "real numbers"),
    ("dict", {"a": 1}, ""),
]


def _good(kind):
    return {3: np.ones(3), 6: np.ones(6), 4: np.ones(4), 33: np.eye(3), 44: np.eye(4)}[kind]


PUBLIC = [  # (function, kinds of valid input, name)
    (se3.hat, (3, 6)), (se3.vee, (33, 44)), (se3.exp, (3, 6)), (se3.log, (33, 44)),
    (se3.Ad, (44,)), (se3.Ad_dual, (44,)), (se3.ad, (6,)), (se3.ad_dual, (6,)),
    (se3.dexp, (3, 6)), (se3.dexp_inv, (3, 6)), (se3.inverse, (44,)), (se3.quat_to_rot, (4,)),
    (se3.rot_to_quat, (33,)), (se3.translation, (3,)),
]


def _bad_variants(kind):
    g = _good(kind)
    out = []
    for label, junk, _ in JUNK:
        out.append((label, junk))
    for v in (np.nan, np.inf, -np.inf):
        b = g.copy()
        b.flat[0] = v
        out.append((f"non-finite {v}", b))
    out.append(("complex array", g.astype(complex)))
    out.append(("string array", g.astype(str)))
    out.append(("ragged", [[1, 2, 3], [4, 5]]))
    out.append(("wrong shape", np.ones(5)))
    out.append(("wrong shape 2d", np.ones((2, 5))))
    out.append(("scalar", 1.0))
    return out


@pytest.mark.parametrize("f,kinds", PUBLIC, ids=[p[0].__name__ for p in PUBLIC])
def test_bad_input_public(f, kinds):
    for kind in kinds:
        f(_good(kind))  # the good input works
        for label, bad in _bad_variants(kind):
            with pytest.raises(ValueError, match=r".+"):
                f(bad)
    # the messages name the problem
    with pytest.raises(ValueError, match="non-finite"):
        b = _good(kinds[0]).copy()
        b.flat[0] = np.nan
        f(b)
    with pytest.raises(ValueError, match="shape"):
        f(np.ones(5))


def test_bad_input_binary_and_constructors():
    for bad in ["abc", None, [1j] * 16, np.full((4, 4), np.nan), np.ones((3, 3)), np.ones((2, 4, 4)) + 0j]:
        with pytest.raises(ValueError):
            se3.compose(bad, np.eye(4))
        with pytest.raises(ValueError):
            se3.compose(np.eye(4), bad)
    with pytest.raises(ValueError, match="broadcast"):
        se3.compose(np.ones((2, 4, 4)), np.ones((3, 4, 4)))
    with pytest.raises(ValueError, match="zero norm"):
        se3.quat_to_rot(np.zeros(4))
    for axis in ["w", "", None, [0, 0, 0], [1, 2], [np.nan, 0, 1], [1j, 0, 0]]:
        with pytest.raises(ValueError):
            se3.rotation(axis, 0.1)
    for angle in ["1", None, np.nan, np.inf, 1j]:
        with pytest.raises(ValueError):
            se3.rotation("x", angle)
    for R, p in [(np.eye(3), [1, 2]), (np.eye(4), [0, 0, 0]), (np.full((3, 3), np.inf), [0, 0, 0]),
                 (np.eye(3), [np.nan, 0, 0]), ("abc", [0, 0, 0]), (np.eye(3), None),
                 (np.ones((2, 3, 3)), np.ones((3, 3)))]:
        with pytest.raises(ValueError):
            se3.pose(R, p)


CORE = ["so3_hat", "so3_vee", "so3_exp", "so3_log", "so3_jac", "so3_jac_inv", "se3_hat", "se3_vee",
        "se3_exp", "se3_log", "se3_inverse", "se3_Ad", "se3_Ad_dual", "se3_ad", "se3_ad_dual",
        "se3_dexp", "se3_dexp_inv", "quat_to_rot", "quat_from_rot"]


@pytest.mark.parametrize("name", CORE)
def test_core_direct_junk_raises(name):
    f = getattr(_core, name)
    for bad in ["abc", ["1", "2", "3"], b"1", None, [1j, 0, 0], np.ones(5), np.full((4, 4), np.nan),
                np.full((3, 3), np.inf), np.ones((6, 6), complex), object(), [[1, 2], [3]],
                np.array([1, 2, 3, 4, 5, 6], dtype=object)]:
        with pytest.raises(ValueError):
            f(bad)
    with pytest.raises(TypeError):
        f()
    assert issubclass(phmech.ModelError, ValueError)


def test_core_compose_junk_raises():
    for args in [("abc", np.eye(4)), (np.eye(4), None), (np.eye(4), np.ones((2, 4, 4))),
                 (np.eye(4),), (np.eye(4), np.eye(4), np.eye(4)), (np.eye(4), np.full((4, 4), np.nan))]:
        with pytest.raises((ValueError, TypeError)):
            _core.se3_compose(*args)

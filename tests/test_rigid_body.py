"""Validation of free rigid bodies against closed-form references.

Conventions (docs/method.md section 3): body twist (omega, v) at the body frame, pose H = (R, p)
maps body to world, inertia given about the centre of mass in body axes, ``com`` in body
coordinates.
References are independent of phmech: Euler's equations solved in closed form (Jacobi elliptic
functions, Landau & Lifshitz Mechanics section 37), the closed-form torque-free motion of an
axisymmetric body, scipy's ``solve_ivp`` on the quaternion ODE, and Newton's laws for the centre of
mass. Rotations in the references come from ``scipy.spatial.transform``, not from ``phmech.se3``.

The longer versions (50+ flips, tolerance sweeps, CPU tables) are in
``benchmarks/validate_rigid_body.py``.
"""
from __future__ import annotations

import time
import warnings

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.spatial.transform import Rotation
from scipy.special import ellipj, ellipk, ellipkinc

import phmech as ph

RTOL = 1e-10


# ------------------------------------------------------------------ references
def euler_elliptic(I, w0):
    """Closed-form torque-free body angular velocity for principal inertia I = (I1, I2, I3),
    I1 < I2 < I3, from body omega w0 (Landau & Lifshitz section 37). Returns (omega(t) callable,
    half period of omega_2 = time between two sign changes of omega_2 [s])."""
    I = np.asarray(I, dtype=float)
    w0 = np.asarray(w0, dtype=float)
    assert I[0] < I[1] < I[2]
    E2 = float(np.sum(I * w0 ** 2))            # 2 T
    M2 = float(np.sum((I * w0) ** 2))          # |L|^2
    # Landau's formulas hold for M^2 > 2 E I2; otherwise exchange axes 1 and 3.
    perm = [0, 1, 2] if M2 > E2 * I[1] else [2, 1, 0]
    I1, I2, I3 = I[perm]
    a1 = np.sqrt((E2 * I3 - M2) / (I1 * (I3 - I1)))
    a2 = np.sqrt((E2 * I3 - M2) / (I2 * (I3 - I2)))
    a3 = np.sqrt((M2 - E2 * I1) / (I3 * (I3 - I1)))
    rate = np.sqrt((I3 - I2) * (M2 - E2 * I1) / (I1 * I2 * I3))
    k2 = (I2 - I1) * (E2 * I3 - M2) / ((I3 - I2) * (M2 - E2 * I1))
    K = ellipk(k2)
    wp = w0[perm]
    # initial phase: sn(tau0) = w2/a2, cn(tau0) = w1/a1 (quadrant from both)
    s0 = np.clip(wp[1] / a2, -1, 1)
    c0 = np.clip(wp[0] / a1, -1, 1)
    phi0 = np.arctan2(s0, c0)                   # Jacobi amplitude at tau0
    tau0 = ellipkinc(phi0, k2) if abs(phi0) <= np.pi / 2 else np.sign(phi0) * (2 * K - ellipkinc(np.pi - abs(phi0), k2))
    sign3 = np.sign(wp[2])
    # omega1 = a1 cn, omega2 = a2 sn, omega3 = a3 dn solve Euler's equations (I1 < I2 < I3) with
    # tau = tau0 + rate t when omega3 > 0; a negative omega3 reverses the direction of tau. After
    # the relabelling 1 <-> 3 two reversals cancel: the cross product changes sign (odd
    # permutation) and so do the inertia differences (I1 > I2 > I3).
    s = sign3

    def omega(t):
        sn, cn, dn, _ = ellipj(tau0 + s * rate * np.asarray(t), k2)
        w = np.empty(np.shape(t) + (3,))
        w[..., perm[0]] = a1 * cn
        w[..., perm[1]] = a2 * sn
        w[..., perm[2]] = sign3 * a3 * dn
        return w

    return omega, 2 * K / rate


def axisym_closed_form(I1, I3, R0, w0, t):
    """Torque-free axisymmetric body (inertia diag(I1, I1, I3), body omega w0, pose R0):
    omega(t) = R(t)^T L / I1 - lam e3 and R(t) = exp(t hat(L) / I1) R0 exp(-lam t hat(e3)),
    L = R0 I w0 (world, constant), lam = (I3 - I1) / I1 * w0[2] (body-frame precession rate)."""
    Ib = np.diag([I1, I1, I3])
    L = R0 @ Ib @ w0
    lam = (I3 - I1) / I1 * w0[2]
    t = np.asarray(t, dtype=float)
    Ra = Rotation.from_rotvec(np.outer(t, L / I1)).as_matrix()
    Rb = Rotation.from_rotvec(np.outer(-lam * t, [0, 0, 1.0])).as_matrix()
    R = Ra @ R0 @ Rb
    w = np.einsum("nji,j->ni", R, L) / I1 - lam * np.array([0, 0, 1.0])
    return R, w


def quaternion_reference(Ib, R0, w0, t, rtol=1e-13, atol=1e-14):
    """solve_ivp (DOP853) on Euler's equations + the quaternion ODE q' = q * (0, omega) / 2
    (scalar-first, body omega). Returns R(t), omega(t)."""
    Ib = np.asarray(Ib, dtype=float)
    Ii = np.linalg.inv(Ib)
    x, y, z, w = Rotation.from_matrix(R0).as_quat()

    def f(_, s):
        q0, qv, om = s[0], s[1:4], s[4:7]
        dq0 = -0.5 * qv @ om
        dqv = 0.5 * (q0 * om + np.cross(qv, om))
        dom = Ii @ np.cross(Ib @ om, om)
        return np.concatenate([[dq0], dqv, dom])

    sol = solve_ivp(f, (t[0], t[-1]), np.concatenate([[w, x, y, z], w0]), method="DOP853",
                    t_eval=t, rtol=rtol, atol=atol)
    assert sol.success
    q = sol.y[:4].T
    R = Rotation.from_quat(np.column_stack([q[:, 1:], q[:, :1]])).as_matrix()
    return R, sol.y[4:].T


def rot_angle_error(Ra, Rb):
    """Angle [rad] of Ra^T Rb, per sample."""
    return np.linalg.norm(Rotation.from_matrix(np.einsum("nji,njk->nik", Ra, Rb)).as_rotvec(), axis=1)


def com_state(res, com, k=0):
    """World COM position and velocity from the poses and body twists of carrier k."""
    R, p = res.poses[:, k, :3, :3], res.poses[:, k, :3, 3]
    om, v = res.twists[:, k, :3], res.twists[:, k, 3:]
    c = np.asarray(com, dtype=float)
    pc = p + R @ c
    vc = np.einsum("nij,nj->ni", R, v + np.cross(om, c))
    return pc, vc


def world_L_about_com(res, Ic, k=0):
    """World angular momentum about the COM [N m s]: R Ic omega."""
    return np.einsum("nij,jk,nk->ni", res.poses[:, k, :3, :3], np.asarray(Ic), res.twists[:, k, :3])


def timed_simulate(m, *args, **kw):
    """IDA run of ``m`` and its CPU time [s]. Its bodies fly freely on purpose (torque-free
    motion, free fall), so UnattachedWarning is silenced rather than answered with a ph.Free()
    pair: the pair's joint coordinates would join IDA's error test (other steps) and cost
    1.6-2x the CPU of a lone body (tests/test_unattached.py), which the benchmark reports."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ph.UnattachedWarning)
        t0 = time.process_time()
        r = m.simulate(*args, **kw, integrator="ida")
        return r, time.process_time() - t0


def sign_change_times(t, y):
    """Linearly interpolated zero crossings of y(t)."""
    i = np.nonzero(np.sign(y[:-1]) * np.sign(y[1:]) < 0)[0]
    return t[i] - y[i] * (t[i + 1] - t[i]) / (y[i + 1] - y[i])


# ------------------------------------------------------------------ 1. Dzhanibekov
DZ_I = np.diag([1.0, 2.0, 3.0])
DZ_W0 = np.array([0.01, 5.0, 0.01])


def dzhanibekov(t_end, rtol=RTOL, solver="dense", dt_out=0.01, com=(0, 0, 0), pose=None):
    m = ph.Mechanism()
    m.add_rigid_body("b", 2.5, DZ_I, com=com, pose=pose,
                     twist=np.concatenate([DZ_W0, -np.cross(DZ_W0, com)]))   # COM at rest
    return timed_simulate(m, t_end, dt_out, rtol=rtol, atol=rtol * 1e-2, linear_solver=solver)


def test_elliptic_reference_solves_euler_equations():
    """The elliptic closed form matches a tight solve_ivp (guards the reference itself)."""
    omega, half = euler_elliptic(np.diag(DZ_I), DZ_W0)
    t = np.linspace(0, 12.0, 601)
    _, w_ref = quaternion_reference(DZ_I, np.eye(3), DZ_W0, t)
    assert np.max(np.abs(omega(t) - w_ref)) < 1e-8
    # a case on the other side of the separatrix (M^2 < 2 E I2)
    omega1, _ = euler_elliptic([1.0, 2.0, 3.0], [0.3, 5.0, 0.01])
    _, w_ref1 = quaternion_reference(DZ_I, np.eye(3), [0.3, 5.0, 0.01], t)
    assert np.max(np.abs(omega1(t) - w_ref1)) < 1e-8
    # and with negative omega_3
    omega2, _ = euler_elliptic([1.0, 2.0, 3.0], [0.02, -5.0, -0.01])
    _, w_ref2 = quaternion_reference(DZ_I, np.eye(3), [0.02, -5.0, -0.01], t)
    assert np.max(np.abs(omega2(t) - w_ref2)) < 1e-8


@pytest.mark.parametrize("solver", ["dense", "klu"])
def test_dzhanibekov_flips_conserve_energy_and_momentum(solver):
    """Intermediate-axis spin, inertia diag(1, 2, 3), omega0 = (0.01, 5, 0.01) rad/s, with a COM
    offset: 50 flips of omega_y; T and world L about the COM conserved to 1e-5 relative
    (measured ~5e-8 at rtol 1e-10); flip interval equals the elliptic-function half period."""
    omega, half = euler_elliptic(np.diag(DZ_I), DZ_W0)
    com = (0.1, -0.2, 0.3)
    pose = np.eye(4)
    pose[:3, :3] = Rotation.from_rotvec([0.3, -0.5, 0.7]).as_matrix()
    pose[:3, 3] = (1.0, 2.0, 3.0)
    r, cpu = dzhanibekov(51.5 * half, solver=solver, com=com, pose=pose)
    w = r.twists[:, 0, :3]
    flips = sign_change_times(r.t, w[:, 1])
    assert len(flips) >= 50
    T = 0.5 * np.einsum("ni,ij,nj->n", w, DZ_I, w)
    assert np.max(np.abs(T / T[0] - 1)) < 1e-5
    # the solver's own kinetic energy includes the COM, at rest here
    assert np.max(np.abs(r.energy["kinetic"] / T[0] - 1)) < 1e-5
    L = world_L_about_com(r, DZ_I)
    assert np.max(np.linalg.norm(L - L[0], axis=1)) / np.linalg.norm(L[0]) < 1e-5
    assert np.allclose(L[0], pose[:3, :3] @ DZ_I @ DZ_W0, rtol=1e-12, atol=0)
    # COM stays where it was
    pc, _ = com_state(r, com)
    assert np.max(np.linalg.norm(pc - pc[0], axis=1)) < 1e-6
    # flip timing vs the closed form: mean interval and every crossing time
    mean_interval = (flips[-1] - flips[0]) / (len(flips) - 1)
    assert abs(mean_interval / half - 1) < 1e-5
    ref_flips = sign_change_times(r.t, omega(r.t)[:, 1])
    assert len(ref_flips) == len(flips)
    assert np.max(np.abs(flips - ref_flips)) < 1e-3 * half
    print(f"\n[{solver}] {len(flips)} flips in {r.t[-1]:.1f} s, CPU {cpu:.2f} s, steps {r.stats['steps']}")


@pytest.mark.parametrize("flips, tol", [(2, 5e-7), (10, 1e-3)])
def test_dzhanibekov_body_omega_matches_elliptic_solution(flips, tol):
    """Body omega(t) against the Jacobi-elliptic closed form, rtol 1e-10. Measured max
    |omega - ref| / |omega0|: 4.4e-8 over 2 flips, 9.3e-5 over 10 flips. The growth is the
    physics of the near-separatrix orbit (1 - k^2 = 8e-6): the flip period K(k) has
    dK/d(k^2) = 1/(2 (1 - k^2)) ~ 6e4, so invariant errors of ~1e-9 shift each flip by ~1e-5 s
    (the rtol sweep in benchmarks/validate_rigid_body.py shows the convergence)."""
    omega, half = euler_elliptic(np.diag(DZ_I), DZ_W0)
    r, cpu = dzhanibekov(flips * half)
    err = np.max(np.linalg.norm(r.twists[:, 0, :3] - omega(r.t), axis=1)) / np.linalg.norm(DZ_W0)
    print(f"\nmax |omega - elliptic| / |omega0| = {err:.2e} over {r.t[-1]:.1f} s, CPU {cpu:.3f} s")
    assert err < tol


# ------------------------------------------------------------------ 2. axisymmetric fast spin
AX_I1, AX_I3 = 0.5, 0.8
AX_W0 = np.array([0.3, -0.2, 100.0])


def axisym(t_end, rtol=RTOL, dt_out=0.01, solver="dense"):
    m = ph.Mechanism()
    pose = np.eye(4)
    pose[:3, :3] = Rotation.from_rotvec([0.2, 0.4, -0.1]).as_matrix()
    m.add_rigid_body("top", 3.0, np.diag([AX_I1, AX_I1, AX_I3]), pose=pose,
                     twist=np.concatenate([AX_W0, np.zeros(3)]))
    r, cpu = timed_simulate(m, t_end, dt_out, rtol=rtol, atol=rtol * 1e-2, linear_solver=solver)
    return r, cpu, pose[:3, :3]


def test_axisymmetric_spin_closed_form():
    """I1 = I2 = 0.5, I3 = 0.8 kg m^2, omega0 = (0.3, -0.2, 100) rad/s, 10 s (~160 turns):
    omega_3 constant, (omega_1, omega_2) rotating at lam = (I3 - I1)/I1 omega_3 = 60 rad/s, and
    R(t) = exp(t hat(L)/I1) R0 exp(-lam t hat(e3)); rtol 1e-10."""
    r, cpu, R0 = axisym(10.0)
    Rr, wr = axisym_closed_form(AX_I1, AX_I3, R0, AX_W0, r.t)
    w = r.twists[:, 0, :3]
    w_err = np.max(np.linalg.norm(w - wr, axis=1)) / np.linalg.norm(AX_W0)
    R_err = np.max(rot_angle_error(r.poses[:, 0, :3, :3], Rr))
    w3_err = np.max(np.abs(w[:, 2] / AX_W0[2] - 1))
    print(f"\naxisym 10 s: |omega err|/|omega0| {w_err:.2e}, omega3 rel {w3_err:.2e}, "
          f"orientation {R_err:.2e} rad, CPU {cpu:.2f} s, steps {r.stats['steps']}")
    # measured at rtol 1e-10: omega3 exactly constant (I1 = I2 makes its equation 0 = 0), omega
    # error 7.2e-9 |omega0|, orientation 5.5e-8 rad after ~160 turns
    assert w3_err < 1e-12
    assert w_err < 1e-7
    assert R_err < 5e-7
    # transverse amplitude constant: error 7e-7 rad/s = 7e-9 |omega0| (2e-6 of the 0.36 rad/s
    # amplitude itself: IDA's error norm is dominated by omega3 = 100 rad/s)
    a = np.hypot(w[:, 0], w[:, 1])
    assert np.max(np.abs(a - np.hypot(*AX_W0[:2]))) / np.linalg.norm(AX_W0) < 1e-7


def test_axisymmetric_closed_form_agrees_with_quaternion_ode():
    """The closed form (the test's reference) against solve_ivp on the quaternion ODE, and phmech
    against solve_ivp too (second, independent check), over 2 s."""
    r, _, R0 = axisym(2.0)
    Rr, wr = axisym_closed_form(AX_I1, AX_I3, R0, AX_W0, r.t)
    Rq, wq = quaternion_reference(np.diag([AX_I1, AX_I1, AX_I3]), R0, AX_W0, r.t)
    assert np.max(rot_angle_error(Rr, Rq)) < 1e-9
    assert np.max(np.abs(wr - wq)) < 1e-9
    assert np.max(rot_angle_error(r.poses[:, 0, :3, :3], Rq)) < 1e-6


# ------------------------------------------------------------------ 3. frame away from the COM
def offset_body(com, gravity=(0, 0, 0), t_end=5.0, rtol=RTOL, twist=None, pose=None):
    Ic = np.array([[0.4, 0.05, -0.02], [0.05, 0.6, 0.03], [-0.02, 0.03, 0.9]])
    if pose is None:
        pose = np.eye(4)
        pose[:3, :3] = Rotation.from_rotvec([-0.4, 0.9, 0.2]).as_matrix()
        pose[:3, 3] = (0.5, -1.0, 2.0)
    tw = np.array([1.5, -2.0, 3.0, 0.4, 0.7, -0.3]) if twist is None else np.asarray(twist)
    m = ph.Mechanism(gravity=gravity)
    m.add_rigid_body("b", 2.0, Ic, com=com, pose=pose, twist=tw)
    r, cpu = timed_simulate(m, t_end, 0.01, rtol=rtol, atol=rtol * 1e-2)
    return r, cpu, Ic, pose, tw


def test_offset_com_free_body():
    """Frame 0.3 m away from the COM, general inertia, tumbling: COM in a straight line at
    constant velocity, world L about the COM conserved, kinetic energy = m|v_c|^2/2 + w.Ic.w/2."""
    com = np.array([0.2, -0.1, 0.2])
    r, cpu, Ic, pose, tw = offset_body(com)
    R0 = pose[:3, :3]
    pc0 = pose[:3, 3] + R0 @ com
    vc0 = R0 @ (tw[3:] + np.cross(tw[:3], com))
    pc, vc = com_state(r, com)
    pos_err = np.max(np.linalg.norm(pc - (pc0 + np.outer(r.t, vc0)), axis=1))
    vel_err = np.max(np.linalg.norm(vc - vc0, axis=1)) / np.linalg.norm(vc0)
    L = world_L_about_com(r, Ic)
    L_err = np.max(np.linalg.norm(L - L[0], axis=1)) / np.linalg.norm(L[0])
    # the frame origin itself does NOT move in a straight line (the test would notice a COM mixup)
    p = r.poses[:, 0, :3, 3]
    frame_dev = np.max(np.linalg.norm(p - (p[0] + np.outer(r.t, r.twists[0, 0, 3:] @ R0.T)), axis=1))
    T = 0.5 * 2.0 * np.sum(vc ** 2, axis=1) + 0.5 * np.einsum("ni,ij,nj->n", r.twists[:, 0, :3], Ic, r.twists[:, 0, :3])
    print(f"\noffset COM: pos err {pos_err:.2e} m, vel rel {vel_err:.2e}, L rel {L_err:.2e}, "
          f"frame deviation {frame_dev:.2f} m, CPU {cpu:.3f} s")
    # measured at rtol 1e-10: 2.6e-8 m, 7.0e-9, 7.6e-10
    assert frame_dev > 0.1
    assert pos_err < 1e-7
    assert vel_err < 5e-8
    assert L_err < 1e-8
    assert np.max(np.abs(r.energy["kinetic"] / T - 1)) < 1e-12
    assert np.max(np.abs(T / T[0] - 1)) < 1e-8


# ------------------------------------------------------------------ 4. falling under gravity
@pytest.mark.parametrize("com", [(0.0, 0.0, 0.0), (0.2, -0.1, 0.2), (-0.5, 0.4, 0.0)])
def test_free_fall_com_parabola(com):
    """Gravity g = (0.5, -1, -9.81) m/s^2: COM = p0 + v0 t + g t^2 / 2 for any frame offset,
    while tumbling; world L about the COM conserved (gravity has no moment about the COM);
    total energy conserved."""
    g = np.array([0.5, -1.0, -9.81])
    com = np.asarray(com)
    r, cpu, Ic, pose, tw = offset_body(com, gravity=g, t_end=3.0)
    R0 = pose[:3, :3]
    pc0 = pose[:3, 3] + R0 @ com
    vc0 = R0 @ (tw[3:] + np.cross(tw[:3], com))
    pc, vc = com_state(r, com)
    ref = pc0 + np.outer(r.t, vc0) + 0.5 * np.outer(r.t ** 2, g)
    pos_err = np.max(np.linalg.norm(pc - ref, axis=1))
    vel_err = np.max(np.linalg.norm(vc - (vc0 + np.outer(r.t, g)), axis=1))
    L = world_L_about_com(r, Ic)
    L_err = np.max(np.linalg.norm(L - L[0], axis=1)) / np.linalg.norm(L[0])
    E = r.energy["total"]
    E_err = np.max(np.abs(E - E[0])) / np.max(np.abs(r.energy["kinetic"]))
    drop = np.linalg.norm(ref[-1] - ref[0])
    vmax = np.max(np.linalg.norm(vc, axis=1))
    print(f"\nfall com={com.tolist()}: pos err {pos_err:.2e} m (drop {drop:.1f} m), rel {pos_err / drop:.1e}, "
          f"vel err {vel_err:.2e} m/s, rel {vel_err / vmax:.1e}, L rel {L_err:.2e}, E rel {E_err:.2e}, CPU {cpu:.3f} s")
    # measured at rtol 1e-10 (3 offsets): position <= 2.7e-9 of the 46 m drop, velocity
    # <= 3.5e-9 of the speed, L <= 2.9e-10, energy <= 3.6e-9
    assert pos_err / drop < 1e-8
    assert vel_err / vmax < 1e-8
    assert L_err < 1e-8
    assert E_err < 2e-8
    # the gravity potential is taken at the COM: V = -m g . p_c
    assert np.allclose(r.energy["gravity"], -2.0 * pc @ g, rtol=1e-12, atol=1e-12 * np.abs(2.0 * pc @ g).max())


def test_a_given_twist_is_kept_when_a_pair_places_the_body():
    """add_rigid_body(twist=...) on a body placed by a pair whose rates xdot0 were not given: the
    twist is the body's initial motion (it started at rest without a word before). Exact: free
    flight x = v t; along a prismatic pair's axis the same."""
    for pair in (ph.Free(), ph.Prismatic(axis="x")):
        m = ph.Mechanism(gravity=(0, 0, 0))
        b = m.add_rigid_body("b", 1.0, np.eye(3) * 1e-2, twist=(0, 0, 0, 1.0, 0, 0))
        m.add_pair("p", pair, m.ground, b)
        r = m.simulate(1.0, 0.1)
        np.testing.assert_allclose(r.poses[:, b.carrier, 0, 3], r.t, atol=1e-9)

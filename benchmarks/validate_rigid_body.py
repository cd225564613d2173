"""Issue 4 validation: free rigid bodies against closed-form references, with CPU times.

    python benchmarks/validate_rigid_body.py [--flips 50] [--rtol 1e-8 1e-10 1e-12]

Writes benchmarks/results/rigid_body.json and prints a table. The references (Jacobi-elliptic
solution of Euler's equations, the axisymmetric closed form, solve_ivp on the quaternion ODE, the
COM parabola) are the ones of tests/test_rigid_body.py, imported from there so both stay one.

1. Dzhanibekov: inertia diag(1, 2, 3) kg m^2, omega0 = (0.01, 5, 0.01) rad/s, COM offset
   (0.1, -0.2, 0.3) m: drift of T and of the world angular momentum about the COM over the flips,
   flip times vs the elliptic half period, body omega vs the elliptic solution over 2 and 10 flips.
2. Axisymmetric body I1 = I2 = 0.5, I3 = 0.8 kg m^2, omega0 = (0.3, -0.2, 100) rad/s, 10 s.
3. Free body with the frame 0.3 m from its COM; 4. the same falling under gravity.
CPU = time.process_time() around Mechanism.simulate.
"""
from __future__ import annotations

import argparse
import importlib.util
import json
import os
import platform
import time

import numpy as np

_here = os.path.dirname(os.path.abspath(__file__))
_spec = importlib.util.spec_from_file_location(
    "rigid_refs", os.path.join(_here, "..", "tests", "test_rigid_body.py"))
R = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(R)


def dzhanibekov(flips: int, rtol: float, solver: str) -> dict:
    omega, half = R.euler_elliptic(np.diag(R.DZ_I), R.DZ_W0)
    com = (0.1, -0.2, 0.3)
    pose = np.eye(4)
    pose[:3, :3] = R.Rotation.from_rotvec([0.3, -0.5, 0.7]).as_matrix()
    pose[:3, 3] = (1.0, 2.0, 3.0)
    r, cpu = R.dzhanibekov((flips + 1.5) * half, rtol=rtol, solver=solver, com=com, pose=pose)
    w = r.twists[:, 0, :3]
    fl = R.sign_change_times(r.t, w[:, 1])
    fr = R.sign_change_times(r.t, omega(r.t)[:, 1])
    T = 0.5 * np.einsum("ni,ij,nj->n", w, R.DZ_I, w)
    L = R.world_L_about_com(r, R.DZ_I)
    pc, _ = R.com_state(r, com)
    n = min(len(fl), len(fr))
    row = dict(rtol=rtol, solver=solver, t_end=float(r.t[-1]), flips=int(len(fl)),
               flips_reference=int(len(fr)), half_period_s=float(half),
               T_max_rel_drift=float(np.max(np.abs(T / T[0] - 1))),
               L_max_rel_drift=float(np.max(np.linalg.norm(L - L[0], axis=1)) / np.linalg.norm(L[0])),
               com_max_drift_m=float(np.max(np.linalg.norm(pc - pc[0], axis=1))),
               mean_flip_interval_rel_err=float((fl[-1] - fl[0]) / (len(fl) - 1) / half - 1),
               max_flip_time_err_s=float(np.max(np.abs(fl[:n] - fr[:n]))),
               orthonormality_err=float(np.max(np.abs(np.einsum("nij,nkj->nik", r.poses[:, 0, :3, :3],
                                                                r.poses[:, 0, :3, :3]) - np.eye(3)))),
               cpu_s=cpu, steps=int(r.stats["steps"]),
               residual_evals=int(r.stats["residual_evals"]), jacobian_evals=int(r.stats["jacobian_evals"]))
    for k in (2, 10):
        m = r.t <= k * half
        row[f"omega_err_{k}_flips"] = float(np.max(np.linalg.norm(w[m] - omega(r.t[m]), axis=1))
                                            / np.linalg.norm(R.DZ_W0))
    return row


def axisym(rtol: float) -> dict:
    r, cpu, R0 = R.axisym(10.0, rtol=rtol)
    Rr, wr = R.axisym_closed_form(R.AX_I1, R.AX_I3, R0, R.AX_W0, r.t)
    w = r.twists[:, 0, :3]
    return dict(rtol=rtol, t_end=float(r.t[-1]),
                omega_err_rel=float(np.max(np.linalg.norm(w - wr, axis=1)) / np.linalg.norm(R.AX_W0)),
                omega3_rel=float(np.max(np.abs(w[:, 2] / R.AX_W0[2] - 1))),
                orientation_err_rad=float(np.max(R.rot_angle_error(r.poses[:, 0, :3, :3], Rr))),
                cpu_s=cpu, steps=int(r.stats["steps"]))


def axisym_scipy(rtol: float) -> dict:
    t = np.arange(0, 10.0 + 1e-9, 0.01)
    R0 = R.Rotation.from_rotvec([0.2, 0.4, -0.1]).as_matrix()
    c0 = time.process_time()
    Rq, wq = R.quaternion_reference(np.diag([R.AX_I1, R.AX_I1, R.AX_I3]), R0, R.AX_W0, t,
                                    rtol=rtol, atol=rtol * 1e-2)
    cpu = time.process_time() - c0
    Rr, wr = R.axisym_closed_form(R.AX_I1, R.AX_I3, R0, R.AX_W0, t)
    return dict(rtol=rtol, omega_err_rel=float(np.max(np.linalg.norm(wq - wr, axis=1)) / np.linalg.norm(R.AX_W0)),
                orientation_err_rad=float(np.max(R.rot_angle_error(Rq, Rr))), cpu_s=cpu)


def offset(com, gravity, t_end: float, rtol: float) -> dict:
    g = np.asarray(gravity, dtype=float)
    com = np.asarray(com, dtype=float)
    r, cpu, Ic, pose, tw = R.offset_body(com, gravity=g, t_end=t_end, rtol=rtol)
    R0 = pose[:3, :3]
    pc0 = pose[:3, 3] + R0 @ com
    vc0 = R0 @ (tw[3:] + np.cross(tw[:3], com))
    pc, vc = R.com_state(r, com)
    ref = pc0 + np.outer(r.t, vc0) + 0.5 * np.outer(r.t ** 2, g)
    L = R.world_L_about_com(r, Ic)
    E = r.energy["total"]
    span = np.linalg.norm(ref[-1] - ref[0])
    return dict(com=com.tolist(), gravity=g.tolist(), rtol=rtol, t_end=float(r.t[-1]),
                com_pos_err_m=float(np.max(np.linalg.norm(pc - ref, axis=1))),
                com_pos_err_rel=float(np.max(np.linalg.norm(pc - ref, axis=1)) / span),
                com_vel_err_rel=float(np.max(np.linalg.norm(vc - (vc0 + np.outer(r.t, g)), axis=1))
                                      / np.max(np.linalg.norm(vc, axis=1))),
                L_max_rel_drift=float(np.max(np.linalg.norm(L - L[0], axis=1)) / np.linalg.norm(L[0])),
                E_max_rel_drift=float(np.max(np.abs(E - E[0])) / np.max(np.abs(r.energy["kinetic"]))),
                cpu_s=cpu, steps=int(r.stats["steps"]))


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--flips", type=int, default=50)
    ap.add_argument("--long-flips", type=int, default=500)
    ap.add_argument("--rtol", type=float, nargs="+", default=[1e-8, 1e-10, 1e-12])
    ap.add_argument("--out", default=os.path.join(_here, "results", "rigid_body.json"))
    a = ap.parse_args()
    out = dict(description="Free rigid bodies vs closed-form references (issue 4)",
               machine=platform.platform(), python=platform.python_version(),
               dzhanibekov=[], axisymmetric=[], axisymmetric_scipy_DOP853=[], offset_free=[], fall=[])

    print("1. Dzhanibekov, diag(1,2,3), omega0 (0.01, 5, 0.01), COM offset (0.1,-0.2,0.3)")
    print(f"{'rtol':>7} {'solver':>6} {'flips':>5} {'T drift':>9} {'L drift':>9} {'flip dt':>9} "
          f"{'w err 2f':>9} {'w err 10f':>9} {'steps':>7} {'CPU s':>6}")
    runs = [(a.flips, rt, "dense") for rt in a.rtol] + [(a.flips, 1e-10, "klu"), (a.long_flips, 1e-10, "dense")]
    for nf, rt, sol in runs:
        row = dzhanibekov(nf, rt, sol)
        out["dzhanibekov"].append(row)
        print(f"{rt:7.0e} {sol:>6} {row['flips']:5d} {row['T_max_rel_drift']:9.1e} {row['L_max_rel_drift']:9.1e} "
              f"{row['max_flip_time_err_s']:9.1e} {row['omega_err_2_flips']:9.1e} {row['omega_err_10_flips']:9.1e} "
              f"{row['steps']:7d} {row['cpu_s']:6.2f}", flush=True)

    print("\n2. Axisymmetric, I1 = I2 = 0.5, I3 = 0.8, omega0 (0.3, -0.2, 100), 10 s")
    print(f"{'rtol':>7} {'code':>8} {'w err':>9} {'R err rad':>9} {'steps':>7} {'CPU s':>6}")
    for rt in a.rtol:
        row = axisym(rt)
        out["axisymmetric"].append(row)
        print(f"{rt:7.0e} {'phmech':>8} {row['omega_err_rel']:9.1e} {row['orientation_err_rad']:9.1e} "
              f"{row['steps']:7d} {row['cpu_s']:6.2f}", flush=True)
    for rt in a.rtol:
        row = axisym_scipy(rt)
        out["axisymmetric_scipy_DOP853"].append(row)
        print(f"{rt:7.0e} {'DOP853':>8} {row['omega_err_rel']:9.1e} {row['orientation_err_rad']:9.1e} "
              f"{'':>7} {row['cpu_s']:6.2f}", flush=True)

    print("\n3./4. frame off the COM: free (5 s) and falling, g = (0.5, -1, -9.81) (3 s)")
    print(f"{'rtol':>7} {'case':>5} {'com':>18} {'pos rel':>9} {'vel rel':>9} {'L drift':>9} {'E drift':>9} {'CPU s':>6}")
    for rt in a.rtol:
        for com in ((0.2, -0.1, 0.2),):
            row = offset(com, (0, 0, 0), 5.0, rt)
            out["offset_free"].append(row)
            print(f"{rt:7.0e} {'free':>5} {str(com):>18} {row['com_pos_err_rel']:9.1e} {row['com_vel_err_rel']:9.1e} "
                  f"{row['L_max_rel_drift']:9.1e} {row['E_max_rel_drift']:9.1e} {row['cpu_s']:6.3f}")
        for com in ((0.0, 0.0, 0.0), (0.2, -0.1, 0.2), (-0.5, 0.4, 0.0)):
            row = offset(com, (0.5, -1.0, -9.81), 3.0, rt)
            out["fall"].append(row)
            print(f"{rt:7.0e} {'fall':>5} {str(com):>18} {row['com_pos_err_rel']:9.1e} {row['com_vel_err_rel']:9.1e} "
                  f"{row['L_max_rel_drift']:9.1e} {row['E_max_rel_drift']:9.1e} {row['cpu_s']:6.3f}", flush=True)

    os.makedirs(os.path.dirname(a.out), exist_ok=True)
    with open(a.out, "w") as f:
        json.dump(out, f, indent=1)
    print(f"\nwrote {a.out}")


if __name__ == "__main__":
    main()

"""URDF import against an independent implementation: Pinocchio (PyPI ``pin``) on UR5 and Panda
from ``example-robot-data`` (PyPI). Needs the validation extra (pip install -e .[validate], or
tools/requirements-validate.txt); ``make validate`` runs it. Writes
benchmarks/results/validate_urdf.json.

1. Forward dynamics at 20 random states (q, qdot, tau uniform in [-1, 1] rad, rad/s, N m): the
   joint accelerations of phmech (phmech.urdf.forward_dynamics: phmech's DAE solved for them at
   the acceleration level of its consistent initial values) against pinocchio.aba; bound 1e-8
   relative (max |a_ph - a_pin| / max |a_pin| per state).
2. A 2 s free swing under gravity from a random q0 at rest (SWINGS): phmech's IDA
   (integrator="ida", rtol 3e-12, atol 3e-14) against pinocchio.aba integrated by scipy's
   solve_ivp (DOP853, rtol = atol = 1e-12; its own error estimated against rtol = atol = 1e-13),
   joint coordinates compared every 10 ms; bound 1e-6 rad.
3. UR5 with its forearm a flexible aluminium tube: simulate() with its defaults, and its first
   modes.

Both robots load with joint_damping=False (pinocchio.aba has no joint damping; Panda's URDF
has 0.003 N m s/rad) and Panda with mimic="free" (pinocchio's default also makes its second
finger an independent joint).

Usage: python benchmarks/validate_urdf.py [--quick]   (--quick: 3 states, a 0.5 s swing)
"""
from __future__ import annotations

import argparse
import json
import os
import sys
import time
import warnings

import numpy as np
from scipy.integrate import solve_ivp

import phmech as ph

try:
    import pinocchio as pin
except ImportError as e:
    sys.exit(f"validate_urdf.py needs the validation extra (pip install pin example-robot-data): {e}")

HERE = os.path.dirname(os.path.abspath(__file__))


def robot_path(rel: str) -> str:
    """A URDF file of example-robot-data's robots folder (installed under site-packages'
    cmeel.prefix)."""
    for prefix in sys.path:
        p = os.path.join(prefix, "cmeel.prefix", "share", "example-robot-data", "robots", rel)
        if os.path.isfile(p):
            return p
    sys.exit(f"example-robot-data's {rel} not found (pip install example-robot-data)")


ROBOTS = {"ur5": ("ur_description/urdf/ur5_robot.urdf", {}),
          "panda": ("panda_description/urdf/panda.urdf", {"mimic": "free"})}
#: the swings: q0 = centre + uniform(-spread, spread) per joint [rad], joints locked at a value
#: (phmech: driven by the constant; Pinocchio: pinocchio.buildReducedModel). UR5 from anywhere in
#: [-1, 1] rad; Panda from about a reaching pose (arm forward, roughly horizontal), its fingers
#: locked half open: its free fingers (prismatic, no stops) slide out without bound, and from
#: random starts in [-1, 1] rad its light wrist whips round 20-30 rad in 2 s, a motion that
#: amplifies a local error ~1e5-fold (docs/user_guide.md, "Robots from URDF")
SWINGS = {"ur5": (np.zeros(6), 1.0, {}),
          "panda": (np.array([0.0, 1.2, 0.0, -1.0, 0.0, 1.0, 0.0]), 0.2,
                    {"panda_finger_joint1": 0.02, "panda_finger_joint2": 0.02})}
SWING_RTOL = 3e-12
KW = dict(limits="ignore", joint_damping=False)


def pinocchio_model(path):
    model = pin.buildModelFromUrdf(path)
    assert model.nq == model.nv, "continuous joints (nq != nv) are not handled here"
    return model, model.createData()


def forward_dynamics(path, opts, model, data, states):
    rows = []
    for q, v, tau in states:
        a_pin = pin.aba(model, data, q, v, tau).copy()
        t = time.perf_counter()
        a_ph = ph.urdf.forward_dynamics(path, q, v, tau, **KW, **opts)
        dt = time.perf_counter() - t
        rel = float(np.max(np.abs(a_ph - a_pin)) / np.max(np.abs(a_pin)))
        rows.append(dict(q=q.tolist(), qdot=v.tolist(), tau=tau.tolist(), a_pinocchio=a_pin.tolist(),
                         a_phmech=a_ph.tolist(), relative_error=rel, seconds=dt))
    return rows


def swing(path, opts, q0, locked, t_end, dt_out=0.01):
    """A free swing under gravity from q0 at rest (the joints in ``locked`` held): phmech's IDA
    against pinocchio.aba + solve_ivp; the reference's own error is estimated by a second
    integration at rtol = atol = 1e-13."""
    full = pin.buildModelFromUrdf(path)
    if locked:
        qref = pin.neutral(full)
        for nm, v in locked.items():
            qref[full.joints[full.getJointId(nm)].idx_q] = v
        model = pin.buildReducedModel(full, [full.getJointId(nm) for nm in locked], qref)
    else:
        model = full
    data = model.createData()
    n = model.nv
    names = list(model.names)[1:]

    def f(t, y):
        return np.concatenate([y[n:], pin.aba(model, data, y[:n], y[n:], np.zeros(n))])

    tout = np.arange(0.0, t_end + 1e-12, dt_out)
    t = time.perf_counter()
    y0 = np.concatenate([q0, np.zeros(n)])
    ref = solve_ivp(f, (0, t_end), y0, method="DOP853", rtol=1e-12, atol=1e-12, t_eval=tout)
    t_ref = time.perf_counter() - t
    tighter = solve_ivp(f, (0, t_end), y0, method="DOP853", rtol=1e-13, atol=1e-13, t_eval=tout)
    robot = ph.load_urdf(path, q0=dict(zip(names, q0)), driven=locked or None, **KW, **opts)
    t = time.perf_counter()
    res = robot.mechanism.simulate(t_end, dt_out, integrator="ida", rtol=SWING_RTOL,
                                   atol=SWING_RTOL * 1e-2)
    t_ph = time.perf_counter() - t
    x = np.hstack([res.joint(nm)["x"] for nm in names])
    err = np.abs(x - ref.y[:n].T)
    # the brief's suggested rtol 1e-10, for comparison
    loose = robot.mechanism.simulate(t_end, dt_out, integrator="ida", rtol=1e-10, atol=1e-12)
    err_loose = float(np.abs(np.hstack([loose.joint(nm)["x"] for nm in names]) - ref.y[:n].T).max())
    return dict(t_end=t_end, dt_out=dt_out, q0=q0.tolist(), locked=locked, integrator="ida",
                rtol=SWING_RTOL, atol=SWING_RTOL * 1e-2,
                reference="pinocchio.aba + solve_ivp DOP853 rtol=atol=1e-12",
                reference_self_difference_rad=float(np.abs(ref.y[:n] - tighter.y[:n]).max()),
                max_error_rad=float(err.max()), error_at_end=err[-1].tolist(),
                max_error_rad_at_rtol_1e_10=err_loose,
                error_at_each_0_5_s=[float(err[k].max()) for k in range(0, len(tout), 50)],
                travel_rad=float(np.max(np.abs(x - x[0]))), seconds_phmech=t_ph,
                seconds_reference=t_ref, steps=int(res.stats["steps"]))


def flexible_forearm(t_end):
    """UR5 with its forearm a flexible aluminium tube: its first modes with the joints held at
    q0 (driven by constants) about the static equilibrium under gravity, and a free swing under
    gravity with simulate()'s defaults."""
    path = robot_path(ROBOTS["ur5"][0])
    tube = ph.Section.tube(0.09, 0.082)
    alu = ph.Material(E=70e9, nu=0.33, density=2700.0)
    q0 = {"shoulder_lift_joint": -np.pi / 2 + 0.3, "elbow_joint": 0.5}
    held = ph.load_urdf(path, flexible={"forearm_link": (tube, alu)}, limits="ignore", driven={
        n: float(q0.get(n, 0.0)) for n in ph.load_urdf(path, limits="ignore").joints})
    modes = held.mechanism.modes(4, at=held.mechanism.static())
    robot = ph.load_urdf(path, flexible={"forearm_link": (tube, alu)}, limits="ignore", q0=q0)
    m = robot.mechanism
    t = time.perf_counter()
    res = m.simulate(t_end, 0.01)
    dt = time.perf_counter() - t
    tip = res.tip("forearm_link")
    return dict(section="tube, outer diameter 0.09 m, inner 0.082 m", material="aluminium E 70 GPa",
                masses_kg_urdf_flexible=list(robot.replaced_mass["forearm_link"]),
                elements=m.links["forearm_link"].elements,
                frequencies_hz_joints_held=[float(x) for x in modes.frequency],
                mode_labels=[str(x) for x in modes.labels],
                t_end=t_end, seconds=dt, steps=int(res.stats["steps"]), integrator=res.stats["integrator"],
                tip_travel_m=float(np.max(np.linalg.norm(tip - tip[0], axis=1))))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args()
    nstates, t_end = (3, 0.5) if args.quick else (20, 2.0)
    out = {"pinocchio": pin.__version__, "phmech": ph.__version__, "machine": "shared, 2 cores",
           "robots": {}}
    for name, (rel, opts) in ROBOTS.items():
        path = robot_path(rel)
        model, data = pinocchio_model(path)
        rng = np.random.default_rng(20261206)
        states = [tuple(rng.uniform(-1, 1, model.nv) for _ in range(3)) for _ in range(nstates)]
        fd = forward_dynamics(path, opts, model, data, states)
        worst = max(r["relative_error"] for r in fd)
        print(f"{name}: forward dynamics at {len(fd)} states: largest relative error {worst:.3g} "
              f"(bound 1e-8)", flush=True)
        centre, spread, locked = SWINGS[name]
        q0 = centre + rng.uniform(-spread, spread, centre.size)
        sw = swing(path, opts, q0, locked, t_end)
        print(f"{name}: {t_end:g} s swing: largest joint error {sw['max_error_rad']:.3g} rad (bound "
              f"1e-6; the reference's own {sw['reference_self_difference_rad']:.2g}; at rtol 1e-10 "
              f"{sw['max_error_rad_at_rtol_1e_10']:.2g}), travel {sw['travel_rad']:.3g} rad, phmech {sw['seconds_phmech']:.2f} s, "
              f"{sw['steps']} steps", flush=True)
        out["robots"][name] = dict(urdf=rel, dof=model.nv, forward_dynamics=dict(
            states=fd, largest_relative_error=worst, bound=1e-8), swing=sw)
    ff = flexible_forearm(t_end)
    print(f"ur5 flexible forearm: first modes (joints held) "
          f"{', '.join(f'{f:.4g}' for f in ff['frequencies_hz_joints_held'])} Hz; "
          f"{t_end:g} s with the defaults in {ff['seconds']:.2f} s ({ff['steps']} steps)", flush=True)
    out["ur5_flexible_forearm"] = ff
    ok = all(r["forward_dynamics"]["largest_relative_error"] < 1e-8 and r["swing"]["max_error_rad"] < 1e-6
             for r in out["robots"].values())
    out["passed"] = ok
    if not args.quick:
        dest = os.path.join(HERE, "results", "validate_urdf.json")
        with open(dest, "w") as fh:
            json.dump(out, fh, indent=1)
        print("written", dest)
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()

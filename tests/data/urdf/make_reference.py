"""Regenerate tests/data/urdf/{ur5,panda}_reference.json from Pinocchio (pip install pin): the
reference tables tests/test_urdf.py checks phmech.load_urdf against without Pinocchio.

Per robot (the URDF files beside this script, fixed base, gravity (0, 0, -9.81) m/s^2, no joint
damping: pinocchio.aba has none; Panda's second finger an independent joint, Pinocchio's
default and phmech's mimic="free"): three random states (q, qdot, tau uniform in [-1, 1]) with
pinocchio.aba's joint accelerations, and a 0.5 s free swing from a random q0 at rest (Panda:
about a reaching pose, its fingers locked half open; see benchmarks/validate_urdf.py, SWINGS):
pinocchio.aba integrated by scipy's solve_ivp (DOP853, rtol = atol = 1e-12), joint coordinates
every 0.05 s.

Usage: .venv/bin/python tests/data/urdf/make_reference.py
"""
import datetime
import json
import os

import numpy as np
import pinocchio as pin
from scipy.integrate import solve_ivp

HERE = os.path.dirname(os.path.abspath(__file__))
ROBOTS = {"ur5": "ur5_robot.urdf", "panda": "panda.urdf"}
#: the swing's start: centre + uniform(-spread, spread) [rad], the joints locked (Pinocchio's
#: buildReducedModel; phmech: driven by the constant), as in benchmarks/validate_urdf.py
SWINGS = {"ur5": ([0.0] * 6, 1.0, {}),
          "panda": ([0.0, 1.2, 0.0, -1.0, 0.0, 1.0, 0.0], 0.2,
                    {"panda_finger_joint1": 0.02, "panda_finger_joint2": 0.02})}
T_END, DT = 0.5, 0.05


def main():
    for name, fname in ROBOTS.items():
        model = pin.buildModelFromUrdf(os.path.join(HERE, fname))
        fd_joints = list(model.names)[1:]
        data = model.createData()
        n = model.nv
        rng = np.random.default_rng(30)
        states = []
        for _ in range(3):
            q, v, tau = (rng.uniform(-1, 1, n) for _ in range(3))
            states.append(dict(q=q.tolist(), qdot=v.tolist(), tau=tau.tolist(),
                               qddot=pin.aba(model, data, q, v, tau).tolist()))
        centre, spread, locked = SWINGS[name]
        if locked:
            qref = pin.neutral(model)
            for nm, v in locked.items():
                qref[model.joints[model.getJointId(nm)].idx_q] = v
            model = pin.buildReducedModel(model, [model.getJointId(nm) for nm in locked], qref)
            data = model.createData()
            n = model.nv
        q0 = np.array(centre) + rng.uniform(-spread, spread, n)

        def f(t, y):
            return np.concatenate([y[n:], pin.aba(model, data, y[:n], y[n:], np.zeros(n))])

        t = np.linspace(0.0, T_END, int(round(T_END / DT)) + 1)
        joints = list(model.names)[1:]
        sol = solve_ivp(f, (0.0, T_END), np.concatenate([q0, np.zeros(n)]), method="DOP853",
                        rtol=1e-12, atol=1e-12, t_eval=t)
        out = dict(command="python tests/data/urdf/make_reference.py", pinocchio=pin.__version__,
                   date=datetime.date.today().isoformat(), urdf=fname, joints=fd_joints,
                   gravity=model.gravity.linear.tolist(), states=states,
                   swing=dict(q0=q0.tolist(), joints=joints, locked=locked, t=t.tolist(), q=sol.y[:n].T.tolist(),
                              integrator="solve_ivp DOP853 rtol=atol=1e-12"))
        with open(os.path.join(HERE, f"{name}_reference.json"), "w") as fh:
            json.dump(out, fh, indent=1)
        print("written", f"{name}_reference.json")


if __name__ == "__main__":
    main()

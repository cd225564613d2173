"""A robot from URDF: the UR5 (tests/data/urdf/ur5_robot.urdf) rigid, then with its forearm a
flexible aluminium tube.

1. The rigid UR5 released at rest from a pose swings under gravity (joints free, no damping):
   phmech.load_urdf, then simulate(integrator="tree"), the route for rigid trees (joint
   coordinates, O(n) dynamics, Dormand-Prince 5(4)): its error check keeps the result within
   its tolerance (rtol 1e-8; stats["global_error_estimate"]) in ~40 ms. (The default
   integrator takes ~150 ms here and warns: the swing amplifies its errors to ~2x rtol 1e-4.)
   The energy ledger says how well the motion keeps its energy.
2. The same robot with its forearm flexible -- three lines: the section and material, the import
   with ``flexible={"forearm_link": ...}``, an analysis. Its first modes with the joints held
   (every joint driven by a constant) about the static equilibrium under gravity, and the free
   swing with simulate()'s defaults, the forearm's tip deflection relative to its rigid chord.

    python examples/urdf_robot.py [--quick] [--json] [--t-end 2] [--urdf FILE] [--no-plot]

(docs/user_guide.md, "Robots from URDF"; benchmarks/validate_urdf.py checks the import against
Pinocchio.)
"""
import json
import os
import sys
import warnings

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import phmech as ph  # noqa: E402
from _cli import example_parser  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
UR5 = os.path.join(HERE, "..", "tests", "data", "urdf", "ur5_robot.urdf")
#: the start: shoulder lifted 0.3 rad above horizontal, elbow bent 0.5 rad [rad]
Q0 = {"shoulder_lift_joint": -np.pi / 2 + 0.3, "elbow_joint": 0.5}


def run(urdf: str = UR5, t_end: float = 2.0, dt_out: float = 0.01) -> dict:
    """Both parts; a dict of figures."""
    # 1. the rigid robot (its joint limits are not enforced: limits="ignore" says we know), a
    # tree of revolutes: the tree integrator
    rigid = ph.load_urdf(urdf, q0=Q0, limits="ignore")
    res = rigid.mechanism.simulate(t_end, dt_out, integrator="tree")
    q = rigid.joint_coordinates(res)

    # 2. the flexible forearm, in three lines
    tube = (ph.Section.tube(0.09, 0.082), ph.Material(E=70e9, nu=0.33, density=2700.0))
    robot = ph.load_urdf(urdf, flexible={"forearm_link": tube}, q0=Q0, limits="ignore")
    flex = robot.mechanism.simulate(t_end, dt_out)

    # its modes with the joints held where they start (each driven by a constant)
    held = ph.load_urdf(urdf, flexible={"forearm_link": tube}, limits="ignore",
                        driven={n: Q0.get(n, 0.0) for n in robot.joints})
    modes = held.mechanism.modes(4, at=held.mechanism.static())

    # the forearm's deflection: its end relative to the chord from its start, in m
    link = robot.flexible["forearm_link"]
    P = flex.poses[:, link.nodes]
    chord = P[:, -1, :3, 3] - P[:, 0, :3, 3]
    axis0 = P[:, 0, :3, 0]                      # the start node's x: the undeformed direction
    lateral = chord - np.einsum("ti,ti->t", chord, axis0)[:, None] * axis0
    return dict(
        rigid=dict(t_end=t_end, final_joints_rad=dict(zip(rigid.joints, q[-1].tolist())),
                   steps=int(res.stats["steps"]),
                   error_estimate=float(res.stats["global_error_estimate"]),
                   rtol=float(res.stats["rtol"]),
                   ledger_relative=float(res.stats["ledger_relative"])),
        flexible=dict(urdf_forearm_mass_kg=robot.replaced_mass["forearm_link"][0],
                      tube_mass_kg=robot.replaced_mass["forearm_link"][1],
                      elements=link.elements,
                      modes_hz_joints_held=[float(f) for f in modes.frequency],
                      mode_labels=[str(x) for x in modes.labels],
                      steps=int(flex.stats["steps"]),
                      max_deflection_mm=float(1e3 * np.max(np.linalg.norm(lateral, axis=1))),
                      ledger_relative=float(flex.stats["ledger_relative"])))


def main():
    ap = example_parser(__doc__, "a 0.5 s swing instead of 2 s")
    ap.add_argument("--urdf", default=UR5, help="the URDF file (default: the UR5 of tests/data/urdf)")
    args = ap.parse_args()
    t_end = args.t_end or (0.5 if args.quick else 2.0)
    out = run(args.urdf, t_end)
    if args.json:
        print(json.dumps(out, indent=1))
        return
    r, f = out["rigid"], out["flexible"]
    print(f"rigid UR5, {t_end:g} s free swing (integrator='tree'): {r['steps']} steps, error "
          f"estimate {r['error_estimate']:.2g} of its tolerance (rtol {r['rtol']:g}), energy "
          f"ledger {r['ledger_relative']:.2g} of its scale; final joints [rad]:")
    for n, v in r["final_joints_rad"].items():
        print(f"  {n:22s} {v:+.4f}")
    print(f"flexible forearm: aluminium tube {f['tube_mass_kg']:.3g} kg (the URDF's forearm "
          f"{f['urdf_forearm_mass_kg']:.3g} kg), {f['elements']} elements")
    print("  first modes, joints held: " + ", ".join(
        f"{h:.4g} Hz" for h in f["modes_hz_joints_held"]))
    print(f"  {t_end:g} s swing with the defaults: {f['steps']} steps, largest forearm deflection "
          f"{f['max_deflection_mm']:.3g} mm, energy ledger {f['ledger_relative']:.2g}")


if __name__ == "__main__":
    with warnings.catch_warnings():
        warnings.simplefilter("default")
        main()

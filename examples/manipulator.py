"""The manipulator of the paper's Fig. 3 / Sec. VIII-C: 3 rigid and 3 flexible links.

Topology exactly as the paper (docs/method.md section 8.3); an edge (a, b) is
``add_pair(name, pair, a, b)``:

    k1 = (1L, 0)   shoulder: F1's start to the ground             actuated (PD)
    k2 = (1, 1R)   elbow hub R1 on F1's tip                       actuated (PD)
    k3 = (2L, 1)   upper forearm strip F2 on R1                   passive
    k4 = (3L, 1)   lower forearm strip F3 on R1                   actuated (PD)
    k5 = (2, 2R)   wrist plate R2 on F2's tip                     passive
    k6 = (2, 3R)   wrist plate R2 on F3's tip                     passive
    k7 = (3, 2)    hand R3 on the wrist plate R2                  actuated (PD)
    i1 = (3, 0)    a knock on the hand from the environment (rectangular force pulse)

A serial structure (ground - F1 - R1 ... R2 - R3) and a closed chain of rigid and flexible links
(R1 - F2 - R2 - F3 - R1, through k3, k5, k6, k4: a flexible parallelogram forearm) coexist.

Planar arrangement: every revolute axis along world z, gravity along -y. Initial (rest) pose:
F1 upright from the shoulder at the origin, R1 at (0, L1), the forearm strips F2 / F3 horizontal,
``spacing`` apart, R2 at x = L2, the hand R3 hinged at ``hand_offset`` beyond R2. All links start
unstressed and at rest; every pair's joint coordinate is 0 there (both pair frames coincide).
The four PD controllers (decentralized, each on its own joint) drive the joints to a target
configuration at t = 0 (a set-point step) plus a constant gravity-compensation torque: the
actuator torques that hold the target configuration statically under gravity (from
``Mechanism.static`` with the joints locked by very stiff springs), so the equilibrium of the
controlled arm is the target itself.

Joint coordinate convention (phmech): x = rotation of pair frame F_b relative to F_a about z.
For k1 = (1L, 0) that is the ground relative to F1, so lifting the arm clockwise is x1 > 0.

The links are thin aluminium strips, stiff out of plane (depth along z) and flexible in plane,
chosen so that the set-point step makes the link tips deflect by more than 10 % of their length
during the transient. Material damping D = beta K.

    python examples/manipulator.py [--quick] [--json] [--elements 8] [--t-end 6] [--no-plot] [--gif]
                                   [--rigid F1 ...]  (links modelled rigid, fidelity="rigid")

A planar loop built with 3-D revolute pairs is hyperconstrained when all its members are rigid;
here the loop contains flexible links (which can twist and bend out of plane), so the constraint
Jacobian keeps full rank and phmech finds no redundant rows: the loop is statically
indeterminate (out-of-plane), not kinematically redundant. The script reports
``m.redundant_constraints`` either way.
"""
from __future__ import annotations

import dataclasses
import json
import math
import os
import sys
import time
import warnings

import numpy as np

import phmech as ph
from phmech import se3

from _cli import example_parser

ACTUATED = ("k1", "k2", "k4", "k7")
PAIRS = ("k1", "k2", "k3", "k4", "k5", "k6", "k7")


# ------------------------------------------------------------------------------- parameters
@dataclasses.dataclass
class ManipulatorParams:
    """Geometry [m], materials, masses [kg], gains and set points of the arm (SI units).

    Links: aluminium strips ``L_i`` long, in-plane thickness ``t_i`` (bending direction, local y
    = in the x-y plane), depth ``d_i`` along world z. Rigid bodies: aluminium plates/blocks
    given by mass and in-plane size. Gains: kp [N m/rad], kd [N m s/rad] per actuated joint.
    ``target``: joint coordinates [rad] of k1, k2, k4, k7 (x of F_b relative to F_a)."""
    E: float = 70e9
    nu: float = 0.33
    density: float = 2700.0
    beta: float = 5e-3            # s, material damping D = beta K (lumps joint friction too)
    L1: float = 0.50              # F1 (upper arm)
    t1: float = 5e-3
    d1: float = 40e-3
    L2: float = 0.60              # F2, F3 (forearm strips, identical)
    t2: float = 3e-3
    d2: float = 30e-3
    spacing: float = 0.10         # distance F2 - F3 at R1 and R2
    m_R1: float = 0.30            # elbow hub, a 0.06 x 0.14 m plate
    a_R1: float = 0.14
    m_R2: float = 0.15            # wrist plate, 0.04 x 0.14 m
    a_R2: float = 0.14
    m_R3: float = 0.20            # hand, a 0.12 m bar hinged at its end
    L_R3: float = 0.12
    hand_offset: float = 0.04     # k7 lies this far beyond R2's centre (along x)
    kp: tuple = (120.0, 40.0, 40.0, 4.0)
    kd: tuple = (20.0, 6.0, 6.0, 0.3)
    target: tuple = (0.5, -0.4, 0.6, -0.5)
    knock: float = 20.0           # N, force of the knock i1 on the hand (world -x)
    knock_t0: float = 0.4         # s
    knock_duration: float = 0.02  # s
    gravity: float = 9.81

    def section(self, which: int) -> ph.BeamProperties:
        t, d = (self.t1, self.d1) if which == 1 else (self.t2, self.d2)
        mat = ph.Material(E=self.E, nu=self.nu, density=self.density)
        bp = ph.BeamProperties.from_material(ph.Section.rectangle(t, d), mat)
        return ph.BeamProperties(bp.stiffness, bp.inertia, self.beta * bp.stiffness)

    def as_dict(self) -> dict:
        d = dataclasses.asdict(self)
        for i in (1, 2):
            s = self.section(i)
            d[f"EI_inplane_{i}"] = s.EI_z
            d[f"EI_outofplane_{i}"] = s.EI_y
            d[f"rhoA_{i}"] = s.rhoA
        d["m_F1"] = self.density * self.L1 * self.t1 * self.d1
        d["m_F2"] = d["m_F3"] = self.density * self.L2 * self.t2 * self.d2
        return d


# ------------------------------------------------------------------------------- model
def _plate_inertia(m, a, b, c=0.01):
    """Inertia of a homogeneous box a x b x c (along x, y, z) about its centre [kg m^2]."""
    return np.diag([m * (b * b + c * c), m * (a * a + c * c), m * (a * a + b * b)]) / 12.0


def target_pairs(target) -> dict:
    """Joint coordinates [rad] of all seven pairs in the target configuration: the forearm is a
    parallelogram, so F2 turns with F3 (x3 = x4) and R2 stays parallel to R1 (x5 = x6 = -x4)."""
    x1, x2, x4, x7 = target
    return dict(k1=x1, k2=x2, k3=x4, k4=x4, k5=-x4, k6=-x4, k7=x7)


def build(p: ManipulatorParams, elements: int = 8, ff=None, kp=None, kd=None, target=None,
          knock: bool = True, x0: dict | None = None, fidelity: dict | None = None):
    """The mechanism and a dict of handles. ``ff``: constant gravity-compensation torques
    [N m] per actuated joint (None: none); ``kp``, ``kd``, ``target`` override the params.
    ``x0``: initial joint coordinates per pair name (default: all 0, the rest pose).
    ``fidelity``: link name -> "rigid", "modal" or "nonlinear" (default: every link nonlinear),
    or a dict of add_flexible_link keywords (e.g. ``{"fidelity": "modal", "modes": 2}``)."""
    x0 = x0 or {}
    kp = p.kp if kp is None else kp
    kd = p.kd if kd is None else kd
    target = p.target if target is None else target
    m = ph.Mechanism(gravity=(0.0, -p.gravity, 0.0))
    Rup = se3.rotation("z", math.pi / 2)                      # F1 local x = world y
    T = se3.translation
    H_F1 = Rup
    H_F2 = T([0.0, p.L1 + p.spacing / 2, 0.0])
    H_F3 = T([0.0, p.L1 - p.spacing / 2, 0.0])
    H_R1 = T([0.0, p.L1, 0.0])
    H_R2 = T([p.L2, p.L1, 0.0])
    H_k7 = T([p.L2 + p.hand_offset, p.L1, 0.0])
    H_R3 = T([p.L2 + p.hand_offset + p.L_R3 / 2, p.L1, 0.0])   # R3's frame at its centre
    fid = {"F1": "nonlinear", "F2": "nonlinear", "F3": "nonlinear", **(fidelity or {})}
    kw = {k: dict(fidelity=v) if isinstance(v, str) else dict(v) for k, v in fid.items()}
    F1 = m.add_flexible_link("F1", p.L1, p.section(1), elements=elements, pose=H_F1, **kw["F1"])
    F2 = m.add_flexible_link("F2", p.L2, p.section(2), elements=elements, pose=H_F2, **kw["F2"])
    F3 = m.add_flexible_link("F3", p.L2, p.section(2), elements=elements, pose=H_F3, **kw["F3"])
    R1 = m.add_rigid_body("R1", p.m_R1, _plate_inertia(p.m_R1, 0.06, p.a_R1), pose=H_R1)
    R2 = m.add_rigid_body("R2", p.m_R2, _plate_inertia(p.m_R2, 0.04, p.a_R2), pose=H_R2)
    R3 = m.add_rigid_body("R3", p.m_R3, _plate_inertia(p.m_R3, p.L_R3, 0.03), pose=H_R3)
    # rigid bodies must be in the order R1, R2, R3 (rows 1, 2, 3 of the paper's (25)): the
    # graphs list rigid bodies in the order added, flexible links likewise.

    def frame(carrier, H_carrier, H_joint, label):
        return ph.Frame(carrier, se3.inverse(H_carrier) @ H_joint, label)

    ground = lambda H_joint, label: ph.Frame(-1, H_joint, label)
    start = lambda lk, H: frame(lk.nodes[0], H, H, lk.name + ".start")
    # the end frame's carrier is the end node (nonlinear) or the whole link (rigid: link.end's
    # offset on it); H @ T(L) is where the end frame sits in the rest pose
    end = lambda lk, H, Hj: ph.Frame(lk.end.carrier, lk.end.T @ se3.inverse(H @ T([lk.length, 0, 0]))
                                     @ Hj, lk.name + ".end")
    gains = dict(zip(ACTUATED, zip(kp, kd, target)))

    def act(name):
        if name not in gains:
            return None
        k, c, x = gains[name]
        return ph.PD(kp=k, kd=c, target=x)

    rev = ph.Revolute("z")
    Hj1 = H_F1
    Hj2 = T([0.0, p.L1, 0.0])
    Hj3, Hj4 = H_F2, H_F3
    Hj5 = T([p.L2, p.L1 + p.spacing / 2, 0.0])
    Hj6 = T([p.L2, p.L1 - p.spacing / 2, 0.0])
    m.add_pair("k1", rev, start(F1, H_F1), ground(Hj1, "shoulder"), actuator=act("k1"), x0=x0.get("k1"))        # (1L, 0)
    m.add_pair("k2", rev, frame(R1.carrier, H_R1, Hj2, "R1.k2"), end(F1, H_F1, Hj2),
               actuator=act("k2"), x0=x0.get("k2"))                                                              # (1, 1R)
    m.add_pair("k3", rev, start(F2, H_F2), frame(R1.carrier, H_R1, Hj3, "R1.k3"), x0=x0.get("k3"))              # (2L, 1)
    m.add_pair("k4", rev, start(F3, H_F3), frame(R1.carrier, H_R1, Hj4, "R1.k4"),
               actuator=act("k4"), x0=x0.get("k4"))                                                              # (3L, 1)
    m.add_pair("k5", rev, frame(R2.carrier, H_R2, Hj5, "R2.k5"), end(F2, H_F2, Hj5), x0=x0.get("k5"))           # (2, 2R)
    m.add_pair("k6", rev, frame(R2.carrier, H_R2, Hj6, "R2.k6"), end(F3, H_F3, Hj6), x0=x0.get("k6"))           # (2, 3R)
    m.add_pair("k7", rev, frame(R3.carrier, H_R3, H_k7, "R3.k7"), frame(R2.carrier, H_R2, H_k7, "R2.k7"),
               actuator=act("k7"), x0=x0.get("k7"))                                                              # (3, 2)
    if ff is not None:
        for name, u in zip(ACTUATED, ff):
            m.add_actuator(name + ".ff", name, ph.Effort(law=float(u)))
    law = ph.Pulse(t0=p.knock_t0, duration=p.knock_duration, value=p.knock) if knock else ph.Constant(0.0)
    # i1 = (3, 0): on the hand's tip, world -x, reaction on the ground
    m.add_interaction("i1", R3, (0, 0, 0, -1.0, 0, 0), law=law, point=(p.L_R3 / 2, 0, 0))
    return m, dict(F1=F1, F2=F2, F3=F3, R1=R1, R2=R2, R3=R3)


def planar_joint_angles(m: ph.Mechanism, poses: np.ndarray) -> dict:
    """Joint angles [rad] of every pair from carrier poses (planar: angle of F_a^-1 F_b about z),
    computed independently of the core's joint coordinates."""
    out = {}
    for e in m._pairs:
        Ha = np.eye(4) if e["a"] < 0 else poses[e["a"]]
        Hb = np.eye(4) if e["b"] < 0 else poses[e["b"]]
        h = se3.inverse(Ha @ e["Ta"]) @ (Hb @ e["Tb"])
        out[e["name"]] = math.atan2(h[1, 0], h[0, 0])
    return out


def gravity_compensation(p: ManipulatorParams, elements: int = 8, k_lock: float = 1e5,
                         iterations: int = 2, fidelity: dict | None = None) -> tuple:
    """Constant actuator torques [N m] that hold the target configuration statically under
    gravity: the joints are locked at the target by stiff springs (k_lock [N m/rad]), the static
    equilibrium gives the springs' torques; one or two corrections remove the lock's own
    compliance. Returns (torques, StaticResult at the target)."""
    ff = np.zeros(len(ACTUATED))
    st = None
    for _ in range(iterations):
        m, _ = build(p, elements=elements, ff=ff, kp=[k_lock] * 4, kd=[0.0] * 4, knock=False,
                     x0=target_pairs(p.target), fidelity=fidelity)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ph.RedundantConstraintWarning)
            st = m.static(steps=10, start=st)
        x = planar_joint_angles(m, st.poses)
        ff = ff + np.array([-k_lock * (x[n] - t) for n, t in zip(ACTUATED, p.target)])
    return ff, st


# ------------------------------------------------------------------------------- analysis
def deflection(res, link: ph.FlexibleLink) -> np.ndarray:
    """Transverse tip deflection of a link relative to the tangent of its start [m], (nt,):
    the in-plane (local y) coordinate of the end node in the start node's frame."""
    Hs = res.pose(link.start)
    pe = res.position(link.end)
    d = pe - Hs[:, :3, 3]
    return np.einsum("tij,ti->tj", Hs[:, :3, :3], d)[:, 1]


def settling_time(t, err, tol) -> float:
    """First time after which |err| stays below tol (inf if it never does)."""
    bad = np.nonzero(np.abs(err) > tol)[0]
    if bad.size == 0:
        return float(t[0])
    if bad[-1] == len(t) - 1:
        return math.inf
    return float(t[bad[-1] + 1])


def run(p: ManipulatorParams, t_end: float = 6.0, elements: int = 8, dt_out: float = 2e-3,
        rtol: float | None = None, atol: float | None = None, linear_solver: str = "auto",
        settle_tol: float = 0.02, nmodes: int = 8, integrator: str = "generalized-alpha",
        fidelity: dict | None = None) -> dict:
    """Gravity compensation, simulation, modes at the target; returns a dict of results.
    The simulation runs with phmech's defaults unless rtol/atol/linear_solver/integrator say
    otherwise."""
    cpu = {}
    c0 = time.process_time()
    ff, st_lock = gravity_compensation(p, elements=elements, fidelity=fidelity)
    cpu["gravity_compensation"] = time.process_time() - c0
    m, h = build(p, elements=elements, ff=ff, fidelity=fidelity)
    with warnings.catch_warnings(record=True) as wlist:
        warnings.simplefilter("always", ph.RedundantConstraintWarning)
        c0 = time.process_time()
        res = m.simulate(t_end=t_end, dt_out=dt_out, rtol=rtol, atol=atol, linear_solver=linear_solver,
                         integrator=integrator)
        cpu["simulate"] = time.process_time() - c0
    redundant_warned = any(issubclass(w.category, ph.RedundantConstraintWarning) for w in wlist)
    # static equilibrium of the controlled arm (PD + compensation) and modes there
    c0 = time.process_time()
    st = m.static(steps=10, start=st_lock)
    x_eq = planar_joint_angles(m, st.poses)
    cpu["static"] = time.process_time() - c0
    c0 = time.process_time()
    modes = m.modes(nmodes, at=st)
    cpu["modes"] = time.process_time() - c0
    c0 = time.process_time()
    cres = m.constraint_residuals(res)
    cpu["constraint_residuals"] = time.process_time() - c0

    joints = {n: res.joint(n)["x"][:, 0] for n in PAIRS}
    step = max(abs(x) for x in p.target)
    err = {n: joints[n] - tgt for n, tgt in zip(ACTUATED, p.target)}
    ts = {n: settling_time(res.t, err[n], settle_tol * step) for n in ACTUATED}
    defl = {name: deflection(res, h[name]) for name in ("F1", "F2", "F3")}
    L = dict(F1=p.L1, F2=p.L2, F3=p.L2)
    rel = {k: float(np.max(np.abs(v)) / L[k]) for k, v in defl.items()}
    rel_t = {k: float(res.t[np.argmax(np.abs(v))]) for k, v in defl.items()}
    rel_static = {k: float(abs(deflection_static(st, h[k])) / L[k]) for k in defl}
    E = res.energy
    scale = res.stats["energy_scale"]     # the run's own figures (phmech._run.quality), as plot.energy
    ports = {k: float(v[-1]) for k, v in res.port_energy.items()}
    tip = res.poses[:, h["R3"].carrier, :3, 3]
    tip_err = np.linalg.norm(tip - st.poses[h["R3"].carrier, :3, 3], axis=1)
    return dict(
        m=m, res=res, handles=h, static=st, modes=modes, ff=ff, joints=joints, deflection=defl,
        tip_error=tip_err,
        summary=dict(
            settling_time_s={**ts, "all": max(ts.values())},
            settle_tol_rad=settle_tol * step,
            tip_settling_time_s=settling_time(res.t, tip_err, 1e-3),
            final_joint_error_rad={n: float(err[n][-1]) for n in ACTUATED},
            static_joint_error_rad={n: float(x_eq[n] - t) for n, t in zip(ACTUATED, p.target)},
            max_deflection_rel=rel, max_deflection_time_s=rel_t, static_deflection_rel=rel_static,
            max_deflection_rel_all=max(rel.values()),
            energy=dict(initial_total=float(E["total"][0]), final_total=float(E["total"][-1]),
                        delta_total=float(E["total"][-1] - E["total"][0]),
                        kinetic_final=float(E["kinetic"][-1]), elastic_final=float(E["elastic"][-1]),
                        gravity_delta=float(E["gravity"][-1] - E["gravity"][0]),
                        supplied=float(E["supplied"][-1]), dissipated=float(E["dissipated"][-1]),
                        ports=ports, ledger_max_abs=float(np.max(np.abs(E["ledger"]))),
                        scale=scale, ledger_rel=res.stats["ledger_relative"]),
            constraint_residuals=dict(position_max=float(cres["position"].max()),
                                      velocity_max=float(cres["velocity"].max())),
            redundant_constraints=[list(r) for r in m.redundant_constraints],
            redundant_warning=redundant_warned,
            gravity_compensation_Nm=dict(zip(ACTUATED, map(float, ff))),
            modes_hz=modes.frequency.tolist(), damping_ratios=modes.damping_ratio.tolist(),
            cpu_s=cpu, ida=dict(res.stats),
            settings=dict(elements=elements, t_end=t_end, dt_out=dt_out, rtol=rtol, atol=atol,
                          linear_solver=linear_solver),
            params=p.as_dict()))


def deflection_static(st, link) -> float:
    P = link.node_poses(st.poses[link.nodes])
    Hs = P[0]
    d = P[-1, :3, 3] - Hs[:3, 3]
    return float((Hs[:3, :3].T @ d)[1])


# ------------------------------------------------------------------------------- drawing
def plot_snapshots(out: dict, p: ManipulatorParams, path: str, n: int = 12) -> None:
    """Snapshots of the arm (phmech.plot.draw, x-y plane) over the target equilibrium (grey)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import phmech.plot as pp

    os.makedirs(os.path.dirname(path) or ".", exist_ok=True)
    res, m, st = out["res"], out["m"], out["static"]
    # denser early (the transient), then sparser
    tt = np.unique(np.concatenate([np.linspace(0, min(1.0, res.t[-1]), n - 4), np.linspace(1.0, res.t[-1], 5)[1:]]))[:n]
    idx = [int(np.argmin(np.abs(res.t - t))) for t in tt]
    cols = 4
    rows = int(math.ceil(len(idx) / cols))
    fig, axs = plt.subplots(rows, cols, figsize=(3.4 * cols, 3.1 * rows))
    for ax, i in zip(axs.ravel(), idx):
        d = max(abs(out["deflection"][k][i]) / L for k, L in (("F1", p.L1), ("F2", p.L2), ("F3", p.L2)))
        pp.draw(m, res, time=res.t[i], ax=ax, plane="xy", ghost=st, labels=False,
                title=f"t = {res.t[i]:.2f} s, max defl. {100 * d:.0f} %")
        ax.tick_params(labelsize=7)
        ax.xaxis.label.set_fontsize(8)
        ax.yaxis.label.set_fontsize(8)
    used = axs.ravel()[:len(idx)]
    for get, put in ((lambda a: a.get_xlim(), lambda a, v: a.set_xlim(v)),
                     (lambda a: a.get_ylim(), lambda a, v: a.set_ylim(v))):
        lims = np.array([get(ax) for ax in used])         # one scale for all snapshots
        for ax in used:
            put(ax, (lims[:, 0].min(), lims[:, 1].max()))
    for ax in axs.ravel()[len(idx):]:
        ax.axis("off")
    fig.suptitle("Fig. 3 manipulator: deformed links (blue), bodies (black), pairs (red circles); "
                 "grey: target equilibrium", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def save_gif(out: dict, p: ManipulatorParams, path: str, fps: int = 25, t_max: float = 3.0) -> bool:
    """Animation (phmech.plot.animate, Pillow); returns False when pillow is not installed."""
    try:
        import PIL  # noqa: F401
    except ImportError:
        return False
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import phmech.plot as pp

    anim = pp.animate(out["m"], out["res"], path, fps=fps, t_max=t_max, plane="xy",
                      ghost=out["static"], dpi=70, figsize=(5.5, 4.6),
                      title="Fig. 3 manipulator (grey: target)")
    plt.close(anim._fig)
    return True


def plot_response(out: dict, p: ManipulatorParams, path: str, path_energy: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import phmech.plot as pp

    res = out["res"]
    fig, ax = plt.subplots(2, 1, figsize=(7.5, 6), sharex=True)
    pp.trajectory(res, list(ACTUATED), ax=ax[0], unit="rad")
    for ln, tgt in zip(ax[0].get_lines(), p.target):
        ax[0].axhline(tgt, color=ln.get_color(), ls=":", lw=0.8)
    ax[0].set(title="(a) actuated joints (dotted: targets)", xlabel="")
    ax[0].legend(fontsize=8, ncol=4)
    for k, L in (("F1", p.L1), ("F2", p.L2), ("F3", p.L2)):
        ax[1].plot(res.t, 100 * out["deflection"][k] / L, label=k)
    ax[1].set(xlabel="t [s]", ylabel="tip deflection [% of L]",
              title="(b) link-tip deflection vs start tangent")
    ax[1].legend(fontsize=8)
    ax[1].grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)
    fig = pp.energy(res)
    fig.savefig(path_energy, dpi=100)
    plt.close(fig)


def main(argv=None) -> dict:
    ap = example_parser(__doc__, "short run (N = 4 elements, 3 s)")
    ap.add_argument("--gif", action="store_true", help="also save an animated GIF (needs pillow)")
    ap.add_argument("--rigid", nargs="*", default=[], choices=("F1", "F2", "F3"),
                    help="links modelled rigid (fidelity='rigid'), e.g. --rigid F1")
    a = ap.parse_args(argv)
    N = a.elements or (4 if a.quick else 8)
    t_end = a.t_end or (3.0 if a.quick else 6.0)
    p = ManipulatorParams()
    c0 = time.process_time()
    out = run(p, t_end=t_end, elements=N, rtol=a.rtol, atol=a.atol,
              fidelity={k: "rigid" for k in a.rigid})
    s = out["summary"]
    s["cpu_s"]["total_run"] = time.process_time() - c0
    figures = []
    if not a.no_plot:
        c0 = time.process_time()
        plot_snapshots(out, p, os.path.join(a.outdir, "manipulator_snapshots.png"))
        plot_response(out, p, os.path.join(a.outdir, "manipulator_response.png"),
                      os.path.join(a.outdir, "manipulator_energy.png"))
        figures = [os.path.join(a.outdir, f"manipulator_{k}.png") for k in ("snapshots", "response", "energy")]
        if a.gif:
            s["gif"] = save_gif(out, p, os.path.join(a.outdir, "manipulator.gif"))
            if s["gif"]:
                figures.append(os.path.join(a.outdir, "manipulator.gif"))
        s["cpu_s"]["plots"] = time.process_time() - c0
    if a.json:
        print(json.dumps(s))
    else:
        e = s["energy"]
        print(f"Fig. 3 manipulator: N = {N} elements per link, t_end = {t_end:g} s, rtol = {a.rtol or 'default'}"
              + (f"; rigid links: {', '.join(a.rigid)}" if a.rigid else ""))
        print(f"redundant constraint rows: {s['redundant_constraints'] or 'none (the loop contains flexible links)'}")
        print("settling time (|x - target| < {:.4f} rad for good): ".format(s["settle_tol_rad"]) +
              ", ".join(f"{k} {v:.3f} s" for k, v in s["settling_time_s"].items()) +
              f"; hand within 1 mm of its equilibrium after {s['tip_settling_time_s']:.3f} s")
        print("final joint errors [rad]: " + ", ".join(f"{k} {v:+.2e}" for k, v in s["final_joint_error_rad"].items()))
        print("largest tip deflection / length: " + ", ".join(
            f"{k} {100 * v:.1f} % at t = {s['max_deflection_time_s'][k]:.3f} s" for k, v in s["max_deflection_rel"].items()) +
            "  (static at the target: " + ", ".join(f"{k} {100 * v:.1f} %" for k, v in s["static_deflection_rel"].items()) + ")")
        print(f"energy: E(T) - E(0) = {e['delta_total']:.6f} J; supplied {e['supplied']:.6f} J "
              f"(ports: " + ", ".join(f"{k} {v:+.4f}" for k, v in e["ports"].items()) +
              f"), material dissipation {e['dissipated']:.6f} J; ledger residual max {e['ledger_max_abs']:.2e} J "
              f"= {e['ledger_rel']:.2e} of the energy scale {e['scale']:.4f} J")
        print(f"constraint residuals: position {s['constraint_residuals']['position_max']:.2e}, "
              f"velocity {s['constraint_residuals']['velocity_max']:.2e}")
        print("modes at the target [Hz]: " + ", ".join(f"{f:.3f} (zeta {z:.3f})" for f, z in zip(s["modes_hz"], s["damping_ratios"])))
        ida = s["ida"]
        print(f"simulate: {ida['steps']} steps, {ida['residual_evals']} residuals, {ida['jacobian_evals']} Jacobians; CPU "
              + ", ".join(f"{k} {v:.2f} s" for k, v in s["cpu_s"].items()))
        for f_ in figures:
            print(f"figure: {os.path.relpath(f_)}")
    return s


if __name__ == "__main__":
    main(sys.argv[1:])

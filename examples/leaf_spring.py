"""The leaf-spring mechanism of the paper's Sec. VIII-D: a parallel leaf-spring guide.

Two steel leaf springs F1, F2 stand vertically (along world z), clamped to the ground at their
bases; their tips carry the clamp blocks R2 (on F1) and R3 (on F2), and the platform R1 is welded
on top of both blocks. All joints are Fixed pairs, so the chain ground-F1-R2-R1-R3-F2-ground is a
closed loop (the paper's "hyperconstrained" mechanism: statically indeterminate, but with no
rigid-only loop, so no constraint is redundant). When the leaves bend, R1 translates along x.

An impulsive force w_x on R1 (a short rectangular Pulse) starts the oscillation; the FFT of the x
coordinate of R1's centre of mass after t = 2 s is compared with the linearized eigenfrequency
(``Mechanism.modes``), the paper's analytic formula f = (1/pi) sqrt(6 E I_y / (m_R L_y^3)), the
formula corrected for the leaves' own mass, and the paper's 3.366 Hz (20-Sim) and 3.4 Hz (SPACAR).
The paper's Table II is lost; the parameters below are chosen (and documented in
docs/leaf_spring.md) so that the analytic formula gives the paper's 3.369 Hz.

F1's base misalignment delta (the paper's "complete setup", ``--misalignment``): see
:func:`misalignment_study` and docs/leaf_spring.md.

    python examples/leaf_spring.py [--quick] [--json] [--elements 10] [--t-end 10] [--no-plot]
                                   [--misalignment]
"""
from __future__ import annotations

import dataclasses
import json
import math
import os
import sys
import time

import numpy as np

import phmech as ph
from phmech import se3

from _cli import example_parser

F_PAPER_ANALYTIC = 3.369  # Hz, Sec. VIII-D
F_PAPER_20SIM = 3.366     # Hz
F_PAPER_SPACAR = 3.4      # Hz
K_MOUNT = 1e8             # N m/rad, joint spring locking F1's revolute base at delta


# ------------------------------------------------------------------------------- parameters
@dataclasses.dataclass
class LeafSpringParams:
    """Geometry [m], materials and masses [kg] of the guide (world x = motion, z = up).

    Leaves: ``L`` long (the paper's L_y), ``width`` along world y, ``thickness`` along world x
    (the bending direction), spaced ``spacing`` apart along x (F1 at x = -spacing/2). Clamp
    blocks R2, R3: steel cubes of side ``block`` on the leaf tips. Platform R1: a steel plate
    ``plate_x`` x ``plate_y`` on top of the blocks; its thickness is chosen so that the paper's
    formula gives ``f_target`` (see :func:`default_params`)."""
    E: float = 210e9
    nu: float = 0.3
    density: float = 7850.0
    L: float = 0.100
    width: float = 0.020
    thickness: float = 0.5e-3
    spacing: float = 0.080
    block: float = 0.020
    plate_x: float = 0.100
    plate_y: float = 0.100
    plate_t: float = 0.0
    f_target: float = F_PAPER_ANALYTIC

    @property
    def I_y(self) -> float:
        """Second moment of the leaf section for bending in the motion direction [m^4]."""
        return self.width * self.thickness ** 3 / 12.0

    @property
    def m_leaf(self) -> float:
        return self.density * self.L * self.width * self.thickness

    @property
    def m_block(self) -> float:
        return self.density * self.block ** 3

    @property
    def m_plate(self) -> float:
        return self.density * self.plate_x * self.plate_y * self.plate_t

    @property
    def m_R(self) -> float:
        """Total mass of the moving rigid bodies R1 + R2 + R3 [kg]."""
        return self.m_plate + 2 * self.m_block

    def as_dict(self) -> dict:
        d = dataclasses.asdict(self)
        d.update(I_y=self.I_y, EI_y=self.E * self.I_y, m_leaf=self.m_leaf, m_R1=self.m_plate,
                 m_R2=self.m_block, m_R3=self.m_block, m_R=self.m_R)
        return d


def default_params() -> LeafSpringParams:
    """A 100 x 20 x 0.5 mm spring-steel leaf pair (E = 210 GPa) carrying a ~2.3 kg steel stage.

    The platform thickness is solved from the paper's formula, m_R = 6 E I_y / (pi^2 f^2 L^3),
    with f = 3.369 Hz, minus the two 20 mm clamp cubes."""
    p = LeafSpringParams()
    m_R = 6 * p.E * p.I_y / (math.pi ** 2 * p.f_target ** 2 * p.L ** 3)
    p.plate_t = (m_R - 2 * p.m_block) / (p.density * p.plate_x * p.plate_y)
    return p


# ------------------------------------------------------------------------------- formulas
def f_analytic(p: LeafSpringParams) -> float:
    """Paper's formula: two guided-clamped Euler-Bernoulli leaves (stiffness 12 E I / L^3
    each) carrying the mass m_R: f = (1/pi) sqrt(6 E I_y / (m_R L^3)) [Hz]."""
    return math.sqrt(6 * p.E * p.I_y / (p.m_R * p.L ** 3)) / math.pi


def f_analytic_mass_corrected(p: LeafSpringParams) -> float:
    """Rayleigh correction for the leaves' own mass: with the static guided-clamped deflection
    shape w(s) = u (3 s^2/L^2 - 2 s^3/L^3) as trial function, a leaf's kinetic energy is
    (1/2) (13/35) m_leaf u_dot^2, so m_eff = m_R + 2 (13/35) m_leaf."""
    m_eff = p.m_R + 2 * (13.0 / 35.0) * p.m_leaf
    return math.sqrt(6 * p.E * p.I_y / (m_eff * p.L ** 3)) / math.pi


# ------------------------------------------------------------------------------- model
def _box_inertia(m, a, b, c):
    """Inertia of a homogeneous box a x b x c (along x, y, z) about its centre [kg m^2]."""
    return np.diag([m * (b * b + c * c), m * (a * a + c * c), m * (a * a + b * b)]) / 12.0


def _weld(m, name, a_carrier, H_a, b_carrier, H_b, H_joint):
    """Fixed pair between two carriers with initial poses H_a, H_b, at the world frame H_joint."""
    Ta = se3.inverse(H_a) @ H_joint
    Tb = se3.inverse(H_b) @ H_joint
    m.add_pair(name, ph.Fixed(), ph.Frame(a_carrier, Ta, name + ".a"), ph.Frame(b_carrier, Tb, name + ".b"))


def build(p: LeafSpringParams, elements: int = 10, beta: float = 1e-5, leaf_mass_scale: float = 1.0,
          axial_shear_scale: float = 1.0, body_rot_inertia_scale: float = 1.0,
          pulse: ph.Pulse | None = None, delta: float = 0.0, mounting: str = "clamp",
          k_mount: float = K_MOUNT, mass: str = "consistent", fidelity: str = "nonlinear",
          band: float | None = None):
    """The mechanism. ``mass``: the leaves' mass ("consistent", the links' default, or "lumped"), ``fidelity`` the
    leaves' ("nonlinear", or "modal": each reduced onto its ends, with the fixed-interface modes
    ``band`` [Hz] chooses (None: none); see Mechanism.add_flexible_link). ``beta`` [s]: stiffness-proportional material damping D = beta K.
    ``leaf_mass_scale`` scales the leaves' inertia (tiny: massless leaves), ``axial_shear_scale``
    scales EA, kGA_y, kGA_z (large: inextensible, shear-rigid leaves), ``body_rot_inertia_scale``
    the rotational inertia of the bodies. ``pulse``: the force law of w_x [N] on R1's centre of
    mass (None: no load). Returns (mechanism, dict of handles).

    Misalignment (Sec. VIII-D, "complete setup"): ``delta`` [rad] is the angle of F1's base
    about world x. ``mounting`` "clamp": a Fixed clamp rotated by delta about x (delta = 0: the
    aligned guide); "revolute": a Revolute pair about world x whose angle is held at delta by a
    joint spring of stiffness ``k_mount`` [N m/rad] (damping beta k_mount), the paper's topology.
    The initial poses are the aligned ones, so for delta != 0 the loop is not in equilibrium
    (revolute: the spring is stretched; clamp: the clamp is violated): find the prestressed
    equilibrium with ``m.static()`` first (see :func:`misaligned_equilibrium`)."""
    steel = ph.Material(E=p.E, nu=p.nu, density=p.density)
    # local leaf axes: x along the leaf (world z), y = world y (width), z = world -x (thickness):
    # bending in the motion direction x is bending about the local y axis, stiffness E I_y.
    el = ph.BeamProperties.from_material(ph.Section.rectangle(p.width, p.thickness), steel)
    K = el.stiffness.copy()
    for i in (3, 4, 5):
        K[i, i] *= axial_shear_scale
    props = ph.BeamProperties(K, el.inertia * leaf_mass_scale, beta * K)

    m = ph.Mechanism(gravity=(0.0, 0.0, 0.0), band=band)
    Rleaf = se3.rotation("y", -math.pi / 2)      # local x -> world z, local z -> world -x
    xs = (-p.spacing / 2, p.spacing / 2)
    H_start = [se3.translation([x, 0.0, 0.0]) @ Rleaf for x in xs]
    H_tip = [se3.translation([x, 0.0, p.L]) @ Rleaf for x in xs]
    F1 = m.add_flexible_link("F1", p.L, props, elements=elements, pose=H_start[0], mass=mass,
                             fidelity=fidelity)
    F2 = m.add_flexible_link("F2", p.L, props, elements=elements, pose=H_start[1], mass=mass,
                             fidelity=fidelity)

    ri = body_rot_inertia_scale
    b = p.block
    H_R2 = se3.translation([xs[0], 0.0, p.L + b / 2])
    H_R3 = se3.translation([xs[1], 0.0, p.L + b / 2])
    H_R1 = se3.translation([0.0, 0.0, p.L + b + p.plate_t / 2])
    J_blk = ri * _box_inertia(p.m_block, b, b, b)
    R2 = m.add_rigid_body("R2", p.m_block, J_blk, pose=H_R2)
    R3 = m.add_rigid_body("R3", p.m_block, J_blk, pose=H_R3)
    R1 = m.add_rigid_body("R1", p.m_plate, ri * _box_inertia(p.m_plate, p.plate_x, p.plate_y, p.plate_t),
                          pose=H_R1)

    if mounting == "clamp":                                                      # edge (1L, 0)
        Hb = se3.translation([xs[0], 0.0, 0.0]) @ se3.rotation("x", delta) @ Rleaf
        m.add_pair("clamp1", ph.Fixed(), ph.Frame(-1, Hb, "base1"), F1.start)
    elif mounting == "revolute":
        # both pair frames world-aligned at F1's base, so axis "x" is world x and angle 0 is
        # the aligned initial pose; the joint spring's rest angle is the misalignment delta
        Hw = se3.translation([xs[0], 0.0, 0.0])
        m.add_pair("clamp1", ph.Revolute(axis="x"), ph.Frame(-1, Hw, "base1"),
                   ph.Frame(F1.nodes[0], se3.inverse(H_start[0]) @ Hw, "F1.base"),
                   actuator=ph.Spring(k=k_mount, c=beta * k_mount, rest=delta))
    else:
        raise ValueError(f"mounting must be 'clamp' or 'revolute' (got {mounting!r})")
    m.add_pair("clamp2", ph.Fixed(), ph.Frame(-1, H_start[1], "base2"), F2.start)   # edge (2L, 0)
    _weld(m, "tip1", F1.nodes[-1], H_tip[0], R2.carrier, H_R2, H_tip[0])
    _weld(m, "tip2", F2.nodes[-1], H_tip[1], R3.carrier, H_R3, H_tip[1])
    _weld(m, "R2R1", R2.carrier, H_R2, R1.carrier, H_R1, se3.translation([xs[0], 0.0, p.L + b]))
    _weld(m, "R3R1", R3.carrier, H_R3, R1.carrier, H_R1, se3.translation([xs[1], 0.0, p.L + b]))
    if pulse is not None:
        m.add_wrench("w_x", R1, (0, 0, 0, 1.0, 0, 0), law=pulse, frame="world")
    return m, dict(F1=F1, F2=F2, R1=R1, R2=R2, R3=R3)


def f_modal(p: LeafSpringParams, **kw) -> float:
    """Lowest linearized eigenfrequency [Hz] (the x translation of the stage)."""
    m, _ = build(p, **kw)
    return float(m.modes(1).frequency[0])


def modal_breakdown(p: LeafSpringParams, elements: int, beta: float, refine: bool = True) -> dict:
    """The first eigenfrequency [Hz] with one effect at a time changed. Tiny scale factors make
    the (finite-difference) linearization ill-conditioned, so the leaf mass is scaled by 0.01 and
    EA, kGA by 100 (their effects are then 99 % of the full ones). ``refine``: also 2x and 4x
    elements and the Richardson extrapolation of the second-order convergence."""
    out = dict(base=f_modal(p, elements=elements, beta=beta))
    out["no_damping"] = f_modal(p, elements=elements, beta=0.0)
    out["leaf_mass_x0.01"] = f_modal(p, elements=elements, beta=beta, leaf_mass_scale=1e-2)
    out["axial_shear_x100"] = f_modal(p, elements=elements, beta=beta, axial_shear_scale=1e2)
    out["body_rot_inertia_x0.001"] = f_modal(p, elements=elements, beta=beta, body_rot_inertia_scale=1e-3)
    if refine:
        f2 = out[f"elements_{2 * elements}"] = f_modal(p, elements=2 * elements, beta=beta)
        f4 = out[f"elements_{4 * elements}"] = f_modal(p, elements=4 * elements, beta=beta)
        out["elements_richardson"] = f4 + (f4 - f2) / 3.0
    return out


def f_euler_bernoulli(p: LeafSpringParams) -> float:
    """Exact first frequency [Hz] of the continuous model: two clamped-guided Euler-Bernoulli
    leaves (with their distributed mass) carrying m_R, no tilt, no axial/shear compliance.

    Each leaf carries M = m_R/2. With w = a1 (cosh - cos)(bs) + a2 (sinh - sin)(bs),
    b^4 = rho A w^2 / (E I), x = b L, mu = M / (rho A L), the guided tip w'(L) = 0 and the tip
    mass M w_tt(L) = E I w'''(L) give
    (sh + sn) [(ch + cs) + mu x (sh - sn)] - (ch - cs) [(sh - sn) + mu x (ch - cs)] = 0.
    """
    from scipy.optimize import brentq

    rhoA = p.density * p.width * p.thickness
    mu = 0.5 * p.m_R / (rhoA * p.L)

    def det(x):
        sh, ch, sn, cs = math.sinh(x), math.cosh(x), math.sin(x), math.cos(x)
        return (sh + sn) * ((ch + cs) + mu * x * (sh - sn)) - (ch - cs) * ((sh - sn) + mu * x * (ch - cs))

    # massless-leaf estimate w^2 = 24 E I / (m_R L^3), i.e. x0^4 = rho A w^2 L^4 / (E I)
    x0 = (rhoA * 24.0 * p.L / p.m_R) ** 0.25
    x = brentq(det, 0.5 * x0, 1.01 * x0, xtol=1e-15)
    return x ** 2 / p.L ** 2 * math.sqrt(p.E * p.I_y / rhoA) / (2 * math.pi)


# ------------------------------------------------------------------------------- simulation
def run(p: LeafSpringParams, t_end: float = 10.0, elements: int = 10, beta: float = 1e-5,
        rtol: float | None = None, atol: float | None = None, dt_out: float = 2e-3, t_fft: float = 2.0,
        impulse: float = 0.05, duration: float = 0.01, t0: float = 0.1,
        fidelity: str = "nonlinear", band: float | None = None) -> dict:
    """Simulate the pulse response and analyse it. Impulse ``impulse`` [N s] as a rectangular
    pulse of ``duration`` [s] from ``t0`` [s]; ``fidelity`` of the leaves and the ``band`` [Hz]
    that chooses modal leaves' fixed-interface modes (see build). Returns a dict of results and
    arrays."""
    pulse = ph.Pulse(t0=t0, duration=duration, value=impulse / duration)
    m, h = build(p, elements=elements, beta=beta, pulse=pulse, fidelity=fidelity, band=band)
    c0 = time.process_time()
    modes = m.modes(3)
    cpu_modes = time.process_time() - c0
    c0 = time.process_time()
    res = m.simulate(t_end=t_end, dt_out=dt_out, rtol=rtol, atol=atol)
    cpu_sim = time.process_time() - c0
    x0 = res.poses[0, h["R1"].carrier, 0, 3]
    x = res.poses[:, h["R1"].carrier, 0, 3] - x0          # x of R1's centre of mass [m]
    sel = res.t >= t_fft
    fm = float(modes.frequency[0])
    f_fft = ph.analysis.dominant_frequency(res.t[sel], x[sel], fmin=0.3 * fm, fmax=3 * fm)
    force = np.array([pulse.value if t0 <= t < t0 + duration else 0.0 for t in res.t])
    E = res.energy
    return dict(f_fft=f_fft, f_modal=fm, modes=modes.frequency.tolist(),
                damping_ratio=float(modes.damping_ratio[0]), cpu_sim=cpu_sim, cpu_modes=cpu_modes,
                stats=dict(res.stats), amplitude=float(np.abs(x[sel]).max()),
                ledger=float(np.max(np.abs(E["ledger"])) / max(E["supplied"].max(), 1e-300)),
                t=res.t, x=x, force=force, t_fft=t_fft, res=res, handles=h, mechanism=m,
                modes_result=m.modes(6))


# ------------------------------------------------------------------------------- misalignment
MISALIGNMENT_DEG = (0.0, 0.1, 0.2, 0.25, 0.3, 0.4, 0.5, 0.55, 1.0, 1.5, 2.0)
MISALIGNMENT_SIM_DEG = (0.25, 0.5)


def delta_cr_estimate(p: LeafSpringParams) -> float:
    """Closed-form estimate of the misalignment [rad] at which the leaves buckle sideways.

    The loop closes by bending both leaves in their stiff plane (y-z) to a tip rotation delta/2:
    a uniform moment M = E I_z (delta/2) / L with I_z = t w^3/12. Lateral-torsional buckling of
    a clamped-clamped strip under uniform moment: M_cr = (2 pi / L) sqrt(E I_y G J), J = w t^3/3
    (1 - 0.63 t/w). So delta_cr = 4 pi sqrt(E I_y G J) / (E I_z), about 8 pi sqrt(G/E) (t/w)^2,
    independent of L."""
    G = p.E / (2 * (1 + p.nu))
    I_z = p.thickness * p.width ** 3 / 12.0
    J = p.width * p.thickness ** 3 / 3.0 * (1 - 0.63 * p.thickness / p.width)
    return 4 * math.pi * math.sqrt(p.E * p.I_y * G * J) / (p.E * I_z)


def misaligned_equilibrium(p: LeafSpringParams, delta: float, mounting: str = "revolute",
                           **kw):
    """Build the misaligned guide and find its prestressed static equilibrium (Newton from the
    aligned poses). Returns (mechanism, handles, StaticResult). Beyond the buckling limit this
    prestressed equilibrium is unstable, which the study finds with modes() itself: static()'s
    own stability check (which would retry with more load steps, and warn) is off."""
    m, h = build(p, delta=delta, mounting=mounting, **kw)
    return m, h, m.static(check_stability=False)


def _r1_world(st_pose: np.ndarray, shape: np.ndarray) -> np.ndarray:
    """A mode shape of R1 (body-frame (rotation, translation), H exp(xi)) in world axes."""
    R = st_pose[:3, :3]
    return np.concatenate([R @ shape[:3], R @ shape[3:]])


def misalignment_point(p: LeafSpringParams, delta_deg: float, elements: int = 10,
                       beta: float = 1e-5, mounting: str = "revolute", nmodes: int = 4) -> dict:
    """Prestressed equilibrium, modes about it and the parasitic motion of R1 in the first mode
    at the misalignment ``delta_deg`` [deg]. Parasitic ratios are per unit x motion of R1
    (rotations in rad/m = mrad/mm, z in m/m = mm/mm), world axes."""
    c0 = time.process_time()
    m, h, st = misaligned_equilibrium(p, math.radians(delta_deg), mounting=mounting,
                                      elements=elements, beta=beta)
    cpu_static = time.process_time() - c0
    c0 = time.process_time()
    mo = m.modes(nmodes, at=st)
    cpu_modes = time.process_time() - c0
    r1 = h["R1"].carrier
    H = st.poses[r1]
    s = _r1_world(H, mo.shapes[0, r1])
    s = s / s[3]                                  # per unit x displacement
    rot = se3.log(H)[:3]                          # rotation vector of R1 (its initial pose is R = I)
    return dict(delta_deg=delta_deg, f1=float(mo.frequency[0]), modes=mo.frequency.tolist(),
                unstable=int(np.sum(mo.frequency < 0)),
                R1_static=dict(x=float(H[0, 3]), y=float(H[1, 3]), dz=float(H[2, 3] - _z_r1(p)),
                               rot_x=float(rot[0]), rot_y=float(rot[1]), rot_z=float(rot[2])),
                parasitic_mode=dict(dz_per_dx=float(s[5]), dy_per_dx=float(s[4]),
                                    rot_x_per_dx=float(s[0]), rot_y_per_dx=float(s[1]),
                                    rot_z_per_dx=float(s[2])),
                static_iterations=int(st.iterations), cpu_static=cpu_static, cpu_modes=cpu_modes)


def _z_r1(p: LeafSpringParams) -> float:
    return p.L + p.block + p.plate_t / 2


def critical_misalignment(p: LeafSpringParams, lo_deg: float, hi_deg: float, elements: int = 10,
                          beta: float = 1e-5, tol_deg: float = 1e-3) -> float:
    """Bisection [deg] for the smallest misalignment at which the prestressed equilibrium has an
    unstable (negative) linearized mode: the sideways (lateral-torsional) buckling of the leaves."""
    def unstable(d):
        try:
            m, _, st = misaligned_equilibrium(p, math.radians(d), elements=elements, beta=beta)
        except ph.SolverError:
            # within ~1e-3 deg of the limit point the tangent stiffness is singular and Newton
            # finds no equilibrium (measured at 0.5747 deg, next to 0.5731 deg: 31 iterations,
            # f1 = 0.22 Hz): count it as the unstable side
            return True
        return bool(m.modes(1, at=st).frequency[0] < 0)
    if unstable(lo_deg) or not unstable(hi_deg):
        raise ValueError("the bracket does not contain the stability limit")
    while hi_deg - lo_deg > tol_deg:
        mid = 0.5 * (lo_deg + hi_deg)
        lo_deg, hi_deg = (lo_deg, mid) if unstable(mid) else (mid, hi_deg)
    return 0.5 * (lo_deg + hi_deg)


def misalignment_simulation(p: LeafSpringParams, delta_deg: float, elements: int = 10,
                            beta: float = 1e-5, t_end: float = 4.0, t_fft: float = 0.3,
                            impulse: float = 0.005, duration: float = 0.01, t0: float = 0.05,
                            rtol: float | None = None, atol: float | None = None, dt_out: float = 2e-3) -> dict:
    """Pulse response about the prestressed equilibrium (simulate(initial=static)): FFT of x(R1)
    and the parasitic motion of R1 as least-squares slopes of its world rotation (relative to the
    equilibrium) and z displacement against its x displacement, over t >= ``t_fft``. The impulse
    (0.005 N s, ~0.1 mm) keeps the response linear."""
    pulse = ph.Pulse(t0=t0, duration=duration, value=impulse / duration)
    m, h = build(p, elements=elements, beta=beta, pulse=pulse, delta=math.radians(delta_deg),
                 mounting="revolute")
    st = m.static()
    c0 = time.process_time()
    res = m.simulate(t_end=t_end, dt_out=dt_out, rtol=rtol, atol=atol,
                     initial=st)
    cpu = time.process_time() - c0
    r1 = h["R1"].carrier
    Hs = st.poses[r1]
    P = res.poses[:, r1]
    dx = P[:, 0, 3] - Hs[0, 3]
    dz = P[:, 2, 3] - Hs[2, 3]
    dth = np.array([se3.log(_rot4(Hk[:3, :3] @ Hs[:3, :3].T))[:3]
                    for Hk in P])
    sel = res.t >= t_fft
    fm = float(m.modes(1, at=st).frequency[0])
    f_fft = ph.analysis.dominant_frequency(res.t[sel], dx[sel], fmin=0.3 * fm, fmax=3 * fm)
    X = np.column_stack([dx[sel], np.ones(sel.sum())])
    slope = lambda y: float(np.linalg.lstsq(X, y[sel], rcond=None)[0][0])
    return dict(delta_deg=delta_deg, f_fft=f_fft, f_modal=fm, amplitude=float(np.abs(dx[sel]).max()),
                parasitic_sim=dict(dz_per_dx=slope(dz), rot_x_per_dx=slope(dth[:, 0]),
                                   rot_y_per_dx=slope(dth[:, 1]), rot_z_per_dx=slope(dth[:, 2])),
                cpu_sim=cpu, ida_steps=int(res.stats["steps"]), t=res.t, x=dx, rot=dth, z=dz)


def _rot4(R: np.ndarray) -> np.ndarray:
    H = np.eye(4)
    H[:3, :3] = R
    return H


def misalignment_study(p: LeafSpringParams, deltas_deg=MISALIGNMENT_DEG,
                       sim_deltas_deg=MISALIGNMENT_SIM_DEG, elements: int = 10, beta: float = 1e-5,
                       t_end: float = 4.0, check_clamp: bool = True) -> dict:
    """The sweep: one :func:`misalignment_point` per delta, the stability limit, pulse-response
    simulations at ``sim_deltas_deg``, and (``check_clamp``) the rotated-Fixed-clamp mounting at
    the largest stable delta as a cross-check of the revolute + stiff-spring model."""
    c0 = time.process_time()
    rows = [misalignment_point(p, d, elements=elements, beta=beta) for d in deltas_deg]
    stable = [r["delta_deg"] for r in rows if r["unstable"] == 0]
    unstable = [r["delta_deg"] for r in rows if r["unstable"] > 0]
    d_cr = None
    if stable and unstable and max(stable) < min(unstable):
        d_cr = critical_misalignment(p, max(stable), min(unstable), elements=elements, beta=beta)
    sims = [misalignment_simulation(p, d, elements=elements, beta=beta, t_end=t_end)
            for d in sim_deltas_deg]
    out = dict(rows=rows, delta_cr_deg=d_cr,
               delta_cr_estimate_deg=math.degrees(delta_cr_estimate(p)), sims=sims,
               settings=dict(elements=elements, beta=beta, k_mount=K_MOUNT, t_end_sim=t_end))
    if check_clamp and stable:
        d = max(stable)
        chk = dict(delta_deg=d, revolute=rows[[r["delta_deg"] for r in rows].index(d)]["f1"])
        try:
            chk["clamp"] = misalignment_point(p, d, elements=elements, beta=beta, mounting="clamp")["f1"]
        except ph.ModelError as e:      # the clamp violates the loop at t = 0 by design
            chk["clamp_error"] = str(e)
        out["clamp_check"] = chk
    out["cpu_s"] = time.process_time() - c0
    return out


def plot_misalignment(study: dict, path: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    os.makedirs(os.path.dirname(path) or ".", exist_ok=True)
    rows = [r for r in study["rows"] if r["unstable"] == 0]
    d = np.array([r["delta_deg"] for r in rows])
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.2))
    ax[0].plot(d, [r["f1"] for r in rows], "o-", label="linearized at the prestressed equilibrium")
    ax[0].plot([s["delta_deg"] for s in study["sims"]], [s["f_fft"] for s in study["sims"]], "rx",
               ms=10, mew=2, label="FFT of the pulse response")
    if study["delta_cr_deg"] is not None:
        ax[0].axvline(study["delta_cr_deg"], color="k", ls="--", lw=1,
                      label=f"unstable beyond {study['delta_cr_deg']:.3f} deg")
    ax[0].axvline(study["delta_cr_estimate_deg"], color="gray", ls=":", lw=1,
                  label=f"LTB estimate {study['delta_cr_estimate_deg']:.3f} deg")
    ax[0].set(xlabel="misalignment delta [deg]", ylabel="first frequency [Hz]",
              title="(a) first frequency", xlim=(0, None), ylim=(0, None))
    ax[0].legend(fontsize=8, loc="lower left")
    keys = (("rot_z_per_dx", "rotation about z [mrad/mm]", "C0"),
            ("rot_y_per_dx", "rotation about y [mrad/mm]", "C1"),
            ("rot_x_per_dx", "rotation about x [mrad/mm]", "C2"),
            ("dz_per_dx", "z displacement x 1000 [mm/mm]", "C3"))
    for k, lab, c in keys:
        sc = 1e3 if k == "dz_per_dx" else 1.0
        ax[1].plot(d, [sc * r["parasitic_mode"][k] for r in rows], "o-", color=c, label=lab)
        ax[1].plot([s["delta_deg"] for s in study["sims"]], [sc * s["parasitic_sim"][k] for s in study["sims"]],
                   "x", color=c, ms=9, mew=2)
    ax[1].axhline(0, color="k", lw=0.5)
    ax[1].set(xlabel="misalignment delta [deg]", ylabel="per mm of x motion of R1",
              title="(b) parasitic motion of R1 (lines: mode 1, x: simulation)")
    ax[1].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot(out: dict, p: LeafSpringParams, path_resp: str, path_spec: str, path_modes: str) -> list:
    """The pulse response (force, x of R1), its spectrum against the linearized mode, the
    paper's formula and SPACAR, and the first six labelled mode shapes; returns the paths."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import phmech.plot as pp

    os.makedirs(os.path.dirname(path_resp) or ".", exist_ok=True)
    t, x, F, res, h = out["t"], out["x"], out["force"], out["res"], out["handles"]
    fig, ax = plt.subplots(2, 1, figsize=(7.5, 5.2), sharex=True)
    ax[0].plot(t, F)
    ax[0].set(ylabel="w_x [N]", title="(a) external force on R1 (a pulse along x)")
    pp.trajectory(res, h["R1"], components="x", scale=1e3, unit="mm", ax=ax[1])
    ax[1].axvline(out["t_fft"], color="gray", ls=":", label="FFT window starts")
    ax[1].set(title="(b) response: x of R1's centre of mass", ylabel="x [mm]")
    ax[1].legend(loc="upper right", fontsize=8)
    fig.tight_layout()
    fig.savefig(path_resp, dpi=110)
    plt.close(fig)

    sel = t >= out["t_fft"]
    ax = pp.spectrum(t[sel], x[sel], scale=1e3, unit="mm", fmax=4 * out["f_modal"],
                     references={"linearized mode": out["f_modal"], "paper's formula": f_analytic(p),
                                 "SPACAR (paper)": F_PAPER_SPACAR},
                     title=f"spectrum of x(R1) for t >= {out['t_fft']:g} s: peak "
                           f"{out['f_fft']:.4f} Hz")
    ax.figure.savefig(path_spec, dpi=110)
    plt.close(ax.figure)

    fig = pp.modes(out["modes_result"], 6, mechanism=out["mechanism"])
    fig.savefig(path_modes, dpi=90)
    plt.close(fig)
    return [path_resp, path_spec, path_modes]


def main(argv=None) -> dict:
    ap = example_parser(__doc__, "short run (5 s, no mesh refinement study)")
    ap.add_argument("--beta", type=float, default=1e-5, help="material damping D = beta K [s]")
    ap.add_argument("--fidelity", choices=("nonlinear", "modal"), default="nonlinear",
                    help="the leaves: nonlinear se3 chains, or each reduced onto its ends "
                         "(modal; try --elements 64)")
    ap.add_argument("--modes-band", type=float, default=None, metavar="HZ",
                    help="modal leaves: keep the fixed-interface modes this band needs "
                         "(default: none, the static shapes only)")
    ap.add_argument("--misalignment", action="store_true",
                    help="also sweep F1's base misalignment delta (0..2 deg): prestressed modes, "
                         "stability limit, pulse responses, parasitic motion of R1")
    a = ap.parse_args(argv)
    N = a.elements or 10
    t_end = a.t_end or (5.0 if a.quick else 10.0)

    p = default_params()
    c0 = time.process_time()
    out = run(p, t_end=t_end, elements=N, beta=a.beta, rtol=a.rtol, atol=a.atol,
              fidelity=a.fidelity, band=a.modes_band)
    brk = modal_breakdown(p, N, a.beta, refine=not a.quick)
    cpu = time.process_time() - c0
    fa, fc = f_analytic(p), f_analytic_mass_corrected(p)
    st = out["stats"]
    result = dict(f_fft=out["f_fft"], f_modal=out["f_modal"], f_analytic=fa,
                  f_analytic_mass_corrected=fc, f_euler_bernoulli=f_euler_bernoulli(p), f_20sim=F_PAPER_20SIM, f_spacar=F_PAPER_SPACAR,
                  cpu_s=cpu, cpu_simulate_s=out["cpu_sim"], cpu_modes_s=out["cpu_modes"],
                  ida_steps=st["steps"], ida_residual_evals=st["residual_evals"],
                  ida_jacobian_evals=st["jacobian_evals"], ida_error_test_fails=st["error_test_fails"],
                  fft_vs_modal=out["f_fft"] / out["f_modal"] - 1, modal_vs_analytic=out["f_modal"] / fa - 1,
                  modal_vs_mass_corrected=out["f_modal"] / fc - 1, modes=out["modes"],
                  damping_ratio=out["damping_ratio"], amplitude_m=out["amplitude"],
                  energy_ledger_rel=out["ledger"], breakdown=brk,
                  settings=dict(elements=N, t_end=t_end, beta=a.beta, rtol=a.rtol, atol=a.atol,
                                fidelity=a.fidelity, modes_band=a.modes_band),
                  params=p.as_dict())
    figures = []
    if a.misalignment:
        mis = misalignment_study(p, elements=N, beta=a.beta)
        result["misalignment"] = dict(
            {k: v for k, v in mis.items() if k != "sims"},
            sims=[{k: v for k, v in s_.items() if k not in ("t", "x", "rot", "z")} for s_ in mis["sims"]])
        if not a.no_plot:
            plot_misalignment(mis, os.path.join(a.outdir, "leaf_spring_misalignment.png"))
            figures.append(os.path.join(a.outdir, "leaf_spring_misalignment.png"))
    if not a.no_plot:
        figures += plot(out, p, os.path.join(a.outdir, "leaf_spring_response.png"),
                       os.path.join(a.outdir, "leaf_spring_spectrum.png"),
                       os.path.join(a.outdir, "leaf_spring_modes.png"))
    if a.json:
        print(json.dumps(result))
    else:
        print(f"leaf: {1e3 * p.L:g} x {1e3 * p.width:g} x {1e3 * p.thickness:g} mm steel, m_leaf = "
              f"{1e3 * p.m_leaf:.2f} g; m_R = {p.m_R:.4f} kg (R1 {p.m_plate:.4f}, R2 = R3 {p.m_block:.4f})")
        print(f"f_fft      = {out['f_fft']:.4f} Hz  (FFT of x(R1) after {out['t_fft']:g} s, "
              f"{(out['f_fft'] / out['f_modal'] - 1) * 100:+.3f} % vs modal)")
        print(f"f_modal    = {out['f_modal']:.4f} Hz  ({(out['f_modal'] / fa - 1) * 100:+.3f} % vs analytic, "
              f"{(out['f_modal'] / fc - 1) * 100:+.3f} % vs mass-corrected)")
        print(f"f_analytic = {fa:.4f} Hz; mass-corrected {fc:.4f} Hz; exact Euler-Bernoulli "
              f"{result['f_euler_bernoulli']:.4f} Hz; paper: 20-Sim {F_PAPER_20SIM}, "
              f"SPACAR {F_PAPER_SPACAR}")
        for k, v in brk.items():
            print(f"  modes, {k:28s}: {v:.5f} Hz ({(v / brk['base'] - 1) * 100:+.4f} %)")
        print(f"simulate (default integrator): {st['steps']} steps, {st['residual_evals']} residuals, {st['jacobian_evals']} "
              f"Jacobians; CPU simulate {out['cpu_sim']:.2f} s, total {cpu:.2f} s")
        if a.misalignment:
            mis = result["misalignment"]
            print("misalignment (revolute base + stiff joint spring; parasitic per mm of x, world axes):")
            print("  delta[deg]  f1[Hz]  rot_x[mrad/mm] rot_y[mrad/mm] rot_z[mrad/mm] dz[um/mm]  unstable")
            for r in mis["rows"]:
                q = r["parasitic_mode"]
                print(f"  {r['delta_deg']:9.3g} {r['f1']:8.4f} {q['rot_x_per_dx']:13.5f} "
                      f"{q['rot_y_per_dx']:14.5f} {q['rot_z_per_dx']:14.2e} {1e3 * q['dz_per_dx']:10.4f}"
                      f"  {r['unstable']}")
            print(f"  stability limit {mis['delta_cr_deg']} deg (LTB estimate "
                  f"{mis['delta_cr_estimate_deg']:.4f} deg)")
            for s_ in mis["sims"]:
                print(f"  pulse response at {s_['delta_deg']:g} deg: f_fft {s_['f_fft']:.5f} Hz "
                      f"(modal {s_['f_modal']:.5f}), rot_x {s_['parasitic_sim']['rot_x_per_dx']:.5f} "
                      f"mrad/mm, CPU {s_['cpu_sim']:.2f} s")
            print(f"  CPU misalignment study {mis['cpu_s']:.2f} s")
        print("modes (labelled):\n" + out["modes_result"].table())
        for f_ in figures:
            print(f"figure: {os.path.relpath(f_)}")
    return result


if __name__ == "__main__":
    main(sys.argv[1:])

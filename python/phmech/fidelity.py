"""Per-link fidelity (docs/user_guide.md, "Model only what a scene needs"): what a flexible link
becomes when it is modelled at a lower fidelity than the se3 chain.

``fidelity="rigid"``: the link is ONE rigid carrier whose frame is the link's start frame. Its
spatial inertia is the section inertia integrated along the unstressed shape (straight, or the
arc of a constant unstressed curvature), its node frames are fixed offsets on it at the places
the se3 chain's nodes have on the undeformed link, and a distributed load is its resultant
wrench (docs/method.md, "Rigid links"). Everything here is exact for a rigid body up to the
quadrature, which is exact for a straight link and converged to round-off for a curved one.

``fidelity="modal"``: the link reduced to its interface frames, start and end (docs/method.md,
"Modal links"): the linearization of its own se3 discretization (``elements``; free, at the
unstressed shape, phmech's linearize: the same element and mass) condensed onto the two end
nodes by its static modes (Guyan), plus, with ``modes=``, its fixed-interface modes (Craig-Bampton). The reduced link
is ONE se3 element between two carriers whose stiffness and damping reproduce the condensed ones
exactly at the unstressed shape, and whose mass is the condensed mass as a constant coupling of
the two carriers' body twists (csrc/include/phmech_types.h, PHM_MASS_GIVEN): port-Hamiltonian,
its energy balance exact, and every large rigid motion exact. Linear in the deformation between
its ends (no geometric stiffening); the link's own modes are represented as far as the static
modes and the fixed-interface modes kept carry them: each kept mode is a slider carrier on the
link's start (modal_sliders), chosen by count or from a band (choose_modes).
"""
from __future__ import annotations


import numpy as np
from scipy.linalg import eigh
from threadpoolctl import threadpool_limits

from . import se3
from .analysis import mode_energies
from .description import mass_centre

#: the fidelities add_flexible_link accepts
FIDELITIES = ("nonlinear", "rigid", "modal")

# composite Gauss-Legendre: 5 points per segment, segments of at most _MAX_TURN rad of the
# unstressed curvature (error ~ (0.2)^10 / 10! of the integrand: round-off)
_GAUSS = np.polynomial.legendre.leggauss(5)
_MAX_TURN = 0.2


def _quadrature(L: float, eps: np.ndarray) -> tuple:
    """Points s (n,) in [0, L] and weights w (n,) integrating functions of exp(s eps_hat)."""
    turn = float(np.linalg.norm(eps[:3])) * L
    nseg = max(1, int(np.ceil(turn / _MAX_TURN)))
    x, w = _GAUSS
    edges = np.linspace(0.0, L, nseg + 1)
    a, b = edges[:-1, None], edges[1:, None]
    s = (0.5 * (b - a) * x[None, :] + 0.5 * (a + b)).ravel()
    ws = (0.5 * (b - a) * w[None, :]).ravel()
    return s, ws


def rigid_link_inertia(L: float, inertia: np.ndarray, eps: np.ndarray) -> tuple:
    """The rigid link's spatial inertia M (6x6, about its start frame, (omega, v) order), mass
    [kg] and centre of mass [m, start-frame coordinates]: M = int_0^L Ad_{g(s)^-1}^T I Ad_{g(s)^-1}
    ds, g(s) = exp(s eps_hat) the section frame at arc length s on the unstressed shape, I the
    section inertia per unit length (the kinetic energy of every section moving with the body
    twist t: its twist is Ad_{g^-1} t)."""
    s, w = _quadrature(L, eps)
    A = se3.Ad(se3.inverse(se3.exp(s[:, None] * eps[None, :])))       # (n, 6, 6)
    M = np.einsum("n,nji,jk,nkl->il", w, A, inertia, A)
    M = 0.5 * (M + M.T)
    mass = float(np.trace(M[3:, 3:]) / 3.0)
    return M, mass, mass_centre(M, mass)


def node_offsets(L: float, elements: int, eps: np.ndarray) -> np.ndarray:
    """Offsets (elements + 1, 4, 4) of the node frames on the start frame: exp(k h eps_hat)."""
    h = L / elements
    return se3.exp(np.arange(elements + 1)[:, None] * h * eps[None, :])


def distributed_resultant(L: float, eps: np.ndarray, q: np.ndarray, world: bool) -> tuple:
    """A uniform distributed force q [N/m] on a rigid link as one wrench row: (w (tau, f), point
    [m, start-frame coordinates]). ``world``: q in world axes, applied at the centroid of the
    centre line (a uniform world force has no moment about it); else q in each section's axes
    (a follower load), its resultant in start-frame axes at the start frame's origin:
    (int p(s) x R(s) q ds, int R(s) q ds)."""
    s, w = _quadrature(L, eps)
    G = se3.exp(s[:, None] * eps[None, :])
    p = G[:, :3, 3]
    if world:
        return np.concatenate([np.zeros(3), q * L]), np.einsum("n,ni->i", w, p) / L
    f = np.einsum("nij,j->ni", G[:, :3, :3], q)
    return np.concatenate([np.einsum("n,ni->i", w, np.cross(p, f)), w @ f]), np.zeros(3)


def interior_modes(red: dict, n: int) -> dict:
    """The first ``n`` fixed-interface modes of a statically reduced link (``red``, from
    static_reduction): its chain's modes with both ends held, Phi (6 (N + 1) x n, zero at the
    ends), mass-normalized (Phi^T M Phi = I), lowest first. Their Ritz coupling with the static
    modes T (Craig-Bampton): ``Mbq`` = T^T M Phi (12 x n, the kinetic coupling of the ends' body
    twists with the modal rates), stiffness ``lam`` = Phi^T K Phi (n,; T^T K Phi = 0: an interior
    shape is K-orthogonal to the static modes), damping ``Dqq`` = Phi^T D Phi and ``Dbq`` =
    T^T D Phi (zero for a damping proportional to the stiffness), and ``Cg`` (n x 3) the modal
    forces of the chain's weight per unit gravity along the start frame's axes (Phi^T w_j). The
    modes' frequencies ``frequency`` [Hz] (all of them, for choose_modes), ``peak`` (n, 2):
    each mode's largest nodal displacement [m] and rotation [rad] per unit of q, and ``kinds``
    (n, 4): the shares of each mode's strain energy in torsion, bending-y, bending-z and axial
    strain (phmech.analysis.mode_energies on the chain), which label the modal link's modes."""
    ch = red["chain"]
    K, M, D, T, i = ch["K"], ch["M"], ch["D"], ch["T"], ch["interior"]
    if "fixed_interface" not in ch:          # once per reduction (choose_modes asks repeatedly)
        with threadpool_limits(limits=1, user_api="blas"):
            ch["fixed_interface"] = eigh(K[np.ix_(i, i)], M[np.ix_(i, i)])
    lam, Pi = ch["fixed_interface"]
    Phi = np.zeros((K.shape[0], n))
    Phi[i] = Pi[:, :n]
    desc = ch["desc"]
    shapes = np.moveaxis(Phi.reshape(K.shape[0] // 6, 6, n), 2, 0)      # (mode, node, 6)
    strain = mode_energies(desc, np.array([c["H0"] for c in desc.carriers]), shapes)["strain"].sum(axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        kinds = np.where(strain.sum(axis=1, keepdims=True) > 0,
                         strain / np.maximum(strain.sum(axis=1, keepdims=True), 1e-300), 0.0)
    peak = np.zeros((n, 2))
    if n:
        peak[:, 0] = np.linalg.norm(shapes[:, :, 3:], axis=2).max(axis=1)
        peak[:, 1] = np.linalg.norm(shapes[:, :, :3], axis=2).max(axis=1)
    return dict(Mbq=T.T @ M @ Phi, lam=lam[:n].copy(), Dqq=Phi.T @ D @ Phi, Dbq=T.T @ D @ Phi,
                Dbb=np.diag(T.T @ D @ T).copy(),
                Cg=Phi.T @ ch["weights"], frequency=np.sqrt(np.maximum(lam, 0.0)) / (2 * np.pi),
                peak=peak, kinds=kinds)


def reduced_matrices(red: dict, modes: dict) -> tuple:
    """K_r, M_r (12 + n square) of the reduced link in (start, end, modal) coordinates."""
    n = len(modes["lam"])
    Kr = np.zeros((12 + n, 12 + n))
    Kr[:12, :12] = red["K_B"]
    Kr[12:, 12:] = np.diag(modes["lam"])
    Mr = np.eye(12 + n)
    Mr[:12, :12] = red["M_B"]
    Mr[:12, 12:] = modes["Mbq"]
    Mr[12:, :12] = modes["Mbq"].T
    return Kr, Mr


def _frequencies(K: np.ndarray, M: np.ndarray, skip: int) -> np.ndarray:
    """Frequencies [Hz] of (K, M) past the ``skip`` lowest (rigid) ones."""
    with threadpool_limits(limits=1, user_api="blas"):
        ev = eigh(K, M, eigvals_only=True)[skip:]
    return np.sqrt(np.maximum(ev, 0.0)) / (2 * np.pi)


def chain_frequencies(red: dict) -> tuple:
    """The chain's frequencies [Hz], free (its six rigid modes left out) and held at its start."""
    K, M = red["chain"]["K"], red["chain"]["M"]
    return _frequencies(K, M, 6), _frequencies(K[6:, 6:], M[6:, 6:], 0)


def reduction_error(red: dict, modes: dict, band: float, full: tuple = None) -> tuple:
    """The largest relative error of the reduced link's frequencies below ``band`` [Hz] against
    its chain's (``full``: chain_frequencies, computed if None), free and held at its start (the
    two ways a link's own modes show), and how many chain frequencies lie below the band. Ritz
    bounds: the error only falls as modes are added."""
    full = chain_frequencies(red) if full is None else full
    Kr, Mr = reduced_matrices(red, modes)
    worst, count = 0.0, 0
    for f, sub in ((full[0], lambda: _frequencies(Kr, Mr, 6)),
                   (full[1], lambda: _frequencies(Kr[6:, 6:], Mr[6:, 6:], 0))):
        k = int(np.sum(f <= band))
        count = max(count, k)
        if k == 0:
            continue
        g = sub()
        if len(g) < k:
            return np.inf, count
        worst = max(worst, float(np.max(np.abs(g[:k] / f[:k] - 1.0))))
    return worst, count


def choose_modes(red: dict, band: float, tolerance: float) -> tuple:
    """The fewest fixed-interface modes (interior_modes) for which reduction_error at ``band``
    is within ``tolerance``: (n, error, modes). All the chain's interior modes reproduce it to
    round-off, so a choice always exists."""
    total = len(red["chain"]["interior"])
    full = chain_frequencies(red)
    n = 0
    while True:
        modes = interior_modes(red, n)
        err, _ = reduction_error(red, modes, band, full)
        if err <= tolerance or n >= total:
            return n, err, modes
        # every mode below twice the band at least (they converge the in-band ones), then one more
        below = int(np.sum(modes["frequency"] <= 2.0 * band))
        n = min(total, max(n + 1, below if n < below else n + 1))


def chain_weights(car: list, g: np.ndarray) -> np.ndarray:
    """The chain's weights under gravity g (its start frame's axes) as generalized forces on its
    nodes' body perturbations, 6 per node: (c_k x f_k, f_k), f_k = m_k R_k^T g, at the
    unstressed shape (c_k: the node's centre of mass, the section's)."""
    w = np.zeros(6 * len(car))
    for k, c in enumerate(car):
        f = c["mass"] * np.asarray(c["H0"])[:3, :3].T @ g
        w[6 * k:6 * k + 3] = np.cross(c["com"], f)
        w[6 * k + 3:6 * k + 6] = f
    return w


def gravity_sag_error(m, K: np.ndarray, gravity: tuple, K_end: np.ndarray, length: float) -> float:
    """How far the gravity points put the end of the link held at its start, against the chain
    (linear statics, the three directions of g, the end's rotation scaled by the length): the
    largest difference over the largest sag (an axial g barely moves the end: its own relative
    error means nothing). Round-off for a straight link; the measure of the gravity warning
    (Mechanism._build)."""
    (_, _, _), (m_b, c_b, _) = gravity
    Rb = np.asarray(m._car[-1]["H0"])[:3, :3]
    scale = np.r_[length, length, length, 1.0, 1.0, 1.0]
    worst = big = 0.0
    for j in range(3):
        g = np.eye(3)[j]
        full = np.linalg.solve(K[6:, 6:], chain_weights(m._car, g)[6:])[-6:]
        f = m_b * Rb.T @ g
        red = np.linalg.solve(K_end, np.r_[np.cross(c_b, f), f])
        worst = max(worst, np.linalg.norm(scale * (red - full)))
        big = max(big, np.linalg.norm(scale * full))
    return float(worst / max(big, 1e-300))


def gravity_points(m, T: np.ndarray, X0: np.ndarray) -> tuple:
    """Where gravity acts on a modal link: a point mass on each end carrier whose weight is the
    static condensation T^T w of the chain's weights (node k: (0, m_k R_k^T g) in its body
    frame, at the unstressed shape) for every direction of g: so the reduced link's gravity
    load is the chain's, condensed (Guyan's consistent load). The forces give the masses (half
    the link's each); the moments give the two points by least squares over the three
    directions, constrained to keep the chain's centre of mass (exact when the condensed
    moments are those of points, as for a straight uniform link: the points sit at L/6 from each
    end, the consistent load's end moments w L^2 / 12). Returns ((m_start, c_start, miss_start),
    (m_end, c_end, miss_end)), c in each end's frame, miss the relative misfit of that end's
    weights and moments, the larger (0 for a straight uniform link; a curved or pre-twisted
    link's condensed weight is not that of any point; what that does to the sag is
    _gravity_sag_error's)."""
    car = m._car
    nodes = [np.asarray(c["H0"]) for c in car]          # the link alone: start at identity
    wB = [T.T @ chain_weights(car, np.eye(3)[j]) for j in range(3)]
    Tb = se3.exp(X0)
    masses, blocks, rhs, forces, e_bodies = [], [], [], [], []
    for end, R in ((0, np.eye(3)), (1, Tb[:3, :3])):
        f = np.array([wB[j][6 * end + 3:6 * end + 6] for j in range(3)])      # (3 dirs, 3)
        tau = np.array([wB[j][6 * end:6 * end + 3] for j in range(3)])
        e_body = np.array([R.T @ np.eye(3)[j] for j in range(3)])           # g_j in the end's axes
        mass = float(np.mean(np.einsum("ji,ji->j", f, e_body)))
        masses.append(mass)
        forces.append(f)
        e_bodies.append(e_body)
        blocks.append(np.vstack([-mass * se3.hat(e) for e in e_body]))      # tau_j = c x (mass e_j)
        rhs.append(tau.reshape(-1))
    # minimize |A_a c_a - tau_a|^2 + |A_b c_b - tau_b|^2 subject to the centre of mass:
    # m_a c_a + m_b (R_b c_b + p_b) = sum_k m_k p_k
    mtot = sum(c["mass"] for c in car)
    com = sum(c["mass"] * (Hk[:3, :3] @ c["com"] + Hk[:3, 3]) for c, Hk in zip(car, nodes)) / mtot
    A = np.zeros((18, 6))
    A[:9, :3], A[9:, 3:] = blocks
    b = np.concatenate(rhs)
    C = np.hstack([masses[0] * np.eye(3), masses[1] * Tb[:3, :3]])
    d = mtot * com - masses[1] * Tb[:3, 3]
    K = np.block([[A.T @ A, C.T], [C, np.zeros((3, 3))]])
    sol = np.linalg.lstsq(K, np.concatenate([A.T @ b, d]), rcond=None)[0]
    out = []
    for end in range(2):
        c = sol[3 * end:3 * end + 3]
        r = blocks[end] @ c - rhs[end]
        f_fit = masses[end] * e_bodies[end]                                  # the point's weights
        miss = max(np.linalg.norm(r) / max(np.linalg.norm(rhs[end]), 1e-300),
                   np.linalg.norm(forces[end] - f_fit) / max(np.linalg.norm(forces[end]), 1e-300))
        out.append((masses[end], c, float(miss)))
    return tuple(out)


#: Southwell's coefficient of a uniform cantilever's first bending mode: spinning at Omega about
#: an axis through its root, omega^2 = omega_0^2 + 1.19 Omega^2 (centrifugal stiffening)
SOUTHWELL = 1.19


def _beyond_linear(name: str, where: str, theta: float, u: float, tolerance: float) -> list:
    """modal_validity's deflection message: rotation theta [rad] and displacement u (a share of
    the length) whose square, the linear model's error, exceeds the tolerance."""
    big = max(theta, u)
    if big * big <= tolerance:
        return []
    return [f"modal link {name!r} deflects by up to {theta:.3g} rad and {u:.3g} of its length "
            f"{where}: a modal link is linear in that deflection, its error of order "
            f"{big * big:.2g} (above the tolerance {tolerance:g}); use fidelity='nonlinear' for it"]


def modal_validity(result, link, T0: np.ndarray, tolerance: float) -> list:
    """What a simulation asked of a modal link beyond what it models (docs/method.md section
    4.10): messages for the AccuracyWarning of Mechanism.simulate. ``T0``: the unstressed pose
    of its end on its start, exp(L eps_hat); ``tolerance``: the relative frequency error the
    Mechanism accepts.

    - spin: the link's rotation rate Omega (its start's, about axes across its chord, the largest
      over the run) against its
      first frequency held at its start, omega_1: centrifugal stiffening, which a modal link
      lacks, raises that frequency by sqrt(1 + 1.19 (Omega/omega_1)^2) - 1 (Southwell's
      coefficient for a uniform cantilever); warned when that exceeds ``tolerance``;
    - deflection: the end's rotation and displacement relative to the start carried rigidly,
      theta and |u|/L: the reduction is linear in them, its error of order their square;
      warned when max(theta, |u|/L)^2 exceeds ``tolerance``; likewise inside the link, the sum
      over its fixed-interface modes of |s_j| times the mode's peak displacement (/L) and
      rotation per unit of s_j (an upper bound of the interior deflection)."""
    a, b = link.nodes[0], link.nodes[-1]
    try:
        cols = result._columns([a, b])
    except Exception:   # noqa: BLE001 -- the link was not recorded: nothing to check
        return []
    out = []
    om1 = link.clamped_frequency * 2.0 * np.pi
    # spin about the chord (the link's own axis) does not stiffen its bending: only the rest
    chord = T0[:3, 3] / max(np.linalg.norm(T0[:3, 3]), 1e-300)          # start-frame axes
    w = result.twists[:, cols[0], :3]
    spin = float(np.max(np.linalg.norm(w - np.outer(w @ chord, chord), axis=1)))
    rise = np.sqrt(1.0 + SOUTHWELL * (spin / om1) ** 2) - 1.0
    if rise > tolerance:
        out.append(f"modal link {link.name!r} spins at up to {spin:.3g} rad/s, {spin / om1:.3g} "
                   f"times its first frequency held at its start ({om1:.3g} rad/s), across its "
                   f"axis: the "
                   f"centrifugal stiffening a modal link leaves out raises that frequency by about "
                   f"{100 * rise:.3g} % (above the tolerance {tolerance:g}); use "
                   f"fidelity='nonlinear' for it")
    Ha, Hb = result.poses[:, cols[0]], result.poses[:, cols[1]]
    rel = np.linalg.inv(Ha @ T0) @ Hb
    c = np.clip((np.trace(rel[:, :3, :3], axis1=1, axis2=2) - 1.0) / 2.0, -1.0, 1.0)
    theta = float(np.max(np.arccos(c)))
    u = float(np.max(np.linalg.norm(rel[:, :3, 3], axis=1))) / link.length
    out += _beyond_linear(link.name, "between its ends", theta, u, tolerance)
    if link.sliders:
        # its modes' deflection inside, bounded by the sum of their peaks (slider coordinates s)
        s = np.abs(np.stack([result.joint(f"{link.name}.mode{j + 1}")["x"][:, 0]
                             for j in range(len(link.sliders))], axis=1))
        peak = np.asarray(link.modal_peaks)
        out += _beyond_linear(link.name, "inside, in its fixed-interface modes",
                              float(np.max(s @ peak[:, 1])),
                              float(np.max(s @ peak[:, 0])) / link.length, tolerance)
    return out


def damping_coupling(modes: dict) -> float:
    """The largest damping coupling a modal link leaves out, as a correlation: |D_ij| /
    sqrt(D_ii D_jj) over the modes' off-diagonal entries (Phi^T D Phi) and over the ends' static
    shapes with the modes (T^T D Phi), 0 for a damping proportional to the stiffness. Entries
    and directions below 1e-10 of the largest damping are round-off and left out (a damped
    direction's coupling with an undamped one is itself zero for a positive semidefinite D)."""
    Dqq, Dbq, dbb = modes["Dqq"], modes["Dbq"], modes["Dbb"]
    dq = np.diag(Dqq)
    if not len(dq):
        return 0.0
    diag = np.concatenate([np.abs(dq), np.abs(dbb)])
    floor = 1e-10 * max(float(diag.max()), 1e-300)
    worst = 0.0
    for X, r, c in ((Dqq - np.diag(dq), dq, dq), (Dbq, dbb, dq)):
        den = np.sqrt(np.outer(np.abs(r), np.abs(c)))
        ok = (den > floor) & (np.abs(X) > floor)
        if np.any(ok):
            worst = max(worst, float(np.max(np.abs(X[ok]) / den[ok])))
    return worst


#: a slider's inertia across its axis, relative to its modal mass (and times the link length
#: squared for rotations): the slider moves with the link's start there (its pair holds it), and
#: its carrier needs a positive definite inertia; the same inertia is taken back through its
#: coupling with the start, so that the kinetic energy of the pair's motion is unchanged. Left:
#: 1/2 EPS mu s^2 |e x omega|^2 (the slider's offset s along e turning with the start at omega),
#: a 1e-9 share of a mode's kinetic energy at the rotation rates a modal link stays valid at.
#: Measured on a cantilever with 60 modes (372 coordinates): at 1e-6 the sparse modes path found
#: its KKT matrix singular and the dense one, which AUTO fell back to, gave the five frequencies
#: to 1.2e-8 (80 modes: 1.9e-7); at 1e-9 the sparse path gives 8.7e-11 at 40-80 modes.
SLIDER_EPS = 1e-9
#: what a link's start keeps of its gravity mass when its sliders take theirs (share of it)
SLIDER_GRAVITY_SHARE = 0.5


def modal_sliders(red: dict, modes: dict, length: float) -> dict:
    """The modal coordinates of a reduced link as sliders (docs/method.md section 4.10): mode j
    is the displacement s_j = alpha_j q_j of a carrier that slides along the unit axis e_j of the
    link's start frame (a prismatic pair holds it to the start: same orientation, origin at
    s_j e_j), so that every stage of phmech carries it as a carrier. Its rate is
    q_j' = u_j . (t_j - t_a), u_j = (0, e_j) / alpha_j, a constant linear map of the two body
    twists, so the Craig-Bampton kinetic energy

        T = 1/2 [t_a; t_b]^T M_B [t_a; t_b] + [t_a; t_b]^T Mbq q' + 1/2 q'^T q'

    becomes a constant quadratic form in the body twists of the start, the end and the sliders:
    its diagonal blocks the carriers' inertias, the (start, end) block the element's coupling and
    the others couplings without an element (csrc/include/phmech_types.h, phm_coupling_desc). Its
    stiffness lam_j q_j^2 / 2 and damping are a spring-damper along the slider (collinear, so
    exactly linear in s_j). Gravity: the slider carries a point mass m_j at its origin, so its
    weight's potential -m_j s_j e_j . R_a^T g is the modal one, -q_j Cg_j . R_a^T g, when
    e_j = Cg_j / |Cg_j| and m_j alpha_j = |Cg_j|; the start's point mass gives up m_j at its
    origin (its first moment kept). alpha_j = max(|Cg_j| / m_g, 1/sqrt(link mass)), m_g a share
    of the start's gravity mass: the slider's mass 1/alpha_j^2 stays below the link's. A mode
    without weight (|Cg_j| ~ 0) slides along x, with alpha_j = 1/sqrt(link mass).

    Returns the carriers' inertias ``M_start``, ``M_end`` and ``sliders`` (one dict per mode:
    ``M`` 6x6, ``axis`` e_j, ``alpha``, ``gravity_mass``, ``couplings`` {'start', 'end', k (an
    earlier slider)}: 12x12 on [t_other; t_j], ``k``, ``c`` [N/m, N s/m], ``peak``: the mode's
    largest displacement [m] and rotation [rad] inside the link per metre of s_j), the element's coupling
    ``Mc``, the mass ``gravity_taken`` from the start, ``damping_coupling``: the damping coupling
    left out (damping_coupling), and ``mismatch``: the largest
    difference, relative to its largest entry, between the Craig-Bampton mass of
    reduced_matrices and the sliders' quadratic form restricted to the motions their pairs allow
    (round-off for a well-conditioned model)."""
    n = len(modes["lam"])
    (m_start, _, _), _ = red["gravity"]
    mass = float(np.trace(red["M_B"][3:6, 3:6] + red["M_B"][9:12, 9:12]) / 3.0 +
                 2.0 * np.trace(red["M_B"][3:6, 9:12]) / 3.0)
    mass = max(mass, 1e-300)
    Cg = modes["Cg"]
    cnorm = np.linalg.norm(Cg, axis=1) if n else np.zeros(0)
    heavy = cnorm > 1e-8 * np.sqrt(mass)
    m_g = SLIDER_GRAVITY_SHARE * m_start / max(int(np.sum(heavy)), 1)
    N = 6 * (2 + n)
    F = np.zeros((N, N))
    F[:12, :12] = red["M_B"]
    sliders = []
    for j in range(n):
        # alpha at least 1/sqrt(link mass): a mode with a small weight would otherwise get a tiny
        # alpha, a slider mass 1/alpha^2 many orders above the link's and an ill-conditioned
        # model (measured: a curved link's modes with |Cg| ~ 1e-6 put its frequencies 10 % off)
        alpha = 1.0 / np.sqrt(mass)
        if heavy[j]:
            alpha = max(cnorm[j] / m_g, alpha)
            e, mg = Cg[j] / cnorm[j], cnorm[j] / alpha
        else:
            e, mg = np.array([1.0, 0.0, 0.0]), 0.0
        E = np.concatenate([np.zeros(3), e])
        u = E / alpha
        mu = float(u @ u)
        A, B, J = slice(0, 6), slice(6, 12), slice(12 + 6 * j, 18 + 6 * j)
        ma, mb = modes["Mbq"][:6, j], modes["Mbq"][6:, j]
        F[A, J] += np.outer(ma, u) - np.outer(u, u)
        F[J, A] += np.outer(u, ma) - np.outer(u, u)
        F[B, J] += np.outer(mb, u)
        F[J, B] += np.outer(u, mb)
        F[A, A] += np.outer(u, u) - np.outer(ma, u) - np.outer(u, ma)
        F[B, A] -= np.outer(mb, u)
        F[A, B] -= np.outer(u, mb)
        F[J, J] += np.outer(u, u)
        R = SLIDER_EPS * mu * np.diag(np.r_[np.full(3, length ** 2), np.ones(3)])
        R[3:, 3:] -= SLIDER_EPS * mu * np.outer(e, e)
        F[J, J] += R
        F[A, A] += R
        F[A, J] -= R
        F[J, A] -= R
        sliders.append(dict(axis=e, alpha=alpha, gravity_mass=mg, k=modes["lam"][j] / alpha ** 2,
                            c=max(modes["Dqq"][j, j], 0.0) / alpha ** 2,
                            peak=modes["peak"][j] / alpha, kinds=modes["kinds"][j]))
    F = 0.5 * (F + F.T)
    # what the sliders' pairs let move, (t_a, t_b, q'), mapped back: the Craig-Bampton mass
    P = np.zeros((N, 12 + n))
    P[:12, :12] = np.eye(12)
    for j, sl in enumerate(sliders):
        P[12 + 6 * j:18 + 6 * j, :6] = np.eye(6)
        P[15 + 6 * j:18 + 6 * j, 12 + j] = sl["axis"] * sl["alpha"]
    _, Mr = reduced_matrices(red, modes)
    mismatch = float(np.max(np.abs(P.T @ F @ P - Mr)) / max(np.max(np.abs(Mr)), 1e-300))
    blk = lambda X, i, k: X[6 * i:6 * i + 6, 6 * k:6 * k + 6]
    Mc = np.zeros((12, 12))
    Mc[:6, 6:], Mc[6:, :6] = blk(F, 0, 1), blk(F, 1, 0)
    for j, sl in enumerate(sliders):
        sl["M"] = blk(F, 2 + j, 2 + j).copy()
        sl["couplings"] = {}
        for other, i in [("start", 0), ("end", 1)] + [(k, 2 + k) for k in range(j)]:
            X = blk(F, i, 2 + j)
            if np.any(X):
                C = np.zeros((12, 12))
                C[:6, 6:], C[6:, :6] = X, X.T
                sl["couplings"][other] = C
    dbq = damping_coupling(modes)
    return dict(M_start=blk(F, 0, 0).copy(), M_end=blk(F, 1, 1).copy(), Mc=Mc, sliders=sliders,
                gravity_taken=float(sum(s["gravity_mass"] for s in sliders)), damping_coupling=dbq,
                mismatch=mismatch)

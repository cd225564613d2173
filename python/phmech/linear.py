"""The linear port-Hamiltonian model of a mechanism about an equilibrium (Mechanism.linearize):
the C core's reduced stiffness, damping and mass on the constraint manifold and the ports' input
matrix (csrc/analyze/linear_model.c, phm_linear_model), assembled here into (J, R, Q, B, C, D), with a
passivity check and conversions to scipy.signal and python-control (docs/method.md section 7.4,
docs/user_guide.md "Linear port-Hamiltonian model")."""
from __future__ import annotations

import dataclasses
from typing import List, Optional

import numpy as np

from ._errors import ModelError
from .components import state_layout
from .frames import Body, Frame, frame_of
from .sensors import SENSOR_TYPES, joint_pair, output_row, sensor_rows

__all__ = ["LinearPortHamiltonian", "Passivity"]

#: the round-off of Q's blocks' relative eigenvalues (Passivity.Q_min): above it positive, within
#: +-Q_RESOLVED zero
Q_RESOLVED = 1e3 * np.finfo(float).eps
#: csrc/include/phmech_types.h, PHM_MODES_RESOLVED: the modes the shift-inverted pencil resolves
MODES_RESOLVED = 1e-6


@dataclasses.dataclass(frozen=True)
class Passivity:
    """The numbers of a passivity check (LinearPortHamiltonian.passivity): ``J_skew`` =
    max|J + J^T| / max|J| (0 for a skew-symmetric J), ``R_min`` = the smallest eigenvalue of R
    over its largest magnitude (>= -tol: R positive semidefinite), ``Q_min`` = the smallest
    eigenvalue over the largest of the stiffness block K and of the inverse-mass block M^-1 of Q,
    the smaller of the two (the blocks carry different units, so each is measured against
    itself). Q counts as positive semidefinite -- the energy H = x^T Q x / 2 >= 0, which
    passivity needs -- when Q_min >= -Q_RESOLVED = -1000 eps: LAPACK's eigenvalues are exact to
    about eps times the largest, so a zero eigenvalue (a motion nothing resists, a pendulum's
    stiffness linearized where gravity has no restoring moment) reads anywhere within a few eps
    of 0 (issue 27 reported -8.9e-18; the horizontal pendulum gives 0.0; both read not passive
    before), and a flexible link's blocks are legitimately ill-conditioned (Q_min ~ 1e-10 for
    the leaf spring); it is positive definite (``Q_definite``) when Q_min >
    Q_RESOLVED. ``collocation`` = max|C - B^T Q| / max|B^T Q| (0 when the
    outputs are the inputs' power conjugates; nan otherwise), ``D_min`` the smallest eigenvalue of
    D + D^T (0 here), ``tol`` and the verdict ``passive`` (Q positive semidefinite within
    round-off and the other figures within ``tol``)."""
    J_skew: float
    R_min: float
    Q_min: float
    collocation: float
    D_min: float
    tol: float
    passive: bool
    Q_definite: bool = False


@dataclasses.dataclass(frozen=True)
class LinearPortHamiltonian:
    """dx/dt = (J - R) Q x + B u, y = C x + D u, with the state x = (q, p): q the nr reduced
    displacements (coordinates in the null space Z of the constraint Jacobian, units mixed: rad
    and m along the tangent directions), p = M dq/dt their momenta. The energy is
    H = x^T Q x / 2 = q^T K q / 2 + p^T M^-1 p / 2.

    J = [[0, I], [-I, 0]], R = diag(0, Dr), Q = diag(K, M^-1), B = [0; Bq] with Bq = Z^T F the
    reduced generalized forces per unit input, C = [0, Cq M^-1] with Cq = Fo^T Z the outputs'
    velocity maps (Cq = Bq^T for the default, collocated outputs), D = 0. With sensors among the
    outputs (Mechanism.linearize), C = [Cd, Cq M^-1, Cz]: ``Cd`` (ny x nr) the rows of the
    displacement outputs (joint coordinates, frames' poses and positions, tip deflections,
    strains: their change per unit q), ``Cq`` those of the rates (zero rows for the others),
    ``Cz`` (ny x nz) those of the components' states.

    ``stiffness`` K, ``damping`` Dr, ``mass`` M (nr x nr), ``basis`` Z (6 nc x nr: the reduced
    coordinates as the carriers' tangent coordinates (omega, v), body frames), ``inputs``,
    ``outputs``: one label per column of B and row of C.

    With components (``Mechanism.add_component``: controllers, motors, friction; docs/method.md
    section 7.5) the state is x = (q, p, z), z their nz states (``states``: their labels,
    "name.state"), and their laws linearized at the point, at rest, enter as: the change of
    their reduced generalized forces -Kc dq - Dc dq/dt + Kz dz (``Kc``, ``Dc`` nr x nr, in
    general not symmetric: a non-collocated controller; ``Kz`` nr x nz) and dz/dt = Fq q +
    Fv dq/dt + Fz z (``Fq``, ``Fv`` nz x nr, ``Fz`` nz x nz). ``A`` is then the closed loop,
    (J - R) Q + ``A_components``; J, R, Q, ``frequencies()`` and ``passivity()`` stay the
    mechanism's own (a controller is in general not passive), B and C get nz zero rows and
    columns. ``poles()``: the eigenvalues of A. ``rest_force``: Z^T of every generalized force at
    the point (the mechanism's and the components'; zero at an equilibrium), ``rest_rates``:
    dz/dt there.

    About a steady rotation (``Mechanism.linearize(spin=...)``, docs/method.md section 7.6) the
    state is that of the frame turning with it: K holds the centrifugal stiffness, and
    ``gyroscopic`` G (nr x nr, skew-symmetric: Coriolis) enters A as M q'' + (D + G) q' + K q
    = 0; ``poles()`` are then the rotating mechanism's."""
    stiffness: np.ndarray
    damping: np.ndarray
    mass: np.ndarray
    basis: np.ndarray
    Bq: np.ndarray
    Cq: np.ndarray
    inputs: List[str]
    outputs: List[str]
    collocated: bool
    Kc: Optional[np.ndarray] = None
    Dc: Optional[np.ndarray] = None
    Kz: Optional[np.ndarray] = None
    Fq: Optional[np.ndarray] = None
    Fv: Optional[np.ndarray] = None
    Fz: Optional[np.ndarray] = None
    states: List[str] = dataclasses.field(default_factory=list)
    rest_force: Optional[np.ndarray] = None
    rest_rates: Optional[np.ndarray] = None
    rest_force_components: Optional[np.ndarray] = None
    rest_states: Optional[np.ndarray] = None
    gyroscopic: Optional[np.ndarray] = None
    rest_scale: float = 0.0
    Cd: Optional[np.ndarray] = None
    Cz: Optional[np.ndarray] = None

    def at_rest(self, rtol: float = 1e-6) -> tuple:
        """(ok, reason): whether the point is a rest state of the mechanism with its components
        (or in its steady rotation) -- the reduced generalized forces ``rest_force`` vanish
        within ``rtol`` of ``rest_scale``, the largest constraint, centrifugal or component
        wrench there (or within the round-off 100 eps max|K| of the stiffness, at least 1e-12 N
        or N m, when there are none), and the components' states are still
        (abs(dz/dt) <= rtol (1 + abs(z)) [unit of z per s]). Without components and spin:
        (True, "")."""
        if self.rest_force is None:
            return True, ""
        f, scale = self.rest_force, self.rest_scale
        bad = np.abs(f).max(initial=0.0)
        floor = max(1e-12, 100 * np.finfo(float).eps * np.abs(self.stiffness).max(initial=0.0))
        if bad > max(rtol * scale, floor):
            i = int(np.argmax(np.abs(f)))
            return False, (f"the generalized forces with the components' efforts do not balance: "
                           f"{bad:.3g} in reduced coordinate {i} (of {scale:.3g} applied)")
        zr = np.abs(self.rest_rates) - rtol * (1 + np.abs(self.rest_states))
        if zr.size and zr.max() > 0:
            i = int(np.argmax(zr))
            return False, (f"the component state {self.states[i]!r} moves: dz/dt = "
                           f"{self.rest_rates[i]:.3g} per s there")
        return True, ""

    @property
    def nz(self) -> int:
        """The components' states (0 without components)."""
        return 0 if self.Fz is None else self.Fz.shape[0]

    @property
    def A_components(self) -> np.ndarray:
        """The components' part of A over x = (q, p, z) ((2 nr + nz) square; zero without
        components)."""
        n, nz = self.nr, self.nz
        out = np.zeros((2 * n + nz, 2 * n + nz))
        if self.gyroscopic is not None:
            out[n:2 * n, n:2 * n] = -self.gyroscopic @ self._minv
        if self.Kc is None:
            return out
        Mi = self._minv
        out[n:2 * n, :n] = -self.Kc
        out[n:2 * n, n:2 * n] -= self.Dc @ Mi
        out[n:2 * n, 2 * n:] = self.Kz
        out[2 * n:, :n] = self.Fq
        out[2 * n:, n:2 * n] = self.Fv @ Mi
        out[2 * n:, 2 * n:] = self.Fz
        return out

    def poles(self) -> np.ndarray:
        """The eigenvalues s [1/s] of A (the closed loop with the components), by ascending
        magnitude: a pole with Re s > 0 is unstable; s = -zeta omega +- i omega sqrt(1 - zeta^2)
        for a mode of natural frequency omega [rad/s] and damping ratio zeta."""
        s = np.linalg.eigvals(self.A).astype(complex)
        return s[np.lexsort((s.imag, np.abs(s)))]

    @property
    def nr(self) -> int:
        """Reduced coordinates (degrees of freedom)."""
        return self.stiffness.shape[0]

    @property
    def J(self) -> np.ndarray:
        n = self.nr
        return np.block([[np.zeros((n, n)), np.eye(n)], [-np.eye(n), np.zeros((n, n))]])

    @property
    def R(self) -> np.ndarray:
        n = self.nr
        Z = np.zeros((n, n))
        return np.block([[Z, Z], [Z, self.damping]])

    @property
    def Q(self) -> np.ndarray:
        n = self.nr
        Z = np.zeros((n, n))
        return np.block([[self.stiffness, Z], [Z, self._minv]])

    @property
    def _minv(self) -> np.ndarray:
        Mi = np.linalg.inv(self.mass)
        return 0.5 * (Mi + Mi.T)

    @property
    def B(self) -> np.ndarray:
        return np.vstack([np.zeros_like(self.Bq), self.Bq, np.zeros((self.nz, self.Bq.shape[1]))])

    @property
    def C(self) -> np.ndarray:
        """[Cd, Cq M^-1, Cz] over x = (q, p, z): y = Cd q + Cq dq/dt + Cz z."""
        ny = self.Cq.shape[0]
        return np.hstack([np.zeros_like(self.Cq) if self.Cd is None else self.Cd,
                          self.Cq @ self._minv,
                          np.zeros((ny, self.nz)) if self.Cz is None else self.Cz])

    @property
    def D(self) -> np.ndarray:
        return np.zeros((self.Cq.shape[0], self.Bq.shape[1]))

    @property
    def A(self) -> np.ndarray:
        """(J - R) Q, and with components the closed loop (J - R) Q + A_components over
        x = (q, p, z)."""
        A = (self.J - self.R) @ self.Q
        if not self.nz and self.Kc is None and self.gyroscopic is None:
            return A
        n = 2 * self.nr
        out = self.A_components
        out[:n, :n] += A
        return out

    def frequencies(self) -> np.ndarray:
        """Undamped natural frequencies [Hz], ascending: sqrt of the eigenvalues of (K, M) / 2 pi
        (negative for a negative eigenvalue: unstable, as ModesResult.frequency)."""
        from scipy.linalg import LinAlgError, eigh

        K, M = self.stiffness, self.mass
        # as modes() (csrc/analyze/modes.c): the shift-inverted pencil M y = theta (K - sigma M) y
        # for the modes it resolves (theta above MODES_RESOLVED of the largest: the lowest modes,
        # to ~eps relative), the direct pencil for the others and when K - sigma M is indefinite
        lam = eigh(K, M, eigvals_only=True)
        trK, trM = np.trace(K), np.trace(M)
        sigma = -1e-9 * trK / trM if trK > 0 and trM > 0 else -1.0
        try:
            theta = eigh(M, K - sigma * M, eigvals_only=True)[::-1]
        except LinAlgError:
            theta = np.zeros(1)
        if theta[-1] > 0:
            ok = theta > MODES_RESOLVED * theta[0]
            lam[ok] = sigma + 1.0 / theta[ok]
        return np.sign(lam) * np.sqrt(np.abs(lam)) / (2 * np.pi)

    def passivity(self, tol: float = 1e-9) -> Passivity:
        """Check J = -J^T, R >= 0, Q >= 0 (and, for collocated outputs, C = B^T Q, D + D^T >= 0)
        within the relative tolerance ``tol`` (Q within round-off, Q_RESOLVED, relative to each
        block's largest eigenvalue); returns the numbers (Passivity)."""
        J, R = self.J, self.R
        js = float(np.abs(J + J.T).max() / np.abs(J).max())
        er = np.linalg.eigvalsh(R)
        rmin = float(er.min() / max(np.abs(er).max(), 1e-300))
        qmin = np.inf
        for blk in (self.stiffness, self._minv):
            e = np.linalg.eigvalsh(blk)
            qmin = min(qmin, float(e.min() / max(np.abs(e).max(), 1e-300)))
        if self.collocated:
            n = 2 * self.nr                      # the mechanism's part (not its components')
            BQ = self.B[:n].T @ self.Q
            col = float(np.abs(self.C[:, :n] - BQ).max() / max(np.abs(BQ).max(), 1e-300))
        else:
            col = float("nan")
        dmin = float(np.linalg.eigvalsh(self.D + self.D.T).min()) if self.D.size else 0.0
        ok = js <= tol and rmin >= -tol and qmin >= -Q_RESOLVED and dmin >= -tol and \
            (not self.collocated or col <= tol)
        return Passivity(js, rmin, qmin, col, dmin, tol, bool(ok), bool(qmin > Q_RESOLVED))

    def displacement(self, x) -> np.ndarray:
        """The carriers' tangent displacements (nc, 6) (omega, v in body axes: H = H0 exp(xi))
        of states ``x`` (2 nr,) or (nt, 2 nr) -> (nc, 6) or (nt, nc, 6)."""
        x = np.asarray(x, dtype=float)
        q = x[..., :self.nr]
        xi = q @ self.basis.T
        return xi.reshape(xi.shape[:-1] + (-1, 6))

    def to_statespace(self):
        """scipy.signal.StateSpace(A, B, C, D)."""
        from scipy.signal import StateSpace

        return StateSpace(self.A, self.B, self.C, self.D)

    def to_control(self):
        """python-control ``StateSpace`` with the ports' names as input and output names ('.'
        written '_': python-control refuses dots) (needs the optional package ``control``: pip install control)."""
        try:
            import control
        except ImportError:
            raise ModelError("to_control needs python-control (pip install control; or "
                             "pip install phmech[control]); to_statespace() needs only SciPy") from None
        n = self.nr
        states = [f"q{i}" for i in range(n)] + [f"p{i}" for i in range(n)] + [z.replace(".", "_") for z in self.states]
        name = lambda s: s.replace(".", "_")                       # noqa: E731 ('.' is refused)
        return control.ss(self.A, self.B, self.C, self.D, inputs=[name(s) for s in self.inputs],
                          outputs=[name(s) for s in self.outputs], states=states)


# ------------------------------------------------------------------------------- ports by name
PORT_PAIR, PORT_LOAD, PORT_FRAME = 0, 1, 2   # csrc/include/phmech_types.h, PHM_PORT_*


def resolve_ports(desc, items, what: str) -> tuple:
    """Ports given by name (or Frame/Body) -> (core ports [(kind, index, T)], groups, labels):
    ``groups[i]`` the core columns summed into input/output column i. Names: a pair (its k joint
    efforts [N m or N] / joint rates), an actuator (its pair's), a wrench or interaction (its
    wrench per unit law value / the power-conjugate velocity), a distributed load (all its
    nodes' loads together), a body's name (a wrench (tau, f) in its axes / its body twist)."""

    if isinstance(items, (str, Frame, Body)):
        items = [items]
    if not isinstance(items, (list, tuple)):
        raise ModelError(f"{what}: expected a list of port names (got {type(items).__name__})")
    pairs = {e["name"]: i for i, e in enumerate(desc.pairs)}
    acts = {a["name"]: a["pair"] for a in desc.actuators}
    loads = {ld["name"]: i for i, ld in enumerate(desc.loads)}
    ports, groups, labels = [], [], []
    col = 0

    def add(kind, index, T, ncols, names):
        nonlocal col
        ports.append((kind, index, np.asarray(T, dtype=float)))
        for j, nm in enumerate(names):
            groups.append([col + j])
            labels.append(nm)
        col += ncols

    for x in items:
        if isinstance(x, str) and (x in pairs or x in acts):
            ip = pairs[x] if x in pairs else acts[x]
            k = desc.pairs[ip]["k"]
            if k == 0:
                raise ModelError(f"{what}: pair {x!r} is a Fixed pair: it has no joint coordinates "
                                 f"to act on or measure")
            add(PORT_PAIR, ip, np.eye(4), k, [x] if k == 1 else [f"{x}[{j}]" for j in range(k)])
        elif isinstance(x, str) and x in loads:
            add(PORT_LOAD, loads[x], np.eye(4), 1, [x])
        elif isinstance(x, str) and f"{x}[0]" in loads:            # a distributed load
            idx = [i for n, i in loads.items() if n.startswith(x + "[") and n.endswith("]")]
            first = col
            for i in idx:
                ports.append((PORT_LOAD, i, np.eye(4)))
            col += len(idx)
            groups.append(list(range(first, col)))
            labels.append(x)
        elif isinstance(x, (Frame, Body)) or (isinstance(x, str) and x in desc.bodies):
            f = frame_of(x, desc, what)
            if f.carrier < 0:
                raise ModelError(f"{what}: the ground does not move: no port")
            nm = f.name or f"carrier{f.carrier}"
            add(PORT_FRAME, f.carrier, f.T, 6, [f"{nm}.{c}" for c in ("tau_x", "tau_y", "tau_z", "f_x", "f_y", "f_z")])
        else:
            avail = sorted([n for n, i in pairs.items() if desc.pairs[i]["k"] > 0]) + sorted(acts) + \
                sorted(loads) + sorted(desc.bodies)
            sens = f"; or its sensors (add_sensor): {', '.join(map(repr, desc.sensors)) or 'none'}, " \
                f"or sensor objects (JointSensor, FrameSensor, ...)" if "outputs" in what else ""
            raise ModelError(f"{what}: unknown port {x!r}; ports are pairs with joint coordinates, "
                             f"actuators, wrenches, interactions and bodies (or Frame objects) of "
                             f"this mechanism: {', '.join(map(repr, avail)) or 'none'}{sens}")
    return ports, groups, labels


def output_labels(labels: List[str]) -> List[str]:
    """The power conjugates' names of input labels: efforts -> rates, wrenches -> twists."""
    out = []
    for s in labels:
        for a, b in ((".tau_", ".omega_"), (".f_", ".v_")):
            if a in s:
                s = s.replace(a, b)
                break
        else:
            s = s + ".rate"
        out.append(s)
    return out


def component_states(desc) -> List[str]:
    """The labels "name.state" of the components' states in the core's order
    (components.state_layout)."""
    rows = {r["name"]: r for r in desc.components}
    out = [""] * sum(r["nstates"] for r in rows.values())
    for nm, (first, count) in state_layout(desc.components).items():
        for j in range(count):
            out[first + j] = f"{nm}.{rows[nm]['states'][j]}"
    return out


def initial_states(desc) -> np.ndarray:
    """The components' initial states (nz,) in the core's order (components.state_layout)."""
    rows = {r["name"]: r for r in desc.components}
    out = np.zeros(sum(r["nstates"] for r in rows.values()))
    for nm, (first, count) in state_layout(desc.components).items():
        out[first:first + count] = rows[nm]["z0"][:count]
    return out


def _outputs(desc, outputs) -> tuple:
    """(core ports, entries, labels) of linearize's ``outputs``: per item ("port", its groups of
    core columns, None) or ("sensor", the groups of its pair's columns (a JointSensor) or None,
    its sensor row)."""
    items = [outputs] if isinstance(outputs, (str, Frame, Body) + SENSOR_TYPES) else outputs
    if not isinstance(items, (list, tuple)):
        raise ModelError(f"linearize outputs: expected a list of port names, sensor names or "
                         f"sensors (got {type(outputs).__name__})")
    ports, entries, labels, col = [], [], [], 0
    for x in items:
        sens = output_row(desc, x)
        groups, row = None, None
        if sens is None:
            p, g, lab = resolve_ports(desc, [x], "linearize outputs")
            lab = output_labels(lab)
        else:
            (row, lab), p, g = sens, [], []
            if row["kind"] == "joint":
                name, j0 = joint_pair(desc, row["cols"][0])
                p, g, _ = resolve_ports(desc, [name], "linearize outputs")
                groups = [[col + g[c - j0][0]] for c in row["cols"]]
        if sens is None:
            groups = [[col + j for j in gi] for gi in g]
        entries.append(("port" if sens is None else "sensor", groups, row))
        ports += p
        labels += lab
        col += 1 + max((j for gi in g for j in gi), default=-1)
    return ports, entries, labels


def _output_rows(desc, entries, Fo: np.ndarray, Z: np.ndarray, poses: np.ndarray,
                 nz: int) -> tuple:
    """(Cq, Cd, Cz): the outputs' rows over dq/dt, q and z (python/phmech/linear.py's C)."""
    nr = Z.shape[1]
    cq, cd, cz = [], [], []
    for kind, groups, row in entries:
        if kind == "port":
            v = np.stack([Fo[:, g].sum(axis=1) for g in groups], axis=0)
            cq.append(v)
            cd.append(np.zeros_like(v))
            cz.append(np.zeros((len(v), nz)))
            continue
        pair = None if groups is None else np.stack([Fo[:, g[0]] for g in groups], axis=0)
        first = state_layout(desc.components)[row["component"]][0] + row["index"] \
            if row["kind"] == "state" else None
        k, r = sensor_rows(row, poses, Z, pair, first)
        n = row["size"]
        zero = np.zeros((n, nr))
        zr = np.zeros((n, nz))
        if k == "z":
            zr[0, r] = 1.0
        cq.append(r if k == "v" else zero)
        cd.append(r if k == "q" else zero)
        cz.append(zr)
    return tuple(np.concatenate(c, axis=0) if c else np.zeros((0, w)) for c, w in
                 ((cq, nr), (cd, nr), (cz, nz)))


def build(core, model, desc, inputs, outputs, poses, lam, time, z=None,
          spin: bool = False, point_poses=None) -> LinearPortHamiltonian:
    """The LinearPortHamiltonian of a core model at poses/lam (None: its initial state, whose
    poses are ``point_poses``, for sensor outputs); with the description's components, their
    linearized laws at their states ``z`` (None: the initial ones); ``spin``: the model turns
    steadily (_core.model_set_spin): its gyroscopic matrix."""
    pin, gin, lin = resolve_ports(desc, inputs, "linearize inputs")
    if outputs is None:
        pout, entries, lout, coll = [], [], output_labels(lin), True
    else:
        pout, entries, lout = _outputs(desc, outputs)
        coll = False
        if spin and any(e[0] == "sensor" for e in entries):
            raise ModelError("linearize outputs: sensors are not outputs about a steady rotation "
                             "(spin); ports are")
    withc = bool(desc.components) or spin
    K, D, M, Z, B, (nr, ncol), *comp = core.model_linear(model, pin + pout, poses, lam, time,
                                                          withc, z)
    nc6 = 6 * len(desc.carriers)
    F = B[:nr * ncol].reshape(nr, ncol)
    nin = sum(len(g) for g in gin)
    Bq = np.stack([F[:, g].sum(axis=1) for g in gin], axis=1) if gin else np.zeros((nr, 0))
    Fo = F[:, nin:]
    extra = {}
    if coll:
        Cq = Bq.T.copy()
    else:
        nz = comp[0][9] if withc else 0
        at = point_poses if poses is None else poses
        Cq, Cd, Cz = _output_rows(desc, entries, Fo, Z[:nc6 * nr].reshape(nc6, nr),
                                  None if at is None else np.asarray(at, dtype=float), nz)
        if any(e[0] == "sensor" for e in entries):
            extra.update(Cd=Cd, Cz=Cz)
    if withc:
        Kc, Dc, Kz, Fq, Fv, Fz, f, fc, zdot, nz, Gy, fmax = comp[0]
        extra.update(Kc=Kc[:nr * nr].reshape(nr, nr), Dc=Dc[:nr * nr].reshape(nr, nr),
                     Kz=Kz[:nr * nz].reshape(nr, nz), Fq=Fq[:nz * nr].reshape(nz, nr),
                     Fv=Fv[:nz * nr].reshape(nz, nr), Fz=Fz.reshape(nz, nz),
                     states=component_states(desc), rest_force=f[:nr].copy(),
                     rest_rates=zdot.copy(), rest_force_components=fc[:nr].copy(),
                     rest_states=initial_states(desc) if z is None else np.asarray(z, float),
                     gyroscopic=Gy[:nr * nr].reshape(nr, nr) if spin else None,
                     rest_scale=float(fmax))
    return LinearPortHamiltonian(
        stiffness=K[:nr * nr].reshape(nr, nr), damping=D[:nr * nr].reshape(nr, nr),
        mass=M[:nr * nr].reshape(nr, nr), basis=Z[:nc6 * nr].reshape(nc6, nr), Bq=Bq, Cq=Cq,
        inputs=lin, outputs=lout, collocated=coll, **extra)

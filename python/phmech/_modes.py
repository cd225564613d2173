"""Mechanism.modes: vibration modes about the initial configuration or a static equilibrium
(``_core.model_modes``: LAPACK or the sparse shift-invert eigensolver of the core), labelled by
their strain energy (phmech.analysis), and the check that the configuration is an equilibrium
(EquilibriumWarning otherwise). Frequencies in Hz, omega in rad/s."""
from __future__ import annotations

import warnings
from typing import Optional

import numpy as np

from . import analysis, _core, linear, _model, se3
from ._checks import integer, real
from ._errors import (AccuracyWarning, EquilibriumWarning, ModelError, SolverError,
                      outside_stacklevel)
from .results import ModesResult, StaticResult


def modes(mech, n: int = 5, at: Optional[StaticResult] = None, time: float = 0.0,
          spin=None) -> ModesResult:
    """Mechanism.modes of the builder ``mech`` (python/phmech/mechanism.py: its docstring
    gives the arguments, their units and what is returned)."""
    if mech._desc.components or spin is not None:
        return closed_loop_modes(mech, n, at, time, spin)
    n = integer("n", n, 1)
    time = real("time", time)
    _model.check_linearization_time(mech, "modes", time, at)
    model, poses, lam, keep = _model.linearization_point_kept(mech, at)
    poses, lam, eq = equilibrium_point(mech, keep, model, poses, lam, time, at)
    where = mech._state.poses if poses is None else poses
    # at most 6 per carrier exist: asking for more allocates no more than that
    om, ze, sh, nf, _ = _core.model_modes(model, min(n, 6 * len(mech._car)), poses, lam, time)
    if nf < len(om):
        om, ze, sh = om[:nf], ze[:nf], sh[:nf]
    if not eq:
        if np.any(om < 0):
            neg = "; its negative eigenvalues lambda show as negative frequencies -sqrt(-lambda)"
        else:
            neg = ("; a negative eigenvalue lambda of the tangent would show as a negative "
                   "frequency -sqrt(-lambda)")
        warnings.warn(f"modes: the configuration is not a static equilibrium ({eq.reason}): "
                      f"the values are the eigenvalues of the tangent stiffness there, not the "
                      f"frequencies of small vibrations about a rest state" + neg +
                      ". For vibrations about the equilibrium use modes(at=m.static(...)).",
                      EquilibriumWarning, stacklevel=outside_stacklevel())
    f, lab = _labels(mech, keep, where, om, sh, at)
    # the link and body tables as they are now (a later add_* makes a new keep): one copy
    # per initial configuration, which its results only read
    tables = keep.get("tables")
    if tables is None:
        tables = keep["tables"] = (dict(mech._links), dict(mech._bodies))
    # positional: a dataclass's keywords cost ~1 us a call here (ModesResult's field order:
    # tests/test_analysis_cache.py checks it)
    return ModesResult(om, f, ze, sh, *lab, np.array(where), bool(eq), None, *tables)

def equilibrium_point(mech, keep: dict, model, poses, lam, time: float,
                      at: Optional[StaticResult]) -> tuple:
    """(poses, lam, eq) of a linearization at linearization_point_kept's ``poses`` and ``lam``
    (None, None: the initial configuration) at ``time`` [s]: ``eq`` its equilibrium check
    (_equilibrium), and at the initial configuration, when the check passes, the equilibrium
    its static solve found there with that equilibrium's constraint wrenches (equilibrium_check
    says why)."""
    eq = _equilibrium(mech, keep, model, mech._state.poses if poses is None else poses, time, at)
    if at is None and eq.poses is not None:
        return eq.poses, eq.lam, eq
    return poses, lam, eq

def _equilibrium(mech, keep: dict, model, poses, time: float, at: Optional[StaticResult]):
    """equilibrium_check of ``poses``; at the initial configuration (``at`` None), or at a
    StaticResult found without extra loads (the model is then the mechanism's), made once per
    time [s] and poses and kept in ``keep`` (the mechanism's _model.built) until the mechanism
    changes."""
    if at is not None and at.loads:
        return equilibrium_check(mech, model, poses, time, True)
    done = keep.get("equilibrium")
    if done is None:
        done = keep["equilibrium"] = {}
    key = (time, None if at is None else np.asarray(poses, dtype=float).tobytes())
    eq = done.get(key)
    if eq is None:
        eq = done[key] = equilibrium_check(mech, model, poses, time, at is not None)
    return eq

#: analysis.label_modes' fields, in the order of ModesResult's fields after ``shapes``
LABEL_FIELDS = ("kind", "strain_fractions", "elastic_fraction", "participation",
                "strain_participation")

def _labels(mech, keep: dict, poses, omega, shapes, at: Optional[StaticResult]) -> tuple:
    """(frequencies [Hz], labels): ``omega`` / 2 pi and analysis.label_modes of these modes,
    its fields listed in LABEL_FIELDS' order. The last of both are kept in ``keep`` (the
    mechanism's _model.built) with the configuration (``at``, or None: the initial one), omega
    and shapes they were made from, and a call that finds the same ones, bit for bit, gets
    copies of them."""
    key = (None if at is None else np.asarray(poses, dtype=float).tobytes(), omega.tobytes(),
           shapes.tobytes())
    last = keep.get("labels")
    if last is None or last[0] != key:
        lab = analysis.label_modes(mech._desc, poses, omega, shapes,
                                   _geometry(mech, keep, poses, at))
        last = keep["labels"] = (key, omega / (2 * np.pi),
                                 [(lab[k], _copier(lab[k])) for k in LABEL_FIELDS])
    # copies: a caller changing its result's labels changes neither the kept ones nor others'
    return last[1].copy(), [copy(v) for v, copy in last[2]]

def _copier(value):
    """How _labels copies a field of analysis.label_modes' dict (an array, a list of str or a
    list of dicts): one test per field, made when the labels are."""
    if isinstance(value, np.ndarray):
        return np.ndarray.copy
    if value and isinstance(value[0], dict):
        return _copy_dicts
    return list

def _copy_dicts(value: list) -> list:
    """A new list of copies of the dicts in ``value``."""
    return list(map(dict.copy, value))

def _geometry(mech, keep: dict, poses, at: Optional[StaticResult]):
    """analysis.element_geometry at ``poses``; at the initial configuration (``at`` None) made
    once and kept in ``keep`` (the mechanism's _model.built) until the mechanism changes."""
    if at is not None:
        return analysis.element_geometry(mech._desc, poses)
    if "element_geometry" not in keep:
        keep["element_geometry"] = analysis.element_geometry(mech._desc, poses)
    return keep["element_geometry"]

def equilibrium_check(mech, model, poses, time, at_given: bool):
    """Whether ``poses`` is a static equilibrium: a static solve at the full load started there
    (no load steps: Newton, else pseudo-transient continuation) must not move any carrier by
    more than 1e-6 of the mechanism's size [m] or 1e-6 rad.
    Returns a truthy/falsy object with a ``reason`` and, when it holds, the equilibrium that
    solve found within those bounds, ``poses`` and ``lam`` (what a StaticResult's poses and
    ``constraint_wrenches`` are): a linearization at the initial configuration (``at`` None) is
    made there, with the constraint wrenches' and the loaded links' geometric stiffness (a
    hanging pendulum's gravity stiffness through its joints: 0 and 0.65 Hz instead of 0.43 and
    1.14 Hz without them; a steel strip hanging with 1 kg at its end, whose 7e-7 m stretch is
    within the bounds, 3.3 % high at its unstretched start). A solve that fails (a free
    mechanism is singular) tells nothing: then the check passes, with ``poses`` and ``lam``
    None."""
    class _Eq:
        def __init__(mech, ok, reason="", poses=None, lam=None):
            mech.ok, mech.reason, mech.poses, mech.lam = ok, reason, poses, lam

        def __bool__(mech):
            return mech.ok
    try:
        P, lam, _ = _core.model_static(model, poses, time, 0, 1e-10)
    except (SolverError, ModelError):
        return _Eq(True)
    size = max([1.0] + [lk.length for lk in mech._links.values()])
    dp = np.linalg.norm(P[:, :3, 3] - poses[:, :3, 3], axis=1)
    rel = np.einsum("cji,cjk->cik", poses[:, :3, :3], P[:, :3, :3])
    dth = np.arccos(np.clip((np.trace(rel, axis1=1, axis2=2) - 1) / 2, -1, 1))
    c = int(np.argmax(dp / size + dth))
    if dp[c] <= 1e-6 * size and dth[c] <= 1e-6:
        return _Eq(True, poses=P, lam=lam)
    return _Eq(False, f"a static solve from it moves {mech._desc.carrier_name(c)} by "
                      f"{dp[c]:.3g} m and {dth[c]:.3g} rad")


def frequencies(model, n: int, poses: np.ndarray, lam: np.ndarray, time: float = 0.0) -> np.ndarray:
    """The ``n`` lowest frequencies [Hz] of the core ``model`` linearized at ``poses`` with
    multipliers ``lam`` (_model.linearization_point) at ``time`` [s]: what modes computes,
    without its labels and its equilibrium check (phmech.mesh sizes meshes with them)."""
    om, _, _, nf, _ = _core.model_modes(model, n, poses, lam, time)
    return om[:nf] / (2 * np.pi)


#: the largest mechanism (6 x carriers) whose starting deflection simulate decomposes into
#: modes, and the modes it asks for first (then 4x as many, once): the core's shift-invert
#: solver (a strip of 100 / 199 / 500 elements: 0.04 / 0.07 / 0.19 s for 20 modes, 0.48 / 0.97 /
#: 2.3 s for 80)
RINGING_MAX_DOF = 6000
RINGING_MODES = 24
#: a mode the start needs is taken into the band with this margin: the estimate's filter
#: (csrc/integrate/galpha_scheme.c) sees a mode at f through its two stages at 1 / (1 + (f /
#: band)^2) of its weight, 0.8 at half the band (the strip started straight under gravity:
#: its 131 Hz mode at 1.25x: 1.48x its tolerance; 1.5x: 1.06x)
RINGING_BAND_MARGIN = 2.0
#: ... and the band is raised at most this many times: beyond, simulate warns instead
RINGING_BAND_MAX_RAISE = 20.0


def ringing_band(mech, initial: Optional[StaticResult], time: float, t_end: float, band: float,
                 rtol: float, atol: float, given: bool = False):
    """The band [Hz] a run from ``time`` to ``t_end`` [s] needs for the modes its start and its
    loads' steps set ringing, or None when ``band`` [Hz] holds them or the check does not apply.
    A start rings when it is at rest away from the equilibrium of the run's own loads: a
    release (``initial`` a StaticResult found under extra loads, which the run lets go) or the
    initial configuration at rest (a structure started undeformed under gravity); a load's law
    that steps during the run (a Step) rings as the release of the step's static deflection.
    Not checked: no flexible link, more than RINGING_MAX_DOF degrees of freedom, a start that
    moves, a start or step that is not a small vibration about an
    equilibrium next to it (a mechanism that swings or falls: no modal picture), and what the
    other laws excite (a Pulse: taken as two steps, the 2 ms hit of benchmarks/scenes.py's
    cantilever + tip mass read 20 tolerances above half its 500 Hz band and raised it 20x,
    3.1x the CPU; actuators, prescribed motions).

    The default integrator resolves the motion up to the band and leaves what lies above it to
    the scheme, neither resolved nor estimated (csrc/integrate/galpha_scheme.c). A deflection let
    go rings in every mode it holds: the README's strip (0.2 m, 10 elements) bent by 0.1 N at
    its tip and released, sampled every 0.01 s (band 50 Hz), holds 1.9e-5 m of its 131 Hz mode
    at the tip and ended 5.5x its tolerance off; started straight under gravity, 3.7x; with the
    0.1 N stepped on at 0.1 s, 5.1x over 0.5 s (tests/accuracy/). So: each deflection u
    (body-frame twists from the equilibrium next to the start to the start; between the
    equilibria just before and just after a step) in the mass-normalized modes of the start's
    equilibrium, c = Phi^T M u;
    what the modes up to f leave of it, in tolerances (per carrier and component: rtol
    max|position| + atol, rotations rtol + atol), bounds the error their leaving out can make
    (on the released strip 1.4-4x the error measured at bands of 50 .. 1000 Hz). The band
    becomes RINGING_BAND_MARGIN times the frequency of the lowest mode that brings every
    deflection within 1, at most RINGING_BAND_MAX_RAISE times ``band``, when the modes above
    1/RINGING_BAND_MARGIN of the default ``band`` hold more than 1; beyond, an AccuracyWarning.
    A band the caller ``given`` is kept, with an AccuracyWarning when the modes above it hold
    more than the tolerance. Returns (band, where it came from) or None."""
    desc = mech._desc
    if not desc.elements or 6 * len(mech._car) > RINGING_MAX_DOF:
        return None
    if initial is not None:
        start = np.asarray(initial.poses, dtype=float)
        what = "the released state" if initial.loads else "the start"
    else:
        state = _model.initial_state(mech)[0]
        if np.any(state.twists):
            return None
        start, what = state.poses, "the start at rest"
    model, keep = _model.build(mech), _model.built(mech)
    found = _start_equilibrium(model, keep, start, time)
    if found is None:
        return None
    P, lam, u = found
    deflections = [(what, u)] + _load_steps(desc, model, keep, P, time, t_end)
    tol_p = rtol * np.abs(P[:, :3, 3]).max(axis=0) + atol
    if max(_left_after_modes(desc, P, du, None, tol_p, rtol + atol)[0]
           for _, du in deflections) <= 1.0:
        return None   # every deflection within the tolerance: nothing to ring
    f, phi = _start_modes(model, keep, start, P, lam, time, RINGING_MODES, len(mech._car))
    if not len(f):
        return None   # no modes there: no modal picture
    ratios = [_left_after_modes(desc, P, du, phi, tol_p, rtol + atol) for _, du in deflections]
    if max(r[-1] for r in ratios) > 1.0 and len(f) == RINGING_MODES:   # 4x as many, once
        f, phi = _start_modes(model, keep, start, P, lam, time, 4 * RINGING_MODES, len(mech._car))
        ratios = [_left_after_modes(desc, P, du, phi, tol_p, rtol + atol) for _, du in deflections]
    ratio = np.max(ratios, axis=0)
    # the modes a default band holds: up to band / RINGING_BAND_MARGIN (modes 0..inside-1); a
    # band given: up to itself (a warning names what lies above it)
    inside = int(np.searchsorted(f, band if given else band / RINGING_BAND_MARGIN, side="right"))
    above = float(ratio[inside])
    what = deflections[int(np.argmax([r[inside] for r in ratios]))][0]
    if above <= 1.0:
        return None
    enough = np.flatnonzero(ratio[1:] <= 1.0)
    need = RINGING_BAND_MARGIN * f[enough[0]] if len(enough) else np.inf
    raised = float(min(need, RINGING_BAND_MAX_RAISE * band))
    # where no band the modes found reach holds them: what those modes leave
    beyond = (f"the {len(f)} lowest modes, up to {f[-1]:.4g} Hz, leave {ratio[-1]:.3g} times the "
              f"tolerance")
    if given:
        warnings.warn(f"simulate: the modes {what} rings in above the band (band={band:.4g} "
                      f"Hz) hold {above:.3g} times the tolerance; they are neither resolved nor "
                      f"estimated "
                      + (f"(band={need:.4g} resolves them, or leave band to its default)"
                         if np.isfinite(need) else f"({beyond})"),
                      AccuracyWarning, stacklevel=outside_stacklevel())
        return None
    why = (f"the modes {what} rings in above {band / RINGING_BAND_MARGIN:.4g} Hz, 1/"
           f"{RINGING_BAND_MARGIN:g} of the default band ({band:.4g} Hz), hold {above:.3g} times "
           f"the tolerance")
    if need > raised:
        left = float(ratio[int(np.searchsorted(f, raised / RINGING_BAND_MARGIN, side="right"))])
        top = f" (band={need:.4g} holds them)" if np.isfinite(need) else f" ({beyond})"
        warnings.warn(f"simulate: {why}; the band is raised to {raised:.4g} Hz, "
                      f"{RINGING_BAND_MAX_RAISE:g}x, and what lies above it, {left:.3g} times the "
                      f"tolerance, is neither resolved nor estimated{top}",
                      AccuracyWarning, stacklevel=outside_stacklevel())
    return raised, f"{why}, raised to {raised:.4g} Hz"


def _start_equilibrium(model, keep: dict, start: np.ndarray, time: float):
    """(P, lam, u) of ringing_band for the poses ``start`` at ``time`` [s]: the equilibrium
    ``P`` (multipliers ``lam``) the core ``model``'s static solve finds from them (Newton only)
    and the deflection ``u`` (ncarriers, 6: body-frame twists) from it to the start; None when
    the solve fails or moves the poses by more than 0.2 rad or 0.2 of the mechanism's size (no
    small vibration about it). Kept in ``keep`` (the mechanism's _model.built) per start and
    time: a run called again on the same start solves nothing."""
    done = keep.setdefault("ringing", {})
    key = (start.tobytes(), time)
    if key not in done:
        done[key] = None
        try:
            P, lam, _ = _core.model_static(model, start, time, -1, 1e-10)
        except (SolverError, ModelError):
            return None
        u = se3.log(se3.inverse(P) @ start)
        if _small_vibration(u, P):
            done[key] = (P, lam, u)
    return done[key]


def _start_modes(model, keep: dict, start: np.ndarray, P: np.ndarray, lam: np.ndarray,
                 time: float, n: int, ncar: int):
    """(f [Hz], mass-normalized shapes phi) of the ``n`` lowest modes of the core ``model`` at
    the start's equilibrium ``P``, ``lam`` (_start_equilibrium), kept in ``keep`` per start,
    time and n; (empty, empty) when the eigensolver fails."""
    done = keep.setdefault("ringing_modes", {})
    key = (start.tobytes(), time, n)
    if key not in done:
        try:
            om, _, shapes, nf, _ = _core.model_modes(model, min(n, 6 * ncar), P, lam, time)
            done[key] = (om[:nf] / (2 * np.pi), shapes[:nf])
        except (SolverError, ModelError):
            done[key] = (np.zeros(0), np.zeros((0, ncar, 6)))
    return done[key]


def _load_steps(desc, model, keep: dict, P: np.ndarray, t_start: float, t_end: float) -> list:
    """[(what, du)] of ringing_band: for each time in (t_start, t_end) [s] where a load's law
    jumps for good (a Step's t0, in sums and products too), the deflection du
    (ncarriers, 6: body-frame twists) between the core ``model``'s equilibria just before and
    just after it, each found by Newton alone from ``P`` (the start's equilibrium); steps whose
    equilibria are not found, or are not a small vibration, are left out. Kept in ``keep`` per
    start and span."""
    done = keep.setdefault("ringing_steps", {})
    key = (P.tobytes(), t_start, t_end)
    if key in done:
        return done[key]
    times = set()

    def edges(d):
        if isinstance(d, dict):
            if d.get("law") == "Step":
                times.add(float(d["t0"]))
            for v in d.values():
                edges(v)
        elif isinstance(d, (list, tuple)):
            for v in d:
                edges(v)
    laws = [row["law"] for row in desc.loads if row.get("law") is not None]
    for law in laws:
        edges(law.to_data())
    out = []
    for tb in sorted(t for t in times if t_start < t < t_end):
        eps = 1e-9 * max(1.0, abs(tb))
        vals = [law.evaluate(np.array([tb - eps, tb + eps])) for law in laws]
        if all(abs(b - a) <= 1e-9 * max(abs(a), abs(b), 1.0) for a, b in vals):
            continue   # no jump there (a continuous law's corner)
        try:
            Pb, _, _ = _core.model_static(model, P, tb - eps, -1, 1e-10)
            Pa, _, _ = _core.model_static(model, Pb, tb + eps, -1, 1e-10)
        except (SolverError, ModelError):
            continue
        du = se3.log(se3.inverse(Pb) @ Pa)
        if _small_vibration(du, P):
            out.append((f"a load's step at t = {tb:.6g} s", du))
    done[key] = out
    return out


def _small_vibration(u: np.ndarray, P: np.ndarray) -> bool:
    """Whether the deflection ``u`` (ncarriers, 6: body-frame twists) from the poses ``P`` is
    a small vibration about them, for ringing_band's modal picture: at most 0.2 rad and 0.2 of
    the mechanism's size."""
    size = max(float(np.ptp(P[:, :3, 3], axis=0).max()), 1e-12)
    return bool(np.abs(u[:, :3]).max() <= 0.2 and np.abs(u[:, 3:]).max() <= 0.2 * size)


def _left_after_modes(desc, P, u, phi, tol_p, tol_r) -> np.ndarray:
    """What of the deflection ``u`` (ncarriers, 6: body-frame twists from the poses ``P``) the
    mass-normalized modes ``phi`` (n, ncarriers, 6; None: no mode) leave, before any and after
    each of them in turn: (n + 1,) the largest component in tolerances (positions in the world
    frame against ``tol_p`` (3,) [m], rotations against ``tol_r`` [rad])."""
    if phi is None or len(phi) == 0:
        left = u[None]
    else:
        c = np.einsum("nci,ci->n", desc.mass_times(phi), u)
        left = np.concatenate([u[None], u[None] - np.cumsum(c[:, None, None] * phi, axis=0)])
    moved = np.einsum("cij,kcj->kci", P[:, :3, :3], left[:, :, 3:])
    return np.maximum(np.abs(moved / tol_p).max(axis=(1, 2)),
                      np.abs(left[:, :, :3]).max(axis=(1, 2)) / tol_r)


def rest_check(lin):
    """equilibrium_check's verdict for a mechanism with components, from its linear model ``lin``
    (linear.LinearPortHamiltonian.at_rest: the forces with the components' efforts balance and
    their states are still): a truthy/falsy object with a ``reason``."""
    ok, reason = lin.at_rest()

    class _Eq:
        def __bool__(self):
            return ok
    e = _Eq()
    e.reason = reason
    return e


def spun_point(mech, model, spin, at: Optional[StaticResult], time: float, poses, lam) -> tuple:
    """With ``spin`` (pair name, Omega; _model.spin_twist) set on the core ``model``, the
    steady rotation's relative equilibrium (the static solve with the centrifugal wrenches, 10
    load steps in Omega^2 from the initial configuration) unless ``at`` gives it: (poses, lam).
    Without spin: (poses, lam) unchanged."""
    if spin is None:
        return poses, lam
    if mech._desc.components:
        raise ModelError("spin: a steady rotation of a mechanism with components is not "
                         "supported yet")
    _core.model_set_spin(model, _model.spin_twist(mech, spin))
    if at is None:
        poses, lam, _ = _core.model_static(model, None, time, 10, 1e-10)
    return poses, lam


def closed_loop_modes(mech, n: int, at: Optional[StaticResult], time: float,
                      spin=None) -> ModesResult:
    """Mechanism.modes with components (docs/method.md section 7.5) or about a steady rotation
    ``spin`` (section 7.6): the eigenvalues s [1/s] of the state matrix
    (linear.LinearPortHamiltonian.A over (q, p, z)), one of each complex pair, the n of
    smallest magnitude: omega = abs(s) [rad/s] (natural frequency), damping ratio
    -Re(s)/abs(s) (negative: unstable), shapes the reduced part q of the eigenvector turned
    real at its largest entry, unit modal mass, as carrier tangents."""
    n = integer("n", n, 1)
    time = real("time", time)
    _model.check_linearization_time(mech, "modes", time, at)
    model, poses, lam, built = _model.linearization_point_kept(mech, at)
    if spin is None and at is None:   # with spin, spun_point finds the relative equilibrium
        poses, lam, _ = equilibrium_point(mech, built, model, poses, lam, time, at)
    try:
        poses, lam = spun_point(mech, model, spin, at, time, poses, lam)
        lin = linear.build(_core, model, mech._desc, [], None, poses, lam, time,
                           spin=spin is not None)
    finally:
        if spin is not None:
            _core.model_set_spin(model, np.zeros(6))
    s, V = np.linalg.eig(lin.A)
    keep = s.imag >= -1e-12 * np.maximum(np.abs(s), 1e-300)     # one of each complex pair
    s, V = s[keep], V[:, keep]
    order = np.lexsort((s.imag, np.abs(s)))[:n]
    s, V = s[order], V[:, order]
    nr, nc = lin.nr, len(mech._car)
    shapes = np.zeros((len(s), nc, 6))
    for k in range(len(s)):
        q = V[:nr, k]
        if np.abs(q).max(initial=0.0) > 0:
            j = int(np.argmax(np.abs(q)))
            q = (q * np.conj(q[j]) / abs(q[j])).real
            mm = q @ lin.mass @ q
            q = q / np.sqrt(mm) if mm > 0 else q
        else:
            q = np.zeros(nr)
        shapes[k] = (lin.basis @ q).reshape(nc, 6)
    om = np.abs(s)
    with np.errstate(invalid="ignore", divide="ignore"):
        ze = np.where(om > 0, -s.real / np.where(om > 0, om, 1.0), 0.0)
    where = mech._state.poses if poses is None else poses
    eq = rest_check(lin)
    if not eq:
        warnings.warn(f"modes: the configuration is not a rest state of the mechanism with its "
                      f"components or steady rotation ({eq.reason}): the poles are those of the "
                      f"tangent there, not of small motions about a rest state", EquilibriumWarning,
                      stacklevel=outside_stacklevel())
    lab = analysis.label_modes(mech._desc, where, om, shapes)
    return ModesResult(om, om / (2 * np.pi), ze, shapes, poses=np.array(where),
                       equilibrium=bool(eq), poles=s, _links=dict(mech._links),
                       _bodies=dict(mech._bodies), **lab)

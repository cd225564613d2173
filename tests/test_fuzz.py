"""Property-based fuzzing of the model-building API.

Hypothesis generates small random mechanisms -- rigid bodies, flexible links with random sections
and materials, pairs of every type between random frames, actuators, spring-dampers, loads, time
laws, gravity -- and random arguments, some of them bad: NaN, inf, huge (1e300), tiny (1e-300),
negative, zero, wrong shapes, wrong types, malformed arrays. Then it builds, simulates (a few ms),
computes modes or statics. The property, for every call:

- it succeeds, and every number it returns is finite (poses are rigid, modes ascending, ...), or
- it raises a documented phmech exception (ModelError, SolverError) with a message, and a
  failed ``add_*`` call leaves the mechanism as it was;
- no other exception (no raw TypeError / IndexError / AttributeError / numpy error from the
  internals), no warning but phmech's own (CostWarning, RedundantConstraintWarning,
  InitialValueWarning, UnattachedWarning, ...: a numpy RuntimeWarning would be an overflow
  passed on silently), no
  crash, no hang (every example runs under a time limit; a hung C loop ends the process with a
  traceback).

Reproducible: every test is derandomized (the same examples on every run). The number of
examples is chosen so that the file runs well under 2 minutes on 2 cores; ``make test`` runs
``MODELS_PER_RUN`` generated models in all (test_fuzz_ran_enough_models checks it).
PHMECH_FUZZ_SCALE (default 1) multiplies the number of examples, e.g. 10 for a longer hunt.
"""
from __future__ import annotations

import faulthandler
import math
import os
import signal
import warnings

import numpy as np
import pytest
from hypothesis import HealthCheck, given, note, settings, strategies as st

import phmech as ph
from phmech import se3
from phmech.frames import frame_of

DOCUMENTED = (ph.ModelError, ph.SolverError)
DOCUMENTED_WARNINGS = (ph.CostWarning, ph.RedundantConstraintWarning, ph.InitialValueWarning,
                       ph.StabilityWarning, ph.AccuracyWarning, ph.EquilibriumWarning,
                       ph.UnattachedWarning, ph.PlausibilityWarning)

SCALE = float(os.environ.get("PHMECH_FUZZ_SCALE", "1"))
#: seconds one example may take (a sanitizer build is several times slower: PHMECH_FUZZ_LIMIT)
LIMIT = float(os.environ.get("PHMECH_FUZZ_LIMIT", "20"))


def _without_local_constants():
    """Hypothesis (>= 6.131) also draws "local constants" harvested from the non-test modules
    loaded so far, cached in .hypothesis/constants in an order that differs from a first run: the
    examples then depended on the import history (test_fuzz.py alone or after the whole suite)
    and on the cache (a fresh clone's first `make test` ran other examples than the second). Off
    here, so that the examples depend on the seed alone. A Hypothesis without this internal is
    left as it is."""
    try:
        from hypothesis.internal.conjecture import providers as p
        empty = p.Constants(integers=p.SortedSet(), floats=p.SortedSet(key=p.float_to_int),
                            bytes=p.SortedSet(), strings=p.SortedSet())
        p._get_local_constants = lambda: empty
        p.CONSTANTS_CACHE = type(p.CONSTANTS_CACHE)(1024)
    except (ImportError, AttributeError, TypeError):
        pass


_without_local_constants()


def fuzz_settings(n: int):
    return settings(max_examples=max(1, int(n * SCALE)), derandomize=True, deadline=None,
                    database=None, print_blob=True,
                    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large,
                                           HealthCheck.filter_too_much])


N_MECHANISMS = 900     # random mechanisms, built and analysed
N_ARGUMENTS = 900      # one bad argument in an otherwise valid model
MODELS_PER_RUN = N_MECHANISMS + N_ARGUMENTS
models_built = []      # one entry per generated model (test_fuzz_ran_enough_models)
outcomes = {}          # (analysis, "ok" | exception name) -> count, random mechanisms


# ------------------------------------------------------------------ time limit, hang guard
class Hang(Exception):
    """Raised by the alarm: an example ran past LIMIT seconds."""


class time_limit:
    """SIGALRM after LIMIT s: the handler raises Hang in Python code; inside simulate the core
    polls signals (every ~100 steps), stops and returns an interrupted result, so `fired` is
    checked as well. A C loop that never returns to Python cannot be stopped that way: after
    3 LIMIT + 30 s a watchdog (faulthandler) dumps every thread's traceback and ends the process
    instead of hanging the suite."""

    def __enter__(self):
        self.fired = False

        def handler(signum, frame):
            self.fired = True
            raise Hang(f"example still running after {LIMIT} s")

        self.previous = signal.signal(signal.SIGALRM, handler)
        signal.setitimer(signal.ITIMER_REAL, LIMIT)
        faulthandler.dump_traceback_later(3 * LIMIT + 30, exit=True)
        return self

    def __exit__(self, *exc):
        faulthandler.cancel_dump_traceback_later()
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, self.previous)
        assert not self.fired, f"hang: the example ran for more than {LIMIT} s"
        return False


# ------------------------------------------------------------------ property checks
def _fin(x, what):
    a = np.asarray(x, dtype=float)
    assert np.all(np.isfinite(a)), f"silent non-finite value in {what}: {a}"


def _rigid(H, what):
    H = np.asarray(H)
    R = H[..., :3, :3]
    err = np.max(np.abs(np.einsum("...ji,...jk->...ik", R, R) - np.eye(3))) if R.size else 0.0
    assert err < 1e-8, f"{what}: rotation not orthonormal (|R^T R - I| = {err:.3g})"
    assert np.all(H[..., 3, :] == [0, 0, 0, 1]), f"{what}: last row is not (0, 0, 0, 1)"


def check_warnings(caught):
    for w in caught:
        assert issubclass(w.category, DOCUMENTED_WARNINGS), \
            f"undocumented warning {w.category.__name__}: {w.message} ({w.filename}:{w.lineno})"


def check_simulation(m, r, bodies, links, pairs):
    assert len(r.t) >= 1 and np.all(np.diff(r.t) > 0)
    for name in ("t", "poses", "twists", "constraint_wrenches", "joints", "joint_rates",
                 "efforts", "pair_wrenches"):
        _fin(getattr(r, name), f"result.{name}")
    _rigid(r.poses, "result.poses")
    for k, v in r.energy.items():
        _fin(v, f"energy[{k!r}]")
    for k, v in r.port_energy.items():
        _fin(v, f"port_energy[{k!r}]")
    for k, v in r.stats.items():
        if isinstance(v, (int, float)) and not isinstance(v, bool):
            _fin(v, f"stats[{k!r}]")
    # with record=, asking for a carrier that was not recorded is a documented ModelError
    for b in bodies:
        for f in (r.pose, r.twist):
            out = attempt(None, f, b)
            if out is not FAILED:
                _fin(out, f"result.{f.__name__}({b!r})")
    for lk in links:
        for f in (r.tip, lambda lk: m.stress_resultants(r, lk)):
            out = attempt(None, f, lk)
            if out is not FAILED:
                _fin(out, f"{f.__name__}({lk.name!r})")
        if r.carriers is None:
            _fin(r.tip(lk), f"result.tip({lk.name!r})")
    for p in pairs:
        for k, v in r.joint(p).items():
            _fin(v, f"joint({p!r})[{k!r}]")
    if r.carriers is None and len(r.t):
        for k, v in m.constraint_residuals(r).items():
            _fin(v, f"constraint_residuals[{k!r}]")


def check_modes(md, n):
    assert len(md.omega) <= n
    for name in ("omega", "frequency", "damping_ratio", "shapes"):
        _fin(getattr(md, name), f"modes.{name}")
    assert np.all(np.diff(md.omega) >= -1e-9 * max(1.0, np.max(np.abs(md.omega), initial=0))), \
        f"modes not ascending: {md.omega}"


def check_static(s, links):
    _fin(s.poses, "static.poses")
    _fin(s.constraint_wrenches, "static.constraint_wrenches")
    _rigid(s.poses, "static.poses")
    for lk in links:
        _fin(s.positions(lk), f"static.positions({lk.name!r})")


FAILED = object()
last_outcome = ["ok"]   # of the latest attempt(): "ok" or the documented exception's name


def snapshot(m):
    """What a failed add_* call must leave unchanged (private state: the lists the core model is
    built from and the names taken)."""
    if not isinstance(m, ph.Mechanism):
        return None
    return (sorted(m._names), len(m._car), len(m._el), len(m._pairs), len(m._loads),
            len(m._acts), len(m._springs), sorted(m._links), sorted(m._bodies), sorted(m._given))


def attempt(m, fn, *args, **kw):
    """fn(*args, **kw): its value, or FAILED when it raised a documented exception (which must
    carry a message and leave the mechanism `m` unchanged). Anything else propagates and fails
    the example."""
    before = snapshot(m)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            out = fn(*args, **kw)
        except DOCUMENTED as e:
            note(f"  -> {type(e).__name__}: {e}")
            assert str(e).strip(), f"{type(e).__name__} without a message"
            assert snapshot(m) == before, f"a failed call changed the mechanism ({e})"
            if isinstance(e, ph.SolverError) and hasattr(e, "result"):
                r = e.result   # a SimulationResult up to the failure, or a static solve's
                names = (("poses", "constraint_wrenches", "load_factor")   # last equilibrium
                         if isinstance(r, ph.StaticResult) else ("t", "poses", "twists", "joints"))
                for name in names:
                    _fin(getattr(r, name), f"SolverError.result.{name}")
            out = FAILED
            last_outcome[0] = type(e).__name__
        else:
            last_outcome[0] = "ok"
    check_warnings(caught)
    return out


# ------------------------------------------------------------------ value generation
NAN, INF = float("nan"), float("inf")
WEIRD_NUMBERS = [NAN, INF, -INF, 1e300, -1e300, 1e-300, -1e-300, 0.0, -0.0, -1.0, 1e20, -1e20,
                 5e-324, 1e154, 2.0 ** 63]
JUNK_OBJECTS = ["abc", "", None, 1j, [], (), {}, {"a": 1}, object(), [[1.0, 2.0], [3.0]],
                ["1", "2", "3"], np.array(["x", "y", "z"]), np.array([1.0, 2.0, 3.0], dtype=object),
                np.zeros((2, 2)), np.full(7, 0.5), b"\x00", True, slice(1), np.complex128(1j),
                np.array([]), (lambda t: t)]


class Gen:
    """Draws values from hypothesis' `data`; with probability `rate` a value is replaced by
    junk (a weird number, a wrong shape or type, a malformed array)."""

    def __init__(self, data, rate):
        self.data, self.rate = data, rate

    def draw(self, strategy, label=None):
        return self.data.draw(strategy, label=label)

    def bad(self) -> bool:
        return self.rate > 0 and self.draw(st.integers(0, 999)) < 1000 * self.rate

    def choice(self, items, label=None):
        return self.draw(st.sampled_from(items), label)

    def junk(self, good, label=None):
        """A bad variant of the good value `good`."""
        kind = self.choice(["number", "object", "entry", "shape", "complex", "strings", "full"])
        try:
            a = None if isinstance(good, str) else np.asarray(good)
        except (TypeError, ValueError):
            a = None
        if a is not None and a.dtype.kind in "biuf":
            a = a.astype(float)
        else:
            a = None   # not numeric (a pair type, a law, ...): replaced by a number or an object
        if kind != "object" and (a is None or a.ndim == 0 or a.size == 0):
            kind = "number"
        if kind == "number":
            v = self.choice(WEIRD_NUMBERS + ["abc", None, 1j])
        elif kind == "object":
            v = self.choice(JUNK_OBJECTS)
        elif kind == "entry":
            v = a.copy()
            v.flat[self.draw(st.integers(0, a.size - 1))] = self.choice(WEIRD_NUMBERS)
        elif kind == "shape":
            v = self.choice([a.ravel()[:-1], np.append(a.ravel(), 1.0), a[None], a.ravel(),
                             np.stack([a, a]), a.tolist() + [[0.0]] if a.ndim else [a]])
        elif kind == "complex":
            with np.errstate(invalid="ignore"):   # inf * 1j
                v = a.astype(complex) * self.choice([1, 1j])
        elif kind == "strings":
            v = a.astype(str)
        else:
            v = np.full(a.shape, self.choice(WEIRD_NUMBERS))
        note(f"  junk for {label}: {v!r}")
        return v

    def maybe(self, good, label=None):
        return self.junk(good, label) if self.bad() else good

    # -- good values (each maybe replaced by junk)
    def real(self, lo, hi, label=None):
        return self.maybe(self.draw(st.floats(lo, hi, allow_nan=False, allow_infinity=False)), label)

    def log(self, lo, hi, label=None):
        """Log-uniform in [lo, hi] (lo > 0)."""
        e = self.draw(st.floats(math.log10(lo), math.log10(hi)))
        return self.maybe(10.0 ** e, label)

    def good_vec(self, n, lo, hi):
        return np.array([self.draw(st.floats(lo, hi, allow_nan=False, allow_infinity=False))
                         for _ in range(n)])

    def vec(self, n, lo, hi, label=None):
        return self.maybe(self.good_vec(n, lo, hi), label)

    def axis(self, label=None):
        if self.draw(st.booleans()):
            return self.maybe(self.choice(["x", "y", "z"]), label)
        v = self.good_vec(3, -1, 1)
        if np.linalg.norm(v) < 1e-3:
            v = np.array([0.0, 0.0, 1.0])
        return self.maybe(v, label)

    def pose(self, label=None, scale=0.5):
        x = np.concatenate([self.good_vec(3, -np.pi, np.pi), self.good_vec(3, -scale, scale)])
        return self.maybe(se3.exp(x), label)

    def spd3(self, lo, hi, label=None):
        d = np.array([self.draw(st.floats(math.log10(lo), math.log10(hi))) for _ in range(3)])
        J = np.diag(10.0 ** d)
        # keep the triangle inequality of a rigid body's principal moments
        J = np.diag(np.maximum(np.diag(J), 0.51 * (np.trace(J) - np.diag(J))))
        R = se3.exp(self.good_vec(3, -np.pi, np.pi))
        return self.maybe(R @ J @ R.T, label)

    def law(self, label=None, numbers=False):
        """A time law; `numbers`: a number may stand for Constant (actuator laws)."""
        kind = self.choice(["Constant", "Step", "Pulse", "Sine", "Table", "Cycloidal"]
                           + ["number"] * (numbers or self.bad()) + ["function", "junk"] * self.bad())
        r = lambda lo, hi, what: self.real(lo, hi, f"{label} {what}")
        if kind == "Constant":
            return ph.Constant(r(-2, 2, "value"))
        if kind == "Step":
            return ph.Step(r(-1e-3, 4e-3, "t0"), r(-2, 2, "value"))
        if kind == "Pulse":
            return ph.Pulse(r(-1e-3, 3e-3, "t0"), self.log(1e-4, 1e-2, f"{label} duration"),
                            r(-2, 2, "value"))
        if kind == "Sine":
            return ph.Sine(r(-2, 2, "amplitude"), self.log(1e-1, 1e3, f"{label} frequency"),
                           r(-3, 3, "phase"), r(-1, 1, "offset"))
        if kind == "Table":
            n = self.draw(st.integers(1, 4))
            t = np.cumsum([self.draw(st.floats(1e-4, 2e-3)) for _ in range(n)]) - 1e-3
            return ph.Table(self.maybe(t, f"{label} times"), self.vec(n, -2, 2, f"{label} values"))
        if kind == "Cycloidal":
            return ph.Cycloidal(r(-2, 2, "value"), r(-1e-3, 2e-3, "t0"),
                                self.log(1e-4, 1e-2, f"{label} duration"))
        if kind == "number":
            return self.real(-2, 2, label)
        if kind == "function":
            return lambda t: t
        return self.junk(0.0, label)


# ------------------------------------------------------------------ random mechanisms
def random_properties(g: Gen, label):
    kind = g.choice(["material", "values", "matrices", "table1", "object"])
    if kind == "material":
        sec = g.choice(["rectangle", "circle", "tube"])
        if sec == "rectangle":
            section = attempt(None, ph.Section.rectangle, g.log(2e-3, 5e-2, "width"), g.log(1e-3, 2e-2, "height"))
        elif sec == "circle":
            section = attempt(None, ph.Section.circle, g.log(2e-3, 5e-2, "diameter"))
        else:
            d = 10 ** g.draw(st.floats(math.log10(5e-3), math.log10(5e-2)))
            section = attempt(None, ph.Section.tube, g.maybe(d, "outer"),
                              g.maybe(d * g.draw(st.floats(0.1, 0.9)), "inner"))
        material = attempt(None, ph.Material, g.log(1e8, 5e11, "E"), g.real(0.0, 0.45, "nu"),
                           g.log(500.0, 2e4, "density"))
        if section is FAILED or material is FAILED:
            return FAILED
        damping = None
        if g.draw(st.booleans()):
            damping = attempt(None, lambda: 1e-6 * ph.BeamProperties.from_material(section, material).stiffness)
            damping = None if damping is FAILED else g.maybe(damping, "damping")
        return attempt(None, ph.BeamProperties.from_material, section, material, damping)
    if kind == "values":
        kw = {k: g.log(lo, hi, k) for k, lo, hi in [
            ("EA", 1e5, 1e8), ("GA_y", 1e5, 1e8), ("GA_z", 1e5, 1e8), ("GJ", 1.0, 1e3),
            ("EI_y", 1.0, 1e3), ("EI_z", 1.0, 1e3), ("rhoA", 0.1, 10.0), ("rhoI_y", 1e-6, 1e-3),
            ("rhoI_z", 1e-6, 1e-3)]}
        return attempt(None, lambda: ph.BeamProperties.from_values(**kw))
    if kind == "matrices":
        K = g.maybe(np.diag([10.0, 10.0, 10.0, 1e6, 1e6, 1e6]), "K")
        M = g.maybe(np.diag([1e-4, 1e-4, 1e-4, 1.0, 1.0, 1.0]), "M")
        return attempt(None, ph.BeamProperties, K, M)
    if kind == "table1":
        return ph.table1_properties()
    # a plain object with the three attributes (add_flexible_link accepts any such object)
    return type("P", (), dict(stiffness=g.maybe(np.diag([10.0, 10, 10, 1e6, 1e6, 1e6]), "stiffness"),
                              inertia=g.maybe(np.diag([1e-4, 1e-4, 1e-4, 1.0, 1, 1]), "inertia")))


class Model:
    """A random mechanism and the names of what was added successfully."""

    def __init__(self, g: Gen):
        self.g = g
        self.bodies, self.links, self.pairs, self.frames = [], [], [], []
        self.n = 0
        gravity = g.choice([(0.0, 0.0, -9.81), (0.0, -9.81, 0.0), (0.0, 0.0, 0.0), "random"])
        if gravity == "random":
            gravity = g.vec(3, -20, 20)
        gravity = g.maybe(gravity, "gravity")
        kw = dict(gravity=gravity)
        if g.bad():
            kw[g.choice(["strict", "band", "frequency_tolerance"])] = g.junk(1.0, "Mechanism kw")
        m = attempt(None, ph.Mechanism, **kw)
        self.m = ph.Mechanism() if m is FAILED else m
        # a third of the models are structures: every joint sprung, every body and link held
        # (statics then have an equilibrium to find)
        self.restrained = g.draw(st.integers(0, 2)) == 0

    def name(self, kind):
        self.n += 1
        return self.g.maybe(f"{kind}{self.n}", "name")

    def frame(self, label, ground=True, avoid=None):
        """A frame of this mechanism: ground, a body (object or name), a link end or node, or a
        Frame with a random offset (not on carrier `avoid`, mostly); sometimes junk."""
        g, m = self.g, self.m
        if g.bad():
            return g.choice([ph.Frame(99, np.eye(4)), ph.Frame(0, np.full((4, 4), np.nan)),
                             ph.Frame(0, np.ones((4, 4))), ph.Frame(-1, "abc"), ph.Frame(1.5, np.eye(4)),
                             "nobody", None, 3, m, *(self.links[:1])])
        bodies = [b for b in self.bodies if m._bodies[b].carrier != avoid]
        links = [lk for lk in self.links if avoid not in lk.nodes]
        ground = ground or not (bodies or links)
        options = ["ground", "ground-name"] * ground + ["body", "body-name"] * bool(bodies) + \
                  ["link-end", "link-node"] * bool(links) + ["offset"] * bool(bodies or links)
        kind = g.choice(options, label)
        if kind == "ground":
            return m.ground
        if kind == "ground-name":
            return "ground"
        if kind == "body":
            return m._bodies[g.choice(bodies)]
        if kind == "body-name":
            return g.choice(bodies)
        if kind == "link-end":
            lk = g.choice(links)
            return g.choice([lk.start, lk.end])
        if kind == "link-node":
            lk = g.choice(links)
            k = g.draw(st.integers(-lk.elements - 2, lk.elements + 2))
            f = attempt(None, lk.node, k)
            return lk.start if f is FAILED else f
        base = g.choice([m._bodies[b].frame for b in bodies] + [lk.end for lk in links])
        return ph.Frame(base.carrier, g.pose("frame offset", scale=0.2))

    def add_body(self):
        g = self.g
        name = self.name("body")
        kw = {}
        if g.draw(st.booleans()):
            kw["com"] = g.vec(3, -0.2, 0.2, "com")
        if g.draw(st.integers(0, 3)) == 0:
            kw["pose"] = g.pose("body pose")
        if g.draw(st.integers(0, 4)) == 0:
            kw["twist"] = g.vec(6, -2, 2, "body twist")
        b = attempt(self.m, self.m.add_rigid_body, name, g.log(0.1, 10.0, "mass"),
                    g.spd3(1e-3, 1.0, "inertia"), **kw)
        if b is not FAILED:
            self.bodies.append(b.name)

    def add_link(self):
        g = self.g
        props = random_properties(g, "properties")
        if props is FAILED:
            return
        kw = dict(elements=g.maybe(g.draw(st.integers(1, 3)), "elements"))
        if g.draw(st.integers(0, 3)) == 0:
            kw["pose"] = g.pose("link pose")
        if g.draw(st.integers(0, 3)) == 0:
            kw["curvature"] = g.vec(3, -2, 2, "curvature")
        lk = attempt(self.m, self.m.add_flexible_link, self.name("link"), g.log(0.05, 1.5, "length"),
                     props, **kw)
        if lk is not FAILED:
            self.links.append(lk)

    def pair_type(self):
        g = self.g
        kind = g.choice(["Fixed", "Revolute", "Prismatic", "Helical", "Cylindrical", "Universal",
                         "Spherical", "Planar", "Free"] + ["junk"] * g.bad())
        if kind == "Fixed":
            return ph.Fixed()
        if kind in ("Revolute", "Prismatic", "Cylindrical"):
            return getattr(ph, kind)(g.axis(f"{kind} axis"))
        if kind == "Helical":
            return ph.Helical(g.axis("Helical axis"), g.real(-0.05, 0.05, "pitch"))
        if kind == "Universal":
            a1 = g.choice(["x", "y", "z"])
            a2 = g.choice([a for a in "xyz" if a != a1])
            return ph.Universal(g.maybe(a1, "axis1"), g.maybe(a2, "axis2"))
        if kind == "Planar":
            return ph.Planar(g.axis("normal"))
        if kind in ("Spherical", "Free"):
            return getattr(ph, kind)()
        return g.choice([ph.Effort(), "Revolute", ph.Revolute, None, 1])

    def actuator(self, k):
        g = self.g
        kind = g.choice(["Effort", "PD", "Spring"] + ["junk"] * g.bad())
        if kind == "Effort":
            return ph.Effort(g.law("Effort law", numbers=True), g.maybe(None, "direction") if g.draw(st.booleans())
                             else g.vec(max(k, 1), -1, 1, "direction"))
        if kind == "PD":
            return ph.PD(g.log(1e-1, 1e3, "kp"), g.log(1e-2, 10.0, "kd"), g.law("PD target", numbers=True),
                         offset=g.maybe(None, "offset"))
        if kind == "Spring":
            return ph.Spring(g.log(1e-1, 1e3, "k"), g.real(0.0, 5.0, "c"),
                             g.maybe(None, "rest") if g.draw(st.booleans()) else g.vec(max(k, 1), -1, 1, "rest"))
        return g.junk(0.0, "actuator")

    def add_pair(self):
        g, m = self.g, self.m
        pair = self.pair_type()
        k = getattr(pair, "k", 1)
        kw = {}
        if (k > 0 or g.bad()) and g.draw(st.integers(0, 2)) == 0:
            kw["x0"] = g.vec(max(k, 1), -1, 1, "x0")
        if (k > 0 or g.bad()) and g.draw(st.integers(0, 3)) == 0:
            kw["xdot0"] = g.vec(max(k, 1), -3, 3, "xdot0")
        if (k > 0 or g.bad()) and g.draw(st.integers(0, 3)) == 0:
            kw["actuator"] = self.actuator(k)
        elif k > 0 and self.restrained:
            kw["actuator"] = ph.Spring(g.log(1.0, 1e3, "k"), g.real(0.0, 1.0, "c"))
        if (k == 0 or g.bad()) and g.draw(st.integers(0, 2)) == 0:
            kw["driven"] = ph.Motion(g.maybe(g.choice([(0, 0, 1, 0, 0, 0), (0, 0, 0, 1, 0, 0)]), "motion axis"),
                                     g.law("Motion law"))
        name = self.name("pair")
        if not (self.bodies or self.links):
            return
        # mostly a tree grown from the ground: b on a body or link no pair reaches yet
        used = {c for e in m._pairs for c in (e["a"], e["b"])}
        free = [m._bodies[n].frame for n in self.bodies if m._bodies[n].carrier not in used] + \
               [lk.start for lk in self.links if not used & set(lk.nodes)]
        b = g.choice(free) if free and g.draw(st.integers(0, 3)) else self.frame("pair b", ground=False)
        a = self.frame("pair a", avoid=getattr(attempt(None, frame_of, b, m._desc, "b"), "carrier", None))
        if attempt(m, m.add_pair, name, pair, a, b, **kw) is not FAILED:
            self.pairs.append(name)

    def add_actuator(self):
        g, m = self.g, self.m
        if not self.pairs:
            return
        p = g.choice([p for p in self.pairs if m._pair_entry(p)["k"] > 0] or self.pairs)
        attempt(m, m.add_actuator, self.name("act"), g.maybe(p, "pair name"), self.actuator(1))

    def add_load(self):
        g, m = self.g, self.m
        kind = g.choice(["wrench", "interaction", "distributed", "spring"])
        if kind == "wrench":
            attempt(m, m.add_wrench, self.name("w"), self.frame("wrench target", ground=False),
                    g.vec(6, -10, 10, "wrench"), law=g.law("wrench law"),
                    frame=g.maybe(g.choice(["world", "body"]), "wrench frame"),
                    point=g.vec(3, -0.1, 0.1, "wrench point"))
        elif kind == "interaction":
            target = self.frame("interaction target", ground=False)
            carrier = getattr(attempt(None, frame_of, target, m._desc, "t"), "carrier", None)
            attempt(m, m.add_interaction, self.name("i"), target,
                    g.vec(6, -10, 10, "interaction wrench"), law=g.law("interaction law"),
                    reaction=self.frame("reaction", avoid=carrier) if g.draw(st.booleans()) else None)
        elif kind == "distributed":
            if not self.links:
                return
            lk = g.maybe(g.choice(self.links), "link")
            attempt(m, m.add_distributed_load, self.name("q"), lk, g.vec(3, -20, 20, "force_per_length"),
                    law=g.law("distributed law"))
        else:
            kw = {}
            if g.draw(st.booleans()):
                kw["rest_length"] = g.log(1e-2, 1.0, "rest_length")
            if g.draw(st.booleans()):
                kw["point_a"] = g.vec(3, -0.1, 0.1, "point_a")
            a = self.frame("spring a", ground=False)
            carrier = getattr(attempt(None, frame_of, a, m._desc, "a"), "carrier", None)
            attempt(m, m.add_spring_damper, self.name("s"), a, self.frame("spring b", avoid=carrier),
                    g.log(1.0, 1e4, "spring k"), g.real(0.0, 10.0, "spring c"), **kw)


    def restrain(self):
        """Weld every body and link no pair reaches to the ground, where it is."""
        m = self.m
        used = {c for e in m._pairs for c in (e["a"], e["b"])}
        for f, cs in [(m._bodies[n].frame, {m._bodies[n].carrier}) for n in self.bodies] + \
                [(lk.start, set(lk.nodes)) for lk in self.links]:
            if not cs & used:
                ground = ph.Frame(-1, m._given.get(f.carrier, np.eye(4)), "ground")
                name = self.name("weld")
                if attempt(m, m.add_pair, name, ph.Fixed(), ground, f) is not FAILED:
                    self.pairs.append(name)


def random_model(g: Gen) -> Model:
    md = Model(g)
    for _ in range(g.draw(st.integers(0, 3), "bodies")):
        md.add_body()
    for _ in range(g.draw(st.integers(0, 2), "links")):
        md.add_link()
    for _ in range(g.draw(st.integers(0, 4), "pairs")):
        md.add_pair()
    for _ in range(g.draw(st.integers(0, 3), "loads")):
        md.add_load()
    if g.draw(st.integers(0, 3)) == 0:
        md.add_actuator()
    if md.restrained:
        md.restrain()
    return md


def analyse(md: Model, g: Gen):
    what = g.choice(["simulate", "simulate", "simulate-ida", "simulate-fixed", "modes", "static",
                     "static-modes", "static-simulate", "initial", "graphs"], "analysis")
    if what == "simulate-ida" and md.links:
        # IDA resolves every vibration of a flexible link, however fast (documented: minutes where
        # the default takes seconds; a free 11 cm link took 1e6 steps in 0.2 ms): only rigid models
        what = "simulate"
    outcome = "stopped"
    try:
        _analyse(md, g, what)
    except Exception:
        outcome = "failed"
        raise
    else:
        outcome = md.outcome
    finally:
        key = (what, outcome)
        outcomes[key] = outcomes.get(key, 0) + 1


def _analyse(md: Model, g: Gen, what: str):
    m = md.m
    md.outcome = "error"
    check = dict(bodies=md.bodies, links=md.links, pairs=md.pairs)
    if what.startswith("simulate"):
        kw = dict(integrator="ida", rtol=1e-5) if what == "simulate-ida" else \
            dict(integrator="generalized-alpha", step=2.5e-4) if what == "simulate-fixed" else {}
        if g.draw(st.integers(0, 4)) == 0:
            kw["record"] = g.maybe(g.choice(md.bodies + md.links + ["ground"]), "record")
        if g.bad():
            kw[g.choice(["rtol", "band", "max_step", "callback", "initial", "t_start"])] = g.junk(1e-3, "simulate kw")
        r = attempt(m, m.simulate, g.maybe(g.choice([2e-3, 3e-3, 5e-3]), "t_end"),
                    g.maybe(1e-3, "dt_out"), **kw)
        md.outcome = last_outcome[0]
        if r is not FAILED:
            check_simulation(m, r, **check)
    elif what == "modes":
        n = g.maybe(g.draw(st.integers(1, 4)), "n")
        md_ = attempt(m, m.modes, n, time=g.maybe(0.0, "time"))
        md.outcome = last_outcome[0]
        if md_ is not FAILED:
            check_modes(md_, n)
    elif what.startswith("static"):
        loads = []
        if g.draw(st.booleans()):
            loads = [(md.frame("static load target"), g.vec(6, -10, 10, "static load"),
                      g.maybe(g.choice(["world", "body"]), "static frame"))]
        loads = g.maybe(loads, "static loads")
        s = attempt(m, m.static, loads=loads, steps=g.maybe(g.draw(st.integers(1, 3)), "steps"),
                    tol=g.maybe(1e-10, "tol"))
        md.outcome = last_outcome[0]
        if s is FAILED:
            return
        check_static(s, md.links)
        if what == "static-modes":
            md_ = attempt(m, m.modes, 3, at=s)
            md.outcome = last_outcome[0]
            if md_ is not FAILED:
                check_modes(md_, 3)
        elif what == "static-simulate":
            r = attempt(m, m.simulate, 2e-3, 1e-3, initial=s)
            md.outcome = last_outcome[0]
            if r is not FAILED:
                check_simulation(m, r, **check)
    elif what == "initial":
        ic = attempt(m, m.initial_configuration)
        md.outcome = last_outcome[0]
        if ic is not FAILED:
            _fin(ic.poses, "initial poses")
            _fin(ic.twists, "initial twists")
            _rigid(ic.poses, "initial poses")
            for a in ic.adjustments:
                _fin(a.moved, f"adjustment {a}")
    else:
        gr = attempt(m, m.graphs)
        md.outcome = last_outcome[0]
        if gr is not FAILED:
            # an edge (a, b): -1 at row a, +1 at row b (the ground has no row)
            for inc, edges in ((gr.B_K, gr.G_K), (gr.B_I, gr.G_I)):
                B = inc.full
                assert B.shape[1] == len(edges) and set(np.unique(B)) <= {-1, 0, 1}
                assert np.all(np.sum(B == -1, axis=0) <= 1) and np.all(np.sum(B == 1, axis=0) <= 1)


@fuzz_settings(N_MECHANISMS)
@given(data=st.data())
def test_fuzz_random_mechanisms(data):
    """Random mechanisms, a third of them clean, the rest with 3 % or 15 % of their values bad;
    built, then one analysis. Every call: finite results or a documented exception."""
    rate = data.draw(st.sampled_from([0.0, 0.03, 0.15]), label="junk rate")
    g = Gen(data, rate)
    with time_limit():
        md = random_model(g)
        models_built.append(1)
        analyse(md, g)


# ------------------------------------------------------------------ one bad argument
PROPS = ph.BeamProperties.from_values(EA=1e6, GA_y=1e5, GA_z=1e5, GJ=10.0, EI_y=10.0, EI_z=10.0,
                                      rhoA=1.0, rhoI_y=1e-4, rhoI_z=1e-4)


def base_model():
    """A valid model touching every kind of component: a body on a revolute with a PD actuator,
    a clamped link, a spring-damper, a wrench; and a body b2 on a sprung Free pair (every degree
    of freedom is restrained: statics work) for the calls to connect."""
    m = ph.Mechanism(gravity=(0, 0, -9.81))
    b = m.add_rigid_body("b", 1.0, np.diag([0.01, 0.02, 0.02]), com=(0.1, 0, 0))
    m.add_pair("k", ph.Revolute("y"), m.ground, b, actuator=ph.PD(10.0, 1.0))
    lk = m.add_flexible_link("l", 0.4, PROPS, elements=2)
    m.add_pair("c", ph.Fixed(), b, lk.start)
    m.add_spring_damper("s", m.ground, lk.end, 100.0, 1.0)
    m.add_wrench("w", lk.end, (0, 0, 0, 0, 0, 1.0), law=ph.Step(1e-3))
    b2 = m.add_rigid_body("b2", 1.0, np.eye(3) * 0.01)
    m.add_pair("f2", ph.Free(), m.ground, b2, actuator=ph.Spring(100.0, 1.0))   # held elastically
    return m, b, b2, lk


def _pd(m, b, b2, v, what):
    m.add_pair("p", ph.Revolute("z"), ph.Frame(b.carrier, se3.translation([0.2, 0, 0])),
               b2, actuator=ph.PD(**{"kp": 1.0, "kd": 1.0, what: v}))


#: (label, good value, call(m, b, lk, v)): each puts v in one argument of one call
CALLS = [
    ("Mechanism gravity", (0, 0, -9.81), lambda m, b, b2, lk, v: ph.Mechanism(gravity=v)),
    ("Mechanism strict", False, lambda m, b, b2, lk, v: ph.Mechanism(strict=v)),
    ("Mechanism band", 50.0, lambda m, b, b2, lk, v: ph.Mechanism(band=v)),
    ("Mechanism frequency_tolerance", 1e-3, lambda m, b, b2, lk, v: ph.Mechanism(frequency_tolerance=v)),
    ("body name", "b3", lambda m, b, b2, lk, v: m.add_rigid_body(v, 1.0, np.eye(3))),
    ("body mass", 1.0, lambda m, b, b2, lk, v: m.add_rigid_body("b3", v, np.eye(3))),
    ("body inertia", np.eye(3), lambda m, b, b2, lk, v: m.add_rigid_body("b3", 1.0, v)),
    ("body com", (0, 0, 0.1), lambda m, b, b2, lk, v: m.add_rigid_body("b3", 1.0, np.eye(3), com=v)),
    ("body pose", np.eye(4), lambda m, b, b2, lk, v: m.add_rigid_body("b3", 1.0, np.eye(3), pose=v)),
    ("body twist", np.zeros(6), lambda m, b, b2, lk, v: m.add_rigid_body("b3", 1.0, np.eye(3), twist=v)),
    ("link length", 0.3, lambda m, b, b2, lk, v: m.add_flexible_link("l2", v, PROPS, elements=2)),
    ("link properties", PROPS, lambda m, b, b2, lk, v: m.add_flexible_link("l2", 0.3, v, elements=2)),
    ("link stiffness", PROPS.stiffness, lambda m, b, b2, lk, v: m.add_flexible_link(
        "l2", 0.3, type("P", (), dict(stiffness=v, inertia=PROPS.inertia)), elements=2)),
    ("link damping", np.zeros((6, 6)), lambda m, b, b2, lk, v: m.add_flexible_link(
        "l2", 0.3, type("P", (), dict(stiffness=PROPS.stiffness, inertia=PROPS.inertia, damping=v)), elements=2)),
    ("link elements", 2, lambda m, b, b2, lk, v: m.add_flexible_link("l2", 0.3, PROPS, elements=v)),
    ("link pose", np.eye(4), lambda m, b, b2, lk, v: m.add_flexible_link("l2", 0.3, PROPS, elements=2, pose=v)),
    ("link curvature", (0, 0, 1.0), lambda m, b, b2, lk, v: m.add_flexible_link("l2", 0.3, PROPS, elements=2, curvature=v)),
    ("link band", 20.0, lambda m, b, b2, lk, v: m.add_flexible_link("l2", 0.3, PROPS, band=v)),
    ("link discretization", "se3", lambda m, b, b2, lk, v: m.add_flexible_link("l2", 0.3, PROPS, elements=2, discretization=v)),
    ("pair type", ph.Revolute("z"), lambda m, b, b2, lk, v: m.add_pair("p", v, lk.end, b2)),
    ("pair axis", "z", lambda m, b, b2, lk, v: m.add_pair("p", ph.Revolute(v), lk.end, b2)),
    ("pair Universal axis2", "y", lambda m, b, b2, lk, v: m.add_pair("p", ph.Universal("x", v), lk.end, b2)),
    ("pair pitch", 0.01, lambda m, b, b2, lk, v: m.add_pair("p", ph.Helical("z", v), lk.end, b2)),
    ("pair a", "ground", lambda m, b, b2, lk, v: m.add_pair("p", ph.Spherical(), v, b2)),
    ("pair b frame offset", np.eye(4), lambda m, b, b2, lk, v: m.add_pair("p", ph.Spherical(), lk.end, ph.Frame(b.carrier, v))),
    ("pair b frame carrier", 0, lambda m, b, b2, lk, v: m.add_pair("p", ph.Spherical(), lk.end, ph.Frame(v, np.eye(4)))),
    ("pair x0", 0.3, lambda m, b, b2, lk, v: m.add_pair("p", ph.Revolute("z"), lk.end, b2, x0=v)),
    ("pair x0 prismatic", 0.3, lambda m, b, b2, lk, v: m.add_pair("p", ph.Prismatic("z"), lk.end, b2, x0=v)),
    ("pair x0 free", np.zeros(6), lambda m, b, b2, lk, v: m.add_pair("p", ph.Free(), lk.end, b2, x0=v)),
    ("pair xdot0", 1.0, lambda m, b, b2, lk, v: m.add_pair("p", ph.Revolute("z"), lk.end, b2, xdot0=v)),
    ("pair driven axis", (0, 0, 1, 0, 0, 0), lambda m, b, b2, lk, v: m.add_pair(
        "p", ph.Fixed(), lk.end, b2, driven=ph.Motion(v, ph.Sine(0.1, 10.0)))),
    ("pair driven", ph.Motion((0, 0, 1, 0, 0, 0), ph.Constant()), lambda m, b, b2, lk, v: m.add_pair(
        "p", ph.Fixed(), lk.end, b2, driven=v)),
    ("pair actuator", ph.Spring(1.0), lambda m, b, b2, lk, v: m.add_pair(
        "p", ph.Revolute("z"), lk.end, b2, actuator=v)),
    ("PD kp", 1.0, lambda m, b, b2, lk, v: _pd(m, b, b2, v, "kp")),
    ("PD kd", 1.0, lambda m, b, b2, lk, v: _pd(m, b, b2, v, "kd")),
    ("PD target", 0.1, lambda m, b, b2, lk, v: _pd(m, b, b2, v, "target")),
    ("PD direction", 1.0, lambda m, b, b2, lk, v: _pd(m, b, b2, v, "direction")),
    ("PD offset", 0.0, lambda m, b, b2, lk, v: _pd(m, b, b2, v, "offset")),
    ("Effort law", ph.Constant(1.0), lambda m, b, b2, lk, v: m.add_actuator("e", "k", ph.Effort(v))),
    ("Effort direction", 1.0, lambda m, b, b2, lk, v: m.add_actuator("e", "k", ph.Effort(1.0, v))),
    ("Spring k", 1.0, lambda m, b, b2, lk, v: m.add_actuator("e", "k", ph.Spring(v))),
    ("Spring c", 0.1, lambda m, b, b2, lk, v: m.add_actuator("e", "k", ph.Spring(1.0, v))),
    ("Spring rest", 0.0, lambda m, b, b2, lk, v: m.add_actuator("e", "k", ph.Spring(1.0, 0.1, v))),
    ("actuator pair", "k", lambda m, b, b2, lk, v: m.add_actuator("e", v, ph.Spring(1.0))),
    ("wrench target", "b", lambda m, b, b2, lk, v: m.add_wrench("w2", v, np.ones(6))),
    ("wrench", np.ones(6), lambda m, b, b2, lk, v: m.add_wrench("w2", b, v)),
    ("wrench point", np.zeros(3), lambda m, b, b2, lk, v: m.add_wrench("w2", b, np.ones(6), point=v)),
    ("wrench frame", "body", lambda m, b, b2, lk, v: m.add_wrench("w2", b, np.ones(6), frame=v)),
    ("wrench law", ph.Constant(1.0), lambda m, b, b2, lk, v: m.add_wrench("w2", b, np.ones(6), law=v)),
    ("Step t0", 1e-3, lambda m, b, b2, lk, v: m.add_wrench("w2", b, np.ones(6), law=ph.Step(v))),
    ("Pulse duration", 1e-3, lambda m, b, b2, lk, v: m.add_wrench("w2", b, np.ones(6), law=ph.Pulse(0.0, v))),
    ("Sine frequency", 10.0, lambda m, b, b2, lk, v: m.add_wrench("w2", b, np.ones(6), law=ph.Sine(1.0, v))),
    ("Cycloidal duration", 1e-3, lambda m, b, b2, lk, v: m.add_wrench("w2", b, np.ones(6), law=ph.Cycloidal(1.0, 0.0, v))),
    ("Table times", [0.0, 1e-3], lambda m, b, b2, lk, v: m.add_wrench("w2", b, np.ones(6), law=ph.Table(v, [0.0, 1.0]))),
    ("Table values", [0.0, 1.0], lambda m, b, b2, lk, v: m.add_wrench("w2", b, np.ones(6), law=ph.Table([0.0, 1e-3], v))),
    ("interaction reaction", "ground", lambda m, b, b2, lk, v: m.add_interaction("i", b, np.ones(6), reaction=v)),
    ("distributed link", None, lambda m, b, b2, lk, v: m.add_distributed_load("q", lk if v is None else v, (0, 0, -1.0))),
    ("distributed force", (0, 0, -1.0), lambda m, b, b2, lk, v: m.add_distributed_load("q", lk, v)),
    ("distributed frame", "world", lambda m, b, b2, lk, v: m.add_distributed_load("q", lk, (0, 0, -1.0), frame=v)),
    ("spring k", 10.0, lambda m, b, b2, lk, v: m.add_spring_damper("s2", b, lk.end, v)),
    ("spring c", 0.1, lambda m, b, b2, lk, v: m.add_spring_damper("s2", b, lk.end, 10.0, v)),
    ("spring rest_length", 0.2, lambda m, b, b2, lk, v: m.add_spring_damper("s2", b, lk.end, 10.0, rest_length=v)),
    ("spring point_b", np.zeros(3), lambda m, b, b2, lk, v: m.add_spring_damper("s2", b, lk.end, 10.0, point_b=v)),
    ("link node", 1, lambda m, b, b2, lk, v: lk.node(v)),
    ("simulate t_end", 2e-3, lambda m, b, b2, lk, v: m.simulate(v, 1e-3)),
    ("simulate dt_out", 1e-3, lambda m, b, b2, lk, v: m.simulate(2e-3, v)),
    ("simulate t_start", 0.0, lambda m, b, b2, lk, v: m.simulate(2e-3, 1e-3, t_start=v)),
    ("simulate rtol", 1e-4, lambda m, b, b2, lk, v: m.simulate(2e-3, 1e-3, rtol=v)),
    ("simulate atol", 1e-6, lambda m, b, b2, lk, v: m.simulate(2e-3, 1e-3, atol=v)),
    ("simulate band", 500.0, lambda m, b, b2, lk, v: m.simulate(2e-3, 1e-3, band=v)),
    ("simulate max_step", 1e-3, lambda m, b, b2, lk, v: m.simulate(2e-3, 1e-3, max_step=v)),
    ("simulate step", 2.5e-4, lambda m, b, b2, lk, v: m.simulate(2e-3, 1e-3, step=v)),
    ("simulate rho_inf", 0.9, lambda m, b, b2, lk, v: m.simulate(2e-3, 1e-3, rho_inf=v)),
    ("simulate integrator", "ida", lambda m, b, b2, lk, v: m.simulate(2e-3, 1e-3, integrator=v)),
    ("simulate linear_solver", "dense", lambda m, b, b2, lk, v: m.simulate(2e-3, 1e-3, linear_solver=v)),
    ("simulate error_test", "all", lambda m, b, b2, lk, v: m.simulate(2e-3, 1e-3, integrator="ida", error_test=v)),
    ("simulate max_order", 5, lambda m, b, b2, lk, v: m.simulate(2e-3, 1e-3, integrator="ida", max_order=v)),
    ("simulate record", "b", lambda m, b, b2, lk, v: m.simulate(2e-3, 1e-3, record=v)),
    # (a callback that raises, e.g. called with the wrong number of arguments, propagates its own
    # exception, as documented: junk that is callable is replaced by a valid callback)
    ("simulate callback", None, lambda m, b, b2, lk, v: m.simulate(
        2e-3, 1e-3, callback=(lambda t, i: i > 1) if callable(v) else v)),
    ("simulate initial", None, lambda m, b, b2, lk, v: m.simulate(2e-3, 1e-3, initial=v)),
    ("modes n", 2, lambda m, b, b2, lk, v: m.modes(v)),
    ("modes time", 0.0, lambda m, b, b2, lk, v: m.modes(2, time=v)),
    ("modes at", None, lambda m, b, b2, lk, v: m.modes(2, at=v)),
    ("static loads", [], lambda m, b, b2, lk, v: m.static(loads=v)),
    ("static load", ("b", np.ones(6), "world"), lambda m, b, b2, lk, v: m.static(loads=[v])),
    ("static load wrench", np.ones(6), lambda m, b, b2, lk, v: m.static(loads=[(b, v, "world")])),
    ("static steps", 2, lambda m, b, b2, lk, v: m.static(steps=v)),
    ("static time", 0.0, lambda m, b, b2, lk, v: m.static(time=v)),
    ("static tol", 1e-10, lambda m, b, b2, lk, v: m.static(tol=v)),
    ("static start", None, lambda m, b, b2, lk, v: m.static(start=v)),
    ("stress_resultants link", "l", lambda m, b, b2, lk, v: m.stress_resultants(m.simulate(2e-3, 1e-3), v)),
    ("result pose", "b", lambda m, b, b2, lk, v: m.simulate(2e-3, 1e-3).pose(v)),
    ("frame_at point", (0.1, 0, 0), lambda m, b, b2, lk, v: m.add_pair("p", ph.Spherical(), lk.end, b2.frame_at(v))),
    ("frame_at rotation", np.eye(3), lambda m, b, b2, lk, v: m.add_pair(
        "p", ph.Fixed(), lk.end.frame_at((0, 0, 0.1), v), b2)),
    ("frame_at name", "f", lambda m, b, b2, lk, v: m.add_wrench("w2", b.frame_at((0.1, 0, 0), name=v), np.ones(6))),
    ("body at", "b", lambda m, b, b2, lk, v: m.add_rigid_body("b3", 1.0, np.eye(3), at=v)),
    ("link start", "b", lambda m, b, b2, lk, v: m.add_flexible_link("l2", 0.3, PROPS, elements=2, start=v)),
    ("result pose of an offset frame", (0.1, 0, 0), lambda m, b, b2, lk, v: m.simulate(2e-3, 1e-3).pose(b.frame_at(v))),
]


@fuzz_settings(N_ARGUMENTS)
@given(data=st.data())
def test_fuzz_one_bad_argument(data):
    """A valid model, one call with one argument replaced by junk (or left good): the call
    succeeds with finite results or raises a documented exception, leaving the model as it was;
    then the model still simulates."""
    label, good, call = data.draw(st.sampled_from(CALLS), label="call")
    g = Gen(data, 0.0)
    v = g.junk(good, label) if data.draw(st.integers(0, 7)) else good
    note(f"call {label!r} with {v!r}")
    with time_limit():
        m, b, b2, lk = base_model()
        models_built.append(1)
        out = attempt(m, call, m, b, b2, lk, v)
        if isinstance(out, ph.SimulationResult):
            check_simulation(m, out, bodies=["b", "b2"], links=[lk], pairs=["k", "c", "f2"])
        elif isinstance(out, ph.ModesResult):
            check_modes(out, 10)
        elif isinstance(out, ph.StaticResult):
            check_static(out, [lk])
        elif isinstance(out, np.ndarray):
            _fin(out, label)
        # what the call added (when it succeeded) still simulates, or fails in a documented way
        r = attempt(m, m.simulate, 2e-3, 1e-3)
        if r is not FAILED:
            check_simulation(m, r, bodies=["b", "b2"], links=[lk], pairs=["k", "c", "f2"])


# ------------------------------------------------------------------ se3, sections
SE3_UNARY = [(se3.hat, (3,)), (se3.hat, (6,)), (se3.vee, (3, 3)), (se3.vee, (4, 4)),
             (se3.exp, (3,)), (se3.exp, (6,)), (se3.log, (3, 3)), (se3.log, (4, 4)),
             (se3.Ad, (4, 4)), (se3.Ad_dual, (4, 4)), (se3.ad, (6,)), (se3.ad_dual, (6,)),
             (se3.dexp, (3,)), (se3.dexp, (6,)), (se3.dexp_inv, (3,)), (se3.dexp_inv, (6,)),
             (se3.inverse, (4, 4)), (se3.quat_to_rot, (4,)), (se3.rot_to_quat, (3, 3)),
             (se3.translation, (3,))]
ANY_FLOAT = st.one_of(st.floats(-10, 10), st.floats(), st.sampled_from(WEIRD_NUMBERS))


@fuzz_settings(400)
@given(data=st.data())
def test_fuzz_se3(data):
    """phmech.se3 on stacks of arbitrary floats (huge, tiny, NaN, inf) and junk: a finite result
    of the documented shape, or ValueError (documented: phmech.ModelError is one) -- never a
    silent NaN or inf."""
    f, tail = data.draw(st.sampled_from(SE3_UNARY), label="function")
    lead = data.draw(st.sampled_from([(), (2,), (1, 3)]), label="stack")
    n = int(np.prod(lead + tail))
    x = np.array(data.draw(st.lists(ANY_FLOAT, min_size=n, max_size=n)), dtype=float).reshape(lead + tail)
    if data.draw(st.integers(0, 9)) == 0:
        x = Gen(data, 0.0).junk(x, f.__name__)
    with time_limit(), warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            y = f(x)
        except ValueError as e:
            assert str(e)
            y = None
    check_warnings(caught)
    if y is not None:
        _fin(y, f"se3.{f.__name__}({x!r})")
        assert y.shape[:len(lead)] == lead


@fuzz_settings(150)
@given(data=st.data())
def test_fuzz_se3_binary(data):
    """se3.compose, pose, rotation with arbitrary floats: finite or ValueError."""
    which = data.draw(st.sampled_from(["compose", "pose", "rotation"]))
    g = st.lists(ANY_FLOAT, min_size=16, max_size=16)
    A = np.array(data.draw(g)).reshape(4, 4)
    B = np.array(data.draw(g)).reshape(4, 4)
    try:
        with time_limit(), warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            y = se3.compose(A, B) if which == "compose" else \
                se3.pose(A[:3, :3], B[0, :3]) if which == "pose" else se3.rotation(A[0, :3], B[0, 0])
    except ValueError as e:
        assert str(e)
        return
    check_warnings(caught)
    _fin(y, f"se3.{which}")


@fuzz_settings(150)
@given(data=st.data())
def test_fuzz_sections(data):
    """Material, Section, BeamProperties with any numbers: valid finite properties (stiffness
    and inertia positive definite) or ModelError."""
    g = Gen(data, 0.2)
    with time_limit():
        p = random_properties(g, "properties")
    if isinstance(p, ph.BeamProperties):   # (not the plain objects random_properties also makes)
        for name in ("stiffness", "inertia"):
            A = np.asarray(getattr(p, name), dtype=float)
            _fin(A, name)
            assert np.all(np.linalg.eigvalsh(A) > 0), f"{name} not positive definite"


def test_fuzz_ran_enough_models():
    """The fuzz tests above generated MODELS_PER_RUN models (>= 1000), and the random mechanisms
    still reach the solvers: enough of them simulate, have modes, find a static equilibrium
    (measured at scale 1: 149, 44, 15 of 900; the rest end in documented errors, most of them
    on purpose). Skipped when those tests were deselected (pytest -k)."""
    if not models_built or not outcomes:
        pytest.skip("the model fuzz tests did not run in this session")
    assert MODELS_PER_RUN >= 1000
    assert len(models_built) >= int(MODELS_PER_RUN * SCALE), len(models_built)

    def ok(prefix):
        return sum(c for (what, out), c in outcomes.items() if what.startswith(prefix) and out == "ok")

    assert ok("simulate") >= 60 * SCALE and ok("modes") >= 20 * SCALE and ok("static") >= 5 * SCALE, \
        f"the generator degenerated: {sorted(outcomes.items())}"

"""Sizes from a frequency band: how many elements a flexible link needs so that its modes up to
a band are within a tolerance of the converged ones.

The se3 element converges at second order in the element length (docs/mass_matrix_study.md). The
error is measured on the link alone, free in space: the frequencies of N, 2N and 4N elements give
each mode's error at N by Richardson extrapolation, e_N = (f_N - f_2N) / f_2N rho / (rho - 1) with
the observed ratio rho of successive differences, at most 4 (second order; _richardson), and N
grows until every mode in the band is within the tolerance.

Why the free link. With the consistent element mass (the default) the interior of the link has no
h^2 dispersion error; its h^2 error comes from the ends, and with the sign of their support: a
clamped end raises the frequencies, a free end lowers them, by about the same amount (Table I
link, band 300 rad/s, 21 elements, against the exact Timoshenko values of phmech.timoshenko:
clamped-clamped +0.26 ... +0.32 %, free-free up to 0.43 %, and the cantilever, one end of
each, within 0.066 % because they nearly cancel; its error is not even monotone in N). The free
link has the largest error of the three and converges cleanly, towards order 2 from below (the
estimate above is 0.2 ... 3.3 % over its true error from 6 elements on), and its choice is about
the fewest that meets the tolerance on all three supports (14 elements for 1e-2, 45 for 1e-3
with a straight link's rigid-rotation coupling; before it 15 and 46, the fewest 14 and 45;
tests/test_mesh.py). Estimating on the cantilever picked 7 and 9 before that coupling, where the
clamped-clamped link is 3.8e-2 and 2.0e-2 off. With lumped mass the interior error dominates and the free link's
error is about twice the cantilever's (25 and 78 elements; fewest on all three supports 24 and
76). A mechanism's modes couple links and bodies, and a link much shorter than the wavelengths
of the band needs few elements whatever it carries. ``Mechanism(band=...,
frequency_tolerance=...)`` applies it to every flexible link added without ``elements=``.

A finished mechanism knows its supports: ``Mechanism.sized`` (size_mechanism below) measures the
mechanism's own modes in the band on meshes from 1 element up against a refined reference of
the same mechanism, and keeps the first mesh within the tolerance: the cantilever gets 7 and 9
elements, the fewest (tests/test_mesh.py; docs/user_guide.md, "Choosing the number of elements
and tolerances").
"""
from __future__ import annotations

import copy
import dataclasses
import math
import warnings

import numpy as np

from ._checks import integer, real
from . import io
from .frames import MeshChoice
from . import _model, _modes
from ._builder import Builder
from ._errors import EquilibriumWarning, ModelError, UnattachedWarning, outside_stacklevel

__all__ = ["MeshChoice", "choose_elements", "MechanismMeshChoice", "size_mechanism"]

RIGID_MODES = 6   # a free link has six rigid-body modes (zero frequency), skipped


def _free_frequencies(length: float, properties, elements: int, band: float, curvature,
                      mass: str = "consistent") -> np.ndarray:
    """Elastic free-free frequencies [Hz] of the link alone up to just above ``band``."""
    m = Builder()
    m.add_flexible_link("link", length, properties, elements=elements, curvature=curvature,
                        mass=mass)
    available = 6 * (elements + 1)
    n = min(available, RIGID_MODES + 8)
    while True:
        with warnings.catch_warnings():   # the link alone, free in space on purpose
            warnings.simplefilter("ignore", UnattachedWarning)
            f = _modes.modes(m, n).frequency[RIGID_MODES:]
        if f.size == 0 or f[-1] > band or n >= available:
            return f
        n = min(available, 2 * n)


def _richardson(f1: np.ndarray, f2: np.ndarray, f4: np.ndarray) -> float:
    """Largest relative error of the frequencies ``f1`` of N elements, from those of 2N and 4N:
    e_N = |f1 - f2| / f2 * rho / (rho - 1), rho = |f1 - f2| / |f2 - f4| the observed ratio of
    successive differences (4 at second order), kept at most 4: a mesh that converges slower
    than second order so far (rho < 4) gets the larger estimate it needs, a faster one is not
    trusted to go on. Measured on Table I's free link (the ends' error, consistent mass): the
    second-order estimate (rho = 4) was up to 4.9 % low from 6 elements on, this one 0.2 ... 3.3 %
    high."""
    d = np.abs(f1 - f2)
    with np.errstate(divide="ignore", invalid="ignore"):
        rho = np.minimum(d / np.abs(f2 - f4), 4.0)
    rho = np.where(np.isfinite(rho), rho, 4.0)
    with np.errstate(divide="ignore"):
        factor = np.where(rho > 1.0, rho / (rho - 1.0), np.inf)   # not converging yet: unknown
    return float(np.max(np.where(d > 0, d / f2 * factor, 0.0)))


def _request(band, tolerance, max_elements) -> tuple:
    """(band [Hz], tolerance, max_elements) checked: ModelError unless band > 0, 0 < tolerance
    < 1 and max_elements a positive integer."""
    band = real("band", band)
    tolerance = real("frequency tolerance", tolerance)
    if not band > 0:
        raise ModelError(f"band must be a frequency > 0 [Hz] (got {band!r})")
    if not 0 < tolerance < 1:
        raise ModelError(f"frequency tolerance must be in (0, 1) (got {tolerance!r})")
    return band, tolerance, integer("max_elements", max_elements, 1)


def choose_elements(length: float, properties, band: float, tolerance: float = 1e-3,
                    max_elements: int = 256, curvature=None, mass: str = "consistent") -> MeshChoice:
    """About the fewest elements for which every free-free mode of a flexible link up to ``band``
    [Hz] has an estimated relative frequency error within ``tolerance``: from 2 elements, each
    next count is the one the second-order error law predicts from the last estimate (5 % more),
    and a count the law says could be smaller is tried once. ``properties``: as for
    ``Mechanism.add_flexible_link`` (and ``curvature``, ``mass``). Raises ModelError for a band or tolerance that is not
    positive and when ``max_elements`` are not enough."""
    band, tolerance, max_elements = _request(band, tolerance, max_elements)
    N, last, best, tried, meshes = 2, None, None, set(), {}

    def free(n):
        if n not in meshes:
            meshes[n] = _free_frequencies(length, properties, n, band, curvature, mass)
        return meshes[n]

    while N <= max_elements and N not in tried:
        tried.add(N)
        f1, f2 = (free(n) for n in (N, 2 * N))
        if not (np.all(f1 > 0) and np.all(f2 > 0)):
            # an unstable "mode" (phm_modes reports omega^2 < 0 as a negative frequency) or a zero
            # one: a link of 1e20 m had them, in a band of 1e-300 Hz; no error estimate is possible
            bad = np.concatenate([f1, f2])
            raise ModelError(f"the free-free modes of this link (length {length:g} m) include "
                             f"{bad[~(bad > 0)][0]:.3g} Hz, not a positive frequency: its length, "
                             f"stiffness or inertia are beyond what its linearization resolves in "
                             f"double precision; give elements= instead of a band")
        inband = f2[f2 <= band]
        k = inband.size
        if k == 0:
            return MeshChoice(N, band, tolerance, 0, 0.0, ())
        if f1.size < k:   # the coarse mesh does not have that many modes yet
            if k == f2.size and f2[-1] <= band:
                # the band lies above every mode of the 2N-element mesh; the mesh's top frequency
                # grows about like N, so it needs about this many elements
                need = 2 * N * band / f2[-1] if f2[-1] > 0 else math.inf
                if need > 2 * max_elements:
                    raise ModelError(f"band {band:g} Hz lies above every mode of a {2 * N}-element "
                                     f"mesh of this link (highest {f2[-1]:.3g} Hz): resolving it "
                                     f"would take about {need:.3g} elements, more than "
                                     f"max_elements = {max_elements}; ask for a lower band")
            N *= 2
            continue
        # the second-order estimate (rho = 4) is the smallest _richardson gives: above the
        # tolerance it decides alone, and only a count it accepts needs the 4N-element mesh
        err = _richardson(f1[:k], f2[:k], f2[:k] - (f1[:k] - f2[:k]) / 4.0)
        if err <= tolerance:
            err = _richardson(f1[:k], f2[:k], free(4 * N)[:k])
        last = (N, err)
        if not math.isfinite(err):   # not converging yet at N: no error law to aim with
            N *= 2
            continue
        if err <= tolerance:
            if best is None or N < best.elements:
                best = MeshChoice(N, band, tolerance, k, err, tuple(float(x) for x in inband))
            # second order: the error falls like 1/N^2, so fewer might do; try that once
            N = int(math.ceil(N * math.sqrt(err / tolerance) * 1.02))
        else:   # aim 5 % beyond the count the error law predicts
            N = max(N + 1, int(math.ceil(N * math.sqrt(err / tolerance) * 1.05)))
            if best is not None and N >= best.elements:
                break
    if best is not None:
        return best
    msg = f" (at {last[0]} elements: {last[1]:.2g})" if last else ""
    raise ModelError(f"no mesh of at most {max_elements} elements resolves the modes up to "
                     f"{band:g} Hz within {tolerance:g}{msg}: raise max_elements, or ask for a "
                     f"lower band or a looser tolerance")


# ------------------------------------------------------------------ a mechanism, sized as a whole
@dataclasses.dataclass(frozen=True)
class MechanismMeshChoice:
    """What :meth:`Mechanism.sized` chose. ``elements``: per nonlinear link (by name), the chosen
    count; ``band`` [Hz] and ``tolerance`` asked for; ``modes_in_band``: the mechanism's modes up
    to the band that were compared (those below ``ZERO_MODE`` times the band, rigid motions, are
    not: their relative error means nothing); ``estimated_error``: a bound on their largest
    relative frequency error at the chosen meshes, the difference to the reference plus the
    reference's own error; ``reference_elements`` and ``reference_error``: the meshes of the
    reference and its error bound; ``frequencies`` [Hz]: the compared modes of the reference;
    ``tried``: how many meshes were built."""
    elements: dict
    band: float
    tolerance: float
    modes_in_band: int
    estimated_error: float
    reference_elements: dict
    reference_error: float
    frequencies: tuple
    tried: int

    def __str__(self) -> str:
        links = ", ".join(f"{k}: {v}" for k, v in self.elements.items())
        return (f"elements {links}: {self.modes_in_band} modes up to {self.band:g} Hz within "
                f"{self.estimated_error:.2g} (asked {self.tolerance:g}; reference "
                f"{', '.join(f'{k}: {v}' for k, v in self.reference_elements.items())} elements)")


#: modes below this fraction of the band on the reference's coarsest mesh are rigid motions,
#: not compared: as many are left out of every mesh
ZERO_MODE = 1e-3


def _wavenumber_weight(length: float, properties, band: float) -> float:
    """How many radians of the band's shortest wave a link spans: its length times the largest
    wavenumber at 2 pi band over bending (k^4 = omega^2 rhoA / EI, each plane), axial, shear and
    torsion waves (k = omega / c). Only the ratios between links use it: the link that spans most
    gets the most elements."""
    K = np.diag(np.asarray(properties.stiffness, dtype=float))   # torsion, bend y, bend z, axial, shear y, shear z
    I = np.diag(np.asarray(properties.inertia, dtype=float))     # rotary (x, y, z), then mass per length
    w, mu = 2 * np.pi * band, I[3]
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        k = [(w * w * mu / K[1]) ** 0.25, (w * w * mu / K[2]) ** 0.25, w * np.sqrt(mu / K[3]),
             w * np.sqrt(mu / K[4]), w * np.sqrt(mu / K[5]), w * np.sqrt(I[0] / K[0])]
    k = [x for x in k if np.isfinite(x) and x > 0]
    return length * max(k) if k else length


def _node_refs(x, found: list) -> None:
    """Every {"link": name, "node": k} reference inside an encoded call (io.model_to_dict)."""
    if isinstance(x, dict):
        if set(x) == {"link", "node"}:
            found.append(x)
        for v in x.values():
            _node_refs(v, found)
    elif isinstance(x, list):
        for v in x:
            _node_refs(v, found)


def _without_smallest(f: np.ndarray, n: int) -> np.ndarray:
    """``f`` without its ``n`` entries of smallest magnitude (the rigid motions' zero
    frequencies, whose eigensolver noise, about sqrt(eps) times the mesh's highest frequency,
    grows with the mesh), the others in their order."""
    return np.delete(f, np.argsort(np.abs(f), kind="stable")[:n]) if n else f


def size_mechanism(mech, band: float, tolerance: float, max_elements: int = 256):
    """The mechanism ``mech`` rebuilt from its add_* calls (phmech.io) with the fewest elements
    in its nonlinear links for which its own modes up to ``band`` [Hz] are within ``tolerance``
    of the converged ones; returns (Mechanism, MechanismMeshChoice). See Mechanism.sized."""
    band, tolerance, max_elements = _request(band, tolerance, max_elements)
    try:
        doc = io.model_to_dict(mech)
    except ModelError as e:
        raise ModelError(f"sized() rebuilds the mechanism from its add_* calls, and {e}") from None
    calls = doc["calls"]
    sized = {}   # call index -> link name, the nonlinear links
    for i, c in enumerate(calls):
        a = c["args"]
        if c["method"] == "add_flexible_link" and a.get("fidelity", "nonlinear") == "nonlinear":
            sized[i] = a["name"]
    if not sized:
        raise ModelError("sized(): the mechanism has no nonlinear flexible link to size")
    old = {name: mech._links[name].elements for name in sized.values()}
    refs = []
    for c in calls:
        _node_refs(c["args"], refs)
    for r in refs:
        if r["link"] in old and r["node"] not in (0, old[r["link"]]):
            raise ModelError(f"sized(): a frame sits on node {r['node']} of link {r['link']!r}, "
                             f"inside it; another mesh would move it (only its start and end "
                             f"stay): give that link elements= yourself")
    props = {name: io.decode_value(calls[i]["args"]["properties"]) for i, name in sized.items()}
    weight = {name: _wavenumber_weight(float(calls[i]["args"]["length"]), props[name], band)
              for i, name in sized.items()}
    top = max(weight.values())

    def elements(s: int) -> dict:
        return {name: max(1, int(math.ceil(s * weight[name] / top - 1e-9))) for name in weight}

    def build(counts: dict):
        d = copy.deepcopy(doc)
        for i, name in sized.items():
            a = d["calls"][i]["args"]
            a["elements"] = counts[name]
            a.pop("band", None)
            a.pop("frequency_tolerance", None)
        found = []
        for c in d["calls"]:
            _node_refs(c["args"], found)
        for r in found:
            if r["link"] in counts and r["node"] == old[r["link"]]:
                r["node"] = counts[r["link"]]
        return io.model_from_dict(d, type(mech))

    tried = [0]

    def equilibrium() -> bool:
        """Whether the initial configuration is a static equilibrium (Mechanism.modes' check)."""
        return bool(_modes.equilibrium_check(mech, model0, mech._state.poses, 0.0, False))

    def frequencies(counts: dict, n_band=None):
        """The mesh's modes [Hz] (those of Mechanism.modes, without its labels: at the
        equilibrium its check finds at the initial configuration, when it passes, with that
        equilibrium's constraint wrenches and stresses): the lowest n_band, or (None) all up to
        just above the band."""
        tried[0] += 1
        m = build(counts)
        model, poses, lam, keep = _model.linearization_point_kept(m, None)
        poses, lam, _ = _modes.equilibrium_point(m, keep, model, poses, lam, 0.0, None)
        available = 6 * len(m._car)
        n = min(available, 8 if n_band is None else n_band)
        while True:
            f = _modes.frequencies(model, n, poses, lam)
            if n_band is not None or f.size == 0 or f[-1] > band or n >= available:
                return f
            n = min(available, 2 * n)

    # the user's mechanism, analysed as modes() would: its warnings (unattached bodies, moved
    # initial values, redundant constraints, ...) are the user's to hear, and each comes once per
    # mechanism, so before the silenced analyses of its rebuilt copies
    model0, _, _ = _model.linearization_point(mech, None)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        # the reference: meshes 8, 16, 32, ... (the widest link's count, up to 8 max_elements:
        # only the choice is bounded by max_elements) until a level differs
        # from the one before by at most tolerance / 10, and by at most half of the difference
        # before that (it converges, at least at first order); its error is then taken as that
        # whole difference (2-3 times its second-order estimate, on the safe side)
        levels, s, ref, zero = [], 8, None, None
        while s <= 8 * max_elements:   # the reference may exceed what is chosen
            f = frequencies(elements(s))
            if zero is None:   # rigid motions: as many on every mesh, counted on the coarsest
                zero = int(np.count_nonzero(np.abs(f) < ZERO_MODE * band))
            e = _without_smallest(f, zero)
            k = int(np.count_nonzero(e <= band))
            levels.append(e)
            if k == 0:
                ref = (s, e[:0], 0.0)
                break
            if len(levels) >= 2 and levels[-2].size >= k:
                d = np.max(np.abs(e[:k] - levels[-2][:k]) / np.abs(e[:k]))
                dp = np.inf
                if len(levels) >= 3 and levels[-3].size >= k:
                    dp = np.max(np.abs(levels[-2][:k] - levels[-3][:k]) / np.abs(e[:k]))
                if d <= tolerance / 10 and (d <= dp / 2 or d == 0):
                    ref = (s, e[:k], float(d))
                    break
            s *= 2
        if ref is None:
            why = "" if equilibrium() else (
                " (the initial configuration is not a static equilibrium: its modes are the "
                "tangent's eigenvalues there, which need not converge like vibrations)")
            raise ModelError(f"sized(): the mechanism's modes up to {band:g} Hz do not settle "
                             f"within {tolerance / 10:g} with up to {8 * max_elements} elements "
                             f"(8 max_elements) per link{why}: raise max_elements, or ask for a "
                             f"lower band or a looser tolerance")
        s_ref, f_ref, ref_err = ref
        k = f_ref.size
        chosen, seen = None, set()
        for s in range(1, min(s_ref, max_elements) + 1):
            counts = elements(s)
            key = tuple(counts.values())
            if key in seen:
                continue
            seen.add(key)
            if s == s_ref:
                chosen = (counts, ref_err)
                break
            try:
                f = frequencies(counts, zero + k)
            except ModelError:   # too coarse to build or to have modes (no degree of freedom)
                continue
            e = _without_smallest(f, zero)
            if e.size < k:
                continue
            err = float(np.max(np.abs(e[:k] - f_ref) / np.abs(f_ref), initial=0.0))
            if err + ref_err <= tolerance:
                chosen = (counts, err + ref_err)
                break
    if chosen is None:
        raise ModelError(f"sized(): no mesh of at most {max_elements} elements per link keeps the "
                         f"mechanism's modes up to {band:g} Hz within {tolerance:g}: raise "
                         f"max_elements, or ask for a lower band or a looser tolerance")
    if not equilibrium():
        warnings.warn("sized(): the initial configuration is not a static equilibrium, so the "
                      "modes it sized for are eigenvalues of the tangent stiffness there "
                      "(Mechanism.modes)", EquilibriumWarning, stacklevel=outside_stacklevel())
    counts, err = chosen
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        out = build(counts)
    choice = MechanismMeshChoice(dict(counts), band, tolerance, k, float(err), elements(s_ref),
                                 ref_err, tuple(float(x) for x in f_ref), tried[0])
    out.sizing = choice
    return out, choice

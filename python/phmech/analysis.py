"""Oscillation analysis: spectra and dominant frequencies of sampled signals, and the energy of
each linearized mode along a simulated trajectory."""
from __future__ import annotations

from typing import Optional

import numpy as np

from . import se3
from ._errors import ModelError

__all__ = ["spectrum", "dominant_frequency", "modal_energy", "mac", "label_modes", "mode_energies",
           "MODE_KINDS"]


def _uniform(t, x) -> tuple[np.ndarray, np.ndarray, float]:
    t = np.asarray(t, dtype=float)
    x = np.asarray(x, dtype=float)
    if t.ndim != 1 or x.shape != t.shape or t.size < 8:
        raise ModelError("t and x must be 1-D arrays of the same length (at least 8 samples)")
    if not (np.all(np.isfinite(t)) and np.all(np.isfinite(x))):
        raise ModelError("t and x must be finite")
    dt = np.diff(t)
    if np.any(dt <= 0) or np.ptp(dt) > 1e-6 * dt.mean():
        raise ModelError("t must be uniformly spaced and increasing")
    return t, x, float(dt.mean())


def spectrum(t, x, pad: int = 8) -> tuple[np.ndarray, np.ndarray]:
    """Amplitude spectrum of ``x(t)`` (mean removed, Hann window, zero-padded ``pad`` times).

    Returns ``(f [Hz], |X|)``; the magnitude is scaled so that a sinusoid of amplitude A shows a
    peak of about A.
    """
    t, x, dt = _uniform(t, x)
    w = np.hanning(x.size)
    n = int(pad) * x.size
    X = np.abs(np.fft.rfft((x - x.mean()) * w, n)) * 2.0 / w.sum()
    return np.fft.rfftfreq(n, dt), X


def dominant_frequency(t, x, fmin: float = 0.0, fmax: float = np.inf, pad: int = 16) -> float:
    """Frequency [Hz] of the largest spectral peak of ``x(t)`` in ``[fmin, fmax]``.

    The peak of the zero-padded Hann spectrum is refined by a parabola through the logarithms of
    its three highest bins; for a clean sinusoid over many periods this is accurate to a small
    fraction of the bin width 1/(pad T).
    """
    f, X = spectrum(t, x, pad)
    band = np.nonzero((f >= fmin) & (f <= fmax))[0]
    band = band[(band > 0) & (band < f.size - 1)]
    if band.size == 0:
        raise ModelError("no spectral bin inside [fmin, fmax]")
    k = band[np.argmax(X[band])]
    a, b, c = np.log(X[k - 1:k + 2] + 1e-300)
    denom = a - 2 * b + c
    shift = 0.5 * (a - c) / denom if denom != 0 else 0.0
    return float(f[k] + shift * (f[1] - f[0]))


def modal_energy(mechanism, result, modes) -> np.ndarray:
    """Energy [J] of each linearized mode along a trajectory: (nt, nmodes).

    ``modes``: ``mechanism.modes(n)`` at the configuration ``result`` started from (its shapes are
    mass-normalized tangent displacements). Each carrier's displacement is the tangent
    d = log(H(0)^-1 H(t)) and its rate the body twist; the modal coordinate is q_k = phi_k^T M d
    and the modal energy 1/2 (qdot_k^2 + omega_k^2 q_k^2), M the mechanism's mass (the
    carriers' 6x6 blocks and any consistent or modal element's coupling). Meaningful for small motions about the start (vibrations): the sum over the modes
    is then the mechanical energy. Large rotations and the axial shortening of bending (second
    order in the deflection) are not modal motions: they show as spurious energy in the stiff
    axial modes, so compare modes one by one, or the total of the modes you trust, over time.
    Typical use: which modes the integrator's numerical dissipation takes energy from
    (docs/integrators.md, "Where the numerical dissipation goes")."""
    poses, twists = np.asarray(result.poses), np.asarray(result.twists)
    M = np.array([c["M"] for c in mechanism._car])
    phi = np.asarray(modes.shapes)
    if poses.ndim != 4 or poses.shape[1] != M.shape[0] or phi.shape[1:] != (M.shape[0], 6):
        raise ModelError("modal_energy: the result must record every carrier of the mechanism "
                         "(simulate without record=) and the modes must be this mechanism's")
    H0inv = np.array([se3.inverse(H) for H in poses[0]])
    d = np.array([[se3.log(H0inv[c] @ Hc) for c, Hc in enumerate(Ht)] for Ht in poses])
    Mphi = mechanism._desc.mass_times(phi)
    q = np.einsum("kci,nci->nk", Mphi, d)
    qdot = np.einsum("kci,nci->nk", Mphi, twists)
    return 0.5 * (qdot ** 2 + np.asarray(modes.omega) ** 2 * q ** 2)


# ------------------------------------------------------------------ mode shapes: MAC, labels

#: the kinds a mode is labelled with (``ModesResult.kind``). Bending "about y" is a rotation of
#: the sections about the link's local y axis: curvature kappa_y and shear gamma_z, the link
#: deflecting along its local z axis (bending in the local x-z plane); bending "about z" is
#: kappa_z with gamma_y, deflection along local y (the x-y plane). The local x axis runs along
#: the link from its start to its end (Mechanism.add_flexible_link).
MODE_KINDS = ("torsion", "bending-y", "bending-z", "axial", "rigid-body")

#: human-readable form of each kind
MODE_KIND_TEXT = {"torsion": "torsion", "bending-y": "bending about y (local x-z plane)",
                  "bending-z": "bending about z (local x-y plane)", "axial": "axial",
                  "rigid-body": "rigid-body"}

#: strain components (kappa_x, kappa_y, kappa_z, eps_x, gamma_y, gamma_z) -> kind
_STRAIN_KIND = (0, 1, 2, 3, 2, 1)


def mac(a, b=None) -> np.ndarray:
    """Modal assurance criterion between two sets of mode shapes: (na, nb) with
    ``MAC_ij = |a_i . b_j|^2 / ((a_i . a_i)(b_j . b_j))``, 1 for parallel shapes and 0 for orthogonal
    ones (plain Euclidean products of the flattened shapes; for ModesResult shapes these mix
    rotations [rad] and translations [m], so compare shapes of the same mechanism). ``a``, ``b``:
    ModesResult objects or arrays (n, ...) of shapes; ``b`` None: ``a`` against itself."""
    def flat(s, what):
        s = getattr(s, "shapes", s)
        s = np.asarray(s, dtype=float)
        if s.ndim < 1 or s.size == 0 or not np.all(np.isfinite(s)):
            raise ModelError(f"mac: {what} must be a ModesResult or a non-empty finite array of "
                             f"shapes (n, ...)")
        return s.reshape(len(s), -1) if s.ndim > 1 else s[None, :]
    A = flat(a, "a")
    B = A if b is None else flat(b, "b")
    if A.shape[1] != B.shape[1]:
        raise ModelError(f"mac: the shapes have {A.shape[1]} and {B.shape[1]} entries: not the "
                         f"same mechanism")
    num = (A @ B.T) ** 2
    den = np.outer(np.sum(A * A, axis=1), np.sum(B * B, axis=1))
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(den > 0, num / np.where(den > 0, den, 1.0), 0.0)


def element_geometry(desc, poses) -> Optional[tuple]:
    """What mode_energies needs of the elements at ``poses`` (ncarriers, 4, 4), whatever the
    shapes: their carriers a, b, lengths h [m], section stiffnesses K, T = dexp_inv(-X) and
    Ad(exp(-X)) of their relative twists X (None without elements). Modes keeps it for the
    initial configuration (python/phmech/_modes.py)."""
    els = desc.elements
    if not els:
        return None
    a = np.array([e["a"] for e in els])
    b = np.array([e["b"] for e in els])
    h = np.array([e["h"] for e in els], dtype=float)
    K = np.array([e["K"] for e in els], dtype=float)
    X = se3.log(np.einsum("eij,ejk->eik", se3.inverse(poses[a]), poses[b]))
    return a, b, h, K, se3.dexp_inv(-X), se3.Ad(se3.exp(-X))


def mode_energies(desc, poses, shapes, geometry=None) -> dict:
    """Where each mode's energy sits (used by Mechanism.modes to label the modes).

    ``desc``: the ModelDescription, ``poses`` (ncarriers, 4, 4) the configuration the modes were
    computed at, ``shapes`` (n, ncarriers, 6) tangent displacements (body frame, H exp(phi)).
    Returns a dict of arrays:

    - ``kinetic`` (n, ncarriers): phi_c^T (M phi)_c per carrier, M the mechanism's mass with any
      element couplings (twice the kinetic energy of a unit modal velocity, split by carrier;
      sums to 1 for mass-normalized shapes);
    - ``strain`` (n, nelements, 4): twice the strain energy of the shape in each element, split by
      (torsion, bending-y, bending-z, axial) (see MODE_KINDS): 1/h dX_g . (K dX)_g, dX the change
      of the element's relative twist log(H_a^-1 H_b) = dexp_inv(-X) (phi_b - Ad_{exp(-X)} phi_a),
      h its length, K the section stiffness. Linear in the shape, so exact for the tangent;
    - ``spring_strain`` (n, nsprings, 4): the same for the springs that carry a modal link's
      fixed-interface modes (phmech.fidelity.modal_sliders; ``spring_links`` names each one's
      link), k dd^2 split by the shares of its mode's strain kinds.

    ``geometry``: element_geometry(desc, poses), if already made."""
    phi = np.asarray(shapes, dtype=float)
    kin = np.einsum("nci,nci->nc", phi, desc.mass_times(phi))
    els = desc.elements
    strain = np.zeros((len(phi), len(els), 4))
    if els:
        a, b, h, K, T, AdX = element_geometry(desc, poses) if geometry is None else geometry
        xi = phi[:, b] - np.einsum("eij,nej->nei", AdX, phi[:, a])         # (n, e, 6)
        dX = np.einsum("eij,nej->nei", T, xi)
        KdX = np.einsum("eij,nej->nei", K, dX)
        prod = dX * KdX / h[None, :, None]
        for comp, kind in enumerate(_STRAIN_KIND):
            strain[:, :, kind] += prod[:, :, comp]
    # a modal link's fixed-interface modes store their strain energy in their sliders' springs:
    # k dd^2 (dd the change of the spring's length), split by the mode's kinds
    internal = [q for q in desc.springs if "kinds" in q]
    sstrain = np.zeros((len(phi), len(internal), 4))
    for i, q in enumerate(internal):
        ends = []
        for c, pt in ((q["a"], q["pa"]), (q["b"], q["pb"])):
            R, p = poses[c][:3, :3], poses[c][:3, :3] @ pt + poses[c][:3, 3]
            ends.append((p, np.einsum("ij,nj->ni", R, phi[:, c, 3:] + np.cross(phi[:, c, :3], pt))))
        n_hat = (ends[1][0] - ends[0][0]) / np.linalg.norm(ends[1][0] - ends[0][0])
        dd = (ends[1][1] - ends[0][1]) @ n_hat
        sstrain[:, i, :] = (q["kcd"][0] * dd ** 2)[:, None] * np.asarray(q["kinds"])[None, :]
    return dict(kinetic=kin, strain=strain, spring_strain=sstrain,
                spring_links=[q["link"] for q in internal])


def label_modes(desc, poses, omega, shapes, geometry=None) -> dict:
    """Label each mode by the dominant kind of its links' strain energy (MODE_KINDS).

    A mode whose links store less than half of its energy in strain (twice the strain energy
    below omega^2 / 2 for a unit modal amplitude) is ``"rigid-body"``: the bodies move and the
    links follow without deforming much (free motion, joints, springs, actuators, gravity). The
    others take the kind with the largest share of the strain energy summed over all links.
    Returns ``kind`` (list), ``strain_fractions`` (n, 4: torsion, bending-y, bending-z, axial
    shares of the links' strain energy), ``elastic_fraction`` (n,: the links' strain energy
    over the modal energy omega^2/2 phi^T M phi; 1 for a mode of free-standing links) and
    ``participation`` (list of dicts: each body's and link's share of the mode's kinetic
    energy) and ``strain_participation`` (each link's share of the strain energy).
    ``geometry``: as for mode_energies."""
    e = mode_energies(desc, poses, shapes, geometry)
    kin, strain, sstrain = e["kinetic"], e["strain"], e["spring_strain"]
    om2 = np.asarray(omega, dtype=float) ** 2
    per_kind = strain.sum(axis=1) + sstrain.sum(axis=1)     # (n, 4)
    U = per_kind.sum(axis=1)
    ktot = kin.sum(axis=1)
    ref = om2 * ktot
    with np.errstate(invalid="ignore", divide="ignore"):
        elastic = np.where(ref > 0, U / np.where(ref > 0, ref, 1.0), np.where(U > 0, np.inf, 0.0))
        frac = np.where(U[:, None] > 0, per_kind / np.where(U > 0, U, 1.0)[:, None], 0.0)
    kinds = [MODE_KINDS[int(np.argmax(frac[k]))] if elastic[k] >= 0.5 else "rigid-body"
             for k in range(len(om2))]
    groups = dict(desc.groups())
    part = [{nm: float(kin[k, cs].sum() / ktot[k]) if ktot[k] > 0 else 0.0
             for nm, cs in groups.items()} for k in range(len(om2))]
    spart = []
    for k in range(len(om2)):
        d = {}
        for lk in desc.links.values():
            i0 = desc.first_element[lk.name]
            ne = len(desc.link_elements(lk))
            own = strain[k, i0:i0 + ne].sum() + sum(
                sstrain[k, i].sum() for i, nm in enumerate(e["spring_links"]) if nm == lk.name)
            d[lk.name] = float(own / U[k]) if U[k] > 0 else 0.0
        spart.append(d)
    return dict(kind=kinds, strain_fractions=frac, elastic_fraction=elastic, participation=part,
                strain_participation=spart)

"""Modal links: add_flexible_link(fidelity="modal") assembled on a mechanism from the static
reduction of the link alone (python/phmech/_reduction.py) -- two carriers, one element carrying
the condensed stiffness, damping and mass, and a slider (prismatic pair and spring-damper) per
fixed-interface mode kept (phmech.fidelity; docs/method.md, "Modal links")."""
from __future__ import annotations

import functools
import warnings

import numpy as np

from ._checks import positive_definite
from ._errors import AccuracyWarning, ModelError, outside_stacklevel
from ._reduction import gravity_preload_sensitivity, static_reduction
from .fidelity import choose_modes, interior_modes, modal_sliders, reduction_error
from .frames import FlexibleLink, Frame, ModalChoice
from .pairs import Prismatic


def add_modal_link(mech, name, L, properties, N, eps, I, H0, given, choice, mass, modes,
                    band, tol, placed) -> FlexibleLink:
    """add_flexible_link(fidelity="modal"): two carriers (start, end) and one se3 element
    carrying the link's statically reduced stiffness, damping and mass (phmech.fidelity), and
    a slider per fixed-interface mode kept (modal_sliders)."""
    with np.errstate(over="ignore", under="ignore", invalid="ignore", divide="ignore"):
        try:
            red = static_reduction(L, properties, N, eps, mass)
        except np.linalg.LinAlgError:
            red = None
    ok = red is not None and all(np.all(np.isfinite(red[k])) for k in ("K", "D", "Mc", "M_start", "M_end"))
    if not (ok and positive_definite(red["K"], cholesky=True) and positive_definite(red["M_B"], cholesky=True)
            and positive_definite(red["M_start"], cholesky=True) and positive_definite(red["M_end"], cholesky=True)):
        raise ModelError(f"link {name!r}: its static reduction ({N} elements onto its ends) is not "
                         f"finite and positive definite in double precision (length {L:g} m with "
                         f"these properties)")
    interior = len(red["chain"]["interior"])
    modal_choice = None
    if modes is not None:
        if isinstance(modes, (bool, np.bool_)) or not isinstance(modes, (int, np.integer)) \
                or modes < 0:
            raise ModelError(f"link {name!r}: modes must be an integer >= 0 or None (got {modes!r})")
        if modes > interior:
            raise ModelError(f"link {name!r}: modes={modes} but its {N}-element chain has "
                             f"{interior} interior degrees of freedom, so at most {interior} "
                             f"fixed-interface modes (more elements=, or fewer modes)")
        n = int(modes)
        shapes = interior_modes(red, n)
        if band is not None:
            err, _ = reduction_error(red, shapes, band)
            modal_choice = ModalChoice(n, band, tol, err, False)
    elif band is not None:
        n, err, shapes = choose_modes(red, band, tol)
        modal_choice = ModalChoice(n, band, tol, err, True)
    else:
        n, shapes = 0, interior_modes(red, 0)
    for j in range(n):   # the sliders' names, before anything is added
        for nm in (f"{name}.mode{j + 1}", f"{name}.mode{j + 1}.spring"):
            if nm in mech._names:
                raise ModelError(f"link {name!r}: its mode {j + 1} needs the name {nm!r}, which "
                                 f"is already used")
    sl = modal_sliders(red, shapes, L)
    if sl["mismatch"] > 1e-8:
        raise ModelError(f"link {name!r}: its {n} fixed-interface modes as sliders reproduce the "
                         f"Craig-Bampton mass only to {sl['mismatch']:.2g} (ill-conditioned in "
                         f"double precision); keep fewer modes")
    if n and sl["damping_coupling"] > tol:
        warnings.warn(f"link {name!r}: its section damping couples its modes with each other "
                      f"and with its ends (correlation {sl['damping_coupling']:.2g}); a modal "
                      f"link keeps only each mode's own damping (exact for a damping "
                      f"proportional to the stiffness)", AccuracyWarning, stacklevel=outside_stacklevel())
    first = mech._start_link(name, eps, placed)
    # gravity's point masses: the chain's weights condensed onto the ends (phmech.fidelity;
    # also what centre_of_mass() reads); the start's gives the sliders theirs
    (m_a, c_a, _), (m_b, c_b, _) = red["gravity"]
    m_keep = m_a - sl["gravity_taken"]
    mech._car.append(dict(M=sl["M_start"], mass=m_keep, com=c_a * (m_a / m_keep), H0=H0[0],
                          t0=np.zeros(6)))
    mech._car.append(dict(M=sl["M_end"], mass=m_b, com=c_b, H0=H0[N], t0=np.zeros(6)))
    mech._modal_gravity_miss[name] = red["gravity_sag_error"]
    # measured when a build under gravity asks (_model.build)
    mech._modal_preload[name] = [functools.partial(gravity_preload_sensitivity, L, properties, N, eps, mass), None]
    mech._el.append(dict(a=first, b=first + 1, h=L, K=red["K"], D=red["D"], eps=eps,
                         mass="given", Mc=sl["Mc"], Ms=I))
    sliders = list(range(first + 2, first + 2 + n))
    for j, s in enumerate(sl["sliders"]):
        mech._car.append(dict(M=s["M"], mass=s["gravity_mass"], com=np.zeros(3), H0=H0[0],
                              t0=np.zeros(6)))
        ends = {"start": first, "end": first + 1}
        for other, C in s["couplings"].items():
            a = ends[other] if isinstance(other, str) else first + 2 + other
            mech._desc.couplings.append(dict(a=a, b=first + 2 + j, Mc=C))
    if given is not None:
        mech._given[first] = np.array(H0[0])
        mech._given[first + 1] = np.array(H0[N])
        for c in sliders:
            mech._given[c] = np.array(H0[0])
    link = FlexibleLink(name, L, 1, [first, first + 1], None, fidelity="modal", reduced_from=N,
                        clamped_frequency=red["omega_clamped"] / (2.0 * np.pi),
                        sliders=sliders, modal_choice=modal_choice,
                        modal_peaks=[list(s["peak"]) for s in sl["sliders"]])
    mech._links[name] = link
    reach = 10.0 * L
    for j, (c, s) in enumerate(zip(sliders, sl["sliders"])):
        on_start = Frame(first, np.eye(4), f"{name}.start")
        on_slider = Frame(c, np.eye(4), f"{name}.mode{j + 1}")
        mech.add_pair(f"{name}.mode{j + 1}", Prismatic(axis=s["axis"]), on_start, on_slider)
        # collinear with the slide: tension k (d - reach) = k s exactly
        mech.add_spring_damper(f"{name}.mode{j + 1}.spring", on_start, on_slider, s["k"], s["c"],
                               rest_length=reach, point_a=-reach * s["axis"])
        # its energy is the link's strain energy, of its mode's kinds (analysis.label_modes)
        mech._springs[-1].update(link=name, kinds=np.asarray(s["kinds"], dtype=float))
    if choice is not None and choice.modes_in_band > 0 and n == 0:
        warnings.warn(f"link {name!r} is modal but has {choice.modes_in_band} of its own "
                      f"(free-free) modes in the band {choice.band:g} Hz, from "
                      f"{choice.frequencies[0]:.4g} Hz: with modes=0 a modal link keeps only "
                      f"its static shapes, so it drops them; leave modes=None to have them "
                      f"chosen from the band", AccuracyWarning, stacklevel=outside_stacklevel())
    return link

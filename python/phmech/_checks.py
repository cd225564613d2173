"""Argument checks shared by the Python layer: one message style for every bad number or array.

Every value a user passes is converted here (or in the C binding, which applies the same rules),
never by a bare ``float()`` or ``np.asarray(..., dtype=float)``: those accept strings ("1.5"),
drop imaginary parts with a warning, and raise NumPy's own TypeError/ValueError for junk."""
from __future__ import annotations

import math
import numbers

import numpy as np

from ._errors import ModelError


def _kind(value) -> str:
    """A short description of what was given, for messages."""
    if isinstance(value, np.ndarray):
        return f"an array of shape {value.shape} and dtype {value.dtype}"
    return type(value).__name__


def real(name: str, value) -> float:
    """``value`` as a finite float, or ModelError naming ``name``. Accepts Python and NumPy real
    numbers (bool included) and 0-d real arrays; refuses strings, complex numbers and arrays."""
    if type(value) is float and math.isfinite(value):   # the common case, without the tests below
        return value
    if isinstance(value, np.ndarray) and value.ndim == 0 and value.dtype.kind in "biuf":
        value = value[()]
    if not isinstance(value, (numbers.Real, np.bool_)) or isinstance(value, (str, bytes)):
        raise ModelError(f"{name} must be a real number, got {value!r}")
    try:
        v = float(value)
    except (TypeError, ValueError, OverflowError):
        raise ModelError(f"{name} must be a real number, got {value!r}") from None
    if not math.isfinite(v):
        raise ModelError(f"{name} must be finite, got {v!r}")
    return v


def positive(name: str, value) -> float:
    """``value`` as a positive finite float, or ModelError naming ``name``."""
    v = real(name, value)
    if v <= 0.0:
        raise ModelError(f"{name} must be positive and finite, got {v!r}")
    return v


def integer(name: str, value, minimum: int = None) -> int:
    """``value`` as an int (Python or NumPy integer, not bool), >= ``minimum`` if given."""
    if type(value) is int and (minimum is None or value >= minimum):   # the common case
        return value
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer)) or \
            (minimum is not None and value < minimum):
        at_least = f" >= {minimum}" if minimum is not None else ""
        raise ModelError(f"{name} must be an integer{at_least} (got {value!r})")
    return int(value)


def array(name: str, value, shape: tuple, expected: str = None, finite: bool = True) -> np.ndarray:
    """``value`` as a new float64 array of ``shape``, or ModelError naming ``name`` and saying
    what was ``expected`` (default: "an array of shape ..."). Refuses strings, None, complex
    numbers, objects, ragged sequences and (when ``finite``) NaN and inf."""
    expected = expected or f"an array of real numbers of shape {shape}"
    if value is None or isinstance(value, (str, bytes)):
        raise ModelError(f"{name}: expected {expected}, got {value!r}")
    try:
        raw = np.asarray(value)
    except (TypeError, ValueError):   # ragged nested sequences, objects numpy cannot read
        raise ModelError(f"{name}: expected {expected}, got {_kind(value)} that is not a "
                         f"regular array of numbers") from None
    if raw.dtype.kind not in "biuf":
        what = {"c": "complex numbers", "U": "strings", "S": "bytes", "O": "objects (e.g. None "
                "or mixed types)"}.get(raw.dtype.kind, f"values of dtype {raw.dtype}")
        raise ModelError(f"{name}: expected {expected}, got {what}")
    if raw.shape != tuple(shape):
        raise ModelError(f"{name}: expected {expected}, got shape {raw.shape}")
    a = raw.astype(np.float64)   # a copy: the caller may keep it
    if finite and not np.all(np.isfinite(a)):
        raise ModelError(f"{name}: expected {expected}, got a non-finite value (NaN or inf)")
    return a


def real_numbers(what: str, v) -> np.ndarray:
    """A number or a (nested) sequence of numbers, flattened to float64; ModelError for anything
    else (strings, None, objects)."""
    try:
        raw = np.asarray(v)
    except (TypeError, ValueError):
        raw = np.asarray(None)
    if v is None or isinstance(v, (str, bytes)) or raw.dtype.kind not in "biuf":
        raise ModelError(f"{what}: expected real numbers, got {v!r}")
    return raw.astype(float).ravel()


def choice(what: str, value, options) -> str:
    """``value`` if it is one of the strings ``options``, else ModelError naming them."""
    if not isinstance(value, str) or value not in options:
        raise ModelError(f"{what} must be {' or '.join(map(repr, options))} (got {value!r})")
    return value


def per_coordinate(v, k: int, what: str, default: float = 1.0) -> np.ndarray:
    """One finite value per joint coordinate, (k,): ``v`` a number (the same for all) or k
    numbers; None gives ``default`` for all."""
    if v is None:
        return np.full(k, float(default))
    expected = f"a number or {k} finite number{'s' if k != 1 else ''}"
    try:
        a = real_numbers(what, v)
    except ModelError:
        raise ModelError(f"{what}: expected {expected}, got {v!r}") from None
    if a.size == 1:
        a = np.full(k, float(a[0]))
    if a.shape != (k,) or not np.all(np.isfinite(a)):
        raise ModelError(f"{what}: expected {expected}, got {v!r}")
    return a


def positive_definite(A: np.ndarray, cholesky: bool = False) -> bool:
    """A (finite) is symmetric positive definite: its eigenvalues, scaled by its largest entry,
    are positive; with ``cholesky`` the test the core applies (a Cholesky factorization, no
    tolerance)."""
    scale = np.max(np.abs(A))
    if not (np.isfinite(scale) and scale > 0):
        return False
    B = 0.5 * (A / scale + A.T / scale)   # scaled first: A + A^T may overflow
    if cholesky:
        try:
            np.linalg.cholesky(A)
        except np.linalg.LinAlgError:
            return False
    return bool(np.all(np.linalg.eigvalsh(B) > 0))


def not_rotation(R: np.ndarray) -> str:
    """Why the finite 3x3 ``R`` is not a rotation (orthonormal within 1e-6 with det +1, the
    core's test), or "" when it is one."""
    (a, b, c), (d, e, f), (g, h, i) = R.tolist()   # plain floats: 3x3 numpy calls cost more
    big = max(map(abs, (a, b, c, d, e, f, g, h, i)))
    if big > 2:   # not a rotation (and R^T R could overflow)
        return f"entries up to {big:.3g}"
    cols = ((a, d, g), (b, e, h), (c, f, i))
    err = max(abs(sum(x * y for x, y in zip(cols[j], cols[k])) - (j == k))
              for j in range(3) for k in range(j, 3))
    det = a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g)
    return "" if err <= 1e-6 and det > 0 else f"|R^T R - I| = {err:.2g}, det R = {det:.3g}"


_EYE4 = np.eye(4)
_EYE4.setflags(write=False)


def rigid_pose(x, what: str) -> np.ndarray:
    """A rigid pose [[R, p], [0, 0, 0, 1]] (R orthonormal with det +1 within 1e-6, the core's
    test; p in m), or ModelError naming ``what``."""
    if isinstance(x, np.ndarray) and x.shape == (4, 4) and x.dtype == np.float64 and \
            np.array_equal(x, _EYE4):   # the frames phmech makes mostly are
        return _EYE4.copy()
    H = array(what, x, (4, 4), "a finite 4x4 pose")
    why = not_rotation(H[:3, :3])
    if why:
        raise ModelError(f"{what}: expected a rigid 4x4 pose [[R, p], [0, 0, 0, 1]], but its R is "
                         f"not a rotation ({why})")
    if np.max(np.abs(H[3] - [0, 0, 0, 1])) > 1e-12:
        raise ModelError(f"{what}: expected a rigid 4x4 pose, but its last row is {H[3].tolist()}, "
                         f"not [0, 0, 0, 1]")
    return H


# -- plausibility: what no physical part can be (ModelError) and what looks like a unit slip or
# -- an implausible run (PlausibilityWarning, phmech._run; docs/user_guide.md "Plausibility checks")

#: relative slack of the triangle inequality of principal moments of inertia: a thin plate
#: meets it with equality (J3 = J1 + J2), which round-off may tip either way
TRIANGLE_SLACK = 1e-9


def inertia_triangle(what: str, J: np.ndarray) -> None:
    """ModelError when the principal moments J1 <= J2 <= J3 of the symmetric positive definite
    rotational inertia ``J`` [kg m^2] (about the centre of mass) violate J1 + J2 >= J3: no
    distribution of positive mass has them (J1 + J2 - J3 = 2 int m x3^2 >= 0)."""
    j = np.linalg.eigvalsh(0.5 * (J + J.T))
    if j[0] + j[1] < j[2] * (1.0 - TRIANGLE_SLACK):
        raise ModelError(
            f"{what}: inertia principal moments {j[0]:.4g}, {j[1]:.4g}, {j[2]:.4g} kg m^2 violate "
            f"the triangle inequality J1 + J2 >= J3 ({j[0]:.4g} + {j[1]:.4g} = {j[0] + j[1]:.4g} "
            f"< {j[2]:.4g}), which every body of positive mass meets: no physical body has this "
            f"inertia (check the diagonal's order and units, and that it is about the centre of "
            f"mass, in the body's axes)")


#: speed of sound sqrt(EA / rhoA) [m/s] below which a link's section looks like a unit slip:
#: engineering solids are above ~30 m/s (soft rubber); E in GPa (E = 210 for steel) gives
#: 0.16 m/s. (No upper bound: a link stiffened on purpose to approach the rigid limit, E x 1e4,
#: has 5e5 m/s; a density in g/cm^3 is caught by Material)
WAVE_SPEED_MIN = 1.0
#: a section whose radius of gyration sqrt(rhoI / rhoA) (of its mass: a stiffened section's
#: EI/EA would not tell) exceeds the link's length is no beam (a 20 x 2 mm strip given in mm:
#: 5.8 m on a 0.3 m link)
GYRATION_PER_LENGTH = 1.0
#: Young's modulus [Pa] and density [kg/m^3] below which a Material looks like a unit slip
#: (GPa or MPa; g/cm^3): the softest rubbers are ~1e5-1e6 Pa, the lightest foams ~30 kg/m^3
E_SLIP, DENSITY_SLIP = 1.0e5, 30.0
#: a revolute-type coordinate's x0 [rad] beyond which it looks like degrees: one turn
ANGLE_SLIP = 2.0 * math.pi
#: the largest fibre strain of a flexible link over a run above which it warns, by the link's
#: speed of sound sqrt(EA / rhoA): at or above STIFF_SOLID [m/s] (metals, ceramics, wood, fibre
#: composites: steel 5100, aluminium 5100, CFRP ~9000, wood ~4000) 1 %, a stress of E/100,
#: beyond their elastic limits (0.1-1 %; a steel coupler at 2.5 GPa strains 1.2 %); below it
#: (polymers ~1000-2000 m/s, elastomers ~30-100) SOFT_STRAIN_WARN, 10 %, beyond the small
#: strains a linear elastic section law is meant for (the Table I beam, E/rho = 2360 m^2/s^2 --
#: 49 m/s, a rubber -- bends to 7.7 % in tests/test_beam_dynamics.py)
STIFF_SOLID = 2500.0
STRAIN_WARN, SOFT_STRAIN_WARN = 1.0e-2, 1.0e-1


def strain_bound(K: np.ndarray, I: np.ndarray) -> tuple:
    """(bound, what) for a link of section stiffness ``K`` and inertia ``I``: the fibre strain
    above which a run warns and the class of material its speed of sound sqrt(EA / rhoA)
    suggests."""
    c = math.sqrt(K[3, 3] / I[3, 3])
    if c >= STIFF_SOLID:
        return STRAIN_WARN, (f"its speed of sound {c:.3g} m/s is a metal's, a ceramic's or a "
                             f"composite's, whose elastic limits are 0.1-1 %")
    return SOFT_STRAIN_WARN, (f"its speed of sound {c:.3g} m/s is a polymer's or an "
                              f"elastomer's; a linear elastic section law is meant for small "
                              f"strains")


def section_slips(what: str, K: np.ndarray, I: np.ndarray, length: float) -> list:
    """Messages (empty when plausible) for a link's section stiffness ``K`` and inertia ``I``
    (6x6, strain order) that look like a unit slip: a speed of sound sqrt(EA/rhoA) below
    WAVE_SPEED_MIN, or a radius of gyration sqrt(rhoI/rhoA) beyond GYRATION_PER_LENGTH times
    the ``length`` [m]."""
    EA, rhoA = K[3, 3], I[3, 3]
    c = math.sqrt(EA / rhoA)
    r = math.sqrt(max(I[1, 1], I[2, 2]) / rhoA)
    out = []
    if c < WAVE_SPEED_MIN:
        out.append(f"{what}: its speed of sound sqrt(EA / rhoA) is {c:.3g} m/s (EA {EA:.3g} N, "
                   f"rhoA {rhoA:.3g} kg/m), below the {WAVE_SPEED_MIN:g} m/s of any engineering "
                   f"solid (steel 5100 m/s, rubber ~30): Young's modulus given in GPa or MPa? "
                   f"(steel: E=210e9 Pa, not 210)")
    if r > GYRATION_PER_LENGTH * length:
        out.append(f"{what}: its section's radius of gyration sqrt(rhoI / rhoA) is {r:.3g} m, "
                   f"more than its length {length:.3g} m: no beam; section dimensions given in "
                   f"mm? (20 x 2 mm is Section.rectangle(0.02, 0.002))")
    return out


def material_slips(E: float, density: float) -> list:
    """Messages for a Material whose Young's modulus [Pa] or density [kg/m^3] looks like a unit
    slip (below E_SLIP, DENSITY_SLIP)."""
    out = []
    if E < E_SLIP:
        out.append(f"Material: E = {E:.4g} Pa is softer than the softest rubber (~1e5-1e6 Pa): "
                   f"given in GPa or MPa? Steel is E=210e9 (Pa)")
    if density < DENSITY_SLIP:
        out.append(f"Material: density = {density:.4g} kg/m^3 is lighter than solid foams "
                   f"(~{DENSITY_SLIP:g} kg/m^3 and up): given in g/cm^3? Steel is density=7850 "
                   f"(kg/m^3)")
    return out


def fibre_strain(sigma: np.ndarray, K: np.ndarray) -> np.ndarray:
    """The largest fibre strain of each of the section stress resultants ``sigma`` (..., 6)
    (strain order) of a section of diagonal stiffness ``K``: |N| / EA + |M_y| c_z / EI_y +
    |M_z| c_y / EI_z with the extreme fibre at c = sqrt(3 EI / EA) (a rectangle's exactly; a
    circle's 2 r, a thin tube's 1.4 r: within 15 %). Vectorized; no copy of ``sigma``."""
    EA = K[3, 3]
    return (np.abs(sigma[..., 3]) / EA
            + np.abs(sigma[..., 1]) * (math.sqrt(3.0 / (K[1, 1] * EA)))
            + np.abs(sigma[..., 2]) * (math.sqrt(3.0 / (K[2, 2] * EA))))

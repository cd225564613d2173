"""Materials, cross-sections and beam properties (phmech.section): hand-computed values,
independent checks (finite-difference Prandtl stress function for the torsion constant,
Cowper's thin-walled limit) and the validation errors."""
import dataclasses
import math

import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as spla

import phmech
from phmech import timoshenko
from phmech.section import BeamProperties, Material, Section, table1_properties

ModelError = phmech.ModelError


# ------------------------------------------------------------------------------- Material
def test_material_default_G():
    m = Material(E=210e9, nu=0.3, density=7850.0)
    assert m.G == pytest.approx(210e9 / 2.6, rel=1e-15)      # 80.769... GPa
    assert Material(E=70e9, nu=0.33, density=2700.0, G=26e9).G == 26e9


@pytest.mark.parametrize("kwargs,field", [
    (dict(E=0.0), "E"), (dict(E=-1.0), "E"), (dict(E=float("nan")), "E"),
    (dict(density=0.0), "density"), (dict(density=float("inf")), "density"),
    (dict(nu=0.5), "nu"), (dict(nu=-1.0), "nu"), (dict(nu="a"), "nu"),
    (dict(G=-3.0), "G"),
])
def test_material_validation(kwargs, field):
    args = dict(E=210e9, nu=0.3, density=7850.0)
    args.update(kwargs)
    with pytest.raises(ModelError, match=field):
        Material(**args)
    assert issubclass(ModelError, ValueError)


# -------------------------------------------------------------------------------- Section
def test_rectangle_geometry():
    s = Section.rectangle(0.02, 0.005)          # width along y, height along z
    assert s.A == pytest.approx(1.0e-4, rel=1e-14)
    assert s.I_y == pytest.approx(2.0833333333333333e-10, rel=1e-14)  # 0.02 * 0.005^3 / 12
    assert s.I_z == pytest.approx(3.3333333333333333e-09, rel=1e-14)  # 0.005 * 0.02^3 / 12
    assert s.I_p == pytest.approx(3.5416666666666667e-09, rel=1e-14)
    # Saint-Venant constant is symmetric in the two sides
    assert Section.rectangle(0.005, 0.02).J == pytest.approx(s.J, rel=1e-15)


# Timoshenko & Goodier, Theory of Elasticity, Table (torsion of rectangular bars):
# J = k1 a b^3 for a/b = 1, 1.5, 2, 3, 5, 10 (3 significant digits in the table).
@pytest.mark.parametrize("ratio,k1", [(1, 0.141), (1.5, 0.196), (2, 0.229), (3, 0.263),
                                      (5, 0.291), (10, 0.312)])
def test_rectangle_torsion_table(ratio, k1):
    b = 0.01
    J = Section.rectangle(ratio * b, b).J
    assert J / (ratio * b * b**3) == pytest.approx(k1, abs=6e-4)
    # Roark (Table 10.7): a b^3 (1/3 - 0.21 (b/a) (1 - (b/a)^4/12)), about 0.5 % accurate
    q = 1.0 / ratio
    roark = ratio * b * b**3 * (1.0 / 3.0 - 0.21 * q * (1.0 - q**4 / 12.0))
    assert J == pytest.approx(roark, rel=5e-3)


def _prandtl_J(a, b, n):
    """Torsion constant from the Prandtl stress function: lap(phi) = -2 on the a x b rectangle,
    phi = 0 on the boundary, J = 2 int phi dA; 5-point finite differences, n x (n b/a) cells."""
    nx, ny = n, int(round(n * b / a))
    hx, hy = a / nx, b / ny
    Tx = sp.diags([1.0, -2.0, 1.0], [-1, 0, 1], shape=(nx - 1, nx - 1)) / hx**2
    Ty = sp.diags([1.0, -2.0, 1.0], [-1, 0, 1], shape=(ny - 1, ny - 1)) / hy**2
    Lap = sp.kron(sp.eye(ny - 1), Tx) + sp.kron(Ty, sp.eye(nx - 1))
    phi = spla.spsolve(Lap.tocsc(), -2.0 * np.ones((nx - 1) * (ny - 1)))
    return 2.0 * phi.sum() * hx * hy


def test_rectangle_torsion_prandtl():
    """Independent check of the series: second-order finite differences + Richardson."""
    a, b = 0.03, 0.01
    J1, J2 = _prandtl_J(a, b, 120), _prandtl_J(a, b, 240)
    J_fd = (4.0 * J2 - J1) / 3.0
    assert Section.rectangle(a, b).J == pytest.approx(J_fd, rel=1e-6)   # measured 1.9e-7


def test_circle_and_tube_geometry():
    c = Section.circle(0.01)
    assert c.A == pytest.approx(7.853981633974483e-05, rel=1e-14)      # pi 0.01^2 / 4
    assert c.I_y == c.I_z == pytest.approx(4.908738521234052e-10, rel=1e-14)  # pi d^4 / 64
    assert c.J == pytest.approx(9.817477042468103e-10, rel=1e-14)      # pi d^4 / 32
    t = Section.tube(0.02, 0.016)
    assert t.A == pytest.approx(1.1309733552923256e-04, rel=1e-14)     # pi (4e-4 - 2.56e-4)/4
    assert t.I_y == pytest.approx(4.636990756698535e-09, rel=1e-14)    # pi (1.6e-7 - 6.5536e-8)/64
    assert t.J == pytest.approx(2.0 * t.I_y, rel=1e-15)


def test_shear_coefficients():
    nu = 0.3
    assert Section.rectangle(0.1, 0.3).shear_coefficients(nu) == \
        pytest.approx((13.0 / 15.3, 13.0 / 15.3), rel=1e-15)             # 0.84967
    assert Section.circle(0.1).shear_coefficients(nu)[0] == pytest.approx(7.8 / 8.8, rel=1e-15)
    # tube, m = 0.8: 6 (1.3) 1.64^2 / (8.8 * 1.64^2 + 23.6 * 0.64) = 20.97888 / 38.77248
    assert Section.tube(0.1, 0.08).shear_coefficients(nu)[1] == \
        pytest.approx(20.97888 / 38.77248, rel=1e-14)
    # thin-walled limit m -> 1: Cowper's 2 (1+nu) / (4 + 3 nu); solid limit m -> 0
    assert Section.tube(1.0, 1.0 - 1e-7).shear_coefficients(nu)[0] == \
        pytest.approx(2.6 / 4.9, rel=1e-12)
    assert Section.tube(1.0, 1e-7).shear_coefficients(nu)[0] == pytest.approx(7.8 / 8.8, rel=1e-12)
    with pytest.raises(ModelError, match="nu"):
        Section.circle(0.1).shear_coefficients(0.5)


@pytest.mark.parametrize("make,field", [
    (lambda: Section.rectangle(0.0, 1.0), "width_y"),
    (lambda: Section.rectangle(1.0, -2.0), "height_z"),
    (lambda: Section.circle(float("nan")), "diameter"),
    (lambda: Section.tube(0.1, 0.1), "inner_diameter"),
    (lambda: Section.tube(0.1, 0.0), "inner_diameter"),
    (lambda: Section.tube(float("inf"), 0.05), "outer_diameter"),
    (lambda: Section("hexagon", (1.0,)), "hexagon"),
])
def test_section_validation(make, field):
    with pytest.raises(ModelError, match=field):
        make()


# ------------------------------------------------------------------------- BeamProperties
def test_from_material_rectangle():
    sec, mat = Section.rectangle(0.02, 0.005), Material(E=210e9, nu=0.3, density=7850.0)
    p = BeamProperties.from_material(sec, mat)
    G, k = 210e9 / 2.6, 13.0 / 15.3
    expect_K = [G * sec.J, 210e9 * 2.0833333333333333e-10, 210e9 * 3.3333333333333333e-09,
                210e9 * 1e-4, k * G * 1e-4, k * G * 1e-4]
    expect_M = [7850 * 3.5416666666666667e-09, 7850 * 2.0833333333333333e-10,
                7850 * 3.3333333333333333e-09, 0.785, 0.785, 0.785]
    np.testing.assert_allclose(p.stiffness, np.diag(expect_K), rtol=1e-14, atol=0)
    np.testing.assert_allclose(p.inertia, np.diag(expect_M), rtol=1e-14, atol=0)
    np.testing.assert_array_equal(p.damping, np.zeros((6, 6)))
    assert (p.EI_y, p.GA_z, p.rhoA) == pytest.approx((43.75, k * G * 1e-4, 0.785), rel=1e-14)
    assert p.stiffness.flags.c_contiguous and p.stiffness.dtype == np.float64
    with pytest.raises(ValueError):
        p.stiffness[0, 0] = 1.0                       # read-only
    with pytest.raises(dataclasses.FrozenInstanceError):
        p.inertia = np.eye(6)


def test_from_material_damping_and_types():
    sec, mat = Section.circle(0.01), Material(E=70e9, nu=0.33, density=2700.0)
    D = np.diag([1e-3, 2e-3, 2e-3, 5.0, 1.0, 1.0])
    p = BeamProperties.from_material(sec, mat, damping=D)
    np.testing.assert_array_equal(p.damping, D)
    with pytest.raises(ModelError, match="section"):
        BeamProperties.from_material(mat, mat)
    with pytest.raises(ModelError, match="material"):
        BeamProperties.from_material(sec, sec)


VALUES = dict(EA=2e6, GA_y=6e5, GA_z=7e5, GJ=3e3, EI_y=5e3, EI_z=6e3,
              rhoA=873.0, rhoI_y=2.0, rhoI_z=2.5)


def test_from_values():
    p = BeamProperties.from_values(**VALUES)
    np.testing.assert_array_equal(p.stiffness.diagonal(), [3e3, 5e3, 6e3, 2e6, 6e5, 7e5])
    np.testing.assert_array_equal(p.inertia.diagonal(), [4.5, 2.0, 2.5, 873.0, 873.0, 873.0])
    assert BeamProperties.from_values(**VALUES, rhoJ=4.0).rhoJ == 4.0
    # a full (coupled) stiffness instead of the six values
    K = np.diag([3e3, 5e3, 6e3, 2e6, 6e5, 7e5])
    K[1, 5] = K[5, 1] = 1e3
    q = BeamProperties.from_values(stiffness=K, rhoA=873.0, rhoI_y=2.0, rhoI_z=2.5)
    np.testing.assert_array_equal(q.stiffness, K)
    assert q == BeamProperties(K, q.inertia)


@pytest.mark.parametrize("change,field", [
    (dict(EA=-1.0), "EA"), (dict(GA_z=0.0), "GA_z"), (dict(EI_y=float("nan")), "EI_y"),
    (dict(rhoA=0.0), "rhoA"), (dict(rhoI_z=-2.0), "rhoI_z"), (dict(rhoJ=float("inf")), "rhoJ"),
    (dict(GJ=None), "GJ"),
    (dict(stiffness=np.eye(6)), "not both"),
])
def test_from_values_validation(change, field):
    args = dict(VALUES)
    args.update(change)
    with pytest.raises(ModelError, match=field):
        BeamProperties.from_values(**args)


def _bad_K(kind):
    K = np.diag([3e3, 5e3, 6e3, 2e6, 6e5, 7e5])
    if kind == "shape":
        return np.eye(5)
    if kind == "symmetric":
        K[0, 1] = 10.0
    elif kind == "definite":
        K[3, 3] = -1.0
    elif kind == "singular":
        K[1, 2] = K[2, 1] = math.sqrt(5e3 * 6e3)
    elif kind == "finite":
        K[2, 2] = np.nan
    return K


@pytest.mark.parametrize("kind,msg", [("shape", "shape"), ("symmetric", "symmetric"),
                                      ("definite", "positive definite"),
                                      ("singular", "positive definite"), ("finite", "non-finite")])
def test_matrix_validation(kind, msg):
    M = np.diag([4.5, 2.0, 2.5, 873.0, 873.0, 873.0])
    with pytest.raises(ModelError, match=f"stiffness.*{msg}|{msg}.*stiffness"):
        BeamProperties(_bad_K(kind), M)
    with pytest.raises(ModelError, match="inertia"):
        BeamProperties(np.eye(6), -M)
    with pytest.raises(ModelError, match="damping.*semi-definite"):
        BeamProperties(np.eye(6), M, -np.eye(6))
    BeamProperties(np.eye(6), M, np.zeros((6, 6)))   # zero damping is fine


# ------------------------------------------------------------------------------- Table I
def test_table1_properties():
    p = table1_properties()
    assert (p.EI_y, p.GA_z, p.rhoI_y, p.rhoA) == (5143.0, 656625.0, 2.1797, 873.0)
    L = 1.0
    xz = timoshenko.frequencies(5, L, p.EI_y, p.GA_z, p.rhoA, p.rhoI_y, "clamped-free")
    # every other family must start well above the fifth Table I mode
    xy1 = timoshenko.frequencies(1, L, p.EI_z, p.GA_y, p.rhoA, p.rhoI_z, "clamped-free")[0]
    axial1 = math.pi / 2 * math.sqrt(p.EA / p.rhoA) / L
    torsion1 = math.pi / 2 * math.sqrt(p.GJ / p.rhoJ) / L
    assert xy1 == pytest.approx(100.0 * xz[0], rel=1e-12)     # both stiffnesses x 1e4
    assert min(xy1, axial1, torsion1) > 2.5 * xz[-1]
    assert p.rhoJ == pytest.approx(p.rhoI_y + p.rhoI_z)
    with pytest.raises(ModelError, match="stiff_factor"):
        table1_properties(stiff_factor=0.5)

"""Mechanism.graphs() (paper (25)), the tree placement rule of the initial configuration, and bad
input that must raise (never crash or hang)."""
import numpy as np
import pytest

import phmech as ph
from phmech import se3
from phmech import _model

from test_graphs import B_K_f, B_K_r

PROPS = type("P", (), dict(stiffness=np.diag([1e2, 1e2, 1e2, 1e5, 1e4, 1e4]),
                           inertia=np.diag([1e-3, 1e-3, 1e-3, 1.0, 1.0, 1.0])))


def body(m, name, **kw):
    return m.add_rigid_body(name, 1.0, np.eye(3) * 0.01, **kw)


def test_fig3_through_the_mechanism_api_gives_eq25():
    m = ph.Mechanism()
    R = [body(m, f"R{i}") for i in (1, 2, 3)]
    F = [m.add_flexible_link(f"F{i}", 1.0, PROPS, elements=2) for i in (1, 2, 3)]
    rev = ph.Revolute("z")
    for name, a, b in [("k1", F[0].start, m.ground), ("k2", R[0], F[0].end), ("k3", F[1].start, R[0]),
                       ("k4", F[2].start, R[0]), ("k5", R[1], F[1].end), ("k6", R[1], F[2].end),
                       ("k7", R[2], R[1])]:
        m.add_pair(name, rev, a, b)
    m.add_interaction("i1", R[2], (0, 0, 0, 1.0, 0, 0))   # reaction: the ground -> edge (3, 0)
    g = m.graphs()
    np.testing.assert_array_equal(g.B_K_r, B_K_r)
    np.testing.assert_array_equal(g.B_K_f, B_K_f)
    np.testing.assert_array_equal(g.B_I_r, [[0], [0], [-1]])
    np.testing.assert_array_equal(g.B_I_f, np.zeros((6, 1)))
    assert g.B_K.rigid_rows == ("R1", "R2", "R3")
    assert g.B_K.flexible_rows == ("F1L", "F1R", "F2L", "F2R", "F3L", "F3R")
    assert g.B_K.columns == tuple(f"k{i}" for i in range(1, 8))
    assert g.G_F == [("F1", "F1L", "F1R"), ("F2", "F2L", "F2R"), ("F3", "F3L", "F3R")]
    assert len(g.loops()) == 1


def test_tree_places_serial_chain_and_keeps_relative_poses_across_pairs_without_x0():
    # Rule (topology.place_tree): x0 wins over a given pose; across a pair without x0 the far
    # carrier keeps its given pose RELATIVE to the near one (the given poses are the reference).
    m = ph.Mechanism()
    a = body(m, "a", pose=se3.rotation("z", 0.1))           # moved by the tree: x0 given
    b = body(m, "b", pose=se3.rotation("z", 0.3))           # follows a: pair without x0
    link = m.add_flexible_link("L", 1.0, PROPS, elements=4)
    T = se3.translation([1.0, 0, 0])
    m.add_pair("p1", ph.Revolute("z"), m.ground, a, x0=0.5)
    m.add_pair("p2", ph.Revolute("z"), a, b)
    m.add_pair("p3", ph.Fixed(), ph.Frame(a.carrier, T), link.end)   # link placed from its end
    H, _, _, _ = _model.initial(m)
    np.testing.assert_allclose(H[a.carrier], se3.rotation("z", 0.5), atol=1e-14)
    # p2 at its given angle 0.3 - 0.1 = 0.2 rad: b at 0.5 + 0.2
    np.testing.assert_allclose(H[b.carrier], se3.rotation("z", 0.7), atol=1e-14)
    # the link, unstressed and straight, ends at a's frame (1, 0, 0): its start is 1 m behind
    end = se3.rotation("z", 0.5) @ T
    np.testing.assert_allclose(H[link.nodes[-1]], end, atol=1e-13)
    np.testing.assert_allclose(H[link.nodes[0]][:3, 3], end[:3, 3] - end[:3, 0], atol=1e-13)


def test_given_poses_that_violate_a_pair_are_refused():
    # a's given pose (5, 5, 5) m is overridden by x0, but it is the reference of p2, whose frames
    # (the origins of a and b) are then sqrt(75) = 8.66 m apart: refused, not re-posed
    m = ph.Mechanism()
    a = body(m, "a", pose=se3.translation([5, 5, 5]))
    b = body(m, "b", pose=se3.rotation("z", 0.3))
    m.add_pair("p1", ph.Revolute("z"), m.ground, a, x0=0.5)
    m.add_pair("p2", ph.Revolute("z"), a, b)
    with pytest.raises(ph.ModelError, match=r"pair 'p2' \(Revolute\).*'a' and 'b' are 8\.66025 m apart"):
        _model.initial(m)


def test_unconnected_body_is_free_and_falls():
    """Allowed, and said (tests/test_unattached.py): a body no pair joins to the ground falls."""
    m = ph.Mechanism(gravity=(0, 0, -9.81))
    body(m, "free", pose=se3.translation([0, 0, 1]))
    with pytest.warns(ph.UnattachedWarning, match=r"bodies/links \['free'\] are not connected"):
        r = m.simulate(0.5, 0.05, integrator="ida")
    np.testing.assert_allclose(r.poses[-1, 0, 2, 3], 1 - 0.5 * 9.81 * 0.25, rtol=1e-6)


@pytest.mark.parametrize("case", ["unknown", "self", "duplicate", "inertia", "mass", "nan", "span",
                                  "nan_x0"])
def test_bad_input_raises(case):
    m = ph.Mechanism()
    a = body(m, "a")
    with pytest.raises(ph.ModelError):
        if case == "unknown":
            m.add_pair("p", ph.Revolute(), "ground", "nobody")
        elif case == "self":
            m.add_pair("p", ph.Revolute(), a, a)
        elif case == "duplicate":
            body(m, "a")
        elif case == "inertia":
            m.add_rigid_body("b", 1.0, np.diag([1.0, 1.0, -1.0]))
        elif case == "mass":
            m.add_rigid_body("b", 0.0, np.eye(3))
        elif case == "nan":
            m.add_rigid_body("b", float("nan"), np.eye(3))
        elif case == "span":
            m.simulate(-1.0, 0.1, integrator="ida")
        elif case == "nan_x0":
            m.add_pair("p", ph.Revolute(), "ground", a, x0=float("nan"))


def test_solver_failure_reports_ida_reason_and_time(capfd):
    m = ph.Mechanism()
    a = body(m, "a")
    m.add_pair("p", ph.Revolute("z"), m.ground, a, xdot0=1.0)
    with pytest.raises(ph.SolverError, match=r"IDA.*t = .*\(IDASolve: .*too much accuracy"):
        m.simulate(1.0, 0.5, rtol=1e-30, atol=1e-40, integrator="ida")   # IDA: too much accuracy requested
    # IDA's message is in the exception only: SUNDIALS prints nothing (SUNDIALS 7's default error
    # handler and logger would; csrc/util/sundials_compat.h removes them)
    assert capfd.readouterr() == ("", "")

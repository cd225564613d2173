"""A chain of 200 rigid links released from rest: the consistent initial values of a model too
large for dense least squares (csrc/dae/ic_schur.c: the sparse Schur complement of the
constraint rows; python/phmech/topology.py: redundant rows tested only for loop-closing pairs).

Reference: the planar chain in absolute angles phi_i (link i: mass m, length L, centre at L/2,
inertia I about it), at rest and straight along x under gravity -y: M(phi) phi'' = Q with
M = sum_i m J_i^T J_i + I e_i e_i^T (J_i = d r_i / d phi) and Q_j = -m g sum_i dy_i/dphi_j; the
relative joint accelerations are the differences of phi''. phmech's joint rates after one tiny
step h are a h + O(h^2) (from rest the integrators start from the consistent accelerations)."""
import numpy as np

import phmech as ph
from phmech import se3

N, L, MASS, G = 200, 0.1, 0.1, 9.81
I_C = MASS * L ** 2 / 12


def chain() -> ph.Mechanism:
    m = ph.Mechanism(gravity=(0, -G, 0))
    prev = ph.Frame(-1, np.eye(4))
    for i in range(N):
        b = m.add_rigid_body(f"l{i}", MASS, np.diag([1e-6, I_C, I_C]), com=(L / 2, 0, 0))
        m.add_pair(f"k{i}", ph.Revolute("z"), prev, b, x0=0.0)
        prev = ph.Frame(b.carrier, se3.translation([L, 0, 0]))
    return m


def reference_joint_accelerations() -> np.ndarray:
    # straight along x at rest: d r_i / d phi_j = (0, L) for j < i, (0, L/2) for j = i (y only)
    J = np.tril(np.full((N, N), L), -1) + np.diag(np.full(N, L / 2))   # dy_i / dphi_j
    M = MASS * J.T @ J + I_C * np.eye(N)
    Q = -MASS * G * J.sum(axis=0)
    phi_dd = np.linalg.solve(M, Q)
    return np.diff(np.concatenate([[0.0], phi_dd]))


def test_a_long_chain_starts_with_the_right_accelerations():
    m = chain()
    h = 1e-6
    res = m.simulate(h, h, integrator="ida", rtol=1e-10)
    rates = np.array([res.joint(f"k{i}")["xdot"][1, 0] for i in range(N)])
    a = reference_joint_accelerations()
    # measured: largest difference 2.8e-13 of max |a| (IDA, h = 1e-6 and 1e-7 s, and the
    # generalized-alpha alike: round-off of the 200 x 200 reference)
    np.testing.assert_allclose(rates / h, a, atol=1e-9 * np.max(np.abs(a)))
    assert m.redundant_constraints == []

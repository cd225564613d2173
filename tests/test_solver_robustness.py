"""Solver robustness: runs that once hung or failed at t = 0 must finish, or fail with a clear
SolverError in bounded time -- never hang. Each case runs in a subprocess with a time limit, so a
regression fails this test instead of hanging the suite."""
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

PRELUDE = textwrap.dedent("""
    import warnings; warnings.simplefilter("ignore")
    import numpy as np, phmech as ph
    from phmech import se3
    A, B, C, D = 0.2, 0.6, 0.5, 0.5   # crank, coupler, rocker, ground [m]
    def bar(m, name, L, mass=1.0):
        J = np.diag([1e-4, mass * L**2 / 12, mass * L**2 / 12])
        return m.add_rigid_body(name, mass, J, com=(L / 2, 0, 0))
    T = lambda x: se3.translation([x, 0, 0])
    m = ph.Mechanism(gravity=(0, -9.81, 0))
    crank, coupler, rocker = bar(m, "crank", A), bar(m, "coupler", B), bar(m, "rocker", C)
    m.add_pair("k1", ph.Revolute("z"), m.ground, crank, x0=0.6, xdot0=4.0)
    m.add_pair("k2", ph.Revolute("z"), ph.Frame(crank.carrier, T(A)), coupler)
    m.add_pair("k4", ph.Revolute("z"), ph.Frame(-1, T(D)), rocker)
""")


def run(code: str, limit: float = 60.0) -> str:
    out = subprocess.run([sys.executable, "-c", PRELUDE + textwrap.dedent(code)],
                         capture_output=True, text=True, timeout=limit)
    assert out.returncode == 0, out.stderr[-2000:]
    return out.stdout


def test_open_chain_with_a_body_accelerating_from_rest_does_not_hang():
    # The rocker starts at rest under gravity; IDA's first step was ~1e-11 s, where the
    # multipliers' Newton corrections were round-off / h and the step crept down to 1e-18 s.
    out = run("""
        r = m.simulate(0.003, 0.001, integrator="ida")
        print(r.stats["steps"], r.joint("k4")["xdot"][-1][0])
    """)
    steps, rate = out.split()
    assert int(steps) < 1000
    # rocker released horizontal at rest: initial angular acceleration m g (C/2) / I_pivot
    C = 0.5  # rocker length [m], 1 kg, COM at C/2, pivot at its frame origin
    I_pivot = 1.0 * C**2 / 12 + 1.0 * (C / 2) ** 2
    alpha = -9.81 * (C / 2) / I_pivot
    assert float(rate) == pytest.approx(alpha * 0.003, rel=2e-3)


def test_closed_fourbar_runs_at_rtol_1e10():
    out = run("""
        m.add_pair("k3", ph.Revolute("z"), ph.Frame(coupler.carrier, T(B)), ph.Frame(rocker.carrier, T(C)))
        r = m.simulate(0.5, 0.01, rtol=1e-10, integrator="ida")
        res = m.constraint_residuals(r)
        print(r.stats["steps"], max(np.max(np.abs(v)) for v in res.values()))
    """, limit=120)
    steps, worst = out.split()
    assert int(steps) > 10 and float(worst) < 1e-8


def test_manipulator_first_step_at_rtol_1e8_and_1e10():
    """The Fig. 3 manipulator (examples/manipulator.py, 8 elements per link) under its PD
    set-point step from rest: the consistent accelerations of the links' nodes (1e8 .. 5e8
    rad/s^2) decay within ~15 ps, and IDA's every-state error test admits a first step of only
    ~6e-15 s at rtol 1e-8 (~6e-16 s at 1e-10). IDA's 10 error-test failures from the first step
    of 1e-8 s reach 3.8e-14 s, the floor was 1e-14 s: IDA_ERR_FAIL at t = 0 with KLU (the auto
    choice here) at both tolerances. run_ida now retries the first step from the same consistent
    values (csrc/integrate/ida.c). Measured over 2 ms: 988 and 5817 steps, the two runs 3.6e-13 m
    apart, ledgers 7.9e-10 and 6.9e-11 of the energy scale."""
    examples = str(Path(__file__).resolve().parents[1] / "examples")
    out = run(f"""
        import sys
        sys.path.insert(0, {examples!r})
        import manipulator as M
        m = M.build(M.ManipulatorParams())[0]
        r8, r10 = (m.simulate(0.002, 1e-3, rtol=rtol, integrator="ida") for rtol in (1e-8, 1e-10))
        print(r8.stats["linear_solver"], np.abs(r8.poses[:, :, :3, 3] - r10.poses[:, :, :3, 3]).max(),
              r8.stats["ledger_relative"], r10.stats["ledger_relative"])
    """)
    solver, diff, ledger8, ledger10 = out.split()
    assert solver == "klu"
    assert float(diff) < 1e-10
    assert float(ledger8) < 1e-8 and float(ledger10) < 1e-9


def test_manipulator_dense_lu_matches_klu_from_the_first_step():
    """IDA's difference-quotient Jacobian (the dense LU) perturbs a state by 1/weight: 1e300 for
    the energy ledger's integrals, whose rates it moved by cj 1e300, inf once cj > 1.8e8 (the
    manipulator's first steps are ~1e-15 s). The ledger's columns were inf, its corrections 0 or
    NaN: over the first 2 ms at rtol 1e-8 one Newton failure (a NaN iterate) and a ledger
    residual of 9.2e-5 of the energy scale, against KLU's 7.9e-10 (csrc/integrate/ida.c, ida_atol).
    Measured with the ledger fixed: no Newton failure, ledger 6.7e-10, the two runs 1.0e-12 m
    apart. The dense LU now takes the closed-form Jacobian too (ida_jac_dense): 988 steps as
    KLU's (1028 before), ledger 6.8e-10, 8.0e-12 m apart (tests/test_ida_linear_solvers.py)."""
    examples = str(Path(__file__).resolve().parents[1] / "examples")
    out = run(f"""
        import sys
        sys.path.insert(0, {examples!r})
        import manipulator as M
        m = M.build(M.ManipulatorParams())[0]
        rd, rk = (m.simulate(0.002, 1e-3, rtol=1e-8, integrator="ida", linear_solver=s)
                  for s in ("dense", "klu"))
        print(rd.stats["nonlinear_conv_fails"], rd.stats["ledger_relative"],
              np.abs(rd.poses[:, :, :3, 3] - rk.poses[:, :, :3, 3]).max())
    """)
    fails, ledger, diff = out.split()
    assert int(fails) == 0
    assert float(ledger) < 1e-8
    assert float(diff) < 1e-10


def test_manipulator_set_point_step_at_a_breakpoint():
    """The same set-point step at t = 1 ms (a Step law: a breakpoint, restart from consistent
    values) failed the same way at the restart (IDA_ERR_FAIL at t = 0.001 s, h = 3.8e-14 s, KLU
    at rtol 1e-8 and 1e-10); the first-step retry applies at each restart. Measured: 1533 and
    6584 steps over 3 ms."""
    examples = str(Path(__file__).resolve().parents[1] / "examples")
    out = run(f"""
        import sys
        sys.path.insert(0, {examples!r})
        import manipulator as M
        p = M.ManipulatorParams()
        m = M.build(p, target=tuple(ph.Step(t0=1e-3, value=v) for v in p.target))[0]
        for rtol in (1e-8, 1e-10):
            r = m.simulate(0.003, 1e-3, rtol=rtol, integrator="ida", linear_solver="klu")
            print(r.t[-1], r.stats["ledger_relative"])
    """)
    vals = [float(v) for v in out.split()]
    assert vals[0] == pytest.approx(0.003) and vals[2] == pytest.approx(0.003)
    assert vals[1] < 1e-8 and vals[3] < 1e-9

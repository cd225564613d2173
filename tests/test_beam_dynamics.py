"""Single flexible link: modes, statics, free vibration energy, input validation.
References: the exact Timoshenko frequency equation (phmech.timoshenko), the analytic roll-up of
a cantilever under an end moment 2 pi EI / L, conservation of energy, the energy ledger."""
import numpy as np
import pytest

import phmech as pm   # the public names
from phmech import timoshenko
from phmech._core import ModelError
from phmech.section import TABLE1, table1_properties
from phmech import _model


def cantilever(props, N=21, damping=None):
    m = pm.Mechanism()
    if damping is not None:
        props = type("P", (), dict(stiffness=props.stiffness, inertia=props.inertia, damping=damping))()
    b = m.add_flexible_link("b", TABLE1["L"], props, elements=N)
    m.add_pair("clamp", pm.Fixed(), m.ground, b.start)
    return m, b


def test_cantilever_modes_timoshenko_N21():
    m, _ = cantilever(table1_properties(), N=21)
    md = m.modes(5)
    ref = timoshenko.frequencies(5, TABLE1["L"], TABLE1["EI"], TABLE1["kGA"], TABLE1["rhoA"], TABLE1["rhoI"])
    err = np.abs(md.omega / ref - 1)
    # docs/method.md section 4.2: lumped se3, N = 21, first five modes within about 0.7 %
    assert np.all(err < 0.007), err
    # second order convergence: N = 42 reduces the error about four times
    m2, _ = cantilever(table1_properties(), N=42)
    err2 = np.abs(m2.modes(5).omega / ref - 1)
    assert np.all(err2 < 0.4 * err), (err, err2)


def test_rollup_end_moment_closes_circle():
    P = table1_properties(1.0)
    m, b = cantilever(P, N=21)
    EI = TABLE1["EI"]
    st = m.static(loads=[(b.end, (0, -2 * np.pi * EI, 0, 0, 0, 0), "body")], steps=8)
    x = st.positions(b)
    assert np.linalg.norm(x[-1] - x[0]) < 1e-3 * TABLE1["L"]
    # every node on the circle of radius L / (2 pi)
    r = TABLE1["L"] / (2 * np.pi)
    centre = x[0] + np.array([0, 0, r])
    assert np.max(np.abs(np.linalg.norm(x - centre, axis=1) - r)) < 1e-9


def _released(P, damping=None, rtol=1e-8, t_end=0.8):
    m, b = cantilever(P, N=21, damping=damping)
    EI = TABLE1["EI"]
    F = 0.25 * 3 * EI  # linear tip deflection 0.25 L
    st = m.static(loads=[(b.end, (0, 0, 0, 0, 0, -F), "world")], steps=4)
    assert -st.positions(b)[-1, 2] >= 0.2 * TABLE1["L"]
    return m.simulate(t_end, 0.01, rtol=rtol, initial=st, integrator="ida"), b


def test_free_vibration_energy_conserved():
    r, b = _released(table1_properties(1.0))
    e = r.energy
    E0 = e["total"][0]
    drift = np.max(np.abs(e["total"] - E0)) / E0
    assert drift <= 1e-4, drift
    # it really oscillates: the tip passes the undeformed axis within the first period
    assert np.max(r.tip(b)[:, 2]) > 0.0


def test_damped_ledger_closes():
    P = table1_properties(1.0)
    D = 1e-3 * np.asarray(P.stiffness)  # Kelvin-Voigt, 1 ms retardation time
    r, _ = _released(P, damping=D, t_end=0.4)
    e = r.energy
    E0 = e["total"][0]
    assert e["dissipated"][-1] > 1e-3 * E0  # damping is active
    assert np.max(np.abs(e["ledger"])) <= 1e-5 * E0, np.max(np.abs(e["ledger"])) / E0


@pytest.mark.parametrize("kw", [dict(length=0.0), dict(length=-1.0), dict(elements=0),
                                dict(elements=2.5), dict(discretization="bogus"),
                                dict(length=float("nan"))])
def test_bad_link_input(kw):
    m = pm.Mechanism()
    args = dict(name="b", length=1.0, properties=table1_properties(), elements=4)
    args.update(kw)
    with pytest.raises(ModelError):
        m.add_flexible_link(**args)


def test_bad_stiffness_and_frames():
    P = table1_properties()
    bad = type("P", (), dict(stiffness=-np.asarray(P.stiffness), inertia=P.inertia, damping=None))()
    m = pm.Mechanism()
    with pytest.raises(ModelError):
        m.add_flexible_link("b", 1.0, bad)
    b = m.add_flexible_link("c", 1.0, P, elements=2)
    with pytest.raises(ModelError):
        m.add_pair("p", pm.Fixed(), "nowhere", b.start)
    m.add_pair("p", pm.Fixed(), m.ground, b.start)
    with pytest.raises(ModelError):
        m.simulate(-1.0, 0.1, integrator="ida")
    with pytest.raises(ModelError):
        m.simulate(1.0, 0.1, linear_solver="magic", integrator="ida")


def test_core_simulate_rejects_bad_initial_arrays_without_crashing():
    # the binding's early error path once returned an uninitialized pointer (a crash)
    from phmech import _core
    m, _ = cantilever(table1_properties(), N=2)
    model = _model.build(m)
    tout = np.array([0.0, 0.01])
    with pytest.raises(ValueError, match="initial poses"):
        _core.model_simulate(model, tout, 1e-6, 1e-8, 0, np.zeros((2, 2)), None, None, 0.0)
    with pytest.raises(ValueError, match="initial poses"):
        _core.model_simulate(model, tout, 1e-6, 1e-8, 0, "junk", None, None, 0.0)

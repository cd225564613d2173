"""Long runs stop cleanly on Ctrl-C and return what was computed so far."""
import os
import signal
import threading
import time

import numpy as np
import pytest

import phmech as ph
from phmech.section import table1_properties


def test_ctrl_c_returns_the_partial_result():
    m = ph.Mechanism()
    b = m.add_flexible_link("b", 1.0, table1_properties(1.0), elements=21)
    m.add_pair("clamp", ph.Fixed(), m.ground, b.start)
    m.add_wrench("tap", b.end, (0, 0, 0, 0, 0, 50.0), law=ph.Pulse(t0=0.0, duration=0.01))
    # Python's own Ctrl-C handler, also where the test runner was started with SIGINT ignored
    # (a background job of a non-interactive shell)
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    # SIGINT from another thread while the C core integrates with the GIL released: 0.5 s after
    # its first output, not after simulate's call (a fresh clone's run on a loaded machine lost
    # its worker to a KeyboardInterrupt, probably raised in the Python set-up before the core's
    # handler was in place)
    timer = threading.Timer(0.5, os.kill, (os.getpid(), signal.SIGINT))
    t0 = time.perf_counter()

    def give_up(t, i):
        if i == 0:
            timer.start()
        # safety net: if the interrupt is lost, stop the run after 20 s (and the assertion on
        # `interrupted` below fails) instead of integrating for minutes
        return time.perf_counter() - t0 > 20.0
    try:
        res = m.simulate(200.0, 0.01, rtol=1e-8, linear_solver="klu", callback=give_up, integrator="ida")
    finally:
        timer.cancel()
        signal.signal(signal.SIGINT, previous)
    elapsed = time.perf_counter() - t0
    assert res.interrupted
    assert elapsed < 30.0
    n = len(res.t)
    assert 2 <= n < 20001
    assert res.t[-1] < 200.0
    assert res.poses.shape[0] == n and np.all(np.isfinite(res.poses))
    assert np.all(np.isfinite(res.energy["total"]))


def test_callback_sees_every_output_once_in_order_and_its_exception_propagates():
    # the core asks the callback inside its signal check (one GIL round trip per output):
    # every output still reaches it once, in order, and an exception it raises stops the run
    m = ph.Mechanism()
    b = m.add_flexible_link("b", 1.0, table1_properties(1.0), elements=3)
    m.add_pair("clamp", ph.Fixed(), m.ground, b.start)
    m.add_wrench("tap", b.end, (0, 0, 0, 0, 0, 50.0), law=ph.Pulse(t0=0.0, duration=0.01))
    for integrator in ("generalized-alpha", "ida"):
        calls = []
        res = m.simulate(0.05, 0.005, integrator=integrator, callback=lambda t, i: calls.append((i, t)))
        assert not res.interrupted
        assert [i for i, _ in calls] == list(range(len(res.t)))
        np.testing.assert_array_equal([t for _, t in calls], res.t)

        def boom(t, i):
            if i == 3:
                raise ValueError("stop here")

        with pytest.raises(ValueError, match="stop here"):
            m.simulate(0.05, 0.005, integrator=integrator, callback=boom)


def test_a_monitor_flag_without_a_truth_value_neither_stops_nor_breaks_the_run(monkeypatch):
    """Without a per-output callback the core reads RunMonitor.terminated itself; a flag whose
    truth cannot be taken is no request to stop (it was a SystemError: an exception left set)."""
    from phmech import _run

    class NoTruth:
        def __bool__(self):
            raise RuntimeError("no truth value")

    init = _run.RunMonitor.__init__

    def patched(self, *a, **k):
        init(self, *a, **k)
        self.terminated = NoTruth()

    monkeypatch.setattr(_run.RunMonitor, "__init__", patched)
    monkeypatch.setattr(_run.RunMonitor, "__call__", lambda self, t, steps, h: False)
    m = ph.Mechanism(gravity=(0, -9.81, 0))
    b = m.add_rigid_body("b", 1.0, np.eye(3) * 0.01, com=(0.1, 0, 0))
    m.add_pair("k", ph.Revolute("z"), m.ground, b, x0=0.3)
    res = m.simulate(0.05, 1e-2, integrator="generalized-alpha", step=1e-3)
    assert len(res.t) == 6 and res.t[-1] == pytest.approx(0.05)   # ran to its end


def test_a_callback_that_stops_the_run_marks_it_interrupted():
    # results.py documents ``interrupted`` as "stopped by Ctrl-C or the callback": a run the
    # callback stopped at 0.3 s of 1 s is not a whole run (it read False before 2026-12-07)
    m = ph.Mechanism(gravity=(0, 0, -9.81))
    b = m.add_rigid_body("rod", 1.0, np.diag([1e-4, 1 / 12, 1 / 12]), com=(0.5, 0, 0))
    m.add_pair("pivot", ph.Revolute(axis="y"), m.ground, b)
    for integrator in ("generalized-alpha", "ida", "tree"):
        r = m.simulate(1.0, 0.01, callback=lambda t, i: t >= 0.3, integrator=integrator)
        assert r.interrupted and r.t[-1] == pytest.approx(0.3) and len(r.t) == 31, integrator
        r = m.simulate(0.1, 0.01, callback=lambda t, i: False, integrator=integrator)
        assert not r.interrupted and len(r.t) == 11, integrator

"""Progress of static load stepping (Mechanism.static(progress=True), the core's monitor of
phm_static_monitored); simulate's bar is tested in tests/test_default_integrator.py."""
import numpy as np
import pytest

import phmech as ph
from phmech import _core, studies
from phmech import _model


def loaded_cantilever():
    m, leaf = studies.se3_cantilever(8)
    return m, leaf, [(leaf.end, (0, 0, 0, 0, 0, 3000.0), "world")]


def test_static_monitor_sees_every_load_step_and_can_stop():
    m, leaf, loads = loaded_cantilever()
    ref = m.static(loads=loads, steps=4)
    model = _model.build(m, ref.loads)
    calls = []
    P, lam, it = _core.model_static(model, None, 0.0, 4, 1e-10,
                                    lambda s, n, ds: calls.append((s, n, ds)) and False)
    np.testing.assert_array_equal(P, ref.poses)          # watching changes nothing
    assert [c[0] for c in calls] == pytest.approx([0.25, 0.5, 0.75, 1.0])
    assert calls[-1][1] == it and all(c[2] == 0.25 for c in calls)
    assert [c[1] for c in calls] == sorted(c[1] for c in calls)
    with pytest.raises(KeyboardInterrupt, match="stopped by the caller at load factor 0.25"):
        _core.model_static(model, None, 0.0, 4, 1e-10, lambda s, n, ds: True)
    with pytest.raises(ZeroDivisionError):              # the monitor's exception comes through
        _core.model_static(model, None, 0.0, 4, 1e-10, lambda s, n, ds: 1 / 0)


def test_static_progress_bar(capsys):
    m, leaf, loads = loaded_cantilever()
    st = m.static(loads=loads, steps=4, progress=True)
    err = capsys.readouterr().err
    assert "phmech static: 100%" in err and "load factor 1/1" in err
    assert f"{st.iterations} Newton iterations" in err
    m.static(loads=loads, steps=4)
    assert capsys.readouterr().err == ""                 # off by default

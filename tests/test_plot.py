"""phmech.plot: every function draws what it says from a result (checked on the artists'
data against the result's numbers), returns its Axes/Figure, never shows, and the module is
imported lazily. The interactive view (plotly) is tested when plotly is installed."""
import subprocess
import sys

import numpy as np
import pytest

import matplotlib
matplotlib.use("Agg")

import phmech as ph
from phmech import studies


@pytest.fixture(scope="module")
def run():
    m, leaf = studies.se3_cantilever(6)
    m.add_wrench("tap", leaf.end, (0, 0, 0, 0, 0, 50.0), law=ph.Pulse(t0=0.0, duration=2e-3),
                 frame="world")
    res = m.simulate(0.4, 2e-3)
    return m, leaf, res


def test_import_phmech_does_not_import_matplotlib():
    code = "import sys, phmech; print('matplotlib' in sys.modules); phmech.plot; print('matplotlib' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.split() == ["False", "True"]


def test_trajectory_and_energy_draw_the_results_numbers(run):
    import matplotlib.pyplot as plt
    m, leaf, res = run
    ax = ph.plot.trajectory(res, [leaf, "clamp"], components="z", scale=1e3, unit="mm")
    lines = ax.get_lines()
    np.testing.assert_array_equal(lines[0].get_ydata(), 1e3 * res.tip(leaf)[:, 2])
    assert "[mm]" in ax.get_ylabel() and ax.get_xlabel() == "t [s]"
    fig, given = plt.subplots()
    assert ph.plot.trajectory(res, leaf.end, ax=given) is given      # draws into the given Axes
    fig = ph.plot.energy(res)
    a0, a1 = fig.axes[:2]
    labels = [ln.get_label() for ln in a0.get_lines()]
    assert labels[:3] == ["kinetic", "potential (elastic + gravity)", "total E"]
    np.testing.assert_array_equal(a1.get_lines()[0].get_ydata(), res.energy["ledger"])
    fig, one = plt.subplots()
    assert ph.plot.energy(res, ax=one) is fig and len(fig.axes) == 2     # the ledger on a twin axis
    np.testing.assert_array_equal(fig.axes[1].get_lines()[0].get_ydata(), res.energy["ledger"])
    plt.close("all")


def test_spectrum_marks_the_peak_and_separates_close_references():
    import matplotlib.pyplot as plt
    t = np.linspace(0.0, 4.0, 2001)
    x = 1e-3 * np.sin(2 * np.pi * 5.0 * t)
    ax = ph.plot.spectrum(t, x, scale=1e3, unit="mm", fmax=20,
                          references={"model": 5.01, "formula": 4.98})
    peak = [ln for ln in ax.get_lines() if ln.get_label().startswith("peak")][0]
    assert peak.get_xdata()[0] == pytest.approx(5.0, abs=1e-3)
    assert "resolution 1/T = 0.25 Hz" in peak.get_label()
    legend = [tx.get_text() for tx in ax.get_legend().get_texts()]
    assert "model: 5.01 Hz" in legend and "formula: 4.98 Hz" in legend
    zoom = ax.figure.axes[1]                  # references 0.03 Hz apart on a 20 Hz axis: zoomed
    lo, hi = zoom.get_xlim()
    assert hi - lo < 0.2 and lo < 4.98 and hi > 5.01
    plt.close("all")


def test_draw_mode_shapes_and_animation(run, tmp_path):
    import matplotlib.pyplot as plt
    m, leaf, res = run
    ax = ph.plot.draw(m, res, time=0.1, plane="xz")
    i = int(np.argmin(np.abs(res.t - 0.1)))
    link = ax.get_lines()[0]
    np.testing.assert_allclose(link.get_xdata(), res.positions(leaf)[i, :, 0])
    np.testing.assert_allclose(link.get_ydata(), res.positions(leaf)[i, :, 2])
    assert ax.get_title() == f"mechanism, t = {res.t[i]:.4g} s"
    with pytest.raises(ph.ModelError, match="plane"):
        ph.plot.draw(m, plane="xw")
    modes = m.modes(3, time=1.0)          # after the pulse: an equilibrium
    ax = ph.plot.mode_shape(modes, 0, m)
    assert "mode 1" in ax.get_title() and "bending about y" in ax.get_title()
    fig = ph.plot.modes(modes, mechanism=m)
    assert len(fig.axes) == 3
    path = tmp_path / "a.gif"
    anim = ph.plot.animate(m, res, str(path), fps=10, t_max=0.2)
    from PIL import Image
    assert Image.open(path).n_frames == 3
    with pytest.raises(ph.ModelError, match=r"\.gif"):
        ph.plot.animate(m, res, str(tmp_path / "a.avi"))
    from matplotlib import animation
    if animation.writers.is_available("ffmpeg"):
        ph.plot.animate(m, res, str(tmp_path / "a.mp4"), fps=10, t_max=0.2)
        assert (tmp_path / "a.mp4").stat().st_size > 0
    else:
        with pytest.raises(ph.ModelError, match="needs the ffmpeg program.*save as .gif"):
            ph.plot.animate(m, res, str(tmp_path / "a.mp4"))
    plt.close("all")
    del anim


def test_mode_shape_deflects_along_the_mode():
    import matplotlib.pyplot as plt
    m, leaf = studies.se3_cantilever(6)
    modes = m.modes(2)
    ax = ph.plot.mode_shape(modes, 0, plane="xz")
    deformed = [ln for ln in ax.get_lines() if ln.get_color() == "C0"][0]
    z = deformed.get_ydata()
    assert z[0] == pytest.approx(0.0, abs=1e-12)
    assert abs(z[-1]) == pytest.approx(0.15 * 1.0, rel=0.02)     # 15 % of the 1 m beam
    plt.close("all")


def test_interactive_view_with_plotly(run):
    go = pytest.importorskip("plotly.graph_objects")
    m, leaf, res = run
    fig = ph.plot.interactive(m, res, fps=10, t_max=0.2)
    assert isinstance(fig, go.Figure) and len(fig.frames) == 3
    first = fig.frames[1].data[0]
    np.testing.assert_allclose(first.z, res.positions(leaf)[50, :, 2])
    assert [s.label for s in fig.layout.sliders[0].steps] == ["0.000", "0.100", "0.200"]
    fig = ph.plot.interactive(m, modes=m.modes(2, time=1.0), mode=1)
    assert "mode 2" in fig.layout.title.text and len(fig.frames) == 16
    fig = ph.plot.interactive(m)
    assert len(fig.data) == 2       # the link and the clamp


def test_convergence_and_sweep_plots_draw_their_numbers():
    import phmech.plot as pp
    import xarray as xr
    N = np.array([4, 8, 16, 32])
    E = np.stack([1.0 / N ** 2, -3.0 / N ** 2], axis=1)      # the sign is dropped (log axes)
    ax = pp.convergence(N, E, labels=["a", "b"], order=2)
    lines = ax.get_lines()
    np.testing.assert_array_equal(lines[1].get_xdata(), N)
    np.testing.assert_allclose(lines[1].get_ydata(), 3.0 / N ** 2)
    np.testing.assert_allclose(lines[2].get_ydata(), 1.0 / N ** 2)   # the slope -2 reference
    with pytest.raises(ph.ModelError, match="2 columns of errors but 1 labels"):
        pp.convergence(N, E, labels=["a"])
    grid = xr.Dataset({"f": (("m",), [3.0, 2.0, 1.0])}, coords={"m": [1.0, 2.0, 3.0]})
    ax = pp.sweep(grid, "f", reference=[3.0, 2.0, 1.5])
    np.testing.assert_array_equal(ax.get_lines()[0].get_ydata(), [3.0, 2.0, 1.0])
    smp = xr.Dataset({"f": (("sample",), [1.0, np.nan, 2.0, 2.5])},
                     coords={"p": (("sample",), [0.1, 0.2, 0.3, 0.4])})
    ax = pp.sweep(smp, "f", bins=3)
    assert sum(p.get_height() for p in ax.patches) == 3 and "3 of 4 samples" in ax.get_title()
    with pytest.raises(ph.ModelError, match="'g' is not a variable"):
        pp.sweep(smp, "g")

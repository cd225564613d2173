"""Seeing results: trajectories, the energy ledger, spectra, mode shapes, the mechanism at an
instant, animations (matplotlib), and an interactive 3-D view for Jupyter (plotly).

``import phmech`` does not import this module or matplotlib; ``phmech.plot`` (or
``import phmech.plot``) does. Every function returns what it drew on (a matplotlib Axes or
Figure; ``ax=`` draws into an existing Axes) and never calls ``plt.show()``: in a script save
the figure (``ax.figure.savefig(...)``), in Jupyter it shows by itself.

What is drawn (phmech conventions: SI units, world axes): a flexible link is the polyline
through its nodes (so it shows deformed), a rigid body is a star from its frame origin to the
points where its pairs attach (a marker when it has none), a pair is a marker at the origin of
its first frame. ``plane="xy"`` (or ``"xz"``, ``"yz"``) draws a 2-D projection, otherwise a 3-D
view.

The interactive view uses plotly (``pip install plotly``): a pure-Python wheel whose figures
render in Jupyter (and VS Code, and saved HTML) through JavaScript, without a display server or
a compiled widget extension; pyvista and k3d need VTK or a Jupyter widget extension, meshcat a
server. docs/user_guide.md, "Plotting", says more."""
from __future__ import annotations

from typing import Optional

import numpy as np

import matplotlib.pyplot as plt
import matplotlib.ticker

from . import _plotdata, analysis
from ._plotaxes import _AXNAME, _axes, _axes2d, _draw_geometry, _is3d, _limits, _plotly, _traces
from ._errors import ModelError
from .frames import FlexibleLink
from .results import ModesResult, SimulationResult

__all__ = ["trajectory", "energy", "spectrum", "convergence", "sweep", "mode_shape", "modes",
           "campbell", "draw", "animate", "interactive"]



# ------------------------------------------------------------------------------ time series
def trajectory(result: SimulationResult, items, ax=None, components: str = "xyz",
               scale: float = 1.0, unit: Optional[str] = None):
    """Positions and joint coordinates against time; returns the Axes.

    ``items``: one or a list of: a pair's name (its joint coordinates ``x``, rad or m by the
    pair's type), a body, a frame (link.end, ...) or a body's name (its origin's world
    ``components`` of "xyz" [m]), a flexible link or its name (its end node). ``scale``
    multiplies the values (e.g. 1e3 with ``unit="mm"``)."""
    if not isinstance(result, SimulationResult):
        raise ModelError(f"trajectory: expected a SimulationResult (got {type(result).__name__})")
    items = list(items) if isinstance(items, (list, tuple)) else [items]
    if not items:
        raise ModelError("trajectory: nothing to plot (give pairs, bodies, frames or links)")
    if not set(components) <= set(_AXNAME) or not components:
        raise ModelError(f"trajectory: components must be letters of 'xyz' (got {components!r})")
    ax = _axes2d(ax)
    n0 = len(ax.get_lines())
    kinds = set()
    for it in items:
        if isinstance(it, str) and it in result._pairs:
            x = result.joint(it)["x"]
            for j in range(x.shape[1]):
                ax.plot(result.t, scale * x[:, j], label=f"{it}" + (f"[{j}]" if x.shape[1] > 1 else ""))
            kinds.add("joint")
            continue
        if isinstance(it, FlexibleLink) or (isinstance(it, str) and it in result._links):
            name = it if isinstance(it, str) else it.name
            p, lab = result.tip(it), f"{name} end"
        else:
            p = result.position(it)
            lab = it if isinstance(it, str) else getattr(it, "name", "") or "frame"
        for c in components:
            ax.plot(result.t, scale * p[:, _AXNAME.index(c)], label=f"{lab} {c}")
        kinds.add("position")
    u = unit or ("m" if kinds == {"position"} else "rad or m")
    what = ("position" if kinds == {"position"} else "joint coordinate" if kinds == {"joint"}
            else "position, joint coordinate")
    mine = ax.get_lines()[n0:]
    if len(mine) == 1:                    # one curve: its name in the label, no legend
        ax.set(xlabel="t [s]", ylabel=f"{mine[0].get_label()} [{u}]")
    else:
        ax.set(xlabel="t [s]", ylabel=f"{what} [{u}]")
        ax.legend(fontsize=8, loc="best")
    if not ax.get_title():
        ax.set_title("trajectories")
    ax.grid(alpha=0.3)
    return ax


def energy(result: SimulationResult, ax=None):
    """The energy ledger of a simulation; returns the Figure.

    Upper panel: kinetic, potential (elastic + gravity) and total energy, the energy supplied
    through the ports and the energy dissipated [J], and E - E0 - (supplied - dissipated)'s
    ingredients; lower panel: the balance error (the ledger residual) [J] and its size relative
    to the run's energy scale (``result.stats["energy_scale"]``). ``ax``: two Axes to draw
    into (energies, ledger), or one (the ledger then goes on a second y axis)."""
    if not isinstance(result, SimulationResult):
        raise ModelError(f"energy: expected a SimulationResult (got {type(result).__name__})")
    E, t = result.energy, result.t
    twin = False
    if ax is None:
        fig, (a0, a1) = plt.subplots(2, 1, figsize=(9.5, 5.6), sharex=True,
                                     gridspec_kw=dict(height_ratios=(2.2, 1)))
    elif isinstance(ax, (list, tuple, np.ndarray)) and len(ax) == 2:
        a0, a1 = ax
        fig = a0.figure
    else:
        a0, a1, twin = ax, ax.twinx(), True
        fig = ax.figure
    a0.plot(t, E["kinetic"], label="kinetic")
    a0.plot(t, E["elastic"] + E["gravity"], label="potential (elastic + gravity)")
    a0.plot(t, E["total"], "k", lw=1.2, label="total E")
    a0.plot(t, E["supplied"], "--", label="supplied through ports")
    a0.plot(t, E["dissipated"], ":", label="dissipated")
    a0.set(ylabel="energy [J]", title="energy ledger: E - E0 = supplied - dissipated + residual")
    a0.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    a0.grid(alpha=0.3)
    scale = result.stats.get("energy_scale", 0.0) if result.stats else 0.0
    a1.plot(t, E["ledger"], color="C3", lw=1, label="balance error (ledger residual)")
    a1.set(ylabel="residual [J]")
    if not twin:
        a1.set(xlabel="t [s]")
        rel = f", max {np.max(np.abs(E['ledger'])) / scale:.2g} of the energy scale {scale:.3g} J" \
            if scale > 0 else ""
        a1.set_title(f"balance error{rel}", fontsize=9)
        a1.grid(alpha=0.3)
    else:
        a0.set(xlabel="t [s]")
        a1.legend(fontsize=8, loc="lower right")
    fig.tight_layout()
    return fig


def spectrum(t, x, ax=None, fmin: float = 0.0, fmax: Optional[float] = None,
             references: Optional[dict] = None, unit: str = "m", scale: float = 1.0,
             log: bool = True, pad: int = 8, title: Optional[str] = None):
    """Amplitude spectrum of ``x(t)`` (phmech.analysis.spectrum: mean removed, Hann window,
    zero-padded) with its largest peak in [fmin, fmax] marked (phmech.analysis.dominant_frequency)
    and the frequency resolution 1/T of the record stated; returns the Axes.

    ``references``: {label: frequency [Hz]} drawn as vertical lines (e.g. a linearized mode, a
    formula); references closer together than the plot can separate are shown again in a
    zoomed inset. ``unit``/``scale``: the unit of ``x * scale`` for the axis label."""
    f, X = analysis.spectrum(t, x, pad)
    T = float(t[-1] - t[0])
    hi = f[-1] if fmax is None else float(fmax)
    fp = analysis.dominant_frequency(t, x, fmin=fmin, fmax=hi)
    refs = {str(k): float(v) for k, v in (references or {}).items()}
    lo = max(fmin, 0.0)
    vals = [fp] + list(refs.values())
    span = max(vals) - min(vals)
    zoom = len(refs) >= 2 and span < 0.03 * (hi - lo)   # the lines would overlap at full scale
    ins, own = None, ax is None
    if ax is None and zoom:
        fig, (ax, ins) = plt.subplots(1, 2, figsize=(10, 4.2), gridspec_kw=dict(width_ratios=(2, 1)))
    elif ax is None:
        ax = _axes2d(None)
    elif zoom:
        ins = ax.inset_axes([0.6, 0.08, 0.37, 0.33])
    sel = (f >= fmin) & (f <= hi)
    Xs = scale * X
    (ax.semilogy if log else ax.plot)(f[sel], Xs[sel] + (1e-300 if log else 0), lw=1, color="C0",
                                      label=f"|X|, {len(t)} samples over T = {T:.4g} s")
    peak = float(np.interp(fp, f, Xs))
    ax.plot([fp], [peak], "v", color="C3", ms=8, label=f"peak {fp:.5g} Hz "
            f"(resolution 1/T = {1 / T:.3g} Hz)")
    styles = ["--", ":", "-.", (0, (5, 2, 1, 2)), (0, (1, 1))]
    for i, (lab, val) in enumerate(refs.items()):
        ax.axvline(val, color=f"C{i + 1}", ls=styles[i % len(styles)], lw=1.2,
                   label=f"{lab}: {val:.5g} Hz")
    ax.set_xlim(lo, hi)
    if log:
        top = Xs[sel].max()
        ax.set_ylim(max(Xs[sel].min(), 1e-6 * top), 3 * top)
    ax.set(xlabel="frequency [Hz]", ylabel=f"amplitude [{unit}]",
           title=title or f"spectrum: peak at {fp:.5g} Hz")
    if ins is not None:
        c = 0.5 * (max(vals) + min(vals))
        w = max(1.5 * span, 1e-4 * max(abs(c), 1e-300))
        # the same windowed transform evaluated finely (the padded FFT's bins are too coarse)
        fz = np.linspace(c - w, c + w, 201)
        tt, xx = np.asarray(t, dtype=float), np.asarray(x, dtype=float)
        win = np.hanning(xx.size)
        Xz = scale * np.abs(np.exp(-2j * np.pi * np.outer(fz, tt - tt[0])) @ ((xx - xx.mean()) * win)) \
            * 2.0 / win.sum()
        ins.plot(fz, Xz, color="C0", lw=1)
        ins.plot([fp], [np.interp(fp, fz, Xz)], "v", color="C3", ms=8)
        for i, val in enumerate(refs.values()):
            ins.axvline(val, color=f"C{i + 1}", ls=styles[i % len(styles)], lw=1.5)
        ins.set_xlim(c - w, c + w)
        ins.ticklabel_format(useOffset=False)
        ins.tick_params(labelsize=7)
        ins.grid(alpha=0.3)
        if own:
            ins.set_title(f"zoom, linear: the marks lie within {span:.3g} Hz\n"
                          f"({'<' if span < 1 / T else '~'} the resolution 1/T = {1 / T:.3g} Hz)",
                          fontsize=8)
            ins.set_xlabel("frequency [Hz]", fontsize=8)
            ins.figure.tight_layout()
        else:                          # an inset: keep it bare
            ins.set_yticks([])
            ins.set_title(f"zoom: within {span:.3g} Hz", fontsize=7)
    if len(refs) >= 3 and ins is None:      # many lines across the axis: legend beside it
        ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))
        if own:
            ax.figure.set_figwidth(9.5)
            ax.figure.tight_layout()
    else:
        ax.legend(fontsize=8, loc="upper right" if ins is not None else "best")
    ax.grid(alpha=0.3, which="both")
    return ax


# ------------------------------------------------------------------------------ geometry
def convergence(sizes, errors, ax=None, labels=None, style: str = "-", order: Optional[float] = None,
                xlabel: str = "elements N", ylabel: str = "|relative error|"):
    """Errors against model size on log-log axes: ``errors`` (len(sizes),) or (len(sizes), k),
    one line per column (``labels``: k names), ``style`` their line style (colours C0, C1, ...
    by column, so two discretizations drawn with two styles keep one colour per mode);
    ``order``: a reference slope size^-order through the first column's last point. Returns the
    Axes."""
    N = np.asarray(sizes, dtype=float)
    E = np.abs(np.asarray(errors, dtype=float))
    if E.ndim == 1:
        E = E[:, None]
    if N.ndim != 1 or E.shape[0] != N.size or N.size < 2 or not np.all(N > 0):
        raise ModelError(f"convergence: sizes must be > 0 with one row of errors each (got {N.shape} "
                         f"sizes, errors {E.shape})")
    if labels is not None and len(labels) != E.shape[1]:
        raise ModelError(f"convergence: {E.shape[1]} columns of errors but {len(labels)} labels")
    ax = ax if ax is not None else plt.subplots(figsize=(6.5, 4.2))[1]
    for k in range(E.shape[1]):
        ok = E[:, k] > 0      # an exact value has no place on a log axis
        ax.loglog(N[ok], E[ok, k], style, marker="o", ms=3, color=f"C{k % 10}",
                  label=None if labels is None else labels[k])
    if order is not None and E[-1, 0] > 0:
        ax.loglog(N, E[-1, 0] * (N / N[-1]) ** (-order), "k:", lw=1, label=f"slope -{order:g}")
    ax.set(xlabel=xlabel, ylabel=ylabel)
    ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())   # 2 x 10^0 ... overlap
    ax.grid(True, which="both", alpha=0.3)
    if labels is not None or order is not None:
        ax.legend(fontsize=7, ncol=2)
    return ax


def campbell(mechanism, pair: str, speeds, n: int = 4, ax=None, orders=(1, 2),
             hz: bool = False):
    """A Campbell diagram: the ``n`` lowest frequencies of ``mechanism`` about its steady
    rotation at each speed Omega of ``speeds`` [rad/s] about the Revolute pair ``pair`` on the
    ground (``Mechanism.modes(n, spin=(pair, Omega))``: centrifugal stiffening, spin softening
    and Coriolis coupling; docs/method.md section 7.6), against Omega, with the lines k Omega
    of the ``orders`` k (a resonance where a frequency crosses one). ``hz``: frequencies in Hz
    (omega / 2 pi) instead of rad/s. The frequencies are sorted at each speed (crossing modes
    are not followed). Returns the Axes; its ``campbell`` attribute holds (speeds, omega
    (len(speeds), n) [rad/s], nan where fewer modes exist)."""
    W = np.asarray(speeds, dtype=float)
    if W.ndim != 1 or W.size < 1 or not np.all(np.isfinite(W)):
        raise ModelError(f"campbell: speeds must be a 1-D array of finite numbers [rad/s] (got "
                         f"shape {W.shape})")
    om = np.full((W.size, n), np.nan)
    for i, w in enumerate(W):
        o = np.sort(mechanism.modes(n, spin=(pair, float(w))).omega)[:n]
        om[i, :o.size] = o
    k = 1 / (2 * np.pi) if hz else 1.0
    ax = ax if ax is not None else plt.subplots(figsize=(6.5, 4.2))[1]
    for j in range(n):
        ax.plot(W, k * om[:, j], "o-", ms=3, color=f"C{j % 10}", label=f"mode {j + 1}")
    for q in orders:
        ax.plot(W, k * q * W, "k:", lw=0.8)
        ax.annotate(f"{q:g}x", (W[-1], k * q * W[-1]), fontsize=7)
    ax.set(xlabel="speed Omega [rad/s]", ylabel="frequency [Hz]" if hz else "omega [rad/s]")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=7)
    ax.campbell = (W, om)
    return ax


def sweep(ds, var: str, ax=None, reference=None, bins: Optional[int] = None,
          x: Optional[str] = None, y: Optional[str] = None):
    """One variable of a ``phmech.sweep`` result (an xarray.Dataset): against the parameter of a
    one-parameter grid (a line; ``reference``: values on the same grid drawn dashed), or, over
    samples (dimension ``sample``), a histogram of its finite values (failed points are NaN and
    left out; the title says how many), or with ``x`` and ``y`` (two sampled parameters) a
    scatter of the samples coloured by ``var``. Returns the Axes."""
    if var not in getattr(ds, "data_vars", {}):
        raise ModelError(f"sweep: {var!r} is not a variable of this result "
                         f"(has {sorted(getattr(ds, 'data_vars', {}))})")
    v = ds[var]
    ax = ax if ax is not None else plt.subplots(figsize=(6.5, 4.2))[1]
    unit = v.attrs.get("units")
    name = f"{var} [{unit}]" if unit else var
    if "sample" in v.dims and x is not None and y is not None:
        for p in (x, y):
            if p not in ds.variables:
                raise ModelError(f"sweep: {p!r} is not a parameter of this result")
        sc = ax.scatter(ds[x].values, ds[y].values, c=np.asarray(v.values, dtype=float))
        ax.figure.colorbar(sc, ax=ax, label=name)
        ax.set(xlabel=x, ylabel=y)
    elif "sample" in v.dims:
        x = np.asarray(v.values, dtype=float).reshape(-1)
        ok = np.isfinite(x)
        ax.hist(x[ok], bins=bins or max(5, int(ok.sum()) // 6))
        ax.set(xlabel=name, ylabel="samples",
               title=f"{var}: {int(ok.sum())} of {x.size} samples, mean {np.mean(x[ok]):.5g}, "
                     f"std {np.std(x[ok]):.3g}" if ok.any() else f"{var}: no finite samples")
    else:
        if len(v.dims) != 1:
            raise ModelError(f"sweep: {var!r} has dimensions {v.dims}; draw one parameter at a time "
                             f"(select the others, e.g. ds.sel(...) or ds.isel(...))")
        d = v.dims[0]
        ax.plot(ds[d].values, v.values, "o-", label="phmech")
        if reference is not None:
            ax.plot(ds[d].values, np.asarray(reference, dtype=float), "k--", label="reference")
            ax.legend()
        ax.set(xlabel=d, ylabel=name)
    ax.grid(alpha=0.3)
    return ax


def draw(mechanism, state=None, time: Optional[float] = None, ax=None, plane: Optional[str] = None,
         ghost=None, labels: bool = True, title: Optional[str] = None):
    """The mechanism at one instant: deformed links (blue, node markers at their ends), rigid
    bodies (black) and pairs (red circles); returns the Axes.

    ``state``: a SimulationResult (at ``time`` [s], the nearest output; default the last), a
    StaticResult, poses (ncarriers, 4, 4), or None (the initial configuration). ``ghost``: a
    second state drawn in light grey behind (e.g. the target equilibrium). ``plane``: "xy",
    "xz", "yz" for a 2-D projection, None for 3-D."""
    poses, what = _plotdata.poses_of(mechanism, state, time)
    ax = _axes(ax, plane)
    d = mechanism._desc
    g = _plotdata.geometry(d.links, d.bodies, _plotdata.pair_rows(mechanism), poses)
    pts = _plotdata.all_points(g)
    if ghost is not None:
        gg = _plotdata.geometry(d.links, d.bodies, _plotdata.pair_rows(mechanism),
                                _plotdata.poses_of(mechanism, ghost, None)[0])
        _draw_geometry(ax, gg, plane, ghost=True)
        pts += _plotdata.all_points(gg)
    _draw_geometry(ax, g, plane, labels=labels)
    _limits(ax, plane, pts)
    ax.set_title(title if title is not None else f"mechanism, {what}")
    return ax


# ------------------------------------------------------------------------------ modes


def mode_shape(modes: ModesResult, k: int = 0, mechanism=None, ax=None,
               plane: Optional[str] = None, scale: Optional[float] = None):
    """Mode ``k`` (0-based) drawn on the configuration it was computed at (grey), with its
    frequency and label in the title; returns the Axes. Green bars across the links lie along
    their sections' local y axes, so that torsion shows. ``scale``: the modal amplitude (default:
    the largest carrier displacement is 15 % of the mechanism's size; for modes of rotations
    alone, the largest rotation is 0.6 rad). ``mechanism``: draws its pairs
    too."""
    if not isinstance(modes, ModesResult) or modes.poses is None:
        raise ModelError("mode_shape: expected a ModesResult from Mechanism.modes")
    n = len(modes.omega)
    if isinstance(k, bool) or not isinstance(k, (int, np.integer)) or not 0 <= k < n:
        raise ModelError(f"mode_shape: k must be an integer 0..{n - 1} (got {k!r})")
    ax = _axes(ax, plane)
    pairs = _plotdata.pair_rows(mechanism)
    g0 = _plotdata.geometry(modes._links, modes._bodies, pairs, modes.poses)
    P = np.concatenate([np.atleast_2d(p) for p in _plotdata.all_points(g0)])
    size = float(np.ptp(P, axis=0).max()) or 1.0
    amp = _plotdata.mode_amplitude(modes, k, size, scale)
    g = _plotdata.geometry(modes._links, modes._bodies, pairs, _plotdata.mode_poses(modes, k, amp))
    _draw_geometry(ax, g0, plane, ghost=True, sections=0.12 * size)
    _draw_geometry(ax, g, plane, labels=False, sections=0.12 * size)
    _limits(ax, plane, _plotdata.all_points(g0) + _plotdata.all_points(g))
    lab = modes.labels[k] if modes.kind else ""
    ax.set_title(f"mode {k + 1}: {modes.frequency[k]:.4g} Hz\n{lab}", fontsize=9)
    return ax


def modes(modes: ModesResult, n: Optional[int] = None, mechanism=None, plane: Optional[str] = None,
          cols: int = 3, scale: Optional[float] = None):
    """The first ``n`` mode shapes (default all) in a grid, each titled with its frequency and
    label (mode_shape); returns the Figure."""
    if not isinstance(modes, ModesResult):
        raise ModelError("modes: expected a ModesResult from Mechanism.modes")
    n = len(modes.omega) if n is None else min(int(n), len(modes.omega))
    cols = max(1, min(cols, n))
    rows = -(-n // cols)
    fig = plt.figure(figsize=(3.6 * cols, 3.4 * rows))
    for k in range(n):
        ax = fig.add_subplot(rows, cols, k + 1, **({} if plane else dict(projection="3d")))
        mode_shape(modes, k, mechanism, ax=ax, plane=plane, scale=scale)
        ax.tick_params(labelsize=6)
        if _is3d(ax):
            for lab in (ax.xaxis.label, ax.yaxis.label, ax.zaxis.label):
                lab.set_fontsize(7)
    fig.suptitle("mode shapes (grey: the configuration they are computed at; amplitude scaled)",
                 fontsize=10)
    fig.tight_layout()
    return fig


# ------------------------------------------------------------------------------ animation


def animate(mechanism, result: SimulationResult, path: Optional[str] = None, fps: float = 25,
            t_max: Optional[float] = None, speed: float = 1.0, plane: Optional[str] = None,
            ghost=None, dpi: int = 80, figsize=(6.0, 5.0), title: str = "mechanism"):
    """An animation of the deformed mechanism along a simulation (matplotlib.animation); returns
    the FuncAnimation (in Jupyter, ``IPython.display.HTML(anim.to_jshtml())`` shows it).

    ``path``: also save it: ``.gif`` through Pillow, ``.mp4`` through ffmpeg (ModelError saying
    so when ffmpeg is not installed). ``fps`` frames per second of the movie, ``speed`` simulated
    seconds per second of movie, ``t_max`` [s] where to stop; ``ghost``: a state drawn in grey
    (see draw)."""
    from matplotlib import animation

    if not isinstance(result, SimulationResult):
        raise ModelError(f"animate: expected a SimulationResult (got {type(result).__name__})")
    if path is not None:
        ext = str(path).lower().rsplit(".", 1)[-1]
        if ext not in ("gif", "mp4"):
            raise ModelError(f"animate: path must end in .gif (Pillow) or .mp4 (ffmpeg) (got {path!r})")
        if ext == "mp4" and not animation.writers.is_available("ffmpeg"):
            raise ModelError("animate: writing .mp4 needs the ffmpeg program, which is not installed "
                             "(apt-get install ffmpeg); save as .gif instead (Pillow)")
    idx = _plotdata.frames(result, fps, t_max, speed)
    d = mechanism._desc
    pairs = _plotdata.pair_rows(mechanism)
    fig = plt.figure(figsize=figsize)
    ax = fig.add_subplot(**({} if plane else dict(projection="3d")))
    gg = None if ghost is None else _plotdata.geometry(d.links, d.bodies, pairs,
                                              _plotdata.poses_of(mechanism, ghost, None)[0])
    pts = [] if gg is None else _plotdata.all_points(gg)
    for i in idx[:: max(1, len(idx) // 50)] + [idx[-1]]:
        pts += _plotdata.all_points(_plotdata.geometry(d.links, d.bodies, pairs, result.poses[i]))

    def frame(i):
        ax.clear()
        if gg is not None:
            _draw_geometry(ax, gg, plane, ghost=True)
        _draw_geometry(ax, _plotdata.geometry(d.links, d.bodies, pairs, result.poses[i]), plane,
                       labels=False)
        _limits(ax, plane, pts)
        ax.set_title(f"{title}, t = {result.t[i]:.2f} s")
        return []

    anim = animation.FuncAnimation(fig, frame, frames=idx, interval=1000.0 / fps, blit=False)
    if path is not None:
        writer = animation.PillowWriter(fps=fps) if path.lower().endswith(".gif") \
            else animation.FFMpegWriter(fps=fps)
        anim.save(path, writer=writer, dpi=dpi)
    return anim


# ------------------------------------------------------------------------------ interactive
def interactive(mechanism, state=None, fps: float = 20, t_max: Optional[float] = None,
                speed: float = 1.0, modes: Optional[ModesResult] = None, mode: int = 0,
                title: Optional[str] = None):
    """An interactive 3-D view (plotly Figure: rotate, zoom, hover shows the names) of the
    mechanism: at its initial configuration (``state`` None), a StaticResult, or a
    SimulationResult played with a time slider and a play button (frames every ``speed / fps``
    simulated seconds up to ``t_max``); with ``modes``, mode ``mode`` oscillating about the
    configuration it was computed at. Returns the ``plotly.graph_objects.Figure`` (it shows
    itself in Jupyter; ``fig.write_html(path)`` saves it). Needs plotly."""
    go = _plotly()
    d = mechanism._desc
    pairs = _plotdata.pair_rows(mechanism)
    if modes is not None:
        if not isinstance(modes, ModesResult) or modes.poses is None:
            raise ModelError("interactive: modes must be a ModesResult from Mechanism.modes")
        g0 = _plotdata.geometry(d.links, d.bodies, pairs, modes.poses)
        P = np.concatenate([np.atleast_2d(p) for p in _plotdata.all_points(g0)])
        amp = _plotdata.mode_amplitude(modes, mode, float(np.ptp(P, axis=0).max()) or 1.0, None)
        phases = np.linspace(0, 2 * np.pi, 17)[:-1]
        geoms = [_plotdata.geometry(d.links, d.bodies, pairs,
                                    _plotdata.mode_poses(modes, mode, amp * np.sin(ph)))
                 for ph in phases]
        names = [f"{ph:.2f}" for ph in phases]
        head = title or f"mode {mode + 1}: {modes.frequency[mode]:.4g} Hz, " + \
            (modes.labels[mode] if modes.kind else "")
        base = _traces(go, g0, ghost=True)
    elif isinstance(state, SimulationResult):
        if state.carriers is not None:
            raise ModelError("interactive: the result must record every carrier")
        idx = _plotdata.frames(state, fps, t_max, speed)
        geoms = [_plotdata.geometry(d.links, d.bodies, pairs, state.poses[i]) for i in idx]
        names = [f"{state.t[i]:.3f}" for i in idx]
        head = title or "mechanism (press play or drag the time slider [s])"
        base = []
    else:
        poses, what = _plotdata.poses_of(mechanism, state, None)
        geoms, names = [_plotdata.geometry(d.links, d.bodies, pairs, poses)], None
        head = title or f"mechanism, {what}"
        base = []
    first = _traces(go, geoms[0])
    fig = go.Figure(data=base + first)
    P = np.concatenate([np.atleast_2d(p) for g in geoms for p in _plotdata.all_points(g)])
    lo, hi = P.min(axis=0), P.max(axis=0)
    c, R = 0.5 * (lo + hi), 0.55 * max(float((hi - lo).max()), 1e-9)
    scene = dict(aspectmode="cube", **{f"{a}axis": dict(range=[c[i] - R, c[i] + R], title=f"{a} [m]")
                                       for i, a in enumerate(_AXNAME)})
    fig.update_layout(title=head, scene=scene, margin=dict(l=0, r=0, t=40, b=0))
    if names is not None and len(geoms) > 1:
        nb = len(base)
        fig.frames = [go.Frame(data=_traces(go, g), name=nm, traces=list(range(nb, nb + len(first))))
                      for g, nm in zip(geoms, names)]
        ms = 1000.0 / fps
        fig.update_layout(
            updatemenus=[dict(type="buttons", showactive=False, x=0.05, y=0.02, xanchor="left",
                              buttons=[dict(label="play", method="animate",
                                            args=[None, dict(frame=dict(duration=ms, redraw=True),
                                                             fromcurrent=True, transition=dict(duration=0))]),
                                       dict(label="pause", method="animate",
                                            args=[[None], dict(mode="immediate",
                                                               frame=dict(duration=0, redraw=False))])])],
            sliders=[dict(x=0.2, len=0.75, y=0.02, currentvalue=dict(prefix="t = " if modes is None
                                                                      else "phase = "),
                          steps=[dict(label=nm, method="animate",
                                      args=[[nm], dict(mode="immediate", frame=dict(duration=0, redraw=True))])
                                 for nm in names])])
    return fig

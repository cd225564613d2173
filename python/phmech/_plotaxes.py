"""phmech.plot's drawing helpers: the Axes a plot draws into (2-D projections or 3-D), a
configuration's artists (links, bodies, pairs) from _plotdata's world points, the view's
limits, and the plotly traces of the interactive view. Units: m."""
from __future__ import annotations

import numpy as np

import matplotlib.pyplot as plt

from ._errors import ModelError

_PLANES = {"xy": (0, 1), "xz": (0, 2), "yz": (1, 2)}
_AXNAME = "xyz"


def _axes(ax, plane):
    if ax is not None:
        return ax
    if plane is None:
        fig = plt.figure(figsize=(6.4, 5.2))
        return fig.add_subplot(projection="3d")
    if plane not in _PLANES:
        raise ModelError(f"plane must be None (3-D) or one of {', '.join(map(repr, _PLANES))} "
                         f"(got {plane!r})")
    return plt.subplots(figsize=(6.4, 5.2))[1]


def _axes2d(ax):
    return plt.subplots(figsize=(7.5, 4.2))[1] if ax is None else ax


def _is3d(ax) -> bool:
    return getattr(ax, "name", "") == "3d"


def _proj(ax, plane, pts):
    pts = np.atleast_2d(pts)
    if _is3d(ax):
        return pts[:, 0], pts[:, 1], pts[:, 2]
    i, j = _PLANES[plane or "xy"]
    return pts[:, i], pts[:, j]


def _draw_geometry(ax, g, plane, ghost=False, labels=False, sections: float = 0.0):
    """Artists of one configuration; ``ghost``: light grey, behind; ``sections`` > 0: a bar of
    that length [m] along each link node's local y axis (shows torsion)."""
    kw = dict(zorder=1) if ghost else {}
    cl = (lambda c: "0.8") if ghost else (lambda c: c)
    for (name, P), Y in zip(g["links"], g["sections"]):
        ax.plot(*_proj(ax, plane, P), color=cl("C0"), lw=2, **kw)
        if sections > 0:
            h = 0.5 * sections * Y
            bars = np.stack([P - h, P + h, np.full_like(P, np.nan)], axis=1).reshape(-1, 3)
            ax.plot(*_proj(ax, plane, bars), color=cl("C2"), lw=1, **kw)
        if not ghost:
            ax.plot(*_proj(ax, plane, P[[0, -1]]), "o", ms=3, color="C1")
            if labels:
                ax.text(*[v[0] for v in _proj(ax, plane, P[len(P) // 2])], " " + name,
                        fontsize=8, color="C0")
    for name, o, pts in g["bodies"]:
        for q in pts:
            ax.plot(*_proj(ax, plane, np.array([o, q])), color=cl("k"), lw=3, **kw)
        ax.plot(*_proj(ax, plane, o), "s", color=cl("k"), ms=5, **kw)
        if labels and not ghost:
            ax.text(*[v[0] for v in _proj(ax, plane, o)], " " + name, fontsize=8)
    if not ghost:
        for name, q in g["pairs"]:
            ax.plot(*_proj(ax, plane, q), "o", mfc="w", mec="C3", ms=5, mew=1.2)


def _limits(ax, plane, pts):
    pts = np.concatenate([np.atleast_2d(p) for p in pts])
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    c, r = 0.5 * (lo + hi), 0.5 * (hi - lo)
    R = max(r.max() * 1.1, 1e-9)
    if _is3d(ax):
        from matplotlib.ticker import MaxNLocator
        ax.set(xlim=(c[0] - R, c[0] + R), ylim=(c[1] - R, c[1] + R), zlim=(c[2] - R, c[2] + R),
               xlabel="x [m]", ylabel="y [m]", zlabel="z [m]")
        ax.set_box_aspect((1, 1, 1))
        for a in (ax.xaxis, ax.yaxis, ax.zaxis):     # few ticks: 3-D tick labels crowd
            a.set_major_locator(MaxNLocator(4))
    else:
        i, j = _PLANES[plane or "xy"]
        pad = 0.08 * max(r[i], r[j]) + 1e-9
        ax.set(xlim=(lo[i] - pad, hi[i] + pad), ylim=(lo[j] - pad, hi[j] + pad),
               xlabel=f"{_AXNAME[i]} [m]", ylabel=f"{_AXNAME[j]} [m]")
        ax.set_aspect("equal")


# ------------------------------------------------------------------------------ interactive
def _plotly():
    try:
        import plotly.graph_objects as go
    except ImportError:
        raise ModelError("phmech.plot.interactive needs plotly (pip install plotly): a pure-Python "
                         "package whose 3-D figures work in Jupyter without a display server") \
            from None
    return go


def _traces(go, g, ghost=False):
    out = []
    for name, P in g["links"]:
        out.append(go.Scatter3d(x=P[:, 0], y=P[:, 1], z=P[:, 2], mode="lines+markers", name=name,
                                line=dict(width=6, color="lightgrey" if ghost else "royalblue"),
                                marker=dict(size=2), showlegend=not ghost))
    for name, o, pts in g["bodies"]:
        seg = [o]
        for q in pts:
            seg += [q, o]
        S = np.array(seg)
        out.append(go.Scatter3d(x=S[:, 0], y=S[:, 1], z=S[:, 2], mode="lines+markers", name=name,
                                line=dict(width=9, color="lightgrey" if ghost else "black"),
                                marker=dict(size=3, symbol="square"), showlegend=not ghost))
    if g["pairs"] and not ghost:
        Q = np.array([q for _, q in g["pairs"]])
        out.append(go.Scatter3d(x=Q[:, 0], y=Q[:, 1], z=Q[:, 2], mode="markers", name="pairs",
                                text=[n for n, _ in g["pairs"]],
                                marker=dict(size=4, color="white", line=dict(color="red", width=2))))
    return out

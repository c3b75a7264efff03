"""The report's figures: matplotlib drawings returned as inline SVG text (needs the ``plot``
extra; :func:`available` says whether it is installed, and nothing here imports matplotlib
before a figure is asked for).

What is drawn is decimated, never what is computed: a line keeps at most :data:`MAX_LINE_POINTS`
points (every k-th sample, its last one kept), a foot at most :data:`MAX_FOOTPRINTS` footprint
markers, so that an hour of two feet stays a page of a few hundred kB.
"""

from __future__ import annotations

import functools
import io
import re
from typing import Any

import numpy as np

__all__ = [
    "angular_rate_norm",
    "available",
    "decimate",
    "height_svg",
    "overlay_svg",
    "plan_svg",
    "stance_svg",
    "stride_bands",
]

#: Points a drawn line keeps at most (every k-th sample).
MAX_LINE_POINTS = 2500
#: Footprint markers drawn per foot at most.
MAX_FOOTPRINTS = 1500
#: Seconds of the stance figure: a stretch of the walk around its middle.
STANCE_WINDOW_S = 10.0

FOOT_COLORS = {"left": "tab:blue", "right": "tab:red"}
_PIPELINE_COLORS = (
    "tab:blue",
    "tab:orange",
    "tab:green",
    "tab:purple",
    "tab:brown",
    "tab:pink",
    "tab:olive",
    "tab:cyan",
)


def available() -> bool:
    """True when matplotlib (the ``plot`` extra) can be imported."""
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        return False
    return True


def decimate(n: int, limit: int = MAX_LINE_POINTS) -> np.ndarray:
    """Indices of every k-th of ``n`` samples (k the smallest that keeps at most ``limit``), the
    last sample always among them."""
    if n <= limit:
        return np.arange(n)
    step = int(np.ceil(n / (limit - 1)))
    idx = np.arange(0, n, step)
    return idx if idx[-1] == n - 1 else np.append(idx, n - 1)


#: Spans a long height curve is drawn as at most (each its lowest-to-highest band).
MAX_BANDS = 1500


def stride_bands(t: np.ndarray, y: np.ndarray, edges_s: np.ndarray, limit: int = MAX_BANDS):
    """``(start_s, low, high)`` of ``y`` over the spans between successive ``edges_s`` (a foot's
    mid-stances: one span a stride), at most ``limit`` spans (neighbours merged): what a long
    height curve is drawn as. Every-k-th sample aliased the strides (a solid block at one phase
    of the stride), and buckets shorter than a stride drew a moire; a stride's band is the swing
    it spans, and its floor the stance height."""
    t, y = np.asarray(t, dtype=float), np.asarray(y, dtype=float)
    idx = np.unique(np.clip(np.searchsorted(t, np.asarray(edges_s, dtype=float)), 0, len(t) - 1))
    idx = np.unique(np.concatenate([[0], idx]))
    if len(idx) > limit:
        idx = idx[:: int(np.ceil(len(idx) / limit))]
    return t[idx], np.minimum.reduceat(y, idx), np.maximum.reduceat(y, idx)


def _height_curve(ax, t, z, edges_s, color: str, label: str, *, lw: float, alpha: float, outline: bool = False) -> None:
    """The height as a line when short enough to draw whole, else as its band per stride
    (filled, or with ``outline`` its edges dashed: a truth under its estimate)."""
    if len(t) <= MAX_LINE_POINTS or len(edges_s) < 2:
        k = decimate(len(t))
        ax.plot(np.asarray(t)[k], np.asarray(z)[k], color=color, lw=lw, alpha=alpha, label=label)
        return
    start, lo, hi = stride_bands(t, z, edges_s)
    if outline:
        ax.step(start, hi, where="post", color=color, lw=0.8, ls="--", label=f"{label}, per stride")
        ax.step(start, lo, where="post", color=color, lw=0.8, ls="--")
    else:
        ax.fill_between(start, lo, hi, step="post", color=color, alpha=0.3 * alpha, lw=0, label=f"{label}, per stride")


def angular_rate_norm(t: np.ndarray, quaternion: np.ndarray) -> np.ndarray:
    """|angular rate| (rad/s) from an orientation's successive quaternions (w, x, y, z): what the
    report shows under the stances when the recording's gyroscope is not at hand (``follow``)."""
    q = np.asarray(quaternion, dtype=float)
    if len(q) < 2:
        return np.zeros(len(q))
    dot = np.abs(np.sum(q[1:] * q[:-1], axis=1)).clip(0.0, 1.0)
    dt = np.diff(np.asarray(t, dtype=float))
    rate = 2.0 * np.arccos(dot) / np.where(dt > 0, dt, np.inf)
    return np.concatenate([rate[:1], rate])


#: Type size of the figures (pt): a figure 8 in wide shown 560 px wide (a phone, see the page's
#: style) keeps its labels about 9 px high.
FONT_PT = 12.0


def _styled(draw):
    """Draw under the report's style (type size, SVG text as text, stable ids): settings read
    when each artist is made, so around the whole drawing."""

    @functools.wraps(draw)
    def styled(*args, **kwargs):
        import matplotlib

        with matplotlib.rc_context({"font.size": FONT_PT, "svg.fonttype": "none", "svg.hashsalt": "footnav"}):
            return draw(*args, **kwargs)

    return styled


def _figure(width_in: float, height_in: float, **kwargs):
    from matplotlib.figure import Figure  # no pyplot: no backend, no global figure list

    return Figure(figsize=(width_in, height_in), layout="constrained", **kwargs)


def _svg(fig) -> str:
    """The figure as an ``<svg>`` element to inline: text kept as text (smaller, selectable),
    no XML prologue, no fixed size (the page scales it), ids unique to this figure."""
    buf = io.StringIO()
    fig.savefig(buf, format="svg", metadata={"Date": None, "Creator": "footnav"})
    text = buf.getvalue()
    text = text[text.index("<svg") :]
    # a hundredth of a point is finer than any screen: matplotlib writes six decimals
    text = re.sub(r"(\d\.\d\d)\d+", r"\1", text)
    text = re.sub(r'(<svg[^>]*?) width="[^"]*" height="[^"]*"', r"\1", text, count=1)
    # several figures in one page: their clip paths and markers must not share ids
    salt = f"f{id(fig) % 100000}"
    text = re.sub(r'id="([^"]+)"', lambda m: f'id="{salt}{m.group(1)}"', text)
    text = re.sub(r"url\(#([^)]+)\)", lambda m: f"url(#{salt}{m.group(1)})", text)
    text = re.sub(r'xlink:href="#([^"]+)"', lambda m: f'xlink:href="#{salt}{m.group(1)}"', text)
    return text.strip()


def _plan_svg(fig, ax) -> str:
    """A plan view's axes finished (equal scales, labels in m, grid, legend below) as SVG."""
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.grid(True, alpha=0.3)
    _legend_below(ax, ncol=3)
    return _svg(fig)


def _legend_below(ax, ncol: int = 2) -> None:
    """The legend under the figure, outside every axes (the constrained layout makes room for
    it): never over the data nor over the axis labels."""
    handles, labels = ax.get_legend_handles_labels()
    if handles:
        ax.figure.legend(handles, labels, loc="outside lower center", ncol=ncol, fontsize="small", frameon=False)


def _footprints(traj, stance) -> np.ndarray:
    """Mid-stance positions (K, 3) of a foot: one per stance interval."""
    intervals = np.asarray(getattr(stance, "intervals", np.zeros((0, 2))), dtype=int).reshape(-1, 2)
    if len(intervals) == 0:
        return np.zeros((0, 3))
    mid = np.clip((intervals[:, 0] + intervals[:, 1]) // 2, 0, len(traj.t) - 1)
    return np.asarray(traj.position)[mid]


@_styled
def plan_svg(feet: list[tuple[str, Any, Any]], path, truths: dict[str, Any] | None = None) -> str:
    """Plan view: each foot's path and footprints, the fused path, and each foot's truth."""
    fig = _figure(8.0, 6.4)
    ax = fig.add_subplot()
    for foot, traj, stance in feet:
        color = FOOT_COLORS[foot]
        truth = (truths or {}).get(foot)
        if truth is not None:
            k = decimate(len(truth.t))
            ax.plot(truth.position[k, 0], truth.position[k, 1], color=color, lw=4, alpha=0.2, label=f"{foot} truth")
        k = decimate(len(traj.t))
        ax.plot(traj.position[k, 0], traj.position[k, 1], color=color, lw=0.8, alpha=0.7, label=f"{foot} foot")
        prints = _footprints(traj, stance)
        shown = prints[decimate(len(prints), MAX_FOOTPRINTS)] if len(prints) else prints
        ax.plot(
            shown[:, 0],
            shown[:, 1],
            "o",
            color=color,
            ms=3,
            mfc="none",
            mew=0.8,
            label=f"{foot} footprints ({len(prints)}" + (f", {len(shown)} drawn)" if len(shown) < len(prints) else ")"),
        )
        ax.plot(*traj.position[0, :2], "o", color=color, ms=8)
        ax.plot(*traj.position[-1, :2], "s", color=color, ms=8)
    if path is not None and len(path.t) > 1:
        k = decimate(len(path.t))
        ax.plot(path.position[k, 0], path.position[k, 1], color="0.15", lw=1.2, ls="--", label="fused path")
    return _plan_svg(fig, ax)


#: The stride table's columns the height figure reads.
_HEIGHT_COLUMNS = ("foot", "kind", "start_s", "end_s", "level")


@_styled
def height_svg(feet: list[tuple[str, Any, Any]], strides, truths: dict[str, Any] | None = None) -> str:
    """Each foot's height over time, the stair strides shaded and the floor level of each
    stride drawn as a step line on a second axis."""
    fig = _figure(9.0, 3.8)
    ax = fig.add_subplot()
    for foot, traj, stance in feet:
        color = FOOT_COLORS[foot]
        prints = _footprints(traj, stance)
        mid = np.clip(
            np.asarray(stance.intervals, dtype=int).reshape(-1, 2).mean(axis=1).astype(int), 0, len(traj.t) - 1
        )
        edges_s = np.asarray(traj.t)[mid] if len(prints) else np.zeros(0)
        truth = (truths or {}).get(foot)
        if truth is not None:
            z0 = float(np.interp(truth.t[0], traj.t, traj.position[:, 2]))
            _height_curve(
                ax,
                truth.t,
                truth.position[:, 2] - truth.position[0, 2] + z0,
                edges_s,
                color,
                f"{foot} truth",
                lw=4,
                alpha=0.2,
                outline=True,
            )
        _height_curve(ax, traj.t, traj.position[:, 2], edges_s, color, f"{foot} foot", lw=0.6, alpha=0.8)
        if len(prints):
            k = decimate(len(mid))
            ax.plot(edges_s[k], prints[k, 2], color=color, lw=1.4, label=f"{foot} footprints")
    col = {} if strides is None or not len(strides) else {c: np.asarray(strides[c]) for c in _HEIGHT_COLUMNS}
    stair = np.flatnonzero(col["kind"] == "stair") if col else np.zeros(0, dtype=int)
    if len(stair):
        spans = stair[decimate(len(stair), 400)]
        for i, (start, end) in enumerate(zip(col["start_s"][spans], col["end_s"][spans])):
            ax.axvspan(start, end, color="tab:orange", alpha=0.15, lw=0, label="stair strides" if i == 0 else None)
    if col and np.abs(col["level"]).max() > 0:
        ax2 = ax.twinx()
        for foot in ("left", "right"):
            rows = col["foot"] == foot
            if rows.any():
                ax2.step(
                    col["end_s"][rows],
                    col["level"][rows],
                    where="post",
                    color=FOOT_COLORS[foot],
                    lw=1.5,
                    alpha=0.5,
                    ls=":",
                )
        ax2.set_ylabel("floor (dotted)")
        ax2.yaxis.get_major_locator().set_params(integer=True)
    ax.set_xlabel("time (s)")
    ax.set_ylabel("height z (m)")
    ax.grid(True, alpha=0.3)
    _legend_below(ax, ncol=3)
    return _svg(fig)


def stance_window(t: np.ndarray, seconds: float = STANCE_WINDOW_S) -> tuple[float, float]:
    """The stretch the stance figure shows: ``seconds`` around the middle of ``t``."""
    if len(t) == 0:
        return 0.0, 0.0
    mid = 0.5 * (float(t[0]) + float(t[-1]))
    start = max(float(t[0]), mid - seconds / 2)
    return start, min(float(t[-1]), start + seconds)


@_styled
def stance_svg(rows: list[tuple[str, np.ndarray, np.ndarray, np.ndarray, str]], window: tuple[float, float]) -> str:
    """One panel per foot: the angular rate norm over ``window`` with the stance samples
    shaded. ``rows``: (foot, t, rate norm, stance mask, what the rate is)."""
    fig = _figure(9.0, 1.2 + 1.9 * len(rows))
    axes = fig.subplots(len(rows), 1, sharex=True, squeeze=False)[:, 0]
    for ax, (foot, t, rate, mask, source) in zip(axes, rows):
        inside = np.flatnonzero((t >= window[0]) & (t <= window[1]))
        k = inside[decimate(len(inside))] if len(inside) else inside
        ax.fill_between(
            t[k],
            0,
            1,
            where=np.asarray(mask)[k],
            step="mid",
            color="tab:green",
            alpha=0.25,
            lw=0,
            transform=ax.get_xaxis_transform(),
            label="stance",
        )
        ax.plot(t[k], rate[k], color=FOOT_COLORS[foot], lw=0.9)
        ax.set_ylabel("|ω| (rad/s)")
        ax.set_title(f"{foot} foot: angular rate ({source}); green: stance", loc="left", fontsize="medium")
        ax.grid(True, alpha=0.3)
    axes[-1].set_xlabel("time (s)")
    return _svg(fig)


@_styled
def overlay_svg(truths: dict[str, Any], estimates: list[tuple[str, str, np.ndarray]]) -> str:
    """Plan view of an evaluation: each foot's truth, and each pipeline's estimate of it
    (``(pipeline, foot, xy)``, aligned onto the truth by the caller)."""
    fig = _figure(8.0, 6.4)
    ax = fig.add_subplot()
    for foot, truth in truths.items():
        k = decimate(len(truth.t))
        ax.plot(
            truth.position[k, 0],
            truth.position[k, 1],
            color="0.2",
            lw=4,
            alpha=0.2,
            label="truth" if foot == next(iter(truths)) else None,
        )
    pipelines = list(dict.fromkeys(p for p, _, _ in estimates))
    for pipe, foot, xy in estimates:
        color = _PIPELINE_COLORS[pipelines.index(pipe) % len(_PIPELINE_COLORS)]
        k = decimate(len(xy))
        ax.plot(xy[k, 0], xy[k, 1], color=color, lw=1.0, ls="-" if foot == "left" else "--", label=f"{pipe} ({foot})")
    return _plan_svg(fig, ax)

"""Figures of rigid-block results (matplotlib). Presentation only: no computation here.

The figures are :class:`matplotlib.figure.Figure` objects made directly, not through pyplot:
saving one renders it with the canvas of its file's format (Agg for PNG), so no backend is
chosen for the process (at import or at all) and no figure is left open in pyplot's list.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from matplotlib.colors import BoundaryNorm, ListedColormap
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Patch

from .solve import verdict

MODE_COLOURS = ("#f2f2f2", "#d95f02", "#1b9e77")  # safe, after-impact, without-impact
MODE_LABELS = ("safe", "overturns after impact(s)", "overturns without impact")
MODE_MARKERS = ("o", "^", "s")  # the same modes by shape, for markers on a map
COARSE_GRID = 20  # a map with at most this many points along each axis marks every point


@dataclass(frozen=True)
class MarkerStyle:
    """How :func:`grid_markers` draws each code k of a map: ``colours[k]`` (its face colour),
    ``markers[k]`` (its matplotlib marker shape) and ``labels[k]`` (its legend text); by
    default the overturning modes' (safe, after impact, without impact)."""

    colours: Sequence[str] = MODE_COLOURS
    markers: Sequence[str] = MODE_MARKERS
    labels: Sequence[str] = MODE_LABELS


MODE_STYLE = MarkerStyle()


def plot_history(result, path, title: str | None = None):
    """theta/alpha and theta'/p against time, impacts marked; collar utilisation if any. The
    title names the motion and, apart, the collars' state (never "safe" beside a yielded
    collar)."""
    n_rows = 3 if result.collar_histories else 2
    fig = Figure(figsize=(8, 2.6 * n_rows))
    axes = fig.subplots(n_rows, 1, sharex=True)
    alpha, p = result.block.alpha, result.block.p
    theta = result.theta.reshape(result.time.size, -1)
    theta_dot = result.theta_dot.reshape(result.time.size, -1)
    labels = ("left half", "right half") if theta.shape[1] == 2 else (None,)
    for k, label in enumerate(labels):
        axes[0].plot(result.time, theta[:, k] / alpha, lw=1.2, label=label)
        axes[1].plot(result.time, theta_dot[:, k] / p, lw=1.2, label=label)
    axes[0].axhline(1.0, color="0.6", lw=0.8, ls="--")
    axes[0].axhline(-1.0, color="0.6", lw=0.8, ls="--")
    for t in result.impact_times:
        axes[0].axvline(t, color="0.85", lw=0.5, zorder=0)
    axes[0].set_ylabel(r"$\theta/\alpha$")
    axes[1].set_ylabel(r"$\dot\theta/p$")
    if labels[0] is not None:
        axes[0].legend(fontsize=8)
    if result.collar_histories:
        for k, hist in enumerate(result.collar_histories, start=1):
            axes[2].plot(
                result.time, hist.utilisation, lw=1.0, label=f"collar {k} (y = {hist.collar.y:g} m)"
            )
        axes[2].axhline(1.0, color="k", lw=0.8, ls="--", label=r"$f_y$")
        axes[2].set_ylabel(r"$\sigma / f_y$")
        axes[2].legend(fontsize=8)
    axes[-1].set_xlabel("t (s)")
    summary = result.summary()
    axes[0].set_title(
        title or f"{result.model} model, {summary['impacts']} impacts: {verdict(summary)}"
    )
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def plot_spectrum(spectrum, path, title: str | None = None, ax=None):
    """Mode map over (Omega/p, a_p/a_uplift) in the style of Zhang & Makris (2001)."""
    own = ax is None
    if own:
        fig = Figure(figsize=(9, 4.5))
        ax = fig.subplots()
    cmap = ListedColormap(MODE_COLOURS)
    norm = BoundaryNorm([-0.5, 0.5, 1.5, 2.5], cmap.N)
    ax.pcolormesh(
        spectrum.omega_ratios,
        spectrum.amplitude_ratios,
        spectrum.codes,
        cmap=cmap,
        norm=norm,
        shading="nearest",
    )
    # the legend lists what is drawn: on a coarse grid a marker per computed pulse
    handles = grid_markers(ax, spectrum.omega_ratios, spectrum.amplitude_ratios, spectrum.codes)
    if not handles:
        present = np.unique(spectrum.codes)
        handles = [
            Patch(color=MODE_COLOURS[k], label=MODE_LABELS[k]) for k in range(3) if k in present
        ]
    if spectrum.collar_yields is not None and spectrum.collar_yields.any():
        ax.contourf(
            spectrum.omega_ratios,
            spectrum.amplitude_ratios,
            spectrum.collar_yields.astype(float),
            levels=[0.5, 1.5],
            colors="none",
            hatches=["////"],
        )
        ax.contour(
            spectrum.omega_ratios,
            spectrum.amplitude_ratios,
            spectrum.collar_yields.astype(float),
            levels=[0.5],
            colors="k",
            linewidths=0.8,
        )
        handles.append(
            Patch(facecolor="none", edgecolor="k", hatch="////", label="a collar reaches f_y")
        )
    ax.set_xlabel(r"$\Omega / p$")
    norm_name = r"g\,\alpha" if spectrum.model == "linear" else r"g\,\tan\alpha"
    ax.set_ylabel(rf"$a_p / ({norm_name})$")
    ax.legend(
        handles=handles, fontsize=8, loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0.0
    )  # beside the map, never over it
    ax.set_title(
        title
        or f"Overturning spectrum, {spectrum.pulse} pulse, {spectrum.model} model"
        + (", with collars" if spectrum.with_collars else "")
    )
    if own:
        fig.tight_layout()
        fig.savefig(path, dpi=120)


def grid_markers(
    ax,
    x,
    y,
    codes,
    style: MarkerStyle = MODE_STYLE,
    *,
    always: bool = False,
    size: float | None = None,
) -> list:
    """A marker at each computed point of a map (rows: y, columns: x), coloured, shaped and
    labelled by its code as ``style`` says (:class:`MarkerStyle`), so that a coarse grid shows
    where its data are; nothing on a grid finer than COARSE_GRID along an axis unless
    ``always``. ``size``: the markers' area (points^2; None: 40 on a grid of at most 10 points
    along each axis, else 18). Returns a legend handle per code drawn."""
    colours, markers, labels = style.colours, style.markers, style.labels
    codes = np.asarray(codes, dtype=int)
    if not always and max(codes.shape) > COARSE_GRID:
        return []
    xx, yy = np.meshgrid(np.asarray(x, dtype=float), np.asarray(y, dtype=float))
    size = size or (40.0 if max(codes.shape) <= 10 else 18.0)
    handles = []
    for k in np.unique(codes):
        on = codes == k
        ax.scatter(
            xx[on],
            yy[on],
            s=size,
            marker=markers[k],
            c=colours[k],
            edgecolors="k",
            linewidths=0.7,
            zorder=3,
            clip_on=False,
        )  # whole on the map's edges
        handles.append(
            Line2D(
                [],
                [],
                ls="",
                marker=markers[k],
                markersize=size**0.5,
                markerfacecolor=colours[k],
                markeredgecolor="k",
                markeredgewidth=0.7,
                label=labels[k],
            )
        )
    return handles


def plot_design_chart(
    alphas,
    ratios,
    stiffness,
    path=None,
    title: str | None = None,
    ax=None,
    design: tuple | None = None,
    provided: tuple | None = None,
):
    """Minimum total lateral collar stiffness over alpha and a_g/g (paper Fig. 8 analogue), in
    kN/m throughout. ``design``: (a_g/g, alpha, required stiffness in N/m) of the design point,
    marked; ``provided``: (number of collars, their total lateral stiffness in N/m), drawn as
    that stiffness's iso-line (the chart's region its collars cover lies on its low side)."""
    own = ax is None
    if own:
        ax = Figure(figsize=(7, 5.2)).subplots()
    fig = ax.figure
    k = np.asarray(stiffness, dtype=float) / 1e3  # kN/m
    mesh = ax.contourf(ratios, alphas, np.where(k > 0.0, k, np.nan), levels=20, cmap="viridis")
    ax.contour(ratios, alphas, k, levels=[0.0], colors="w", linewidths=1.0)
    fig.colorbar(mesh, ax=ax, label="minimum lateral stiffness k (kN/m)")

    def kn(value):  # N/m -> "11720 kN/m" (4 significant digits, no exponent)
        text = f"{value / 1e3:.4g}"
        return f"{float(text):.0f} kN/m" if "e+" in text else f"{text} kN/m"

    handles = []
    if provided is not None and np.nanmin(k) < provided[1] / 1e3 < np.nanmax(k):
        ax.contour(
            ratios,
            alphas,
            k,
            levels=[provided[1] / 1e3],
            colors="r",
            linewidths=1.2,
            linestyles="--",
        )
        handles.append(
            Line2D(
                [],
                [],
                color="r",
                lw=1.2,
                ls="--",
                label=f"k provided by the {provided[0]} collar(s): {kn(provided[1])}",
            )
        )
    if design is not None:
        ratio, alpha, required = design
        needed = f"k required {kn(required)}" if required > 0.0 else "no collar required"
        handles += ax.plot(
            [ratio],
            [alpha],
            ls="",
            marker="*",
            markersize=15,
            markerfacecolor="r",
            markeredgecolor="k",
            label=f"design point: a_g/g = {ratio:.3g}, alpha_half = {alpha:.3g} rad, {needed}",
        )
    ax.set_xlabel(r"$a_g / g$")
    ax.set_ylabel(r"$\alpha_{half}$ (rad), of the rocking half block")
    ax.set_title(title or "Collar design chart (corrected Eq. 22-24); white: k = 0")
    if handles:  # below the chart, never over it
        ax.legend(handles=handles, fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.14))
    if own:
        fig.tight_layout()
        fig.savefig(path, dpi=120)

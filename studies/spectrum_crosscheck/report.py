"""The spectrum cross-check's report: the mode maps of the FEM, multibody and SDOF models side by
side, where they disagree, and their overturning boundaries (presentation only: the numbers and
maps are summary.json's)."""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.artist import Artist
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Patch

from ..output import write_csv
from ..report import MODE_CODES, blocks_of, distinct, figure, legend_beside, render_page
from ..sections import Ref, table
from .summary import SpectrumSummary, load

# the three models of the spectrum cross-check: (summary key suffix, name)
MODELS = (("fem", "FEM"), ("multibody", "rigid multibody"), ("sdof", "SDOF half block"))


def write_report(out: Path) -> Path:
    """Mode maps of the FEM, multibody and SDOF models side by side, where they disagree, and
    their overturning boundaries overlaid; every map also as CSV."""
    out = Path(out)
    s = json.loads((out / "summary.json").read_text())
    (out / "figures").mkdir(exist_ok=True)
    labels = _axis_labels(out, s)
    maps = {
        m: np.array([[MODE_CODES[c] for c in row] for row in s[f"mode_{m}"]]) for m, _ in MODELS
    }
    _write_maps(out, s, maps)
    figs = [_maps_figure(out, s, maps, labels), _disagreement_figure(out, s, maps, labels)]
    boundaries = _boundaries_figure(out, s, maps, labels)
    if boundaries is not None:
        figs.append(boundaries)
    return render_page(
        out,
        "spectrum_crosscheck/report.html.j2",
        s,
        f"colonna spectrum cross-check: {s['study']}",
        figs=figs,
        rows=table(SPECTRUM_NUMBERS, load(s)),
    )


def _axis_labels(out: Path, s: dict) -> tuple[str, str]:
    """The maps' x label (Omega / p of the SDOF block, or a record's time scale: a record's
    grid moves its time scale where a pulse's moves Omega / p) and amplitude (y) label; the
    pulses are normalised by the SDOF block's alpha and p."""
    block = blocks_of(out)["sdof"]
    amplitude = rf"$a_p / (g\,\tan\alpha_\mathrm{{{block}}})$ (-)"
    x_label = (
        r"record time scale (2: twice as fast)"
        if s.get("x_axis") == "time_scale"
        else rf"$\Omega / p_\mathrm{{{block}}}$ (-)"
    )
    return x_label, amplitude


def _write_maps(out: Path, s: dict, maps: dict) -> None:
    """figures/maps.csv: every pulse of the grid with each model's outcome code and the FEM's
    collar utilisation and toe stress ratio."""
    ww, aa = np.meshgrid(np.array(s["omega_ratios"]), np.array(s["amplitude_ratios"]))
    columns = {"omega_ratio": ww.ravel(), "amplitude_ratio": aa.ravel()}
    columns.update({f"mode_code_{m}": maps[m].ravel() for m, _ in MODELS})
    columns["collar_utilisation_fem"] = np.array(s["collar_utilisation_fem"], float).ravel()
    columns["toe_ratio_fem"] = np.array(s["toe_ratio_fem"], float).ravel()
    write_csv(out / "figures" / "maps.csv", columns)


def _legend(marked: dict, present, colours, labels) -> list[Artist]:
    """One legend entry per code present: the grid's marker where one was drawn
    (``marked``: label -> handle), else a patch of its colour."""
    return [
        marked.get(labels[k]) or Patch(color=colours[k], label=labels[k]) for k in sorted(present)
    ]


def _maps_figure(out: Path, s: dict, maps: dict, labels: tuple[str, str]) -> dict:
    """The outcome of every pulse of the grid, one map per model side by side, with the
    pulses at which a FEM collar reaches f_y."""
    from matplotlib.colors import BoundaryNorm, ListedColormap

    from ...rigid.plotting import MODE_COLOURS, MODE_LABELS, grid_markers

    x_label, amplitude = labels
    w, a = np.array(s["omega_ratios"]), np.array(s["amplitude_ratios"])
    cmap = ListedColormap(MODE_COLOURS)
    norm = BoundaryNorm([-0.5, 0.5, 1.5, 2.5], cmap.N)
    fig = Figure(figsize=(12, 3.8))
    axes = fig.subplots(1, 3, sharey=True)
    yields = np.array(s["collar_yield_fem"], dtype=bool)
    marked: dict[str, Artist] = {}  # a marker at each computed pulse of a coarse grid
    for ax, (m, label) in zip(axes, MODELS):
        ax.pcolormesh(w, a, maps[m], cmap=cmap, norm=norm, shading="nearest")
        marked.update((h.get_label(), h) for h in grid_markers(ax, w, a, maps[m]))
        ax.set_title(label)
        ax.set_xlabel(x_label)
    if yields.any():
        ww, aa = np.meshgrid(w, a)
        axes[0].scatter(ww[yields], aa[yields], marker="x", color="k", s=25, zorder=4)
    axes[0].set_ylabel(amplitude)
    present = {int(k) for m, _ in MODELS for k in np.unique(maps[m])}  # the legend: what is drawn
    handles = _legend(marked, present, MODE_COLOURS, MODE_LABELS)
    if yields.any():
        handles.append(
            Line2D([], [], marker="x", color="k", ls="", label="FEM: a collar reaches f_y")
        )
    fig.legend(handles=handles, loc="lower center", ncol=len(handles), fontsize=8)
    fig.tight_layout(rect=(0, 0.08, 1, 1))
    return figure(
        out,
        "maps",
        fig,
        "Outcome of every pulse of the grid: FEM, rigid "
        "multibody and SDOF (the paper's half block with collars)"
        + ("; a marker at each computed pulse" if marked else ""),
    )


def _disagreement_figure(out: Path, s: dict, maps: dict, labels: tuple[str, str]) -> dict:
    """Where the FEM and each rigid model (multibody, SDOF) disagree over the grid."""
    from matplotlib.colors import ListedColormap

    from ...rigid.plotting import MarkerStyle, grid_markers

    x_label, amplitude = labels
    w, a = np.array(s["omega_ratios"]), np.array(s["amplitude_ratios"])
    fig = Figure(figsize=(9, 3.6))
    axes = fig.subplots(1, 2, sharey=True)
    shades = ("#f2f2f2", "#7570b3")
    drawn: set[int] = set()
    marked: dict[str, Artist] = {}
    words = ("same outcome", "different outcome")
    for ax, m, label in (
        (axes[0], "multibody", "FEM vs rigid multibody"),
        (axes[1], "sdof", "FEM vs SDOF half block"),
    ):
        differ = (maps["fem"] != maps[m]).astype(float)
        drawn |= {int(v) for v in np.unique(differ)}
        ax.pcolormesh(w, a, differ, cmap=ListedColormap(shades), vmin=0, vmax=1, shading="nearest")
        marked.update(
            (h.get_label(), h)
            for h in grid_markers(
                ax, w, a, differ.astype(int), MarkerStyle(shades, ("o", "X"), words)
            )
        )
        ax.set_title(label)
        ax.set_xlabel(x_label)
    axes[0].set_ylabel(amplitude)
    fig.legend(
        handles=_legend(marked, drawn, shades, words), loc="lower center", ncol=2, fontsize=8
    )
    fig.tight_layout(rect=(0, 0.08, 1, 1))
    return figure(out, "disagreement", fig, "Where the FEM and each rigid model disagree")


def _boundaries_figure(out: Path, s: dict, maps: dict, labels: tuple[str, str]) -> dict | None:
    """Each model's overturning boundary: the lowest amplitude of the grid that overturns,
    per frequency (figures/boundaries.csv); no figure where no pulse of the grid overturns
    any model."""
    x_label, amplitude = labels
    w, a = np.array(s["omega_ratios"]), np.array(s["amplitude_ratios"])
    fig = Figure(figsize=(8.5, 4))
    ax = fig.subplots()
    boundary, never = {}, []
    for j, (m, label) in enumerate(MODELS):
        over = maps[m] != 0
        lowest = np.where(over.any(axis=0), a[np.argmax(over, axis=0)], np.nan)
        boundary[f"lowest_overturning_amplitude_{m}"] = lowest
        if np.isfinite(lowest).any():  # the legend lists only what is drawn
            style = dict(distinct(j, len(MODELS)), markevery=None, markersize=10 - 3 * j)
            ax.plot(w, lowest, color=f"C{j}", **style, label=label)  # equal ones stay apart
        else:
            never.append(label)
    write_csv(out / "figures" / "boundaries.csv", {"omega_ratio": w, **boundary})
    ax.set_xlabel(x_label)
    ax.set_ylabel("lowest overturning " + amplitude)
    if len(never) == len(MODELS):
        return None
    legend_beside(ax)
    fig.tight_layout()
    return figure(
        out,
        "boundaries",
        fig,
        "Overturning boundary of each model: the "
        "lowest amplitude of the grid that overturns, per frequency (none "
        "drawn where no amplitude of the grid does)"
        + (f"; no pulse of the grid overturns the {' or the '.join(never)} model" if never else ""),
    )


def _at(get: Callable[[SpectrumSummary], Any]) -> Ref[SpectrumSummary]:
    """A quantity of the summary, named by attribute (studies.sections.Ref)."""
    return Ref(SpectrumSummary, get)


SPECTRUM_NUMBERS: list[tuple[str, Ref[SpectrumSummary], str]] = [
    (
        "FEM and rigid multibody: same outcome, fraction of the grid points",
        _at(lambda s: s.agreement_fem_multibody),
        "-",
    ),
    (
        "FEM and SDOF half block: same outcome, fraction of the grid points",
        _at(lambda s: s.agreement_fem_sdof),
        "-",
    ),
    ("grid points", _at(lambda s: s.points), "-"),
    (
        "FEM energy balance error (max over the grid, relative)",
        _at(lambda s: s.energy_error_fem_max),
        "-",
    ),
    ("FEM wall time per grid point", _at(lambda s: s.fem_seconds_per_point), "s"),
    ("study wall time", _at(lambda s: s.wall_seconds), "s"),
]

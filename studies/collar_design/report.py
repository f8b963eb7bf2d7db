"""The collar design's report: the design chart, the collars' utilisation in the FEM run and the
plastic bands' trials (presentation only: the numbers are summary.json's, the curves the run's
CSV files)."""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.figure import Figure

from ..output import read_csv, write_csv
from ..report import distinct, figure, legend_beside, render_page
from ..sections import Ref, table
from .summary import DesignSummary, load


def write_report(out: Path) -> Path:
    """The collar design's report: the design chart with the study's column and collars, the
    FEM collar utilisation over time, the plastic bands' trials and the design numbers
    (``out/index.html``)."""
    out = Path(out)
    s = json.loads((out / "summary.json").read_text())
    chart = read_csv(out / "figures" / "design_chart.csv")
    alphas = np.unique(chart["alpha"])
    ratios = np.unique(chart["ag_over_g"])
    k = chart["required_stiffness"].reshape(alphas.size, ratios.size)
    from ...rigid.plotting import plot_design_chart

    # the chart in kN/m throughout, the study's column and pulse marked with its required
    # stiffness, and the iso-line of the stiffness its collars provide
    fig = Figure(figsize=(7.5, 5.6))
    ax = fig.subplots()
    plot_design_chart(
        alphas,
        ratios,
        k,
        ax=ax,
        design=(s["design_ag_over_g"], s["design_alpha"], s["design"]["required_stiffness"]),
        provided=(s["collars_provided"], s["lateral_stiffness_provided"]),
    )
    fig.tight_layout()
    chart_fig = figure(
        out,
        "design_chart",
        fig,
        "Minimum total lateral collar stiffness "
        "(kN/m) over alpha and a_g/g (corrected Eq. 22-24); the star: this "
        "study's column and design pulse with the stiffness it requires; the "
        "dashed line, where inside the chart: the stiffness its collars provide "
        "(enough on its side of larger alpha and smaller a_g/g)",
        data_file="figures/design_chart.csv",
    )
    history = read_csv(out / "cases" / "fem" / "history.csv")
    cols = sorted(c for c in history if c.startswith("collar_") and c.endswith("_utilisation"))
    write_csv(
        out / "figures" / "collar_utilisation.csv",
        {"t": history["t"], **{c: history[c] for c in cols}},
    )
    fig = Figure(figsize=(9.5, 3.2))
    ax = fig.subplots()
    for j, c in enumerate(cols):  # collars of one history stay apart
        ax.plot(
            history["t"],
            history[c],
            color=f"C{j}",
            **distinct(j, len(cols)),
            label=c.replace("_utilisation", ""),
        )
    ax.axhline(1.0, color="k", ls="--", lw=1, label="f_y")
    ax.set_xlabel("t (s)")
    ax.set_ylabel("sigma / f_y (-)")
    legend_beside(ax)
    fig.tight_layout()
    util_fig = figure(
        out,
        "collar_utilisation",
        fig,
        "FEM collar utilisation over time "
        "(collars with the same history on top of each other, each with its own "
        "dashes and markers)",
    )
    figs = [chart_fig, util_fig]
    if "ductile_design" in s:
        figs.append(_ductile_design_figure(out, s["ductile_design"]))
    return render_page(
        out,
        "collar_design/report.html.j2",
        s,
        f"colonna collar design: {s['study']}",
        rows=table(DESIGN_NUMBERS, load(s)),
        figs=figs,
    )


def _ductile_design_figure(out: Path, design: dict):
    """Utilisation and ductility demand of the plastic collars against the band's thickness
    (multibody runs), with f_y and the ductility limit, the bands that break or whose column
    overturns marked; the two thinnest answers as vertical lines."""
    trials = design["trials"]
    t_mm = np.array([1e3 * r["t"] for r in trials])
    util = np.array([r["collar_max_utilisation"] for r in trials], dtype=float)
    demand = np.array([r["collar_ductility_demand"] for r in trials], dtype=float)
    broken = np.array([r["collar_fractured"] for r in trials], dtype=bool)
    fell = np.array([r["overturned"] for r in trials], dtype=bool)
    write_csv(
        out / "figures" / "ductile_design.csv",
        {
            "t_mm": t_mm,
            "collar_max_utilisation": util,
            "collar_ductility_demand": demand,
            "collar_fractured": broken.astype(int),
            "overturned": fell.astype(int),
        },
    )
    fig = Figure(figsize=(8.5, 3.8))
    ax = fig.subplots()
    ax.plot(t_mm, demand, "o-", color="C0", label="ductility demand eps_max / eps_y")
    ax.plot(t_mm, util, "s--", color="C1", label="utilisation sigma / f_y")
    if broken.any():
        ax.plot(t_mm[broken], demand[broken], "x", ms=10, color="C3", label="a collar breaks")
    if fell.any():
        ax.plot(t_mm[fell], util[fell], "v", ms=7, mfc="none", color="k", label="column overturns")
    ax.axhline(1.0, color="C1", ls=":", lw=1, label="f_y")
    limit = design["ductility_limit"]
    ax.axhline(limit, color="C0", ls=":", lw=1, label=f"ductility limit {limit:g}")
    for key, style, text in (
        ("never_yields_t", "-", "never yields"),
        ("holds_t", "--", "yields but holds"),
    ):
        if design.get(key) is not None:
            ax.axvline(1e3 * design[key], color="0.4", ls=style, lw=1, label=f"thinnest: {text}")
    ax.set_yscale("log")
    ax.set_xlabel("band thickness t (mm)")
    ax.set_ylabel("largest over the run (-)")
    legend_beside(ax)
    fig.tight_layout()
    return figure(
        out,
        "ductile_design",
        fig,
        "Collars beyond first yield (rigid multibody model, every collar plastic, the study's "
        f"band height {1e3 * design['band_height']:g} mm, heights and steel): the largest "
        "utilisation and ductility demand over the run against the band's thickness; where the "
        "column overturns (triangles) the run, and these numbers, end there: collars tie the "
        "halves, they do not stop a pulse that overturns the whole column",
        data_file="figures/ductile_design.csv",
    )


def _at(get: Callable[[DesignSummary], Any]) -> Ref[DesignSummary]:
    """A quantity of the summary, named by attribute (studies.sections.Ref)."""
    return Ref(DesignSummary, get)


# the collar-design table: (label, quantity, unit)
DESIGN_NUMBERS: list[tuple[str, Ref[DesignSummary], str]] = [
    ("yield moment M_y", _at(lambda s: s.design.yield_moment), "kN m"),
    ("yield offset d_y, corrected Eq. 22", _at(lambda s: s.design.yield_displacement), "mm"),
    ("yield rotation theta_y, Eq. 23", _at(lambda s: s.design.yield_rotation), "rad"),
    (
        "required lateral stiffness k, corrected Eq. 24",
        _at(lambda s: s.design.required_stiffness),
        "kN/m",
    ),
    (
        "one collar's lateral stiffness K_l",
        _at(lambda s: s.design.collar_lateral_stiffness),
        "kN/m",
    ),
    ("collars needed", _at(lambda s: s.design.collars_needed), "-"),
    ("collars provided", _at(lambda s: s.collars_provided), "-"),
    ("lateral stiffness provided", _at(lambda s: s.lateral_stiffness_provided), "kN/m"),
    ("design adequate", _at(lambda s: s.design_adequate), ""),
    ("FEM collar utilisation (max), sigma / f_y", _at(lambda s: s.fem_collar_max_utilisation), "-"),
    ("FEM first yield", _at(lambda s: s.fem_collar_first_yield_time), "s"),
    ("FEM overturned", _at(lambda s: s.fem_overturned), ""),
    ("FEM peak rotation / theta_y", _at(lambda s: s.fem_max_rotation_over_yield_rotation), "-"),
    (
        "thinnest band that never yields (multibody, plastic collars; n/a: none tried)",
        _at(lambda s: s.ductile_design.never_yields_t),
        "mm",
    ),
    (
        "thinnest band that yields but holds (no break, ductility demand within the limit; "
        "n/a: none tried)",
        _at(lambda s: s.ductile_design.holds_t),
        "mm",
    ),
    (
        "ductility limit (EN 1993-1-1, 3.2.2: eps_u >= 15 eps_y)",
        _at(lambda s: s.ductile_design.ductility_limit),
        "-",
    ),
    ("band thickness of the study's collars", _at(lambda s: s.ductile_design.study_t), "mm"),
]

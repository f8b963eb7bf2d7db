"""The free-rocking study's report: the rotations of the FEM and the multibody model from each
tilt and the velocity ratio at each impact beside Housner's (presentation only: the numbers are
summary.json's, the curves the run's CSV files)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from ..output import read_csv, write_csv
from ..report import blocks_of, distinct, figure, legend_beside, render_page
from .summary import load


def write_report(out: Path) -> Path:
    """Free rocking: rotations of the FEM and the multibody model from each tilt, the velocity
    ratio at each impact beside Housner's, and what the FEM's value depends on."""
    out = Path(out)
    s = json.loads((out / "summary.json").read_text())
    typed = load(s)  # a key the report reads that the file lacks fails here, named
    (out / "figures").mkdir(exist_ok=True)
    alpha = typed.alpha
    block = blocks_of(out)["rocking"]  # the body that rocks: its alpha
    figs = []
    fig = Figure(figsize=(9.5, 3.6))
    ax = fig.subplots()
    columns = {}
    n_curves = 2 * len(typed.tilts)
    for k, tilt in enumerate(typed.tilts, start=1):
        for j, (kind, style) in enumerate((("fem", "-"), ("multibody", "--"))):
            h = read_csv(out / "cases" / f"{kind}-tilt{k}" / "history.csv")
            label = "FEM" if kind == "fem" else "rigid multibody"
            # the two models coincide up to the first impact: each its width and markers
            ax.plot(
                h["t"],
                h["theta_left"] / alpha,
                color=f"C{k - 1}",
                **dict(distinct(2 * (k - 1) + j, n_curves), ls=style),
                label=f"{label}, released at {tilt.tilt_fraction:g} alpha_{block}",
            )
            columns[f"t_{kind}_tilt{k}"] = h["t"]
            columns[f"theta_over_alpha_{kind}_tilt{k}"] = h["theta_left"] / alpha
    n = max(len(v) for v in columns.values())
    write_csv(
        out / "figures" / "rotations.csv",
        {k: np.pad(v, (0, n - len(v)), constant_values=np.nan) for k, v in columns.items()},
    )
    ax.set_xlabel("t (s)")
    ax.set_ylabel(rf"$\theta / \alpha_\mathrm{{{block}}}$ (-)")
    legend_beside(ax)
    fig.tight_layout()
    figs.append(
        figure(
            out,
            "rotations",
            fig,
            "Free rocking from each release tilt: FEM (solid) "
            "and rigid multibody (dashed), each curve with its own markers",
        )
    )

    fig = Figure(figsize=(9, 3.6))
    ax = fig.subplots()
    ratio_columns = {}
    for k, tilt in enumerate(typed.tilts, start=1):
        for j, (kind, run) in enumerate((("fem", tilt.fem), ("multibody", tilt.multibody))):
            # a run that overturned has no ratios (a string says so): nothing drawn
            given = run.ratios
            ratios = np.array([] if isinstance(given, str) else given, dtype=float)
            label = "FEM" if kind == "fem" else "rigid multibody"
            i = 2 * (k - 1) + j  # equal ratios stay apart: each its marker and size
            ax.plot(
                np.arange(1, ratios.size + 1),
                ratios,
                color=f"C{k - 1}",
                **dict(
                    distinct(i, n_curves),
                    ls="-" if kind == "fem" else "--",
                    markevery=None,
                    markersize=8.0 - 4.0 * i / max(n_curves - 1, 1),
                ),
                label=f"{label}, released at {tilt.tilt_fraction:g} alpha_{block}",
            )
            ratio_columns[f"ratio_{kind}_tilt{k}"] = ratios
    ax.axhline(
        typed.restitution_housner, color="k", lw=0.8, ls=":", label=f"Housner 1 - 1.5 sin²α_{block}"
    )
    ax.set_xlabel("impact (count)")
    ax.set_ylabel(r"$\dot\theta_{after} / \dot\theta_{before}$ (-)")
    legend_beside(ax)
    fig.tight_layout()
    n = max((len(v) for v in ratio_columns.values()), default=0)
    write_csv(
        out / "figures" / "ratios.csv",
        {
            "impact": np.arange(1, n + 1),
            **{
                k: np.pad(v, (0, n - len(v)), constant_values=np.nan)
                for k, v in ratio_columns.items()
            },
        },
    )
    figs.append(
        figure(
            out,
            "ratios",
            fig,
            "Velocity ratio at each impact, from the rotation "
            "peaks either side through the free-rocking energy",
        )
    )

    return render_page(
        out, "free_rocking/report.html.j2", s, f"colonna free rocking: {s['study']}", figs=figs
    )

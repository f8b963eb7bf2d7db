"""The mesh-convergence study's report: each quantity over the meshes, its observed order and
Richardson estimate, and its figure (presentation only: the numbers are summary.json's)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.artist import Artist
from matplotlib.figure import Figure
from matplotlib.ticker import NullFormatter

from ..output import write_csv
from ..report import figure, one_figure_report, wrap
from ..sections import Ref
from ..units import shown_unit
from .summary import Convergence, load


def write_report(out: Path) -> Path:
    """The mesh-convergence study: the table of each quantity over the meshes, its figure."""
    return one_figure_report(
        out,
        "mesh_convergence",
        "mesh convergence",
        _convergence_figure,
        quantities=CONVERGENCE_QUANTITIES,
    )


# (quantity of the summary's convergence section, label, unit) of the mesh-convergence table;
# the template joins each quantity's key into the page's keys ("convergence." ~ name ~ ...)
CONVERGENCE_QUANTITIES: list[tuple[Ref[Convergence], str, str]] = [
    (Ref(Convergence, lambda c: c.peak_rotation), "peak rotation", "rad"),
    (
        Ref(Convergence, lambda c: c.collar_max_utilisation),
        "collar utilisation sigma / f_y",
        "-",
    ),
    (
        Ref(Convergence, lambda c: c.edge_stress_max),
        "toe stress, study-mesh peak (base contact pressure averaged over the toe window)",
        "Pa",
    ),
    (
        Ref(Convergence, lambda c: c.toe_pressure_winkler),
        "Winkler toe pressure of the sampled base force and tilt, on the bed's fixed k",
        "Pa",
    ),
]


def _convergence_figure(out: Path, s: dict) -> dict:
    typed = load(s)  # a key the report reads that the file lacks fails here, named
    sizes = typed.sizes
    columns = {"h": np.array(sizes)}
    fig = Figure(figsize=(13, 3.6))
    axes = fig.subplots(1, len(CONVERGENCE_QUANTITIES))
    handles: dict[str, Artist] = {}  # one legend for the three panels, below them: what is drawn
    for ax, (quantity, label, unit) in zip(axes, CONVERGENCE_QUANTITIES):
        c = quantity.of(typed.convergence)
        # a run that overturned has no value (its rotation is where it stopped): not drawn
        given = np.array([v if isinstance(v, (int, float)) else np.nan for v in c.values])
        columns[quantity.key] = given
        unit, scale = shown_unit(unit)  # stresses in MPa
        values = scale * given
        handles.setdefault("FEM", ax.plot(sizes, values, "o-", color="C0", label="FEM")[0])
        if isinstance(c.richardson, (int, float)):
            handles.setdefault(
                "Richardson",
                ax.axhline(
                    scale * c.richardson,
                    color="k",
                    ls="--",
                    lw=0.8,
                    label="Richardson extrapolation",
                ),
            )
        ax.set_xscale("log")
        ax.set_xticks(sizes, [f"{1e3 * h:g}" for h in sizes])
        ax.xaxis.set_minor_formatter(NullFormatter())
        ax.set_xlabel("mesh size h (mm)")
        # the table's label says what it averages; wrapped: a long one ran off the figure
        ax.set_title(wrap(label.split(" (")[0], 44), fontsize=9)
        ax.set_ylabel(f"({unit})")
    fig.legend(handles=list(handles.values()), loc="lower center", ncol=len(handles), fontsize=8)
    fig.tight_layout(rect=(0, 0.08, 1, 1))
    write_csv(out / "figures" / "convergence.csv", columns)
    return figure(out, "convergence", fig, "FEM numbers against the mesh size")

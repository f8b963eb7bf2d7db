"""The solid-vs-cracked study's report: what the crack and the collars change, variant by variant
(presentation only: the numbers are summary.json's, the curves the run's CSV files)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from ..output import read_csv, write_csv
from ..report import distinct, figure, legend_beside, one_figure_report
from ..sections import Ref
from .summary import Variant, load


def write_report(out: Path) -> Path:
    """The solid / cracked / cracked-with-collars study."""
    return one_figure_report(
        out, "solid_vs_cracked", "solid vs cracked", _variants_figure, fields=VARIANT_FIELDS
    )


# (quantity of a variant, label, unit) of the solid-vs-cracked table; the template joins each
# quantity's key into the page's keys ("variants." ~ n ~ "." ~ key)
VARIANT_FIELDS: list[tuple[Ref[Variant], str, str]] = [
    (Ref(Variant, lambda v: v.fem_peak_rotation), "FEM peak rotation", "rad"),
    (Ref(Variant, lambda v: v.fem_overturned), "FEM overturned", ""),
    (Ref(Variant, lambda v: v.rigid_peak_rotation), "rigid peak rotation", "rad"),
    (Ref(Variant, lambda v: v.rigid_mode), "rigid mode", ""),
    (Ref(Variant, lambda v: v.collar_max_utilisation), "collar utilisation sigma / f_y", "-"),
    (
        Ref(Variant, lambda v: v.edge_stress_ratio),
        "toe stress / f_c, study-mesh peak (base contact pressure averaged over the toe window)",
        "-",
    ),
    (Ref(Variant, lambda v: v.status), "FEM status", ""),
]


def _variants_figure(out: Path, s: dict) -> dict:
    typed = load(s)  # a key the report reads that the file lacks fails here, named
    fig = Figure(figsize=(9.5, 3.6))
    ax = fig.subplots()
    n_curves = 2 * len(typed.variants)
    for k, n in enumerate(typed.variants):
        fem = read_csv(out / "cases" / f"{n}-fem" / "history.csv")
        rig = read_csv(out / "cases" / f"{n}-rigid" / "history.csv")
        write_csv(
            out / "figures" / f"theta_{n}.csv",
            {
                "t": fem["t"],
                "theta_fem_left": fem["theta_left"],
                "theta_fem_right": fem["theta_right"],
                "theta_rigid": np.interp(fem["t"], rig["t"], rig["theta"]),
            },
        )
        # variants that rotate alike stay apart: each curve its width and markers
        fem_style = dict(distinct(2 * k, n_curves), ls="-")
        ax.plot(fem["t"], fem["theta_left"], color=f"C{k}", **fem_style, label=f"{n}: FEM")
        m = rig["t"] <= fem["t"][-1]
        rigid_style = dict(distinct(2 * k + 1, n_curves), ls="--")
        ax.plot(rig["t"][m], rig["theta"][m], color=f"C{k}", **rigid_style, label=f"{n}: rigid")
    ax.set_xlabel("t (s)")
    ax.set_ylabel(r"$\theta$ (rad)")
    legend_beside(ax)
    fig.tight_layout()
    return figure(
        out,
        "theta_variants",
        fig,
        "Rotation (left half): what the crack and the "
        "collars change; FEM solid, rigid dashed, each curve with its own markers",
        data_file="figures/theta_*.csv",
    )

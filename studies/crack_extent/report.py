"""The crack-extent study's report: what the crack's extent changes, extent by extent, beside
the column's two rigid limits (presentation only: the numbers are summary.json's, the curves
the run's CSV files)."""

from __future__ import annotations

from pathlib import Path

from matplotlib.figure import Figure

from ..output import read_csv, write_csv
from ..report import distinct, figure, legend_beside, one_figure_report
from ..sections import Ref
from .summary import Extent, load


def write_report(out: Path) -> Path:
    """The crack-extent study."""
    return one_figure_report(
        out, "crack_extent", "crack extent", _extents_figure, fields=EXTENT_FIELDS
    )


# (quantity of an extent, label, unit) of the crack-extent table; the template joins each
# quantity's key into the page's keys ("variants." ~ n ~ "." ~ key)
EXTENT_FIELDS: list[tuple[Ref[Extent], str, str]] = [
    (Ref(Extent, lambda v: v.crack_from), "crack from", "m"),
    (Ref(Extent, lambda v: v.crack_to), "crack to", "m"),
    (Ref(Extent, lambda v: v.crack_length_initial), "crack length at the start", "m"),
    (Ref(Extent, lambda v: v.fem_peak_rotation), "FEM peak rotation (median)", "rad"),
    (Ref(Extent, lambda v: v.fem_overturned), "FEM overturns (replicas)", ""),
    (Ref(Extent, lambda v: v.crack_grows), "does the crack grow? (replicas)", ""),
    (Ref(Extent, lambda v: v.crack_length_final), "crack length at the end (median)", "m"),
    (Ref(Extent, lambda v: v.crack_tip_KI_ratio), "largest K_I / K_IC at a tip (median)", "-"),
    (Ref(Extent, lambda v: v.collar_max_utilisation), "collar utilisation sigma / f_y", "-"),
    (
        Ref(Extent, lambda v: v.edge_stress_ratio),
        "toe stress / f_c, study-mesh peak (base contact pressure averaged over the toe window)",
        "-",
    ),
    (Ref(Extent, lambda v: v.status), "FEM status (replica 0)", ""),
]


def _extents_figure(out: Path, s: dict) -> dict:
    typed = load(s)  # a key the report reads that the file lacks fails here, named
    fig = Figure(figsize=(9.5, 3.6))
    ax = fig.subplots()
    n_curves = len(typed.variants)
    for k, n in enumerate(typed.variants):
        fem = read_csv(out / "cases" / f"{n}-fem" / "history.csv")
        write_csv(
            out / "figures" / f"theta_{n}.csv",
            {"t": fem["t"], "theta_left": fem["theta_left"], "theta_right": fem["theta_right"]},
        )
        ax.plot(fem["t"], fem["theta_left"], color=f"C{k}", **distinct(k, n_curves), label=n)
    ax.set_xlabel("t (s)")
    ax.set_ylabel(r"$\theta$ (rad)")
    legend_beside(ax)
    fig.tight_layout()
    return figure(
        out,
        "theta_extents",
        fig,
        "Rotation of the left half (FEM, replica 0) for each extent of the crack, each curve "
        "with its own markers",
        data_file="figures/theta_*.csv",
    )

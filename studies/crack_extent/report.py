"""The crack-extent study's report: what the crack's extent changes, extent by extent, beside
the column's two rigid limits (presentation only: the numbers are summary.json's, the curves
the run's CSV files)."""

from __future__ import annotations

import json
import math
from pathlib import Path

from matplotlib.figure import Figure

from ..outcome import NOT_ASSESSED
from ..output import read_csv, write_csv
from ..report import distinct, figure, legend_beside, render_page, wrap
from ..sections import Ref
from .summary import CrackExtentSummary, Extent, load


def write_report(out: Path) -> Path:
    """The crack-extent study: its table, the answers against the crack's extent, what the
    full-crack hypothesis changes, and the rotation histories."""
    out = Path(out)
    s = json.loads((out / "summary.json").read_text())
    (out / "figures").mkdir(exist_ok=True)
    typed = load(s)  # a key the report reads that the file lacks fails here, named
    return render_page(
        out,
        "crack_extent/report.html.j2",
        s,
        f"colonna crack extent: {s['study']}",
        figs=[answers_figure(out, typed), _extents_figure(out, typed)],
        fields=EXTENT_FIELDS,
        full_crack=full_crack_sentence(typed),
    )


# (quantity of an extent, label, unit) of the crack-extent table; the template joins each
# quantity's key into the page's keys ("variants." ~ n ~ "." ~ key)
EXTENT_FIELDS: list[tuple[Ref[Extent], str, str]] = [
    (Ref(Extent, lambda v: v.crack_from), "crack from", "m"),
    (Ref(Extent, lambda v: v.crack_to), "crack to", "m"),
    # the crack as it runs on the mesh's node pairs (the pair at an inner end is its intact
    # tip): it differs from "to - from" by up to half an element at each inner end
    (
        Ref(Extent, lambda v: v.crack_length_initial),
        "crack length at the start, as run on the mesh's node pairs",
        "m",
    ),
    (Ref(Extent, lambda v: v.fem_peak_rotation), "FEM peak rotation (median)", "rad"),
    (Ref(Extent, lambda v: v.fem_overturned), "FEM overturns (replicas)", ""),
    (Ref(Extent, lambda v: v.collars_yield), "do the collars yield? (replicas)", ""),
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


def _extents_figure(out: Path, typed: CrackExtentSummary) -> dict:
    """Each extent's rotation history (FEM, replica 0), from its case's history.csv."""
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


# --- the answers against the crack's extent ------------------------------------------------

# the answers (yes / no / undecided over the replicas) an extent is compared with the full
# crack's on: (attribute of Extent, the question in words)
COMPARED = (("fem_overturned", "overturns"), ("collars_yield", "collars yield"))
FULL = 1.0  # the extent fraction of the full crack (the paper's hypothesis)


def _percent(fraction: float) -> str:
    return f"{100.0 * fraction:.3g} %"


def _answers(v: Extent) -> dict[str, str]:
    return {words: getattr(v, key) for key, words in COMPARED}


def full_crack_sentence(s: CrackExtentSummary) -> str:
    """From which extent the full-crack hypothesis changes the column's answers: each extent's
    yes / no answers (overturning, the collars' yield) against the full crack's, the extents
    below the full height whose answers differ named (none: it never does on this column)."""
    full = [v for v in s.variants.values() if v.extent_fraction >= FULL and v.crack_depth >= 1]
    if not full:
        return "The sweep has no full crack: the full-crack hypothesis is not compared."
    reference = _answers(full[0])
    said = "; ".join(f"{q}: {a}" for q, a in reference.items() if a != NOT_ASSESSED)
    partial = sorted(
        (
            (v.extent_fraction, n, v)
            for n, v in s.variants.items()
            if v.extent_fraction < FULL or v.crack_depth < 1
        ),
        key=lambda item: (item[0], item[1]),
    )
    differ = [(f, n, v) for f, n, v in partial if _answers(v) != reference]
    if not differ:
        return (
            f"The full-crack hypothesis never changes the answers on this column: every "
            f"extent swept ({', '.join(_percent(f) for f, _, _ in partial)} of the height) "
            f"answers as the full crack ({said})."
        )
    words = []
    for f, n, v in differ:
        changed = ", ".join(f"{q}: {a}" for q, a in _answers(v).items() if a != reference[q])
        words.append(f"{_percent(f)} ({n}: {changed})")
    largest = differ[-1][0]
    above = [f for f, _, _ in partial if f > largest]
    from_where = (
        f"from {_percent(above[0])} of the height up every extent swept answers as the full crack"
        if above
        else "only the full crack itself gives them"
    )
    return (
        f"The full-crack hypothesis ({said}) changes the answers of the column cracked over "
        f"{'; '.join(words)} of its height; {from_where}."
    )


# the strip above the peak-rotation axes where an extent whose runs overturned is marked (y /
# the axis' cap): such a run has no peak rotation, it stopped there (issue 48)
OVERTURNED_STRIP = (1.05, 1.50)
OVERTURNED_MARK = 1.13
LIMIT_MARKS = {"solid": 1.24, "split": 1.30}  # a rigid limit that overturned, in the strip
LIMIT_STYLES = {
    "solid": dict(color="C2", ls="--", lw=1.2),
    "split": dict(color="C3", ls=":", lw=1.4),
}
LIMIT_NAMES = {
    "solid": "rigid limit: the solid column (SDOF)",
    "split": "rigid limit: the fully split column (SDOF half block)",
}
ANSWER_LEVELS = {"no": 0.0, "undecided": 1.0, "yes": 2.0}


def _number(value) -> float | None:
    """A summary value as a number, None where it is none (JSON null, the words of a stop)."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return None
    return float(value) if math.isfinite(float(value)) else None


def _band(ax, x: float, median, low, high, style: dict, label: str | None) -> None:
    """A median with its range over the replicas (the range alone where there is no median)."""
    m, lo, hi = _number(median), _number(low), _number(high)
    if lo is not None and hi is not None:
        ax.plot([x, x], [lo, hi], color=style["color"], lw=1.2, solid_capstyle="butt")
        ax.plot([x, x], [lo, hi], "_", color=style["color"], ms=7)
    if m is not None:
        ax.plot([x], [m], style["marker"], color=style["color"], ms=5, label=label)


def answers_figure(out: Path, s: CrackExtentSummary) -> dict:
    """Peak rotation (FEM median, the range over the replicas that stood), overturning, the
    collars' utilisation and K_I / K_IC against the crack's extent (its fraction of the
    height), the rigid limits as horizontal lines; an extent whose runs overturned has no peak
    but a marker in the 'overturned' strip, a rigid limit that overturned a line there.
    figures/answers.csv: each extent's numbers (empty where there is none)."""
    names = sorted(s.variants, key=lambda n: (s.variants[n].extent_fraction, n))
    rows = [s.variants[n] for n in names]
    x = [v.extent_fraction for v in rows]
    fig = Figure(figsize=(9.5, 6.6))
    axes = fig.subplots(2, 2, sharex=True)
    peaks = [
        p
        for v in rows
        for p in (_number(v.fem_peak_rotation), _number(v.fem_peak_rotation_max))
        if p is not None
    ] + [p for lim in s.limits.values() if (p := _number(lim.peak_rotation)) is not None]
    cap = 1.1 * max(peaks) if peaks else 1.0
    _overturned_strip(axes[0, 0], cap)
    labelled: set[str] = set()
    for n, v, f in zip(names, rows, x):
        _draw_extent(axes, f, v, cap, n == s.as_found, labelled)
    _draw_limits(axes, s, cap)
    _dress_answers_axes(fig, axes, cap, bool(peaks))
    _write_blank_csv(out / "figures" / "answers.csv", _answers_columns(x, rows))
    return figure(
        out,
        "answers_extent",
        fig,
        "The answers against the crack's extent (its fraction of the height; the column as "
        "found in orange): FEM peak rotation, median with the "
        "range over the replicas that stood; an extent whose runs overturned has no peak (its "
        "runs stopped there, a stopping convention, not a result) and is marked in the grey "
        "'overturned' strip with the count of its replicas; whether it overturns; the collars' "
        "utilisation and the largest K_I / K_IC at a crack tip (median, range over the "
        "replicas; 1: yield, toughness); the two rigid limits (SDOF) as horizontal lines, in "
        "the strip where they overturn",
    )


def _overturned_strip(rot, cap: float) -> None:
    """The grey 'overturned' strip above the peak rotations (cap: the top of their scale)."""
    rot.axhspan(OVERTURNED_STRIP[0] * cap, OVERTURNED_STRIP[1] * cap, color="0.92", lw=0)
    rot.text(
        0.01,
        OVERTURNED_STRIP[1] * cap - 0.02 * cap,
        "overturned",
        transform=rot.get_yaxis_transform(),
        fontsize=8,
        color="0.3",
        va="top",
    )


def _draw_extent(axes, f: float, v, cap: float, as_found: bool, labelled: set) -> None:
    """One extent's answers at x = f on the four panels (labelled: the legend's labels given
    so far, each given once)."""
    rot, over, collars, tip = axes.ravel()
    st = dict(color="C1", marker="D") if as_found else dict(color="C0", marker="o")
    what = "the column as found" if as_found else "an extent swept"

    def once(label: str) -> str | None:
        if label in labelled:
            return None
        labelled.add(label)
        return label

    _band(
        rot,
        f,
        v.fem_peak_rotation,
        v.fem_peak_rotation_min,
        v.fem_peak_rotation_max,
        st,
        once(f"FEM, {what}: median, range over the replicas (that stood, for the peak)"),
    )
    if v.fem_overturned_replicas:
        rot.plot(
            [f],
            [OVERTURNED_MARK * cap],
            "^",
            color=st["color"],
            ms=6,
            label=once(f"FEM, {what}: replicas that overturned (no peak: stopped)"),
        )
        rot.annotate(
            f"{v.fem_overturned_replicas}/{v.replicas}",
            (f, OVERTURNED_MARK * cap),
            textcoords="offset points",
            xytext=(-6, -3) if f > 0.9 else (6, -3),
            ha="right" if f > 0.9 else "left",
            fontsize=7,
        )
    over.plot(
        [f], [ANSWER_LEVELS.get(v.fem_overturned, 1.0)], st["marker"], color=st["color"], ms=5
    )
    _band(
        collars,
        f,
        v.collar_max_utilisation,
        v.collar_max_utilisation_min,
        v.collar_max_utilisation_max,
        st,
        None,
    )
    _band(
        tip, f, v.crack_tip_KI_ratio, v.crack_tip_KI_ratio_min, v.crack_tip_KI_ratio_max, st, None
    )


def _draw_limits(axes, s: CrackExtentSummary, cap: float) -> None:
    """The rigid limits as horizontal lines: the peak rotation (in the strip where the limit
    overturned) and the overturning answer."""
    rot, over = axes[0, 0], axes[0, 1]
    for name, lim in s.limits.items():
        style = LIMIT_STYLES.get(name, dict(color="0.4", ls="-.", lw=1.0))
        label = LIMIT_NAMES.get(name, f"rigid limit: {name}")
        peak = _number(lim.peak_rotation)
        if peak is None:  # it overturned: its line in the strip, no peak
            rot.axhline(LIMIT_MARKS.get(name, 1.2) * cap, **style, label=f"{label}, overturned")
        else:
            rot.axhline(peak, **style, label=label)
        over.axhline(ANSWER_LEVELS.get(lim.overturned, 1.0), **style)


def _dress_answers_axes(fig, axes, cap: float, any_peak: bool) -> None:
    """Limits, ticks, labels and the legend of the answers figure."""
    rot, over, collars, tip = axes.ravel()
    rot.set_ylim(0.0, OVERTURNED_STRIP[1] * cap)
    rot.set_yticks([y for y in rot.get_yticks() if 0.0 <= y <= cap + 1e-12] if any_peak else [])
    rot.set_ylabel("peak |theta| (rad)")
    over.set_yticks(list(ANSWER_LEVELS.values()), list(ANSWER_LEVELS))
    over.set_ylim(-0.4, 2.4)
    over.set_ylabel("overturns? (replicas)")
    collars.axhline(1.0, color="k", lw=0.8, ls="-", alpha=0.6)
    collars.set_ylabel(wrap("collar utilisation sigma / f_y", 22))
    tip.axhline(1.0, color="k", lw=0.8, ls="-", alpha=0.6)
    tip.set_ylabel("largest K_I / K_IC")
    for ax in (collars, tip):
        ax.set_xlabel("crack extent (fraction of the height)")
        ax.set_ylim(bottom=0.0)
    for ax in axes.ravel():
        ax.set_xlim(-0.05, 1.05)
    handles, labels = rot.get_legend_handles_labels()
    fig.legend(
        handles,
        [wrap(lab, 48) for lab in labels],
        loc="lower center",
        ncol=2,
        fontsize=8,
        frameon=False,
    )
    fig.tight_layout(rect=(0.0, 0.17, 1.0, 1.0))


def _answers_columns(x: list, rows: list) -> dict:
    """figures/answers.csv's columns: each extent's numbers, None where a run gives none."""
    return {
        "extent_fraction": x,
        "fem_peak_rotation_median": [_number(v.fem_peak_rotation) for v in rows],
        "fem_peak_rotation_min_stood": [_number(v.fem_peak_rotation_min) for v in rows],
        "fem_peak_rotation_max_stood": [_number(v.fem_peak_rotation_max) for v in rows],
        "fem_overturned_replicas": [v.fem_overturned_replicas for v in rows],
        "replicas": [v.replicas for v in rows],
        "collar_utilisation_median": [_number(v.collar_max_utilisation) for v in rows],
        "collar_utilisation_min": [_number(v.collar_max_utilisation_min) for v in rows],
        "collar_utilisation_max": [_number(v.collar_max_utilisation_max) for v in rows],
        "KI_ratio_median": [_number(v.crack_tip_KI_ratio) for v in rows],
        "KI_ratio_min": [_number(v.crack_tip_KI_ratio_min) for v in rows],
        "KI_ratio_max": [_number(v.crack_tip_KI_ratio_max) for v in rows],
    }


def _write_blank_csv(path: Path, columns: dict) -> None:
    """A table with an empty cell where a value is None (a number a run does not give)."""
    names = list(columns)
    lines = [",".join(names)]
    for row in zip(*(columns[n] for n in names)):
        lines.append(",".join("" if v is None else repr(float(v)) for v in row))
    path.write_text("\n".join(lines) + "\n")

"""The collar-layout study's report: the answer first (the chosen layout, its risk against the
target), then the trade-off of risk against steel mass over the whole catalogue, why each
lighter layout fails, and the chosen layout's FEM check at the design intensity
(presentation only: every number is summary.json's)."""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

from matplotlib.figure import Figure

from ..report import figure, legend_beside, render_page


def write_report(out: Path) -> Path:
    """index.html of a collar-layout study from its summary.json."""
    out = Path(out)
    s = json.loads((out / "summary.json").read_text())
    (out / "figures").mkdir(exist_ok=True)
    return render_page(
        out,
        "collar_layout/report.html.j2",
        s,
        f"colonna collar layout: {s['study']}",
        figs=[_trade_off(out, s)],
        lighter=lighter_rows(s),
        fem_rows=fem_rows(s),
        attempt_rows=attempt_rows(s),
    )


def frequency_text(row: dict) -> str:
    """A layout's lambda (1/year) as the report gives it: the refined value, else the
    screening's bracket (or its bound)."""
    if row.get("frequency") is not None:
        return f"{row['frequency']:.3g}"
    if row["lower"] == row["upper"]:
        return f"{'at most ' if row['upper_is_bound'] else ''}{row['upper']:.3g}"
    return f"{row['lower']:.3g} to {row['upper']:.3g}"


def band_text(row: dict) -> str:
    """A judged layout's lambda band over the records (1/year; the bootstrap's, at the
    study's confidence), "-" where there is none (not judged, or a bound)."""
    entry = row.get("frequency_entry") or {}
    interval = (entry.get("risk") or {}).get("frequency_interval")
    if not interval:
        return "-"
    return f"{interval[0]:.3g} to {interval[1]:.3g}"


# the model that decided a layout (its row's decided_by)
DECIDED_BY = {
    "screening": "screened (elastic collars; none yields before the column overturns)",
    "refinement": "refined (plastic collars)",
    None: "-",
}


def lighter_rows(s: dict) -> list[dict]:
    """The layouts up to the chosen one in the catalogue's order, lightest first (without a
    choice: up to the one that meets the target but is not chosen, else all), each with the
    model that decided it and why it fails (or is chosen)."""
    chosen = s.get("chosen")
    rows: list[dict] = []
    for r in s["layouts"]:
        if rows and rows[-1]["decision"] in ("chosen", "meets the target, not chosen"):
            break
        rows.append(
            {
                "label": r["label"],
                "mass": f"{r['mass']:.1f}",
                "frequency": frequency_text(r),
                "band": band_text(r),
                "by": DECIDED_BY[r.get("decided_by")],
                "decision": r["decision"],
                "why": r.get("why", ""),
            }
        )
        if chosen is not None and r["label"] == chosen["label"]:
            break
    return rows


def fem_rows(s: dict) -> list[dict]:
    """The FEM stripe at the design intensity beside the multibody's P there."""
    fem = s.get("fem")
    if not fem:
        return []
    p = fem["multibody_probability"]
    band = fem["multibody_probability_interval"]
    low, high = fem["fraction_interval"]
    return [
        {
            "model": "rigid multibody (plastic collars), the IDA fit at the design intensity",
            "value": "-" if p is None else f"{p:.2f} ({band[0]:.2f} to {band[1]:.2f})",
        },
        {
            "model": f"FEM, the {len(fem['overturned'])} records at the design intensity",
            "value": f"{fem['fraction']:.2f} overturned ({low:.2f} to {high:.2f}); "
            f"{fem['fracture_share']:.2f} fracture a collar",
        },
        {
            "model": "record by record: overturned by one model only",
            "value": f"FEM only: {', '.join(fem['fem_only']) or 'none'}; multibody only "
            f"(its first overturning on the ladder at or below the design intensity): "
            f"{', '.join(fem['multibody_only']) or 'none'}",
        },
    ]


AGREEMENT = {
    "confirms": "confirms",
    "contradicts": "contradicts",
    "undecided": "neither confirms nor contradicts",
}


def attempt_rows(s: dict) -> list[dict]:
    """Each layout FEM-checked at the design intensity, in the order checked: its steel, its
    multibody frequency, the records each model overturns there, McNemar's p, the fractures
    and what the stripe says."""
    choice = s.get("fem_choice")
    if not choice:
        return []
    rows = []
    for a in choice["attempts"]:
        fem = a["fem"]
        n = len(fem["overturned"])
        rows.append(
            {
                "label": a["label"],
                "mass": f"{a['mass']:.1f}",
                "frequency": f"{a['frequency']:.3g}",
                "fem": f"{sum(fem['overturned'])} of {n}",
                "multibody": f"{sum(fem['multibody_overturned'])} of {n}",
                "differ": f"FEM only: {', '.join(fem['fem_only']) or 'none'}; multibody only: "
                f"{', '.join(fem['multibody_only']) or 'none'}",
                "p": f"{fem['mcnemar_p']:.2g}",
                "fractures": f"{fem['fracture_share']:.2f}",
                "agreement": AGREEMENT[a["agreement"]]
                + (
                    " (collars fracture beyond the allowance)"
                    if fem["fracture_share"] > fem["fracture_allowed"]
                    else ""
                ),
                "chosen": a["label"] == choice["chosen"],
            }
        )
    return rows


DECISION_STYLE = {
    "fails": ("x", "tab:red"),
    "not confirmed by the FEM": ("s", "tab:orange"),
    "chosen": ("*", "tab:green"),
    "meets the target, not chosen": ("*", "tab:grey"),
    "skipped by the FEM attempts": ("D", "tab:purple"),
    "not judged": ("o", "tab:grey"),
    "not refined": ("o", "tab:grey"),
    "heavier than the chosen layout": ("o", "tab:blue"),
}


def _trade_off(out: Path, s: dict) -> dict:
    """lambda of overturning against steel mass over the catalogue: refined values as points,
    screening brackets as bars, the target as a line, the chosen layout starred."""
    fig = Figure(figsize=(7.0, 4.2))
    ax = fig.add_subplot()
    rows = s["layouts"]
    columns: dict[str, list] = {
        "label": [],
        "mass_kg": [],
        "lambda_low": [],
        "lambda_high": [],
        "lambda": [],
        "decision": [],
    }
    seen = set()
    for r in rows:
        marker, colour = DECISION_STYLE.get(r["decision"], ("o", "tab:grey"))
        low, high = r["lower"], r["upper"]
        floor = 1e-7
        ax.plot([r["mass"]] * 2, [max(low, floor), max(high, floor)], color=colour, lw=1.0)
        value = r.get("frequency")
        label = None if r["decision"] in seen else r["decision"]
        seen.add(r["decision"])
        ax.plot(
            r["mass"],
            max(value if value is not None else high, floor),
            marker=marker,
            color=colour,
            ls="none",
            ms=9 if r["decision"] == "chosen" else 5,
            label=label,
        )
        columns["label"].append(r["label"])
        columns["mass_kg"].append(r["mass"])
        columns["lambda_low"].append(low)
        columns["lambda_high"].append(high)
        columns["lambda"].append(value if value is not None else math.nan)
        columns["decision"].append(r["decision"])
    front = [r for r in rows if r["label"] in set(s.get("pareto", ()))]
    if len(front) > 1:
        ax.step(
            [r["mass"] for r in front],
            [r["frequency"] for r in front],
            where="post",
            color="tab:green",
            lw=1.0,
            alpha=0.6,
            label="Pareto front",
        )
    ax.axhline(s["target"]["frequency"], color="k", ls="--", lw=1.0, label="target")
    ax.set_yscale("log")
    ax.set_xlabel("steel mass of the collars (kg)")
    ax.set_ylabel("overturning, mean annual frequency (1/year)")
    ax.grid(True, which="both", alpha=0.3)
    legend_beside(ax)
    fig.tight_layout()
    with open(out / "figures" / "trade_off.csv", "w", newline="") as f:
        rows_out = csv.writer(f)
        rows_out.writerow(columns)
        rows_out.writerows(zip(*columns.values()))
    return figure(
        out,
        "trade_off",
        fig,
        "Risk against steel: each layout's mean annual frequency of overturning at the site "
        "(a bar: the bracket of the elastic screening; a marker: the value refined with plastic "
        "collars, or the bracket's upper end) against its steel mass; the target dashed.",
    )

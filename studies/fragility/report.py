"""The fragility study's report: the probability of each limit state at the design intensity per
model first, then the fragility curves with their bootstrap bands and the stripe fractions with
their confidence bars, the IDA curves, the suite's spectra and IM table, and the likelihood-ratio
tests of the rigid models against the FEM (presentation only: every number is summary.json's)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from ...rigid.multibody import COLLAR_STEP_FRACTION
from ..output import CSV_FORMAT, write_csv
from ..report import figure, legend_beside, render_page
from .analysis import LIMIT_STATES
from .models import MODEL_NAMES
from .runner import answer_fit
from .summary import load

FIT_NAMES = {"ida": "IDA", "stripes": "stripes"}
INTENSITY_LABELS = {
    "pga": "PGA (m/s$^2$)",
    "pgv": "PGV (m/s)",
    "sa": "Sa(T) (m/s$^2$)",
    # a_up = g tan(alpha) (1 + lambda): the rocking block's uplift (lambda: its top load / weight)
    "pga_rocking": r"PGA / (g tan$\alpha$ (1 + $\lambda$))",
    "pgv_rocking": r"PGV p / (g tan$\alpha$ (1 + $\lambda$))",
}


def write_report(out: Path) -> Path:
    """index.html of a fragility study from its summary.json."""
    out = Path(out)
    s = json.loads((out / "summary.json").read_text())
    typed = load(s)  # a key the report reads that the file lacks fails here, named
    (out / "figures").mkdir(exist_ok=True)
    label = INTENSITY_LABELS[typed.intensity]
    if typed.intensity == "sa":
        label = label.replace("T", f"T = {typed.period:g} s")
    figs = [
        _curves(out, s, label),
        _ida(out, s, label),
        _spectra(out, s),
    ]
    hazard_figure = _hazard(out, s, label) if typed.hazard else None
    return render_page(
        out,
        "fragility/report.html.j2",
        s,
        f"colonna fragility: {typed.study}",
        figs=[f for f in figs if f is not None],
        design_rows=design_rows(s),
        risk_rows=risk_rows(s),
        hazard_figure=hazard_figure,
        collar_rows=collar_rows(s),
        overturn_rows=overturn_rows(s),
        extrapolated=extrapolated_rows(s),
        fit_rows=fit_rows(s),
        im_rows=im_rows(s),
        tests=test_rows(s),
        names=MODEL_NAMES,
        states=LIMIT_STATES,
        single_multibody_step=COLLAR_STEP_FRACTION,
    )


def _answer(entry: dict) -> tuple[str, dict | None]:
    """(which fit, the fit) a limit state's probability is read from (the runner's
    :func:`answer_fit`: the IDA capacities' where there is one, else the stripes')."""
    fit = answer_fit(entry)
    if fit is None:
        return "", None
    return ("ida" if fit is entry.get("ida") else "stripes"), fit


UNREACHABLE = "cannot be reached by this model"


def design_rows(s: dict) -> list[dict]:
    """Per limit state, per model: P at the design intensity with its interval (or why
    none); "cannot be reached by this model" with why where the model cannot reach the limit
    state (never a probability of zero), and beside an answer that rests on elastic collars
    past f_y (:func:`rests_note`) a note that says so."""
    rows = []
    for state, words in LIMIT_STATES.items():
        cells = []
        for model in s["models"]:
            entry = s["limit_states"][model].get(state)
            why = s.get("unreachable", {}).get(model, {}).get(state)
            if why is not None:
                cells.append({"text": UNREACHABLE, "key": None, "note": why, "unreachable": True})
                continue
            if entry is None:
                cells.append({"text": "not assessed", "key": None, "note": None})
                continue
            note = rests_note(s, model, state)
            which, fit = _answer(entry)
            if fit is None:
                cells.append({"text": entry.get("why", "no curve"), "key": None, "note": note})
                continue
            low, high = fit["probability_interval"]
            cells.append(
                {
                    "text": f"{fit['probability']:.3g} [{low:.3g}, {high:.3g}]",
                    "key": f"design.P({state})_{model}",
                    "fit": which,
                    "note": note,
                }
            )
        if any(c["key"] is not None or c["text"] != "not assessed" for c in cells):
            rows.append({"state": words, "cells": cells})
    return rows


def risk_rows(s: dict) -> list[dict]:
    """With a hazard: per limit state and model, the risk of the fit its probability is read
    from (summary.json's limit_states[model][state][fit].risk): lambda per year, the return
    period and the probability in the hazard's years, each with its bootstrap interval, and
    what of lambda is read beyond the hazard table; a limit state without a fit says why."""
    if not s.get("hazard"):
        return []
    rows = []
    for state, words in LIMIT_STATES.items():
        for model in s["models"]:
            entry = s["limit_states"][model].get(state)
            why = s.get("unreachable", {}).get(model, {}).get(state)
            if entry is None and why is None:
                continue
            row: dict = {"state": words, "model": MODEL_NAMES[model]}
            which, fit = _answer(entry) if entry is not None else ("", None)
            if why is not None or fit is None:
                row["text"] = UNREACHABLE if why is not None else entry.get("why", "no curve")
                rows.append(row)
                continue
            r = fit["risk"]
            low, high = r["frequency_interval"]
            period = r["return_period"]
            short, long = r["return_period_interval"]
            p_low, p_high = r["probability_interval"]
            row.update(
                key=f"risk.lambda({state})_{model}",
                fit=FIT_NAMES[which],
                frequency=f"{r['frequency']:.2e} [{low:.2e}, {high:.2e}]",
                period=f"{_years(period)} [{_years(short)}, {_years(long)}]",
                probability=f"{r['probability']:.3g} [{p_low:.3g}, {p_high:.3g}]",
                beyond=_beyond_text(s["hazard"], r),
                qualified=bool(r["beyond"]),
                words=r["beyond"],
            )
            rows.append(row)
    return rows


def _years(period: float | None) -> str:
    """A return period in years as people write it: 1790, 45.2; "never" for none."""
    if period is None:
        return "never"
    return f"{period:.0f}" if period >= 100.0 else f"{period:.3g}"


def _share(fraction: float) -> str:
    """A share of lambda in per cent: 16 %, 0.12 %, "< 0.1 %"."""
    return f"{100 * fraction:.2g} %" if fraction >= 1e-3 else "< 0.1 %"


def _beyond_text(hazard: dict, r: dict) -> str:
    """What of a lambda is read beyond the data, said always: the shares of lambda from
    capacities below and above the levels run (the fit's extrapolation) and the hazard table
    (held below it; extrapolated or truncated above), then the words where they matter."""
    levels = f"levels run {_share(r['below_levels'])} below, {_share(r['above_levels'])} above"
    if hazard["form"] == "table":
        how = "extrapolated" if hazard["beyond"] == "extrapolate" else "truncated"
        levels += (
            f"; hazard table {_share(r['below'])} below (held), {_share(r['above'])} above ({how})"
        )
    return levels + (": " + "; ".join(r["beyond"]) if r["beyond"] else "")


def rests_note(s: dict, model: str, state: str) -> str | None:
    """Where a model's answer for ``state`` rests on elastic collars that carried more than
    f_y in runs the column survived (summary.json's collars[model].past_fy), that in words."""
    law = s.get("collars", {}).get(model, {})
    past = law.get("past_fy")
    if past is None or state not in law.get("rests", ()):
        return None
    return (
        f"rests on {law['short']} at up to {past['largest_utilisation']:.3g} f_y "
        f"({past['runs']} of {past['of']} survived runs past f_y)"
    )


def collar_rows(s: dict) -> list[dict]:
    """Per model: what its collars are and, where they are elastic and passed f_y, the note
    (summary.json's collars)."""
    return [
        {"model": MODEL_NAMES[m], "words": law["words"], "note": law.get("note")}
        for m, law in s.get("collars", {}).items()
    ]


def extrapolated_rows(s: dict) -> list[str]:
    """Every fit read outside the levels run (its median or the median's interval), in
    words: model, limit state, fit and what lies outside."""
    found = []
    for model in s["models"]:
        for state, entry in s["limit_states"][model].items():
            for which in ("ida", "stripes"):
                fit = entry.get(which) or {}
                for words in fit.get("extrapolated", ()):
                    found.append(
                        f"{MODEL_NAMES[model]}, {LIMIT_STATES[state]}, {FIT_NAMES[which]} fit: "
                        + words
                    )
    return found


def fit_rows(s: dict) -> list[dict]:
    """Per model and limit state: each fit's median and dispersion with their intervals."""
    rows = []
    for model in s["models"]:
        for state, entry in s["limit_states"][model].items():
            for which in ("ida", "stripes"):
                fit = entry.get(which)
                if fit is None:
                    continue
                row = {
                    "model": MODEL_NAMES[model],
                    "state": LIMIT_STATES[state],
                    "fit": "IDA capacities" if which == "ida" else "stripes (binomial MLE)",
                }
                if fit.get("fit") is None:
                    row["text"] = fit.get("why", "no fit")
                else:
                    f = fit["fit"]
                    m, b = fit["median_interval"], fit["beta_interval"]
                    row.update(
                        median=f"{f['median']:.4g} [{m[0]:.3g}, {m[1]:.3g}]",
                        beta=f"{f['beta']:.3g} [{b[0]:.3g}, {b[1]:.3g}]",
                        method=f["method"]
                        + (" (a step: the data separate)" if f["separated"] else "")
                        + (
                            f", shifted lognormal of IM - {f['origin']:.4g} (the uplift intensity)"
                            if f.get("origin", 0.0) > 0.0
                            else ""
                        ),
                        extrapolated="; ".join(fit.get("extrapolated", ())),
                    )
                rows.append(row)
    return rows


def im_rows(s: dict) -> list[dict]:
    """The suite's records: their IMs (as in the suite, times its scale)."""
    return [
        {
            "name": r["name"],
            "file": r["file"],
            "scale": r["suite_scale"],
            "duration": r["duration"],
            "intensity": r["intensity"],
            **r["ims"],
        }
        for r in s["records"]
    ]


def test_rows(s: dict) -> list[dict]:
    """The likelihood-ratio tests: per limit state, each rigid model against the FEM."""
    rows = []
    for state, tests in s.get("same_curve", {}).items():
        for pair, test in tests.items():
            model = pair.removesuffix("_fem")
            rows.append(
                {
                    "state": LIMIT_STATES[state],
                    "pair": f"{MODEL_NAMES[model]} vs FEM",
                    "p_value": test.get("p_value"),
                    "statistic": test.get("statistic"),
                    "one_curve": test.get("one_curve"),
                    "why": test.get("why"),
                }
            )
    return rows


def _curves(out: Path, s: dict, label: str) -> dict | None:
    """The fragility curves: per limit state, each model's fit with its band and its stripe
    fractions with their confidence bars; the design intensity marked."""
    states = [st for st in LIMIT_STATES if any(st in s["limit_states"][m] for m in s["models"])]
    if not states:
        return None
    columns = min(3, len(states))
    rows = (len(states) + columns - 1) // columns
    fig = Figure(figsize=(4.2 * columns + 1.8, 3.3 * rows))
    axes = np.atleast_1d(fig.subplots(rows, columns, squeeze=False)).ravel()
    levels = np.array(s["levels"])
    data: dict = {"im": levels}
    for ax, state in zip(axes, states):
        cannot, fitted = [], False
        for k, model in enumerate(s["models"]):
            entry = s["limit_states"][model].get(state)
            if state in s.get("unreachable", {}).get(model, {}):
                cannot.append(MODEL_NAMES[model])
            if entry is None:
                continue
            colour = f"C{k}"
            name = model_label(s, model)
            fractions = np.array(entry["fractions"])
            bars = np.array(entry["fraction_intervals"])
            x = levels * (1.0 + 0.01 * (k - 1))  # models' bars side by side
            ax.errorbar(
                x,
                fractions,
                yerr=[fractions - bars[:, 0], bars[:, 1] - fractions],
                fmt="none",
                color=colour,
                capsize=2,
                lw=0.8,
            )
            past = np.zeros(levels.size, dtype=bool)
            if rests_note(s, model, state) is not None:
                past = np.array(s["collars"][model]["past_fy"]["levels"], dtype=bool)
            if (~past).any():
                ax.plot(
                    x[~past],
                    fractions[~past],
                    "o",
                    ms=4,
                    color=colour,
                    label=f"{name}: fraction of records",
                )
            if past.any():
                ax.plot(
                    x[past],
                    fractions[past],
                    "o",
                    ms=4,
                    mfc="white",
                    mec=colour,
                    label=f"{name}: fraction of records, at a level where a run it survived "
                    "had its elastic collars past f_y",
                )
            data[f"{state}_{model}_fraction"] = fractions
            which, fit = _answer(entry)
            if fit is not None:
                curve = fit["curve"]
                im = np.array(curve["im"])
                outside = np.array(
                    curve.get("extrapolated", (im < levels.min()) | (im > levels.max())),
                    dtype=bool,
                )
                fitted = True
                ax.fill_between(im, curve["low"], curve["high"], color=colour, alpha=0.18, lw=0)
                p = np.array(curve["probability"], dtype=float)
                ax.plot(im, p, color=colour, ls="--", lw=0.9)
                ax.plot(
                    im,
                    np.where(outside, np.nan, p),
                    color=colour,
                    label=f"{MODEL_NAMES[model]}: lognormal fit ({FIT_NAMES[which]}) and band",
                )
        ax.axvline(s["design_intensity"], color="k", ls=":", lw=1.0, label="design intensity")
        if fitted:
            ax.plot([], [], color="k", ls="--", lw=0.9, label=EXTRAPOLATED)
        title = LIMIT_STATES[state]
        if cannot:
            title += "\n" + ", ".join(cannot) + ": " + UNREACHABLE
        ax.set_title(title, fontsize=10 if not cannot else 8.5)
        ax.set_ylim(-0.03, 1.03)
        ax.set_xlabel(label)
        ax.set_ylabel("P[limit state | IM]")
    for ax in axes[len(states) :]:
        ax.set_visible(False)
    handles, labels = axes[0].get_legend_handles_labels()
    seen = dict(zip(labels, handles))
    for ax in axes[1 : len(states)]:
        for h, lab in zip(*ax.get_legend_handles_labels()):
            seen.setdefault(lab, h)
    fig.legend(list(seen.values()), list(seen), loc="lower center", ncol=2, fontsize=8)
    fig.tight_layout(rect=(0, 0.06 + 0.03 * len(seen) / 2 / rows, 1, 1))
    write_csv(out / "figures" / "curves.csv", data)
    band = next(
        (
            fit["level"]
            for m in s["models"]
            for entry in s["limit_states"][m].values()
            for fit in (entry.get("ida"), entry.get("stripes"))
            if fit and "level" in fit
        ),
        None,
    )  # (the first model need not assess the first limit state: the FEM's uplift)
    return figure(
        out,
        "curves",
        fig,
        "Fragility curves: per limit state, each model's lognormal fit with its bootstrap band "
        + (f"({100 * band:.0f} %, over records) " if band else "")
        + "and the fraction of records in the limit state at each level with its exact "
        "binomial interval; the dotted line is the design intensity; a fit is dashed outside "
        "the levels run (extrapolated); a hollow marker: a level at which the model's elastic "
        "collars carried more than f_y in a run it survived; a model that cannot reach a limit "
        "state is named in its panel's title, no curve drawn",
    )


EXTRAPOLATED = "dashed: a fit outside the levels run (extrapolated)"


def model_label(s: dict, model: str) -> str:
    """A model's name with its collars (summary.json's collars[model].short), for a legend."""
    short = s.get("collars", {}).get(model, {}).get("short")
    if short in (None, "no collars"):
        return MODEL_NAMES[model]
    return f"{MODEL_NAMES[model]} ({short})"


# the strip right of the IDA axes where a run that overturned is marked (x / the axis' cap): it
# has no largest |theta| / alpha, its run stopped there (issue 48)
OVERTURNED_STRIP = (1.05, 1.32)
OVERTURNED_MARK = 1.13
RUN_OVERTURNED = "a run that overturned (no peak: it stopped)"


def overturn_times(s: dict, model: str) -> np.ndarray:
    """The records x levels table of when each run of ``model`` overturned (s; NaN where it
    stood or the summary has no times: summary.json's runs[model].overturned_at)."""
    runs = s["runs"][model]
    times = runs.get("overturned_at")
    if times is None:
        return np.full(np.shape(runs["overturned"]), np.nan)
    return np.array([[np.nan if v is None else v for v in row] for row in times], dtype=float)


def overturn_rows(s: dict) -> list[dict]:
    """Per model, each record that overturned at a level: at how many levels, the first (its
    IDA capacity) and, in place of its largest |theta| / alpha there, "not applicable: ...
    overturned at t = ..." (:func:`colonna.studies.outcome.overturned_at`: a run that
    overturned stopped there, its peak is the stopping angle)."""
    from ..outcome import not_applicable, overturned_at

    rows = []
    levels = s["levels"]
    for model in s["models"]:
        over = np.array(s["runs"][model]["overturned"], dtype=bool)
        times = overturn_times(s, model)
        for i in np.flatnonzero(over.any(axis=1)):
            j = int(np.argmax(over[i]))
            t = None if np.isnan(times[i, j]) else float(times[i, j])
            rows.append(
                {
                    "model": MODEL_NAMES[model],
                    "record": s["records"][i]["name"],
                    "levels": f"{int(over[i].sum())} of {len(levels)}",
                    "first": f"{levels[j]:.4g}",
                    "peak": not_applicable(overturned_at(f"the {MODEL_NAMES[model]}", True, t)),
                }
            )
    return rows


def write_csv_blank(path: Path, columns: dict) -> None:
    """:func:`..output.write_csv`'s table with an empty cell where a value is NaN (a run that
    gives no number), not "nan"."""
    names = list(columns)
    table = np.column_stack([np.asarray(columns[n], dtype=float) for n in names])
    lines = [",".join(names)] + [
        ",".join("" if np.isnan(v) else CSV_FORMAT % v for v in row) for row in table
    ]
    path.write_text("\n".join(lines) + "\n")


def _ida(out: Path, s: dict, label: str) -> dict | None:
    """The IDA curves: each record's largest |theta| / alpha over the levels where its run
    stood, per model; a run that overturned has none (its run stopped there) and is marked in
    a strip beside the axes, the first one of each record as its capacity. figures/ida.csv:
    each run's peak (empty where it overturned) and when it overturned (empty where it
    stood)."""
    models = s["models"]
    levels = np.array(s["levels"])
    cap = max(2.0, 2.0 * s["theta_ratio"])
    mark = OVERTURNED_MARK * cap
    fig = Figure(figsize=(4.0 * len(models) + 1.8, 3.6))
    axes = np.atleast_1d(fig.subplots(1, len(models), sharey=True, squeeze=False)).ravel()
    data: dict = {"im": levels}
    past_cap = False
    for ax, model in zip(axes, models):
        peak = np.array(s["runs"][model]["peak_ratio"], dtype=float)
        over = np.array(s["runs"][model]["overturned"], dtype=bool)
        times = overturn_times(s, model)
        stood = np.where(over, np.nan, peak)
        past_cap |= bool(np.any(stood > cap))
        ax.axvspan(OVERTURNED_STRIP[0] * cap, OVERTURNED_STRIP[1] * cap, color="0.92", lw=0)
        ax.text(
            0.5 * (OVERTURNED_MARK + OVERTURNED_STRIP[1]) * cap,
            0.5,
            "overturned",
            transform=ax.get_xaxis_transform(),
            rotation=90,
            ha="left",
            va="center",
            fontsize=8,
            color="0.3",
        )
        for i in range(stood.shape[0]):
            ax.plot(
                np.minimum(stood[i], cap),
                levels,
                ".-",
                color="0.55",
                lw=0.8,
                ms=2.5,
                gid=f"record{i}",
            )
            data[f"{model}_record{i}"] = stood[i]
            data[f"{model}_record{i}_overturned_at_s"] = np.where(over[i], times[i], np.nan)
            if over[i].any():
                ax.plot(
                    np.full(int(over[i].sum()), mark),
                    levels[over[i]],
                    ">",
                    color="0.35",
                    ms=3.5,
                    label=RUN_OVERTURNED,
                    gid=f"record{i}-overturned",
                )
                j = int(np.argmax(over[i]))
                ax.plot([mark], [levels[j]], "x", color="C3", ms=7, label="first overturning")
        ax.axvline(s["theta_ratio"], color="C1", ls="--", lw=1.0, label="rotation threshold")
        ax.axhline(s["design_intensity"], color="k", ls=":", lw=1.0, label="design intensity")
        ax.set_xlim(0.0, OVERTURNED_STRIP[1] * cap)
        ax.set_xticks([x for x in ax.get_xticks() if 0.0 <= x <= cap + 1e-9])
        ax.set_title(model_label(s, model), fontsize=10)
        ax.set_xlabel(r"largest $|\theta| / \alpha$ of a run that stood")
    axes[0].set_ylabel(label)
    handles, labels = axes[-1].get_legend_handles_labels()
    for ax in axes:
        for h, lab in zip(*ax.get_legend_handles_labels()):
            if lab not in labels:
                handles.append(h)
                labels.append(lab)
    unique = dict(zip(labels, handles))
    legend_beside(axes[-1], handles=list(unique.values()), labels=list(unique))
    fig.tight_layout()
    write_csv_blank(out / "figures" / "ida.csv", data)
    return figure(
        out,
        "ida",
        fig,
        "IDA curves: each record's largest |theta| / alpha (alpha of the rocking block) at "
        "each level where its run stood"
        + (f" (drawn at {cap:g} where larger)" if past_cap else "")
        + "; a run that overturned has none, its run stopped there (a stopping convention, "
        "not a result): it is marked in the grey strip, a record's capacity is its first "
        "overturning (x), even where it survives a higher level. The data give each run's "
        "peak, empty where it overturned, and beside it when it overturned "
        "(RECORD_overturned_at_s, s)",
    )


def _spectra(out: Path, s: dict) -> dict | None:
    """The suite's 5 %-damped pseudo-spectral accelerations and their median."""
    spectra = s.get("spectra")
    if not spectra:
        return None
    periods = np.array(spectra["periods"])
    sa = np.array(spectra["sa"], dtype=float)
    fig = Figure(figsize=(7.5, 3.6))
    ax = fig.subplots()
    for row in sa:
        ax.loglog(periods, row, color="0.65", lw=0.8)
    ax.loglog(periods, np.median(sa, axis=0), color="C0", lw=2.2, label="median of the suite")
    ax.plot([], [], color="0.65", lw=0.8, label="each record")
    ax.set_xlabel("period T (s)")
    ax.set_ylabel(r"Sa(T, 5 %) (m/s$^2$)")
    legend_beside(ax)
    fig.tight_layout()
    write_csv(
        out / "figures" / "spectra.csv",
        {"period": periods, **{f"record{i}": row for i, row in enumerate(sa)}},
    )
    return figure(
        out,
        "spectra",
        fig,
        "The suite's 5 %-damped pseudo-spectral accelerations (each record times its suite "
        "scale, before the study scales it to a level)",
    )


def _hazard(out: Path, s: dict, label: str) -> dict:
    """The site's hazard curve in the fragility's measure (log-log: the table's points, its
    interpolation, held below it and extrapolated or truncated above it; or the power law),
    beside where each limit state's lambda comes from: d lambda_LS / d ln IM = lambda_IM(x)
    dP / d ln x (the answer fit's: :mod:`colonna.core.risk`'s integrand; its area over ln IM
    is lambda), per limit state, of the first model with a fit; the levels run shaded, the
    table's ends marked."""
    from ...core.fragility import LognormalFit
    from ...core.hazard import HazardCurve, annual_frequency

    h = s["hazard"]
    curve = HazardCurve(
        h["intensity"],
        h["unit"],
        im=tuple(h["im"]),
        frequency=tuple(h["frequency"]),
        k0=h["k0"],
        k=h["k"],
        period=h["period"],
        beyond=h["beyond"],
    )
    levels = np.array(s["levels"], dtype=float)
    ends = [levels.min(), levels.max()] + (list(curve.range) if curve.tabulated else [])
    x = np.geomspace(0.3 * min(ends), 3.0 * max(ends), 400)
    fig = Figure(figsize=(10.0, 4.4))
    left, right = fig.subplots(1, 2)
    lam = annual_frequency(curve, x)
    data: dict = {"im": x, "hazard_frequency": lam}
    if curve.tabulated:
        low, high = curve.range
        left.loglog(
            np.where((x >= low) & (x <= high), x, np.nan),
            lam,
            color="k",
            label="hazard: its table, log-log between the points (o)",
        )
        left.loglog(curve.im, curve.frequency, "o", color="k", ms=4)
        left.loglog(
            np.where(x < low, x, np.nan),
            lam,
            color="k",
            ls=":",
            label="hazard below the table: held at its lowest frequency",
        )
        if curve.beyond == "extrapolate":
            left.loglog(
                np.where(x > high, x, np.nan),
                lam,
                color="k",
                ls="--",
                label="hazard above the table: its last segment's power law",
            )
        for ax in (left, right):
            for end in (low, high):
                ax.axvline(end, color="0.5", ls=":", lw=0.8)
        right.plot([], [], color="0.5", ls=":", lw=0.8, label="the hazard table's ends")
    else:
        left.loglog(x, lam, color="k", label=f"hazard: {h['source']}")
    for ax in (left, right):
        ax.axvspan(levels.min(), levels.max(), color="C0", alpha=0.08, lw=0)
        ax.set_xlabel(label)
    left.plot([], [], color="C0", alpha=0.3, lw=6, label="the levels run")
    left.set_ylabel("annual frequency of exceedance (1/year)")
    for k, state in enumerate(LIMIT_STATES):
        for model in s["models"]:
            entry = s["limit_states"][model].get(state)
            _, fit = _answer(entry) if entry is not None else ("", None)
            if fit is None or fit["fit"]["beta"] == 0.0:
                continue
            f = fit["fit"]
            lognormal = LognormalFit(f["median"], f["beta"], f.get("origin", 0.0))
            density = lam * np.gradient(lognormal.probability(x), np.log(x))
            right.semilogx(
                x, density, color=f"C{k + 1}", label=f"{LIMIT_STATES[state]} ({MODEL_NAMES[model]})"
            )
            data[f"{state}_{model}_dlambda_dlnim"] = density
            break
    right.set_ylabel("d lambda_LS / d ln IM (1/year)")
    right.set_ylim(bottom=0.0)
    seen: dict = {}
    for ax in (left, right):
        for handle, text in zip(*ax.get_legend_handles_labels()):
            seen.setdefault(text, handle)
    fig.legend(list(seen.values()), list(seen), loc="lower center", ncol=2, fontsize=8)
    fig.tight_layout(rect=(0, 0.05 + 0.045 * ((len(seen) + 1) // 2), 1, 1))
    write_csv(out / "figures" / "hazard.csv", data)
    source = Path(h["source"]).name if curve.tabulated else h["source"]
    return figure(
        out,
        "hazard",
        fig,
        "Left: the site's hazard, the annual frequency at which the intensity is exceeded "
        f"({source}, in the fragility's measure), and the levels run (shaded). Right: "
        "where each limit state's mean annual frequency comes from, the integrand of "
        "lambda_LS = int lambda_IM dP[LS | IM] per unit of ln IM (the answer fit of the first "
        "model that has one): the area under a curve is its lambda; outside the hazard "
        "table's ends (dotted lines) it rests on the hazard as the left panel draws it there",
    )

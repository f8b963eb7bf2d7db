"""The cross-check's report: the FEM against the rigid models, figure by figure, with the
Numbers table (presentation only: the numbers are summary.json's, the curves the run's CSV and
field files)."""

from __future__ import annotations

import json
import math
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.artist import Artist
from matplotlib.collections import PolyCollection
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Patch
from matplotlib.ticker import FuncFormatter, MaxNLocator

from ...core.collar import hinge_strain_profile
from ...core.constants import DUCTILITY_LIMIT
from ..output import read_csv, write_csv
from ..report import (
    LINE_STYLES,
    MODE_CODES,
    distinct,
    figure,
    image,
    legend_beside,
    render_page,
    wrap,
)
from ..sections import Ref, table
from .summary import CollarSection, CrosscheckSummary, load

SIDES = ("left", "right")  # a collar's ends in the FEM history


PLAIN = FuncFormatter(lambda value, _: f"{value:g}")  # tick labels as numbers, not powers

# The toe and base stresses the report shows, each named wherever it appears (issue 35):
# - the toe stress: the base contact pressure averaged over the toe window (the first
#   edge_length from each base corner, and edge_time), fem/toe_stress.py; its largest value is
#   quoted as the REFINED peak (toe windows rerun on refined meshes: the answer's number) or
#   the STUDY_MESH peak (the study's own mesh, median of the replicas);
# - the base contact pressure AT_NODES (not averaged: the deformed-shape and base-pressure
#   figures);
# - the stone's minimum principal stress sigma_3 per element (the renders, studies/render.py).
REFINED = "refined toe-window peak"
STUDY_MESH = "study-mesh peak"
AT_NODES = "base contact pressure at the nodes"


# s: a refined toe window longer than this did not end at its landing: its peak came as the
# column tilted on that toe, and over that time the refined runs drift from the study's run
# (docs/speed.md: refinement x2 of a 6 m column, started 0.15 to 0.35 s before its peak, peaked
# 7.15 to 8.27 MPa against the study mesh's 7.12 MPa); a landing's window is 25-35 ms
LONG_TOE_WINDOW = 0.1


def long_toe_window(summary: CrosscheckSummary) -> str:
    """The refined toe windows' length in words where it is longer than
    :data:`LONG_TOE_WINDOW` (their refinement then understates the peak's mesh uncertainty),
    else ""."""
    toe = summary.toe_stress
    if toe is None or toe.t_end - toe.t_start <= LONG_TOE_WINDOW:
        return ""
    return f"{1e3 * (toe.t_end - toe.t_start):.0f} ms"


def toe_window(summary: CrosscheckSummary) -> str:
    """What the toe stress is, in words with this run's window."""
    fem = summary.fem
    text = f"base contact pressure averaged over the first {1e3 * fem.edge_length:.3g} mm"
    if fem.edge_time:
        text += f" from the toe and over {1e3 * fem.edge_time:.3g} ms"
    return text


def write_report(out: Path) -> Path:
    """The cross-check's report: the rotations of the FEM and the rigid models, the deformed
    column, the pulse on the rigid spectrum, the collars and the toe against their limits, the
    base pressure, the renders and the Numbers table (``out/index.html``)."""
    out = Path(out)
    summary = json.loads((out / "summary.json").read_text())
    typed = load(summary)  # a key the report reads that the file lacks fails here, named
    runs = _histories(out)
    spectrum_file = out / "cases" / "spectrum" / "spectrum.json"  # pulses only
    spectrum = json.loads(spectrum_file.read_text()) if spectrum_file.exists() else None
    (out / "figures").mkdir(exist_ok=True)
    # the figures in the page's order, each appended by its function where it has something
    # to draw (collars, a plastic collar, a field file, a pulse's spectrum)
    figs: list = []
    sdof = _sdof_block(typed.outcome)
    _rotation_figure(out, typed, runs, figs)
    # the deformed column and the base pressure at one instant: its peak rotation, or where
    # the run overturned its largest rotation before overturning
    state = drawn_state(out, runs["fem"])
    _deformed_figure(out, runs["fem"], figs, state)
    if spectrum is not None:  # a record has no place on the rigid spectrum
        _spectrum_figure(out, spectrum, figs, sdof)
    _collar_stress_figure(out, typed, runs, figs)
    _collar_hinge_figure(out, typed, runs["fem"], figs)
    _toe_stress_figure(out, typed, runs["fem"], figs)
    _base_pressure_figure(out, typed, state, figs)
    renders, renders_error = _renders(out)
    return render_page(
        out,
        "crosscheck/report.html.j2",
        summary,
        f"colonna cross-check: {typed.study}",
        figs=figs,
        renders=renders,
        renders_error=renders_error,
        rows=[
            (label.replace("_{sdof}", f"_{sdof}"), key, unit)
            for label, key, unit in table(CROSSCHECK_NUMBERS, typed)
        ],
        toe={
            "refined": REFINED,
            "study_mesh": STUDY_MESH,
            "window": toe_window(typed),
            "long": long_toe_window(typed),
        },
    )


def _histories(out: Path) -> dict:
    """The history.csv of each model's run: ``fem`` (replica 0), ``rigid`` (the SDOF half
    block with collars), ``monolith`` (the whole-column SDOF) and ``multibody``."""
    return {
        name: read_csv(out / "cases" / name / "history.csv")
        for name in ("fem", "rigid", "monolith", "multibody")
    }


def _on_times(t, h: dict, key: str):
    """A history's column at the times ``t`` (NaN after its run ended)."""
    return np.interp(t, h["t"], h[key], right=np.nan)


def _rotation_figure(out: Path, summary: CrosscheckSummary, runs: dict, figs: list) -> None:
    """The rotation of each half, the FEM's (with the band of its replicas) against the rigid
    multibody model and the two SDOF models; its CSV on the FEM's times, where all ran."""
    fem_h, mb_h = runs["fem"], runs["multibody"]
    mb_names = ("left", "right") if "theta_left" in mb_h else ("column", "column")
    t = fem_h["t"]
    write_csv(
        out / "figures" / "theta.csv",
        {
            "t": t,
            "theta_fem_left": fem_h["theta_left"],
            "theta_fem_right": fem_h["theta_right"],
            "theta_multibody_left": _on_times(t, mb_h, f"theta_{mb_names[0]}"),
            "theta_multibody_right": _on_times(t, mb_h, f"theta_{mb_names[1]}"),
            "theta_rigid_half_with_collars": _on_times(t, runs["rigid"], "theta"),
            "theta_rigid_monolith": _on_times(t, runs["monolith"], "theta"),
        },
    )
    fig = Figure(figsize=(8, 3.6))
    ax = fig.subplots()
    _replica_band(ax, out, summary, t)
    ax.plot(t, fem_h["theta_left"], color="C0", lw=1.6, label="FEM, left half")
    ax.plot(t, fem_h["theta_right"], "--", color="C0", lw=1.6, label="FEM, right half")
    for h, key, style, label in (
        (mb_h, f"theta_{mb_names[0]}", ("-", "C3", 1.0), "rigid multibody, left half"),
        (mb_h, f"theta_{mb_names[1]}", ("--", "C3", 1.0), "rigid multibody, right half"),
        (runs["rigid"], "theta", ("-", "C1", 1.0), "SDOF, half block + collars (paper)"),
        (runs["monolith"], "theta", (":", "C2", 1.2), "SDOF, whole column (monolith)"),
    ):
        m = h["t"] <= t[-1]
        ax.plot(h["t"][m], h[key][m], ls=style[0], color=style[1], lw=style[2], label=label)
    ax.set_xlabel("t (s)")
    ax.set_ylabel(r"$\theta$ (rad)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    figs.append(
        figure(
            out,
            "theta",
            fig,
            "Rotation of each half: FEM against the rigid "
            "multibody model (the rigid reference) and the two SDOF models",
        )
    )


def _replica_band(ax, out: Path, summary: CrosscheckSummary, t) -> None:
    """The band the FEM replicas' rotations span, both halves (chaotic after the first
    landing); nothing for a single run."""
    replicas = _replica_histories(out / "cases" / "fem", summary.fem.replicas)
    if len(replicas) <= 1:
        return
    envelope = [
        np.vstack([_on_times(t, h, key) for h in replicas]) for key in ("theta_left", "theta_right")
    ]
    low = np.fmin(*(np.nanmin(e, axis=0) for e in envelope))
    high = np.fmax(*(np.nanmax(e, axis=0) for e in envelope))
    ax.fill_between(
        t,
        low,
        high,
        color="C0",
        alpha=0.25,
        lw=0,
        label=f"FEM, range over {len(replicas)} replicas",
    )


def _collar_stress_figure(out: Path, summary: CrosscheckSummary, runs: dict, figs: list) -> None:
    """Each collar's extreme-fibre stress against f_y over time, the FEM's (replica 0) and,
    dotted, the rigid multibody model's; nothing without collars."""
    fem_h, mb_h = runs["fem"], runs["multibody"]
    t = fem_h["t"]
    collar_cols = sorted(k for k in fem_h if k.startswith("collar_") and k.endswith("_stress"))
    if not collar_cols:
        return
    mb_cols = [k for k in collar_cols if k in mb_h]  # the rigid multibody's, where it ran
    write_csv(
        out / "figures" / "collars.csv",
        {
            "t": t,
            **{k: fem_h[k] for k in collar_cols},
            **{f"multibody_{k}": _on_times(t, mb_h, k) for k in mb_cols},
        },
    )
    fig = Figure(figsize=(9.5, 3.4))
    ax = fig.subplots()
    for j, k in enumerate(collar_cols):  # collars of one history stay apart
        ax.plot(
            t,
            fem_h[k] / 1e6,
            color=f"C{j}",
            **distinct(j, len(collar_cols)),
            label=f"FEM {k.replace('_stress', '').replace('_', ' ')}",
        )
    m = mb_h["t"] <= t[-1]
    for j, k in enumerate(mb_cols):  # thin and dark beside the FEM's: the rigid reference
        ax.plot(
            mb_h["t"][m],
            mb_h[k][m] / 1e6,
            color=f"C{j}",
            ls=(0, (1, 1.5)),
            lw=1.0,
            alpha=0.9,
            label=f"rigid multibody {k.replace('_stress', '').replace('_', ' ')}",
        )
    fy = summary.collar_fy[0]
    ax.axhline(fy / 1e6, color="k", ls="--", lw=1, label="f_y (yield stress)")
    ax.set_xlabel("t (s)")
    ax.set_ylabel("extreme-fibre stress (MPa)")
    legend_beside(ax)
    fig.tight_layout()
    figs.append(
        figure(
            out,
            "collars",
            fig,
            "Collar extreme-fibre stress against the yield stress: the FEM's "
            "(replica 0) and, dotted, the rigid multibody model's, collar by collar "
            "(collars with the same history drawn on top of each other, each "
            "with its own dashes and markers)" + _until_caption(summary.outcome),
        )
    )


def _toe_stress_figure(out: Path, summary: CrosscheckSummary, fem_h: dict, figs: list) -> None:
    """The toe stress at each toe of the study mesh (replica 0) against f_c, with the
    study-mesh peak of the Numbers table and, where the toe windows were refined, the refined
    peak that "Does the toe crush?" quotes."""
    t = fem_h["t"]
    edge_cols = [k for k in fem_h if k.startswith("edge_stress_")]
    write_csv(out / "figures" / "toe_stress.csv", {"t": t, **{k: fem_h[k] for k in edge_cols}})
    fig = Figure(figsize=(9.5, 3.4))
    ax = fig.subplots()
    for j, k in enumerate(edge_cols):
        ax.plot(
            t,
            fem_h[k] / 1e6,
            color=f"C{j}",
            **distinct(j, len(edge_cols)),
            label=k.replace("edge_stress_", "toe ").replace("_", " "),
        )
    fc = summary.stone_fc
    ax.axhline(fc / 1e6, color="k", ls="--", lw=1, label="f_c (stone strength)")
    study_mesh = summary.fem.edge_stress_max
    if study_mesh is not None:
        ax.axhline(
            study_mesh / 1e6,
            color="0.4",
            ls=":",
            lw=1.2,
            label=f"{STUDY_MESH}, median of the replicas: {study_mesh / 1e6:.4g} MPa",
        )
    toe = summary.toe_stress
    if toe:
        ax.plot(
            [toe.t_peak],
            [toe.stress / 1e6],
            ls="none",
            marker="*",
            ms=14,
            mfc="none",
            mec="C3",
            mew=1.6,
            label=f"{REFINED} (the answer's): {toe.stress / 1e6:.4g} MPa",
        )
    ax.set_yscale("symlog", linthresh=1.0)
    ax.set_xlabel("t (s)")
    ax.set_ylabel("toe stress (MPa)")
    legend_beside(ax)  # the f_c line stays in view
    fig.tight_layout()
    answer = (
        f'the star is the {REFINED} that "Does the toe crush?" quotes '
        f"({toe.ratio:.3g} f_c, toe windows rerun on refined meshes from replica "
        f"{toe.replica}), the dotted line the {STUDY_MESH} of the Numbers table"
        if toe
        else f'the answer to "Does the toe crush?" is the {STUDY_MESH}, dotted'
    )
    figs.append(
        figure(
            out,
            "toe_stress",
            fig,
            f"Toe stress against the stone strength: the {toe_window(summary)}, at each "
            f"toe of the study mesh, replica 0; {answer}" + _until_caption(summary.outcome),
        )
    )


def _base_pressure_figure(out: Path, summary: CrosscheckSummary, state: dict, figs: list) -> None:
    """The base contact pressure at the nodes (replica 0, not averaged) at rest and at the
    deformed column's instant (its peak rotation, or where the run overturned its largest
    rotation before overturning: :func:`drawn_state`)."""
    pressure = read_csv(out / "cases" / "fem" / "base_pressure.csv")
    names = [k for k in pressure if k != "t"]
    x = np.array([float(n.split("_x=")[1]) for n in names])
    row = int(np.argmin(np.abs(pressure["t"] - state["t"])))
    p_peak = np.array([pressure[n][row] for n in names])
    p_rest = np.array([pressure[n][0] for n in names])
    write_csv(
        out / "figures" / "base_pressure.csv",
        {"x": x, "pressure_at_rest": p_rest, "pressure_at_peak_rotation": p_peak},
    )
    fig = Figure(figsize=(8, 3.2))
    ax = fig.subplots()
    ax.plot(x, p_rest / 1e6, "o-", ms=3, label="at rest (gravity)")
    ax.plot(x, p_peak / 1e6, "s-", ms=3, label=f"{state['when']}, t = {pressure['t'][row]:.3f} s")
    ax.set_xlabel("x (m)")
    ax.set_ylabel(wrap(f"{AT_NODES} (MPa)", 24))  # one line was taller than the figure
    ax.legend(fontsize=8)
    fig.tight_layout()
    figs.append(
        figure(
            out,
            "base_pressure",
            fig,
            f"The {AT_NODES} (replica 0), not averaged, at rest and {state['when']}"
            f"{_state_note(state)}: the toe stress is its average over the toe window "
            f"({toe_window(summary)})",
        )
    )


def _sdof_block(outcome: dict) -> str:
    """The block of the paper's SDOF model (``half`` or ``column``: its alpha and p normalise
    the pulse), from the ``outcome``'s models."""
    for m in outcome.get("models", []):
        if m["model"].startswith("SDOF half block"):
            return m.get("alpha_block", "half")
    return "half"


def _until_caption(outcome: dict) -> str:
    """Where the FEM overturns, what a stress figure's curves stop at (the ``outcome``'s
    qualifier, :func:`colonna.studies.outcome.outcome`); empty otherwise."""
    for a in outcome.get("answers", []):
        if a.get("qualifier"):
            return f"; the stresses hold {a['qualifier']} (the FEM run stops there)"
    return ""


def _first_time(t, flags) -> float | None:
    """The first time at which ``flags`` holds (None where it never does)."""
    hit = np.flatnonzero(flags)
    return float(t[hit[0]]) if hit.size else None


def _hinge_profile_panel(
    ax_p, c: CollarSection, x, profile, peak: float, eps_y: float, top: float, k
):
    """Panel (b) of the collar hinge figure: a resultant-law collar's plastic strain along its
    span (lumped hinges), per mille, with the largest fibre strain reached, eps_u and eps_y."""
    ax_p.plot(1e3 * x, 1e3 * profile, color="C2", lw=2, label="plastic strain at the end")
    ax_p.axhline(
        1e3 * peak,
        color="C3",
        ls="-.",
        lw=1,
        label=f"largest fibre strain reached, {1e3 * peak:.3g} per mille",
    )
    ax_p.axhline(1e3 * c.eps_u, color="k", ls="--", lw=1, label="eps_u (fracture)")
    ax_p.axhline(eps_y, color="0.5", ls=":", lw=1, label="eps_y = f_y / E")
    for end in (c.hinge_length, c.span - c.hinge_length):
        ax_p.axvline(1e3 * end, color="0.8", lw=0.8)
    ax_p.set_yscale("symlog", linthresh=eps_y)  # eps_u is often far above the rest
    ax_p.yaxis.set_major_formatter(PLAIN)
    ax_p.set_ylim(0.0, top)
    ax_p.set_xlabel(f"along the collar (mm), hinges over L_p = {1e3 * c.hinge_length:.3g} mm")
    ax_p.set_ylabel("extreme-fibre strain (per mille)")
    ax_p.set_title(f"(b) collar {k}: plastic strain along it (lumped hinges)", fontsize=9)
    legend_beside(ax_p)


def _collar_hinge_figure(out: Path, summary: CrosscheckSummary, fem_h: dict, figs: list) -> None:
    """The plastic collars of the FEM run (replica 0, the unperturbed run, whose history is
    drawn): (a) the end moment against the end rotation (relative to the chord) at both ends
    of the most strained collar (the largest extreme-fibre strain), with +-M_y and +-M_p;
    (b) that collar's plastic strain along its span at the end of the run, from its axial
    plastic strain and end hinges (:func:`colonna.core.collar.hinge_strain_profile`), with
    the largest fibre strain it reached and eps_u (for a resultant-law collar only: a fibre
    section's plastic strain lives at its integration sections, which the history does not
    keep); (c) the fibre strain of every plastic collar over time, with the most strained
    one's first yield and fracture. Drawn only for plastic collars."""
    collars = summary.collars
    plastic = [
        k
        for k, c in enumerate(collars, start=1)
        if c.plastic and f"collar_{k}_moment_left" in fem_h
    ]
    if not plastic:
        return
    t = fem_h["t"]
    k, peak = _most_strained_collar(summary, fem_h, plastic)
    c = collars[k - 1]
    yielded = _first_time(t, fem_h[f"collar_{k}_utilisation"] >= 1.0)
    fractured = _first_time(t, fem_h[f"collar_{k}_fractured"] > 0.0)
    fibre = c.section == "fibre"  # a fibre section: no lumped-hinge profile to draw
    columns = {"t": t}
    for j in plastic:
        columns.update({key: fem_h[key] for key in fem_h if key.startswith(f"collar_{j}_")})
    write_csv(out / "figures" / "collar_hinge.csv", columns)
    top = 1e3 * 1.5 * max(c.eps_u, peak)
    if fibre:
        fig = Figure(figsize=(9.5, 6.2))
        ax_m, ax_t = fig.subplots(2, 1)
    else:
        x, profile = _residual_hinge_profile(out, c, fem_h, k)
        top = max(top, 1e3 * 1.5 * float(np.max(profile)))
        fig = Figure(figsize=(9.5, 9.0))
        ax_m, ax_p, ax_t = fig.subplots(3, 1)
    _moment_rotation_panel(ax_m, c, fem_h, k, fractured)
    eps_y = 1e3 * c.yield_strain
    if not fibre:
        _hinge_profile_panel(ax_p, c, x, profile, peak, eps_y, top, k)
    _fibre_strain_panel(ax_t, c, fem_h, plastic, k, (yielded, fractured), (eps_y, top))
    ax_t.set_title(
        f"({'b' if fibre else 'c'}) the plastic collars' fibre strain over time", fontsize=9
    )
    fig.tight_layout()
    figs.append(
        figure(
            out,
            "collar_hinge",
            fig,
            _collar_hinge_caption(c, k, yielded, fractured),
            data_file="figures/collar_hinge.csv"
            + ("" if fibre else ", figures/collar_hinge_profile.csv"),
        )
    )


def _most_strained_collar(
    summary: CrosscheckSummary, fem_h: dict, plastic: list
) -> tuple[int, float]:
    """The plastic collar with the largest extreme-fibre strain (a broken one first: it
    reached eps_u, whatever its history sampled before the break) and that strain: the run's
    largest over every step (the ensemble's band of replica 0) where this collar has the
    run's largest, since the history samples only the output times and after a fracture is
    0."""
    peaks = {k: float(np.max(fem_h[f"collar_{k}_fibre_strain"])) for k in plastic}
    k = max(plastic, key=lambda j: (bool(np.any(fem_h[f"collar_{j}_fractured"] > 0.0)), peaks[j]))
    peak = peaks[k]
    values = summary.fem.bands.get("collar_max_fibre_strain", {}).get("values")
    every = [float(np.max(fem_h[key])) for key in fem_h if key.endswith("_fibre_strain")]
    if values and values[0] is not None and peak >= max(every):
        peak = max(peak, float(values[0]))
    return k, peak


def _residual_hinge_profile(out: Path, c: CollarSection, fem_h: dict, k: int):
    """Collar k's plastic fibre strain along its span at the end of the run (its axial
    plastic strain and end hinges, :func:`colonna.core.collar.hinge_strain_profile`), also
    written as figures/collar_hinge_profile.csv: (x, strain)."""
    axial = float(fem_h[f"collar_{k}_plastic_strain"][-1])
    left, right = (float(fem_h[f"collar_{k}_hinge_rotation_{side}"][-1]) for side in SIDES)
    x, profile = hinge_strain_profile(c.span, c.hinge_length, c.h, axial, (left, right))
    write_csv(
        out / "figures" / "collar_hinge_profile.csv",
        {"x": x, "plastic_fibre_strain": profile},
    )
    return x, profile


def _moment_rotation_panel(
    ax_m, c: CollarSection, fem_h: dict, k: int, fractured: float | None
) -> None:
    """Panel (a) of the collar hinge figure: collar k's end moment against its end rotation,
    kN m against mrad, at both ends up to a fracture (the broken band's ends turn on carrying
    nothing), with +-M_y and +-M_p."""
    t = fem_h["t"]
    held = t < fractured if fractured is not None else np.ones(t.size, dtype=bool)
    ends = [
        (
            1e3 * fem_h[f"collar_{k}_rotation_{side}"][held],
            1e-3 * fem_h[f"collar_{k}_moment_{side}"][held],
        )
        for side in SIDES
    ]
    for j, (side, (rotation, moment)) in enumerate(zip(SIDES, ends)):
        ax_m.plot(
            rotation,
            moment,
            color=f"C{j}",
            ls=LINE_STYLES[j],
            lw=1.6 - 0.6 * j,
            label=f"{side} end",
        )
    if fractured is not None and held.any():
        ax_m.plot(
            [r[-1] for r, _ in ends],
            [m[-1] for _, m in ends],
            "X",
            ls="none",
            color="C3",
            ms=8,
            label="last output before the fracture",
        )
    for value, style, name in (
        (c.plastic_moment, ("k", "--"), "M_p = f_y t h\u00b2/4 (plastic)"),
        (c.yield_moment, ("0.5", ":"), "M_y = f_y t h\u00b2/6 (first yield)"),
    ):
        for sign in (1.0, -1.0):
            ax_m.axhline(
                sign * 1e-3 * value,
                color=style[0],
                ls=style[1],
                lw=1,
                label=f"\u00b1{name}" if sign > 0 else None,
            )
    ax_m.set_xlabel("end rotation relative to the chord (mrad)")
    ax_m.set_ylabel("end moment (kN m)")
    ax_m.set_title(f"(a) collar {k} (y = {c.y:g} m): end moment against rotation", fontsize=9)
    legend_beside(ax_m)


def _fibre_strain_panel(
    ax_t, c: CollarSection, fem_h: dict, plastic: list, k: int, times, limits
) -> None:
    """The last panel of the collar hinge figure: every plastic collar's extreme-fibre strain
    over time, per mille, against eps_u and eps_y, with collar k's first yield and fracture
    (``times``, None where it does not); ``limits``: eps_y (per mille) and the axis top."""
    eps_y, top = limits
    t = fem_h["t"]
    for j, n in enumerate(plastic):
        ax_t.plot(
            t,
            1e3 * fem_h[f"collar_{n}_fibre_strain"],
            color=f"C{j}",
            **distinct(j, len(plastic)),
            label=f"collar {n}",
        )
    ax_t.axhline(1e3 * c.eps_u, color="k", ls="--", lw=1, label="eps_u (fracture)")
    ax_t.axhline(eps_y, color="0.5", ls=":", lw=1, label="eps_y = f_y / E")
    for when, colour, name in zip(times, ("C1", "C3"), ("first yield", "fracture")):
        if when is not None:
            ax_t.axvline(when, color=colour, lw=1.2, label=f"collar {k}: {name}, t = {when:.4g} s")
    ax_t.set_yscale("symlog", linthresh=eps_y)
    ax_t.yaxis.set_major_formatter(PLAIN)
    ax_t.set_ylim(0.0, top)
    ax_t.set_xlabel("t (s)")
    ax_t.set_ylabel("extreme-fibre strain (per mille)")
    legend_beside(ax_t)


def _collar_hinge_caption(
    c: CollarSection, k: int, yielded: float | None, fractured: float | None
) -> str:
    """The collar hinge figure's caption: when collar k first yields and fractures, and what
    its panels show for its section (fibre or resultant law with lumped hinges)."""
    return (
        f"Plastic collars, FEM replica 0: collar {k}, the most strained, "
        + (f"first yields at t = {yielded:.4g} s" if yielded is not None else "does not yield")
        + (
            f" and fractures at t = {fractured:.4g} s (its fibre strain reached eps_u)"
            if fractured is not None
            else " and does not fracture"
        )
        + (
            f"; its end moment-rotation loops against M_y and M_p (a fibre section of "
            f"{c.n_fibres} layers at {c.n_sections} sections: its fibres yield "
            "from M_y, the moment nears M_p, hardening may carry it past, and the axial force "
            "lowers it), and the collars' largest surface strain over time"
            if c.section == "fibre"
            else "; its end hinges' moment-rotation loops against M_y and M_p (the hinges "
            "harden slightly past M_p, and the moment falls with the axial force on the N-M "
            "surface), and its residual plastic strain along the band: the axial plastic "
            "strain everywhere plus each hinge's plastic rotation spread over its length L_p = "
            f"{1e3 * c.hinge_length:.3g} mm"
        )
    )


def _at(get: Callable[[CrosscheckSummary], Any]) -> Ref[CrosscheckSummary]:
    """A quantity of the cross-check's summary, named by attribute (checked by the type checker
    and when this module is imported: studies.sections.Ref)."""
    return Ref(CrosscheckSummary, get)


# the Numbers table of the cross-check: (label, quantity, unit; "-" a ratio, "" words)
CROSSCHECK_NUMBERS: list[tuple[str, Ref[CrosscheckSummary], str]] = [
    (
        "FEM largest rotation, left half (not applicable where the run overturned)",
        _at(lambda s: s.peak_rotations.fem_left),
        "rad",
    ),
    (
        "FEM largest rotation, right half (not applicable where the run overturned)",
        _at(lambda s: s.peak_rotations.fem_right),
        "rad",
    ),
    (
        "multibody largest rotation, left half (not applicable where the run overturned)",
        _at(lambda s: s.peak_rotations.multibody_left),
        "rad",
    ),
    (
        "multibody largest rotation, right half (not applicable where the run overturned)",
        _at(lambda s: s.peak_rotations.multibody_right),
        "rad",
    ),
    ("multibody mode", _at(lambda s: s.rigid_multibody.mode), ""),
    ("multibody status", _at(lambda s: s.rigid_multibody.status), ""),
    ("multibody crack slip max", _at(lambda s: s.rigid_multibody.max_abs_crack_slip), "mm"),
    (
        "multibody collar utilisation max, sigma / f_y",
        _at(lambda s: s.rigid_multibody.collar_max_utilisation),
        "-",
    ),
    (
        "multibody collar ductility demand, largest fibre strain / (f_y / E) "
        f"(limit {DUCTILITY_LIMIT:g}: EN 1993-1-1 eps_u >= 15 eps_y)",
        _at(lambda s: s.rigid_multibody.collar_ductility_demand),
        "-",
    ),
    (
        "multibody first collar fracture (n/a: the collars hold)",
        _at(lambda s: s.rigid_multibody.collar_fracture_time),
        "s",
    ),
    (
        "multibody energy balance error (max, relative)",
        _at(lambda s: s.rigid_multibody.energy_error_max),
        "-",
    ),
    ("multibody wall time", _at(lambda s: s.rigid_multibody.wall_seconds), "s"),
    (
        "SDOF peak rotation, half + collars (n/a where it overturns)",
        _at(lambda s: s.rigid.max_abs_theta),
        "rad",
    ),
    (
        "SDOF overturning mode, half + collars (safe: it does not overturn)",
        _at(lambda s: s.rigid.mode),
        "",
    ),
    (
        "SDOF collar state, half + collars (elastic collars: yielded means sigma reached f_y)",
        _at(lambda s: s.rigid.collar_state),
        "",
    ),
    (
        "SDOF peak rotation, whole column (n/a where it overturns)",
        _at(lambda s: s.rigid_monolith.max_abs_theta),
        "rad",
    ),
    (
        "SDOF collars: elastic springs; where one passed f_y, what that leaves out",
        _at(lambda s: s.rigid.collar_note),
        "",
    ),
    ("halves rock as one block", _at(lambda s: s.verdict.rocks_as_one_block), ""),
    ("FEM status", _at(lambda s: s.fem.status), ""),
    (
        f"toe stress, {REFINED} (the answer's; base contact pressure averaged over the toe window)",
        _at(lambda s: s.toe_stress and s.toe_stress.stress),
        "MPa",
    ),
    (
        f"toe stress, {STUDY_MESH} (base contact pressure averaged over the toe window; median "
        "of the replicas)",
        _at(lambda s: s.fem.edge_stress_max),
        "MPa",
    ),
    (
        "toe window: length from the toe over which the toe stress is averaged",
        _at(lambda s: s.fem.edge_length),
        "mm",
    ),
    ("toe window: time over which the toe stress is averaged", _at(lambda s: s.fem.edge_time), "s"),
    ("energy balance error (max, relative)", _at(lambda s: s.fem.energy_error_max), "-"),
    ("time step", _at(lambda s: s.fem.dt), "s"),
    (
        "stable-step reduction by contact",
        _at(lambda s: s.fem.stable_step_reduction_by_contact),
        "-",
    ),
    ("steps", _at(lambda s: s.fem.steps), "-"),
    ("dofs", _at(lambda s: s.fem.dofs), "-"),
    ("FEM wall time", _at(lambda s: s.fem.wall_seconds), "s"),
    ("pulse Omega/p_{sdof} (n/a for a record)", _at(lambda s: s.pulse.omega_ratio), "-"),
    ("peak ground acceleration", _at(lambda s: s.pulse.amplitude), "m/s^2"),
    (
        "pulse a_p / a_uplift (a_uplift = g tan alpha_{sdof} (1 + lambda), lambda = top load / "
        "weight of the SDOF block)",
        _at(lambda s: s.pulse.amplitude_ratio),
        "-",
    ),
    ("top load on the capital", _at(lambda s: s.fem.top_load), "kN"),
    ("collar plastic strain max, FEM", _at(lambda s: s.fem.collar_max_plastic_strain), "-"),
    ("collar plastic work, FEM", _at(lambda s: s.fem.collar_plastic_work), "J"),
    (
        "collar extreme-fibre strain max, FEM: a fibre section's surface strain (resultant "
        "law: axial + bending + hinge rotation over L_p; median of the replicas)",
        _at(lambda s: s.fem.collar_max_fibre_strain),
        "per mille",
    ),
    (
        "collar ductility demand, FEM: largest fibre strain / (f_y / E) "
        f"(limit {DUCTILITY_LIMIT:g}: EN 1993-1-1 eps_u >= 15 eps_y)",
        _at(lambda s: s.fem.collar_ductility_demand),
        "-",
    ),
    (
        "first collar fracture, FEM (median over the replicas; n/a: the collars hold in half "
        "of them or more)",
        _at(lambda s: s.fem.collar_fracture_time),
        "s",
    ),
    (
        "FEM replicas in which a collar fractured",
        _at(lambda s: s.fem.collar_fractured_replicas),
        "-",
    ),
    ("crack slip left at the end of the run, FEM", _at(lambda s: s.fem.crack_slip_residual), "mm"),
    (
        "static base reaction, FEM: weight + top load",
        _at(lambda s: s.fem.base_reaction_static),
        "kN",
    ),
    # contact diagnostics (the run's own, replica 0): a chattering crack or an unresolved toe
    # is seen here, not guessed (n/a: a solid column has no crack)
    (
        "crack normal force, FEM: mean over the output samples",
        _at(lambda s: s.fem.crack_normal_force_mean),
        "kN",
    ),
    (
        "crack normal force, FEM: mean over the samples with the halves in contact",
        _at(lambda s: s.fem.crack_normal_force_mean_closed),
        "kN",
    ),
    ("crack normal force, FEM: largest sample", _at(lambda s: s.fem.crack_normal_force_max), "kN"),
    (
        "fraction of the output samples with the crack faces in contact, FEM",
        _at(lambda s: s.fem.crack_closed_fraction),
        "-",
    ),
    ("friction work along the crack, FEM", _at(lambda s: s.fem.friction_work_crack), "J"),
    ("friction work at the base, FEM", _at(lambda s: s.fem.friction_work_base), "J"),
    ("contact damping work (base and crack), FEM", _at(lambda s: s.fem.contact_damping_work), "J"),
    (
        "largest elastic energy in the contact penalty springs, FEM",
        _at(lambda s: s.fem.contact_penalty_energy_max),
        "J",
    ),
    (
        "toe contact length, FEM, at the output sample of the largest toe force: the base nodes "
        "in contact from the toe, their tributary lengths (one node: the zone is not resolved)",
        _at(lambda s: s.fem.toe_contact_length),
        "mm",
    ),
    (
        "base nodes in contact from the toe, FEM, at the output sample of the largest toe force",
        _at(lambda s: s.fem.toe_contact_nodes),
        "-",
    ),
    ("base node spacing at the toe, FEM", _at(lambda s: s.fem.toe_node_spacing), "mm"),
    # the bed and the resolved toe (issue 38)
    ("bed stiffness per unit area k (held on every mesh)", _at(lambda s: s.bed.stiffness), "GPa/m"),
    ("bed stiffness, softest of its range", _at(lambda s: s.bed.low), "GPa/m"),
    ("bed stiffness, stiffest of its range", _at(lambda s: s.bed.high), "GPa/m"),
    ("bed: where its stiffness comes from", _at(lambda s: s.bed.source), ""),
    (
        "Winkler contact length at half the rocking body's slenderness, "
        "c = sqrt(2 W / (k t theta))",
        _at(lambda s: s.bed.contact_length),
        "mm",
    ),
    ("toe element size that resolves it (c / 4)", _at(lambda s: s.bed.toe_size), "mm"),
    (
        "Winkler toe pressure at half the rocking body's slenderness, 2 W / (t c)",
        _at(lambda s: s.bed.pressure),
        "MPa",
    ),
    ("the same, softest bed of the range", _at(lambda s: s.bed.pressure_low), "MPa"),
    ("the same, stiffest bed of the range", _at(lambda s: s.bed.pressure_high), "MPa"),
    (
        "largest sampled nodal base pressure, FEM (resolved only with several nodes across c)",
        _at(lambda s: s.fem.toe_pressure_max),
        "MPa",
    ),
    (
        "Winkler toe pressure of the FEM's sampled base force and tilt",
        _at(lambda s: s.fem.toe_pressure_winkler),
        "MPa",
    ),
    (
        "base force of the toe's body at the output sample of the largest toe force, FEM",
        _at(lambda s: s.fem.toe_resultant),
        "kN",
    ),
    (
        "its point of application: distance from the toe, FEM",
        _at(lambda s: s.fem.toe_resultant_offset),
        "mm",
    ),
]


def _replica_histories(directory: Path, replicas: int) -> list[dict]:
    """The history.csv of each replica of the FEM ensemble (replica 0 is the run's own)."""
    paths = [directory / "history.csv"] + [
        directory / "replicas" / str(r) / "history.csv" for r in range(1, replicas)
    ]
    return [read_csv(p) for p in paths if p.is_file()]


def _renders(out: Path) -> tuple[list, str]:
    """pyvista renders of the deformed halves coloured by the minimum principal stress (and
    why there are none, if rendering failed)."""
    try:
        from ..render import render_snapshots

        images = render_snapshots(out)
    except Exception as exc:  # rendering is a picture, never a reason to lose the report
        return [], str(exc)
    return [image(out / "figures" / name, caption) for name, caption in images], ""


# the instant the deformed-column and base-pressure figures draw (drawn_state): the trial's
# "FEM at peak rotation" was the 45-degree overturning stop, drawn as if it were a result
PEAK = "at peak rotation"
BEFORE = "at its largest rotation before overturning"
STOP = "at the overturning stop"


def _fem_status(out: Path) -> dict:
    """The FEM run's own summary (replica 0: whether it overturned, its stop in words)."""
    try:
        found = json.loads((out / "cases" / "fem" / "summary.json").read_text())
    except (OSError, ValueError):
        return {}
    return found if isinstance(found, dict) else {}


def _frames(series: Path) -> list[tuple[float, np.ndarray]]:
    """The saved field frames of a FEM run (fields.xdmf): (t, displacement (n, 2)) each."""
    import meshio

    with meshio.xdmf.TimeSeriesReader(series) as reader:
        reader.read_points_cells()
        frames = []
        for k in range(reader.num_steps):
            t, point_data, _ = reader.read_data(k)
            frames.append((float(t), np.asarray(point_data["displacement"])[:, :2]))
    return frames


def drawn_state(out: Path, fem_h: dict) -> dict:
    """The FEM state (replica 0) that the deformed-column and base-pressure figures draw:
    ``t``, ``when`` (PEAK, BEFORE or STOP) and ``displacement`` (a saved frame's, (n, 2), or
    None: fields_peak_rotation.vtu's), with ``swing``, ``stop`` and ``spacing`` (s) for BEFORE.

    A run that did not overturn: its peak rotation. A run that overturned stopped at its largest
    rotation (its overturning rule: past its toe moving outward, or a half past 45 degrees), no
    state to read: the saved frame (fields.xdmf) of the largest rotation before the swing in
    which it overturned, that swing starting at the last output with the column upright or
    tilted the other way. Where there is no such swing (it overturned in its first, or every
    earlier rotation is below 1e-4 of the stop's: the stone's elastic sway), the stop, said so."""
    t = fem_h["t"]
    theta = np.maximum(np.abs(fem_h["theta_left"]), np.abs(fem_h["theta_right"]))
    peak = {"t": float(t[int(np.argmax(theta))]), "when": PEAK, "displacement": None}
    if not _fem_status(out).get("overturned"):
        return peak
    stop = dict(peak, when=STOP)
    tilt = fem_h["theta_left"] + fem_h["theta_right"]
    back = np.flatnonzero(np.sign(tilt[-1]) * tilt <= 0.0)
    series = out / "cases" / "fem" / "fields.xdmf"
    if not back.size or not series.is_file():
        return stop
    swing = float(t[back[-1]])  # the overturning swing starts after this output
    frames = _frames(series)
    times = np.array([f[0] for f in frames])
    before = np.flatnonzero(times <= swing)
    if not before.size:
        return stop
    rotation = np.interp(times[before], t, theta)
    if rotation.max() < 1e-4 * float(theta.max()):
        return stop
    k = int(before[np.argmax(rotation)])
    return {
        "t": float(times[k]),
        "when": BEFORE,
        "displacement": frames[k][1],
        "swing": swing,
        "stop": float(t[-1]),
        "spacing": float(np.median(np.diff(times))) if times.size > 1 else 0.0,
    }


def _state_note(state: dict) -> str:
    """What the drawn instant is, for a caption (empty at a peak rotation)."""
    if state["when"] == BEFORE:
        return (
            f" (t = {state['t']:.4g} s: the saved field frame, one every "
            f"{state['spacing']:.3g} s, of the largest rotation before the swing from "
            f"t = {state['swing']:.4g} s in which the column overturns; the run stops at "
            f"t = {state['stop']:.4g} s by its overturning rule, a stopping convention, not "
            "a state to read)"
        )
    if state["when"] == STOP:
        return (
            f" (t = {state['t']:.4g} s: the column overturned in its first swing, and this is "
            "where the run stopped by its overturning rule, a stopping convention, not a peak)"
        )
    return ""


def _elastic_part(X: np.ndarray, quads: np.ndarray, cell_body: np.ndarray, u: np.ndarray):
    """``u`` less each body's best-fit rigid motion (centroid and rotation weighted by a quarter
    of each element's area at its nodes): the elastic deformation, as the solver splits its own
    snapshots (fem.output.elastic_displacement, with its lumped masses)."""
    p = X[quads]
    area = 0.5 * np.abs(
        np.sum(
            p[..., 0] * np.roll(p[..., 1], -1, axis=1) - np.roll(p[..., 0], -1, axis=1) * p[..., 1],
            axis=1,
        )
    )
    weight = np.zeros(len(X))
    np.add.at(weight, quads, np.repeat(area[:, None] / 4.0, 4, axis=1))
    elastic = np.zeros_like(u)
    for b in np.unique(cell_body):
        on = np.zeros(len(X), dtype=bool)
        on[quads[cell_body == b]] = True
        w = weight[on] / weight[on].sum()
        P = X[on] - w @ X[on]
        Q = X[on] + u[on] - w @ (X[on] + u[on])
        phi = np.arctan2(
            np.sum(w * (P[:, 0] * Q[:, 1] - P[:, 1] * Q[:, 0])), np.sum(w * np.sum(P * Q, axis=1))
        )
        c, s = np.cos(phi), np.sin(phi)
        elastic[on] = Q - P @ np.array([[c, s], [-s, c]])
    return elastic


def _magnification(largest: float, height: float) -> float:
    """A round factor (1, 2 or 5 x 10^k) that draws the largest elastic displacement at about
    2 % of the column height."""
    if largest <= 0.0:
        return 1.0
    raw = 0.02 * height / largest
    k = math.floor(math.log10(raw))
    return max(1.0, max(f * 10.0**k for f in (1.0, 2.0, 5.0) if f * 10.0**k <= raw))


def _deformed_figure(out: Path, fem_h: dict, figs: list, state: dict | None = None) -> None:
    """The FEM column at the instant of ``state`` (:func:`drawn_state`: its peak rotation, or
    where it overturned its largest rotation before overturning), drawn in the ground frame:
    each half's rigid motion true to scale, its elastic deformation (the field file's
    ``elastic_displacement``, split off by the solver; :func:`_elastic_part` of a saved frame)
    magnified by a factor stated on the figure; the collars between their attachment nodes
    (``collar_end``); the base contact pressure under the toes at that instant."""
    import meshio

    fem = out / "cases" / "fem"
    vtu = fem / "fields_peak_rotation.vtu"
    if not vtu.exists():
        return
    state = drawn_state(out, fem_h) if state is None else state
    m = meshio.read(vtu)
    X = m.points[:, :2]
    collar_end = m.point_data["collar_end"].astype(int)
    quads = np.vstack([c.data for c in m.cells if c.type == "quad"])
    cell_body = np.concatenate(m.cell_data["body"]).astype(int)
    if state["displacement"] is None:
        u = m.point_data["displacement"][:, :2]
        elastic = m.point_data["elastic_displacement"][:, :2]
    else:
        u = state["displacement"]
        elastic = _elastic_part(X, quads, cell_body, u)
    height = float(np.ptp(X[:, 1]))
    factor = _magnification(float(np.abs(elastic).max()), height)
    drawn = X + u + (factor - 1.0) * elastic
    t_drawn = state["t"]
    fig = Figure(figsize=(7.0, 6.4))
    ax = fig.subplots()
    handles = _draw_column(ax, X, drawn, quads, cell_body, collar_end)
    handles += _draw_base_pressure(ax, fem / "base_pressure.csv", t_drawn, height)
    ax.axhline(0.0, color="k", lw=0.8)
    ax.set_aspect("equal")
    ax.set_anchor("W")  # the narrow column to the left, its legend's room to the right
    # a column is narrow: few x ticks, so that their labels never run into each other
    ax.xaxis.set_major_locator(MaxNLocator(nbins=3, steps=[1, 2, 2.5, 5, 10]))
    ax.xaxis.set_major_formatter(PLAIN)
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    # what is drawn and at what scale, on the figure itself: from the axes' left edge, so that
    # a narrow column's title does not run off the figure
    ax.set_title(
        f"FEM {state['when']}, t = {t_drawn:.3f} s\nrigid motion true to scale,\n"
        f"elastic deformation x{factor:g}",
        loc="left",
        fontsize=9,
    )
    ax.legend(handles=handles, fontsize=8, loc="upper left", bbox_to_anchor=(1.02, 1.0))
    fig.tight_layout()
    figs.append(
        figure(
            out,
            "deformed",
            fig,
            f"The FEM column {state['when']}{_state_note(state)}: each half's rigid motion "
            "true to scale, its elastic deformation magnified "
            f"x{factor:g}; the crack is the gap between the halves; collars in red; "
            f"under the base, the {AT_NODES} at that instant (not averaged, and not to the "
            "length scale: the toe stress of the answers is its average over the toe window)",
        )
    )


def _draw_column(ax, X, drawn, quads, cell_body, collar_end) -> list[Artist]:
    """The deformed column's halves (``drawn``: the nodes' drawn positions) as filled
    elements, its outline at rest (``X``) and its collars between their attachment nodes;
    their legend handles."""
    height = float(np.ptp(X[:, 1]))
    handles: list[Artist] = []
    for b in np.unique(cell_body):
        polys = drawn[quads[cell_body == b]]
        colour = ("C0", "C1")[min(int(b), 1)]
        ax.add_collection(
            PolyCollection(polys, facecolors=colour, edgecolors="w", linewidths=0.2, alpha=0.6)
        )
        handles.append(
            Patch(
                facecolor=colour,
                alpha=0.6,
                label=("left half", "right half")[min(int(b), 1)]
                if cell_body.max() > 0
                else "column",
            )
        )
    outline = np.array(
        [
            [X[:, 0].min(), 0.0],
            [X[:, 0].max(), 0.0],
            [X[:, 0].max(), height],
            [X[:, 0].min(), height],
            [X[:, 0].min(), 0.0],
        ]
    )
    handles += ax.plot(outline[:, 0], outline[:, 1], color="0.6", ls=":", lw=1.0, label="at rest")
    for number in range(1, collar_end.max() + 1):
        ends = np.flatnonzero(collar_end == number)
        ax.plot(drawn[ends, 0], drawn[ends, 1], color="C3", lw=2.0)
    if collar_end.max() > 0:
        handles.append(Line2D([], [], color="C3", lw=2.0, label="collars"))
    return handles


def _draw_base_pressure(ax, pressure_file: Path, t_drawn: float, height: float) -> list[Artist]:
    """The base contact pressure at the nodes at the output nearest ``t_drawn``, drawn below
    the base at 12 % of the column height for its largest value; its legend handle (none
    without base_pressure.csv)."""
    if not pressure_file.exists():
        return []
    with open(pressure_file) as fh:
        names = fh.readline().strip().split(",")[1:]
        rows = np.loadtxt(fh, delimiter=",", ndmin=2)
    row = rows[int(np.argmin(np.abs(rows[:, 0] - t_drawn)))]
    xs = np.array([float(n.split("=")[1]) for n in names])
    pressure = row[1:] / 1e6
    scale = 0.12 * height / max(pressure.max(), 1e-12)
    order = np.argsort(xs, kind="stable")
    ax.fill_between(xs[order], 0.0, -scale * pressure[order], color="k", alpha=0.35, step=None)
    return [
        Patch(
            facecolor="k", alpha=0.35, label=wrap(f"{AT_NODES} (max {pressure.max():.3g} MPa)", 28)
        )
    ]


def _spectrum_figure(out: Path, spectrum: dict, figs: list, block: str = "half") -> None:
    """The study's pulse on the rigid overturning spectra: the SDOF half block with collars as a
    map and, where spectrum.json holds it (key ``multibody``), the rigid multibody model, the
    verdict's rigid reference, as a marker at each pulse of its coarser grid."""
    from matplotlib.colors import BoundaryNorm, ListedColormap

    from ...rigid.plotting import MODE_COLOURS, MODE_LABELS, MarkerStyle, grid_markers

    codes = np.array([[MODE_CODES[c] for c in row] for row in spectrum["mode"]])
    w = np.array(spectrum["omega_ratios"])
    a = np.array(spectrum["amplitude_ratios"])
    write_csv(
        out / "figures" / "spectrum.csv",
        {
            "omega_ratio": np.tile(w, a.size),
            "amplitude_ratio": np.repeat(a, w.size),
            "mode_code": codes.ravel(),
        },
    )
    mb = spectrum.get("multibody")  # none in a spectrum saved before it was computed
    fig = Figure(figsize=(9.5, 4.4))
    ax = fig.subplots()
    ax.pcolormesh(
        w,
        a,
        codes,
        cmap=ListedColormap(MODE_COLOURS),
        norm=BoundaryNorm([-0.5, 0.5, 1.5, 2.5], 3),
        shading="nearest",
    )
    # the legend lists what is drawn: the modes present (a marker per pulse of a coarse grid),
    # the yield line if any, the multibody outcomes, the pulse
    handles = grid_markers(
        ax, w, a, codes, MarkerStyle(labels=[f"SDOF: {m}" for m in MODE_LABELS]), size=12
    )
    handles = handles or [
        Patch(facecolor=MODE_COLOURS[k], edgecolor="0.5", label=f"SDOF: {MODE_LABELS[k]}")
        for k in range(3)
        if np.any(codes == k)
    ]
    yields = np.array(spectrum.get("collar_yields", [[0]]), dtype=float)
    if yields.min() < 0.5 < yields.max():
        ax.contour(w, a, yields, levels=[0.5], colors="k", linewidths=0.8)
        handles.append(Line2D([], [], color="k", lw=0.8, label="SDOF: a collar reaches f_y above"))
    if mb is not None:
        handles += _multibody_markers(out, ax, mb)
    handles += ax.plot(
        spectrum["study_omega_ratio"],
        spectrum["study_amplitude_ratio"],
        ls="",
        marker="*",
        markersize=22,
        markerfacecolor="none",
        markeredgecolor="r",
        markeredgewidth=1.6,
        zorder=4,
        label="this study's pulse",
    )
    ax.set_xlabel(rf"$\Omega/p_\mathrm{{{block}}}$ (-)")
    ax.set_ylabel(rf"$a_p/(g\tan\alpha_\mathrm{{{block}}})$ (-)")
    legend_beside(ax, handles=handles)
    ax.set_title(
        "Rigid overturning spectra: SDOF half block with collars (map)"
        + (", rigid multibody (markers)" if mb is not None else ""),
        fontsize=10,
    )
    fig.tight_layout()
    figs.append(
        figure(
            out,
            "spectrum",
            fig,
            SPECTRUM_CAPTIONS[mb is not None],
            data_file="figures/spectrum*.csv" if mb is not None else "",
        )
    )


def _multibody_markers(out: Path, ax, mb: dict) -> list[Artist]:
    """The rigid multibody model's outcome at each pulse of its coarse grid (spectrum.json's
    ``multibody``) as a marker, also written as figures/spectrum_multibody.csv; the legend
    handles."""
    from ...rigid.plotting import MODE_LABELS, MarkerStyle, grid_markers

    mb_codes = np.array([[MODE_CODES[c] for c in row] for row in mb["mode"]])
    mb_w, mb_a = np.array(mb["omega_ratios"]), np.array(mb["amplitude_ratios"])
    columns = {
        "omega_ratio": np.tile(mb_w, mb_a.size),
        "amplitude_ratio": np.repeat(mb_a, mb_w.size),
        "mode_code": mb_codes.ravel(),
    }
    if "collar_yields" in mb:
        columns["collar_yield"] = np.array(mb["collar_yields"], dtype=int).ravel()
    write_csv(out / "figures" / "spectrum_multibody.csv", columns)
    return grid_markers(
        ax,
        mb_w,
        mb_a,
        mb_codes,
        MarkerStyle(labels=[f"rigid multibody: {m}" for m in MODE_LABELS]),
        always=True,
        size=60,
    )


# the spectrum figure's caption, with (True) and without (False) the multibody's markers
SPECTRUM_CAPTIONS = {
    True: "The study's pulse (red star) on the rigid overturning spectra. The verdict "
    "relies on the rigid multibody model (two rigid halves, ground and crack "
    "contact with friction, collars as frames): its outcome at each pulse of a "
    "coarser grid through the study's pulse is a marker. The map beneath is the "
    "paper's SDOF half block with collars, a simplification of it, with the line "
    "above which a collar reaches its yield stress; where the two differ, the "
    "markers are the rigid reference",
    False: "The study's pulse on the rigid overturning spectrum of the SDOF half block "
    "with collars: outcome of each pulse (legend), and where a collar reaches its "
    "yield stress. The verdict relies on the rigid multibody model, whose "
    "spectrum this run does not hold; the SDOF map is a simplification of it",
}

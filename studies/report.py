"""What the HTML reports of every study kind share: the number format, the inputs section, the
figure helpers and the Jinja2 environment. Each kind's report (its figures, its tables and its
template ``report.html.j2``) is in its package (``studies/<kind>/report.py``); the pages extend
``studies/templates/base.html.j2``. Presentation only: every number comes from ``summary.json``
and every curve from the CSV files of the run directory.

Each figure's data is written next to it as CSV. Numbers in the HTML carry a ``data-key``
attribute naming their place in summary.json (dotted path), so a test can check that the report
says what the data say. Figures drawn here are inlined as SVG with their text kept as text, and
each ``<figure>`` lists its legend entries in ``data-legend``, so a browser test can check that
every entry is drawn; a PNG copy of each goes to ``figures/``.
"""

from __future__ import annotations

import base64
import functools
import io
import json
import math
from pathlib import Path

import jinja2
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from markupsafe import Markup, escape  # noqa: E402
from matplotlib.artist import Artist  # noqa: E402
from matplotlib.collections import PolyCollection  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402
from matplotlib.patches import Patch  # noqa: E402
from matplotlib.ticker import FuncFormatter  # noqa: E402

from ..core.constants import DUCTILITY_LIMIT  # noqa: E402
from .kinds import KINDS  # noqa: E402
from .output import read_csv, write_csv  # noqa: E402
from .units import DISPLAY_UNITS, input_unit  # noqa: E402

# the shared pieces (base.html.j2, macros.html.j2) in studies/templates; each kind's page in its
# package, by its path from here ("crosscheck/report.html.j2")
TEMPLATES = jinja2.Environment(
    loader=jinja2.FileSystemLoader([Path(__file__).with_name("templates"), Path(__file__).parent]),
    autoescape=True,
    undefined=jinja2.StrictUndefined,
    trim_blocks=True,
    lstrip_blocks=True,
)


def fmt(value, digits: int = 4) -> str:
    """The report's number format (the consistency test uses the same function)."""
    if value is None:
        return "n/a"
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, str):
        return value
    if isinstance(value, (int,)):
        return str(value)
    value = float(value)
    if not math.isfinite(value):
        return "n/a"
    return f"{value:.{digits}g}"


def get(summary: dict, dotted: str):
    node = summary
    for part in dotted.split("."):
        node = node[int(part)] if isinstance(node, list) else node[part]
    return node


def num(
    summary: dict, dotted: str, digits: int = 4, unit: str = "", show_unit: bool = True
) -> Markup:
    """summary.json's value at a dotted key, in a span naming the key, then its unit. A unit of
    DISPLAY_UNITS shows the SI value scaled (MPa from Pa, kN from N, mm from m), the span
    carrying the factor in ``data-scale``."""
    value = get(summary, dotted)
    number = not isinstance(value, (bool, str)) and value is not None
    scale = DISPLAY_UNITS.get(unit) if number else None
    if scale is not None:
        shown = Markup('<span data-key="{}" data-scale="{}">{}</span>').format(
            dotted, f"{scale:g}", fmt(float(value) * scale, digits)
        )
    else:
        shown = Markup('<span data-key="{}">{}</span>').format(dotted, fmt(value, digits))
    if unit and number and show_unit:
        shown += Markup("&nbsp;") + escape(unit)
    return shown


# the tables of a study file shown in the inputs section, in the file's order; then the tables
# of its kind's own (its registry entry's ``tables``, studies/kinds.py)
INPUT_TABLES = ("study", "column", "stone", "collar", "ground", "contact", "mesh", "run", "rigid")


def _input_value(value, factor: float) -> str:
    if isinstance(value, list):
        return ", ".join(_input_value(v, factor) for v in value)
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        return fmt(value * factor, 4)
    return fmt(value)


def input_tables(inputs: dict) -> list[dict]:
    """The study's inputs (inputs.json: the validated file, every default filled in) as tables:
    one per [table], its keys with their values in the units an engineer reads (from the
    schema's SI units), a column per collar. Keys without a value (not given, no default) are
    left out."""
    from . import schema

    kind = KINDS.get(inputs["study"]["kind"])
    tables = []
    for name in INPUT_TABLES + (kind.tables if kind is not None else ()):
        if inputs.get(name) in (None, [], {}):
            continue
        model = schema.table_model(name)
        entries = inputs[name] if isinstance(inputs[name], list) else [inputs[name]]
        rows = []
        for key in model.model_fields:
            values = [entry.get(key) for entry in entries]
            if all(v is None for v in values):
                continue
            unit, factor = input_unit(name, key)
            rows.append(
                {
                    "key": key,
                    "path": f"{name}.{key}",
                    "unit": unit,
                    "values": [_input_value(v, factor) for v in values],
                }
            )
        tables.append({"name": name, "rows": rows, "columns": len(entries)})
    return tables


def _inputs(out: Path) -> dict | None:
    """inputs.json with its tables, or None where the study's inputs are not on record."""
    path = Path(out) / "inputs.json"
    if not path.is_file():
        return None
    inputs = json.loads(path.read_text())
    return dict(inputs, tables=input_tables(inputs))


def _ground_figure(out: Path) -> dict | None:
    """The ground motion the study applied (ground_motion.csv), horizontal and vertical."""
    path = Path(out) / "ground_motion.csv"
    if not path.is_file():
        return None
    g = read_csv(path)
    fig, ax = plt.subplots(figsize=(8, 2.6))
    ax.plot(g["t"], g["horizontal_acceleration"], color="C0", label="horizontal")
    if np.any(g["vertical_acceleration"] != 0.0):
        ax.plot(g["t"], g["vertical_acceleration"], "--", color="C3", label="vertical (up +)")
    ax.axhline(0.0, color="0.6", lw=0.6)
    ax.set_xlabel("t (s)")
    ax.set_ylabel("ground acceleration (m/s$^2$)")
    legend_beside(ax)
    fig.tight_layout()
    return figure(
        out,
        "ground_motion",
        fig,
        "The ground motion applied: horizontal and vertical accelerations",
        data_file="ground_motion.csv",
    )


def render_page(out: Path, template: str, summary: dict, title: str, **context) -> Path:
    """Fill a template with the summary (``s``), ``num`` and the figures; write index.html."""
    text = TEMPLATES.get_template(template).render(
        s=summary,
        title=title,
        num=functools.partial(num, summary),
        inputs=_inputs(out),
        ground=_ground_figure(out),
        **context,
    )
    return _write_page(out, text)


def _legend_entries(fig) -> list[str]:
    """The texts of every legend of the figure (figure legends and axes legends)."""
    legends = list(fig.legends) + [ax.get_legend() for ax in fig.axes if ax.get_legend()]
    return [t.get_text() for legend in legends for t in legend.get_texts()]


def figure(out: Path, name: str, fig, caption: str, data_file: str | None = "") -> dict:
    """A matplotlib figure for a template: inline SVG (text kept as text), its legend entries,
    and a PNG copy in figures/ (data: figures/NAME.csv unless told otherwise)."""
    (out / "figures").mkdir(exist_ok=True)
    fig.savefig(out / "figures" / f"{name}.png", dpi=110)
    buf = io.StringIO()
    with plt.rc_context({"svg.fonttype": "none", "svg.hashsalt": name}):
        fig.savefig(buf, format="svg")
    legend = _legend_entries(fig)
    plt.close(fig)
    svg = buf.getvalue()
    svg = svg[svg.index("<svg") :]
    return {
        "name": name,
        "caption": caption,
        "svg": Markup(svg),
        "legend": legend,
        "data_file": f"figures/{name}.csv" if data_file == "" else data_file,
    }


def image(path: Path, caption: str, name: str | None = None) -> dict:
    """An image file (PNG or GIF) for a template, embedded as data."""
    path = Path(path)
    mime = "image/gif" if path.suffix == ".gif" else "image/png"
    return {
        "name": name or path.stem,
        "caption": caption,
        "svg": None,
        "legend": [],
        "mime": mime,
        "data": base64.b64encode(path.read_bytes()).decode(),
        "data_file": None,
    }


SIDES = ("left", "right")  # a collar's ends in the FEM history
PLAIN = FuncFormatter(lambda value, _: f"{value:g}")  # tick labels as numbers, not powers

# curves that may lie on top of each other (collars with one history, ...): each its own
# dashes, width and markers, so that none hides another
LINE_STYLES = ("-", "--", "-.", ":")
MARKERS = ("o", "s", "^", "v", "D", "P", "X")
MARK_EVERY = 0.12  # markers apart, as a fraction of the axes diagonal


def distinct(k: int, n: int) -> dict:
    """Plot keywords of curve k of n that may coincide: dashes cycling, the width narrowing
    from the first drawn (underneath) to the last, markers at staggered places."""
    return {
        "ls": LINE_STYLES[k % len(LINE_STYLES)],
        "lw": 2.6 - 1.6 * k / max(n - 1, 1),
        "marker": MARKERS[k % len(MARKERS)],
        "markersize": 4.5,
        "markevery": (MARK_EVERY * k / max(n, 1), MARK_EVERY),
    }


def legend_beside(ax, **kw):
    """The axes' legend to its right, never over a curve or a limit line (tight_layout makes
    room for it)."""
    return ax.legend(
        fontsize=8, loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0.0, **kw
    )


def write_crosscheck_report(out: Path) -> Path:
    out = Path(out)
    summary = json.loads((out / "summary.json").read_text())
    fem_h = read_csv(out / "cases" / "fem" / "history.csv")
    rigid_h = read_csv(out / "cases" / "rigid" / "history.csv")
    mono_h = read_csv(out / "cases" / "monolith" / "history.csv")
    mb_h = read_csv(out / "cases" / "multibody" / "history.csv")
    mb_names = ("left", "right") if "theta_left" in mb_h else ("column", "column")
    spectrum_file = out / "cases" / "spectrum" / "spectrum.json"  # pulses only
    spectrum = json.loads(spectrum_file.read_text()) if spectrum_file.exists() else None
    (out / "figures").mkdir(exist_ok=True)
    figs = []

    # 1. rotations, FEM vs the rigid models (the CSV on the FEM's times, where all ran)
    t = fem_h["t"]

    def on_fem_times(h, key):
        return np.interp(t, h["t"], h[key], right=np.nan)

    write_csv(
        out / "figures" / "theta.csv",
        {
            "t": t,
            "theta_fem_left": fem_h["theta_left"],
            "theta_fem_right": fem_h["theta_right"],
            "theta_multibody_left": on_fem_times(mb_h, f"theta_{mb_names[0]}"),
            "theta_multibody_right": on_fem_times(mb_h, f"theta_{mb_names[1]}"),
            "theta_rigid_half_with_collars": on_fem_times(rigid_h, "theta"),
            "theta_rigid_monolith": on_fem_times(mono_h, "theta"),
        },
    )
    fig, ax = plt.subplots(figsize=(8, 3.6))
    replicas = _replica_histories(out / "cases" / "fem", summary["fem"].get("replicas", 1))
    if len(replicas) > 1:  # the band the replicas span (chaotic after the first landing)
        envelope = [
            np.vstack([np.interp(t, h["t"], h[key], right=np.nan) for h in replicas])
            for key in ("theta_left", "theta_right")
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
    ax.plot(t, fem_h["theta_left"], color="C0", lw=1.6, label="FEM, left half")
    ax.plot(t, fem_h["theta_right"], "--", color="C0", lw=1.6, label="FEM, right half")
    m = mb_h["t"] <= t[-1]
    ax.plot(
        mb_h["t"][m],
        mb_h[f"theta_{mb_names[0]}"][m],
        color="C3",
        lw=1.0,
        label="rigid multibody, left half",
    )
    ax.plot(
        mb_h["t"][m],
        mb_h[f"theta_{mb_names[1]}"][m],
        "--",
        color="C3",
        lw=1.0,
        label="rigid multibody, right half",
    )
    m = rigid_h["t"] <= t[-1]
    ax.plot(
        rigid_h["t"][m],
        rigid_h["theta"][m],
        color="C1",
        lw=1.0,
        label="SDOF, half block + collars (paper)",
    )
    m = mono_h["t"] <= t[-1]
    ax.plot(
        mono_h["t"][m],
        mono_h["theta"][m],
        ":",
        color="C2",
        lw=1.2,
        label="SDOF, whole column (monolith)",
    )
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

    # 1b. the deformed column at peak rotation: crack, collars, toe pressure
    _deformed_figure(out, fem_h, figs)

    # 2. where the pulse sits on the rigid spectrum (a record has no place on it)
    if spectrum is not None:
        _spectrum_figure(out, spectrum, figs)

    # 3. collar stress against f_y
    collar_cols = sorted(k for k in fem_h if k.startswith("collar_") and k.endswith("_stress"))
    if collar_cols:
        write_csv(out / "figures" / "collars.csv", {"t": t, **{k: fem_h[k] for k in collar_cols}})
        fig, ax = plt.subplots(figsize=(9.5, 3.4))
        for j, k in enumerate(collar_cols):  # collars of one history stay apart
            ax.plot(
                t,
                fem_h[k] / 1e6,
                color=f"C{j}",
                **distinct(j, len(collar_cols)),
                label=f"FEM {k.replace('_stress', '')}",
            )
        fy = summary["collar_fy"][0]
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
                "Collar stress against the yield stress "
                "(collars with the same history drawn on top of each other, each "
                "with its own dashes and markers)",
            )
        )

    # 3b. plastic collars: the end hinges of the most strained one, its plastic strain along
    # the band, and the times of first yield and fracture
    _collar_hinge_figure(out, summary, fem_h, figs)

    # 4. toe stress against f_c
    edge_cols = [k for k in fem_h if k.startswith("edge_stress_")]
    write_csv(out / "figures" / "toe_stress.csv", {"t": t, **{k: fem_h[k] for k in edge_cols}})
    fig, ax = plt.subplots(figsize=(9.5, 3.4))
    for j, k in enumerate(edge_cols):
        ax.plot(
            t,
            fem_h[k] / 1e6,
            color=f"C{j}",
            **distinct(j, len(edge_cols)),
            label=k.replace("edge_stress_", "toe "),
        )
    fc = summary["stone_fc"]
    ax.axhline(fc / 1e6, color="k", ls="--", lw=1, label="f_c (stone strength)")
    ax.set_yscale("symlog", linthresh=1.0)
    ax.set_xlabel("t (s)")
    ax.set_ylabel(f"toe stress over {1e3 * summary['fem']['edge_length']:.0f} mm (MPa)")
    legend_beside(ax)  # the f_c line stays in view
    fig.tight_layout()
    figs.append(
        figure(
            out,
            "toe_stress",
            fig,
            "Base-edge compressive stress at the toes against the stone strength",
        )
    )

    # 5. base contact pressure at peak rotation
    pressure = read_csv(out / "cases" / "fem" / "base_pressure.csv")
    peak = int(np.argmax(np.maximum(np.abs(fem_h["theta_left"]), np.abs(fem_h["theta_right"]))))
    names = [k for k in pressure if k != "t"]
    x = np.array([float(n.split("_x=")[1]) for n in names])
    row = min(peak, pressure["t"].size - 1)
    p_peak = np.array([pressure[n][row] for n in names])
    p_rest = np.array([pressure[n][0] for n in names])
    write_csv(
        out / "figures" / "base_pressure.csv",
        {"x": x, "pressure_at_rest": p_rest, "pressure_at_peak_rotation": p_peak},
    )
    fig, ax = plt.subplots(figsize=(8, 3.2))
    ax.plot(x, p_rest / 1e6, "o-", ms=3, label="at rest (gravity)")
    ax.plot(x, p_peak / 1e6, "s-", ms=3, label=f"at peak rotation, t = {pressure['t'][row]:.3f} s")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("base contact pressure (MPa)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    figs.append(figure(out, "base_pressure", fig, "Base contact pressure"))

    renders, renders_error = _renders(out)
    return render_page(
        out,
        "crosscheck.html.j2",
        summary,
        f"colonna cross-check: {summary['study']}",
        figs=figs,
        renders=renders,
        renders_error=renders_error,
        rows=[row for row in CROSSCHECK_NUMBERS if has(summary, row[1])],
    )


def has(summary: dict, dotted: str) -> bool:
    """Whether summary.json has a value (None included) at the dotted key: a row of a Numbers
    table is left out where its key is not there (an SDOF collar note where no collar passed
    f_y, the fibre strains of a column without collars, a summary of an earlier version)."""
    try:
        get(summary, dotted)
    except (KeyError, IndexError, TypeError):
        return False
    return True


def _first_time(t, flags) -> float | None:
    """The first time at which ``flags`` holds (None where it never does)."""
    hit = np.flatnonzero(flags)
    return float(t[hit[0]]) if hit.size else None


def hinge_strain_profile(collar: dict, axial: float, hinges: tuple[float, float]):
    """The plastic strain of a collar's extreme fibre along its span under the lumped-hinge
    model (colonna.core.collar_law): the axial plastic strain |s_p / L| everywhere, plus at
    each end, over the hinge length L_p, the hinge's plastic rotation spread over it,
    |theta_p| h / (2 L_p) (hinge zones longer than half the span overlap and add). ``collar``
    is one of summary["collars"]. Returns (x, strain), a step profile: each piece's two ends,
    x from the left attachment (m)."""
    span, lp, h = collar["span"], collar["hinge_length"], collar["h"]
    rotation = [abs(r) * h / (2.0 * lp) for r in hinges]
    edges = np.unique(np.clip([0.0, lp, span - lp, span], 0.0, span))
    x, strain = [], []
    for a, b in zip(edges[:-1], edges[1:]):
        middle = 0.5 * (a + b)
        value = abs(axial) + rotation[0] * (middle < lp) + rotation[1] * (middle > span - lp)
        x += [a, b]
        strain += [value, value]
    return np.array(x), np.array(strain)


def _collar_hinge_figure(out: Path, summary: dict, fem_h: dict, figs: list) -> None:
    """The plastic collars of the FEM run (replica 0, the unperturbed run, whose history is
    drawn): (a) the end moment against the end rotation (relative to the chord) at both ends
    of the most strained collar (the largest extreme-fibre strain), with +-M_y and +-M_p;
    (b) that collar's plastic strain along its span at the end of the run, from its axial
    plastic strain and end hinges (:func:`hinge_strain_profile`), with the largest fibre
    strain it reached and eps_u; (c) the fibre strain of every plastic collar over time, with
    the most strained one's first yield and fracture. Drawn only for plastic collars."""
    collars = summary.get("collars") or []
    plastic = [
        k
        for k, c in enumerate(collars, start=1)
        if c["plastic"] and f"collar_{k}_moment_left" in fem_h
    ]
    if not plastic:
        return
    t = fem_h["t"]
    peaks = {k: float(np.max(fem_h[f"collar_{k}_fibre_strain"])) for k in plastic}
    # a collar that broke reached eps_u, whatever its history sampled before the break
    k = max(plastic, key=lambda j: (bool(np.any(fem_h[f"collar_{j}_fractured"] > 0.0)), peaks[j]))
    c = collars[k - 1]
    # the largest fibre strain over every step (the run's state), where this collar has the
    # run's largest: the history samples only the output times, and after a fracture it is 0
    peak = peaks[k]
    values = summary["fem"].get("bands", {}).get("collar_max_fibre_strain", {}).get("values")
    every = [float(np.max(fem_h[key])) for key in fem_h if key.endswith("_fibre_strain")]
    if values and values[0] is not None and peak >= max(every):
        peak = max(peak, float(values[0]))
    yielded = _first_time(t, fem_h[f"collar_{k}_utilisation"] >= 1.0)
    fractured = _first_time(t, fem_h[f"collar_{k}_fractured"] > 0.0)
    axial = float(fem_h[f"collar_{k}_plastic_strain"][-1])
    left, right = (float(fem_h[f"collar_{k}_hinge_rotation_{side}"][-1]) for side in SIDES)
    x, profile = hinge_strain_profile(c, axial, (left, right))
    columns = {"t": t}
    for j in plastic:
        columns.update({key: fem_h[key] for key in fem_h if key.startswith(f"collar_{j}_")})
    write_csv(out / "figures" / "collar_hinge.csv", columns)
    write_csv(
        out / "figures" / "collar_hinge_profile.csv",
        {"x": x, "plastic_fibre_strain": profile},
    )

    fig, (ax_m, ax_p, ax_t) = plt.subplots(3, 1, figsize=(9.5, 9.0))
    # (a) moment against rotation at both ends, kN m against mrad, up to a fracture (the
    # broken band's ends turn on carrying nothing)
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
        (c["plastic_moment"], ("k", "--"), "M_p = f_y t h\u00b2/4 (plastic)"),
        (c["yield_moment"], ("0.5", ":"), "M_y = f_y t h\u00b2/6 (first yield)"),
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
    ax_m.set_title(f"(a) collar {k} (y = {c['y']:g} m): end moment against rotation", fontsize=9)
    legend_beside(ax_m)
    # (b) the plastic strain along the span at the end of the run, per mille
    eps_y = 1e3 * c["yield_strain"]
    ax_p.plot(1e3 * x, 1e3 * profile, color="C2", lw=2, label="plastic strain at the end")
    ax_p.axhline(
        1e3 * peak,
        color="C3",
        ls="-.",
        lw=1,
        label=f"largest fibre strain reached, {1e3 * peak:.3g} per mille",
    )
    ax_p.axhline(1e3 * c["eps_u"], color="k", ls="--", lw=1, label="eps_u (fracture)")
    ax_p.axhline(eps_y, color="0.5", ls=":", lw=1, label="eps_y = f_y / E")
    for end in (c["hinge_length"], c["span"] - c["hinge_length"]):
        ax_p.axvline(1e3 * end, color="0.8", lw=0.8)
    ax_p.set_yscale("symlog", linthresh=eps_y)  # eps_u is often far above the rest
    ax_p.yaxis.set_major_formatter(PLAIN)
    top = 1e3 * 1.5 * max(c["eps_u"], peak, float(np.max(profile)))
    ax_p.set_ylim(0.0, top)
    ax_p.set_xlabel(f"along the collar (mm), hinges over L_p = {1e3 * c['hinge_length']:.3g} mm")
    ax_p.set_ylabel("extreme-fibre strain (per mille)")
    ax_p.set_title(f"(b) collar {k}: plastic strain along it (lumped hinges)", fontsize=9)
    legend_beside(ax_p)
    # (c) fibre strain over time, first yield and fracture
    for j, n in enumerate(plastic):
        ax_t.plot(
            t,
            1e3 * fem_h[f"collar_{n}_fibre_strain"],
            color=f"C{j}",
            **distinct(j, len(plastic)),
            label=f"collar {n}",
        )
    ax_t.axhline(1e3 * c["eps_u"], color="k", ls="--", lw=1, label="eps_u (fracture)")
    ax_t.axhline(eps_y, color="0.5", ls=":", lw=1, label="eps_y = f_y / E")
    for when, colour, name in ((yielded, "C1", "first yield"), (fractured, "C3", "fracture")):
        if when is not None:
            ax_t.axvline(when, color=colour, lw=1.2, label=f"collar {k}: {name}, t = {when:.4g} s")
    ax_t.set_yscale("symlog", linthresh=eps_y)
    ax_t.yaxis.set_major_formatter(PLAIN)
    ax_t.set_ylim(0.0, top)
    ax_t.set_xlabel("t (s)")
    ax_t.set_ylabel("extreme-fibre strain (per mille)")
    ax_t.set_title("(c) the plastic collars' fibre strain over time", fontsize=9)
    legend_beside(ax_t)
    fig.tight_layout()
    caption = (
        f"Plastic collars, FEM replica 0: collar {k}, the most strained, "
        + (f"first yields at t = {yielded:.4g} s" if yielded is not None else "does not yield")
        + (
            f" and fractures at t = {fractured:.4g} s (its fibre strain reached eps_u)"
            if fractured is not None
            else " and does not fracture"
        )
        + "; its end hinges' moment-rotation loops against M_y and M_p (the hinges harden "
        "slightly past M_p, and the moment falls with the axial force on the N-M surface), "
        "and its residual plastic strain along the band: the axial plastic strain everywhere "
        "plus each hinge's plastic rotation spread over its length L_p = "
        f"{1e3 * c['hinge_length']:.3g} mm"
    )
    figs.append(
        figure(
            out,
            "collar_hinge",
            fig,
            caption,
            data_file="figures/collar_hinge.csv, figures/collar_hinge_profile.csv",
        )
    )


# the Numbers table of the cross-check: (label, summary key, unit; "-" a ratio, "" words)
CROSSCHECK_NUMBERS = [
    (
        "FEM largest rotation, left half (where the run stopped if it overturns)",
        "fem.max_abs_theta_left",
        "rad",
    ),
    (
        "FEM largest rotation, right half (where the run stopped if it overturns)",
        "fem.max_abs_theta_right",
        "rad",
    ),
    (
        "multibody largest rotation, left half (where the run stopped if it overturns)",
        "rigid_multibody.max_abs_theta_left",
        "rad",
    ),
    (
        "multibody largest rotation, right half (where the run stopped if it overturns)",
        "rigid_multibody.max_abs_theta_right",
        "rad",
    ),
    ("multibody mode", "rigid_multibody.mode", ""),
    ("multibody status", "rigid_multibody.status", ""),
    ("multibody crack slip max", "rigid_multibody.max_abs_crack_slip", "mm"),
    (
        "multibody collar utilisation max, sigma / f_y",
        "rigid_multibody.collar_max_utilisation",
        "-",
    ),
    (
        "multibody collar ductility demand, largest fibre strain / (f_y / E) "
        f"(limit {DUCTILITY_LIMIT:g}: EN 1993-1-1 eps_u >= 15 eps_y)",
        "rigid_multibody.collar_ductility_demand",
        "-",
    ),
    (
        "multibody first collar fracture (n/a: the collars hold)",
        "rigid_multibody.collar_fracture_time",
        "s",
    ),
    ("multibody energy balance error (max, relative)", "rigid_multibody.energy_error_max", "-"),
    ("multibody wall time", "rigid_multibody.wall_seconds", "s"),
    ("SDOF peak rotation, half + collars (n/a where it overturns)", "rigid.max_abs_theta", "rad"),
    ("SDOF overturning mode, half + collars (safe: it does not overturn)", "rigid.mode", ""),
    (
        "SDOF collar state, half + collars (elastic collars: yielded means sigma reached f_y)",
        "rigid.collar_state",
        "",
    ),
    (
        "SDOF peak rotation, whole column (n/a where it overturns)",
        "rigid_monolith.max_abs_theta",
        "rad",
    ),
    (
        "SDOF collars: elastic springs; where one passed f_y, what that leaves out",
        "rigid.collar_note",
        "",
    ),
    ("halves rock as one block", "verdict.rocks_as_one_block", ""),
    ("FEM status", "fem.status", ""),
    ("toe stress max (study mesh, median of the replicas)", "fem.edge_stress_max", "MPa"),
    ("energy balance error (max, relative)", "fem.energy_error_max", "-"),
    ("time step", "fem.dt", "s"),
    ("stable-step reduction by contact", "fem.stable_step_reduction_by_contact", "-"),
    ("steps", "fem.steps", "-"),
    ("dofs", "fem.dofs", "-"),
    ("FEM wall time", "fem.wall_seconds", "s"),
    ("pulse Omega/p (n/a for a record)", "pulse.omega_ratio", "-"),
    ("peak ground acceleration", "pulse.amplitude", "m/s^2"),
    (
        "pulse a_p / a_uplift (a_uplift = g tan alpha (1 + lambda), lambda = top load / weight "
        "of the rocking half)",
        "pulse.amplitude_ratio",
        "-",
    ),
    ("top load on the capital", "fem.top_load", "kN"),
    ("collar plastic strain max, FEM", "fem.collar_max_plastic_strain", "-"),
    ("collar plastic work, FEM", "fem.collar_plastic_work", "J"),
    (
        "collar extreme-fibre strain max, FEM: axial + bending + hinge rotation over L_p "
        "(median of the replicas)",
        "fem.collar_max_fibre_strain",
        "per mille",
    ),
    (
        "collar ductility demand, FEM: largest fibre strain / (f_y / E) "
        f"(limit {DUCTILITY_LIMIT:g}: EN 1993-1-1 eps_u >= 15 eps_y)",
        "fem.collar_ductility_demand",
        "-",
    ),
    (
        "first collar fracture, FEM (median over the replicas; n/a: the collars hold in half "
        "of them or more)",
        "fem.collar_fracture_time",
        "s",
    ),
    ("FEM replicas in which a collar fractured", "fem.collar_fractured_replicas", "-"),
    ("crack slip left at the end of the run, FEM", "fem.crack_slip_residual", "mm"),
    ("static base reaction, FEM: weight + top load", "fem.base_reaction_static", "kN"),
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
        from .render import render_snapshots

        images = render_snapshots(out)
    except Exception as exc:  # rendering is a picture, never a reason to lose the report
        return [], str(exc)
    return [image(out / "figures" / name, caption) for name, caption in images], ""


def _magnification(largest: float, height: float) -> float:
    """A round factor (1, 2 or 5 x 10^k) that draws the largest elastic displacement at about
    2 % of the column height."""
    if largest <= 0.0:
        return 1.0
    raw = 0.02 * height / largest
    k = math.floor(math.log10(raw))
    return max(1.0, max(f * 10.0**k for f in (1.0, 2.0, 5.0) if f * 10.0**k <= raw))


def _deformed_figure(out: Path, fem_h: dict, figs: list) -> None:
    """The FEM column at its peak rotation, drawn in the ground frame: each half's rigid motion
    true to scale, its elastic deformation (the field file's ``elastic_displacement``, split off
    by the solver) magnified by a stated factor; the collars between their attachment nodes
    (``collar_end``); the base contact pressure under the toes at that instant."""
    import meshio

    fem = out / "cases" / "fem"
    vtu = fem / "fields_peak_rotation.vtu"
    if not vtu.exists():
        return
    m = meshio.read(vtu)
    X = m.points[:, :2]
    u = m.point_data["displacement"][:, :2]
    elastic = m.point_data["elastic_displacement"][:, :2]
    collar_end = m.point_data["collar_end"].astype(int)
    quads = np.vstack([c.data for c in m.cells if c.type == "quad"])
    cell_body = np.concatenate(m.cell_data["body"]).astype(int)
    height = float(np.ptp(X[:, 1]))
    factor = _magnification(float(np.abs(elastic).max()), height)
    drawn = X + u + (factor - 1.0) * elastic
    k = int(np.argmax(np.maximum(np.abs(fem_h["theta_left"]), np.abs(fem_h["theta_right"]))))
    t_peak = float(fem_h["t"][k])
    fig, ax = plt.subplots(figsize=(7.0, 6.4))
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
    pressure_file = fem / "base_pressure.csv"
    if pressure_file.exists():
        with open(pressure_file) as fh:
            names = fh.readline().strip().split(",")[1:]
            rows = np.loadtxt(fh, delimiter=",", ndmin=2)
        row = rows[int(np.argmin(np.abs(rows[:, 0] - t_peak)))]
        xs = np.array([float(n.split("=")[1]) for n in names])
        pressure = row[1:] / 1e6
        scale = 0.12 * height / max(pressure.max(), 1e-12)
        order = np.argsort(xs, kind="stable")
        ax.fill_between(xs[order], 0.0, -scale * pressure[order], color="k", alpha=0.35, step=None)
        handles.append(
            Patch(
                facecolor="k",
                alpha=0.35,
                label=f"base contact pressure (max {pressure.max():.2f} MPa)",
            )
        )
    ax.axhline(0.0, color="k", lw=0.8)
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_title(f"FEM at peak rotation, t = {t_peak:.3f} s")
    ax.legend(handles=handles, fontsize=8, loc="upper left", bbox_to_anchor=(1.02, 1.0))
    fig.tight_layout()
    figs.append(
        figure(
            out,
            "deformed",
            fig,
            "The FEM column at its peak rotation: each "
            "half's rigid motion true to scale, its elastic deformation magnified "
            f"x{factor:g}; the crack is the gap between the halves; collars in red; "
            "under the base, the contact pressure at that instant (not to the "
            "length scale)",
        )
    )


def _spectrum_figure(out: Path, spectrum: dict, figs: list) -> None:
    """The study's pulse on the rigid overturning spectra: the SDOF half block with collars as a
    map and, where spectrum.json holds it (key ``multibody``), the rigid multibody model, the
    verdict's rigid reference, as a marker at each pulse of its coarser grid."""
    from matplotlib.colors import BoundaryNorm, ListedColormap

    from ..rigid.plotting import MODE_COLOURS, MODE_LABELS, grid_markers

    code = {"safe": 0, "after-impact": 1, "without-impact": 2}
    codes = np.array([[code[c] for c in row] for row in spectrum["mode"]])
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
    fig, ax = plt.subplots(figsize=(9.5, 4.4))
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
    handles = grid_markers(ax, w, a, codes, labels=[f"SDOF: {m}" for m in MODE_LABELS], size=12)
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
        mb_codes = np.array([[code[c] for c in row] for row in mb["mode"]])
        mb_w, mb_a = np.array(mb["omega_ratios"]), np.array(mb["amplitude_ratios"])
        columns = {
            "omega_ratio": np.tile(mb_w, mb_a.size),
            "amplitude_ratio": np.repeat(mb_a, mb_w.size),
            "mode_code": mb_codes.ravel(),
        }
        if "collar_yields" in mb:
            columns["collar_yield"] = np.array(mb["collar_yields"], dtype=int).ravel()
        write_csv(out / "figures" / "spectrum_multibody.csv", columns)
        handles += grid_markers(
            ax,
            mb_w,
            mb_a,
            mb_codes,
            always=True,
            size=60,
            labels=[f"rigid multibody: {m}" for m in MODE_LABELS],
        )
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
    ax.set_xlabel(r"$\Omega/p$")
    ax.set_ylabel(r"$a_p/(g\tan\alpha)$")
    legend_beside(ax, handles=handles)
    ax.set_title(
        "Rigid overturning spectra: SDOF half block with collars (map)"
        + (", rigid multibody (markers)" if mb is not None else ""),
        fontsize=10,
    )
    fig.tight_layout()
    if mb is not None:
        caption = (
            "The study's pulse (red star) on the rigid overturning spectra. The verdict "
            "relies on the rigid multibody model (two rigid halves, ground and crack "
            "contact with friction, collars as frames): its outcome at each pulse of a "
            "coarser grid through the study's pulse is a marker. The map beneath is the "
            "paper's SDOF half block with collars, a simplification of it, with the line "
            "above which a collar reaches its yield stress; where the two differ, the "
            "markers are the rigid reference"
        )
    else:
        caption = (
            "The study's pulse on the rigid overturning spectrum of the SDOF half block "
            "with collars: outcome of each pulse (legend), and where a collar reaches its "
            "yield stress. The verdict relies on the rigid multibody model, whose "
            "spectrum this run does not hold; the SDOF map is a simplification of it"
        )
    figs.append(
        figure(
            out,
            "spectrum",
            fig,
            caption,
            data_file="figures/spectrum*.csv" if mb is not None else "",
        )
    )


def _write_page(out: Path, text: str) -> Path:
    path = Path(out) / "index.html"
    tmp = Path(out) / "index.html.part"
    tmp.write_text(text)
    tmp.replace(path)
    return path


def write_convergence_report(out: Path) -> Path:
    """The mesh-convergence study: the table of each quantity over the meshes, its figure."""
    out = Path(out)
    s = json.loads((out / "summary.json").read_text())
    (out / "figures").mkdir(exist_ok=True)
    return render_page(
        out,
        "convergence.html.j2",
        s,
        f"colonna mesh convergence: {s['study']}",
        quantities=CONVERGENCE_QUANTITIES,
        figs=[_convergence_figure(out, s)],
    )


def write_variants_report(out: Path) -> Path:
    """The solid / cracked / cracked-with-collars study."""
    out = Path(out)
    s = json.loads((out / "summary.json").read_text())
    (out / "figures").mkdir(exist_ok=True)
    return render_page(
        out,
        "variants.html.j2",
        s,
        f"colonna solid vs cracked: {s['study']}",
        fields=VARIANT_FIELDS,
        figs=[_variants_figure(out, s)],
    )


# (summary key, label, unit) of the mesh-convergence table
CONVERGENCE_QUANTITIES = [
    ("peak_rotation", "peak rotation", "rad"),
    ("collar_max_utilisation", "collar utilisation sigma / f_y", "-"),
    ("edge_stress_max", "toe stress", "Pa"),
]


def _convergence_figure(out: Path, s: dict) -> dict:
    sizes = s["sizes"]
    columns = {"h": np.array(sizes)}
    fig, axes = plt.subplots(1, 3, figsize=(10, 3.6))
    handles: dict[str, Artist] = {}  # one legend for the three panels, below them: what is drawn
    for ax, (name, label, unit) in zip(axes, CONVERGENCE_QUANTITIES):
        c = s["convergence"][name]
        columns[name] = np.array(c["values"], dtype=float)
        scale, unit = (1e-6, "MPa") if unit == "Pa" else (1.0, unit)  # stresses in MPa
        values = scale * np.array(c["values"], dtype=float)
        handles.setdefault("FEM", ax.plot(sizes, values, "o-", color="C0", label="FEM")[0])
        if c["richardson"] is not None:
            handles.setdefault(
                "Richardson",
                ax.axhline(
                    scale * c["richardson"],
                    color="k",
                    ls="--",
                    lw=0.8,
                    label="Richardson extrapolation",
                ),
            )
        ax.set_xscale("log")
        ax.set_xticks(sizes, [f"{1e3 * h:g}" for h in sizes])
        ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
        ax.set_xlabel("mesh size h (mm)")
        ax.set_title(f"{label} ({unit})", fontsize=9)
    fig.legend(handles=list(handles.values()), loc="lower center", ncol=len(handles), fontsize=8)
    fig.tight_layout(rect=(0, 0.08, 1, 1))
    write_csv(out / "figures" / "convergence.csv", columns)
    return figure(out, "convergence", fig, "FEM numbers against the mesh size")


# (summary key, label, unit) of the solid-vs-cracked table
VARIANT_FIELDS = [
    ("fem_peak_rotation", "FEM peak rotation", "rad"),
    ("fem_overturned", "FEM overturned", ""),
    ("rigid_peak_rotation", "rigid peak rotation", "rad"),
    ("rigid_mode", "rigid mode", ""),
    ("collar_max_utilisation", "collar utilisation sigma / f_y", "-"),
    ("edge_stress_ratio", "toe stress / f_c", "-"),
    ("status", "FEM status", ""),
]


def _variants_figure(out: Path, s: dict) -> dict:
    fig, ax = plt.subplots(figsize=(9.5, 3.6))
    n_curves = 2 * len(s["variants"])
    for k, n in enumerate(s["variants"]):
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


def write_design_report(out: Path) -> Path:
    out = Path(out)
    s = json.loads((out / "summary.json").read_text())
    chart = read_csv(out / "figures" / "design_chart.csv")
    alphas = np.unique(chart["alpha"])
    ratios = np.unique(chart["ag_over_g"])
    k = chart["required_stiffness"].reshape(alphas.size, ratios.size)
    from ..rigid.plotting import plot_design_chart

    # the chart in kN/m throughout, the study's column and pulse marked with its required
    # stiffness, and the iso-line of the stiffness its collars provide
    fig, ax = plt.subplots(figsize=(7.5, 5.6))
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
    fig, ax = plt.subplots(figsize=(9.5, 3.2))
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
        "design.html.j2",
        s,
        f"colonna collar design: {s['study']}",
        rows=DESIGN_NUMBERS,
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
    fig, ax = plt.subplots(figsize=(8.5, 3.8))
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


# the collar-design table: (label, summary key, unit)
DESIGN_NUMBERS = [
    ("yield moment M_y", "design.yield_moment", "kN m"),
    ("yield offset d_y, corrected Eq. 22", "design.yield_displacement", "mm"),
    ("yield rotation theta_y, Eq. 23", "design.yield_rotation", "rad"),
    ("required lateral stiffness k, corrected Eq. 24", "design.required_stiffness", "kN/m"),
    ("one collar's lateral stiffness K_l", "design.collar_lateral_stiffness", "kN/m"),
    ("collars needed", "design.collars_needed", "-"),
    ("collars provided", "collars_provided", "-"),
    ("lateral stiffness provided", "lateral_stiffness_provided", "kN/m"),
    ("design adequate", "design_adequate", ""),
    ("FEM collar utilisation (max), sigma / f_y", "fem_collar_max_utilisation", "-"),
    ("FEM first yield", "fem_collar_first_yield_time", "s"),
    ("FEM overturned", "fem_overturned", ""),
    ("FEM peak rotation / theta_y", "fem_max_rotation_over_yield_rotation", "-"),
    (
        "thinnest band that never yields (multibody, plastic collars; n/a: none tried)",
        "ductile_design.never_yields_t",
        "mm",
    ),
    (
        "thinnest band that yields but holds (no break, ductility demand within the limit; "
        "n/a: none tried)",
        "ductile_design.holds_t",
        "mm",
    ),
    (
        "ductility limit (EN 1993-1-1, 3.2.2: eps_u >= 15 eps_y)",
        "ductile_design.ductility_limit",
        "-",
    ),
    ("band thickness of the study's collars", "ductile_design.study_t", "mm"),
]


def write_spectrum_crosscheck_report(out: Path) -> Path:
    """Mode maps of the FEM, multibody and SDOF models side by side, where they disagree, and
    their overturning boundaries overlaid; every map also as CSV."""
    from matplotlib.colors import BoundaryNorm, ListedColormap
    from matplotlib.patches import Patch

    from ..rigid.plotting import MODE_COLOURS, MODE_LABELS, grid_markers

    out = Path(out)
    s = json.loads((out / "summary.json").read_text())
    (out / "figures").mkdir(exist_ok=True)
    w, a = np.array(s["omega_ratios"]), np.array(s["amplitude_ratios"])
    # a record's grid moves its time scale where a pulse's moves Omega / p
    x_label = (
        r"record time scale (2: twice as fast)"
        if s.get("x_axis") == "time_scale"
        else r"$\Omega / p$"
    )
    code = {"safe": 0, "after-impact": 1, "without-impact": 2}
    models = (("fem", "FEM"), ("multibody", "rigid multibody"), ("sdof", "SDOF half block"))
    maps = {m: np.array([[code[c] for c in row] for row in s[f"mode_{m}"]]) for m, _ in models}
    ww, aa = np.meshgrid(w, a)
    columns = {"omega_ratio": ww.ravel(), "amplitude_ratio": aa.ravel()}
    columns.update({f"mode_code_{m}": maps[m].ravel() for m, _ in models})
    columns["collar_utilisation_fem"] = np.array(s["collar_utilisation_fem"], float).ravel()
    columns["toe_ratio_fem"] = np.array(s["toe_ratio_fem"], float).ravel()
    write_csv(out / "figures" / "maps.csv", columns)
    figs = []

    cmap = ListedColormap(MODE_COLOURS)
    norm = BoundaryNorm([-0.5, 0.5, 1.5, 2.5], cmap.N)
    fig, axes = plt.subplots(1, 3, figsize=(12, 3.8), sharey=True)
    yields = np.array(s["collar_yield_fem"], dtype=bool)
    marked: dict[str, Artist] = {}  # a marker at each computed pulse of a coarse grid
    for ax, (m, label) in zip(axes, models):
        ax.pcolormesh(w, a, maps[m], cmap=cmap, norm=norm, shading="nearest")
        marked.update((h.get_label(), h) for h in grid_markers(ax, w, a, maps[m]))
        ax.set_title(label)
        ax.set_xlabel(x_label)
    if yields.any():
        axes[0].scatter(ww[yields], aa[yields], marker="x", color="k", s=25, zorder=4)
    axes[0].set_ylabel(r"$a_p / (g\,\tan\alpha)$")
    present = {int(k) for m, _ in models for k in np.unique(maps[m])}  # the legend: what is drawn
    handles = [
        marked.get(MODE_LABELS[k]) or Patch(color=MODE_COLOURS[k], label=MODE_LABELS[k])
        for k in sorted(present)
    ]
    if yields.any():
        handles.append(
            plt.Line2D([], [], marker="x", color="k", ls="", label="FEM: a collar reaches f_y")
        )
    fig.legend(handles=handles, loc="lower center", ncol=len(handles), fontsize=8)
    fig.tight_layout(rect=(0, 0.08, 1, 1))
    figs.append(
        figure(
            out,
            "maps",
            fig,
            "Outcome of every pulse of the grid: FEM, rigid "
            "multibody and SDOF (the paper's half block with collars)"
            + ("; a marker at each computed pulse" if marked else ""),
        )
    )

    fig, axes = plt.subplots(1, 2, figsize=(9, 3.6), sharey=True)
    shades = ("#f2f2f2", "#7570b3")
    drawn, marked = set(), {}
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
                ax, w, a, differ.astype(int), colours=shades, markers=("o", "X"), labels=words
            )
        )
        ax.set_title(label)
        ax.set_xlabel(x_label)
    axes[0].set_ylabel(r"$a_p / (g\,\tan\alpha)$")
    fig.legend(
        handles=[
            marked.get(words[k]) or Patch(color=shades[k], label=words[k]) for k in sorted(drawn)
        ],
        loc="lower center",
        ncol=2,
        fontsize=8,
    )
    fig.tight_layout(rect=(0, 0.08, 1, 1))
    figs.append(figure(out, "disagreement", fig, "Where the FEM and each rigid model disagree"))

    fig, ax = plt.subplots(figsize=(8.5, 4))
    boundary, never = {}, []
    for j, (m, label) in enumerate(models):
        over = maps[m] != 0
        lowest = np.where(over.any(axis=0), a[np.argmax(over, axis=0)], np.nan)
        boundary[f"lowest_overturning_amplitude_{m}"] = lowest
        if np.isfinite(lowest).any():  # the legend lists only what is drawn
            style = dict(distinct(j, len(models)), markevery=None, markersize=10 - 3 * j)
            ax.plot(w, lowest, color=f"C{j}", **style, label=label)  # equal ones stay apart
        else:
            never.append(label)
    write_csv(out / "figures" / "boundaries.csv", {"omega_ratio": w, **boundary})
    ax.set_xlabel(x_label)
    ax.set_ylabel(r"lowest overturning $a_p / (g\,\tan\alpha)$")
    if len(never) < len(models):
        legend_beside(ax)
        fig.tight_layout()
        figs.append(
            figure(
                out,
                "boundaries",
                fig,
                "Overturning boundary of each model: the "
                "lowest amplitude of the grid that overturns, per frequency (none "
                "drawn where no amplitude of the grid does)"
                + (
                    f"; no pulse of the grid overturns the {' or the '.join(never)} model"
                    if never
                    else ""
                ),
            )
        )
    else:
        plt.close(fig)

    return render_page(
        out,
        "spectrum_crosscheck.html.j2",
        s,
        f"colonna spectrum cross-check: {s['study']}",
        figs=figs,
        rows=SPECTRUM_NUMBERS,
    )


SPECTRUM_NUMBERS = [
    (
        "FEM and rigid multibody: same outcome, fraction of the grid points",
        "agreement_fem_multibody",
        "-",
    ),
    (
        "FEM and SDOF half block: same outcome, fraction of the grid points",
        "agreement_fem_sdof",
        "-",
    ),
    ("grid points", "points", "-"),
    ("FEM energy balance error (max over the grid, relative)", "energy_error_fem_max", "-"),
    ("FEM wall time per grid point", "fem_seconds_per_point", "s"),
    ("study wall time", "wall_seconds", "s"),
]


def write_free_rocking_report(out: Path) -> Path:
    """Free rocking: rotations of the FEM and the multibody model from each tilt, the velocity
    ratio at each impact beside Housner's, and what the FEM's value depends on."""
    out = Path(out)
    s = json.loads((out / "summary.json").read_text())
    (out / "figures").mkdir(exist_ok=True)
    alpha = s["alpha"]
    figs = []
    fig, ax = plt.subplots(figsize=(9.5, 3.6))
    columns = {}
    n_curves = 2 * len(s["tilts"])
    for k, tilt in enumerate(s["tilts"], start=1):
        for j, (kind, style) in enumerate((("fem", "-"), ("multibody", "--"))):
            h = read_csv(out / "cases" / f"{kind}-tilt{k}" / "history.csv")
            label = "FEM" if kind == "fem" else "rigid multibody"
            # the two models coincide up to the first impact: each its width and markers
            ax.plot(
                h["t"],
                h["theta_left"] / alpha,
                color=f"C{k - 1}",
                **dict(distinct(2 * (k - 1) + j, n_curves), ls=style),
                label=f"{label}, released at {tilt['tilt_fraction']:g} alpha",
            )
            columns[f"t_{kind}_tilt{k}"] = h["t"]
            columns[f"theta_over_alpha_{kind}_tilt{k}"] = h["theta_left"] / alpha
    n = max(len(v) for v in columns.values())
    write_csv(
        out / "figures" / "rotations.csv",
        {k: np.pad(v, (0, n - len(v)), constant_values=np.nan) for k, v in columns.items()},
    )
    ax.set_xlabel("t (s)")
    ax.set_ylabel(r"$\theta / \alpha$")
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

    fig, ax = plt.subplots(figsize=(9, 3.6))
    ratio_columns = {}
    for k, tilt in enumerate(s["tilts"], start=1):
        for j, kind in enumerate(("fem", "multibody")):
            ratios = np.array(tilt[kind]["ratios"], dtype=float)
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
                label=f"{label}, released at {tilt['tilt_fraction']:g} alpha",
            )
            ratio_columns[f"ratio_{kind}_tilt{k}"] = ratios
    ax.axhline(s["restitution_housner"], color="k", lw=0.8, ls=":", label="Housner 1 - 1.5 sin²α")
    ax.set_xlabel("impact")
    ax.set_ylabel(r"$\dot\theta_{after} / \dot\theta_{before}$")
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
        out, "free_rocking.html.j2", s, f"colonna free rocking: {s['study']}", figs=figs
    )


def write_zhang_makris_report(out: Path) -> Path:
    """The Zhang & Makris validation: figures, boundaries and spectra."""
    out = Path(out)
    summary = json.loads((out / "summary.json").read_text())
    histories = [
        image(out / f"history_{x.replace('.', '_')}.png", f"a_p = {x} g alpha, Omega/p = 5")
        for x in ("3.00", "3.01", "6.32", "6.33")
    ]
    spectra = [
        image(out / f"spectrum_{m}_{c}.png", f"{m} model, {c.replace('free', 'free block')}")
        for m in ("linear", "nonlinear")
        for c in ("free", "collars")
    ]
    return render_page(
        out,
        "zhang_makris.html.j2",
        summary,
        "colonna validation: Zhang & Makris block",
        histories=histories,
        spectra=spectra,
    )

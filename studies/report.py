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
import importlib
import io
import json
import math
import textwrap
from pathlib import Path

import jinja2
import matplotlib
import numpy as np
from markupsafe import Markup, escape
from matplotlib.figure import Figure

from .kinds import KINDS
from .output import read_csv
from .sections import Resolved
from .units import DISPLAY_UNITS, input_unit

# the shared pieces (base.html.j2, macros.html.j2) in studies/templates; each kind's page in its
# package, by its path from the folders of colonna.studies ("crosscheck/report.html.j2"), so that
# a kind's package brings its own template wherever the package is found
TEMPLATES = jinja2.Environment(
    loader=jinja2.FileSystemLoader(
        [Path(__file__).with_name("templates"), *importlib.import_module(__package__).__path__]
    ),
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
    carrying the factor in ``data-scale``. A key of a typed table (studies.sections.Resolved)
    brings its value, read by attribute from the typed summary."""
    value = dotted.value if isinstance(dotted, Resolved) else get(summary, dotted)
    dotted = str(dotted)
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
INPUT_TABLES = (
    "study",
    "column",
    "stone",
    "collar",
    "ground",
    "contact",
    "base",
    "mesh",
    "run",
    "rigid",
    "hazard",
)


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
    for name in INPUT_TABLES + (tuple(kind.tables) if kind is not None else ()):
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


def _run_duration(out: Path) -> float | None:
    """The run's duration (s) as inputs.json records it (None without a record or a number)."""
    path = Path(out) / "inputs.json"
    if not path.is_file():
        return None
    duration = (json.loads(path.read_text()).get("run") or {}).get("duration")
    return float(duration) if isinstance(duration, (int, float)) else None


def _ground_figure(out: Path) -> dict | None:
    """The ground motion the study applied (ground_motion.csv), horizontal and vertical."""
    path = Path(out) / "ground_motion.csv"
    if not path.is_file():
        return None
    g = read_csv(path)
    fig = Figure(figsize=(8, 2.6))
    ax = fig.subplots()
    ax.plot(g["t"], g["horizontal_acceleration"], color="C0", label="horizontal")
    if np.any(g["vertical_acceleration"] != 0.0):
        ax.plot(g["t"], g["vertical_acceleration"], "--", color="C3", label="vertical (up +)")
    ax.axhline(0.0, color="0.6", lw=0.6)
    run_end = _run_duration(out)
    if run_end is not None and run_end < float(g["t"][-1]):
        # a record longer than the run: what follows the run's end was never applied
        ax.axvspan(run_end, float(g["t"][-1]), color="0.85", zorder=0, label="after the run's end")
        ax.axvline(run_end, color="0.3", lw=0.8, ls=":")
    ax.set_xlabel("t (s)")
    ax.set_ylabel("ground acceleration (m/s$^2$)")
    legend_beside(ax)
    fig.tight_layout()
    return figure(
        out,
        "ground_motion",
        fig,
        "The ground motion applied: horizontal and vertical accelerations"
        + (
            f"; the record after the run's end (t > {run_end:g} s, shaded) was not applied"
            if run_end is not None and run_end < float(g["t"][-1])
            else ""
        ),
        data_file="ground_motion.csv",
    )


def blocks_of(out: Path) -> dict[str, str]:
    """Whose alpha and p a report's numbers are in, from inputs.json (``column``: the whole
    column, ``half``: one half block; studies.outcome.BLOCKS): ``sdof``, the paper's SDOF
    block (the half of a cracked column: it normalises the pulse and the spectra), and
    ``rocking``, the body whose rotation the FEM and multibody histories are compared with
    (the whole column where collars or no crack hold the halves together). Without inputs on
    record, those of a cracked column with collars."""
    from .outcome import rocking_block

    path = Path(out) / "inputs.json"
    inputs = json.loads(path.read_text()) if path.is_file() else {}
    cracked = bool((inputs.get("column") or {}).get("cracked", True))
    collared = bool(inputs.get("collar", True))
    return {
        "sdof": "half" if cracked else "column",
        "rocking": rocking_block(cracked, collared),
    }


def render_page(out: Path, template: str, summary: dict, title: str, **context) -> Path:
    """Fill a template with the summary (``s``), ``num``, the blocks of its alphas
    (:func:`blocks_of`) and the figures; write index.html."""
    text = TEMPLATES.get_template(template).render(
        s=summary,
        title=title,
        num=functools.partial(num, summary),
        inputs=_inputs(out),
        ground=_ground_figure(out),
        blocks=blocks_of(out),
        **context,
    )
    return _write_page(out, text)


def one_figure_report(out: Path, package: str, title: str, draw, **context) -> Path:
    """The report of a kind whose page is one table and one figure (mesh convergence, solid vs
    cracked): summary.json into its package's template ``<package>/report.html.j2``, titled
    ``colonna <title>: <study>``, with the figure ``draw(out, summary)`` and ``context`` (its
    table)."""
    out = Path(out)
    s = json.loads((out / "summary.json").read_text())
    (out / "figures").mkdir(exist_ok=True)
    return render_page(
        out,
        f"{package}/report.html.j2",
        s,
        f"colonna {title}: {s['study']}",
        figs=[draw(out, s)],
        **context,
    )


def _legend_entries(fig) -> list[str]:
    """The texts of every legend of the figure (figure legends and axes legends), a wrapped
    entry's lines joined by a space."""
    legends = list(fig.legends) + [ax.get_legend() for ax in fig.axes if ax.get_legend()]
    return [" ".join(t.get_text().split()) for legend in legends for t in legend.get_texts()]


def figure(out: Path, name: str, fig, caption: str, data_file: str | None = "") -> dict:
    """A matplotlib figure for a template: inline SVG (text kept as text), its legend entries,
    and a PNG copy in figures/ (data: figures/NAME.csv unless told otherwise)."""
    (out / "figures").mkdir(exist_ok=True)
    fig.savefig(out / "figures" / f"{name}.png", dpi=110)
    buf = io.StringIO()
    with matplotlib.rc_context({"svg.fonttype": "none", "svg.hashsalt": name}):
        fig.savefig(buf, format="svg")
    legend = _legend_entries(fig)
    svg = buf.getvalue()
    svg = svg[svg.index("<svg") :]
    return {
        "name": name,
        "caption": caption,
        "svg": Markup(svg),
        "legend": legend,
        "data_file": f"figures/{name}.csv" if data_file == "" else data_file,
    }


def texts_outside(fig) -> list[str]:
    """What of a figure's text reaches beyond its edges once drawn (a legend entry, an axis
    label, a title, the tick labels of an axis), as "where: text"; empty where every text is
    inside. The trial's PDF showed "base contact pressure at the" and "nodes (MPa": texts cut
    at the figure's edge."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.text import Text

    canvas = FigureCanvasAgg(fig)
    canvas.draw()
    renderer = canvas.get_renderer()
    page = fig.bbox.padded(1.0)  # a pixel of rounding

    def cut(text) -> bool:
        box = text.get_window_extent(renderer)
        return not (
            page.x0 <= box.x0 and box.x1 <= page.x1 and page.y0 <= box.y0 and box.y1 <= page.y1
        )

    found: list[str] = []
    tick_labels: set = set()
    for n, ax in enumerate(fig.axes):
        for axis in (ax.xaxis, ax.yaxis):
            every = axis.get_major_ticks() + axis.get_minor_ticks()
            tick_labels.update(t for tick in every for t in (tick.label1, tick.label2))
            # the ticks drawn (those in the view; matplotlib's own choice)
            for tick in axis._update_ticks():
                for label in (tick.label1, tick.label2):
                    if label.get_visible() and label.get_text() and cut(label):
                        found.append(f"axes {n} {axis.axis_name} tick label: {label.get_text()}")
    for text in fig.findobj(Text):
        if text in tick_labels or not text.get_visible() or not text.get_text().strip():
            continue
        if cut(text):
            found.append(f"text: {' '.join(text.get_text().split())}")
    return found


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


# an overturning spectrum's outcomes as the codes its maps are drawn in (the order of
# colonna.rigid.plotting's MODE_COLOURS and MODE_LABELS)
MODE_CODES = {"safe": 0, "after-impact": 1, "without-impact": 2}


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


def wrap(text: str, width: int = 30) -> str:
    """A label broken into lines of at most ``width`` characters: a long legend entry or axis
    label would otherwise run past its figure's edge (:func:`texts_outside`)."""
    return "\n".join(textwrap.wrap(text, width)) or text


def has(summary: dict, dotted: str) -> bool:
    """Whether summary.json has a value (None included) at the dotted key: a row of a Numbers
    table is left out where its key is not there (an SDOF collar note where no collar passed
    f_y, the fibre strains of a column without collars, a summary of an earlier version)."""
    try:
        get(summary, dotted)
    except (KeyError, IndexError, TypeError):
        return False
    return True


def _write_page(out: Path, text: str) -> Path:
    path = Path(out) / "index.html"
    tmp = Path(out) / "index.html.part"
    tmp.write_text(text)
    tmp.replace(path)
    return path

"""``colonna collar``: one collar driven through imposed end displacements and rotations, as the
models step it (:func:`colonna.core.collar.response`): a test bench to see what the section
does before running a column.

    colonna collar --t 0.008 --h 0.06 --length 0.45 --fy 235e6 history.csv --out response.csv
    colonna collar --collar band.toml history.csv --out response.csv

The collar: a TOML file with a ``[collar]`` table (the keys of a study file's [[collar]] and
the fibre law's: section, n_fibres, n_sections, steel, isotropic, R0, cR1, cR2, a1 .. a4; SI
units), or the flags, which
override the file's values. The bench's collar is plastic unless ``plastic = false`` or
``--elastic``. The history: a CSV with a header row naming the columns u1, v1, r1, u2, v2, r2
(m, rad; the ends' displacements and rotations in the collar's initial axes, end 1 at the
origin, end 2 at (L, 0)), one row per step from the unstressed collar. Writes a CSV of the
response per row (SI: N, N m, Pa, J) and prints the peaks in kN, kN m, MPa, J.
"""

from __future__ import annotations

import dataclasses
import json
import math
from pathlib import Path

import numpy as np

from ..core.collar import RESPONSE_FIELDS, Collar, response
from ..core.errors import InputError, read_toml
from .output import write_csv

COLUMNS = ("u1", "v1", "r1", "u2", "v2", "r2")
# flag -> Collar field (SI), for the flags that set a collar's number
FLAGS = {
    "t": "t",
    "h": "h",
    "length": "length",
    "E": "E",
    "fy": "fy",
    "Eh": "Eh",
    "eps_u": "eps_u",
    "pretension": "pretension",
    "n_fibres": "n_fibres",
    "n_sections": "n_sections",
    "isotropic": "isotropic",
    "section": "section",
    "steel": "steel",
}
BENCH_Y = 1.0  # m: a collar's height, which the bench does not use


def add_arguments(parser) -> None:
    parser.add_argument("history", type=Path, help="CSV: header u1,v1,r1,u2,v2,r2 (m, rad)")
    parser.add_argument("--collar", type=Path, help="TOML file with a [collar] table")
    g = parser.add_argument_group("collar (SI units; override the file's values)")
    g.add_argument("--t", type=float, help="band thickness t (m)")
    g.add_argument("--h", type=float, help="band depth h (m)")
    g.add_argument("--length", type=float, help="span L (m)")
    g.add_argument("--E", type=float, help="Young's modulus (Pa)")
    g.add_argument("--fy", type=float, help="yield stress (Pa)")
    g.add_argument("--Eh", type=float, help="hardening modulus (Pa; default 0.01 E)")
    g.add_argument("--eps-u", dest="eps_u", type=float, help="fracture strain")
    g.add_argument("--pretension", type=float, help="pretension (N)")
    g.add_argument("--section", choices=("fibre", "resultant"), help="the local law")
    g.add_argument("--n-fibres", dest="n_fibres", type=int, help="layers across h")
    g.add_argument("--n-sections", dest="n_sections", type=int, help="sections along L")
    g.add_argument(
        "--steel",
        choices=("bilinear", "menegotto-pinto"),
        help="the fibres' law (its R0, cR1, cR2, a1-a4 from the collar file)",
    )
    g.add_argument("--isotropic", type=float, help="isotropic share of the hardening (0-1)")
    g.add_argument("--elastic", action="store_true", help="an elastic collar (plastic = false)")
    parser.add_argument("--out", type=Path, help="CSV of the response, one row per step")
    parser.add_argument("--json", action="store_true", help="print the peaks as JSON (SI)")


def collar_from(args) -> Collar:
    """The bench's collar: the file's [collar] table, then the flags over it."""
    table: dict = {}
    if args.collar is not None:
        data = read_toml(args.collar, "collar file")
        if not isinstance(data.get("collar"), dict):
            raise InputError(f"collar file {args.collar} needs one [collar] table")
        table = dict(data["collar"])
        for key in data:
            if key != "collar":
                raise InputError(f"collar file {args.collar}: unknown table [{key}]")
    for flag, field in FLAGS.items():
        value = getattr(args, flag, None)
        if value is not None:
            table[field] = value
    if args.elastic:
        table["plastic"] = False
    table.setdefault("plastic", True)
    table.setdefault("y", BENCH_Y)
    fields = {f.name for f in dataclasses.fields(Collar)}
    for key in table:
        if key not in fields:
            raise InputError(
                f"collar key {key!r} is unknown: the keys are {', '.join(sorted(fields))}"
            )
    for key in ("t", "h", "length"):
        if key not in table:
            raise InputError(f"collar {key} is not given: set it in [collar] or with --{key}")
    try:
        return Collar(**table)
    except TypeError as exc:  # a number given as text, ...
        raise InputError(f"collar: {exc}") from None


def read_history(path: Path) -> np.ndarray:
    """The rows (u1, v1, r1, u2, v2, r2) of a history CSV, by its header's names."""
    try:
        lines = Path(path).read_text().splitlines()
    except OSError as exc:
        raise InputError(f"history {path} cannot be read: {exc.strerror}") from None
    lines = [line for line in lines if line.strip()]
    if not lines:
        raise InputError(f"history {path} is empty: it needs a header u1,v1,r1,u2,v2,r2")
    header = [name.strip() for name in lines[0].split(",")]
    missing = [name for name in COLUMNS if name not in header]
    if missing:
        raise InputError(
            f"history {path}: header {lines[0]!r} lacks column(s) {', '.join(missing)} "
            "(it needs u1,v1,r1,u2,v2,r2)"
        )
    rows = np.zeros((len(lines) - 1, 6))
    for k, line in enumerate(lines[1:]):
        cells = line.split(",")
        if len(cells) != len(header):
            raise InputError(
                f"history {path} line {k + 2}: {len(cells)} values for {len(header)} columns"
            )
        for j, name in enumerate(COLUMNS):
            text = cells[header.index(name)].strip()
            try:
                value = float(text)
            except ValueError:
                value = math.nan
            if not math.isfinite(value):
                raise InputError(f"history {path} line {k + 2}: {name} = {text!r} is no number")
            rows[k, j] = value
    if rows.shape[0] == 0:
        raise InputError(f"history {path} has a header and no rows")
    return rows


def peaks(collar: Collar, r: dict) -> dict:
    """The response's peaks (SI): |N|, |end moment|, largest fibre strain and stress, the
    plastic work at the end, and whether (and at which row, from 1) the collar fractured."""
    broken = np.nonzero(r["fractured"])[0]
    return {
        "local_law": collar.local_law,
        "peak_axial_force": float(np.abs(r["N"]).max()),
        "peak_end_moment": float(np.maximum(np.abs(r["M1"]), np.abs(r["M2"])).max()),
        "largest_fibre_strain": float(r["largest_fibre_strain"].max()),
        "ductility_demand": float(r["largest_fibre_strain"].max() / collar.yield_strain),
        "peak_fibre_stress": float(r["fibre_stress"].max()),
        "plastic_work": float(r["plastic_work"][-1]),
        "fractured": bool(broken.size),
        "fracture_row": int(broken[0]) + 1 if broken.size else None,
    }


SHOWN = {  # key: (words, unit, factor from SI)
    "peak_axial_force": ("peak axial force", "kN", 1e-3),
    "peak_end_moment": ("peak end moment", "kN m", 1e-3),
    "largest_fibre_strain": ("largest fibre strain", "", 1.0),
    "ductility_demand": ("ductility demand (strain / eps_y)", "", 1.0),
    "peak_fibre_stress": ("peak fibre stress", "MPa", 1e-6),
    "plastic_work": ("plastic work", "J", 1.0),
}


def run_command(args) -> None:
    collar = collar_from(args)
    rows = read_history(args.history)
    r = response(collar, rows)
    if args.out is not None:
        columns = {name: rows[:, k] for k, name in enumerate(COLUMNS)}
        columns.update({name: r[name] for name in RESPONSE_FIELDS})
        write_csv(args.out, columns)
    summary = peaks(collar, r)
    if args.json:
        print(json.dumps(summary))
        return None
    print(f"{'local law':36s} {summary['local_law']}")
    for key, (words, unit, factor) in SHOWN.items():
        print(f"{words:36s} {summary[key] * factor:.4g} {unit}".rstrip())
    row = summary["fracture_row"]
    print(f"{'fractured':36s} " + (f"yes, at row {row}" if row else "no"))
    return None

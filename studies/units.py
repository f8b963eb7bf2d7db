"""The units numbers are shown in, in one place: the report (summary.json's values and the study
file's inputs) and the command line's printed summaries read them from here.

Every value on disk is in SI units (Pa, N, m, s, J, rad); a unit of :data:`DISPLAY_UNITS` is shown
as the SI value times its factor (MPa from Pa, kN from N, mm from m), any other unit as it is.
"""

from __future__ import annotations

# units an engineer reads, from the SI of summary.json: shown value = SI value * factor
DISPLAY_UNITS = {
    "MPa": 1e-6,
    "GPa": 1e-9,
    "GPa/m": 1e-9,
    "kN": 1e-3,
    "kN m": 1e-3,
    "kN/m": 1e-3,
    "MN/m": 1e-6,
    "mm": 1e3,
    "kJ": 1e-3,
    "per mille": 1e3,
}


# the unit an engineer reads (one of DISPLAY_UNITS) for a schema unit, and per key of the study
# file where it differs
INPUT_UNITS = {"Pa": "MPa", "N": "kN"}
INPUT_UNITS_BY_KEY = {
    ("collar", "t"): "mm",
    ("collar", "h"): "mm",
    ("stone", "E"): "GPa",
    ("collar", "E"): "GPa",
    ("collar", "Eh"): "GPa",
    ("contact", "penalty"): "GPa/m",
}


def shown_unit(si: str) -> tuple[str, float]:
    """(unit shown, factor from SI) of a value in the SI unit ``si``: MPa for Pa, kN for N, the
    unit itself otherwise."""
    shown = INPUT_UNITS.get(si, si)
    return shown, DISPLAY_UNITS.get(shown, 1.0)


def input_unit(table: str, key: str) -> tuple[str, float]:
    """(unit shown, factor from the schema's SI unit) of a study-file key in the inputs
    section: the schema's own unit where no other reads better."""
    from . import schema

    extra = schema.table_model(table).model_fields[key].json_schema_extra
    si = str(extra.get("unit", "")) if isinstance(extra, dict) else ""
    shown = INPUT_UNITS_BY_KEY.get((table, key))
    return shown_unit(si) if shown is None else (shown, DISPLAY_UNITS.get(shown, 1.0))


# The unit a summary value is printed in on the command line (its key in SI units: Pa, N, m, s,
# ...), found from the words of its key (split at "_"): the first row with a word in the key
# wins. Ratios come first, so that edge_stress_ratio or yield_rotation_over_alpha are plain
# numbers. The factor from SI is the unit's in DISPLAY_UNITS (1 for a unit not there).
KEY_UNITS: tuple[tuple[frozenset[str], str], ...] = (
    (
        frozenset(
            {
                "over",
                "ratio",
                "ratios",
                "utilisation",
                "error",
                "restitution",
                "friction",
                "strain",
                "reduction",
                "agreement",
            }
        ),
        "",
    ),
    (frozenset({"stress"}), "MPa"),
    (frozenset({"moment"}), "kN m"),
    (frozenset({"force", "load", "reaction"}), "kN"),
    (frozenset({"stiffness", "penalty"}), "kN/m"),
    (frozenset({"energy", "work"}), "J"),
    (frozenset({"acceleration"}), "m/s^2"),
    (frozenset({"mass"}), "kg"),
    (frozenset({"time", "seconds", "dt", "t"}), "s"),
    (frozenset({"theta", "rotation", "angle", "alpha"}), "rad"),
    (frozenset({"p"}), "rad/s"),
    (frozenset({"b", "h", "uplift", "opening", "slip", "length", "displacement"}), "m"),
)


def unit_of(key: str) -> tuple[str, float]:
    """(unit, factor from SI) a summary value is printed in, from the words of its key
    (:data:`KEY_UNITS`); ("", 1) for a plain number."""
    words = set(key.split("_"))
    for names, unit in KEY_UNITS:
        if words & names:
            return unit, DISPLAY_UNITS.get(unit, 1.0)
    return "", 1.0

"""The units numbers are shown in, in one place: the report (summary.json's values and the study
file's inputs) and the command line's printed summaries read them from here.

Every value on disk is in SI units (Pa, N, m, s, J, rad); a unit of :data:`DISPLAY_UNITS` is shown
as the SI value times its factor (MPa from Pa, kN from N, mm from m), any other unit as it is.

The SI unit of a model run's summary key is declared by its typed result (the frozen dataclasses
of colonna.rigid.solve, colonna.rigid.multibody, colonna.fem.solver and colonna.fem.ensemble,
each field a colonna.core.quantities.quantity): :func:`unit_of` reads it there first and shows
it as :data:`SHOWN_UNITS` says. Only a key that no typed result declares (one a study adds to
its own summary) has its unit guessed from its words (:data:`KEY_UNITS`).
"""

from __future__ import annotations

from ..core import quantities

# units an engineer reads, from the SI of summary.json: shown value = SI value * factor
DISPLAY_UNITS = {
    "MPa": 1e-6,
    "MPa m^0.5": 1e-6,
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
INPUT_UNITS = {"Pa": "MPa", "N": "kN", "Pa m^0.5": "MPa m^0.5"}
INPUT_UNITS_BY_KEY = {
    ("collar", "t"): "mm",
    ("collar", "h"): "mm",
    ("stone", "E"): "GPa",
    ("collar", "E"): "GPa",
    ("collar", "Eh"): "GPa",
    ("contact", "penalty"): "GPa/m",
    ("base", "stiffness"): "GPa/m",
    ("base", "stiffness_range"): "GPa/m",
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


# how a summary value in a declared SI unit is shown: stresses in MPa, forces in kN, ...; a ratio
# ("-") as a plain number; any other unit (m, s, rad, J, ...) as it is
SHOWN_UNITS = {
    "Pa": "MPa",
    "N": "kN",
    "N m": "kN m",
    "N/m": "kN/m",
    "N/m^3": "GPa/m",
    "Pa m^0.5": "MPa m^0.5",
    "-": "",
}


def declared_units() -> dict[str, str]:
    """Summary key -> SI unit, as the typed results declare them (their modules imported here,
    on first use: importing this module stays light)."""
    from ..fem import ensemble, solver  # noqa: F401  (their summaries register their units)
    from ..rigid import multibody, solve  # noqa: F401

    return quantities.declared_units()


def declared_unit(key: str) -> str | None:
    """The SI unit a typed result declares for a summary key; None where none declares it."""
    return declared_units().get(key)


# The fallback for a key that no typed result declares (:func:`declared_unit` None): a study's
# own summary keys, e.g. the command line's uplift_acceleration, the design's yield_moment or
# required_stiffness, a spectrum's counts. The unit is found from the words of the key (split at
# "_"): the first row with a word in the key wins. Ratios come first, so that
# yield_rotation_over_alpha is a plain number. The factor from SI is the unit's in
# DISPLAY_UNITS (1 for a unit not there).
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
    """(unit, factor from SI) a summary value is printed in: its typed result's unit
    (:func:`declared_unit`) shown as :data:`SHOWN_UNITS` says, else the unit guessed from the
    words of its key (:func:`guessed_unit`); ("", 1) for a plain number."""
    si = declared_unit(key)
    if si is None:
        return guessed_unit(key)
    shown = SHOWN_UNITS.get(si, si)
    return shown, DISPLAY_UNITS.get(shown, 1.0)


def guessed_unit(key: str) -> tuple[str, float]:
    """(unit, factor from SI) from the words of a key (:data:`KEY_UNITS`), for a key that no
    typed result declares; ("", 1) for a plain number."""
    words = set(key.split("_"))
    for names, unit in KEY_UNITS:
        if words & names:
            return unit, DISPLAY_UNITS.get(unit, 1.0)
    return "", 1.0


def duration_text(seconds: float) -> str:
    """A duration for people: '25 s', '40 min', '14 h', '3.2 days', '2e+03 years'."""
    units = (
        ("years", 365 * 86400.0),
        ("days", 86400.0),
        ("h", 3600.0),
        ("min", 60.0),
        ("s", 1.0),
    )
    unit, size = next((u for u in units if seconds >= 2.0 * u[1]), units[-1])
    value = seconds / size
    return f"{value:.0f} {unit}" if 10.0 <= value < 1e4 else f"{value:.2g} {unit}"

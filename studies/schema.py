"""The study file's schema: every table and key, with its type, range, default and unit, in one
place (pydantic v2). ``colonna schema`` prints it as JSON Schema for editors (e.g. Taplo /
Even Better TOML) and ``colonna schema --markdown`` as the key list of docs/study-file.md.

A study file is parsed by :func:`parse`; its errors all come at once, as one :class:`InputError`
of one line per error naming the key path (``column.height``, ``collar[2].y``: collars counted
from 1) and what is allowed. Ranges that depend on other keys (a collar within the column height,
the mesh size within the width of a half) are checked here too (each table's :meth:`Table.across`),
also where another key failed; the ones that need the column's physics (a pulse above the uplift
acceleration) are checked where the ground motion is built (:mod:`studies.fem_study`).
"""

from __future__ import annotations

import copy
import difflib
import math
from typing import TYPE_CHECKING, Annotated, Any, Literal, get_origin

from pydantic import (
    BaseModel,
    ConfigDict,
    Field,
    TypeAdapter,
    ValidationError,
    create_model,
    field_validator,
    model_validator,
)

from ..core.collar import LOWEST as COLLAR_LOWEST
from ..core.collar import MAX_FIBRES, MAX_SECTIONS, STEELS
from ..core.collar import Collar as CollarLaw
from ..core.constants import STANDARD_GRAVITY, STEEL_E, STEEL_EPS_U, STEEL_FY
from ..core.errors import InputError, read_toml
from ..fem.bed import BED_PRESETS, DEFAULT_BED, STIFFNESS_RANGE, YIELD_PRESSURE_RANGE
from ..fem.solver import EDGE_TIME, REPLICAS
from ..fem.toe_stress import REFINEMENTS
from ..rigid import collars as rigid_collars
from ..rigid.block import OMEGA_RATIO_RANGE
from .kinds import DEFAULT_KIND, KINDS, kind_tables
from .stone_presets import MARBLE, with_preset
from .stone_presets import PRESETS as STONE_PRESETS

G = STANDARD_GRAVITY  # m/s^2, the gravity of every study


FAILED = object()  # in a table's view (Table.across): a key whose value failed its own check
LONGEST = 3600.0  # s: the longest run or motion (the longest records last a few minutes)


def quantity(
    unit: str,
    description: str,
    default: Any = None,
    plausible: tuple[float, float, str, str] | None = None,
    **limits,
) -> Any:
    """A field with its unit (SI) and limits (gt, ge, lt, le), shown in the JSON Schema.

    ``plausible`` = (low, high, shown in, of what): the range (SI) in which the value of a real
    column lies, written in another unit (``GPa``) for people. Outside it the study stops with
    the likely unit slip (:func:`implausible`) unless the key is listed in [study] intended;
    the description says so, and the JSON Schema carries it as ``plausible``."""
    extra: dict[str, Any] = {"unit": unit}
    if plausible is not None:
        low, high, shown, what = plausible
        extra["plausible"] = {"range": [low, high], "shown_in": shown, "of": what}
        description += (
            f" Plausible: {'up to ' if low == 0.0 else ''}{_range_words(low, high, shown)} "
            f"({what}); outside it an error, unless the key is in [study] intended."
        )
    return Field(default, description=description, json_schema_extra=extra, **limits)


# units a number may have been written in by mistake, by the SI unit of its key: (name, SI per
# one of it). A value outside its plausible range is read in each; one that lands inside is
# suggested ("did you mean 275 MPa?").
UNIT_SLIPS: dict[str, tuple[tuple[str, float], ...]] = {
    "Pa": (("kPa", 1e3), ("MPa", 1e6), ("GPa", 1e9)),
    "m": (("mm", 1e-3), ("cm", 1e-2)),
    "kg/m^3": (("g/cm^3", 1e3),),
    "s": (("ms", 1e-3),),
    "m/s^2": (("cm/s^2", 1e-2),),
}
SHOWN_IN = {"GPa": 1e9, "MPa": 1e6, "kPa": 1e3, "mm": 1e-3, "cm": 1e-2, "ms": 1e-3}


def _number(value: float) -> str:
    """A number as people write it: 50000, 0.008, 5e10 (not 5e+10)."""
    text = f"{value:.6g}"
    if "e" in text:
        mantissa, exponent = text.split("e")
        text = f"{mantissa}e{int(exponent)}"
    return text


def _range_words(low: float, high: float, shown: str) -> str:
    """'1-200 GPa'; 'at most 50 m/s^2 in size' for a range from 0 of a signed key."""
    factor = SHOWN_IN.get(shown, 1.0)
    unit = "" if shown == "-" else f" {shown}"  # a pure number: no unit
    if low == 0.0:
        return f"{_number(high / factor)}{unit} in size"
    return f"{_number(low / factor)}-{_number(high / factor)}{unit}"


class Table(BaseModel):
    """A TOML table: unknown keys are errors, numbers are finite, no type coercion (a string or
    a boolean is never a number)."""

    model_config = ConfigDict(extra="forbid", strict=True, allow_inf_nan=False, frozen=True)

    @staticmethod
    def across(view: dict, given: set) -> list[tuple[str, tuple]]:
        """The errors across keys of the table: (message, the key paths a "required" message
        asks for), from its ``view`` (key -> value: its default where not given, FAILED where
        it failed its own check; a check that reads a FAILED key is skipped) and the keys
        ``given``."""
        return []

    @model_validator(mode="after")
    def _across_keys(self):
        found = self.across(self.model_dump(), self.model_fields_set)
        if found:
            raise ValueError("\n".join(message for message, _ in found))
        return self


class Column(Table):
    """[column]: the column's geometry and the load it carries."""

    height: float = quantity(
        "m",
        "Height of the column shaft; 1 cm to 100 m (beyond, no column: the mesh and the time "
        "step leave what the models are built for).",
        ...,
        (0.3, 30.0, "m", "a stone column"),
        ge=0.01,
        le=100,
    )
    width: float = quantity(
        "m",
        "Width (diameter) of the column, 4b; 1 mm to 20 m (as the height).",
        ...,
        (0.05, 5.0, "m", "a stone column"),
        ge=0.001,
        le=20,
    )
    thickness: float | None = quantity(
        "m",
        "Out-of-plane thickness of the 2D model; default pi * width / 4 (the half column "
        "then has the mass of a half circular column); 1 mm to 20 m (as the width).",
        None,
        (0.05, 5.0, "m", "a stone column"),
        ge=0.001,
        le=20,
    )
    cracked: bool = Field(
        True, description="A full-height vertical crack splits the column into two halves."
    )
    crack: list[float] | None = Field(
        None,
        min_length=2,
        max_length=2,
        description="Where the vertical crack of a cracked column runs in the FEM, [from, to] "
        "heights (m): [2.0, 4.0] from the top of a 4 m column down to 2 m, [0, 1.5] from the "
        "base up, [1, 3] between two heights; 0 <= from <= to <= height; default the full "
        "height. The rest of the mid-plane is intact stone that can crack ([stone] ft, Gf: "
        "a cohesive interface); from = to leaves no crack. The rigid models see the column "
        "fully split (the paper's hypothesis).",
        json_schema_extra={"unit": "m"},
    )
    crack_depth: float = quantity(
        "-",
        "Fraction of the column's thickness (out of plane) that the crack runs through, over "
        "its extent ([column] crack, or the full height), 0 < d <= 1; default 1, a through "
        "crack. Below 1 the FEM keeps an intact ligament of (1 - d) of the thickness along the "
        "crack, with the stone's cohesive law ([stone] ft, Gf): a smeared 2D idealisation of "
        "a part-depth crack (docs/physics.md). The rigid models see the column fully split.",
        1.0,
        gt=0,
        le=1,
    )
    top_load: float = quantity(
        "N",
        "Dead load on the capital (architrave), without mass: a "
        "uniform pressure on the top in the FEM, half at the top of each "
        "rigid half.",
        0.0,
        ge=0,
    )

    @staticmethod
    def across(c: dict, given: set) -> list[tuple[str, tuple]]:
        """The crack's heights within the column, in order, on a cracked column; its depth
        on a cracked column."""
        crack, height = c["crack"], c["height"]
        depth = c.get("crack_depth", 1.0)
        if known(depth, c["cracked"]) and float(depth) < 1.0 and not c["cracked"]:
            return [("column.crack_depth needs column.cracked = true (a column with a crack)", ())]
        if crack is None or not known(crack):
            return []
        if known(c["cracked"]) and not c["cracked"]:
            return [("column.crack needs column.cracked = true (a column with a crack)", ())]
        low, high = crack
        if not known(height):
            return []
        if not 0.0 <= low <= high <= height:
            return [
                (
                    f"column.crack = [{low:g}, {high:g}] m is outside the allowed range: "
                    f"0 <= from <= to <= {height:g} m (the column height)",
                    (),
                )
            ]
        return []


class Stone(Table):
    """[stone]: linear elastic stone (defaults: a white marble)."""

    preset: Literal[tuple(STONE_PRESETS)] | None = Field(  # type: ignore[valid-type]
        None,
        description="A stone whose values fill the keys of [stone] not given (a key given "
        "overrides it): "
        + "; ".join(
            f"{name}: " + ", ".join(f"{k} {v:g}" for k, v in values.items())
            for name, values in STONE_PRESETS.items()
        )
        + " (SI; studies/stone_presets.py gives each value's source; docs/physics.md the "
        "ranges). Without one, the defaults are the marble's.",
    )

    @model_validator(mode="before")
    @classmethod
    def _preset(cls, data):
        """The preset's values where the table does not give the key."""
        return with_preset(data) if isinstance(data, dict) else data

    E: float = quantity(
        "Pa",
        "Young's modulus; 1 MPa to 100 TPa (100 times diamond's, room for a stiff-limit "
        "study; beyond, the stiffness overflows the stable-step estimate).",
        MARBLE["E"],
        (1e9, 200e9, "GPa", "stone"),
        ge=1e6,
        le=1e14,
    )
    nu: float = quantity("-", "Poisson's ratio.", MARBLE["nu"], ge=0, lt=0.5)
    density: float = quantity(
        "kg/m^3",
        "Density; 100 to 30000 kg/m^3 (from the lightest solids to past osmium; beyond, the "
        "mass overflows the stable-step estimate).",
        MARBLE["density"],
        (1000.0, 4000.0, "kg/m^3", "stone"),
        ge=100,
        le=30000,
    )
    fc: float = quantity(
        "Pa",
        "Compressive strength, for the toe-crushing check.",
        MARBLE["fc"],
        (1e6, 500e6, "MPa", "stone"),
        gt=0,
    )
    ft: float = quantity(
        "Pa",
        "Tensile strength of the intact stone, the cohesive mid-plane of a partial crack "
        "([column] crack); default 8 MPa, a white marble in direct tension (about half its "
        "14.9 MPa in bending); granite 5-15 MPa, 10 MPa in the granite example "
        "docs/stones/granite.toml (docs/physics.md gives the sources).",
        MARBLE["ft"],
        (0.5e6, 40e6, "MPa", "stone in tension"),
        gt=0,
    )
    Gf: float = quantity(
        "N/m",
        "Fracture energy of the intact stone (mode I; mode II taken equal), the cohesive "
        "mid-plane's; default 40 N/m (marble 5-45, granite 7-90 N/m as K_IC^2 / E, a lower "
        "bound; docs/physics.md; 60 N/m in docs/stones/granite.toml, twice its K_IC^2 / E'); "
        "0.1 to 100000 N/m.",
        MARBLE["Gf"],
        gt=0.1,
        le=1e5,
    )
    KIC: float = quantity(
        "Pa m^0.5",
        "Fracture toughness, against which the crack tip's stress intensity K_I is judged; "
        "default 1 MPa m^0.5 (marble 0.5-1.5, granite 0.7-1.9 MPa m^0.5; docs/physics.md; "
        "1.3 MPa m^0.5 in docs/stones/granite.toml); 1 kPa m^0.5 to 100 MPa m^0.5.",
        MARBLE["KIC"],
        ge=1e3,
        le=1e8,
    )


class Collar(Table):
    """[[collar]]: one steel collar (flat bar around the column), counted from 1."""

    y: float = quantity(
        "m",
        "Height of the collar above the base, from 1 mm (a row of nodes is placed there: one "
        "nearer the base leaves an element of no height) to the column height.",
        ...,
        ge=COLLAR_LOWEST,
    )
    t: float = quantity(
        "m",
        "Section thickness (radial), at most 1 m.",
        ...,
        (1e-3, 0.2, "mm", "a steel collar's section"),
        gt=0,
        le=1,
    )
    h: float = quantity(
        "m",
        "Section height (vertical), at most 1 m.",
        ...,
        (1e-3, 0.2, "mm", "a steel collar's section"),
        gt=0,
        le=1,
    )
    length: float | None = quantity(
        "m",
        "Span between the attachment points; default the column width; 1 mm to 100 m (a "
        "shorter span makes the collar's stiffness E A / L overflow the stable step).",
        None,
        (0.05, 10.0, "m", "a collar's span"),
        ge=1e-3,
        le=100,
    )
    E: float = quantity(
        "Pa",
        "Young's modulus of the steel, at most 100 TPa (as the stone's).",
        STEEL_E,
        (150e9, 250e9, "GPa", "structural steel"),
        gt=0,
        le=1e14,
    )
    fy: float = quantity(
        "Pa",
        "Yield stress of the steel.",
        STEEL_FY,
        (100e6, 1000e6, "MPa", "structural steel"),
        gt=0,
    )
    pretension: float = quantity(
        "N",
        "Axial pretension (tension positive), at most the yield force fy t h (past it the "
        "band has yielded before the column moves).",
        0.0,
        ge=0,
    )
    plastic: bool = Field(
        False,
        description="Bilinear elastic-plastic collars (FEM and "
        "multibody; the SDOF model stays elastic).",
    )
    Eh: float | None = quantity(
        "Pa", "Hardening (tangent) modulus past f_y, below E; default 0.01 E.", ge=0
    )
    eps_u: float = quantity(
        "-",
        "Ultimate (fracture) strain of a plastic collar's extreme fibre, above f_y / E; "
        "default 0.15, the elongation at failure EN 1993-1-1 3.2.2(1) requires of steel "
        "used in plastic analysis.",
        STEEL_EPS_U,
        gt=0,
        le=1,
    )
    hinge_length: float | None = quantity(
        "m",
        "Length of an end hinge's plastic zone, over which its rotation gives a fibre "
        "strain; default the section height h.",
        None,
        (1e-3, 1.0, "mm", "a collar's hinge"),
        gt=0,
    )
    section: Literal["fibre", "resultant"] | None = Field(
        None,
        description="Local law of a plastic collar: 'fibre' (the default) a fibre-section "
        "frame element (the depth h cut into n_fibres layers of uniaxial steel, n_sections "
        "Gauss-Lobatto sections along the span: yield spreads, hinges lengthen, fracture where "
        "a section's surface strain reaches eps_u); 'resultant' the faster lumped law (end "
        "hinges on the N-M surface: exact to first yield, past it its membrane force, moments "
        "and fracture slip are off, docs/collars.md). An elastic collar is exact with either.",
    )
    n_fibres: int = quantity(
        "-",
        f"Layers of a fibre section across the depth h, 2 to {MAX_FIBRES}.",
        CollarLaw.n_fibres,
        ge=2,
        le=MAX_FIBRES,
    )
    n_sections: int = quantity(
        "-",
        f"Integration sections of a fibre collar along its span (Gauss-Lobatto, the two ends "
        f"included), 2 to {MAX_SECTIONS}.",
        CollarLaw.n_sections,
        ge=2,
        le=MAX_SECTIONS,
    )
    steel: Literal[STEELS] = Field(  # type: ignore[valid-type]
        "bilinear",
        description="Uniaxial law of a fibre collar's steel: 'bilinear' (E, fy, Eh, with "
        "kinematic and isotropic hardening) or 'menegotto-pinto' (OpenSees's Steel02: E, fy, "
        "b = Eh / E, the curvature R0, cR1, cR2 and the isotropic hardening a1 .. a4).",
    )
    isotropic: float = quantity(
        "-",
        "Share of a fibre collar's hardening (Eh) that is isotropic, 0 to 1; the rest is "
        "kinematic (0, the default: the Bauschinger effect, a reversal yields 2 fy below the "
        "shifted centre).",
        0.0,
        ge=0,
        le=1,
    )
    R0: float = quantity(
        "-",
        "Menegotto-Pinto steel: the curvature of the transition from elastic to plastic, 1 to "
        "100 (OpenSees Steel02's R0).",
        CollarLaw.R0,
        ge=1,
        le=100,
    )
    cR1: float = quantity(
        "-",
        "Menegotto-Pinto steel: R's decay with the plastic excursion xi, R = R0 (1 - cR1 xi / "
        "(cR2 + xi)), 0 to below 1.",
        CollarLaw.cR1,
        ge=0,
        lt=1,
    )
    cR2: float = quantity(
        "-", "Menegotto-Pinto steel: R's decay constant cR2, above 0.", CollarLaw.cR2, gt=0
    )
    a1: float = quantity(
        "-",
        "Menegotto-Pinto steel: isotropic hardening in compression, the shift a1 (0: none).",
        CollarLaw.a1,
        ge=0,
    )
    a2: float = quantity(
        "-",
        "Menegotto-Pinto steel: isotropic hardening in compression, the strain scale a2.",
        CollarLaw.a2,
        gt=0,
    )
    a3: float = quantity(
        "-",
        "Menegotto-Pinto steel: isotropic hardening in tension, the shift a3 (0: none).",
        CollarLaw.a3,
        ge=0,
    )
    a4: float = quantity(
        "-",
        "Menegotto-Pinto steel: isotropic hardening in tension, the strain scale a4.",
        CollarLaw.a4,
        gt=0,
    )

    @staticmethod
    def across(c: dict, given: set) -> list[tuple[str, tuple]]:
        """The hardening modulus below E; a plastic collar's ultimate strain above its yield
        strain; the pretension at most the yield force."""
        found = []
        force = c["fy"] * c["t"] * c["h"] if known(c["fy"], c["t"], c["h"]) else None
        if known(c["pretension"]) and force is not None and c["pretension"] > force:
            found.append(
                (
                    f"pretension = {c['pretension']:g} N must be at most the yield force "
                    f"fy t h = {force:.4g} N (past it the band has yielded)",
                    (),
                )
            )
        if c["Eh"] is not None and known(c["Eh"], c["E"]) and c["Eh"] >= c["E"]:
            found.append((f"Eh = {c['Eh']:g} Pa must be below E = {c['E']:g} Pa", ()))
        if c["section"] == "fibre" and c["plastic"] is False:
            found.append(
                (
                    "section = 'fibre' needs plastic = true (an elastic collar's resultant "
                    "law is exact)",
                    (),
                )
            )
        if (
            c["plastic"] is True
            and known(c["eps_u"], c["fy"], c["E"])
            and c["eps_u"] <= c["fy"] / c["E"]
        ):
            found.append(
                (
                    f"eps_u = {c['eps_u']:g} must be above the yield strain "
                    f"fy / E = {c['fy'] / c['E']:.3g} (a plastic collar yields before it "
                    "breaks)",
                    (),
                )
            )
        return found


PULSE_PAIRS = (("amplitude", "amplitude_ratio"), ("period", "omega_ratio"))
RECORD_SCALES = ("scale", "scale_to_pga", "scale_to_pgv")  # a record's factor: one of them
HORIZONTAL = (
    "amplitude",
    "amplitude_ratio",
    "period",
    "omega_ratio",
    "record",
    *RECORD_SCALES,
    "time_scale",
)


class Ground(Table):
    """[ground]: the horizontal ground motion (a pulse, a record or none) and an optional
    vertical one (harmonic or a record). Ratios refer to the rocking half."""

    pulse: Literal["sine", "cosine", "record", "none"] = Field(
        "sine",
        description="One-sine or one-cosine pulse, a record (file), or none (free "
        "rocking from run.initial_tilt or run.initial_angular_velocity).",
    )
    amplitude: float | None = quantity(
        "m/s^2",
        "Pulse amplitude a_p (sign: direction), "
        "|a_p| at least the uplift acceleration and at most 1000 m/s^2 (100 g: no ground "
        "shakes so; 1e308 overflowed the FEM); or give amplitude_ratio.",
        None,
        (0.0, 50.0, "m/s^2", "a ground motion (5 g)"),
        ge=-1000,
        le=1000,
    )
    amplitude_ratio: float | None = quantity(
        "-",
        "a_p / (g tan alpha (1 + lambda)) of the rocking half, 1 to 1000 (far past any "
        "ground motion; 1e308 overflowed the FEM); or give amplitude.",
        ge=1,
        le=1000,
    )
    period: float | None = quantity(
        "s",
        "Pulse period T_p, at most 1000 s (the run lasts as long); or give omega_ratio.",
        None,
        (0.02, 30.0, "s", "a pulse"),
        gt=0,
        le=1000,
    )
    omega_ratio: float | None = quantity(
        "-",
        "Omega / p of the rocking half, 0.001 to 1000 (a smaller one is a pulse thousands of "
        "rocking periods long); or give period.",
        ge=OMEGA_RATIO_RANGE[0],
        le=OMEGA_RATIO_RANGE[1],
    )
    record: str | None = Field(
        None,
        min_length=1,
        description="Record file (PEER .AT2 or ESM ASCII, its units from its header, or two "
        "columns t (s), a (m/s^2)), relative to the study file; pulse = record.",
    )
    scale: float | None = quantity(
        "-",
        "Factor on the record's acceleration (default 1), at most 1000 in size.",
        ge=-1000,
        le=1000,
    )
    scale_to_pga: float | None = quantity(
        "m/s^2",
        "Scale the record so that its peak ground acceleration is this, in place of scale "
        "(the factor, this over the file's PGA, is on record).",
        None,
        (0.0, 50.0, "m/s^2", "a ground motion (5 g)"),
        gt=0,
        le=1000,
    )
    scale_to_pgv: float | None = quantity(
        "m/s",
        "Scale the record so that its peak ground velocity is this, in place of scale: the "
        "PGV of the motion as applied, as the fragility's (the factor is on record).",
        None,
        (0.0, 5.0, "m/s", "a ground motion"),
        gt=0,
        le=100,
    )
    time_scale: float | None = quantity(
        "-",
        "Plays the record this many times as fast (default 1), 0.001 to 1000.",
        ge=1e-3,
        le=1000,
    )
    vertical_amplitude: float | None = quantity(
        "m/s^2",
        "Vertical harmonic a_v sin(2 pi t / T + phase), upward positive; |a_v| below "
        "g (at g the ground falls away from the column).",
        gt=-G,
        lt=G,
    )
    vertical_period: float | None = quantity(
        "s",
        "Period T of the vertical harmonic, at most 1000 s.",
        None,
        (0.02, 30.0, "s", "a ground motion"),
        gt=0,
        le=1000,
    )
    vertical_phase: float | None = quantity("rad", "Phase of the vertical harmonic (default 0).")
    vertical_duration: float | None = quantity(
        "s",
        "How long the vertical harmonic lasts (default: as long as the horizontal motion), "
        "at most an hour (as run.duration).",
        gt=0,
        le=LONGEST,
    )
    vertical_record: str | None = Field(
        None,
        min_length=1,
        description="Vertical record file (as record), instead of the harmonic.",
    )
    vertical_scale: float | None = quantity(
        "-", "Factor on the vertical record (default 1); its peak times this factor below g."
    )

    @field_validator("vertical_amplitude", mode="before")
    @classmethod
    def _on_the_ground(cls, value):
        """|a_v| >= g: the ground falls away from the column (said in words, not as a range)."""
        if (
            isinstance(value, (int, float))
            and not isinstance(value, bool)
            and math.isfinite(value)
            and abs(value) >= G
        ):
            size = "it" if value > 0 else "its size"
            raise ValueError(
                f"ground.vertical_amplitude = {value:g} m/s^2 lifts the column off "
                f"the ground: {size} must be below g = {G:g} m/s^2"
            )
        return value

    @staticmethod
    def across(g: dict, given: set) -> list[tuple[str, tuple]]:
        """The keys that go with the pulse kind, and with a vertical harmonic or record."""
        given = {k for k in given if g[k] is not None}  # a FAILED key is given
        pulse, found = g["pulse"], []
        if pulse == "none":
            found += _none_of(given, HORIZONTAL, "with pulse = 'none'")
        elif pulse == "record":
            if "record" not in given:
                found.append(
                    ("ground.record (a file) is required with pulse = 'record'", ("ground.record",))
                )
            found += _none_of(
                given,
                ("amplitude", "amplitude_ratio", "period", "omega_ratio"),
                "with pulse = 'record' (use scale and time_scale)",
            )
            scales = [k for k in RECORD_SCALES if k in given]
            if len(scales) > 1:
                found.append(
                    (
                        f"give only one of ground.{', ground.'.join(scales)} (each sets the "
                        "record's factor)",
                        tuple(f"ground.{k}" for k in scales),
                    )
                )
        elif pulse is not FAILED:
            found += _none_of(
                given, ("record", *RECORD_SCALES, "time_scale"), f"with pulse = '{pulse}'"
            )
            for pair in PULSE_PAIRS:
                if len(given & set(pair)) > 1:
                    found.append((f"give only one of ground.{pair[0]} and ground.{pair[1]}", ()))
        vertical = {k for k in given if k.startswith("vertical_")}
        if "vertical_record" in vertical:
            found += _none_of(
                vertical,
                ("vertical_amplitude", "vertical_period", "vertical_phase", "vertical_duration"),
                "with ground.vertical_record",
            )
        elif vertical:
            for key in ("vertical_amplitude", "vertical_period"):
                if key not in vertical:
                    found.append(
                        (
                            f"ground.{key} is required for a vertical harmonic (or give "
                            "ground.vertical_record)",
                            (f"ground.{key}",),
                        )
                    )
            found += _none_of(vertical, ("vertical_scale",), "without ground.vertical_record")
        return found


def _none_of(given: set, keys, why: str) -> list[tuple[str, tuple]]:
    """One error for each key of ``keys`` given."""
    return [(f"ground.{key} has no meaning {why}", ()) for key in sorted(given & set(keys))]


def known(*values) -> bool:
    """Whether none of the values failed its own check (a check across keys may read them)."""
    return all(value is not FAILED for value in values)


class Contact(Table):
    """[contact]: frictional contact at the base (penalty springs on the bed, [base]) and along
    the crack (exact, or penalty: enforcement) in the FEM; the friction also in the multibody
    model. The base's normal stiffness is the bed's ([base]); the penalty keys set the crack's
    (with enforcement = "penalty")."""

    friction: float = quantity("-", "Coulomb friction coefficient (base and crack).", 0.7, ge=0)
    penalty_factor: float = quantity(
        "-",
        "Factor on the crack's default penalty, 0.001 to 1000 (softer, the faces sink into each "
        "other; stiffer, the stable step shrinks with its square root).",
        1.0,
        ge=1e-3,
        le=1e3,
    )
    penalty: float | None = quantity(
        "N/m^3",
        "Crack penalty per unit contact area; overrides penalty_factor; 1e6 to 1e18 N/m^3 (the "
        "default E / h is about 1e12 for stone).",
        ge=1e6,
        le=1e18,
    )
    damping: float = quantity(
        "-",
        "Fraction of critical damping of each contact spring: the bed's (its own loss, 2 zeta "
        "sqrt(k m) a base node) and, with the penalty crack, the crack's. From 1 % to 20 % the "
        "uncollared column's first swing moves by at most 1.2 % (docs/validation.md); an "
        "undamped bed rings at its contact frequency and moved it by 4.2 % on one mesh, and no "
        "bed is undamped.",
        0.05,
        plausible=(0.01, 0.2, "-", "a bed's contact damping, a fraction of critical"),
        ge=0,
        lt=1,
    )
    friction_filter: float = quantity(
        "s",
        "Time constant of the low-pass filter on the normal "
        "force that sets the friction cone (0: none), at most 1 s (longer than a rocking "
        "swing: the cone would never follow the contact).",
        1e-3,
        ge=0,
        le=1,
    )
    enforcement: Literal["penalty", "lagrange"] = Field(
        "lagrange",
        description="How the crack's contact is enforced: lagrange, exact (forward-increment "
        "Lagrange multipliers with Coulomb friction, Carpenter, Taylor & Katona 1991; no "
        "penalty, damping nor filter at the crack), or penalty springs (penalty_factor or "
        "penalty, damping, friction_filter). damping and friction_filter set the base's "
        "contact too, whose stiffness is the bed's ([base]).",
    )

    @staticmethod
    def across(c: dict, given: set) -> list[tuple[str, tuple]]:
        """The crack's penalty keys act only with its penalty enforcement: given under the
        exact contact they would change nothing, silently."""
        if c["enforcement"] != "lagrange":
            return []
        return [
            (
                f"contact.{key} sets the crack's penalty, which acts only with contact."
                f'enforcement = "penalty" (the default, "lagrange", is exact and has none; the '
                "base's stiffness is [base]'s): remove it, or set the enforcement",
                (),
            )
            for key in ("penalty_factor", "penalty")
            if key in given and known(c[key])
        ]


class Base(Table):
    """[base]: the bed the column stands on (FEM): its stiffness per unit area, k = E_bed /
    t_bed, held fixed when the mesh is refined; the range's ends give the toe answer's spread
    (colonna.fem.bed says where each preset's numbers come from)."""

    bed: Literal[tuple(BED_PRESETS)] = Field(  # type: ignore[valid-type]
        DEFAULT_BED,
        description="The bed: "
        + "; ".join(
            f"{name}, k {p.stiffness_range[0]:.2g}-{p.stiffness_range[1]:.2g} N/m^3 "
            f"(nominal {p.stiffness:.2g})"
            for name, p in BED_PRESETS.items()
        )
        + ". A given stiffness overrides it.",
    )
    stiffness: float | None = quantity(
        "N/m^3",
        "Bed stiffness per unit area, E_bed / t_bed; overrides the preset; 1e6 to 1e18 N/m^3.",
        ge=STIFFNESS_RANGE[0],
        le=STIFFNESS_RANGE[1],
    )
    stiffness_range: list[float] | None = quantity(
        "N/m^3",
        "[low, high]: the uncertainty range of a given stiffness, around it; default the "
        "stiffness alone.",
        min_length=2,
        max_length=2,
    )
    plastic: bool | None = Field(
        None,
        description="Whether the bed yields (elastic-perfectly plastic: the pressure capped at "
        "its yield pressure, the indentation kept): default true for lead (5-40 MPa, nominal "
        "14 MPa), false for mortar (1-20 MPa when true) and stone (no yield of its own).",
    )
    yield_pressure: float | None = quantity(
        "Pa",
        "The bed's yield pressure, in place of its preset's; the bed then yields. 0.1 MPa to "
        "10 GPa.",
        None,
        (5e5, 5e8, "MPa", "a bed's yield pressure"),
        ge=YIELD_PRESSURE_RANGE[0],
        le=YIELD_PRESSURE_RANGE[1],
    )

    @staticmethod
    def across(b: dict, given: set) -> list[tuple[str, tuple]]:
        """A range goes with a given stiffness and lies around it, within 1e6-1e18 N/m^3."""
        value, k = b["stiffness_range"], b["stiffness"]
        if not known(value, k) or value is None:
            return []
        if k is None:
            return [("base.stiffness_range goes with a given base.stiffness", ())]
        low, high = value
        if not (STIFFNESS_RANGE[0] <= low <= k <= high <= STIFFNESS_RANGE[1]):
            return [
                (
                    f"base.stiffness_range = {value!r} must hold base.stiffness = {k:g} "
                    f"within [1e6, 1e18] N/m^3",
                    (),
                )
            ]
        return []


class Mesh(Table):
    """[mesh]: the FEM mesh, generated (size, grading) or read from a file."""

    size: float | None = quantity(
        "m", "Element size; default width / 16; at most the width of one half.", gt=0
    )
    grading: float = quantity(
        "-", "Grading toward the base and crack (0: uniform).", 0.5, ge=0, lt=1
    )
    edge_length: float | None = quantity(
        "m",
        "Toe length over which the edge stress is averaged; default 0.1 x the width of a half.",
        gt=0,
    )
    edge_time: float = quantity(
        "s", "Time over which the toe stress is averaged.", EDGE_TIME, ge=0, le=0.01
    )
    toe_size: float | None = quantity(
        "m",
        "Element size at the base corners, graded over the toe window (edge_length) and "
        "beyond; default none. The report gives the size that resolves the bed's contact "
        "zone (a quarter of its length at half the slenderness); the time step shrinks with it; "
        "at least 1e-5 m (0.01 mm: about 1e8 steps a second of motion).",
        ge=1e-5,
    )
    toe_refinements: list[int] = Field(
        list(REFINEMENTS),
        description="The impact that gives "
        "the peak toe stress is rerun with the toe zones refined "
        "so many times: [] or [1, 2, 4] up to [1, 2, 4, 8, 16].",
    )
    file: str | None = Field(
        None,
        min_length=1,
        description="A quadrilateral mesh made elsewhere (e.g. "
        "gmsh .msh), relative to the study file, instead of size/grading.",
    )

    @staticmethod
    def across(m: dict, given: set) -> list[tuple[str, tuple]]:
        """The toe refinements: powers of two from 1."""
        value = m["toe_refinements"]
        if (
            known(value)
            and value
            and (len(value) < 3 or value[-1] > 16 or value != [2**k for k in range(len(value))])
        ):
            return [
                (
                    f"mesh.toe_refinements = {value!r} must be [] or [1, 2, 4] or "
                    "[1, 2, 4, 8] or [1, 2, 4, 8, 16]",
                    (),
                )
            ]
        return []


class Run(Table):
    """[run]: the explicit time integration."""

    duration: float | None = quantity(
        "s",
        "Simulated time; default the end of the ground motion + 1.5 s; at most an hour (the "
        "longest records last a few minutes; the work is bounded too: see --long).",
        gt=0,
        le=LONGEST,
    )
    output_interval: float | None = quantity(
        "s", "Time between history rows; default duration / 400.", gt=0
    )
    dt: float | None = quantity(
        "s",
        "Time step; default the stable step (a larger one is an error); at least 1e-9 s "
        "(below, a second of motion is a billion steps).",
        ge=1e-9,
    )
    safety: float = quantity("-", "Fraction of the stable step used.", 0.9, gt=0, le=1)
    initial_tilt: float = quantity(
        "rad",
        "Release tilt about the outer toe (> 0 toward +x).",
        0.0,
        gt=-math.pi / 4,
        lt=math.pi / 4,
    )
    initial_angular_velocity: float = quantity(
        "rad/s",
        "Initial angular velocity about that toe, at most 10 rad/s in size (at 5 rad/s even "
        "a 0.3 m block overturns at once; at 30 rad/s the FEM stops as blown up at its first "
        "check).",
        0.0,
        ge=-10,
        le=10,
    )
    replicas: int = quantity(
        "-",
        "Replicas of each FEM run whose initial positions differ by "
        "1e-12 of the column height: landing-dependent numbers are reported "
        "as median and range over them (the contact is chaotic at "
        "landings). The spectrum cross-check's grid points run one each "
        "unless set.",
        REPLICAS,
        ge=1,
        le=64,
    )

    @staticmethod
    def across(r: dict, given: set) -> list[tuple[str, tuple]]:
        """An output interval no longer than the run (the run ends on a whole interval)."""
        d, k = r["duration"], r["output_interval"]
        if d is not None and k is not None and known(d, k) and k > d:
            return [
                (
                    f"output_interval = {k:g} s must be at most duration = {d:g} s "
                    "(the run ends on a whole output interval)",
                    (),
                )
            ]
        return []


class Rigid(Table):
    """[rigid]: options of the rigid models."""

    restitution: float | None = quantity(
        "-",
        "Coefficient of restitution of the SDOF model; default Housner's 1 - 1.5 sin^2 alpha.",
        ge=0,
        le=1,
    )


HAZARD_MEASURES = ("pga", "pgv", "sa")  # a power-law hazard's intensity (colonna.core.hazard)


class Hazard(Table):
    """[hazard] (optional, shared): the site's hazard curve, a table file or a power law; a
    fragility study gives with it each limit state's mean annual frequency and its probability
    in hazard.years (colonna.core.risk); other kinds do not read it yet."""

    file: str | None = Field(
        None,
        min_length=1,
        description="Hazard table, a CSV relative to the study file: a header naming the "
        "intensity measure and unit, then annual_frequency (e.g. pga_g,annual_frequency; pga_m_s2, "
        "pgv_m_s, sa_0.5s_g, ...), one row per return period; interpolated log-log. "
        "Or the power law k0, k.",
    )
    intensity: Literal[HAZARD_MEASURES] | None = Field(  # type: ignore[valid-type]
        None,
        description="The power law's intensity measure: pga (m/s^2), pgv (m/s), sa (m/s^2, with "
        "period); a table's header names its own.",
    )
    period: float | None = quantity(
        "s", "Period of Sa (the power law with intensity = sa), 0.01 to 20 s.", ge=0.01, le=20
    )
    k0: float | None = quantity(
        "1/year",
        "Power law lambda = k0 IM^-k (IM in SI): its k0, the frequency at IM = 1.",
        gt=0,
        le=1e6,
    )
    k: float | None = quantity("-", "Power law's exponent k, (0, 20].", gt=0, le=20)
    years: float = quantity(
        "year", "Period T of the probability 1 - exp(-lambda T), (0, 10000].", 50.0, gt=0, le=1e4
    )
    beyond: Literal["extrapolate", "truncate"] = Field(
        "extrapolate",
        description="A table above its highest intensity: extrapolate (the power law of its "
        "last segment) or truncate (every exceedance of the highest counted there: a lower "
        "bound); below its lowest it is held at that frequency (a lower bound). The report says "
        "how much of each lambda lies beyond either end.",
    )

    @staticmethod
    def across(h: dict, given: set) -> list[tuple[str, tuple]]:
        """A file, or the power law k0, k and intensity (with period for Sa), not both."""
        law = given & {"k0", "k", "intensity", "period"}
        if h["file"] is not None:
            if law:
                return [
                    (
                        f"hazard.file goes without {', '.join(f'hazard.{k}' for k in sorted(law))}"
                        " (the file's header names its intensity measure)",
                        (),
                    )
                ]
            return []
        found: list[tuple[str, tuple]] = []
        missing = [k for k in ("k0", "k", "intensity") if h[k] is None]
        if missing:
            found.append(
                (
                    "give hazard.file, or the power law hazard.k0, hazard.k and hazard.intensity",
                    tuple(f"hazard.{k}" for k in missing),
                )
            )
        if h["intensity"] == "sa" and h["period"] is None:
            found.append(("hazard.period is required with hazard.intensity = 'sa'", ()))
        if h["intensity"] not in ("sa", FAILED) and h["period"] is not None:
            found.append(("hazard.period goes with hazard.intensity = 'sa' only", ()))
        return found


class StudyInfo(Table):
    """[study]: what the file is."""

    name: str | None = Field(None, description="Name in reports; default the file name.")
    description: str | None = Field(None, description="Free text.")
    # the report's title block (page 1): they name the document, not the computation, so
    # they leave the saved cases valid (studies.executor.NOT_STUDY_INPUTS)
    project: str | None = Field(
        None, description="Project, in the report's title block; a blank line to fill if not given."
    )
    site: str | None = Field(None, description="Site (building, place), in the title block.")
    client: str | None = Field(None, description="Client, in the title block.")
    prepared_by: str | None = Field(
        None, description="Who prepared the study, beside its signature line in the title block."
    )
    checked_by: str | None = Field(
        None, description="Who checked it, beside its signature line in the title block."
    )
    revision: str | None = Field(
        None, description='Revision of the document, e.g. "A" or "1", in the title block.'
    )
    kind: str = Field(  # one of the registered kinds (study_model)
        DEFAULT_KIND, description="Which study to run."
    )
    intended: list[str] = Field(
        [],
        description="Keys whose values outside their plausible range are meant, as table.key "
        '(collar.t: every collar\'s), e.g. ["stone.E"] for a stiff-limit study; without it '
        "such a value is an error naming the likely unit slip.",
    )


def pair(default, description: str, unit: str = "-") -> Any:
    """A two-element list field ([start, stop] or two counts)."""
    return Field(
        default,
        min_length=2,
        max_length=2,
        description=description,
        json_schema_extra={"unit": unit},
    )


class StudyFile(Table):
    """A colonna study file (TOML). SI units throughout."""

    # the shared tables; a study's model (study_model) adds [study] kind's choices and the
    # kinds' own tables (studies/kinds.py), as attributes of the same names
    model_config = ConfigDict(title="colonna study file")

    if TYPE_CHECKING:  # a kind's table: study.spec.fragility

        def __getattr__(self, name: str) -> Any: ...

    study: StudyInfo = StudyInfo()
    column: Column | None = Field(
        None,
        description="Required, except for kind = "
        + " or ".join(f'"{name}"' for name, kind in KINDS.items() if not kind.column)
        + ".",
    )
    stone: Stone = Stone()
    collar: list[Collar] = Field([], description="Zero or more collars, each a [[collar]] table.")
    ground: Ground = Ground.model_construct(pulse="sine")
    contact: Contact = Contact()
    base: Base = Base()
    mesh: Mesh = Mesh()
    run: Run = Run()
    rigid: Rigid = Rigid()
    hazard: Hazard | None = None

    @classmethod
    def across(cls, s: dict, given: set) -> list[tuple[str, tuple]]:
        """The tables against each other (:meth:`_tables`), then every value against its
        plausible range, but those of the keys in [study] intended (:func:`implausible`), of
        the study's model ``cls`` (:func:`study_model`: with its kind's tables)."""
        info = s["study"]
        intended = info["intended"] if isinstance(info, dict) else FAILED
        return StudyFile._tables(s, given) + implausible(cls, s, intended, "[study] intended")

    @staticmethod
    def _tables(s: dict, given: set) -> list[tuple[str, tuple]]:
        """A column and a ground motion given, the collars within the column height, the mesh
        within the width of a half, no table of another kind's."""
        kind = s["study"]["kind"] if isinstance(s["study"], dict) else FAILED
        c, ground = s["column"], s["ground"]
        found: list[tuple[str, tuple]] = []
        for table in kind_tables():  # a table no code of this kind would read
            if table in given and isinstance(kind, str) and table not in KINDS[kind].tables:
                readers = [name for name, k in KINDS.items() if table in k.tables]
                found.append(
                    (
                        f"[{table}] is read by studies of kind {' or '.join(readers)} only, and "
                        f"this study is of kind {kind!r}: leave the table out, or set "
                        "[study] kind",
                        (),
                    )
                )
        if c is None:
            if not isinstance(kind, str) or not KINDS[kind].column:  # (a failed kind: maybe)
                return []
            found.append(
                ("column.height is required: the study has no [column] table", ("column",))
            )
        if "ground" not in given:
            if kind is not FAILED:  # (a failed kind may be free-rocking: none)
                found.append(
                    (
                        "the study has no [ground] table: give ground.pulse and, for a "
                        "pulse, exactly one of ground.amplitude and "
                        "ground.amplitude_ratio and one of ground.period and "
                        "ground.omega_ratio",
                        ("ground",),
                    )
                )
        elif (
            isinstance(ground, dict)
            and ground["pulse"] in ("sine", "cosine")
            and isinstance(kind, str)
            and not KINDS[kind].sets_pulse
        ):  # (its grid sets them)
            for pair in PULSE_PAIRS:
                if ground[pair[0]] is None and ground[pair[1]] is None:
                    found.append(
                        (
                            f"give exactly one of ground.{pair[0]} and ground.{pair[1]} "
                            f"for a {ground['pulse']} pulse",
                            tuple(f"ground.{key}" for key in pair),
                        )
                    )
        if not isinstance(c, dict):
            return found
        collars = s["collar"] if known(s["collar"]) else []
        for i, collar in enumerate(collars, start=1):
            if known(collar, c["height"]) and known(collar["y"]) and collar["y"] > c["height"]:
                found.append(
                    (
                        f"collar[{i}].y = {collar['y']:.10g} m is outside the allowed range "
                        f"[{COLLAR_LOWEST:g}, {c['height']:.10g}] m (the column height)",
                        (),
                    )
                )
        mesh = s["mesh"]
        if not known(c["width"], c["cracked"], mesh):
            return found
        half = c["width"] / (2.0 if c["cracked"] else 1.0)
        for key in ("size", "edge_length"):
            value = mesh[key]
            if value is not None and known(value) and value > half:
                found.append(
                    (
                        f"mesh.{key} = {value:g} m is outside the allowed range "
                        f"(0, {half:g}] m (the width of one half)",
                        (),
                    )
                )
        return found


_MODELS: dict[tuple, type[StudyFile]] = {}  # study_model's, by kind and registry


def study_model(
    kind: str | None = DEFAULT_KIND, *, given=(), every: bool = False
) -> type[StudyFile]:
    """The model of a study file of kind ``kind`` (a name of :data:`studies.kinds.KINDS`;
    None where the file's is none of them): the shared tables (:class:`StudyFile`), ``[study]
    kind`` one of the registered kinds, and the tables that kinds register
    (``StudyKind.tables``, each a model of its package's module ``schema``): ``kind``'s own
    and those ``given`` in the file checked by their models (another kind's table is refused
    too: :meth:`StudyFile._tables`), the others' not imported. ``every``: every kind's tables
    (the schema as documented: :func:`json_schema`, :func:`markdown`). Built on first use, and
    again once the registry has changed."""
    checked = tuple(
        name
        for name, k in KINDS.items()
        if every or name == kind or any(table in given for table in k.tables)
    )
    key = (checked, tuple((name, id(k)) for name, k in KINDS.items()))
    if key not in _MODELS:
        _MODELS[key] = _study_model(checked)
    return _MODELS[key]


def _study_model(checked: tuple[str, ...]) -> type[StudyFile]:
    """:func:`study_model` of the kinds whose tables are ``checked``, built (pydantic's
    create_model on :class:`StudyFile`)."""
    choices: Any = Literal[tuple(KINDS)]  # [study] kind: a registered kind
    info = create_model(
        "StudyInfo",
        __base__=StudyInfo,
        __doc__=StudyInfo.__doc__,
        kind=(choices, StudyInfo.model_fields["kind"]),
    )
    without = " or ".join(f'"{name}"' for name, k in KINDS.items() if not k.column)
    fields: dict[str, Any] = {
        "study": (info, info()),
        "column": (
            Column | None,
            Field(None, description=f"Required, except for kind = {without}."),
        ),
    }
    own: dict[str, type[Table]] = {}
    for name in checked:
        own.update(KINDS[name].table_models())
    for table in kind_tables():
        if table in StudyFile.model_fields:
            raise TypeError(f"a study kind registers [{table}], a shared table of the study file")
        model = own.get(table)
        if model is None:  # not given: a study that gives it is refused (StudyFile._tables)
            readers = " or ".join(name for name, k in KINDS.items() if table in k.tables)
            fields[table] = (
                dict[str, Any] | None,
                Field(None, description=f"Read by studies of kind {readers}."),
            )
        elif all(not f.is_required() for f in model.model_fields.values()):
            fields[table] = (model, model())
        else:  # a table with required keys: given, or none
            fields[table] = (model | None, None)
    return create_model("StudyFile", __base__=StudyFile, __doc__=StudyFile.__doc__, **fields)


def table_names() -> tuple[str, ...]:
    """The tables of a study file: the shared ones, then those of the kinds."""
    return (*StudyFile.model_fields, *kind_tables())


REMOVED = object()  # in variant(): leave this key or table out


def variant(data: dict, changes: dict[str, Any], source: str = "study") -> dict:
    """The tables of a study file with ``changes`` made (dotted key path -> value: "mesh.size",
    a whole table by its name, :data:`REMOVED` to leave one out), checked against the schema;
    ``data`` stays as it was. Every variant of a study (a mesh size, a pulse of a grid, the
    column without its collars) is made here, never by editing the study's dict in place."""
    out = copy.deepcopy(data)
    for path, value in changes.items():
        *tables, key = path.split(".")
        node = out
        for table in tables:
            node = node.setdefault(table, {})
        if value is REMOVED:
            node.pop(key, None)
        else:
            node[key] = copy.deepcopy(value)
    parse(out, source)
    return out


def parse(data: dict, source: str = "study") -> StudyFile:
    """The validated study, or an :class:`InputError` of one line per error, each naming its
    key: the model of its kind (:func:`study_model`), the kind its [study] kind names."""
    info = data.get("study") if isinstance(data, dict) else None
    kind = info.get("kind", DEFAULT_KIND) if isinstance(info, dict) else DEFAULT_KIND
    registered = isinstance(kind, str) and kind in KINDS
    given = tuple(data) if isinstance(data, dict) else ()
    return _validate(study_model(kind if registered else None, given=given), data, source)


class CollarFile(Table):
    """A collar file: [[collar]] tables, as in a study file, and the keys whose implausible
    values are meant (``intended = ["collar.fy"]``, before the tables)."""

    intended: list[str] = []
    collar: list[Collar] = []

    @staticmethod
    def across(s: dict, given: set) -> list[tuple[str, tuple]]:
        """Every value against its plausible range, but those of the keys in intended."""
        return implausible(CollarFile, s, s["intended"], "intended")


def plausible_keys(model: type[Table] | None = None) -> dict[str, dict]:
    """The keys with a plausible range ('stone.E' -> its range, the unit it is shown in, of
    what, and its SI unit), of a study file (or of the file ``model``)."""
    found: dict[str, dict] = {}
    for table, field in (model or study_model(every=True)).model_fields.items():
        inner = _find_model(field.annotation)
        for key, sub in (inner.model_fields if inner is not None else {}).items():
            extra = sub.json_schema_extra
            plausible = extra.get("plausible") if isinstance(extra, dict) else None
            if isinstance(extra, dict) and isinstance(plausible, dict):
                found[f"{table}.{key}"] = {**plausible, "unit": extra["unit"]}
    return found


def implausible(model: type[Table], s: dict, intended, where: str) -> list[tuple[str, tuple]]:
    """The values of the file's view ``s`` outside their plausible ranges, each with the unit
    slip that would bring it inside (a number written in MPa where Pa is read), but those of
    the keys in ``intended``; and a key of ``intended`` that has no plausible range."""
    keys = plausible_keys(model)
    found: list[tuple[str, tuple]] = []
    if not isinstance(intended, list):  # (it failed its own check)
        intended = []
    for name in intended:
        if name not in keys:
            found.append(
                (
                    f"{where}: {name!r} is not a key with a plausible range (those are: "
                    + ", ".join(keys)
                    + ")",
                    (),
                )
            )
    for name, p in keys.items():
        table, key = name.split(".")
        rows = s.get(table)
        if name in intended or not isinstance(rows, (dict, list)):
            continue
        for i, row in enumerate(rows if isinstance(rows, list) else [rows], start=1):
            value = row.get(key) if isinstance(row, dict) else None
            if isinstance(value, (int, float)) and not isinstance(value, bool):
                path = f"{table}[{i}].{key}" if isinstance(rows, list) else name
                line = _implausible_line(path, name, float(value), p, where)
                if line is not None:
                    found.append((line, ()))
    return found


def _implausible_line(path: str, name: str, value: float, p: dict, where: str) -> str | None:
    """The error of a value outside its plausible range ``p`` (:func:`plausible_keys`), or
    None; it says how to mean it: list the key in ``where``."""
    (low, high), unit = p["range"], p["unit"]
    if low <= (abs(value) if low == 0.0 else value) <= high:
        return None
    words = _range_words(low, high, p["shown_in"])
    given = _number(value) + ("" if unit == "-" else f" {unit}")
    text = (
        f"{path} = {given} is beyond the plausible {words} for {p['of']}"
        if low == 0.0
        else f"{path} = {given} is outside the plausible range {words} for {p['of']}"
    )
    slip = _slip(value, p)
    if slip is not None:
        text += f": {slip} If {given} is meant"
    else:
        text += ": if it is meant"
    return text + f', list "{name}" in {where}'


def _slip(value: float, p: dict) -> str | None:
    """'did you mean 275 MPa (2.75e8 Pa)?': the unit of :data:`UNIT_SLIPS` in which ``value``
    lands in its plausible range ``p`` (:func:`plausible_keys`; the one nearest the middle of
    the range), or None."""
    (low, high), unit = p["range"], p["unit"]
    size = low == 0.0  # a signed key: its size
    middle = math.sqrt(low * high) if low > 0.0 else 0.1 * high
    slips = [
        (abs(math.log(abs(value) * factor / middle)), other, factor)
        for other, factor in UNIT_SLIPS.get(unit, ())
        if value != 0.0 and (size or value > 0.0) and low <= abs(value) * factor <= high
    ]
    if not slips:
        return None
    _, other, factor = min(slips)
    return f"did you mean {_number(value)} {other} ({_number(value * factor)} {unit})?"


def read_collars(path) -> tuple[rigid_collars.Collar, ...]:
    """The collars of a TOML file of [[collar]] tables (keys as in a study file)."""
    spec = _validate(CollarFile, read_toml(path, "collar file"), str(path))
    if not spec.collar:
        raise InputError(
            f"{path}: a collar file needs at least one [[collar]] table (for a column without "
            "collars, leave the collar file out)"
        )
    return tuple(rigid_collars.Collar(**c.model_dump()) for c in spec.collar)


def _reader(name: str) -> str | None:
    """The first kind that registers the table ``name``, None for a shared table."""
    return next((kind for kind, k in KINDS.items() if name in k.tables), None)


def table_model(name: str) -> type[BaseModel]:
    """The model of a study file's table (``column``, ``collar``: one [[collar]], ``grid``:
    a kind's own, from its package: :func:`study_model`)."""
    return _model_of(study_model(_reader(name)).model_fields[name].annotation)


def parse_table(name: str, table, source: str = "study"):
    """One table of a study file (``grid``, ``convergence``, ...) checked on its own."""
    root = study_model(_reader(name))
    model = _model_of(root.model_fields[name].annotation)
    return _validate(model, table, source, within=(name,), root=root)


def _validate(model: type[Table], data, source: str, within: tuple = (), root=None):
    """``model`` validated from ``data``, or an :class:`InputError` of one line per error
    (:func:`_error_lines`). ``within``: the key path of ``data`` in the study file, whose
    model is ``root`` (``model`` itself where None and it is a study's, else a study of the
    default kind's)."""
    try:
        return model.model_validate(data)
    except ValidationError as exc:
        errors = exc.errors()
    if root is None:
        root = model if issubclass(model, StudyFile) else study_model()
    lines = _error_lines(model, data, errors, within, root)
    raise InputError("\n".join(f"{source}: {line}" for line in lines))


def _error_lines(
    model: type[Table], data, errors: list, within: tuple = (), root=None
) -> list[str]:
    """Every error of ``data``, one line each: pydantic's (the first bad item of a list of
    numbers only), then the checks across keys that it skipped because a key of their table
    failed (:func:`_view`). A key reported missing where an unknown key of its table looks like
    it is left out: the unknown key is its misspelling, one mistake."""
    root = root or study_model()
    found, lists = [], set()  # (line, unknown key path, key paths it asks for)
    for error in errors:
        loc = tuple(p for p in (*within, *error["loc"]) if not str(p).startswith("function"))
        if loc and isinstance(loc[-1], int) and _model_at(loc[:-1], root) is None:
            if loc[:-1] in lists:
                continue
            lists.add(loc[:-1])
        line = _one_line({**error, "loc": loc}, root)
        unknown = _path(loc) if error["type"] == "extra_forbidden" else None
        wanted = (_path(loc),) if error["type"] == "missing" else ()
        where = error["type"] == "value_error" and loc and isinstance(loc[-1], int)
        found += [
            (_in_table(loc, text) if where else text, unknown, wanted) for text in line.splitlines()
        ]
    if isinstance(data, dict):
        skipped: list[tuple[tuple, str, tuple]] = []
        _view(model, data, errors, (), skipped)
        found += [(_in_table((*within, *loc), text), None, wanted) for loc, text, wanted in skipped]
    unknown_keys = [key for _, key, _ in found if key]
    return [
        text for text, _, wanted in found if not any(_misspelt(key, unknown_keys) for key in wanted)
    ]


def _in_table(loc: tuple, text: str) -> str:
    """A check's message, prefixed with its table where that is one of a list (``collar[2]``:
    its message does not know which)."""
    return f"{_path(loc)}: {text}" if loc and isinstance(loc[-1], int) else text


def _misspelt(key: str, unknown: list[str]) -> bool:
    """Whether an unknown key of the table of ``key`` looks like it (``heigth``, ``grund``)."""
    table, _, name = key.rpartition(".")
    return any(
        u.rpartition(".")[0] == table
        and difflib.SequenceMatcher(None, u.rpartition(".")[2], name).ratio() >= 0.6
        for u in unknown
    )


def _view(model: type[Table], data: dict, errors: list, loc: tuple, skipped: list) -> dict:
    """The table ``data`` at ``loc`` as far as it passed (:meth:`Table.across`): each key's
    value, its default where not given, FAILED where it failed; a table within as its own
    view. Pydantic checks a table across its keys only when each of them passed: for a table
    where one failed, those checks run here, on the rest, into ``skipped``."""
    view = {}
    for name, field in model.model_fields.items():
        here, inner = (*loc, name), _find_model(field.annotation)
        many = get_origin(field.annotation) is list  # [[collar]]
        if name not in data:
            value = FAILED if field.is_required() else field.get_default(call_default_factory=True)
            view[name] = value.model_dump() if isinstance(value, BaseModel) else value
            continue
        value = data[name]
        if inner is not None and many and isinstance(value, list):
            view[name] = [
                _view(inner, item, errors, (*here, i), skipped)
                if isinstance(item, dict)
                else FAILED
                for i, item in enumerate(value)
            ]
        elif inner is not None and not many and isinstance(value, dict):
            view[name] = _view(inner, value, errors, here, skipped)
        else:
            failed = any(e["loc"][: len(here)] == here for e in errors)
            view[name] = FAILED if failed else value
    if any(len(e["loc"]) > len(loc) and e["loc"][: len(loc)] == loc for e in errors):
        given = set(data) & set(model.model_fields)
        skipped += [(loc, text, wanted) for text, wanted in model.across(view, given)]
    return view


def _path(loc) -> str:
    """('collar', 1, 'y') -> 'collar[2].y' (collars counted from 1, as in the file)."""
    text = ""
    for part in loc:
        text += f"[{part + 1}]" if isinstance(part, int) else ("." if text else "") + str(part)
    return text


def _one_line(error: dict, root: type[BaseModel]) -> str:
    """One error as a line naming its key path in the file of model ``root``."""
    kind, loc = error["type"], tuple(p for p in error["loc"] if not str(p).startswith("function"))
    if kind == "value_error":  # a model validator's own message names its keys
        return str(error["ctx"]["error"])
    if kind == "extra_forbidden":
        model = _model_at(loc[:-1], root)
        where = f"[{_path(loc[:-1])}]" if loc[:-1] else "the study file"
        allowed = ", ".join(model.model_fields) if model else ""
        what = "table" if not loc[:-1] else "key"
        return f"unknown {what} {_path(loc)} (allowed in {where}: {allowed})"
    field = _field_at(loc, root)
    allowed = describe(field) if field is not None else error["msg"].lower()
    if kind == "missing":
        return f"{_path(loc)} is required: {allowed}"
    text = f"{_path(loc)} = {error['input']!r} is not allowed: {allowed}"
    value, extra = error["input"], field.json_schema_extra if field is not None else None
    plausible = extra.get("plausible") if isinstance(extra, dict) else None
    if (
        isinstance(extra, dict)
        and isinstance(plausible, dict)
        and isinstance(value, (int, float))
        and not isinstance(value, bool)
        and math.isfinite(value)
    ):  # beyond the hard range by a unit slip: 8 (mm) for a collar's t, 50000 (MPa) for E
        slip = _slip(float(value), {**plausible, "unit": extra["unit"]})
        text += f"; {slip}" if slip is not None else ""
    return text


def _model_at(loc, root: type[BaseModel]) -> type[BaseModel] | None:
    model = root
    for part in loc:
        if isinstance(part, int):
            continue
        field = model.model_fields.get(part)
        inner = _find_model(field.annotation) if field else None
        if inner is None:
            return None
        model = inner
    return model


def _model_of(annotation) -> type[Table]:
    """The table model of a StudyFile field's annotation (a table, a list of them, or one or
    None)."""
    found = _find_model(annotation)
    if found is None:
        raise TypeError(f"{annotation!r} holds no table model")
    return found


def _find_model(annotation) -> type[Table] | None:
    if isinstance(annotation, type) and issubclass(annotation, Table):
        return annotation
    for arg in getattr(annotation, "__args__", ()):
        found = _find_model(arg)
        if found is not None:
            return found
    return None


def _field_at(loc, root: type[BaseModel]):
    names = [p for p in loc if not isinstance(p, int)]
    model = _model_at(loc[:-1] if not isinstance(loc[-1], int) else loc[:-2], root) if loc else None
    if model is None or not names:
        return None
    return model.model_fields.get(names[-1])


def describe(field) -> str:
    """What a key allows, in words: type, range and unit ('a number in (0, inf), m')."""
    model = _find_model(field.annotation)
    if model is not None:
        return f"a table of the keys {', '.join(model.model_fields)}"
    text = _allowed(_field_schema(field))
    unit = _unit(field)
    return f"{text}, {unit}" if unit and unit != "-" else text


def _unit(field) -> str:
    """The field's unit ('-' dimensionless), '' for a key without one."""
    extra = field.json_schema_extra
    return extra.get("unit", "") if isinstance(extra, dict) else ""


def _allowed(schema: dict) -> str:
    """Type and range in words: 'a number in (0, inf)'."""
    rng = range_text(schema)
    return _type_words(schema) + (f" in {rng}" if rng else "")


def hard_range(model: type[BaseModel], key: str) -> tuple[float, float]:
    """[minimum, maximum] of a closed-range number field of ``model`` (its ``ge`` and ``le``):
    for a command-line flag that means the same quantity."""
    schema = _field_schema(model.model_fields[key])
    return float(schema["minimum"]), float(schema["maximum"])


def _field_schema(field) -> dict:
    annotation = field.annotation
    adapter = TypeAdapter(Annotated[annotation, *field.metadata] if field.metadata else annotation)
    return adapter.json_schema()


def _strip_optional(schema: dict) -> dict:
    options = [s for s in schema.get("anyOf", []) if s.get("type") != "null"]
    return options[0] if len(options) == 1 else schema


def _type_words(schema: dict) -> str:
    schema = _strip_optional(schema)
    if "enum" in schema:
        return "one of " + ", ".join(repr(v) for v in schema["enum"])
    if "const" in schema:
        return repr(schema["const"])
    kind = schema.get("type")
    if kind == "array":
        items = schema.get("items", {})
        n = schema.get("minItems"), schema.get("maxItems")
        count = f"{n[0]} " if n[0] == n[1] and n[0] else f"{n[0]} or more " if n[0] else ""
        inner = (
            _allowed(items)
            .replace("a number", "numbers")
            .replace("an integer", "integers")
            .replace("a text", "texts")
        )
        return f"a list of {count}{inner}"
    if kind in ("number", "integer") and not range_text(schema):
        return "any finite number" if kind == "number" else "any integer"
    return {
        "number": "a number",
        "integer": "an integer",
        "boolean": "true or false",
        "string": "a text",
    }.get(str(kind), "a value")


def range_text(schema: dict) -> str:
    """'(0, inf)', '[0, 0.5)', ... from JSON Schema limits; '' for none."""
    schema = _strip_optional(schema)
    if schema.get("type") not in ("number", "integer"):
        return ""
    low = (
        ("(", schema["exclusiveMinimum"])
        if "exclusiveMinimum" in schema
        else ("[", schema["minimum"])
        if "minimum" in schema
        else ("(", -math.inf)
    )
    high = (
        (")", schema["exclusiveMaximum"])
        if "exclusiveMaximum" in schema
        else ("]", schema["maximum"])
        if "maximum" in schema
        else (")", math.inf)
    )
    if low[1] == -math.inf and high[1] == math.inf:
        return ""
    return f"{low[0]}{low[1]:g}, {high[1]:g}{high[0]}"


def json_schema() -> dict:
    """The JSON Schema of a study file (draft 2020-12), with a ``unit`` on every quantity: every
    kind's tables (:func:`study_model`)."""
    schema = study_model(every=True).model_json_schema()
    return {
        "$schema": "https://json-schema.org/draft/2020-12/schema",
        "$id": "https://github.com/colonna/colonna/study-file.schema.json",
        **schema,
    }


def markdown() -> str:
    """The key list of docs/study-file.md: one table per TOML table, from the schema."""
    lines = [
        "# Study file keys",
        "",
        "Generated from the schema (`colonna schema --markdown`); "
        "`tests/test_schema.py` checks that this file is current. SI units; ranges in "
        "interval notation; `-` means dimensionless.",
        "",
    ]
    for name, field in study_model(every=True).model_fields.items():
        model = _model_of(field.annotation)
        header = f"[[{name}]]" if name == "collar" else f"[{name}]"
        about = " ".join((model.__doc__ or "").split()).split(": ", 1)[-1]
        lines += [
            f"## {header}",
            "",
            about[0].upper() + about[1:],
            "",
            "| key | allowed | unit | default | meaning |",
            "|---|---|---|---|---|",
        ]
        for key, sub in model.model_fields.items():
            default = (
                "required"
                if sub.is_required()
                else ("see meaning" if sub.default is None else _toml(sub.default))
            )
            cells = [
                f"`{key}`",
                _allowed(_field_schema(sub)),
                _unit(sub),
                default,
                sub.description or "",
            ]
            lines.append("| " + " | ".join(c.replace("|", "\\|") for c in cells) + " |")
        lines.append("")
    return "\n".join(lines)


def _toml(value) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return f'"{value}"'
    if isinstance(value, float):
        return f"{value:g}"
    return str(value)

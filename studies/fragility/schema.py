"""The fragility study's own table of the study file, [fragility]: its record suite, intensity
levels, models and fits. Registered with the kind (studies/kinds.py: ``tables``) and checked with
the shared tables by :mod:`studies.schema` (:func:`studies.schema.study_model`)."""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import Field

from ..schema import FAILED, Table, known, pair, quantity

INTENSITY_MEASURES = {  # [fragility] intensity: the IMs a record is scaled by, and their units
    "pga": "m/s^2",
    "pgv": "m/s",
    "sa": "m/s^2",
    "pga_rocking": "-",
    "pgv_rocking": "-",
}
FRAGILITY_MODELS = ("sdof", "multibody", "fem")
SUITE_TEXT = (
    "Record suite: a folder of records or a TOML list of them ([[record]] file, scale, "
    "units), relative to the study file."
)
SUITE = Field(min_length=1, description=SUITE_TEXT)  # a kind's suite key (also [layout])


class Fragility(Table):
    """[fragility] (fragility): a record suite scaled over intensity levels through the models:
    IDA (a ladder of levels, each record's capacity at its first exceedance) or multiple-stripe
    analysis (given levels); lognormal fits with bootstrap bands."""

    suite: str = SUITE
    intensity: Literal[tuple(INTENSITY_MEASURES)] = Field(  # type: ignore[valid-type]
        "pga_rocking",
        description="Intensity measure the records are scaled by and the curves are drawn "
        "against: pga (m/s^2), pgv (m/s), sa (5 %-damped Sa(period), m/s^2), pga_rocking "
        "(PGA / (g tan alpha)), pgv_rocking (PGV p / (g tan alpha)) of the rocking block.",
    )
    period: float | None = quantity(
        "s", "Period of Sa (intensity = sa only), 0.01 to 20 s.", ge=0.01, le=20
    )
    analysis: Literal["ida", "msa"] = Field(
        "ida",
        description="ida: every record over the ladder (capacity at the first exceedance); "
        "msa: every record at the given levels (stripes).",
    )
    ladder: list[Annotated[float, Field(gt=0, le=1e4)]] | None = pair(
        None, "[start, stop] of the IDA ladder, inclusive, in the intensity's unit.", "IM"
    )
    steps: int = quantity("-", "Levels of the IDA ladder, 2 to 1000.", 20, ge=2, le=1000)
    levels: list[Annotated[float, Field(gt=0, le=1e4)]] | None = Field(
        None,
        min_length=2,
        max_length=1000,
        description="The MSA stripes, increasing, in the intensity's unit.",
        json_schema_extra={"unit": "IM"},
    )
    models: list[Literal[FRAGILITY_MODELS]] = Field(  # type: ignore[valid-type]
        ["sdof", "multibody"],
        min_length=1,
        description="Models to run: sdof (the paper's half block with collar springs), "
        "multibody (rigid bodies with the FEM's contacts), fem (the study's mesh, one run per "
        "record and level, stopped once settled).",
    )
    theta_ratio: float = quantity(
        "-", "Threshold of the rotation limit state |theta| / alpha, (0, 100].", 0.5, gt=0, le=100
    )
    fit: Literal["lognormal", "shifted"] = Field(
        "lognormal",
        description="The fitted curve: lognormal, or shifted (a lognormal of IM - x0, 0 up to "
        "the origin x0 at the uplift intensity: the least level at which a record of the suite "
        "lifts the rocking block, PGA = g tan alpha).",
    )
    design_intensity: float = Field(
        description="The site's design intensity, in the intensity's unit, within the levels "
        "run (the ladder's [start, stop], or the first to the last stripe): the report opens "
        "with each limit state's probability there.",
        json_schema_extra={"unit": "IM"},
        gt=0,
        le=1e4,
    )
    bootstrap: int = quantity(
        "-",
        "Bootstrap resamples of the records for the bands, 10 to 100000.",
        500,
        ge=10,
        le=100000,
    )
    confidence: float = quantity(
        "-", "Two-sided level of the bootstrap intervals, (0, 1).", 0.9, gt=0, lt=1
    )
    seed: int = quantity("-", "Seed of the bootstrap (numpy PCG64).", 0, ge=0)
    sdof_rtol: float = quantity(
        "-",
        "Relative tolerance of the SDOF runs, 1e-12 to 1e-3 (the single SDOF run's is 1e-10).",
        1e-6,
        ge=1e-12,
        le=1e-3,
    )
    multibody_step: float = quantity(
        "-",
        "Step of the multibody runs where the collars set it, as a fraction of their explicit "
        "stability limit 2/omega, 0.01 to 0.25 (a single multibody run's is 0.125, whose crack "
        "tolerance the runs keep; at 0.5 the answers move by 5-25 %: docs/fragility.md).",
        0.25,
        ge=0.01,
        le=0.25,
    )

    @staticmethod
    def across(f: dict, given: set) -> list[tuple[str, tuple]]:
        """The ladder with IDA, the levels with MSA, the period with Sa; the design intensity
        within the levels run (:meth:`_design_within`)."""
        found: list[tuple[str, tuple]] = []
        if f["analysis"] == "ida":
            if f["ladder"] is None:
                found.append(
                    ("fragility.ladder = [start, stop] is required with analysis = 'ida'", ())
                )
            elif known(f["ladder"]) and not f["ladder"][0] <= f["ladder"][1]:
                found.append((f"fragility.ladder = {f['ladder']!r} must have start <= stop", ()))
            else:
                found += Fragility._design_within(f, "ladder")
            if f["levels"] is not None:
                found.append(("fragility.levels goes with analysis = 'msa' (use ladder)", ()))
        elif f["analysis"] == "msa":
            if f["levels"] is None:
                found.append(("fragility.levels is required with analysis = 'msa'", ()))
            elif known(f["levels"]) and any(b <= a for a, b in zip(f["levels"], f["levels"][1:])):
                found.append((f"fragility.levels = {f['levels']!r} must increase", ()))
            else:
                found += Fragility._design_within(f, "levels")
            if f["ladder"] is not None or "steps" in given:
                found.append(("fragility.ladder and steps go with analysis = 'ida'", ()))
        if f["intensity"] == "sa" and f["period"] is None:
            found.append(("fragility.period is required with intensity = 'sa'", ()))
        if f["intensity"] not in ("sa", FAILED) and f["period"] is not None:
            found.append(("fragility.period goes with intensity = 'sa' only", ()))
        return found

    @staticmethod
    def _design_within(f: dict, key: str) -> list[tuple[str, tuple]]:
        """The design intensity within the levels run (``key``: ladder or levels), else
        refused, before anything runs. Refused rather than reported as extrapolated: outside
        the levels a probability is the fitted lognormal's tail, not the records' answer (a
        design PGV p / (g tan alpha) of 245 over a ladder of 0.5-8 gave every P = 1), such a
        value is most often an IM in another unit, and the remedy (a ladder or a stripe that
        reaches it) is one key and gives data where the answer is read."""
        levels, design = f[key], f["design_intensity"]
        if not known(levels, design, f["intensity"]) or design is None:
            return []
        low, high = min(levels), max(levels)
        if low <= design <= high:
            return []
        unit = INTENSITY_MEASURES.get(f["intensity"], "")
        unit = f"{f['intensity']}, no unit" if unit == "-" else f"{f['intensity']} in {unit}"
        where = "above the highest" if design > high else "below the lowest"
        return [
            (
                f"fragility.design_intensity = {design:g} lies {where} level run: "
                f"fragility.{key} spans {low:g} to {high:g} ({unit}); a probability there "
                "would be the fitted curve's extrapolation, not the records' answer: "
                + ("extend the ladder" if key == "ladder" else "add a stripe")
                + " to reach it, or give it in the intensity's unit",
                (),
            )
        ]

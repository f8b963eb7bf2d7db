"""The collar-layout study's own table, [layout]: the catalogue of collar layouts to choose from,
the record suite and ladder that give each layout's fragility, and the target its risk at the
site ([hazard]) must meet. Registered with the kind (studies/kinds.py: ``tables``)."""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import Field

from ..fragility.schema import INTENSITY_MEASURES, SUITE
from ..schema import Table, known, pair, quantity

# EN 10025-2:2019, Table 7: f_y of the non-alloy structural steels for t <= 16 mm, Pa
STEEL_GRADES = {"S235": 235e6, "S275": 275e6, "S355": 355e6, "S450": 440e6}
# flat bars t x h (m) of the default catalogue: EN 10058 sizes, 5 x 40 mm to 15 x 120 mm
DEFAULT_SECTIONS = [
    [0.005, 0.04],
    [0.006, 0.05],
    [0.008, 0.06],
    [0.008, 0.08],
    [0.010, 0.08],
    [0.012, 0.10],
    [0.015, 0.12],
]
Section = Annotated[list[Annotated[float, Field(gt=0, le=1.0)]], Field(min_length=2, max_length=2)]


class Layout(Table):
    """[layout] (collar-layout): the lightest collar layout of a catalogue whose risk of
    overturning at the site ([hazard]) meets a target, screened over a record suite with the
    rigid multibody model, refined with its plastic collars and confirmed by FEM stripes."""

    suite: str = SUITE
    intensity: Literal[tuple(INTENSITY_MEASURES)] = Field(  # type: ignore[valid-type]
        "pga_rocking",
        description="Intensity measure the records are scaled by (as [fragility] intensity; "
        "sa is not offered here): pga (m/s^2), pgv (m/s), pga_rocking, pgv_rocking (of the "
        "rocking block: the half of a cracked column). The [hazard] must be of the same measure.",
    )
    ladder: list[Annotated[float, Field(gt=0, le=1e4)]] = pair(
        [0.5, 8.0], "[start, stop] of the IDA ladder, inclusive, in the intensity's unit.", "IM"
    )
    steps: int = quantity("-", "Levels of the IDA ladder, 2 to 200.", 12, ge=2, le=200)
    counts: list[Annotated[int, Field(ge=0, le=12)]] = Field(
        [1, 2, 3, 4, 5],
        min_length=1,
        description="Numbers of collars of the catalogue, 0 (none) to 12.",
        json_schema_extra={"unit": "-"},
    )
    sections: list[Section] = Field(
        DEFAULT_SECTIONS,
        min_length=1,
        description="Flat-bar sections of the catalogue, [t, h] in m (thickness, height).",
        json_schema_extra={"unit": "m"},
    )
    grades: list[Literal[tuple(STEEL_GRADES)]] = Field(  # type: ignore[valid-type]
        ["S235", "S275", "S355"],
        min_length=1,
        description="Steel grades of the catalogue (EN 10025-2, f_y for t <= 16 mm): S235, "
        "S275, S355, S450.",
    )
    pretensions: list[Annotated[float, Field(ge=0, lt=1)]] = Field(
        [0.0],
        min_length=1,
        description="Pretension levels of the catalogue, each a fraction [0, 1) of the "
        "collar's yield force f_y t h (the force in N is that times its grade and section); "
        "default [0]: none.",
        json_schema_extra={"unit": "-"},
    )
    end_distance: float | None = quantity(
        "m",
        "Distance of the lowest and highest collar from the shaft's ends; the others evenly "
        "between (one collar: at mid-height). Default: an eighth of the height.",
        gt=0,
    )
    ring_length: float | None = quantity(
        "m",
        "Length of one collar's bar around the shaft, for its steel mass. Default: pi times the "
        "width (a round shaft).",
        gt=0,
        le=100,
    )
    target_frequency: float | None = quantity(
        "1/year",
        "Target: the highest acceptable mean annual frequency of overturning, 1e-8 to 0.1.",
        ge=1e-8,
        le=0.1,
    )
    target_probability: float | None = quantity(
        "-",
        "Target: the highest acceptable probability of overturning in hazard.years, "
        "1e-6 to 0.5 (or target_frequency).",
        ge=1e-6,
        le=0.5,
    )
    design_return_period: float = quantity(
        "year",
        "Return period of the design intensity (the hazard's intensity there), at which the "
        "collars must not fracture and the FEM confirms the choice, 10 to 1e5 years.",
        475.0,
        ge=10,
        le=1e5,
    )
    fracture_fraction: float = quantity(
        "-",
        "The largest fraction of the suite's records whose run at the design intensity may "
        "fracture a collar, [0, 1).",
        0.0,
        ge=0,
        lt=1,
    )
    shortlist: int = quantity(
        "-",
        "Layouts refined with plastic collars in one search, lightest first, 1 to 50: those "
        "whose collars yield before the column overturns in some record, and those the "
        "screening has missing the target by less than its scatter. A layout is chosen only "
        "where none before it in the catalogue was left unrefined.",
        6,
        ge=1,
        le=50,
    )
    fem: bool = Field(
        True,
        description="Confirm the chosen layout with FEM runs of every record at the design "
        "intensity (on the study's [mesh]).",
    )
    fem_attempts: int = quantity(
        "-",
        "Layouts FEM-checked at most, 1 to 10: where the FEM stripe does not confirm the chosen "
        "layout (it contradicts it or neither confirms nor contradicts it), the next heavier "
        "layout that meets the target by the multibody model is checked (where no collar "
        "yielded in the stripe, the next with more collars or a larger bar: not the same bars "
        "in another grade), up to this many.",
        2,
        ge=1,
        le=10,
    )
    crosscheck: bool = Field(
        True,
        description="Run the chosen layout's cross-check (the cross-check kind: FEM ensemble "
        "and rigid models) under the record of median capacity at the design intensity, into "
        "the study's chosen-crosscheck folder; its answers in the report.",
    )
    bootstrap: int = quantity(
        "-",
        "Bootstrap resamples of the records for the bands, 10 to 100000.",
        200,
        ge=10,
        le=100000,
    )
    confidence: float = quantity(
        "-", "Two-sided level of the bootstrap intervals, (0, 1).", 0.9, gt=0, lt=1
    )
    seed: int = quantity("-", "Seed of the bootstrap (numpy PCG64).", 0, ge=0)

    @staticmethod
    def across(f: dict, given: set) -> list[tuple[str, tuple]]:
        """One target; the ladder increasing; no sa (a hazard of Sa needs its period)."""
        found: list[tuple[str, tuple]] = []
        targets = [k for k in ("target_frequency", "target_probability") if f[k] is not None]
        if len(targets) != 1:
            found.append(
                (
                    "layout.target_frequency (per year) or layout.target_probability (in "
                    "hazard.years) is required, one of them",
                    (),
                )
            )
        if known(f["ladder"]) and not f["ladder"][0] < f["ladder"][1]:
            found.append((f"layout.ladder = {f['ladder']!r} must have start < stop", ()))
        if f["intensity"] == "sa":
            found.append(("layout.intensity = 'sa' is not offered: pga, pgv or *_rocking", ()))
        return found

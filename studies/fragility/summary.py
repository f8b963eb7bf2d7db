"""The fragility study's summary.json as typed sections (studies.sections): its top-level keys
with their units, as its report reads them. The per-model, per-limit-state tables (runs,
limit_states, collars, unreachable, same_curve) are kept as the file's dicts."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from ...core.quantities import quantity
from ...rigid.solve import RockingSummary
from ..sections import like, read, section


@dataclass(frozen=True, kw_only=True)
class FragilityBlock:
    """``block``: the rocking block the intensities are normalised by."""

    alpha: float = like(RockingSummary, "alpha")
    p: float = like(RockingSummary, "p")
    uplift_acceleration: float = quantity("m/s^2", "a_up = g tan(alpha) (1 + lambda)")


@dataclass(frozen=True, kw_only=True)
class FragilitySummary:
    """The fragility study's summary.json, the keys its report reads."""

    study: str = quantity("", "the study's name")
    intensity: str = quantity("", "the intensity measure (pga, pgv, sa, pga_rocking, ...)")
    intensity_unit: str = quantity("", "its unit, as the report shows it")
    period: float | None = quantity("s", "Sa's period T (None: another measure)")
    analysis: str = quantity("", "ida or stripes")
    levels: list[float] = quantity("", "the intensity levels, in the measure's unit")
    design_intensity: float = quantity("", "the design intensity, in the measure's unit")
    theta_ratio: float = quantity("-", "the rotation limit state's |theta| / alpha")
    fit: str = quantity("", "the fit of the fragility curves")
    origin: float = quantity("", "the fit's origin, in the measure's unit")
    confidence: float = quantity("-", "the bands' confidence level")
    models: list[str] = quantity("", "the models run (sdof, multibody, fem)")
    block: FragilityBlock = section(FragilityBlock, "the rocking block")
    records: list[dict[str, Any]] = quantity("", "the suite's records (name, scale, ...)")
    runs: dict[str, Any] = quantity("", "runs[model][key][record][level]")
    limit_states: dict[str, Any] = quantity("", "limit_states[model][state]: the fits")
    hazard: dict[str, Any] | None = quantity("", "the site's hazard curve (None: none given)")
    collars: dict[str, Any] = quantity("", "collars[model]: the collars' law and f_y")
    unreachable: dict[str, Any] = quantity("", "unreachable[model][state]: why")
    sdof_rtol: float = quantity("-", "the SDOF solver's relative tolerance")
    multibody_step: float = quantity("-", "the multibody step, a fraction of its default")


def load(data: dict) -> FragilitySummary:
    """The fragility study's summary.json (its dict) as typed sections."""
    return read(FragilitySummary, data)

"""The Zhang & Makris validation's summary.json as typed sections (studies.sections): what its
HTML page and ``colonna validate``'s Markdown report read, with their SI units."""

from __future__ import annotations

from dataclasses import dataclass

from ...core.quantities import quantity
from ...rigid.solve import RockingSummary
from ..sections import like, read, section


@dataclass(frozen=True, kw_only=True)
class ValidationBlock:
    """``block``: the paper's validation block."""

    p: float = like(RockingSummary, "p")
    alpha: float = like(RockingSummary, "alpha")


@dataclass(frozen=True, kw_only=True)
class Boundaries:
    """``boundaries``: the mode boundaries at Omega / p = 5, a_p / a_uplift (bisection)."""

    linear: list[float] = quantity("-", "the linear model's three boundaries")
    nonlinear: list[float] = quantity("-", "the nonlinear model's three boundaries")
    meaning: list[str] = quantity("", "what each boundary separates")
    paper_fig5_brackets: list[list[float] | None] = quantity(
        "-", "the paper's Fig. 5 bracket of each (None: not read off it)"
    )


@dataclass(frozen=True, kw_only=True)
class History:
    """``histories.<a_p>``: one pulse's run of the linear model."""

    mode: str = like(RockingSummary, "mode")
    impacts: int = like(RockingSummary, "impacts")
    max_abs_theta_over_alpha: float = like(RockingSummary, "max_abs_theta_over_alpha")


@dataclass(frozen=True, kw_only=True)
class ZhangMakrisSummary:
    """The Zhang & Makris validation's summary.json, what its reports read."""

    block: ValidationBlock = section(ValidationBlock, "the validation block")
    histories: dict[str, History] = section(History, "each pulse's run, by a_p", many=True)
    boundaries: Boundaries = section(Boundaries, "the mode boundaries")


def load(data: dict) -> ZhangMakrisSummary:
    """The validation's summary.json (its dict) as typed sections."""
    return read(ZhangMakrisSummary, data)

"""The collar design's summary.json as typed sections (studies.sections): what its runner writes
and its report's Numbers table reads, each key with its SI unit."""

from __future__ import annotations

from dataclasses import dataclass

from ...core.quantities import quantity
from ...fem.solver import FemRunSummary
from ..sections import Stoppable, like, read, section


@dataclass(frozen=True, kw_only=True)
class Design:
    """``design``: the first-yield design of colonna.rigid.design (corrected Eq. 22-24)."""

    yield_moment: float = quantity("N m", "yield moment M_y = f_y t h^2 / 6")
    yield_displacement: float = quantity("m", "yield offset d_y (corrected Eq. 22)")
    yield_rotation: float = quantity("rad", "yield rotation theta_y (Eq. 23)")
    required_stiffness: float = quantity("N/m", "required lateral stiffness k (Eq. 24)")
    collar_lateral_stiffness: float = quantity("N/m", "one collar's lateral stiffness K_l")
    collars_needed: int = quantity("", "collars needed")
    design_acceleration: float = quantity("m/s^2", "the design pulse's peak a_g")
    column_mass: float = quantity("kg", "the mass the collars hold (both halves)")


@dataclass(frozen=True, kw_only=True)
class DuctileDesign:
    """``ductile_design``: the plastic bands tried in the multibody model, thinnest passing."""

    never_yields_t: float | None = quantity("m", "thinnest band that never yields (None: none)")
    holds_t: float | None = quantity("m", "thinnest band that yields but holds (None: none)")
    ductility_limit: float = quantity("-", "largest fibre strain over f_y / E allowed")
    study_t: float = quantity("m", "band thickness of the study's collars")


@dataclass(frozen=True, kw_only=True)
class DesignSummary:
    """The collar design's summary.json, the sections its report reads."""

    study: str = quantity("", "the study's name")
    design: Design = section(Design, "the first-yield design")
    design_alpha: float = quantity("rad", "alpha of the design's block")
    design_ag_over_g: float = quantity("-", "the design pulse's a_g / g")
    collars_provided: int = quantity("", "the study's collars")
    lateral_stiffness_provided: float = quantity("N/m", "their lateral stiffness")
    design_adequate: bool = quantity("", "provided >= required")
    fem_collar_max_utilisation: float = like(FemRunSummary, "collar_max_utilisation")
    fem_collar_first_yield_time: float | None = like(FemRunSummary, "collar_first_yield_time")
    fem_overturned: bool = like(FemRunSummary, "overturned")
    fem_max_rotation_over_yield_rotation: Stoppable = quantity(
        "-", "the FEM's peak rotation over theta_y (the words of its stop where it overturned)"
    )
    ductile_design: DuctileDesign = section(DuctileDesign, "the plastic bands' design")


def load(data: dict) -> DesignSummary:
    """The collar design's summary.json (its dict) as typed sections."""
    return read(DesignSummary, data)

"""The solid-vs-cracked study's summary.json as typed sections (studies.sections): each variant's
numbers, as its report's table reads them, with their SI units."""

from __future__ import annotations

from dataclasses import dataclass

from ...core.quantities import quantity
from ...fem.solver import FemRunSummary
from ..sections import Stoppable, like, read, section


@dataclass(frozen=True, kw_only=True)
class Variant:
    """``variants.<name>``: one variant's FEM and rigid runs (solid, cracked, with collars)."""

    fem_peak_rotation: Stoppable = quantity(
        "rad", "FEM peak rotation (the words of its stop where it overturned)"
    )
    fem_overturned: bool = like(FemRunSummary, "overturned")
    rigid_peak_rotation: Stoppable = quantity(
        "rad", "rigid SDOF peak rotation (the words of its stop where it overturned)"
    )
    rigid_mode: str = quantity("", "the rigid SDOF's overturning mode")
    collar_max_utilisation: float = like(FemRunSummary, "collar_max_utilisation")
    edge_stress_ratio: float = like(FemRunSummary, "edge_stress_ratio")
    status: str = like(FemRunSummary, "status")


@dataclass(frozen=True, kw_only=True)
class SolidVsCrackedSummary:
    """The solid-vs-cracked study's summary.json, what its report reads."""

    study: str = quantity("", "the study's name")
    variants: dict[str, Variant] = section(Variant, "each variant by name", many=True)


def load(data: dict) -> SolidVsCrackedSummary:
    """The solid-vs-cracked study's summary.json (its dict) as typed sections."""
    return read(SolidVsCrackedSummary, data)

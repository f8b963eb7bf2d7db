"""The spectrum cross-check's summary.json as typed sections (studies.sections): what its
report's Numbers table reads, each key with its SI unit."""

from __future__ import annotations

from dataclasses import dataclass

from ...core.quantities import quantity
from ..sections import absent, read


@dataclass(frozen=True, kw_only=True)
class SpectrumSummary:
    """The spectrum cross-check's summary.json, the keys its report's table reads."""

    study: str = quantity("", "the study's name")
    agreement_fem_multibody: float = quantity("-", "grid points where FEM and multibody agree")
    agreement_fem_sdof: float = quantity("-", "grid points where FEM and SDOF agree")
    points: int = quantity("", "grid points")
    energy_error_fem_max: float = quantity("-", "largest FEM energy balance error of the grid")
    fem_seconds_per_point: float = quantity("s", "FEM wall time per grid point")
    wall_seconds: float = absent("s", "the study's wall time")
    record: str = absent("", "the record the grid scales (a record only)")


def load(data: dict) -> SpectrumSummary:
    """The spectrum cross-check's summary.json (its dict) as typed sections."""
    return read(SpectrumSummary, data)

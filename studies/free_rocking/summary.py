"""The free-rocking study's summary.json as typed sections (studies.sections): what its report
reads, each key with its SI unit."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from ...core.quantities import quantity
from ...rigid.solve import RockingSummary
from ..sections import absent, like, read, section


@dataclass(frozen=True, kw_only=True)
class ReleaseRun:
    """A run released from a tilt (FEM or multibody): the velocity ratios of its impacts."""

    ratios: list[float] | str = quantity(
        "-", "velocity ratio at each impact (words where the run overturned)"
    )
    ratio_first: float | None = quantity("-", "velocity ratio at the first impact (median)")
    impulse_ratios: list[float] = absent(
        "-", "the multibody run's ratio at each impact from its impulses (multibody only)"
    )


@dataclass(frozen=True, kw_only=True)
class Tilt:
    """``tilts``: one release tilt and its two runs."""

    tilt_fraction: float = quantity("-", "the release tilt, a fraction of alpha")
    tilt: float = quantity("rad", "the release tilt")
    fem: ReleaseRun = section(ReleaseRun, "the FEM run")
    multibody: ReleaseRun = section(ReleaseRun, "the rigid multibody run")


@dataclass(frozen=True, kw_only=True)
class Variant:
    """``damping_variants``, ``mesh_variants``: the FEM from the first tilt, one setting moved."""

    damping: float = quantity("-", "contact damping, fraction of critical")
    mesh_size: float = quantity("m", "mesh size")
    ratio_first: float | None = quantity("-", "velocity ratio at the first impact (median)")


@dataclass(frozen=True, kw_only=True)
class FreeRockingSummary:
    """The free-rocking study's summary.json, the keys its report reads."""

    study: str = quantity("", "the study's name")
    alpha: float = like(RockingSummary, "alpha")
    restitution_housner: float = like(RockingSummary, "restitution_housner")
    E: float = quantity("Pa", "the stone's Young's modulus")
    fem_ratio_study_stone: float | None = quantity(
        "-", "FEM velocity ratio at the first impact, the study's stone (median)"
    )
    fem_ratio_study_stone_band: dict[str, Any] | None = quantity(
        "-", "its band over the replicas (median, min, max, values)"
    )
    replicas: int = quantity("", "replicas of each FEM run")
    fem_ratio_study_stone_mean: float | None = quantity("-", "mean ratio over its impacts")
    multibody_ratio: float | None = quantity("-", "multibody velocity ratio at the first impact")
    tilts: list[Tilt] = section(Tilt, "each release tilt", many=True)
    damping_variants: list[Variant] = section(Variant, "contact damping moved", many=True)
    mesh_variants: list[Variant] = section(Variant, "mesh size moved", many=True)
    damping: float = quantity("-", "the study's contact damping, fraction of critical")
    mesh_size: float = quantity("m", "the study's mesh size")


def load(data: dict) -> FreeRockingSummary:
    """The free-rocking study's summary.json (its dict) as typed sections."""
    return read(FreeRockingSummary, data)

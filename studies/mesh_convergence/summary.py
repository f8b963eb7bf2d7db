"""The mesh-convergence study's summary.json as typed sections (studies.sections): each
quantity over the meshes, as its report's table reads them."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from ...core.quantities import quantity
from ..sections import Stoppable, read, section


@dataclass(frozen=True, kw_only=True)
class ConvergenceEntry:
    """One quantity over the meshes (colonna.fem.convergence.convergence_table), in its unit."""

    values: list[Stoppable] = quantity("", "its value on each mesh, coarse to fine")
    observed_order: float | None = quantity("-", "observed order of convergence")
    richardson: float | None = quantity("", "Richardson extrapolation, in its unit")
    fine_relative_error: float | None = quantity("-", "the finest mesh's estimated error")


@dataclass(frozen=True, kw_only=True)
class Convergence:
    """``convergence``: the quantities the table shows (a run that overturned: the words of
    its stop in place of its peak rotation's value)."""

    peak_rotation: ConvergenceEntry = section(ConvergenceEntry, "peak rotation, rad")
    collar_max_utilisation: ConvergenceEntry = section(ConvergenceEntry, "collar utilisation, -")
    edge_stress_max: ConvergenceEntry = section(ConvergenceEntry, "study-mesh toe stress, Pa")
    toe_pressure_winkler: ConvergenceEntry = section(
        ConvergenceEntry, "Winkler toe pressure of the sampled base force and tilt, Pa"
    )


@dataclass(frozen=True, kw_only=True)
class MeshConvergenceSummary:
    """The mesh-convergence study's summary.json, what its report reads."""

    study: str = quantity("", "the study's name")
    sizes: list[float] = quantity("m", "the mesh sizes, coarse to fine")
    dofs: list[int] = quantity("", "degrees of freedom of each mesh")
    convergence: Convergence = section(Convergence, "each quantity over the meshes")
    bed: dict[str, Any] | None = quantity("", "the bed the column stands on (stiffness, source)")


def load(data: dict) -> MeshConvergenceSummary:
    """The mesh-convergence study's summary.json (its dict) as typed sections."""
    return read(MeshConvergenceSummary, data)

"""The crack-extent study's summary.json as typed sections (studies.sections): each extent's
numbers and the rigid limits', as its report's tables read them, with their SI units."""

from __future__ import annotations

from dataclasses import dataclass

from ...core.quantities import quantity
from ...fem.solver import FemRunSummary
from ..sections import Stoppable, like, read, section


@dataclass(frozen=True, kw_only=True)
class Extent:
    """``variants.<name>``: the FEM ensemble of the column with its crack over one extent."""

    crack_from: float = quantity("m", "height the crack runs from")
    crack_to: float = quantity("m", "height the crack runs to")
    extent_fraction: float = quantity("-", "the crack's length over the column's height")
    crack_depth: float = quantity(
        "-",
        "the fraction of the thickness the crack runs through (1: through; the full height's "
        "is always 1, the paper's hypothesis)",
        default=1.0,
    )
    crack_length_initial: float = like(FemRunSummary, "crack_length_initial")
    fem_peak_rotation: Stoppable = quantity(
        "rad", "FEM peak rotation, median (the words of its stop where it overturned)"
    )
    fem_peak_rotation_min: float | None = quantity(
        "rad", "FEM peak rotation, smallest over the replicas that stood (None: none stood)"
    )
    fem_peak_rotation_max: float | None = quantity(
        "rad", "FEM peak rotation, largest over the replicas that stood (None: none stood)"
    )
    replicas: int = quantity("", "runs in the ensemble")
    fem_overturned_replicas: int = quantity("", "replicas that overturned")
    fem_overturned: str = quantity("", "does the FEM column overturn: yes, no or undecided")
    collars_yield: str = quantity(
        "", "do the collars yield (utilisation band against 1): yes, no, undecided, not assessed"
    )
    crack_grows: str = quantity("", "does the crack grow: yes, no or undecided")
    crack_length_final: float = like(FemRunSummary, "crack_length_final")
    crack_tip_KI_ratio: float | None = like(FemRunSummary, "crack_tip_KI_ratio")
    crack_tip_KI_ratio_min: float | None = quantity("-", "K_I / K_IC, smallest over the replicas")
    crack_tip_KI_ratio_max: float | None = quantity("-", "K_I / K_IC, largest over the replicas")
    collar_max_utilisation: float = like(FemRunSummary, "collar_max_utilisation")
    collar_max_utilisation_min: float | None = quantity(
        "-", "collar utilisation, smallest over the replicas"
    )
    collar_max_utilisation_max: float | None = quantity(
        "-", "collar utilisation, largest over the replicas"
    )
    edge_stress_ratio: float = like(FemRunSummary, "edge_stress_ratio")
    status: str = like(FemRunSummary, "status")


@dataclass(frozen=True, kw_only=True)
class Limit:
    """``limits.<name>``: a rigid limit, the solid column or the fully split one (SDOF)."""

    peak_rotation: Stoppable = quantity(
        "rad", "SDOF peak rotation (the words of its stop where it overturned)"
    )
    overturned: str = quantity("", "does the SDOF block overturn: yes or no")
    block: str = quantity("", "the rocking block: the whole column or one half")


@dataclass(frozen=True, kw_only=True)
class CrackExtentSummary:
    """The crack-extent study's summary.json, what its report reads."""

    study: str = quantity("", "the study's name")
    as_found: str = quantity("", "the variant of the study's own crack")
    from_base: bool = quantity("", "the swept cracks run from the base up (else from the top)")
    variants: dict[str, Extent] = section(Extent, "each extent by name", many=True)
    limits: dict[str, Limit] = section(Limit, "the rigid limits by name", many=True)


def load(data: dict) -> CrackExtentSummary:
    """The crack-extent study's summary.json (its dict) as typed sections."""
    return read(CrackExtentSummary, data)

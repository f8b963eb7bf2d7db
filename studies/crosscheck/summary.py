"""The cross-check's summary.json as typed sections (studies.sections): what its runner writes
and its report reads, each key with its SI unit. The FEM's section is the FEM run's own summary
(colonna.fem.solver.FemRunSummary) with the ensemble's tally and the cross-check's three
history numbers; the multibody and SDOF sections keep a selection of those runs' summaries,
each key declared where the run declares it (:func:`studies.sections.like`). A number of a run
that stopped (overturned) may be the words that say so (studies.outcome.unless_stopped) in place
of its value, so the types are those of the values, not a promise that each is a number.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from ...core.quantities import quantity
from ...fem.ensemble import EnsembleTally
from ...fem.solver import FemRunSummary
from ...rigid.multibody import MultibodySummary
from ...rigid.solve import RockingSummary
from ..sections import ABSENT, Stoppable, absent, like, read, section


@dataclass(frozen=True, kw_only=True)
class FemSection(EnsembleTally, FemRunSummary):
    """``fem``: the FEM ensemble's summary (colonna.fem.ensemble.ensemble_summary of the
    replicas': replica 0's, landing-dependent keys the median with their ``bands``), its
    rotations the words of its stop where it overturned."""

    crack_slip_max: float = quantity("m", "largest crack slip over the run")
    impacts_before_pulse_end: float = quantity("", "impacts before the pulse ends (median)")
    restitution_after_motion: Stoppable = quantity(
        "-", "mean velocity ratio of the impacts after the ground motion (None: none)"
    )


@dataclass(frozen=True, kw_only=True)
class MultibodySection:
    """``rigid_multibody``: what the summary keeps of the rigid multibody run, in this order
    (its rotations the words of its stop where it overturned)."""

    overturned: bool = like(MultibodySummary, "overturned")
    mode: str = like(MultibodySummary, "mode")
    status: str = like(MultibodySummary, "status")
    impacts: int = like(MultibodySummary, "impacts")
    max_abs_theta_left: Stoppable = like(MultibodySummary, "max_abs_theta_left")
    max_abs_theta_right: Stoppable = like(MultibodySummary, "max_abs_theta_right")
    overturn_time: float | None = like(MultibodySummary, "overturn_time")
    max_abs_crack_slip: float = like(MultibodySummary, "max_abs_crack_slip")
    max_crack_opening: float = like(MultibodySummary, "max_crack_opening")
    max_uplift: float = like(MultibodySummary, "max_uplift")
    collar_max_utilisation: float | None = like(MultibodySummary, "collar_max_utilisation")
    collar_first_yield_time: float | None = like(MultibodySummary, "collar_first_yield_time")
    collar_max_fibre_strain: float | None = like(MultibodySummary, "collar_max_fibre_strain")
    collar_ductility_demand: float | None = like(MultibodySummary, "collar_ductility_demand")
    collar_fractured: bool | None = like(MultibodySummary, "collar_fractured")
    collar_fracture_time: float | None = like(MultibodySummary, "collar_fracture_time")
    collar_max_plastic_strain: float | None = like(MultibodySummary, "collar_max_plastic_strain")
    collar_plastic_work: float | None = like(MultibodySummary, "collar_plastic_work")
    impact_velocity_ratio_mean: float | None = like(MultibodySummary, "impact_velocity_ratio_mean")
    energy_error_max: float = like(MultibodySummary, "energy_error_max")
    friction: float = like(MultibodySummary, "friction")
    dt: float = like(MultibodySummary, "dt")
    steps: int = like(MultibodySummary, "steps")
    wall_seconds: float = like(MultibodySummary, "wall_seconds")


@dataclass(frozen=True, kw_only=True)
class SdofSection:
    """``rigid_monolith`` (the whole-column SDOF block) and the first keys of ``rigid`` (the
    half block with collars): an overturned block's max_abs_theta is the words of its stop,
    not the pi/2 of its stopping rule."""

    overturned: bool = like(RockingSummary, "overturned")
    mode: str = like(RockingSummary, "mode")
    max_abs_theta: Stoppable = like(RockingSummary, "max_abs_theta")
    overturn_time: float | None = like(RockingSummary, "overturn_time")


@dataclass(frozen=True, kw_only=True)
class SdofHalfSection(SdofSection):
    """``rigid``: the SDOF half block with its elastic collars; the collar note only where a
    collar passed f_y."""

    collar_max_utilisation: float | None = like(RockingSummary, "collar_max_utilisation")
    collar_state: str | None = like(RockingSummary, "collar_state")
    impacts: int = like(RockingSummary, "impacts")
    collar_law: str | None = like(RockingSummary, "collar_law", left_out=True)
    collar_note: str | None = like(RockingSummary, "collar_note", left_out=True)


@dataclass(frozen=True, kw_only=True)
class SdofColumnSection(SdofSection):
    """``rigid_monolith``: the whole column as one SDOF block."""

    impacts: int = like(RockingSummary, "impacts")


@dataclass(frozen=True, kw_only=True)
class PeakRotations:
    """``peak_rotations``: each model's largest rotation, the words of its stop where it
    overturned."""

    fem_left: Stoppable = quantity("rad", "FEM, left half")
    fem_right: Stoppable = quantity("rad", "FEM, right half")
    multibody_left: Stoppable = quantity("rad", "rigid multibody model, left half")
    multibody_right: Stoppable = quantity("rad", "rigid multibody model, right half")


@dataclass(frozen=True, kw_only=True)
class Verdict:
    """``verdict``: the cross-check's answers in words (yes, no, undecided, not applicable)."""

    rigid_assumption_ok: str = quantity("", "the FEM and the multibody model agree")
    sdof_half_model_ok: str = quantity("", "the paper's SDOF half block agrees with multibody")
    collars_yield: str = quantity("", "do the collars yield")
    toe_crushes: str = quantity("", "does the toe crush")
    rocks_as_one_block: str = quantity("", "the halves rock as one block")
    overturns_fem: str = quantity("", "does the FEM column overturn")


@dataclass(frozen=True, kw_only=True)
class ToeStress:
    """``toe_stress``: the toe stress refined over the impact of the median replica
    (colonna.fem.toe_stress), the quoted answer."""

    stress: float = quantity("Pa", "refined toe-window peak")
    ratio: float = quantity("-", "refined toe-window peak over f_c")
    uncertainty: float = quantity("-", "the band's larger relative distance from the ratio")
    t_peak: float = quantity("s", "time of the refined window's peak")
    replica: int = quantity("", "the replica the windows restart from (the median's)")


@dataclass(frozen=True, kw_only=True)
class Bed:
    """``bed``: the bed under the column and the toe's Winkler pivot at alpha / 2 over its
    range (studies.fem_study.toe_resolution)."""

    stiffness: float = quantity("N/m^3", "bed stiffness per unit area k")
    low: float = quantity("N/m^3", "softest bed stiffness of the range")
    high: float = quantity("N/m^3", "stiffest bed stiffness of the range")
    source: str = quantity("", "where the bed's stiffness comes from")
    contact_length: float = quantity("m", "Winkler contact length c = sqrt(2 W / (k t theta))")
    toe_size: float = quantity("m", "toe element size that resolves it (c / 4)")
    pressure: float = quantity("Pa", "Winkler toe pressure 2 W / (t c)")
    pressure_low: float = quantity("Pa", "the same, softest bed")
    pressure_high: float = quantity("Pa", "the same, stiffest bed")


@dataclass(frozen=True, kw_only=True)
class Pulse:
    """``pulse``: where the ground motion sits (a record: its peak, no Omega)."""

    omega_ratio: float | None = quantity("-", "Omega / p of the SDOF block (None: a record)")
    amplitude_ratio: float = quantity("-", "a_p / a_uplift of the SDOF block")
    amplitude: float = quantity("m/s^2", "peak ground acceleration")
    omega: float | None = quantity("rad/s", "the pulse's circular frequency (None: a record)")
    record: str = absent("", "the record's name (a record only)")


@dataclass(frozen=True, kw_only=True)
class CrosscheckSummary:
    """The cross-check's summary.json, the sections its report reads."""

    study: str = quantity("", "the study's name")
    outcome: dict[str, Any] = quantity("", "the models' motion and the answers (studies.outcome)")
    fem: FemSection = section(FemSection, "the FEM ensemble")
    peak_rotations: PeakRotations = section(PeakRotations, "each model's largest rotation")
    rigid_multibody: MultibodySection = section(MultibodySection, "the rigid multibody run")
    rigid: SdofHalfSection = section(SdofHalfSection, "the SDOF half block with collars")
    rigid_monolith: SdofColumnSection = section(SdofColumnSection, "the whole-column SDOF")
    verdict: Verdict = section(Verdict, "the answers in words")
    toe_stress: ToeStress | None = section(ToeStress, "the refined toe stress", optional=True)
    bed: Bed = section(Bed, "the bed and the toe's Winkler pivot")
    pulse: Pulse = section(Pulse, "where the ground motion sits")
    collar_fy: list[float] = quantity("Pa", "each collar's yield stress")
    stone_fc: float = quantity("Pa", "the stone's compressive strength f_c")


def load(data: dict[str, Any]) -> CrosscheckSummary:
    """The cross-check's summary.json (its dict) as typed sections: a key a section declares
    that the file lacks raises StaleResultsError naming it (studies.sections.read)."""
    return read(CrosscheckSummary, data)


__all__ = ["ABSENT", "CrosscheckSummary", "load"]

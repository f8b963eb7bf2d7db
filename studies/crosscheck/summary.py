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
    crack_grows: str | None = quantity(
        "", "does the partial crack grow ([column] crack)", omit_when_none=True, default=None
    )


@dataclass(frozen=True, kw_only=True)
class ToeStress:
    """``toe_stress``: the toe stress refined over the impact of the median replica
    (colonna.fem.toe_stress), the quoted answer."""

    stress: float = quantity("Pa", "refined toe-window peak")
    ratio: float = quantity("-", "refined toe-window peak over f_c")
    uncertainty: float = quantity("-", "the band's larger relative distance from the ratio")
    t_peak: float = quantity("s", "time of the refined window's peak")
    replica: int = quantity("", "the replica the windows restart from (the median's)")
    mesh_uncertainty: float = quantity("-", "the refinement's relative mesh uncertainty")
    replica_spread: float = quantity("-", "the replicas' spread of the unrefined toe stress")
    band_ratio: dict[str, float] = quantity("-", "min and max of the band, over f_c")
    spread: float = quantity("-", "spread of the refined windows' peaks")
    bound_ratio: float = quantity("-", "the refinement's upper bound over f_c")
    ratios: list[float] = quantity("-", "each refinement's peak over f_c")
    t_start: float = quantity("s", "start of the toe window's impact")
    t_end: float = quantity("s", "end of the toe window's impact")
    refinements: list[int] = quantity("", "the toe refinements run")
    dofs: list[int] = quantity("", "degrees of freedom of each refined mesh")
    steps: list[int] = quantity("", "time steps of each refined window")
    handover_error: float = quantity("-", "relative error of the state handed to the windows")
    edge_length: float = quantity("m", "length from the toe the toe stress averages over")
    observed_order: float | None = quantity("-", "observed order of convergence (None: none)")
    static_mean_ratio: float = quantity("-", "mean base pressure at rest over f_c")
    unrefined_ratio: float = quantity(
        "-", "the median replica's toe stress on the study mesh / f_c"
    )
    richardson_ratio: float | None = quantity("-", "Richardson estimate over f_c (None: none)")


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
    yield_pressure: float | None = quantity("Pa", "the bed's yield pressure (None: elastic)")
    weight: float = quantity("N", "the rocking body's weight and top load W")
    theta: float = quantity("rad", "the tilt the Winkler pivot is taken at (alpha / 2)")
    elements_across: int = quantity("", "elements across c the toe grading asks for")
    study_mesh_toe_size: float = quantity("m", "toe element size of the study mesh")
    finest_toe_size: float = quantity("m", "toe element size of the finest toe window")
    finest_refinement: int = quantity("", "the finest toe refinement")
    across_study_mesh: float = quantity("-", "study-mesh toe elements across c")
    across_finest: float = quantity("-", "finest toe window's elements across c")
    pressure_ratio: float = quantity("-", "Winkler toe pressure over f_c")
    pressure_low_ratio: float = quantity("-", "the same, softest bed")
    pressure_high_ratio: float = quantity("-", "the same, stiffest bed")
    range_runs: dict[str, Any] | None = quantity(
        "", "the unperturbed FEM run on the softest, nominal and stiffest bed (None: no range)"
    )
    winkler_run_ratio_max: float = quantity("-", "the runs' largest Winkler toe pressure / f_c")


@dataclass(frozen=True, kw_only=True)
class CollarSection:
    """``collars``: a collar as the report draws it (runner._collar_section)."""

    y: float = quantity("m", "height of the collar above the base")
    t: float = quantity("m", "band thickness")
    h: float = quantity("m", "band height")
    span: float = quantity("m", "span between the attachment points")
    E: float = quantity("Pa", "steel Young's modulus")
    fy: float = quantity("Pa", "yield stress f_y")
    Eh: float | None = quantity("Pa", "hardening modulus E_h")
    plastic_modulus: float | None = quantity("Pa", "plastic modulus H")
    plastic: bool = quantity("", "a plastic collar (else elastic)")
    eps_u: float = quantity("-", "fracture strain")
    hinge_length: float = quantity("m", "end hinges' plastic length L_p")
    yield_moment: float = quantity("N m", "M_y = f_y t h^2 / 6")
    plastic_moment: float = quantity("N m", "M_p = f_y t h^2 / 4")
    yield_strain: float = quantity("-", "eps_y = f_y / E")
    section: str = quantity("", "the local law the models step: fibre or resultant")
    n_fibres: int = quantity("", "a fibre section's layers")
    n_sections: int = quantity("", "a fibre collar's integration sections")


@dataclass(frozen=True, kw_only=True)
class Tolerances:
    """``verdict_criteria.tolerances``: what "the same answer" allows."""

    peak: float = quantity("-", "|theta / theta_reference - 1| allowed")
    history: float = quantity("-", "history error to the first impact allowed")
    impacts: int = quantity("", "impacts before the pulse's end may differ by this many")


@dataclass(frozen=True, kw_only=True)
class VerdictCriteria:
    """``verdict_criteria``: the FEM against the multibody model on four counts."""

    same_outcome: str = quantity("", "the same outcome in words")
    replicas: int = quantity("", "FEM replicas the counts are over")
    history_error_to_first_impact: float | None = quantity(
        "-", "history error to the first impact, median over the replicas"
    )
    peak_ok: str = quantity("", "peak rotations within the tolerance")
    impacts_before_pulse_end_multibody: int = quantity("", "multibody impacts to the pulse's end")
    impacts_ok: str = quantity("", "impacts within the tolerance")
    history_window_end: float = quantity("s", "end of the history window (first impact)")
    history_ok: str = quantity("", "history error within the tolerance")
    at_rest: bool = quantity("", "neither model uplifts")
    bands: dict[str, Any] = quantity("", "the replicas' bands of the counts")
    tolerances: Tolerances = section(Tolerances, "the tolerances")
    fine_step_factor: float = quantity("-", "the finer multibody step, a fraction of its own")
    history_error_fine_step: float | None = quantity("-", "history error at the finer step")
    history_step_sensitive: bool = quantity("", "the two steps answer differently")


@dataclass(frozen=True, kw_only=True)
class FemVsMultibody:
    """``fem_vs_multibody``: how far the FEM is from the rigid multibody model."""

    t_end_fem: float = quantity("s", "end of the FEM run (or its overturning stop)")
    t_end_multibody: float | None = quantity("s", "multibody overturning time (None: stands)")
    collar_utilisation_ratio: Stoppable = quantity("-", "FEM over multibody collar utilisation")
    crack_slip_fem: float | None = quantity("m", "largest crack slip, FEM")
    crack_slip_multibody: float = quantity("m", "largest crack slip, multibody")


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
    """The cross-check's summary.json, every key in the file's order: what the runner writes
    (runner.assemble_summary: the FEM, toe stress, bed and criteria sections as their dicts)
    and the report reads. ``wall_seconds`` is added once the study is done."""

    study: str = quantity("", "the study's name")
    outcome: dict[str, Any] = quantity("", "the models' motion and the answers (studies.outcome)")
    verdict: Verdict = section(Verdict, "the answers in words")
    verdict_caveats: dict[str, str] = quantity("", "why a verdict rests on a model's limits")
    sdof_at_rest: bool = quantity("", "neither the SDOF nor the multibody model uplifts")
    fem: FemSection = section(FemSection, "the FEM ensemble")
    peak_rotations: PeakRotations = section(PeakRotations, "each model's largest rotation")
    collar_heights: list[float] = quantity("m", "each collar's height")
    collar_fy: list[float] = quantity("Pa", "each collar's yield stress")
    collars: list[CollarSection] = section(CollarSection, "each collar", many=True)
    collar_ductility_limit: float = quantity("-", "largest fibre strain / eps_y allowed")
    stone_fc: float = quantity("Pa", "the stone's compressive strength f_c")
    toe_stress: ToeStress | None = section(ToeStress, "the refined toe stress", optional=True)
    bed: Bed = section(Bed, "the bed and the toe's Winkler pivot")
    rigid_multibody: MultibodySection = section(MultibodySection, "the rigid multibody run")
    rigid: SdofHalfSection = section(SdofHalfSection, "the SDOF half block with collars")
    rigid_monolith: SdofColumnSection = section(SdofColumnSection, "the whole-column SDOF")
    theta_peak_ratio_fem_over_multibody: Stoppable = quantity("-", "peak rotation ratio")
    fem_vs_multibody: FemVsMultibody = section(FemVsMultibody, "FEM against multibody")
    verdict_criteria: VerdictCriteria = section(VerdictCriteria, "the verdict's four counts")
    theta_peak_ratio_fem_over_rigid: Stoppable = quantity("-", "peak rotation ratio")
    theta_peak_ratio_fem_over_monolith: Stoppable = quantity("-", "peak rotation ratio")
    theta_peak_ratio_rigid_over_multibody: Stoppable = quantity("-", "peak rotation ratio")
    theta_peak_ratio_monolith_over_multibody: Stoppable = quantity("-", "peak rotation ratio")
    restitution_after_motion_fem: Stoppable = quantity(
        "-", "FEM impacts' velocity ratio after the ground motion (median)"
    )
    restitution_after_motion_multibody: Stoppable = quantity(
        "-", "multibody impacts' velocity ratio after the ground motion"
    )
    restitution_housner: float = like(RockingSummary, "restitution_housner")
    pulse: Pulse = section(Pulse, "where the ground motion sits")
    peak_tolerance: float = quantity("-", "|theta / theta_reference - 1| for one answer")
    convergence: dict[str, Any] | None = quantity(
        "", "the FEM numbers on meshes 4h, 2h, h (None: not run)"
    )
    wall_seconds: float = absent("s", "the study's wall-clock time")


def load(data: dict[str, Any]) -> CrosscheckSummary:
    """The cross-check's summary.json (its dict) as typed sections: a key a section declares
    that the file lacks raises StaleResultsError naming it (studies.sections.read)."""
    return read(CrosscheckSummary, data)


__all__ = ["ABSENT", "CrosscheckSummary", "load"]

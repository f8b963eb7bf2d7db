"""The cross-check study: one column and pulse through the FEM contact model and the rigid
rocking solver, side by side, with the safety checks and a verdict.

Cases (run through :mod:`studies.executor`, each saved as it completes):
  fem        the 2D contact model of the study
  multibody  the rigid multibody model with the FEM's contact topology: rigid halves, ground and
             crack contact with the study's friction, collars as frame elements. The rigid
             reference: "FEM minus multibody" is the effect of deformability alone
  rigid      the paper's SDOF model: one half block with the collars, both halves rotating equally
  monolith   the whole column as one rigid SDOF block (the limit of a crack held shut)
  spectrum   the rigid overturning spectra around the study's pulse: the SDOF half block's with
             collars, and the rigid multibody model's on a coarser grid

The SDOF models are simplifications of the multibody one; "SDOF minus multibody" is the error of
their kinematic assumption, reported beside the verdict.
"""

from __future__ import annotations

import math
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from ...core.constants import DUCTILITY_LIMIT
from ...core.errors import InputError, StaleResultsError
from ...core.quantities import selected
from ...fem.ensemble import LANDING_DEPENDENT, NO, YES, band, decide_count
from ...fem.solver import unreliable_reason
from ...rigid.impacts import half_cycles, impact_ratios_from_peaks
from ...rigid.multibody import MultibodySummary
from ...rigid.solve import motion_word
from ..executor import RunOptions, run_cases
from ..fem_study import case_of, mesh_uncertainty_sizes, study_of_case
from ..guard import check_fem_results
from ..kinds import kind_of_package
from ..models import multibody_spectrum, run_multibody, run_sdof, sdof_spectrum
from ..outcome import (
    QUESTIONS,
    CollarOutcome,
    collars_hold,
    crack_grows,
    criteria_answer,
    fem_model,
    fem_stop,
    is_stopped,
    limit_answer,
    model_outcome,
    not_assessed,
    outcome,
    overturned_at,
    rocking_block,
    unless_stopped,
    without_stopping_angles,
)
from ..output import read_csv, write_csv, write_json
from ..sections import ABSENT, keyed, keys_of, written
from ..study import Study
from ..work import FemWork
from ..work import fem_work as estimate_work
from .summary import (
    CrosscheckSummary,
    MultibodySection,
    PeakRotations,
    Pulse,
    SdofColumnSection,
    SdofHalfSection,
    Verdict,
)

NOT_APPLICABLE = "not applicable"
SDOF_HALF = "SDOF half block with collars (the paper's)"  # the model's name in the outcome

# tolerances of the verdict "rigid assumption good enough?" (FEM against the multibody model)
PEAK_TOLERANCE = 0.20  # |theta / theta_reference - 1| for two models to give one answer
HISTORY_TOLERANCE = 0.10  # max |theta_FEM - theta_rigid| / max |theta_rigid| to the first impact
IMPACT_TOLERANCE = 0  # impacts before the end of the pulse may differ by this many
REFERENCE_STEP = 0.25  # the multibody reference runs at this fraction of its default step
FINE_STEP = 0.25  # and is rerun at this fraction of that


TOE_START = "toe_start.npz"  # in the fem case's folder: the state the toe windows restart from


def fem_case(case: dict, directory: str) -> dict:
    """The study's FEM run as an ensemble of replicas (``case["replicas"]``, default the study's
    ``[run] replicas``): ``summary`` is :func:`colonna.fem.ensemble.ensemble_summary` of the
    replicas' (landing-dependent numbers as median and band), ``replica_summaries`` each
    replica's own. The ensemble saves checkpoints in the case's folder as it goes, and a rerun
    of an interrupted case goes on from the last (:func:`studies.models.case_checkpoint`).
    With ``toe_refinement`` it also saves where the toe stress's refinement
    starts (:func:`colonna.fem.toe_stress.refinement_start` of the replica whose toe stress is
    the median) as ``toe_start.npz``, and says so under ``toe_start`` (the replica and the
    state's SHA-256, :func:`colonna.fem.toe_stress.start_digest`): the refined windows are
    cases of their own (:func:`toe_case`)."""
    from ...fem.ensemble import ensemble_summary, median_replica
    from ..models import case_checkpoint, run_fem

    study = study_of_case(case)
    replicas = run_fem(
        study,
        out_dir=directory,
        progress=case.get("progress", False),
        replicas=case.get("replicas"),
        checkpoint=case_checkpoint(case, directory),
    )
    summaries = [fem_run_summary(study, r) for r in replicas]
    summary = ensemble_summary(summaries, FEM_BANDED)
    out = {
        "summary": summary,
        "replica_summaries": summaries,
        "crack_slip_max": summary["crack_slip_max"],
    }
    if (
        case.get("toe_refinement")
        and study.mesh_file is None
        and study.toe_refinements
        and unreliable_reason(summaries) is None  # no landing to refine in a broken run
    ):
        from ...fem.output import write_start
        from ...fem.toe_stress import check_refinements, refinement_start, start_digest

        check_refinements(study.toe_refinements)
        m = median_replica([s["edge_stress_max"] for s in summaries])
        start = refinement_start(replicas[m])
        write_start(Path(directory) / TOE_START, start)
        out["toe_start"] = {"replica": m, "sha256": start_digest(start)}
    return out


def toe_case(case: dict, directory: str) -> dict:
    """One window of the toe stress's refinement: the study's mesh with its toe zones refined
    ``case["refinement"]`` times, restarted from the state the FEM case saved in its folder
    (beside this case's: ``cases/fem``), whose SHA-256 ``case["start"]`` is an input of this
    case, over the impact window (:func:`studies.models.refine_toe_window`)."""
    from ...fem.output import read_start
    from ...fem.toe_stress import start_digest
    from ..models import refine_toe_window

    study = study_of_case(case)
    path = Path(directory).parent / "fem" / TOE_START
    start = read_start(path)
    if start_digest(start) != case["start"]:
        raise StaleResultsError(f"{path} is not the state the FEM case saved: run with --force")
    return refine_toe_window(study, start, case["refinement"])


def refine_toe_stress(study, fem: dict, out: Path, options: RunOptions) -> dict | None:
    """The toe stress's refinement over the impact of the FEM case's median replica: one case
    per refinement (:func:`toe_case`, the finest first: they run on as many workers as there
    are, each saved as it completes), then :func:`colonna.fem.toe_stress.refinement_summary`
    with the replica's number. None when the FEM case saved no start (a mesh file, or no
    refinements asked for)."""
    from ...fem.output import read_start
    from ...fem.toe_stress import refinement_summary

    start = fem.get("toe_start")
    if start is None:
        return None
    path = out / "cases" / "fem" / TOE_START
    saved_start = read_start(path)
    revise_toe_estimate(study, saved_start, out, options)
    refinements = list(study.toe_refinements)
    cases = [
        case_of(
            study,
            key=f"toe-{r}",
            kind="toe",
            refinement=r,
            start=start["sha256"],
        )
        for r in sorted(refinements, reverse=True)  # the finest (the longest) starts first
    ]
    windows = run_cases(_case_runner, cases, out, stage="toe stress windows", run_options=options)
    refined = refinement_summary(
        saved_start, refinements, [windows[f"toe-{r}"] for r in refinements]
    )
    refined["replica"] = start["replica"]
    write_json(out / "toe_refinement.json", refined)
    return refined


# landing-dependent numbers of a FEM run, reported as bands over the replicas
FEM_BANDED = LANDING_DEPENDENT + (
    "crack_slip_max",
    "impacts_before_pulse_end",
    "restitution_after_motion",
)


def impacts_before(t, thetas, t_end: float) -> int:
    """Impacts (half cycles of the rotation) up to ``t_end``, the most of the given histories."""
    return max(int(np.sum(t[half_cycles(th)] <= t_end)) for th in thetas)


def restitution_after_motion(study, t, theta) -> float | None:
    """Mean velocity ratio of the impacts after the ground motion has ended, from the rotation
    peaks either side through the free-rocking energy (exact for free rocking; see
    :func:`colonna.rigid.impacts.impact_ratios_from_peaks`); None without such an impact (the
    column overturned, or came to rest, first). Under the ground motion the ground works
    through every impact, and a ratio measured there (it can exceed 1) means nothing."""
    end = max(study.ground.end_time, study.vertical.end_time)
    free = np.asarray(t) >= end
    if np.count_nonzero(free) < 3:
        return None
    t_free, theta_free = np.asarray(t)[free], np.asarray(theta)[free]
    measured = impact_ratios_from_peaks(t_free, theta_free, study.rocking_alpha)
    ratios = measured.ratios
    # the first sample counts as a peak; it is one only if the column was swinging outward
    # then: a first impact whose peak before is that sample is left out
    crossings = half_cycles(theta_free)
    if (
        ratios.size
        and measured.times[0] == t_free[crossings[0]]
        and measured.peak_before[0] == abs(theta_free[0])
    ):
        ratios = ratios[1:]
    return float(np.mean(ratios[:5])) if ratios.size else None


def fem_run_summary(study, result) -> dict:
    """A FEM run's summary with what the cross-check reads from its history: the largest crack
    slip (m), the impacts before the end of the pulse and the velocity ratio of the impacts
    after the ground motion."""
    h = result.history
    out = dict(result.summary)
    out["crack_slip_max"] = float(np.max(h["crack_slip_max"])) if "crack_slip_max" in h else 0.0
    out["impacts_before_pulse_end"] = impacts_before(
        h["t"], (h["theta_left"], h["theta_right"]), study.ground.end_time
    )
    out["restitution_after_motion"] = restitution_after_motion(study, h["t"], h["theta_left"])
    return out


def rigid_case(case: dict, directory: str) -> dict:
    study = study_of_case(case)
    result = run_sdof(study, whole_column=case["key"] == "monolith")
    columns = {"t": result.time, "theta": result.theta, "theta_dot": result.theta_dot}
    for k, hist in enumerate(result.collar_histories, start=1):
        columns[f"collar_{k}_stress"] = hist.stress
    write_csv(Path(directory) / "history.csv", columns)
    summary = result.summary()
    summary["alpha"] = result.block.alpha
    return summary


def multibody_case(case: dict, directory: str) -> dict:
    """The rigid multibody model of the study, at its default step times ``step_factor``."""
    from ...rigid.multibody import build_column, default_step, history_columns

    study = study_of_case(case)
    dt = None
    if case.get("step_factor", 1.0) != 1.0:
        column = build_column(
            study.rocking_block,
            cracked=study.cracked,
            collars=study.collars,
            friction=study.contact.friction,
        )
        dt = case["step_factor"] * default_step(column, study.ground)
    result = run_multibody(study, dt)
    write_csv(Path(directory) / "history.csv", history_columns(result))
    summary = result.summary()
    summary["restitution_after_motion"] = restitution_after_motion(
        study, result.time, result.theta[:, 0]
    )
    return summary


def spectrum_case(case: dict, directory: str) -> dict:
    """The overturning spectra around the study's pulse: the SDOF half block with collars on a
    fine grid, and under ``multibody`` the rigid multibody model (the verdict's rigid
    reference) on a coarse grid over the same range (``case["multibody_grid"]``: omega ratios
    x amplitude ratios, default 7 x 6; its nodes nearest the study's pulse moved onto it)."""
    study = study_of_case(case)
    block = study.rocking_block
    omega_ratio = study.ground.omega / block.p
    amplitude_ratio = abs(study.ground.amplitude) / block.uplift_acceleration("nonlinear")
    omega_range = (max(0.2, 0.25 * omega_ratio), 2.0 * omega_ratio + 1.0)
    amplitude_range = (1.0, max(2.0 * amplitude_ratio, 4.0))
    omegas = np.linspace(*omega_range, 60)
    amplitudes = np.linspace(*amplitude_range, 50)
    spec = sdof_spectrum(study, omegas, amplitudes)
    data = spec.to_dict()
    data.update(study_omega_ratio=omega_ratio, study_amplitude_ratio=amplitude_ratio)

    def through_study(bounds, n, value, lowest=0.0):  # n nodes, the nearest one on value
        nodes = np.linspace(*bounds, n)
        if value >= lowest:
            nodes[np.argmin(np.abs(nodes - value))] = value
        return np.unique(nodes)

    n_omega, n_amplitude = case.get("multibody_grid", (7, 6))
    mb = multibody_spectrum(
        study,
        through_study(omega_range, n_omega, omega_ratio),
        through_study(
            amplitude_range, n_amplitude, amplitude_ratio, lowest=1.0
        ),  # below 1 the column does not rock
    )
    data["multibody"] = dict(mb.to_dict(), cracked=study.cracked, friction=study.contact.friction)
    write_json(Path(directory) / "spectrum.json", data)
    return {
        "omega_ratio": omega_ratio,
        "amplitude_ratio": amplitude_ratio,
        "seconds": spec.seconds,
        "multibody_seconds": mb.seconds,
    }


def _case_runner(case: dict, directory: str) -> dict:
    kind = case["kind"]
    if kind == "fem":
        return fem_case(case, directory)
    if kind == "rigid":
        return rigid_case(case, directory)
    if kind == "multibody":
        return multibody_case(case, directory)
    if kind == "toe":
        return toe_case(case, directory)
    return spectrum_case(case, directory)


def run(study: Study, out: Path, options: RunOptions) -> dict:
    """Run (or resume) the cross-check of a study (:func:`studies.study.load`) into ``out``:
    its cases, the toe stress's refinement, the verdict and ``summary.json``."""
    fem = study.fem  # fails early
    if not fem.ground.moves:
        raise InputError(
            f"{study.source}: the cross-check study needs a ground motion "
            "(ground.pulse = sine, cosine or record); for free rocking use "
            f"[study] kind = {kind_of_package('free_rocking')!r}"
        )
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    cases = [
        case_of(
            fem,
            key="fem",
            kind="fem",
            progress=options.progress and not options.scheduler,
            toe_refinement=True,
        ),
        case_of(fem, key="multibody", kind="multibody", step_factor=REFERENCE_STEP),
        case_of(
            fem, key="multibody-fine", kind="multibody", step_factor=REFERENCE_STEP * FINE_STEP
        ),
        case_of(fem, key="rigid", kind="rigid"),
        case_of(fem, key="monolith", kind="rigid"),
    ]
    if fem.ground.pulse_shape is not None:  # a pulse is placed on the rigid spectrum
        cases.append(case_of(fem, key="spectrum", kind="spectrum"))
    # mesh-convergence uncertainty of the FEM numbers: the same run on meshes 2h and 4h
    for factor, size in zip((2, 4), mesh_uncertainty_sizes(fem)):
        cases.append(case_of(replace(fem, mesh_size=size), key=f"fem-mesh-{factor}h", kind="fem"))
    cases += bed_range_cases(fem)
    start = time.perf_counter()
    results = run_cases(_case_runner, cases, out, stage="FEM and rigid models", run_options=options)
    check_fem_results(results, out)
    # then the toe stress's refinement, from the state the FEM case saved
    refined = refine_toe_stress(fem, results["fem"], out, options)
    if refined is not None:
        results["fem"] = {**results["fem"], "toe_refinement": refined}
    fem_histories = replica_histories(out / "cases" / "fem", results["fem"]["summary"]["replicas"])
    criteria = verdict_criteria(
        fem, results, fem_histories, read_csv(out / "cases" / "multibody" / "history.csv")
    )
    criteria.update(
        step_check(
            criteria,
            verdict_criteria(
                fem,
                {**results, "multibody": results["multibody-fine"]},
                fem_histories,
                read_csv(out / "cases" / "multibody-fine" / "history.csv"),
            ),
        )
    )
    summary = assemble_summary(fem, results, criteria=criteria)
    summary["wall_seconds"] = time.perf_counter() - start
    write_json(out / "summary.json", summary)
    return summary


FEWER = ", fewer [run] replicas"  # its way to ask for less FEM work (besides [run], [mesh])


def expected_work(study: Study) -> FemWork:
    """The FEM work of the cross-check as it is expected to run (:func:`fem_work` to
    :func:`expected_stop`), for the estimate of its time (studies.driver.expected_work_of)."""
    return fem_work(study, until=expected_stop(study.fem))


def fem_work(study: Study, until: float | None = None) -> FemWork:
    """The FEM work of the cross-check (:func:`studies.driver.check_work`), case by case: the
    study's run with its replicas, the same on the meshes of its mesh-convergence uncertainty,
    the bed range's runs, then (a stage of their own) the toe windows on their refined meshes.
    The FEM runs stop where the column overturns: ``until`` (s), where they are expected to
    (:func:`expected_work`), bounds their time; their memory and the work limit's measure stay
    those of the whole duration."""
    fem = study.fem
    models: dict = {}  # the model of each mesh, built once
    work = estimate_work(fem, fem.replicas, models=models, case="fem", until=until)
    for factor, size in zip((2, 4), mesh_uncertainty_sizes(fem)):
        mesh = replace(fem, mesh_size=size)
        work += estimate_work(
            mesh, fem.replicas, models=models, case=f"fem-mesh-{factor}h", until=until
        )
    for end, bed in bed_range_studies(fem).items():
        work += estimate_work(bed, 1, models=models, case=f"fem-bed-{end}", until=until)
    return work + toe_window_work(fem) + rigid_work(fem)


EXPECTED_STOP_SECONDS = (
    5.0  # the most of the study's time the multibody run of the estimate may take
)


def expected_stop(fem) -> float:
    """Where the FEM runs of the cross-check are expected to stop (s), for the estimate of
    their time: the study's duration, or, where the rigid multibody model (its default step:
    a fraction of a second for a pulse) overturns at t_o, a quarter of the way from t_o to the
    duration. The FEM usually overturns where the multibody does (the default column: 1.41 s
    against 1.39 s of 2.53 s), but the cross-check is run to find where it does not: a quarter
    of the way keeps the default study's estimate within 1.4 times its wall time either way
    (benchmarks/bench_estimate.py)."""
    if MULTIBODY_SECONDS_PER_SECOND * fem.duration > EXPECTED_STOP_SECONDS:
        return (
            fem.duration
        )  # a long record: its multibody run costs more than the estimate is worth
    rigid = run_multibody(fem).summary()
    end = rigid.get("overturn_time")
    if not rigid.get("overturned") or end is None:
        return fem.duration
    end = min(end, fem.duration)
    return end + 0.25 * (fem.duration - end)


# CPU seconds of the rigid cases (measured on the machine of the README's timings: the default
# study's spectrum case 15 s, the tiny test study's 10 s; its multibody runs 0.7 s a simulated s)
SPECTRUM_SECONDS = 12.0
MULTIBODY_SECONDS_PER_SECOND = 0.75


def rigid_work(fem) -> FemWork:
    """The rigid cases as work of the study's first stage (for its wall time): the multibody
    runs and, with a pulse, the spectra."""
    from ..work import FemRun

    runs = [
        FemRun(0, 0, 0, 0, "multibody", other_seconds=MULTIBODY_SECONDS_PER_SECOND * fem.duration)
    ]
    if fem.ground.pulse_shape is not None:
        runs.append(FemRun(0, 0, 0, 0, "spectrum", other_seconds=SPECTRUM_SECONDS))
    return FemWork(runs=tuple(runs))


# s: a toe window's length, about (fem.toe_stress: from LEAD_TIME before the landing to
# TAIL_TIME after the peak, the landing itself a few ms); measured 24-34 ms on the default column
# under its pulse
TOE_WINDOW = 0.03
# s: the same under a record, whose peak toe stress came as the column tilted on its toe after
# the landing: 0.30 and 0.28 s on two columns of docs/speed.md (a 5.2 m granite column under a
# 10 s record, a 6 m one under a 12 s record)
TOE_WINDOW_RECORD = 0.3


def expected_toe_window(fem) -> float:
    """The toe windows' length (s) expected before the FEM case finds it: :data:`TOE_WINDOW`
    under a pulse, :data:`TOE_WINDOW_RECORD` under a record."""
    return TOE_WINDOW if fem.ground.pulse_shape is not None else TOE_WINDOW_RECORD


def toe_window_work(fem, window: float | None = None) -> FemWork:
    """The work of the toe stress's refined windows (:func:`toe_case`), one state each over
    ``window`` (s; before the FEM case has found it, :func:`expected_toe_window`), in the stage
    after the other cases (none without refinements or with a mesh file)."""
    from ...fem.model import stable_time_step
    from ...fem.toe_stress import model_on
    from ..models import build, toe_mesh
    from ..work import FemRun

    if fem.mesh_file is not None or not fem.toe_refinements:
        return FemWork()
    window = expected_toe_window(fem) if window is None else window
    model = build(fem)
    work = FemWork()
    for refinement in fem.toe_refinements:
        fine = model_on(model, toe_mesh(fem, refinement))
        steps = window / stable_time_step(fine, fem.safety).dt
        nodes = fine.n_dofs // 2
        run = FemRun(nodes, steps, steps / 50.0, 1, f"toe-{refinement}", stage=1)
        work += FemWork(steps, steps * nodes, nodes, 0.0, (run,))
    return work


def revise_toe_estimate(fem, start: dict, out: Path, options: RunOptions) -> None:
    """The study's time estimated again as its toe windows start (``fem``: the study's FEM
    part): their length is known now (``start``, the FEM case's saved start: t_start to
    t_end), where the estimate took :func:`expected_toe_window`: a pulse's peak toe stress
    comes at a landing, a record's can come a few tenths of a second after it, as the column
    tilts on that toe, and a window ten times as long costs ten times as much."""
    from ..driver import wall_estimate, without_saved
    from ..executor import revise_study_estimate

    window = float(start["t_end"]) - float(start["t_start"])
    revise_study_estimate(
        lambda: wall_estimate(without_saved(toe_window_work(fem, window), out), options.workers),
        f"as the toe stress windows start, {1e3 * window:.0f} ms long (the first estimate "
        f"took {1e3 * expected_toe_window(fem):.0f} ms)",
        options.progress,
    )


def bed_range_studies(fem) -> dict:
    """The study on the softest and the stiffest bed of its range (one unperturbed run each, at
    its own stable step: a step set by hand for the nominal bed may be too long for the
    stiffest), where the bed's stiffness has a range: the toe answer at the range's ends."""
    bed = fem.bed
    if not bed.low < bed.high:
        return {}
    return {
        end: replace(
            fem,
            bed=replace(
                bed, stiffness=k, low=k, high=k, source=f"{bed.source}: the range's {end} end"
            ),
            replicas=1,
            dt=None,
        )
        for end, k in (("low", bed.low), ("high", bed.high))
    }


def bed_range_cases(fem) -> list[dict]:
    """The cases of :func:`bed_range_studies`, keys fem-bed-low and fem-bed-high."""
    return [
        case_of(study, key=f"fem-bed-{end}", kind="fem")
        for end, study in bed_range_studies(fem).items()
    ]


def replica_histories(directory: Path, replicas: int) -> list[dict]:
    """The history.csv of each replica of a FEM ensemble written by :func:`fem_case`."""
    directory = Path(directory)
    return [read_csv(directory / "history.csv")] + [
        read_csv(directory / "replicas" / str(r) / "history.csv") for r in range(1, replicas)
    ]


def _peak_ratio(value: float, reference: float) -> float:
    return value / reference if reference > 0 else math.nan


def _same_answer(fate, peak_ratio, reference_fate) -> bool:
    """Same outcome, and (when neither overturns) peaks within PEAK_TOLERANCE."""
    return bool(fate) == bool(reference_fate) and (
        bool(fate) or abs(peak_ratio - 1.0) <= PEAK_TOLERANCE
    )


def step_check(criteria: dict, fine: dict) -> dict:
    """The history criterion again against the multibody model at FINE_STEP of its step.

    The reference itself runs at REFERENCE_STEP of the default step: at the default step the
    collar utilisation and crack slip of the default column carry about 1 % of step error, at a
    quarter of it 0.3 %, for 0.2 s more.

    The early rotations, which the history criterion compares, are the part of the rigid
    solution most sensitive to its step: how a cracked column starts to rock (whether the
    halves press on each other at the crack) once hung on the scheme's drift, and rotations
    1e-9 apart in step ended 17 % apart (README, multibody model). This reruns that count so
    that a step-dependent answer shows. ``history_step_sensitive``: the two steps answer the
    criterion differently."""
    return {
        "history_error_fine_step": fine["history_error_to_first_impact"],
        "history_window_end_fine_step": fine["history_window_end"],
        "fine_step_factor": FINE_STEP,
        "history_ok_fine_step": fine["history_ok"],
        "history_step_sensitive": fine["history_ok"] != criteria["history_ok"],
    }


def _criteria_one(
    study,
    fem: dict,
    fem_history: dict,
    mb: dict,
    mb_t,
    theta_mb: list,
    impacts_mb: int,
    t_first: float,
) -> dict:
    """The four counts for one FEM replica against the multibody model (booleans); mb_t,
    theta_mb: the multibody history's times and rotations of the two halves."""
    theta_fem = [fem_history["theta_left"], fem_history["theta_right"]]
    window = mb_t <= t_first
    scale = max(np.max(np.abs(th[window]), initial=0.0) for th in theta_mb)
    errors = [
        np.max(np.abs(np.interp(mb_t[window], fem_history["t"], tf) - tm[window]), initial=0.0)
        for tf, tm in zip(theta_fem, theta_mb)
    ]
    history_error = float(max(errors) / scale) if scale > 0 else math.nan
    impacts_fem = impacts_before(fem_history["t"], theta_fem, study.ground.end_time)
    fem_peak = max(fem["max_abs_theta_left"], fem["max_abs_theta_right"])
    mb_peak = max(mb["max_abs_theta_left"], mb["max_abs_theta_right"])
    peak_ratio = _peak_ratio(fem_peak, mb_peak)
    either_over = bool(fem["overturned"]) or bool(mb["overturned"])
    fem_motion = motion_word(bool(fem["overturned"]), fem_peak, study.rocking_alpha)
    mb_motion = motion_word(bool(mb["overturned"]), mb_peak, study.rocking_alpha)
    # a column that stays at rest in both models: the FEM's rotation is then its elastic
    # sway (1e-7 rad against the rigid model's 1e-13), and its sign changes are vibration,
    # not impacts: the counts of rocking do not apply, the outcomes agree
    at_rest = fem_motion == mb_motion == "no uplift"
    # the peak count compares rotations of columns that stay up: where one model overturns,
    # its peak is where it stopped, so the count does not apply (None), and neither does the
    # ratio
    out = {
        "same_outcome": fem_motion == mb_motion,
        "peak_ratio": None if either_over or at_rest else peak_ratio,
        "peak_ok": None
        if either_over or at_rest
        else bool(abs(peak_ratio - 1.0) <= PEAK_TOLERANCE),
        "impacts_fem": impacts_fem,
        "impacts_multibody": impacts_mb,
        "impacts_ok": None if at_rest else abs(impacts_fem - impacts_mb) <= IMPACT_TOLERANCE,
        "history_error": history_error,
        "history_ok": None if at_rest else bool(history_error <= HISTORY_TOLERANCE),
    }
    out["at_rest"] = at_rest
    out["all_ok"] = all(
        out[k]
        for k in ("same_outcome", "peak_ok", "impacts_ok", "history_ok")
        if out[k] is not None
    )
    return out


def count_word(flags) -> str:
    """yes / no / undecided over the replicas where a count applies
    (:func:`colonna.fem.ensemble.decide_count`); ``not applicable`` where it applies to none."""
    flags = [f for f in flags if f is not None]
    return decide_count(flags) if flags else NOT_APPLICABLE


def verdict_criteria(
    study, results: dict, fem_histories: list[dict], multibody_history: dict
) -> dict:
    """The FEM against the rigid multibody model on four counts, each with its tolerance:
    outcome; peak rotation (when neither overturns); impacts before the end of the pulse; and
    the history error max |theta_FEM - theta_mb| / max |theta_mb| up to the first impact (of
    the multibody model; the end of the pulse without one, or the moment it passes the whole
    column's unstable equilibrium if that is earlier), both halves.

    Each count is made for every FEM replica; a count is yes where it holds in all of them, no
    where it holds in none, undecided otherwise; the numbers are medians with their ``bands``.
    The answer (``all_ok``) is yes where every replica passes all four counts, no where none
    does, undecided otherwise."""
    mb = results["multibody"]
    t_pulse = study.ground.end_time
    mb_t = multibody_history["t"]
    names = ("left", "right") if study.cracked else ("column", "column")
    theta_mb = [multibody_history[f"theta_{n}"] for n in names]
    crossings = [mb_t[half_cycles(th)] for th in theta_mb]
    firsts = [c[0] for c in crossings if c.size]
    t_first = min(firsts) if firsts else t_pulse
    # past the whole column's unstable equilibrium it is falling: beyond that the histories
    # differ by where each model stops, not by how it moved
    falling = np.nonzero(
        np.max(np.abs(np.array(theta_mb)), axis=0) > study.column_block.critical_angle()
    )[0]
    if falling.size:
        t_first = min(t_first, float(mb_t[falling[0]]))
    fem = results["fem"]
    summaries = fem.get("replica_summaries", [fem["summary"]])
    impacts_mb = impacts_before(mb_t, theta_mb, t_pulse)
    per = [
        _criteria_one(study, s, h, mb, mb_t, theta_mb, impacts_mb, t_first)
        for s, h in zip(summaries, fem_histories)
    ]
    bands = {
        key: band(c[key] for c in per) for key in ("peak_ratio", "impacts_fem", "history_error")
    }
    out = {
        "same_outcome": decide_count(c["same_outcome"] for c in per),
        "peak_ratio": bands["peak_ratio"]["median"],
        "peak_ok": count_word(c["peak_ok"] for c in per),
        "impacts_before_pulse_end_fem": bands["impacts_fem"]["median"],
        "impacts_before_pulse_end_multibody": impacts_mb,
        "impacts_ok": count_word(c["impacts_ok"] for c in per),
        "history_error_to_first_impact": bands["history_error"]["median"],
        "history_window_end": float(t_first),
        "history_ok": count_word(c["history_ok"] for c in per),
        "all_ok": decide_count(c["all_ok"] for c in per),
        # both models keep the column at rest in every replica: counts (2)-(4) do not apply
        "at_rest": all(c["at_rest"] for c in per),
        "replicas": len(per),
        "bands": bands,
        "tolerances": {
            "peak": PEAK_TOLERANCE,
            "history": HISTORY_TOLERANCE,
            "impacts": IMPACT_TOLERANCE,
        },
    }
    return out


def _word(flag: bool) -> str:
    return YES if flag else NO


def _multibody_stop(mb: dict) -> str | None:
    """Where the rigid multibody run overturned: :func:`studies.outcome.overturned_at`."""
    return overturned_at("the multibody model", mb["overturned"], mb.get("overturn_time"))


def _sdof_stop(name: str, sdof: dict) -> str | None:
    """Where an SDOF run overturned (its max_abs_theta is then pi/2 by convention)."""
    return overturned_at(name, sdof["overturned"], sdof.get("overturn_time"))


def _stops(fem: dict, results: dict) -> dict:
    """Each model's stop (:func:`studies.outcome.overturned_at`; None where it stayed up)."""
    return {
        "fem": fem_stop("the FEM", fem),
        "multibody": _multibody_stop(results["multibody"]),
        "rigid": _sdof_stop("the SDOF half block", results["rigid"]),
        "monolith": _sdof_stop("the whole-column SDOF", results["monolith"]),
    }


def assemble_summary(study, results: dict, criteria: dict) -> dict:
    """summary.json of the cross-check; ``criteria`` from :func:`verdict_criteria`."""
    fem = results["fem"]["summary"]
    multibody = results["multibody"]
    # a ratio of peak rotations compares columns that stay up: an overturned block's peak is
    # where its run stopped (pi/2 for the SDOF model, by convention), not a rotation it reached
    # (a run that stopped in any replica: its ensemble's median mixes stopping angles), in
    # its place the words that say which run stopped when
    stops = _stops(fem, results)
    ratios = _peak_ratios(results, stops)
    sdof_at_rest = _sdof_at_rest(study, results)
    answers = crosscheck_outcome(study, results, criteria)
    sdof_model = next(m for m in answers["models"] if m["model"] == SDOF_HALF)
    summary = {
        "study": study.name,
        "outcome": answers,
        "verdict": _verdict(study, results, answers, ratios, sdof_at_rest),
        # a verdict that rests on a model outside its validity: why (the SDOF's elastic
        # collars past f_y), said beside its word
        "verdict_caveats": {
            key: m["caveat"] for key, m in (("sdof_half_model_ok", sdof_model),) if m.get("caveat")
        },
        # neither the SDOF half block nor the multibody model uplifts the column
        "sdof_at_rest": sdof_at_rest,
        # the FEM's summary, its rotations (the angle it stopped at) not given where it overturned
        "fem": without_stopping_angles(fem, stops["fem"]),
        # each model's largest rotation, a rotation it reached where it stayed up
        "peak_rotations": written(
            PeakRotations(
                fem_left=unless_stopped(fem["max_abs_theta_left"], stops["fem"]),
                fem_right=unless_stopped(fem["max_abs_theta_right"], stops["fem"]),
                multibody_left=unless_stopped(multibody["max_abs_theta_left"], stops["multibody"]),
                multibody_right=unless_stopped(
                    multibody["max_abs_theta_right"], stops["multibody"]
                ),
            )
        ),
        **_limits(study),
        "toe_stress": _toe_stress(study, results),
        "bed": _bed(study, results),
        # the multibody run's summary, as its typed result selects it for the cross-check
        "rigid_multibody": without_stopping_angles(
            selected(multibody, MultibodySummary, MULTIBODY_KEYS), stops["multibody"]
        ),
        **_sdof_runs(results, stops),
        "theta_peak_ratio_fem_over_multibody": ratios["fem_over_multibody"],
        "fem_vs_multibody": _fem_vs_multibody(results["fem"], multibody),
        "verdict_criteria": criteria,
        "theta_peak_ratio_fem_over_rigid": ratios["fem_over_rigid"],
        "theta_peak_ratio_fem_over_monolith": ratios["fem_over_monolith"],
        # an overturned SDOF block reports pi/2 by convention: no rotation to compare
        "theta_peak_ratio_rigid_over_multibody": ratios["rigid_over_multibody"],
        "theta_peak_ratio_monolith_over_multibody": ratios["monolith_over_multibody"],
        # the velocity ratio of the impacts after the ground motion (free rocking), where
        # there are any: FEM median and band, multibody; of a run that overturned the rotation
        # peak after its last impact is the angle it stopped at, so none
        "restitution_after_motion_fem": unless_stopped(
            fem["restitution_after_motion"], stops["fem"]
        ),
        "restitution_after_motion_multibody": unless_stopped(
            multibody.get("restitution_after_motion"), stops["multibody"]
        ),
        "restitution_housner": study.rocking_block.restitution_housner,
        "pulse": _pulse_summary(study, results),
        "peak_tolerance": PEAK_TOLERANCE,
        "convergence": _uncertainty(results),
    }
    # its keys and their order are CrosscheckSummary's, the one declaration the report reads
    return keyed(CrosscheckSummary, summary)


def _two_halves_peak(summary: dict) -> float:
    """The larger of a two-half run's peak rotations (left, right); the multibody and FEM runs
    stop at the same overturning rule: the rotations they reached, not the pi/2 of a block
    lying down."""
    return max(summary["max_abs_theta_left"], summary["max_abs_theta_right"])


def _peak_ratios(results: dict, stops: dict) -> dict:
    """The ratios of the models' peak rotations (``fem_over_rigid``, ``fem_over_monolith``,
    ``fem_over_multibody``, ``rigid_over_multibody``, ``monolith_over_multibody``), each the
    words of :func:`_stops` in its place where either run stopped."""
    fem_peak = _two_halves_peak(results["fem"]["summary"])
    mb_peak = _two_halves_peak(results["multibody"])
    rigid, monolith = results["rigid"]["max_abs_theta"], results["monolith"]["max_abs_theta"]
    return {
        name: unless_stopped(_peak_ratio(value, reference), stops[model], stops[base])
        for name, value, model, reference, base in (
            ("fem_over_rigid", fem_peak, "fem", rigid, "rigid"),
            ("fem_over_monolith", fem_peak, "fem", monolith, "monolith"),
            ("fem_over_multibody", fem_peak, "fem", mb_peak, "multibody"),
            ("rigid_over_multibody", rigid, "rigid", mb_peak, "multibody"),
            ("monolith_over_multibody", monolith, "monolith", mb_peak, "multibody"),
        )
    }


def _sdof_at_rest(study, results: dict) -> bool:
    """Neither the SDOF half block nor the multibody model uplifts the column: the SDOF model
    agrees with the multibody one whatever the ratio of their (elastic, contact-compliance)
    rotations."""
    rigid, multibody = results["rigid"], results["multibody"]
    return (
        motion_word(rigid["overturned"], rigid["max_abs_theta"], rigid["alpha"])
        == motion_word(multibody["overturned"], _two_halves_peak(multibody), study.rocking_alpha)
        == "no uplift"
    )


def _verdict(study, results: dict, answers: dict, ratios: dict, sdof_at_rest: bool) -> dict:
    """The verdict's words: the outcome's answers, whether the paper's SDOF half block agrees
    with the multibody model, whether the halves rock as one block (not applicable where a
    run stopped or the FEM column does not uplift) and whether the FEM overturns."""
    fem, rigid, multibody = results["fem"]["summary"], results["rigid"], results["multibody"]
    words = {a["key"]: a["answer"] for a in answers["answers"]}
    ratio, ratio_monolith = ratios["fem_over_rigid"], ratios["fem_over_monolith"]
    fem_peak = _two_halves_peak(fem)
    fem_at_rest = motion_word(fem["overturned"], fem_peak, study.rocking_alpha) == "no uplift"
    verdict = Verdict(
        rigid_assumption_ok=words["rigid_assumption_ok"],
        sdof_half_model_ok=_word(
            sdof_at_rest
            or _same_answer(
                rigid["overturned"],
                _peak_ratio(rigid["max_abs_theta"], _two_halves_peak(multibody)),
                multibody["overturned"],
            )
        ),
        collars_yield=words["collars_yield"],
        toe_crushes=words["toe_crushes"],
        rocks_as_one_block=NOT_APPLICABLE
        if is_stopped(ratio) or is_stopped(ratio_monolith) or fem_at_rest
        else _word(abs(ratio_monolith - 1.0) < abs(ratio - 1.0)),
        overturns_fem=fem["overturned_answer"],
        crack_grows=words.get("crack_grows"),
    )
    return written(verdict)


def _limits(study) -> dict:
    """The collars' heights, yield stresses and sections, the ductility limit and the stone's
    strength: what the stresses and strains are judged against."""
    return {
        "collar_heights": [c.y for c in study.collars],
        "collar_fy": [c.fy for c in study.collars],  # Pa
        "collars": [_collar_section(study, c) for c in study.collars],
        # largest fibre strain / yield strain a collar may reach (EN 1993-1-1: eps_u >= 15 eps_y)
        "collar_ductility_limit": DUCTILITY_LIMIT,
        "stone_fc": study.stone.fc,  # Pa
    }


def _sdof_runs(results: dict, stops: dict) -> dict:
    """The SDOF runs' summaries, ``rigid`` (the half block with collars) and
    ``rigid_monolith`` (the whole column): an overturned block's max_abs_theta is the pi/2
    of its stopping rule, not shown."""
    rigid, monolith = results["rigid"], results["monolith"]
    return {
        "rigid": written(
            SdofHalfSection(
                overturned=rigid["overturned"],
                mode=rigid["mode"],
                max_abs_theta=unless_stopped(rigid["max_abs_theta"], stops["rigid"]),
                overturn_time=rigid.get("overturn_time"),
                collar_max_utilisation=rigid.get("collar_max_utilisation"),
                collar_state=rigid.get("collar_state"),
                impacts=rigid["impacts"],
                # "elastic" springs, and where a collar passed f_y, what that leaves out
                collar_law=rigid.get("collar_law", ABSENT),
                collar_note=rigid.get("collar_note", ABSENT),
            )
        ),
        "rigid_monolith": written(
            SdofColumnSection(
                overturned=monolith["overturned"],
                mode=monolith["mode"],
                max_abs_theta=unless_stopped(monolith["max_abs_theta"], stops["monolith"]),
                overturn_time=monolith.get("overturn_time"),
                impacts=monolith["impacts"],
            )
        ),
    }


# what the summary keeps of the rigid multibody run (its run summary has more: p, alpha, ...):
# the keys of its section, the one declaration the report reads too
MULTIBODY_KEYS = keys_of(MultibodySection)


def _collar_section(study, collar) -> dict:
    """A collar as the report draws it (SI units): its height, band section, span between
    the attachment points (the column's width unless set), steel (E, f_y, the hardening
    modulus E_h and plastic modulus H), law (plastic or elastic), fracture strain eps_u and
    end hinges' plastic length L_p, with the moments and strain they give: M_y = f_y t h^2 / 6,
    M_p = f_y t h^2 / 4, eps_y = f_y / E; the local law the models step ("fibre" or
    "resultant") and a fibre section's layers and sections."""
    return {
        "y": collar.y,
        "t": collar.t,
        "h": collar.h,
        "span": collar.length if collar.length is not None else study.width,
        "E": collar.E,
        "fy": collar.fy,
        "Eh": collar.hardening_modulus,
        "plastic_modulus": collar.plastic_modulus,
        "plastic": collar.plastic,
        "eps_u": collar.eps_u,
        "hinge_length": collar.plastic_hinge_length,
        "yield_moment": collar.yield_moment,
        "plastic_moment": collar.plastic_moment,
        "yield_strain": collar.yield_strain,
        "section": collar.local_law,
        "n_fibres": collar.n_fibres,
        "n_sections": collar.n_sections,
    }


def _pulse_summary(study, results: dict) -> dict:
    """Where the ground motion sits: a pulse's Omega/p and a_p / a_uplift; a record's peak
    acceleration (m/s^2, after its scale factor) over a_uplift, and its name."""
    if "spectrum" in results:
        pulse = Pulse(
            omega_ratio=results["spectrum"]["omega_ratio"],
            amplitude_ratio=results["spectrum"]["amplitude_ratio"],
            amplitude=study.ground.amplitude,
            omega=study.ground.omega,
        )
    else:
        peak = float(study.ground.peak_acceleration)
        pulse = Pulse(
            omega_ratio=None,
            amplitude_ratio=peak / study.rocking_block.uplift_acceleration("nonlinear"),
            amplitude=peak,
            omega=None,
            record=study.ground.name,
        )
    return written(pulse)


def _fem_vs_multibody(fem_case_result: dict, multibody: dict) -> dict:
    """The numbers behind "how far is the FEM from the rigid multibody model": end (or
    overturning) times, collar utilisation and crack slip of each."""
    fem = fem_case_result["summary"]
    return {
        "t_end_fem": fem["t_end"],
        "t_end_multibody": multibody["overturn_time"] if multibody["overturned"] else None,
        # each run's peak is its peak until it stopped: their ratio compares two stops
        "collar_utilisation_ratio": unless_stopped(
            _peak_ratio(
                fem["collar_max_utilisation"], multibody.get("collar_max_utilisation") or 0.0
            ),
            fem_stop("the FEM", fem),
            _multibody_stop(multibody),
        ),
        "crack_slip_fem": fem_case_result.get("crack_slip_max"),
        "crack_slip_multibody": multibody["max_abs_crack_slip"],
    }


def _uncertainty(results: dict) -> dict | None:
    """Observed order, Richardson estimate and fine-mesh relative error of the FEM numbers from
    the runs on 4h, 2h and h (None when the coarse runs were not made)."""
    from ...fem.convergence import convergence_table

    keys = ["fem-mesh-4h", "fem-mesh-2h", "fem"]
    if not all(k in results for k in keys):
        return None
    quantities = {
        "peak_rotation": lambda s: max(s["max_abs_theta_left"], s["max_abs_theta_right"]),
        "collar_max_utilisation": lambda s: s["collar_max_utilisation"],
        "edge_stress_ratio": lambda s: s["edge_stress_ratio"],
    }
    table = {
        name: convergence_table([get(results[k]["summary"]) for k in keys], 2.0)
        for name, get in quantities.items()
    }
    table["edge_stress_ratio"]["method"] = "meshes 4h, 2h, h"
    # the rotations of runs that overturned are their stopping angles: no order to observe
    table["peak_rotation"] = unless_stopped(
        table["peak_rotation"],
        *(fem_stop(f"the FEM on mesh {k[4:] or 'h'}", results[k]["summary"]) for k in keys),
    )
    return table


def _toe_stress(study, results: dict) -> dict | None:
    """The toe stress from the local refinement over the impact of the median replica (None
    when not run): the quoted ratio to f_c, its mesh uncertainty (see colonna.fem.toe_stress)
    and its band: the replicas' unrefined toe stresses scaled by the refinement's factor on
    the median replica (refined / unrefined), widened by the mesh uncertainty. ``uncertainty``
    is the band's larger relative distance from the quoted value: mesh and replicas together."""
    refined = results["fem"].get("toe_refinement")
    if not refined:
        return None
    fc = study.stone.fc

    def finite(value):  # NaN (no monotone convergence) is null, in memory as in JSON
        return None if value is None or not math.isfinite(value) else value

    richardson = finite(refined["richardson"])
    ratio = refined["stress_estimate"] / fc
    fem = results["fem"]["summary"]
    replica = refined.get("replica", 0)
    summaries = results["fem"].get("replica_summaries", [fem])
    unrefined = [s["edge_stress_ratio"] for s in summaries]
    factor = ratio / unrefined[replica] if unrefined[replica] > 0 else 1.0
    mesh = refined["uncertainty"]
    low = min(unrefined) * factor * (1.0 - mesh)
    high = max(unrefined) * factor * (1.0 + mesh)
    return {
        "ratio": ratio,
        "stress": refined["stress_estimate"],
        "mesh_uncertainty": mesh,
        "replica_spread": (max(unrefined) - min(unrefined)) / unrefined[replica]
        if unrefined[replica] > 0
        else 0.0,
        "band_ratio": {"min": low, "max": high},
        "uncertainty": max(high / ratio - 1.0, 1.0 - low / ratio) if ratio > 0 else 0.0,
        "spread": refined["spread"],
        "bound_ratio": refined["stress_bound"] / fc,
        "ratios": [p / fc for p in refined["peaks"]],
        "unrefined_ratio": unrefined[replica],
        "replica": replica,
        **{
            key: refined[key]
            for key in (
                "toe",
                "t_start",
                "t_end",
                "t_peak",
                "refinements",
                "dofs",
                "steps",
                "handover_error",
                "edge_length",
                "edge_time",
            )
        },
        "observed_order": finite(refined["observed_order"]),
        # the mean base pressure at rest, (W + P) / A, for scale
        "static_mean_ratio": _static_mean_pressure(study, results) / fc,
        "richardson_ratio": None if richardson is None else richardson / fc,
    }


def _mesh_uncertainty(results: dict, quantity: str) -> float:
    """The fine mesh's relative error of a quantity where the three meshes converge, else 0."""
    table = _uncertainty(results)
    error = table[quantity]["fine_relative_error"] if table else None
    return error if error is not None and math.isfinite(error) else 0.0


def collars_yield(study, fem: dict, results: dict) -> dict:
    """Do the collars yield? The replicas' largest utilisation sigma / f_y against 1, widened
    by the mesh uncertainty (:func:`colonna.studies.outcome.limit_answer`)."""
    question = QUESTIONS["collars_yield"]
    if not study.collars:
        return not_assessed(question, "the column has no collars")
    return limit_answer(
        question,
        "largest collar stress / f_y",
        fem["bands"].get("collar_max_utilisation"),
        1.0,
        "-",
        _mesh_uncertainty(results, "collar_max_utilisation"),
        figure="collars",
    )


def toe_crushes(study, results: dict) -> dict:
    """Does the toe crush? The toe stress / f_c band (refined where it was, its band widened by
    the replicas' spread and the mesh refinement's uncertainty) against 1."""
    question = QUESTIONS["toe_crushes"]
    fem = results["fem"]["summary"]
    # the toe stress named (issue 35): which peak, and what it averages
    window = f"base contact pressure averaged over the first {1e3 * fem['edge_length']:.3g} mm"
    if fem.get("edge_time") is not None:
        window += f" and {1e3 * fem['edge_time']:.3g} ms"
    toe = _toe_stress(study, results)
    if toe is None:
        answer = limit_answer(
            question,
            f"toe stress ({window}) / f_c, study-mesh peak",
            fem["bands"]["edge_stress_ratio"],
            1.0,
            "-",
            _mesh_uncertainty(results, "edge_stress_ratio"),
            figure="toe_stress",
        )
    else:
        b = toe["band_ratio"]
        answer = limit_answer(
            question,
            f"toe stress ({window}) / f_c, refined toe-window peak",
            {"median": toe["ratio"], "min": b["min"], "max": b["max"], "missing": 0},
            1.0,
            "-",
            figure="toe_stress",
        )
    return toe_local(study, results, answer)


LOCAL_SPALLING = "local spalling of the corner possible"
NO_LOCAL_SPALLING = "no local spalling"


def toe_local(study, results: dict, answer: dict) -> dict:
    """The toe answer with what its first screen must say beside it (issue 48): ``averaged``,
    the averaged toe stress (Pa) its word compares with f_c, over ``edge_length`` (m) and
    ``edge_time`` (s); ``local``, the largest Winkler toe pressure of the runs (Pa, over the
    few millimetres of contact the mesh does not resolve; the toe section's number,
    :func:`winkler_run_max`) over f_c and its spalling verdict; and ``caveat`` where the
    answer rests on more than its word says: the local pressure past f_c, or an elastic bed
    whose toe pressure passes the yield pressure of its material (:func:`bed_yield`)."""
    fem = results["fem"]["summary"]
    if answer.get("median") is None or fem.get("toe_pressure_winkler") is None:
        return answer
    fc = study.stone.fc
    pressure = winkler_run_max(results)
    answer = dict(
        answer,
        averaged={
            "stress": answer["median"] * fc,
            "edge_length": fem["edge_length"],
            "edge_time": fem.get("edge_time"),
        },
        local={
            "measure": "Winkler toe pressure of the runs (the bed's elastic peak over the first "
            "millimetres of contact, which the mesh does not resolve)",
            "pressure": pressure,
            "ratio": pressure / fc,
            "spalling": LOCAL_SPALLING if pressure > fc else NO_LOCAL_SPALLING,
        },
    )
    caveats = []
    if pressure > fc:
        caveats.append(
            f"the local (Winkler) toe pressure reaches {pressure / fc:.3g} f_c: {LOCAL_SPALLING}"
        )
    yielding = bed_yield(study.bed)
    if yielding is not None and pressure > yielding["pressure"]:
        caveats.append(
            f"it rests on an elastic bed past its yield: the toe pressure "
            f"{pressure / 1e6:.3g} MPa is above the {yielding['name']} bed's yield pressure "
            f"{yielding['pressure'] / 1e6:.3g} MPa (range {yielding['low'] / 1e6:.3g} to "
            f"{yielding['high'] / 1e6:.3g} MPa: {yielding['source']}), which it cannot carry"
        )
        answer["bed_yield"] = yielding
    if caveats:
        answer["caveat"] = "; ".join(caveats)
    return answer


def bed_yield(bed) -> dict | None:
    """Where an elastic bed (no ``yield_pressure`` of its own) is a preset of
    :data:`colonna.fem.bed.BED_PRESETS` whose material yields (its ``yield_range`` and
    ``yield_source``: lead at a few MPa, mortar at its compressive strength): its name, its
    nominal yield ``pressure`` (the range's geometric mean, as a bed that yields takes it),
    the range (Pa) and the source; None for a bed that yields in the model, a given stiffness or
    a preset without a yield pressure."""
    from ...fem.bed import BED_PRESETS

    if getattr(bed, "yield_pressure", None) is not None:
        return None
    for name, preset in BED_PRESETS.items():
        limits = getattr(preset, "yield_range", None)
        if limits and bed.source.startswith(preset.source):
            return {
                "name": name,
                # the nominal value, the geometric mean of the range (as a bed that yields uses)
                "pressure": math.sqrt(limits[0] * limits[1]),
                "low": float(limits[0]),
                "high": float(limits[1]),
                "source": getattr(preset, "yield_source", ""),
            }
    return None


def winkler_run_max(results: dict) -> float:
    """The largest Winkler toe pressure (Pa) the runs themselves gave (their base force and
    tilt): the FEM ensemble's, and where the bed has a range, replica 0's on the nominal bed
    and the range's ends' (the toe section's ``winkler_run_ratio_max`` times f_c)."""
    fem = results["fem"]
    values = [fem["summary"]["toe_pressure_winkler"]]
    if "fem-bed-low" in results and "fem-bed-high" in results:
        values += [
            fem.get("replica_summaries", [fem["summary"]])[0]["toe_pressure_winkler"],
            results["fem-bed-low"]["summary"]["toe_pressure_winkler"],
            results["fem-bed-high"]["summary"]["toe_pressure_winkler"],
        ]
    return float(max(values))


def crosscheck_outcome(study, results: dict, criteria: dict) -> dict:
    """summary["outcome"] of the cross-check: each model's outcome and the four answers."""
    fem = results["fem"]["summary"]
    rigid, monolith, mb = results["rigid"], results["monolith"], results["multibody"]
    alpha = study.rocking_alpha
    block = rocking_block(study.cracked, bool(study.collars))
    models = [
        fem_model("FEM, deformable halves", fem, alpha, block),
        model_outcome(
            "rigid multibody (the rigid reference)",
            mb["overturned"],
            max(mb["max_abs_theta_left"], mb["max_abs_theta_right"]),
            alpha,
            mb.get("overturn_time"),
            collars=CollarOutcome(
                mb.get("collar_max_utilisation") if study.collars else None,
                fractured=bool(mb.get("collar_fractured")),
                elastic=None
                if any(c.plastic for c in study.collars)
                else "the multibody model's collars are elastic frames",
            ),
            block=block,
        ),
        model_outcome(
            SDOF_HALF,
            rigid["overturned"],
            rigid["max_abs_theta"],
            rigid["alpha"],
            rigid.get("overturn_time"),
            collars=CollarOutcome(
                rigid.get("collar_max_utilisation"),
                # the SDOF's collar springs never yield (rigid.solve: collar_law "elastic")
                elastic="the SDOF's collars are elastic"
                if rigid.get("collar_law", "elastic") == "elastic"
                else None,
            ),
            block="half" if study.cracked else "column",
        ),
        model_outcome(
            "SDOF whole column, no crack",
            monolith["overturned"],
            monolith["max_abs_theta"],
            monolith["alpha"],
            monolith.get("overturn_time"),
        ),
    ]
    rigid_answer = criteria_answer(
        QUESTIONS["rigid_assumption_ok"],
        criteria["all_ok"],
        {
            "same outcome": criteria["same_outcome"],
            "peak rotation": criteria["peak_ok"],
            "impacts before the pulse ends": criteria["impacts_ok"],
            "rotation history to the first impact": criteria["history_ok"],
        },
        figure="theta",
    )
    return outcome(
        models,
        {
            "rigid_assumption_ok": rigid_answer,
            "collars_yield": collars_yield(study, fem, results),
            "collars_hold": collars_hold(fem, study.collars, figure="collar_hinge"),
            "toe_crushes": toe_crushes(study, results),
            # a partial crack ([column] crack): does it grow? (the FEM's cohesive mid-plane)
            **({"crack_grows": crack_grows(fem)} if study.crack is not None else {}),
        },
    )


def _bed(study, results: dict) -> dict:
    """The bed under the column (SI): its stiffness per unit area, range and source; the toe
    grading rule's contact length, element size and Winkler toe pressure at alpha / 2 over the
    bed's range (:func:`studies.fem_study.toe_resolution`); the toe element size of the study
    mesh and of the finest toe window, and how many of each lie across that contact length;
    where the bed has a range, ``range_runs``: the unperturbed FEM run (study mesh) on the
    softest, the nominal and the stiffest bed, each one's toe stress, Winkler toe pressure,
    peak rotation and whether it overturned."""
    import numpy as np

    from ..fem_study import toe_resolution
    from ..models import toe_mesh

    rule = toe_resolution(study)

    def toe_size(refinement: int) -> float:
        mesh = toe_mesh(study, refinement)
        xs = np.unique(mesh.points[0])
        return float(min(xs[1] - xs[0], xs[-1] - xs[-2]))

    runs = {}
    if "fem-bed-low" in results and "fem-bed-high" in results:
        nominal = results["fem"].get("replica_summaries", [results["fem"]["summary"]])[0]
        for end, summary in (
            ("low", results["fem-bed-low"]["summary"]),
            ("nominal", nominal),
            ("high", results["fem-bed-high"]["summary"]),
        ):
            runs[end] = {
                "stiffness": {"low": study.bed.low, "nominal": study.bed.stiffness}.get(
                    end, study.bed.high
                ),
                "edge_stress_max": summary["edge_stress_max"],
                "edge_stress_ratio": summary["edge_stress_max"] / study.stone.fc,
                "toe_pressure_winkler": summary["toe_pressure_winkler"],
                "peak_rotation": unless_stopped(
                    max(summary["max_abs_theta_left"], summary["max_abs_theta_right"]),
                    fem_stop("this run", summary),
                ),
                "overturned": bool(summary["overturned"]),
            }
    finest = max(study.toe_refinements, default=1)
    sizes = {"study_mesh_toe_size": toe_size(1), "finest_toe_size": toe_size(finest)}
    return {
        "stiffness": study.bed.stiffness,
        "low": study.bed.low,
        "high": study.bed.high,
        "source": study.bed.source,
        **rule,
        **sizes,
        "finest_refinement": finest,
        "across_study_mesh": rule["contact_length"] / sizes["study_mesh_toe_size"],
        "across_finest": rule["contact_length"] / sizes["finest_toe_size"],
        "pressure_ratio": rule["pressure"] / study.stone.fc,
        "pressure_low_ratio": rule["pressure_low"] / study.stone.fc,
        "pressure_high_ratio": rule["pressure_high"] / study.stone.fc,
        "range_runs": runs or None,
        # the largest Winkler toe pressure the runs themselves gave (their base force and tilt),
        # nominal bed and the range's ends, over f_c
        "winkler_run_ratio_max": winkler_run_max(results) / study.stone.fc,
    }


def _static_mean_pressure(study, results: dict) -> float:
    """(W + P) / A (Pa): the FEM's static base reaction over the base area."""
    fem = results["fem"]["summary"]
    return (fem.get("base_reaction_static") or 0.0) / (study.width * study.thickness)

"""The gateway to the models: every run of a study's column goes through here.

A study's column (:class:`studies.fem_study.FemStudy`, :attr:`studies.study.Study.fem`) is
built into a FEM model here (:func:`build`, on :func:`toe_mesh`) and run through one function
per model, whatever the kind: the SDOF rocking block (:func:`run_sdof`), the rigid multibody
model (:func:`run_multibody`), the FEM (:func:`run_fem`, or :func:`iter_fem` for a batch of
motions on one model). The fragility's fast paths are functions of this module too: the SDOF
kernel without a history (:func:`sdof_outcome`) and the multibody model without histories
(:func:`run_multibody_outcome`); so are the spectra of a study's column
(:func:`sdof_spectrum`, :func:`multibody_spectrum`), the cross-check's toe windows
(:func:`refine_toe_window`) and the numba kernels a study compiles
(:func:`kernels`, for the command line's compile notice). No other module of studies/ imports
a solver's run function or a private kernel module (tests/test_layering.py). A variant is a
changed study (``dataclasses.replace``), never another argument set.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import TYPE_CHECKING, NamedTuple

from ..core.errors import InputError
from ..core.motion import Motion, Release
from .fem_study import FemStudy

if TYPE_CHECKING:
    from ..fem.settings import FemSettings


def toe_mesh(study: FemStudy, refinement: int):
    """The study's generated mesh (graded to ``toe_size`` at the base corners over edge_length
    where the study sets it) with its toe zones (edge_length from each base corner) refined
    ``refinement`` times. The bed's stiffness per unit area is held: the refinement
    refines the mesh only. (A mesh graded to the rule of
    :func:`studies.fem_study.toe_resolution` costs a step
    of about 1e-7 s on the default column: too many steps for a window; the static pivot of
    tests/test_bed.py resolves the zone.)"""
    from ..meshes.column import ToeGrading, column_mesh

    return column_mesh(
        study.width,
        study.height,
        study.mesh_size,
        cracked=study.cracked,
        grading=study.grading,
        pinned_heights=[c.y for c in study.collars],
        toe=ToeGrading(refinement, study.edge_length, study.toe_size),
    )


def model_record(study: FemStudy) -> dict:
    """The FEM model of a study's own mesh as its runs build it (:func:`build`), for the
    inputs on record: nodes, elements and degrees of freedom; the stable time step
    (:func:`colonna.fem.model.stable_time_step`: safety x 2 / omega_max x the contact damping's
    reduction) and the step used (run.dt where given, else the stable one); the row spacing
    of the histories (a whole number of steps nearest the output interval: duration / 400
    by default); the base contact's stiffness per node (N/m: the bed's k x t x tributary
    length, [base]) and the bed's k (N/m^3), its range and source. Variants of the study
    (a finer mesh, a toe refinement) build their own."""
    import numpy as np

    from ..fem.model import stable_time_step

    model = build(study)
    step = stable_time_step(model, study.safety)
    dt = study.dt if study.dt is not None else step.dt
    record = {
        "nodes": int(model.mesh.n_nodes),
        "elements": int(model.mesh.cells.shape[1]),
        "dofs": int(model.n_dofs),
        "dt_stable": step.dt,
        "dt_critical": step.critical,
        "dt_critical_stone": step.critical_elastic,
        "dt": dt,
        "penalty_base_mean": float(np.mean(model.base_kn)),
        "penalty_base_min": float(np.min(model.base_kn)),
        "penalty_base_max": float(np.max(model.base_kn)),
        "bed_stiffness": study.bed.stiffness,
        "bed_stiffness_low": study.bed.low,
        "bed_stiffness_high": study.bed.high,
        "bed_source": study.bed.source,
    }
    if model.cohesive is not None:  # a partial crack: its extent given, and as the pairs run it
        record.update(crack_extent(model.cohesive))
    interval = study.output_interval or (study.duration / 400.0 if study.duration else None)
    if interval is not None:
        per_output = max(1, int(round(interval / dt)))
        record.update(steps_per_output=per_output, output_interval_used=per_output * dt)
    return record


def crack_extent(interface) -> dict:
    """A partial crack's extent given ([column] crack: to - from, m) and run: the tributary
    lengths of the mesh's node pairs on it (fem.partial_crack.cracked_pairs: the pair at an
    inner end is the intact tip, so a crack ends half an element short of a height between
    nodes), and its depth."""
    import numpy as np

    low, high = interface.crack
    on = (interface.damage0 >= 1.0) | (
        interface.ligament if interface.ligament is not None else False
    )
    return {
        "crack_length_given": float(high - low),
        "crack_length_run": float(np.sum(interface.tributary[on])),
        "crack_depth": float(interface.depth),
    }


def build(study: FemStudy):
    """Mesh and model of the study."""
    from ..fem.model import Loads, build_model
    from ..fem.partial_crack import Crack

    if study.mesh_file is not None:
        from ..meshes.io import read

        mesh = read(study.mesh_file)
        for name, value, expected in (
            ("width", mesh.width, study.width),
            ("height", mesh.height, study.height),
        ):
            if abs(value - expected) > 1e-6 * expected:
                raise InputError(
                    f"mesh.file {study.mesh_file.name}: its {name} {value:g} m "
                    f"differs from column.{name} = {expected:g} m"
                )
        if mesh.cracked != study.cracked:
            raise InputError(
                f"mesh.file {study.mesh_file.name} has {mesh.n_bodies} bodies but "
                f"column.cracked = {str(study.cracked).lower()}"
            )
    else:
        mesh = toe_mesh(study, 1)
    return build_model(
        mesh,
        study.stone,
        study.thickness,
        study.collars,
        study.contact,
        loads=Loads(top_load=study.top_load),
        bed=study.bed,
        crack=Crack(study.crack, study.crack_depth),
    )


def run_fem(
    study: FemStudy,
    *,
    replicas: int | None = None,
    out_dir=None,
    progress: bool = False,
    checkpoint=None,
):
    """The FEM run of a study as an ensemble of ``replicas`` (default ``study.replicas``) runs
    perturbed at round-off level (:func:`colonna.fem.solver.run_ensemble`); replica 0 is the
    unperturbed run and writes the files of a run into ``out_dir``.

    Every FEM run of every study kind goes through here (the single study, the cross-check,
    free rocking, the sweeps; the spectrum's grid points through :func:`iter_fem`, batched on
    one model): a variant is a changed study
    (``dataclasses.replace``), never another argument set. The refinement of the toe stress
    restarts these runs on finer meshes (:func:`colonna.fem.toe_stress.toe_stress_refinement`).
    ``checkpoint`` (:class:`colonna.fem.checkpoint.Checkpoint`): where the ensemble saves its
    state as it goes, and goes on from when run again (a study's FEM case:
    :func:`case_checkpoint`)."""
    from ..fem.solver import run_ensemble

    return run_ensemble(
        build(study),
        _motion(study),
        _run_settings(study, progress=progress),
        _release(study),
        replicas=study.replicas if replicas is None else replicas,
        out_dir=out_dir,
        checkpoint=checkpoint,
    )


def case_checkpoint(case: dict, directory):
    """The checkpoint of a study's FEM case in its folder (``directory``/checkpoint), keyed by
    the hash of the case's inputs (:func:`studies.executor.case_inputs`: the case, the bytes of
    the files it reads, the colonna version): a case computed again from other inputs never
    goes on from it."""
    from ..fem.checkpoint import Checkpoint
    from .executor import case_inputs, inputs_hash

    return Checkpoint(Path(directory) / "checkpoint", inputs_hash(case_inputs(case)))


def run_multibody(study: FemStudy, dt: float | None = None, touching_dt: float | None = None):
    """The rigid multibody model of a study (:func:`colonna.rigid.multibody.rock_multibody`; its
    default step where ``dt`` is None; ``touching_dt`` as rock_multibody's). Every study kind's
    multibody run goes through here (the cross-check, the design study, the spectrum's grid
    points, free rocking): a variant is a changed study (``dataclasses.replace``), as for
    :func:`run_fem`."""
    from ..core.motion import Motion, Release
    from ..rigid.multibody import MultibodyContact, MultibodySettings, rock_multibody

    return rock_multibody(
        study.rocking_block,
        Motion(study.ground, duration=study.duration, vertical=study.vertical),
        study.collars,
        contact=MultibodyContact(cracked=study.cracked, friction=study.contact.friction),
        release=Release(tilt=study.initial_tilt, angular_velocity=study.initial_angular_velocity),
        settings=MultibodySettings(dt=dt, touching_dt=touching_dt),
    )


def run_sdof(study: FemStudy, *, whole_column: bool = False):
    """The SDOF rocking block of a study, nonlinear (:func:`colonna.rigid.solve.rock`): the
    half (or the whole, if not cracked) with the study's collars, the paper's model; with
    ``whole_column`` the uncracked column without collars (the monolith). Every study kind's
    SDOF run goes through here, as for :func:`run_fem`."""
    from ..core.motion import Motion, Release
    from ..rigid.solve import rock

    if whole_column:
        block, collars = study.column_block, ()
    else:
        block, collars = study.rocking_block, study.collars
    return rock(
        block,
        Motion(study.ground, duration=study.duration, vertical=study.vertical),
        collars,
        model="nonlinear",
        release=Release(tilt=study.initial_tilt, angular_velocity=study.initial_angular_velocity),
    )


def _run_settings(study: FemStudy, **changes) -> FemSettings:
    """The FEM solver's settings of a study (those of :data:`SHARED_BY_A_BATCH` that are not
    the model's nor its release), with ``changes`` (more of FemSettings' fields): one place
    for run_fem and iter_fem."""
    from ..fem.settings import FemSettings

    settings = {
        "dt": study.dt,
        "safety": study.safety,
        "output_interval": study.output_interval,
        "edge_length": study.edge_length,
        "edge_time": study.edge_time,
        "stop_when_settled": study.stop_when_settled,
        "progress": False,
    }
    return FemSettings(**(settings | changes))


def _motion(study: FemStudy, ground=None, duration: float | None = None) -> Motion:
    """The study's motion (its ``ground``, ``duration`` where given), for the solvers."""
    return Motion(
        study.ground if ground is None else ground,
        study.duration if duration is None else duration,
        study.vertical,
    )


def _release(study: FemStudy) -> Release:
    """How the study's runs start: upright at rest, or released tilted and spinning."""
    return Release(study.initial_tilt, study.initial_angular_velocity)


# the keys of a FemStudy that make its model and time step (build, stable_time_step)
MODEL_KEYS = (
    "height",
    "width",
    "thickness",
    "cracked",
    "stone",
    "collars",
    "contact",
    "bed",
    "mesh_size",
    "toe_size",
    "grading",
    "mesh_file",
    "top_load",
    "safety",
    "dt",
)


# what the runs of iter_fem may not differ in: the model and the run settings (they share one
# model and one stable step); the ground motions and durations may differ
SHARED_BY_A_BATCH = MODEL_KEYS + (
    "edge_length",
    "output_interval",
    "initial_tilt",
    "initial_angular_velocity",
    "edge_time",
    "stop_when_settled",
)


def iter_fem(studies: list[FemStudy], *, slots: int | None = None, **options):
    """One FEM run of each study (no replicas). The studies that differ only in their ground
    motion and duration (the pulses of a grid: :data:`SHARED_BY_A_BATCH` equal) share a model
    and advance together on the batched kernel (:func:`colonna.fem.solver.iter_batch`,
    ``slots`` runs at a time, default :data:`colonna.fem.solver.BATCH_SLOTS`). Yields (index in
    studies, FemResult) as each run ends; each is the same bits as ``run_fem(study,
    replicas=1)``, a run whose energy balance fails rerun at half the step up to
    :data:`colonna.fem.solver.STEP_HALVINGS` times as there (the failed runs of a batch
    together). ``options``: more of :class:`colonna.fem.settings.FemSettings`' fields (its
    ``stop_in_weak_tail``)."""
    from ..fem.solver import (
        BATCH_SLOTS,
        STEP_HALVINGS,
        _with_halvings,
        iter_batch,
        unreliable_reason,
    )

    notes: dict[int, str] = {}  # why a run was rerun at a halved step (unreliable_reason)
    groups: list[list[int]] = []
    for index, study in enumerate(studies):
        for members in groups:
            first = studies[members[0]]
            if all(getattr(study, k) == getattr(first, k) for k in SHARED_BY_A_BATCH):
                members.append(index)
                break
        else:
            groups.append([index])
    for members in groups:
        # the longest runs first: they advance together, and the short ones take the slots that
        # runs ending early leave, so the batch does not end on a few long runs alone
        members.sort(key=lambda i: -studies[i].duration)
        first = studies[members[0]]
        model = build(first)
        settings = _run_settings(first, **options)
        halvings = 0
        while members:
            runs = iter_batch(
                model,
                [_motion(studies[i]) for i in members],
                settings,
                _release(first),
                slots=BATCH_SLOTS if slots is None else slots,
            )
            failed: list[tuple[int, float]] = []  # (index in studies, its step)
            for k, result in runs:
                reason = unreliable_reason([result.summary])
                if halvings:
                    result = _with_halvings(result, halvings, notes[members[k]])
                if reason is None or halvings == STEP_HALVINGS:
                    yield members[k], result
                else:  # as run_ensemble: rerun at half the step (those that failed, together)
                    notes[members[k]] = reason
                    failed.append((members[k], result.summary["dt"]))
            members = [i for i, _ in failed]
            if failed:
                halvings += 1
                settings = dataclasses.replace(settings, dt=0.5 * failed[0][1])


def refine_toe_window(study: FemStudy, start: dict, refinement: int):
    """One window of the toe stress's refinement: the study's FEM model moved onto its mesh
    with the toe zones refined ``refinement`` times (:func:`toe_mesh`), restarted from
    ``start`` (the state a FEM run saved before its impact) over the impact window under the
    study's motions (:func:`colonna.fem.toe_stress.refine_window`)."""
    from ..fem.toe_stress import refine_window

    return refine_window(
        build(study),
        start,
        toe_mesh(study, refinement),
        study.ground,
        vertical=study.vertical,
    )


# --- the fragility's fast paths, the spectra and the kernels ----------------------------------


class SdofOutcome(NamedTuple):
    """What :func:`sdof_outcome` keeps of an SDOF run: whether it overturned, its impacts,
    its largest |theta| (rad) and when it overturned (s)."""

    overturned: bool
    impacts: int
    max_abs_theta: float
    overturned_at: float | None = None  # s (None: it stood)


def sdof_outcome(
    study: FemStudy, ground, duration: float, *, rtol: float, atol: float
) -> SdofOutcome:
    """The SDOF rocking block of a study under ``ground`` from rest, nonlinear, as
    :func:`run_sdof` models it (the half, or the whole column if not cracked, with the study's
    collar springs: :func:`colonna.rigid.solve.kernel_params`), through the kernel alone
    without a history (:func:`colonna.rigid._kernels.rk_run`; with collars it ends once, after
    the motion, it can no longer overturn): the fragility's fast path. ``rtol``, ``atol``: the
    integrator's tolerances."""
    import numpy as np

    from ..rigid import _kernels as K
    from ..rigid.solve import kernel_params

    collars = study.collars
    P, rec_t, rec_a = kernel_params(study.rocking_block, ground, collars, "nonlinear")
    out, impacts = np.zeros((1, 3)), np.zeros((1, 3))
    status, n_imp, max_theta, _, _, t_over = K.rk_run(
        P, rec_t, rec_a, duration, rtol, atol, bool(collars), 0.0, out, impacts
    )
    over = status == K.OVERTURNED
    return SdofOutcome(over, int(n_imp), float(max_theta), float(t_over) if over else None)


def run_multibody_outcome(
    study: FemStudy,
    ground,
    duration: float,
    *,
    stop_when_decided: bool = True,
    dt: float | None = None,
    touching_dt: float | None = None,
):
    """:func:`colonna.rigid.multibody.multibody_outcome` of the study's column under ``ground``
    from rest (the settings of :func:`run_multibody`, without histories: the fragility's fast
    path); ``stop_when_decided``: as multibody_outcome's (False runs the free tail to its end);
    ``dt`` and ``touching_dt``: its step and the crack's tolerance (s; None: the single run's).
    The run does not keep its impact count (impacts_needed False: its stop need not wait for
    the last impact; impacts None)."""
    from ..core.motion import Motion
    from ..rigid.multibody import MultibodyContact, MultibodySettings, multibody_outcome

    return multibody_outcome(
        study.rocking_block,
        Motion(ground, duration=duration),
        study.collars,
        stop_when_decided=stop_when_decided,
        impacts_needed=False,
        contact=MultibodyContact(cracked=study.cracked, friction=study.contact.friction),
        settings=MultibodySettings(dt=dt, touching_dt=touching_dt),
    )


def sdof_spectrum(study: FemStudy, omega_ratios, amplitude_ratios):
    """The overturning spectrum of the study's SDOF block with its collar springs, nonlinear,
    under its pulse's shape (:func:`colonna.rigid.spectrum.overturning_spectrum`; the ratios
    to p and to the uplift acceleration of :attr:`FemStudy.rocking_block`)."""
    from ..rigid.spectrum import overturning_spectrum

    return overturning_spectrum(
        study.rocking_block,
        omega_ratios,
        amplitude_ratios,
        study.collars,
        model="nonlinear",
        pulse=study.ground.kind,
    )


def multibody_spectrum(study: FemStudy, omega_ratios, amplitude_ratios):
    """The overturning spectrum of the study's rigid multibody column under its pulse's shape
    (:func:`colonna.rigid.multibody.multibody_spectrum`, the ratios as :func:`sdof_spectrum`'s)."""
    from ..rigid.multibody import MultibodyContact
    from ..rigid.multibody import multibody_spectrum as spectrum

    return spectrum(
        study.rocking_block,
        omega_ratios,
        amplitude_ratios,
        study.collars,
        contact=MultibodyContact(cracked=study.cracked, friction=study.contact.friction),
        pulse=study.ground.kind,
    )


def kernels(*models: str) -> list:
    """The numba kernels that runs of ``models`` compile on their first run (for the compile
    notice, :func:`studies.cli.kernels_cached`): "fem" the FEM's time step, "multibody" the
    multibody model's run, "multibody spectrum" its spectrum's."""
    found = []
    for model in models:
        if model == "fem":
            from ..fem import _kernels as fem_kernels

            found.append(fem_kernels.advance)
        elif model == "multibody":
            from ..rigid import _multibody

            found.append(_multibody.simulate)
        elif model == "multibody spectrum":
            from ..rigid import _multibody

            found.append(_multibody.spectrum_modes)
        else:
            raise ValueError(f"no kernels of a model {model!r}")
    return found

"""Explicit dynamics of the column under gravity and a ground pulse, and the recovered results.

The run starts from static equilibrium under gravity (a linear solve with the contact springs
closed), then steps with central differences. The compiled kernel advances one output interval
at a time; between intervals Python recovers the outputs, appends them to ``history.csv`` (so an
interrupted run keeps every row already computed) and checks for overturning or blow-up.

Outputs per output time (``history``):
  t; theta_left, theta_right (rad, rigid rotation of each half from a mass-weighted least-squares
  fit, positive tipping toward +x as in rigid/); uplift_left, uplift_right (m, height of the outer
  toes); edge_stress_left, edge_stress_right (Pa, compression positive: base contact pressure
  averaged over ``edge_length`` from the outer toes and over the last ``edge_time`` seconds,
  its peak over every time step of the output interval ending at t, so that a short impact is
  not missed; edge_stress_inner_* at the crack toes);
  base and crack contact forces; crack slip and opening; collar_k_axial_force, _moment, _stress,
  _utilisation; energies (kinetic, strain, gravity, contact, collar, dissipated, external_work;
  of the dissipated: friction_base, friction_crack, contact_damping, tallied every step);
  toe_force_<toe> (N, the toe's resultant over its window, sampled at t) and
  toe_contact_nodes_<toe>, toe_contact_length_<toe> (m: the base nodes in contact from that toe
  inward, up to the first open one, and their tributary lengths)
  (base_pressure.csv: the contact pressure at every base node, one row per output time)
  and energy_error = (energy now + dissipated - external work - energy at start) / scale, scale =
  the largest of the kinetic energy and |external work| seen so far, and at least the rocking
  energy scale m g R (1 - cos alpha) of the halves (the work that tips them onto a toe).
"""

from __future__ import annotations

import dataclasses
import math
import sys
import time
from collections import deque
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from scipy.sparse.linalg import spsolve
from tqdm import tqdm

from ..core.collar import collar_strain_summary
from ..core.collar_law import FIBRE_STRAIN, FRACTURED, OUT_SIZE
from ..core.errors import InputError, require_positive
from ..core.fibre import STRESS as FIBRE_STRESS
from ..core.ground import require_motion
from ..core.motion import Motion, Release
from ..core.quantities import quantity, shared, to_dict, typed_result
from . import _kernels as K
from .checkpoint import Checkpoint, clear, read_parts, write_part
from .model import Model, coincident_nodes, collar_stiffness, contact_stiffness, stable_time_step
from .output import HistoryFiles, write_run, write_summary
from .partial_crack import crack_columns, crack_summary
from .settings import (
    AT_REST,
    DEFAULT_SETTINGS,
    EDGE_TIME,
    REPLICA_PERTURBATION,
    REPLICAS,
    FemSettings,
    FemStart,
    Replicas,
)

BLOW_UP = "numerical blow-up"  # how the status of a run stopped as unstable begins

# energy balance error (relative to the energy scale, see the module) past which a run is
# unreliable; a correct run closes to about 1e-2 (tests), undamped frictionless penalty
# contact gains tens of per cent
ENERGY_ERROR_LIMIT = 0.05
# runs that advance together when a batch of many runs is streamed through iter_batch: one
# group of the kernel (its cost per state is lowest at a full group)
BATCH_SLOTS = K.GROUP
# the weak-tail stop (FemSettings.stop_in_weak_tail): a seated column under a ground that stays
# below a body's uplift acceleration g tan(alpha_b) over WEAK_TAIL_MARGIN for the rest of the
# motion cannot start rocking again. Half of the least rigid threshold of any part (a free half
# lifts at g tan(alpha_b), the halves locked together at about twice that); measured on the
# fragility's column (spectrum mesh, synthetic 20 s records, docs/fragility.md, Speed): it
# first rocked (|theta| past SEATED_TILT alpha_b) once the ground had reached 1.6-6.7
# g tan(alpha_b) (in 5 runs), and took 0.8-3.1 without rocking; below that it sways on its
# bed, about 0.03 alpha_b per g tan(alpha_b) of ground at most
WEAK_TAIL_MARGIN = 2.0
# seated: every body's rigid |theta| below SEATED_TILT alpha_b at every output over one period
# of free rocking at that amplitude (so that a body rocking at it would show it): three times
# the bed's sway under the weak ground
SEATED_TILT = 0.05
# the exact crack contact's Gauss-Seidel tolerance, m per m of the column's size: no multiplier
# moves a gap by more than it at the last sweep (fem._kernels.crack_lagrange)
LAGRANGE_TOLERANCE = 1e-9


@dataclass
class FemResult:
    history: dict = field(repr=False)
    summary: dict  # to_dict(typed_summary)
    displacement_frames: list = field(repr=False)  # (t, u (n_nodes, 2)) at output times
    model: Model = field(repr=False)
    velocity_frames: list = field(default_factory=list, repr=False)  # (t, v (n_nodes, 2))
    # (t, contact state: dict of base_ft, base_fc, crack_ft, crack_fc; see FemStart.contact)
    contact_frames: list = field(default_factory=list, repr=False)
    # the summary with the unit of every value
    typed_summary: FemRunSummary | None = field(default=None, repr=False)


@typed_result
@dataclass(frozen=True, kw_only=True)
class FemRunSummary:
    """What a FEM run answers, SI units (the history's quantities: see the module); the
    collars' strain keys only with collars. ``FemResult.summary`` is its dict, in this order
    (the keys the models share: colonna.core.quantities.SHARED)."""

    overturned: bool = shared("overturned")
    status: str = shared("status")
    max_abs_theta_left: float = shared("max_abs_theta_left")
    max_abs_theta_right: float = shared("max_abs_theta_right")
    # a partial crack's answers ([column] crack; fem.partial_crack.crack_summary), only with one
    crack_length_initial: float | None = quantity(
        "m", "the crack's length at the start (partial crack)", omit_when_none=True, default=None
    )
    crack_length_final: float | None = quantity(
        "m", "the crack's length at the end (partial crack)", omit_when_none=True, default=None
    )
    crack_growth: float | None = quantity(
        "m", "how much the crack grew (partial crack)", omit_when_none=True, default=None
    )
    crack_grew: bool | None = quantity(
        "", "whether the crack grew by a pair or more", omit_when_none=True, default=None
    )
    crack_tip_KI_max: float | None = quantity(
        "Pa m^0.5",
        "largest mode-I stress intensity at a crack tip (displacement correlation)",
        omit_when_none=True,
        default=None,
    )
    crack_tip_KI_time: float | None = quantity(
        "s", "time of the largest K_I at a tip", omit_when_none=True, default=None
    )
    crack_tip_KI_ratio: float | None = quantity(
        "-", "largest K_I at a tip over the stone's K_IC", omit_when_none=True, default=None
    )
    cohesive_dissipated: float | None = quantity(
        "J", "energy the intact mid-plane dissipated cracking", omit_when_none=True, default=None
    )
    # a crack of part depth ([column] crack_depth < 1; fem.partial_crack): its ligament
    crack_depth: float | None = quantity(
        "-",
        "fraction of the thickness the crack runs through (part-depth crack)",
        omit_when_none=True,
        default=None,
    )
    crack_ligament_length: float | None = quantity(
        "m",
        "extent of the part-depth crack's ligament on the mesh's pairs",
        omit_when_none=True,
        default=None,
    )
    crack_ligament_damage_max: float | None = quantity(
        "-",
        "largest damage of the part-depth crack's ligament (1: broken through there)",
        omit_when_none=True,
        default=None,
    )
    collar_max_utilisation: float = shared("collar_max_utilisation")
    collar_first_yield_time: float | None = shared("collar_first_yield_time")
    edge_stress_max: float = quantity("Pa", "largest toe stress (compression positive)")
    edge_stress_ratio: float = quantity("-", "largest toe stress over the stone's f_c")
    edge_length: float = quantity("m", "length from the outer toe the toe stress averages over")
    edge_time: float = quantity("s", "time the toe stress averages over")
    # the base's total normal force at t = 0: the static reaction, weight + top load, when the
    # run starts from the static state (None for a release or a restart)
    base_reaction_static: float | None = quantity(
        "N", "the base's normal force at t = 0 from the static state (None: no static start)"
    )
    # plastic collars: the largest |plastic strain| reached, and the work done yielding
    collar_max_plastic_strain: float = shared("collar_max_plastic_strain")
    collar_plastic_work: float = shared("collar_plastic_work")
    # the largest fibre strain is the state's running maximum over every step; a fracture time
    # is the first output at which the break is recorded
    collar_max_fibre_strain: float | None = shared(
        "collar_max_fibre_strain", omit_when_none=True, default=None
    )
    collar_ductility_demand: float | None = shared(
        "collar_ductility_demand", omit_when_none=True, default=None
    )
    collar_fractured: bool | None = shared("collar_fractured", omit_when_none=True, default=None)
    collar_fracture_time: float | None = shared(
        "collar_fracture_time", present_with="collar_fractured", default=None
    )
    crack_slip_residual: float = quantity("m", "crack slip at the end of the run")
    # contact diagnostics (issue 38): whether an interface chatters or is resolved. The crack's
    # normal force is sampled at the output times (a chattering force jumps between 0 and
    # several kN); None for a solid column
    crack_normal_force_mean: float | None = quantity(
        "N", "crack's normal force, mean over the output samples", omit_when_none=True, default=None
    )
    crack_normal_force_mean_closed: float | None = quantity(
        "N",
        "crack's normal force, mean over the samples with the halves in contact (0: never)",
        present_with="crack_normal_force_mean",
        default=None,
    )
    crack_normal_force_max: float | None = quantity(
        "N",
        "crack's largest sampled normal force",
        present_with="crack_normal_force_mean",
        default=None,
    )
    crack_closed_fraction: float | None = quantity(
        "-",
        "fraction of the output samples with the halves in contact",
        present_with="crack_normal_force_mean",
        default=None,
    )
    # work tallied every step: of the dissipated energy, friction at the base and along the
    # crack and the contact damping (with the clipped tensile part; with exact crack contact
    # the work of its normal multipliers, the impacts' loss, too); the penalty springs'
    # stored (elastic) energy at its largest
    friction_work_base: float = quantity(
        "J", "work dissipated by friction at the base", default=0.0
    )
    friction_work_crack: float = quantity(
        "J", "work dissipated by friction along the crack", default=0.0
    )
    contact_damping_work: float = quantity(
        "J",
        "work dissipated by the contact damping (base, penalty crack) and the exact crack's "
        "impacts",
        default=0.0,
    )
    contact_penalty_energy_max: float = quantity(
        "J", "largest elastic energy stored in the contact penalty springs", default=0.0
    )
    # the toe's contact at the output sample with the largest toe resultant (over the toe
    # window; samples at the output times, as the contact is, not the peak over every step
    # that edge_stress_max is): the extent of the base nodes in contact from that toe inward
    # (the sum of their tributary lengths), and how many. One node: the zone is unresolved
    toe_contact_length: float = quantity(
        "m", "contact length at the toe, at the sample of the largest toe force", default=0.0
    )
    toe_contact_nodes: int = quantity(
        "", "base nodes in contact from the toe, at the sample of the largest toe force", default=0
    )
    toe_node_spacing: float = quantity("m", "base node spacing at the toe", default=0.0)
    # the resolved toe answers (issue 38), sampled at the output times: the largest nodal
    # pressure of any toe's body (the peak of the contact pressure where the zone is
    # resolved), and at the sample of the largest toe force the base's resultant force of that
    # toe's body and its distance from the toe
    toe_pressure_max: float = quantity(
        "Pa", "largest sampled nodal base pressure (the resolved peak pressure)", default=0.0
    )
    toe_resultant: float = quantity(
        "N",
        "base normal force of the toe's body, at the sample of the largest toe force",
        default=0.0,
    )
    toe_resultant_offset: float = quantity(
        "m", "distance of that force's point of application from the toe", default=0.0
    )
    # the pivot on the bed in closed form (colonna.fem.bed.winkler_toe_pressure): each body's
    # base force and tilt at the output samples give its toe pressure on a rigid base
    toe_pressure_winkler: float = quantity(
        "Pa", "largest Winkler toe pressure of a body's sampled base force and tilt", default=0.0
    )
    bed_stiffness: float = quantity("N/m^3", "the base's bed stiffness per unit area", default=0.0)
    bed_yield_pressure: float | None = quantity(
        "Pa", "the bed's yield pressure (None: an elastic bed)", default=None
    )
    bed_plastic_work: float = quantity(
        "J",
        "the bed's plastic work over the run (its indentation, on a bed that yields)",
        default=0.0,
    )
    top_load: float = shared("top_load")
    energy_error_max: float = shared("energy_error_max")
    energy_error_limit: float = quantity("-", "the balance error past which a run is unreliable")
    # a run stopped as blown up is never reliable, whatever its last balance said
    energy_reliable: bool = quantity("", "balance within its limit and no blow-up")
    dt: float = shared("dt")
    dt_critical: float = quantity("s", "stable time step estimate (contact and collars in)")
    dt_critical_elastic: float = quantity("s", "stable time step of the stone alone")
    stable_step_reduction_by_contact: float = quantity(
        "-", "dt_critical / dt_critical_elastic: how much contact and collars shorten it"
    )
    penalty_base_mean: float = quantity("N/m", "mean normal penalty stiffness of a base node")
    steps: int = shared("steps")
    dofs: int = quantity("", "degrees of freedom of the mesh")
    wall_seconds: float = shared("wall_seconds")
    t_end: float = quantity("s", "time of the last output")
    batch_size: int = quantity("", "runs that advanced together in the kernel")
    step_halvings: int = quantity(
        "", "times the run was rerun at half its step after an unreliable one (0: none)", default=0
    )
    step_note: str | None = quantity(
        "", "why the step was halved: rerun at dt/2 after ... (None: it was not)", default=None
    )


def static_state(model: Model):
    """Gravity equilibrium with all contact springs closed: displacement and the tangential
    contact forces that hold it (used as the initial friction state). Frictionless contact
    keeps only a vanishing tangential spring (1e-9 k) that removes the rigid translation."""
    tangential = 1.0 if model.contact.friction > 0.0 else 1e-9
    springs = contact_stiffness(model, tangential_scale=tangential)
    total = (model.stiffness + springs + collar_stiffness(model)).tocsc()
    f = model.gravity.copy()
    out = np.zeros((model.collar_nodes.shape[0], OUT_SIZE))
    K.collar_forces(
        model.X.copy(),
        model.collar_nodes,
        model.collar_props,
        out,
        f,  # pretension
        model.collar_rest_state(),
        False,
    )
    u = spsolve(total, f)
    base_fn = -model.base_kn * u[2 * model.base_nodes + 1]
    if model.bed.yield_pressure is not None and np.any(base_fn > model.base_yield_force):
        pressure = float(np.max(base_fn / (model.base_tributary * model.thickness)))
        raise InputError(
            f"the bed yields under the column at rest: its static pressure reaches "
            f"{pressure / 1e6:.3g} MPa, above the bed's yield pressure "
            f"{model.bed.yield_pressure / 1e6:.3g} MPa: raise base.yield_pressure or set "
            "base.plastic = false"
        )
    base_ft = -tangential * model.base_kt * u[2 * model.base_nodes]
    crack_ft = []
    for slaves, masters, _sign, _kn, kt, _cn in model.crack_passes:
        partner = coincident_nodes(model.mesh, slaves, masters)
        crack_ft.append(-tangential * kt * (u[2 * slaves + 1] - u[2 * partner + 1]))
    return u, base_ft, crack_ft


def run(
    model: Model,
    motion: Motion,
    settings: FemSettings = DEFAULT_SETTINGS,
    start: Release = AT_REST,
    out_dir=None,
) -> FemResult:
    """Run the model under ``motion`` (:class:`colonna.core.motion.Motion`: the horizontal
    ground acceleration, a HarmonicPulse, Record or NoMotion of colonna.core.ground; the
    vertical one, upward positive, applied as the body force -rho vg'' in y; the run's
    ``duration``, s, which a FEM run needs) from ``start`` (:class:`colonna.fem.settings.
    FemStart` or a plain :class:`~colonna.core.motion.Release`; default the static state under
    gravity), stepping, recording and stopping as ``settings`` say
    (:class:`colonna.fem.settings.FemSettings`). ``out_dir``: where the run writes its files
    (None: nowhere).

    One run is a batch of one: :func:`run_ensemble` runs replicas of it, :func:`run_batch`
    other ground motions on the same model, each through the same compiled step."""
    return run_batch(model, [motion], settings, start, out_dirs=[out_dir])[0]


def unreliable_reason(summaries: list[dict]) -> str | None:
    """Why runs are unreliable (``energy_reliable`` false in any of their summaries), or None:
    a blow-up by its status (its balance may never have had a step to be off by), else the
    largest energy balance error against its limit."""
    bad = [s for s in summaries if not s["energy_reliable"]]
    if not bad:
        return None
    blown = [s["status"] for s in bad if s["status"].startswith(BLOW_UP)]
    if blown:
        return blown[0]

    def error(summary) -> float:  # a balance that is not a number (NaN, None in JSON) is worst
        value = summary.get("energy_error_max")
        return math.inf if value is None or not math.isfinite(value) else value

    worst = max(bad, key=error)
    if not math.isfinite(error(worst)):
        return (
            f"the energy balance is not a number (limit {worst['energy_error_limit']:g}): the "
            "state stopped being finite"
        )
    return (
        f"the energy balance is off by {worst['energy_error_max']:.3g} of the energy scale "
        f"(limit {worst['energy_error_limit']:g})"
    )


# an ensemble whose runs are unreliable is rerun at half its step up to this many times before
# it is returned as it is (and the study refuses it): explicit steps next to a landing's limit
STEP_HALVINGS = 2


def replica_perturbation(
    model: Model, replica: int, size: float = REPLICA_PERTURBATION
) -> np.ndarray:
    """The initial position offsets (m, flat, 2 per node) of ensemble replica ``replica``:
    ``size`` x the column height x standard normal numbers seeded by the replica's number (so
    the ensemble is reproducible); zero for replica 0, which is the unperturbed run."""
    if replica == 0:
        return np.zeros(model.n_dofs)
    rng = np.random.default_rng(replica)
    return size * model.mesh.height * rng.standard_normal(model.n_dofs)


def run_ensemble(
    model: Model,
    motion: Motion,
    settings: FemSettings = DEFAULT_SETTINGS,
    start: Release = AT_REST,
    *,
    replicas: Replicas | int = REPLICAS,
    out_dir=None,
    checkpoint: Checkpoint | None = None,
) -> list[FemResult]:
    """``replicas`` (:class:`colonna.fem.settings.Replicas`; an int n: Replicas(n)) runs of
    the model that differ only at round-off level: replica r starts from the initial state of
    :func:`run` moved by :func:`replica_perturbation` (1e-12 of the column height by default;
    replica 0 is unperturbed). Penalty contact with friction is chaotic at landings: a
    last-bit difference there becomes another landing, so a number that depends on landings is
    a band over the replicas (:mod:`colonna.fem.ensemble`), not one sample. The replicas
    advance together, one pass through the stiffness per step for all.

    ``out_dir``: replica 0 writes the files of :func:`run` there, replica r its history.csv and
    summary.json under ``out_dir/replicas/r``. ``checkpoint``: the ensemble saves its state
    there as it goes (:func:`iter_batch`; each rerun at a halved step in a folder of its own
    under it), goes on from it when run again, and removes it once done. ``motion``,
    ``settings``, ``start``: as in :func:`run`."""
    ensemble = replicas if isinstance(replicas, Replicas) else Replicas(int(replicas))
    count = int(ensemble.count)
    out_dirs: list[Path | None] = [None] * count
    if out_dir is not None:
        out_dirs = [Path(out_dir)]
        out_dirs += [Path(out_dir) / "replicas" / str(r) for r in range(1, count)]
    offsets = [replica_perturbation(model, r, ensemble.perturbation) for r in range(count)]

    def attempt(halvings: int, settings: FemSettings) -> list[FemResult]:
        """The ensemble at settings.dt (None: the stable step), halved ``halvings`` times."""
        return run_batch(
            model,
            [motion] * count,
            settings,
            start,
            out_dirs=out_dirs,
            offsets=offsets,
            slots=ensemble.slots,
            checkpoint=None if checkpoint is None else checkpoint.sub(f"dt-{halvings}", "ensemble"),
        )

    results = attempt(0, settings)
    for halvings in range(1, STEP_HALVINGS + 1):
        reason = unreliable_reason([r.summary for r in results])
        if reason is None:
            break
        settings = dataclasses.replace(settings, dt=0.5 * results[0].summary["dt"])
        results = attempt(halvings, settings)
        results = [_with_halvings(r, halvings, reason) for r in results]
        for result, folder in zip(results, out_dirs, strict=True):
            if folder is not None:
                write_summary(Path(folder) / "summary.json", result.summary)
    if checkpoint is not None:
        clear(checkpoint)
    return results


def _with_halvings(result: FemResult, halvings: int, reason: str) -> FemResult:
    """``result`` with its summary saying that its step was halved ``halvings`` times, and
    why: the ``reason`` the run before it was unreliable (:func:`unreliable_reason`)."""
    note = f"rerun at dt/{2**halvings} after {reason}"
    result.summary.update(step_halvings=halvings, step_note=note)
    if result.typed_summary is not None:
        result.typed_summary = dataclasses.replace(
            result.typed_summary, step_halvings=halvings, step_note=note
        )
    return result


def run_batch(
    model: Model,
    motions: list[Motion],
    settings: FemSettings = DEFAULT_SETTINGS,
    start: Release = AT_REST,
    *,
    out_dirs: list | None = None,
    offsets: list | None = None,
    slots: int | None = None,
    checkpoint: Checkpoint | None = None,
) -> list[FemResult]:
    """One run of the model per motion in ``motions``, advanced together (:func:`iter_batch`,
    the same arguments), as a list in the order of ``motions``."""
    results: list = [None] * len(motions)
    runs = iter_batch(
        model,
        motions,
        settings,
        start,
        out_dirs=out_dirs,
        offsets=offsets,
        slots=slots,
        checkpoint=checkpoint,
    )
    for k, result in runs:
        results[k] = result
    return results


def iter_batch(
    model: Model,
    motions: list[Motion],
    settings: FemSettings = DEFAULT_SETTINGS,
    start: Release = AT_REST,
    *,
    out_dirs: list | None = None,
    offsets: list | None = None,
    slots: int | None = None,
    checkpoint: Checkpoint | None = None,
):
    """One run of the model per motion in ``motions`` (:class:`colonna.core.motion.Motion`:
    the ground motion, the vertical one and the duration of each run), advanced together: the
    runs share the model, its stable step, ``settings`` and ``start`` (as in :func:`run`), and
    each step reads the stiffness once for all the states in the kernel. Yields (k, FemResult
    of run k) as each run ends.

    ``slots``: how many runs advance at once (default: all). With fewer slots than runs, a run
    that ends (overturned, at rest past its duration, or blown up) leaves its slot to the next
    run waiting, so the batch never waits on its longest member. A run's trajectory does not
    depend on its slot nor on its companions (the kernel computes each state alone, in strict
    arithmetic): run k of a batch is the same bits as run k alone.

    Runs of different durations need ``settings.output_interval`` (the runs share it).
    ``offsets[k]``: initial position offsets (m, flat) of run k (replicas, see
    :func:`run_ensemble`). ``out_dirs[k]``: where run k writes its files (None: nowhere; only
    run 0 writes field files).

    ``settings.stop_when_settled``: a run from the static state stops once its fate is
    settled: after the ground motion, every body short of its toe (|theta| below its
    slenderness angle) and the mechanical energy above the start (plus the balance error)
    below half the work that tips one body onto its toe. Energy only leaves the column once
    the ground is still (contact damping, friction, plastic work), so it can no longer reach a
    toe, let alone overturn, and every later swing is smaller than that energy allows (for
    maps of outcomes, such as the spectrum's grid points).

    ``settings.stop_in_weak_tail`` (with ``stop_when_settled``): such a run also stops during
    the motion, in its weak tail: from the first output at which (1) the ground the kernel
    reads stays below :func:`weak_ground_level` (a body's uplift acceleration g tan alpha_b
    over :data:`WEAK_TAIL_MARGIN`, less with vertical motion) at every later step
    (:func:`weak_tail_start`), (2) the column is seated (every body's |theta| below
    :data:`SEATED_TILT` alpha_b at every output over the last period of free rocking at that
    amplitude, 4 acosh(1 / (1 - SEATED_TILT)) / p_b) after it has rocked (a body's |theta|
    reached SEATED_TILT alpha_b at an output) and (3) the energy criterion above holds. A
    seated column that the ground cannot lift answers as an elastic body from then on,
    swaying on its bed below the seated tilt: no rocking, so no overturning, no rotation past
    what it has reached, no crack opening that strains a collar, no toe impact; the run's
    answers are those up to the stop (records have weak tails seconds long), save the toe
    stress of a mild rocking, which the sway may approach (docs/fragility.md). A run that never
    rocked runs on: its peaks are its sway, and a weak tail can sway it more than the strong
    motion did (tests/test_fragility_fem_speed.py).

    ``checkpoint`` (:class:`colonna.fem.checkpoint.Checkpoint`): the batch saves its state there
    every ``checkpoint.interval`` s of wall time and when it ends, and a batch started with the
    parts of an earlier one of the same key goes on from the last part (its ended runs yielded
    at once, the others restored bit for bit: the same numbers as uninterrupted runs), saying so
    on stderr."""
    start = FemStart.of(start)
    plan = _plan_batch(
        model, motions, settings, start, out_dirs=out_dirs, offsets=offsets, slots=slots
    )
    state = _initial_state(model, start)
    yield from _Batch(model, plan, state, checkpoint, settings.progress).run()


@dataclass(frozen=True)
class _BatchPlan:
    """A batch's checked inputs and what they set (:func:`iter_batch`): one entry per run in
    the lists; ``dt`` the step (s) and ``step`` the stable step it is a fraction of; every run
    records every ``steps_per_output`` steps, ``n_outputs[k]`` times."""

    grounds: list
    verticals: list
    out_dirs: list
    durations: list
    offsets: list | None
    slots: int
    step: object  # colonna.fem.model.StableStep
    dt: float
    steps_per_output: int
    n_outputs: list
    edge_length: float  # m
    edge_time: float  # s
    start_time: float  # s
    static_start: bool
    stop_on_overturn: bool
    settled_stop: bool  # stop a run from the static state once its fate is settled
    weak_stop: bool  # ... and in the motion's weak tail

    @property
    def size(self) -> int:
        return len(self.grounds)

    @property
    def ground_end(self) -> list:
        """Each run's end of ground motion (s), horizontal or vertical."""
        return [max(g.end_time, vg.end_time) for g, vg in zip(self.grounds, self.verticals)]

    @property
    def identity(self) -> dict:
        """What a checkpoint part must match to be gone on from (with the checkpoint's key)."""
        return {
            "dt": self.dt,
            "durations": self.durations,
            "slots": self.slots,
            "start_time": self.start_time,
        }


def _plan_batch(
    model: Model, motions: list, settings: FemSettings, start: FemStart, *, out_dirs, offsets, slots
) -> _BatchPlan:
    """The checked inputs of :func:`iter_batch` as a :class:`_BatchPlan`."""
    batch = len(motions)
    if batch < 1:
        raise InputError("run_batch: no ground motion given")
    verticals, out_dirs, durations = _batch_lists(motions, out_dirs, offsets)
    slots = batch if slots is None else int(slots)
    if slots < 1:
        raise InputError(f"run_batch slots = {slots} must be at least 1")
    step, dt = _batch_step(model, settings.dt, settings.safety, settings.check_dt)
    steps_per_output, n_outputs = _output_steps(durations, settings.output_interval, dt)
    edge_length, edge_time = _edge_settings(model, settings.edge_length, settings.edge_time)
    static_start = start.static
    return _BatchPlan(
        grounds=[m.ground for m in motions],
        verticals=verticals,
        out_dirs=out_dirs,
        durations=durations,
        offsets=offsets,
        slots=min(slots, batch),
        step=step,
        dt=dt,
        steps_per_output=steps_per_output,
        n_outputs=n_outputs,
        edge_length=edge_length,
        edge_time=edge_time,
        start_time=start.time,
        static_start=static_start,
        stop_on_overturn=settings.stop_on_overturn,
        settled_stop=settings.stop_when_settled and static_start,
        weak_stop=settings.stop_in_weak_tail and settings.stop_when_settled and static_start,
    )


def _batch_lists(motions: list, out_dirs, offsets):
    """The batch's vertical motions, output folders and durations, one per motion, checked."""
    batch = len(motions)
    for k, motion in enumerate(motions):
        if not isinstance(motion, Motion):
            raise InputError(
                f"run motion {k + 1}: a colonna.core.motion.Motion is needed, "
                f"not {type(motion).__name__}"
            )
        require_motion(f"ground motion {k + 1}", motion.ground)
        require_motion(f"vertical ground motion {k + 1}", motion.vertical)
        if motion.duration is None:
            raise InputError(f"run motion {k + 1}: a FEM run needs its duration (s)")
    verticals = [m.vertical for m in motions]
    durations = [m.duration for m in motions]
    out_dirs = [None] * batch if out_dirs is None else list(out_dirs)
    if len(out_dirs) != batch or (offsets is not None and len(offsets) != batch):
        raise InputError(
            f"run_batch: {batch} motions but {len(out_dirs)} output folders"
            + ("" if offsets is None else f", {len(offsets)} offsets")
        )
    for d in durations:
        require_positive("run duration (s)", d)
    return verticals, out_dirs, durations


def _batch_step(model: Model, dt: float | None, safety: float, check_dt: bool):
    """The stable step of the model and the step of the run: ``dt`` (s) if given, checked
    against the stable step unless ``check_dt`` is False, else the stable step's (a given dt
    is positive: :class:`FemSettings` checks it)."""
    step = stable_time_step(model, safety)
    if dt is None:
        return step, step.dt
    if check_dt and dt > step.dt * (1.0 + 1e-9):
        raise InputError(
            f"run dt = {dt:.4g} s is above the stable time step {step.dt:.4g} s "
            f"(critical {step.critical:.4g} s x safety {safety:g} x damping "
            "reduction): lower it or leave it out"
        )
    return step, dt


def _output_steps(durations: list, output_interval: float | None, dt: float):
    """Steps per output interval and each run's number of outputs (whole intervals covering
    its duration); the interval defaults to 1/400 of a common duration (a given one is
    positive: :class:`FemSettings` checks it)."""
    if output_interval is None:
        if len(set(durations)) > 1:
            raise InputError("run_batch: runs of different durations need an output_interval")
        output_interval = durations[0] / 400.0
    if output_interval > max(durations):
        raise InputError(
            f"run output_interval = {output_interval:g} s must be at most the run's duration "
            f"{max(durations):g} s (the run ends on a whole output interval)"
        )
    steps_per_output = max(1, int(round(output_interval / dt)))
    return steps_per_output, [int(math.ceil(d / (steps_per_output * dt))) for d in durations]


def _edge_settings(model: Model, edge_length: float | None, edge_time: float | None):
    """The toe stress's averaging length (m; a tenth of a body's width by default) and time
    (s; :data:`EDGE_TIME`); a given length within a body's width (its sign and the time's
    range :class:`FemSettings` checks)."""
    mesh = model.mesh
    body_width = mesh.width / mesh.n_bodies
    if edge_length is None:
        edge_length = 0.1 * body_width
    if edge_time is None:
        edge_time = EDGE_TIME
    if edge_length > body_width:
        raise InputError(
            f"edge_length = {edge_length:g} m is larger than the width of a body ({body_width:g} m)"
        )
    return edge_length, edge_time


class _Batch:
    """The runs of :func:`iter_batch` in progress: the kernel's state of its slots, each run's
    recorder and counters, the progress bar and the checkpoint's parts. :meth:`run` yields
    (k, FemResult) as each run ends."""

    def __init__(self, model: Model, plan: _BatchPlan, start: dict, checkpoint, progress: bool):
        self.model, self.plan, self.start, self.checkpoint = model, plan, start, checkpoint
        dt, batch = plan.dt, plan.size
        self.toes = edge_weights(model, plan.edge_length)
        self.state = _BatchState(
            model,
            plan.slots,
            max(1, int(round(plan.edge_time / dt))),
            np.ascontiguousarray(np.array(list(self.toes.values()))),
        )
        tau = model.contact.friction_filter
        self.blend = 1.0 if tau == 0.0 else min(1.0, dt / tau)
        self.stiffness = _stiffness(model)
        self.ground_end = plan.ground_end
        self.weak_level = weak_ground_level(model)
        self.pending = deque(range(batch))
        self.run_in = [-1] * plan.slots  # the run in each slot (-1: none)
        self.recorders: dict[int, _Recorder] = {}
        self.weak_from: list = [None] * batch  # s, where the weak tail starts (weak_stop)
        self.steps_done = [0] * batch
        self.outputs = [0] * batch  # output intervals done
        self.reasons = ["completed"] * batch
        self.overturned = [False] * batch
        self.energy0: list = [None] * batch
        self.walls = [0.0] * batch  # each run's share of the compute time (s)
        self.credited = [0.0] * batch
        self.ended_since: dict = {}  # the runs ended since the last checkpoint part, as saved
        self.parts = 0  # checkpoint parts there are
        self.last_save = time.monotonic()
        # a progress bar on a terminal only (quiet in logs and under a sweep's workers)
        self.bar = tqdm(
            total=sum(plan.durations),
            desc="[fem]" if batch == 1 else f"[fem x{batch}]",
            unit="s",
            dynamic_ncols=True,
            disable=not (progress and sys.stderr.isatty()),
            bar_format="{desc} {percentage:5.1f}%|{bar}| t = {n:.3f}/{total:.3f} s "
            "[{elapsed}<{remaining}]",
        )

    # the counters a checkpoint part keeps, by name
    COUNTERS = (
        "steps_done",
        "outputs",
        "reasons",
        "overturned",
        "energy0",
        "walls",
        "weak_from",
    )

    def run(self):
        """Yield (k, FemResult) as each run ends, from the checkpoint's last part if it
        matches, else from the start."""
        saved = self.saved_parts()
        try:
            if saved:
                yield from self.resume(saved)
                self.parts = len(saved)
            else:
                for slot in range(self.plan.slots):
                    yield from self.refill(slot)
            while self.state.motion.alive.any():
                yield from self.advance()
                if (
                    self.checkpoint is not None
                    and time.monotonic() - self.last_save >= self.checkpoint.interval
                ):
                    self.save_part()
            if self.checkpoint is not None and self.ended_since:
                self.save_part()  # the batch's end: a rerun yields it at once
        finally:
            self.bar.close()

    def advance(self):
        """One output interval of every live slot through the kernel; yields the runs that end
        and refills their slots."""
        plan, motion = self.plan, self.state.motion
        n, dt = plan.steps_per_output, plan.dt
        live = np.flatnonzero(motion.alive).tolist()
        acc = np.zeros((plan.slots, n))
        vacc = np.zeros((plan.slots, n))
        for slot in live:
            k = self.run_in[slot]
            # times from the step count, not accumulated: the trajectory then does not
            # depend on how the steps are grouped into output intervals (contact stick/slip
            # decisions amplify round-off differences)
            times = plan.start_time + dt * (self.steps_done[k] + np.arange(n))
            acc[slot] = plan.grounds[k].acceleration(times)
            vacc[slot] = plan.verticals[k].acceleration(times)
        clock = time.perf_counter()
        self.state.advance(n, dt, self.blend, self.stiffness, acc, vacc)
        share = (time.perf_counter() - clock) / len(live)
        for slot in live:
            k = self.run_in[slot]
            self.walls[k] += share
            done = int(motion.done[slot])
            if done < n:
                t_k = plan.start_time + (self.steps_done[k] + done) * dt
                self.reasons[k] = (
                    f"{BLOW_UP} at t = {t_k:.4g} s: the state stopped being "
                    f"finite (dt = {dt:.3g} s too large for the contact or collar "
                    "stiffness?)"
                )
                self.steps_done[k] += done
                yield self.finish(slot)
                yield from self.refill(slot)
                continue
            self.steps_done[k] += n
            self.outputs[k] += 1
            self.credit(k, n * dt)
            if not self.record(slot):
                yield self.finish(slot)
                yield from self.refill(slot)

    def credit(self, k: int, seconds: float) -> None:
        """Advance the progress bar by run k's simulated seconds, up to its duration."""
        seconds = min(seconds, self.plan.durations[k] - self.credited[k])
        self.credited[k] += seconds
        bar = self.bar
        bar.update(max(0.0, min(seconds, bar.total - bar.n)))  # (sums of floats: never past)

    def load(self, slot: int, k: int) -> None:
        """Start run k in the slot: its initial state and the forces there."""
        plan, state = self.plan, self.state
        clock = time.perf_counter()
        state.reset(slot, self.start, None if plan.offsets is None else plan.offsets[k])
        if plan.weak_stop:
            self.weak_from[k] = weak_tail_start(
                plan.grounds[k],
                plan.verticals[k],
                self.weak_level,
                self.model.g,
                plan.start_time,
                plan.dt,
                plan.n_outputs[k] * plan.steps_per_output,
            )
        # the forces of the initial state (contact normal forces at rest) for the first record
        state.evaluate(plan.dt, self.blend, self.stiffness, slot)
        recorder = _Recorder(self.model, plan.edge_length, list(self.toes), plan.out_dirs[k])
        recorder.start_edge_average(state, slot)
        self.recorders[k] = recorder
        self.run_in[slot] = k
        self.walls[k] += time.perf_counter() - clock

    def record(self, slot: int) -> bool:
        """Record the slot's run at its present output time; False where the run ends."""
        plan = self.plan
        clock = time.perf_counter()
        k = self.run_in[slot]
        t = plan.start_time + self.steps_done[k] * plan.dt
        recorder = self.recorders[k]
        row = recorder.record(t, self.state, slot)
        if self.energy0[k] is None:
            self.energy0[k] = row["energy_total"]
        recorder.finish_row(row, self.energy0[k])
        stop = _check(
            row,
            recorder,
            self.ground_end[k],
            t,
            plan.stop_on_overturn,
            self.energy0[k] if plan.settled_stop else None,
            self.weak_from[k],
        )
        self.walls[k] += time.perf_counter() - clock
        if stop is not None:
            self.reasons[k], self.overturned[k] = stop
            return False
        return self.outputs[k] < plan.n_outputs[k]

    def finish(self, slot: int) -> tuple[int, FemResult]:
        """End the slot's run: its result, files written; the slot is free."""
        plan = self.plan
        k = self.run_in[slot]
        self.run_in[slot] = -1
        self.state.motion.alive[slot] = False
        recorder = self.recorders.pop(k)
        history = recorder.close()
        typed = _summary(
            self.model,
            history,
            self.reasons[k],
            self.overturned[k],
            plan.dt,
            plan.step,
            self.outputs[k],
            plan.steps_per_output,
            self.walls[k],
            plan.edge_length,
            plan.edge_time,
            plan.static_start,
            self.state.collars.plastic[slot],
            batch_size=plan.slots,
        )
        summary = to_dict(typed)
        result = FemResult(
            history,
            summary,
            recorder.frames,
            self.model,
            recorder.velocity_frames,
            recorder.contact_frames,
            typed_summary=typed,
        )
        if self.checkpoint is not None:  # for the next part: what a rerun needs to yield it
            self.ended_since[k] = {"tail": recorder.snapshot(), "summary": summary, "typed": typed}
        if plan.out_dirs[k] is not None:
            write_run(result, plan.out_dirs[k], first=k == 0)
        self.credit(k, plan.durations[k])  # the rest of a run that ended early
        return k, result

    def refill(self, slot: int):
        """Start the next waiting run in a free slot (yielding any that end at once)."""
        while self.pending:
            self.load(slot, self.pending.popleft())
            if self.record(slot):
                return
            yield self.finish(slot)

    def saved_parts(self) -> list:
        """The checkpoint's parts to go on from: none without a checkpoint, and none (the
        checkpoint cleared, said on stderr) where they do not match this batch or its files."""
        checkpoint = self.checkpoint
        saved = [] if checkpoint is None else read_parts(checkpoint)
        if saved and (
            any(saved[-1][name] != value for name, value in self.plan.identity.items())
            or not self.resumable(saved)
        ):
            print(
                f"[fem] the checkpoint in {checkpoint.folder} does not match this run or its "
                "files: starting afresh",
                file=sys.stderr,
            )
            clear(checkpoint)
            saved = []
        return saved

    def save_part(self) -> None:
        """A checkpoint part: the runs in progress, those ended since the last part, counters."""
        assert self.checkpoint is not None
        live = {
            k: {
                "slot": slot,
                "arrays": self.state.slot_arrays(slot),
                "recorder": self.recorders[k].snapshot(),
            }
            for slot, k in enumerate(self.run_in)
            if k >= 0
        }
        counters = {name: getattr(self, name) for name in self.COUNTERS}
        counters.update(pending=list(self.pending), credited=self.credited)
        write_part(
            self.checkpoint,
            self.parts,
            {
                **self.plan.identity,
                "live": live,
                "ended": dict(self.ended_since),
                "counters": counters,
            },
        )
        self.parts += 1
        self.ended_since.clear()
        self.last_save = time.monotonic()

    def resumable(self, saved: list[dict]) -> bool:
        """Whether the runs in progress at the last part still have their files as saved."""
        live = saved[-1]["live"]
        return all(
            _Recorder.can_resume(run["recorder"], self.plan.out_dirs[k]) for k, run in live.items()
        )

    def resume(self, saved: list[dict]) -> list:
        """Go on from the checkpoint's parts: the runs in progress put back in their slots;
        returns the (k, FemResult) of those that had ended."""
        assert self.checkpoint is not None
        plan = self.plan
        snapshots: dict[int, list] = {}
        ended: dict = {}
        for part in saved:
            for k, run in part["live"].items():
                snapshots.setdefault(k, []).append(run["recorder"])
            for k, end in part["ended"].items():
                snapshots.setdefault(k, []).append(end["tail"])
                ended[k] = end
        last = saved[-1]
        for k, run in last["live"].items():
            recorder = _Recorder(self.model, plan.edge_length, list(self.toes), None)
            recorder.resume(snapshots[k], plan.out_dirs[k])
            self.recorders[k] = recorder
            self.state.restore_slot(run["slot"], run["arrays"])
            self.run_in[run["slot"]] = k
        counters = last["counters"]
        self.pending.clear()
        self.pending.extend(counters["pending"])
        for name in self.COUNTERS:
            getattr(self, name)[:] = counters[name]
        for k in range(plan.size):
            self.credit(k, counters["credited"][k])
        times = [plan.start_time + self.steps_done[k] * plan.dt for k in last["live"]]
        print(
            f"[fem] resumed from the checkpoint in {self.checkpoint.folder}: {len(ended)} of "
            f"{plan.size} runs had ended"
            + (f", the others go on from t = {min(times):.4g} s" if times else ""),
            file=sys.stderr,
            flush=True,
        )
        return [(k, self.ended_result(snapshots[k], end)) for k, end in ended.items()]

    def ended_result(self, tail: list[dict], end: dict) -> FemResult:
        """The FemResult of a run that had ended before the checkpoint's last part, from its
        recorder's snapshots and its summary as saved."""
        rows = [row for snap in tail for row in snap["rows"]]
        frames = {
            name: [f for snap in tail for f in snap[name]]
            for name in ("frames", "velocity_frames", "contact_frames")
        }
        return FemResult(
            _history(rows),
            end["summary"],
            frames["frames"],
            self.model,
            frames["velocity_frames"],
            frames["contact_frames"],
            typed_summary=end["typed"],
        )


def turned_about_toe(model: Model, x: np.ndarray, tilt: float, angular_velocity: float):
    """Positions x turned by ``tilt`` (rad, theta sign: > 0 toward +x, clockwise) about the
    outer toe the column tips on, and the velocities of a rotation at ``angular_velocity``
    (rad/s, theta sign) about it."""
    p = model.mesh.points
    side = 1.0 if (tilt > 0.0 or (tilt == 0.0 and angular_velocity > 0.0)) else -1.0
    pivot = np.array([p[0].max() if side > 0 else p[0].min(), p[1].min()])
    phi, omega = -tilt, -angular_velocity  # counter-clockwise
    c, s = math.cos(phi), math.sin(phi)
    r = x.reshape(-1, 2) - pivot
    turned = np.stack((c * r[:, 0] - s * r[:, 1], s * r[:, 0] + c * r[:, 1]), axis=1)
    v = omega * np.stack((-turned[:, 1], turned[:, 0]), axis=1)
    return (pivot + turned).ravel(), v.ravel()


def _initial_state(model: Model, start: FemStart) -> dict:
    """The state a run starts from: x, v (flat) and the contact state (base_ft, base_fc,
    crack_ft, crack_fc lists, collar_state), checked."""
    contact = {
        "base_fc": np.zeros(model.base_nodes.size),
        "crack_fc": [np.zeros(p[0].size) for p in model.crack_passes],
        "collar_state": model.collar_rest_state(),
    }
    if start.state is not None:
        x, v = (np.array(a, dtype=float).reshape(-1) for a in start.state)
        if x.size != model.n_dofs or v.size != model.n_dofs:
            raise InputError(
                f"run start.state: x and v need {model.n_dofs} values each "
                f"(2 per node), got {x.size} and {v.size}"
            )
        if not (np.all(np.isfinite(x)) and np.all(np.isfinite(v))):
            raise InputError("run start.state: x and v must be finite")
        contact["base_ft"] = np.zeros(model.base_nodes.size)
        contact["crack_ft"] = [np.zeros(p[0].size) for p in model.crack_passes]
    else:
        u0, base_ft, crack_ft = static_state(model)
        x = model.X + u0
        v = np.zeros_like(x)
        contact["base_ft"], contact["crack_ft"] = base_ft, list(crack_ft)
    if not start.at_rest:
        x, v = turned_about_toe(model, x, start.tilt, start.angular_velocity)
        contact["base_ft"] = np.zeros(model.base_nodes.size)  # only the toe touches: no friction
    if start.velocity is not None:
        v = v + np.asarray(start.velocity, dtype=float).reshape(-1)
    if start.contact is not None:
        contact.update(_restore_contact(model, start.contact))
    return {"x": x, "v": v, **contact}


def _restore_contact(model, state: dict) -> dict:
    """A restart's contact state (base_ft, base_fc, crack_ft, crack_fc and, if given, the
    collars' plastic state), shapes checked."""
    try:
        base = [np.array(state[key], dtype=float) for key in ("base_ft", "base_fc")]
        passes = [
            [np.array(a, dtype=float) for a in state[key]] for key in ("crack_ft", "crack_fc")
        ]
    except (KeyError, TypeError, ValueError) as err:
        raise InputError(
            f"run start.contact: needs base_ft, base_fc, crack_ft, crack_fc ({err})"
        ) from None
    expected = [(model.base_nodes.size,)] * 2 + [(p[0].size,) for p in model.crack_passes] * 2
    given = [a.shape for a in base] + [a.shape for a in passes[0] + passes[1]]
    if given != expected:
        raise InputError(f"run start.contact: expected arrays of shapes {expected}, got {given}")
    out = {"base_ft": base[0], "base_fc": base[1], "crack_ft": passes[0], "crack_fc": passes[1]}
    if state.get("base_indentation") is not None:  # the bed's plastic indentation (m)
        indentation = np.array(state["base_indentation"], dtype=float)
        if indentation.shape != (model.base_nodes.size,):
            raise InputError(
                f"run start.contact: base_indentation must have shape "
                f"({model.base_nodes.size},), got {indentation.shape}"
            )
        out["base_indentation"] = indentation
    if "collar_state" in state:  # the plastic state of the collars
        collar_state = np.asarray(state["collar_state"], dtype=float)
        shape = (model.collar_nodes.shape[0], model.collar_state_size)
        if collar_state.shape != shape:
            raise InputError(
                f"run start.contact: collar_state must have shape {shape} (per collar: "
                f"plastic elongation, accumulated plastic strain, plastic work, two hinge "
                f"rotations, largest fibre strain, fractured, then what its law keeps), "
                f"got {collar_state.shape}"
            )
        out["collar_state"] = collar_state
    if state.get("cohesive_damage") is not None:  # a partial crack's pair damage
        damage = np.asarray(state["cohesive_damage"], dtype=float)
        pairs = 0 if model.cohesive is None else model.cohesive.left.size
        if damage.shape != (pairs,) or not np.all((damage >= 0.0) & (damage <= 1.0)):
            raise InputError(
                f"run initial_contact: cohesive_damage must be {pairs} numbers in [0, 1] (one "
                f"per mid-plane pair of the partial crack), got shape {damage.shape}"
            )
        out["cohesive_damage"] = damage
    return out


def _stiffness(model: Model) -> K.Stiffness:
    A = model.stiffness.tobsr(blocksize=(2, 2))
    return K.Stiffness(
        A.indptr.astype(np.int64),
        A.indices.astype(np.int64),
        # each block by columns (fem._kernels.Stiffness)
        np.ascontiguousarray(A.data.transpose(0, 2, 1), dtype=float),
    )


class _BatchState:
    """The kernel's bundles (fem._kernels) for B slots of one model, each slot empty (not
    alive) until :meth:`reset` puts a run's start in it."""

    def __init__(self, model: Model, batch: int, edge_steps: int, weights: np.ndarray):
        self.model = model
        n, n_base = model.n_dofs, model.base_nodes.size
        node_body = model.mesh.node_body
        order = np.argsort(node_body, kind="stable").astype(np.int64)
        offsets = np.searchsorted(node_body[order], np.arange(model.mesh.n_bodies + 1))
        self.bodies = K.Bodies(
            model.X,
            model.mass,
            node_body,
            model.centroid_ref,
            model.gravity,
            order,
            offsets.astype(np.int64),
        )
        empty_i = np.zeros(0, dtype=np.int64)
        self.base = K.ContactPass(
            model.base_nodes,
            np.zeros(1, dtype=np.int64),
            1.0,
            model.base_kn,
            model.base_kt,
            model.base_cn,
            model.base_yield_force,
        )
        passes = [
            K.ContactPass(sl, ma, float(sign), kn, kt, cn, np.full(sl.size, np.inf))
            for sl, ma, sign, kn, kt, cn in model.crack_passes
        ]
        none = np.zeros(0)
        while len(passes) < 2:
            passes.append(
                K.ContactPass(empty_i, np.zeros(1, dtype=np.int64), 1.0, none, none, none, none)
            )
        self.cracks = tuple(passes)
        self.motion = K.Motion(
            np.zeros((batch, n)),
            np.zeros((batch, n)),
            np.zeros((batch, model.mesh.n_bodies, 3)),
            np.zeros((batch, 6)),
            np.zeros((batch, 6)),
            np.zeros(batch, dtype=np.bool_),
            np.zeros(batch, dtype=np.int64),
        )

        def contact_state(nodes: int) -> K.ContactState:
            return K.ContactState(
                np.zeros((batch, nodes), dtype=np.int64),
                np.zeros((batch, nodes)),
                np.zeros((batch, nodes)),
                np.zeros((batch, nodes)),
                np.zeros((batch, nodes)),
            )

        self.base_state = contact_state(n_base)
        self.crack_states = tuple(contact_state(crack.nodes.size) for crack in self.cracks)
        n_collars = model.collar_nodes.shape[0]
        self.collars = K.CollarState(
            np.zeros((batch, n_collars, OUT_SIZE)),
            np.zeros((batch, n_collars, model.collar_state_size)),
        )
        self.collar_model = K.Collars(model.collar_nodes, model.collar_props)
        # a partial crack's intact mid-plane (fem.partial_crack): its pairs and their damage
        pairs = model.cohesive
        if pairs is None:
            self.cohesive = K.Cohesive(empty_i, empty_i, none, none, np.zeros(5))
        else:
            self.cohesive = K.Cohesive(
                pairs.left, pairs.right, pairs.area, pairs.stiffness, pairs.law
            )
        self.cohesive_state = K.CohesiveState(
            np.zeros((batch, self.cohesive.left.size)), np.zeros((batch, 2))
        )
        self.edge = K.EdgeAverage(
            weights,
            np.zeros((batch, weights.shape[0], edge_steps)),
            np.zeros(batch, dtype=np.int64),
            np.zeros((batch, weights.shape[0])),
            np.zeros((batch, weights.shape[0])),
        )
        self.scratch = K.new_scratch(n)
        self.lagrange_tolerance = LAGRANGE_TOLERANCE * float(model.X.max() - model.X.min())

    def advance(self, n_steps, dt, blend, stiffness, acc, vacc):
        K.advance(
            n_steps,
            dt,
            self.model.contact.friction,
            blend,
            stiffness,
            self.bodies,
            self.base,
            self.cracks,
            self.collar_model,
            acc,
            vacc,
            self.motion,
            self.base_state,
            self.crack_states,
            self.collars,
            self.edge,
            self.scratch,
            self.model.contact.enforcement == "lagrange",
            self.lagrange_tolerance,
            self.cohesive,
            self.cohesive_state,
        )

    def _bundles(self) -> dict:
        return {
            "motion": self.motion,
            "base": self.base_state,
            "crack_a": self.crack_states[0],
            "crack_b": self.crack_states[1],
            "collars": self.collars,
            "edge": self.edge,
            "cohesive": self.cohesive_state,
        }

    def slot_arrays(self, slot: int) -> dict:
        """Copies of every array the kernel keeps for state ``slot`` (a checkpoint's)."""
        return {
            f"{name}.{f}": np.copy(getattr(bundle, f)[slot])
            for name, bundle in self._bundles().items()
            for f in bundle._fields
            if (name, f) != ("edge", "weights")  # the toes' weights are the model's
        }

    def restore_slot(self, slot: int, arrays: dict) -> None:
        """State ``slot`` as :meth:`slot_arrays` saved it."""
        for name, bundle in self._bundles().items():
            for f in bundle._fields:
                key = f"{name}.{f}"
                if key not in arrays and name == "cohesive" and not self.cohesive.left.size:
                    bundle.energy[slot] = 0.0  # saved before partial cracks: there were none
                    continue
                if (name, f) != ("edge", "weights"):
                    getattr(bundle, f)[slot] = arrays[key]

    def reset(self, slot: int, start: dict, offset=None) -> None:
        """Put state ``slot`` at ``start`` (positions moved by ``offset``, m, flat), at rest in
        its contact and collar history, and alive."""
        m = self.motion
        m.x[slot] = start["x"] if offset is None else start["x"] + np.asarray(offset).ravel()
        m.v[slot] = start["v"]
        for array in (m.frames, m.tallies, m.energies):
            array[slot] = 0.0
        m.alive[slot] = True
        m.done[slot] = 0
        crack_ft = list(start["crack_ft"]) + [np.zeros(0)] * 2
        crack_fc = list(start["crack_fc"]) + [np.zeros(0)] * 2
        for contact, seg, ft, fc in (
            (self.base_state, 0, start["base_ft"], start["base_fc"]),
            *((c, -1, crack_ft[p], crack_fc[p]) for p, c in enumerate(self.crack_states)),
        ):
            contact.seg[slot] = seg
            contact.ft[slot] = ft
            contact.fn[slot] = 0.0
            contact.fc[slot] = fc
            contact.indentation[slot] = 0.0
        if start.get("base_indentation") is not None:  # a restart on a bed that yielded
            self.base_state.indentation[slot] = start["base_indentation"]
        self.collars.out[slot] = 0.0
        self.collars.plastic[slot] = np.asarray(start["collar_state"]).reshape(
            self.collars.plastic.shape[1:]
        )
        for array in (self.edge.buffer, self.edge.position, self.edge.sums, self.edge.peak):
            array[slot] = 0
        if self.model.cohesive is not None:  # the crack as given or as a restart carries it
            damage = start.get("cohesive_damage")
            self.cohesive_state.damage[slot] = (
                self.model.cohesive.damage0 if damage is None else damage
            )
        self.cohesive_state.energy[slot] = 0.0

    def evaluate(self, dt, blend, stiffness, slot: int) -> None:
        """The forces of state ``slot`` at its present state without moving it: one step of
        size 0 on copies of the state, whose outputs (contact normal forces, collar forces,
        frames, energies) are kept."""
        copy = lambda bundle: type(bundle)(
            *(
                a.copy() if isinstance(a, np.ndarray) else a  # noqa: E731
                for a in bundle
            )
        )
        motion, base, cracks = (
            copy(self.motion),
            copy(self.base_state),
            tuple(copy(c) for c in self.crack_states),
        )
        motion.alive[:] = False
        motion.alive[slot] = True
        collars, edge, cohesive = copy(self.collars), copy(self.edge), copy(self.cohesive_state)
        zeros = np.zeros((self.motion.x.shape[0], 1))
        K.advance(
            1,
            0.0,
            self.model.contact.friction,
            blend,
            stiffness,
            self.bodies,
            self.base,
            self.cracks,
            self.collar_model,
            zeros,
            zeros,
            motion,
            base,
            cracks,
            collars,
            edge,
            self.scratch,
            self.model.contact.enforcement == "lagrange",
            self.lagrange_tolerance,
            self.cohesive,
            cohesive,
        )
        self.motion.frames[slot] = motion.frames[slot]
        self.motion.energies[slot] = motion.energies[slot]
        self.base_state.fn[slot] = base.fn[slot]
        for mine, new in zip(self.crack_states, cracks):
            mine.fn[slot] = new.fn[slot]
        self.collars.out[slot] = collars.out[slot]


def _tributary_intervals(mesh):
    """Each base node's tributary interval along the base (lo, hi), body by body."""
    lo, hi = [], []
    for nodes in mesh.base_nodes:
        xs = mesh.points[0, nodes]
        mid = 0.5 * (xs[1:] + xs[:-1])
        lo.append(np.concatenate(([xs[0]], mid)))
        hi.append(np.concatenate((mid, [xs[-1]])))
    return np.concatenate(lo), np.concatenate(hi)


def edge_weights(model: Model, edge_length: float) -> dict:
    """Per toe (left, right and, cracked, inner_left, inner_right): each base node's share of
    its tributary segment within ``edge_length`` of that toe, so that the toe's resultant is
    weights . base_fn."""
    mesh = model.mesh
    p = mesh.points
    base = model.base_nodes
    xb = p[0, base]
    trib_lo, trib_hi = _tributary_intervals(mesh)
    weights = {}
    corners = {"left": (xb.min(), +1), "right": (xb.max(), -1)}
    if mesh.cracked:
        corners["inner_left"] = (p[0, mesh.base_nodes[0]].max(), -1)
        corners["inner_right"] = (p[0, mesh.base_nodes[1]].min(), +1)
    for name, (x0, direction) in corners.items():
        lo, hi = (x0, x0 + edge_length) if direction > 0 else (x0 - edge_length, x0)
        body = 0 if name in ("left", "inner_left") else mesh.n_bodies - 1
        same_body = mesh.node_body[base] == body
        overlap = np.clip(np.minimum(trib_hi, hi) - np.maximum(trib_lo, lo), 0.0, None)
        weights[name] = np.where(same_body, overlap / (trib_hi - trib_lo), 0.0)
    return weights


class _Recorder:
    """Recovers the outputs of one state of a batch at each output time, and hands them to its
    run's :class:`colonna.fem.output.HistoryFiles` (history.csv, base_pressure.csv) where it
    has an output folder."""

    def __init__(self, model: Model, edge_length: float, edge_names: list, out_dir):
        self.model = model
        mesh = model.mesh
        self.rows: list = []
        self.frames: list = []
        self.velocity_frames: list = []
        self.contact_frames: list = []
        # energy scale floor: the gravity work that tips the halves onto a toe,
        # m g R (1 - cos alpha) summed over the bodies
        w_b = mesh.width / mesh.n_bodies
        r_b = 0.5 * math.hypot(w_b, mesh.height)
        alpha_b = math.atan2(w_b, mesh.height)
        self.scale = float(model.mass[0::2].sum()) * model.g * r_b * (1.0 - math.cos(alpha_b))
        self.tipping_work = self.scale / mesh.n_bodies  # J: one body onto its toe
        self.tipping_angle = alpha_b  # rad: a body's centre of mass above its toe
        self.body_p = math.sqrt(0.75 * model.g / r_b)  # 1/s: a body's p, sqrt(m g R / J0)
        self.seated_time = 0.0  # s: the span :meth:`seated` looked back over
        self.peak_tilt = 0.0  # rad: the largest |theta| of a body at the outputs so far
        self.potential_scale = float(model.mass[0::2].sum()) * model.g * mesh.height
        self.body_mass = np.array(
            [model.node_mass[mesh.node_body == b].sum() for b in range(mesh.n_bodies)]
        )
        # toes: outer corners of the column, and the crack corners of each half
        self.toe_left = mesh.base_nodes[0][0]
        self.toe_right = mesh.base_nodes[-1][-1]
        self.edge_names = edge_names  # the toes, in the order of the edge weights
        self.edge_area = edge_length * model.thickness

        self.crack_pairs: tuple | None = None
        if mesh.cracked:
            left, right = mesh.crack_nodes
            self.crack_pairs = (left, coincident_nodes(mesh, left, right))
        self.files: HistoryFiles | None = None
        if out_dir is not None:
            self.files = HistoryFiles(
                out_dir,
                mesh.points[0, model.base_nodes],
                mesh.node_body[model.base_nodes] + 1,
            )
        self.header = None
        self.saved_rows = 0  # rows already in a checkpoint part (snapshot)
        self.base_area = model.base_tributary * model.thickness
        # per toe, the base nodes of its body (positions in the base arrays) from the toe
        # inward, and their tributary lengths (m): the contact length at the toe
        lo, hi = _tributary_intervals(mesh)
        xb = mesh.points[0, model.base_nodes]
        body_of_base = mesh.node_body[model.base_nodes]
        self.toe_runs: dict = {}
        for name in edge_names:
            body = 0 if name in ("left", "inner_left") else mesh.n_bodies - 1
            mine = np.nonzero(body_of_base == body)[0]
            inward = name in ("left", "inner_right")  # the toe is the body's smallest x
            run = mine[np.argsort(xb[mine] if inward else -xb[mine], kind="stable")]
            self.toe_runs[name] = (run, (hi - lo)[run])
        # per toe, each of its run's nodes' distance from it (reference positions, m)
        self.toe_distance = {
            name: np.abs(xb[run] - xb[run[0]]) for name, (run, _) in self.toe_runs.items()
        }

    @staticmethod
    def start_edge_average(state, r: int):
        """Fill state r's toe averaging buffers with the resultants at the start."""
        edge = state.edge
        resultants = edge.weights @ state.base_state.fn[r]
        edge.buffer[r] = resultants[:, None]
        edge.position[r] = 0
        edge.sums[r] = resultants * edge.buffer.shape[2]

    def seated(self, t: float, tilt: float) -> bool:
        """Whether every body's |theta| stayed below ``tilt`` x its slenderness angle at every
        output over the last period of a body's free rocking at that amplitude before ``t``
        (s): 4 acosh(1 / (1 - tilt)) / p_b, linearised (the rows recorded so far)."""
        limit = tilt * self.tipping_angle
        span = self.seated_time = 4.0 * math.acosh(1.0 / (1.0 - tilt)) / self.body_p
        for row in reversed(self.rows):
            if max(abs(row["theta_left"]), abs(row["theta_right"])) >= limit:
                return False
            if row["t"] <= t - span:
                return True
        return False

    def falling(self, row, previous) -> str | None:
        """Which part, if any, has its centre of mass beyond its outer toe and moving outward.

        Collars and crack contact are internal forces: once the ground is still and the whole
        column's centre of mass is past the outer toe it pivots on, nothing restores it. Without
        collars a half tipping away from the other is free, and is judged alone the same way."""
        x_toe_left, x_toe_right = row["_toe_x_left"], row["_toe_x_right"]
        xc, xc_prev = row["_com_x"], previous["_com_x"]
        if (xc > x_toe_right and xc > xc_prev) or (xc < x_toe_left and xc < xc_prev):
            return "the column's centre of mass"
        # a free half, on its own (not while intact stone of a partial crack joins the halves)
        if self.model.mesh.cracked and not self.model.collars and not row.get("_intact_pairs"):
            if row["_com_x_1"] < x_toe_left and row["_com_x_1"] < previous["_com_x_1"]:
                return "the left half's centre of mass"
            if row["_com_x_2"] > x_toe_right and row["_com_x_2"] > previous["_com_x_2"]:
                return "the right half's centre of mass"
        return None

    def record(self, t: float, state, r: int) -> dict:
        """The output row of state r of a batch (a _BatchState) at time t; its frames kept,
        its base pressures written."""
        motion = state.motion
        x, frames = motion.x[r], motion.frames[r]
        base_fn = state.base_state.fn[r]
        passes = [
            (c.ft[r], c.fn[r], c.fc[r])
            for c, p in zip(state.crack_states, state.cracks)
            if p.nodes.size
        ]
        row = self._motion_columns(t, x, frames)
        self._toe_columns(row, state.edge, r, base_fn)
        self._force_columns(row, x, frames, base_fn, passes)
        self._collar_columns(row, state.collars.out[r], state.collars.plastic[r])
        self._energy_columns(row, motion.energies[r], motion.tallies[r])
        if self.model.cohesive is not None:  # a partial crack: its extent and the stone's work
            row["_intact_pairs"] = int(np.sum(state.cohesive_state.damage[r] < 1.0))
            row.update(
                crack_columns(
                    self.model.cohesive,
                    state.cohesive_state.damage[r],
                    state.cohesive_state.energy[r],
                    x,
                    frames[:, 2],
                    self.model.stone.E,  # plane stress: E' = E
                )
            )
        self._keep_frames(t, state, r, passes)
        return row

    def _motion_columns(self, t: float, x, frames) -> dict:
        """t, the bodies' rotations and translations, the centre of mass, the toes' uplift."""
        model, mesh = self.model, self.model.mesh
        theta = -frames[:, 2]
        row = {"t": t, "theta_left": theta[0], "theta_right": theta[-1]}
        for b in range(mesh.n_bodies):
            c = model.centroid_ref[b]
            row[f"translation_x_{b + 1}"] = frames[b, 0] - c[0]
            row[f"translation_y_{b + 1}"] = frames[b, 1] - c[1]
        row["_com_x"] = float(self.body_mass @ frames[:, 0] / self.body_mass.sum())
        for b in range(mesh.n_bodies):
            row[f"_com_x_{b + 1}"] = float(frames[b, 0])
        row["_toe_x_left"] = float(x[2 * self.toe_left])
        row["_toe_x_right"] = float(x[2 * self.toe_right])
        row["uplift_left"] = max(x[2 * self.toe_left + 1], 0.0)
        row["uplift_right"] = max(x[2 * self.toe_right + 1], 0.0)
        return row

    def _toe_columns(self, row: dict, edge, r: int, base_fn) -> None:
        """Each toe's stress (the peak over the output interval), force, contact run and
        resolved pressure."""
        # peak over the output interval ending at t (every step of it), not a sample at t
        for e, name in enumerate(self.edge_names):
            peak = float(edge.peak[r, e]) if self.rows else float(edge.weights[e] @ base_fn)
            row[f"edge_stress_{name}"] = peak / self.edge_area
        edge.peak[r] = 0.0
        for e, name in enumerate(self.edge_names):
            # sampled at t: the toe's resultant over its window (N), and the nodes in contact
            # from the toe inward, up to the first open one
            run, lengths = self.toe_runs[name]
            row[f"toe_force_{name}"] = float(edge.weights[e] @ base_fn)
            touching = base_fn[run] > 0.0
            n = int(np.argmin(touching)) if not touching.all() else touching.size
            row[f"toe_contact_nodes_{name}"] = n
            row[f"toe_contact_length_{name}"] = float(lengths[:n].sum())
            # the resolved pressure: the largest nodal pressure of the toe's body (Pa), and
            # its base's resultant (N) and the resultant's distance from the toe (m)
            pressure = base_fn[run] / self.base_area[run]
            force = float(base_fn[run].sum())
            row[f"toe_pressure_{name}"] = float(pressure.max())
            row[f"toe_resultant_{name}"] = force
            row[f"toe_resultant_offset_{name}"] = (
                float(base_fn[run] @ self.toe_distance[name]) / force if force > 0.0 else 0.0
            )

    def _force_columns(self, row: dict, x, frames, base_fn, passes) -> None:
        """The base's normal force per body; the crack's normal force, opening and slip."""
        model, mesh = self.model, self.model.mesh
        body_of_base = mesh.node_body[model.base_nodes]
        for b in range(mesh.n_bodies):
            row[f"base_normal_force_{b + 1}"] = float(base_fn[body_of_base == b].sum())
        if mesh.cracked:
            row["crack_normal_force"] = float(sum(fn.sum() for _, fn, _ in passes))
            assert self.crack_pairs is not None
            left, right = self.crack_pairs
            c, s = math.cos(frames[0, 2]), math.sin(frames[0, 2])
            d = x.reshape(-1, 2)[right] - x.reshape(-1, 2)[left]
            opening = c * d[:, 0] + s * d[:, 1]  # along the left half's x axis
            slip = -s * d[:, 0] + c * d[:, 1]
            row["crack_opening_max"] = float(opening.max())
            row["crack_slip_max"] = float(np.abs(slip).max())

    def _collar_columns(self, row: dict, collar_out, collar_state) -> None:
        """Each collar's forces, stress, utilisation and strains (its hinges if plastic)."""
        for k, collar in enumerate(self.model.collars, start=1):
            N, M1, M2 = collar_out[k - 1, :3]
            moment = max(abs(M1), abs(M2))
            if collar.local_law == "fibre":  # its largest fibre stress (0 once broken)
                broken = collar_state[k - 1, FRACTURED] != 0.0
                stress = 0.0 if broken else collar_state[k - 1, FIBRE_STRESS]
            else:
                stress = collar.fibre_stress(N, moment, collar_state[k - 1, 1])
            row[f"collar_{k}_axial_force"] = N
            row[f"collar_{k}_moment"] = moment
            row[f"collar_{k}_stress"] = stress
            row[f"collar_{k}_utilisation"] = stress / collar.fy
            row[f"collar_{k}_fibre_strain"] = collar_out[k - 1, 5]
            if collar.plastic:
                row[f"collar_{k}_plastic_strain"] = collar_out[k - 1, 4]
                for end, side in enumerate(("left", "right")):
                    row[f"collar_{k}_moment_{side}"] = collar_out[k - 1, 1 + end]
                    row[f"collar_{k}_rotation_{side}"] = collar_out[k - 1, 6 + end]
                    row[f"collar_{k}_hinge_rotation_{side}"] = collar_state[k - 1, 3 + end]
                row[f"collar_{k}_fractured"] = collar_state[k - 1, FRACTURED]

    def _energy_columns(self, row: dict, energies, tallies) -> None:
        """The energies and the dissipated energy's parts (J)."""
        kinetic, gravity = energies[5], energies[4]
        row.update(
            energy_kinetic=kinetic,
            energy_strain=energies[0],
            energy_gravity=gravity,
            energy_contact=energies[1] + energies[2],
            energy_collar=energies[3],
            energy_dissipated=tallies[0],
            energy_external_work=tallies[1],
            # of the dissipated energy: friction at the base and along the crack, and the
            # contact damping (with the clipped tensile part); the rest is the collars' yielding
            energy_friction_base=tallies[2],
            energy_friction_crack=tallies[3],
            energy_contact_damping=tallies[4],
            energy_bed_plastic=tallies[5],
        )
        row["energy_total"] = (
            kinetic + energies[0] + gravity + energies[1] + energies[2] + energies[3]
        )

    def _keep_frames(self, t: float, state, r: int, passes) -> None:
        """The displacement, velocity and contact frames at t; the base's pressures written."""
        motion = state.motion
        x, v, X = motion.x[r], motion.v[r], self.model.X
        base_fn, base_ft, base_fc = (
            state.base_state.fn[r],
            state.base_state.ft[r],
            state.base_state.fc[r],
        )
        collar_state = state.collars.plastic[r]
        self.frames.append((t, (x - X).reshape(-1, 2).copy()))
        self.velocity_frames.append((t, v.reshape(-1, 2).copy()))
        contact = {
            "base_ft": base_ft.copy(),
            "base_fc": base_fc.copy(),
            "base_indentation": state.base_state.indentation[r].copy(),
            "crack_ft": [ft.copy() for ft, _, _ in passes],
            "crack_fc": [fc.copy() for _, _, fc in passes],
            "collar_state": collar_state.copy(),
        }
        if self.model.cohesive is not None:  # a partial crack's pair damage (fem.partial_crack)
            contact["cohesive_damage"] = state.cohesive_state.damage[r].copy()
        self.contact_frames.append((t, contact))
        if self.files is not None:  # contact pressure along the base (Pa), one row per output
            self.files.write_pressure(t, base_fn / self.base_area)

    def finish_row(self, row, energy0):
        self.peak_tilt = max(self.peak_tilt, abs(row["theta_left"]), abs(row["theta_right"]))
        self.scale = max(self.scale, row["energy_kinetic"], abs(row["energy_external_work"]))
        imbalance = (
            row["energy_total"] + row["energy_dissipated"] - row["energy_external_work"] - energy0
        )
        row["energy_error"] = imbalance / self.scale
        self.rows.append(row)
        if self.files is not None:
            if self.header is None:
                self.header = [key for key in row if not key.startswith("_")]
                self.files.write_header(self.header)
            self.files.write_row([float(row[h]) for h in self.header])

    def close(self) -> dict:
        if self.files is not None:
            self.files.close()
        return _history(self.rows)

    # what changes as the run goes: the rest is the model's and the toes' (see __init__)
    SNAPSHOT_SCALARS = ("scale", "peak_tilt", "seated_time", "header")

    def snapshot(self) -> dict:
        """What the recorder gained since its last snapshot, for a checkpoint part
        (:mod:`colonna.fem.checkpoint`): the rows and frames, its running scalars, and the sizes
        of its .part files (bytes; None without files)."""
        n, self.saved_rows = self.saved_rows, len(self.rows)
        files = None if self.files is None else self.files.sizes()
        return {
            "rows": self.rows[n:],
            "frames": self.frames[n:],
            "velocity_frames": self.velocity_frames[n:],
            "contact_frames": self.contact_frames[n:],
            "files": files,
            **{name: getattr(self, name) for name in self.SNAPSHOT_SCALARS},
        }

    def resume(self, snapshots: list[dict], out_dir) -> None:
        """The recorder as it was at the last of ``snapshots`` (all of its run's, in order),
        its .part files in ``out_dir`` cut back to what they held then and appended to."""
        for snap in snapshots:
            for name in ("rows", "frames", "velocity_frames", "contact_frames"):
                getattr(self, name).extend(snap[name])
        last = snapshots[-1]
        for name in self.SNAPSHOT_SCALARS:
            setattr(self, name, last[name])
        self.saved_rows = len(self.rows)
        if out_dir is not None:
            self.files = HistoryFiles.resume(out_dir, last["files"])

    @staticmethod
    def can_resume(snapshot: dict, out_dir) -> bool:
        """Whether the files in ``out_dir`` hold at least what they held at ``snapshot``."""
        return out_dir is None or HistoryFiles.can_resume(out_dir, snapshot["files"])


def _history(rows: list[dict]) -> dict:
    """The history arrays of a run's output rows (the keys not starting with _)."""
    keys = [key for key in rows[0] if not key.startswith("_")] if rows else []
    return {k: np.array([r[k] for r in rows]) for k in keys}


def weak_ground_level(model: Model) -> float:
    """The horizontal ground acceleration (m/s^2) below which the weak-tail stop counts the
    ground as weak: a body's uplift acceleration g tan(alpha_b) (alpha_b = atan(body width /
    height), the rigid body's static threshold; a top load only raises it) over
    :data:`WEAK_TAIL_MARGIN`."""
    mesh = model.mesh
    return model.g * (mesh.width / mesh.n_bodies) / mesh.height / WEAK_TAIL_MARGIN


def weak_tail_start(
    ground, vertical, level: float, g: float, start_time: float, dt: float, steps: int
) -> float:
    """The time (s) from which the ground of a run is weak to its end: the step after the last
    of its ``steps`` step times (start_time + n dt, the times at which the kernel reads the
    motion) at which |a_h| >= level (1 - |a_v| / g) (a vertical acceleration a_v of either
    sign taken as lowering the gravity that holds the column down); ``start_time`` if none."""
    last = -1
    chunk = 1 << 20
    for first in range(0, steps, chunk):
        n = np.arange(first, min(steps, first + chunk))
        times = start_time + dt * n
        horizontal = np.abs(ground.acceleration(times))
        loud = horizontal >= level * (1.0 - np.abs(vertical.acceleration(times)) / g)
        hits = np.flatnonzero(loud)
        if hits.size:
            last = int(n[hits[-1]])
    return start_time + dt * (last + 1)


def _check(row, recorder, ground_end, t, stop_on_overturn, rest_energy=None, weak_from=None):
    """None to go on, or (reason, overturned). ``rest_energy`` (J, the energy at the static
    start): stop a run whose fate is settled (see :func:`iter_batch`); ``weak_from`` (s): also
    during the motion's weak tail, from that time on (iter_batch's ``stop_in_weak_tail``)."""
    thetas = [row["theta_left"], row["theta_right"]]
    # no physical motion has more kinetic energy than the column's whole potential energy
    # plus the work the ground put in; beyond that the integration has gone unstable
    # and a stone column stores only a sliver of that as elastic (or contact) energy
    budget = recorder.potential_scale + abs(row["energy_external_work"])
    stored = row["energy_strain"] + row["energy_contact"] + row["energy_collar"]
    if (
        not all(math.isfinite(v) for v in thetas)
        or not math.isfinite(row["energy_total"])
        or abs(row["energy_kinetic"]) > 10.0 * budget
        or stored > budget
    ):
        return (
            f"{BLOW_UP} at t = {t:.4g} s: the energy grew without bound "
            "(time step too large for the contact or collar stiffness?)",
            False,
        )
    if rest_energy is not None:
        # the energy above the static start, the balance's error its margin: below half the
        # work that tips one body onto its toe, no body can reach a toe while the ground adds
        # nothing (after the motion) or too little to lift a seated column (its weak tail)
        above_rest = row["energy_total"] - rest_energy
        bound = above_rest + abs(row["energy_error"]) * recorder.scale
        settled = bound < 0.5 * recorder.tipping_work
        if settled and t > ground_end and max(abs(th) for th in thetas) < recorder.tipping_angle:
            return (
                f"settled at t = {t:.4g} s: after the ground motion the column, short of "
                f"its toes, holds {above_rest:.3g} J above its rest state, less than half "
                f"the {recorder.tipping_work:.3g} J that tip one body onto its toe: it can "
                "no longer overturn",
                False,
            )
        if (
            settled
            and weak_from is not None
            and weak_from <= t <= ground_end
            and recorder.peak_tilt >= SEATED_TILT * recorder.tipping_angle
            and recorder.seated(t, SEATED_TILT)
        ):
            return (
                f"settled at t = {t:.4g} s: in the ground motion's weak tail (from "
                f"t = {weak_from:.4g} s below 1/{WEAK_TAIL_MARGIN:g} of a body's uplift "
                f"acceleration to its end) the column is seated (every body within "
                f"{SEATED_TILT:g} of its slenderness angle for {recorder.seated_time:.3g} s) with "
                f"{above_rest:.3g} J above its rest state, after rocking to "
                f"{recorder.peak_tilt / recorder.tipping_angle:.3g} of it: it can no longer "
                "lift",
                False,
            )
    if not stop_on_overturn:
        return None
    if max(abs(th) for th in thetas) >= math.pi / 4:
        return (f"overturned: a half rotated past 45 degrees at t = {t:.4g} s", True)
    if t > ground_end and len(recorder.rows) >= 2:  # rows[-1] is this row
        falling = recorder.falling(row, recorder.rows[-2])
        if falling:
            return (
                f"overturned: {falling} is past its toe moving outward after the ground "
                f"motion (t = {t:.4g} s): gravity has no restoring moment left",
                True,
            )
    return None


def _summary(
    model,
    history,
    reason,
    overturned,
    dt,
    step,
    k,
    steps_per_output,
    wall,
    edge_length,
    edge_time,
    static_start,
    collar_state,
    *,
    batch_size: int,
) -> FemRunSummary:
    h = history
    collars = model.collars
    util = [h[f"collar_{i}_utilisation"] for i in range(1, len(collars) + 1)]
    first_yield = None
    for u in util:
        hit = np.nonzero(u >= 1.0)[0]
        if hit.size:
            ty = float(h["t"][hit[0]])
            first_yield = ty if first_yield is None else min(first_yield, ty)
    bodies = [key for key in h if key.startswith("base_normal_force_")]
    reaction0 = float(sum(h[key][0] for key in bodies))
    edge_keys = [key for key in h if key.startswith("edge_stress_")]
    edge_max = max(float(np.max(h[key])) for key in edge_keys)
    strains = (
        collar_strain_summary(
            collars,
            collar_state[:, FIBRE_STRAIN],
            [_fracture_time(h, k) for k in range(1, len(collars) + 1)],
        )
        if collars
        else {}
    )
    error_max = float(np.max(np.abs(h["energy_error"])))
    toe = max(
        (key for key in h if key.startswith("toe_force_")), key=lambda key: float(np.max(h[key]))
    )
    name = toe.removeprefix("toe_force_")
    at_peak = int(np.argmax(h[toe]))
    return FemRunSummary(
        overturned=bool(overturned),
        status=reason,
        max_abs_theta_left=float(np.max(np.abs(h["theta_left"]))),
        max_abs_theta_right=float(np.max(np.abs(h["theta_right"]))),
        collar_max_utilisation=float(max((np.max(u) for u in util), default=0.0)),
        collar_first_yield_time=first_yield,
        edge_stress_max=edge_max,
        edge_stress_ratio=edge_max / model.stone.fc,
        edge_length=edge_length,
        edge_time=edge_time,
        base_reaction_static=reaction0 if static_start else None,
        collar_max_plastic_strain=max(
            (float(np.max(np.abs(h[key]))) for key in h if key.endswith("_plastic_strain")),
            default=0.0,
        ),
        collar_plastic_work=float(collar_state[:, 2].sum()),
        **strains,
        # what the run leaves behind: the crack slip at its end (m)
        crack_slip_residual=float(h["crack_slip_max"][-1]) if "crack_slip_max" in h else 0.0,
        **_crack_force_summary(h),
        **(
            crack_summary(model.cohesive, h, model.stone.KIC)
            if model.cohesive is not None and len(h["t"])
            else {}
        ),
        friction_work_base=float(h["energy_friction_base"][-1]),
        friction_work_crack=float(h["energy_friction_crack"][-1]),
        contact_damping_work=float(h["energy_contact_damping"][-1]),
        contact_penalty_energy_max=float(np.max(h["energy_contact"])),
        toe_contact_length=float(h[f"toe_contact_length_{name}"][at_peak]),
        toe_contact_nodes=int(h[f"toe_contact_nodes_{name}"][at_peak]),
        toe_node_spacing=_toe_spacing(model),
        toe_pressure_max=max(float(np.max(h[k])) for k in h if k.startswith("toe_pressure_")),
        toe_resultant=float(h[f"toe_resultant_{name}"][at_peak]),
        toe_resultant_offset=float(h[f"toe_resultant_offset_{name}"][at_peak]),
        toe_pressure_winkler=_winkler_pressure(model, h),
        bed_stiffness=model.bed.stiffness,
        bed_yield_pressure=model.bed.yield_pressure,
        bed_plastic_work=float(h["energy_bed_plastic"][-1]) if len(h["t"]) else 0.0,
        top_load=model.top_load,
        energy_error_max=error_max,
        energy_error_limit=ENERGY_ERROR_LIMIT,
        energy_reliable=bool(error_max <= ENERGY_ERROR_LIMIT) and not reason.startswith(BLOW_UP),
        dt=dt,
        dt_critical=step.critical,
        dt_critical_elastic=step.critical_elastic,
        stable_step_reduction_by_contact=step.contact_reduction,
        penalty_base_mean=float(np.mean(model.base_kn)),
        steps=int(k * steps_per_output),
        dofs=int(model.n_dofs),
        wall_seconds=wall,
        t_end=float(h["t"][-1]),
        batch_size=batch_size,
    )


def _crack_force_summary(history) -> dict:
    """The crack's sampled normal force (N): mean over the run and over the samples in
    contact, largest, and the fraction of samples in contact; nothing for a solid column."""
    if "crack_normal_force" not in history:
        return {}
    force = history["crack_normal_force"]
    closed = force > 0.0
    return {
        "crack_normal_force_mean": float(force.mean()),
        "crack_normal_force_mean_closed": float(force[closed].mean()) if closed.any() else 0.0,
        "crack_normal_force_max": float(force.max()),
        "crack_closed_fraction": float(closed.mean()),
    }


def _winkler_pressure(model, history) -> float:
    """The largest toe pressure of a rigid base on the bed (Pa) over the output samples and the
    bodies, from each body's base normal force and rigid tilt
    (:func:`colonna.fem.bed.winkler_toe_pressure`, at most the yield pressure of a bed that
    yields)."""
    from .bed import winkler_toe_pressure

    mesh = model.mesh
    tilts = ["theta_left", "theta_right"][: mesh.n_bodies]
    return max(
        float(
            np.max(
                winkler_toe_pressure(
                    history[f"base_normal_force_{b + 1}"],
                    history[tilt],
                    model.bed.stiffness,
                    model.thickness,
                    mesh.width / mesh.n_bodies,
                    model.bed.yield_pressure,
                )
            )
        )
        for b, tilt in enumerate(tilts)
    )


def _toe_spacing(model) -> float:
    """The spacing of the base nodes at the outer left toe (m)."""
    xs = model.mesh.points[0, model.mesh.base_nodes[0]]
    return float(abs(xs[1] - xs[0]))


def _fracture_time(history, k) -> float | None:
    """The first output time at which collar k (from 1) is recorded broken, None if never."""
    broken = np.nonzero(history.get(f"collar_{k}_fractured", np.zeros(0)) > 0.0)[0]
    return float(history["t"][broken[0]]) if broken.size else None

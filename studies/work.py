"""The work of FEM runs, bounded before they run: the work a study's FEM runs ask for
(:func:`fem_work`: state-steps, node-steps, memory, each run for the estimate of time,
:mod:`studies.cost`) and the limits it is held to (:func:`require_bounded_work`: 2 h of CPU
unless --long, half this machine's memory).
"""

from __future__ import annotations

import itertools
import math
import os
from collections.abc import Iterable
from dataclasses import dataclass

from ..core.errors import InputError
from .fem_study import FemStudy
from .models import MODEL_KEYS, build
from .units import duration_text as _hours

# CPU seconds to advance one node of a mesh by one explicit time step, for one state (a replica
# or a grid point), on the machine of the README's timings, in a batch (the work limit's unit:
# the estimates of time use this machine's calibrated cost model, studies.cost)
NODE_STEP_SECONDS = 25e-9
WORK_LIMIT_SECONDS = 2 * 3600.0  # the CPU time a study (or colonna fem) may ask for, unless --long
# what one state keeps per output row (measured: 54.5 kB on 1,512 nodes): its displacement and
# velocity frames, 4 numbers a node, and the row's numbers and contact state
OUTPUT_BYTES_PER_NODE = 32
OUTPUT_ROW_BYTES = 8000
STATE_BYTES_PER_NODE = 400  # a state's own arrays in the kernel (positions, velocities, forces)


@dataclass(frozen=True)
class FemRun:
    """``states`` FEM runs of one model advanced together: its ``nodes``, ``steps`` and
    ``outputs`` (rows), the ``case`` they are part of (a label: the runs of one case run one
    after the other, cases side by side) and its ``stage`` (the stages of a study run one after
    the other). A case without FEM runs (a rigid model's) is a FemRun of no states and its
    ``other_seconds``."""

    nodes: int
    steps: float
    outputs: float
    states: int
    case: str
    stage: int = 0
    other_seconds: float = 0.0  # CPU seconds of the case's work outside the FEM (rigid models)

    @property
    def seconds(self) -> float:
        """CPU seconds on this machine (:func:`studies.cost.cost_model`)."""
        from .cost import cost_model

        fem = cost_model().run_seconds(self.nodes, self.steps, self.outputs, self.states)
        return fem + self.other_seconds


@dataclass(frozen=True)
class FemWork:
    """What FEM runs ask for, estimated before they run: ``state_steps`` (time steps x states,
    a state being a replica or a grid point), ``node_steps`` (each state-step x the nodes of its
    mesh), the largest mesh's ``nodes``, ``memory`` (bytes) of the largest run, its states
    held at once, and the ``runs`` themselves (:class:`FemRun`) for their time. Runs add up
    (``+``)."""

    state_steps: float = 0.0
    node_steps: float = 0.0
    nodes: int = 0
    memory: float = 0.0
    runs: tuple[FemRun, ...] = ()

    @property
    def seconds(self) -> float:
        """CPU seconds at :data:`NODE_STEP_SECONDS` a node-step (the work limit's measure)."""
        return self.node_steps * NODE_STEP_SECONDS

    @property
    def cpu_seconds(self) -> float:
        """CPU seconds of the runs on this machine (its calibrated cost model)."""
        return sum(run.seconds for run in self.runs)

    def wall_seconds(self, workers: int) -> float:
        """Wall seconds of the runs on ``workers`` cores: per stage, its cases dealt as the
        executor deals them (the costliest first, each to the least loaded worker), the
        stages one after the other."""
        total = 0.0
        for stage in sorted({run.stage for run in self.runs}):
            cases: dict[str, float] = {}
            for run in self.runs:
                if run.stage == stage:
                    cases[run.case] = cases.get(run.case, 0.0) + run.seconds
            load = [0.0] * max(1, workers)
            for seconds in sorted(cases.values(), reverse=True):
                load[load.index(min(load))] += seconds
            total += max(load)
        return total

    def __add__(self, other: FemWork) -> FemWork:
        return FemWork(
            self.state_steps + other.state_steps,
            self.node_steps + other.node_steps,
            max(self.nodes, other.nodes),
            max(self.memory, other.memory),
            self.runs + other.runs,
        )


def fem_work(
    study: FemStudy,
    states: int = 1,
    *,
    held: int | None = None,
    models: dict | None = None,
    case: str | None = None,
    stage: int = 0,
    until: float | None = None,
) -> FemWork:
    """The work of ``states`` FEM runs of ``study`` over its whole duration (its replicas, or
    grid points that share its model and duration; ``held`` of them at once, default all), as
    :func:`run_fem` would run them: the model is built for its nodes and stable step (once per
    model in ``models``, a cache shared by the runs of a study: about 0.1 s for the default
    column). ``case``: the case they are part of (default: a case of their own), ``stage``
    the study's stage (:class:`FemRun`). A run that stops early (overturned, settled) costs
    less: ``until`` (s), where the runs are expected to stop, bounds the time they are
    estimated to take (not their memory, which is bounded for the whole duration)."""
    key = tuple(getattr(study, k) for k in MODEL_KEYS)
    if models is None or key not in models:
        from ..fem.model import stable_time_step

        model = build(study)
        dt = study.dt if study.dt is not None else stable_time_step(model, study.safety).dt
        found = (model.n_dofs // 2, dt)
        if models is not None:
            models[key] = found
    else:
        found = models[key]
    nodes, dt = found
    interval = study.output_interval or study.duration / 400.0
    per_output = max(1.0, round(interval / dt))
    outputs = math.ceil(study.duration / (per_output * dt))
    steps = float(outputs) * per_output
    per_state = (
        outputs * (OUTPUT_BYTES_PER_NODE * nodes + OUTPUT_ROW_BYTES)
        + STATE_BYTES_PER_NODE * nodes
        + 16.0 * per_output  # the ground accelerations of an output interval
        + 32.0 * max(1.0, round(study.edge_time / dt))  # the toe stresses' averaging window
    )
    at_once = states if held is None else min(states, held)
    share = 1.0 if until is None else min(1.0, max(0.0, until) / study.duration)
    run = FemRun(
        nodes,
        steps * share,
        outputs * share,
        states,
        case if case is not None else f"run-{next(_RUN_LABELS)}",
        stage,
    )
    return FemWork(steps * states, steps * states * nodes, nodes, at_once * per_state, (run,))


_RUN_LABELS = itertools.count()


def ensembles_work(studies: Iterable[FemStudy]) -> FemWork:
    """The work of each of ``studies``' FEM runs with its replicas, one study after the
    other (the variants of a sweep: extents, meshes, solid or cracked), each model built once
    (:func:`fem_work`)."""
    work = FemWork()
    models: dict = {}
    for study in studies:
        work += fem_work(study, study.replicas, models=models)
    return work


def memory_limit() -> float:
    """The memory (bytes) one FEM run may ask for: half this machine's (16 GiB where it cannot
    be read)."""
    try:
        return 0.5 * os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    except (AttributeError, ValueError, OSError):
        return 16.0 * 2**30


def require_bounded_work(
    work: FemWork, *, long: bool = False, what: str = "this study", fewer: str = ""
) -> None:
    """An InputError of one line where ``work`` is more than :data:`WORK_LIMIT_SECONDS` of CPU
    (unless ``long``: the user asked for it) or more memory than :func:`memory_limit` (always:
    it would not fit), giving the estimate and what to change (``fewer``: the study's own ways
    to ask for less, "fewer replicas")."""
    if work.seconds > WORK_LIMIT_SECONDS and not long:
        raise InputError(
            f"{what} asks for {work.state_steps:.2g} state-steps (time steps x runs and "
            f"replicas) on up to {work.nodes:,} nodes, about {_hours(work.seconds)} of CPU at "
            f"{NODE_STEP_SECONDS * 1e9:g} ns a node-step (limit {_hours(WORK_LIMIT_SECONDS)}): "
            f"shorten [run] duration, coarsen [mesh] size{fewer}, or pass --long to run it "
            "anyway"
        )
    limit = memory_limit()
    if work.memory > limit:
        raise InputError(
            f"{what} asks for about {work.memory / 2**30:.3g} GiB of memory for one FEM run's "
            f"history and states (at most {limit / 2**30:.3g} GiB, half of this machine's): "
            "lengthen [run] output_interval, shorten [run] duration or coarsen [mesh] size"
        )

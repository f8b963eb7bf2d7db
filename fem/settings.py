"""The FEM run's parameter objects: how it steps, stops and records (:class:`FemSettings`) and
how it starts (:class:`FemStart`), beside the ground's :class:`colonna.core.motion.Motion`.

``run(model, motion, settings, start)`` (:mod:`colonna.fem.solver`) takes these few typed
objects instead of a score of keywords; each field checks what needs no model here, the
solver what depends on the model (the stable step, a body's width, the mesh's size).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..core.errors import InputError, require_positive, require_range
from ..core.motion import Release

EDGE_TIME = 2.5e-4  # s: default averaging time of the toe stress (FemSettings.edge_time)
REPLICAS = 8  # default size of an ensemble (Replicas.count; [run] replicas)
# replicas start from positions moved by this fraction of the column height (standard normal
# offsets): far below anything physical, far above the last bit of a position
REPLICA_PERTURBATION = 1e-12


@dataclass(frozen=True, kw_only=True)
class FemSettings:
    """How a FEM run steps, records and stops (every field has its default).

    ``dt`` (s): the time step, set by hand but not above the stable step (None: the stable
    step, :func:`colonna.fem.model.stable_time_step`); ``safety``: the stable step's fraction of
    the critical one; ``check_dt``: False lifts the guard on a ``dt`` above the stable step
    (for tests of the estimate). ``output_interval`` (s): time between recorded outputs (None:
    1/400 of the duration, which the runs of a batch must then share). ``edge_length`` (m):
    the length from each outer toe the toe stress averages over (None: a tenth of a body's
    width); ``edge_time`` (s, in [0, 0.01]): the time it averages over (None:
    :data:`EDGE_TIME`). ``stop_on_overturn``: end a run once it overturns.
    ``stop_when_settled``: a run from the static state stops once its fate is settled (after
    the ground motion, every body short of its toe and too little energy left to tip one onto
    it: :func:`colonna.fem.solver.iter_batch`); ``stop_in_weak_tail`` (with it): also in the
    motion's weak tail, once the column is seated and the ground cannot lift it.
    ``progress``: a progress bar on a terminal."""

    dt: float | None = None
    safety: float = 0.9
    check_dt: bool = True
    output_interval: float | None = None
    edge_length: float | None = None
    edge_time: float | None = None
    stop_on_overturn: bool = True
    stop_when_settled: bool = False
    stop_in_weak_tail: bool = False
    progress: bool = True

    def __post_init__(self) -> None:
        if self.dt is not None:
            require_positive("run dt (s)", self.dt)
        require_positive("run safety", self.safety)
        if self.output_interval is not None:
            require_positive("run output_interval (s)", self.output_interval)
        if self.edge_length is not None:
            require_positive("edge_length (m)", self.edge_length)
        if self.edge_time is not None:
            require_range(
                "edge_time (s)",
                self.edge_time,
                0.0,
                0.01,
                closed_low=True,
                closed_high=True,
                range_text="[0, 0.01] s",
            )


@dataclass(frozen=True, kw_only=True)
class FemStart(Release):
    """How a FEM run starts: a :class:`~colonna.core.motion.Release` (``tilt``, rad in (-pi/4,
    pi/4), and ``angular_velocity``, rad/s: the column turned rigidly about the outer toe it
    tips on, its elastic state the upright static state turned with it; both zero: the static
    state under gravity) and more.

    ``state`` = (x, v): node positions and velocities (m, m/s; flat, 2 per node) to start from
    instead of the static state, at ``time`` (s; the ground motion is read at time + t): a
    restart, for instance of another mesh's state transferred by
    :func:`colonna.fem.transfer.transfer_state`. ``contact``: the contact state it starts
    with (zero if left out; only with ``state``), a dict as in ``FemResult.contact_frames`` or
    from :func:`colonna.fem.transfer.transfer_contact`: base_ft, base_fc (tangential and
    filtered normal force per base node, N), crack_ft, crack_fc (lists, one array per crack
    pass). ``velocity``: nodal velocities (n_nodes, 2) added at t = 0."""

    state: tuple | None = None
    contact: dict | None = None
    velocity: np.ndarray | None = None
    time: float = 0.0

    def __post_init__(self) -> None:
        require_range(
            "run start.tilt (rad)",
            self.tilt,
            -0.25 * math.pi,
            0.25 * math.pi,
            range_text="(-pi/4, pi/4)",
        )
        if not math.isfinite(self.angular_velocity):
            raise InputError(
                f"run start.angular_velocity = {self.angular_velocity!r} rad/s must be finite"
            )
        if not math.isfinite(self.time):
            raise InputError(f"run start.time = {self.time!r} s must be finite")
        if self.contact is not None and self.state is None:
            raise InputError("run start.contact needs start.state (a restart)")
        if self.state is not None and not self.at_rest:
            raise InputError("run start: give either state or tilt / angular_velocity, not both")

    @property
    def static(self) -> bool:
        """True for a run from the static state under gravity (no state, release or velocity)."""
        return self.state is None and self.at_rest and self.velocity is None

    @classmethod
    def of(cls, start: Release) -> FemStart:
        """``start`` as a FemStart (a plain :class:`~colonna.core.motion.Release` is one with
        no more than its tilt and angular velocity)."""
        if isinstance(start, FemStart):
            return start
        return cls(tilt=start.tilt, angular_velocity=start.angular_velocity)


@dataclass(frozen=True)
class Replicas:
    """An ensemble of :func:`colonna.fem.solver.run_ensemble`: ``count`` runs that differ only
    at round-off level, replica r's start moved by ``perturbation`` (relative, in [0, 1e-6])
    x the column height x standard normal numbers (replica 0 unperturbed); ``slots``: how many
    advance at once (None: all; :func:`colonna.fem.solver.iter_batch`)."""

    count: int = REPLICAS
    perturbation: float = REPLICA_PERTURBATION
    slots: int | None = None

    def __post_init__(self) -> None:
        if int(self.count) < 1:
            raise InputError(f"run replicas = {int(self.count)} must be at least 1")
        require_range(
            "replica perturbation (relative)",
            self.perturbation,
            0.0,
            1e-6,
            closed_low=True,
            closed_high=True,
            range_text="[0, 1e-6]",
        )


AT_REST = FemStart()  # the default start: the static state under gravity
DEFAULT_SETTINGS = FemSettings()

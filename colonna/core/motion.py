"""What a run is driven by and how it starts, shared by the rigid and finite-element solvers.

The solvers' public run functions take these few typed objects instead of a dozen keywords
(docs/layout.md, "Parameter objects"): :class:`Motion` is the ground's part (horizontal and
vertical ground acceleration, the run's length), :class:`Release` the column's start (upright at
rest, or released tilted and spinning about the toe it tips on). The FEM's fuller start (a
state carried from another mesh) extends :class:`Release` in :mod:`colonna.fem.solver`.
"""

from __future__ import annotations

from dataclasses import dataclass

from colonna.core.ground import NO_MOTION, GroundMotion


@dataclass(frozen=True)
class Motion:
    """The ground's part of a run: ``ground``, the horizontal ground acceleration (a pulse, a
    record or NoMotion: :mod:`colonna.core.ground`); ``vertical``, the vertical one (upward
    positive); ``duration``, how long the run lasts (s; None: the solver's default, the end of
    the ground motion plus its free-rocking tail)."""

    ground: GroundMotion = NO_MOTION
    duration: float | None = None
    vertical: GroundMotion = NO_MOTION


@dataclass(frozen=True)
class Release:
    """How a run starts: at rest upright (the default), or released at t = 0 turned rigidly
    by ``tilt`` (rad, > 0 toward +x) about the outer toe it tips on, spinning about it at
    ``angular_velocity`` (rad/s)."""

    tilt: float = 0.0
    angular_velocity: float = 0.0

    @property
    def at_rest(self) -> bool:
        """True for the upright column at rest (the static start)."""
        return self.tilt == 0.0 and self.angular_velocity == 0.0

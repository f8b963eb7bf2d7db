"""Mesh convergence of the toe stress by local refinement over the impact that produces it.

The base-edge stress (contact pressure averaged over ``edge_length`` from a toe) peaks when a
toe lands. Resolving it needs elements a few times smaller than ``edge_length`` at the toe,
which a whole run on a uniformly finer mesh cannot afford (explicit steps shrink with the
elements). So the run is repeated only over the window around that impact, on meshes whose
toe zones are refined 1, 2, 4 and 8 times (:func:`colonna.meshes.column_mesh`'s
``toe_refinement``), each started from the coarse run's state at the window's start, handed
over by :func:`colonna.fem.transfer.transfer_state` and
:func:`colonna.fem.transfer.transfer_contact`. Refinement 1 restarts the original mesh: it
checks the hand-over (it must give the original run's peak back).

What the refinement shows for the default column: the stress averaged over ``edge_length``
and ``edge_time`` rises from the unrefined mesh to the refined ones and then stays within a band
of about 10 % without settling monotonically. The landing is a burst of contact chatter (node
by node bounces of the penalty contact) whose details differ between meshes. So the quoted
value is the band's upper end (``stress_bound``), or the Richardson estimate where the peaks
do converge monotonically toward a larger value (a column pivoting on one toe under a top
load), with the band's width or the estimated error as the mesh uncertainty.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from ..core.errors import InputError
from ..core.ground import NO_MOTION, GroundMotion
from ..core.motion import Motion
from ..meshes.column import ColumnMesh
from .convergence import convergence_table
from .model import Loads, build_model
from .output import flat_start
from .partial_crack import Crack
from .settings import FemSettings, FemStart
from .solver import FemResult, run

LEAD_TIME = 0.01  # s before the toe's last airborne output time at which the window opens
TAIL_TIME = 0.01  # s after the peak at which it closes
# s before the peak at which the window opens where its toe never lifted (no landing to open
# before): a state carried onto a refined mesh while its toe is loaded overshoots, and on a
# granite column the overshoot died out over about 0.2 s (refined peaks 45 % high handed over
# 30 ms before the peak, 3 % at 0.15 s, none at 0.2 s: docs/speed.md)
HANDOVER_SETTLE = 0.2
REFINEMENTS = (1, 2, 4, 8)


def peak_toe(history: dict) -> tuple[str, int]:
    """The toe (edge_stress_* key suffix) and output index of the largest base-edge stress."""
    keys = [k for k in history if k.startswith("edge_stress_")]
    if not keys:
        raise InputError("toe stress: the history has no edge_stress_* columns")
    key = max(keys, key=lambda k: float(np.max(history[k])))
    return key.removeprefix("edge_stress_"), int(np.argmax(history[key]))


def impact_window(history: dict, lead: float = LEAD_TIME, tail: float = TAIL_TIME):
    """(toe, t_start, t_end, t_peak): the window around the landing that gives the peak toe
    stress. It opens ``lead`` seconds before the last output time at which that toe carried no
    load (the landing begins after it, and the refined runs start with the toe unloaded), or,
    if it never lifted, :data:`HANDOVER_SETTLE` before the peak (or at the run's start)."""
    toe, i = peak_toe(history)
    t, stress = history["t"], history[f"edge_stress_{toe}"]
    airborne = np.nonzero(stress[:i] <= 0.0)[0]
    if airborne.size:
        start = float(t[airborne[-1]]) - lead
    else:  # loaded throughout: the hand-over's overshoot must die out before the peak
        start = float(t[i]) - HANDOVER_SETTLE
    return toe, max(float(t[0]), start), float(t[i]) + tail, float(t[i])


def check_refinements(refinements) -> list[int]:
    """The refinements as ints: 1, then at least two doublings (an :class:`InputError` else)."""
    refinements = [int(r) for r in refinements]
    if (
        len(refinements) < 3
        or refinements[0] != 1
        or any(b != 2 * a for a, b in zip(refinements, refinements[1:]))
    ):
        raise InputError(
            f"toe refinements = {refinements}: need 1 and then at least two "
            "doublings (1, 2, 4, ...)"
        )
    return refinements


def refinement_start(result: FemResult, lead: float = LEAD_TIME, tail: float = TAIL_TIME) -> dict:
    """Where the refined runs start: the impact window of ``result``'s history
    (:func:`impact_window`, its start moved to the output time nearest it) and ``result``'s
    state there. Returns toe, t_start, t_end, t_peak (s); interval (s, the output interval);
    original_peak (Pa, the run's own peak over the window); edge_length (m) and edge_time (s);
    displacement and velocity (n_nodes, 2) and contact (a ``contact_frames`` entry) at
    t_start. Plain arrays and numbers: it can be saved (:func:`colonna.fem.output.write_start`)
    and the windows run elsewhere (:func:`refine_window`)."""
    history = result.history
    toe, t_start, t_end, t_peak = impact_window(history, lead, tail)
    times = np.array([t for t, _ in result.displacement_frames])
    k = int(np.argmin(np.abs(times - t_start)))
    t_start = float(times[k])
    interval = float(np.median(np.diff(history["t"])))
    inside = (history["t"] > t_start) & (history["t"] <= t_end + 0.5 * interval)
    original = max(
        float(np.max(history[key][inside])) for key in history if key.startswith("edge_stress_")
    )
    return {
        "toe": toe,
        "t_start": t_start,
        "t_end": t_end,
        "t_peak": t_peak,
        "interval": interval,
        "original_peak": original,
        "edge_length": float(result.summary["edge_length"]),
        "edge_time": float(result.summary["edge_time"]),
        "displacement": np.asarray(result.displacement_frames[k][1]),
        "velocity": np.asarray(result.velocity_frames[k][1]),
        "contact": result.contact_frames[k][1],
    }


def start_digest(start: dict) -> str:
    """SHA-256 of a ``start`` (:func:`refinement_start`): of its numbers and of its arrays'
    bytes, shapes and types, in a fixed order. The same state gives the same digest, however
    often it is saved."""
    import hashlib

    digest = hashlib.sha256()
    flat = flat_start(start)
    for key in sorted(flat):
        value = flat[key]
        digest.update(f"{key}:{value.dtype.str}:{value.shape}:".encode())
        digest.update(np.ascontiguousarray(value).tobytes())
    return digest.hexdigest()


def model_on(model, mesh: ColumnMesh):
    """``model`` (its stone, thickness, collars, contact, gravity, top load, bed and partial
    crack) built on another ``mesh``: a toe window's refined model."""
    return build_model(
        mesh,
        model.stone,
        model.thickness,
        model.collars,
        model.contact,
        Loads(model.g, model.top_load),
        model.bed,
        # a partial crack's ends and depth
        None if model.cohesive is None else Crack(model.cohesive.crack, model.cohesive.depth),
    )


def refine_window(
    model,
    start: dict,
    mesh: ColumnMesh,
    ground,
    *,
    vertical: GroundMotion = NO_MOTION,
    progress: bool = False,
) -> dict:
    """One refined run over the window of ``start`` (:func:`refinement_start` of a run of
    ``model``) on ``mesh``: restarted from that state (:func:`colonna.fem.transfer.transfer_state`
    and :func:`~colonna.fem.transfer.transfer_contact`) under ``ground`` and ``vertical``.
    Returns peaks_by_toe (Pa, the largest toe stress of each toe over the window), dofs, steps
    and dt (s)."""
    from .transfer import transfer_contact, transfer_state

    fine = model_on(model, mesh)
    t_start, t_end = start["t_start"], start["t_end"]
    window = run(
        fine,
        Motion(ground, t_end - t_start, vertical),
        FemSettings(
            output_interval=start["interval"],
            edge_length=start["edge_length"],
            edge_time=start["edge_time"],
            progress=progress,
            stop_on_overturn=False,
        ),
        FemStart(
            state=transfer_state(model.mesh, mesh, start["displacement"], start["velocity"]),
            contact=transfer_contact(model, fine, start["contact"]),
            time=t_start,
        ),
    )
    if window.summary["status"] != "completed":
        raise InputError(
            f"toe refinement of a {fine.n_dofs}-dof mesh: the restarted run stopped: "
            f"{window.summary['status']}"
        )
    return {
        "peaks_by_toe": {
            key.removeprefix("edge_stress_"): float(np.max(window.history[key]))
            for key in window.history
            if key.startswith("edge_stress_")
        },
        "dofs": int(fine.n_dofs),
        "steps": int(window.summary["steps"]),
        "dt": float(window.summary["dt"]),
    }


def refinement_summary(start: dict, refinements, windows: list[dict]) -> dict:
    """What the refinement shows, from the windows (:func:`refine_window`, one per refinement,
    in the order of ``refinements``) restarted from ``start``.

    Returns (stresses in Pa): toe, t_start, t_end, t_peak; refinements, dofs, steps, dt;
    peaks_by_toe (one dict per refinement), peaks (the largest over the toes);
    handover_error: refinement 1 against the original run over the same window (relative);
    stress_bound: the largest peak of the refined meshes (r > 1), spread: their
    (max - min) / max; :func:`convergence_table` of the last three peaks; stress_estimate:
    the quoted value, the larger of stress_bound and the Richardson estimate (where the peaks
    converge monotonically), uncertainty: the larger of the spread and the finest mesh's
    estimated relative error."""
    refinements = check_refinements(refinements)
    by_toe = [w["peaks_by_toe"] for w in windows]
    peaks = [max(p.values()) for p in by_toe]
    refined = peaks[1:]
    table = convergence_table(peaks, 2.0)
    # the quoted value: the refined meshes' largest, or the Richardson estimate where the
    # peaks converge monotonically toward a larger one; its uncertainty the larger of their
    # spread and the finest mesh's estimated error
    spread = (max(refined) - min(refined)) / max(refined)
    estimate, uncertainty = max(refined), spread
    if math.isfinite(table["richardson"]) and table["richardson"] > 0.0:
        estimate = max(estimate, table["richardson"])
        uncertainty = max(uncertainty, table["fine_relative_error"])
    original = start["original_peak"]
    return {
        "toe": start["toe"],
        "t_start": start["t_start"],
        "t_end": start["t_end"],
        "t_peak": start["t_peak"],
        "edge_length": start["edge_length"],
        "edge_time": start["edge_time"],
        "refinements": refinements,
        "dofs": [w["dofs"] for w in windows],
        "steps": [w["steps"] for w in windows],
        "dt": [w["dt"] for w in windows],
        "peaks_by_toe": by_toe,
        "peaks": peaks,
        "original_peak": original,
        "handover_error": abs(peaks[0] - original) / original if original > 0 else 0.0,
        "stress_bound": max(refined),
        "spread": spread,
        "stress_estimate": estimate,
        "uncertainty": uncertainty,
        **table,
    }


def toe_stress_refinement(
    result: FemResult,
    ground,
    mesh_for: Callable[[int], ColumnMesh],
    refinements=REFINEMENTS,
    *,
    lead: float = LEAD_TIME,
    tail: float = TAIL_TIME,
    progress: bool = False,
    vertical: GroundMotion = NO_MOTION,
) -> dict:
    """Peak toe stress over the impact window on meshes ``mesh_for(r)`` for r in
    ``refinements`` (1, then doubling), each restarted from ``result``'s state, under the
    same ``ground`` and ``vertical`` motions as the run that gave ``result``: in one process,
    :func:`refinement_start`, :func:`refine_window` for each refinement, and
    :func:`refinement_summary` (which says what it returns). The cross-check runs the windows
    as cases of their own, on as many workers as there are."""
    refinements = check_refinements(refinements)
    start = refinement_start(result, lead, tail)
    windows = [
        refine_window(
            result.model, start, mesh_for(r), ground, vertical=vertical, progress=progress
        )
        for r in refinements
    ]
    return refinement_summary(start, refinements, windows)

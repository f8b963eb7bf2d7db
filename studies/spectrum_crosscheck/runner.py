"""The cross-check over the pulse space: one column, a grid of pulses Omega/p x a_p/a_uplift, each
run through the FEM model, the rigid multibody model and the paper's SDOF model.

The study file is a cross-check file (column, stone, collars, contact, mesh, run) whose [ground]
gives the pulse shape (sine or cosine), plus a [grid] table:

    [grid]
    omega_ratios = [1.0, 8.0]       # range of Omega / p (p of the rocking half), inclusive
    amplitude_ratios = [1.2, 6.0]   # range of a_p / (g tan alpha) of the rocking half
    points = [6, 5]                 # number of omega ratios x number of amplitude ratios

With ``pulse = "record"`` (and ``record``, a file) the grid runs the record instead of a pulse:
the amplitude axis scales it to a peak of amplitude_ratio x a_uplift, and the other axis,
``time_scales = [start, stop]`` in place of ``omega_ratios``, compresses its time by that factor
(2: twice as fast, its frequencies doubled), as the omega ratio moves a pulse.

Each grid point is one case of :mod:`studies.executor` (local processes or Dask, saved as it
completes, resumable). Its FEM run writes no field files: a grid point keeps only its numbers.
Maps are 2D lists with rows following the amplitude ratios and columns the omega ratios, as in
the rigid spectra.
"""

from __future__ import annotations

import dataclasses
import time
from pathlib import Path

import numpy as np

from ...core.errors import InputError
from ...fem.ensemble import NO, YES
from ...rigid.impacts import half_cycles
from .. import schema
from ..executor import RunOptions, run_cases
from ..fem_study import FemStudy, case_of, from_spec, study_of_case
from ..guard import check_fem_results, halved_steps
from ..models import run_multibody, run_sdof
from ..outcome import QUESTIONS, count_answer, grid_outcome, not_assessed, outcome
from ..output import write_json
from ..study import Study
from ..work import FemWork
from ..work import fem_work as estimate_work
from .schema import Grid

DEFAULT_X_RANGE = {"omega_ratios": [1.0, 8.0], "time_scales": [0.5, 2.0]}
MODES = ("safe", "after-impact", "without-impact")


def parse_grid_size(text: str) -> tuple[int, int]:
    """'NxM' -> (N omega ratios, M amplitude ratios), each >= 1."""
    try:
        n, m = (int(part) for part in text.lower().split("x"))
    except ValueError:
        raise InputError(
            f"--grid = {text!r} is not of the form NxM (omega ratios x amplitude ratios, e.g. 3x3)"
        ) from None
    if n < 1 or m < 1:
        raise InputError(f"--grid = {text!r}: both counts must be >= 1")
    return n, m


def grid_of(
    grid: Grid,
    size: tuple[int, int] | None = None,
    record: bool = False,
    source: str = "study",
):
    """(omega ratios, or time scales for a record; amplitude ratios) of the study's validated
    [grid] (:class:`.schema.Grid`), ``size`` overriding the counts."""
    x_key = "time_scales" if record else "omega_ratios"
    other = "omega_ratios" if record else "time_scales"
    if getattr(grid, other) is not None:
        raise InputError(
            f"{source}: grid.{other} goes with "
            + ("a pulse" if record else 'ground.pulse = "record"')
            + f": use grid.{x_key}"
        )
    x_range = getattr(grid, x_key) or DEFAULT_X_RANGE[x_key]
    points = grid.points if size is None else list(size)
    (x_low, x_high), (a_low, a_high) = x_range, grid.amplitude_ratios
    return np.linspace(x_low, x_high, points[0]), np.linspace(a_low, a_high, points[1])


def grid_point_case(case: dict, directory: str) -> dict:
    """One pulse through the FEM, multibody and SDOF models, alone: modes and the FEM's
    safety numbers (what :func:`grid_points_case` gives for the same point in a batch)."""
    from ..models import run_fem

    study = _point_study(case)
    return _point_result(case, study, run_fem(study, replicas=1)[0])


def grid_points_case(cases: list[dict], directories: list[str]):
    """Grid points through the FEM, multibody and SDOF models, the FEM runs of the points that
    share a model advancing together on the batched kernel (:func:`studies.models.iter_fem`,
    a full group of the kernel per pass through the stiffness; a pulse that ends leaves its
    slot to the next). Yields (index in cases, result) as each point completes; a point's
    result is the same as :func:`grid_point_case`'s for it alone."""
    from ..models import iter_fem

    studies = [_point_study(case) for case in cases]
    for index, fem in iter_fem(studies):
        yield index, _point_result(cases[index], studies[index], fem)


def _point_study(case: dict):
    """A grid point's study; its FEM run stops once the point's outcome is settled."""
    return dataclasses.replace(study_of_case(case), stop_when_settled=True)


def _point_result(case: dict, study, fem) -> dict:
    """A grid point's result from its FEM run; the multibody and SDOF runs of its pulse."""
    s = fem.summary
    fem_impacts = max(
        _impacts_before(fem.history, key, s["t_end"]) for key in ("theta_left", "theta_right")
    )
    mb = run_multibody(study)
    sdof = run_sdof(study)
    return {
        "omega_ratio": case["omega_ratio"],
        "amplitude_ratio": case["amplitude_ratio"],
        "mode_fem": _mode(s["overturned"], fem_impacts),
        "mode_multibody": mb.mode,
        "mode_sdof": sdof.mode,
        "peak_fem": max(s["max_abs_theta_left"], s["max_abs_theta_right"]),
        "peak_multibody": max(
            mb.summary()["max_abs_theta_left"], mb.summary()["max_abs_theta_right"]
        ),
        "collar_utilisation_fem": s["collar_max_utilisation"],
        "toe_ratio_fem": s["edge_stress_ratio"],
        "energy_error_fem": s["energy_error_max"],
        "status_fem": s["status"],
        # a point rerun at a halved step (fem.solver.STEP_HALVINGS) and why; its step
        "step_halvings": int(s.get("step_halvings") or 0),
        "step_note": s.get("step_note"),
        "dt": s["dt"],
        "fem_seconds": s["wall_seconds"],
        "fem_steps": s["steps"],
        # the ground motion this point ran: its peak (m/s^2) and when it ends (s)
        "ground_peak": float(
            np.max(
                np.abs(study.ground.acceleration(np.linspace(0.0, study.ground.end_time, 20001)))
            )
        ),
        "ground_end_time": float(study.ground.end_time),
    }


def _impacts_before(history: dict, key: str, t_end: float) -> int:
    """Changes of sign of a half's rotation (impacts) in the FEM history, ignoring wiggles."""
    theta = history[key]
    return int(np.sum(history["t"][half_cycles(theta)] <= t_end)) if theta.size else 0


def _mode(overturned: bool, impacts: int) -> str:
    if not overturned:
        return "safe"
    return "after-impact" if impacts > 0 else "without-impact"


class Points:
    """The grid points of a spectrum cross-check study: each point's FEM study, the study
    with the point's pulse (or the record scaled and played faster), built from the validated
    file without validating it again. ``kind``: the pulse's shape, or "record"."""

    def __init__(self, study: Study):
        source = study.source
        ground = study.spec.ground
        self.kind = ground.pulse
        if self.kind not in ("sine", "cosine", "record"):
            raise InputError(
                f"{source}: ground.pulse = {self.kind!r}: the spectrum cross-check needs "
                "'sine', 'cosine' or 'record' (the grid sets its amplitude and "
                "frequency or time scale)"
            )
        self.record_file = ground.record if self.kind == "record" else None
        if self.kind == "record" and self.record_file is None:
            raise InputError(f"{source}: ground.record (file) is required with pulse = 'record'")
        given = sorted(set(study.data.get("ground", {})) - {"pulse", "record"})
        if given:
            raise InputError(
                f"{source}: ground.{given[0]} is set by the grid of a "
                "spectrum cross-check: leave it out"
            )
        self.study = study
        self.spec = study.spec
        self.grid((2, 2))  # its [grid] fits its motion, before a record is read
        if self.kind == "record":  # the study with the record as it is: its block and peak
            as_given = self._study({"pulse": "record", "record": self.record_file})
            self.original = as_given.ground
            self.uplift = as_given.rocking_block.uplift_acceleration("nonlinear")

    def _study(self, ground: dict) -> FemStudy:
        spec = self.spec.model_copy(update={"ground": schema.Ground(**ground)})
        return from_spec(spec, self.study.source, self.study.base)

    def at(self, omega_ratio: float, amplitude_ratio: float) -> FemStudy:
        """The study of the point (omega_ratio: the time scale for a record)."""
        if self.kind == "record":
            return self._study(
                {
                    "pulse": "record",
                    "record": str(self.record_file),
                    "scale": float(amplitude_ratio * self.uplift / self.original.peak_acceleration),
                    "time_scale": float(omega_ratio),
                }
            )
        return self._study(
            {
                "pulse": self.kind,
                "amplitude_ratio": float(amplitude_ratio),
                "omega_ratio": float(omega_ratio),
            }
        )

    def grid(self, size: tuple[int, int] | None = None):
        """(x values, amplitude ratios) of the study's [grid], ``size`` overriding its counts."""
        return grid_of(self.spec.grid, size, record=self.kind == "record", source=self.study.source)


FEWER = ", fewer grid points (--grid)"  # its way to ask for less FEM work (besides [run], [mesh])


def fem_work(study: Study) -> FemWork:
    """The FEM work of a spectrum cross-check (:func:`studies.driver.check_work`): one run per
    grid point, its duration that of its pulse (the amplitude does not change it). A grid too
    large even at the shortest point's duration is given as that (a lower bound), without
    building every column of it."""
    from ...fem.solver import BATCH_SLOTS
    from ..work import WORK_LIMIT_SECONDS

    points = Points(study)
    models: dict = {}  # the model of each mesh, built once
    size = study.options.get("grid") or tuple(study.spec.grid.points)
    counts = size[0] * size[1]
    x_range = points.grid((2, 2))[0]  # [first, last]
    shortest = points.at(float(max(x_range)), 2.0)  # the fastest pulse: the shortest run
    bound = estimate_work(shortest, counts, held=BATCH_SLOTS, models=models)
    if bound.seconds > WORK_LIMIT_SECONDS:
        return bound
    work = FemWork()
    for x in points.grid(size)[0]:
        work += estimate_work(points.at(float(x), 2.0), size[1], held=BATCH_SLOTS, models=models)
    return work


def run(study: Study, out: Path, options: RunOptions) -> dict:
    """Run (or resume) the grid of a spectrum cross-check study (:func:`studies.study.load`;
    its ``grid`` option overriding [grid] points) into ``out``: ``summary.json``."""
    points = Points(study)
    omegas, amplitudes = points.grid(study.options.get("grid"))
    # every point's study, before anything runs (fails early); its simulated duration (s)
    # balances the workers' shares
    durations = {(w, a): points.at(w, a).duration for a in amplitudes for w in omegas}
    if study.spec.run.output_interval is None:
        interval = min(durations.values()) / 400.0
        # one output interval for every point (the runs of a batch share it), as a run's
        # default: 1/400 of the shortest point's duration
        points.spec = points.spec.model_copy(
            update={"run": points.spec.run.model_copy(update={"output_interval": interval})}
        )
    first = points.at(omegas[0], amplitudes[0])
    kind = points.kind
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    cases = []
    for i, a in enumerate(amplitudes):
        for j, w in enumerate(omegas):
            cases.append(
                case_of(
                    points.at(w, a),
                    cost=durations[w, a],
                    key=f"a{a:.6g}-w{w:.6g}",
                    omega_ratio=float(w),
                    amplitude_ratio=float(a),
                    row=i,
                    column=j,
                )
            )
    start = time.perf_counter()
    results = run_cases(
        grid_points_case,
        cases,
        out,
        run_options=options,
        batched=True,
    )
    check_fem_results(results, out)
    summary = assemble_summary(first, omegas, amplitudes, cases, results)
    summary["halved_steps"] = halved_steps(
        [
            (
                f"the grid point (amplitude ratio, x) = ({c['amplitude_ratio']:.3g}, "
                f"{c['omega_ratio']:.3g})",
                results[c["key"]],
            )
            for c in cases
        ]
    )
    summary["x_axis"] = "time_scale" if kind == "record" else "omega_ratio"
    if kind == "record":
        summary["record"] = points.original.name
        summary["time_scales"] = summary["omega_ratios"]
    summary["wall_seconds"] = time.perf_counter() - start
    write_json(out / "summary.json", summary)
    return summary


def assemble_summary(study, omegas, amplitudes, cases, results) -> dict:
    shape = (len(amplitudes), len(omegas))

    def grid(key):
        values = [[None] * shape[1] for _ in range(shape[0])]
        for case in cases:
            values[case["row"]][case["column"]] = results[case["key"]][key]
        return values

    mode_fem, mode_mb, mode_sdof = grid("mode_fem"), grid("mode_multibody"), grid("mode_sdof")
    seconds = [results[c["key"]]["fem_seconds"] for c in cases]

    def overturned(modes):
        return [[m != "safe" for m in row] for row in modes]

    same = [
        [f == m for f, m in zip(rf, rm)]
        for rf, rm in zip(overturned(mode_fem), overturned(mode_mb))
    ]
    flat = [v for row in same for v in row]
    rigid = {
        "question": QUESTIONS["rigid_assumption_ok"],
        "answer": YES if all(flat) else NO,
        "measure": "pulses where the FEM and the rigid multibody model give the same outcome "
        "(overturns or not; one FEM run per pulse)",
        "count": sum(flat),
        "points": len(flat),
        "figure": "maps",
    }
    answers = {
        "rigid_assumption_ok": rigid,
        "collars_yield": count_answer(
            QUESTIONS["collars_yield"],
            "pulses where the FEM's collars yield",
            [[u >= 1.0 for u in row] for row in grid("collar_utilisation_fem")],
            "maps",
        )
        if study.collars
        else not_assessed(QUESTIONS["collars_yield"], "the column has no collars"),
        "toe_crushes": count_answer(
            QUESTIONS["toe_crushes"],
            "pulses where the FEM's toe stress reaches f_c",
            [[r is not None and r >= 1.0 for r in row] for row in grid("toe_ratio_fem")],
            "maps",
        ),
    }
    models = [
        grid_outcome("FEM, deformable halves", overturned(mode_fem)),
        grid_outcome("rigid multibody", overturned(mode_mb)),
        grid_outcome("SDOF half block with collars (the paper's)", overturned(mode_sdof)),
    ]
    return {
        "study": study.name,
        "kind": "spectrum-crosscheck",
        "outcome": outcome(models, answers),
        "layout": "maps[i][j]: i indexes amplitude_ratios (rows), j indexes omega_ratios",
        "omega_ratios": [float(w) for w in omegas],
        "amplitude_ratios": [float(a) for a in amplitudes],
        "mode_fem": mode_fem,
        "mode_multibody": mode_mb,
        "mode_sdof": mode_sdof,
        "collar_yield_fem": [[u >= 1.0 for u in row] for row in grid("collar_utilisation_fem")],
        "collar_utilisation_fem": grid("collar_utilisation_fem"),
        "toe_ratio_fem": grid("toe_ratio_fem"),
        "agreement_fem_multibody": agreement(mode_fem, mode_mb),
        "agreement_fem_sdof": agreement(mode_fem, mode_sdof),
        "energy_error_fem_max": max(results[c["key"]]["energy_error_fem"] for c in cases),
        "fem_seconds_per_point": float(np.mean(seconds)),
        "points": len(cases),
    }


def agreement(a: list, b: list) -> float:
    """Fraction of grid points where two mode maps give the same outcome."""
    pairs = [(x, y) for row_a, row_b in zip(a, b) for x, y in zip(row_a, row_b)]
    return sum(x == y for x, y in pairs) / len(pairs)

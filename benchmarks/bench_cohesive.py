"""Cost of the cohesive mid-plane (issue 51): one explicit step of the default column with its
crack over the full height (today's crack, no cohesive pair), from the top to mid-height (the
lower half of the mid-plane's pairs cohesive: fem/_kernels.py cohesive_forces) and of no extent
(every pair cohesive, the intact column), each at its own stable step; medians of interleaved
measurements, with the cost per simulated second.

Run: make bench (or .venv/bin/python benchmarks/bench_cohesive.py)
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np

from colonna.core.motion import Motion
from colonna.fem.model import stable_time_step
from colonna.fem.settings import FemSettings
from colonna.fem.solver import run
from colonna.studies.models import build
from colonna.studies.study import load

STUDY = Path(__file__).resolve().parents[1] / "studies" / "default.toml"
STEPS = 4000
REPEATS = 5


def variants() -> tuple:
    """The default study (its FemStudy) and its three models by the crack's extent."""
    study = load(STUDY).fem
    H = study.height
    cracks = {"full height": None, "top to mid-height": (H / 2, H), "no extent": (H, H)}
    return study, {
        name: build(dataclasses.replace(study, crack=crack)) for name, crack in cracks.items()
    }


def intact_pairs(model) -> int:
    """The cohesive pairs of a model (intact at the start; 0 without a partial crack)."""
    return 0 if model.cohesive is None else int(np.sum(model.cohesive.bonded))


def main() -> None:
    study, models = variants()
    dts = {name: stable_time_step(m, study.safety).dt for name, m in models.items()}
    for model in models.values():  # compilation
        run(model, Motion(study.ground, 1e-3), FemSettings(progress=False))
    per_step: dict[str, list[float]] = {name: [] for name in models}
    for _ in range(REPEATS):  # interleaved: this machine's timings are noisy
        for name, model in models.items():
            duration = STEPS * dts[name]
            result = run(
                model,
                Motion(study.ground, duration),
                FemSettings(progress=False, output_interval=duration),
            )
            per_step[name].append(result.summary["wall_seconds"] / result.summary["steps"])
    full = float(np.median(per_step["full height"]))
    print(f"default column: {models['full height'].n_dofs} dofs")
    for name, model in models.items():
        intact = intact_pairs(model)
        cost = float(np.median(per_step[name]))
        print(
            f"crack {name:18s} {intact:4d} cohesive pairs  {cost * 1e6:8.1f} us per step "
            f"({cost / full:.2f} x the full crack's); dt {dts[name] * 1e6:.2f} us, "
            f"{cost / dts[name]:.2f} s per simulated s"
        )


if __name__ == "__main__":
    main()

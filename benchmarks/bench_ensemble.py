"""Cost of FEM replica ensembles on the batched explicit step (default column, one core).

1. Wall time of one run against an ensemble of 8 replicas over the same stretch of the default
   study (target: at most 3 x).
2. Cost per state of one step of the batched kernel at B = 1, 4, 8, 16 states, against B = 1.

Medians of three interleaved measurements (this machine's timings are noisy). Run alone, on
an idle machine: NUMBA_NUM_THREADS does not matter (the kernel is serial), other processes do.
Run: make bench
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from colonna.core.motion import Motion
from colonna.fem.model import stable_time_step
from colonna.fem.settings import FemSettings
from colonna.fem.solver import run_ensemble
from colonna.studies.models import build
from colonna.studies.study import load

STUDY = Path(__file__).resolve().parents[1] / "studies" / "default.toml"
STEPS = 4000


def _seconds(model, study, replicas: int, duration: float) -> float:
    start = time.perf_counter()
    run_ensemble(
        model,
        Motion(study.ground, duration),
        FemSettings(progress=False, output_interval=duration / 20),
        replicas=replicas,
    )
    return time.perf_counter() - start


def main() -> None:
    study = load(STUDY).fem
    model = build(study)
    dt = stable_time_step(model, study.safety).dt
    duration = STEPS * dt
    for batch in (1, 4, 8, 16):  # compilation, and a warm cache
        _seconds(model, study, batch, 10 * dt)
    sizes = (1, 4, 8, 16)
    samples = {b: [] for b in sizes}
    for _ in range(3):
        for b in sizes:
            samples[b].append(_seconds(model, study, b, duration))
    wall = {b: float(np.median(v)) for b, v in samples.items()}
    print(
        f"default column: {model.n_dofs} dofs, {STEPS} steps of {dt:.3g} s "
        f"(the first {duration:.3f} s of the pulse)"
    )
    ratio = wall[8] / wall[1]
    print(f"one run               {wall[1]:7.2f} s")
    print(
        f"ensemble of 8         {wall[8]:7.2f} s  = {ratio:.2f} x one run "
        f"(target <= 3) {'ok' if ratio <= 3.0 else 'SLOWER THAN TARGET'}"
    )
    print("states B   us per step and state   relative to B = 1")
    for b in sizes:
        per_state = wall[b] / (b * STEPS)
        print(f"{b:8d}   {per_state * 1e6:21.1f}   {per_state * STEPS / wall[1]:17.2f}")


if __name__ == "__main__":
    main()

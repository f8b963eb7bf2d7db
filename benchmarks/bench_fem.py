"""Cost of one explicit step of the default column (contact, collars and bookkeeping included)
against a bare sparse matrix-vector product (scipy CSR) with the model's stiffness matrix;
medians of five interleaved measurements.

Target: at most 2x the mat-vec. Run: make bench
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from colonna.fem.solver import run
from colonna.studies.fem_study import build, load

STUDY = Path(__file__).resolve().parents[1] / "studies" / "default.toml"


def main() -> None:
    study = load(STUDY)
    model = build(study)
    A = model.stiffness.tocsr()
    x = np.random.default_rng(0).standard_normal(A.shape[0])
    from colonna.fem.model import stable_time_step

    dt = stable_time_step(model, study.safety).dt
    run(model, study.ground, 1e-3, progress=False)  # compilation
    # interleave the two measurements and take medians: this machine's timings are noisy
    matvecs, per_steps = [], []
    steps = 5000
    for _ in range(5):
        start = time.perf_counter()
        for _ in range(2000):
            A @ x
        matvecs.append((time.perf_counter() - start) / 2000)
        result = run(model, study.ground, steps * dt, progress=False, output_interval=steps * dt)
        per_steps.append(result.summary["wall_seconds"] / result.summary["steps"])
    matvec, per_step = float(np.median(matvecs)), float(np.median(per_steps))
    ratio = per_step / matvec
    print(
        f"default column: {model.n_dofs} dofs, {A.nnz} stiffness non-zeros, "
        f"{len(study.collars)} collars"
    )
    print(f"bare scipy mat-vec   {matvec * 1e6:8.1f} us")
    print(
        f"one explicit step    {per_step * 1e6:8.1f} us  = {ratio:.2f} x mat-vec "
        f"(target <= 2) {'ok' if ratio <= 2.0 else 'SLOWER THAN TARGET'}"
    )


if __name__ == "__main__":
    main()

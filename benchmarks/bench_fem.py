"""Cost of one explicit step of the default column (contact, collars and bookkeeping included)
against a bare sparse matrix-vector product (scipy CSR) with the model's stiffness matrix;
medians of five interleaved measurements. The crack's contact both ways (issue 38): penalty
springs and exact (Lagrange multipliers), each at its own stable step, with the cost per
simulated second (the exact contact's step is not limited by the crack's springs).

Target: at most 2x the mat-vec. Run: make bench
"""

from __future__ import annotations

import dataclasses
import time
from pathlib import Path

import numpy as np

from colonna.core.motion import Motion
from colonna.fem.model import Loads, build_model, stable_time_step
from colonna.fem.settings import FemSettings
from colonna.fem.solver import run
from colonna.studies.models import build
from colonna.studies.study import load

STUDY = Path(__file__).resolve().parents[1] / "studies" / "default.toml"


def main() -> None:
    study = load(STUDY).fem
    base = build(study)
    models = {
        enforcement: build_model(
            base.mesh,
            base.stone,
            base.thickness,
            base.collars,
            dataclasses.replace(base.contact, enforcement=enforcement),
            loads=Loads(top_load=base.top_load),
        )
        for enforcement in ("penalty", "lagrange")
    }
    A = base.stiffness.tocsr()
    x = np.random.default_rng(0).standard_normal(A.shape[0])
    steps = 5000
    dts = {}
    for name, model in models.items():
        dts[name] = stable_time_step(model, study.safety).dt
        run(model, Motion(study.ground, 1e-3), FemSettings(progress=False))  # compilation
    # interleave the measurements and take medians: this machine's timings are noisy
    matvecs: list[float] = []
    per_steps: dict[str, list[float]] = {name: [] for name in models}
    for _ in range(5):
        start = time.perf_counter()
        for _ in range(2000):
            A @ x
        matvecs.append((time.perf_counter() - start) / 2000)
        for name, model in models.items():
            duration = steps * dts[name]
            result = run(
                model,
                Motion(study.ground, duration),
                FemSettings(progress=False, output_interval=duration),
            )
            per_steps[name].append(result.summary["wall_seconds"] / result.summary["steps"])
    matvec = float(np.median(matvecs))
    print(
        f"default column: {base.n_dofs} dofs, {A.nnz} stiffness non-zeros, "
        f"{len(study.collars)} collars"
    )
    print(f"bare scipy mat-vec   {matvec * 1e6:8.1f} us")
    for name in models:
        per_step = float(np.median(per_steps[name]))
        ratio = per_step / matvec
        print(
            f"one explicit step, crack {name:8s} {per_step * 1e6:8.1f} us  = {ratio:.2f} x "
            f"mat-vec (target <= 2) {'ok' if ratio <= 2.0 else 'SLOWER THAN TARGET'}; "
            f"dt {dts[name] * 1e6:.2f} us, {per_step / dts[name]:.2f} s per simulated s"
        )


if __name__ == "__main__":
    main()

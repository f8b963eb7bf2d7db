"""Cost of plastic collars against elastic ones: the fibre section (a plastic collar's default,
colonna.core.fibre) and the resultant law (axial law and N-M end hinges).

1. FEM: one explicit step of the default column (three collars) with elastic collars, plastic
   collars with the resultant law and with the fibre section (20 fibres, 5 sections), medians
   of five interleaved runs of the first 5000 steps (the collars stay elastic in them).
   Then a step of a small column whose one collar is bent far past yield through the whole run
   (the right half flung up along the crack, as tests/test_fibre_dynamics.py), each law.
2. The frame element alone, per collar and call, FEM and multibody kernels: elastic; plastic
   inside the surface; plastic on the surface (a hinge returning every call), each law.
Run: make bench
"""

from __future__ import annotations

import dataclasses
import time
from pathlib import Path

import numpy as np

from colonna.core.collar import Collar
from colonna.core.collar_law import OUT_SIZE, state_size
from colonna.core.ground import NoMotion
from colonna.core.motion import Motion
from colonna.fem import _kernels as FK
from colonna.fem.assembly import Stone
from colonna.fem.model import ContactSettings, build_model, stable_time_step
from colonna.fem.settings import FemSettings, FemStart
from colonna.fem.solver import run
from colonna.meshes import column_mesh
from colonna.rigid import _multibody as MK
from colonna.rigid.block import Block
from colonna.rigid.multibody import build_column
from colonna.studies.models import build
from colonna.studies.study import load

STUDY = Path(__file__).resolve().parents[1] / "studies" / "default.toml"
CALLS = 200_000


LAWS = {  # name: the collar's fields
    "elastic": dict(plastic=False, section=None),
    "resultant": dict(plastic=True, section="resultant"),
    "fibre": dict(plastic=True, section="fibre"),
}


def _per_step(study, law: str, steps: int) -> float:
    collars = tuple(dataclasses.replace(c, **LAWS[law]) for c in study.collars)
    model = build(dataclasses.replace(study, collars=collars))
    dt = stable_time_step(model, study.safety).dt
    result = run(
        model,
        Motion(study.ground, steps * dt),
        FemSettings(progress=False, output_interval=steps * dt),
    )
    return result.summary["wall_seconds"] / result.summary["steps"]


def _bent_per_step(law: str) -> float:
    """Seconds per step of a 0.4 x 2 m column whose collar yields through the run."""
    collar = Collar(y=1.0, t=0.004, h=0.03, **LAWS[law])
    mesh = column_mesh(0.4, 2.0, 0.1, cracked=True, grading=0.0, pinned_heights=[1.0])
    model = build_model(mesh, Stone(), 0.3, (collar,), ContactSettings(friction=0.0, damping=0.0))
    v0 = np.zeros((mesh.n_nodes, 2))
    v0[mesh.node_body == 1, 1] = 1.0
    result = run(
        model,
        Motion(NoMotion(), 0.03),
        FemSettings(output_interval=0.03, progress=False, stop_on_overturn=False),
        FemStart(velocity=v0),
    )
    return result.summary["wall_seconds"] / result.summary["steps"]


def _element_calls(law: str, offset: float) -> tuple[float, float]:
    """Seconds per call of the FEM and the multibody element at a lateral end offset (m)."""
    collar = Collar(y=1.0, t=0.004, h=0.03, **LAWS[law])
    mesh = column_mesh(0.4, 2.0, 0.1, cracked=True, grading=0.0, pinned_heights=[1.0])
    model = build_model(mesh, Stone(), 0.3, (collar,))
    x = model.X.copy()
    x[2 * model.collar_nodes[0, 3:] + 1] += offset
    out, f = np.zeros((1, OUT_SIZE)), np.zeros_like(x)
    state = np.zeros((1, state_size([collar.law()])))
    args = (x, model.collar_nodes, model.collar_props, out, f, state, False)
    FK.collar_forces(*args)
    start = time.perf_counter()
    for _ in range(CALLS):
        FK.collar_forces(*args)
    fem = (time.perf_counter() - start) / CALLS
    column = build_column(Block(b=0.1, h=2.0, mass=100.0), cracked=True, collars=(collar,))
    q = column.q_rest.copy()
    q[4] += offset
    f = np.zeros(q.size)
    margs = (q, column.col_a, column.col_b, column.col_r, column.col_props, f, out, state, False)
    MK.collar_forces(*margs)
    start = time.perf_counter()
    for _ in range(CALLS):
        MK.collar_forces(*margs)
    return fem, (time.perf_counter() - start) / CALLS


def main() -> None:
    study = load(STUDY).fem
    steps = 5000
    for law in LAWS:
        _per_step(study, law, 10)  # compilation
    samples: dict[str, list[float]] = {law: [] for law in LAWS}
    for _ in range(5):
        for law in LAWS:
            samples[law].append(_per_step(study, law, steps))
    step = {law: float(np.median(samples[law])) for law in LAWS}
    elastic = step["elastic"]
    print(f"FEM step, default column (3 collars): elastic collars {elastic * 1e6:.1f} us")
    for law in ("resultant", "fibre"):
        print(
            f"  plastic collars, {law:9s} law {step[law] * 1e6:7.1f} us "
            f"({step[law] / elastic:.2f} x; the collars' share "
            f"{(step[law] - elastic) / 3 * 1e6:+.1f} us per collar over elastic)"
        )
    bent: dict[str, list[float]] = {law: [] for law in LAWS}
    for law in LAWS:
        _bent_per_step(law)  # compilation
    for _ in range(5):
        for law in LAWS:
            bent[law].append(_bent_per_step(law))
    small = {law: float(np.median(bent[law])) for law in LAWS}
    print(
        "FEM step, small column, one collar bent past yield: elastic "
        f"{small['elastic'] * 1e6:.1f} us"
    )
    for law in ("resultant", "fibre"):
        print(
            f"  {law:9s} law {small[law] * 1e6:7.1f} us (the collar's share "
            f"{(small[law] - small['elastic']) * 1e6:+.1f} us over elastic)"
        )
    print("frame element, per call (python call overhead included)   FEM      multibody")
    d_y = Collar(y=1.0, t=0.004, h=0.03).yield_displacement(0.1)
    for name, law, offset in (
        ("elastic", "elastic", 2.0 * d_y),
        ("resultant, inside the surface", "resultant", 0.5 * d_y),
        ("resultant, hinges returning", "resultant", 2.0 * d_y),
        ("fibre, elastic", "fibre", 0.5 * d_y),
        ("fibre, yielding (trial from the state at rest)", "fibre", 2.0 * d_y),
    ):
        fem, mb = _element_calls(law, offset)
        print(f"  {name:52s} {fem * 1e6:6.2f} us {mb * 1e6:8.2f} us")


if __name__ == "__main__":
    main()

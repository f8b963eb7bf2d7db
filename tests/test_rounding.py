"""Answers that hold on any machine.

``NUMBA_CPU_NAME=generic`` compiles the kernels without this processor's instructions (no fused
multiply-add, other vector widths). The FEM kernels are strict IEEE arithmetic (no contraction,
no reassociation), so they give the same bits either way: a change of instruction set moves
nothing. What a machine can still change (the static solve's sparse library, the mathematical
library's sine and arctangent, another numba) moves the last bits of the start, and the
landings amplify that, so single numbers move by several per cent; their bands must not. That
is pinned with another set of round-off-level perturbations of the start."""

import json
import os
import subprocess
import sys
import textwrap

import numpy as np
import pytest

from colonna.fem.ensemble import band

# the small cracked column with a collar, rocked through its first landings (as in
# tests/test_toe_stress.py): 8 replicas take a few seconds
CASE = textwrap.dedent("""
    import json, math
    from colonna.fem.assembly import Stone
    from colonna.fem.model import ContactSettings, build_model
    from colonna.core.motion import Motion
    from colonna.fem.settings import FemSettings, Replicas
    from colonna.fem.solver import run_ensemble
    from colonna.meshes import column_mesh
    from colonna.rigid.block import Block
    from colonna.rigid.collars import Collar
    from colonna.core.ground import sine_pulse

    width, height = 0.2, 1.0
    mesh = column_mesh(width, height, 0.05, grading=0.0, pinned_heights=[0.5])
    model = build_model(mesh, Stone(E=30e9, fc=100e6), math.pi * width / 4.0,
                        (Collar(y=0.5, t=0.004, h=0.02),), ContactSettings())
    half = Block(b=width / 4, h=height / 2, mass=1.0)
    uplift = half.uplift_acceleration("nonlinear")
    pulse = sine_pulse(2.5 * uplift, 3.0 * half.p, uplift)
    settings = FemSettings(output_interval=0.005, edge_length=0.01, progress=False)
    runs = run_ensemble(model, Motion(pulse, 0.6), settings,
                        replicas=Replicas(8, perturbation=PERTURBATION))
    print(json.dumps([{key: r.summary[key] for key in KEYS} | {
        "crack_slip_max": float(max(r.history["crack_slip_max"]))} for r in runs]))
""")
KEYS = (
    "max_abs_theta_left",
    "max_abs_theta_right",
    "collar_max_utilisation",
    "edge_stress_max",
    "crack_slip_residual",
    "energy_error_max",
)


def _replicas(cpu_name: str | None, perturbation: float = 1e-12) -> list[dict]:
    env = dict(os.environ)
    env.pop("NUMBA_CPU_NAME", None)
    if cpu_name:
        env["NUMBA_CPU_NAME"] = cpu_name
    script = f"KEYS = {KEYS!r}\nPERTURBATION = {perturbation!r}\n" + CASE
    done = subprocess.run(
        [sys.executable, "-c", script],
        env=env,
        capture_output=True,
        text=True,
        timeout=900,
        check=True,
    )
    return json.loads(done.stdout.strip().splitlines()[-1])


def inside_band(value: float, b: dict) -> bool:
    """value within the band widened by half its width on each side (and by 1e-9 of its
    median, for numbers the landings do not move): the median of another 8 samples of the
    same distribution falls outside that with a probability of order 1e-5 for a normal one."""
    width = b["max"] - b["min"]
    slack = 0.5 * width + 1e-9 * abs(b["median"])
    return b["min"] - slack <= value <= b["max"] + slack


@pytest.fixture(scope="module")
def here():
    return _replicas(None)


@pytest.mark.slow  # compiling every FEM kernel for the generic processor: 75 s; .ci/run runs it
@pytest.mark.skipif(
    os.environ.get("NUMBA_CPU_NAME") == "generic",
    reason="compares this processor's instructions with the generic ones",
)
def test_the_kernels_give_the_same_bits_on_another_instruction_set(here):
    """Strict arithmetic: compiled for a generic processor, every replica's numbers are the
    same bits as here (fast-math would fuse and reorder differently per instruction set)."""
    assert _replicas("generic") == here


@pytest.mark.chaotic
def test_another_perturbation_lands_inside_the_replicas_bands(here):
    """Replicas started from another set of round-off-level offsets (3e-12 of the height in
    place of 1e-12): every median inside this ensemble's bands, and the bands are not empty
    words (the landings do scatter the collar and toe)."""
    other = _replicas(None, perturbation=3e-12)
    keys = list(here[0])
    assert any(here[1][k] != other[1][k] for k in keys)  # other landings
    for key in keys:
        b = band(r[key] for r in here)
        median = float(np.median([r[key] for r in other]))
        assert inside_band(median, b), (key, median, b)
    for key in ("collar_max_utilisation", "edge_stress_max"):
        b = band(r[key] for r in here)
        assert b["max"] > b["min"]

"""Answers that hold on any machine: the FEM's landing-dependent numbers, recomputed with the
kernels compiled for another processor (another rounding of every operation), fall inside the
bands of the replicas computed here.

``NUMBA_CPU_NAME=generic`` compiles the kernels without this processor's instructions (no fused
multiply-add, other vector widths), which changes the last bits of every result: the same
perturbation a change of machine makes. The landings amplify it, so single numbers move by
several per cent; their bands must not."""

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
    runs = run_ensemble(model, pulse, 0.6, 8, output_interval=0.005, edge_length=0.01,
                        progress=False)
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


def _replicas(cpu_name: str | None) -> list[dict]:
    env = dict(os.environ)
    env.pop("NUMBA_CPU_NAME", None)
    if cpu_name:
        env["NUMBA_CPU_NAME"] = cpu_name
    script = f"KEYS = {KEYS!r}\n" + CASE
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


@pytest.mark.skipif(
    os.environ.get("NUMBA_CPU_NAME") == "generic",
    reason="compares this processor's rounding with the generic one",
)
def test_another_rounding_lands_inside_the_replicas_bands():
    here = _replicas(None)
    generic = _replicas("generic")
    keys = list(here[0])
    # the two roundings do differ: the first replica's numbers are not the same bits
    assert any(here[0][k] != generic[0][k] for k in keys)
    for key in keys:
        b = band(r[key] for r in here)
        other = float(np.median([r[key] for r in generic]))
        assert inside_band(other, b), (key, other, b)
    # and the bands are not empty words: the landings do scatter the collar and toe
    for key in ("collar_max_utilisation", "edge_stress_max"):
        b = band(r[key] for r in here)
        assert b["max"] > b["min"]


def test_inside_band_rejects_a_median_off_the_band():
    b = band([1.0, 1.1, 1.2, 1.05])
    assert inside_band(1.25, b) and inside_band(0.95, b)
    assert not inside_band(1.35, b) and not inside_band(0.85, b)

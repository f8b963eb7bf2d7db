"""Mesh convergence of the FEM numbers it reports (the mesh runs are slow: make test-all)."""

import math

import pytest

from colonna.core.motion import Motion
from colonna.fem.assembly import Stone
from colonna.fem.convergence import convergence_table, observed_order, richardson
from colonna.fem.model import ContactSettings, build_model
from colonna.fem.settings import FemSettings
from colonna.fem.solver import run
from colonna.meshes.column import column_mesh
from colonna.rigid import Block, pulse_from_ratios


def test_observed_order_and_richardson_are_exact_for_a_power_law():
    f = [3.0 + 0.7 * h**1.6 for h in (0.4, 0.2, 0.1)]
    assert observed_order(*f) == pytest.approx(1.6, rel=1e-12)
    assert richardson(f[1], f[2], 1.6) == pytest.approx(3.0, rel=1e-12)
    table = convergence_table(f)
    assert table["fine_relative_error"] == pytest.approx(0.7 * 0.1**1.6 / 3.0, rel=1e-9)
    assert math.isnan(observed_order(1.0, 2.0, 4.0))  # diverging: no order


@pytest.mark.slow
def test_peak_rotation_and_toe_stress_converge():
    """A solid column under a sine pulse up to the first impact, meshes h, h/2, h/4: the peak
    rotation and the toe stress averaged over 40 mm converge (orders about 1.2 and above 2)."""
    W, H = 0.4, 2.0
    block = Block(b=W / 2, h=H / 2)
    pulse = pulse_from_ratios(block, "sine", 3.0, 2.5, "nonlinear")
    peaks, toes = [], []
    for size in (0.1, 0.05, 0.025):
        model = build_model(
            column_mesh(W, H, size, cracked=False, grading=0.0),
            Stone(),
            0.3,
            contact=ContactSettings(friction=1.0),
        )
        r = run(
            model,
            Motion(pulse, 0.7),
            FemSettings(progress=False, output_interval=1e-3, edge_length=0.04),
        )
        peaks.append(float(abs(r.history["theta_left"]).max()))
        toes.append(float(r.history["edge_stress_left"].max()))
    rotation, toe = convergence_table(peaks), convergence_table(toes)
    print(
        f"\npeak rotation {peaks}: order {rotation['observed_order']:.2f}, "
        f"Richardson {rotation['richardson']:.6f}"
    )
    print(
        f"toe stress {toes}: order {toe['observed_order']:.2f}, "
        f"Richardson {toe['richardson']:.0f} Pa"
    )
    assert rotation["observed_order"] > 0.8
    assert toe["observed_order"] > 0.8
    assert rotation["fine_relative_error"] < 0.01 and toe["fine_relative_error"] < 0.05

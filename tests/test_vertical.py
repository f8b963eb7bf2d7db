"""Vertical ground acceleration vg'' (upward positive): the weight becomes m (g + vg''), in the
rocking equation and in the uplift level (Eq. 1-2), in the SDOF, multibody and FEM models."""

import math

import numpy as np
import pytest

from colonna.core.ground import NoMotion, Record, cosine_pulse
from colonna.core.motion import Motion, Release
from colonna.fem.settings import FemSettings
from colonna.rigid.block import Block
from colonna.rigid.multibody import MultibodyContact, MultibodySettings, rock_multibody
from colonna.rigid.solve import rock

G = 9.81


def _constant(value, duration):
    """A vertical acceleration held at ``value`` (m/s^2) from 0 to ``duration`` s."""
    return Record(np.array([0.0, duration]), np.array([value, value]), "constant")


@pytest.mark.parametrize("model", ["nonlinear", "linear", "multibody"])
def test_free_fall_of_the_support_leaves_no_restoring_moment(model):
    """vg'' = -g: the block weighs nothing, so released tilted and at rest it stays where it
    is; with the support still it falls back to the vertical within its quarter period."""
    blk = Block(b=0.2, h=1.0, mass=100.0)
    tilt = 0.3 * blk.alpha
    for vertical, moves in ((_constant(-G, 2.0), False), (NoMotion(), True)):
        if model == "multibody":
            r = rock_multibody(
                blk,
                Motion(NoMotion(), duration=1.0, vertical=vertical),
                contact=MultibodyContact(friction=1.0),
                release=Release(tilt=tilt),
            )
            theta = r.theta[:, 0]
        else:
            r = rock(
                blk,
                Motion(NoMotion(), duration=1.0, vertical=vertical),
                model=model,
                release=Release(tilt=tilt),
            )
            theta = r.theta
        if moves:
            assert theta.min() < 0.0  # it reached the vertical and went past
        else:
            assert np.abs(theta - tilt).max() < 1e-9 * tilt


@pytest.mark.parametrize("model", ["nonlinear", "linear"])
@pytest.mark.parametrize("vertical_g", [0.3, -0.4])
def test_uplift_level_follows_eq_2_with_vertical_acceleration(model, vertical_g):
    """ug'' > g (1 + vg''/g) tan(alpha) (Eq. 2; linear: alpha for tan alpha): a cosine pulse
    (it starts at its peak) 0.1 % below that level leaves the block at rest, 0.1 % above it
    rocks; also with a top load, where the level is g (1 + lambda + vg''/g) tan(alpha)."""
    for load_ratio in (0.0, 1.0):
        blk = Block(b=0.2, h=1.5, mass=500.0, top_load=load_ratio * 500.0 * G)
        slope = math.tan(blk.alpha) if model == "nonlinear" else blk.alpha
        level = G * slope * (1.0 + load_ratio + vertical_g)
        vertical = _constant(vertical_g * G, 5.0)
        for factor, rocks in ((0.999, False), (1.001, True)):
            pulse = cosine_pulse(factor * level, 4.0 * blk.p, 0.5 * factor * level)
            r = rock(blk, Motion(pulse, duration=3.0, vertical=vertical), model=model)
            assert (r.max_abs_theta > 0.0) == rocks, (load_ratio, factor)


def test_multibody_with_vertical_shaking_follows_the_nonlinear_sdof():
    """A horizontal sine pulse with a vertical harmonic of 0.4 g at twice its frequency: the
    rigid multibody block follows the SDOF equation with the weight m (g + vg'') to the second
    impact, and its energy balance (with the vertical work) closes."""
    from colonna.core.ground import HarmonicPulse, sine_pulse

    blk = Block(b=0.2, h=1.5, mass=500.0)
    a_up = blk.uplift_acceleration("nonlinear")
    omega = 6.0 * blk.p
    pulse = sine_pulse(1.5 * a_up, omega, a_up)
    vertical = HarmonicPulse("sine", 0.4 * G, 2.0 * omega, 0.0, pulse.duration)
    sdof = rock(blk, Motion(pulse, duration=2.0, vertical=vertical), model="nonlinear")
    mb = rock_multibody(
        blk,
        Motion(pulse, duration=2.0, vertical=vertical),
        contact=MultibodyContact(friction=1.0),
        settings=MultibodySettings(dt=5e-5),
    )
    plain = rock(blk, Motion(pulse, duration=2.0), model="nonlinear")
    assert sdof.impacts >= 2
    end = sdof.impact_times[1]
    t = mb.time[mb.time < end]
    error = np.abs(mb.theta[: t.size, 0] - np.interp(t, sdof.time, sdof.theta)).max()
    assert error < 1e-3 * blk.alpha
    # and the vertical shaking does change the response
    assert abs(plain.max_abs_theta - sdof.max_abs_theta) > 10 * error
    assert mb.summary()["energy_error_max"] < 1e-2


def test_fem_vertical_acceleration_loads_the_base_as_extra_weight():
    """The support accelerating upward at 0.5 g (reached over 50 ms, slow against the column's
    millisecond axial period) makes the base carry 1.5 W; the energy balance, with the work
    of the vertical ground motion, closes."""
    from colonna.core.ground import NoMotion
    from colonna.fem.assembly import Stone
    from colonna.fem.model import ContactSettings, build_model
    from colonna.fem.solver import run
    from colonna.meshes import column_mesh

    width, height, thickness = 0.4, 2.0, 0.3
    stone = Stone()
    weight = stone.density * width * height * thickness * G
    model = build_model(
        column_mesh(width, height, 0.05, cracked=True, grading=0.0),
        stone,
        thickness,
        contact=ContactSettings(friction=0.7, damping=0.2),
    )
    ramp = Record(np.array([0.0, 0.05, 0.2]), np.array([0.0, 0.5 * G, 0.5 * G]), "ramp")
    r = run(
        model,
        Motion(NoMotion(), 0.15, vertical=ramp),
        FemSettings(output_interval=1e-3, progress=False),
    )
    reaction = r.history["base_normal_force_1"] + r.history["base_normal_force_2"]
    late = r.history["t"] > 0.1
    assert reaction[0] == pytest.approx(weight, rel=1e-6)
    assert reaction[late].mean() == pytest.approx(1.5 * weight, rel=0.01)
    assert r.summary["energy_error_max"] < 0.01
    assert abs(r.history["theta_left"]).max() < 1e-6  # straight up: no rocking

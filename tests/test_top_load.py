"""A dead load on the capital (``top_load``): closed forms of the rigid models against an
independent integration, the multibody model against the SDOF one, and the FEM's static state."""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from colonna.core.errors import InputError
from colonna.core.ground import NoMotion, sine_pulse
from colonna.core.motion import Motion, Release
from colonna.fem.settings import FemSettings, FemStart
from colonna.rigid.block import Block
from colonna.rigid.multibody import MultibodyContact, MultibodySettings, rock_multibody
from colonna.rigid.solve import SdofSettings, rock

MASS = 500.0
LOAD_RATIO = 1.5


def _block(load_ratio=LOAD_RATIO, **kw):
    return Block(b=0.2, h=1.5, mass=MASS, top_load=load_ratio * MASS * 9.81, **kw)


def _independent_free_rocking(block: Block, tilt: float, t_end: float):
    """theta(t) of the block released from ``tilt`` > 0, pivoting on its corner (b, 0), from
    the potential energy of its centre of mass and of the load point, positions found by
    rotating the body-fixed points (no moment formula), derivative by central differences."""
    b, h, m, g, load = block.b, block.h, block.mass, block.g, block.top_load
    inertia = m * (b * b + h * h) / 3.0 + m * (b * b + h * h)  # about the corner

    def height(point, theta):  # point in the body frame (origin at the pivot corner)
        c, s = math.cos(theta), math.sin(theta)  # clockwise by theta
        return -s * point[0] + c * point[1]

    def potential(theta):
        return m * g * height((-b, h), theta) + load * height((-b, 2.0 * h), theta)

    def rhs(t, y):
        d = 1e-6
        return [y[1], -(potential(y[0] + d) - potential(y[0] - d)) / (2.0 * d) / inertia]

    def vertical(t, y):
        return y[0]

    vertical.terminal = True
    return solve_ivp(
        rhs, (0.0, t_end), [tilt, 0.0], rtol=1e-11, atol=1e-13, events=vertical, dense_output=True
    )


def test_top_load_is_checked():
    with pytest.raises(InputError, match="top_load"):
        Block(b=0.2, h=1.5, mass=MASS, top_load=-1.0)
    with pytest.raises(InputError, match="mass"):
        Block(b=0.2, h=1.5, top_load=1000.0)


@pytest.mark.parametrize("model", ["nonlinear", "linear"])
def test_uplift_acceleration_grows_with_the_load(model):
    """Rocking starts at |ug''| = g tan(alpha) (1 + lambda) (Eq. 2 with the load; linear: g alpha
    (1 + lambda)): a sine pulse 0.1 % below does not lift the block, 0.1 % above does."""
    blk = _block()
    slope = math.tan(blk.alpha) if model == "nonlinear" else blk.alpha
    uplift = blk.uplift_acceleration(model)
    assert uplift == pytest.approx(9.81 * slope * (1.0 + LOAD_RATIO), rel=1e-12)
    for factor, rocks in ((0.999, False), (1.001, True)):
        pulse = sine_pulse(factor * uplift, 3.0 * blk.p, blk.g * slope)
        result = rock(blk, Motion(pulse, duration=3.0), model=model)
        assert (result.max_abs_theta > 0.0) == rocks


def test_free_rocking_with_a_top_load_follows_an_independent_integration():
    blk = _block()
    tilt = 0.5 * blk.critical_angle()
    reference = _independent_free_rocking(blk, tilt, 5.0)
    t_vertical = reference.t_events[0][0]
    result = rock(
        blk,
        Motion(NoMotion(), duration=1.2 * t_vertical),
        model="nonlinear",
        release=Release(tilt=tilt),
        settings=SdofSettings(dt_out=t_vertical / 200),
    )
    inside = result.time < t_vertical
    expected = reference.sol(result.time[inside])[0]
    assert np.abs(result.theta[inside] - expected).max() < 1e-7 * tilt
    assert result.impact_times[0] == pytest.approx(t_vertical, rel=1e-7)


def test_linear_model_with_a_top_load_is_the_equivalent_free_block():
    """Linearised, the load makes p' = p sqrt(1 + 2 lambda) and alpha' = alpha (1 + lambda) /
    (1 + 2 lambda): from rest at theta0 the block reaches the vertical at arccosh(1 / (1 -
    theta0 / alpha')) / p' (corrected Eq. 13 of the equivalent block)."""
    blk = _block()
    p_eq = blk.p * math.sqrt(1.0 + 2.0 * LOAD_RATIO)
    alpha_eq = blk.alpha * (1.0 + LOAD_RATIO) / (1.0 + 2.0 * LOAD_RATIO)
    assert blk.critical_angle("linear") == pytest.approx(alpha_eq, rel=1e-14)
    tilt = 0.4 * alpha_eq
    result = rock(blk, Motion(NoMotion(), duration=2.0), model="linear", release=Release(tilt=tilt))
    expected = math.acosh(1.0 / (1.0 - tilt / alpha_eq)) / p_eq
    assert result.impact_times[0] == pytest.approx(expected, rel=1e-9)


@pytest.mark.parametrize("model", ["nonlinear", "multibody"])
def test_the_load_lowers_the_unstable_equilibrium(model):
    """theta_c = atan((1 + lambda) / (1 + 2 lambda) tan(alpha)): released 1 % inside it the
    block comes back, 1 % outside it overturns, in the SDOF and the multibody model."""
    blk = _block()
    tc = blk.critical_angle()
    assert tc < 0.8 * blk.alpha
    for factor, falls in ((0.99, False), (1.01, True)):
        if model == "nonlinear":
            r = rock(
                blk,
                Motion(NoMotion(), duration=6.0),
                model="nonlinear",
                release=Release(tilt=factor * tc),
            )
        else:
            r = rock_multibody(
                blk,
                Motion(NoMotion(), duration=6.0),
                contact=MultibodyContact(friction=1.0),
                release=Release(tilt=factor * tc),
            )
        assert r.overturned == falls


def test_a_massless_load_keeps_housners_restitution():
    """The load has no mass, so it gives no impulse at the impact: the multibody model, whose
    impact comes from its contact impulses, gives Housner's ratio with the load too."""
    for load_ratio in (0.0, LOAD_RATIO):
        blk = _block(load_ratio)
        r = rock_multibody(
            blk,
            Motion(NoMotion(), duration=1.5),
            contact=MultibodyContact(friction=1.0),
            release=Release(tilt=0.5 * blk.critical_angle()),
        )
        assert r.impact_velocity_ratios()[0] == pytest.approx(blk.restitution_housner, rel=1e-3)


def test_multibody_block_with_a_load_follows_the_nonlinear_sdof():
    blk = _block()
    a_up = blk.uplift_acceleration("nonlinear")
    pulse = sine_pulse(1.5 * a_up, 8.0 * blk.p, a_up)  # 5 impacts, theta up to 0.5 theta_c
    sdof = rock(blk, Motion(pulse, duration=2.5), model="nonlinear")
    # (the load makes the impact timing more sensitive to the step than without: at the
    # default step the error to the third impact is 5e-3 alpha, 0.9e-3 without a load)
    mb = rock_multibody(
        blk,
        Motion(pulse, duration=2.5),
        contact=MultibodyContact(friction=1.0),
        settings=MultibodySettings(dt=5e-5),
    )
    assert sdof.impacts >= 2 and mb.impacts >= 2
    end = sdof.impact_times[2] if sdof.impacts > 2 else 2.5
    t = mb.time[mb.time < end]
    theta_mb = mb.theta[: t.size, 0]
    theta_sdof = np.interp(t, sdof.time, sdof.theta)
    assert np.abs(theta_mb - theta_sdof).max() < 1e-3 * blk.alpha
    assert mb.summary()["energy_error_max"] < 1e-2  # the load's potential included


# --- the FEM ---------------------------------------------------------------------------------


def test_fem_static_state_carries_weight_and_top_load():
    """Static reaction = weight + load (to 1e-6: a linear solve). On a frictionless base the
    solid column is in uniaxial stress, so the base pressure is (W + P) / A across the base
    (with friction the base holds the Poisson spread back and the pressure rises toward the
    edges)."""
    from colonna.core.ground import NoMotion
    from colonna.fem.assembly import Stone
    from colonna.fem.model import ContactSettings, Loads, build_model
    from colonna.fem.solver import run, static_state
    from colonna.meshes import column_mesh

    width, height, thickness = 0.4, 2.0, 0.3
    stone = Stone()
    weight = stone.density * width * height * thickness * 9.81
    mesh = column_mesh(width, height, 0.025, cracked=False, grading=0.0)
    for load in (0.0, 3.0 * weight):
        model = build_model(
            mesh,
            stone,
            thickness,
            contact=ContactSettings(friction=0.0),
            loads=Loads(top_load=load),
        )
        r = run(model, Motion(NoMotion(), 1e-4), FemSettings(output_interval=1e-4, progress=False))
        assert r.summary["base_reaction_static"] == pytest.approx(weight + load, rel=1e-6)
        assert r.summary["top_load"] == load
        u, _, _ = static_state(model)
        pressure = -model.base_kn * u[2 * model.base_nodes + 1] / (model.base_tributary * thickness)
        # (1 %: self-weight bends the base by nu rho g x^2 / 2E against the penalty springs)
        assert pressure == pytest.approx((weight + load) / (width * thickness), rel=1e-2)
    with pytest.raises(InputError, match="top_load"):
        build_model(mesh, stone, thickness, loads=Loads(top_load=-1.0))


def test_fem_column_with_a_top_load_rocks_like_the_rigid_block():
    """Released from half its theta_c, a stiff FEM column with a top load of twice its weight
    reaches the vertical when the rigid block with the same load does (1 %)."""
    from colonna.core.ground import NoMotion
    from colonna.fem.assembly import Stone
    from colonna.fem.model import ContactSettings, Loads, build_model
    from colonna.fem.solver import run
    from colonna.meshes import column_mesh

    width, height, thickness = 0.4, 2.0, 0.3
    stone = Stone()
    weight = stone.density * width * height * thickness * 9.81
    blk = Block(b=width / 2, h=height / 2, mass=weight / 9.81, top_load=2.0 * weight)
    tilt = 0.5 * blk.critical_angle()
    rigid = rock(
        blk, Motion(NoMotion(), duration=1.0), model="nonlinear", release=Release(tilt=tilt)
    )
    model = build_model(
        column_mesh(width, height, 0.1, cracked=False, grading=0.3),
        stone,
        thickness,
        contact=ContactSettings(friction=1.0),
        loads=Loads(top_load=2.0 * weight),
    )
    r = run(
        model,
        Motion(NoMotion(), 1.2 * rigid.impact_times[0]),
        FemSettings(output_interval=1e-4, progress=False),
        FemStart(tilt=tilt),
    )
    theta = r.history["theta_left"]
    crossing = np.nonzero(theta <= 0.0)[0][0]
    assert r.history["t"][crossing] == pytest.approx(rigid.impact_times[0], rel=0.01)
    assert r.summary["energy_error_max"] < 0.01

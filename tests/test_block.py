import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from colonna.rigid import Block, InputError, housner_restitution


def test_dimensionless_round_trip():
    blk = Block.from_dimensionless(p=2.14, alpha=0.25)
    assert blk.p == pytest.approx(2.14, rel=1e-14)
    assert blk.alpha == pytest.approx(0.25, rel=1e-14)
    # p^2 = m g R / J0 with J0 = 4/3 m R^2
    blk = Block(b=0.3, h=2.1, mass=500.0)
    assert blk.p**2 == pytest.approx(blk.mass * blk.g * blk.R / blk.J0, rel=1e-14)


def test_housner_restitution_is_corrected_eq12():
    """nu = 1 - (2 m R^2 / J0) sin^2(alpha), not the printed 1 - 2 m R^2 alpha / J0."""
    blk = Block(b=0.5, h=1.5, mass=100.0)
    expected = 1.0 - 2.0 * blk.mass * blk.R**2 / blk.J0 * math.sin(blk.alpha) ** 2
    assert blk.nu == pytest.approx(expected, rel=1e-14)
    assert housner_restitution(blk.alpha) == pytest.approx(1 - 1.5 * math.sin(blk.alpha) ** 2)


def test_uplift_acceleration_eq2_3():
    blk = Block(b=0.2, h=2.0)
    assert blk.uplift_acceleration("nonlinear") == pytest.approx(9.81 * 0.1)
    assert blk.uplift_acceleration("linear") == pytest.approx(9.81 * math.atan(0.1))


@pytest.mark.parametrize("ratio", [0.2, 0.5, 0.9])
def test_time_to_vertical_is_corrected_eq13(ratio):
    """Free linear rocking from rest at theta0 reaches theta = 0 after
    arccosh(1 / (1 - theta0 / alpha)) / p."""
    blk = Block.from_dimensionless(p=2.0, alpha=0.2)
    theta0 = ratio * blk.alpha
    p2, a = blk.p**2, blk.alpha

    def zero(t, y):
        return y[0]

    zero.terminal = True
    sol = solve_ivp(
        lambda t, y: [y[1], p2 * y[0] - p2 * a],
        (0, 50),
        [theta0, 0.0],
        events=zero,
        rtol=1e-12,
        atol=1e-14,
    )
    assert sol.t_events[0][0] == pytest.approx(blk.time_to_vertical(theta0), rel=1e-9)


@pytest.mark.parametrize(
    "kwargs, name",
    [
        (dict(p=2.0, alpha=2.0), "alpha"),
        (dict(p=2.0, alpha=0.0), "alpha"),
        (dict(p=-1.0, alpha=0.2), "p"),
    ],
)
def test_bad_dimensionless_input_names_parameter(kwargs, name):
    with pytest.raises(InputError, match=name):
        Block.from_dimensionless(**kwargs)


@pytest.mark.parametrize(
    "kwargs, name",
    [
        (dict(b=-0.2, h=1.0), "b"),
        (dict(b=0.2, h=0.0), "h"),
        (dict(b=0.2, h=1.0, mass=-3.0), "mass"),
        (dict(b=0.2, h=1.0, restitution=1.5), "restitution"),
    ],
)
def test_bad_block_input_names_parameter(kwargs, name):
    with pytest.raises(InputError, match=name):
        Block(**kwargs)


def test_density_mass():
    blk = Block.from_density(b=0.2, h=2.0, density=2700.0, thickness=0.5)
    assert blk.mass == pytest.approx(2700.0 * 0.4 * 4.0 * 0.5)
    assert np.isfinite(blk.J0)

"""Collar springs, kinematics, stress and design against hand calculations."""

import math

import numpy as np
import pytest

from colonna.core.motion import Motion
from colonna.rigid import Block, Collar, InputError, pulse_from_ratios, rock
from colonna.rigid import _kernels as K
from colonna.rigid.collars import (
    collar_deformation,
    collar_deformation_from_positions,
    collar_response,
    collar_restoring_moment,
    collar_strain_energy,
    crack_face_overlap,
)
from colonna.rigid.design import design_chart, design_collars
from colonna.rigid.solve import kernel_params
from colonna.studies.schema import read_collars

E, FY = 206e9, 235e6


def test_spring_stiffness_hand_calculation():
    c = Collar(y=1.0, t=0.01, h=0.06, length=1.2)
    assert c.axial_stiffness() == pytest.approx(E * 0.01 * 0.06 / 1.2)
    assert c.lateral_stiffness() == pytest.approx(12 * E * (0.01 * 0.06**3 / 12) / 1.2**3)
    # default length: the column width 4b
    assert Collar(y=1.0, t=0.01, h=0.06).lateral_stiffness(b=0.3) == pytest.approx(
        12 * E * (0.01 * 0.06**3 / 12) / 1.2**3
    )


@pytest.mark.parametrize("y", [0.1, 1.0, 3.9])
def test_deformation_from_exact_positions(y):
    theta = np.array([-0.4, -0.1, -1e-3, 1e-3, 0.05, 0.3])
    b = 0.2
    da, dl = collar_deformation_from_positions(theta, b, y)
    da2, dl2 = collar_deformation(theta, b)
    np.testing.assert_allclose(da, da2, atol=1e-15)
    np.testing.assert_allclose(dl, dl2, atol=1e-15)
    # lateral offset = paper Eq. 19 to third order; crack faces touch, never interpenetrate
    np.testing.assert_allclose(dl, 4 * b * np.tan(theta / 2), rtol=0.25 * 0.4**2)
    np.testing.assert_allclose(crack_face_overlap(theta, b, y), 0.0, atol=1e-15)


def test_restoring_moment_is_minus_energy_gradient():
    collars = (Collar(y=1.0, t=0.01, h=0.05), Collar(y=2.5, t=0.008, h=0.04, length=1.1))
    theta = np.linspace(-0.5, 0.5, 21)
    h = 1e-6
    b = 0.25
    fd = -(
        collar_strain_energy(theta + h, b, collars) - collar_strain_energy(theta - h, b, collars)
    ) / (2 * h)
    np.testing.assert_allclose(
        collar_restoring_moment(theta, b, collars), fd, rtol=1e-6, atol=1e-6 * np.abs(fd).max()
    )


def test_kernel_collar_moment_matches_shared_moment(half_column):
    """In the equation of motion the collar moment is shared by the two halves (inertia 2 J0)."""
    collars = (Collar(y=1.0, t=0.01, h=0.05),)
    pulse = pulse_from_ratios(half_column, "sine", 2.0, 2.0, "nonlinear")
    P, rt, ra = kernel_params(half_column, pulse, collars, "nonlinear")
    P_free, *_ = kernel_params(half_column, pulse, (), "nonlinear")
    for theta in (-0.2, 0.05, 0.3):
        s = 1.0 if theta > 0 else -1.0
        extra = K.angular_acceleration(10.0, theta, s, P, rt, ra) - K.angular_acceleration(
            10.0, theta, s, P_free, rt, ra
        )
        expected = collar_restoring_moment(theta, half_column.b, collars) / (2 * half_column.J0)
        assert extra == pytest.approx(float(expected), rel=1e-12)


def test_stress_hand_calculation():
    b, theta = 0.2, 0.01
    c = Collar(y=1.0, t=0.01, h=0.05, pretension=2e3)
    L = 4 * b
    I, A, W = 0.01 * 0.05**3 / 12, 0.01 * 0.05, 0.01 * 0.05**2 / 6  # noqa: E741 (the paper's I)
    d_l = 2 * b * math.sin(theta)
    d_a = 4 * b * (math.sqrt(1 + 0.25 * math.sin(theta) ** 2) - 1)
    N = 2e3 + E * A / L * d_a
    M = 6 * E * I * d_l / L**2
    r = collar_response(theta, b, c)
    assert float(r["axial_force"]) == pytest.approx(N)
    assert float(r["end_moment"]) == pytest.approx(M)
    assert float(r["stress"]) == pytest.approx(abs(N) / A + abs(M) / W)
    assert float(r["utilisation"]) == pytest.approx((abs(N) / A + abs(M) / W) / FY)


def test_collar_history_first_yield(half_column):
    collars = (Collar(y=1.0, t=0.01, h=0.05),)
    result = rock(
        half_column,
        Motion(pulse_from_ratios(half_column, "sine", 2.0, 3.0, "nonlinear")),
        collars,
        model="nonlinear",
    )
    hist = result.collar_histories[0]
    assert hist.max_utilisation > 1.0
    first = np.argmax(hist.utilisation >= 1.0)
    assert hist.first_yield_time == pytest.approx(result.time[first])
    assert np.all(hist.utilisation[:first] < 1.0)
    s = result.summary()
    assert s["collar_first_yield_time"] == pytest.approx(hist.first_yield_time)


def test_sdof_summary_says_its_collars_are_elastic_and_what_that_leaves_out(half_column):
    """The SDOF model's collar springs never yield: its summary names its collar law, and
    where a collar passed f_y, a note naming that collar and its utilisation says that the
    stress past f_y is not one the steel can carry and what is not modelled (the verdict
    says elastic collars were assumed); where none passed f_y there is no note."""
    pulse = pulse_from_ratios(half_column, "sine", 2.0, 3.0, "nonlinear")
    weak = rock(half_column, Motion(pulse), (Collar(y=1.0, t=0.01, h=0.05),), model="nonlinear")
    s = weak.summary()
    assert s["collar_law"] == "elastic" and s["collar_max_utilisation"] > 1.0
    note = s["collar_note"]
    assert note.startswith("elastic collars assumed: collar 1 (y = 1 m, utilisation ")
    assert f"utilisation {s['collar_max_utilisation']:.3g})" in note
    assert "not in this model" in note and "plastic = true" in note
    assert "elastic collars assumed" in s["verdict"]
    strong = rock(
        half_column, Motion(pulse), (Collar(y=1.0, t=0.01, h=0.05, fy=1e11),), model="nonlinear"
    )
    s = strong.summary()
    assert s["collar_law"] == "elastic" and s["collar_max_utilisation"] < 1.0
    assert "collar_note" not in s and "elastic collars assumed" not in s["verdict"]
    bare = rock(half_column, Motion(pulse), model="nonlinear").summary()
    assert "collar_law" not in bare and "collar_note" not in bare


def test_design_hand_calculation(half_column):
    c = Collar(y=1.0, t=0.01, h=0.05)
    b = half_column.b
    L = 4 * b
    My = FY * 0.01 * 0.05**2 / 6
    d_y = My * L**2 / (6 * E * 0.01 * 0.05**3 / 12)  # corrected Eq. 22
    assert d_y == pytest.approx(FY * L**2 / (3 * E * 0.05))
    th_y = 2 * math.atan(d_y / (4 * b))  # Eq. 23
    a_g = 0.35 * 9.81
    m = 2 * half_column.mass
    R, alpha = half_column.R, half_column.alpha
    k = m * R * (a_g * math.cos(alpha - th_y) - 9.81 * math.sin(alpha - th_y)) / (2 * b * d_y)
    d = design_collars(half_column, c, a_g)
    assert d.yield_displacement == pytest.approx(d_y)
    assert d.yield_rotation == pytest.approx(th_y)
    assert d.required_stiffness == pytest.approx(k)
    assert d.collars_needed == math.ceil(k / c.lateral_stiffness(b))


def test_design_is_consistent_with_the_dynamic_model(half_column):
    """Under a constant ground acceleration a_g, a column held by exactly the design stiffness is
    in equilibrium at the yield rotation (corrected Eq. 24 = static limit of the rocking model,
    axial springs neglected as in the paper)."""
    c = Collar(y=1.0, t=0.01, h=0.05)
    a_g = 0.3 * 9.81
    d = design_collars(half_column, c, a_g)
    # a collar of exactly the required lateral stiffness and no axial stiffness
    P = K.make_params(
        half_column.p,
        half_column.alpha,
        True,
        K.GROUND_HARMONIC,
        a_g / 9.81,
        1e-9,
        math.pi / 2,
        1e9,
        0.0,
        4 * half_column.b**2 * d.required_stiffness / half_column.J0,
        0.9,
        math.tan(half_column.alpha),
        0.0,
    )
    empty = np.zeros(1)
    acc = K.angular_acceleration(1.0, -d.yield_rotation, -1.0, P, empty, empty)
    gravity = half_column.p**2 * math.sin(half_column.alpha - d.yield_rotation)
    assert abs(acc) < 2e-3 * gravity


def test_design_chart_monotonic():
    c = Collar(y=1.0, t=0.01, h=0.05)
    alphas = np.linspace(0.05, 0.3, 6)
    ratios = np.linspace(0.1, 0.8, 8)
    k = design_chart(0.3, 2700.0, math.pi * 0.3, c, alphas, ratios)
    assert np.all(np.diff(k, axis=1) > 0)  # stronger pulse, stiffer collars
    assert k[0, 0] < 0 < k[-1, -1] or k[-1, -1] > 0


def test_collar_above_column_top_is_rejected(half_column, tmp_path):
    with pytest.raises(InputError, match="collar 1 y"):
        rock(
            half_column,
            Motion(pulse_from_ratios(half_column, "sine", 2.0, 2.0, "nonlinear")),
            (Collar(y=5.0, t=0.01, h=0.05),),
            model="nonlinear",
        )
    f = tmp_path / "c.toml"
    f.write_text("[[collar]]\ny = 1.0\nt = 0.01\nh = 0.05\nwidth = 3\n")
    with pytest.raises(InputError, match="width"):
        read_collars(f)
    f.write_text("[[collar]]\ny = 1.0\nt = -0.01\nh = 0.05\n")
    with pytest.raises(InputError, match=r"collar\[1\]\.t = -0.01 .* in \(0, 1\], m"):
        read_collars(f)


def test_collars_need_mass():
    blk = Block.from_dimensionless(2.0, 0.2)
    with pytest.raises(InputError, match="mass"):
        rock(
            blk,
            Motion(pulse_from_ratios(blk, "sine", 2.0, 2.0, "nonlinear")),
            (Collar(y=1.0, t=0.01, h=0.05),),
            model="nonlinear",
        )


def test_the_thinnest_band_that_passes_is_the_one_every_thicker_band_confirms():
    """A rocking response need not be monotone in the band: a thin band that passes between
    two that fail is not a design."""
    from colonna.rigid.design import thinnest_passing

    t = [0.003, 0.004, 0.005, 0.006, 0.008]
    assert thinnest_passing(t, [True, False, True, True, True]) == 0.005
    assert thinnest_passing(t[::-1], [True, True, True, False, True]) == 0.005  # any order
    assert thinnest_passing(t, [True] * 5) == 0.003
    assert thinnest_passing(t, [True, True, True, True, False]) is None

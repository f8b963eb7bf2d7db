"""Ground motions and record readers (round trips over files written here)."""

import math

import numpy as np
import pytest

from colonna.rigid import (
    InputError,
    NoMotion,
    Record,
    pulse_from_ratios,
    read_peer_at2,
    read_record,
    read_two_column,
    sine_pulse,
)


def test_sine_pulse_phase_makes_rocking_start_at_zero(zm_block):
    for model in ("linear", "nonlinear"):
        pulse = pulse_from_ratios(zm_block, "sine", 3.0, 2.5, model)
        assert pulse.acceleration(0.0) == pytest.approx(zm_block.uplift_acceleration(model))
        assert pulse.phase == pytest.approx(math.asin(1 / 2.5))
        assert pulse.duration == pytest.approx((2 * math.pi - pulse.phase) / pulse.omega)
        assert pulse.acceleration(pulse.duration + 1e-9) == 0.0
        assert pulse.omega == pytest.approx(3.0 * zm_block.p)


def test_amplitude_below_uplift_is_rejected(zm_block):
    with pytest.raises(InputError, match="amplitude ratio"):
        pulse_from_ratios(zm_block, "sine", 3.0, 0.9)
    with pytest.raises(InputError, match="uplift"):
        sine_pulse(1.0, 5.0, 2.0)


def test_peer_at2_round_trip(tmp_path):
    values = np.sin(np.linspace(0, 6, 23)) * 0.3
    lines = [
        "PEER NGA STRONG MOTION DATABASE RECORD",
        "Test event, station, component",
        "ACCELERATION TIME SERIES IN UNITS OF G",
        "NPTS=   23, DT=   .0100 SEC",
    ]
    body = [" ".join(f"{v:15.7E}" for v in values[i : i + 5]) for i in range(0, values.size, 5)]
    path = tmp_path / "motion.AT2"
    path.write_text("\n".join(lines + body) + "\n")
    rec = read_record(path)
    np.testing.assert_allclose(rec.time, np.arange(23) * 0.01)
    np.testing.assert_allclose(rec.acceleration_values, values * 9.81, rtol=1e-6)
    assert rec.name == "motion"


def test_two_column_csv_round_trip(tmp_path):
    t = np.linspace(0, 1, 11)
    a = np.cos(t)
    path = tmp_path / "acc.csv"
    path.write_text("time,acc\n" + "\n".join(f"{x},{y}" for x, y in zip(t, a)))
    rec = read_two_column(path)
    np.testing.assert_allclose(rec.time, t)
    np.testing.assert_allclose(rec.acceleration_values, a)
    in_g = read_two_column(path, units="g")
    np.testing.assert_allclose(in_g.acceleration_values, a * 9.81)
    assert rec.acceleration(-1.0) == 0.0 and rec.acceleration(2.0) == 0.0
    assert rec.acceleration(0.05) == pytest.approx(0.5 * (a[0] + a[1]))


@pytest.mark.parametrize(
    "text, match",
    [
        ("PEER\nno header here\n1 2 3\n", "NPTS"),
        ("PEER\nx\ny\nNPTS= 10, DT= 0.01 SEC\n1 2 3\n", "NPTS = 10"),
    ],
)
def test_bad_at2_files(tmp_path, text, match):
    path = tmp_path / "bad.at2"
    path.write_text(text)
    with pytest.raises(InputError, match=match):
        read_peer_at2(path)


def test_unreadable_record_names_the_file(tmp_path):
    with pytest.raises(InputError, match="missing.csv"):
        read_record(tmp_path / "missing.csv")
    bad = tmp_path / "bad.csv"
    bad.write_text("0 1\n1 oops\n")
    with pytest.raises(InputError, match="line 2"):
        read_record(bad)
    with pytest.raises(InputError, match="increase"):
        Record(np.array([0.0, 1.0, 0.5]), np.zeros(3))


def test_none_is_not_a_ground_motion():
    """No motion is NoMotion(), with a zero acceleration, end time and peak; None is refused
    with the field named (issue 17: None never means no motion)."""
    from colonna.core.ground import NO_MOTION, GroundMotion
    from colonna.rigid import Block, rock
    from colonna.rigid.multibody import rock_multibody

    assert isinstance(NO_MOTION, GroundMotion)
    assert (NO_MOTION.end_time, NO_MOTION.peak_acceleration) == (0.0, 0.0)
    assert not NO_MOTION.acceleration([0.0, 1.0]).any()
    block = Block.from_dimensionless(p=2.0, alpha=0.2)
    with pytest.raises(InputError, match="ground = None is not a ground motion"):
        rock(block, None, initial_tilt=0.1)
    with pytest.raises(InputError, match="vertical = None is not a ground motion"):
        rock_multibody(block, NoMotion(), initial_tilt=0.1, vertical=None)

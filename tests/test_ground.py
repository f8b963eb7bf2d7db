"""Ground motions and record readers (round trips over files written here)."""

import math

import numpy as np
import pytest

from colonna.core.motion import Motion, Release
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
    t = np.linspace(0, 1, 101)
    a = np.cos(t)
    path = tmp_path / "acc.csv"
    path.write_text("time,acc\n" + "\n".join(f"{x},{y}" for x, y in zip(t, a)))
    rec = read_two_column(path)
    np.testing.assert_allclose(rec.time, t)
    np.testing.assert_allclose(rec.acceleration_values, a)
    for units, factor in (("g", 9.81), ("cm/s2", 0.01), ("gal", 0.01), ("mm/s2", 0.001)):
        np.testing.assert_allclose(
            read_two_column(path, units=units).acceleration_values, a * factor
        )
    with pytest.raises(
        InputError, match="units = 'in/s2' is not one of g, m/s2, cm/s2, gal, mm/s2"
    ):
        read_two_column(path, units="in/s2")
    assert rec.acceleration(-1.0) == 0.0 and rec.acceleration(2.0) == 0.0
    assert rec.acceleration(0.005) == pytest.approx(0.5 * (a[0] + a[1]))


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
        rock(block, Motion(None), release=Release(tilt=0.1))
    # issue 49: the run functions take parameter objects; a bare motion is refused by name
    with pytest.raises(InputError, match=r"motion = NoMotion\(.*\) is not a colonna.Motion"):
        rock(block, NoMotion(), release=Release(tilt=0.1))
    with pytest.raises(InputError, match="vertical = None is not a ground motion"):
        rock_multibody(block, Motion(NoMotion(), vertical=None), release=Release(tilt=0.1))


# --- issue 33: records are never silently misread ------------------------------------------


def _at2(path, header_lines, values, dt="0.0100", npts_line=None):
    """Write a PEER-style AT2 file: the header lines, the NPTS/DT line, five values a line."""
    npts_line = npts_line or f"NPTS=   {len(values)}, DT=   {dt} SEC"
    body = [" ".join(f"{v:15.7E}" for v in values[i : i + 5]) for i in range(0, len(values), 5)]
    path.write_text("\n".join([*header_lines, npts_line, *body]) + "\n")
    return path


VALUES = np.sin(np.linspace(0, 6, 23)) * 0.3


@pytest.mark.parametrize(
    "phrase, factor",
    [
        ("ACCELERATION TIME SERIES IN UNITS OF G", 9.81),
        ("ACCELERATION TIME HISTORY IN UNITS OF G. FILTER POINTS: HP=0.1 Hz LP=40.0 Hz", 9.81),
        ("acceleration time series in units of g", 9.81),
        ("ACCELERATION TIME HISTORY IN UNITS OF CM/SEC/SEC", 0.01),
        ("ACCELERATION IN UNITS OF CM/S/S", 0.01),
        ("ACCELERATION IN UNITS OF CM/S^2", 0.01),
        ("ACCELERATION IN UNITS OF CM/SEC**2", 0.01),
        ("ACCELERATION IN UNITS OF GAL", 0.01),
        ("ACCELERATION IN UNITS OF M/SEC/SEC", 1.0),
        ("ACCELERATION IN UNITS OF M/S^2", 1.0),
        ("ACCELERATION IN UNITS OF MM/S/S", 0.001),
    ],
)
def test_at2_units_come_from_the_header(tmp_path, phrase, factor):
    """A PEER AT2 file in cm/s^2 is read in cm/s^2, not as g (981 times too large)."""
    path = _at2(
        tmp_path / "m.AT2", ["PEER NGA STRONG MOTION DATABASE RECORD", "event", phrase], VALUES
    )
    rec = read_peer_at2(path)
    np.testing.assert_allclose(rec.acceleration_values, VALUES * factor, rtol=1e-6)
    np.testing.assert_allclose(rec.time, np.arange(23) * 0.01)


def test_at2_units_of_the_old_peer_format(tmp_path):
    """The old PEER format: '3930 0.01000 NPTS, DT' after '... IN UNITS OF G'."""
    path = _at2(
        tmp_path / "old.at2",
        ["PEER STRONG MOTION DATABASE RECORD", "event", "ACCELERATION TIME HISTORY IN UNITS OF G"],
        VALUES,
        npts_line="   23    0.01000    NPTS, DT",
    )
    np.testing.assert_allclose(read_record(path).acceleration_values, VALUES * 9.81, rtol=1e-6)


@pytest.mark.parametrize(
    "phrase, match",
    [
        (
            "ACCELERATION TIME SERIES",
            r"record file \S*m\.AT2: no 'UNITS OF \.\.\.' phrase in the header \(lines 1-4\)",
        ),
        ("ACCELERATION IN UNITS OF IN/S/S", r"m\.AT2, line 3: units 'IN/S/S' are not known"),
        (
            "VELOCITY TIME SERIES IN UNITS OF CM/SEC",
            r"m\.AT2, line 3: units 'CM/SEC' are not known",
        ),
    ],
)
def test_at2_without_known_units_is_an_error(tmp_path, phrase, match):
    path = _at2(
        tmp_path / "m.AT2", ["PEER NGA STRONG MOTION DATABASE RECORD", "event", phrase], VALUES
    )
    with pytest.raises(InputError, match=match) as raised:
        read_record(path)
    assert "(known: g, cm/s^2 (gal), m/s^2, mm/s^2)" in str(raised.value)
    assert "\n" not in str(raised.value)


def test_at2_header_with_two_units_is_an_error(tmp_path):
    header = ["IN UNITS OF G", "event", "ACCELERATION IN UNITS OF CM/S/S"]
    with pytest.raises(InputError, match="two units"):
        read_record(_at2(tmp_path / "two.AT2", header, VALUES))


def test_shipped_synthetic_record_states_g():
    """tests/data/synthetic.AT2 says 'UNITS OF G' (as PEER NGA files do) and peaks at 0.25 g."""
    from pathlib import Path

    path = Path(__file__).parent / "data" / "synthetic.AT2"
    assert "UNITS OF G" in path.read_text().splitlines()[2]
    rec = read_record(path)
    assert rec.peak_acceleration == pytest.approx(0.25 * 9.81, rel=1e-6)


def _two_column(path, t, a=None, fmt="{:.6f}"):
    a = np.zeros_like(t) if a is None else a
    path.write_text("".join(f"{fmt.format(x)} {y:.6f}\n" for x, y in zip(t, a)))
    return path


def test_gapped_record_is_an_error_naming_the_gap(tmp_path):
    """1200 rows at 0.01 s, then nothing from 12 s to 22 s: refused, not interpolated across."""
    t = np.concatenate((np.arange(1201) * 0.01, 22.0 + np.arange(100) * 0.01))
    path = _two_column(tmp_path / "gap.txt", t)
    with pytest.raises(InputError) as raised:
        read_record(path)
    assert str(raised.value) == (
        f"record file {path}: the time step from t = 12 s (line 1201) to t = 22 s (line 1202) "
        "is 10 s, the record's step is 0.01 s: gapped or non-uniform sampling is not "
        "interpolated (resample the record uniformly)"
    )


@pytest.mark.parametrize(
    "t, line",
    [
        (np.concatenate((np.arange(100) * 0.01, 1.0 + np.arange(1, 50) * 0.02)), 100),  # rate
        (np.delete(np.arange(300) * 0.005, 150), 150),  # one sample missing
        (np.arange(300) * 0.01 + np.where(np.arange(300) >= 200, 0.001, 0.0), 200),  # a jump
    ],
)
def test_non_uniform_record_is_an_error(tmp_path, t, line):
    with pytest.raises(InputError, match=rf"\(line {line}\) to t = .*non-uniform"):
        read_record(_two_column(tmp_path / "uneven.csv", t))


@pytest.mark.parametrize(
    "dt, fmt",
    [
        (0.02 / 3.0, "{:.4f}"),  # 0.0067, 0.0133, 0.0200: steps of 0.0066 and 0.0067
        (0.005, "{:.3f}"),
        (0.005, "{:g}"),  # 0, 0.005, 0.01, ...: trailing zeros dropped
        (1 / 256, "{:.9g}"),
        (0.01, "{:.7e}"),
    ],
)
def test_uniform_records_printed_rounded_are_read(tmp_path, dt, fmt):
    t = np.arange(12000) * dt
    rec = read_record(_two_column(tmp_path / "r.txt", t, np.sin(t), fmt=fmt))
    np.testing.assert_allclose(rec.time, [float(fmt.format(x)) for x in t])


def test_single_precision_times_are_uniform(tmp_path):
    t = (np.arange(20000) * 0.005).astype(np.float32)
    rec = read_record(_two_column(tmp_path / "f32.txt", t.astype(float), fmt="{:.9g}"))
    assert rec.end_time == pytest.approx(99.995, abs=1e-4)


def test_coarse_record_is_an_error(tmp_path):
    """A 1 Hz record has lost the peaks that rock a column: one line with its step and the
    limit. 0.02 s (50 Hz), what strong-motion databases give at worst, is read."""
    path = _two_column(tmp_path / "slow.txt", np.arange(30.0), np.ones(30))
    with pytest.raises(InputError) as raised:
        read_record(path)
    assert str(raised.value) == (
        f"record file {path}: sampling step 1 s (1 Hz) is coarser than 0.02 s (50 Hz), the "
        "least a record must be sampled at to keep the peaks that rock a column"
    )
    at2 = _at2(tmp_path / "slow.AT2", ["x", "y", "IN UNITS OF G"], VALUES, dt="0.0250")
    with pytest.raises(InputError, match=r"slow\.AT2: sampling step 0\.025 s \(40 Hz\)"):
        read_record(at2)
    read_record(_two_column(tmp_path / "ok.txt", np.arange(100) * 0.02, fmt="{:.2f}"))
    read_record(_at2(tmp_path / "ok.AT2", ["x", "y", "IN UNITS OF G"], VALUES, dt="0.0200"))
    from colonna.core.ground import MAX_RECORD_STEP

    assert MAX_RECORD_STEP == 0.02


def test_uplift_margin_and_the_note_on_a_weak_record():
    from colonna.core.ground import uplift_margin, weak_record_note

    t = np.arange(500) * 0.01
    rec = Record(t, 0.8 * np.sin(2 * np.pi * t), "weak")  # peaks at 0.8 m/s^2
    assert uplift_margin(rec, 1.6) == pytest.approx(0.5, rel=1e-3)
    assert weak_record_note(rec, 0.7) is None  # it rocks
    note = weak_record_note(rec, 1.1)
    assert note == (
        "record 'weak' peaks at 0.8 m/s^2 (scale = 1 included), below the uplift acceleration "
        "g tan(alpha) = 1.1 m/s^2: the record alone does not uplift the column, which stays "
        "at rest"
    )
    in_g = weak_record_note(rec, 1.1, in_m_s2=True)  # 0.8 g would rock it
    assert (
        in_g
        == note + "; if the file's accelerations are in g (it is read in m/s^2), set scale = 9.81"
    )
    assert weak_record_note(rec.scaled(0.5), 1.1, scale=0.5, in_m_s2=True).endswith(
        "set scale = 4.905"
    )
    assert weak_record_note(rec, 8.0, in_m_s2=True) == note.replace("1.1", "8")  # not even in g


def test_a_study_on_a_record_below_uplift_says_so(tmp_path):
    """A two-column record in g, read as m/s^2, never uplifts the column: the study is built
    (a column at rest is an answer) with a RecordNote naming the peak and the uplift."""
    import tomllib

    from tiny_study import TINY_STUDY

    from colonna.core.ground import RecordNote
    from colonna.studies.fem_study import from_dict

    t = np.arange(400) * 0.01
    _two_column(tmp_path / "in_g.txt", t, 0.3 * np.sin(2 * np.pi * t))  # 0.3 "g"
    text = TINY_STUDY.format(amplitude_ratio=2.5, duration=0.1).replace(
        "amplitude_ratio = 2.5\nomega_ratio = 3.0\n", 'pulse = "record"\nrecord = "in_g.txt"\n'
    )
    with pytest.warns(RecordNote) as caught:
        study = from_dict(tomllib.loads(text), "s.toml", base=tmp_path)
    uplift = study.rocking_block.uplift_acceleration("nonlinear")
    assert [str(w.message) for w in caught] == [
        f"s.toml: ground.record 'in_g.txt' peaks at 0.3 m/s^2 (ground.scale = 1 included), below "
        f"the uplift acceleration g tan(alpha) (1 + lambda) of the rocking half = {uplift:.3g} "
        "m/s^2: the record alone does not uplift the column, which stays at rest; if the file's "
        "accelerations are in g (it is read in m/s^2), set ground.scale = 9.81"
    ]
    assert study.ground.peak_acceleration == pytest.approx(0.3, rel=1e-3)
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")  # scaled by g it rocks the column: no note
        from_dict(
            tomllib.loads(text.replace("record = ", "scale = 9.81\nrecord = ")), base=tmp_path
        )


# --- how a two-column file is written (issue 48) ---------------------------------------------

RECORD_T = np.arange(6) * 0.01
RECORD_A = np.array([0.0, 0.5, -1.25, 2.0, -0.75, 0.125])


def _written(path, sep, decimal=".", header=""):
    rows = (f"{t:.2f}{sep}{a:.4f}".replace(".", decimal) for t, a in zip(RECORD_T, RECORD_A))
    path.write_text(header + "\n".join(rows) + "\n")
    return path


@pytest.mark.parametrize("sep, words", [("\t", "tabs"), (" ", "spaces"), (";", "';'")])
def test_decimal_commas_are_named_with_their_line(tmp_path, sep, words):
    """0,01 read with commas between columns would be time 0 on every line ('time must
    increase strictly' before): one line with the file, the line and the cause."""
    path = _written(tmp_path / "commas.txt", sep, ",", header="time acceleration\n")
    with pytest.raises(InputError) as raised:
        read_record(path)
    assert str(raised.value) == (
        f"record file {path}, line 2: decimal commas in {f'0,00{sep}0,0000'!r} (columns "
        f"separated by {words}): use a point as the decimal separator, 0.00 for 0,00"
    )


def test_decimal_commas_between_commas_are_named(tmp_path):
    """'0,01,0,5': every time reads as 0; the line where time stops is named with the cause."""
    path = _written(tmp_path / "commas.csv", ",", ",")
    with pytest.raises(InputError) as raised:
        read_record(path)
    assert str(raised.value) == (
        f"record file {path}, line 2: decimal commas ('0,01,0,5000' reads as time 0 s, as line "
        "1 does): use a point as the decimal separator"
    )


@pytest.mark.parametrize("sep", [";", "; ", ",", ", ", "\t"])
def test_separators_with_points_read_as_spaces_do(tmp_path, sep):
    """Semicolons (a spreadsheet's CSV where the comma is the decimal mark, written with points),
    commas and tabs: the same record as the space-separated file."""
    plain = read_record(_written(tmp_path / "plain.txt", " "))
    np.testing.assert_array_equal(plain.time, RECORD_T.round(2))
    np.testing.assert_array_equal(plain.acceleration_values, RECORD_A)
    other = read_record(_written(tmp_path / "other.txt", sep))
    np.testing.assert_array_equal(other.time, plain.time)
    np.testing.assert_array_equal(other.acceleration_values, plain.acceleration_values)


def test_a_header_line_of_text_is_skipped_and_text_after_data_is_not(tmp_path):
    plain = read_record(_written(tmp_path / "plain.txt", " "))
    header = "Zeit [s];Beschl. [m/s2], Filter ab 0,1 Hz\n"  # a decimal comma in words
    headed = read_record(_written(tmp_path / "h.txt", ";", header=header))
    np.testing.assert_array_equal(headed.acceleration_values, plain.acceleration_values)
    np.testing.assert_array_equal(headed.time, plain.time)
    path = tmp_path / "late.txt"
    path.write_text((tmp_path / "plain.txt").read_text() + "end of record\n")
    with pytest.raises(InputError, match=r"late\.txt, line 7: not numeric: 'end of record'"):
        read_record(path)


@pytest.mark.parametrize("mark", ["|", ":"])
def test_another_column_separator_is_named(tmp_path, mark):
    """'0.01|0.5' is no header: before, every line was skipped as one ('fewer than two rows')."""
    path = _written(tmp_path / "pipe.txt", mark, header="t|a\n")
    with pytest.raises(InputError) as raised:
        read_record(path)
    assert str(raised.value) == (
        f"record file {path}, line 2: columns separated by {mark!r} "
        f"({f'0.00{mark}0.0000'!r}): separate them by spaces, tabs, commas or semicolons"
    )
    # a header of letters and digits is a header: x1 and x2 are no numbers apart
    plain = read_record(_written(tmp_path / "plain.txt", " "))
    headed = read_record(_written(tmp_path / "h.txt", ",", header="x1,x2\n"))
    np.testing.assert_array_equal(headed.acceleration_values, plain.acceleration_values)


def test_a_time_that_stops_increasing_names_its_line(tmp_path):
    path = tmp_path / "back.txt"
    path.write_text("# t a\n0.00 0\n0.01 1\n0.02 2\n0.02 3\n0.03 4\n")
    with pytest.raises(InputError) as raised:
        read_record(path)
    assert str(raised.value) == (
        f"record file {path}, line 5: time 0.02 s is not after 0.02 s on line 4: time must "
        "increase strictly"
    )
    path.write_text("0.00 0\n0.01 1\n0.005 2\n")
    with pytest.raises(InputError, match="line 3: time 0.005 s is not after 0.01 s on line 2"):
        read_record(path)


def test_a_studys_record_with_decimal_commas_is_named_by_its_key(tmp_path):
    import tomllib

    from tiny_study import TINY_STUDY

    from colonna.studies.fem_study import from_dict

    path = _written(tmp_path / "commas.txt", ";", ",")
    text = TINY_STUDY.format(amplitude_ratio=2.5, duration=0.1).replace(
        "amplitude_ratio = 2.5\nomega_ratio = 3.0\n", 'pulse = "record"\nrecord = "commas.txt"\n'
    )
    with pytest.raises(InputError) as raised:
        from_dict(tomllib.loads(text), "s.toml", base=tmp_path)
    assert str(raised.value) == (
        f"s.toml: ground.record = 'commas.txt': record file {path}, line 1: decimal commas in "
        "'0,00;0,0000' (columns separated by ';'): use a point as the decimal separator, 0.00 "
        "for 0,00"
    )

"""A record scaled to a target PGA or PGV (issue 48): the factor is the target over the
record's own peak, the motion applied has that peak to round-off, and the factor is on record
with how it was set. One way to set a record's factor at a time."""

import shutil
from pathlib import Path

import numpy as np
import pytest

from colonna.core.errors import InputError
from colonna.core.intensity import intensity_measures
from colonna.studies.study import load

SUITE = Path(__file__).parents[1] / "studies" / "suites" / "synthetic-pulses"

STUDY = """
[column]
height = 4.0
width = 0.45
[[collar]]
y = 2.0
t = 0.008
h = 0.06
[ground]
pulse = "record"
record = "synth02.AT2"
{scaling}
"""


def _study(tmp_path, scaling: str):
    shutil.copy(SUITE / "synth02.AT2", tmp_path)
    path = tmp_path / "study.toml"
    path.write_text(STUDY.format(scaling=scaling))
    return load(path)


def test_scale_to_pga_gives_a_record_of_that_pga_and_puts_the_factor_on_record(tmp_path):
    study = _study(tmp_path, "scale_to_pga = 3.43")
    ground = study.fem.ground
    assert ground.peak_acceleration == pytest.approx(3.43, rel=1e-12)
    plain = _study(tmp_path, "").fem.ground
    factor = 3.43 / plain.peak_acceleration
    assert np.array_equal(ground.acceleration_values, plain.acceleration_values * factor)
    inputs = study.to_json()
    assert inputs["ground"]["scale"] == pytest.approx(factor, rel=1e-15)
    assert inputs["resolved"]["ground.scale"].startswith(
        "scale_to_pga 3.43 m/s^2 / the record's PGA"
    )
    motion = inputs["ground_motion"]["horizontal"]
    assert motion["peak_acceleration"] == pytest.approx(3.43, rel=1e-12)
    assert motion["file_peak_acceleration"] == pytest.approx(plain.peak_acceleration, rel=1e-12)


def test_scale_to_pgv_gives_a_record_of_that_pgv_as_the_fragility_measures_it(tmp_path):
    study = _study(tmp_path, "scale_to_pgv = 0.5")
    assert intensity_measures(study.fem.ground).pgv == pytest.approx(0.5, rel=1e-12)
    assert study.to_json()["resolved"]["ground.scale"].startswith("scale_to_pgv 0.5 m/s")


@pytest.mark.parametrize(
    "scaling, words",
    [
        ("scale = 2.0\nscale_to_pga = 3.0", "give only one of ground.scale, ground.scale_to_pga"),
        ("scale_to_pga = 3.0\nscale_to_pgv = 0.4", "give only one of ground.scale_to_pga"),
        ("scale_to_pga = -1.0", "ground.scale_to_pga"),
    ],
)
def test_one_factor_at_a_time_and_a_positive_target(tmp_path, scaling, words):
    with pytest.raises(InputError, match=words):
        _study(tmp_path, scaling)


def test_a_pulse_takes_no_record_scaling(tmp_path):
    path = tmp_path / "pulse.toml"
    text = STUDY.format(scaling="").replace('pulse = "record"\nrecord = "synth02.AT2"\n', "")
    path.write_text(text + "amplitude_ratio = 3.0\nomega_ratio = 3.0\nscale_to_pga = 3.0\n")
    with pytest.raises(InputError, match="ground.scale_to_pga"):
        load(path)

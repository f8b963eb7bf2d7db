"""The report's ground-motion figure says what of a record the run applied."""

import json

import numpy as np

from colonna.studies.output import write_csv
from colonna.studies.report import _ground_figure


def _out(tmp_path, duration, record_end=20.0):
    t = np.linspace(0.0, record_end, 401)
    write_csv(
        tmp_path / "ground_motion.csv",
        {
            "t": t,
            "horizontal_acceleration": np.sin(t),
            "vertical_acceleration": np.zeros_like(t),
        },
    )
    (tmp_path / "inputs.json").write_text(json.dumps({"run": {"duration": duration}}))
    return tmp_path


def test_a_record_longer_than_the_run_is_shaded_after_the_run_s_end(tmp_path):
    fig = _ground_figure(_out(tmp_path, duration=5.0))
    assert "t > 5 s, shaded" in fig["caption"]
    assert "after the run's end" in fig["legend"] or any(
        "after the run's end" in str(entry) for entry in fig["legend"]
    )


def test_a_record_the_run_covers_is_drawn_without_a_shade(tmp_path):
    fig = _ground_figure(_out(tmp_path, duration=20.0))
    assert "shaded" not in fig["caption"]
    assert not any("after the run's end" in str(entry) for entry in fig["legend"])

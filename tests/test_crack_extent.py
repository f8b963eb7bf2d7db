"""The crack-extent study kind (issue 51): the column's FEM with its crack over 0 to 100 % of
the height and as found, beside its two rigid limits."""

from __future__ import annotations

import re

import pytest

from colonna.studies.crack_extent.runner import AS_FOUND, FRACTIONS, variants
from colonna.studies.study import load

TINY = """
[study]
name = "tiny-extent"
kind = "crack-extent"
[column]
height = 1.0
width = 0.2
{crack}
[[collar]]
y = 0.75
t = 0.004
h = 0.02
[ground]
amplitude_ratio = 2.5
omega_ratio = 3.0
[mesh]
size = 0.05
grading = 0.0
[run]
duration = 0.6
output_interval = 0.005
replicas = 2
"""


def _study(tmp_path, crack: str):
    path = tmp_path / "tiny.toml"
    path.write_text(TINY.format(crack=crack))
    return load(path)


def test_the_extents_swept_run_from_the_top_or_from_the_base_and_add_the_column_as_found(
    tmp_path,
):
    top = variants(_study(tmp_path, "crack = [0.6, 1.0]"))
    assert list(top) == ["crack-0", "crack-25", "crack-50", "crack-75", "crack-100", AS_FOUND]
    assert [top[f"crack-{round(100 * f)}"].crack for f in FRACTIONS] == [
        (1.0, 1.0),
        (0.75, 1.0),
        (0.5, 1.0),
        (0.25, 1.0),
        (0.0, 1.0),
    ]
    assert top[AS_FOUND].crack == (0.6, 1.0)
    base = variants(_study(tmp_path, "crack = [0.0, 0.5]"))  # from the base: swept so, found
    assert base["crack-25"].crack == (0.0, 0.25) and AS_FOUND not in base
    full = variants(_study(tmp_path, ""))  # no [column] crack: the full height, crack-100
    assert AS_FOUND not in full and full["crack-100"].crack == (0.0, 1.0)


@pytest.mark.slow
def test_a_tiny_column_s_extents_against_its_rigid_limits(tmp_path):
    """Measured on the tiny collared column (0.2 m x 1 m), cracked from the top to mid-height,
    marble defaults, a 2.5 x uplift pulse: every partial crack rocks as the intact column
    (FEM peak 0.058-0.061 rad, the solid SDOF 0.057), the full crack twice as far (0.116);
    no crack grows; the answers are the column's as found."""
    from colonna.studies.driver import run_study_file
    from colonna.studies.executor import RunOptions

    path = tmp_path / "tiny.toml"
    path.write_text(TINY.format(crack="crack = [0.5, 1.0]"))
    s = run_study_file(path, tmp_path / "out", run_options=RunOptions(workers=1, progress=False))
    rows = s["variants"]
    assert list(rows) == ["crack-0", "crack-25", "crack-50", "crack-75", "crack-100"]
    assert s["as_found"] == "crack-50" and s["from_base"] is False
    assert rows["crack-0"]["crack_length_initial"] == 0.0
    assert rows["crack-100"]["crack_length_initial"] == 1.0
    peaks = {n: r["fem_peak_rotation"] for n, r in rows.items()}
    partial = [peaks[n] for n in ("crack-0", "crack-25", "crack-50", "crack-75")]
    assert max(partial) < 1.1 * min(partial) and peaks["crack-100"] > 1.5 * max(partial)
    assert s["limits"]["solid"]["block"] == "column" and s["limits"]["split"]["block"] == "half"
    assert all(r["crack_grows"] == "no" for r in rows.values())
    found = {a["key"]: a for a in s["outcome"]["answers"]}
    assert found["crack_grows"]["answer"] == "no"
    assert found["crack_grows"]["length_initial"] == rows["crack-50"]["crack_length_initial"]
    html = (tmp_path / "out" / "index.html").read_text()
    words = re.sub("<[^>]+>", "", html)
    assert "The column as found is crack-50" in words.replace("\n", " ")
    assert "does the crack grow? (replicas)" in words

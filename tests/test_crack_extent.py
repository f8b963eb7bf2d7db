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


def test_crack_extent_fractions_choose_the_extents_swept(tmp_path):
    """[crack_extent] fractions: today's five by default, or the study's own."""
    base = variants(_study(tmp_path, "crack = [0.6, 1.0]"))
    assert [n for n in base if n != AS_FOUND] == [f"crack-{round(100 * f)}" for f in FRACTIONS]
    path = tmp_path / "own.toml"
    path.write_text(
        TINY.format(crack="crack = [0.6, 1.0]") + "[crack_extent]\nfractions = [0.1, 0.5, 1.0]\n"
    )
    own = variants(load(path))
    assert list(own) == ["crack-10", "crack-50", "crack-100", AS_FOUND]
    assert own["crack-10"].crack == pytest.approx((0.9, 1.0))


@pytest.mark.parametrize(
    "fractions, words",
    [
        ("[0.5, 1.2]", ["crack_extent.fractions[2] = 1.2", "[0, 1]"]),
        ("[-0.1, 1.0]", ["crack_extent.fractions[1] = -0.1", "[0, 1]"]),
        ("[]", ["crack_extent.fractions = [] is not allowed", "1 or more numbers in [0, 1]"]),
        ("[0.5, 0.25]", ["crack_extent.fractions = [0.5, 0.25] must increase"]),
        ("[0.25, 0.252]", ["crack_extent.fractions = [0.25, 0.252]", "whole percent"]),
    ],
)
def test_crack_extent_fractions_out_of_range_name_the_key(tmp_path, fractions, words):
    from colonna.core.errors import InputError

    path = tmp_path / "bad.toml"
    path.write_text(TINY.format(crack="") + f"[crack_extent]\nfractions = {fractions}\n")
    with pytest.raises(InputError) as raised:
        load(path)
    for w in words:
        assert w in str(raised.value), str(raised.value)


def test_crack_extent_is_read_by_its_kind_only(tmp_path):
    from colonna.core.errors import InputError

    path = tmp_path / "other.toml"
    path.write_text(
        TINY.format(crack="").replace('kind = "crack-extent"', 'kind = "cross-check"')
        + "[crack_extent]\nfractions = [0.5]\n"
    )
    with pytest.raises(InputError, match=r"\[crack_extent\] is read by studies of kind"):
        load(path)


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


# --- the answers against the extent, drawn from a hand-made summary (fast) ------------------

STOP = "not applicable: the FEM overturned at t = 1.4 s in {k} of 3 replicas"


def _extent(fraction, peak, over=0, collars="no", util=0.3, ki=0.2, lo=None, hi=None):
    """A variants.<name> row: ``over`` of 3 replicas overturned (then the median is words)."""
    stood = peak is not None and over < 3
    return {
        "crack_from": 1.0 - fraction,
        "crack_to": 1.0,
        "extent_fraction": fraction,
        "crack_length_initial": fraction,
        "fem_peak_rotation": STOP.format(k=over) if over else peak,
        "fem_peak_rotation_min": (lo if lo is not None else 0.9 * peak) if stood else None,
        "fem_peak_rotation_max": (hi if hi is not None else 1.1 * peak) if stood else None,
        "replicas": 3,
        "fem_overturned_replicas": over,
        "fem_overturned": "yes" if over == 3 else "undecided" if over else "no",
        "collars_yield": collars,
        "crack_depth": 1.0,
        "crack_grows": "no",
        "crack_length_final": fraction,
        "crack_tip_KI_ratio": None if fraction in (0.0, 1.0) else ki,
        "crack_tip_KI_ratio_min": None if fraction in (0.0, 1.0) else 0.8 * ki,
        "crack_tip_KI_ratio_max": None if fraction in (0.0, 1.0) else 1.2 * ki,
        "collar_max_utilisation": util,
        "collar_max_utilisation_min": 0.9 * util,
        "collar_max_utilisation_max": 1.1 * util,
        "edge_stress_ratio": 0.1,
        "status": "completed",
    }


def _summary(variants, solid="no", split="yes"):
    def limit(over, peak, block):
        words = "not applicable: the SDOF overturned at t = 1.2 s"
        return {
            "peak_rotation": words if over == "yes" else peak,
            "overturned": over,
            "block": block,
        }

    return {
        "study": "hand-made",
        "as_found": "crack-50",
        "from_base": False,
        "variants": variants,
        "limits": {"solid": limit(solid, 0.05, "column"), "split": limit(split, 0.12, "half")},
    }


def _sweep(**changed):
    rows = {
        "crack-0": _extent(0.0, 0.050),
        "crack-25": _extent(0.25, 0.052),
        "crack-50": _extent(0.5, 0.055),
        "crack-75": _extent(0.75, 0.06),
        "crack-100": _extent(1.0, 0.12, collars="yes", util=1.3),
    }
    rows.update(changed)
    return rows


def test_the_report_says_from_which_extent_the_full_crack_changes_the_answers():
    from colonna.studies.crack_extent.report import full_crack_sentence
    from colonna.studies.crack_extent.summary import load as load_summary

    # the full crack's collars yield, no partial crack's: every partial extent differs
    said = full_crack_sentence(load_summary(_summary(_sweep())))
    assert "changes the answers" in said and "75 % (crack-75: collars yield: no)" in said
    assert "only the full crack itself gives them" in said
    # from 3/4 up the answers are the full crack's (it overturns, its collars yield)
    full = _extent(1.0, None, over=3, collars="yes")
    said = full_crack_sentence(
        load_summary(
            _summary(
                _sweep(
                    **{"crack-75": _extent(0.75, None, over=3, collars="yes"), "crack-100": full}
                )
            )
        )
    )
    assert "overturns: yes; collars yield: yes" in said
    assert "50 % (crack-50: overturns: no, collars yield: no)" in said
    assert "from 75 % of the height up every extent swept answers as the full crack" in said
    # every extent answers as the full crack
    same = {
        n: _extent(f, None, over=3)
        for n, f in (("crack-0", 0.0), ("crack-50", 0.5), ("crack-100", 1.0))
    }
    said = full_crack_sentence(load_summary(_summary(same)))
    assert said.startswith("The full-crack hypothesis never changes the answers on this column")
    assert "(0 %, 50 % of the height)" in said


def test_the_answers_figure_marks_an_overturned_extent_without_a_peak(tmp_path):
    """An extent all of whose replicas overturned has no peak drawn (the stopping angle is no
    value) but a marker in the 'overturned' strip; one where some overturned shows the range
    of those that stood and the marker; the rigid limit that overturned is a line in the
    strip; no text runs off the figure; the CSV leaves the peaks of a stopped extent empty."""
    from colonna.studies.crack_extent.report import (
        LIMIT_MARKS,
        OVERTURNED_MARK,
        OVERTURNED_STRIP,
        answers_figure,
    )
    from colonna.studies.crack_extent.summary import load as load_summary
    from colonna.studies.report import texts_outside

    rows = _sweep(
        **{
            "crack-75": _extent(0.75, 0.07, over=1, lo=0.065, hi=0.075),
            "crack-100": _extent(1.0, None, over=3, collars="yes", util=1.3),
        }
    )
    captured = {}

    import colonna.studies.crack_extent.report as report

    def capture(out, name, fig, caption, data_file=""):
        captured.update(fig=fig, name=name)
        return {"name": name}

    (tmp_path / "figures").mkdir()
    keep = report.figure
    report.figure = capture
    try:
        answers_figure(tmp_path, load_summary(_summary(rows, solid="yes", split="no")))
    finally:
        report.figure = keep
    fig = captured["fig"]
    rot = fig.axes[0]
    cap = rot.get_ylim()[1] / OVERTURNED_STRIP[1]
    points = [
        (float(x), float(y))
        for line in rot.get_lines()
        for x, y in zip(line.get_xdata(), line.get_ydata())
        if len(line.get_xdata()) == 1 or line.get_xdata()[0] == line.get_xdata()[-1]
    ]
    at = lambda f: sorted(y for x, y in points if x == f)  # noqa: E731
    assert at(1.0) == [pytest.approx(OVERTURNED_MARK * cap)]  # the full crack: a marker only
    assert [y for y in at(0.75) if y < cap] == [0.065, 0.065, 0.075, 0.075]  # the stood range
    assert any(y == pytest.approx(OVERTURNED_MARK * cap) for y in at(0.75))
    assert 0.055 in at(0.5)  # a median
    horizontal = {
        round(float(line.get_ydata()[0]) / cap, 3)
        for line in rot.get_lines()
        if len(line.get_xdata()) == 2 and line.get_xdata()[0] != line.get_xdata()[-1]
    }
    assert LIMIT_MARKS["solid"] in horizontal  # the solid limit overturned: in the strip
    assert texts_outside(fig) == []
    csv = (tmp_path / "figures" / "answers.csv").read_text().splitlines()
    head = csv[0].split(",")
    full = dict(zip(head, csv[-1].split(",")))
    assert full["fem_peak_rotation_median"] == "" and full["fem_peak_rotation_max_stood"] == ""
    assert full["fem_overturned_replicas"] == "3.0"


def test_an_extent_s_peak_range_leaves_out_the_replicas_that_overturned():
    from colonna.studies.crack_extent.runner import _stood_peaks

    fem = {
        "max_abs_theta_left": 0.06,
        "max_abs_theta_right": 0.05,
        "status": "completed",
        "statuses": ["completed", "overturned at t = 1.4 s", "completed"],
        "bands": {
            "max_abs_theta_left": {"values": [0.06, 0.78, 0.04]},
            "max_abs_theta_right": {"values": [0.05, 0.70, 0.045]},
        },
    }
    assert _stood_peaks(fem) == [0.06, 0.045]


def test_the_report_page_says_what_the_full_crack_changes_beside_its_answers_figure(tmp_path):
    """The page (from a hand-made summary and histories) carries the sentence of
    :func:`full_crack_sentence`, the answers figure and the rotation histories."""
    from colonna.studies.crack_extent.report import write_report
    from colonna.studies.output import write_csv, write_json

    rows = _sweep(
        **{
            "crack-75": _extent(0.75, None, over=3, collars="yes"),
            "crack-100": _extent(1.0, None, over=3, collars="yes"),
        }
    )
    write_json(tmp_path / "summary.json", _summary(rows))
    for n in rows:
        write_csv(
            tmp_path / "cases" / f"{n}-fem" / "history.csv",
            {"t": [0.0, 0.1], "theta_left": [0.0, 0.01], "theta_right": [0.0, 0.01]},
        )
    words = re.sub(r"\s+", " ", re.sub("<[^>]+>", "", write_report(tmp_path).read_text()))
    assert (
        "The full-crack hypothesis (overturns: yes; collars yield: yes) changes the answers of "
        "the column cracked over 0 % (crack-0: overturns: no, collars yield: no)" in words
    )
    assert "from 75 % of the height up every extent swept answers as the full crack" in words
    assert (tmp_path / "figures" / "answers_extent.png").exists()
    assert (tmp_path / "figures" / "theta_extents.png").exists()


def test_a_sweep_of_part_depth_cracks_says_its_lengths_are_the_through_cracks(tmp_path):
    """With [column] crack_depth < 1 on record (inputs.json), the page says that each crack
    runs through part of the thickness, that its lengths and tips are the through crack's (none
    at the start) and that there is no K_I until a ligament breaks; a through crack, nothing."""
    from colonna.studies.crack_extent.report import write_report
    from colonna.studies.output import write_csv, write_json

    rows = _sweep()
    write_json(tmp_path / "summary.json", _summary(rows))
    for n in rows:
        write_csv(
            tmp_path / "cases" / f"{n}-fem" / "history.csv",
            {"t": [0.0, 0.1], "theta_left": [0.0, 0.01], "theta_right": [0.0, 0.01]},
        )
    inputs = {
        "study": {"name": "hand-made", "kind": "crack-extent"},
        "column": {"height": 1.0, "width": 0.2, "crack": [0.5, 1.0], "crack_depth": 0.5},
        "resolved": {},
        "study_file": "tiny.toml",
        "study_sha256": "0" * 64,
        "colonna_version": "0",
    }
    for depth, said in ((0.5, True), (1.0, False)):
        inputs["column"]["crack_depth"] = depth
        write_json(tmp_path / "inputs.json", inputs)
        words = re.sub(r"\s+", " ", re.sub("<[^>]+>", "", write_report(tmp_path).read_text()))
        sentence = (
            "Each crack runs through 0.5 of the thickness ([column] crack_depth): along it a "
            "ligament of the rest holds"
        )
        assert (sentence in words) == said
        assert ("the crack's lengths below and its tips are the through crack's" in words) == said
        # the given extent (from, to) beside the length the mesh's node pairs run
        assert "crack from" in words and "crack to" in words
        assert "crack length at the start, as run on the mesh&#39;s node pairs" in words


def test_a_part_depth_sweep_compares_with_the_through_crack_of_full_height(tmp_path):
    """With [column] crack_depth < 1 the extents are swept at that depth, but the full height is
    the paper's hypothesis, a crack through the whole thickness: the rigid block of a half is
    its, and the sentence compares the others (the column as found at full height but part
    depth among them) with it."""
    from colonna.studies.crack_extent.report import full_crack_sentence
    from colonna.studies.crack_extent.summary import load as load_summary

    swept = variants(_study(tmp_path, "crack = [0.0, 1.0]\ncrack_depth = 0.4"))
    assert swept["crack-100"].crack == (0.0, 1.0) and swept["crack-100"].crack_depth == 1.0
    assert {swept[n].crack_depth for n in ("crack-0", "crack-50", "crack-75")} == {0.4}
    found = swept[AS_FOUND]  # the full height at part depth is no full crack: run as found
    assert found.crack == (0.0, 1.0) and found.crack_depth == 0.4
    rows = _sweep(**{"as-found": {**_extent(1.0, 0.05), "crack_depth": 0.4}})
    said = full_crack_sentence(load_summary(_summary(rows)))
    assert "(as-found: collars yield: no)" in said  # compared, not the reference
    assert "collars yield: yes" in said.split("changes the answers")[0]  # the through crack's

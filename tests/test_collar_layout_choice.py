"""The collar-layout study's choice (issue 50): a layout is chosen only once every layout before
it in the catalogue's order (lighter, or of equal mass) is refined and fails or is screened to
miss beyond the screening's scatter; and the FEM attempts step to more capacity where no
collar yielded in the failed stripe. The model runs are faked: each elastic walk, plastic walk
and FEM run says what the test needs."""

from __future__ import annotations

import dataclasses
import json
import math

import pytest

# the tiny catalogue (tests/tiny_study.py TINY_LAYOUT), lightest first: no collars, then
# 1 x 4 x 30, 2 x 4 x 30, 1 x 10 x 80, 2 x 10 x 80 mm, each in S235 then S355
S235_1, S355_1 = "1 x 4 x 30 mm S235", "1 x 4 x 30 mm S355"
S235_2, S355_2 = "2 x 4 x 30 mm S235", "2 x 4 x 30 mm S355"


def _tiny_setup(tmp_path, layout_lines: str = ""):
    """The tiny layout study (tests/tiny_study.py) and its Setup, [layout] given more lines
    (its shortlist of 8 among them where they give one)."""
    from tiny_study import TINY_LAYOUT, write_pulse_suite

    from colonna.studies.collar_layout.runner import setup
    from colonna.studies.study import load

    write_pulse_suite(tmp_path)
    path = tmp_path / "layout.toml"
    text = TINY_LAYOUT.format(target=3.2e-3)
    if "shortlist" in layout_lines:
        text = text.replace("shortlist = 8\n", "")
    path.write_text(text + layout_lines)
    study = load(path)
    return study, setup(study)


def _agrees(prefix, i):
    """A FEM run that stands, no collar yielding: agrees where the multibody run stands."""
    return (False, False, 0.5)


def _world(tmp_path, monkeypatch, elastic, plastic, layout_lines="", fem=_agrees):
    """Run the tiny layout study with its runs faked. ``elastic(count, t, record)`` gives the
    elastic walk's first overturning (a level offset from the design level, None: never) and
    its collars' stress (Pa, every level); ``plastic(label, record)`` the plastic walk's first
    overturning (an offset, None: never); ``fem(prefix, record)`` a FEM run's (overturned,
    fractured, utilisation). The target lies between the frequencies of the capacities
    d + 1 + i and d - 2 + i of record i. Returns summary.json, the refinement's cases and the
    FEM case keys."""
    from colonna.studies.collar_layout import runner
    from colonna.studies.executor import RunOptions

    study, s = _tiny_setup(tmp_path, layout_lines)
    d = s.design_level
    top = len(s.levels)

    def level(offset):
        return None if offset is None or d + offset >= top else d + offset

    meets = [d + 1 + i for i in range(4)]
    misses = [d - 2 + i for i in range(4)]
    low = runner.frequency_of(meets, s)["frequency"]
    high = runner.frequency_of(misses, s)["frequency"]
    s = dataclasses.replace(s, target=math.sqrt(low * high))
    monkeypatch.setattr(runner, "setup", lambda _study: s)
    refined: list[dict] = []
    fem_keys: list[str] = []

    def walk(first, k, stress):
        end = top - 1 if k is None else k
        return [
            {"overturned": j == k, "stress": stress, "fractured": False}
            for j in range(first, end + 1)
        ]

    def fake_run_cases(function, cases, out, **kwargs):
        found = {}
        for case in cases:
            key, i = case["key"], case["record"]
            if key.startswith("elastic-"):
                count, t = case["section"][:2]
                offset, stress = elastic(count, t, i)
                found[key] = {"walk": walk(0, level(offset), stress), "seconds": 0.0}
            elif key.startswith("plastic-"):
                refined.append(case)
                k = level(plastic(case["label"], i))
                found[key] = {"walk": walk(case["first"], k, 1.0), "seconds": 0.0}
            else:
                fem_keys.append(key)
                overturned, fractured, utilisation = fem(key.split("-")[0], i)
                found[key] = {
                    "overturned": overturned,
                    "collar_fractured": fractured,
                    "collar_utilisation": utilisation,
                    "fem_seconds": 1.0,
                }
        return found

    monkeypatch.setattr(runner, "run_cases", fake_run_cases)
    monkeypatch.setattr(runner, "run_crosscheck", lambda *a: None)
    out = tmp_path / "out"
    runner.run(study, out, RunOptions(1, None, False, False))
    return json.loads((out / "summary.json").read_text()), refined, fem_keys


def _thin_bars_yield(count, t, i):
    """No collars: overturns below the target's capacities; the 4 mm bars carry 300 MPa before
    the column overturns (S235 yields, S355 not), two of them 400 MPa (both grades yield); the
    10 mm bars 100 MPa: with elastic collars, every layout overturns at d + 1 + i."""
    if count == 0:
        return -2 + i, None
    return 1 + i, (100e6 if t > 0.005 else 400e6 if count == 1 else 300e6)


def _s235_fails(label, i):
    """The plastic runs: the S235 layouts overturn as the column without collars; the S355
    ones as with elastic collars."""
    return -2 + i if "S235" in label else 1 + i


def test_a_layout_is_not_chosen_over_a_lighter_one_left_unrefined(tmp_path, monkeypatch):
    """shortlist = 1: 1 x 4 x 30 S235 is refined and fails; 1 x 4 x 30 S355 and 2 x 4 x 30 S235
    (open: their collars yield first, so the screening cannot rule them out) are beyond the
    shortlist. 2 x 4 x 30 S355, whose collars never yield, meets the target by the screening:
    it used to be chosen with the equal-mass 1 x 4 x 30 S355 unrefined; now nothing is
    chosen, the answer says why, and no FEM stripe is run."""
    s, refined, fem_keys = _world(
        tmp_path, monkeypatch, _thin_bars_yield, _s235_fails, "shortlist = 1\n"
    )
    rows = {r["label"]: r for r in s["layouts"]}
    assert s["chosen"] is None and fem_keys == []
    assert {c["label"] for c in refined} == {S235_1}
    assert rows[S355_1]["decision"] == rows[S235_2]["decision"] == "not refined"
    assert "which the screening cannot decide" in rows[S355_1]["why"]
    assert rows[S355_2]["decision"] == "meets the target, not chosen"
    assert f"({S355_1}, {S235_2}; layout.shortlist = 1)" in rows[S355_2]["why"]
    assert s["answer"].startswith(
        f"No layout is chosen: {S355_2} meets the target {s['target']['frequency']:.2g} per "
        "year by the multibody model"
    )
    assert s["answer"].endswith(
        "2 lighter layouts that the screening cannot rule out were not "
        "refined (beyond layout.shortlist = 1): raise it to decide them."
    )
    assert s["before_first_choice_all_fail"] is None
    # the report: the answer, and the table up to the layout that meets the target
    import re

    from colonna.studies.collar_layout.report import write_report

    write_report(tmp_path / "out")
    html = (tmp_path / "out" / "index.html").read_text()
    assert 'class="bad" id="answer-text">No layout is chosen:' in html
    table = re.search(r'data-table="layouts">(.*?)</table>', html, re.S).group(1)
    cells = [re.findall(r"<td>(.*?)</td>", r) for r in re.findall(r"<tr>(.*?)</tr>", table)]
    assert [c[0] for c in cells if c] == ["no collars", S235_1, S355_1, S235_2, S355_2]
    assert [c[5] for c in cells if c][-1] == "meets the target, not chosen"
    band = {c[0]: c[3] for c in cells if c}  # no band where no fit was judged
    assert band[S355_1] == band[S235_2] == "-"


def test_the_lightest_layout_meeting_the_target_is_chosen_once_every_lighter_one_is_decided(
    tmp_path, monkeypatch
):
    """shortlist = 3: the open layouts are refined in the catalogue's order until one meets
    the target, 1 x 4 x 30 S355, of the same mass as the S235 layout refined and failing; the
    column without collars (no collar to yield: exact) is screened to miss by more than the
    screening's scatter. The report's table of lighter layouts names each one's model."""
    import re

    from colonna.studies.collar_layout.report import write_report

    s, refined, _ = _world(
        tmp_path,
        monkeypatch,
        _thin_bars_yield,
        _s235_fails,
        "shortlist = 3\nfem = false\ncrosscheck = false\n",
    )
    rows = {r["label"]: r for r in s["layouts"]}
    assert s["chosen"]["label"] == S355_1
    assert [c["label"] for c in refined] == [S235_1] * 4 + [S355_1] * 4
    assert rows["no collars"]["decided_by"] == "screening"
    assert "one ladder level higher (the screening's scatter)" in rows["no collars"]["why"]
    assert rows[S235_1]["decided_by"] == "refinement" == s["chosen"]["decided_by"]
    assert (
        "with plastic collars (refined: its collars yield first in 4 records)"
        in (rows[S235_1]["why"])
    )
    assert s["lighter_all_fail"] and s["before_first_choice_all_fail"]
    write_report(tmp_path / "out")
    html = (tmp_path / "out" / "index.html").read_text()
    table = re.search(r'data-table="layouts">(.*?)</table>', html, re.S).group(1)
    cells = [re.findall(r"<td>(.*?)</td>", r) for r in re.findall(r"<tr>(.*?)</tr>", table)]
    band = {c[0]: c[3] for c in cells if c}  # each judged fit's band over the records
    low, high = rows[S235_1]["frequency_entry"]["risk"]["frequency_interval"]
    assert band[S235_1] == f"{low:.3g} to {high:.3g}" and low < rows[S235_1]["frequency"] < high
    assert "a miss of this suite, not a certainty" in html
    by = {c[0]: c[4] for c in cells if c}
    assert by == {
        "no collars": "screened (elastic collars; none yields before the column overturns)",
        S235_1: "refined (plastic collars)",
        S355_1: "refined (plastic collars)",
    }
    assert "All lighter layouts of the catalogue miss the target" in html


def test_a_near_miss_of_the_screening_is_refined_over_the_whole_ladder(tmp_path, monkeypatch):
    """A layout whose collars never yield but whose screened lambda misses the target by less
    than one ladder level in every record (capacities d - 1 + i: 1.09 times the target; one
    level higher, 0.76 times) is not a screened miss: its every record is run with plastic
    collars from the ladder's foot; here the plastic runs meet the target and it is chosen.
    The column without collars (d - 2 + i: 1.97 and 1.09 times) is a screened miss."""
    from colonna.studies.collar_layout.runner import frequency_of, screened_miss, shifted

    def elastic(count, t, i):
        return (-1 + i if count else -2 + i), (1e6 if count else None)

    s, refined, _ = _world(
        tmp_path,
        monkeypatch,
        elastic,
        lambda label, i: 1 + i,
        "fem = false\ncrosscheck = false\n",
    )
    assert [(c["label"], c["record"], c["first"]) for c in refined] == [
        (S235_1, i, 0) for i in range(4)
    ]
    chosen = s["chosen"]
    assert chosen["label"] == S235_1 and chosen["decided_by"] == "refinement"
    assert chosen["frequency"] <= s["target"]["frequency"]
    assert "over the whole ladder (refined: the screening's" not in chosen.get("why", "")
    none = {r["label"]: r for r in s["layouts"]}["no collars"]
    assert none["decided_by"] == "screening" and none["decision"] == "fails"
    assert shifted([3, None, 9, 10], 11, 1) == [4, None, 10, None]
    (tmp_path / "again").mkdir()
    _, setup_ = _tiny_setup(tmp_path / "again")
    d = setup_.design_level
    exact = {"open": [], "records": [{"exact": d - 1 + i} for i in range(4)]}
    lam = frequency_of([d - 1 + i for i in range(4)], setup_)["frequency"]
    assert screened_miss(exact, dataclasses.replace(setup_, target=0.99 * lam)) is None
    miss = screened_miss(exact, dataclasses.replace(setup_, target=0.5 * lam))
    assert miss["frequency"] == lam and 0.5 * lam < miss["shifted"] < lam
    opened = {"open": [0], "records": [{"exact": "open", "from": d}] * 4}
    assert screened_miss(opened, dataclasses.replace(setup_, target=1e-9)) is None


def test_a_near_meet_of_the_screening_is_refined_over_the_whole_ladder(tmp_path, monkeypatch):
    """The other side of the screening's scatter: a layout whose collars never yield and whose
    screened lambda meets the target (capacities d + i: 0.76 times it) but not with every
    record one ladder level lower (d - 1 + i: 1.09 times, as the plastic runs may overturn a
    level lower) is no screened meet: its records run with plastic collars from the ladder's
    foot, and where they overturn that level lower it fails instead of being chosen."""
    from colonna.studies.collar_layout.runner import frequency_of, screened_meet, shifted

    def elastic(count, t, i):
        return (i if count else -2 + i), (1e6 if count else None)

    s, refined, _ = _world(
        tmp_path,
        monkeypatch,
        elastic,
        lambda label, i: -1 + i,
        "fem = false\ncrosscheck = false\n",
    )
    assert (S235_1, 0, 0) in [(c["label"], c["record"], c["first"]) for c in refined]
    row = {r["label"]: r for r in s["layouts"]}[S235_1]
    assert row["decided_by"] == "refinement" and row["decision"] == "fails"
    assert "meets the target by less than its scatter of one ladder level" in row["why"]
    assert s["chosen"] is None or s["chosen"]["label"] != S235_1
    assert shifted([3, None, 0], 11, -1) == [2, 10, 0]
    (tmp_path / "again").mkdir()
    _, setup_ = _tiny_setup(tmp_path / "again")
    d = setup_.design_level
    exact = {"open": [], "records": [{"exact": d + i} for i in range(4)]}
    lam = frequency_of([d + i for i in range(4)], setup_)["frequency"]
    assert screened_meet(exact, dataclasses.replace(setup_, target=1.01 * lam)) is None
    meet = screened_meet(exact, dataclasses.replace(setup_, target=3.0 * lam))
    assert meet["frequency"] == lam and lam < meet["shifted"] <= 3.0 * lam


def _no_yield(prefix, i):
    """FEM runs in which no collar yields (utilisation 0.6), record 0 overturning: the stripe
    overturns one record more than the multibody runs, undecided."""
    return (i == 0, False, 0.6)


def _elastic_all_meet(count, t, i):
    return (1 + i if count else -2 + i), (1e6 if count else None)


def test_the_fem_attempts_step_to_more_capacity_where_no_collar_yields(tmp_path, monkeypatch):
    """The first choice's FEM stripe is undecided with no collar yielding: the next attempt
    skips the same bars in S355 (its runs would be the stripe's) and 1 x 10 x 80 (one
    collar: no more collars than 2), and checks 2 x 4 x 30 S235, one collar more; the report
    says which were skipped and why."""
    from colonna.studies.collar_layout.report import write_report

    s, _, keys = _world(
        tmp_path,
        monkeypatch,
        _elastic_all_meet,
        lambda label, i: 1 + i,
        "fem_attempts = 3\ncrosscheck = false\n",
        fem=_no_yield,
    )
    choice = s["fem_choice"]
    labels = [a["label"] for a in choice["attempts"]]
    assert labels == [S235_1, S235_2, "2 x 10 x 80 mm S235"]
    assert [k.split("-")[0] for k in keys] == ["fem"] * 4 + ["fem2"] * 4 + ["fem3"] * 4
    skipped = {x["label"]: x["why"] for x in choice["skipped"]}
    assert skipped[S355_1] == (
        f"S355 skipped: no collar yielded in the FEM stripe of {S235_1}, so the grade cannot "
        "change its runs"
    )
    assert set(skipped) == {S355_1, S355_2, "1 x 10 x 80 mm S235", "1 x 10 x 80 mm S355"}
    assert skipped["1 x 10 x 80 mm S235"] == (
        f"skipped: fewer collars than {S235_2}, in whose FEM stripe no collar yielded (the "
        "attempts step to more collars or a larger bar)"
    )
    rows = {r["label"]: r for r in s["layouts"]}
    assert rows[S355_1]["decision"] == "skipped by the FEM attempts"
    write_report(tmp_path / "out")
    html = (tmp_path / "out" / "index.html").read_text()
    assert "S355 skipped: no collar yielded in the FEM stripe of 1 x 4 x 30 mm S235" in html


def test_the_fem_attempts_keep_the_catalogues_order_where_a_collar_yields(tmp_path, monkeypatch):
    """Where a collar yielded in the failed stripe, the grade can change the runs: the next
    attempt is the same bars in S355."""

    def yields(prefix, i):
        return (i == 0, False, 1.0 if i == 0 else 0.6)

    s, _, _ = _world(
        tmp_path,
        monkeypatch,
        _elastic_all_meet,
        lambda label, i: 1 + i,
        "crosscheck = false\n",
        fem=yields,
    )
    assert [a["label"] for a in s["fem_choice"]["attempts"]] == [S235_1, S355_1]
    assert s["fem_choice"]["skipped"] == []


@pytest.mark.parametrize(
    "base, other, why",
    [
        ((2, 0.008, 0.06, "S275"), (2, 0.008, 0.06, "S355"), "S355 skipped"),
        ((2, 0.008, 0.06, "S275"), (1, 0.012, 0.10, "S235"), "skipped: fewer collars"),
        ((2, 0.008, 0.06, "S275"), (4, 0.006, 0.05, "S235"), "skipped: a thinner or lower"),
        ((2, 0.008, 0.06, "S275"), (2, 0.008, 0.06, "S355", 2.0, 0.3), "skipped: the bars of"),
        ((2, 0.008, 0.06, "S275"), (3, 0.008, 0.06, "S235"), None),
        ((2, 0.008, 0.06, "S275"), (2, 0.010, 0.08, "S235"), None),
        ((0, 0.0, 0.0, ""), (1, 0.006, 0.05, "S235"), None),
    ],
)
def test_capacity_is_more_collars_or_a_larger_bar(base, other, why):
    from colonna.studies.collar_layout.runner import Candidate, capacity_skip

    other = other if len(other) > 4 else (*other, 2.0)
    found = capacity_skip(Candidate(*base, mass=1.0), Candidate(*other))
    assert (found is None) if why is None else found.startswith(why)


def test_a_recommendation_among_equal_mass_layouts_says_it_is_the_first_of_its_mass():
    """Two attempts overturning as many records, of one mass (the same bars in S235 and S275):
    the first in the catalogue's order is recommended, and the why does not claim less steel
    than the other; of different masses, the lighter, with the least steel."""
    from colonna.studies.collar_layout.runner import recommended

    def attempt(label, mass):
        fem = {"overturned": [True] * 3 + [False] * 7, "fracture_share": 0.0}
        return {"row": {"label": label, "mass": mass}, "fem": {**fem, "fracture_allowed": 0.0}}

    best, why = recommended([attempt("S235", 10.65), attempt("S275", 10.65)])
    assert best["row"]["label"] == "S235"
    assert why == (
        "its FEM stripe overturns 3 of 10 records at the design intensity, as few as any "
        "attempt, with the least steel, the first in the catalogue's order of those of its mass"
    )
    best, why = recommended([attempt("heavy", 12.0), attempt("light", 10.65)])
    assert best["row"]["label"] == "light" and why.endswith(
        "as few as any attempt, with the least steel"
    )

"""The collar-layout study kind (issue 50): its catalogue, the design intensity from the hazard,
the screening's reading of an elastic walk, and (slow) a whole study that names a layout."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from colonna.core.hazard import annual_frequency, power_law
from colonna.studies.collar_layout.runner import (
    STEEL_DENSITY,
    catalogue,
    collar_heights,
    frequency_of,
    intensity_at_return_period,
    record_bounds,
)
from colonna.studies.collar_layout.schema import Layout


def test_collars_are_evenly_spaced_between_their_end_distances():
    assert collar_heights(4.0, 0, 0.5) == []
    assert collar_heights(4.0, 1, 0.5) == [2.0]
    assert np.allclose(collar_heights(4.0, 3, 0.5), [0.5, 2.0, 3.5])
    assert np.allclose(np.diff(collar_heights(6.0, 5, 0.75)), 1.125)


def test_the_catalogue_is_every_count_section_and_grade_lightest_first():
    spec = Layout(
        suite="s",
        counts=[0, 1, 3],
        sections=[[0.006, 0.05], [0.010, 0.08]],
        grades=["S235", "S355"],
        target_frequency=1e-3,
    )
    ring = math.pi * 0.45
    found = catalogue(spec, ring)
    assert len(found) == 1 + 2 * 2 * 2  # no collars once
    assert [c.mass for c in found] == sorted(c.mass for c in found)
    three = next(c for c in found if c.count == 3 and c.t == 0.010 and c.grade == "S355")
    assert three.mass == pytest.approx(3 * 0.010 * 0.08 * ring * STEEL_DENSITY, rel=1e-12)
    assert three.fy == 355e6
    assert found[0].count == 0 and found[0].mass == 0.0


def test_one_target_is_required():
    with pytest.raises(ValueError, match="target_frequency .* or layout.target_probability"):
        Layout(suite="s")
    with pytest.raises(ValueError, match="one of them"):
        Layout(suite="s", target_frequency=1e-3, target_probability=0.02)


@pytest.mark.parametrize("k0, k, period", [(1e-4, 2.5, 475.0), (3e-3, 1.8, 2475.0)])
def test_the_design_intensity_is_the_hazards_at_the_return_period(k0, k, period):
    """On a power law lambda = k0 x^-k the intensity at lambda = 1 / T is (k0 T)^(1/k)."""
    hazard = power_law(k0, k, "pga")
    closed = (k0 * period) ** (1.0 / k)
    found = intensity_at_return_period(hazard, period, [0.5 * closed, 2.0 * closed])
    assert found == pytest.approx(closed, rel=1e-9)
    assert float(annual_frequency(hazard, np.array([found]))[0]) == pytest.approx(1.0 / period)


def _walk(*runs):
    return [{"overturned": o, "stress": s} for o, s in runs]


def test_a_record_that_overturns_before_its_collars_yield_has_its_capacity_exactly():
    walk = _walk((False, 100e6), (False, 200e6), (True, 230e6))
    assert record_bounds(walk, 235e6) == {"exact": 2}
    # the same walk with a weaker grade: the collars yield first, at level 1: open from there
    assert record_bounds(walk, 200e6) == {"exact": "open", "from": 1}


def test_a_record_that_neither_overturns_nor_yields_is_censored_exactly():
    walk = _walk(*[(False, 50e6)] * 12)
    assert record_bounds(walk, 235e6) == {"exact": None}
    assert record_bounds(_walk(*[(False, None)] * 12), 235e6) == {"exact": None}


def test_too_few_overturnings_for_a_fit_give_the_hazards_bound():
    """With one record overturning no dispersion can be fitted: lambda is bounded by the
    hazard's frequency at the lowest capacity (P <= 1 above it)."""

    class Setup:
        levels = np.array([1.0, 2.0, 4.0])
        hazard = power_law(1e-3, 2.0, "pga")

    found = frequency_of([1, None, None], Setup)
    assert found["bound"] is True
    assert found["frequency"] == pytest.approx(1e-3 / 4.0)
    found = frequency_of([None, None, None], Setup)
    assert found["frequency"] == pytest.approx(1e-3 / 16.0)


@pytest.mark.slow
def test_a_study_names_the_lightest_layout_that_meets_its_target(tmp_path, capsys, monkeypatch):
    """The tiny column over the four-pulse suite: the chosen layout meets the target, every
    lighter one fails or was not refined and says why, the report opens with the answer and
    the FEM stripe at the design intensity is on record."""
    from tiny_study import TINY_LAYOUT, write_pulse_suite

    from colonna.studies.cli import main

    write_pulse_suite(tmp_path)
    study = tmp_path / "layout.toml"
    study.write_text(TINY_LAYOUT.format(target=3.2e-3))
    out = tmp_path / "out"
    assert main(["study", str(study), "--out", str(out), "--workers", "1"]) in (0, None)
    s = json.loads((out / "summary.json").read_text())
    chosen = s["chosen"]
    assert chosen is not None, s["answer"]
    assert chosen["frequency"] <= s["target"]["frequency"]
    # every layout before it in the catalogue's order (lighter, or of equal mass): decided
    index = next(i for i, r in enumerate(s["layouts"]) if r["label"] == chosen["label"])
    lighter = s["layouts"][:index]
    for row in lighter:
        assert row["decision"] in (
            "fails",
            "not confirmed by the FEM",
            "skipped by the FEM attempts",
        ), row
        assert row["why"], row
        if row["decision"] == "fails":
            assert row["decided_by"] in ("screening", "refinement"), row
    failed = [r for r in lighter if r["decision"] == "fails" and r.get("frequency") is not None]
    for row in failed:  # a refined layout that fails: its frequency above the target or fracture
        assert row["frequency"] > s["target"]["frequency"] or row["fracture_share"] > 0
    fem = s["fem"]
    assert fem is not None and len(fem["overturned"]) == 4
    from colonna.studies.collar_layout.runner import stripe_agreement

    stripe = [c is not None and c <= s["design_intensity"] for c in chosen["capacities"]]
    assert fem["multibody_overturned"] == stripe
    agreement = stripe_agreement(fem["overturned"], stripe, s["confidence"])
    if fem["fracture_share"] > fem["fracture_allowed"]:
        agreement = "contradicts"
    assert fem["agreement"] == agreement and fem["confirmed"] == (agreement == "confirms")
    names = [r["name"] for r in s["records"]]
    assert fem["fem_only"] == [
        n for n, f, m in zip(names, fem["overturned"], stripe) if f and not m
    ]
    # the chosen layout's cross-check, run as a study of its own in chosen-crosscheck/: its
    # collars the chosen ones, the section's numbers its summary's, its report linked
    from colonna.studies.collar_layout.runner import crosscheck_section

    check = s["crosscheck"]
    assert check is not None and check["refused"] is None, check
    sub = out / "chosen-crosscheck"
    sub_summary = json.loads((sub / "summary.json").read_text())
    ran = json.loads((sub / "inputs.json").read_text())["collar"]
    assert [(c["y"], c["t"], c["h"], c["fy"], c["plastic"]) for c in ran] == [
        (pytest.approx(y), chosen["t"], chosen["h"], chosen["fy"], True) for y in chosen["heights"]
    ]
    assert check["collars"] == [
        {k: c[k] for k in ("y", "t", "h", "fy", "plastic", "pretension")} for c in ran
    ]
    assert {k: check[k] for k in crosscheck_section(sub_summary)} == crosscheck_section(sub_summary)
    answers = {a["key"]: a for a in sub_summary["outcome"]["answers"]}
    toe = next(a for a in check["answers"] if a["key"] == "toe_crushes")
    assert toe["answer"] == answers["toe_crushes"]["answer"]
    assert toe["median"] == answers["toe_crushes"]["median"]
    assert check["record"] == s["records"][check["record_index"]]["name"]
    assert (sub / "index.html").exists()
    # the estimate of a resumed run: every case it expects is saved under the key it expects
    # (the screening's, the FEM stripe's, the cross-check's in its folder) but the refinement's
    # (which layouts it refines is known from the screening only)
    from colonna.studies.collar_layout.runner import expected_work
    from colonna.studies.driver import without_saved
    from colonna.studies.study import load

    expected = expected_work(load(study))
    assert {r.case.split("-")[0] for r in expected.runs} >= {"elastic", "fem", "chosen"}
    left = without_saved(expected, out)
    # and the FEM attempts not needed (the estimate counts layout.fem_attempts of them)
    from colonna.studies.collar_layout.runner import fem_key

    ran = len(s["fem_choice"]["attempts"])
    unneeded = {fem_key(a, i) for a in range(ran, s["fem_choice"]["allowed"]) for i in range(4)}
    assert left.runs and all(
        r.case.startswith("plastic-") or r.case in unneeded for r in left.runs
    ), left.runs
    for run in s["fem"]["runs"]:  # an overturned run's stop is no peak
        assert run["peak_ratio"] is None or not run["overturned"]
    html = (out / "index.html").read_text()
    first = html.index('id="answer-text"')
    assert s["answer"].split(":")[0] in html[first : first + 400]
    assert "Why each lighter layout fails" in html
    assert 'href="chosen-crosscheck/index.html"' in html and "Does the toe crush?" in html
    from browser import assert_report_says_what_summary_says

    assert assert_report_says_what_summary_says(html, s) > 0
    assert "Which collars does this column need?" in capsys.readouterr().out
    # the page in a headless browser: its figure drawn, every number with its unit, the
    # trade-off figure's texts inside it once drawn
    from browser import assert_every_figure_drawn, assert_table_numbers_have_units
    from matplotlib.figure import Figure

    from colonna.studies.collar_layout.report import write_report
    from colonna.studies.report import texts_outside

    keep, checked = Figure.savefig, {}

    def spy(fig, fname, *args, **kwargs):
        checked.setdefault(str(fname), texts_outside(fig))
        return keep(fig, fname, *args, **kwargs)

    monkeypatch.setattr(Figure, "savefig", spy)
    write_report(out)
    assert checked and all(found == [] for found in checked.values()), checked
    assert_table_numbers_have_units(html)
    assert_every_figure_drawn(out / "index.html", tmp_path, at_least=1)


def test_the_pareto_front_keeps_the_layouts_no_lighter_one_beats():
    from colonna.studies.collar_layout.runner import pareto_front

    def row(label, mass, frequency, bound=False):
        return {
            "label": label,
            "mass": mass,
            "frequency": frequency,
            "frequency_entry": {"bound": bound},
        }

    rows = [
        row("none", 0.0, 4e-3),
        row("a", 1.0, 5e-3),  # heavier and worse than none: off the front
        row("b", 2.0, 2e-3),
        row("c", 3.0, 1e-3, bound=True),  # a bound decides nothing
        row("d", 4.0, 1.5e-3),
        {"label": "e", "mass": 5.0, "frequency": None},  # not refined
        row("f", 6.0, 1e-3),
    ]
    assert pareto_front(rows) == ["none", "b", "d", "f"]


@pytest.mark.slow
def test_collars_far_below_yield_give_the_elastic_screenings_capacities():
    """The screening's premise: a plastic collar that never yields is the elastic one, so a
    record's first overturning on the ladder is the same in both models. The two are different
    code paths (the fragility's fast path, the full run with the collars' history) and chaotic
    at impacts, so the capacities agree within the runs' scatter, not bit for bit. Measured on
    the shipped study's column with 2 x 10 x 80 mm S355 collars (utilisation below 0.45 before
    overturning) over the ten records: 8 identical, 2 one level lower with plastic collars
    (lambda 6.6e-4 against 7.5e-4 per year). Here five records that overturn by the seventh
    level: every one within one level, at least three identical (four were)."""
    import dataclasses
    from pathlib import Path

    from colonna.studies.collar_layout.runner import layout_column, setup
    from colonna.studies.fragility import analysis
    from colonna.studies.fragility.models import FREE_TIME_P, multibody_runs
    from colonna.studies.study import load

    s = setup(load(Path(__file__).resolve().parents[1] / "studies" / "collar-layout.toml"))
    first = {}
    for plastic in (False, True):
        one = layout_column(s.column, s.heights[2], 0.010, 0.08, 355e6, plastic=plastic)
        for i in (0, 2, 5, 7, 9):
            record = s.records[i]
            study = dataclasses.replace(
                one, ground=record, duration=record.end_time + FREE_TIME_P / one.rocking_block.p
            )
            for level, scale in enumerate(analysis.scales_for(s.levels, s.intensity[i])):
                run = multibody_runs(study, record, [scale])[0]
                assert run["collar_utilisation"] < 0.6  # far below yield: the premise applies
                if run["overturned"]:
                    first[i, plastic] = level
                    break
    shifts = [first[i, True] - first[i, False] for i in (0, 2, 5, 7, 9)]
    assert all(abs(d) <= 1 for d in shifts), shifts
    assert sum(d == 0 for d in shifts) >= 3, shifts


def test_the_answer_says_when_no_collars_are_needed():
    """The lightest layout that meets the target may be none: the answer says so in words, not
    as a layout of no collars at no heights."""
    from types import SimpleNamespace

    from colonna.studies.collar_layout.runner import answer_text

    s = SimpleNamespace(
        years=50.0, target=1e-3, spec=SimpleNamespace(target_probability=None, shortlist=4)
    )
    none = {"count": 0, "label": "no collars", "heights": [], "frequency": 2.3e-4}
    text = answer_text(s, none, None, [none])
    assert text.startswith("No collars are needed: overturning 0.00023 per year"), text
    two = {"count": 2, "label": "2 x 8 x 60 mm S275", "heights": [0.5, 3.5], "frequency": 9e-4}
    assert answer_text(s, two, None, [two]).startswith("2 x 8 x 60 mm S275 at 0.50, 3.50 m:")


def _tiny_setup(tmp_path, layout_lines: str = ""):
    """The tiny layout study (tests/tiny_study.py) and its Setup, [layout] given more lines."""
    from tiny_study import TINY_LAYOUT, write_pulse_suite

    from colonna.studies.collar_layout.runner import setup
    from colonna.studies.study import load

    write_pulse_suite(tmp_path)
    path = tmp_path / "layout.toml"
    path.write_text(TINY_LAYOUT.format(target=3.2e-3) + layout_lines)
    study = load(path)
    return study, setup(study)


def test_pretension_levels_are_a_catalogue_axis_carried_into_the_models(tmp_path):
    """[layout] pretensions (fractions of the yield force f_y t h): every count, section and
    grade once per level; a pretensioned layout's screening runs its own elastic walk (its
    force changes the elastic motion, its grade alone does not), and its collars carry the
    force into the FEM model and the multibody column as the refinement and FEM build them."""
    from colonna.rigid.block import Block
    from colonna.rigid.multibody import build_column
    from colonna.studies.collar_layout.runner import candidate_column, screen_fy
    from colonna.studies.models import build

    study, s = _tiny_setup(tmp_path, "pretensions = [0.0, 0.3]\n")
    with_collars = [c for c in s.candidates if c.count]
    assert len(with_collars) == 2 * 2 * 2 * 2 and len(s.candidates) == 17
    c = next(
        c for c in with_collars if (c.count, c.t, c.grade, c.pretension) == (2, 0.010, "S355", 0.3)
    )
    force = 0.3 * 355e6 * 0.010 * 0.08
    assert c.pretension_force == pytest.approx(force, rel=1e-12)
    assert c.label == "2 x 10 x 80 mm S355 pretensioned to 85.2 kN (30% of f_y t h)"
    assert c.section == (2, 0.010, 0.08, c.pretension_force)
    plain = next(d for d in with_collars if d.label == "2 x 10 x 80 mm S355")
    assert plain.section == (2, 0.010, 0.08) and plain.pretension_force == 0.0
    from colonna.studies.collar_layout.runner import refinement_key

    assert refinement_key(c, 7) == "plastic-2x10x80-S355-P0.3-007"
    assert refinement_key(plain, 7) == "plastic-2x10x80-S355-007"  # as before pretension
    assert len({d.section for d in with_collars}) == 2 * 2 + 2 * 2 * 2  # P = 0 shared by grades
    # the screening's f_y admits the force (a collar's pretension is at most f_y t h)
    assert screen_fy(0.004, 0.03, 0.9 * 440e6 * 0.004 * 0.03) == pytest.approx(0.9 * 440e6)
    assert screen_fy(0.004, 0.03, 0.0) == 235e6
    one = candidate_column(s.column, s, c)
    assert [k.pretension for k in one.collars] == [pytest.approx(force)] * 2
    assert all(k.plastic and k.fy == 355e6 for k in one.collars)
    model = build(one)
    assert model.collar_props[:, 2] == pytest.approx([force, force])
    block = Block(b=0.15, h=2.0, mass=1000.0)
    column = build_column(block, cracked=True, collars=one.collars)
    assert np.asarray(column.col_props)[:, 2] == pytest.approx([force, force])


def test_the_default_catalogue_has_no_pretension():
    spec = Layout(suite="s", target_frequency=1e-3)
    assert spec.pretensions == [0.0]
    with pytest.raises(ValueError, match="pretensions"):
        Layout(suite="s", target_frequency=1e-3, pretensions=[1.0])


def test_the_crosscheck_file_runs_the_chosen_collars_at_the_design_intensity(tmp_path):
    """The chosen layout's cross-check study: its collars the chosen ones (plastic, with their
    pretension), the study's mesh and run settings, the record of median capacity scaled so
    that its intensity (here PGA over the half's uplift acceleration) is the design
    intensity; a two-column record (read in m/s^2 by [ground]) with the suite's units in the
    scale."""
    from colonna.studies.collar_layout.runner import (
        crosscheck_of,
        crosscheck_study,
        median_record,
    )

    study, s = _tiny_setup(tmp_path)
    assert median_record([3, None, 1, 5]) == 3  # upper median, never overturning highest
    assert median_record([None, 2, 7]) == 2
    chosen = {
        "label": "2 x 4 x 30 mm S275",
        "heights": [0.5, 3.5],
        "t": 0.004,
        "h": 0.03,
        "fy": 275e6,
        "pretension_force": 0.2 * 275e6 * 0.004 * 0.03,
    }
    text, name = crosscheck_study(study, s, chosen, 1)
    assert name == s.suite[1].name
    sub = crosscheck_of(text, tmp_path / "chosen-crosscheck.toml")
    assert sub.kind == "cross-check"
    fem = sub.fem
    assert [(c.y, c.t, c.h, c.fy, c.plastic) for c in fem.collars] == [
        (0.5, 0.004, 0.03, 275e6, True),
        (3.5, 0.004, 0.03, 275e6, True),
    ]
    assert [c.pretension for c in fem.collars] == [pytest.approx(6.6e3)] * 2
    assert fem.mesh_size == s.column.mesh_size and fem.replicas == 2  # the study's
    uplift = s.column.rocking_block.uplift_acceleration("nonlinear")
    assert fem.ground.peak_acceleration / uplift == pytest.approx(s.design, rel=1e-9)


def _crosscheck_summary(peaks_left, peaks_right, overturned=False):
    """A cross-check summary.json's parts that the collar-layout section reads."""
    band = {"n": 3, "missing": 0, "median": 0.02, "min": 0.01, "max": 0.03}
    fem = {
        "bands": {
            "max_abs_theta_left": {**band, "values": peaks_left},
            "max_abs_theta_right": {**band, "values": peaks_right},
        }
    }
    if overturned:
        fem["bands"]["max_abs_theta_left"] = "not applicable: the FEM overturned at t = 1 s"
    toe = {
        "key": "toe_crushes",
        "question": "Does the toe crush?",
        "answer": "no",
        "measure": "toe stress / f_c",
        "median": 0.05,
        "min": 0.04,
        "max": 0.06,
        "unit": "-",
        "caveat": "the local (Winkler) toe pressure reaches 1.4 f_c",
    }
    models = [
        {"model": "FEM, deformable halves", "motion": "rocking", "peak_rotation": 0.025},
        {
            "model": "rigid multibody (the rigid reference)",
            "motion": "overturned",
            "peak_rotation": None,
            "overturn_time": 1.5,
        },
    ]
    return {
        "outcome": {"answers": [toe, {"key": "other", "answer": "yes"}], "models": models},
        "fem": fem,
        "verdict_criteria": {
            "bands": {"peak_ratio": {"median": 1.1, "min": 1.0, "max": 1.2}},
            "tolerances": {"peak": 0.2},
        },
        "verdict": {"toe_crushes": "no"},
        "verdict_caveats": {"sdof_half_model_ok": "its collars would carry 3 times f_y"},
        "stone_fc": 110e6,
    }


def test_the_crosscheck_section_quotes_its_summary():
    """The section's numbers are the cross-check's: the FEM's peak rotation with the range of
    its replicas' peaks (the larger half of each), a model that overturned without a peak,
    the answers the report quotes (others left out) and every caveat once."""
    from colonna.studies.collar_layout.runner import crosscheck_section

    found = crosscheck_section(_crosscheck_summary([0.01, 0.04, 0.02], [0.03, 0.01, 0.02]))
    fem, mb = found["rotations"]
    assert fem["peak_rotation"] == 0.025 and fem["band"] == [0.02, 0.04]
    assert mb["peak_rotation"] is None and mb["overturn_time"] == 1.5 and mb["band"] is None
    assert found["peak_ratio"] == {"median": 1.1, "min": 1.0, "max": 1.2}
    assert found["peak_tolerance"] == 0.2
    assert [a["key"] for a in found["answers"]] == ["toe_crushes"]
    toe = found["answers"][0]
    assert (toe["median"], toe["min"], toe["max"]) == (0.05, 0.04, 0.06)
    assert found["caveats"] == [
        "its collars would carry 3 times f_y",
        "the local (Winkler) toe pressure reaches 1.4 f_c",
    ]
    # a replica that overturned: its stop is no peak, so no band
    stopped = crosscheck_section(_crosscheck_summary([0.01, 0.04, 0.02], [0.03, 0.01, 0.02], True))
    assert stopped["rotations"][0]["band"] is None


def test_a_crosscheck_the_guard_refuses_gives_no_answer(tmp_path, monkeypatch):
    """Where a FEM run of the chosen layout's cross-check is not an answer (the guard refuses
    it), the section says why and holds no number of it; its study file is still written."""
    from colonna.core.errors import InputError
    from colonna.studies.collar_layout.runner import run_crosscheck
    from colonna.studies.executor import RunOptions
    from colonna.studies.guard import UnreliableRun
    from colonna.studies.kinds import KINDS

    study, s = _tiny_setup(tmp_path)
    why = "FEM case fem is unreliable (energy balance error 0.2 > 0.05)"
    error = UnreliableRun

    def refuse(sub, folder, options):
        assert [c.y for c in sub.fem.collars] == [2.0]
        raise error(why)

    monkeypatch.setattr(KINDS["cross-check"].module(), "run", refuse)
    chosen = {
        "label": "1 x 4 x 30 mm S235",
        "heights": [2.0],
        "t": 0.004,
        "h": 0.03,
        "fy": 235e6,
        "pretension_force": 0.0,
        "capacities": [2.0, None, 1.5, 3.0],
    }
    out = tmp_path / "out"
    out.mkdir()
    found = run_crosscheck(study, s, chosen, out, RunOptions(1, None, False, False))
    assert found["refused"] == why and found["record"] == s.suite[3].name
    assert not {"rotations", "answers", "peak_ratio", "report"} & set(found)
    assert (out / "chosen-crosscheck.toml").is_file()
    # nor where the cross-check kind refuses the study itself (it says why)
    error, why = InputError, "chosen-crosscheck.toml: the record stays below the uplift"
    assert (
        run_crosscheck(study, s, chosen, out, RunOptions(1, None, False, False))["refused"] == why
    )


def test_the_fem_stripe_is_compared_record_by_record():
    """The FEM stripe against the multibody runs at the design intensity, record by record:
    confirms where every record agrees; the shipped study's (the FEM overturns synth01, 06
    and 08, the multibody synth01 only: exact McNemar p = 0.5) undecided, the former rule (the
    fit's 0.11 inside the FEM's 90 % interval 0.09-0.61) had said "confirms"; contradicts
    where the differing records lean one way beyond chance (5 of 5: p = 0.0625 < 0.1)."""
    from colonna.studies.collar_layout.runner import mcnemar_p, stripe_agreement

    assert mcnemar_p(0, 0) == 1.0 and mcnemar_p(2, 0) == 0.5
    assert mcnemar_p(5, 0) == pytest.approx(0.0625) and mcnemar_p(3, 1) == pytest.approx(0.625)
    fem = [True, False, False, False, False, True, False, True, False, False]
    multibody = [True] + [False] * 9
    assert stripe_agreement(fem, multibody, 0.9) == "undecided"
    assert stripe_agreement(fem, fem, 0.9) == "confirms"
    assert stripe_agreement([True] * 5 + [False] * 5, [False] * 10, 0.9) == "contradicts"
    assert stripe_agreement([True] * 5 + [False] * 5, [False] * 10, 0.95) == "undecided"


def test_the_answer_says_what_the_fem_stripe_says():
    from types import SimpleNamespace

    from colonna.studies.collar_layout.runner import answer_text

    s = SimpleNamespace(
        years=50.0, target=1e-3, spec=SimpleNamespace(target_probability=None, shortlist=4)
    )
    two = {"count": 2, "label": "2 x 8 x 60 mm S275", "heights": [0.5, 3.5], "frequency": 9e-4}
    said = {
        "confirms": "confirms it.",
        "contradicts": "contradicts it (see the FEM check).",
        "undecided": "neither confirms nor contradicts it (see the FEM check).",
    }
    for agreement, end in said.items():
        assert answer_text(s, two, {"agreement": agreement}, [two]).endswith(end)


def test_a_resumed_estimate_leaves_the_saved_cases_out(tmp_path):
    """studies.driver.without_saved: the runs whose case is saved in out/cases (or, for a case
    ``sub/key``, in out/sub/cases) leave the estimate; a damaged one stays in it."""
    from colonna.studies.driver import without_saved
    from colonna.studies.executor import save_case
    from colonna.studies.work import FemRun, FemWork

    def run(case):
        return FemRun(0, 0, 0, 0, case, other_seconds=1.0)

    work = FemWork(runs=tuple(run(c) for c in ("a", "b", "e", "sub/c", "sub/d")))
    save_case(tmp_path / "cases" / "a", {"key": "a", "sha256": "0"}, {"x": 1})
    save_case(tmp_path / "sub" / "cases" / "c", {"key": "c", "sha256": "0"}, {"x": 2})
    save_case(tmp_path / "cases" / "e", {"key": "e", "sha256": "0"}, {"x": 3})
    (tmp_path / "cases" / "e" / "result.json").write_text('{"x": 4}')  # edited: not saved
    left = without_saved(work, tmp_path)
    assert [r.case for r in left.runs] == ["b", "e", "sub/d"]
    assert left.cpu_seconds == pytest.approx(3.0)


def test_the_screening_and_refinement_run_each_layouts_pretension(tmp_path, monkeypatch):
    """The cases the screening and the refinement hand to their workers: an elastic walk per
    count x section x pretension force, its collars carrying the force (their f_y at least
    the force over the area, as a collar requires); a refined layout's plastic walks with its
    grade's f_y and its force."""
    from colonna.studies.collar_layout import runner
    from colonna.studies.executor import RunOptions
    from colonna.studies.fem_study import study_of_case

    study, s = _tiny_setup(tmp_path, "pretensions = [0.0, 0.9]\n")
    seen: list[dict] = []

    def fake_run_cases(function, cases, out, **kwargs):
        seen.extend(cases)
        return {
            c["key"]: {"walk": [{"overturned": True, "stress": 1.0}], "seconds": 0.0} for c in cases
        }

    monkeypatch.setattr(runner, "run_cases", fake_run_cases)
    options = RunOptions(1, None, False, False)
    runner.screening(s, tmp_path, options)
    forces = {}
    for case in seen:
        collars = study_of_case(case).collars
        section = tuple(case["section"])
        force = section[3] if len(section) > 3 else 0.0
        assert [c.pretension for c in collars] == [force] * section[0], case["key"]
        assert all(not c.plastic and c.fy * c.t * c.h >= force for c in collars)
        forces[section[:3]] = forces.get(section[:3], set()) | {round(force)}
    # S355 at 0.9 of 4 x 30 mm: 38.3 kN, above the screening's S235 yield force 28.2 kN
    assert forces[(1, 0.004, 0.03)] == {0, round(0.9 * 235e6 * 1.2e-4), round(0.9 * 355e6 * 1.2e-4)}
    seen.clear()
    c = next(c for c in s.candidates if c.label.startswith("2 x 10 x 80 mm S355 pretensioned"))
    brackets = {c.label: {"open": [0, 2], "records": [{"from": 3}] * 4}}
    runner.refine([c], brackets, s, tmp_path, options)
    assert [case["record"] for case in seen] == [0, 2]
    for case in seen:
        collars = study_of_case(case).collars
        assert [(k.fy, k.plastic) for k in collars] == [(355e6, True)] * 2
        assert [k.pretension for k in collars] == [pytest.approx(0.9 * 355e6 * 8e-4)] * 2


def _attempts_study(tmp_path, monkeypatch, fem_plan: dict, layout_lines: str = ""):
    """Run the tiny layout study (tests/tiny_study.py TINY_LAYOUT) with its model runs faked:
    each record i overturns first at level design + 1 + i with collars (never yielding, so the
    screening decides every layout: all meet the target) and at design - 2 + i without (fails);
    the FEM run of record i in the case ``fem_plan[prefix]`` gives (overturned, fractured),
    prefix the case key's ("fem", "fem2", ...). The cross-check is asserted to be asked of the
    finally chosen layout, and not run. Returns the summary.json read back, the FEM case keys
    in the order run and the Setup."""
    import dataclasses

    from colonna.studies.collar_layout import runner
    from colonna.studies.executor import RunOptions

    study, s = _tiny_setup(tmp_path, layout_lines)
    d = s.design_level
    assert 2 <= d <= len(s.levels) - 5, s.levels  # room below and above the design level

    def capacity(count: int, i: int) -> int:
        return d + 1 + i if count else d - 2 + i

    none = [capacity(0, i) for i in range(4)]
    one = [capacity(1, i) for i in range(4)]
    low, high = runner.frequency_of(one, s)["frequency"], runner.frequency_of(none, s)["frequency"]
    assert low < high
    s = dataclasses.replace(s, target=math.sqrt(low * high))
    monkeypatch.setattr(runner, "setup", lambda _study: s)
    fem_keys: list[str] = []

    def fake_run_cases(function, cases, out, **kwargs):
        found = {}
        for case in cases:
            key = case["key"]
            if key.startswith("elastic-"):
                k = capacity(case["section"][0], case["record"])
                walk = [
                    {"overturned": j == k, "stress": 1.0, "fractured": False} for j in range(k + 1)
                ]
                found[key] = {"walk": walk, "seconds": 0.0}
            else:
                fem_keys.append(key)
                overturned, fractured, *utilisation = fem_plan[key.split("-")[0]][case["record"]]
                found[key] = {
                    "overturned": overturned,
                    "collar_fractured": fractured,
                    "collar_utilisation": utilisation[0] if utilisation else None,
                    "fem_seconds": 1.0,
                }
        return found

    monkeypatch.setattr(runner, "run_cases", fake_run_cases)
    crosschecked: list[str] = []

    def fake_crosscheck(study, s, chosen, out, options):
        crosschecked.append(chosen["label"])
        return None

    monkeypatch.setattr(runner, "run_crosscheck", fake_crosscheck)
    out = tmp_path / "out"
    runner.run(study, out, RunOptions(1, None, False, False))
    found = json.loads((out / "summary.json").read_text())
    assert crosschecked == [found["chosen"]["label"]]  # the finally chosen layout's
    return found, fem_keys, s


AGREE = [(False, False)] * 4  # the multibody overturns no record at the design intensity
ONE_MORE = [(True, False)] + [(False, False)] * 3  # undecided: 1 of 4 differ, p = 1
TWO_MORE = [(True, False)] * 2 + [(False, False)] * 2  # undecided: p = 0.5
FRACTURES = [(False, True)] + [(False, False)] * 3  # contradicts: a collar fractures
# as ONE_MORE and TWO_MORE, a collar yielding (utilisation 1) in the run that overturns: the
# next attempt then goes in the catalogue's order (tests/test_collar_layout_choice.py)
ONE_MORE_YIELDS = [(True, False, 1.0)] + [(False, False)] * 3
TWO_MORE_YIELDS = [(True, False, 1.0)] * 2 + [(False, False)] * 2


def test_a_contradicted_choice_is_followed_by_the_next_heavier_layout_until_one_is_confirmed(
    tmp_path, monkeypatch
):
    """The FEM contradicts the lightest layout that meets the target (a collar fractures): the
    next heavier one that meets it is FEM-checked (its runs saved as fem2-*), confirmed and
    chosen; no third attempt; the answer, the rows and summary.json say the same."""
    from colonna.studies.collar_layout.runner import NOT_CONFIRMED, _fem_stripe_work

    plan = {"fem": FRACTURES, "fem2": AGREE, "fem3": AGREE}
    s, keys, setup_ = _attempts_study(tmp_path, monkeypatch, plan)
    assert keys == [f"fem-{i:03d}" for i in range(4)] + [f"fem2-{i:03d}" for i in range(4)]
    choice = s["fem_choice"]
    first, second = "1 x 4 x 30 mm S235", "1 x 4 x 30 mm S355"
    assert [a["label"] for a in choice["attempts"]] == [first, second]
    assert [a["agreement"] for a in choice["attempts"]] == ["contradicts", "confirms"]
    assert choice["first"] == first and choice["confirmed"] == second == choice["chosen"]
    assert choice["stopped"] == "confirmed"
    assert s["chosen"]["label"] == second and s["fem"] == choice["attempts"][1]["fem"]
    rows = {r["label"]: r for r in s["layouts"]}
    assert rows[first]["decision"] == NOT_CONFIRMED and "contradicts it" in rows[first]["why"]
    assert rows[second]["decision"] == "chosen" and rows["no collars"]["decision"] == "fails"
    assert not s["lighter_all_fail"] and s["lighter_all_fail_or_not_confirmed"]
    assert s["answer"].startswith(f"{second} at 2.00 m: overturning")
    assert s["answer"].endswith(
        f"confirms it, not the lighter {first} (contradicted) that met the target by the "
        "multibody model (see the FEM check)."
    )
    # the estimate counts both attempts' runs (an upper bound), under the keys they are saved at
    assert {r.case for r in _fem_stripe_work(setup_).runs} == set(keys)


def test_the_reports_fem_section_lists_each_attempt(tmp_path, monkeypatch):
    """The report's FEM section: each layout FEM-checked, in order, with its comparison, the
    chosen one marked, and what the attempts found."""
    import re

    from colonna.studies.collar_layout.report import write_report

    plan = {"fem": FRACTURES, "fem2": AGREE}
    _attempts_study(tmp_path, monkeypatch, plan)
    first, second = "1 x 4 x 30 mm S235", "1 x 4 x 30 mm S355"
    write_report(tmp_path / "out")
    html = (tmp_path / "out" / "index.html").read_text()
    table = re.search(r'data-table="fem-attempts">(.*?)</table>', html, re.S).group(1)
    cells = [re.findall(r"<td>(.*?)</td>", row) for row in re.findall(r"<tr>(.*?)</tr>", table)]
    cells = [c for c in cells if c]
    assert [c[0] for c in cells] == [first, f"{second} (chosen)"]
    assert [c[-1] for c in cells] == [
        "contradicts (collars fracture beyond the allowance)",
        "confirms",
    ]
    assert f"The FEM confirms {second}, not the lighter" in html


def test_no_confirmed_attempt_recommends_the_one_the_fem_overturns_least(tmp_path, monkeypatch):
    """Three attempts, none confirmed (undecided twice, then contradicted; a collar yields in
    each stripe): all three run in the catalogue's order and the study recommends the one
    whose FEM stripe overturns the fewest records within the fracture allowance, here the
    first, saying so."""
    plan = {"fem": ONE_MORE_YIELDS, "fem2": TWO_MORE_YIELDS, "fem3": FRACTURES}
    s, keys, _ = _attempts_study(tmp_path, monkeypatch, plan, "fem_attempts = 3\n")
    assert [k.split("-")[0] for k in keys] == ["fem"] * 4 + ["fem2"] * 4 + ["fem3"] * 4
    choice = s["fem_choice"]
    labels = [a["label"] for a in choice["attempts"]]
    assert labels == ["1 x 4 x 30 mm S235", "1 x 4 x 30 mm S355", "2 x 4 x 30 mm S235"]
    assert [a["agreement"] for a in choice["attempts"]] == ["undecided", "undecided", "contradicts"]
    assert choice["confirmed"] is None and choice["chosen"] == labels[0] == s["chosen"]["label"]
    assert choice["stopped"] == "layout.fem_attempts = 3 reached"
    assert choice["why"] == (
        "its FEM stripe overturns 1 of 4 records at the design intensity, the fewest of the "
        "attempts"
    )
    assert s["fem"] == choice["attempts"][0]["fem"]
    assert f"confirm none of the 3 layouts checked ({labels[0]}: undecided; " in s["answer"]
    assert s["answer"].endswith(f"recommended as {choice['why']}.")
    decisions = {r["label"]: r["decision"] for r in s["layouts"]}
    assert [decisions[x] for x in labels] == ["chosen"] + ["not confirmed by the FEM"] * 2


def test_a_single_attempt_says_why_no_other_was_checked(tmp_path, monkeypatch):
    """layout.fem_attempts = 1: the undecided first choice stays chosen, the answer says so and
    why no other layout was checked; a confirmed first choice is the one attempt."""
    s, keys, _ = _attempts_study(tmp_path, monkeypatch, {"fem": ONE_MORE}, "fem_attempts = 1\n")
    assert len(keys) == 4 and s["fem_choice"]["confirmed"] is None
    assert s["answer"].endswith(
        "neither confirms nor contradicts it (see the FEM check); no other layout was "
        "FEM-checked: layout.fem_attempts = 1 reached."
    )
    (tmp_path / "b").mkdir()
    s, keys, _ = _attempts_study(tmp_path / "b", monkeypatch, {"fem": AGREE})
    assert len(keys) == 4 and s["fem_choice"]["confirmed"] == s["chosen"]["label"]
    assert s["answer"].endswith("the FEM stripe at the design intensity confirms it.")


def test_fem_attempts_out_of_range_names_the_key():
    with pytest.raises(ValueError, match="fem_attempts"):
        Layout(suite="s", target_frequency=1e-3, fem_attempts=0)
    with pytest.raises(ValueError, match="fem_attempts"):
        Layout(suite="s", target_frequency=1e-3, fem_attempts=11)
    assert Layout(suite="s", target_frequency=1e-3).fem_attempts == 2

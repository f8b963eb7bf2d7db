"""The report's opening: each answer's word follows its number.

Values on both sides of every limit and tolerance (f_y and f_c against the band widened by the
mesh uncertainty; the rigid-body counts' peak, history and impact tolerances) go through the
functions that make the answers, and through the template that prints them: the word and the
sentence are generated from the one comparison, so they cannot disagree.
"""

import re

import numpy as np
import pytest

from colonna.core.collar import Collar
from colonna.fem.ensemble import band
from colonna.studies.crosscheck import runner as crosscheck
from colonna.studies.outcome import (
    QUESTIONS,
    CollarOutcome,
    ReplicaCount,
    collars_hold,
    criteria_answer,
    fem_answers,
    limit_answer,
    model_outcome,
    none_assessed,
    not_assessed,
    outcome,
)
from colonna.studies.report import TEMPLATES, num

PAGE = TEMPLATES.from_string(
    '{% from "macros.html.j2" import outcome_section with context %}{{ outcome_section() }}'
)


def _render(summary: dict) -> str:
    return PAGE.render(s=summary, num=lambda *a, **k: num(summary, *a, **k))


def _cell(page: str, key: str, attribute: str) -> str:
    found = re.search(rf'<[^>]*{attribute}="{key}"[^>]*>(.*?)</(td|span)>', page, re.S)
    return re.sub(r"<[^>]+>", "", found.group(1)).strip()


def _summary(answers: dict) -> dict:
    model = model_outcome("FEM", False, 0.01, 0.1, None, replicas=ReplicaCount(8, 0))
    return {"outcome": outcome([model], answers)}


@pytest.mark.parametrize("limit", [1.0])
@pytest.mark.parametrize("uncertainty", [0.0, 0.05])
@pytest.mark.parametrize(
    "low, high",
    [(0.80, 0.90), (0.90, 0.999), (0.98, 1.02), (1.0, 1.1), (1.2, 1.3), (0.96, 0.99), (1.01, 1.04)],
)
def test_the_word_follows_the_band_against_the_limit(low, high, uncertainty, limit):
    b = band([low, 0.5 * (low + high), high])
    answers = {
        key: limit_answer(
            QUESTIONS[key], "stress / strength", b, limit, "-", uncertainty, figure="x"
        )
        for key in ("collars_yield", "toe_crushes")
    }
    answers["rigid_assumption_ok"] = not_assessed(QUESTIONS["rigid_assumption_ok"], "elsewhere")
    bottom, top = low * (1.0 - uncertainty), high * (1.0 + uncertainty)
    expected = "yes" if bottom >= limit else "no" if top < limit else "undecided"
    relation = {"yes": "reaches", "no": "stays below", "undecided": "straddles"}[expected]
    page = _render(_summary(answers))
    for key in ("collars_yield", "toe_crushes"):
        assert answers[key]["answer"] == expected
        assert _cell(page, key, "data-answer") == expected
        assert _cell(page, key, "data-relation") == relation
    # the numbers beside the word are the band's
    assert f">{high:.3g}<" in page and f">{low:.3g}<" in page


@pytest.mark.parametrize("ratio, ok", [(1.19, True), (1.21, False), (0.81, True), (0.79, False)])
def test_peak_count_on_both_sides_of_its_tolerance(ratio, ok):
    c = _criteria(fem_peak=ratio * 0.02, mb_peak=0.02)
    assert crosscheck.PEAK_TOLERANCE == pytest.approx(0.2)
    assert c["peak_ok"] is ok and c["peak_ratio"] == pytest.approx(ratio)


def test_peak_count_does_not_apply_where_a_model_overturns():
    c = _criteria(fem_peak=0.05, mb_peak=0.02, fem_overturned=True)
    assert c["peak_ok"] is None and c["peak_ratio"] is None and not c["same_outcome"]
    assert crosscheck.count_word([None, None]) == "not applicable"
    assert crosscheck.count_word([None, True]) == "yes"


def test_a_column_both_models_keep_at_rest_agrees_whatever_its_sway():
    """No uplift in either model (rotations below 1e-4 alpha): the FEM's is elastic sway, its
    sign changes vibration, so the counts of rocking do not apply and the outcomes agree (they
    had said 'no' on a peak ratio of 1.5e6 between 2e-7 and 1e-13 rad). Where one model uplifts
    and the other does not, the outcomes differ."""
    c = _criteria(fem_peak=2e-7, mb_peak=1e-13, impacts_mb=0)
    assert c["at_rest"] and c["same_outcome"] and c["all_ok"]
    assert c["peak_ok"] is None and c["impacts_ok"] is None and c["history_ok"] is None
    rocking = _criteria(fem_peak=0.002, mb_peak=1e-13, impacts_mb=0)
    assert not rocking["at_rest"] and not rocking["same_outcome"] and not rocking["all_ok"]


@pytest.mark.parametrize("error, ok", [(0.09, True), (0.11, False)])
def test_history_count_on_both_sides_of_its_tolerance(error, ok):
    assert crosscheck.HISTORY_TOLERANCE == pytest.approx(0.10)
    c = _criteria(fem_peak=0.02, mb_peak=0.02, history_error=error)
    assert c["history_error"] == pytest.approx(error, rel=1e-6) and c["history_ok"] is ok


@pytest.mark.parametrize("impacts_mb, ok", [(1, True), (2, False), (0, False)])
def test_impact_count_on_both_sides_of_its_tolerance(impacts_mb, ok):
    assert crosscheck.IMPACT_TOLERANCE == 0
    c = _criteria(fem_peak=0.02, mb_peak=0.02, impacts_mb=impacts_mb)
    assert c["impacts_fem"] == 1 and c["impacts_ok"] is ok


@pytest.mark.parametrize(
    "words, answer",
    [
        (("yes", "yes", "yes", "not applicable"), "yes"),
        (("yes", "no", "yes", "yes"), "no"),
        (("yes", "undecided", "yes", "yes"), "undecided"),
    ],
)
def test_the_rigid_answer_lists_its_counts_by_their_word(words, answer):
    names = ("same outcome", "peak rotation", "impacts", "history")
    a = criteria_answer(
        QUESTIONS["rigid_assumption_ok"], answer, dict(zip(names, words)), figure="theta"
    )
    answers = {
        "rigid_assumption_ok": a,
        "collars_yield": not_assessed(QUESTIONS["collars_yield"], "no collars"),
        "toe_crushes": not_assessed(QUESTIONS["toe_crushes"], "no FEM"),
    }
    page = _render(_summary(answers))
    text = _cell(page, "rigid_assumption_ok", "data-answer")
    assert text == answer
    for name, word in zip(names, words):
        listed = {
            "no": a["failed"],
            "undecided": a["undecided"],
            "yes": a["passed"],
            "not applicable": a["not_applicable"],
        }[word]
        assert name in listed
    if answer == "no":
        assert "failed in every replica: peak rotation" in re.sub(r"\s+", " ", page)
    assert "no collars" in page and "not assessed" in page


def test_an_overturned_model_shows_no_rotation_and_names_the_stopping_rule():
    m = model_outcome("SDOF", True, np.pi / 2, 0.1, 1.4)
    assert m["motion"] == "overturned" and m["peak_rotation"] is None
    page = _render(
        {"outcome": outcome([m], {k: not_assessed(q, "-") for k, q in QUESTIONS.items()})}
    )
    assert "1.57" not in page and "overturns" in page and "overturning rule" in page
    assert model_outcome("x", False, 1e-9, 0.1)["motion"] == "no uplift"


@pytest.mark.parametrize(
    "fractured, replicas, hold", [("no", 0, "yes"), ("yes", 8, "no"), ("undecided", 3, "undecided")]
)
def test_the_collars_hold_where_no_plastic_collar_fractured(fractured, replicas, hold):
    """ "Do the collars hold?" turns the replicas' "a collar fractured" round (a plastic collar
    beside an elastic one is enough to ask it), and the page says the count behind the word,
    coloured good only for yes, with the link to the hinge figure."""
    collars = (Collar(y=1.0, t=0.004, h=0.02, plastic=True), Collar(y=2.0, t=0.004, h=0.02))
    fem = {
        "collar_fractured_answer": fractured,
        "collar_fractured_replicas": replicas,
        "replicas": 8,
    }
    a = collars_hold(fem, collars, figure="collar_hinge")
    assert a["answer"] == hold and a["count"] == replicas and a["points"] == 8
    answers = {k: not_assessed(q, "elsewhere") for k, q in QUESTIONS.items()}
    answers["collars_hold"] = a
    page = _render(_summary(answers))
    assert _cell(page, "collars_hold", "data-answer") == hold
    text = re.sub(r"\s+", " ", re.sub(r"<[^>]+>", "", page))
    assert f"a collar fractured (its extreme fibre reached eps_u): {replicas} of 8" in text
    assert 'href="#figure-collar_hinge"' in page
    colour = re.search(r'data-answer="collars_hold" class="([^"]+)"', page).group(1)
    assert colour == {"yes": "good", "no": "bad", "undecided": "undecided"}[hold]
    # the four answers in QUESTIONS' order
    assert [a["key"] for a in _summary(answers)["outcome"]["answers"]] == list(QUESTIONS)


def test_whether_collars_hold_is_asked_only_of_plastic_collars_and_where_a_study_asks_it():
    """Elastic collars are never followed past f_y, so whether they hold is not assessed
    (saying how to assess it); a study that does not ask the question (free rocking, the
    spectrum cross-check) lists the other three; a model whose collar broke says so."""
    fem = {"collar_fractured_answer": "no", "collar_fractured_replicas": 0, "replicas": 8}
    elastic = collars_hold(fem, (Collar(y=1.0, t=0.004, h=0.02),))
    assert elastic["answer"] == "not assessed" and "set plastic = true" in elastic["why"]
    assert collars_hold(fem, ())["why"] == "the column has no collars"
    three = ["rigid_assumption_ok", "collars_yield", "toe_crushes"]
    asked = {k: not_assessed(q, "-") for k, q in QUESTIONS.items() if k in three}
    # "Does the column stay up?" first, made from the models (none here: not assessed)
    assert [a["key"] for a in outcome([], asked)["answers"]] == ["stays_up", *three]
    assert [a["key"] for a in none_assessed("no ground motion")["answers"]] == ["stays_up", *three]
    with pytest.raises(KeyError):  # the three are always answered, if only as not assessed
        outcome([], {"collars_hold": elastic})
    broken = model_outcome(
        "multibody", False, 0.02, 0.1, collars=CollarOutcome(1.3, fractured=True)
    )
    assert broken["collar_state"] == "fractured"
    yielded = model_outcome("multibody", False, 0.02, 0.1, collars=CollarOutcome(1.3))
    assert yielded["collar_state"] == "yielded"
    # no collars (a utilisation of None) say no collar state
    assert "collar_state" not in model_outcome("x", False, 0.02, 0.1, collars=CollarOutcome(None))
    page = _render(
        {"outcome": outcome([broken], {k: not_assessed(q, "-") for k, q in QUESTIONS.items()})}
    )
    assert re.search(
        r'<span class="bad"><span data-key="outcome\.models\.0\.collar_state">fractured', page
    )


def _criteria(fem_peak, mb_peak, fem_overturned=False, history_error=0.0, impacts_mb=1):
    """crosscheck._criteria_one on synthetic histories: the multibody rotation one sine lobe
    of amplitude mb_peak then a smaller one (an impact at t = 0.5), the FEM's the same scaled
    to fem_peak plus a bump of history_error * mb_peak before the first impact."""
    t = np.linspace(0.0, 1.0, 2001)
    shape = np.where(t < 0.5, np.sin(2 * np.pi * t), 0.5 * np.sin(2 * np.pi * t))
    theta_mb = mb_peak * shape
    theta_fem = theta_mb + history_error * mb_peak * np.exp(-(((t - 0.25) / 0.02) ** 2))
    theta_fem = theta_fem * (fem_peak / np.max(np.abs(theta_fem)))
    if fem_peak == mb_peak:
        theta_fem = theta_mb + history_error * mb_peak * np.exp(-(((t - 0.25) / 0.02) ** 2))

    class Study:
        rocking_alpha = 0.1

        class ground:
            end_time = 0.75

    fem = {
        "overturned": fem_overturned,
        "max_abs_theta_left": fem_peak,
        "max_abs_theta_right": fem_peak,
    }
    mb = {"overturned": False, "max_abs_theta_left": mb_peak, "max_abs_theta_right": mb_peak}
    history = {"t": t, "theta_left": theta_fem, "theta_right": theta_fem}
    return crosscheck._criteria_one(
        Study, fem, history, mb, t, [theta_mb, theta_mb], impacts_mb, 0.5
    )


def test_a_study_whose_fem_runs_alone_asks_whether_plastic_collars_hold():
    """The design, mesh-convergence and solid-vs-cracked studies answer from their FEM
    ensemble alone (fem_answers): with a plastic collar they also ask "Do the collars hold?",
    its word turned round from the replicas' fracture count; with elastic collars (never followed
    past f_y) or none they leave it out, and without collars "Do the collars yield?" is not
    assessed."""
    fem = {
        "bands": {
            "collar_max_utilisation": band([1.1, 1.2, 1.3]),
            "edge_stress_ratio": band([0.1]),
        },
        "collar_fractured_answer": "yes",
        "collar_fractured_replicas": 8,
        "replicas": 8,
    }
    elastic = (Collar(y=1.0, t=0.004, h=0.02),)
    plastic = (Collar(y=1.0, t=0.004, h=0.02, plastic=True),)
    asked = fem_answers(fem, "-", plastic)
    assert asked["collars_hold"]["answer"] == "no" and asked["collars_hold"]["count"] == 8
    assert asked["collars_yield"]["answer"] == "yes"
    # every question but the partial crack's (asked only with one)
    assert [a["key"] for a in outcome([], asked)["answers"]] == list(QUESTIONS)[:-1]
    assert list(QUESTIONS)[-1] == "crack_grows"
    assert "collars_hold" not in fem_answers(fem, "-", elastic)
    bare = fem_answers(fem, "-", ())
    assert "collars_hold" not in bare and bare["collars_yield"]["answer"] == "not assessed"

"""Bands over replicas and the answers decided on them (colonna.fem.ensemble), and the study's
stop on a run whose energy balance failed."""

import pytest

from colonna.core.errors import NumericalFailure
from colonna.fem.ensemble import (
    LANDING_DEPENDENT,
    band,
    decide,
    decide_count,
    ensemble_summary,
    median_replica,
)


def test_band_counts_missing_values_and_keeps_every_value():
    b = band([0.9, None, 1.1, float("nan"), 1.0])
    assert (b["median"], b["min"], b["max"]) == (1.0, 0.9, 1.1)
    assert b["n"] == 5 and b["missing"] == 2
    assert b["values"][1] is None
    empty = band([None, None])
    assert empty["median"] is None and empty["missing"] == 2


@pytest.mark.parametrize(
    "values, uncertainty, word",
    [
        ([1.01, 1.05, 1.2], 0.0, "yes"),  # the whole band past the limit
        ([0.5, 0.7, 0.99], 0.0, "no"),  # none of it
        ([0.95, 1.0, 1.05], 0.0, "undecided"),  # straddles it
        ([1.01, 1.05], 0.02, "undecided"),  # past it, but not once the mesh error is added
        ([0.9, 0.97], 0.02, "no"),  # below it even so
        ([0.97, 0.98], 0.05, "undecided"),  # the mesh error reaches the limit
    ],
)
def test_decide_follows_the_band_on_each_side_of_the_limit(values, uncertainty, word):
    assert decide(band(values), 1.0, uncertainty) == word


def test_decide_is_undecided_where_some_replicas_have_no_value():
    assert decide(band([1.2, None, 1.3]), 1.0) == "undecided"
    assert decide(band([None, None]), 1.0) == "undecided"
    assert decide(band([0.2, None]), 1.0) == "no"


def test_decide_count():
    assert decide_count([True, True]) == "yes"
    assert decide_count([False, False]) == "no"
    assert decide_count([True, False, True]) == "undecided"


def test_ensemble_summary_medians_bands_and_majority():
    runs = [
        {
            "overturned": o,
            "status": "s",
            "collar_max_utilisation": u,
            "collar_first_yield_time": ty,
            "edge_stress_max": 1e6 * u,
        }
        for o, u, ty in ((True, 0.8, None), (False, 1.1, 0.5), (True, 0.9, None))
    ]
    s = ensemble_summary(runs, LANDING_DEPENDENT)
    assert s["collar_max_utilisation"] == 0.9 and s["edge_stress_max"] == 0.9e6
    assert s["bands"]["collar_max_utilisation"]["max"] == 1.1
    # a first-yield time only where most replicas yield
    assert s["collar_first_yield_time"] is None
    assert s["overturned"] and s["overturned_replicas"] == 2
    assert s["overturned_answer"] == "undecided" and s["replicas"] == 3
    assert median_replica([0.8, 1.1, 0.9]) == 2


def test_a_run_whose_energy_balance_failed_stops_the_study():
    from colonna.studies.guard import check_fem_results as check_energy

    limit = {"energy_error_limit": 0.05}
    good = {"energy_error_max": 1e-3, "energy_reliable": True, "status": "completed", **limit}
    bad = {"energy_error_max": 0.54, "energy_reliable": False, "status": "completed", **limit}
    # stopped at its first check: no balance to be off, but nothing to report either
    blown = {
        "energy_error_max": 0.0,
        "energy_reliable": False,
        "status": "numerical blow-up at t = 0 s: the energy grew without bound",
        **limit,
    }
    check_energy(
        {
            "fem": {"summary": good, "replica_summaries": [good, good]},
            "rigid": {"overturned": False},
        }
    )
    with pytest.raises(
        NumericalFailure,
        match=r"FEM case fem-mesh-2h is unreliable \(1 of 2 FEM runs: the energy balance "
        r"is off by 0\.54 ",
    ):
        check_energy(
            {
                "fem": {"summary": good, "replica_summaries": [good]},
                "fem-mesh-2h": {"summary": good, "replica_summaries": [good, bad]},
            }
        )
    with pytest.raises(
        NumericalFailure, match=r"FEM case fem is unreliable \(1 of 2 FEM runs: numerical blow-up"
    ):
        check_energy({"fem": {"summary": good, "replica_summaries": [blown, good]}})


def test_the_refusal_names_the_work_that_grew_and_the_keys_that_change_it():
    """An unstable step pumps energy into the contact that its damping and friction take out
    (the default column on lead at the old step: the bed's damping 216 J, its friction 85 J,
    the crack's 44 J against 337 J of ground work). The refusal names the largest of them and
    the keys that change it; without those keys in its summaries it names the usual causes."""
    from colonna.studies.guard import GENERIC_CAUSES, check_fem_results

    bad = {
        "energy_error_max": 1.0,
        "energy_reliable": False,
        "status": "completed",
        "energy_error_limit": 0.05,
        "contact_damping_work": 216.0,
        "friction_work_base": 84.6,
        "friction_work_crack": 44.0,
        "collar_plastic_work": 0.0,
    }
    with pytest.raises(NumericalFailure) as stopped:
        check_fem_results({"fem": {"summary": bad, "replica_summaries": [bad]}})
    assert "the work that grew most is the bed's contact damping, 216 J" in str(stopped.value)
    assert "change [run] safety (a shorter step) or the bed ([base]" in str(stopped.value)
    crack = {**bad, "friction_work_crack": 500.0}
    with pytest.raises(NumericalFailure, match=r"the crack's friction, 500 J: change \[run\]"):
        check_fem_results({"fem": {"summary": crack, "replica_summaries": [crack]}})
    bare = {k: bad[k] for k in ("energy_error_max", "energy_reliable", "status")}
    bare["energy_error_limit"] = 0.05
    with pytest.raises(NumericalFailure) as stopped:
        check_fem_results({"fem": {"fem_runs": [bare]}})
    assert GENERIC_CAUSES in str(stopped.value)

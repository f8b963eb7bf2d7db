"""One guard for every study kind: a FEM run whose energy balance failed, or that blew up, is
never an answer. Each kind passes the results of its cases here before it assembles a summary;
a case with an unreliable FEM run stops the study with one line naming the case and why
(:func:`colonna.fem.solver.unreliable_reason`), its files kept in ``cases/`` to be looked at.

A case result holds its FEM runs in one of the shapes the kinds save:

* ``replica_summaries`` (or a lone ``summary``): the FEM summaries of an ensemble
  (:func:`studies.crosscheck.runner.fem_case`);
* ``fem_runs``: a list of the reliability keys of each run (:func:`reliability`), as free
  rocking saves them (its result keeps one replica's status);
* ``status_fem`` and ``energy_error_fem``: a spectrum grid point's one run, judged as the
  solver judges it (a blow-up, or a balance error past ``ENERGY_ERROR_LIMIT``).
"""

from __future__ import annotations

from ..core.errors import NumericalFailure

# what a run's reliability is read from (keys of a FEM run summary)
RELIABILITY_KEYS = ("status", "energy_reliable", "energy_error_max", "energy_error_limit")


class UnreliableRun(NumericalFailure):
    """A FEM run of a study is not an answer: its energy balance failed, or it blew up."""


def reliability(summary: dict) -> dict:
    """The keys of a FEM run summary that say whether it is an answer (:data:`RELIABILITY_KEYS`)."""
    return {key: summary[key] for key in RELIABILITY_KEYS}


def halved_steps(runs: list[tuple[str, dict]]) -> list[dict]:
    """The FEM runs of a study whose step was halved (:func:`colonna.fem.solver.run_ensemble`
    reruns an ensemble whose balance failed at half its step), for its report's opening: of
    each (what the run is in words, its summary: a FEM run's or an ensemble's, whose
    ``step_halvings``, ``step_note`` and ``dt`` it carries) that was halved, those three and
    the words as ``run``. Summaries without them (saved before the reruns) count as not
    halved."""
    return [
        {
            "run": run,
            "step_halvings": int(summary["step_halvings"]),
            "step_note": summary.get("step_note"),
            "dt": summary.get("dt"),
        }
        for run, summary in runs
        if summary.get("step_halvings")
    ]


def fem_runs(result) -> list[dict]:
    """The FEM runs of a case result, as summaries with :data:`RELIABILITY_KEYS` (none for a
    case without a FEM run)."""
    if not isinstance(result, dict):
        return []
    if isinstance(result.get("fem_runs"), list):
        return result["fem_runs"]
    if isinstance(result.get("replica_summaries"), list):
        return result["replica_summaries"]
    summary = result.get("summary")
    if isinstance(summary, dict) and "energy_error_limit" in summary:
        return [summary]
    if "status_fem" in result and "energy_error_fem" in result:
        from ..fem.solver import BLOW_UP, ENERGY_ERROR_LIMIT

        error = float(result["energy_error_fem"])
        status = str(result["status_fem"])
        return [
            {
                "status": status,
                "energy_reliable": not status.startswith(BLOW_UP) and error <= ENERGY_ERROR_LIMIT,
                "energy_error_max": error,
                "energy_error_limit": ENERGY_ERROR_LIMIT,
            }
        ]
    return []


def unreliable_cases(results: dict) -> dict[str, str]:
    """Case key -> why its FEM runs are not an answer, for the cases whose runs are not."""
    from ..fem.solver import unreliable_reason

    found = {}
    for key, result in results.items():
        runs = fem_runs(result)
        why = unreliable_reason(runs) if runs else None
        if why is not None:
            bad = sum(not run["energy_reliable"] for run in runs)
            found[key] = f"{bad} of {len(runs)} FEM run{'s' if len(runs) > 1 else ''}: {why}"
    return found


# the dissipated work of a FEM summary that an unstable step makes grow, what it is, and the
# study keys that change it (a step too long for a stiff contact pumps energy into the contact
# that its damping and friction then take out: the dissipation grows, not the motion)
GROWTH_TERMS = (
    (
        "contact_damping_work",
        "the bed's contact damping",
        "[run] safety (a shorter step) or the bed ([base] bed, stiffness)",
    ),
    (
        "friction_work_base",
        "the bed's friction",
        "[run] safety (a shorter step) or the bed ([base] bed, stiffness)",
    ),
    (
        "friction_work_crack",
        "the crack's friction",
        "[run] safety (a shorter step) or the crack's contact ([contact] enforcement, "
        "friction_filter)",
    ),
    (
        "bed_plastic_work",
        "the bed's plastic work",
        "[run] safety (a shorter step) or the bed's yield ([base] yield_pressure, plastic)",
    ),
    (
        "collar_plastic_work",
        "the collars' plastic work",
        "[run] safety (a shorter step) or the collars ([[collar]] t, h, plastic)",
    ),
)
GENERIC_CAUSES = (
    "a time step or contact penalty too large, a stone modulus in the wrong unit, or undamped "
    "frictionless contact"
)


def grown_term(runs: list[dict]) -> str | None:
    """Which dissipated work (:data:`GROWTH_TERMS`) is largest in the worst unreliable run of a
    case, and the keys that change it; None where its summaries do not keep them (or none
    grew)."""
    bad = [run for run in runs if not run["energy_reliable"]]
    if not bad:
        return None
    worst = max(bad, key=lambda run: run["energy_error_max"])
    value, name, keys = max(
        (float(worst.get(key) or 0.0), name, keys) for key, name, keys in GROWTH_TERMS
    )
    if value <= 0.0:
        return None
    return f"the work that grew most is {name}, {value:.3g} J: change {keys}"


def check_fem_results(results: dict, out=None) -> None:
    """Stop the study (:class:`UnreliableRun`, one line) where any case's FEM run is not an
    answer: the first such case by name, why, which dissipated work grew most and the keys
    that change it (where its summaries keep it; else the usual causes), and how many more
    cases there are."""
    found = unreliable_cases(results)
    if not found:
        return
    key, why = next(iter(found.items()))
    more = len(found) - 1
    where = f"{out}/cases/{key}" if out is not None else f"cases/{key}"
    hint = grown_term(fem_runs(results[key])) or GENERIC_CAUSES
    raise UnreliableRun(
        f"FEM case {key} is unreliable ({why})"
        + (f", and {more} more case{'s' if more > 1 else ''}" if more else "")
        + f": no report is written from it; its files are kept in {where} ({hint})"
    )

"""Bands over ensemble replicas, and answers on bands.

Penalty contact with friction is chaotic at landings: a difference in the last bit of a
position becomes, a landing later, another landing (another node bouncing first, another
stick/slip decision). A number that depends on landings (toe stress, collar utilisation,
impacts, crack slip, overturning time) is therefore one sample of a distribution, and the same
study run on another processor draws another sample. colonna runs replicas of each FEM run,
their initial positions moved at round-off level (:func:`colonna.fem.solver.run_ensemble`), and
reports such a number as the median and range over them. What happens before the first landing
is not chaotic and keeps a single value.

A question with a limit ("do the collars yield?": utilisation against 1) is answered on the
band: yes when the whole band is past the limit, no when none of it is, undecided when it
straddles the limit (:func:`decide`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..core.quantities import quantity, to_dict, typed_result

# summary keys of a FEM run that depend on landings, reported as bands over the replicas
LANDING_DEPENDENT = (
    "max_abs_theta_left",
    "max_abs_theta_right",
    "collar_max_utilisation",
    "collar_first_yield_time",
    "edge_stress_max",
    "edge_stress_ratio",
    "collar_max_plastic_strain",
    "collar_plastic_work",
    "bed_plastic_work",
    "collar_max_fibre_strain",
    "collar_ductility_demand",
    "collar_fracture_time",
    "crack_slip_residual",
    "crack_length_final",
    "crack_growth",
    "crack_tip_KI_max",
    "crack_tip_KI_ratio",
    "crack_ligament_damage_max",
    "t_end",
    "energy_error_max",
)

YES, NO, UNDECIDED = "yes", "no", "undecided"


def band(values) -> dict:
    """Median, min and max of the finite numbers among ``values`` (None and NaN are counted as
    ``missing``: a collar that never yields has no first-yield time), and the values."""
    values = list(values)
    finite = np.array(
        [
            float(v)
            for v in values
            if v is not None and not isinstance(v, bool) and math.isfinite(float(v))
        ]
    )
    out = {
        "n": len(values),
        "missing": len(values) - finite.size,
        "values": [None if v is None else float(v) for v in values],
    }
    if finite.size:
        out.update(
            median=float(np.median(finite)), min=float(finite.min()), max=float(finite.max())
        )
    else:
        out.update(median=None, min=None, max=None)
    return out


def relative_width(b: dict) -> float | None:
    """(max - min) / |median| of a band; None without numbers or with a zero median."""
    if b["median"] is None or b["median"] == 0.0:
        return None
    return (b["max"] - b["min"]) / abs(b["median"])


def decide(b: dict, limit: float, uncertainty: float = 0.0) -> str:
    """yes / no / undecided: does the quantity reach ``limit``? Its band widened by the relative
    ``uncertainty`` (another source of error, e.g. the mesh) on both sides: yes when the band's
    bottom reaches the limit, no when its top stays below it, undecided otherwise (and where
    some replicas have no value: it may be yes in some and absent in others)."""
    if b["median"] is None:
        return UNDECIDED
    low = b["min"] * (1.0 - uncertainty)
    high = b["max"] * (1.0 + uncertainty)
    if low >= limit and not b["missing"]:
        return YES
    if high < limit:
        return NO
    return UNDECIDED


def decide_count(flags) -> str:
    """yes / no / undecided for a yes-or-no outcome of each replica (overturned, yielded):
    yes when all replicas say yes, no when none does, undecided otherwise."""
    flags = [bool(f) for f in flags]
    if all(flags):
        return YES
    if not any(flags):
        return NO
    return UNDECIDED


def ensemble_summary(summaries: list[dict], keys=LANDING_DEPENDENT) -> dict:
    """One summary for an ensemble: replica 0's (the unperturbed run) for what does not depend
    on landings, the median over the replicas for what does (``keys``), with ``bands``
    (:func:`band` of each) and ``replicas``. ``overturned`` (and, with collars,
    ``collar_fractured``) is the majority's, with ``overturned_replicas`` counting them and
    ``overturned_answer`` yes / no / undecided."""
    out = dict(summaries[0])
    bands = {key: band(s.get(key) for s in summaries) for key in keys if key in summaries[0]}
    for key, b in bands.items():
        # the median where at least half the replicas have a value (a first-yield time is
        # None where most never yield)
        out[key] = b["median"] if b["missing"] * 2 <= b["n"] else None
    tally: dict[str, Any] = {}
    for flag in ("overturned", "collar_fractured", "crack_grew"):  # each replica's yes or no
        if flag not in summaries[0]:
            continue
        flags = [bool(s[flag]) for s in summaries]
        out[flag] = sum(flags) * 2 > len(flags)
        tally[f"{flag}_replicas"] = int(sum(flags))
        tally[f"{flag}_answer"] = decide_count(flags)
    out.update(
        to_dict(
            EnsembleTally(
                **tally,
                statuses=tuple(s["status"] for s in summaries),
                replicas=len(summaries),
                bands=bands,
            )
        )
    )
    return out


def median_replica(values) -> int:
    """The replica whose value is the median's (the lower middle one for an even count)."""
    values = np.asarray(values, dtype=float)
    order = np.argsort(values, kind="stable")
    return int(order[(values.size - 1) // 2])


@typed_result
@dataclass(frozen=True, kw_only=True)
class EnsembleTally:
    """The keys :func:`ensemble_summary` adds to the FEM run's summary (the units of the others:
    colonna.fem.solver.FemRunSummary); each yes-or-no outcome's two only where the runs give it."""

    overturned_replicas: int | None = quantity(
        "", "replicas that overturned", omit_when_none=True, default=None
    )
    overturned_answer: str | None = quantity(
        "",
        "does it overturn: yes (all replicas), no (none) or undecided",
        omit_when_none=True,
        default=None,
    )
    collar_fractured_replicas: int | None = quantity(
        "", "replicas in which a collar broke", omit_when_none=True, default=None
    )
    collar_fractured_answer: str | None = quantity(
        "", "does a collar break: yes, no or undecided", omit_when_none=True, default=None
    )
    crack_grew_replicas: int | None = quantity(
        "", "replicas in which the partial crack grew", omit_when_none=True, default=None
    )
    crack_grew_answer: str | None = quantity(
        "", "does the crack grow: yes, no or undecided", omit_when_none=True, default=None
    )
    statuses: tuple[str, ...] = quantity("", "how each replica's run ended")
    replicas: int = quantity("", "runs in the ensemble")
    bands: dict = quantity("", "median, min, max and values of each key, in the key's unit")

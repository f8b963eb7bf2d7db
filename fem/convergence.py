"""Mesh-convergence arithmetic: observed order and Richardson extrapolation from three meshes
refined by a constant ratio r (h, h/r, h/r^2)."""

from __future__ import annotations

import math


def observed_order(coarse: float, medium: float, fine: float, ratio: float = 2.0) -> float:
    """p = ln(|f1 - f2| / |f2 - f3|) / ln(r); NaN when the differences do not shrink."""
    d1, d2 = abs(coarse - medium), abs(medium - fine)
    if d1 == 0.0 or d2 == 0.0 or d2 >= d1:
        return math.nan
    return math.log(d1 / d2) / math.log(ratio)


def richardson(medium: float, fine: float, order: float, ratio: float = 2.0) -> float:
    """Extrapolated value f3 + (f3 - f2) / (r^p - 1)."""
    return fine + (fine - medium) / (ratio**order - 1.0)


def convergence_table(values, ratio: float = 2.0) -> dict:
    """Observed order, Richardson estimate and the fine mesh's estimated relative error for the
    last three of ``values`` (coarse to fine)."""
    f1, f2, f3 = values[-3:]
    p = observed_order(f1, f2, f3, ratio)
    estimate = richardson(f2, f3, p, ratio) if math.isfinite(p) else math.nan
    error = abs(f3 - estimate) / abs(estimate) if math.isfinite(estimate) and estimate else math.nan
    return {
        "values": list(values),
        "observed_order": p,
        "richardson": estimate,
        "fine_relative_error": error,
    }

"""The spectrum cross-check's own table of the study file, [grid]: the pulses of its grid.
Registered with the kind (studies/kinds.py: ``tables``) and checked with the shared tables by
:mod:`studies.schema` (:func:`studies.schema.study_model`)."""

from __future__ import annotations

from typing import Annotated

from pydantic import Field

from ...rigid.block import OMEGA_RATIO_RANGE
from ..schema import Table, known, pair


class Grid(Table):
    """[grid] (spectrum-crosscheck): the pulses of the grid, each a [start, stop] range."""

    omega_ratios: (
        list[Annotated[float, Field(ge=OMEGA_RATIO_RANGE[0], le=OMEGA_RATIO_RANGE[1])]] | None
    ) = pair(None, "Omega / p range, inclusive (pulses; default [1, 8]); as ground.omega_ratio.")
    amplitude_ratios: list[Annotated[float, Field(ge=1, le=1000)]] = pair(
        [1.2, 6.0], "a_p / (g tan alpha) range, inclusive; as ground.amplitude_ratio."
    )
    time_scales: list[Annotated[float, Field(ge=1e-3, le=1000)]] | None = pair(
        None,
        "Record time-scale range (records, in place of omega_ratios; default [0.5, 2]); as "
        "ground.time_scale.",
    )
    points: list[Annotated[int, Field(ge=1, le=10000)]] = pair(
        [6, 5],
        "Number of points along the first axis x number of amplitude ratios, each at most "
        "10000 (the FEM work of the grid is bounded too: see --long).",
    )

    @staticmethod
    def across(g: dict, given: set) -> list[tuple[str, tuple]]:
        """Each range [start, stop] with start <= stop."""
        return [
            (f"grid.{key} = {g[key]!r} must be [start, stop] with start <= stop", ())
            for key in ("omega_ratios", "amplitude_ratios", "time_scales")
            if g[key] is not None and known(g[key]) and not g[key][0] <= g[key][1]
        ]

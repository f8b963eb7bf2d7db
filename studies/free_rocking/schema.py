"""Free rocking's own table of the study file, [free_rocking]: its release tilts and the FEM
variants it tries. Registered with the kind (studies/kinds.py: ``tables``) and checked with the
shared tables by :mod:`studies.schema` (:func:`studies.schema.study_model`)."""

from __future__ import annotations

from typing import Annotated

from pydantic import Field

from ..schema import Table


class FreeRocking(Table):
    """[free_rocking] (free-rocking): release tilts and the FEM variants to try."""

    tilt_fractions: list[Annotated[float, Field(gt=0, lt=1)]] = Field(
        [0.5],
        min_length=1,
        description="Release tilts, fractions of alpha, in (0, 1).",
        json_schema_extra={"unit": "-"},
    )
    damping: list[Annotated[float, Field(ge=0, lt=1)]] = Field(
        [0.0, 0.2],
        min_length=1,
        description="Extra contact dampings to try, in [0, 1).",
        json_schema_extra={"unit": "-"},
    )
    mesh_sizes: list[Annotated[float, Field(gt=0)]] | None = Field(
        None,
        min_length=1,
        description="Extra mesh sizes to try, at most the width of a half "
        "(default: twice the study's).",
        json_schema_extra={"unit": "m"},
    )

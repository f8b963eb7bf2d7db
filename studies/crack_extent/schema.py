"""The crack-extent study's own table of the study file, [crack_extent]: the crack's extents it
sweeps. Registered with the kind (studies/kinds.py: ``tables``) and checked with the shared
tables by :mod:`studies.schema` (:func:`studies.schema.study_model`)."""

from __future__ import annotations

from typing import Annotated

from pydantic import Field

from ..schema import Table, known

# the crack's extents swept by default, fractions of the column's height (0: no crack, 1: the
# full height, the paper's hypothesis)
DEFAULT_FRACTIONS = (0.0, 0.25, 0.5, 0.75, 1.0)


class CrackExtent(Table):
    """[crack_extent] (crack-extent): the extents of the crack swept, from the top down (or from
    the base up where [column] crack starts at the base)."""

    fractions: list[Annotated[float, Field(ge=0.0, le=1.0)]] = Field(
        list(DEFAULT_FRACTIONS),
        min_length=1,
        max_length=21,
        description="The crack's extents swept, fractions of the column's height, increasing, "
        "each in [0, 1] (0: no crack, the solid column; 1: the full height, the paper's "
        "hypothesis, which the report compares the others with) and a whole percent apart "
        "(each names its variant, crack-<percent>); 1 to 21 of them. The column as found "
        "([column] crack) is run beside them where it is not one of them.",
        json_schema_extra={"unit": "-"},
    )

    @staticmethod
    def across(c: dict, given: set) -> list[tuple[str, tuple]]:
        """The fractions increasing, each a whole percent from the next (their names)."""
        fractions = c["fractions"]
        if not known(fractions):
            return []
        names = [round(100 * f) for f in fractions]
        if not all(a < b for a, b in zip(names, names[1:])):
            return [
                (
                    f"crack_extent.fractions = {fractions!r} must increase by a whole percent "
                    "at least (each names its variant, crack-<percent>)",
                    (),
                )
            ]
        return []

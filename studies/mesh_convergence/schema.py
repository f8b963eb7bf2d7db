"""Mesh convergence's own table of the study file, [convergence]: its mesh sizes. Registered
with the kind (studies/kinds.py: ``tables``) and checked with the shared tables by
:mod:`studies.schema` (:func:`studies.schema.study_model`)."""

from __future__ import annotations

from typing import Annotated

from pydantic import Field

from ..schema import Table, known, quantity


class Convergence(Table):
    """[convergence] (mesh-convergence): the mesh sizes, given or from levels and ratio."""

    sizes: list[Annotated[float, Field(gt=0)]] | None = Field(
        None,
        min_length=3,
        description="Three or more decreasing mesh sizes.",
        json_schema_extra={"unit": "m"},
    )
    levels: int = quantity(
        "-", "Number of meshes ..., r^2 h, r h, h, the finest h = mesh.size.", 3, ge=3
    )
    ratio: float = quantity("-", "Refinement ratio r between meshes.", 2.0, gt=1)

    @staticmethod
    def across(c: dict, given: set) -> list[tuple[str, tuple]]:
        """Sizes, or levels and ratio; the sizes decreasing by one ratio (the Richardson
        estimate and the observed order assume it)."""
        sizes = c["sizes"]
        if sizes is None or not known(sizes):
            return []
        if not all(b < a for a, b in zip(sizes, sizes[1:])):
            return [(f"convergence.sizes = {sizes!r} must decrease", ())]
        if given & {"levels", "ratio"}:
            return [("convergence.sizes goes without levels and ratio (it sets both)", ())]
        ratios = [a / b for a, b in zip(sizes, sizes[1:])]
        if max(ratios) - min(ratios) > 1e-6 * ratios[0]:
            return [
                (
                    f"convergence.sizes = {sizes!r} must refine by one ratio (here "
                    + ", ".join(f"{r:.4g}" for r in ratios)
                    + "): the convergence rate and the Richardson estimate assume it",
                    (),
                )
            ]
        return []

"""A rerun that finds cases saved from other inputs names the changed key as the study file
spells it (issue 48: a changed [run] safety was named study.safety)."""

from __future__ import annotations

import dataclasses
import tomllib

import pytest
from tiny_study import TINY_STUDY

from colonna.studies.executor import (
    STUDY_FILE_KEYS,
    case_inputs,
    describe_difference,
    study_file_key,
)
from colonna.studies.fem_study import FemStudy, case_of, from_dict

TINY = TINY_STUDY.format(amplitude_ratio=2.5, duration=0.1).replace("[run]", "[run]\nsafety = 0.5")


def _inputs(text: str) -> dict:
    study = from_dict(tomllib.loads(text), "tiny.toml")
    return case_inputs(case_of(study, key="fem"))


@pytest.mark.parametrize(
    "old, new, named",
    [
        ("safety = 0.5", "safety = 0.4", "run.safety: 0.5 -> 0.4"),
        ("t = 0.004", "t = 0.005", "collar[1].t: 0.004 -> 0.005"),
        ("duration = 0.1", "duration = 0.2", "run.duration: 0.1 -> 0.2"),
        ("size = 0.05", "size = 0.04", "mesh.size: 0.05 -> 0.04"),
        ("[column]\n", "[column]\ntop_load = 1000.0\n", "column.top_load: 0.0 -> 1000.0"),
        ("[stone]\n" if "[stone]" in TINY else "[run]", "[stone]\nE = 4e10\n[run]", "stone.E: "),
        # the width changes the pulse (its uplift) and the thickness (pi w / 4): the width is named
        ("width = 0.2", "width = 0.25", "column.width: 0.2 -> 0.25"),
        ("omega_ratio = 3.0", "omega_ratio = 4.0", "ground.period or ground.omega_ratio (Omega, "),
        ("amplitude_ratio = 2.5", "amplitude_ratio = 3.0", "ground.amplitude or ground.amplitude_"),
        ("[run]", '[base]\nbed = "lead"\n[run]', "base.bed: "),
    ],
)
def test_a_changed_input_is_named_as_the_study_file_spells_it(old, new, named):
    assert old in TINY
    said = describe_difference(_inputs(TINY), _inputs(TINY.replace(old, new)))
    assert said.startswith(named), said
    assert not said.startswith("study."), said


def test_every_field_of_a_case_study_has_its_study_file_key():
    """A FemStudy field without an entry would be named by its Python name again."""
    fields = {f.name for f in dataclasses.fields(FemStudy)} - {"name", "source"}
    assert fields == set(STUDY_FILE_KEYS)
    assert study_file_key("study.collars[2].fy") == "collar[2].fy"
    assert study_file_key("study.contact.friction") == "contact.friction"
    assert study_file_key("study.bed.yield_pressure") == "base.yield_pressure"
    assert study_file_key("study.vertical.amplitude") == "ground.vertical_amplitude"
    assert study_file_key("omega_ratio") == "omega_ratio"  # a case's own key, as it is

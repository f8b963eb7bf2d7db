"""[stone] preset (issue 51): a named stone's values fill the [stone] keys not given, a key
given overrides its preset's, an unknown name is refused naming those allowed, and the
report's inputs show each value used and that it came from the preset."""

from __future__ import annotations

import pytest

from colonna.core.errors import InputError
from colonna.studies import schema
from colonna.studies.report import input_tables
from colonna.studies.stone_presets import GRANITE, MARBLE, PRESETS, SOURCES
from colonna.studies.study import load

STUDY = """
[study]
name = "preset"
kind = "cross-check"
[column]
height = 3.2
width = 0.36
crack = [1.6, 3.2]
[stone]
{stone}
[ground]
amplitude_ratio = 2.5
omega_ratio = 4.0
"""


def study_with(tmp_path, stone: str):
    path = tmp_path / "study.toml"
    path.write_text(STUDY.format(stone=stone))
    return load(path)


def test_a_presets_values_reach_the_model(tmp_path):
    from colonna.studies.models import build

    study = study_with(tmp_path, 'preset = "granite"')
    stone = study.fem.stone
    assert {key: getattr(stone, key) for key in GRANITE} == GRANITE
    model = build(study.fem)
    assert (model.stone.E, model.stone.ft, model.stone.KIC) == (55e9, 10e6, 1.3e6)
    # the cohesive law of the partial crack takes the granite's f_t and G_f
    assert model.cohesive.law[0] == 10e6 and model.cohesive.law[2] == 60.0


def test_a_key_given_overrides_its_preset_and_the_inputs_say_which_came_from_it(tmp_path):
    study = study_with(tmp_path, 'preset = "granite"\nft = 7e6')
    assert study.fem.stone.ft == 7e6 and study.fem.stone.E == GRANITE["E"]
    inputs = study.to_json()
    assert inputs["stone"] == {"preset": "granite", **GRANITE, "ft": 7e6}
    resolved = inputs["resolved"]
    assert "stone.ft" not in resolved  # given in the file
    for key in set(GRANITE) - {"ft"}:
        assert resolved[f"stone.{key}"] == f"the granite preset: {SOURCES['granite'][key]}"
    rows = next(t for t in input_tables(inputs) if t["name"] == "stone")["rows"]
    shown = {row["key"]: row["values"][0] for row in rows}
    assert shown["preset"] == "granite" and shown["E"] == "55" and shown["ft"] == "7"


def test_without_a_preset_the_stone_is_todays_marble(tmp_path):
    fields = schema.Stone.model_fields
    assert {key: fields[key].default for key in MARBLE} == MARBLE == PRESETS["marble"]
    study = study_with(tmp_path, "")
    assert "preset" not in study.to_json()["stone"]
    assert not any(key.startswith("stone.") for key in study.to_json()["resolved"])
    marble = study_with(tmp_path, 'preset = "marble"')
    assert marble.fem.stone == study.fem.stone


def test_an_unknown_preset_is_refused_naming_those_allowed(tmp_path):
    with pytest.raises(InputError, match="stone.preset = 'basalt' is not allowed: one of "
                       "'marble', 'granite'"):  # fmt: skip
        study_with(tmp_path, 'preset = "basalt"')


def test_every_preset_value_has_a_source_and_lies_in_its_schema_range():
    for name, values in PRESETS.items():
        assert set(SOURCES[name]) == set(values), name
        schema.Stone(**values)  # inside every range (a validation error otherwise)
        assert name in schema.Stone.model_fields["preset"].description

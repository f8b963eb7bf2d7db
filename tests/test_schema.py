"""The study-file schema: one place for keys, types, ranges, defaults and units.

The documentation's key list (docs/study-file.md) is generated from it and must be current; the
defaults it states are the ones the solvers use; every shipped study satisfies it; its errors
name the key path and the allowed range."""

import dataclasses
import json
import tomllib
from pathlib import Path

import pytest
from pydantic import ValidationError

from colonna.core.errors import InputError
from colonna.fem.assembly import Stone
from colonna.fem.model import ContactSettings
from colonna.rigid.collars import Collar
from colonna.studies import schema
from colonna.studies.cli import main
from colonna.studies.kinds import KINDS

ROOT = Path(__file__).resolve().parents[1]
STUDIES = sorted((ROOT / "studies").glob("*.toml"))


def test_the_documented_key_list_is_generated_from_the_schema():
    """docs/study-file.md is `colonna schema --markdown`: regenerate it when the schema moves."""
    assert (ROOT / "docs" / "study-file.md").read_text() == schema.markdown()


def test_json_schema_has_every_key_with_its_unit_and_range(capsys):
    assert main(["schema"]) == 0
    printed = json.loads(capsys.readouterr().out)
    assert printed["$schema"].startswith("https://json-schema.org/")
    defs = printed["$defs"]
    tables = dict(schema.study_model(every=True).model_fields)  # every kind's tables too
    assert set(printed["properties"]) == set(tables)
    numbers = 0
    for name, field in tables.items():
        model = schema._model_of(field.annotation)
        props = defs[model.__name__]["properties"]
        assert set(props) == set(model.model_fields), name
        assert defs[model.__name__]["additionalProperties"] is False
        for key, prop in props.items():
            kinds = {prop.get("type")} | {o.get("type") for o in prop.get("anyOf", [])}
            assert prop.get("description"), f"{name}.{key} has no description"
            names = prop.get("items", {}).get("type") == "string"  # [study] intended: key names
            if kinds & {"number", "integer", "array"} and key != "toe_refinements" and not names:
                assert "unit" in prop, f"{name}.{key} has no unit"
                numbers += 1
    assert numbers > 50
    # ranges are in the schema itself, e.g. Poisson's ratio [0, 0.5) and the height (0, inf)
    stone = defs["Stone"]["properties"]
    assert stone["nu"]["minimum"] == 0 and stone["nu"]["exclusiveMaximum"] == 0.5
    assert defs["Column"]["properties"]["height"]["minimum"] == 0.01
    assert defs["Column"]["properties"]["height"]["unit"] == "m"


@pytest.mark.parametrize("model, table", [(Stone, schema.Stone), (ContactSettings, schema.Contact)])
def test_schema_defaults_are_the_solvers_defaults(model, table):
    for f in dataclasses.fields(model):
        assert table.model_fields[f.name].default == f.default, f.name


def test_collar_defaults_are_the_collar_defaults():
    given = {"y": 1.0, "t": 0.01, "h": 0.05}
    assert Collar(**schema.Collar(**given).model_dump()) == Collar(**given)


@pytest.mark.parametrize("path", STUDIES, ids=[p.stem for p in STUDIES])
def test_every_shipped_study_satisfies_the_schema(path):
    spec = schema.parse(tomllib.loads(path.read_text()), str(path))
    assert spec.study.kind in KINDS


BASE = {
    "column": {"height": 2.0, "width": 0.4},
    "ground": {"pulse": "sine", "amplitude_ratio": 2.0, "omega_ratio": 3.0},
}


# the kind that reads a table of its own (the registry, studies/kinds.py)
READER = {table: name for name, kind in KINDS.items() for table in kind.tables}


def _with(table, **keys):
    data = json.loads(json.dumps(BASE))
    data.setdefault(table, {}).update(keys)
    if table in READER:
        data["study"] = {"kind": READER[table]}
    return data


@pytest.mark.parametrize(
    "data, words",
    [
        (_with("column", height=-1.0), ["column.height = -1.0", "[0.01, 100], m"]),
        (_with("column", height=True), ["column.height = True", "[0.01, 100], m"]),
        (_with("column", height="2"), ["column.height = '2'"]),
        (_with("stone", fc=float("inf")), ["stone.fc = inf", "(0, inf), Pa"]),
        (_with("stone", colour=1), ["unknown key stone.colour", "E, nu, density, fc"]),
        ({**BASE, "colour": {}}, ["unknown table colour", "column"]),
        (
            {
                **BASE,
                "collar": [{"y": 1.0, "t": 0.01, "h": 0.05}, {"y": 1.0, "t": 0.01, "h": -0.05}],
            },
            ["collar[2].h = -0.05"],
        ),
        (
            {**BASE, "collar": [{"y": 3.0, "t": 0.01, "h": 0.05}]},
            ["collar[1].y = 3 m", "[0.001, 2] m"],
        ),
        ({**BASE, "collar": [{"y": 1.0, "t": 0.01, "h": 0.05, "Eh": 300e9}]}, ["Eh", "below E"]),
        (_with("mesh", size=0.5), ["mesh.size = 0.5 m", "(0, 0.2] m"]),
        (_with("mesh", toe_refinements=[1, 3, 9]), ["mesh.toe_refinements", "[1, 2, 4]"]),
        (
            _with("mesh", toe_refinements=[1.0, 2.0, 4.0]),
            ["mesh.toe_refinements[1] = 1.0", "integer"],
        ),
        (_with("ground", amplitude=3.0), ["only one of ground.amplitude"]),
        (
            {**BASE, "ground": {"pulse": "cosine", "omega_ratio": 2.0}},
            ["exactly one of ground.amplitude and ground.amplitude_ratio for a cosine pulse"],
        ),
        (_with("ground", record="a.AT2"), ["ground.record has no meaning with pulse = 'sine'"]),
        (_with("ground", vertical_amplitude=2.0), ["ground.vertical_period is required"]),
        (
            _with("ground", vertical_amplitude=200.0, vertical_period=0.5),
            [
                "ground.vertical_amplitude = 200 m/s^2",
                "lifts the column off the ground",
                "below g = 9.81 m/s^2",
            ],
        ),
        (_with("ground", pulse="square"), ["ground.pulse = 'square'", "'sine', 'cosine'"]),
        (_with("run", initial_tilt=1.0), ["run.initial_tilt = 1.0", "(-0.785398, 0.785398), rad"]),
        (_with("contact", damping=1.0), ["contact.damping = 1.0", "[0, 1)"]),
        # a toe element of 1e-258 m was accepted and the mesh grader then asked numpy for
        # 1e256 nodes (found by test_properties' generated study files)
        (_with("mesh", toe_size=1e-258), ["mesh.toe_size = 1e-258", "[1e-05, inf), m"]),
        (_with("grid", points=[3, 0]), ["grid.points[2] = 0", "[1, 10000]"]),
        (_with("grid", amplitude_ratios=[3.0, 2.0]), ["grid.amplitude_ratios", "start <= stop"]),
        (_with("convergence", sizes=[0.1, 0.2, 0.05]), ["convergence.sizes", "decrease"]),
        (  # just past the top: the message must not round it onto the top
            {**BASE, "collar": [{"y": 2.0000001, "t": 0.01, "h": 0.05}]},
            ["collar[1].y = 2.0000001 m is outside the allowed range [0.001, 2] m"],
        ),
        (
            # a table of another kind's would be read by nothing
            {**BASE, "grid": {"points": [3, 3]}},
            ["[grid] is read by studies of kind spectrum-crosscheck only", "'cross-check'"],
        ),
        (
            _with("convergence", sizes=[0.1, 0.05, 0.0125]),
            ["convergence.sizes", "one ratio", "2, 4"],
        ),
        (
            _with("convergence", sizes=[0.1, 0.05, 0.025], levels=4),
            ["convergence.sizes goes without levels and ratio"],
        ),
        (
            _with("free_rocking", tilt_fractions=[1.5]),
            ["free_rocking.tilt_fractions[1] = 1.5", "(0, 1)"],
        ),
        (_with("study", kind="wobble"), ["study.kind = 'wobble'", "'cross-check'"]),
        ({"ground": BASE["ground"]}, ["column.height is required"]),
        ({"column": BASE["column"]}, ["no [ground] table"]),
    ],
)
def test_errors_name_the_key_path_and_the_allowed_range(data, words):
    with pytest.raises(InputError) as raised:
        schema.parse(data, "s.toml")
    message = str(raised.value)
    assert message.startswith("s.toml: ") and "\n" not in message
    for word in words:
        assert word in message, (word, message)


def test_a_valid_study_gets_its_defaults():
    spec = schema.parse(BASE)
    assert spec.column.cracked is True and spec.contact.friction == 0.7
    assert spec.mesh.toe_refinements == [1, 2, 4, 8] and spec.run.safety == 0.9
    assert schema.parse({"study": {"kind": "zhang-makris"}}).column is None


def _limits(table, key):
    prop = table.model_json_schema()["properties"][key]
    prop = next((o for o in prop.get("anyOf", []) if o.get("type") == "number"), prop)
    return {
        k: prop[k]
        for k in ("minimum", "exclusiveMinimum", "maximum", "exclusiveMaximum")
        if k in prop
    }


@pytest.mark.parametrize(
    "model, table, required",
    [
        (Stone, schema.Stone, {}),
        (ContactSettings, schema.Contact, {"enforcement": "penalty"}),  # its penalty keys need it
        (Collar, schema.Collar, {"y": 1.0, "t": 0.01, "h": 0.05}),
    ],
)
def test_the_solvers_own_checks_have_the_schemas_ranges(model, table, required):
    """The dataclasses check their values for the Python API; at each end of every range of
    the schema they accept and reject what the schema does."""
    checked = 0
    for key in table.model_fields:
        for bound, value in _limits(table, key).items():
            inside = {
                "minimum": value,
                "maximum": value,
                "exclusiveMinimum": value + 1e-9 * max(1.0, abs(value)),
                "exclusiveMaximum": value - 1e-9 * max(1.0, abs(value)),
            }[bound]
            outside = {
                "minimum": value - 1e-9 * max(1.0, abs(value)),
                "maximum": value + 1e-9 * max(1.0, abs(value)),
                "exclusiveMinimum": value,
                "exclusiveMaximum": value,
            }[bound]
            given = {**required, key: inside}
            table(**given)
            model(**given)
            with pytest.raises(ValidationError):
                table(**{**required, key: outside})
            with pytest.raises(InputError):
                model(**{**required, key: outside})
            checked += 1
    assert checked >= 4


# --- a study file's errors all at once, one line each ---------------------------------------------

COLLAR = {"y": 1.0, "t": 0.01, "h": 0.05}


@pytest.mark.parametrize(
    "data, lines",
    [
        # a key out of range, an unknown key and a collar above the column: three tables
        (
            {
                **_with("column", width=-0.4),
                "stone": {"colour": 1},
                "collar": [{**COLLAR, "y": 3.0}],
            },
            ["column.width = -0.4", "unknown key stone.colour", "collar[1].y = 3 m"],
        ),
        # no [ground] no longer hides a collar above the column, nor a key out of range
        (
            {"column": {"height": 2.0, "width": -0.4}, "collar": [{**COLLAR, "y": 3.0}]},
            ["column.width = -0.4", "no [ground] table", "collar[1].y = 3 m"],
        ),
        # every key passes, three checks across tables fail
        (
            {"column": BASE["column"], "collar": [{**COLLAR, "y": 3.0}], "mesh": {"size": 0.5}},
            ["no [ground] table", "collar[1].y = 3 m", "mesh.size = 0.5 m"],
        ),
        # checks across the keys of a table where another key failed
        (
            _with("ground", vertical_amplitude=200.0),
            ["ground.vertical_amplitude = 200 m/s^2", "ground.vertical_period is required"],
        ),
        (
            {**BASE, "collar": [{**COLLAR, "t": -0.01, "Eh": 300e9}, {**COLLAR, "Eh": 300e9}]},
            [
                "collar[1].t = -0.01",
                "collar[2]: Eh = 3e+11 Pa must be below E",
                "collar[1]: Eh = 3e+11 Pa must be below E",
            ],
        ),
        (
            {
                **_with("grid", omega_ratios=[8.0, 1.0], points=[0, 3]),
                "convergence": {"sizes": [0.1, 0.2, 0.3], "levels": 2},
            },
            [
                "grid.points[1] = 0",
                "convergence.levels = 2",
                "grid.omega_ratios = [8.0, 1.0]",
                "convergence.sizes = [0.1, 0.2, 0.3] must decrease",
                "[convergence] is read by studies of kind mesh-convergence only",
            ],
        ),
        # a misspelt key is one mistake: the key it leaves missing is not reported again
        (
            {**_with("stone", nu=0.6), "column": {"heigth": 2.0, "width": 0.4}},
            ["unknown key column.heigth", "stone.nu = 0.6"],
        ),
        (
            {**_with("run", safety=2.0), "ground": {"amplitud": 2.0, "omega_ratio": 3.0}},
            ["unknown key ground.amplitud", "run.safety = 2.0"],
        ),
        (
            {
                "grund": BASE["ground"],
                "column": {"height": 2.0, "width": 0.4},
                "collar": [{**COLLAR, "y": 3.0}],
            },
            ["unknown table grund", "collar[1].y = 3 m"],
        ),
        # ... but an unknown key unlike the missing one is another mistake
        (
            {"column": {"height": 2.0, "colour": "red"}, "ground": BASE["ground"]},
            ["column.width is required", "unknown key column.colour"],
        ),
        # one line for a list of numbers, at its first bad item
        (_with("mesh", toe_refinements=[1.0, 2.0, 4.0]), ["mesh.toe_refinements[1] = 1.0"]),
        # a kind that failed does not say what else is required
        (
            {"study": {"kind": "wobble"}, "column": {"height": -2.0, "width": 0.4}},
            ["study.kind = 'wobble'", "column.height = -2.0"],
        ),
    ],
)
def test_every_error_of_a_study_file_comes_at_once_one_line_each(data, lines):
    """Pydantic's errors first, in the order of the schema's tables, then the checks across keys
    (also those of a table where a key failed, which pydantic skips)."""
    with pytest.raises(InputError) as raised:
        schema.parse(data, "s.toml")
    printed = str(raised.value).split("\n")
    assert len(printed) == len(lines), printed
    for line, words in zip(printed, lines):
        assert line.startswith("s.toml: ") and words in line, (words, printed)


def test_a_table_checked_on_its_own_lists_its_errors_too():
    with pytest.raises(InputError) as raised:
        schema.parse_table("grid", {"omega_ratios": [8.0, 1.0], "points": [0, 3]}, "s.toml")
    assert str(raised.value).split("\n") == [
        "s.toml: grid.points[1] = 0 is not allowed: a list of 2 integers in [1, 10000]",
        "s.toml: grid.omega_ratios = [8.0, 1.0] must be [start, stop] with start <= stop",
    ]


def test_a_variant_is_a_checked_copy_never_an_edit():
    """schema.variant makes the study's variants (sweeps, grids, free rocking): the original
    dict stays as it was, and a variant outside the schema is an InputError naming the key."""
    import copy

    from colonna.studies import schema

    data = {
        "column": {"width": 0.5, "height": 3.0, "cracked": True},
        "ground": {"pulse": "sine", "amplitude_ratio": 2.0, "omega_ratio": 3.0},
        "collar": [{"y": 1.5, "t": 0.004, "h": 0.04}],
    }
    before = copy.deepcopy(data)
    solid = schema.variant(data, {"column.cracked": False, "collar": schema.REMOVED})
    finer = schema.variant(data, {"mesh.size": 0.01})
    assert data == before
    assert solid["column"]["cracked"] is False and "collar" not in solid
    assert finer["mesh"] == {"size": 0.01} and finer["collar"] == data["collar"]
    with pytest.raises(InputError, match="mesh.size"):
        schema.variant(data, {"mesh.size": -1.0}, "study.toml")


# --- plausible ranges: unit slips stop, intended values pass ------------------------------------


def test_plausible_ranges_are_in_the_json_schema_and_the_key_list():
    """Each plausible range is in the JSON Schema (``plausible``, SI) and in the description
    that docs/study-file.md lists, in the unit people write it in."""
    stone = schema.json_schema()["$defs"]["Stone"]["properties"]["E"]
    assert stone["plausible"] == {"range": [1e9, 200e9], "shown_in": "GPa", "of": "stone"}
    text = schema.markdown()
    for words in (
        "Plausible: 1-200 GPa (stone)",
        "Plausible: 1000-4000 kg/m^3 (stone)",
        "Plausible: 1-200 mm (a steel collar's section)",
        "Plausible: 100-1000 MPa (structural steel)",
        "Plausible: 150-250 GPa (structural steel)",
        "Plausible: 0.3-30 m (a stone column)",
        "Plausible: 0.05-5 m (a stone column)",
        "Plausible: up to 50 m/s^2 in size",
    ):
        assert words in text, words


def test_an_implausible_value_is_an_error_unless_intended():
    """A stiff-limit study (E = 5 TPa) is refused as a unit slip, one line naming the key,
    until it lists the key in [study] intended; ``collar.t`` covers every collar."""
    stiff = _with("stone", E=5e12)
    with pytest.raises(InputError) as raised:
        schema.parse(stiff, "s.toml")
    assert str(raised.value) == (
        "s.toml: stone.E = 5e12 Pa is outside the plausible range 1-200 GPa for stone: "
        'if it is meant, list "stone.E" in [study] intended'
    )
    assert schema.parse({**stiff, "study": {"intended": ["stone.E"]}}).stone.E == 5e12
    thin = {**BASE, "collar": [{**COLLAR, "t": 5e-4}, {**COLLAR, "y": 1.5, "t": 4e-4}]}
    with pytest.raises(InputError) as raised:
        schema.parse(thin, "s.toml")
    assert [line.split(" is ")[0] for line in str(raised.value).split("\n")] == [
        "s.toml: collar[1].t = 0.0005 m",
        "s.toml: collar[2].t = 0.0004 m",
    ]
    schema.parse({**thin, "study": {"intended": ["collar.t"]}})
    # a variant of an intended study keeps it (the sweeps' and grids' variants)
    schema.variant({**stiff, "study": {"intended": ["stone.E"]}}, {"mesh.size": 0.05})


def test_an_undamped_bed_must_be_meant():
    """Issue 38: from 1 % to 20 % of critical the bed's contact damping moves the uncollared
    first swing by at most 1.2 %; undamped it moved it 4.2 % on one mesh. 0 (or 0.3) is then
    refused with the range, a pure number written without a unit, unless listed as meant."""
    for value in (0.0, 0.3):
        with pytest.raises(InputError) as raised:
            schema.parse(_with("contact", damping=value), "s.toml")
        assert str(raised.value) == (
            f"s.toml: contact.damping = {value:g} is outside the plausible range 0.01-0.2 for "
            "a bed's contact damping, a fraction of critical: if it is meant, list "
            '"contact.damping" in [study] intended'
        )
    meant = {**_with("contact", damping=0.0), "study": {"intended": ["contact.damping"]}}
    assert schema.parse(meant).contact.damping == 0.0
    assert schema.parse(_with("contact", damping=0.01)).contact.damping == 0.01


def test_a_collar_file_has_the_plausible_ranges_too(tmp_path):
    path = tmp_path / "collars.toml"
    path.write_text("[[collar]]\ny = 1.0\nt = 0.01\nh = 0.05\nfy = 355.0\n")
    with pytest.raises(InputError, match=r"fy = 355 Pa .* did you mean 355 MPa"):
        schema.read_collars(path)
    path.write_text('intended = ["collar.fy"]\n' + path.read_text())
    assert schema.read_collars(path)[0].fy == 355.0


def test_every_error_at_once_includes_the_implausible_values():
    """The plausibility check runs with the others: beside a key out of its range, one line
    each."""
    data = {**_with("stone", E=50e3, fc=110.0), "column": {"height": -1.0, "width": 0.4}}
    with pytest.raises(InputError) as raised:
        schema.parse(data, "s.toml")
    lines = str(raised.value).split("\n")
    assert len(lines) == 3, lines
    assert "column.height = -1.0" in lines[0]
    assert "stone.E = 50000.0" in lines[1] and "did you mean 50000 MPa (5e10 Pa)?" in lines[1]
    assert "stone.fc = 110 Pa" in lines[2] and "did you mean 110 MPa (1.1e8 Pa)?" in lines[2]


def test_each_kind_s_own_table_lives_in_its_package():
    """studies/schema.py holds the tables every kind shares; a kind's own table is a model of
    its package's schema.py, named by its registry line (issue 49), and a study of the kind is
    checked against it through the registry."""
    shared = {
        name
        for name, obj in vars(schema).items()
        if isinstance(obj, type) and issubclass(obj, schema.Table)
    }
    tables = 0
    for name, kind in KINDS.items():
        for table, model in kind.table_models().items():
            assert model.__module__ == f"{kind.module().__name__}.schema", (name, table)
            assert model.__name__ not in shared and table not in schema.StudyFile.model_fields
            assert schema.study_model(name).model_fields[table].annotation in (model, model | None)
            tables += 1
    assert tables >= 4  # grid, free_rocking, convergence, fragility

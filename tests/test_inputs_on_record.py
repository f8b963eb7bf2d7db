"""Results keyed by their inputs, and the inputs on record.

Every saved case carries the hash of what it was computed from (the case dict, the bytes of the
files it reads, the colonna version): it is reused only when that is identical, and a study
rerun into an --out computed from other inputs is refused before any work, naming the first
difference, unless --force. ``colonna study --out DIR`` also writes DIR/study.toml (the file as
given) and DIR/inputs.json (the validated study with its defaults, the version, the file's
SHA-256). And a vertical ground acceleration that lifts the column off the ground is an error.
"""

import hashlib
import json
import math
import re
import shutil
import tomllib
from pathlib import Path

import numpy as np
import pytest
from tiny_study import TINY_STUDY

import colonna
from colonna.core.errors import InputError, StaleResultsError
from colonna.core.ground import read_record
from colonna.fem.toe_stress import REFINEMENTS
from colonna.studies import executor
from colonna.studies.cli import main, resolve_study
from colonna.studies.executor import RunOptions
from colonna.studies.fem_study import from_dict
from colonna.studies.kinds import KINDS
from colonna.studies.output import record_inputs
from colonna.studies.study import load

# the smallest study there is: one short FEM run of the tiny column (a collar-design study)
DESIGN = TINY_STUDY.format(amplitude_ratio=2.5, duration=0.1).replace(
    'name = "tiny"', 'name = "tiny"\nkind = "collar-design"'
)
RECORD = Path(__file__).parent / "data" / "synthetic.AT2"


def _files(out: Path) -> dict:
    """Every file under ``out`` with its bytes and modification time."""
    return {
        p.relative_to(out): (p.read_bytes(), p.stat().st_mtime_ns)
        for p in sorted(out.rglob("*"))
        if p.is_file()
    }


@pytest.fixture(scope="module")
def design_run(tmp_path_factory):
    """The tiny collar-design study run once; each test copies its --out."""
    root = tmp_path_factory.mktemp("design")
    study = root / "design.toml"
    study.write_text(DESIGN)
    assert main(["study", str(study), "--out", str(root / "out"), "--workers", "1"]) == 0
    return root / "out"


@pytest.fixture
def copied(design_run, tmp_path):
    """(study file, out) in a fresh place: a copy of the run (times kept) and of its study."""
    out = tmp_path / "out"
    shutil.copytree(design_run, out)
    study = tmp_path / "design.toml"
    study.write_text(DESIGN)
    return study, out


def test_edited_study_is_refused_and_force_recomputes_it(copied, capsys):
    study, out = copied
    before = _files(out)
    old = json.loads((out / "summary.json").read_text())
    old_ground = json.loads((out / "cases" / "fem" / "inputs.json").read_text())["inputs"]
    old_ground = old_ground["case"]["study"]["ground"]
    study.write_text(DESIGN.replace("amplitude_ratio = 2.5", "amplitude_ratio = 3.0"))
    capsys.readouterr()
    assert main(["study", str(study), "--out", str(out), "--workers", "1"]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1
    assert err.startswith("colonna: error: ")
    assert str(Path("cases") / "fem") in err
    # the case names what it computes from that changed: the pulse's amplitude (m/s^2)
    assert re.search(
        r"\(ground\.amplitude or ground\.amplitude_ratio \(a_p, m/s\^2\): 2\.4525 -> 2\.943", err
    )
    assert "--force" in err and "another --out" in err
    assert _files(out) == before  # nothing was written, nothing lost

    assert (
        main(["study", str(study), "--out", str(out), "--workers", "1", "--force", "--json"]) == 0
    )
    new = json.loads(capsys.readouterr().out)
    assert json.loads((out / "summary.json").read_text()) == new
    # the design pulse peak is the amplitude ratio times the uplift acceleration
    assert new["design_ag_over_g"] == pytest.approx(old["design_ag_over_g"] * 3.0 / 2.5)
    assert new["fem_collar_max_utilisation"] != old["fem_collar_max_utilisation"]
    saved = json.loads((out / "cases" / "fem" / "inputs.json").read_text())
    ground = saved["inputs"]["case"]["study"]["ground"]  # the case's study: its pulse in SI
    assert ground["amplitude"] == pytest.approx(old_ground["amplitude"] * 3.0 / 2.5, rel=1e-15)
    assert json.loads((out / "inputs.json").read_text())["ground"]["amplitude_ratio"] == 3.0
    assert (out / "study.toml").read_bytes() == study.read_bytes()


def test_unchanged_rerun_reuses_the_saved_case(copied, monkeypatch):
    study, out = copied
    result = out / "cases" / "fem" / "result.json"
    mtime, text = result.stat().st_mtime_ns, result.read_text()

    def must_not_run(case, directory):
        raise AssertionError(f"case {case['key']} recomputed")

    monkeypatch.setattr("colonna.studies.collar_design.runner.fem_case", must_not_run)
    assert main(["study", str(study), "--out", str(out), "--workers", "1"]) == 0
    assert result.stat().st_mtime_ns == mtime and result.read_text() == text


def test_changed_record_file_is_detected(tmp_path, capsys):
    record = tmp_path / "quake.AT2"
    shutil.copyfile(RECORD, record)
    study = tmp_path / "record.toml"
    study.write_text(
        DESIGN.replace(
            "amplitude_ratio = 2.5\nomega_ratio = 3.0\n",
            'pulse = "record"\nrecord = "quake.AT2"\nscale = 2.0\n',
        )
    )
    out = tmp_path / "out"
    assert main(["study", str(study), "--out", str(out), "--workers", "1"]) == 0
    # the record on record: its file by SHA-256, its peak as read and as applied (scale 2)
    inputs = json.loads((out / "inputs.json").read_text())
    applied = inputs["ground_motion"]["horizontal"]
    assert applied["file"] == "quake.AT2" and applied["samples"] > 2
    assert applied["file_sha256"] == hashlib.sha256(record.read_bytes()).hexdigest()
    peak = read_record(record).peak_acceleration
    assert applied["file_peak_acceleration"] == pytest.approx(peak, rel=1e-15)
    assert applied["peak_acceleration"] == pytest.approx(2.0 * peak, rel=1e-15)
    assert inputs["ground"]["scale"] == 2.0 and inputs["ground"]["time_scale"] == 1.0
    assert "ground.time_scale" in inputs["resolved"] and "ground.scale" not in inputs["resolved"]
    assert list(_nulls(inputs)) == []
    before = _files(out)
    # the same record, one sample changed: the study file itself is as it was
    lines = record.read_text().splitlines(keepends=True)
    lines[4] = lines[4].replace("4.2846362E-05", "4.2846363E-05", 1)
    assert "".join(lines) != RECORD.read_text()
    record.write_text("".join(lines))
    capsys.readouterr()
    assert main(["study", str(study), "--out", str(out), "--workers", "1"]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and "motion, record quake, changed" in err
    assert _files(out) == before


def test_study_and_its_resolved_inputs_are_on_record(design_run):
    out = design_run
    assert (out / "study.toml").read_text() == DESIGN
    inputs = json.loads((out / "inputs.json").read_text())
    assert inputs["colonna_version"] == colonna.__version__
    assert inputs["study_sha256"] == hashlib.sha256(DESIGN.encode()).hexdigest()
    assert inputs["study"]["kind"] == "collar-design"
    # every default filled in: keys the file does not give
    assert inputs["stone"] == {
        "E": 50e9,
        "nu": 0.2,
        "density": 2700.0,
        "fc": 110e6,
        "ft": 8e6,
        "Gf": 40.0,
        "KIC": 1e6,
    }
    assert inputs["collar"][0]["E"] == 206e9 and inputs["collar"][0]["fy"] == 235e6
    assert inputs["contact"]["friction"] == 0.7
    assert inputs["mesh"]["toe_refinements"] == list(REFINEMENTS)
    assert inputs["ground"] == {**inputs["ground"], "pulse": "sine", "amplitude_ratio": 2.5}


def test_a_shipped_study_is_recorded_as_shipped(tmp_path):
    path = resolve_study("free-rocking")
    inputs = record_inputs(tmp_path, load(path))
    assert (tmp_path / "study.toml").read_bytes() == path.read_bytes()
    assert json.loads((tmp_path / "inputs.json").read_text()) == inputs
    assert inputs["ground"]["pulse"] == "none" and inputs["run"]["duration"] == 3.0
    assert inputs["free_rocking"]["tilt_fractions"] == [0.3, 0.6]


# --- the values a run used, never a null --------------------------------------------------------

SHIPPED = sorted(p.stem for p in resolve_study("default").parent.glob("*.toml"))


def _nulls(data, path=""):
    """The dotted paths of the nulls in ``data``."""
    if data is None:
        yield path
    elif isinstance(data, dict):
        for key, value in data.items():
            yield from _nulls(value, f"{path}.{key}" if path else key)
    elif isinstance(data, list):
        for i, value in enumerate(data):
            yield from _nulls(value, f"{path}.{i}")


def _given(data: dict, dotted: str) -> bool:
    """Whether the study file's tables give the dotted key (collar.0.length: a [[collar]])."""
    node = data
    for part in dotted.split("."):
        if isinstance(node, list):
            node = node[int(part)] if int(part) < len(node) else None
        elif isinstance(node, dict):
            node = node.get(part)
        if node is None:
            return False
    return True


@pytest.mark.parametrize("name", SHIPPED)
def test_every_shipped_study_records_the_values_its_run_uses_and_no_null(name):
    """inputs.json of each shipped kind, as the driver writes it without its run record (the
    serialisation of the study's resolved inputs, no case run): no null anywhere; the values
    resolved for the run against their closed forms (mesh size w / 16, toe length a tenth of
    a body, Housner's restitution of the rocking half, the pulse's amplitude g tan(alpha) x
    ratio and period 2 pi / (ratio p), duration = pulse end + 1.5 s, the stable step with
    its safety and damping factors); each value named in ``resolved`` absent from the file."""
    import math

    study = load(resolve_study(name))
    inputs = json.loads(json.dumps(study.to_json()))  # through text, as written
    assert list(_nulls(inputs)) == []
    given = tomllib.loads(study.text.decode())
    per_case = KINDS[study.kind].per_case_rules()  # set by each case: a rule, no value
    for key in inputs["resolved"]:
        assert not _given(given, key), key
        assert _given(inputs, key) != (key in per_case), key
    assert set(per_case) <= set(inputs["resolved"])
    if study.spec.column is None:  # the Zhang & Makris validation: its own fixed block
        assert "model" not in inputs and inputs["resolved"] == {}
        return
    column, mesh, run = inputs["column"], inputs["mesh"], inputs["run"]
    body = column["width"] / (2.0 if column["cracked"] else 1.0)
    assert mesh["size"] == given.get("mesh", {}).get("size", column["width"] / 16.0)
    assert mesh["edge_length"] == pytest.approx(0.1 * body, rel=1e-15)
    b, h = column["width"] / 4.0, column["height"] / 2.0  # the cracked column's half block
    alpha = math.atan(b / h)
    assert inputs["rigid"]["restitution"] == pytest.approx(1.0 - 1.5 * math.sin(alpha) ** 2)
    model = inputs["model"]
    xi, safety = inputs["contact"]["damping"], run["safety"]
    assert run["dt"] == model["dt"] == model["dt_stable"]
    assert model["dt"] == pytest.approx(
        safety * model["dt_critical"] * (math.sqrt(1.0 + xi * xi) - xi), rel=1e-12
    )
    assert model["dt_critical"] < model["dt_critical_stone"]  # contact and collars stiffen
    assert model["dofs"] == 2 * model["nodes"] and model["elements"] > 0
    assert model["steps_per_output"] == round(run["output_interval"] / model["dt"])
    assert 0.0 < model["penalty_base_min"] <= model["penalty_base_mean"]
    ground = inputs["ground"]
    if "ground_motion" not in inputs:  # the kind's cases set their own motion
        assert "duration" not in run or _given(given, "run.duration")
        return
    motion = inputs["ground_motion"]["horizontal"]
    assert run["duration"] == pytest.approx(motion["end_time"] + 1.5, rel=1e-15)
    if column["top_load"] == 0.0:  # uplift g tan(alpha); p = sqrt(3 g / (4 R))
        p = math.sqrt(3.0 * 9.81 / (4.0 * math.hypot(b, h)))
        assert ground["amplitude"] == pytest.approx(ground["amplitude_ratio"] * 9.81 * b / h)
        assert ground["period"] == pytest.approx(2.0 * math.pi / (ground["omega_ratio"] * p))
    assert motion["peak_acceleration"] == pytest.approx(ground["amplitude"], rel=1e-15)


def test_a_run_records_the_model_it_ran_and_when_and_where(design_run):
    """The model on record is the one the FEM case ran (its step, degrees of freedom, base
    penalty and step count, as the solver's own summary has them), and the run's date, wall
    time and machine are on record."""
    from datetime import datetime

    path = design_run / "inputs.json"
    inputs = json.loads(path.read_text())
    assert list(_nulls(inputs)) == []
    fem = json.loads((design_run / "cases" / "fem" / "result.json").read_text())["summary"]
    model = inputs["model"]
    assert fem["dt"] == model["dt"] == inputs["run"]["dt"]
    assert fem["dofs"] == model["dofs"]
    assert fem["penalty_base_mean"] == model["penalty_base_mean"]
    assert fem["steps"] == model["steps_per_output"] * math.ceil(
        inputs["run"]["duration"] / model["output_interval_used"]
    )
    record = inputs["run_record"]
    started = datetime.fromisoformat(record["started_utc"])
    finished = datetime.fromisoformat(record["finished_utc"])
    assert started.utcoffset().total_seconds() == 0.0
    assert 0.0 < record["wall_seconds"] <= (finished - started).total_seconds() + 1.0
    assert finished.timestamp() <= path.stat().st_mtime + 1.0
    assert record["machine"]["cores"] >= 1 and record["machine"]["platform"]
    assert record["colonna_version"] == colonna.__version__


# --- run_cases on its own: cheap cases ----------------------------------------------------------


def _square(case, directory):
    return {"value": case["x"] ** 2}


def _cases(tmp_path, x=3.0, **study):
    return [
        {
            "key": "one",
            "x": x,
            "study": study,
            "base": str(tmp_path),
            "source": "s.toml",
            "progress": True,
        },
        {"key": "two", "x": 2 * x, "study": study, "base": str(tmp_path), "source": "s.toml"},
    ]


@pytest.mark.parametrize(
    "table, key, what",
    [
        ("ground", "record", "record file"),
        ("ground", "vertical_record", "vertical record file"),
        ("mesh", "file", "mesh file"),
    ],
)
def test_a_changed_input_file_is_named(tmp_path, table, key, what):
    (tmp_path / "input.txt").write_text("0 0\n1 1\n")
    cases = _cases(tmp_path, **{table: {key: "input.txt"}})
    assert executor.run_cases(
        _square, cases, tmp_path / "out", run_options=RunOptions(progress=False)
    )["one"] == {"value": 9.0}
    (tmp_path / "input.txt").write_text("0 0\n1 2\n")
    with pytest.raises(StaleResultsError, match=f"{what} input.txt changed") as raised:
        executor.run_cases(_square, cases, tmp_path / "out", run_options=RunOptions(progress=False))
    assert "and 1 more case" in str(raised.value)


def test_what_does_not_change_the_computation_is_not_an_input(tmp_path):
    """Progress reporting, where the study file was, a scheduling cost and the study's name
    and description do not change what a case computes; its kind does."""
    calls = []

    def counted(case, directory):
        calls.append(case["key"])
        return _square(case, directory)

    named = {"name": "a", "kind": "cross-check"}
    executor.run_cases(
        counted,
        _cases(tmp_path, study=named),
        tmp_path / "out",
        run_options=RunOptions(progress=False),
    )
    renamed = {"name": "b", "description": "now described", "kind": "cross-check"}
    moved = [
        dict(c, base=str(tmp_path / "elsewhere"), source="t.toml", progress=False)
        for c in _cases(tmp_path, study=renamed)
    ]
    executor.run_cases(counted, moved, tmp_path / "out", run_options=RunOptions(progress=False))
    rescheduled = [dict(c, cost=7.0) for c in _cases(tmp_path, study=renamed)]  # a hint only
    executor.run_cases(
        counted, rescheduled, tmp_path / "out", run_options=RunOptions(progress=False)
    )
    assert calls == ["one", "two"]
    with pytest.raises(
        StaleResultsError, match=r'\(study\.kind: "cross-check" -> "free-rocking"\)'
    ):
        executor.run_cases(
            counted,
            _cases(tmp_path, study={**named, "kind": "free-rocking"}),
            tmp_path / "out",
            run_options=RunOptions(progress=False),
        )


def test_another_version_is_named_and_nothing_runs_before_the_refusal(tmp_path, monkeypatch):
    out = tmp_path / "out"
    executor.run_cases(_square, _cases(tmp_path)[:1], out, run_options=RunOptions(progress=False))
    before = colonna.__version__
    monkeypatch.setattr(colonna, "__version__", "99.0")
    calls = []

    def counted(case, directory):
        calls.append(case["key"])
        return _square(case, directory)

    with pytest.raises(StaleResultsError) as raised:
        executor.run_cases(counted, _cases(tmp_path), out, run_options=RunOptions(progress=False))
    message = str(raised.value)
    assert f"colonna version {before} -> 99.0" in message
    assert str(out / "cases" / "one") in message and "\n" not in message
    assert calls == [] and not (out / "cases" / "two").exists()
    results = executor.run_cases(
        counted, _cases(tmp_path), out, run_options=RunOptions(progress=False, force=True)
    )
    assert sorted(calls) == ["one", "two"] and results["one"] == {"value": 9.0}
    saved = json.loads((out / "cases" / "one" / "inputs.json").read_text())
    assert saved["inputs"]["colonna_version"] == "99.0"


def test_a_case_without_a_record_of_its_inputs_is_refused_then_forced(tmp_path):
    out = tmp_path / "out"
    executor.run_cases(_square, _cases(tmp_path), out, run_options=RunOptions(progress=False))
    (out / "cases" / "one" / "inputs.json").unlink()  # as an older colonna left it
    (out / "cases" / "one" / "old.csv").write_text("stale")
    with pytest.raises(StaleResultsError, match="one has no record of the inputs"):
        executor.run_cases(_square, _cases(tmp_path), out, run_options=RunOptions(progress=False))
    executor.run_cases(
        _square, _cases(tmp_path), out, run_options=RunOptions(progress=False, force=True)
    )
    assert not (out / "cases" / "one" / "old.csv").exists()  # the stale case was deleted
    assert (out / "cases" / "one" / "inputs.json").is_file()


def test_an_interrupted_case_is_computed_again_and_a_done_one_kept(tmp_path):
    out = tmp_path / "out"
    executor.run_cases(_square, _cases(tmp_path), out, run_options=RunOptions(progress=False))
    (out / "cases" / "two" / "result.json").unlink()  # killed before it finished
    kept = (out / "cases" / "one" / "result.json").stat().st_mtime_ns
    calls = []

    def counted(case, directory):
        calls.append(case["key"])
        return _square(case, directory)

    results = executor.run_cases(
        counted, _cases(tmp_path), out, run_options=RunOptions(progress=False)
    )
    assert calls == ["two"] and results["two"] == {"value": 36.0}
    assert (out / "cases" / "one" / "result.json").stat().st_mtime_ns == kept


# --- a vertical acceleration that lifts the column off the ground ------------------------------


def test_vertical_amplitude_of_g_or_more_is_an_error(tmp_path, capsys):
    study = tmp_path / "study.toml"
    study.write_text(
        DESIGN.replace(
            "omega_ratio = 3.0",
            "omega_ratio = 3.0\nvertical_amplitude = 12.0\nvertical_period = 0.2",
        )
    )
    assert main(["study", str(study), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert err.strip() == (
        f"colonna: error: {study}: ground.vertical_amplitude = 12 m/s^2 lifts "
        "the column off the ground: it must be below g = 9.81 m/s^2"
    )
    assert not (tmp_path / "out").exists()
    below = DESIGN.replace(
        "omega_ratio = 3.0", "omega_ratio = 3.0\nvertical_amplitude = -9.8\nvertical_period = 0.2"
    )
    assert from_dict(tomllib.loads(below)).vertical.amplitude == -9.8


@pytest.mark.parametrize("scale, lifts", [(1.9, False), (2.1, True)])
def test_vertical_record_reaching_g_is_an_error(tmp_path, scale, lifts):
    t = np.arange(31) * 0.01  # 0 -> 5 -> -3 -> 0 m/s^2 every 0.1 s, sampled at 0.01 s
    a = np.interp(t, [0.0, 0.1, 0.2, 0.3], [0.0, 5.0, -3.0, 0.0])  # peak 5 m/s^2
    (tmp_path / "up.txt").write_text("".join(f"{x:.2f} {y:.6g}\n" for x, y in zip(t, a)))
    text = DESIGN.replace(
        "omega_ratio = 3.0",
        f'omega_ratio = 3.0\nvertical_record = "up.txt"\nvertical_scale = {scale}',
    )
    data = tomllib.loads(text)
    if not lifts:
        assert from_dict(data, "s.toml", base=tmp_path).vertical.peak_acceleration == pytest.approx(
            5.0 * scale
        )
        return
    with pytest.raises(InputError) as raised:
        from_dict(data, "s.toml", base=tmp_path)
    message = str(raised.value)
    assert message.startswith("s.toml: ground.vertical_record 'up.txt'")
    assert "lifts the column off the ground" in message and "below g = 9.81 m/s^2" in message


def test_a_pulse_below_uplift_names_its_file():
    data = tomllib.loads(DESIGN.replace("amplitude_ratio = 2.5", "amplitude = 0.1"))
    with pytest.raises(
        InputError,
        match=r"^s\.toml: ground\.amplitude = 0\.1 m/s\^2 is below "
        r"the uplift acceleration",
    ):
        from_dict(data, "s.toml")


def test_report_opens_with_the_outcome_then_lists_the_inputs_of_the_study_file(design_run):
    """The report's first section is the outcome and the three answers; the next lists the
    study file's values (in the units it shows them in: MPa from Pa, mm for a collar section)
    and plots the ground motion that was applied."""
    import re

    from colonna.studies.report import fmt
    from colonna.studies.units import input_unit

    page = (design_run / "index.html").read_text()
    sections = re.findall(r"<h2>([^<]+)</h2>", page)
    assert sections[:2] == ["Outcome", "Inputs"], sections
    assert all(
        f'data-answer="{key}"' in page
        for key in ("rigid_assumption_ok", "collars_yield", "toe_crushes")
    )
    given = tomllib.loads(DESIGN)
    cells = re.findall(
        r'<td data-input="([^"]+)" data-index="(\d+)">([^<]*)'
        r'(?:<sup class="resolved" title="[^"]+" data-resolved="([^"]+)">r</sup>)?</td>',
        page,
    )
    shown = {(path, int(i)): value for path, i, value, _ in cells}
    # a value resolved for the run (not in the file) is marked, a given one is not
    marked = {(path, int(i)): key for path, i, _, key in cells if key}
    resolved = json.loads((design_run / "inputs.json").read_text())["resolved"]
    assert sorted(marked.values()) == sorted(resolved)
    assert marked[("column.thickness", 0)] == "column.thickness"
    assert marked[("collar.length", 0)] == "collar.0.length"
    checked = 0
    for table, entries in given.items():
        for i, entry in enumerate(entries if isinstance(entries, list) else [entries]):
            for key, value in entry.items():
                _, factor = input_unit(table, key)
                expected = fmt(value * factor if isinstance(value, float) else value)
                assert shown[(f"{table}.{key}", i)] == expected, (table, key)
                checked += 1
    assert checked >= 12
    # the defaults filled in are shown too, and the ground motion is drawn from its CSV
    assert ("column.thickness", 0) in shown and ("collar.fy", 0) in shown
    assert 'data-figure="ground_motion"' in page
    assert (
        (design_run / "ground_motion.csv")
        .read_text()
        .startswith("t,horizontal_acceleration,vertical_acceleration")
    )


def test_a_penalty_crack_is_said_in_the_report(design_run, tmp_path):
    """The crack's penalty contact moves the swing with its settings (issue 38): a report of a
    study that chose it says so beside the model; the default's (exact contact) does not."""
    assert "data-penalty-crack" not in (design_run / "index.html").read_text()
    study = tmp_path / "penalty.toml"
    study.write_text(DESIGN + '[contact]\nenforcement = "penalty"\n')
    assert main(["study", str(study), "--out", str(tmp_path / "out"), "--workers", "1"]) == 0
    page = (tmp_path / "out" / "index.html").read_text()
    assert page.count("data-penalty-crack") == 1
    assert "7-10&nbsp;% below the exact contact's" in page


def test_shares_are_balanced_on_the_cases_cost():
    """Equal costs (or none) deal round-robin; unequal ones go costliest first to the share
    with the least so far, so that no worker ends long after the others (the spectrum's grid
    points are dealt on their simulated durations)."""
    plain = [{"key": str(i)} for i in range(7)]
    assert [[c["key"] for c in s] for s in executor._deal(plain, 3)] == [
        ["0", "3", "6"],
        ["1", "4"],
        ["2", "5"],
    ]
    # a grid row's durations (s): round-robin would give 46 s to one worker and 34.5 s to the
    # other over five such rows
    durations = [4.8, 2.9, 2.4, 2.1, 2.0, 1.9] * 5
    cases = [{"key": str(i), "cost": d} for i, d in enumerate(durations)]
    shares = executor._deal(cases, 2)
    assert sorted(c["key"] for s in shares for c in s) == sorted(c["key"] for c in cases)
    loads = [sum(c["cost"] for c in s) for s in shares]
    assert max(loads) - min(loads) <= max(durations)  # the greedy bound
    assert max(loads) < 0.51 * sum(durations)
    for share in shares:  # costliest first
        assert [c["cost"] for c in share] == sorted((c["cost"] for c in share), reverse=True)


def test_every_row_of_the_design_table_resolves_against_the_summary(design_run):
    """The collar design's table reads each of its rows by attribute from the typed summary,
    the value summary.json holds, on the page under its key; none left out."""
    from summary_rows import assert_rows_resolve

    from colonna.studies.collar_design.report import DESIGN_NUMBERS
    from colonna.studies.collar_design.summary import load

    assert assert_rows_resolve(DESIGN_NUMBERS, load, design_run) == []

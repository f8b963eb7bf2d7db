"""A study kind is its package and one line of the registry (studies/kinds.py): an example
kind (tests/data/kinds/peak_rotation) is added as a contributor would add one, and runs through
the command line like the shipped kinds, its page with the shared outcome and inputs."""

import json
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest
from tiny_study import TINY_STUDY

from colonna.studies import kinds, schema
from colonna.studies.cli import main
from colonna.studies.models import run_sdof
from colonna.studies.study import load

KINDS_FOLDER = Path(__file__).parent / "data" / "kinds"

# the whole of adding the kind, before anything reads the registry: its package where
# colonna.studies finds packages, and its line in the registry
ADD_AND_RUN = textwrap.dedent(
    f"""
    import sys
    import colonna.studies
    from colonna.studies import kinds

    colonna.studies.__path__.append({str(KINDS_FOLDER)!r})
    kinds.KINDS["peak-rotation"] = kinds.StudyKind("peak_rotation", ("outcome", "peak_rotation"))

    from colonna.studies.cli import main

    sys.exit(main(sys.argv[1:]))
    """
)


def _study(tmp_path: Path, kind: str) -> Path:
    text = TINY_STUDY.format(amplitude_ratio=2.5, duration=0.6)
    path = tmp_path / "tiny.toml"
    path.write_text(text.replace('name = "tiny"', f'name = "tiny"\nkind = "{kind}"'))
    return path


PLAIN = "import sys\nfrom colonna.studies.cli import main\nsys.exit(main(sys.argv[1:]))\n"


def _colonna(*args: str, script: str = PLAIN) -> subprocess.CompletedProcess:
    command = [sys.executable, "-c", script, *args]
    return subprocess.run(command, capture_output=True, text=True, check=False)


def test_a_kind_added_as_its_package_and_one_line_runs_like_the_shipped_ones(tmp_path):
    path, out = _study(tmp_path, "peak-rotation"), tmp_path / "out"
    done = _colonna("study", str(path), "--out", str(out), "--json", script=ADD_AND_RUN)
    assert done.returncode == 0, done.stderr[-2000:]
    summary = json.loads(done.stdout)
    # it ran the study's own column (the same SDOF run, bit for bit)
    (tmp_path / "same").mkdir()
    expected = run_sdof(load(_study(tmp_path / "same", "cross-check")).fem)
    assert not expected.overturned
    assert summary["peak_rotation"] == expected.max_abs_theta
    assert summary["kind"] == "peak-rotation"
    # the driver put its inputs on record and its page has the shared sections
    inputs = json.loads((out / "inputs.json").read_text())
    assert inputs["study"]["kind"] == "peak-rotation" and inputs["column"]["width"] == 0.2
    page = (out / "index.html").read_text()
    assert 'id="outcome"' in page and f"{expected.max_abs_theta:.4g}" in page
    assert (out / "ground_motion.csv").is_file()  # a kind with one ground motion


def test_without_its_registry_line_the_kind_is_refused_naming_the_registered_ones(tmp_path):
    done = _colonna("study", str(_study(tmp_path, "peak-rotation")), "--out", str(tmp_path / "o"))
    assert done.returncode == 2
    assert "study.kind" in done.stderr and "cross-check" in done.stderr


# --- a kind with a table and an option of its own, outside colonna (issue 49) ----------------

TOY_SCHEMA = '''
from colonna.studies.schema import Table, quantity


class Toy(Table):
    """[toy] (toy): the example kind's own table."""

    length: float = quantity("m", "A length, (0, 10] m.", 1.0, gt=0, le=10)
'''

TOY_PACKAGE = '''
import json
from pathlib import Path


def parse_option(name, text):
    """--toy-factor, a number."""
    return float(text)


def run(study, out, options):
    """[toy] length times --toy-factor (1 without it) into summary.json."""
    scaled = study.spec.toy.length * study.options.get("toy-factor", 1.0)
    summary = {"study": study.spec.study.name, "kind": study.kind, "scaled": scaled}
    Path(out).mkdir(parents=True, exist_ok=True)
    (Path(out) / "summary.json").write_text(json.dumps(summary))
    return summary


def write_report(out):
    """index.html from summary.json."""
    summary = json.loads((Path(out) / "summary.json").read_text())
    page = Path(out) / "index.html"
    page.write_text(f"<h1>toy</h1><p>scaled length {summary['scaled']:.3f} m</p>")
    return page
'''

TOY_STUDY = """
[study]
name = "toy"
kind = "toy"
[ground]
pulse = "none"
[toy]
length = {length}
"""


@pytest.fixture
def toy_kind(tmp_path, monkeypatch):
    """The toy kind: a package in a temporary folder on sys.path (its run, report and option
    reader, and its table in its module ``schema``) and one registration call; no file of
    colonna edited. Unregistered after the test."""
    package = tmp_path / "lib" / "toy_kind"
    package.mkdir(parents=True)
    (package / "__init__.py").write_text(TOY_PACKAGE)
    (package / "schema.py").write_text(TOY_SCHEMA)
    monkeypatch.syspath_prepend(str(tmp_path / "lib"))
    kind = kinds.StudyKind(
        "toy_kind",
        ground_motion=False,
        column=False,
        tables={"toy": "Toy"},
        options={"toy-factor": "the toy kind's factor on [toy] length"},
        home="",
    )
    kinds.register("toy", kind)
    yield kind
    del kinds.KINDS["toy"]
    for name in [m for m in sys.modules if m.split(".")[0] == "toy_kind"]:
        del sys.modules[name]


def _toy(tmp_path: Path, length: float) -> Path:
    path = tmp_path / "toy.toml"
    path.write_text(TOY_STUDY.format(length=length))
    return path


def test_a_kind_with_its_own_table_and_option_runs_through_colonna_study(
    toy_kind, tmp_path, capsys
):
    """Registered by one call, the kind's table is part of the study file's schema and its
    option part of colonna study's: run in-process, its option read by its package, its
    summary, inputs on record and report written."""
    out = tmp_path / "out"
    argv = ["study", str(_toy(tmp_path, 2.5)), "--out", str(out), "--workers", "1"]
    assert main([*argv, "--toy-factor", "3", "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary == {"study": "toy", "kind": "toy", "scaled": 7.5}
    assert "scaled length 7.500 m" in (out / "index.html").read_text()
    inputs = json.loads((out / "inputs.json").read_text())
    assert inputs["toy"] == {"length": 2.5} and inputs["options"] == {"toy-factor": 3.0}
    # the documented schema has its table, with its range and unit
    assert "## [toy]" in schema.markdown() and "| `length` | a number in (0, 10] | m |" in (
        schema.markdown()
    )


def test_the_toy_kind_s_table_and_option_are_checked_naming_the_key(toy_kind, tmp_path, capsys):
    """A value outside the toy table's range is one line naming the key and its range, before
    anything is written; its table in a study of another kind, and its option given to one,
    are refused naming the toy kind."""
    out = tmp_path / "out"
    assert main(["study", str(_toy(tmp_path, 50.0)), "--out", str(out), "--workers", "1"]) == 2
    error = capsys.readouterr().err
    assert "toy.length = 50.0 is not allowed: a number in (0, 10], m" in error, error
    assert not out.exists()
    cross = _study(tmp_path, "cross-check")
    assert main(["study", str(cross), "--out", str(out), "--toy-factor", "2"]) == 2
    assert "--toy-factor applies to studies of kind toy, not 'cross-check'" in (
        capsys.readouterr().err
    )
    cross.write_text(cross.read_text() + "[toy]\nlength = 2.0\n")
    assert main(["study", str(cross), "--out", str(out)]) == 2
    assert "[toy] is read by studies of kind toy only" in capsys.readouterr().err
    assert not out.exists()

"""A study kind is its package and one line of the registry (studies/kinds.py): an example
kind (tests/data/kinds/peak_rotation) is added as a contributor would add one, and runs through
the command line like the shipped kinds, its page with the shared outcome and inputs."""

import json
import subprocess
import sys
import textwrap
from pathlib import Path

from tiny_study import TINY_STUDY

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

"""One study object: a study file is read once and validated once (:func:`studies.study.load`),
its FEM column travels to the workers as JSON and comes back the same study, and the inputs on
record are the study's own serialisation."""

import json
import subprocess
import sys
import textwrap
from dataclasses import replace
from importlib.resources import files
from pathlib import Path

import pytest
from tiny_study import TINY_STUDY

from colonna.studies.fem_study import FemStudy, from_dict
from colonna.studies.study import load

DATA = Path(__file__).parent / "data"
SHIPPED = sorted(p.name for p in files("colonna.studies").iterdir() if p.name.endswith(".toml"))

# run one study in a fresh interpreter, counting the opens of its file (an audit hook sees
# every open, by any function) and the validations of the schema (every one goes through
# schema._validate); one worker, so every case runs in that interpreter
COUNT = textwrap.dedent(
    """
    import json, os, sys
    from pathlib import Path

    study, out = Path(sys.argv[1]).resolve(), Path(sys.argv[2])
    opens = []

    def hook(event, args):
        if event == "open" and isinstance(args[0], (str, os.PathLike)):
            try:
                if Path(os.fsdecode(args[0])).resolve() == study:
                    opens.append(event)
            except (OSError, ValueError):
                pass

    sys.addaudithook(hook)
    from colonna.studies import schema
    from colonna.studies.driver import run_study_file

    validations = []
    validate = schema._validate

    def counted(model, *args, **kw):
        validations.append(model.__name__)
        return validate(model, *args, **kw)

    schema._validate = counted
    run_study_file(study, out, workers=1, progress=False)
    print(json.dumps({"opens": len(opens), "validations": validations}))
    """
)


def _count(study: Path, out: Path) -> dict:
    done = subprocess.run(
        [sys.executable, "-c", COUNT, str(study), str(out)],
        capture_output=True,
        text=True,
        check=False,
    )
    assert done.returncode == 0, done.stderr[-3000:]
    return json.loads(done.stdout.strip().splitlines()[-1])


@pytest.mark.slow  # 20-40 s: make test stays under 10 minutes (make test-all runs it)
def test_a_cross_check_reads_its_file_once_and_validates_it_once(tmp_path):
    """The whole cross-check (its FEM, rigid, spectrum and toe cases, the record of its
    inputs, the ground motion and the report) from one read and one validation."""
    study = tmp_path / "tiny.toml"
    # two replicas: the ensemble's path is taken, and each replica reads no more than one
    text = TINY_STUDY.format(amplitude_ratio=2.5, duration=0.3)
    study.write_text(text.replace("[run]\n", "[run]\nreplicas = 2\n"))
    counts = _count(study, tmp_path / "out")
    assert counts == {"opens": 1, "validations": ["StudyFile"]}


@pytest.mark.slow
def test_the_default_study_reads_its_file_once_and_validates_it_once(tmp_path):
    counts = _count(Path(str(files("colonna.studies") / "default.toml")), tmp_path / "out")
    assert counts == {"opens": 1, "validations": ["StudyFile"]}


@pytest.mark.parametrize("name", SHIPPED)
def test_the_inputs_on_record_resolve_what_the_model_uses(name):
    """inputs.json is Study.to_json: the defaults that depend on the column are the values the
    model is built with (thickness, collar lengths), not nulls."""
    study = load(files("colonna.studies") / name)
    inputs = study.to_json()
    assert inputs["study"]["kind"] == study.kind and inputs["study_sha256"] == study.sha256
    if study.kind in ("cross-check", "collar-design"):
        assert inputs["column"]["thickness"] == study.fem.thickness
        for entry, collar in zip(inputs["collar"], study.fem.collars, strict=True):
            assert entry["y"] == collar.y and entry["length"] > 0.0 and entry["Eh"] > 0.0


def _round_trip(study: FemStudy) -> FemStudy:
    text = json.dumps(study.to_json())  # through text, as a case's record is
    return FemStudy.from_json(json.loads(text), name=study.name, source=study.source)


def test_a_fem_study_travels_as_json_and_comes_back_the_same():
    study = from_dict(json.loads(json.dumps(schema_example())), source="x.toml")
    back = _round_trip(study)
    assert back.to_json() == study.to_json()
    assert back == study  # pulses, collars, stone and contact compare by value
    # a variant is a changed study, and its JSON says so
    coarse = replace(study, mesh_size=2 * study.mesh_size)
    assert _round_trip(coarse).mesh_size == coarse.mesh_size
    assert coarse.to_json() != study.to_json()


def test_a_recorded_motion_travels_with_its_samples(tmp_path):
    text = TINY_STUDY.format(amplitude_ratio=2.5, duration=0.3).replace(
        "amplitude_ratio = 2.5\nomega_ratio = 3.0",
        f'pulse = "record"\nrecord = "{DATA / "synthetic.AT2"}"\nscale = 2.0',
    )
    (tmp_path / "r.toml").write_text(text)
    study = load(tmp_path / "r.toml").fem
    back = _round_trip(study)
    t = [0.0, 0.0133, 0.5, 1.25]
    assert list(back.ground.acceleration(t)) == list(study.ground.acceleration(t))
    assert back.ground.end_time == study.ground.end_time


def test_a_mesh_file_is_on_record_by_its_bytes(tmp_path):
    """A case's inputs name its mesh file by path and SHA-256: another mesh under the same name
    is another input (the case is recomputed, not reused)."""
    mesh = tmp_path / "m.msh"
    mesh.write_bytes(b"one")
    study = replace(from_dict(schema_example()), mesh_file=mesh)
    before = study.to_json()["mesh_file"]
    mesh.write_bytes(b"two")
    after = study.to_json()["mesh_file"]
    assert before["path"] == after["path"] and before["sha256"] != after["sha256"]
    assert _round_trip(study).mesh_file == mesh


def schema_example() -> dict:
    import tomllib

    return tomllib.loads(TINY_STUDY.format(amplitude_ratio=2.5, duration=0.3))


def test_a_kind_s_own_defaults_are_in_the_study():
    """A free-rocking study without [ground] runs with no motion (its kind's default): the
    study is validated with it, once, and its record says so."""
    study = load(files("colonna.studies") / "free-rocking.toml")
    assert study.spec.ground.pulse == "none"
    assert study.to_json()["ground"]["pulse"] == "none"

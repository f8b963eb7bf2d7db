"""An interrupted FEM case goes on from its last checkpoint (issue 47), with the numbers of an
uninterrupted run: the kernel's state is restored bit for bit and the ground is read from the
step count, so the trajectory after a resume is the same bits (not a statistical equality: the
same machine, the same start).

Pinned: an ensemble stopped after a checkpoint part, while all its runs are in progress and
again after some have ended, ends with every history, frame, summary and file equal to an
uninterrupted ensemble's, and removes its checkpoint; a checkpoint of other inputs, or one
whose files were changed, is not used; a part cut short is dropped (the run goes on from the
part before); the estimate of a resumed study counts only the steps the checkpoint left to do;
and, end to end (slow), SIGINT to `colonna study` in its FEM case, then the same
command: it says it resumed, and its FEM case's result equals an uninterrupted one's."""

import filecmp
import json
import os
import shutil
import signal
import subprocess
import sys
import time
import tomllib
from pathlib import Path

import numpy as np
import pytest

from colonna.core.motion import Motion
from colonna.fem import checkpoint as ck
from colonna.fem import solver
from colonna.fem.settings import FemSettings, Replicas
from colonna.studies.driver import without_saved
from colonna.studies.fem_study import from_dict
from colonna.studies.models import build
from colonna.studies.work import FemRun, FemWork

DEFAULT = Path(__file__).parents[1] / "studies" / "default.toml"
DURATION = 0.8  # s: the pulse and some rocking after it
REPLICAS = 3
SLOTS = 2  # fewer slots than runs: the third waits for a slot, as a larger ensemble's would


@pytest.fixture(scope="module")
def model_and_ground():
    data = tomllib.loads(DEFAULT.read_text())
    data["mesh"]["size"] = 0.225
    study = from_dict(data)
    return build(study), study.ground


def _ensemble(model_and_ground, out, checkpoint=None):
    model, ground = model_and_ground
    return solver.run_ensemble(
        model,
        Motion(ground, DURATION),
        FemSettings(progress=False),
        replicas=Replicas(REPLICAS, slots=SLOTS),
        out_dir=out,
        checkpoint=checkpoint,
    )


@pytest.fixture(scope="module")
def uninterrupted(model_and_ground, tmp_path_factory):
    out = tmp_path_factory.mktemp("uninterrupted")
    return out, _ensemble(model_and_ground, out)


def _stop_after_part(monkeypatch, last: int) -> None:
    """Interrupt the batch (as Ctrl-C would) once part ``last`` is written."""
    write = ck.write_part

    def write_then_stop(checkpoint, index, data):
        write(checkpoint, index, data)
        if index == last:
            raise KeyboardInterrupt

    monkeypatch.setattr(solver, "write_part", write_then_stop)


def _assert_same(results, reference, out, reference_out) -> None:
    for got, expected in zip(results, reference, strict=True):
        assert got.history.keys() == expected.history.keys()
        for key, values in expected.history.items():
            assert np.array_equal(got.history[key], values), key
        walls = ("wall_seconds",)
        assert {k: v for k, v in got.summary.items() if k not in walls} == {
            k: v for k, v in expected.summary.items() if k not in walls
        }
        for name in ("displacement_frames", "velocity_frames"):
            frames, expected_frames = getattr(got, name), getattr(expected, name)
            assert [t for t, _ in frames] == [t for t, _ in expected_frames]
            assert all(np.array_equal(a, b) for (_, a), (_, b) in zip(frames, expected_frames))
        assert all(
            np.array_equal(a["collar_state"], b["collar_state"])
            and np.array_equal(a["base_ft"], b["base_ft"])
            for (_, a), (_, b) in zip(got.contact_frames, expected.contact_frames)
        )
    for name in ("history.csv", "base_pressure.csv", "replicas/1/history.csv"):
        assert filecmp.cmp(out / name, reference_out / name, shallow=False), name


@pytest.mark.parametrize("stop_at", [30, 550], ids=["all running", "after some ended"])
def test_an_interrupted_ensemble_goes_on_from_its_checkpoint_with_the_same_numbers(
    model_and_ground, uninterrupted, tmp_path, monkeypatch, capsys, stop_at
):
    """A part at every output (interval 0): stopped at part 30 (runs 0 and 1 in progress, run 2
    waiting) or 550 (runs 0 and 1 ended: 0.8 s is 400 outputs), then the same call."""
    reference_out, reference = uninterrupted
    checkpoint = ck.Checkpoint(tmp_path / "checkpoint", "inputs", interval=0.0)
    _stop_after_part(monkeypatch, stop_at)
    with pytest.raises(KeyboardInterrupt):
        _ensemble(model_and_ground, tmp_path, checkpoint)
    assert len(list((tmp_path / "checkpoint" / "dt-0").glob("part-*.pkl"))) == stop_at + 1
    monkeypatch.undo()
    steps = reference[0].summary["steps"]
    left = ck.remaining_work(tmp_path / "checkpoint", steps)
    # a study's estimate of time, resumed: its interrupted case counts what is left of it
    study_out = tmp_path / "study"
    shutil.copytree(tmp_path / "checkpoint", study_out / "cases" / "fem" / "checkpoint")
    runs = (FemRun(100, steps, 400, REPLICAS, "fem"), FemRun(100, steps, 400, 1, "rigid"))
    resumed_work = without_saved(FemWork(runs=runs), study_out).runs
    assert resumed_work[0].steps == pytest.approx(left * steps)
    assert resumed_work[1] == runs[1]
    capsys.readouterr()
    results = _ensemble(
        model_and_ground, tmp_path, ck.Checkpoint(tmp_path / "checkpoint", "inputs")
    )
    said = capsys.readouterr().err
    ended = 0 if stop_at == 30 else 2
    assert f"[fem] resumed from the checkpoint in {tmp_path / 'checkpoint' / 'dt-0'}" in said
    assert f"{ended} of {REPLICAS} runs had ended" in said
    _assert_same(results, reference, tmp_path, reference_out)
    assert not (tmp_path / "checkpoint").exists()  # removed once the ensemble is done
    # what the estimate of the resumed study counts: the steps left from where the runs in
    # progress went on (run 2 waits for a slot at part 30, all of its steps left; runs 0 and
    # 1 have ended by part 550, none left)
    resumed_at = float(said.split("the others go on from t = ")[1].split(" s")[0])
    done = round(resumed_at / reference[0].summary["dt"])
    in_progress = 2 if stop_at == 30 else 1
    waiting = 1 if stop_at == 30 else 0
    assert 0 < done < steps
    assert left == pytest.approx(
        (in_progress * (steps - done) + waiting * steps) / (REPLICAS * steps), rel=1e-3
    )


def test_a_checkpoint_of_other_inputs_or_changed_files_is_not_used(
    model_and_ground, uninterrupted, tmp_path, monkeypatch, capsys
):
    reference_out, reference = uninterrupted
    _stop_after_part(monkeypatch, 20)
    with pytest.raises(KeyboardInterrupt):
        _ensemble(model_and_ground, tmp_path, ck.Checkpoint(tmp_path / "c", "old", interval=0.0))
    monkeypatch.undo()
    capsys.readouterr()
    # other inputs: its parts are deleted, the ensemble starts afresh
    other = _ensemble(model_and_ground, tmp_path, ck.Checkpoint(tmp_path / "c", "new"))
    assert "resumed" not in capsys.readouterr().err
    _assert_same(other, reference, tmp_path, reference_out)
    # the same inputs, but the history the run streams was cut: not the run the part saved
    _stop_after_part(monkeypatch, 20)
    with pytest.raises(KeyboardInterrupt):
        _ensemble(model_and_ground, tmp_path, ck.Checkpoint(tmp_path / "c", "old", interval=0.0))
    monkeypatch.undo()
    (tmp_path / "history.csv.part").write_text("t\n")
    capsys.readouterr()
    again = _ensemble(model_and_ground, tmp_path, ck.Checkpoint(tmp_path / "c", "old"))
    assert "does not match this run or its files: starting afresh" in capsys.readouterr().err
    _assert_same(again, reference, tmp_path, reference_out)


def test_a_part_cut_short_is_dropped_and_the_run_goes_on_from_the_one_before(
    model_and_ground, uninterrupted, tmp_path, monkeypatch, capsys
):
    """A run killed while a part was renamed into place cannot happen (the rename is atomic),
    but a disk that lost a part's tail can: that part and any after it are dropped."""
    reference_out, reference = uninterrupted
    _stop_after_part(monkeypatch, 40)
    checkpoint = ck.Checkpoint(tmp_path / "c", "inputs", interval=0.0)
    with pytest.raises(KeyboardInterrupt):
        _ensemble(model_and_ground, tmp_path, checkpoint)
    monkeypatch.undo()
    folder = tmp_path / "c" / "dt-0"
    cut = folder / "part-00035.pkl"
    cut.write_bytes(cut.read_bytes()[:100])
    assert len(ck.read_parts(ck.Checkpoint(folder, "inputs/ensemble"))) == 35
    assert not (folder / "part-00036.pkl").exists()
    capsys.readouterr()
    results = _ensemble(model_and_ground, tmp_path, ck.Checkpoint(tmp_path / "c", "inputs"))
    assert "[fem] resumed from the checkpoint" in capsys.readouterr().err
    _assert_same(results, reference, tmp_path, reference_out)


def test_the_checkpoint_interval_is_read_from_the_environment(monkeypatch):
    from colonna.core.errors import InputError

    monkeypatch.setenv("COLONNA_CHECKPOINT_SECONDS", "30")
    assert ck.Checkpoint(Path("x"), "k").interval == 30.0
    monkeypatch.setenv("COLONNA_CHECKPOINT_SECONDS", "soon")
    with pytest.raises(InputError, match="COLONNA_CHECKPOINT_SECONDS = 'soon' must be a positive"):
        ck.checkpoint_seconds()
    monkeypatch.delenv("COLONNA_CHECKPOINT_SECONDS")
    assert ck.checkpoint_seconds() == ck.CHECKPOINT_SECONDS


def _at_a_terminal() -> None:  # see tests/test_executor.py: Ctrl-C as at a terminal
    signal.signal(signal.SIGINT, signal.SIG_DFL)


@pytest.mark.slow
def test_sigint_in_a_fem_case_then_the_same_command_resumes_with_the_same_numbers(tmp_path):
    """The issue's acceptance, end to end: `colonna study` of the tiny study over 3 s, parts
    every 0.2 s; SIGINT to its process group once its FEM case has saved two parts; the same
    command again says it resumed, and its FEM case's result (the ensemble's summary and every
    replica's) equals that of an uninterrupted run of the same command."""
    sys.path.insert(0, str(Path(__file__).parent))
    from tiny_study import TINY_STUDY

    study = tmp_path / "tiny.toml"
    study.write_text(TINY_STUDY.format(amplitude_ratio=1.5, duration=3.0))
    env = {**os.environ, "COLONNA_CHECKPOINT_SECONDS": "0.2"}
    colonna = [sys.executable, "-m", "colonna.studies.cli", "study", str(study), "--out"]

    def command(out):
        return subprocess.Popen(
            [*colonna, str(out)],
            stdout=subprocess.DEVNULL,
            stderr=subprocess.PIPE,
            text=True,
            env=env,
            start_new_session=True,
            preexec_fn=_at_a_terminal,
        )

    out = tmp_path / "out"
    proc = command(out)
    parts = out / "cases" / "fem" / "checkpoint" / "dt-0"
    deadline = time.monotonic() + 120
    while not (parts / "part-00001.pkl").exists() and proc.poll() is None:
        assert time.monotonic() < deadline, "the FEM case saved no checkpoint"
        time.sleep(0.02)
    os.killpg(proc.pid, signal.SIGINT)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 128 + signal.SIGINT, err
    assert not (out / "cases" / "fem" / "result.json").exists()
    resumed = command(out)
    _, err = resumed.communicate(timeout=300)
    assert resumed.returncode == 0, err
    assert "[fem] resumed from the checkpoint in" in err
    reference = command(tmp_path / "reference")
    _, reference_err = reference.communicate(timeout=300)
    assert reference.returncode == 0, reference_err

    def fem_numbers(folder):
        result = json.loads((folder / "cases" / "fem" / "result.json").read_text())
        for summary in [result["summary"], *result["replica_summaries"]]:
            summary.pop("wall_seconds", None)
        return result

    assert fem_numbers(out) == fem_numbers(tmp_path / "reference")
    assert not (out / "cases" / "fem" / "checkpoint").exists()

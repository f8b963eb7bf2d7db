"""One colonna run at a time writes an output folder (studies.output.output_lock): a second
run on the same --out stops at once, naming the first, instead of the two overwriting each
other's cases (found running a study twice on one folder by mistake: the second failed
with "cannot write .../history.csv.part: No such file or directory")."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from colonna.studies.cli import main
from colonna.studies.output import LOCK_NAME, FolderInUse, output_lock

STUDIES = Path(__file__).resolve().parents[1] / "studies"

HOLDER = textwrap.dedent(
    """
    import sys
    from colonna.studies.output import output_lock
    with output_lock(sys.argv[1]):
        print("held", flush=True)
        sys.stdin.read()  # until the test closes the pipe, or kills this process
    """
)


def _hold(out: Path) -> subprocess.Popen:
    """Another process holding ``out``, as a running study would."""
    holder = subprocess.Popen(
        [sys.executable, "-c", HOLDER, str(out)],
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        text=True,
    )
    assert holder.stdout.readline().strip() == "held"
    return holder


def test_a_second_study_on_a_folder_in_use_stops_naming_the_run_that_holds_it(tmp_path, capsys):
    out = tmp_path / "out"
    holder = _hold(out)
    try:
        status = main(["study", str(STUDIES / "zhang-makris.toml"), "--out", str(out)])
        written = sorted(p.name for p in out.iterdir())
    finally:
        holder.stdin.close()
        holder.wait(timeout=30)
    err = capsys.readouterr().err
    assert status == 2
    assert f"{out} is being written by another colonna run (pid {holder.pid}" in err
    assert "another --out" in err
    assert written == [LOCK_NAME]  # nothing of the study written
    assert not out.exists()  # the holder made it, wrote nothing in it, and has ended


def test_the_lock_goes_with_the_process_that_held_it_even_killed(tmp_path):
    out = tmp_path / "out"
    holder = _hold(out)
    with pytest.raises(FolderInUse), output_lock(out):
        pass
    holder.send_signal(signal.SIGKILL)
    holder.wait(timeout=30)
    with output_lock(out):  # the system released it with the killed process
        (out / "result.txt").write_text("mine")
    assert sorted(p.name for p in out.iterdir()) == ["result.txt"]  # and no lock left


def test_a_folder_made_for_a_run_that_wrote_nothing_is_removed_and_one_given_is_kept(tmp_path):
    made = tmp_path / "made"
    with output_lock(made):
        assert (made / LOCK_NAME).read_text().startswith(f"pid {os.getpid()}, started ")
    assert not made.exists()
    given = tmp_path / "given"
    given.mkdir()
    with output_lock(given):
        pass
    assert given.is_dir()

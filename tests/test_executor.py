"""The study executor's saved cases are checked, not trusted, and a study stops cleanly: a
damaged or edited result.json is computed again (one line), Ctrl-C or SIGTERM ends the workers
with one line and status 130 or 143, a main process killed outright takes its workers with it,
a lost Dask scheduler is one error line, and --workers is bounded by the machine's cores.

Run as a script (``python tests/test_executor.py OUT``) this file is a ``colonna study`` whose
cases are :func:`napping` (the study's own run replaced), for the tests that signal a process.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import os
import signal
import subprocess
import sys
import threading
import time
import uuid
from pathlib import Path

import pytest

from colonna.core.errors import ColonnaError, InputError, StaleResultsError
from colonna.studies import cli, driver, executor
from colonna.studies.executor import (
    RunOptions,
    StudyInterrupted,
    StudyStopped,
    load_done,
    run_cases,
    save_case,
)

MARKER = "COLONNA_TEST_MARKER"  # in the environment of a signalled study and its workers
QUICK = "COLONNA_TEST_QUICK"  # set: the long cases take no time (the rerun)
LONG = 60.0  # seconds a long case naps: far longer than any test waits


# --- case functions (module level: a worker process finds them by name) ------------------------


def square(case, directory):
    return {"value": case["x"] ** 2, "mode": case.get("mode", "safe")}


def napping(case, directory):
    """A case that says it started (a file in its folder), then naps ``case["seconds"]``."""
    (Path(directory) / "started").write_text(str(os.getpid()))
    if not os.environ.get(QUICK):
        time.sleep(case["seconds"])
    return {"key": case["key"]}


def _cases(n=4, **extra):
    return [{"key": f"c{i}", "x": float(i), **extra} for i in range(n)]


NAPS = [{"key": f"c{i}", "seconds": 0.0 if i < 3 else LONG} for i in range(8)]


def _fake_study(monkeypatch, run):
    """``colonna study free-rocking`` with its run replaced by ``run(out, workers, scheduler)``
    (the study file is not what these tests are about)."""
    monkeypatch.setattr(cli, "_announce_compilation", lambda *args: None)

    def run_study_file(path, out, *, run_options, **options):
        return run(out, run_options.workers, run_options.scheduler) or {}

    monkeypatch.setattr(driver, "run_study_file", run_study_file)


# --- 1. results checked, not trusted -----------------------------------------------------------


@pytest.mark.parametrize("content", [b"", b'{\n  "value": 4', b"\x00\xff"])
@pytest.mark.parametrize("force", [False, True])
def test_a_damaged_result_is_named_and_computed_again(tmp_path, capsys, content, force):
    out = tmp_path / "out"
    run_cases(square, _cases(), out, run_options=RunOptions(progress=False))
    path = out / "cases" / "c2" / "result.json"
    path.write_bytes(content)  # truncated, empty or garbled: a full disk, a crash, a copy
    results = run_cases(square, _cases(), out, run_options=RunOptions(progress=False, force=force))
    assert results["c2"] == {"value": 4.0, "mode": "safe"}
    assert capsys.readouterr().err.splitlines() == [
        f"[study] {path} is damaged or was edited (checksum mismatch): computing it again"
    ]
    assert json.loads(path.read_text()) == results["c2"]  # saved again, and now trusted
    run_cases(square, _cases(), out, run_options=RunOptions(progress=False))
    assert capsys.readouterr().err == ""


def test_an_edited_result_is_never_used(tmp_path, capsys):
    """Only the inputs were hashed once: a result edited by hand flipped the answer."""
    out = tmp_path / "out"
    run_cases(square, _cases(), out, run_options=RunOptions(progress=False))
    path = out / "cases" / "c1" / "result.json"
    path.write_text(path.read_text().replace('"safe"', '"after-impact"'))
    calls = []

    def counted(case, directory):
        calls.append(case["key"])
        return square(case, directory)

    results = run_cases(counted, _cases(), out, run_options=RunOptions(progress=False))
    assert calls == ["c1"] and results["c1"]["mode"] == "safe"
    assert "c1/result.json is damaged or was edited" in capsys.readouterr().err


def test_the_record_holds_the_checksum_of_the_result_bytes(tmp_path):
    out = tmp_path / "out"
    run_cases(square, _cases(1), out, run_options=RunOptions(progress=False))
    folder = out / "cases" / "c0"
    record = json.loads((folder / "inputs.json").read_text())
    digest = hashlib.sha256((folder / "result.json").read_bytes()).hexdigest()
    assert record["result_sha256"] == digest and set(record) == {
        "sha256",
        "inputs",
        "result_sha256",
    }


def test_a_save_stopped_between_record_and_result_is_not_done(tmp_path, monkeypatch, capsys):
    """The record is written first, naming the new result's bytes: stopped before the result
    is, the folder holds a result its record does not name, which is computed again."""
    folder = tmp_path / "cases" / "c0"
    record = {"sha256": "0" * 64, "inputs": {}}
    save_case(folder, record, {"mode": "safe"})
    assert load_done(tmp_path, "c0") == {"mode": "safe"}

    def killed(path, data):
        raise KeyboardInterrupt

    monkeypatch.setattr(executor, "_atomic_write_bytes", killed)
    with pytest.raises(KeyboardInterrupt):
        save_case(folder, record, {"mode": "after-impact"})
    assert json.loads((folder / "result.json").read_text()) == {"mode": "safe"}
    assert load_done(tmp_path, "c0") is None
    assert "checksum mismatch" in capsys.readouterr().err


def test_a_record_without_a_result_checksum_is_refused_then_forced(tmp_path):
    """As a case without a record of its inputs: an older colonna saved it."""
    out = tmp_path / "out"
    run_cases(square, _cases(), out, run_options=RunOptions(progress=False))
    path = out / "cases" / "c3" / "inputs.json"
    record = json.loads(path.read_text())
    del record["result_sha256"]
    path.write_text(json.dumps(record))
    with pytest.raises(StaleResultsError, match="c3 has no checksum of its result on record"):
        run_cases(square, _cases(), out, run_options=RunOptions(progress=False))
    assert (
        run_cases(square, _cases(), out, run_options=RunOptions(progress=False, force=True))["c3"][
            "value"
        ]
        == 9.0
    )
    assert "result_sha256" in json.loads(path.read_text())


def test_an_unreadable_record_is_refused_not_a_traceback(tmp_path):
    out = tmp_path / "out"
    run_cases(square, _cases(), out, run_options=RunOptions(progress=False))
    (out / "cases" / "c0" / "inputs.json").write_text('{"sha256": ["not", "a", "hash"]}')
    with pytest.raises(StaleResultsError, match="c0 has a record of its inputs .* cannot be"):
        run_cases(square, _cases(), out, run_options=RunOptions(progress=False))


def test_cases_saved_from_other_inputs_are_stale_results_not_bad_input(tmp_path):
    """The refusal is its own kind of error (the input is fine, the folder holds other
    results): a ColonnaError that no ``except InputError`` (or ValueError) takes for bad
    input."""
    out = tmp_path / "out"
    run_cases(square, _cases(), out, run_options=RunOptions(progress=False))
    with pytest.raises(StaleResultsError, match="--force") as raised:
        run_cases(square, _cases(mode="other"), out, run_options=RunOptions(progress=False))
    assert isinstance(raised.value, ColonnaError)
    assert not isinstance(raised.value, (InputError, ValueError))


# --- what runs before the first case is computed -----------------------------------------------


def test_before_computing_runs_once_per_run_that_computes(tmp_path):
    """The callback of a ``before_computing`` block runs once before a run computes its cases,
    not for a run whose cases are all saved; the block's end takes it away, and blocks nest."""
    said = []
    out = tmp_path / "out"
    with executor.before_computing(lambda: said.append("outer")):
        run_cases(square, _cases(2), out, run_options=RunOptions(progress=False))
        run_cases(
            square, _cases(2), out, run_options=RunOptions(progress=False)
        )  # all saved: nothing computed
        assert said == ["outer"]
        with executor.before_computing(lambda: said.append("inner")):
            run_cases(
                square, _cases(3), out, run_options=RunOptions(progress=False)
            )  # c2 is computed
        assert said == ["outer", "outer", "inner"]
    run_cases(
        square, _cases(4), out, run_options=RunOptions(progress=False)
    )  # c3, outside any block
    assert said == ["outer", "outer", "inner"]
    assert executor._BEFORE_COMPUTING.get() == ()
    assert not hasattr(executor, "BEFORE_COMPUTING")  # no module-level list left


def test_before_computing_as_an_argument_replaces_the_blocks(tmp_path):
    said = []
    out = tmp_path / "out"
    with executor.before_computing(lambda: said.append("block")):
        run_cases(
            square,
            _cases(2),
            out,
            before_computing=lambda: said.append("arg"),
            run_options=RunOptions(progress=False),
        )
    assert said == ["arg"]


def test_before_computing_is_not_called_for_a_refused_run(tmp_path):
    said = []
    out = tmp_path / "out"
    run_cases(square, _cases(2), out, run_options=RunOptions(progress=False))
    with pytest.raises(StaleResultsError):
        run_cases(
            square,
            _cases(3, mode="other"),
            out,
            before_computing=lambda: said.append("arg"),
            run_options=RunOptions(progress=False),
        )
    assert said == []


# --- 2 and 6. an interrupt keeps what is saved and overwrites nothing --------------------------


def test_an_interrupt_counts_the_saved_cases_and_a_rerun_keeps_them(tmp_path):
    out = tmp_path / "out"

    def stopping_at(key):
        def function(case, directory):
            if case["key"] == key:
                raise KeyboardInterrupt
            return square(case, directory)

        return function

    with pytest.raises(StudyInterrupted) as raised:
        run_cases(stopping_at("c2"), _cases(), out, run_options=RunOptions(progress=False))
    assert str(raised.value) == (
        f"interrupted: 2 of 4 cases saved in {out / 'cases'}; run the same command again to resume"
    )
    assert raised.value.signum == signal.SIGINT
    first = {k: (out / "cases" / k / "result.json").stat().st_mtime_ns for k in ("c0", "c1")}
    with pytest.raises(StudyInterrupted, match="3 of 4 cases saved"):
        run_cases(stopping_at("c3"), _cases(), out, run_options=RunOptions(progress=False))
    results = run_cases(square, _cases(), out, run_options=RunOptions(progress=False))
    assert results == {c["key"]: square(c, None) for c in _cases()}
    for key, mtime in first.items():  # neither interrupted rerun touched them
        assert (out / "cases" / key / "result.json").stat().st_mtime_ns == mtime


def test_an_interrupt_inside_a_parallel_kernel_is_an_interrupt_not_a_traceback(tmp_path):
    """Ctrl-C while numba's parallel threads run a kernel comes back from the kernel's call as
    a SystemError whose context is the KeyboardInterrupt (found interrupting a cross-check in
    its multibody spectrum): it stops the cases as a Ctrl-C does, counting those saved; any
    other SystemError is raised as it is."""

    def kernel_interrupted(case, directory):
        if case["key"] == "c1":
            try:
                raise KeyboardInterrupt
            except KeyboardInterrupt:
                raise SystemError("CPUDispatcher returned a result with an exception set")  # noqa: B904 (as numba: context, no cause)
        return square(case, directory)

    out = tmp_path / "out"
    with pytest.raises(StudyInterrupted, match="1 of 4 cases saved") as raised:
        run_cases(kernel_interrupted, _cases(), out, run_options=RunOptions(progress=False))
    assert raised.value.signum == signal.SIGINT

    def broken(case, directory):
        raise SystemError("a bug")

    with pytest.raises(SystemError, match="a bug"):
        run_cases(broken, _cases(), tmp_path / "other", run_options=RunOptions(progress=False))


# --- 2, 3 and 6. signals to a running `colonna study` ------------------------------------------


def _marked_processes(marker: str) -> list[int]:
    """Live (not zombie) processes whose environment holds the marker."""
    found = []
    needle = f"{MARKER}={marker}".encode()
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            if needle not in (entry / "environ").read_bytes():
                continue
            state = (entry / "stat").read_text().rsplit(")", 1)[1].split()[0]
        except (OSError, IndexError):
            continue
        if state != "Z":
            found.append(int(entry.name))
    return found


def _no_process_left(marker: str, seconds: float = 5.0) -> list[int]:
    deadline = time.monotonic() + seconds
    while (left := _marked_processes(marker)) and time.monotonic() < deadline:
        time.sleep(0.1)
    for pid in left:  # never leave them to the next test
        os.kill(pid, signal.SIGKILL)
    return left


def _at_a_terminal() -> None:
    """Ctrl-C as at a terminal: a test run started in the background of a shell without job
    control (``cmd &`` in a script, as some CI runners do) ignores SIGINT, and a command
    inherits that (the shell's way to keep Ctrl-C from background jobs)."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def _start_study(out: Path, marker: str) -> subprocess.Popen:
    env = {**os.environ, MARKER: marker}
    env.pop(QUICK, None)
    return subprocess.Popen(
        [sys.executable, __file__, str(out)],
        stdout=subprocess.DEVNULL,  # the summary: not what is tested
        stderr=subprocess.PIPE,
        text=True,
        env=env,
        start_new_session=True,  # its own process group, as a shell gives a command
        preexec_fn=_at_a_terminal,
    )


def _wait_for_long_cases(proc: subprocess.Popen, out: Path) -> dict:
    """The three short cases saved and two long ones running; their result files' bytes."""
    deadline = time.monotonic() + 60
    cases = out / "cases"
    while time.monotonic() < deadline and proc.poll() is None:
        saved = [cases / f"c{i}" / "result.json" for i in range(3)]
        started = [cases / f"c{i}" / "started" for i in (3, 4)]
        if all(p.exists() for p in saved + started):
            return {p: (p.read_bytes(), p.stat().st_mtime_ns) for p in saved}
        time.sleep(0.05)
    proc.kill()
    pytest.fail(f"the study did not get to its long cases: {proc.communicate()}")


needs_proc = pytest.mark.skipif(not Path("/proc/self/environ").exists(), reason="needs /proc")


@needs_proc
@pytest.mark.parametrize(
    "signum, to_group", [(signal.SIGINT, True), (signal.SIGTERM, False), (signal.SIGTERM, True)]
)
def test_a_signalled_study_stops_its_workers_says_so_and_resumes(
    tmp_path, monkeypatch, signum, to_group
):
    """Ctrl-C at a terminal (SIGINT to the process group), or SIGTERM (kill, a job
    scheduler): one line, status 128 + the signal, no worker left, the saved cases kept."""
    out, marker = tmp_path / "out", uuid.uuid4().hex
    proc = _start_study(out, marker)
    saved = _wait_for_long_cases(proc, out)
    if to_group:
        os.killpg(proc.pid, signum)
    else:
        proc.send_signal(signum)
    try:
        _, err = proc.communicate(timeout=15)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.communicate()
        pytest.fail("the study went on after the signal")
    finally:
        left = _no_process_left(marker)
    assert err.splitlines() == [
        f"colonna: interrupted: 3 of 8 cases saved in {out / 'cases'}; "
        "run the same command again to resume"
    ]
    assert proc.returncode == 128 + signum
    assert left == []
    for path, (data, mtime) in saved.items():
        assert (path.read_bytes(), path.stat().st_mtime_ns) == (data, mtime)
    monkeypatch.setenv(QUICK, "1")
    assert run_cases(napping, NAPS, out, run_options=RunOptions(workers=2, progress=False)) == {
        c["key"]: {"key": c["key"]} for c in NAPS
    }
    for path, (data, mtime) in saved.items():  # loaded, not computed again
        assert (path.read_bytes(), path.stat().st_mtime_ns) == (data, mtime)


@needs_proc
def test_workers_end_with_a_main_process_killed_outright(tmp_path):
    out, marker = tmp_path / "out", uuid.uuid4().hex
    proc = _start_study(out, marker)
    _wait_for_long_cases(proc, out)
    assert len(_marked_processes(marker)) >= 3  # the main process and its two workers
    proc.kill()  # SIGKILL: no handler runs
    proc.wait()
    left = _no_process_left(marker)
    proc.communicate()  # (after: a worker left holds its pipes open)
    assert left == []


# --- 4. a lost Dask scheduler ------------------------------------------------------------------


def test_a_lost_dask_scheduler_is_one_error_line(tmp_path, monkeypatch, capfd):
    pytest.importorskip("distributed")
    tests = str(Path(__file__).parent)
    code = (
        "import time\nfrom distributed import LocalCluster\n"
        "c = LocalCluster(n_workers=1, threads_per_worker=1, processes=False, "
        "dashboard_address=None, host='127.0.0.1', protocol='tcp')\n"
        "print(c.scheduler_address, flush=True)\ntime.sleep(120)\n"
    )
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([tests, os.environ.get("PYTHONPATH", "")])}
    env.pop(QUICK, None)
    cluster = subprocess.Popen(
        [sys.executable, "-c", code],
        stdout=subprocess.PIPE,
        stderr=subprocess.DEVNULL,
        env=env,
        text=True,
    )
    out = tmp_path / "out"
    cases = [{"key": f"c{i}", "seconds": 0.3} for i in range(8)]

    def lose_the_scheduler_after_two_cases():
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline and len(list(out.glob("cases/*/result.json"))) < 2:
            time.sleep(0.02)
        cluster.kill()

    def run(out, workers, scheduler):
        threading.Thread(target=lose_the_scheduler_after_two_cases, daemon=True).start()
        run_cases(napping, cases, out, run_options=RunOptions(scheduler=scheduler, progress=False))

    _fake_study(monkeypatch, run)
    try:
        address = cluster.stdout.readline().strip()
        assert address.startswith("tcp://"), address
        capfd.readouterr()
        status = cli.main(["study", "free-rocking", "--out", str(out), "--scheduler", address])
    finally:
        cluster.kill()
        cluster.wait()
    err = capfd.readouterr().err
    saved = len(executor.saved_cases(out))
    assert 2 <= saved < 8
    assert err.splitlines() == [
        f"colonna: error: the Dask scheduler {address} was lost after {saved} of 8 cases: the "
        "cases saved are kept; run the same command again to resume"
    ]
    assert status == 1


def test_a_stopped_study_is_one_error_line_with_status_1(monkeypatch, capsys, tmp_path):
    def run(out, workers, scheduler):
        raise StudyStopped("the Dask scheduler tcp://x:1 was lost after 0 of 1 cases")

    _fake_study(monkeypatch, run)
    assert cli.main(["study", "free-rocking", "--out", str(tmp_path), "--workers", "1"]) == 1
    assert capsys.readouterr().err == (
        "colonna: error: the Dask scheduler tcp://x:1 was lost after 0 of 1 cases\n"
    )


# --- 5. --workers is bounded by the machine ----------------------------------------------------


@pytest.mark.parametrize(
    "workers, cores, words",
    [
        (64, 2, "outside 1..2 (this machine has 2 cores)"),
        (3, 2, "outside 1..2 (this machine has 2 cores)"),
        (0, 2, "outside 1..2 (this machine has 2 cores)"),
        (-1, 2, "outside 1..2 (this machine has 2 cores)"),
        (2, 1, "outside 1..1 (this machine has 1 core)"),
    ],
)
def test_workers_beyond_the_cores_are_an_error(
    tmp_path, monkeypatch, capsys, workers, cores, words
):
    monkeypatch.setattr(os, "sched_getaffinity", lambda pid: set(range(cores)), raising=False)
    monkeypatch.setattr(os, "cpu_count", lambda: cores)

    def run(out, workers, scheduler):
        raise AssertionError("a study with a bad --workers ran")

    _fake_study(monkeypatch, run)
    out = tmp_path / "out"
    argv = ["study", "free-rocking", "--out", str(out), "--workers", str(workers)]
    assert cli.main(argv) == 2
    assert capsys.readouterr().err == f"colonna: error: --workers = {workers} is {words}\n"
    assert not out.exists()


def test_workers_up_to_the_cores_run(tmp_path, monkeypatch):
    monkeypatch.setattr(os, "sched_getaffinity", lambda pid: {0, 1}, raising=False)
    monkeypatch.setattr(os, "cpu_count", lambda: 2)
    ran = []
    _fake_study(monkeypatch, lambda out, workers, scheduler: ran.append(workers))
    assert cli.main(["study", "free-rocking", "--out", str(tmp_path), "--workers", "2"]) == 0
    assert ran == [2]


# --- the signalled study, run as a script ------------------------------------------------------


@pytest.mark.parametrize("columns", [0, 60])
def test_the_progress_bar_is_drawn_on_a_terminal_that_reports_no_width(monkeypatch, columns):
    """A pseudo-terminal nobody sized (``script``, some CI and editor consoles) reports 0
    rows and columns, and tqdm draws nothing on 0 rows: the study's bar (its stage, its cases
    and the study's time left) must still show. A sized terminal keeps its own width."""
    import pty
    import select
    import struct
    import termios
    from fcntl import ioctl

    from tqdm import tqdm

    # no monitor thread left behind for the rest of the session (a drawn bar starts one)
    monkeypatch.setattr(tqdm, "monitor_interval", 0)
    master, slave = pty.openpty()
    ioctl(slave, termios.TIOCSWINSZ, struct.pack("HHHH", 24 if columns else 0, columns, 0, 0))
    terminal = os.fdopen(slave, "w", buffering=1)
    monkeypatch.setattr(sys, "stderr", terminal)
    try:
        bar = executor._progress_bar(3, 0, "FEM and rigid models", True)
        bar.set_postfix_str("7 min left", refresh=True)
        bar.update()
        bar.refresh()  # not left to the bar's own interval between draws
        bar.close()
        terminal.flush()
        chunks = []  # all that reached the terminal (one read may return a part)
        while select.select([master], [], [], 0.2)[0]:
            chunk = os.read(master, 65536)
            if not chunk:
                break
            chunks.append(chunk)
        drawn = b"".join(chunks).decode(errors="replace")
    finally:
        terminal.close()
        os.close(master)
    line = drawn.split("\r")[-2] if "\r" in drawn else drawn
    assert "[study] FEM and rigid models" in drawn and "1/3" in drawn and "7 min" in drawn
    assert len(line.rstrip()) <= (columns or 100)


def _script(out: str) -> int:
    """``colonna study`` on 8 napping cases with 2 workers, whatever this machine's cores."""
    os.sched_getaffinity = lambda pid: set(range(4))
    cli._announce_compilation = lambda *args: None

    def run_study_file(path, out, *, run_options, **options):
        run_cases(napping, NAPS, out, run_options=dataclasses.replace(run_options, progress=False))
        return {}

    driver.run_study_file = run_study_file
    return cli.main(["study", "free-rocking", "--out", out, "--workers", "2"])


if __name__ == "__main__":
    sys.exit(_script(sys.argv[1]))

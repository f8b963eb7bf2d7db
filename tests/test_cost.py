"""The time a study announces (issue 47): the cost model's formula, its fit, its calibration on
this machine kept per machine, the wall time of cases dealt to workers, and the line and the
time left the user reads. (How close the estimate comes to the wall time is measured by
benchmarks/bench_estimate.py, not by a timed test.)"""

import json
import sys
import time
from pathlib import Path

import pytest

from colonna.studies import cost
from colonna.studies.cost import CostModel, fit
from colonna.studies.work import FemRun, FemWork

TRUE = CostModel(
    group_step=2e-6,
    group_node_step=1e-8,
    single_step=5e-6,
    single_node_step=3e-8,
    output=1.5e-4,
    output_node=1e-8,
)


def _measured(model: CostModel) -> list[dict]:
    """The calibration's measurements, their seconds those of ``model``."""
    rows = []
    for nodes in (168, 440, 1512):
        for states in (1, 8):
            for per_output in (100, 5):
                steps = 3000 if states == 1 else 1500
                outputs = steps // per_output
                seconds = model.run_seconds(nodes, steps, outputs, states)
                rows.append(
                    {
                        "nodes": nodes,
                        "states": states,
                        "steps": steps,
                        "outputs": outputs,
                        "seconds": seconds,
                    }
                )
    return rows


def test_the_fit_recovers_the_model_its_measurements_came_from():
    fitted = fit(_measured(TRUE))
    for name in (
        "group_step",
        "group_node_step",
        "single_step",
        "single_node_step",
        "output",
        "output_node",
    ):
        assert getattr(fitted, name) == pytest.approx(getattr(TRUE, name), rel=1e-6), name
    assert fitted.calibrated


def test_the_fit_keeps_every_cost_positive_under_noise():
    noisy = _measured(TRUE)
    for i, row in enumerate(noisy):  # +-10 %, alternating
        row["seconds"] *= 1.1 if i % 2 else 0.9
    fitted = fit(noisy)
    assert all(getattr(fitted, n) >= 0.0 for n in ("output_node", "single_step", "group_step"))
    for row in noisy:  # still within the noise of each measurement, and a little more
        predicted = fitted.run_seconds(row["nodes"], row["steps"], row["outputs"], row["states"])
        assert 0.8 < predicted / row["seconds"] < 1.25


def test_a_run_alone_costs_the_single_layout_and_a_batch_the_group_one():
    one = TRUE.run_seconds(1000, 100, 0, 1)
    assert one == pytest.approx(100 * (5e-6 + 1000 * 3e-8))
    eight = TRUE.run_seconds(1000, 100, 10, 8)
    assert eight == pytest.approx(800 * (2e-6 + 1e-5) + 80 * (1.5e-4 + 1e-5))
    assert TRUE.run_seconds(1000, 0, 0, 8) == 0.0


def test_a_calibration_is_this_machine_s_and_this_version_s(tmp_path, monkeypatch):
    monkeypatch.setenv("COLONNA_CACHE_DIR", str(tmp_path))
    cost._LOADED.clear()
    assert cost.cost_model() == cost.UNCALIBRATED and not cost.cost_model().calibrated
    path = cost.save_calibration(TRUE, _measured(TRUE))
    assert path == tmp_path / cost.FILE_NAME
    loaded = cost.cost_model()
    assert loaded.calibrated and loaded.single_node_step == TRUE.single_node_step
    data = json.loads(path.read_text())
    data["machine"]["processor"] = "another processor"
    path.write_text(json.dumps(data))
    cost._LOADED.clear()
    assert cost.cost_model() == cost.UNCALIBRATED  # another machine's: not used
    path.write_text("{not json")
    cost._LOADED.clear()
    assert cost.cost_model() == cost.UNCALIBRATED
    cost._LOADED.clear()


def _case(name: str, seconds: float, stage: int = 0) -> FemWork:
    return FemWork(runs=(FemRun(0, 0, 0, 0, name, stage, other_seconds=seconds),))


def test_cases_are_dealt_to_the_workers_and_stages_follow_each_other():
    work = _case("a", 10.0) + _case("b", 6.0) + _case("c", 5.0) + _case("t", 3.0, stage=1)
    assert work.cpu_seconds == 24.0
    assert work.wall_seconds(1) == 24.0
    assert work.wall_seconds(2) == 11.0 + 3.0  # a | b + c, then t
    assert work.wall_seconds(8) == 10.0 + 3.0  # the longest case bounds a stage
    # the runs of one case follow each other: two runs of case "a" are one case of 16 s
    assert (work + _case("a", 6.0)).wall_seconds(8) == 16.0 + 3.0


def test_the_time_left_counts_down_from_the_estimate_and_then_says_it_is_past():
    from colonna.studies.executor import StudyClock, time_left

    assert StudyClock().reading() is None  # not started: no time left to say
    assert time_left((100.0, 300.0), now=160.0) == "about 4 min left of 5 min estimated"
    assert time_left((100.0, 30.0), now=145.0) == "15 s past the 30 s estimated"


def test_a_revised_estimate_counts_from_now_and_a_changed_one_is_said(capsys):
    """A stage whose work is known only when it starts (the toe windows) estimates the study
    again: the time spent plus what is left; a change of more than a tenth is said once."""
    from colonna.studies.executor import StudyClock, revise_study_estimate, study_clock
    from colonna.studies.units import duration_text

    clock = StudyClock()
    assert clock.revise(50.0) is None  # not started: nothing to revise
    clock.start(300.0)
    started = clock.started
    assert clock.revise(100.0, now=started + 240.0) == pytest.approx(340.0)
    assert clock.reading() == (started, pytest.approx(340.0))
    with study_clock(clock):
        revise_study_estimate(lambda: clock.estimate - (time.monotonic() - started) + 5.0, "now")
        assert capsys.readouterr().err == ""  # 5 s more: not worth a line
        revise_study_estimate(lambda: 600.0, "as the windows start")
    said = capsys.readouterr().err
    assert said.startswith("[study] estimated again as the windows start: ")
    assert said.rstrip().endswith(f" of wall time in all, not {duration_text(345.0)}")
    assert clock.estimate == pytest.approx(time.monotonic() - started + 600.0, abs=1.0)
    asked = []
    revise_study_estimate(lambda: asked.append(1) or 1.0, "no study running")
    assert capsys.readouterr().err == "" and not asked  # outside a study's clock: nothing


def test_the_toe_windows_are_estimated_again_at_their_length_as_they_start(tmp_path, capsys):
    """The toe windows' work is their length's: ten times the steps for a window ten times
    TOE_WINDOW (as a record's, whose peak comes as the column tilts on its toe, and which the
    estimate expects of a record), and the study's clock is set to it as the windows start."""
    from colonna.studies.crosscheck.runner import (
        TOE_WINDOW,
        TOE_WINDOW_RECORD,
        expected_toe_window,
        revise_toe_estimate,
        toe_window_work,
    )
    from colonna.studies.driver import wall_estimate
    from colonna.studies.executor import RunOptions, StudyClock, study_clock
    from colonna.studies.study import load

    sys.path.insert(0, str(Path(__file__).parent))
    from tiny_study import TINY_STUDY

    study = tmp_path / "tiny.toml"
    study.write_text(TINY_STUDY.format(amplitude_ratio=2.5, duration=0.3))
    fem = load(study).fem
    assert expected_toe_window(fem) == TOE_WINDOW  # a pulse's peak: at a landing
    record = tmp_path / "record.toml"
    suite = Path(__file__).parents[1] / "studies" / "suites" / "synthetic-pulses"
    record.write_text(
        f'[column]\nheight = 4.0\nwidth = 0.45\n[ground]\npulse = "record"\n'
        f'record = "{(suite / "synth02.AT2").as_posix()}"\n'
    )
    assert expected_toe_window(load(record).fem) == TOE_WINDOW_RECORD > TOE_WINDOW
    short, long = toe_window_work(fem), toe_window_work(fem, 10 * TOE_WINDOW)
    assert [r.case for r in long.runs] == [r.case for r in short.runs]
    for a, b in zip(short.runs, long.runs):
        assert (b.nodes, b.steps) == (a.nodes, pytest.approx(10 * a.steps))
    clock = StudyClock()
    clock.start(1.0)
    with study_clock(clock):
        revise_toe_estimate(
            fem, {"t_start": 2.0, "t_end": 2.0 + 10 * TOE_WINDOW}, tmp_path, RunOptions(2)
        )
    left = clock.estimate - (time.monotonic() - clock.started)
    assert left == pytest.approx(wall_estimate(long, 2), abs=1.0)
    assert f"as the toe stress windows start, {1e3 * 10 * TOE_WINDOW:.0f} ms long" in (
        capsys.readouterr().err
    )


def test_a_study_announces_its_wall_and_cpu_time_before_it_starts(tmp_path, capsys):
    """As the work starts: the study's wall time on its workers and CPU time at this machine's
    cost model (studies.driver.work_estimate of the kind's own work), said once before the
    first case is computed; then the report."""
    sys.path.insert(0, str(Path(__file__).parent))
    from tiny_study import TINY_STUDY

    from colonna.studies.cli import main
    from colonna.studies.driver import (
        STUDY_OVERHEAD_SECONDS,
        expected_work_of,
        fem_work_of,
        wall_estimate,
        work_estimate,
    )
    from colonna.studies.study import load

    study = tmp_path / "tiny.toml"
    study.write_text(TINY_STUDY.format(amplitude_ratio=2.5, duration=0.3))
    work = fem_work_of(load(study))
    cases = {run.case for run in work.runs}
    assert {"fem", "fem-bed-low", "fem-bed-high", "toe-8", "multibody", "spectrum"} <= cases
    assert wall_estimate(work, 1) == pytest.approx(work.cpu_seconds + STUDY_OVERHEAD_SECONDS)
    assert wall_estimate(work, 2) < wall_estimate(work, 1)
    # one worker: a pool forked from this process, which has run OpenMP, would be killed
    assert main(["study", str(study), "--out", str(tmp_path / "out"), "--workers", "1"]) == 0
    err = capsys.readouterr().err
    line = f"[study] {work_estimate(expected_work_of(load(study), work), 1)}"
    assert line in err and err.index(line) < err.index("[study] report")
    assert err.count("[study] estimated") == 1
    assert line.startswith("[study] estimated ") and " of wall time on 1 worker (" in line
    assert " of wall time on 2 workers (" in work_estimate(work, 2)


def test_the_cross_check_expects_its_fem_runs_to_stop_where_its_rigid_model_overturns():
    """The default study's multibody overturns at 1.39 s of 2.53 s: its FEM runs are expected
    a quarter of the way from there to the end, their time scaled to it; a study whose
    multibody stays up is expected to its end; the work limit's measure is the whole
    duration's either way."""
    from colonna.studies.crosscheck.runner import expected_stop, fem_work
    from colonna.studies.driver import expected_work_of
    from colonna.studies.models import run_multibody
    from colonna.studies.study import load

    study = load(Path(__file__).parents[1] / "studies" / "default.toml")
    fem = study.fem
    overturn = run_multibody(fem).summary()["overturn_time"]
    assert overturn < fem.duration
    assert expected_stop(fem) == pytest.approx(overturn + 0.25 * (fem.duration - overturn))
    full = fem_work(study)
    expected = expected_work_of(study, full)  # as the driver reads it from the kind
    assert expected.seconds == full.seconds  # the limit's measure: the whole duration
    ratio = expected_stop(fem) / fem.duration
    by_case = {r.case: r for r in expected.runs}
    for run in full.runs:
        if run.case.startswith("fem"):
            assert by_case[run.case].steps == pytest.approx(ratio * run.steps)

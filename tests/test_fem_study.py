"""FEM study files and ``colonna fem``: contracts of the outputs, and bad input named by key."""

import json
import math
import re

import pytest
from tiny_study import TINY_STUDY

from colonna.rigid import InputError, NoMotion
from colonna.studies.cli import main
from colonna.studies.fem_study import from_dict
from colonna.studies.study import load

TINY = TINY_STUDY.format(amplitude_ratio=2.0, duration=0.05)


def test_fem_command_writes_the_documented_outputs(tmp_path, capsys):
    study = tmp_path / "tiny.toml"
    study.write_text(TINY)
    assert main(["fem", str(study), "--out", str(tmp_path / "out"), "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    for key in (
        "overturned",
        "max_abs_theta_left",
        "max_abs_theta_right",
        "collar_max_utilisation",
        "collar_first_yield_time",
        "edge_stress_max",
        "edge_stress_ratio",
        "energy_error_max",
        "dt",
        "steps",
        "dofs",
        "wall_seconds",
    ):
        assert key in summary
    header = (tmp_path / "out" / "history.csv").read_text().splitlines()[0].split(",")
    for column in (
        "t",
        "theta_left",
        "theta_right",
        "uplift_left",
        "uplift_right",
        "edge_stress_left",
        "edge_stress_right",
        "energy_error",
        "collar_1_stress",
    ):
        assert column in header
    for name in (
        "summary.json",
        "fields_initial.vtu",
        "fields_peak_rotation.vtu",
        "fields.xdmf",
        "base_pressure.csv",
    ):
        assert (tmp_path / "out" / name).stat().st_size > 0
    import meshio

    snapshot = meshio.read(tmp_path / "out" / "fields_initial.vtu")
    # under gravity the column is in compression: sigma_yy < 0 in (almost) every element
    assert (snapshot.cell_data["sigma_yy"][0] < 0).mean() > 0.9
    saved = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert saved["steps"] == summary["steps"]


def test_default_study_loads():
    study = load("studies/default.toml").fem
    assert study.cracked and len(study.collars) == 3
    assert study.rocking_block.b == pytest.approx(0.45 / 4)


def test_top_load_study_shares_the_load_between_the_halves():
    study = load("studies/default-top-load.toml").fem
    assert study.top_load == 40e3 and study.cracked
    half = study.rocking_block
    assert half.top_load == pytest.approx(20e3)
    lam = 20e3 / (half.mass * 9.81)
    assert half.uplift_acceleration() == pytest.approx(9.81 * math.tan(half.alpha) * (1 + lam))
    # the pulse is given relative to that uplift level
    assert study.ground.amplitude == pytest.approx(3.0 * half.uplift_acceleration())


def test_vertical_ground_motion_of_a_study():
    study = from_dict(
        _study(
            **{
                "ground.vertical_amplitude": -3.0,
                "ground.vertical_period": 0.25,
                "ground.vertical_phase": 0.5,
            }
        )
    )
    v = study.vertical
    assert (v.amplitude, v.omega, v.phase) == (-3.0, pytest.approx(2 * math.pi / 0.25), 0.5)
    assert v.duration == pytest.approx(study.ground.end_time)  # the horizontal pulse's
    assert from_dict(_study()).vertical == NoMotion()


def _study(**changes):
    import tomllib

    data = tomllib.loads(TINY)
    for dotted, value in changes.items():
        table, key = dotted.split(".")
        if table == "collar":
            data["collar"][0][key] = value
        else:
            data.setdefault(table, {})[key] = value
    return data


@pytest.mark.parametrize(
    "changes, name",
    [
        ({"column.height": -1.0}, "column.height"),
        ({"column.widht": 0.3}, "column.widht"),
        ({"collar.y": 2.0}, "collar[1].y"),
        ({"contact.friction": -0.1}, "friction"),
        ({"mesh.size": 0.5}, "mesh.size"),
        ({"ground.amplitude_ratio": 0.5}, "amplitude_ratio"),
        ({"ground.pulse": "square"}, "ground.pulse"),
        ({"stone.nu": 0.7}, "nu"),
        ({"run.initial_tilt": 1.0}, "run.initial_tilt"),
        ({"column.top_load": -5.0}, "column.top_load"),
        ({"column.top_load": "heavy"}, "top_load"),
        ({"mesh.toe_refinements": [1, 3, 9]}, "mesh.toe_refinements"),
        ({"mesh.toe_refinements": [1, 2]}, "mesh.toe_refinements"),
        ({"mesh.edge_time": 0.5}, "mesh.edge_time"),
        ({"ground.vertical_amplitude": 3.0}, "ground.vertical_period"),
        ({"ground.vertical_scale": 2.0}, "ground.vertical_amplitude"),
        (
            {"ground.vertical_amplitude": 1e3, "ground.vertical_period": 0.2},
            "ground.vertical_amplitude",
        ),
        (
            {"ground.vertical_amplitude": 2.0, "ground.vertical_period": -0.2},
            "ground.vertical_period",
        ),
        ({"run.initial_angular_velocity": float("inf")}, "run.initial_angular_velocity"),
    ],
)
def test_bad_study_values_name_the_key(changes, name):
    with pytest.raises(InputError, match=re.escape(name)):
        from_dict(_study(**changes))


def test_time_step_above_stable_is_rejected_on_the_command_line(tmp_path, capsys):
    study = tmp_path / "dt.toml"
    study.write_text(TINY.replace("duration = 0.05", "duration = 0.05\ndt = 1e-3"))
    assert main(["fem", str(study), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "run dt" in err[0] and "stable" in err[0]


def test_unknown_study_name(capsys):
    assert main(["fem", "no-such-study", "--out", "x"]) == 2
    assert "no-such-study" in capsys.readouterr().err


def test_study_with_a_mesh_made_elsewhere(tmp_path, capsys):
    """A gmsh file of the column (here written by meshio) replaces the built-in mesher."""
    from colonna.meshes.column import column_mesh
    from colonna.meshes.io import write

    write(tmp_path / "column.msh", column_mesh(0.2, 1.0, 0.05, cracked=True))
    study = tmp_path / "gmsh.toml"
    study.write_text(
        TINY.replace("[mesh]\nsize = 0.05\ngrading = 0.0", '[mesh]\nfile = "column.msh"')
    )
    assert main(["fem", str(study), "--out", str(tmp_path / "o"), "--json"]) == 0
    # 2 halves x 3 x 21 nodes x 2 dofs
    assert json.loads(capsys.readouterr().out)["dofs"] == 2 * 3 * 21 * 2
    wrong = tmp_path / "wrong.toml"
    wrong.write_text(study.read_text().replace("width = 0.2", "width = 0.3"))
    assert main(["fem", str(wrong), "--out", str(tmp_path / "o2")]) == 2
    assert "differs from column.width" in capsys.readouterr().err


def test_free_rocking_study_needs_initial_conditions_and_no_pulse_keys():
    import tomllib

    data = tomllib.loads(TINY)
    data["ground"] = {"pulse": "none"}
    with pytest.raises(InputError, match="initial_tilt"):
        from_dict(data)
    data["run"]["initial_tilt"] = 0.02
    study = from_dict(data)
    assert study.ground.end_time == 0.0 and study.initial_tilt == 0.02
    data["ground"]["amplitude_ratio"] = 2.0
    with pytest.raises(InputError, match="ground.amplitude_ratio"):
        from_dict(data)


def test_cross_check_refuses_a_study_without_ground_motion(tmp_path, capsys):
    study = tmp_path / "free.toml"
    study.write_text(
        TINY.replace("[ground]", '[ground]\npulse = "none"')
        .replace("amplitude_ratio = 2.0\n", "")
        .replace("omega_ratio = 3.0\n", "")
        .replace("[run]", "[run]\ninitial_tilt = 0.02")
    )
    assert main(["study", str(study), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert "free-rocking" in err and err.count("\n") == 1


def test_progress_bars_stay_quiet_off_a_terminal(tmp_path):
    """Run as a CI log would (stderr a pipe, not a terminal): no progress bar, no carriage
    returns; the only stderr lines are the study's own messages."""
    import subprocess
    import sys
    from pathlib import Path

    study = tmp_path / "tiny.toml"
    study.write_text(TINY)
    proc = subprocess.run(
        [
            sys.executable,
            "-m",
            "colonna.studies.cli",
            "fem",
            str(study),
            "--out",
            str(tmp_path / "out"),
        ],
        capture_output=True,
        text=True,
        cwd=Path(__file__).parents[1],
        timeout=300,
    )
    assert proc.returncode == 0, proc.stderr
    assert "\r" not in proc.stderr and "%|" not in proc.stderr
    assert (tmp_path / "out" / "history.csv").exists()

"""The ``colonna`` command line: JSON contracts, files written, one-line errors."""

import json

import pytest

from colonna.studies.cli import main


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


ZM = ("--p", "2.14", "--alpha", "0.25", "--restitution", "0.9")


def test_rigid_json_contract(capsys):
    code, out, _ = run(capsys, "rigid", *ZM, "--model", "linear", "--omega-ratio", "5",
                       "--amplitude-ratio", "4", "--json")
    assert code == 0
    data = json.loads(out)
    assert data["overturned"] is True and data["mode"] == "after-impact"
    assert isinstance(data["impacts"], int) and data["impacts"] >= 1
    assert isinstance(data["max_abs_theta_over_alpha"], float)


def test_rigid_out_writes_history(capsys, tmp_path):
    collars = tmp_path / "collars.toml"
    collars.write_text("[[collar]]\ny = 1.0\nt = 0.01\nh = 0.04\n\n"
                       "[[collar]]\ny = 3.0\nt = 0.01\nh = 0.04\n")
    code, out, _ = run(capsys, "rigid", "--b", "0.2", "--h", "2.0", "--density", "2700",
                       "--omega-ratio", "2", "--amplitude-ratio", "2", "--collars",
                       str(collars), "--out", str(tmp_path / "o"), "--json")
    assert code == 0
    data = json.loads(out)
    assert "collar_max_utilisation" in data
    header = (tmp_path / "o" / "history.csv").read_text().splitlines()[0].split(",")
    assert header[:3] == ["t", "theta", "theta_dot"] and "collar_2_stress" in header
    assert (tmp_path / "o" / "history.png").stat().st_size > 1000


def test_spectrum_json_contract(capsys, tmp_path):
    code, out, _ = run(capsys, "spectrum", *ZM, "--model", "linear", "--omega-ratios", "1:9:5",
                       "--amplitude-ratios", "1.5:10:4", "--json", "--out", str(tmp_path))
    assert code == 0
    data = json.loads(out)
    assert len(data["mode"]) == 4 and len(data["mode"][0]) == 5
    assert data["omega_ratios"][0] == 1.0 and len(data["amplitude_ratios"]) == 4
    assert "layout" in data and isinstance(data["seconds"], float)
    assert (tmp_path / "spectrum.png").exists()


def test_design_json(capsys, tmp_path):
    code, out, _ = run(capsys, "design", "--b", "0.2", "--h", "2.0", "--density", "2700",
                       "--collar-t", "0.01", "--collar-h", "0.05", "--ag-ratio", "0.3",
                       "--json", "--out", str(tmp_path))
    assert code == 0
    data = json.loads(out)
    assert data["required_stiffness"] > 0 and data["collars_needed"] >= 1
    assert (tmp_path / "design_chart.png").exists()


@pytest.mark.parametrize("argv, word", [
    (("rigid", "--p", "2", "--alpha", "2", "--omega-ratio", "2", "--amplitude-ratio", "2"),
     "alpha"),
    (("rigid", *ZM, "--omega-ratio", "2", "--amplitude-ratio", "0.5"), "amplitude ratio"),
    (("rigid", "--b", "-1", "--h", "2", "--omega-ratio", "2", "--amplitude-ratio", "2"), "b "),
    (("rigid", "--b", "0.2", "--h", "2", "--mass", "-5", "--omega-ratio", "2",
      "--amplitude-ratio", "2"), "mass"),
    (("rigid", *ZM, "--record", "/nonexistent/rec.at2"), "rec.at2"),
    (("spectrum", *ZM, "--omega-ratios", "1:9", "--amplitude-ratios", "1:2:3"),
     "--omega-ratios"),
])
def test_bad_input_one_line_error(capsys, argv, word):
    code, out, err = run(capsys, *argv)
    assert code == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("colonna: error:") and word in lines[0]


def test_collar_above_top_cli(capsys, tmp_path):
    collars = tmp_path / "c.toml"
    collars.write_text("[[collar]]\ny = 9.0\nt = 0.01\nh = 0.04\n")
    code, _, err = run(capsys, "rigid", "--b", "0.2", "--h", "2.0", "--density", "2700",
                       "--omega-ratio", "2", "--amplitude-ratio", "2", "--collars", str(collars))
    assert code == 2 and "collar 1 y" in err


@pytest.mark.parametrize("argv, word", [
    (("spectrum", *ZM, "--amplitude-ratios", "1:2:3"), "--omega-ratios"),
    (("rigid", "--p", "abc"), "--p"),
    (("rigid", *ZM, "--model", "quadratic"), "--model"),
])
def test_argument_errors_are_one_line(capsys, argv, word):
    with pytest.raises(SystemExit) as exc:
        main(list(argv))
    err = capsys.readouterr().err
    assert exc.value.code == 2
    assert len(err.strip().splitlines()) == 1 and word in err and err.startswith("colonna: error")


# --- the multibody model ------------------------------------------------------------------------

def test_rigid_multibody_json_contract_matches_the_python_api(capsys):
    from colonna.rigid import Block, pulse_from_ratios
    from colonna.rigid.multibody import rock_multibody

    code, out, _ = run(capsys, "rigid", "--p", "2.14", "--alpha", "0.25", "--model",
                       "multibody", "--friction", "2", "--omega-ratio", "5",
                       "--amplitude-ratio", "3", "--json")
    assert code == 0
    data = json.loads(out)
    blk = Block.from_dimensionless(p=2.14, alpha=0.25)
    direct = rock_multibody(blk, pulse_from_ratios(blk, "sine", 5.0, 3.0, "nonlinear"),
                            friction=2.0)
    assert data["overturned"] is direct.overturned and data["mode"] == direct.mode
    assert data["impacts"] == direct.impacts
    for key in ("max_abs_theta_over_alpha", "max_abs_theta_left", "max_abs_theta_right"):
        assert isinstance(data[key], float)


def test_rigid_multibody_cracked_with_collars_writes_its_histories(capsys, tmp_path):
    collars = tmp_path / "collars.toml"
    collars.write_text("[[collar]]\ny = 2.0\nt = 0.008\nh = 0.06\n")
    code, out, _ = run(capsys, "rigid", "--b", "0.1125", "--h", "2.0", "--density", "2700",
                       "--model", "multibody", "--crack-friction", "0.3", "--collars",
                       str(collars), "--omega-ratio", "3", "--amplitude-ratio", "2",
                       "--duration", "1.0", "--out", str(tmp_path / "o"), "--json")
    assert code == 0
    data = json.loads(out)
    assert data["cracked"] is True and data["crack_friction"] == 0.3 and data["friction"] == 0.7
    header = (tmp_path / "o" / "history.csv").read_text().splitlines()[0].split(",")
    for column in ("theta_left", "theta_right", "crack_slip", "collar_1_stress",
                   "energy_error"):
        assert column in header
    assert (tmp_path / "o" / "impacts.csv").is_file()


def test_spectrum_multibody_json(capsys):
    code, out, _ = run(capsys, "spectrum", "--p", "2.14", "--alpha", "0.25", "--model",
                       "multibody", "--friction", "2", "--omega-ratios", "2:8:3",
                       "--amplitude-ratios", "1.5:12:3", "--json")
    assert code == 0
    data = json.loads(out)
    assert data["model"] == "multibody"
    assert len(data["mode"]) == 3 and len(data["mode"][0]) == 3


@pytest.mark.parametrize("argv, word", [
    (("--model", "nonlinear", "--friction", "0.5"), "--friction"),
    (("--model", "linear", "--cracked"), "--cracked"),
    (("--model", "multibody", "--friction", "-0.5"), "friction"),
    (("--model", "multibody", "--crack-friction", "nan"), "crack friction"),
])
def test_multibody_options_errors_are_one_line(capsys, argv, word):
    code, _, err = run(capsys, "rigid", "--p", "2", "--alpha", "0.2", "--omega-ratio", "3",
                       "--amplitude-ratio", "2", *argv)
    assert code == 2
    assert err.count("\n") == 1 and err.startswith("colonna: error:") and word in err

"""The ``colonna`` command line: JSON contracts, files written, one-line errors."""

import json
import re
from pathlib import Path

import pytest

from colonna.core.motion import Motion
from colonna.rigid.multibody import MultibodyContact
from colonna.studies.cli import main, resolve_study


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


ZM = ("--p", "2.14", "--alpha", "0.25", "--restitution", "0.9")


def test_rigid_json_contract(capsys):
    code, out, _ = run(
        capsys,
        "rigid",
        *ZM,
        "--model",
        "linear",
        "--omega-ratio",
        "5",
        "--amplitude-ratio",
        "4",
        "--json",
    )
    assert code == 0
    data = json.loads(out)
    assert data["overturned"] is True and data["mode"] == "after-impact"
    assert isinstance(data["impacts"], int) and data["impacts"] >= 1
    assert isinstance(data["max_abs_theta_over_alpha"], float)


def test_rigid_out_writes_history(capsys, tmp_path):
    collars = tmp_path / "collars.toml"
    collars.write_text(
        "[[collar]]\ny = 1.0\nt = 0.01\nh = 0.04\n\n[[collar]]\ny = 3.0\nt = 0.01\nh = 0.04\n"
    )
    code, out, _ = run(
        capsys,
        "rigid",
        "--b",
        "0.2",
        "--h",
        "2.0",
        "--density",
        "2700",
        "--omega-ratio",
        "2",
        "--amplitude-ratio",
        "2",
        "--collars",
        str(collars),
        "--out",
        str(tmp_path / "o"),
        "--json",
    )
    assert code == 0
    data = json.loads(out)
    assert "collar_max_utilisation" in data
    header = (tmp_path / "o" / "history.csv").read_text().splitlines()[0].split(",")
    assert header[:3] == ["t", "theta", "theta_dot"] and "collar_2_stress" in header
    assert (tmp_path / "o" / "history.png").stat().st_size > 1000


def test_spectrum_json_contract(capsys, tmp_path):
    code, out, _ = run(
        capsys,
        "spectrum",
        *ZM,
        "--model",
        "linear",
        "--omega-ratios",
        "1:9:5",
        "--amplitude-ratios",
        "1.5:10:4",
        "--json",
        "--out",
        str(tmp_path),
    )
    assert code == 0
    data = json.loads(out)
    assert len(data["mode"]) == 4 and len(data["mode"][0]) == 5
    assert data["omega_ratios"][0] == 1.0 and len(data["amplitude_ratios"]) == 4
    assert "layout" in data and isinstance(data["seconds"], float)
    assert (tmp_path / "spectrum.png").exists()


def test_design_json(capsys, tmp_path):
    code, out, _ = run(
        capsys,
        "design",
        "--b",
        "0.2",
        "--h",
        "2.0",
        "--density",
        "2700",
        "--collar-t",
        "0.01",
        "--collar-h",
        "0.05",
        "--ag-ratio",
        "0.3",
        "--json",
        "--out",
        str(tmp_path),
    )
    assert code == 0
    data = json.loads(out)
    assert data["required_stiffness"] > 0 and data["collars_needed"] >= 1
    assert (tmp_path / "design_chart.png").exists()


@pytest.mark.parametrize(
    "argv, word",
    [
        (
            ("rigid", "--p", "2", "--alpha", "2", "--omega-ratio", "2", "--amplitude-ratio", "2"),
            "alpha",
        ),
        (("rigid", *ZM, "--omega-ratio", "2", "--amplitude-ratio", "0.5"), "amplitude ratio"),
        (("rigid", "--b", "-1", "--h", "2", "--omega-ratio", "2", "--amplitude-ratio", "2"), "b "),
        (
            (
                "rigid",
                "--b",
                "0.2",
                "--h",
                "2",
                "--mass",
                "-5",
                "--omega-ratio",
                "2",
                "--amplitude-ratio",
                "2",
            ),
            "mass",
        ),
        (("rigid", *ZM, "--record", "/nonexistent/rec.at2"), "rec.at2"),
        (
            ("spectrum", *ZM, "--omega-ratios", "1:9", "--amplitude-ratios", "1:2:3"),
            "--omega-ratios",
        ),
    ],
)
def test_bad_input_one_line_error(capsys, argv, word):
    code, out, err = run(capsys, *argv)
    assert code == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("colonna: error:") and word in lines[0]


def test_collar_above_top_cli(capsys, tmp_path):
    collars = tmp_path / "c.toml"
    collars.write_text("[[collar]]\ny = 9.0\nt = 0.01\nh = 0.04\n")
    code, _, err = run(
        capsys,
        "rigid",
        "--b",
        "0.2",
        "--h",
        "2.0",
        "--density",
        "2700",
        "--omega-ratio",
        "2",
        "--amplitude-ratio",
        "2",
        "--collars",
        str(collars),
    )
    assert code == 2 and "collar 1 y" in err


@pytest.mark.parametrize(
    "argv, word",
    [
        (("spectrum", *ZM, "--amplitude-ratios", "1:2:3"), "--omega-ratios"),
        (("rigid", "--p", "abc"), "--p"),
        (("rigid", *ZM, "--model", "quadratic"), "--model"),
    ],
)
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

    code, out, _ = run(
        capsys,
        "rigid",
        "--p",
        "2.14",
        "--alpha",
        "0.25",
        "--model",
        "multibody",
        "--friction",
        "2",
        "--omega-ratio",
        "5",
        "--amplitude-ratio",
        "3",
        "--json",
    )
    assert code == 0
    data = json.loads(out)
    blk = Block.from_dimensionless(p=2.14, alpha=0.25)
    direct = rock_multibody(
        blk,
        Motion(pulse_from_ratios(blk, "sine", 5.0, 3.0, "nonlinear")),
        contact=MultibodyContact(friction=2.0),
    )
    assert data["overturned"] is direct.overturned and data["mode"] == direct.mode
    assert data["impacts"] == direct.impacts
    for key in ("max_abs_theta_over_alpha", "max_abs_theta_left", "max_abs_theta_right"):
        assert isinstance(data[key], float)


def test_rigid_multibody_cracked_with_collars_writes_its_histories(capsys, tmp_path):
    collars = tmp_path / "collars.toml"
    collars.write_text("[[collar]]\ny = 2.0\nt = 0.008\nh = 0.06\n")
    code, out, _ = run(
        capsys,
        "rigid",
        "--b",
        "0.1125",
        "--h",
        "2.0",
        "--density",
        "2700",
        "--model",
        "multibody",
        "--crack-friction",
        "0.3",
        "--collars",
        str(collars),
        "--omega-ratio",
        "3",
        "--amplitude-ratio",
        "2",
        "--duration",
        "1.0",
        "--out",
        str(tmp_path / "o"),
        "--json",
    )
    assert code == 0
    data = json.loads(out)
    assert data["cracked"] is True and data["crack_friction"] == 0.3 and data["friction"] == 0.7
    header = (tmp_path / "o" / "history.csv").read_text().splitlines()[0].split(",")
    for column in ("theta_left", "theta_right", "crack_slip", "collar_1_stress", "energy_error"):
        assert column in header
    assert (tmp_path / "o" / "impacts.csv").is_file()


def test_spectrum_multibody_json(capsys):
    code, out, _ = run(
        capsys,
        "spectrum",
        "--p",
        "2.14",
        "--alpha",
        "0.25",
        "--model",
        "multibody",
        "--friction",
        "2",
        "--omega-ratios",
        "2:8:3",
        "--amplitude-ratios",
        "1.5:12:3",
        "--json",
    )
    assert code == 0
    data = json.loads(out)
    assert data["model"] == "multibody"
    assert len(data["mode"]) == 3 and len(data["mode"][0]) == 3


@pytest.mark.parametrize(
    "argv, word",
    [
        (("--model", "nonlinear", "--friction", "0.5"), "--friction"),
        (("--model", "linear", "--cracked"), "--cracked"),
        (("--model", "multibody", "--friction", "-0.5"), "friction"),
        (("--model", "multibody", "--crack-friction", "nan"), "crack friction"),
    ],
)
def test_multibody_options_errors_are_one_line(capsys, argv, word):
    code, _, err = run(
        capsys,
        "rigid",
        "--p",
        "2",
        "--alpha",
        "0.2",
        "--omega-ratio",
        "3",
        "--amplitude-ratio",
        "2",
        *argv,
    )
    assert code == 2
    assert err.count("\n") == 1 and err.startswith("colonna: error:") and word in err


# --- what a person reads: the verdict words, units and digits ------------------------------------

COLLARS = "[[collar]]\ny = 1.0\nt = 0.01\nh = 0.04\n\n[[collar]]\ny = 3.0\nt = 0.01\nh = 0.04\n"
HALF = ("--b", "0.2", "--h", "2.0", "--density", "2700")


@pytest.mark.chaotic
def test_rigid_collar_state_is_apart_from_the_rocking_mode(capsys, tmp_path, monkeypatch):
    """A block that stays up while its collars pass f_y keeps mode "safe" (no overturning) but
    says "yielded" beside it, in the summary, the printed lines and the figure's title."""
    import colonna.rigid.plotting as plotting

    collars = tmp_path / "collars.toml"
    collars.write_text(COLLARS)
    argv = (
        "rigid",
        *HALF,
        "--omega-ratio",
        "2",
        "--amplitude-ratio",
        "3",
        "--collars",
        str(collars),
    )
    titles = []
    save = plotting.Figure.savefig  # the figure's title, read as it is saved
    monkeypatch.setattr(
        plotting.Figure,
        "savefig",
        lambda fig, *a, **k: (titles.append(fig.axes[0].get_title()), save(fig, *a, **k)),
    )
    code, out, _ = run(capsys, *argv, "--json", "--out", str(tmp_path / "o"))
    assert code == 0
    data = json.loads(out)
    assert not data["overturned"] and data["collar_max_utilisation"] >= 1.0  # the case
    assert data["mode"] == "safe" and data["motion"] == "rocking"
    assert data["collar_state"] == "yielded"
    for text in (data["verdict"], titles[0]):
        assert "collars yielded" in text and "safe" not in text, text
    code, out, _ = run(capsys, *argv)
    lines = dict(line.split(None, 1) for line in out.splitlines())
    assert lines["collar_state"] == "yielded" and "yielded" in lines["verdict"]


def test_spectrum_counts_safe_pulses_whose_collars_yield(capsys, tmp_path):
    """The printed spectrum counts beside "safe" the pulses in which a collar yields."""
    collars = tmp_path / "collars.toml"
    collars.write_text(COLLARS)
    argv = (
        "spectrum",
        *HALF,
        "--collars",
        str(collars),
        "--omega-ratios",
        "1:9:3",
        "--amplitude-ratios",
        "1.5:10:3",
    )
    code, out, _ = run(capsys, *argv, "--json")
    data = json.loads(out)
    modes = sum(data["mode"], [])
    yields = sum(data["collar_yields"], [])
    code, out, _ = run(capsys, *argv)
    assert code == 0
    lines = dict(line.split(None, 1) for line in out.splitlines())
    assert int(lines["collars_yielded"]) == sum(yields)
    assert int(lines["safe_with_collars_yielded"]) == sum(
        y and m == "safe" for y, m in zip(yields, modes)
    )


def test_motion_and_collar_words():
    from colonna.rigid.solve import UPLIFT_THRESHOLD, collar_state, motion_word, verdict

    alpha = 0.2
    assert motion_word(False, 0.0, alpha) == "no uplift"
    assert motion_word(False, 0.5 * UPLIFT_THRESHOLD * alpha, alpha) == "no uplift"
    assert motion_word(False, 0.1, alpha) == "rocking"
    assert motion_word(True, 0.5 * alpha, alpha) == "overturned"
    assert collar_state(0.99) == "elastic" and collar_state(1.0) == "yielded"
    assert collar_state(0.99, max_plastic_strain=1e-4) == "yielded"
    words = verdict(
        {
            "motion": "no uplift",
            "overturned": False,
            "mode": "safe",
            "collar_state": "elastic",
            "collar_max_utilisation": 0.25,
        }
    )
    assert words == "no uplift; collars elastic (max utilisation 0.25)"
    assert (
        verdict({"motion": "overturned", "overturned": True, "mode": "after-impact"})
        == "overturned (after-impact)"
    )


@pytest.mark.parametrize(
    "key, unit",
    [
        ("edge_stress_max", "MPa"),
        ("collar_yield_stress", "MPa"),
        ("edge_stress_ratio", ""),
        ("base_reaction_static", "kN"),
        ("top_load", "kN"),
        ("yield_moment", "kN m"),
        ("required_stiffness", "kN/m"),
        ("energy_dissipated", "J"),
        ("energy_error_max", ""),
        ("collar_first_yield_time", "s"),
        ("dt", "s"),
        ("t_end", "s"),
        ("wall_seconds", "s"),
        ("max_abs_theta", "rad"),
        ("max_abs_theta_over_alpha", ""),
        ("alpha", "rad"),
        ("p", "rad/s"),
        ("b", "m"),
        ("max_uplift", "m"),
        ("uplift_acceleration", "m/s^2"),
        ("column_mass", "kg"),
        ("collar_max_utilisation", ""),
        ("restitution_housner", ""),
        ("steps", ""),
        ("dofs", ""),
    ],
)
def test_printed_units_follow_the_key(key, unit):
    from colonna.studies.units import unit_of

    assert unit_of(key)[0] == unit


def _significant_digits(number: str) -> int:
    mantissa = number.lstrip("-").split("e")[0]
    digits = mantissa.replace(".", "").lstrip("0")
    return len(digits if "." in mantissa else digits.rstrip("0"))


@pytest.mark.parametrize(
    "argv",
    [
        ("design", *HALF, "--collar-t", "0.01", "--collar-h", "0.05", "--ag-ratio", "0.3"),
        (
            "rigid",
            *HALF,
            "--top-load",
            "5000",
            "--omega-ratio",
            "2",
            "--amplitude-ratio",
            "3",
            "--collars",
            "COLLARS",
        ),
    ],
)
def test_printed_numbers_have_four_digits_and_a_unit_json_keeps_all(capsys, tmp_path, argv):
    """Lines are ``key  value unit``: 4 significant digits in MPa, kN, ...; --json gives the
    same numbers in SI units at full precision."""
    from colonna.studies.units import unit_of

    collars = tmp_path / "collars.toml"
    collars.write_text(COLLARS)
    argv = [str(collars) if a == "COLLARS" else a for a in argv]
    code, out, _ = run(capsys, *argv, "--json")
    assert code == 0
    data = json.loads(out)
    code, out, _ = run(capsys, *argv)
    assert code == 0
    lines = dict(line.split(None, 1) for line in out.splitlines())
    floats = [k for k, v in data.items() if isinstance(v, float)]
    assert floats and set(floats) <= set(lines)
    assert any(len(repr(data[k])) > 8 for k in floats)  # full precision in the JSON
    for key in floats:
        unit, factor = unit_of(key)
        number, *shown = lines[key].split(" ", 1)
        assert shown == ([unit] if unit else []), (key, lines[key])
        assert _significant_digits(number) <= 4, (key, lines[key])
        assert float(number) == pytest.approx(data[key] * factor, rel=5e-4, abs=1e-300), key


# --- the first multibody run announces numba's compilation ---------------------------------------


@pytest.mark.parametrize("cached", [False, True])
def test_multibody_run_announces_compilation_only_when_it_compiles(capsys, monkeypatch, cached):
    import colonna.studies.cli as cli

    monkeypatch.setattr(cli, "kernels_cached", lambda kernels: cached)
    code, out, err = run(
        capsys,
        "rigid",
        *ZM,
        "--model",
        "multibody",
        "--friction",
        "2",
        "--omega-ratio",
        "5",
        "--amplitude-ratio",
        "3",
        "--duration",
        "1",
        "--json",
    )
    assert code == 0 and json.loads(out)["model"] == "multibody"
    assert ("compiling the multibody kernels" in err) is not cached
    assert err.count("\n") == (0 if cached else 1)


def test_kernels_cached_reads_numba_cache(tmp_path):
    """A kernel is cached once a process compiled it into numba's cache (here an empty cache
    folder of its own), not before; and for a process that compiled it already."""
    import os
    import subprocess
    import sys

    code = (
        "import sys, numpy as np; from colonna.core import tables as K; "
        "from colonna.studies.cli import kernels_cached; "
        "print(kernels_cached([K.table_value])); "
        "K.table_value(0.5, np.array([0.0, 1.0]), np.array([0.0, 2.0])); "
        "print(kernels_cached([K.table_value]))"
    )
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path)}
    first = subprocess.run(
        [sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True
    ).stdout.split()
    second = subprocess.run(
        [sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True
    ).stdout.split()
    assert first == ["False", "True"] and second == ["True", "True"]


def test_a_study_announces_only_the_kernels_it_runs(tmp_path):
    """The compilation a study announces is of the kernels it will run: a cross-check's FEM and
    multibody kernels; a fragility's those of its models (the multibody's alone for the
    shipped one, none for an SDOF-only one, whose run would otherwise announce, every time,
    a FEM compilation it never does)."""
    from colonna.fem import _kernels as fem_kernels
    from colonna.rigid import _multibody as multibody_kernels
    from colonna.studies.cli import _study_kernels, resolve_study
    from colonna.studies.study import load

    kernels, what = _study_kernels(load(resolve_study("default")))
    assert kernels == [fem_kernels.advance, multibody_kernels.simulate]
    assert what == "FEM and multibody kernels"
    shipped = resolve_study("fragility")
    kernels, what = _study_kernels(load(shipped))
    assert kernels == [multibody_kernels.simulate] and what == "multibody kernels"
    suite = (shipped.parent / "suites" / "synthetic-pulses").resolve()
    text = shipped.read_text().replace('models = ["sdof", "multibody"]', 'models = ["sdof"]')
    text = re.sub(r'suite = "[^"]*"', f'suite = "{suite}"', text)
    (tmp_path / "sdof.toml").write_text(text)
    assert _study_kernels(load(tmp_path / "sdof.toml"))[0] == []


# --- a study file's errors all at once ---------------------------------------------------------

STUDY = """
[study]
name = "errors"
{study}
[column]
height = 1.0
width = {width}
[[collar]]
y = {y}
t = 0.004
h = 0.02
{ground}
[contact]
{contact}
[mesh]
size = 0.05
"""
GROUND = "[ground]\namplitude_ratio = 2.0\nomega_ratio = 3.0"


@pytest.mark.parametrize("command", ["study", "fem"])
@pytest.mark.parametrize(
    "keys, lines",
    [
        # a column key out of range, an unknown key in [contact], a collar above the column
        (
            {"width": -0.2, "y": 1.5, "contact": "frikshun = 0.5"},
            [
                "column.width = -0.2 is not allowed: a number in [0.001, 20], m",
                "unknown key contact.frikshun (allowed in [contact]: friction, penalty_factor, "
                "penalty, damping, friction_filter, enforcement)",
                "collar[1].y = 1.5 m is outside the allowed range [0.001, 1] m (the column height)",
            ],
        ),
        # no [ground] hides neither a collar above the column nor a key out of range
        (
            {"y": 1.5, "ground": "", "contact": "friction = -1.0"},
            [
                "contact.friction = -1.0 is not allowed: a number in [0, inf)",
                "the study has no [ground] table: give ground.pulse and, for a pulse, exactly one "
                "of ground.amplitude and ground.amplitude_ratio and one of ground.period and "
                "ground.omega_ratio",
                "collar[1].y = 1.5 m is outside the allowed range [0.001, 1] m (the column height)",
            ],
        ),
        # an error in [study] (which says what to run) hides none in the other tables
        (
            {"study": "kynd = 'cross-check'", "y": 1.5},
            [
                "unknown key study.kynd (allowed in [study]: name, description, project, site, "
                "client, prepared_by, checked_by, revision, kind, intended)",
                "collar[1].y = 1.5 m is outside the allowed range [0.001, 1] m (the column height)",
            ],
        ),
        # a single error: its one line, as ever
        (
            {"y": 1.5},
            ["collar[1].y = 1.5 m is outside the allowed range [0.001, 1] m (the column height)"],
        ),
    ],
)
def test_every_error_of_a_study_file_one_line_each_nothing_written(
    capsys, tmp_path, command, keys, lines
):
    """``colonna study`` and ``colonna fem``: all the study file's errors at once, one
    ``colonna: error:`` line each naming its key, exit status 2, and no output folder."""
    study = tmp_path / "errors.toml"
    given = {"study": "", "width": 0.2, "ground": GROUND, "contact": "", **keys}
    study.write_text(STUDY.format(**given))
    out = tmp_path / "out"
    code, printed, err = run(capsys, command, str(study), "--out", str(out))
    assert code == 2 and printed == ""
    assert err.splitlines() == [f"colonna: error: {study}: {line}" for line in lines]
    assert not out.exists()


# --- errors by kind: one line each, their exit status --------------------------------------------


@pytest.mark.parametrize(
    "error, status",
    [
        ("InputError", 2),
        ("StaleResultsError", 2),
        ("NumericalFailure", 2),
        ("UnreliableRun", 2),
        ("StudyStopped", 1),
    ],
)
def test_each_kind_of_error_is_one_line_per_line_with_its_status(
    capsys, monkeypatch, tmp_path, error, status
):
    """Bad input, results saved from other inputs and a run that is not an answer end with
    ``colonna: error:`` lines and status 2 (as when one InputError covered them all); a study
    that cannot go on (a lost scheduler), status 1."""
    from colonna.core import errors
    from colonna.studies import cli, executor, guard

    kind = getattr(errors, error, None) or getattr(guard, error, None) or getattr(executor, error)

    def fail(args):
        raise kind("first line\nsecond line")

    monkeypatch.setattr(cli, "_cmd_validate", fail)
    code, out, err = run(capsys, "validate", "--out", str(tmp_path))
    assert (code, out) == (status, "")
    assert err.splitlines() == ["colonna: error: first line", "colonna: error: second line"]


def test_the_kinds_of_error():
    """InputError stays a ValueError (callers that catch either keep working); the others are
    not bad input; an unreliable study run is a numerical failure."""
    from colonna.core.errors import ColonnaError, InputError, NumericalFailure, StaleResultsError
    from colonna.studies.executor import StudyStopped
    from colonna.studies.guard import UnreliableRun

    assert issubclass(InputError, ValueError)
    for kind in (InputError, StaleResultsError, NumericalFailure, StudyStopped):
        assert issubclass(kind, ColonnaError)
    for kind in (StaleResultsError, NumericalFailure, StudyStopped):
        assert not issubclass(kind, (InputError, ValueError))
    assert issubclass(UnreliableRun, NumericalFailure)


# --- colonna warmup: the kernels compiled once, at install time ---------------------------------


def test_warmup_runs_its_command_lines_through_the_main_it_is_given():
    """warm() takes the command line to run (``colonna warmup`` gives its own main), so that
    the warm-up imports nothing of the command line; a command that fails stops it, named."""
    from colonna.studies.warmup import warm

    ran = []

    def fake_main(argv):
        ran.append(list(argv))
        return 0

    said = []
    assert warm(fake_main, say=said.append) >= 0.0
    assert ran and all(argv[-1] == "--json" for argv in ran)
    assert {argv[0] for argv in ran} == {"rigid", "spectrum", "fem"} and len(said) == len(ran)
    with pytest.raises(RuntimeError, match="colonna warmup: rigid, linear failed"):
        warm(lambda argv: 2, say=said.append)


def _readme_examples() -> list[list[str]]:
    """The command lines of the manual's command-line block (docs/command-line.md, moved there
    from the README; continuation lines joined)."""
    text = (Path(__file__).parents[1] / "docs" / "command-line.md").read_text()
    block = text.split("# Command line", 1)[1].split("```sh", 1)[1].split("```", 1)[0]
    lines = block.replace("\\\n", " ").splitlines()
    return [line.split()[1:] for line in lines if line.startswith("colonna ")]


def _flavour(argv: list[str]) -> tuple:
    """What decides which kernels a command line compiles: its command, model, and whether
    it has collars or a crack."""
    model = argv[argv.index("--model") + 1] if "--model" in argv else "nonlinear"
    return (argv[0], model, "--collars" in argv, "--cracked" in argv)


def _shown_examples() -> list[list[str]]:
    """Every colonna command line the README, the command-line page and the tutorial show."""
    import shlex

    root = Path(__file__).parents[1]
    lines = list(_readme_examples())
    for page in (root / "README.md", root / "docs" / "tutorial.md"):
        for block in page.read_text().split("```sh\n")[1:]:
            for line in block.split("```", 1)[0].replace("\\\n", " ").splitlines():
                words = shlex.split(line, comments=True)
                if words and words[0].endswith("colonna"):
                    lines.append(words[1:])
    return lines


def test_warmup_runs_every_flavour_of_the_readme_examples():
    """`make` runs `colonna warmup` after installing so that a fresh install's first run of an
    example of the README or the manual loads compiled kernels instead of compiling them: the
    warm-up must run every rigid and spectrum flavour they show (a flavour it missed would
    compile on the user's first run)."""
    from colonna.studies.warmup import commands

    warmed = {_flavour(argv) for _, argv in commands(Path("."))}
    shown = {_flavour(argv) for argv in _shown_examples() if argv[0] in ("rigid", "spectrum")}
    assert shown and shown <= warmed, shown - warmed
    assert {"fem"} <= {argv[0] for _, argv in commands(Path("."))}


@pytest.mark.slow
def test_after_warmup_a_readme_example_compiles_nothing(tmp_path):
    """After `colonna warmup` into an empty numba cache, the manual's multibody examples (the
    longest to compile) and a FEM ensemble of another column load every kernel from the cache:
    numba saves nothing new (NUMBA_DEBUG_CACHE reports each save). make test-all."""
    import os
    import subprocess
    import sys

    from colonna.studies.warmup import FEM_STUDY

    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "cache")}
    cli = [sys.executable, "-m", "colonna.studies.cli"]
    subprocess.run([*cli, "warmup"], env=env, check=True, cwd=tmp_path)
    (tmp_path / "collars.toml").write_text("[[collar]]\ny = 0.5\nt = 0.006\nh = 0.05\n")
    study = FEM_STUDY.format(replicas=8).replace("width = 0.2", "width = 0.3")
    (tmp_path / "fem.toml").write_text(study)
    examples = [argv for argv in _readme_examples() if _flavour(argv)[1] == "multibody"]
    for argv in [*examples, ["fem", "fem.toml", "--out", "fem"]]:
        run = subprocess.run(
            [*cli, *argv],
            env={**env, "NUMBA_DEBUG_CACHE": "1"},
            cwd=tmp_path,
            capture_output=True,
            text=True,
        )
        assert run.returncode == 0, run.stderr
        assert "data saved to" not in run.stdout + run.stderr, argv


def test_version_is_the_one_the_inputs_record(capsys):
    """colonna --version prints the version every inputs.json and report records."""
    import colonna
    from colonna.studies.study import load

    with pytest.raises(SystemExit) as exited:
        main(["--version"])
    assert exited.value.code == 0
    printed = capsys.readouterr().out.strip()
    recorded = load(resolve_study("default")).to_json()["colonna_version"]
    assert printed == f"colonna {recorded}" == f"colonna {colonna.__version__}"


def test_the_help_says_what_each_command_runs(capsys, monkeypatch):
    """`colonna study` runs every kind of KINDS (issue 48: the help called it a cross-check),
    so its help line names them from the table; the rigid and spectrum commands say they take
    collars, fem that it runs the FEM alone."""
    from colonna.studies.kinds import DEFAULT_KIND, KINDS

    monkeypatch.setenv("COLUMNS", "1000")  # one line a command: argparse wraps at hyphens
    with pytest.raises(SystemExit):
        main(["--help"])
    lines = {
        line.split()[0]: " ".join(line.split()[1:])
        for line in capsys.readouterr().out.splitlines()
        if line.startswith("    ") and line.split()[0].isalpha()
    }
    kinds = ", ".join(KINDS)
    assert lines["study"] == (
        f"run a study file of any kind, the one its [study] kind names ({kinds}; default "
        f"{DEFAULT_KIND}), into an HTML report"
    )
    assert "cross-check study" not in " ".join(lines.values())
    assert "collars" in lines["rigid"] and "collars" in lines["spectrum"]
    assert "without the rigid models or a report" in lines["fem"]
    assert "Zhang & Makris" in lines["validate"]
    with pytest.raises(SystemExit):
        main(["study", "--help"])
    assert f"of any kind, the one its [study] kind names ({kinds};" in capsys.readouterr().out


SNAKE_CASE = re.compile(r"\b[a-z0-9]+(?:_[a-z0-9]+)+\b")


def test_the_study_summary_prints_the_reports_questions_and_answers(tmp_path, capsys):
    """`colonna study` prints the report line, then the report's first screen in its words:
    each model's row, each question with its answer; the verdict's internal keys
    (sdof_half_model_ok, rocks_as_one_block, overturns_fem: issue 48) stay in summary.json."""
    from tiny_study import TINY_STUDY

    from colonna.studies.outcome import QUESTIONS

    study = tmp_path / "tiny.toml"
    study.write_text(TINY_STUDY.format(amplitude_ratio=2.5, duration=0.1))
    out = tmp_path / "out"
    assert main(["study", str(study), "--out", str(out), "--workers", "1"]) == 0
    lines = capsys.readouterr().out.splitlines()
    summary = json.loads((out / "summary.json").read_text())
    assert lines[0].split() == ["report", str(out / "index.html")]
    models = [m["model"] for m in summary["outcome"]["models"]]
    answers = {a["question"]: a["answer"] for a in summary["outcome"]["answers"]}
    printed = []
    for line in lines[1:]:
        head = next(h for h in models + list(QUESTIONS.values()) if line.startswith(h))
        assert line[len(head) :].strip(), line  # an answer beside it
        assert not SNAKE_CASE.search(head), line
        printed.append(head)
    assert printed == models + list(answers)  # every row of the first screen, in its order
    for question, answer in answers.items():
        assert (
            next(x for x in lines if x.startswith(question))[len(question) :].split()[0]
            == (answer.split()[0])
        )
    assert set(summary["verdict"]) >= {"sdof_half_model_ok", "rocks_as_one_block"}
    for key in summary["verdict"]:  # on record, not printed
        assert key not in "\n".join(lines)


def test_every_kind_prints_its_first_screen_in_words():
    """Each kind's terminal summary is the report's opening ("outcome") or, for the fragility,
    its probabilities at the design intensity ("design"), each a question in words."""
    from colonna.studies.cli import short_summary
    from colonna.studies.kinds import KINDS

    for name, kind in KINDS.items():
        assert kind.short in (("outcome",), ("design",), ("answer",)), name
    layout = short_summary(
        ("answer",), {"answer": "2 x 8 x 60 mm S275 at 0.50, 3.50 m: ..."}, Path("r")
    )
    assert layout["Which collars does this column need?"].startswith("2 x 8 x 60 mm S275")
    summary = {
        "intensity": "pga_rocking",
        "intensity_unit": "-",
        "design_intensity": 1.5,
        "models": ["sdof"],
        "limit_states": {
            "sdof": {
                "overturning": {
                    "stripes": {
                        "fit": "lognormal",
                        "probability": 0.3125,
                        "probability_interval": [0.2, 0.45],
                    }
                }
            }
        },
        "design": {"P(overturning)_sdof": 0.3125},
    }
    printed = short_summary(KINDS["fragility"].short, summary, Path("out/index.html"))
    assert printed == {
        "report": "out/index.html",
        "Probability of overturning at PGA / (g tan alpha) = 1.5?": "SDOF half block: 0.312 "
        "[0.2, 0.45]",
    }

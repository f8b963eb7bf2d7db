"""Property-based input testing (hypothesis): study files and command lines an engineer might
write, valid and invalid, generated. Each must either be accepted (a study then reaches the
point where its cases would run; a rigid run finishes) or stop with exit 2 and one error line
per problem, naming the field it is about, before any file is written: never a traceback,
never a hang. The hand-written cases of ``test_bad_input`` stay beside these.
"""

from __future__ import annotations

import contextlib
import json
import math
import signal
import tomllib
from pathlib import Path

from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st
from tiny_study import TINY_STUDY

from colonna.studies import schema
from colonna.studies.cli import main
from colonna.studies.kinds import KINDS

BASE = tomllib.loads(TINY_STUDY.format(amplitude_ratio=2.5, duration=0.6))

# every key of every table of the study file, from the schema itself
TABLES = {
    name: sorted(schema.table_model(name).model_fields)
    for name in schema.table_names()
    if name != "collar"
}
TABLES["collar"] = sorted(schema.Collar.model_fields)

# printable text, Latin and beyond, without what a TOML basic string would have to escape
TEXT = st.characters(min_codepoint=32, max_codepoint=0x2FF, exclude_characters='"\\')
NUMBERS = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.sampled_from([0.0, -1.0, 1e-300, 1e300, 1e-9, 1e9, 0.5, 2.5, 45e3, 275.0, 8.0]),
    st.integers(-(10**6), 10**6),
)
VALUES = st.one_of(
    NUMBERS,
    st.booleans(),
    st.text(
        st.characters(min_codepoint=32, max_codepoint=0x2FF, exclude_characters='"\\'), max_size=6
    ),
    st.lists(st.floats(-10, 10), max_size=3),
    st.sampled_from(list(KINDS) + ["sine", "cosine", "record", "none"]),
)


@st.composite
def mutations(draw):
    """One change to a study file: a key set to a value, a key removed, or an unknown key."""
    table = draw(st.sampled_from(sorted(TABLES)))
    key = draw(st.sampled_from(TABLES[table]))
    how = draw(st.sampled_from(["set", "set", "set", "remove", "unknown"]))
    if how == "unknown":
        key = key + "x"
    value = draw(VALUES) if how != "remove" else None
    return table, key, how, value


def apply(study: dict, changes) -> dict:
    study = json.loads(json.dumps(study))
    for table, key, how, value in changes:
        if table == "collar":
            where = study.setdefault("collar", [{}])[0]
        else:
            where = study.setdefault(table, {})
        if how == "remove":
            where.pop(key, None)
        else:
            where[key] = value
    return study


def toml_value(value) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if math.isnan(value):
            return "nan"
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
        return repr(value)
    if isinstance(value, str):
        return json.dumps(value)
    if isinstance(value, list):
        return "[" + ", ".join(toml_value(v) for v in value) + "]"
    raise TypeError(value)


def to_toml(study: dict) -> str:
    lines = []
    for table, content in study.items():
        if table == "collar":
            for collar in content:
                lines.append("[[collar]]")
                lines += [f"{k} = {toml_value(v)}" for k, v in collar.items()]
            continue
        lines.append(f"[{table}]")
        lines += [f"{k} = {toml_value(v)}" for k, v in content.items()]
    return "\n".join(lines) + "\n"


class Reached(Exception):
    """The study passed every check made before its cases run."""


def _refuse_to_run(*args, **kwargs):
    raise Reached


@contextlib.contextmanager
def no_computation():
    """Every study kind's ``run_cases`` replaced: a study that passes its checks stops there."""
    import importlib

    names = [
        "crosscheck.runner",
        "sweep",
        "collar_design.runner",
        "spectrum_crosscheck.runner",
        "free_rocking.runner",
    ]
    modules = [importlib.import_module(f"colonna.studies.{n}") for n in names]
    saved = [(m, "run_cases", m.run_cases) for m in modules if hasattr(m, "run_cases")]
    # the Zhang & Makris validation runs no cases: its block is fixed, its run is the check
    zhang_makris = importlib.import_module("colonna.studies.zhang_makris")
    saved.append((zhang_makris, "run", zhang_makris.run))
    for module, name, _ in saved:
        setattr(module, name, _refuse_to_run)
    try:
        yield
    finally:
        for module, name, function in saved:
            setattr(module, name, function)


@contextlib.contextmanager
def time_limit(seconds: int):
    """A hang is a failure: SIGALRM after ``seconds``."""

    def hang(signum, frame):
        raise TimeoutError(f"no answer in {seconds} s")

    previous = signal.signal(signal.SIGALRM, hang)
    signal.alarm(seconds)
    try:
        yield
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)


def assert_one_line_per_error(err: str, names: list[str]) -> None:
    """Exit 2's stderr: only ``colonna: error:`` (and ``colonna: note:``) lines, no traceback,
    and one of them names a changed field."""
    lines = [line for line in err.splitlines() if line.strip()]
    assert lines, "exit 2 without a word"
    assert "Traceback" not in err
    for line in lines:
        assert line.startswith(("colonna: error:", "colonna: note:")) or "Warning" in line, line
    text = err.lower()
    assert any(name.lower() in text for name in names), (names, err)


@settings(
    max_examples=300,
    deadline=None,
    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow],
)
@given(changes=st.lists(mutations(), min_size=1, max_size=3))
def test_a_generated_study_file_is_accepted_or_refused_in_one_line_per_error(
    changes, tmp_path, capsys
):
    study = apply(BASE, changes)
    try:
        text = to_toml(study)
    except TypeError:
        assume(False)
    import tempfile

    folder = Path(tempfile.mkdtemp(dir=tmp_path))
    path = folder / "study.toml"
    path.write_text(text)
    out = folder / "out"
    code = None
    with no_computation(), time_limit(60):
        try:
            code = main(["study", str(path), "--out", str(out), "--workers", "1"])
        except Reached:
            code = None
    err = capsys.readouterr().err
    assert "Traceback" not in err
    if code is None:  # accepted: it reached its cases
        return
    assert code == 2, err
    names = [key.rstrip("x") if how == "unknown" else key for _, key, how, _ in changes]
    names += [table for table, _, _, _ in changes]
    assert_one_line_per_error(err, names)
    written = [p for p in out.rglob("*") if p.is_file()] if out.exists() else []
    assert not written, written


FLOATS = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.sampled_from([0.0, -1.0, 1e-300, 1e300, 0.2, 2.0, 3.0, 0.9, 1e6]),
)
RIGID_FLAGS = {
    "--b": FLOATS,
    "--h": FLOATS,
    "--density": FLOATS,
    "--omega-ratio": FLOATS,
    "--amplitude-ratio": FLOATS,
    "--restitution": FLOATS,
    "--duration": FLOATS,
    "--model": st.sampled_from(["linear", "nonlinear", "multibody", "quadratic"]),
    "--pulse": st.sampled_from(["sine", "cosine"]),
}


@st.composite
def rigid_arguments(draw):
    chosen = draw(st.sets(st.sampled_from(sorted(RIGID_FLAGS)), min_size=1))
    base = {"--b": 0.2, "--h": 2.0, "--omega-ratio": 3.0, "--amplitude-ratio": 2.0}
    base.update({flag: draw(RIGID_FLAGS[flag]) for flag in chosen})
    return base, sorted(chosen)


@settings(
    max_examples=60,
    deadline=None,
    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow],
)
@given(arguments=rigid_arguments())
def test_generated_rigid_command_lines_run_or_stop_in_one_line(arguments, capsys):
    flags, chosen = arguments
    argv = ["rigid", "--json"]
    for flag, value in flags.items():
        argv += [flag, str(value)]
    with time_limit(120):
        try:
            code = main(argv)
        except SystemExit as exc:  # argparse: a choice it does not know, exit 2
            code = exc.code
    out, err = capsys.readouterr()
    assert "Traceback" not in err
    if code == 0:
        result = json.loads(out)
        assert isinstance(result["overturned"], bool)
        return
    assert code == 2, err
    lines = [line for line in err.splitlines() if line.strip()]
    assert "Traceback" not in err and lines
    names = [f.lstrip("-").replace("-", "_") for f in chosen] + [f.lstrip("-") for f in chosen]
    names += ["alpha", "p", "duration", "ratio", "pulse", "collar"]
    assert any(n.lower() in err.lower() for n in names), err


def test_the_generator_writes_the_base_study_back(tmp_path):
    """The TOML writer of these tests reproduces the study it was given."""
    assert tomllib.loads(to_toml(BASE)) == BASE
    assert Path(tmp_path).is_dir()

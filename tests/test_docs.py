"""The README and the documentation site stay true to the code they describe.

The site itself is built by ``make docs`` (warnings as errors, the gallery executed), which CI
runs; it takes a minute, too long for the default suite. These checks are the cheap part: the
README stays short and shows only commands that exist, its study example and the tutorial's file
are valid studies, the generated references list every schema key and every command-line option,
and the default study's quoted numbers come from a run of the current study file."""

import json
import re
import shlex
import sys
from pathlib import Path

import pytest

from colonna.studies import schema
from colonna.studies.cli import build_parser
from colonna.studies.study import load

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
README = ROOT / "README.md"
sys.path.insert(0, str(DOCS))

import cli_reference  # noqa: E402
import run_numbers  # noqa: E402


def _blocks(text: str, language: str) -> list[str]:
    """The fenced code blocks of ``language`` in a Markdown text."""
    return re.findall(rf"^```{language}\n(.*?)^```", text, flags=re.S | re.M)


def _command_lines(text: str) -> list[list[str]]:
    """The colonna command lines of the text's sh blocks (continuations joined, comments off)."""
    lines = []
    for block in _blocks(text, "sh"):
        for line in block.replace("\\\n", " ").splitlines():
            words = shlex.split(line, comments=True)
            if words and words[0].endswith("colonna"):
                lines.append(words[1:])
    return lines


def test_the_readme_is_short():
    """The manual lives in docs/; the README says what colonna is, the two commands, one
    example and where the documentation is (issue 35: under 200 lines)."""
    lines = README.read_text().splitlines()
    assert len(lines) < 200, len(lines)
    text = README.read_text()
    for link in re.findall(r"\]\((docs/[^)#]+)", text):
        assert (ROOT / link).exists(), link


def test_every_make_command_the_readme_shows_is_a_makefile_target():
    text = README.read_text()
    shown = set(re.findall(r"\bmake ([a-z][a-z-]*)", text))
    targets = set(re.findall(r"^([a-z][a-z-]*):", (ROOT / "Makefile").read_text(), flags=re.M))
    assert {"demo", "test", "docs"} <= shown
    assert shown <= targets, shown - targets


@pytest.mark.parametrize("page", [README, DOCS / "tutorial.md"], ids=lambda p: p.name)
def test_the_command_lines_shown_parse(page):
    """Every colonna command line of the README and the tutorial is one the parser takes
    (options that exist, values of the right type); an option renamed in cli.py fails here."""
    parser = build_parser()
    lines = _command_lines(page.read_text())
    assert lines
    for argv in lines:
        try:
            parser.parse_args(argv)
        except SystemExit as refused:
            pytest.fail(f"{page.name}: colonna {' '.join(argv)} is refused ({refused})")


def test_the_study_examples_are_valid_studies(tmp_path):
    """The README's study file and the tutorial's (docs/tutorial/my-column.toml) pass the
    schema as they are shown."""
    [example] = _blocks(README.read_text(), "toml")
    (tmp_path / "my-column.toml").write_text(example)
    readme_study = load(tmp_path / "my-column.toml")
    assert readme_study.spec.column.height == 3.2 and len(readme_study.spec.collar) == 1
    tutorial = load(DOCS / "tutorial" / "my-column.toml")
    assert tutorial.spec.column.width == 0.36 and len(tutorial.spec.collar) == 2
    assert "tutorial/my-column.toml" in (DOCS / "tutorial.md").read_text()


def test_the_cli_reference_lists_every_subcommand_and_option():
    """docs/generated/cli.md is made from the parser at every build: every subcommand has its
    section and every option its row, so the reference cannot drift from the command line."""
    parser = build_parser()
    text = cli_reference.markdown(parser)
    commands = cli_reference.subcommands(parser)
    assert {"rigid", "spectrum", "design", "fem", "study", "schema", "validate"} <= set(commands)
    sections = re.split(r"^## colonna ", text, flags=re.M)[1:]
    assert [s.split("\n", 1)[0] for s in sections] == list(commands)
    for section, (name, sub) in zip(sections, commands.items()):
        for action in sub._actions:
            for option in action.option_strings:
                if option not in ("-h", "--help"):
                    assert f"`{option}`" in section, f"colonna {name} {option}"
            if not action.option_strings:
                assert f"`{action.dest}` | positional" in section, f"colonna {name} {action.dest}"
    assert "`--version`" in text.split("## colonna", 1)[0]


def test_the_study_file_reference_lists_every_key():
    """The generator of docs/study-file.md (``colonna schema --markdown``; test_schema checks
    that the file is its output) gives a section per table and a row per key of the schema."""
    text = schema.markdown()
    for name, field in schema.study_model(every=True).model_fields.items():
        header = f"[[{name}]]" if name == "collar" else f"[{name}]"
        section = text.split(f"## {header}\n", 1)[1].split("\n## ", 1)[0]
        for key in schema._model_of(field.annotation).model_fields:
            assert f"| `{key}` |" in section, f"{header} {key}"


def test_the_numbers_quoted_from_runs_come_from_runs_of_the_current_studies():
    """The numbers the pages quote from the shipped studies are read from docs/runs/STUDY.json,
    the record of a run, refused where the run read another study file or was made by another
    colonna version (run ``make docs-numbers``); every substitution a page uses exists, and
    each study's record is quoted somewhere."""
    records = {study: run_numbers.load_current(study) for study in run_numbers.STUDIES}
    names = run_numbers.substitutions(records)
    used = set()
    for page in DOCS.glob("*.md"):
        used |= set(re.findall(r"\{\{\s*(\w+)\s*\}\}", page.read_text()))
    assert used <= set(names), used - set(names)
    for study in run_numbers.STUDIES:
        assert any(name.startswith(study.replace("-", "_") + "_") for name in used), study
    assert all(text and "nan" not in text for text in names.values())


@pytest.mark.parametrize("study", run_numbers.STUDIES)
def test_a_stale_record_of_a_run_is_refused(tmp_path, study):
    record = json.loads(run_numbers.record_path(study).read_text())
    for change in ({"study_sha256": "0" * 64}, {"colonna_version": "0.0.1"}):
        stale = tmp_path / "record.json"
        stale.write_text(json.dumps({**record, **change}))
        with pytest.raises(SystemExit, match="make docs-numbers"):
            run_numbers.load_current(study, stale)


def test_the_readme_python_example_prints_what_it_says():
    """The README's Python block runs, and its last line gives the value its comment shows."""
    [example] = _blocks(README.read_text(), "python")
    *body, last = example.strip().splitlines()
    expression, shown = (part.strip() for part in last.split("#", 1))
    namespace: dict = {}
    exec("\n".join(body), namespace)
    assert repr(eval(expression, namespace)) == shown


def _layout_entry(folder: str, text: str | None = None) -> str:
    """The text of one folder's entry in docs/layout.md's tree (or in ``text``): its first line
    starts with the folder's name, its next lines are indented past it."""
    text = (DOCS / "layout.md").read_text() if text is None else text
    block = text.split("\n\n")[1]
    entry = re.search(rf"^    {re.escape(folder)}\s.*?(?=^    \S|\Z)", block, flags=re.S | re.M)
    assert entry is not None, folder
    return entry.group(0)


def _core_modules_named(text: str | None = None) -> set[str]:
    """The modules of colonna/core that the layout's ``colonna/`` entry names (``name.py``)."""
    core = _layout_entry("colonna/", text).split("core/", 1)[1]
    return set(re.findall(r"\b(\w+)\.py\b", core)) - {"__init__"}


def test_the_layout_lists_every_core_module_and_every_kind():
    """docs/layout.md names each module of the shared core (colonna/core) and each study kind's
    package, and only those that are there (issue 49: 7 of 15 core modules and the fragility
    kind were missing)."""
    from colonna.studies.kinds import KINDS

    present = {p.stem for p in (ROOT / "colonna" / "core").glob("*.py")} - {"__init__"}
    named = _core_modules_named()
    assert named == present, (sorted(present - named), sorted(named - present))
    studies = _layout_entry("studies/")
    kinds = re.search(r"one package per study kind \((.*?):", studies, flags=re.S)
    assert kinds is not None
    listed = set(re.findall(r"(\w+)/", kinds.group(1)))
    assert listed == {kind.package for kind in KINDS.values()}, listed


def test_the_layout_reader_sees_a_missing_module():
    """The check above would pass vacuously if the reader found nothing: in a layout whose
    core lists two modules, it finds those two (the file's own lists the core's errors.py)."""
    text = (
        "# Layout\n\n    pyproject.toml\n    colonna/    __init__.py: the package;\n"
        "                core/, errors (errors.py), ground (ground.py)\n"
        "    rigid/      block\n"
    )
    assert _core_modules_named(text) == {"errors", "ground"}
    assert "errors" in _core_modules_named()

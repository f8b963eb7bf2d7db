"""The report's title block (issue 48): the [study] keys project, site, client, prepared_by,
checked_by and revision on page 1 of every kind's report, with a signature line (name, date,
signature) for who prepared and who checked it, the study file's full SHA-256 and the colonna
version; blank lines to fill, never "None", where the file gives none; and, since they name the
document and not the computation, a changed title key leaves the saved cases valid."""

import hashlib
import html
import json
import re
import shutil

import pytest
from tiny_study import TINY_FRAGILITY, write_pulse_suite

import colonna
from colonna.studies import executor
from colonna.studies.cli import main
from colonna.studies.executor import RunOptions
from colonna.studies.kinds import KINDS

TITLE = {
    "project": "Loggia C3 & C4 assessment",
    "site": "Mirandola, City Hall",
    "client": "Comune di Mirandola",
    "prepared_by": "A. Rossi",
    "checked_by": "B. Bianchi",
    "revision": "B",
}
KEYS = tuple(TITLE)
TITLE_LINES = "".join(f'{key} = "{value}"\n' for key, value in TITLE.items())

# the fastest study of two kinds: a fragility of the SDOF over four pulses (its page opens with
# its own block), and the Zhang & Makris validation (no column)
FRAGILITY = TINY_FRAGILITY.replace('name = "tiny-fragility"', 'name = "titled-fragility"').replace(
    "\n[column]", "\n{title}[column]", 1
)
ZHANG_MAKRIS = """
[study]
name = "titled-validation"
kind = "zhang-makris"
{title}"""


def _run(root, text, *extra):
    study = root / "study.toml"
    study.write_text(text)
    return main(["study", str(study), "--out", str(root / "out"), "--workers", "1", *extra])


@pytest.fixture(scope="module")
def titled(tmp_path_factory):
    """The two studies run with every title key given: {kind: its folder (study.toml, out)}."""
    roots = {}
    for kind, text in (("fragility", FRAGILITY), ("zhang-makris", ZHANG_MAKRIS)):
        root = tmp_path_factory.mktemp(kind)
        if kind == "fragility":
            write_pulse_suite(root)
        assert _run(root, text.format(title=TITLE_LINES)) == 0
        roots[kind] = root
    return roots


def first_page(page: str) -> str:
    """What a report shows before its inputs (which the print rules start on page 2)."""
    return page[: page.index('<section id="inputs">')]


def title_block(page: str) -> str:
    found = re.findall(r'<section id="title-block">.*?</section>', page, re.S)
    assert len(found) == 1, "one title block"
    return found[0]


@pytest.mark.parametrize(
    "kind", [pytest.param("fragility", marks=pytest.mark.slow), "zhang-makris"]
)
def test_the_title_block_is_on_the_first_page(titled, kind):
    """Its values, the full SHA-256 of the study file (as copied beside the report) and the
    version, before the page's opening; a signature line each for who prepared and who checked
    it, with a blank for the date and one for the signature."""
    root = titled[kind]
    page = (root / "out" / "index.html").read_text()
    first = first_page(page)
    block = title_block(first)
    assert first.index('id="title-block"') < first.index("<h2")  # before the opening
    for key, value in TITLE.items():
        assert f'<span data-title="{key}">{html.escape(value, quote=False)}</span>' in block, key
    sha = hashlib.sha256((root / "study.toml").read_bytes()).hexdigest()
    assert sha == hashlib.sha256((root / "out" / "study.toml").read_bytes()).hexdigest()
    assert re.search(rf'<code class="sha256"[^>]*>{sha}</code>', block)
    assert json.loads((root / "out" / "inputs.json").read_text())["study_sha256"] == sha
    assert f"colonna {colonna.__version__}" in block
    for key, name in (("prepared_by", "prepared by"), ("checked_by", "checked by")):
        row = re.search(rf'<tr data-sign="{key}"><th>{name}</th>(.*?)</tr>', block, re.S)
        assert row, key
        cells = re.findall(r"<td>(.*?)</td>", row.group(1), re.S)
        assert len(cells) == 3 and TITLE[key] in cells[0], cells  # name, date, signature
        assert all('class="blank' in cell for cell in cells[1:]), cells
    assert "data-blank" not in block and "title-note" not in block  # nothing left to fill


def test_without_title_keys_the_block_leaves_blank_lines(titled, tmp_path):
    """The same report of a file without the keys: a blank line for each, a sentence naming
    them as the study file spells them, and no None, n/a or null."""
    out = tmp_path / "out"
    shutil.copytree(titled["fragility"] / "out", out)
    inputs = json.loads((out / "inputs.json").read_text())
    inputs["study"] = {k: v for k, v in inputs["study"].items() if k not in KEYS}
    (out / "inputs.json").write_text(json.dumps(inputs))
    KINDS["fragility"].module().write_report(out)
    block = title_block(first_page((out / "index.html").read_text()))
    text = " ".join(re.sub(r"<[^>]+>", " ", block).split())
    for word in ("None", "none", "n/a", "null", "undefined"):
        assert word not in text.split(), word
    assert set(re.findall(r'data-blank="(\w+)"', block)) == set(KEYS)
    note = re.search(r'<p class="title-note" data-missing="([^"]*)">(.*?)</p>', block, re.S)
    assert note and note.group(1).split() == list(KEYS)
    assert re.findall(r"<code>(\w+)</code>", note.group(2)) == list(KEYS)
    assert "[study]" in note.group(2)
    assert inputs["study_sha256"] in block  # the hash and the version are still there


def test_the_pdf_carries_the_title_block_on_page_one(titled, tmp_path):
    """Printed: page 1 has the title block's values, both signature lines and the full hash
    in one piece."""
    import subprocess

    from colonna.studies.pdf import find_browser, write_pdf

    if find_browser() is None or shutil.which("pdftotext") is None:
        pytest.skip("needs a Chromium browser and poppler's pdftotext")
    out = titled["fragility"] / "out"
    pdf = write_pdf(out / "index.html", tmp_path / "report.pdf")
    text = subprocess.run(
        ["pdftotext", "-layout", str(pdf), "-"], capture_output=True, text=True, check=True
    ).stdout
    page1 = text.split("\f")[0]
    for value in TITLE.values():
        assert value in page1, value
    assert "prepared by" in page1 and "checked by" in page1
    assert "signature" in page1 and "date" in page1
    sha = json.loads((out / "inputs.json").read_text())["study_sha256"]
    assert sha in page1 and f"colonna {colonna.__version__}" in page1


def test_a_changed_title_key_keeps_the_saved_cases(titled, tmp_path, capsys):
    """Another checker's name, a new revision: the same command keeps every saved case (none
    rewritten) and the report says the new names; a changed column is refused as stale."""
    root = tmp_path / "study"
    shutil.copytree(titled["fragility"], root)
    results = sorted((root / "out" / "cases").glob("*/result.json"))
    assert len(results) == 4
    before = {p: p.stat().st_mtime_ns for p in results}
    text = FRAGILITY.format(title=TITLE_LINES)
    renamed = text.replace('checked_by = "B. Bianchi"', 'checked_by = "C. Verdi"').replace(
        'revision = "B"', 'revision = "C"'
    )
    assert _run(root, renamed) == 0
    assert {p: p.stat().st_mtime_ns for p in results} == before
    block = title_block((root / "out" / "index.html").read_text())
    assert '<span data-title="checked_by">C. Verdi</span>' in block
    assert '<span data-title="revision">C</span>' in block
    capsys.readouterr()
    assert _run(root, renamed.replace("height = 4.0", "height = 4.2")) == 2
    assert "--force" in capsys.readouterr().err


def test_title_keys_are_not_inputs_of_a_case(tmp_path):
    """A case whose study dict holds a [study] table: its title keys, like its name, are left
    out of the case's inputs, so changing them recomputes nothing; its kind is an input."""
    calls = []

    def counted(case, directory):
        calls.append(case["key"])
        return {"value": case["x"] ** 2}

    def cases(**study):
        return [{"key": "one", "x": 3.0, "study": {"study": {"kind": "cross-check", **study}}}]

    out = tmp_path / "out"
    executor.run_cases(counted, cases(**TITLE), out, run_options=RunOptions(progress=False))
    executor.run_cases(
        counted,
        cases(prepared_by="someone else", revision="D"),
        out,
        run_options=RunOptions(progress=False),
    )
    assert calls == ["one"]
    assert set(KEYS) <= set(executor.NOT_STUDY_INPUTS)
    with pytest.raises(
        colonna.core.errors.StaleResultsError,
        match=r"study\.kind: \"cross-check\" -> \"free-rocking\"",
    ):
        executor.run_cases(
            counted, cases(kind="free-rocking"), out, run_options=RunOptions(progress=False)
        )

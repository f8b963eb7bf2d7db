"""The report as a PDF fit to file (``colonna study --pdf``), read back page by page with
poppler's pdfinfo and pdftotext: A4 by default (595 x 842 pt; Letter, 612 x 792 pt, with
``--paper letter``), every page numbered "x / y" under a running header with the study's name,
the colonna version and the run's date, page 1 the outcome, no table split from its header
row, no heading left at a page foot. The default study's PDF is checked the same way under
``make test-all`` (it runs the default study)."""

import json
import re
import shutil
import subprocess
from datetime import datetime
from pathlib import Path

import pytest
from jinja2 import ChoiceLoader, FileSystemLoader
from tiny_study import TINY_STUDY

import colonna
from colonna.studies import report
from colonna.studies.cli import main
from colonna.studies.pdf import find_browser, header_rows_repeated, write_pdf
from colonna.studies.report import render_page

# the smallest study there is: one short FEM run of the tiny column (a collar-design study)
DESIGN = TINY_STUDY.format(amplitude_ratio=2.5, duration=0.1).replace(
    'name = "tiny"', 'name = "tiny"\nkind = "collar-design"'
)
A4 = (595, 842)  # pt: 210 x 297 mm
LETTER = (612, 792)  # pt: 8.5 x 11 in


@pytest.fixture(scope="module", autouse=True)
def _printing_tools():
    if find_browser() is None or not all(shutil.which(tool) for tool in ("pdftotext", "pdfinfo")):
        pytest.skip(
            "needs a Chromium browser and poppler's pdftotext and pdfinfo (make test "
            "installs them where apt is available)"
        )


def page_size(pdf: Path) -> tuple[int, int]:
    """The first page's size (pt, rounded) as pdfinfo reads it."""
    info = subprocess.run(["pdfinfo", str(pdf)], capture_output=True, text=True, check=True)
    found = re.search(r"Page size:\s+([\d.]+) x ([\d.]+) pts", info.stdout)
    assert found, info.stdout
    return round(float(found.group(1))), round(float(found.group(2)))


def pages(pdf: Path, layout: bool = True) -> list[str]:
    """The text of each page (pdftotext, -layout: as laid out, else in reading order, a table
    cell's lines together; pages end with a form feed)."""
    text = subprocess.run(
        ["pdftotext", *(["-layout"] if layout else []), str(pdf), "-"],
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    return text.split("\f")[:-1]


def flat(text: str) -> str:
    return " ".join(text.split())


FOOTER = re.compile(r"page (\d+) / (\d+)")


def check_running_header_and_footer(pdf: Path, header: str) -> int:
    """Every page has ``header`` (a regular expression) as its first line and "page k / n" as
    its last, k counting 1..n with n the number of pages; returns n."""
    texts = pages(pdf)
    assert texts, pdf
    for k, text in enumerate(texts, start=1):
        lines = [line.strip() for line in text.splitlines() if line.strip()]
        assert re.fullmatch(header, flat(lines[0])), (k, lines[0])
        footer = FOOTER.fullmatch(flat(lines[-1]))
        assert footer, (k, lines[-1])
        assert (int(footer.group(1)), int(footer.group(2))) == (k, len(texts))
    return len(texts)


def header_of(page: Path) -> str:
    """The running header the report's pages must carry: from its inputs.json."""
    inputs = json.loads((page.parent / "inputs.json").read_text())
    started = datetime.fromisoformat(inputs["run_record"]["started_utc"])
    name = inputs["study"].get("name") or Path(inputs["study_file"]).stem
    return re.escape(f"{name} · colonna {colonna.__version__} · run {started:%Y-%m-%d %H:%M} UTC")


def check_headings_not_at_a_page_foot(pdf: Path, page: Path) -> None:
    """No section heading of the page is the last text of a PDF page above its footer."""
    html = page.read_text()
    headings = {flat(re.sub(r"<[^>]+>", "", h)) for h in re.findall(r"<h[1-4][^>]*>(.*?)</h", html)}
    assert headings
    for k, text in enumerate(pages(pdf), start=1):
        lines = [flat(line) for line in text.splitlines() if line.strip()]
        assert lines[-2] not in headings, (k, lines[-2])  # lines[-1]: the footer


def check_tables_keep_their_header(pdf: Path, header: str, labels: list[str]) -> set[int]:
    """Each page that shows a row of a table (its label) shows the table's header row above
    it; returns those pages (1-based)."""
    shown = set()
    for k, text in enumerate(pages(pdf), start=1):
        lines = [flat(line) for line in text.splitlines()]
        rows = [i for i, line in enumerate(lines) if any(label in line for label in labels)]
        if not rows:
            continue
        shown.add(k)
        heads = [i for i, line in enumerate(lines) if header in line]
        assert heads and heads[0] < rows[0], f"page {k}: rows without the header row {header!r}"
    return shown


@pytest.fixture(scope="module")
def printed(tmp_path_factory):
    """The tiny collar-design study run once with --pdf (A4, the default)."""
    root = tmp_path_factory.mktemp("printed")
    study = root / "design.toml"
    study.write_text(DESIGN)
    out = root / "out"
    assert main(["study", str(study), "--out", str(out), "--workers", "1", "--pdf"]) == 0
    return out


def test_the_pdf_is_a4_and_every_page_carries_study_version_date_and_x_of_y(printed):
    pdf = printed / "report.pdf"
    assert page_size(pdf) == A4
    n = check_running_header_and_footer(pdf, header_of(printed / "index.html"))
    assert n >= 2  # the outcome, then the inputs from a page of their own
    check_headings_not_at_a_page_foot(pdf, printed / "index.html")
    assert not list(printed.glob(".*print.html"))  # the print copy is removed


def test_page_one_is_the_outcome_and_the_inputs_follow(printed):
    """Page 1 has the outcome and the questions; the inputs (with the model as built) start
    on page 2."""
    texts = [flat(t) for t in pages(printed / "report.pdf", layout=False)]
    assert "Outcome" in texts[0] and "Inputs" not in texts[0]
    second = [line.strip() for line in pages(printed / "report.pdf")[1].splitlines()]
    assert [line for line in second if line][1] == "Inputs"  # under the running header
    for question in (
        "rigid-body assumption good enough?",
        "Do the collars yield?",
        "Does the toe crush?",
    ):
        assert question in texts[0], question
    assert "The FEM model of the study's mesh" in " ".join(texts[1:])


def test_letter_paper_on_request(printed, tmp_path, capsys):
    """write_pdf(paper="letter") prints the same page on US Letter, still numbered; --paper
    without --pdf, or another paper, is an input error before anything runs."""
    pdf = write_pdf(printed / "index.html", tmp_path / "letter.pdf", paper="letter")
    assert page_size(pdf) == LETTER
    check_running_header_and_footer(pdf, header_of(printed / "index.html"))
    study = tmp_path / "design.toml"
    study.write_text(DESIGN)
    capsys.readouterr()
    assert main(["study", str(study), "--out", str(tmp_path / "o"), "--paper", "letter"]) == 2
    assert "--paper" in capsys.readouterr().err and not (tmp_path / "o").exists()


def test_a_long_table_keeps_its_header_row_on_every_page(tmp_path, monkeypatch):
    """A report page with a table of 150 rows (as a kind's template writes one: its header
    row a plain <tr> of <th>) and a numbers table from the shared macro, printed through the
    shared base template: each spans pages, each page shows the header row above its rows,
    and no row is split (its label and value on one page). Without inputs on record, the
    running header has the page's title and the print date."""
    rows = "".join(
        f"<tr><th>row-{i:03d}</th><td>value-{i:03d}<br>second line</td><td>m</td></tr>"
        for i in range(150)
    )
    template = tmp_path / "long.html.j2"
    template.write_text(
        '{% extends "base.html.j2" %}{% from "macros.html.j2" import numbers with context %}'
        "{% block body %}<h2>A long table</h2>"
        f"<table><tr><th>kind's label</th><th>kind's value</th><th>unit</th></tr>{rows}</table>"
        "<h2>Numbers</h2>{{ numbers(long_rows) }}{% endblock %}"
    )
    # the test's template found beside the shipped ones
    shipped = report.TEMPLATES.loader
    assert shipped is not None
    monkeypatch.setattr(
        report.TEMPLATES, "loader", ChoiceLoader([shipped, FileSystemLoader(str(tmp_path))])
    )
    summary = {f"q{i:03d}": float(i) for i in range(120)}
    page = render_page(
        tmp_path,
        "long.html.j2",
        summary,
        "long",
        long_rows=[(f"numbered-{i:03d}", f"q{i:03d}", "m") for i in range(120)],
    )
    pdf = write_pdf(page, tmp_path / "long.pdf")
    spanned = check_tables_keep_their_header(
        pdf, "kind's label kind's value unit", [f"row-{i:03d}" for i in range(150)]
    )
    assert len(spanned) >= 2
    numbered = check_tables_keep_their_header(
        pdf, "quantity value unit", [f"numbered-{i:03d}" for i in range(120)]
    )
    assert len(numbered) >= 2
    for k, text in enumerate(pages(pdf), start=1):  # each row whole on one page
        for i in range(150):
            assert (f"row-{i:03d}" in text) == (f"value-{i:03d}" in text), (k, i)
    assert page_size(pdf) == A4
    # no inputs on record: the page's title and the print date
    printed = re.escape(f"long · colonna {colonna.__version__} · printed ")
    check_running_header_and_footer(pdf, printed + r"\d{4}-\d\d-\d\d \d\d:\d\d UTC")


def test_a_header_row_becomes_the_table_head_and_a_data_row_does_not():
    page = (
        '<table class="x"><tr><th>a</th><th>b</th></tr><tr><th>r</th><td>1</td></tr></table>'
        "<table><tr><th>r</th><td>2</td></tr></table>"
        "<table><thead><tr><th>h</th></tr></thead><tr><td>3</td></tr></table>"
    )
    assert header_rows_repeated(page) == (
        '<table class="x"><thead><tr><th>a</th><th>b</th></tr></thead>'
        "<tr><th>r</th><td>1</td></tr></table>"
        "<table><tr><th>r</th><td>2</td></tr></table>"
        "<table><thead><tr><th>h</th></tr></thead><tr><td>3</td></tr></table>"
    )


@pytest.mark.slow
def test_the_default_study_pdf(tmp_path):
    """The default study printed: A4, every page numbered with its running header, no
    heading at a page foot, and every table that spans pages shows its header row on each."""
    out = tmp_path / "out"
    assert main(["study", "default", "--out", str(out), "--pdf"]) == 0
    pdf, page = out / "report.pdf", out / "index.html"
    assert page_size(pdf) == A4
    check_running_header_and_footer(pdf, header_of(page))
    check_headings_not_at_a_page_foot(pdf, page)
    html = header_rows_repeated(page.read_text())
    for table in re.findall(r"<table\b.*?</table>", html, re.S):
        head = re.search(r"<thead>(.*?)</thead>", table, re.S)
        if head is None:
            continue
        header = flat(re.sub(r"<[^>]+>", " ", head.group(1)))
        labels = [
            flat(re.sub(r"<[^>]+>", " ", label))
            for label in re.findall(r"<tr><th>(.*?)</th>", table.split("</thead>", 1)[1])
        ]
        labels = [label for label in labels if len(label) >= 12 and html.count(label) == 1]
        if labels:
            check_tables_keep_their_header(pdf, header, labels)

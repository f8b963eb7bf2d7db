"""The report as a PDF fit to file, printed by the headless Chromium the report tests already
use: the page as the browser lays it out for print, the title block (with its signature lines
and the study file's full SHA-256) and the outcome and the answers on its first page (the
``@media print`` rules of ``templates/base.html.j2`` leave the GIF and the 3-D
renders out and start the inputs on a page of their own).

Paged media, and why Chromium's CSS rather than WeasyPrint or the browser's print settings
------------------------------------------------------------------------------------------
The page is A4 by default (Letter with ``paper="letter"``, ``colonna study --pdf --paper
letter``); each page carries a running header (the study's name, the colonna version and the
run's date in UTC, from ``inputs.json``) and a footer "page x / y". All of it is plain CSS
paged media: ``@page { size: A4; @top-left { content: ... } @bottom-right { content:
counter(page) " / " counter(pages) } }``, which Chromium implements (margin boxes and the
``pages`` counter since version 131; 156 here), with ``thead { display: table-header-group }``
repeating a table's header row on each page it spans, ``tr { break-inside: avoid }`` keeping a
row whole and ``break-after: avoid`` keeping a heading with what follows it. WeasyPrint
implements the same CSS, but it would be a second layout engine with its own dependencies
(Pango, cairo) and it runs no JavaScript nor renders the page's SVG exactly as the browser the
report tests check it with; Chromium is already needed for those tests, so the PDF is the page
the tests read. Chromium's own print settings (``--print-to-pdf`` paper and its header
template) can put only the page's title and URL in a running header and no study-specific
text, so they are turned off (``--no-pdf-header-footer``) and the CSS decides. What the
templates cannot know (the paper asked for, the run's date) and a table whose header row is
not a ``<thead>`` (a kind's template may write ``<tr><th>``) are settled in a print copy of
the page (:func:`print_copy`), written beside it and removed once printed: index.html itself
is not changed.
"""

from __future__ import annotations

import importlib
import json
import re
import shutil
import subprocess
from datetime import UTC, datetime
from pathlib import Path

from ..core.errors import InputError

BROWSERS = ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable")

# the paper sizes --paper offers, as CSS names them (ISO A4: 210 x 297 mm, 595 x 842 pt;
# US Letter: 8.5 x 11 in, 612 x 792 pt)
PAPERS = {"a4": "A4", "letter": "letter"}


def find_browser() -> str | None:
    """The path of a Chromium-family browser, or None."""
    for name in BROWSERS:
        found = shutil.which(name)
        if found:
            return found
    return None


def require_browser() -> str:
    """The browser that prints, or an InputError naming what to install (checked before a
    study runs, so that ``--pdf`` fails before any work)."""
    browser = find_browser()
    if browser is None:
        raise InputError(
            "--pdf needs a Chromium browser (chromium, chromium-browser or "
            "google-chrome) on the PATH: install one (e.g. apt-get install "
            "chromium), or open index.html and print it"
        )
    return browser


def require_paper(paper: str) -> str:
    """The CSS name of a paper size of :data:`PAPERS`, or an InputError naming them."""
    if paper.lower() not in PAPERS:
        raise InputError(f"--paper = {paper!r} is not one of: {', '.join(PAPERS)}")
    return PAPERS[paper.lower()]


def running_header(page: Path) -> str:
    """The running header of a report's pages: its study's name, the colonna version and the
    date (UTC) of its run, from the ``inputs.json`` beside the page (the print date, and the
    page's title, where that is not on record)."""
    name, version, date = None, importlib.import_module("colonna").__version__, None
    try:
        inputs = json.loads((Path(page).parent / "inputs.json").read_text())
    except (OSError, ValueError):
        inputs = {}
    if isinstance(inputs, dict):
        study = inputs.get("study") or {}
        name = study.get("name") or Path(str(inputs.get("study_file", ""))).stem or None
        version = inputs.get("colonna_version", version)
        record = inputs.get("run_record") or {}
        when = record.get("started_utc") or record.get("finished_utc")
        if when:
            date = datetime.fromisoformat(when).astimezone(UTC)
    if name is None:
        found = re.search(r"<title>([^<]*)</title>", Path(page).read_text())
        name = found.group(1).strip() if found else Path(page).parent.name
    shown = (
        f"run {date:%Y-%m-%d %H:%M} UTC"
        if date is not None
        else f"printed {datetime.now(UTC):%Y-%m-%d %H:%M} UTC"
    )
    return f"{name} \N{MIDDLE DOT} colonna {version} \N{MIDDLE DOT} {shown}"


def css_string(text: str) -> str:
    """``text`` as a quoted CSS string (backslash, quote and ``<`` escaped, so that no text
    ends the string or the style element)."""
    escaped = text.replace("\\", "\\\\").replace('"', '\\"').replace("<", "\\3c ")
    return '"' + " ".join(escaped.split()) + '"'


# the first row of a table, where it has header cells only (a row with a <td> is data)
_FIRST_ROW = re.compile(r"(<table\b[^>]*>)(\s*)(<tr\b(?:(?!</tr>).)*</tr>)", re.S)


def header_rows_repeated(html: str) -> str:
    """``html`` with each table's first row made its ``<thead>`` where that row holds header
    cells only and the table has no thead: the row the print rules repeat on every page the
    table spans."""

    def head(match: re.Match) -> str:
        table, space, row = match.groups()
        if "<td" in row:
            return match.group(0)
        return f"{table}{space}<thead>{row}</thead>"

    return _FIRST_ROW.sub(head, html)


def print_copy(page: Path, paper: str = "a4") -> str:
    """The page as it is printed: its tables' header rows as ``<thead>``
    (:func:`header_rows_repeated`), the paper size and the running header
    (:func:`running_header`) set in an ``@page`` rule after the template's own."""
    size = require_paper(paper)
    html = header_rows_repeated(Path(page).read_text())
    rule = (
        f"<style>@page {{ size: {size}; "
        f"@top-left {{ content: {css_string(running_header(page))}; }} }}</style>"
    )
    at = html.find("</head>")
    return html[:at] + rule + html[at:] if at >= 0 else rule + html


def write_pdf(page: Path, pdf: Path, paper: str = "a4", timeout: float = 180.0) -> Path:
    """Print the HTML ``page`` to ``pdf`` on ``paper`` (a key of :data:`PAPERS`): its print
    copy (:func:`print_copy`), written beside the page (so that what it links to resolves as
    from the page) and removed after; the browser's own message where printing fails."""
    size = require_paper(paper)
    browser = require_browser()
    page, pdf = Path(page).resolve(), Path(pdf).resolve()
    copy = page.with_name(f".{page.stem}.print.html")
    copy.write_text(print_copy(page, paper))
    pdf.unlink(missing_ok=True)  # a PDF of an earlier run is not this one
    try:
        run = subprocess.run(
            [
                browser,
                "--headless=new",
                "--no-sandbox",
                "--disable-gpu",
                "--no-pdf-header-footer",
                "--virtual-time-budget=20000",
                f"--print-to-pdf={pdf}",
                copy.as_uri(),
            ],
            capture_output=True,
            text=True,
            timeout=timeout,
        )
    finally:
        copy.unlink(missing_ok=True)
    if run.returncode != 0 or not pdf.is_file() or pdf.stat().st_size == 0:
        raise RuntimeError(
            f"printing {page} to PDF ({size}) failed ({browser}, exit "
            f"{run.returncode}): {run.stderr.strip()[-500:]}"
        )
    return pdf

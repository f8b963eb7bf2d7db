"""Open a report in headless Chromium and read back what data/report_check.js found."""

import html
import json
import re
import subprocess
from pathlib import Path

import pytest

CHECK = Path(__file__).with_name("data") / "report_check.js"
# a number of summary.json in a report: its dotted key, its display scale, what is shown
SPAN = re.compile(r'<span data-key="([^"]+)"(?: data-scale="([^"]+)")?>([^<]*)</span>')


def browser() -> str:
    from colonna.studies.pdf import find_browser

    found = find_browser()
    if found is None:
        pytest.skip("no headless browser (make test installs chromium where apt is available)")
    return found


def check_report(page: Path, scratch: Path) -> list[dict]:
    """One result per <figure>: name, legend entries, problems (empty when all is drawn)."""
    text = Path(page).read_text()
    probe = f"<script>{CHECK.read_text()}</script>"
    checked = Path(scratch) / "check.html"
    checked.write_text(text.replace("</body>", probe + "</body>"))
    run = subprocess.run(
        [
            browser(),
            "--headless=new",
            "--no-sandbox",
            "--disable-gpu",
            "--virtual-time-budget=20000",
            "--dump-dom",
            checked.as_uri(),
        ],
        capture_output=True,
        text=True,
        timeout=180,
    )
    found = re.findall(r'<pre id="colonna-check">(.*?)</pre>', run.stdout, re.S)
    assert found, run.stderr[-2000:]
    return json.loads(html.unescape(found[-1]))


def assert_every_figure_drawn(page: Path, scratch: Path, at_least: int) -> list[dict]:
    results = check_report(page, scratch)
    problems = {r["name"]: r["problems"] for r in results if r["problems"]}
    assert not problems, problems
    assert len(results) >= at_least, [r["name"] for r in results]
    return results


NUMBER = re.compile(r"^[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$")


def assert_table_numbers_have_units(page_text: str) -> int:
    """Every table cell that holds one number from summary.json (a data-key span) states its
    unit: after the number, in the row's unit cell (class="unit", "-" for a ratio), or in its
    column header as "(unit)". Returns how many cells were checked."""
    checked = 0
    for table in re.findall(r"<table[^>]*>(.*?)</table>", page_text, re.S):
        rows = re.findall(r"<tr>(.*?)</tr>", table, re.S)
        header = re.findall(r"<t[hd][^>]*>(.*?)</t[hd]>", rows[0], re.S) if rows else []
        for row in rows[1:]:
            cells = re.findall(r"<t[hd]([^>]*)>(.*?)</t[hd]>", row, re.S)
            unit_cell = [c for attrs, c in cells if 'class="unit"' in attrs]
            for j, (_attrs, cell) in enumerate(cells):
                spans = [shown for _, _, shown in SPAN.findall(cell)]
                bare = re.sub(r"<[^>]+>", "", cell).replace("&times;", "").strip()
                if (
                    len(spans) != 1
                    or not NUMBER.match(spans[0])
                    or bare != spans[0]
                    and "&nbsp;" not in cell
                ):
                    continue  # not a lone number (words, prose, yes/no)
                checked += 1
                has_unit = (
                    "</span>&nbsp;" in cell
                    or (unit_cell and unit_cell[0].strip())
                    or (j < len(header) and re.search(r"\([^)]+\)", header[j]))
                )
                assert has_unit, (row, header)
    return checked


def assert_report_says_what_summary_says(page_text: str, summary: dict) -> int:
    """Every number of the page in a data-key span is summary.json's value at that key
    (times its data-scale where the report shows another unit: MPa from Pa, ...), as the
    report formats it; words are the summary's words. Returns how many were checked."""
    from colonna.studies.report import fmt

    spans = SPAN.findall(page_text)
    for key, scale, shown in spans:
        node = summary
        for part in key.split("."):
            node = node[int(part)] if isinstance(node, list) else node[part]
        if isinstance(node, str):
            assert html.unescape(shown) == node, key
            continue
        if scale and node is not None:
            node = node * float(scale)
        assert shown in {fmt(node, d) for d in (2, 3, 4, 5)}, (key, shown, node)
    return len(spans)


def assert_opens_with_the_outcome(page_text: str, summary: dict) -> None:
    """The report's first section is the outcome, "Does the column stay up?" first, then the
    three answers (and, in their
    place, the optional ones the study gives: "Do the collars hold?"), each the word of
    summary.json's outcome (the data-key of the word names it)."""
    from colonna.studies.outcome import OPTIONAL_QUESTIONS, QUESTIONS

    assert re.findall(r"<h2>([^<]+)</h2>", page_text)[0] == "Outcome"
    answers = summary["outcome"]["answers"]
    keys = [a["key"] for a in answers]
    assert [k for k in keys if k not in OPTIONAL_QUESTIONS] == [
        "stays_up",
        "rigid_assumption_ok",
        "collars_yield",
        "toe_crushes",
    ]
    assert keys == [k for k in QUESTIONS if k in keys]
    for i, a in enumerate(answers):
        cell = re.search(
            rf'data-answer="{a["key"]}"[^>]*><span data-key="outcome\.answers\.'
            rf'{i}\.answer">([^<]+)</span>',
            page_text,
        )
        assert cell and cell.group(1) == a["answer"], a["key"]

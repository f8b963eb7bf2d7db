"""No legend entry, axis label or title of a report figure is cut off in the report's PDF, read
back with pdftotext (issue 48: the trial's PDF showed a legend entry "base contact pressure at
the" and an axis label "nodes (MPa").

The reports embed each figure as inline SVG whose text stays text (:func:`colonna.studies.
report.figure`, ``svg.fonttype`` none), so Chromium prints it as text and pdftotext reads it
back. A text that runs past its figure is clipped by the SVG's viewport, and pdftotext reads
only the glyphs printed: a legend entry cut at the figure's right edge comes back as its first
words, a line wholly outside not at all (:func:`test_the_check_finds_the_texts_a_figure_cuts`
pins that on a page of its own). The texts expected are taken from the matplotlib figures the
report module builds (every ``savefig`` of the run, by its file's name), each line as the
figure draws it (mathtext as its glyphs), and compared without whitespace (pdftotext spaces
per-glyph text its own way): each must be printed at least as often as the page's own text
and the figures' texts hold it, so that a legend entry that is also a word of the body text
("design intensity") is not found in the body in place of the figure. A figure embedded as a
PNG (``report.image``: the zhang-makris kind's, the renders) has no text to read and is not
checked here (``texts_outside`` checks its matplotlib figure: tests/test_figure_texts.py).
"""

from __future__ import annotations

import html
import re
import shutil
import subprocess
from pathlib import Path

import matplotlib
import pytest

matplotlib.use("Agg")
from matplotlib.figure import Figure  # noqa: E402
from matplotlib.mathtext import MathTextParser  # noqa: E402

from colonna.studies.pdf import find_browser, write_pdf  # noqa: E402
from colonna.studies.report import figure, texts_outside  # noqa: E402


@pytest.fixture(scope="module", autouse=True)
def _printing_tools():
    if find_browser() is None or shutil.which("pdftotext") is None:
        pytest.skip(
            "needs a Chromium browser and poppler's pdftotext (make test installs them where "
            "apt is available)"
        )


def squeeze(text: str) -> str:
    """``text`` without any whitespace."""
    return "".join(text.split())


def drawn_lines(text) -> list[str]:
    """The lines of a matplotlib Text as its figure draws them, each without whitespace: a
    line with math ($...$) as mathtext's glyphs in order (r"$|\\theta| / \\alpha$" draws
    "|θ|/α")."""
    lines = []
    for line in text.get_text().split("\n"):
        source, math = text._preprocess_math(line)
        if math is True:
            glyphs = MathTextParser("path").parse(source, 72, text.get_fontproperties()).glyphs
            # (font, size, character code, glyph index, x, y) in matplotlib 3.11
            line = "".join(chr(g[2]) for g in sorted(glyphs, key=lambda g: g[-2]))
        if squeeze(line):
            lines.append(squeeze(line))
    return lines


def figure_texts(fig: Figure) -> list[str]:
    """Every legend entry and title, axis label, axes title and free text of ``fig`` that is
    shown, as :func:`drawn_lines` (tick labels aside: numbers)."""
    texts = []
    legends = list(fig.legends) + [ax.get_legend() for ax in fig.axes if ax.get_legend()]
    for legend in legends:
        if legend.get_visible():
            texts += list(legend.get_texts()) + [legend.get_title()]
    for ax in fig.axes:
        if not ax.get_visible():
            continue
        texts += [ax.xaxis.label, ax.yaxis.label, ax.title, ax._left_title, ax._right_title]
        texts += list(ax.texts)
    texts += list(fig.texts)
    texts += [t for t in (fig._suptitle, fig._supxlabel, fig._supylabel) if t is not None]
    return [line for t in texts if t.get_visible() for line in drawn_lines(t)]


def page_text(page: str) -> str:
    """The text of a report page outside its figures (what the PDF prints besides them)."""
    page = re.sub(r"<(head|svg|style|script)\b.*?</\1>", " ", page, flags=re.S)
    return squeeze(html.unescape(re.sub(r"<[^>]+>", " ", page)))


def pdf_text(pdf: Path) -> str:
    return subprocess.run(
        ["pdftotext", str(pdf), "-"], capture_output=True, text=True, check=True
    ).stdout


def svg_figures(page: str) -> list[str]:
    """The names of the page's figures embedded as SVG (their text printed as text)."""
    return re.findall(r'<figure [^>]*data-figure="([^"]+)"[^>]*>\s*<svg', page)


def cut_texts(page: str, printed: str, figures: dict[str, Figure]) -> dict[str, list[str]]:
    """Each text of the figures of ``figures`` (name: the matplotlib figure) embedded in
    ``page`` as SVG that ``printed`` (the PDF's text) does not hold whole (whitespace
    removed), with the figures that draw it: printed fewer times than the page's text outside
    its figures and the figures' texts hold it."""
    shown = [name for name in svg_figures(page) if name in figures]
    expected = {name: figure_texts(figures[name]) for name in shown}
    every = [line for lines in expected.values() for line in lines]
    body, printed = page_text(page), squeeze(printed)
    found: dict[str, list[str]] = {}
    for line in dict.fromkeys(every):
        need = body.count(line) + sum(other.count(line) for other in every)
        if printed.count(line) < need:
            found[line] = [name for name, lines in expected.items() if line in lines]
    return found


def test_the_check_finds_the_texts_a_figure_cuts(tmp_path):
    """A page of two figures: one laid out (every text inside), one whose legend runs off its
    right edge, whose y label is taller than the figure, whose x label's second line lies below
    it and with a note wholly outside. Printed, the check finds exactly the cut texts (those
    :func:`texts_outside` finds on the figure), none of the figure laid out, although a body
    sentence holds one of the cut legend entries whole."""
    whole = Figure(figsize=(6, 3))
    ax = whole.subplots()
    ax.plot([0, 1], [0, 1], label="design intensity")
    ax.set_xlabel(r"largest $|\theta| / \alpha$ of a run")
    ax.set_ylabel("P[limit state | IM]")
    ax.set_title("laid out")
    ax.legend()
    whole.tight_layout()
    cut = Figure(figsize=(6, 3))
    ax = cut.subplots()
    ax.plot([0, 1], [0, 1], label="base contact pressure at the nodes (max 9.36 MPa)")
    ax.plot([0, 1], [1, 0], label="design intensity")
    ax.legend(loc="upper left", bbox_to_anchor=(0.8, 1.0))
    ax.set_ylabel("base contact pressure at the nodes, a label far too tall (MPa)")
    ax.set_xlabel("time (s)\nsecond line below the figure")
    ax.text(1.6, 0.5, "a note outside", transform=ax.transAxes)
    ax.set_title("cut")
    figures = {"whole": whole, "cut": cut}
    page, printed = _printed(tmp_path, figures, "page")
    assert texts_outside(whole) == []
    outside = [squeeze(t.split(": ", 1)[1]) for t in texts_outside(cut)]
    found = cut_texts(page, printed, figures)
    assert found == {
        squeeze("design intensity"): ["whole", "cut"],  # (its legend entry in both figures)
        squeeze("base contact pressure at the nodes (max 9.36 MPa)"): ["cut"],
        squeeze("base contact pressure at the nodes, a label far too tall (MPa)"): ["cut"],
        squeeze("time (s)"): ["cut"],
        squeeze("second line below the figure"): ["cut"],
        squeeze("a note outside"): ["cut"],
    }
    # each is (a line of) a text that texts_outside finds, and each text it finds is found
    assert all(any(line in text for text in outside) for line in found)
    assert all(any(line in text for line in found) for text in outside)
    # the same figure laid out: nothing cut
    ax.get_legend().remove()
    ax.texts[0].remove()
    ax.legend(loc="upper left")
    ax.set_ylabel("pressure (MPa)")
    cut.tight_layout()
    assert texts_outside(cut) == []
    assert cut_texts(*_printed(tmp_path, figures, "again"), figures) == {}


def _printed(root: Path, figures: dict[str, Figure], name: str) -> tuple[str, str]:
    """A page with a sentence and ``figures`` (as the reports embed them: report.figure),
    printed to NAME.pdf: (the page, the PDF's text)."""
    shown = [figure(root, key, fig, f"The figure {key}.") for key, fig in figures.items()]
    page = root / f"{name}.html"
    page.write_text(
        "<html><head><title>t</title></head><body><h1>Two figures</h1>"
        "<p>The dotted line is the design intensity.</p>"
        + "".join(
            f'<figure data-figure="{f["name"]}">{f["svg"]}<figcaption>{f["caption"]}'
            "</figcaption></figure>"
            for f in shown
        )
        + "</body></html>"
    )
    return page.read_text(), pdf_text(write_pdf(page, root / f"{name}.pdf"))


@pytest.mark.slow
def test_no_text_of_a_figure_is_cut_off_in_the_shipped_fragility_pdf(tmp_path, monkeypatch):
    """The shipped fragility study (studies/fragility.toml: the SDOF and the multibody over
    the synthetic suite; its figures the ones with the most legend entries of any shipped study
    that runs in seconds) printed with --pdf: every legend entry, axis label, title and note of
    its fragility curves, IDA curves and spectra is in the PDF's text whole."""
    from colonna.studies.cli import main

    figures: dict[str, Figure] = {}
    keep = Figure.savefig

    def spy(fig, fname, *args, **kwargs):
        if isinstance(fname, (str, Path)):
            figures.setdefault(Path(fname).stem, fig)
        return keep(fig, fname, *args, **kwargs)

    monkeypatch.setattr(Figure, "savefig", spy)
    out = tmp_path / "out"
    assert main(["study", "fragility", "--out", str(out), "--workers", "1", "--pdf"]) == 0
    page = (out / "index.html").read_text()
    assert {"curves", "ida", "spectra"} <= set(svg_figures(page)) <= set(figures)
    checked = {name: figure_texts(figures[name]) for name in svg_figures(page)}
    assert sum(len(lines) for lines in checked.values()) >= 20, checked
    assert cut_texts(page, pdf_text(out / "report.pdf"), figures) == {}

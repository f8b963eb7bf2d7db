"""The browser check of report figures (tests/data/report_check.js) catches what it should.

A figure with nothing drawn, a legend entry whose handle is drawn nowhere, a legend that falls
outside the figure and an image that does not decode are each reported; a good figure is not.
The reports themselves are checked with it in test_study, test_spectrum_crosscheck and
test_free_rocking."""

import base64

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.patches import Patch  # noqa: E402

from browser import browser, check_report  # noqa: E402
from colonna.studies.report import TEMPLATES, _figure, _image  # noqa: E402


def _good(out):
    fig, ax = plt.subplots()
    ax.plot([0, 1, 2], [0, 1, 0], color="C0", label="rotation")
    ax.axhline(0.5, color="k", ls="--", label="f_y (yield stress)")
    ax.legend()
    return _figure(out, "good", fig, "a good figure")


def _empty(out):
    fig, ax = plt.subplots()
    ax.set_xlabel("t (s)")
    return _figure(out, "empty", fig, "nothing drawn")


def _proxy(out):
    fig, ax = plt.subplots()
    ax.plot([0, 1], [1, 2], color="C0", label="drawn")
    ax.legend(handles=[*ax.get_lines(), Patch(color="C3", label="never drawn")])
    return _figure(out, "proxy", fig, "a legend entry for nothing")


def _outside(out):
    fig, ax = plt.subplots()
    ax.plot([0, 1], [1, 2], color="C0", label="off the page")
    ax.legend(loc="upper left", bbox_to_anchor=(1.5, 1.0))     # no tight bbox: cut off
    return _figure(out, "outside", fig, "legend outside")


def test_the_browser_check_finds_what_is_wrong(tmp_path):
    browser()
    broken = tmp_path / "broken.png"
    broken.write_bytes(b"not a png")
    figs = [_good(tmp_path), _empty(tmp_path), _proxy(tmp_path), _outside(tmp_path),
            _image(broken, "an image that does not decode")]
    page = TEMPLATES.from_string(
        '{% from "macros.html.j2" import figures with context %}'
        "<!DOCTYPE html><html><body>{{ figures(figs) }}</body></html>").render(figs=figs)
    (tmp_path / "index.html").write_text(page)
    found = {r["name"]: r["problems"] for r in check_report(tmp_path / "index.html", tmp_path)}
    assert found["good"] == []
    assert found["empty"] == ["no data drawn"]
    assert len(found["proxy"]) == 1 and "never drawn" in found["proxy"][0] \
        and "is not drawn" in found["proxy"][0]
    assert found["outside"] == ['legend entry "off the page" outside the figure']
    assert found["broken"] == ["image not drawn"]
    assert base64.b64decode(figs[-1]["data"]) == b"not a png"

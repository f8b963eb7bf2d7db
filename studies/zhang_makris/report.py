"""The Zhang & Makris validation's reports: the HTML page of the study (its histories and spectra,
drawn by the runner) and the short Markdown report of ``colonna validate`` (presentation only:
the numbers are summary.json's)."""

from __future__ import annotations

import json
from pathlib import Path

from ..report import fmt, image, render_page
from .summary import load


def write_markdown(out: Path, s: dict) -> None:
    """``out/report.md``: the validation's histories and mode boundaries against the paper's
    Fig. 5, and its spectra (what ``colonna validate`` leaves beside summary.json)."""
    typed = load(s)  # a key the report reads that the summary lacks fails here, named
    lin, non = typed.boundaries.linear, typed.boundaries.nonlinear
    rows = "\n".join(
        f"| {x} | {h.mode} | {h.impacts} | {fmt(h.max_abs_theta_over_alpha, 4)} |"
        for x, h in typed.histories.items()
    )
    text = f"""# Zhang & Makris block: validation of the rigid solver

Block: p = {typed.block.p:.2f} rad/s, alpha = {typed.block.alpha:.2f} rad, nu = 0.9;
one-sine pulse, Omega/p = 5, amplitude a_p in units of g alpha (linear model).

| a_p / (g alpha) | mode | impacts | max abs theta / alpha |
|---|---|---|---|
{rows}

Mode boundaries at Omega/p = 5 (a_p / a_uplift, bisection to 1e-6):

| boundary | linear | nonlinear | paper Fig. 5 |
|---|---|---|---|
| safe -> overturns after impact | {lin[0]:.4f} | {non[0]:.4f} | between 3.00 and 3.01 |
| overturns after impact -> safe | {lin[1]:.4f} | {non[1]:.4f} | between 6.32 and 6.33 |
| safe -> overturns without impact | {lin[2]:.4f} | {non[2]:.4f} | - |

![spectrum](spectrum_linear_free.png)
![spectrum](spectrum_linear_collars.png)
![spectrum](spectrum_nonlinear_free.png)
![spectrum](spectrum_nonlinear_collars.png)
"""
    (out / "report.md").write_text(text)


def write_report(out: Path) -> Path:
    """The Zhang & Makris validation: figures, boundaries and spectra."""
    out = Path(out)
    summary = json.loads((out / "summary.json").read_text())
    load(summary)  # a key the page reads that the file lacks fails here, named
    histories = [
        image(out / f"history_{x.replace('.', '_')}.png", f"a_p = {x} g alpha, Omega/p = 5")
        for x in ("3.00", "3.01", "6.32", "6.33")
    ]
    spectra = [
        image(out / f"spectrum_{m}_{c}.png", f"{m} model, {c.replace('free', 'free block')}")
        for m in ("linear", "nonlinear")
        for c in ("free", "collars")
    ]
    return render_page(
        out,
        "zhang_makris/report.html.j2",
        summary,
        "colonna validation: Zhang & Makris block",
        histories=histories,
        spectra=spectra,
    )

"""The report as a PDF, printed by the headless Chromium the report tests already use: the page
as the browser lays it out for print (the ``@media print`` rules of the templates leave the GIF
and the 3-D renders out), the outcome and the three answers on its first page."""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

from ..core.errors import InputError

BROWSERS = ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable")


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


def write_pdf(page: Path, pdf: Path, timeout: float = 180.0) -> Path:
    """Print the HTML ``page`` to ``pdf`` (no browser header or footer); the browser's own
    message where printing fails."""
    browser = require_browser()
    page, pdf = Path(page).resolve(), Path(pdf).resolve()
    run = subprocess.run(
        [
            browser,
            "--headless=new",
            "--no-sandbox",
            "--disable-gpu",
            "--no-pdf-header-footer",
            "--virtual-time-budget=20000",
            f"--print-to-pdf={pdf}",
            page.as_uri(),
        ],
        capture_output=True,
        text=True,
        timeout=timeout,
    )
    if run.returncode != 0 or not pdf.is_file() or pdf.stat().st_size == 0:
        raise RuntimeError(
            f"printing {page} to PDF failed ({browser}, exit "
            f"{run.returncode}): {run.stderr.strip()[-500:]}"
        )
    return pdf

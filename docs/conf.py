"""Sphinx configuration of colonna's documentation (``make docs``).

The pages are Markdown (MyST). Two reference pages and the default study's numbers are made here,
at every build, so that none can drift from what it documents:

* ``generated/cli.md``: the command line, from colonna's argparse parser (``cli_reference.py``);
* the study-file keys are ``study-file.md``, ``colonna schema --markdown``, committed so that it
  reads on GitHub too: the build stops if it is not the schema's (as ``tests/test_schema.py``);
* ``generated/runs.md`` and the ``{{ default_... }}``, ``{{ free_rocking_... }}`` substitutions:
  the numbers quoted from the shipped studies, read from ``runs/STUDY.json``, which
  ``run_numbers.py`` writes from each study's run (``make docs-numbers``); the build stops if a
  record was made from another study file or another colonna version (see the page itself).

The examples gallery (``examples/plot_*.py``) is executed by sphinx-gallery at every build.
"""

from __future__ import annotations

import sys
from pathlib import Path

from sphinx.errors import ConfigError

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import cli_reference  # noqa: E402
import run_numbers  # noqa: E402

import colonna  # noqa: E402
from colonna.studies.cli import build_parser  # noqa: E402

project = "colonna"
author = "the colonna authors"
copyright = "the colonna authors, BSD-3-Clause"
release = colonna.__version__
version = release

extensions = ["myst_parser", "sphinx_gallery.gen_gallery"]
source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
root_doc = "index"
exclude_patterns = ["_build", "examples", "Thumbs.db", ".DS_Store"]
myst_enable_extensions = ["substitution", "colon_fence"]
myst_heading_anchors = 3
html_theme = "alabaster"
html_theme_options = {
    "description": "cracked stone columns held by steel collars",
    "page_width": "1160px",
}
html_title = f"colonna {release}"

sphinx_gallery_conf = {
    "examples_dirs": "examples",
    "gallery_dirs": "gallery",
    "filename_pattern": r"/plot_",
    "download_all_examples": False,
    "within_subsection_order": "FileNameSortKey",
    "remove_config_comments": True,
    "show_memory": False,
    "matplotlib_animations": False,
}


def _generate() -> dict[str, str]:
    """Write the generated pages; return the substitutions of the numbers quoted from runs."""
    from colonna.studies.schema import markdown

    if (HERE / "study-file.md").read_text() != markdown():
        raise ConfigError(
            "docs/study-file.md is not the schema's key list: "
            "run `.venv/bin/colonna schema --markdown > docs/study-file.md`"
        )
    out = HERE / "generated"
    out.mkdir(exist_ok=True)
    _write(out / "cli.md", cli_reference.markdown(build_parser()))
    _write(out / "kinds-toc.md", _kinds_toctree())
    try:
        records = {study: run_numbers.load_current(study) for study in run_numbers.STUDIES}
    except SystemExit as stale:  # Sphinx would hide the reason of a SystemExit
        raise ConfigError(str(stale)) from None
    _write(out / "runs.md", run_numbers.page(records))
    for stale in set(out.glob("*.md")) - {out / "cli.md", out / "kinds-toc.md", out / "runs.md"}:
        stale.unlink()  # a page this build no longer makes (renamed) would warn, not in a toctree
    return run_numbers.substitutions(records)


# Pages of study kinds that are written beside their kind (docs/<page>.md): each one present is
# listed under "Using colonna" (index.md includes generated/kinds-toc.md), so that a kind's page
# lands in the site with the kind, and a missing one is no broken link.
KIND_PAGES = ("fragility",)


def _kinds_toctree() -> str:
    pages = [page for page in KIND_PAGES if (HERE / f"{page}.md").exists()]
    if not pages:
        return ""
    return "\n".join(
        [
            "```{toctree}",
            ":caption: Study kinds",
            ":maxdepth: 2",
            "",
            *[f"/{page}" for page in pages],
            "```",
            "",
        ]
    )


def _write(path: Path, text: str) -> None:
    """Write only a changed page, so that an unchanged build stays incremental."""
    if not path.exists() or path.read_text() != text:
        path.write_text(text)


myst_substitutions = _generate()

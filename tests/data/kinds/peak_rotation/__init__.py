"""An example study kind, added as a contributor would (docs/contributing.md): the peak rotation
of the study's column under its ground motion in the paper's SDOF model, and whether it
overturns. It is this package and one line of the registry; tests/test_kinds.py registers and
runs it through the command line."""

from __future__ import annotations

import json
from pathlib import Path

from colonna.studies.models import run_sdof
from colonna.studies.outcome import model_outcome, none_assessed, outcome
from colonna.studies.output import write_json
from colonna.studies.report import render_page


def run(study, out: Path, options) -> dict:
    """The study's column (the validated :class:`~colonna.studies.study.Study`) rocked by its
    ground motion: summary.json with its peak rotation (rad)."""
    column = study.fem
    rocking = run_sdof(column)
    peak = None if rocking.overturned else float(rocking.max_abs_theta)
    summary = {
        "study": column.name,
        "kind": study.kind,
        "peak_rotation": peak,
        "overturned": bool(rocking.overturned),
        "outcome": outcome(
            [
                model_outcome(
                    "SDOF, half column",
                    rocking.overturned,
                    peak,
                    column.rocking_block.alpha,
                    block="half" if column.cracked else "column",
                )
            ],
            {
                a["key"]: a
                for a in none_assessed("an example kind: the rigid model only")["answers"]
            },
        ),
    }
    Path(out).mkdir(parents=True, exist_ok=True)
    write_json(Path(out) / "summary.json", summary)
    return summary


def write_report(out: Path) -> Path:
    """index.html from summary.json, with the shared outcome and inputs sections."""
    summary = json.loads((Path(out) / "summary.json").read_text())
    return render_page(
        Path(out), "peak_rotation/report.html.j2", summary, f"peak rotation: {summary['study']}"
    )

"""docs/tour.ipynb, the Python API tour, runs: every code cell in order, in a scratch folder,
with the checks the notebook states (no Jupyter needed: the cells are plain Python)."""

import json
import os
from pathlib import Path

NOTEBOOK = Path(__file__).parents[1] / "docs" / "tour.ipynb"


def test_the_tour_notebook_runs(tmp_path):
    cells = json.loads(NOTEBOOK.read_text())["cells"]
    code = ["".join(c["source"]) for c in cells if c["cell_type"] == "code"]
    assert len(code) >= 5
    namespace = {"__name__": "__tour__"}
    here = os.getcwd()
    os.chdir(tmp_path)
    try:
        for number, source in enumerate(code, start=1):
            exec(compile(source, f"{NOTEBOOK.name}, cell {number}", "exec"), namespace)
    finally:
        os.chdir(here)
    # what the cells produce: a history figure, the spectra, a FEM run, a report
    assert (tmp_path / "tour_history.png").stat().st_size > 0
    assert namespace["held"].codes.shape == (25, 30)
    assert namespace["fem"].summary["energy_error_max"] < 0.01
    assert (tmp_path / "tour_out" / "index.html").stat().st_size > 0
    assert set(namespace["summary"]["verdict"]) >= {"rigid_assumption_ok", "toe_crushes"}

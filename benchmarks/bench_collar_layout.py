"""The collar-layout study's screening of a catalogue of at least 100 layouts over the shipped
suite (issue 50: within 10 minutes on 2 cores).

The shipped study (studies/collar-layout.toml: the default column, the synthetic near-fault
suite, the illustrative Mirandola hazard) with the schema's default catalogue: 1 to 5 collars x
7 flat-bar sections x 3 grades = 105 layouts, screened as 35 count x section walks of each of
the 10 records (a grade changes nothing until its collars yield:
:mod:`colonna.studies.collar_layout.runner`). Only the screening runs (its stage 1); the
refinement and the FEM confirmation depend on where the target falls.

Run alone, on an idle machine: `.venv/bin/python benchmarks/bench_collar_layout.py [workers]`
(default 2). Prints the layouts, walks, multibody runs, wall and CPU seconds.
"""

from __future__ import annotations

import re
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def main(workers: int = 2) -> None:
    from colonna.studies.collar_layout.runner import screening, setup
    from colonna.studies.executor import RunOptions
    from colonna.studies.study import load

    text = (ROOT / "studies" / "collar-layout.toml").read_text()
    for key in ("counts", "sections", "grades"):  # the schema's default catalogue
        text = re.sub(rf"^{key} = .*$", "", text, flags=re.M)
    for folder in ("suites", "hazards"):
        text = text.replace(f'"{folder}/', f'"{ROOT / "studies" / folder}/')
    with tempfile.TemporaryDirectory() as tmp:
        study_file = Path(tmp) / "layout.toml"
        study_file.write_text(text)
        s = setup(load(study_file))
        sections = {c.section for c in s.candidates}
        start, cpu = time.perf_counter(), time.process_time()
        found = screening(s, Path(tmp) / "out", RunOptions(workers=workers, progress=False))
        wall = time.perf_counter() - start
    print(
        f"{len(s.candidates)} layouts, {len(sections)} count x section walks x "
        f"{len(s.records)} records, {found['runs']} multibody runs: {wall:.0f} s wall on "
        f"{workers} workers, {found['seconds']:.0f} s of the workers' CPU "
        f"({found['seconds'] / max(found['runs'], 1):.3f} s a run; this process "
        f"{time.process_time() - cpu:.0f} s)"
    )


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 2)

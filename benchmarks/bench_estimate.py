"""The study's announced time against its wall time, on three study sizes (issue 47: within a
factor 1.5 of each).

Each study runs as a user runs it (`colonna study FILE --out DIR`, this machine's cores) into
a fresh folder; its estimate is :func:`colonna.studies.driver.wall_estimate` of its work, the
number the command prints first ("[study] estimated ... of wall time"), from the cost model
`colonna warmup` calibrated here. The sizes: the tiny test study (a 0.2 x 1 m column, 3 s),
the shipped default study and the README's example (a 3.2 x 0.36 m column on a lead sheet).

Run alone, on an idle machine, after `make` (the warm-up): `.venv/bin/python
benchmarks/bench_estimate.py [names...]`. Prints one line a study and a table for docs/speed.md.
"""

from __future__ import annotations

import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))

README_EXAMPLE = """
[column]
height = 3.2
width = 0.36
[stone]
E = 55e9
density = 2650.0
fc = 150e6
[base]
bed = "lead"
[[collar]]
y = 1.6
t = 0.006
h = 0.05
[ground]
pulse = "sine"
amplitude_ratio = 2.5
omega_ratio = 4.0
"""


def studies(folder: Path) -> dict[str, Path]:
    from tiny_study import TINY_STUDY

    files = {
        "tiny": TINY_STUDY.format(amplitude_ratio=1.5, duration=3.0),
        "readme-example": README_EXAMPLE,
    }
    paths = {"default": ROOT / "studies" / "default.toml"}
    for name, text in files.items():
        paths[name] = folder / f"{name}.toml"
        paths[name].write_text(text)
    return paths


def main(names: list[str]) -> None:
    from colonna.studies.cost import cost_model
    from colonna.studies.driver import fem_work_of, wall_estimate
    from colonna.studies.executor import default_workers
    from colonna.studies.study import load

    workers = default_workers()
    print(f"cost model calibrated here: {cost_model().calibrated}; {workers} workers")
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        paths = studies(Path(tmp))
        for name in names or list(paths):
            estimate = wall_estimate(fem_work_of(load(paths[name])), workers)
            start = time.perf_counter()
            subprocess.run(
                [str(ROOT / ".venv" / "bin" / "colonna"), "study", str(paths[name])]
                + ["--out", str(Path(tmp) / name)],
                check=True,
                stdout=subprocess.DEVNULL,
                stderr=subprocess.DEVNULL,
            )
            wall = time.perf_counter() - start
            rows.append((name, estimate, wall))
            ratio = wall / estimate
            print(f"{name}: estimated {estimate:.0f} s, took {wall:.0f} s, ratio {ratio:.2f}")
    print("\n| study | estimated (s) | wall (s) | wall / estimate |\n|---|---|---|---|")
    for name, estimate, wall in rows:
        print(f"| {name} | {estimate:.0f} | {wall:.0f} | {wall / estimate:.2f} |")


if __name__ == "__main__":
    main(sys.argv[1:])

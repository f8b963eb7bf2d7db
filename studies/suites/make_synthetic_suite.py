"""Write the shipped synthetic suite ``studies/suites/synthetic-pulses/``: 10 near-fault records
of 20 s at 100 Hz, each a Mavroeidis & Papageorgiou (2003) velocity pulse on a Rezaeian & Der
Kiureghian (2008) stochastic background (:mod:`colonna.core.synthetic`), seed 37, as PEER AT2
files in g (7 significant digits), and the suite list ``suite.toml`` with each record's drawn
parameters.

Run ``python -m colonna.studies.suites.make_synthetic_suite`` (or this file) to regenerate it
bit for bit; ``tests/test_synthetic.py`` checks that it does. The suite sits with the study
files that read it (``suite = "suites/synthetic-pulses"``), as tests/data/synthetic.AT2 sits
with its maker; benchmarks/ holds timing scripts, not data.
"""

from __future__ import annotations

import sys
from pathlib import Path

from colonna.core.constants import STANDARD_GRAVITY
from colonna.core.ground import Record
from colonna.core.suite import suite_toml
from colonna.core.synthetic import SyntheticParameters, synthetic_suite

FOLDER = Path(__file__).resolve().parent / "synthetic-pulses"
COUNT, SEED, DT, DURATION = 10, 37, 0.01, 20.0


def at2_text(record: Record, parameters: SyntheticParameters) -> str:
    """The PEER AT2 text of a record, in g (g = 9.81 m/s^2), five values a line."""
    lines = [
        "PEER NGA STRONG MOTION DATABASE RECORD (format only)",
        f"colonna synthetic near-fault record {record.name}: M&P 2003 pulse Tp = "
        f"{parameters.Tp:.3f} s, Vp = {parameters.Vp:.3f} m/s on an R&DK 2008 background",
        "ACCELERATION TIME SERIES IN UNITS OF G",
        f"NPTS= {record.time.size}, DT= {DT:.4f} SEC",
    ]
    values = [f"{v: .7E}" for v in record.acceleration_values / STANDARD_GRAVITY]
    lines += ["  ".join(values[i : i + 5]) for i in range(0, len(values), 5)]
    return "\n".join(lines) + "\n"


def suite_files(count: int = COUNT, seed: int = SEED) -> dict[str, str]:
    """File name -> text of every file of the suite (the list and the records)."""
    suite = synthetic_suite(count, seed, dt=DT, duration=DURATION)
    comment = (
        f"colonna's synthetic near-fault suite: {count} records of {DURATION:g} s at "
        f"{1 / DT:g} Hz, seed {seed}.\n"
        "Made by studies/suites/make_synthetic_suite.py (colonna.core.synthetic): a "
        "Mavroeidis & Papageorgiou (2003)\nvelocity pulse on a Rezaeian & Der Kiureghian "
        "(2008) modulated filtered white noise, baseline-corrected.\n"
        "Each record's drawn parameters (SI: s, m/s, rad, Hz, Hz/s) are under it."
    )
    entries = [
        {"file": f"{record.name}.AT2", "name": record.name, "parameters": p.to_dict()}
        for record, p in suite
    ]
    files = {"suite.toml": suite_toml(entries, comment=comment)}
    files.update({f"{record.name}.AT2": at2_text(record, p) for record, p in suite})
    return files


def write(folder: Path = FOLDER) -> None:
    folder.mkdir(parents=True, exist_ok=True)
    for name, text in suite_files().items():
        (folder / name).write_text(text)


if __name__ == "__main__":
    write(Path(sys.argv[1]) if len(sys.argv) > 1 else FOLDER)

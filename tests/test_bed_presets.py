"""Every bed preset at both ends of its range gives an answer (issue 47).

The shipped default column (studies/default.toml: its mesh, collars, contact, replicas and toe
refinements) on each bed preset of colonna.fem.bed (mortar, lead, stone), its stiffness at
each end of the preset's range, as built (elastic collars, no load on the capital) and with
plastic collars and the 40 kN top load of studies/default-top-load.toml: twelve studies, each
run as ``colonna study`` runs it (studies.driver.run_study_file, one worker) to its report.

Only the ground motion and the run are shortened: a pulse of Omega / p = 10 (0.31 s, in place
of the default's 1 s) over 0.3 s (in place of the pulse's end + 1.5 s). The column uplifts at
the start of the pulse (its phase is set so) and presses its toe into the bed, so that a toe
answer is made in every study. The default mesh (0.0375 m) is kept. Measured on the 2-core
machine (shared): 34 to 102 s a study, 678 s the twelve; the plastic, loaded column on the
stiffest lead the longest (its contact sets a step of 1.7 us, against the mortar's 3.8 us).
About 25-45 s of each study does not shorten with the run: the toe stress's refined windows,
the rigid spectrum and the report. The stone range's stiff end is the mortar's (1e12 N/m^3):
those two studies are the same column on the same bed.

Each study must finish with its report: its FEM replicas reliable (no unreliable reason, every
energy balance within its limit), on the bed asked for (the summary's stiffness), and the
stiffer end of each preset presses the toe harder than the softer end (the resolved peak toe
pressure of the unperturbed run; measured, the stiff end's is 1.03-1.1 times the soft end's on
lead, 1.06-1.3 on mortar, 2.0-2.7 on stone, the plastic loaded column's the nearer)."""

import json
import tomllib
from pathlib import Path

import pytest

from colonna.fem.bed import BED_PRESETS
from colonna.fem.solver import unreliable_reason
from colonna.studies.executor import RunOptions

STUDIES = Path(__file__).parents[1] / "studies"
OMEGA_RATIO = 10.0  # a short pulse: (2 pi - asin(1/3)) / Omega = 0.31 s on the default column
DURATION = 0.3  # s
TOP_LOAD = 40e3  # N: studies/default-top-load.toml's

VARIANTS = {"as built": False, "plastic collars, top load": True}
CASES = [
    pytest.param(preset, end, variant, id=f"{preset}-{end}-{variant.replace(', ', '+')}")
    for preset in BED_PRESETS
    for variant in VARIANTS
    for end in ("low", "high")
]

_answers: dict[tuple[str, str, str], dict] = {}  # (preset, end, variant): its summary


def _value(value) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return json.dumps(value)
    if isinstance(value, list):
        return "[" + ", ".join(_value(v) for v in value) + "]"
    return repr(value)


def _toml(data: dict) -> str:
    """A study file of tables and arrays of tables of plain values (no TOML writer in the
    environment: tomli_w is not installed)."""
    lines = []
    for name, table in data.items():
        for row in table if isinstance(table, list) else [table]:
            lines.append(f"[[{name}]]" if isinstance(table, list) else f"[{name}]")
            lines += [f"{key} = {_value(value)}" for key, value in row.items()]
    return "\n".join(lines) + "\n"


def study_file(folder: Path, preset: str, end: str, variant: str) -> Path:
    """The default study on the preset's bed at the range's ``end``, as the variant asks."""
    data = tomllib.loads((STUDIES / "default.toml").read_text())
    low, high = BED_PRESETS[preset].stiffness_range
    data["study"]["name"] = f"default on {preset} ({end} end), {variant}"
    data["base"] = {"bed": preset, "stiffness": low if end == "low" else high}
    data["ground"]["omega_ratio"] = OMEGA_RATIO
    data["run"]["duration"] = DURATION
    if VARIANTS[variant]:
        data["column"]["top_load"] = TOP_LOAD
        for collar in data["collar"]:
            collar["plastic"] = True
    path = folder / f"{preset}-{end}.toml"
    path.write_text(_toml(data))
    return path


def answer(folder: Path, preset: str, end: str, variant: str) -> dict:
    """The study's summary, its report and its FEM replicas' summaries checked (once a
    session)."""
    from colonna.studies.driver import run_study_file

    key = (preset, end, variant)
    if key in _answers:
        return _answers[key]
    out = folder / "out"
    summary = run_study_file(
        study_file(folder, preset, end, variant),
        out,
        run_options=RunOptions(workers=1, progress=False),
    )
    assert (out / "index.html").stat().st_size > 0
    replicas = json.loads((out / "cases" / "fem" / "result.json").read_text())["replica_summaries"]
    assert unreliable_reason(replicas) is None
    for replica in replicas:
        assert replica["energy_reliable"]
        assert replica["energy_error_max"] < replica["energy_error_limit"]
    k = BED_PRESETS[preset].stiffness_range[end == "high"]
    assert summary["bed"]["stiffness"] == k
    assert summary["fem"]["bed_stiffness"] == pytest.approx(k, rel=1e-12)
    assert summary["fem"]["top_load"] == (TOP_LOAD if VARIANTS[variant] else 0.0)
    assert summary["fem"]["toe_pressure_max"] > 0.0
    _answers[key] = summary
    return summary


@pytest.mark.slow
@pytest.mark.parametrize("preset, end, variant", CASES)
def test_the_default_column_on_every_bed_preset_gives_an_answer(
    tmp_path_factory, preset, end, variant
):
    folder = tmp_path_factory.mktemp(f"{preset}-{end}")
    summary = answer(folder, preset, end, variant)
    if end == "high":
        softer = answer(tmp_path_factory.mktemp(f"{preset}-low"), preset, "low", variant)
        assert summary["fem"]["toe_pressure_max"] >= softer["fem"]["toe_pressure_max"]

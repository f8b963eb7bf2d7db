"""Numbers the documentation quotes from runs of the shipped studies, never retyped.

Running a study takes minutes, too long for every documentation build, so the numbers come from
a record of one run per study, committed under ``docs/runs/``: ``default.json`` (``colonna study
default``, ``make demo``) and ``free-rocking.json``. ``make docs-numbers`` runs the studies and
writes them (``python docs/run_numbers.py STUDY OUT`` for one); a record holds

* the SHA-256 of the study file the run read (``inputs.json``'s ``study_sha256``) and the colonna
  version that ran it, when the run finished, its wall time and the git commit recorded with it;
* each quoted number (``QUOTED[study]``: a path into the run's files) as the run wrote it, in SI.

``docs/conf.py`` loads each with :func:`load_current`, which refuses a record made from another
study file or by another colonna version: the build stops and says to run ``make
docs-numbers``. The pages quote the numbers through MyST substitutions (``{{ default_fem_util
}}``, ``{{ free_rocking_fem_ratio }}``) and ``generated/runs.md`` lists them all with where each
comes from. What a record cannot know is a change of the solvers that keeps the study file and
the version: the page states the commit, so that a reader can tell.
"""

from __future__ import annotations

import datetime
import hashlib
import json
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
RUNS = HERE / "runs"

# study -> name -> (file of the run, path of keys in it, what it is); SI values, as the run wrote
# them. A path into a CSV history is (column, time): the column's absolute value at that time.
QUOTED: dict[str, dict[str, tuple[str, tuple, str]]] = {"default": {}, "free-rocking": {}}
STUDIES = tuple(QUOTED)


def _quote(study: str, name: str, file: str, path: str, about: str) -> None:
    keys = tuple(int(k) if k.isdigit() else k for k in path.split("."))
    if file.endswith(".csv"):
        column, time = path.split("@")
        keys = (column, float(time))
    QUOTED[study][name] = (file, keys, about)


_SUMMARY = (
    ("fem_overturned_replicas", "fem.overturned_replicas", "FEM replicas that overturn"),
    ("fem_replicas", "verdict_criteria.replicas", "FEM replicas"),
    ("fem_end_time", "fem.bands.t_end.median", "FEM end (overturning) time, median (s)"),
    ("fem_end_time_min", "fem.bands.t_end.min", "FEM end time, earliest replica (s)"),
    ("fem_end_time_max", "fem.bands.t_end.max", "FEM end time, latest replica (s)"),
    ("mb_end_time", "rigid_multibody.overturn_time", "multibody overturning time (s)"),
    ("sdof_mode", "rigid.mode", "the paper's SDOF half-block model: outcome"),
    ("monolith_mode", "rigid_monolith.mode", "whole column as one rigid block: outcome"),
    ("fem_theta", "fem.bands.max_abs_theta_left.median", "FEM peak rotation, median (rad)"),
    ("fem_theta_min", "fem.bands.max_abs_theta_left.min", "FEM peak rotation, lowest (rad)"),
    ("fem_theta_max", "fem.bands.max_abs_theta_left.max", "FEM peak rotation, highest (rad)"),
    ("mb_theta", "rigid_multibody.max_abs_theta_left", "multibody peak rotation (rad)"),
    ("theta_ratio", "theta_peak_ratio_fem_over_multibody", "peak rotation FEM / multibody"),
    ("fem_util", "fem.bands.collar_max_utilisation.median", "FEM collar utilisation, median"),
    ("fem_util_min", "fem.bands.collar_max_utilisation.min", "FEM collar utilisation, lowest"),
    ("fem_util_max", "fem.bands.collar_max_utilisation.max", "FEM collar utilisation, highest"),
    ("mb_util", "rigid_multibody.collar_max_utilisation", "multibody collar utilisation"),
    ("fem_slip", "fem.bands.crack_slip_max.median", "FEM largest crack slip, median (m)"),
    ("fem_slip_min", "fem.bands.crack_slip_max.min", "FEM largest crack slip, lowest (m)"),
    ("fem_slip_max", "fem.bands.crack_slip_max.max", "FEM largest crack slip, highest (m)"),
    ("mb_slip", "rigid_multibody.max_abs_crack_slip", "multibody largest crack slip (m)"),
    (
        "history_error",
        "verdict_criteria.history_error_to_first_impact",
        "history error to the first impact, median over the replicas",
    ),
    (
        "history_error_min",
        "verdict_criteria.bands.history_error.min",
        "history error to the first impact, lowest replica",
    ),
    (
        "history_error_max",
        "verdict_criteria.bands.history_error.max",
        "history error to the first impact, highest replica",
    ),
    (
        "history_error_fine",
        "verdict_criteria.history_error_fine_step",
        "history error to the first impact, multibody at a quarter of its step",
    ),
    ("history_tolerance", "verdict_criteria.tolerances.history", "history error tolerance"),
    ("rigid_assumption_ok", "verdict.rigid_assumption_ok", "is the rigid assumption good enough?"),
    ("collars_yield", "verdict.collars_yield", "do the collars yield?"),
    ("toe_crushes", "verdict.toe_crushes", "does the toe crush?"),
    ("toe_ratio", "toe_stress.ratio", "toe stress / f_c, refined at the toe (quoted)"),
    ("toe_ratio_low", "toe_stress.band_ratio.min", "toe stress / f_c, band, low end"),
    ("toe_ratio_high", "toe_stress.band_ratio.max", "toe stress / f_c, band, high end"),
    ("toe_unrefined", "toe_stress.unrefined_ratio", "toe stress / f_c on the study mesh"),
    ("toe_refined_2", "toe_stress.ratios.1", "toe stress / f_c, toe elements split 2 times"),
    ("toe_refined_4", "toe_stress.ratios.2", "toe stress / f_c, toe elements split 4 times"),
    ("toe_refined_8", "toe_stress.ratios.3", "toe stress / f_c, toe elements split 8 times"),
    ("toe_richardson", "toe_stress.richardson_ratio", "toe stress / f_c, Richardson estimate"),
    ("toe_order", "toe_stress.observed_order", "toe stress, observed order of the refinement"),
    ("toe_uncertainty", "toe_stress.uncertainty", "toe stress, relative uncertainty"),
    ("toe_replica_spread", "toe_stress.replica_spread", "toe stress, replicas' relative spread"),
    ("toe_mesh", "toe_stress.mesh_uncertainty", "toe stress, relative mesh uncertainty"),
    ("toe_handover", "toe_stress.handover_error", "toe window's hand-over error"),
    ("fem_energy_min", "fem.bands.energy_error_max.min", "FEM energy error, lowest replica"),
    ("fem_energy_max", "fem.bands.energy_error_max.max", "FEM energy error, highest replica"),
)
for _name, _path, _about in _SUMMARY:
    _quote("default", _name, "summary.json", _path, _about)
_FINE = "cases/multibody-fine/result.json"
_quote(
    "default",
    "mb_fine_util",
    _FINE,
    "collar_max_utilisation",
    "multibody at 1/16 step: utilisation",
)
_quote(
    "default", "mb_fine_slip", _FINE, "max_abs_crack_slip", "multibody at 1/16 step: crack slip (m)"
)
for _time in ("0.1", "0.3", "0.5"):
    _t = _time.replace(".", "")
    _quote(
        "default",
        f"fem_theta_{_t}",
        "cases/fem/history.csv",
        f"theta_left@{_time}",
        f"FEM rotation at t = {_time} s, plain run (rad)",
    )
    _quote(
        "default",
        f"mb_theta_{_t}",
        "cases/multibody/history.csv",
        f"theta_left@{_time}",
        f"multibody rotation at t = {_time} s (rad)",
    )

for _name, _path, _about in (
    ("alpha", "alpha", "alpha of the whole column (rad)"),
    ("tilt_1", "tilts.0.tilt_fraction", "first release tilt, fraction of alpha"),
    ("tilt_2", "tilts.1.tilt_fraction", "second release tilt, fraction of alpha"),
    ("housner", "restitution_housner", "Housner's ratio of the whole column"),
    ("mb_ratio", "multibody_ratio", "multibody velocity ratio, first impact"),
    ("mb_half_impulse", "tilts.0.multibody.impulse_ratios.0", "multibody: a half's impulse ratio"),
    ("fem_ratio", "fem_ratio_study_stone", "FEM velocity ratio, first impact, median"),
    ("fem_ratio_min", "fem_ratio_study_stone_band.min", "FEM velocity ratio, lowest replica"),
    ("fem_ratio_max", "fem_ratio_study_stone_band.max", "FEM velocity ratio, highest replica"),
    ("damping", "damping", "the study's contact damping (of critical)"),
    ("damping_1", "damping_variants.0.damping", "first damping variant (of critical)"),
    ("fem_ratio_damping_1", "damping_variants.0.ratio_first", "FEM ratio, first damping variant"),
    ("damping_2", "damping_variants.1.damping", "second damping variant (of critical)"),
    ("fem_ratio_damping_2", "damping_variants.1.ratio_first", "FEM ratio, second damping variant"),
    ("mesh_size", "mesh_size", "the study's mesh size (m)"),
    ("mesh_size_1", "mesh_variants.0.mesh_size", "mesh variant's size (m)"),
    ("fem_ratio_mesh_1", "mesh_variants.0.ratio_first", "FEM ratio on the mesh variant"),
):
    _quote("free-rocking", _name, "summary.json", _path, _about)


def _csv_value(path: Path, column: str, time: float) -> float:
    """|column| of a history CSV (header row, first column t) interpolated at ``time``."""
    import numpy as np

    header = path.open().readline().strip().split(",")
    data = np.loadtxt(path, delimiter=",", skiprows=1, usecols=(0, header.index(column)))
    return float(abs(np.interp(time, data[:, 0], data[:, 1])))


def _get(data, path: tuple):
    for key in path:
        data = data[key]
    return data


def record_of(study: str, run: Path) -> dict:
    """The record of the run of ``study`` in folder ``run`` (``colonna study STUDY --out run``)."""
    inputs = json.loads((run / "inputs.json").read_text())
    files: dict[str, dict] = {}
    values = {}
    for name, (file, path, _about) in QUOTED[study].items():
        try:
            if file.endswith(".csv"):
                values[name] = _csv_value(run / file, *path)
                continue
            if file not in files:
                files[file] = json.loads((run / file).read_text())
            values[name] = _get(files[file], path)
        except (KeyError, IndexError, TypeError, ValueError) as missing:
            raise SystemExit(f"{run / file}: no {'.'.join(map(str, path))} ({missing})") from None
    commit = _commit()
    files.setdefault("summary.json", json.loads((run / "summary.json").read_text()))
    return {
        "study": study,
        "study_sha256": inputs["study_sha256"],
        "colonna_version": inputs["colonna_version"],
        "recorded": datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC"),
        "commit": commit or "unknown",
        "run_wall_seconds": files["summary.json"].get("wall_seconds"),
        "run_finished": datetime.datetime.fromtimestamp(
            (run / "summary.json").stat().st_mtime, datetime.UTC
        ).strftime("%Y-%m-%d %H:%M UTC"),
        "values": values,
    }


def record_path(study: str) -> Path:
    return RUNS / f"{study}.json"


def study_sha256(study: str) -> str:
    return hashlib.sha256((ROOT / "studies" / f"{study}.toml").read_bytes()).hexdigest()


def load_current(study: str, path: Path | None = None) -> dict:
    """The record of ``study`` (at ``path``, default docs/runs/STUDY.json), refused (SystemExit)
    where it was made from another study file or by another colonna version than this one."""
    import colonna

    path = Path(path or record_path(study))
    record = json.loads(path.read_text())
    rerun = f"run `make docs-numbers` (or python docs/run_numbers.py {study} OUT after a run)"
    if record["study_sha256"] != study_sha256(study):
        raise SystemExit(f"{path}: made from another studies/{study}.toml: {rerun}")
    if record["colonna_version"] != colonna.__version__:
        raise SystemExit(
            f"{path}: made by colonna {record['colonna_version']}, this is "
            f"{colonna.__version__}: {rerun}"
        )
    if set(record["values"]) != set(QUOTED[study]):
        raise SystemExit(f"{path}: holds other numbers than run_numbers.py quotes: {rerun}")
    return record


def _commit() -> str:
    """The commit checked out, '-dirty' where files other than these records (which make
    docs-numbers writes one after the other) have changes not yet committed."""

    def git(*args: str) -> str:
        done = subprocess.run(["git", "-C", str(ROOT), *args], capture_output=True, text=True)
        return done.stdout.strip()

    changed = git("status", "--porcelain", "--untracked-files=no", "--", ".", ":!docs/runs")
    return git("rev-parse", "--short", "HEAD") + ("-dirty" if changed else "")


def _band(v: dict, name: str, digits: str, scale: float = 1.0) -> str:
    return f"{v[name + '_min'] * scale:{digits}} to {v[name + '_max'] * scale:{digits}}"


def _percent(x: float) -> str:
    return f"{100 * x:.0f} %"


def _toe_convergence(v: dict) -> str:
    """How the refined toe peaks behave, in words, and which value is quoted."""
    if v["toe_order"] is not None and v["toe_ratio"] == v["toe_richardson"]:
        return (
            f"converging monotonically (observed order {v['toe_order']:.1f}): the quoted value "
            "is the Richardson estimate"
        )
    return "without converging monotonically: the quoted value is the largest refined one"


def _default_substitutions(record: dict) -> dict[str, str]:
    """The default study's quotes, formatted for reading."""
    v = record["values"]
    mm = 1e3
    out = {
        "fem_overturned": f"{v['fem_overturned_replicas']} of {v['fem_replicas']}",
        "fem_end_time": f"{v['fem_end_time']:.3f} s",
        "fem_end_time_band": _band(v, "fem_end_time", ".3f") + " s",
        "mb_end_time": f"{v['mb_end_time']:.3f} s",
        "sdof_mode": str(v["sdof_mode"]),
        "monolith_mode": str(v["monolith_mode"]),
        "fem_theta": f"{v['fem_theta']:.4f} rad",
        "fem_theta_band": _band(v, "fem_theta", ".4f") + " rad",
        "mb_theta": f"{v['mb_theta']:.4f} rad",
        "theta_ratio": f"{v['theta_ratio']:.3f}",
        "fem_util": f"{v['fem_util']:.3f}",
        "fem_util_band": _band(v, "fem_util", ".3f"),
        "mb_util": f"{v['mb_util']:.3f}",
        "mb_fine_util": f"{v['mb_fine_util']:.3f}",
        "fem_slip": f"{v['fem_slip'] * mm:.3f} mm",
        "fem_slip_band": _band(v, "fem_slip", ".3f", mm) + " mm",
        "mb_slip": f"{v['mb_slip'] * mm:.3f} mm",
        "mb_fine_slip": f"{v['mb_fine_slip'] * mm:.3f} mm",
        "history_error": _percent(v["history_error"]),
        "history_error_band": _band(v, "history_error", ".3f"),
        "history_error_fine": _percent(v["history_error_fine"]),
        "history_tolerance": _percent(v["history_tolerance"]),
        "fem_theta_early": ", ".join(f"{v[f'fem_theta_{t}'] * 1e3:.2f}e-3" for t in ("01", "03"))
        + f" and {v['fem_theta_05'] * 1e3:.2f}e-3 rad",
        "mb_theta_early": ", ".join(f"{v[f'mb_theta_{t}'] * 1e3:.2f}e-3" for t in ("01", "03"))
        + f" and {v['mb_theta_05'] * 1e3:.2f}e-3 rad",
        "rigid_assumption_ok": str(v["rigid_assumption_ok"]),
        "collars_yield": str(v["collars_yield"]),
        "toe_crushes": str(v["toe_crushes"]),
        "toe_ratio": f"{v['toe_ratio']:.3f} f_c",
        "toe_band": f"{v['toe_ratio_low']:.3f} to {v['toe_ratio_high']:.3f} f_c",
        "toe_unrefined": f"{v['toe_unrefined']:.3f} f_c",
        "toe_refined": f"{v['toe_refined_2']:.3f}, {v['toe_refined_4']:.3f} and "
        f"{v['toe_refined_8']:.3f} f_c",
        "toe_convergence": _toe_convergence(v),
        "toe_uncertainty": _percent(v["toe_uncertainty"]),
        "toe_replica_spread": _percent(v["toe_replica_spread"]),
        "toe_mesh": _percent(v["toe_mesh"]),
        "toe_handover": f"{v['toe_handover']:.1e}",
        "toe_factor": f"{int(1.0 / v['toe_ratio_high'])}",
        "fem_energy_band": f"{v['fem_energy_min']:.1e} to {v['fem_energy_max']:.1e}",
        "recorded": record["recorded"],
        "commit": record["commit"],
        "version": record["colonna_version"],
    }
    return out


def _free_rocking_substitutions(record: dict) -> dict[str, str]:
    """The free-rocking study's quotes, formatted for reading."""
    v = record["values"]
    return {
        "alpha": f"{v['alpha']:.3f}",
        "tilts": f"{v['tilt_1']:g} and {v['tilt_2']:g}",
        "housner": f"{v['housner']:.3f}",
        "mb_ratio": f"{v['mb_ratio']:.3f}",
        "mb_half_impulse": f"{v['mb_half_impulse']:.3f}",
        "fem_ratio": f"{v['fem_ratio']:.3f}",
        "fem_ratio_band": f"{v['fem_ratio_min']:.3f} to {v['fem_ratio_max']:.3f}",
        "damping": f"{v['damping']:g}",
        "damping_1": f"{v['damping_1']:g}",
        "fem_ratio_damping_1": f"{v['fem_ratio_damping_1']:.3f}",
        "damping_2": f"{v['damping_2']:g}",
        "fem_ratio_damping_2": f"{v['fem_ratio_damping_2']:.3f}",
        "mesh_ratio": f"{v['mesh_size_1'] / v['mesh_size']:g}",
        "fem_ratio_mesh_1": f"{v['fem_ratio_mesh_1']:.3f}",
        "wall_minutes": f"{record['run_wall_seconds'] / 60:.0f}",
    }


_SUBSTITUTIONS = {"default": _default_substitutions, "free-rocking": _free_rocking_substitutions}


def substitutions(records: dict[str, dict]) -> dict[str, str]:
    """The MyST substitutions the pages quote, ``<study>_<name>`` (``default_fem_util``,
    ``free_rocking_fem_ratio``), from each study's record."""
    out = {}
    for study, record in records.items():
        prefix = study.replace("-", "_")
        out |= {f"{prefix}_{name}": text for name, text in _SUBSTITUTIONS[study](record).items()}
    return out


ABOUT = {
    "default": "`colonna study default`, `make demo`: a cracked marble column 4 m tall and "
    "0.45 m across, three 8 x 60 mm steel collars, a sine pulse of three times a half's uplift "
    "acceleration at Omega / p = 3",
    "free-rocking": "`colonna study free-rocking`: the default column released from rest at "
    "two tilts, the FEM with other contact dampings and a coarser mesh",
}


def page(records: dict[str, dict]) -> str:
    """``generated/runs.md``: every quoted number, its source and its run."""
    subs = substitutions(records)
    lines = [
        "# Numbers quoted from runs",
        "",
        "The numbers these pages quote from the shipped studies are inserted when the "
        "documentation is built from the record of one run of each, `docs/runs/STUDY.json`, "
        "not typed into the text. The build refuses a record made from another study file or "
        "by another colonna version (`make docs-numbers` runs the studies and makes new ones).",
        "",
    ]
    for study, record in records.items():
        lines += [
            f"## {study}",
            "",
            f"{ABOUT[study]}. Run by colonna {record['colonna_version']} in "
            f"{record['run_wall_seconds']:.0f} s, finished {record['run_finished']} (its "
            f"summary.json written); recorded {record['recorded']} with commit "
            f"`{record['commit']}` checked out (`-dirty`: with changes not yet committed); "
            f"study file SHA-256 `{record['study_sha256']}`.",
            "",
            "| quantity | value | from the run's file |",
            "|---|---|---|",
        ]
        for name, (file, path, about) in QUOTED[study].items():
            value = record["values"][name]
            shown = f"{value:.6g}" if isinstance(value, float) else str(value)
            lines.append(f"| {about} | {shown} | `{file}`: `{'.'.join(map(str, path))}` |")
        lines.append("")
    lines += [
        "## As the pages quote them",
        "",
        "| substitution (for authors) | quoted as |",
        "|---|---|",
        *[f"| `{name}` | {text} |" for name, text in subs.items()],
        "",
    ]
    return "\n".join(lines)


def main(argv: list[str]) -> int:
    if len(argv) != 2 or argv[0] not in QUOTED:
        print(f"usage: python docs/run_numbers.py STUDY OUT  (STUDY one of {', '.join(QUOTED)};")
        print("       OUT the --out folder of its run)")
        return 2
    study, run = argv[0], Path(argv[1])
    record = record_of(study, run)
    if record["study_sha256"] != study_sha256(study):
        print(f"{run} was run from another studies/{study}.toml: run the study again")
        return 2
    RUNS.mkdir(exist_ok=True)
    record_path(study).write_text(json.dumps(record, indent=1) + "\n")
    print(f"wrote {record_path(study)} from {run} ({len(record['values'])} numbers)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

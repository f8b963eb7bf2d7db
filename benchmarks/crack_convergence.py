"""The uncollared default column under the default pulse along the crack contact's convergence
path (issue 38): penalty up, step down, the contact damping and friction filter varied, and the
exact (Lagrange multiplier) crack contact, on two meshes; the rigid multibody model alongside.

Per run: the first peak of |theta| (the larger of the halves), the crack slip at it, the
crack's mean normal force and its friction work up to it, the step and the cost per step.
Prints a markdown table (docs/validation.md quotes it) and writes the rows as JSON.

With --replicas: the exact crack contact on the study's bed, 8 round-off replicas per row
(fem.solver.run_ensemble), along the step and the mesh and over the base's free settings
(contact damping 0-10 %, friction filter 0-2 ms) and the Gauss-Seidel tolerance (1e-9 to 1e-12
m per m): the median first peak, the replicas' band and the cost per step and replica.

Run: nice python benchmarks/crack_convergence.py [out.json] [--sizes=0.225,0.1125] [--replicas]
"""

from __future__ import annotations

import dataclasses
import json
import sys
import time
from pathlib import Path

import numpy as np

from colonna.core.motion import Motion
from colonna.fem import solver
from colonna.fem.model import build_model
from colonna.fem.settings import FemSettings
from colonna.fem.solver import run, run_ensemble
from colonna.meshes import column_mesh
from colonna.rigid.multibody import MultibodyContact, rock_multibody
from colonna.studies.study import load

STUDY = Path(__file__).resolve().parents[1] / "studies" / "default.toml"
DURATION = 1.0  # s: past the first peak of every setting (0.70-0.78 s)

# (label, enforcement, penalty factor, damping, friction filter (s), safety)
SETTINGS = [
    ("exact (default)", "lagrange", 1.0, 0.05, 1e-3, 0.9),
    ("exact, step / 2", "lagrange", 1.0, 0.05, 1e-3, 0.45),
    ("exact, step / 4", "lagrange", 1.0, 0.05, 1e-3, 0.225),
    ("penalty x 0.25", "penalty", 0.25, 0.05, 1e-3, 0.9),
    ("penalty x 1 (its own defaults)", "penalty", 1.0, 0.05, 1e-3, 0.9),
    ("penalty x 1, step / 4", "penalty", 1.0, 0.05, 1e-3, 0.225),
    ("penalty x 1, damping 0", "penalty", 1.0, 0.0, 1e-3, 0.9),
    ("penalty x 1, damping 0.1", "penalty", 1.0, 0.1, 1e-3, 0.9),
    ("penalty x 1, filter 0", "penalty", 1.0, 0.05, 0.0, 0.9),
    ("penalty x 4", "penalty", 4.0, 0.05, 1e-3, 0.9),
    ("penalty x 4, step / 4", "penalty", 4.0, 0.05, 1e-3, 0.225),
    ("penalty x 4, damping 0", "penalty", 4.0, 0.0, 1e-3, 0.9),
    ("penalty x 4, damping 0.1", "penalty", 4.0, 0.1, 1e-3, 0.9),
    ("penalty x 4, filter 0", "penalty", 4.0, 0.05, 0.0, 0.9),
    ("penalty x 16", "penalty", 16.0, 0.05, 1e-3, 0.9),
    ("penalty x 64", "penalty", 64.0, 0.05, 1e-3, 0.9),
    ("penalty x 16, damping 0, filter 0", "penalty", 16.0, 0.0, 0.0, 0.9),
]


def first_peak(theta: np.ndarray) -> int:
    """Index of the first local maximum of |theta| above 1 mrad (the last sample if none)."""
    for k in range(1, theta.size - 1):
        if theta[k] > 1e-3 and theta[k] >= theta[k - 1] and theta[k] > theta[k + 1]:
            return k
    return theta.size - 1


def fem_row(study, size, label, enforcement, factor, damping, friction_filter, safety) -> dict:
    mesh = column_mesh(study.width, study.height, size, cracked=True, grading=study.grading)
    contact = dataclasses.replace(
        study.contact,
        penalty_factor=factor,
        damping=damping,
        friction_filter=friction_filter,
        enforcement=enforcement,
    )
    model = build_model(mesh, study.stone, study.thickness, (), contact)
    r = run(
        model,
        Motion(study.ground, DURATION),
        FemSettings(output_interval=1e-3, safety=safety, progress=False),
    )
    h, s = r.history, r.summary
    theta = np.maximum(np.abs(h["theta_left"]), np.abs(h["theta_right"]))
    k = first_peak(theta)
    return {
        "model": "fem",
        "label": label,
        "mesh_size": size,
        "dofs": s["dofs"],
        "enforcement": enforcement,
        "penalty_factor": factor,
        "damping": damping,
        "friction_filter": friction_filter,
        "safety": safety,
        "peak": float(theta[k]),
        "t_peak": float(h["t"][k]),
        "slip": float(h["crack_slip_max"][k]),
        "crack_force_mean": float(np.mean(h["crack_normal_force"][: k + 1])),
        "crack_friction_work": float(h["energy_friction_crack"][k]),
        "dt": s["dt"],
        "us_per_step": 1e6 * s["wall_seconds"] / max(s["steps"], 1),
        "energy_error_max": s["energy_error_max"],
        "status": s["status"],
    }


def rigid_rows(study) -> list[dict]:
    rows = []
    for crack_friction in (study.contact.friction, 0.0):
        r = rock_multibody(
            study.rocking_block,
            Motion(study.ground, duration=DURATION),
            contact=MultibodyContact(
                cracked=True, friction=study.contact.friction, crack_friction=crack_friction
            ),
        )
        theta = np.abs(r.theta).max(axis=1)
        k = first_peak(theta)
        rows.append(
            {
                "model": "rigid",
                "label": f"rigid multibody, crack friction {crack_friction:g}",
                "peak": float(theta[k]),
                "t_peak": float(r.time[k]),
                "slip": float(abs(r.crack_slip[k])),
                "crack_force_mean": float(np.mean(r.crack_normal_force[: k + 1])),
            }
        )
    return rows


def table(rows: list[dict]) -> str:
    exact = {r["mesh_size"]: r["peak"] for r in rows if r["label"] == "exact (default)"}
    lines = [
        "| mesh (m) | crack contact | first peak (mrad) | / exact | slip at it (mm) "
        "| crack force, mean (kN) | dt (us) | cost per step (us) |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        if r["model"] == "rigid":
            lines.append(
                f"| - | {r['label']} | {1e3 * r['peak']:.2f} | - | {1e3 * r['slip']:.2f} "
                f"| {1e-3 * r['crack_force_mean']:.2f} | - | - |"
            )
            continue
        lines.append(
            f"| {r['mesh_size']:g} | {r['label']} | {1e3 * r['peak']:.2f} "
            f"| {r['peak'] / exact[r['mesh_size']]:.3f} | {1e3 * r['slip']:.2f} "
            f"| {1e-3 * r['crack_force_mean']:.2f} | {1e6 * r['dt']:.2f} "
            f"| {r['us_per_step']:.1f} |"
        )
    return "\n".join(lines)


# replica medians (--replicas): (label, mesh size (m), safety, Gauss-Seidel tolerance (m per
# m), contact settings changed from the study's)
REPLICA_SETTINGS = [
    ("default", 0.225, 0.9, 1e-9, {}),
    ("step / 2", 0.225, 0.45, 1e-9, {}),
    ("step / 4", 0.225, 0.225, 1e-9, {}),
    ("step / 8", 0.225, 0.1125, 1e-9, {}),
    ("base damping 0", 0.225, 0.9, 1e-9, {"damping": 0.0}),
    ("base damping 0.1", 0.225, 0.9, 1e-9, {"damping": 0.1}),
    ("friction filter 0", 0.225, 0.9, 1e-9, {"friction_filter": 0.0}),
    ("friction filter 2 ms", 0.225, 0.9, 1e-9, {"friction_filter": 2e-3}),
    ("tolerance 1e-11", 0.225, 0.9, 1e-11, {}),
    ("tolerance 1e-12", 0.225, 0.9, 1e-12, {}),
    ("default", 0.1125, 0.9, 1e-9, {}),
    ("step / 2", 0.1125, 0.45, 1e-9, {}),
    ("step / 4", 0.1125, 0.225, 1e-9, {}),
    ("base damping 0", 0.1125, 0.9, 1e-9, {"damping": 0.0}),
    ("base damping 0.01", 0.1125, 0.9, 1e-9, {"damping": 0.01}),
    ("base damping 0.1", 0.1125, 0.9, 1e-9, {"damping": 0.1}),
    ("friction filter 0", 0.1125, 0.9, 1e-9, {"friction_filter": 0.0}),
    ("friction filter 2 ms", 0.1125, 0.9, 1e-9, {"friction_filter": 2e-3}),
    ("tolerance 1e-11", 0.1125, 0.9, 1e-11, {}),
    ("tolerance 1e-12", 0.1125, 0.9, 1e-12, {}),
    ("default", 0.05625, 0.9, 1e-9, {}),
    ("step / 2", 0.05625, 0.45, 1e-9, {}),
    ("base damping 0", 0.05625, 0.9, 1e-9, {"damping": 0.0}),
    ("base damping 0.1", 0.05625, 0.9, 1e-9, {"damping": 0.1}),
    ("friction filter 0", 0.05625, 0.9, 1e-9, {"friction_filter": 0.0}),
    ("friction filter 2 ms", 0.05625, 0.9, 1e-9, {"friction_filter": 2e-3}),
    ("default", 0.0375, 0.9, 1e-9, {}),
    ("default", 0.028125, 0.9, 1e-9, {}),
]


def replica_row(study, label, size, safety, tolerance, contact, replicas=8) -> dict:
    """The median first peak over ``replicas`` round-off replicas of the exact crack contact
    on the study's bed, the replicas' band and the cost per step and replica."""
    solver.LAGRANGE_TOLERANCE = tolerance
    try:
        mesh = column_mesh(study.width, study.height, size, cracked=True, grading=study.grading)
        settings = dataclasses.replace(study.contact, enforcement="lagrange", **contact)
        model = build_model(mesh, study.stone, study.thickness, (), settings, bed=study.bed)
        clock = time.perf_counter()
        runs = run_ensemble(
            model,
            Motion(study.ground, 0.9),
            FemSettings(output_interval=1e-3, safety=safety, progress=False),
            replicas=replicas,
        )
        wall = time.perf_counter() - clock
    finally:
        solver.LAGRANGE_TOLERANCE = 1e-9
    peaks = []
    for r in runs:
        theta = np.maximum(np.abs(r.history["theta_left"]), np.abs(r.history["theta_right"]))
        peaks.append(float(theta[first_peak(theta)]))
    steps = runs[0].summary["steps"]
    return {
        "label": label,
        "mesh_size": size,
        "safety": safety,
        "tolerance": tolerance,
        "contact": contact,
        "peaks": peaks,
        "median": float(np.median(peaks)),
        "dt": runs[0].summary["dt"],
        "us_per_step": 1e6 * wall / (steps * replicas),
    }


def replica_table(rows: list[dict]) -> str:
    default = {r["mesh_size"]: r["median"] for r in rows if r["label"] == "default"}
    lines = [
        "| mesh (m) | setting | median first peak (mrad) | / default | replicas (mrad) "
        "| dt (us) | cost per step and replica (us) |",
        "|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        lines.append(
            f"| {r['mesh_size']:g} | {r['label']} | {1e3 * r['median']:.2f} "
            f"| {r['median'] / default[r['mesh_size']]:.3f} "
            f"| {1e3 * min(r['peaks']):.2f}-{1e3 * max(r['peaks']):.2f} | {1e6 * r['dt']:.2f} "
            f"| {r['us_per_step']:.1f} |"
        )
    return "\n".join(lines)


def main() -> None:
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    out = Path(args[0]) if args else Path("crack_convergence.json")
    sizes = [0.225, 0.1125]
    for a in sys.argv[1:]:
        if a.startswith("--sizes="):
            sizes = [float(v) for v in a.split("=", 1)[1].split(",")]
    study = load(STUDY).fem
    if "--replicas" in sys.argv[1:]:
        rows = []
        for label, size, safety, tolerance, contact in REPLICA_SETTINGS:
            if size in sizes or "--sizes=" not in " ".join(sys.argv):
                clock = time.perf_counter()
                rows.append(replica_row(study, label, size, safety, tolerance, contact))
                print(f"{size:g} {label}: {time.perf_counter() - clock:.1f} s", file=sys.stderr)
                out.write_text(json.dumps(rows, indent=1))
        print(replica_table(rows))
        return
    rows = rigid_rows(study)
    run(
        build_model(
            column_mesh(study.width, study.height, 0.225, cracked=True),
            study.stone,
            study.thickness,
            (),
            study.contact,
        ),
        Motion(study.ground, 1e-3),
        FemSettings(progress=False),
    )
    for size in sizes:
        for setting in SETTINGS:
            clock = time.perf_counter()
            rows.append(fem_row(study, size, *setting))
            print(f"{size:g} {setting[0]}: {time.perf_counter() - clock:.1f} s", file=sys.stderr)
            out.write_text(json.dumps(rows, indent=1))
    print(table(rows))


if __name__ == "__main__":
    main()

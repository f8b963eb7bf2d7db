"""Files of a FEM run: history.csv and base_pressure.csv streamed as it runs
(:class:`HistoryFiles`), summary.json, VTU snapshots and an XDMF time series for ParaView. The
one module of fem/ that writes a run's files: the solver hands it its rows and results."""

from __future__ import annotations

import json
import math
import os
from pathlib import Path
from typing import Any

import numpy as np

from ..meshes.io import write, write_time_series
from .assembly import element_stress


def local_displacement(model, u: np.ndarray) -> np.ndarray:
    """Displacement of each body in its own best-fit rotated frame (interleaved), from the
    global nodal displacement u (n_nodes, 2): the strain-producing part of the motion."""
    return _split_rigid_motion(model, u)[0].ravel()


def elastic_displacement(model, u: np.ndarray) -> np.ndarray:
    """The part of the nodal displacement u (n_nodes, 2) that each body's best-fit rigid motion
    (mass-weighted centroid and rotation) leaves: the elastic deformation, in the ground frame
    (n_nodes, 2), m. u minus it is the bodies' rigid motion."""
    local, angle = _split_rigid_motion(model, u)
    cs, sn = np.cos(angle), np.sin(angle)
    return np.column_stack(
        (cs * local[:, 0] - sn * local[:, 1], sn * local[:, 0] + cs * local[:, 1])
    )


def _split_rigid_motion(model, u):
    """(displacement in each body's rotated frame (n_nodes, 2), each node's body rotation)."""
    X = model.X.reshape(-1, 2)
    x = X + u
    m = model.node_mass
    out = np.zeros_like(x)
    angle = np.zeros(x.shape[0])
    for b in range(model.mesh.n_bodies):
        on = model.mesh.node_body == b
        P = X[on] - model.centroid_ref[b]
        c = (x[on] * m[on, None]).sum(axis=0) / m[on].sum()
        Q = x[on] - c
        phi = np.arctan2(
            (m[on] * (P[:, 0] * Q[:, 1] - P[:, 1] * Q[:, 0])).sum(),
            (m[on] * (P * Q).sum(axis=1)).sum(),
        )
        cs, sn = np.cos(phi), np.sin(phi)
        out[on, 0] = cs * Q[:, 0] + sn * Q[:, 1] - P[:, 0]
        out[on, 1] = -sn * Q[:, 0] + cs * Q[:, 1] - P[:, 1]
        angle[on] = phi
    return out, angle


def collar_end_marks(model) -> np.ndarray:
    """Per node: the number (from 1) of the collar attached there, 0 elsewhere (the two end
    nodes of each collar element)."""
    marks = np.zeros(model.X.size // 2, dtype=np.int64)
    for c, row in enumerate(model.collar_nodes):
        marks[[row[0], row[3]]] = c + 1
    return marks


def stress_fields(model, u: np.ndarray) -> dict:
    """Element stresses (Pa, body frame; compression negative), the minimum principal stress and
    its ratio to the stone strength f_c, as cell data."""
    s = element_stress(model.mesh, model.stone, local_displacement(model, u))
    centre = 0.5 * (s[0] + s[1])
    radius = np.hypot(0.5 * (s[0] - s[1]), s[2])
    minimum = centre - radius
    return {
        "sigma_xx": s[0],
        "sigma_yy": s[1],
        "sigma_xy": s[2],
        "sigma_min_principal": minimum,
        "compression_over_fc": -minimum / model.stone.fc,
    }


def _json_safe(value):
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, (np.floating, np.integer)):
        return value.item()
    return value


def write_summary(path: Path, summary: dict) -> None:
    tmp = path.with_name(path.name + ".part")
    tmp.write_text(json.dumps({k: _json_safe(v) for k, v in summary.items()}, indent=2) + "\n")
    os.replace(tmp, path)


def write_outputs(result, out: Path) -> None:
    out.mkdir(parents=True, exist_ok=True)
    mesh = result.model.mesh
    frames = result.displacement_frames
    theta = np.maximum(np.abs(result.history["theta_left"]), np.abs(result.history["theta_right"]))
    peak = int(np.argmax(theta))
    model = result.model
    collar_end = collar_end_marks(model)
    for name, k in (("initial", 0), ("peak_rotation", peak), ("final", len(frames) - 1)):
        t, u = frames[k]
        write(
            out / f"fields_{name}.vtu",
            mesh,
            point_data={
                "displacement": u,
                "elastic_displacement": elastic_displacement(model, u),
                "collar_end": collar_end,
            },
            cell_data=stress_fields(model, u),
        )
    step = max(1, len(frames) // 60)  # inline XML: keep the series a few MB
    chosen = frames[::step]
    write_time_series(
        out / "fields.xdmf", mesh, [t for t, _ in chosen], lambda k: {"displacement": chosen[k][1]}
    )
    write_summary(out / "summary.json", result.summary)


class HistoryFiles:
    """The files a run streams while it runs, one row per output time, so that an interrupted
    run keeps every row it computed: ``history.csv`` (the history's columns) and
    ``base_pressure.csv`` (the contact pressure at every base node, Pa). Rows go to
    ``*.part`` files, renamed to their names when the run ends (:meth:`close`); a run resumed
    from a checkpoint cuts them back to their sizes then and appends (:meth:`resume`)."""

    def __init__(self, out_dir, base_x=None, base_bodies=None, *, append: bool = False):
        out = Path(out_dir)
        out.mkdir(parents=True, exist_ok=True)
        self.history_path = out / "history.csv"
        self.pressure_path = out / "base_pressure.csv"
        history, pressure = self.part_files(out)
        self.history = open(history, "a" if append else "w")
        self.pressure = open(pressure, "a" if append else "w")
        if not append:
            self.pressure.write(
                "t," + ",".join(f"p_body{b}_x={v:.6f}" for b, v in zip(base_bodies, base_x)) + "\n"
            )

    @staticmethod
    def part_files(out_dir) -> tuple[Path, Path]:
        """The files a run streams its rows to while it runs."""
        return Path(out_dir) / "history.csv.part", Path(out_dir) / "base_pressure.csv.part"

    def write_header(self, header: list[str]) -> None:
        self.history.write(",".join(header) + "\n")

    def write_row(self, values) -> None:
        """One history row (numbers in the header's order), to the last digit."""
        np.savetxt(
            self.history, np.asarray(values, dtype=float)[None, :], fmt="%.17g", delimiter=","
        )
        self.history.flush()

    def write_pressure(self, t: float, pressure: np.ndarray) -> None:
        """The base nodes' contact pressures (Pa) at time t."""
        np.savetxt(
            self.pressure, np.concatenate(([t], pressure))[None, :], fmt="%.17g", delimiter=","
        )
        self.pressure.flush()

    def sizes(self) -> tuple[int, int] | None:
        """The .part files' sizes (bytes) now, for a checkpoint; None once closed."""
        if self.history.closed:
            return None
        self.history.flush()
        self.pressure.flush()
        return (os.fstat(self.history.fileno()).st_size, os.fstat(self.pressure.fileno()).st_size)

    def close(self) -> None:
        """The run has ended: the .part files become history.csv and base_pressure.csv."""
        self.history.close()
        Path(self.history.name).replace(self.history_path)
        self.pressure.close()
        Path(self.pressure.name).replace(self.pressure_path)

    @classmethod
    def resume(cls, out_dir, sizes: tuple[int, int]) -> HistoryFiles:
        """The files of a run resumed from a checkpoint: cut back to ``sizes`` and appended to."""
        for part, size in zip(cls.part_files(out_dir), sizes, strict=True):
            os.truncate(part, size)
        return cls(out_dir, append=True)

    @classmethod
    def can_resume(cls, out_dir, sizes: tuple[int, int] | None) -> bool:
        """Whether the files in ``out_dir`` hold at least ``sizes`` (bytes)."""
        if sizes is None:
            return False
        return all(
            part.is_file() and part.stat().st_size >= size
            for part, size in zip(cls.part_files(out_dir), sizes, strict=True)
        )


def write_run(result, out_dir, first: bool) -> None:
    """A finished run's files besides its history: the first run of a batch (replica 0) its
    field files and summary (:func:`write_outputs`), the others their summary.json."""
    if first:
        write_outputs(result, Path(out_dir))
    else:
        write_summary(Path(out_dir) / "summary.json", result.summary)


START_ARRAYS = ("displacement", "velocity")


def flat_start(start: dict) -> dict[str, Any]:
    """``start`` as one flat mapping of names to arrays: the contact's entries as
    ``contact.<key>`` (``contact.<key>.<pass>`` for one array per crack pass), the numbers and
    the toe's name as 0-d arrays (what :func:`write_start` saves and
    :func:`colonna.fem.toe_stress.start_digest` hashes; :func:`read_start` undoes it)."""
    flat: dict[str, Any] = {}
    for key, value in start.items():
        if key != "contact":
            flat[key] = np.asarray(value)
    for key, value in start["contact"].items():
        if isinstance(value, list):  # one array per crack pass
            for p, part in enumerate(value):
                flat[f"contact.{key}.{p}"] = np.asarray(part)
        else:
            flat[f"contact.{key}"] = np.asarray(value)
    return flat


def write_start(path, start: dict) -> None:
    """``start`` (:func:`colonna.fem.toe_stress.refinement_start`) as one ``.npz`` file (arrays
    bit for bit, the numbers as 0-d arrays, the toe's name as a string), written whole or not
    at all."""
    path = Path(path)
    partial = path.with_name(path.name + ".partial")
    with open(partial, "wb") as f:
        np.savez(f, **flat_start(start))
    os.replace(partial, path)


def read_start(path) -> dict:
    """The ``start`` dict that :func:`write_start` saved."""
    with np.load(path) as data:
        start: dict = {"contact": {}}
        for name in data.files:
            value = data[name]
            if not name.startswith("contact."):
                start[name] = value if name in START_ARRAYS else value.item()
                continue
            _, key, *part = name.split(".")
            if part:
                start["contact"].setdefault(key, {})[int(part[0])] = value
            else:
                start["contact"][key] = value
    for key, value in start["contact"].items():
        if isinstance(value, dict):
            start["contact"][key] = [value[p] for p in sorted(value)]
    return start

"""Files of a FEM run: summary.json, VTU snapshots and an XDMF time series for ParaView.
(history.csv is streamed by the solver while it runs.)"""

from __future__ import annotations

import json
import math
import os
from pathlib import Path

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

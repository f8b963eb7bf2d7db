"""Files of a FEM run: summary.json, VTU snapshots and an XDMF time series for ParaView.
(history.csv is streamed by the solver while it runs.)"""

from __future__ import annotations

import json
import math
import os
from pathlib import Path

import numpy as np

from meshes.io import write, write_time_series


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
    for name, k in (("initial", 0), ("peak_rotation", peak), ("final", len(frames) - 1)):
        t, u = frames[k]
        write(out / f"fields_{name}.vtu", mesh, point_data={"displacement": u})
    step = max(1, len(frames) // 60)      # inline XML: keep the series a few MB
    chosen = frames[::step]
    write_time_series(out / "fields.xdmf", mesh, [t for t, _ in chosen],
                      lambda k: {"displacement": chosen[k][1]})
    write_summary(out / "summary.json", result.summary)

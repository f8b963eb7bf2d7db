"""What FEM work costs on this machine: a cost model calibrated by measuring the kernel here.

A FEM run of ``states`` states (replicas or grid points) on a mesh of ``nodes`` nodes, over
``steps`` time steps with ``outputs`` output rows, costs this much CPU (s):

    steps x states x (a_L + b_L x nodes) + outputs x states x (c + e x nodes)

with L the kernel's layout: one state alone (``single``) or a group of states (``group``,
several states a pass through the stiffness, cheaper per state); ``c`` and ``e`` the Python
recorder's cost of an output row (its numbers, its frames); a run's setup (the static state)
is a few ms, below what the fit resolves. :func:`studies.warmup.calibrate` measures them here
on the default column's meshes (168, 440 and 1,512 nodes; one state and 8; outputs every 100
steps and every 5) and :func:`fit` fits them by least squares; ``colonna warmup`` (run by
``make`` at install) saves the fit (:func:`save_calibration`) under :func:`cache_dir`, keyed by
this machine and colonna's version. Without one (another machine, another version)
:data:`UNCALIBRATED` is used, the fit on the machine of the README's timings, and the
estimates say so.

Measured on that machine (2 cores): group 2.3 us + 11.3 ns a node per state-step, single 5.0 us
+ 29.4 ns, an output row 148 us + 12 ns a node a state (the fit within 10 % of each of the 12
measurements). A study's estimate adds its cases' runs
(:class:`studies.work.FemWork`); runs that stop early (overturned, settled) cost less.
"""

from __future__ import annotations

import functools
import json
import os
import platform
from dataclasses import asdict, dataclass
from pathlib import Path

FILE_NAME = "cost-model.json"


@dataclass(frozen=True)
class CostModel:
    """The coefficients of the module's cost formula (s), and where they come from
    (``calibrated``: measured on this machine by :func:`calibrate`)."""

    group_step: float  # a_group: s a state-step, in a group of states
    group_node_step: float  # b_group: s a node-step, in a group
    single_step: float  # a_single: s a step of a state alone
    single_node_step: float  # b_single: s a node-step of a state alone
    output: float  # c: s an output row of a state
    output_node: float  # e: s a node of an output row of a state
    calibrated: bool = False

    def run_seconds(self, nodes: int, steps: float, outputs: float, states: int) -> float:
        """CPU seconds of ``states`` runs advanced together over ``steps`` steps."""
        if states <= 0 or steps <= 0:
            return 0.0
        a, b = (
            (self.single_step, self.single_node_step)
            if states == 1
            else (self.group_step, self.group_node_step)
        )
        return steps * states * (a + b * nodes) + outputs * states * (
            self.output + self.output_node * nodes
        )


# the fit on the machine of the README's timings (2 cores, 2026-11-29), used where this machine
# has no calibration of its own
UNCALIBRATED = CostModel(
    group_step=2.3e-6,
    group_node_step=11.3e-9,
    single_step=5.0e-6,
    single_node_step=29.4e-9,
    output=148e-6,
    output_node=12.4e-9,
)


def cache_dir() -> Path:
    """Where colonna keeps what it measured on this machine: $COLONNA_CACHE_DIR, else
    $XDG_CACHE_HOME/colonna, else ~/.cache/colonna."""
    given = os.environ.get("COLONNA_CACHE_DIR")
    if given:
        return Path(given)
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "colonna"


@functools.cache
def _machine_key() -> str:
    return json.dumps(machine_key(), sort_keys=True)


def machine_key() -> dict:
    """What a calibration belongs to: this machine (its name, processor and cores) and this
    version of colonna (its kernels)."""
    from .executor import available_cores, colonna_version

    processor = platform.processor() or platform.machine()
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                processor = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    return {
        "node": platform.node(),
        "processor": processor,
        "cores": available_cores(),
        "colonna": colonna_version(),
        "numba_cpu": os.environ.get("NUMBA_CPU_NAME", ""),
    }


_LOADED: dict = {}


def cost_model() -> CostModel:
    """This machine's calibrated model (``colonna warmup`` saved it), else
    :data:`UNCALIBRATED`."""
    key = _machine_key()  # read once a process: every FEM run's estimate asks for the model
    if key not in _LOADED:
        _LOADED[key] = _read(cache_dir() / FILE_NAME, json.loads(key)) or UNCALIBRATED
    return _LOADED[key]


def _read(path: Path, key: dict) -> CostModel | None:
    try:
        data = json.loads(path.read_text())
        if data.get("machine") != key:
            return None
        return CostModel(**data["model"], calibrated=True)
    except (OSError, ValueError, TypeError, KeyError):
        return None


def save_calibration(model: CostModel, measurements: list[dict]) -> Path:
    """Save ``model`` (fitted here) with this machine's key and what it was fitted to."""
    folder = cache_dir()
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / FILE_NAME
    fields = {k: v for k, v in asdict(model).items() if k != "calibrated"}
    data = {"machine": machine_key(), "model": fields, "measurements": measurements}
    partial = path.with_name(path.name + ".tmp")
    partial.write_text(json.dumps(data, indent=1))
    os.replace(partial, path)
    _LOADED.clear()
    return path


def fit(measurements: list[dict]) -> CostModel:
    """The cost model that fits ``measurements`` (each: nodes, states, steps, outputs, the
    seconds it took) by least squares on the relative error, every measurement weighing the
    same; no coefficient below 0."""
    import numpy as np
    from scipy.optimize import nnls

    rows, seconds = [], []
    for m in measurements:
        work_steps = m["steps"] * m["states"]
        work_outputs = m["outputs"] * m["states"]
        single = m["states"] == 1
        rows.append(
            [
                0.0 if single else work_steps,
                0.0 if single else work_steps * m["nodes"],
                work_steps if single else 0.0,
                work_steps * m["nodes"] if single else 0.0,
                work_outputs,
                work_outputs * m["nodes"],
            ]
        )
        seconds.append(m["seconds"])
    A = np.array(rows) / np.array(seconds)[:, None]
    scale = np.abs(A).max(axis=0)
    scale[scale == 0.0] = 1.0  # a term no measurement has (then its coefficient is 0)
    coefficients, _ = nnls(A / scale, np.ones(len(seconds)))  # no cost is negative
    coefficients = coefficients / scale
    names = (
        "group_step",
        "group_node_step",
        "single_step",
        "single_node_step",
        "output",
        "output_node",
    )
    fitted = {name: float(c) for name, c in zip(names, coefficients, strict=True)}
    return CostModel(**fitted, calibrated=True)

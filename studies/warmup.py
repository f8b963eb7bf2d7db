"""Compile the numba kernels of the command line into numba's cache, once, when colonna is
installed (``make`` runs ``colonna warmup`` after ``pip install``), and measure the FEM's cost
on this machine for the estimates of time (:func:`calibrate`, :mod:`studies.cost`).

numba compiles a kernel the first time a process calls it with a given signature and, with
``cache=True``, saves the machine code beside its module (the ``__pycache__`` folders of the
package; ``NUMBA_CACHE_DIR`` moves them). A later process loads it in a fraction of a second, so
after this a fresh install's first run of a command costs about what its second does. The
warm-up runs the README's command-line examples on tiny inputs (a short pulse, a 2 x 2 grid, a
coarse mesh) in this process: the kernels get exactly the signatures the commands use. The cache
is keyed on the source files and the processor; an edited kernel or another machine compiles
again, on its first call.

The command line is given to :func:`warm` (``colonna warmup`` passes its own ``main``), so that
this module imports nothing of it: the command line imports this one, not the other way round.
"""

from __future__ import annotations

import contextlib
import io
import tempfile
import time
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from .cost import CostModel

COLLARS = """
[[collar]]
y = 0.5
t = 0.006
h = 0.05

[[collar]]
y = 1.5
t = 0.006
h = 0.05
"""

FEM_STUDY = """
[study]
name = "warmup"
[column]
height = 1.0
width = 0.2
[[collar]]
y = 0.5
t = 0.004
h = 0.02
[[collar]]
y = 0.8
t = 0.004
h = 0.02
plastic = true
[ground]
amplitude_ratio = 3.0
omega_ratio = 3.0
[mesh]
size = 0.1
grading = 0.0
[run]
duration = 0.004
output_interval = 0.002
replicas = {replicas}
"""


def commands(folder: Path) -> list[tuple[str, list[str]]]:
    """(what, arguments) of the command lines run: the README's examples, made tiny."""
    collars = folder / "collars.toml"
    block = ["--b", "0.2", "--h", "2.0", "--density", "2700"]
    sdof = ["--p", "2.14", "--alpha", "0.25"]
    pulse = ["--omega-ratio", "3", "--amplitude-ratio", "3"]
    grid = ["--omega-ratios", "1:4:2", "--amplitude-ratios", "1.5:4:2"]
    return [
        ("rigid, linear", ["rigid", *sdof, "--model", "linear", "--restitution", "0.9", *pulse]),
        ("rigid, nonlinear", ["rigid", *sdof, *pulse]),
        ("rigid, collars", ["rigid", *block, "--collars", str(collars), *pulse]),
        (
            "rigid, multibody",
            ["rigid", "--model", "multibody", *block, "--collars", str(collars), *pulse],
        ),
        (
            "rigid, multibody cracked",
            ["rigid", "--model", "multibody", *sdof, "--friction", "2", "--cracked", *pulse],
        ),
        ("spectrum, linear", ["spectrum", *sdof, "--model", "linear", *grid]),
        ("spectrum, nonlinear", ["spectrum", *sdof, *grid]),
        ("spectrum, collars", ["spectrum", *block, "--collars", str(collars), *grid]),
        ("spectrum, multibody", ["spectrum", *sdof, "--model", "multibody", *grid]),
        # one run (the kernel's one-state code) and an ensemble (its group code)
        ("fem, one run", ["fem", str(folder / "fem-1.toml"), "--out", str(folder / "fem-1")]),
        ("fem, ensemble", ["fem", str(folder / "fem-2.toml"), "--out", str(folder / "fem-2")]),
    ]


def warm(main: Callable[[Sequence[str]], int], say: Callable[[str], object] = print) -> float:
    """Run the tiny command lines through ``main`` (the command line's entry: arguments in, exit
    status out; their output discarded); the seconds it took."""
    start = time.perf_counter()
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        (folder / "collars.toml").write_text(COLLARS)
        for replicas in (1, 2):
            (folder / f"fem-{replicas}.toml").write_text(FEM_STUDY.format(replicas=replicas))
        for what, argv in commands(folder):
            clock = time.perf_counter()
            sink = io.StringIO()
            with contextlib.redirect_stdout(sink), contextlib.redirect_stderr(sink):
                code = main([*argv, "--json"])
            if code != 0:
                raise RuntimeError(f"colonna warmup: {what} failed:\n{sink.getvalue()}")
            say(f"  {what}: {time.perf_counter() - clock:.1f} s")
    return time.perf_counter() - start


def calibrate(repeats: int = 2) -> tuple[CostModel, list[dict]]:
    """Measure the FEM kernel here and fit the cost formula: the default column on meshes of
    0.15, 0.075 and 0.0375 m, one state and 8, outputs every 100 and every 5 steps (the best of
    ``repeats`` each); a few seconds. Returns the model and the measurements."""
    import tomllib
    from dataclasses import replace

    from ..fem.model import stable_time_step
    from .cost import fit
    from .fem_study import from_dict
    from .models import build, iter_fem

    data = tomllib.loads((Path(__file__).parent / "default.toml").read_text())
    measurements = []
    for size in (0.15, 0.075, 0.0375):
        data["mesh"]["size"] = size
        study = from_dict(data)
        model = build(study)
        dt = stable_time_step(model, study.safety).dt
        nodes = model.n_dofs // 2
        for states in (1, 8):
            for per_output in (100, 5):
                steps = 3000 if states == 1 else 1500
                wall = []
                for _ in range(repeats):
                    run = replace(study, duration=steps * dt, output_interval=per_output * dt)
                    clock = time.perf_counter()
                    for _ in iter_fem([run] * states):  # one batch: they share the model
                        pass
                    wall.append(time.perf_counter() - clock)
                measurements.append(
                    {
                        "nodes": nodes,
                        "states": states,
                        "steps": steps,
                        "outputs": steps // per_output,
                        "seconds": min(wall),
                    }
                )
    return fit(measurements), measurements

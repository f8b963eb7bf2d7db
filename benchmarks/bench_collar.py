"""Cost of one call of the collar's local law: the fibre-section element (colonna.core.fibre)
against the resultant law, ns per call, so that the FEM step's collar share can be estimated
(a step calls the law once per collar).

Cases, for the default study's collar (60 x 8 mm, L 0.45 m, S235), the ends slipping laterally
(d_y: the first-yield slip):
  elastic   trial calls at 0.5 d_y from the unstressed state
  plastic   trial calls 1e-4 d_y past a state committed at 10 d_y (an explicit step's increment)
  stepping  committed calls along the slip from 10 d_y on, 1e-4 d_y a step
The loops run inside numba (no Python call in the timing). ``--fem`` also times a step of the
default study's FEM with its (elastic) collars, for the share.

    .venv/bin/python benchmarks/bench_collar.py [--fem]
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np
from numba import njit

from colonna.core.collar import Collar
from colonna.core.collar_law import frame_local_law, state_size
from colonna.core.motion import Motion
from colonna.fem.settings import FemSettings

L = 0.45
BAND = dict(y=1.0, t=0.008, h=0.06, length=L, fy=235e6, plastic=True, eps_u=0.15)
CALLS = 20_000


@njit
def _calls(d0, step, n, commit, ea_l, ei_l, law, state):
    """n calls at slips d0 + k step (commit) or n trial calls at d0 + step; returns a checksum."""
    total = 0.0
    for k in range(n):
        d = d0 + (k + 1) * step if commit else d0 + step
        th = -math.atan2(d, L)
        N, M1, M2, U, ep, fibre = frame_local_law(
            math.hypot(L, d) - L, th, th, ea_l, ei_l, 0.0, law, state, 0, commit
        )
        total += M1
    return total


def _state_at(collar, d, law, ea_l, ei_l):
    """The state committed along the slip from 0 to d in 1000 steps."""
    state = np.zeros((1, state_size(law)))
    _calls(0.0, d / 1000, 1000, True, ea_l, ei_l, law, state)
    return state


def per_call(collar: Collar) -> dict:
    """ns per call of the three cases for a collar."""
    law = np.array(collar.law())
    ea_l = collar.E * collar.area / L
    ei_l = collar.E * collar.second_moment / L
    dy = collar.yield_displacement()
    times = {}
    cases = {
        "elastic": (np.zeros((1, state_size(law))), 0.0, 0.5 * dy, False),
        "plastic": (_state_at(collar, 10 * dy, law, ea_l, ei_l), 10 * dy, 1e-4 * dy, False),
        "stepping": (_state_at(collar, 10 * dy, law, ea_l, ei_l), 10 * dy, 1e-4 * dy, True),
    }
    for name, (state, d0, step, commit) in cases.items():
        best = math.inf
        for _ in range(5):
            work = state.copy()
            start = time.perf_counter()
            _calls(d0, step, CALLS, commit, ea_l, ei_l, law, work)
            best = min(best, (time.perf_counter() - start) / CALLS)
        times[name] = best * 1e9
    return times


def fem_step() -> float:
    """Seconds per explicit step of the default study's FEM (its collars as the study has them)."""
    from pathlib import Path

    from colonna.fem.model import stable_time_step
    from colonna.fem.solver import run
    from colonna.studies.models import build
    from colonna.studies.study import load

    study = load(Path(__file__).resolve().parents[1] / "studies" / "default.toml").fem
    model = build(study)
    dt = stable_time_step(model, study.safety).dt
    run(model, Motion(study.ground, 10 * dt), FemSettings(progress=False, output_interval=10 * dt))
    result = run(
        model,
        Motion(study.ground, 3000 * dt),
        FemSettings(progress=False, output_interval=3000 * dt),
    )
    return result.summary["wall_seconds"] / result.summary["steps"]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--fem", action="store_true", help="also time a FEM step")
    args = parser.parse_args()
    variants = {
        "resultant": Collar(**BAND, section="resultant"),
        "fibre 5 x 20": Collar(**BAND, n_sections=5),
        "fibre 10 x 20 (default)": Collar(**BAND),
        "fibre 10 x 20 Menegotto-Pinto": Collar(**BAND, steel="menegotto-pinto"),
        "fibre 10 x 40": Collar(**BAND, n_fibres=40),
        "fibre 20 x 40": Collar(**BAND, n_sections=20, n_fibres=40),
    }
    per_call(variants["resultant"])  # compile
    print(f"{'law':30s} {'elastic':>10s} {'plastic':>10s} {'stepping':>10s}   ns per call")
    for name, collar in variants.items():
        t = per_call(collar)
        print(f"{name:30s} {t['elastic']:10.0f} {t['plastic']:10.0f} {t['stepping']:10.0f}")
    if args.fem:
        print(f"FEM step of the default study: {fem_step() * 1e9:.0f} ns")


if __name__ == "__main__":
    main()

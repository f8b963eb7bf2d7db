"""Spectrum throughput: a 200 x 400 grid (80,000 sine pulses) of the Zhang & Makris block, for
the linear closed form and the nonlinear DOPRI5 solver, and with collars.

Targets on a 2-core machine: <= 10 s (linear), <= 120 s (nonlinear); with collars, nonlinear
<= 5 s (issue 19). Compilation is done (and timed separately) before the measured runs. Each time
is the best of REPEATS runs (a shared machine's other work only ever slows a run down).
Run: make bench
"""

from __future__ import annotations

import os
import time

import numba
import numpy as np

from colonna.rigid import Block, Collar
from colonna.rigid.spectrum import overturning_spectrum

TARGETS = {"linear": 10.0, "nonlinear": 120.0}
TARGETS_WITH_COLLARS = {"linear": None, "nonlinear": 5.0}
REPEATS = 3


def best_of(repeats: int, *args, **kwargs):
    """overturning_spectrum(*args, **kwargs) run ``repeats`` times: the run of the shortest time."""
    runs = [overturning_spectrum(*args, **kwargs) for _ in range(repeats)]
    return min(runs, key=lambda spec: spec.seconds)


def verdict(seconds: float, target: float | None) -> str:
    """The time against its target (empty where there is none)."""
    if target is None:
        return ""
    return f"(target {target:g} s) " + ("ok" if seconds <= target else "SLOWER THAN TARGET")


def main() -> None:
    block = Block.from_dimensionless(p=2.14, alpha=0.25, restitution=0.9)
    omegas = np.linspace(0.5, 15.0, 400)
    amplitudes = np.linspace(1.0, 20.0, 200)
    start = time.perf_counter()
    for model in TARGETS:
        overturning_spectrum(block, omegas[:2], amplitudes[:2], model=model)
    print(f"cores: {os.cpu_count()}, compile/warm-up: {time.perf_counter() - start:.1f} s")
    print(f"numba threads: {numba.get_num_threads()}, best of {REPEATS}")
    for model, target in TARGETS.items():
        spec = best_of(REPEATS, block, omegas, amplitudes, model=model)
        per = spec.seconds / spec.codes.size * 1e6
        print(
            f"{model:9s} free block: {spec.codes.size} pulses in {spec.seconds:6.2f} s "
            f"({per:6.1f} us/pulse) {verdict(spec.seconds, target)}"
        )
    cracked = Block(
        b=block.b, h=block.h, mass=2700.0 * 4 * block.b * block.h * np.pi * block.b, restitution=0.9
    )
    collars = (Collar(y=0.5 * block.h, t=0.01, h=0.04), Collar(y=1.5 * block.h, t=0.01, h=0.04))
    for model, target in TARGETS_WITH_COLLARS.items():
        spec = best_of(REPEATS, cracked, omegas, amplitudes, collars, model=model)
        per = spec.seconds / spec.codes.size * 1e6
        print(
            f"{model:9s} + collars:   {spec.codes.size} pulses in {spec.seconds:6.2f} s "
            f"({per:6.1f} us/pulse) {verdict(spec.seconds, target)}"
        )


if __name__ == "__main__":
    main()

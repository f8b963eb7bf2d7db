"""Spectrum throughput: a 200 x 400 grid (80,000 sine pulses) of the Zhang & Makris block, for
the linear closed form and the nonlinear DOPRI5 solver, and with collars.

Targets on a 2-core machine: <= 10 s (linear), <= 120 s (nonlinear). Compilation is done (and
timed separately) before the measured runs. Run: make bench
"""

from __future__ import annotations

import os
import time

import numpy as np

from colonna.rigid import Block, Collar
from colonna.rigid.spectrum import overturning_spectrum

TARGETS = {"linear": 10.0, "nonlinear": 120.0}


def main() -> None:
    block = Block.from_dimensionless(p=2.14, alpha=0.25, restitution=0.9)
    omegas = np.linspace(0.5, 15.0, 400)
    amplitudes = np.linspace(1.0, 20.0, 200)
    start = time.perf_counter()
    for model in TARGETS:
        overturning_spectrum(block, omegas[:2], amplitudes[:2], model=model)
    print(f"cores: {os.cpu_count()}, compile/warm-up: {time.perf_counter() - start:.1f} s")
    for model, target in TARGETS.items():
        spec = overturning_spectrum(block, omegas, amplitudes, model=model)
        per = spec.seconds / spec.codes.size * 1e6
        verdict = "ok" if spec.seconds <= target else "SLOWER THAN TARGET"
        print(
            f"{model:9s} free block: {spec.codes.size} pulses in {spec.seconds:6.2f} s "
            f"({per:6.1f} us/pulse; target {target:g} s) {verdict}"
        )
    cracked = Block(
        b=block.b, h=block.h, mass=2700.0 * 4 * block.b * block.h * np.pi * block.b, restitution=0.9
    )
    collars = (Collar(y=0.5 * block.h, t=0.01, h=0.04), Collar(y=1.5 * block.h, t=0.01, h=0.04))
    for model in TARGETS:
        spec = overturning_spectrum(cracked, omegas, amplitudes, collars, model=model)
        print(f"{model:9s} + collars:   {spec.codes.size} pulses in {spec.seconds:6.2f} s")


if __name__ == "__main__":
    main()

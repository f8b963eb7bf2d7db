"""Speed of the rigid multibody model on a 2-core machine. Run: make bench

* one history of the default cross-check study (cracked column, three collars, contact at the
  base and along the crack), median of 5 runs; target < 0.2 s;
* a 100 x 200 spectrum of the solid Zhang & Makris block (p = 2.14, alpha = 0.25, Housner
  impacts, friction high enough to forbid sliding); target < 60 s.

Compilation is done (and timed separately) before the measured runs.
"""

from __future__ import annotations

import os
import statistics
import time

import numpy as np

from colonna.core.motion import Motion
from colonna.rigid import Block, pulse_from_ratios
from colonna.rigid.multibody import MultibodyContact, multibody_spectrum, rock_multibody
from colonna.studies.cli import resolve_study
from colonna.studies.study import load

TARGET_HISTORY = 0.2
TARGET_SPECTRUM = 60.0


def main() -> None:
    study = load(resolve_study("default")).fem
    start = time.perf_counter()
    rock_multibody(
        study.rocking_block,
        Motion(study.ground, duration=0.1),
        study.collars,
        contact=MultibodyContact(cracked=True, friction=study.contact.friction),
    )
    block = Block.from_dimensionless(p=2.14, alpha=0.25)
    multibody_spectrum(block, [5.0], [2.0], contact=MultibodyContact(friction=2.0))
    print(f"cores: {os.cpu_count()}, compile/warm-up: {time.perf_counter() - start:.1f} s")

    walls, result = [], None
    for _ in range(5):
        start = time.perf_counter()
        result = rock_multibody(
            study.rocking_block,
            Motion(study.ground, duration=study.duration),
            study.collars,
            contact=MultibodyContact(cracked=True, friction=study.contact.friction),
        )
        walls.append(time.perf_counter() - start)
    wall = statistics.median(walls)
    verdict = "ok" if wall <= TARGET_HISTORY else "SLOWER THAN TARGET"
    print(
        f"default study history: {result.steps} steps of {result.dt:.3g} s to "
        f"t = {result.time[-1]:.3g} s ({result.status}) in {wall:.3f} s "
        f"({wall / result.steps * 1e6:.2f} us/step; target {TARGET_HISTORY} s) {verdict}"
    )

    omegas = np.linspace(0.5, 15.0, 200)
    amplitudes = np.linspace(1.0, 20.0, 100)
    spec = multibody_spectrum(block, omegas, amplitudes, contact=MultibodyContact(friction=2.0))
    verdict = "ok" if spec.seconds <= TARGET_SPECTRUM else "SLOWER THAN TARGET"
    print(
        f"solid-block spectrum: {spec.codes.size} pulses in {spec.seconds:.1f} s "
        f"({spec.seconds / spec.codes.size * 1e3:.2f} ms/pulse; target {TARGET_SPECTRUM:g} s) "
        f"{verdict}"
    )
    pulse = pulse_from_ratios(block, "sine", 5.0, 3.0, "nonlinear")
    one = rock_multibody(block, Motion(pulse), contact=MultibodyContact(friction=2.0))
    print(
        f"  (one pulse of it, Omega/p = 5, a_p = 3 g tan(alpha): {one.steps} steps, "
        f"{one.wall_seconds * 1e3:.1f} ms)"
    )


if __name__ == "__main__":
    main()

"""Validation of the rigid solver on the block of Zhang & Makris (2001), used by the source paper
(section 4, Fig. 5 and 7): p = 2.14 rad/s, alpha = 0.25 rad, nu = 0.9, one-sine pulse.

Writes time histories at the paper's four amplitudes (Omega/p = 5), the amplitude boundaries of
the overturning modes at Omega/p = 5 (bisection to 1e-6), the overturning spectra of both models,
with and without collars, a short Markdown report and ``summary.json``.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

from ...core.collar import Collar
from ...core.motion import Motion
from ...rigid.block import Block, pulse_from_ratios
from ...rigid.solve import rock
from ...rigid.spectrum import overturning_spectrum
from ..executor import RunOptions
from ..outcome import overturned_at, unless_stopped
from ..output import write_csv, write_json
from ..study import Study
from .report import write_markdown

ZHANG_MAKRIS = dict(p=2.14, alpha=0.25, restitution=0.9)
PAPER_AMPLITUDES = (3.0, 3.01, 6.32, 6.33)  # a_p / (g alpha), paper Fig. 5 a-d
OMEGA_RATIO = 5.0


def zhang_makris_block(**kw) -> Block:
    return Block.from_dimensionless(**ZHANG_MAKRIS, **kw)


def history_entry(result) -> dict:
    """What the summary keeps of a time history: whether and how the block overturned, its
    impacts, and its largest |theta| / alpha, which of a block that overturned is where its
    run stopped (no result: the words that say so in its place)."""
    run = result.summary()
    return {
        **{k: run[k] for k in ("overturned", "mode", "impacts")},
        "max_abs_theta_over_alpha": unless_stopped(
            run["max_abs_theta_over_alpha"],
            overturned_at("the block", run["overturned"], run.get("overturn_time")),
        ),
    }


def mode_boundaries(
    block: Block, omega_ratio: float, model: str, brackets, tol: float = 1e-6, collars=()
) -> list[float]:
    """Amplitude ratios where the mode changes, refined by bisection inside each bracket."""

    def mode(x):
        return rock(
            block,
            Motion(pulse_from_ratios(block, "sine", omega_ratio, x, model)),
            collars,
            model=model,
        ).mode

    found = []
    for lo, hi in brackets:
        m_lo, m_hi = mode(lo), mode(hi)
        if m_lo == m_hi:
            found.append(float("nan"))
            continue
        while hi - lo > tol:
            mid = 0.5 * (lo + hi)
            if mode(mid) == m_lo:
                lo = mid
            else:
                hi = mid
        found.append(0.5 * (lo + hi))
    return found


def zhang_makris_validation(out: Path, progress: bool = True) -> dict:
    from ...rigid.plotting import plot_history, plot_spectrum

    def say(msg):
        if progress:
            print(f"[validate] {msg}", file=sys.stderr, flush=True)

    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    block = zhang_makris_block()
    summary: dict[str, Any] = {
        "block": {
            "p": block.p,
            "alpha": block.alpha,
            "restitution": block.nu,
            "b": block.b,
            "h": block.h,
        },
        "omega_ratio": OMEGA_RATIO,
        "histories": {},
    }
    start = time.perf_counter()

    say("time histories at the paper's amplitudes (linear model, Omega/p = 5)")
    for x in PAPER_AMPLITUDES:
        result = rock(
            block,
            Motion(pulse_from_ratios(block, "sine", OMEGA_RATIO, x, "linear")),
            model="linear",
        )
        tag = f"{x:.2f}".replace(".", "_")
        write_csv(
            out / f"history_{tag}.csv",
            {
                "t": result.time,
                "theta_over_alpha": result.theta / block.alpha,
                "theta_dot_over_p": result.theta_dot / block.p,
            },
        )
        plot_history(
            result,
            out / f"history_{tag}.png",
            title=f"a_p = {x:g} g alpha, Omega/p = 5: {result.mode}",
        )
        summary["histories"][f"{x:g}"] = history_entry(result)

    say("mode boundaries at Omega/p = 5 (bisection)")
    brackets = [(2.5, 4.0), (5.5, 6.9), (6.9, 8.0)]
    summary["boundaries"] = {
        "linear": mode_boundaries(block, OMEGA_RATIO, "linear", brackets),
        "nonlinear": mode_boundaries(block, OMEGA_RATIO, "nonlinear", brackets),
        "meaning": [
            "safe -> overturns after impact",
            "overturns after impact -> safe",
            "safe -> overturns without impact",
        ],
        "paper_fig5_brackets": [[3.0, 3.01], [6.32, 6.33], None],
    }

    say("overturning spectra (linear and nonlinear, 300 x 200 pulses each)")
    omegas = np.linspace(0.5, 15.0, 300)
    amplitudes = np.linspace(1.0, 20.0, 200)
    cracked = Block(
        b=block.b,
        h=block.h,
        mass=2700.0 * 4 * block.b * block.h * np.pi * block.b,
        restitution=block.restitution,
    )
    collars = (Collar(y=0.5 * block.h, t=0.01, h=0.04), Collar(y=1.5 * block.h, t=0.01, h=0.04))
    summary["spectra"] = {}
    for model in ("linear", "nonlinear"):
        for label, blk, cols in (("free", block, ()), ("collars", cracked, collars)):
            spec = overturning_spectrum(blk, omegas, amplitudes, cols, model=model)
            name = f"spectrum_{model}_{label}"
            plot_spectrum(spec, out / f"{name}.png")
            write_csv(
                out / f"{name}_minimum_amplitude.csv",
                {
                    "omega_ratio": spec.omega_ratios,
                    "amplitude_ratio": spec.minimum_overturning_amplitude(),
                },
            )
            counts = np.bincount(spec.codes.ravel(), minlength=3)
            summary["spectra"][name] = {
                "seconds": spec.seconds,
                "safe": int(counts[0]),
                "after_impact": int(counts[1]),
                "without_impact": int(counts[2]),
            }
            say(f"  {name}: {spec.codes.size} pulses in {spec.seconds:.2f} s")
    summary["wall_seconds"] = time.perf_counter() - start
    write_json(out / "summary.json", summary)
    write_markdown(out, summary)
    say(f"done in {summary['wall_seconds']:.1f} s: {out / 'report.md'}")
    return summary


def run(study: Study, out: Path, options: RunOptions) -> dict:
    """The validation as a study (:func:`studies.study.load`; its file has nothing to vary):
    summary.json, figures."""
    from ..outcome import none_assessed

    summary = zhang_makris_validation(Path(out), progress=options.progress)
    summary["outcome"] = none_assessed(
        "this study validates the rigid solver against Zhang & Makris (2001); it assesses no column"
    )
    write_json(Path(out) / "summary.json", summary)
    return summary

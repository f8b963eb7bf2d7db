"""Overturning spectra (Zhang & Makris 2001 form): the response mode over a grid of pulse frequency
ratios Omega/p and amplitude ratios a_p / a_uplift, with or without collars.

Each grid point is an independent pulse run from rest; the grid runs in parallel over the CPU cores
(numba ``prange``; the points are dealt out spread over the grid so that the cores share the work
evenly, and each is computed by the same code whatever the thread count). With collars, a second
map tells where a collar reaches f_y (the elastic collar model holds only up to there). The linear
model without collars uses the exact closed form, all other cases the DOPRI5 integrator with event
location. A run stops as soon as its fate is certain: overturned, or (after the pulse) mechanical
energy below the gravity barrier at |theta| = alpha.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from ..core.errors import InputError
from ..core.ground import PULSE_KINDS
from . import _kernels as K
from .block import Block, check_model
from .collars import collar_kernel_constants, collar_yield_rotation, validate_collars
from .solve import MODE_NAMES, SdofSettings, kernel_block_constants, require_parameter_object

# a spectrum's default tolerances: rtol 1e-9 (rock()'s is 1e-10); it keeps no history
SPECTRUM_SETTINGS = SdofSettings(rtol=1e-9)

LAYOUT = "mode[i][j]: i indexes amplitude_ratios (rows), j indexes omega_ratios (columns)"


@dataclass
class Spectrum:
    omega_ratios: np.ndarray = field(repr=False)
    amplitude_ratios: np.ndarray = field(repr=False)
    codes: np.ndarray = field(repr=False)  # int8, rows: amplitude, columns: omega
    max_abs_theta: np.ndarray = field(repr=False)  # rad, pi/2 where overturned
    collar_yields: np.ndarray | None = field(repr=False)  # bool, None without collars
    model: str
    pulse: str
    seconds: float
    with_collars: bool

    @property
    def modes(self) -> list[list[str]]:
        return [[MODE_NAMES[int(c)] for c in row] for row in self.codes]

    def minimum_overturning_amplitude(self) -> np.ndarray:
        """Lowest amplitude ratio that overturns, per omega ratio (NaN where none does)."""
        over = self.codes != K.SAFE
        first = np.argmax(over, axis=0)
        return np.where(over.any(axis=0), self.amplitude_ratios[first], np.nan)

    def to_dict(self) -> dict:
        out = {
            "omega_ratios": self.omega_ratios.tolist(),
            "amplitude_ratios": self.amplitude_ratios.tolist(),
            "mode": self.modes,
            "layout": LAYOUT,
            "model": self.model,
            "pulse": self.pulse,
            "with_collars": self.with_collars,
            "seconds": self.seconds,
        }
        if self.collar_yields is not None:
            out["collar_yields"] = self.collar_yields.tolist()
        return out


def overturning_spectrum(
    block: Block,
    omega_ratios,
    amplitude_ratios,
    collars=(),
    *,
    model: str = "linear",
    pulse: str = "sine",
    free_time: float | None = None,
    settings: SdofSettings = SPECTRUM_SETTINGS,
) -> Spectrum:
    """Mode of every (amplitude ratio, omega ratio) pair.

    free_time: how long (s) free rocking is followed after the pulse when the block's fate is
    not settled earlier (default 50 / p).
    settings: the integrator's tolerances ``rtol``, ``atol`` (default :data:`SPECTRUM_SETTINGS`,
    rtol 1e-9); ``dt_out`` and ``max_impacts_stored`` do not apply (no history is kept).
    """
    require_parameter_object("settings", settings, SdofSettings)
    for name in ("dt_out", "max_impacts_stored"):
        if getattr(settings, name) != getattr(SPECTRUM_SETTINGS, name):
            raise InputError(f"settings.{name} does not apply to a spectrum: it keeps no history")
    rtol, atol = settings.rtol, settings.atol
    check_model(model)
    omega_ratios, amplitude_ratios = check_spectrum_grid(omega_ratios, amplitude_ratios, pulse)
    collars = validate_collars(collars, block)
    ka, kl = collar_kernel_constants(block, collars)
    nonlinear = model == "nonlinear"
    # (a top load makes the linear model an equivalent free block of another p: the omega
    # ratios, relative to the block's own p, are carried over to it)
    p, alpha, uplift, _, load = kernel_block_constants(block, model)
    if free_time is None:
        free_time = 50.0 / block.p
    start = time.perf_counter()
    codes, max_theta = K.spectrum_modes(
        p,
        alpha,
        block.nu,
        nonlinear,
        pulse == "cosine",
        ka,
        kl,
        uplift,
        load,
        omega_ratios * (block.p / p),
        amplitude_ratios,
        free_time,
        rtol,
        atol,
    )
    seconds = time.perf_counter() - start
    yields = None
    if collars:
        theta_yield = min(collar_yield_rotation(c, block.b) for c in collars)
        yields = max_theta >= theta_yield
    return Spectrum(
        omega_ratios,
        amplitude_ratios,
        codes,
        max_theta,
        yields,
        model,
        pulse,
        seconds,
        bool(collars),
    )


def check_spectrum_grid(omega_ratios, amplitude_ratios, pulse: str):
    """The grid as float arrays, or an InputError naming what is wrong."""
    if pulse not in PULSE_KINDS:
        raise InputError(f"pulse = {pulse!r} is not one of {', '.join(PULSE_KINDS)}")
    omega_ratios = np.ascontiguousarray(omega_ratios, dtype=float)
    amplitude_ratios = np.ascontiguousarray(amplitude_ratios, dtype=float)
    if (
        omega_ratios.ndim != 1
        or omega_ratios.size == 0
        or not np.all(omega_ratios > 0)
        or not np.all(np.isfinite(omega_ratios))
    ):
        raise InputError("omega ratios must be a non-empty list of finite values > 0")
    if (
        amplitude_ratios.ndim != 1
        or amplitude_ratios.size == 0
        or not np.all(amplitude_ratios >= 1)
        or not np.all(np.isfinite(amplitude_ratios))
    ):
        raise InputError(
            "amplitude ratios must be a non-empty list of finite values >= 1 "
            "(a_p / a_uplift; below 1 the block does not rock)"
        )
    return omega_ratios, amplitude_ratios


MAX_RANGE_POINTS = 10_000  # per axis: 10^8 pulses of a spectrum would take hours


def parse_range(text: str, name: str) -> np.ndarray:
    """'START:STOP:N' -> N evenly spaced values (inclusive)."""
    parts = text.split(":")
    try:
        if len(parts) != 3:
            raise ValueError
        start, stop, n = float(parts[0]), float(parts[1]), int(parts[2])
    except ValueError:
        raise InputError(f"{name} = {text!r} is not of the form START:STOP:N") from None
    if not 1 <= n <= MAX_RANGE_POINTS:
        raise InputError(f"{name}: N = {n} must be in [1, {MAX_RANGE_POINTS:,}]")
    if n > 1 and not start < stop:
        raise InputError(f"{name} = {text!r}: START must be below STOP (START:STOP:N)")
    return np.linspace(start, stop, n)

"""Ground motions: one-sine and one-cosine acceleration pulses, and recorded accelerograms.

A sine pulse is ``ug''(t) = a_p sin(Omega t + phi)`` for ``0 <= t <= (2 pi - phi) / Omega`` and zero
after (paper Eq. 6), with ``phi = asin(a_uplift / a_p)`` so that rocking starts at t = 0. A cosine
pulse is ``ug''(t) = a_p cos(Omega t)`` for ``0 <= t <= 2 pi / Omega``: it starts at its peak, so a
block rocks from t = 0 as soon as ``a_p`` exceeds the uplift acceleration. Both are stored as
``a_p sin(Omega t + phase)`` on ``[0, duration]``. A negative ``a_p`` mirrors the pulse.

Records are read from a two-column text/CSV file (time in s, acceleration in m/s^2 unless
``units='g'``) or from the PEER NGA ``.AT2`` format (acceleration in g).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Protocol, runtime_checkable

import numpy as np

from .constants import STANDARD_GRAVITY
from .errors import InputError, require_positive

PULSE_KINDS = ("sine", "cosine")


@runtime_checkable
class GroundMotion(Protocol):
    """What every ground motion gives (a pulse, a record, or :class:`NoMotion`: ``None`` never
    stands for "no motion")."""

    def acceleration(self, t): ...  # m/s^2 at times t (s), zero outside the motion

    @property
    def end_time(self) -> float: ...  # s, when the motion ends

    @property
    def peak_acceleration(self) -> float: ...  # m/s^2, largest |acceleration|


@dataclass(frozen=True)
class HarmonicPulse:
    """``ug''(t) = amplitude * sin(omega t + phase)`` for 0 <= t <= duration, zero otherwise.

    amplitude in m/s^2 (sign gives the direction of the first push), omega in rad/s.
    """

    kind: str
    amplitude: float
    omega: float
    phase: float
    duration: float

    def acceleration(self, t):
        """Ground acceleration (m/s^2) at times ``t`` (array or scalar)."""
        t = np.asarray(t, dtype=float)
        inside = (t >= 0.0) & (t <= self.duration)
        return np.where(inside, self.amplitude * np.sin(self.omega * t + self.phase), 0.0)

    @property
    def end_time(self) -> float:
        return self.duration

    @property
    def peak_acceleration(self) -> float:
        return abs(self.amplitude)


@dataclass(frozen=True)
class Record:
    """A recorded ground acceleration, linearly interpolated, zero outside its time span."""

    time: np.ndarray = field(repr=False)  # s, strictly increasing
    acceleration_values: np.ndarray = field(repr=False)  # m/s^2
    name: str = "record"

    def __post_init__(self):
        t = np.asarray(self.time, dtype=float)
        a = np.asarray(self.acceleration_values, dtype=float)
        if t.ndim != 1 or t.shape != a.shape or t.size < 2:
            raise InputError(f"record {self.name!r}: needs at least two (time, acceleration) rows")
        if not np.all(np.isfinite(t)) or not np.all(np.isfinite(a)):
            raise InputError(f"record {self.name!r}: contains non-finite values")
        if np.any(np.diff(t) <= 0.0):
            raise InputError(f"record {self.name!r}: time must increase strictly")
        object.__setattr__(self, "time", t)
        object.__setattr__(self, "acceleration_values", a)

    def acceleration(self, t):
        return np.interp(t, self.time, self.acceleration_values, left=0.0, right=0.0)

    def scaled(self, factor: float) -> Record:
        return Record(self.time, self.acceleration_values * float(factor), self.name)

    @property
    def end_time(self) -> float:
        return float(self.time[-1])

    @property
    def peak_acceleration(self) -> float:
        return float(np.max(np.abs(self.acceleration_values)))


@dataclass(frozen=True)
class NoMotion:
    """No ground motion: free rocking from the initial conditions of a run."""

    kind: str = "none"

    def acceleration(self, t):
        return np.zeros_like(np.asarray(t, dtype=float))

    @property
    def end_time(self) -> float:
        return 0.0

    @property
    def peak_acceleration(self) -> float:
        return 0.0


NO_MOTION = NoMotion()  # the default of every optional motion (the vertical one)


def require_motion(name: str, motion) -> GroundMotion:
    """``motion`` if it is a ground motion; an InputError naming ``name`` otherwise (None
    included: no motion is :data:`NO_MOTION`)."""
    if not isinstance(motion, GroundMotion):
        raise InputError(
            f"{name} = {motion!r} is not a ground motion (a pulse, a record, or "
            "NoMotion() for none)"
        )
    return motion


def sine_pulse(amplitude: float, omega: float, uplift_acceleration: float) -> HarmonicPulse:
    """One-sine pulse whose phase makes rocking start at t = 0 (Eq. 6, phi = asin(a_up / a_p))."""
    _check_amplitude(amplitude, uplift_acceleration)
    require_positive("omega (pulse circular frequency, rad/s)", omega)
    phase = math.asin(min(1.0, uplift_acceleration / abs(amplitude)))
    return HarmonicPulse(
        "sine", float(amplitude), float(omega), phase, (2.0 * math.pi - phase) / omega
    )


def cosine_pulse(amplitude: float, omega: float, uplift_acceleration: float) -> HarmonicPulse:
    """One-cosine pulse a_p cos(Omega t), 0 <= t <= 2 pi / Omega: rocking starts at t = 0."""
    _check_amplitude(amplitude, uplift_acceleration)
    require_positive("omega (pulse circular frequency, rad/s)", omega)
    return HarmonicPulse(
        "cosine", float(amplitude), float(omega), math.pi / 2.0, 2.0 * math.pi / omega
    )


def _check_amplitude(amplitude: float, uplift: float) -> None:
    require_positive("uplift acceleration (m/s^2)", uplift)
    if not abs(amplitude) >= uplift * (1.0 - 1e-12):
        raise InputError(
            f"pulse amplitude = {amplitude:g} m/s^2 is below the uplift acceleration "
            f"{uplift:g} m/s^2: the block would not rock"
        )


# --- record readers -------------------------------------------------------------------------

_AT2_HEADER = re.compile(
    r"NPTS\s*=\s*(?P<npts>\d+)\s*,?\s*DT\s*=\s*(?P<dt>[0-9.Ee+-]+)"
    r"|^\s*(?P<npts2>\d+)\s+(?P<dt2>[0-9.Ee+-]+)\s+NPTS",
    re.IGNORECASE | re.MULTILINE,
)


def read_peer_at2(path, *, g: float = STANDARD_GRAVITY) -> Record:
    """Read a PEER NGA ``.AT2`` accelerogram (acceleration in g) into m/s^2."""
    path = Path(path)
    text = _read_text(path)
    lines = text.splitlines()
    for i, line in enumerate(lines[:10]):  # noqa: B007 (i: the header's line, after the loop)
        match = _AT2_HEADER.search(line)
        if match:
            npts = int(match.group("npts") or match.group("npts2"))
            dt = float(match.group("dt") or match.group("dt2"))
            break
    else:
        raise InputError(
            f"record file {path}: no 'NPTS=..., DT=...' header line in the first 10 "
            "lines (not a PEER AT2 file?)"
        )
    if dt <= 0.0 or npts < 2:
        raise InputError(f"record file {path}: NPTS = {npts}, DT = {dt:g} are not valid")
    try:
        values = np.array(" ".join(lines[i + 1 :]).split(), dtype=float)
    except ValueError:
        raise InputError(f"record file {path}: non-numeric value after the header") from None
    if values.size < npts:
        raise InputError(
            f"record file {path}: header says NPTS = {npts} but {values.size} values follow"
        )
    return Record(np.arange(npts) * dt, values[:npts] * g, name=path.stem)


def read_two_column(path, *, units: str = "m/s2", g: float = STANDARD_GRAVITY) -> Record:
    """Read ``time, acceleration`` rows (comma, semicolon or whitespace separated; '#' comments
    and a non-numeric header line are skipped). ``units`` is 'm/s2' or 'g'."""
    path = Path(path)
    if units not in ("m/s2", "g"):
        raise InputError(f"units = {units!r} is not one of m/s2, g")
    rows: list[list[float]] = []
    for lineno, line in enumerate(_read_text(path).splitlines(), start=1):
        line = line.split("#", 1)[0].strip()
        if not line:
            continue
        parts = re.split(r"[,;\s]+", line)
        try:
            values = [float(x) for x in parts if x]
        except ValueError:
            if not rows:  # a header line
                continue
            raise InputError(f"record file {path}, line {lineno}: not numeric: {line!r}") from None
        if len(values) < 2:
            raise InputError(
                f"record file {path}, line {lineno}: needs two columns (time, acceleration)"
            )
        rows.append(values[:2])
    if len(rows) < 2:
        raise InputError(f"record file {path}: fewer than two data rows")
    data = np.array(rows)
    scale = g if units == "g" else 1.0
    return Record(data[:, 0], data[:, 1] * scale, name=path.stem)


def read_record(path, *, g: float = STANDARD_GRAVITY) -> Record:
    """Read a record by extension: ``.at2`` as PEER NGA, anything else as two columns."""
    path = Path(path)
    if path.suffix.lower() == ".at2":
        return read_peer_at2(path, g=g)
    return read_two_column(path, g=g)


def _read_text(path: Path) -> str:
    try:
        return path.read_text(errors="replace")
    except OSError as exc:
        raise InputError(f"record file {path} cannot be read: {exc.strerror}") from None


def acceleration_table(motion, samples_per_period: int = 400):
    """(time (s), acceleration (m/s^2)) of a ground motion as a piecewise-linear table, zero
    outside it: a record as it is, a harmonic pulse sampled ``samples_per_period`` times per
    period over its duration (linear interpolation of the sine is then exact to 3e-5 of its
    amplitude). NoMotion: None."""
    if isinstance(motion, NoMotion):
        return None
    if isinstance(motion, Record):
        return motion.time.copy(), motion.acceleration_values.copy()
    if isinstance(motion, HarmonicPulse):
        n = max(
            2,
            int(math.ceil(samples_per_period * motion.duration * motion.omega / (2.0 * math.pi)))
            + 1,
        )
        t = np.linspace(0.0, motion.duration, n)
        return t, motion.acceleration(t)
    raise InputError(f"ground motion of type {type(motion).__name__} is not supported")


def kernel_tables(
    ground: GroundMotion, vertical: GroundMotion = NO_MOTION, horizontal_scale: float = 1.0
):
    """The tables the compiled solvers read the ground from, one pair of arrays: the
    horizontal record's rows (times ``horizontal_scale``; none for a pulse, which the kernels
    compute) followed by the vertical motion's table (:func:`acceleration_table`), m/s^2.
    Returns (times, accelerations, rows of the horizontal record, whether vertical rows
    follow); never empty arrays (numba wants one element)."""
    times = values = np.zeros(0)
    if isinstance(ground, Record):
        times, values = ground.time, horizontal_scale * ground.acceleration_values
    n_horizontal = times.size
    table = acceleration_table(vertical)
    if table is not None:
        times, values = np.concatenate((times, table[0])), np.concatenate((values, table[1]))
    if times.size == 0:
        times = values = np.zeros(1)
    return (
        np.ascontiguousarray(times, dtype=float),
        np.ascontiguousarray(values, dtype=float),
        n_horizontal,
        table is not None,
    )


def peak_acceleration(motion) -> float:
    """Peak |acceleration| (m/s^2) of a pulse (its amplitude) or a record (its largest
    sample); an InputError for no motion."""
    if isinstance(motion, (HarmonicPulse, Record)):
        return motion.peak_acceleration
    raise InputError("the study needs a ground motion (a pulse or a record) here, not 'none'")

"""Ground motions: one-sine and one-cosine acceleration pulses, and recorded accelerograms.

A sine pulse is ``ug''(t) = a_p sin(Omega t + phi)`` for ``0 <= t <= (2 pi - phi) / Omega`` and zero
after (paper Eq. 6), with ``phi = asin(a_uplift / a_p)`` so that rocking starts at t = 0. A cosine
pulse is ``ug''(t) = a_p cos(Omega t)`` for ``0 <= t <= 2 pi / Omega``: it starts at its peak, so a
block rocks from t = 0 as soon as ``a_p`` exceeds the uplift acceleration. Both are stored as
``a_p sin(Omega t + phase)`` on ``[0, duration]``. A negative ``a_p`` mirrors the pulse.

Records are read from a two-column text/CSV file (time in s, acceleration in m/s^2 unless
``units`` says otherwise) or from the PEER NGA ``.AT2`` format (units from its header's
``UNITS OF ...`` phrase) or from the ESM ASCII format (:mod:`colonna.core.esm`, units from its
header's ``UNITS``). A record file must be sampled uniformly at :data:`MAX_RECORD_STEP` or
finer; one that never reaches a column's uplift acceleration is legitimate but worth a note
(:func:`weak_record_note`).

Every motion gives what the solvers and the studies need through :class:`GroundMotion`, so
that none of them asks which class a motion is: a new kind of motion is its class alone,
registered for JSON with :func:`motion_type`.
"""

from __future__ import annotations

import dataclasses
import math
import re
from collections.abc import Callable
from dataclasses import dataclass, field
from decimal import Decimal, InvalidOperation
from pathlib import Path
from typing import Any, NamedTuple, Protocol, TypeVar, runtime_checkable

import numpy as np

from .constants import STANDARD_GRAVITY
from .errors import InputError, require_positive

PULSE_KINDS = ("sine", "cosine")


class SineForm(NamedTuple):
    """A motion that is one harmonic, ``amplitude sin(omega t + phase)`` for
    ``0 <= t <= duration`` and zero outside, in the form the rigid kernels compute exactly
    (instead of reading a table of it)."""

    amplitude: float  # m/s^2
    omega: float  # rad/s
    phase: float  # rad
    duration: float  # s


@runtime_checkable
class GroundMotion(Protocol):
    """What every ground motion gives (a pulse, a record, or :class:`NoMotion`: ``None`` never
    stands for "no motion"). The solvers read a motion only through these members:

    * ``acceleration(t)``: m/s^2 at times t (s, array or scalar), zero outside the motion;
    * ``end_time``: s, when the motion ends; ``peak_acceleration``: m/s^2, largest |acceleration|;
    * ``moves``: False only for no motion;
    * ``pulse_shape``: "sine" or "cosine" for a harmonic pulse that can be placed on the rigid
      overturning spectrum (it then has ``amplitude`` and ``omega``), None otherwise;
    * ``sine_form``: the motion as one exact harmonic (:class:`SineForm`) where it is one, for
      the kernels that compute it in closed form; None: they read ``acceleration_table``;
    * ``sample_times(samples_per_period=200)``: times on [0, end_time] fine enough to draw it
      (empty for no motion);
    * ``acceleration_table(samples_per_period=400)``: (times, accelerations) of the motion as
      a piecewise-linear table, zero outside it (None for no motion);
    * ``to_json()``: a plain JSON dict with a ``"type"`` key, read back by
      :func:`motion_from_json` (register the class with :func:`motion_type`).
    """

    def acceleration(self, t): ...  # m/s^2 at times t (s), zero outside the motion

    @property
    def end_time(self) -> float: ...  # s, when the motion ends

    @property
    def peak_acceleration(self) -> float: ...  # m/s^2, largest |acceleration|

    @property
    def moves(self) -> bool: ...  # False only for no motion

    @property
    def pulse_shape(self) -> str | None: ...  # "sine"/"cosine" for a spectrum pulse, else None

    @property
    def sine_form(self) -> SineForm | None: ...  # the exact harmonic, None: read the table

    def sample_times(self, samples_per_period: int = 200) -> np.ndarray: ...

    def acceleration_table(
        self, samples_per_period: int = 400
    ) -> tuple[np.ndarray, np.ndarray] | None: ...

    def to_json(self) -> dict[str, Any]: ...


# --- the JSON registry of motion types ---------------------------------------------------------

_MOTION_TYPES: dict[str, Any] = {}
_Motion = TypeVar("_Motion", bound=type)


def motion_type(name: str) -> Callable[[_Motion], _Motion]:
    """Class decorator: register a ground-motion class under the JSON ``"type"`` ``name``, so
    that :func:`motion_from_json` reads back what its ``to_json`` writes. A dataclass that
    defines neither gets both: its fields as JSON values (arrays as lists, read back as float
    arrays). Put it above ``@dataclass``."""

    def register(cls: _Motion) -> _Motion:
        target: Any = cls  # gets the JSON methods it lacks
        known = _MOTION_TYPES.get(name)
        if known is not None and (known.__module__, known.__qualname__) != (
            cls.__module__,
            cls.__qualname__,
        ):
            raise ValueError(f"ground-motion type {name!r} is already {known.__qualname__}")
        generic = getattr(cls, "to_json", None) is None or getattr(cls, "from_json", None) is None
        if generic and not dataclasses.is_dataclass(cls):
            raise TypeError(
                f"{cls.__qualname__}: a ground-motion type that is not a dataclass must define "
                "to_json and the classmethod from_json"
            )
        if getattr(cls, "to_json", None) is None:
            target.to_json = _fields_to_json
        if getattr(cls, "from_json", None) is None:
            target.from_json = classmethod(_fields_from_json)
        target.json_type = name
        _MOTION_TYPES[name] = cls
        return cls

    return register


def _plain(value):
    """A field's value as JSON: arrays as lists, numpy scalars as Python numbers."""
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, np.generic):
        return value.item()
    return value


def _fields_to_json(self) -> dict[str, Any]:
    """The JSON of a registered dataclass: its ``"type"`` and its fields."""
    data = {"type": type(self).json_type}
    data.update((f.name, _plain(getattr(self, f.name))) for f in dataclasses.fields(self))
    return data


def _fields_from_json(cls, data: dict[str, Any]):
    """A registered dataclass from its JSON: its fields, lists as float arrays."""
    names = {f.name for f in dataclasses.fields(cls)}
    values = {k: v for k, v in data.items() if k != "type"}
    unknown = sorted(set(values) - names)
    if unknown:
        raise InputError(
            f"ground motion {data['type']!r}: unknown keys {', '.join(map(repr, unknown))} "
            f"(known: {', '.join(sorted(names))})"
        )
    values = {
        k: np.asarray(v, dtype=float) if isinstance(v, list) else v for k, v in values.items()
    }
    try:
        return cls(**values)
    except TypeError as exc:  # a field missing
        raise InputError(f"ground motion {data['type']!r}: {exc}") from None


def motion_from_json(data: dict[str, Any]) -> GroundMotion:
    """The ground motion a ``to_json`` dict describes (its ``"type"`` names a class registered
    with :func:`motion_type`); bit for bit the motion written."""
    if not isinstance(data, dict) or not isinstance(data.get("type"), str):
        raise InputError(f"a ground motion's JSON must be an object with a 'type': {data!r:.80}")
    cls = _MOTION_TYPES.get(data["type"])
    if cls is None:
        raise InputError(
            f"ground motion type {data['type']!r} is not known (known: "
            f"{', '.join(sorted(_MOTION_TYPES))})"
        )
    return require_motion(f"ground motion {data['type']!r}", cls.from_json(data))


# --- the motions -----------------------------------------------------------------------------


@motion_type("harmonic_pulse")
@dataclass(frozen=True)
class HarmonicPulse:
    """``ug''(t) = amplitude * sin(omega t + phase)`` for 0 <= t <= duration, zero otherwise.

    amplitude in m/s^2 (sign gives the direction of the first push), omega in rad/s; kind:
    "sine" or "cosine" (the pulse's shape, :attr:`pulse_shape`).
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

    @property
    def moves(self) -> bool:
        return True

    @property
    def pulse_shape(self) -> str | None:
        return self.kind

    @property
    def sine_form(self) -> SineForm:
        return SineForm(self.amplitude, self.omega, self.phase, self.duration)

    def sample_times(self, samples_per_period: int = 200) -> np.ndarray:
        """``ceil(samples_per_period * duration * omega / 2 pi)`` intervals (at least 2) over
        [0, duration]."""
        n = math.ceil(samples_per_period * self.end_time * self.omega / (2 * math.pi))
        return np.linspace(0.0, self.end_time, max(n, 2) + 1)

    def acceleration_table(self, samples_per_period: int = 400) -> tuple[np.ndarray, np.ndarray]:
        """Sampled ``samples_per_period`` times per period over its duration (linear
        interpolation of the sine is then exact to 3e-5 of its amplitude)."""
        n = max(
            2,
            int(math.ceil(samples_per_period * self.duration * self.omega / (2.0 * math.pi))) + 1,
        )
        t = np.linspace(0.0, self.duration, n)
        return t, self.acceleration(t)

    def to_json(self) -> dict[str, Any]:
        return {
            "type": "harmonic_pulse",
            "kind": str(self.kind),
            "amplitude": float(self.amplitude),
            "omega": float(self.omega),
            "phase": float(self.phase),
            "duration": float(self.duration),
        }

    @classmethod
    def from_json(cls, data: dict[str, Any]) -> HarmonicPulse:
        return _fields_from_json(cls, data)


@motion_type("record")
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

    @property
    def moves(self) -> bool:
        return True

    @property
    def pulse_shape(self) -> None:
        return None

    @property
    def sine_form(self) -> None:
        return None

    def sample_times(self, samples_per_period: int = 200) -> np.ndarray:
        """The record's own sample times (``samples_per_period`` is a pulse's)."""
        return self.time.copy()

    def acceleration_table(self, samples_per_period: int = 400) -> tuple[np.ndarray, np.ndarray]:
        """The record as it is (``samples_per_period`` is a pulse's)."""
        return self.time.copy(), self.acceleration_values.copy()

    def to_json(self) -> dict[str, Any]:
        """Its samples inline: ``time`` and ``acceleration_values`` as lists, and its name."""
        return _fields_to_json(self)

    @classmethod
    def from_json(cls, data: dict[str, Any]) -> Record:
        return _fields_from_json(cls, data)


@motion_type("none")
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

    @property
    def moves(self) -> bool:
        return False

    @property
    def pulse_shape(self) -> None:
        return None

    @property
    def sine_form(self) -> None:
        return None

    def sample_times(self, samples_per_period: int = 200) -> np.ndarray:
        """No times: there is nothing to draw."""
        return np.zeros(0)

    def acceleration_table(self, samples_per_period: int = 400) -> None:
        return None

    def to_json(self) -> dict[str, Any]:
        return _fields_to_json(self)

    @classmethod
    def from_json(cls, data: dict[str, Any]) -> NoMotion:
        return _fields_from_json(cls, data)


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

MAX_RECORD_STEP = 0.02
"""s, the coarsest sampling step a record file may have (50 samples a second). Strong-motion
databases deliver 0.005 to 0.02 s (PEER NGA); at 0.02 s the band they keep (up to 25 Hz, the
Nyquist frequency) is there and a 5 Hz wave, where most of the energy of a record lies, has
10 samples a period (linear interpolation within 5 % of its peak). A coarser file has lost the
peaks that uplift and strike a column, and interpolating it does not bring them back."""

# m/s^2 per unit of a record file, by the names read_two_column's ``units`` takes; g stands
# for the reader's ``g``
UNITS = {"g": None, "m/s2": 1.0, "cm/s2": 0.01, "gal": 0.01, "mm/s2": 0.001}
KNOWN_UNITS = "g, cm/s^2 (gal), m/s^2, mm/s^2"

_AT2_HEADER = re.compile(
    r"NPTS\s*=\s*(?P<npts>\d+)\s*,?\s*DT\s*=\s*(?P<dt>[0-9.Ee+-]+)"
    r"|^\s*(?P<npts2>\d+)\s+(?P<dt2>[0-9.Ee+-]+)\s+NPTS",
    re.IGNORECASE | re.MULTILINE,
)
_UNITS_PHRASE = re.compile(r"\bUNITS?\s*(?:OF\b|IN\b|:|=)\s*(?P<unit>[^\s,;()]+)", re.IGNORECASE)


def _unit_name(text: str) -> str | None:
    """The :data:`UNITS` key of a unit as written in a header ('CM/SEC/SEC', 'cm/s^2', 'GAL',
    'G.'), or None."""
    unit = text.lower().rstrip(".:")
    for old, new in (("sec", "s"), ("**", ""), ("^", ""), ("\u00b2", "2"), ("gals", "gal")):
        unit = unit.replace(old, new)
    unit = re.sub(r"/s/s$", "/s2", unit)
    return unit if unit in UNITS else None


def _at2_units(path: Path, header: list[str]) -> str:
    """The :data:`UNITS` key the header lines of an AT2 file give ('UNITS OF G', ...)."""
    found: dict[str, int] = {}
    for lineno, line in enumerate(header, start=1):
        for match in _UNITS_PHRASE.finditer(line):
            unit = _unit_name(match.group("unit"))
            if unit is None:
                raise InputError(
                    f"record file {path}, line {lineno}: units {match.group('unit')!r} are not "
                    f"known (known: {KNOWN_UNITS})"
                )
            found.setdefault(unit, lineno)
    if not found:
        raise InputError(
            f"record file {path}: no 'UNITS OF ...' phrase in the header (lines 1-{len(header)}), "
            f"so the acceleration's units are unknown (known: {KNOWN_UNITS})"
        )
    if len({UNITS[u] for u in found}) > 1:  # gal and cm/s2 agree
        where = ", ".join(f"{u} on line {n}" for u, n in found.items())
        raise InputError(f"record file {path}: the header gives two units ({where})")
    return next(iter(found))


def _to_si(unit: str, g: float) -> float:
    """m/s^2 per unit of :data:`UNITS` ``unit``."""
    factor = UNITS[unit]
    return g if factor is None else factor


def _check_step(path: Path, dt: float) -> None:
    """A record file's sampling step must be :data:`MAX_RECORD_STEP` or finer."""
    if dt > MAX_RECORD_STEP * (1.0 + 1e-9):
        raise InputError(
            f"record file {path}: sampling step {dt:.6g} s ({1.0 / dt:.3g} Hz) is coarser than "
            f"{MAX_RECORD_STEP:g} s ({1.0 / MAX_RECORD_STEP:g} Hz), the least a record must be "
            "sampled at to keep the peaks that rock a column"
        )


def read_peer_at2(path, *, g: float = STANDARD_GRAVITY) -> Record:
    """Read a PEER NGA ``.AT2`` accelerogram into m/s^2, in the units its header states
    ('ACCELERATION TIME SERIES IN UNITS OF G'; also cm/s^2 or gal, m/s^2, mm/s^2); its DT must
    be :data:`MAX_RECORD_STEP` or finer."""
    path = Path(path)
    text = _read_text(path)
    lines = text.splitlines()
    for i, line in enumerate(lines[:10]):  # noqa: B007 (i: the header's line, after the loop)
        match = _AT2_HEADER.search(line)
        if match:
            npts = int(match.group("npts") or match.group("npts2"))
            dt_text = match.group("dt") or match.group("dt2")
            try:
                dt = float(dt_text)
            except ValueError:
                raise InputError(
                    f"record file {path}, line {i + 1}: DT = {dt_text!r} is not a number"
                ) from None
            break
    else:
        raise InputError(
            f"record file {path}: no 'NPTS=..., DT=...' header line in the first 10 "
            "lines (not a PEER AT2 file?)"
        )
    if not (0.0 < dt < math.inf) or npts < 2:
        raise InputError(f"record file {path}: NPTS = {npts}, DT = {dt:g} are not valid")
    try:
        values = np.array(" ".join(lines[i + 1 :]).split(), dtype=float)
    except ValueError:
        raise InputError(f"record file {path}: non-numeric value after the header") from None
    if values.size < npts:
        raise InputError(
            f"record file {path}: header says NPTS = {npts} but {values.size} values follow"
        )
    unit = _at2_units(path, lines[: i + 1])
    _check_step(path, dt)
    return Record(np.arange(npts) * dt, values[:npts] * _to_si(unit, g), name=path.stem)


def _last_digit(text: str) -> float:
    """The value of the last digit a number is printed with: '0.0050' -> 1e-4, '1.5E+01' -> 1."""
    try:
        exponent = Decimal(text).as_tuple().exponent
    except InvalidOperation:
        return 0.0
    return 10.0 ** min(exponent, 300) if isinstance(exponent, int) else 0.0  # '0e999'


def _check_uniform(path: Path, time: np.ndarray, printed: list[str], lines: list[int]) -> float:
    """The step of a uniformly sampled record's times; an InputError at a gap or an uneven step.

    The step is the median one; each step may differ from it by 1 % (clocks in single
    precision), more where the times are printed rounded (twice the last digit of the finer
    printed of the two, at most half the step): 0.0067, 0.0133, 0.02 stand for 0.02 / 3 s steps.
    A missing sample, a gap or a change of rate is refused."""
    steps = np.diff(time)
    dt = float(np.median(steps))
    digit = np.array([_last_digit(x) for x in printed])
    rounding = np.minimum(2.0 * np.minimum(digit[:-1], digit[1:]), 0.5 * dt)
    off = np.flatnonzero(np.abs(steps - dt) > rounding + 0.01 * dt)
    if off.size:
        k = int(off[0])
        raise InputError(
            f"record file {path}: the time step from t = {time[k]:g} s (line {lines[k]}) to "
            f"t = {time[k + 1]:g} s (line {lines[k + 1]}) is {steps[k]:.6g} s, the record's step "
            f"is {dt:.6g} s: gapped or non-uniform sampling is not interpolated (resample the "
            "record uniformly)"
        )
    return dt


_DECIMAL_COMMA = re.compile(r"[+-]?\d*,\d+(?:[eE][+-]?\d+)?")
_NUMBER = re.compile(r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?")
_COLUMN_SEPARATORS = "spaces, tabs, commas or semicolons"


def _separator_words(line: str) -> str:
    """How the columns of a line are separated, in words: "';'", 'tabs', 'spaces'."""
    return "';'" if ";" in line else "tabs" if "\t" in line else "spaces"


def _decimal_commas(path: Path, lineno: int, line: str) -> None:
    """An InputError where a line writes its numbers with decimal commas beside another column
    separator ('0,01;0,5', '0,01<tab>0,5', '0,01 0,5'): read as commas between columns, every
    time would be its integer part."""
    tokens = [x.strip(",") for x in re.split(r"[;\s]+", line) if x.strip(",")]
    comma = next((x for x in tokens if _DECIMAL_COMMA.fullmatch(x)), None)
    numbers = all(_DECIMAL_COMMA.fullmatch(x) or _NUMBER.fullmatch(x) for x in tokens)
    if len(tokens) >= 2 and comma is not None and numbers:  # not a header ('f = 1,5 Hz')
        raise InputError(
            f"record file {path}, line {lineno}: decimal commas in {line[:40]!r} (columns "
            f"separated by {_separator_words(line)}): use a point as the decimal separator, "
            f"{comma.replace(',', '.')} for {comma}"
        )


def _unknown_separator(path: Path, lineno: int, line: str) -> None:
    """An InputError where a line that is not numeric would be numbers with its columns
    separated by another character ('0.01|0.5', '0.01:0.5'): not a header line."""
    others = set(re.sub(r"[0-9.eE+\-,;\s]", "", line))
    if len(others) != 1:
        return
    mark = others.pop()
    number = r"\s*[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?\s*"
    if not re.fullmatch(rf"{number}(?:{re.escape(mark)}{number})+", line):  # a header: 'x1 x2'
        return
    raise InputError(
        f"record file {path}, line {lineno}: columns separated by {mark!r} ({line[:40]!r}): "
        f"separate them by {_COLUMN_SEPARATORS}"
    )


def _check_increasing(path: Path, time: np.ndarray, texts: list[str], lines: list[int]) -> None:
    """An InputError naming the first line whose time is not after the line before it; where
    those lines have commas and no point, the likely cause: decimal commas between columns
    separated by commas ('0,01,0,5' reads as time 0)."""
    stops = np.flatnonzero(np.diff(time) <= 0.0)
    if not stops.size:
        return
    k = int(stops[0])
    where = f"record file {path}, line {lines[k + 1]}"
    if all("," in texts[i] and not re.search(r"[.eE]", texts[i]) for i in (k, k + 1)):
        raise InputError(
            f"{where}: decimal commas ({texts[k + 1][:40]!r} reads as time {time[k + 1]:g} s, "
            f"as line {lines[k]} does): use a point as the decimal separator"
        )
    raise InputError(
        f"{where}: time {time[k + 1]:g} s is not after {time[k]:g} s on line {lines[k]}: time "
        "must increase strictly"
    )


def read_two_column(path, *, units: str = "m/s2", g: float = STANDARD_GRAVITY) -> Record:
    """Read ``time, acceleration`` rows (comma, semicolon or whitespace separated; '#' comments
    and non-numeric header lines are skipped). ``units``: one of :data:`UNITS` ('m/s2', 'g',
    'cm/s2', 'gal', 'mm/s2'). The times must increase, uniformly spaced,
    :data:`MAX_RECORD_STEP` or finer. Decimal commas, another column separator and a time that
    does not increase are an InputError naming the line and the cause."""
    path = Path(path)
    if units not in UNITS:
        raise InputError(f"units = {units!r} is not one of {', '.join(UNITS)}")
    rows: list[list[float]] = []
    printed: list[str] = []  # the times as written, for their rounding
    texts: list[str] = []  # the data lines as written
    lines: list[int] = []
    for lineno, line in enumerate(_read_text(path).splitlines(), start=1):
        line = line.split("#", 1)[0].strip()
        if not line:
            continue
        _decimal_commas(path, lineno, line)
        parts = [x for x in re.split(r"[,;\s]+", line) if x]
        try:
            values = [float(x) for x in parts]
        except ValueError:
            _unknown_separator(path, lineno, line)
            if not rows:  # a header line
                continue
            raise InputError(f"record file {path}, line {lineno}: not numeric: {line!r}") from None
        if len(values) < 2:
            raise InputError(
                f"record file {path}, line {lineno}: needs two columns (time, acceleration)"
            )
        rows.append(values[:2])
        printed.append(parts[0])
        texts.append(line)
        lines.append(lineno)
    if len(rows) < 2:
        raise InputError(f"record file {path}: fewer than two data rows")
    data = np.array(rows)
    _check_increasing(path, data[:, 0], texts, lines)
    record = Record(data[:, 0], data[:, 1] * _to_si(units, g), name=path.stem)
    _check_step(path, _check_uniform(path, record.time, printed, lines))
    return record


ESM_PGA_TOLERANCE = 0.02  # relative: an ESM header's PGA_CM/S^2 against max |sample|
_ESM_KEY = re.compile(r"^(?P<key>[A-Z][A-Z0-9_/^.\-]*)\s*:(?P<value>.*)$")


def _esm_number(path: Path, header: dict[str, str], key: str) -> float:
    if key not in header:
        raise InputError(f"ESM file {path}: the header has no {key} line (not an ESM file?)")
    try:
        return float(header[key])
    except ValueError:
        raise InputError(f"ESM file {path}: {key} = {header[key]!r} is not a number") from None


def read_esm_file(path, *, g: float = STANDARD_GRAVITY) -> tuple[Record, dict[str, str]]:
    """Read an ESM ASCII accelerogram (Engineering Strong-Motion database; the format is
    described in :mod:`colonna.core.esm`): the record in m/s^2, in the units of the header's
    ``UNITS``, sampled at ``SAMPLING_INTERVAL_S`` from t = 0, and the header (``KEY: value``
    lines, the key ending at the first colon). An InputError names the file and the key: no
    ``SAMPLING_INTERVAL_S``, ``NDATA`` or ``UNITS``; units not known; a ``DATA_TYPE`` other
    than ACCELERATION; not ``NDATA`` samples; a non-numeric sample; a step coarser than
    :data:`MAX_RECORD_STEP`; samples whose peak is not the header's ``PGA_CM/S^2`` (within
    :data:`ESM_PGA_TOLERANCE`: the header's units or the samples are wrong)."""
    path = Path(path)
    lines = _read_text(path).splitlines()
    header: dict[str, str] = {}
    first = len(lines)  # the first data line
    for i, line in enumerate(lines):
        match = _ESM_KEY.match(line.strip())
        if match is None:
            first = i
            break
        key = match.group("key")
        if key in header:
            raise InputError(f"ESM file {path}, line {i + 1}: header key {key} appears twice")
        header[key] = match.group("value").strip()
    if not header:
        raise InputError(f"ESM file {path}: no 'KEY: value' header lines (not an ESM file?)")
    data_type = header.get("DATA_TYPE", "ACCELERATION").upper()
    if data_type != "ACCELERATION":
        raise InputError(
            f"ESM file {path}: DATA_TYPE = {data_type!r}: only ACCELERATION files are ground "
            "motions (take the acceleration file of this record)"
        )
    dt = _esm_number(path, header, "SAMPLING_INTERVAL_S")
    ndata = _esm_number(path, header, "NDATA")
    if not 0.0 < dt < math.inf:
        raise InputError(f"ESM file {path}: SAMPLING_INTERVAL_S = {dt:g} must be > 0 s")
    if ndata != int(ndata) or ndata < 2:
        raise InputError(f"ESM file {path}: NDATA = {header['NDATA']} must be an integer >= 2")
    if "UNITS" not in header:
        raise InputError(
            f"ESM file {path}: the header has no UNITS line, so the acceleration's units are "
            f"unknown (known: {KNOWN_UNITS})"
        )
    unit = _unit_name(header["UNITS"])
    if unit is None:
        raise InputError(
            f"ESM file {path}: UNITS = {header['UNITS']!r} is not known (known: {KNOWN_UNITS})"
        )
    values: list[float] = []
    for lineno, line in enumerate(lines[first:], start=first + 1):
        try:
            values.extend(float(x) for x in line.split())
        except ValueError:
            raise InputError(
                f"ESM file {path}, line {lineno}: not numeric: {line.strip()[:40]!r}"
            ) from None
    if len(values) != ndata:
        raise InputError(f"ESM file {path}: NDATA = {int(ndata)} but {len(values)} samples follow")
    _check_step(path, dt)
    acceleration = np.array(values) * _to_si(unit, g)
    if header.get("PGA_CM/S^2"):
        pga = abs(_esm_number(path, header, "PGA_CM/S^2")) * 0.01  # m/s^2
        peak = float(np.max(np.abs(acceleration)))
        if abs(peak - pga) > ESM_PGA_TOLERANCE * max(pga, peak):
            raise InputError(
                f"ESM file {path}: PGA_CM/S^2 = {pga * 100:g} in the header, but the samples "
                f"read in {header['UNITS']} peak at {peak * 100:.6g} cm/s^2: the header's "
                "units or the samples are wrong"
            )
    return Record(np.arange(int(ndata)) * dt, acceleration, name=path.stem), header


def is_esm(path) -> bool:
    """True where a file's first line is an ESM header's first (``EVENT_NAME: ...``)."""
    try:
        with open(path, errors="replace") as stream:
            first = stream.readline()
    except OSError:
        return False
    return first.lstrip().upper().startswith("EVENT_NAME:")


def read_record(path, *, g: float = STANDARD_GRAVITY) -> Record:
    """Read a record by its format: ``.at2`` as PEER NGA; ``.asc``, or any file whose first
    line is ``EVENT_NAME: ...``, as ESM ASCII (units from the header); anything else as two
    columns (m/s^2)."""
    path = Path(path)
    if path.suffix.lower() == ".at2":
        return read_peer_at2(path, g=g)
    if path.suffix.lower() == ".asc" or is_esm(path):
        return read_esm_file(path, g=g)[0]
    return read_two_column(path, g=g)


class RecordNote(UserWarning):
    """A note on a record that is not an error: one that never uplifts the column."""


def uplift_margin(motion, uplift_acceleration: float) -> float:
    """The motion's peak |acceleration| over the uplift acceleration (both m/s^2): below 1, a
    rigid block at rest is never uplifted by it (horizontal motion alone)."""
    require_positive("uplift acceleration (m/s^2)", uplift_acceleration)
    return peak_acceleration(motion) / uplift_acceleration


def weak_record_note(
    record: Record,
    uplift_acceleration: float,
    *,
    what: str | None = None,
    scale: float = 1.0,
    scale_name: str = "scale",
    uplift_text: str = "g tan(alpha)",
    in_m_s2: bool = False,
    g: float = STANDARD_GRAVITY,
) -> str | None:
    """One line saying that ``record`` (already times ``scale``) never reaches the uplift
    acceleration, so that the column stays at rest; None if it does. ``in_m_s2``: the file was
    read as m/s^2 without saying so (two columns), and the line says what its peak would be in g
    where that would rock the column."""
    if uplift_margin(record, uplift_acceleration) >= 1.0:
        return None
    peak = record.peak_acceleration
    what = what or f"record {record.name!r}"
    note = (
        f"{what} peaks at {peak:.3g} m/s^2 ({scale_name} = {scale:g} included), below the "
        f"uplift acceleration {uplift_text} = {uplift_acceleration:.3g} m/s^2: the record "
        "alone does not uplift the column, which stays at rest"
    )
    as_written = peak / abs(scale) if scale else 0.0
    if in_m_s2 and 0.0 < as_written <= 2.0 and peak * g >= uplift_acceleration:
        note += (
            f"; if the file's accelerations are in g (it is read in m/s^2), set "
            f"{scale_name} = {scale * g:.4g}"
        )
    return note


def _read_text(path: Path) -> str:
    try:
        return path.read_text(errors="replace")
    except OSError as exc:
        raise InputError(f"record file {path} cannot be read: {exc.strerror}") from None


def acceleration_table(motion, samples_per_period: int = 400):
    """(time (s), acceleration (m/s^2)) of a ground motion as a piecewise-linear table, zero
    outside it (the motion's own ``acceleration_table``): a record as it is, a harmonic pulse
    sampled ``samples_per_period`` times per period over its duration (linear interpolation of
    the sine is then exact to 3e-5 of its amplitude). NoMotion: None."""
    if not isinstance(motion, GroundMotion):
        raise InputError(f"ground motion of type {type(motion).__name__} is not supported")
    return motion.acceleration_table(samples_per_period)


def kernel_tables(
    ground: GroundMotion, vertical: GroundMotion = NO_MOTION, horizontal_scale: float = 1.0
):
    """The tables the compiled solvers read the ground from, one pair of arrays: the
    horizontal motion's table (times ``horizontal_scale``; none for a motion with a
    ``sine_form``, which the kernels compute, or for no motion) followed by the vertical
    motion's table (:func:`acceleration_table`), m/s^2. Returns (times, accelerations, rows of
    the horizontal table, whether vertical rows follow); never empty arrays (numba wants one
    element)."""
    times = values = np.zeros(0)
    if ground.sine_form is None:
        horizontal = acceleration_table(ground)
        if horizontal is not None:
            times, values = horizontal[0], horizontal_scale * horizontal[1]
        elif ground.moves:
            raise InputError(
                f"ground motion of type {type(ground).__name__} moves but gives neither a "
                "sine_form nor an acceleration_table"
            )
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
    if isinstance(motion, GroundMotion) and motion.moves:
        return motion.peak_acceleration
    raise InputError("the study needs a ground motion (a pulse or a record) here, not 'none'")

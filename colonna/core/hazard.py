"""The site's seismic hazard: the mean annual frequency lambda_IM(x) at which an intensity
measure IM exceeds x, as national hazard models publish it.

Two forms:

* a table (:func:`read_hazard`): a CSV of two columns, the intensity and its annual frequency of
  exceedance, e.g. PGA at the return periods 30-2475 years of a grid point. The header names
  the intensity measure and its unit, ``pga_g``, ``pga_m_s2``, ``pga_cm_s2``, ``pgv_m_s``,
  ``pgv_cm_s``, ``sa_0.5s_g`` (Sa(0.5 s), 5 % damped; ``_m_s2``, ``_cm_s2``), and then
  ``annual_frequency`` (1/year); ``#`` lines are notes (the table's source). Between its points
  lambda is interpolated linearly in log-log (a power law on each segment, the form hazard
  curves take locally: Cornell et al. 2002). Below its lowest intensity it is held at that
  point's frequency: the table says nothing of weaker shaking, and a power law continued
  there grows without bound (the rate of all earthquakes is finite), so the part of a risk
  read there is a lower bound. Above its highest it is either extrapolated by the power law
  of the end segment or truncated (zero: every exceedance of the highest counted there, a
  lower bound), whichever the curve's ``beyond`` says; the risk says how much of it lies
  beyond either end (:mod:`colonna.core.risk`);
* a power law (:func:`power_law`): ``lambda(x) = k0 x^-k`` (x in SI), Cornell et al. (2002)'s
  approximation, for which the risk has a closed form.

:func:`in_measure` gives the curve in a fragility's intensity measure: the same measure, or its
rocking-normalised form (PGA / a_up, PGV p / a_up: a change of variable x' = c x, so that
lambda'(x') = lambda(x' / c)); any other pairing is refused.

Reference: C. A. Cornell, F. Jalayer, R. O. Hamburger, D. A. Foutch (2002), Probabilistic basis
for 2000 SAC Federal Emergency Management Agency steel moment frame guidelines, Journal of
Structural Engineering 128(4), 526-533.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from .constants import STANDARD_GRAVITY
from .errors import InputError

__all__ = [
    "HAZARD_MEASURES",
    "HazardCurve",
    "annual_frequency",
    "in_measure",
    "log_annual_frequency",
    "power_law",
    "read_hazard",
]

HAZARD_MEASURES = {"pga": "m/s^2", "pgv": "m/s", "sa": "m/s^2"}  # a hazard's IM -> SI unit
# a header's unit -> (SI unit, SI per one of it)
HEADER_UNITS = {
    "m_s2": ("m/s^2", 1.0),
    "g": ("m/s^2", STANDARD_GRAVITY),
    "cm_s2": ("m/s^2", 0.01),
    "m_s": ("m/s", 1.0),
    "cm_s": ("m/s", 0.01),
}
HEADER = re.compile(
    r"^(?P<im>pga|pgv|sa_(?P<period>\d+(?:\.\d+)?)s)_(?P<unit>m_s2|g|cm_s2|m_s|cm_s)$"
)
FREQUENCY_HEADER = "annual_frequency"
BEYOND = ("extrapolate", "truncate")


@dataclass(frozen=True)
class HazardCurve:
    """A hazard curve: the ``intensity`` measure (``pga``, ``pgv``, ``sa``, or a fragility's
    measure after :func:`in_measure`) in ``unit`` (SI; ``-`` normalised), the Sa ``period``
    (s), either the table (``im`` increasing, ``frequency`` decreasing, 1/year) or the power law
    (``k0``, ``k``: lambda = k0 x^-k), what lies ``beyond`` the table's highest intensity
    ("extrapolate" or "truncate"), its ``source`` (the file, or the law) and ``notes`` (the
    file's # lines)."""

    intensity: str
    unit: str
    im: tuple[float, ...] = ()
    frequency: tuple[float, ...] = ()
    k0: float | None = None
    k: float | None = None
    period: float | None = None
    beyond: str = "extrapolate"
    source: str = ""
    notes: tuple[str, ...] = ()

    @property
    def tabulated(self) -> bool:
        """True for a table, False for a power law."""
        return self.k0 is None

    @property
    def range(self) -> tuple[float, float]:
        """(lowest, highest) intensity the curve is given at: the table's ends; (0, inf) for a
        power law."""
        return (self.im[0], self.im[-1]) if self.tabulated else (0.0, math.inf)

    def slopes(self) -> np.ndarray:
        """k of each segment of the table, -d ln lambda / d ln x (the power law's k)."""
        if self.k is not None:
            return np.array([self.k])
        return -np.diff(np.log(self.frequency)) / np.diff(np.log(self.im))

    def to_dict(self) -> dict:
        return {
            "intensity": self.intensity,
            "unit": self.unit,
            "period": self.period,
            "form": "table" if self.tabulated else "power law",
            "im": list(self.im),
            "frequency": list(self.frequency),
            "k0": self.k0,
            "k": self.k,
            "beyond": self.beyond,
            "source": self.source,
            "notes": list(self.notes),
        }


def _check_beyond(beyond: str) -> None:
    if beyond not in BEYOND:
        raise InputError(f"hazard beyond = {beyond!r}: allowed {', '.join(BEYOND)}")


def read_hazard(path, *, beyond: str = "extrapolate") -> HazardCurve:
    """The hazard table of the CSV file ``path`` (see the module's docstring), in SI; an
    InputError naming the file and line of the first fault: a header that names no intensity
    measure and unit, a row that is not two numbers, an intensity or frequency not > 0, an
    intensity that does not increase down the file or a frequency that does not decrease, fewer
    than two rows."""
    _check_beyond(beyond)
    path = Path(path)
    try:
        lines = path.read_text().splitlines()
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"hazard file {path}: cannot be read ({exc})") from None
    notes: list[str] = []
    header = None
    rows: list[tuple[int, float, float]] = []
    for number, line in enumerate(lines, start=1):
        text = line.strip()
        if not text:
            continue
        if text.startswith("#"):
            notes.append(text.lstrip("#").strip())
            continue
        cells = [c.strip() for c in text.split(",")]
        where = f"hazard file {path}, line {number}"
        if header is None:
            header = _header(cells, where)
            continue
        if len(cells) != 2:
            raise InputError(f"{where}: {text!r} is not two numbers (intensity, frequency)")
        try:
            x, f = float(cells[0]), float(cells[1])
        except ValueError:
            raise InputError(
                f"{where}: {text!r} is not two numbers (intensity, frequency)"
            ) from None
        if not (0.0 < x < math.inf and 0.0 < f < math.inf):
            raise InputError(
                f"{where}: intensity {cells[0]} and annual frequency {cells[1]} must both be > 0 "
                "and finite (log-log interpolation)"
            )
        if rows and not x > rows[-1][1]:
            raise InputError(
                f"{where}: intensity {x:g} is not above the previous row's {rows[-1][1]:g}: the "
                "intensities must increase down the file"
            )
        if rows and not f < rows[-1][2]:
            raise InputError(
                f"{where}: annual frequency {f:g} is not below the previous row's "
                f"{rows[-1][2]:g}: a hazard curve's frequency of exceedance falls as the "
                "intensity rises (non-monotonic)"
            )
        rows.append((number, x, f))
    if header is None or len(rows) < 2:
        raise InputError(
            f"hazard file {path}: {len(rows)} rows of data: a hazard curve needs a header "
            f"(e.g. pga_m_s2,{FREQUENCY_HEADER}) and two or more rows"
        )
    measure, period, unit, factor = header
    return HazardCurve(
        measure,
        unit,
        im=tuple(x * factor for _, x, _ in rows),
        frequency=tuple(f for _, _, f in rows),
        period=period,
        beyond=beyond,
        source=str(path),
        notes=tuple(notes),
    )


def _header(cells: list[str], where: str) -> tuple[str, float | None, str, float]:
    """(measure, Sa period, SI unit, SI per the file's unit) of a hazard file's header."""
    names = ", ".join(HEADER_UNITS)
    match = HEADER.match(cells[0].lower()) if cells else None
    if len(cells) != 2 or match is None or cells[1].lower() != FREQUENCY_HEADER:
        raise InputError(
            f"{where}: the header {','.join(cells)!r} must name the intensity measure and its "
            f"unit, then {FREQUENCY_HEADER}: e.g. pga_g,{FREQUENCY_HEADER} (measures pga, pgv, "
            f"sa_<period>s; units {names})"
        )
    measure = "sa" if match["period"] else match["im"]
    unit, factor = HEADER_UNITS[match["unit"]]
    if unit != HAZARD_MEASURES[measure]:
        raise InputError(
            f"{where}: {cells[0]!r}: {measure} is in {HAZARD_MEASURES[measure]}, not "
            f"{match['unit']}"
        )
    period = float(match["period"]) if match["period"] else None
    if period is not None and not period > 0.0:
        raise InputError(f"{where}: {cells[0]!r}: the Sa period must be > 0")
    return measure, period, unit, factor


def power_law(k0: float, k: float, intensity: str, *, period: float | None = None) -> HazardCurve:
    """The power-law hazard ``lambda(x) = k0 x^-k`` (x in the SI unit of ``intensity``,
    lambda in 1/year; Cornell et al. 2002, Eq. 7)."""
    if intensity not in HAZARD_MEASURES:
        raise InputError(f"hazard intensity = {intensity!r}: allowed {', '.join(HAZARD_MEASURES)}")
    for name, value in (("k0", k0), ("k", k)):
        if not (0.0 < value < math.inf):
            raise InputError(f"hazard {name} = {value:g} must be > 0 and finite")
    if (intensity == "sa") != (period is not None):
        raise InputError("hazard period goes with intensity = 'sa', and only with it")
    return HazardCurve(
        intensity,
        HAZARD_MEASURES[intensity],
        k0=float(k0),
        k=float(k),
        period=period,
        source=f"power law lambda = {k0:g} x^-{k:g}",
    )


def annual_frequency(curve: HazardCurve, x) -> np.ndarray:
    """lambda(x), 1/year (array): the power law; or the table interpolated linearly in log-log,
    held at its lowest point's frequency below it, and above its highest as ``curve.beyond``
    says (the module's docstring)."""
    x = np.asarray(x, dtype=float)
    with np.errstate(divide="ignore"):
        return np.exp(log_annual_frequency(curve, np.log(x)))


def log_annual_frequency(curve: HazardCurve, log_x) -> np.ndarray:
    """ln lambda at ln x = ``log_x`` (:func:`annual_frequency` in logs: finite where lambda
    itself would overflow; -inf where lambda is 0)."""
    lx = np.asarray(log_x, dtype=float)
    if curve.k0 is not None and curve.k is not None:
        return math.log(curve.k0) - curve.k * lx
    li, lf = np.log(curve.im), np.log(curve.frequency)
    inside = np.interp(lx, li, lf)  # (held at lf[0] below the table)
    if curve.beyond == "extrapolate":
        above = lf[-1] - curve.slopes()[-1] * (lx - li[-1])
        return np.where(lx > li[-1], above, inside)
    return np.where(lx > li[-1], -np.inf, inside)


def in_measure(
    curve: HazardCurve,
    measure: str,
    base: str,
    factor: float,
    unit: str,
    *,
    period: float | None = None,
) -> HazardCurve:
    """The hazard in a fragility's intensity ``measure`` (unit ``unit``), which is ``factor``
    times the hazard's measure ``base`` (1 for the same measure; 1 / a_up for PGA / a_up):
    x' = factor x, lambda'(x') = lambda(x' / factor), the power law's k0' = k0 factor^k. An
    InputError where ``base`` is not the curve's measure, or an Sa of another period."""
    if curve.intensity != base:
        raise InputError(
            f"the hazard is of {curve.intensity.upper()} ({curve.unit}) and the fragility's "
            f"intensity {measure!r} is of {base.upper()}: a hazard and a fragility must be of one "
            "intensity measure"
        )
    if base == "sa" and not math.isclose(curve.period or 0.0, period or -1.0, rel_tol=1e-9):
        raise InputError(
            f"the hazard is of Sa({curve.period:g} s) and the fragility's of Sa({period:g} s): "
            "a hazard and a fragility must be of one period"
        )
    if not (0.0 < factor < math.inf):
        raise InputError(f"the intensity's factor {factor:g} must be > 0 and finite")
    if curve.k0 is not None and curve.k is not None:
        return replace(curve, intensity=measure, unit=unit, k0=curve.k0 * factor**curve.k)
    return replace(curve, intensity=measure, unit=unit, im=tuple(factor * x for x in curve.im))

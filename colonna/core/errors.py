"""colonna's errors, by kind, and the input checks that fail with one line naming the parameter
and its allowed range.

Each kind of failure has its class (as meshio separates read, write and corruption errors), all
under :class:`ColonnaError`, so that a caller catches what it can act on:

* :class:`InputError`: bad input (a value out of range, a file that cannot be read); also a
  ``ValueError``. Fix the input.
* :class:`StaleResultsError`: results saved in an output folder from other inputs (another
  study file, record or colonna version), refused rather than reused. Recompute (``--force``) or
  choose another folder. A damaged saved result is no error: it is computed again.
* :class:`NumericalFailure`: a run whose numbers are not an answer (a blow-up, an energy
  balance past its limit). Its input was accepted; the model or its settings did not hold.

The command line ends each with one line ``colonna: error: ...`` and exit status 2.
"""

from __future__ import annotations

import math
import tomllib
from pathlib import Path


class ColonnaError(Exception):
    """Base class of the errors colonna raises on purpose; the message is for people."""


class InputError(ColonnaError, ValueError):
    """Bad user input. The message names the parameter and the allowed range."""


class StaleResultsError(ColonnaError):
    """Results in an output folder were saved from other inputs (or without a record of them)
    and are not reused; the message names the first case and the first difference."""


class NumericalFailure(ColonnaError):
    """A computation whose result is not an answer: it blew up, or its energy balance is off
    past its limit. The message says which run and why."""


def require_positive(name: str, value: float) -> float:
    value = _as_float(name, value)
    if not 0.0 < value < math.inf:
        raise InputError(f"{name} = {value:g} is not allowed: it must be > 0 and finite")
    return value


def require_non_negative(name: str, value: float) -> float:
    value = _as_float(name, value)
    if not 0.0 <= value < math.inf:
        raise InputError(f"{name} = {value:g} is not allowed: it must be >= 0 and finite")
    return value


MAX_HISTORY_ROWS = 10_000_000  # rows of a time history kept in memory (a few GB at most)


def require_history_rows(duration: float, interval: float) -> int:
    """The rows of a history of ``duration`` (s) sampled every ``interval`` (s), or an
    InputError naming both where they exceed MAX_HISTORY_ROWS."""
    rows = duration / interval + 2.0  # a float: a tiny interval overflows no int
    if not rows <= MAX_HISTORY_ROWS:
        raise InputError(
            f"duration = {duration:g} s at an output interval of {interval:g} s gives {rows:.3g} "
            f"history rows: at most {MAX_HISTORY_ROWS:,} (shorten the duration)"
        )
    return int(rows)


def require_range(
    name: str,
    value: float,
    low: float,
    high: float,
    *,
    closed_low: bool = False,
    closed_high: bool = False,
    range_text: str | None = None,
) -> float:
    """Check low < value < high (ends included where asked)."""
    value = _as_float(name, value)
    ok_low = value >= low if closed_low else value > low
    ok_high = value <= high if closed_high else value < high
    if not (ok_low and ok_high):
        if range_text is None:
            range_text = (
                ("[" if closed_low else "(") + f"{low:g}, {high:g}" + ("]" if closed_high else ")")
            )
        raise InputError(f"{name} = {value:g} is outside the allowed range {range_text}")
    return value


def _as_float(name: str, value) -> float:
    try:
        value = float(value)
    except (TypeError, ValueError):
        raise InputError(f"{name} = {value!r} is not a number") from None
    if math.isnan(value):
        raise InputError(f"{name} is NaN")
    return value


def read_toml(path, what: str = "file") -> dict:
    """Parse a TOML file; an unreadable or malformed one is an InputError naming it."""
    return read_toml_bytes(path, what)[1]


def read_toml_bytes(path, what: str = "file") -> tuple[bytes, dict]:
    """A TOML file's bytes (to put on record or hash) and its tables, from one read; an
    unreadable or malformed one is an InputError naming it."""
    path = Path(path)
    try:
        raw = path.read_bytes()
    except OSError as exc:
        raise InputError(f"{what} {path} cannot be read: {exc.strerror}") from None
    try:
        return raw, tomllib.loads(raw.decode())
    except UnicodeDecodeError:
        raise InputError(f"{what} {path} is not UTF-8 text (a binary file?)") from None
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"{what} {path} is not valid TOML: {exc}") from None

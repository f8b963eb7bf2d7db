"""Input checks that fail with one line naming the parameter and its allowed range."""

from __future__ import annotations

import math
import tomllib
from pathlib import Path


class InputError(ValueError):
    """Bad user input. The message names the parameter and the allowed range."""


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
    path = Path(path)
    try:
        return tomllib.loads(path.read_text())
    except OSError as exc:
        raise InputError(f"{what} {path} cannot be read: {exc.strerror}") from None
    except UnicodeDecodeError:
        raise InputError(f"{what} {path} is not UTF-8 text (a binary file?)") from None
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"{what} {path} is not valid TOML: {exc}") from None

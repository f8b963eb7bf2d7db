"""The FEM's weak-tail stop gives the answers of the full run (issue 37, the FEM's cost on
long records).

Pinned: where the weak tail of a motion starts (the last step at which the ground reaches the
weak level, against the closed form of a sine segment); a run that rocks the column and then
lets it settle under a weak tail stops in the tail, its history up to the stop the full run's
bits, and the full run, carried on to the end, never rocks again (every body below the seated
tilt), stays below half the tipping work, and has the same peaks and limit states; a run
that never rocks is not stopped in its weak tail, which may sway it more than the strong
motion did.
"""

import dataclasses
import math
import tomllib

import numpy as np
import pytest

from colonna.core.ground import NO_MOTION, Record
from colonna.fem.solver import (
    SEATED_TILT,
    WEAK_TAIL_MARGIN,
    weak_ground_level,
    weak_tail_start,
)
from colonna.studies.fem_study import from_dict
from colonna.studies.fragility import analysis
from colonna.studies.fragility.models import fem_point
from colonna.studies.models import build, iter_fem, run_fem

# a small cracked column with one collar, cheap to run (66 nodes)
COLUMN = """
[study]
name = "weak-tail"
[column]
height = 1.0
width = 0.2
cracked = true
[[collar]]
y = 0.5
t = 0.004
h = 0.02
[ground]
pulse = "sine"
amplitude_ratio = 1.5
omega_ratio = 3.0
[mesh]
size = 0.1
grading = 0.0
[run]
duration = 1.0
output_interval = 0.005
"""
ALPHA_B = math.atan2(0.1, 1.0)  # a half's slenderness angle
UPLIFT = 9.81 * math.tan(ALPHA_B)  # a half's uplift acceleration g tan(alpha_b), m/s^2


def _record(parts, dt: float = 0.002) -> Record:
    """Sine segments one after the other: (duration s, amplitude / g tan(alpha_b), period s),
    each a whole number of half periods (no jump between them)."""
    t, a, start = [0.0], [0.0], 0.0
    for duration, ratio, period in parts:
        local = np.arange(dt, duration + 0.5 * dt, dt)
        t.extend(start + local)
        a.extend(ratio * UPLIFT * np.sin(2.0 * math.pi * local / period))
        start += duration
    return Record(np.array(t), np.array(a), "segments")


@pytest.fixture(scope="module")
def column():
    return from_dict(tomllib.loads(COLUMN))


# rest-level motion, one strong cycle that rocks the column, then a long weak tail
ROCKS_THEN_WEAK = [(0.2, 0.3, 0.1), (0.3, 1.8, 0.3), (2.8, 0.3, 0.1)]


def test_the_weak_tail_starts_after_the_last_step_at_the_weak_level(column):
    """The weak level is a half's g tan(alpha_b) over the margin; the tail starts at the step
    after the last step time at which |a_g| reaches it: in the strong segment
    1.8 sin(2 pi tau / 0.3) of ROCKS_THEN_WEAK its last such time is tau = 0.3 (1 - asin(r) /
    (2 pi)), r = (1 / margin) / 1.8, closed form within one record sample (linear
    interpolation); a vertical motion that lowers gravity lowers the level."""
    model = build(column)
    level = weak_ground_level(model)
    assert level == pytest.approx(UPLIFT / WEAK_TAIL_MARGIN, rel=1e-12)
    record = _record(ROCKS_THEN_WEAK)
    dt = 1e-5
    steps = int(record.end_time / dt)
    start = weak_tail_start(record, NO_MOTION, level, 9.81, 0.0, dt, steps)
    r = (1.0 / WEAK_TAIL_MARGIN) / 1.8
    closed = 0.2 + 0.3 * (1.0 - math.asin(r) / (2.0 * math.pi))
    assert abs(start - closed) < 0.002
    n = round(start / dt)
    assert abs(record.acceleration(np.array([(n - 1) * dt]))[0]) >= level
    later = np.abs(record.acceleration(dt * np.arange(n, steps)))
    assert later.max() < level
    # a constant vertical acceleration of g / 4 lowers the level to 3/4 (still above the
    # tail's 0.3): the tail then starts where |a_g| last reaches 3/4 of the level
    down = Record(np.array([0.0, 10.0]), np.array([0.25 * 9.81] * 2), "vertical")
    lower = weak_tail_start(record, down, level, 9.81, 0.0, dt, steps)
    closed = 0.2 + 0.3 * (1.0 - math.asin(0.75 * r) / (2.0 * math.pi))
    assert lower > start and abs(lower - closed) < 0.002
    # a ground that stays weak throughout: the tail is the whole run
    assert weak_tail_start(record.scaled(0.1), NO_MOTION, level, 9.81, 0.0, dt, steps) == 0.0


def _runs(column, record):
    """The full run of the record (to its end) and the run with the weak-tail stop."""
    study = dataclasses.replace(column, ground=record, duration=record.end_time)
    full = run_fem(study, replicas=1)[0]
    settled = dataclasses.replace(study, stop_when_settled=True)
    [(_, stopped)] = list(iter_fem([settled], stop_in_weak_tail=True))
    return full, stopped


SAME = (
    "overturned",
    "max_abs_theta_left",
    "max_abs_theta_right",
    "collar_max_utilisation",
    "edge_stress_max",
    "toe_pressure_max",
    "collar_max_fibre_strain",
)


def test_a_run_that_rocks_then_settles_in_a_weak_tail_stops_with_the_full_run_s_answers(column):
    """The strong cycle rocks the column (|theta| well past the seated tilt); in the weak tail
    it settles and the run stops long before the record ends. The full run agrees bit for bit
    up to the stop; after it the full run never rocks again (every body below the seated tilt),
    its energy above rest stays below half the work that tips a half onto its toe, and its
    peaks and limit states are the stopped run's."""
    record = _record(ROCKS_THEN_WEAK)
    full, stopped = _runs(column, record)
    status = stopped.summary["status"]
    assert status.startswith("settled") and "weak tail" in status
    n = stopped.history["t"].size
    assert stopped.history["t"][-1] < record.end_time - 0.5
    for key in ("theta_left", "theta_right", "energy_total", "edge_stress_left"):
        assert np.array_equal(full.history[key][:n], stopped.history[key])
    theta = np.maximum(np.abs(full.history["theta_left"]), np.abs(full.history["theta_right"]))
    assert theta[:n].max() > 2.0 * SEATED_TILT * ALPHA_B  # it rocked
    assert theta[n:].max() < SEATED_TILT * ALPHA_B  # and never again
    # the weak ground still does work on the elastic column, but the energy above rest stays
    # below half the work that tips a half onto its toe (the settled-stop's bound)
    model = build(column)
    half_mass = model.mass[0::2].sum() / 2.0
    tipping = half_mass * 9.81 * 0.5 * math.hypot(0.1, 1.0) * (1.0 - math.cos(ALPHA_B))
    energy = full.history["energy_total"] - full.history["energy_total"][0]
    assert energy[n:].max() < 0.5 * tipping
    for key in SAME:
        assert full.summary.get(key) == stopped.summary.get(key), key
    _same_limit_states(column, full, stopped)


def test_a_run_that_never_rocks_is_not_stopped_in_its_weak_tail_which_may_sway_it_more(
    column,
):
    """A ground of 1.2 g tan(alpha_b) (below the 1.8 that rocks this column) only sways it on
    its bed, and the weak tail after it sways it more (0.0011 against 0.00056 rad: the tail's
    period sits nearer the sway's): the peaks of a run that never rocked may still come, so the
    weak-tail stop leaves it to the end, the same run as without it."""
    record = _record([(0.2, 0.3, 0.1), (0.3, 1.2, 0.3), (1.0, 0.3, 0.1)])
    full, stopped = _runs(column, record)
    assert "weak tail" not in stopped.summary["status"]  # (settled once the record ends)
    assert np.array_equal(full.history["theta_left"], stopped.history["theta_left"])
    theta = np.maximum(np.abs(full.history["theta_left"]), np.abs(full.history["theta_right"]))
    assert theta.max() < 0.5 * SEATED_TILT * ALPHA_B  # it never rocked
    tail = full.history["t"] > 0.5
    assert theta[tail].max() > 1.5 * theta[~tail].max()
    states = _same_limit_states(column, full, stopped)
    assert not states["overturning"].any() and not states["rotation"].any()


def _same_limit_states(column, full, stopped) -> dict:
    """The fragility's limit states of both runs (studies.fragility.analysis), equal."""
    found = [analysis.exceedances([[fem_point(column, run)]], 0.5) for run in (full, stopped)]
    assert found[0].keys() == found[1].keys()
    for name in found[0]:
        assert np.array_equal(found[0][name], found[1][name]), name
    return found[0]

"""Ground motions through their protocol (issue 34): the solvers read a motion only through the
members of colonna.core.ground.GroundMotion, so that a new kind of motion is its class alone.

Two motions are written here as new classes, registered for JSON and nothing else: a Ricker
wavelet (read by the rigid kernels from its table) and a one-sine pulse written afresh (read
in closed form, like HarmonicPulse). Both run through the SDOF solver (colonna.rock), the rigid
multibody model and the FEM."""

from __future__ import annotations

import json
import math
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

from colonna.core.ground import (
    NO_MOTION,
    GroundMotion,
    HarmonicPulse,
    NoMotion,
    Record,
    SineForm,
    acceleration_table,
    cosine_pulse,
    kernel_tables,
    motion_from_json,
    motion_type,
    peak_acceleration,
    sine_pulse,
)
from colonna.core.motion import Motion
from colonna.fem.settings import FemSettings
from colonna.rigid import Block, InputError, pulse_from_ratios, rock
from colonna.rigid.multibody import MultibodyContact, MultibodySettings, rock_multibody
from colonna.rigid.solve import SdofSettings

ROOT = Path(__file__).resolve().parents[1]
STICK = 2.0  # a friction coefficient that forbids sliding of these blocks


@motion_type("test_ricker")
@dataclass(frozen=True)
class Ricker:
    """A Ricker wavelet peak (1 - 2 u^2) exp(-u^2), u = pi f (t - center), on [0, 2 center],
    zero outside: a motion the kernels know nothing of. Its JSON is the generic one of a
    registered dataclass."""

    peak: float  # m/s^2, at t = center
    frequency: float  # Hz
    center: float  # s

    def acceleration(self, t):
        t = np.asarray(t, dtype=float)
        u = math.pi * self.frequency * (t - self.center)
        inside = (t >= 0.0) & (t <= self.end_time)
        return np.where(inside, self.peak * (1.0 - 2.0 * u * u) * np.exp(-u * u), 0.0)

    @property
    def end_time(self) -> float:
        return 2.0 * self.center

    @property
    def peak_acceleration(self) -> float:
        return abs(self.peak)

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
        n = math.ceil(samples_per_period * self.end_time * self.frequency)
        return np.linspace(0.0, self.end_time, max(n, 2) + 1)

    def acceleration_table(self, samples_per_period: int = 400):
        t = self.sample_times(samples_per_period)
        return t, self.acceleration(t)


@motion_type("test_one_sine")
@dataclass(frozen=True)
class OneSine:
    """amplitude sin(omega t + phase) on [0, duration]: HarmonicPulse written again, as a new
    class with its own JSON methods."""

    amplitude: float
    omega: float
    phase: float
    duration: float

    def acceleration(self, t):
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
    def pulse_shape(self) -> str:
        return "sine"

    @property
    def sine_form(self) -> SineForm:
        return SineForm(self.amplitude, self.omega, self.phase, self.duration)

    def sample_times(self, samples_per_period: int = 200) -> np.ndarray:
        n = math.ceil(samples_per_period * self.duration * self.omega / (2 * math.pi))
        return np.linspace(0.0, self.duration, max(n, 2) + 1)

    def acceleration_table(self, samples_per_period: int = 400):
        n = math.ceil(samples_per_period * self.duration * self.omega / (2 * math.pi))
        t = np.linspace(0.0, self.duration, max(n, 2) + 1)
        return t, self.acceleration(t)

    def to_json(self) -> dict:
        data = {"a": self.amplitude, "w": self.omega, "phi": self.phase, "T": self.duration}
        return {"type": "test_one_sine", **data}

    @classmethod
    def from_json(cls, data: dict) -> OneSine:
        return cls(data["a"], data["w"], data["phi"], data["T"])


def zm_block():
    return Block.from_dimensionless(p=2.14, alpha=0.25)


def one_sine(pulse: HarmonicPulse) -> OneSine:
    return OneSine(pulse.amplitude, pulse.omega, pulse.phase, pulse.duration)


def same_fields(a, b) -> bool:
    """Same class and every field equal bit for bit (arrays included)."""
    if type(a) is not type(b):
        return False
    for name in a.__dataclass_fields__:
        x, y = getattr(a, name), getattr(b, name)
        if isinstance(x, np.ndarray):
            if not (x.dtype == y.dtype and np.array_equal(x, y)):
                return False
        elif type(x) is not type(y) or not (x == y or (x != x and y != y)):
            return False
    return True


def arrays_equal(a, b, names) -> None:
    for name in names:
        x, y = getattr(a, name), getattr(b, name)
        assert np.array_equal(x, y), name


MOTIONS = [
    sine_pulse(3.7, 6.1, 1.9),
    cosine_pulse(-2.3, 4.9, 1.1),
    HarmonicPulse("sine", 0.4 * 9.81, 17.0, 0.0, 1.3),
    Record(np.arange(7) * 0.01, np.random.default_rng(3).standard_normal(7) / 3.0, "kobe 1995"),
    NoMotion(),
    NO_MOTION,
    Ricker(2.5, 1.7, 0.9),
    OneSine(1.0 / 3.0, math.pi, -0.1, 2.0 / 7.0),
]


# --- the protocol's members ------------------------------------------------------------------


@pytest.mark.parametrize("motion", MOTIONS, ids=lambda m: type(m).__name__)
def test_every_motion_is_a_ground_motion_and_round_trips_through_json_bit_for_bit(motion):
    assert isinstance(motion, GroundMotion)
    data = motion.to_json()
    assert isinstance(data["type"], str)
    text = json.dumps(data, allow_nan=False)  # plain JSON: no numpy types, no NaN
    back = motion_from_json(json.loads(text))
    assert same_fields(back, motion)
    assert back.to_json() == data


def test_a_record_stores_its_samples_and_name_inline():
    record = MOTIONS[3]
    data = record.to_json()
    assert data["type"] == "record" and data["name"] == "kobe 1995"
    assert data["time"] == record.time.tolist()
    assert data["acceleration_values"] == record.acceleration_values.tolist()
    assert motion_from_json(data).acceleration_values.dtype == np.float64


def test_json_of_an_unknown_or_malformed_motion_is_an_input_error():
    with pytest.raises(InputError, match="'ricker2' is not known.*harmonic_pulse, none, record"):
        motion_from_json({"type": "ricker2"})
    with pytest.raises(InputError, match="with a 'type'"):
        motion_from_json({"amplitude": 1.0})
    with pytest.raises(InputError, match="unknown keys 'omgea'"):
        motion_from_json({**MOTIONS[0].to_json(), "omgea": 1.0})
    with pytest.raises(InputError, match="'record'.*acceleration_values"):
        motion_from_json({"type": "record", "time": [0.0, 1.0]})


def test_a_type_name_is_registered_once():
    with pytest.raises(ValueError, match="'record' is already Record"):
        motion_type("record")(Ricker)


def test_moves_is_false_only_for_no_motion():
    assert [m.moves for m in MOTIONS] == [True, True, True, True, False, False, True, True]
    with pytest.raises(InputError, match="not 'none'"):
        peak_acceleration(NO_MOTION)
    assert peak_acceleration(MOTIONS[6]) == 2.5


def test_pulse_shape_names_the_pulses_a_spectrum_can_hold():
    blk = zm_block()
    for shape in ("sine", "cosine"):
        pulse = pulse_from_ratios(blk, shape, 4.0, 2.0, "linear")
        assert pulse.pulse_shape == shape
        uplift = blk.uplift_acceleration("linear")
        assert (pulse.amplitude, pulse.omega) == (2.0 * uplift, 4.0 * blk.p)
    assert [m.pulse_shape for m in MOTIONS[3:7]] == [None, None, None, None]


def test_sample_times():
    for pulse in MOTIONS[:3]:
        for spp in (200, 7):
            n = math.ceil(spp * pulse.end_time * pulse.omega / (2 * math.pi))
            expected = np.linspace(0.0, pulse.end_time, max(n, 2) + 1)
            assert np.array_equal(pulse.sample_times(spp), expected)
        assert pulse.sample_times()[-1] == pulse.end_time
    assert np.array_equal(MOTIONS[0].sample_times(), MOTIONS[0].sample_times(200))
    short = HarmonicPulse("sine", 1.0, 1.0, 0.0, 1e-3)  # under one interval: at least 2
    assert np.array_equal(short.sample_times(), np.linspace(0.0, 1e-3, 3))
    record = MOTIONS[3]
    times = record.sample_times()
    assert np.array_equal(times, record.time) and times.dtype == np.float64
    times[0] = -1.0  # a copy: the record is unchanged
    assert record.time[0] == 0.0
    for none in (NoMotion(), NO_MOTION):
        empty = none.sample_times()
        assert empty.dtype == np.float64 and empty.shape == (0,)


def test_tables_come_from_the_motion():
    """acceleration_table and the kernels' tables ask the motion: a pulse's sine is computed by
    the kernels (no rows), any other motion's table is read."""
    ricker = MOTIONS[6]
    t, a = acceleration_table(ricker)
    assert np.array_equal(t, ricker.sample_times(400)) and np.array_equal(a, ricker.acceleration(t))
    assert acceleration_table(NO_MOTION) is None
    times, values, rows, vertical = kernel_tables(ricker, NO_MOTION, 0.5)
    assert rows == t.size and not vertical
    assert np.array_equal(times, t) and np.array_equal(values, 0.5 * a)
    times, values, rows, vertical = kernel_tables(MOTIONS[0], ricker)
    assert rows == 0 and vertical and np.array_equal(values, a)
    with pytest.raises(InputError, match="type int is not supported"):
        acceleration_table(3)


def test_the_solvers_ask_no_motion_for_its_class():
    """No isinstance on a concrete motion class in rigid/ or in the ground module: the protocol
    is all they use."""
    concrete = re.compile(r"isinstance\([^)]*\b(HarmonicPulse|Record|NoMotion)\b")
    files = [*sorted((ROOT / "rigid").glob("*.py")), ROOT / "colonna" / "core" / "ground.py"]
    found = [f"{f.name}: {m.group(0)}" for f in files for m in concrete.finditer(f.read_text())]
    assert not found


# --- a new motion through every solver --------------------------------------------------------


def test_a_new_class_equal_to_a_harmonic_pulse_gives_its_answers_bit_for_bit():
    blk = zm_block()
    pulse = pulse_from_ratios(blk, "sine", 5.0, 2.5, "nonlinear")
    twin = one_sine(pulse)
    vertical = HarmonicPulse("sine", 0.2 * 9.81, 9.0, 0.0, 2.0)
    fields = ["time", "theta", "theta_dot", "impact_times", "impact_velocity_after"]
    for model in ("linear", "nonlinear"):
        a = rock(blk, Motion(pulse, duration=5.0), model=model)
        b = rock(blk, Motion(twin, duration=5.0), model=model)
        assert a.solver == b.solver and a.mode == b.mode and a.impacts == b.impacts > 0
        arrays_equal(a, b, fields)
    # and as a vertical motion (read from its table)
    a = rock(blk, Motion(pulse, duration=3.0, vertical=vertical), model="nonlinear")
    b = rock(blk, Motion(pulse, duration=3.0, vertical=one_sine(vertical)), model="nonlinear")
    arrays_equal(a, b, fields)
    a = rock_multibody(blk, Motion(pulse, duration=4.0), contact=MultibodyContact(friction=STICK))
    b = rock_multibody(blk, Motion(twin, duration=4.0), contact=MultibodyContact(friction=STICK))
    assert a.dt == b.dt and a.impacts == b.impacts > 0
    arrays_equal(a, b, ["time", "theta", "theta_dot", "impacts_table"])


def test_a_new_motion_read_from_its_table_moves_the_rigid_models():
    """The Ricker wavelet reaches the kernels as its table: the same answer as a Record of that
    table, bit for bit; below the uplift acceleration the block stands, above it rocks, and the
    SDOF and the multibody model (which reduces to it without sliding) agree to the first
    impact."""
    blk = zm_block()
    uplift = blk.uplift_acceleration("nonlinear")
    strong = Ricker(3.0 * uplift, 1.2 * blk.p / (2 * math.pi), 1.5)
    as_record = Record(*strong.acceleration_table(), name="ricker")
    fields = ["time", "theta", "theta_dot", "impact_times"]
    for model in ("linear", "nonlinear"):
        a = rock(blk, Motion(strong, duration=6.0), model=model)
        b = rock(blk, Motion(as_record, duration=6.0), model=model)
        assert a.solver == "dopri5" and a.impacts > 0
        arrays_equal(a, b, fields)
    weak = rock(blk, Motion(Ricker(0.9 * uplift, strong.frequency, 1.5)), model="nonlinear")
    assert not weak.theta.any() and weak.summary()["motion"] == "no uplift"

    sdof = rock(
        blk, Motion(strong, duration=6.0), model="nonlinear", settings=SdofSettings(dt_out=1e-3)
    )
    mb = rock_multibody(
        blk,
        Motion(strong, duration=6.0),
        contact=MultibodyContact(friction=STICK),
        settings=MultibodySettings(dt_out=1e-3),
    )
    same = rock_multibody(
        blk,
        Motion(as_record, duration=6.0),
        contact=MultibodyContact(friction=STICK),
        settings=MultibodySettings(dt_out=1e-3),
    )
    arrays_equal(mb, same, ["time", "theta", "theta_dot", "impacts_table"])
    sel = mb.time <= sdof.impact_times[0]
    reference = np.interp(mb.time[sel], sdof.time, sdof.theta)
    assert np.max(np.abs(mb.theta[sel, 0] - reference)) < 1e-3 * blk.alpha
    assert mb.impacts > 0 and abs(mb.impacts_table[0, 0] - sdof.impact_times[0]) < 2e-3


def test_a_new_motion_moves_the_fem_column():
    """The FEM reads a motion through acceleration(t) and end_time: the one-sine twin of a pulse
    gives the pulse's run bit for bit; the Ricker wavelet below the uplift acceleration leaves
    the column standing, well above it rocks it."""
    from colonna.fem.assembly import Stone
    from colonna.fem.model import ContactSettings, build_model
    from colonna.fem.solver import run
    from colonna.meshes.column import column_mesh

    width, height = 0.4, 2.0
    blk = Block(b=width / 2, h=height / 2)
    model = build_model(
        column_mesh(width, height, 0.1, cracked=True),
        Stone(),
        0.3,
        contact=ContactSettings(friction=1.0),
    )
    pulse = pulse_from_ratios(blk, "sine", 3.0, 3.0, "nonlinear")
    a = run(model, Motion(pulse, 0.25), FemSettings(progress=False, output_interval=1e-2))
    b = run(model, Motion(one_sine(pulse), 0.25), FemSettings(progress=False, output_interval=1e-2))
    assert a.history.keys() == b.history.keys()
    for key in a.history:
        assert np.array_equal(a.history[key], b.history[key]), key
    assert a.summary["max_abs_theta_left"] > 0.01

    uplift = blk.uplift_acceleration("nonlinear")
    peaks = {}
    for ratio in (0.5, 3.0):
        ricker = Ricker(ratio * uplift, 2.0, 0.3)
        r = run(model, Motion(ricker, 0.45), FemSettings(progress=False, output_interval=1e-2))
        peaks[ratio] = max(r.summary["max_abs_theta_left"], r.summary["max_abs_theta_right"])
    assert peaks[0.5] < 1e-3 * blk.alpha  # elastic sway only
    assert peaks[3.0] > 100.0 * peaks[0.5]

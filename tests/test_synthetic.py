"""The synthetic near-fault generator (colonna.core.synthetic) against its published models'
stated properties: the Mavroeidis & Papageorgiou (2003) pulse's peak velocity, period, duration
and derivative; the Rezaeian & Der Kiureghian (2008) modulating function's Arias intensity,
D5-95 and t_mid, and the background's unit-variance normalisation (E[a^2] = q^2); the record
ending at rest; the seeds; and the shipped suite regenerating bit for bit."""

import math
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.optimize import brentq

from colonna.core.errors import InputError
from colonna.core.intensity import ground_velocity_displacement
from colonna.core.suite import load_suite
from colonna.core.synthetic import (
    SyntheticParameters,
    background,
    modulation,
    pulse_acceleration,
    pulse_velocity,
    synthetic_record,
    synthetic_suite,
)
from colonna.studies.suites import make_synthetic_suite

G = 9.81
PULSE = {"Tp": 1.3, "Vp": 0.6, "gamma": 2.2, "nu": 0.0, "t0": 4.0}


def test_the_pulse_peaks_at_vp_and_never_exceeds_it():
    t = np.arange(0.0, 8.0, 0.001)  # t0 = 4 s is a sample
    assert np.max(np.abs(pulse_velocity(t, **PULSE))) == pytest.approx(0.6, rel=1e-12)
    for nu in np.linspace(0.3, 6.0, 7):
        assert np.max(np.abs(pulse_velocity(t, **{**PULSE, "nu": nu}))) <= 0.6


def test_the_pulse_lasts_gamma_periods_and_its_zeros_are_half_a_period_apart():
    """Support |t - t0| <= gamma Tp / 2; the carrier cos(2 pi (t - t0) / Tp + nu) crosses zero
    every Tp / 2 inside it (nu = 0.7)."""
    p = {**PULSE, "nu": 0.7}
    half = p["gamma"] * p["Tp"] / 2
    assert pulse_velocity(p["t0"] - half - 1e-9, **p) == 0.0
    assert pulse_velocity(p["t0"] + half + 1e-9, **p) == 0.0
    grid = np.linspace(p["t0"] - half + 1e-6, p["t0"] + half - 1e-6, 4001)
    v = pulse_velocity(grid, **p)
    brackets = np.flatnonzero(np.sign(v[:-1]) * np.sign(v[1:]) < 0)
    zeros = [
        brentq(lambda x: float(pulse_velocity(x, **p)), grid[i], grid[i + 1], xtol=1e-14)
        for i in brackets
    ]
    assert len(zeros) >= 3
    np.testing.assert_allclose(np.diff(zeros), p["Tp"] / 2, rtol=1e-9)


def test_the_pulse_acceleration_is_the_velocitys_derivative():
    p = {**PULSE, "nu": 1.1}
    t = np.linspace(2.7, 5.3, 501)
    h = 1e-6
    slope = (pulse_velocity(t + h, **p) - pulse_velocity(t - h, **p)) / (2 * h)
    np.testing.assert_allclose(pulse_acceleration(t, **p), slope, atol=1e-7)


def test_the_modulating_function_holds_its_arias_intensity_d5_95_and_t_mid():
    arias, d5_95, t_mid = 0.3, 8.0, 5.0
    _, (a1, a2, a3) = modulation(np.zeros(1), arias, d5_95, t_mid, G)

    def q2(t):
        return (a1 * t ** (a2 - 1) * math.exp(-a3 * t)) ** 2

    def energy(upto):
        return quad(q2, 0.0, upto, limit=200)[0]

    total = quad(q2, 0.0, np.inf, limit=200)[0]
    assert math.pi / (2 * G) * total == pytest.approx(arias, rel=1e-8)

    def at(fraction):
        return brentq(lambda t: energy(t) / total - fraction, 1e-6, 200.0, xtol=1e-12)

    assert at(0.45) == pytest.approx(t_mid, rel=1e-7)
    assert at(0.95) - at(0.05) == pytest.approx(d5_95, rel=1e-7)


def test_the_background_has_the_envelopes_variance_and_arias_intensity():
    """The normalised filtered noise has unit variance: over 40 seeds, mean (a / q)^2 = 1 and
    the mean Arias intensity is the parameter's (a sample mean: within 6 %)."""
    dt, arias = 0.02, 0.2
    t = np.arange(601) * dt
    q, _ = modulation(t, arias, 6.0, 4.0, G)
    ratios, energies = [], []
    for seed in range(40):
        a = background(t, q, 4.0, -0.1, 0.3, 4.0, np.random.default_rng(seed))
        ratios.append((a[1:] / q[1:]) ** 2)
        energies.append(math.pi / (2 * G) * np.sum(a**2) * dt)
    assert np.mean(ratios) == pytest.approx(1.0, abs=0.05)
    expected = math.pi / (2 * G) * np.sum(q**2) * dt  # the envelope's, on this grid
    assert expected == pytest.approx(arias, rel=0.01)  # the record holds 99 % of it
    assert np.mean(energies) == pytest.approx(expected, rel=0.06)


def test_a_record_ends_at_rest_where_it_started():
    """Pulse plus background, less the line c0 + c1 t that brings the ground to rest where it
    started (the pulse with nu = 0 alone moves it by int v dt)."""
    params = SyntheticParameters(**PULSE, arias=0.1, d5_95=6.0, t_mid=5.0, f_mid=4.0,
                                 f_slope=-0.1, zeta_f=0.3, noise_seed=7)  # fmt: skip
    record, parts = synthetic_record(params, dt=0.01, duration=12.0, parts=True)
    _, _, v, u = ground_velocity_displacement(record, baseline=False)
    assert abs(v[-1]) < 1e-12 and abs(u[-1]) < 1e-12
    correction = record.acceleration_values - (parts["pulse"] + parts["background"])
    np.testing.assert_allclose(np.diff(correction, 2), 0.0, atol=1e-12)  # a line c0 + c1 t


def test_records_are_seeded_each_by_its_own_stream():
    """The same seed, the same records; record i does not depend on how many are drawn."""
    short = synthetic_suite(2, 5, dt=0.02, duration=10.0)
    longer = synthetic_suite(3, 5, dt=0.02, duration=10.0)
    for (a, pa), (b, pb) in zip(short, longer[:2], strict=True):
        assert pa == pb
        np.testing.assert_array_equal(a.acceleration_values, b.acceleration_values)
    other = synthetic_suite(1, 6, dt=0.02, duration=10.0)[0][1]
    assert other != short[0][1]
    with pytest.raises(InputError, match="gamma = 1 must be > 1"):
        pulse_velocity(0.0, 1.0, 1.0, 1.0, 0.0, 0.0)


def test_the_shipped_suite_regenerates_bit_for_bit():
    folder = make_synthetic_suite.FOLDER
    files = make_synthetic_suite.suite_files()
    assert sorted(files) == sorted(p.name for p in folder.iterdir())
    for name, text in files.items():
        assert (folder / name).read_text() == text, f"{name} differs from what the script writes"


def test_the_shipped_suite_loads_with_its_parameters():
    suite = load_suite(Path(make_synthetic_suite.FOLDER))
    assert len(suite) == 10 and suite[0].name == "synth01"
    params = SyntheticParameters(**suite[3].parameters)
    assert 0.5 <= params.Tp <= 3.0 and 1.5 <= params.gamma <= 3.0
    assert suite[3].record.time[-1] == pytest.approx(20.0)

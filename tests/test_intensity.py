"""Intensity measures (colonna.core.intensity) against closed forms: Arias intensity and CAV of a
sine, PGV and PGD of a one-cycle cosine (with and without a baseline offset), D5-95 from the sine's
Husid curve, Sa at resonance against the oscillator's steady state, Sa(T -> 0) = PGA, and the
Nigam-Jennings recurrence against an independent integration of the oscillator."""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from colonna.core.errors import InputError
from colonna.core.ground import Record
from colonna.core.intensity import (
    arias_intensity,
    cumulative_absolute_velocity,
    ground_velocity_displacement,
    intensity_measures,
    significant_duration,
    spectral_acceleration,
)
from colonna.rigid import Block

G = 9.81


def sine(amplitude=2.0, period=0.5, cycles=10, per_period=400):
    t = np.linspace(0.0, cycles * period, cycles * per_period + 1)
    return Record(t, amplitude * np.sin(2.0 * math.pi * t / period), "sine")


def test_arias_intensity_and_cav_of_a_sine():
    """A sin(w t) over n cycles: I_A = pi / (2 g) A^2 n T / 2, CAV = n 4 A / w."""
    a, period, n = 2.0, 0.5, 10
    rec = sine(a, period, n)
    assert arias_intensity(rec, g=G) == pytest.approx(
        math.pi / (2 * G) * a**2 * n * period / 2, rel=1e-4
    )
    omega = 2 * math.pi / period
    assert cumulative_absolute_velocity(rec) == pytest.approx(n * 4 * a / omega, rel=1e-4)


def test_significant_duration_of_a_sine_from_its_husid_curve():
    """H(t) = (t - sin(2 w t) / (2 w)) / T_total; D5-95 = t(0.95) - t(0.05)."""
    period, n = 0.5, 10
    omega, total = 2 * math.pi / period, n * period

    def husid_time(level):
        return brentq(
            lambda t: (t - math.sin(2 * omega * t) / (2 * omega)) / total - level, 0, total
        )

    expected = husid_time(0.95) - husid_time(0.05)
    assert significant_duration(sine(2.0, period, n)) == pytest.approx(expected, abs=2e-4)


def one_cycle_cosine(a=3.0, period=0.8, offset=0.0, samples=2001):
    t = np.linspace(0.0, period, samples)
    return Record(t, a * np.cos(2 * math.pi * t / period) + offset, "cos")


def test_pgv_and_pgd_of_a_one_cycle_cosine():
    """a = A cos(w t), 0 <= t <= 2 pi / w: v = A sin(w t) / w, u = A (1 - cos(w t)) / w^2, so
    PGV = A / w and PGD = 2 A / w^2; the ground ends at rest where it started, and the baseline
    correction leaves it."""
    a, period = 3.0, 0.8
    omega = 2 * math.pi / period
    ims = intensity_measures(one_cycle_cosine(a, period))
    assert ims.pga == pytest.approx(a)
    assert ims.pgv == pytest.approx(a / omega, rel=1e-6)
    assert ims.pgd == pytest.approx(2 * a / omega**2, rel=1e-6)


def test_pgv_and_pgd_are_those_of_the_motion_as_applied():
    """a = A sin(w t) for one cycle, then rest: v = A (1 - cos(w t)) / w peaks at 2 A / w, and
    the ground ends displaced by u = 2 pi A / w^2 (a pulse's fling, which the solvers apply): no
    baseline correction unless asked for (it would halve this PGV)."""
    a, period = 3.0, 0.8
    omega = 2 * math.pi / period
    t = np.linspace(0.0, 2.0 * period, 4001)
    pulse = Record(t, np.where(t <= period, a * np.sin(omega * t), 0.0), "sine")
    ims = intensity_measures(pulse)
    assert ims.pgv == pytest.approx(2 * a / omega, rel=1e-5)
    assert ims.pgd == pytest.approx(2 * math.pi * a / omega**2, rel=1e-5)  # v >= 0: u grows
    assert intensity_measures(pulse, baseline=True).pgv < 0.75 * ims.pgv


def test_the_baseline_correction_removes_an_offset_and_a_drift_exactly():
    """An offset 0.05 + 0.02 t m/s^2 added to the cosine drifts the raw displacement by meters;
    the corrected one is the clean cosine's."""
    clean = ground_velocity_displacement(one_cycle_cosine())
    t = clean[0]
    drifting = Record(t, clean[1] + 0.05 + 0.02 * t)
    raw = ground_velocity_displacement(drifting, baseline=False)
    fixed = ground_velocity_displacement(drifting)
    assert abs(raw[3][-1]) > 0.015  # 0.05 T^2 / 2 + 0.02 T^3 / 6 = 0.0177 m
    np.testing.assert_allclose(fixed[2], clean[2], atol=1e-12)
    np.testing.assert_allclose(fixed[3], clean[3], atol=1e-12)


def test_sa_at_resonance_is_the_steady_state_amplitude():
    """A sin(w t) on an oscillator of the same period, damping zeta: steady state
    x = A / (2 zeta w^2), so PSa = A / (2 zeta) = 10 A at 5 %; 40 s leaves a transient of
    e^(-zeta w 40 s) ~ 1e-5."""
    rec = sine(1.5, 1.0, 40, per_period=200)
    assert spectral_acceleration(rec, [1.0])[0] == pytest.approx(1.5 / (2 * 0.05), rel=2e-4)


def test_sa_tends_to_pga_at_short_period_and_pseudo_is_absolute_without_damping():
    rng = np.random.default_rng(0)
    t = np.arange(1000) * 0.01
    rec = Record(t, rng.standard_normal(1000))
    assert spectral_acceleration(rec, [1e-4])[0] == pytest.approx(rec.peak_acceleration, rel=1e-3)
    periods = [0.2, 0.7, 1.5]
    np.testing.assert_allclose(
        spectral_acceleration(rec, periods, damping=0.0, kind="absolute"),
        spectral_acceleration(rec, periods, damping=0.0),
        rtol=1e-9,
    )


def test_the_recurrence_is_exact_against_an_independent_integration():
    """The oscillator (10 % damping) under the piecewise-linear record, integrated step by step
    by an adaptive Runge-Kutta (DOP853, rtol 1e-12; no kink inside a step) and then freely for
    one period after the record: the same peak to 1e-9."""
    rng = np.random.default_rng(1)
    dt = 0.01
    a = rng.standard_normal(60)
    rec = Record(np.arange(60) * dt, a)
    for period in (0.1, 0.6):
        w = 2 * math.pi / period

        def rhs(tau, z, start=0.0, slope=0.0, w=w):
            return [z[1], -(start + slope * tau) - 0.2 * w * z[1] - w * w * z[0]]

        z, peak = np.zeros(2), 0.0
        for i in range(a.size - 1):
            args = (a[i], (a[i + 1] - a[i]) / dt)
            z = solve_ivp(rhs, [0, dt], z, "DOP853", args=args, rtol=1e-12, atol=1e-14).y[:, -1]
            peak = max(peak, abs(z[0]))
        after = np.arange(1, int(period / dt) + 1) * dt
        free = solve_ivp(rhs, [0, after[-1]], z, "DOP853", after, rtol=1e-12, atol=1e-14)
        peak = max(peak, np.max(np.abs(free.y[0])))
        sa = spectral_acceleration(rec, [period], damping=0.1)[0]
        assert sa == pytest.approx(w * w * peak, rel=1e-9)


def test_the_rocking_normalised_intensities_of_a_block():
    """PGA / (g tan alpha) and PGV p / (g tan alpha) of the one-cycle cosine (PGV = A / w)."""
    block = Block(b=0.2, h=2.0)
    a, period = 3.0, 0.8
    ims = intensity_measures(one_cycle_cosine(a, period), block=block, periods=[0.5, 1.0])
    uplift = G * math.tan(block.alpha)
    assert ims.pga_rocking == pytest.approx(a / uplift)
    assert ims.pgv_rocking == pytest.approx(a / (2 * math.pi / period) * block.p / uplift, rel=1e-6)
    assert set(ims.to_dict()) >= {"pga", "sa(T=0.5 s)", "sa(T=1 s)", "pgv_rocking"}


def test_bad_requests_are_input_errors():
    rec = one_cycle_cosine()
    with pytest.raises(InputError, match="period must be > 0"):
        spectral_acceleration(rec, [0.0])
    with pytest.raises(InputError, match="uniformly sampled"):
        spectral_acceleration(Record(np.array([0.0, 0.01, 0.03]), np.ones(3)), [0.5])
    with pytest.raises(InputError, match="zero everywhere"):
        significant_duration(Record(np.array([0.0, 0.01]), np.zeros(2)))


def test_a_top_load_enters_the_rocking_normalisation_as_it_enters_the_uplift():
    """With a top load P (lambda = P / (m g)) the block uplifts at g tan(alpha) (1 + lambda)
    (Eq. 2 with P): a record whose PGA is that acceleration has PGA / a_up = 1, and the rocking
    scale of PGV uses the same a_up."""
    mass = 500.0
    block = Block(b=0.2, h=2.0, mass=mass, top_load=0.5 * mass * G)  # lambda = 0.5
    uplift = G * math.tan(block.alpha) * 1.5
    period = 0.8
    ims = intensity_measures(one_cycle_cosine(uplift, period), block=block)
    assert ims.pga_rocking == pytest.approx(1.0, rel=1e-12)
    w = 2 * math.pi / period
    assert ims.pgv_rocking == pytest.approx(uplift / w * block.p / uplift, rel=1e-6)

"""Time histories: both solvers against an independent scipy integration, energy between impacts,
restitution at every impact, mirror symmetry."""

import math

import numpy as np
import pytest
from reference import reference_rocking, sine_pulse_over_g

from colonna.core.motion import Motion, Release
from colonna.rigid import Block, Collar, InputError, NoMotion, Record, pulse_from_ratios, rock
from colonna.rigid import _kernels as K
from colonna.rigid.solve import SdofSettings, kernel_params

CASES = [(5.0, 3.0), (5.0, 4.5), (2.0, 2.0), (8.0, 6.0), (1.0, 1.5), (5.0, 7.3)]


def _reference(block, pulse, model, **kw):
    return reference_rocking(
        block.p,
        block.alpha,
        block.nu,
        sine_pulse_over_g(pulse.amplitude / block.g, pulse.omega, pulse.phase, pulse.duration),
        pulse.duration,
        nonlinear=model == "nonlinear",
        t_stop=pulse.duration + 20.0 / block.p,
        settle=False,
        **kw,
    )


def _ref_theta(pieces, t):
    out = np.full_like(t, np.nan)
    for sol in pieces:
        inside = (t >= sol.t[0]) & (t <= sol.t[-1])
        if inside.any():
            out[inside] = sol.sol(t[inside])[0]
    return out


@pytest.mark.chaotic
@pytest.mark.parametrize("model", ["linear", "nonlinear"])
@pytest.mark.parametrize("omega_ratio, amplitude_ratio", CASES)
def test_history_matches_reference_integration(zm_block, model, omega_ratio, amplitude_ratio):
    pulse = pulse_from_ratios(zm_block, "sine", omega_ratio, amplitude_ratio, model)
    result = rock(zm_block, Motion(pulse), model=model)
    overturned, impacts, max_theta, impact_times, pieces = _reference(zm_block, pulse, model)
    assert result.overturned == overturned
    assert result.impacts == impacts
    n = min(len(impact_times), 5)
    np.testing.assert_allclose(result.impact_times[:n], impact_times[:n], rtol=1e-7, atol=1e-9)
    # theta(t) up to the fifth impact (or the end)
    t_end = impact_times[n - 1] if n else result.time[-1]
    t = result.time[result.time <= min(t_end, result.time[-1])]
    ref = _ref_theta(pieces, t)
    ok = np.isfinite(ref)
    np.testing.assert_allclose(result.theta[: t.size][ok], ref[ok], atol=1e-7 * zm_block.alpha)
    if not overturned:
        assert result.max_abs_theta >= max_theta * (1 - 1e-9)
        assert result.max_abs_theta == pytest.approx(max_theta, rel=1e-3)


def test_closed_form_and_dopri5_agree(zm_block):
    """The exact linear closed form and the DOPRI5 integration of the same linear equation."""
    pulse = pulse_from_ratios(zm_block, "sine", 4.0, 3.5, "linear")
    exact = rock(zm_block, Motion(pulse), model="linear")
    P, rec_t, rec_a = kernel_params(zm_block, pulse, (), "linear")
    out = np.zeros((exact.time.size + 10, 3))
    impacts = np.zeros((1000, 3))
    dt = exact.time[1] - exact.time[0]
    status, n_imp, *_, n_out, _ = K.rk_run(
        P, rec_t, rec_a, exact.time[-1], 1e-11, 1e-13, False, dt, out, impacts
    )
    assert exact.solver == "closed-form"
    assert n_imp == exact.impacts
    np.testing.assert_allclose(impacts[:n_imp, 0], exact.impact_times, rtol=1e-8)
    m = min(n_out, exact.time.size)
    np.testing.assert_allclose(out[:m, 1], exact.theta[:m], atol=1e-7 * zm_block.alpha)


@pytest.mark.parametrize("model", ["linear", "nonlinear"])
def test_restitution_applied_at_every_impact(zm_block, model):
    result = rock(
        zm_block, Motion(pulse_from_ratios(zm_block, "sine", 5.0, 2.8, model)), model=model
    )
    assert not result.overturned and result.impacts >= 3
    np.testing.assert_allclose(
        result.impact_velocity_after, 0.9 * result.impact_velocity_before, rtol=1e-14
    )
    # the block changes side at each impact: successive velocities alternate in sign
    assert np.all(np.diff(np.sign(result.impact_velocity_before)) != 0)


def _energy_per_j0(theta, omega, block, model, ka=0.0, kl=0.0):
    p2, a = block.p**2, block.alpha
    x = np.abs(theta)
    if model == "nonlinear":
        s = np.sin(theta)
        return (
            0.5 * omega**2
            + p2 * (np.cos(a - x) - np.cos(a))
            + ka * (np.sqrt(1 + 0.25 * s * s) - 1) ** 2
            + 0.25 * kl * s * s
        )
    return 0.5 * omega**2 + p2 * (a * x - 0.5 * x * x) + 0.25 * kl * theta**2


def _flights_with_constant_energy(result, energy, t_free, rel_tol):
    """Assert the energy is constant (to rel_tol) on every flight between impacts after t_free;
    return how many flights were checked."""
    edges = np.concatenate(([t_free], result.impact_times[result.impact_times > t_free]))
    checked = 0
    for lo, hi in zip(edges[:-1], edges[1:]):
        inside = (result.time > lo + 1e-9) & (result.time < hi - 1e-9)
        if inside.sum() > 10:
            e = energy[inside]
            assert np.ptp(e) <= rel_tol * np.max(np.abs(e)), (lo, hi)
            checked += 1
    return checked


@pytest.mark.parametrize("model", ["linear", "nonlinear"])
def test_energy_conserved_between_impacts_after_pulse(zm_block, model):
    pulse = pulse_from_ratios(zm_block, "sine", 5.0, 2.8, model)
    result = rock(zm_block, Motion(pulse), model=model)
    assert not result.overturned
    energy = _energy_per_j0(result.theta, result.theta_dot, zm_block, model)
    assert _flights_with_constant_energy(result, energy, pulse.duration, 1e-8) >= 3
    # and each impact removes (1 - nu^2) of the kinetic energy
    ratio = (result.impact_velocity_after / result.impact_velocity_before) ** 2
    np.testing.assert_allclose(ratio, 0.81, rtol=1e-12)


def test_energy_conserved_with_collars(half_column):
    """Collar springs are conservative: kinetic + gravity + collar energy is constant between
    impacts once the ground is still."""
    collars = (Collar(y=1.0, t=0.004, h=0.03), Collar(y=3.0, t=0.004, h=0.03))
    pulse = pulse_from_ratios(half_column, "sine", 3.0, 3.0, "nonlinear")
    result = rock(half_column, Motion(pulse), collars, model="nonlinear")
    P, *_ = kernel_params(half_column, pulse, collars, "nonlinear")
    energy = _energy_per_j0(
        result.theta, result.theta_dot, half_column, "nonlinear", P[K.P_KA], P[K.P_KL]
    )
    assert _flights_with_constant_energy(result, energy, pulse.duration, 1e-7) >= 2


@pytest.mark.parametrize("model", ["linear", "nonlinear"])
def test_mirror_symmetry(zm_block, model):
    pulse = pulse_from_ratios(zm_block, "sine", 4.0, 3.3, model)
    mirrored = type(pulse)(pulse.kind, -pulse.amplitude, pulse.omega, pulse.phase, pulse.duration)
    a = rock(zm_block, Motion(pulse), model=model)
    b = rock(zm_block, Motion(mirrored), model=model)
    assert a.theta.min() < 0 < b.theta.max()  # positive ground push rocks to negative theta
    np.testing.assert_allclose(b.theta, -a.theta, atol=1e-12)
    assert a.mode == b.mode and a.impacts == b.impacts


@pytest.mark.chaotic
def test_record_path_reproduces_the_pulse(zm_block):
    """A finely sampled record of the pulse gives the pulse's response (record interpolation)."""
    pulse = pulse_from_ratios(zm_block, "sine", 3.0, 2.2, "nonlinear")
    t = np.linspace(0.0, pulse.duration, 20001)
    record = Record(t, pulse.acceleration(t))
    a = rock(zm_block, Motion(pulse, duration=pulse.duration + 5.0), model="nonlinear")
    b = rock(
        zm_block,
        Motion(record, duration=pulse.duration + 5.0),
        model="nonlinear",
        settings=SdofSettings(dt_out=a.time[1]),
    )
    assert a.impacts == b.impacts
    n = min(a.time.size, b.time.size)
    np.testing.assert_allclose(b.theta[:n], a.theta[:n], atol=2e-5 * zm_block.alpha)


def test_overturning_modes_named_in_words(zm_block):
    after = rock(zm_block, Motion(pulse_from_ratios(zm_block, "sine", 5.0, 4.0, "linear")))
    without = rock(zm_block, Motion(pulse_from_ratios(zm_block, "sine", 5.0, 9.0, "linear")))
    safe = rock(zm_block, Motion(pulse_from_ratios(zm_block, "sine", 5.0, 2.0, "linear")))
    assert (after.mode, without.mode, safe.mode) == ("after-impact", "without-impact", "safe")
    assert after.impacts >= 1 and without.impacts == 0
    assert after.max_abs_theta == pytest.approx(math.pi / 2)


@pytest.mark.chaotic
def test_cosine_pulse_starts_rocking_at_once(zm_block):
    pulse = pulse_from_ratios(zm_block, "cosine", 3.0, 2.0, "nonlinear")
    assert pulse.acceleration(0.0) == pytest.approx(2.0 * zm_block.uplift_acceleration())
    result = rock(zm_block, Motion(pulse), model="nonlinear")
    assert abs(result.theta[5]) > 0.0 and result.theta[5] < 0.0
    overturned, impacts, *_ = reference_rocking(
        zm_block.p,
        zm_block.alpha,
        0.9,
        lambda t: pulse.acceleration(t) / zm_block.g,
        pulse.duration,
        nonlinear=True,
        t_stop=pulse.duration + 20 / zm_block.p,
    )
    assert (result.overturned, result.impacts) == (overturned, impacts)


def test_block_stays_put_below_uplift(zm_block):
    weak = Record(
        np.linspace(0, 2, 201),
        0.5 * zm_block.uplift_acceleration() * np.sin(np.linspace(0, 2, 201) * 5),
    )
    result = rock(zm_block, Motion(weak), model="nonlinear")
    assert result.max_abs_theta == 0.0 and result.impacts == 0 and not result.overturned


def test_housner_default_restitution_used():
    blk = Block(b=0.25, h=2.0)
    result = rock(
        blk, Motion(pulse_from_ratios(blk, "sine", 3.0, 2.5, "nonlinear")), model="nonlinear"
    )
    np.testing.assert_allclose(
        result.impact_velocity_after / result.impact_velocity_before,
        1 - 1.5 * math.sin(blk.alpha) ** 2,
        rtol=1e-13,
    )


@pytest.mark.parametrize("model", ["linear", "nonlinear"])
def test_release_from_a_tilt_reaches_the_vertical_at_the_corrected_eq13_time(model):
    """Free rocking (no ground motion) from rest at theta0: the linear model reaches theta = 0
    at arccosh(1 / (1 - theta0/alpha)) / p exactly (corrected Eq. 13); the nonlinear one within
    alpha^2; each impact then keeps Housner's ratio."""
    blk = Block.from_dimensionless(p=2.0, alpha=0.2)
    result = rock(blk, Motion(NoMotion(), duration=3.0), model=model, release=Release(tilt=-0.1))
    expected = blk.time_to_vertical(0.1)
    rel = 1e-9 if model == "linear" else 0.2**2
    assert result.impact_times[0] == pytest.approx(expected, rel=rel)
    assert result.theta[0] == -0.1 and not result.overturned
    np.testing.assert_allclose(
        result.impact_velocity_after / result.impact_velocity_before,
        blk.restitution_housner,
        rtol=1e-12,
    )


def test_release_with_an_outward_spin_above_the_barrier_overturns_without_impact():
    """From upright, theta' > p sqrt(2 (1 - cos alpha)) carries the free block past alpha."""
    blk = Block.from_dimensionless(p=2.0, alpha=0.2)
    barrier = blk.p * math.sqrt(2.0 * (1.0 - math.cos(blk.alpha)))
    over = rock(
        blk,
        Motion(NoMotion(), duration=10.0),
        model="nonlinear",
        release=Release(angular_velocity=1.01 * barrier),
    )
    back = rock(
        blk,
        Motion(NoMotion(), duration=10.0),
        model="nonlinear",
        release=Release(angular_velocity=0.99 * barrier),
    )
    assert over.mode == "without-impact" and back.mode == "safe" and back.impacts >= 1


def test_no_ground_motion_and_no_initial_state_is_an_error():
    blk = Block.from_dimensionless(p=2.0, alpha=0.2)
    with pytest.raises(InputError, match="stays at rest"):
        rock(blk, Motion(NoMotion()), model="nonlinear")


def test_a_record_that_only_touches_the_uplift_level_leaves_the_block_at_rest(zm_block):
    """Rocking needs the ground to exceed g tan(alpha), as for a pulse: a record whose peak
    sample is the uplift level exactly leaves the block at rest (it used to start a rocking
    that ended at once, at the same instant, for 50 million steps); 1 % above, it rocks."""
    t = np.linspace(0.0, 1.0, 201)
    shape = np.sin(np.pi * t)  # its peak sample is 1.0 exactly (t = 0.5)
    assert shape.max() == 1.0
    P, rec_t, rec_a = kernel_params(zm_block, Record(t, 9.81 * shape, "touch"), (), "nonlinear")
    n = int(P[K.P_NHREC])
    out, impacts = np.zeros((1, 3)), np.zeros((10, 3))
    peaks = {}
    for factor in (1.0, 1.01):
        rec_a[:n] = factor * P[K.P_UPLIFT] * shape
        status, n_imp, peak, *_ = K.rk_run(
            P, rec_t, rec_a, 2.0, 1e-10, 1e-12, False, 0.0, out, impacts
        )
        peaks[factor] = (status, peak)
    assert peaks[1.0] == (K.AT_REST, 0.0)
    assert peaks[1.01][1] > 0.0


@pytest.mark.parametrize("scale", [0.5, 0.6])
def test_the_early_exit_keeps_the_peak_of_a_swing_going_out(scale):
    """Once the free block is trapped in its well (below the energy to reach alpha), the
    spectra's early exit stops the run; a swing still going out there peaks at its turning
    point. Without it the peak came out 0.7 % (scale 0.5) and 6.7 % (scale 0.6) low on the
    synthetic record; now it is the full run's."""
    from pathlib import Path

    from colonna.core.ground import read_record

    record = read_record(Path(__file__).parent / "data" / "synthetic.AT2").scaled(scale)
    P, rec_t, rec_a = kernel_params(Block(b=0.1125, h=2.0), record, (), "nonlinear")
    out, impacts = np.zeros((1, 3)), np.zeros((10000, 3))
    peaks = {}
    for early in (True, False):
        status, _, peak, *_ = K.rk_run(
            P, rec_t, rec_a, record.end_time + 30.0, 1e-10, 1e-12, early, 0.0, out, impacts
        )
        peaks[early] = peak
        assert status != K.OVERTURNED
    assert peaks[True] == pytest.approx(peaks[False], rel=1e-7)

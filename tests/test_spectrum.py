"""Overturning spectra: classification against the independent reference integration, and the
published Zhang & Makris / source-paper boundaries."""

import numpy as np
import pytest
from reference import reference_rocking, sine_pulse_over_g

from colonna.rigid import Collar, InputError, pulse_from_ratios
from colonna.rigid.collars import collar_yield_rotation
from colonna.rigid.spectrum import overturning_spectrum
from colonna.studies.zhang_makris import mode_boundaries


def _reference_mode(block, omega_ratio, amplitude_ratio, model, **kw):
    pulse = pulse_from_ratios(block, "sine", omega_ratio, amplitude_ratio, model)
    overturned, impacts, *_ = reference_rocking(
        block.p,
        block.alpha,
        block.nu,
        sine_pulse_over_g(pulse.amplitude / block.g, pulse.omega, pulse.phase, pulse.duration),
        pulse.duration,
        nonlinear=model == "nonlinear",
        t_stop=pulse.duration + 50 / block.p,
        **kw,
    )
    if not overturned:
        return "safe"
    return "after-impact" if impacts else "without-impact"


@pytest.mark.chaotic
@pytest.mark.parametrize("model", ["linear", "nonlinear"])
def test_spectrum_matches_reference_at_sampled_points(zm_block, model):
    omegas = np.linspace(0.8, 9.0, 9)
    amplitudes = np.linspace(1.2, 12.0, 10)
    spec = overturning_spectrum(zm_block, omegas, amplitudes, model=model)
    rng = np.random.default_rng(7)
    picks = rng.choice(spec.codes.size, size=14, replace=False)
    modes = spec.modes
    seen = set()
    for k in picks:
        i, j = divmod(int(k), omegas.size)
        expected = _reference_mode(zm_block, omegas[j], amplitudes[i], model)
        assert modes[i][j] == expected, (omegas[j], amplitudes[i])
        seen.add(expected)
    assert len(seen) >= 2  # the sample crosses a boundary


@pytest.mark.chaotic
def test_spectrum_with_collars_matches_reference(half_column):
    from colonna.rigid.collars import collar_kernel_constants

    collars = (Collar(y=1.0, t=0.002, h=0.02), Collar(y=3.0, t=0.002, h=0.02))
    ka, kl = collar_kernel_constants(half_column, collars)
    omegas = np.array([1.0, 3.0, 6.0])
    amplitudes = np.array([1.5, 4.0, 8.0])
    spec = overturning_spectrum(half_column, omegas, amplitudes, collars, model="nonlinear")
    for i, a in enumerate(amplitudes):
        for j, w in enumerate(omegas):
            assert spec.modes[i][j] == _reference_mode(
                half_column, w, a, "nonlinear", collar_ka=ka, collar_kl=kl
            )
    # collar yield map: yields exactly where the peak rotation passes the yield rotation
    theta_y = min(collar_yield_rotation(c, half_column.b) for c in collars)
    np.testing.assert_array_equal(spec.collar_yields, spec.max_abs_theta >= theta_y)


def test_collars_shrink_the_overturning_region(half_column):
    omegas = np.linspace(1.0, 8.0, 15)
    amplitudes = np.linspace(1.1, 10.0, 30)
    free = overturning_spectrum(half_column, omegas, amplitudes, model="linear")
    collars = (Collar(y=2.0, t=0.01, h=0.03),)
    held = overturning_spectrum(half_column, omegas, amplitudes, collars, model="linear")
    assert (held.codes != 0).sum() < (free.codes != 0).sum()
    # rocking is not monotonic (collars move the safe window), but the lowest overturning
    # amplitude rises at every frequency
    lowest_free = free.minimum_overturning_amplitude()
    lowest_held = held.minimum_overturning_amplitude()
    assert np.all(lowest_held >= lowest_free)
    assert np.any(lowest_held > lowest_free)


def test_zhang_makris_published_boundaries(zm_block):
    """Source paper Fig. 5 (Omega/p = 5, linear model, nu = 0.9): the block is safe at
    3.00 g alpha and overturns at 3.01; overturns at 6.32 and is safe at 6.33. The exact solution
    (confirmed against solve_ivp at rtol 1e-12 in test_rocking) puts the boundaries at
    3.019 and 6.318: within 0.3 % of the published figure (see docs/validation.md)."""
    lower, upper, mode2 = mode_boundaries(
        zm_block, 5.0, "linear", [(2.5, 4.0), (5.5, 6.9), (6.9, 8.0)], tol=1e-5
    )
    assert 3.00 * (1 - 3e-3) <= lower <= 3.01 * (1 + 3e-3)
    assert 6.32 * (1 - 5e-4) <= upper <= 6.33 * (1 + 5e-4)
    assert 7.0 < mode2 < 7.4  # overturning without impact above the safe window
    # the independent reference agrees on both sides of each boundary
    for boundary, below, above in (
        (lower, "safe", "after-impact"),
        (upper, "after-impact", "safe"),
        (mode2, "safe", "without-impact"),
    ):
        assert _reference_mode(zm_block, 5.0, boundary - 0.005, "linear") == below
        assert _reference_mode(zm_block, 5.0, boundary + 0.005, "linear") == above


def test_spectrum_layout_and_json(zm_block):
    spec = overturning_spectrum(zm_block, [2.0, 5.0, 9.0], [2.0, 4.0], model="linear")
    d = spec.to_dict()
    assert len(d["mode"]) == 2 and len(d["mode"][0]) == 3
    assert "amplitude_ratios" in d["layout"] and "rows" in d["layout"]
    assert set(sum(d["mode"], [])) <= {"safe", "after-impact", "without-impact"}


def test_spectrum_rejects_amplitude_below_uplift(zm_block):
    with pytest.raises(InputError, match="amplitude"):
        overturning_spectrum(zm_block, [1.0], [0.5])


def test_spectrum_settings_are_its_tolerances_and_a_history_setting_is_refused(zm_block):
    """The spectrum takes SdofSettings for rtol and atol (issue 49); it keeps no history, so an
    output interval given to it is an error naming the field, not silently dropped."""
    from colonna.rigid.solve import SdofSettings
    from colonna.rigid.spectrum import SPECTRUM_SETTINGS

    assert (SPECTRUM_SETTINGS.rtol, SPECTRUM_SETTINGS.atol) == (1e-9, 1e-12)
    with pytest.raises(InputError, match="settings.dt_out does not apply to a spectrum"):
        overturning_spectrum(zm_block, [2.0], [2.0], settings=SdofSettings(dt_out=1e-3))


def _collared_block_and_collars():
    """The benchmark's cracked block (Zhang & Makris geometry, granite mass) with two collars."""
    from colonna.rigid import Block

    free = Block.from_dimensionless(p=2.14, alpha=0.25, restitution=0.9)
    block = Block(b=free.b, h=free.h, mass=2700.0 * 4 * free.b * free.h * np.pi * free.b)
    collars = (Collar(y=0.5 * block.h, t=0.01, h=0.04), Collar(y=1.5 * block.h, t=0.01, h=0.04))
    return block, collars


def _map_pulse(block, collars, model, amplitude_ratio, omega_ratio):
    """The kernel parameters and the end time (s) of one pulse of a map, made as
    overturning_spectrum makes them."""
    import math

    from colonna.rigid import _kernels as K
    from colonna.rigid.collars import collar_kernel_constants
    from colonna.rigid.solve import kernel_block_constants

    ka, kl = collar_kernel_constants(block, collars)
    p, alpha, uplift, _, load = kernel_block_constants(block, model)
    omega = omega_ratio * (block.p / p) * p  # as overturning_spectrum and the kernel
    phase = math.asin(min(1.0, 1.0 / amplitude_ratio))
    t_end = (2.0 * math.pi - phase) / omega
    P = K.make_params(
        p,
        alpha,
        model == "nonlinear",
        K.GROUND_HARMONIC,
        amplitude_ratio * uplift,
        omega,
        phase,
        t_end,
        ka,
        kl,
        block.nu,
        uplift,
        load,
    )
    return P, t_end


@pytest.mark.parametrize("model", ["linear", "nonlinear"])
def test_collared_spectrum_stops_early_without_changing_its_answer(model):
    """With collars a free swing past alpha may be held, so the spectrum stops following a
    pulse once the free block's energy is below the largest potential (gravity + collars) on
    the way to pi/2, taking the peak from the swing's turning point. Every pulse of a grid
    then has the fate and the peak rotation of the run followed to its end (the slow way)."""
    from colonna.rigid import _kernels as K

    block, collars = _collared_block_and_collars()
    omegas, amplitudes = np.array([1.0, 2.5, 6.0]), np.array([1.5, 4.0, 12.0])
    spec = overturning_spectrum(block, omegas, amplitudes, collars, model=model)
    stopped_early = 0
    for i, ratio in enumerate(amplitudes):
        for j, omega_ratio in enumerate(omegas):
            P, t_end = _map_pulse(block, collars, model, ratio, omega_ratio)
            t_stop = t_end + 50.0 / block.p
            empty = np.zeros(1)
            runs = [
                K.rk_run(
                    P.copy(),
                    empty,
                    empty,
                    t_stop,
                    1e-10,
                    1e-12,
                    early,
                    0.0,
                    np.zeros((1, 3)),
                    np.zeros((1, 3)),
                )
                for early in (True, False)
            ]
            (status, _, peak, t_stopped, _, _), (status_full, _, peak_full, _, _, _) = runs
            stopped_early += t_stopped < 0.5 * t_stop
            assert (status == K.OVERTURNED) == (status_full == K.OVERTURNED)
            assert (spec.codes[i, j] != K.SAFE) == (status_full == K.OVERTURNED)
            if status_full != K.OVERTURNED:
                assert peak == pytest.approx(peak_full, rel=1e-6)
                assert spec.max_abs_theta[i, j] == pytest.approx(peak_full, rel=1e-6)
    assert stopped_early >= 4  # the early stop is exercised


@pytest.mark.parametrize("model", ["linear", "nonlinear"])
def test_parallel_spectrum_is_the_pulse_by_pulse_map(model):
    """The map's kernel deals its cells out to the threads in a spread order: every cell must
    hold exactly (bit for bit) what one rk_run of that cell's pulse gives, and the map must not
    depend on the thread count."""
    import numba

    from colonna.rigid import _kernels as K
    from colonna.rigid.solve import DEFAULT_ATOL

    block, collars = _collared_block_and_collars()
    omegas = np.array([0.7, 1.0, 1.9, 2.5, 4.0, 6.0, 11.0])
    amplitudes = np.array([1.5, 2.2, 4.0, 8.0, 12.0, 19.0])
    spec = overturning_spectrum(block, omegas, amplitudes, collars, model=model)
    empty = np.zeros(1)
    for i, ratio in enumerate(amplitudes):
        for j, omega_ratio in enumerate(omegas):
            P, t_end = _map_pulse(block, collars, model, ratio, omega_ratio)
            status, n_imp, peak, *_ = K.rk_run(
                P,
                empty,
                empty,
                t_end + 50.0 / block.p,
                1e-9,
                DEFAULT_ATOL,
                True,
                0.0,
                np.zeros((1, 3)),
                np.zeros((1, 3)),
            )
            assert spec.codes[i, j] == K._mode(status, n_imp), (i, j)
            assert spec.max_abs_theta[i, j] == peak, (i, j)
    assert len(set(spec.codes.ravel().tolist())) >= 2  # the grid crosses a boundary
    threads = numba.get_num_threads()
    try:
        numba.set_num_threads(1)
        serial = overturning_spectrum(block, omegas, amplitudes, collars, model=model)
    finally:
        numba.set_num_threads(threads)
    np.testing.assert_array_equal(serial.codes, spec.codes)
    np.testing.assert_array_equal(serial.max_abs_theta, spec.max_abs_theta)


def test_spread_order_visits_every_cell_once():
    """The map's cell order is a permutation: no cell is skipped or computed twice."""
    from colonna.rigid import _kernels as K

    for n in (1, 2, 3, 4, 10, 42, 80_000, 12_345):
        stride = K.spread_stride(n)
        cells = (np.arange(n, dtype=np.int64) * stride) % n
        assert np.array_equal(np.sort(cells), np.arange(n)), n


@pytest.mark.parametrize("model", ["linear", "nonlinear"])
def test_turning_point_is_the_first_root_of_the_potential(model):
    """The collared free block's turning point against a root of V(x) = E found by scipy on the
    potential sampled finely (the first crossing beyond the start)."""
    from scipy.optimize import brentq

    from colonna.rigid import _kernels as K
    from colonna.rigid.collars import collar_kernel_constants
    from colonna.rigid.solve import kernel_block_constants

    block, collars = _collared_block_and_collars()
    ka, kl = collar_kernel_constants(block, collars)
    p, alpha, uplift, _, load = kernel_block_constants(block, model)
    P = K.make_params(
        p,
        alpha,
        model == "nonlinear",
        K.GROUND_HARMONIC,
        0.0,
        1.0,
        0.0,
        0.0,
        ka,
        kl,
        block.nu,
        uplift,
        load,
    )
    V = lambda x: K.mechanical_energy(x, 0.0, P)
    xs = np.linspace(0.0, np.pi / 2, 20_001)
    vs = np.array([V(x) for x in xs])
    v_max, x_max = K.collar_barrier(P)  # the exit uses it inside |theta| < x_max only
    for start in (0.0, 0.2 * x_max, 0.6 * x_max, 0.95 * x_max):
        for fraction in (0.02, 0.3, 0.9):
            energy = V(start) + fraction * (v_max - V(start))
            beyond = (xs > start) & (vs >= energy)
            assert beyond.any()
            k = int(np.argmax(beyond))
            lo, hi = max(start, xs[k - 1]), xs[k]
            expected = brentq(lambda x, e: V(x) - e, lo, hi, args=(energy,), xtol=1e-15)
            assert K.turning_point(-start, energy, P) == pytest.approx(expected, abs=1e-12)

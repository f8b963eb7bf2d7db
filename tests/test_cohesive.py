"""The cohesive law of the intact mid-plane (colonna.fem.cohesive, issue 51): peak force and
fracture energy of a bonded pair pulled apart, elastic unloading on the damaged secant,
irreversible damage, contact and friction once fully damaged, the B-K mixed mode, the stable
step of an interface node pair, and that the scalar functions compile with numba."""

import math

import numpy as np
import pytest

from colonna.core.errors import InputError
from colonna.fem.cohesive import (
    check_parameters,
    cohesive_zone_length,
    damage,
    onset_and_final,
    penalty_stiffness,
    stable_step,
    traction,
)

# a marble: f_t 8 MPa, G_I 100 N/m (docs/physics.md gives the ranges); mode II stronger
E, H = 50e9, 0.02  # Pa, element size (m)
K = penalty_stiffness(E, H)  # alpha = 1: 2.5e12 Pa/m
FT, S, GI, GII, ETA, MU = 8e6, 12e6, 100.0, 400.0, 2.0, 0.6
PARAMS = (K, FT, S, GI, GII, ETA, MU)
AREA = 0.05 * 0.3  # m^2: a 5 cm strip of the mid-plane of a column 0.3 m thick


def law(dn, ds, d, slip, params=PARAMS):
    return traction(dn, ds, d, slip, *params)


def pull(path_n, path_s=None, d=0.0, slip=0.0, params=PARAMS):
    """The tractions along a separation path, the history carried from step to step."""
    path_s = np.zeros_like(path_n) if path_s is None else path_s
    tn, ts, ds = [], [], []
    for a, b in zip(path_n, path_s):
        t_n, t_s, d, slip = law(a, b, d, slip, params)
        tn.append(t_n)
        ts.append(t_s)
        ds.append(d)
    return np.array(tn), np.array(ts), np.array(ds)


def work(path_n, path_s, tn, ts):
    """The work done on the interface, trapezoid rule: sum of t . d(delta)."""
    return float(
        np.sum(0.5 * (tn[1:] + tn[:-1]) * np.diff(path_n))
        + np.sum(0.5 * (ts[1:] + ts[:-1]) * np.diff(path_s))
    )


def test_bonded_pair_pulled_apart_peak_and_fracture_energy():
    """Monotonic opening past full damage: peak force f_t A, work G_I A (both within 1 %), no
    force left once the pair has separated."""
    delta_f = 2 * GI / FT
    path = np.linspace(0.0, 1.5 * delta_f, 3001)
    tn, ts, d = pull(path)
    force = tn * AREA
    assert force.max() == pytest.approx(FT * AREA, rel=0.01)
    assert path[np.argmax(force)] == pytest.approx(FT / K, rel=0.01)  # the peak at f_t / K
    assert work(path, np.zeros_like(path), force, ts * AREA) == pytest.approx(GI * AREA, rel=0.01)
    assert force[-1] == 0.0 and d[-1] == 1.0 and np.all(ts == 0.0)


def test_unloading_and_reloading_follow_the_damaged_secant():
    delta_f = 2 * GI / FT
    d1 = 0.4 * delta_f
    load = np.linspace(0.0, d1, 801)
    cycle = np.concatenate([np.linspace(d1, 0.0, 401), np.linspace(0.0, d1, 401)[1:]])
    rest = np.linspace(d1, 1.5 * delta_f, 1601)
    tn_l, _, d_l = pull(load)
    dmg = d_l[-1]
    assert 0.5 < dmg < 1.0
    tn_c, _, d_c = pull(cycle, d=dmg)
    np.testing.assert_allclose(tn_c, (1 - dmg) * K * cycle, rtol=1e-12)  # through the origin
    assert np.all(d_c == dmg)  # no more damage below the largest separation
    loop = work(cycle, np.zeros_like(cycle), tn_c, np.zeros_like(tn_c))
    assert abs(loop) < 1e-9 * GI  # the cycle dissipates nothing
    tn_r, _, d_r = pull(rest, d=dmg)
    total = work(load, 0 * load, tn_l, 0 * tn_l) + loop + work(rest, 0 * rest, tn_r, 0 * tn_r)
    assert total == pytest.approx(GI, rel=0.01)  # the cycle changed nothing of the energy


def test_damage_never_decreases_on_a_random_path():
    rng = np.random.default_rng(51)
    steps = rng.normal(scale=2e-6, size=(4000, 2))
    path = np.cumsum(steps, axis=0)
    _, _, d = pull(path[:, 0], path[:, 1])
    assert np.all(np.diff(d) >= 0.0) and d.min() >= 0.0 and d.max() <= 1.0
    assert d[-1] > 0.1  # the path went far enough to damage (so the test can fail)


def test_fully_damaged_interface_carries_contact_and_friction_only():
    d, slip = 1.0, 0.0
    t_n, t_s, d, slip = law(1e-4, 3e-5, d, slip)  # open: nothing
    assert (t_n, t_s) == (0.0, 0.0)
    dn = -2e-6  # closed: the penalty pushes the faces apart, damage or not
    t_n, t_s, _, slip_stick = law(dn, 3e-5 + 1e-7, d, slip)
    assert t_n == pytest.approx(K * dn)
    # the slip after opening was reset to the separation there: a small move sticks elastically
    assert t_s == pytest.approx(K * 1e-7) and slip_stick == slip
    t_n, t_s, _, slip_far = law(dn, 1e-3, d, slip)  # a large move slides at mu |t_n|
    assert t_s == pytest.approx(MU * abs(t_n))
    assert slip_far == pytest.approx(1e-3 - MU * abs(t_n) / K)
    t_n, t_s, _, _ = law(dn, -1e-3, d, slip)
    assert t_s == pytest.approx(-MU * abs(t_n))


def test_vanishing_opening_is_mode_one():
    """An opening whose square underflows takes the mode-I onset, not 0 / 0."""
    assert onset_and_final(1e-200, 0.0, K, FT, S, GI, GII, ETA) == (FT / K, 2 * GI / FT)
    assert law(1e-200, 0.0, 0.0, 0.0) == (K * 1e-200, 0.0, 0.0, 0.0)


def test_intact_interface_in_compression_is_not_damaged_by_pressure():
    tn, ts, d = pull(np.linspace(0.0, -50 * FT / K, 200))
    assert np.all(d == 0.0) and tn[-1] == pytest.approx(-50 * FT)


@pytest.mark.parametrize("ratio", [0.0, 0.5, 1.0, 3.0, np.inf])
def test_mixed_mode_dissipates_the_bk_toughness(ratio):
    """Along a proportional path delta_s = ratio delta_n the work to full damage is the
    Benzeggagh-Kenane toughness G_I + (G_II - G_I) B^eta, B = ratio^2 / (1 + ratio^2)."""
    B = 1.0 if np.isinf(ratio) else ratio**2 / (1 + ratio**2)
    Gc = GI + (GII - GI) * B**ETA
    angle = math.atan(ratio)
    d0, df = onset_and_final(math.cos(angle), math.sin(angle), K, FT, S, GI, GII, ETA)
    assert 0.5 * K * d0 * df == pytest.approx(Gc, rel=1e-12)
    m = np.linspace(0.0, 1.3 * df, 4001)
    path_n, path_s = m * math.cos(angle), m * math.sin(angle)
    if np.isinf(ratio):
        path_n = np.full_like(m, 1e-30)  # just open: pure shear, not contact
    tn, ts, d = pull(path_n, path_s)
    assert work(path_n, path_s, tn, ts) == pytest.approx(Gc, rel=0.01)
    assert d[-1] == 1.0


def test_equal_modes_make_an_effective_separation_law():
    """s = f_t and G_II = G_I: the damage depends on the effective separation only."""
    params = (K, FT, FT, GI, GI, ETA, MU)
    dm = 0.5 * (FT / K + 2 * GI / FT)
    for angle in (0.0, 0.3, 0.9, 1.4):
        dn, ds = dm * math.cos(angle), dm * math.sin(angle)
        assert damage(dn, ds, 0.0, *params[:-1]) == pytest.approx(
            damage(dm, 0.0, 0.0, *params[:-1]), rel=1e-12
        )


def test_stable_step_is_the_node_pairs_frequency():
    """2 / omega of two lumped masses joined by K A: the eigenvalue of M^-1 K, and a
    central-difference integration stays bounded just below it and blows up just above."""
    m_a, m_b = 2.0, 3.0
    k = K * 1e-4
    dt = stable_step(K, 1e-4, m_a, m_b)
    stiff = np.array([[k, -k], [-k, k]])
    omega = np.sqrt(np.max(np.linalg.eigvals(np.diag([1 / m_a, 1 / m_b]) @ stiff).real))
    assert dt == pytest.approx(2 / omega, rel=1e-12)

    def peak(step):
        u, v = np.array([0.0, 1e-6]), np.zeros(2)
        masses, big = np.array([m_a, m_b]), 0.0
        for _ in range(2000):
            v += step * (-stiff @ u) / masses
            u += step * v
            big = max(big, np.abs(u).max())
        return big

    assert peak(0.99 * dt) < 1e-4 and peak(1.01 * dt) > 1.0


def test_dynamic_pair_energy_balance_closes_with_the_cohesive_work():
    """Two blocks bonded by the interface fly apart: kinetic energy + cohesive work (trapezoid
    rule) stays the initial kinetic energy under central differences, and G_I A of it is gone
    once they have separated (the step resolves the softening: 44 steps across it; at 0.5 of the
    stable step it crosses in 2 and dissipates 53 % of G_I A, at 0.9 in 1 and nothing)."""
    m = 2700 * 0.1 * AREA  # kg: 0.1 m of marble each side of the strip
    v0 = 1.0  # m/s each way: 4 J of kinetic energy against G_I A = 1.5 J
    dt = 0.02 * stable_step(K, AREA, m, m)
    x0, x1, v_0, v_1 = 0.0, 0.0, -v0, v0
    d, slip, w, f_old = 0.0, 0.0, 0.0, 0.0
    ke0 = 0.5 * m * (v_0**2 + v_1**2)
    for _ in range(20000):
        gap_old = x1 - x0
        x0, x1 = x0 + dt * v_0, x1 + dt * v_1
        gap = x1 - x0
        t_n, _, d, slip = law(gap, 0.0, d, slip)
        f = t_n * AREA  # pulls the blocks together
        w += 0.5 * (f + f_old) * (gap - gap_old)
        f_old = f
        v_0, v_1 = v_0 + dt * f / m, v_1 - dt * f / m
        if d == 1.0:
            break
    ke = 0.5 * m * (v_0**2 + v_1**2)
    assert d == 1.0
    assert ke + w == pytest.approx(ke0, rel=1e-3)
    assert ke0 - ke == pytest.approx(GI * AREA, rel=0.01)


def test_a_compiled_kernel_calls_the_law():
    """The law is numba-compiled and callable from another compiled function (a kernel), with
    the numbers of its Python source."""
    numba = pytest.importorskip("numba")

    @numba.njit
    def kernel(dn, ds, d0, params):
        K_, ft, s, gi, gii, eta, mu = params
        return traction(dn, ds, d0, 0.0, K_, ft, s, gi, gii, eta, mu)

    for dn, ds, d0 in ((1e-6, 0.0, 0.0), (5e-6, 4e-6, 0.2), (-1e-6, 2e-5, 1.0), (2e-5, 0, 0)):
        expected = traction.py_func(dn, ds, d0, 0.0, *PARAMS)
        assert kernel(dn, ds, d0, PARAMS) == pytest.approx(expected, rel=1e-14)


def test_zone_length_and_penalty():
    assert cohesive_zone_length(E, GI, FT) == pytest.approx(E * GI / FT**2)
    assert penalty_stiffness(E, H, alpha=50) == pytest.approx(50 * E / H)


@pytest.mark.parametrize(
    "change, words",
    [
        ({"K": 1e9}, "penalty stiffness K"),  # below f_t^2 / (2 G_I) = 3.2e11
        ({"f_t": -1.0}, "tensile strength"),
        ({"G_II": 0.0}, "mode-II fracture energy"),
        ({"eta": 9.0}, "B-K exponent"),
        ({"mu": -0.1}, "friction"),
    ],
)
def test_bad_parameters_name_themselves(change, words):
    kw = dict(K=K, f_t=FT, s=S, G_I=GI, G_II=GII, eta=ETA, mu=MU) | change
    with pytest.raises(InputError, match=words):
        check_parameters(**kw)
    check_parameters(*PARAMS)  # the good set passes

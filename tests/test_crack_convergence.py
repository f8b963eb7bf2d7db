"""The crack contact against statics and closed forms, penalty and exact (issue 38): the
closed crack's normal force where a known force presses the halves together, Coulomb slip
onset and friction work of a block sliding on the base and of a half sliding down the crack,
and the uncollared default column's first swing along the contact's convergence path (slow).

Closed forms (Coulomb friction mu, gravity g, a constant or ramped ground acceleration):
- a block on the ground under a(t) = A t / T (0 <= t <= T, zero after) slips once a = mu g,
  at t_s = mu g T / A; its slip by T is (A / T) (T - t_s)^3 / 6, and it then slides on at the
  deceleration mu g: v_T^2 / (2 mu g) more, v_T = (A / T) (T - t_s)^2 / 2. Friction work: mu m
  g times the whole slip.
- a half held off the ground beside the other, under a constant ground acceleration a toward
  the other: the crack presses on it with N = m a (its horizontal balance), and it slides down
  the crack with g - mu a: s = (g - mu a) t^2 / 2, friction work mu N s.
"""

import dataclasses

import numpy as np
import pytest

from colonna.core.ground import NoMotion, Record
from colonna.core.motion import Motion
from colonna.fem.assembly import Stone
from colonna.fem.model import ContactSettings, Loads, build_model
from colonna.fem.settings import FemSettings, FemStart
from colonna.fem.solver import ENERGY_ERROR_LIMIT, run
from colonna.meshes import column_mesh

G = 9.81
STONE = Stone()
ENFORCEMENTS = ["penalty", "lagrange"]


@pytest.mark.parametrize("enforcement", ENFORCEMENTS)
def test_the_closed_cracks_force_is_the_statics_of_a_half(enforcement):
    """A cracked column at rest under a top load of twice its weight: the only horizontal
    forces on the left half are the base's friction and the crack's normal force (its friction
    is vertical), so their means agree (2 %); the crack never opens, no sample is below zero."""
    width, height, thickness = 0.4, 2.0, 0.3
    weight = STONE.density * width * height * thickness * G
    mesh = column_mesh(width, height, 0.1, cracked=True, grading=0.3)
    contact = ContactSettings(enforcement=enforcement)
    model = build_model(mesh, STONE, thickness, contact=contact, loads=Loads(top_load=2.0 * weight))
    r = run(model, Motion(NoMotion(), 0.02), FemSettings(output_interval=1e-3, progress=False))
    s, h = r.summary, r.history
    left = mesh.node_body[model.base_nodes] == 0
    base_friction = np.mean([frame["base_ft"][left].sum() for _, frame in r.contact_frames])
    assert base_friction > 50.0  # N: the Poisson spread presses the halves together
    assert s["crack_normal_force_mean"] == pytest.approx(base_friction, rel=0.02)
    assert s["crack_closed_fraction"] == 1.0
    assert h["crack_normal_force"].min() > 0.0
    assert s["energy_error_max"] < ENERGY_ERROR_LIMIT


def _sliding_block(mu):
    """A squat solid block (1 m x 0.25 m, 0.3 m thick) under the ramp A t / T, A = 2 mu g."""
    mesh = column_mesh(1.0, 0.25, 0.125, cracked=False, grading=0.0)
    model = build_model(mesh, STONE, 0.3, contact=ContactSettings(friction=mu))
    ramp_time, peak = 0.05, 2.0 * mu * G
    ramp = Record(np.array([0.0, ramp_time]), np.array([0.0, peak]), name="ramp")
    return model, ramp, ramp_time, peak


def test_a_block_slips_on_the_base_when_the_ground_exceeds_mu_g():
    """Coulomb slip onset and friction work at the base against the closed form (module doc):
    no slip before t_s (below a thousandth of the final slip), then the slip by T and the
    final slip within 1 %, and the base's friction work mu m g s within 1 %."""
    mu = 0.3
    model, ramp, T, A = _sliding_block(mu)
    r = run(model, Motion(ramp, 0.08), FemSettings(output_interval=5e-4, progress=False))
    h, s = r.history, r.summary
    t_slip = mu * G * T / A
    slip_T = A / T * (T - t_slip) ** 3 / 6.0
    v_T = A / T * (T - t_slip) ** 2 / 2.0
    total = slip_T + v_T**2 / (2.0 * mu * G)
    slip = -h["translation_x_1"]  # the ground force pushes the block toward -x
    assert np.all(np.abs(slip[h["t"] < 0.95 * t_slip]) < 1e-3 * total)
    assert np.interp(T, h["t"], slip) == pytest.approx(slip_T, rel=0.01)
    assert slip[-1] == pytest.approx(total, rel=0.01)
    mass = model.mass[0::2].sum()
    assert s["friction_work_base"] == pytest.approx(mu * mass * G * total, rel=0.01)
    assert s["energy_error_max"] < ENERGY_ERROR_LIMIT


def _half_sliding_down_the_crack(enforcement):
    """The right half (1 m x 1 m, 0.3 m thick, friction 0.3) held 20 mm above the ground beside
    the left one, pressed on the crack by a ground acceleration a(t) = a min(t / tau, 1), a =
    0.1 g, tau = 10 ms (the left half's base friction holds both: 0.2 m g < 0.3 (m g + 0.3 m
    a)); 60 ms. Returns (run, its half's mass, mu, the ramp's (tau, a), duration)."""
    mu, a, tau, duration = 0.3, 0.1 * G, 0.01, 0.06
    mesh = column_mesh(2.0, 1.0, 0.125, cracked=True, grading=0.0)
    contact = ContactSettings(friction=mu, enforcement=enforcement)
    model = build_model(mesh, STONE, 0.3, contact=contact)
    x = model.X.copy()
    right = np.flatnonzero(mesh.node_body == 1)
    x[2 * right + 1] += 0.02
    push = Record(np.array([0.0, tau, 1.0]), np.array([0.0, a, a]), name="ramp")
    r = run(
        model,
        Motion(push, duration),
        FemSettings(output_interval=2.5e-4, progress=False),
        FemStart(state=(x, np.zeros_like(x))),
    )
    return r, model.mass[2 * right].sum(), mu, (tau, a), duration


def _sliding_closed_form(mass, mu, tau, a, duration):
    """Slip of the half down the crack (m) and the crack's friction work (J) by ``duration``:
    s'' = g - mu a(t), work mu m a(t) s' integrated (fine trapezoids of the closed-form
    integrands)."""
    t = np.linspace(0.0, duration, 200_001)
    acc = a * np.minimum(t / tau, 1.0)
    dt = t[1] - t[0]
    pressed = np.concatenate(([0.0], np.cumsum(0.5 * (acc[1:] + acc[:-1]) * dt)))
    speed = G * t - mu * pressed
    slip = np.sum(0.5 * (speed[1:] + speed[:-1]) * dt)
    work = mu * mass * np.sum(0.5 * (acc[1:] * speed[1:] + acc[:-1] * speed[:-1]) * dt)
    return slip, work


@pytest.mark.parametrize("enforcement", ENFORCEMENTS)
def test_a_half_slides_down_the_crack_at_the_coulomb_rate(enforcement):
    """The half pressed on the crack by m a(t) (module doc, _half_sliding_down_the_crack): the
    crack's normal force is m a in the mean once the ramp is past (2 %; the half rings about
    it) and never below zero, and the half slides down as s'' = g - mu a(t): 1 % with the
    exact contact; 2 % with the penalty, whose slip includes its tangential springs' stretch
    and their restarts (measured 1.2 % on the bed's base)."""
    r, mass, mu, (tau, a), duration = _half_sliding_down_the_crack(enforcement)
    h = r.history
    force = h["crack_normal_force"][h["t"] > 2.0 * tau]
    assert force.mean() == pytest.approx(mass * a, rel=0.02)
    assert force.min() >= 0.0
    slip = -(h["translation_y_2"] - h["translation_y_1"])
    slip_expected, _ = _sliding_closed_form(mass, mu, tau, a, duration)
    tolerance = 0.01 if enforcement == "lagrange" else 0.02
    assert slip[-1] - slip[0] == pytest.approx(slip_expected, rel=tolerance)
    assert r.summary["energy_error_max"] < ENERGY_ERROR_LIMIT


@pytest.mark.parametrize(
    "enforcement",
    [
        pytest.param(
            "penalty",
            marks=pytest.mark.xfail(
                strict=True,
                reason="penalty crack friction does about 10 % too little work: a node that "
                "parts and closes again restarts its stick spring from zero (issue 38)",
            ),
        ),
        "lagrange",
    ],
)
def test_the_crack_friction_work_is_coulombs(enforcement):
    """The crack's friction work on the sliding half is mu m a(t) s' integrated (1 %): with
    exact contact; the penalty contact's is about 10 % short (measured 0.90)."""
    r, mass, mu, (tau, a), duration = _half_sliding_down_the_crack(enforcement)
    _, work = _sliding_closed_form(mass, mu, tau, a, duration)
    assert r.summary["friction_work_crack"] == pytest.approx(work, rel=0.01)


def _first_swing_medians(size, replicas=8, safety=0.9, **contact):
    """Median over ``replicas`` round-off replicas of the uncollared default column (on the
    study's bed) of its first peak of |theta| (rad) under the default pulse, and the replicas'
    (min, max)."""
    from colonna.fem.solver import run_ensemble
    from colonna.studies.study import load

    study = load("studies/default.toml").fem
    mesh = column_mesh(study.width, study.height, size, cracked=True, grading=study.grading)
    settings = dataclasses.replace(study.contact, **contact)
    model = build_model(mesh, study.stone, study.thickness, (), settings, bed=study.bed)
    runs = run_ensemble(
        model,
        Motion(study.ground, 0.9),
        FemSettings(output_interval=1e-3, safety=safety, progress=False),
        replicas=replicas,
    )
    peaks = []
    for r in runs:
        theta = np.maximum(np.abs(r.history["theta_left"]), np.abs(r.history["theta_right"]))
        rising = (theta[1:-1] > 1e-3) & (theta[1:-1] >= theta[:-2]) & (theta[1:-1] > theta[2:])
        peaks.append(theta[1 + np.flatnonzero(rising)[0]])
    return float(np.median(peaks)), (min(peaks), max(peaks))


# the two meshes of the first swing's convergence (m): two and four elements across a half
FINE, FINER = 0.1125, 0.05625


@pytest.mark.slow
@pytest.mark.chaotic
def test_the_uncollared_first_swing_converges_with_exact_crack_contact():
    """The uncollared default column's first swing (docs/validation.md, "The crack contact's
    convergence path") with the default, exact crack contact on the mortar bed, judged by the
    medians of 8 round-off replicas (the crack's ringing makes it chaotic). The converged value
    is the 0.05625 m mesh's (measured 50.84 mrad; 50.55 at half its step, 51.54 on the study's
    0.0375 m mesh). Against it, within 3 %: the default on the 0.1125 m mesh (50.43) and at
    half its step (50.47); on both meshes the base's free settings over the ranges issue 38
    asks for, within 3 % of that mesh's default: contact damping 10 % (measured 49.90 and
    50.50), friction filter 0 and 2 ms (50.99, 50.44; 50.90, 50.41), on the coarser mesh
    damping 1 % and 20 % (50.52, 49.83: the ends of the range a study file accepts) and on the
    finer damping 0 (50.89; on 0.1125 m it is off by 4.2 %, the xfail below, which is why a
    study file refuses it unless intended). The penalty crack at
    its own defaults sits below the exact contact's band on the one-element mesh (46.13 mrad
    against 47.46-49.65)."""
    converged, _ = _first_swing_medians(FINER)
    default, _ = _first_swing_medians(FINE)
    assert default == pytest.approx(converged, rel=0.03)
    assert _first_swing_medians(FINE, safety=0.45)[0] == pytest.approx(converged, rel=0.03)
    for size, reference, settings in (
        (
            FINE,
            default,
            (
                {"damping": 0.01},
                {"damping": 0.1},
                {"damping": 0.2},
                {"friction_filter": 0.0},
                {"friction_filter": 2e-3},
            ),
        ),
        (FINER, converged, ({"damping": 0.0}, {"damping": 0.1}, {"friction_filter": 0.0})),
    ):
        for setting in settings:
            median, _ = _first_swing_medians(size, **setting)
            assert median == pytest.approx(reference, rel=0.03), (size, setting)
    _, band = _first_swing_medians(0.225)
    penalty, _ = _first_swing_medians(0.225, replicas=2, enforcement="penalty")
    assert penalty < band[0]


@pytest.mark.slow
@pytest.mark.chaotic
@pytest.mark.xfail(
    strict=False,  # a branch taken or not: another rounding (NUMBA_CPU_NAME) may not take it
    reason="an undamped bed on the 0.1125 m mesh: every replica takes another branch, 4.2 % "
    "below the damped ones (48.33 against 50.43 mrad; 1 % damping: 50.52; issue 38)",
)
def test_an_undamped_bed_moves_the_first_swing_by_at_most_3_percent():
    """Base contact damping 0 against the default 5 % on the 0.1125 m mesh (3 %)."""
    default, _ = _first_swing_medians(FINE)
    undamped, _ = _first_swing_medians(FINE, damping=0.0)
    assert undamped == pytest.approx(default, rel=0.03)


def test_the_exact_crack_contact_is_action_and_reaction():
    """Two halves in flight (2 mm above the ground), the right one thrown at the left at 0.5
    m/s across a 1 mm gap: the multipliers act on both faces equal and opposite, so the
    horizontal momentum is the same to round-off through the impact, the vertical one changes
    by gravity's impulse alone; the impact dissipates (plastic, node by node) and the energy
    balance closes."""
    mesh = column_mesh(2.0, 1.0, 0.125, cracked=True, grading=0.0)
    model = build_model(mesh, STONE, 0.3, contact=ContactSettings(friction=0.5))
    x = model.X.copy()
    right = np.flatnonzero(mesh.node_body == 1)
    x[2 * right] += 1e-3
    x[1::2] += 2e-3
    v = np.zeros_like(x)
    v[2 * right] = -0.5
    v[2 * right + 1] = -0.1
    duration = 0.008  # the halves meet at 2 ms, land at 20 ms
    r = run(
        model,
        Motion(NoMotion(), duration),
        FemSettings(output_interval=1e-4, progress=False),
        FemStart(state=(x, v)),
    )
    h, s = r.history, r.summary
    mass = model.mass[0::2]
    momentum = np.array([(mass @ u[:, 0], mass @ u[:, 1]) for _, u in r.velocity_frames])
    assert h["crack_normal_force"].max() > 0.0  # they met
    assert h["base_normal_force_1"].max() == h["base_normal_force_2"].max() == 0.0
    np.testing.assert_allclose(momentum[:, 0], momentum[0, 0], rtol=1e-12)
    impulse = -G * mass.sum() * h["t"]  # gravity's, over n steps of dt
    np.testing.assert_allclose(momentum[1:, 1] - momentum[0, 1], impulse[1:], rtol=1e-9)
    assert s["contact_damping_work"] > 0.01 * 0.5 * mass[right].sum() * 0.5**2
    assert s["energy_error_max"] < 1e-4

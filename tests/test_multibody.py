"""The rigid multibody contact model against closed forms, the SDOF solvers and its own limits."""

import math

import numpy as np
import pytest

from colonna.core.collar_law import OUT_SIZE, STATE_SIZE
from colonna.core.motion import Motion, Release
from colonna.rigid import (
    Block,
    Collar,
    HarmonicPulse,
    InputError,
    NoMotion,
    Record,
    housner_restitution,
    pulse_from_ratios,
    rock,
)
from colonna.rigid import _multibody as K
from colonna.rigid.multibody import (
    MultibodyContact,
    MultibodySettings,
    build_column,
    default_step,
    multibody_outcome,
    multibody_spectrum,
    rock_multibody,
)
from colonna.rigid.solve import SdofSettings

STICK = 2.0  # a friction coefficient that forbids sliding of these blocks


def zm_block():
    return Block.from_dimensionless(p=2.14, alpha=0.25)  # Housner restitution


def marble_half():
    """One half of the default study's column: 0.45 m wide, 4 m tall, t = pi * width / 4."""
    return Block.from_density(b=0.1125, h=2.0, density=2700.0, thickness=math.pi * 0.45 / 4)


def theta_error(result, reference, t_end, body=0, alpha=None):
    """max |theta_mb - theta_ref| / alpha for t <= t_end."""
    sel = result.time <= t_end
    ref = np.interp(result.time[sel], reference.time, reference.theta)
    alpha = alpha if alpha is not None else result.column.block.alpha
    return np.max(np.abs(result.theta[sel, body] - ref)) / alpha


def assert_energy_closes(result, tol=1e-2):
    assert result.summary()["energy_error_max"] < tol


# --- one solid block: the SDOF nonlinear model is its no-slip limit ---------------------------


@pytest.mark.chaotic
@pytest.mark.parametrize("omega_ratio, amplitude_ratio", [(5.0, 2.0), (5.0, 2.5), (8.0, 3.0)])
def test_solid_block_follows_nonlinear_sdof_to_the_third_impact(omega_ratio, amplitude_ratio):
    blk = zm_block()
    pulse = pulse_from_ratios(blk, "sine", omega_ratio, amplitude_ratio, "nonlinear")
    ref = rock(
        blk, Motion(pulse, duration=8.0), model="nonlinear", settings=SdofSettings(dt_out=1e-3)
    )
    mb = rock_multibody(
        blk,
        Motion(pulse, duration=8.0),
        contact=MultibodyContact(friction=STICK),
        settings=MultibodySettings(dt_out=1e-3),
    )
    assert ref.impacts >= 3 and mb.impacts >= 3
    assert theta_error(mb, ref, ref.impact_times[2]) < 1e-3
    np.testing.assert_allclose(mb.impacts_table[:3, 0], ref.impact_times[:3], atol=2e-3)
    assert mb.mode == ref.mode
    assert_energy_closes(mb)


def _sdof_boundaries(blk, omega_ratio, low, high, n=60):
    """Amplitude ratios where the nonlinear SDOF's overturning verdict changes, by bisection."""

    def over(a):
        return rock(
            blk,
            Motion(pulse_from_ratios(blk, "sine", omega_ratio, a, "nonlinear")),
            model="nonlinear",
        ).overturned

    grid = np.linspace(low, high, n)
    fate = [over(a) for a in grid]
    out = []
    for k in range(1, n):
        if fate[k] != fate[k - 1]:
            lo, hi = grid[k - 1], grid[k]
            for _ in range(30):
                mid = 0.5 * (lo + hi)
                lo, hi = (mid, hi) if over(mid) == fate[k - 1] else (lo, mid)
            out.append(0.5 * (lo + hi))
    return out


@pytest.mark.chaotic
def test_overturning_classification_matches_sdof_on_both_sides_of_zhang_makris_boundaries():
    blk = zm_block()
    boundaries = _sdof_boundaries(blk, 5.0, 1.5, 10.0)
    assert len(boundaries) >= 2  # the safe region, the overturning one, the safe island
    for boundary in boundaries:
        for side in (0.99, 1.01):
            pulse = pulse_from_ratios(blk, "sine", 5.0, side * boundary, "nonlinear")
            ref = rock(blk, Motion(pulse), model="nonlinear")
            mb = rock_multibody(blk, Motion(pulse), contact=MultibodyContact(friction=STICK))
            assert mb.mode == ref.mode, (boundary, side)


@pytest.mark.parametrize("alpha", [0.1, 0.2, 0.3])
def test_plastic_impact_gives_housners_ratio(alpha):
    """e_n = 0 and no slip: angular momentum about the new pivot is conserved, which is
    Housner's 1 - 1.5 sin^2(alpha); nothing in the model imposes it."""
    blk = Block.from_dimensionless(p=2.0, alpha=alpha)
    mb = rock_multibody(
        blk,
        Motion(NoMotion(), duration=4.0),
        contact=MultibodyContact(friction=STICK),
        release=Release(tilt=0.5 * alpha),
    )
    ratios = mb.impact_velocity_ratios(0)
    assert ratios.size >= 2
    np.testing.assert_allclose(ratios[:3], housner_restitution(alpha), rtol=5e-3)
    assert_energy_closes(mb)


def test_free_rocking_from_rest_reaches_the_vertical_at_the_closed_form_time():
    """Corrected Eq. 13 (linearised): t = arccosh(1 / (1 - theta0/alpha)) / p; the nonlinear
    block of small alpha is within alpha^2 of it."""
    blk = Block.from_dimensionless(p=2.0, alpha=0.05)
    mb = rock_multibody(
        blk,
        Motion(NoMotion(), duration=2.0),
        contact=MultibodyContact(friction=STICK),
        release=Release(tilt=0.5 * 0.05),
    )
    assert mb.impacts_table[0, 0] == pytest.approx(blk.time_to_vertical(0.025), rel=5e-3)


@pytest.mark.chaotic
def test_mirror_symmetry():
    blk = zm_block()
    pulse = pulse_from_ratios(blk, "sine", 4.0, 2.5, "nonlinear")
    mirrored = type(pulse)(pulse.kind, -pulse.amplitude, pulse.omega, pulse.phase, pulse.duration)
    a = rock_multibody(blk, Motion(pulse, duration=3.0), contact=MultibodyContact(friction=STICK))
    b = rock_multibody(
        blk, Motion(mirrored, duration=3.0), contact=MultibodyContact(friction=STICK)
    )
    np.testing.assert_allclose(a.theta, -b.theta, atol=1e-9 * blk.alpha)


def test_time_step_convergence():
    """theta up to the third impact converges with the step. Impacts are first order in the
    substep h / refine (where an impact falls within it is luck, so the error is bounded rather
    than monotonic): refining the step or the impact substeps both reduce it."""
    blk = zm_block()
    pulse = pulse_from_ratios(blk, "sine", 5.0, 2.0, "nonlinear")
    ref = rock(
        blk, Motion(pulse, duration=4.0), model="nonlinear", settings=SdofSettings(dt_out=1e-5)
    )
    t3 = ref.impact_times[2]

    def error(dt, refine=32):
        mb = rock_multibody(
            blk,
            Motion(pulse, duration=4.0),
            contact=MultibodyContact(friction=STICK),
            settings=MultibodySettings(dt=dt, dt_out=dt, refine=refine),
        )
        return theta_error(mb, ref, t3)

    by_step = [error(dt) for dt in (2e-3, 1e-3, 5e-4, 2.5e-4)]
    assert max(by_step[1:]) < 0.1 * by_step[0]
    assert by_step[-1] < 1e-4
    by_refinement = [error(5e-4, refine) for refine in (1, 32, 256)]
    assert by_refinement[0] > 5.0 * by_refinement[1] > 5.0 * by_refinement[2]


def _cracked_column(from_rest: bool = False):
    """Half of a 0.45 x 4 m cracked marble column under a sine pulse of 3 x uplift at
    Omega/p = 3 (the default study's column and pulse). The paper's pulse starts at the
    uplift acceleration of a half; ``from_rest`` starts it from zero acceleration."""
    blk = Block.from_density(b=0.1125, h=2.0, density=2700.0, thickness=math.pi * 0.1125)
    pulse = pulse_from_ratios(blk, "sine", 3.0, 3.0, "nonlinear")
    if from_rest:
        pulse = HarmonicPulse(
            "sine", pulse.amplitude, pulse.omega, 0.0, 2.0 * math.pi / pulse.omega
        )
    return blk, pulse


COLLARS = (
    Collar(y=0.5, t=0.008, h=0.06),
    Collar(y=2.0, t=0.008, h=0.06),
    Collar(y=3.5, t=0.008, h=0.06),
)


@pytest.mark.parametrize("from_rest", [False, True])
def test_cracked_column_onset_converges_with_the_step(from_rest):
    """The crack starts closed with no force across it. A crack contact whose gap is within the
    midpoint scheme's drift (g h^2) and whose free motion closes it is active: without that
    the drift decided whether the halves pressed, and the rotation at 0.3 s moved by 17 %
    between steps 1e-9 apart (the paper's pulse, which starts at a half's uplift) and converged
    at order 0.3 (a pulse from rest). Now the default step is within 0.5 % of one 16 times
    smaller, the error falls with the step, and a step changed by 1e-9 changes nothing."""
    blk, pulse = _cracked_column(from_rest)
    step = default_step(build_column(blk, cracked=True, collars=COLLARS), pulse)

    def theta(factor):
        r = rock_multibody(
            blk,
            Motion(pulse, duration=0.35),
            COLLARS,
            contact=MultibodyContact(cracked=True, friction=0.7),
            settings=MultibodySettings(dt=step * factor),
        )
        return np.interp(0.3, r.time, r.theta[:, 0])

    fine = theta(1.0 / 16.0)
    assert abs(fine) > 3e-3
    errors = [abs(theta(f) / fine - 1.0) for f in (1.0, 0.25)]
    assert errors[0] < 5e-3 and errors[1] < 0.5 * errors[0]
    assert theta(1.0 + 1e-9) == pytest.approx(theta(1.0), rel=1e-6)


def test_active_set_solves_the_redundant_contact_problem_exactly():
    """The contact problem of one step of that column (two base pivots and two crack
    contacts: 8 rows on 6 dof), solved by enumerating every open / stick / slide status with
    a linear program for the impulses: exactly one status combination is feasible, and the
    active-set solve finds its velocities from any start."""
    import itertools

    from scipy.optimize import linprog

    from colonna.rigid.multibody import IMPACT_THRESHOLD, _ground_arrays, tilted_state

    blk, pulse = _cracked_column(from_rest=True)
    column = build_column(blk, cracked=True, friction=0.7)
    ground = _ground_arrays(pulse, blk.g)
    q, v = tilted_state(column, 0.0, 0.0)
    nb, nc = 2, column.cand_a.size
    bodies, contacts, collars = column.kernel_bundles()
    settings = K.Settings(
        h=9e-5,
        n_steps=0,
        refine=1,
        e_n=0.0,
        out_every=1,
        free_halves=False,
        barrier=0.0,
        early_exit=False,
        impact_tol=IMPACT_THRESHOLD * blk.alpha,
        energy_scale=1.0,
        tol=1e-10,
        max_iter=500,
    )
    scratch = K.new_scratch(nb, nc, 0, 0)
    state = K.new_step_state(nb, nc, np.zeros((10, 4)))
    was_active = state.was_active
    h = settings.h
    for step in range(int(0.3 / h)):  # to t = 0.3 s: the halves rock together
        K._step(step * h, h, q, v, bodies, contacts, collars, ground, settings, scratch, state)
    n = int(was_active.sum())  # the last step's problem
    assert n == 4
    rows = scratch.act[:n]
    W, b = scratch.W[: 2 * n, : 2 * n].copy(), scratch.bvec[: 2 * n].copy()
    mu = column.cand_mu[rows]
    feasible = []
    for combo in itertools.product(range(4), repeat=n):  # open, stick, slide +, slide -
        eq, beq, ub, bub = [], [], [], []
        for j, st in enumerate(combo):
            en, et = np.eye(2 * n)[2 * j], np.eye(2 * n)[2 * j + 1]
            if st == 0:
                eq += [en, et]
                beq += [0, 0]
                ub.append(-W[2 * j])
                bub.append(b[2 * j])
            elif st == 1:
                eq += [W[2 * j], W[2 * j + 1]]
                beq += [-b[2 * j], -b[2 * j + 1]]
                ub += [-en, et - mu[j] * en, -et - mu[j] * en]
                bub += [0, 0, 0]
            else:
                sign = 1.0 if st == 2 else -1.0
                eq += [W[2 * j], et + sign * mu[j] * en]
                beq += [-b[2 * j], 0]
                ub += [-en, -sign * W[2 * j + 1]]
                bub += [0, sign * b[2 * j + 1]]
        lp = linprog(
            np.zeros(2 * n),
            A_ub=np.array(ub),
            b_ub=bub,
            A_eq=np.array(eq),
            b_eq=beq,
            bounds=[(None, None)] * (2 * n),
        )
        if lp.status == 0:
            feasible.append(W @ lp.x + b)
    assert len(feasible) == 1
    exact = feasible[0]
    scale = np.abs(b).max()
    for sweeps in (0, 100):  # from nothing, and from the kernel's Gauss-Seidel start
        P = np.zeros(2 * n)
        if sweeps:
            K._solve_contacts(W, b, P, mu, n, 1e-10, sweeps)
        assert K._active_set(W, b, P, mu, n)
        assert np.abs(W @ P + b - exact).max() < 1e-8 * scale


# --- friction: sliding and the rock/slide criterion ---------------------------------------------


def constant_ground(acceleration, duration):
    return Record(np.array([0.0, duration]), np.array([acceleration, acceleration]), "constant")


@pytest.mark.parametrize("factor", [0.95, 1.05, 1.5])
def test_block_on_tilted_ground_slides_exactly_when_tilt_exceeds_friction_angle(factor):
    """A constant ground acceleration a tilts gravity by atan(a/g) in the ground frame. A squat
    block (tan alpha > mu: it cannot rock first) sticks for a < mu g and slides at a - mu g."""
    mu = 0.4
    blk = Block(b=1.0, h=0.5, mass=100.0)
    g = blk.g
    a = factor * mu * g
    mb = rock_multibody(
        blk,
        Motion(constant_ground(a, 2.0), duration=1.0),
        contact=MultibodyContact(friction=mu),
        settings=MultibodySettings(dt_out=1e-2),
    )
    x = mb.centroid[:, 0, 0]
    if factor < 1.0:
        assert np.max(np.abs(x)) < 1e-9
    else:
        expected = -0.5 * (a - mu * g) * mb.time**2  # body force -m a, friction + mu m g
        np.testing.assert_allclose(x, expected, rtol=2e-2, atol=1e-9)
    assert np.max(np.abs(mb.theta)) < 1e-9
    assert_energy_closes(mb)


def test_slender_block_slides_instead_of_rocking_when_mu_is_below_tan_alpha():
    """Rock or slide (Shenton 1996): friction can pass at most mu m g to the base; rocking needs
    m g tan(alpha). With mu < tan(alpha) the block slides and never tips; with mu > tan(alpha)
    it rocks."""
    blk = zm_block()
    pulse = pulse_from_ratios(blk, "sine", 3.0, 3.0, "nonlinear")
    tan_alpha = math.tan(blk.alpha)
    slides = rock_multibody(
        blk, Motion(pulse, duration=2.0), contact=MultibodyContact(friction=0.8 * tan_alpha)
    )
    rocks = rock_multibody(
        blk, Motion(pulse, duration=2.0), contact=MultibodyContact(friction=1.2 * tan_alpha)
    )
    assert slides.max_abs_theta < 1e-4 * blk.alpha and slides.impacts == 0
    assert np.max(np.abs(slides.centroid[:, 0, 0])) > 0.05  # metres of sliding
    assert slides.summary()["energy_dissipated"] > 0.0
    assert rocks.max_abs_theta > 0.5 * blk.alpha
    assert_energy_closes(slides)
    assert_energy_closes(rocks)


# --- two halves ---------------------------------------------------------------------------------


@pytest.mark.chaotic
def test_halves_with_frictionless_crack_rock_as_independent_half_blocks():
    """No collars, no crack friction: each half is the SDOF half block up to the first impact.
    They touch at second order only (equal rotations about different toes overlap the faces by
    2b (1 - cos theta)): the half that leans on the other is held back slightly."""
    half = marble_half()
    pulse = pulse_from_ratios(half, "sine", 5.0, 2.0, "nonlinear")
    ref = rock(
        half, Motion(pulse, duration=6.0), model="nonlinear", settings=SdofSettings(dt_out=1e-3)
    )
    mb = rock_multibody(
        half,
        Motion(pulse, duration=6.0),
        contact=MultibodyContact(cracked=True, friction=STICK, crack_friction=0.0),
        settings=MultibodySettings(dt_out=1e-3),
    )
    t1 = ref.impact_times[0]
    leading = theta_error(mb, ref, t1, body=0)
    leaning = theta_error(mb, ref, t1, body=1)
    assert leading < 1e-3
    assert leaning < 1e-2
    assert mb.mode == ref.mode
    assert_energy_closes(mb)


@pytest.mark.chaotic
def test_stiff_collars_and_crack_friction_lock_the_halves_into_the_whole_column_block():
    half = marble_half()
    whole = Block(b=2.0 * half.b, h=half.h, mass=2.0 * half.mass)
    pulse = pulse_from_ratios(half, "sine", 3.0, 3.0, "nonlinear")
    ref = rock(
        whole, Motion(pulse, duration=5.0), model="nonlinear", settings=SdofSettings(dt_out=1e-3)
    )
    t1 = ref.impact_times[0]
    errors = []
    for stiffening in (1.0, 10.0, 100.0):
        collars = tuple(Collar(y=y, t=0.008, h=0.06, E=206e9 * stiffening) for y in (0.5, 2.0, 3.5))
        mb = rock_multibody(
            half,
            Motion(pulse, duration=t1 + 0.05),
            collars,
            contact=MultibodyContact(cracked=True, friction=STICK, crack_friction=0.7),
            settings=MultibodySettings(dt_out=1e-3),
        )
        errors.append(max(theta_error(mb, ref, t1, body=b, alpha=whole.alpha) for b in (0, 1)))
        assert_energy_closes(mb)
    assert errors[0] > errors[1] > errors[2]
    assert errors[2] < 1e-2


def test_collar_element_forces_are_the_gradient_of_its_energy():
    half = marble_half()
    collars = (
        Collar(y=1.0, t=0.008, h=0.06, pretension=5e3),
        Collar(y=3.0, t=0.01, h=0.05, length=0.5),
    )
    col = build_column(half, cracked=True, collars=collars)
    rng = np.random.default_rng(1)
    q = col.q_rest + rng.normal(scale=[1e-3, 1e-3, 1e-3] * 2)
    f = np.zeros(6)
    out = np.zeros((2, OUT_SIZE))
    K.collar_forces(
        q,
        col.col_a,
        col.col_b,
        col.col_r,
        col.col_props,
        f,
        out,
        np.zeros((col.col_a.size, STATE_SIZE)),
        False,
    )
    step = 1e-7
    for k in range(6):
        qp, qm = q.copy(), q.copy()
        qp[k] += step
        qm[k] -= step
        up = K.collar_forces(
            qp,
            col.col_a,
            col.col_b,
            col.col_r,
            col.col_props,
            np.zeros(0),
            out,
            np.zeros((col.col_a.size, STATE_SIZE)),
            False,
        )
        um = K.collar_forces(
            qm,
            col.col_a,
            col.col_b,
            col.col_r,
            col.col_props,
            np.zeros(0),
            out,
            np.zeros((col.col_a.size, STATE_SIZE)),
            False,
        )
        assert f[k] == pytest.approx(-(up - um) / (2 * step), rel=1e-5, abs=1e-3)


def test_collar_element_axial_and_lateral_stiffness():
    """Right half moved out by d: N = E A / L d; moved up by d (no rotation): the end moment is
    6 E I d / L^2 and the shear 12 E I d / L^3, as the FEM's frame element."""
    half = marble_half()
    collar = Collar(y=2.0, t=0.008, h=0.06)
    col = build_column(half, cracked=True, collars=(collar,))
    L = 4.0 * half.b
    d = 1e-5
    out = np.zeros((1, OUT_SIZE))
    for dof, check in ((3, "axial"), (4, "lateral")):
        q = col.q_rest.copy()
        q[dof] += d
        f = np.zeros(6)
        K.collar_forces(
            q,
            col.col_a,
            col.col_b,
            col.col_r,
            col.col_props,
            f,
            out,
            np.zeros((col.col_a.size, STATE_SIZE)),
            False,
        )
        if check == "axial":
            assert out[0, 0] == pytest.approx(collar.E * collar.area / L * d, rel=1e-4)
        else:
            EI = collar.E * collar.second_moment
            assert -out[0, 1] == pytest.approx(6 * EI * d / L**2, rel=1e-4)
            assert f[1] == pytest.approx(12 * EI * d / L**3, rel=1e-4)  # pulls left half up


# --- spectra and input checks -------------------------------------------------------------------


@pytest.mark.chaotic
def test_spectrum_points_equal_single_histories_and_the_sdof_away_from_boundaries():
    blk = zm_block()
    omegas = np.array([2.0, 5.0, 9.0])
    amplitudes = np.array([1.5, 4.0, 12.0])
    spec = multibody_spectrum(blk, omegas, amplitudes, contact=MultibodyContact(friction=STICK))
    for i, a in enumerate(amplitudes):
        for j, om in enumerate(omegas):
            pulse = pulse_from_ratios(blk, "sine", om, a, "nonlinear")
            single = rock_multibody(blk, Motion(pulse), contact=MultibodyContact(friction=STICK))
            ref = rock(blk, Motion(pulse), model="nonlinear")
            assert spec.modes[i][j] == single.mode == ref.mode, (a, om)


@pytest.mark.chaotic
def test_solid_block_spectrum_equals_the_nonlinear_sdof_spectrum():
    """The no-slip solid block is the nonlinear SDOF model: the two mode maps agree over a grid
    that holds all three outcomes (a point may differ only on a boundary)."""
    from colonna.rigid.spectrum import overturning_spectrum

    blk = zm_block()
    omegas = np.linspace(1.0, 12.0, 12)
    amplitudes = np.linspace(1.2, 16.0, 10)
    mb = multibody_spectrum(blk, omegas, amplitudes, contact=MultibodyContact(friction=STICK))
    sdof = overturning_spectrum(blk, omegas, amplitudes, model="nonlinear")
    assert set(np.unique(sdof.codes)) == {0, 1, 2}
    assert np.mean(mb.codes == sdof.codes) >= 0.98


@pytest.mark.chaotic
def test_collar_yield_map_of_the_spectrum_is_that_of_the_histories():
    half = marble_half()
    collars = (Collar(y=2.0, t=0.008, h=0.06),)
    omegas, amplitudes = np.array([3.0]), np.array([1.2, 3.0])
    spec = multibody_spectrum(
        half, omegas, amplitudes, collars, contact=MultibodyContact(cracked=True)
    )
    assert spec.collar_yields is not None
    assert spec.collar_yields.tolist() == [[False], [True]]
    for i, a in enumerate(amplitudes):
        pulse = pulse_from_ratios(half, "sine", 3.0, a, "nonlinear")
        one = rock_multibody(
            half,
            Motion(pulse),
            collars,
            contact=MultibodyContact(cracked=True),
            settings=MultibodySettings(dt_out=1e-4),
        )
        assert spec.modes[i][0] == one.mode
        util = one.summary()["collar_max_utilisation"]
        if abs(util - 1.0) > 0.05:
            assert bool(spec.collar_yields[i, 0]) == (util >= 1.0), (a, util)


@pytest.mark.parametrize(
    "kwargs, word",
    [
        ({"contact": MultibodyContact(friction=-0.1)}, "friction"),
        (
            {"contact": MultibodyContact(cracked=True, crack_friction=float("nan"))},
            "crack friction",
        ),
        ({"contact": MultibodyContact(restitution_normal=1.5)}, "restitution_normal"),
        ({"settings": MultibodySettings(dt=0.0)}, "dt"),
        ({"settings": MultibodySettings(refine=0)}, "refine"),
        ({"release": Release(tilt=2.0)}, r"release\.tilt"),
        ({"collars": (Collar(y=1.0, t=0.01, h=0.05),)}, "cracked"),
        ({"contact": {"friction": 0.5}}, "contact = .* is not a colonna.MultibodyContact"),
    ],
)
def test_bad_input_is_named(kwargs, word):
    blk = Block(b=0.2, h=2.0, mass=800.0)
    with pytest.raises(InputError, match=word):
        rock_multibody(blk, Motion(NoMotion(), duration=0.1), **kwargs)


def test_a_setting_a_run_does_not_use_is_refused_by_name():
    """The outcome keeps no history and a spectrum steps each pulse on its own (issue 49): a
    field of MultibodySettings they would ignore is an error naming it, never silently
    dropped."""
    blk = Block(b=0.2, h=2.0, mass=800.0)
    pulse = pulse_from_ratios(blk, "sine", 3.0, 2.0, "nonlinear")
    with pytest.raises(InputError, match="settings.dt_out does not apply to multibody_outcome"):
        multibody_outcome(blk, Motion(pulse), settings=MultibodySettings(dt_out=1e-3))
    with pytest.raises(InputError, match="settings.touching_dt does not apply"):
        multibody_spectrum(blk, [2.0], [2.0], settings=MultibodySettings(touching_dt=1e-4))


def test_a_step_above_the_collars_stable_step_is_refused():
    half = marble_half()
    collars = (Collar(y=2.0, t=0.008, h=0.06),)
    with pytest.raises(InputError, match="stable step"):
        rock_multibody(
            half,
            Motion(NoMotion(), duration=0.1),
            collars,
            contact=MultibodyContact(cracked=True),
            settings=MultibodySettings(dt=1e-2),
        )


def test_a_collar_law_without_an_answer_stops_the_run_and_says_so(monkeypatch):
    """A collar whose law returns NaN (a fibre section whose iteration did not converge) makes
    the state non-finite at that step: the run stops there, and the error names the collar's
    law rather than the step (whose own instability reads differently)."""
    import colonna.rigid.multibody as multibody

    block = Block(b=0.1125, h=2.0, mass=858.8)
    collars = (Collar(y=2.0, t=0.008, h=0.06),)
    column_type = type(multibody.build_column(block, cracked=True, collars=collars))
    bundles = column_type.kernel_bundles

    def broken(self):
        bodies, contacts, collar_elements = bundles(self)
        collar_elements.props[:] = np.nan  # every property of the law: no answer
        return bodies, contacts, collar_elements

    monkeypatch.setattr(column_type, "kernel_bundles", broken)
    record = Record(np.array([0.0, 0.5]), np.array([0.0, 0.0]), "still")
    for run in (multibody.rock_multibody, multibody.multibody_outcome):
        with pytest.raises(InputError, match="a collar's law gave no answer") as raised:
            run(
                block, Motion(record, duration=0.1), collars, contact=MultibodyContact(cracked=True)
            )
        assert "t = 0.000" in str(raised.value)  # its first step
    state = multibody._unstable(K.UNSTABLE_STATE, 1.25, 1e-4)
    assert "went unstable at t = 1.25 s" in str(state) and "lower dt" in str(state)

"""The fragility study's speed-ups give the answers of the full runs (issue 37).

Pinned: the multibody model's outcome path (no histories) without its speed-ups is the full
run's steps; with them (the steps of a column at rest skipped, the contact problem's exact
solve by Gaussian elimination) it gives the full run's outcome, and its peak |theta| / alpha and
collar utilisation within the scatter of the contact solver's own tolerance, on records that
hold the column at rest, rock it and let it settle; a column at rest under a motion below the
uplift acceleration stays at rest; a run stopped in its free tail once no answer can change
answers what the whole run does, a column that overturns after its record is not stopped, and
the two lower bounds the stop rests on (a half's potential at a rotation, a collar's elastic
energy at a utilisation) are their closed forms; without the impact count (the fragility's
runs) the stop's threshold is half the least potential at the peak, and a block that still
rocks is stopped with the whole run's answers; the shifted lognormal's origin is the suite's
uplift intensity, its curve is 0 up to it and the report names it; the fragility's multibody
runs step at their stated fraction of the collars' stability limit, where the collared
column's energy error still falls as the step squared, and with a single run's crack tolerance
their answers stay a single run's.
"""

import json
import math

import chaos
import numpy as np
import pytest

from colonna.core.ground import Record
from colonna.core.motion import Motion
from colonna.rigid.block import Block
from colonna.rigid.collars import Collar
from colonna.rigid.multibody import (
    MultibodyContact,
    MultibodySettings,
    multibody_outcome,
    rock_multibody,
)
from colonna.studies.cli import main
from colonna.studies.fragility.runner import uplift_intensity

# the half of the default column (4 m x 0.45 m, cracked; 2700 kg/m^3, thickness pi b)
HALF = Block(b=0.1125, h=2.0, mass=2700.0 * 0.225 * 4.0 * math.pi * 0.1125)
COLLARS = tuple(Collar(y=y, t=0.008, h=0.06) for y in (0.5, 2.0, 3.5))


def _record(parts, dt: float = 0.005, block: Block = HALF) -> Record:
    """A record of sine segments: (duration s, amplitude over the block's g tan alpha, period
    s) one after the other, each a whole number of periods (no jump between them)."""
    t, a, start = [0.0], [0.0], 0.0
    for duration, ratio, period in parts:
        local = np.arange(dt, duration + 0.5 * dt, dt)
        t.extend(start + local)
        a.extend(ratio * block.uplift_acceleration() * np.sin(2.0 * math.pi * local / period))
        start += duration
    return Record(np.array(t), np.array(a), "segments")


def test_a_column_at_rest_under_a_motion_below_uplift_stays_at_rest():
    """Below g tan(alpha) of the half no part lifts (the whole column needs twice that): the
    full run and the fast one both leave the column at rest (|theta| at the contact
    solver's round-off, far below the uplift threshold 1e-4 alpha), collars unstrained."""
    record = _record([(2.0, 0.8, 0.4)])
    full = rock_multibody(
        HALF, Motion(record, duration=2.5), COLLARS, contact=MultibodyContact(cracked=True)
    ).summary()
    fast = multibody_outcome(
        HALF, Motion(record, duration=2.5), COLLARS, contact=MultibodyContact(cracked=True)
    )
    assert not full["overturned"] and not fast.overturned
    assert full["max_abs_theta"] < 1e-8 * HALF.alpha
    assert fast.max_abs_theta < 1e-8 * HALF.alpha
    assert fast.impacts == full["impacts"] == 0
    assert fast.collar_max_utilisation < 1e-6


ROCKS = [(1.0, 0.8, 0.25), (0.8, 3.0, 0.8), (1.5, 0.5, 0.25)]  # rest, one strong cycle, rest
SETTLES = [(0.5, 0.6, 0.25), (0.6, 2.2, 0.6), (2.0, 0.3, 0.2)]  # rocks, then settles


def test_the_outcome_path_is_rock_multibody_s_run_without_its_history():
    """Without its speed-ups, the outcome path runs rock_multibody's steps: the same impacts and
    overturning, the peak |theta| (its every step against the history's rows every 1/200 p:
    at least as large, the same to 1e-5) and the collars' utilisation (at the steps'
    midpoints against the rows: to 1e-3)."""
    record = _record(ROCKS)
    full = rock_multibody(
        HALF, Motion(record, duration=4.0), COLLARS, contact=MultibodyContact(cracked=True)
    ).summary()
    path = multibody_outcome(
        HALF,
        Motion(record, duration=4.0),
        COLLARS,
        fast=False,
        contact=MultibodyContact(cracked=True),
    )
    assert full["max_abs_theta"] > 0.5 * HALF.alpha  # it rocked
    assert path.overturned == full["overturned"]
    assert path.impacts == full["impacts"]
    assert path.max_abs_theta == pytest.approx(full["max_abs_theta"], rel=1e-5)
    assert path.max_abs_theta >= full["max_abs_theta"]
    assert path.collar_max_utilisation == pytest.approx(full["collar_max_utilisation"], rel=1e-3)


def _outcome_ensemble(record, **options) -> list:
    """:func:`multibody_outcome` of the cracked half with its collars over
    :data:`chaos.ENSEMBLE_SIZE` runs of 4 s, each with its ground moved in the last bits and
    the contact solver's tolerance drawn within a decade of the model's 1e-10
    (:func:`chaos.multibody_member`). ``options``: those of multibody_outcome."""
    runs = []
    for seed in chaos.ensemble_seeds():
        with chaos.multibody_member(seed):
            runs.append(
                multibody_outcome(
                    HALF,
                    Motion(chaos.perturbed(record, seed), duration=4.0),
                    COLLARS,
                    contact=MultibodyContact(cracked=True),
                    **options,
                )
            )
    return runs


@pytest.mark.chaotic
@pytest.mark.parametrize("parts", [ROCKS, SETTLES], ids=["rocks", "settles"])
def test_the_fast_path_stays_within_the_contact_solver_s_own_scatter(parts):
    """The column's start of rocking amplifies the contact solver's round-off (its velocities
    at rest, 1e-11 m/s): over runs whose ground differs in its last bits and whose solver
    tolerance lies within a decade of the model's, the peak |theta| scatters by about 0.03 %
    and the collars' utilisation by 0.1-0.4 % (measured). The fast path (the model's
    tolerance, an exact solve) is one more draw: its peak and utilisation lie inside the
    ensemble's prediction band (tests/chaos.py: false-failure rate 1e-3), and its
    overturning is every run's. A fast path 5 % off is outside both bands. Impact counts are
    not compared: they follow landings."""
    record = _record(parts)
    runs = _outcome_ensemble(record, fast=False)  # the fast path is one more draw of these
    fast = multibody_outcome(
        HALF,
        Motion(chaos.perturbed(record, 0), duration=4.0),
        COLLARS,
        contact=MultibodyContact(cracked=True),
    )
    for key in ("max_abs_theta", "collar_max_utilisation"):
        values = [getattr(r, key) for r in runs]
        chaos.assert_in_band(getattr(fast, key), values, key)
        low, high = chaos.band(values)
        assert not low <= 1.05 * getattr(fast, key) <= high, key  # a wrong fast path is seen
    assert {r.overturned for r in runs} == {fast.overturned}


def test_the_outcome_path_refuses_plastic_collars():
    from colonna.core.errors import InputError

    plastic = (Collar(y=2.0, t=0.008, h=0.06, plastic=True),)
    with pytest.raises(InputError, match="plastic"):
        multibody_outcome(
            HALF,
            Motion(_record([(0.5, 0.5, 0.25)])),
            plastic,
            contact=MultibodyContact(cracked=True),
        )


# --- the shifted lognormal ------------------------------------------------------------------


def test_the_uplift_intensity_is_where_the_first_record_lifts_the_block():
    """Record i lifts the block once its scaled PGA reaches g tan alpha: at IM_i g tan alpha /
    PGA_i; the suite's origin is the least of these, 1 for PGA / (g tan alpha)."""
    uplift = HALF.uplift_acceleration()
    im = np.array([0.3, 0.5, 0.2])  # m/s
    pga = np.array([2.0, 1.0, 4.0])  # m/s^2
    assert uplift_intensity("pgv", im, pga, uplift) == pytest.approx(0.05 * uplift)
    assert uplift_intensity("pga_rocking", pga / uplift, pga, uplift) == 1.0


SHIFTED = """
[study]
name = "shifted"
kind = "fragility"
[column]
height = 4.0
width = 0.6
cracked = false
[ground]
pulse = "none"
[fragility]
suite = "suite.toml"
intensity = "pgv_rocking"
ladder = [0.05, 1.5]
steps = 16
models = ["sdof"]
design_intensity = 0.06
bootstrap = 10
fit = "shifted"
"""


def test_a_shifted_fragility_starts_at_the_uplift_intensity(tmp_path):
    """The SDOF lifts record i exactly above its own uplift level u_i = IM_i g tan alpha /
    PGA_i: the uplift counts at each level are #{u_i < level}; the fits' origin is min u_i,
    every curve is 0 up to it (the design intensity lies below it) and the report says which
    curve it fitted."""
    block = Block(b=0.3, h=2.0)
    for i, ratio in enumerate((1.5, 2.5, 4.0, 6.0)):
        omega = ratio * block.p
        t = np.linspace(0.0, 2.0 * math.pi / omega, 401)
        np.savetxt(tmp_path / f"p{i}.txt", np.column_stack([t, (1 + i) * np.sin(omega * t)]))
    (tmp_path / "suite.toml").write_text(
        "\n".join(f'[[record]]\nfile = "p{i}.txt"\nunits = "m/s2"\n' for i in range(4))
    )
    (tmp_path / "study.toml").write_text(SHIFTED)
    out = tmp_path / "out"
    assert main(["study", str(tmp_path / "study.toml"), "--out", str(out), "--workers", "1"]) == 0
    s = json.loads((out / "summary.json").read_text())
    levels = np.array(s["levels"])
    u = np.array(
        [r["intensity"] * s["block"]["uplift_acceleration"] / r["ims"]["pga"] for r in s["records"]]
    )
    assert s["fit"] == "shifted"
    assert s["origin"] == pytest.approx(u.min(), rel=1e-12)
    uplift = s["limit_states"]["sdof"]["uplift"]
    assert uplift["counts"] == [int(np.sum(u < x)) for x in levels]
    for state in s["limit_states"]["sdof"].values():
        for which in ("stripes", "ida"):
            entry = state.get(which)
            if entry and entry.get("fit"):
                assert entry["fit"]["origin"] == s["origin"]
                assert entry["probability"] == 0.0  # the design intensity is below the origin
    assert s["design_intensity"] < s["origin"]
    page = (out / "index.html").read_text()
    assert "shifted lognormal" in page


# --- the free tail stops once no answer can change ----------------------------------------------

SETTLES_EARLY = [(0.5, 0.6, 0.25), (0.2, 2.0, 0.2), (1.0, 0.3, 0.2)]  # a small rocking, then rest


@pytest.mark.chaotic
def test_a_run_stopped_once_decided_answers_what_the_whole_run_does():
    """The record lifts the column (peak 0.02 alpha, about a hundred impacts) and leaves it
    to settle: the run stops in its free tail, seconds before its duration, and every answer
    is the whole run's (overturning and impacts equal, the peak |theta| and the collars'
    largest utilisation to 1e-12)."""
    record = _record(SETTLES_EARLY)
    stopped = multibody_outcome(
        HALF, Motion(record), COLLARS, contact=MultibodyContact(cracked=True)
    )
    whole = multibody_outcome(
        HALF,
        Motion(record),
        COLLARS,
        stop_when_decided=False,
        contact=MultibodyContact(cracked=True),
    )
    assert whole.max_abs_theta > 1e-2 * HALF.alpha and whole.impacts > 10  # it rocked
    assert whole.decided_at is None
    assert stopped.decided_at is not None
    assert record.end_time < stopped.decided_at < whole.steps * _default_dt() - 1.0
    assert stopped.steps < whole.steps
    assert stopped.overturned == whole.overturned is False
    assert stopped.impacts == whole.impacts
    assert stopped.max_abs_theta == pytest.approx(whole.max_abs_theta, rel=1e-12)
    assert stopped.collar_max_utilisation == pytest.approx(whole.collar_max_utilisation, rel=1e-12)


@pytest.mark.chaotic
@pytest.mark.parametrize("impacts_needed", [True, False])
def test_a_column_that_overturns_after_the_record_is_not_stopped(impacts_needed):
    """A pulse of 2.7 g tan alpha over 1 s leaves the column tipping: it lands once and
    overturns about 0.9 s after the record. Its energy stays above the overturning barrier,
    so the run is not stopped, with the impact count or without it (the fragility's): the
    same steps and answers as without the stop."""
    record = _record([(1.0, 2.7, 1.0)])
    stopped = multibody_outcome(
        HALF,
        Motion(record),
        COLLARS,
        impacts_needed=impacts_needed,
        contact=MultibodyContact(cracked=True),
    )
    whole = multibody_outcome(
        HALF,
        Motion(record),
        COLLARS,
        stop_when_decided=False,
        impacts_needed=impacts_needed,
        contact=MultibodyContact(cracked=True),
    )
    dt = _default_dt()
    assert whole.overturned and stopped.overturned
    assert stopped.decided_at is None
    assert stopped.steps == whole.steps
    assert stopped.steps * dt > record.end_time + 0.5  # it fell in the free tail
    assert stopped.impacts == whole.impacts


def _default_dt() -> float:
    from colonna.rigid.multibody import build_column, default_step

    return default_step(build_column(HALF, cracked=True, collars=COLLARS))


def test_the_least_potential_is_that_of_a_body_pivoting_on_its_toe():
    """V(x) = m g (R cos(alpha - x) - h) + P (R cos(alpha - x) + h cos x - 2 h): a block with a
    top load tilted by x about its toe has exactly this potential above rest; in a cracked
    column tilted rigidly about its outer toe the half on that toe has it and the other half
    more (it is raised by the first)."""
    import colonna.rigid._multibody as K
    from colonna.rigid.multibody import build_column, tilted_state

    loaded = Block(b=0.3, h=1.5, mass=800.0, top_load=2.0e4)
    for cracked in (False, True):
        column = build_column(loaded, cracked=cracked)
        for x in (1e-4, 0.05, 0.15):
            q, _ = tilted_state(column, x)
            m, half, g = column.mass, column.half, column.block.g
            pivot = column.n_bodies - 1  # tilted toward +x: the right body's toe
            least = K._least_potential(m, half, g, pivot, x)
            assert K._potential(q, m, half, g, pivot) == pytest.approx(least, rel=1e-9)
            if cracked:
                assert K._potential(q, m, half, g, 0) > 1.5 * K._least_potential(m, half, g, 0, x)


def test_the_collars_least_energy_at_a_utilisation():
    """An elastic collar at utilisation u = (|N| / A + max|M_i| / W) / f_y holds at least
    s^2 / (2 (k_a / A^2 + 4 k_b / W^2)) - P^2 / (2 k_a), s = u f_y: over random stretches and
    end rotations (the frame element's own law) never less, and exactly that at the
    Lagrange point (N / k_a : M / (8 k_b) as 1 / A : 1 / (4 W), M2 = M1 / 2)."""
    import colonna.rigid._multibody as K
    from colonna.core.collar_law import resultant_local_law
    from colonna.rigid.multibody import build_column

    collar = Collar(y=2.0, t=0.008, h=0.06, pretension=2.0e4)
    column = build_column(HALF, cracked=True, collars=(collar,))
    _, _, bundle = column.kernel_bundles()
    least, offset = K._collar_least_energy(bundle)
    ka, kb, pre = column.col_props[0, :3]
    area, modulus, fy = column.col_limits[0, :3]
    law = column.col_props[0, 5:]
    state = column.collar_rest_state()
    assert offset == pytest.approx(pre**2 / (2.0 * ka), rel=1e-12)

    def energy_and_utilisation(stretch, th1, th2):
        N, M1, M2, U, _, _ = resultant_local_law(
            stretch, th1, th2, ka, kb, pre, law, state, 0, False
        )
        return U, (abs(N) / area + max(abs(M1), abs(M2)) / modulus) / fy

    rng = np.random.default_rng(37)
    for stretch, th1, th2 in rng.normal(0.0, [1e-4, 1e-3, 1e-3], size=(2000, 3)):
        U, u = energy_and_utilisation(stretch, th1, th2)
        assert U + offset >= least[0] * (u * fy) ** 2 * (1.0 - 1e-12)
    s = 0.5 * fy  # the Lagrange point at u = 0.5
    lam = s / (ka / area**2 + 4.0 * kb / modulus**2)
    N, M = ka * lam / area, 4.0 * kb * lam / modulus
    # M1 = kb (4 a1 + 2 a2) = M and M2 = kb (2 a1 + 4 a2) = M / 2: a1 = M / (4 kb), a2 = 0
    U, u = energy_and_utilisation((N - pre) / ka, M / (4.0 * kb), 0.0)
    assert u == pytest.approx(0.5, rel=1e-12)
    assert U + offset == pytest.approx(least[0] * s**2, rel=1e-12)


# --- the fragility needs no impact count: the stop leaves the impact threshold out -------------

STOCKY = Block(b=0.25, h=1.0, mass=500.0)  # alpha 0.245: each impact takes a fifth of the energy


def _stop_settings(column, impacts_needed: bool):
    import colonna.rigid._multibody as K

    return K.Settings(
        h=1e-4,
        n_steps=1,
        refine=1,
        e_n=0.0,
        out_every=1,
        free_halves=False,
        barrier=float(column.overturning_barrier()),
        early_exit=False,
        impact_tol=1e-4 * column.block.alpha,
        energy_scale=1.0,
        tol=1e-10,
        max_iter=10,
        outcome_only=True,
        stop_decided=True,
        impacts_needed=impacts_needed,
    )


def test_without_the_impact_count_the_stop_is_half_the_least_potential_at_the_peak():
    """A block without collars, upright, its peak |theta| x = alpha / 2 so far: without the
    impact count the stop's threshold is half of V(x) = m g (R cos(alpha - x) - h) (below the
    barrier m g (R - h)), whether or not an impact is armed: an energy 1e-9 below it stops,
    1e-9 above it does not. With the impact count an armed block never stops, and an unarmed
    one only below half of V(1e-4 alpha), 3,800 times less here."""
    import colonna.rigid._multibody as K
    from colonna.rigid.multibody import build_column

    column = build_column(STOCKY)
    bodies, _, collars = column.kernel_bundles()
    least, offset = K._collar_least_energy(collars)
    q = column.q_rest.copy()
    alpha, b, h = STOCKY.alpha, STOCKY.b, STOCKY.h
    R = math.hypot(b, h)

    def V(x):
        return STOCKY.mass * STOCKY.g * (R * math.cos(alpha - x) - h)

    x = 0.5 * alpha
    assert V(x) < column.overturning_barrier()
    without, exact = _stop_settings(column, False), _stop_settings(column, True)

    def decided(energy, armed, settings):
        flags = np.array([armed])
        return K._decided(q, energy, x, 0.0, flags, bodies, collars, settings, least, offset)

    for armed in (False, True):
        assert decided(0.5 * V(x) * (1.0 - 1e-9), armed, without)
        assert not decided(0.5 * V(x) * (1.0 + 1e-9), armed, without)
    assert not decided(0.0, True, exact)
    low = V(1e-4 * alpha)
    assert V(x) / low > 3000.0
    assert decided(0.5 * low * (1.0 - 1e-6), False, exact)
    assert not decided(0.5 * low * (1.0 + 1e-6), False, exact)


def _stocky_record(parts, dt: float = 0.005) -> Record:
    """_record's sine segments for STOCKY (amplitudes over its g tan alpha)."""
    return _record(parts, dt, STOCKY)


@pytest.mark.chaotic
@pytest.mark.parametrize(
    "case",
    ["rocking block", "collared column"],
)
def test_a_run_that_needs_no_impact_count_stops_while_it_rocks_with_the_whole_run_s_answers(case):
    """Without the impact count (the fragility's runs) the stop waits only for the energy to
    fall below half of V(peak), the collars' least energy at their largest utilisation and the
    barrier. A stocky block rocked to 0.6 alpha by one sine cycle still rocks (17 impacts in
    all) when its tail is stopped, about 4 s into a 5.8 s run; with the impact count it runs
    to its end. The collared cracked column of the settling test stops earlier than with the
    count. Either way the fragility's answers are the whole run's: overturning, the peak
    |theta| (uplift and rotation read it) and the collars' largest utilisation to 1e-12."""
    if case == "rocking block":
        block, record, kw = STOCKY, _stocky_record([(0.6, 1.6, 0.6)]), {}
    else:
        block, record = HALF, _record(SETTLES_EARLY)
        kw = {"contact": MultibodyContact(cracked=True), "collars": COLLARS}
    whole = multibody_outcome(block, Motion(record), stop_when_decided=False, **kw)
    counted = multibody_outcome(block, Motion(record), **kw)
    stopped = multibody_outcome(block, Motion(record), impacts_needed=False, **kw)
    assert whole.max_abs_theta > 1e-2 * block.alpha and whole.impacts > 10  # it rocked
    assert stopped.impacts is None and counted.impacts == whole.impacts
    assert stopped.decided_at is not None
    assert record.end_time < stopped.decided_at
    assert stopped.steps < counted.steps
    if case == "rocking block":
        assert counted.decided_at is None and counted.steps == whole.steps
        assert stopped.steps < 0.6 * whole.steps
    assert stopped.overturned == whole.overturned is False
    assert stopped.max_abs_theta == pytest.approx(whole.max_abs_theta, rel=1e-12)
    if whole.collar_max_utilisation is None:
        assert stopped.collar_max_utilisation is None
    else:
        assert stopped.collar_max_utilisation == pytest.approx(
            whole.collar_max_utilisation, rel=1e-12
        )


# --- the fragility's multibody step -------------------------------------------------------------


@pytest.mark.chaotic
def test_the_collared_column_s_energy_error_falls_as_the_step_squared_up_to_the_fragility_s():
    """The collars' forces are explicit (the midpoint rule): with them the energy balance
    closes to O(h^2). At steps of 1/16, 1/8 (a single run's) and 1/4 (the fragility's
    default, [fragility] multibody_step) of the collars' stability limit 2/omega, the
    largest energy error of a column rocked by one strong cycle grows 4 times per doubling
    (measured 3.9 and 4.0): the fragility's step is still in the scheme's second-order range."""
    from colonna.rigid.multibody import build_column

    limit = build_column(HALF, cracked=True, collars=COLLARS).collar_stable_step()
    record = _record(ROCKS)
    errors = []
    for fraction in (0.0625, 0.125, 0.25):
        run = rock_multibody(
            HALF,
            Motion(record, duration=2.5),
            COLLARS,
            contact=MultibodyContact(cracked=True),
            settings=MultibodySettings(dt=fraction * limit, touching_dt=0.125 * limit),
        ).summary()
        assert run["max_abs_theta"] > 0.5 * HALF.alpha  # it rocked
        errors.append(run["energy_error_max"])
    ratios = np.array(errors[1:]) / np.array(errors[:-1])
    assert np.all(np.abs(ratios - 4.0) < 0.6), ratios


@pytest.mark.chaotic
@pytest.mark.parametrize("parts", [ROCKS, SETTLES], ids=["rocks", "settles"])
def test_at_twice_the_step_with_a_single_run_s_crack_tolerance_the_answers_stay(parts):
    """A crack contact within g h^2 of touching and closing is active (the midpoint scheme's
    drift). That tolerance grows with the step, and it was most of what a longer step changed:
    at twice a single run's step h with its own tolerance the peak |theta| falls 1.6 % (one
    strong cycle) and 4 % (a column that settles). With the single run's tolerance g h^2 kept
    (the fragility's runs) the peak and the collars' utilisation at 2 h stay within 0.5 % and
    1 % of h's, as h / 2's do (measured 0.9 % at 2 h). Each is the mean of an ensemble of
    runs whose ground differs in its last bits and whose contact solver's tolerance within a
    decade (the utilisation scatters by 0.1-0.3 %, 1 % from least to most: one sample each
    is not a comparison), compared up to its sampling error (tests/chaos.py)."""
    from colonna.rigid.multibody import build_column, default_step

    record = _record(parts)
    h = default_step(build_column(HALF, cracked=True, collars=COLLARS))

    def ensemble(factor, touching_dt):
        runs = _outcome_ensemble(
            record, settings=MultibodySettings(dt=factor * h, touching_dt=touching_dt)
        )
        assert {r.overturned for r in runs} == {False}
        return {
            key: [getattr(r, key) for r in runs]
            for key in ("max_abs_theta", "collar_max_utilisation")
        }

    single = ensemble(1.0, None)
    assert min(single["max_abs_theta"]) > 0.1 * HALF.alpha  # it rocked
    for factor in (0.5, 2.0):
        kept = ensemble(factor, h)
        for key, rel in (("max_abs_theta", 5e-3), ("collar_max_utilisation", 1e-2)):
            chaos.assert_same_centre(kept[key], single[key], rel, f"{key} at {factor} h")
    own = ensemble(2.0, None)
    assert chaos.clearly_apart(own["max_abs_theta"], single["max_abs_theta"], 1e-2)


STEPPED = """
[study]
name = "stepped"
kind = "fragility"
[column]
height = 4.0
width = 0.45
cracked = true
[[collar]]
y = 0.5
t = 0.008
h = 0.06
[[collar]]
y = 2.0
t = 0.008
h = 0.06
[[collar]]
y = 3.5
t = 0.008
h = 0.06
[ground]
pulse = "none"
[fragility]
suite = "suite.toml"
intensity = "pga_rocking"
ladder = [0.5, 2.0]
steps = 2
models = ["multibody"]
design_intensity = 1.0
bootstrap = 10
"""


def test_the_fragility_s_multibody_step_is_its_fraction_of_the_collars_limit(tmp_path):
    """A fragility study's multibody runs step at multibody_step of the collars' stability
    limit 2/omega where the collars set the step (a quarter by default: twice a single run's
    eighth), the crack's tolerance a single run's, and at 1/(1000 p) where that is smaller
    (half of the limit here is 0.76 ms against 0.52 ms); the summary, each case and the report
    say which."""
    from colonna.rigid.multibody import build_column, default_step
    from colonna.studies.fragility.models import multibody_steps
    from colonna.studies.fragility.runner import setup
    from colonna.studies.study import load

    (tmp_path / "study.toml").write_text(STEPPED)
    t = np.linspace(0.0, 1.0, 101)
    for i in (1, 2):
        np.savetxt(tmp_path / f"p{i}.txt", np.column_stack([t, np.sin(2.0 * i * math.pi * t)]))
    (tmp_path / "suite.toml").write_text(
        "\n".join(f'[[record]]\nfile = "p{i}.txt"\nunits = "m/s2"\n' for i in (1, 2))
    )
    s = setup(load(tmp_path / "study.toml"))
    study, record = s.column, s.records[0]
    column = build_column(
        study.rocking_block,
        cracked=True,
        collars=study.collars,
        friction=study.contact.friction,
    )
    limit = column.collar_stable_step()
    assert s.spec.multibody_step == 0.25
    dt, touching_dt = multibody_steps(study, record, 0.25)
    assert dt == pytest.approx(0.25 * limit, rel=1e-12)
    assert touching_dt == default_step(column, record)  # the single run's crack tolerance
    assert 0.5 * limit > 1.0 / (1000.0 * study.rocking_block.p)
    # the step is also at most 1/(1000 p) (a column whose collars are soft enough)
    assert multibody_steps(study, record, 0.5)[0] == pytest.approx(1e-3 / study.rocking_block.p)
    assert multibody_steps(study, record, None) == (None, None)
    assert default_step(column, record) == pytest.approx(0.125 * limit, rel=1e-12)
    out = tmp_path / "out"
    assert main(["study", str(tmp_path / "study.toml"), "--out", str(out), "--workers", "1"]) == 0
    summary = json.loads((out / "summary.json").read_text())
    assert summary["multibody_step"] == 0.25
    case = json.loads((out / "cases" / "multibody-000-p1" / "inputs.json").read_text())
    assert case["inputs"]["case"]["collar_step"] == 0.25  # a case is keyed by its step
    assert "multibody runs step at\n0.25 of the collars" in (out / "index.html").read_text()

"""A crack along part of the column's height, the rest of the mid-plane a cohesive interface
(issue 51): the [column] crack key, the model's node pairs and stable step, the kernel's
cohesive forces, damage and energy, and the two limits (no crack, a full crack)."""

from __future__ import annotations

import copy
import math
import re

import numpy as np
import pytest

from colonna.core.errors import InputError
from colonna.core.ground import NoMotion, sine_pulse
from colonna.core.motion import Motion
from colonna.fem.assembly import Stone
from colonna.fem.ensemble import ensemble_summary
from colonna.fem.model import ContactSettings, build_model, stable_time_step
from colonna.fem.partial_crack import cracked_pairs
from colonna.fem.settings import FemSettings, FemStart
from colonna.fem.solver import run, run_batch, run_ensemble
from colonna.meshes.column import ToeGrading, column_mesh, from_arrays
from colonna.studies import schema

WIDTH, HEIGHT = 0.45, 4.0
STRONG = Stone(ft=40e6, Gf=1e5)  # a mid-plane that does not crack under these motions
UPLIFT = 9.81 * WIDTH / HEIGHT  # the whole column's uplift acceleration (m/s^2), tan(alpha) g


def coarse(**kw):
    return column_mesh(WIDTH, HEIGHT, 0.1125, **kw)


def welded(mesh):
    """The cracked mesh's halves welded along the mid-plane: one body on the same nodes."""
    left, right = mesh.crack_nodes
    y = mesh.points[1]
    new = np.arange(mesh.n_nodes)
    new[right] = left[np.argmin(np.abs(y[right][:, None] - y[left][None, :]), axis=1)]
    keep = np.setdiff1d(np.arange(mesh.n_nodes), right)
    index = np.full(mesh.n_nodes, -1)
    index[keep] = np.arange(keep.size)
    return from_arrays(mesh.points[:, keep], index[new[mesh.cells]])


# ------------------------------------------------------------------------------------------
# the study file's key and the model's pairs
# ------------------------------------------------------------------------------------------

BASE = {
    "column": {"height": 4.0, "width": 0.45},
    "ground": {"pulse": "sine", "amplitude_ratio": 2.0, "omega_ratio": 3.0},
}


@pytest.mark.parametrize(
    ("crack", "message"),
    [
        ([3.0, 2.0], "column.crack = [3, 2] m is outside the allowed range: 0 <= from <= to <= 4"),
        (
            [1.0, 4.5],
            "column.crack = [1, 4.5] m is outside the allowed range: 0 <= from <= to <= 4",
        ),
        ([-0.5, 1.0], "0 <= from <= to <= 4 m (the column height)"),
    ],
)
def test_crack_heights_outside_the_column_are_refused_naming_the_key(crack, message):
    data = copy.deepcopy(BASE)
    data["column"]["crack"] = crack
    with pytest.raises(InputError, match=re_escape(message)):
        schema.parse(data)


def re_escape(text):
    return re.escape(text)


def test_crack_on_an_uncracked_column_and_a_wrong_length_are_refused():
    data = copy.deepcopy(BASE)
    data["column"].update(crack=[1.0, 2.0], cracked=False)
    with pytest.raises(InputError, match="column.crack needs column.cracked = true"):
        schema.parse(data)
    data["column"].update(crack=[1.0], cracked=True)
    with pytest.raises(InputError, match="column.crack"):
        schema.parse(data)


def test_crack_and_stone_fracture_keys_reach_the_fem_study():
    from colonna.studies.fem_study import FemStudy, column_of

    data = copy.deepcopy(BASE)
    data["column"]["crack"] = [2.0, 4.0]
    data["stone"] = {"ft": 6e6, "Gf": 80.0, "KIC": 1.2e6}
    study = column_of(schema.parse(data))
    assert study.crack == (2.0, 4.0)
    assert (study.stone.ft, study.stone.Gf, study.stone.KIC) == (6e6, 80.0, 1.2e6)
    assert FemStudy.from_json(study.to_json()).crack == (2.0, 4.0)
    assert column_of(schema.parse(BASE)).crack is None  # today's full-height crack


def test_which_pairs_lie_on_the_crack():
    y = np.array([0.0, 1.0, 2.0, 3.0, 4.0])
    on = lambda crack: cracked_pairs(y, crack, 4.0).tolist()  # noqa: E731
    assert on((0.0, 4.0)) == [True] * 5  # full height: every pair, base and top too
    assert on((2.0, 4.0)) == [False, False, False, True, True]  # from the top: the tip intact
    assert on((0.0, 2.0)) == [True, True, False, False, False]  # from the base
    assert on((0.5, 3.5)) == [False, True, True, True, False]
    assert on((2.0, 2.0)) == [False] * 5 and on((0.0, 0.0)) == [False] * 5  # no crack


def test_model_pairs_damage_and_stable_step():
    mesh = coarse()
    full = build_model(mesh, STRONG, 0.35)
    assert full.cohesive is None
    whole = build_model(mesh, STRONG, 0.35, crack=(0.0, HEIGHT))
    assert not np.any(whole.cohesive.bonded)
    # no intact pair, no spring: today's step to the bit
    assert stable_time_step(whole).dt == stable_time_step(full).dt
    half = build_model(mesh, STRONG, 0.35, crack=(2.0, HEIGHT))
    c = half.cohesive
    assert np.all(c.bonded == (c.heights <= 2.0 + 1e-12))
    assert math.isclose(c.area.sum(), 0.35 * HEIGHT, rel_tol=1e-12)
    np.testing.assert_allclose(c.stiffness, STRONG.E / 0.1125)  # K = E / h, h the face element
    assert np.all(half.mesh.points[:, c.left] == half.mesh.points[:, c.right])
    # the intact pairs' springs join the bound between the bodies: the step shortens
    assert stable_time_step(half).critical_linear < 0.95 * stable_time_step(full).critical_linear
    # marble defaults on 112 mm wide face elements: E / h = 4.4e11 Pa/m is below f_t^2 / (2 G_f)
    # = 8e11 (the peak would come after full damage): K is raised to twice that, 1.6e12
    marble = build_model(mesh, Stone(), 0.35, crack=(2.0, HEIGHT)).cohesive
    np.testing.assert_allclose(marble.stiffness, 2.0 * 8e6**2 / (2.0 * 40.0))
    with pytest.raises(InputError, match="outside the allowed range"):
        build_model(mesh, STRONG, 0.35, crack=(2.0, 5.0))
    with pytest.raises(InputError, match="needs a cracked column"):
        build_model(coarse(cracked=False), STRONG, 0.35, crack=(2.0, 4.0))


# ------------------------------------------------------------------------------------------
# the kernel
# ------------------------------------------------------------------------------------------

SETTINGS = FemSettings(progress=False, output_interval=0.01)


def test_a_full_crack_given_is_todays_crack_to_the_bit():
    pulse = sine_pulse(2.0 * UPLIFT, 2.0 * math.pi * 1.5, UPLIFT)
    mesh = coarse()
    today = run(build_model(mesh, STRONG, 0.35), Motion(pulse, 0.15), SETTINGS)
    given = run(build_model(mesh, STRONG, 0.35, crack=(0.0, HEIGHT)), Motion(pulse, 0.15), SETTINGS)
    for key in ("theta_left", "theta_right", "energy_total", "energy_dissipated"):
        assert np.array_equal(today.history[key], given.history[key]), key
    assert np.all(given.history["crack_length"] == HEIGHT)
    assert np.all(given.history["energy_cohesive_dissipated"] == 0.0)
    assert np.all(np.isnan(given.history["crack_tip_KI"]))  # no tip
    s = given.summary
    assert s["crack_grew"] is False and "crack_tip_KI_max" not in s  # omitted: no tip
    assert "crack_grew" not in today.summary  # no partial crack, no crack answers


def test_bonded_halves_pulled_apart_dissipate_the_fracture_energy():
    """Two halves of a block, all of the mid-plane intact, flying apart on a frictionless
    bed: every pair breaks, the interface dissipates G_f t H (measured: to 1e-6), and the
    energy balance closes with the cohesive work in it (measured 0.6 %: 130 steps across the
    softening; the kinetic energy lost is G_f t H)."""
    stone = Stone(ft=2e6, Gf=2000.0)  # delta_f = 2 G_f / f_t = 2 mm: many steps across
    mesh = column_mesh(0.2, 0.2, 0.025)
    t = 0.1
    model = build_model(
        mesh, stone, t, contact=ContactSettings(friction=0.0, damping=0.0), crack=(0.1, 0.1)
    )
    assert np.all(model.cohesive.bonded)
    speed = 3.0  # m/s each half, outward: kinetic energy 0.5 M v^2 = 2.7 G_f t H
    v = np.zeros(model.n_dofs)
    v[0::2] = np.where(mesh.node_body == 0, -speed, speed)
    r = run(
        model,
        Motion(NoMotion(), 2e-3),
        FemSettings(progress=False, output_interval=1e-4),
        FemStart(velocity=v),
    )
    h = r.history
    G = stone.Gf * t * 0.2
    assert h["crack_length"][0] == 0.0 and h["crack_length"][-1] == pytest.approx(0.2)
    assert h["energy_cohesive_dissipated"][-1] == pytest.approx(G, rel=0.01)
    assert h["energy_cohesive"][-1] == 0.0  # broken: no spring left
    assert r.summary["energy_error_max"] < 0.01
    lost = h["energy_kinetic"][0] - h["energy_kinetic"][-1] - h["energy_strain"][-1]
    assert lost == pytest.approx(G, rel=0.01)


def test_checkpoints_carry_each_pairs_damage():
    """A checkpoint's arrays (fem.solver._BatchState.slot_arrays) hold the pairs' damage and
    cohesive energies, and restoring them puts them back bit for bit; reset starts from the
    crack as given."""
    from colonna.fem.solver import _BatchState

    model = build_model(coarse(), STRONG, 0.35, crack=(2.0, HEIGHT))
    state = _BatchState(model, 2, 1, np.zeros((0, model.base_nodes.size)))
    start = {
        "x": model.X.copy(),
        "v": np.zeros(model.n_dofs),
        "base_ft": np.zeros(model.base_nodes.size),
        "base_fc": np.zeros(model.base_nodes.size),
        "crack_ft": [np.zeros(p[0].size) for p in model.crack_passes],
        "crack_fc": [np.zeros(p[0].size) for p in model.crack_passes],
        "collar_state": model.collar_rest_state(),
    }
    state.reset(0, start)
    assert np.array_equal(state.cohesive_state.damage[0], model.cohesive.damage0)
    damage = np.random.default_rng(1).uniform(size=model.cohesive.left.size)
    state.cohesive_state.damage[0] = damage
    state.cohesive_state.energy[0] = (1.5, 2.5)
    saved = state.slot_arrays(0)
    assert np.array_equal(saved["cohesive.damage"], damage)
    state.restore_slot(1, saved)
    assert np.array_equal(state.cohesive_state.damage[1], damage)
    assert state.cohesive_state.energy[1].tolist() == [1.5, 2.5]


@pytest.mark.slow
def test_damage_is_state_restored_bit_for_bit_alone_and_in_a_batch():
    """The damage is part of each state: a run alone (one-state kernel) and the same run in a
    batch (the group kernel) crack alike to the bit."""
    stone = Stone(ft=20e3, Gf=2.0)  # a weak stone: the crack from the base grows at 0.5 s
    model = build_model(coarse(), stone, 0.35, crack=(0.0, 2.0))
    pulse = sine_pulse(2.0 * UPLIFT, 2.0 * math.pi * 1.5, UPLIFT)
    alone = run(model, Motion(pulse, 0.6), SETTINGS)
    batch = run_batch(model, [Motion(pulse, 0.6), Motion(pulse, 0.6)], SETTINGS)
    assert alone.history["crack_length"][-1] > alone.history["crack_length"][0]  # it grew
    for r in batch:
        for key in ("crack_length", "energy_cohesive_dissipated", "theta_left", "crack_tip_KI"):
            assert np.array_equal(alone.history[key], r.history[key], equal_nan=True), key
    s = alone.summary
    assert s["crack_grew"] is True and s["crack_length_initial"] == pytest.approx(2.03, abs=0.01)
    assert s["crack_growth"] == s["crack_length_final"] - s["crack_length_initial"] > 0.1
    assert s["crack_tip_KI_ratio"] == pytest.approx(s["crack_tip_KI_max"] / stone.KIC)
    assert s["crack_tip_KI_time"] <= 0.6 and s["cohesive_dissipated"] > 0.0


def test_tip_stress_intensity_of_the_split_column_is_the_double_cantilever_beams():
    """The column split from the top down to a (the mid-plane below intact), its halves pulled
    apart at the top by P: a double cantilever beam, K_I = 2 sqrt(3) P a / (t h^1.5)
    (1 + 0.64 h / a), h the half width (Tada, Paris & Irwin 2000). Static solve with the
    intact pairs' springs; K_I by displacement correlation on the four pairs behind the tip.
    Measured, a = 2 m: -47 %, -18 %, -4.5 %, -0.03 %, +1.6 % on meshes of width / 4 to
    width / 64; the default mesh (width / 16) within 5 %."""
    from scipy.sparse.linalg import spsolve

    from colonna.fem.model import base_stiffness
    from colonna.fem.partial_crack import springs, tip_stress_intensity

    t, a, P = 0.35, 2.0, 1e4
    h = WIDTH / 2
    exact = 2.0 * math.sqrt(3.0) * P * a / (t * h**1.5) * (1.0 + 0.64 * h / a)
    errors = []
    for size in (WIDTH / 8, WIDTH / 16):
        m = build_model(
            column_mesh(WIDTH, HEIGHT, size, grading=0.0), STRONG, t, crack=(HEIGHT - a, HEIGHT)
        )
        c = m.cohesive
        f = np.zeros(m.n_dofs)
        f[2 * c.left[-1]], f[2 * c.right[-1]] = -P, P  # the crack's mouth opened
        K = (m.stiffness + springs(c, m.n_dofs) + base_stiffness(m)).tocsc()
        u = spsolve(K, f)
        KI = tip_stress_intensity(c, c.damage0 >= 1.0, m.X + u, np.zeros(2), m.stone.E)
        errors.append(KI / exact - 1.0)
    assert abs(errors[1]) < 0.05 and abs(errors[1]) < 0.5 * abs(errors[0])


@pytest.mark.slow
def test_a_crack_of_no_extent_is_the_solid_column():
    """On the same nodes, the column bonded along its whole mid-plane (strong stone) against
    the welded (solid) column: the same overturning answer and peak rotations within 0.5 %
    (the interface's penalty adds a layer of stone h thick; measured 0.17 %), every replica."""
    mesh = coarse()
    pulse = sine_pulse(2.0 * UPLIFT, 2.0 * math.pi * 1.5, UPLIFT)
    out = {}
    for name, model in (
        ("solid", build_model(welded(mesh), STRONG, 0.35)),
        ("bonded", build_model(mesh, STRONG, 0.35, crack=(2.0, 2.0))),
    ):
        runs = run_ensemble(model, Motion(pulse, 3.0), SETTINGS, replicas=3)
        out[name] = ensemble_summary([r.summary for r in runs])
    assert out["solid"]["overturned_answer"] == out["bonded"]["overturned_answer"] == "no"
    for side in ("left", "right"):
        key = f"max_abs_theta_{side}"
        solid, bonded = out["solid"]["bands"][key], out["bonded"]["bands"][key]
        assert bonded["min"] >= solid["min"] * 0.995 and bonded["max"] <= solid["max"] * 1.005


def _cycles(amplitude_ratio: float, frequency: float, cycles: int, width: float, height: float):
    """A record of whole sine cycles, amplitude_ratio times the whole column's uplift g b / h:
    a motion that rocks a column and lands it several times while it lasts."""
    from colonna.core.ground import Record

    t = np.linspace(0.0, cycles / frequency, 400 * cycles + 1)
    a = amplitude_ratio * 9.81 * width / height * np.sin(2.0 * math.pi * frequency * t)
    return Record(t, a, "cycles")


def _bands(model, motion, settings, perturbation=1e-12):
    from colonna.fem.settings import Replicas

    runs = run_ensemble(model, motion, settings, replicas=Replicas(8, perturbation=perturbation))
    return ensemble_summary([r.summary for r in runs])


def _within_each_others_band(a: dict, b: dict, key: str) -> None:
    """Each ensemble's median inside the other's replica band (min to max over 8 replicas)."""
    A, B = a["bands"][key], b["bands"][key]
    assert B["min"] <= A["median"] <= B["max"], (key, A, B)
    assert A["min"] <= B["median"] <= A["max"], (key, A, B)


@pytest.mark.slow
def test_the_two_limits_lie_within_their_replicas_bands_after_landings():
    """The acceptance's limits, after landings, each within its replicas' band: a 0.2 m x 1 m
    column on a 50 mm mesh rocked and landed by whole sine cycles; 8 replicas perturbed at
    round-off (1e-12 of the height), whose peak rotations spread by the landings (measured
    35-50 % for the first pair, 3-8 % for the second); each median inside the other's band.
    - No extent (the mid-plane bonded, strong stone) against the welded (solid) column, 2.5 x
      uplift at 3 Hz, 4 cycles, both on the bonded column's stable step (the welded column's
      own is 14 % longer, and after landings the peak moves with the step as much as between
      the two: measured on the 4 m column, 0.0459 / 0.0404 / 0.0390 rad at 11.4 / 10.1 / 5.7
      us, its band 3 % wide).
    - A full crack given against today's cracked column (no crack key), 1.0 x uplift at 4 Hz,
      6 cycles (the halves rock apart and land, none overturns); the full crack's replicas
      perturbed by 3e-12 instead, so that the two are independent samples (with the same
      perturbation they are the same runs to the bit: test_a_full_crack_given_is_todays_...)."""
    from dataclasses import replace

    width, height = 0.2, 1.0
    mesh = column_mesh(width, height, 0.05)
    bonded = build_model(mesh, STRONG, 0.1, crack=(0.5, 0.5))
    settings = replace(SETTINGS, dt=stable_time_step(bonded).dt)
    rocked = Motion(_cycles(2.5, 3.0, 4, width, height), 2.0)
    solid = _bands(build_model(welded(mesh), STRONG, 0.1), rocked, settings)
    none = _bands(bonded, rocked, settings)
    assert solid["overturned_answer"] == none["overturned_answer"] == "no"
    for key in ("max_abs_theta_left", "max_abs_theta_right"):
        band = solid["bands"][key]
        assert band["max"] - band["min"] > 0.2 * band["median"]  # the landings spread them
        _within_each_others_band(solid, none, key)
    landed = Motion(_cycles(1.0, 4.0, 6, width, height), 2.0)
    today = _bands(build_model(mesh, STRONG, 0.1), landed, SETTINGS)
    full = _bands(build_model(mesh, STRONG, 0.1, crack=(0.0, height)), landed, SETTINGS, 3e-12)
    assert today["overturned_answer"] == full["overturned_answer"] == "no"
    for key in ("max_abs_theta_left", "max_abs_theta_right"):
        assert today["bands"][key]["values"] != full["bands"][key]["values"]
        assert today["bands"][key]["max"] > 1.02 * today["bands"][key]["min"]
        _within_each_others_band(today, full, key)


def test_does_the_crack_grow_is_answered_on_the_replicas():
    """Each replica's crack_grew is a yes-or-no outcome: yes when all grew, no when none,
    undecided otherwise; the crack's final length and K_I / K_IC are landing-dependent bands."""
    base = {"status": "completed", "overturned": False, "crack_length_final": 2.0}
    runs = [
        {**base, "crack_grew": grew, "crack_tip_KI_ratio": ratio, "crack_length_final": length}
        for grew, ratio, length in ((True, 1.3, 2.5), (False, 0.8, 2.0), (True, 1.1, 2.4))
    ]
    out = ensemble_summary(runs)
    assert out["crack_grew_answer"] == "undecided" and out["crack_grew_replicas"] == 2
    assert out["crack_grew"] is True  # the majority's
    assert out["bands"]["crack_tip_KI_ratio"]["min"] == 0.8
    assert out["crack_length_final"] == 2.4  # the median
    assert ensemble_summary(runs[::2])["crack_grew_answer"] == "yes"
    assert ensemble_summary(runs[1:2])["crack_grew_answer"] == "no"


def test_crack_grows_answer_from_the_ensemble():
    from colonna.studies.outcome import QUESTIONS, crack_grows, outcome

    fem = ensemble_summary(
        [
            {"status": "completed", "overturned": False, "crack_grew": grew,
             "crack_length_initial": 1.0, "crack_length_final": final,
             "crack_tip_KI_ratio": ratio}
            for grew, final, ratio in ((False, 1.0, 0.4), (False, 1.0, 0.5))
        ]
    )  # fmt: skip
    answer = crack_grows(fem)
    assert answer["question"] == QUESTIONS["crack_grows"] == "Does the crack grow?"
    assert answer["answer"] == "no" and (answer["count"], answer["points"]) == (0, 2)
    assert answer["length_final"]["max"] == 1.0 and answer["ki_ratio"]["median"] == 0.45
    assert crack_grows({"bands": {}})["answer"] == "not assessed"
    # listed where given, left out where a study has no partial crack
    base = {"answer": "no", "question": "q"}
    keys = ("rigid_assumption_ok", "collars_yield", "toe_crushes", "stays_up")
    plain = outcome([], {key: base for key in keys})
    assert "crack_grows" not in [a["key"] for a in plain["answers"]]
    given = outcome([], {**{key: base for key in keys}, "crack_grows": answer})
    assert [a["key"] for a in given["answers"]][-1] == "crack_grows"
    # a study whose FEM runs alone asks it too where its column has a partial crack
    from colonna.studies.outcome import fem_answers

    assert fem_answers(fem, "-")["crack_grows"]["answer"] == "no"
    assert "crack_grows" not in fem_answers({"bands": {}}, "-")


def test_a_crack_that_did_not_grow_before_the_column_overturned_says_until_when():
    """Where the FEM overturns, "Does the crack grow? no" holds only up to then (the crack
    may grow as the column falls): the answer carries the qualifier the collars' and the
    toe's answers carry, and where the FEM stands it carries none (found on a granite column
    cracked from the base that overturned at 1.025 s: its crack answer read a bare "no")."""
    from colonna.studies.outcome import ReplicaCount, crack_grows, model_outcome, outcome

    fem = ensemble_summary(
        [
            {"status": "overturned", "overturned": True, "crack_grew": False,
             "crack_length_initial": 1.2, "crack_length_final": 1.2, "crack_tip_KI_ratio": r}
            for r in (0.12, 0.17)
        ]
    )  # fmt: skip
    base = {"answer": "no", "question": "q"}
    answers = {k: base for k in ("rigid_assumption_ok", "collars_yield", "toe_crushes")}
    answers["crack_grows"] = crack_grows(fem)
    for overturned, qualified in ((True, "until overturning at t = 1.025 s, in all 2 replicas"),
                                  (False, None)):  # fmt: skip
        model = model_outcome(
            "FEM",
            overturned,
            None if overturned else 0.01,
            0.1,
            1.025 if overturned else None,
            replicas=ReplicaCount(2, 2 if overturned else 0),
        )
        said = {a["key"]: a for a in outcome([model], answers)["answers"]}
        assert said["crack_grows"]["answer"] == "no"
        assert said["crack_grows"].get("qualifier") == qualified
        assert said["collars_yield"].get("qualifier") == qualified


TINY_PARTIAL = """
[study]
name = "tiny-partial"
[column]
height = 1.0
width = 0.2
crack = [0.5, 1.0]
[stone]
ft = {ft}
[[collar]]
y = 0.75
t = 0.004
h = 0.02
[ground]
amplitude_ratio = 2.5
omega_ratio = 3.0
[mesh]
size = 0.05
grading = 0.0
toe_refinements = []
[run]
duration = 0.6
output_interval = 0.005
replicas = 2
"""


@pytest.mark.slow
def test_the_crosscheck_first_screen_answers_does_the_crack_grow(tmp_path):
    """A tiny column cracked from the top down to mid-height, marble strength: the first
    screen answers no, with the count of replicas, the crack's length at the start and its
    band at the end, and K_I / K_IC; the verdict carries the word."""
    from colonna.studies.driver import run_study_file
    from colonna.studies.executor import RunOptions

    study = tmp_path / "tiny.toml"
    study.write_text(TINY_PARTIAL.format(ft=8e6))
    summary = run_study_file(
        study, tmp_path / "out", run_options=RunOptions(workers=1, progress=False)
    )
    answer = next(a for a in summary["outcome"]["answers"] if a["key"] == "crack_grows")
    assert answer["answer"] == summary["verdict"]["crack_grows"] == "no"
    assert answer["count"] == 0 and answer["points"] == 2
    assert answer["length_initial"] == answer["length_final"]["max"] == pytest.approx(0.475)
    assert 0.0 < answer["ki_ratio"]["max"] < 1.0
    html = (tmp_path / "out" / "index.html").read_text()
    row = html[html.index('data-answer="crack_grows"') :].split("</tr>")[0]
    words = re.sub("<[^>]+>", "", row).replace("&nbsp;", " ")
    assert 'class="good"' in row and "grew" in words and ": 0 of 2;" in words
    assert "crack length 0.475 m at the start, 0.475 m at the end" in words
    assert "largest K_I / K_IC at a tip" in words
    # the answers in detail: its row, with the count, the lengths and K_I / K_IC banded
    at = html.index('data-verdict="crack_grows"')
    detail = html[html.rindex("<tr>", 0, at) :].split("</tr>")[0]
    said = " ".join(re.sub("<[^>]+>", " ", detail).replace("&nbsp;", " ").split())
    assert 'class="good" data-verdict="crack_grows"' in detail
    assert said.startswith("Does the crack grow? no the column is found with a partial crack")
    assert "in 0 of 2 replicas; crack length 0.475 m at the start, 0.475 m (replicas 0.475 m" in (
        said
    )
    assert "largest K_I / K_IC at a crack tip 0.0" in said


@pytest.mark.slow
def test_a_restart_carries_the_grown_crack_to_the_same_and_a_refined_mesh():
    """A run whose crack grew, restarted from its last contact frame (as the cross-check's toe
    windows restart): on the same mesh every pair's damage is the run's; on the toe-refined
    mesh (fem.toe_stress.model_on) the crack has the same length (the damage carried by
    height, fem.transfer.transfer_damage) and its model the same ends."""
    from colonna.fem.toe_stress import model_on
    from colonna.fem.transfer import transfer_contact, transfer_state

    stone = Stone(ft=20e3, Gf=2.0)  # grows at about 0.5 s (as in the batch test)
    model = build_model(coarse(), stone, 0.35, crack=(0.0, 2.0))
    pulse = sine_pulse(2.0 * UPLIFT, 2.0 * math.pi * 1.5, UPLIFT)
    first = run(model, Motion(pulse, 0.6), SETTINGS)
    t, contact = first.contact_frames[-1]
    _, u = first.displacement_frames[-1]
    _, v = first.velocity_frames[-1]
    grown = first.history["crack_length"][-1]
    assert grown > first.history["crack_length"][0]
    again = run(
        model,
        Motion(pulse, t + 0.01),
        SETTINGS,
        FemStart(state=((model.X + u.ravel()), v.ravel()), contact=contact, time=t),
    )
    assert again.history["crack_length"][0] == grown
    mesh = column_mesh(WIDTH, HEIGHT, 0.1125, toe=ToeGrading(refinement=2, zone=0.1))
    refined = model_on(model, mesh)
    assert refined.cohesive.crack == (0.0, 2.0)
    assert refined.cohesive.left.size > model.cohesive.left.size
    x, vel = transfer_state(model.mesh, mesh, u, v)
    carried = transfer_contact(model, refined, contact)
    on_refined = run(
        refined,
        Motion(pulse, t + 0.01),
        SETTINGS,
        FemStart(state=(x, vel), contact=carried, time=t),
    )
    assert on_refined.history["crack_length"][0] == pytest.approx(grown, abs=1e-9)


def test_the_granite_example_loads_with_granite_fracture_keys_its_docs_quote():
    """docs/stones/granite.toml (issue 51): a study file that loads, its [stone] fracture keys
    inside docs/physics.md's granite ranges (f_t 5-15 MPa and at most f_c / 10, K_IC 0.71-1.89
    MPa sqrt(m), G_f 7-90 N/m), G_f not below its own K_IC^2 (1 - nu^2) / E (the cohesive law's
    LEFM limit), and the values the [stone] key descriptions quote for it."""
    from pathlib import Path

    from colonna.studies.study import load

    path = Path(__file__).parents[1] / "docs" / "stones" / "granite.toml"
    study = load(path)
    stone = study.spec.stone
    assert 5e6 <= stone.ft <= min(15e6, stone.fc / 10)
    assert 0.71e6 <= stone.KIC <= 1.89e6
    assert 7.0 <= stone.Gf <= 90.0
    assert stone.Gf >= stone.KIC**2 * (1 - stone.nu**2) / stone.E
    assert study.fem.crack == (1.6, 3.2) and study.fem.stone.ft == stone.ft
    fields = schema.Stone.model_fields
    assert f"{stone.ft / 1e6:g} MPa in the granite example" in fields["ft"].description
    assert f"{stone.Gf:g} N/m in docs/stones/granite.toml" in fields["Gf"].description
    assert f"{stone.KIC / 1e6:g} MPa m^0.5 in docs/stones/granite.toml" in (
        fields["KIC"].description
    )


def test_the_cohesive_benchmark_s_columns_have_the_pairs_docs_speed_quotes():
    """benchmarks/bench_cohesive.py (docs/speed.md): the default column with its crack over the
    full height has no cohesive pair, from the top to mid-height 67, of no extent all 108; the
    pairs do not lengthen the stable step (3.74 us full, 3.05 us with pairs)."""
    import importlib.util
    from pathlib import Path

    path = Path(__file__).parents[1] / "benchmarks" / "bench_cohesive.py"
    spec = importlib.util.spec_from_file_location("bench_cohesive", path)
    assert spec is not None and spec.loader is not None
    bench = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(bench)
    study, models = bench.variants()
    pairs = {name: bench.intact_pairs(m) for name, m in models.items()}
    assert pairs == {"full height": 0, "top to mid-height": 67, "no extent": 108}
    dts = {name: stable_time_step(m, study.safety).dt for name, m in models.items()}
    assert dts["full height"] == pytest.approx(3.74e-6, rel=0.01)
    assert dts["top to mid-height"] == pytest.approx(3.05e-6, rel=0.01)
    assert dts["no extent"] == pytest.approx(3.05e-6, rel=0.01)

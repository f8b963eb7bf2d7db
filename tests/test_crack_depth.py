"""A crack through part of the column's thickness ([column] crack_depth, issue 51): along the
crack each node pair keeps a ligament, the cohesive law over (1 - d) of its area, on top of the
crack's contact; d = 1 is the through crack, d -> 0 the intact mid-plane (fem.partial_crack)."""

from __future__ import annotations

import copy
import math

import numpy as np
import pytest

from colonna.core.errors import InputError
from colonna.core.ground import NoMotion, sine_pulse
from colonna.core.motion import Motion
from colonna.fem import _kernels as K
from colonna.fem.assembly import Stone
from colonna.fem.model import ContactSettings, build_model, stable_time_step
from colonna.fem.partial_crack import Crack
from colonna.fem.settings import FemSettings, FemStart
from colonna.fem.solver import run
from colonna.meshes.column import column_mesh
from colonna.studies import schema

WIDTH, HEIGHT = 0.45, 4.0
STRONG = Stone(ft=40e6, Gf=1e5)  # a mid-plane that does not crack under these motions
UPLIFT = 9.81 * WIDTH / HEIGHT
SETTINGS = FemSettings(progress=False, output_interval=0.01)
BASE = {
    "column": {"height": 4.0, "width": 0.45},
    "ground": {"pulse": "sine", "amplitude_ratio": 2.0, "omega_ratio": 3.0},
}


def coarse():
    return column_mesh(WIDTH, HEIGHT, 0.1125)


@pytest.mark.parametrize("depth", [0.0, -0.1, 1.5])
def test_a_depth_outside_zero_to_one_is_refused_naming_the_key_and_range(depth):
    data = copy.deepcopy(BASE)
    data["column"]["crack_depth"] = depth
    with pytest.raises(InputError, match=r"column\.crack_depth = .* a number in \(0, 1\]"):
        schema.parse(data)
    with pytest.raises(InputError, match=r"column crack_depth .* allowed range \(0, 1\]"):
        build_model(coarse(), STRONG, 0.35, crack=Crack((2.0, HEIGHT), depth))


def test_a_part_depth_crack_needs_a_cracked_column_and_reaches_the_fem_study():
    from colonna.studies.fem_study import FemStudy, column_of

    data = copy.deepcopy(BASE)
    data["column"].update(crack_depth=0.5, cracked=False)
    with pytest.raises(InputError, match="column.crack_depth needs column.cracked = true"):
        schema.parse(data)
    data["column"].update(cracked=True, crack=[2.0, 4.0])
    study = column_of(schema.parse(data))
    assert study.crack_depth == 0.5
    assert FemStudy.from_json(study.to_json()).crack_depth == 0.5
    # depth 1 given is the file without the key: the same case JSON (and inputs hash)
    data["column"]["crack_depth"] = 1.0
    given = column_of(schema.parse(data)).to_json()
    del data["column"]["crack_depth"]
    assert given == column_of(schema.parse(data)).to_json() and "crack_depth" not in given


def test_the_ligament_is_the_cracks_pairs_with_the_uncracked_area_scaled():
    mesh = coarse()
    through = build_model(mesh, STRONG, 0.35, crack=(2.0, HEIGHT)).cohesive
    part = build_model(mesh, STRONG, 0.35, crack=Crack((2.0, HEIGHT), 0.3)).cohesive
    on = through.damage0 >= 1.0
    assert np.array_equal(part.ligament, on) and np.all(part.damage0 == 0.0)
    np.testing.assert_array_equal(part.area[on], 0.7 * through.area[on])
    np.testing.assert_array_equal(part.area[~on], through.area[~on])
    assert math.isclose(part.area.sum(), 0.35 * (HEIGHT - 0.3 * 2.0), rel_tol=0.03)
    # without [column] crack a part-depth crack runs the full height
    full = build_model(mesh, STRONG, 0.35, crack=Crack(None, 0.3)).cohesive
    assert full.crack == (0.0, HEIGHT) and np.all(full.ligament)
    # the ligament's springs join the stable step's bound
    assert stable_time_step(build_model(mesh, STRONG, 0.35, crack=Crack(None, 0.3))).dt < (
        stable_time_step(build_model(mesh, STRONG, 0.35)).dt
    )


def _pull(model, openings):
    """The interface's total normal force (N) and the dissipated energy (J) along a path of
    uniform openings (m) of the right face away from the left (the kernel's cohesive
    forces)."""
    c = model.cohesive
    law = K.Cohesive(c.left, c.right, c.area, c.stiffness, c.law)
    damage = c.damage0.copy()
    forces, dissipated = [], 0.0
    for opening in openings:
        x = model.X.copy()
        x[2 * c.right] += opening
        f = np.zeros(model.n_dofs)
        _, w = K.cohesive_forces(x, f, law, damage, 1.0, 0.0)
        dissipated += w
        forces.append(float(np.sum(f[2 * c.left])))
    return np.array(forces), dissipated


@pytest.mark.parametrize("depth", [0.25, 0.5, 0.9])
def test_a_ligament_pulled_apart_peaks_at_ft_and_dissipates_gf_on_its_area(depth):
    """Every pair on the crack (its full height), pulled apart in mode I: the peak force is
    f_t A (1 - d) and the work G_f A (1 - d), A = t H (within 1 %)."""
    stone = Stone(ft=2e6, Gf=200.0)
    t, side = 0.1, 0.2
    model = build_model(column_mesh(side, side, 0.025), stone, t, crack=Crack(None, depth))
    A = t * side
    openings = np.linspace(0.0, 1.05 * 2.0 * stone.Gf / stone.ft, 20001)
    forces, dissipated = _pull(model, openings)
    assert forces.max() == pytest.approx(stone.ft * A * (1.0 - depth), rel=0.01)
    assert dissipated == pytest.approx(stone.Gf * A * (1.0 - depth), rel=0.01)
    assert forces[-1] == 0.0  # broken through: only the contact is left


def test_a_depth_of_one_is_todays_crack_to_the_bit():
    pulse = sine_pulse(2.0 * UPLIFT, 2.0 * math.pi * 1.5, UPLIFT)
    mesh = coarse()
    for crack in ((2.0, HEIGHT), None):
        today = run(build_model(mesh, STRONG, 0.35, crack=crack), Motion(pulse, 0.15), SETTINGS)
        given = run(
            build_model(mesh, STRONG, 0.35, crack=Crack(crack, 1.0)),
            Motion(pulse, 0.15),
            SETTINGS,
        )
        assert today.history.keys() == given.history.keys()
        for key in today.history:
            assert np.array_equal(today.history[key], given.history[key], equal_nan=True), key
        wall = ("wall_seconds",)
        assert {k: v for k, v in today.summary.items() if k not in wall} == {
            k: v for k, v in given.summary.items() if k not in wall
        }
        assert "crack_ligament_damage" not in given.history and "crack_depth" not in given.summary


def test_a_vanishing_depth_is_the_intact_mid_plane():
    """d = 1e-6 along the top half against the mid-plane bonded over the whole height (crack of
    no extent): the same motion, strain energy and crack opening within 1e-5 (measured 1e-7),
    where the through crack differs by 10-30 %."""
    pulse = sine_pulse(2.0 * UPLIFT, 2.0 * math.pi * 1.5, UPLIFT)
    mesh = coarse()

    def history(**kw):
        return run(build_model(mesh, STRONG, 0.35, **kw), Motion(pulse, 0.3), SETTINGS).history

    intact = history(crack=(2.0, 2.0))
    shallow = history(crack=Crack((2.0, HEIGHT), 1e-6))
    through = history(crack=(2.0, HEIGHT))
    for key in ("theta_left", "theta_right", "energy_strain", "crack_opening_max"):
        scale = np.max(np.abs(intact[key]))
        assert scale > 0.0, key
        assert np.max(np.abs(shallow[key] - intact[key])) < 1e-5 * scale, key
    for key in ("energy_strain", "crack_opening_max"):
        scale = np.max(np.abs(intact[key]))
        assert np.max(np.abs(through[key] - intact[key])) > 0.05 * scale, key


def test_a_ligament_that_breaks_deepens_the_crack_and_the_balance_closes():
    """The halves of a block flying apart, the mid-plane cracked over its upper half to half
    the depth: the intact lower half and the upper half's ligament all break; the interface
    dissipates G_f over its area, t (H - d l), l the ligament's length (within 1 %), the
    energy balance closes with it, and the through crack grows from nothing to the full
    height (the ligament broken: the crack deepened), the ligament's damage reaching 1."""
    stone = Stone(ft=2e6, Gf=2000.0)
    mesh = column_mesh(0.2, 0.2, 0.025)
    t, d = 0.1, 0.5
    model = build_model(
        mesh,
        stone,
        t,
        contact=ContactSettings(friction=0.0, damping=0.0),
        crack=Crack((0.1, 0.2), d),
    )
    c = model.cohesive
    assert np.all(c.bonded) and c.ligament.sum() == 4  # the pairs above the tip at 0.1 m
    v = np.zeros(model.n_dofs)
    v[0::2] = np.where(mesh.node_body == 0, -3.0, 3.0)
    r = run(
        model,
        Motion(NoMotion(), 2e-3),
        FemSettings(progress=False, output_interval=1e-4),
        FemStart(velocity=v),
    )
    h, s = r.history, r.summary
    G = stone.Gf * float(c.area.sum())
    ligament = float(np.sum(c.tributary[c.ligament]))  # 0.1 m to within an element (graded)
    assert abs(ligament - 0.1) < 0.025
    assert G == pytest.approx(stone.Gf * t * (0.2 - d * ligament), rel=1e-12)
    assert h["energy_cohesive_dissipated"][-1] == pytest.approx(G, rel=0.01)
    assert s["energy_error_max"] < 0.01
    lost = h["energy_kinetic"][0] - h["energy_kinetic"][-1] - h["energy_strain"][-1]
    assert lost == pytest.approx(G, rel=0.01)
    assert h["crack_length"][0] == 0.0 and h["crack_length"][-1] == pytest.approx(0.2)
    assert h["crack_ligament_damage"][0] == 0.0 and h["crack_ligament_damage"][-1] == 1.0
    assert s["crack_grew"] is True and s["crack_depth"] == d
    assert s["crack_ligament_length"] == pytest.approx(float(np.sum(c.tributary[c.ligament])))
    assert s["crack_ligament_damage_max"] == 1.0


TINY_PART_DEPTH = """
[study]
name = "tiny-part-depth"
[column]
height = 1.0
width = 0.2
crack = [0.5, 1.0]
crack_depth = 0.5
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
def test_the_crosscheck_says_the_crack_runs_through_part_of_the_thickness(tmp_path):
    """The tiny column of tests/test_partial_crack.py cracked from the top to mid-height
    through half its thickness: the answers in detail say the depth, the ligament's extent on
    the mesh's pairs and its damage, and that the length is the through crack's (none at the
    start: the ligament holds the whole crack)."""
    import re

    from colonna.studies.driver import run_study_file
    from colonna.studies.executor import RunOptions

    study = tmp_path / "tiny.toml"
    study.write_text(TINY_PART_DEPTH)
    summary = run_study_file(
        study, tmp_path / "out", run_options=RunOptions(workers=1, progress=False)
    )
    fem = summary["fem"]
    assert fem["crack_depth"] == 0.5 and fem["crack_ligament_length"] == pytest.approx(0.475)
    assert fem["crack_length_initial"] == 0.0
    html = (tmp_path / "out" / "index.html").read_text()
    at = html.index('data-verdict="crack_grows"')
    detail = html[html.rindex("<tr>", 0, at) :].split("</tr>")[0]
    said = " ".join(re.sub("<[^>]+>", " ", detail).replace("&nbsp;", " ").split())
    assert (
        "the crack runs through 0.5 of the thickness ([column] crack_depth): along its 0.475 m"
        in said
    )
    assert "the crack's length and its tips are the through crack's" in said
    assert "the ligament's largest damage" in said
    # the first screen: the lengths are the through crack's, the depth and the ligament's damage
    row = html[html.index('data-answer="crack_grows"') :].split("</tr>")[0]
    words = " ".join(re.sub("<[^>]+>", " ", row).replace("&nbsp;", " ").split())
    assert "crack length 0 m at the start" in words
    assert "the crack through 0.5 of the thickness: the lengths are the through crack's" in words
    assert "the ligament's largest damage" in words
    answer = next(a for a in summary["outcome"]["answers"] if a["key"] == "crack_grows")
    assert answer["depth"] == 0.5 and 0.0 <= answer["ligament_damage"]["max"] <= 1.0


def test_a_refined_toe_window_keeps_the_cracks_depth():
    """The cross-check's toe windows rebuild the model on a refined mesh (fem.toe_stress.
    model_on): the crack's extent and depth go with it."""
    from colonna.fem.toe_stress import model_on
    from colonna.meshes.column import ToeGrading

    model = build_model(coarse(), STRONG, 0.35, crack=Crack((2.0, HEIGHT), 0.4))
    mesh = column_mesh(WIDTH, HEIGHT, 0.1125, toe=ToeGrading(refinement=2, zone=0.1))
    refined = model_on(model, mesh).cohesive
    assert refined.crack == (2.0, HEIGHT) and refined.depth == 0.4
    assert np.array_equal(refined.ligament, refined.heights > 2.0 + 1e-9)


def _inputs_page(inputs: dict) -> str:
    """The report's inputs section of ``inputs`` (inputs.json), as every kind renders it."""
    from colonna.studies.report import TEMPLATES, input_tables

    page = TEMPLATES.from_string(
        '{% from "macros.html.j2" import inputs_section with context %}'
        "{{ inputs_section(inputs, None) }}"
    )
    return page.render(inputs=dict(inputs, tables=input_tables(inputs)))


@pytest.mark.parametrize(("crack", "depth"), [((2.0, 3.2), 1.0), ((2.0, 3.2), 0.6)])
def test_the_report_says_where_the_crack_run_differs_from_the_crack_given(tmp_path, crack, depth):
    """A crack from 2.0 m to the top of a 3.2 m column (1.2 m given) runs on the mesh's node
    pairs, the pair nearest 2.0 m its intact tip: measured 1.204 m. The inputs' data paragraph
    says both lengths; a crack given where the pairs run it says nothing."""
    import re

    from colonna.studies.study import load

    path = tmp_path / "study.toml"
    path.write_text(STUDY_WITH_CRACK.format(crack=list(crack), depth=depth))
    inputs = load(path).to_json()
    model = inputs["model"]
    assert model["crack_length_given"] == pytest.approx(1.2)
    assert 1e-3 < abs(model["crack_length_run"] - 1.2) < 0.36 / 16  # within an element
    html = _inputs_page(inputs)
    said = " ".join(re.sub("<[^>]+>", " ", html).replace("&nbsp;", " ").split())
    run = f"{model['crack_length_run']:.3f}"
    assert f"crack given 1.200 m ( column.crack ), run {run} m on the mesh's node pairs" in said
    assert ("through 0.6 of the thickness" in said) == (depth < 1.0)
    # the full height given runs the full height: no sentence
    path.write_text(STUDY_WITH_CRACK.format(crack=[0.0, 3.2], depth=depth))
    inputs = load(path).to_json()
    assert inputs["model"]["crack_length_run"] == pytest.approx(3.2)
    assert "data-crack-extent" not in _inputs_page(inputs)


STUDY_WITH_CRACK = """
[study]
name = "crack-run"
kind = "cross-check"
[column]
height = 3.2
width = 0.36
crack = {crack}
crack_depth = {depth}
[ground]
amplitude_ratio = 2.5
omega_ratio = 4.0
"""

"""The base as a physical interface (issue 38): a Winkler bed of stiffness k per unit area,
fixed under mesh refinement, against the rigid block's closed form for a pivot on it
(c = sqrt(2 W / (k t theta)), p = 2 W / (t c), resultant c / 3 from the toe). Static solves
on small meshes and one short explicit run (a few seconds in all)."""

import numpy as np
import pytest

from colonna.core.errors import InputError
from colonna.core.ground import NoMotion
from colonna.core.motion import Motion
from colonna.fem.assembly import Stone
from colonna.fem.bed import (
    BED_PRESETS,
    Bed,
    bed_of,
    resolving_toe_size,
    static_on_bed,
    stone_bed,
    winkler_contact_length,
    winkler_peak_pressure,
    winkler_toe_pressure,
)
from colonna.fem.model import ContactSettings, build_model
from colonna.fem.settings import FemSettings, FemStart
from colonna.fem.solver import run
from colonna.meshes import column_mesh
from colonna.meshes.column import ToeGrading
from colonna.studies import schema

WIDTH, HEIGHT, THICKNESS = 0.4, 1.0, 0.3
K_BED = 1e11  # N/m^3
CONTACT = 0.02  # m: the contact length the horizontal load sets (equilibrium)


def _pivot(toe_size: float, E: float = 500e9):
    """A solid block on the bed under gravity and a horizontal body force that puts the base's
    resultant CONTACT / 3 from the right toe: the static state, the block's weight, its rigid
    rotation (mass-weighted least squares), the contact length (where the penetration crosses
    zero, between nodes linearly), the toe's pressure and the resultant's distance from it."""
    mesh = column_mesh(
        WIDTH, HEIGHT, 0.05, cracked=False, grading=0.3, toe=ToeGrading(zone=0.03, size=toe_size)
    )
    model = build_model(mesh, Stone(E=E), THICKNESS, bed=Bed(K_BED, K_BED, K_BED, "test"))
    m = model.node_mass
    weight = m.sum() * model.g
    # moments about the resultant: W x_R = H h_G, h_G = HEIGHT / 2 (uniform block)
    lever = 0.5 * WIDTH - CONTACT / 3.0
    load = model.gravity.copy()
    load[0::2] += m * model.g * lever / (0.5 * HEIGHT)
    state = static_on_bed(model, load)
    u = state["displacement"].reshape(-1, 2)
    r = mesh.points.T - (mesh.points.T * m[:, None]).sum(axis=0) / m.sum()
    theta = (m * (r[:, 0] * u[:, 1] - r[:, 1] * u[:, 0])).sum() / (m * (r**2).sum(axis=1)).sum()
    xb = mesh.points[0, model.base_nodes]
    order = np.argsort(-xb)  # from the right toe inward
    xb, pen = xb[order], state["penetration"][order]
    j = int(np.argmax(pen <= 0.0))
    x0 = xb[j - 1] + (xb[j] - xb[j - 1]) * pen[j - 1] / (pen[j - 1] - pen[j])
    fn = state["base_fn"][order]
    return {
        "model": model,
        "weight": weight,
        "theta": abs(theta),
        "contact": 0.5 * WIDTH - x0,
        "pressure": float(state["pressure"][order][0]),
        "resultant": 0.5 * WIDTH - float(fn @ xb) / fn.sum(),
        "force": fn.sum(),
    }


def test_a_block_pivoting_on_a_winkler_bed_has_the_closed_forms_contact_and_pressure():
    """A stiff stone (10 x marble) resolved with 8 elements across the contact: at its own tilt
    the contact length and toe pressure are the rigid closed form's within 5 % (measured 0.3 %
    and 0.4 %), the base carries the weight, and the resultant is c / 3 from the toe."""
    p = _pivot(CONTACT / 8)
    W, theta = p["weight"], p["theta"]
    assert p["force"] == pytest.approx(W, rel=1e-6)
    assert p["resultant"] == pytest.approx(CONTACT / 3.0, rel=1e-3)
    c = winkler_contact_length(W, K_BED, THICKNESS, theta)
    assert p["contact"] == pytest.approx(c, rel=0.05)
    assert p["pressure"] == pytest.approx(winkler_peak_pressure(W, K_BED, THICKNESS, theta), 0.05)
    assert p["pressure"] == pytest.approx(2.0 * W / (THICKNESS * CONTACT), rel=0.05)


def test_the_resolved_toe_pressure_converges_at_a_fixed_bed_stiffness():
    """The toe graded to 4, 8 and 16 elements across the contact, the bed's k held: the toe
    pressure changes by less than 3 % from the second mesh to the finest (measured 1.0 %) and
    approaches the closed form 2 W / (t c) (measured within 0.3 % on the finest); the base's
    springs add up to k t width on every mesh (nothing scales with the element size)."""
    runs = [_pivot(CONTACT / n) for n in (4, 8, 16)]
    for p in runs:
        total = p["model"].base_kn.sum()
        assert total == pytest.approx(K_BED * THICKNESS * WIDTH, rel=1e-12)
    pressures = [p["pressure"] for p in runs]
    assert abs(pressures[2] - pressures[1]) / pressures[2] < 0.03
    exact = 2.0 * runs[2]["weight"] / (THICKNESS * CONTACT)
    assert abs(pressures[2] - exact) < abs(pressures[0] - exact)
    assert pressures[2] == pytest.approx(exact, rel=0.01)


def test_the_base_springs_are_the_bed_and_nothing_else():
    """Each base node's spring is k t l_trib: refining the toe, changing the stone's E or the
    contact's penalty settings (the crack's) leaves it as it is; the old E / h scaling would
    have doubled it at the toe with each refinement."""
    bed = bed_of("lead")
    totals, toe = [], []
    for r in (1, 2, 4):
        mesh = column_mesh(WIDTH, 2.0, 0.1, toe=ToeGrading(refinement=r, zone=0.04))
        for E, factor in ((50e9, 1.0), (5e9, 4.0)):
            model = build_model(
                mesh,
                Stone(E=E),
                THICKNESS,
                contact=ContactSettings(penalty_factor=factor),
                bed=bed,
            )
            np.testing.assert_allclose(
                model.base_kn, bed.stiffness * THICKNESS * model.base_tributary, rtol=1e-12
            )
            totals.append(model.base_kn.sum())
        toe.append(model.base_kn[0] / model.base_tributary[0])
    np.testing.assert_allclose(totals, bed.stiffness * THICKNESS * WIDTH, rtol=1e-12)
    np.testing.assert_allclose(toe, bed.stiffness * THICKNESS, rtol=1e-12)


def test_a_column_at_rest_on_its_bed_presses_it_evenly():
    """Standing still (explicit run, resolved toe grading): the base's resultant is the whole
    weight at mid-width from the toe, and the largest nodal pressure is the mean W / (t width)
    raised by the elastic block's edge effect on its bed by a few per cent (measured 3.9 %)."""
    mesh = column_mesh(WIDTH, HEIGHT, 0.1, cracked=False, toe=ToeGrading(zone=0.02, size=0.005))
    model = build_model(mesh, Stone(), THICKNESS, bed=bed_of("mortar"))
    r = run(model, Motion(NoMotion(), 0.01), FemSettings(output_interval=1e-3, progress=False))
    s = r.summary
    weight = model.node_mass.sum() * model.g
    mean = weight / (THICKNESS * WIDTH)
    assert mean < s["toe_pressure_max"] < 1.05 * mean
    assert s["toe_resultant"] == pytest.approx(weight, rel=1e-6)
    assert s["toe_resultant_offset"] == pytest.approx(0.5 * WIDTH, rel=1e-6)
    assert s["bed_stiffness"] == bed_of("mortar").stiffness
    # upright: the rigid base on its bed presses it evenly (the tilt is the elastic sag's)
    assert s["toe_pressure_winkler"] == pytest.approx(mean, rel=1e-3)


def test_the_winkler_toe_pressure_of_a_force_and_a_tilt():
    """Partial contact: the pivot's closed form; full contact: N / (t w) + k theta w / 2 (the
    trapezoid's larger end), equal to it where c = w; none without a force."""
    W, k, t, w = 3e3, 1e11, 0.3, 0.4
    theta = np.array([1e-3, 1e-4])
    p = winkler_toe_pressure(W, theta, k, t, w)
    assert p[0] == pytest.approx(winkler_peak_pressure(W, k, t, 1e-3), rel=1e-12)
    assert winkler_contact_length(W, k, t, 1e-4) < w
    at_w = 2 * W / (k * t * w * w)  # the tilt at which c = w
    both = winkler_toe_pressure(W, [at_w * (1 - 1e-9), at_w * (1 + 1e-9), 0.0], k, t, w)
    assert both[0] == pytest.approx(both[1], rel=1e-6)
    assert both[2] == pytest.approx(W / (t * w), rel=1e-12)
    theta_full = 0.5 * at_w
    expected = W / (t * w) + 0.5 * k * theta_full * w
    assert winkler_toe_pressure(W, theta_full, k, t, w) == pytest.approx(expected, rel=1e-12)
    assert winkler_toe_pressure(-1.0, 1e-3, k, t, w) == 0.0


def test_the_stone_bed_is_the_base_rows_stiffness():
    """stone_bed (the stiff limit's base): each base node's spring is E t l_trib / h with h the
    base row's height, the element penalty of old, and it stiffens with the stone."""
    mesh = column_mesh(WIDTH, 2.0, 0.1, grading=0.3)
    h = np.unique(mesh.points[1])[1]
    for E in (50e9, 5000e9):
        model = build_model(mesh, Stone(E=E), THICKNESS, bed=stone_bed(mesh, E))
        expected = E * THICKNESS * model.base_tributary / h
        np.testing.assert_allclose(model.base_kn, expected, rtol=1e-12)


@pytest.mark.parametrize("name", list(BED_PRESETS))
def test_each_preset_is_its_layers_modulus_over_its_thickness(name):
    """A layer's range is (softest E / thickest layer, stiffest E / thinnest); every preset's
    nominal is the geometric mean of its range's ends; the bed of it carries them and names
    its source."""
    p = BED_PRESETS[name]
    low, high = p.stiffness_range
    if p.layer is not None:
        (e_low, e_high), (t_low, t_high) = p.layer
        assert (low, high) == pytest.approx((e_low / t_high, e_high / t_low), rel=1e-12)
    bed = bed_of(name)
    assert (bed.low, bed.high) == (low, high)
    assert bed.stiffness == pytest.approx(np.sqrt(low * high), rel=1e-12)
    assert bed.source == p.source
    assert BED_PRESETS["mortar"].stiffness_range == pytest.approx((5e10, 1e12))
    assert BED_PRESETS["lead"].stiffness_range == pytest.approx((16e9 / 3.55e-3, 16e9 / 1.32e-3))


def test_the_toe_grading_rule_puts_its_elements_across_the_contact():
    """resolving_toe_size is the closed-form contact length at half the slenderness over 4."""
    W, k, t, alpha = 16.8e3, 2.2e11, 0.35, 0.11
    size = resolving_toe_size(W, k, t, alpha)
    assert 4 * size == pytest.approx(np.sqrt(2 * W / (k * t * alpha / 2)), rel=1e-12)
    mesh = column_mesh(0.45, 4.0, 0.0375, toe=ToeGrading(zone=0.01, size=size))
    xs = np.unique(mesh.points[0])
    ys = np.unique(mesh.points[1])
    assert np.diff(xs)[0] <= size * (1 + 1e-9) and np.diff(ys)[0] <= size * (1 + 1e-9)
    assert np.sum(xs < xs[0] + 4 * size * (1 + 1e-9)) >= 5  # 4 elements over c at alpha / 2
    # the graded zone keeps a collar's row, and says so where it would not
    pinned = column_mesh(
        0.45, 4.0, 0.0375, pinned_heights=[0.5], toe=ToeGrading(zone=0.01, size=size)
    )
    assert np.any(np.abs(pinned.points[1] - 0.5) < 1e-12)
    with pytest.raises(InputError, match="pinned"):
        column_mesh(0.45, 4.0, 0.0375, pinned_heights=[0.02], toe=ToeGrading(zone=0.03, size=size))


def test_a_bad_bed_is_an_input_error_naming_the_key():
    """An unknown preset, a range without a stiffness or not around it, a stiffness out of
    range: each names its key."""
    base = {"column": {"height": 2.0, "width": 0.4}, "ground": {"pulse": "none"}}
    for table, words in (
        ({"bed": "sand"}, "base.bed"),
        ({"stiffness_range": [1e10, 1e12]}, "base.stiffness_range"),
        ({"stiffness": 1e11, "stiffness_range": [1e12, 1e13]}, "base.stiffness_range"),
        ({"stiffness": 1e3}, "base.stiffness"),
    ):
        with pytest.raises(InputError, match=words.replace(".", r"\.")):
            schema.parse({**base, "base": table})
    with pytest.raises(InputError, match="base stiffness"):
        Bed(1e11, 1e12, 1e13, "x")


@pytest.mark.slow
def test_a_block_dropping_onto_its_toe_presses_the_bed_as_the_closed_form_says():
    """Explicit dynamics: a solid block released at half its slenderness falls onto its toe and
    rebounds on a soft bed (k = 1 GPa/m, contact about 18 mm at the peak), the toe graded to 4
    and 8 elements across that length. At the output sample of the largest base force the
    toe's nodal pressure is the Winkler pressure of the run's own base force and tilt within
    2 % (measured 0.7 % and 0.4 %), and it converges between the two meshes (measured 0.5 %)."""
    k = 1e9
    alpha = np.arctan(WIDTH / HEIGHT)
    peaks = []
    for across in (4, 8):
        mesh = column_mesh(
            WIDTH,
            HEIGHT,
            0.05,
            cracked=False,
            grading=0.3,
            toe=ToeGrading(zone=0.03, size=0.0146 / across),
        )
        model = build_model(mesh, Stone(), THICKNESS, bed=Bed(k, k, k, "a soft bed"))
        h = run(
            model,
            Motion(NoMotion(), 0.045),
            FemSettings(output_interval=2e-3, progress=False),
            FemStart(tilt=0.5 * alpha),
        ).history
        i = int(np.argmax(h["base_normal_force_1"]))
        force, tilt = h["base_normal_force_1"][i], h["theta_left"][i]
        assert force > 2.0 * model.node_mass.sum() * model.g  # the drop: more than its weight
        nodal = max(h["toe_pressure_left"][i], h["toe_pressure_right"][i])
        closed = winkler_toe_pressure(force, tilt, k, THICKNESS, WIDTH)
        assert winkler_contact_length(force, k, THICKNESS, tilt) < 0.1 * WIDTH  # a pivot
        assert nodal == pytest.approx(closed, rel=0.02)
        peaks.append(nodal)
    assert peaks[1] == pytest.approx(peaks[0], rel=0.03)


def test_a_study_can_grade_its_mesh_to_the_toe():
    """[mesh] toe_size grades the study's own mesh at the base corners (its runs then resolve
    the toe, at a shorter step); the bed's springs still add up to k t width; the toe element
    can be no larger than the toe window."""
    from colonna.studies.fem_study import from_dict
    from colonna.studies.models import build

    data = {
        "column": {"height": 1.0, "width": 0.2},
        "ground": {"pulse": "none"},
        "run": {"initial_tilt": 0.01},
        "mesh": {"size": 0.05, "toe_size": 0.002, "edge_length": 0.01},
    }
    study = from_dict(data)
    model = build(study)
    xs = np.unique(model.mesh.points[0])
    ys = np.unique(model.mesh.points[1])
    assert xs[1] - xs[0] <= 0.002 + 1e-12 and ys[1] - ys[0] <= 0.002 + 1e-12
    k, t = study.bed.stiffness, study.thickness
    assert model.base_kn.sum() == pytest.approx(k * t * 0.2, rel=1e-12)
    with pytest.raises(InputError, match="toe_size"):
        build(from_dict({**data, "mesh": {"size": 0.05, "toe_size": 0.02, "edge_length": 0.01}}))

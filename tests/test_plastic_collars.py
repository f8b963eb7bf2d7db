"""Elastoplastic collars (``plastic = true``) with the resultant law (``section = "resultant"``;
the fibre law's are tests/test_fibre_collar.py and tests/test_fibre_dynamics.py): bilinear axial
law with hardening in the FEM frame element, the energy balance with the plastic work, and the
study keys."""

import numpy as np
import pytest

from colonna.core.collar_law import FIBRE_STRAIN, FRACTURED, OUT_SIZE, STATE_SIZE
from colonna.core.errors import InputError
from colonna.core.ground import NoMotion
from colonna.core.motion import Motion
from colonna.fem.assembly import Stone
from colonna.fem.model import ContactSettings, build_model
from colonna.fem.settings import FemSettings, FemStart
from colonna.fem.solver import run
from colonna.meshes import column_mesh
from colonna.rigid.collars import Collar
from colonna.rigid.multibody import MultibodyContact


def _pulled_apart(collar, duration=0.006, speed=0.4):
    """The two halves of a 0.4 x 2 m column flung apart at +-speed (m/s) on frictionless,
    undamped contacts, held by one collar at mid height: the collar stretches, yields if it
    must, and stops them (the run ends before the crack closes again)."""
    mesh = column_mesh(0.4, 2.0, 0.1, cracked=True, grading=0.0, pinned_heights=[1.0])
    model = build_model(mesh, Stone(), 0.3, (collar,), ContactSettings(friction=0.0, damping=0.0))
    v0 = np.zeros((mesh.n_nodes, 2))
    v0[mesh.node_body == 0, 0] = -speed
    v0[mesh.node_body == 1, 0] = speed
    return run(
        model,
        Motion(NoMotion(), duration),
        FemSettings(output_interval=1e-5, progress=False, stop_on_overturn=False),
        FemStart(velocity=v0),
    )


def test_plastic_collar_follows_the_bilinear_law_and_the_energy_balance_closes():
    collar = Collar(y=1.0, t=0.004, h=0.03, plastic=True, section="resultant")
    r = _pulled_apart(collar)
    h, s = r.history, r.summary
    N, eps_p = h["collar_1_axial_force"], h["collar_1_plastic_strain"]
    assert s["collar_max_plastic_strain"] > 2.0 * collar.fy / collar.E  # well past yield
    # while it yields, |N| = A (f_y + H eps_p), H = E E_h / (E - E_h), E_h = 0.01 E
    yielding = np.r_[False, np.diff(np.abs(eps_p)) > 0.0]
    assert yielding.sum() > 20
    law = collar.area * (collar.fy + collar.plastic_modulus * np.abs(eps_p[yielding]))
    assert np.abs(np.abs(N[yielding]) - law).max() < 1e-9 * collar.fy * collar.area
    # and never beyond that surface
    assert np.all(
        np.abs(N)
        <= collar.area * (collar.fy + collar.plastic_modulus * np.abs(eps_p)) * (1 + 1e-12)
    )
    # initial kinetic energy = kinetic + stone strain + collar elastic + plastic work (1 %)
    assert s["collar_plastic_work"] > 0.3 * h["energy_kinetic"][0]
    assert h["energy_dissipated"][-1] == pytest.approx(s["collar_plastic_work"], rel=1e-9)
    assert s["energy_error_max"] < 0.01


def test_elastic_collar_is_the_same_law_without_the_yield():
    """plastic = false keeps the elastic collar: it carries more than f_y A, with no plastic
    work; plastic = true with a yield far above the force reached changes nothing."""
    elastic = _pulled_apart(Collar(y=1.0, t=0.004, h=0.03))
    assert elastic.history["collar_1_axial_force"].max() > 0.004 * 0.03 * 235e6
    assert elastic.summary["collar_plastic_work"] == 0.0
    strong = _pulled_apart(
        Collar(y=1.0, t=0.004, h=0.03, fy=1e10, plastic=True, section="resultant")
    )
    np.testing.assert_allclose(
        strong.history["collar_1_axial_force"], elastic.history["collar_1_axial_force"], rtol=1e-12
    )


@pytest.mark.parametrize(
    "kw, name",
    [
        ({"plastic": "yes"}, "plastic"),
        ({"Eh": 3e11}, "Eh"),
        ({"Eh": -1.0}, "Eh"),
        ({"eps_u": 1e-3, "plastic": True}, "eps_u"),  # below f_y / E: breaks before yielding
        ({"eps_u": 2.0}, "eps_u"),
        ({"hinge_length": 0.0}, "hinge_length"),
    ],
)
def test_bad_plastic_collar_input(kw, name):
    with pytest.raises(InputError, match=name):
        Collar(y=1.0, t=0.004, h=0.03, **kw)


def test_multibody_collar_element_is_bilinear_on_a_load_unload_cycle():
    """The multibody frame element pulled along its chord to 4 strain-at-yield and part way
    back: slope E A on loading, E_h A past N_y = f_y A, E A again on unloading, keeping the
    plastic elongation; the work put in = elastic energy left + plastic work (trapezoid)."""
    from colonna.rigid import _multibody as K
    from colonna.rigid.block import Block
    from colonna.rigid.multibody import build_column

    collar = Collar(y=1.0, t=0.004, h=0.03, plastic=True, section="resultant")
    column = build_column(Block(b=0.1, h=1.0, mass=100.0), cracked=True, collars=(collar,))
    span = collar.span(0.1)
    eps_y = collar.fy / collar.E
    # back to 2.5 eps_y: sigma = 1.03 f_y - 1.5 E eps_y = -0.47 f_y, inside the elastic range
    path = np.concatenate(
        (np.linspace(0.0, 4.0 * eps_y, 400), np.linspace(4.0 * eps_y, 2.5 * eps_y, 400)[1:])
    )
    state, out = np.zeros((1, STATE_SIZE)), np.zeros((1, OUT_SIZE))
    forces = []
    for eps in path:
        q = column.q_rest.copy()
        q[3] += eps * span  # the right half moves out along the chord
        K.collar_forces(
            q,
            column.col_a,
            column.col_b,
            column.col_r,
            column.col_props,
            np.zeros(0),
            out,
            state,
            True,
        )
        forces.append(out[0, 0])
    N = np.array(forces)
    A, E, Eh = collar.area, collar.E, collar.hardening_modulus
    peak = A * (collar.fy + Eh * (4.0 * eps_y - eps_y))  # bilinear: E_h past eps_y
    assert N[399] == pytest.approx(peak, rel=1e-9)
    assert N[50] == pytest.approx(E * A * path[50], rel=1e-9)  # elastic branch
    plastic = state[0, 0] / span
    assert plastic == pytest.approx(4.0 * eps_y - peak / (E * A), rel=1e-9)
    assert N[-1] == pytest.approx(E * A * (2.5 * eps_y - plastic), rel=1e-6)  # unloading
    work = np.sum(0.5 * (N[1:] + N[:-1]) * np.diff(path) * span)
    assert work == pytest.approx(out[0, 3] + state[0, 2], rel=1e-3)


@pytest.mark.chaotic
def test_multibody_rocking_with_plastic_collars_keeps_its_energy_balance():
    """A cracked column rocked hard enough to yield thin collars: plastic strain appears, the
    elastic run's collar would be past f_y, and the energy balance (plastic work counted as
    dissipated) closes to 1 %."""
    from colonna.core.ground import sine_pulse
    from colonna.rigid.block import Block
    from colonna.rigid.multibody import rock_multibody

    half = Block(b=0.1125, h=2.0, mass=858.0)
    a_up = half.uplift_acceleration()
    pulse = sine_pulse(3.0 * a_up, 3.0 * half.p, a_up)
    thin = dict(y=2.0, t=0.002, h=0.02)
    runs = {
        plastic: rock_multibody(
            half,
            Motion(pulse, duration=2.0),
            (Collar(**thin, plastic=plastic, section="resultant" if plastic else None),),
            contact=MultibodyContact(cracked=True),
        )
        for plastic in (False, True)
    }
    elastic, plastic = runs[False].summary(), runs[True].summary()
    assert elastic["collar_max_utilisation"] > 1.5
    assert plastic["collar_max_plastic_strain"] > 0.1 * 235e6 / 206e9
    assert plastic["collar_plastic_work"] > 0.0 and elastic["collar_plastic_work"] == 0.0
    assert plastic["energy_error_max"] < 1e-2


def test_fem_collar_element_pulled_quasi_statically_follows_the_bilinear_law():
    """The FEM frame element pulled along its chord to 4 strain-at-yield and part way back,
    one committed evaluation per increment (quasi-static): slopes E A, E_h A past f_y A, E A
    on unloading; the work put in = elastic energy + plastic work to 1e-3."""
    from colonna.fem import _kernels as K

    collar = Collar(y=1.0, t=0.004, h=0.03, plastic=True, section="resultant")
    mesh = column_mesh(0.4, 2.0, 0.1, cracked=True, grading=0.0, pinned_heights=[1.0])
    model = build_model(mesh, Stone(), 0.3, (collar,))
    span = collar.span(0.1)
    eps_y = collar.fy / collar.E
    path = np.concatenate(
        (np.linspace(0.0, 4.0 * eps_y, 400), np.linspace(4.0 * eps_y, 2.5 * eps_y, 400)[1:])
    )
    state, out = np.zeros((1, STATE_SIZE)), np.zeros((1, OUT_SIZE))
    right = model.collar_nodes[0, 3:]
    forces = []
    for eps in path:
        x = model.X.copy()
        x[2 * right] += eps * span  # the right end and its face nodes move out
        K.collar_forces(
            x, model.collar_nodes, model.collar_props, out, np.zeros_like(x), state, True
        )
        forces.append(out[0, 0])
    N = np.array(forces)
    A, E, Eh = collar.area, collar.E, collar.hardening_modulus
    assert N[50] == pytest.approx(E * A * path[50], rel=1e-9)
    assert N[399] == pytest.approx(A * (collar.fy + Eh * 3.0 * eps_y), rel=1e-9)
    plastic = state[0, 0] / span
    assert N[-1] == pytest.approx(E * A * (2.5 * eps_y - plastic), rel=1e-6)
    work = np.sum(0.5 * (N[1:] + N[:-1]) * np.diff(path) * span)
    assert work == pytest.approx(out[0, 3] + state[0, 2], rel=1e-3)


# --- bending: the end hinges on the N-M interaction surface ----------------------------------


def _fem_element(collar):
    """The FEM frame element of `collar` (0.4 m span) and a function that imposes on its right
    end (node and face nodes) an axial stretch and a lateral offset, returning the element's
    (N, M1, M2, elastic energy) and the forces on the moved dofs (lateral ones summed)."""
    from colonna.fem import _kernels as K

    mesh = column_mesh(0.4, 2.0, 0.1, cracked=True, grading=0.0, pinned_heights=[1.0])
    model = build_model(mesh, Stone(), 0.3, (collar,))
    right = model.collar_nodes[0, 3:]
    out = np.zeros((1, OUT_SIZE))

    def impose(dx, dy, state, commit=True):
        x = model.X.copy()
        x[2 * right] += dx
        x[2 * right + 1] += dy
        f = np.zeros_like(x)
        K.collar_forces(x, model.collar_nodes, model.collar_props, out, f, state, commit)
        return out[0].copy(), (f[2 * right].sum(), f[2 * right + 1].sum())

    return impose, collar.span(0.1)


def _multibody_element(collar):
    """As _fem_element, for the multibody model's frame element (right half moved)."""
    from colonna.rigid import _multibody as K
    from colonna.rigid.block import Block
    from colonna.rigid.multibody import build_column

    column = build_column(Block(b=0.1, h=2.0, mass=100.0), cracked=True, collars=(collar,))
    out = np.zeros((1, OUT_SIZE))

    def impose(dx, dy, state, commit=True):
        q = column.q_rest.copy()
        q[3] += dx
        q[4] += dy
        f = np.zeros(q.size)
        K.collar_forces(
            q, column.col_a, column.col_b, column.col_r, column.col_props, f, out, state, commit
        )
        return out[0].copy(), (f[3], f[4])

    return impose, collar.span(0.1)


def _offset_cycle(impose, collar, span, axial_ratio=0.0):
    """A full quasi-static cycle of the lateral end offset, 0 -> 4 d_y -> -4 d_y -> 0 (d_y =
    M_y L^2 / (6 E I), fixed-fixed), the chord held at the length that carries axial_ratio N_p
    (elastic stretch): the end moves on a circle, so that the offset bends the collar without
    the membrane stretch of a purely lateral move (6 % of the span here). Returns the offsets,
    the chord rotations, the element's outputs (N, M1, M2, U), the work done on the moved end
    per increment and the state."""
    from colonna.core.collar_law import STATE_SIZE

    d_y = collar.yield_moment * span**2 / (6.0 * collar.E * collar.second_moment)
    stretch = axial_ratio * collar.fy * collar.area * span / (collar.E * collar.area)
    step = d_y / 200.0
    path = np.concatenate(
        (
            np.arange(0.0, 4.0 * d_y, step),
            np.arange(4.0 * d_y, -4.0 * d_y, -step),
            np.arange(-4.0 * d_y, step / 2, step),
        )
    )
    chord = span + stretch
    dx = np.sqrt(chord**2 - path**2) - span
    state = np.zeros((1, STATE_SIZE))
    rows = [impose(x, y, state) for x, y in zip(dx, path)]
    outs = np.array([r[0] for r in rows])
    f = np.array([r[1] for r in rows])
    # work done on the element by the imposed motion: -(force of the collar on the end) . dx
    work = -(
        0.5 * (f[1:, 0] + f[:-1, 0]) * np.diff(dx) + 0.5 * (f[1:, 1] + f[:-1, 1]) * np.diff(path)
    )
    return path, np.arcsin(path / chord), d_y, outs, work, state


@pytest.mark.parametrize("element", [_fem_element, _multibody_element], ids=["fem", "multibody"])
def test_fixed_fixed_collar_yields_in_bending_to_the_plastic_moment(element):
    """Imposed relative end offset d, both ends held against rotation: M = 6 E I d / L^2 while
    elastic, the extreme fibre reaches f_y at M_y (the stress reported), the end moment levels
    off at M_p = f_y t h^2 / 4 (times the hardening factor), unloading is elastic, and a full
    cycle's loop area is the plastic work plus the change of elastic energy (1 %)."""
    collar = Collar(y=1.0, t=0.004, h=0.03, plastic=True, section="resultant")
    impose, span = element(collar)
    path, beta, d_y, outs, work, state = _offset_cycle(impose, collar, span)
    M = np.abs(outs[:, 1])
    EI = collar.E * collar.second_moment
    # elastic branch (up to the plastic moment M_p = 1.5 M_y, at d = 1.5 d_y): 6 E I d / L^2
    # for small d (the co-rotational element: 6 E I beta / L of the chord rotation beta)
    early = (path > 0) & (path < 1.4 * d_y) & (np.arange(path.size) < 800)
    np.testing.assert_allclose(M[early], 6.0 * EI * beta[early] / span, rtol=1e-9)
    assert M[1] == pytest.approx(6.0 * EI * path[1] / span**2, rel=1e-6)
    at_yield = np.argmin(np.abs(path[:800] - d_y))
    assert M[at_yield] / collar.section_modulus == pytest.approx(collar.fy, rel=1e-2)
    # the plateau: M_p times the hardening factor, within 2 % of M_p
    peak = M[799]
    assert collar.plastic_moment <= peak <= 1.02 * collar.plastic_moment
    g = 1.0 + collar.plastic_modulus * state[0, 1] / collar.fy  # the hardening factor
    assert M.max() <= g * collar.plastic_moment * (1.0 + 1e-12) and g < 1.02
    assert state[0, 3] != 0.0 and state[0, 4] != 0.0  # both hinges turned
    # unloading from the peak is elastic: slope 6 E I / L^2
    slope = (outs[801, 1] - outs[800, 1]) / (beta[801] - beta[800])
    assert abs(slope) == pytest.approx(6.0 * EI / span, rel=1e-9)
    # the loop: work done on the element over the cycle = plastic work + elastic energy left
    assert state[0, 2] > 0.5 * work.sum()
    assert work.sum() == pytest.approx(state[0, 2] + outs[-1, 3] - outs[0, 3], rel=1e-2)


@pytest.mark.parametrize("element", [_fem_element, _multibody_element], ids=["fem", "multibody"])
def test_under_half_the_squash_load_the_hinges_form_at_three_quarters_of_m_p(element):
    """With N = N_p / 2 held, the interaction surface M / M_p + (N / N_p)^2 = 1 gives the
    plateau 0.75 M_p; N itself stays at N_p / 2 (the hinges rotate, the axial law holds N)."""
    collar = Collar(y=1.0, t=0.004, h=0.03, plastic=True, section="resultant")
    impose, span = element(collar)
    path, beta, d_y, outs, _work, state = _offset_cycle(impose, collar, span, axial_ratio=0.5)
    M = np.abs(outs[:, 1])
    assert M[799] == pytest.approx(0.75 * collar.plastic_moment, rel=0.02)
    # never outside the hardened surface: M <= g M_p (1 - (N / (g N_p))^2), g = 1 + H alpha / f_y
    g = 1.0 + collar.plastic_modulus * state[0, 1] / collar.fy
    assert g < 1.02
    assert M.max() <= collar.plastic_moment * (g - 0.25 / g) * (1.0 + 1e-12)
    assert outs[799, 0] == pytest.approx(0.5 * collar.fy * collar.area, rel=1e-3)


def test_an_elastic_collar_keeps_bending_past_the_plastic_moment():
    """plastic = false: the same cycle stays on 6 E I d / L^2 (the report then quotes an elastic
    stress past f_y, which the utilisation flags)."""
    collar = Collar(y=1.0, t=0.004, h=0.03)
    impose, span = _fem_element(collar)
    path, beta, d_y, outs, _work, state = _offset_cycle(impose, collar, span)
    EI = collar.E * collar.second_moment
    np.testing.assert_allclose(
        np.abs(outs[:, 1]), 6.0 * EI * np.abs(beta) / span, rtol=1e-9, atol=1e-6
    )
    assert np.abs(outs[:, 1]).max() > 2.5 * collar.yield_moment
    # no plastic flow, no fracture; only the largest fibre strain is kept: the elastic
    # bending strain M / (E W) of the largest end moment
    assert not state[:, :FIBRE_STRAIN].any() and not state[:, FRACTURED].any()
    assert state[0, FIBRE_STRAIN] == pytest.approx(
        np.abs(outs[:, 1]).max() / (collar.E * collar.section_modulus), rel=1e-9
    )


def _flung_up(collar, duration=0.03):
    """The right half of a 0.4 x 2 m column flung up along the crack at 1 m/s on frictionless,
    undamped contacts, held by ``collar`` at mid height, which it bends (and stretches)."""
    mesh = column_mesh(0.4, 2.0, 0.1, cracked=True, grading=0.0, pinned_heights=[1.0])
    model = build_model(mesh, Stone(), 0.3, (collar,), ContactSettings(friction=0.0, damping=0.0))
    v0 = np.zeros((mesh.n_nodes, 2))
    v0[mesh.node_body == 1, 1] = 1.0
    return run(
        model,
        Motion(NoMotion(), duration),
        FemSettings(output_interval=1e-5, progress=False, stop_on_overturn=False),
        FemStart(velocity=v0),
    )


def test_collar_bent_by_sliding_halves_yields_and_the_energy_balance_closes():
    """The right half of a column flung up along the crack on frictionless, undamped contacts:
    the collar at mid height bends (and stretches), its end hinges yield, the end moments
    reach the plastic moment and never pass it (the hardening is small here), and the initial
    kinetic energy = kinetic + strain + contact + gravity + collar elastic + plastic work (1 %)."""
    collar = Collar(y=1.0, t=0.004, h=0.03, plastic=True, section="resultant")
    r = _flung_up(collar)
    h, s = r.history, r.summary
    assert s["collar_plastic_work"] > 0.1 * h["energy_kinetic"][0]
    moment = h["collar_1_moment"]
    assert 0.98 * collar.plastic_moment < moment.max() <= 1.02 * collar.plastic_moment
    assert s["energy_error_max"] < 0.01


# --- fracture: the extreme fibre's strain against eps_u ----------------------------------------


@pytest.mark.parametrize("element", [_fem_element, _multibody_element], ids=["fem", "multibody"])
def test_fixed_fixed_collar_fractures_where_its_fibre_strain_reaches_eps_u(element):
    """The offset cycle of a collar with eps_u = 0.006: on the plateau both hinges carry M_p
    and turn by theta_p = beta - M_p L / (6 E I) (the ends held, beta the chord rotation), so
    the extreme fibre's strain is M_p / (E W) + theta_p h / (2 L_p); the collar breaks at the
    offset where that reaches eps_u, then carries nothing, and all the work put into it has
    gone into plastic work and the energy released by the break (1 %)."""
    collar = Collar(y=1.0, t=0.004, h=0.03, plastic=True, section="resultant", eps_u=0.006)
    impose, span = element(collar)
    path, beta, d_y, outs, work, state = _offset_cycle(impose, collar, span)
    EI, EW = collar.E * collar.second_moment, collar.E * collar.section_modulus
    assert state[0, FRACTURED] == 1.0
    broken = np.flatnonzero(np.all(outs[:, :4] == 0.0, axis=1) & (np.arange(path.size) > 0))
    k = broken[0]
    assert np.all(outs[k:, :4] == 0.0)  # nothing carried from the break on
    # the closed form on the plateau (hardening < 2 %): the strain at the step before the break
    plateau = collar.plastic_moment / EW
    theta_p = beta[k - 1] - collar.plastic_moment * span / (6.0 * EI)
    predicted = plateau + theta_p * collar.h / (2.0 * collar.plastic_hinge_length)
    assert outs[k - 1, 5] == pytest.approx(predicted, rel=0.02)
    assert outs[k - 1, 5] < collar.eps_u <= state[0, FIBRE_STRAIN]
    # the offset of the break from the same closed form, to one increment
    beta_break = collar.plastic_moment * span / (6.0 * EI) + (collar.eps_u - plateau) * 2.0 * (
        collar.plastic_hinge_length / collar.h
    )
    assert abs(beta[k] - beta_break) < 0.03 * beta_break
    # the work put in = plastic work + the elastic energy the break released (no energy left)
    assert work.sum() == pytest.approx(state[0, 2], rel=1e-2)


def test_a_collar_that_breaks_in_a_run_drops_out_and_the_energy_balance_closes():
    """The flung-up half of the bending test with a brittle collar (eps_u = 0.004): the collar
    breaks, the summary says when, the collar carries nothing after that, the ductility demand
    is the largest fibre strain over the yield strain, and the energy balance (the released
    elastic energy counted as dissipated) still closes to 1 %."""
    collar = Collar(y=1.0, t=0.004, h=0.03, plastic=True, section="resultant", eps_u=0.004)
    r = _flung_up(collar)
    h, s = r.history, r.summary
    assert s["collar_fractured"] and s["collar_fracture_time"] is not None
    after = h["t"] >= s["collar_fracture_time"]
    assert 0 < after.sum() < after.size
    assert np.all(h["collar_1_fractured"][after] == 1.0) and not h["collar_1_fractured"][0]
    assert np.all(h["collar_1_axial_force"][after] == 0.0)
    assert np.all(h["collar_1_moment"][after] == 0.0)
    assert s["collar_max_fibre_strain"] >= collar.eps_u
    assert s["collar_ductility_demand"] == pytest.approx(
        s["collar_max_fibre_strain"] / collar.yield_strain, rel=1e-12
    )
    assert s["energy_error_max"] < 0.01


@pytest.mark.chaotic
def test_multibody_collar_breaks_and_reports_it():
    """The multibody model's rocking test with a brittle thin collar: it breaks, the summary
    says when and gives the ductility demand, the collar's forces are zero after the break,
    and the energy balance closes to 1 %; with the default eps_u the same collar holds."""
    from colonna.core.ground import sine_pulse
    from colonna.rigid.block import Block
    from colonna.rigid.multibody import rock_multibody

    half = Block(b=0.1125, h=2.0, mass=858.0)
    a_up = half.uplift_acceleration()
    pulse = sine_pulse(3.0 * a_up, 3.0 * half.p, a_up)
    thin = dict(y=2.0, t=0.002, h=0.02, plastic=True, section="resultant")
    holds, breaks = (
        rock_multibody(
            half,
            Motion(pulse, duration=2.0),
            (Collar(**thin, eps_u=eps_u),),
            contact=MultibodyContact(cracked=True),
        )
        for eps_u in (0.15, 0.003)
    )
    s = breaks.summary()
    assert s["collar_fractured"] and s["collar_state"] == "fractured"
    hist = breaks.collar_histories[0]
    after = breaks.time >= s["collar_fracture_time"]
    assert 0 < after.sum() < after.size
    assert np.all(hist.axial_force[after] == 0.0) and np.all(hist.end_moment[after] == 0.0)
    assert s["collar_max_fibre_strain"] >= 0.003
    assert s["collar_ductility_demand"] == pytest.approx(
        s["collar_max_fibre_strain"] / hist.collar.yield_strain, rel=1e-12
    )
    assert s["energy_error_max"] < 1e-2
    kept = holds.summary()
    assert not kept["collar_fractured"] and kept["collar_fracture_time"] is None
    assert 1.0 < kept["collar_ductility_demand"] < 0.15 / hist.collar.yield_strain


@pytest.mark.chaotic
def test_the_multibody_history_has_the_fem_histories_collar_columns():
    """history.csv of the multibody model carries the FEM's collar columns (same frame element
    and law: fibre strain; for a plastic collar its plastic strain, end moments, rotations,
    hinge rotations and fracture flag), so a study's two histories read alike. The brittle
    collar that breaks in the multibody rocking test: the fracture flag is 0 before the
    reported fracture time and 1 from it, and the hinges turned before the break."""
    from colonna.core.ground import sine_pulse
    from colonna.rigid.block import Block
    from colonna.rigid.multibody import history_columns, rock_multibody

    collar = Collar(y=2.0, t=0.002, h=0.02, plastic=True, section="resultant", eps_u=0.003)
    half = Block(b=0.1125, h=2.0, mass=858.0)
    a_up = half.uplift_acceleration()
    result = rock_multibody(
        half,
        Motion(sine_pulse(3.0 * a_up, 3.0 * half.p, a_up), duration=2.0),
        (collar,),
        contact=MultibodyContact(cracked=True),
    )
    columns = history_columns(result)
    fem = _flung_up(
        Collar(y=1.0, t=0.004, h=0.03, plastic=True, section="resultant", eps_u=0.004)
    ).history
    assert {k for k in columns if k.startswith("collar_")} == {
        k for k in fem if k.startswith("collar_")
    }
    hist = result.collar_histories[0]
    broken = result.time >= result.summary()["collar_fracture_time"]
    assert np.all(columns["collar_1_fractured"][broken] == 1.0)
    assert np.all(columns["collar_1_fractured"][~broken] == 0.0)
    # it yields in bending (its axial plastic strain stays 0): the end hinges turn first
    assert np.array_equal(columns["collar_1_plastic_strain"], hist.plastic_strain)
    hinges = np.abs(columns["collar_1_hinge_rotation_left"]) + np.abs(
        columns["collar_1_hinge_rotation_right"]
    )
    assert hinges[~broken].max() > 0.0
    assert np.array_equal(columns["collar_1_fibre_strain"], hist.fibre_strain)
    band = Collar(y=2.0, t=0.008, h=0.06)
    gentle = sine_pulse(1.5 * a_up, 3.0 * half.p, a_up)
    elastic = rock_multibody(half, Motion(gentle), (band,), contact=MultibodyContact(cracked=True))
    assert {k for k in history_columns(elastic) if k.startswith("collar_")} == {
        f"collar_1_{name}"
        for name in ("axial_force", "moment", "stress", "utilisation", "fibre_strain")
    }

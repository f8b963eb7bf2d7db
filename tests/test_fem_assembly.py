"""Stone bodies: mass, gravity, rigid-body modes and the static gravity state."""

import numpy as np
import pytest
from scipy.sparse.linalg import spsolve

from colonna.fem.assembly import Stone, assemble, element_stress
from colonna.meshes.column import column_mesh

STONE = Stone(E=50e9, nu=0.2, density=2700.0)
W, H, T = 0.8, 4.0, 0.6


@pytest.fixture(scope="module")
def model():
    mesh = column_mesh(W, H, 0.1, cracked=True, grading=0.4)
    return mesh, assemble(mesh, STONE, T)


def test_mass_and_weight(model):
    mesh, a = model
    assert a.lumped_mass[0::2].sum() == pytest.approx(STONE.density * W * H * T, rel=1e-12)
    assert np.all(a.lumped_mass > 0)
    assert a.gravity[1::2].sum() == pytest.approx(-STONE.density * 9.81 * W * H * T, rel=1e-12)
    assert np.abs(a.gravity[0::2]).max() == 0.0


def test_rigid_body_modes_are_free(model):
    mesh, a = model
    x, y = mesh.points
    for body in range(mesh.n_bodies):
        on = mesh.node_body == body
        for mode in (
            np.vstack((on, 0 * on)),
            np.vstack((0 * on, on)),
            np.vstack((-y * on, x * on)),
        ):
            u = mode.T.ravel().astype(float)
            assert np.abs(a.stiffness @ u).max() <= 1e-9 * np.abs(a.stiffness).max()


def test_static_gravity_base_pressure(model):
    """On a roller base the column is in uniaxial compression sigma_yy = -rho g (H - y): the base
    reaction is the weight and the base pressure rho g H away from the corners (2 %)."""
    mesh, a = model
    n_dof = 2 * mesh.n_nodes
    fixed = []
    for base in mesh.base_nodes:
        fixed += list(2 * base + 1)  # vertical support
        fixed.append(2 * base[0])  # one horizontal support per body
    fixed = np.array(fixed)
    free = np.setdiff1d(np.arange(n_dof), fixed)
    u = np.zeros(n_dof)
    K = a.stiffness
    u[free] = spsolve(K[free][:, free].tocsc(), a.gravity[free])
    reaction = K @ u - a.gravity
    weight = STONE.density * 9.81 * W * H * T
    assert reaction[fixed].sum() == pytest.approx(weight, rel=1e-10)
    x = mesh.points[0]
    for base in mesh.base_nodes:
        xs = x[base]
        tributary = np.diff(np.concatenate(([xs[0]], 0.5 * (xs[1:] + xs[:-1]), [xs[-1]])))
        pressure = reaction[2 * base + 1] / (tributary * T)
        interior = slice(2, -2)
        np.testing.assert_allclose(pressure[interior], STONE.density * 9.81 * H, rtol=0.02)
    stress = element_stress(mesh, STONE, u)
    centres = mesh.points[:, mesh.cells].mean(axis=1)
    mid = np.abs(centres[1] - 0.5 * H) < 0.3
    np.testing.assert_allclose(
        stress[1, mid], -STONE.density * 9.81 * (H - centres[1, mid]), rtol=0.02
    )

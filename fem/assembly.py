"""Plane-stress elasticity of the stone bodies with scikit-fem: stiffness, lumped mass, gravity,
and element stresses.

Dofs are interleaved (node i owns dofs 2i and 2i + 1). Bodies share no nodes, so the stiffness
matrix is block diagonal over the bodies and the crack stays open to contact only.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import sparse
from skfem import Basis, BilinearForm, ElementQuad1, ElementVector, LinearForm, asm
from skfem.helpers import dot
from skfem.models.elasticity import linear_elasticity, plane_stress

from ..core.constants import STANDARD_GRAVITY
from ..core.errors import require_positive, require_range
from ..meshes.column import ColumnMesh


@dataclass(frozen=True)
class Stone:
    """Linear elastic stone: E (Pa), Poisson's ratio nu, density (kg/m^3), compressive strength
    fc (Pa). Defaults: a white marble (E 50 GPa, 2700 kg/m^3, f_c 110 MPa; the source paper
    cites f_c > 110 MPa and E > 30 GPa for low-porosity stones). The intact stone of a partial
    crack's mid-plane (issue 51, :mod:`colonna.fem.cohesive`): tensile strength ft (Pa),
    fracture energy Gf (N/m) and fracture toughness KIC (Pa sqrt(m)); marble defaults, ranges
    and sources in docs/physics.md ("The cohesive mid-plane")."""

    E: float = 50e9
    nu: float = 0.2
    density: float = 2700.0
    fc: float = 110e6
    ft: float = 8e6
    Gf: float = 40.0
    KIC: float = 1.0e6

    def __post_init__(self):
        # hard limits as in the study file's schema (studies.schema.Stone says why): past them
        # the stiffness or the mass overflows the stable-step estimate
        require_range("stone E (Pa)", self.E, 1e6, 1e14, closed_low=True, closed_high=True)
        require_range("stone nu", self.nu, 0.0, 0.5, closed_low=True)
        require_range(
            "stone density (kg/m^3)",
            self.density,
            100.0,
            30000.0,
            closed_low=True,
            closed_high=True,
        )
        require_positive("stone fc (Pa)", self.fc)
        require_positive("stone ft (Pa)", self.ft)
        require_range("stone Gf (N/m)", self.Gf, 0.1, 1e5, closed_high=True)
        require_range("stone KIC (Pa m^0.5)", self.KIC, 1e3, 1e8, closed_low=True, closed_high=True)

    @property
    def wave_speed(self) -> float:
        """Plane-stress dilatational wave speed sqrt(E / (rho (1 - nu^2))), m/s."""
        return float(np.sqrt(self.E / (self.density * (1.0 - self.nu**2))))


@dataclass
class Assembly:
    """Matrices of the stone bodies (per unit of nothing: thickness included)."""

    stiffness: sparse.csr_matrix  # N/m, (2n, 2n)
    lumped_mass: np.ndarray  # kg, (2n,) row sums of the consistent mass
    gravity: np.ndarray  # N, (2n,)
    basis: Basis


def basis_of(mesh: ColumnMesh) -> Basis:
    return Basis(mesh.to_skfem(), ElementVector(ElementQuad1()))


@BilinearForm
def _unit_mass(u, v, w):
    return dot(u, v)


@LinearForm
def _unit_downward(v, w):
    return -v[1]


def assemble(
    mesh: ColumnMesh, stone: Stone, thickness: float, g: float = STANDARD_GRAVITY
) -> Assembly:
    """Plane-stress stiffness, row-sum lumped mass and gravity load for out-of-plane thickness t."""
    require_positive("column thickness (m)", thickness)
    basis = basis_of(mesh)
    lam, mu = plane_stress(stone.E, stone.nu)
    stiffness = (asm(linear_elasticity(lam, mu), basis) * thickness).tocsr()
    consistent = asm(_unit_mass, basis) * (stone.density * thickness)
    lumped = np.asarray(consistent.sum(axis=1)).ravel()
    gravity = asm(_unit_downward, basis) * (stone.density * thickness * g)
    return Assembly(stiffness, lumped, gravity, basis)


def element_stress(mesh: ColumnMesh, stone: Stone, displacement: np.ndarray) -> np.ndarray:
    """Plane-stress (sigma_xx, sigma_yy, sigma_xy) at each element centre (Pa), shape (3, n_cells).

    ``displacement`` is the interleaved dof vector (small strain, in the body's own frame)."""
    p = mesh.points[:, mesh.cells]  # (2, 4, n_cells)
    u = displacement.reshape(-1, 2).T[:, mesh.cells]  # (2, 4, n_cells)
    # bilinear shape-function derivatives at the centre (xi = eta = 0)
    dN_dxi = np.array([-0.25, 0.25, 0.25, -0.25])
    dN_deta = np.array([-0.25, -0.25, 0.25, 0.25])
    J11, J12 = dN_dxi @ p[0], dN_dxi @ p[1]
    J21, J22 = dN_deta @ p[0], dN_deta @ p[1]
    det = J11 * J22 - J12 * J21
    dN_dx = (J22[None] * dN_dxi[:, None] - J12[None] * dN_deta[:, None]) / det
    dN_dy = (-J21[None] * dN_dxi[:, None] + J11[None] * dN_deta[:, None]) / det
    exx = np.einsum("ke,ke->e", dN_dx, u[0])
    eyy = np.einsum("ke,ke->e", dN_dy, u[1])
    gxy = np.einsum("ke,ke->e", dN_dy, u[0]) + np.einsum("ke,ke->e", dN_dx, u[1])
    factor = stone.E / (1.0 - stone.nu**2)
    return np.vstack(
        (
            factor * (exx + stone.nu * eyy),
            factor * (eyy + stone.nu * exx),
            stone.E / (2.0 * (1.0 + stone.nu)) * gxy,
        )
    )

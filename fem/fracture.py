"""The mode-I stress intensity at a crack tip from a linear-elastic solve: displacement correlation.

Near the tip of a mode-I crack the faces open by (Williams; Irwin)

    delta(r) = u_y(upper) - u_y(lower) = (8 K_I / E') sqrt(r / (2 pi)) + O(r^(3/2)),

r the distance behind the tip, E' = E / (1 - nu^2) in plane strain, E' = E in plane stress. So
each face node behind the tip gives an apparent stress intensity

    K*(r) = E' / 8 * sqrt(2 pi / r) * delta(r),

and K_I is K*(r) extrapolated linearly to r -> 0 over the near-tip nodes (displacement
correlation: Chan, Tuba & Wilson, Eng. Fract. Mech. 2 (1970) 1-17; Anderson, Fracture Mechanics,
3rd ed., 2005, section 12.1.2). The elements are plain bilinear quadrilaterals (no quarter-point
nodes): the extrapolation leaves out the nodes nearest the tip, whose opening the bilinear field
misses, and fits a line K*(r) = K_I + c r over r in [r_min, r_max].

The check against a closed form: a single-edge-cracked strip of width W, crack length a, under a
uniform tension sigma on its ends (:func:`edge_crack_stress_intensity`, Tada, Paris & Irwin).

>>> round(tada_edge_crack_factor(0.0), 3), round(tada_edge_crack_factor(0.5), 3)
(1.12, 2.826)
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..core.errors import InputError, require_positive, require_range
from ..meshes.crack_tip import CrackTipMesh, edge_crack_mesh

PLANES = ("strain", "stress")


def tada_edge_crack_factor(a_over_w: float) -> float:
    """F(a/W) = 1.12 - 0.231 (a/W) + 10.55 (a/W)^2 - 21.72 (a/W)^3 + 30.39 (a/W)^4 of a single
    edge crack in a strip under uniform end tension (Tada, Paris & Irwin, The Stress Analysis of
    Cracks Handbook, 3rd ed., 2000; from Brown & Srawley's boundary collocation): within 0.5 % for
    a/W <= 0.6."""
    s = require_range("crack length a / W", a_over_w, 0.0, 0.6, closed_low=True, closed_high=True)
    return 1.12 - 0.231 * s + 10.55 * s**2 - 21.72 * s**3 + 30.39 * s**4


def edge_crack_stress_intensity(sigma: float, a: float, width: float) -> float:
    """K_I = sigma sqrt(pi a) F(a/W) (Pa sqrt(m)) of the edge-cracked strip (Tada's F)."""
    return sigma * math.sqrt(math.pi * a) * tada_edge_crack_factor(a / width)


def effective_modulus(E: float, nu: float, plane: str = "strain") -> float:
    """E' = E / (1 - nu^2) in plane strain, E in plane stress (Pa)."""
    if plane not in PLANES:
        raise InputError(f"plane = {plane!r} is not allowed: one of {', '.join(PLANES)}")
    return E / (1.0 - nu**2) if plane == "strain" else E


def apparent_stress_intensity(r: np.ndarray, opening: np.ndarray, E_prime: float) -> np.ndarray:
    """K*(r) = E' / 8 * sqrt(2 pi / r) * delta(r) at each face node r > 0 behind the tip.

    >>> k = apparent_stress_intensity(np.array([1e-3]), np.array([8e-6]), 1e10)
    >>> round(float(k[0]) / 1e6, 3)  # 1e10 / 8 * sqrt(2 pi / 1e-3) * 8e-6 (MPa sqrt(m))
    0.793
    """
    r = np.asarray(r, dtype=float)
    return E_prime / 8.0 * np.sqrt(2.0 * math.pi / r) * np.asarray(opening, dtype=float)


def extrapolate_to_tip(
    r: np.ndarray, k_star: np.ndarray, r_min: float, r_max: float
) -> tuple[float, float]:
    """(K_I, c): the least-squares line K*(r) = K_I + c r over the nodes with r_min <= r <= r_max
    (at least two), its value at r = 0 and its slope.

    >>> K, c = extrapolate_to_tip(np.array([1.0, 2.0, 3.0]), np.array([5.0, 4.0, 3.0]), 0.5, 3.0)
    >>> round(K, 9), round(c, 9)
    (6.0, -1.0)
    """
    r, k_star = np.asarray(r, dtype=float), np.asarray(k_star, dtype=float)
    use = (r >= r_min) & (r <= r_max)
    if np.count_nonzero(use) < 2:
        raise InputError(
            f"displacement correlation window r in [{r_min:g}, {r_max:g}] m holds "
            f"{np.count_nonzero(use)} face node(s): at least 2 (widen it or refine the tip mesh)"
        )
    slope, intercept = np.polyfit(r[use], k_star[use], 1)
    return float(intercept), float(slope)


def face_jumps(
    points: np.ndarray,
    displacement: np.ndarray,
    face_a: np.ndarray,
    face_b: np.ndarray,
    tip: np.ndarray,
    normal: np.ndarray,
    ahead: np.ndarray,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(r, opening, sliding) at a crack's face node pairs, on any mesh with split face nodes
    (the column's partial crack as well as the strip): ``face_a`` / ``face_b`` paired node
    indices (2, n) columns of ``points`` and ``displacement``; ``tip`` the tip's coordinates;
    ``normal`` the unit normal from face a's body into face b's; ``ahead`` the unit vector from
    the crack into the ligament. r = (tip - x_a) . ahead, opening = (u_b - u_a) . normal (> 0
    open), sliding = (u_b - u_a) . ahead.

    >>> pts = np.array([[0.0, 0.0], [1.0, 1.0]])  # a vertical crack, one node pair at (0, 1)
    >>> u = np.array([[-1e-6, 2e-6], [0.0, 5e-7]])  # the right face (b) moves right and up
    >>> r, dn, ds = face_jumps(pts, u, np.array([0]), np.array([1]), np.array([0.0, 0.4]),
    ...                        normal=np.array([1.0, 0.0]), ahead=np.array([0.0, -1.0]))
    >>> r.tolist(), dn.tolist(), ds.tolist()  # a crack from the top down to y = 0.4
    ([0.6], [3e-06], [-5e-07])
    """
    points, u = np.asarray(points, dtype=float), np.asarray(displacement, dtype=float)
    n, t = np.asarray(normal, dtype=float), np.asarray(ahead, dtype=float)
    if not (math.isclose(n @ n, 1.0) and math.isclose(t @ t, 1.0) and abs(n @ t) < 1e-9):
        raise InputError(
            f"crack normal {n.tolist()} and direction ahead {t.tolist()} are not allowed: two "
            "orthogonal unit vectors"
        )
    jump = u[:, face_b] - u[:, face_a]
    r = (np.asarray(tip, dtype=float)[:, None] - points[:, face_a]).T @ t
    return r, n @ jump, t @ jump


def stress_intensities(
    r: np.ndarray,
    opening: np.ndarray,
    sliding: np.ndarray,
    E_prime: float,
    r_min: float,
    r_max: float,
) -> tuple[float, float]:
    """(K_I, K_II) by displacement correlation: K* = E' / 8 sqrt(2 pi / r) times the opening
    (mode I) or the sliding (mode II: delta_s = (8 K_II / E') sqrt(r / 2 pi) likewise),
    extrapolated to r = 0 over r_min <= r <= r_max. K_I < 0 means the faces press on each other
    at the tip (no mode-I intensity: the crack is closed there)."""
    K_I, _ = extrapolate_to_tip(r, apparent_stress_intensity(r, opening, E_prime), r_min, r_max)
    K_II, _ = extrapolate_to_tip(r, apparent_stress_intensity(r, sliding, E_prime), r_min, r_max)
    return K_I, K_II


@dataclass(frozen=True)
class CrackTipSolution:
    """A static solve of the edge-cracked strip: the face nodes' distance behind the tip r (m,
    nearest first), the crack opening delta(r) (m), K*(r) (Pa sqrt(m)), the extrapolated K_I
    (Pa sqrt(m)) and the closed form's (Tada), the mesh and the nodal displacements (2, n)."""

    r: np.ndarray
    opening: np.ndarray
    k_star: np.ndarray
    K_I: float
    K_closed_form: float
    mesh: CrackTipMesh
    displacement: np.ndarray

    @property
    def relative_error(self) -> float:
        """(K_I - K_closed_form) / K_closed_form."""
        return (self.K_I - self.K_closed_form) / self.K_closed_form


# the extrapolation window, in units of the tip element size h (nodes at r = h, 2h, ... behind
# the tip, then growing): the first node (r = h) is left out, the fit ends at a tenth of a
FIT_FROM_TIP_ELEMENTS = 4.0
FIT_TO_CRACK_FRACTION = 0.2


@dataclass(frozen=True)
class EdgeCrackStrip:
    """The single-edge-cracked strip of :func:`solve_edge_crack`: ``width`` W (m), crack length
    a (m, ``crack_length``, from one edge), uniform end tension ``sigma`` (Pa), the stone's
    ``E`` (Pa) and ``nu``, ``plane`` ("strain" or "stress") and the strip's ``half_height`` (m;
    None: 1.5 W, the strip 3 W tall; at least that, Tada's F(a/W) being for a long strip)."""

    width: float
    crack_length: float
    sigma: float
    E: float = 50e9
    nu: float = 0.2
    plane: str = "strain"
    half_height: float | None = None


def solve_edge_crack(
    strip: EdgeCrackStrip,
    *,
    tip_size: float | None = None,
    growth: float = 1.25,
    refine: int = 0,
    full: bool = False,
) -> CrackTipSolution:
    """Linear-elastic static solve of the single-edge-cracked ``strip`` under its uniform end
    tension, K_I by displacement correlation (module docstring). Half model (symmetry on the
    ligament: u_y = 0, the crack face free) or, with ``full``, the whole strip with the crack
    faces' nodes split. The mesh (:func:`colonna.meshes.crack_tip.edge_crack_mesh`, its
    ``tip_size``, ``growth`` and ``refine``) defaults to a tip element a / 50."""
    from skfem import Basis, ElementQuad1, ElementVector, asm, condense, solve
    from skfem.models.elasticity import lame_parameters, linear_elasticity, plane_stress

    width, crack_length, sigma = strip.width, strip.crack_length, strip.sigma
    E, nu, plane, half_height = strip.E, strip.nu, strip.plane, strip.half_height
    require_positive("strip width W (m)", width)
    require_positive("end tension sigma (Pa)", sigma)
    require_range("stone E (Pa)", E, 1e6, 1e14, closed_low=True, closed_high=True)
    require_range("stone nu", nu, 0.0, 0.5, closed_low=True)
    E_prime = effective_modulus(E, nu, plane)
    H = 1.5 * width if half_height is None else half_height
    if H < 1.5 * width * (1.0 - 1e-12):
        raise InputError(
            f"strip half-height = {H:g} m is not allowed: at least 1.5 W = {1.5 * width:g} m "
            "(Tada's F(a/W) is for a long strip)"
        )
    mesh = edge_crack_mesh(
        width, crack_length, H, tip_size=tip_size, growth=growth, refine=refine, full=full
    )
    sk = mesh.to_skfem()
    basis = Basis(sk, ElementVector(ElementQuad1()))
    lame = lame_parameters(E, nu) if plane == "strain" else plane_stress(E, nu)
    form = linear_elasticity(*lame)
    K = asm(form, basis)
    dofs = basis.nodal_dofs  # (2, n_nodes)

    f = np.zeros(K.shape[0])
    for edge_nodes, sign in ((mesh.top, 1.0), (mesh.bottom, -1.0)):
        if edge_nodes is None:
            continue
        xs = mesh.points[0, edge_nodes]
        order = np.argsort(xs)
        nodes, lengths = edge_nodes[order], np.diff(xs[order])
        # uniform traction on linear edges: half of each edge's force to each of its end nodes
        np.add.at(f, dofs[1, nodes[:-1]], sign * sigma * 0.5 * lengths)
        np.add.at(f, dofs[1, nodes[1:]], sign * sigma * 0.5 * lengths)

    corner = mesh.ligament[-1]  # (W, 0)
    if full:  # rigid motions only: the loads are self-equilibrated and symmetric about y = 0
        fixed = np.array([dofs[0, corner], dofs[1, corner], dofs[1, mesh.tip]])
    else:  # symmetry on the ligament, x held at one node
        fixed = np.concatenate([dofs[1, mesh.ligament], [dofs[0, corner]]])
    u = solve(*condense(K, f, D=fixed))
    uy = u[dofs[1]]

    upper = mesh.crack_upper
    if mesh.crack_lower is None:
        opening = 2.0 * uy[upper]
        r = crack_length - mesh.points[0, upper]
    else:
        r, opening, _ = face_jumps(
            mesh.points,
            u[dofs],
            mesh.crack_lower,
            upper,
            mesh.points[:, mesh.tip],
            normal=np.array([0.0, 1.0]),
            ahead=np.array([1.0, 0.0]),
        )
    k_star = apparent_stress_intensity(r, opening, E_prime)
    h = mesh.tip_element_size
    K_I, _ = extrapolate_to_tip(
        r, k_star, FIT_FROM_TIP_ELEMENTS * h * (1.0 - 1e-9), FIT_TO_CRACK_FRACTION * crack_length
    )
    return CrackTipSolution(
        r=r,
        opening=opening,
        k_star=k_star,
        K_I=K_I,
        K_closed_form=edge_crack_stress_intensity(sigma, crack_length, width),
        mesh=mesh,
        displacement=u[dofs],
    )


__all__ = [
    "CrackTipSolution",
    "EdgeCrackStrip",
    "face_jumps",
    "stress_intensities",
    "apparent_stress_intensity",
    "edge_crack_stress_intensity",
    "effective_modulus",
    "extrapolate_to_tip",
    "solve_edge_crack",
    "tada_edge_crack_factor",
]

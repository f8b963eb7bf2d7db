"""Steel collars joining the two half columns: stiffness, kinematics, forces and stress.

Each collar is a steel band of section ``t`` (radial thickness) x ``h`` (height) and length ``L``,
clamped to the two outer faces of the cracked column at height ``y``. In the rigid model it is an
axial spring and a lateral (shear) spring (paper Eq. 14-15)::

    K_a = E A / L,  A = t h          K_l = 12 E I / L^3,  I = t h^3 / 12

Kinematics. Both halves rotate by the same theta, each about its own active toe (derived in
``docs/theory.md``, section 6, Cracked column with collars; errata in its section 10). Taken
literally this makes the two crack faces interpenetrate by 2b (1 - cos theta), and that overlap is
exactly what would shorten the collar (the paper's Eq. 16-17): a kinematic artefact that steel's
large E A / L would turn into a large spurious force. Crack contact forbids the overlap, so the
halves separate by it and the crack faces stay in contact. From the exact end positions of that
admissible motion, in the frame of the rotated halves the right end is offset from the left one by
(4b, 2b sin theta), hence

    lateral offset    delta_l = 2b sin theta      (= paper Eq. 19, 4b tan(theta/2), to O(theta^3))
    axial elongation  delta_a = 4b (sqrt(1 + sin^2(theta) / 4) - 1)      (membrane stretching)

the same at every height: with equal rotations a collar's height changes only the lever arms of its
end forces, whose moments about the two pivots cancel pairwise. The restoring moment on the pair of
halves is -dU/dtheta, U = sum(K_a delta_a^2 + K_l delta_l^2) / 2, shared by the two half blocks
(total inertia 2 J0). Extreme-fibre stress, with the fixed-fixed end moment M = 6 E I delta_l / L^2
(corrected Eq. 22)::

    sigma = |N| / A + |M| / W,  N = pretension + K_a delta_a,  W = t h^2 / 6
"""

from __future__ import annotations

import math

import numpy as np
from scipy.optimize import brentq

from ..core.collar import Collar
from ..core.errors import require_range
from .block import Block


def validate_collars(collars, block: Block) -> tuple[Collar, ...]:
    """Check the collars against the column: each within its height, mass known."""
    collars = tuple(collars)
    if collars:
        block.require_mass("collar springs")
    for i, collar in enumerate(collars, start=1):
        require_range(
            f"collar {i} y (height, m)",
            collar.y,
            0.0,
            2.0 * block.h,
            closed_high=True,
            range_text=f"(0, {2.0 * block.h:g}] (the column height 2h)",
        )
    return collars


def collar_end_positions(theta, b: float, y: float):
    """Positions (x, y) of the collar's left and right ends on the two rotated half columns.

    The column spans x in [-2b, 2b] with the crack at x = 0. theta > 0 tips both halves toward +x,
    each about its right toe; theta < 0 toward -x about the left toes. The half that tips away
    from the other is moved out by 2b (1 - cos theta) along the crack-face normal, so that the
    crack faces touch instead of interpenetrating. Returns two arrays ``theta.shape + (2,)``.
    """
    return _half_points(theta, b, -2.0 * b, 2.0 * b, y)


def crack_face_overlap(theta, b: float, y: float = 0.0):
    """Interpenetration (m) of the crack faces at material height y, normal to the faces, for the
    motion of :func:`collar_end_positions` (zero: the faces just touch)."""
    left_face, right_face = _half_points(theta, b, 0.0, 0.0, y)
    gap = right_face - left_face
    theta = np.asarray(theta, dtype=float)
    return -(gap[..., 0] * np.cos(theta) - gap[..., 1] * np.sin(theta))


def _half_points(theta, b, x_left, x_right, y):
    """Material point x_left (x <= 0) of the left half and x_right (x >= 0) of the right half."""
    theta = np.asarray(theta, dtype=float)
    pos = theta > 0.0
    pivot_left = np.where(pos, 0.0, -2.0 * b)
    pivot_right = np.where(pos, 2.0 * b, 0.0)
    left = _rotate_about(theta, pivot_left, x_left, y)
    right = _rotate_about(theta, pivot_right, x_right, y)
    # separation along the face normal (1, 0) of the rotated halves: cos(theta), -sin(theta)
    shift = 2.0 * b * (1.0 - np.cos(theta))
    normal = np.stack((np.cos(theta), -np.sin(theta)), axis=-1)
    right = right + np.where(pos, shift, 0.0)[..., None] * normal
    left = left - np.where(pos, 0.0, shift)[..., None] * normal
    return left, right


def _rotate_about(theta, pivot_x, x, y):
    """Material point (x, y) of a body rotated clockwise by theta about (pivot_x, 0)."""
    dx = x - pivot_x
    c, s = np.cos(theta), np.sin(theta)
    return np.stack((pivot_x + dx * c + y * s, -dx * s + y * c), axis=-1)


def collar_deformation_from_positions(theta, b: float, y: float):
    """(delta_a, delta_l) from the exact end positions, co-rotational: chord length minus 4b, and
    the lateral offset 4b tan(phi), phi the end rotation relative to the chord."""
    theta = np.asarray(theta, dtype=float)
    left, right = collar_end_positions(theta, b, y)
    chord = right - left
    c, s = np.cos(theta), np.sin(theta)
    # chord in the frame of the rotated halves (undo the clockwise rotation)
    along = chord[..., 0] * c - chord[..., 1] * s
    across = chord[..., 0] * s + chord[..., 1] * c
    return np.hypot(along, across) - 4.0 * b, 4.0 * b * across / along


def collar_deformation(theta, b: float):
    """Closed form of :func:`collar_deformation_from_positions`:
    delta_a = 4b (sqrt(1 + sin^2(theta)/4) - 1), delta_l = 2b sin(theta)."""
    s = np.sin(np.asarray(theta, dtype=float))
    return 4.0 * b * (np.sqrt(1.0 + 0.25 * s * s) - 1.0), 2.0 * b * s


def total_stiffness(collars, b: float) -> tuple[float, float]:
    """Summed axial and lateral spring stiffness of the collars (N/m)."""
    return (
        sum(c.axial_stiffness(b) for c in collars),
        sum(c.lateral_stiffness(b) for c in collars),
    )


def collar_strain_energy(theta, b: float, collars) -> np.ndarray:
    """U(theta) = sum(K_a delta_a^2 + K_l delta_l^2) / 2, J (pretension excluded: it is balanced
    by crack-face contact and does no work under equal rotations)."""
    delta_a, delta_l = collar_deformation(theta, b)
    ka, kl = total_stiffness(collars, b)
    return 0.5 * (ka * delta_a**2 + kl * delta_l**2)


def collar_restoring_moment(theta, b: float, collars) -> np.ndarray:
    """Generalised moment -dU/dtheta on the pair of half columns (N m), exact geometry."""
    theta = np.asarray(theta, dtype=float)
    s, c = np.sin(theta), np.cos(theta)
    root = np.sqrt(1.0 + 0.25 * s * s)
    ka, kl = total_stiffness(collars, b)
    delta_a = 4.0 * b * (root - 1.0)
    return -(ka * delta_a * b * s * c / root + kl * 2.0 * b * s * 2.0 * b * c)


def collar_response(theta, b: float, collar: Collar) -> dict:
    """Axial force N (N, tension +), lateral force V (N), end moment M (N m), extreme-fibre
    stress (Pa) and utilisation sigma / f_y of one collar for rotations ``theta``."""
    delta_a, delta_l = collar_deformation(theta, b)
    axial = collar.pretension + collar.axial_stiffness(b) * delta_a
    lateral = collar.lateral_stiffness(b) * delta_l
    moment = 6.0 * collar.E * collar.second_moment * delta_l / collar.span(b) ** 2
    stress = np.abs(axial) / collar.area + np.abs(moment) / collar.section_modulus
    return {
        "axial_force": axial,
        "lateral_force": lateral,
        "end_moment": moment,
        "stress": stress,
        "utilisation": stress / collar.fy,
    }


def collar_yield_rotation(collar: Collar, b: float) -> float:
    """Smallest |theta| (rad) at which the collar's extreme-fibre stress reaches f_y; inf if it
    does not before pi/2. The stress grows monotonically with |theta| on [0, pi/2]."""

    def excess(theta):
        return float(collar_response(theta, b, collar)["utilisation"]) - 1.0

    if excess(0.0) >= 0.0:
        return 0.0
    if excess(0.5 * math.pi) < 0.0:
        return math.inf
    return brentq(excess, 0.0, 0.5 * math.pi, xtol=1e-14)


def collar_kernel_constants(block: Block, collars) -> tuple[float, float]:
    """(k_a, k_l) used by the solver kernels, k = 4 b^2 sum(K) / J0: with r = sqrt(1 + sin^2/4),
    collar moment / (2 J0) = -k_a (r - 1) sin cos / (2 r) - k_l sin cos / 2 (sin, cos of theta)."""
    if not collars:
        return 0.0, 0.0
    b, j0 = block.b, block.J0
    ka, kl = total_stiffness(collars, b)
    return 4.0 * b * b * ka / j0, 4.0 * b * b * kl / j0

"""Steel collars joining the two half columns: stiffness, kinematics, forces and stress.

Each collar is a steel band of section ``t`` (radial thickness) x ``h`` (height) and length ``L``,
clamped to the two outer faces of the cracked column at height ``y``. In the rigid model it is an
axial spring and a lateral (shear) spring (paper Eq. 14-15)::

    K_a = E A / L,  A = t h          K_l = 12 E I / L^3,  I = t h^3 / 12

Kinematics (both halves rotate by the same theta, each about its own active toe, DESIGN.md): the
collar ends lie on the two outer faces, 4b apart. From their exact positions the chord shortens to
``4b cos(theta/2)`` and turns by ``theta/2`` while the clamped ends turn by ``theta``, so

    axial elongation  delta_a = 4b (cos(theta/2) - 1)          (compression)
    lateral offset    delta_l = 4b tan(theta/2)                (paper Eq. 19)

the same at every height: with equal rotations the height of a collar changes only the lever arms,
whose moments about the two pivots cancel pairwise. The restoring moment on the pair of halves is
the derivative of the collar strain energy U = sum(K_a delta_a^2 + K_l delta_l^2) / 2, and it is
shared by the two half blocks (total inertia 2 J0). Extreme-fibre stress, from the fixed-fixed end
moment M = 6 E I delta_l / L^2 (corrected Eq. 22)::

    sigma = |N| / A + |M| / W,  N = pretension + K_a delta_a,  W = t h^2 / 6
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from .block import Block
from .validation import InputError, require_non_negative, require_positive, require_range

STEEL_E = 206e9      # Pa
STEEL_FY = 235e6     # Pa


@dataclass(frozen=True)
class Collar:
    """One steel collar. Lengths in m, E and fy in Pa, pretension in N (tension positive).

    ``length=None`` means the distance between the attachment points, 4b (the full column width).

    >>> c = Collar(y=1.0, t=0.01, h=0.05, length=0.8)
    >>> round(c.axial_stiffness() / 1e6, 3)      # E t h / L = 206e9 * 5e-4 / 0.8, in MN/m
    128.75
    """

    y: float
    t: float
    h: float
    length: float | None = None
    E: float = STEEL_E
    fy: float = STEEL_FY
    pretension: float = 0.0

    def __post_init__(self):
        require_positive("collar y (height, m)", self.y)
        require_positive("collar t (section thickness, m)", self.t)
        require_positive("collar h (section height, m)", self.h)
        if self.length is not None:
            require_positive("collar length (m)", self.length)
        require_positive("collar E (Pa)", self.E)
        require_positive("collar fy (Pa)", self.fy)
        require_non_negative("collar pretension (N)", self.pretension)

    @property
    def area(self) -> float:
        return self.t * self.h

    @property
    def second_moment(self) -> float:
        """I = t h^3 / 12: bending in the plane of the column (m^4)."""
        return self.t * self.h ** 3 / 12.0

    @property
    def section_modulus(self) -> float:
        return self.t * self.h ** 2 / 6.0

    @property
    def yield_moment(self) -> float:
        """M_y = f_y t h^2 / 6 (N m)."""
        return self.fy * self.section_modulus

    def span(self, b: float | None = None) -> float:
        if self.length is not None:
            return self.length
        if b is None:
            raise InputError("collar length is not set and the column width is unknown")
        return 4.0 * b

    def axial_stiffness(self, b: float | None = None) -> float:
        """K_a = E A / L (N/m), paper Eq. 14."""
        return self.E * self.area / self.span(b)

    def lateral_stiffness(self, b: float | None = None) -> float:
        """K_l = 12 E I / L^3 (N/m), paper Eq. 15."""
        return 12.0 * self.E * self.second_moment / self.span(b) ** 3

    def yield_displacement(self, b: float | None = None) -> float:
        """Lateral end offset at first yield, d_y = M_y L^2 / (6 E I) (corrected Eq. 22), m."""
        return self.yield_moment * self.span(b) ** 2 / (6.0 * self.E * self.second_moment)


def validate_collars(collars, block: Block) -> tuple[Collar, ...]:
    """Check the collars against the column: each within its height, mass known."""
    collars = tuple(collars)
    if collars:
        block.require_mass("collar springs")
    for i, collar in enumerate(collars, start=1):
        require_range(f"collar {i} y (height, m)", collar.y, 0.0, 2.0 * block.h, closed_high=True,
                      range_text=f"(0, {2.0 * block.h:g}] (the column height 2h)")
    return collars


def read_collars(path) -> tuple[Collar, ...]:
    """Read ``[[collar]]`` tables (keys y, t, h, length, E, fy, pretension) from a TOML file."""
    path = Path(path)
    try:
        data = tomllib.loads(path.read_text())
    except OSError as exc:
        raise InputError(f"collar file {path} cannot be read: {exc.strerror}") from None
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"collar file {path} is not valid TOML: {exc}") from None
    return collars_from_tables(data.get("collar", []), source=str(path))


COLLAR_KEYS = ("y", "t", "h", "length", "E", "fy", "pretension")


def collars_from_tables(tables, source: str = "collar") -> tuple[Collar, ...]:
    collars = []
    for i, table in enumerate(tables, start=1):
        unknown = sorted(set(table) - set(COLLAR_KEYS))
        if unknown:
            raise InputError(f"{source}: collar {i} has unknown key {unknown[0]!r} "
                             f"(allowed: {', '.join(COLLAR_KEYS)})")
        missing = [k for k in ("y", "t", "h") if k not in table]
        if missing:
            raise InputError(f"{source}: collar {i} lacks the key {missing[0]!r}")
        collars.append(Collar(**table))
    return tuple(collars)


def with_default_length(collars, b: float) -> tuple[Collar, ...]:
    return tuple(c if c.length is not None else replace(c, length=4.0 * b) for c in collars)


# --- kinematics -------------------------------------------------------------------------------

def collar_end_positions(theta, b: float, y: float):
    """Positions (x, y) of the collar's left and right ends on the two rotated half columns.

    The column spans x in [-2b, 2b] with the crack at x = 0. theta > 0 tips both halves toward +x,
    each about its right toe; theta < 0 toward -x about the left toes. Returns two arrays of shape
    ``theta.shape + (2,)``.
    """
    theta = np.asarray(theta, dtype=float)
    pos = theta > 0.0
    # active pivots of the left and right half
    pivot_left = np.where(pos, 0.0, -2.0 * b)
    pivot_right = np.where(pos, 2.0 * b, 0.0)
    left = _rotate_about(theta, pivot_left, -2.0 * b, y)
    right = _rotate_about(theta, pivot_right, 2.0 * b, y)
    return left, right


def _rotate_about(theta, pivot_x, x, y):
    """Material point (x, y) of a body rotated clockwise by theta about (pivot_x, 0)."""
    dx = x - pivot_x
    c, s = np.cos(theta), np.sin(theta)
    return np.stack((pivot_x + dx * c + y * s, -dx * s + y * c), axis=-1)


def collar_deformation_from_positions(theta, b: float, y: float):
    """(delta_a, delta_l) from the exact end positions: chord length change, and the lateral
    offset 4b tan(phi) where phi is the end rotation relative to the chord."""
    left, right = collar_end_positions(theta, b, y)
    chord = right - left
    length = np.hypot(chord[..., 0], chord[..., 1])
    chord_angle = np.arctan2(-chord[..., 1], chord[..., 0])   # clockwise, like theta
    relative_rotation = np.asarray(theta) - chord_angle
    return length - 4.0 * b, 4.0 * b * np.tan(relative_rotation)


def collar_deformation(theta, b: float):
    """Closed form of :func:`collar_deformation_from_positions`: 4b(cos(theta/2)-1), 4b tan(theta/2)."""
    half = 0.5 * np.asarray(theta, dtype=float)
    return 4.0 * b * (np.cos(half) - 1.0), 4.0 * b * np.tan(half)


def collar_strain_energy(theta, b: float, collars) -> np.ndarray:
    """U(theta) = sum(K_a delta_a^2 + K_l delta_l^2) / 2, J (pretension excluded: it is carried by
    crack-face contact and does no work under equal rotations)."""
    delta_a, delta_l = collar_deformation(theta, b)
    ka = sum(c.axial_stiffness(b) for c in collars)
    kl = sum(c.lateral_stiffness(b) for c in collars)
    return 0.5 * (ka * delta_a ** 2 + kl * delta_l ** 2)


def collar_restoring_moment(theta, b: float, collars) -> np.ndarray:
    """Generalised moment -dU/dtheta on the pair of half columns (N m), exact geometry."""
    theta = np.asarray(theta, dtype=float)
    half = 0.5 * theta
    ka = sum(c.axial_stiffness(b) for c in collars)
    kl = sum(c.lateral_stiffness(b) for c in collars)
    return 8.0 * b * b * (ka * (np.cos(half) - 1.0) * np.sin(half)
                          - kl * np.tan(half) / np.cos(half) ** 2)


def collar_response(theta, b: float, collar: Collar) -> dict:
    """Axial force N (N, tension +), lateral force V (N), end moment M (N m), extreme-fibre
    stress (Pa) and utilisation sigma / f_y of one collar for rotations ``theta``."""
    delta_a, delta_l = collar_deformation(theta, b)
    axial = collar.pretension + collar.axial_stiffness(b) * delta_a
    lateral = collar.lateral_stiffness(b) * delta_l
    moment = 6.0 * collar.E * collar.second_moment * delta_l / collar.span(b) ** 2
    stress = np.abs(axial) / collar.area + np.abs(moment) / collar.section_modulus
    return {"axial_force": axial, "lateral_force": lateral, "end_moment": moment,
            "stress": stress, "utilisation": stress / collar.fy}


def collar_kernel_constants(block: Block, collars) -> tuple[float, float]:
    """(k_a, k_l) used by the solver kernels: collar moment / (2 J0) =
    k_a (cos(theta/2)-1) sin(theta/2) - k_l tan(theta/2)/cos^2(theta/2), k = 4 b^2 sum(K) / J0."""
    if not collars:
        return 0.0, 0.0
    b, j0 = block.b, block.J0
    ka = sum(c.axial_stiffness(b) for c in collars)
    kl = sum(c.lateral_stiffness(b) for c in collars)
    return 4.0 * b * b * ka / j0, 4.0 * b * b * kl / j0



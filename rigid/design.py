"""Simplified collar design (paper section 5, with Eq. 22 and 24 corrected).

For a collar of section t_c x h_c and length L (the same L as in K_l = 12 E I / L^3):

    M_y   = f_y t_c h_c^2 / 6                                   yield moment
    d_y   = M_y L^2 / (6 E I_c) = f_y L^2 / (3 E h_c)           yield lateral offset   (Eq. 22)
    th_y  = 2 atan(d_y / (4 b))                                 yield rotation         (Eq. 23)

Under a long (quasi-static) pulse of peak a_g the column must be held at th_y by the collars:

    m a_g R cos(alpha - th_y) = m g R sin(alpha - th_y) + k d_y 2b                     (Eq. 24)

with R, alpha, b of the half block and m the mass the collars hold: both half columns (the
collars' restoring moment is shared by the two halves, see :mod:`rigid.collars`). The printed
Eq. 22 (4b)^3 / (12 E I) is not dimensionally consistent and the printed Eq. 24 drops R in the
gravity term. Solving for k gives the minimum total lateral collar stiffness; the axial springs
and the 1/cos^2(th_y/2) factor of the exact kinematics are neglected, as in the paper.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np

from ..core.constants import STANDARD_GRAVITY
from ..core.errors import require_non_negative
from .block import Block
from .collars import Collar


@dataclass(frozen=True)
class CollarDesign:
    yield_moment: float  # N m
    yield_displacement: float  # m, d_y
    yield_rotation: float  # rad, theta_y
    required_stiffness: float  # N/m, total lateral stiffness k (<= 0: no collar needed)
    collar_lateral_stiffness: float  # N/m, K_l of one collar
    collars_needed: int
    design_acceleration: float  # m/s^2
    column_mass: float  # kg, both halves
    yield_rotation_over_alpha: float

    def to_dict(self) -> dict:
        return asdict(self)


def yield_displacement(collar: Collar, b: float) -> float:
    """d_y = M_y L^2 / (6 E I_c) (corrected Eq. 22), m."""
    return collar.yield_displacement(b)


def yield_rotation(collar: Collar, b: float) -> float:
    """theta_y = 2 atan(d_y / 4b) (Eq. 23), rad."""
    return 2.0 * math.atan(yield_displacement(collar, b) / (4.0 * b))


def required_stiffness(block: Block, design_acceleration, d_y, theta_y):
    """Minimum total lateral collar stiffness k from corrected Eq. 24 (N/m); vectorised.

    ``block`` is one half column; the mass held is 2 * block.mass.
    """
    m = 2.0 * block.require_mass("the collar design")
    a = block.alpha
    return (
        m
        * block.R
        * (np.asarray(design_acceleration) * np.cos(a - theta_y) - block.g * np.sin(a - theta_y))
        / (2.0 * block.b * d_y)
    )


def design_collars(block: Block, collar: Collar, design_acceleration: float) -> CollarDesign:
    """Yield displacement, yield rotation, minimum stiffness and number of collars of this
    section needed for a design pulse of peak ``design_acceleration`` (m/s^2)."""
    require_non_negative("design acceleration a_g (m/s^2)", design_acceleration)
    d_y = yield_displacement(collar, block.b)
    th_y = yield_rotation(collar, block.b)
    k = float(required_stiffness(block, design_acceleration, d_y, th_y))
    k_one = collar.lateral_stiffness(block.b)
    needed = 0 if k <= 0.0 else math.ceil(k / k_one)
    return CollarDesign(
        collar.yield_moment,
        d_y,
        th_y,
        k,
        k_one,
        needed,
        float(design_acceleration),
        2.0 * block.require_mass("the collar design"),
        th_y / block.alpha,
    )


def design_chart(
    b: float,
    density: float,
    thickness: float,
    collar: Collar,
    alphas,
    acceleration_ratios,
    g: float = STANDARD_GRAVITY,
) -> np.ndarray:
    """Minimum stiffness k (N/m) over slenderness alpha (rows) and a_g / g (columns): the
    paper's Fig. 8 with the corrected equations. Half width b is fixed; h = b / tan(alpha).
    Non-positive values mean no collar is needed."""
    alphas = np.asarray(alphas, dtype=float)
    ratios = np.asarray(acceleration_ratios, dtype=float)
    k = np.empty((alphas.size, ratios.size))
    d_y = yield_displacement(collar, b)
    th_y = yield_rotation(collar, b)
    for i, alpha in enumerate(alphas):
        block = Block.from_density(b, b / math.tan(alpha), density, thickness, g=g)
        k[i] = required_stiffness(block, ratios * g, d_y, th_y)
    return k


# --- beyond first yield: the thinnest band that holds, from the multibody model --------------

FLAT_BAR_THICKNESSES = (0.003, 0.004, 0.005, 0.006, 0.008, 0.01, 0.012, 0.015, 0.02, 0.025, 0.03)
"""m: the flat-bar thicknesses the ductile design tries (the usual hot-rolled range, EN 10058)."""


def collar_trial(summary: dict, ductility_limit: float) -> dict:
    """One band thickness's outcome from a multibody summary with plastic collars, and the
    two design answers for the collars (the column's own fate is reported beside them: a pulse
    that overturns the whole column overturns it whatever ties its halves):
    ``never_yields`` (no fibre reaches f_y) and ``holds`` (no collar breaks and the ductility
    demand, largest fibre strain / yield strain, stays within ``ductility_limit``), both over
    the run, up to the overturning where the column overturns."""
    demand = summary.get("collar_ductility_demand") or 0.0
    broken = bool(summary.get("collar_fractured"))
    return {
        "overturned": bool(summary["overturned"]),
        "collar_max_utilisation": summary.get("collar_max_utilisation"),
        "collar_ductility_demand": demand,
        "collar_fractured": broken,
        "collar_fracture_time": summary.get("collar_fracture_time"),
        "collar_plastic_work": summary.get("collar_plastic_work"),
        "never_yields": summary.get("collar_max_utilisation", 0.0) < 1.0,
        "holds": not broken and demand <= ductility_limit,
    }


def thinnest_passing(thicknesses, passes) -> float | None:
    """The smallest thickness from which every thicker one tried also passes (a rocking
    response need not be monotone in the band's thickness: a thin band that passes between
    two that fail is not a design); None if the thickest fails."""
    order = np.argsort(thicknesses)
    best = None
    for k in order[::-1]:
        if not passes[k]:
            break
        best = float(thicknesses[k])
    return best

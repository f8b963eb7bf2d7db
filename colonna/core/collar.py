"""The description of a steel collar: its band section, its steel and its axial law's data.

Plain data shared by the rigid models (springs K_a = E A / L, K_l = 12 E I / L^3, paper Eq. 14-15)
and the FEM (a frame element between the two outer faces). The length convention (``None``: the
column's full width 4b) is resolved by the model that places the collar.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .constants import STEEL_E, STEEL_FY
from .errors import InputError, require_non_negative, require_positive, require_range


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
    plastic: bool = False  # bilinear in tension and compression (FEM and multibody)
    Eh: float | None = None  # Pa, hardening (tangent) modulus past f_y; default 1 % of E

    def __post_init__(self):
        require_positive("collar y (height, m)", self.y)
        require_positive("collar t (section thickness, m)", self.t)
        require_positive("collar h (section height, m)", self.h)
        if self.length is not None:
            require_positive("collar length (m)", self.length)
        require_positive("collar E (Pa)", self.E)
        require_positive("collar fy (Pa)", self.fy)
        require_non_negative("collar pretension (N)", self.pretension)
        if not isinstance(self.plastic, bool):
            raise InputError(f"collar plastic = {self.plastic!r} must be true or false")
        if self.Eh is not None:
            require_range(
                "collar Eh (hardening modulus, Pa)",
                self.Eh,
                0.0,
                self.E,
                closed_low=True,
                range_text=f"[0, E = {self.E:g})",
            )

    @property
    def hardening_modulus(self) -> float:
        """E_h (Pa): the slope of stress against strain past f_y (default 0.01 E)."""
        return 0.01 * self.E if self.Eh is None else self.Eh

    @property
    def plastic_modulus(self) -> float:
        """H = E E_h / (E - E_h) (Pa): the slope of stress against *plastic* strain."""
        eh = self.hardening_modulus
        return self.E * eh / (self.E - eh)

    @property
    def area(self) -> float:
        return self.t * self.h

    @property
    def second_moment(self) -> float:
        """I = t h^3 / 12: bending in the plane of the column (m^4)."""
        return self.t * self.h**3 / 12.0

    @property
    def section_modulus(self) -> float:
        return self.t * self.h**2 / 6.0

    @property
    def plastic_moment(self) -> float:
        """M_p = f_y t h^2 / 4 (N m): the rectangle's full plastic moment (shape factor 1.5)."""
        return self.fy * self.t * self.h**2 / 4.0

    def fibre_stress(self, axial, moment, alpha=0.0):
        """Extreme-fibre stress (Pa) under axial force N (N) and end moment M (N m), scalars or
        arrays: the elastic |N|/A + |M|/W, capped for a plastic collar at f_y + H alpha, the
        stress its outer fibres carry once they yield (alpha: accumulated plastic strain)."""
        stress = np.abs(axial) / self.area + np.abs(moment) / self.section_modulus
        if self.plastic:
            stress = np.minimum(stress, self.fy + self.plastic_modulus * np.asarray(alpha))
        return stress if np.ndim(stress) else float(stress)

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

"""The description of a steel collar: its band section, its steel and its axial law's data.

Plain data shared by the rigid models (springs K_a = E A / L, K_l = 12 E I / L^3, paper Eq. 14-15)
and the FEM (a frame element between the two outer faces). The length convention (``None``: the
column's full width 4b) is resolved by the model that places the collar.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .constants import STEEL_E, STEEL_EPS_U, STEEL_FY
from .errors import InputError, require_non_negative, require_positive, require_range

# Hard limits of a collar's numbers, as in the study file's schema (studies.schema.Collar, whose
# descriptions say why): past them a model's stiffness overflows or its mesh degenerates.
LOWEST = 1e-3  # m: the lowest collar (a row of nodes at it; nearer, an element of no height)
THICKEST = 1.0  # m: the largest section thickness t and height h
SPAN = (1e-3, 100.0)  # m: the shortest and longest span L (E A / L overflows below)
STIFFEST = 1e14  # Pa: the largest E (100 times diamond's)
MAX_FIBRES = 200  # layers of a fibre section (past it the cost grows, not the accuracy)
STEELS = ("bilinear", "menegotto-pinto")  # the fibres' uniaxial laws (colonna.core.fibre)
MAX_SECTIONS = 30  # Gauss-Lobatto sections of a fibre collar (colonna.core.fibre's tables)


def _require_count(name: str, value, low: int, high: int) -> int:
    """An integer in [low, high], or an InputError naming the field and the range."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise InputError(f"{name} = {value!r} must be an integer in [{low}, {high}]")
    if not low <= value <= high:
        raise InputError(f"{name} = {value} is not allowed: it must be in [{low}, {high}]")
    return int(value)


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
    eps_u: float = STEEL_EPS_U  # fracture strain of a plastic collar's extreme fibre
    hinge_length: float | None = None  # m, length of an end hinge's plastic zone; default h
    # the plastic collar's local law: "fibre" (default: colonna.core.fibre) or "resultant"
    section: str | None = None
    n_fibres: int = 20  # layers across the depth h (fibre section), 2 .. MAX_FIBRES
    n_sections: int = 10  # Gauss-Lobatto sections along the span (fibre section), 2 .. 30
    steel: str = "bilinear"  # the fibres' law: "bilinear" (E, fy, Eh) or "menegotto-pinto"
    isotropic: float = 0.0  # bilinear: share of the hardening that is isotropic (0: kinematic)
    # menegotto-pinto (OpenSees Steel02): the curvature R0 and its decay cR1, cR2; isotropic
    # hardening a1, a2 (compression), a3, a4 (tension), 0 (none) by default
    R0: float = 20.0
    cR1: float = 0.925
    cR2: float = 0.15
    a1: float = 0.0
    a2: float = 1.0
    a3: float = 0.0
    a4: float = 1.0

    def __post_init__(self):
        require_range("collar y (height, m)", self.y, LOWEST, math.inf, closed_low=True)
        require_range("collar t (section thickness, m)", self.t, 0.0, THICKEST, closed_high=True)
        require_range("collar h (section height, m)", self.h, 0.0, THICKEST, closed_high=True)
        if self.length is not None:
            require_range(
                "collar length (m)", self.length, *SPAN, closed_low=True, closed_high=True
            )
        require_range("collar E (Pa)", self.E, 0.0, STIFFEST, closed_high=True)
        require_positive("collar fy (Pa)", self.fy)
        require_non_negative("collar pretension (N)", self.pretension)
        if self.pretension > self.fy * self.area:
            raise InputError(
                f"collar pretension = {self.pretension:g} N must be at most the yield force "
                f"fy t h = {self.fy * self.area:.4g} N (past it the band has yielded)"
            )
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
        require_range("collar eps_u (ultimate strain)", self.eps_u, 0.0, 1.0, closed_high=True)
        if self.plastic and self.eps_u <= self.fy / self.E:
            raise InputError(
                f"collar eps_u = {self.eps_u:g} must be above the yield strain "
                f"fy / E = {self.fy / self.E:.3g} (a plastic collar yields before it breaks)"
            )
        if self.hinge_length is not None:
            require_positive("collar hinge_length (m)", self.hinge_length)
        if self.section not in (None, "fibre", "resultant"):
            raise InputError(f"collar section = {self.section!r} must be 'fibre' or 'resultant'")
        if self.section == "fibre" and not self.plastic:
            raise InputError(
                "collar section = 'fibre' needs plastic = true (an elastic collar's resultant "
                "law is exact)"
            )
        _require_count("collar n_fibres", self.n_fibres, 2, MAX_FIBRES)
        _require_count("collar n_sections", self.n_sections, 2, MAX_SECTIONS)
        if self.steel not in STEELS:
            raise InputError(
                f"collar steel = {self.steel!r} must be one of {', '.join(map(repr, STEELS))}"
            )
        require_range(
            "collar isotropic (share of isotropic hardening)",
            self.isotropic,
            0.0,
            1.0,
            closed_low=True,
            closed_high=True,
        )
        if self.steel == "menegotto-pinto":
            if self.isotropic != 0.0:
                raise InputError(
                    "collar isotropic applies to the bilinear steel: the Menegotto-Pinto "
                    "steel's isotropic hardening is a1 .. a4"
                )
            if self.hardening_modulus <= 0.0:
                raise InputError(
                    "collar Eh must be > 0 for the Menegotto-Pinto steel (its b = Eh / E)"
                )

        require_range("collar R0 (Menegotto-Pinto curvature)", self.R0, 1.0, 100.0,
                      closed_low=True, closed_high=True)  # fmt: skip
        require_range("collar cR1", self.cR1, 0.0, 1.0, closed_low=True)
        require_positive("collar cR2", self.cR2)
        require_non_negative("collar a1", self.a1)
        require_positive("collar a2", self.a2)
        require_non_negative("collar a3", self.a3)
        require_positive("collar a4", self.a4)

    @property
    def local_law(self) -> str:
        """The law the models step: "fibre" (a plastic collar's default), or "resultant"
        (an elastic collar's, exact; a plastic one's where ``section = "resultant"``)."""
        if not self.plastic:
            return "resultant"
        return "fibre" if self.section is None else self.section

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
    def yield_strain(self) -> float:
        """eps_y = f_y / E."""
        return self.fy / self.E

    @property
    def plastic_hinge_length(self) -> float:
        """L_p (m): the length over which an end hinge's plastic rotation is spread to give a
        fibre strain; default the band's depth h (the usual lumped-plasticity estimate for a
        steel member, of the order of its depth)."""
        return self.h if self.hinge_length is None else self.hinge_length

    def law(self) -> tuple:
        """The frame element's law row (colonna.core.collar_law.LAW_SIZE numbers): N_y = f_y A,
        E A, H A, M_p, 1 / (E W), h / (2 L_p), eps_u; the yield and fracture entries are 0 for
        an elastic collar (it never yields nor breaks: its stress past f_y is reported as
        such)."""
        from .collar_law import FIBRE, LAW_SIZE, RESULTANT  # numba: on first use

        plastic = self.plastic
        resultant = (
            self.fy * self.area if plastic else 0.0,
            self.E * self.area,
            self.plastic_modulus * self.area,
            self.plastic_moment if plastic else 0.0,
            1.0 / (self.E * self.section_modulus),
            self.h / (2.0 * self.plastic_hinge_length),
            self.eps_u if plastic else 0.0,
        )
        if self.local_law != "fibre":
            return resultant + (float(RESULTANT),) + (0.0,) * (LAW_SIZE - len(resultant) - 1)
        h = self.plastic_modulus
        mp = self.steel == "menegotto-pinto"
        fibre: tuple[float, ...] = (
            float(FIBRE),
            float(self.n_sections),
            float(self.n_fibres),
            self.E,
            self.fy,
            self.hardening_modulus if mp else (1.0 - self.isotropic) * h,
            0.0 if mp else self.isotropic * h,
            self.h,
            self.t,
            float(STEELS.index(self.steel)),
        )
        if mp:
            fibre += (self.R0, self.cR1, self.cR2, self.a1, self.a2, self.a3, self.a4)
        return resultant + fibre + (0.0,) * (LAW_SIZE - len(resultant) - len(fibre))

    def state_size(self) -> int:
        """Numbers in this collar's state row (colonna.core.collar_law.law_state_size)."""
        from .collar_law import law_state_size

        return law_state_size(self.law())

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


def collar_strain_summary(collars, largest_strains, fracture_times) -> dict:
    """The collars' largest extreme-fibre strain, ductility demand (a collar's largest strain
    over its f_y / E, the most of them) and whether and when the first one fractured, from
    each collar's largest fibre strain and fracture time (None: it holds). The FEM and the
    multibody summaries both give these."""
    demands = [e / c.yield_strain for c, e in zip(collars, largest_strains)]
    broken = [t for t in fracture_times if t is not None]
    return {
        "collar_max_fibre_strain": float(max(largest_strains)),
        "collar_ductility_demand": float(max(demands)),
        "collar_fractured": bool(broken),
        "collar_fracture_time": min(broken) if broken else None,
    }


def hinge_strain_profile(
    span: float, hinge_length: float, h: float, axial: float, hinges: tuple[float, float]
):
    """The plastic strain of a collar's extreme fibre along its span under the lumped-hinge
    model (colonna.core.collar_law): the axial plastic strain |s_p / L| (``axial``) everywhere,
    plus at each end, over the hinge length L_p, the hinge's plastic rotation (``hinges``: left,
    right) spread over it, |theta_p| h / (2 L_p) (hinge zones longer than half the span overlap
    and add). Returns (x, strain), a step profile: each piece's two ends, x from the left
    attachment (m)."""
    lp = hinge_length
    rotation = [abs(r) * h / (2.0 * lp) for r in hinges]
    edges = np.unique(np.clip([0.0, lp, span - lp, span], 0.0, span))
    x, strain = [], []
    for a, b in zip(edges[:-1], edges[1:]):
        middle = 0.5 * (a + b)
        value = abs(axial) + rotation[0] * (middle < lp) + rotation[1] * (middle > span - lp)
        x += [a, b]
        strain += [value, value]
    return np.array(x), np.array(strain)


RESPONSE_FIELDS = (
    "F1x",
    "F1y",
    "M1",
    "F2x",
    "F2y",
    "M2",
    "N",
    "fibre_strain",
    "fibre_stress",
    "plastic_work",
    "fractured",
    "elastic_energy",
    "plastic_strain",
    "largest_fibre_strain",
    "alpha",
)
"""The arrays of :func:`response`: end forces (N) and moments (N m) holding the ends, in the
collar's initial axes; the axial force N (N, tension +); the largest surface strain now and its
largest reached; the largest fibre stress now (Pa); the plastic work (J); fractured (bool); the
elastic energy (J); the axial plastic strain; the accumulated plastic strain (the resultant
law's, the fibre law's largest fibre's)."""


def response(collar: Collar, history) -> dict:
    """A collar driven through imposed end displacements and rotations, as the models step it.

    ``history``: rows (u1, v1, r1, u2, v2, r2), the ends' displacements (m) and rotations (rad)
    in the collar's initial axes (end 1 at the origin, end 2 at (L, 0), L = ``collar.length``),
    from the unstressed (but pretensioned) collar, each row committed in turn. The co-rotational
    kinematics and local law are the models'
    (:func:`colonna.core.collar_law.history_response`); the plastic work is the trapezoid
    rule's (docs/collars.md): drive it in steps of a fraction of the first-yield slip. Returns
    a dict of arrays, one value per row (RESPONSE_FIELDS); the resultant law's fibre stress
    is the elastic |N|/A + |M|/W capped at f_y + H alpha (:meth:`Collar.fibre_stress`)."""
    from .collar_law import history_response, state_size

    if collar.length is None:
        raise InputError("collar length is not set: the test bench needs the span L (m)")
    rows = np.asarray(history, dtype=float)
    if rows.ndim != 2 or rows.shape[1] != 6:
        raise InputError(
            f"collar history has shape {rows.shape}: it must be rows of 6 numbers "
            "(u1, v1, r1, u2, v2, r2)"
        )
    if not np.isfinite(rows).all():
        raise InputError("collar history has a value that is not a finite number")
    span = collar.length
    law = np.array(collar.law())
    state = np.zeros((1, state_size(law)))
    out = np.zeros((rows.shape[0], len(RESPONSE_FIELDS)))
    ea_l = collar.E * collar.area / span
    ei_l = collar.E * collar.second_moment / span
    history_response(rows, span, ea_l, ei_l, collar.pretension, law, state, out)
    result: dict[str, np.ndarray] = {
        name: out[:, k].copy() for k, name in enumerate(RESPONSE_FIELDS)
    }
    result["fractured"] = out[:, RESPONSE_FIELDS.index("fractured")] > 0.0
    if collar.local_law != "fibre":
        moment = np.maximum(np.abs(result["M1"]), np.abs(result["M2"]))
        stress = collar.fibre_stress(result["N"], moment, result["alpha"])
        result["fibre_stress"] = np.where(result["fractured"], 0.0, stress)
    return result

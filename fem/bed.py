"""The column's bed: the base as a physical interface of stiffness per unit area k (N/m^3).

A column stands on a mortar bed, a lead sheet or a stone plinth. The layer of modulus E_bed and
thickness t_bed between the column and a (much stiffer) support is a Winkler bed of stiffness
per unit area k = E_bed / t_bed (a thin layer; its lateral confinement raises it, its yield
lowers it: both are left out of this first-order model). The base contact of the FEM is this
bed: each base node's spring is k x t x l_trib (thickness t, tributary length l_trib), held
fixed when the mesh is refined, so that a toe refinement refines the mesh only.

Presets (the range's ends give the answer's spread; the nominal value is their geometric mean):
  mortar: E_bed 1-10 GPa (lime to cement-lime bedding mortars) over t_bed 10-20 mm (a bedding
    joint), k = 5e10-1e12 N/m^3; the joint stiffness k_n = E_m / t_m of masonry micro-models
    (Lourenco & Rots 1997, J. Eng. Mech. 123(7); with a stone far stiffer than the mortar).
  lead: E_bed 16 GPa (lead, handbook value: ASM Handbook Vol. 2) over t_bed 1.32-3.55 mm (lead
    sheet codes 3-8 of EN 12588), k = 4.5e12-1.2e13 N/m^3. Lead yields at a few MPa: under a
    toe the sheet is plastic, the elastic bed an upper bound of its stiffness.
  stone: dressed stone on stone, dry: k = 1e10-1e12 N/m^3, the order of the dry-joint normal
    stiffnesses used for stone masonry and classical columns in discrete-element models
    (reviewed by Lemos 2007, Int. J. Archit. Herit. 1(2)); the widest range of the three.

Closed form (the design brief's): a rigid block of weight W and thickness t pivoting at tilt
theta on a tensionless Winkler bed touches it over c = sqrt(2 W / (k t theta)) from the toe,
with the pressure linear from p = k theta c = 2 W / (t c) at the toe to 0, and its resultant
c / 3 from the toe.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..core.errors import InputError, require_range

STIFFNESS_RANGE = (1e6, 1e18)  # N/m^3: the range a bed stiffness may take (as contact.penalty)
YIELD_PRESSURE_RANGE = (1e5, 1e10)  # Pa: the range a bed's yield pressure may take


@dataclass(frozen=True)
class BedPreset:
    """A named bed: its stiffness range (N/m^3), where the numbers come from, and for a layer
    its modulus and thickness ranges ((Pa, Pa), (m, m)), whose ratio gives the range."""

    name: str
    stiffness_range: tuple[float, float]
    source: str
    layer: tuple[tuple[float, float], tuple[float, float]] | None = None
    # the pressure (Pa) at which the layer yields, its range and where it comes from; None for
    # a bed that does not yield before the stone (stone on stone)
    yield_range: tuple[float, float] | None = None
    yield_source: str = ""
    plastic: bool = False  # whether the preset yields unless [base] plastic = false

    @property
    def yield_pressure(self) -> float | None:
        """The nominal yield pressure (Pa): the geometric mean of its range's ends."""
        if self.yield_range is None:
            return None
        return math.sqrt(self.yield_range[0] * self.yield_range[1])

    @property
    def stiffness(self) -> float:
        """The nominal k (N/m^3): the geometric mean of the range's ends."""
        low, high = self.stiffness_range
        return math.sqrt(low * high)


def _layer(modulus: tuple[float, float], thickness: tuple[float, float]) -> dict:
    """A layer's stiffness range k = E / t, softest (E low, t high) to stiffest, and itself."""
    return {
        "stiffness_range": (modulus[0] / thickness[1], modulus[1] / thickness[0]),
        "layer": (modulus, thickness),
    }


BED_PRESETS = {
    "mortar": BedPreset(
        "mortar",
        source="mortar bed: E 1-10 GPa over 10-20 mm (joint stiffness E_m / t_m, Lourenco & Rots "
        "1997)",
        **_layer((1e9, 10e9), (0.010, 0.020)),
        yield_range=(1e6, 20e6),
        yield_source="mortar: compressive strength 1-20 MPa, classes M1 to M20 of EN 998-2 "
        "(a bed joint's confinement raises it: the lower end is conservative for the toe)",
    ),
    "lead": BedPreset(
        "lead",
        source="lead sheet: E 16 GPa (ASM Handbook Vol. 2) over 1.32-3.55 mm (EN 12588 codes 3-8)",
        **_layer((16e9, 16e9), (1.32e-3, 3.55e-3)),
        yield_range=(5e6, 40e6),
        yield_source="lead: from its uniaxial yield stress, about 5 MPa (pure lead, ASM Handbook "
        "Vol. 2), for a sheet free to flow out, to its Brinell hardness, about 4 HB = 40 MPa, "
        "for one confined under the toe (an indentation pressure about 3 times the yield "
        "stress, Tabor 1951)",
        plastic=True,
    ),
    "stone": BedPreset(
        "stone",
        (1e10, 1e12),
        "stone on stone, dry: k 1e10-1e12 N/m^3, dry-joint normal stiffnesses of stone "
        "masonry in discrete-element models (Lemos 2007)",
    ),
}
DEFAULT_BED = "mortar"


@dataclass(frozen=True)
class Bed:
    """The bed under the column: stiffness per unit area (N/m^3), the ends of its uncertainty
    range (N/m^3; both equal to it where it is known) and its source in words."""

    stiffness: float
    low: float
    high: float
    source: str
    # Pa: the pressure at which the bed yields (elastic-perfectly plastic, its indentation
    # kept); None: elastic
    yield_pressure: float | None = None
    yield_source: str = ""

    def __post_init__(self):
        for name, value in (("stiffness", self.stiffness), ("low", self.low), ("high", self.high)):
            require_range(
                f"base {name} (N/m^3)", value, *STIFFNESS_RANGE, closed_low=True, closed_high=True
            )
        if self.yield_pressure is not None:
            require_range(
                "base yield_pressure (Pa)",
                self.yield_pressure,
                *YIELD_PRESSURE_RANGE,
                closed_low=True,
                closed_high=True,
            )
        if not self.low <= self.stiffness <= self.high:
            raise InputError(
                f"base stiffness = {self.stiffness:g} N/m^3 must lie within its range "
                f"[{self.low:g}, {self.high:g}] N/m^3"
            )


def bed_of(
    preset: str | None = DEFAULT_BED,
    stiffness: float | None = None,
    low: float | None = None,
    high: float | None = None,
    plastic: bool | None = None,
    yield_pressure: float | None = None,
) -> Bed:
    """The bed of a preset name (:data:`BED_PRESETS`), or of a given ``stiffness`` (N/m^3, with
    an optional range ``low``-``high``; it overrides the preset, which then only names it).

    It yields (elastic-perfectly plastic) at ``yield_pressure`` (Pa) where given, else at the
    preset's nominal yield pressure where ``plastic`` (default: the preset's own choice, lead
    yields); ``plastic = False`` keeps it elastic."""
    name = preset or DEFAULT_BED
    if name not in BED_PRESETS:
        raise InputError(f"base.bed = {name!r} must be one of {', '.join(BED_PRESETS)}")
    p = BED_PRESETS[name]
    yields = p.plastic if plastic is None else plastic
    if plastic is False and yield_pressure is not None:
        raise InputError(
            "base.yield_pressure goes with a bed that yields: not with plastic = false"
        )
    pressure: float | None = None
    why = ""
    if yield_pressure is not None:
        pressure, why = float(yield_pressure), "given (base.yield_pressure)"
    elif yields:
        if p.yield_pressure is None:
            raise InputError(
                f"base.plastic = true: the {name} bed has no yield pressure of its own (it "
                "does not yield before the stone): give base.yield_pressure"
            )
        pressure, why = p.yield_pressure, p.yield_source
    if stiffness is not None:
        low = stiffness if low is None else low
        high = stiffness if high is None else high
        return Bed(
            float(stiffness), float(low), float(high), "given (base.stiffness)", pressure, why
        )
    if low is not None or high is not None:
        raise InputError("base.stiffness_range goes with a given base.stiffness only")
    return Bed(p.stiffness, *p.stiffness_range, p.source, pressure, why)


DEFAULT = bed_of()


def stone_bed(mesh, modulus: float) -> Bed:
    """A bed as stiff as the stone's base row: k = E / h, h the height of the mesh's lowest
    element row (m) and E the stone's modulus (Pa), the base penalty colonna used before the
    bed was data. For the stiff limit (a stone made ever stiffer on a base that stiffens with
    it, toward a rigid block on a rigid base); not a physical bed."""
    y = np.unique(mesh.points[1])
    k = modulus / float(y[1] - y[0])
    return Bed(k, k, k, f"as stiff as the stone's base row: E / h = {k:.3g} N/m^3")


# ------------------------------------------------------------------------------------------
# the rigid block pivoting on a Winkler bed
# ------------------------------------------------------------------------------------------


def winkler_contact_length(weight: float, stiffness: float, thickness: float, theta: float):
    """c = sqrt(2 W / (k t theta)) (m): the contact length of a rigid block of weight W (N) and
    thickness t (m) pivoting at tilt theta (rad) on a tensionless bed of k (N/m^3)."""
    return math.sqrt(2.0 * weight / (stiffness * thickness * abs(theta)))


def winkler_peak_pressure(
    weight: float,
    stiffness: float,
    thickness: float,
    theta: float,
    yield_pressure: float | None = None,
):
    """p = 2 W / (t c) = sqrt(2 W k theta / t) (Pa): the pressure at the toe of that block; on
    a bed that yields at most its ``yield_pressure`` (:func:`winkler_plastic_pivot`'s peak)."""
    elastic = math.sqrt(2.0 * weight * stiffness * abs(theta) / thickness)
    return elastic if yield_pressure is None else min(elastic, yield_pressure)


def winkler_toe_pressure(
    force,
    theta,
    stiffness: float,
    thickness: float,
    width: float,
    yield_pressure: float | None = None,
):
    """The toe pressure (Pa) of a rigid base of width w (m) pressed on the bed by a normal force
    N (N) at tilt theta (rad), arrays alike: while c = sqrt(2 N / (k t |theta|)) <= w the
    partial contact's k |theta| c, else the full contact's N / (t w) + k |theta| w / 2 (the
    two agree at c = w); 0 where N <= 0; on a bed that yields at most its ``yield_pressure``."""
    force = np.maximum(np.asarray(force, dtype=float), 0.0)
    tilt = np.abs(np.asarray(theta, dtype=float))
    k, t, w = stiffness, thickness, width
    partial = 2.0 * force * k * tilt / t  # (k theta c)^2
    full = force / (t * w) + 0.5 * k * tilt * w
    inside = 2.0 * force <= k * t * tilt * w * w  # c <= w
    pressure = np.where(inside, np.sqrt(partial), full)
    return pressure if yield_pressure is None else np.minimum(pressure, yield_pressure)


def winkler_plastic_pivot(
    weight: float, stiffness: float, thickness: float, theta: float, yield_pressure: float
) -> dict:
    """A rigid block of weight W (N) and thickness t (m) pivoting at tilt theta (rad) on a
    tensionless elastic-perfectly plastic Winkler bed (k N/m^3, yield pressure p_y Pa),
    loaded monotonically: the bed's pressure is min(k theta (c - s), p_y) at a distance s from
    the toe. Where the elastic peak k theta c_e (c_e = sqrt(2 W / (k t theta))) stays below
    p_y, the elastic answer; else a plastic zone of length a = W / (t p_y) - p_y / (2 k theta)
    at p_y, then the elastic wedge over p_y / (k theta): c = a + p_y / (k theta), from
    W = t (p_y a + p_y^2 / (2 k theta)). Returns contact_length c, plastic_length a (m),
    peak_pressure (Pa) and offset, the resultant's distance from the toe (m)."""
    k, t, p_y, tilt = stiffness, thickness, yield_pressure, abs(theta)
    elastic = winkler_contact_length(weight, k, t, tilt)
    if k * tilt * elastic <= p_y:
        return {
            "contact_length": elastic,
            "plastic_length": 0.0,
            "peak_pressure": k * tilt * elastic,
            "offset": elastic / 3.0,
        }
    wedge = p_y / (k * tilt)
    a = weight / (t * p_y) - 0.5 * wedge
    # moments about the toe: the plastic block p_y a at a / 2, the wedge p_y wedge / 2 at
    # a + wedge / 3
    moment = p_y * a * 0.5 * a + 0.5 * p_y * wedge * (a + wedge / 3.0)
    return {
        "contact_length": a + wedge,
        "plastic_length": a,
        "peak_pressure": p_y,
        "offset": moment / (p_y * a + 0.5 * p_y * wedge),
    }


ELEMENTS_ACROSS = 4  # elements across the contact zone that resolve it (the toe grading rule)


def resolving_toe_size(weight, stiffness, thickness, alpha, across: int = ELEMENTS_ACROSS):
    """The toe element size (m) that resolves the contact zone: ``across`` elements over the
    Winkler contact length at the representative tilt theta = alpha / 2 (half way to the
    rocking body's overturning tilt: at smaller tilts the zone is longer, at alpha only
    sqrt(2) shorter)."""
    return winkler_contact_length(weight, stiffness, thickness, 0.5 * alpha) / across


# ------------------------------------------------------------------------------------------
# a static solve with a tensionless base (quasi-static pivot)
# ------------------------------------------------------------------------------------------


def static_on_bed(model, load: np.ndarray, max_iterations: int = 200) -> dict:
    """Small-displacement static equilibrium of the model's bodies on their tensionless base
    springs under ``load`` (N per dof, the model's dof order), by an active set: springs in
    tension open, open ones that penetrate close, until none changes. The tangential springs
    stay closed (they hold the block against the horizontal load: no slip). No crack or collars
    (a solid column). Returns displacement (n_dofs), base_fn (N, per base node), pressure (Pa,
    base_fn over the node's tributary area) and active (bool per base node)."""
    from scipy import sparse
    from scipy.sparse.linalg import spsolve

    if model.mesh.cracked or model.collars:
        raise InputError("static_on_bed solves a solid column without collars")
    n = model.n_dofs
    nodes = model.base_nodes
    horizontal = sparse.csr_matrix((model.base_kt, (2 * nodes, 2 * nodes)), shape=(n, n))
    active = np.ones(nodes.size, dtype=bool)
    for _ in range(max_iterations):
        vertical = sparse.csr_matrix(
            (np.where(active, model.base_kn, 0.0), (2 * nodes + 1, 2 * nodes + 1)), shape=(n, n)
        )
        u = spsolve((model.stiffness + horizontal + vertical).tocsc(), load)
        penetration = -u[2 * nodes + 1]
        now = penetration > 0.0
        if np.array_equal(now, active):
            break
        active = now
    else:
        raise InputError("static_on_bed: the active set did not settle")
    fn = np.where(active, model.base_kn * penetration, 0.0)
    return {
        "displacement": u,
        "base_fn": fn,
        "pressure": fn / (model.base_tributary * model.thickness),
        "penetration": penetration,
        "active": active,
    }

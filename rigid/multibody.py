"""Rigid multibody model of the column with the FEM's contact topology.

One rigid body (solid column) or two (cracked column: left and right half), each with (x, y,
theta) in the plane; unilateral contact with Coulomb friction between each body's base corners and
the ground, and between the crack faces (each half's two crack-face corners against the other
half's face, so that the halves can open, close and slide vertically along the crack); collars as
the FEM's co-rotational frame element between their true attachment points on the outer faces.
This is the rigid reference with no kinematic assumption: what the source paper ran in Working
Model 2D.

Numerics: Moreau-Jean time stepping at the velocity-impulse level (see :mod:`rigid._multibody`),
Newton's impact law with e_n = 0 by default. With a plastic impact and no slip an impact conserves
the angular momentum about the new pivot, so the scheme gives Housner's ratio
1 - 1.5 sin^2(alpha) by itself: no restitution coefficient is imposed.

Geometry follows the other solvers: ``block`` is the rocking block, 2b x 2h. For a cracked column
it is one half (the column is 4b wide) and the two halves are copies of it side by side, the
crack at x = 0; a solid column is the block itself. Rotations are reported as in the paper
(theta > 0 tipping toward +x).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field, replace

import numpy as np

from ..core.collar import collar_strain_summary
from ..core.collar_law import (
    FIBRE_STRAIN,
    FRACTURED,
    LAW_SIZE,
    OUT_SIZE,
    RECORDED,
    state_size,
)
from ..core.errors import (
    InputError,
    require_history_rows,
    require_non_negative,
    require_positive,
    require_range,
)
from ..core.fibre import STRESS as FIBRE_STRESS
from ..core.ground import NO_MOTION, GroundMotion, kernel_tables, require_motion
from ..core.motion import Motion, Release
from ..core.quantities import CollarPeaks, quantity, shared, to_dict, typed_result
from . import _multibody as K
from .block import Block
from .collars import validate_collars
from .solve import (
    AT_REST,
    CollarHistory,
    collar_state,
    motion_word,
    require_parameter_object,
    verdict,
)

DEFAULT_FRICTION = 0.7  # as the FEM's ContactSettings
STEPS_PER_ROCKING_TIME = 1000  # default step: (1/p) / 1000
# the collars' forces are explicit: a step is at most half their stability limit 2 / omega
# (h omega <= 1; above it is refused), by default an eighth of it (h omega = 0.25)
COLLAR_STEP_LIMIT = 0.5
COLLAR_STEP_FRACTION = 0.125
SOLVER_TOLERANCE = 1e-10  # relative change of the impulses that ends the Gauss-Seidel
SOLVER_MAX_ITERATIONS = 500
IMPACT_REFINEMENT = 32  # a step in which a contact closes is redone as 32 substeps
IMPACT_THRESHOLD = 1e-4  # an impact counts once |theta| > 1e-4 alpha since the last one


def _unstable(reason: int, t: float, dt: float) -> InputError:
    """The error of a run the kernel stopped as UNSTABLE at time t (s), saying why."""
    if reason == K.UNSTABLE_COLLAR:
        return InputError(
            f"the multibody run stopped at t = {t:.4g} s: a collar's law gave no answer (a "
            'fibre section whose iteration did not converge: try section = "resultant", '
            "more n_sections, or a lower dt)"
        )
    return InputError(
        f"the multibody run went unstable at t = {t:.4g} s (dt = {dt:g} s): the state or "
        "its energy left every physical bound: lower dt"
    )


OVERTURN_REASONS = {
    K.OVER_HALF_PI: "a body rotated past pi/2",
    K.OVER_COLUMN: "the column's centre of mass passed its outer toe moving outward after the "
    "ground motion",
    K.OVER_HALF: "a free half's centre of mass passed its outer toe moving outward after the "
    "ground motion",
}


@dataclass(frozen=True)
class MultibodyColumn:
    """The bodies, contact candidates and collar elements, as arrays for the kernel."""

    block: Block
    cracked: bool
    collars: tuple
    friction: float
    crack_friction: float
    mass: np.ndarray = field(repr=False)  # (n_bodies,) kg
    inertia: np.ndarray = field(repr=False)  # (n_bodies,) kg m^2, centroidal
    # (n_bodies, 3): half width, half height (m), dead load at the top's centre (N)
    half: np.ndarray = field(repr=False)
    q_rest: np.ndarray = field(repr=False)  # (3 n_bodies,)
    cand_a: np.ndarray = field(repr=False)
    cand_b: np.ndarray = field(repr=False)
    cand_pt: np.ndarray = field(repr=False)
    cand_face: np.ndarray = field(repr=False)
    cand_mu: np.ndarray = field(repr=False)
    cand_kind: np.ndarray = field(repr=False)
    col_a: np.ndarray = field(repr=False)
    col_b: np.ndarray = field(repr=False)
    col_r: np.ndarray = field(repr=False)
    col_props: np.ndarray = field(repr=False)

    @property
    def col_limits(self) -> np.ndarray:
        """(A, W, f_y, H) of each collar: area (m^2), section modulus (m^3), yield stress (Pa)
        and, for a plastic collar, the plastic modulus H (Pa; -1: elastic collar, its stress
        is not capped; see Collar.fibre_stress)."""
        return np.array(
            [
                (c.area, c.section_modulus, c.fy, c.plastic_modulus if c.plastic else -1.0)
                for c in self.collars
            ],
            dtype=float,
        ).reshape(-1, 4)

    @property
    def collar_state_size(self) -> int:
        """Numbers per collar in the collars' plastic state (a row as long as the largest
        their laws need: colonna.core.collar_law)."""
        return state_size(self.col_props[:, 5:])

    def collar_rest_state(self) -> np.ndarray:
        """The collars' plastic state at rest, (n_collars, collar_state_size), zeros."""
        return np.zeros((self.col_a.size, self.collar_state_size))

    @property
    def n_bodies(self) -> int:
        return self.mass.size

    @property
    def total_mass(self) -> float:
        return float(self.mass.sum())

    def kernel_bundles(self) -> tuple[K.Bodies, K.Contacts, K.Collars]:
        """The column as the kernels take it: its bodies, contact candidates and collars."""
        return (
            K.bodies(self.mass, self.inertia, self.half, self.block.g),
            K.Contacts(
                self.cand_a, self.cand_b, self.cand_pt, self.cand_face, self.cand_mu, self.cand_kind
            ),
            K.Collars(
                self.col_a,
                self.col_b,
                self.col_r,
                self.col_props,
                self.col_limits,
                self.collar_state_size,
            ),
        )

    @property
    def column_width(self) -> float:
        return 2.0 * float(self.half[:, 0].sum())

    def overturning_barrier(self) -> float:
        """The least energy above rest (J) with which any part can pass its toe: the whole
        column tipping as one block, or (cracked) one half alone."""
        g = self.block.g
        whole = Block(
            b=0.5 * self.column_width,
            h=self.block.h,
            mass=self.total_mass,
            g=g,
            top_load=float(self.half[:, 2].sum()),
        )
        barrier = overturning_energy(whole)
        for m, (bw, hh, load) in zip(self.mass, self.half):
            barrier = min(
                barrier, overturning_energy(Block(b=bw, h=hh, mass=m, g=g, top_load=load))
            )
        return float(barrier)

    def rocking_energy(self) -> float:
        """m g R (1 - cos alpha) of the rocking block (J): the scale of the energy balance."""
        blk = self.block
        return self.total_mass * blk.g * blk.R * (1.0 - math.cos(blk.alpha))

    def collar_stable_step(self) -> float:
        """2 / omega_max of the collar springs on the rigid bodies (s); inf without collars."""
        if self.col_a.size == 0 or not self.cracked:
            return math.inf
        n = self.q_rest.size
        stiffness = np.zeros((n, n))
        step = 1e-7 * self.column_width
        out = np.zeros((self.col_a.size, OUT_SIZE))
        state = self.collar_rest_state()
        for k in range(n):
            q = self.q_rest.copy()
            fp, fm = np.zeros(n), np.zeros(n)
            q[k] += step
            K.collar_forces(
                q, self.col_a, self.col_b, self.col_r, self.col_props, fp, out, state, False
            )
            q[k] -= 2.0 * step
            K.collar_forces(
                q, self.col_a, self.col_b, self.col_r, self.col_props, fm, out, state, False
            )
            stiffness[:, k] = -(fp - fm) / (2.0 * step)
        stiffness = 0.5 * (stiffness + stiffness.T)
        m = np.stack((self.mass, self.mass, self.inertia), axis=1).ravel()
        scale = 1.0 / np.sqrt(m)
        lam = np.linalg.eigvalsh(stiffness * scale[:, None] * scale[None, :]).max()
        return 2.0 / math.sqrt(lam) if lam > 0.0 else math.inf


def overturning_energy(block: Block) -> float:
    """Energy above rest (J) that takes a free block, with its top load, to its unstable
    equilibrium theta_c: m g R (cos(alpha - theta_c) - cos alpha) + P R (2 cos alpha (cos
    theta_c - 1) + sin alpha sin theta_c); m g (R - h) without a load."""
    m = block.require_mass("the overturning energy")
    a, tc, R = block.alpha, block.critical_angle("nonlinear"), block.R
    return m * block.g * R * (math.cos(a - tc) - math.cos(a)) + block.top_load * R * (
        2.0 * math.cos(a) * (math.cos(tc) - 1.0) + math.sin(a) * math.sin(tc)
    )


def build_column(
    block: Block,
    *,
    cracked: bool = False,
    collars=(),
    friction: float = DEFAULT_FRICTION,
    crack_friction: float | None = None,
) -> MultibodyColumn:
    """Bodies, contact candidates and collar elements of a solid or cracked column.

    ``block`` is the rocking block (one half of a cracked column), with its top load (each
    half of a cracked column carries its block's). Its mass is needed with collars or a top
    load; a free block may have none (the motion does not depend on it: 1 kg is used).
    Collars need a cracked column (on a solid one both ends sit on the same rigid body)."""
    require_non_negative("friction (base Coulomb coefficient)", friction)
    crack_friction = friction if crack_friction is None else crack_friction
    require_non_negative("crack friction (Coulomb coefficient)", crack_friction)
    collars = validate_collars(collars, block)
    if collars and not cracked:
        raise InputError(
            "collars need a cracked column (--cracked): on a solid rigid column "
            "both collar ends sit on the same body"
        )
    b, h = block.b, block.h
    m = block.mass if block.mass is not None else 1.0
    inertia = m * (b * b + h * h) / 3.0  # (2b)^2 + (2h)^2 over 12
    n = 2 if cracked else 1
    centres = [(-b, h), (b, h)] if cracked else [(0.0, h)]
    q_rest = np.array([c for xy in centres for c in (*xy, 0.0)], dtype=float)
    cand_a, cand_b, cand_pt, cand_face, cand_mu, cand_kind = [], [], [], [], [], []

    def add(a, b_, pt, face, mu, kind):
        cand_a.append(a), cand_b.append(b_), cand_pt.append(pt), cand_face.append(face)
        cand_mu.append(mu), cand_kind.append(kind)

    for body in range(n):
        for sx in (-1.0, 1.0):
            add(body, -1, (sx * b, -h), (0.0, 0.0, 0.0), friction, K.CONTACT_BASE)
    if cracked:
        # the left half's crack-face corners on the right half's face (its local x = -b,
        # outward normal -x), and the right half's corners on the left half's face
        for sy in (-1.0, 1.0):
            add(0, 1, (b, sy * h), (-b, -1.0, h), crack_friction, K.CONTACT_CRACK)
        for sy in (-1.0, 1.0):
            add(1, 0, (-b, sy * h), (b, 1.0, h), crack_friction, K.CONTACT_CRACK)
    col_a = np.zeros(len(collars), dtype=np.int64)
    col_b = np.ones(len(collars), dtype=np.int64)
    col_r = np.zeros((len(collars), 4))
    col_props = np.zeros((len(collars), 5 + LAW_SIZE))
    for c, collar in enumerate(collars):
        y = collar.y - h  # height relative to the centroids
        col_r[c] = (-b, y, b, y)  # outer faces: left half x = -2b, right x = 2b
        chord = 4.0 * b
        span = collar.span(b)
        ea_l = collar.E * collar.area / span
        # as the FEM: bending stiffness scaled so that the lateral one is 12 E I / L^3
        ei_l = collar.E * collar.second_moment * (chord / span) ** 3 / chord
        col_props[c] = (
            ea_l,
            ei_l,
            collar.pretension,
            chord,
            0.0,
            *collar.law(),
        )
    return MultibodyColumn(
        block,
        bool(cracked),
        collars,
        float(friction),
        float(crack_friction),
        np.full(n, float(m)),
        np.full(n, inertia),
        np.tile([b, h, block.top_load], (n, 1)).astype(float),
        q_rest,
        np.array(cand_a, dtype=np.int64),
        np.array(cand_b, dtype=np.int64),
        np.array(cand_pt, dtype=float),
        np.array(cand_face, dtype=float),
        np.array(cand_mu, dtype=float),
        np.array(cand_kind, dtype=np.int64),
        col_a,
        col_b,
        col_r,
        col_props,
    )


def tilted_state(column: MultibodyColumn, tilt: float, angular_velocity: float = 0.0):
    """Positions and velocities of the column turned rigidly by ``tilt`` (rad, theta sign:
    > 0 toward +x) about the outer toe it tips on, spinning at ``angular_velocity`` (rad/s)."""
    require_range(
        "release.tilt (rad)", tilt, -0.5 * math.pi, 0.5 * math.pi, range_text="(-pi/2, pi/2)"
    )
    q = column.q_rest.copy()
    v = np.zeros_like(q)
    if tilt == 0.0 and angular_velocity == 0.0:
        return q, v
    side = 1.0 if (tilt > 0.0 or (tilt == 0.0 and angular_velocity > 0.0)) else -1.0
    pivot = np.array([side * 0.5 * column.column_width, 0.0])
    phi = -tilt
    c, s = math.cos(phi), math.sin(phi)
    omega = -angular_velocity
    for i in range(column.n_bodies):
        r = q[3 * i : 3 * i + 2] - pivot
        r_new = np.array([c * r[0] - s * r[1], s * r[0] + c * r[1]])
        q[3 * i : 3 * i + 2] = pivot + r_new
        q[3 * i + 2] = phi
        v[3 * i : 3 * i + 3] = (-omega * r_new[1], omega * r_new[0], omega)
    return q, v


@dataclass
class MultibodyResult:
    """Histories of the rigid multibody model (SI units, theta positive toward +x).

    ``theta``, ``theta_dot``: (n_times, n_bodies), left half first. ``impacts``: rows (t, body,
    theta' before, theta' after) at each change of sign of a body's rotation."""

    time: np.ndarray = field(repr=False)
    theta: np.ndarray = field(repr=False)
    theta_dot: np.ndarray = field(repr=False)
    centroid: np.ndarray = field(repr=False)  # (n_times, n_bodies, 2) m
    uplift: np.ndarray = field(repr=False)  # (n_times, 2) outer toes' height, m
    crack_opening: np.ndarray = field(repr=False)  # (n_times,) m, max over the face
    crack_slip: np.ndarray = field(repr=False)  # (n_times,) m, right relative to left
    base_normal_force: np.ndarray = field(repr=False)  # (n_times, n_bodies) N
    base_tangential_force: np.ndarray = field(repr=False)  # (n_times, n_bodies) N
    crack_normal_force: np.ndarray = field(repr=False)  # (n_times,) N
    energies: dict = field(repr=False)
    impacts_table: np.ndarray = field(repr=False)
    column: MultibodyColumn = field(repr=False)
    status: str
    overturned: bool
    mode: str
    impacts: int
    overturn_time: float | None
    dt: float
    steps: int
    wall_seconds: float
    solver_iterations_max: int
    collar_histories: list = field(default_factory=list, repr=False)
    collar_max_plastic_strain: float = 0.0  # largest |plastic strain| of a plastic collar
    collar_plastic_work: float = 0.0  # J, work done yielding the collars

    model = "multibody"

    @property
    def cracked(self) -> bool:
        return self.column.cracked

    @property
    def block(self) -> Block:
        return self.column.block

    @property
    def impact_times(self) -> np.ndarray:
        return self.impacts_table[:, 0]

    @property
    def impact_bodies(self) -> np.ndarray:
        """Which body hit the ground at each impact (0: left half or the solid column)."""
        return self.impacts_table[:, 1].astype(int)

    @property
    def impact_velocity_before(self) -> np.ndarray:
        return self.impacts_table[:, 2]

    @property
    def impact_velocity_after(self) -> np.ndarray:
        return self.impacts_table[:, 3]

    @property
    def max_abs_theta(self) -> float:
        if self.overturned:
            return 0.5 * math.pi
        return float(np.max(np.abs(self.theta))) if self.theta.size else 0.0

    @property
    def max_abs_theta_over_alpha(self) -> float:
        return self.max_abs_theta / self.column.block.alpha

    def impact_velocity_ratios(self, body: int = 0) -> np.ndarray:
        """|theta' after / theta' before| at each impact of ``body``."""
        mine = self.impact_bodies == body
        return np.abs(self.impact_velocity_after[mine] / self.impact_velocity_before[mine])

    def summary(self) -> dict:
        """Plain-data summary (the CLI's ``--json`` object): :meth:`typed_summary` as a dict."""
        return to_dict(self.typed_summary())

    def typed_summary(self) -> MultibodySummary:
        """The summary with the unit of every value (:class:`MultibodySummary`)."""
        blk = self.column.block
        left = np.max(np.abs(self.theta[:, 0])) if self.theta.size else 0.0
        right = np.max(np.abs(self.theta[:, -1])) if self.theta.size else 0.0
        e = self.energies
        hists = self.collar_histories
        collars = None
        strains = {}
        if hists:
            collars = tuple(
                MultibodyCollarSummary(
                    y=hist.collar.y,
                    max_stress=float(np.max(hist.stress)),
                    max_utilisation=hist.max_utilisation,
                    first_yield_time=hist.first_yield_time,
                    max_fibre_strain=hist.max_fibre_strain,
                    ductility_demand=hist.ductility_demand,
                    fracture_time=hist.fracture_time,
                )
                for hist in hists
            )
            strains = collar_strain_summary(
                [h.collar for h in hists],
                [h.max_fibre_strain for h in hists],
                [h.fracture_time for h in hists],
            )
        utilisation = max(h.max_utilisation for h in hists) if hists else None
        yields = [h.first_yield_time for h in hists if h.first_yield_time is not None]
        summary = MultibodySummary(
            verdict="",
            model="multibody",
            overturned=bool(self.overturned),
            mode=self.mode,
            motion=motion_word(self.overturned, self.max_abs_theta, blk.alpha),
            status=self.status,
            impacts=int(self.impacts),
            max_abs_theta=self.max_abs_theta,
            max_abs_theta_over_alpha=self.max_abs_theta_over_alpha,
            max_abs_theta_left=float(left),
            max_abs_theta_right=float(right),
            overturn_time=self.overturn_time,
            cracked=self.cracked,
            friction=self.column.friction,
            crack_friction=self.column.crack_friction,
            p=blk.p,
            alpha=blk.alpha,
            restitution_housner=blk.restitution_housner,
            impact_velocity_ratio_mean=_mean_or_none(self.impact_velocity_ratios(0)),
            max_uplift=float(np.max(self.uplift)) if self.uplift.size else 0.0,
            max_crack_opening=float(np.max(self.crack_opening)) if self.cracked else 0.0,
            max_abs_crack_slip=float(np.max(np.abs(self.crack_slip))) if self.cracked else 0.0,
            energy_dissipated=float(e["dissipated"][-1]),
            energy_external_work=float(e["external_work"][-1]),
            energy_error_max=float(np.max(np.abs(e["error"]))),
            dt=self.dt,
            steps=self.steps,
            wall_seconds=self.wall_seconds,
            collars=collars,
            collar_max_utilisation=utilisation,
            collar_first_yield_time=min(yields) if yields else None,
            collar_max_plastic_strain=self.collar_max_plastic_strain if hists else None,
            collar_plastic_work=self.collar_plastic_work if hists else None,
            **strains,
            collar_state=None
            if utilisation is None
            else collar_state(
                utilisation, self.collar_max_plastic_strain, strains["collar_fractured"]
            ),
        )
        return replace(summary, verdict=verdict(to_dict(summary)))


@typed_result
@dataclass(frozen=True, kw_only=True)
class MultibodyCollarSummary(CollarPeaks):
    """One collar of the multibody model's summary (the FEM's frame element and law): the
    peaks every rigid model's collar gives (CollarPeaks), then its strains."""

    max_fibre_strain: float | None = quantity("-", "largest extreme-fibre strain reached")
    ductility_demand: float | None = quantity("-", "largest fibre strain over f_y / E")
    fracture_time: float | None = quantity("s", "time the collar broke (None: it holds)")


@typed_result
@dataclass(frozen=True, kw_only=True)
class MultibodySummary:
    """What a run of the rigid multibody model (:func:`rock_multibody`) answers, SI units; the
    collar keys only with collars. ``MultibodyResult.summary()`` is its dict, in this order
    (the keys the models share: colonna.core.quantities.SHARED)."""

    # the keys the cross-check reports of its rigid reference, in its summary's order
    # first: what a person reads first
    verdict: str = shared("verdict")
    model: str = quantity("", "the model: multibody")
    overturned: bool = shared("overturned")
    mode: str = shared("mode")
    motion: str = shared("motion")
    status: str = shared("status")
    impacts: int = shared("impacts")
    max_abs_theta: float = shared("max_abs_theta")
    max_abs_theta_over_alpha: float = shared("max_abs_theta_over_alpha")
    max_abs_theta_left: float = shared("max_abs_theta_left")
    max_abs_theta_right: float = shared("max_abs_theta_right")
    overturn_time: float | None = shared("overturn_time")
    cracked: bool = quantity("", "two half blocks split by the crack (else one body)")
    friction: float = quantity("-", "Coulomb friction coefficient at the base")
    crack_friction: float = quantity("-", "Coulomb friction coefficient between the crack faces")
    p: float = shared("p")
    alpha: float = shared("alpha")
    restitution_housner: float = shared("restitution_housner")
    impact_velocity_ratio_mean: float | None = quantity(
        "-", "mean |theta' after / theta' before| of the left body's impacts (None: none)"
    )
    max_uplift: float = quantity("m", "largest height of an outer toe above the ground")
    max_crack_opening: float = quantity("m", "largest opening of the crack (0 uncracked)")
    max_abs_crack_slip: float = quantity("m", "largest |slip| along the crack (0 uncracked)")
    energy_dissipated: float = quantity("J", "energy dissipated by contact, to the end")
    energy_external_work: float = quantity("J", "work of the ground motion, to the end")
    energy_error_max: float = shared("energy_error_max")
    dt: float = shared("dt")
    steps: int = shared("steps")
    wall_seconds: float = shared("wall_seconds")
    collars: tuple[MultibodyCollarSummary, ...] | None = quantity(
        "",
        "per collar (MultibodyCollarSummary); only with collars",
        omit_when_none=True,
        default=None,
    )
    collar_max_utilisation: float | None = shared(
        "collar_max_utilisation", present_with="collars", default=None
    )
    collar_first_yield_time: float | None = shared(
        "collar_first_yield_time", present_with="collars", default=None
    )
    collar_max_plastic_strain: float | None = shared(
        "collar_max_plastic_strain", present_with="collars", default=None
    )
    collar_plastic_work: float | None = shared(
        "collar_plastic_work", present_with="collars", default=None
    )
    collar_max_fibre_strain: float | None = shared(
        "collar_max_fibre_strain", present_with="collars", default=None
    )
    collar_ductility_demand: float | None = shared(
        "collar_ductility_demand", present_with="collars", default=None
    )
    collar_fractured: bool | None = shared("collar_fractured", present_with="collars", default=None)
    collar_fracture_time: float | None = shared(
        "collar_fracture_time", present_with="collars", default=None
    )
    collar_state: str | None = shared("collar_state", present_with="collars", default=None)


def history_columns(result: MultibodyResult) -> dict:
    """The histories as named 1D arrays (SI units), one per CSV column."""
    names = ("left", "right") if result.cracked else ("column",)
    columns = {"t": result.time}
    for k, name in enumerate(names):
        columns[f"theta_{name}"] = result.theta[:, k]
        columns[f"theta_dot_{name}"] = result.theta_dot[:, k]
        columns[f"x_{name}"] = result.centroid[:, k, 0]
        columns[f"y_{name}"] = result.centroid[:, k, 1]
        columns[f"base_normal_force_{name}"] = result.base_normal_force[:, k]
        columns[f"base_tangential_force_{name}"] = result.base_tangential_force[:, k]
    columns["uplift_left"] = result.uplift[:, 0]
    columns["uplift_right"] = result.uplift[:, 1]
    if result.cracked:
        columns["crack_opening"] = result.crack_opening
        columns["crack_slip"] = result.crack_slip
        columns["crack_normal_force"] = result.crack_normal_force
    for k, hist in enumerate(result.collar_histories, start=1):
        # the FEM history's collar columns (fem.solver), of the same frame element and law
        columns[f"collar_{k}_axial_force"] = hist.axial_force
        columns[f"collar_{k}_moment"] = hist.end_moment
        columns[f"collar_{k}_stress"] = hist.stress
        columns[f"collar_{k}_utilisation"] = hist.utilisation
        columns[f"collar_{k}_fibre_strain"] = hist.fibre_strain
        if hist.collar.plastic:
            columns[f"collar_{k}_plastic_strain"] = hist.plastic_strain
            for end, side in enumerate(("left", "right")):
                columns[f"collar_{k}_moment_{side}"] = hist.end_moments[:, end]
                columns[f"collar_{k}_rotation_{side}"] = hist.end_rotations[:, end]
                columns[f"collar_{k}_hinge_rotation_{side}"] = hist.hinge_rotations[:, end]
            columns[f"collar_{k}_fractured"] = hist.fractured
    for key, values in result.energies.items():
        columns[f"energy_{key}"] = values
    return columns


def _mean_or_none(values) -> float | None:
    return float(np.mean(values)) if len(values) else None


def _ground_arrays(ground: GroundMotion, g: float, vertical: GroundMotion = NO_MOTION) -> K.Ground:
    """The ground for the kernel (:class:`rigid._multibody.Ground`): kind, params = (amplitude,
    omega, phase, duration, rows of the horizontal record, 1 if vertical motion follows), the
    tables, and the end of the ground motion."""
    gpar = np.zeros(6)
    require_motion("vertical", vertical)
    # the kernel computes a harmonic motion in closed form and reads any other from its table
    sine = require_motion("ground", ground).sine_form
    if sine is not None:
        gpar[:4] = sine
        kind, end = K.GROUND_HARMONIC, sine.duration
    elif ground.moves:
        kind, end = K.GROUND_RECORD, ground.end_time
    else:
        kind, end = K.GROUND_NONE, 0.0
    rec_t, rec_a, gpar[4], has_vertical = kernel_tables(ground, vertical)
    if has_vertical:
        gpar[5] = 1.0
        end = max(end, vertical.end_time)
    return K.Ground(kind, gpar, rec_t, rec_a, end)


def default_step(
    column: MultibodyColumn,
    ground: GroundMotion = NO_MOTION,
    collar_fraction: float = COLLAR_STEP_FRACTION,
) -> float:
    """(1/p)/1000, at most 1/400 of the pulse period, and at most ``collar_fraction`` of the
    collars' explicit stability limit 2/omega (their forces are explicit; by default an eighth:
    h omega = 0.25) (s)."""
    h = 1.0 / (column.block.p * STEPS_PER_ROCKING_TIME)
    sine = ground.sine_form
    if sine is not None:
        h = min(h, 2.0 * math.pi / sine.omega / 400.0)
    return min(h, collar_fraction * column.collar_stable_step())


def touching_scale(dt: float, touching_dt: float | None) -> float:
    """The kernel's touching_scale: (touching_dt / dt)^2, so that a crack contact within
    g touching_dt^2 of touching and closing is active at the step dt (1 where touching_dt is
    None: dt's own drift, g dt^2). A fragility steps longer than a single run and keeps the
    single run's tolerance (``docs/fragility.md``, "The multibody's step")."""
    if touching_dt is None:
        return 1.0
    require_positive("touching_dt (s)", touching_dt)
    return float((touching_dt / dt) ** 2)


@dataclass(frozen=True)
class MultibodyContact:
    """The multibody column's contacts: ``cracked``, two half bodies with contacts along the
    crack (False: one solid body); ``friction``, the Coulomb coefficient at the base corners
    (and at the crack where ``crack_friction`` is None); ``crack_friction``, the crack faces'
    own; ``restitution_normal``, Newton's e_n in [0, 1] (0: plastic impacts, which give
    Housner's ratio)."""

    cracked: bool = False
    friction: float = DEFAULT_FRICTION
    crack_friction: float | None = None
    restitution_normal: float = 0.0


@dataclass(frozen=True)
class MultibodySettings:
    """How the multibody equations are stepped and stored: ``dt``, the time step (s; None:
    :func:`default_step`); ``dt_out``, the output interval (s; None: 1/200 of 1/p, at least
    dt); ``refine``, a step in which a contact closes is redone as that many substeps (1: plain
    Moreau-Jean, first order at impacts); ``touching_dt``, the step (s) whose midpoint drift
    g touching_dt^2 is the crack contacts' touching tolerance (None: dt's own;
    :func:`touching_scale`); ``max_impacts_stored``, how many impacts keep their record (all
    are counted)."""

    dt: float | None = None
    dt_out: float | None = None
    refine: int = IMPACT_REFINEMENT
    touching_dt: float | None = None
    max_impacts_stored: int = 10_000


MOTIONLESS = Motion()  # no ground motion: free rocking from a Release
SOLID_CONTACT = MultibodyContact()
MULTIBODY_SETTINGS = MultibodySettings()


def _not_applicable(settings: MultibodySettings, names: tuple[str, ...], where: str) -> None:
    """An InputError where one of ``names`` is set to other than its default: ``where`` does
    not use it (a field silently ignored would read as applied)."""
    for name in names:
        if getattr(settings, name) != getattr(MULTIBODY_SETTINGS, name):
            raise InputError(f"settings.{name} does not apply to {where}: leave it at its default")


def rock_multibody(
    block: Block,
    motion: Motion = MOTIONLESS,
    collars=(),
    *,
    contact: MultibodyContact = SOLID_CONTACT,
    release: Release = AT_REST,
    settings: MultibodySettings = MULTIBODY_SETTINGS,
) -> MultibodyResult:
    """Time history of the rigid multibody column under ``motion.ground`` (a pulse, a record,
    or NoMotion(), the default, for free rocking from ``release``) and ``motion.vertical`` (the
    vertical ground acceleration, upward positive, applied to every body as -m vg'').
    ``motion.duration``: s (default: end of the ground motion + 20 / p). ``contact``:
    :class:`MultibodyContact`; ``settings``: :class:`MultibodySettings`."""
    require_parameter_object("motion", motion, Motion)
    require_parameter_object("contact", contact, MultibodyContact)
    require_parameter_object("release", release, Release)
    require_parameter_object("settings", settings, MultibodySettings)
    ground, duration, vertical = motion.ground, motion.duration, motion.vertical
    cracked, friction = contact.cracked, contact.friction
    crack_friction, restitution_normal = contact.crack_friction, contact.restitution_normal
    dt, dt_out, refine = settings.dt, settings.dt_out, settings.refine
    touching_dt, max_impacts_stored = settings.touching_dt, settings.max_impacts_stored
    initial_tilt, initial_angular_velocity = release.tilt, release.angular_velocity
    column = build_column(
        block, cracked=cracked, collars=collars, friction=friction, crack_friction=crack_friction
    )
    _check_restitution(restitution_normal)
    kernel_ground = _ground_arrays(ground, block.g, vertical)
    if duration is None:
        duration = kernel_ground.end + 20.0 / block.p
    require_positive("duration (s)", duration)
    h_stable = COLLAR_STEP_LIMIT * column.collar_stable_step()
    if dt is None:
        dt = default_step(column, ground)
    require_positive("dt (s)", dt)
    if dt > h_stable:
        raise InputError(
            f"dt = {dt:g} s is above the collars' stable step {h_stable:g} s "
            "(half of 2/omega_max of the collar springs)"
        )
    if dt_out is None:
        dt_out = 1.0 / (200.0 * block.p)
    require_positive("dt_out (s)", dt_out)
    out_every = max(1, int(round(dt_out / dt)))
    require_history_rows(duration, out_every * dt)
    n_steps = int(math.ceil(duration / dt))
    q, v = tilted_state(column, initial_tilt, initial_angular_velocity)
    n_cols = K.history_columns(column.n_bodies, column.col_a.size)
    out = np.zeros((n_steps // out_every + 3, n_cols))
    impacts = np.zeros((max_impacts_stored, 4))
    energy_scale = max(column.rocking_energy(), 1e-300)
    kernel_settings = K.Settings(
        h=float(dt),
        n_steps=n_steps,
        refine=_check_refine(refine),
        e_n=float(restitution_normal),
        out_every=out_every,
        free_halves=bool(column.cracked and not column.collars),
        barrier=float(column.overturning_barrier()),
        early_exit=False,
        impact_tol=IMPACT_THRESHOLD * block.alpha,
        energy_scale=energy_scale,
        tol=SOLVER_TOLERANCE,
        max_iter=SOLVER_MAX_ITERATIONS,
        touching_scale=touching_scale(dt, touching_dt),
    )
    bodies, contacts, collar_elements = column.kernel_bundles()
    start = time.perf_counter()
    status, steps, rows, n_imp, reason, t_over, _peak, iters, _util, plastic, work = K.simulate(
        q, v, bodies, contacts, collar_elements, kernel_ground, kernel_settings, out, impacts
    )
    wall = time.perf_counter() - start
    if status == K.UNSTABLE:
        raise _unstable(reason, steps * dt, dt)
    overturned = status == K.OVERTURNED
    table = impacts[: min(n_imp, max_impacts_stored)].copy()
    if n_imp <= max_impacts_stored:
        # the column's impacts: the halves of a cracked column often land together
        n_imp = max(
            (int(np.sum(table[:, 1] == body)) for body in range(column.n_bodies)), default=0
        )
    if overturned:
        text = f"overturned: {OVERTURN_REASONS[reason]} (t = {t_over:.4g} s)"
        mode = "after-impact" if n_imp > 0 else "without-impact"
    else:
        text = f"finished at t = {steps * dt:.4g} s"
        mode = "safe"
    result = _result(
        column,
        out[:rows],
        table,
        text,
        overturned,
        mode,
        int(n_imp),
        t_over if overturned else None,
        dt,
        steps,
        wall,
        iters,
    )
    result.collar_max_plastic_strain = float(plastic)
    result.collar_plastic_work = float(work)
    return result


@dataclass(frozen=True)
class MultibodyOutcome:
    """What a run of :func:`multibody_outcome` answers (no histories): whether it overturned,
    the largest |theta| of any body over every step (rad; pi/2 once overturned), the column's
    impacts (the most of any body; None where impacts_needed was False), the largest collar
    utilisation over every step's midpoint (None without collars), the steps taken and
    skipped at rest, the kernel's wall time, when the run stopped because no answer could
    change any more (s; None: it ran to its duration or overturned) and when it overturned
    (s; None: it did not)."""

    overturned: bool
    max_abs_theta: float
    impacts: int | None
    collar_max_utilisation: float | None
    steps: int
    wall_seconds: float
    decided_at: float | None = None
    overturned_at: float | None = None


def multibody_outcome(
    block: Block,
    motion: Motion,
    collars=(),
    *,
    contact: MultibodyContact = SOLID_CONTACT,
    settings: MultibodySettings = MULTIBODY_SETTINGS,
    fast: bool = True,
    stop_when_decided: bool = True,
    impacts_needed: bool = True,
) -> MultibodyOutcome:
    """The outcome of :func:`rock_multibody`'s run from rest (same column, step, contact solver
    and impact refinement) without its histories: what a fragility needs of a run. The peak
    |theta| and the collars' utilisation are the kernel's running maxima over every step (the
    history's are over its rows). With ``fast`` (the kernel's outcome_only,
    :func:`rigid._multibody.simulate`) the steps at which the column is at rest under a ground
    acceleration at which it has already stayed at rest are skipped (it stays at rest there),
    and each step's contact problem, where 20 Gauss-Seidel sweeps do not settle it, is solved
    exactly by Gaussian elimination: the same model to the contact solver's tolerance, whose
    own scatter (the start of rocking amplifies it) is what the answers move by (tests/
    test_fragility_speed.py); without it, rock_multibody's steps exactly. With ``fast`` and
    ``stop_when_decided`` the run also stops after the ground motion once no answer can change
    any more (its energy below what the peak |theta|, an impact, the collars' largest
    utilisation or overturning would take: :func:`rigid._multibody._decided`): every answer is
    the whole run's. ``impacts_needed`` False: the caller does not use the impact count (the
    fragility's limit states are uplift, rotation, overturning and the collars'), so the stop
    need not keep it exact: it stops once the other answers cannot change (the impact
    threshold, 1e-4 alpha, was the least of its bounds by far) and ``impacts`` is None.
    ``motion``, ``contact`` and ``settings`` as rock_multibody's (``settings.dt_out`` does not
    apply: no history is kept). Elastic collars only (a plastic collar's fracture is read from
    its history: rock_multibody)."""
    require_parameter_object("motion", motion, Motion)
    require_parameter_object("contact", contact, MultibodyContact)
    require_parameter_object("settings", settings, MultibodySettings)
    _not_applicable(settings, ("dt_out",), "multibody_outcome (it keeps no history)")
    if any(c.plastic for c in collars):
        raise InputError("multibody_outcome: plastic collars need rock_multibody's history")
    ground, duration, dt, touching_dt = (
        motion.ground,
        motion.duration,
        settings.dt,
        settings.touching_dt,
    )
    column = build_column(
        block,
        cracked=contact.cracked,
        collars=collars,
        friction=contact.friction,
        crack_friction=contact.crack_friction,
    )
    _check_restitution(contact.restitution_normal)
    kernel_ground = _ground_arrays(ground, block.g, motion.vertical)
    if duration is None:
        duration = kernel_ground.end + 20.0 / block.p
    require_positive("duration (s)", duration)
    if dt is None:
        dt = default_step(column, ground)
    require_positive("dt (s)", dt)
    if dt > COLLAR_STEP_LIMIT * column.collar_stable_step():
        raise InputError(f"dt = {dt:g} s is above the collars' stable step: lower dt")
    n_steps = int(math.ceil(duration / dt))
    q, v = column.q_rest.copy(), np.zeros_like(column.q_rest)
    # the initial row only (the kernel writes one whole row: N_COLLAR_COLS per collar)
    out = np.zeros((1, K.history_columns(column.n_bodies, column.col_a.size)))
    impacts = np.zeros((settings.max_impacts_stored, 4))
    kernel_settings = K.Settings(
        h=float(dt),
        n_steps=n_steps,
        refine=_check_refine(settings.refine),
        e_n=float(contact.restitution_normal),
        out_every=n_steps + 1,
        free_halves=bool(column.cracked and not column.collars),
        barrier=float(column.overturning_barrier()),
        early_exit=False,
        impact_tol=IMPACT_THRESHOLD * block.alpha,
        energy_scale=max(column.rocking_energy(), 1e-300),
        tol=SOLVER_TOLERANCE,
        max_iter=SOLVER_MAX_ITERATIONS,
        outcome_only=bool(fast),
        stop_decided=bool(fast and stop_when_decided),
        impacts_needed=bool(impacts_needed),
        touching_scale=touching_scale(dt, touching_dt),
    )
    bodies, contacts, collar_elements = column.kernel_bundles()
    start = time.perf_counter()
    status, steps, _rows, n_imp, reason, t_over, peak, _it, util, _pl, _w = K.simulate(
        q, v, bodies, contacts, collar_elements, kernel_ground, kernel_settings, out, impacts
    )
    wall = time.perf_counter() - start
    if status == K.UNSTABLE:
        raise _unstable(reason, steps * dt, dt)
    overturned = status == K.OVERTURNED
    if n_imp <= impacts.shape[0]:  # the column's impacts, as rock_multibody counts them
        table = impacts[:n_imp]
        n_imp = max((int(np.sum(table[:, 1] == b)) for b in range(column.n_bodies)), default=0)
    return MultibodyOutcome(
        overturned=bool(overturned),
        max_abs_theta=0.5 * math.pi if overturned else float(max(peak[0], peak[1])),
        impacts=int(n_imp) if impacts_needed else None,
        collar_max_utilisation=float(util) if column.collars else None,
        steps=int(steps),
        wall_seconds=wall,
        decided_at=steps * dt if status == K.SETTLED else None,
        overturned_at=float(t_over) if overturned else None,
    )


def _check_restitution(restitution_normal: float) -> None:
    require_range(
        "restitution_normal (Newton's e_n)",
        restitution_normal,
        0.0,
        1.0,
        closed_low=True,
        closed_high=True,
    )


def _check_refine(refine) -> int:
    if isinstance(refine, bool) or not isinstance(refine, (int, np.integer)) or refine < 1:
        raise InputError(
            f"refine = {refine!r} must be an integer >= 1 (substeps per step "
            "in which a contact closes)"
        )
    return int(refine)


def _result(
    column, rows, table, status, overturned, mode, n_imp, t_over, dt, steps, wall, iters
) -> MultibodyResult:
    nb = column.n_bodies
    t = rows[:, 0]
    body = rows[:, 1 : 1 + K.N_BODY_COLS * nb].reshape(-1, nb, K.N_BODY_COLS)
    q = body[:, :, :3]
    k0 = 1 + K.N_BODY_COLS * nb
    tail = rows[:, k0:]
    theta = -q[:, :, 2]
    theta_dot = -body[:, :, 5]
    toes = _outer_toe_heights(column, q)
    opening, slip = _crack_kinematics(column, q)
    energies = {
        "kinetic": tail[:, 0],
        "gravity": tail[:, 1],
        "collar": tail[:, 2],
        "dissipated": tail[:, 3],
        "external_work": tail[:, 4],
    }
    total = tail[:, 0] + tail[:, 1] + tail[:, 2]
    balance = total + tail[:, 3] - tail[:, 4] - total[0]
    scale = max(np.max(np.abs(tail[:, 4]), initial=0.0), total[0], column.rocking_energy())
    energies["total"] = total
    energies["error"] = balance / scale
    result = MultibodyResult(
        time=t,
        theta=theta,
        theta_dot=theta_dot,
        centroid=q[:, :, :2].copy(),
        uplift=toes,
        crack_opening=opening,
        crack_slip=slip,
        base_normal_force=tail[:, K.N_TAIL :: 2][:, :nb],
        base_tangential_force=tail[:, K.N_TAIL + 1 :: 2][:, :nb],
        crack_normal_force=tail[:, 5],
        energies=energies,
        impacts_table=table,
        column=column,
        status=status,
        overturned=overturned,
        mode=mode,
        impacts=n_imp,
        overturn_time=t_over,
        dt=dt,
        steps=int(steps),
        wall_seconds=wall,
        solver_iterations_max=int(iters),
    )
    ncol = column.col_a.size
    recorded = tail[:, K.N_TAIL + 2 * nb : K.N_TAIL + 2 * nb + K.N_COLLAR_COLS * ncol]
    recorded = recorded.reshape(t.size, ncol, K.N_COLLAR_COLS)
    result.collar_histories = collar_histories(
        column, t, q, recorded[:, :, OUT_SIZE:], recorded[:, :, :OUT_SIZE]
    )
    return result


def _corner(q, half, sx, sy):
    """World position of corner (sx b, sy h) for q rows (n, 3)."""
    c, s = np.cos(q[:, 2]), np.sin(q[:, 2])
    lx, ly = sx * half[0], sy * half[1]
    return q[:, 0] + c * lx - s * ly, q[:, 1] + s * lx + c * ly


def _outer_toe_heights(column, q):
    first, last = 0, column.n_bodies - 1
    _, y_left = _corner(q[:, first], column.half[first], -1.0, -1.0)
    _, y_right = _corner(q[:, last], column.half[last], 1.0, -1.0)
    return np.stack((y_left, y_right), axis=1)


def _crack_kinematics(column, q):
    """Opening (max over the face, normal to the left half's face) and slip (right half
    relative to the left, along it) of the crack, m."""
    n = q.shape[0]
    if not column.cracked:
        return np.zeros(n), np.zeros(n)
    c, s = np.cos(q[:, 0, 2]), np.sin(q[:, 0, 2])
    openings, slips = [], []
    for sy in (-1.0, 1.0):
        xl, yl = _corner(q[:, 0], column.half[0], 1.0, sy)
        xr, yr = _corner(q[:, 1], column.half[1], -1.0, sy)
        dx, dy = xr - xl, yr - yl
        openings.append(c * dx + s * dy)
        slips.append(-s * dx + c * dy)
    return np.maximum(*openings), 0.5 * (slips[0] + slips[1])


def collar_histories(
    column: MultibodyColumn, t, q, plastic=None, forces=None
) -> list[CollarHistory]:
    """N (tension +), end moment, extreme-fibre stress |N|/A + max|M|/W, utilisation, fibre
    strain, end moments and rotations of every collar over time, from the frame element (as
    the FEM reports them). ``plastic``: (n_times, n_collars, len(RECORDED)) the collars'
    recorded state at those times (colonna.core.collar_law.RECORDED: plastic elongation,
    accumulated plastic strain, hinge rotations, largest fibre strain, fractured; zero if
    None); ``forces``: (n_times, n_collars, OUT_SIZE) the frame element's outputs the run
    recorded at those times (None: computed from q with the collars at rest, as elastic
    collars are; a plastic law's state is larger than what a history row keeps)."""
    if not column.collars:
        return []
    n = q.shape[0]
    if forces is None:
        forces = _collar_outputs_at_rest(column, q)
    histories = []
    for c, collar in enumerate(column.collars):
        axial = forces[:, c, 0]
        moment = np.maximum(np.abs(forces[:, c, 1]), np.abs(forces[:, c, 2]))
        shear = (forces[:, c, 1] + forces[:, c, 2]) / collar.span(column.block.b)
        recorded = plastic[:, c] if plastic is not None else np.zeros((n, K.N_RECORDED))
        if collar.local_law == "fibre":  # its largest fibre stress (0 once broken)
            stress = recorded[:, RECORDED.index(FIBRE_STRESS)].copy()
            stress[recorded[:, RECORDED.index(FRACTURED)] > 0.0] = 0.0
        else:
            stress = collar.fibre_stress(axial, moment, recorded[:, RECORDED.index(1)])
        util = stress / collar.fy
        hit = np.nonzero(util >= 1.0)[0]
        fibre = forces[:, c, 5]
        largest = recorded[:, RECORDED.index(FIBRE_STRAIN)]
        fractured = recorded[:, RECORDED.index(FRACTURED)] > 0.0
        broken = np.nonzero(fractured)[0]
        hinges = recorded[:, [RECORDED.index(3), RECORDED.index(4)]]
        histories.append(
            CollarHistory(
                collar,
                axial,
                shear,
                moment,
                stress,
                util,
                float(t[hit[0]]) if hit.size else None,
                fibre_strain=fibre,
                # the state's running maximum (every step) where recorded, else the samples'
                max_fibre_strain=float(max(np.max(largest), np.max(fibre))) if n else 0.0,
                fracture_time=float(t[broken[0]]) if broken.size else None,
                end_moments=forces[:, c, 1:3].copy(),
                end_rotations=forces[:, c, 6:8].copy(),
                hinge_rotations=hinges,
                plastic_strain=forces[:, c, 4].copy(),
                fractured=fractured.astype(float),
            )
        )
    return histories


def _collar_outputs_at_rest(column: MultibodyColumn, q) -> np.ndarray:
    """The frame element's outputs (n_times, n_collars, OUT_SIZE) at positions q (n_times,
    n_bodies, 3) with the collars' plastic state at rest."""
    n = q.shape[0]
    ncol = column.col_a.size
    forces = np.zeros((n, ncol, OUT_SIZE))
    out = np.zeros((ncol, OUT_SIZE))
    state = column.collar_rest_state()
    flat = q.reshape(n, -1)
    for k in range(n):
        K.collar_forces(
            flat[k],
            column.col_a,
            column.col_b,
            column.col_r,
            column.col_props,
            np.zeros(0),
            out,
            state,
            False,
        )
        forces[k] = out
    return forces


def multibody_spectrum(
    block: Block,
    omega_ratios,
    amplitude_ratios,
    collars=(),
    *,
    contact: MultibodyContact = SOLID_CONTACT,
    settings: MultibodySettings = MULTIBODY_SETTINGS,
    pulse: str = "sine",
    free_time: float | None = None,
):
    """Overturning spectrum of the multibody column: mode code per (amplitude ratio, omega
    ratio), amplitudes normalised by g tan(alpha) of ``block``, Omega by its p. Runs in
    parallel over the cores; each run stops once its fate is certain (overturned, or after the
    pulse with less energy than any part needs to overturn). With collars, ``collar_yields``
    maps where a collar's extreme-fibre stress reaches f_y. Returns a
    :class:`rigid.spectrum.Spectrum` (model "multibody"). ``contact`` as rock_multibody's;
    ``settings``: ``dt``, the largest step (each pulse's is at most 1/400 of its period), and
    ``refine`` (the others do not apply). ``free_time``: how long (s) free rocking is followed
    after the pulse when the column's fate is not settled earlier (default 50 / p)."""
    from .spectrum import Spectrum, check_spectrum_grid

    require_parameter_object("contact", contact, MultibodyContact)
    require_parameter_object("settings", settings, MultibodySettings)
    _not_applicable(
        settings, ("dt_out", "touching_dt", "max_impacts_stored"), "a multibody spectrum"
    )
    omega_ratios, amplitude_ratios = check_spectrum_grid(omega_ratios, amplitude_ratios, pulse)
    column = build_column(
        block,
        cracked=contact.cracked,
        collars=collars,
        friction=contact.friction,
        crack_friction=contact.crack_friction,
    )
    restitution_normal, dt, refine = contact.restitution_normal, settings.dt, settings.refine
    _check_restitution(restitution_normal)
    h_max = dt if dt is not None else default_step(column)
    require_positive("dt (s)", h_max)
    if free_time is None:
        free_time = 50.0 / block.p
    uplift = block.uplift_acceleration("nonlinear")
    kernel_settings = K.Settings(
        h=float(h_max),  # each pulse's step: at most 1/400 of its period
        n_steps=0,  # each pulse's own
        refine=_check_refine(refine),
        e_n=float(restitution_normal),
        out_every=0,  # each pulse's own
        free_halves=bool(column.cracked and not column.collars),
        barrier=float(column.overturning_barrier()),
        early_exit=True,
        impact_tol=IMPACT_THRESHOLD * block.alpha,
        energy_scale=max(column.rocking_energy(), 1e-300),
        tol=SOLVER_TOLERANCE,
        max_iter=SOLVER_MAX_ITERATIONS,
    )
    bodies, contacts, collar_elements = column.kernel_bundles()
    start = time.perf_counter()
    codes, peaks, _status, utilisation = K.spectrum_modes(
        column.q_rest,
        bodies,
        contacts,
        collar_elements,
        omega_ratios * block.p,
        amplitude_ratios,
        uplift,
        pulse == "cosine",
        float(free_time),
        kernel_settings,
    )
    seconds = time.perf_counter() - start
    yields = utilisation >= 1.0 if column.collars else None
    return Spectrum(
        omega_ratios,
        amplitude_ratios,
        codes,
        peaks,
        yields,
        "multibody",
        pulse,
        seconds,
        bool(column.collars),
    )

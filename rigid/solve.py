"""Time history of a rocking block (solid, or one half of a cracked column with collars).

``rock`` chooses the solver:

* linear model, no collars, sine/cosine pulse: the exact closed form between events (corrected
  Eq. 8-11), impacts found by bracketing and root finding on the closed form;
* otherwise (nonlinear model, collars, or a recorded motion): Dormand-Prince 5(4) with its
  4th-order dense output, impacts located on the dense output to round-off.

At an impact (theta = 0) theta' -> nu theta'. Overturning: after the ground motion, a free block
passing its unstable equilibrium moving outward (|theta| > alpha, theta theta' > 0), or at any time
|theta| reaching pi/2. Modes are named in words: ``"after-impact"`` (Zhang & Makris's mode 1),
``"without-impact"`` (their mode 2), ``"safe"`` (it does not overturn). The summary adds the motion
(``"no uplift"``, ``"rocking"``, ``"overturned"``) and, with collars, their state (``"elastic"``,
``"yielded"``): "safe" speaks of overturning only, never of the collars.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from ..core.errors import InputError, require_history_rows, require_positive, require_range
from ..core.ground import NO_MOTION, GroundMotion, kernel_tables, require_motion
from ..core.motion import Motion, Release
from ..core.quantities import CollarPeaks, quantity, shared, to_dict, typed_result
from . import _kernels as K
from .block import Block, check_model
from .collars import Collar, collar_kernel_constants, collar_response, validate_collars

MODE_NAMES = {K.SAFE: "safe", K.AFTER_IMPACT: "after-impact", K.WITHOUT_IMPACT: "without-impact"}

UPLIFT_THRESHOLD = 1e-4  # rotations up to 1e-4 alpha are no uplift (multibody contact compliance)

DEFAULT_RTOL = 1e-10
DEFAULT_ATOL = 1e-12
AT_REST = Release()  # the default start: upright at rest


def motion_word(overturned: bool, max_abs_theta: float, alpha: float) -> str:
    """How the block moved: ``"overturned"``, ``"rocking"`` (it uplifted, |theta| beyond
    UPLIFT_THRESHOLD alpha, and did not overturn) or ``"no uplift"``."""
    if overturned:
        return "overturned"
    return "rocking" if max_abs_theta > UPLIFT_THRESHOLD * alpha else "no uplift"


def collar_state(
    max_utilisation: float, max_plastic_strain: float = 0.0, fractured: bool = False
) -> str:
    """ "fractured" (a plastic collar's fibre strain reached eps_u), "yielded" (a fibre reached
    f_y or flowed) or "elastic"."""
    if fractured:
        return "fractured"
    return "yielded" if max_utilisation >= 1.0 or max_plastic_strain > 0.0 else "elastic"


def elastic_collar_note(histories) -> str | None:
    """What an elastic-collar answer means where a collar passed f_y (None where none did):
    the SDOF model's springs stay elastic, so a stress past f_y is the elastic stress the
    steel cannot carry, and what follows (hinges, more slip, a break) is not modelled."""
    passed = [
        f"collar {k} (y = {h.collar.y:g} m, utilisation {h.max_utilisation:.3g})"
        for k, h in enumerate(histories, start=1)
        if h.max_utilisation >= 1.0
    ]
    if not passed:
        return None
    return (
        "elastic collars assumed: "
        + ", ".join(passed)
        + " passed f_y, so the stress past f_y is not one the steel can carry and what "
        "follows (hinges, more crack slip, a break) is not in this model; run the multibody "
        "or FEM model with plastic = true collars for it"
    )


def verdict(summary: dict) -> str:
    """The motion and, with collars, their state, from a rigid summary: e.g. ``"rocking;
    collars yielded (max utilisation 26.7)"``, ``"overturned (after-impact)"``."""
    words = summary["motion"]
    if summary["overturned"]:
        words += f" ({summary['mode']})"
    if "collar_state" in summary:
        words += (
            f"; collars {summary['collar_state']} "
            f"(max utilisation {summary['collar_max_utilisation']:.3g}"
            + (", elastic collars assumed" if summary.get("collar_note") else "")
            + ")"
        )
    return words


@dataclass
class CollarHistory:
    """Forces and stress of one collar over time (SI units, tension positive)."""

    collar: Collar
    axial_force: np.ndarray = field(repr=False)
    lateral_force: np.ndarray = field(repr=False)
    end_moment: np.ndarray = field(repr=False)
    stress: np.ndarray = field(repr=False)
    utilisation: np.ndarray = field(repr=False)
    first_yield_time: float | None = None
    # the frame element's (multibody): extreme-fibre strain now and its largest value reached
    # (lumped hinges, colonna.core.collar_law), the time of fracture (None: it holds), and
    # per end (left, right) the signed moment, the rotation relative to the chord and the
    # hinge's plastic rotation (n_times, 2)
    fibre_strain: np.ndarray | None = field(default=None, repr=False)
    max_fibre_strain: float | None = None
    fracture_time: float | None = None
    end_moments: np.ndarray | None = field(default=None, repr=False)
    end_rotations: np.ndarray | None = field(default=None, repr=False)
    hinge_rotations: np.ndarray | None = field(default=None, repr=False)
    # accumulated plastic strain of the axial law (-) and the fracture flag (1 once broken)
    plastic_strain: np.ndarray | None = field(default=None, repr=False)
    fractured: np.ndarray | None = field(default=None, repr=False)

    @property
    def max_utilisation(self) -> float:
        return float(np.max(self.utilisation)) if self.utilisation.size else 0.0

    @property
    def ductility_demand(self) -> float | None:
        """Largest fibre strain / yield strain (None where the model has no fibre strain)."""
        if self.max_fibre_strain is None:
            return None
        return self.max_fibre_strain / self.collar.yield_strain


@dataclass
class RockingResult:
    """Response of a rocking block. Times in s, rotations in rad, angular velocities in rad/s."""

    time: np.ndarray = field(repr=False)
    theta: np.ndarray = field(repr=False)
    theta_dot: np.ndarray = field(repr=False)
    impact_times: np.ndarray = field(repr=False)
    impact_velocity_before: np.ndarray = field(repr=False)
    impact_velocity_after: np.ndarray = field(repr=False)
    overturned: bool
    mode: str
    impacts: int
    max_abs_theta: float
    overturn_time: float | None
    model: str
    solver: str
    block: Block
    collars: tuple = ()
    collar_histories: list = field(default_factory=list, repr=False)

    @property
    def alpha(self) -> float:
        return self.block.alpha

    @property
    def max_abs_theta_over_alpha(self) -> float:
        return self.max_abs_theta / self.block.alpha

    def summary(self) -> dict:
        """Plain-data summary (the CLI's ``--json`` object): :meth:`typed_summary` as a dict."""
        return to_dict(self.typed_summary())

    def typed_summary(self) -> RockingSummary:
        """The summary with the unit of every value (:class:`RockingSummary`)."""
        hists = self.collar_histories
        collars = None
        if hists:
            b = self.block.b
            collars = tuple(
                RockingCollarSummary(
                    y=h.collar.y,
                    max_stress=float(np.max(h.stress)),
                    max_utilisation=h.max_utilisation,
                    first_yield_time=h.first_yield_time,
                    axial_stiffness=h.collar.axial_stiffness(b),
                    lateral_stiffness=h.collar.lateral_stiffness(b),
                )
                for h in hists
            )
        utilisation = max(h.max_utilisation for h in hists) if hists else None
        yields = [h.first_yield_time for h in hists if h.first_yield_time is not None]
        summary = RockingSummary(
            verdict="",
            overturned=bool(self.overturned),
            mode=self.mode,
            motion=motion_word(self.overturned, self.max_abs_theta, self.block.alpha),
            impacts=int(self.impacts),
            max_abs_theta=float(self.max_abs_theta),
            max_abs_theta_over_alpha=float(self.max_abs_theta_over_alpha),
            overturn_time=self.overturn_time,
            model=self.model,
            solver=self.solver,
            p=self.block.p,
            alpha=self.block.alpha,
            restitution=self.block.nu,
            restitution_housner=self.block.restitution_housner,
            top_load=self.block.top_load,
            critical_angle=self.block.critical_angle(self.model),
            collars=collars,
            collar_max_utilisation=utilisation,
            collar_state=None if utilisation is None else collar_state(utilisation),
            collar_first_yield_time=min(yields) if yields else None,
            collar_law="elastic" if hists else None,  # the SDOF springs never yield nor break
            collar_note=elastic_collar_note(hists),
        )
        return replace(summary, verdict=verdict(to_dict(summary)))


@typed_result
@dataclass(frozen=True, kw_only=True)
class RockingCollarSummary(CollarPeaks):
    """One collar of a rocking block's summary (its elastic springs, paper Eq. 14-15): the
    peaks every model's collar gives (CollarPeaks), then its springs."""

    axial_stiffness: float = quantity("N/m", "axial spring K_a = E A / L (Eq. 14)")
    lateral_stiffness: float = quantity("N/m", "lateral spring K_l = 12 E I / L^3 (Eq. 15)")


@typed_result
@dataclass(frozen=True, kw_only=True)
class RockingSummary:
    """What a rocking-block run (:func:`rock`) answers, SI units; the collar keys only with
    collars. ``RockingResult.summary()`` is its dict, in this order (the keys the models share:
    colonna.core.quantities.SHARED)."""

    # first: what a person reads first
    verdict: str = shared("verdict")
    overturned: bool = shared("overturned")
    mode: str = shared("mode")
    motion: str = shared("motion")
    impacts: int = shared("impacts")
    max_abs_theta: float = shared("max_abs_theta")
    max_abs_theta_over_alpha: float = shared("max_abs_theta_over_alpha")
    overturn_time: float | None = shared("overturn_time")
    model: str = quantity("", "linear or nonlinear equation of motion")
    solver: str = quantity("", "the solver used (closed form or Dormand-Prince)")
    p: float = shared("p")
    alpha: float = shared("alpha")
    restitution: float = quantity("-", "coefficient of restitution nu used at impacts")
    restitution_housner: float = shared("restitution_housner")
    top_load: float = shared("top_load")
    critical_angle: float = quantity("rad", "rotation of the free block's unstable equilibrium")
    collars: tuple[RockingCollarSummary, ...] | None = quantity(
        "", "per collar (RockingCollarSummary); only with collars", omit_when_none=True
    )
    collar_max_utilisation: float | None = shared("collar_max_utilisation", present_with="collars")
    collar_state: str | None = shared("collar_state", present_with="collars")
    collar_first_yield_time: float | None = shared(
        "collar_first_yield_time", present_with="collars"
    )
    collar_law: str | None = quantity(
        "", "the collars' law: elastic (the SDOF springs never yield)", present_with="collars"
    )
    collar_note: str | None = quantity(
        "", "what the elastic answer means where a collar passed f_y", omit_when_none=True
    )


def kernel_block_constants(block: Block, model: str, vertical: bool = False):
    """(p, alpha, uplift level / g, ground scale, lambda) as the kernels take them.

    The nonlinear kernel takes the top load's lambda itself. The linear model with a top load is
    the linear free block with p' = p sqrt(1 + 2 lambda), alpha' = alpha (1 + lambda) / (1 + 2
    lambda) and the ground acceleration scaled by 1 / (1 + 2 lambda) (see rigid.block), so it
    gets those constants and lambda = 0; with vertical ground motion that equivalence fails and
    its kernel takes lambda too."""
    lam = block.load_ratio
    if model == "nonlinear" or vertical:
        return block.p, block.alpha, block.uplift_acceleration(model) / block.g, 1.0, lam
    stiffening = 1.0 + 2.0 * lam
    alpha = block.alpha * (1.0 + lam) / stiffening
    return block.p * math.sqrt(stiffening), alpha, alpha, 1.0 / stiffening, 0.0


def kernel_params(
    block: Block,
    ground: GroundMotion,
    collars=(),
    model: str = "linear",
    initial_tilt: float = 0.0,
    initial_angular_velocity: float = 0.0,
    vertical: GroundMotion = NO_MOTION,
):
    """Parameter vector and record arrays for the kernels (ground NoMotion: free rocking).

    ``vertical``: the vertical ground acceleration (upward positive), a pulse, a record or
    NoMotion; it is appended to the record arrays as a table (see rigid._kernels)."""
    check_model(model)
    require_motion("ground", ground)
    g = block.g
    nonlinear = model == "nonlinear"
    has_vertical = require_motion("vertical", vertical).moves
    p, alpha, uplift, scale, load = kernel_block_constants(block, model, has_vertical)
    ka, kl = collar_kernel_constants(block, collars)
    rec_t, rec_a, n_horizontal, has_vertical = kernel_tables(ground, vertical, scale)
    rec_a = rec_a / g
    # the kernels compute a harmonic motion in closed form and read any other from its table
    sine = ground.sine_form
    if sine is not None:
        kind, ag, omega, phase, t_end = (
            K.GROUND_HARMONIC,
            scale * sine.amplitude / g,
            sine.omega,
            sine.phase,
            sine.duration,
        )
    elif ground.moves:
        kind, ag, omega, phase, t_end = K.GROUND_RECORD, 0.0, 0.0, 0.0, ground.end_time
    else:
        kind, ag, omega, phase, t_end = K.GROUND_NONE, 0.0, 0.0, 0.0, 0.0
    P = K.make_params(
        p, alpha, nonlinear, kind, ag, omega, phase, t_end, ka, kl, block.nu, uplift, load
    )
    P[K.P_NHREC] = n_horizontal
    P[K.P_VERT] = 1.0 if has_vertical else 0.0
    require_range(
        "release.tilt (rad)",
        initial_tilt,
        -0.5 * math.pi,
        0.5 * math.pi,
        range_text="(-pi/2, pi/2)",
    )
    P[K.P_TH0] = initial_tilt
    P[K.P_OM0] = _as_finite("release.angular_velocity (rad/s)", initial_angular_velocity)
    return P, rec_t, rec_a


def _as_finite(name: str, value) -> float:
    value = float(value)
    if not math.isfinite(value):
        raise InputError(f"{name} = {value!r} is not a finite number")
    return value


@dataclass(frozen=True)
class SdofSettings:
    """How the SDOF rocking equation is integrated and stored (the model itself is ``rock``'s
    ``model``).

    dt_out:  output interval, s (None: 1/200 of the shortest of 1/p and 2 pi/Omega);
    rtol, atol: the DOPRI5 integrator's relative and absolute error tolerances (the closed form
             of the linear model needs none);
    max_impacts_stored: how many impacts keep their time and velocities (all are counted).
    """

    dt_out: float | None = None
    rtol: float = DEFAULT_RTOL
    atol: float = DEFAULT_ATOL
    max_impacts_stored: int = 20_000


def require_parameter_object(name: str, value, kind: type):
    """``value`` itself, or an InputError naming the parameter and the object it takes."""
    if not isinstance(value, kind):
        raise InputError(f"{name} = {value!r} is not a colonna.{kind.__name__}")
    return value


def rock(
    block: Block,
    motion: Motion,
    collars=(),
    *,
    model: str = "linear",
    release: Release = AT_REST,
    settings: SdofSettings = SdofSettings(),
) -> RockingResult:
    """Rocking response of ``block`` to ``motion.ground`` (a pulse, a record, or NoMotion(): free
    rocking; any colonna.core.ground.GroundMotion: a sine_form is solved exactly, any other motion
    is read from its acceleration_table), starting at rest upright, or released at t = 0 from
    ``release.tilt`` (rad) with ``release.angular_velocity`` (rad/s). ``motion.vertical``: the
    vertical ground acceleration (upward positive; a pulse or a record), which scales the weight
    by (g + vg'') / g and the uplift level with it (Eq. 1-2). ``motion.duration``: end of the
    computed history, s (default: end of the ground motion + 20 / p). ``settings``: the output
    interval, tolerances and impact storage (:class:`SdofSettings`).
    """
    require_parameter_object("motion", motion, Motion)
    require_parameter_object("release", release, Release)
    require_parameter_object("settings", settings, SdofSettings)
    ground, duration, vertical = motion.ground, motion.duration, motion.vertical
    initial_tilt, initial_angular_velocity = release.tilt, release.angular_velocity
    dt_out, rtol, atol = settings.dt_out, settings.rtol, settings.atol
    max_impacts_stored = settings.max_impacts_stored
    check_model(model)
    collars = validate_collars(collars, block)
    P, rec_t, rec_a = kernel_params(
        block, ground, collars, model, initial_tilt, initial_angular_velocity, vertical
    )
    p = block.p
    t_ground = max(ground.end_time, vertical.end_time)  # motions checked by kernel_params
    if not ground.moves and initial_tilt == 0.0 and initial_angular_velocity == 0.0:
        raise InputError(
            "no ground motion and no initial tilt or angular velocity: the block stays at rest"
        )
    if duration is None:
        duration = t_ground + 20.0 / p
    require_positive("duration (s)", duration)
    sine = ground.sine_form
    if dt_out is None:
        scale = 1.0 / p
        if sine is not None:
            scale = min(scale, 2.0 * math.pi / sine.omega)
        dt_out = scale / 200.0
    require_positive("dt_out (s)", dt_out)
    n_max = require_history_rows(duration, dt_out)
    impacts = np.zeros((max_impacts_stored, 3))

    closed_form = model == "linear" and not collars and sine is not None and P[K.P_VERT] == 0.0
    if closed_form:
        segs = np.zeros((max(4 * max_impacts_stored, 1000), 6))
        status, n_imp, max_theta, t_end, n_seg, t_over = K.linear_run(
            P, duration, False, segs, impacts
        )
        time = np.arange(n_max) * dt_out
        time = time[time <= duration + 1e-12 * duration]
        if status == K.OVERTURNED:
            time = time[time <= t_over]
        theta, theta_dot = _evaluate_segments(segs[: min(n_seg, segs.shape[0])], P, time)
        solver = "closed-form"
    else:
        out = np.zeros((n_max, 3))
        status, n_imp, max_theta, t_end, n_out, t_over = K.rk_run(
            P, rec_t, rec_a, duration, rtol, atol, False, dt_out, out, impacts
        )
        time, theta, theta_dot = out[:n_out, 0].copy(), out[:n_out, 1].copy(), out[:n_out, 2].copy()
        solver = "dopri5"
    n_stored = min(n_imp, impacts.shape[0])
    overturned = status == K.OVERTURNED
    if overturned:
        # the history ends where the block lies down
        fallen = np.nonzero(np.abs(theta) >= 0.5 * math.pi)[0]
        if fallen.size:
            time, theta, theta_dot = (a[: fallen[0] + 1] for a in (time, theta, theta_dot))
        max_theta = 0.5 * math.pi
    mode = MODE_NAMES[K.AFTER_IMPACT if n_imp else K.WITHOUT_IMPACT] if overturned else "safe"
    result = RockingResult(
        time=time,
        theta=theta,
        theta_dot=theta_dot,
        impact_times=impacts[:n_stored, 0].copy(),
        impact_velocity_before=impacts[:n_stored, 1].copy(),
        impact_velocity_after=impacts[:n_stored, 2].copy(),
        overturned=overturned,
        mode=mode,
        impacts=int(n_imp),
        max_abs_theta=float(
            max_theta if overturned else max(max_theta, np.max(np.abs(theta), initial=0.0))
        ),
        overturn_time=float(t_over) if overturned else None,
        model=model,
        solver=solver,
        block=block,
        collars=collars,
    )
    result.collar_histories = [_collar_history(time, theta, block.b, c) for c in collars]
    return result


def _evaluate_segments(segs: np.ndarray, P: np.ndarray, time: np.ndarray):
    """Vectorised evaluation of closed-form pieces (t0, s, A, B, C, t1); zero (at rest) between."""
    theta = np.zeros_like(time)
    theta_dot = np.zeros_like(time)
    if segs.size == 0:
        return theta, theta_dot
    t0, t1 = segs[:, 0], segs[:, 5]
    k = np.searchsorted(t0, time, side="right") - 1
    inside = (k >= 0) & (time <= t1[np.clip(k, 0, None)] + 1e-14)
    k = k[inside]
    t = time[inside]
    p = math.sqrt(P[K.P_P2])
    s, A, B, C = segs[k, 1], segs[k, 2], segs[k, 3], segs[k, 4]
    tau = t - t0[k]
    psi = P[K.P_OMEGA] * t + P[K.P_PHASE]
    ch, sh = np.cosh(p * tau), np.sinh(p * tau)
    theta[inside] = s * P[K.P_ALPHA] + C * np.sin(psi) + A * ch + B / p * sh
    theta_dot[inside] = C * P[K.P_OMEGA] * np.cos(psi) + A * p * sh + B * ch
    return theta, theta_dot


def _collar_history(time, theta, b, collar) -> CollarHistory:
    r = collar_response(theta, b, collar)
    yielded = np.nonzero(r["utilisation"] >= 1.0)[0]
    first = float(time[yielded[0]]) if yielded.size else None
    return CollarHistory(
        collar,
        r["axial_force"],
        r["lateral_force"],
        r["end_moment"],
        r["stress"],
        r["utilisation"],
        first,
    )

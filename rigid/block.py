"""The rocking block: a rigid rectangle 2b wide and 2h tall on a rigid base.

Notation follows the source paper and ``docs/theory.md`` (section 2, Conventions; the
derivations of this module are in its sections 3-5): ``b`` and ``h`` are the half width and half
height of the rocking block (for a cracked column, of one half column: the full column is 4b wide).

    R = sqrt(b^2 + h^2),  alpha = atan(b / h),  J0 = 4/3 m R^2,
    p = sqrt(m g R / J0) = sqrt(3 g / (4 R))

Housner's coefficient of restitution for a rectangular block (the paper's Eq. 12 with the sin^2
restored) is ``nu = 1 - (2 m R^2 / J0) sin^2(alpha) = 1 - 1.5 sin^2(alpha)``.

Top load: a vertical dead load P (N, without mass: the weight of an architrave or of an arch
springing carried by the block) acting at the centre of the block's top. With lambda = P / (m g),
rocking on the corner s = sign(theta), the gravity moment about that corner per m g R is

    sin(s alpha - theta) + lambda [sin(s alpha - theta) - cos(alpha) sin(theta)]

(the load's arm is b cos(theta) - 2h sin(theta), twice the centre of mass's height), so that

    uplift at |ug''| = g tan(alpha) (1 + lambda)                                   (Eq. 2 with P)
    unstable equilibrium theta_c = atan((1 + lambda) / (1 + 2 lambda) tan(alpha))  (< alpha)
    linearised: theta'' = p^2 (1 + 2 lambda) theta - p^2 ((1 + lambda) s alpha + ug''/g), the
    free block's linear equation with p' = p sqrt(1 + 2 lambda), alpha' = alpha (1 + lambda) /
    (1 + 2 lambda) and ug''/g scaled by 1 / (1 + 2 lambda).

The load has no mass, so it gives no impulse at an impact: Housner's restitution is unchanged.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..core.constants import STANDARD_GRAVITY
from ..core.errors import InputError, require_positive, require_range
from ..core.ground import PULSE_KINDS, HarmonicPulse, cosine_pulse, sine_pulse

MODELS = ("linear", "nonlinear")


def housner_restitution(alpha: float) -> float:
    """Housner's angular-velocity ratio at impact, 1 - 1.5 sin^2(alpha) (corrected Eq. 12)."""
    return 1.0 - 1.5 * math.sin(alpha) ** 2


@dataclass(frozen=True)
class Block:
    """A rigid rectangular block 2b x 2h (m) of mass ``mass`` (kg) rocking on a rigid base.

    ``restitution`` is the ratio of angular velocities after/before an impact; ``None`` means
    Housner's value. ``mass`` may be ``None`` for dimensionless studies of a free block (the motion
    does not depend on it); collars need it.

    >>> blk = Block.from_dimensionless(p=2.14, alpha=0.25, restitution=0.9)
    >>> round(blk.p, 6), round(blk.alpha, 6)
    (2.14, 0.25)
    >>> round(Block(b=0.2, h=2.0, mass=1.0).nu, 4)   # Housner: 1 - 1.5 sin^2(atan(0.1))
    0.9851
    """

    b: float
    h: float
    mass: float | None = None
    restitution: float | None = None
    g: float = STANDARD_GRAVITY
    top_load: float = 0.0  # N, dead load at the centre of the top (see the module notes)

    def __post_init__(self):
        require_positive("b (block half width, m)", self.b)
        require_positive("h (block half height, m)", self.h)
        require_positive("g (gravity, m/s^2)", self.g)
        if self.mass is not None:
            require_positive("mass (kg)", self.mass)
        if self.restitution is not None:
            require_range(
                "restitution", self.restitution, 0.0, 1.0, closed_low=True, closed_high=True
            )
        require_range(
            "top_load (N)", self.top_load, 0.0, math.inf, closed_low=True, range_text="[0, inf)"
        )
        if self.top_load > 0.0:
            self.require_mass("a top load (it is measured against the block's weight)")

    # --- constructors -------------------------------------------------------------------
    @classmethod
    def from_dimensionless(
        cls,
        p: float,
        alpha: float,
        *,
        restitution: float | None = None,
        mass: float | None = None,
        g: float = STANDARD_GRAVITY,
    ) -> Block:
        """Block with frequency parameter ``p`` (rad/s) and slenderness ``alpha`` (rad).

        Inverts p^2 = 3 g / (4 R): R = 3 g / (4 p^2), b = R sin(alpha), h = R cos(alpha).
        """
        require_positive("p (frequency parameter, rad/s)", p)
        require_range(
            "alpha (slenderness angle, rad)", alpha, 0.0, math.pi / 2, range_text="(0, pi/2)"
        )
        radius = 3.0 * g / (4.0 * p * p)
        return cls(
            b=radius * math.sin(alpha),
            h=radius * math.cos(alpha),
            mass=mass,
            restitution=restitution,
            g=g,
        )

    @classmethod
    def from_density(
        cls,
        b: float,
        h: float,
        density: float,
        thickness: float,
        *,
        restitution: float | None = None,
        g: float = STANDARD_GRAVITY,
    ) -> Block:
        """Block of density (kg/m^3) and out-of-plane thickness (m): m = density * 2b * 2h * t."""
        require_positive("density (kg/m^3)", density)
        require_positive("thickness (m)", thickness)
        require_positive("b (block half width, m)", b)
        require_positive("h (block half height, m)", h)
        return cls(b=b, h=h, mass=density * 4.0 * b * h * thickness, restitution=restitution, g=g)

    # --- derived quantities ---------------------------------------------------------------
    @property
    def R(self) -> float:
        """Distance from a base corner to the centre of mass (m)."""
        return math.hypot(self.b, self.h)

    @property
    def alpha(self) -> float:
        """Slenderness angle atan(b/h) (rad)."""
        return math.atan2(self.b, self.h)

    @property
    def p(self) -> float:
        """Frequency parameter sqrt(m g R / J0) = sqrt(3 g / (4 R)) (rad/s)."""
        return math.sqrt(3.0 * self.g / (4.0 * self.R))

    @property
    def J0(self) -> float:
        """Moment of inertia about a base corner, 4/3 m R^2 (kg m^2)."""
        return 4.0 / 3.0 * self.require_mass("the moment of inertia") * self.R**2

    @property
    def nu(self) -> float:
        """Coefficient of restitution in use: the given one or Housner's. Housner's is negative
        past alpha = asin(sqrt(2/3)) (54.7 deg, a squat block), where his impact law no longer
        describes a block that rocks on: then a restitution must be given."""
        if self.restitution is not None:
            return self.restitution
        nu = housner_restitution(self.alpha)
        if nu < 0.0:
            raise InputError(
                f"Housner's restitution 1 - 1.5 sin^2(alpha) = {nu:.3g} is negative for this "
                f"squat block (alpha = {self.alpha:.3g} rad, above asin(sqrt(2/3)) = "
                f"{math.asin(math.sqrt(2.0 / 3.0)):.3g} rad): give a restitution in [0, 1]"
            )
        return nu

    @property
    def restitution_housner(self) -> float:
        return housner_restitution(self.alpha)

    @property
    def load_ratio(self) -> float:
        """lambda = top_load / (m g): the top load against the block's weight (-)."""
        if self.top_load == 0.0:
            return 0.0
        return self.top_load / (self.require_mass("the load ratio") * self.g)

    def uplift_acceleration(self, model: str = "nonlinear") -> float:
        """Minimum ground acceleration that starts rocking (Eq. 2-3), m/s^2.

        g tan(alpha) (1 + lambda) for the nonlinear equation, g alpha (1 + lambda) for the
        linearised one (lambda: :attr:`load_ratio`).
        """
        check_model(model)
        slope = math.tan(self.alpha) if model == "nonlinear" else self.alpha
        return self.g * slope * (1.0 + self.load_ratio)

    def critical_angle(self, model: str = "nonlinear") -> float:
        """Rotation of the unstable equilibrium of the free block (rad): alpha without a top
        load; atan((1 + lambda) / (1 + 2 lambda) tan(alpha)) with one (linearised: alpha (1 +
        lambda) / (1 + 2 lambda))."""
        check_model(model)
        lam = self.load_ratio
        if model == "nonlinear":
            return math.atan((1.0 + lam) / (1.0 + 2.0 * lam) * math.tan(self.alpha))
        return self.alpha * (1.0 + lam) / (1.0 + 2.0 * lam)

    def time_to_vertical(self, theta0: float) -> float:
        """Free rocking from rest at theta0 to the vertical, linear model (corrected Eq. 13), s.

        t = arccosh(1 / (1 - |theta0| / alpha)) / p: a quarter of the free-rocking period, not the
        period as the paper prints. Only defined for 0 < |theta0| < alpha.
        """
        ratio = abs(theta0) / self.alpha
        require_range("theta0 / alpha", ratio, 0.0, 1.0)
        return math.acosh(1.0 / (1.0 - ratio)) / self.p

    def require_mass(self, what: str) -> float:
        if self.mass is None:
            raise InputError(
                f"mass is needed for {what}: give the block mass (or density and thickness)"
            )
        return self.mass


def check_model(model: str) -> str:
    if model not in MODELS:
        raise InputError(f"model = {model!r} is not one of {', '.join(MODELS)}")
    return model


# Omega / p of a pulse, ends included (a study file's ground.omega_ratio too): past these a
# pulse lasts thousands of rocking periods, or a millionth of one
OMEGA_RATIO_RANGE = (1e-3, 1e3)


def pulse_from_ratios(
    block: Block, kind: str, omega_ratio: float, amplitude_ratio: float, model: str = "linear"
) -> HarmonicPulse:
    """Pulse with Omega = omega_ratio * p and a_p = amplitude_ratio * a_uplift(model).

    The amplitude ratio is normalised by g alpha (linear model) or g tan(alpha) (nonlinear).
    """
    check_model(model)
    require_range(
        "omega ratio (Omega / p)",
        omega_ratio,
        *OMEGA_RATIO_RANGE,
        closed_low=True,
        closed_high=True,
    )
    if kind not in PULSE_KINDS:
        raise InputError(f"pulse = {kind!r} is not one of {', '.join(PULSE_KINDS)}")
    uplift = block.uplift_acceleration(model)
    if not abs(amplitude_ratio) >= 1.0:
        raise InputError(
            f"amplitude ratio = {amplitude_ratio:g} is below uplift: it must be "
            ">= 1 (a_p / a_uplift)"
        )
    make = sine_pulse if kind == "sine" else cosine_pulse
    return make(amplitude_ratio * uplift, omega_ratio * block.p, uplift)

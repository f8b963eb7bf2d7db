"""A crack along part of the column's height: the intact rest of the mid-plane is a cohesive
interface (issue 51).

The mesh of a cracked column splits the mid-plane along the whole height (two bodies, the crack
faces' nodes distinct): each left-face node and the right-face node at its height are a *pair*.
On the cracked part the pairs are today's crack, held only by the crack's contact (exact or
penalty, fem/model.py). On the rest each pair also carries the cohesive law of
:mod:`colonna.fem.cohesive` (bilinear, Benzeggagh-Kenane mixed mode) with the stone's tensile
strength f_t and fracture energy G_f ([stone] ft, Gf; s = f_t, G_II = G_I, eta = 2) over its
area A = t l_trib (thickness t, tributary length along the crack), with the penalty
K = ``ALPHA`` E / h (h: the width of the crack face's element, the crack contact's penalty with
factor 1), and at least ``SOFTENING_FLOOR`` f_t^2 / (2 G_f). Its damage d grows with the
largest separation and never decreases: a pair at d = 1 is a broken one, and only the contact
holds it (the crack has grown to it).

How the law meets the contact: the contact acts on every pair, bonded or not, and carries the
compression and the Coulomb friction; the cohesive interface adds the law's tension
(1 - d) K <delta_n> and shear (1 - d) K delta_s (cohesion on top of friction, as Mohr-Coulomb;
fem._kernels.cohesive_forces). The separation is measured in the frame of the two halves'
mean rotation, so that rocking does not read as opening.

A crack of part depth ([column] crack_depth d, the fraction of the thickness it runs through,
0 < d < 1): a smeared 2D idealisation. Along the cracked part each pair keeps a *ligament*, the
intact (1 - d) of the thickness: it carries the same cohesive law over the area (1 - d) A, on top
of the crack's contact (which carries compression and friction through the full thickness), and
starts undamaged; the uncracked part stays fully cohesive. d = 1 is the through crack (the
cracked pairs broken at the start, nothing else changes); d -> 0 the intact mid-plane. The
through crack is the broken pairs: a ligament that fully damages is the crack deepening to the
full thickness there, and counts in the crack's length; the K_I at the tips is the through
crack's. What it does not capture: the part-depth crack's own front in the thickness (its 3D
tip, and K_I along it), and the bending of the ligament about the crack's front.

Energy: the springs' elastic energy (1 - d) K (<delta_n>^2 + delta_s^2) A / 2 joins the crack
contact's energy; damage dissipates K (<delta_n>^2 + delta_s^2) A / 2 times its increment (the
energy release of a secant damage law), added to the dissipated tally; pulled apart in mode I a
pair dissipates G_f A in all.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy import sparse

# the cohesive penalty K = ALPHA E / h: alpha = 1 is the crack contact's own penalty (factor 1),
# as stiff as the stone next to it, so that it does not shorten the stable step (docs/physics.md,
# "The cohesive mid-plane")
ALPHA = 1.0
ETA = 2.0  # Benzeggagh-Kenane exponent (with s = f_t and G_II = G_I it does not matter)
# the penalty is at least this many times f_t^2 / (2 G_f), where the law's peak would come at its
# full damage: on crack-face elements too wide for alpha E / h (coarse meshes, a strong or
# brittle stone) K is raised so that the softening takes at least half of the separation
SOFTENING_FLOOR = 2.0


@dataclass(frozen=True)
class Crack:
    """A crack as given: ``extent`` (from, to) heights (m; None: the full height) and ``depth``,
    the fraction of the thickness it runs through (0 < depth <= 1; 1: a through crack)."""

    extent: tuple | None = None
    depth: float = 1.0


@dataclass(frozen=True)
class CohesiveInterface:
    """The mid-plane's node pairs (left-face node, right-face node at its height, sorted by
    height) and what the kernel needs of them: area A (m^2), penalty K (Pa/m), the law's
    parameters (f_t, s, G_I, G_II, eta) and each pair's damage at the start (1: cracked, 0:
    intact stone); ``crack`` the (from, to) heights (m) the crack was given."""

    left: np.ndarray = field(repr=False)
    right: np.ndarray = field(repr=False)
    heights: np.ndarray = field(repr=False)
    tributary: np.ndarray = field(repr=False)  # m, along the crack
    area: np.ndarray = field(repr=False)
    stiffness: np.ndarray = field(repr=False)
    law: np.ndarray = field(repr=False)
    damage0: np.ndarray = field(repr=False)
    crack: tuple = (0.0, 0.0)
    # the fraction of the thickness the crack runs through ([column] crack_depth; 1: through)
    depth: float = 1.0
    # the pairs on the crack that keep a ligament, the intact (1 - depth) of the thickness
    # (none at depth 1)
    ligament: np.ndarray | None = field(default=None, repr=False)

    @property
    def bonded(self) -> np.ndarray:
        """The pairs intact at the start."""
        return self.damage0 < 1.0

    @property
    def part_depth(self) -> bool:
        """A crack that runs through part of the thickness only (a ligament on the crack)."""
        return self.depth < 1.0


def ligament_area(area: np.ndarray, on_crack: np.ndarray, depth: float) -> np.ndarray:
    """The pairs' areas (m^2) with a crack of part ``depth`` along ``on_crack``: the ligament
    (1 - depth) A there, A elsewhere; the areas as they are at depth 1 (the through crack's
    pairs are broken, :func:`cracked_pairs`)."""
    if depth >= 1.0:
        return area
    return np.where(on_crack, (1.0 - depth) * area, area)


def cracked_pairs(heights: np.ndarray, crack: tuple, height: float) -> np.ndarray:
    """Which pairs, at ``heights`` (m), lie on the crack (from, to): those strictly between its
    ends, and those at an end that is the column's base or top (a crack reaching the base
    splits the base pair); none where from = to. The pair at an inner end is the crack's tip,
    intact."""
    low, high = crack
    tol = 1e-9 * height
    if high - low <= tol:
        return np.zeros(heights.size, dtype=bool)
    above = (heights > low + tol) | ((low <= tol) & (heights >= -tol))
    below = (heights < high - tol) | ((high >= height - tol) & (heights <= height + tol))
    return above & below


def springs(interface: CohesiveInterface | None, n_dofs: int) -> sparse.csr_matrix:
    """Stiffness of the intact pairs' undamaged springs K A, on both dofs of each pair (the
    law's stiffness is isotropic, so the matrix holds for any rotation of the halves; damage
    only softens it): what the stable step's bound adds between the bodies."""
    if interface is None or not np.any(interface.bonded):
        return sparse.csr_matrix((n_dofs, n_dofs))
    on = interface.bonded
    k = interface.stiffness[on] * interface.area[on]
    rows, cols, vals = [], [], []
    for dof in (0, 1):
        i, j = 2 * interface.left[on] + dof, 2 * interface.right[on] + dof
        rows += [i, j, i, j]
        cols += [i, j, j, i]
        vals += [k, k, -k, -k]
    return sparse.csr_matrix(
        (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
        shape=(n_dofs, n_dofs),
    )


def crack_columns(
    interface: CohesiveInterface,
    damage: np.ndarray,
    energy: np.ndarray,
    x: np.ndarray,
    rotations: np.ndarray,
    E_prime: float,
) -> dict:
    """A history row's crack columns from one state's damage, cohesive energies, positions x
    (flat) and the bodies' rotations (rad): the crack's length (m, the tributary lengths of the
    broken pairs, d = 1), its lowest and highest broken pair (m; NaN without one), the length
    of the partly damaged pairs (the softening zone, m), the springs' elastic and dissipated
    energy (J), and the largest mode-I stress intensity at a crack tip (Pa m^0.5,
    :func:`tip_stress_intensity`; NaN without a tip)."""
    broken = damage >= 1.0
    at = interface.heights[broken]
    ligament = {}
    if interface.part_depth:  # the ligament's largest damage (NaN: no pair on the crack)
        on = interface.ligament
        ligament["crack_ligament_damage"] = float(np.max(damage[on])) if np.any(on) else math.nan
    return {
        **ligament,
        "crack_length": float(np.sum(interface.tributary[broken])),
        "crack_from": float(at.min()) if at.size else math.nan,
        "crack_to": float(at.max()) if at.size else math.nan,
        "crack_softening": float(np.sum(interface.tributary[(damage > 0.0) & ~broken])),
        "crack_tip_KI": tip_stress_intensity(interface, broken, x, rotations, E_prime),
        "energy_cohesive": float(energy[0]),
        "energy_cohesive_dissipated": float(energy[1]),
    }


TIP_FIT_PAIRS = 4  # the broken pairs nearest a tip that the displacement correlation fits


def tip_stress_intensity(
    interface: CohesiveInterface,
    broken: np.ndarray,
    x: np.ndarray,
    rotations: np.ndarray,
    E_prime: float,
) -> float:
    """The largest K_I (Pa m^0.5) over the crack's tips by displacement correlation
    (:func:`colonna.fem.fracture.stress_intensities`): a tip is an intact pair next to a run of
    broken ones; the TIP_FIT_PAIRS broken pairs nearest it (r from one to four elements behind
    it), their opening read in the frame of the halves' mean rotation, K*(r) extrapolated
    linearly to r = 0. NaN without a tip or with fewer than two broken pairs behind it.

    The column's mesh has no refined tip and the near-tip field of a split column (a double
    cantilever beam, arms half the width wide) is short: the fit keeps to the nearest pairs.
    Against the double cantilever beam's K_I = 2 sqrt(3) P a / (t h^1.5) (1 + 0.64 h / a)
    (Tada, Paris & Irwin, 3rd ed., 2000) see docs/physics.md: a screening value against K_IC."""
    from .fracture import stress_intensities

    n = broken.size
    if n < 3 or not np.any(broken) or np.all(broken):
        return math.nan
    mean = float(np.mean(rotations))
    normal = np.array([math.cos(mean), math.sin(mean)])
    along = np.array([-math.sin(mean), math.cos(mean)])
    jump = x.reshape(-1, 2)[interface.right] - x.reshape(-1, 2)[interface.left]
    opening, sliding = jump @ normal, jump @ along
    y = interface.heights
    best = math.nan
    for k in range(n - 1):
        if broken[k] == broken[k + 1]:
            continue
        tip, step = (k + 1, -1) if broken[k] else (k, 1)  # the intact pair; the run behind it
        run: list[int] = []
        j = tip + step
        while 0 <= j < n and broken[j] and len(run) < TIP_FIT_PAIRS:
            run.append(j)
            j += step
        if len(run) < 2:
            continue
        near = np.array(run)
        K_I, _ = stress_intensities(
            np.abs(y[near] - y[tip]), opening[near], sliding[near], E_prime, 0.0, math.inf
        )
        best = K_I if not (best >= K_I) else best
    return float(best)


def crack_summary(interface: CohesiveInterface, history: dict, KIC: float) -> dict:
    """A run's answers about its partial crack from its history (crack_columns): the crack's
    length at the start and the end (m), its growth (m) and whether it grew (by at least one
    pair), the largest K_I at a tip and its time, K_I / K_IC, and the work the cohesive
    interface dissipated (J). With a crack of part depth, the through crack's (a ligament broken
    is the crack deepened to the full thickness there, and grows it), and the crack's depth,
    the extent of its ligament on the mesh's pairs (m) and the ligament's largest damage."""
    length = np.asarray(history["crack_length"], dtype=float)
    KI = np.asarray(history["crack_tip_KI"], dtype=float)
    smallest_pair = float(np.min(interface.tributary))
    start, end = float(length[0]), float(length[-1])
    finite = np.isfinite(KI)
    at = int(np.argmax(np.where(finite, KI, -np.inf))) if np.any(finite) else None
    KI_max = float(KI[at]) if at is not None else None
    ligament = {}
    if interface.part_depth:
        damage = np.asarray(history["crack_ligament_damage"], dtype=float)
        ligament = {
            "crack_depth": interface.depth,
            "crack_ligament_length": float(np.sum(interface.tributary[interface.ligament])),
            "crack_ligament_damage_max": float(np.nanmax(damage))
            if np.any(np.isfinite(damage))
            else None,
        }
    return {
        **ligament,
        "crack_length_initial": start,
        "crack_length_final": end,
        "crack_growth": end - start,
        "crack_grew": bool(end - start >= 0.5 * smallest_pair),
        "crack_tip_KI_max": KI_max,
        "crack_tip_KI_time": float(history["t"][at]) if at is not None else None,
        "crack_tip_KI_ratio": KI_max / KIC if KI_max is not None else None,
        "cohesive_dissipated": float(history["energy_cohesive_dissipated"][-1]),
    }

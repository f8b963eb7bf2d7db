"""Convergence of the fibre-section collar with its fibres and sections (issue 36): the default
study's collar (60 x 8 mm, L 0.45 m, S235, E_h = 0.01 E, eps_u = 0.15), its ends slipping
laterally with the chord held (u = 0, rotations 0: the two halves hold the collar between them),
driven by colonna.core.collar.response.

Prints, per (n_sections, n_fibres), the end moment and membrane force at 5 and 20 times the
first-yield slip d_y = M_y L^2 / (6 E I) and the slip at fracture (the largest surface strain
reaching eps_u, interpolated between steps), and their differences from the finest
discretisation, and the resultant law's (``section = "resultant"``) against the same;
``--markdown`` prints the table of docs/collars.md.

    .venv/bin/python benchmarks/collar_convergence.py [--markdown]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from colonna.core.collar import Collar, response

DEFAULT = dict(y=1.0, t=0.008, h=0.06, length=0.45, fy=235e6, plastic=True, eps_u=0.15)
STEPS_PER_YIELD = 10  # slip steps per d_y
REACH = 400  # the largest slip, in d_y


def slip_history(collar: Collar, reach: float, steps_per_yield: int):
    """The lateral slip d (m) in steps of d_y / steps_per_yield up to reach d_y, and its rows
    (u1, v1, r1, u2, v2, r2): end 2 moves by d normal to the chord, nothing else."""
    dy = collar.yield_displacement()
    d = np.arange(0, int(reach * steps_per_yield) + 1) * dy / steps_per_yield
    rows = np.zeros((d.size, 6))
    rows[:, 4] = d
    return d, rows


def measures(collar: Collar, reach: float = REACH, steps_per_yield: int = STEPS_PER_YIELD):
    """End moment and membrane force at 5 and 20 d_y, and the slip at fracture (m; nan if none
    within the reach)."""
    dy = collar.yield_displacement()
    d, rows = slip_history(collar, reach, steps_per_yield)
    r = response(collar, rows)
    at = {m: int(round(m * steps_per_yield)) for m in (5, 20)}
    strain = r["largest_fibre_strain"]
    broken = np.nonzero(r["fractured"])[0]
    if broken.size:
        k = broken[0]
        e0, e1 = strain[k - 1], strain[k]
        fracture = d[k - 1] + (d[k] - d[k - 1]) * (collar.eps_u - e0) / (e1 - e0)
    else:
        fracture = float("nan")
    return {
        "M5": abs(r["M1"][at[5]]),
        "N5": r["N"][at[5]],
        "M20": abs(r["M1"][at[20]]),
        "N20": r["N"][at[20]],
        "fracture": fracture,
        "fracture_dy": fracture / dy,
    }


GRID = [(n_s, 20) for n_s in (3, 5, 7, 10, 15, 20)] + [(10, n_f) for n_f in (8, 12, 16, 30, 40)]
FINEST = (30, 40)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--markdown", action="store_true")
    args = parser.parse_args()
    rows: dict[tuple, dict] = {}
    for n_s, n_f in GRID + [FINEST]:
        start = time.perf_counter()
        rows[n_s, n_f] = measures(Collar(**DEFAULT, n_sections=n_s, n_fibres=n_f))
        rows[n_s, n_f]["seconds"] = time.perf_counter() - start
    rows["resultant", "-"] = measures(Collar(**DEFAULT, section="resultant"))
    ref = rows[FINEST]
    print(
        "| sections | fibres | M(5 d_y) kN m | N(5 d_y) kN | M(20 d_y) kN m | N(20 d_y) kN "
        "| slip at fracture mm (d_y) |"
    )
    print("|" + "---|" * 7)
    for key in GRID + [FINEST, ("resultant", "-")]:
        r = rows[key]

        def cell(name, scale, digits, r=r):
            diff = 100.0 * (r[name] / ref[name] - 1.0)
            return f"{r[name] * scale:.{digits}f} ({diff:+.2f} %)"

        print(
            f"| {key[0]} | {key[1]} | {cell('M5', 1e-3, 3)} | {cell('N5', 1e-3, 2)} | "
            f"{cell('M20', 1e-3, 3)} | {cell('N20', 1e-3, 2)} | "
            f"{r['fracture'] * 1e3:.2f} ({r['fracture_dy']:.1f}; "
            f"{100.0 * (r['fracture'] / ref['fracture'] - 1.0):+.2f} %) |"
        )
    if not args.markdown:
        for key in GRID + [FINEST]:
            print(key, f"{rows[key]['seconds']:.2f} s")


if __name__ == "__main__":
    main()

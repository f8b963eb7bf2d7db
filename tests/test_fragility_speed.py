"""The fragility study's speed-ups give the answers of the full runs (issue 37).

Pinned: the multibody model's outcome path (no histories) without its speed-ups is the full
run's steps; with them (the steps of a column at rest skipped, the contact problem's exact
solve by Gaussian elimination) it gives the full run's outcome, and its peak |theta| / alpha and
collar utilisation within the scatter of the contact solver's own tolerance, on records that
hold the column at rest, rock it and let it settle; a column at rest under a motion below the
uplift acceleration stays at rest; the shifted lognormal's origin is the suite's uplift
intensity, its curve is 0 up to it and the report names it.
"""

import json
import math

import numpy as np
import pytest

from colonna.core.ground import Record
from colonna.rigid.block import Block
from colonna.rigid.collars import Collar
from colonna.rigid.multibody import multibody_outcome, rock_multibody
from colonna.studies.cli import main
from colonna.studies.fragility.runner import uplift_intensity

# the half of the default column (4 m x 0.45 m, cracked; 2700 kg/m^3, thickness pi b)
HALF = Block(b=0.1125, h=2.0, mass=2700.0 * 0.225 * 4.0 * math.pi * 0.1125)
COLLARS = tuple(Collar(y=y, t=0.008, h=0.06) for y in (0.5, 2.0, 3.5))


def _record(parts, dt: float = 0.005) -> Record:
    """A record of sine segments: (duration s, amplitude over the half's g tan alpha, period s)
    one after the other, each a whole number of periods (no jump between them)."""
    t, a, start = [0.0], [0.0], 0.0
    for duration, ratio, period in parts:
        local = np.arange(dt, duration + 0.5 * dt, dt)
        t.extend(start + local)
        a.extend(ratio * HALF.uplift_acceleration() * np.sin(2.0 * math.pi * local / period))
        start += duration
    return Record(np.array(t), np.array(a), "segments")


def test_a_column_at_rest_under_a_motion_below_uplift_stays_at_rest():
    """Below g tan(alpha) of the half no part lifts (the whole column needs twice that): the
    full run and the fast one both leave the column at rest (|theta| at the contact
    solver's round-off, far below the uplift threshold 1e-4 alpha), collars unstrained."""
    record = _record([(2.0, 0.8, 0.4)])
    full = rock_multibody(HALF, record, COLLARS, cracked=True, duration=2.5).summary()
    fast = multibody_outcome(HALF, record, COLLARS, cracked=True, duration=2.5)
    assert not full["overturned"] and not fast.overturned
    assert full["max_abs_theta"] < 1e-8 * HALF.alpha
    assert fast.max_abs_theta < 1e-8 * HALF.alpha
    assert fast.impacts == full["impacts"] == 0
    assert fast.collar_max_utilisation < 1e-6


ROCKS = [(1.0, 0.8, 0.25), (0.8, 3.0, 0.8), (1.5, 0.5, 0.25)]  # rest, one strong cycle, rest
SETTLES = [(0.5, 0.6, 0.25), (0.6, 2.2, 0.6), (2.0, 0.3, 0.2)]  # rocks, then settles


def test_the_outcome_path_is_rock_multibody_s_run_without_its_history():
    """Without its speed-ups, the outcome path runs rock_multibody's steps: the same impacts and
    overturning, the peak |theta| (its every step against the history's rows every 1/200 p:
    at least as large, the same to 1e-5) and the collars' utilisation (at the steps'
    midpoints against the rows: to 1e-3)."""
    record = _record(ROCKS)
    full = rock_multibody(HALF, record, COLLARS, cracked=True, duration=4.0).summary()
    path = multibody_outcome(HALF, record, COLLARS, cracked=True, duration=4.0, fast=False)
    assert full["max_abs_theta"] > 0.5 * HALF.alpha  # it rocked
    assert path.overturned == full["overturned"]
    assert path.impacts == full["impacts"]
    assert path.max_abs_theta == pytest.approx(full["max_abs_theta"], rel=1e-5)
    assert path.max_abs_theta >= full["max_abs_theta"]
    assert path.collar_max_utilisation == pytest.approx(full["collar_max_utilisation"], rel=1e-3)


@pytest.mark.parametrize("parts", [ROCKS, SETTLES], ids=["rocks", "settles"])
def test_the_fast_path_stays_within_the_contact_solver_s_own_scatter(parts, monkeypatch):
    """The column's start of rocking amplifies the contact solver's round-off (its velocities
    at rest, 1e-11 m/s): rerun at the solver's tolerances 1e-9, 1e-10 (the model's) and
    1e-11, the peak |theta| and the collars' utilisation move by up to 1 % (measured). The
    fast path (at the model's tolerance) lies within twice that spread of the three runs, and
    every outcome (overturning, impacts) is theirs."""
    import colonna.rigid.multibody as multibody

    record = _record(parts)
    runs = []
    for tol in (1e-9, 1e-10, 1e-11):
        monkeypatch.setattr(multibody, "SOLVER_TOLERANCE", tol)
        runs.append(
            multibody_outcome(HALF, record, COLLARS, cracked=True, duration=4.0, fast=False)
        )
    monkeypatch.setattr(multibody, "SOLVER_TOLERANCE", 1e-10)
    fast = multibody_outcome(HALF, record, COLLARS, cracked=True, duration=4.0)
    for key in ("max_abs_theta", "collar_max_utilisation"):
        values = np.array([getattr(r, key) for r in runs])
        # three runs' range underestimates the scatter's: twice it on each side
        spread = 2.0 * max(np.ptp(values), 1e-6 * values.max())
        assert values.min() - spread <= getattr(fast, key) <= values.max() + spread, key
    assert {r.overturned for r in runs} == {fast.overturned}
    assert {r.impacts for r in runs} == {fast.impacts}


def test_the_outcome_path_refuses_plastic_collars():
    from colonna.core.errors import InputError

    plastic = (Collar(y=2.0, t=0.008, h=0.06, plastic=True),)
    with pytest.raises(InputError, match="plastic"):
        multibody_outcome(HALF, _record([(0.5, 0.5, 0.25)]), plastic, cracked=True)


# --- the shifted lognormal ------------------------------------------------------------------


def test_the_uplift_intensity_is_where_the_first_record_lifts_the_block():
    """Record i lifts the block once its scaled PGA reaches g tan alpha: at IM_i g tan alpha /
    PGA_i; the suite's origin is the least of these, 1 for PGA / (g tan alpha)."""
    uplift = HALF.uplift_acceleration()
    im = np.array([0.3, 0.5, 0.2])  # m/s
    pga = np.array([2.0, 1.0, 4.0])  # m/s^2
    assert uplift_intensity("pgv", im, pga, uplift) == pytest.approx(0.05 * uplift)
    assert uplift_intensity("pga_rocking", pga / uplift, pga, uplift) == 1.0


SHIFTED = """
[study]
name = "shifted"
kind = "fragility"
[column]
height = 4.0
width = 0.6
cracked = false
[ground]
pulse = "none"
[fragility]
suite = "suite.toml"
intensity = "pgv_rocking"
ladder = [0.05, 1.5]
steps = 16
models = ["sdof"]
design_intensity = 0.06
bootstrap = 10
fit = "shifted"
"""


def test_a_shifted_fragility_starts_at_the_uplift_intensity(tmp_path):
    """The SDOF lifts record i exactly above its own uplift level u_i = IM_i g tan alpha /
    PGA_i: the uplift counts at each level are #{u_i < level}; the fits' origin is min u_i,
    every curve is 0 up to it (the design intensity lies below it) and the report says which
    curve it fitted."""
    block = Block(b=0.3, h=2.0)
    for i, ratio in enumerate((1.5, 2.5, 4.0, 6.0)):
        omega = ratio * block.p
        t = np.linspace(0.0, 2.0 * math.pi / omega, 401)
        np.savetxt(tmp_path / f"p{i}.txt", np.column_stack([t, (1 + i) * np.sin(omega * t)]))
    (tmp_path / "suite.toml").write_text(
        "\n".join(f'[[record]]\nfile = "p{i}.txt"\nunits = "m/s2"\n' for i in range(4))
    )
    (tmp_path / "study.toml").write_text(SHIFTED)
    out = tmp_path / "out"
    assert main(["study", str(tmp_path / "study.toml"), "--out", str(out), "--workers", "1"]) == 0
    s = json.loads((out / "summary.json").read_text())
    levels = np.array(s["levels"])
    u = np.array(
        [r["intensity"] * s["block"]["uplift_acceleration"] / r["ims"]["pga"] for r in s["records"]]
    )
    assert s["fit"] == "shifted"
    assert s["origin"] == pytest.approx(u.min(), rel=1e-12)
    uplift = s["limit_states"]["sdof"]["uplift"]
    assert uplift["counts"] == [int(np.sum(u < x)) for x in levels]
    for state in s["limit_states"]["sdof"].values():
        for which in ("stripes", "ida"):
            entry = state.get(which)
            if entry and entry.get("fit"):
                assert entry["fit"]["origin"] == s["origin"]
                assert entry["probability"] == 0.0  # the design intensity is below the origin
    assert s["design_intensity"] < s["origin"]
    page = (out / "index.html").read_text()
    assert "shifted lognormal" in page

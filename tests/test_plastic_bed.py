"""A bed that yields where its material does (issue 48): the base contact as an
elastic-perfectly plastic Winkler bed, its pressure capped at the yield pressure and its
indentation kept.

Pinned: the law is the elastic one bit for bit where the bed does not yield (an elastic bed's
runs are unchanged); a rigid base pivoting on the bed matches the closed form of
:func:`colonna.fem.bed.winkler_plastic_pivot` (contact length, plastic zone, resultant); a FEM
run on a bed that yields closes its energy balance with the bed's plastic work and never
presses the bed past its yield; lead yields by default, and a bed that would yield under the
column at rest is refused."""

import math
import sys
from pathlib import Path

import numpy as np
import pytest

from colonna.core.errors import InputError
from colonna.fem import _kernels as K
from colonna.fem.bed import (
    BED_PRESETS,
    bed_of,
    winkler_contact_length,
    winkler_peak_pressure,
    winkler_plastic_pivot,
    winkler_toe_pressure,
)
from colonna.studies.executor import RunOptions

sys.path.insert(0, str(Path(__file__).parent))


def test_where_the_bed_does_not_yield_the_law_is_the_elastic_one_bit_for_bit():
    rng = np.random.default_rng(4)
    for _ in range(2000):
        gap = -(10.0 ** rng.uniform(-9, -3))
        vn, vt = rng.normal(size=2)
        kn, kt = 10.0 ** rng.uniform(6, 10, size=2)
        cn = 10.0 ** rng.uniform(1, 4)
        ft, fc = rng.normal() * kn * 1e-6, abs(rng.normal()) * kn * 1e-6 * rng.integers(0, 2)
        dt, blend = 10.0 ** rng.uniform(-8, -5), rng.uniform(0.0, 1.0)
        elastic = K._penalty_contact(gap, vn, vt, kn, kt, cn, 0.7, dt, ft, fc, blend)
        bed = K._bed_contact(-gap, vn, vt, kn, kt, cn, math.inf, 0.7, dt, ft, fc, blend)
        assert bed[:7] == elastic and bed[7:] == (0.0, 0.0)


def _pivot(theta, weight, k, t, p_y, width, nodes=4000):
    """The base of a rigid block (``nodes`` base nodes over ``width``, the toe at x = 0)
    pressed into the bed through base_contact at tilt theta, its toe depth found by bisection
    so that the bed carries ``weight``, loaded from a fresh bed (monotonic loading: each node's
    depth reached at once gives the state its history would). Returns the contact length, the
    plastic zone's length and the resultant's distance from the toe."""
    xs = np.linspace(0.0, width, nodes)
    trib = np.full(nodes, width / (nodes - 1))
    trib[[0, -1]] *= 0.5
    kn = k * t * trib
    fy = p_y * t * trib
    index = np.arange(nodes, dtype=np.int64)

    def carried(depth):
        x = np.zeros((2 * nodes, 1))
        x[1::2, 0] = -(depth - theta * xs)
        zeros = np.zeros((1, nodes))
        state = [zeros.copy() for _ in range(4)]
        out = np.zeros((5, 1))
        K.base_contact(
            x,
            np.zeros_like(x),
            np.zeros_like(x),
            np.ones(1, dtype=np.bool_),
            np.zeros(1, dtype=np.int64),
            index,
            kn,
            kn,
            np.zeros(nodes),
            fy,
            0.0,
            0.0,
            state[0],
            state[1],
            state[2],
            state[3],
            1.0,
            out,
        )
        return state[1][0], state[3][0]

    low, high = 0.0, 1.0
    for _ in range(200):
        middle = 0.5 * (low + high)
        if carried(middle)[0].sum() < weight:
            low = middle
        else:
            high = middle
    fn, indentation = carried(high)
    touching = fn > 0.0
    return {
        "contact_length": float(xs[touching].max()),
        "plastic_length": float(xs[indentation > 0.0].max(initial=0.0)),
        "offset": float(fn @ xs / fn.sum()),
        "peak_pressure": float((fn / (t * trib)).max()),
    }


@pytest.mark.parametrize("p_y", [2e6, 5e6, 1e12], ids=["deep plastic zone", "short", "elastic"])
def test_a_block_pivoting_on_a_yielding_bed_matches_the_closed_form(p_y):
    """W = 20 kN, k = 5e12 N/m^3 (lead), t = 0.35 m, theta = 0.02 rad, a 0.2 m base: the
    elastic peak would be 16 MPa over 1.4 mm; at 2 MPa the plastic zone is 27 mm of a 29 mm
    contact, at 5 MPa 10 of 12 mm; 1e12 Pa is the elastic bed."""
    weight, k, t, theta = 2e4, 5e12, 0.35, 0.02
    closed = winkler_plastic_pivot(weight, k, t, theta, p_y)
    found = _pivot(theta, weight, k, t, p_y, 0.2)
    for key in ("contact_length", "offset"):
        assert found[key] == pytest.approx(closed[key], rel=0.03), key
    assert found["peak_pressure"] <= p_y * (1 + 1e-12)
    # the closed forms the reports use: their peak is the pivot's, capped at p_y
    assert winkler_peak_pressure(weight, k, t, theta, p_y) == pytest.approx(
        closed["peak_pressure"], rel=1e-12
    )
    assert winkler_toe_pressure(weight, theta, k, t, 0.2, p_y) == pytest.approx(
        closed["peak_pressure"], rel=1e-12
    )
    if p_y < 1e12:
        assert closed["plastic_length"] > 0.5 * closed["contact_length"]
        assert found["plastic_length"] == pytest.approx(closed["plastic_length"], rel=0.03)
        assert found["peak_pressure"] == pytest.approx(p_y, rel=1e-12)
    else:
        assert closed["contact_length"] == winkler_contact_length(weight, k, t, theta)
        assert found["plastic_length"] == 0.0


def _default_on_lead(mesh, **base):
    from test_stable_step import _default_on

    return _default_on(mesh, bed="lead", **base)


def test_a_run_on_a_yielding_bed_closes_its_energy_balance_with_the_plastic_work():
    """The default column on lead yielding at 1 MPa (its toes reach 2.4 MPa on the elastic
    lead; the column at rest presses 0.1 MPa): the bed's plastic work is a real share of what
    the run dissipates, the balance closes within 1 % of its scale, and no base node's pressure
    ever exceeds 1 MPa."""
    from colonna.studies.fem_study import from_dict
    from colonna.studies.models import run_fem

    study = from_dict(_default_on_lead(0.225, yield_pressure=1e6))
    result = run_fem(study, replicas=1)[0]
    h, summary = result.history, result.summary
    assert summary["bed_yield_pressure"] == 1e6
    assert summary["bed_plastic_work"] == h["energy_bed_plastic"][-1] > 0.0
    assert h["energy_bed_plastic"][-1] > 0.05 * h["energy_dissipated"][-1]
    assert np.all(np.diff(h["energy_bed_plastic"]) >= 0.0)  # work done on a plastic bed stays
    assert summary["energy_error_max"] < 0.01
    assert summary["toe_pressure_max"] <= 1e6 * (1 + 1e-12)
    assert summary["toe_pressure_winkler"] <= 1e6


def test_lead_yields_by_default_and_its_yield_is_stated():
    lead = bed_of("lead")
    low, high = BED_PRESETS["lead"].yield_range
    assert lead.yield_pressure == pytest.approx(math.sqrt(low * high))
    assert "Brinell" in lead.yield_source and "yield stress" in lead.yield_source
    assert bed_of("lead", plastic=False).yield_pressure is None
    assert bed_of("mortar").yield_pressure is None  # mortar yields where asked
    assert bed_of("mortar", plastic=True).yield_pressure == pytest.approx(math.sqrt(20e12))
    assert bed_of("stone", yield_pressure=50e6).yield_pressure == 50e6
    with pytest.raises(InputError, match="the stone bed has no yield pressure of its own"):
        bed_of("stone", plastic=True)
    with pytest.raises(InputError, match="not with plastic = false"):
        bed_of("lead", plastic=False, yield_pressure=5e6)


def test_a_bed_that_yields_under_the_column_at_rest_is_refused():
    from colonna.studies.fem_study import from_dict
    from colonna.studies.models import run_fem

    data = _default_on_lead(0.225, yield_pressure=1e5)  # below the 0.5 MPa a bed plausibly has
    data["study"] = {"intended": ["base.yield_pressure"]}
    study = from_dict(data)
    with pytest.raises(InputError, match="the bed yields under the column at rest"):
        run_fem(study, replicas=1)


def test_a_slot_starts_with_its_own_indentation_not_the_last_run_s():
    """A batch with fewer slots than runs puts the next run in the slot of one that ended: its
    bed starts from the start's indentation (none, or a restart's), not the last run's."""
    from colonna.fem.settings import FemStart
    from colonna.fem.solver import _BatchState, _initial_state
    from colonna.studies.fem_study import from_dict
    from colonna.studies.models import build

    model = build(from_dict(_default_on_lead(0.225)))
    state = _BatchState(model, 2, 1, np.zeros((1, model.base_nodes.size)))
    start = _initial_state(model, FemStart())
    state.base_state.indentation[:] = 1e-3  # what a run that ended left
    state.reset(0, start)
    assert np.all(state.base_state.indentation[0] == 0.0)
    assert np.all(state.base_state.indentation[1] == 1e-3)  # another slot is left alone
    dented = dict(start, base_indentation=np.full(model.base_nodes.size, 2e-4))
    state.reset(1, dented)
    assert np.all(state.base_state.indentation[1] == 2e-4)


@pytest.mark.slow
def test_the_default_column_on_lead_reports_toe_pressures_within_the_lead_s_yield(tmp_path):
    """The issue's acceptance, on the default column on lead (a coarse mesh, two replicas, a
    short run: the report's numbers, not their convergence): every toe pressure it reports
    (the runs' nodal and Winkler pressures, the closed form at alpha / 2 over the bed's range)
    is at most the lead's yield pressure, and the report says that the bed yields and at what."""
    import json
    import re
    import tomllib

    from colonna.studies.driver import run_study_file

    data = _default_on_lead(0.225)
    data["run"]["replicas"] = 2
    data["run"]["duration"] = 1.6
    data["mesh"]["toe_refinements"] = [1, 2, 4]
    study = tmp_path / "lead.toml"
    lines = []
    for table, values in data.items():
        lines.append(f"[{table}]" if table != "collar" else "")
        if table == "collar":
            for collar in values:
                lines.append("[[collar]]")
                lines += [f"{k} = {v!r}" for k, v in collar.items()]
            continue
        for key, value in values.items():
            text = f'"{value}"' if isinstance(value, str) else repr(value).lower()
            lines.append(f"{key} = {text}" if not isinstance(value, list) else f"{key} = {value}")
    study.write_text("\n".join(lines) + "\n")
    tomllib.loads(study.read_text())  # (the file as written reads back)
    out = tmp_path / "out"
    run_study_file(study, out, run_options=RunOptions(workers=1, progress=False))
    summary = json.loads((out / "summary.json").read_text())
    p_y = summary["bed"]["yield_pressure"]
    assert p_y == pytest.approx(math.sqrt(5e6 * 40e6))
    for key in ("toe_pressure_max", "toe_pressure_winkler"):
        assert summary["fem"][key] <= p_y * (1 + 1e-12), key
    for key in ("pressure", "pressure_low", "pressure_high"):
        assert summary["bed"][key] <= p_y, key
    html = (out / "index.html").read_text().replace("&nbsp;", " ")
    page = " ".join(re.sub(r"<[^>]+>", "", html).split())
    assert "The bed yields at p_y = 14.1 MPa" in page
    assert "no pressure on it exceeds p_y" in page

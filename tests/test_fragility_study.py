"""The fragility study kind (issue 37): IDA and stripes over a record suite, SDOF cases.

Pinned: the SDOF's uplift fragility against PGA is a step at g tan(alpha) exactly; two blocks of
equal alpha under records time-scaled by their p ratio give the same overturning fractions and
the same dimensionless IDA curves (Dimitrakopoulos & DeJong 2012); an IDA curve that overturns
at one level and survives a higher one has its capacity at the first; the study's SDOF path
gives rock()'s answers; the report opens with the probabilities at the design intensity.
"""

import json
import math
import re
import subprocess
import types
from pathlib import Path

import numpy as np
import pytest
from tiny_study import TINY_FRAGILITY, write_pulse_suite

from colonna.core.errors import InputError
from colonna.core.ground import Record
from colonna.core.intensity import intensity_measures
from colonna.core.motion import Motion
from colonna.core.suite import load_suite
from colonna.rigid.block import Block
from colonna.studies.cli import main
from colonna.studies.fragility import analysis
from colonna.studies.fragility.models import sdof_runs

ROOT = Path(__file__).resolve().parents[1]
SHIPPED_SUITE = ROOT / "studies" / "suites" / "synthetic-pulses"


def _free(block: Block):
    """What sdof_runs reads of a study: the rocking block and its collars (none)."""
    return types.SimpleNamespace(rocking_block=block, collars=())


@pytest.fixture(scope="module")
def suite():
    return [entry.scaled for entry in load_suite(SHIPPED_SUITE)]


def test_the_sdof_uplift_fragility_against_pga_is_a_step_at_g_tan_alpha(suite):
    """Every record uplifts the free block iff its scaled PGA exceeds g tan(alpha): levels a
    thousandth below and above, through the IM module's PGA / (g tan alpha)."""
    block = Block(b=0.2, h=1.5, mass=500.0)
    levels = np.array([0.99, 0.999, 1.001, 1.01, 1.2])  # PGA / (g tan alpha)
    runs = []
    for record in suite:
        ims = intensity_measures(record, block=block)
        assert ims.pga_rocking == pytest.approx(
            record.peak_acceleration / (block.g * math.tan(block.alpha)), rel=1e-12
        )
        runs.append(sdof_runs(_free(block), record, analysis.scales_for(levels, ims.pga_rocking)))
    uplift = analysis.exceedances(runs, 0.5)["uplift"]
    assert (uplift == (levels > 1.0)).all(), uplift
    capacity, censored = analysis.first_exceedance(uplift, levels)
    assert (capacity == 1.001).all() and not censored.any()
    # the rotations below uplift are exactly zero, above it positive
    peaks = analysis.table(runs, "peak_ratio")
    assert (peaks[:, :2] == 0.0).all() and (peaks[:, 2:] > 0.0).all()


def test_self_similarity_two_blocks_of_equal_alpha_give_the_same_fragility(suite):
    """Dimitrakopoulos & DeJong (2012): with tau = p t the equation depends on alpha and
    ug''(tau / p) / g only. A block four times as large in R (p / 2) under the records played
    twice as slow gives the same overturning fractions, the same |theta| / alpha at every level,
    and the same rocking-normalised PGA and PGV (the factor 2 is exact in binary: the two
    integrations take the same steps in tau)."""
    small = Block.from_dimensionless(p=2.0, alpha=0.2, mass=100.0)
    large = Block.from_dimensionless(p=1.0, alpha=0.2, mass=6400.0)
    ratio = small.p / large.p
    levels = np.linspace(1.2, 3.2, 6)  # PGA / (g tan alpha)
    curves = {}
    for name, block, stretch in (("small", small, 1.0), ("large", large, ratio)):
        runs = []
        for record in suite[:5]:
            played = Record(record.time * stretch, record.acceleration_values, record.name)
            ims = intensity_measures(played, block=block)
            curves.setdefault(f"pgv_{name}", []).append(ims.pgv_rocking)
            runs.append(
                sdof_runs(
                    _free(block), played, analysis.scales_for(levels, ims.pga_rocking), rtol=1e-9
                )
            )
        curves[name] = runs
    assert curves["pgv_small"] == pytest.approx(curves["pgv_large"], rel=1e-9)
    over = {n: analysis.exceedances(curves[n], 0.5)["overturning"] for n in ("small", "large")}
    assert over["small"].any() and not over["small"].all()  # the ladder crosses overturning
    assert (over["small"] == over["large"]).all()
    assert (over["small"].mean(axis=0) == over["large"].mean(axis=0)).all()
    peaks = {n: analysis.table(curves[n], "peak_ratio") for n in ("small", "large")}
    np.testing.assert_allclose(peaks["small"], peaks["large"], rtol=1e-9)


def test_the_sdof_path_gives_the_answers_of_rock(suite):
    """The study's SDOF runs (rock's kernel without the history) at rock's tolerance are
    rock()'s: overturning, largest |theta|, collar utilisation at the largest |theta|."""
    from colonna.core.collar import Collar
    from colonna.rigid.solve import rock

    block = Block(b=0.1125, h=2.0, mass=1900.0)
    collars = (Collar(y=2.0, t=0.008, h=0.06),)
    record = suite[0]
    scales = np.array([1.5, 4.0, 9.0]) * block.uplift_acceleration() / record.peak_acceleration
    study = types.SimpleNamespace(rocking_block=block, collars=collars)
    runs = sdof_runs(study, record, scales, rtol=1e-10)
    for scale, run in zip(scales, runs):
        r = rock(block, Motion(record.scaled(scale)), collars, model="nonlinear")
        assert run["overturned"] == r.overturned
        assert run["peak_ratio"] == pytest.approx(r.max_abs_theta / block.alpha, rel=1e-9)
        if not r.overturned:
            assert run["collar_utilisation"] == pytest.approx(
                r.collar_histories[0].max_utilisation, rel=1e-3
            )


def test_first_exceedance_keeps_the_first_level_and_censors_the_rest():
    levels = np.array([1.0, 2.0, 3.0, 4.0])
    exceeded = np.array(
        [[False, True, False, True], [False, False, False, False], [True, True, True, True]]
    )
    capacity, censored = analysis.first_exceedance(exceeded, levels)
    assert capacity.tolist() == [2.0, 4.0, 1.0]
    assert censored.tolist() == [False, True, False]


def test_clopper_pearson_matches_its_closed_forms():
    """k = 0: upper bound 1 - (tail)^(1/n); k = n: lower bound (tail)^(1/n)."""
    n, level = 10, 0.9
    bounds = analysis.clopper_pearson([0, 10], n, level)
    assert bounds[0, 0] == 0.0 and bounds[0, 1] == pytest.approx(1.0 - 0.05 ** (1 / n))
    assert bounds[1, 1] == 1.0 and bounds[1, 0] == pytest.approx(0.05 ** (1 / n))


# --- the study through colonna study ------------------------------------------------------------

BLOCK = Block(b=0.3, h=2.0)  # the rocking block of the tiny study's column (uncracked)


def _pulse(shape: str, omega_ratio: float) -> np.ndarray:
    omega = omega_ratio * BLOCK.p
    t = np.linspace(0.0, 2.0 * math.pi / omega, 401)
    return np.column_stack([t, np.cos(omega * t) if shape == "cos" else np.sin(omega * t)])


TINY = TINY_FRAGILITY


@pytest.fixture(scope="module")
def tiny(tmp_path_factory):
    root = tmp_path_factory.mktemp("fragility")
    write_pulse_suite(root)
    (root / "study.toml").write_text(TINY)
    out = root / "out"
    assert main(["study", str(root / "study.toml"), "--out", str(out), "--workers", "1"]) == 0
    return out, json.loads((out / "summary.json").read_text())


@pytest.mark.chaotic
def test_an_ida_curve_that_overturns_then_survives_is_reported_at_its_first_overturning(tiny):
    """The one-cosine pulse at 2.5 p overturns the block from a low level, survives a band of
    higher ones (Zhang & Makris's safe region) and overturns again: its capacity is the first."""
    _, s = tiny
    levels = np.array(s["levels"])
    over = np.array(s["runs"]["sdof"]["overturned"], dtype=bool)
    entry = s["limit_states"]["sdof"]["overturning"]
    non_monotonic = [
        i for i in range(over.shape[0]) if over[i].any() and not over[i][np.argmax(over[i]) :].all()
    ]
    assert 0 in non_monotonic, over.astype(int)
    for i in non_monotonic:
        first = int(np.argmax(over[i]))
        assert entry["capacities"][i] == pytest.approx(levels[first])
        assert not entry["censored"][i]
    # the stripes count each level as it is: a record that survives there is not counted
    assert entry["counts"] == over.sum(axis=0).tolist()


def test_the_summary_holds_the_fits_and_the_design_probabilities(tiny):
    _, s = tiny
    state = s["limit_states"]["sdof"]["overturning"]
    fit = state["ida"]
    assert fit["fit"]["method"] in ("capacity moments", "censored capacity MLE")
    low, high = fit["probability_interval"]
    assert low <= fit["probability"] <= high or math.isclose(low, high)
    assert s["design"]["P(overturning)_sdof"] == fit["probability"]
    # the uplift of every pulse is at the first level (1.1 > 1): IDA capacities all equal
    assert s["limit_states"]["sdof"]["uplift"]["counts"] == [4] * 24


def test_the_report_opens_with_the_probabilities_at_the_design_intensity(tiny, tmp_path):
    """The first section of the page is the design table, whose cells are summary.json's
    probabilities; every figure is drawn (headless browser, where there is one)."""
    out, s = tiny
    page = (out / "index.html").read_text()
    assert re.findall(r"<h2>([^<]+)</h2>", page)[0].startswith("Probability of each limit state")
    cell = re.search(r'data-key="design\.P\(overturning\)_sdof">([^<]+)<', page)
    assert cell and cell.group(1).startswith(f"{s['design']['P(overturning)_sdof']:.3g}")
    from browser import assert_every_figure_drawn, browser

    run = subprocess.run(
        [browser(), "--headless=new", "--no-sandbox", "--disable-gpu", "--dump-dom"]
        + [(out / "index.html").as_uri()],
        capture_output=True,
        text=True,
        timeout=120,
    )
    first = re.search(r"<h2>([^<]+)</h2>", run.stdout)
    assert first and first.group(1).startswith("Probability of each limit state"), run.stderr
    assert_every_figure_drawn(out / "index.html", tmp_path, at_least=3)


@pytest.mark.parametrize(
    "change, words",
    [
        ({"ladder": None}, "fragility.ladder = [start, stop] is required"),
        ({"intensity": "sa"}, "fragility.period is required with intensity = 'sa'"),
        ({"analysis": "msa"}, "fragility.levels is required"),
        ({"models": ["rigid"]}, "fragility.models"),
    ],
)
def test_a_bad_fragility_table_is_one_line_naming_the_key(tmp_path, capsys, change, words):
    from colonna.studies import schema

    table = {
        "suite": "suite.toml",
        "ladder": [1.0, 2.0],
        "design_intensity": 1.5,
    }
    table.update(change)
    table = {k: v for k, v in table.items() if v is not None}
    data = {
        "study": {"kind": "fragility"},
        "column": {"height": 4.0, "width": 0.6},
        "ground": {"pulse": "none"},
        "fragility": table,
    }
    with pytest.raises(InputError, match=re.escape(words)):
        schema.parse(data)


def test_a_fragility_study_refuses_a_ground_motion_of_its_own(tmp_path, capsys):
    (tmp_path / "study.toml").write_text(
        TINY.replace('pulse = "none"', 'pulse = "sine"\namplitude_ratio = 2.0\nomega_ratio = 2.0')
    )
    code = main(["study", str(tmp_path / "study.toml"), "--out", str(tmp_path / "out")])
    err = capsys.readouterr().err
    assert code == 2 and "[ground] of a fragility study is the suite's records" in err


def test_colonna_fragility_gives_the_study_s_sdof_fits_from_flags(tiny, capsys):
    """The fast command (the SDOF alone, no executor nor report) from flags describing the
    tiny study's block, suite and ladder gives the study's fits and probabilities."""
    out, s = tiny
    suite = out.parent / "suite.toml"
    args = ["fragility", "--suite", str(suite), "--b", "0.3", "--h", "2.0"]
    args += ["--ladder", "1.1:8:24", "--design", "3", "--bootstrap", "40", "--json"]
    assert main(args) == 0
    fast = json.loads(capsys.readouterr().out)
    for state in ("uplift", "overturning", "rotation"):
        assert fast["limit_states"][state] == s["limit_states"]["sdof"][state], state
    assert main(["fragility", str(out.parent / "study.toml")]) == 0
    printed = capsys.readouterr().out
    p = s["design"]["P(overturning)_sdof"]
    assert re.search(rf"^overturning\s+{re.escape(f'{p:.3g}')} ", printed, re.M), printed


def test_a_record_that_only_touches_the_uplift_level_does_not_rock_the_block():
    """PGA / (g tan alpha) = 1 exactly: no uplift (rocking needs the ground to exceed it)."""
    t = np.linspace(0.0, 1.0, 101)
    record = Record(t, np.sin(math.pi * t))
    runs = sdof_runs(
        _free(BLOCK), record, [BLOCK.uplift_acceleration(), 1.001 * BLOCK.uplift_acceleration()]
    )
    assert [r["uplift"] for r in runs] == [False, True]


# --- slow: the shipped study, the FEM and Dask --------------------------------------------------


@pytest.mark.slow
def test_the_shipped_fragility_study_runs_and_its_report_opens_with_the_probabilities(tmp_path):
    """studies/fragility.toml (SDOF and multibody over the shipped suite): every limit state of
    each model has its fractions and P at the design intensity, the report's first section is
    the design table with summary.json's values, every figure drawn."""
    from browser import assert_every_figure_drawn

    out = tmp_path / "out"
    assert main(["study", "fragility", "--out", str(out), "--workers", "2"]) == 0
    s = json.loads((out / "summary.json").read_text())
    assert s["models"] == ["sdof", "multibody"] and len(s["records"]) == 10
    for model in s["models"]:
        for state in ("uplift", "rotation", "overturning", "collar_yield"):
            entry = s["limit_states"][model][state]
            assert len(entry["fractions"]) == len(s["levels"])
    page = (out / "index.html").read_text()
    assert re.findall(r"<h2>([^<]+)</h2>", page)[0].startswith("Probability of each limit state")
    for key, value in s["design"].items():
        if value is not None:
            cell = re.search(rf'data-key="design\.{re.escape(key)}">([^<]+)<', page)
            assert cell and cell.group(1).startswith(f"{value:.3g}"), key
    assert_every_figure_drawn(out / "index.html", tmp_path, at_least=3)


FEM_TINY = (
    TINY.replace('models = ["sdof"]', 'models = ["sdof", "multibody", "fem"]')
    .replace("steps = 24", "steps = 2")
    .replace("ladder = [1.1, 8.0]", "ladder = [1.5, 3.0]")
    + "[mesh]\nsize = 0.15\n"
)


@pytest.mark.slow
def test_a_fem_fragility_runs_every_record_and_level_and_dask_gives_the_local_runs(tmp_path):
    """With the FEM among the models: one settled-stop FEM run per record and level, its
    limit states beside the rigid ones (toe crushing its own), the likelihood-ratio tests of
    the rigid models against it; the same study on a local Dask cluster gives the same runs
    and fits as local processes."""
    root = tmp_path
    entries = []
    for i, (shape, ratio) in enumerate((("cos", 2.5), ("sin", 3.5))):
        np.savetxt(root / f"p{i}.txt", _pulse(shape, ratio))
        entries.append(f'[[record]]\nfile = "p{i}.txt"\nunits = "m/s2"\n')
    (root / "suite.toml").write_text("\n".join(entries))
    (root / "study.toml").write_text(FEM_TINY)
    assert main(["study", str(root / "study.toml"), "--out", str(root / "local")]) == 0
    local = json.loads((root / "local" / "summary.json").read_text())
    assert len(list((root / "local" / "cases").glob("fem-*"))) == 2 * 2
    assert "toe_crushing" in local["limit_states"]["fem"]
    assert "overturning" in local["same_curve"]
    from distributed import LocalCluster

    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True) as cluster:
        code = main(
            ["study", str(root / "study.toml"), "--out", str(root / "dask")]
            + ["--scheduler", cluster.scheduler_address]
        )
    assert code == 0
    dask = json.loads((root / "dask" / "summary.json").read_text())
    assert dask["runs"] == local["runs"]
    assert dask["limit_states"] == local["limit_states"]


def test_the_fem_does_not_answer_uplift_it_sways_on_its_bed_before_it_rocks():
    """A FEM run below rocking still turns its halves by its bed's sway (far above the rigid
    models' 1e-4 alpha): its uplift is not assessed, and the limit state is left out of the
    FEM's table, not read as never (or always) exceeded; its rotation is still answered."""
    from colonna.studies.fragility.models import fem_point

    block = Block(b=0.1125, h=2.0)
    swaying = {
        "overturned": False,
        "max_abs_theta_left": 0.02 * block.alpha,  # bed sway: 200 times the uplift threshold
        "max_abs_theta_right": 0.02 * block.alpha,
        "collar_max_utilisation": 0.0,
        "edge_stress_ratio": 0.01,
        "status": "finished",
        "energy_error_max": 1e-4,
        "wall_seconds": 1.0,
        "steps": 10,
    }
    run = fem_point(_free(block), types.SimpleNamespace(summary=swaying))
    assert run["uplift"] is None
    assert run["peak_ratio"] == pytest.approx(0.02)
    found = analysis.exceedances([[run, run]], 0.5)
    assert "uplift" not in found
    assert not found["rotation"].any() and not found["overturning"].any()
    rigid = dict(run, uplift=True)
    assert analysis.exceedances([[rigid, rigid]], 0.5)["uplift"].all()

"""A fragility says what its answers rest on (issue 48).

Pinned: a design intensity outside the levels run is refused before anything runs, naming the
key, its value and the levels' range in the study's unit (from a study file and from the
command's flags); a fit read outside the levels (its median or the median's interval; its
curve past the ladder) is flagged in summary.json, in the report's opening and beside the
value; each model's collars are said (the SDOF's elastic springs, the multibody's and the FEM's
frame elements with their law); a limit state a model cannot reach is "cannot be reached by
this model", never a probability or a zero curve; an elastic model's survival on collars past
f_y is said beside its answer (the trial: the SDOF never overturns with its springs at many
times f_y while the multibody does).
"""

import html as html_module
import json
import math
import re
import types
from pathlib import Path

import numpy as np
import pytest

from colonna.core.collar import Collar
from colonna.core.errors import InputError
from colonna.rigid.block import Block
from colonna.studies import schema
from colonna.studies.cli import main
from colonna.studies.fragility import analysis
from colonna.studies.fragility.models import collar_law, unreachable

BOOTSTRAP = analysis.Bootstrap(draws=20, seed=0, level=0.9)
HALF = Block(b=0.1125, h=2.0)  # the rocking block of the collared column (a half, cracked)

COLLARED = """
[study]
name = "collared"
kind = "fragility"
[column]
height = 4.0
width = 0.45
cracked = true
[[collar]]
y = 0.5
t = 0.008
h = 0.06
plastic = true
[[collar]]
y = 3.5
t = 0.008
h = 0.06
plastic = true
[ground]
pulse = "none"
[fragility]
suite = "suite.toml"
intensity = "pga_rocking"
ladder = [3.0, 12.0]
steps = 2
models = ["sdof", "multibody"]
design_intensity = 6.0
bootstrap = 10
"""


def _pulses(root: Path, block: Block, shapes) -> None:
    """One-cycle pulses (sin or cos, at ratio x p of ``block``) as the suite.toml of ``root``."""
    entries = []
    for i, (shape, ratio) in enumerate(shapes):
        omega = ratio * block.p
        t = np.linspace(0.0, 2.0 * math.pi / omega, 401)
        a = np.cos(omega * t) if shape == "cos" else np.sin(omega * t)
        np.savetxt(root / f"p{i}.txt", np.column_stack([t, a]))
        entries.append(f'[[record]]\nfile = "p{i}.txt"\nunits = "m/s2"\n')
    (root / "suite.toml").write_text("\n".join(entries))


@pytest.fixture(scope="module")
def collared(tmp_path_factory):
    """The default column's half with two plastic collars, two pulses at two levels, through
    the SDOF (elastic springs, whatever plastic says) and the multibody (plastic frames):
    about 15 s."""
    root = tmp_path_factory.mktemp("collared")
    _pulses(root, HALF, (("sin", 2.0), ("cos", 3.0)))
    (root / "study.toml").write_text(COLLARED)
    out = root / "out"
    assert main(["study", str(root / "study.toml"), "--out", str(out), "--workers", "1"]) == 0
    return out, json.loads((out / "summary.json").read_text())


def _text(html: str) -> str:
    """A page's text: figures, tags and runs of blanks dropped."""
    html = re.sub(r"<svg.*?</svg>", " ", html, flags=re.S)
    return re.sub(r"\s+", " ", html_module.unescape(re.sub(r"<[^>]+>", " ", html)))


def _cell(page: str, state: str, column: int) -> str:
    """The text of the design table's cell of limit state ``state`` (its words) in model
    column ``column`` (0: the first model)."""
    table = re.search(r'<table class="design".*?</table>', page, re.S).group(0)
    row = re.search(rf"<tr><th>{re.escape(state)}</th>(.*?)</tr>", table, re.S).group(1)
    return _text(re.findall(r"<td[^>]*>(.*?)</td>", row, re.S)[column]).strip()


# --- extrapolation ------------------------------------------------------------------------------


def _table(analysis_kind: str, levels, design: float, intensity: str = "pgv_rocking") -> dict:
    key = {"ladder": [min(levels), max(levels)]} if analysis_kind == "ida" else {"levels": levels}
    return {
        "study": {"kind": "fragility"},
        "column": {"height": 4.0, "width": 0.6},
        "ground": {"pulse": "none"},
        "fragility": {
            "suite": "suite.toml",
            "intensity": intensity,
            "analysis": analysis_kind,
            "design_intensity": design,
            **key,
        },
    }


@pytest.mark.parametrize(
    "kind, levels, design, intensity, words",
    [
        # the trial: 245 over a ladder of 0.5-8 gave every P = 1, without a word
        ("ida", [0.5, 8.0], 245.0, "pgv_rocking", ["= 245 lies above the highest", "0.5 to 8"]),
        ("ida", [0.5, 8.0], 0.4, "pgv_rocking", ["= 0.4 lies below the lowest", "no unit"]),
        ("msa", [1.0, 2.0, 3.0], 3.5, "pga", ["fragility.levels spans 1 to 3", "pga in m/s^2"]),
    ],
)
def test_a_design_intensity_outside_the_levels_is_refused_naming_key_value_and_range(
    kind, levels, design, intensity, words
):
    with pytest.raises(InputError) as caught:
        schema.parse(_table(kind, levels, design, intensity))
    message = str(caught.value)
    assert "fragility.design_intensity" in message, message
    for w in words:
        assert w in message, message
    assert len(message.splitlines()) == 1


@pytest.mark.parametrize("design", [0.5, 3.0, 8.0])
def test_a_design_intensity_within_the_ladder_its_ends_included_is_accepted(design):
    assert schema.parse(_table("ida", [0.5, 8.0], design)).fragility.design_intensity == design


def test_colonna_study_refuses_it_before_anything_runs(tmp_path, capsys):
    """No suite file exists: the refusal comes from the study file alone, and no output is
    written."""
    text = COLLARED.replace("design_intensity = 6.0", "design_intensity = 245.0")
    (tmp_path / "study.toml").write_text(text)
    out = tmp_path / "out"
    assert main(["study", str(tmp_path / "study.toml"), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert "fragility.design_intensity = 245 lies above the highest level run" in err, err
    assert "3 to 12 (pga_rocking, no unit)" in err
    assert not (out / "summary.json").exists()


def test_colonna_fragility_names_the_flag_it_refuses(capsys):
    suite = Path(__file__).resolve().parents[1] / "studies" / "suites" / "synthetic-pulses"
    args = ["fragility", "--suite", str(suite), "--b", "0.1125", "--h", "2"]
    args += ["--ladder", "0.5:8:3", "--design", "245", "--intensity", "pgv_rocking"]
    assert main(args) == 2
    err = capsys.readouterr().err
    assert "--design = 245 lies above the highest level run: --ladder spans 0.5 to 8" in err, err


def test_a_fit_read_outside_the_levels_is_flagged_in_the_summary():
    """Two of six records exceed within the ladder 1-4, one only at its top: the IDA median
    (censored MLE) lies above 4, and every point of the curve past 4 or below 1 is flagged; a
    fit inside the ladder has nothing flagged."""
    levels = np.array([1.0, 2.0, 3.0, 4.0])
    exceeded = np.zeros((6, 4), dtype=bool)
    exceeded[0, 2:] = exceeded[1, 3] = exceeded[2, 1:] = True
    entry = analysis.fit_limit_state(exceeded, levels, 2.5, bootstrap=BOOTSTRAP, ida=True)
    ida = entry["ida"]
    assert ida["fit"]["median"] > 4.0
    assert ida["extrapolated"][0] == (
        f"the median, {ida['fit']['median']:.4g}, lies above the highest level run, 4"
    )
    im = np.array(ida["curve"]["im"])
    assert ida["curve"]["extrapolated"] == ((im < 1.0) | (im > 4.0)).tolist()
    assert any(ida["curve"]["extrapolated"]) and not all(ida["curve"]["extrapolated"])
    inside = np.zeros((6, 4), dtype=bool)
    for i, first in enumerate((1, 2, 1, 0, 2, 3)):
        inside[i, first:] = True
    entry = analysis.fit_limit_state(inside, levels, 2.5, bootstrap=BOOTSTRAP, ida=True)
    assert entry["ida"]["extrapolated"] == [] and entry["stripes"]["extrapolated"] == []


def test_the_report_opens_with_the_fits_read_outside_the_levels(tmp_path):
    """A ladder that stops where the rotation's bootstrap interval does not: the opening's
    first line after its heading says which fit and what lies outside, and the fits table
    says it beside the median."""
    block = Block(b=0.3, h=2.0)
    _pulses(tmp_path, block, (("cos", 2.5), ("cos", 2.0), ("sin", 3.5), ("sin", 6.0)))
    text = (
        COLLARED.split("[[collar]]")[0].replace("width = 0.45", "width = 0.6")
        + '[ground]\npulse = "none"\n[fragility]\nsuite = "suite.toml"\n'
        + 'intensity = "pga_rocking"\nladder = [1.1, 1.6]\nsteps = 3\nmodels = ["sdof"]\n'
        + "design_intensity = 1.3\nbootstrap = 20\n"
    ).replace("cracked = true", "cracked = false")
    (tmp_path / "study.toml").write_text(text)
    out = tmp_path / "out"
    assert main(["study", str(tmp_path / "study.toml"), "--out", str(out), "--workers", "1"]) == 0
    s = json.loads((out / "summary.json").read_text())
    flagged = s["limit_states"]["sdof"]["rotation"]["ida"]["extrapolated"]
    assert flagged and "above the highest level run, 1.6" in flagged[0]
    page = (out / "index.html").read_text()
    opening = re.search(
        r"<h2>Probability of each limit state[^<]*</h2>\s*(<p[^>]*>.*?</p>)", page, re.S
    )
    first = _text(opening.group(1))
    assert 'id="extrapolated"' in opening.group(1)
    assert "Read outside the levels run" in first
    assert f"SDOF half block, |theta| / alpha above the threshold, IDA fit: {flagged[0]}" in first
    fits = re.search(r'<table class="fits">.*?</table>', page, re.S).group(0)
    assert f"extrapolated: {flagged[0]}" in _text(fits)


# --- the collars each model has, and what a model cannot reach -----------------------------------


def test_each_model_s_collars_are_said_in_the_summary_the_opening_and_the_legend(collared):
    out, s = collared
    sdof, multibody = s["collars"]["sdof"], s["collars"]["multibody"]
    assert sdof["law"] == "elastic springs" and not sdof["yields"] and not sdof["fractures"]
    assert "never yield nor fracture, whatever [[collar]] plastic says" in sdof["words"]
    assert multibody["yields"] and multibody["fractures"]
    assert multibody["words"].startswith("co-rotational frame elements")
    assert "plastic, fibre section (20 layers x 10 sections, bilinear steel)" in multibody["words"]
    assert "fracture at an extreme-fibre strain of 0.15" in multibody["words"]
    page = (out / "index.html").read_text()
    laws = _text(re.search(r'<ul id="collar-laws">.*?</ul>', page, re.S).group(0))
    assert f"SDOF half block : {sdof['words']}." in laws
    assert f"rigid multibody : {multibody['words']}." in laws
    # the legend of the curves (SVG text) names each model's collars
    assert "SDOF half block (elastic collar springs)" in page
    assert "rigid multibody (plastic frame collars, fibre law)" in page


def test_the_sdof_s_survival_on_collars_past_f_y_is_said_beside_its_answer(collared):
    """The trial's case: the SDOF never overturns, its springs at many times f_y; the
    multibody, whose plastic collars yield, overturns. The largest utilisation is over the
    runs it survived (an overturned run's stress is its stop's)."""
    out, s = collared
    sdof = s["collars"]["sdof"]
    over = np.array(s["runs"]["sdof"]["overturned"], dtype=bool)
    utilisation = np.array(s["runs"]["sdof"]["collar_utilisation"])
    assert not over.any() and np.array(s["runs"]["multibody"]["overturned"], dtype=bool).any()
    past = sdof["past_fy"]
    u = past["largest_utilisation"]
    assert u == utilisation[~over].max() and u > 10.0
    assert past["runs"] == int((utilisation[~over] >= 1.0).sum()) and past["of"] == over.size
    p = s["design"]["P(overturning)_multibody"]
    assert p is not None and p > 0.0
    assert sdof["note"].endswith(
        f"up to {u:.3g} times their strength; it never overturns over the suite, while the "
        f"rigid multibody does (P = {p:.2g} at the design intensity)"
    )
    assert s["collars"]["multibody"]["past_fy"] is None  # plastic: past f_y is modelled
    page = (out / "index.html").read_text()
    cell = _cell(page, "overturning", 0)
    assert cell.startswith("no run reached it")
    assert f"rests on elastic collar springs at up to {u:.3g} f_y" in cell
    assert "rests on" not in _cell(page, "overturning", 1)
    # a qualified answer keeps its number first and its key (the terminal and tests read it)
    rotation = re.search(r'data-key="design\.P\(rotation\)_sdof">([^<]+)<br>', page)
    assert rotation and rotation.group(1).startswith(f"{s['design']['P(rotation)_sdof']:.3g}")
    assert "rests on elastic collar springs" in _cell(
        page, "|theta| / alpha above the threshold", 0
    )
    assert f"The SDOF half block: {sdof['note']}." in _text(page)


def test_a_limit_state_a_model_cannot_reach_is_said_never_a_zero_curve(collared):
    out, s = collared
    assert set(s["unreachable"]["sdof"]) == {"collar_fracture", "toe_crushing"}
    assert set(s["unreachable"]["multibody"]) == {"toe_crushing"}  # its collars break
    assert "collar_fracture" not in s["limit_states"]["sdof"]
    assert "P(collar_fracture)_sdof" not in s["design"]
    assert "collar_fracture" in s["limit_states"]["multibody"]
    page = (out / "index.html").read_text()
    sdof_cell = _cell(page, "collar fracture", 0)
    assert (
        sdof_cell == "cannot be reached by this model elastic collar springs: they never fracture"
    )
    assert _cell(page, "toe crushing", 1).startswith("cannot be reached by this model")
    assert not re.search(r"\d", _cell(page, "toe crushing", 0))
    # the curves: no SDOF points in the fracture panel, whose title says why
    header = (out / "figures" / "curves.csv").read_text().splitlines()[0]
    assert "collar_fracture_multibody_fraction" in header
    assert "collar_fracture_sdof_fraction" not in header
    assert "SDOF half block: cannot be reached by this model" in page


def test_frame_collars_say_their_law_and_elastic_ones_cannot_fracture():
    elastic = types.SimpleNamespace(collars=(Collar(y=1.0, t=0.008, h=0.06),))
    resultant = types.SimpleNamespace(
        collars=(Collar(y=1.0, t=0.008, h=0.06, plastic=True, section="resultant"),)
    )
    for model in ("multibody", "fem"):
        law = collar_law(elastic, model)
        assert law["short"] == "elastic frame collars" and not law["fractures"]
        assert law["words"].endswith("elastic (plastic = false): they never yield nor fracture")
        assert "collar_fracture" in unreachable(elastic, model)
        law = collar_law(resultant, model)
        assert law["short"] == "plastic frame collars, resultant law" and law["fractures"]
        assert "|M| / M_p + (N / N_p)^2 = 1" in law["words"]
        assert "collar_fracture" not in unreachable(resultant, model)
    assert "toe_crushing" not in unreachable(elastic, "fem")
    assert collar_law(resultant, "sdof")["law"] == "elastic springs"  # whatever plastic says
    assert unreachable(types.SimpleNamespace(collars=()), "sdof") == {
        "toe_crushing": "rigid bodies: no stress at the toe, the FEM's answer"
    }


def test_a_limit_state_a_model_does_not_assess_is_said_so_beside_the_others(collared, tmp_path):
    """The FEM's uplift (its column sways on its bed before it rocks) is "not assessed", not
    "cannot be reached": the report of a summary whose multibody lacks uplift says so."""
    import copy
    import shutil

    from colonna.studies.fragility import write_report

    out, s = collared
    s = copy.deepcopy(s)
    folder = tmp_path / "out"
    shutil.copytree(out, folder)
    del s["limit_states"]["multibody"]["uplift"]
    (folder / "summary.json").write_text(json.dumps(s))
    page = write_report(folder).read_text()
    assert _cell(page, "uplift", 1) == "not assessed"
    assert _cell(page, "uplift", 0) == s["limit_states"]["sdof"]["uplift"].get("why", "no curve")
    # the first model without the first limit state (the FEM first, without uplift)
    s["limit_states"]["multibody"]["uplift"] = s["limit_states"]["sdof"].pop("uplift")
    (folder / "summary.json").write_text(json.dumps(s))
    page = write_report(folder).read_text()
    assert _cell(page, "uplift", 0) == "not assessed"


def test_the_curves_and_ida_figures_keep_their_longer_texts_inside(collared, tmp_path, monkeypatch):
    """The legend entries with each model's collars and hollow markers, and a panel title that
    names a model which cannot reach its limit state, stay within the figure
    (:func:`colonna.studies.report.texts_outside`)."""
    import shutil

    from matplotlib.figure import Figure

    from colonna.studies.fragility import write_report
    from colonna.studies.report import texts_outside

    out, _ = collared
    folder = tmp_path / "out"
    shutil.copytree(out, folder)
    keep, checked = Figure.savefig, {}

    def spy(fig, fname, *args, **kwargs):
        if isinstance(fname, (str, Path)):
            checked.setdefault(Path(fname).stem, texts_outside(fig))
        return keep(fig, fname, *args, **kwargs)

    monkeypatch.setattr(Figure, "savefig", spy)
    write_report(folder)
    assert {"curves", "ida"} <= set(checked)
    assert {name: cut for name, cut in checked.items() if cut} == {}


def test_a_run_that_overturned_has_no_peak_in_the_summary(collared):
    """No number from a stopped run is a result (issue 48): where a model's run overturned,
    summary.json's peak_ratio is null (its peak was the stop's: pi/2 for the SDOF, 45 degrees
    for the multibody); the analysis reads the runs themselves, its probabilities unchanged."""
    out, s = collared
    over = np.array(s["runs"]["multibody"]["overturned"], dtype=bool)
    peaks = s["runs"]["multibody"]["peak_ratio"]
    assert over.any()
    for i, row in enumerate(peaks):
        for j, value in enumerate(row):
            assert (value is None) == bool(over[i][j])
    assert "a run that overturned has no peak_ratio" in s["layout"]

"""No number from a stopped run is a result (issue 48).

A run stops where its column overturns (a stopping convention): its largest rotation is then the
angle it stopped at, a ratio of two such angles compares two stopping rules ("Peak rotation FEM /
multibody: 0.5199" where both overturned), a velocity ratio from the rotation peaks takes the
stopping angle for a peak. Every study kind with a column, run on a column that overturns in
every model, must say "not applicable: ... overturned at t = ..." in place of each of them: in
summary.json, in the report's text, in the terminal's lines and (where Chromium and pdftotext
are installed) in the PDF's text. :func:`stopped_numbers` finds the numbers that break this; the
cheap tests pin the words and the first screen's caveats (the toe's averaged stress beside its
local pressure, a model on elastic collars past f_y or an elastic bed past its yield never
green) on outcomes composed with the runner's own functions.
"""

from __future__ import annotations

import html
import json
import re
import shutil
import subprocess
import sys
import tomllib
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from tiny_study import TINY_FRAGILITY, TINY_LAYOUT, TINY_STUDY, write_pulse_suite

from colonna.core.motion import Motion
from colonna.fem.ensemble import band
from colonna.studies.crosscheck import runner as crosscheck
from colonna.studies.fem_study import from_dict
from colonna.studies.outcome import (
    fem_stop,
    not_applicable,
    overturned_at,
    unless_stopped,
)
from colonna.studies.report import TEMPLATES, num

GREEN = "good"  # the class of a pass (studies/templates/base.html.j2)

# the summary keys (anywhere in a dotted path) whose value is a rotation, a ratio of rotations
# or a velocity ratio from rotation peaks: of a run that overturned, never a number
STOPPED = re.compile(
    r"theta_peak_ratio|peak_ratio|max_abs_theta|peak_rotation|max_rotation"
    r"|collar_utilisation_ratio|restitution_after_motion|(^|\.)ratio_first|(^|\.)ratio_mean"
    r"|multibody_ratio|fem_ratio_study_stone|impulse_ratios"
    r"|(^|\.)(fem|multibody|damping_variants\.\d+|mesh_variants\.\d+)\.ratios(\.|$)"
)
COUNTS = ("n", "missing")  # a band's counts of replicas: no value of a run
NUMBER = re.compile(r"^[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$")


def _is_number(value) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def _leaves(node, path=""):
    if isinstance(node, dict):
        for k, v in node.items():
            yield from _leaves(v, f"{path}.{k}" if path else str(k))
    elif isinstance(node, list):
        for i, v in enumerate(node):
            yield from _leaves(v, f"{path}.{i}")
    else:
        yield path, node


def _text(fragment: str) -> str:
    return re.sub(r"\s+", " ", html.unescape(re.sub(r"<[^>]+>", " ", fragment))).strip()


def _stood(summary: dict, path: str) -> bool:
    """Whether the value at ``path`` is of a run that stayed up (an SDOF that rocks beside an
    FEM that overturns): a dict on its way says ``overturned`` false in no replica, or its
    ``motion`` is not an overturning; or the leaf's own model (``fem_``, ``rigid_`` ...) says
    ``<model>_overturned`` false beside it; a fragility's records x levels table
    (``runs.<model>.<key>.<i>.<j>``): ``runs.<model>.overturned[i][j]`` false."""
    table = re.fullmatch(r"runs\.(\w+)\.\w+\.(\d+)\.(\d+)", path)
    if table and summary.get("kind") == "fragility":
        model, i, j = table.group(1), int(table.group(2)), int(table.group(3))
        return not summary["runs"][model]["overturned"][i][j]
    node = summary
    parts = path.split(".")
    stood = (False, "no")  # overturned: a flag, or the yes/no/undecided of the replicas
    for part in parts[:-1]:
        node = node[int(part)] if isinstance(node, list) else node[part]
        if not isinstance(node, dict) or node.get("overturned_replicas"):
            continue
        if node.get("overturned") in stood or not str(node.get("motion", "over")).startswith(
            "over"
        ):
            return True
    return isinstance(node, dict) and node.get(parts[-1].split("_")[0] + "_overturned") in stood


def stopped_numbers(out: Path, terminal: str = "", pdf_text: str = "") -> list[str]:
    """Every number of a stopped run that a study in ``out`` gives as a result: in
    summary.json (a number at a STOPPED key, unless of a run that stood, :func:`_stood`), in
    the report (a span of such a key showing a number; a "peak rotation ... / ...: <number>"
    sentence), in the terminal's lines (``terminal``: such a key with a number) and in the
    PDF's text (that sentence)."""
    found = []
    summary = json.loads((out / "summary.json").read_text())
    found += [
        f"summary.json {path} = {value}"
        for path, value in _leaves(summary)
        if STOPPED.search(path)
        and _is_number(value)
        and path.rsplit(".", 1)[-1] not in COUNTS
        and not _stood(summary, path)
    ]
    page = (out / "index.html").read_text()
    for key, shown in re.findall(r'<span data-key="([^"]+)"[^>]*>([^<]*)</span>', page):
        if STOPPED.search(key) and NUMBER.match(shown.strip()) and not _stood(summary, key):
            found.append(f"index.html {key} shows {shown}")
    ratio = re.compile(r"peak rotation[^.;:]*?/[^.;:]*?[:=] ?(\d\S*)", re.I)
    found += [f"index.html: {m.group(0)}" for m in ratio.finditer(_text(page))]
    for line in terminal.splitlines():
        key, _, value = line.partition(" ")
        if STOPPED.search(key) and NUMBER.match(value.strip()):
            found.append(f"terminal: {line.strip()}")
    found += [f"PDF: {m.group(0)}" for m in ratio.finditer(" ".join(pdf_text.split()))]
    return found


def _stays_up(summary: dict) -> str:
    """The answer to "Does the column stay up?": no where the model the answers quote
    overturned in every replica or pulse (the premise of the check)."""
    return next(a["answer"] for a in summary["outcome"]["answers"] if a["key"] == "stays_up")


# --- cheap: the words ------------------------------------------------------------------------


def test_a_stopped_number_is_the_words_that_say_which_run_stopped_when():
    assert overturned_at("the FEM", 0, 1.0) is None
    assert overturned_at("the FEM", True, 1.234567) == "the FEM overturned at t = 1.235 s"
    assert (
        overturned_at("the FEM", 2, 0.5, of=4)
        == "the FEM overturned at t = 0.5 s in 2 of 4 replicas"
    )
    assert unless_stopped(0.52, None, None) == 0.52
    said = unless_stopped(0.52, "the FEM overturned at t = 1 s", "the multibody model overturned")
    assert said == ("not applicable: the FEM overturned at t = 1 s; the multibody model overturned")
    assert not_applicable(None) is None
    # an ensemble stops where any replica overturns: its median mixes stopping angles
    fem = {
        "overturned": False,
        "overturned_replicas": 1,
        "replicas": 4,
        "statuses": ["completed", "overturned: ...", "completed", "completed"],
        "t_end": 2.0,
        "bands": {"t_end": band([2.0, 1.25, 2.0, 2.0])},
    }
    assert fem_stop("the FEM", fem) == "the FEM overturned at t = 1.25 s in 1 of 4 replicas"


# --- cheap: the first screen's caveats --------------------------------------------------------


def _study(bed: str | None = None):
    study = from_dict(tomllib.loads(TINY_STUDY.format(amplitude_ratio=4.0, duration=2.0)))
    if bed is None:
        return study
    from colonna.fem.bed import BED_PRESETS, Bed

    preset = BED_PRESETS[bed]
    # an elastic bed of the preset (no yield pressure of its own)
    return replace(study, bed=Bed(preset.stiffness, *preset.stiffness_range, preset.source))


def _results(study, winkler: float, sdof_utilisation: float = 18.0) -> dict:
    """The cross-check's results of a column that stays up in every model (none overturns):
    the FEM ensemble's toe stress 0.123 f_c, its Winkler toe pressure ``winkler`` (Pa); the
    SDOF half block's elastic collars at ``sdof_utilisation`` times f_y."""
    ratios = [0.121, 0.123, 0.125, 0.122]
    fem = {
        "overturned": False,
        "overturned_replicas": 0,
        "replicas": 4,
        "statuses": ["completed"] * 4,
        "t_end": 2.0,
        "max_abs_theta_left": 0.004,
        "max_abs_theta_right": 0.004,
        "edge_length": 0.0225,
        "edge_time": 0.005,
        "toe_pressure_winkler": winkler,
        "bands": {
            "t_end": band([2.0] * 4),
            "collar_max_utilisation": band([0.70, 0.73, 0.74, 0.72]),
            "edge_stress_ratio": band(ratios),
        },
    }
    return {
        "fem": {"summary": fem},
        "multibody": {
            "overturned": False,
            "max_abs_theta_left": 0.004,
            "max_abs_theta_right": 0.004,
            "collar_max_utilisation": 0.77,
            "collar_fractured": False,
        },
        "rigid": {
            "overturned": False,
            "max_abs_theta": 0.022,
            "alpha": study.rocking_block.alpha,
            "collar_max_utilisation": sdof_utilisation,
            "collar_law": "elastic",
        },
        "monolith": {
            "overturned": False,
            "max_abs_theta": 0.003,
            "alpha": study.column_block.alpha,
        },
    }


def _outcome(study, results) -> dict:
    criteria = {k: "yes" for k in ("same_outcome", "peak_ok", "impacts_ok", "history_ok")}
    criteria["all_ok"] = "yes"
    return {"outcome": crosscheck.crosscheck_outcome(study, results, criteria)}


def _first_screen(summary: dict) -> str:
    return TEMPLATES.get_template("base.html.j2").render(
        s=summary,
        title="test",
        num=lambda *a, **k: num(summary, *a, **k),
        inputs=None,
        ground=None,
    )


def _cell(page: str, attribute: str) -> tuple[str, str]:
    """(class, text) of the first screen's cell (td) or span carrying ``attribute``."""
    m = re.search(rf"<(td|span) ([^>]*{attribute}[^>]*)>", page)
    assert m, attribute
    rest = page[m.end() :]
    inner = rest[: rest.index("</td>")] if m.group(1) == "td" else rest[: rest.index("</span>")]
    cls = re.search(r'class="([^"]*)"', m.group(2))
    return (cls.group(1) if cls else ""), _text(inner)


def test_the_sdof_that_stays_up_on_collars_past_f_y_is_not_green_and_says_why():
    """The trial: the SDOF half block "rocks and stays up" in green with its collar springs at
    sigma / f_y = 18. Its row, its "stays up" word and the verdict "SDOF good enough?" say
    "its collars would carry 18 times f_y (the SDOF's collars are elastic)" and none is green;
    below f_y the same model is green and says nothing."""
    study = _study()
    summary = _outcome(study, _results(study, winkler=2e6))
    sdof = next(m for m in summary["outcome"]["models"] if m["model"] == crosscheck.SDOF_HALF)
    assert sdof["motion"] == "rocking"
    assert sdof["caveat"] == "its collars would carry 18 times f_y (the SDOF's collars are elastic)"
    page = _first_screen(summary)
    index = summary["outcome"]["models"].index(sdof)
    row = page.split(f'data-caveat="model-{index}"')[0].rsplit("<tr>", 1)[1]
    assert "rocks and stays up" in row and f'class="{GREEN}"' not in row
    assert "its collars would carry 18 times f_y (the SDOF's collars are elastic)" in _text(
        page.split("<tr>")[index + 2]
    )
    cls, text = _cell(page, f'data-stays-up="{index}"')
    assert text == "yes" and cls != GREEN
    assert "its collars would carry 18 times f_y" in _text(
        page.split(f'data-caveat="stays-up-{index}"')[1][:200]
    )
    # the multibody model's elastic frames at 0.77 f_y: a pass, green, no caveat
    assert "caveat" not in summary["outcome"]["models"][1]
    # below f_y the SDOF is green
    below = _outcome(study, _results(study, winkler=2e6, sdof_utilisation=0.5))
    page = _first_screen(below)
    assert "its collars would carry" not in page
    assert _cell(page, f'data-stays-up="{index}"')[0] == GREEN


def _verdict_row(s: dict) -> str:
    """The cross-check report's verdict_row macro (its source, from the page's template) for
    "SDOF half-block model good enough?" rendered on the summary ``s``."""
    source = Path(TEMPLATES.get_template("crosscheck/report.html.j2").filename).read_text()
    macro = re.search(r"{% macro verdict_row.*?{%- endmacro %}", source, re.S).group(0)
    call = '{% call verdict_row("sdof_half_model_ok", "SDOF?", "yes") %}{% endcall %}'
    return TEMPLATES.from_string(macro + call).render(s=s, num=lambda *a, **k: num(s, *a, **k))


def test_the_sdof_verdict_row_of_the_report_carries_the_caveat():
    """The cross-check's detail row "SDOF half-block model good enough?" is not green where the
    SDOF's survival rests on collars past f_y (summary["verdict_caveats"]), and says why."""
    caveat = "its collars would carry 18 times f_y (the SDOF's collars are elastic)"
    s = {
        "verdict": {"sdof_half_model_ok": "yes"},
        "outcome": {"answers": [], "models": []},
        "verdict_caveats": {"sdof_half_model_ok": caveat},
    }
    shown = _verdict_row(s)
    assert 'class="qualified"' in shown and caveat in _text(shown)
    s["verdict_caveats"] = {}
    assert f'class="{GREEN}"' in _verdict_row(s)


def test_the_toe_answer_gives_the_averaged_stress_and_the_local_pressure_side_by_side():
    """The trial: page 1 "Does the toe crush? no (0.123 f_c)", page 5 the Winkler pressure at
    9.36 f_c, local spalling possible. The toe answer's row gives both: the averaged stress
    (MPa, over edge_length and edge_time) its word compares with f_c, and the local pressure
    with its spalling verdict (the toe section's number), and is not green where spalling is
    possible."""
    study = _study()
    fc = study.stone.fc
    results = _results(study, winkler=9.36 * fc)
    summary = _outcome(study, results)
    toe = next(a for a in summary["outcome"]["answers"] if a["key"] == "toe_crushes")
    assert toe["answer"] == "no"
    assert toe["averaged"]["stress"] == pytest.approx(0.1225 * fc)
    assert toe["local"]["ratio"] == pytest.approx(9.36)
    assert toe["local"]["spalling"] == crosscheck.LOCAL_SPALLING
    # the toe section's number is the same
    assert crosscheck.winkler_run_max(results) / fc == pytest.approx(toe["local"]["ratio"])
    page = _first_screen(summary)
    cls, word = _cell(page, 'data-answer="toe_crushes"')
    assert cls != GREEN and word.startswith("no")
    assert "local (Winkler) toe pressure reaches 9.36 f_c" in word
    row = _text(page.split('data-answer="toe_crushes"')[1].split("</tr>")[0])
    averaged = f"{0.1225 * fc / 1e6:.4g} MPa averaged over 22.5 mm and 0.005 s"
    local = f"local (Winkler) toe pressure {9.36 * fc / 1e6:.4g} MPa = 9.36 f_c: "
    assert averaged in row and local + crosscheck.LOCAL_SPALLING in row
    # below f_c (and the mortar bed's yield): no spalling, and the word is a pass again
    summary = _outcome(study, _results(study, winkler=2e6))
    page = _first_screen(summary)
    toe = next(a for a in summary["outcome"]["answers"] if a["key"] == "toe_crushes")
    assert toe["local"]["spalling"] == crosscheck.NO_LOCAL_SPALLING and "caveat" not in toe
    assert _cell(page, 'data-answer="toe_crushes"')[0] == GREEN


def test_a_toe_answer_on_an_elastic_bed_past_its_yield_is_not_green_and_says_so():
    """An elastic lead sheet under a toe pressure above lead's yield pressure (fem.bed's
    preset: its yield range and source): the toe answer says it rests on an elastic bed past
    its yield, with the pressure, the range and the source, and is not green, even with the
    local pressure below f_c. The same pressure on a bed that yields in the model, or below
    the yield range, carries no such caveat."""
    from colonna.fem.bed import BED_PRESETS

    lead = BED_PRESETS["lead"]
    low, high = lead.yield_range
    study = _study("lead")
    pressure = 2.0 * high  # above the range, below f_c (110 MPa)
    assert pressure < study.stone.fc
    summary = _outcome(study, _results(study, winkler=pressure))
    toe = next(a for a in summary["outcome"]["answers"] if a["key"] == "toe_crushes")
    assert toe["local"]["spalling"] == crosscheck.NO_LOCAL_SPALLING
    nominal = (low * high) ** 0.5
    assert toe["caveat"] == (
        f"it rests on an elastic bed past its yield: the toe pressure {pressure / 1e6:.3g} MPa "
        f"is above the lead bed's yield pressure {nominal / 1e6:.3g} MPa (range "
        f"{low / 1e6:.3g} to {high / 1e6:.3g} MPa: {lead.yield_source}), which it cannot carry"
    )
    cls, word = _cell(_first_screen(summary), 'data-answer="toe_crushes"')
    assert cls != GREEN and "elastic bed past its yield" in word
    # below the yield pressure: a pass
    summary = _outcome(study, _results(study, winkler=0.9 * nominal))
    toe = next(a for a in summary["outcome"]["answers"] if a["key"] == "toe_crushes")
    assert "caveat" not in toe
    # a bed that yields in the model: its pressure is capped there, no caveat of this kind
    plastic = replace(study, bed=replace(study.bed, yield_pressure=low))
    summary = _outcome(plastic, _results(plastic, winkler=pressure))
    toe = next(a for a in summary["outcome"]["answers"] if a["key"] == "toe_crushes")
    assert "elastic bed" not in toe.get("caveat", "")


def test_the_terminal_says_the_caveats():
    """``colonna study`` prints each caveat beside its answer and its model."""
    from colonna.studies.cli import short_summary
    from colonna.studies.kinds import DEFAULT_KIND, KINDS

    study = _study()
    summary = _outcome(study, _results(study, winkler=9.36 * study.stone.fc))
    printed = short_summary(KINDS[DEFAULT_KIND].short, summary, Path("out/index.html"))
    assert "its collars would carry 18 times f_y" in printed[crosscheck.SDOF_HALF]
    assert "local spalling of the corner possible" in printed["Does the toe crush?"]


def test_a_fragility_run_says_when_it_overturned():
    """Each fragility run (studies.fragility.models) of a free block carries when it
    overturned, as the model's own run says (rock's and rock_multibody's overturn_time), and
    None where it stood: the report's "not applicable: ... overturned at t = ..." in place of
    its largest |theta| / alpha, which is the stopping angle."""
    import math

    from colonna.core.ground import Record
    from colonna.rigid.multibody import rock_multibody
    from colonna.rigid.solve import rock
    from colonna.studies.fragility.models import FREE_TIME_P, multibody_runs, sdof_runs

    study = replace(_study(), collars=(), cracked=False)
    block = study.rocking_block
    omega = 3.0 * block.p
    t = np.linspace(0.0, 2.0 * math.pi / omega, 201)
    record = Record(t, np.sin(omega * t), "pulse")
    uplift = block.g * math.tan(block.alpha)
    scales = [1.05 * uplift, 6.0 * uplift]  # stands; overturns
    duration = record.end_time + FREE_TIME_P / block.p
    ground = record.scaled(scales[1])
    sdof = rock(block, Motion(ground, duration=duration), model="nonlinear").overturn_time
    multibody = rock_multibody(block, Motion(ground, duration=duration)).summary()["overturn_time"]
    for runs, when in (
        (sdof_runs(study, record, scales), sdof),
        (multibody_runs(study, record, scales), multibody),
    ):
        assert [r["overturned"] for r in runs] == [False, True]
        assert runs[0]["overturned_at"] is None
        assert runs[1]["overturned_at"] == pytest.approx(when, rel=1e-3)


# --- slow: every kind on a column that overturns ----------------------------------------------

BASE = TINY_STUDY.format(amplitude_ratio=4.0, duration=1.0).replace("[run]", "[run]\nreplicas = 2")


def _kind(text: str, kind: str) -> str:
    return text.replace('name = "tiny"', f'name = "tiny"\nkind = "{kind}"')


# each kind with a column, as a study that overturns the tiny column in every model (cheap
# settings: one worker, 1 s, two replicas; free rocking: a collar too weak to hold the halves
# together, released at 0.95 alpha_column, which each half cannot stand at)
OVERTURNING = {
    "cross-check": BASE,
    "collar-design": _kind(BASE, "collar-design"),
    "solid-vs-cracked": _kind(BASE, "solid-vs-cracked"),
    "mesh-convergence": _kind(BASE, "mesh-convergence")
    + "[convergence]\nsizes = [0.1, 0.05, 0.025]\n",
    "spectrum-crosscheck": _kind(BASE, "spectrum-crosscheck").replace(
        "amplitude_ratio = 4.0\nomega_ratio = 3.0\n", 'pulse = "sine"\n'
    )
    + "[grid]\nomega_ratios = [3.0, 3.0]\namplitude_ratios = [4.0, 4.0]\npoints = [1, 1]\n",
    "free-rocking": _kind(BASE, "free-rocking")
    .replace("[ground]\namplitude_ratio = 4.0\nomega_ratio = 3.0\n", "")
    .replace("t = 0.004\nh = 0.02", "t = 0.0002\nh = 0.001")
    .replace('name = "tiny"', 'name = "tiny"\nintended = ["collar.t", "collar.h"]')
    + "[free_rocking]\ntilt_fractions = [0.95]\ndamping = [0.05]\nmesh_sizes = [0.1]\n",
    # the SDOF and the multibody of an uncracked 0.6 x 4 m column over four one-cycle pulses
    # (tiny_study.write_pulse_suite), eight levels: in each model it overturns at some and
    # stands at others
    "fragility": TINY_FRAGILITY.replace(
        'models = ["sdof"]', 'models = ["sdof", "multibody"]'
    ).replace("steps = 24", "steps = 8"),
    # the same column cracked, its collar layouts over the same suite: its FEM stripe at the
    # design intensity overturns in some records
    "collar-layout": TINY_LAYOUT.format(target=3.2e-3),
    # the tiny column found cracked from the top to mid-height, its crack swept from none to
    # the full height: the fully split column overturns (its partial cracks need not)
    "crack-extent": _kind(BASE, "crack-extent").replace(
        "width = 0.2\n", "width = 0.2\ncrack = [0.5, 1.0]\n"
    ),
}


def test_every_kind_with_a_column_is_covered():
    from colonna.studies.kinds import KINDS

    # zhang-makris aside (no column: its histories are pinned by
    # test_zhang_makris_histories_of_overturned_blocks)
    assert set(KINDS) - set(OVERTURNING) == {"zhang-makris"}


def _pdf_text(pdf: Path) -> str:
    return subprocess.run(
        ["pdftotext", "-layout", str(pdf), "-"], capture_output=True, text=True, check=True
    ).stdout


@pytest.mark.slow
@pytest.mark.parametrize("kind", list(OVERTURNING))
def test_no_number_from_a_stopped_run_in_any_kind(kind, tmp_path):
    """The kind's study of a column that overturns (the premise, checked: its FEM overturns in
    every replica; free rocking: its FEM released from the tilt; fragility: each model at some
    levels, not all) gives no number of a stopped run in summary.json, its report, its terminal
    lines or (where Chromium and pdftotext are installed) its PDF; it says "not applicable:
    ... overturned at t = ..." where one stood (the fragility: :func:`_assert_fragility_says_
    each_overturning`)."""
    study = tmp_path / "study.toml"
    study.write_text(OVERTURNING[kind])
    if kind in ("fragility", "collar-layout"):
        write_pulse_suite(tmp_path)
    out = tmp_path / "out"
    pdf = (
        kind in ("cross-check", "fragility")
        and shutil.which("pdftotext") is not None
        and any(shutil.which(b) for b in ("chromium", "chromium-browser", "google-chrome"))
    )
    command = [
        sys.executable,
        "-c",
        "import sys\nfrom colonna.studies.cli import main\nsys.exit(main(sys.argv[1:]))\n",
        "study",
        str(study),
        "--out",
        str(out),
        "--workers",
        "1",
    ] + (["--pdf"] if pdf else [])
    done = subprocess.run(command, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr[-3000:]
    summary = json.loads((out / "summary.json").read_text())
    if kind == "free-rocking":
        assert summary["tilts"][0]["fem"]["status"].startswith("overturned"), "the premise"
    elif kind == "collar-layout":  # the premise: its FEM stripe overturns, not in all
        over = summary["fem"]["overturned"]
        assert any(over) and not all(over), over
    elif kind == "crack-extent":  # the premise: the full crack's FEM overturns
        assert summary["variants"]["crack-100"]["fem_overturned"] == "yes"
    elif kind == "fragility":
        for model in summary["models"]:  # the premise: it overturns at some levels, not all
            over = np.array(summary["runs"][model]["overturned"], dtype=bool)
            assert over.any() and not over.all(), model
    else:
        assert _stays_up(summary) == "no", "the premise: the FEM overturns"
    text = _pdf_text(out / "report.pdf") if pdf else ""
    assert stopped_numbers(out, done.stdout, text) == []
    said = json.dumps(summary) + (out / "index.html").read_text()
    # the spectrum's maps and the collar layout's capacities and frequencies give no rotation
    # to replace (the layout's FEM runs that overturned have overturned_at and no peak)
    if kind not in ("spectrum-crosscheck", "collar-layout"):
        assert re.search(r"not applicable: [^\"<]*overturned at t = \d", said)
    if pdf:
        assert "not applicable:" in text
    if kind == "cross-check":  # the first screen's caveats on a real run (issue 48)
        _assert_first_screen_caveats(summary, done.stdout)
    if kind == "fragility":
        _assert_fragility_says_each_overturning(out, summary, pdf)


def _assert_first_screen_caveats(summary: dict, terminal: str) -> None:
    """The tiny column's SDOF half block stays up on its elastic collar springs past f_y (its
    multibody and FEM models overturn): its row says so and is no pass, here and at the
    terminal; the toe answer gives the averaged stress and the toe section's local pressure."""
    models = {m["model"]: m for m in summary["outcome"]["models"]}
    sdof = models[crosscheck.SDOF_HALF]
    assert sdof["motion"] == "rocking" and sdof["collar_utilisation"] > 1.0
    caveat = (
        f"its collars would carry {sdof['collar_utilisation']:.3g} times f_y "
        "(the SDOF's collars are elastic)"
    )
    assert sdof["caveat"] == caveat
    assert summary["verdict_caveats"]["sdof_half_model_ok"] == caveat
    assert caveat in terminal
    toe = next(a for a in summary["outcome"]["answers"] if a["key"] == "toe_crushes")
    assert toe["local"]["ratio"] == pytest.approx(summary["bed"]["winkler_run_ratio_max"])
    assert toe["averaged"]["stress"] == pytest.approx(toe["median"] * summary["stone_fc"])


def _assert_fragility_says_each_overturning(out: Path, summary: dict, pdf: bool) -> None:
    """A fragility's run that overturned gives no largest |theta| / alpha but when it
    overturned: summary.json's peak_ratio null and overturned_at a time there (and only
    there); figures/ida.csv's peak empty beside its RECORD_overturned_at_s; the report's "Runs
    that overturned" says "not applicable: the <model> overturned at t = ..." for each record
    at its first overturning (and the PDF the same words); the IDA figure draws no such run
    as a value (its record's line has no point there) but a marker in the strip beside the
    axes, past its largest tick."""
    from matplotlib.figure import Figure

    from colonna.studies.fragility import report
    from colonna.studies.fragility.models import MODEL_NAMES

    levels = np.array(summary["levels"])
    with open(out / "figures" / "ida.csv") as fh:
        header = fh.readline().strip().split(",")
        rows = [line.rstrip("\n").split(",") for line in fh]
    csv = {name: [row[k] for row in rows] for k, name in enumerate(header)}
    page = _text((out / "index.html").read_text())
    said = 0
    for model in summary["models"]:
        runs = summary["runs"][model]
        over = np.array(runs["overturned"], dtype=bool)
        for i, row in enumerate(over):
            for j, o in enumerate(row):
                peak, t = runs["peak_ratio"][i][j], runs["overturned_at"][i][j]
                assert (peak is None, t is not None and t > 0) == (o, o), (model, i, j)
                shown = csv[f"{model}_record{i}"][j]
                assert shown == "" if o else float(shown) == pytest.approx(peak)
                when = csv[f"{model}_record{i}_overturned_at_s"][j]
                assert when == "" if not o else float(when) == pytest.approx(t)
            if row.any():
                j = int(np.argmax(row))
                words = f"not applicable: the {MODEL_NAMES[model]} overturned at t = "
                assert f"{words}{runs['overturned_at'][i][j]:.4g} s" in page, (model, i)
                said += 1
    assert said and page.count("not applicable: the ") == said
    if pdf:  # (in reading order: a table cell's lines together)
        read = subprocess.run(
            ["pdftotext", str(out / "report.pdf"), "-"], capture_output=True, text=True, check=True
        ).stdout
        assert " ".join(read.split()).count("not applicable: the ") == said
    # the IDA figure, drawn again in this process
    drawn = {}
    keep = Figure.savefig

    def spy(fig, fname, *args, **kwargs):
        if isinstance(fname, (str, Path)):
            drawn.setdefault(Path(fname).stem, fig)
        return keep(fig, fname, *args, **kwargs)

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(Figure, "savefig", spy)
        report.write_report(out)
    for ax, model in zip(drawn["ida"].axes, summary["models"]):
        over = np.array(summary["runs"][model]["overturned"], dtype=bool)
        lines = {line.get_gid(): line for line in ax.get_lines() if line.get_gid()}
        edge = max(ax.get_xticks())
        for i, row in enumerate(over):
            x = np.asarray(lines[f"record{i}"].get_xdata(), dtype=float)
            assert np.array_equal(np.isnan(x), row) and np.all(x[~row] <= edge), (model, i)
            if row.any():
                marks = lines[f"record{i}-overturned"]
                assert np.array_equal(marks.get_ydata(), levels[row])
                assert np.all(np.asarray(marks.get_xdata()) > edge)


def test_zhang_makris_histories_of_overturned_blocks():
    """The Zhang & Makris validation's histories (paper Fig. 5, Omega/p = 5): a block that
    overturns gives no max |theta| / alpha (its run stopped there) but the words, one that
    stays up gives its number."""
    from colonna.rigid.block import pulse_from_ratios
    from colonna.rigid.solve import rock
    from colonna.studies.zhang_makris import runner

    block = runner.zhang_makris_block()
    entries = {
        x: runner.history_entry(
            rock(
                block,
                Motion(pulse_from_ratios(block, "sine", runner.OMEGA_RATIO, x, "linear")),
                model="linear",
            )
        )
        for x in (4.5, 2.0)  # overturns after an impact (between Fig. 5b and 5c); stays up
    }
    over, up = entries[4.5], entries[2.0]
    assert over["overturned"] and not up["overturned"]
    assert re.fullmatch(
        r"not applicable: the block overturned at t = [\d.]+ s", over["max_abs_theta_over_alpha"]
    )
    assert 0 < up["max_abs_theta_over_alpha"] < 1

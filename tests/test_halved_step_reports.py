"""Every study kind whose FEM ensembles can be rerun at half their step says so (issue 47).

The cross-check's report says "Its step was halved" (tests/test_stable_step.py); the other
kinds that run FEM ensembles through studies.models.run_fem (collar design, mesh
convergence, solid vs cracked, free rocking) keep each halved run's step_halvings, step_note
and step in their summary.json (``halved_steps``) and say so in their report's opening data
paragraph. The spectrum cross-check and the fragility study run their FEM points batched
(studies.models.iter_fem), which does not rerun them: a failed point stops the study.

As there: the tiny study on a lead bed with the onset limit lifted to 2.0, so that its FEM
runs fail their balance at the first step and answer at half of it; two replicas, short runs."""

import json
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).parent))
from tiny_study import TINY_STUDY  # noqa: E402

LEAD = '[base]\nbed = "lead"\nplastic = false\n'  # the elastic lead: its springs uncapped
TINY = TINY_STUDY.format(amplitude_ratio=2.5, duration=0.6).replace("[run]", "[run]\nreplicas = 2")
FREE = """
[study]
name = "tiny-free"
kind = "free-rocking"
[column]
height = 1.0
width = 0.2
cracked = false
[ground]
pulse = "none"
[mesh]
size = 0.05
grading = 0.0
[run]
duration = 0.6
output_interval = 0.005
replicas = 2
[free_rocking]
tilt_fractions = [0.5]
damping = [0.0]
mesh_sizes = [0.1]
"""


def _kind(kind: str, extra: str = "") -> str:
    return TINY.replace('name = "tiny"', f'name = "tiny"\nkind = "{kind}"') + extra + LEAD


STUDIES = {
    "collar-design": _kind("collar-design"),
    "mesh-convergence": _kind("mesh-convergence", "[convergence]\nsizes = [0.1, 0.05, 0.025]\n"),
    "solid-vs-cracked": _kind("solid-vs-cracked"),
    "free-rocking": FREE + LEAD,
}


@pytest.mark.parametrize(
    "kind",
    # one kind in the default suite (the macro is shared), the others in make test-all
    [k if k == "collar-design" else pytest.param(k, marks=pytest.mark.slow) for k in STUDIES],
)
def test_a_study_whose_step_was_halved_says_so_in_its_opening(tmp_path, monkeypatch, kind):
    """The FEM runs of the study that fail at the lifted limit are halved once: each is in
    summary.json's ``halved_steps`` with its note and step, and the report's first paragraph
    names it, its note and that step (in s, as the cross-check's)."""
    import colonna.fem.model as fem_model
    from colonna.studies.cli import main
    from colonna.studies.report import fmt

    monkeypatch.setattr(fem_model, "CONTACT_ONSET_LIMIT", 2.0)
    study = tmp_path / "lead.toml"
    study.write_text(STUDIES[kind])
    out = tmp_path / "out"
    assert main(["study", str(study), "--out", str(out), "--workers", "1"]) == 0
    summary = json.loads((out / "summary.json").read_text())
    halved = summary["halved_steps"]
    assert halved  # measured: the one run of the collar design, the 50 mm mesh of the three
    # meshes (the coarser ones hold), each variant of solid vs cracked, each free-rocking run
    if kind == "mesh-convergence":  # the ensembles the kind keeps whole say the same
        assert [r["step_note"] for r in halved] == [
            f["step_note"] for f in summary["fem"].values() if f["step_halvings"]
        ]
    for run in halved:
        assert run["step_halvings"] == 1
        assert run["step_note"].startswith("rerun at dt/2 after the energy balance is off by")
        assert run["dt"] > 0.0
    body = " ".join((out / "index.html").read_text().split("</section>")[-1].split())
    opening = body[body.index("<p>") : body.index("</p>")]
    for k, run in enumerate(halved):
        sentence = (
            f"The step of {run['run']} was halved: its replicas were {run['step_note']} at the "
            f"first step, whose runs were not an answer; its numbers here are those of the run "
            f'at <span data-key="halved_steps.{k}.dt">{fmt(run["dt"], 3)}</span>&nbsp;s.'
        )
        assert sentence in opening


def test_a_study_whose_steps_held_says_nothing_of_halving():
    """A summary without halved runs (or saved before them) gives no sentence."""
    from colonna.studies.guard import halved_steps

    assert halved_steps([("the FEM run", {"step_halvings": 0, "step_note": None})]) == []
    assert halved_steps([("the FEM run", {"dt": 1e-5})]) == []
    assert halved_steps(
        [("a run", {"step_halvings": 2, "step_note": "rerun at dt/4", "dt": 1.0})]
    ) == [{"run": "a run", "step_halvings": 2, "step_note": "rerun at dt/4", "dt": 1.0}]

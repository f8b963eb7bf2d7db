"""No text of a report figure runs off its figure, and the deformed FEM column is drawn at a state
to read (issue 48).

The trial's PDF cut a legend entry to "base contact pressure at the" and an axis label to
"nodes (MPa"; its "FEM at peak rotation" was the 45-degree overturning stop with its elastic
deformation x200. :func:`colonna.studies.report.texts_outside` finds a text past its figure's
edge once drawn; it is run on every figure the shipped kinds draw for a small study (every
``savefig`` of the run, in the runner or the report), and on the deformed column of a tall
column tipped 45 degrees (the trial's shape). The deformed column of a run that overturned is
drawn at its largest rotation before overturning, from the saved field frames."""

import json

import matplotlib
import numpy as np
import pytest

matplotlib.use("Agg")
from matplotlib.figure import Figure  # noqa: E402
from tiny_study import TINY_FRAGILITY, TINY_STUDY, write_pulse_suite  # noqa: E402

from colonna.studies.crosscheck import report as crosscheck  # noqa: E402
from colonna.studies.output import read_csv, write_csv, write_json  # noqa: E402
from colonna.studies.report import texts_outside, wrap  # noqa: E402

LONG = "base contact pressure at the nodes (MPa)"


def test_the_check_finds_cut_labels_legends_and_tick_labels():
    """A label taller than its figure, a legend off its right edge and a tick label off its left
    edge are each found, by their text; wrapped and laid out, none is."""
    fig = Figure(figsize=(8, 3.2))
    ax = fig.subplots()
    ax.plot([0, 1], [0, 1], label="base contact pressure at the nodes (max 9.36 MPa)")
    ax.set_ylabel(LONG)
    ax.set_yticks([0.0, 1.0], ["a tick label far too long for the margin", "1"])
    ax.legend(loc="upper left", bbox_to_anchor=(1.5, 1.0))
    found = texts_outside(fig)
    assert f"text: {LONG}" in found
    assert "text: base contact pressure at the nodes (max 9.36 MPa)" in found
    assert "axes 0 y tick label: a tick label far too long for the margin" in found
    assert len(found) == 3, found
    ax.set_ylabel(wrap(LONG, 24))
    ax.set_yticks([0.0, 1.0], ["0", "1"])
    ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0))
    fig.tight_layout()
    assert texts_outside(fig) == []


# --- the deformed column: which state, at what magnification --------------------------------

STEP = 0.01  # s between history rows; the saved field frames are every other row


def _tilt(t: np.ndarray, overturns_first: bool) -> np.ndarray:
    """A rotation history (rad): a swing to 0.06 peaking at t = 0.26 s, one to -0.03 ending at
    t = 0.72 s, then the swing in which the column overturns (past 45 degrees at t = 1 s); or,
    ``overturns_first``, that last swing alone from t = 0."""
    if overturns_first:
        return 0.8 * (t / t[-1]) ** 2
    return np.where(
        t <= 0.52,
        0.06 * np.sin(np.pi * t / 0.52),
        np.where(
            t <= 0.72, -0.03 * np.sin(np.pi * (t - 0.52) / 0.2), 0.8 * ((t - 0.72) / 0.28) ** 2
        ),
    )


def _fem_run(out, theta, overturned, width=0.2, height=1.0, collars=(0.5,)):
    """The FEM files the deformed-column figure reads, for a cracked column turned as one rigid
    body about its right toe by ``theta`` (rad, one per history row), with a small elastic
    bending: history.csv, fields.xdmf (every other row), fields_peak_rotation.vtu (the row of
    the largest rotation: the stop of a run that overturned), base_pressure.csv, summary.json.
    Returns the history and the displacement of each row."""
    from colonna.meshes.column import column_mesh
    from colonna.meshes.io import write, write_time_series

    mesh = column_mesh(width, height, width / 4, grading=0.0, pinned_heights=collars)
    X = mesh.points.T
    toe = np.array([0.5 * width, 0.0])
    bend = np.column_stack((1e-6 * (X[:, 1] / height) ** 2, np.zeros(len(X))))

    def displacement(a: float) -> np.ndarray:
        c, s = np.cos(a), np.sin(a)
        return toe + (X - toe) @ np.array([[c, -s], [s, c]]).T - X + bend

    t = np.arange(theta.size) / 100.0  # STEP apart, each the float of its decimal
    u = [displacement(-a) for a in theta]  # clockwise about the right toe
    fem = out / "cases" / "fem"
    marks = np.zeros(len(X), dtype=np.int64)
    for c, y in enumerate(collars):
        marks[[mesh.outer_node_at(0, y), mesh.outer_node_at(1, y)]] = c + 1
    k = int(np.argmax(np.abs(theta)))
    write(
        fem / "fields_peak_rotation.vtu",
        mesh,
        point_data={"displacement": u[k], "elastic_displacement": bend, "collar_end": marks},
    )
    frames = list(range(0, theta.size, 2))
    write_time_series(
        fem / "fields.xdmf", mesh, t[frames], lambda j: {"displacement": u[frames[j]]}
    )
    history = {"t": t, "theta_left": -theta, "theta_right": -theta}
    write_csv(fem / "history.csv", history)
    base = np.concatenate(mesh.base_nodes)
    write_csv(
        fem / "base_pressure.csv",
        {"t": t, **{f"p_x={X[n, 0]:.6g}": 1e6 * (1.0 + t) * (X[n, 0] > 0) for n in base}},
    )
    write_json(fem / "summary.json", {"overturned": overturned})
    (out / "figures").mkdir(exist_ok=True)
    return read_csv(fem / "history.csv"), u, mesh


def _drawn(out, history):
    figs = []
    state = crosscheck.drawn_state(out, history)
    kept = {}

    def capture(where, name, fig, caption, data_file=""):
        kept["fig"], kept["caption"] = fig, caption
        return {"name": name}

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(crosscheck, "figure", capture)
        crosscheck._deformed_figure(out, history, figs, state)
    return state, kept["fig"], kept["caption"]


def test_an_overturned_run_is_drawn_at_its_largest_rotation_before_overturning(tmp_path):
    """The run stopped past 45 degrees: the figure draws the saved frame of its largest rotation
    before the swing it overturned in (t = 0.26 s, 0.06 rad), says so with the stop's time, and
    states its magnification on the figure."""
    theta = _tilt(np.arange(101) / 100.0, overturns_first=False)
    history, u, mesh = _fem_run(tmp_path, theta, overturned=True)
    state, fig, caption = _drawn(tmp_path, history)
    assert state["when"] == crosscheck.BEFORE
    assert state["t"] == pytest.approx(0.26, abs=1e-9)
    assert state["swing"] == pytest.approx(0.72, abs=1e-9) and state["stop"] == pytest.approx(1.0)
    assert np.allclose(state["displacement"], u[26], atol=1e-12)
    title = fig.axes[0].get_title(loc="left")
    assert title.startswith("FEM at its largest rotation before overturning, t = 0.260 s")
    elastic = crosscheck._elastic_part(mesh.points.T, mesh.cells.T, mesh.cell_body, u[26])
    factor = crosscheck._magnification(float(np.abs(elastic).max()), 1.0)
    assert 0.004 < factor * np.abs(elastic).max() <= 0.02  # about 2 % of the height
    assert title.endswith(f"elastic deformation x{factor:g}")
    assert f"magnified x{factor:g}" in caption and "overturns" in caption
    assert "stopping convention" in caption and "t = 1 s" in caption
    assert texts_outside(fig) == []


def test_a_rigid_motion_has_no_elastic_part():
    """A saved frame has no elastic field of its own: each half's best-fit rigid motion taken
    off leaves nothing of a rigid turn and shift of each half (the solver's own split is
    compared on a real run below)."""
    from colonna.meshes.column import column_mesh

    mesh = column_mesh(0.2, 1.0, 0.05, grading=0.0)
    X, quads = mesh.points.T, mesh.cells.T
    u = np.zeros_like(X)
    for b, (a, shift) in enumerate(((0.3, (0.01, 0.02)), (-0.1, (0.0, -0.03)))):
        on = mesh.node_body == b
        c, s = np.cos(a), np.sin(a)
        u[on] = X[on] @ np.array([[c, -s], [s, c]]).T - X[on] + np.array(shift)
    assert np.abs(crosscheck._elastic_part(X, quads, mesh.cell_body, u)).max() < 1e-15
    bend = np.column_stack((1e-6 * X[:, 1] ** 2, np.zeros(len(X))))
    assert np.abs(crosscheck._elastic_part(X, quads, mesh.cell_body, u + bend)).max() > 1e-7


def test_a_run_that_overturns_in_its_first_swing_is_drawn_at_its_stop_said_so(tmp_path):
    theta = _tilt(np.arange(101) / 100.0, overturns_first=True)
    history, _, _ = _fem_run(tmp_path, theta, overturned=True)
    state, fig, caption = _drawn(tmp_path, history)
    assert state["when"] == crosscheck.STOP and state["t"] == pytest.approx(1.0)
    assert fig.axes[0].get_title(loc="left").startswith("FEM at the overturning stop, t = 1.000 s")
    assert "overturned in its first swing" in caption and "stopping convention" in caption


def test_a_run_that_stays_up_is_drawn_at_its_peak_rotation(tmp_path):
    theta = _tilt(np.arange(101) / 100.0, overturns_first=False)
    theta = np.where(np.arange(101) > 72, 0.0, theta)  # no last swing: it stays up
    history, _, _ = _fem_run(tmp_path, theta, overturned=False)
    state, fig, caption = _drawn(tmp_path, history)
    assert state == {"t": pytest.approx(0.26), "when": crosscheck.PEAK, "displacement": None}
    assert fig.axes[0].get_title(loc="left").startswith("FEM at peak rotation, t = 0.260 s")


def test_a_tall_column_tipped_45_degrees_keeps_its_texts_inside(tmp_path):
    """The trial's shape: a 5.2 x 0.55 m column with three collars that overturned in its first
    swing, drawn at its stop past 45 degrees: title, legend (the nodal pressure's entry
    wrapped) and tick labels inside the figure."""
    theta = np.linspace(0.0, 0.8, 41) ** 1.0
    history, _, _ = _fem_run(
        tmp_path, theta, overturned=True, width=0.55, height=5.2, collars=(0.6, 2.6, 4.6)
    )
    _, fig, _ = _drawn(tmp_path, history)
    legend = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    assert any(e.startswith("base contact pressure at the\nnodes (max") for e in legend)
    assert texts_outside(fig) == []


# --- every figure of the shipped kinds' reports, for a small study --------------------------


def _kind(text: str, kind: str) -> str:
    return text.replace('name = "tiny"', f'name = "tiny"\nkind = "{kind}"')


TINY = TINY_STUDY.format(amplitude_ratio=2.5, duration=0.4)
OVERTURNING = TINY_STUDY.format(amplitude_ratio=4.0, duration=1.0).replace(
    "[run]", "[run]\nreplicas = 2"
)
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
duration = 1.2
output_interval = 0.002
[free_rocking]
tilt_fractions = [0.5]
damping = [0.0]
mesh_sizes = [0.1]
"""
GRID = (
    _kind(TINY_STUDY.format(amplitude_ratio=2.5, duration=0.6), "spectrum-crosscheck").replace(
        "amplitude_ratio = 2.5\nomega_ratio = 3.0\n", 'pulse = "sine"\n'
    )
    + "[grid]\nomega_ratios = [1.5, 6.0]\namplitude_ratios = [1.5, 8.0]\npoints = [3, 3]\n"
)
FRAGILITY = TINY_FRAGILITY
slow = pytest.mark.slow
# (study file, the figures it must draw at least)
STUDIES = {
    "cross-check, overturns": (
        OVERTURNING,
        {"theta", "deformed", "collars", "toe_stress", "base_pressure", "spectrum"},
    ),
    "collar-design": (
        _kind(TINY_STUDY.format(amplitude_ratio=2.5, duration=0.1), "collar-design"),
        {"design_chart", "collar_utilisation", "ductile_design", "ground_motion"},
    ),
    "fragility": (FRAGILITY, {"curves"}),
    "cross-check, rocks": (TINY, {"theta", "deformed", "toe_stress", "base_pressure"}),
    "free-rocking": (FREE, {"rotations", "ratios"}),
    "spectrum-crosscheck": (GRID, {"maps", "disagreement", "boundaries"}),
    "solid-vs-cracked": (
        _kind(TINY_STUDY.format(amplitude_ratio=2.5, duration=0.3), "solid-vs-cracked"),
        {"theta_variants"},
    ),
    "crack-extent": (
        _kind(TINY_STUDY.format(amplitude_ratio=2.5, duration=0.3), "crack-extent"),
        {"theta_extents", "answers_extent"},
    ),
    "mesh-convergence": (
        _kind(TINY_STUDY.format(amplitude_ratio=2.5, duration=0.3), "mesh-convergence").replace(
            "[run]", "[convergence]\nsizes = [0.1, 0.05, 0.025]\n\n[run]"
        ),
        {"convergence"},
    ),
    "zhang-makris": ('[study]\nname = "zm"\nkind = "zhang-makris"\n', {"spectrum_linear_free"}),
}
FAST = ("collar-design", "fragility")  # the default suite's; the rest (20-30 s each) slow


@pytest.mark.chaotic
@pytest.mark.parametrize("name", [n if n in FAST else pytest.param(n, marks=slow) for n in STUDIES])
def test_no_text_of_a_report_figure_runs_off_it(tmp_path, monkeypatch, name):
    """The study run in this process (one worker), every figure it saves (runner or report)
    checked once drawn; where the FEM overturned, its deformed column is not drawn at the
    stop but before it, and a saved frame's elastic part is the solver's split."""
    from pathlib import Path

    import meshio

    from colonna.studies.cli import main

    text, expected = STUDIES[name]
    keep = Figure.savefig
    checked = {}

    def spy(fig, fname, *args, **kwargs):
        if isinstance(fname, (str, Path)) and Path(fname).stem not in checked:
            checked[Path(fname).stem] = texts_outside(fig)
        return keep(fig, fname, *args, **kwargs)

    monkeypatch.setattr(Figure, "savefig", spy)
    if name == "fragility":
        write_pulse_suite(tmp_path)
    study = tmp_path / "study.toml"
    study.write_text(text)
    out = tmp_path / "out"
    options = ["--grid", "3x3"] if name == "spectrum-crosscheck" else []
    assert main(["study", str(study), "--out", str(out), "--workers", "1", *options]) == 0
    assert expected <= set(checked), sorted(checked)
    assert {figure: cut for figure, cut in checked.items() if cut} == {}
    if name == "cross-check, overturns":
        page = (out / "index.html").read_text()
        assert json.loads((out / "summary.json").read_text())["fem"]["overturned"]
        assert "The FEM column at peak rotation" not in page
        assert "The FEM column at its largest rotation before overturning" in page or (
            "The FEM column at the overturning stop" in page
        )
        m = meshio.read(out / "cases" / "fem" / "fields_peak_rotation.vtu")
        quads = np.vstack([c.data for c in m.cells if c.type == "quad"])
        body = np.concatenate(m.cell_data["body"]).astype(int)
        split = crosscheck._elastic_part(
            m.points[:, :2], quads, body, m.point_data["displacement"][:, :2]
        )
        solver = m.point_data["elastic_displacement"][:, :2]
        assert np.abs(split - solver).max() < 1e-6 * np.abs(solver).max()


@pytest.mark.parametrize("overturned", [True, False])
def test_the_render_at_the_end_of_an_overturned_run_says_it_is_the_stop(
    tmp_path, monkeypatch, overturned
):
    """The pyvista render of a run whose peak is its end (no field of a frame before it: the
    renders colour by stress) says that it is the overturning stop where the run overturned,
    and that it is drawn true to scale."""
    import shutil

    from colonna.studies import render

    _fem_run(tmp_path, np.linspace(0.0, 0.8, 41), overturned=overturned)
    fem = tmp_path / "cases" / "fem"
    for name in ("initial", "final"):
        shutil.copy(fem / "fields_peak_rotation.vtu", fem / f"fields_{name}.vtu")
    monkeypatch.setattr(render, "_snapshot", lambda m, path: None)
    monkeypatch.setattr(render, "_gif", lambda out, fem, n: ("rocking.gif", "the rocking"))
    images = render.render_snapshots(tmp_path)
    assert [name for name, _ in images] == [
        "render_initial.png",
        "render_peak_rotation.png",
        "rocking.gif",
    ]
    caption = images[1][1]
    assert "end of the run" in caption and "true to scale" in caption
    assert ("overturning stop" in caption) == overturned
    assert ("stopping convention" in caption) == overturned

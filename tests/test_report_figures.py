"""The browser check of report figures (tests/data/report_check.js) catches what it should.

A figure with nothing drawn, a legend entry whose handle is drawn nowhere, a legend that falls
outside the figure and an image that does not decode are each reported; a good figure is not.
The reports themselves are checked with it in test_study, test_spectrum_crosscheck and
test_free_rocking."""

import base64
import re
from types import SimpleNamespace

import matplotlib
import numpy as np
import pytest

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from browser import browser, check_report  # noqa: E402
from matplotlib.patches import Patch  # noqa: E402

from colonna.studies.report import TEMPLATES, figure, image  # noqa: E402


def _good(out):
    fig, ax = plt.subplots()
    ax.plot([0, 1, 2], [0, 1, 0], color="C0", label="rotation")
    ax.axhline(0.5, color="k", ls="--", label="f_y (yield stress)")
    ax.legend()
    return figure(out, "good", fig, "a good figure")


def _empty(out):
    fig, ax = plt.subplots()
    ax.set_xlabel("t (s)")
    return figure(out, "empty", fig, "nothing drawn")


def _proxy(out):
    fig, ax = plt.subplots()
    ax.plot([0, 1], [1, 2], color="C0", label="drawn")
    ax.legend(handles=[*ax.get_lines(), Patch(color="C3", label="never drawn")])
    return figure(out, "proxy", fig, "a legend entry for nothing")


def _outside(out):
    fig, ax = plt.subplots()
    ax.plot([0, 1], [1, 2], color="C0", label="off the page")
    ax.legend(loc="upper left", bbox_to_anchor=(1.5, 1.0))  # no tight bbox: cut off
    return figure(out, "outside", fig, "legend outside")


def test_the_browser_check_finds_what_is_wrong(tmp_path):
    browser()
    broken = tmp_path / "broken.png"
    broken.write_bytes(b"not a png")
    figs = [
        _good(tmp_path),
        _empty(tmp_path),
        _proxy(tmp_path),
        _outside(tmp_path),
        image(broken, "an image that does not decode"),
    ]
    page = TEMPLATES.from_string(
        '{% from "macros.html.j2" import figures with context %}'
        "<!DOCTYPE html><html><body>{{ figures(figs) }}</body></html>"
    ).render(figs=figs)
    (tmp_path / "index.html").write_text(page)
    found = {r["name"]: r["problems"] for r in check_report(tmp_path / "index.html", tmp_path)}
    assert found["good"] == []
    assert found["empty"] == ["no data drawn"]
    assert (
        len(found["proxy"]) == 1
        and "never drawn" in found["proxy"][0]
        and "is not drawn" in found["proxy"][0]
    )
    assert found["outside"] == ['legend entry "off the page" outside the figure']
    assert found["broken"] == ["image not drawn"]
    assert base64.b64decode(figs[-1]["data"]) == b"not a png"


def _fem_output(out, thetas):
    """A FEM run's files as the renders read them (fields_*.vtu, fields.xdmf): a cracked column
    0.45 x 4 m turned as one rigid body about its right toe by the angles thetas (rad), the last
    three being the initial, peak and final snapshots; the stress field grows with height."""
    import numpy as np

    from colonna.meshes.column import column_mesh
    from colonna.meshes.io import write, write_time_series

    mesh = column_mesh(0.45, 4.0, 0.1125, grading=0.0)
    X = mesh.points.T
    toe = np.array([0.225, 0.0])

    def displacement(theta):
        c, s = np.cos(theta), np.sin(theta)
        d = X - toe
        return toe + d @ np.array([[c, -s], [s, c]]) - X  # clockwise: towards the right

    fem = out / "cases" / "fem"
    centres = X[mesh.cells].mean(axis=0)
    for name, theta in zip(("initial", "peak_rotation", "final"), thetas[-3:]):
        write(
            fem / f"fields_{name}.vtu",
            mesh,
            point_data={"displacement": displacement(theta)},
            cell_data={"sigma_min_principal": -1e5 * centres[:, 1]},
        )
    write_time_series(
        fem / "fields.xdmf",
        mesh,
        np.arange(len(thetas)) * 0.1,
        lambda k: {"displacement": displacement(thetas[k])},
    )
    (out / "figures").mkdir()


def _border(png):
    """Background rows/columns (px) on each side of an image: top, bottom, left, right."""
    import numpy as np
    from PIL import Image

    img = np.asarray(Image.open(png).convert("RGB")).astype(int)
    drawn = np.any(np.abs(img - 255) > 6, axis=2)
    rows, cols = np.nonzero(drawn.any(axis=1))[0], np.nonzero(drawn.any(axis=0))[0]
    return (rows[0], img.shape[0] - 1 - rows[-1], cols[0], img.shape[1] - 1 - cols[-1]), img


def test_renders_are_cropped_to_the_column_and_show_peak_and_end(tmp_path, capfd, monkeypatch):
    """Each render is trimmed to what is drawn (a few px of border), the peak-rotation and end
    frames are drawn from their own data, and no display leaves no VTK warning on stderr."""
    import numpy as np
    from PIL import Image

    from colonna.studies.render import MARGIN, render_snapshots

    monkeypatch.delenv("DISPLAY", raising=False)
    _fem_output(tmp_path, [0.0, 0.05, 0.12, 0.04, 0.0, 0.12, 0.04])
    images = render_snapshots(tmp_path, n_frames=4)
    assert [name for name, _ in images] == [
        "render_initial.png",
        "render_peak_rotation.png",
        "render_final.png",
        "rocking.gif",
    ]
    pictures = {}
    for name, _ in images[:3]:
        border, pictures[name] = _border(tmp_path / "figures" / name)
        assert max(border) <= MARGIN + 1, (name, border)
        assert pictures[name].shape[0] > 2 * pictures[name].shape[1]  # a tall column
    assert pictures["render_peak_rotation.png"].shape != pictures[
        "render_final.png"
    ].shape or np.any(pictures["render_peak_rotation.png"] != pictures["render_final.png"])
    gif = Image.open(tmp_path / "figures" / "rocking.gif")
    assert gif.n_frames == 4
    drawn = 0
    for k in range(gif.n_frames):  # one box for all frames, trimmed as a whole
        gif.seek(k)
        drawn = drawn + 255 - np.asarray(gif.convert("L"), dtype=int)
    rows, cols = np.nonzero((drawn > 6).any(axis=1))[0], np.nonzero((drawn > 6).any(axis=0))[0]
    assert (
        max(rows[0], drawn.shape[0] - 1 - rows[-1], cols[0], drawn.shape[1] - 1 - cols[-1])
        <= MARGIN + 1
    )
    assert "bad X server" not in capfd.readouterr().err
    for name in ("render_initial.png", "render_peak_rotation.png"):
        _assert_bar_title_apart_from_its_ticks(pictures[name])


def _assert_bar_title_apart_from_its_ticks(img):
    """The colour bar (the lowest band of coloured rows) has its tick labels just above it and
    its title below it: dark text on both sides, each apart from the bar by blank rows, so
    that the title cannot overprint the numbers (as VTK's own title did)."""
    chroma = img.max(axis=2) - img.min(axis=2)
    coloured = np.flatnonzero((chroma > 60).sum(axis=1) > 0.3 * img.shape[1])
    assert coloured.size, "no colour bar"
    bottom = coloured[-1]
    top = bottom
    while top - 1 in set(coloured):
        top -= 1
    dark = (img.max(axis=2) < 110).sum(axis=1) > 0
    above, below = dark[max(top - 30, 0) : top], dark[bottom + 1 :]
    assert above.any() and below.any(), (above.any(), below.any())  # ticks above, title below
    assert not below[:1].any() and not above[-1:].any()  # a blank row each side of the bar


def test_a_run_that_ends_at_its_peak_rotation_is_drawn_once(tmp_path):
    """An overturned run stops at its largest rotation: the peak and end snapshots are the same
    frame, drawn once with a caption that says so."""
    from colonna.studies.render import render_snapshots

    _fem_output(tmp_path, [0.0, 0.05, 0.1, 0.0, 0.1, 0.1])
    images = render_snapshots(tmp_path, n_frames=3)
    names = [name for name, _ in images]
    assert names == ["render_initial.png", "render_peak_rotation.png", "rocking.gif"]
    assert "end of the run" in images[1][1]


# --- the figures of the reports: the design point, a marker per computed pulse, curves that
# coincide, legends beside the data. Each report is written from made-up run files, its
# figures kept as figure receives them; the pages themselves (templates) are not drawn.


def _history(t, **columns):
    return {"t": t, **columns}


def _made_up_runs(out):
    """The files the report writers read, for a cracked column whose three collars (and the
    variants "cracked" and "cracked-collars", and the two models released at one tilt) have
    the same histories: curves that lie on top of each other. The design summary is that of a
    0.225 x 4 m half column with 8 x 60 mm collars at a_g = 0.3 g."""
    from colonna.rigid.block import Block
    from colonna.rigid.collars import Collar
    from colonna.rigid.design import design_chart, design_collars
    from colonna.studies.output import write_csv, write_json

    t = np.linspace(0.0, 2.0, 401)
    theta = 0.02 * np.sin(2 * np.pi * t) * np.exp(-t)
    stress = 150e6 * np.abs(np.sin(3 * t))
    runs = {}
    crosscheck = out / "crosscheck"
    write_csv(
        crosscheck / "cases" / "fem" / "history.csv",
        _history(
            t,
            theta_left=theta,
            theta_right=theta,
            collar_1_stress=stress,
            collar_2_stress=stress,
            collar_3_stress=stress,
            edge_stress_left=5e6 + 0 * t,
            edge_stress_right=5e6 + 0 * t,
        ),
    )
    write_csv(
        crosscheck / "cases" / "multibody" / "history.csv",
        _history(t, theta_left=theta, theta_right=theta),
    )
    for key in ("rigid", "monolith"):
        write_csv(crosscheck / "cases" / key / "history.csv", _history(t, theta=theta))
    write_csv(
        crosscheck / "cases" / "fem" / "base_pressure.csv",
        {"t": t, **{f"p_x={x:g}": 1e6 * (1 + x) + 0 * t for x in (-0.2, 0.0, 0.2)}},
    )
    write_json(
        crosscheck / "summary.json",
        {
            "study": "made up",
            "fem": {"replicas": 1, "edge_length": 0.01},
            "collar_fy": [235e6] * 3,
            "stone_fc": 110e6,
        },
    )
    runs["crosscheck"] = crosscheck

    design = out / "design"
    block = Block.from_density(0.1125, 2.0, 2700.0, 0.45)
    collar = Collar(y=2.0, t=0.008, h=0.06)
    alphas, ratios = np.linspace(0.03, 0.4, 12), np.linspace(0.05, 1.0, 13)
    chart = design_chart(block.b, 2700.0, 0.45, collar, alphas, ratios, block.g)
    write_csv(
        design / "figures" / "design_chart.csv",
        {
            "alpha": np.repeat(alphas, ratios.size),
            "ag_over_g": np.tile(ratios, alphas.size),
            "required_stiffness": chart.ravel(),
        },
    )
    write_csv(
        design / "cases" / "fem" / "history.csv",
        _history(t, **{f"collar_{k}_utilisation": stress / 235e6 for k in (1, 2, 3)}),
    )
    write_json(
        design / "summary.json",
        {
            "study": "made up",
            "design": design_collars(block, collar, 0.3 * block.g).to_dict(),
            "design_alpha": block.alpha,
            "design_ag_over_g": 0.3,
            "collars_provided": 3,
            "lateral_stiffness_provided": 3 * collar.lateral_stiffness(block.b),
            "design_adequate": True,
            "fem_collar_max_utilisation": 0.64,
            "fem_collar_first_yield_time": None,
            "fem_overturned": False,
            "fem_max_rotation_over_yield_rotation": 0.8,
            "ductile_design": {
                "never_yields_t": 0.008,
                "holds_t": 0.006,
                "ductility_limit": 15.0,
                "study_t": 0.008,
            },
        },
    )
    runs["design"] = design

    grid = out / "grid"  # a 3 x 3 spectrum cross-check
    modes = [
        ["after-impact", "safe", "safe"],
        ["without-impact", "after-impact", "safe"],
        ["without-impact", "without-impact", "after-impact"],
    ]
    write_json(
        grid / "summary.json",
        {
            "study": "made up",
            "omega_ratios": [1.0, 3.0, 5.0],
            "amplitude_ratios": [2.0, 3.0, 4.0],
            "mode_fem": modes,
            "mode_multibody": modes,
            "mode_sdof": [["safe"] * 3, ["safe"] * 3, modes[2]],
            "collar_utilisation_fem": [[0.5] * 3] * 3,
            "toe_ratio_fem": [[0.05] * 3] * 3,
            "collar_yield_fem": [[False] * 3] * 3,
            "agreement_fem_multibody": 1.0,
            "agreement_fem_sdof": 5 / 9,
            "points": 9,
            "energy_error_fem_max": 0.01,
            "fem_seconds_per_point": 2.0,
        },
    )
    runs["grid"] = grid

    rocking = out / "free-rocking"
    tilts = []
    for k, fraction in enumerate((0.5, 0.8), start=1):
        for kind in ("fem", "multibody"):
            write_csv(
                rocking / "cases" / f"{kind}-tilt{k}" / "history.csv",
                _history(t, theta_left=fraction * 0.05 * np.cos(4 * t)),
            )
        ratios_k = [0.9, 0.88, 0.87]
        tilts.append(
            {
                "tilt_fraction": fraction,
                "tilt": fraction * 0.05,
                "fem": {"ratios": ratios_k, "ratio_first": ratios_k[0]},
                "multibody": {
                    "ratios": ratios_k if k == 1 else [0.8, 0.8],
                    "ratio_first": ratios_k[0] if k == 1 else 0.8,
                },
            }
        )
    write_json(
        rocking / "summary.json",
        {
            "study": "made up",
            "alpha": 0.05,
            "tilts": tilts,
            "restitution_housner": 0.85,
            "E": 50e9,
            "fem_ratio_study_stone": 0.9,
            "fem_ratio_study_stone_band": None,
            "replicas": 1,
            "fem_ratio_study_stone_mean": 0.89,
            "multibody_ratio": 0.9,
            "damping_variants": [],
            "mesh_variants": [],
            "damping": 0.05,
            "mesh_size": 0.05,
        },
    )
    runs["free-rocking"] = rocking

    sweep = out / "sweep"
    for n in ("solid", "cracked", "cracked-collars"):
        scale = 0.5 if n == "solid" else 1.0
        write_csv(
            sweep / "cases" / f"{n}-fem" / "history.csv",
            _history(t, theta_left=scale * theta, theta_right=scale * theta),
        )
        write_csv(sweep / "cases" / f"{n}-rigid" / "history.csv", _history(t, theta=theta))
    runs["sweep"] = sweep
    return runs


@pytest.fixture(scope="module")
def drawn(tmp_path_factory):
    """Every figure the report writers make from _made_up_runs: name -> (figure, what figure
    gave the template)."""
    from colonna.studies import report
    from colonna.studies.collar_design import report as collar_design
    from colonna.studies.crosscheck import report as crosscheck
    from colonna.studies.free_rocking import report as free_rocking
    from colonna.studies.mesh_convergence import report as mesh_convergence
    from colonna.studies.output import read_csv
    from colonna.studies.solid_vs_cracked import report as solid_vs_cracked
    from colonna.studies.spectrum_crosscheck import report as spectrum_crosscheck

    out = tmp_path_factory.mktemp("reports")
    runs = _made_up_runs(out)
    figures = {}
    keep = report.figure

    def capture(where, name, fig, caption, data_file=""):
        figures[name] = (fig, keep(where, name, fig, caption, data_file))
        return figures[name][1]

    kinds = (
        crosscheck,
        collar_design,
        spectrum_crosscheck,
        free_rocking,
        mesh_convergence,
        solid_vs_cracked,
    )
    with pytest.MonkeyPatch.context() as mp:
        for module in (report, *kinds):  # each kind's report draws through these
            mp.setattr(module, "figure", capture)
            # (a kind with one table and one figure renders through report.one_figure_report)
            mp.setattr(
                module, "render_page", lambda out, *a, **k: out / "index.html", raising=False
            )
        # (the plastic bands' figure needs a real design's trials: test_figure_texts draws it)
        mp.setattr(collar_design, "_ductile_design_figure", lambda *a: None)
        # the cross-check's two checked figures, drawn from its made-up runs and the part of
        # its typed summary they read (write_report needs a whole summary: test_study's)
        made_up = runs["crosscheck"]
        (made_up / "figures").mkdir(exist_ok=True)
        typed = SimpleNamespace(
            collar_fy=[235e6] * 3,
            stone_fc=110e6,
            toe_stress=None,
            outcome={},
            fem=SimpleNamespace(edge_length=0.01, edge_time=None, edge_stress_max=5e6),
        )
        histories = crosscheck._histories(made_up)
        crosscheck._collar_stress_figure(made_up, typed, histories, [])
        crosscheck._toe_stress_figure(made_up, typed, histories["fem"], [])
        collar_design.write_report(runs["design"])
        spectrum_crosscheck.write_report(runs["grid"])
        free_rocking.write_report(runs["free-rocking"])
        entries = {
            "peak_rotation": ([0.02, 0.021, 0.0212], 0.0213),
            "collar_max_utilisation": ([0.7, 0.72, 0.73], None),
            "edge_stress_max": ([4e6, 5e6, 5.5e6], 6e6),
            "toe_pressure_winkler": ([30e6, 31e6, 31.5e6], None),
        }
        summary = {
            "study": "made up",
            "sizes": [0.1, 0.05, 0.025],
            "dofs": [200, 800, 3200],
            "bed": None,
            "convergence": {
                key: {
                    "values": values,
                    "richardson": richardson,
                    "observed_order": None,
                    "fine_relative_error": None,
                }
                for key, (values, richardson) in entries.items()
            },
        }
        mesh_convergence._convergence_figure(runs["sweep"], summary)
        variant = {
            "fem_peak_rotation": 0.02,
            "fem_overturned": False,
            "rigid_peak_rotation": 0.02,
            "rigid_mode": "safe",
            "collar_max_utilisation": 0.5,
            "edge_stress_ratio": 0.05,
            "status": "ok",
        }
        solid_vs_cracked._variants_figure(
            runs["sweep"],
            {
                "study": "made up",
                "variants": {n: variant for n in ("solid", "cracked", "cracked-collars")},
            },
        )
    assert read_csv(runs["design"] / "figures" / "design_chart.csv")["alpha"].size == 12 * 13
    return figures


# the figures whose curves and legends are checked: of the cross-check only the collar and toe
# stress figures (its others are drawn elsewhere in write_crosscheck_report)
CHECKED = (
    "collars",
    "toe_stress",
    "design_chart",
    "collar_utilisation",
    "maps",
    "disagreement",
    "boundaries",
    "rotations",
    "ratios",
    "convergence",
    "theta_variants",
)


def _texts(fig) -> list[str]:
    from matplotlib.text import Text

    return [t.get_text() for t in fig.findobj(Text) if t.get_text()]


def test_the_design_chart_marks_the_design_point_in_kN_per_m(drawn):
    """The design chart is an inline figure with the study's own column and pulse marked at
    (a_g/g, alpha of the half block), its required stiffness and the provided one in the
    legend, and every stiffness on it in kN/m (none in N/m)."""
    fig, entry = drawn["design_chart"]
    assert "<svg" in entry["svg"] and entry["data_file"] == "figures/design_chart.csv"
    ax = fig.axes[0]
    stars = [line for line in ax.get_lines() if line.get_marker() == "*"]
    assert len(stars) == 1
    x, y = stars[0].get_xydata()[0]
    assert x == pytest.approx(0.3) and 0.03 < y < 0.4
    legend = [t.get_text() for t in ax.get_legend().get_texts()]
    assert any(t.startswith("design point") and "kN/m" in t for t in legend), legend
    # alpha is the rocking half block's (Eq. 22-24), and says so, as everywhere in the reports
    assert any("alpha_half = " in t for t in legend), legend
    assert "alpha_{half}" in ax.get_ylabel()
    assert any(t.startswith("k provided by the 3 collar(s)") for t in legend), legend
    text = " ".join(_texts(fig))
    assert "kN/m" in text and not re.search(r"(?<![kM])N/m", text), text
    assert "design point" in " ".join(entry["legend"])


def _scatter_points(ax) -> dict:
    """(x, y) -> face colour (hex) of every scatter marker of the axes."""
    from matplotlib.collections import PathCollection
    from matplotlib.colors import to_hex

    points = {}
    for c in ax.collections:
        if type(c) is PathCollection:
            colours = c.get_facecolors()
            for k, (x, y) in enumerate(c.get_offsets()):
                points[(round(float(x), 9), round(float(y), 9))] = to_hex(colours[k % len(colours)])
    return points


def test_coarse_maps_mark_every_computed_pulse(drawn):
    """On a 3 x 3 grid each computed pulse is a marker coloured by its outcome, on every map of
    the spectrum cross-check and on the rigid spectrum map (rigid/plotting.plot_spectrum)."""
    import matplotlib.pyplot as plt

    from colonna.rigid.plotting import MODE_COLOURS, plot_spectrum
    from colonna.rigid.spectrum import Spectrum

    code = {"safe": 0, "after-impact": 1, "without-impact": 2}
    w, a = [1.0, 3.0, 5.0], [2.0, 3.0, 4.0]
    fig, _ = drawn["maps"]
    sdof = [["safe"] * 3, ["safe"] * 3, ["without-impact", "without-impact", "after-impact"]]
    modes = {
        0: [["after-impact", "safe", "safe"], ["without-impact", "after-impact", "safe"], sdof[2]]
    }
    modes[1], modes[2] = modes[0], sdof
    for k, ax in enumerate(fig.axes):
        points = _scatter_points(ax)
        for i, y in enumerate(a):
            for j, x in enumerate(w):
                assert points.get((x, y)) == MODE_COLOURS[code[modes[k][i][j]]], (k, x, y)
    fig, _ = drawn["disagreement"]
    assert all(len(_scatter_points(ax)) == 9 for ax in fig.axes)
    codes = np.array([[code[m] for m in row] for row in modes[0]], dtype=np.int8)
    spectrum = Spectrum(
        np.array(w), np.array(a), codes, np.zeros((3, 3)), None, "nonlinear", "sine", 0.0, False
    )
    fig, ax = plt.subplots()
    plot_spectrum(spectrum, None, ax=ax)
    assert len(_scatter_points(ax)) == 9
    plt.close(fig)


def _identical_lines(fig):
    """Groups (two or more) of the figure's data lines that lie on top of each other."""
    groups = []
    for ax in fig.axes:
        lines = [line for line in ax.get_lines() if len(line.get_xdata()) > 2]
        for k, line in enumerate(lines):
            same = [
                other
                for other in lines[k:]
                if np.array_equal(other.get_xydata(), line.get_xydata(), equal_nan=True)
            ]
            if len(same) > 1 and not any(line in g for g in groups):
                groups.append(same)
    return groups


def test_curves_that_coincide_stay_visible(drawn):
    """Three collars with one history, two variants with one rotation, FEM and multibody with one
    rotation: each curve of a group that lies on top of another has its own markers, and those
    drawn first are wider (an outline round the later ones), so none hides another."""
    checked = set()
    for name in CHECKED:
        for group in _identical_lines(drawn[name][0]):
            markers = [line.get_marker() for line in group]
            widths = [line.get_linewidth() for line in group]
            assert "None" not in markers and len(set(markers)) == len(group), (name, markers)
            assert all(w1 > w2 for w1, w2 in zip(widths, widths[1:])), (name, widths)
            checked.add(name)
    assert {
        "collars",
        "toe_stress",
        "collar_utilisation",
        "theta_variants",
        "rotations",
        "ratios",
        "boundaries",
    } <= checked


def test_legends_cover_no_data(drawn):
    """Every legend of every figure lies inside the figure and outside every axes (the curves,
    the f_y and f_c lines and the maps stay in view)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    for name in CHECKED:
        fig = drawn[name][0]
        canvas = FigureCanvasAgg(fig)  # the figure was closed after saving
        canvas.draw()
        renderer = canvas.get_renderer()
        legends = list(fig.legends) + [ax.get_legend() for ax in fig.axes if ax.get_legend()]
        assert legends, name
        page = fig.bbox.padded(1.0)
        for legend in legends:
            box = legend.get_window_extent(renderer)
            assert (
                page.containsx(box.x0)
                and page.containsx(box.x1)
                and page.containsy(box.y0)
                and page.containsy(box.y1)
            ), name
            for ax in fig.axes:
                inner = ax.get_window_extent(renderer).padded(-1.0)
                assert not box.overlaps(inner), (name, ax.get_title())


def test_the_crosscheck_spectrum_holds_the_multibody_model_through_the_study_pulse(tmp_path):
    """spectrum.json of the cross-check keeps the SDOF keys and adds the rigid multibody
    spectrum on a coarse grid with the study's pulse on it; the figure marks each of its pulses
    and says the verdict relies on the multibody model."""
    import json
    import tomllib

    from tiny_study import TINY_STUDY

    from colonna.studies.crosscheck.report import _spectrum_figure
    from colonna.studies.crosscheck.runner import spectrum_case
    from colonna.studies.fem_study import case_of, from_dict

    study = from_dict(tomllib.loads(TINY_STUDY.format(amplitude_ratio=2.5, duration=0.6)))
    case = case_of(study, key="spectrum", kind="spectrum", multibody_grid=(3, 2))
    result = spectrum_case(case, str(tmp_path))
    data = json.loads((tmp_path / "spectrum.json").read_text())
    assert {
        "omega_ratios",
        "amplitude_ratios",
        "mode",
        "layout",
        "collar_yields",
        "study_omega_ratio",
        "study_amplitude_ratio",
    } <= set(data)
    mb = data["multibody"]
    assert mb["model"] == "multibody" and mb["cracked"] and mb["friction"] == 0.7
    assert len(mb["omega_ratios"]) == 3 and len(mb["amplitude_ratios"]) == 2
    assert result["omega_ratio"] in mb["omega_ratios"]
    assert result["amplitude_ratio"] in mb["amplitude_ratios"]
    assert np.array(mb["mode"]).shape == (2, 3) and result["multibody_seconds"] > 0
    (tmp_path / "figures").mkdir()
    figs = []
    _spectrum_figure(tmp_path, data, figs)
    assert "verdict relies on the rigid multibody model" in figs[0]["caption"]
    assert any(e.startswith("rigid multibody: ") for e in figs[0]["legend"])
    assert "this study's pulse" in figs[0]["legend"]
    marked = np.loadtxt(
        tmp_path / "figures" / "spectrum_multibody.csv", delimiter=",", skiprows=1, ndmin=2
    )
    assert marked.shape[0] == 6


def test_the_reports_figures_pass_the_browser_check(drawn, tmp_path):
    """In headless Chromium every figure of the made-up reports is drawn, its legend entries
    inside the figure and of colours drawn (tests/data/report_check.js)."""
    browser()
    figs = [entry for _, entry in drawn.values()]
    page = TEMPLATES.from_string(
        '{% from "macros.html.j2" import figures with context %}'
        "<!DOCTYPE html><html><body>{{ figures(figs) }}</body></html>"
    ).render(figs=figs)
    (tmp_path / "index.html").write_text(page)
    found = {r["name"]: r["problems"] for r in check_report(tmp_path / "index.html", tmp_path)}
    assert set(found) == set(drawn) and not any(found.values()), found


# --- plastic collars in the cross-check report ------------------------------------------------


def _plastic_crosscheck(root, eps_u=None, section="resultant"):
    """The tiny cross-check with its collar plastic, its f_y lowered to 60 MPa so that the
    thin band yields in bending under the study's pulse (ductility demand about 11), and
    ``eps_u`` where given (0.0025 breaks it); 2 FEM replicas, no toe refinement. The pulse
    is given as a record of the same sine, so that the cross-check runs no spectrum (the
    slow part of it); the report is written without the 3-D renders."""
    import tomllib

    from tiny_study import TINY_STUDY

    from colonna.studies.crosscheck import report
    from colonna.studies.crosscheck import run as run_crosscheck
    from colonna.studies.executor import RunOptions
    from colonna.studies.fem_study import from_dict
    from colonna.studies.study import load

    text = TINY_STUDY.format(amplitude_ratio=2.5, duration=0.6)
    ground = from_dict(tomllib.loads(text)).ground
    t = np.linspace(0.0, ground.end_time, 201)
    root.mkdir(parents=True, exist_ok=True)
    np.savetxt(root / "pulse.csv", np.c_[t, ground.acceleration(t)], delimiter=",")
    # by default the lumped-hinge law, whose hinge profile the figure draws
    collar = f'h = 0.02\nplastic = true\nsection = "{section}"\nfy = 60e6\n' + (
        f"eps_u = {eps_u}\n" if eps_u else ""
    )
    text = (
        text.replace("h = 0.02\n", collar)
        .replace(
            "amplitude_ratio = 2.5\nomega_ratio = 3.0\n", 'pulse = "record"\nrecord = "pulse.csv"\n'
        )
        .replace("grading = 0.0\n", "grading = 0.0\ntoe_refinements = []\n")
        .replace("[run]\n", "[run]\nreplicas = 2\n")
        # a weak steel on purpose (60 MPa), so that the tiny collar yields and breaks
        .replace('name = "tiny"\n', 'name = "tiny"\nintended = ["collar.fy"]\n')
    )
    (root / "tiny-plastic.toml").write_text(text)
    out = root / "out"
    study = load(root / "tiny-plastic.toml")
    summary = run_crosscheck(study, out, RunOptions(workers=1, progress=False))
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(report, "_renders", lambda out: ([], "not rendered in this test"))
        report.write_report(out)
    return out, summary


@pytest.mark.slow
def test_the_crosscheck_report_of_a_fibre_collar(tmp_path):
    """The tiny cross-check's plastic collar with the fibre section (its default law): the
    summary names the law, the collar yields (its stress is its largest fibre's, at least
    f_y), the end moment passes M_y and nears M_p, the hinge figure draws the moment loops
    and the fibre strain but no lumped-hinge profile, and the report says what the summary
    says (issue 36)."""
    from browser import assert_report_says_what_summary_says

    from colonna.studies.output import read_csv

    out, summary = _plastic_crosscheck(tmp_path, section="fibre")
    page = (out / "index.html").read_text()
    fem, collar = summary["fem"], summary["collars"][0]
    assert collar["section"] == "fibre" and collar["n_fibres"] == 20
    assert fem["collar_max_utilisation"] >= 1.0
    history = read_csv(out / "cases" / "fem" / "history.csv")
    moments = np.abs(np.r_[history["collar_1_moment_left"], history["collar_1_moment_right"]])
    assert collar["yield_moment"] < moments.max()
    assert moments.max() > 0.9 * collar["plastic_moment"]
    assert 'data-figure="collar_hinge"' in page
    assert not (out / "figures" / "collar_hinge_profile.csv").exists()
    assert f"fibre section of 20 layers at {collar['n_sections']} sections" in page
    assert summary["rigid_multibody"]["collar_ductility_demand"] > 1.0
    assert assert_report_says_what_summary_says(page, summary) >= 40


@pytest.mark.chaotic
@pytest.mark.parametrize("eps_u", [None, 0.0025], ids=["holds", "breaks"])
def test_the_crosscheck_report_draws_the_hinges_of_plastic_collars(tmp_path, eps_u):
    """A tiny cross-check whose plastic collar yields: its report has the hinge figure with
    its data, whose end moments reach the plastic moment M_p and never pass it by more than
    the hardening the collar's plastic work allows (g = 1 + H alpha / f_y, alpha <= W /
    (N_p L)), whose plastic strain profile is the lumped-hinge one of the run's last hinge
    rotations; the fibre strain, ductility demand and fracture rows; the multibody and SDOF
    numbers in summary.json; and "Do the collars hold?" answered from the replicas (no with
    eps_u = 0.0025, where the band breaks and carries nothing after)."""
    from browser import assert_report_says_what_summary_says, assert_table_numbers_have_units

    from colonna.studies.crosscheck import report
    from colonna.studies.crosscheck.summary import load
    from colonna.studies.output import read_csv

    out, summary = _plastic_crosscheck(tmp_path, eps_u)
    page = (out / "index.html").read_text()
    fem, collar = summary["fem"], summary["collars"][0]
    assert collar["plastic"] and collar["span"] == pytest.approx(0.2)
    assert collar["hinge_length"] == pytest.approx(0.02)  # L_p = h by default
    assert collar["plastic_moment"] == pytest.approx(60e6 * 0.004 * 0.02**2 / 4)
    assert fem["collar_max_utilisation"] >= 1.0  # it yields
    # summary.json: the multibody's collar keys and the SDOF's elastic law with its note
    mb = summary["rigid_multibody"]
    assert {
        "collar_max_fibre_strain",
        "collar_ductility_demand",
        "collar_fractured",
        "collar_fracture_time",
        "collar_max_plastic_strain",
        "collar_plastic_work",
    } <= set(mb)
    assert mb["collar_ductility_demand"] > 1.0
    rigid = summary["rigid"]
    assert rigid["collar_law"] == "elastic" and rigid["collar_max_utilisation"] > 1.0
    assert rigid["collar_note"].startswith("elastic collars assumed")
    # "Do the collars hold?": no fracture in any replica -> yes, in every replica -> no
    answers = {a["key"]: a for a in summary["outcome"]["answers"]}
    hold = answers["collars_hold"]
    word = {"no": "yes", "yes": "no", "undecided": "undecided"}[fem["collar_fractured_answer"]]
    assert hold["answer"] == word == ("yes" if eps_u is None else "no")
    assert hold["count"] == fem["collar_fractured_replicas"] and hold["points"] == 2
    # the figure and its data
    assert 'data-figure="collar_hinge"' in page and 'href="#figure-collar_hinge"' in page
    loops = read_csv(out / "figures" / "collar_hinge.csv")
    profile = read_csv(out / "figures" / "collar_hinge_profile.csv")
    history = read_csv(out / "cases" / "fem" / "history.csv")
    np.testing.assert_array_equal(loops["collar_1_moment_left"], history["collar_1_moment_left"])
    moments = np.abs(np.r_[loops["collar_1_moment_left"], loops["collar_1_moment_right"]])
    m_p, n_p = collar["plastic_moment"], collar["fy"] * collar["t"] * collar["h"]
    work = fem["bands"]["collar_plastic_work"]["values"][0]  # replica 0's, drawn
    hardened = m_p * (
        1.0 + collar["plastic_modulus"] * work / (collar["fy"] * n_p * collar["span"])
    )
    assert 0.95 * m_p < moments.max() <= hardened * (1.0 + 1e-9)
    # the profile: axial plastic strain plus each hinge's rotation spread over L_p
    last = {side: history[f"collar_1_hinge_rotation_{side}"][-1] for side in ("left", "right")}
    axial = abs(history["collar_1_plastic_strain"][-1])
    spread = collar["h"] / (2.0 * collar["hinge_length"])
    assert profile["x"][0] == 0.0 and profile["x"][-1] == pytest.approx(collar["span"])
    ends = profile["plastic_fibre_strain"][[0, -1]]
    np.testing.assert_allclose(ends, [axial + abs(last[s]) * spread for s in ("left", "right")])
    middle = profile["plastic_fibre_strain"][np.abs(profile["x"] - 0.1) < 0.05]
    np.testing.assert_allclose(middle, axial)
    assert ends.max() > 0.0  # the hinges turned
    # the Numbers rows and the verdict's words
    for key in (
        "fem.collar_max_fibre_strain",
        "fem.collar_ductility_demand",
        "fem.collar_fracture_time",
        "fem.collar_fractured_replicas",
        "rigid_multibody.collar_ductility_demand",
        "rigid_multibody.collar_fracture_time",
        "rigid.collar_note",
        "fem.bands.collar_ductility_demand.median",
    ):
        assert f'data-key="{key}"' in page, key
    assert "limit 15: EN 1993-1-1 eps_u &gt;= 15 eps_y" in page
    assert assert_report_says_what_summary_says(page, summary) >= 40
    assert assert_table_numbers_have_units(page) >= 20
    if eps_u is None:
        assert fem["collar_fracture_time"] is None and "does not fracture" in page
    else:
        broke = history["t"] >= fem["bands"]["collar_fracture_time"]["values"][0]
        assert broke.any() and np.all(loops["collar_1_moment_left"][broke] == 0.0)
        assert "a collar fractured</b> in" in page and " and fractures at t = " in page
    # drawn in a browser, legend and all (where there is one: tests/data/report_check.js)
    from colonna.studies.pdf import find_browser

    if eps_u is not None and find_browser() is not None:
        found = {r["name"]: r["problems"] for r in check_report(out / "index.html", tmp_path)}
        assert found["collar_hinge"] == [], found
    # an elastic collar has no hinges to draw
    figs: list = []
    elastic = dict(summary, collars=[dict(collar, plastic=False)])
    report._collar_hinge_figure(out, load(elastic), history, figs)
    assert figs == []

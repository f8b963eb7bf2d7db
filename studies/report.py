"""The HTML report of a cross-check study. Presentation only: every number comes from
``summary.json`` and every curve from the CSV files of the run directory.

Each figure's data is written next to it as CSV. Numbers in the HTML carry a ``data-key``
attribute naming their place in summary.json (dotted path), so a test can check that the report
says what the data say.
"""

from __future__ import annotations

import base64
import html
import io
import json
import math
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402
from matplotlib.patches import Patch  # noqa: E402

from .output import read_csv, write_csv  # noqa: E402


def fmt(value, digits: int = 4) -> str:
    """The report's number format (the consistency test uses the same function)."""
    if value is None:
        return "n/a"
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, (int,)) and not isinstance(value, bool):
        return str(value)
    value = float(value)
    if not math.isfinite(value):
        return "n/a"
    return f"{value:.{digits}g}"


def _get(summary: dict, dotted: str):
    node = summary
    for part in dotted.split("."):
        node = node[int(part)] if isinstance(node, list) else node[part]
    return node


def _num(summary, dotted, digits=4):
    return f'<span data-key="{dotted}">{html.escape(fmt(_get(summary, dotted), digits))}</span>'


def _png(fig) -> str:
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=110)
    plt.close(fig)
    return base64.b64encode(buf.getvalue()).decode()


def _figure(out: Path, name: str, fig, caption: str) -> str:
    data = _png(fig)
    (out / "figures").mkdir(exist_ok=True)
    (out / "figures" / f"{name}.png").write_bytes(base64.b64decode(data))
    return (f'<figure><img alt="{html.escape(caption)}" src="data:image/png;base64,{data}">'
            f'<figcaption>{html.escape(caption)} (data: figures/{name}.csv)</figcaption></figure>')


def write_crosscheck_report(out: Path) -> Path:
    out = Path(out)
    summary = json.loads((out / "summary.json").read_text())
    fem_h = read_csv(out / "cases" / "fem" / "history.csv")
    rigid_h = read_csv(out / "cases" / "rigid" / "history.csv")
    mono_h = read_csv(out / "cases" / "monolith" / "history.csv")
    mb_h = read_csv(out / "cases" / "multibody" / "history.csv")
    mb_names = ("left", "right") if "theta_left" in mb_h else ("column", "column")
    spectrum_file = out / "cases" / "spectrum" / "spectrum.json"      # pulses only
    spectrum = json.loads(spectrum_file.read_text()) if spectrum_file.exists() else None
    (out / "figures").mkdir(exist_ok=True)
    figs = []

    # 1. rotations, FEM vs the rigid models (the CSV on the FEM's times, where all ran)
    t = fem_h["t"]

    def on_fem_times(h, key):
        return np.interp(t, h["t"], h[key], right=np.nan)

    write_csv(out / "figures" / "theta.csv", {
        "t": t, "theta_fem_left": fem_h["theta_left"], "theta_fem_right": fem_h["theta_right"],
        "theta_multibody_left": on_fem_times(mb_h, f"theta_{mb_names[0]}"),
        "theta_multibody_right": on_fem_times(mb_h, f"theta_{mb_names[1]}"),
        "theta_rigid_half_with_collars": on_fem_times(rigid_h, "theta"),
        "theta_rigid_monolith": on_fem_times(mono_h, "theta")})
    fig, ax = plt.subplots(figsize=(8, 3.6))
    ax.plot(t, fem_h["theta_left"], color="C0", lw=1.6, label="FEM, left half")
    ax.plot(t, fem_h["theta_right"], "--", color="C0", lw=1.6, label="FEM, right half")
    m = mb_h["t"] <= t[-1]
    ax.plot(mb_h["t"][m], mb_h[f"theta_{mb_names[0]}"][m], color="C3", lw=1.0,
            label="rigid multibody, left half")
    ax.plot(mb_h["t"][m], mb_h[f"theta_{mb_names[1]}"][m], "--", color="C3", lw=1.0,
            label="rigid multibody, right half")
    m = rigid_h["t"] <= t[-1]
    ax.plot(rigid_h["t"][m], rigid_h["theta"][m], color="C1", lw=1.0,
            label="SDOF, half block + collars (paper)")
    m = mono_h["t"] <= t[-1]
    ax.plot(mono_h["t"][m], mono_h["theta"][m], ":", color="C2", lw=1.2,
            label="SDOF, whole column (monolith)")
    ax.set_xlabel("t (s)")
    ax.set_ylabel(r"$\theta$ (rad)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    figs.append(_figure(out, "theta", fig, "Rotation of each half: FEM against the rigid "
                        "multibody model (the rigid reference) and the two SDOF models"))

    # 1b. the deformed column at peak rotation: crack, collars, toe pressure
    _deformed_figure(out, summary, fem_h, figs)

    # 2. where the pulse sits on the rigid spectrum (a record has no place on it)
    if spectrum is not None:
        _spectrum_figure(out, spectrum, figs)

    # 3. collar stress against f_y
    collar_cols = sorted(k for k in fem_h if k.startswith("collar_") and k.endswith("_stress"))
    if collar_cols:
        write_csv(out / "figures" / "collars.csv",
                  {"t": t, **{k: fem_h[k] for k in collar_cols}})
        fig, ax = plt.subplots(figsize=(8, 3.4))
        for k in collar_cols:
            ax.plot(t, fem_h[k] / 1e6, label=f"FEM {k.replace('_stress', '')}")
        fy = fem_h[collar_cols[0]].max() / max(summary["fem"]["collar_max_utilisation"], 1e-30)
        ax.axhline(fy / 1e6, color="k", ls="--", lw=1, label=r"$f_y$")
        ax.set_xlabel("t (s)")
        ax.set_ylabel("extreme-fibre stress (MPa)")
        ax.legend(fontsize=8)
        fig.tight_layout()
        figs.append(_figure(out, "collars", fig, "Collar stress against the yield stress"))

    # 3b. plastic strain of plastic collars
    plastic_cols = sorted(k for k in fem_h if k.endswith("_plastic_strain"))
    if plastic_cols:
        write_csv(out / "figures" / "collar_plastic_strain.csv",
                  {"t": t, **{k: fem_h[k] for k in plastic_cols}})
        fig, ax = plt.subplots(figsize=(8, 3.0))
        for k in plastic_cols:
            ax.plot(t, 1e3 * fem_h[k], label=f"FEM {k.replace('_plastic_strain', '')}")
        ax.set_xlabel("t (s)")
        ax.set_ylabel("plastic strain (per mille)")
        ax.legend(fontsize=8)
        fig.tight_layout()
        figs.append(_figure(out, "collar_plastic_strain", fig, "Plastic strain of the plastic "
                            "collars (bilinear law, hardening E_h)"))

    # 4. toe stress against f_c
    edge_cols = [k for k in fem_h if k.startswith("edge_stress_")]
    write_csv(out / "figures" / "toe_stress.csv", {"t": t, **{k: fem_h[k] for k in edge_cols}})
    fig, ax = plt.subplots(figsize=(8, 3.4))
    for k in edge_cols:
        ax.plot(t, fem_h[k] / 1e6, label=k.replace("edge_stress_", "toe "))
    fc = summary["fem"]["edge_stress_max"] / max(summary["fem"]["edge_stress_ratio"], 1e-30)
    ax.axhline(fc / 1e6, color="k", ls="--", lw=1, label=r"$f_c$")
    ax.set_yscale("symlog", linthresh=1.0)
    ax.set_xlabel("t (s)")
    ax.set_ylabel(f"toe stress over {1e3 * summary['fem']['edge_length']:.0f} mm (MPa)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    figs.append(_figure(out, "toe_stress", fig, "Base-edge compressive stress at the toes "
                        "against the stone strength"))

    # 5. base contact pressure at peak rotation
    pressure = read_csv(out / "cases" / "fem" / "base_pressure.csv")
    peak = int(np.argmax(np.maximum(np.abs(fem_h["theta_left"]), np.abs(fem_h["theta_right"]))))
    names = [k for k in pressure if k != "t"]
    x = np.array([float(n.split("_x=")[1]) for n in names])
    row = min(peak, pressure["t"].size - 1)
    p_peak = np.array([pressure[n][row] for n in names])
    p_rest = np.array([pressure[n][0] for n in names])
    write_csv(out / "figures" / "base_pressure.csv",
              {"x": x, "pressure_at_rest": p_rest, "pressure_at_peak_rotation": p_peak})
    fig, ax = plt.subplots(figsize=(8, 3.2))
    ax.plot(x, p_rest / 1e6, "o-", ms=3, label="at rest (gravity)")
    ax.plot(x, p_peak / 1e6, "s-", ms=3, label=f"at peak rotation, t = {pressure['t'][row]:.3f} s")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("base contact pressure (MPa)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    figs.append(_figure(out, "base_pressure", fig, "Base contact pressure"))

    renders = _renders(out)
    return _write_page(out, _html(summary, figs, renders))


def _renders(out: Path) -> str:
    """pyvista renders of the deformed halves (x10) coloured by the minimum principal stress."""
    try:
        from .render import render_snapshots
        images = render_snapshots(out)
    except Exception as exc:     # rendering is a picture, never a reason to lose the report
        return f"<p>Renders unavailable: {html.escape(str(exc))}</p>"
    parts = []
    for name, caption in images:
        data = base64.b64encode((out / "figures" / name).read_bytes()).decode()
        mime = "image/gif" if name.endswith(".gif") else "image/png"
        parts.append(f'<figure><img alt="{html.escape(caption)}" src="data:{mime};base64,'
                     f'{data}"><figcaption>{html.escape(caption)}</figcaption></figure>')
    return "\n".join(parts)


def _rigid_fit(X, x):
    """Rotation R and translations of the best rigid motion taking points X to x (Kabsch)."""
    cX, cx = X.mean(axis=0), x.mean(axis=0)
    U, _, Vt = np.linalg.svd((x - cx).T @ (X - cX))
    R = U @ np.diag([1.0, np.sign(np.linalg.det(U @ Vt))]) @ Vt
    return R, cX, cx


def _magnification(largest: float, height: float) -> float:
    """A round factor (1, 2 or 5 x 10^k) that draws the largest elastic displacement at about
    2 % of the column height."""
    if largest <= 0.0:
        return 1.0
    raw = 0.02 * height / largest
    k = math.floor(math.log10(raw))
    return max(1.0, max(f * 10.0 ** k for f in (1.0, 2.0, 5.0) if f * 10.0 ** k <= raw))


def _deformed_figure(out: Path, summary: dict, fem_h: dict, figs: list) -> None:
    """The FEM column at its peak rotation, drawn in the ground frame: each half's rigid motion
    true to scale, its elastic deformation magnified by a stated factor; the collars between
    their attachment points; the base contact pressure under the toes at that instant."""
    import meshio
    fem = out / "cases" / "fem"
    vtu = fem / "fields_peak_rotation.vtu"
    if not vtu.exists():
        return
    m = meshio.read(vtu)
    X = m.points[:, :2]
    u = m.point_data["displacement"][:, :2]
    quads = np.vstack([c.data for c in m.cells if c.type == "quad"])
    cell_body = np.concatenate(m.cell_data["body"]).astype(int)
    node_body = np.full(X.shape[0], -1)
    node_body[quads.ravel()] = np.repeat(cell_body, 4)
    height = float(np.ptp(X[:, 1]))
    rigid, elastic = np.empty_like(X), np.empty_like(X)
    for b in np.unique(cell_body):
        on = node_body == b
        R, cX, cx = _rigid_fit(X[on], X[on] + u[on])
        rigid[on] = (X[on] - cX) @ R.T + cx
        elastic[on] = X[on] + u[on] - rigid[on]
    factor = _magnification(float(np.abs(elastic).max()), height)
    drawn = rigid + factor * elastic
    k = int(np.argmax(np.maximum(np.abs(fem_h["theta_left"]), np.abs(fem_h["theta_right"]))))
    t_peak = float(fem_h["t"][k])
    fig, ax = plt.subplots(figsize=(7.0, 6.4))
    handles = []
    for b in np.unique(cell_body):
        polys = drawn[quads[cell_body == b]]
        colour = ("C0", "C1")[min(int(b), 1)]
        for poly in polys:
            ax.fill(poly[:, 0], poly[:, 1], facecolor=colour, edgecolor="w", lw=0.2, alpha=0.6)
        handles.append(Patch(facecolor=colour, alpha=0.6, label=("left half", "right half")[
            min(int(b), 1)] if cell_body.max() > 0 else "column"))
    outline = np.array([[X[:, 0].min(), 0.0], [X[:, 0].max(), 0.0],
                        [X[:, 0].max(), height], [X[:, 0].min(), height], [X[:, 0].min(), 0.0]])
    handles += ax.plot(outline[:, 0], outline[:, 1], color="0.6", ls=":", lw=1.0,
                       label="at rest")
    heights = summary.get("collar_heights") or []
    left, right = node_body == 0, node_body == node_body.max()
    for y in heights:
        a = np.flatnonzero(left)[np.argmin(np.abs(X[left, 0] - X[:, 0].min())
                                           + np.abs(X[left, 1] - y))]
        c = np.flatnonzero(right)[np.argmin(np.abs(X[right, 0] - X[:, 0].max())
                                            + np.abs(X[right, 1] - y))]
        ax.plot(drawn[[a, c], 0], drawn[[a, c], 1], color="C3", lw=2.0)
    if heights:
        handles.append(Line2D([], [], color="C3", lw=2.0, label="collars"))
    pressure_file = fem / "base_pressure.csv"
    if pressure_file.exists():
        with open(pressure_file) as fh:
            names = fh.readline().strip().split(",")[1:]
            rows = np.loadtxt(fh, delimiter=",", ndmin=2)
        row = rows[int(np.argmin(np.abs(rows[:, 0] - t_peak)))]
        xs = np.array([float(n.split("=")[1]) for n in names])
        pressure = row[1:] / 1e6
        scale = 0.12 * height / max(pressure.max(), 1e-12)
        order = np.argsort(xs, kind="stable")
        ax.fill_between(xs[order], 0.0, -scale * pressure[order], color="k", alpha=0.35,
                        step=None)
        handles.append(Patch(facecolor="k", alpha=0.35,
                             label=f"base contact pressure (max {pressure.max():.2f} MPa)"))
    ax.axhline(0.0, color="k", lw=0.8)
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_title(f"FEM at peak rotation, t = {t_peak:.3f} s")
    ax.legend(handles=handles, fontsize=8, loc="upper left", bbox_to_anchor=(1.02, 1.0))
    fig.tight_layout()
    figs.append(_figure(out, "deformed", fig, "The FEM column at its peak rotation: each "
                        "half's rigid motion true to scale, its elastic deformation magnified "
                        f"x{factor:g}; the crack is the gap between the halves; collars in red; "
                        "under the base, the contact pressure at that instant (not to the "
                        "length scale)"))


def _spectrum_figure(out: Path, spectrum: dict, figs: list) -> None:
    """The study's pulse on the rigid overturning spectrum."""
    codes = np.array([[{"safe": 0, "after-impact": 1, "without-impact": 2}[c] for c in row]
                      for row in spectrum["mode"]])
    w = np.array(spectrum["omega_ratios"])
    a = np.array(spectrum["amplitude_ratios"])
    write_csv(out / "figures" / "spectrum.csv", {
        "omega_ratio": np.tile(w, a.size), "amplitude_ratio": np.repeat(a, w.size),
        "mode_code": codes.ravel()})
    from ..rigid.plotting import MODE_COLOURS, MODE_LABELS
    from matplotlib.colors import BoundaryNorm, ListedColormap
    fig, ax = plt.subplots(figsize=(7, 4))
    ax.pcolormesh(w, a, codes, cmap=ListedColormap(MODE_COLOURS),
                  norm=BoundaryNorm([-0.5, 0.5, 1.5, 2.5], 3), shading="nearest")
    # the legend lists what is drawn: the modes present, the yield line if any, the pulse
    handles = [Patch(facecolor=MODE_COLOURS[k], edgecolor="0.5", label=MODE_LABELS[k])
               for k in range(3) if np.any(codes == k)]
    yields = np.array(spectrum.get("collar_yields", [[0]]), dtype=float)
    if yields.min() < 0.5 < yields.max():
        ax.contour(w, a, yields, levels=[0.5], colors="k", linewidths=0.8)
        handles.append(Line2D([], [], color="k", lw=0.8, label="a collar reaches f_y above"))
    handles += ax.plot(spectrum["study_omega_ratio"], spectrum["study_amplitude_ratio"], "r*",
                       markersize=14, label="this study's pulse")
    ax.set_xlabel(r"$\Omega/p$")
    ax.set_ylabel(r"$a_p/(g\tan\alpha)$")
    ax.legend(handles=handles, fontsize=8, loc="upper left")
    ax.set_title("Rigid overturning spectrum (half block with collars)")
    fig.tight_layout()
    figs.append(_figure(out, "spectrum", fig, "The study's pulse on the rigid overturning "
                        "spectrum of the SDOF half block with collars: outcome of each pulse "
                        "(legend), and where a collar reaches its yield stress"))


def _verdict_row(summary, key, label, detail):
    ok = _get(summary, f"verdict.{key}")
    good = ok if key in ("rigid_assumption_ok", "sdof_half_model_ok") else not ok
    colour = "#1b9e77" if good else "#d95f02"
    return (f'<tr><th>{label}</th><td style="color:{colour};font-weight:bold">'
            f'{_num(summary, "verdict." + key)}</td><td>{detail}</td></tr>')


def _uncertain(s: dict, quantity: str) -> str:
    """' (mesh: +-x %)' from the convergence estimate, where there is one."""
    conv = s.get("convergence")
    if not conv or conv[quantity]["fine_relative_error"] is None:
        return " (mesh uncertainty: not estimated)" if conv else ""
    return (f" (mesh: &plusmn;{_num(s, f'convergence.{quantity}.fine_relative_error', 2)}, "
            f"order {_num(s, f'convergence.{quantity}.observed_order', 2)})")


def _toe_detail(s: dict) -> str:
    """The crushing verdict's evidence: the toe stress refined at the toes where it was."""
    if not s.get("toe_stress"):
        return (f"max toe stress / f_c = {_num(s, 'fem.edge_stress_ratio', 3)}"
                f"{_uncertain(s, 'edge_stress_ratio')} (averaged over "
                f"{_num(s, 'fem.edge_length', 3)} m and {_num(s, 'fem.edge_time', 2)} s)")
    return (f"max toe stress / f_c = {_num(s, 'toe_stress.ratio', 3)} from the meshes refined "
            "at the toes (mesh uncertainty &plusmn;"
            f"{_num(s, 'toe_stress.uncertainty', 2)}; the study mesh alone gives "
            f"{_num(s, 'toe_stress.unrefined_ratio', 3)}); contact pressure averaged over "
            f"{_num(s, 'toe_stress.edge_length', 3)} m from the toe and "
            f"{_num(s, 'toe_stress.edge_time', 2)} s; see \"Toe stress, refined\" below")


def _toe_section(s: dict) -> str:
    """How the toe stress was refined: one row per refinement of the impact window."""
    t = s.get("toe_stress")
    if not t:
        return ""
    rows = "\n".join(
        f"<tr><td>&times;{_num(s, f'toe_stress.refinements.{i}')}</td>"
        f"<td>{_num(s, f'toe_stress.dofs.{i}')}</td><td>{_num(s, f'toe_stress.steps.{i}')}</td>"
        f"<td>{_num(s, f'toe_stress.ratios.{i}', 4)}</td></tr>"
        for i in range(len(t["refinements"])))
    return f"""<h2>Toe stress, refined</h2>
<p>The peak toe stress comes at the {html.escape(str(t["toe"]).replace("_", " "))} toe at
t = {_num(s, 'toe_stress.t_peak', 4)} s (a landing, or the column pivoting on that toe). The
FEM reruns only the window
{_num(s, 'toe_stress.t_start', 4)}&ndash;{_num(s, 'toe_stress.t_end', 4)} s, started from the
study run's state (displacements, velocities and contact forces carried to the new mesh), with
the elements within {_num(s, 'toe_stress.edge_length', 3)} m of each base corner split in both
directions. Refinement &times;1 restarts the study mesh itself: it differs from the study run by
{_num(s, 'toe_stress.handover_error', 2)} (relative), which is the error of the hand-over.
The refined meshes give at most {_num(s, 'toe_stress.bound_ratio', 3)} f_c, spread
&plusmn;{_num(s, 'toe_stress.spread', 2)}; the observed order of the last three is
{_num(s, 'toe_stress.observed_order', 3)} (none when they do not converge monotonically: a
landing is a burst of contact chatter whose details move with the mesh). The quoted value is
the larger of that maximum and the Richardson estimate where there is one,
{_num(s, 'toe_stress.ratio', 3)} f_c, with the larger of the spread and the finest mesh's
estimated error as its uncertainty, &plusmn;{_num(s, 'toe_stress.uncertainty', 2)}.</p>
<p>For scale: at rest the base carries its mean pressure (W + P) / A =
{_num(s, 'toe_stress.static_mean_ratio', 3)} f_c (P: the top load on the capital,
{_num(s, 'fem.top_load')} N).</p>
<table><tr><th>toe refinement</th><th>dofs</th><th>time steps</th>
<th>toe stress / f_c (-)</th></tr>
{rows}</table>"""


def _html(s: dict, figs: list, renders: str) -> str:
    verdict = "\n".join([
        _verdict_row(s, "rigid_assumption_ok", "Rigid-body assumption good enough?",
                     "judged against the rigid multibody model (same contacts, friction and "
                     "collars, rigid halves); yes when all four hold. (1) same outcome: "
                     f"{_num(s, 'verdict_criteria.same_outcome')} (overturned: FEM "
                     f"{_num(s, 'fem.overturned')}, multibody "
                     f"{_num(s, 'rigid_multibody.overturned')}); (2) peak rotation FEM / "
                     f"multibody = {_num(s, 'verdict_criteria.peak_ratio')}, within 1 &plusmn; "
                     f"{_num(s, 'verdict_criteria.tolerances.peak', 2)} when neither "
                     f"overturns: {_num(s, 'verdict_criteria.peak_ok')}"
                     f"{_uncertain(s, 'peak_rotation')}; (3) impacts before the end of the "
                     f"pulse, FEM {_num(s, 'verdict_criteria.impacts_before_pulse_end_fem')}, "
                     "multibody "
                     f"{_num(s, 'verdict_criteria.impacts_before_pulse_end_multibody')}, "
                     f"differing by at most {_num(s, 'verdict_criteria.tolerances.impacts')}: "
                     f"{_num(s, 'verdict_criteria.impacts_ok')}; (4) history error max "
                     "|theta_FEM - theta_multibody| / max |theta_multibody| up to the first "
                     f"impact (t = {_num(s, 'verdict_criteria.history_window_end', 3)} s) = "
                     f"{_num(s, 'verdict_criteria.history_error_to_first_impact', 3)}, at most "
                     f"{_num(s, 'verdict_criteria.tolerances.history', 2)}: "
                     f"{_num(s, 'verdict_criteria.history_ok')}. Effective restitution under "
                     f"the pulse: FEM {_num(s, 'effective_restitution_fem', 3)}, multibody "
                     f"{_num(s, 'rigid_multibody.impact_velocity_ratio_mean', 3)}, Housner "
                     f"{_num(s, 'restitution_housner', 3)} (the free-rocking study measures "
                     "it cleanly)"),
        _verdict_row(s, "sdof_half_model_ok", "SDOF half-block model (the paper's) good enough?",
                     "its kinematic assumption (halves rotating equally, each on its own toe) "
                     f"against the multibody model: overturned: SDOF "
                     f"{_num(s, 'rigid.overturned')}, multibody "
                     f"{_num(s, 'rigid_multibody.overturned')}; peak rotation SDOF / multibody "
                     f"= {_num(s, 'theta_peak_ratio_rigid_over_multibody')}; whole-column SDOF "
                     f"/ multibody = {_num(s, 'theta_peak_ratio_monolith_over_multibody')}; "
                     f"FEM / SDOF half block = {_num(s, 'theta_peak_ratio_fem_over_rigid')}, "
                     f"FEM / whole-column SDOF = "
                     f"{_num(s, 'theta_peak_ratio_fem_over_monolith')}"),
        _verdict_row(s, "collars_yield", "Do the collars yield?",
                     f"max utilisation {_num(s, 'fem.collar_max_utilisation', 3)}"
                     f"{_uncertain(s, 'collar_max_utilisation')}; time of first yield (s): "
                     f"{_num(s, 'fem.collar_first_yield_time')}"),
        _verdict_row(s, "toe_crushes", "Does the toe crush?", _toe_detail(s)),
    ])
    rows = [("FEM peak rotation, left half (rad)", "fem.max_abs_theta_left"),
            ("FEM peak rotation, right half (rad)", "fem.max_abs_theta_right"),
            ("multibody peak rotation, left half (rad)", "rigid_multibody.max_abs_theta_left"),
            ("multibody peak rotation, right half (rad)",
             "rigid_multibody.max_abs_theta_right"),
            ("multibody mode", "rigid_multibody.mode"),
            ("multibody status", "rigid_multibody.status"),
            ("multibody crack slip max (m)", "rigid_multibody.max_abs_crack_slip"),
            ("multibody collar utilisation max", "rigid_multibody.collar_max_utilisation"),
            ("multibody energy balance error (max, relative)",
             "rigid_multibody.energy_error_max"),
            ("multibody wall time (s)", "rigid_multibody.wall_seconds"),
            ("SDOF peak rotation, half + collars (rad)", "rigid.max_abs_theta"),
            ("SDOF mode, half + collars", "rigid.mode"),
            ("SDOF peak rotation, whole column (rad)", "rigid_monolith.max_abs_theta"),
            ("halves rock as one block", "verdict.rocks_as_one_block"),
            ("FEM status", "fem.status"),
            ("toe stress max (Pa)", "fem.edge_stress_max"),
            ("energy balance error (max, relative)", "fem.energy_error_max"),
            ("time step (s)", "fem.dt"), ("stable-step reduction by contact",
                                           "fem.stable_step_reduction_by_contact"),
            ("steps", "fem.steps"), ("dofs", "fem.dofs"),
            ("FEM wall time (s)", "fem.wall_seconds"),
            ("pulse Omega/p (n/a for a record)", "pulse.omega_ratio"),
            ("peak ground acceleration (m/s^2)", "pulse.amplitude"),
            ("pulse a_p / a_uplift (a_uplift = g tan alpha (1 + lambda))",
             "pulse.amplitude_ratio"),
            ("top load on the capital (N)", "fem.top_load"),
            ("collar plastic strain max, FEM (-)", "fem.collar_max_plastic_strain"),
            ("collar plastic work, FEM (J)", "fem.collar_plastic_work"),
            ("crack slip left at the end of the run, FEM (m)", "fem.crack_slip_residual"),
            ("static base reaction, FEM (N): weight + top load", "fem.base_reaction_static")]
    table = "\n".join(f"<tr><th>{html.escape(label)}</th><td>{_num(s, key)}</td></tr>"
                      if not isinstance(_get(s, key), str) else
                      f'<tr><th>{html.escape(label)}</th><td><span data-key="{key}">'
                      f'{html.escape(_get(s, key))}</span></td></tr>' for label, key in rows)
    return _page(f"colonna cross-check: {s['study']}", f"""
<h2>Verdict</h2>
<table>{verdict}</table>
<h2>FEM against the rigid multibody model</h2>
<p>The multibody model has the FEM's contact topology with rigid halves: the same ground and
crack contacts and friction, the same collar frame elements. What separates the two is the
deformability of the stone, and the penalty contact's compliance and damping. Peak rotation
FEM / multibody: {_num(s, 'theta_peak_ratio_fem_over_multibody')}; overturned: FEM
{_num(s, 'fem.overturned')}, multibody {_num(s, 'rigid_multibody.overturned')}; run end
(overturning or the study's duration), FEM {_num(s, 'fem_vs_multibody.t_end_fem')} s,
multibody overturning time {_num(s, 'fem_vs_multibody.t_end_multibody')} s; collar utilisation
FEM / multibody: {_num(s, 'fem_vs_multibody.collar_utilisation_ratio', 3)}; largest crack slip
FEM {_num(s, 'fem_vs_multibody.crack_slip_fem', 3)} m, multibody
{_num(s, 'fem_vs_multibody.crack_slip_multibody', 3)} m.</p>
{_toe_section(s)}
<h2>Numbers</h2>
<table>{table}</table>
<h2>Figures</h2>
{''.join(figs)}
<h2>Deformed halves</h2>
{renders}
<p>Data: summary.json, cases/*/history.csv, cases/fem/base_pressure.csv, figures/*.csv;
fields for ParaView: cases/fem/*.vtu and fields.xdmf.</p>""")


def _page(title: str, body: str) -> str:
    return f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8">
<title>{html.escape(title)}</title>
<style>
body {{ font-family: sans-serif; max-width: 980px; margin: 2em auto; color: #222; }}
table {{ border-collapse: collapse; margin: 1em 0; }}
th, td {{ border: 1px solid #ccc; padding: 4px 8px; text-align: left; vertical-align: top; }}
figure {{ margin: 1.5em 0; page-break-inside: avoid; }}
img {{ max-width: 100%; }}
figcaption {{ font-size: 0.9em; color: #555; }}
@media print {{ body {{ max-width: none; }} }}
</style></head><body>
<h1>{html.escape(title)}</h1>
{body}
</body></html>
"""


def _write_page(out: Path, text: str) -> Path:
    path = Path(out) / "index.html"
    tmp = Path(out) / "index.html.part"
    tmp.write_text(text)
    tmp.replace(path)
    return path


def write_sweep_report(out: Path, kind: str) -> Path:
    out = Path(out)
    s = json.loads((out / "summary.json").read_text())
    (out / "figures").mkdir(exist_ok=True)
    if kind == "mesh-convergence":
        return _write_page(out, _page(f"colonna mesh convergence: {s['study']}",
                                      _convergence_body(out, s)))
    return _write_page(out, _page(f"colonna solid vs cracked: {s['study']}",
                                  _variants_body(out, s)))


def _convergence_body(out: Path, s: dict) -> str:
    sizes = s["sizes"]
    head = "".join(f"<th>h = {fmt(h, 3)} m ({n} dofs)</th>" for h, n in zip(sizes, s["dofs"]))
    rows = []
    labels = {"peak_rotation": "peak rotation (rad)",
              "collar_max_utilisation": "collar utilisation sigma/f_y",
              "edge_stress_max": "toe stress (Pa)"}
    columns = {"h": np.array(sizes)}
    fig, axes = plt.subplots(1, 3, figsize=(10, 3.2))
    for ax, (name, label) in zip(axes, labels.items()):
        c = s["convergence"][name]
        cells = "".join(f'<td>{_num(s, f"convergence.{name}.values.{k}")}</td>'
                        for k in range(len(sizes)))
        rows.append(f"<tr><th>{label}</th>{cells}"
                    f"<td>{_num(s, f'convergence.{name}.observed_order', 3)}</td>"
                    f"<td>{_num(s, f'convergence.{name}.richardson')}</td>"
                    f"<td>{_num(s, f'convergence.{name}.fine_relative_error', 2)}</td></tr>")
        columns[name] = np.array(c["values"], dtype=float)
        ax.plot(sizes, c["values"], "o-")
        if c["richardson"] is not None:
            ax.axhline(c["richardson"], color="k", ls="--", lw=0.8, label="Richardson")
        ax.set_xscale("log")
        ax.set_xlabel("mesh size h (m)")
        ax.set_title(label, fontsize=9)
    axes[0].legend(fontsize=8)
    fig.tight_layout()
    write_csv(out / "figures" / "convergence.csv", columns)
    figure = _figure(out, "convergence", fig, "FEM numbers against the mesh size")
    return (f"<table><tr><th></th>{head}<th>observed order</th><th>Richardson</th>"
            f"<th>fine-mesh relative error</th></tr>{''.join(rows)}</table>{figure}")


def _variants_body(out: Path, s: dict) -> str:
    names = list(s["variants"])
    fields = [("fem_peak_rotation", "FEM peak rotation (rad)"), ("fem_overturned",
              "FEM overturned"), ("rigid_peak_rotation", "rigid peak rotation (rad)"),
              ("rigid_mode", "rigid mode"), ("collar_max_utilisation", "collar utilisation"),
              ("edge_stress_ratio", "toe stress / f_c"), ("status", "FEM status")]
    head = "".join(f"<th>{html.escape(n)}</th>" for n in names)
    rows = []
    for key, label in fields:
        cells = []
        for n in names:
            value = s["variants"][n][key]
            dotted = f"variants.{n}.{key}"
            cells.append(f'<td><span data-key="{dotted}">{html.escape(value)}</span></td>'
                         if isinstance(value, str) else f"<td>{_num(s, dotted)}</td>")
        rows.append(f"<tr><th>{label}</th>{''.join(cells)}</tr>")
    fig, ax = plt.subplots(figsize=(8, 3.6))
    for k, n in enumerate(names):
        fem = read_csv(out / "cases" / f"{n}-fem" / "history.csv")
        rig = read_csv(out / "cases" / f"{n}-rigid" / "history.csv")
        write_csv(out / "figures" / f"theta_{n}.csv",
                  {"t": fem["t"], "theta_fem_left": fem["theta_left"],
                   "theta_fem_right": fem["theta_right"],
                   "theta_rigid": np.interp(fem["t"], rig["t"], rig["theta"])})
        ax.plot(fem["t"], fem["theta_left"], color=f"C{k}", label=f"{n}: FEM")
        m = rig["t"] <= fem["t"][-1]
        ax.plot(rig["t"][m], rig["theta"][m], "--", color=f"C{k}", label=f"{n}: rigid")
    ax.set_xlabel("t (s)")
    ax.set_ylabel(r"$\theta$ (rad)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    figure = _figure(out, "theta_variants", fig, "Rotation (left half): what the crack and the "
                     "collars change; FEM solid, rigid dashed")
    return f"<table><tr><th></th>{head}</tr>{''.join(rows)}</table>{figure}"


def write_design_report(out: Path) -> Path:
    out = Path(out)
    s = json.loads((out / "summary.json").read_text())
    chart = read_csv(out / "figures" / "design_chart.csv")
    alphas = np.unique(chart["alpha"])
    ratios = np.unique(chart["ag_over_g"])
    k = chart["required_stiffness"].reshape(alphas.size, ratios.size)
    from ..rigid.plotting import plot_design_chart
    plot_design_chart(alphas, ratios, k, out / "figures" / "design_chart.png")
    data = base64.b64encode((out / "figures" / "design_chart.png").read_bytes()).decode()
    chart_fig = (f'<figure><img alt="design chart" src="data:image/png;base64,{data}">'
                 "<figcaption>Minimum total lateral collar stiffness over alpha and a_g/g "
                 "(corrected Eq. 22-24; data: figures/design_chart.csv)</figcaption></figure>")
    history = read_csv(out / "cases" / "fem" / "history.csv")
    cols = sorted(c for c in history if c.startswith("collar_") and c.endswith("_utilisation"))
    write_csv(out / "figures" / "collar_utilisation.csv",
              {"t": history["t"], **{c: history[c] for c in cols}})
    fig, ax = plt.subplots(figsize=(8, 3.2))
    for c in cols:
        ax.plot(history["t"], history[c], label=c.replace("_utilisation", ""))
    ax.axhline(1.0, color="k", ls="--", lw=1, label="f_y")
    ax.set_xlabel("t (s)")
    ax.set_ylabel("sigma / f_y")
    ax.legend(fontsize=8)
    fig.tight_layout()
    util_fig = _figure(out, "collar_utilisation", fig, "FEM collar utilisation over time")
    rows = [("yield moment M_y (N m)", "design.yield_moment"),
            ("yield offset d_y (m), corrected Eq. 22", "design.yield_displacement"),
            ("yield rotation theta_y (rad), Eq. 23", "design.yield_rotation"),
            ("required lateral stiffness k (N/m), corrected Eq. 24",
             "design.required_stiffness"),
            ("one collar's lateral stiffness K_l (N/m)", "design.collar_lateral_stiffness"),
            ("collars needed", "design.collars_needed"),
            ("collars provided", "collars_provided"),
            ("lateral stiffness provided (N/m)", "lateral_stiffness_provided"),
            ("design adequate", "design_adequate"),
            ("FEM collar utilisation (max)", "fem_collar_max_utilisation"),
            ("FEM first yield (s)", "fem_collar_first_yield_time"),
            ("FEM overturned", "fem_overturned"),
            ("FEM peak rotation / theta_y", "fem_max_rotation_over_yield_rotation")]
    table = "".join(f"<tr><th>{html.escape(label)}</th><td>{_num(s, key)}</td></tr>"
                    for label, key in rows)
    body = (f"<p>Design pulse peak a_g = {_num(s, 'design.design_acceleration')} m/s^2 "
            f"(a_g/g = {_num(s, 'design_ag_over_g', 3)}), alpha = {_num(s, 'design_alpha', 3)} "
            f"rad; mass held {_num(s, 'design.column_mass')} kg.</p>"
            f"<table>{table}</table>{chart_fig}{util_fig}")
    return _write_page(out, _page(f"colonna collar design: {s['study']}", body))


def _record_axes(s: dict) -> str:
    """What the axes mean when the grid runs a record instead of a pulse."""
    if s.get("x_axis") != "time_scale":
        return ""
    return (f"<p>The grid runs the record <span data-key=\"record\">"
            f"{html.escape(str(s['record']))}</span>: each row scales it to a peak of the row's "
            "amplitude ratio times the uplift acceleration, each column plays it that many "
            "times as fast (the record time scale on the horizontal axis, in place of "
            "Omega / p).</p>")


def write_spectrum_crosscheck_report(out: Path) -> Path:
    """Mode maps of the FEM, multibody and SDOF models side by side, where they disagree, and
    their overturning boundaries overlaid; every map also as CSV."""
    from ..rigid.plotting import MODE_COLOURS, MODE_LABELS
    from matplotlib.colors import BoundaryNorm, ListedColormap
    from matplotlib.patches import Patch

    out = Path(out)
    s = json.loads((out / "summary.json").read_text())
    (out / "figures").mkdir(exist_ok=True)
    w, a = np.array(s["omega_ratios"]), np.array(s["amplitude_ratios"])
    # a record's grid moves its time scale where a pulse's moves Omega / p
    x_label = (r"record time scale (2: twice as fast)" if s.get("x_axis") == "time_scale"
               else r"$\Omega / p$")
    code = {"safe": 0, "after-impact": 1, "without-impact": 2}
    models = (("fem", "FEM"), ("multibody", "rigid multibody"), ("sdof", "SDOF half block"))
    maps = {m: np.array([[code[c] for c in row] for row in s[f"mode_{m}"]]) for m, _ in models}
    ww, aa = np.meshgrid(w, a)
    columns = {"omega_ratio": ww.ravel(), "amplitude_ratio": aa.ravel()}
    columns.update({f"mode_code_{m}": maps[m].ravel() for m, _ in models})
    columns["collar_utilisation_fem"] = np.array(s["collar_utilisation_fem"], float).ravel()
    columns["toe_ratio_fem"] = np.array(s["toe_ratio_fem"], float).ravel()
    write_csv(out / "figures" / "maps.csv", columns)
    figs = []

    cmap = ListedColormap(MODE_COLOURS)
    norm = BoundaryNorm([-0.5, 0.5, 1.5, 2.5], cmap.N)
    fig, axes = plt.subplots(1, 3, figsize=(12, 3.8), sharey=True)
    yields = np.array(s["collar_yield_fem"], dtype=bool)
    for ax, (m, label) in zip(axes, models):
        ax.pcolormesh(w, a, maps[m], cmap=cmap, norm=norm, shading="nearest")
        ax.set_title(label)
        ax.set_xlabel(x_label)
    if yields.any():
        axes[0].scatter(ww[yields], aa[yields], marker="x", color="k", s=25)
    axes[0].set_ylabel(r"$a_p / (g\,\tan\alpha)$")
    handles = [Patch(color=c, label=lab) for c, lab in zip(MODE_COLOURS, MODE_LABELS)]
    if yields.any():
        handles.append(plt.Line2D([], [], marker="x", color="k", ls="", label="FEM: a collar "
                                  "reaches f_y"))
    fig.legend(handles=handles, loc="lower center", ncol=len(handles), fontsize=8)
    fig.tight_layout(rect=(0, 0.08, 1, 1))
    figs.append(_figure(out, "maps", fig, "Outcome of every pulse of the grid: FEM, rigid "
                        "multibody and SDOF (the paper's half block with collars)"))

    fig, axes = plt.subplots(1, 2, figsize=(9, 3.6), sharey=True)
    for ax, m, label in ((axes[0], "multibody", "FEM vs rigid multibody"),
                         (axes[1], "sdof", "FEM vs SDOF half block")):
        differ = (maps["fem"] != maps[m]).astype(float)
        ax.pcolormesh(w, a, differ, cmap=ListedColormap(["#f2f2f2", "#7570b3"]), vmin=0, vmax=1,
                      shading="nearest")
        ax.set_title(label)
        ax.set_xlabel(x_label)
    axes[0].set_ylabel(r"$a_p / (g\,\tan\alpha)$")
    fig.legend(handles=[Patch(color="#f2f2f2", label="same outcome"),
                        Patch(color="#7570b3", label="different outcome")],
               loc="lower center", ncol=2, fontsize=8)
    fig.tight_layout(rect=(0, 0.08, 1, 1))
    figs.append(_figure(out, "disagreement", fig, "Where the FEM and each rigid model disagree"))

    fig, ax = plt.subplots(figsize=(7, 4))
    boundary = {}
    for (m, label), style in zip(models, ("-o", "--s", ":^")):
        over = maps[m] != 0
        lowest = np.where(over.any(axis=0), a[np.argmax(over, axis=0)], np.nan)
        boundary[f"lowest_overturning_amplitude_{m}"] = lowest
        ax.plot(w, lowest, style, label=label)
    write_csv(out / "figures" / "boundaries.csv", {"omega_ratio": w, **boundary})
    ax.set_xlabel(x_label)
    ax.set_ylabel(r"lowest overturning $a_p / (g\,\tan\alpha)$")
    ax.legend(fontsize=8)
    fig.tight_layout()
    figs.append(_figure(out, "boundaries", fig, "Overturning boundary of each model: the lowest "
                        "amplitude of the grid that overturns, per frequency (none drawn where "
                        "no amplitude of the grid does)"))

    body = f"""
<h2>Agreement</h2>
<table>
<tr><th>FEM and rigid multibody: same outcome</th>
<td>{_num(s, 'agreement_fem_multibody', 3)} of the grid points</td></tr>
<tr><th>FEM and SDOF half block: same outcome</th>
<td>{_num(s, 'agreement_fem_sdof', 3)} of the grid points</td></tr>
<tr><th>grid points</th><td>{_num(s, 'points')}</td></tr>
<tr><th>FEM energy balance error (max over the grid, relative)</th>
<td>{_num(s, 'energy_error_fem_max', 3)}</td></tr>
<tr><th>FEM wall time per grid point (s)</th><td>{_num(s, 'fem_seconds_per_point', 3)}</td></tr>
<tr><th>study wall time (s)</th><td>{_num(s, 'wall_seconds', 3)}</td></tr>
</table>
<p>Outcomes: safe, overturns after one or more impacts (Zhang &amp; Makris's mode 1),
overturns without impact (their mode 2). Amplitudes are normalised by g tan(alpha) and
frequencies by p of the rocking half. The FEM runs on the study's mesh; see the
mesh-convergence study for how far its numbers are converged.</p>
{_record_axes(s)}
<h2>Figures</h2>
{''.join(figs)}
<p>Data: summary.json (maps: rows follow the amplitude ratios), figures/*.csv,
cases/*/result.json (one per grid point).</p>"""
    return _write_page(out, _page(f"colonna spectrum cross-check: {s['study']}", body))


def write_free_rocking_report(out: Path) -> Path:
    """Free rocking: rotations of the FEM and the multibody model from each tilt, the velocity
    ratio at each impact beside Housner's, and what the FEM's value depends on."""
    out = Path(out)
    s = json.loads((out / "summary.json").read_text())
    (out / "figures").mkdir(exist_ok=True)
    alpha = s["alpha"]
    figs = []
    fig, ax = plt.subplots(figsize=(8, 3.6))
    columns = {}
    for k, tilt in enumerate(s["tilts"], start=1):
        for kind, style in (("fem", "-"), ("multibody", "--")):
            h = read_csv(out / "cases" / f"{kind}-tilt{k}" / "history.csv")
            label = "FEM" if kind == "fem" else "rigid multibody"
            ax.plot(h["t"], h["theta_left"] / alpha, style, color=f"C{k - 1}",
                    label=f"{label}, released at {tilt['tilt_fraction']:g} alpha")
            columns[f"t_{kind}_tilt{k}"] = h["t"]
            columns[f"theta_over_alpha_{kind}_tilt{k}"] = h["theta_left"] / alpha
    n = max(len(v) for v in columns.values())
    write_csv(out / "figures" / "rotations.csv",
              {k: np.pad(v, (0, n - len(v)), constant_values=np.nan) for k, v in columns.items()})
    ax.set_xlabel("t (s)")
    ax.set_ylabel(r"$\theta / \alpha$")
    ax.legend(fontsize=8)
    fig.tight_layout()
    figs.append(_figure(out, "rotations", fig, "Free rocking from each release tilt: FEM (solid) "
                        "and rigid multibody (dashed)"))

    fig, ax = plt.subplots(figsize=(7, 3.6))
    ratio_columns = {}
    for k, tilt in enumerate(s["tilts"], start=1):
        for kind, marker in (("fem", "o"), ("multibody", "s")):
            ratios = np.array(tilt[kind]["ratios"], dtype=float)
            label = "FEM" if kind == "fem" else "rigid multibody"
            ax.plot(np.arange(1, ratios.size + 1), ratios, marker=marker, ls="-" if kind ==
                    "fem" else "--", color=f"C{k - 1}",
                    label=f"{label}, released at {tilt['tilt_fraction']:g} alpha")
            ratio_columns[f"ratio_{kind}_tilt{k}"] = ratios
    ax.axhline(s["restitution_housner"], color="k", lw=0.8, ls=":",
               label=r"Housner $1 - 1.5\sin^2\alpha$")
    ax.set_xlabel("impact")
    ax.set_ylabel(r"$\dot\theta_{after} / \dot\theta_{before}$")
    ax.legend(fontsize=8)
    fig.tight_layout()
    n = max((len(v) for v in ratio_columns.values()), default=0)
    write_csv(out / "figures" / "ratios.csv",
              {"impact": np.arange(1, n + 1),
               **{k: np.pad(v, (0, n - len(v)), constant_values=np.nan)
                  for k, v in ratio_columns.items()}})
    figs.append(_figure(out, "ratios", fig, "Velocity ratio at each impact, from the rotation "
                        "peaks either side through the free-rocking energy"))

    variants = "\n".join(
        f"<tr><td>contact damping {_num(s, f'damping_variants.{k}.damping', 3)}</td>"
        f"<td>{_num(s, f'damping_variants.{k}.ratio_first', 4)}</td></tr>"
        for k in range(len(s["damping_variants"])))
    variants += "\n".join(
        f"<tr><td>mesh size {_num(s, f'mesh_variants.{k}.mesh_size', 3)} m</td>"
        f"<td>{_num(s, f'mesh_variants.{k}.ratio_first', 4)}</td></tr>"
        for k in range(len(s["mesh_variants"])))
    body = f"""
<h2>Energy lost at impact</h2>
<p>The FEM's velocity ratio at the first impact for the study's stone (E =
{_num(s, 'E', 3)} Pa, contact damping {_num(s, 'damping', 3)}, mesh
{_num(s, 'mesh_size', 3)} m) is <b>{_num(s, 'fem_ratio_study_stone', 4)}</b> (mean over its
impacts {_num(s, 'fem_ratio_study_stone_mean', 4)}); the rigid multibody model gives
{_num(s, 'multibody_ratio', 4)} and Housner's 1 - 1.5 sin^2(alpha)
{_num(s, 'restitution_housner', 4)}, alpha = {_num(s, 'alpha', 4)} rad (the body that rocks).
A ratio above Housner's means the FEM column keeps more of its rocking energy at an impact: the
penalty contact spreads the blow over the elastic base instead of a plastic blow at one corner.
</p>
<h2>What the FEM's value depends on (first release tilt)</h2>
<table><tr><th>variant</th><th>velocity ratio, first impact</th></tr>
{variants}</table>
<h2>Figures</h2>
{''.join(figs)}
<p>Data: summary.json, figures/*.csv, cases/*/history.csv.</p>"""
    return _write_page(out, _page(f"colonna free rocking: {s['study']}", body))

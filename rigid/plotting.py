"""Figures of rigid-block results (matplotlib, Agg). Presentation only: no computation here."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.colors import BoundaryNorm, ListedColormap  # noqa: E402
from matplotlib.patches import Patch  # noqa: E402

MODE_COLOURS = ("#f2f2f2", "#d95f02", "#1b9e77")    # safe, after-impact, without-impact
MODE_LABELS = ("safe", "overturns after impact(s)", "overturns without impact")


def plot_history(result, path, title: str | None = None):
    """theta/alpha and theta'/p against time, impacts marked; collar utilisation if any."""
    n_rows = 3 if result.collar_histories else 2
    fig, axes = plt.subplots(n_rows, 1, figsize=(8, 2.6 * n_rows), sharex=True)
    alpha, p = result.block.alpha, result.block.p
    theta = result.theta.reshape(result.time.size, -1)
    theta_dot = result.theta_dot.reshape(result.time.size, -1)
    labels = ("left half", "right half") if theta.shape[1] == 2 else (None,)
    for k, label in enumerate(labels):
        axes[0].plot(result.time, theta[:, k] / alpha, lw=1.2, label=label)
        axes[1].plot(result.time, theta_dot[:, k] / p, lw=1.2, label=label)
    axes[0].axhline(1.0, color="0.6", lw=0.8, ls="--")
    axes[0].axhline(-1.0, color="0.6", lw=0.8, ls="--")
    for t in result.impact_times:
        axes[0].axvline(t, color="0.85", lw=0.5, zorder=0)
    axes[0].set_ylabel(r"$\theta/\alpha$")
    axes[1].set_ylabel(r"$\dot\theta/p$")
    if labels[0] is not None:
        axes[0].legend(fontsize=8)
    if result.collar_histories:
        for k, hist in enumerate(result.collar_histories, start=1):
            axes[2].plot(result.time, hist.utilisation, lw=1.0,
                         label=f"collar {k} (y = {hist.collar.y:g} m)")
        axes[2].axhline(1.0, color="k", lw=0.8, ls="--", label=r"$f_y$")
        axes[2].set_ylabel(r"$\sigma / f_y$")
        axes[2].legend(fontsize=8)
    axes[-1].set_xlabel("t (s)")
    verdict = result.mode if result.overturned else "safe"
    axes[0].set_title(title or f"{result.model} model, {verdict}, {result.impacts} impacts")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def plot_spectrum(spectrum, path, title: str | None = None, ax=None):
    """Mode map over (Omega/p, a_p/a_uplift) in the style of Zhang & Makris (2001)."""
    own = ax is None
    if own:
        fig, ax = plt.subplots(figsize=(7, 4.5))
    cmap = ListedColormap(MODE_COLOURS)
    norm = BoundaryNorm([-0.5, 0.5, 1.5, 2.5], cmap.N)
    ax.pcolormesh(spectrum.omega_ratios, spectrum.amplitude_ratios, spectrum.codes, cmap=cmap,
                  norm=norm, shading="nearest")
    present = np.unique(spectrum.codes)                 # the legend lists what is drawn
    handles = [Patch(color=MODE_COLOURS[k], label=MODE_LABELS[k]) for k in range(3)
               if k in present]
    if spectrum.collar_yields is not None and spectrum.collar_yields.any():
        ax.contourf(spectrum.omega_ratios, spectrum.amplitude_ratios,
                    spectrum.collar_yields.astype(float), levels=[0.5, 1.5], colors="none",
                    hatches=["////"])
        ax.contour(spectrum.omega_ratios, spectrum.amplitude_ratios,
                   spectrum.collar_yields.astype(float), levels=[0.5], colors="k",
                   linewidths=0.8)
        handles.append(Patch(facecolor="none", edgecolor="k", hatch="////",
                             label="a collar reaches f_y"))
    ax.set_xlabel(r"$\Omega / p$")
    norm_name = r"g\,\alpha" if spectrum.model == "linear" else r"g\,\tan\alpha"
    ax.set_ylabel(rf"$a_p / ({norm_name})$")
    ax.legend(handles=handles, fontsize=8, loc="upper left")
    ax.set_title(title or f"Overturning spectrum, {spectrum.pulse} pulse, {spectrum.model} model"
                 + (", with collars" if spectrum.with_collars else ""))
    if own:
        fig.tight_layout()
        fig.savefig(path, dpi=120)
        plt.close(fig)


def plot_design_chart(alphas, ratios, stiffness, path, title: str | None = None):
    """Minimum total lateral collar stiffness over alpha and a_g/g (paper Fig. 8 analogue)."""
    fig, ax = plt.subplots(figsize=(7, 4.5))
    k = np.where(stiffness > 0.0, stiffness, np.nan) / 1e3
    mesh = ax.contourf(ratios, alphas, k, levels=20, cmap="viridis")
    ax.contour(ratios, alphas, stiffness, levels=[0.0], colors="w", linewidths=1.0)
    fig.colorbar(mesh, ax=ax, label="minimum lateral stiffness k (kN/m)")
    ax.set_xlabel(r"$a_g / g$")
    ax.set_ylabel(r"$\alpha$ (rad)")
    ax.set_title(title or "Collar design chart (corrected Eq. 22-24); white: k = 0")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)

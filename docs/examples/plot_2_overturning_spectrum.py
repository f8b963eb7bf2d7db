"""
Overturning spectrum with and without collars
=============================================

The mode map over pulse frequency Omega / p and amplitude a_p / a_uplift: which pulses leave
the block standing, which overturn it after an impact and which without one. First the solid
Zhang & Makris block (linearised, closed form between impacts), then one half of the default
cracked column held by its three steel collars (nonlinear model with the collar springs). Elastic
steel collars almost never let the column overturn in this model; the limit state they meet
first is yield, hatched where a collar reaches f_y.
"""

import matplotlib.pyplot as plt
import numpy as np

from colonna import Block, Collar, overturning_spectrum

omega = np.linspace(1.0, 12.0, 45)
amplitude = np.linspace(1.0, 12.0, 45)

block = Block.from_dimensionless(p=2.14, alpha=0.25, restitution=0.9)
solid = overturning_spectrum(block, omega, amplitude, model="linear")

half = Block.from_density(b=0.1125, h=2.0, density=2700.0, thickness=0.3534)
collars = [Collar(y=y, t=0.008, h=0.06) for y in (0.5, 2.0, 3.5)]
held = overturning_spectrum(half, omega, amplitude, collars=collars, model="nonlinear")

names = ["safe", "after-impact", "without-impact"]
fig, axes = plt.subplots(1, 2, figsize=(9, 3.8), layout="constrained", sharey=True)
for ax, spec, title in zip(
    axes, (solid, held), ("solid block", "half column with collars (hatched: a collar yields)")
):
    image = ax.pcolormesh(omega, amplitude, spec.codes, cmap="viridis", vmin=0, vmax=2)
    ax.set_title(title)
    ax.set_xlabel("Omega / p (-)")
    counts = {n: int(np.sum(spec.codes == k)) for k, n in enumerate(names)}
    print(title, counts)
if held.collar_yields is not None:
    axes[1].contourf(
        omega,
        amplitude,
        held.collar_yields.astype(float),
        levels=[0.5, 1.5],
        colors="none",
        hatches=["//"],
    )
    print(f"collars yield at {int(held.collar_yields.sum())} of {held.collar_yields.size} pulses")
axes[0].set_ylabel("a_p / a_uplift (-)")
bar = fig.colorbar(image, ax=axes, ticks=[0, 1, 2])
bar.ax.set_yticklabels(names)

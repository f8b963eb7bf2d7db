"""
Collar design chart (corrected Eq. 22-24)
=========================================

The minimum total lateral collar stiffness that holds a column at the collars' first yield
under a quasi-static pulse of peak a_g (the paper's section 5 and Fig. 8, with its Eq. 22 and
24 corrected: see the errata on the theory page), over the slenderness alpha and a_g / g, for
the default column's half width and an 8 x 60 mm S235 band.
"""

import matplotlib.pyplot as plt
import numpy as np

from colonna import Block, Collar
from colonna.rigid.design import design_chart, design_collars

b, density = 0.1125, 2700.0
collar = Collar(y=2.0, t=0.008, h=0.06)
alphas = np.linspace(0.03, 0.2, 40)
ratios = np.linspace(0.05, 0.4, 36)
k = design_chart(b, density, np.pi * b, collar, alphas, ratios)

half = Block.from_density(b=b, h=2.0, density=density, thickness=np.pi * b)
design = design_collars(half, collar, 0.3 * 9.81)
print(f"d_y = {design.yield_displacement * 1e3:.2f} mm, theta_y = {design.yield_rotation:.4f} rad")
k_design = design.required_stiffness / 1e3
print(f"a_g = 0.3 g: k = {k_design:.0f} kN/m, {design.collars_needed} collars")

fig, ax = plt.subplots(figsize=(6, 4), layout="constrained")
levels = ax.contourf(ratios, alphas, np.maximum(k, 0.0) / 1e3, levels=12)
ax.contour(ratios, alphas, k, levels=[0.0], colors="w", linewidths=1.2)
ax.set_xlabel("a_g / g (-)")
ax.set_ylabel("alpha of the rocking half block (rad)")
fig.colorbar(levels, ax=ax, label="required lateral stiffness k (kN/m)")

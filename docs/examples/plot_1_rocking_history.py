"""
Rocking of a rigid block under a sine pulse
===========================================

The validation block of Zhang & Makris (2001), p = 2.14 rad/s, alpha = 0.25 rad, restitution
0.9, under one sine pulse of Omega / p = 5 (Housner's equation, see the theory page). The
published overturning boundary at this frequency lies between a_p = 3.00 and 3.01 g alpha
(linearised model): the block survives just below it and overturns just above it.
"""

import matplotlib.pyplot as plt

from colonna import Block, Motion, pulse_from_ratios, rock

block = Block.from_dimensionless(p=2.14, alpha=0.25, restitution=0.9)

fig, ax = plt.subplots(figsize=(7, 3.5), layout="constrained")
for ratio in (2.99, 3.03):
    pulse = pulse_from_ratios(block, "sine", 5.0, ratio, "linear")
    result = rock(block, Motion(pulse, duration=8.0), model="linear")
    print(f"a_p = {ratio} g alpha: {result.mode}, {result.impacts} impacts")
    label = f"a_p / (g alpha) = {ratio}: {result.mode}"
    ax.plot(result.time, result.theta / block.alpha, label=label)
ax.axhline(1.0, color="0.6", lw=0.8, ls="--")
ax.axhline(-1.0, color="0.6", lw=0.8, ls="--")
ax.set_ylim(-1.6, 1.6)
ax.set_xlabel("time t (s)")
ax.set_ylabel("rotation theta / alpha (-)")
ax.legend(loc="lower left")

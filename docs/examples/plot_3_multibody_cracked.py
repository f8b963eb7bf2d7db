"""
Two rigid halves, crack friction and collars (multibody model)
==============================================================

The default column of ``colonna study default`` (4 m tall, 0.45 m wide, split by a full-height
crack, three 8 x 60 mm steel collars) as the rigid multibody model: two rigid halves with
unilateral contact and Coulomb friction at the base and along the crack, the collars as frame
elements. Under the default pulse (three times a half's uplift acceleration, Omega / p = 3)
the halves lock together through the crack friction and the collars and rock as one block.
"""

import matplotlib.pyplot as plt

from colonna import Block, Collar, Motion, MultibodyContact, pulse_from_ratios, rock_multibody

half = Block.from_density(b=0.1125, h=2.0, density=2700.0, thickness=0.3534)
collars = [Collar(y=y, t=0.008, h=0.06) for y in (0.5, 2.0, 3.5)]
pulse = pulse_from_ratios(half, "sine", 3.0, 3.0, "nonlinear")
run = rock_multibody(
    half, Motion(pulse), collars, contact=MultibodyContact(cracked=True, friction=0.7)
)
print(f"{run.mode}, overturning at t = {run.overturn_time} s; {run.impacts} impacts")

fig, (top, bottom) = plt.subplots(2, 1, figsize=(7, 5), layout="constrained", sharex=True)
top.plot(run.time, run.theta[:, 0], label="left half")
top.plot(run.time, run.theta[:, 1], ls="--", label="right half")
top.set_ylabel("rotation (rad)")
top.legend()
for k, history in enumerate(run.collar_histories):
    bottom.plot(run.time, history.utilisation, label=f"collar {k + 1}")
bottom.axhline(1.0, color="0.4", lw=0.8, ls=":")
bottom.set_xlabel("time t (s)")
bottom.set_ylabel("sigma / f_y (-)")
bottom.legend()

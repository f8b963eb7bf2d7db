"""
A finite-element run beside the rigid multibody model
=====================================================

The default column on a coarse mesh (two elements across each half, so that this page builds
in seconds; the studies use finer ones), through the 2D finite-element contact model: two
elastic halves, penalty contact with friction at the base and along the crack, the three
collars as frame elements, explicit time stepping from the static gravity state. Its rotation
is drawn over the first 0.8 s of the default pulse beside the rigid multibody model's, the
comparison behind "is the rigid-body assumption good enough?". A coarse mesh and a single run
(no replicas) show the method, not the study's answer.
"""

import matplotlib.pyplot as plt
import numpy as np

from colonna import Block, Collar, pulse_from_ratios, rock_multibody
from colonna.core.motion import Motion
from colonna.fem.assembly import Stone
from colonna.fem.model import ContactSettings, build_model
from colonna.fem.settings import FemSettings
from colonna.fem.solver import run
from colonna.meshes import column_mesh
from colonna.rigid.multibody import MultibodyContact

width, height = 0.45, 4.0
collars = [Collar(y=y, t=0.008, h=0.06) for y in (0.5, 2.0, 3.5)]
half = Block.from_density(b=width / 4, h=height / 2, density=2700.0, thickness=np.pi * width / 4)
pulse = pulse_from_ratios(half, "sine", 3.0, 3.0, "nonlinear")

mesh = column_mesh(width, height, width / 4, cracked=True, pinned_heights=[c.y for c in collars])
model = build_model(mesh, Stone(E=50e9, fc=110e6), np.pi * width / 4, collars, ContactSettings())
fem = run(model, Motion(pulse, 0.8), FemSettings(progress=False))
s = fem.summary
print(
    f"FEM: {s['dofs']} dofs, {s['steps']} steps of {s['dt'] * 1e6:.2f} us, "
    f"energy error {s['energy_error_max']:.1e}, collar utilisation "
    f"{s['collar_max_utilisation']:.2f}, toe stress {s['edge_stress_max'] / 1e6:.2f} MPa"
)

rigid = rock_multibody(
    half, Motion(pulse, duration=0.8), collars, contact=MultibodyContact(cracked=True, friction=0.7)
)

fig, ax = plt.subplots(figsize=(7, 3.5), layout="constrained")
ax.plot(fem.history["t"], fem.history["theta_left"], label="FEM, left half")
ax.plot(rigid.time, rigid.theta[:, 0], ls="--", label="rigid multibody, left half")
ax.set_xlabel("time t (s)")
ax.set_ylabel("rotation (rad)")
ax.legend()

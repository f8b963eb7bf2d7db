"""A small study shared by the study tests: a 0.2 x 1 m cracked column with one collar."""

TINY_STUDY = """
[study]
name = "tiny"
[column]
height = 1.0
width = 0.2
[[collar]]
y = 0.5
t = 0.004
h = 0.02
[ground]
amplitude_ratio = {amplitude_ratio}
omega_ratio = 3.0
[mesh]
size = 0.05
grading = 0.0
[run]
duration = {duration}
output_interval = 0.005
"""

# A small fragility study: the SDOF of an uncracked 0.6 x 4 m column over four one-cycle pulses
# (write_pulse_suite writes them and the suite.toml it reads beside the study file)
TINY_FRAGILITY = """
[study]
name = "tiny-fragility"
kind = "fragility"
[column]
height = 4.0
width = 0.6
cracked = false
[ground]
pulse = "none"
[fragility]
suite = "suite.toml"
intensity = "pga_rocking"
ladder = [1.1, 8.0]
steps = 24
models = ["sdof"]
design_intensity = 3.0
bootstrap = 40
"""

# the collar-layout kind on the same column, cracked, over the same suite: a small catalogue
# (none, one or two collars of two sections and two grades), a power-law hazard whose 475-year
# intensity lies inside the ladder; ``target`` (1/year) to fill in
TINY_LAYOUT = """
[study]
name = "tiny-layout"
kind = "collar-layout"
[column]
height = 4.0
width = 0.6
cracked = true
[mesh]
size = 0.1
[run]
output_interval = 0.01
replicas = 2  # of the chosen layout's cross-check (the FEM stripe runs one each)
[hazard]
k0 = 1.5e-2
k = 2.5
intensity = "pga"
[layout]
suite = "suite.toml"
ladder = [1.1, 8.0]
steps = 10
counts = [0, 1, 2]
sections = [[0.004, 0.03], [0.010, 0.08]]
grades = ["S235", "S355"]
target_frequency = {target}
design_return_period = 475
shortlist = 8
bootstrap = 40
"""

# (shape, Omega / p) of the four pulses: the cosine at 2.5 p overturns from a low level,
# survives a band of higher ones and overturns again
PULSES = (("cos", 2.5), ("cos", 2.0), ("sin", 3.5), ("sin", 6.0))


def write_pulse_suite(root) -> None:
    """TINY_FRAGILITY's records in ``root``: one cycle of each of :data:`PULSES` at the
    column's p (its rocking block, 0.3 x 2 m half-sizes), unit amplitude, as two-column files
    in m/s^2, and their suite.toml."""
    import numpy as np

    from colonna.rigid.block import Block

    p = Block(b=0.3, h=2.0).p
    entries = []
    for i, (shape, ratio) in enumerate(PULSES):
        omega = ratio * p
        t = np.linspace(0.0, 2.0 * np.pi / omega, 401)
        wave = np.cos(omega * t) if shape == "cos" else np.sin(omega * t)
        np.savetxt(root / f"p{i}.txt", np.column_stack([t, wave]))
        entries.append(f'[[record]]\nfile = "p{i}.txt"\nunits = "m/s2"\n')
    (root / "suite.toml").write_text("\n".join(entries))

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

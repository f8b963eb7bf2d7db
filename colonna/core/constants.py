"""Physical constants and material defaults of the project (SI units)."""

STANDARD_GRAVITY = 9.81  # m/s^2, the project's convention (docs/theory.md, section 2);
# a study may set g
STEEL_E = 206e9  # Pa, Young's modulus of structural steel (EN 1993-1-1, 3.2.6)
STEEL_FY = 235e6  # Pa, yield stress of S235 (EN 1993-1-1, Table 3.1, t <= 40 mm)

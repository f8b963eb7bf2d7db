"""Physical constants and material defaults of the project (SI units)."""

STANDARD_GRAVITY = 9.81  # m/s^2, the project's convention (docs/theory.md, section 2);
# a study may set g
STEEL_E = 206e9  # Pa, Young's modulus of structural steel (EN 1993-1-1, 3.2.6)
STEEL_FY = 235e6  # Pa, yield stress of S235 (EN 1993-1-1, Table 3.1, t <= 40 mm)
STEEL_EPS_U = 0.15  # ultimate (fracture) strain of a collar: the elongation at failure that
# EN 1993-1-1:2005, 3.2.2(1) requires of any steel used in plastic analysis (S235 to
# EN 10025-2 guarantees at least 26 % for 3-40 mm, so 0.15 is a lower bound that also covers
# the strain concentrated at a hinge beyond the lumped estimate)
DUCTILITY_LIMIT = 15.0  # largest fibre strain / yield strain a collar may reach in design:
# EN 1993-1-1:2005, 3.2.2(1) requires eps_u >= 15 eps_y (eps_u: the strain at f_u), so a
# demand within 15 keeps the fibres short of the ultimate stress's strain

"""colonna.fem: 2D finite-element contact model of the (cracked) column.

Not implemented yet (issue 3): plane-stress halves in scikit-fem, penalty frictional contact at the
base and along the crack, collars as frame elements, explicit central-difference time stepping.
"""

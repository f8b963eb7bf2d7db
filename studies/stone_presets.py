"""The stones a study file can name in ``[stone] preset`` (issue 51): each key's value (SI) and
where it comes from. A key given in [stone] overrides its preset's; without a preset the
defaults are the marble's (studies.schema.Stone). The ranges and their sources are in
docs/physics.md ("Tensile strength and fracture energy", "A granite"); these are working values
for a sensitivity study, not design values: a stone's own tests replace them where they exist.

>>> sorted(PRESETS)
['granite', 'marble']
>>> PRESETS["granite"]["ft"]
10000000.0
"""

from __future__ import annotations

# the white marble: the schema's defaults (studies.schema.Stone) are these values
MARBLE = {
    "E": 50e9,
    "nu": 0.2,
    "density": 2700.0,
    "fc": 110e6,
    "ft": 8e6,
    "Gf": 40.0,
    "KIC": 1.0e6,
}
MARBLE_SOURCES = {
    "E": "a white marble, within stone's 30-70 GPa (DESIGN.md; the paper cites E > 30 GPa)",
    "nu": "a white marble, within stone's 0.1-0.25 (DESIGN.md)",
    "density": "a white marble, within stone's 2600-2800 kg/m^3 (DESIGN.md)",
    "fc": "the source paper's tests, f_c > 110 MPa",
    "ft": "a white marble in direct tension, about half its 14.9 MPa in bending (Spagnoli et "
    "al., Frattura ed Integrita Strutturale 33 (2015) 80-88; docs/physics.md)",
    "Gf": "marble 5-45 N/m as K_IC^2 / E, a lower bound (docs/physics.md)",
    "KIC": "marble 0.5-1.5 MPa m^0.5 (docs/physics.md)",
}

# the granite of docs/stones/granite.toml (docs/physics.md, "A granite")
GRANITE = {
    "E": 55e9,
    "nu": 0.2,
    "density": 2650.0,
    "fc": 150e6,
    "ft": 10e6,
    "Gf": 60.0,
    "KIC": 1.3e6,
}
GRANITE_SOURCES = {
    "E": "granite 40-70 GPa (docs/theory.md, section 9; the tutorial's granite)",
    "nu": "the tutorial's granite",
    "density": "the tutorial's granite",
    "fc": "the tutorial's granite",
    "ft": "granite 5-15 MPa in direct tension, the middle, below f_c / 10 (docs/physics.md)",
    "Gf": "twice its K_IC^2 (1 - nu^2) / E = 29.5 N/m (the law's LEFM limit), inside the "
    "derived 7-90 N/m (docs/physics.md)",
    "KIC": "0.71-1.89 MPa m^0.5 for fine-grained granites, the middle (Nasseri & Mohanty, Int. "
    "J. Rock Mech. Min. Sci. 45 (2008) 167-193)",
}

PRESETS = {"marble": MARBLE, "granite": GRANITE}
SOURCES = {"marble": MARBLE_SOURCES, "granite": GRANITE_SOURCES}


def with_preset(table: dict) -> dict:
    """A [stone] table with the keys its ``preset`` names filled in where not given (a key
    given overrides the preset's); the table as it is without a known preset (the schema
    refuses an unknown one, naming those allowed)."""
    name = table.get("preset")
    values = PRESETS.get(name) if isinstance(name, str) else None
    if values is None:
        return table
    return {**values, **table}


def from_preset(table: dict) -> dict[str, str]:
    """The keys of a [stone] table (as the file gives it) that its preset sets, each with where
    its value comes from: what the report's inputs mark as resolved."""
    name = table.get("preset")
    if not isinstance(name, str) or name not in PRESETS:
        return {}
    return {
        key: f"the {name} preset: {SOURCES[name][key]}" for key in PRESETS[name] if key not in table
    }


__all__ = ["PRESETS", "SOURCES", "from_preset", "with_preset"]

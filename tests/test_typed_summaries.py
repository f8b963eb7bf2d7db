"""The reports read summary.json through typed sections (studies.sections): a table's row names
its quantity by attribute, a wrong name fails when the report module is imported, a key the file
lacks fails at load naming it, and each row's display unit is its field's SI unit scaled. The
rows against a real summary of each kind: tests/test_study.py (the cross-check's tiny run),
tests/test_inputs_on_record.py (collar design), tests/test_spectrum_crosscheck.py."""

import dataclasses
import re
from dataclasses import dataclass
from pathlib import Path

import pytest

from colonna.core.errors import StaleResultsError
from colonna.core.quantities import quantity
from colonna.studies.collar_design.report import DESIGN_NUMBERS
from colonna.studies.collar_design.summary import DesignSummary
from colonna.studies.crosscheck.report import CROSSCHECK_NUMBERS
from colonna.studies.crosscheck.summary import CrosscheckSummary
from colonna.studies.fragility.summary import FragilitySummary
from colonna.studies.free_rocking.summary import FreeRockingSummary
from colonna.studies.mesh_convergence.report import CONVERGENCE_QUANTITIES
from colonna.studies.mesh_convergence.summary import MeshConvergenceSummary
from colonna.studies.report import num
from colonna.studies.sections import (
    ABSENT,
    MANY,
    SECTION,
    Ref,
    absent,
    keyed,
    read,
    section,
    table,
    written,
)
from colonna.studies.solid_vs_cracked.report import VARIANT_FIELDS
from colonna.studies.solid_vs_cracked.summary import SolidVsCrackedSummary
from colonna.studies.spectrum_crosscheck.report import SPECTRUM_NUMBERS
from colonna.studies.spectrum_crosscheck.summary import SpectrumSummary
from colonna.studies.zhang_makris.summary import ZhangMakrisSummary

ROOT = Path(__file__).resolve().parents[1]

# a display unit of a report table and the SI unit of its field (studies.units.DISPLAY_UNITS)
SI_OF = {
    "MPa": "Pa",
    "GPa/m": "N/m^3",
    "kN": "N",
    "kN m": "N m",
    "kN/m": "N/m",
    "mm": "m",
    "per mille": "-",
    "kJ": "J",
}

TABLES = {
    "crosscheck": CROSSCHECK_NUMBERS,
    "collar-design": DESIGN_NUMBERS,
    "spectrum-crosscheck": SPECTRUM_NUMBERS,
}


@dataclass(frozen=True, kw_only=True)
class _Inner:
    stress: float = quantity("Pa", "a stress")
    note: str = absent("", "a note, only where there is one")


@dataclass(frozen=True, kw_only=True)
class _Outer:
    name: str = quantity("", "a name")
    inner: _Inner = section(_Inner, "the inner section")
    maybe: _Inner | None = section(_Inner, "a section a run may not give", optional=True)


@dataclass(frozen=True, kw_only=True)
class _Listing:
    items: list[_Inner] = section(_Inner, "one per case", many=True)


def test_a_list_of_sections_reads_each_and_names_the_one_that_lacks_a_key():
    s = read(_Listing, {"items": [{"stress": 1.0}, {"stress": 2.0, "note": "x"}]})
    assert [i.stress for i in s.items] == [1.0, 2.0] and s.items[0].note is ABSENT
    with pytest.raises(StaleResultsError, match="'items.1.stress'"):
        read(_Listing, {"items": [{"stress": 1.0}, {}]})
    with pytest.raises(AttributeError, match="not a section"):
        Ref(_Listing, lambda s: s.items.stress)  # type: ignore[attr-defined]


@pytest.mark.parametrize("kind", sorted(TABLES))
def test_each_row_shows_its_fields_si_unit_scaled(kind):
    """A row in MPa reads a field in Pa, mm a field in m, "-" a ratio or a count: a row whose
    unit does not match its quantity's would show a number off by its factor."""
    wrong = []
    for label, ref, unit in TABLES[kind]:
        si = SI_OF.get(unit, unit)
        if not (ref.unit == si or (unit == "-" and ref.unit in ("", "-"))):
            wrong.append(f"{ref.key}: shown in {unit!r}, declared in {ref.unit!r} ({label})")
    assert not wrong, wrong


def test_a_wrong_name_fails_when_the_table_is_made():
    with pytest.raises(AttributeError, match="declares no 'edge_stres_max'"):
        Ref(CrosscheckSummary, lambda s: s.fem.edge_stres_max)  # type: ignore[attr-defined]
    with pytest.raises(AttributeError, match="is a quantity, not a section"):
        Ref(CrosscheckSummary, lambda s: s.fem.status.words)
    assert Ref(CrosscheckSummary, lambda s: s.fem.edge_stress_max).key == "fem.edge_stress_max"
    assert Ref(CrosscheckSummary, lambda s: s.fem.edge_stress_max).unit == "Pa"


def test_a_missing_key_fails_at_load_named_and_a_left_out_one_is_absent():
    with pytest.raises(StaleResultsError, match="'inner.stress'"):
        read(_Outer, {"name": "a", "inner": {}, "maybe": None})
    with pytest.raises(StaleResultsError, match="'maybe'"):
        read(_Outer, {"name": "a", "inner": {"stress": 1.0}})
    s = read(_Outer, {"name": "a", "inner": {"stress": 2e6}, "maybe": None, "extra": 1})
    assert s.inner.stress == 2e6 and s.inner.note is ABSENT and s.maybe is None


def test_rows_left_out_where_the_summary_has_no_value_and_none_shown_na():
    """A key left out (a note where there is none) or under a section the run did not give
    drops its row; a null value (JSON None) keeps it, shown n/a."""
    rows = [
        ("stress", Ref(_Outer, lambda s: s.inner.stress), "MPa"),
        ("note", Ref(_Outer, lambda s: s.inner.note), ""),
        ("maybe", Ref(_Outer, lambda s: s.maybe and s.maybe.stress), "MPa"),
    ]
    s = read(_Outer, {"name": "a", "inner": {"stress": None}, "maybe": None})
    shown = table(rows, s)
    assert [label for label, _, _ in shown] == ["stress"]
    assert num({}, shown[0][1], 4, "MPa") == '<span data-key="inner.stress">n/a</span>'
    s = read(_Outer, {"name": "a", "inner": {"stress": 2.5e6, "note": "x"}, "maybe": None})
    shown = table(rows, s)
    assert [label for label, _, _ in shown] == ["stress", "note"]
    # the value read by attribute, scaled to the row's unit, the key named for the page's check
    assert num({}, shown[0][1], 4, "MPa") == (
        '<span data-key="inner.stress" data-scale="1e-06">2.5</span>&nbsp;MPa'
    )


def _declared(cls, key: str) -> bool:
    """Whether a dotted key of a page is declared by the summary class: each part a field, the
    rest of the key free once it reaches a dict or list quantity (its entries are the data's);
    a key ending in "." (the page adds an index or a name) names its container."""
    parts = key.rstrip(".").split(".")
    for n, part in enumerate(parts):
        fields = {f.name: f for f in dataclasses.fields(cls)}
        if part not in fields:
            return False
        nested = fields[part].metadata.get(SECTION)
        if nested is not None and fields[part].metadata.get(MANY):
            rest = parts[n + 1 :]  # a list of sections: an index, then the section's key
            if not rest:
                return True
            return rest[0].isdigit() and (len(rest) == 1 or _declared(nested, ".".join(rest[1:])))
        if nested is None:
            kind = str(fields[part].type)
            return n == len(parts) - 1 or "dict" in kind or "list" in kind
        cls = nested
    return True


PAGES = {
    "crosscheck": ("studies/crosscheck/report.html.j2", CrosscheckSummary),
    "collar-design": ("studies/collar_design/report.html.j2", DesignSummary),
    "spectrum-crosscheck": ("studies/spectrum_crosscheck/report.html.j2", SpectrumSummary),
    "free-rocking": ("studies/free_rocking/report.html.j2", FreeRockingSummary),
    "fragility": ("studies/fragility/report.html.j2", FragilitySummary),
    "mesh-convergence": ("studies/mesh_convergence/report.html.j2", MeshConvergenceSummary),
    "solid-vs-cracked": ("studies/solid_vs_cracked/report.html.j2", SolidVsCrackedSummary),
    "zhang-makris": ("studies/zhang_makris/report.html.j2", ZhangMakrisSummary),
}


@pytest.mark.parametrize("kind", sorted(PAGES))
def test_every_number_the_page_names_is_a_declared_quantity(kind):
    """The template's num("...") keys are strings: each must be a quantity its kind's typed
    summary declares, so that a key renamed in the summary fails here, not as "n/a"."""
    path, cls = PAGES[kind]
    keys = re.findall(r'num\("([^"]+)"', (ROOT / path).read_text())
    assert keys
    undeclared = sorted({k for k in keys if not _declared(cls, k)})
    assert not undeclared, undeclared
    assert not _declared(cls, "fem.edge_stres_max") and not _declared(cls, "study.name")


def test_the_writer_checks_its_keys_against_the_reader():
    """keyed: the dict a study writes has the reading class's keys, in its order, each
    required one there; a renamed, extra, missing or moved key fails when it is written."""
    assert keyed(_Inner, {"stress": 1.0}) == {"stress": 1.0}
    with pytest.raises(ValueError, match=r"not declared \['stres'\]"):
        keyed(_Inner, {"stres": 1.0})
    with pytest.raises(ValueError, match=r"not written \['stress'\]"):
        keyed(_Inner, {"note": "x"})
    with pytest.raises(ValueError, match="out of the declared order"):
        keyed(_Inner, {"note": "x", "stress": 1.0})
    s = read(_Inner, {"stress": None})
    assert written(s) == {"stress": None}  # ABSENT left out, None kept


def test_per_item_tables_name_their_quantities_and_join_into_the_page_keys():
    """The tables of a quantity per variant or per mesh name it by attribute too; the page joins
    its key (str of the Ref) into its own: "variants." ~ n ~ "." ~ key."""
    assert [str(ref) for ref, _, _ in VARIANT_FIELDS] == [
        "fem_peak_rotation",
        "fem_overturned",
        "rigid_peak_rotation",
        "rigid_mode",
        "collar_max_utilisation",
        "edge_stress_ratio",
        "status",
    ]
    assert [ref.key for ref, _, _ in CONVERGENCE_QUANTITIES] == [
        "peak_rotation",
        "collar_max_utilisation",
        "edge_stress_max",
        "toe_pressure_winkler",
    ]
    s = read(SolidVsCrackedSummary, {"study": "a", "variants": {"solid": _variant(0.1)}})
    assert VARIANT_FIELDS[0][0].of(s.variants["solid"]) == 0.1
    with pytest.raises(StaleResultsError, match="'variants.cracked.status'"):
        bad = _variant(0.2)
        del bad["status"]
        read(SolidVsCrackedSummary, {"study": "a", "variants": {"cracked": bad}})


def _variant(peak: float) -> dict:
    return {
        "fem_peak_rotation": peak,
        "fem_overturned": False,
        "rigid_peak_rotation": peak,
        "rigid_mode": "safe",
        "collar_max_utilisation": 0.5,
        "edge_stress_ratio": 0.1,
        "status": "completed",
    }


def test_every_number_the_docs_quote_from_a_summary_is_declared():
    """docs/run_numbers.py quotes the shipped studies' numbers by their summary.json paths:
    each must be a quantity of its kind's typed summary (a renamed key fails here)."""
    import importlib.util

    spec = importlib.util.spec_from_file_location("run_numbers", ROOT / "docs" / "run_numbers.py")
    assert spec is not None and spec.loader is not None
    run_numbers = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(run_numbers)
    classes = {"default": CrosscheckSummary, "free-rocking": FreeRockingSummary}
    quoted = [
        (study, ".".join(map(str, keys)))
        for study, names in run_numbers.QUOTED.items()
        for file, keys, _ in names.values()
        if file == "summary.json"
    ]
    assert len(quoted) > 40
    undeclared = [(study, key) for study, key in quoted if not _declared(classes[study], key)]
    assert not undeclared, undeclared

"""The packages' dependencies point one way (README, Layout): read from the source's imports.

core <- meshes <- fem;  core <- rigid;  studies -> fem, rigid, meshes, core. The shared core
(colonna/core) imports none of the physics packages; fem/ and meshes/ import nothing from rigid/
or studies/; rigid/ nothing from fem/, meshes/ or studies/.
"""

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
FOLDERS = {
    "core": ROOT / "colonna" / "core",
    "rigid": ROOT / "rigid",
    "fem": ROOT / "fem",
    "meshes": ROOT / "meshes",
    "studies": ROOT / "studies",
}
ALLOWED = {
    "core": set(),
    "meshes": {"core"},
    "rigid": {"core"},
    "fem": {"core", "meshes"},
    "studies": {"core", "rigid", "fem", "meshes"},
}


def imported_packages(path: Path, package: str) -> set[str]:
    """The colonna subpackages that one module imports (relative or absolute, at any depth)."""
    found = set()
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.ImportFrom):
            if node.level == 0:
                parts = (node.module or "").split(".")
                if parts[0] == "colonna" and len(parts) > 1:
                    found.add(parts[1])
                elif parts[0] == "colonna":
                    found.update(alias.name for alias in node.names)
            elif node.level >= 2:  # from ..rigid import x / from .. import rigid
                target = (node.module or "").split(".")[0]
                found.update([target] if target else [alias.name for alias in node.names])
        elif isinstance(node, ast.Import):
            for alias in node.names:
                parts = alias.name.split(".")
                if parts[0] == "colonna" and len(parts) > 1:
                    found.add(parts[1])
    return (found & set(FOLDERS)) - {package}


@pytest.mark.parametrize("package", sorted(FOLDERS))
def test_a_package_imports_only_what_the_layout_allows(package):
    offending = {}
    for path in sorted(FOLDERS[package].rglob("*.py")):
        extra = imported_packages(path, package) - ALLOWED[package]
        if extra:
            offending[str(path.relative_to(ROOT))] = sorted(extra)
    assert not offending, f"{package} imports outside its layer: {offending}"


def test_the_import_reader_sees_every_form(tmp_path):
    """The reader above would pass vacuously if it missed an import form."""
    module = tmp_path / "m.py"
    module.write_text(
        "from ..rigid.block import Block\nfrom .. import studies\n"
        "import colonna.fem.model\nfrom colonna.meshes import column\n"
        "def f():\n    from ..core.errors import InputError\n"
    )
    assert imported_packages(module, "x") == {"rigid", "studies", "fem", "meshes", "core"}


FEM_RUNS = {"run", "run_ensemble", "run_batch", "iter_batch"}
RIGID_RUNS = {"rock", "rock_multibody"}


def _importers(module_suffixes: tuple[str, ...], names: set) -> dict:
    """Where studies/ imports any of ``names`` from a module whose dotted name ends with one of
    ``module_suffixes``: {"file.py:innermost function (or <module>)": names imported there}."""
    callers: dict = {}
    for path in sorted(FOLDERS["studies"].rglob("*.py")):
        tree = ast.parse(path.read_text(), str(path))
        scopes = [
            (node.name, node)
            for node in ast.walk(tree)
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef))
        ]
        for node in ast.walk(tree):
            if not (
                isinstance(node, ast.ImportFrom) and (node.module or "").endswith(module_suffixes)
            ):
                continue
            found = names & {alias.name for alias in node.names}
            if found:  # the innermost function around the import, or the module
                inner = [name for name, f in scopes if f.lineno <= node.lineno <= f.end_lineno]
                where = f"{path.name}:{inner[-1] if inner else '<module>'}"
                callers.setdefault(where, set()).update(found)
    return callers


def test_every_fem_run_of_a_study_goes_through_one_function():
    """studies/ reaches the FEM solver's run functions in one place, fem_study (run_fem, and
    iter_fem for a batch of pulses on one model), so the kinds cannot drift apart on the
    arguments of one computation (issue 17)."""
    callers = _importers(("solver",), FEM_RUNS)
    assert set(callers) == {"fem_study.py:run_fem", "fem_study.py:iter_fem"}, callers


def test_every_rigid_run_of_a_study_goes_through_one_function():
    """The rigid models of a study's column run in one place each, fem_study's run_sdof and
    run_multibody, so that every kind starts them as its FEM (tilt, angular velocity, vertical
    motion). Elsewhere only the command line (a block from flags, no study) and the Zhang &
    Makris validation (the paper's dimensionless block) call them."""
    callers = _importers(("solve", "multibody"), RIGID_RUNS)
    assert set(callers) == {
        "fem_study.py:run_sdof",
        "fem_study.py:run_multibody",
        "cli.py:_cmd_rigid",
        "zhang_makris.py:<module>",
    }, callers


def test_the_study_kinds_have_one_registry():
    """Adding a study kind is one module and one line of studies/kinds.py: the study file's
    allowed [study] kind values are read from that table, and every registered runner and
    report writer resolves to a function."""
    from colonna.studies import driver, kinds, schema

    allowed = schema.StudyFile.model_json_schema()["$defs"]["StudyInfo"]["properties"]["kind"]
    assert tuple(allowed["enum"]) == tuple(kinds.KINDS)
    assert driver.KINDS is kinds.KINDS
    for kind in kinds.KINDS.values():
        assert callable(driver._function(kind.run)) and callable(driver._function(kind.report))

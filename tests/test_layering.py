"""The packages' dependencies point one way (docs/layout.md): read from the source's imports.

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
                name = path.relative_to(FOLDERS["studies"]).as_posix()
                where = f"{name}:{inner[-1] if inner else '<module>'}"
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
        "zhang_makris/runner.py:<module>",
    }, callers


def test_the_study_kinds_have_one_registry():
    """Adding a study kind is its package and one line of studies/kinds.py: the study file's
    allowed [study] kind values are read from that table, and every registered package has a
    runner and a report writer."""
    from colonna.studies import driver, kinds, schema

    allowed = schema.json_schema()["$defs"]["StudyInfo"]["properties"]["kind"]
    assert tuple(allowed["enum"]) == tuple(kinds.KINDS)
    assert driver.KINDS is kinds.KINDS
    for kind in kinds.KINDS.values():
        module = kind.module()
        assert callable(module.run) and callable(module.write_report)
        assert module.__name__ == f"colonna.studies.{kind.package}"


# --- extension points: what adding a ground motion or a study kind touches (issue 34) -----------

GROUND = ROOT / "colonna" / "core" / "ground.py"


def _all_modules():
    for folder in FOLDERS.values():
        yield from sorted(folder.rglob("*.py"))


def _motion_classes() -> set[str]:
    """The concrete ground motions: the classes core/ground.py defines (the protocol aside)."""
    tree = ast.parse(GROUND.read_text())
    names = {node.name for node in tree.body if isinstance(node, ast.ClassDef)}
    return names - {"GroundMotion", "RecordNote"}


def test_no_code_outside_core_branches_on_the_type_of_a_ground_motion():
    """The solvers and the studies use a motion through its protocol (its tables, its sample
    times, its shape), so that a new motion is its class alone (tests/test_motion_protocol.py
    adds one)."""
    motions = _motion_classes()
    assert {"HarmonicPulse", "Record", "NoMotion"} <= motions
    found = []
    for path in _all_modules():
        if path == GROUND:
            continue
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            if isinstance(node, ast.Call) and getattr(node.func, "id", None) == "isinstance":
                named = {n.id for n in ast.walk(node.args[1]) if isinstance(n, ast.Name)}
                named |= {n.attr for n in ast.walk(node.args[1]) if isinstance(n, ast.Attribute)}
                if named & motions:
                    found.append(f"{path.relative_to(ROOT)}:{node.lineno}")
    assert not found, found


def _strings(path: Path) -> list[tuple[int, str]]:
    """The string constants of a module's code (its docstrings aside: prose may say "the
    cross-check")."""
    tree = ast.parse(path.read_text(), str(path))
    docstrings = set()
    for node in ast.walk(tree):
        body = getattr(node, "body", None)
        if isinstance(body, list) and body and isinstance(body[0], ast.Expr):
            docstrings.add(id(body[0].value))
    return [
        (node.lineno, node.value)
        for node in ast.walk(tree)
        if isinstance(node, ast.Constant)
        and isinstance(node.value, str)
        and id(node) not in docstrings
    ]


def _names_kind(text: str, name: str) -> bool:
    """A string that is a kind's name, or quotes it (a message: kind = "free-rocking")."""
    return text == name or f'"{name}"' in text or f"'{name}'" in text


def test_a_kind_is_named_only_in_its_package_and_the_registry():
    """Adding (or renaming) a study kind is its package and one line of studies/kinds.py: no
    other module names it, not even in a message (a kind that points to another finds it in
    the registry)."""
    from colonna.studies.kinds import KINDS

    packages = {name: FOLDERS["studies"] / kind.package for name, kind in KINDS.items()}
    assert all(folder.is_dir() for folder in packages.values()), packages
    found = []
    for path in _all_modules():
        if path == FOLDERS["studies"] / "kinds.py":
            continue
        for lineno, text in _strings(path):
            for name, folder in packages.items():
                if _names_kind(text, name) and folder not in path.parents:
                    found.append(f"{path.relative_to(ROOT)}:{lineno} names {name!r}")
    assert not found, "\n".join(found)

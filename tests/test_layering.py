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


FEM_RUNS = {"run", "run_ensemble", "run_batch", "iter_batch", "refine_window"}
RIGID_RUNS = {
    "rock",
    "rock_multibody",
    "multibody_outcome",
    "overturning_spectrum",
    "multibody_spectrum",
}


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
    """studies/ reaches the FEM solver's run functions in one place, the gateway studies/models.py
    (run_fem, iter_fem for a batch of pulses on one model, refine_toe_window for the
    cross-check's toe windows), so the kinds cannot drift apart on the arguments of one
    computation (issues 17, 49)."""
    callers = _importers(("solver", "toe_stress"), FEM_RUNS)
    assert set(callers) == {
        "models.py:run_fem",
        "models.py:iter_fem",
        "models.py:refine_toe_window",
    }, callers


def test_every_rigid_run_of_a_study_goes_through_one_function():
    """The rigid models of a study's column run in one place each, the gateway's (studies/
    models.py) run_sdof and run_multibody, their fast paths without histories (the fragility's:
    sdof_outcome on the kernel, run_multibody_outcome) and their spectra, so that every kind
    starts them as its FEM (tilt, angular velocity, vertical motion). Elsewhere only the
    command line (a block from flags, no study) and the Zhang & Makris validation (the paper's
    dimensionless block) call them."""
    callers = _importers(("solve", "multibody", "spectrum"), RIGID_RUNS)
    assert set(callers) == {
        "models.py:run_sdof",
        "models.py:run_multibody",
        "models.py:run_multibody_outcome",
        "models.py:sdof_spectrum",
        "models.py:multibody_spectrum",
        "cli.py:_cmd_rigid",
        "cli.py:_cmd_spectrum",
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


# the modules outside a kind's package that import it, each with why (docs/contributing.md): the
# registry loads every kind by name (kinds.py, through importlib)
KIND_IMPORTERS = {
    ("colonna.studies.collar_design.runner", "crosscheck"): "runs the cross-check's cases",
    ("colonna.studies.sweep", "crosscheck"): "the sweeps run the cross-check's cases",
    ("colonna.studies.cli", "zhang_makris"): "colonna validate runs its validation",
    ("colonna.studies.cli", "fragility"): "the fragility command's first screen in words",
    ("colonna.studies.collar_layout.runner", "fragility"): "each layout's fragility is the "
    "fragility kind's: its records' IMs, ladder, multibody runs, FEM stripe and risk entry",
    ("colonna.studies.collar_layout.schema", "fragility"): "the same intensity measures",
    ("colonna.studies.collar_layout", "fragility"): "the same defaults: the suite's records",
}


def test_a_kind_package_is_imported_only_where_the_list_says():
    """docs/contributing.md: "no other module names a kind"; its code is imported by name only
    by the registry and by :data:`KIND_IMPORTERS` (a new importer is a decision: add it there
    with its reason). An import that goes away may leave the list."""
    from test_imports import import_graph

    from colonna.studies.kinds import KINDS

    packages = {f"colonna.studies.{kind.package}": kind.package for kind in KINDS.values()}
    found = set()
    for importer, imported in import_graph().items():
        for module in imported:
            for dotted, package in packages.items():
                inside = importer == dotted or importer.startswith(dotted + ".")
                if (module == dotted or module.startswith(dotted + ".")) and not inside:
                    found.add((importer, package))
    assert found <= set(KIND_IMPORTERS), sorted(found - set(KIND_IMPORTERS))


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


# --- one gateway to the models (issue 49) -------------------------------------------------------


def _dotted(name: str, path: Path) -> str:
    """The package a module's relative imports are read from."""
    return name if path.name == "__init__.py" else name.rpartition(".")[0]


def private_imports(path: Path, name: str, modules: dict[str, Path]) -> list[str]:
    """The private modules (a dotted part ``_x``, not ``__init__``) of colonna that module
    ``name`` at ``path`` imports: by ``import``, ``from ... import`` (the module or a name of
    it) or ``importlib.import_module`` with a literal string."""
    from test_imports import imports_of

    targets = imports_of(name, path, modules) | importlib_imports(name, path, modules)
    return sorted(
        t
        for t in targets
        if any(part.startswith("_") and not part.startswith("__") for part in t.split("."))
    )


def _literal_module(node: ast.Call, package: str, modules: dict[str, Path]) -> set[str]:
    """The colonna modules an ``import_module(...)`` call can name: a literal string (relative
    to ``package`` with a second argument), an f-string of ``__package__`` / ``__name__`` and
    literal parts, or an f-string whose head is not known and whose literal tail ends a module
    name (``f"{kind.module().__name__}.command"``: every module that ends so)."""
    if not node.args:
        return set()
    arg = node.args[0]
    if len(node.args) > 1 and isinstance(node.args[1], ast.Constant):
        package = str(node.args[1].value)
    if isinstance(arg, ast.Constant) and isinstance(arg.value, str):
        text = arg.value
        if text.startswith("."):
            dots = len(text) - len(text.lstrip("."))
            base = package.split(".")
            base = base[: len(base) - (dots - 1)]
            text = ".".join(base + ([text.lstrip(".")] if text.lstrip(".") else []))
        return {text} & set(modules)
    if isinstance(arg, ast.JoinedStr):
        parts, known = [], True
        for value in arg.values:
            if isinstance(value, ast.Constant):
                parts.append(str(value.value))
            elif ast.unparse(value.value) == "__package__":
                parts.append(package)
            else:
                known = False
                parts = []
        text = "".join(parts)
        if known:
            return {text} & set(modules)
        if text.startswith("."):
            return {m for m in modules if m.endswith(text)}
    return set()


def importlib_imports(name: str, path: Path, modules: dict[str, Path]) -> set[str]:
    """The colonna modules that module ``name`` imports through ``importlib.import_module``
    (:func:`_literal_module`)."""
    package = _dotted(name, path)
    found: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Call) and (
            getattr(node.func, "attr", None) == "import_module"
            or getattr(node.func, "id", None) == "import_module"
        ):
            found |= _literal_module(node, package, modules)
    return found - {name}


GATEWAY = "colonna.studies.models"  # the one study module that reaches the kernels


def test_no_study_module_imports_a_private_module():
    """studies/ runs the solvers through their public functions, every run of a model through
    studies/models.py (the gateway, the one module that may): no other study module imports a
    private module of fem/, rigid/, meshes/ or core/ (``fem._kernels``, ``rigid._kernels``,
    ``rigid._multibody``), not even to list the kernels a study compiles (the gateway names
    them: ``models.kernels``)."""
    from test_imports import module_names

    modules = module_names()
    found = {}
    for name, path in modules.items():
        if name.startswith("colonna.studies") and name != GATEWAY:
            private = private_imports(path, name, modules)
            if private:
                found[str(path.relative_to(ROOT))] = private
    assert not found, f"studies/ imports private modules (ask studies/models.py): {found}"


def test_the_private_import_reader_sees_every_form(tmp_path):
    """The scan above would pass vacuously if it missed an import form."""
    from test_imports import module_names

    modules = module_names()
    forms = {
        "from ..fem import _kernels\n": ["colonna.fem._kernels"],
        "def f():\n    from ..rigid import _multibody as K\n": ["colonna.rigid._multibody"],
        "from ..rigid._kernels import rk_run\n": ["colonna.rigid._kernels"],
        "import colonna.fem._kernels\n": ["colonna.fem._kernels"],
        "import importlib\nimportlib.import_module('colonna.rigid._kernels')\n": [
            "colonna.rigid._kernels"
        ],
        "from importlib import import_module\nimport_module('._multibody', 'colonna.rigid')\n": [
            "colonna.rigid._multibody"
        ],
        "from ..rigid.solve import rock\n": [],
    }
    for text, expected in forms.items():
        path = tmp_path / "x.py"
        path.write_text(text)
        modules["colonna.studies.x"] = path  # read from tmp_path, as a study module
        assert private_imports(path, "colonna.studies.x", modules) == expected, text


# Import edges through importlib that close a cycle, allowed while their owners remove them;
# each names why (as tests/test_imports.ALLOWED_CYCLE_EDGES for plain imports).
# (cli -(importlib)-> fragility.command -> cli was one until the block and collar options left
# cli.py for studies/options.py, issue 49)
ALLOWED_IMPORTLIB_CYCLE_EDGES: dict[tuple[str, str], str] = {}


# the registry of study kinds loads each kind's package (and its schema and command modules) by
# name on first use: that is what it is for, and a kind's package imports the shared modules
# that read the registry; its loads are not edges (a plugin, not a cycle of the tree's own)
REGISTRY = "colonna.studies.kinds"


def test_no_import_cycle_through_importlib():
    """No import cycle, counting the modules loaded by ``importlib.import_module`` with a
    literal name (or an f-string of literal parts, or one whose literal tail names a module:
    a kind's ``command`` module), which the plain-import graph (tests/test_imports.py) does not
    see: cli.py loads ``fragility.command`` so, and that module imported cli's private option
    helpers. The registry's own loads of the kinds aside (:data:`REGISTRY`)."""
    from test_imports import ALLOWED_CYCLE_EDGES, cycles, import_graph, module_names

    modules = module_names()
    graph = import_graph()
    for name, path in modules.items():
        if name != REGISTRY:
            graph[name] |= importlib_imports(name, path, modules)
    for importer, imported in {**ALLOWED_CYCLE_EDGES, **ALLOWED_IMPORTLIB_CYCLE_EDGES}:
        graph[importer].discard(imported)
    found = [" -> ".join(m.removeprefix("colonna.") for m in c) for c in cycles(graph)]
    assert not found, "import cycles through importlib:\n" + "\n".join(found)


def test_the_importlib_reader_resolves_literal_names(tmp_path):
    """The cycle scan above would pass vacuously if it missed the forms colonna uses."""
    from test_imports import module_names

    modules = module_names()
    path = tmp_path / "cli.py"
    path.write_text(
        "import importlib\n"
        "a = importlib.import_module('colonna.studies.kinds')\n"
        "b = importlib.import_module(f'{__package__}.collar_bench')\n"
        "c = importlib.import_module(f'{kind.module().__name__}.command')\n"
        "d = importlib.import_module(name)\n"
    )
    found = importlib_imports("colonna.studies.cli", path, modules)
    commands = {m for m in modules if m.endswith(".command")}
    assert commands and "colonna.studies.fragility.command" in commands
    assert found == {"colonna.studies.kinds", "colonna.studies.collar_bench"} | commands

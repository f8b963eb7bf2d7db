"""No function outside the numba kernels is over 120 lines, and no public one takes more than 8
parameters (issue 49): read from the source's ast.

A numba kernel is a function decorated with njit, jit, intrinsic or vectorize (bare, called, or
as numba.njit), or any function defined inside one (the codegen of an @intrinsic). Every other
function or method in colonna/, fem/, rigid/, meshes/ and studies/ is counted from its `def` line
(decorators excluded) to its last line. A public function is a module's function or a method of
its class, in a module whose name, and along a path whose every name, has no leading underscore
(``_kernels.py``, ``_Recorder.record``, ``__init__`` and closures are not the public API); its
parameters are the positional-only, positional and keyword-only ones, ``*args`` and ``**kwargs``
one each, a method's ``self`` or ``cls`` not counted.
"""

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
FOLDERS = ("colonna", "fem", "rigid", "meshes", "studies")
KERNEL_DECORATORS = {"njit", "jit", "intrinsic", "vectorize"}
MAX_LINES = 120
MAX_PARAMETERS = 8


def _decorator_name(node: ast.expr) -> str:
    """The last dotted name of a decorator: `numba.njit(cache=True)` -> "njit"."""
    if isinstance(node, ast.Call):
        node = node.func
    if isinstance(node, ast.Attribute):
        return node.attr
    if isinstance(node, ast.Name):
        return node.id
    return ""


def long_functions(source: str, name: str, limit: int = MAX_LINES) -> list[tuple[str, int]]:
    """(qualified name, lines) of every non-kernel function of one module over `limit` lines."""
    found = []

    def visit(node: ast.AST, prefix: str) -> None:
        for child in ast.iter_child_nodes(node):
            if isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef)):
                if {_decorator_name(d) for d in child.decorator_list} & KERNEL_DECORATORS:
                    continue  # a kernel and everything defined inside it
                lines = child.end_lineno - child.lineno + 1
                if lines > limit:
                    found.append((f"{name}: {prefix}{child.name}", lines))
                visit(child, f"{prefix}{child.name}.")
            elif isinstance(child, ast.ClassDef):
                visit(child, f"{prefix}{child.name}.")
            else:
                visit(child, prefix)

    visit(ast.parse(source, name), "")
    return found


def _parameter_count(node: ast.FunctionDef | ast.AsyncFunctionDef, method: bool) -> int:
    """Positional-only, positional and keyword-only parameters, *args and **kwargs one each;
    a method's self or cls not counted (a staticmethod has none)."""
    a = node.args
    named = [*a.posonlyargs, *a.args]
    static = "staticmethod" in {_decorator_name(d) for d in node.decorator_list}
    if method and not static and named and named[0].arg in ("self", "cls"):
        named = named[1:]
    return len(named) + len(a.kwonlyargs) + (a.vararg is not None) + (a.kwarg is not None)


def long_signatures(source: str, name: str, limit: int = MAX_PARAMETERS) -> list[tuple[str, int]]:
    """(qualified name, parameters) of every public non-kernel function of one module with
    more than ``limit`` parameters (none where the module's own name is private)."""
    if Path(name).stem.startswith("_") and Path(name).stem != "__init__":
        return []
    found = []

    def visit(node: ast.AST, prefix: str, method: bool) -> None:
        for child in ast.iter_child_nodes(node):
            if isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef)):
                kernel = {_decorator_name(d) for d in child.decorator_list} & KERNEL_DECORATORS
                if kernel or child.name.startswith("_"):
                    continue  # a kernel, or not the public API
                count = _parameter_count(child, method)
                if count > limit:
                    found.append((f"{name}: {prefix}{child.name}", count))
                # what is defined inside a function is not reachable from outside it
            elif isinstance(child, ast.ClassDef):
                if not child.name.startswith("_"):
                    visit(child, f"{prefix}{child.name}.", True)
            elif not isinstance(child, ast.Lambda):
                visit(child, prefix, method)

    visit(ast.parse(source, name), "", False)
    return found


def test_no_function_outside_the_kernels_is_over_120_lines():
    offending = []
    for folder in FOLDERS:
        for path in sorted((ROOT / folder).rglob("*.py")):
            offending += long_functions(path.read_text(), str(path.relative_to(ROOT)))
    assert not offending, f"functions over {MAX_LINES} lines (split them): {offending}"


def test_the_size_reader_counts_methods_and_skips_kernels():
    body = "\n".join(f"    x{i} = {i}" for i in range(5))
    inner = body.replace("\n", "\n    ")
    source = (
        f"def long():\n{body}\n"
        f"class C:\n    def method(self):\n    {inner}\n"
        f"@njit(cache=True)\ndef kernel():\n{body}\n"
        f"@numba.vectorize\ndef ufunc():\n{body}\n"
        f"@intrinsic\ndef intr(typingctx):\n    def codegen():\n    {inner}\n"
        f"def short():\n    return 1\n"
    )
    assert long_functions(source, "m.py", limit=5) == [("m.py: long", 6), ("m.py: C.method", 6)]


def test_no_public_function_takes_more_than_8_parameters():
    """The public API's run functions take a few typed objects (a Motion, a Release, settings),
    not a dozen keywords each (issue 49)."""
    offending = []
    for folder in FOLDERS:
        for path in sorted((ROOT / folder).rglob("*.py")):
            offending += long_signatures(path.read_text(), str(path.relative_to(ROOT)))
    assert not offending, (
        f"public functions over {MAX_PARAMETERS} parameters (group them into parameter "
        f"objects): {offending}"
    )


def test_the_signature_reader_counts_every_kind_of_parameter_and_skips_the_private():
    def params(more: str = "") -> str:  # 1 positional-only + 2 + *args + 2 keyword-only + **kw
        return f"a, /, b, c=1, *args, d, e=2{more}, **kwargs"

    nine, eight = params(", f, g"), params(", f")
    source = (
        f"def seven({params()}):\n    pass\n"
        f"def nine({nine}):\n    pass\n"
        f"def _private({nine}):\n    pass\n"
        f"class C:\n"
        f"    def method(self, {eight}):\n        pass\n"
        f"    @classmethod\n    def make(cls, {eight}):\n        pass\n"
        f"    @staticmethod\n    def static(self, {params()}):\n        pass\n"
        f"    def __init__(self, {nine}):\n        pass\n"
        f"class _Hidden:\n    def method(self, {nine}):\n        pass\n"
        f"@njit\ndef kernel({nine}):\n    pass\n"
        f"def outer():\n    def inner({nine}):\n        pass\n"
    )
    assert long_signatures(source, "m.py", limit=7) == [
        ("m.py: nine", 9),
        ("m.py: C.method", 8),
        ("m.py: C.make", 8),
        ("m.py: C.static", 8),
    ]
    assert long_signatures(source, "pkg/_kernels.py", limit=7) == []

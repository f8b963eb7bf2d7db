"""No function outside the numba kernels is over 120 lines (issue 49): read from the source's ast.

A numba kernel is a function decorated with njit, jit, intrinsic or vectorize (bare, called, or
as numba.njit), or any function defined inside one (the codegen of an @intrinsic). Every other
function or method in colonna/, fem/, rigid/, meshes/ and studies/ is counted from its `def` line
(decorators excluded) to its last line.
"""

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
FOLDERS = ("colonna", "fem", "rigid", "meshes", "studies")
KERNEL_DECORATORS = {"njit", "jit", "intrinsic", "vectorize"}
MAX_LINES = 120


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

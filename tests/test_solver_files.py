"""Solvers compute, one module writes (issue 49): no module of fem/ or rigid/ writes a file but
the ones whose job it is. A run's files go through colonna.fem.output (history.csv streamed as
it runs, summary.json, VTU, the toe window's start), a run's checkpoint through
colonna.fem.checkpoint, figures through colonna.rigid.plotting."""

from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
WRITERS = {
    "fem/output.py": "a FEM run's files",
    "fem/checkpoint.py": "a FEM run's checkpoint parts",
    "rigid/plotting.py": "the rigid model's figures (matplotlib savefig)",
}
WRITING_CALLS = {
    "savetxt",
    "savez",
    "savez_compressed",
    "save",
    "write_text",
    "write_bytes",
    "dump",
    "savefig",
    "replace",
    "truncate",
}


def _writes(tree: ast.AST) -> list[str]:
    """The file-writing calls of a module: open() for writing or appending, and calls named as
    numpy's, pathlib's, json's, matplotlib's and os's writers."""
    found = []
    for node in ast.walk(tree):
        if not isinstance(node, ast.Call):
            continue
        func = node.func
        name = func.attr if isinstance(func, ast.Attribute) else getattr(func, "id", "")
        if name == "open":
            modes = [a for a in node.args[1:2]] + [
                k.value for k in node.keywords if k.arg == "mode"
            ]
            if any(isinstance(m, ast.Constant) and set(str(m.value)) & set("wax+") for m in modes):
                found.append(f"{node.lineno}: open(..., {ast.unparse(modes[0])})")
        elif name in WRITING_CALLS and isinstance(func, ast.Attribute):
            owner = func.value
            # a rename or truncation is os's or a path's (dataclasses.replace is no write)
            if name in ("replace", "truncate") and not (
                isinstance(owner, ast.Call) or getattr(owner, "id", "") == "os"
            ):
                continue
            found.append(f"{node.lineno}: {ast.unparse(func)}")
    return found


def test_no_solver_module_writes_a_file():
    offenders = {}
    for folder in ("fem", "rigid"):
        for path in sorted((ROOT / folder).glob("*.py")):
            rel = f"{folder}/{path.name}"
            if rel in WRITERS:
                continue
            found = _writes(ast.parse(path.read_text()))
            if found:
                offenders[rel] = found
    assert not offenders, offenders


def test_the_check_finds_a_solver_that_writes():
    """The scan catches the ways the solver wrote its history before (so the test can fail)."""
    source = """
def record(self, out):
    self.csv = open(out / "history.csv.part", "w")
    np.savetxt(self.csv, rows)
    Path(self.csv.name).replace(out / "history.csv")
    (out / "summary.json").write_text("{}")
    with open(out / "x") as f:  # reading is fine
        f.read()
"""
    found = _writes(ast.parse(source))
    assert [line.split(":")[0] for line in found] == ["3", "4", "5", "6"], found

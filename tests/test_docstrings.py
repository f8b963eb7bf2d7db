"""The docstring examples of every colonna module run as tests (as pyvista's do)."""

import doctest
import importlib
import pkgutil

import pytest

import colonna

SUBPACKAGES = ("core", "rigid", "fem", "meshes", "studies")


def _modules():
    names = ["colonna"]
    for sub in SUBPACKAGES:
        package = importlib.import_module(f"colonna.{sub}")
        names.append(package.__name__)
        names += [m.name for m in pkgutil.iter_modules(package.__path__, f"{package.__name__}.")]
    return names


@pytest.mark.parametrize("name", _modules())
def test_docstring_examples(name):
    module = importlib.import_module(name)
    result = doctest.testmod(module, optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    assert result.failed == 0, f"{result.failed} docstring example(s) failed in {name}"


def test_docstring_examples_exist():
    """The suite above would pass vacuously if no module had an example."""
    attempted = sum(
        doctest.testmod(importlib.import_module(n)).attempted
        for n in ("colonna", "colonna.rigid.block", "colonna.core.collar")
    )
    assert attempted >= 5 and colonna.__version__

"""A plain (non-editable) install is one ``colonna`` package: no bare top-level ``rigid``,
``fem``, ``meshes`` or ``studies`` (other distributions own those names)."""

import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).parents[1]


@pytest.fixture(scope="module")
def wheel_build(tmp_path_factory):
    """The wheel built from the source tree, and what the build printed."""
    out = tmp_path_factory.mktemp("wheel")
    proc = subprocess.run(
        [
            sys.executable,
            "-m",
            "pip",
            "wheel",
            "--no-deps",
            "--quiet",
            "--wheel-dir",
            str(out),
            str(ROOT),
        ],
        capture_output=True,
        text=True,
    )
    if proc.returncode != 0:
        pytest.skip(f"cannot build a wheel here (no package index?): {proc.stderr[-300:]}")
    return next(out.glob("colonna-*.whl")), proc.stdout + proc.stderr


@pytest.fixture(scope="module")
def wheel(wheel_build):
    return wheel_build[0]


def test_wheel_builds_without_setuptools_warnings(wheel_build):
    """No deprecated metadata (a license table) and no package-data folder left out of
    ``packages``: setuptools builds the wheel without a warning."""
    printed = wheel_build[1]
    assert "warning" not in printed.lower(), printed[-2000:]


def test_wheel_holds_only_the_colonna_package(wheel):
    names = zipfile.ZipFile(wheel).namelist()
    tops = {name.split("/")[0] for name in names}
    assert tops == {
        "colonna",
        wheel.name.split("-")[0] + "-" + wheel.name.split("-")[1] + ".dist-info",
    }
    for sub in ("rigid", "fem", "meshes", "studies"):
        assert f"colonna/{sub}/__init__.py" in names
    assert "colonna/studies/default.toml" in names  # the shipped studies
    assert "colonna/studies/templates/base.html.j2" in names  # the shared page
    for package in ("crosscheck", "collar_design", "free_rocking", "zhang_makris"):
        assert f"colonna/studies/{package}/report.html.j2" in names  # each kind's own page


def test_installed_package_runs_outside_the_source_tree(wheel, tmp_path):
    target = tmp_path / "site"
    subprocess.run(
        [
            sys.executable,
            "-m",
            "pip",
            "install",
            "--no-deps",
            "--quiet",
            "--target",
            str(target),
            str(wheel),
        ],
        check=True,
    )
    assert not any((target / name).exists() for name in ("rigid", "fem", "meshes", "studies"))
    code = (
        "import colonna, colonna.studies.cli as cli, colonna.fem, colonna.meshes; "
        "from colonna.studies.report import TEMPLATES; "
        "from colonna.studies.schema import json_schema; "
        "assert TEMPLATES.get_template('crosscheck/report.html.j2'); "
        "assert 'column' in json_schema()['properties']; "
        "print(colonna.rigid.__file__); print(cli.resolve_study('default'))"
    )
    proc = subprocess.run(
        [sys.executable, "-c", code],
        capture_output=True,
        text=True,
        cwd=tmp_path,
        env={"PYTHONPATH": str(target), "PATH": ""},
        check=True,
    )
    rigid_file, default_study = proc.stdout.split()
    assert Path(rigid_file).is_relative_to(target / "colonna" / "rigid")
    assert Path(default_study).is_file()

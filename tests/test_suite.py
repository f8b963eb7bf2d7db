"""Record suites (colonna.core.suite): a TOML list or a folder of AT2, ESM and two-column files,
each record with its scale, its units and its file's SHA-256; one InputError naming the entry for
each mistake; the list writer reads back exactly."""

import hashlib
import shutil
from pathlib import Path

import numpy as np
import pytest

from colonna.core.errors import InputError
from colonna.core.ground import read_record
from colonna.core.suite import load_suite, suite_toml

DATA = Path(__file__).parent / "data"


@pytest.fixture
def folder(tmp_path):
    """synthetic.AT2 (units of g), esm_example.ASC (cm/s^2) and a two-column file in g."""
    shutil.copy(DATA / "synthetic.AT2", tmp_path / "a_peer.AT2")
    shutil.copy(DATA / "esm_example.ASC", tmp_path / "b_esm.ASC")
    t = np.arange(200) * 0.01
    rows = "\n".join(f"{x:.2f} {0.1 * np.sin(6 * x):.6f}" for x in t)
    (tmp_path / "c_plain.txt").write_text("time acceleration\n" + rows + "\n")
    (tmp_path / "README.md").write_text("not a record\n")
    return tmp_path


def test_a_list_reads_each_format_in_its_units_with_scale_and_hash(folder):
    (folder / "list.toml").write_text(
        suite_toml(
            [
                {"file": "a_peer.AT2", "scale": 2.0},
                {"file": "b_esm.ASC", "name": "esm"},
                {"file": "c_plain.txt", "units": "g", "parameters": {"Tp": 1.25, "seed": 3}},
            ]
        )
    )
    suite = load_suite(folder / "list.toml")
    assert [r.name for r in suite] == ["a_peer", "esm", "c_plain"]
    peer, esm, plain = suite
    assert peer.scale == 2.0 and peer.scaled.peak_acceleration == pytest.approx(
        2 * 0.25 * 9.81, rel=1e-6
    )
    assert esm.record.peak_acceleration == pytest.approx(2.1228, rel=1e-4)  # 212.28 cm/s^2
    assert plain.record.peak_acceleration == pytest.approx(0.1 * 9.81, rel=1e-4)
    assert plain.parameters == {"Tp": 1.25, "seed": 3}
    assert peer.sha256 == hashlib.sha256((folder / "a_peer.AT2").read_bytes()).hexdigest()
    assert esm.path == (folder / "b_esm.ASC").resolve()


def test_a_folder_reads_its_self_describing_files_and_needs_units_for_two_columns(folder):
    with pytest.raises(
        InputError, match=r"c_plain.txt: a two-column file does not state its units"
    ):
        load_suite(folder)
    suite = load_suite(folder, units="g")
    assert [r.name for r in suite] == ["a_peer", "b_esm", "c_plain"]  # README.md left out
    np.testing.assert_array_equal(
        suite[1].record.acceleration_values,
        read_record(DATA / "esm_example.ASC").acceleration_values,
    )
    (folder / "suite.toml").write_text('[[record]]\nfile = "b_esm.ASC"\nscale = 0.5\n')
    only = load_suite(folder)  # the folder's list wins
    assert [(r.name, r.scale) for r in only] == [("b_esm", 0.5)]


@pytest.mark.parametrize(
    ("text", "message"),
    [
        (
            '[[record]]\nfile = "a_peer.AT2"\nscal = 2\n',
            r"record 1 \(a_peer.AT2\): unknown key 'scal'",
        ),
        ('[[record]]\nfile = "nothing.AT2"\n', r"record 1 \(nothing.AT2\): no such file"),
        ('[[record]]\nfile = "a_peer.AT2"\nscale = -1\n', r"scale = -1 must be a number > 0"),
        ('[[record]]\nfile = "a_peer.AT2"\nunits = "g"\n', r"header states its units"),
        ('[[record]]\nfile = "c_plain.txt"\nunits = "furlong"\n', r"units = 'furlong' is not one"),
        ("[[record]]\nscale = 2\n", r"record 1: file = ... .* is required"),
        (
            '[[record]]\nfile = "a_peer.AT2"\n[[record]]\nfile = "b_esm.ASC"\nname = "a_peer"\n',
            r"records 1 and 2 are both named 'a_peer'",
        ),
        ("[suite]\nname = 'x'\n", r"no \[\[record\]\] entries"),
        ("[records]\nfile = 'x'\n", r"unknown table 'records'"),
    ],
)
def test_a_mistake_in_a_list_names_the_entry(folder, text, message):
    (folder / "list.toml").write_text(text)
    with pytest.raises(InputError, match=message):
        load_suite(folder / "list.toml")


def test_an_empty_folder_and_a_missing_path_are_input_errors(tmp_path):
    with pytest.raises(InputError, match="no record files"):
        load_suite(tmp_path)
    with pytest.raises(InputError, match="no such folder or file"):
        load_suite(tmp_path / "nowhere")


def test_the_list_writer_reads_back_every_float_exactly(folder):
    values = {"Tp": 0.1 + 0.2, "Vp": 1e-17, "gamma": 2.0 / 3.0, "name": 'a "quoted" one'}
    (folder / "list.toml").write_text(
        suite_toml([{"file": "a_peer.AT2", "scale": 1 / 3, "parameters": values}], comment="x\ny")
    )
    (entry,) = load_suite(folder / "list.toml")
    assert entry.scale == 1 / 3 and entry.parameters == values
    assert (folder / "list.toml").read_text().startswith("# x\n# y\n\n[[record]]\n")


def test_a_suite_record_scaled_to_a_target_pga_or_pgv_has_that_peak(folder):
    """scale_to_pga (m/s^2) or scale_to_pgv (m/s) in place of scale (issue 48): the factor is
    the target over the record's own peak, as the fragility measures it, and is the record's
    scale (reported with the suite)."""
    from colonna.core.intensity import intensity_measures

    (folder / "list.toml").write_text(
        '[[record]]\nfile = "a_peer.AT2"\nscale_to_pga = 3.43\n\n'
        '[[record]]\nfile = "b_esm.ASC"\nscale_to_pgv = 0.25\n'
    )
    peer, esm = load_suite(folder / "list.toml")
    assert peer.scaled.peak_acceleration == pytest.approx(3.43, rel=1e-12)
    assert peer.scale == pytest.approx(3.43 / peer.record.peak_acceleration, rel=1e-15)
    assert intensity_measures(esm.scaled).pgv == pytest.approx(0.25, rel=1e-12)
    (folder / "both.toml").write_text(
        '[[record]]\nfile = "a_peer.AT2"\nscale = 2\nscale_to_pga = 3\n'
    )
    with pytest.raises(InputError, match="give only one of scale, scale_to_pga"):
        load_suite(folder / "both.toml")

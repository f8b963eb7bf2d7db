"""The ESM ASCII reader (colonna.core.esm): units from the header, the format's checks.

tests/data/esm_example.ASC is a format example (64 header lines as the database writes them,
synthetic samples: 290 cm/s^2 sin(4 pi t) e^(-t/2) ramped over 0.5 s, 400 samples at 0.01 s).
"""

from pathlib import Path

import numpy as np
import pytest

from colonna.core import esm
from colonna.core.errors import InputError
from colonna.core.ground import read_record

EXAMPLE = Path(__file__).parent / "data" / "esm_example.ASC"


def _samples():
    t = np.arange(400) * 0.01
    return 290.0 * np.sin(4.0 * np.pi * t) * np.exp(-0.5 * t) * np.minimum(1.0, t / 0.5)


def test_the_example_reads_in_m_s2_from_its_cm_s2_header():
    read = esm.read_file(EXAMPLE)
    rec = read.record
    assert rec.time.size == 400 and rec.time[1] == pytest.approx(0.01)
    # cm/s^2 -> m/s^2: the samples are printed to 1e-6 cm/s^2
    np.testing.assert_allclose(rec.acceleration_values, 0.01 * _samples(), atol=1e-8)
    assert rec.peak_acceleration == pytest.approx(float(read.header["PGA_CM/S^2"]) / 100.0)
    assert (read.station, read.stream) == ("SYN", "HNE")
    assert read.header["PROCESSING"] == "none: colonna's format example (tests/data)"
    assert len(read.header) == 64


def test_read_record_dispatches_by_extension_and_by_header(tmp_path):
    by_suffix = read_record(EXAMPLE)
    renamed = tmp_path / "mrn.txt"  # ESM also serves .txt: the header says what it is
    renamed.write_text(EXAMPLE.read_text())
    by_header = read_record(renamed)
    np.testing.assert_array_equal(by_suffix.acceleration_values, by_header.acceleration_values)
    assert esm.is_esm(renamed) and not esm.is_esm(EXAMPLE.with_name("synthetic.AT2"))


def _edited(tmp_path, old: str, new: str) -> Path:
    text = EXAMPLE.read_text()
    assert old in text
    path = tmp_path / "edited.ASC"
    path.write_text(text.replace(old, new, 1))
    return path


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        ("UNITS: cm/s^2", "UNITS: furlongs", r"UNITS = 'furlongs' is not known"),
        ("UNITS: cm/s^2\n", "", r"no UNITS line"),
        ("NDATA: 400", "NDATA: 401", r"NDATA = 401 but 400 samples follow"),
        ("NDATA: 400", "NDATA: many", r"NDATA = 'many' is not a number"),
        ("SAMPLING_INTERVAL_S: 0.010000", "SAMPLING_INTERVAL_S: 0.05", r"coarser than 0.02 s"),
        ("SAMPLING_INTERVAL_S: 0.010000\n", "", r"no SAMPLING_INTERVAL_S line"),
        ("DATA_TYPE: ACCELERATION", "DATA_TYPE: VELOCITY", r"only ACCELERATION files"),
        ("\n0.723307\n", "\n0.72x307\n", r"line 66: not numeric"),
    ],
)
def test_a_malformed_file_is_one_input_error_naming_the_key(tmp_path, old, new, message):
    with pytest.raises(InputError, match=message):
        esm.read(_edited(tmp_path, old, new))


def test_units_that_do_not_fit_the_samples_are_caught_by_the_header_pga(tmp_path):
    """A file whose header says m/s^2 for cm/s^2 samples peaks 100 x its PGA_CM/S^2."""
    with pytest.raises(InputError, match=r"PGA_CM/S\^2 = 212.28 in the header.*21228"):
        esm.read(_edited(tmp_path, "UNITS: cm/s^2", "UNITS: m/s^2"))


def test_units_in_g_are_converted_with_the_readers_g(tmp_path):
    path = _edited(tmp_path, "UNITS: cm/s^2", "UNITS: g")
    path.write_text(path.read_text().replace("PGA_CM/S^2: 212.279903", "PGA_CM/S^2: "))
    rec = esm.read(path, g=10.0)
    np.testing.assert_allclose(rec.acceleration_values, 10.0 * _samples(), atol=1e-5)

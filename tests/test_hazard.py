"""The site's hazard as data (issue 50, colonna.core.hazard): a CSV table read in SI and
interpolated log-log, bad files refused naming the file and line, the power law, and the
change of variable to a fragility's rocking-normalised measure."""

from __future__ import annotations

import math
from importlib.resources import files

import numpy as np
import pytest

from colonna.core.constants import STANDARD_GRAVITY
from colonna.core.errors import InputError
from colonna.core.hazard import annual_frequency, in_measure, power_law, read_hazard

EXAMPLE = files("colonna.studies") / "hazards" / "mirandola-illustrative-pga.csv"


def _write(tmp_path, text: str):
    path = tmp_path / "hazard.csv"
    path.write_text(text)
    return path


def test_the_shipped_example_says_it_is_illustrative_and_reads_in_si():
    curve = read_hazard(EXAMPLE)
    assert curve.intensity == "pga" and curve.unit == "m/s^2" and curve.tabulated
    assert any("ILLUSTRATIVE" in note for note in curve.notes)
    # its 475-year row (0.147 g, 1/475 per year), in m/s^2
    i = int(np.argmin(np.abs(np.array(curve.frequency) - 1.0 / 475.0)))
    assert curve.im[i] == pytest.approx(0.147 * STANDARD_GRAVITY, rel=1e-12)
    assert len(curve.im) == 9


def test_between_its_points_a_table_is_a_power_law_and_beyond_them_as_it_says(tmp_path):
    path = _write(tmp_path, "pga_m_s2,annual_frequency\n1.0,1e-2\n2.0,1e-3\n4.0,5e-4\n")
    curve = read_hazard(path)
    # log-log midpoint of the first segment: the geometric mean of the frequencies
    assert annual_frequency(curve, math.sqrt(2.0)) == pytest.approx(math.sqrt(1e-5), rel=1e-12)
    np.testing.assert_allclose(curve.slopes(), [math.log2(10.0), 1.0])
    # above the table: extrapolated by the last segment's power law, or truncated (none)
    assert annual_frequency(curve, 8.0) == pytest.approx(2.5e-4)
    cut = read_hazard(path, beyond="truncate")
    assert annual_frequency(cut, 8.0) == 0.0
    # below it, either way: held at the lowest point's frequency (no unbounded power law)
    assert annual_frequency(curve, 0.5) == annual_frequency(cut, 0.5) == pytest.approx(1e-2)
    assert annual_frequency(cut, 3.0) == pytest.approx(annual_frequency(curve, 3.0))


@pytest.mark.parametrize(
    ("header", "scale"),
    [("pga_g", STANDARD_GRAVITY), ("pga_cm_s2", 0.01), ("pgv_cm_s", 0.01), ("sa_0.5s_g", 9.81)],
)
def test_the_header_names_the_measure_and_the_unit(tmp_path, header, scale):
    curve = read_hazard(_write(tmp_path, f"{header},annual_frequency\n1,1e-2\n2,1e-3\n"))
    np.testing.assert_allclose(curve.im, [scale, 2.0 * scale])
    assert curve.period == (0.5 if header.startswith("sa") else None)


@pytest.mark.parametrize(
    ("text", "words"),
    [
        ("pga,annual_frequency\n1,1e-2\n2,1e-3\n", "line 1: the header 'pga,annual_frequency'"),
        ("pga_m_s,annual_frequency\n1,1e-2\n2,1e-3\n", "pga is in m/s^2, not m_s"),
        ("pga_g,rate\n1,1e-2\n2,1e-3\n", "then annual_frequency"),
        (
            "# note\npga_g,annual_frequency\n0.1,1e-2\n0.1,1e-3\n",
            "line 4: intensity 0.1 is not above",
        ),
        (
            "pga_g,annual_frequency\n0.1,1e-2\n0.2,2e-2\n",
            "line 3: annual frequency 0.02 is not below",
        ),
        (
            "pga_g,annual_frequency\n0.1,1e-2\n0.2,0\n",
            "line 3: intensity 0.2 and annual frequency 0",
        ),
        ("pga_g,annual_frequency\n-0.1,1e-2\n0.2,1e-3\n", "line 2: intensity -0.1"),
        ("pga_g,annual_frequency\n0.1;1e-2\n", "line 2: '0.1;1e-2' is not two numbers"),
        ("pga_g,annual_frequency\n0.1,1e-2\n", "1 rows of data"),
    ],
)
def test_a_bad_hazard_file_is_one_error_naming_the_file_and_line(tmp_path, text, words):
    path = _write(tmp_path, text)
    with pytest.raises(InputError) as caught:
        read_hazard(path)
    assert str(path) in str(caught.value) and words in str(caught.value)


def test_a_missing_file_is_an_input_error(tmp_path):
    with pytest.raises(InputError, match="cannot be read"):
        read_hazard(tmp_path / "none.csv")


def test_the_power_law_and_its_checks():
    curve = power_law(1e-4, 3.0, "pga")
    assert annual_frequency(curve, 0.5) == pytest.approx(8e-4)
    assert curve.range == (0.0, math.inf)
    with pytest.raises(InputError, match="k = -1"):
        power_law(1e-4, -1.0, "pga")
    with pytest.raises(InputError, match="period goes with intensity = 'sa'"):
        power_law(1e-4, 3.0, "sa")


def test_in_a_rocking_normalised_measure_the_hazard_is_the_same_curve_rescaled(tmp_path):
    """x' = c x: lambda'(x') = lambda(x' / c), for the table and the power law alike."""
    c = 1.0 / 1.47  # 1 / a_up
    table = read_hazard(EXAMPLE)
    scaled = in_measure(table, "pga_rocking", "pga", c, "-")
    x = np.geomspace(0.2, 5.0, 17)
    np.testing.assert_allclose(annual_frequency(scaled, c * x), annual_frequency(table, x))
    law = power_law(2e-4, 2.5, "pga")
    scaled = in_measure(law, "pga_rocking", "pga", c, "-")
    np.testing.assert_allclose(annual_frequency(scaled, c * x), annual_frequency(law, x))


def test_a_hazard_of_another_measure_or_period_is_refused():
    with pytest.raises(InputError, match="the hazard is of PGA .* and the fragility's intensity"):
        in_measure(read_hazard(EXAMPLE), "pgv_rocking", "pgv", 1.0, "-")
    with pytest.raises(InputError, match=r"Sa\(0.5 s\) and the fragility's of Sa\(1 s\)"):
        in_measure(power_law(1e-4, 2.0, "sa", period=0.5), "sa", "sa", 1.0, "m/s^2", period=1.0)

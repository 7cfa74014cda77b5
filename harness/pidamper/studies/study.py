"""Parametric studies: a grid of FMU parameters and forcing settings, one tidy row per run.

    pidamper study --grid FR=1.5,2,4,5 --grid d=0.05,0.1,0.2 --set theta_dot_0=2.19 --out study.csv

A point is a dict of FMU start values plus two study settings: `Omega_ratio` (the built-in
harmonic at Omega = ratio * w2, when F0 > 0) and `periods` (the horizon of a forced run, in
primary periods; default 20). A point with F0 = 0 is a free-vibration run and gets the
damping ratios (every averaging of measures.DAMPING_AVERAGES); a forced point gets the
amplitude ratio against the same forcing without the damper (mu = 0) at its horizon.

Runs go to a local process pool (default), to a local Dask cluster (--dask) or to a Dask
distributed scheduler (--scheduler tcp://host:port), which receives the FMU file itself: the
packages inside the FMU carry a hash of their sources in their names, so a worker that ran an
older build imports the new one under new names and never runs stale code from its module
cache. Each finished row is appended to the CSV at once, so an interrupted study resumes where
it stopped (rows are keyed by their point).
"""
import argparse
import itertools
import hashlib
import json
import math
import time

from pidamper_physics import Params

from ..running.fmu import find_fmu
from ..running.variants import storeys_of
from ..measures import DAMPING_AVERAGES, damping_ratio, max_abs_theta
from ..running.simulation import resonance
from ..running.stepper import CoreStepper, FmuStepper
from .runner import Table, write_parquet, add_runner_arguments, run_table

SETTINGS = ("Omega_ratio", "periods")
MEASURES = ("damping_printed", "damping_exact", "damping_accumulated", "amplitude_ratio", "max_theta",
            "max_theta_undamped", "impacts", "energy_dissipated", "cpu_s")


def points(grid, fixed=None):
    """The cartesian product of the grid (name -> values), each point completed by `fixed`."""
    names = list(grid)
    out = []
    for combo in itertools.product(*(grid[n] for n in names)):
        point = dict(fixed or {})
        point.update(zip(names, combo))
        out.append(point)
    return out


def key(point):
    """A stable identifier of a point (the resume key)."""
    return hashlib.sha1(json.dumps(point, sort_keys=True).encode()).hexdigest()[:16]


def _start_values(point):
    """FMU start values of a point and its primary's natural frequency w2 [rad/s] (a building's
    first natural frequency when storeys >= 1)."""
    values = {k: v for k, v in point.items() if k not in SETTINGS}
    w2 = resonance(values)
    if values.get("F0", 0.0):
        values["Omega"] = point.get("Omega_ratio", 1.0) * w2
        values.setdefault("theta_dot_0", 0.0)
    return values, w2


def run_point(point, engine="fmu", fmu=None):
    """Measures of one point (see the module doc); `fmu` is the FMU path for engine 'fmu' (None: the
    FMU of the point's model, find_fmu(storeys=...))."""
    values, w2 = _start_values(point)
    if engine == "fmu" and fmu is None:
        fmu = find_fmu(storeys=storeys_of(values))
    period = 2 * math.pi / w2
    make = (lambda v, name="a": FmuStepper(fmu, v, instance_name=name)) if engine == "fmu" else \
        (lambda v, name="a": CoreStepper(v))
    row = {"key": key(point), **point, **{m: math.nan for m in MEASURES}}
    cpu = time.process_time()
    if not values.get("F0", 0.0):
        with make(values) as stepper:
            ratios, _ = damping_ratio(stepper, period)
            row.update({f"damping_{k}": v for k, v in ratios.items()})
            row["impacts"], row["energy_dissipated"] = stepper.get("impacts"), stepper.get("energy_dissipated")
    else:
        horizon = point.get("periods", 20) * period
        with make(values) as damped, make({**values, "mu": 0.0}, "baseline") as bare:
            with_d = max_abs_theta(damped, horizon, period / 50)
            without = max_abs_theta(bare, horizon, period / 50)
            row["impacts"], row["energy_dissipated"] = damped.get("impacts"), damped.get("energy_dissipated")
        row["max_theta"], row["max_theta_undamped"] = abs(with_d.theta), abs(without.theta)
        row["amplitude_ratio"] = abs(with_d.theta) / abs(without.theta)
    row["cpu_s"] = time.process_time() - cpu
    return row


def run_study(grid, fixed=None, out="study.csv", engine="fmu", workers=None, dask=False, scheduler=None,
              fmu=None, parquet=None, progress=True):
    """Run every point not yet in `out`; returns the full table as a list of dicts."""
    todo_all = points(grid, fixed)
    columns = ["key"] + list(dict.fromkeys(k for p in todo_all for k in p)) + list(MEASURES)
    table = Table(out, columns)
    path = str(fmu) if engine == "fmu" and fmu is not None else None
    if engine == "fmu" and fmu is None:  # each point runs its model's FMU: each built once, before the workers start
        for n in sorted({storeys_of(_start_values(p)[0]) for p in todo_all}):
            find_fmu(storeys=n)
    run_table(run_point, todo_all, [key(p) for p in todo_all], table, engine, path, workers, dask, scheduler,
              progress, "study")
    rows = [table.done[key(p)] for p in todo_all]
    if parquet:
        write_parquet(out, parquet)
    return rows


def frequency_response(base, ratios, periods=200, settle=150, engine="core", fmu=None):
    """Steady peak amplitude |theta| against Omega / w2, with the damper: the largest |theta| over
    the last (periods - settle) periods of a run from rest; without it: the amplitude of the
    undamped steady state F0 / (M L2 |w2^2 - Omega^2|) (infinite at resonance)."""
    out = []
    values, w2 = _start_values({**base, "Omega_ratio": 1.0})
    p = Params.from_variables(values)
    M, L2, F0 = p.M, p.L2, values["F0"]
    period = 2 * math.pi / w2
    for ratio in ratios:
        v = {**values, "Omega": ratio * w2}
        stepper = CoreStepper(v) if engine == "core" else FmuStepper(fmu, v)
        with stepper:
            stepper.advance(settle * period)
            peak = abs(max_abs_theta(stepper, periods * period, period / 50).theta)
        gap = abs(w2 * w2 - (ratio * w2) ** 2)
        out.append({"Omega_ratio": ratio, "peak_theta_damper": peak,
                    "peak_theta_no_damper": F0 / (M * L2 * gap) if gap else math.inf})
    return out


def _parse_values(text):
    name, sep, values = text.partition("=")
    if not sep or not values:
        raise argparse.ArgumentTypeError(f"{text!r} is not allowed: use NAME=V1,V2,...")
    try:
        return name.strip(), [int(v) if name.strip() == "contact_form" else float(v) for v in values.split(",")]
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not allowed: the values must be numbers") from None


def main(argv=None):
    parser = argparse.ArgumentParser(prog="pidamper study", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--grid", action="append", type=_parse_values, default=[], metavar="NAME=V1,V2,...",
                        help="a grid axis: an FMU parameter, Omega_ratio or periods (repeatable)")
    parser.add_argument("--set", action="append", type=_parse_values, default=[], metavar="NAME=V",
                        help="a fixed value for every point (repeatable)")
    parser.add_argument("--out", default="study.csv", help="the table (CSV; resumed if it exists)")
    parser.add_argument("--parquet", help="also write the table as Parquet")
    add_runner_arguments(parser)
    args = parser.parse_args(argv)
    if not args.grid:
        parser.error("at least one --grid NAME=V1,V2,... is needed")
    fixed = {name: values[0] for name, values in args.set}
    t0 = time.perf_counter()
    rows = run_study(dict(args.grid), fixed, args.out, args.engine, args.workers, args.dask, args.scheduler,
                     args.fmu, args.parquet)
    print(f"{len(rows)} runs in {args.out} ({time.perf_counter() - t0:.1f} s wall); measures: "
          f"{', '.join(DAMPING_AVERAGES)} damping averagings, amplitude_ratio")
    return 0

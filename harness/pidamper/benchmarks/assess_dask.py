"""The shipped yielding study's runs on a real Dask scheduler: a `dask scheduler` process and 1, then 2
`dask worker` processes (one thread each) started here, a subset of the study's records run through
them (`pidamper assess --scheduler ADDRESS`, the FMU shipped to the workers once), the wall time
measured and extrapolated to the whole study on 8 and 32 workers; writes OUT/scaling.md.

    python -m pidamper.benchmarks.assess_dask [--study studies/yielding-three-storey.toml]
        [--events 4] [--out docs/assessment]

A study whose stripes are read off its IDA curves ([ida] stripes = "interpolate") runs its IDA tasks
(one per record and configuration, hunt and fill); any other its stripe tasks.
"""
import argparse
import json
import os
import platform
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from ..assessment import assess
from ..machine import cpu_model


def subset_study(study_path, events, folder):
    """A copy of the study (in `folder`, with its performance model and hazard curve) whose FEMA P-695
    suite keeps its first `events` record IDs (both components each); its path."""
    study = assess.load(study_path)
    keep = sorted({r.meta["record_id"] for r in study.records})[:events]
    line = f'set = "{study.suite["set"]}"'
    text = Path(study_path).read_text()
    if line not in text:
        raise ValueError(f"{study_path}: its [suite] must be a FEMA P-695 set ({line!r} not found)")
    (folder / "subset.toml").write_text(text.replace(line, f"{line}\nrecords = {json.dumps(keep)}", 1))
    for name in (study.losses.get("components"), study.hazard.get("curve")):
        if name:
            (folder / name).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy(Path(study_path).parent / name, folder / name)
    return folder / "subset.toml"


class Cluster:
    """A `dask scheduler` and n `dask worker` processes (one thread each) on this machine."""

    def __init__(self, workers, folder):
        self.file = Path(folder) / "scheduler.json"
        exe = Path(sys.executable).parent
        self.scheduler = subprocess.Popen([str(exe / "dask"), "scheduler", "--scheduler-file", str(self.file),
                                           "--port", "0", "--no-dashboard"], stdout=subprocess.DEVNULL,
                                          stderr=subprocess.DEVNULL)
        for _ in range(300):
            if self.file.exists() and self.file.stat().st_size:
                break
            time.sleep(0.1)
        self.address = json.loads(self.file.read_text())["address"]
        self.workers = [subprocess.Popen([str(exe / "dask"), "worker", self.address, "--nworkers", "1",
                                          "--nthreads", "1", "--no-dashboard"], stdout=subprocess.DEVNULL,
                                         stderr=subprocess.DEVNULL) for _ in range(workers)]
        from dask.distributed import Client
        with Client(self.address) as client:
            client.wait_for_workers(workers, timeout=120)

    def close(self):
        for process in self.workers + [self.scheduler]:
            process.terminate()
        for process in self.workers + [self.scheduler]:
            process.wait(timeout=60)


def stripes_run(study):
    return study.ida.get("stripes") != "interpolate"


def run_cpu(study, out, scheduler):
    """Run the study's tasks (its IDA, then its stripes unless they are read off the IDA curves)
    into OUT; the CPU of each run [s] (a stripe the IDA ran is not run again)."""
    cpu, traces = [], None
    if study.ida:
        traces = assess.run_ida(study, out, scheduler=scheduler, progress=False)
        cpu += [r["cpu_s"] / len(r["runs"]) for r in traces for _ in r["runs"]]
    if stripes_run(study):
        rows = assess.run_study(study, out, scheduler=scheduler, progress=False, traces=traces)
        cpu += [r["cpu_s"] for r in rows if np.isfinite(r["cpu_s"])]
    return cpu


def shipped_cpu(study, out):
    """(The CPU of each run, the CPU of its longest task) of the shipped study's journals in OUT
    (ida.csv: a task is one record's IDA; runs.csv: one stripe run) [s]."""
    import csv

    journals = (["ida.csv"] if study.ida else []) + (["runs.csv"] if stripes_run(study) else [])
    cpu, longest = [], 0.0
    for name in journals:
        journal = Path(out) / name
        if not journal.exists():
            raise SystemExit(f"{journal} is missing: run the study first (pidamper assess {study.source} --out {out})")
        with journal.open(newline="") as handle:
            rows = list(csv.DictReader(handle))
        longest = max([longest] + [float(r["cpu_s"]) for r in rows])
        if name == "ida.csv":
            cpu += [float(r["cpu_s"]) / len(json.loads(r["runs"])) for r in rows for _ in json.loads(r["runs"])]
        else:
            cpu += [float(r["cpu_s"]) for r in rows]
    return cpu, longest


def timed(study, out, workers, folder):
    """(wall of the runs [s], CPU per run [s], runs) on a fresh cluster of `workers` Dask workers."""
    cluster = Cluster(workers, folder)
    try:
        for name in ("runs.csv", "runs.parquet", "ida.csv"):
            (Path(out) / name).unlink(missing_ok=True)
        t0 = time.perf_counter()
        cpu = run_cpu(assess.load(study), out, cluster.address)
        wall = time.perf_counter() - t0
    finally:
        cluster.close()
    return wall, float(np.mean(cpu)), len(cpu)


def report(study, events, subset_runs, whole_runs, whole_cpu, results, kind, longest):
    (w1, c1, n), (w2, c2, _) = results[1], results[2]
    efficiency = w1 / (2 * w2)
    per_run = whole_cpu * (w1 / n) / c1  # the whole study's CPU per run, with the subset's wall / CPU
    floor = longest * (w1 / n) / c1  # no worker count ends before the longest task
    rows = "\n".join(f"| {N} | {max(whole_runs * per_run / (N * (efficiency if N > 1 else 1.0)), floor) / 60:.1f} |"
                      for N in (1, 2, 8, 32))
    return f"""# Cost of the yielding study on a Dask scheduler

The runs of `{study}` restricted to its first {events} FEMA P-695 events ({subset_runs} runs: both
components x configurations x {kind}) on a real Dask scheduler: a `dask scheduler` process and
`dask worker` processes (one thread each) on this machine, the FMU shipped to them once. Measured on
{platform.machine()} ({cpu_model()}, {os.cpu_count()} cores), Python {platform.python_version()}, by
`python -m pidamper.benchmarks.assess_dask` (this page is its output).

| Dask workers | wall of the runs [s] | CPU per run [s] (mean) | wall per run [s] |
|---:|---:|---:|---:|
| 1 | {w1:.1f} | {c1:.3f} | {w1 / n:.3f} |
| 2 | {w2:.1f} | {c2:.3f} | {w2 / n:.3f} |

Parallel efficiency on 2 workers: {efficiency:.2f} (wall on 1 / (2 x wall on 2)).

**Extrapolation (not measured beyond 2 workers).** The whole study has {whole_runs} runs of
{whole_cpu:.2f} s CPU each on average (its journal: its records are longer than the subset's, some
sampled at 0.005 or 0.0025 s), so {per_run:.2f} s of wall per run on one worker (the subset's wall
per CPU second); with the measured efficiency (assumed to hold on more workers, the FMU shipped once
per worker), and never below the study's longest task ({floor:.0f} s of wall: one worker runs it
alone):

| workers N | runs of the whole study, T(N) [min] |
|---:|---:|
{rows}

The analysis after the runs (fits, collapse margin, losses with pelicun, page) takes a few minutes
more in the main process (the study's page gives its time by stage).
"""


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python -m pidamper.benchmarks.assess_dask", description=__doc__)
    parser.add_argument("--study", default="studies/yielding-three-storey.toml")
    parser.add_argument("--events", type=int, default=4, help="FEMA P-695 events kept (2 components each)")
    parser.add_argument("--out", default="docs/assessment", help="where scaling.md goes")
    args = parser.parse_args(argv)
    folder = Path(tempfile.mkdtemp(prefix="pidamper_dask_"))
    try:
        subset = subset_study(args.study, args.events, folder)
        study = assess.load(args.study)
        cpu, longest = shipped_cpu(study, args.out)
        kind = " and ".join((["the runs of each IDA (hunt and fill)"] if study.ida else [])
                            + (["the stripes not on an IDA run"] if stripes_run(study) else []))
        results = {n: timed(subset, folder / f"out{n}", n, folder) for n in (1, 2)}
        text = report(args.study, args.events, results[1][2], len(cpu), float(np.mean(cpu)), results, kind, longest)
    finally:
        shutil.rmtree(folder, ignore_errors=True)
    (Path(args.out) / "scaling.md").write_text(text)
    print(text)


if __name__ == "__main__":
    main()

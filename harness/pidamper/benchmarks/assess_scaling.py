"""Cost of an assessment: the shipped study run from scratch on 1 and on 2 local workers, the CPU per
run, and the wall time a larger study would take on N workers.  The 2-worker run writes the study's
page (docs/assessment-elastic/README.md and its figures); this module adds docs/assessment-elastic/scaling.md.

    python -m pidamper.benchmarks.assess_scaling [--study studies/three-storey.toml] [--out docs/assessment-elastic]
"""
import argparse
import os
import platform
import shutil
import tempfile
import time
from pathlib import Path

import numpy as np

from ..assessment import assess
from ..machine import cpu_model

#: the larger study the figures are extrapolated to (a FEMA P-695-size far-field set: 22 pairs = 44
#: records, 20 stripes, with and without the damper)
LARGE = {"records": 44, "levels": 20, "configurations": 2}


def timed(study, out, workers):
    """(wall [s], CPU per run [s], runs) of a study run from scratch on `workers` processes."""
    for name in ("runs.csv", "runs.parquet"):
        (Path(out) / name).unlink(missing_ok=True)
    command = f"pidamper assess {study} --out {out} --workers {workers}"
    t0 = time.perf_counter()
    rows, _, _ = assess.assess(study, out, workers=workers, progress=False, command=command)
    wall = time.perf_counter() - t0
    return wall, float(np.mean([r["cpu_s"] for r in rows])), len(rows)


def report(study, results):
    (w1, c1, n), (w2, c2, _) = results[1], results[2]
    per_run = w1 / n  # wall per run on one worker: CPU of the run plus the pool's share
    efficiency = w1 / (2 * w2)
    large = LARGE["records"] * LARGE["levels"] * LARGE["configurations"]
    rows = "\n".join(f"| {N} | {large * per_run / (N * (efficiency if N > 1 else 1.0)) / 60:.1f} |"
                     for N in (1, 2, 8, 32, 128))
    return f"""# Cost of the shipped assessment

`{study}` run from scratch ({n} runs: records x stripes x configurations), the FMU through fmpy on
a local process pool. Measured on {platform.machine()} ({cpu_model()}, {os.cpu_count()} cores), Python
{platform.python_version()}, by `python -m pidamper.benchmarks.assess_scaling` (this page is its output).

| workers | wall [s] | CPU per run [s] (mean) | wall per run [s] |
|---:|---:|---:|---:|
| 1 | {w1:.1f} | {c1:.3f} | {w1 / n:.3f} |
| 2 | {w2:.1f} | {c2:.3f} | {w2 / n:.3f} |

Parallel efficiency on 2 workers: {efficiency:.2f} (wall on 1 / (2 x wall on 2)); the figures
and the page take a few seconds more (bootstrap, plots).

**Extrapolation.** The runs are independent and about equally costly, so a study of R records,
L stripes and C configurations takes about

    T(N) = R L C t1 / (N e)

on N workers, t1 = {per_run:.3f} s the wall per run on one worker of this machine and e the
parallel efficiency ({efficiency:.2f} measured at N = 2; with Dask on more machines, e also pays
for shipping the FMU once per worker). For R = {LARGE['records']}, L = {LARGE['levels']}, C =
{LARGE['configurations']} ({large} runs):

| workers N | T(N) [min] |
|---:|---:|
{rows}

(N > 2 assumes e stays at its 2-worker value; the cost per run grows with the record's length, the
communication step's inverse and the impacts per run.)
"""


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python -m pidamper.benchmarks.assess_scaling", description=__doc__)
    parser.add_argument("--study", default="studies/three-storey.toml")
    parser.add_argument("--out", default="docs/assessment-elastic", help="the 2-worker run's page folder")
    args = parser.parse_args(argv)
    results = {}
    scratch = Path(tempfile.mkdtemp(prefix="pidamper_assess_"))
    try:
        results[1] = timed(args.study, scratch, 1)
    finally:
        shutil.rmtree(scratch, ignore_errors=True)
    Path(args.out).mkdir(parents=True, exist_ok=True)
    results[2] = timed(args.study, args.out, 2)
    text = report(args.study, results)
    (Path(args.out) / "scaling.md").write_text(text)
    print(text)


if __name__ == "__main__":
    main()

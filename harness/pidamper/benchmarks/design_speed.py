"""Speed of a design search: the study's first batches run from scratch on a local process pool and
on a local Dask cluster, each with the same number of workers; designs and runs per second.  The
two give the same trials (tests/test_design.py), so only the time differs.  Writes OUT/speed.md,
which the study's page links.

    python -m pidamper.benchmarks.design_speed [--study studies/design-la9.toml] [--batches 2]
                                               [--workers 2] [--out docs/design/la9]
"""
import argparse
import os
import platform
import tempfile
import time
from pathlib import Path

from ..design import design_file, search
from ..machine import cpu_model


def timed(design, trials, workers, dask):
    """(wall [s], runs) of the first `trials` designs from scratch."""
    with tempfile.TemporaryDirectory() as out:
        t0 = time.perf_counter()
        search.search(design, out, workers=workers, dask=dask, trials=trials)
        wall = time.perf_counter() - t0
        runs = sum(1 for _ in (Path(out) / "runs.csv").open()) - 1
    return wall, runs


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python -m pidamper.benchmarks.design_speed", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--study", default="studies/design-la9.toml")
    parser.add_argument("--batches", type=int, default=2)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--out", default="docs/design/la9")
    args = parser.parse_args(argv)
    design = design_file.load(args.study)
    trials = args.batches * design.batch
    rows = []
    for name, dask in (("process pool", False), ("Dask LocalCluster", True)):
        wall, runs = timed(design, trials, args.workers, dask)
        rows.append(f"| {name} | {args.workers} | {trials} | {runs} | {wall:.1f} | {trials / wall:.3f} | "
                    f"{runs / wall:.2f} |")
        print(rows[-1], flush=True)
    text = f"""# Speed of the design search

`{args.study}`: its first {args.batches} batches ({trials} designs, each with the bare building's runs
of the first batch) from scratch, on {platform.machine()} ({cpu_model()}, {os.cpu_count()} cores),
Python {platform.python_version()}; written by
`python -m pidamper.benchmarks.design_speed --study {args.study} --batches {args.batches} --workers {args.workers} --out {args.out}`.
The process pool and Dask give the same trials; a Dask cluster starts its workers and ships the
FMU once per search.

| executor | workers | designs | runs | wall [s] | designs / s | runs / s |
|---|---:|---:|---:|---:|---:|---:|
""" + "\n".join(rows) + "\n"
    Path(args.out).mkdir(parents=True, exist_ok=True)
    (Path(args.out) / "speed.md").write_text(text)
    print(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

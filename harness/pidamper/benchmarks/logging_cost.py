"""Cost of logging a long run: the same run without logs, with MCAP, with MCAP and .rrd.

    python -m pidamper.benchmarks.logging_cost [--steps 100000] [--repeats 2]

Prints wall and process CPU time (minimum over repeats) and the file sizes.
"""
import argparse
import math
import platform
import tempfile
import time
from pathlib import Path

from .. import forcing
from ..running.fmu import find_fmu
from ..runlog.logged_run import run_logged
from ..running.simulation import run

W2 = math.sqrt(9.81)
PERIOD = 2 * math.pi / W2
SCENE = {"mu": 0.02, "theta_dot_0": 0.0}  # resonance, the paper's forced case


def timed(fn):
    wall, cpu = time.perf_counter(), time.process_time()
    out = fn()
    return time.perf_counter() - wall, time.process_time() - cpu, out


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--steps", type=int, default=100_000)
    parser.add_argument("--repeats", type=int, default=2)
    args = parser.parse_args(argv)
    h = PERIOD / 200
    stop = args.steps * h
    drive = forcing.harmonic(0.0981, W2, math.pi / 2)
    fmu = find_fmu()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        variants = (
            ("no logging", lambda: run(SCENE, drive, stop, h, fmu=fmu), ()),
            ("MCAP", lambda: run_logged(SCENE, drive, stop, h, out_dir=tmp, name="m", fmu=fmu, rrd=False), ("m.mcap",)),
            ("MCAP + .rrd", lambda: run_logged(SCENE, drive, stop, h, out_dir=tmp, name="b", fmu=fmu),
             ("b.mcap", "b.rrd")),
        )
        for name, fn, files in variants:
            best = (math.inf, math.inf)
            for _ in range(args.repeats):
                wall, cpu, out = timed(fn)
                best = (min(best[0], wall), min(best[1], cpu))
            sizes = {f: (Path(tmp) / f).stat().st_size for f in files}
            rows.append((name, *best, sizes))
    base_wall = rows[0][1]
    print(f"{args.steps} steps of T/200 at resonance (mu 0.02, F0 = 0.01 M g), fmpy.simulate_fmu, "
          f"Python {platform.python_version()} on {platform.machine()}, min of {args.repeats} runs")
    print(f"{'logging':14s} {'wall s':>8s} {'CPU s':>8s} {'x no log':>9s}  files")
    for name, wall, cpu, sizes in rows:
        files = ", ".join(f"{f} {s / 1e6:.2f} MB" for f, s in sizes.items())
        print(f"{name:14s} {wall:8.2f} {cpu:8.2f} {wall / base_wall:9.2f}  {files}")


if __name__ == "__main__":
    main()

"""Cost per communication step of the damper FMU next to a trivial pythonfmu FMU, same run.

    python -m pidamper.benchmarks.step_cost [--steps N] [--repeats R]

Both FMUs run under fmpy.simulate_fmu with the same step count; the figure is
process CPU time per step, the minimum over repeats.
"""
import argparse
import math
import platform
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import fmpy

from ..fmu import find_fmu

W2 = math.sqrt(9.81)
PERIOD = 2 * math.pi / W2

CASES = (
    ("damper, no contact (d = 10 m)", {"d": 10.0, "theta_dot_0": 0.5}),
    ("damper, no contact, validity check off (angle_limit = 0)", {"d": 10.0, "theta_dot_0": 0.5, "angle_limit": 0.0}),
    ("damper, free decay (FR 5, d 0.1 m, e 0.2, A0 = 0.7 rad)", {"theta_dot_0": 0.7 * W2}),
    ("damper, free decay, validity check off", {"theta_dot_0": 0.7 * W2, "angle_limit": 0.0}),
    ("damper, resonance (mu 0.02, F0 = 0.01 M g)", {"mu": 0.02, "theta_dot_0": 0.0, "F0": 0.0981, "Omega": W2,
                                                    "phi": math.pi / 2}),
)


def build_trivial(out_dir):
    script = Path(__file__).with_name("trivial_model.py")
    cmd = [sys.executable, "-m", "pythonfmu", "build", "-f", str(script), "-d", str(out_dir), "--no-external-tool"]
    subprocess.run(cmd, check=True, capture_output=True)
    return Path(out_dir) / "TrivialPythonFmu.fmu"


def cpu_per_step(fmu, steps, h, start_values, outputs, repeats):
    best = math.inf
    impacts = None
    for _ in range(repeats):
        t0 = time.process_time()
        res = fmpy.simulate_fmu(str(fmu), stop_time=steps * h, output_interval=h, start_values=start_values,
                                output=outputs)
        best = min(best, (time.process_time() - t0) / steps)
        if "impacts" in res.dtype.names:
            impacts = int(res["impacts"][-1])
    return best, impacts


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--steps", type=int, default=20000)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--interval", type=float, default=PERIOD / 200, help="communication step [s]")
    args = parser.parse_args(argv)
    damper = find_fmu()
    with tempfile.TemporaryDirectory() as tmp:
        trivial = build_trivial(tmp)
        base, _ = cpu_per_step(trivial, args.steps, args.interval, {}, ["y1", "y2", "y3", "n"], args.repeats)
        rows = [("trivial pythonfmu FMU (3 Real + 1 Integer outputs)", base, None)]
        for name, values in CASES:
            cost, impacts = cpu_per_step(damper, args.steps, args.interval, values,
                                         ["theta", "theta_dot", "impacts", "energy"], args.repeats)
            rows.append((name, cost, impacts))
    print(f"fmpy {fmpy.__version__}, Python {platform.python_version()}, {platform.machine()}, "
          f"{args.steps} steps of {args.interval:.6g} s, min of {args.repeats} runs (process CPU time)")
    print(f"{'FMU':60s} {'us/step':>9s} {'x trivial':>9s} {'impacts':>8s}")
    for name, cost, impacts in rows:
        print(f"{name:60s} {cost * 1e6:9.1f} {cost / base:9.2f} {'' if impacts is None else impacts:>8}")


if __name__ == "__main__":
    main()

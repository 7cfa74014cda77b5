"""Worst wall time of one fmi2DoStep at the edges of the accepted ranges, as a host sees it.

    python -m pidamper.benchmarks.worst_step [--out docs/bench]

Each row steps the FMU (fmpy's FMU2Slave, one instance, every output read after every step)
through N steps of h and reports the slowest fmi2DoStep (wall clock, time.perf_counter) and
whether the FMU accepted the steps or refused one by its work cap.  The cases sit near the
cap: the fastest motion the cap admits for a 0.01 s step, dense impacts, each level.
Writes OUT/worst-step.md and prints it.
"""
import argparse
import platform
import time
from pathlib import Path

from fmpy.fmi1 import FMICallException

from ..running.fmu import find_fmu
from ..running.instance import FmuInstance

#: (label, parameters, h [s], steps)
CASES = [
    ("default, 0.01 s steps", {}, 0.01, 200),
    ("FR = 1.9e6: 9500 periods per 0.01 s step (linear)", {"FR": 1.9e6}, 0.01, 5),
    ("FR = 1.9e6, damped", {"FR": 1.9e6, "fidelity": 1, "zeta_s": 0.01}, 0.01, 5),
    ("FR = 1.9e6, coupled", {"FR": 1.9e6, "fidelity": 2, "zeta_s": 0.01}, 0.01, 5),
    ("FR = 1e9: refused by the cap", {"FR": 1e9}, 0.01, 5),
    ("dense impacts: e = 1, d = 1e-4 m, FR = 1e5", {"e": 1.0, "d": 1e-4, "FR": 1e5, "theta_dot_0": 3.0}, 0.01, 20),
    ("nonlinear, FR = 1e3", {"fidelity": 3, "FR": 1e3}, 0.01, 10),
    ("nonlinear, FR = 1e4", {"fidelity": 3, "FR": 1e4}, 0.01, 10),
    ("one step of 1e5 s: refused by the cap", {}, 1e5, 1),
]


def worst_step(fmu, params, h, steps):
    """(worst doStep seconds, steps accepted, refused?)"""
    slave = FmuInstance(fmu, params, instance_name="worst")
    outputs = [v for v in slave.vars.values() if v.causality == "output"]
    reals = [v.valueReference for v in outputs if v.type == "Real"]
    ints = [v.valueReference for v in outputs if v.type == "Integer"]
    worst, done, refused = 0.0, 0, False
    for k in range(steps):
        t0 = time.perf_counter()
        try:
            slave.do_step(k * h, h)
        except FMICallException:
            worst, refused = max(worst, time.perf_counter() - t0), True
            break
        worst = max(worst, time.perf_counter() - t0)
        slave.fmu.getReal(reals)
        slave.fmu.getInteger(ints)
        done += 1
    slave.close()
    return worst, done, refused


def report(fmu):
    lines = ["# Worst step time at the edges", "",
             f"Machine: the 2-core {platform.machine()} development machine (AMD EPYC), CPython {platform.python_version()}; "
             "command: `python -m pidamper.benchmarks.worst_step`.", "",
             "| case | h [s] | steps accepted | worst fmi2DoStep [ms] | outcome |", "|---|---|---|---|---|"]
    for label, params, h, steps in CASES:
        worst, done, refused = worst_step(fmu, params, h, steps)
        lines.append(f"| {label} | {h:g} | {done} of {steps} | {worst * 1e3:.1f} | "
                     f"{'refused (fmi2Error, message names the cap)' if refused else 'answered'} |")
    return "\n".join(lines) + "\n"


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", default="docs/bench")
    parser.add_argument("--fmu", default=None)
    args = parser.parse_args(argv)
    text = report(find_fmu(args.fmu))
    Path(args.out).mkdir(parents=True, exist_ok=True)
    (Path(args.out) / "worst-step.md").write_text(text)
    print(text)


if __name__ == "__main__":
    main()

"""Step cost of FMU models, a base revision's build against this tree's (issue 24: the elastic
building's step no slower than before).

    python tools/fmu_step_compare.py --base REV [--model ShearBuilding3 ...] [--host fmpy|native] [--rest]
                                     [--runs 5] [--steps 20000]

Both trees build the models with their own builder; each host drives each build as hosts do,
fmi2DoStep of 0.01 s then every output and local variable read:
- fmpy (default): fmpy's FMU2Slave sets the input a_g to a Kanai-Tajimi-like random ground
  acceleration (fixed seed) before each step, or leaves every input at zero with --rest, and reads
  the Real outputs and locals in one fmi2GetReal;
- native: the C host of pidamper.benchmarks (benchmarks/native/every_output_host.c, compiled here)
  sets a_g = 3 sin(6 t) m/s2 before each step, or no input with --rest (every input zero: a building
  at rest), and reads every output and local with its own fmi2GetReal / fmi2GetInteger call; its
  figure is the CPU time of its step loop.
The two builds' runs alternate in fresh processes; each figure is the median process CPU time per
step of `--runs` runs.
"""
import argparse
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

from pidamper.machine import describe

ROOT = Path(__file__).resolve().parents[1]

RUNNER = """
import sys, time
import numpy as np
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave
path, steps = sys.argv[1], int(sys.argv[2])
md = read_model_description(path)
unzipdir = extract(path)
fmu = FMU2Slave(guid=md.guid, unzipDirectory=unzipdir, modelIdentifier=md.coSimulation.modelIdentifier,
                instanceName="bench")
fmu.instantiate()
fmu.setupExperiment(startTime=0.0)
fmu.enterInitializationMode()
fmu.exitInitializationMode()
vr = {v.name: v.valueReference for v in md.modelVariables}
reads = [v.valueReference for v in md.modelVariables if v.causality in ("output", "local") and v.type == "Real"]
ag = np.zeros(steps) if sys.argv[3] == "rest" else np.random.default_rng(1).normal(0.0, 3.0, steps)
t0 = time.process_time()
for k in range(steps):
    fmu.setReal([vr["a_g"]], [float(ag[k])])
    fmu.doStep(currentCommunicationPoint=k * 0.01, communicationStepSize=0.01)
    fmu.getReal(reads)
print((time.process_time() - t0) / steps * 1e6)
fmu.terminate()
fmu.freeInstance()
"""


def build(tree, out, models):
    subprocess.run([sys.executable, "-m", "build_fmu", "--out", str(out), "--model", *models], cwd=tree, check=True,
                   capture_output=True, env={"PYTHONPATH": str(tree), "PATH": "/usr/bin:/bin"})
    return [out / f"{model}.fmu" for model in models]


def one_run(fmu, steps, rest=False):
    out = subprocess.run([sys.executable, "-c", RUNNER, str(fmu), str(steps), "rest" if rest else "input"],
                         capture_output=True, text=True, check=True).stdout.split()
    return float(out[-1])


class NativeHost:
    """The every-output C host, compiled once; run(fmu, steps) -> CPU us per step of its loop."""

    def __init__(self, tmp):
        from pidamper.benchmarks.floor import build_every_output_host

        self.exe = build_every_output_host(tmp)
        self.tmp = Path(tmp)
        self.unzipped = {}

    def run(self, fmu, steps, rest=True):
        """rest: no input set; else the ground acceleration a_g = 3 sin(6 t) m/s2 set before each step
        (tools/speed_compare.py's building input)."""
        import fmpy

        if fmu not in self.unzipped:
            md = fmpy.read_model_description(str(fmu))
            where = fmpy.extract(str(fmu), unzipdir=str(self.tmp / f"x{len(self.unzipped)}"))
            reads = [f"{v.type[0]}:{v.valueReference}" for v in md.modelVariables
                     if v.causality in ("output", "local")]
            a_g = [v.valueReference for v in md.modelVariables if v.name == "a_g"]
            self.unzipped[fmu] = ([where, md.coSimulation.modelIdentifier, md.guid, str(steps), "0.01"] + reads,
                                  [f"U:{vr}:3:6" for vr in a_g])
        args, drive = self.unzipped[fmu]
        env = {"PATH": "/usr/local/bin:/usr/bin:/bin", "HOME": os.environ.get("HOME", "/tmp"), "LANG": "C.UTF-8"}
        done = subprocess.run([str(self.exe)] + args + ([] if rest else drive), capture_output=True, text=True,
                              env=env, check=True, timeout=1800)
        return float(done.stdout.split()[0])


def compare(olds, news, models, host, rest, runs, steps):
    """[(model, base us/step, this tree's us/step)] of the base's FMUs `olds` and this tree's `news`
    (build()), the host ("fmpy" or "native") running the two builds alternately, medians of `runs`."""
    with tempfile.TemporaryDirectory() as tmp:
        run = NativeHost(tmp).run if host == "native" else one_run
        rows = []
        for model, old_fmu, new_fmu in zip(models, olds, news):
            old, new = [], []
            for _ in range(runs):
                old.append(run(old_fmu, steps, rest))
                new.append(run(new_fmu, steps, rest))
            rows.append((model, statistics.median(old), statistics.median(new)))
        return rows


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--base", required=True)
    parser.add_argument("--model", nargs="+", default=["ShearBuilding3"])
    parser.add_argument("--host", choices=("fmpy", "native"), default="fmpy")
    parser.add_argument("--rest", action="store_true", help="every input zero (the native host sets none)")
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--steps", type=int, default=20000)
    args = parser.parse_args(argv)
    rest = args.rest
    with tempfile.TemporaryDirectory() as tmp:
        base = Path(tmp) / "base"
        subprocess.run(["git", "-C", str(ROOT), "worktree", "add", "--detach", "-q", str(base), args.base], check=True)
        try:
            olds, news = build(base, Path(tmp) / "old", args.model), build(ROOT, Path(tmp) / "new", args.model)
            rows = compare(olds, news, args.model, args.host, rest, args.runs, args.steps)
        finally:
            subprocess.run(["git", "-C", str(ROOT), "worktree", "remove", "--force", str(base)], check=True)
    what = ("the native C host, " + ("no input set (at rest)" if rest else "a_g = 3 sin(6 t)") +
            ", every output and local read one call each" if args.host == "native" else
            "fmpy FMU2Slave, " + ("every input zero (at rest)" if rest else "a_g random") +
            ", every Real output and local read each step")
    print(f"Machine: {describe('fmpy')}; {what}; {args.steps} steps of 0.01 s, median of {args.runs} interleaved "
          "runs, process CPU time")
    print("| model | base us/step | new us/step | new / base |\n|---|---:|---:|---:|")
    for model, mo, mn in rows:
        print(f"| {model} | {mo:.2f} | {mn:.2f} | {mn / mo:.3f} |")


if __name__ == "__main__":
    main()

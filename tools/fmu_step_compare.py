"""Step cost of one FMU model, a base revision's build against this tree's (issue 24: the elastic
building's step no slower than before).

    python tools/fmu_step_compare.py --base REV [--model ShearBuilding3] [--runs 5] [--steps 20000]

Both trees build the model with their own builder; fmpy's FMU2Slave drives each build as a host
does: set every input, fmi2DoStep of 0.01 s, read every output and local variable, under a
Kanai-Tajimi-like random ground acceleration (fixed seed).  The two builds' runs alternate in fresh
processes; each figure is the median process CPU time per step of `--runs` runs.
"""
import argparse
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
ag = np.random.default_rng(1).normal(0.0, 3.0, steps)
t0 = time.process_time()
for k in range(steps):
    fmu.setReal([vr["a_g"]], [float(ag[k])])
    fmu.doStep(currentCommunicationPoint=k * 0.01, communicationStepSize=0.01)
    fmu.getReal(reads)
print((time.process_time() - t0) / steps * 1e6)
fmu.terminate()
fmu.freeInstance()
"""


def build(tree, out, model):
    subprocess.run([sys.executable, "-m", "build_fmu", "--out", str(out), "--model", model], cwd=tree, check=True,
                   capture_output=True, env={"PYTHONPATH": str(tree), "PATH": "/usr/bin:/bin"})
    return out / f"{model}.fmu"


def one_run(fmu, steps):
    out = subprocess.run([sys.executable, "-c", RUNNER, str(fmu), str(steps)], capture_output=True, text=True,
                         check=True).stdout.split()
    return float(out[-1])


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--base", required=True)
    parser.add_argument("--model", default="ShearBuilding3")
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--steps", type=int, default=20000)
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory() as tmp:
        base = Path(tmp) / "base"
        subprocess.run(["git", "-C", str(ROOT), "worktree", "add", "--detach", "-q", str(base), args.base], check=True)
        try:
            old_fmu = build(base, Path(tmp) / "old", args.model)
            new_fmu = build(ROOT, Path(tmp) / "new", args.model)
            old, new = [], []
            for _ in range(args.runs):
                old.append(one_run(old_fmu, args.steps))
                new.append(one_run(new_fmu, args.steps))
        finally:
            subprocess.run(["git", "-C", str(ROOT), "worktree", "remove", "--force", str(base)], check=True)
    mo, mn = statistics.median(old), statistics.median(new)
    print(f"Machine: {describe('fmpy')}; {args.model}, {args.steps} steps of 0.01 s, every output and local read "
          f"each step, median of {args.runs} interleaved runs, process CPU time")
    print(f"| model | base us/step | new us/step | new / base |\n|---|---:|---:|---:|\n"
          f"| {args.model} | {mo:.2f} | {mn:.2f} | {mn / mo:.3f} |")


if __name__ == "__main__":
    main()

"""CPU of one assessment run (a record scaled to an intensity, through the building FMU, as `pidamper
assess` runs it), a base revision's tree against this one, each configuration of a study.

    python tools/assess_run_compare.py --base REV [--study studies/yielding-three-storey.toml]
        [--record DUZCE/BOL090] [--im 1.0] [--runs 5]

Each run is a fresh process importing one tree (harness and physics, compiled where that tree is:
the base is compiled in its worktree first) and calling assessment.demands.run_demands on the
study's record scaled to `--im` (the study's intensity measure, g) for each configuration; the two
trees alternate and each figure is the median process CPU time of `--runs` runs (the FMU's build
and first load excluded: one run per tree first).  The demands must agree between the trees.
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

RUNNER = """
import json, sys, time
import numpy as np
from pidamper.assessment import assess, demands
study = assess.load(sys.argv[1])
out = {}
for task in assess.ida_tasks(study):
    if task["record"] != sys.argv[2]:
        continue
    accel = (float(sys.argv[3]) / task["im_record"]) * np.asarray(task["accel"])
    t0 = time.process_time()
    found = demands.run_demands(task["values"], accel, task["dt"], task["period"], task["step"], None, task["record"])
    out[task["configuration"]] = [time.process_time() - t0, found]
print(json.dumps(out))
"""


def one_run(tree, study, record, im):
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(str(Path(tree) / p) for p in ("harness", "fmu_src", ".")))
    done = subprocess.run([sys.executable, "-c", RUNNER, study, record, str(im)], env=env, cwd=tree,
                          capture_output=True, text=True, check=True)
    return json.loads(done.stdout.splitlines()[-1])


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--base", required=True, help="git revision of the old code")
    parser.add_argument("--study", default="studies/yielding-three-storey.toml")
    parser.add_argument("--record", default="DUZCE/BOL090")
    parser.add_argument("--im", type=float, default=1.0)
    parser.add_argument("--runs", type=int, default=5)
    args = parser.parse_args(argv)
    sys.path.insert(0, str(ROOT / "harness"))
    from pidamper.machine import describe

    study = str((ROOT / args.study).resolve())
    with tempfile.TemporaryDirectory() as tmp:
        base = Path(tmp) / "base"
        subprocess.run(["git", "-C", str(ROOT), "worktree", "add", "--detach", "-q", str(base), args.base], check=True)
        try:
            if (base / "build_fmu" / "compile.py").is_file():
                subprocess.run([sys.executable, "-m", "build_fmu.compile"], cwd=base, check=True, capture_output=True,
                               env=dict(os.environ, PYTHONPATH=str(base)))
            trees = {"base": base, "new": ROOT}
            for tree in trees.values():  # builds the FMU once per tree
                one_run(tree, study, args.record, args.im)
            runs = {label: [] for label in trees}
            for _ in range(args.runs):
                for label, tree in trees.items():
                    runs[label].append(one_run(tree, study, args.record, args.im))
        finally:
            subprocess.run(["git", "-C", str(ROOT), "worktree", "remove", "--force", str(base)], check=True)
    print(f"Machine: {describe()}; {args.record} scaled to {args.im} g, {args.study}; median of {args.runs} "
          "interleaved runs, process CPU time per run\n")
    print("| configuration | base s | new s | new / base | demands equal |\n|---|---:|---:|---:|---|")
    for conf in runs["base"][0]:
        cost = {label: statistics.median(r[conf][0] for r in rows) for label, rows in runs.items()}
        equal = runs["base"][0][conf][1] == runs["new"][0][conf][1]
        print(f"| {conf} | {cost['base']:.3f} | {cost['new']:.3f} | {cost['new'] / cost['base']:.3f} | "
              f"{'yes' if equal else 'NO'} |")


if __name__ == "__main__":
    main()

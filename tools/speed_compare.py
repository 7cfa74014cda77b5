"""Step cost of the physics core, merge-base against this tree (issue 22, item 8), each build.

    python tools/speed_compare.py --base REV [--runs 5] [--steps 20000] [--case NAME ...]

Each case steps `Damper.advance` over fixed communication steps of 0.01 s, as fmi2DoStep does, and
reads the outputs the FMU reads every step (observables; a building's floor outputs too).  A run is
one fresh process importing `pidamper_physics` from one tree: the base tree as it runs there, this
tree's plain Python (PIDAMPER_PURE=1) and, when it is compiled (python -m build_fmu.compile), its
compiled build, and the base's compiled build too where the base can compile (it is compiled in its
worktree first).  The runs alternate (base, base compiled, plain, compiled, base, ...) and each
figure is the median of `--runs` runs of process CPU time per step.  Prints the machine and a table:
case, each build's us/step, and this tree's plain and compiled builds over the base's like build.
"""
import argparse
import contextlib
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

from pidamper.machine import describe

ROOT = Path(__file__).resolve().parents[1]

CASES = {
    "no contact": "dict(d=10.0), (0.0, 0.7 * W2, 0.0, 0.0), 0.0",
    "impacts (resonance)": "dict(mu=0.02), (0.0, 0.0, 0.0, 0.0), 0.0981",
    "3-storey building with damper": "dict(storeys=3, fidelity=1, zeta_s=0.05, mu=0.03, FR=1.0, d=0.01), "
                                     "(0.0, 0.0, 0.0, 0.0), 0.0",
    "10-storey building with damper": "dict(storeys=10, fidelity=1, zeta_s=0.02, mu=0.03, FR=1.0, d=0.04), "
                                      "(0.0, 0.0, 0.0, 0.0), 0.0",
    "3-storey yielding building with damper": "dict(storeys=3, floor_m=[1e5] * 3, storey_k=[8e7] * 3, fidelity=1, "
                                              "zeta_s=0.02, p_delta=1, storey_Fy=[8e5, 7e5, 5e5], "
                                              "storey_b=[0.02] * 3, mu=0.05, FR=0.95, d=0.02, e=0.5), "
                                              "(0.0, 0.0, 0.0, 0.0), 0.0",
}

RUNNER = """
import math, sys, time
from pidamper_physics.damper import Damper
from pidamper_physics.params import Params
W2 = math.sqrt(9.81)
params, start, F = {case}
steps = int(sys.argv[1])
d = Damper(Params(**params), *start)
d.bound_work()
h = 0.01
building = bool(params.get("storeys"))
t0 = time.process_time()
for k in range(1, steps + 1):
    f = F * math.sin(W2 * k * h)
    a = 3.0 * math.sin(6.0 * k * h) if building else 0.0
    d.advance(k * h, f, a)
    d.observables(f, a)
    if building:
        d.building_outputs(f, a)
print((time.process_time() - t0) / steps * 1e6, d.impacts)
"""


#: the bare yielding building of docs/yielding (P-Delta, its 2 m/s2 pulse on [0.5, 0.8) s repeated
#: every 6 s) stepped by YieldingMotion.advance, with the outputs ShearBuilding3 packs; "impacts":
#: its storeys' events
BARE = "3-storey yielding building, bare"
BARE_RUNNER = """
import sys, time
from pidamper_physics.yielding import building_motion
steps = int(sys.argv[1])
core = building_motion([1e5] * 3, [8e7] * 3, [3.0] * 3, 0.02, [6e5, 5e5, 3e5], [0.02] * 3, 1)
zero = [0.0] * 3
t0 = time.process_time()
for i in range(steps):
    core.advance((i + 1) * 0.01, zero, 2.0 if 50 <= i % 600 < 80 else 0.0)
    x, v = core.floors()
    core.absolute_accelerations(zero, x, v)
    core.storey_forces(), core.plastic_drifts(), core.energy(), core.base_shear()
print((time.process_time() - t0) / steps * 1e6, core.storeys.events)
"""


def runner(case):
    """The script that times `case` (argv[1]: steps; prints us per step and the impacts or events)."""
    return BARE_RUNNER if case == BARE else RUNNER.format(case=CASES[case])


def one_run(tree, case, steps, pure="0"):
    env = dict(os.environ, PYTHONPATH=str(Path(tree) / "fmu_src"), PIDAMPER_PURE=pure)
    out = subprocess.run([sys.executable, "-c", runner(case), str(steps)], env=env,
                         capture_output=True, text=True, check=True).stdout.split()
    return float(out[0]), int(out[1])


def compiled_here():
    """Whether this tree's physics runs compiled (its build, as a fresh process sees it)."""
    env = dict(os.environ, PYTHONPATH=str(ROOT / "fmu_src"), PIDAMPER_PURE="0")
    said = subprocess.run([sys.executable, "-c", "import pidamper_physics as p; print(p.BUILD)"], env=env,
                          capture_output=True, text=True, check=True).stdout
    return said.startswith("compiled")


@contextlib.contextmanager
def base_tree(rev):
    """A worktree of `rev` (removed afterwards), compiled there when it can compile and this tree is."""
    with tempfile.TemporaryDirectory() as tmp:
        base = Path(tmp) / "base"
        subprocess.run(["git", "-C", str(ROOT), "worktree", "add", "--detach", "-q", str(base), rev], check=True)
        try:
            if (base / "build_fmu" / "compile.py").is_file() and compiled_here():
                subprocess.run([sys.executable, "-m", "build_fmu.compile"], cwd=base, check=True, capture_output=True,
                               env=dict(os.environ, PYTHONPATH=str(base)))
            yield base
        finally:
            subprocess.run(["git", "-C", str(ROOT), "worktree", "remove", "--force", str(base)], check=True)


def builds_of(base):
    """[(label, tree, PIDAMPER_PURE)]: the base as it runs, its compiled build where it has one, this
    tree's plain and compiled builds."""
    builds = [("base", base, "1")]
    if any((base / "fmu_src" / "pidamper_physics").glob("*.so")):
        builds.append(("base compiled", base, "0"))
    return builds + [("plain", ROOT, "1")] + ([("compiled", ROOT, "0")] if compiled_here() else [])


def measure(builds, cases, runs, steps):
    """{case: ({label: median us per step}, impacts)}, the builds' runs interleaved; refuses builds
    that disagree on a case's impacts."""
    out = {}
    for case in cases:
        rows = {label: [] for label, _, _ in builds}
        for _ in range(runs):
            for label, tree, pure in builds:
                rows[label].append(one_run(tree, case, steps, pure))
        if len({i for label in rows for _, i in rows[label]}) != 1:
            raise SystemExit(f"{case}: the builds disagree on the impacts: {rows}")
        out[case] = ({label: statistics.median(c for c, _ in r) for label, r in rows.items()}, rows["base"][0][1])
    return out


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--base", required=True, help="git revision of the old code (e.g. the merge-base)")
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--steps", type=int, default=20000)
    parser.add_argument("--case", action="append", choices=sorted(CASES) + [BARE],
                        help="only these cases (default: all)")
    args = parser.parse_args(argv)
    with base_tree(args.base) as base:
        builds = builds_of(base)
        # each of this tree's builds against the base's like build (the plain one if the base has no other)
        ratios = [(label, "base compiled" if label == "compiled" and len(builds) == 4 else "base")
                  for label, _, _ in builds if not label.startswith("base")]
        print(f"Machine: {describe()}; {args.steps} steps of 0.01 s, median of {args.runs} interleaved runs, "
              "process CPU time\n")
        heads = [f"{label} us/step" for label, _, _ in builds] + [f"{label} / {old}" for label, old in ratios]
        print("| case | " + " | ".join(heads) + " | impacts |\n|---|" + "---:|" * (len(heads) + 1))
        for case in args.case or [*CASES, BARE]:
            cost, impacts = measure(builds, [case], args.runs, args.steps)[case]
            cells = [f"{cost[label]:.2f}" for label, _, _ in builds]
            cells += [f"{cost[label] / cost[old]:.3f}" for label, old in ratios]
            print(f"| {case} | " + " | ".join(cells) + f" | {impacts} |", flush=True)


if __name__ == "__main__":
    main()

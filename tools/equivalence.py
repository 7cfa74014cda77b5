"""Is this tree the same program as an earlier one?  Every output, compared (issue 22, item 6).

    python tools/equivalence.py --base REV [--out FILE.md] [--tolerance 1e-13]

The old tree is checked out at REV (`git worktree add`, removed afterwards).  For each tree:

1. its physics core runs tools/core_cases.py (every fidelity level, both contact forms, chatter to
   sticking, base excitation, buildings of 1, 3 and 10 storeys, the unit with the shear building,
   get_state / set_state mid-run) in a process that imports that tree's `pidamper_physics` only;
2. its own builder builds its FMUs (`python -m build_fmu --out DIR --storeys 1 3 10` inside the
   tree; an older builder without --storeys builds its one PendulumImpactDamper.fmu with a
   `storeys` parameter and ShearBuilding.fmu), and fmpy's FMU2Slave drives both builds with
   identical inputs, reading EVERY output variable the two builds share (by name) after every step:
   every shipped scene (start values and the input signal from this tree's scene loader, the input
   held over each step), the paper's cases, buildings of 1, 3 and 10 storeys with the damper (each
   tree's FMU for it: `storeys = N` there, DampedShearBuilding<N>.fmu here, the start values fitted
   by pidamper.running.variants), PendulumImpactDamperUnit.fmu co-simulated with the 3-storey
   building FMU (one Gauss-Seidel loop, the same for both), and FMU state: get, serialize at a third
   of the run, finish, de-serialize, finish again; and the OLD build's serialized state
   de-serialized into the NEW build when both run the same model.

A case is "bit for bit" when every value is equal, "within tolerance" when the largest difference
is at most TOL times the output's peak.  Beyond that, the old tree runs the case once more with mu
one ulp larger: the case's conditioning, how far one rounding of one input moves its outputs
(impacts amplify rounding; a chattering case moves 1e-12 of its peak under one ulp).  A case whose
difference stays within CONDITIONING (10) times that is "within conditioning": the new code's
intermediate values differ by a few roundings, which is all the case can resolve.  Anything else is
FAIL (exit status 1).  Prints a markdown table.
"""
import argparse
import json
import math
import os
import subprocess
import sys
import tempfile
from pathlib import Path

from pidamper.running.instance import FmuInstance
from pidamper.running.variants import for_model, storeys_of

ROOT = Path(__file__).resolve().parents[1]
H = 0.01


def tree_env(tree):
    return dict(os.environ, PYTHONPATH=os.pathsep.join([str(tree / "fmu_src"), str(tree)]))


def core_values(tree, perturb=False):
    """tools/core_cases.py of THIS tree run against `tree`'s physics: {case: rows of reprs}; perturb:
    with mu one ulp larger."""
    done = subprocess.run([sys.executable, str(ROOT / "tools" / "core_cases.py")] + (["--perturb-mu"] if perturb else []),
                          env=tree_env(tree),
                          capture_output=True, text=True, check=True)
    return json.loads(done.stdout)


def build(tree, out):
    """The tree's FMUs in `out` (with the buildings of 1, 3 and 10 storeys where its builder makes them)."""
    done = subprocess.run([sys.executable, "-m", "build_fmu", "--out", str(out), "--storeys", "1", "3", "10"],
                          cwd=tree, env=tree_env(tree), capture_output=True, text=True)
    if done.returncode != 0:  # an older builder: one FMU with a `storeys` parameter
        subprocess.run([sys.executable, "-m", "build_fmu", "--out", str(out)], cwd=tree, env=tree_env(tree),
                       capture_output=True, text=True, check=True)
    return out


def model_fmu(dist, values):
    """(path, start values) of the FMU of `dist` that runs `values`: DampedShearBuilding<N>.fmu for
    storeys = N where the tree has it, else PendulumImpactDamper.fmu with the values as given."""
    n = storeys_of(values)
    if n and (dist / f"DampedShearBuilding{n}.fmu").is_file():
        return dist / f"DampedShearBuilding{n}.fmu", for_model(f"DampedShearBuilding{n}", values)
    if (dist / "DampedShearBuilding1.fmu").is_file():  # the split tree: the pendulum system has no storeys
        return dist / "PendulumImpactDamper.fmu", for_model("PendulumImpactDamper", values)
    return dist / "PendulumImpactDamper.fmu", values


def bare_building(dist, values):
    """(path, start values) of the 3-storey bare building of `dist`."""
    if (dist / "ShearBuilding3.fmu").is_file():
        return dist / "ShearBuilding3.fmu", values
    return dist / "ShearBuilding.fmu", {"storeys": 3, **values}


def variables(path):
    """The names of every variable of the FMU at `path`."""
    import fmpy

    return {v.name for v in fmpy.read_model_description(str(path)).modelVariables}


def shared_outputs(*paths):
    """The output names every FMU at `paths` has, in the first one's order."""
    import fmpy

    names = [[v.name for v in fmpy.read_model_description(str(p)).modelVariables if v.causality == "output"]
             for p in paths]
    return [n for n in names[0] if all(n in other for other in names[1:])]


class Slave(FmuInstance):
    """One FMU instance stepped by hand (pidamper.running.instance); read() returns the output
    variables `names` (default: every output)."""

    def __init__(self, path, start_values, names=None):
        super().__init__(path, start_values, instance_name="equivalence")
        outputs = [v for v in self.vars.values() if v.causality == "output" and (names is None or v.name in names)]
        if names is not None:
            outputs.sort(key=lambda v: names.index(v.name))
        self._reals = [v.valueReference for v in outputs if v.type == "Real"]
        self._ints = [v.valueReference for v in outputs if v.type != "Real"]

    def read(self):
        return list(self.fmu.getReal(self._reals)) + [float(i) for i in self.fmu.getInteger(self._ints)]

    def step(self, k):
        self.do_step((k - 1) * H, H)


def scene_cases():
    """(name, start values, input name or None, input values per step) of every shipped scene, the
    paper's cases and a 1-storey building, with this tree's scene loader and forcing signals."""
    from pidamper.scenes import scene as scenes  # this tree's loader (the environment's editable install): the inputs both builds get

    cases = []
    for name in sorted(p.stem for p in (ROOT / "harness" / "pidamper" / "scenes").glob("*.toml")):
        s = scenes.load(name)
        forcing = s.make_forcing()
        n = int(round(s.stop_time / s.output_interval))
        values = {**s.start_values, **forcing.start_values}
        signal = [float(forcing.value(k * H)) for k in range(n)] if forcing.target else None
        cases.append((f"scene {name}", values, forcing.target if signal else None, signal, n))
    w2 = math.sqrt(9.81)
    for fr in (1.5, 2.0, 4.0, 5.0):  # the paper's free vibration (docs/paper) and its printed contact reading
        cases.append((f"paper free FR={fr}", {"mu": 0.1, "FR": fr, "theta_dot_0": 0.7 * w2}, None, None, 1000))
        cases.append((f"paper-reading free FR={fr}", {"mu": 0.1, "FR": fr, "theta_dot_0": 0.7 * w2, "contact_form": 1},
                      None, None, 1000))
    for e in (0.2, 0.8):
        cases.append((f"paper forced FR=2 e={e}", {"mu": 0.02, "FR": 2.0, "e": e, "theta_dot_0": 0.0, "F0": 0.0981,
                                                    "Omega": w2, "phi": math.pi / 2}, None, None, 2000))
    building = scenes.load("building-3")
    one = {k: v for k, v in building.start_values.items()}
    one["storeys"] = 1
    ground = building.make_forcing()
    cases.append(("building 1 storey (building-3 scene's input)", one, ground.target,
                  [float(ground.value(k * H)) for k in range(1000)], 1000))
    return cases


def run_scene(fmu, values, target, signal, n, serialize_at=None, names=None):
    """Rows of the outputs `names` (default: all) after each step; with serialize_at, also the rows
    of a rerun from the state serialized after that step, and the serialized bytes."""
    slave = Slave(fmu, values, names)
    rows, blob = [], None
    for k in range(1, n + 1):
        if target:
            slave.set(target, signal[k - 1])
        slave.step(k)
        rows.append(slave.read())
        if k == serialize_at:
            state = slave.fmu.getFMUstate()
            blob = slave.fmu.serializeFMUstate(state)
            slave.fmu.freeFMUstate(state)
    rerun = None
    if blob is not None:
        rerun = resume(slave, blob, target, signal, serialize_at, n)
    slave.close()
    return rows, rerun, blob


def resume(slave, blob, target, signal, k0, n):
    state = slave.fmu.deSerializeFMUstate(blob)
    slave.fmu.setFMUstate(state)
    slave.fmu.freeFMUstate(state)
    rows = []
    for k in range(k0 + 1, n + 1):
        if target:
            slave.set(target, signal[k - 1])
        slave.step(k)
        rows.append(slave.read())
    return rows


def cosim(dist, aware, names, n=2000):
    """PendulumImpactDamperUnit on floor 3 of ShearBuilding (3 storeys), Gauss-Seidel: the unit
    steps with the floor's absolute acceleration, the building with the unit's force (and its
    impulse when impulse-aware); rows of the unit's outputs `names` and the floors'."""
    unit = Slave(dist / "PendulumImpactDamperUnit.fmu", {"impulse_aware": aware, "e": 0.8, "d": 0.02}, names)
    bldg = Slave(*bare_building(dist, {"zeta_s": 0.02}), names=[f"floor[{k}].{q}" for q in "xva" for k in (1, 2, 3)])
    rows = []
    a_s = 0.0
    for k in range(1, n + 1):
        ag = 3.0 * math.sin(6.0 * (k - 1) * H)
        unit.set("a_s", a_s)
        unit.step(k)
        bldg.set("a_g", ag)
        bldg.set("F[3]", unit.get("F_s"))
        if aware:
            bldg.set("J[3]", unit.get("J_s"))
            bldg.set("t_J[3]", unit.get("t_J"))
        bldg.step(k)
        a_s = bldg.get("floor[3].a")
        rows.append(unit.read() + bldg.read())
    unit.close()
    bldg.close()
    return rows


def compare(old, new, tolerance):
    """(verdict, values compared, max |diff| / peak)."""
    if isinstance(old, str) or isinstance(new, str):
        return ("bit for bit" if old == new else "FAIL"), 1, 0.0 if old == new else math.inf
    if len(old) != len(new) or any(len(a) != len(b) for a, b in zip(old, new)):
        return "FAIL", 0, math.inf
    count = sum(len(r) for r in old)
    if old == new:
        return "bit for bit", count, 0.0
    worst = 0.0
    for c in range(max(len(r) for r in old)):  # rows may differ in length (a state row, a floor row)
        pairs = [(float(a[c]), float(b[c])) for a, b in zip(old, new) if c < len(a)]
        peak = max(abs(v) for v, _ in pairs) or 1.0
        worst = max(worst, max(abs(w - v) for v, w in pairs) / peak)
    return ("within tolerance" if worst <= tolerance else "FAIL"), count, worst


CONDITIONING = 10.0  # how many times its one-ulp sensitivity a case may move (a few roundings)


def bumped(values):
    """FMU start values with mu one ulp larger (the FMU's default mu if not given)."""
    from pidamper_physics import Params

    return dict(values, mu=Params.from_variables(values).mu * (1.0 + 2.0 ** -52))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--base", required=True, help="git revision of the old code (e.g. the merge-base)")
    parser.add_argument("--tolerance", type=float, default=1e-13)
    parser.add_argument("--out", help="also write the table to this markdown file")
    args = parser.parse_args(argv)
    lines = [f"Equivalence of {ROOT.name} against {args.base}: every value after every step; tolerance "
             f"{args.tolerance:g} of each output's peak.\n", "| case | values | max diff / peak | old code, 1 ulp of mu | verdict |",
             "|---|---:|---:|---:|---|"]
    failed = False

    def row(name, old, new, sensitivity=None):
        """One line of the table; sensitivity: a callable giving the old tree's rows with mu one ulp
        larger, asked only when the difference is beyond the tolerance."""
        nonlocal failed
        verdict, count, worst = compare(old, new, args.tolerance)
        moved = ""
        if verdict == "FAIL" and sensitivity is not None and not isinstance(old, str):
            _, _, ulp = compare(old, sensitivity(), math.inf)
            moved = f"{ulp:.1e}"
            if worst <= CONDITIONING * ulp:
                verdict = "within conditioning"
        failed |= verdict == "FAIL"
        lines.append(f"| {name} | {count} | {worst:.1e} | {moved} | {verdict} |")
        print(lines[-1], flush=True)

    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        base = tmp / "base"
        subprocess.run(["git", "-C", str(ROOT), "worktree", "add", "--detach", "-q", str(base), args.base], check=True)
        try:
            print("\n".join(lines), flush=True)
            old_core, new_core = core_values(base), core_values(ROOT)
            bumped_core = {}

            def core_sensitivity(name):
                if not bumped_core:
                    bumped_core.update(core_values(base, perturb=True))
                return bumped_core[name]

            for name in old_core:
                row(f"core: {name}", old_core[name], new_core.get(name, "missing"), lambda: core_sensitivity(name))
            dist_old, dist_new = build(base, tmp / "old"), build(ROOT, tmp / "new")
            for name, values, target, signal, n in scene_cases():
                third = n // 3
                (fmu_old, values_old), (fmu_new, values_new) = model_fmu(dist_old, values), model_fmu(dist_new, values)
                missing = sorted(set(values_old) - variables(fmu_old))
                if missing:  # a case of a capability the old tree does not have (its FMU lacks the variables)
                    lines.append(f"| FMU: {name} | | | | new in this tree (the old FMU has no {', '.join(missing)}) |")
                    print(lines[-1], flush=True)
                    continue
                names = shared_outputs(fmu_old, fmu_new)
                old, old_rerun, blob = run_scene(fmu_old, values_old, target, signal, n, third, names)
                new, new_rerun, _ = run_scene(fmu_new, values_new, target, signal, n, third, names)
                moved = {}

                def fmu_sensitivity(part):
                    if not moved:
                        rows, rerun, _ = run_scene(fmu_old, bumped(values_old), target, signal, n, third, names)
                        moved.update(whole=rows, rest=rows[third:])
                    return moved[part]

                label = f"{name} ({fmu_old.stem} -> {fmu_new.stem}, {len(names)} outputs)"
                row(f"FMU: {label}", old, new, lambda: fmu_sensitivity("whole"))
                row(f"FMU: {name}, rerun from a serialized state", old[third:], new_rerun, lambda: fmu_sensitivity("rest"))
                if fmu_old.name != fmu_new.name:
                    continue  # another model: the old state is no state of it
                slave = Slave(fmu_new, values_new, names)
                try:
                    crossed = resume(slave, blob, target, signal, third, n)
                except Exception as err:  # a format change: say so in the table
                    crossed = f"{type(err).__name__}: {err}"
                slave.close()
                if isinstance(crossed, str) and "FMICallException" in crossed and "status 3" in crossed:  # fmi2Error:
                    # the new model refused the old state (its keys name variables the model no longer has)
                    lines.append(f"| FMU: {name}, old build's state into the new build | | | | refused (the state "
                                 "format changed with the model's variables) |")
                    print(lines[-1], flush=True)
                    continue
                row(f"FMU: {name}, old build's state into the new build", old_rerun, crossed,
                    lambda: fmu_sensitivity("rest"))
            unit_names = shared_outputs(*(d / "PendulumImpactDamperUnit.fmu" for d in (dist_old, dist_new)))
            for aware in (0, 1):
                row(f"FMU: unit + 3-storey building, impulse_aware={aware}", cosim(dist_old, aware, unit_names),
                    cosim(dist_new, aware, unit_names))
        finally:
            subprocess.run(["git", "-C", str(ROOT), "worktree", "remove", "--force", str(base)], check=True)
    if args.out:
        Path(args.out).write_text("\n".join(lines) + "\n")
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()

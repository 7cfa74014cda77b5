"""The speed page of issue 36 (docs/bench/core-speed.md): each target beside what this tree measures.

    python tools/speed_page.py [--base 5160ce8] [--runs 5] [--steps 5000] [--out docs/bench/core-speed.md]

Measures, against the base revision (default: the first commit that compiled the physics, unchanged):
- the core's step cost, every build side by side (tools/speed_compare.py: the base plain and
  compiled, this tree plain and compiled, runs interleaved);
- instructions per step by function (tools/callgrind_case.py), the base compiled and this tree;
- the FMUs' step cost in the native C host (at rest: no input set; moving: a_g = 3 sin(6 t) m/s2) and
  under fmpy with a random ground acceleration (tools/fmu_step_compare.py), each tree building its
  own FMUs;
and reads the figures two other generated pages measured with their own commands: ours against
OpenSees on the yielding building (docs/yielding) and the shipped FEMA P-695 study's wall time
(docs/assessment).  Writes the page (targets first) and prints it.  Takes about 25 minutes.
"""
import argparse
import re
import sys
from pathlib import Path

import callgrind_case
import fmu_step_compare
import speed_compare
from pidamper.machine import describe

ROOT = Path(__file__).resolve().parents[1]
YIELDING, RESONANCE = "3-storey yielding building with damper", "impacts (resonance)"
TALL, NO_CONTACT = "10-storey building with damper", "no contact"
PROFILED = (YIELDING, TALL, RESONANCE, speed_compare.BARE)
MODELS = ("DampedShearBuilding3", "ShearBuilding3", "PendulumImpactDamper")


def yielding_frontier(page):
    """{error level: (ours, OpenSees, OpenSees configuration)} from docs/yielding's first frontier table."""
    out = {}
    for level, ours, peer in re.findall(r"^\| (0\.01|0\.001|1e-05) \| ([\d.]+) \| (.+?) \|$", page, re.M):
        if level not in out:  # the first table is the bare building's
            match = re.match(r"([\d.]+) \((.+)\)", peer)
            out[level] = (float(ours), float(match.group(1)) if match else None, match.group(2) if match else peer)
    return out


def study_wall(page):
    """Seconds of wall time by stage of the assessment page, summed, and its worker count."""
    stages = re.search(r"Wall time by stage: (.+?)\.\s", page).group(1)
    workers = int(re.search(r"s wall on (\d+) worker", page).group(1))
    return sum(float(s) for s in re.findall(r"([\d.]+) s", stages)), workers


def table(head, rows):
    return "\n".join(["| " + " | ".join(head) + " |", "|---|" + "---:|" * (len(head) - 1)]
                     + ["| " + " | ".join(str(c) for c in row) + " |" for row in rows])


def met(value, limit):
    return "met" if value <= limit else "not met"


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--base", default="5160ce8")
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--steps", type=int, default=5000)
    parser.add_argument("--profile-steps", type=int, default=1500)
    parser.add_argument("--out", default=str(ROOT / "docs" / "bench" / "core-speed.md"))
    args = parser.parse_args(argv)
    with speed_compare.base_tree(args.base) as base:
        builds = speed_compare.builds_of(base)
        core = speed_compare.measure(builds, [*speed_compare.CASES, speed_compare.BARE], args.runs, args.steps)
        profiles = {case: (callgrind_case.profile(base, case, args.profile_steps),
                           callgrind_case.profile(ROOT, case, args.profile_steps)) for case in PROFILED}
        with speed_compare.tempfile.TemporaryDirectory() as tmp:
            olds = fmu_step_compare.build(base, Path(tmp) / "old", list(MODELS))
            news = fmu_step_compare.build(ROOT, Path(tmp) / "new", list(MODELS))
            native = fmu_step_compare.compare(olds, news, MODELS, "native", True, args.runs, args.steps)
            driven = fmu_step_compare.compare(olds, news, MODELS, "native", False, args.runs, args.steps)
            moving = fmu_step_compare.compare(olds, news, MODELS, "fmpy", False, args.runs, args.steps)
    frontier = yielding_frontier((ROOT / "docs" / "yielding" / "README.md").read_text())
    wall, workers = study_wall((ROOT / "docs" / "assessment" / "README.md").read_text())
    page = render(args, builds, core, profiles, (native, driven, moving), frontier, wall, workers)
    Path(args.out).write_text(page)
    print(page)


def render(args, builds, core, profiles, fmus, frontier, wall, workers):
    native, driven, moving = fmus
    cost = {case: c for case, (c, _) in core.items()}
    impacts = {case: i for case, (_, i) in core.items()}
    per_impact = (cost[RESONANCE]["compiled"] - cost[NO_CONTACT]["compiled"]) * args.steps / impacts[RESONANCE]
    at_rest = {model: (old, new) for model, old, new in native}
    speedup = {model: old / new for model, old, new in driven}
    ours, peer, label = frontier["0.01"]
    targets = [
        ("core: 3-storey yielding building with damper, us per step", "<= 30", f"{cost[YIELDING]['compiled']:.1f}",
         met(cost[YIELDING]["compiled"], 30.0)),
        ("core: 10-storey building with damper, us per step", "<= 45", f"{cost[TALL]['compiled']:.1f}",
         met(cost[TALL]["compiled"], 45.0)),
        ("core: pendulum at resonance, us per step", "<= 2", f"{cost[RESONANCE]['compiled']:.2f}",
         met(cost[RESONANCE]["compiled"], 2.0)),
        ("core: pendulum, marginal us per impact (resonance less no contact, per impact)", "<= 10",
         f"{per_impact:.1f}", met(per_impact, 10.0)),
        ("FMU: DampedShearBuilding3 at rest, native C host, us per step", "<= 5",
         f"{at_rest['DampedShearBuilding3'][1]:.1f}", met(at_rest["DampedShearBuilding3"][1], 5.0)),
        *[(f"FMU: {model} moving (a_g = 3 sin(6 t)), native C host, times faster than {args.base}", ">= 5",
           f"{speedup[model]:.2f}", "met" if speedup[model] >= 5.0 else "not met")
          for model in ("DampedShearBuilding3", "ShearBuilding3")],
        (f"FMU: PendulumImpactDamper, native C host, times faster than {args.base}", ">= 2",
         f"{at_rest['PendulumImpactDamper'][0] / at_rest['PendulumImpactDamper'][1]:.2f}",
         "met" if at_rest["PendulumImpactDamper"][0] >= 2.0 * at_rest["PendulumImpactDamper"][1] else "not met"),
        ("docs/yielding, bare building at the 1e-2 level: ours / OpenSees CPU per simulated second", "< 1",
         f"{ours / peer:.2f} ({ours} / {peer}, {label})", "met" if ours < peer else "not met"),
        ("shipped FEMA P-695 study, wall time on 2 cores", "<= 300 s", f"{wall:.0f} s ({workers} workers)",
         met(wall, 300.0)),
    ]
    labels = [label for label, _, _ in builds]
    core_rows = [[case] + [f"{cost[case][label]:.2f}" for label in labels] + [impacts[case]] for case in cost]
    lines = [
        "# Core and FMU speed against the issue's targets",
        "",
        f"Written by `python tools/speed_page.py --base {args.base} --runs {args.runs} --steps {args.steps}` "
        f"on {describe('fmpy')}.  Process CPU time, medians of {args.runs} interleaved runs; the base "
        f"{args.base} is the commit that first compiled the physics unchanged.",
        "",
        "## Targets",
        "",
        table(["target", "limit", "measured", "status"], targets),
        "",
        "The last two rows come from the pages that measure them with their own commands: "
        "[docs/yielding](../yielding/README.md) (`python -m pidamper.benchmarks.yielding_peer`) and "
        "[docs/assessment](../assessment/README.md) (`pidamper assess studies/yielding-three-storey.toml "
        "--out docs/assessment --workers 2`: the sum of its stages' wall times).  docs/yielding times each run "
        "of our FMU as the harness's studies run it: unpacked and its description read once per process "
        "(its one-off cost is stated on that page), instantiated, initialised and stepped per run.",
        "",
        "## The core per communication step of 0.01 s, every build",
        "",
        f"`Damper.advance` and the outputs the FMU reads, {args.steps} steps (tools/speed_compare.py's cases; the "
        "bare building: `YieldingMotion.advance` and the outputs `ShearBuilding3` packs, its impacts column "
        "the storeys' events); "
        "plain: `PIDAMPER_PURE=1`, the Python that runs as it is; compiled: the same sources compiled "
        "(`python -m build_fmu.compile`).",
        "",
        table(["case"] + [f"{label} us/step" for label in labels] + ["impacts"], core_rows),
        "",
        "## Instructions per step (callgrind, inside `Damper.advance` or `YieldingMotion.advance`)",
        "",
        f"{args.profile_steps} steps; `python tools/callgrind_case.py --case CASE` in each tree.",
        "",
        table(["case", f"{args.base} compiled", "now", "now / then"],
              [[case, f"{old[0] / args.profile_steps:,.0f}", f"{new[0] / args.profile_steps:,.0f}",
                f"{new[0] / old[0]:.2f}"] for case, (old, new) in profiles.items()]),
        "",
        f"By function, {YIELDING} (inclusive instructions per step, the ten largest now):",
        "",
    ]
    old, new = profiles[YIELDING]
    top = sorted(new[1].items(), key=lambda item: -item[1])[:12]
    lines += [table(["function", f"{args.base} compiled", "now"],
                    [[f"`{name}`", f"{old[1].get(name.replace('._Damper.', '.Damper.'), 0) / args.profile_steps:,.0f}",
                      f"{count / args.profile_steps:,.0f}"] for name, count in top]),
              "",
              "(`_Damper` is the typed base class of `Damper` that now holds its stepping methods.)", ""]
    lines += [
        "## The FMUs",
        "",
        "Each tree builds its FMUs (`python -m build_fmu`).  Native: the C host of "
        "`pidamper.benchmarks.native` reads every output and local, one call each, and sets no input "
        "(the buildings stay at rest; the pendulum swings and impacts from its default start) or sets "
        "a_g = 3 sin(6 t) m/s2 before each step (the core cases' building input); fmpy: "
        "FMU2Slave sets a random ground acceleration before each step and reads every Real output and "
        "local (tools/fmu_step_compare.py).",
        "",
        table(["FMU", "host", f"{args.base} us/step", "now us/step", "now / then"],
              [[model, "native, no input", f"{o:.2f}", f"{n:.2f}", f"{n / o:.3f}"] for model, o, n in native]
              + [[model, "native, a_g = 3 sin(6 t)", f"{o:.2f}", f"{n:.2f}", f"{n / o:.3f}"] for model, o, n in driven]
              + [[model, "fmpy, random a_g", f"{o:.2f}", f"{n:.2f}", f"{n / o:.3f}"] for model, o, n in moving]),
        "",
    ]
    return "\n".join(lines)


if __name__ == "__main__":
    sys.exit(main())

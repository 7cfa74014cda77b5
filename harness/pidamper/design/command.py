"""pidamper design: search a damper's parameters on a building (design.search), then write
OUT/trials.csv (every design: its parameters, objectives, constraints, whether it is feasible and on
the front) and OUT/front.csv (the feasible Pareto front), and print the front.

    pidamper design STUDY.toml [--out DIR] [--trials N] [--workers N] [--dask | --scheduler ADDR] [--page]

The study file: design.design_file.  OUT/runs.csv is the journal of every run; a search started
again on the same OUT resumes (and one with more --trials continues) from it.
"""
import argparse
import csv
import os
import shlex
import sys
import time
from pathlib import Path

from ..assessment.study_file import StudyError
from . import design_file, search


def write_trials(design, found, out):
    """OUT/trials.csv and OUT/front.csv; the front."""
    best = {t.number for t in search.front(found)}
    names = list(design.search)
    head = (["trial", "batch"] + names + [o.name for o in design.objectives]
            + [f"constraint_{c}" for c in design.constraints] + ["feasible", "front", "error"])

    def row(t):
        objectives = t.objectives or [""] * len(design.objectives)
        constraints = t.constraints or [""] * len(design.constraints)
        return ([t.number, t.batch] + [t.params.get(n, "") for n in names] + objectives + constraints
                + [int(t.feasible), int(t.number in best), t.error])

    for name, rows in (("trials.csv", found), ("front.csv", [t for t in found if t.number in best])):
        with (Path(out) / name).open("w", newline="") as handle:
            writer = csv.writer(handle)
            writer.writerow(head)
            writer.writerows(row(t) for t in rows)
    return [t for t in found if t.number in best]


INVOCATIONS = ("started", "command", "designs", "runs_held", "runs_ran", "search_s", "workers", "executor", "machine")


def log_invocation(out, command, designs, held, ran, seconds, workers, dask):
    """Append this invocation's search to OUT/invocations.csv: the runs its journal held at the start
    and those it ran, so that a page written by a resumed invocation says what its figures cover."""
    from datetime import datetime, timedelta, timezone

    from ..machine import describe

    path = Path(out) / "invocations.csv"
    fresh = not path.is_file()
    with path.open("a", newline="") as handle:
        writer = csv.writer(handle)
        if fresh:
            writer.writerow(INVOCATIONS)
        started = datetime.now(timezone.utc) - timedelta(seconds=seconds)
        writer.writerow([started.strftime("%Y-%m-%d %H:%M UTC"), command, designs, held, ran,
                         f"{seconds:.0f}", workers, "Dask" if dask else "process pool", describe()])


def summary(design, found, best, seconds):
    lines = [f"pidamper design: {design.name}: {len(found)} designs "
             f"({sum(t.feasible for t in found)} feasible, {sum(bool(t.error) for t in found)} failed), "
             f"{len(best)} on the front, {seconds:.0f} s"]
    for t in sorted(best, key=lambda t: t.objectives):
        params = ", ".join(f"{k} {v:.4g}" for k, v in t.params.items())
        objectives = ", ".join(f"{o.name} {v:.4g}" for o, v in zip(design.objectives, t.objectives))
        lines.append(f"  trial {t.number}: {params}: {objectives}")
    return lines


def main(argv=None):
    parser = argparse.ArgumentParser(prog="pidamper design", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("study", help="the design study file (TOML)")
    parser.add_argument("--out", default="design", help="output folder (resumed if it holds runs.csv)")
    parser.add_argument("--trials", type=int, help="designs to evaluate (default: the study's optimizer.trials)")
    parser.add_argument("--workers", type=int, help="processes or Dask workers (default: one per core)")
    parser.add_argument("--dask", action="store_true", help="use a local Dask cluster")
    parser.add_argument("--scheduler", help="Dask distributed scheduler address, e.g. tcp://host:8786")
    parser.add_argument("--fmu", help="the building FMU (default: build or reuse dist/DampedShearBuilding<N>.fmu)")
    parser.add_argument("--page", action="store_true", help="then write OUT/README.md, the answer page of the "
                        "study's [page] (design.page)")
    args = parser.parse_args(argv)
    for name in ("workers", "trials"):
        value = getattr(args, name)
        if value is not None and value < 1:
            parser.error(f"argument --{name}: {value} is not allowed: at least 1")
    design = design_file.load(args.study)
    if args.page and not design.page:
        raise StudyError(design.source, "page", "(missing)", "a [page] table (building = an assessment study file "
                         "...) for --page")
    Path(args.out).mkdir(parents=True, exist_ok=True)
    journal = Path(args.out) / "runs.csv"
    held = max(0, sum(1 for _ in journal.open()) - 1) if journal.is_file() else 0
    t0 = time.perf_counter()
    report = lambda text: print(f"pidamper design: {text}", file=sys.stderr, flush=True)  # noqa: E731
    found = search.search(design, args.out, args.workers, args.dask, args.scheduler, args.fmu, args.trials, report)
    best = write_trials(design, found, args.out)
    command = "pidamper design " + " ".join(shlex.quote(a) for a in (argv if argv is not None else sys.argv[1:]))
    seconds = time.perf_counter() - t0
    print("\n".join(summary(design, found, best, seconds) + [f"  ({command})"]))
    ran = sum(1 for _ in journal.open()) - 1 - held
    log_invocation(args.out, command, len(found), held, ran, seconds, args.workers or os.cpu_count(), args.dask
                   or bool(args.scheduler))
    if args.page:
        from . import page

        page.write(design, found, args.out, args.workers, args.dask, args.scheduler, args.fmu, command)
        print(f"pidamper design: the page is {Path(args.out) / 'README.md'}")
    return 0


def cli_main(argv=None):
    """pidamper design: main(argv), a study file's error printed with exit status 2."""
    try:
        return main(argv)
    except (StudyError, FileNotFoundError) as err:
        print(f"pidamper design: error: {err}", file=sys.stderr)
        return 2

"""The answer page of a design study (docs/design/<name>/README.md, its figures and CSVs), written by
`pidamper design STUDY --page` after the search: the front; the chosen designs (the front's best
drift within each mass cap of [page] masses) each against the tuned mass damper of the same mass
(Den Hartog's and Warburton's rules, pidamper.tuning) and the bare building, on

(a) the paper's cases on the building: resonance (a harmonic ground motion at w_1) and the free decay
    that follows it (the equivalent damping ratio of the paper's logarithmic decrement, measures);
(b) the study's own motions, and a sweep at stiffness factors 0.7..1.3 (the robustness curves);
(c) a recorded set on the yielding building of [page] building, each record scaled to each [page] sa
    at T1, with paired-bootstrap intervals over the records; and the evaluation criteria of the
    benchmark control problem for seismically excited nonlinear buildings (Ohtori, Christenson,
    Spencer and Dyke 2004, J. Eng. Mech. 130(4), 366-385) under the substitutes of OHTORI.

Every run goes through the study's journal (OUT/runs.csv), so the page resumes like the search.
"""
import csv
import math
import platform
from pathlib import Path

import numpy as np

from pidamper_physics import Params
from pidamper_physics.impact import MATERIAL_DEFAULTS

from .. import tuning
from ..assessment.bootstrap import paired
from ..forcing import Forcing, ground_motion
from ..machine import cpu_model
from ..studies.runner import Pool, Table
from . import excitations, search

#: the stiffness factors of the robustness curves
DETUNING = (0.7, 0.8, 0.9, 1.0, 1.1, 1.2, 1.3)
#: Ohtori et al. (2004)'s records for the 9-storey LA building and the FEMA P-695 far-field
#: record (ID, component) that stands for each here, with why
OHTORI = (
    ("El Centro 1940 (Imperial Valley)", 6, "a", "Imperial Valley 1979, El Centro Array #11: the same fault system "
                                                 "and town, recorded 39 years later (the 1940 record is not in the set)"),
    ("Hachinohe 1968 (Tokachi-oki)", 19, "a", "Chi-Chi 1999, CHY101: the set's largest far-field event (M 7.6), long "
                                              "and rich in long periods like the M 8.2 subduction record it stands for"),
    ("Northridge 1994 (Sylmar)", 1, "a", "Northridge 1994, Beverly Hills - Mulhol: the same event; Sylmar is a "
                                         "near-field record, not in the far-field set"),
    ("Kobe 1995 (JMA)", 8, "a", "Kobe 1995, Shin-Osaka: the same event; JMA Kobe is a near-field record, not in the "
                                "far-field set"),
)
#: Ohtori et al. (2004)'s criteria computed here: (what, the run's metric)
OHTORI_J = {"J1": ("peak drift ratio", "peak_drift"), "J2": ("peak floor acceleration", "peak_accel"),
            "J3": ("peak base shear", "peak_base_shear"), "J4": ("normed (RMS) drift ratio", "rms_drift"),
            "J5": ("normed floor acceleration", "rms_accel"), "J6": ("normed base shear", "rms_base_shear"),
            "J7": ("peak ductility", "ductility"),
            "J8": ("dissipated energy (the storeys' total hysteretic energy; the benchmark takes the largest "
                   "element's, each over its yield force times its yield drift)", "energy_hysteretic"),
            "J9": ("storeys that yielded (the benchmark's plastic connections)", "yielded"),
            "J10": ("normed (RMS) ductility", "rms_ductility"),
            "J11": ("the damper's peak force on its floor over the building's weight (not a ratio)", "damper_force"),
            "J12": ("the damper's peak stroke over the uncontrolled roof's peak displacement", "stroke")}


def chosen(design, found, masses):
    """{label: params}: the front's least first objective with mu within each cap (each design once)."""
    best = search.front(found)
    out = {}
    for cap in masses:
        within = [t for t in best if t.params.get("mu", design.damper.get("mu", 0.0)) <= cap + 1e-12]
        if within:
            pick = min(within, key=lambda t: t.objectives[0])
            if pick.params not in out.values():
                out[f"design {len(out) + 1} (trial {pick.number})"] = dict(pick.params)
    return out


def rivals(design, designs):
    """{label: params}: the Den Hartog and Warburton TMD of each design's mass ratio."""
    out = {}
    values = search.values_of(design, None, 1.0)
    for label, params in designs.items():
        mu = params.get("mu", design.damper.get("mu"))
        for rule, name in (("den-hartog", "Den Hartog"), ("warburton", "Warburton")):
            tmd = tuning.configuration(values, mu, rule)
            out[f"{name} TMD, mu {mu:.3g}"] = {**{k: v for k, v in params.items() if k not in ("FR", "d", "zeta_p")},
                                               **tmd}
    return out


def _by(todo, rows):
    """{(label, member, stiffness): row} of the tasks `todo` ({key: task})."""
    return {(t["design"], t["member"], t["stiffness"]): rows[k] for k, t in todo.items()}


def _ratio(got, label, metric, member, stiffness=1.0):
    return float(got[label, member, stiffness][metric]) / float(got["bare", member, stiffness][metric])


def free_decay(design, params, fmu, amplitude=0.1, periods=20):
    """The equivalent damping ratio (measures: 'exact' averaging of the first five cycles) of the
    free decay after `periods` of a harmonic ground motion at w_1, theta the damper floor's x / L2;
    nan when the motion stops before six cycles (an impact damper can stop it)."""
    from ..measures import damping_ratio
    from ..running.fmu import find_fmu
    from ..running.stepper import FmuStepper
    from ..running.variants import for_model
    from ..running.unpacked import unpacked

    period = design.period
    h = design.step
    t = h * np.arange(int(round(periods * period / h)) + 1)
    table = np.concatenate([amplitude * np.sin(2 * math.pi / period * t), [0.0] * 2])
    times = np.concatenate([t, [t[-1] + h, 1e9]])
    path = str(find_fmu(fmu, storeys=design.storeys))
    values = for_model(unpacked(path)[1].modelName, search.values_of(design, params, 1.0))
    with FmuStepper(path, values, Forcing("table", {}, table=(times, table), target="a_g")) as stepper:
        for k in range(1, len(t)):
            stepper.advance(t[k])
        try:
            ratios, _ = damping_ratio(stepper, period)
        except (RuntimeError, ValueError):
            return math.nan
    return ratios["exact"]


def write(design, found, out, workers=None, dask=False, scheduler=None, fmu=None, command=""):
    """The page (module doc) into OUT/README.md with its figures; its lines."""
    out, page = Path(out), design.page
    designs = chosen(design, found, page["masses"])
    tmds = rivals(design, designs)
    everyone = {"bare": None, **designs, **tmds}
    yielding = page["building"]
    period = design.period
    resonance = excitations.members({"resonance": {"kind": "harmonic", "ratios": [1.0], "amplitude": 0.1,
                                                   "periods": 40}}, period, design.step, design.folder, design.source)
    sweep = [m for m in design.members if m.excitation == page["sweep"]][:1]
    records = ground_motion.suite({"set": page["records"], **({"records": page["ids"]} if "ids" in page else {})})
    at_levels = [m for sa in page["sa"] for m in excitations.scaled(f"sa {sa:g}", records, period, sa=sa)]
    quake = {k: v for k, v in everyone.items() if v is None or not k.startswith("Den Hartog")}
    jobs = {"motions": search.run_tasks(design, everyone),
            "resonance": search.run_tasks(design, everyone, resonance, (1.0,)),
            "detuning": search.run_tasks(design, everyone, sweep, DETUNING),
            "records": search.run_tasks(design, quake, at_levels, (1.0,), yielding)}
    journal = Table(out / "runs.csv", list(search.RUN_COLUMNS))
    got = {}
    try:
        with Pool(_fmu(design, fmu), workers, dask, scheduler) as pool:
            for name, todo in jobs.items():
                search.run_missing(pool, journal, todo)
                got[name] = _by(todo, journal.done)
    finally:
        journal.close()
    decay = {label: free_decay(design, params, fmu) for label, params in everyone.items()}
    lines = _lines(design, found, designs, tmds, got, decay, records, page, out, command)
    (out / "README.md").write_text("\n".join(lines) + "\n")
    return lines


def _fmu(design, fmu):
    from ..running.fmu import find_fmu

    return str(find_fmu(fmu, storeys=design.storeys))


def _invocation_lines(out):
    """The searches that filled the journal (OUT/invocations.csv, command.log_invocation)."""
    path = out / "invocations.csv"
    if not path.is_file():
        return []
    with path.open(newline="") as handle:
        rows = list(csv.DictReader(handle))
    lines = ["The searches that filled this folder's journal (runs.csv), as each invocation logged itself "
             "(invocations.csv); a search's figures are its own only when its journal held no runs at its start"
             + ("; the speed on the process pool and on Dask from scratch: [speed.md](speed.md)" if (
                 out / "speed.md").exists() else "") + ":", "",
             "| started | designs | runs held at start | runs ran | search [s] | designs / s | workers | machine |",
             "|---|---:|---:|---:|---:|---:|---|---|"]
    for r in rows:
        seconds = float(r["search_s"])
        rate = f"{int(r['designs']) / seconds:.3f}" if not int(r["runs_held"]) and seconds > 0 else "(resumed)"
        lines.append(f"| {r['started']} | {r['designs']} | {r['runs_held']} | {r['runs_ran']} | {r['search_s']} | "
                     f"{rate} | {r['workers']} ({r['executor']}) | {r['machine']} |")
    return lines + [""]


def _lines(design, found, designs, tmds, got, decay, records, page, out, command):
    best = search.front(found)
    names = list(design.search)
    lines = [f"# Design: {design.name}", "", design.description, "",
             f"Written by `{command}` on {platform.machine()} ({cpu_model()}), Python {platform.python_version()}; "
             "the runs of the page itself are journaled with the search's.", "", *_invocation_lines(out),
             "## The search", "",
             f"{len(found)} designs ({sum(t.feasible for t in found)} feasible), {len(best)} on the front; "
             "objectives " + ", ".join(f"{o.name} (" + ("the mass ratio" if o.metric == "mu" else
                                                       f"{o.metric}, {o.statistic} over " + ", ".join(o.excitations))
                                       + ")" for o in design.objectives)
             + ", each run's over the bare building's, the worst of the storeys' stiffness x "
             + ", ".join(f"{s:g}" for s in design.variants) + "; constraints "
             + (", ".join(f"{k} {v}" for k, v in design.constraints.items()) or "none") + ".", "",
             "![front](front.png)", "",
             "| trial | " + " | ".join(names) + " | " + " | ".join(o.name for o in design.objectives) + " |",
             "|---" * (1 + len(names) + len(design.objectives)) + "|"]
    for t in sorted(best, key=lambda t: t.objectives[0]):
        lines.append(f"| {t.number} | " + " | ".join(f"{t.params[n]:.4g}" for n in names) + " | "
                     + " | ".join(f"{v:.3f}" for v in t.objectives) + " |")
    _plot_front(design, found, best, out / "front.png")
    lines += ["", "## The chosen designs and the tuned mass dampers of the same mass", "",
              "The front's least " + design.objectives[0].name + f" with mu within each of {page['masses']}, "
              "and for each the Den Hartog TMD (harmonic force) and the Warburton TMD (white-noise ground "
              "motion) of the same mass ratio on the same floor (FR and zeta_p by the rules on the first mode's "
              "effective mass ratio; stops out of reach).", "",
              "| configuration | mu | FR | d [m] | e | zeta_p |", "|---|---|---|---|---|---|"]
    for label, params in {**designs, **tmds}.items():
        lines.append(f"| {label} | {params.get('mu', design.damper.get('mu')):.4g} | {params['FR']:.4g} | "
                     f"{params.get('d', design.damper.get('d', 0)):.4g} | {params.get('e', design.damper.get('e', 0.5)):.3g} | "
                     f"{params.get('zeta_p', design.damper.get('zeta_p', 0.0)):.3g} |")
    labels = [k for k in {**designs, **tmds}]
    lines += ["", "### (a) The paper's cases on the building", "",
              "Resonance: a harmonic ground motion of 0.1 m/s2 at w_1 for 40 periods, the peak drift and floor "
              "acceleration over the bare building's. Free decay: after 20 periods of it, the ground at rest, the "
              "equivalent damping ratio of the first five cycles of the damper floor's motion (the paper's "
              "logarithmic decrement, exact averaging); the bare building's is its own.", "",
              "| configuration | peak drift / bare | peak accel / bare | stroke [m] | damping ratio (free decay) |",
              "|---|---|---|---|---|", f"| bare | 1 | 1 | - | {decay['bare']:.4f} |"]
    for label in labels:
        row = got["resonance"][label, 0, 1.0]
        lines.append(f"| {label} | {_ratio(got['resonance'], label, 'peak_drift', 0):.3f} | "
                     f"{_ratio(got['resonance'], label, 'peak_accel', 0):.3f} | {float(row['stroke']):.3f} | "
                     f"{decay[label]:.4f} |")
    lines += ["", "### (b) The study's motions, and the robustness curves", "",
              "Each motion's peak drift over the bare building's, worst of the stiffness variants; the largest "
              "stroke and contact pressure over every run, and the impacts of all of them.", "",
              "| configuration | " + " | ".join(sorted({m.excitation for m in design.members}, key=[
                  m.excitation for m in design.members].index)) + " | stroke [m] | contact pressure [MPa] | impacts |",
              "|---" * (4 + len({m.excitation for m in design.members})) + "|"]
    kinds = sorted({m.excitation for m in design.members}, key=[m.excitation for m in design.members].index)
    for label in labels:
        cells = []
        for kind in kinds:
            members = [i for i, m in enumerate(design.members) if m.excitation == kind]
            cells.append(max(np.mean([_ratio(got["motions"], label, "peak_drift", i, s) for i in members])
                             for s in design.variants))
        rows = [got["motions"][label, i, s] for i in range(len(design.members)) for s in design.variants]
        lines.append(f"| {label} | " + " | ".join(f"{c:.3f}" for c in cells)
                     + f" | {max(float(r['stroke']) for r in rows):.3f} | "
                     f"{max(float(r['contact_pressure']) for r in rows) / 1e6:.2f} | "
                     f"{sum(int(float(r['impacts'])) for r in rows)} |")
    _plot_detuning(got["detuning"], labels, out / "detuning.png")
    lines += ["", "![detuning](detuning.png)", "",
              "Robustness: the sweep's peak drift over the bare building's (the same stiffness) as the storeys' "
              "stiffness goes from 0.7 to 1.3 times the design's (T1 from 1.20 to 0.88 times).", "",
              "| configuration | " + " | ".join(f"x {s:g}" for s in DETUNING) + " |", "|---" * (1 + len(DETUNING)) + "|"]
    for label in labels:
        lines.append(f"| {label} | " + " | ".join(f"{_ratio(got['detuning'], label, 'peak_drift', 0, s):.3f}"
                                                 for s in DETUNING) + " |")
    quake = {}
    lines += _records_lines(design, got["records"], [k for k in labels if not k.startswith("Den Hartog")], records,
                            page, quake, _weight(design, page["building"]))
    return (lines + _answer_lines(design, designs, got, quake, page, len(records))
            + _found_lines(design, best, designs, got) + _assessment_lines(design, designs, page.get("assessment")))


def _found_lines(design, best, designs, got):
    """What the front's designs are: their clearance and dashpot against the searched ranges, and how
    often the chosen ones hit their stops on the study's motions."""
    runs = [got["motions"][label, i, s] for label in designs for i in range(len(design.members))
            for s in design.variants]
    hit = sum(int(float(r["impacts"])) > 0 for r in runs)
    out = ["", f"What the search found: the chosen designs hit their stops in {hit} of their {len(runs)} runs of the "
           "study's motions"]
    for name in ("d", "zeta_p", "e"):
        if name in design.search:
            r = design.search[name]
            values = [t.params[name] for t in best]
            out[-1] += f"; the front's {name} spans {min(values):.3g} to {max(values):.3g} (searched {r.low:g} to {r.high:g})"
    if runs and hit <= 0.1 * len(runs):
        out[-1] += (". The best pendulum dampers the search found are tuned mass dampers, their dashpots near the "
                    "TMD rules', whose stops bound the swing.")
    else:
        out[-1] += ". The best designs the search found rely on their impacts."
    return out


def _answer_lines(design, designs, got, quake, page, n):
    """The conclusion: each design beside the Warburton TMD of its mass, the peak drift over the bare
    building's in every case (lower is better); n records per level."""
    head = ["resonance", "sweep, worst of x " + ", ".join(f"{s:g}" for s in design.variants),
            "detuning 0.7-1.3, worst"] + [f"records at {sa:g} g (90 %)" for sa in page["sa"]] + ["stroke [m]"]
    lines = ["", "## The answer", "", "Peak drift over the bare building's (lower is better) for each design and the "
             "Warburton TMD of its mass; the largest stroke of every run (the study's motions and the records).", "",
             "| configuration | " + " | ".join(head) + " |", "|---" * (1 + len(head)) + "|"]
    sweep = [i for i, m in enumerate(design.members) if m.excitation == page["sweep"]][0]
    room = design.constraints.get("stroke")
    wins = []
    for label, params in designs.items():
        mu = params.get("mu", design.damper.get("mu"))
        rival = f"Warburton TMD, mu {mu:.3g}"
        cells = {}
        for who in (label, rival):
            rows = ([got["motions"][who, i, s] for i in range(len(design.members)) for s in design.variants]
                    + [row for (name, _, _), row in got["records"].items() if name == who])
            cells[who] = ([_ratio(got["resonance"], who, "peak_drift", 0),
                           max(_ratio(got["motions"], who, "peak_drift", sweep, s) for s in design.variants),
                           max(_ratio(got["detuning"], who, "peak_drift", 0, s) for s in DETUNING)]
                          + [quake[who, sa] for sa in page["sa"]] + [max(float(r["stroke"]) for r in rows)])
            lines.append(f"| {who} | " + " | ".join(c.text() if hasattr(c, "text") else f"{c:.3f}"
                                                    for c in cells[who]) + " |")
        versus = []
        for j, sa in enumerate(page["sa"]):
            members = list(range(j * n, (j + 1) * n))

            def statistic(rows, members=members, label=label, rival=rival):
                return [np.mean([_ratio(got["records"], label, "peak_drift", members[r]) for r in rows])
                        / np.mean([_ratio(got["records"], rival, "peak_drift", members[r]) for r in rows])]

            versus.append(paired(statistic, n, n=1000, seed=0)[0])
        mine, theirs = cells[label], cells[rival]
        plain = [a / b for a, b in zip(mine[:3], theirs[:3])]
        lines.append(f"| {label} over its TMD | " + " | ".join([f"{v:.3f}" for v in plain] + [v.text() for v in versus])
                     + f" | {mine[-1] / theirs[-1]:.3f} |")
        ties = [f"{sa:g} g" for sa, v in zip(page["sa"], versus) if v.lo <= 1.0 <= v.hi]
        wins.append(f"- {label} (mu {mu:.3g}) against the Warburton TMD of its mass: its drift is "
                    + ", ".join(f"{v:.2f} times the TMD's {h.split(',')[0]}" for v, h in zip(plain, head))
                    + "; on the records " + ", ".join(f"{v.text()} at {sa:g} g" for v, sa in zip(versus, page["sa"]))
                    + (f" (1 within the interval at {' and '.join(ties)}: no difference the records can tell)" if ties
                       else "") + f"; its stroke {mine[-1]:.2f} m against the TMD's {theirs[-1]:.2f} m"
                    + (f", beyond the {room:g} m of room the study allows" if room and theirs[-1] > room else "")
                    + ".")
    return lines + [""] + wins


def _records_lines(design, got, labels, records, page, summary, weight):
    """The recorded set's lines; summary[(label, sa)] gets the peak drift ratio's Interval; weight [N]
    the building's (Ohtori's J11)."""
    n = len(records)
    lines = ["", "### (c) Recorded motions on the yielding building", "",
             f"The {page['records']} set ({n} components), each scaled to Sa(T1 = {design.period:.3g} s, 5 %) = "
             + " and ".join(f"{sa:g} g" for sa in page["sa"]) + f" on the yielding building of {page['file']}; "
             "the mean over the records of each run's ratio to the bare building's, with the 90 % paired-bootstrap "
             "interval over the records (1000 resamples). Warburton's TMD is the earthquake rule.", "",
             "| configuration | Sa [g] | peak drift | peak floor accel | RMS drift | collapses (bare) | impacts | "
             "largest contact pressure [MPa] | largest stroke [m] |", "|---|---|---|---|---|---|---|---|---|"]
    for j, sa in enumerate(page["sa"]):
        for label in labels:
            members = range(j * n, (j + 1) * n)

            def statistic(rows, label=label, members=list(members)):
                return [np.mean([_ratio(got, label, m, members[r]) for r in rows])
                        for m in ("peak_drift", "peak_accel", "rms_drift")]

            found = paired(statistic, n, n=1000, seed=0)
            summary[label, sa] = found[0]
            collapses = sum(int(float(got[label, i, 1.0]["collapsed"])) for i in members)
            bare = sum(int(float(got["bare", i, 1.0]["collapsed"])) for i in members)
            runs = [got[label, i, 1.0] for i in members]
            lines.append(f"| {label} | {sa:g} | " + " | ".join(x.text() for x in found) + f" | {collapses} ({bare}) | "
                         f"{sum(int(float(r['impacts'])) for r in runs)} | "
                         f"{max(float(r['contact_pressure']) for r in runs) / 1e6:.2f} | "
                         f"{max(float(r['stroke']) for r in runs):.3f} |")
    return lines + ["", _materials_text(design, got, labels), ""] + _ohtori_lines(got, labels, records, page, weight)


def _weight(design, building):
    """The weight [N] of the building of the [building] table `building` (its floors)."""
    p = Params.from_variables(search.values_of(design, None, 1.0, building))
    return p.g * p.building.total_mass


def _ohtori_lines(got, labels, records, page, weight):
    """Ohtori et al. (2004)'s evaluation criteria on the substitutes of OHTORI: each the largest over
    those records and the page's intensities of the configuration's value over the bare building's."""
    n = len(records)
    lines = ["#### The benchmark's evaluation criteria (Ohtori et al. 2004)", "",
             "Each criterion is the controlled building's value over the uncontrolled one's in the same record, the "
             "largest over the records and the page's intensities (the benchmark scales its records by 0.5, 1 and 1.5; "
             "here they are scaled to the site's Sa): " + "; ".join(f"{j} {text}" for j, (text, _) in OHTORI_J.items())
             + ". The damper's force on its floor is its wire's, its dashpot's and a ridden stop's at the "
             "communication points, or at an impact the peak contact force plus the wire's at the stop. The storeys "
             "are the benchmark's elements here: a storey's ductility is its drift over its yield drift storey[k].Fy / "
             "storey[k].k. The benchmark's records and their substitutes from the set (component a):", "",
             "| benchmark record | substitute | why |", "|---|---|---|"]
    names = [r.name for r in records]
    picks = []
    for title, rid, comp, why in OHTORI:
        index = next((i for i, r in enumerate(records) if r.meta.get("record_id") == rid
                      and r.meta.get("component") == comp), None)
        picks.append(index)
        lines.append(f"| {title} | {names[index] if index is not None else '(not found)'} | {why} |")
    members = [j * n + i for j in range(len(page["sa"])) for i in picks if i is not None]
    if not members:
        return lines + ["", "None of the substitutes is among the page's records ([page] ids): no criteria."]
    lines += ["", "| configuration | " + " | ".join(OHTORI_J) + " |", "|---|" + "---|" * len(OHTORI_J)]
    for label in labels:
        values = [max(_criterion(got, label, metric, m, weight) for m in members) for _, metric in OHTORI_J.values()]
        lines.append(f"| {label} | " + " | ".join("n/a" if math.isnan(v) else f"{v:.3f}" for v in values) + " |")
    return lines + ["", "n/a: the uncontrolled building's value is zero (no storey yielded) or the storeys do not "
                    "yield."]


def _criterion(got, label, metric, member, weight):
    """One criterion in one run: the configuration's metric over the bare building's (J11: the damper's
    force over the weight; J12: the stroke over the bare roof's displacement); nan where the bare value
    is zero or nan."""
    mine, bare = got[label, member, 1.0], got["bare", member, 1.0]
    if metric == "damper_force":
        return float(mine[metric]) / weight
    bottom = float(bare["roof_disp" if metric == "stroke" else metric])
    return float(mine[metric]) / bottom if bottom > 0 else math.nan


def _assessment_lines(design, designs, assessment):
    """Which configuration of the [page] assessment study is each chosen design and its Warburton TMD."""
    if not assessment:
        return []
    confs = assessment["configurations"]
    lines = ["", "## The chosen designs' FEMA P-58 assessment", "",
             "The expected annual loss and the collapse intensity are not objectives of the search (one evaluation "
             "is a whole FEMA P-58 run of some 800 runs of the yielding building); the chosen designs and the "
             f"Warburton TMD of each one's mass go through `pidamper assess {assessment['file']}` instead, as these "
             "of its configurations (matched by their parameters):", "",
             "| chosen design | its configuration | the Warburton TMD of its mass | its configuration |",
             "|---|---|---|---|"]
    missing = "(not in the study: add it)"
    for label, params in designs.items():
        mine = {**design.damper, **params}
        mu = mine.get("mu", 0.0)
        same = next((n for n, c in confs.items() if all(_same(c.get(k), v) for k, v in mine.items())), missing)
        tmd = next((n for n, c in confs.items() if c.get("tmd") == "warburton" and _same(c.get("mu"), mu)), missing)
        lines.append(f"| {label} | {same} | Warburton TMD, mu {mu:.3g} | {tmd} |")
    return lines


def _same(a, b):
    """Two study values alike: numbers to 1e-12 relative, anything else equal."""
    numbers = all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in (a, b))
    return math.isclose(a, b, rel_tol=1e-12) if numbers else a == b


def _materials_text(design, got, labels):
    """The largest contact force and pressure of the recorded runs, against the study's limits."""
    runs = [row for (name, _, _), row in got.items() if name in labels]
    force = max(float(r["impact_force"]) for r in runs)
    pressure = max(float(r["contact_pressure"]) for r in runs)
    plastic = sum(int(float(r["impacts_plastic"])) for r in runs)
    stops = ", ".join(f"{k} = {design.damper.get(k, MATERIAL_DEFAULTS[k]):g}" for k in ("E1", "nu1", "E2", "nu2", "R",
                                                                                       "S_y"))
    limit = design.constraints.get("contact_pressure")
    if not design.damper.get("R", MATERIAL_DEFAULTS["R"]):
        return (f"Impacts and materials: no contact model (R = 0): the impacts are instantaneous, without a contact "
                "force or pressure.")
    return (f"Impacts and materials: the largest contact force of these runs is {force / 1e3:.0f} kN and the largest "
            f"contact pressure {pressure / 1e6:.2f} MPa (Hertz contact, {stops}; the FMU's defaults where [damper] is "
            "silent)"
            + (f", {'within' if pressure <= limit else 'beyond'} the {limit / 1e6:g} MPa the study allows" if limit
               else "") + f"; {plastic} impacts yielded the softer body (at its S_y).")


def _plot_front(design, found, best, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    feasible = [t for t in found if t.feasible]
    x_of = (lambda t: t.params["mu"]) if "mu" in design.search else (lambda t: t.params[next(iter(design.search))])
    ax.scatter([x_of(t) for t in feasible], [t.objectives[0] for t in feasible], s=8, c="0.7", label="feasible")
    ax.scatter([x_of(t) for t in best], [t.objectives[0] for t in best], s=18, c="C0", label="front")
    ax.set_xlabel("mu" if "mu" in design.search else next(iter(design.search)))
    ax.set_ylabel(f"{design.objectives[0].name} (over the bare building's)")
    ax.grid(True, alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _plot_detuning(got, labels, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    for i, label in enumerate(labels):
        ax.plot(DETUNING, [_ratio(got, label, "peak_drift", 0, s) for s in DETUNING], "o-" if "design" in label
                else "--", color=f"C{i}", label=label, ms=3)
    ax.axhline(1.0, color="k", lw=0.8)
    ax.set_xlabel("storeys' stiffness / the design's")
    ax.set_ylabel("peak drift / bare building's (sweep)")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)



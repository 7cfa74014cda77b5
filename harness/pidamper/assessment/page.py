"""The page of an assessment (pidamper assess): OUT/README.md and its figures (stripes, IDA to
collapse, fragility, pushover, repair-complete curves) from what the study computed.  Nothing here
runs or fits; `study` is an assess.Study."""
import math
import platform
from pathlib import Path

import numpy as np

from . import demands, fragility
from .analysis import demand_matrix
from ..machine import cpu_model


def _panels(plt, n):
    """A figure with one panel per configuration, axes shared."""
    fig, axes = plt.subplots(1, n, figsize=(5.2 * n, 4.2), sharex=True, sharey=True)
    return fig, np.atleast_1d(axes)


def plot_ida(study, rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    confs = list(study.configurations)
    fig, axes = _panels(plt, len(confs))
    for ax, conf in zip(axes, confs):
        drift = demand_matrix(study, rows, conf)
        for line in drift:
            ax.plot(100 * line, study.levels, color="0.6", lw=0.8, marker=".", ms=3)
        ax.plot(100 * np.median(drift, axis=0), study.levels, color="C3", lw=2, label="median")
        for state, limit in study.damage_states.items():
            ax.axvline(100 * limit, color="k", ls=":", lw=0.8)
            ax.text(100 * limit, study.levels[-1], f" {state}", va="top", fontsize=8)
        ax.set_title(f"{conf}: one line per record")
        ax.set_xlabel("peak inter-storey drift ratio [%]")
        ax.set_xscale("log")
        ax.grid(alpha=0.3)
    axes[0].set_ylabel(study.label)
    axes[0].legend(loc="lower right")
    fig.suptitle(f"Incremental dynamic analysis (stripes): {study.name}")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_fragility(study, fits, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    states = list(study.damage_states)
    fig, axes = plt.subplots(1, len(states), figsize=(4.6 * len(states), 4.0), sharey=True)
    axes = np.atleast_1d(axes)
    levels = np.asarray(study.levels)
    for ax, state in zip(axes, states):
        for i, conf in enumerate(study.configurations):
            sf = fits[conf][state]
            if sf.fit is None:
                ax.plot(levels, sf.exceed.mean(axis=0), "x", color=f"C{i}", label=f"{conf} (no fit: {sf.failed})")
                continue
            fragility.plot_fragility(ax, sf.fit, sf.band, label=conf, data=(levels, sf.exceed.mean(axis=0)),
                                     color=f"C{i}")
        ax.set_title(f"{state}: drift ratio >= {study.damage_states[state]:g}")
        ax.set_xlabel(study.label)
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("probability of exceedance")
    axes[0].legend(loc="lower right")
    fig.suptitle("Lognormal fragility by maximum likelihood over stripes; bands: 5-95 % bootstrap over records")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


NO_FIT = {"none": "no run reached it", "all": "every run reached it at every stripe",
          "separated": "the stripes separate reached from not reached exactly (beta -> 0)",
          "single_level": "all runs at one level", "decreasing": "exceedance does not rise with intensity",
          "half": "fewer than half of the records collapsed"}


def _scaling_text(study, traces):
    if traces is not None and study.ida["stripes"] == "interpolate":
        return "each record scaled by its own intensity to each level (its demands there read off its IDA curve)"
    if "set" in study.suite and not study.ida:
        return "the set scaled collectively (FEMA P-695 6.2.2: its median intensity brought to each level)"
    return "each record scaled by its own intensity to each level"


def _interpolated(study, traces):
    return traces is not None and study.ida["stripes"] == "interpolate"


def runs_text(study, rows, traces):
    """What was run, counted once for the page and the console: every IDA run, and every stripe run
    unless the stripes were read off the IDA curves."""
    confs = len(study.configurations)
    stripes = f"{len(study.records)} records x {len(study.levels)} levels x {confs} configurations"
    if traces is None:
        return f"{len(rows)} runs ({stripes})"
    ida = sum(len(r["runs"]) for r in traces)
    of = f"IDA of {len(study.records)} records x {confs} configurations"
    if _interpolated(study, traces):
        return f"{ida} runs ({of}; the {len(rows)} stripe demands interpolated on the IDA curves)"
    ran = sum(1 for r in rows if np.isfinite(r["cpu_s"]))
    return (f"{ida + ran} runs ({ida} in the {of}, {ran} at the stripes: {stripes}, the other {len(rows) - ran} "
            "stripe runs the IDA's at that intensity)")


def _runs_text(study, rows, traces):
    """What was run (runs_text), and its CPU per run."""
    if _interpolated(study, traces):
        cpu = np.array([r["cpu_s"] for r in traces]) / np.array([len(r["runs"]) for r in traces])
        return (f"{runs_text(study, rows, traces)}, {cpu.mean():.2f} s CPU per run (median per record "
                f"{np.median(cpu):.2f} s)")
    cpu = np.array([r["cpu_s"] for r in rows if np.isfinite(r["cpu_s"])])
    per = "stripe run" if traces is not None else "run"
    return f"{runs_text(study, rows, traces)}, {cpu.mean():.2f} s CPU per {per} (median {np.median(cpu):.2f} s)"


def maf_text(fits, state, conf, value, unit=""):
    """A configuration's mean annual frequency of a damage state, or why it has none (NO_FIT)."""
    fit = fits[conf][state]
    if fit.fit is None:
        return f"none (no fit: {NO_FIT.get(fit.failed, fit.failed)})"
    return f"{value:.3g}{unit}"


def ratio_text(fits, state, conf, first, value):
    """A configuration's MAF over the first's, or why there is none."""
    missing = [c for c in dict.fromkeys((first, conf)) if fits[c][state].fit is None]
    return f"none (no fit for {' and '.join(missing)})" if missing else f"{value:.3g}"


def write_page(study, rows, fits, risks, out, command, wall, workers, extra=(), stages=(), intervals=None,
               traces=None):
    out = Path(out)
    plot_ida(study, rows, out / "ida.png")
    plot_fragility(study, fits, out / "fragility.png")
    confs = list(study.configurations)
    plot_hazard(study, out / "hazard.png")
    lines = [f"# Assessment: {study.name}", "", study.description, "",
             *(["**What this study is and is not.** " + study.scope, ""] if study.scope else []),
             *(["## What changed from the last page, and why", "", study.changes, ""] if study.changes else []),
             f"Written by `{command}` on {platform.machine()} ({cpu_model()}), Python {platform.python_version()}: "
             f"{_runs_text(study, rows, traces)}, {wall:.0f} s wall on {workers} worker(s)." + (" Its cost on 1 and 2 workers and the extrapolation to more: "
             "[scaling.md](scaling.md) (it names the command that wrote it)." if (out / "scaling.md").exists() else "")
             + (" Wall time by stage: " + ", ".join(f"{name} {sec:.0f} s" + (
                 f" (its journal held {held} finished runs at the start: this invocation ran the rest)" if held
                 else "") for name, sec, held in stages) + "." if stages else ""), "",
             f"Intensity: {study.label}, stripes {', '.join(f'{v:g}' for v in study.levels)}; " + _scaling_text(study, traces)
             + ". Demand: peak inter-storey drift ratio, the building FMU's exact running maximum "
             "(located between the communication points; the pendulum primary's over them) (storey "
             f"heights {', '.join(f'{h:g}' for h in study.heights)} m). Damage states: "
             + ", ".join(f"{k} at {v:g}" for k, v in study.damage_states.items()) + ".", "",
             "![IDA](ida.png)", "", "![fragility](fragility.png)", "",
             "## Fragility (lognormal, maximum likelihood over stripes, Baker 2015)", "",
             "| damage state | configuration | median [" + study.unit + "] | dispersion beta | "
             "bootstrap 90 % of the median |", "|---|---|---:|---:|---|"]
    for state in study.damage_states:
        for conf in confs:
            sf = fits[conf][state]
            if sf.fit is None:
                lines.append(f"| {state} | {conf} | no fit: {NO_FIT.get(sf.failed, sf.failed)} | | |")
                continue
            lo, hi = np.percentile(sf.band.theta, [5, 95]) if len(sf.band.theta) else (math.nan, math.nan)
            lines.append(f"| {state} | {conf} | {sf.fit.theta:.4g} | {sf.fit.beta:.3g} | {lo:.4g} to {hi:.4g} |")
    lines += ["", "## Risk: mean annual frequency of exceedance", "", f"Hazard: {hazard_text(study)}.", "",
              "![hazard](hazard.png)", "",
              "| damage state | " + " | ".join(f"MAF {c} [1/yr]" for c in confs) + " | " +
              " | ".join(f"ratio {c} / {confs[0]}" for c in confs[1:]) + " |",
              "|---|" + "---:|" * (2 * len(confs) - 1)]
    for state, values, ratios in risks:
        ratio = {c: ratio_text(fits, state, c, confs[0], ratios[c]) for c in confs[1:]}
        lines.append(f"| {state} | " + " | ".join(maf_text(fits, state, c, values[c]) for c in confs) + " | " +
                     " | ".join(ratio[c] if ratio[c].startswith("none") else f"**{ratio[c]}**" for c in confs[1:])
                     + " |")
    if intervals and any(intervals.values()):
        lines += ["", f"Ratios with 90 % intervals (paired bootstrap over records, {study.bootstrap} resamples, "
                  "both configurations refitted on each draw):", "",
                  "| damage state | " + " | ".join(f"median ratio {c} / {confs[0]} | MAF ratio {c} / {confs[0]}"
                                                   for c in confs[1:]) + " | unfitted resamples |",
                  "|---|" + "---:|" * (2 * len(confs) - 1)]
        for state, per in intervals.items():
            if per:
                cells = [iv.text(3) for c in confs[1:] for iv in per[c]]
                unfitted = max(iv.unfitted for c in confs[1:] for iv in per[c])
                lines.append(f"| {state} | " + " | ".join(cells) + f" | {unfitted} |")
    lines += damper_lines(study, rows)
    lines += list(extra)
    interpolated = traces is not None and study.ida["stripes"] == "interpolate"
    lines += ["", ("Demands per record, stripe and configuration: `runs.parquet` (record and its metadata, level, "
                   "scale factor, configuration, PID-k, RID-k, PFA-k, PFV-k, collapsed, the damper's stroke, impacts "
                   "and largest impact speed, `interpolated` 0 where an IDA run was at the stripe); every IDA run's "
                   "demands: `ida.csv`." if interpolated else
                   "Demands per run: `runs.parquet` (and the journal `runs.csv`: record, level, configuration, "
                   "peak drift ratio and its storey, peak floor absolute acceleration [m/s2], peak particle stroke "
                   "[m], impacts, CPU [s]; a building's PID-k, RID-k, PFA-k, PFV-k and collapse).")
              , "", "## The study file", "", "```toml", study.text.strip(), "```", "",
              "## The command", "", "```sh", command, "```", ""]
    (out / "README.md").write_text("\n".join(lines))


#: the swing of the linear pendulum model's small-angle limit [rad] (pidamper_physics.validity)
SMALL_ANGLE = 0.4


def damper_lines(study, rows):
    """The page's section on each configuration with a particle: what it is (mass, floor, pendulum
    length, gap and the swing there, the stops) and what it did at each stripe (stroke, impacts and
    their speed, the largest contact force and its share of the damper floor's acceleration)."""
    from pidamper_physics import Params

    out = []
    for conf in study.configurations:
        p = Params.from_variables(study.start_values(conf))
        if p.mu <= 0.0:
            continue
        floor = p.floor + 1
        stops = (f"stops of E = {p.E2 / 1e6:.4g} MPa, nu = {p.nu2:g} met by a face of radius R = {p.R:g} m "
                 f"(E = {p.E1 / 1e9:.4g} GPa), Hertz's contact giving each impact's force" if p.materials else
                 "stops without materials (no contact forces: impacts count in the floor's acceleration only as "
                 "velocity jumps)")
        if not out:
            out += ["", "## The damper", ""]
        reduced = p.m * p.M / (p.m + p.M)  # the two-body impact's reduced mass [kg]
        period = 2.0 * math.pi / p.w2
        out += [f"`{conf}`: a particle of {p.m / 1e3:.4g} t ({100 * p.mu:g} % of the building's mass) on floor "
                f"{floor} (of {p.M / 1e3:.4g} t), hung as a pendulum of length L1 = g / w1^2 = {p.L1:.3g} m (frequency "
                f"ratio {p.FR:g} to the building's first mode), free to swing d = {p.d:g} m each way before it "
                f"meets its {stops}; restitution e = {p.e:g}. At the stops it has swung d / L1 = {p.d / p.L1:.3g} rad "
                f"(the linear pendulum holds to {SMALL_ANGLE:g} rad).", "",
                "| stripe | stroke median / max [m] | impacts median | fastest impact [m/s] | largest contact force "
                f"[kN] | it over floor {floor}'s mass [m/s2] | floor {floor}'s PFA median with it [m/s2] | its share "
                "(median) | the fastest impact's contact: duration [s] (of T1), peak pressure [MPa] |",
                "|---:|---:|---:|---:|---:|---:|---:|---:|---|"]
        for level in study.levels:
            at = [r for r in rows if r["configuration"] == conf and r["level"] == level]
            if not at:
                continue
            col = lambda key: np.array([float(r.get(key, math.nan)) for r in at])  # noqa: E731
            stroke, accel, pfa = col("stroke"), col("impact_accel"), col(f"PFA-{floor}")
            force = col("impact_force_max")
            share = np.nanmedian(accel / pfa) if np.any(np.isfinite(accel)) else math.nan
            fastest = np.nanmax(col("v_impact_max"))
            contact = ""
            if p.materials and fastest > 0.0:
                _, pressure, duration, _, _ = p.materials.hit(float(fastest), reduced)
                contact = f"{duration:.3g} ({100 * duration / period:.2g} %), {pressure / 1e6:.3g}"
            out.append(f"| {level:g} | {np.median(stroke):.3g} / {stroke.max():.3g} | {np.median(col('impacts')):.0f} | "
                       f"{fastest:.3g} | "
                       + (f"{np.nanmax(force) / 1e3:.4g} | {np.nanmax(accel):.3g} | " if np.any(np.isfinite(force))
                          else "not modelled | | ")
                       + f"{np.median(pfa):.3g} | " + (f"{100 * share:.2g} % |" if np.isfinite(share) else " |")
                       + f" {contact} |")
        out += ["", "The contact force over the floor's mass is added to the floor's peak acceleration (PFA) of each "
                "run as a bound (as if the largest contact force met the largest acceleration between impacts), "
                "so the acceleration-sensitive components on that floor see it. The model applies each impact at an "
                f"instant: it holds while a contact is short against the building's first period (T1 = {period:.3g} "
                "s); the last column says how short."
                if p.materials else "Without the stops' materials the impacts' forces are not computed: the floor's "
                "accelerations read between impacts under-read what components on the damper's floor feel.", ""]
    return out


def ida_lines(study, traces, wall):
    """The page's IDA section."""
    from .ida import Trace, leave_one_out

    runs = sum(len(r["runs"]) for r in traces)
    spec = study.ida
    bracketed = [r for r in traces if np.isfinite(r["hi"])]
    tight = sum(1 for r in bracketed if r["hi"] - r["lo"] <= spec["tolerance"] * r["lo"])
    how = ("The stripes below were run, each record scaled by its own intensity as in its IDA; where an IDA run fell "
           "on a stripe's intensity, that run is the stripe's (the same run).")
    if spec["stripes"] == "interpolate":
        loo = leave_one_out([Trace([tuple(x) for x in r["runs"]], r["lo"], r["hi"] if np.isfinite(r["hi"]) else None)
                             for r in traces])
        how = (f"The stripes' demands below are interpolated on these curves (ida.at_level: each demand linear in "
               f"intensity between the record's runs around the stripe, from (0, 0); at or above the record's "
               f"collapse intensity its collapsing run's); {_exact_count(study, traces)} of the "
               f"{len(traces) * len(study.levels)} record-stripe pairs fall on a run's intensity. How well that reads "
               "between runs, each interior run left out and read off the others (this doubles the gap, so it "
               "overstates the error at the stripes), median / 90th percentile of the relative error: "
               + ", ".join(f"{p[:-1]} {m:.1%} / {q:.1%}" for p, (m, q) in loo.items())
               + " (residual drifts are erratic from run to run).")
    return ["", "## Incremental dynamic analysis to collapse", "",
            f"Hunt and fill per record and configuration (Vamvatsikos & Cornell 2002; first {spec['first']:g}, step "
            f"{spec['step']:g} {study.unit} growing by {spec.get('increment', spec['step'] / 2):g} a run, tolerance "
            f"{spec['tolerance']:g} of the bracket, at most {spec['max_runs']} runs): {runs} runs, {wall:.0f} s wall, "
            f"each stopped at collapse; {tight} of the {len(bracketed)} collapse brackets within the tolerance (the "
            "others' runs ran out first: their bracket in `ida.csv`); each record scaled by its own intensity; the "
            "collapse fragility below "
            "(P-695 and losses) is the lognormal fit of the records' collapse intensities (bracket midpoints), "
            "records that never collapsed censored (`ida.csv`, every run's demands in its `runs` column). " + how, "",
            "![IDA to collapse](ida-collapse.png)"]


def _exact_count(study, traces):
    return sum(1 for r in traces for level in study.levels if any(run[0] == level for run in r["runs"]))


def plot_ida_traces(study, traces, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    confs = list(study.configurations)
    fig, axes = _panels(plt, len(confs))
    for ax, conf in zip(axes, confs):
        for r in (r for r in traces if r["configuration"] == conf):
            standing = sorted((im, demands.largest(d, study.storeys)["drift_ratio"]) for im, c, d in r["runs"] if not c)
            if standing:
                ims, drifts = zip(*standing)
                ax.plot(100 * np.array(drifts), ims, color="0.6", lw=0.8, marker=".", ms=3)
            if np.isfinite(r["capacity"]):
                ax.plot(100 * study.building.get("collapse_drift", 0.10), r["capacity"], "x", color="C3", ms=4)
        ax.set_title(f"{conf}: IDA per record (x: collapse)")
        ax.set_xlabel("peak inter-storey drift ratio [%]")
        ax.grid(alpha=0.3)
    axes[0].set_ylabel(study.label)
    fig.suptitle("Incremental dynamic analysis to collapse (hunt and fill, Vamvatsikos & Cornell 2002)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_pushover(push, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.0, 4.0))
    ax.plot(push.roof, push.base_shear / push.weight, color="C0")
    ax.axvline(push.delta_u, color="C3", ls="--", lw=0.8, label=f"delta_u ({push.limit})")
    ax.axvline(push.delta_y_eff, color="0.4", ls=":", lw=0.8, label="delta_y,eff (FEMA P-695 Eq. 6-7)")
    ax.set_xlabel("roof displacement [m]")
    ax.set_ylabel("base shear / weight")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    ax.set_title(f"Pushover with P-Delta (first-mode loads): mu_T = {push.mu_t:.2f}")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def hazard_text(study):
    """What the study's hazard is, in a sentence's words."""
    spec, curve = study.hazard, study.curve
    if "curve" not in spec:
        return (f"the power law lambda(IM) = k0 IM^-k with k0 = {spec['k0']:.4g}, k = {spec['k']:g} (IM in "
                f"{study.unit}; " + (f"through two points: {spec['source']}" if "points" in spec else
                                     spec.get("source", "as given")) + "), no site's curve")
    measure = f"Sa at T = {curve.period:g} s" if curve.period else study.measure
    fractiles = [n for n in curve.names[1:]]
    return (f"the site hazard curve `{spec['curve']}` ({curve.source}" + (f"; {curve.site}" if curve.site else "")
            + f"), {measure}, {curve.x.size} points from {curve.x[0]:g} to {curve.x[-1]:g} {study.unit}, "
            f"the {curve.mean} curve" + (f" (fractiles {', '.join(fractiles)} beside it)" if fractiles else "")
            + "; between its points log-log; " + ("no value outside them (every stripe lies on it)"
                                                  if curve.extrapolate == "none" else
                                                  "outside them its end segments' power laws continued"))


def plot_hazard(study, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    curve = study.curve
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    lo, hi = min(curve.x[0], study.levels[0]), max(curve.x[-1], study.levels[-1])
    if "curve" in study.hazard:
        for i, name in enumerate(curve.names):
            ax.loglog(curve.x, curve.rates[name], "o-" if i == 0 else "--", ms=3, lw=1.5 if i == 0 else 0.9,
                      color="k" if i == 0 else f"C{i}", label=name)
    else:
        x = np.geomspace(lo, hi, 200)
        ax.loglog(x, curve.rate(x), "k-", label="power law")
    for level in study.levels:
        ax.axvline(level, color="0.6", lw=0.6)
    for rate, text in ((-math.log(0.9) / 50, "10 % in 50 yr"), (-math.log(0.98) / 50, "2 % in 50 yr")):
        ax.axhline(rate, color="C3", ls=":", lw=0.8)
        ax.annotate(text, (lo, rate), fontsize=7, color="C3", va="bottom")
    ax.set_xlabel(f"{study.label} (grey: the stripes)")
    ax.set_ylabel("annual rate of exceedance [1/yr]")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=8)
    ax.set_title("Hazard curve")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _loss_levels(study):
    """The two stripes of the repair-complete curves: those nearest the 10 % and 2 % in 50 years
    intensities of a site curve or the power law's two cited points, else the middle and the
    highest stripe."""
    points, curve = study.hazard.get("points"), study.curve
    targets = ([p[0] for p in points] if points else
               [curve.intensity(-math.log(p) / 50) for p in (0.9, 0.98)] if "curve" in study.hazard else
               [study.levels[len(study.levels) // 2], study.levels[-1]])
    return sorted({int(np.argmin(np.abs(np.log(np.asarray(study.levels) / t)))) for t in targets})


def plot_repair_complete(study, per_conf, table, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from . import loss_study

    spec = study.losses
    days = np.linspace(0.0, 1.5 * spec["replacement_days"], 400)
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    for i, conf in enumerate(per_conf):
        for j, style in zip(_loss_levels(study), ("-", "--")):
            level = study.levels[j]
            frames = table[(table["configuration"] == conf) & (table["level"] == level)] if len(table) else None
            done = loss_study.repair_complete(per_conf[conf], frames, j, days, spec["replacement_days"])
            ax.plot(days, done, style, color=f"C{i}", label=f"{conf}, {study.measure} = {level:g} {study.unit}")
    ax.set_xlabel("days after the event (repairs of all floors in parallel)")
    ax.set_ylabel("fraction of buildings repaired")
    ax.set_ylim(0, 1.02)
    ax.grid(alpha=0.3)
    ax.legend(loc="lower right", fontsize=8)
    ax.set_title("Repair-complete curves (FEMA P-58 with pelicun; collapse: replaced)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _mean_text(values):
    finite = values[np.isfinite(values)]
    return f"{finite.mean():.3g}" if finite.size else "collapsed"


def loss_lines(study, rows, per_conf, values, ratios, slopes, figures):
    from . import losses

    spec = study.losses
    confs = list(per_conf)
    workers = spec["floor_area"] * losses.WORKERS_PER_M2
    lines = ["", "## Losses and repair time (FEMA P-58 with pelicun)", "",
             f"Performance model `{spec['components']}` ({len(spec['model'])} component rows, FEMA P-58 2nd edition "
             f"fragilities and repair consequences of the SimCenter Damage and Loss Model Library, USD of 2011); "
             f"floor area {spec['floor_area']:g} m2 per storey ({workers:.2f} workers per floor: FEMA P-58's one per "
             f"1000 sq ft); replacement {spec['replacement_cost']:.4g} USD and {spec['replacement_days']:g} days; "
             f"{spec['realizations']} realizations per record and stripe; the building is the same in both directions, "
             "so the one analysed direction's demands serve both and non-directional components see 1.2 times them "
             "(FEMA P-58's non-directional provision, pelicun's default), not the two components of a record pair; "
             + (f"modelling dispersion beta_m = {spec['demand_dispersion']:g} added to every demand (each realization "
                "scaled by one lognormal factor, medians kept); " if spec.get("demand_dispersion") else
                "no modelling dispersion added to the demands; ")
             + "irreparable when the largest residual drift ratio exceeds its capacity (median 1 %, beta 0.3); "
             + (f"replaced when the repairs would cost more than {spec['total_loss']:g} of the replacement cost "
                "(the total-loss threshold, pelicun's replacement configuration). " if spec.get("total_loss") else
                "no total-loss threshold. ")
             + "Collapse: " + "; ".join(f"{c}: {per_conf[c].collapse_source}" for c in confs) + ". "
             + ("Storeys deteriorate (IMKBilin, P-Delta): collapse is the building's sidesway or a storey's loss of "
                "strength." if study.building.get("storey_law") == 1 else
                "Storeys do not deteriorate (bilinear with hardening, P-Delta), so collapse is the drift limit of the "
                "building FMU."), "",
             "| " + study.measure + " [" + study.unit + "] | " + " | ".join(
                 f"{c}: P(collapse) | {c}: mean loss [USD] | {c}: P(> {spec['repair_days'][0]:g} d)" for c in confs)
             + " |", "|---:|" + "---:|" * (3 * len(confs))]
    t0 = spec["repair_days"][0]
    for j, level in enumerate(study.levels):
        cells = []
        for c in confs:
            s = per_conf[c]
            with np.errstate(invalid="ignore"):
                standing = np.nanmean(s.cost[:, j]) if np.isfinite(s.cost[:, j]).any() else spec["replacement_cost"]
                late = np.nanmean(s.exceed_days[t0][:, j]) if np.isfinite(s.exceed_days[t0][:, j]).any() else 1.0
            p = s.p_collapse[j]
            cells += [f"{p:.3f}", f"{p * spec['replacement_cost'] + (1 - p) * standing:.4g}",
                      f"{p * (spec['replacement_days'] > t0) + (1 - p) * late:.3f}"]
        lines.append(f"| {level:g} | " + " | ".join(cells) + " |")
    lines += ["", "Where the repairs go (mean repair cost of the records standing, USD, by the components' demand: "
              "structural = the moment connections, drift = other drift-sensitive components, acceleration = "
              "floor-acceleration-sensitive ones), and the median peak floor acceleration over the records "
              "(all floors' largest, m/s2): the damper lowers drifts and may raise accelerations.", "",
              "| " + study.measure + " | " + " | ".join(f"{c}: {g}" for c in confs for g in losses.GROUPS) + " | "
              + " | ".join(f"{c}: PFA" for c in confs) + " |", "|---:|" + "---:|" * (4 * len(confs))]
    for j, level in enumerate(study.levels):
        cells = [_mean_text(per_conf[c].groups[g][:, j]) for c in confs for g in losses.GROUPS]
        cells += [f"{np.median(demand_matrix(study, rows, c, 'floor_accel')[:, j]):.3g}" for c in confs]
        lines.append(f"| {level:g} | " + " | ".join(cells) + " |")
    names = ["expected annual loss [USD/yr]"] + [f"MAF of repair > {t:g} days [1/yr]" for t in spec["repair_days"]]
    rule = study.hazard.get("rule", "loglog")
    lines += ["", f"Over the hazard (90 % paired bootstrap over records, {study.bootstrap} resamples; "
              f"{RULE_TEXT[rule]}; below the lowest stripe, {study.levels[0]:g} {study.unit}, no loss: "
              "the next section shows what that leaves out):", "",
              "| quantity | " + " | ".join(confs) + " | " + " | ".join(f"ratio {c} / {confs[0]}" for c in confs[1:])
              + " | unfitted resamples |", "|---|" + "---:|" * (2 * len(confs))]
    for i, name in enumerate(names):
        cells = [values[c][i].text(4) for c in confs] + [f"**{ratios[c][i].text(3)}**" for c in confs[1:]]
        unfitted = max([values[c][i].unfitted for c in confs] + [ratios[c][i].unfitted for c in confs[1:]])
        lines.append(f"| {name} | " + " | ".join(cells) + f" | {unfitted} |")
    if slopes:
        lines += ["", "Sensitivity of the EAL ratio to the hazard's slope k (the rate at the higher cited point "
                  "kept): " + "; ".join(f"k x {s:g}: " + ", ".join(f"{r:.3g}" for r in v) for s, v in slopes.items())
                  + "."]
    lines += eal_lines(study, figures, rule)
    lines += ["", "### The performance model", "", f"`{spec['components']}`, each component's FEMA P-58 fragility "
              "by its ID in the SimCenter library (description as the library gives it; direction 0: "
              "non-directional):", "", "| ID | description | demand | floors | directions | quantity per floor | unit |",
              "|---|---|---|---|---|---:|---|"]
    lines += [f"| {cid} | {text} | {demand} | {floors} | {direction} | {quantity:g} | {unit} |"
              for cid, text, demand, floors, direction, quantity, unit in losses.component_rows(spec["model"])]
    lines += ["", "![repair complete](repair-complete.png)", "",
              "Every loss realization: `losses.parquet` (configuration, level, record, cost, days_parallel, "
              "days_sequential, irreparable)."]
    return lines


def uncertainty_lines(study, found):
    """The headline ratios restated with the hazard's and the model's uncertainty (an
    uncertainty.Found): per configuration and ratio the records-only interval, each source's sides
    and one-sigma term, and the widened interval."""
    confs = list(study.configurations)
    names = (["expected annual loss"] + [f"MAF of repair > {t:g} days" for t in study.losses["repair_days"]]
             + ["median collapse intensity"])
    lines = ["", "## The headline ratios with the hazard's and the model's uncertainty", "",
             "Each ratio's 90 % interval: the paired bootstrap over records (as above), then each source below moved "
             "one sigma, its change of ln(ratio) (central: half the change from its minus to its plus side; one "
             "side: the change from the reference) added in quadrature to the bootstrap's half-interval in ln units "
             "over z = 1.645 (first-order second-moment, the sources independent, as FEMA P-695 adds its beta_TOT). "
             "A rate error common to every intensity (the hazard curve scaled up or down) cancels in a ratio "
             "exactly, and so does a modelling error that moves both configurations alike; what is left is what "
             "moves one configuration more than the other: the curve's shape and the damper's tuning and contacts. "
             "The median collapse intensity is where half the records collapsed in their IDA (own Sa scaling); "
             "the hazard does not move it.", "",
             "Sources: " + "; ".join(f"**{source.name}**: {source.text}" for source in found.sources)
             + f". The model sources' {found.runs} runs (every record at every stripe in each perturbed "
             "configuration, no IDA) compare the stripes' lognormal collapse fit with itself: their reference is the "
             "study's own configurations with that fit.", ""]
    for c in confs[1:]:
        lines += [f"| ratio {c} / {confs[0]} | point | records only | "
                  + " | ".join(f"{source.name}: minus / plus (one sigma, ln)" for source in found.sources)
                  + " | records, hazard and model |", "|---|---:|---:|" + "---:|" * (len(found.sources) + 1)]
        for k, name in enumerate(names):
            interval = found.intervals[c][k]
            cells = []
            for source in found.sources:
                minus, plus, step = source.minus[c][k], source.plus[c][k], source.delta(c, k)
                cells.append(f"{minus:.3g} / {plus:.3g}" + (f" ({step:+.3f})" if np.isfinite(step) else ""))
            lo, hi = found.widened[c][k]
            whole = f"**{lo:.3g} to {hi:.3g}**" if np.isfinite(lo) else "no interval"
            records = f"{interval.lo:.3g} to {interval.hi:.3g}" if np.isfinite(interval.lo) else "no interval"
            lines.append(f"| {name} | {interval.point:.3g} | {records} | " + " | ".join(cells) + f" | {whole} |")
        lines.append("")
    lines.append("A one-sided source's minus column is its reference (the study's configurations, the stripes' "
                 "collapse fit).")
    return lines


#: how the EAL integrates between the stripes (hazard.Integral), in the page's words
RULE_TEXT = {"loglog": "E[L | x] a power law in x between neighbouring stripes (linear in ln x next to a zero "
                       "loss), integrated exactly against the log-log hazard, held at the top stripe's above it",
             "semilog": "E[L | x] linear in ln x between neighbouring stripes, integrated exactly against the "
                        "log-log hazard, held at the top stripe's above it",
             "intervals": "each stripe stands for the interval between the geometric midpoints of its neighbours "
                          "(the lowest from x_1^2 / m_1, the highest to infinity)"}


def _share(part, whole, of=""):
    """part / whole in percent, two digits, and `of` (what it is a share of); what is missing when
    the whole is 0 or unknown (no collapse fit)."""
    if not np.isfinite(whole):
        return "no EAL"
    return f"{100 * part / whole:.2g} %{of}" if whole else "its EAL is 0"


def eal_lines(study, figures, rule):
    """The EAL and the hazard: the loss at the lowest stripe and what lies below it, the part from
    outside the curve, the EAL by lower limit and rule, and under each of the curve's fractiles."""
    confs = list(figures.lowest)
    cost = study.losses["replacement_cost"]
    eal = figures.curves[study.curve.mean]
    ratio = lambda row: " | ".join(f"{row[c] / row[confs[0]]:.3g}" if row[confs[0]] else "no EAL"  # noqa: E731
                                   for c in confs[1:])
    lines = ["", "### How the EAL depends on the hazard and the integration", "",
             f"The mean loss at the lowest stripe ({study.levels[0]:g} {study.unit}): " + "; ".join(
                 f"{c} {figures.lowest[c]:.4g} USD ({100 * figures.lowest[c] / cost:.2g} % of replacement)"
                 for c in confs) + ". "
             + ("Below it, if the loss there is no more than at the lowest stripe, at most " + "; ".join(
                 f"{c} {figures.below[c]:.3g} USD/yr ({_share(figures.below[c], eal[c], ' of its EAL')})"
                 for c in confs) + f" (down to the curve's first point, {study.curve.x[0]:g} {study.unit}); the power "
                 "law through the two lowest stripes' losses continued down there gives " + "; ".join(
                     f"{c} {figures.trend[c]:.3g} USD/yr ({_share(figures.trend[c], eal[c])})" for c in confs)
                 + "."
                if np.isfinite(list(figures.below.values())).all() else
                "The curve does not reach below it, so nothing bounds what lies there.")
             + " From intensities outside the curve's points (its extrapolation rule): " + "; ".join(
                 f"{c} {_share(figures.outside[c], eal[c], ' of its EAL')}" for c in confs) + ".", "",
             "EAL [USD/yr] with the integral's lower limit at each of the lowest stripes and by integration rule "
             f"(the page's figures: from {study.levels[0]:g} {study.unit}, rule {rule}):", "",
             "| lower limit [" + study.unit + "] | rule | " + " | ".join(confs) + " | "
             + " | ".join(f"ratio {c} / {confs[0]}" for c in confs[1:]) + " |",
             "|---:|---|" + "---:|" * (2 * len(confs) - 1)]
    for (lower, how), row in figures.convergence.items():
        lines.append(f"| {study.levels[lower]:g} | {how} | " + " | ".join(f"{row[c]:.4g}" for c in confs) + " | "
                     + ratio(row) + " |")
    if len(figures.curves) > 1:
        lines += ["", "EAL [USD/yr] under each of the hazard's curves (all records; the hazard's epistemic spread):",
                  "", "| curve | " + " | ".join(confs) + " | " + " | ".join(f"ratio {c} / {confs[0]}"
                                                                           for c in confs[1:]) + " |",
                  "|---|" + "---:|" * (2 * len(confs) - 1)]
        for name, row in figures.curves.items():
            lines.append(f"| {name} | " + " | ".join(f"{row[c]:.4g}" for c in confs) + " | " + ratio(row) + " |")
    return lines

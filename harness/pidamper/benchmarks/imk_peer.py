"""OpenSees converging to our deteriorating building (issue 37), and what each costs: writes
docs/yielding/deteriorating.md with its figures (this module holds the page's prose: one source).

The 3-storey building of `IMKBilin` storeys with P-Delta under a held two-cycle pulse that takes
storey 1 past capping and down its post-capping branch; ours (exact, event-driven) against OpenSees
(zeroLength `IMKBilin` storeys, `modalDamping`, Newmark average acceleration, Newton) at falling
steps, bare and with the pendulum damper on the roof (OpenSees's stops `JankowskiImpact` gap
elements, our restitution the one they give); and FEMA P-695's pushover of the same building, ours
(exact) against OpenSees's displacement-controlled one.

    python -m pidamper.benchmarks.imk_peer [--out docs/yielding] [--runs 5]
"""
import argparse
import math
import time
from pathlib import Path

import numpy as np

from pidamper.machine import describe
from pidamper.running import isolated
from pidamper_physics import BUILD, Damper, Params
from pidamper_physics.imk_storeys import imk_tables
from pidamper_physics.yielding import building_motion

MASSES, STIFFNESSES, YIELD_FORCES, HEIGHTS = [1e5] * 3, [8e7] * 3, [6e5, 5.2e5, 3.2e5], [3.0] * 3
SIDE = dict(dp=0.02, dpc=0.3, du=0.5, FmaxFy=1.3, FresFy=0.3)
#: each storey: capping 2 cm past yield at 1.3 Fy, zero force 30 cm beyond, residual 0.3 Fy, Lamda 1 m
ENTRY = {**{f"{k}_{s}": v for k, v in SIDE.items() for s in ("pos", "neg")}, "LamdaS": 1.0, "LamdaC": 1.0,
         "LamdaK": 1.0}
TABLES = imk_tables(STIFFNESSES, YIELD_FORCES, [ENTRY] * 3)
ZETA, INTERVAL, SECONDS, AMPLITUDE = 0.05, 0.01, 6.0, 3.5
STEPS = (5e-3, 2e-3, 1e-3, 1e-4, 1e-5)
#: the damper: 5 % of the building's mass on the roof, tuned to the first mode, 2 cm each way; the
#: peer's stops (Hertz stiffness Kh [N/m^1.5], damping ratio XI) at the steps that resolve them
DAMPER = dict(mu=0.05, FR=1.0, d=0.02, zeta_p=0.0)
XI, CONTACT = 0.35, ((1e9, (1e-3, 1e-4, 1e-5)), (1e10, (1e-4, 1e-5)))
LEVELS = (1e-2, 1e-3)


def record():
    """The held ground acceleration [m/s2] per INTERVAL: two 1 s sine cycles of AMPLITUDE, then 0."""
    n = int(round(SECONDS / INTERVAL))
    return [AMPLITUDE * math.sin(2.0 * math.pi * i * INTERVAL) if i * INTERVAL < 2.0 else 0.0 for i in range(n + 1)]


def damped_params(e=0.5):
    return Params(storeys=3, fidelity=1, zeta_s=ZETA, storey_Fy=YIELD_FORCES, p_delta=1, floor_m=MASSES,
                  storey_k=STIFFNESSES, storey_law=1, storey_imk=[ENTRY] * 3, collapse_drift=0.3, e=e, **DAMPER)


def ours_roof(samples, damped=False, e=0.5):
    """Our core's roof displacement [m] at every INTERVAL instant (t = 0 first)."""
    if damped:
        core = Damper(damped_params(e))
        step = lambda t, a: core.advance(t, 0.0, a)  # noqa: E731
        roof = lambda: core.floors()[0][2]  # noqa: E731
    else:
        core = building_motion(MASSES, STIFFNESSES, HEIGHTS, ZETA, None, None, p_delta=1, collapse_drift=0.3,
                               imk=TABLES)
        step = lambda t, a: core.advance(t, [0.0] * 3, a)  # noqa: E731
        roof = lambda: core.x[2]  # noqa: E731
    out = [0.0]
    for i in range(len(samples) - 1):
        step((i + 1) * INTERVAL, samples[i])
        out.append(roof())
    return np.array(out)


def ours_fmu(samples, damped=False, e=0.5):
    """The roof from our FMU (ShearBuilding3 or DampedShearBuilding3) as fmpy's simulate_fmu runs it."""
    import fmpy

    from pidamper import find_fmu
    from pidamper.running.unpacked import unpacked

    from pidamper.benchmarks.yielding_peer import quiet

    folder, md = unpacked(str(find_fmu(storeys=3, damper=damped)))
    start = fmu_start_values(damped, e)
    stop = (len(samples) - 1) * INTERVAL
    signal = np.array([(i * INTERVAL, a) for i, a in enumerate(samples)], dtype=[("time", float), ("a_g", float)])
    with quiet():  # (fmpy's note of every input the signal leaves at its start value)
        res = fmpy.simulate_fmu(folder, model_description=md, stop_time=stop, output_interval=INTERVAL, input=signal,
                                start_values=start, output=["floor[3].x"], step_size=INTERVAL)
    return np.asarray(res["floor[3].x"])


def fmu_start_values(damped=False, e=0.5):
    """The FMU's start values of the building (and the damper)."""
    start = {"p_delta": 1, "zeta_s": ZETA, "storey_law": 1, "collapse_drift": 0.3,
             **{f"storey[{k + 1}].Fy": YIELD_FORCES[k] for k in range(3)},
             **{f"storey[{k}].{name}": v for k in (1, 2, 3) for name, v in ENTRY.items()}}
    if damped:
        start.update({**DAMPER, "fidelity": 1, "e": e})
    return start


def native_cpu(damped=False, e=0.5, repeats=5):
    """(CPU s per simulated s of our FMU in the native C host, median of `repeats`; its outputs):
    benchmarks/native/every_output_host.c sets the start values, sets a_g to record()'s samples and
    reads every output at every step, one call each (the steps only are timed)."""
    import subprocess
    import tempfile

    import fmpy

    from pidamper import find_fmu
    from pidamper.benchmarks.floor import build_every_output_host

    tmp = Path(tempfile.mkdtemp(prefix="pidamper_imk_host_"))
    exe = build_every_output_host(tmp)
    fmu = find_fmu(storeys=3, damper=damped)
    md = fmpy.read_model_description(str(fmu))
    unzipped = fmpy.extract(str(fmu), unzipdir=str(tmp / "fmu"))
    by_name = {v.name: v for v in md.modelVariables}
    params = [f"{'P' if by_name[k].type == 'Real' else 'Q'}:{by_name[k].valueReference}:{v!r}"
              for k, v in fmu_start_values(damped, e).items()]
    outputs = [f"{v.type[0]}:{v.valueReference}" for v in md.modelVariables if v.causality == "output"]
    pulse = f"U:{by_name['a_g'].valueReference}:{AMPLITUDE!r}:{2.0 * math.pi!r}:2.0"
    steps = int(round(SECONDS / INTERVAL))
    cpus = []
    for _ in range(repeats):
        done = subprocess.run([str(exe), unzipped, md.coSimulation.modelIdentifier, md.guid, str(steps),
                               repr(INTERVAL), *params, *outputs, pulse], capture_output=True, text=True, timeout=600)
        if done.returncode != 0:
            raise RuntimeError(f"{fmu.name} in the native host: {done.stderr[-800:]}")
        cpus.append(float(done.stdout.split()[0]) * 1e-6 / INTERVAL)
    return float(np.median(cpus)), len(outputs)


def opensees_roof(samples, dt, damped=False, Kh=None, e=None):
    """(OpenSees's roof at every INTERVAL instant, its CPU seconds) at the analysis step dt."""
    roof, cpu = isolated.call("pidamper.benchmarks.imk_peer:_timed_opensees", list(map(float, samples)), dt, damped,
                              Kh, hard_exit=True)
    return np.array(roof), cpu


def _timed_opensees(samples, dt, damped, Kh):
    from pidamper.oracles import opensees as peer

    start = time.process_time()
    stop = (len(samples) - 1) * INTERVAL
    if damped:
        p = damped_params()
        peer.damped_shear_building(MASSES, STIFFNESSES, YIELD_FORCES, [0.0] * 3, HEIGHTS, ZETA, True, 2, p.m, p.w1,
                                   DAMPER["zeta_p"], DAMPER["d"], Kh, XI, imk=TABLES)
    else:
        peer.shear_building(MASSES, STIFFNESSES, YIELD_FORCES, [0.0] * 3, HEIGHTS, ZETA, p_delta=True, imk=TABLES)
    try:
        _, x = peer.run_building(3, samples, INTERVAL, dt, stop, floors=[3])
    except ArithmeticError:
        return None, None
    return [row[0] for row in x], time.process_time() - start


def roof_errors(steps=STEPS):
    """[(dt, OpenSees's roof error over the peak, its CPU s per simulated s)] of the bare building."""
    samples = record()
    roof = ours_roof(samples)
    rows = []
    for dt in steps:
        theirs, cpu = opensees_roof(samples, dt)
        rows.append((dt, float(np.abs(theirs - roof).max() / np.abs(roof).max()), cpu / SECONDS))
    return rows, roof


def _median_cpu(fn, runs):
    times, out = [], None
    for _ in range(runs):
        t0 = time.process_time()
        out = fn()
        times.append(time.process_time() - t0)
    return float(np.median(times)), out


def measure(runs):
    """Every figure of the page."""
    from pidamper.benchmarks.yielding_peer import restitution

    samples = record()
    out = {}
    for key, damped in (("bare", False), ("damped", True)):
        e = restitution(1e10, XI, (MASSES[2], damped_params().m)) if damped else 0.5
        exact = ours_roof(samples, damped, e)
        core_cpu, _ = _median_cpu(lambda: ours_roof(samples, damped, e), runs)
        fmu_cpu, fmu = _median_cpu(lambda: ours_fmu(samples, damped, e), runs)
        native, outputs = native_cpu(damped, e, runs)
        rows = [("ours, core", 0.0, core_cpu / SECONDS), ("ours, FMU in fmpy", float(np.abs(fmu - exact).max()),
                                                        fmu_cpu / SECONDS),
                (f"ours, FMU in a native C host reading its {outputs} outputs every step", 0.0, native)]
        for Kh, steps in (CONTACT if damped else ((None, STEPS),)):
            for dt in steps:
                cpus, roof = [], None
                for _ in range(1 if dt < 1e-4 else runs):
                    roof, cpu = opensees_roof(samples, dt, damped, Kh)
                    cpus.append(np.nan if cpu is None else cpu)
                label = f"OpenSees dt = {dt:g} s" + (f", Kh = {Kh:g}" if damped else "")
                err = np.inf if roof is None or roof.ndim == 0 else float(np.abs(roof - exact).max() / np.abs(exact).max())
                rows.append((label, err, float(np.median(cpus)) / SECONDS))
        out[key] = dict(rows=rows, peak=float(np.abs(exact).max()), e=e)
    out["pushover"] = pushover_figures()
    return out


def pushover_figures():
    """Ours (exact corners) and OpenSees's displacement-controlled pushover of the same building."""
    from pidamper.assessment.deteriorating_pushover import pushover
    from pidamper.assessment.p695 import first_mode

    po = pushover(MASSES, TABLES, HEIGHTS, p_delta=True)
    m = np.asarray(MASSES)
    geo = 9.81 * np.cumsum(m[::-1])[::-1] / np.asarray(HEIGHTS)
    phi, _ = first_mode(m, np.array([t[0] for t in TABLES]) - geo)
    pattern = list(map(float, m * phi / np.sum(m * phi)))
    roof, shear = isolated.call("pidamper.oracles.opensees:imk_pushover_curve", MASSES, TABLES, HEIGHTS, True,
                                pattern, float(po.roof[-1]), 16000, hard_exit=True)
    ours = np.interp(roof, po.roof, po.base_shear)
    return dict(ours=(list(map(float, po.roof)), list(map(float, po.base_shear))), opensees=(roof, shear),
                error=float(np.abs(np.asarray(shear) - ours).max() / po.v_max), mu_t=po.mu_t, v_max=po.v_max)


def plot(out, folder):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    for ax, key, title in ((axes[0], "bare", "bare deteriorating building"), (axes[1], "damped", "with the damper")):
        for label, err, c in out[key]["rows"]:
            if not np.isfinite(err):
                continue
            mine = label.startswith("ours")
            ax.loglog(max(err, 1e-16), c, "o" if mine else "s", color="C0" if mine else "C1", ms=8 if mine else 5)
            ax.annotate(label.replace("OpenSees ", ""), (max(err, 1e-16), c), fontsize=6)
        ax.set_xlabel("roof error / peak (ours exact: plotted at 1e-16)")
        ax.set_ylabel("CPU s per simulated s")
        ax.set_title(title)
        ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(folder / "deteriorating.png", dpi=110)
    fig, ax = plt.subplots(figsize=(6, 4))
    po = out["pushover"]
    ax.plot(*po["opensees"], color="C1", label="OpenSees, 16,000 displacement steps")
    ax.plot(*po["ours"], "o-", color="C0", ms=4, lw=1, label="ours (exact corners)")
    ax.set_xlabel("roof displacement [m]")
    ax.set_ylabel("base shear [N]")
    ax.legend()
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(folder / "deteriorating-pushover.png", dpi=110)


def page(out, runs):
    def table(key):
        lines = ["| run | roof error / peak | CPU s per simulated s |", "|---|---:|---:|"]
        for label, err, c in out[key]["rows"]:
            shown = "exact" if err == 0.0 else ("diverged" if not np.isfinite(err) else f"{err:.2g}")
            if label == "ours, FMU in fmpy":
                shown = "bit for bit with the core" if err == 0.0 else f"{err:.2g} m from the core"
            elif label.startswith("ours, FMU in a native"):
                shown = "the FMU's"
            lines.append(f"| {label} | {shown} | {c:.3g} |")
        return "\n".join(lines)

    def cheaper(key):
        rows = out[key]["rows"]
        peers = [r for r in rows[3:] if np.isfinite(r[1])]
        parts = []
        for label, _, cost in rows[:3]:
            beaten = [(peer, err) for peer, err, c in peers if c <= cost]
            parts.append(f"{label}: cheaper than OpenSees at every step" if not beaten else
                         f"{label}: OpenSees at " + ", ".join(peer.replace("OpenSees ", "") for peer, _ in beaten)
                         + f" costs less (at errors of {min(err for _, err in beaten):.2g} and above)")
        return "; ".join(parts) + (". fmpy's `simulate_fmu` adds its own Python per step (the difference between its "
                                   "row and the core's)")

    po = out["pushover"]
    return f"""# Deteriorating storeys: exact against OpenSees's IMKBilin

Generated by `python -m pidamper.benchmarks.imk_peer` on {describe("fmpy", "openseespy")}, the physics
{BUILD}; CPU figures are process CPU per simulated second, median of {runs} runs (OpenSees below dt = 1e-4 s: one run): our core alone, our FMU
as fmpy's `simulate_fmu` runs it (host included, the FMU unpacked once per process), our FMU in the native C
host of `pidamper.benchmarks.native` (it sets the start values, the input, and reads every output at every
step, one call each; the steps are timed), OpenSeesPy's model definition and `analyze` loop.

The 3-storey building of [Yielding buildings](README.md) (floors 1e5 kg, storeys 8e7 N/m of 3 m,
P-Delta, modal damping 5 %) with deteriorating storeys (`storey_law = 1`, OpenSees's `IMKBilin`
law, exact; yield forces 6e5 / 5.2e5 / 3.2e5 N, capping 2 cm past yield at 1.3 Fy, zero force 30 cm
beyond, residual 0.3 Fy, reference energies 1 m x Fy), under {AMPLITUDE} m/s2 of two 1 s sine cycles
held per {INTERVAL} s, {SECONDS} s in all: storey 1 goes past capping and down its post-capping
branch (peak roof {out['bare']['peak']:.3g} m bare). OpenSees models the same building of zeroLength
`IMKBilin` storeys (Newmark average acceleration, Newton); with the damper its stops are
`JankowskiImpact` gap elements of Hertz stiffness Kh and damping ratio {XI}, our restitution the one
they give ({out['damped']['e']:.4f}), so its error also holds the contact's finite duration.

![error against CPU](deteriorating.png)

## Bare building (`ShearBuilding3`, `storey_law = 1`)

{table('bare')}

OpenSees's error falls with its step overall, not monotonically (its per-step rules place the law's
events at its samples: tests/test_imk.py), to {out['bare']['rows'][-1][1]:.2g} of the peak at dt =
1e-5 s. Here {cheaper('bare')}.

## With the damper (`DampedShearBuilding3`, `storey_law = 1`)

{table('damped')}

Here {cheaper('damped')}.

## Pushover (FEMA P-695)

![pushover](deteriorating-pushover.png)

`pidamper.assessment.deteriorating_pushover.pushover`: the first mode's lateral loads, exact corners to
20 % strength loss, with P-Delta: V_max = {po['v_max']:.6g} N, mu_T = {po['mu_t']:.4g}. OpenSees's
displacement-controlled pushover of the same `IMKBilin` storeys (16,000 steps) lies within
{po['error']:.1e} of V_max of ours.

The tests check ours against an independent reference (tests/test_imk_buildings.py) and OpenSees's
convergence to ours.
"""


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", default="docs/yielding")
    ap.add_argument("--runs", type=int, default=5)
    args = ap.parse_args(argv)
    folder = Path(args.out)
    folder.mkdir(parents=True, exist_ok=True)
    out = measure(args.runs)
    plot(out, folder)
    (folder / "deteriorating.md").write_text(page(out, args.runs))
    print(f"wrote {folder / 'deteriorating.md'}, deteriorating.png, deteriorating-pushover.png")


if __name__ == "__main__":
    main()

"""The FMU's documentation/ folder: model, variables, assumptions, the default experiment
(plot and reference result CSV), as the Modelica Reference-FMUs ship them."""
import csv
import html
import subprocess
from pathlib import Path

MODEL_NAME = "PendulumImpactDamper"
REF_OUTPUTS = ("theta", "theta_dot", "alpha", "alpha_dot", "impacts", "contact", "energy", "energy_dissipated")


def reference_result(stop=20.0, step=0.01):
    """Rows of the default experiment (defaults of every parameter), computed by the physics core
    on the FMU's communication grid: the FMU must reproduce them."""
    from pidamper_physics import DEFAULTS, INITIAL_DEFAULTS, Damper, Params

    core = Damper(Params(**DEFAULTS), *INITIAL_DEFAULTS.values())
    n = int(round(stop / step))
    rows = []
    for k in range(n + 1):
        if k:
            core.advance(k * step)
        p = core.p
        rows.append((core.t, core.x / p.L2, core.v / p.L2, core.y / p.L1, core.u / p.L1, core.impacts, core.contact,
                     core.energy, core.dissipated))
    return rows


def write_reference_csv(path, rows):
    with open(path, "w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(("time",) + REF_OUTPUTS)
        for row in rows:
            writer.writerow([repr(v) if isinstance(v, float) else v for v in row])


def write_plot(path, rows):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    t = [r[0] for r in rows]
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(7, 5), sharex=True)
    a1.plot(t, [r[1] for r in rows], label="theta (primary)")
    a1.plot(t, [r[3] for r in rows], label="alpha (particle)", alpha=0.6)
    a1.set_ylabel("angle [rad]")
    a1.legend(fontsize=8)
    a2.plot(t, [r[7] for r in rows], label="energy")
    a2.plot(t, [r[8] for r in rows], label="energy dissipated")
    a2.set_xlabel("time [s]")
    a2.set_ylabel("[J]")
    a2.legend(fontsize=8)
    fig.suptitle("PendulumImpactDamper, default experiment (free decay)", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def git_revision():
    try:
        done = subprocess.run(["git", "describe", "--always", "--dirty"], capture_output=True, text=True,
                              cwd=Path(__file__).parent, timeout=10)
        return done.stdout.strip() or "unknown"
    except (OSError, subprocess.SubprocessError):
        return "unknown"


def write_index(path, version):
    """documentation/index.html: the model, its assumptions, its variables (build_fmu.variables) and
    the default experiment."""
    from .variables import html_tables

    text = f"""<!DOCTYPE html>
<html><head><meta charset="utf-8"><title>PendulumImpactDamper</title></head><body>
<h1>PendulumImpactDamper {html.escape(version)}</h1>
<p>Pendulum-type particle impact damper: a primary structure modelled as a pendulum (mass M, length L2)
and a particle hung inside it as a second pendulum (mass m = mu M, length L1 = L2/FR<sup>2</sup>) that
strikes two stops. FMI 2.0 co-simulation; source revision {html.escape(git_revision())}.</p>
<h2>Model</h2>
<p>Linear coordinates x = L2 theta, y = L1 alpha. Between impacts:
x'' + w2<sup>2</sup> x = F/M + (F0/M) sin(Omega t + phi) - a_g, y'' + w1<sup>2</sup> y = -a_g, with
w2 = sqrt(g/L2), w1 = FR w2, solved in closed form (exact also at resonance). Contact at
x - y = &plusmn;d (contact_form 0) or theta - alpha = &plusmn;d_angle as printed in the paper
(contact_form 1, where a pair that still closes after an impact passes through the stop until it
re-enters the gap). Impact law: momentum conserved, Newton restitution e. Every impact inside a
communication step is located exactly (conservative advancement: none can be missed) and handled
inside fmi2DoStep; a chatter sequence whose rebound falls below float64 resolution collapses into
sticking, and the particle rides the stop until the contact force reaches zero.</p>
<p>Parameter fidelity picks the model: 0 linear (the above, the paper's), 1 damped (plus dashpots
2 zeta_s M w2 on the primary and 2 zeta_p m w1 on the particle), 2 coupled (plus the particle hung from
the moving primary: a linearised double pendulum; alpha is then the wire angle and y = x + L1 alpha),
both closed form by complex modes, and 3 nonlinear (the double pendulum at any angle, integrated by
DOP853 with guaranteed event location; x = L2 sin theta, y = x + L1 sin alpha). energy_viscous is the
energy taken by the dashpots.</p>
<h2>Assumptions</h2>
<ul><li>point impacts; levels 0 to 2 assume small angles (linearised pendulums); when a body's swing
first exceeds angle_limit the FMU logs a warning (fmi2Warning, once per run) with the exact error of the
linearisation at that swing, and at fmi2Terminate the largest swings of the run;</li>
<li>the inputs F [N] (force on the primary) and a_g [m/s2] (ground acceleration under both pivots; x and y
are measured from the ground) are held constant over each communication step (canInterpolateInputs = false);</li>
<li>the model runs in Python: in the host's interpreter when the host process has one (fmpy, libcosimpy; 3.8
or newer), else the FMU's native layer (binaries/linux64/PendulumImpactDamper.so) starts one by itself: the
libpython named by PIDAMPER_LIBPYTHON, else the one the FMU was built with, else the system's of the same
minor version, isolated from PYTHONPATH and PYTHONHOME; when none is found fmi2Instantiate says where it
looked. The Windows binary is pythonfmu's own (not tested): the host needs Python on its PATH.</li>
<li>the FMI 2.0 calling sequence is enforced: a call not allowed in the instance's state, on a variable of
another type or on an unknown value reference answers fmi2Error with a logged message, as does any value
the model refuses; fixed parameters set after initialization to their current value are accepted.</li></ul>
{html_tables(MODEL_NAME)}
<p>Local variables impact[k].t, .side, .v_rel_before, .v_rel_after, .energy_lost, .theta (k = 1..16) record
the impacts of the last communication step (slots beyond impacts_in_step hold zeros); hosts do not record
them by default, any host reads them by name after fmi2DoStep.</p>
<h2>Default experiment</h2>
<p>0 to 20 s, step 0.01 s, every parameter at its start value (free decay from theta_dot_0 = 0.5 rad/s).
Result: PendulumImpactDamper_ref.csv.</p>
<img src="default_experiment.png" alt="default experiment">
</body></html>
"""
    Path(path).write_text(text)


def write(folder, version):
    """Fill `folder` with index.html, default_experiment.png and PendulumImpactDamper_ref.csv."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    rows = reference_result()
    write_reference_csv(folder / "PendulumImpactDamper_ref.csv", rows)
    write_plot(folder / "default_experiment.png", rows)
    write_index(folder / "index.html", version)
    return folder

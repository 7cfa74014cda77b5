"""The scene commands: `pidamper run` (a scene, with every field overridable on the command line, run
with fmpy and logged) and `pidamper demo` (build the FMU, run the free-decay and resonance scenes,
print the headline figures)."""
import argparse
import math
import sys
import time
from pathlib import Path

from pidamper_physics import Params

from .. import measures
from ..running.fmu import find_fmu
from ..running.simulation import FmuError, run
from ..running.stepper import FmuStepper
from ..runlog.logged_run import run_logged, wait_for_viewers
from .scene import (FORCING_ARGS, PER_STOREY, SceneError, check_parameters, load, parse, shipped, storey_variable,
                    tomllib)


def parse_param(text):
    """-p NAME=VALUE: VALUE as a scene file writes it (TOML: 0.02, 3, 6e5, [6e5, 5e5, 3e5]), or any
    number Python reads (.5, 1.); NAME is checked with the scene (scene.check_parameters)."""
    name, sep, value = text.partition("=")
    name = name.strip()
    if not sep or not name:
        raise argparse.ArgumentTypeError(f"-p {text!r} is not allowed: use NAME=VALUE, e.g. -p mu=0.02, "
                                         "-p 'storey[1].Fy=1e6' or -p 'storey_Fy=[6e5, 5e5, 3e5]'")
    try:
        parsed = tomllib.loads(f"value = {value.strip()}")
        if list(parsed) == ["value"]:
            return name, parsed["value"]
    except tomllib.TOMLDecodeError:
        pass
    try:
        return name, float(value)
    except ValueError:
        raise argparse.ArgumentTypeError(f"-p {text!r} is not allowed: {value!r} is not a number or a list of "
                                         "numbers as a scene file writes it, e.g. [6e5, 5e5, 3e5]") from None


def _parameters(base, overrides):
    """The scene's parameters with the -p overrides: a per-storey parameter given replaces the
    scene's value and any storey[k] variable of it the scene gives; refusals of an override name it
    as -p NAME."""
    params = dict(base.parameters)
    for key in overrides:
        if key in PER_STOREY:
            for name in [n for n in params if (storey_variable(n) or (None,))[0] == key]:
                del params[name]
    params.update(overrides)
    try:
        check_parameters(params, base.source)
    except SceneError as err:
        name = err.name.removeprefix("parameters.")
        key = next((k for k in overrides if name == k or name.startswith(k + "[")), None)
        if key is None:
            raise
        raise SceneError(f"pidamper run {base.name}", f"-p {name}", err.value, err.allowed) from None
    return params


def scene_from_args(args):
    """The scene to run: args.scene (a shipped name or a file; default: 'default') with every
    option given on the command line overriding its field (validated like the file)."""
    base = load(args.scene or "default")
    data = {"description": base.description, "parameters": _parameters(base, dict(args.param or [])),
            "forcing": dict(base.forcing), "run": dict(base.run), "outputs": {"record": list(base.outputs)},
            "log": dict(base.log)}
    forcing = data["forcing"]
    if args.forcing is not None and args.forcing != forcing.get("kind"):
        forcing = data["forcing"] = {"kind": args.forcing}
    if args.csv is not None:
        forcing.clear()
        forcing.update(kind="csv", file=str(Path(args.csv).resolve()))
    for option, key in (("F0", "F0"), ("omega", "Omega"), ("phi", "phi"), ("omega_start", "Omega_start"),
                        ("omega_end", "Omega_end")):
        value = getattr(args, option)
        if value is not None:
            forcing[key] = value
            forcing.pop(key + "_ratio", None)
    if args.sampled:
        forcing["sampled"] = True
    run = data["run"]
    if args.stop_time is not None or args.periods is not None:
        run.pop("stop_time", None)
        run.pop("periods", None)
        run["stop_time" if args.stop_time is not None else "periods"] = (
            args.stop_time if args.stop_time is not None else args.periods)
    if args.output_interval is not None:
        run["output_interval"] = args.output_interval
    if args.fidelity is not None:
        run["fidelity"] = args.fidelity
    if args.no_log:
        data["log"].update(mcap=False, rrd=False)
    if args.no_rrd:
        data["log"]["rrd"] = False
    return parse(data, base.source, base.folder, base.name)


def add_arguments(parser):
    """The options of `pidamper run`: a scene and every field it may override."""
    parser.add_argument("scene", nargs="?", help="a shipped scene (" + ", ".join(shipped())
                       + ") or a scene file (.toml); default: default. Every option below overrides its field")
    parser.add_argument("--fmu", help="FMU file (default: build or reuse dist/PendulumImpactDamper.fmu)")
    parser.add_argument("-p", "--param", action="append", type=parse_param, metavar="NAME=VALUE",
                       help="FMU parameter or initial state, by its scene or FMU name, the value as a scene file "
                            "writes it, e.g. -p mu=0.02 -p theta_dot_0=1.5; on a building "
                            "-p 'storey_Fy=[6e5, 5e5, 3e5]' (storey 1 first) or -p 'storey[1].Fy=1e6' "
                            "(repeatable; names checked before the run)")
    parser.add_argument("--forcing", choices=list(FORCING_ARGS))
    parser.add_argument("--F0", type=float, help="force amplitude [N]")
    parser.add_argument("--omega", type=float, help="harmonic frequency [rad/s] (default: resonance w2)")
    parser.add_argument("--phi", type=float, help="harmonic phase [rad]")
    parser.add_argument("--sampled", action="store_true",
                       help="feed the harmonic through input F (held per step) instead of the built-in force")
    parser.add_argument("--omega-start", type=float, help="sweep start [rad/s] (default 0.5 w2)")
    parser.add_argument("--omega-end", type=float, help="sweep end [rad/s] (default 1.5 w2)")
    parser.add_argument("--csv", help="forcing file with columns time,F [s, N] or time,a_g [s, m/s2]")
    parser.add_argument("--stop-time", type=float, help="horizon [s]")
    parser.add_argument("--periods", type=float, help="horizon in primary periods")
    parser.add_argument("--output-interval", type=float, help="communication step [s]")
    parser.add_argument("--fidelity", help="model level: linear, damped, coupled or nonlinear (validated like the scene)")
    parser.add_argument("--csv-out", help="write the result table to this CSV file")
    parser.add_argument("--out", default="out", help="folder for the run's NAME.mcap and NAME.rrd (default: out)")
    parser.add_argument("--name", help="file stem of the logs (default: the scene's name)")
    parser.add_argument("--after-collapse", action="store_true",
                        help="a building that collapses: run on to the end (its outputs hold) instead of stopping")
    parser.add_argument("--no-log", action="store_true", help="write neither MCAP nor .rrd")
    parser.add_argument("--no-rrd", action="store_true", help="write the MCAP only")
    parser.add_argument("--serve", action="store_true", help="also serve the recording to Rerun viewers (gRPC)")
    parser.add_argument("--connect", metavar="URL", help="also stream to a Rerun viewer, e.g. rerun+http://host:9876/proxy")


def run_command(args):
    """pidamper run: the scene of `args` run with fmpy, logged as it asks; prints its headline figures."""
    sc = scene_from_args(args)
    params, signal = sc.start_values, sc.make_forcing()
    stop, h = sc.stop_time, sc.output_interval
    log = sc.log
    logs = None
    mcap, rrd = log.get("mcap", True), log.get("rrd", True)
    try:
        if not (mcap or rrd or args.serve or args.connect):
            result = run(params, signal, stop_time=stop, output_interval=h, fmu=args.fmu,
                         after_collapse=args.after_collapse)
        else:
            logged = run_logged(params, signal, stop_time=stop, output_interval=h, out_dir=args.out,
                                name=args.name or sc.name, fmu=args.fmu, mcap=mcap, rrd=rrd, serve=args.serve,
                                connect=args.connect, topics=log.get("mcap_topics"), views=log.get("rerun_views"),
                                scene=sc.summary(), after_collapse=args.after_collapse)
            result, logs = logged.result, logged
    except (FmuError, KeyboardInterrupt) as err:
        partial = getattr(err, "partial", None)
        if partial is not None and args.csv_out:
            partial.write_csv(args.csv_out, sc.outputs)
            print(f"wrote {args.csv_out} up to t = {partial.data['time'][-1]:.6g} s, where the run failed",
                  file=sys.stderr)
        if mcap or rrd:
            print(f"the log in {args.out}/ reads back up to the failure", file=sys.stderr)
        raise
    d = result.data
    for warning in result.meta.get("warnings", ()):
        print(f"warning from the FMU: {warning}", file=sys.stderr)
    print(f"scene {sc.name}: {sc.description}; FMU {result.fmu}")
    print(f"forcing {signal.kind} {signal.args}; {len(d) - 1} steps of {h:g} s to t = {d['time'][-1]:.6g} s")
    if "collapsed" in result.meta:
        print(f"the building collapsed in the step ending at t = {result.meta['collapsed']:.6g} s: the run stopped "
              "there (--after-collapse runs on)")
    building = "base_shear" in d.dtype.names
    swing = (f"max |x| of the damper floor {abs(d['x']).max():.6g} m, max |base_shear| "
             f"{abs(d['base_shear']).max():.6g} N" if building else f"max |theta| {abs(d['theta']).max():.6g} rad")
    if building:  # the FMU's exact running maxima
        n = sum(1 for name in d.dtype.names if name.endswith("].drift_ratio_max"))
        peaks = measures.building_peaks(d, n)
        print(f"peaks (exact): drift ratio {peaks['drift_ratio'].max():.6g} (storey "
              f"{int(peaks['drift_ratio'].argmax()) + 1}), floor absolute acceleration {peaks['a_abs'].max():.6g} m/s2, "
              f"absolute velocity {peaks['v_abs'].max():.6g} m/s")
        if d["energy_hysteretic"][-1] > 0.0:
            print(f"the storeys yielded: hysteretic energy {d['energy_hysteretic'][-1]:.6g} J")
    if "impact_force_peak" in d.dtype.names:  # the materials given: the impacts' forces (exact per impact)
        print(f"largest impact force {d['impact_force_peak'].max():.6g} N, contact pressure "
              f"{d['contact_pressure_peak'].max() / 1e6:.6g} MPa; plastic impacts {int(d['impacts_plastic'][-1])}")
    print(f"impacts {int(d['impacts'][-1])}; {swing}; "
          f"energy {d['energy'][-1]:.6g} J; dissipated {d['energy_dissipated'][-1]:.6g} J; "
          f"work in {d['work_in'][-1]:.6g} J; CPU {result.cpu_time:.3f} s")
    if args.csv_out:
        result.write_csv(args.csv_out, sc.outputs)
        print(f"wrote {args.csv_out}")
    if logs is not None:
        written = [str(p) for p in (logs.mcap, logs.rrd) if p is not None]
        print(f"logged to {' and '.join(written)} ({logs.impacts_recorded} impacts recorded individually, "
              f"{logs.impacts_unrecorded} counted only); CPU with logging {logs.cpu_time:.3f} s")
    if args.serve:
        wait_for_viewers()
    return 0


def demo(out_dir="out"):
    """Build the FMU, run the free-decay and resonance scenes with fmpy (logged to MCAP and .rrd),
    print the headline figures."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    t_build = time.perf_counter()
    fmu = find_fmu()
    print(f"FMU: {fmu} (ready in {time.perf_counter() - t_build:.1f} s)")

    free_scene = load("free-decay")
    period = 2 * math.pi / free_scene.w2
    free = _run_scene(free_scene, fmu, out)
    cpu = time.process_time()
    with FmuStepper(fmu, free_scene.parameters) as stepper:
        ratios, peaks = measures.damping_ratio(stepper, period)
    cpu_measure = time.process_time() - cpu
    p = free_scene.parameters
    a0 = p["theta_dot_0"] / free_scene.w2
    print(f"\nScene free-decay (mu={p['mu']:g}, FR={p['FR']:g}, d={p['d']:g} m, e={p['e']:g}, A0 = {a0:.3g} rad, "
          f"A0/d = {a0 * Params.from_variables(p).L2 / p['d']:.3g}), displacement form:")
    print(f"  average damping ratio, first 5 cycles: {ratios['printed']:.4f} (printed formula), "
          f"{ratios['exact']:.4f} (exact), {ratios['accumulated']:.4f} (accumulated from peak 1)")
    print(f"  peaks theta_m [rad]: {', '.join(f'{pk.theta:.4f}' for pk in peaks)}")
    print(f"  impacts in {free_scene.stop_time / period:g} periods: {int(free.data['impacts'][-1])}; "
          f"CPU: run {free.cpu_time:.3f} s ({len(free.data) - 1} steps), measure {cpu_measure:.3f} s")
    _print_warnings(free)

    forced_scene = load("resonance")
    forced = _run_scene(forced_scene, fmu, out)
    drive = forced_scene.make_forcing()
    horizon = forced_scene.stop_time
    values = {**forced_scene.parameters, **drive.start_values}
    cpu = time.process_time()
    with FmuStepper(fmu, values) as damped, FmuStepper(fmu, {**values, "mu": 0.0}, instance_name="bare") as bare:
        ratio, with_d, without = measures.amplitude_ratio(damped, bare, horizon, period / 200)
    cpu_measure = time.process_time() - cpu
    q = forced_scene.parameters
    print(f"\nScene resonance (mu={q['mu']:g}, FR={q['FR']:g}, d={q['d']:g} m, e={q['e']:g}, F0 = 0.01 M g "
          f"cos(w2 t), horizon {horizon / period:g} periods):")
    print(f"  amplitude ratio max|theta| with / without damper: {ratio:.4f} "
          f"({abs(with_d.theta):.5f} / {abs(without.theta):.5f} rad)")
    print(f"  impacts: {int(forced.data['impacts'][-1])}; CPU: run {forced.cpu_time:.3f} s "
          f"({len(forced.data) - 1} steps), measure {cpu_measure:.3f} s")
    _print_warnings(forced)
    print(f"\nWritten to {out}/: free-decay and resonance as .csv, .mcap (Foxglove) and .rrd "
          f"(rerun {out}/resonance.rrd)")
    return 0


def _print_warnings(result):
    for text in result.meta.get("warnings", ()):
        print("  FMU warning: " + text.partition(": ")[2])


def _run_scene(sc, fmu, out):
    """A scene's logged run into out/, its table as CSV beside the logs."""
    result = run_logged(sc.start_values, sc.make_forcing(), stop_time=sc.stop_time, output_interval=sc.output_interval,
                        out_dir=out, name=sc.name, fmu=fmu, topics=sc.log.get("mcap_topics"),
                        views=sc.log.get("rerun_views"), scene=sc.summary()).result
    result.write_csv(out / f"{sc.name}.csv", sc.outputs)
    return result

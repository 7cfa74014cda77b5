"""Command line: pidamper run | replay | demo.

    pidamper run [--forcing none|harmonic|sweep|csv] [-p NAME=VALUE ...] [--stop-time S | --periods N]
                 [--output-interval H] [--fmu PATH] [--csv-out FILE] [--out DIR] [--serve | --connect URL]
    pidamper replay RUN.mcap --out FILE.rrd [--serve | --connect URL]
    pidamper demo [--out DIR]
"""
import argparse
import math
import sys
import time
from pathlib import Path

from . import forcing as forcing_mod
from .fmu import find_fmu
from .logged_run import replay, run_logged
from .simulation import FmuError, resonance, run
from .stepper import FmuStepper
from . import measures

# the paper's free-vibration case (section 3) and forced case (section 4); Tables 1 and 2
# were lost, the values not named in the text are ours (README, "Default scenes")
FREE_DECAY = {"mu": 0.1, "FR": 5.0, "d": 0.1, "e": 0.2, "L2": 1.0, "g": 9.81, "theta_dot_0": 0.7 * math.sqrt(9.81)}
RESONANCE = {"mu": 0.02, "FR": 5.0, "d": 0.1, "e": 0.2, "L2": 1.0, "g": 9.81, "theta_dot_0": 0.0}
RESONANCE_F0 = 0.01 * 9.81  # N: F0 = 0.01 M g with M = 1 kg
RESONANCE_PERIODS = 20


def _parse_param(text):
    name, sep, value = text.partition("=")
    if not sep:
        raise argparse.ArgumentTypeError(f"-p {text!r} is not allowed: use NAME=VALUE")
    try:
        number = int(value) if name == "contact_form" else float(value)
    except ValueError:
        raise argparse.ArgumentTypeError(f"-p {text!r} is not allowed: {value!r} is not a number") from None
    return name.strip(), number


def _forcing(args, params):
    w2 = resonance(params)
    if args.forcing == "none":
        return forcing_mod.none()
    if args.forcing == "harmonic":
        omega = w2 if args.omega is None else args.omega
        return forcing_mod.harmonic(args.F0, omega, args.phi, sampled=args.sampled)
    if args.forcing == "sweep":
        start = 0.5 * w2 if args.omega_start is None else args.omega_start
        end = 1.5 * w2 if args.omega_end is None else args.omega_end
        return forcing_mod.sweep(args.F0, start, end, args.stop_time or args.periods * 2 * math.pi / w2)
    if args.forcing == "csv":
        if args.csv is None:
            raise SystemExit("--forcing csv needs --csv FILE (columns time,F in s and N)")
        return forcing_mod.from_csv(args.csv)
    raise SystemExit(f"--forcing {args.forcing!r} is not allowed: none, harmonic, sweep or csv")


def cmd_run(args):
    params = dict(args.param or [])
    signal = _forcing(args, params)
    stop = args.stop_time or args.periods * 2 * math.pi / resonance(params)
    logs = None
    try:
        if args.no_log:
            result = run(params, signal, stop_time=stop, output_interval=args.output_interval, fmu=args.fmu)
        else:
            logged = run_logged(params, signal, stop_time=stop, output_interval=args.output_interval,
                                out_dir=args.out, name=args.name, fmu=args.fmu, rrd=not args.no_rrd,
                                serve=args.serve, connect=args.connect)
            result, logs = logged.result, logged
    except (FmuError, KeyboardInterrupt) as err:
        partial = getattr(err, "partial", None)
        if partial is not None and args.csv_out:
            partial.write_csv(args.csv_out)
            print(f"wrote {args.csv_out} up to t = {partial.data['time'][-1]:.6g} s, where the run failed",
                  file=sys.stderr)
        if not args.no_log:
            print(f"the log in {args.out}/ reads back up to the failure", file=sys.stderr)
        raise
    d = result.data
    print(f"FMU {result.fmu}")
    print(f"forcing {signal.kind} {signal.args}; {len(d) - 1} steps of {args.output_interval} s to t = {d['time'][-1]:.6g} s")
    print(f"impacts {int(d['impacts'][-1])}; max |theta| {abs(d['theta']).max():.6g} rad; "
          f"energy {d['energy'][-1]:.6g} J; dissipated {d['energy_dissipated'][-1]:.6g} J; "
          f"work in {d['work_in'][-1]:.6g} J; CPU {result.cpu_time:.3f} s")
    if args.csv_out:
        result.write_csv(args.csv_out)
        print(f"wrote {args.csv_out}")
    if logs is not None:
        written = [str(p) for p in (logs.mcap, logs.rrd) if p is not None]
        print(f"logged to {' and '.join(written)} ({logs.impacts_recorded} impacts recorded individually, "
              f"{logs.impacts_unrecorded} counted only); CPU with logging {logs.cpu_time:.3f} s")
    if args.serve:
        _wait_for_viewers()
    return 0


def cmd_replay(args):
    if not (args.out or args.serve or args.connect):
        raise ValueError("replay needs --out FILE.rrd, --serve or --connect URL")
    info = replay(args.mcap, args.out, serve=args.serve, connect=args.connect)
    print(f"replayed run {info['recording_id']} from {args.mcap}" + (f" into {args.out}" if args.out else ""))
    if args.serve:
        _wait_for_viewers()
    return 0


def _wait_for_viewers():
    print("serving on rerun+http://127.0.0.1:9876/proxy; Ctrl-C to stop", file=sys.stderr)
    try:
        while True:
            time.sleep(1.0)
    except KeyboardInterrupt:
        return


def demo(out_dir="out"):
    """Build the FMU, run free decay and resonance with fmpy (logged to MCAP and .rrd), print the
    headline figures."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    t_build = time.perf_counter()
    fmu = find_fmu()
    print(f"FMU: {fmu} (ready in {time.perf_counter() - t_build:.1f} s)")
    w2 = resonance(FREE_DECAY)
    period = 2 * math.pi / w2

    free = run_logged(FREE_DECAY, forcing_mod.none(), stop_time=10 * period, output_interval=period / 200,
                      out_dir=out, name="free-decay", fmu=fmu).result
    free.write_csv(out / "free-decay.csv")
    cpu = time.process_time()
    with FmuStepper(fmu, FREE_DECAY) as stepper:
        ratios, peaks = measures.damping_ratio(stepper, period)
    cpu_measure = time.process_time() - cpu
    a0 = FREE_DECAY["theta_dot_0"] / w2
    print(f"\nFree decay (mu=0.1, FR=5, d=0.1 m, e=0.2, A0 = {a0:.3g} rad, A0/d = {a0 * 1.0 / 0.1:.3g}), displacement form:")
    print(f"  average damping ratio, first 5 cycles: {ratios['printed']:.4f} (printed formula), "
          f"{ratios['exact']:.4f} (exact), {ratios['accumulated']:.4f} (accumulated from peak 1)")
    print(f"  peaks theta_m [rad]: {', '.join(f'{p.theta:.4f}' for p in peaks)}")
    print(f"  impacts in 10 periods: {int(free.data['impacts'][-1])}; CPU: run {free.cpu_time:.3f} s "
          f"({len(free.data) - 1} steps), measure {cpu_measure:.3f} s")

    horizon = RESONANCE_PERIODS * period
    drive = forcing_mod.harmonic(RESONANCE_F0, w2, math.pi / 2)  # cosine forcing, the paper's form
    forced = run_logged(RESONANCE, drive, stop_time=horizon, output_interval=period / 200, out_dir=out,
                        name="resonance", fmu=fmu).result
    forced.write_csv(out / "resonance.csv")
    cpu = time.process_time()
    with FmuStepper(fmu, {**RESONANCE, **drive.start_values}) as damped, \
            FmuStepper(fmu, {**RESONANCE, **drive.start_values, "mu": 0.0}, instance_name="baseline") as bare:
        ratio, with_d, without = measures.amplitude_ratio(damped, bare, horizon, period / 200)
    cpu_measure = time.process_time() - cpu
    print(f"\nResonance (mu=0.02, FR=5, d=0.1 m, e=0.2, F0 = 0.01 M g cos(w2 t), horizon {RESONANCE_PERIODS} periods):")
    print(f"  amplitude ratio max|theta| with / without damper: {ratio:.4f} "
          f"({abs(with_d.theta):.5f} / {abs(without.theta):.5f} rad)")
    print(f"  impacts: {int(forced.data['impacts'][-1])}; CPU: run {forced.cpu_time:.3f} s "
          f"({len(forced.data) - 1} steps), measure {cpu_measure:.3f} s")
    print(f"\nWritten to {out}/: free-decay and resonance as .csv, .mcap (Foxglove) and .rrd (rerun {out}/resonance.rrd)")
    return 0


def _bench(rest):
    from .bench.workprecision import main as bench_main
    return bench_main(rest)


def _paper(rest):
    from .paper import main as paper_main
    return paper_main(rest)


def _study(rest):
    from .study import main as study_main
    return study_main(rest)


def _stress(rest):
    from .bench.stress import main as stress_main
    return stress_main(rest)


def main(argv=None):
    parser = argparse.ArgumentParser(prog="pidamper", description="Pendulum impact damper FMU harness")
    sub = parser.add_subparsers(dest="command", required=True)

    p_run = sub.add_parser("run", help="run the FMU with fmpy against a forcing signal")
    p_run.add_argument("--fmu", help="FMU file (default: build or reuse dist/PendulumImpactDamper.fmu)")
    p_run.add_argument("-p", "--param", action="append", type=_parse_param, metavar="NAME=VALUE",
                       help="FMU parameter or initial state, e.g. -p mu=0.02 -p theta_dot_0=1.5 (repeatable)")
    p_run.add_argument("--forcing", default="none", choices=["none", "harmonic", "sweep", "csv"])
    p_run.add_argument("--F0", type=float, default=RESONANCE_F0, help="force amplitude [N]")
    p_run.add_argument("--omega", type=float, help="harmonic frequency [rad/s] (default: resonance w2)")
    p_run.add_argument("--phi", type=float, default=0.0, help="harmonic phase [rad]")
    p_run.add_argument("--sampled", action="store_true",
                       help="feed the harmonic through input F (held per step) instead of the built-in force")
    p_run.add_argument("--omega-start", type=float, help="sweep start [rad/s] (default 0.5 w2)")
    p_run.add_argument("--omega-end", type=float, help="sweep end [rad/s] (default 1.5 w2)")
    p_run.add_argument("--csv", help="forcing file with columns time,F [s, N]")
    p_run.add_argument("--stop-time", type=float, help="horizon [s] (default: --periods)")
    p_run.add_argument("--periods", type=float, default=10.0, help="horizon in primary periods (default 10)")
    p_run.add_argument("--output-interval", type=float, default=0.01, help="communication step [s]")
    p_run.add_argument("--csv-out", help="write the result table to this CSV file")
    p_run.add_argument("--out", default="out", help="folder for the run's NAME.mcap and NAME.rrd (default: out)")
    p_run.add_argument("--name", default="run", help="file stem of the logs (default: run)")
    p_run.add_argument("--no-log", action="store_true", help="write neither MCAP nor .rrd")
    p_run.add_argument("--no-rrd", action="store_true", help="write the MCAP only")
    p_run.add_argument("--serve", action="store_true", help="also serve the recording to Rerun viewers (gRPC)")
    p_run.add_argument("--connect", metavar="URL", help="also stream to a Rerun viewer, e.g. rerun+http://host:9876/proxy")
    p_run.set_defaults(func=cmd_run)

    p_replay = sub.add_parser("replay", help="turn a run's MCAP into a Rerun recording")
    p_replay.add_argument("mcap", help="the run's .mcap")
    p_replay.add_argument("--out", help="the .rrd to write")
    p_replay.add_argument("--serve", action="store_true", help="serve the recording to Rerun viewers (gRPC)")
    p_replay.add_argument("--connect", metavar="URL", help="stream to a Rerun viewer at URL")
    p_replay.set_defaults(func=cmd_replay)

    p_demo = sub.add_parser("demo", help="build the FMU, run free decay and resonance, print headline figures")
    p_demo.add_argument("--out", default="out", help="folder for the CSV, MCAP and .rrd files (default: out)")
    p_demo.set_defaults(func=lambda a: demo(a.out))

    sub.add_parser("bench", help="work-precision benchmark (pidamper bench --help)")
    sub.add_parser("stress", help="hard-case stability table (pidamper stress --help)")
    sub.add_parser("study", help="parametric study over a grid (pidamper study --help)")
    sub.add_parser("paper", help="regenerate the paper's figures for both readings (pidamper paper --help)")

    argv = sys.argv[1:] if argv is None else list(argv)
    own = {"bench": _bench, "stress": _stress, "study": _study, "paper": _paper}
    if argv and argv[0] in own:  # their own parsers take the rest
        return own[argv[0]](argv[1:])
    args = parser.parse_args(argv)
    try:
        return args.func(args)
    except (ValueError, FileNotFoundError, KeyError, FmuError) as err:
        print(f"pidamper: error: {err}", file=sys.stderr)
        return 2
    except KeyboardInterrupt as err:
        print(f"pidamper: {err or 'interrupted'}", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())

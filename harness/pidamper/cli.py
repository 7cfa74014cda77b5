"""Command line: pidamper run | replay | demo | bench | stress | study | paper | cosim | assess | design.

    pidamper run [SCENE] [--forcing KIND] [-p NAME=VALUE ...] [--stop-time S | --periods N]
                 [--output-interval H] [--fmu PATH] [--csv-out FILE] [--out DIR] [--serve | --connect URL]
    pidamper replay RUN.mcap --out FILE.rrd [--serve | --connect URL]
    pidamper demo [--out DIR]

The commands live in their rooms; this module only dispatches.  The commands with their own parser
(bench, stress, study, paper, cosim, assess, design) are imported when called.
"""
import argparse
import importlib
import os
import sys

from .running.simulation import FmuError

#: command -> (module:function taking the rest of argv, help)
OWN_PARSER = {
    "bench": ("pidamper.benchmarks.workprecision:main", "work-precision benchmark (pidamper bench --help)"),
    "stress": ("pidamper.benchmarks.stress:main", "hard-case stability table (pidamper stress --help)"),
    "study": ("pidamper.studies.study:main", "parametric study over a grid (pidamper study --help)"),
    "paper": ("pidamper.studies.paper:main", "regenerate the paper's figures for both readings (pidamper paper --help)"),
    "cosim": ("pidamper.cosim.command:cli_main",
              "the damper unit FMU on a ShearBuilding<N> FMU, or with --opensees MODEL.py on a node of your "
              "OpenSees model, co-simulated (pidamper cosim --help shows both)"),
    "assess": ("pidamper.assessment.assess:cli_main",
               "performance-based assessment: suite, stripes, fragility, risk (pidamper assess --help)"),
    "design": ("pidamper.design.command:cli_main",
               "search the damper's parameters on a building with optuna (pidamper design --help)"),
}


def _own(command, rest):
    module, _, function = OWN_PARSER[command][0].partition(":")
    return getattr(importlib.import_module(module), function)(rest)


def cmd_replay(args):
    from .runlog.logged_run import replay, wait_for_viewers

    if not (args.out or args.serve or args.connect):
        raise ValueError("replay needs --out FILE.rrd, --serve or --connect URL")
    info = replay(args.mcap, args.out, serve=args.serve, connect=args.connect)
    print(f"replayed run {info['recording_id']} from {args.mcap}" + (f" into {args.out}" if args.out else ""))
    if args.serve:
        wait_for_viewers()
    return 0


def parser():
    from .scenes import command as scenes

    top = argparse.ArgumentParser(prog="pidamper", description="Pendulum impact damper FMU harness")
    sub = top.add_subparsers(dest="command", required=True)

    p_run = sub.add_parser("run", help="run a scene: the FMU with fmpy against a forcing signal, logged")
    scenes.add_arguments(p_run)
    p_run.set_defaults(func=scenes.run_command)

    p_replay = sub.add_parser("replay", help="turn a run's MCAP into a Rerun recording")
    p_replay.add_argument("mcap", help="the run's .mcap")
    p_replay.add_argument("--out", help="the .rrd to write")
    p_replay.add_argument("--serve", action="store_true", help="serve the recording to Rerun viewers (gRPC)")
    p_replay.add_argument("--connect", metavar="URL", help="stream to a Rerun viewer at URL")
    p_replay.set_defaults(func=cmd_replay)

    p_demo = sub.add_parser("demo", help="build the FMU, run free decay and resonance, print headline figures")
    p_demo.add_argument("--out", default="out", help="folder for the CSV, MCAP and .rrd files (default: out)")
    p_demo.set_defaults(func=lambda a: scenes.demo(a.out))

    for command, (_, text) in OWN_PARSER.items():
        sub.add_parser(command, help=text)
    return top


def main(argv=None):
    argv = sys.argv[1:] if argv is None else list(argv)
    if argv and argv[0] == "cosim" and any(a == "--opensees" or a.startswith("--opensees=") for a in argv):
        code = importlib.import_module("pidamper.opensees.command").main(argv[1:])
        # OpenSeesPy tears its library down at interpreter exit, and that teardown has crashed a
        # finished process (running/isolated.py): the logs are closed, so leave without it
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(code)
    if argv and argv[0] == "cosim" and any(a in ("-h", "--help") for a in argv):  # both forms' options
        from .cosim.command import cli_main
        from .opensees.command import parser as opensees_parser

        return cli_main(argv[1:], more_help=opensees_parser().format_help())
    if argv and argv[0] in OWN_PARSER:  # their own parsers take the rest
        return _own(argv[0], argv[1:])
    args = parser().parse_args(argv)
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

"""python -m build_fmu [--out DIR]: build PendulumImpactDamper.fmu (default dist/)."""
import argparse

from .builder import build


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python -m build_fmu", description=__doc__)
    parser.add_argument("--out", default="dist", help="output folder (default: dist)")
    args = parser.parse_args(argv)
    print(build(args.out))


if __name__ == "__main__":
    main()

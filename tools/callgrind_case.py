"""Instructions the physics core spends per communication step, by function (callgrind), for one
case of tools/speed_compare.py in one source tree: a profile that does not move with the machine's
load, for before and after a change.

    python tools/callgrind_case.py [--tree DIR] [--case NAME] [--steps 1500] [--top 15]

Runs the case's loop (Damper.advance, or YieldingMotion.advance for the bare building, over steps
of 0.01 s) under `valgrind --tool=callgrind`, counting only inside that advance, in the tree's physics as it
imports there (compiled if that tree is compiled: python -m build_fmu.compile there first).
Prints the instructions per step in all and, for the physics' own functions, their inclusive
instructions per step and share.  Needs valgrind.
"""
import argparse
import os
import re
import subprocess
import sys
import tempfile
from pathlib import Path

from speed_compare import BARE, CASES, runner

ROOT = Path(__file__).resolve().parents[1]
_FUNCTION = re.compile(r"^\s*([\d,]+) \(\s*[\d.]+%\)\s+\S*?:(?:__pyx_pw|__pyx_f)_\d+pidamper_physics_(\w+?)\s*(?:\[|$)")


def readable(mangled):
    """module.Class.method or module.function of Cython's name for it ('5modal_6Motion_13bounds':
    names prefixed by their lengths; a Python wrapper's method or function by a counter)."""
    digits = re.match(r"\d+", mangled).group()
    module = mangled[len(digits):len(digits) + int(digits)]
    rest = mangled[len(digits) + int(digits) + 1:]
    size = re.match(r"\d+", rest)
    if size:
        cls = rest[len(size.group()):len(size.group()) + int(size.group())]
        after = rest[len(size.group()) + int(size.group()):]
        if cls.isidentifier() and after.startswith("_"):  # a method: '_<counter><name>' or '_<name>'
            method = re.sub(r"^\d+", "", after[1:])
            return f"{module}.{cls}.{method}"
        rest = rest[len(size.group()):]  # a function's wrapper: '<counter><name>'
    return f"{module}.{rest}"


def profile(tree, case, steps):
    """(instructions in the case's advance, {function: inclusive instructions}) over `steps` steps."""
    with tempfile.TemporaryDirectory() as tmp:
        script, out = Path(tmp) / "case.py", Path(tmp) / "callgrind.out"
        script.write_text(runner(case))
        env = dict(os.environ, PYTHONPATH=str(Path(tree) / "fmu_src"))
        subprocess.run(["valgrind", "--tool=callgrind", f"--callgrind-out-file={out}",
                        f"--toggle-collect=*{'YieldingMotion' if case == BARE else 'Damper'}_*advance", sys.executable,
                        str(script), str(steps)],
                       env=env, check=True, capture_output=True)
        text = subprocess.run(["callgrind_annotate", "--inclusive=yes", str(out)], check=True,
                              capture_output=True, text=True).stdout
    total = int(re.search(r"([\d,]+) \(100\.0%\)\s+PROGRAM TOTALS", text).group(1).replace(",", ""))
    functions = {}
    for line in text.splitlines():
        match = _FUNCTION.match(line)
        if match:  # a cpdef function's C body and its Python wrapper: the larger is its inclusive count
            name = readable(match.group(2))
            functions[name] = max(functions.get(name, 0), int(match.group(1).replace(",", "")))
    return total, functions


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tree", default=str(ROOT), help="source tree (default: this one)")
    parser.add_argument("--case", default="3-storey yielding building with damper", choices=sorted(CASES) + [BARE])
    parser.add_argument("--steps", type=int, default=1500)
    parser.add_argument("--top", type=int, default=15)
    args = parser.parse_args(argv)
    said = subprocess.run([sys.executable, "-c", "import pidamper_physics as p; print(p.BUILD)"], check=True,
                          capture_output=True, text=True,
                          env=dict(os.environ, PYTHONPATH=str(Path(args.tree) / "fmu_src"))).stdout.strip()
    total, functions = profile(args.tree, args.case, args.steps)
    print(f"{args.case}, {args.steps} steps, physics {said}: {total / args.steps:,.0f} instructions per step\n")
    print("| function (inclusive) | instructions per step | share |\n|---|---:|---:|")
    for name, count in sorted(functions.items(), key=lambda item: -item[1])[:args.top]:
        print(f"| {name} | {count / args.steps:,.0f} | {count / total:.1%} |")


if __name__ == "__main__":
    main()

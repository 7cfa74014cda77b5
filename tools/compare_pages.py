"""Compare the numbers of a regenerated page folder with the shipped one (issue 22, item 7).

    python tools/compare_pages.py SHIPPED_DIR REGENERATED_DIR [--rel 1e-13]

Markdown and CSV files present in both folders are read as text; every number on a line is
compared with the number at the same place of the same line in the other file, relative to the
larger magnitude of the two.  Lines whose words differ (a changed sentence, a missing row) are
listed as such.  Prints, per file, how many numbers agree within --rel, and each line where one
does not, so that timings (which are expected to move) can be told from results (which must not).
"""
import argparse
import re
from pathlib import Path

NUMBER = re.compile(r"[-+]?(?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?")


def split(line):
    """(the line with numbers replaced by #, the numbers as floats)."""
    return NUMBER.sub("#", line), [float(n) for n in NUMBER.findall(line)]


def compare_file(old, new, rel):
    """(numbers compared, numbers agreeing, list of (line number, worst relative difference, old, new))."""
    old_lines, new_lines = old.read_text().splitlines(), new.read_text().splitlines()
    compared = agreeing = 0
    bad = []
    for k, (a, b) in enumerate(zip(old_lines, new_lines), 1):
        (sa, na), (sb, nb) = split(a), split(b)
        if sa != sb or len(na) != len(nb):
            bad.append((k, float("inf"), a, b))
            continue
        worst = 0.0
        for x, y in zip(na, nb):
            scale = max(abs(x), abs(y))
            diff = abs(x - y) / scale if scale else 0.0
            compared += 1
            agreeing += diff <= rel
            worst = max(worst, diff)
        if worst > rel:
            bad.append((k, worst, a, b))
    if len(old_lines) != len(new_lines):
        bad.append((min(len(old_lines), len(new_lines)) + 1, float("inf"),
                    f"<{len(old_lines)} lines>", f"<{len(new_lines)} lines>"))
    return compared, agreeing, bad


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("shipped", type=Path)
    parser.add_argument("regenerated", type=Path)
    parser.add_argument("--rel", type=float, default=1e-13)
    parser.add_argument("--width", type=int, default=160, help="characters of each differing line shown")
    args = parser.parse_args(argv)
    for old in sorted(args.shipped.rglob("*")):
        if old.suffix not in (".md", ".csv"):
            continue
        new = args.regenerated / old.relative_to(args.shipped)
        if not new.is_file():
            print(f"{old.relative_to(args.shipped)}: not regenerated")
            continue
        compared, agreeing, bad = compare_file(old, new, args.rel)
        print(f"{old.relative_to(args.shipped)}: {agreeing}/{compared} numbers within {args.rel:g}, "
              f"{len(bad)} line(s) differ")
        for k, worst, a, b in bad:
            print(f"  line {k} (worst {worst:.1e}):\n    - {a[:args.width]}\n    + {b[:args.width]}")


if __name__ == "__main__":
    main()

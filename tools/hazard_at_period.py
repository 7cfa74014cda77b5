"""Write a site's mean hazard curve of Sa at a period between two of its shipped curves: at each rate
of exceedance ln Sa is linear in ln T between the two curves' intensities (hazard.at_period).

    python tools/hazard_at_period.py studies/hazard/los-angeles-2018-sa2p0.csv 2.0 \\
        studies/hazard/los-angeles-2018-sa3p0.csv 3.0 2.28 studies/hazard/los-angeles-2018-sa2p28.csv

The two source files' comment headers are carried into the new file's, under a line that says how it
was made."""
import sys

from pidamper.assessment import hazard


def header(path):
    with open(path) as handle:
        return [line.rstrip("\n") for line in handle if line.startswith("#")]


def main(short, t_short, long, t_long, period, target):
    a = hazard.read(short, period=float(t_short))
    b = hazard.read(long, period=float(t_long))
    curve = hazard.at_period(a, b, float(period))
    lines = [f"# Mean hazard curve of Sa({float(period):g} s, 5 %) [g] interpolated between the two curves below "
             f"(Sa({float(t_short):g} s) and Sa({float(t_long):g} s)): at each rate of exceedance, ln Sa linear in "
             f"ln T (python tools/hazard_at_period.py {' '.join(sys.argv[1:])}).",
             f"# --- {short}:", *header(short), f"# --- {long}:", *header(long), "im,rate"]
    lines += [f"{x!r},{r!r}" for x, r in zip(curve.x.tolist(), curve.rates["mean"].tolist())]
    with open(target, "w") as handle:
        handle.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main(*sys.argv[1:7])

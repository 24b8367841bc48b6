"""Compares the balance.csv reports that two builds wrote in the same test (for example
test_balance_graph.py run once per build with TMPDIR pointing at an empty folder each time):
  python3 tests/support/compare_balance_reports.py BEFORE_TMPDIR AFTER_TMPDIR
Runs are paired by their directory's prefix (balance_<kind>_<ranks>) and the order they started
in. Prints, per pair, `identical` (byte for byte), `untimed-same` (every column but the timings:
partition and migration seconds, measured imbalance, cpu_*) or `DIFFERENT`. Runs whose costs come
from timings (cost calibrated, timed, fitted) differ between two runs of one build too."""
import csv
import os
import re
import sys

TIMED = {"partition_seconds", "migration_seconds_total", "measured_imbalance", "cpu_work_max",
         "cpu_work_avg"}


def runs(root):
    """balance.csv files by run prefix, in the order their runs started."""
    def started(d):  # the first input copied into the run's directory
        return min(os.stat(os.path.join(root, d, f)).st_ctime_ns
                   for f in os.listdir(os.path.join(root, d)) if f.startswith("in."))
    out = {}
    dirs = [d for d in os.listdir(root) if os.path.exists(os.path.join(root, d, "balance.csv"))]
    for d in sorted(dirs, key=started):
        m = re.match(r"(balance_.*?_[0-9]+)_", d)
        if m:
            out.setdefault(m.group(1), []).append(os.path.join(root, d, "balance.csv"))
    return out


def compare(fa, fb):
    with open(fa) as a, open(fb) as b:
        if a.read() == b.read():
            return "identical"
    with open(fa) as a, open(fb) as b:
        ra, rb = list(csv.DictReader(a)), list(csv.DictReader(b))
    cols = [c for c in (ra[0] if ra else {}) if c not in TIMED and not c.startswith("cpu_rank")]
    same = len(ra) == len(rb) and all(x[c] == y[c] for x, y in zip(ra, rb) for c in cols)
    return "untimed-same" if same else "DIFFERENT"


def main():
    before, after = runs(sys.argv[1]), runs(sys.argv[2])
    for key in sorted(before):
        for fa, fb in zip(before[key], after.get(key, [])):
            print(f"{compare(fa, fb):13} {key}: {fa} {fb}")


if __name__ == "__main__":
    main()

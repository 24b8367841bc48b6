"""Reader for the PMPI counter (libfracdem_mpicount.so): runs a script with it, loads the per-rank
JSON files, takes the difference of two runs of different lengths (so that set-up traffic
cancels and what remains is exactly the traffic of the steps in between) and summarises it per
rank and step. Call sites are resolved to function names with `nm`.

    python3 tests/support/mpicount.py PREFIX [--base PREFIX0] [--steps N]
"""
import argparse
import bisect
import glob
import json
import os
import subprocess

CATS = ("send", "recv", "wait", "coll", "comm", "crecv")  # crecv: bytes received from collectives


def mpirun_counted(np_, lib, prefix):
    """mpirun command line that preloads the counter into the ranks (not into mpirun itself)."""
    cmd = ["mpirun", "-np", str(np_)]
    if os.geteuid() == 0:
        cmd.append("--allow-run-as-root")
    if np_ > (os.cpu_count() or 1):
        cmd.append("--oversubscribe")
    return cmd + ["-x", f"LD_PRELOAD={lib}", "-x", f"FRACDEM_MPICOUNT={prefix}"]


def run(exe, script, np_, workdir, lib, tag, variables=None, timeout=900):
    """Run `exe -in script` counted; return (stdout text, list of per-rank reports)."""
    prefix = os.path.join(workdir, f"mpicount_{tag}")
    for old in glob.glob(prefix + ".*.json"):
        os.remove(old)
    cmd = mpirun_counted(np_, lib, prefix) + [exe, "-echo", "none", "-in", script]
    for k, v in (variables or {}).items():
        cmd += ["-var", k, str(v)]
    env = dict(os.environ, OMPI_MCA_rmaps_base_oversubscribe="1")
    r = subprocess.run(cmd, cwd=workdir, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                       text=True, errors="replace", timeout=timeout, env=env)
    if r.returncode != 0 or "ERROR" in r.stdout:
        raise AssertionError(f"{' '.join(cmd)} failed (rc={r.returncode}) in {workdir}:\n"
                             f"{r.stdout[-4000:]}")
    return r.stdout, load(prefix, np_)


def load(prefix, np_=None):
    files = sorted(glob.glob(prefix + ".*.json"), key=lambda p: int(p.split(".")[-2]))
    ranks = [json.load(open(p)) for p in files]
    for r, path in zip(ranks, files):  # call sites resolve against the module files as they are
        for module in r["modules"] + [r["exe"]]:
            if os.path.isfile(module) and os.path.getmtime(module) > os.path.getmtime(path):
                print(f"warning: {module} changed after {path} was written: call-site names "
                      f"will be wrong")
                break
        break
    if np_ is not None and len(ranks) != np_:
        raise AssertionError(f"expected {np_} counter files {prefix}.*.json, found {len(ranks)}")
    return ranks


class Symbols:
    """Function names of call-site offsets, per module file (`nm -C`, cached)."""

    def __init__(self):
        self.tables = {}

    def _table(self, path):
        if path not in self.tables:
            addrs, names = [], []
            out = ""
            for flags in (["-C"], ["-C", "-D"]):  # a stripped library has dynamic symbols only
                try:
                    out = subprocess.run(["nm", *flags, "--defined-only", path],
                                         stdout=subprocess.PIPE, stderr=subprocess.DEVNULL,
                                         text=True).stdout
                except OSError:
                    out = ""
                if out.strip():
                    break
            rows = []
            for line in out.splitlines():
                w = line.split(" ", 2)
                if len(w) == 3 and w[1] in "tTwW":
                    rows.append((int(w[0], 16), w[2]))
            rows.sort()
            for a, n in rows:
                addrs.append(a)
                names.append(n)
            self.tables[path] = (addrs, names)
        return self.tables[path]

    def name(self, path, offset):
        addrs, names = self._table(path)
        k = bisect.bisect_right(addrs, offset - 1) - 1  # the return address follows the call
        return names[k] if k >= 0 else "?"


SYMBOLS = Symbols()


def owner_class(function_name):
    """Which code made the call: the communicator, the balance fix (with the MPI pieces of the
    balance policy, namespace fracdem::balance), other project code."""
    if "CommGraph" in function_name:
        return "CommGraph"
    if "FixBalanceGraph" in function_name or "fracdem::balance::" in function_name:
        return "FixBalanceGraph"
    return "other"


def sites(report, exe=None):
    """Per call site: dict keyed by (module basename, caller function, MPI function, category)."""
    out = {}
    exe = exe or report["exe"]
    for s in report["sites"]:
        path = report["modules"][s["module"]] if s["module"] >= 0 else "?"
        if not path.startswith("/") and os.path.basename(path) == os.path.basename(exe):
            path = exe
        caller = SYMBOLS.name(path, s["offset"]) if path != "?" else "?"
        key = (os.path.basename(path), caller, s["func"], s["cat"])
        c = out.setdefault(key, [0, 0])
        c[0] += s["count"]
        c[1] += s["bytes"]
    return out


def difference(long_run, short_run):
    """Per rank: totals, per-destination sends and call sites of long_run minus short_run."""
    diffs = []
    for a, b in zip(long_run, short_run):
        d = {"rank": a["rank"], "size": a["size"], "exe": a["exe"]}
        d["totals"] = {c: [a["totals"][c][k] - b["totals"][c][k] for k in (0, 1)] for c in CATS}
        d["dest"] = [[x[0] - y[0], x[1] - y[1]] for x, y in zip(a["dest"], b["dest"])]
        sa, sb = sites(a), sites(b)
        d["sites"] = {k: [v[0] - sb.get(k, [0, 0])[0], v[1] - sb.get(k, [0, 0])[1]]
                      for k, v in sa.items()}
        diffs.append(d)
    return diffs


def as_diff(run):
    """A single run in the shape of difference() (whole run, set-up included)."""
    return [dict(r, sites=sites(r)) for r in run]


def summarise(diffs, steps):
    """Per rank and step figures of a difference (or of a whole run with as_diff)."""
    n = len(diffs)
    msgs = [d["totals"]["send"][0] / steps for d in diffs]
    nbytes = [d["totals"]["send"][1] / steps for d in diffs]
    partners = [sum(1 for r, x in enumerate(d["dest"]) if x[0] > 0 and r != d["rank"])
                for d in diffs]
    # Per-step partners: destinations that get a message in at least half of the steps (forward
    # communication), as against those reached only on reneighbouring steps.
    step_partners = [sum(1 for r, x in enumerate(d["dest"]) if x[0] >= 0.5 * steps and
                         r != d["rank"]) for d in diffs]
    # Messages per step to one destination (worst rank and destination): 1 where every
    # communication sends one message per partner, more where a partner gets one per swap.
    dest_rate = max(x[0] / steps for d in diffs for r, x in enumerate(d["dest"]) if r != d["rank"])
    coll = [d["totals"]["coll"][0] / steps for d in diffs]
    waits = [(d["totals"]["wait"][0] + d["totals"]["recv"][0]) / steps for d in diffs]
    by_owner = {}
    for d in diffs:
        exe = os.path.basename(d["exe"])
        for (module, caller, func, cat), (count, _) in d["sites"].items():
            if cat != "coll" or module != exe:
                continue
            cls = owner_class(caller)
            by_owner[cls] = max(by_owner.get(cls, 0.0), count / steps)
    return {
        "ranks": n,
        "msgs_avg": sum(msgs) / n, "msgs_max": max(msgs),
        "bytes_avg": sum(nbytes) / n, "bytes_max": max(nbytes),
        "partners_avg": sum(partners) / n, "partners_max": max(partners),
        "step_partners_avg": sum(step_partners) / n, "step_partners_max": max(step_partners),
        "dest_rate_max": dest_rate, "msgs": msgs, "step_partners": step_partners,
        "coll_max": max(coll), "recv_wait_avg": sum(waits) / n,
        "project_coll": by_owner,
    }


def site_lines(diffs, steps, top=25):
    """The busiest call sites (summed over ranks, per step), for a report."""
    total = {}
    for d in diffs:
        for k, v in d["sites"].items():
            t = total.setdefault(k, [0, 0])
            t[0] += v[0]
            t[1] += v[1]
    rows = sorted(total.items(), key=lambda kv: -kv[1][0])[:top]
    n = len(diffs)
    return [f"{v[0] / steps / n:9.3f} /rank/step {v[1] / steps / n:11.0f} B  {k[3]:4s} {k[2]:14s} "
            f"{k[0]}: {k[1][:90]}" for k, v in rows if v[0]]


def format_summary(s):
    pc = ", ".join(f"{k} {v:.3f}" for k, v in sorted(s["project_coll"].items())) or "none"
    return (f"{s['ranks']} ranks: messages/rank/step {s['msgs_avg']:.2f} (max {s['msgs_max']:.2f}), "
            f"bytes/rank/step {s['bytes_avg']:.0f} (max {s['bytes_max']:.0f}), partners "
            f"{s['partners_avg']:.2f} (max {s['partners_max']}), per-step partners "
            f"{s['step_partners_avg']:.2f} (max {s['step_partners_max']}), messages/step to one "
            f"partner max {s['dest_rate_max']:.3f}, collectives/step "
            f"{s['coll_max']:.3f} (project code: {pc}), receives+waits/rank/step "
            f"{s['recv_wait_avg']:.2f}")


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("prefix", help="PREFIX of PREFIX.RANK.json files")
    p.add_argument("--base", help="shorter run to subtract (same scene, fewer steps)")
    p.add_argument("--steps", type=float, default=1.0, help="steps between the two runs")
    p.add_argument("--sites", type=int, default=20, help="busiest call sites to list")
    a = p.parse_args()
    run_ = load(a.prefix)
    diffs = difference(run_, load(a.base)) if a.base else as_diff(run_)
    print(format_summary(summarise(diffs, a.steps)))
    for line in site_lines(diffs, a.steps, a.sites):
        print(line)


if __name__ == "__main__":
    main()

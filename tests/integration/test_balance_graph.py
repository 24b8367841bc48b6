"""fix balance/graph under MPI: ownership follows the partition without losing or duplicating a
particle, and changes who computes, not what (thermo matches the stock decomposition)."""
import os
import tempfile

import harness as h

args = h.parse_args()
STEPS = 200


def run(np_, tag, **variables):
    wd = tempfile.mkdtemp(prefix=f"balance_{tag}_{np_}_")
    h.copy_inputs(["in.balance_bed"], wd)
    text = h.run(args.exe, "in.balance_bed", np_=np_, workdir=wd,
                 variables=dict(steps=STEPS, **variables))
    csv = os.path.join(wd, "balance.csv")
    return h.thermo_blocks(text), (h.read_csv(csv) if os.path.exists(csv) else None), text


def worst_rel(a, b, names):
    worst = 0.0
    for name in names:
        for x, y in zip(h.column(a, name), h.column(b, name)):
            worst = max(worst, h.rel_diff(x, y))
    return worst


# Configurations: the a posteriori model with plain counts, the a priori model with calibrated
# costs while fix insert/rate/region keeps inserting into the stock bricks (ghosts covering the
# whole bricks, or only the named insertion region), one graph vertex per particle (cells 0:
# particles stay on their rank between repartitions) instead of cells, Scotch's
# SCOTCH_graphRepart with the cost model fitted to the measured time, and the layered (brick-wall)
# partitioner of the cells.
CONFIGS = [("aposteriori", dict(model="aposteriori", cost="counts", insert=0)),
           ("apriori+insert", dict(model="apriori", cost="calibrated", insert=1)),
           ("insert+region cover", dict(model="aposteriori", cost="counts", insert=1,
                                        cover="insert_region ins")),
           ("particle vertices", dict(model="aposteriori", cost="counts", insert=0,
                                      cover="cells 0")),
           ("scotch fitted", dict(model="aposteriori", cost="fitted", insert=0,
                                  cover="partitioner scotch")),
           ("layers", dict(model="aposteriori", cost="counts", insert=0,
                           cover="partitioner layers"))]
for np_ in (2, 3):
    for name, cfg in CONFIGS:
        stock, _, _ = run(np_, f"stock_{cfg['model']}", balance=0, insert=cfg["insert"])
        graph, csv, text = run(np_, f"graph_{cfg['model']}", balance=1, every=20, thresh=1.0, **cfg)
        # No particle lost or duplicated at any output step: ids are 1..n (insertion appends), so
        # the count, the sum of ids and the sum of squared ids pin the set down.
        ok = True
        for n, s1, s2 in zip(h.column(graph, "Atoms"), h.column(graph, "sumid"), h.column(graph, "sumid2")):
            ok &= s1 == n * (n + 1) / 2 and abs(s2 - n * (n + 1) * (2 * n + 1) / 6) < 0.5
        n0, n1 = h.column(graph, "Atoms")[0], h.column(graph, "Atoms")[-1]
        h.check(ok, f"np={np_} {name}: {n0:.0f} -> {n1:.0f} particles, none lost or duplicated "
                    f"(count, sum id, sum id^2 at every output step)")
        h.check(h.column(stock, "Atoms") == h.column(graph, "Atoms"),
                f"np={np_} {name}: same particle count as the stock decomposition at every step")
        reps = h.column(graph, "nrep")[-1]
        migrated = sum(csv["migrated"])
        h.check(reps >= 1 and migrated > 0,
                f"np={np_} {name}: {reps:.0f} repartitions moved {migrated:.0f} particles")
        h.check(csv["imbalance"][0] > 1.5,
                f"np={np_} {name}: z-slabs start imbalanced (B = {csv['imbalance'][0]:.2f})")
        h.check(csv["step"][0] == 1 and csv["repartitioned"][0] == 1,
                f"np={np_} {name}: the run starts balanced (first check at step 1, "
                f"repartitioned: {csv['repartitioned'][0]:.0f})")
        h.check(csv["predicted_imbalance"][0] < 1.1,
                f"np={np_} {name}: the partitioner balances the work model "
                f"(predicted B = {csv['predicted_imbalance'][0]:.3f})")
        # The a posteriori graph is weighted by the very cost that is measured, so the next check
        # must see it balanced; the a priori graph balances neighbour counts only (no such claim).
        # Only for costs fixed during the run: `fitted` (like `timed`) reprices every check from
        # thread CPU time, which on a shared CI machine is noise at this scene's size (a timed
        # assertion, which a test must not make; bench/ measures that).
        later = [b for b, r in zip(csv["imbalance"][1:], csv["repartitioned"][:-1]) if r]
        if cfg["model"] == "aposteriori" and cfg["cost"] in ("counts", "calibrated"):
            h.check(later and later[0] < 1.15,
                    f"np={np_} {name}: measured B after the repartition {later[0]:.3f} < 1.15")
        w = worst_rel(stock, graph, ["KinEng", "rke", "sumid"])
        h.check(w < 1e-8, f"np={np_} {name}: thermo matches the stock decomposition over "
                          f"{STEPS} steps (worst rel. diff {w:.1e})")

# Restart under graph ownership: write at step 100, continue to 200. The continuation must match
# the stock code's own restart continuation (the stock restart is not bit-exact itself: primitive
# wall contact history is not in the restart file), and stay within that spread of the straight run.
for np_ in (3,):
    cont = {}
    for label, exe, bal in (("stock", args.exe, 0), ("graph", args.exe, 1)):
        wd = tempfile.mkdtemp(prefix=f"balance_restart_{label}_{np_}_")
        h.copy_inputs(["in.balance_bed", "in.balance_bed_continue"], wd)
        straight = h.thermo_blocks(h.run(exe, "in.balance_bed", np_=np_, workdir=wd,
                                         variables=dict(steps=STEPS, balance=bal, restart_every=100)))
        cont[label] = h.thermo_blocks(h.run(exe, "in.balance_bed_continue", np_=np_, workdir=wd,
                                            variables=dict(balance=bal, steps=100)))
        cont[label + "_straight"] = straight
    header, rows = cont["graph"][-1]
    h.check(all(r[header.index("Atoms")] == rows[0][header.index("Atoms")] for r in rows),
            f"np={np_}: no particle lost across the restart under graph ownership")
    h.check(h.column(cont["graph"], "nrep")[-1] >= 1,
            f"np={np_}: graph ownership resumed after the restart "
            f"({h.column(cont['graph'], 'nrep')[-1]:.0f} repartitions counted)")
    w = worst_rel(cont["stock"], cont["graph"], ["KinEng", "rke"])
    h.check(w < 1e-8, f"np={np_}: restarted graph run matches the restarted stock run (worst {w:.1e})")
    ke_g = h.column(cont["graph"], "KinEng")[-1]
    ke_s = h.column(cont["graph_straight"], "KinEng")[-1]
    h.check(h.rel_diff(ke_g, ke_s) < 1e-6,
            f"np={np_}: continued KE within 1e-6 of the uninterrupted run ({h.rel_diff(ke_g, ke_s):.1e})")

# With a plugin body: a rigid fem/body bucket dragged through a bed of disks (2D). Particle-facet
# contacts are computed by whichever rank owns the particle; the body's contact count and force
# must not depend on who that is.
for np_ in (2, 3):
    runs = {}
    for label, bal in (("stock", 0), ("graph", 1)):
        wd = tempfile.mkdtemp(prefix=f"balance_dragline_{label}_{np_}_")
        h.copy_inputs(["in.balance_dragline"], wd)
        h.make_bucket_mesh(os.path.join(wd, "bucket.msh"))
        runs[label] = h.thermo_blocks(h.run(args.exe, "in.balance_dragline", np_=np_, workdir=wd,
                                            variables=dict(balance=bal, steps=600, every=50, thresh=1.0)))
    g = runs["graph"]
    h.check(h.column(g, "nrep")[-1] >= 1 and max(h.column(g, "ncont")) >= 1,
            f"np={np_} dragline: {h.column(g, 'nrep')[-1]:.0f} repartitions, up to "
            f"{max(h.column(g, 'ncont')):.0f} bucket contacts")
    h.check(h.column(g, "Atoms") == h.column(runs["stock"], "Atoms") and
            len(set(h.column(g, "sumid"))) == 1, f"np={np_} dragline: no disk lost or duplicated")
    w = worst_rel(runs["stock"], g, ["KinEng", "rke", "ncont", "fx"])
    h.check(w < 1e-8, f"np={np_} dragline: thermo and bucket contact force match the stock "
                      f"decomposition (worst rel. diff {w:.1e})")

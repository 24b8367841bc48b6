"""fix balance/graph with pair_style fracdem/gran: the contacts the pair counts while computing
them equal the balance fix's own recount over the neighbour list (a frozen packed box, so that
the pair's counts of the step before a check and the recount at the check see the same
positions): the modelled work of every check is the same with 'counts pair' and 'counts
recount'. With bridges, the pair's counts add the bridge term, which the recount cannot see."""
import tempfile

import harness as h

args = h.parse_args()


def work(counts, bridge, integrate=0, steps=30, jitter=0):
    wd = tempfile.mkdtemp(prefix=f"pair_counts_{counts}_{bridge}_")
    h.copy_inputs(["in.wet_dry_box"], wd)
    # 1.95 mm spacing: every lattice neighbour of the left block overlaps (a contact).
    h.run(args.exe, "in.wet_dry_box", np_=2, workdir=wd,
          variables=dict(counts=counts, bridge=bridge, integrate=integrate, wet_spacing=0.00195,
                         cost="counts", thresh=1e30, every=10, steps=steps, jitter=jitter))
    c = h.read_csv(f"{wd}/balance.csv")
    return list(zip(c["step"], c["work_max"], c["work_avg"]))


dry_pair, dry_recount = work("pair", 0), work("recount", 0)
h.check(len(dry_pair) == 4, f"{len(dry_pair)} checks (the start and every 10 steps)")
h.check(dry_pair == dry_recount,
        f"no bridges: modelled work of every check, pair counts {dry_pair[-1][1:]} = recount "
        f"{dry_recount[-1][1:]} (max, mean over 2 ranks)")
# Moving (the overlapping block, jittered by 20 um, flies apart): the pair counted the step before each check, the
# recount sees the check's positions, so the two differ a little, which shows that the pair's
# counts are the ones used.
moving_pair, moving_recount = work("pair", 0, 1, 200, 2e-5), work("recount", 0, 1, 200, 2e-5)
diff = max(abs(a[1] - b[1]) / b[1] for a, b in zip(moving_pair[1:], moving_recount[1:]))
h.check(0 < diff < 0.05, f"no bridges, moving: pair counts and recount differ by up to "
        f"{100 * diff:.2f} % of the wet rank's work (one step apart)")
wet_pair, wet_recount = work("pair", 1), work("recount", 1)
# Bridges widen the pair's neighbour cut-off (more listed pairs in both); on top of that every
# overlapping pair is bridged (wet yes), each bridge costing 1 in 'cost counts': the pair's counts
# raise the wet rank's work by its bridges, the dry rank's not at all.
extra_max = wet_pair[-1][1] - wet_recount[-1][1]
extra_avg = wet_pair[-1][2] - wet_recount[-1][2]
h.check(extra_max > 0 and abs(extra_max - 2 * extra_avg) < 1e-6 * extra_max,
        f"bridges on: pair counts add {extra_max:.0f} bridges to the wet rank's work, "
        f"{2 * extra_avg - extra_max:.3g} to the dry rank's")
print("OK")

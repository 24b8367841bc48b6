"""compute fracdem/cost: per-particle a posteriori cost under LAMMPS, and as fix balance's weight.

1. Per-atom cost against brute force: a static packing of spheres of varied radii (box periodic
   in x and y, so pairs across the periodic boundaries and with their own images count too),
   `pair granular`, no time integration. Each particle's recorded cost must equal
   base + (check * potential pairs + pair * overlapping pairs) / 2, both counted in Python from the
   dumped positions and radii (potential pair: centre distance < r_i + r_j + skin, the size
   neighbour list built at set-up; overlapping: distance < r_i + r_j), at np 1 and 2, newton on
   and off; the totals agree between all four runs.
2. Facet contacts: spheres above and in a clamped fix fem/body block with `contact`; with the
   weights `facet 1` (others 0) each particle's cost is 1 where it overlaps the top face, else 0.
3. As a weight: on a scene with a dense (heavily overlapping) region and a sparse one, `fix balance
   rcb weight var` with the compute reaches a lower imbalance of the recorded cost (max/avg per
   rank, the compute's vector) than `weight neigh` (one weight per rank: its mean neighbour count).
4. Keyword errors name the keyword.
"""
import os
import random
import tempfile

import lammps_harness as lh

h = lh.harness
args = lh.parse_args()
lmp = lh.Lammps(args)

SKIN = 0.002
BASE, CHECK, PAIR = 0.7, 0.3, 5.0
BOX = (0.05, 0.05, 0.05)


def write_data(path, atoms, box):
    with open(path, "w") as f:
        f.write(f"fracdem/cost test packing\n\n{len(atoms)} atoms\n1 atom types\n\n")
        f.write(f"0 {box[0]!r} xlo xhi\n0 {box[1]!r} ylo yhi\n0 {box[2]!r} zlo zhi\n\nAtoms # sphere\n\n")
        for k, (x, y, z, r) in enumerate(atoms, 1):
            f.write(f"{k} 1 {2 * r!r} 2500 {x!r} {y!r} {z!r}\n")


def packing(n, seed):
    rng = random.Random(seed)
    atoms = []
    for _ in range(n):
        r = rng.uniform(0.003, 0.005)
        atoms.append((rng.uniform(0, BOX[0]), rng.uniform(0, BOX[1]),
                      rng.uniform(r, BOX[2] - r), r))
    return atoms


PREAMBLE = """plugin load ${plugin}
atom_style sphere
atom_modify map array
boundary p p f
newton ${newton}
comm_modify vel yes
units si
"""

PACK = PREAMBLE + f"""read_data pack.data
pair_style granular
pair_coeff * * hertz/material 5e6 0.3 0.45 tangential mindlin NULL 0.8424 0.5 &
    damping coeff_restitution
neighbor {SKIN} bin
timestep 1e-7
compute c all fracdem/cost cost base {BASE} check {CHECK} pair {PAIR} facet_check 0 facet 0
compute tot all reduce sum c_c
dump d all custom 5 dump.txt id x y z radius c_c
dump_modify d format float %.17g sort id
thermo_style custom step c_tot c_c[2] c_c[3] c_c[4]
thermo_modify format float %.17g
thermo 5
run 5
"""


def read_dump(path):
    lines = open(path).read().splitlines()
    start = max(i for i, l in enumerate(lines) if l.startswith("ITEM: ATOMS"))
    return [[float(v) for v in l.split()] for l in lines[start + 1:]]


def brute_force(rows):
    """Expected cost per atom: base + (check * potential + pair * overlapping pairs) / 2."""
    n = len(rows)
    expect = []
    for i in range(n):
        xi, ri = rows[i][1:4], rows[i][4]
        potential = contacts = 0
        for j in range(n):
            if j == i:
                continue
            d = [xi[k] - rows[j][1 + k] for k in range(3)]
            for k in (0, 1):  # periodic in x and y (minimum image: the box is > 2 cut-offs wide)
                d[k] -= BOX[k] * round(d[k] / BOX[k])
            dist2 = sum(v * v for v in d)
            rs = ri + rows[j][4]
            potential += dist2 < (rs + SKIN) ** 2
            contacts += dist2 < rs * rs
        expect.append((BASE + 0.5 * (CHECK * potential + PAIR * contacts), potential, contacts))
    return expect


def per_atom_against_brute_force():
    atoms = packing(250, 4711)
    totals = []
    for newton in ("on", "off"):
        for np_ in (1, 2):
            wd = tempfile.mkdtemp(prefix="lmp_cost_pack_")
            write_data(os.path.join(wd, "pack.data"), atoms, BOX)
            with open(os.path.join(wd, "in.pack"), "w") as f:
                f.write(PACK)
            out = lmp.run("in.pack", np_=np_, workdir=wd, variables=dict(newton=newton))
            rows = read_dump(os.path.join(wd, "dump.txt"))
            h.check(len(rows) == len(atoms), f"np {np_} newton {newton}: {len(rows)} atoms dumped")
            expect = brute_force(rows)
            worst = max(abs(r[5] - e[0]) for r, e in zip(rows, expect))
            ncontact = sum(e[2] for e in expect) // 2
            h.check(ncontact > 50, f"the packing has overlapping pairs ({ncontact})")
            h.check(worst <= 1e-12,
                    f"np {np_} newton {newton}: per-atom cost = base + (check * potential + "
                    f"pair * overlapping pairs) / 2 for all {len(rows)} atoms (largest difference "
                    f"{worst:.1e}; {ncontact} overlapping pairs)")
            header, thermo = h.thermo_blocks(out)[-1]
            total = thermo[-1][header.index("c_tot")]
            run_avg = thermo[-1][header.index("c_c[4]")] * np_
            h.check(abs(run_avg - total) <= 1e-9 * total,
                    f"np {np_} newton {newton}: the per-rank work (vector 4 x ranks, {run_avg:.10g})"
                    f" equals the per-atom total ({total:.10g})")
            totals.append(total)
    h.check(max(totals) - min(totals) <= 1e-9 * max(totals),
            f"the same total cost at np 1 and 2, newton on and off: {totals}")


FACET = PREAMBLE + """region box block -0.03 0.03 -0.03 0.03 -0.021 0.02 units box
create_box 2 box
neighbor 0.001 bin
fix body all fem/body file block.msh type 2 density 1000 youngs 1e7 poisson 0.3 fixed all &
    compliance combined contact granular hertz/material 1e7 0.5 0.3 &
    damping coeff_restitution tangential mindlin NULL 0.907485 0.3
read_data facet.data add append
pair_style granular
pair_coeff * * hertz/material 1e7 0.5 0.3 tangential mindlin NULL 0.907485 0.3 &
    damping coeff_restitution
timestep 1e-7
compute c all fracdem/cost cost base 0 check 0 pair 0 facet_check ${fc} facet 1
compute tot all reduce sum c_c
dump d all custom 3 dump.txt id x y z radius c_c
dump_modify d format float %.17g sort id
thermo_style custom step c_tot f_body[7]
thermo 3
run 3
"""


def facet_contacts():
    rng = random.Random(99)
    atoms = []
    for ix in range(5):
        for iy in range(5):
            r = rng.uniform(0.002, 0.003)
            z = rng.uniform(-0.5 * r, 1.5 * r)  # about half of them overlap the top face z = 0
            atoms.append((-0.02 + 0.01 * ix + 0.0013, -0.02 + 0.01 * iy + 0.0017, z, r))
    for np_ in (1, 2):
        wd = tempfile.mkdtemp(prefix="lmp_cost_facet_")
        h.make_box_mesh(os.path.join(wd, "block.msh"), (5, 5, 2), (0.05, 0.05, 0.02),
                        (-0.025, -0.025, -0.02))
        with open(os.path.join(wd, "facet.data"), "w") as f:
            f.write(f"facet test\n\n{len(atoms)} atoms\n1 atom types\n\n"
                    "-0.03 0.03 xlo xhi\n-0.03 0.03 ylo yhi\n-0.021 0.02 zlo zhi\n\nAtoms # sphere\n\n")
            for k, (x, y, z, r) in enumerate(atoms, 1):
                f.write(f"{k} 1 {2 * r!r} 7800 {x!r} {y!r} {z!r}\n")
        with open(os.path.join(wd, "in.facet"), "w") as f:
            f.write(FACET)
        out = lmp.run("in.facet", np_=np_, workdir=wd, variables=dict(newton="on", fc=0))
        rows = read_dump(os.path.join(wd, "dump.txt"))
        touching = [1.0 if r[3] - r[4] < 0 else 0.0 for r in rows]
        bad = [int(r[0]) for r, t in zip(rows, touching) if abs(r[5] - t) > 1e-12]
        h.check(0 < sum(touching) < len(rows) and not bad,
                f"np {np_}: facet contacts per particle = overlap with the block's top face "
                f"({int(sum(touching))} of {len(rows)} touch; mismatches: {bad})")
        header, thermo = h.thermo_blocks(out)[-1]
        h.check(thermo[-1][header.index("f_body[7]")] == sum(touching),
                f"np {np_}: the compute's facet contacts sum to fix fem/body's contact count")
        out = lmp.run("in.facet", np_=np_, workdir=wd, variables=dict(newton="on", fc=1))
        rows = read_dump(os.path.join(wd, "dump.txt"))
        checks = [r[5] - t for r, t in zip(rows, touching)]
        h.check(all(c >= t for c, t in zip(checks, touching)) and sum(checks) > 0,
                f"np {np_}: facet checks recorded (sum {sum(checks):g}, at least one per contact)")


# Dense region: x < 0.045, spheres of diameter 0.008 on a lattice of spacing 0.0075 (each overlaps
# its 6 lattice neighbours); loose region: x > 0.045, spacing 0.0095 (gaps of 0.0015, inside the
# skin: as many neighbours, no contacts). weight neigh sees the same neighbour count per atom on
# both sides; the recorded cost is 4x higher in the dense region.
WEIGHT = """plugin load ${plugin}
atom_style sphere
atom_modify map array
boundary p p f
newton off
comm_modify vel yes
units si
comm_style tiled
region box block 0 0.12 0 0.06 0 0.06 units box
create_box 1 box
region dense block 0 0.045 0 0.06 0.001 0.059 units box
region loose block 0.0475 0.12 0 0.06 0.001 0.059 units box
lattice sc 0.0075
create_atoms 1 region dense
lattice sc 0.0095 origin 0.5 0.5 0.5
create_atoms 1 region loose
set group all diameter 0.008 density 2500
pair_style granular
pair_coeff * * hertz/material 5e6 0.3 0.45 tangential mindlin NULL 0.8424 0.5 &
    damping coeff_restitution
neighbor 0.002 bin
timestep 1e-7
compute c all fracdem/cost cost base 1 check 1 pair 4 facet_check 1 facet 1
variable w atom c_c
thermo_style custom step atoms c_c[1] c_c[2]
thermo_modify format float %.17g
thermo 10
run 10
if "${weight} == var" then "fix b all balance 10 1.0 rcb weight var w" &
else "fix b all balance 10 1.0 rcb weight neigh 1.0"
run 30
"""


def weight_var_beats_neigh():
    imb = {}
    for weight in ("var", "neigh"):
        wd = tempfile.mkdtemp(prefix="lmp_cost_weight_")
        with open(os.path.join(wd, "in.weight"), "w") as f:
            f.write(WEIGHT)
        out = lmp.run("in.weight", np_=2, workdir=wd, variables=dict(weight=weight))
        header, thermo = h.thermo_blocks(out)[-1]
        imb[weight] = thermo[-1][header.index("c_c[2]")]
        first = h.thermo_blocks(out)[0]
        imb[weight + " before"] = first[1][-1][first[0].index("c_c[2]")]
    h.check(imb["var before"] > 1.3,
            f"the stock bricks are imbalanced in recorded cost ({imb['var before']:.3f})")
    h.check(imb["var"] < 1.10 and imb["var"] < imb["neigh"] - 0.1,
            f"rcb weight var (fracdem/cost) reaches recorded-cost imbalance {imb['var']:.3f}, "
            f"below weight neigh's {imb['neigh']:.3f}")


def keyword_errors():
    for words, message in (("bogus 1", "unknown keyword 'bogus'"),
                           ("cost 1", "keyword 'cost' expects NAME C pairs"),
                           ("cost pair -1", "keyword 'pair' expects a non-negative number"),
                           ("every 2.5", "keyword 'every' expects a whole number")):
        wd = tempfile.mkdtemp(prefix="lmp_cost_err_")
        with open(os.path.join(wd, "in.err"), "w") as f:
            f.write("plugin load ${plugin}\natom_style sphere\nregion b block 0 1 0 1 0 1\n"
                    f"create_box 1 b\ncompute c all fracdem/cost {words}\n")
        out = lmp.run("in.err", workdir=wd, expect_fail=True)
        h.check(message in out, f"'compute c all fracdem/cost {words}' stops with: {message}")


keyword_errors()
per_atom_against_brute_force()
facet_contacts()
weight_var_beats_neigh()
print("test_cost: all checks passed")

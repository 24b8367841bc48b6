"""Cracks through quad4 elements (fracture nodal min_size, issue #9): a free Rankine quad4 bar on
a herringbone grid (cross edges at +-31 degrees to the expected vertical crack, none along it;
a tri3 at the left end of each row), notched at the middle of its bottom face and pulled (fixed
left end, right end at 0.1 m/s), cracks along a straighter path with min_size 0.2 than with
boundary-only cracks; cuts happen (logged); no piece falls below min_size of its mesh element
(areas of the frame's cells grouped by the field mesh_element); the energy balance closes;
np 1 = np 2, byte for byte. The same bar free, its halves thrown apart (and all of it moving up
at 0.5 m/s), cuts quads and keeps its momentum, and its mass (p_y = mass x 0.5 m/s), and comes
apart in two fragments whose masses add up to the bar's.

Parameters (in.fracture_quad_cut): the concrete-like ones of test_fracture_cut (f_t 3 MPa, G_f 100
N/m, CEB-FIP Model Code 1990 ranges), the load of test_fracture_cut (0.1 m/s, ramp 1e-4 s) over
1e-3 s. The crack of a bar in uniaxial tension runs normal to its axis (Rankine: the crack normal is the major principal direction), so the straight reference
is the vertical line through the crack's own median x (as in test_fracture_cut).
"""
import glob
import os
import re
import sys
import tempfile

import numpy as np

import harness as h

args = h.parse_args()
sys.path.insert(0, os.path.join(h.ROOT, "python"))
from fracdem import fem, meshgen  # noqa: E402

MIN_SIZE = 0.2
L, H, NX, NY = 0.2, 0.05, 20, 6
RHO, THICK = 2400, 0.05
DT, STEPS, FREE_STEPS = 2e-7, 5000, 2500
NOTCH_ROWS = (0,)  # a notch in the bottom row only
VY = 0.5  # the free bar's common y velocity: p_y = mass VY


def herringbone_bar():
    """L x H bar, NY rows of height r = H / NY: even rows of nodes at x = i h, odd rows at
    (i + 1/2) h plus both ends. Between two rows NX quads (parallelograms leaning 31 degrees,
    atan(h / 2 / r), right and left in turn; a trapezoid at the right end) and a tri3 at the left
    end: no element edge is vertical. Notches: the quad of the bottom and of the top row nearest
    the middle removed. Node groups left / right: the edges of the elements wholly at
    x <= L/2 - h / x >= L/2 + h (the band between starts at rest)."""
    h_ = L / NX
    rows = []
    for j in range(NY + 1):
        xs = [i * h_ for i in range(NX + 1)] if j % 2 == 0 else \
            [0.0] + [(i + 0.5) * h_ for i in range(NX)] + [L]
        rows.append([(x, j * H / NY) for x in xs])
    nodes, ids = [], []
    for r in rows:
        ids.append(list(range(len(nodes), len(nodes) + len(r))))
        nodes += [(x, y, 0.0) for x, y in r]
    X = np.array(nodes)
    elems = []
    for j in range(NY):
        a, b = ids[j], ids[j + 1]
        if j % 2 == 0:  # a: NX + 1 nodes, b: NX + 2
            elems.append((a[0], b[1], b[0]))
            quads = [(a[i], a[i + 1], b[i + 2], b[i + 1]) for i in range(NX)]
        else:  # a: NX + 2, b: NX + 1
            elems.append((a[0], a[1], b[0]))
            quads = [(a[i + 1], a[i + 2], b[i + 1], b[i]) for i in range(NX)]
        outer = j in NOTCH_ROWS
        elems += [q for q in quads if not (outer and abs(np.mean(X[list(q), 0]) - L / 2) < 0.5 * h_)]
    groups = {"left": [], "right": [], "xmin": [], "xmax": []}
    for e in elems:
        for name, x0 in (("xmin", 0.0), ("xmax", L)):
            on = [v for v in e if abs(X[v, 0] - x0) < 1e-12]
            if len(on) == 2:
                groups[name].append(tuple(on))
        k = len(e)
        for name, side in (("left", X[list(e), 0] <= L / 2 + 1e-9),
                           ("right", X[list(e), 0] >= L / 2 - 1e-9)):
            if side.all():
                groups[name] += [(e[m], e[(m + 1) % k]) for m in range(k)]
    return X, elems, {k: np.array(v) for k, v in groups.items()}, L * H - len(NOTCH_ROWS) * h_ * H / NY


def write_mesh(path):
    """Gmsh 2.2 with the tri3 and quad4 elements together (meshgen.write_gmsh22 takes one
    element type per call)."""
    X, elems, groups, _ = herringbone_bar()
    names = ["left", "right", "xmin", "xmax"]
    lines = ["$MeshFormat", "2.2 0 8", "$EndMeshFormat", "$PhysicalNames", str(len(names) + 1),
             '2 1 "body"'] + [f'1 {k + 2} "{n}"' for k, n in enumerate(names)]
    lines += ["$EndPhysicalNames", "$Nodes", str(len(X))]
    lines += [f"{i + 1} {float(x)!r} {float(y)!r} 0" for i, (x, y, _) in enumerate(X)]
    rows = []
    for k, name in enumerate(names):
        rows += [(1, k + 2, e) for e in groups[name]]
    rows += [(2 if len(e) == 3 else 3, 1, e) for e in elems]
    lines += ["$EndNodes", "$Elements", str(len(rows))]
    lines += [f"{n + 1} {t} 2 {tag} {tag} " + " ".join(str(v + 1) for v in e)
              for n, (t, tag, e) in enumerate(rows)]
    lines.append("$EndElements")
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


def log_of(wd):
    with open(os.path.join(wd, "log.liggghts")) as f:
        return f.read()


STATIC = "fixed xmin x prescribed_velocity xmax 0.1 0 0 ramp 1e-4"
FREE = f"velocity left -1 {VY} 0 velocity right 1 {VY} 0"


def run(frac, load, np_, name, steps=STEPS):
    wd = tempfile.mkdtemp(prefix=f"fracture_quad_cut_{name}_{np_}_")
    write_mesh(os.path.join(wd, "bar.msh"))
    h.copy_inputs(["in.fracture_quad_cut"], wd)
    out = h.run(args.exe, "in.fracture_quad_cut", np_=np_, workdir=wd,
                variables={"frac": frac, "load": load, "dt": DT, "steps": steps})
    with open(os.path.join(wd, "energy.csv")) as f:
        text = f.read()
    return wd, out, log_of(wd), text


def polygon_area(p):
    x, y = p[:, 0], p[:, 1]
    return 0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def frame(wd):
    d = fem.read_vtu(sorted(glob.glob(os.path.join(wd, "bar_*.vtu")))[-1])
    return d, d["points"] - d["point_data"]["displacement"]


def crack_deviation(wd):
    """Mean |x - x_crack| of the nodes on the crack (field 'split', reference positions), with
    x_crack their median."""
    d, ref = frame(wd)
    on = d["point_data"]["split"] > 0.5
    x = ref[on, 0]
    return float(np.mean(np.abs(x - np.median(x)))), int(on.sum())


_, _, _, bar_area = herringbone_bar()
bar_mass = RHO * THICK * bar_area
CUT = f"every 5 min_size {MIN_SIZE}"
wd_b, out_b, log_b, csv_b = run("every 5", STATIC, 1, "boundary")
wd_c, out_c, log_c, csv_c = run(CUT, STATIC, 1, "cut")
wd_c2, out_c2, log_c2, csv_c2 = run(CUT, STATIC, 2, "cut")
wd_f, out_f, log_f, csv_f = run(CUT, FREE, 1, "free", steps=FREE_STEPS)

h.check("crack through element" not in log_b, "without min_size no element is cut")
h.check("min_size ignored" not in log_c, "no set-up note that quads are not cut")
cuts = re.findall(r"crack through element \d+ at node \d+ \(t = ([0-9.]+)\)", log_c)
h.check(len(cuts) > 0, f"with min_size {MIN_SIZE}: {len(cuts)} cracks through quad4 elements")

dev_b, n_b = crack_deviation(wd_b)
dev_c, n_c = crack_deviation(wd_c)
h.check(n_b > 0 and n_c > 0, f"both bars cracked ({n_b} and {n_c} nodes on the crack)")
h.check(dev_c < dev_b,
        f"crack path straighter with min_size: mean |x - x_crack| {dev_c * 1e3:.3f} mm against "
        f"{dev_b * 1e3:.3f} mm on element boundaries (element size {L / NX * 1e3:.0f} mm)")


def pieces_check(wd, name):
    """No piece below min_size of its mesh element (pieces of pieces included); the cut quads'
    pieces are tri3 and quad4 cells."""
    d, ref = frame(wd)
    root = d["cell_data"]["mesh_element"].astype(int)
    area = np.array([polygon_area(ref[list(c)]) for c in d["cells"]])
    worst, cut_roots = 1.0, 0
    for r in np.unique(root):
        pieces = area[root == r]
        if len(pieces) > 1:
            cut_roots += 1
            worst = min(worst, pieces.min() / pieces.sum())
    h.check(cut_roots > 0 and worst >= MIN_SIZE - 1e-9,
            f"{name}: {cut_roots} mesh elements cut, no piece below min_size (smallest {worst:.3f})")
    h.check(abs(area.sum() / bar_area - 1) < 1e-12, f"{name}: cells cover the bar ({area.sum():.6e} m^2)")


pieces_check(wd_c, "tension")
pieces_check(wd_f, "free")


for name, wd in (("boundary", wd_b), ("min_size", wd_c)):
    e = h.read_csv(os.path.join(wd, "energy.csv"))
    lhs = np.array(e["kinetic"]) + np.array(e["strain"]) + np.array(e["fracture_energy"])
    rhs = np.array(e["boundary_work"]) + np.array(e["external_work"]) + np.array(e["contact_work"])
    w = float(np.max(np.abs(lhs - rhs)) / np.max(np.abs(rhs)))
    h.check(w < 0.02, f"{name}: energy balance closes within 2 % of the input work (worst {w:.2e})")
h.check(csv_c == csv_c2, "min_size: np 2 writes the same energy file as np 1, byte for byte")

# The free bar: no constraints, so its momentum is kept through the quad4 cuts; every node moves
# at VY in y, so p_y = mass VY at every step checks the mass too.
cuts_f = re.findall(r"crack through element \d+ at node \d+", log_f)
h.check(len(cuts_f) > 0, f"free bar: {len(cuts_f)} cracks through quad4 elements")
hdr, rows = h.thermo_blocks(out_f)[-1]
p0 = [rows[0][hdr.index(c)] for c in ("body[13]", "body[14]")]
drift = max(abs(r[hdr.index(c)] - p0[k]) for r in rows for k, c in enumerate(("body[13]", "body[14]")))
h.check(drift < 1e-12 * bar_mass,
        f"free bar: momentum kept (initial ({p0[0]:.3e}, {p0[1]:.6f}) kg m/s, drift {drift:.1e})")
h.check(abs(p0[1] / (VY * bar_mass) - 1) < 1e-12,
        f"free bar: p_y = mass x {VY} m/s with the bar's mass {bar_mass:.5f} kg at every step")
e = h.read_csv(os.path.join(wd_f, "energy.csv"))
# The free bar comes apart: the node at the crack's mouth that held the two face-connected
# halves together (never split itself) is separated once the elements beside the opened edge
# no longer soften (nodal_fracture.cpp, separate_pinched_nodes), and no chip of failed material
# is cut loose: two fragments at the end, whose masses (log, 4 digits) add up to the bar's.
frag_f = re.findall(r"step \d+: (\d+) fragments, masses ([0-9.e+\- ]+)", log_f)
h.check(int(e["fragments"][-1]) == 2 and len(frag_f) > 0 and int(frag_f[-1][0]) == 2,
        f"free bar: ends in 2 fragments (energy file {int(e['fragments'][-1])}, log "
        f"{frag_f[-1][0] if frag_f else 0})")
m_f = sum(float(m) for m in frag_f[-1][1].split()) if frag_f else 0.0
h.check(abs(m_f / bar_mass - 1) < 1e-3,
        f"free bar: fragment masses sum to the bar's {bar_mass:.5f} kg ({m_f:.5f})")
lhs = np.array(e["kinetic"]) + np.array(e["strain"]) + np.array(e["fracture_energy"])
w = float(np.max(np.abs(lhs - lhs[0] - np.array(e["contact_work"]))) / lhs[0])
h.check(w < 0.02, f"free bar: kinetic + strain + dissipated = initial + contact work within 2 % "
                  f"(worst {w:.2e})")
print(f"OK: {len(cuts)} quad4 cuts in tension, crack deviation {dev_c * 1e3:.3f} mm vs "
      f"{dev_b * 1e3:.3f} mm; {len(cuts_f)} cuts in the free bar")

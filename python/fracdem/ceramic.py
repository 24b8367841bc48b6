"""The layered ceramic target of the paper's Example 3 (tungsten rod into RHA / alumina / RHA):
geometry, published material constants, axisymmetric meshes, the 3D rod-into-plate companion and
the Lanz-Odermatt penetration bound used as a plausibility check.

Shared by examples/ceramic_target (make_meshes.py, the inputs' header) and
tests/integration/test_rod_impact.py, so that all run the same problem. Units SI; x = r, y = the
axis (the rod flies in -y; the cover plate's front face is y = 0).

Sources (docs/ceramic_target.md has the discussion):
* Target (Owen, Feng, Yu, Peric, VECPAR 2000, Example 3): 6 mm RHA cover plate, three unconfined
  ceramic tiles of about 25 mm, radius 74 mm, RHA backing block; each component its own body;
  1325 and 1800 m/s. The backing's size and the rod's are not given there: ROD_* and BACKING_*
  are our choices (L/D 15, a typical long-rod ratio of the Hohler-Stilp data).
* Tungsten heavy alloy (90W-7Ni-3Fe): Johnson-Cook constants, density, specific heat and melting
  temperature from Johnson & Cook (1983), "A constitutive model and data for metals subjected to
  large strains, high strain rates and high temperatures", 7th Int. Symp. Ballistics, Table 1;
  E 345 GPa, nu 0.29 (typical handbook values for 90W alloys).
* RHA: the Johnson-Cook 4340 steel (Rc 30) of the same table stands in for it (a quenched and
  tempered Ni-Cr-Mo armour steel of the same class and hardness, about BHN 290); E 200 GPa,
  nu 0.29, Mie-Grueneisen C0 4569 m/s, S 1.49, Gamma0 2.17 (steel, LASL Shock Hugoniot Data /
  Steinberg 1996 "Equation of state and strength properties of selected materials").
* Alumina AD995 (CoorsTek data sheet): rho 3890 kg/m^3, E 370 GPa, nu 0.22, tensile strength
  262 MPa, K_IC 4 MPa m^0.5; G_F = K_IC^2 (1 - nu^2) / E = 41 J/m^2 (Irwin, plane strain).
"""
import math
import os

import numpy as np

from . import meshgen

# ---- geometry (m) ----------------------------------------------------------------------------
COVER_T, TILE_T, N_TILES, TARGET_R = 6e-3, 25e-3, 3, 74e-3
BACKING_T = 100e-3
RHA_BLOCK_T = 200e-3  # the steel-only reference target (in.rod_rha), deeper than Lanz-Odermatt's P
ROD_D, ROD_L = 10e-3, 150e-3
GAP = 0.2e-3  # rod nose above the cover at t = 0
VELOCITIES = (1325.0, 1800.0)

# ---- materials ---------------------------------------------------------------------------------
# Tungsten heavy alloy, Johnson & Cook (1983) Table 1.
WHA = dict(rho=17000.0, E=345e9, nu=0.29, A=1506e6, B=177e6, n=0.12, C=0.016, m=1.0,
           tmelt=1723.0, cp=134.0)
# 4340 steel (Rc 30) of Johnson & Cook (1983) Table 1 for RHA; steel Hugoniot for the EOS.
RHA = dict(rho=7830.0, E=200e9, nu=0.29, A=792e6, B=510e6, n=0.26, C=0.014, m=1.03,
           tmelt=1793.0, cp=477.0, C0=4569.0, S=1.49, G0=2.17, BHN=290.0)
# Alumina AD995, CoorsTek data sheet; G_F from K_IC.
AD995 = dict(rho=3890.0, E=370e9, nu=0.22, FT=262e6, KIC=4e6)
AD995["GF"] = AD995["KIC"] ** 2 * (1 - AD995["nu"] ** 2) / AD995["E"]


def snapback_size(mat):
    """Largest crack-band width the Rankine softening allows without snap-back: 2 E G_F / f_t^2."""
    return 2 * mat["E"] * mat["GF"] / mat["FT"] ** 2


def band_strength(mat, diameter, margin=0.95):
    """The tensile strength a crack band of width `diameter` can carry without snap-back
    (Bazant & Oh 1983: elements wider than 2 E G_F / f_t^2 take a reduced strength so that they
    still dissipate G_F per unit crack area): min(f_t, margin * sqrt(2 E G_F / diameter))."""
    return min(mat["FT"], margin * math.sqrt(2 * mat["E"] * mat["GF"] / diameter))


# ---- Lanz-Odermatt --------------------------------------------------------------------------
# Lanz & Odermatt (1992), "Penetration limits of conventional large caliber anti tank guns /
# kinetic energy projectiles", 13th Int. Symp. Ballistics, Stockholm: semi-infinite RHA,
# tungsten rods, normal incidence: P/L = a / tanh(b0 + b1 L/D) sqrt(rho_p / rho_t)
# exp(-(c0 + c1 BHN) BHN / (rho_p v^2)) with stresses in MPa and rho v^2 in MPa
# (a 0.994, b0 0.283, b1 0.0656, c0 134.5, c1 -0.148 for tungsten alloys).
LO_TUNGSTEN = dict(a=0.994, b0=0.283, b1=0.0656, c0=134.5, c1=-0.148)


def lanz_odermatt(v, length=ROD_L, diameter=ROD_D, rho_p=WHA["rho"], rho_t=RHA["rho"],
                  bhn=RHA["BHN"], k=LO_TUNGSTEN):
    """Penetration depth (m) of a tungsten rod into semi-infinite RHA at v (m/s)."""
    resist = (k["c0"] + k["c1"] * bhn) * bhn * 1e6  # Pa
    ratio = k["a"] / math.tanh(k["b0"] + k["b1"] * length / diameter)
    return length * ratio * math.sqrt(rho_p / rho_t) * math.exp(-resist / (rho_p * v * v))


# ---- meshes ----------------------------------------------------------------------------------
def radii(outer, h_fine, r_fine, growth=1.2, h_max=None):
    """Node radii 0..outer: spacing h_fine up to r_fine, then growing by `growth` per cell up to
    h_max (default 2 h_fine), then even cells no wider than h_max."""
    h_max = 2 * h_fine if h_max is None else h_max
    pts = [i * h_fine for i in range(int(round(r_fine / h_fine)) + 1)]
    h = h_fine
    while h * growth < h_max and pts[-1] + 2 * h * growth <= outer:  # leave one cell or more
        h *= growth
        pts.append(pts[-1] + h)
    n = max(1, int(math.ceil((outer - pts[-1]) / h_max - 1e-9)))
    return np.concatenate([pts, np.linspace(pts[-1], outer, n + 1)[1:]])


def largest_diameter(path):
    """Largest element diameter (longest distance between two of its nodes) of a Gmsh 2.2 mesh
    written by this module: the bound the Rankine set-up compares with the snap-back limit."""
    with open(path) as f:
        text = f.read().split("$Nodes\n")[1]
    lines = text.split("\n")
    n = int(lines[0])
    X = np.array([[float(v) for v in ln.split()[1:3]] for ln in lines[1:n + 1]])
    worst = 0.0
    for ln in text.split("$Elements\n")[1].split("\n")[1:]:
        w = ln.split()
        if len(w) < 5 or w[1] not in ("2", "3"):
            continue
        P = X[[int(k) - 1 for k in w[5:]]]
        worst = max(worst, max(np.linalg.norm(a - b) for a in P for b in P))
    return worst


def levels(top, thickness, h):
    """Node levels of a layer from y = top down to top - thickness, about h apart."""
    n = max(1, int(round(thickness / h)))
    return np.linspace(top - thickness, top, n + 1)


def _rect_axes(xs, ys, element):
    """rect_mesh on arbitrary (monotone) axis coordinates; same edges xmin..ymax."""
    X, E, G = meshgen.rect_mesh(len(xs) - 1, len(ys) - 1, 1.0, 1.0, element=element)
    i = np.rint(X[:, 0] * (len(xs) - 1)).astype(int)
    j = np.rint(X[:, 1] * (len(ys) - 1)).astype(int)
    X = np.column_stack([np.asarray(xs)[i], np.asarray(ys)[j], np.zeros(len(X))])
    return X, E, G


def _write(path, xs, ys, element):
    X, E, G = _rect_axes(xs, ys, element)
    meshgen.write_gmsh22(path, X, E, G)
    return len(E)


def target_meshes(folder, h, tiles=N_TILES, cover=True, backing_t=BACKING_T, r_fine=20e-3,
                  growth=1.2, rod_l=ROD_L, target_r=TARGET_R, tile_t=TILE_T):
    """Write rod.msh (quad4), cover.msh (quad4), tile1..N.msh (tri3), backing.msh (quad4) into
    `folder`: cells of h up to r = r_fine (at least the rod's diameter), then growing outwards
    to 2 h in the tiles (their crack band) and 4 h in the metals, up to target_r. Each mesh has
    the edge groups xmin (axis), xmax, ymin, ymax. Returns
    {name: element count}."""
    r_tile = radii(target_r, h, max(r_fine, ROD_D), growth)  # cells <= 2 h (crack band)
    r_metal = radii(target_r, h, max(r_fine, ROD_D), growth, h_max=4 * h)
    r_rod = np.linspace(0, ROD_D / 2, max(2, int(round(ROD_D / 2 / h))) + 1)
    counts = {"rod": _write(os.path.join(folder, "rod.msh"), r_rod,
                            levels(GAP + rod_l, rod_l, h), "quad4")}
    top = 0.0
    if cover:
        counts["cover"] = _write(os.path.join(folder, "cover.msh"), r_metal,
                                 levels(top, COVER_T, h), "quad4")
        top -= COVER_T
    for k in range(tiles):
        counts[f"tile{k + 1}"] = _write(os.path.join(folder, f"tile{k + 1}.msh"), r_tile,
                                        levels(top, tile_t, h), "tri3")
        top -= tile_t
    counts["backing"] = _write(os.path.join(folder, "backing.msh"), r_metal,
                               levels(top, backing_t, h), "quad4")
    return counts


def rha_block_mesh(folder, h, thickness=RHA_BLOCK_T, r_fine=20e-3, growth=1.2):
    """The steel-only reference target: rha_block.msh (quad4), an RHA block of radius TARGET_R
    and `thickness` with its front face at y = 0, meshed like the backing."""
    r = radii(TARGET_R, h, max(r_fine, ROD_D), growth, h_max=4 * h)
    return _write(os.path.join(folder, "rha_block.msh"), r, levels(0.0, thickness, h), "quad4")


def plate_3d_meshes(folder, h, rod_d=ROD_D, rod_l=30e-3, plate_t=10e-3, plate_w=40e-3):
    """The 3D companion: a square tet4 rod (side rod_d, length rod_l) above a square tet4 plate
    (plate_w x plate_w x plate_t, front face z = 0, cells of 2 h), both centred on the z axis. Writes
    rod3d.msh and plate3d.msh; returns their element counts."""
    n = max(2, int(round(rod_d / h)))
    X, E, G = meshgen.box_tet_mesh(n, n, int(round(rod_l / h)), rod_d, rod_d, rod_l,
                                   origin=(-rod_d / 2, -rod_d / 2, GAP))
    meshgen.write_gmsh22(os.path.join(folder, "rod3d.msh"), X, E, G)
    m = max(2, int(round(plate_w / (2 * h))))
    P, F, H = meshgen.box_tet_mesh(m, m, max(2, int(round(plate_t / (2 * h)))), plate_w, plate_w,
                                   plate_t, origin=(-plate_w / 2, -plate_w / 2, -plate_t))
    meshgen.write_gmsh22(os.path.join(folder, "plate3d.msh"), P, F, H)
    return {"rod3d": len(E), "plate3d": len(F)}


# ---- depth of penetration from the ParaView frames ------------------------------------------
def _frame(path):
    """(points[N,3], cells as node lists) of one .vtu frame (needs the vtk Python module)."""
    import vtk
    from vtk.util.numpy_support import vtk_to_numpy

    r = vtk.vtkXMLUnstructuredGridReader()
    r.SetFileName(path)
    r.Update()
    g = r.GetOutput()
    pts = vtk_to_numpy(g.GetPoints().GetData())
    cells = [[g.GetCell(c).GetPointId(k) for k in range(g.GetCell(c).GetNumberOfPoints())]
             for c in range(g.GetNumberOfCells())]
    return pts, cells


def last_frame(folder, body):
    """Path of the last frame of body `body` in `folder` (files BODY_<step>.vtu)."""
    import glob
    import re

    frames = glob.glob(os.path.join(folder, f"{body}_*.vtu"))
    return max(frames, key=lambda f: int(re.findall(r"_(\d+)\.vtu$", f)[0]))


def depth(folder, backing_top=-(COVER_T + N_TILES * TILE_T), body="backing", thickness=BACKING_T,
          r_axis=None):
    """From the last frames in `folder`: the depth of penetration into `body` (its initial front
    face minus the highest point of its remaining elements within one rod radius of the axis:
    the crater floor; `thickness` when nothing is left there) and the residual rod length (axial
    extent of the rod's remaining elements). Returns (dop, residual length) in m."""
    r_axis = ROD_D / 2 if r_axis is None else r_axis
    pts, cells = _frame(last_frame(folder, body))
    used = np.unique([n for c in cells for n in c])
    near = [n for n in used if pts[n, 0] <= r_axis]
    floor = max(pts[n, 1] for n in near) if near else backing_top - thickness
    pts, cells = _frame(last_frame(folder, "rod"))
    used = np.unique([n for c in cells for n in c])
    residual = float(np.ptp(pts[used, 1])) if len(used) else 0.0
    return max(0.0, backing_top - floor), residual


BODIES = ("rod", "cover", "tile1", "tile2", "tile3", "backing")
HELD = ("kinetic", "strain", "plastic_work", "fracture_energy", "viscous_work", "eroded_energy")
WORK = ("external_work", "contact_work", "boundary_work", "shield_work")


def energy_summary(folder, bodies=BODIES):
    """From the energy files BODY_energy.csv in `folder`: E0 and, as fractions of it at the last
    common row, what the bodies hold (HELD columns, summed), the summed contact work and the
    worst balance error over all rows: |sum HELD - E0 - sum WORK| / E0."""
    import csv

    e = {}
    for b in bodies:
        with open(os.path.join(folder, f"{b}_energy.csv")) as f:
            rows = list(csv.DictReader(f))
        e[b] = {k: [float(r[k]) for r in rows] for k in rows[0]}
    n = min(len(e[b]["step"]) for b in bodies)
    e0 = sum(e[b]["kinetic"][0] for b in bodies)

    def total(cols, k):
        return sum(e[b][c][k] for b in bodies for c in cols if c in e[b])

    worst = max(abs(total(HELD, k) - e0 - total(WORK, k)) / e0 for k in range(n))
    out = {c: total((c,), n - 1) / e0 for c in HELD + ("contact_work",)}
    out.update(E0=e0, balance=worst, eroded={b: int(e[b]["eroded_elements"][n - 1]) for b in bodies})
    return out


def mass_efficiency(v, dop, ceramic_t=N_TILES * TILE_T, cover_t=COVER_T):
    """Mass efficiency of the ceramic against the Lanz-Odermatt steel depth: the areal density of
    RHA it replaced, rho_s (P_LO - cover - DOP), over its own, rho_c t_c (DOP-test definition)."""
    return RHA["rho"] * (lanz_odermatt(v) - cover_t - dop) / (AD995["rho"] * ceramic_t)


def _report(folder, bodies, dop, rest, thickness, efficiency):
    s = energy_summary(folder, bodies)
    print(f"depth of penetration {dop * 1e3:.1f} mm "
          f"({'perforated' if dop >= thickness else 'not perforated'}), "
          f"residual rod length {rest * 1e3:.1f} mm")
    print(f"E0 {s['E0']:.0f} J; worst energy balance error {100 * s['balance']:.3f} % of E0; "
          f"eroded elements {s['eroded']}")
    print("fractions of E0 at the end: " + ", ".join(
        f"{c} {s[c]:.4f}" for c in HELD + ("contact_work",)))
    v = math.sqrt(2 * s["E0"] / (WHA["rho"] * math.pi * ROD_D ** 2 / 4 * ROD_L))
    line = (f"impact at {v:.0f} m/s: Lanz-Odermatt depth into semi-infinite RHA "
            f"{lanz_odermatt(v) * 1e3:.1f} mm")
    if efficiency:
        bound = "at most " if dop >= thickness else ""
        line += f"; ceramic mass efficiency {bound}{mass_efficiency(v, dop):.2f}"
    print(line)


if __name__ == "__main__":
    import sys

    if len(sys.argv) == 3 and sys.argv[1] == "depth":
        _report(sys.argv[2], BODIES, *depth(sys.argv[2]), BACKING_T, True)
    elif len(sys.argv) == 3 and sys.argv[1] == "depth_rha":
        dop, rest = depth(sys.argv[2], 0.0, "rha_block", RHA_BLOCK_T)
        _report(sys.argv[2], ("rod", "rha_block"), dop, rest, RHA_BLOCK_T, False)
    else:
        print("usage: python3 -m fracdem.ceramic depth|depth_rha OUT_FOLDER "
              "(in.ceramic_target | in.rod_rha output)")

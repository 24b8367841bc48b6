"""3D fracture: a single-edge-notched concrete block of tet4 pulled apart splits cleanly into two
fragments along its notch plane, with its energy balanced and about G_f per unit ligament area
dissipated.

Every parameter and its source:

* Concrete: Petersson (1981), Report TVBM-1006, Lund Institute of Technology, as quoted by the
  benchmarks of his notched beam (e.g. Rots 1988): E = 30 GPa, nu = 0.2, f_t = 3.33 MPa,
  G_f = 124 N/m, the values of the 2D validation (test_fracture_validation.py). Density
  2400 kg/m^3 (EN 1991-1-1 Table A.1): it sets only the inertia.
* Section and notch: the RILEM TC 50-FMC (1985) notched beam for aggregates up to 16 mm,
  100 x 100 mm, with its notch of half the depth (a = 50 mm, a zero-width cut through the whole
  width); a block 200 mm long (2 D). Ligament 50 x 100 mm: G_f A_lig = 0.62 J.
* Loading: tension, not the RILEM three-point bending. Under three-point bending the crack
  climbs from the notch tip but the two halves stay joined at the load line: its nodes are
  shared and held by the prescribed velocity, and the compressed zone under them never fails in
  tension (docs/validation.md, "Fracture: mixed mode and 3D"). Here both end faces are held in
  all components (clamped grips: the ends neither rotate nor slide), the face x = +100 mm moves
  at v = 50 mm/s ramped over 0.2 ms (about two periods of the held block's first axial mode,
  2 L / c = 0.11 ms); the peak comes at ~0.54 ms with KE/SE ~ 0.02; run to an end displacement of 0.1 mm
  (about 4.5 times the one at the peak; the halves separate at ~0.06 mm).
* Mesh: Kuhn-split hexes (meshgen.notched_block_tet), h = 12.5 mm in y (8 cells, 4 across the
  ligament) and along x within 25 mm of the notch, growing by 1.3 to 25 mm towards the ends;
  4 cells of 25 mm through the width; 2304 tet4. Time step 0.7 of the stable step (the cracks
  follow element faces, element geometry is unchanged). `erode_cracked yes` removes elements
  that carry no more tension: without it the halves separate (2 fragments) and then failed band
  elements hanging on the crack faces by a node or an edge are split off one by one.
* Checks and tolerances: 2 fragments at the end (the energy file's `fragments`); every split
  node within one element (h) of the notch plane x = 0 and on the ligament (y >= a): the crack
  follows element faces on either side of a one-element band; the first split on the notch tip
  line; energy balance kinetic + strain + dissipated + eroded = boundary work within 1 % of the
  work at every output row; dissipated energy within a factor of 1.5 of G_f A_lig either way
  (a crack band dissipates G_f per unit area only where it localises into one element layer:
  damage that spreads beside it adds to it, band elements that a split unloads before they are
  traction-free stop short of it); quasi-static peak (KE/SE < 5e-2); the
  same run at np 2 makes the same splits in the same order and ends with as many fragments.
  Reported, not asserted: the peak load against f_t times the ligament area.

Run: python3 tests/integration/test_fracture_3d.py --exe build/fracdem (~20 s; the np 1 and np 2 runs).
"""
import os
import sys
import tempfile

import numpy as np

import harness as h

sys.path.insert(0, os.path.join(h.ROOT, "python"))
from fracdem import meshgen  # noqa: E402

args = h.parse_args(h.parser(vtk="block.pvd"))

# Petersson (1981); density EN 1991-1-1; section and notch RILEM TC 50-FMC.
RHO, E, NU, FT, GF = 2400.0, 30e9, 0.2, 3.33e6, 124.0
LENGTH, DEPTH, WIDTH, NOTCH = 0.2, 0.1, 0.1, 0.05
H, FINE, GROWTH, CAP, NZ = 0.0125, 0.025, 1.3, 0.025, 4
V, RAMP, STRETCH, DT_FRACTION = 0.05, 2e-4, 1e-4, 0.7
A_LIG = (DEPTH - NOTCH) * WIDTH


def block_mesh(path):
    # x: spacing H within FINE of the notch, then growing by GROWTH up to CAP
    xs = meshgen.capped_graded_axis(FINE, H, LENGTH / 2, GROWTH, CAP)
    # span: only names the (unused) support groups; any grid line inside the block will do
    X, T, _ = meshgen.notched_block_tet(LENGTH, DEPTH, WIDTH, NOTCH, H, span=2 * xs[-2], xs=xs, nz=NZ)
    tol = 1e-9 * LENGTH
    groups = {name: meshgen._chain(np.flatnonzero(np.abs(X[:, 0] - x) < tol), 3)
              for name, x in (("xmin", -LENGTH / 2), ("xmax", LENGTH / 2))}
    meshgen.write_gmsh22(path, X, T, groups)
    return X, T


def run_block(wd, np_=1):
    h.copy_inputs(["in.notched_block_3d", "in.fe_common"], wd)
    X, T = block_mesh(os.path.join(wd, "block.msh"))
    var = dict(mesh="block.msh", rho=RHO, E=E, nu=NU, ft=FT, gf=GF, v=V, ramp=RAMP, fevery=10,
               thermo=10 ** 9, vtk=args.vtk)
    r = h.run_at_stable_fraction(args.exe, "in.notched_block_3d", wd, var, DT_FRACTION,
                                 STRETCH / V + RAMP / 2, 500, np_=np_)
    # every split, separations (logged without a normal) included
    r.update(X=X, ntet=len(T), splits=h.node_splits(wd))
    return r


wd = tempfile.mkdtemp(prefix="fracture_3d_")
r = run_block(wd)
print(f"run directory {wd}")
r2 = run_block(tempfile.mkdtemp(prefix="fracture_3d_np2_"), np_=2)
e = r["energy"]
P = np.array(e["reaction_xmax_x"])
k = int(np.argmax(P))
ke_se = e["kinetic"][k] / e["strain"][k]
pos = h.split_positions(r["splits"], r["X"])
D = np.array(e["fracture_energy"])
work = np.array(e["boundary_work"])
balance = h.energy_balance(e)
frags = np.array(e["fragments"]).astype(int)
two = np.flatnonzero(frags == 2)
print(f"notched block: {r['ntet']} tet4, dt = {r['dt']:.3g} s ({DT_FRACTION} x {r['dt0']:.3g}), "
      f"{r['steps']} steps, {r['wall']:.1f} s")
print(f"  peak {P[k] / 1e3:.2f} kN at u = {e['displacement_xmax_x'][k] * 1e6:.1f} um "
      f"(f_t A_lig = {FT * A_LIG / 1e3:.2f} kN, {100 * (P[k] / (FT * A_LIG) - 1):+.1f} %), "
      f"KE/SE at the peak {ke_se:.1e}")
print(f"  {len(pos)} splits, {int(e['eroded_elements'][-1])} elements eroded "
      f"({e['eroded_energy'][-1]:.2e} J), fragments {frags[-1]} at the end"
      + (f", 2 from u = {e['displacement_xmax_x'][two[0]] * 1e6:.1f} um" if len(two) else ""))
if len(pos):
    print(f"  split nodes: |x| <= {np.abs(pos[:, 0]).max() * 1e3:.1f} mm, y from "
          f"{pos[:, 1].min() * 1e3:.1f} to {pos[:, 1].max() * 1e3:.1f} mm; first at "
          f"({pos[0][0] * 1e3:.1f}, {pos[0][1] * 1e3:.1f}, {pos[0][2] * 1e3:.1f}) mm")
print(f"  dissipated {D[-1]:.4f} J = {D[-1] / (GF * A_LIG):.3f} G_f A_lig ({GF * A_LIG:.3f} J); "
      f"kinetic {e['kinetic'][-1]:.4f} J, work {work[-1]:.4f} J at the end; "
      f"energy balance worst {balance:.1e} of the work")

tol = 1e-9
h.check(ke_se < 5e-2, f"quasi-static: KE/SE at the peak {ke_se:.1e} < 5e-2")
h.check(frags[-1] == 2, f"the block ends in 2 fragments (got {frags[-1]})")
h.check(len(pos) > 0 and np.abs(pos[:, 0]).max() <= H + tol,
        f"every split node within h = {H * 1e3:.1f} mm of the notch plane x = 0")
h.check(len(pos) > 0 and pos[:, 1].min() >= NOTCH - tol,
        f"every split node on the ligament (y >= a = {NOTCH * 1e3:.0f} mm)")
h.check(len(pos) > 0 and abs(pos[0][0]) < tol and abs(pos[0][1] - NOTCH) < tol,
        "the first split is on the notch tip line (x = 0, y = a)")
h.check(balance < 1e-2, f"energy balance closes within 1 % of the work (worst {balance:.1e})")
ratio = D[-1] / (GF * A_LIG)
h.check(1 / 1.5 <= ratio <= 1.5,
        f"dissipated energy {D[-1]:.4f} J = {ratio:.3f} G_f A_lig, within a factor of 1.5")
h.check(r2["splits"] == r["splits"] and int(r2["energy"]["fragments"][-1]) == frags[-1],
        f"np 2 makes the same {len(r['splits'])} splits (step, node, new node) and ends with "
        f"{int(r2['energy']['fragments'][-1])} fragments like np 1")
print("OK")

"""The Kalthoff-Winkler edge impact (a pre-notched plate struck between its notches) as a
convergence case for fracture: Gmsh meshes of the half plate, the input script, and the crack
measures read from fem/vtk frames (angle from the notch axis, branches, far-edge cracks, tip
position). Used by bench/fracture_convergence.py.

Geometry and loading from the experiment (Kalthoff & Winkler 1987; Kalthoff 1988, as modelled by
Belytschko et al. 2003 and Borden et al. 2012): a 200 x 100 mm plate with two 50 mm notches 50 mm
apart, struck between them at 16.5 m/s; by symmetry the half plate 100 x 100 mm, the notch from
(0, 25 mm) to (50 mm, 25 mm), the struck edge x = 0, 0 <= y <= 25 mm, the symmetry line y = 0
held in y. Maraging steel: E 190 GPa, nu 0.3, rho 8000 kg/m3, G_f 2.213e4 J/m2 (K_Ic 68 MPa
sqrt(m)). The experiment: one crack leaves the notch tip at about 70 deg from the notch axis."""
import math
import os
import re

import numpy as np

STEEL = dict(density=8000, youngs=190e9, poisson=0.3, fracture_energy=2.213e4)
# Tensile strength of the Rankine model: not given by the experiment (it reports the angle and
# the speed); 1 GPa keeps the characteristic length E G_f / f_t^2 = 4.2 mm above every element
# size of the study (no snap-back) and lets the crack start at about 25 us as observed.
STRENGTH = 1.0e9
NOTCH_Y, NOTCH_LENGTH, NOTCH_WIDTH, SIZE = 0.025, 0.05, 0.3e-3, 0.1
SPEED, RISE = 16.5, 1e-6
TIP = (NOTCH_LENGTH, NOTCH_Y)
EXPERIMENT_ANGLE = 70.0


def mesh(path, h):
    """Half plate with the notch (a slot of NOTCH_WIDTH ending at the tip), element size h
    everywhere (Gmsh's default frontal-Delaunay triangles), finer only at the slot's end. Groups: `impact` (x = 0 below the notch) and
    `sym` (y = 0). Returns the element count."""
    import gmsh
    gmsh.initialize()
    gmsh.option.setNumber("General.Verbosity", 0)
    gmsh.model.add("kalthoff")
    occ = gmsh.model.occ
    plate = occ.addRectangle(0, 0, 0, SIZE, SIZE)
    slot = occ.addRectangle(0, NOTCH_Y - NOTCH_WIDTH / 2, 0, NOTCH_LENGTH, NOTCH_WIDTH)
    occ.cut([(2, plate)], [(2, slot)])
    occ.synchronize()
    for _, tag in gmsh.model.getEntities(1):
        x, y, _ = occ.getCenterOfMass(1, tag)
        name = ("impact" if abs(x) < 1e-9 and y < NOTCH_Y else
                "sym" if abs(y) < 1e-9 else None)
        if name:
            gmsh.model.setPhysicalName(1, gmsh.model.addPhysicalGroup(1, [tag]), name)
    surfaces = [t for _, t in gmsh.model.getEntities(2)]
    gmsh.model.setPhysicalName(2, gmsh.model.addPhysicalGroup(2, surfaces), "plate")
    gmsh.option.setNumber("Mesh.CharacteristicLengthMax", h)
    gmsh.option.setNumber("Mesh.CharacteristicLengthMin", min(h, NOTCH_WIDTH))
    # The slot's end is NOTCH_WIDTH wide: elements there are at most that size.
    field = gmsh.model.mesh.field
    dist = field.add("Distance")
    field.setNumbers(dist, "PointsList", [t for _, t in gmsh.model.getEntities(0)
                                          if abs(occ.getCenterOfMass(0, t)[0] - NOTCH_LENGTH)
                                          < 1e-9])
    thr = field.add("Threshold")
    field.setNumber(thr, "InField", dist)
    field.setNumber(thr, "SizeMin", min(h, NOTCH_WIDTH))
    field.setNumber(thr, "SizeMax", h)
    field.setNumber(thr, "DistMin", NOTCH_WIDTH)
    field.setNumber(thr, "DistMax", 10 * h)
    field.setAsBackgroundMesh(thr)
    gmsh.option.setNumber("Mesh.MshFileVersion", 2.2)
    gmsh.model.mesh.generate(2)
    gmsh.write(path)
    n = len(gmsh.model.mesh.getElementsByType(2)[0])
    gmsh.finalize()
    return n


SCENE = """dimension 2
atom_style granular
atom_modify map array
boundary f f p
newton off
communicate single vel yes
units si
region box block -0.05 0.15 -0.05 0.15 -0.001 0.001 units box
create_box 1 box
neighbor 0.001 bin
neigh_modify delay 0
hard_particles yes
fix m1 all property/global youngsModulus peratomtype {youngs}
fix m2 all property/global poissonsRatio peratomtype {poisson}
fix m3 all property/global coefficientRestitution peratomtypepair 1 0.5
fix m4 all property/global coefficientFriction peratomtypepair 1 0.3
pair_style gran model hertz tangential history
pair_coeff * *
timestep {dt}
fix plate all fem/body file {mesh} type 1 density {density} youngs {youngs} poisson {poisson} &
    plane strain thickness 0.001 material rankine strength {strength} &
    fracture_energy {fracture_energy} {softening}fracture nodal {fracture} &
    fixed sym y prescribed_velocity impact {speed} NULL 0 ramp {rise} &
    energy_file energy.csv {every}
thermo {every}
fix vtk all fem/vtk {every} out/plate body plate
run {steps}
"""


def input_text(mesh_path, dt, end_time=80e-6, frames=16, fracture="", softening=""):
    """The input script: the half plate struck at SPEED (ramped over RISE), run to end_time with
    `frames` fem/vtk frames and energy rows."""
    steps = int(round(end_time / dt))
    every = max(1, steps // frames)
    return SCENE.format(mesh=mesh_path, dt=dt, strength=STRENGTH, speed=SPEED, rise=RISE,
                        steps=every * frames, every=every, fracture=fracture,
                        softening=softening, **STEEL)


def failed_centres(vtu, threshold=0.99):
    """Centroids (deformed, in-plane) of the active elements of a fem/vtk frame at damage >=
    threshold."""
    from fracdem import stress
    _, centres, damage = stress.damage_fraction(vtu)
    return centres[damage >= threshold][:, :2]


def arcs(points, radius, width):
    """The failed arcs that the circle of `radius` about the notch tip crosses (above the notch):
    angles (deg from the notch axis) of the points within `width` of it, grouped where gaps
    exceed 3 widths along the circle. Returns the mean angle of each group."""
    d = points - np.array(TIP)
    r = np.hypot(d[:, 0], d[:, 1])
    sel = (np.abs(r - radius) < width) & (d[:, 1] > -NOTCH_WIDTH)
    ang = np.sort(np.degrees(np.arctan2(d[sel, 1], d[sel, 0])))
    if len(ang) == 0:
        return []
    gap = np.degrees(3 * width / radius)
    groups, start = [], 0
    for k in range(1, len(ang) + 1):
        if k == len(ang) or ang[k] - ang[k - 1] > gap:
            groups.append(float(np.mean(ang[start:k])))
            start = k
    return groups


def crack_measures(points, h):
    """From the failed elements of the last frame: the crack angle (deg from the notch axis, the
    line from the tip through the failed elements 5-25 mm from it, least squares), the largest
    number of separate cracks that one circle about the tip crosses (10, 20, 30, 40 mm), the
    crack length (the farthest failed element from the tip within 15 deg of the angle), and the
    failed elements farther than 10 mm from every circle crossing and from the tip's crack (a
    crack started elsewhere: the far corner, the struck edge)."""
    d = points - np.array(TIP)
    r = np.hypot(d[:, 0], d[:, 1])
    width = max(1.5 * h, 1e-3)
    near = (r > 0.005) & (r < 0.025) & (d[:, 1] > 0)
    angle = float("nan")
    if near.sum() >= 3:
        # The direction through the tip that minimises the squared distances of the points.
        u, s, vt = np.linalg.svd(d[near], full_matrices=False)
        v = vt[0] if vt[0][1] >= 0 else -vt[0]
        angle = math.degrees(math.atan2(v[1], v[0]))
    crossings = [len(arcs(points, R, width)) for R in (0.01, 0.02, 0.03, 0.04)]
    length = 0.0
    if not math.isnan(angle):
        a = np.degrees(np.arctan2(d[:, 1], d[:, 0]))
        on = np.abs(a - angle) < 15
        length = float(r[on].max()) if on.any() else 0.0
    # Failed elements away from the tip's crack (the segment from the tip along the angle, out to
    # its length) and from the tip itself: a crack started elsewhere.
    stray = int(len(points))
    if not math.isnan(angle):
        t = np.array([math.cos(math.radians(angle)), math.sin(math.radians(angle))])
        along = np.clip(d @ t, 0.0, max(length, 0.0))
        off = np.hypot(d[:, 0] - along * t[0], d[:, 1] - along * t[1])
        stray = int(np.sum((off > 0.01) & (r > 0.005)))
    return dict(angle=angle, branches=max(crossings) if crossings else 0, length=length,
                stray=stray)


LOOP = re.compile(r"Loop time of ([0-9.eE+-]+)")


def loop_time(log_text):
    m = LOOP.search(log_text)
    return float(m.group(1)) if m else float("nan")


def frame_step(path):
    """The step of a fem/vtk frame, from its name."""
    return int(re.findall(r"(\d+)\.vtu$", path)[0])


def frames(workdir):
    """The fem/vtk frames of a run, in step order."""
    out = os.path.join(workdir, "out")
    names = [os.path.join(out, f) for f in os.listdir(out) if f.endswith(".vtu")]
    return sorted(names, key=frame_step)


# ---- the same case in LAMMPS PERI (pair_style peri/pmb), the peer of the speed comparison ----
# A bond-based prototype microelastic brittle solid on a simple cubic lattice of spacing a, three
# layers thick with free faces, horizon 3a (the usual choice, Silling & Askari 2005). PMB's
# Poisson's ratio is 1/4, so its bulk modulus is E / 1.5; the micromodulus c = 18 k / (pi
# delta^4) and the critical stretch s00 = sqrt(5 G_f / (9 k delta)) (Silling & Askari 2005);
# alpha 0.25 as in the LAMMPS examples. The whole plate (a row of sites held in y is no symmetry
# plane for a nonlocal model): 100 x 200 mm, notches at y = 75 and 125 mm, struck between them.
# A notch is its row of sites removed, and the bonds across it carry nothing (sites just above a
# notch are type 2, just below type 3, and the 2-3 micromodulus is zero: one spacing could not
# keep bonds of a 3a horizon from reaching across). Sites on the struck edge move at SPEED from
# the start. A site is on the crack where compute damage/atom (the fraction of its bonds broken)
# reaches PERI_CRACK_DAMAGE. Positions are returned in the half plate's frame (y - 100 mm).
PERI_CRACK_DAMAGE = 0.35

PERI_SCENE = """units si
dimension 3
boundary s s s
atom_style peri
atom_modify map array
lattice sc {a}
region plate block 0 {size} 0 {height} 0 {thick} units box
create_box 3 plate
create_atoms 1 region plate
region n1 block -1 {notch_x} {n1_lo} {n1_hi} -1 1 units box
region n2 block -1 {notch_x} {n2_lo} {n2_hi} -1 1 units box
region notches union 2 n1 n2
delete_atoms region notches
region above1 block -1 {notch_x} {n1_hi} {n1_top} -1 1 units box
region below1 block -1 {notch_x} {n1_bot} {n1_lo} -1 1 units box
region above2 block -1 {notch_x} {n2_hi} {n2_top} -1 1 units box
region below2 block -1 {notch_x} {n2_bot} {n2_lo} -1 1 units box
set region above1 type 2
set region above2 type 2
set region below1 type 3
set region below2 type 3
pair_style peri/pmb
pair_coeff * * {c} {horizon} {s00} 0.25
pair_coeff 2 3 0.0 {horizon} {s00} 0.25
set group all density {density}
set group all volume {volume}
region impact block -1 {impact_x} {n1_hi} {n2_lo} -1 1 units box
group impact region impact
velocity impact set {speed} NULL NULL units box
fix hold impact setforce 0.0 NULL NULL
fix integrate all nve
compute damage all damage/atom
timestep {dt}
thermo {every}
dump crack all custom {steps} crack.*.txt id x y z c_damage
dump_modify crack sort id
run {steps}
"""


def peri_input(a, end_time=80e-6):
    """The PERI input for lattice spacing a; returns (text, time step)."""
    E, rho = STEEL["youngs"], STEEL["density"]
    k = E / 1.5
    delta = 3.0 * a + 1e-9
    c = 18.0 * k / (math.pi * delta ** 4)
    s00 = math.sqrt(5.0 * STEEL["fracture_energy"] / (9.0 * k * delta))
    dt = 0.5 * a * math.sqrt(rho / (2.0 * k))  # half the stable step of the lattice sum
    steps = int(round(end_time / dt))
    y1, y2 = SIZE - NOTCH_Y, SIZE + NOTCH_Y
    text = PERI_SCENE.format(
        a=a, size=SIZE, height=2 * SIZE, thick=3 * a - 1e-9, notch_x=NOTCH_LENGTH,
        n1_lo=y1 - 0.4 * a, n1_hi=y1 + 0.4 * a, n1_top=y1 + delta, n1_bot=y1 - delta,
        n2_lo=y2 - 0.4 * a, n2_hi=y2 + 0.4 * a, n2_top=y2 + delta, n2_bot=y2 - delta,
        c=c, horizon=delta, s00=s00, density=rho, volume=a ** 3, impact_x=0.5 * a,
        speed=SPEED, dt=dt, every=max(1, steps // 10), steps=steps)
    return text, dt


def peri_failed_points(dump_path):
    """In-plane positions (half plate frame) of the sites at crack damage, upper half only."""
    with open(dump_path) as f:
        lines = f.read().splitlines()
    start = next(i for i, l in enumerate(lines) if l.startswith("ITEM: ATOMS")) + 1
    data = np.array([[float(v) for v in l.split()] for l in lines[start:]])
    pts = data[data[:, 4] >= PERI_CRACK_DAMAGE][:, 1:3] - np.array([0.0, SIZE])
    return pts[pts[:, 1] >= 0]

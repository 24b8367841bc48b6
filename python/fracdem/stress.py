"""Energy stress scenes: particles shot at brittle bodies (3D slab of tets, 2D plate of triangles)
on unstructured Gmsh meshes, and the energy account of a run (particles + bodies + dissipated
against what was put in). Used by bench/fracture_stress.py and the integration tests."""
import csv
import os
import re
import subprocess

import numpy as np

# Concrete (order-of-magnitude handbook values: E 30 GPa, nu 0.2, rho 2400 kg/m3, f_t 3 MPa,
# G_f 100 N/m) hit by steel (E 200 GPa, nu 0.3, rho 7800 kg/m3).
CONCRETE = dict(density=2400, youngs=30e9, poisson=0.2, strength=3e6, fracture_energy=100)
STEEL = dict(density=7800, youngs=2e11, poisson=0.3)


def _gmsh_mesh(path, dim, lc, add_shape, lx, name):
    """Meshes the shape add_shape() makes (Gmsh's default algorithm of the dimension, largest
    element size lc), names its end faces at x = -lx/2 and lx/2 xmin and xmax, writes Gmsh 2.2;
    returns the element count."""
    import gmsh
    gmsh.initialize()
    gmsh.option.setNumber("General.Verbosity", 0)
    gmsh.model.add(name)
    add_shape(gmsh.model.occ)
    gmsh.model.occ.synchronize()
    for _, tag in gmsh.model.getEntities(dim - 1):
        c = gmsh.model.occ.getCenterOfMass(dim - 1, tag)
        for end, x in (("xmin", -lx / 2), ("xmax", lx / 2)):
            if abs(c[0] - x) < 1e-9:
                gmsh.model.setPhysicalName(dim - 1, gmsh.model.addPhysicalGroup(dim - 1, [tag]),
                                           end)
    gmsh.model.setPhysicalName(dim, gmsh.model.addPhysicalGroup(dim, [1]), name)
    gmsh.option.setNumber("Mesh.CharacteristicLengthMax", lc)
    gmsh.option.setNumber("Mesh.MshFileVersion", 2.2)
    gmsh.model.mesh.generate(dim)
    gmsh.write(path)
    n = len(gmsh.model.mesh.getElementsByType(4 if dim == 3 else 2)[0])
    gmsh.finalize()
    return n


def gmsh_slab(path, lc, size=(0.3, 0.3, 0.05)):
    """Unstructured tet4 box, centred in x and y, z from 0 to its height; xmin and xmax name the
    end faces."""
    lx, ly, lz = size
    return _gmsh_mesh(path, 3, lc, lambda occ: occ.addBox(-lx / 2, -ly / 2, 0, lx, ly, lz), lx,
                      "slab")


def gmsh_plate(path, lc, size=(0.2, 0.02)):
    """Unstructured tri3 rectangle (frontal-Delaunay), centred in x, y from 0 to its height; xmin
    and xmax name the end edges."""
    lx, ly = size
    return _gmsh_mesh(path, 2, lc, lambda occ: occ.addRectangle(-lx / 2, 0, 0, lx, ly), lx,
                      "plate")


PREAMBLE = """atom_style      granular
atom_modify     map array
boundary        f f {zb}
newton          off
communicate     single vel yes
units           si
region          domain block {box} units box
create_box      2 domain
neighbor        {skin} bin
neigh_modify    delay 0
hard_particles  yes
fix m1 all property/global youngsModulus peratomtype {Es} {Eb}
fix m2 all property/global poissonsRatio peratomtype {nus} {nub}
fix m3 all property/global coefficientRestitution peratomtypepair 2 0.5 0.5 0.5 0.5
fix m4 all property/global coefficientFriction peratomtypepair 2 0.4 0.4 0.4 0.4
pair_style      gran model hertz tangential history
pair_coeff      * *
timestep        {dt}
"""

BODY = """fix body all fem/body file {mesh} type 2 density {density} youngs {youngs} poisson {poisson} &
    {plane}model {model} material rankine strength {strength} fracture_energy {fracture_energy} &
    fracture nodal fixed xmin fixed xmax contact_bodies {contact} energy_file energy.csv {every}
fix integr all nve/sphere
compute rke all erotate/sphere
thermo_style    custom step atoms ke c_rke f_body[1] f_body[17] f_body[18]
thermo          {every}
thermo_modify   lost ignore norm no
fix vtk all fem/vtk {steps} out/body body body
run             {steps}
"""


def slab_input(mesh, speed, model, contact, dt, steps, every=10):
    """Four steel balls (r 15 mm) at `speed` m/s onto a 0.3 x 0.3 x 0.05 m concrete slab clamped
    at both x ends."""
    text = PREAMBLE.format(zb="f", box="-0.2 0.2 -0.2 0.2 -0.1 0.2", skin=0.003, dt=dt,
                           Es=STEEL["youngs"], Eb=CONCRETE["youngs"], nus=STEEL["poisson"],
                           nub=CONCRETE["poisson"])
    for x, y, z in ((0.04, 0.04, 0.07), (-0.04, 0.04, 0.071), (0.04, -0.04, 0.072),
                    (-0.04, -0.04, 0.073)):
        text += f"create_atoms 1 single {x} {y} {z} units box\n"
    text += f"set atom * diameter 0.03 density {STEEL['density']}\n"
    text += f"velocity all set 0 0 -{speed} units box\n"
    return text + BODY.format(mesh=mesh, plane="", model=model, contact=contact, steps=steps,
                              every=every, **CONCRETE)


def plate_input(mesh, speed, model, contact, dt, steps, every=10):
    """Three steel disks (r 4 mm) at `speed` m/s onto a 200 x 20 mm concrete strip (plane strain)
    clamped at both x ends."""
    text = "dimension       2\n" + PREAMBLE.format(
        zb="p", box="-0.12 0.12 -0.05 0.08 -0.0005 0.0005", skin=0.001, dt=dt,
        Es=STEEL["youngs"], Eb=CONCRETE["youngs"], nus=STEEL["poisson"], nub=CONCRETE["poisson"])
    for x, y in ((0.0, 0.0245), (0.012, 0.027), (-0.012, 0.0295)):
        text += f"create_atoms 1 single {x} {y} 0 units box\n"
    text += f"set atom * diameter 0.008 density {STEEL['density']}\n"
    text += f"velocity all set 0 -{speed} 0 units box\nfix twod all enforce2d\n"
    return text + BODY.format(mesh=mesh, plane="plane strain ", model=model, contact=contact,
                              steps=steps, every=every, **CONCRETE)


STABLE = re.compile(r"stable FE time step ([0-9.eE+-]+)")


def mpirun(np_):
    cmd = ["mpirun", "-np", str(np_)]
    if os.geteuid() == 0:
        cmd.append("--allow-run-as-root")
    if np_ > (os.cpu_count() or 1):
        cmd.append("--oversubscribe")
    return cmd


def run(exe, workdir, text, np_=1, timeout=1800):
    """Writes in.scene into workdir and runs it; returns the combined output."""
    with open(os.path.join(workdir, "in.scene"), "w") as f:
        f.write(text)
    os.makedirs(os.path.join(workdir, "out"), exist_ok=True)
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    r = subprocess.run(mpirun(np_) + [exe, "-echo", "none", "-in", "in.scene"], cwd=workdir,
                       stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                       errors="replace", timeout=timeout, env=env)
    return r.returncode, r.stdout


def stable_step(exe, workdir, text):
    """The stable FE time step the fix logs for the scene (a run of 0 steps)."""
    rc, out = run(exe, workdir, re.sub(r"run\s+\d+", "run 0", text), 1)
    m = STABLE.search(out)
    if rc != 0 or not m:
        raise RuntimeError(f"no stable step in the log of {workdir}:\n{out[-2000:]}")
    return float(m.group(1))


def thermo_rows(text):
    """step -> (particle kinetic + rotational energy) from the thermo block of one run."""
    rows, header = {}, None
    for line in text.splitlines():
        w = line.split()
        if w and w[0] == "Step":
            header = w
            continue
        if header and len(w) == len(header):
            try:
                vals = [float(x) for x in w]
            except ValueError:
                continue
            rows[int(vals[0])] = vals[header.index("KinEng")] + vals[header.index("rke")]
    return rows


def energy_account(log_text, energy_csv):
    """Per output row: (step, total now, total put in). Total now = particles' kinetic energy +
    the body's kinetic + strain + dissipated (material, bulk viscosity) + eroded energy; put in =
    the particles' initial kinetic energy + the body's external and boundary work."""
    particles = thermo_rows(log_text)
    rows = []
    with open(energy_csv) as f:
        for r in csv.DictReader(f):
            step = int(float(r["step"]))
            if step not in particles:
                continue
            body = sum(float(r.get(k) or 0) for k in ("kinetic", "strain", "fracture_energy",
                                                       "viscous_work", "eroded_energy"))
            put = sum(float(r.get(k) or 0) for k in ("external_work", "boundary_work"))
            rows.append((step, particles[step] + body, put))
    if not rows:
        raise RuntimeError("no energy rows")
    e0 = rows[0][1]
    return [(s, now, e0 + put) for s, now, put in rows]


def damage_fraction(vtu, threshold=0.5):
    """Fraction of the active elements of a fem/vtk frame with damage >= threshold, and the
    element centroids (deformed) with their damage, for a picture."""
    import vtk
    from vtk.util.numpy_support import vtk_to_numpy
    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(vtu)
    reader.Update()
    grid = reader.GetOutput()
    damage = vtk_to_numpy(grid.GetCellData().GetArray("damage"))
    cc = vtk.vtkCellCenters()
    cc.SetInputData(grid)
    cc.Update()
    centres = vtk_to_numpy(cc.GetOutput().GetPoints().GetData())
    return float(np.mean(damage >= threshold)) if len(damage) else 0.0, centres, damage

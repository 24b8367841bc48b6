"""Periodic images touch body facets as they touch stock mesh walls (issue #12 item 2).

A box periodic in x holds a rigid wall beside its low x face; a sphere (d 10 mm, E 1e7, e 0.8,
friction 0.4) starts beside the high x face and moves towards +x and obliquely in y, so that only
its periodic image can reach the wall. Compared:
  * 3D, np 1 and 2: the rigid `fix fem/body` wall against the same triangles as a stock
    `fix mesh/surface` + `fix wall/gran` wall: velocity and spin after the bounce agree within
    1e-6 (relative to the impact speed, and to the spin's size) (the same Hertz/history law on the same geometry);
  * 3D and 2D: the image contact against the same relative geometry met directly (wall and
    sphere translated so that no image is needed), within 1e-8 relative (round-off of translated coordinates); 2D also np 2 vs np 1;
  * the bounce happened: vx reversed (a sphere that passes into the wall keeps vx > 0).
About 20 s.
"""
import os
import sys
import tempfile

import harness as h

args = h.parse_args()
sys.path.insert(0, os.path.join(h.ROOT, "python"))
from fracdem import meshgen  # noqa: E402

L = 0.1


def write_wall(wd, dim, x0):
    """Rigid wall body x0 .. x0 + 0.01 as a Gmsh mesh, plus its surface as STL (3D)."""
    with open(os.path.join(wd, "in.wall_fem"), "w") as f:
        f.write("fix wall all fem/body file wall.msh type 2 rigid yes\n")
    if dim == 3:
        X, E, G = h_mesh3(wd, x0)
        meshgen.write_stl(os.path.join(wd, "wall.stl"), X, meshgen.group_triangles(G), "wall")
        with open(os.path.join(wd, "in.wall_mesh"), "w") as f:
            f.write("fix wallmesh all mesh/surface file wall.stl type 2\n"
                    "fix wall all wall/gran model hertz tangential history mesh n_meshes 1 "
                    "meshes wallmesh\n")
    else:
        h.make_rect_mesh(os.path.join(wd, "wall.msh"), (2, 6), (0.01, 0.06), origin=(x0, -0.03))


def h_mesh3(wd, x0):
    X, E, G = meshgen.box_tet_mesh(2, 6, 6, 0.01, 0.06, 0.06, origin=(x0, -0.03, -0.03))
    meshgen.write_gmsh22(os.path.join(wd, "wall.msh"), X, E, G)
    return X, E, G


def bounce(dim, wall, bc, wall_x, x0, vx, np_=1):
    wd = tempfile.mkdtemp(prefix=f"periodic_{dim}d_")
    h.copy_inputs(["in.periodic_wall"], wd)
    write_wall(wd, dim, wall_x)
    zlo, zhi = (-0.05, 0.05) if dim == 3 else (-0.005, 0.005)
    out = h.run(args.exe, "in.periodic_wall", np_=np_, workdir=wd, variables=dict(
        DIM=dim, BC=bc, BCZ="f" if dim == 3 else "p", ZLO=zlo, ZHI=zhi, WALL=wall, X0=x0, VX=vx,
        ENFORCE="fix twod all enforce2d" if dim == 2 else "", steps=6000 if dim == 3 else 14000))
    runs = h.thermo_blocks(out)
    atoms = h.column(runs, "Atoms")
    h.check(min(atoms) == 1, f"{dim}D {wall} {bc} np {np_}: no particle lost")
    return [h.column(runs, k)[-1] for k in ("vx", "vy", "wz")]


def close(a, b, tol, what):
    # relative to the impact speed (1 m/s) and to the spin's own size
    err = max(abs(p - q) / max(1.0, abs(q)) for p, q in zip(a, b))
    h.check(err < tol, f"{what}: (vx, vy, wz) {a} vs {b}, max difference {err:.2e} < {tol:g}")


# Wall beside the low x face; the sphere 6 mm inside the high x face moves +x at 1 m/s.
image_fem = bounce(3, "fem", "p", 0.001, L - 0.006, 1.0)
h.check(image_fem[0] < -0.5, f"3D: the sphere bounced off the wall through its image "
                             f"(vx after {image_fem[0]:.4f} m/s)")
image_mesh = bounce(3, "mesh", "p", 0.001, L - 0.006, 1.0)
close(image_fem, image_mesh, 1e-6, "3D image contact: fem/body vs stock mesh wall")
close(bounce(3, "fem", "p", 0.001, L - 0.006, 1.0, np_=2), image_mesh, 1e-6,
      "3D image contact at np 2: fem/body vs stock mesh wall")
# The same relative geometry met directly: wall and sphere translated by one period minus 2 cm,
# so that the wall sits inside the box ahead of the sphere.
direct = bounce(3, "fem", "p", L + 0.001 - 0.02, L - 0.006 - 0.02, 1.0)
close(image_fem, direct, 1e-8, "3D image contact vs the same contact met directly")

image_2d = bounce(2, "fem", "p", 0.001, L - 0.006, 1.0)
h.check(image_2d[0] < -0.5, f"2D: the disc bounced off the wall through its image "
                            f"(vx after {image_2d[0]:.4f} m/s)")
close(bounce(2, "fem", "p", 0.001, L - 0.006, 1.0, np_=2), image_2d, 1e-9,
      "2D image contact: np 2 vs np 1")
direct_2d = bounce(2, "fem", "p", L + 0.001 - 0.02, L - 0.006 - 0.02, 1.0)
close(image_2d, direct_2d, 1e-8, "2D image contact vs the same contact met directly")

"""The Taylor bar benchmark (copper rod on a rigid wall): parameters, published results, mesh.

Shared by tests/integration/test_taylor_bar.py, bench/taylor_bar.py and examples/taylor_bar, so
that the three run the same problem. Sources (docs/validation.md, "Taylor bar"):

* Problem: Ansys Technology Demonstration Guide, ch. 17 "Metal Bar Impacting a Rigid Wall": a
  copper bar, length 32.4 mm, radius 3.2 mm, 227 m/s onto a rigid frictionless wall; its
  elastoplastic case compares mushroom radius, final length and equivalent plastic strain with a
  reference solution. The benchmark goes back to Kamoulakos (1990), "A simple benchmark for
  impact", NAFEMS Benchmark magazine.
* Material (the benchmark's bilinear copper): E 117 GPa, nu 0.35, rho 8930 kg/m^3, yield 400 MPa,
  linear isotropic hardening 100 MPa, end time 80 us.
* Published results at 80 us (spread over codes and meshes): final length 21.4-21.5 mm, foot
  (mushroom) radius 7.0-7.1 mm, largest equivalent plastic strain 2.5-3.2. REF_* are the midpoints.
"""
import numpy as np

from . import meshgen

# Geometry and loading (SI units).
L0, R0, V0 = 32.4e-3, 3.2e-3, 227.0
T_END = 80e-6
# Bilinear copper of the benchmark.
RHO, E, NU, YIELD, HARDENING = 8930.0, 117e9, 0.35, 400e6, 100e6
# Published results at T_END: ranges over codes and meshes, and their midpoints.
LENGTH_RANGE, RADIUS_RANGE, EPS_RANGE = (21.4e-3, 21.5e-3), (7.0e-3, 7.1e-3), (2.5, 3.2)
REF_LENGTH, REF_RADIUS = sum(LENGTH_RANGE) / 2, sum(RADIUS_RANGE) / 2


def cells_along(nr):
    """Axial cell count for nr radial cells: square cells (L0 / R0 = 10.125)."""
    return int(round(nr * L0 / R0))


def bar_mesh(path, nr):
    """Quad4 mesh of the bar's half section, x = r in [0, R0], y = axis in [0, L0], written to
    `path` (Gmsh 2.2). Groups: xmin (the axis), xmax (the side), ymin (the impact face), ymax (the
    rear face), foot (the node at r = R0 on the impact face) and tail (the node at the rear on the
    axis); single nodes are written as degenerate [n, n] lines. Returns (nodes, elements)."""
    ny = cells_along(nr)
    X, E_, G = meshgen.rect_mesh(nr, ny, R0, L0, element="quad4")
    G["foot"] = np.array([[nr, nr]])  # node (i = nr, j = 0)
    G["tail"] = np.array([[(nr + 1) * ny] * 2])  # node (i = 0, j = ny)
    meshgen.write_gmsh22(path, X, E_, G)
    return X, E_


def body_command(mesh, energy_file, every, extra=""):
    """The benchmark's `fix bar all fem/body` command (one line). The wall: the impact-face nodes
    held in y (frictionless: r free); the axis held in r (u_r = 0 on it); `fixed foot z` and
    `fixed tail z` hold nothing in 2D and make the energy file report those nodes' displacements
    (columns displacement_foot_x, displacement_tail_y)."""
    return (f"fix bar all fem/body file {mesh} type 2 density {RHO:g} youngs {E:g} poisson {NU:g} "
            f"plane axisymmetric model corotational material j2 yield {YIELD:g} hardening "
            f"{HARDENING:g} gravity no fixed ymin y fixed xmin x fixed foot z fixed tail z "
            f"velocity all 0 {-V0:g} 0 energy_file {energy_file} {every} {extra}").rstrip()


def final_shape(energy):
    """(length, foot radius) at each row of an energy file read as {column: list}."""
    length = [L0 + d for d in energy["displacement_tail_y"]]
    radius = [R0 + d for d in energy["displacement_foot_x"]]
    return length, radius


def energy_balance_error(energy):
    """Largest |kinetic + strain + plastic + viscous + eroded - E(0) - shield work - boundary work|
    over the rows, over E(0) (the held wall and axis nodes do no work: they do not move)."""
    e0 = energy["kinetic"][0]
    worst = 0.0
    for k in range(len(energy["kinetic"])):
        lhs = sum(energy[c][k] for c in ("kinetic", "strain", "plastic_work", "viscous_work",
                                         "eroded_energy") if c in energy)
        rhs = e0 + sum(energy[c][k] for c in ("shield_work", "boundary_work") if c in energy)
        worst = max(worst, abs(lhs - rhs))
    return worst / e0

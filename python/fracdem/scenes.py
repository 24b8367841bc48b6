"""Input scenes shared by benchmarks and tests: the pile of plane-strain tri3 blocks thrown onto a floor."""
import os

from . import meshgen

# The pile's preamble: a 2D granular box without particles, one contact material for the bodies.
_PILE_PREAMBLE = [
    "dimension 2", "atom_style granular", "atom_modify map array", "boundary f f p",
    "newton off", "communicate single vel yes", "units si",
    None,  # the region, whose height depends on the pile
    "create_box 1 box",
    "neighbor 0.001 bin", "neigh_modify delay 0",
    "fix m1 all property/global youngsModulus peratomtype 1e7",
    "fix m2 all property/global poissonsRatio peratomtype 0.3",
    "fix m3 all property/global coefficientRestitution peratomtypepair 1 0.5",
    "fix m4 all property/global coefficientFriction peratomtypepair 1 0.3",
    "pair_style gran model hertz tangential history", "pair_coeff * *", "timestep 1e-5",
]


def block_pile(wd, rows, cols, row_speed, floor_cells, box_top, floor_balance,
               size=0.04, gap=0.008, extra="", name="b{r}{c}"):
    """Writes block.msh, floor.msh and returns the pile's input lines (without thermo and run)
    and the names of its fem/body fixes, floor first.

    rows x cols tri3 blocks (4 x 4 elements, `size` wide, `gap` apart: farther than the contact
    search reaches, so candidates grow where blocks meet), row r (bottom up) thrown down at
    row_speed(r) m/s with +-0.5 m/s sideways in a checkerboard, onto a fixed quad4 floor of
    floor_cells elements along x (2 high, 10 mm each) that holds the scene's `contact_balance`
    (floor_balance: the keyword's arguments). All bodies contact_bodies yes; `extra` is added to
    every body's material keywords."""
    meshgen.write_gmsh22(os.path.join(wd, "block.msh"),
                         *meshgen.rect_mesh(4, 4, size, size, origin=(0.0, 0.0), element="tri3"))
    floor = meshgen.rect_mesh(floor_cells, 2, 0.01 * floor_cells, 0.02, origin=(0.0, 0.0),
                              element="quad4")
    meshgen.write_gmsh22(os.path.join(wd, "floor.msh"), *floor)
    lines = list(_PILE_PREAMBLE)
    lines[lines.index(None)] = f"region box block -0.05 0.3 -0.05 {box_top} -0.01 0.01 units box"
    lines += [
        "variable common string \"type 1 density 1000 youngs 1e7 poisson 0.3 plane strain "
        f"thickness 0.1 contact_bodies yes gravity no{extra}\"",
        f"fix floor all fem/body file floor.msh ${{common}} move -0.01 {-0.02 - gap} 0 "
        f"fixed ymin contact_balance {floor_balance} file balance.csv",
    ]
    names = ["floor"]
    for r in range(rows):
        for c in range(cols):
            block = name.format(r=r, c=c)
            names.append(block)
            x, y = 0.005 + c * (size + gap), r * (size + gap)
            vx = 0.5 if (r + c) % 2 else -0.5
            lines.append(f"fix {block} all fem/body file block.msh ${{common}} move {x} {y} 0 "
                         f"velocity all {vx} {-row_speed(r)} 0")
    return lines, names

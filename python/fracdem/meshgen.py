"""Structured Gmsh 2.2 meshes (tet4 boxes, tri3/quad4 rectangles) for examples and tests, no Gmsh needed."""
import itertools

import numpy as np

_FACES3 = ("xmin", "xmax", "ymin", "ymax", "zmin", "zmax")
_EDGES2 = ("xmin", "xmax", "ymin", "ymax")


def _grid_nodes(counts, lengths, origin):
    axes = [np.linspace(o, o + l, n + 1) for n, l, o in zip(counts, lengths, origin)]
    mesh = np.meshgrid(*axes, indexing="ij")
    return np.stack([m.ravel(order="F") for m in mesh], axis=1)


def graded_axis(length_fine, h_fine, length_total, growth=1.25, symmetric=True):
    """Node coordinates: uniform spacing h_fine over length_fine, then geometric growth to length_total.

    symmetric: coordinates run from -length_total/2 to +length_total/2 with the fine zone centred;
    otherwise from -length_total to 0 with the fine zone at the top (0).
    """
    half_fine = length_fine / 2 if symmetric else length_fine
    reach = length_total / 2 if symmetric else length_total
    n_fine = max(1, int(round(half_fine / h_fine)))
    pts = [i * h_fine for i in range(n_fine + 1)]
    h = h_fine
    while pts[-1] < reach - 1e-12:
        h *= growth
        nxt = pts[-1] + h
        if reach - nxt < 0.5 * h * growth:
            nxt = reach
        pts.append(min(nxt, reach))
    pos = np.array(pts)
    if symmetric:
        return np.concatenate([-pos[:0:-1], pos])
    return -pos[::-1]


def box_tet_mesh_axes(xs, ys, zs):
    """Tet4 box on arbitrary (graded) axis coordinates; same splitting and face sets as box_tet_mesh."""
    nx, ny, nz = len(xs) - 1, len(ys) - 1, len(zs) - 1
    X, E, G = box_tet_mesh(nx, ny, nz, 1.0, 1.0, 1.0)
    ii = np.rint(X[:, 0] * nx).astype(int)
    jj = np.rint(X[:, 1] * ny).astype(int)
    kk = np.rint(X[:, 2] * nz).astype(int)
    X = np.column_stack([np.asarray(xs)[ii], np.asarray(ys)[jj], np.asarray(zs)[kk]])
    for k, t in enumerate(E):
        a, b, c, d = (X[n] for n in t)
        if np.dot(np.cross(b - a, c - a), d - a) < 0:
            E[k, 2], E[k, 3] = E[k, 3], E[k, 2]
    return X, E, G


def box_tet_mesh(nx, ny, nz, lx, ly, lz, origin=(0.0, 0.0, 0.0)):
    """Box split into nx*ny*nz hexahedra, each cut into 6 positive-volume tetrahedra.

    Returns (nodes[N,3], tets[M,4] 0-based, faces{name: quads[K,4]}) with faces named
    xmin..zmax for physical groups.
    """
    X = _grid_nodes((nx, ny, nz), (lx, ly, lz), origin)

    def nid(i, j, k):
        return i + (nx + 1) * (j + (ny + 1) * k)

    tets = []
    for i, j, k in itertools.product(range(nx), range(ny), range(nz)):
        corner = {(a, b, c): nid(i + a, j + b, k + c) for a in (0, 1) for b in (0, 1) for c in (0, 1)}
        for perm in itertools.permutations(range(3)):
            p = [0, 0, 0]
            path = [tuple(p)]
            for ax in perm:
                p[ax] = 1
                path.append(tuple(p))
            t = [corner[q] for q in path]
            a, b, c, d = (X[n] for n in t)
            if np.dot(np.cross(b - a, c - a), d - a) < 0:
                t[2], t[3] = t[3], t[2]
            tets.append(t)
    faces = {}
    for name in _FACES3:
        axis = "xyz".index(name[0])
        side = 0 if name.endswith("min") else (nx, ny, nz)[axis]
        quads = []
        others = [a for a in range(3) if a != axis]
        n = (nx, ny, nz)
        for u in range(n[others[0]]):
            for v in range(n[others[1]]):
                q = []
                for du, dv in ((0, 0), (1, 0), (1, 1), (0, 1)):
                    idx = [0, 0, 0]
                    idx[axis] = side
                    idx[others[0]] = u + du
                    idx[others[1]] = v + dv
                    q.append(nid(*idx))
                quads.append(q)
        faces[name] = np.array(quads)
    return X, np.array(tets), faces


def rect_mesh(nx, ny, lx, ly, origin=(0.0, 0.0), element="tri3"):
    """Rectangle of nx*ny cells as counter-clockwise tri3 (2 per cell) or quad4.

    Returns (nodes[N,3] with z = 0, elements[M,3|4], edges{name: lines[K,2]}).
    """
    X = _grid_nodes((nx, ny), (lx, ly), origin)
    X = np.column_stack([X, np.zeros(len(X))])

    def nid(i, j):
        return i + (nx + 1) * j

    elems = []
    for i, j in itertools.product(range(nx), range(ny)):
        a, b, c, d = nid(i, j), nid(i + 1, j), nid(i + 1, j + 1), nid(i, j + 1)
        if element == "quad4":
            elems.append([a, b, c, d])
        elif element == "tri3":
            elems += [[a, b, c], [a, c, d]]
        else:
            raise ValueError(f"element must be 'tri3' or 'quad4', got {element!r}")
    edges = {
        "xmin": np.array([[nid(0, j), nid(0, j + 1)] for j in range(ny)]),
        "xmax": np.array([[nid(nx, j), nid(nx, j + 1)] for j in range(ny)]),
        "ymin": np.array([[nid(i, 0), nid(i + 1, 0)] for i in range(nx)]),
        "ymax": np.array([[nid(i, ny), nid(i + 1, ny)] for i in range(nx)]),
    }
    return X, np.array(elems), edges


def compact(nodes, elements):
    """Drop nodes that no element uses and renumber: (nodes, elements)."""
    used = np.unique(np.asarray(elements).ravel())
    new_id = -np.ones(len(nodes), dtype=int)
    new_id[used] = np.arange(len(used))
    return np.asarray(nodes)[used], new_id[np.asarray(elements)]


def bucket_2d(width, height, wall, h, origin=(0.0, 0.0), opening="+x"):
    """A 2D dragline bucket: a U-shaped tri3 section (floor, back wall, top lip open), open
    towards `opening` ("+x" or "-x"). Cells of about h; returns (nodes, tri3 elements)."""
    nx, ny = max(2, int(round(width / h))), max(2, int(round(height / h)))
    X, E, _ = rect_mesh(nx, ny, width, height, origin=origin, element="tri3")
    c = X[E].mean(axis=1)
    x0, y0 = origin
    back = (c[:, 0] < x0 + wall) if opening == "+x" else (c[:, 0] > x0 + width - wall)
    keep = (c[:, 1] < y0 + wall) | back
    return compact(X, E[keep])


def funnel_tet_mesh(r_outlet, r_top, height, thickness, n_around, n_up, n_through=1,
                    origin=(0.0, 0.0, 0.0)):
    """A conical hopper wall (tet4): inner radius r_outlet at the bottom to r_top at the top,
    wall `thickness`. A box mesh in (s, theta, z) mapped to cylindrical coordinates, so that
    elements keep a positive orientation. The seam at theta = 0 is left unmerged (fine for a
    rigid body: the seam faces lie inside the wall). Returns (nodes, tets)."""
    X, E, _ = box_tet_mesh(n_through, n_around, n_up, thickness, 2 * np.pi, height)
    s, th, z = X[:, 0], X[:, 1], X[:, 2]
    r = r_outlet + (r_top - r_outlet) * z / height + s
    nodes = np.column_stack([origin[0] + r * np.cos(th), origin[1] + r * np.sin(th), origin[2] + z])
    return nodes, E


_GMSH_TYPE = {2: 1, 3: 2, 4: 4}  # nodes per element -> gmsh type for body elements by dim


def write_gmsh22(path, nodes, elements, groups=None, body_name="body"):
    """Write an ASCII Gmsh 2.2 file.

    elements: body elements (tet4 -> type 4; tri3 -> 2; quad4 -> 3 when 2D).
    groups: {name: boundary elements (lines, tris or quads)} written as named physical groups.
    """
    groups = groups or {}
    elements = np.asarray(elements)
    dim = 3 if (elements.shape[1] == 4 and np.ptp(np.asarray(nodes)[:, 2]) > 0) else 2
    body_type = {(3, 4): 4, (2, 3): 2, (2, 4): 3}[(dim, elements.shape[1])]
    line_type = {2: 1, 3: 2, 4: 3}
    names = [(dim, 1, body_name)] + [(dim - 1, k + 2, g) for k, g in enumerate(groups)]
    with open(path, "w") as f:
        f.write("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n")
        f.write(f"$PhysicalNames\n{len(names)}\n")
        for d, tag, name in names:
            f.write(f'{d} {tag} "{name}"\n')
        f.write("$EndPhysicalNames\n")
        f.write(f"$Nodes\n{len(nodes)}\n")
        for i, p in enumerate(nodes):
            f.write(f"{i + 1} {p[0]:.17g} {p[1]:.17g} {p[2]:.17g}\n")
        f.write("$EndNodes\n")
        total = len(elements) + sum(len(v) for v in groups.values())
        f.write(f"$Elements\n{total}\n")
        eid = 1
        for k, (gname, items) in enumerate(groups.items()):
            for it in np.asarray(items):
                f.write(f"{eid} {line_type[len(it)]} 2 {k + 2} {k + 2} " + " ".join(str(n + 1) for n in it) + "\n")
                eid += 1
        for e in elements:
            f.write(f"{eid} {body_type} 2 1 1 " + " ".join(str(n + 1) for n in e) + "\n")
            eid += 1
        f.write("$EndElements\n")


def main(argv=None):
    """CLI: python -m fracdem.meshgen box NX NY NZ LX LY LZ [OX OY OZ] -o out.msh | rect ..."""
    import argparse

    p = argparse.ArgumentParser(prog="python -m fracdem.meshgen", description=main.__doc__)
    sub = p.add_subparsers(dest="kind", required=True)
    b = sub.add_parser("box", help="tet4 box with faces xmin..zmax as physical groups")
    b.add_argument("n", type=int, nargs=3)
    b.add_argument("l", type=float, nargs=3)
    b.add_argument("--origin", type=float, nargs=3, default=(0, 0, 0))
    r = sub.add_parser("rect", help="tri3/quad4 rectangle with edges xmin..ymax as physical groups")
    r.add_argument("n", type=int, nargs=2)
    r.add_argument("l", type=float, nargs=2)
    r.add_argument("--origin", type=float, nargs=2, default=(0, 0))
    r.add_argument("--element", choices=("tri3", "quad4"), default="tri3")
    for s in (b, r):
        s.add_argument("-o", "--output", required=True)
    a = p.parse_args(argv)
    if a.kind == "box":
        X, E, G = box_tet_mesh(*a.n, *a.l, origin=a.origin)
    else:
        X, E, G = rect_mesh(*a.n, *a.l, origin=a.origin, element=a.element)
    write_gmsh22(a.output, X, E, G)
    print(f"wrote {a.output}: {len(X)} nodes, {len(E)} elements")


if __name__ == "__main__":
    main()

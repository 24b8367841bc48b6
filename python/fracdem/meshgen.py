"""Structured Gmsh 2.2 meshes (tet4 boxes, tri3/quad4 rectangles, fracture specimens), no Gmsh needed."""
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


def capped_graded_axis(fine, h, half_length, growth, cap):
    """-half_length .. half_length, symmetric about 0: spacing h out to |x| = fine (a multiple of
    h), then each spacing growth times the last, at most cap; a last spacing below half the
    next one joins the one before it (the notched specimens' x axes, graded away from the
    notch at x = 0)."""
    pts = [0.0]
    while pts[-1] < fine - 1e-12:
        pts.append(min(fine, pts[-1] + h))
    s = h
    while pts[-1] < half_length - 1e-12:
        s = min(s * growth, cap)
        nxt = pts[-1] + s
        if half_length - nxt < 0.5 * s:
            nxt = half_length
        pts.append(min(nxt, half_length))
    half = np.array(pts)
    return np.concatenate([-half[:0:-1], half])


def sheared_tet_bar(nx=16, ny=4, nz=4, lx=0.16, ly=0.04, lz=0.04, shear=0.5):
    """A box of Kuhn tets (box_tet_mesh) sheared by x += shear * y, so that no face is normal to
    x (the torn bar of the fracture tests). Face groups left / right: the faces of the tets wholly
    left / right of the middle (x = lx / 2 + shear * y). Returns (nodes, tets, groups)."""
    X, E, _ = box_tet_mesh(nx, ny, nz, lx, ly, lz)
    X = np.array(X, dtype=float)
    s = X[:, 0].copy()  # the side, in the unsheared frame
    X[:, 0] += shear * X[:, 1]
    faces = {"left": [], "right": []}
    for t in E:
        for name, side in (("left", s[t] < lx / 2 - 1e-9), ("right", s[t] > lx / 2 + 1e-9)):
            if side.all():
                faces[name] += [(t[0], t[1], t[2]), (t[0], t[1], t[3]), (t[0], t[2], t[3]),
                                (t[1], t[2], t[3])]
    return X, E, {k: np.array(v) for k, v in faces.items()}


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


def group_triangles(groups):
    """The boundary groups' faces as triangles (each quad split along its 0-2 diagonal)."""
    tris = []
    for faces in groups.values():
        for q in faces:
            q = list(q)
            tris += [q] if len(q) == 3 else [[q[0], q[1], q[2]], [q[0], q[2], q[3]]]
    return tris


def write_stl(path, nodes, triangles, name="surface"):
    """ASCII STL of triangles (node indices) for stock `fix mesh/surface`: the same surface a
    `fix fem/body` mesh has, written at full precision."""
    nodes = np.asarray(nodes, dtype=float)
    with open(path, "w") as f:
        f.write(f"solid {name}\n")
        for tri in triangles:
            a, b, c = (nodes[n] for n in tri)
            nrm = np.cross(b - a, c - a)
            length = np.linalg.norm(nrm)
            nrm = nrm / length if length > 0 else nrm
            f.write(" facet normal %.9g %.9g %.9g\n  outer loop\n" % tuple(nrm))
            for p in (a, b, c):
                f.write("   vertex %.17g %.17g %.17g\n" % tuple(p))
            f.write("  endloop\n endfacet\n")
        f.write(f"endsolid {name}\n")


# ---- fracture specimens: Brazilian disc, notched beam, notched block -----------------------
# Node sets are written, like rect_mesh/box_tet_mesh's, as physical groups of boundary
# elements of dimension dim - 1 (lines in 2D, triangles in 3D); the reader keeps their nodes.
# A set that is not a chain of edges (a single node, or a line of nodes in 3D) is written as
# degenerate elements ([n, n] lines, [a, b, b] triangles) that carry exactly those nodes.


def _chain(ids, nper=2):
    """Consecutive nodes of an ordered list as group elements of nper nodes (a lone node: [n]*nper)."""
    ids = [int(i) for i in ids]
    if len(ids) == 1:
        return np.array([ids * nper])
    return np.array([[a] + [b] * (nper - 1) for a, b in zip(ids[:-1], ids[1:])])


def _ring_count(k):
    """Nodes on ring k of a disc (spacing ~ ring step): a multiple of 4, so 0/90/180/270 deg are nodes."""
    return 1 if k == 0 else 4 * max(1, int(round(np.pi * k / 2)))


def _merge_rings(inner, outer, t_in, t_out):
    """Triangles between two node arcs ordered by angle (fractions t); starts and ends on their
    first/last pairs, so the radial edges at both ends are mesh edges."""
    tris, p, q = [], 0, 0
    while p < len(inner) - 1 or q < len(outer) - 1:
        if q == len(outer) - 1 or (p < len(inner) - 1 and t_in[p + 1] < t_out[q + 1]):
            tris.append([inner[p], outer[q], inner[p + 1]])
            p += 1
        else:
            tris.append([inner[p], outer[q], outer[q + 1]])
            q += 1
    return tris


def disc(radius, h, element="tri3", flat_angle_deg=10.0):
    """Brazilian-test disc of radius `radius` centred at (0,0), z = 0: tri3 on concentric rings
    (ring step radius/round(radius/h), ~h along each ring), triangulated ring by ring.

    The mesh is mirror symmetric in x and in y; rings have nodes at 0/90/180/270 deg, so the
    nodes on x = 0 are joined by a chain of edges from (0, R) to (0, -R). Returns
    (nodes[N,3], tri3[M,3] counter-clockwise, groups{name: lines[K,2]}) with groups
    "top"/"bottom" (boundary nodes within +-flat_angle_deg/2 of 90/270 deg) and "boundary".
    """
    if element != "tri3":
        raise ValueError(f"disc: element must be 'tri3', got {element!r}")
    n = max(1, int(round(radius / h)))
    counts = [_ring_count(k) for k in range(n + 1)]
    first = np.concatenate([[0], np.cumsum(counts)[:-1]])
    X = np.zeros((sum(counts), 3))
    for k in range(1, n + 1):
        m, r = counts[k], radius * k / n
        q = m // 4
        th = 2 * np.pi * np.arange(q + 1) / m
        xq, yq = r * np.cos(th), r * np.sin(th)
        xq[q], yq[0] = 0.0, 0.0
        xq[0], yq[q] = r, r
        j = np.arange(m)
        base = np.select([j <= q, j <= 2 * q, j <= 3 * q], [j, 2 * q - j, j - 2 * q], m - j)
        sx = np.where((j > q) & (j < 3 * q), -1.0, 1.0)
        sy = np.where(j > 2 * q, -1.0, 1.0)
        X[first[k] + j, 0], X[first[k] + j, 1] = sx * xq[base], sy * yq[base]

    def ring(k, js):
        return [int(first[k] + (j % counts[k])) for j in js]

    quarter = []  # first quadrant, then mirrored
    for k in range(1, n + 1):
        jo = range(counts[k] // 4 + 1)
        if k == 1:
            quarter += [[0, a, b] for a, b in zip(ring(1, jo)[:-1], ring(1, jo)[1:])]
        else:
            ji = range(counts[k - 1] // 4 + 1)
            quarter += _merge_rings(ring(k - 1, ji), ring(k, jo),
                                    [j / counts[k - 1] for j in ji], [j / counts[k] for j in jo])
    kk = np.searchsorted(first, np.arange(len(X)), side="right") - 1
    jj = np.arange(len(X)) - first[kk]
    m_all = np.array(counts)[kk]
    mirror_x = np.where(kk == 0, 0, first[kk] + (m_all // 2 - jj) % m_all)  # x -> -x
    mirror_y = np.where(kk == 0, 0, first[kk] + (-jj) % m_all)  # y -> -y
    T = np.array(quarter)
    T = np.vstack([T, mirror_x[T][:, ::-1]])
    T = np.vstack([T, mirror_y[T][:, ::-1]])
    m = counts[n]
    bnd = ring(n, range(m))
    groups = {}
    for name, centre in (("top", m // 4), ("bottom", 3 * m // 4)):
        arc = [o for o in range(1 - m // 2, m // 2 + 1) if abs(360.0 * o / m) <= flat_angle_deg / 2 + 1e-9]
        groups[name] = _chain(ring(n, [centre + o for o in arc]))
    groups["boundary"] = _chain(bnd + bnd[:1])
    return X, T, groups


def _axis(breaks, h):
    """Coordinates from 0 to max(breaks), ~h apart, with a node on every break (> 0)."""
    b = np.unique([0.0] + [float(v) for v in breaks if v > 0])
    pos = [0.0]
    for lo, hi in zip(b[:-1], b[1:]):
        pos += list(np.linspace(lo, hi, max(1, int(round((hi - lo) / h))) + 1)[1:])
    return np.array(pos)


def _sym_axis(breaks, h):
    """_axis mirrored: -max..max, exactly symmetric, with a node on 0."""
    pos = _axis(breaks, h)
    return np.concatenate([-pos[:0:-1], pos])


def _kuhn_tets(xs, ys, zs):
    """box_tet_mesh_axes(xs, ys, zs)[:2] without its per-tet Python loop: same nodes, same tets."""
    n = np.array([len(xs), len(ys), len(zs)])
    X = np.column_stack([np.asarray(c, float)[m.ravel(order="F")] for c, m in
                         zip((xs, ys, zs), np.meshgrid(*map(np.arange, n), indexing="ij"))])
    cell = np.stack(np.meshgrid(*map(np.arange, n - 1), indexing="ij"), axis=-1).reshape(-1, 3)
    tets = []
    for perm in itertools.permutations(range(3)):
        p, path = np.zeros(3, int), [np.zeros(3, int)]
        for ax in perm:
            p = p.copy()
            p[ax] = 1
            path.append(p)
        tets.append(np.stack([((cell + q) * [1, n[0], n[0] * n[1]]).sum(axis=1) for q in path], axis=1))
    T = np.stack(tets, axis=1).reshape(-1, 4)
    a, b, c, d = (X[T[:, k]] for k in range(4))
    neg = np.einsum("ij,ij->i", np.cross(b - a, c - a), d - a) < 0
    T[neg, 2], T[neg, 3] = T[neg, 3], T[neg, 2].copy()
    return X, T


def _cut_notch(X, E, a, width, tol):
    """Slot |x| < width/2, y < a: drop elements whose centroid lies in it; width 0 splits the
    mesh along x = 0 below y = a instead (elements with centroid x < 0 get copies, appended, of
    the nodes at x = 0, y < a). Returns (nodes, elements), unused nodes dropped."""
    c = X[E].mean(axis=1)
    E = E[~((np.abs(c[:, 0]) < width / 2) & (c[:, 1] < a))].copy()
    if width == 0 and a > 0:
        seam = np.flatnonzero((np.abs(X[:, 0]) < tol) & (X[:, 1] < a - tol))
        copy = -np.ones(len(X), dtype=int)
        copy[seam] = len(X) + np.arange(len(seam))
        left = X[E].mean(axis=1)[:, 0] < 0
        sub = E[left]
        E[left] = np.where(copy[sub] >= 0, copy[sub], sub)
        X = np.vstack([X, X[seam]])
    return compact(X, E)


def _find(X, x, y, tol):
    """Node ids at (x, y) (any z), sorted by z."""
    ids = np.flatnonzero((np.abs(X[:, 0] - x) < tol) & (np.abs(X[:, 1] - y) < tol))
    return ids[np.argsort(X[ids, 2])]


def notched_beam(length, depth, notch_depth, h, element="tri3", notch_width=None, span=None,
                 xs=None):
    """Three-point-bending beam [-L/2, L/2] x [0, depth] (z = 0), tri3 or quad4 on a grid of
    spacing ~h with grid lines on x = 0, +-notch_width/2, +-span/2 and y = notch_depth.

    Notch at x = 0 from y = 0 to notch_depth: the elements inside |x| < notch_width/2 are
    removed; notch_width defaults to 2 h, the two element columns beside x = 0 (the narrowest
    slot whose tip (0, notch_depth) is a node); notch_width = 0 gives a zero-width cut whose two
    faces have distinct nodes at the same coordinates. tri3 diagonals are mirrored for x < 0,
    so the mesh is symmetric. span defaults to 0.9 L. xs: the grid's x coordinates instead of the
    uniform ones (e.g. capped_graded_axis; they must include 0, +-notch_width/2, +-span/2 and
    +-L/2). Returns (nodes, elements, groups):
    "support_left"/"support_right" = the node (-+span/2, 0), "load" = the node (0, depth),
    "ligament" = the nodes on x = 0 from (0, notch_depth) to (0, depth).
    """
    if element not in ("tri3", "quad4"):
        raise ValueError(f"element must be 'tri3' or 'quad4', got {element!r}")
    span = 0.9 * length if span is None else span
    width = 2 * h if notch_width is None else notch_width
    if not (0 <= width / 2 < span / 2 < length / 2 + 1e-12) or not 0 <= notch_depth < depth:
        raise ValueError("need 0 <= notch_width < span <= length and 0 <= notch_depth < depth")
    if xs is None:
        xs = _sym_axis([width / 2, span / 2, length / 2], h)
    ys = _axis([notch_depth, depth], h)
    nx = len(xs) - 1
    X = np.array([[x, y, 0.0] for y in ys for x in xs])
    elems = []
    for j, i in itertools.product(range(len(ys) - 1), range(nx)):
        a, d = i + (nx + 1) * j, i + (nx + 1) * (j + 1)
        b, c = a + 1, d + 1
        if element == "quad4":
            elems.append([a, b, c, d])
        elif xs[i] >= 0:
            elems += [[a, b, c], [a, c, d]]
        else:
            elems += [[a, b, d], [b, c, d]]
    tol = 1e-9 * max(length, depth)
    X, E = _cut_notch(X, np.array(elems), notch_depth, width, tol)
    lig = np.flatnonzero((np.abs(X[:, 0]) < tol) & (X[:, 1] > notch_depth - tol))
    groups = {
        "support_left": _chain(_find(X, -span / 2, 0.0, tol)),
        "support_right": _chain(_find(X, span / 2, 0.0, tol)),
        "load": _chain(_find(X, 0.0, depth, tol)),
        "ligament": _chain(lig[np.argsort(X[lig, 1])]),
    }
    return X, E, groups


def notched_block_tet(lx, ly, lz, notch_depth, h, notch_width=0.0, span=None, xs=None, nz=None):
    """3D notched block [-lx/2, lx/2] x [0, ly] x [0, lz] of tet4 (Kuhn-split hexes as in
    box_tet_mesh, grid ~h with planes x = 0, +-span/2, y = notch_depth).

    Notch through the whole z thickness at x = 0 from y = 0 to notch_depth: by default
    (notch_width = 0) a cut, the hexes on either side of x = 0 having their own copies of the
    nodes at x = 0, y < notch_depth, so the halves meet only at y >= notch_depth; notch_width
    > 0 removes the hexes inside |x| < notch_width/2 instead. span defaults to 0.9 lx. xs: the
    grid's x coordinates instead of the uniform ones (e.g. graded away from the notch; they
    must include 0, +-notch_width/2, +-span/2 and +-lx/2); nz: cells through the thickness
    (default lz / h). Returns
    (nodes, tets, groups) with groups (triangles, degenerate along lines) "support_left"/
    "support_right" = the nodes on y = 0, x = -+span/2 (all z), "load" = the nodes on y = ly,
    x = 0 (all z), and "ligament" = the quads of the plane x = 0 above the notch tip.
    """
    span = 0.9 * lx if span is None else span
    if not (0 <= notch_width / 2 < span / 2 < lx / 2 + 1e-12) or not 0 <= notch_depth < ly:
        raise ValueError("need 0 <= notch_width < span <= lx and 0 <= notch_depth < ly")
    if xs is None:
        xs = _sym_axis([notch_width / 2, span / 2, lx / 2], h)
    ys = _axis([notch_depth, ly], h)
    zs = np.linspace(0.0, lz, (nz or max(1, int(round(lz / h)))) + 1)
    X, T = _kuhn_tets(xs, ys, zs)
    tol = 1e-9 * max(lx, ly, lz)
    X, T = _cut_notch(X, T, notch_depth, notch_width, tol)
    plane = np.flatnonzero((np.abs(X[:, 0]) < tol) & (X[:, 1] > notch_depth - tol))
    at = {(int(np.argmin(np.abs(ys - X[n, 1]))), int(np.argmin(np.abs(zs - X[n, 2])))): n for n in plane}
    j0 = int(np.argmin(np.abs(ys - notch_depth)))
    lig = [[at[j, k], at[j, k + 1], at[j + 1, k + 1], at[j + 1, k]]
           for j in range(j0, len(ys) - 1) for k in range(len(zs) - 1)]
    groups = {
        "support_left": _chain(_find(X, -span / 2, 0.0, tol), 3),
        "support_right": _chain(_find(X, span / 2, 0.0, tol), 3),
        "load": _chain(_find(X, 0.0, ly, tol), 3),
        "ligament": np.array(lig),
    }
    return X, T, groups


def l_panel(size, cut, h, load_offset):
    """L-shaped panel [0, size]^2 without the lower-right square [size - cut, size] x [0, cut]
    (Winkler's mixed-mode specimen): tri3 on a grid of spacing ~h with grid lines on x, y = cut
    and x = size - load_offset; the diagonals alternate by cell parity (criss-cross), so that
    no diagonal direction is preferred. Re-entrant corner at (size - cut, cut). Returns (nodes,
    tri3, groups) with "bottom" = the edge y = 0 (x <= size - cut) and "load" = the node
    (size - load_offset, cut) on the lower face of the horizontal arm.
    """
    if not 0 < cut < size or not 0 < load_offset < cut:
        raise ValueError("need 0 < cut < size and 0 < load_offset < cut")
    corner = size - cut
    xs = _axis([corner, size - load_offset, size], h)
    ys = _axis([cut, size], h)
    nx = len(xs) - 1
    X = np.array([[x, y, 0.0] for y in ys for x in xs])
    elems = []
    for j, i in itertools.product(range(len(ys) - 1), range(nx)):
        if xs[i] >= corner - 1e-12 * size and ys[j + 1] <= cut + 1e-12 * size:
            continue  # inside the cut-out
        a, d = i + (nx + 1) * j, i + (nx + 1) * (j + 1)
        b, c = a + 1, d + 1
        elems += [[a, b, c], [a, c, d]] if (i + j) % 2 == 0 else [[a, b, d], [b, c, d]]
    X, E = compact(X, np.array(elems))
    tol = 1e-9 * size
    bottom = np.flatnonzero(np.abs(X[:, 1]) < tol)
    groups = {
        "bottom": _chain(bottom[np.argsort(X[bottom, 0])]),
        "load": _chain(_find(X, size - load_offset, cut, tol)),
    }
    return X, E, groups


def main(argv=None):
    """CLI: python -m fracdem.meshgen box NX NY NZ LX LY LZ [OX OY OZ] -o out.msh | rect ... |
    disc R H OUT.msh | notched_beam L D A H OUT.msh | notched_block LX LY LZ A H OUT.msh |
    l_panel SIZE CUT H LOAD_OFFSET OUT.msh"""
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
    d = sub.add_parser("disc", help="tri3 Brazilian disc R, spacing H; groups top, bottom, boundary")
    d.add_argument("R", type=float)
    d.add_argument("H", type=float)
    d.add_argument("--flat", type=float, default=10.0, help="top/bottom arc, degrees (default 10)")
    nb = sub.add_parser("notched_beam", help="2D notched beam L x D, notch depth A, spacing H; groups "
                        "support_left, support_right, load, ligament")
    nb.add_argument("L", type=float)
    nb.add_argument("D", type=float)
    nb.add_argument("A", type=float)
    nb.add_argument("H", type=float)
    nb.add_argument("--element", choices=("tri3", "quad4"), default="tri3")
    nk = sub.add_parser("notched_block", help="tet4 notched block LX x LY x LZ, notch depth A, spacing H; "
                        "groups support_left, support_right, load, ligament")
    for name in ("LX", "LY", "LZ", "A", "H"):
        nk.add_argument(name, type=float)
    for s in (nb, nk):
        s.add_argument("--span", type=float, default=None, help="support span (default 0.9 length)")
        s.add_argument("--notch-width", type=float, default=None,
                       help="slot width; 0 = a cut with duplicated face nodes (defaults: beam 2 H, block 0)")
    lp = sub.add_parser("l_panel", help="tri3 L-shaped panel SIZE^2 without the lower-right CUT^2, "
                        "spacing H; groups bottom, load (LOAD_OFFSET from the arm's free end)")
    for name in ("SIZE", "CUT", "H", "LOAD_OFFSET"):
        lp.add_argument(name, type=float)
    for s in (d, nb, nk, lp):
        s.add_argument("output", metavar="OUT.msh")
    a = p.parse_args(argv)
    if a.kind == "box":
        X, E, G = box_tet_mesh(*a.n, *a.l, origin=a.origin)
    elif a.kind == "rect":
        X, E, G = rect_mesh(*a.n, *a.l, origin=a.origin, element=a.element)
    elif a.kind == "disc":
        X, E, G = disc(a.R, a.H, flat_angle_deg=a.flat)
    elif a.kind == "notched_beam":
        X, E, G = notched_beam(a.L, a.D, a.A, a.H, element=a.element, notch_width=a.notch_width, span=a.span)
    elif a.kind == "l_panel":
        X, E, G = l_panel(a.SIZE, a.CUT, a.H, a.LOAD_OFFSET)
    else:
        X, E, G = notched_block_tet(a.LX, a.LY, a.LZ, a.A, a.H, span=a.span,
                                    notch_width=0.0 if a.notch_width is None else a.notch_width)
    write_gmsh22(a.output, X, E, G)
    print(f"wrote {a.output}: {len(X)} nodes, {len(E)} elements")


if __name__ == "__main__":
    main()

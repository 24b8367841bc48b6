"""Fracture specimen meshes of fracdem.meshgen: Brazilian disc, notched beam (2D), notched block (tet4)."""
import subprocess
import sys

import numpy as np
import pytest

from fracdem import meshgen

TOL = 1e-12


def signed_measure(X, E):
    """Signed area (tri3, quad4 by the shoelace formula) or volume (tet4) of each element."""
    P = X[E]
    if E.shape[1] == 4 and np.ptp(X[:, 2]) > 0:
        return np.einsum("ij,ij->i", np.cross(P[:, 1] - P[:, 0], P[:, 2] - P[:, 0]), P[:, 3] - P[:, 0]) / 6
    x, y = P[:, :, 0], P[:, :, 1]
    return 0.5 * (x * np.roll(y, -1, axis=1) - np.roll(x, -1, axis=1) * y).sum(axis=1)


def quad_corners_convex(X, E):
    """Every corner of every quad turns left (strictly convex, counter-clockwise)."""
    P = X[E][:, :, :2]
    u = np.roll(P, -1, axis=1) - P
    v = np.roll(P, -2, axis=1) - np.roll(P, -1, axis=1)
    return np.all(u[:, :, 0] * v[:, :, 1] - u[:, :, 1] * v[:, :, 0] > 0)


def duplicate_coords(X):
    """Node ids whose coordinates some other node also has."""
    _, inv, cnt = np.unique(np.round(X, 12), axis=0, return_inverse=True, return_counts=True)
    return np.flatnonzero(cnt[inv.ravel()] > 1)


def edges(E):
    """Undirected element edges as a set of (i, j), i < j."""
    out = set()
    for e in E:
        for k in range(len(e)):
            a, b = int(e[k]), int(e[(k + 1) % len(e)])
            out.add((min(a, b), max(a, b)))
    return out


def group_nodes(G, name):
    return np.unique(G[name])


def read_msh22(path):
    """Minimal Gmsh 2.2 parser: nodes, {type: [conn]}, node sets of physical groups named in
    $PhysicalNames at dimension (element dim), as fracdem's reader builds them."""
    with open(path) as f:
        lines = f.read().split("\n")
    i = lines.index("$PhysicalNames")
    names = {}
    for ln in lines[i + 2:i + 2 + int(lines[i + 1])]:
        d, tag, name = ln.split(maxsplit=2)
        names[(int(d), int(tag))] = name.strip('"')
    i = lines.index("$Nodes")
    n = int(lines[i + 1])
    X = np.array([[float(v) for v in ln.split()[1:]] for ln in lines[i + 2:i + 2 + n]])
    i = lines.index("$Elements")
    dim_of = {15: 0, 1: 1, 2: 2, 3: 2, 4: 3}
    by_type, sets = {}, {}
    for ln in lines[i + 2:i + 2 + int(lines[i + 1])]:
        f = [int(v) for v in ln.split()]
        t, ntag = f[1], f[2]
        conn = [c - 1 for c in f[3 + ntag:]]
        by_type.setdefault(t, []).append(conn)
        sets.setdefault(names[(dim_of[t], f[3])], set()).update(conn)
    return X, by_type, sets


# ---- disc -------------------------------------------------------------------------------------

def test_disc_area_orientation_and_convergence():
    R = 0.05
    errors = []
    for h in (R / 10, R / 20):
        X, T, _ = meshgen.disc(R, h)
        a = signed_measure(X, T)
        assert a.min() > 0
        errors.append(abs(a.sum() - np.pi * R * R) / (np.pi * R * R))
    assert errors[0] < 0.02
    assert errors[1] < errors[0] / 2


def test_disc_nodes_unique_used_and_mirror_symmetric():
    X, T, _ = meshgen.disc(1.0, 0.1)
    assert len(duplicate_coords(X)) == 0
    assert np.array_equal(np.unique(T), np.arange(len(X)))
    assert np.all(X[:, 2] == 0)
    key = lambda P: set(map(tuple, np.round(P[:, :2], 12)))
    mirrored = X * [-1, 1, 1]
    assert key(mirrored) == key(X)
    flipped = X * [1, -1, 1]
    assert key(flipped) == key(X)
    # the triangles too map onto triangles under x -> -x
    tri_key = lambda P, T: {frozenset(map(tuple, np.round(P[t, :2], 12))) for t in T}
    assert tri_key(mirrored, T) == tri_key(X, T)


def test_disc_edge_chain_along_y_axis():
    R = 2.0
    X, T, _ = meshgen.disc(R, 0.15)
    E = edges(T)
    on_axis = np.flatnonzero(X[:, 0] == 0.0)
    order = on_axis[np.argsort(-X[on_axis, 1])]
    assert X[order[0], 1] == R and X[order[-1], 1] == -R
    assert len(order) >= 2 * round(R / 0.15) + 1
    # walk from the top: each step follows a mesh edge to the next node down on x = 0
    node = order[0]
    path = [node]
    while X[node, 1] > -R:
        nxt = [b if a == node else a for a, b in E if node in (a, b)]
        down = [k for k in nxt if X[k, 0] == 0.0 and X[k, 1] < X[node, 1]]
        assert down, f"no edge down the axis from node {node} at y = {X[node, 1]}"
        node = max(down, key=lambda k: X[k, 1])
        path.append(node)
    assert list(order) == path


def test_disc_groups():
    R = 1.0
    X, T, G = meshgen.disc(R, 0.1, flat_angle_deg=10.0)
    top, bottom, bnd = (group_nodes(G, k) for k in ("top", "bottom", "boundary"))
    r = np.hypot(X[:, 0], X[:, 1])
    assert np.allclose(r[bnd], R, rtol=0, atol=1e-12)
    assert len(bnd) == np.sum(np.abs(r - R) < 1e-12)
    assert G["boundary"].shape[1] == 2 and len(G["boundary"]) == len(bnd)  # a closed loop
    for ids, sign in ((top, 1), (bottom, -1)):
        assert len(ids) >= 1 and set(ids) <= set(bnd)
        ang = np.degrees(np.arctan2(sign * X[ids, 1], np.abs(X[ids, 0])))
        assert np.all(ang >= 85.0 - 1e-9)
        assert np.any((X[ids, 0] == 0) & (X[ids, 1] == sign * R))
    # a wider flat takes every boundary node within the angle, on both sides symmetrically
    _, _, G30 = meshgen.disc(R, 0.1, flat_angle_deg=30.0)
    top30 = group_nodes(G30, "top")
    ang = np.degrees(np.arctan2(X[bnd, 1], X[bnd, 0]))
    assert set(top30) == set(bnd[np.abs(ang - 90) <= 15 + 1e-9])
    assert len(top30) >= 3 and len(top30) % 2 == 1
    with pytest.raises(ValueError):
        meshgen.disc(R, 0.1, element="quad4")


# ---- notched beam ----------------------------------------------------------------------------

@pytest.mark.parametrize("element", ["tri3", "quad4"])
def test_notched_beam_area_orientation_groups(element):
    L, D, A, h = 0.4, 0.1, 0.03, 0.01
    X, E, G = meshgen.notched_beam(L, D, A, h, element=element)
    assert E.shape[1] == (3 if element == "tri3" else 4)
    a = signed_measure(X, E)
    assert a.min() > 0
    if element == "quad4":
        assert quad_corners_convex(X, E)
    w = 2 * h  # default slot: the element columns beside x = 0
    assert abs(a.sum() - (L * D - w * A)) < TOL
    assert len(duplicate_coords(X)) == 0
    assert np.array_equal(np.unique(E), np.arange(len(X)))
    c = X[E].mean(axis=1)
    assert not np.any((np.abs(c[:, 0]) < w / 2) & (c[:, 1] < A))
    S = 0.9 * L
    for name, xy in (("support_left", (-S / 2, 0)), ("support_right", (S / 2, 0)), ("load", (0, D))):
        ids = group_nodes(G, name)
        assert len(ids) == 1 and np.allclose(X[ids[0], :2], xy, rtol=0, atol=1e-15)
    lig = group_nodes(G, "ligament")
    assert np.all(X[lig, 0] == 0) and X[lig, 1].min() == A and X[lig, 1].max() == D
    assert set(lig) == set(np.flatnonzero(X[:, 0] == 0))  # no node on x = 0 below the tip
    # a vertical chain of element edges from the notch tip to the top
    Ed = edges(E)
    chain = lig[np.argsort(X[lig, 1])]
    assert all((min(p, q), max(p, q)) in Ed for p, q in zip(chain[:-1], chain[1:]))


def test_notched_beam_mirror_symmetric_and_span():
    X, E, G = meshgen.notched_beam(1.0, 0.2, 0.07, 0.03, span=0.8)
    key = lambda P: set(map(tuple, np.round(P[:, :2], 12)))
    assert key(X * [-1, 1, 1]) == key(X)
    tri_key = lambda P: {frozenset(map(tuple, np.round(P[t, :2], 12))) for t in E}
    assert tri_key(X * [-1, 1, 1]) == tri_key(X)
    assert np.allclose(X[group_nodes(G, "support_right"), :2], [[0.4, 0.0]], atol=1e-15)
    assert np.any(X[:, 1] == 0.07)  # a grid line through the notch tip


def test_notched_beam_zero_width_cut():
    L, D, A, h = 0.4, 0.1, 0.04, 0.01
    X, E, G = meshgen.notched_beam(L, D, A, h, notch_width=0.0)
    a = signed_measure(X, E)
    assert a.min() > 0 and abs(a.sum() - L * D) < TOL
    dup = duplicate_coords(X)
    # the duplicates are exactly the two faces of the cut: x = 0, 0 <= y < A, twice each
    seam = np.flatnonzero((X[:, 0] == 0) & (X[:, 1] < A - 1e-12))
    assert set(dup) == set(seam) and len(seam) == 2 * round(A / h)  # y = 0 .. A - h, twice
    assert len(np.unique(X[seam], axis=0)) == len(seam) // 2
    c = X[E].mean(axis=1)
    left, right = set(np.unique(E[c[:, 0] < 0])), set(np.unique(E[c[:, 0] > 0]))
    shared = np.array(sorted(left & right))
    assert np.all(X[shared, 0] == 0) and X[shared, 1].min() == A
    assert set(group_nodes(G, "ligament")) == set(shared)


def test_notched_beam_rejects_bad_input():
    with pytest.raises(ValueError):
        meshgen.notched_beam(1.0, 0.2, 0.25, 0.02)  # notch deeper than the beam
    with pytest.raises(ValueError):
        meshgen.notched_beam(1.0, 0.2, 0.05, 0.02, element="tet4")


# ---- notched block ---------------------------------------------------------------------------

@pytest.mark.parametrize("width", [0.0, 0.04])
def test_notched_block_volume_and_disconnected_halves(width):
    lx, ly, lz, A, h = 0.4, 0.1, 0.04, 0.03, 0.01
    X, T, G = meshgen.notched_block_tet(lx, ly, lz, A, h, notch_width=width)
    v = signed_measure(X, T)
    assert v.min() > 0
    assert abs(v.sum() - (lx * ly * lz - width * A * lz)) < TOL
    assert np.array_equal(np.unique(T), np.arange(len(X)))
    dup = duplicate_coords(X)
    if width == 0:
        seam = np.flatnonzero((X[:, 0] == 0) & (X[:, 1] < A - 1e-12))
        assert set(dup) == set(seam) and len(seam) == 2 * round(A / h) * (round(lz / h) + 1)
        assert len(np.unique(X[seam], axis=0)) == len(seam) // 2
    else:
        assert len(dup) == 0
    c = X[T].mean(axis=1)
    left, right = set(np.unique(T[c[:, 0] < 0])), set(np.unique(T[c[:, 0] > 0]))
    assert len(left | right) == len(X)
    shared = np.array(sorted(left & right))
    assert np.all(X[shared, 0] == 0) and np.all(X[shared, 1] >= A)
    ligament = np.flatnonzero((X[:, 0] == 0) & (X[:, 1] >= A))
    assert set(shared) == set(ligament) == set(group_nodes(G, "ligament"))


def test_notched_block_without_notch_is_the_box_split():
    X, T, _ = meshgen.notched_block_tet(0.3, 0.08, 0.03, 0.0, 0.02)
    xs, ys, zs = (np.unique(X[:, k]) for k in range(3))
    Xb, Tb, _ = meshgen.box_tet_mesh_axes(xs, ys, zs)
    assert np.array_equal(X, Xb) and np.array_equal(T, Tb)


def test_notched_block_groups():
    lx, ly, lz, A, h = 0.3, 0.08, 0.03, 0.02, 0.01
    X, T, G = meshgen.notched_block_tet(lx, ly, lz, A, h)
    nz = round(lz / h) + 1
    S = 0.9 * lx
    for name, (x, y) in (("support_left", (-S / 2, 0)), ("support_right", (S / 2, 0)), ("load", (0, ly))):
        ids = group_nodes(G, name)
        assert len(ids) == nz
        assert np.allclose(X[ids, 0], x, atol=1e-15) and np.allclose(X[ids, 1], y, atol=1e-15)
        assert np.allclose(np.sort(X[ids, 2]), np.linspace(0, lz, nz))
        assert G[name].shape[1] == 3  # triangles: 2D groups of a 3D body


# ---- files and CLI --------------------------------------------------------------------------

@pytest.mark.parametrize("kind", ["disc", "beam_tri3", "beam_quad4", "block"])
def test_msh_roundtrip(tmp_path, kind):
    X, E, G = {
        "disc": lambda: meshgen.disc(1.0, 0.2),
        "beam_tri3": lambda: meshgen.notched_beam(1.0, 0.2, 0.05, 0.05),
        "beam_quad4": lambda: meshgen.notched_beam(1.0, 0.2, 0.05, 0.05, element="quad4"),
        "block": lambda: meshgen.notched_block_tet(0.4, 0.1, 0.05, 0.03, 0.025),
    }[kind]()
    path = tmp_path / "m.msh"
    meshgen.write_gmsh22(str(path), X, E, G)
    Y, by_type, sets = read_msh22(str(path))
    body_type = {3: 2, 4: 4 if kind == "block" else 3}[E.shape[1]]
    assert np.array_equal(Y, X)
    assert by_type[body_type] == E.tolist()
    assert set(sets) == {"body"} | set(G)
    for name in G:
        assert sets[name] == set(group_nodes(G, name).tolist())
    assert sets["body"] == set(range(len(X)))


def test_cli(tmp_path, capsys):
    cmds = {
        "d.msh": ["disc", "1.0", "0.25", "--flat", "40"],
        "b.msh": ["notched_beam", "1.0", "0.2", "0.05", "0.05", "--element", "quad4", "--span", "0.8"],
        "k.msh": ["notched_block", "0.4", "0.1", "0.05", "0.03", "0.025"],
    }
    for out, args in cmds.items():
        meshgen.main([*args, str(tmp_path / out)])
        assert f"wrote {tmp_path / out}" in capsys.readouterr().out
    X, by_type, sets = read_msh22(str(tmp_path / "d.msh"))
    assert set(sets) == {"body", "top", "bottom", "boundary"} and len(sets["top"]) == 3  # 15 deg apart
    X, by_type, sets = read_msh22(str(tmp_path / "b.msh"))
    assert 3 in by_type and np.allclose(X[sorted(sets["support_right"])][:, :2], [[0.4, 0.0]])
    X, by_type, sets = read_msh22(str(tmp_path / "k.msh"))
    assert 4 in by_type and {"support_left", "support_right", "load", "ligament"} <= set(sets)
    r = subprocess.run([sys.executable, "-m", "fracdem.meshgen", *cmds["d.msh"], str(tmp_path / "e.msh")],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert (tmp_path / "e.msh").read_text() == (tmp_path / "d.msh").read_text()

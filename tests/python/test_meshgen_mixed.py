"""Meshes of the mixed-mode and 3D fracture tests: meshgen.l_panel and notched_block_tet on a
graded x axis with a chosen number of cells through the thickness."""
import numpy as np
import pytest

from fracdem import meshgen


def tri_area(X, E):
    P = X[E]
    return 0.5 * np.cross(P[:, 1] - P[:, 0], P[:, 2] - P[:, 0])[:, 2]


def tet_volume(X, T):
    P = X[T]
    return np.einsum("ij,ij->i", np.cross(P[:, 1] - P[:, 0], P[:, 2] - P[:, 0]), P[:, 3] - P[:, 0]) / 6


def test_l_panel_area_orientation_and_groups():
    size, cut, h, off = 0.5, 0.25, 0.0125, 0.03
    X, E, G = meshgen.l_panel(size, cut, h, off)
    a = tri_area(X, E)
    assert a.min() > 0
    assert abs(a.sum() - (size ** 2 - cut ** 2)) < 1e-12
    assert np.array_equal(np.unique(E), np.arange(len(X)))
    c = X[E].mean(axis=1)
    assert not np.any((c[:, 0] > size - cut) & (c[:, 1] < cut))  # nothing in the cut-out
    load = np.unique(G["load"])
    assert len(load) == 1 and np.allclose(X[load[0], :2], [size - off, cut])
    bottom = np.unique(G["bottom"])
    assert np.allclose(X[bottom, 1], 0) and np.isclose(X[bottom, 0].max(), size - cut)
    assert len(bottom) == round((size - cut) / h) + 1


def test_l_panel_diagonals_alternate():
    X, E, _ = meshgen.l_panel(0.5, 0.25, 0.05, 0.03)
    P = X[E][:, :, :2]
    edges = np.concatenate([P[:, 1] - P[:, 0], P[:, 2] - P[:, 1], P[:, 0] - P[:, 2]])
    diagonal = edges[(np.abs(edges[:, 0]) > 1e-12) & (np.abs(edges[:, 1]) > 1e-12)]
    rising = np.sum(diagonal[:, 0] * diagonal[:, 1] > 0)
    assert 0.4 < rising / len(diagonal) < 0.6


def test_l_panel_rejects_bad_input():
    with pytest.raises(ValueError):
        meshgen.l_panel(0.5, 0.6, 0.01, 0.03)
    with pytest.raises(ValueError):
        meshgen.l_panel(0.5, 0.25, 0.01, 0.3)


def test_notched_block_graded_axis_and_thickness_cells():
    lx, ly, lz, a = 0.2, 0.1, 0.1, 0.05
    xs = np.array([-0.1, -0.06, -0.025, -0.0125, 0.0, 0.0125, 0.025, 0.06, 0.1])
    X, T, G = meshgen.notched_block_tet(lx, ly, lz, a, 0.0125, span=0.12, xs=xs, nz=4)
    v = tet_volume(X, T)
    assert v.min() > 0 and abs(v.sum() - lx * ly * lz) < 1e-12
    assert np.allclose(np.unique(X[:, 0]), xs)
    assert len(np.unique(X[:, 2])) == 5
    assert len(T) == 6 * (len(xs) - 1) * 8 * 4
    assert np.allclose(X[np.unique(G["support_left"]), 0], -0.06)


def test_capped_graded_axis_and_notched_beam_on_it():
    xs = meshgen.capped_graded_axis(0.06, 0.01, 0.4, 1.2, 0.04)
    assert np.allclose(xs, -xs[::-1]) and xs[0] == -0.4 and xs[-1] == 0.4
    d = np.diff(xs[len(xs) // 2:])
    assert np.allclose(d[:6], 0.01)  # uniform out to 60 mm
    assert d.max() <= 0.04 * 1.5 + 1e-12 and np.all(d[6:-1] >= d[5:-2] - 1e-12)  # grows, capped
    X, E, G = meshgen.notched_beam(0.8, 0.2, 0.1, 0.01, notch_width=0.0, span=0.8, xs=xs)
    assert np.allclose(np.unique(X[:, 0]), xs)
    assert len(E) == 2 * (len(xs) - 1) * 20
    assert np.allclose(X[G["support_left"].ravel(), :2], [-0.4, 0.0])

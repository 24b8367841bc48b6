"""fracdem.ceramic (the layered target of examples/ceramic_target): graded radii, meshes, crack-band
strength consistent with the example's meshes, Lanz-Odermatt limits."""
import math
import os
import re

import numpy as np
import pytest

from fracdem import ceramic

EXAMPLE = os.path.join(os.path.dirname(__file__), "..", "..", "examples", "ceramic_target")


@pytest.mark.parametrize("outer,h,r_fine,h_max", [(74e-3, 5e-3 / 3, 20e-3, None),
                                                  (74e-3, 5e-3 / 3, 20e-3, 20e-3 / 3),
                                                  (25e-3, 1.25e-3, 10e-3, 5e-3),
                                                  (25e-3, 1.25e-3, 10e-3, None)])
def test_radii_graded_without_slivers(outer, h, r_fine, h_max):
    r = ceramic.radii(outer, h, r_fine, h_max=h_max)
    d = np.diff(r)
    assert r[0] == 0 and r[-1] == pytest.approx(outer)
    assert np.allclose(d[: int(round(r_fine / h))], h)
    assert d.max() <= (h_max or 2 * h) * (1 + 1e-9)
    assert d.min() >= 0.5 * h  # no sliver cell at the rim (a 0.1 mm one eroded at set-up)


def test_target_meshes_positive_and_named(tmp_path):
    counts = ceramic.target_meshes(str(tmp_path), 2.5e-3)
    assert set(counts) == {"rod", "cover", "tile1", "tile2", "tile3", "backing"}
    for name in counts:
        text = (tmp_path / f"{name}.msh").read_text()
        for group in ("xmin", "xmax", "ymin", "ymax"):
            assert f'"{group}"' in text
    # tiles are tri3 (gmsh type 2), metals quad4 (type 3)
    assert " 2 2 1 1 " in (tmp_path / "tile1.msh").read_text()
    assert " 3 2 1 1 " in (tmp_path / "backing.msh").read_text()


def test_band_strength_meets_snapback_limit():
    for d in (0.3e-3, 1.77e-3, 3.53e-3):
        ft = ceramic.band_strength(ceramic.AD995, d)
        assert ft <= ceramic.AD995["FT"]
        assert d < 2 * ceramic.AD995["E"] * ceramic.AD995["GF"] / ft ** 2


def test_example_strength_fits_its_tile_meshes():
    """The default -var ft of in.ceramic_target passes the Rankine set-up's snap-back check on the
    committed tile meshes: every element narrower than 2 E G_F / f_t^2."""
    text = open(os.path.join(EXAMPLE, "in.ceramic_target")).read()
    ft = float(re.search(r"^variable\s+ft\s+index\s+(\S+)", text, re.M).group(1))
    gf = float(re.search(r"fracture_energy\s+(\S+)", text).group(1))
    assert gf == pytest.approx(ceramic.AD995["GF"], rel=1e-3)
    for k in (1, 2, 3):
        d = ceramic.largest_diameter(os.path.join(EXAMPLE, f"tile{k}.msh"))
        assert d < 2 * ceramic.AD995["E"] * gf / ft ** 2


def test_lanz_odermatt_limits():
    """Increasing with speed, and tending to the hydrodynamic limit a / tanh(b0 + b1 L/D)
    sqrt(rho_p / rho_t) L at high speed."""
    k = ceramic.LO_TUNGSTEN
    p = [ceramic.lanz_odermatt(v) for v in (800, 1325, 1800, 3000)]
    assert all(a < b for a, b in zip(p, p[1:]))
    limit = ceramic.ROD_L * k["a"] / math.tanh(k["b0"] + k["b1"] * ceramic.ROD_L / ceramic.ROD_D) * \
        math.sqrt(ceramic.WHA["rho"] / ceramic.RHA["rho"])
    assert ceramic.lanz_odermatt(1e6) == pytest.approx(limit, rel=1e-5)

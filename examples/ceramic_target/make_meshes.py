"""Writes the meshes of examples/ceramic_target: python3 make_meshes.py [H] (cell size near the axis, m)."""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python"))
from fracdem import ceramic  # noqa: E402

h = float(sys.argv[1]) if len(sys.argv) > 1 else 5e-3 / 3
here = os.path.dirname(os.path.abspath(__file__))
print(ceramic.target_meshes(here, h))
print({"rha_block": ceramic.rha_block_mesh(here, h)})
print(ceramic.plate_3d_meshes(here, 2.5e-3))
d = ceramic.largest_diameter(os.path.join(here, "tile1.msh"))
limit = ceramic.snapback_size(ceramic.AD995)
print(f"largest ceramic element {d * 1e3:.3f} mm; snap-back limit {limit * 1e3:.3f} mm; "
      f"strength its crack band carries: -var ft {ceramic.band_strength(ceramic.AD995, d):.4g}")

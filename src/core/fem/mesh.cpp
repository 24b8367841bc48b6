// Boundary extraction from mutable connectivity: facets owned by exactly one active element.
#include "fem/mesh.h"

#include <algorithm>
#include <tuple>

namespace fracdem
{

namespace
{
// Outward-oriented faces of a positively oriented tet (0,1,2,3): face k is opposite node 3-k.
const int kTetFaces[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
} // namespace

std::vector<Facet> boundary_facets(const Mesh& mesh)
{
  struct Entry {
    std::array<int, 3> key; // sorted node ids (third = -1 for edges)
    int elem, local;
  };
  std::vector<Entry> all;
  all.reserve(4 * mesh.conn.size());
  for (int e = 0; e < mesh.num_elems(); ++e) {
    if (!mesh.active[e]) continue;
    const auto& c = mesh.conn[e];
    if (mesh.etype[e] == ElemType::Tet4) {
      for (int k = 0; k < 4; ++k) {
        std::array<int, 3> key = {c[kTetFaces[k][0]], c[kTetFaces[k][1]], c[kTetFaces[k][2]]};
        std::sort(key.begin(), key.end());
        all.push_back({key, e, k});
      }
    } else {
      const int n = nodes_per_elem(mesh.etype[e]);
      for (int k = 0; k < n; ++k) {
        std::array<int, 3> key = {std::min(c[k], c[(k + 1) % n]), std::max(c[k], c[(k + 1) % n]),
                                  -1};
        all.push_back({key, e, k});
      }
    }
  }
  std::sort(all.begin(), all.end(), [](const Entry& a, const Entry& b) {
    return std::tie(a.key, a.elem, a.local) < std::tie(b.key, b.elem, b.local);
  });
  std::vector<Facet> out;
  for (size_t i = 0; i < all.size();) {
    size_t j = i + 1;
    while (j < all.size() && all[j].key == all[i].key)
      ++j;
    if (j == i + 1) {
      const Entry& en = all[i];
      const auto& c = mesh.conn[en.elem];
      Facet f;
      f.elem = en.elem;
      f.local_face = en.local;
      if (mesh.etype[en.elem] == ElemType::Tet4) {
        f.nn = 3;
        for (int q = 0; q < 3; ++q)
          f.n[q] = c[kTetFaces[en.local][q]];
      } else {
        const int n = nodes_per_elem(mesh.etype[en.elem]);
        f.nn = 2;
        f.n = {c[en.local], c[(en.local + 1) % n], -1};
      }
      out.push_back(f);
    }
    i = j;
  }
  std::sort(out.begin(), out.end(), [](const Facet& a, const Facet& b) {
    return std::tie(a.elem, a.local_face) < std::tie(b.elem, b.local_face);
  });
  return out;
}

} // namespace fracdem

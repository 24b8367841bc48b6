// Boundary extraction from mutable connectivity: facets owned by exactly one active element.
#include "fem/mesh.h"

#include <algorithm>
#include <cmath>
#include <tuple>

namespace fracdem
{

namespace
{
// Outward-oriented faces of a positively oriented tet (0,1,2,3): face k is opposite node 3-k.
const int kTetFaces[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
} // namespace

double tet_volume6(const double* X, const std::array<int, 4>& c)
{
  const double* a = &X[3 * c[0]];
  double u[3], v[3], w[3];
  for (int k = 0; k < 3; ++k) {
    u[k] = X[3 * c[1] + k] - a[k];
    v[k] = X[3 * c[2] + k] - a[k];
    w[k] = X[3 * c[3] + k] - a[k];
  }
  return u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) +
         u[2] * (v[0] * w[1] - v[1] * w[0]);
}

double signed_measure(const Mesh& m, int e)
{
  const auto& c = m.conn[e];
  if (m.etype[e] == ElemType::Tet4) return tet_volume6(m.X.data(), c) / 6.0;
  const int nn = nodes_per_elem(m.etype[e]);
  double a = 0; // shoelace formula
  for (int k = 0; k < nn; ++k) {
    const double* p = &m.X[3 * c[k]];
    const double* q = &m.X[3 * c[(k + 1) % nn]];
    a += p[0] * q[1] - q[0] * p[1];
  }
  return 0.5 * a;
}

int element_facet_keys(const Mesh& mesh, int e, std::array<int, 3>* keys)
{
  const auto& c = mesh.conn[e];
  if (mesh.etype[e] == ElemType::Tet4) {
    for (int k = 0; k < 4; ++k) {
      keys[k] = {c[kTetFaces[k][0]], c[kTetFaces[k][1]], c[kTetFaces[k][2]]};
      std::sort(keys[k].begin(), keys[k].end());
    }
    return 4;
  }
  const int n = nodes_per_elem(mesh.etype[e]);
  for (int k = 0; k < n; ++k)
    keys[k] = {std::min(c[k], c[(k + 1) % n]), std::max(c[k], c[(k + 1) % n]), -1};
  return n;
}

namespace
{
// Active elements around each node (CSR), ascending.
void active_stars(const Mesh& mesh, std::vector<int>& start, std::vector<int>& elems)
{
  start.assign(mesh.num_nodes() + 1, 0);
  for (int e = 0; e < mesh.num_elems(); ++e)
    if (mesh.active[e])
      for (int a = 0; a < nodes_per_elem(mesh.etype[e]); ++a)
        ++start[mesh.conn[e][a] + 1];
  for (int n = 0; n < mesh.num_nodes(); ++n)
    start[n + 1] += start[n];
  elems.resize(start.back());
  std::vector<int> fill(start.begin(), start.end() - 1);
  for (int e = 0; e < mesh.num_elems(); ++e)
    if (mesh.active[e])
      for (int a = 0; a < nodes_per_elem(mesh.etype[e]); ++a)
        elems[fill[mesh.conn[e][a]]++] = e;
}

bool uses_node(const Mesh& mesh, int e, int node)
{
  const auto& c = mesh.conn[e];
  return c[0] == node || c[1] == node || c[2] == node || c[3] == node;
}

// Another active element has the facet `key` (sorted nodes): it is among the elements around
// the facet's first node and uses the others too.
bool facet_shared(const Mesh& mesh, const std::vector<int>& start, const std::vector<int>& elems,
                  int e, const std::array<int, 3>& key)
{
  for (int i = start[key[0]]; i < start[key[0] + 1]; ++i) {
    const int f = elems[i];
    if (f != e && uses_node(mesh, f, key[1]) && (key[2] < 0 || uses_node(mesh, f, key[2])))
      return true;
  }
  return false;
}
} // namespace

// Each facet is looked up among the elements around its first node (a few to a few dozen)
// instead of sorting all facets: linear in the mesh, and the result comes out in element order.
std::vector<Facet> boundary_facets(const Mesh& mesh)
{
  std::vector<int> start, elems;
  active_stars(mesh, start, elems);
  std::vector<Facet> out;
  std::array<int, 3> keys[4];
  for (int e = 0; e < mesh.num_elems(); ++e) {
    if (!mesh.active[e]) continue;
    const auto& c = mesh.conn[e];
    const int nf = element_facet_keys(mesh, e, keys);
    for (int k = 0; k < nf; ++k) {
      if (facet_shared(mesh, start, elems, e, keys[k])) continue;
      Facet f;
      f.elem = e;
      f.local_face = k;
      if (mesh.etype[e] == ElemType::Tet4) {
        f.nn = 3;
        for (int q = 0; q < 3; ++q)
          f.n[q] = c[kTetFaces[k][q]];
      } else {
        f.nn = 2;
        f.n = {c[k], c[(k + 1) % nf], -1};
      }
      out.push_back(f);
    }
  }
  return out;
}

double facet_measure(const double* x, const Facet& fc)
{
  const double* a = &x[3 * fc.n[0]];
  const double* b = &x[3 * fc.n[1]];
  if (fc.nn == 2) return std::sqrt((b[0] - a[0]) * (b[0] - a[0]) + (b[1] - a[1]) * (b[1] - a[1]));
  const double* c = &x[3 * fc.n[2]];
  const double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  const double e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  const double cr[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                        e1[0] * e2[1] - e1[1] * e2[0]};
  return 0.5 * std::sqrt(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]);
}

double element_diameter(const Mesh& m, int e)
{
  const int n = nodes_per_elem(m.etype[e]);
  double d2 = 0;
  for (int a = 0; a < n; ++a)
    for (int b = a + 1; b < n; ++b) {
      const double* p = &m.X[3 * m.conn[e][a]];
      const double* q = &m.X[3 * m.conn[e][b]];
      d2 = std::max(d2, (p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) +
                            (p[2] - q[2]) * (p[2] - q[2]));
    }
  return std::sqrt(d2);
}

bool element_geometry_finite(const Mesh& m, int e)
{
  return std::isfinite(signed_measure(m, e)) && std::isfinite(element_diameter(m, e));
}

} // namespace fracdem

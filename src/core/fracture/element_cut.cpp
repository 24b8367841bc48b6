// Cracks through elements: the cut decision (plane through the crack point, minimum-size guard).
#include "fracture/element_cut.h"

#include "fem/edge_bisect.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace fracdem
{

namespace
{
// A cut must beat the best boundary by more than round-off: a boundary in the plane wins.
constexpr double kAlignmentMargin = 1e-9;

void diff(const double* x, int a, int b, double r[3])
{
  for (int d = 0; d < 3; ++d)
    r[d] = x[3 * b + d] - x[3 * a + d];
}
double dot(const double* a, const double* b)
{
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
double norm(const double* a)
{
  return std::sqrt(dot(a, a));
}

// The other nodes of element e (in connectivity order) around `node`.
int others(const Mesh& mesh, int e, int node, int o[3])
{
  int m = 0;
  for (int a = 0; a < nodes_per_elem(mesh.etype[e]); ++a)
    if (mesh.conn[e][a] != node && m < 3) o[m++] = mesh.conn[e][a];
  return m;
}

// 2D: |sin| of the angle between the line of unit direction-free normal n and edge (node, E):
// the cosine between n and the edge's normal. Only edges pointing along s (E - A . s > 0).
double best_edge_2d(const Mesh& mesh, const NodeStars& stars, const double* x, int node,
                    const double n[3], const double s[3])
{
  double best = 0;
  for (const int* e = stars.begin(node); e != stars.end(node); ++e) {
    const auto& c = mesh.conn[*e];
    const int k = nodes_per_elem(mesh.etype[*e]);
    int a = 0;
    while (c[a] != node)
      ++a;
    for (int nb : {c[(a + 1) % k], c[(a + k - 1) % k]}) { // the two edges at the node
      double r[3];
      diff(x, node, nb, r);
      const double l = norm(r);
      if (!(l > 0) || dot(r, s) <= 0) continue;
      best = std::max(best, std::fabs(r[0] * n[1] - r[1] * n[0]) / l);
    }
  }
  return best;
}

// 3D: the best |cos| between n and the normal of a face through the node.
double best_face_3d(const Mesh& mesh, const NodeStars& stars, const double* x, int node,
                    const double n[3])
{
  double best = 0;
  for (const int* e = stars.begin(node); e != stars.end(node); ++e) {
    int o[3];
    if (others(mesh, *e, node, o) != 3) continue;
    for (int i = 0; i < 3; ++i)
      for (int j = i + 1; j < 3; ++j) {
        double a[3], b[3];
        diff(x, node, o[i], a);
        diff(x, node, o[j], b);
        const double m[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                             a[0] * b[1] - a[1] * b[0]};
        const double l = norm(m);
        if (l > 0) best = std::max(best, std::fabs(dot(m, n)) / l);
      }
  }
  return best;
}

// Where the plane through x_node with normal m crosses edge bc: t in (0, 1), or -1.
double crossing(const double* x, int node, int b, int c, const double m[3])
{
  double rb[3], rc[3];
  diff(x, node, b, rb);
  diff(x, node, c, rc);
  const double db = dot(rb, m), dc = dot(rc, m);
  if (!(db * dc < 0)) return -1;
  return db / (db - dc);
}

ElementCut tri_cut(const Mesh& mesh, const NodeStars& stars, const double* x, int node, int e,
                   const double n[3])
{
  ElementCut cut;
  int o[3];
  if (mesh.etype[e] != ElemType::Tri3 || others(mesh, e, node, o) != 2) return cut;
  const double t = crossing(x, node, o[0], o[1], n);
  if (t < 0) return cut;
  double s[3];
  for (int d = 0; d < 3; ++d)
    s[d] = x[3 * o[0] + d] + t * (x[3 * o[1] + d] - x[3 * o[0] + d]) - x[3 * node + d];
  cut = {e, o[0], o[1], t, 1.0, best_edge_2d(mesh, stars, x, node, n, s), {}};
  return cut;
}

// quad4 A B C D counter-clockwise from the crack point A: the line leaves through BC or CD (a
// convex quad: exactly one of them changes sign), and P joins A.
ElementCut quad_cut(const Mesh& mesh, const NodeStars& stars, const double* x, int node, int e,
                    const double n[3])
{
  ElementCut cut;
  if (mesh.etype[e] != ElemType::Quad4) return cut;
  const auto& c = mesh.conn[e];
  int a = 0;
  while (c[a] != node)
    ++a;
  const int b = c[(a + 1) % 4], cc = c[(a + 2) % 4], d = c[(a + 3) % 4];
  const double t_bc = crossing(x, node, b, cc, n), t_cd = crossing(x, node, cc, d, n);
  if ((t_bc < 0) == (t_cd < 0)) return cut;
  const int u = t_bc >= 0 ? b : cc, w = t_bc >= 0 ? cc : d;
  const double t = t_bc >= 0 ? t_bc : t_cd;
  double s[3];
  for (int k = 0; k < 3; ++k)
    s[k] = x[3 * u + k] + t * (x[3 * w + k] - x[3 * u + k]) - x[3 * node + k];
  cut = {e, u, w, t, 1.0, best_edge_2d(mesh, stars, x, node, n, s), {}};
  cut.joins.push_back({e, node});
  return cut;
}

ElementCut tet_cut(const Mesh& mesh, const double* x, int node, int e, const double n[3],
                   double best_face)
{
  ElementCut cut;
  int o[3];
  if (mesh.etype[e] != ElemType::Tet4 || others(mesh, e, node, o) != 3) return cut;
  int ib = 0; // the node's edge most nearly in the failure plane
  double least = 2, dir[3] = {0, 0, 0};
  for (int i = 0; i < 3; ++i) {
    double r[3];
    diff(x, node, o[i], r);
    const double l = norm(r), c = l > 0 ? std::fabs(dot(r, n)) / l : 2;
    if (c < least) {
      least = c;
      ib = i;
      for (int d = 0; d < 3; ++d)
        dir[d] = r[d] / l;
    }
  }
  double m[3]; // n made orthogonal to the edge: the plane through it closest to the failure plane
  const double nd = dot(n, dir);
  for (int d = 0; d < 3; ++d)
    m[d] = n[d] - nd * dir[d];
  const double a = norm(m);
  if (!(a > 1e-12)) return cut;
  for (double& v : m)
    v /= a;
  const int c = o[(ib + 1) % 3], dn = o[(ib + 2) % 3];
  const double t = crossing(x, node, c, dn, m);
  if (t < 0) return cut;
  cut = {e, c, dn, t, a, best_face, {}};
  return cut;
}
} // namespace

namespace
{
// Whether every element around edge uw keeps min_size of its mesh element in both pieces (a tri3
// or tet4: t and 1 - t of it; a quad4: its tri3 and quad4 pieces, the quad4 convex, and the
// edge's pieces t and 1 - t >= min_size). Chooses the join of each quad4 neighbour (the cut's own
// quad joins the crack point) among its valid splits: the line P-far most nearly in the failure
// plane (x: current positions, n: unit normal), so that the crack can go on along it from P (the
// other would leave the plane running through the far node, across the quad piece's diagonal);
// the larger smaller piece among equals.
bool plan_pieces(const Mesh& mesh, const NodeStars& stars, const double* x, const double n[3],
                 ElementCut& cut, double min_size, const std::function<double(int)>& fraction)
{
  // The edge's pieces too, for every element type: a P close to an end would leave an edge far
  // shorter than its element (a small stable step) however large the pieces' areas.
  const double piece = std::min(cut.t, 1 - cut.t);
  if (piece < min_size) return false;
  double xp[3];
  for (int d = 0; d < 3; ++d)
    xp[d] = x[3 * cut.u + d] + cut.t * (x[3 * cut.w + d] - x[3 * cut.u + d]);
  for (int e : elements_on_edge(stars, cut.u, cut.w)) {
    const double whole = fraction ? fraction(e) : 1.0;
    if (mesh.etype[e] != ElemType::Quad4) {
      if (piece * whole < min_size) return false;
      continue;
    }
    int own = -1;
    for (const QuadJoin& j : cut.joins)
      if (j.elem == e) own = j.node;
    int best = -1;
    double best_off = 2, best_piece = -1;
    for (int k = 0; k < 4; ++k) {
      const int far = mesh.conn[e][k];
      if (far == cut.u || far == cut.w || (own >= 0 && far != own)) continue;
      const QuadSplitShape shape = quad_split_shape(mesh, e, cut.u, cut.w, cut.t, far);
      const double smaller = std::min(shape.tri_fraction, 1 - shape.tri_fraction);
      if (!shape.convex || smaller < min_size || smaller * whole < min_size) continue;
      double r[3];
      for (int d = 0; d < 3; ++d)
        r[d] = x[3 * far + d] - xp[d];
      const double l = norm(r), off = l > 0 ? std::fabs(dot(r, n)) / l : 2;
      if (off < best_off - 1e-12 || (off < best_off + 1e-12 && smaller > best_piece)) {
        best = far;
        best_off = off;
        best_piece = smaller;
      }
    }
    if (best < 0) return false;
    if (own < 0) cut.joins.push_back({e, best});
  }
  return true;
}
} // namespace

ElementCut find_element_cut(const Mesh& mesh, const NodeStars& stars, const double* x, int node,
                            const double n_in[3], double min_size,
                            const std::function<double(int)>& fraction)
{
  ElementCut best;
  double n[3] = {n_in[0], n_in[1], mesh.dim == 2 ? 0.0 : n_in[2]};
  const double l = norm(n);
  if (!(l > 0) || !(min_size > 0)) return best;
  for (double& v : n)
    v /= l;
  const double face = mesh.dim == 3 ? best_face_3d(mesh, stars, x, node, n) : 0.0;
  for (const int* e = stars.begin(node); e != stars.end(node); ++e) {
    ElementCut cut = mesh.dim == 3                       ? tet_cut(mesh, x, node, *e, n, face)
                     : mesh.etype[*e] == ElemType::Quad4 ? quad_cut(mesh, stars, x, node, *e, n)
                                                         : tri_cut(mesh, stars, x, node, *e, n);
    if (!cut.found() || !(cut.alignment > cut.boundary + kAlignmentMargin)) continue;
    if (best.found() && !(cut.alignment > best.alignment)) continue;
    if (!edge_bisectable(mesh, stars, cut.u, cut.w)) continue;
    if (!plan_pieces(mesh, stars, x, n, cut, min_size, fraction)) continue;
    best = cut;
  }
  return best;
}

} // namespace fracdem

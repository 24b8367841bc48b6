// Structured box (Tet4) and rectangle (Tri3/Quad4) mesh generators.
#include "io/mesh_generators.h"

#include <stdexcept>
#include <string>
#include <utility>

namespace fracdem
{

namespace
{

void check_count(int n, const char* what)
{
  if (n < 1)
    throw std::invalid_argument(std::string(what) + " must be >= 1, got " + std::to_string(n));
}
void check_length(double l, const char* what)
{
  if (!(l > 0.0))
    throw std::invalid_argument(std::string(what) + " must be > 0, got " + std::to_string(l));
}

} // namespace

Mesh make_box_tet_mesh(int nx, int ny, int nz, double lx, double ly, double lz,
                       const std::array<double, 3>& origin)
{
  check_count(nx, "nx");
  check_count(ny, "ny");
  check_count(nz, "nz");
  check_length(lx, "lx");
  check_length(ly, "ly");
  check_length(lz, "lz");
  Mesh m;
  m.dim = 3;
  const int px = nx + 1, py = ny + 1, pz = nz + 1;
  auto id = [&](int i, int j, int k) { return i + px * (j + py * k); };
  m.X.resize(3 * static_cast<std::size_t>(px) * py * pz);
  for (int k = 0; k < pz; ++k)
    for (int j = 0; j < py; ++j)
      for (int i = 0; i < px; ++i) {
        double* x = &m.X[3 * id(i, j, k)];
        // i == nx lands exactly on origin + l (no accumulated rounding).
        x[0] = origin[0] + lx * i / nx;
        x[1] = origin[1] + ly * j / ny;
        x[2] = origin[2] + lz * k / nz;
      }
  // Each of the 6 axis orders (a, b, c) gives the tet v0, v0+e_a, v0+e_a+e_b, v7.
  static const int perms[6][3] = {{0, 1, 2}, {1, 2, 0}, {2, 0, 1}, {0, 2, 1}, {2, 1, 0}, {1, 0, 2}};
  const std::size_t ne = 6 * static_cast<std::size_t>(nx) * ny * nz;
  m.conn.reserve(ne);
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        auto v = [&](int bits) {
          return id(i + (bits & 1), j + ((bits >> 1) & 1), k + ((bits >> 2) & 1));
        };
        for (const auto& p : perms) {
          const int b1 = 1 << p[0], b2 = b1 | (1 << p[1]);
          std::array<int, 4> c{{v(0), v(b1), v(b2), v(7)}};
          if (tet_volume6(m.X.data(), c) < 0) std::swap(c[2], c[3]); // odd axis orders
          m.conn.push_back(c);
        }
      }
  m.etype.assign(ne, ElemType::Tet4);
  m.active.assign(ne, 1);
  m.region.assign(ne, 0);
  auto& xmin = m.node_sets["xmin"];
  auto& xmax = m.node_sets["xmax"];
  auto& ymin = m.node_sets["ymin"];
  auto& ymax = m.node_sets["ymax"];
  auto& zmin = m.node_sets["zmin"];
  auto& zmax = m.node_sets["zmax"];
  // Increasing node index order keeps every set sorted.
  for (int k = 0; k < pz; ++k)
    for (int j = 0; j < py; ++j)
      for (int i = 0; i < px; ++i) {
        const int n = id(i, j, k);
        if (i == 0) xmin.push_back(n);
        if (i == nx) xmax.push_back(n);
        if (j == 0) ymin.push_back(n);
        if (j == ny) ymax.push_back(n);
        if (k == 0) zmin.push_back(n);
        if (k == nz) zmax.push_back(n);
      }
  return m;
}

Mesh make_rect_mesh(int nx, int ny, double lx, double ly, const std::array<double, 2>& origin,
                    ElemType type)
{
  check_count(nx, "nx");
  check_count(ny, "ny");
  check_length(lx, "lx");
  check_length(ly, "ly");
  if (type != ElemType::Tri3 && type != ElemType::Quad4)
    throw std::invalid_argument("make_rect_mesh: element type must be Tri3 or Quad4");
  Mesh m;
  m.dim = 2;
  const int px = nx + 1, py = ny + 1;
  auto id = [&](int i, int j) { return i + px * j; };
  m.X.assign(3 * static_cast<std::size_t>(px) * py, 0.0);
  for (int j = 0; j < py; ++j)
    for (int i = 0; i < px; ++i) {
      m.X[3 * id(i, j)] = origin[0] + lx * i / nx;
      m.X[3 * id(i, j) + 1] = origin[1] + ly * j / ny;
    }
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const int a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
      if (type == ElemType::Quad4) {
        m.conn.push_back({{a, b, c, d}});
        m.etype.push_back(ElemType::Quad4);
      } else {
        m.conn.push_back({{a, b, c, -1}});
        m.conn.push_back({{a, c, d, -1}});
        m.etype.insert(m.etype.end(), 2, ElemType::Tri3);
      }
    }
  m.active.assign(m.conn.size(), 1);
  m.region.assign(m.conn.size(), 0);
  auto& xmin = m.node_sets["xmin"];
  auto& xmax = m.node_sets["xmax"];
  auto& ymin = m.node_sets["ymin"];
  auto& ymax = m.node_sets["ymax"];
  for (int j = 0; j < py; ++j)
    for (int i = 0; i < px; ++i) {
      const int n = id(i, j);
      if (i == 0) xmin.push_back(n);
      if (i == nx) xmax.push_back(n);
      if (j == 0) ymin.push_back(n);
      if (j == ny) ymax.push_back(n);
    }
  return m;
}

} // namespace fracdem

// Shared helpers of the unit tests: per-test scratch directories, independent element-measure
// oracles (written apart from the library's own, so that tests check it rather than echo it) and
// grid graphs for the partitioners.
#pragma once

#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <sstream>
#include <fstream>
#include <string>
#include <system_error>
#include <vector>

#include "balance/graph_partition.h"
#include "body/body_partition.h"
#include "contact/particle_facet.h"
#include "fem/mesh.h"
#include "materials/material.h"

namespace fracdem_test
{

// A fresh directory per test (pid + test name, so parallel ctest runs do not collide).
inline std::filesystem::path make_test_dir()
{
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::filesystem::path d =
      std::filesystem::temp_directory_path() / ("fracdem_io_" + std::to_string(::getpid()) + "_" +
                                                info->test_suite_name() + "_" + info->name());
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d;
}

// Fixture owning such a directory; removed afterwards unless the test failed.
class TempDirTest : public ::testing::Test
{
protected:
  void SetUp() override { dir_ = make_test_dir(); }
  void TearDown() override
  {
    std::error_code ec;
    if (!HasFailure()) std::filesystem::remove_all(dir_, ec);
  }
  std::string write_file(const std::string& name, const std::string& text) const
  {
    const std::filesystem::path p = dir_ / name;
    std::ofstream(p, std::ios::binary) << text;
    return p.string();
  }
  std::filesystem::path dir_;
};

// Signed volume of tet element e (positive for the library's orientation convention).
inline double tet_volume(const fracdem::Mesh& m, int e)
{
  const auto& c = m.conn[e];
  const double* a = &m.X[3 * c[0]];
  double u[3], v[3], w[3];
  for (int k = 0; k < 3; ++k) {
    u[k] = m.X[3 * c[1] + k] - a[k];
    v[k] = m.X[3 * c[2] + k] - a[k];
    w[k] = m.X[3 * c[3] + k] - a[k];
  }
  return (u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) +
          u[2] * (v[0] * w[1] - v[1] * w[0])) /
         6.0;
}

// Signed area of a 2D element in the x-y plane (positive counter-clockwise).
inline double signed_area(const fracdem::Mesh& m, int e)
{
  const auto& c = m.conn[e];
  const int nn = fracdem::nodes_per_elem(m.etype[e]);
  double a = 0;
  for (int k = 0; k < nn; ++k) {
    const double* p = &m.X[3 * c[k]];
    const double* q = &m.X[3 * c[(k + 1) % nn]];
    a += p[0] * q[1] - q[0] * p[1];
  }
  return 0.5 * a;
}

// nx x ny grid graph with unit edges; unit vertex weights unless given (one per vertex).
inline fracdem::balance::Graph grid_graph(int nx, int ny, std::vector<int64_t> vertex_weight = {})
{
  std::vector<fracdem::balance::WeightedPair> pairs;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const int v = j * nx + i;
      if (i + 1 < nx) pairs.push_back({v, v + 1, 1});
      if (j + 1 < ny) pairs.push_back({v, v + nx, 1});
    }
  if (vertex_weight.empty()) vertex_weight.assign(int64_t(nx) * ny, 1);
  return fracdem::balance::build_graph(int64_t(nx) * ny, vertex_weight, pairs);
}

// One sphere (radius, position x, velocity v) as host particle arrays with 4 history slots.
struct OneParticle {
  double x[3], v[3] = {0, 0, 0}, omega[3] = {0, 0, 0}, f[3] = {0, 0, 0}, t[3] = {0, 0, 0};
  double* px[1] = {x};
  double* pv[1] = {v};
  double* po[1] = {omega};
  double* pf[1] = {f};
  double* pt[1] = {t};
  double radius, mass = 1.0;
  int type = 1, mask = 1;
  std::vector<double> hist = std::vector<double>(4 * fracdem::kHistorySlotDoubles, -1.0);
  double* ph[1] = {hist.data()};
  fracdem::ParticleArrays arrays()
  {
    fracdem::ParticleArrays p;
    p.n = 1;
    p.x = px;
    p.v = pv;
    p.omega = po;
    p.f = pf;
    p.torque = pt;
    p.radius = &radius;
    p.rmass = &mass;
    p.type = &type;
    p.mask = &mask;
    p.groupbit = 1;
    p.history = ph;
    p.slots = 4;
    return p;
  }
};

// A command line split at blanks (as a host hands a fix its words).
inline std::vector<std::string> split(const std::string& line)
{
  std::istringstream in(line);
  std::vector<std::string> words;
  for (std::string w; in >> w;)
    words.push_back(w);
  return words;
}

// Structural steel, small-strain elastic (E 200 GPa, nu 0.3, 7800 kg/m^3).
inline fracdem::Material steel()
{
  fracdem::Material m;
  m.E = 2e11;
  m.nu = 0.3;
  m.rho = 7800;
  return m;
}

// The 3-vectors of a part's nodes (in its local order) taken from a whole body's (global order).
inline std::vector<double> part_vectors(const fracdem::MeshPart& part,
                                        const std::vector<double>& whole)
{
  std::vector<double> out;
  for (int g : part.global_node)
    out.insert(out.end(), &whole[3 * g], &whole[3 * g] + 3);
  return out;
}

// Every part's box (box_of(p): what a rank would all-gather) concatenated in part order and
// handed to every part's ghosts, as the MPI_Allgather of the box exchange does.
template <class Ghosts, class BoxOf> void exchange_boxes(std::vector<Ghosts>& ghosts, BoxOf box_of)
{
  std::vector<double> all;
  for (size_t p = 0; p < ghosts.size(); ++p) {
    const std::vector<double> b = box_of(static_cast<int>(p));
    all.insert(all.end(), b.begin(), b.end());
  }
  for (Ghosts& g : ghosts)
    g.set_boxes(all);
}

} // namespace fracdem_test

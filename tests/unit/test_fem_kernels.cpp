// Unit tests of the FE kernels: patch tests, rigid motions, masses, energy consistency, dt safety.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "fem/fe_space.h"
#include "io/mesh_generators.h"

using namespace fracdem;

namespace
{

Material steel(Kinematics k = Kinematics::SmallStrain)
{
  Material m;
  m.E = 2e11;
  m.nu = 0.3;
  m.rho = 7800;
  m.kinematics = k;
  return m;
}

// Applies x = X + G X (linear field) and returns the internal forces.
std::vector<double> forces_for_gradient(const Mesh& mesh, const FeSpace& fs, const double G[9],
                                        double* energy = nullptr)
{
  std::vector<double> x(mesh.X), f(mesh.X.size(), 0.0);
  for (int n = 0; n < mesh.num_nodes(); ++n)
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        x[3 * n + i] += G[3 * i + j] * mesh.X[3 * n + j];
  int inv = -1;
  double e = fs.add_internal_forces(mesh, x.data(), 0, mesh.num_elems(), f.data(), nullptr, &inv);
  if (energy) *energy = e;
  EXPECT_EQ(inv, -1);
  return f;
}

bool on_boundary(const Mesh& mesh, int n)
{
  for (const auto& kv : mesh.node_sets)
    for (int k : kv.second)
      if (k == n) return true;
  return false;
}

} // namespace

TEST(FemKernels, Tet4PatchTestInteriorForcesVanishAndStressIsExact)
{
  Mesh mesh = make_box_tet_mesh(3, 3, 3, 1.0, 1.0, 1.0);
  for (Kinematics k : {Kinematics::SmallStrain, Kinematics::Corotational}) {
    FeSpace fs;
    fs.build(mesh, steel(k));
    const double G[9] = {1e-4, 2e-5, 0, 2e-5, -3e-5, 1e-5, 0, 1e-5, 5e-5}; // symmetric: pure strain
    std::vector<double> f = forces_for_gradient(mesh, fs, G);
    const double scale = 2e11 * 1e-4 * (1.0 / 9.0);
    for (int n = 0; n < mesh.num_nodes(); ++n)
      if (!on_boundary(mesh, n))
        for (int d = 0; d < 3; ++d)
          EXPECT_NEAR(f[3 * n + d], 0.0, 1e-6 * scale) << "node " << n;
    std::vector<double> x(mesh.X);
    for (int n = 0; n < mesh.num_nodes(); ++n)
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
          x[3 * n + i] += G[3 * i + j] * mesh.X[3 * n + j];
    const double lam = steel().lambda(), mu = steel().mu(), tr = 1e-4 - 3e-5 + 5e-5;
    double s[6];
    fs.element_stress(mesh, x.data(), 7, s);
    EXPECT_NEAR(s[0], lam * tr + 2 * mu * 1e-4, 1e-3 * mu * 1e-4);
    EXPECT_NEAR(s[3], 2 * mu * 2e-5, 1e-3 * mu * 1e-4);
    EXPECT_NEAR(s[4], 2 * mu * 1e-5, 1e-3 * mu * 1e-4);
  }
}

TEST(FemKernels, CorotationalIsExactlyInvariantUnderLargeRotation)
{
  Mesh mesh = make_box_tet_mesh(2, 2, 2, 1.0, 0.5, 0.3);
  FeSpace fs;
  fs.build(mesh, steel(Kinematics::Corotational));
  const double a = 60.0 * M_PI / 180.0;
  // rotation about (1,1,1)/sqrt(3) by 60 degrees, plus a translation
  const double k[3] = {1 / std::sqrt(3.0), 1 / std::sqrt(3.0), 1 / std::sqrt(3.0)};
  std::vector<double> x(mesh.X.size()), f(mesh.X.size(), 0.0);
  for (int n = 0; n < mesh.num_nodes(); ++n) {
    const double* p = &mesh.X[3 * n];
    const double kp = k[0] * p[0] + k[1] * p[1] + k[2] * p[2];
    const double kxp[3] = {k[1] * p[2] - k[2] * p[1], k[2] * p[0] - k[0] * p[2],
                           k[0] * p[1] - k[1] * p[0]};
    for (int d = 0; d < 3; ++d)
      x[3 * n + d] =
          p[d] * std::cos(a) + kxp[d] * std::sin(a) + k[d] * kp * (1 - std::cos(a)) + 0.7;
  }
  int inv = -1;
  const double e =
      fs.add_internal_forces(mesh, x.data(), 0, mesh.num_elems(), f.data(), nullptr, &inv);
  EXPECT_NEAR(e, 0.0, 1e-6);
  for (double v : f)
    EXPECT_NEAR(v, 0.0, 1e-3); // forces of order E * 1e-14 * area
  // small strain sees the rotation as strain: a large spurious energy
  FeSpace lin;
  lin.build(mesh, steel());
  std::fill(f.begin(), f.end(), 0.0);
  EXPECT_GT(lin.add_internal_forces(mesh, x.data(), 0, mesh.num_elems(), f.data(), nullptr, &inv),
            1e8);
}

TEST(FemKernels, ForcesAreMinusEnergyGradient)
{
  for (ElemType t : {ElemType::Tet4, ElemType::Tri3, ElemType::Quad4}) {
    for (Kinematics kin : {Kinematics::SmallStrain, Kinematics::Corotational}) {
      for (PlaneMode pm : {PlaneMode::PlaneStrain, PlaneMode::Axisymmetric}) {
        if (t == ElemType::Tet4 && pm == PlaneMode::Axisymmetric) continue;
        Mesh mesh = t == ElemType::Tet4 ? make_box_tet_mesh(1, 1, 1, 1, 1, 1)
                                        : make_rect_mesh(2, 1, 1.0, 0.5, {0.2, 0.0}, t);
        Material m = steel(kin);
        m.E = 1.0;
        m.plane = pm;
        FeSpace fs;
        fs.build(mesh, m);
        std::mt19937 rng(7);
        std::uniform_real_distribution<double> U(-0.05, 0.05);
        std::vector<double> x(mesh.X);
        for (size_t k = 0; k < x.size(); ++k)
          if (mesh.dim == 3 || k % 3 != 2) x[k] += U(rng);
        std::vector<double> f(x.size(), 0.0), scratch(x.size());
        int inv = -1;
        fs.add_internal_forces(mesh, x.data(), 0, mesh.num_elems(), f.data(), nullptr, &inv);
        const double h = 1e-6;
        for (size_t k = 0; k < x.size(); ++k) {
          if (mesh.dim == 2 && k % 3 == 2) continue;
          std::vector<double> xp(x), xm(x);
          xp[k] += h;
          xm[k] -= h;
          const double ep = fs.add_internal_forces(mesh, xp.data(), 0, mesh.num_elems(),
                                                   scratch.data(), nullptr, &inv);
          const double em = fs.add_internal_forces(mesh, xm.data(), 0, mesh.num_elems(),
                                                   scratch.data(), nullptr, &inv);
          EXPECT_NEAR(f[k], -(ep - em) / (2 * h), 1e-6 + 1e-5 * std::fabs(f[k]))
              << "type " << int(t) << " kin " << int(kin) << " mode " << int(pm) << " dof " << k;
        }
      }
    }
  }
}

TEST(FemKernels, LumpedMassTotals)
{
  Mesh box = make_box_tet_mesh(3, 2, 2, 0.3, 0.2, 0.1);
  FeSpace fs;
  Material m = steel();
  fs.build(box, m);
  std::vector<double> mass;
  fs.lumped_masses(box, mass);
  double total = 0;
  for (double v : mass)
    total += v;
  EXPECT_NEAR(total, 7800 * 0.3 * 0.2 * 0.1, 1e-9);
  for (ElemType t : {ElemType::Tri3, ElemType::Quad4}) {
    Mesh rect = make_rect_mesh(4, 3, 0.4, 0.3, {0.1, 0.0}, t);
    m.thickness = 0.05;
    m.plane = PlaneMode::PlaneStrain;
    fs.build(rect, m);
    fs.lumped_masses(rect, mass);
    total = 0;
    for (double v : mass)
      total += v;
    EXPECT_NEAR(total, 7800 * 0.4 * 0.3 * 0.05, 1e-9);
    m.plane = PlaneMode::Axisymmetric; // ring r in [0.1, 0.5], height 0.3
    fs.build(rect, m);
    fs.lumped_masses(rect, mass);
    total = 0;
    for (double v : mass)
      total += v;
    EXPECT_NEAR(total, 7800 * M_PI * (0.5 * 0.5 - 0.1 * 0.1) * 0.3, 1e-8 * total);
  }
}

TEST(FemKernels, StableTimeStepIsSafeAndNotOverlyConservative)
{
  // Largest eigenfrequency of M^-1 K by power iteration on the assembled system.
  for (ElemType t : {ElemType::Tet4, ElemType::Tri3, ElemType::Quad4}) {
    Mesh mesh = t == ElemType::Tet4 ? make_box_tet_mesh(3, 2, 2, 0.3, 0.2, 0.2)
                                    : make_rect_mesh(4, 3, 0.4, 0.3, {0, 0}, t);
    FeSpace fs;
    fs.build(mesh, steel());
    std::vector<double> m;
    fs.lumped_masses(mesh, m);
    std::vector<double> u(mesh.X.size()), f(mesh.X.size());
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> U(-1, 1);
    for (auto& v : u)
      v = U(rng);
    double lam = 0;
    int inv = -1;
    for (int it = 0; it < 3000; ++it) {
      std::vector<double> x(mesh.X);
      for (size_t k = 0; k < x.size(); ++k)
        x[k] += 1e-9 * u[k];
      std::fill(f.begin(), f.end(), 0.0);
      fs.add_internal_forces(mesh, x.data(), 0, mesh.num_elems(), f.data(), nullptr, &inv);
      double norm = 0;
      for (size_t k = 0; k < u.size(); ++k) {
        if (mesh.dim == 2 && k % 3 == 2) {
          u[k] = 0;
          continue;
        }
        u[k] = -f[k] / (1e-9 * m[k / 3]);
        norm += u[k] * u[k];
      }
      norm = std::sqrt(norm);
      lam = norm;
      for (auto& v : u)
        v /= norm;
    }
    const double dt_exact = 2.0 / std::sqrt(lam);
    const double dt = fs.stable_time_step(mesh, mesh.X.data());
    EXPECT_LE(dt, dt_exact * (1 + 1e-6)) << "type " << int(t);
    EXPECT_GE(dt, 0.3 * dt_exact) << "type " << int(t);
  }
}

TEST(FemKernels, InvertedAndDegenerateElementsAreRefused)
{
  Mesh mesh = make_box_tet_mesh(1, 1, 1, 1, 1, 1);
  std::swap(mesh.conn[2][1], mesh.conn[2][2]);
  FeSpace fs;
  try {
    fs.build(mesh, steel());
    FAIL() << "inverted element accepted";
  } catch (const FeError& e) {
    EXPECT_EQ(e.elem, 2);
    EXPECT_NE(std::string(e.what()).find("inverted"), std::string::npos);
  }
}

TEST(FemKernels, BoundaryFacetsAreOutwardAndEncloseTheVolume)
{
  Mesh mesh = make_box_tet_mesh(3, 2, 2, 0.3, 0.2, 0.2);
  auto facets = boundary_facets(mesh);
  EXPECT_EQ(facets.size(), 2u * 2 * (3 * 2 + 2 * 2 + 3 * 2));
  double vol = 0, nsum[3] = {0, 0, 0};
  for (const Facet& f : facets) {
    const double* a = &mesh.X[3 * f.n[0]];
    const double* b = &mesh.X[3 * f.n[1]];
    const double* c = &mesh.X[3 * f.n[2]];
    const double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]},
                 e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    const double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                         e1[0] * e2[1] - e1[1] * e2[0]};
    for (int d = 0; d < 3; ++d)
      nsum[d] += n[d];
    vol += (a[0] * n[0] + a[1] * n[1] + a[2] * n[2]) / 6.0; // divergence theorem
  }
  EXPECT_NEAR(vol, 0.3 * 0.2 * 0.2, 1e-12);
  for (double v : nsum)
    EXPECT_NEAR(v, 0.0, 1e-12);
  mesh.active[0] = 0; // erosion exposes new facets
  EXPECT_GT(boundary_facets(mesh).size(), facets.size() - 4);
}

TEST(FemKernels, VonMisesOfUniaxialStress)
{
  const double s[6] = {5.0, 0, 0, 0, 0, 0};
  EXPECT_DOUBLE_EQ(FeSpace::von_mises(s), 5.0);
  const double shear[6] = {0, 0, 0, 2.0, 0, 0};
  EXPECT_NEAR(FeSpace::von_mises(shear), 2.0 * std::sqrt(3.0), 1e-12);
}

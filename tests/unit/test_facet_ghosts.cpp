// Unit tests of a distributed body's facet ghosts: the facets chosen by particle boxes against a
// brute-force distance check, and three parts stepped in one process (messages routed by hand)
// against the replicated contact of the whole body: forces returned once, sums equal.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "body/body_partition.h"
#include "body/facet_ghosts.h"
#include "contact/geometry.h"
#include "contact/granular_law.h"
#include "contact/particle_facet.h"
#include "io/mesh_generators.h"
#include "test_support.h"

using namespace fracdem;

namespace
{

// Particles as the host lays them out (rows), with their history.
struct Swarm {
  int n = 0;
  std::vector<double> xs, vs, ws, fs, ts, hs, radius, mass;
  std::vector<int> type, mask;
  std::vector<double*> x, v, w, f, t, h;
  static constexpr int kSlots = 4;

  void add(const double at[3], const double vel[3], double r)
  {
    xs.insert(xs.end(), at, at + 3);
    vs.insert(vs.end(), vel, vel + 3);
    ws.insert(ws.end(), {0.0, 0.0, 0.0});
    radius.push_back(r);
    mass.push_back(7800 * 4.18879 * r * r * r);
    type.push_back(1);
    mask.push_back(1);
    ++n;
  }
  ParticleArrays arrays()
  {
    fs.assign(3 * n, 0.0);
    ts.assign(3 * n, 0.0);
    if (hs.empty()) {
      hs.assign(static_cast<size_t>(n) * kSlots * kHistorySlotDoubles, 0.0);
      for (int i = 0; i < n; ++i)
        clear_history_row(&hs[static_cast<size_t>(i) * kSlots * kHistorySlotDoubles], kSlots);
    }
    x.resize(n), v.resize(n), w.resize(n), f.resize(n), t.resize(n), h.resize(n);
    for (int i = 0; i < n; ++i) {
      x[i] = &xs[3 * i], v[i] = &vs[3 * i], w[i] = &ws[3 * i];
      f[i] = &fs[3 * i], t[i] = &ts[3 * i];
      h[i] = &hs[static_cast<size_t>(i) * kSlots * kHistorySlotDoubles];
    }
    ParticleArrays p;
    p.n = n;
    p.x = x.data(), p.v = v.data(), p.omega = w.data(), p.f = f.data(), p.torque = t.data();
    p.radius = radius.data(), p.rmass = mass.data(), p.type = type.data(), p.mask = mask.data();
    p.history = h.data();
    p.slots = kSlots;
    return p;
  }
};

ParticleFacetOptions options(bool patch)
{
  ParticleFacetOptions opt;
  opt.buffer = 0.004;
  opt.hertz_patch = patch;
  return opt;
}

std::vector<ContactMaterial> materials()
{
  return {ContactMaterial{}, mix_materials(1e8, 0.3, 0, 0, 0.9, 0.5, 1, NormalModel::Hertz, true)};
}

// Distance from q to facet f at positions x.
double facet_distance(const Facet& f, const double* x, const double q[3])
{
  const ClosestPoint cp =
      f.nn == 3 ? closest_point_triangle(q, &x[3 * f.n[0]], &x[3 * f.n[1]], &x[3 * f.n[2]])
                : closest_point_segment(q, &x[3 * f.n[0]], &x[3 * f.n[1]]);
  return std::sqrt(cp.dist2);
}

} // namespace

TEST(FacetGhosts, BoxesKeepEveryFacetWithinReachOfTheirParticles)
{
  // Random particles around a tet box: every facet within radius + reach of a particle (brute
  // force over all pairs) lies in the particle box's selection.
  const Mesh mesh = make_box_tet_mesh(8, 6, 4, 0.2, 0.15, 0.1);
  const std::vector<Facet> facets = boundary_facets(mesh);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-0.05, 0.25), ur(0.002, 0.01);
  for (int trial = 0; trial < 20; ++trial) {
    Swarm s;
    const int n = 1 + trial % 5;
    for (int i = 0; i < n; ++i) {
      const double at[3] = {u(rng), 0.75 * u(rng), 0.5 * u(rng)}, zero[3] = {0, 0, 0};
      s.add(at, zero, ur(rng));
    }
    const ParticleArrays p = s.arrays();
    const double extra = 0.003;
    double rmax = 0;
    for (int i = 0; i < n; ++i)
      rmax = std::max(rmax, s.radius[i]);
    const std::vector<int> picked =
        facets_in_box(facets, mesh.X.data(), particle_box(p, rmax + extra));
    int within = 0;
    for (size_t f = 0; f < facets.size(); ++f)
      for (int i = 0; i < n; ++i)
        if (facet_distance(facets[f], mesh.X.data(), p.x[i]) < s.radius[i] + extra) {
          ++within;
          EXPECT_TRUE(std::binary_search(picked.begin(), picked.end(), static_cast<int>(f)))
              << "trial " << trial << ": facet " << f << " within reach of particle " << i;
          break;
        }
    EXPECT_GE(picked.size(), static_cast<size_t>(within));
  }
}

namespace
{

// Three parts (ranks) and their particles in one process: every message routed by hand.
struct Parts {
  Mesh mesh;
  std::vector<MeshPart> parts;
  std::vector<FacetGhosts> ghosts;
  std::vector<std::vector<double>> f_part;

  Parts(const Mesh& m, int nparts, bool patch) : mesh(m), ghosts(nparts)
  {
    const std::vector<int> elem_part = partition_elements(mesh, nparts);
    for (int p = 0; p < nparts; ++p) {
      parts.push_back(extract_part(mesh, elem_part, p));
      ghosts[p].init(parts[p], global_surface(mesh, elem_part));
      ghosts[p].configure(options(patch), materials());
    }
  }
  std::vector<double> local(const std::vector<double>& whole, int p) const
  {
    return fracdem_test::part_vectors(parts[p], whole);
  }
  // One step: boxes (when asked), facets out, contact, forces back.
  std::vector<ParticleFacetResult> step(std::vector<ParticleArrays>& ps,
                                        const std::vector<double>& x, const std::vector<double>& v,
                                        bool boxes)
  {
    const int np = static_cast<int>(parts.size());
    std::vector<std::vector<double>> xp(np), vp(np);
    for (int p = 0; p < np; ++p)
      xp[p] = local(x, p), vp[p] = local(v, p);
    if (boxes)
      fracdem_test::exchange_boxes(
          ghosts, [&](int p) { return ghosts[p].local_boxes(ps[p], xp[p].data()); });
    std::vector<std::vector<std::vector<double>>> out(np), in(np), back(np), ret(np);
    for (int p = 0; p < np; ++p) {
      EXPECT_EQ(ghosts[p].check_particles(ps[p]), "");
      EXPECT_EQ(ghosts[p].outgoing(xp[p].data(), vp[p].data(), out[p]), "");
    }
    route(out, in, false);
    std::vector<ParticleFacetResult> res(np);
    f_part.assign(np, {});
    for (int p = 0; p < np; ++p) {
      f_part[p].assign(xp[p].size(), 0.0);
      res[p] = ghosts[p].evaluate(ps[p], in[p], xp[p].data(), vp[p].data(), 1e-6, f_part[p].data(),
                                  back[p]);
    }
    route(back, ret, true);
    for (int p = 0; p < np; ++p)
      ghosts[p].add_returned(ret[p], f_part[p].data());
    return res;
  }
  // Round 0: p -> send_to; round 1 (back): q -> recv_from. Each side lists the other.
  void route(const std::vector<std::vector<std::vector<double>>>& out,
             std::vector<std::vector<std::vector<double>>>& in, bool back)
  {
    const int np = static_cast<int>(parts.size());
    for (int q = 0; q < np; ++q) {
      const std::vector<int>& from = back ? ghosts[q].send_to() : ghosts[q].recv_from();
      in[q].assign(from.size(), {});
      for (size_t k = 0; k < from.size(); ++k) {
        const int p = from[k];
        const std::vector<int>& to = back ? ghosts[p].recv_from() : ghosts[p].send_to();
        auto it = std::find(to.begin(), to.end(), q);
        ASSERT_NE(it, to.end()) << p << " does not list " << q;
        in[q][k] = out[p][it - to.begin()];
      }
    }
  }
};

// The whole body's nodal forces from the parts' (each node's force on exactly one part before
// the shared-node sum: their plain sum is the total).
std::vector<double> gathered(const Parts& parts, int nnodes)
{
  std::vector<double> f(3 * nnodes, 0.0);
  for (size_t p = 0; p < parts.parts.size(); ++p)
    for (int n = 0; n < parts.parts[p].num_nodes(); ++n)
      for (int d = 0; d < 3; ++d)
        f[3 * parts.parts[p].global_node[n] + d] += parts.f_part[p][3 * n + d];
  return f;
}

void run_against_replicated(bool patch)
{
  // A deformed, moving tet block hit on its top by particles spread over three "ranks" (by x, not
  // by the body's parts): per particle force and torque, per node force and the contact count of
  // the parts equal the whole body's; every node's force is returned to one part only (the sum of
  // all nodal forces balances the particles').
  const Mesh mesh = make_box_tet_mesh(8, 6, 3, 0.2, 0.15, 0.06);
  const int nn = mesh.num_nodes();
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> jitter(-1e-4, 1e-4), u(0, 1);
  std::vector<double> x = mesh.X, v(3 * nn);
  for (int k = 0; k < 3 * nn; ++k)
    x[k] += jitter(rng), v[k] = 100 * jitter(rng);
  Parts parts(mesh, 3, patch);
  const int nranks = 3;
  std::vector<Swarm> dist(nranks), repl(nranks);
  for (int i = 0; i < 24; ++i) {
    const double r = 0.006 + 0.004 * u(rng);
    const double at[3] = {0.2 * u(rng), 0.15 * u(rng), 0.06 + r - 0.0015 * u(rng)};
    const double vel[3] = {u(rng) - 0.5, u(rng) - 0.5, -1.0};
    const int rank = std::min(nranks - 1, static_cast<int>(at[0] / 0.2 * nranks));
    dist[rank].add(at, vel, r);
    repl[rank].add(at, vel, r);
  }
  std::vector<ParticleFacetContact> whole(nranks); // each rank's replica of the whole body
  for (ParticleFacetContact& c : whole) {
    c.configure(options(patch));
    c.set_materials(materials());
    c.rebuild_surface(mesh);
  }
  for (int step = 0; step < 3; ++step) {
    std::vector<ParticleArrays> pd, pr;
    for (int r = 0; r < nranks; ++r)
      pd.push_back(dist[r].arrays()), pr.push_back(repl[r].arrays());
    const std::vector<ParticleFacetResult> res = parts.step(pd, x, v, step == 0);
    std::vector<double> f_whole(3 * nn, 0.0);
    int contacts = 0, contacts_whole = 0;
    for (int r = 0; r < nranks; ++r) {
      contacts += res[r].contacts;
      contacts_whole +=
          whole[r]
              .evaluate(pr[r], mesh.X.data(), x.data(), v.data(), 1e-6, f_whole.data())
              .contacts;
    }
    EXPECT_EQ(contacts, contacts_whole);
    EXPECT_GT(contacts, 5);
    size_t messages = 0; // facets did travel between parts and ranks
    for (const FacetGhosts& g : parts.ghosts)
      messages += g.send_to().size();
    EXPECT_GT(messages, 2u);
    double fmax = 0, sum[3] = {0, 0, 0};
    for (int r = 0; r < nranks; ++r)
      for (int k = 0; k < 3 * dist[r].n; ++k) {
        fmax = std::max(fmax, std::fabs(repl[r].fs[k]));
        sum[k % 3] += dist[r].fs[k];
        EXPECT_EQ(dist[r].fs[k], repl[r].fs[k]) << "force of particle " << k / 3;
        EXPECT_EQ(dist[r].ts[k], repl[r].ts[k]) << "torque of particle " << k / 3;
      }
    const std::vector<double> f = gathered(parts, nn);
    for (int k = 0; k < 3 * nn; ++k) {
      EXPECT_NEAR(f[k], f_whole[k], 1e-13 * fmax) << "node " << k / 3;
      sum[k % 3] += f[k];
    }
    for (int d = 0; d < 3; ++d)
      EXPECT_NEAR(sum[d], 0.0, 1e-12 * fmax) << "momentum balance, axis " << d;
    for (int r = 0; r < nranks; ++r) // the history rows hold the same keys and shears
      EXPECT_EQ(dist[r].hs, repl[r].hs);
    for (int k = 0; k < 3 * nn; ++k) // the body moves a little between steps
      x[k] += 1e-6 * v[k];
    for (int r = 0; r < nranks; ++r)
      for (int k = 0; k < 3 * dist[r].n; ++k)
        dist[r].xs[k] += 1e-6 * dist[r].vs[k], repl[r].xs[k] += 1e-6 * repl[r].vs[k];
  }
}

} // namespace

TEST(FacetGhosts, ThreePartsGiveTheWholeBodysContactPointLaw)
{
  run_against_replicated(false);
}

TEST(FacetGhosts, ThreePartsGiveTheWholeBodysContactHertzPatch)
{
  run_against_replicated(true);
}

TEST(FacetGhosts, ASlidingParticleCrossesPartsAndRanksKeepingItsHistory)
{
  // A sphere pressed into the top of a block slides across it (1 mm per step) over the facets of
  // several parts and, half-way, changes rank with its history row (as the host migrates it):
  // force, torque and history equal the whole body's at every step; boxes are exchanged every
  // third step and at the rank change, so the cached ghosts are used in between.
  const Mesh mesh = make_box_tet_mesh(8, 6, 3, 0.2, 0.15, 0.06);
  const int nn = mesh.num_nodes();
  const std::vector<double> v(3 * nn, 0.0);
  const int nranks = 3;
  Parts parts(mesh, nranks, true);
  const GlobalSurface surface = global_surface(mesh, partition_elements(mesh, nranks));
  std::vector<ParticleFacetContact> whole(nranks);
  for (ParticleFacetContact& c : whole) {
    c.configure(options(true));
    c.set_materials(materials());
    c.rebuild_surface(mesh);
  }
  const double r = 0.008, at[3] = {0.01, 0.07, 0.06 + r - 4e-4}, vel[3] = {1.0, 0.2, 0};
  std::vector<Swarm> dist(nranks), repl(nranks);
  dist[0].add(at, vel, r);
  repl[0].add(at, vel, r);
  int rank = 0, seen_parts = 0, last_exchange = 0;
  for (int step = 0; step < 170; ++step) {
    const int want = dist[rank].xs[0] < 0.1 ? 0 : 1;
    if (want != rank) { // the host migrates the particle, history and all
      for (std::vector<Swarm>* s : {&dist, &repl}) {
        Swarm moved;
        moved.add(&(*s)[rank].xs[0], &(*s)[rank].vs[0], r);
        moved.hs = (*s)[rank].hs;
        (*s)[want] = moved;
        (*s)[rank] = Swarm();
      }
      rank = want;
      last_exchange = -10;
    }
    std::vector<ParticleArrays> pd, pr;
    for (int q = 0; q < nranks; ++q)
      pd.push_back(dist[q].arrays()), pr.push_back(repl[q].arrays());
    const bool boxes = step - last_exchange >= 3 || step == 0;
    if (boxes) last_exchange = step;
    const std::vector<ParticleFacetResult> res = parts.step(pd, mesh.X, v, boxes);
    std::vector<double> f_whole(3 * nn, 0.0);
    const int c_whole =
        whole[rank]
            .evaluate(pr[rank], mesh.X.data(), mesh.X.data(), v.data(), 1e-6, f_whole.data())
            .contacts;
    ASSERT_EQ(res[rank].contacts, c_whole) << "step " << step;
    ASSERT_EQ(c_whole, 1) << "step " << step;
    for (int d = 0; d < 3; ++d) {
      EXPECT_EQ(dist[rank].fs[d], repl[rank].fs[d]) << "step " << step;
      EXPECT_EQ(dist[rank].ts[d], repl[rank].ts[d]) << "step " << step;
    }
    EXPECT_EQ(dist[rank].hs, repl[rank].hs) << "step " << step;
    const std::vector<double> f = gathered(parts, nn);
    for (int k = 0; k < 3 * nn; ++k)
      EXPECT_NEAR(f[k], f_whole[k], 1e-13 * std::fabs(repl[rank].fs[2])) << "node " << k / 3;
    // The parts whose facets the sphere touches (bit mask).
    for (size_t fc = 0; fc < surface.facets.size(); ++fc) {
      Facet g = surface.facets[fc];
      if (facet_distance(g, mesh.X.data(), dist[rank].x[0]) < r)
        seen_parts |= 1 << surface.part[fc];
    }
    for (std::vector<Swarm>* s : {&dist, &repl})
      (*s)[rank].xs[0] += 1e-3;
  }
  EXPECT_EQ(rank, 1);
  EXPECT_GE(__builtin_popcount(seen_parts), 2) << "the sphere slid over facets of several parts";
  EXPECT_NE(dist[1].hs[0], -1.0) << "the contact kept a history slot";
}

TEST(FacetGhosts, DeepContactsReportAPatchBeyondTheGhostReach)
{
  // A particle pressed delta into the undeformed top face of a tet box (no indentation of the
  // body yet, delta_b = 0): its Hertz patch reaches 3.6 sqrt(2 R delta), i.e.
  // 3.6 sqrt(2 delta / R) radii: 1.61 at delta = 0.1 R (within the kPatchRadii that facet ghosts
  // are sent), 4.26 at 0.7 R (beyond: the distributed body warns).
  const Mesh mesh = make_box_tet_mesh(8, 8, 4, 0.2, 0.2, 0.1);
  ParticleFacetContact c;
  c.configure(options(true));
  c.set_materials(materials());
  c.rebuild_surface(mesh);
  const double r = 0.02;
  for (double depth : {0.1, 0.7}) {
    Swarm s;
    const double at[3] = {0.1, 0.1, 0.1 + r - depth * r}, vel[3] = {0, 0, 0};
    s.add(at, vel, r);
    ParticleArrays p = s.arrays();
    std::vector<double> v(mesh.X.size(), 0.0), f(mesh.X.size(), 0.0);
    const ParticleFacetResult res =
        c.evaluate(p, mesh.X.data(), mesh.X.data(), v.data(), 1e-7, f.data());
    ASSERT_GT(res.contacts, 0) << depth;
    EXPECT_NEAR(res.patch_radii, 3.6 * std::sqrt(2 * depth), 1e-9) << depth;
    EXPECT_EQ(res.patch_radii > kPatchRadii, depth > 0.6) << depth;
  }
}

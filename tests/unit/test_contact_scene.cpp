// Unit tests of the contact scene: one search over many bodies against the pairwise code.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <tuple>

#include "contact/contact_scene.h"
#include "io/mesh_generators.h"

using namespace fracdem;

namespace
{

// A pile of tri3 blocks (4 x 3 elements, 1 x 0.75) on a 3 x 3 grid of pitch 0.97 (they overlap
// by 0.03 where neighbours meet), each with a random drift (per axis, up to 0.6), and one
// block (body 0) holding two overlapping pieces of its own (self contact).
struct Pile {
  std::vector<Mesh> mesh;
  std::vector<std::vector<double>> x, v, m;
  std::vector<ContactSurface> surface;
  explicit Pile(unsigned seed, double drift = 0.6)
  {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-drift, drift);
    for (int i = 0; i < 9; ++i) {
      Mesh b = make_rect_mesh(4, 3, 1.0, 0.75, {0.97 * (i % 3), 0.72 * (i / 3)}, ElemType::Tri3);
      if (i == 0) { // a second piece overlapping the first by 0.02 above it
        const Mesh top = make_rect_mesh(4, 2, 1.0, 0.3, {0.05, 0.73}, ElemType::Tri3);
        const int nn = b.num_nodes();
        b.X.insert(b.X.end(), top.X.begin(), top.X.end());
        for (int e = 0; e < top.num_elems(); ++e) {
          std::array<int, 4> c = top.conn[e];
          for (int k = 0; k < 3; ++k)
            c[k] += nn;
          b.conn.push_back(c);
          b.etype.push_back(top.etype[e]);
          b.active.push_back(1);
          b.region.push_back(0);
        }
      }
      const int nn = b.num_nodes();
      x.push_back(b.X);
      v.emplace_back(3 * nn, 0.0);
      const double dvx = u(rng), dvy = u(rng);
      for (int n = 0; n < nn; ++n) {
        v.back()[3 * n] = dvx;
        v.back()[3 * n + 1] = dvy;
      }
      m.emplace_back(nn, 1.0 + 0.1 * i);
      mesh.push_back(std::move(b));
    }
    surface.resize(mesh.size());
    for (size_t i = 0; i < mesh.size(); ++i)
      surface[i].build(mesh[i], boundary_facets(mesh[i]));
  }
  int size() const { return static_cast<int>(mesh.size()); }
  void drift(double dt)
  {
    for (size_t i = 0; i < x.size(); ++i)
      for (size_t k = 0; k < x[i].size(); ++k)
        x[i][k] += v[i][k] * dt;
  }
};

SurfaceContactOptions options(int a, int b)
{
  SurfaceContactOptions o;
  o.youngs = 1e6 * (1 + a + b);
  o.thickness = 0.1;
  o.friction = 0.1 * ((a + b) % 4);
  return o;
}

using Forces = std::vector<std::vector<double>>;

// The code before the scene: each body its pieces, then its pairs with every later body, each
// pair direction an object with its own search.
struct Pairwise {
  std::vector<SurfaceContact> self;
  std::vector<SurfaceContact> pairs; // [2 idx] a on b, [2 idx + 1] b on a
  explicit Pairwise(int n) : self(n), pairs(n * (n - 1))
  {
    for (int b = 0; b < n; ++b) {
      self[b].configure(options(b, b));
      for (int a = 0; a < b; ++a) {
        pairs[2 * ContactScene::pair_index(a, b)].configure(options(a, b));
        pairs[2 * ContactScene::pair_index(a, b) + 1].configure(options(a, b));
      }
    }
  }
  // exact: every object searches afresh at every step (no contact can be missed).
  int step(Pile& p, Forces& f, double dt, bool exact = false)
  {
    if (exact) {
      for (auto& sc : self)
        sc.invalidate();
      for (auto& sc : pairs)
        sc.invalidate();
    }
    int c = 0;
    for (int i = 0; i < p.size(); ++i) {
      ContactBodyState si{p.x[i].data(), p.v[i].data(), p.m[i].data(), f[i].data()};
      c += self[i].evaluate(p.surface[i], si, p.surface[i], si, true, dt);
      for (int j = i + 1; j < p.size(); ++j) {
        ContactBodyState sj{p.x[j].data(), p.v[j].data(), p.m[j].data(), f[j].data()};
        const int k = ContactScene::pair_index(i, j);
        c += pairs[2 * k].evaluate(p.surface[i], si, p.surface[j], sj, false, dt);
        c += pairs[2 * k + 1].evaluate(p.surface[j], sj, p.surface[i], si, false, dt);
      }
    }
    return c;
  }
};

struct Scene {
  std::vector<SurfaceContact> self;
  ContactScene scene;
  Scene(const Pile& p, const ContactBalance& balance) : self(p.size())
  {
    std::vector<SceneMember> members;
    std::vector<SurfaceContactOptions> pair_options(p.size() * (p.size() - 1) / 2);
    for (int b = 0; b < p.size(); ++b) {
      self[b].configure(options(b, b));
      members.push_back({&p.surface[b], &self[b]});
      for (int a = 0; a < b; ++a)
        pair_options[ContactScene::pair_index(a, b)] = options(a, b);
    }
    scene.configure(members, pair_options, balance, SceneComm());
  }
  int step(Pile& p, Forces& f, std::int64_t step, double dt)
  {
    std::vector<ContactBodyState> st;
    for (int i = 0; i < p.size(); ++i)
      st.push_back({p.x[i].data(), p.v[i].data(), p.m[i].data(), f[i].data()});
    int c = 0;
    for (int i = 0; i < p.size(); ++i)
      c += scene.evaluate_body(i, st, step, dt);
    return c;
  }
};

Forces zeros(const Pile& p)
{
  Forces f;
  for (const auto& x : p.x)
    f.emplace_back(x.size(), 0.0);
  return f;
}

} // namespace

// The scene against the pairwise objects over `steps` steps of drift: the same contacts, and the
// same forces bit for bit (same candidates after the filters, same order of accumulation),
// contact offsets carried from step to step. Returns the contacts.
long compare_with_pairwise(double drift, double dt, int steps, bool exact, long* searches)
{
  Pile p(7, drift), q(7, drift);
  Pairwise ref(p.size());
  Scene sc(q, ContactBalance());
  long total = 0;
  for (int s = 0; s < steps; ++s) {
    Forces fr = zeros(p), fs = zeros(q);
    const int cr = ref.step(p, fr, dt, exact);
    const int cs = sc.step(q, fs, s, dt);
    EXPECT_EQ(cs, cr) << "step " << s;
    total += cr;
    for (int i = 0; i < p.size(); ++i)
      for (size_t k = 0; k < fr[i].size(); ++k)
        if (fs[i][k] != fr[i][k]) {
          ADD_FAILURE() << "step " << s << " body " << i << " entry " << k << ": " << fs[i][k]
                        << " vs " << fr[i][k];
          return total;
        }
    p.drift(dt);
    q.drift(dt);
  }
  *searches = sc.scene.searches();
  return total;
}

TEST(ContactScene, ReproducesThePairwiseCodeBitForBit)
{
  // Slow drift (0.2 per axis, 0.12 in all): the pairwise objects' own searches miss nothing.
  long searches = 0;
  EXPECT_GT(compare_with_pairwise(0.2, 0.002, 60, false, &searches), 60 * 10);
  EXPECT_GE(searches, 1);
}

TEST(ContactScene, FindsEveryContactOfASearchAtEveryStep)
{
  // Fast drift (up to 0.6 per axis, 0.18 in all, over reach = 0.125): the scene searches again
  // as its nodes pass half the reach and gets the forces of pairwise objects that search afresh
  // at every step (the pairwise objects' own buffers, half as wide, can miss a contact that
  // appears already deep).
  long searches = 0;
  EXPECT_GT(compare_with_pairwise(0.6, 0.005, 60, true, &searches), 60 * 10);
  EXPECT_GT(searches, 1);
  EXPECT_LT(searches, 60);
}

TEST(ContactScene, CandidatesAreTheBruteForceOnesOfAllBodies)
{
  Pile p(3);
  Scene sc(p, ContactBalance());
  Forces f = zeros(p);
  sc.step(p, f, 0, 1e-3);
  // Scene numbering: members in order, each surface's nodes / facets in order.
  std::vector<Aabb> boxes;
  std::vector<double> spheres;
  std::vector<std::pair<int, int>> node_of, facet_of; // (member, local index)
  for (int m = 0; m < p.size(); ++m) {
    const ContactSurface& s = p.surface[m];
    for (size_t k = 0; k < s.nodes.size(); ++k) {
      for (int d = 0; d < 3; ++d)
        spheres.push_back(p.x[m][3 * s.nodes[k] + d]);
      spheres.push_back(0.0);
      node_of.push_back({m, static_cast<int>(k)});
    }
    for (size_t k = 0; k < s.facets.size(); ++k) {
      Aabb b;
      for (int d = 0; d < 3; ++d) {
        b.lo[d] = 1e300;
        b.hi[d] = -1e300;
        for (int j = 0; j < s.facets[k].nn; ++j) {
          b.lo[d] = std::min(b.lo[d], p.x[m][3 * s.facets[k].n[j] + d]);
          b.hi[d] = std::max(b.hi[d], p.x[m][3 * s.facets[k].n[j] + d]);
        }
      }
      boxes.push_back(b);
      facet_of.push_back({m, static_cast<int>(k)});
    }
  }
  std::set<std::tuple<int, int, int, int>> brute, scene;
  const double buffer = sc.scene.buffer();
  double reach = 0;
  for (const auto& s : p.surface)
    reach = std::max(reach, s.max_reach);
  EXPECT_EQ(buffer, 2 * reach);
  for (const auto& c :
       brute_force_candidates(boxes, spheres.data(), static_cast<int>(node_of.size()), buffer))
    brute.insert({node_of[c.first].first, node_of[c.first].second, facet_of[c.second].first,
                  facet_of[c.second].second});
  for (int a = 0; a < p.size(); ++a)
    for (int b = 0; b < p.size(); ++b)
      for (const auto& c : sc.scene.candidates(a, b))
        scene.insert({a, c.first, b, c.second});
  EXPECT_EQ(scene, brute);
  EXPECT_GT(brute.size(), 100u);
}

TEST(ContactScene, ModelPartsCountEveryContactOnceAndRebalance)
{
  // Three model parts at one rank: the forces stay those of one part (every node is still
  // evaluated here), every surface node has a part, the parts' counts add up to the totals, and
  // an a posteriori repartition (thresh 1: at every check above perfect balance) predicts a
  // balance better than the imbalance it was triggered by.
  Pile p(11), q(11);
  ContactBalance three;
  three.parts = 3;
  three.every = 5;
  three.thresh = 1.0;
  Scene one(p, ContactBalance()), parts(q, three);
  for (int s = 0; s < 30; ++s) {
    Forces f1 = zeros(p), f3 = zeros(q);
    EXPECT_EQ(one.step(p, f1, s, 0.002), parts.step(q, f3, s, 0.002));
    for (int i = 0; i < p.size(); ++i)
      for (size_t k = 0; k < f1[i].size(); ++k)
        ASSERT_EQ(f3[i][k], f1[i][k]);
    p.drift(0.002);
    q.drift(0.002);
  }
  EXPECT_EQ(parts.scene.parts(), 3);
  for (int o : parts.scene.owners()) {
    EXPECT_GE(o, 0);
    EXPECT_LT(o, 3);
  }
  std::set<int> used(parts.scene.owners().begin(), parts.scene.owners().end());
  EXPECT_EQ(used.size(), 3u);
  EXPECT_EQ(parts.scene.contacts(), one.scene.contacts());
  EXPECT_EQ(parts.scene.tests(), one.scene.tests());
  EXPECT_GE(parts.scene.repartitions(), 2); // the first search, then by recorded work
  EXPECT_LT(parts.scene.predicted_imbalance(), 1.1);
}

TEST(ContactScene, WorkBeforeAMidStepTopologyChangeStaysBooked)
{
  // A body's topology change (erosion, a split) in its force evaluation renumbers the scene
  // before the later bodies' evaluation: the work the earlier bodies did in that step must stay
  // booked to the parts that did it (the per-node windows restart with the numbering), so the
  // parts' booked work adds up to every test and contact made.
  Pile p(11);
  ContactBalance three;
  three.parts = 3;
  three.every = 1;
  three.thresh = 1.0;
  Scene sc(p, three);
  for (int s = 0; s < 20; ++s) {
    Forces f = zeros(p);
    std::vector<ContactBodyState> st;
    for (int i = 0; i < p.size(); ++i)
      st.push_back({p.x[i].data(), p.v[i].data(), p.m[i].data(), f[i].data()});
    for (int i = 0; i < p.size(); ++i) {
      sc.scene.evaluate_body(i, st, s, 0.002);
      if (s % 4 == 1 && i == p.size() / 2) sc.scene.invalidate();
    }
    p.drift(0.002);
  }
  double booked = 0;
  for (double w : sc.scene.booked())
    booked += w;
  EXPECT_GT(sc.scene.tests(), 0);
  EXPECT_EQ(booked, static_cast<double>(sc.scene.tests() + sc.scene.contacts()));
}

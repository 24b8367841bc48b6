// Unit tests of crack tracking: band straightness, direction, averaging and nucleation exclusion.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "fracture/crack_tracking.h"

using namespace fracdem;

namespace
{

constexpr double kPi = 3.14159265358979323846;

// Unit square, n x n cells of two triangles. jitter > 0: interior nodes moved by up to jitter
// cells and the diagonal of each cell drawn at random (a mesh with no preferred direction).
Mesh square_mesh(int n, double jitter, unsigned seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Mesh m;
  m.dim = 2;
  const double h = 1.0 / n;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const bool inner = i > 0 && i < n && j > 0 && j < n;
      const double dx = inner ? jitter * h * u(rng) : 0.0, dy = inner ? jitter * h * u(rng) : 0.0;
      m.X.insert(m.X.end(), {i * h + dx, j * h + dy, 0.0});
    }
  auto id = [n](int i, int j) { return j * (n + 1) + i; };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
      const bool flip = jitter > 0 && (rng() & 1u);
      const std::array<std::array<int, 4>, 2> tris =
          flip ? std::array<std::array<int, 4>, 2>{{{a, b, d, -1}, {b, c, d, -1}}}
               : std::array<std::array<int, 4>, 2>{{{a, b, c, -1}, {a, c, d, -1}}};
      for (const auto& t : tris) {
        m.etype.push_back(ElemType::Tri3);
        m.conn.push_back(t);
        m.active.push_back(1);
        m.region.push_back(0);
      }
    }
  return m;
}

// Uniaxial tension along the unit vector at `angle` (radians from x), with an optional
// per-element tilt of the tension axis (noise, radians) that one element's stress would follow.
ElementStressFn uniaxial(double angle, const std::vector<double>& tilt = {})
{
  return [angle, tilt](int e, double s[6]) {
    const double a = angle + (tilt.empty() ? 0.0 : tilt[e]);
    const double c = std::cos(a), sn = std::sin(a);
    s[0] = c * c;
    s[1] = sn * sn;
    s[2] = 0;
    s[3] = c * sn;
    s[4] = s[5] = 0;
  };
}

int element_at(const TrackGeometry& g, double x, double y)
{
  int best = 0;
  double d2 = 1e300;
  for (int e = 0; e < static_cast<int>(g.area.size()); ++e) {
    const double d = std::pow(g.centroid[2 * e] - x, 2) + std::pow(g.centroid[2 * e + 1] - y, 2);
    if (d < d2) {
      d2 = d;
      best = e;
    }
  }
  return best;
}

// A crack started at element `start`, every marked element damaged at once, tracked until its
// tips stop (at the boundary). Returns the state.
CrackTrackState run_crack(const Mesh& m, const TrackGeometry& g, const ElementStressFn& stress,
                          double L, int start)
{
  CrackTrackState st;
  std::vector<int> damaged, over = {start};
  TrackInput in;
  in.stress = stress;
  in.length = L;
  in.damaged = &damaged;
  in.overstressed = &over;
  for (int round = 0; round < 10 * m.num_elems(); ++round) {
    track_cracks(m, g, in, st);
    over.clear();
    if (st.tips.empty()) break;
    damaged.clear();
    for (int e = 0; e < m.num_elems(); ++e)
      if (st.marked[e]) damaged.push_back(e);
  }
  return st;
}

// Largest distance of a marked centroid from the line through p at `angle`, and the extent of
// the band along the line.
void band_measures(const TrackGeometry& g, const CrackTrackState& st, const double p[2],
                   double angle, double& off, double& lo, double& hi)
{
  const double t[2] = {std::cos(angle), std::sin(angle)};
  off = 0;
  lo = 1e300;
  hi = -1e300;
  for (int e = 0; e < static_cast<int>(st.marked.size()); ++e) {
    if (!st.marked[e]) continue;
    const double dx = g.centroid[2 * e] - p[0], dy = g.centroid[2 * e + 1] - p[1];
    off = std::max(off, std::fabs(-t[1] * dx + t[0] * dy));
    lo = std::min(lo, t[0] * dx + t[1] * dy);
    hi = std::max(hi, t[0] * dx + t[1] * dy);
  }
}

int marked_count(const CrackTrackState& st)
{
  return static_cast<int>(std::count(st.marked.begin(), st.marked.end(), 1));
}

// Tension in y, band along x: straight within one element size, across the whole square, and a
// band (a few elements per cell column), not a blob.
void check_horizontal_band(const Mesh& m, double L_cells)
{
  const TrackGeometry g = track_geometry(m, {});
  const double h = mean_element_size(m);
  const int start = element_at(g, 0.5, 0.5);
  const CrackTrackState st = run_crack(m, g, uniaxial(kPi / 2), L_cells * h, start);
  double off, lo, hi;
  band_measures(g, st, &g.centroid[2 * start], 0.0, off, lo, hi);
  EXPECT_EQ(st.cracks, 1);
  EXPECT_LE(off, h) << "band leaves the line y = const by more than one element";
  EXPECT_LE(lo, -0.5 + h);
  EXPECT_GE(hi, 0.5 - h);
  const int cells = static_cast<int>(std::lround(std::sqrt(m.num_elems() / 2.0)));
  EXPECT_LE(marked_count(st), 3 * cells) << "the band is wider than a strip of elements";
}

} // namespace

TEST(CrackTracking, StructuredTensionGivesStraightBand)
{
  check_horizontal_band(square_mesh(20, 0.0, 1), 3.0);
}

TEST(CrackTracking, UnstructuredTensionGivesStraightBand)
{
  check_horizontal_band(square_mesh(24, 0.3, 7), 3.0);
}

// Tension axis at 120 deg: the band runs at 30 deg within one element of the line through the
// start, on the structured and the jittered mesh (where edges offer no 30 deg path).
TEST(CrackTracking, RotatedStressBandFollows30Degrees)
{
  for (double jitter : {0.0, 0.3}) {
    const Mesh m = square_mesh(30, jitter, 3);
    const TrackGeometry g = track_geometry(m, {});
    const double h = mean_element_size(m);
    const int start = element_at(g, 0.5, 0.5);
    const double angle = 30.0 * kPi / 180.0;
    const CrackTrackState st = run_crack(m, g, uniaxial(angle + kPi / 2), 3 * h, start);
    double off, lo, hi;
    band_measures(g, st, &g.centroid[2 * start], angle, off, lo, hi);
    EXPECT_LE(off, h) << "jitter " << jitter;
    // The line through the centre at 30 deg meets the square's sides 0.5 / cos 30 away.
    EXPECT_LE(lo, -0.5 / std::cos(angle) + 2 * h) << "jitter " << jitter;
    EXPECT_GE(hi, 0.5 / std::cos(angle) - 2 * h) << "jitter " << jitter;
  }
}

// A stress whose axis wobbles +-20 deg from element to element: with L of three elements the
// band stays within one element of the mean direction and crosses the whole square.
TEST(CrackTracking, AveragedDirectionIgnoresElementNoise)
{
  const Mesh m = square_mesh(30, 0.3, 11);
  const TrackGeometry g = track_geometry(m, {});
  const double h = mean_element_size(m);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<double> tilt(m.num_elems());
  for (double& a : tilt)
    a = 20.0 * kPi / 180.0 * u(rng);
  const int start = element_at(g, 0.5, 0.5);
  double off, lo, hi;
  const CrackTrackState avg = run_crack(m, g, uniaxial(kPi / 2, tilt), 3 * h, start);
  band_measures(g, avg, &g.centroid[2 * start], 0.0, off, lo, hi);
  EXPECT_LE(off, h);
  EXPECT_LE(lo, -0.5 + h);
  EXPECT_GE(hi, 0.5 - h);
}

// Candidates within L of the first crack do not start a second one; one farther away does.
TEST(CrackTracking, NucleationExclusionRadius)
{
  const Mesh m = square_mesh(20, 0.0, 1);
  const TrackGeometry g = track_geometry(m, {});
  const double h = mean_element_size(m), L = 3 * h;
  const int a = element_at(g, 0.5, 0.5);
  const int near = element_at(g, 0.5 + 0.6 * L, 0.5 + 0.3 * L);
  const int far = element_at(g, 0.5, 0.5 + 3 * L);
  CrackTrackState st;
  std::vector<int> damaged, over = {a, near, far};
  std::sort(over.begin(), over.end());
  TrackInput in;
  in.stress = uniaxial(kPi / 2);
  in.length = L;
  in.damaged = &damaged;
  in.overstressed = &over;
  const TrackEvents ev = track_cracks(m, g, in, st);
  EXPECT_EQ(ev.nucleated, 2);
  EXPECT_TRUE(st.marked[a] && st.marked[far]);
  EXPECT_FALSE(st.marked[near]);
  // After the first crack has grown, a candidate near one of its tips is excluded as well.
  damaged = {a};
  track_cracks(m, g, in, st);
  ASSERT_FALSE(st.tips.empty());
  const TrackTip tip = st.tips[0];
  over = {
      element_at(g, tip.p[0] + 0.5 * L * tip.dir[0], tip.p[1] + 0.5 * L * tip.dir[1] + 0.3 * L)};
  damaged.clear();
  const int before = st.cracks;
  track_cracks(m, g, in, st);
  EXPECT_EQ(st.cracks, before);
}

// An exclusion radius beyond L excludes a candidate that L alone would let start.
TEST(CrackTracking, ExclusionRadiusBeyondL)
{
  const Mesh m = square_mesh(20, 0.0, 1);
  const TrackGeometry g = track_geometry(m, {});
  const double h = mean_element_size(m), L = 3 * h;
  std::vector<int> damaged, over = {element_at(g, 0.5, 0.5), element_at(g, 0.5, 0.5 + 2 * L)};
  std::sort(over.begin(), over.end());
  TrackInput in;
  in.stress = uniaxial(kPi / 2);
  in.length = L;
  in.damaged = &damaged;
  in.overstressed = &over;
  CrackTrackState by_l, by_r;
  EXPECT_EQ(track_cracks(m, g, in, by_l).nucleated, 2);
  in.exclusion = 3 * L;
  EXPECT_EQ(track_cracks(m, g, in, by_r).nucleated, 1);
}

TEST(CrackTracking, StateRoundTrip)
{
  const Mesh m = square_mesh(10, 0.3, 2);
  const TrackGeometry g = track_geometry(m, {});
  CrackTrackState st = run_crack(m, g, uniaxial(1.0), 3 * mean_element_size(m), 57);
  st.tips.push_back(TrackTip{4, {0.25, 0.5}, {0.6, 0.8}});
  std::vector<double> buf;
  pack_track_state(st, buf);
  CrackTrackState back;
  EXPECT_EQ(unpack_track_state(buf.data(), back), buf.data() + buf.size());
  EXPECT_EQ(back.marked, st.marked);
  ASSERT_EQ(back.tips.size(), st.tips.size());
  EXPECT_EQ(back.tips.back().dir[1], 0.8);
  EXPECT_EQ(back.cracks, st.cracks);
}

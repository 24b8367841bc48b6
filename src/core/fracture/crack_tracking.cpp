// Crack tracking: nucleation with an exclusion radius, averaged crack direction, band marching.
#include "fracture/crack_tracking.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

namespace fracdem
{

namespace
{

int root_of(const std::vector<int>& parents, int n)
{
  while (n >= 0 && n < static_cast<int>(parents.size()) && parents[n] >= 0)
    n = parents[n];
  return n;
}

int corners(const Mesh& mesh, int e)
{
  return mesh.conn[e][3] >= 0 && mesh.etype[e] != ElemType::Tet4 ? 4 : 3;
}

double dist2(const double* a, const double* b)
{
  return (a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]);
}

// The crack direction at p (perpendicular to the averaged major principal direction), oriented
// along `along` when given (non-zero); false without stress around p.
bool crack_direction(const Mesh& mesh, const TrackGeometry& geo, const TrackInput& in,
                     const double p[2], const double along[2], double t[2])
{
  double n[2];
  if (!averaged_failure_normal(mesh, geo, in.stress, p, in.length, n)) return false;
  t[0] = -n[1];
  t[1] = n[0];
  if (t[0] * along[0] + t[1] * along[1] < 0) {
    t[0] = -t[0];
    t[1] = -t[1];
  }
  return true;
}

// Where the line p + s t (s > 0) leaves element e: the local edge and the exit point; -1 when it
// does not (p outside e, or t pointing out through p's own edge).
int exit_edge(const Mesh& mesh, int e, const double p[2], const double t[2], double q[2])
{
  const int nv = corners(mesh, e);
  const double* X = mesh.X.data();
  double size2 = 0;
  for (int a = 1; a < nv; ++a)
    size2 = std::max(size2, dist2(&X[3 * mesh.conn[e][0]], &X[3 * mesh.conn[e][a]]));
  const double tol = 1e-9 * std::sqrt(size2);
  int best = -1;
  double best_s = tol, best_u = 0;
  for (int k = 0; k < nv; ++k) {
    const double* a = &X[3 * mesh.conn[e][k]];
    const double* b = &X[3 * mesh.conn[e][(k + 1) % nv]];
    const double ex = b[0] - a[0], ey = b[1] - a[1];
    const double den = t[0] * (-ey) - t[1] * (-ex); // det [t, -(b - a)]
    if (std::fabs(den) < 1e-300) continue;
    const double rx = a[0] - p[0], ry = a[1] - p[1];
    const double s = (rx * (-ey) - ry * (-ex)) / den;
    const double u = (t[0] * ry - t[1] * rx) / den;
    if (u < -1e-9 || u > 1 + 1e-9 || s <= best_s) continue;
    best = k;
    best_s = s;
    best_u = std::clamp(u, 0.0, 1.0);
  }
  if (best < 0) return -1;
  const double* a = &X[3 * mesh.conn[e][best]];
  const double* b = &X[3 * mesh.conn[e][(best + 1) % nv]];
  q[0] = a[0] + best_u * (b[0] - a[0]);
  q[1] = a[1] + best_u * (b[1] - a[1]);
  return best;
}

bool listed(const std::vector<int>* sorted, int e)
{
  return sorted && std::binary_search(sorted->begin(), sorted->end(), e);
}

enum class TipMove { Wait, Advanced, Stopped };

// Whether an unmarked element within L of the tip is held at the strength: the material around
// the tip fails, so the tip grows (a start there is excluded).
bool failing_near(const TrackGeometry& geo, const TrackInput& in, const CrackTrackState& state,
                  const TrackTip& tip)
{
  if (!in.overstressed) return false;
  for (int e : *in.overstressed)
    if (!state.marked[e] && dist2(&geo.centroid[2 * e], tip.p) <= in.length * in.length)
      return true;
  return false;
}

// Moves the tip one element on when its element is damaged or an element within L of it is held
// at the strength; stops it where the line leaves the body or meets a band.
TipMove advance_tip(const Mesh& mesh, const TrackGeometry& geo, const TrackInput& in,
                    CrackTrackState& state, TrackTip& tip)
{
  if (!listed(in.damaged, tip.elem) && !failing_near(geo, in, state, tip)) return TipMove::Wait;
  double t[2];
  if (!crack_direction(mesh, geo, in, tip.p, tip.dir, t)) return TipMove::Stopped;
  double q[2];
  int k = exit_edge(mesh, tip.elem, tip.p, t, q);
  if (k < 0) k = exit_edge(mesh, tip.elem, &geo.centroid[2 * tip.elem], t, q);
  if (k < 0) return TipMove::Stopped;
  const int next = geo.neighbour[tip.elem][k];
  if (next < 0 || !mesh.active[next] || state.marked[next]) return TipMove::Stopped;
  state.marked[next] = 1;
  tip.elem = next;
  tip.p[0] = q[0];
  tip.p[1] = q[1];
  tip.dir[0] = t[0];
  tip.dir[1] = t[1];
  return TipMove::Advanced;
}

double major_stress(const double s[6])
{
  const double c = 0.5 * (s[0] + s[1]), r = std::hypot(0.5 * (s[0] - s[1]), s[3]);
  return c + r;
}

// Whether a crack may start at element e: no tip and no marked element within L.
bool excluded(const TrackGeometry& geo, const CrackTrackState& state, int e, double L)
{
  const double* c = &geo.centroid[2 * e];
  const double L2 = L * L;
  for (const TrackTip& tip : state.tips)
    if (dist2(tip.p, c) < L2) return true;
  const int ne = static_cast<int>(state.marked.size());
  for (int m = 0; m < ne; ++m)
    if (state.marked[m] && dist2(&geo.centroid[2 * m], c) < L2) return true;
  return false;
}

void nucleate(const Mesh& mesh, const TrackGeometry& geo, const TrackInput& in,
              CrackTrackState& state, TrackEvents& ev)
{
  std::vector<std::pair<double, int>> order; // (-s1, e): most stressed first, then by index
  for (int e : *in.overstressed) {
    if (e < 0 || e >= mesh.num_elems() || state.marked[e] || !mesh.active[e]) continue;
    double s[6];
    in.stress(e, s);
    order.emplace_back(-major_stress(s), e);
  }
  std::sort(order.begin(), order.end());
  for (const auto& [neg_s1, e] : order) {
    if (excluded(geo, state, e, in.exclusion > 0 ? in.exclusion : in.length)) continue;
    const double* c = &geo.centroid[2 * e];
    const double none[2] = {0, 0};
    double t[2];
    if (!crack_direction(mesh, geo, in, c, none, t)) continue;
    // Orient the first tip deterministically: positive x, or positive y along the y axis.
    if (t[0] < 0 || (t[0] == 0 && t[1] < 0)) {
      t[0] = -t[0];
      t[1] = -t[1];
    }
    state.marked[e] = 1;
    for (int sign : {1, -1}) {
      TrackTip tip;
      tip.elem = e;
      tip.p[0] = c[0];
      tip.p[1] = c[1];
      tip.dir[0] = sign * t[0];
      tip.dir[1] = sign * t[1];
      state.tips.push_back(tip);
    }
    ++state.cracks;
    ++ev.nucleated;
    ev.started.push_back(e);
  }
}

} // namespace

TrackGeometry track_geometry(const Mesh& mesh, const std::vector<int>& parents)
{
  const int ne = mesh.num_elems();
  TrackGeometry g;
  g.centroid.assign(2 * ne, 0.0);
  g.area.assign(ne, 0.0);
  g.neighbour.assign(ne, {-1, -1, -1, -1});
  std::map<std::pair<int, int>, std::pair<int, int>> edges; // root edge -> (element, local edge)
  for (int e = 0; e < ne; ++e) {
    const int nv = corners(mesh, e);
    double a2 = 0;
    for (int k = 0; k < nv; ++k) {
      const double* p = &mesh.X[3 * mesh.conn[e][k]];
      const double* q = &mesh.X[3 * mesh.conn[e][(k + 1) % nv]];
      g.centroid[2 * e] += p[0] / nv;
      g.centroid[2 * e + 1] += p[1] / nv;
      a2 += p[0] * q[1] - q[0] * p[1];
      int r0 = root_of(parents, mesh.conn[e][k]), r1 = root_of(parents, mesh.conn[e][(k + 1) % nv]);
      if (r0 > r1) std::swap(r0, r1);
      const auto [it, fresh] = edges.emplace(std::make_pair(r0, r1), std::make_pair(e, k));
      if (!fresh) {
        g.neighbour[e][k] = it->second.first;
        g.neighbour[it->second.first][it->second.second] = e;
      }
    }
    g.area[e] = 0.5 * std::fabs(a2);
  }
  return g;
}

bool averaged_failure_normal(const Mesh& mesh, const TrackGeometry& geo,
                             const ElementStressFn& stress, const double p[2], double L,
                             double n[2])
{
  double sum[3] = {0, 0, 0}, w = 0;
  const double L2 = L * L;
  for (int e = 0; e < mesh.num_elems(); ++e) {
    if (!mesh.active[e] || dist2(&geo.centroid[2 * e], p) > L2) continue;
    double s[6];
    stress(e, s);
    sum[0] += geo.area[e] * s[0];
    sum[1] += geo.area[e] * s[1];
    sum[2] += geo.area[e] * s[3];
    w += geo.area[e];
  }
  if (!(w > 0)) return false;
  const double angle = 0.5 * std::atan2(2 * sum[2], sum[0] - sum[1]);
  n[0] = std::cos(angle);
  n[1] = std::sin(angle);
  return true;
}

double mean_element_size(const Mesh& mesh)
{
  double sum = 0;
  int count = 0;
  for (int e = 0; e < mesh.num_elems(); ++e)
    if (mesh.active[e]) {
      sum += element_diameter(mesh, e);
      ++count;
    }
  return count > 0 ? sum / count : 0.0;
}

TrackEvents track_cracks(const Mesh& mesh, const TrackGeometry& geo, const TrackInput& in,
                         CrackTrackState& state, const std::function<int(int)>& parent_of)
{
  const int ne = mesh.num_elems();
  const int old = static_cast<int>(state.marked.size());
  state.marked.resize(ne, 0);
  for (int e = old; e < ne; ++e) {
    const int parent = parent_of ? parent_of(e) : -1;
    state.marked[e] = parent >= 0 && parent < e ? state.marked[parent] : 0;
  }
  TrackEvents ev;
  std::vector<TrackTip> live;
  for (TrackTip tip : state.tips) {
    const TipMove move = advance_tip(mesh, geo, in, state, tip);
    if (move != TipMove::Stopped) live.push_back(tip);
    if (move == TipMove::Advanced) ++ev.advanced;
    if (move == TipMove::Stopped) ++ev.stopped;
  }
  state.tips = std::move(live);
  if (in.overstressed) nucleate(mesh, geo, in, state, ev);
  return ev;
}

void pack_track_state(const CrackTrackState& state, std::vector<double>& buf)
{
  buf.push_back(static_cast<double>(state.marked.size()));
  buf.insert(buf.end(), state.marked.begin(), state.marked.end());
  buf.push_back(static_cast<double>(state.tips.size()));
  for (const TrackTip& t : state.tips)
    buf.insert(buf.end(), {double(t.elem), t.p[0], t.p[1], t.dir[0], t.dir[1]});
  buf.push_back(static_cast<double>(state.cracks));
}

const double* unpack_track_state(const double* p, CrackTrackState& state)
{
  const auto ne = static_cast<std::size_t>(*p++);
  state.marked.assign(p, p + ne);
  p += ne;
  const auto nt = static_cast<std::size_t>(*p++);
  state.tips.assign(nt, TrackTip{});
  for (TrackTip& t : state.tips) {
    t.elem = static_cast<int>(p[0]);
    t.p[0] = p[1];
    t.p[1] = p[2];
    t.dir[0] = p[3];
    t.dir[1] = p[4];
    p += 5;
  }
  state.cracks = static_cast<int>(*p++);
  return p;
}

} // namespace fracdem

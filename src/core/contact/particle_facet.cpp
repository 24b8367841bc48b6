// Particle-facet contact pipeline: candidates, closest points, resolution, law, reaction spread.
#include "contact/particle_facet.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "contact/geometry.h"

namespace fracdem
{

double* history_slot(double* row, int slots, std::uint64_t key, bool create, bool* exhausted)
{
  const double hi = static_cast<double>(key >> 32), lo = static_cast<double>(key & 0xffffffffu);
  int free_slot = -1;
  for (int k = 0; k < slots; ++k) {
    double* s = row + k * kHistorySlotDoubles;
    if (s[0] == hi && s[1] == lo) return s;
    if (free_slot < 0 && s[0] < 0) free_slot = k;
  }
  if (!create) return nullptr;
  if (free_slot < 0) {
    if (exhausted) *exhausted = true;
    return nullptr;
  }
  double* s = row + free_slot * kHistorySlotDoubles;
  s[0] = hi;
  s[1] = lo;
  s[2] = s[3] = s[4] = 0;
  return s;
}

void clear_history_row(double* row, int slots)
{
  for (int k = 0; k < slots; ++k)
    row[k * kHistorySlotDoubles] = row[k * kHistorySlotDoubles + 1] = -1;
}

void ParticleFacetContact::configure(const ParticleFacetOptions& options)
{
  opt_ = options;
  search_ = std::make_unique<BufferedSearch>(opt_.buffer);
  search_stale_ = true;
}

void ParticleFacetContact::rebuild_surface(const Mesh& mesh)
{
  nnodes_ = mesh.num_nodes();
  facets_ = boundary_facets(mesh);
  topology_.build(facets_, nnodes_);
  // Surface area per node in the reference configuration (a third of each triangle, half of
  // each 2D edge): the weights of a pressure spread over the nodes.
  node_area_.assign(nnodes_, 0.0);
  for (const Facet& fc : facets_) {
    const double size = facet_measure(mesh.X.data(), fc);
    for (int j = 0; j < fc.nn; ++j)
      node_area_[fc.n[j]] += size / fc.nn;
  }
  indentation_disp_.assign(nnodes_, 0.0);
  reference_normals(mesh);
  surface_pieces();
  key_nodes_.clear();
  search_stale_ = true;
}

void ParticleFacetContact::set_surface(std::vector<Facet> facets, int nnodes,
                                       std::vector<double> ref_normals, std::vector<int> pieces,
                                       std::vector<double> node_area, std::vector<int> key_nodes)
{
  nnodes_ = nnodes;
  facets_ = std::move(facets);
  topology_.build(facets_, nnodes_);
  facet_ref_normal_ = std::move(ref_normals);
  facet_piece_ = std::move(pieces);
  node_area_ = std::move(node_area);
  key_nodes_ = std::move(key_nodes);
  indentation_disp_.assign(nnodes_, 0.0);
  search_stale_ = true;
}

// Connected components of the surface (facets that share a node): the pieces of a broken body.
// A crack that has not run through still joins both faces at its tip, so only separated
// fragments are different pieces.
void ParticleFacetContact::surface_pieces()
{
  std::vector<int> parent(nnodes_);
  for (int a = 0; a < nnodes_; ++a)
    parent[a] = a;
  auto root = [&](int a) {
    while (parent[a] != a)
      a = parent[a] = parent[parent[a]];
    return a;
  };
  for (const Facet& fc : facets_)
    for (int j = 1; j < fc.nn; ++j)
      parent[root(fc.n[j])] = root(fc.n[0]);
  facet_piece_.resize(facets_.size());
  for (size_t k = 0; k < facets_.size(); ++k)
    facet_piece_[k] = root(facets_[k].n[0]);
}

// Outward unit normal of every facet in the reference configuration (away from its element's
// centroid): the surface region a facet belongs to, whatever the body's deformation.
void ParticleFacetContact::reference_normals(const Mesh& mesh)
{
  facet_ref_normal_.assign(3 * facets_.size(), 0.0);
  const double* X = mesh.X.data();
  for (size_t k = 0; k < facets_.size(); ++k) {
    const Facet& fc = facets_[k];
    const double* a = &X[3 * fc.n[0]];
    double nrm[3];
    facet_normal(X, fc.n.data(), fc.nn, nrm);
    const auto& conn = mesh.conn[fc.elem];
    const int ne = nodes_per_elem(mesh.etype[fc.elem]);
    double out = 0;
    for (int d = 0; d < 3; ++d) {
      double centroid = 0;
      for (int j = 0; j < ne; ++j)
        centroid += X[3 * conn[j] + d] / ne;
      out += nrm[d] * (a[d] - centroid);
    }
    const double l = std::sqrt(nrm[0] * nrm[0] + nrm[1] * nrm[1] + nrm[2] * nrm[2]);
    const double sign = out < 0 ? -1.0 : 1.0;
    for (int d = 0; d < 3; ++d)
      facet_ref_normal_[3 * k + d] = l > 0 ? sign * nrm[d] / l : 0.0;
  }
}

/* ---------------------------------------------------------------------- */

void ParticleFacetContact::rebuild_search(const ParticleArrays& p, const double* x, int nnodes)
{
  std::vector<Aabb> boxes(facets_.size());
  for (size_t k = 0; k < facets_.size(); ++k)
    boxes[k] = node_box(facets_[k].n.data(), facets_[k].nn, x);
  search_spheres(p, boxes);
  const int ns = static_cast<int>(search_atoms_.size());
  search_->build(boxes, search_sphere_.data(), ns);
  bound_facets(x, nnodes);
  prune_candidates();
  // The spheres' build-time centres are search_sphere_ (search_is_stale compares with them).
  search_->remember_positions(x, nnodes, nullptr, 0);
  node_shift_ = 0;
  search_stale_ = false;
  ++nrebuilds_;
}

// A body at rest (a still rigid body) keeps its bounds from one build to the next: the host
// re-neighbours often, the nodes and facets have not changed. Call before remember_positions.
void ParticleFacetContact::bound_facets(const double* x, int nnodes)
{
  bool same = bounded_facets_.size() == facets_.size() && search_->node_travel(x, nnodes) == 0;
  for (size_t k = 0; same && k < facets_.size(); ++k)
    same = bounded_facets_[k].n == facets_[k].n && bounded_facets_[k].nn == facets_[k].nn;
  if (same) return;
  bounded_facets_ = facets_;
  facet_bounds_.resize(facets_.size());
  for (size_t k = 0; k < facets_.size(); ++k) {
    const Facet& fc = facets_[k];
    facet_bounds_[k] =
        facet_bound(&x[3 * fc.n[0]], &x[3 * fc.n[1]], fc.nn == 3 ? &x[3 * fc.n[2]] : nullptr);
  }
}

// Until the next build a sphere and the nodes together move by at most `buffer` along every
// axis, so by at most sqrt(3) buffer in distance: a facet that the sphere's build-time centre
// cannot reach within r + sqrt(3) buffer can make no contact before then. The boxes of the
// search only bound this per axis, which on a curved or slanted surface keeps many facets more.
// The kept candidates of each sphere go to near_ with their distance bound, nearest first, so
// that gather_hits stops at the first one out of reach.
void ParticleFacetContact::prune_candidates()
{
  const double travel = std::sqrt(3.0) * search_->buffer();
  near_start_.assign(search_atoms_.size() + 1, 0);
  near_.clear();
  search_->prune([&](int s, int f) {
    const double* q = &search_sphere_[4 * s];
    const double gap = facet_distance_bound(facet_bounds_[f], q);
    if (gap > q[3] + travel) return false;
    near_.emplace_back(gap, f);
    ++near_start_[s + 1];
    return true;
  });
  // Candidates come sorted by sphere: near_ has the same entries in the same blocks.
  for (size_t s = 0; s + 1 < near_start_.size(); ++s) {
    near_start_[s + 1] += near_start_[s];
    std::sort(near_.begin() + near_start_[s], near_.begin() + near_start_[s + 1]);
  }
}

// The search spheres: every particle of the group, followed by those of its periodic images that
// come within reach of the body (as stock mesh walls see a particle's image across a periodic
// boundary). A particle's images follow it, so its spheres are consecutive.
void ParticleFacetContact::search_spheres(const ParticleArrays& p, const std::vector<Aabb>& boxes)
{
  search_atoms_.clear();
  search_sphere_.clear();
  search_shift_.clear();
  Aabb body;
  for (int d = 0; d < 3; ++d) {
    body.lo[d] = std::numeric_limits<double>::max();
    body.hi[d] = -std::numeric_limits<double>::max();
  }
  for (const Aabb& b : boxes)
    for (int d = 0; d < 3; ++d) {
      body.lo[d] = std::min(body.lo[d], b.lo[d]);
      body.hi[d] = std::max(body.hi[d], b.hi[d]);
    }
  const bool periodic = p.period[0] > 0 || p.period[1] > 0 || p.period[2] > 0;
  for (int i = 0; i < p.n; ++i) {
    if (!(p.mask[i] & p.groupbit)) continue;
    search_atoms_.push_back(i);
    search_sphere_.insert(search_sphere_.end(), {p.x[i][0], p.x[i][1], p.x[i][2], p.radius[i]});
    search_shift_.insert(search_shift_.end(), {0.0, 0.0, 0.0});
    if (!periodic) continue;
    const double reach = p.radius[i] + search_->buffer();
    for (int image = 0; image < 27; ++image) {
      const int k[3] = {image % 3 - 1, image / 3 % 3 - 1, image / 9 - 1};
      if (k[0] == 0 && k[1] == 0 && k[2] == 0) continue;
      double shift[3], q[3];
      bool near = true;
      for (int d = 0; d < 3; ++d) {
        if (k[d] != 0 && p.period[d] <= 0) near = false;
        shift[d] = k[d] * p.period[d];
        q[d] = p.x[i][d] + shift[d];
        if (q[d] + reach < body.lo[d] || q[d] - reach > body.hi[d]) near = false;
      }
      if (!near) continue;
      search_atoms_.push_back(i);
      search_sphere_.insert(search_sphere_.end(), {q[0], q[1], q[2], p.radius[i]});
      search_shift_.insert(search_shift_.end(), {shift[0], shift[1], shift[2]});
    }
  }
}

bool ParticleFacetContact::search_is_stale(const ParticleArrays& p, const double* x, int nnodes)
{
  if (search_stale_) return true;
  // BufferedSearch::needs_rebuild, without copying the centres: largest axis displacement of a
  // sphere plus that of a node against the buffer.
  double ds = 0;
  for (size_t s = 0; s < search_atoms_.size(); ++s)
    for (int d = 0; d < 3; ++d)
      ds = std::max(ds, std::fabs(p.x[search_atoms_[s]][d] + search_shift_[3 * s + d] -
                                  search_sphere_[4 * s + d]));
  return search_->node_travel(x, nnodes, &node_shift_) + ds > search_->buffer();
}

ParticleFacetResult ParticleFacetContact::evaluate(const ParticleArrays& p, const double* X,
                                                   const double* x, const double* v, double dt,
                                                   double* f_nodes)
{
  ParticleFacetResult res;
  if (facets_.empty()) return res;
  if (p.n == 0) {
    // No particle on this rank (an FE-only scene, or a rank whose particles are elsewhere):
    // nothing to search, and no node travel to watch; the first particle rebuilds the search.
    checks_.clear();
    contacts_.clear();
    search_stale_ = true;
    return res;
  }
  // The search covers only this rank's particles against the replicated body, so each rank
  // decides on its own when to rebuild (no collective needed).
  if (search_is_stale(p, x, nnodes_)) rebuild_search(p, x, nnodes_);

  // Per-particle work of this step, read by the load balancer (fix balance/graph).
  checks_.assign(p.n, 0);
  contacts_.assign(p.n, 0);
  touched_.resize(p.slots);
  const auto& cand = search_->candidates();
  size_t c = 0;
  while (c < cand.size()) {
    const int i = search_atoms_[cand[c].first];
    // The particle and its periodic images: each image's hits are resolved on their own, then
    // all of them form the particle's contacts (one history row, one force).
    hits_.clear();
    hit_centres_.clear();
    while (c < cand.size() && search_atoms_[cand[c].first] == i) {
      const double* shift = &search_shift_[3 * cand[c].first];
      const double q[3] = {p.x[i][0] + shift[0], p.x[i][1] + shift[1], p.x[i][2] + shift[2]};
      gather_hits(p, i, q, x, c);
      if (image_hits_.empty()) continue;
      for (const FacetHit& h : resolve_sphere_hits(std::move(image_hits_), q, x, topology_)) {
        hits_.push_back(h);
        hit_centres_.insert(hit_centres_.end(), {q[0], q[1], q[2]});
      }
    }
    double* hist = p.history ? p.history[i] : nullptr;
    if (hits_.empty()) { // forget the history of contacts that ended
      if (hist) clear_history_row(hist, p.slots);
      continue;
    }
    contacts_[i] += static_cast<int>(hits_.size());
    res.contacts += particle_contacts(p, i, X, x, v, dt, f_nodes, res);
  }
  return res;
}

// Closest points of particle i, centred at q (itself or a periodic image), on the candidate
// facets of one search sphere (starting at cand[c]); keeps the overlapping ones in image_hits_
// and advances c past the sphere's candidates.
void ParticleFacetContact::gather_hits(const ParticleArrays& p, int i, const double q[3],
                                       const double* x, size_t& c)
{
  const int s = search_->candidates()[c].first;
  c = near_start_[s + 1];
  image_hits_.clear();
  const double r = p.radius[i];
  // Since the build the centre moved by `moved` and every facet point by at most node_shift_,
  // so the distance can have shrunk by their sum: a candidate whose build-time bound exceeds
  // r + moved + node_shift_ cannot overlap (the exact test would reject it too).
  const double* q0 = &search_sphere_[4 * s];
  const double dq[3] = {q[0] - q0[0], q[1] - q0[1], q[2] - q0[2]};
  const double moved = std::sqrt(dq[0] * dq[0] + dq[1] * dq[1] + dq[2] * dq[2]);
  const double reach = (r + moved + node_shift_) * (1 + 1e-12);
  near_picked_.clear();
  for (size_t k = near_start_[s]; k < c && near_[k].first <= reach; ++k)
    near_picked_.push_back(near_[k].second);
  // In facet order, as the candidates come: the hits' order decides ties downstream.
  std::sort(near_picked_.begin(), near_picked_.end());
  // Only the exact tests count as checks (the load balancer prices a check as a closest point).
  checks_[i] += static_cast<int>(near_picked_.size());
  for (const int f : near_picked_) {
    const Facet& fc = facets_[f];
    FacetHit h;
    h.facet = f;
    h.nn = fc.nn;
    for (int j = 0; j < 3; ++j)
      h.nodes[j] = fc.n[j];
    if (fc.nn == 3)
      h.cp = closest_point_triangle(q, &x[3 * fc.n[0]], &x[3 * fc.n[1]], &x[3 * fc.n[2]]);
    else
      h.cp = closest_point_segment(q, &x[3 * fc.n[0]], &x[3 * fc.n[1]]);
    if (h.cp.dist2 < r * r) image_hits_.push_back(h);
  }
}

// Unit normal (surface to the centre that made the hit) and overlap of every kept hit.
void ParticleFacetContact::hit_normals(double r, const double* x)
{
  const int nh = static_cast<int>(hits_.size());
  normals_.resize(3 * nh);
  overlaps_.resize(nh);
  for (int k = 0; k < nh; ++k) {
    const FacetHit& h = hits_[k];
    const double* q = &hit_centres_[3 * k];
    const double dist = std::sqrt(h.cp.dist2);
    double* nk = &normals_[3 * k];
    if (dist > 1e-12 * r) {
      for (int d = 0; d < 3; ++d)
        nk[d] = (q[d] - h.cp.p[d]) / dist;
    } else { // centre on the surface: the facet normal
      double nrm[3];
      facet_normal(x, h.nodes, h.nn, nrm);
      const double l = std::sqrt(nrm[0] * nrm[0] + nrm[1] * nrm[1] + nrm[2] * nrm[2]);
      for (int d = 0; d < 3; ++d)
        nk[d] = nrm[d] / l;
    }
    overlaps_[k] = r - dist;
  }
}

// The resolved hits of particle i as physical contacts: one per cluster of like normals,
// evaluated at the deepest hit. Returns the number of contacts.
int ParticleFacetContact::particle_contacts(const ParticleArrays& p, int i, const double* X,
                                            const double* x, const double* v, double dt,
                                            double* f_nodes, ParticleFacetResult& res)
{
  const double r = p.radius[i];
  const ContactMaterial& mat = materials_[p.type[i]];
  hit_normals(r, x);
  double* hist = p.history ? p.history[i] : nullptr;
  std::fill(touched_.begin(), touched_.end(), 0);
  int ncontacts = 0;
  const int nh = static_cast<int>(hits_.size());
  // Hits are grouped by the reference normals of their facets: a sphere pressed deep into one
  // surface region bends its facets by more than the clustering angle, yet it is one contact
  // (grouping by the current normals counted it twice at high impact speeds).
  region_normals_.resize(3 * nh);
  hit_pieces_.resize(nh);
  for (int k = 0; k < nh; ++k) {
    for (int d = 0; d < 3; ++d)
      region_normals_[3 * k + d] = facet_ref_normal_[3 * hits_[k].facet + d];
    hit_pieces_[k] = facet_piece_[hits_[k].facet];
  }
  // Separate fragments are separate contacts: each carries the reaction of its own overlap.
  for (const std::vector<int>& cluster :
       cluster_hits(region_normals_.data(), overlaps_.data(), nh, hit_pieces_.data())) {
    // The contact acts at its deepest hit: the overlap, the surface velocity and the point
    // reaction all belong to that one point, so the law's force does exactly the work its
    // potential loses (sharing the reaction among the cluster's facets by overlap^1.5, as
    // before, let a sphere pressing a plastic dent gain 3 % of its impact energy).
    const FacetHit& lead = hits_[cluster[0]];
    ContactInput in;
    for (int d = 0; d < 3; ++d)
      in.n[d] = normals_[3 * cluster[0] + d];
    in.delta = overlaps_[cluster[0]];
    in.radius = r;
    in.mass = p.rmass[i];
    in.dt = dt;
    double vsurf[3] = {0, 0, 0};
    for (int j = 0; j < lead.nn; ++j)
      for (int d = 0; d < 3; ++d)
        vsurf[d] += lead.cp.w[j] * v[3 * lead.nodes[j] + d];
    for (int d = 0; d < 3; ++d) {
      in.v_rel[d] = p.v[i][d] - vsurf[d];
      in.omega[d] = p.omega[i][d];
    }
    double scratch[3] = {0, 0, 0};
    double* shear = scratch;
    if (opt_.tangential_history && hist) {
      FacetHit keyed = lead;
      if (!key_nodes_.empty())
        for (int j = 0; j < lead.nn; ++j)
          keyed.nodes[j] = key_nodes_[lead.nodes[j]];
      double* slot = history_slot(hist, p.slots, feature_key(keyed), true, &res.history_exhausted);
      if (slot) {
        shear = slot + 2;
        touched_[(slot - hist) / kHistorySlotDoubles] = 1;
      }
    }
    check_time_resolution(mat, in, res);
    // An unresolved contact (disc smaller than the mesh) stays a point contact.
    const bool spread = opt_.hertz_patch && hertz_contact_patch(lead, X, x, in, r);
    if (opt_.hertz_patch) res.patch_radii = std::max(res.patch_radii, patch_reach_ / r);
    in.mass = contact_mass(p.rmass[i], lead, spread);
    if (hold_history_) { // the law reads the spring but does not grow it (dt 0), on a copy
      if (shear != scratch) std::copy(shear, shear + 3, scratch);
      shear = scratch;
      in.dt = 0;
    }
    const ContactOutput out = particle_surface_force(mat, in, shear);
    for (int d = 0; d < 3; ++d) {
      p.f[i][d] += out.force[d];
      p.torque[i][d] += out.torque[d];
    }
    ++ncontacts;
    if (spread) {
      for (size_t k = 0; k < patch_.nodes.size(); ++k)
        for (int d = 0; d < 3; ++d)
          f_nodes[3 * patch_.nodes[k] + d] -= patch_weights_[k] * out.force[d];
      continue;
    }
    // Reaction on the lead facet's nodes by the barycentric weights of the contact point: they
    // sum to one, so the pair's linear momentum balance holds to round-off.
    for (int j = 0; j < lead.nn; ++j)
      for (int d = 0; d < 3; ++d)
        f_nodes[3 * lead.nodes[j] + d] -= lead.cp.w[j] * out.force[d];
  }
  if (hist)
    for (int k = 0; k < p.slots; ++k)
      if (!touched_[k]) hist[k * kHistorySlotDoubles] = hist[k * kHistorySlotDoubles + 1] = -1;
  return ncontacts;
}

// Reduced mass of the particle and the surface point: the point's velocity (the lead facet's
// nodes by their weights w_j) changes by F sum_j w_j s_j / m_j per unit impulse when the reaction
// goes to the nodes by weights s_j (the same w_j for a point reaction, the Hertz patch's weights
// when spread), so 1 / m_surface = sum_j w_j s_j / m_j.
double ParticleFacetContact::contact_mass(double particle_mass, const FacetHit& lead,
                                          bool spread) const
{
  if (!node_mass_) return particle_mass;
  double inv_surface = 0;
  for (int j = 0; j < lead.nn; ++j) {
    const int a = lead.nodes[j];
    double s = lead.cp.w[j];
    if (spread) {
      s = 0;
      for (size_t k = 0; k < patch_.nodes.size(); ++k)
        if (patch_.nodes[k] == a) s = patch_weights_[k];
    }
    if (node_mass_[a] > 0) inv_surface += lead.cp.w[j] * s / node_mass_[a];
  }
  return particle_mass / (1 + particle_mass * inv_surface);
}

// A Hertz contact that the time step cannot follow gains or loses energy: flag the approach
// speeds at which one step covers more than kMaxApproachPerStep of the impact's penetration (the
// law's own stiffness: the body's compliance only deepens the penetration, so this is safe).
void ParticleFacetContact::check_time_resolution(const ContactMaterial& mat, const ContactInput& in,
                                                 ParticleFacetResult& res) const
{
  if (mat.model != NormalModel::Hertz || mat.Yeff <= 0) return;
  const double vn = -(in.v_rel[0] * in.n[0] + in.v_rel[1] * in.n[1] + in.v_rel[2] * in.n[2]);
  if (vn <= 0) return;
  const double reach =
      kMaxApproachPerStep * hertz_impact(mat.Yeff, in.radius, in.mass, vn).max_overlap;
  if (vn * in.dt <= reach) return;
  res.unresolved_speed = std::max(res.unresolved_speed, vn);
  res.resolving_dt = std::min(res.resolving_dt, reach / vn);
}

// Hertz's pressure and the radius from the measured indentation presume an elastic half-space
// under the contact. Where the body has begun to fail there (a damaged element at a patch node),
// the indentation is that of a softening or cracking material: taken into the radius, it makes
// the force grow with the body's displacement apart from the overlap, and spread by Hertz's
// weights the reaction does work the overlap never stored (a body breaking under spheres made
// many times their energy so). Such a contact acts at its point, as the law's potential says.
bool ParticleFacetContact::patch_touches_inelastic() const
{
  if (!inelastic_nodes_) return false;
  for (int v : patch_.nodes)
    if ((*inelastic_nodes_)[v]) return true;
  return false;
}

bool ParticleFacetContact::hertz_contact_patch(const FacetHit& lead, const double* X,
                                               const double* x, ContactInput& in, double radius)
{
  // Displacement into the body (along -n) at the contact point and around it.
  auto into_body = [&](int v) {
    double u = 0;
    for (int d = 0; d < 3; ++d)
      u -= (x[3 * v + d] - X[3 * v + d]) * in.n[d];
    return u;
  };
  double u_c = 0;
  for (int j = 0; j < lead.nn; ++j)
    u_c += lead.cp.w[j] * into_body(lead.nodes[j]);
  // The patch must reach the ring [1.5 a, 3.5 a] of the largest plausible contact radius; two
  // passes: the ring of the point-law radius first, then of the radius that gives.
  double a = std::sqrt(radius * in.delta);
  double delta_b = 0;
  patch_reach_ = 0;
  for (int pass = 0; pass < 2; ++pass) {
    const double reach = 3.6 * std::sqrt(2 * radius * (in.delta + delta_b));
    patch_reach_ = std::max(patch_reach_, reach);
    gather_surface_patch(topology_, x, lead.nodes, lead.nn, lead.cp.p, in.n, reach, patch_);
    if (patch_touches_inelastic()) return false;
    for (int v : patch_.nodes)
      indentation_disp_[v] = into_body(v);
    delta_b = local_indentation(radius, in.delta, u_c, indentation_disp_, patch_);
    a = std::sqrt(radius * (in.delta + delta_b));
  }
  if (!hertz_pressure_weights(patch_, node_area_, a, patch_weights_)) return false;
  in.contact_radius = a;
  return true;
}

} // namespace fracdem

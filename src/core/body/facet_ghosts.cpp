// Facet ghosts of a distributed body for particle contact (see facet_ghosts.h).
#include "body/facet_ghosts.h"

#include <algorithm>
#include <cstdio>
#include <limits>

namespace fracdem
{

namespace
{
constexpr double kBig = std::numeric_limits<double>::max();

void grow(Box& b, const double* q)
{
  for (int d = 0; d < 3; ++d) {
    b.lo[d] = std::min(b.lo[d], q[d]);
    b.hi[d] = std::max(b.hi[d], q[d]);
  }
}

bool is_empty(const Box& b)
{
  return b.lo[0] > b.hi[0];
}

Box facet_box(const Facet& f, const double* x)
{
  Box b = empty_box();
  for (int j = 0; j < f.nn; ++j)
    grow(b, &x[3 * f.n[j]]);
  return b;
}

// Ascending node numbers used by the given facets.
std::vector<int> nodes_of(const std::vector<Facet>& facets, const std::vector<int>& which)
{
  std::vector<int> nodes;
  for (int f : which)
    for (int j = 0; j < facets[f].nn; ++j)
      nodes.push_back(facets[f].n[j]);
  std::sort(nodes.begin(), nodes.end());
  nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
  return nodes;
}

int find(const std::vector<int>& sorted, int v)
{
  auto it = std::lower_bound(sorted.begin(), sorted.end(), v);
  return it != sorted.end() && *it == v ? static_cast<int>(it - sorted.begin()) : -1;
}
} // namespace

int GlobalSurface::node_index(int g) const
{
  return find(nodes, g);
}

GlobalSurface global_surface(const Mesh& whole, const std::vector<int>& elem_part)
{
  // The replicated body's own derivation (same facets, normals, pieces and areas, same bits).
  ParticleFacetContact whole_surface;
  whole_surface.rebuild_surface(whole);
  GlobalSurface s;
  s.facets = whole_surface.facets();
  s.ref_normal = whole_surface.reference_normals();
  s.piece = whole_surface.pieces();
  std::vector<int> all(s.facets.size());
  for (size_t f = 0; f < s.facets.size(); ++f) {
    s.part.push_back(elem_part[s.facets[f].elem]);
    all[f] = static_cast<int>(f);
  }
  s.nodes = nodes_of(s.facets, all);
  for (int g : s.nodes) {
    s.X.insert(s.X.end(), &whole.X[3 * g], &whole.X[3 * g] + 3);
    s.area.push_back(whole_surface.node_areas()[g]);
  }
  return s;
}

Box empty_box()
{
  Box b;
  for (int d = 0; d < 3; ++d) {
    b.lo[d] = kBig;
    b.hi[d] = -kBig;
  }
  return b;
}

bool boxes_overlap(const Box& a, const Box& b)
{
  for (int d = 0; d < 3; ++d)
    if (a.lo[d] > b.hi[d] || b.lo[d] > a.hi[d]) return false;
  return true;
}

Box particle_box(const ParticleArrays& p, double reach)
{
  Box b = empty_box();
  for (int i = 0; i < p.n; ++i)
    if (p.mask[i] & p.groupbit) grow(b, p.x[i]);
  if (is_empty(b)) return b;
  for (int d = 0; d < 3; ++d) {
    b.lo[d] = p.period[d] > 0 ? -kBig : b.lo[d] - reach;
    b.hi[d] = p.period[d] > 0 ? kBig : b.hi[d] + reach;
  }
  return b;
}

std::vector<int> facets_in_box(const std::vector<Facet>& facets, const double* x, const Box& box)
{
  std::vector<int> in;
  if (is_empty(box)) return in;
  for (size_t f = 0; f < facets.size(); ++f)
    if (boxes_overlap(facet_box(facets[f], x), box)) in.push_back(static_cast<int>(f));
  return in;
}

/* ---------------------------------------------------------------------- */

void FacetGhosts::init(const MeshPart& part, GlobalSurface surface)
{
  part_ = part.part;
  part_node_ = part.global_node;
  surface_ = std::move(surface);
  own_.clear();
  own_facets_.clear();
  for (size_t f = 0; f < surface_.facets.size(); ++f) {
    if (surface_.part[f] != part_) continue;
    Facet local = surface_.facets[f];
    for (int j = 0; j < local.nn; ++j)
      local.n[j] = find(part_node_, local.n[j]); // the element's nodes are all the part's
    own_.push_back(static_cast<int>(f));
    own_facets_.push_back(local);
  }
  dirty_ = true;
}

void FacetGhosts::configure(const ParticleFacetOptions& options,
                            std::vector<ContactMaterial> materials)
{
  contact_.configure(options);
  contact_.set_materials(std::move(materials));
  dirty_ = true;
}

// Box 1 grows by the particles' travel allowed until the next exchange (the buffer), their reach
// and that of the Hertz patch around a contact.
double FacetGhosts::reach(double rmax) const
{
  const ParticleFacetOptions& o = contact_.options();
  return o.buffer + rmax * (o.hertz_patch ? 1 + kPatchRadii : 1);
}

std::vector<double> FacetGhosts::local_boxes(const ParticleArrays& p, const double* x)
{
  rmax_ = 0;
  for (int i = 0; i < p.n; ++i)
    if (p.mask[i] & p.groupbit) rmax_ = std::max(rmax_, p.radius[i]);
  Box b1 = particle_box(p, reach(rmax_));
  core_ = particle_box(p, contact_.options().buffer);
  Box b2 = empty_box();
  for (const Facet& f : own_facets_)
    for (int j = 0; j < f.nn; ++j)
      grow(b2, &x[3 * f.n[j]]);
  if (!is_empty(b2))
    for (int d = 0; d < 3; ++d) {
      b2.lo[d] -= contact_.options().buffer;
      b2.hi[d] += contact_.options().buffer;
    }
  std::vector<double> out;
  for (const Box* b : {&b1, &b2}) {
    out.insert(out.end(), b->lo, b->lo + 3);
    out.insert(out.end(), b->hi, b->hi + 3);
  }
  return out;
}

void FacetGhosts::set_boxes(const std::vector<double>& all)
{
  const int nranks = static_cast<int>(all.size()) / kBoxDoubles;
  box1_.assign(nranks, empty_box());
  box2_.assign(nranks, empty_box());
  for (int r = 0; r < nranks; ++r) {
    const double* a = &all[static_cast<size_t>(kBoxDoubles) * r];
    std::copy(a, a + 3, box1_[r].lo);
    std::copy(a + 3, a + 6, box1_[r].hi);
    std::copy(a + 6, a + 9, box2_[r].lo);
    std::copy(a + 9, a + 12, box2_[r].hi);
  }
  // Part p sends to rank q when p's surface box meets q's particle box: both sides know it.
  send_to_.clear();
  recv_from_.clear();
  for (int q = 0; q < nranks; ++q) {
    if (q == part_) continue;
    if (boxes_overlap(box2_[part_], box1_[q])) send_to_.push_back(q);
    if (boxes_overlap(box2_[q], box1_[part_])) recv_from_.push_back(q);
  }
  sent_.assign(send_to_.size(), {});
  sent_local_.assign(send_to_.size(), {});
  recv_facets_.assign(recv_from_.size(), {});
  recv_nodes_.assign(recv_from_.size(), {});
  dirty_ = true;
  ++box_exchanges_;
}

std::string FacetGhosts::check_particles(const ParticleArrays& p) const
{
  for (int i = 0; i < p.n; ++i) {
    if (!(p.mask[i] & p.groupbit)) continue;
    bool inside = p.radius[i] <= rmax_;
    for (int d = 0; d < 3; ++d)
      inside = inside && p.x[i][d] >= core_.lo[d] && p.x[i][d] <= core_.hi[d];
    if (inside) continue;
    char text[320];
    std::snprintf(text, sizeof text,
                  "keyword 'parallel distributed': a particle at (%g, %g, %g) has moved more than "
                  "'buffer' %g since the particle boxes were exchanged (when the host last "
                  "re-neighboured); check neighbours every step ('neigh_modify every 1 check yes') "
                  "or raise 'buffer'",
                  p.x[i][0], p.x[i][1], p.x[i][2], contact_.options().buffer);
    return text;
  }
  return "";
}

/* ---------------------------------------------------------------------- */

std::string FacetGhosts::outgoing(const double* x, const double* v,
                                  std::vector<std::vector<double>>& out, const double* mass,
                                  const std::vector<char>* inelastic)
{
  // Only partners listen: a facet within reach of another rank's particles is an error (the
  // surface moved more than the buffer allows since the boxes were exchanged).
  Box now = empty_box();
  for (const Facet& f : own_facets_)
    for (int j = 0; j < f.nn; ++j)
      grow(now, &x[3 * f.n[j]]);
  for (int q = 0; q < static_cast<int>(box1_.size()); ++q) {
    if (q == part_ || !boxes_overlap(now, box1_[q])) continue;
    if (std::binary_search(send_to_.begin(), send_to_.end(), q)) continue;
    if (facets_in_box(own_facets_, x, box1_[q]).empty()) continue;
    return "keyword 'parallel distributed': the body's surface has moved more than 'buffer' since "
           "the particle boxes were exchanged (when the host last re-neighboured) and is now "
           "within reach of particles of rank " +
           std::to_string(q) + "; raise 'buffer' or re-neighbour more often";
  }
  std::vector<int> self;
  for (int i : facets_in_box(own_facets_, x, box1_[part_]))
    self.push_back(own_[i]);
  if (self != self_) {
    self_ = std::move(self);
    dirty_ = true;
  }
  out.resize(send_to_.size());
  for (size_t k = 0; k < send_to_.size(); ++k) {
    const std::vector<int> picked = facets_in_box(own_facets_, x, box1_[send_to_[k]]);
    std::vector<int> sel;
    for (int i : picked)
      sel.push_back(own_[i]);
    std::vector<double>& m = out[k];
    m.clear();
    const bool changed = sel != sent_[k];
    m.push_back(changed ? 1.0 : 0.0);
    if (changed) {
      sent_[k] = std::move(sel);
      sent_local_[k] = nodes_of(own_facets_, picked); // ascending = ascending global number
      m.push_back(static_cast<double>(sent_[k].size()));
      m.insert(m.end(), sent_[k].begin(), sent_[k].end());
    }
    for (int n : sent_local_[k]) {
      m.insert(m.end(), &x[3 * n], &x[3 * n] + 3);
      m.insert(m.end(), &v[3 * n], &v[3 * n] + 3);
      m.push_back(mass ? mass[n] : 0.0);
      m.push_back(inelastic && (*inelastic)[n] ? 1.0 : 0.0);
    }
  }
  return "";
}

// Reads the facet lists of the messages that carry one; node data start after them.
void FacetGhosts::assemble(const std::vector<std::vector<double>>& in)
{
  for (size_t k = 0; k < recv_from_.size(); ++k) {
    if (in[k][0] == 0.0) continue;
    const int nf = static_cast<int>(in[k][1]);
    recv_facets_[k].assign(in[k].begin() + 2, in[k].begin() + 2 + nf);
    std::vector<int> global;
    for (int f : recv_facets_[k])
      for (int j = 0; j < surface_.facets[f].nn; ++j)
        global.push_back(surface_.facets[f].n[j]);
    std::sort(global.begin(), global.end());
    global.erase(std::unique(global.begin(), global.end()), global.end());
    recv_nodes_[k] = std::move(global);
    dirty_ = true;
  }
  if (dirty_) build_surface();
  dirty_ = false;
}

// The local contact surface in global facet order and ascending global node numbers: a particle
// meets its facets in the order, and with the history keys, of the replicated body.
void FacetGhosts::build_surface()
{
  local_facets_ = self_;
  for (const std::vector<int>& r : recv_facets_)
    local_facets_.insert(local_facets_.end(), r.begin(), r.end());
  std::sort(local_facets_.begin(), local_facets_.end());
  local_nodes_ = nodes_of(surface_.facets, local_facets_);
  const int nn = static_cast<int>(local_nodes_.size());
  node_src_.assign(nn, -1);
  node_pos_.assign(nn, -1);
  X_.resize(3 * nn);
  std::vector<double> area(nn);
  for (int i = 0; i < nn; ++i) {
    const int g = local_nodes_[i];
    node_pos_[i] = find(part_node_, g);
    for (size_t k = 0; node_pos_[i] < 0 && k < recv_nodes_.size(); ++k) {
      const int pos = find(recv_nodes_[k], g);
      if (pos < 0) continue;
      node_src_[i] = static_cast<int>(k);
      node_pos_[i] = pos;
    }
    const int s = surface_.node_index(g);
    std::copy(&surface_.X[3 * s], &surface_.X[3 * s] + 3, &X_[3 * i]);
    area[i] = surface_.area[s];
  }
  std::vector<Facet> facets;
  std::vector<double> normals;
  std::vector<int> pieces;
  for (int f : local_facets_) {
    Facet lf = surface_.facets[f];
    for (int j = 0; j < lf.nn; ++j)
      lf.n[j] = find(local_nodes_, lf.n[j]);
    facets.push_back(lf);
    normals.insert(normals.end(), &surface_.ref_normal[3 * f], &surface_.ref_normal[3 * f] + 3);
    pieces.push_back(surface_.piece[f]);
  }
  contact_.set_surface(std::move(facets), nn, std::move(normals), std::move(pieces),
                       std::move(area), local_nodes_);
}

ParticleFacetResult FacetGhosts::evaluate(const ParticleArrays& p,
                                          const std::vector<std::vector<double>>& in,
                                          const double* x, const double* v, double dt,
                                          double* f_part, std::vector<std::vector<double>>& back,
                                          const double* mass, const std::vector<char>* inelastic)
{
  assemble(in);
  // Node data of message k start after its facet list.
  std::vector<size_t> start(in.size());
  for (size_t k = 0; k < in.size(); ++k)
    start[k] = in[k][0] == 0.0 ? 1 : 2 + static_cast<size_t>(in[k][1]);
  const int nn = static_cast<int>(local_nodes_.size());
  x_.resize(3 * nn);
  v_.resize(3 * nn);
  m_.resize(nn);
  inelastic_.assign(nn, 0);
  bool any_inelastic = false;
  for (int i = 0; i < nn; ++i) {
    const int k = node_src_[i], pos = node_pos_[i];
    const double* xs = k < 0 ? &x[3 * pos] : &in[k][start[k] + kNodeDoubles * pos];
    const double* vs = k < 0 ? &v[3 * pos] : xs + 3;
    std::copy(xs, xs + 3, &x_[3 * i]);
    std::copy(vs, vs + 3, &v_[3 * i]);
    m_[i] = k < 0 ? (mass ? mass[pos] : 0.0) : xs[6];
    inelastic_[i] = k < 0 ? (inelastic && (*inelastic)[pos]) : xs[7] != 0.0;
    any_inelastic = any_inelastic || inelastic_[i];
  }
  // Nodes of mass 0 count as infinitely heavy (ParticleFacetContact::contact_mass).
  contact_.set_node_masses(m_.data());
  contact_.set_inelastic_nodes(any_inelastic ? &inelastic_ : nullptr);
  f_.assign(3 * nn, 0.0);
  ParticleFacetResult res;
  if (nn > 0) res = contact_.evaluate(p, X_.data(), x_.data(), v_.data(), dt, f_.data());
  // Each node's force goes to one part: this one where it holds the node, else the lowest part
  // that sent it (the shared-node sum then gives every sharer the total).
  back.resize(recv_from_.size());
  for (size_t k = 0; k < recv_from_.size(); ++k)
    back[k].assign(3 * recv_nodes_[k].size(), 0.0);
  for (int i = 0; i < nn; ++i) {
    const int k = node_src_[i], pos = node_pos_[i];
    double* to = k < 0 ? &f_part[3 * pos] : &back[k][3 * pos];
    for (int d = 0; d < 3; ++d)
      to[d] += f_[3 * i + d];
  }
  return res;
}

void FacetGhosts::add_returned(const std::vector<std::vector<double>>& returned,
                               double* f_part) const
{
  for (size_t k = 0; k < send_to_.size(); ++k)
    for (size_t i = 0; i < sent_local_[k].size(); ++i)
      for (int d = 0; d < 3; ++d)
        f_part[3 * sent_local_[k][i] + d] += returned[k][3 * i + d];
}

} // namespace fracdem

// Particle contact with a distributed body: the whole surface's fixed description, the facets each
// part sends to the ranks whose particles can reach them (paper Box 1 / Box 2), forces returned.
#pragma once

#include <string>
#include <vector>

#include "body/body_partition.h"
#include "contact/particle_facet.h"
#include "fem/mesh.h"

namespace fracdem
{

// The Hertz patch (gather_surface_patch) reaches 3.6 sqrt(2 R (delta + delta_b)) in the plane of
// the contact: within this many radii of the particle while delta + delta_b < 0.6 R. Facet
// ghosts are sent that far (and the buffer) around a rank's particles; a deeper contact is
// warned about (its patch may miss facets of other parts).
constexpr double kPatchRadii = 4.0;

// The whole body's boundary surface, built once on every rank from the whole mesh (a distributed
// body neither breaks nor erodes, so it never changes). A facet's index here is its global key
// (boundary_facets order, the order a replicated body uses); nodes are global node numbers.
struct GlobalSurface {
  std::vector<Facet> facets;
  std::vector<int> part;          // per facet: the part of its element
  std::vector<double> ref_normal; // 3 per facet: outward unit normal, reference state
  std::vector<int> piece;         // per facet: connected piece label
  std::vector<int> nodes;         // surface nodes, ascending global number
  std::vector<double> X, area;    // per surface node: reference position (3), surface area
  // Index of global node g in `nodes` (-1 if g is not on the surface).
  int node_index(int g) const;
};
// elem_part: the element partition (partition_elements).
GlobalSurface global_surface(const Mesh& whole, const std::vector<int>& elem_part);

// An axis-aligned box; empty when lo > hi.
struct Box {
  double lo[3], hi[3];
};
Box empty_box();
bool boxes_overlap(const Box& a, const Box& b);
// The particle box of a rank (paper Box 1): its particles of the group, grown by reach along every
// axis; unbounded along periodic axes (the particles' images). Empty without particles.
Box particle_box(const ParticleArrays& p, double reach);
// Indices (ascending) of the facets whose box at node positions x (3 per node) overlaps box.
std::vector<int> facets_in_box(const std::vector<Facet>& facets, const double* x, const Box& box);

// One rank's side of the contact of its particles with a distributed body, whose part it holds.
// The driver calls, on every rank at the same steps:
//   after the host re-neighbours: all = allgather(local_boxes(...)); set_boxes(all)
//   each step: check_particles; outgoing -> exchange to send_to() / from recv_from();
//              evaluate -> exchange back; add_returned.
// Exchanges are one message per partner; partners follow from the boxes, the same on both sides.
class FacetGhosts
{
public:
  static constexpr int kBoxDoubles = 12; // Box 1, Box 2

  void init(const MeshPart& part, GlobalSurface surface);
  void configure(const ParticleFacetOptions& options, std::vector<ContactMaterial> materials);

  // ---- box exchange ----
  // This rank's Box 1 (particles within reach) and Box 2 (its part's surface at x, the part's
  // positions, grown by the search buffer).
  std::vector<double> local_boxes(const ParticleArrays& p, const double* x);
  // Every rank's local_boxes, in rank order: the partners of this rank.
  void set_boxes(const std::vector<double>& all);
  // "" while this rank's particles stay where its Box 1 covers them, else why not.
  std::string check_particles(const ParticleArrays& p) const;

  // ---- each step ----
  // Messages to send_to(): the facets within reach of each partner's particles (their global
  // keys when they changed) and the positions and velocities of their nodes. x, v: the part's.
  // Returns "" or the error (a facet came within reach of a rank that is no partner).
  // mass: the part's lumped node masses, inelastic: its nodes at damaged elements (see
  // ParticleFacetContact::set_node_masses / set_inelastic_nodes); nullptr: none.
  std::string outgoing(const double* x, const double* v, std::vector<std::vector<double>>& out,
                       const double* mass = nullptr,
                       const std::vector<char>* inelastic = nullptr);
  // The contact of this rank's particles with its own facets within reach and those received
  // (in[k] from recv_from()[k]); forces of the part's nodes are added to f_part, the others go
  // back[k] to the part that sent them (each node to one part: the lowest that sent it).
  ParticleFacetResult evaluate(const ParticleArrays& p, const std::vector<std::vector<double>>& in,
                               const double* x, const double* v, double dt, double* f_part,
                               std::vector<std::vector<double>>& back,
                               const double* mass = nullptr,
                               const std::vector<char>* inelastic = nullptr);
  // Doubles per node in a message: position, velocity, mass, inelastic flag.
  static constexpr int kNodeDoubles = 8;
  // Forces returned by send_to()[k] (returned[k]) added to the part's nodes.
  void add_returned(const std::vector<std::vector<double>>& returned, double* f_part) const;

  const std::vector<int>& send_to() const { return send_to_; }
  const std::vector<int>& recv_from() const { return recv_from_; }
  const ParticleFacetContact& contact() const { return contact_; }
  void hold_history(bool hold) { contact_.hold_history(hold); } // ParticleFacetContact's
  const GlobalSurface& surface() const { return surface_; }     // the whole body's
  int surface_facets() const { return static_cast<int>(local_facets_.size()); }
  int box_exchanges() const { return box_exchanges_; }

private:
  double reach(double rmax) const;
  void assemble(const std::vector<std::vector<double>>& in);
  void build_surface();

  int part_ = 0;
  std::vector<int> part_node_; // global numbers of the part's nodes, ascending
  GlobalSurface surface_;
  std::vector<int> own_;          // facets of the part's elements (surface indices)
  std::vector<Facet> own_facets_; // the same, nodes numbered as in the part
  std::vector<Box> box1_, box2_;  // per rank
  Box core_ = empty_box();        // this rank's particles at the exchange, grown by the buffer
  double rmax_ = 0;               // their largest radius
  std::vector<int> send_to_, recv_from_;
  std::vector<std::vector<int>> sent_, sent_local_; // per send_to: facets, their nodes (part-local)
  std::vector<std::vector<int>> recv_facets_, recv_nodes_; // per recv_from: facets, nodes (global)
  std::vector<int> self_;                                  // own facets within own Box 1
  bool dirty_ = true;
  // The local contact surface: facets (surface indices, ascending), nodes (global, ascending),
  // where each node's position comes from and where its force goes: source -1 the part (index
  // in the part), else recv_from index k (position in recv_nodes_[k]).
  std::vector<int> local_facets_, local_nodes_, node_src_, node_pos_;
  std::vector<double> X_, x_, v_, f_, m_;
  std::vector<char> inelastic_;
  ParticleFacetContact contact_;
  int box_exchanges_ = 0;
};

} // namespace fracdem

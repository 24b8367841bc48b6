// The finite-element body: one owner of its nodal and element state, its explicit update and
// its topology operations (node split, erosion).
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "fem/body_motion.h"
#include "fem/edge_bisect.h"
#include "fem/fe_space.h"
#include "materials/material.h"
#include "fem/mesh.h"
#include "fem/node_split.h"
#include "fracture/crack_tracking.h"

namespace fracdem
{

// Boundary condition of a node: free, held in place, moving at a prescribed velocity, or held
// in some components only (Partial: see the node's held-component mask; a held component moves
// at its prescribed velocity, 0 where `fixed` holds it).
enum class NodeBc : std::uint8_t { Free = 0, Fixed = 1, Prescribed = 2, Partial = 3 };

// What eroded elements took out of the body: their count, the mass removed with them
// (erosion_mass remove), the strain energy they held plus the kinetic energy of the removed mass,
// and the momentum of the removed mass. The energy balance reads
// kinetic + strain + dissipated + energy = initial + external + contact + boundary + shield work.
struct ErosionAccount {
  int elements = 0;
  double mass = 0, energy = 0;
  double momentum[3] = {0, 0, 0};
};

// A deformable (or rigid, prescribed-motion) body, replicated on every rank of a run. The host
// adapter moves data between it and the host; the body does the physics:
//   step:  half_kick_drift(dt)  -> forces: begin_forces(), add_internal_forces(),
//          contact into contact_forces(), [sum over ranks] finish_forces() -> half_kick(dt)
// Per-node arrays (3 doubles per node where vectors) grow together when a node is split.
class Body
{
public:
  // Takes the (placed) mesh, precomputes the element data and lumped masses. Throws FeError.
  void build(Mesh mesh, const Material& material, bool rigid);
  // This rank's share [begin, end) of the element work (the body itself is replicated).
  void set_element_range(int begin, int end);

  // ---- boundary conditions and initial state ----
  // Artificial bulk viscosity (materials/bulk_viscosity.h); off after build. Turning it on keeps
  // each element's viscous work and last viscous force (restart record version 3).
  void set_bulk_viscosity(const BulkViscosity& bv);
  // The set-up evaluation of a run (the host's, at unchanged positions) repeats the viscous
  // forces of the last counted evaluation (or of the restart record) instead of taking them from
  // the full-step velocities: the viscous force of a step is that of its mid-step velocities, so
  // a run continued (second 'run', or read_restart) goes on as the uninterrupted one. A body
  // never evaluated takes its velocities.
  void replay_viscous_forces_once() { replay_viscous_ = viscous_evaluated_; }
  const BulkViscosity& bulk_viscosity() const { return viscosity_; }

  // Holds the components in `mask` (bit d: component d; 7 = all) of `nodes`. group: index of
  // the reaction account these nodes report to (-1: none).
  void set_fixed(const std::vector<int>& nodes, int mask = 7, int group = -1);
  // Moves the components in `mask` of `nodes` at velocity v, ramped linearly from 0 over `ramp`
  // (0: at once); their reactions go to `group`. With mask 7 the node is Prescribed; otherwise
  // the other components stay as they were (free, or held by `fixed`) and the node is Partial,
  // its held components moving at v_prescribed (0 where `fixed` holds them), with this ramp.
  void set_prescribed_velocity(const std::vector<int>& nodes, const double v[3], double ramp = 0,
                               int group = -1, int mask = 7);
  // Sets the components in `mask` of the nodes' velocities (the others are left as they are).
  void set_velocity(const std::vector<int>& nodes, const double v[3], int mask = 7);
  // Velocities of fixed / prescribed nodes set to their conditions (after initial velocities).
  void impose_velocity_conditions();
  void set_rigid_motion(const RigidMotion& motion) { motion_ = motion; }
  // A part of a distributed body lumps at the nodes it shares only its own elements' mass; the
  // host sums the parts' masses (InterfaceSum, body/body_partition.h) and sets the totals here.
  void set_masses(const std::vector<double>& mass);
  // A part of a distributed body counts in its sums over nodes (kinetic energy, momentum,
  // contact and gravity work, reactions, total contact force, axis shield) only the nodes it
  // owns, so that the sum over the parts counts a shared node once (MeshPart::owns). Empty: all.
  void set_counted_nodes(std::vector<std::uint8_t> counted);
  // A part of a distributed body marks the nodes it shares with other parts (MeshPart). An
  // erosion with remove_mass takes no mass off them at once: the part keeps what its elements
  // took (shared_taken) until the parts have summed it (settle_shared_masses), so that every
  // sharer drops the same mass with the same bits. Empty: none.
  void set_shared_nodes(std::vector<std::uint8_t> shared);

  // ---- explicit update (velocity Verlet, in step with the host) ----
  void advance_time(double dt) { time_ += dt; }
  void move_rigid(); // rigid body: positions and velocities from the prescribed motion at time()
  void half_kick_drift(double dt);
  void half_kick(double dt);
  // Zeroes the force and contact buffers.
  void begin_forces();
  // Zeroes the internal forces only (to take them again after an erosion within the step).
  void clear_internal_forces() { std::fill(f_.begin(), f_.end(), 0.0); }
  // A sub-cycled FE step between two contact evaluations of the host (BodyDriver): the contact
  // forces of the last evaluation act again, and finish_forces counts their work over the substep.
  void hold_contact_forces() { f_contact_ = f_contact_prev_; }
  // After the force evaluation that closes a sub-cycled host step dt = n h (finish_forces keeps
  // the contact forces C of this evaluation and, in contact_forces(), those held before, C0):
  // the kick tau (C - C0) with tau = (dt - h) / 2 that gives the body the velocity-Verlet
  // impulse dt (C0 + C) / 2 of the host step (the held force gave it (dt - h / 2) C0 + h C / 2),
  // as its contact partners receive it. Its work (the exact kinetic energy it adds) is contact
  // work. Held components (fixed, prescribed) are not kicked.
  void kick_contact_difference(double tau);
  // Internal forces of this rank's elements into forces(); returns their strain energy.
  // An inverted element (det F <= 0) sets *first_inverted (if still < 0). With bulk viscosity the
  // viscous forces of the current (mid-step) velocities are added; their work is counted once per
  // step by finish_forces, so a second call within a step (after an erosion) counts nothing twice.
  double add_internal_forces(int* first_inverted);
  // After contact_forces() holds every rank's contributions and the strain energy is summed:
  // contact work and bulk-viscosity work (trapezoidal, mid-step velocities), gravity and its
  // work (deformable only),
  // the total contact force, zero force on held nodes. `count_work` is false during set-up.
  void finish_forces(double strain_energy, const double gravity[3], double dt, bool count_work);

  // ---- topology ----
  // Plans the split of `node` along the plane through its current position with normal n
  // (fracture/node_split.h); the plan has an empty side where no split is possible.
  SplitPlan plan_split(int node, const double n[3]) const
  {
    return plan_node_split(mesh_, stars_, x_.data(), node, n);
  }
  // Gives plan.node a copy that the elements plan.side_b use from now on. The copy starts with
  // the node's position, velocity and condition; it takes its elements' share of the lumped
  // mass and the node keeps the rest, and the force is shared in proportion, so mass, momentum
  // and force sums are unchanged (to round-off). Returns the copy's index.
  int split_node(const SplitPlan& plan);
  SplitPlan plan_separation(int node) const { return plan_star_separation(mesh_, stars_, node); }
  // Stable step of element e alone in the current configuration (1e300 if eroded), reduced by
  // the bulk viscosity's damping at the element's last volumetric strain rate.
  double element_time_step(int e) const
  {
    if (!viscosity_.on) return space_.element_time_step(mesh_, x_.data(), e);
    return space_.element_time_step(mesh_, x_.data(), e, viscosity_, viscous_rate_[e]);
  }
  const NodeStars& stars() const { return stars_; }
  // Removes elements from the body. Their strain energy now (evaluated on a copy of their state)
  // leaves the body's strain energy for the erosion account. By default their nodes keep the mass
  // and a node left without elements goes on as a free point mass; with remove_mass each
  // element's lumped mass is taken off its nodes (with its momentum and kinetic energy, counted),
  // and a node left without elements keeps neither mass nor velocity (it stays where it is).
  // Returns the energy the erosion took out (strain + kinetic of removed mass).
  double erode(const std::vector<int>& elems, bool remove_mass = false);
  const ErosionAccount& eroded() const { return eroded_; }
  // Shared nodes (set_shared_nodes): the mass this part's erosions took off node n since the last
  // settle, and the part's active elements around n.
  double shared_taken(int n) const { return taken_.empty() ? 0.0 : taken_[n]; }
  int active_elements(int n) const { return static_cast<int>(stars_.end(n) - stars_.begin(n)); }
  // field[width * n + at], [.. + at + 1]: the mass taken off shared node n and the active elements
  // around it, each summed over the parts that share n (the same bits on every sharer). Every
  // sharer drops that mass; a node of an eroded element left without any element on any part
  // keeps neither mass nor velocity, as erode does, the rest counted as eroded by the part that
  // counts the node. Returns the kinetic energy removed here.
  double settle_shared_masses(const double* field, int width, int at);

  // ---- state ----
  const Mesh& mesh() const { return mesh_; }
  const FeSpace& space() const { return space_; }
  const Material& material() const { return material_; }
  bool rigid() const { return rigid_; }
  int num_nodes() const { return mesh_.num_nodes(); }
  const std::vector<double>& positions() const { return x_; }
  const std::vector<double>& velocities() const { return v_; }
  const std::vector<double>& forces() const { return f_; }
  const std::vector<double>& masses() const { return mass_; }
  double total_mass() const; // the lumped masses of the counted nodes
  const std::vector<NodeBc>& conditions() const { return bc_; }
  const std::vector<int>& parents() const { return parent_; } // -1: not a split copy

  // ---- cracks through elements (fem/body_cut.cpp) ----
  // Bisects edge uw at P = u + t (w - u) (fem/edge_bisect.h: every element around the edge split
  // in two; a tri3 / tet4 slot keeps the child with u, measure t; a quad4 is split into a quad4,
  // kept in its slot, and a tri3 as `joins` says). P's reference and current positions are
  // interpolated; a tri3 / tet4 child copies its parent's material state (its strain is the
  // parent's: the displacement is linear along the edge), a quad4's children take each point's
  // state from the parent's nearest point; the viscous accounts are shared by measure. P takes
  // the lumped mass the nodes around the edge lose (u and w; with a quad4 also its other nodes,
  // whose shares change, and a node that gains takes its gain at the mean velocity of what was
  // lost), with its momentum and a share of the forces in the same proportion, so mass,
  // momentum and force sums are unchanged (to round-off) and the kinetic energy never grows;
  // P moves at the interpolated velocity exactly where the lumped shares are equal (plane
  // tri3, tet4). P is held in the components both ends hold (prescribed if both are, at the
  // interpolated velocity) and joins the node sets that hold both. A whole-body element range
  // grows with the mesh; a shared one must be set again. Returns P; new_elems (optional) gets
  // the appended elements, one per element around the edge. Throws std::invalid_argument when
  // the edge is not bisectable, a quad4 around it has no valid join or t is outside (0, 1).
  int bisect_edge(int u, int w, double t, std::vector<int>* new_elems = nullptr,
                  const std::vector<QuadJoin>& joins = {});
  // Elements of the mesh as built; the ones after them came from cuts, each with its parent.
  int mesh_elements() const { return mesh_elems_; }
  int element_parent(int e) const { return e < mesh_elems_ ? -1 : elem_parent_[e - mesh_elems_]; }
  // Element e's reference measure as a fraction of the mesh element it is a piece of (1 for
  // mesh elements).
  double piece_fraction(int e) const;
  // Nodes made by cuts: (P, u, w) per cut, in order.
  const std::vector<int>& cut_nodes() const { return cut_nodes_; }
  bool counted(int n) const { return counted_.empty() || counted_[n]; }
  // Force (3 per reaction group) that the constraints applied to the body in the last force
  // evaluation: m a - f summed over the group's held components.
  const std::vector<double>& reactions() const { return reactions_; }
  double* forces_data() { return f_.data(); }
  double* contact_forces() { return f_contact_.data(); }
  // Contact forces computed by another body's step (body-body contact) before this body's
  // force evaluation; begin_forces() moves them into contact_forces().
  double* pending_contact_forces() { return f_pending_.data(); }
  double time() const { return time_; }
  double strain_energy() const { return strain_energy_; }
  double external_work() const { return external_work_; }
  double contact_work() const { return contact_work_; }
  // Work done on the body by its prescribed-velocity constraints (fixed nodes do none).
  double boundary_work() const { return boundary_work_; }
  // Axisymmetric bodies: work of the axis shield (<= 0: the radial kinetic energy of the nodes
  // it stopped at r = 0) and the number of times it stopped a node.
  double shield_work() const { return shield_work_; }
  long shield_hits() const { return shield_hits_; }
  const double* contact_force_total() const { return contact_force_total_; }
  double kinetic_energy() const;
  double momentum(int d) const;
  double stable_time_step() const
  {
    return space_.stable_time_step(mesh_, x_.data(), &viscosity_, viscous_rate_.data());
  }
  // Material history of every integration point (layout: FeSpace::state_offset).
  const std::vector<double>& material_state() const { return state_; }
  // Cauchy stress of element e now (Voigt 6), without advancing its history.
  void element_stress(int e, double sigma[6]) const
  {
    space_.element_stress(mesh_, x_.data(), e, sigma, state_.data());
  }
  // Failure measure of element e (largest of its points: 0 intact .. 1 carries no more
  // tension) and the crack normal of that point.
  double element_failure(int e, double normal[3]) const;
  // The same for every element at once (normal: 3 per element, set only where measure > 0);
  // undamaged elements cost one comparison per point. Returns the number of damaged elements.
  int element_failures(std::vector<double>& measure, std::vector<double>& normal) const;
  // Whether a point of element e is damaged, read from its material state (not from the last
  // force evaluation's list): false for eroded elements and materials without damage.
  bool element_damaged(int e) const;
  // Whether a point of element e has yielded (equivalent plastic strain > 0; plastic models
  // only): false for eroded elements and materials without plasticity.
  bool element_yielded(int e) const;
  // The elements at failure measure 1 (a point carries no more tension), ascending, as the last
  // force evaluation found them when it covered the whole body (else null: use
  // element_failures). An element eroded since then may be listed.
  const std::vector<int>* failed_elements() const
  {
    return elem_begin_ <= 0 && elem_end_ >= mesh_.num_elems() ? &failed_elems_ : nullptr;
  }
  // Energy dissipated by the material (cracking) in the whole body so far.
  double dissipated_energy() const;
  // Integration points with any damage at the last force evaluation (of this rank's elements).
  int damaged_points() const { return damaged_points_; }
  // Strain energy per element now (0 for eroded ones), without advancing any history.
  void element_energies(std::vector<double>& energy) const;
  // Work of the bulk viscosity so far (>= 0 up to the trapezoidal rule: energy taken out of the
  // body), in all and per element (empty when the viscosity is off).
  double viscous_work() const;
  const std::vector<double>& element_viscous_work() const { return viscous_work_; }
  // Plastic materials: per element the weighted mean over its integration points of the
  // equivalent plastic strain, the temperature rise (K) and the plastic work per unit volume
  // (0 for eroded elements). Returns false (vectors untouched) for other materials.
  bool element_plastic_state(std::vector<double>& eps_bar, std::vector<double>& temperature_rise,
                             std::vector<double>& plastic_work) const;

  // Bytes this body holds on one rank (it is replicated on every rank): the capacities of its
  // nodal, element, boundary-condition and material-state arrays, its mesh (with the named
  // sets) and its precomputed element data. Grows when fracture splits nodes.
  std::size_t memory_bytes() const;

  // ---- crack tracking (fracture/crack_tracking.h): only the tracked bands may soften ----
  // Turns tracking on with length L (averaging radius) and the nucleation exclusion radius
  // (<= 0: L); every element starts unmarked, so nothing softens until a crack starts.
  void set_crack_tracking(double length, double exclusion = 0);
  bool crack_tracking() const { return track_length_ > 0; }
  // One tracker round after a force evaluation that covered the whole body: tips of damaged
  // elements advance, elements held at the strength start cracks.
  TrackEvents track_cracks();
  const CrackTrackState& track_state() const { return track_; }
  void set_track_state(CrackTrackState state); // restart
  // Elements held elastic whose stress reached the strength at the last force evaluation.
  const std::vector<int>& overstressed_elements() const { return overstressed_elems_; }

  // ---- restart: the whole state including topology (split nodes, connectivity, activity) ----
  void pack_state(std::vector<double>& buf) const;
  // Restores a state packed by pack_state (or a version-1 record: positions, velocities and
  // activity of an unsplit body); the record's length follows from its header. Throws
  // std::runtime_error when the record does not fit this body's mesh.
  void unpack_state(const double* buf);

  // ---- the state a run of an unbroken body changes, piece by piece (restart of distributed
  // bodies at any rank count: each part contributes its nodes and elements by global index) ----
  // Clock and work accounts (a part's share; the body's are the sums over the parts).
  struct Accounts {
    double time = 0, external = 0, contact = 0, boundary = 0, shield_work = 0, shield_hits = 0;
  };
  Accounts accounts() const;
  void set_accounts(const Accounts& a);
  // Node n's position and velocity (6 doubles).
  void set_node_motion(int n, const double* xv);
  // Element e's history: its points' material state, then with bulk viscosity its viscous work,
  // last viscous force and strain rate.
  int element_record_size(int e) const;
  void pack_element(int e, double* out) const;
  void unpack_element(int e, const double* in);

  // ---- what moves with a node or account when a distributed body that breaks is gathered on one
  // rank and scattered again (body/part_restart.h) ----
  // Node n's whole state: reference and current position, velocity, force and held contact force
  // (the next step's half kick and substeps use them), prescribed velocity, condition and held
  // components, ramp, reaction groups (the node's and its components'), lumped mass.
  static constexpr int kNodeRecordSize = 25;
  void pack_node(int n, double* out) const;
  void unpack_node(int n, const double* in);
  // The figures of the last force evaluation that output reads (strain energy, total contact
  // force, reactions) and the erosion account; a part's share (the body's: the sums).
  struct Outputs {
    double strain_energy = 0, contact_force_total[3] = {0, 0, 0};
    std::vector<double> reactions;
    ErosionAccount eroded;
  };
  Outputs outputs() const;
  void set_outputs(const Outputs& o);
  // The damage that the last force evaluation found (of a body gathered from its parts: their
  // damaged points summed, their failed elements in global numbers, ascending).
  void set_damage(int damaged_points, std::vector<int> failed);

private:
  void resize_nodes(int nn);
  void grow_track_marks(); // new elements of cuts take their parent's mark
  // bisect_edge's parts (fem/body_cut.cpp).
  void cut_conditions(int p, int u, int w, double t);
  void cut_masses(int p, const std::vector<int>& nodes, const std::vector<double>& loss,
                  bool gains);
  void cut_elements(const std::vector<int>& parents, int first_child, double t,
                    const std::vector<std::array<int, 4>>& parent_conn);
  void map_quad_states(int e, int c, const std::array<int, 4>& parent_conn);
  // Restart (version 5): the elements and nodes made by cuts.
  void pack_growth(std::vector<double>& buf) const;
  const double* unpack_growth(const double* p, int ne);
  void join_cut_node_sets(int n);
  void cut_node_groups(int n);
  long cut_index(int n) const;
  void restore_cut_elements();
  // Velocity factor of a prescribed node at time t (its ramp), and its rate.
  double ramp_factor(int n, double t) const
  {
    return ramp_[n] > 0 && t < ramp_[n] ? (t > 0 ? t / ramp_[n] : 0.0) : 1.0;
  }
  double ramp_rate(int n, double t) const
  {
    return ramp_[n] > 0 && t < ramp_[n] ? 1.0 / ramp_[n] : 0.0;
  }
  void add_reactions(double dt, bool count_work);
  void open_reaction_group(int group); // a reaction account for group (-1: none)
  void derive_masses();
  void add_viscous_work(double dt, bool count_work);
  const double* unpack_viscosity(int version, const double* p);
  double remove_element_mass(int e);
  double release_bare_nodes(const std::vector<int>& elems);
  double release_node(int n);
  void shield_drift(int n);
  void shield_forces();

  Mesh mesh_;
  FeSpace space_;
  Material material_;
  bool rigid_ = false;
  RigidMotion motion_;
  std::vector<double> x_, v_, f_, mass_, inv_mass_;
  std::vector<std::uint8_t> counted_; // set_counted_nodes; empty: all
  std::vector<std::uint8_t> shared_;  // set_shared_nodes; empty: none
  std::vector<double> taken_;         // per node: mass taken off a shared node, not yet settled
  std::vector<double> f_contact_, f_contact_prev_, f_pending_;
  std::vector<NodeBc> bc_;
  std::vector<double> v_prescribed_;
  std::vector<std::uint8_t> held_; // held components (bit d), Partial nodes
  std::vector<double> ramp_;       // prescribed-velocity ramp time per node (0: none)
  std::vector<int> bc_group_;      // reaction group per node (-1: none; restart record)
  // Reaction group of each held component (3 per node): a node held in x by one group and in y
  // by another reports each reaction to its own group. Set by the conditions (not stored in
  // restart files: rebuilt from the command, split copies take their parent's).
  std::vector<int> component_group_;
  std::vector<double> reactions_; // 3 per group
  std::vector<int> parent_;
  int mesh_elems_ = 0;               // elements of the mesh as built
  std::vector<int> elem_parent_;     // per element made by a cut (index - mesh_elems_): its parent
  std::vector<int> cut_nodes_;       // (P, u, w) per bisected edge
  std::vector<double> mesh_measure_; // reference measure of each mesh element (from the 1st cut)
  std::vector<double> state_;        // per integration point, see FeSpace::state_offset
  BulkViscosity viscosity_;
  // Per element: viscous work so far, q W of the last counted evaluation (restart state); q W and
  // volumetric strain rate of the latest evaluation (recomputed every step).
  std::vector<double> viscous_work_, viscous_force_prev_, viscous_force_, viscous_rate_;
  // viscous_force_prev_ holds a counted evaluation's (or a restored one's); replay_viscous_: the
  // next evaluation takes those instead of the current velocities (replay_viscous_forces_once).
  bool viscous_evaluated_ = false, replay_viscous_ = false;
  NodeStars stars_; // active elements around each node
  int damaged_points_ = 0;
  std::vector<int> damaged_elems_; // elements with a damaged point at the last force evaluation
  std::vector<int> failed_elems_;  // and those with a point that carries no more tension
  std::vector<int> overstressed_elems_; // held elastic by the tracker, at the strength
  double track_length_ = 0;             // 0: no tracking
  double track_exclusion_ = 0;          // <= 0: track_length_
  CrackTrackState track_;
  TrackGeometry track_geo_; // rebuilt when the element count changes
  int elem_begin_ = 0, elem_end_ = 0;
  double time_ = 0;
  double last_dt_ = 0; // step of the last half_kick_drift (material strain rates)
  double strain_energy_ = 0, external_work_ = 0, contact_work_ = 0, boundary_work_ = 0;
  ErosionAccount eroded_;
  double shield_work_ = 0;
  long shield_hits_ = 0;
  double contact_force_total_[3] = {0, 0, 0};
};

} // namespace fracdem

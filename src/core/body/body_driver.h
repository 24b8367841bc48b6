// BodyDriver: the step of one fix fem/body (forces with erosion, fracture, surfaces, body-body
// contact, energy file, restart record) between a host adapter and fracdem::Body.
#pragma once

#include <cstdint>
#include <cstdio>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "contact/contact_scene.h"
#include "contact/particle_facet.h"
#include "contact/edge_contact.h"
#include "contact/surface_contact.h"
#include "fem/body.h"
#include "body/body_partition.h"
#include "body/contact_coordinator.h"
#include "body/body_spec.h"
#include "body/facet_ghosts.h"
#include "body/part_restart.h"
#include "body/piece_ghosts.h"
#include "fracture/fracture_plan.h"
#include "fracture/separation_watch.h"
#include "fracture/nodal_fracture.h"

namespace fracdem
{

// What the driver needs of its host. The reductions work in place and are entered by every rank
// at the same point. print and warning are called on rank 0 (but the history-slots warning, on
// the rank that ran out, as the LIGGGHTS adapter did); error_all stops the run on every rank and
// must not return (the driver throws std::runtime_error if it does).
struct BodyHost {
  int rank = 0, nprocs = 1;
  std::function<void(double*, int)> sum, max, min;
  std::function<void(int*, int)> max_int;
  // A line (with its '\n') for the screen and / or the log file.
  std::function<void(const std::string&, bool screen, bool logfile)> print;
  std::function<void(const std::string&)> warning, error_all;
  // Stops the run from one rank (a check that only that rank can make; must not return). Unset:
  // error_all.
  std::function<void(const std::string&)> error_one;
  // parallel distributed: the sum of per-node values over the parts that share each node
  // (body/body_partition.h InterfaceSum over MPI, src/parallel/node_exchange.h) for this rank's
  // part. Unset: the host cannot hold distributed bodies.
  std::function<std::function<void(double*, int)>(const MeshPart&)> shared_sum_for;
  // Every rank's values, in rank order, on rank 0 (empty on the others): the restart record of a
  // distributed body. Entered by every rank. Unset: one rank (its own values).
  std::function<std::vector<double>(const std::vector<double>&)> gather;
  // Rank 0 makes each rank's values (make(r), called on rank 0 only, one rank at a time, so that it
  // holds one message at a time) and sends them; every rank returns its own: the parts of a
  // distributed body, which rank 0 alone reads. Entered by every rank. Unset: make(0).
  std::function<std::vector<double>(const std::function<std::vector<double>(int)>& make)> scatter;
  // Every rank's values (the same count on each), in rank order, on every rank: the particle and
  // surface boxes of a distributed body, exchanged when the host re-neighbours.
  std::function<std::vector<double>(const std::vector<double>&)> all_gather;
  // One message to each rank of `to` (out[k]) and one from each rank of `from` (in[k], any
  // length): the facet ghosts of a distributed body (round 0) and the forces back (round 1), its
  // pieces' surface nodes (round 2) and their forces back (round 3). Both sides list each other;
  // no collective.
  std::function<void(int round, const std::vector<int>& to,
                     const std::vector<std::vector<double>>& out, const std::vector<int>& from,
                     std::vector<std::vector<double>>& in)>
      exchange;
};
// A host of one rank (reductions do nothing; print, warning and errors go to the given sinks;
// unit tests collect them). error_all throws std::runtime_error(text) when none is given.
BodyHost serial_host(std::function<void(const std::string&)> out = nullptr);

// The global vector after the core's entries and the reactions (docs/fix_fem_body.md).
enum BodyVectorTail {
  kVecErodedElements = 0,
  kVecErodedMass,
  kVecErodedEnergy,
  kVecShieldWork,
  kVecSubsteps,
  kVecMass,
  kVecTailSize
};

// One replicated body and its step, in the order a host calls it:
//   attach(spec, id, host), build(dimension)           fix command
//   configure_contact(...), set_partners(...), set_gravity(...), check_time_step(dt)   init
//   start_run(), [host: box check], compute_forces(...), write_energy_row_if_due(step) setup
//   begin_step(dt) | compute_forces(...) | end_step(step, dt)                           step
// The host fills ParticleArrays and reads its own settings (gravity, friction, box); the
// driver does the rest and reports through BodyHost.
class BodyDriver
{
public:
  BodyDriver() = default;
  BodyDriver(const BodyDriver&) = delete;
  BodyDriver& operator=(const BodyDriver&) = delete;
  ~BodyDriver();

  // The spec stays the host's (it may resolve defaults later, e.g. the search buffer).
  void attach(const BodySpec& spec, const std::string& fix_id, BodyHost host);
  // Builds the body (throws SpecError), shares its element work among the ranks where it can,
  // builds its surfaces and checks the crack band (error_all).
  void build(int dimension);
  // "fix fem/body ID: MESH, N nodes, M elements, F boundary facets, deformable corotational, ..."
  // without the line end.
  std::string describe() const;

  // ---- set-up of a run ----
  // Particle contact: options (search buffer included) and one material per atom type.
  void configure_contact(const ParticleFacetOptions& options, std::vector<ContactMaterial> mats);
  // Body-body contact (contact_bodies yes): `later` and `earlier` are the other bodies with it
  // on, in the host's order of calls; friction(ti, tj) is the Coulomb coefficient between
  // surfaces of types ti and tj (this body's, for its pieces and its pairs with later bodies).
  // The first body holds the contact scene of all (contact/contact_scene.h): one search over
  // their surfaces; each body's call of compute_forces evaluates its pieces and its pairs with
  // the later bodies, every rank the surface nodes of its part. Called by every body, first to
  // last.
  void set_partners(const std::vector<BodyDriver*>& later, const std::vector<BodyDriver*>& earlier,
                    const std::function<double(int, int)>& friction);
  void set_gravity(const double g[3]);
  // Logs the stable step against the host step dt, sets the FE steps per host step (substeps),
  // errors / warns as dt_check says where the FE step stays above the stable step.
  void check_time_step(double dt);
  // Opens energy_file on rank 0 and writes its header; returns "" or the error text.
  std::string open_energy_file();
  // Initial velocities (first run, not after a restart) and a rigid body's placement.
  void start_run();
  void log_memory();

  // ---- the step ----
  // The body's first n - 1 FE steps of h = dt / n (n = substeps()), with the contact forces of the
  // host's last evaluation held, then the half kick and drift of the last one.
  void begin_step(double dt);
  // The host re-neighboured (particles may have changed rank): a distributed body exchanges its
  // ranks' particle and surface boxes at the next force evaluation (every rank, same step).
  void particles_regrouped() { boxes_due_ = piece_boxes_due_ = true; }
  // Internal forces (erosion, inverted elements), body-body and particle contact (particles:
  // nullptr without particle contact), the reductions, the checks; count_work: not in set-up.
  void compute_forces(const ParticleArrays* particles, std::int64_t step, double dt,
                      bool count_work);
  // Second half kick (of the last FE step), fracture check, energy row.
  void end_step(std::int64_t step, double dt);
  void write_energy_row_if_due(std::int64_t step);

  // ---- output ----
  int vector_size() const;
  double scalar(); // every rank enters (distributed bodies sum over the ranks)
  // Entry i of the global vector (every rank enters: the search rebuilds are reduced).
  double vector_entry(int i);
  std::size_t memory_bytes() const;

  // ---- restart: the adapter head (placement, piece contact) and the body's record ----
  // Every rank enters where the body is distributed or has contact_bodies yes (the parts are
  // gathered, the held contact forces summed over the ranks).
  std::vector<double> restart_record() const;
  // Writes the record as LIGGGHTS and LAMMPS read a fix's global restart: its size in bytes
  // (int), then the bytes. Called on every rank (a distributed body gathers its parts); only rank
  // 0 writes to fp.
  void write_restart(std::FILE* fp) const;
  // Restores a record of restart_record() (or an older one without the head); errors name the
  // fix and go to error_all.
  void read_restart(const double* record);
  bool restarted() const { return restarted_; }

  // ---- state ----
  Body& body() { return body_; }
  const Body& body() const { return body_; }
  const BodySpec& spec() const { return *spec_; }
  const ParticleFacetContact& contact() const { return contact_; }
  ParticleFacetContact& contact() { return contact_; }
  bool split_element_work() const { return split_element_work_; }
  bool distributed() const { return distributed_; }
  const MeshPart& part() const { return part_; }
  // A distributed body's part in global numbers, with the whole body's fields for output.
  const PartTopology& topology() const { return topo_; }
  bool can_erode() const { return spec_->erosion.on() || spec_->fracture_every > 0; }
  // Whether a part's modelled work (body_breaking.cpp, element_costs) can change in a run.
  bool work_can_drift() const { return can_erode() || spec_->material.plastic_model(); }
  double stable_dt() const { return dt_stable_; }
  int contacts() const { return ncontacts_; }
  // The contact scene this body belongs to (null: none set up yet) and its index there.
  const ContactScene* contact_scene() const { return in_scene() ? coordinator_->scene() : nullptr; }
  int scene_index() const { return scene_index_; }
  // What this body lends the contact scene of the replicated bodies (contact_coordinator.h), and
  // its place there (set by the first member's set-up of a run).
  SceneBody scene_member();
  void join_scene(std::shared_ptr<ContactCoordinator> coordinator, int index);
  // FE steps of the host step under way (or of the first step of a run, after set-up), and of
  // the next host step (changed by the stable step's re-estimates).
  int substeps() const { return step_substeps_; }
  int next_substeps() const { return substeps_; }

  // Exposed for tests: the fracture check and the erosion log line.
  void fracture(std::int64_t step, double dt);
  std::string erosion_line(std::int64_t step, const int* counts,
                           const std::vector<int>& batch) const;
  // The same line with the given totals (a distributed body's, summed over its parts).
  std::string erosion_line(std::int64_t step, const int* counts, const std::vector<int>& batch,
                           const ErosionAccount& acc) const;

private:
  [[noreturn]] void fail(const std::string& text) const;
  void print(const std::string& line, bool screen = true, bool logfile = true) const;
  void warn(const std::string& text) const; // rank 0
  std::string prefix() const { return "fix fem/body " + id_ + ": "; }
  void check_crack_band();
  void start_crack_tracking();
  void log_crack_starts(std::int64_t step, const TrackEvents& ev) const;
  void check_squeezed(std::int64_t step, double dt);
  bool can_substep() const { return !spec_->rigid && spec_->substeps != kSubstepsOff; }
  void follow_stable_step(std::int64_t step, double dt, double dt_stable);
  std::string step_text(double dt) const;
  void substep(double dt, double h);
  void substep_forces(double dt, double h);
  void check_state(std::int64_t step, double energy, double inverted) const;
  double internal_forces(std::int64_t step, double dt, int& first_inverted);
  double forces_after_erosion(std::int64_t step, double dt, double energy, int& first_inverted);
  double erosion_loop(double energy, int& first_inverted, int* counts, std::vector<int>& batch);
  void after_erosion(std::int64_t step, double dt, const int* counts,
                     const std::vector<int>& batch);
  void follow_step_after_erosion(std::int64_t step, double dt);
  void erode_inverted(std::int64_t step, int e);
  std::string inverted_line(std::int64_t step, int e) const;
  FracturePlanInput fracture_input(const FailureMap& map, double dt) const;
  bool crack_body(std::int64_t step, double dt, FractureOutcome& out,
                  SeparationOutlook* outlook = nullptr);
  void log_cracks(std::int64_t step, const FractureOutcome& out);
  void log_erosions(std::int64_t step, const std::vector<int>& eroded) const;
  void log_splits(std::int64_t step, const std::vector<SplitEvent>& events) const;
  void log_cuts(std::int64_t step, const std::vector<CutEvent>& cuts) const;
  void share_element_work();
  void check_step_after_cracks(std::int64_t step, double dt, bool cut);
  void log_fragments(std::int64_t step);
  void warn_unresolved_contact(std::int64_t step, const ParticleFacetResult& res);
  void warn_history_slots(const ParticleFacetResult& res);
  // The texts of the contact warnings (replicated bodies reduce the figures first; a distributed
  // body's rank warns with its own).
  std::string unresolved_contact_text(std::int64_t step, double speed, double dt_ok) const;
  std::string wide_patch_text(std::int64_t step, double radii) const;
  void rebuild_surfaces();
  const std::vector<char>* mark_inelastic_nodes();
  const double* contact_masses();
  SurfaceContactOptions surface_options(int other_type, double other_E, double friction) const;
  bool in_scene() const { return coordinator_ && coordinator_->active(); }
  ContactCoordinator::Settings scene_settings();
  int body_contacts(std::int64_t step, double dt);
  // The contact of the pieces and with other bodies (contact_bodies yes), or at the set-up of a
  // run that goes on, its forces at the last counted evaluation (body_driver.cpp, "held contact
  // forces").
  void body_contact_forces(std::int64_t step, double dt, bool count_work);
  bool replays_body_contacts(bool count_work) const;
  // Contact of a distributed body with replicated bodies (body_pair_contact.cpp): the group of
  // every contact_bodies body where one is distributed, each (distributed, replicated) pair
  // evaluated on rank 0 from the distributed body's facets near the replicated one.
  std::vector<BodyDriver*> pair_group(const std::vector<BodyDriver*>& all) const;
  void take_pair_group(const std::vector<BodyDriver*>& group);
  void pair_contacts(double dt);
  void configure_pairs();
  void evaluate_pair(size_t k, double dt);
  void build_pair_maps();
  std::vector<double> pair_message(const BodyDriver& other, double grow);
  void gather_pair_nodes(const std::vector<std::vector<double>>& in);
  std::vector<std::vector<double>> resolve_pair(size_t k, double dt, double* other_f);
  void add_pair_forces(const std::vector<double>& back, double* f) const;
  void hold_body_contacts();
  void replay_body_contacts();
  std::vector<double> held_body_contacts_record() const;
  void take_held_body_contacts(const double* list, size_t n);
  void write_energy_row(std::int64_t step);
  void write_distributed_energy_row(std::int64_t step);
  void distributed_forces(const ParticleArrays* particles, std::int64_t step, double dt,
                          bool count_work, bool last);
  // A distributed body that erodes (body_erosion.cpp): each part erodes its own elements in its
  // force evaluation; at the host step's last evaluation the parts agree (one integer reduction)
  // and, after an erosion, rank 0 logs it, the stable step follows and the surface is renewed.
  double erode_part(double energy, int& first_inverted, bool last);
  void sum_forces_and_masses();
  void distributed_erosion(std::int64_t step, double dt, int& piece_moved);
  std::vector<double> pack_part_erosion() const;
  void renew_surface_after_erosion(const std::vector<int>& eroded);
  void distributed_contact(const ParticleArrays& particles, std::int64_t step, double dt);
  // The contact of a distributed body's pieces (body_self_contact.cpp): the partner parts'
  // surface nodes by neighbour messages each host step into a surface replica, each contact
  // evaluated on one rank, the forces of other parts' nodes sent back (piece_ghosts.h).
  void build_part_surface();
  std::vector<double> free_surface_nodes() const;
  void distributed_body_contacts(std::int64_t step, double dt);
  void gather_piece_state();
  double piece_travel() const;
  int piece_moved() const;
  double distributed_vector_entry(int i);
  void build_distributed(Mesh& whole);
  // A distributed body that breaks (body_breaking.cpp): the fracture check on the whole body
  // gathered on rank 0, and the new parts scattered after a change.
  void distributed_fracture(std::int64_t step, double dt);
  bool gather_whole(Body& whole, std::vector<int>& owner) const;
  std::vector<int> repartition(const Body& whole, const std::vector<int>& owner) const;
  void scatter_whole(const Body& whole, const std::vector<int>& elem_part);
  void adopt_part(const std::vector<double>& message);
  void count_whole(const Body& whole);
  bool fracture_may_change(double dt);
  void check_balance(std::int64_t step);
  bool choose_distributed(int dimension, Mesh& whole, bool& have_whole);
  void fail_one(const std::string& text) const;
  void merge_part_erosion(std::int64_t step, const std::vector<double>& all,
                          const std::vector<int>& at, std::vector<std::vector<std::string>>& lines,
                          std::vector<int>& eroded) const;
  // Sections of the head: [0] the pieces' node-facet contact state, [1] their edge contact state,
  // [2] the held contact forces.
  static constexpr int kHeadSections = 5; // sections of the restart record's head
  void read_head(const double* head, int n, const double* (&state)[kHeadSections],
                 size_t (&size)[kHeadSections]);
  std::vector<double> record_head(const std::vector<double>& held) const;
  // The contacts between bodies carried into the next run and in restart records
  // (pair_restart.cpp): records of (first body's ID, second's, state), either holder's alike.
  std::vector<double> pair_records() const;
  void take_restored_body_pairs();
  static void drop_restored_pairs(const std::vector<BodyDriver*>& bodies);
  std::vector<double> record_with(const std::vector<double>& held) const;
  std::vector<double> distributed_body_record() const;
  void read_body_record(const double* record);
  void take_whole(const Body& whole);
  void take_part_records(const double* record);

  const BodySpec* spec_ = nullptr;
  std::string id_;
  BodyHost host_;
  int dimension_ = 3;
  Body body_;
  bool split_element_work_ = false; // element work shared among ranks (else replicated)
  bool distributed_ = false;        // parallel distributed: this rank holds part_ only
  MeshPart part_;
  std::function<void(double*, int)> shared_sum_;
  int global_nodes_ = 0, global_elems_ = 0;
  // A distributed body that breaks: the elements of the mesh as read, the part's topology in
  // global numbers, whether a change came (a topology change or an erosion; kept with the restart
  // record, as the counts are), and, on rank 0, the whole body's split nodes and fragments since
  // the last change (energy file).
  int mesh_elems_ = 0;
  PartTopology topo_;
  bool broken_ = false;
  int whole_split_nodes_ = 0, whole_fragments_ = 1;
  SeparationWatch separation_watch_; // between gathered fracture checks (body_breaking.cpp)
  long long interface_pairs_ = 0;
  // A distributed body that erodes: this part's erosions (global element numbers) in the force
  // evaluations since the last follow-up (fe: their index there), its own stable steps after each
  // evaluation but the last (sub-cycling), its account before the first of them; on rank 0 the
  // whole mesh with its element owners (surfaces after erosion), kept until the parts change.
  struct PartErosion {
    int fe = 0;
    int counts[kErosionCauses] = {0, 0, 0, 0};
    std::vector<int> batch; // the criteria's elements, then the inverted ones (counts[Inverted])
    ErosionAccount took;    // what they took out (elements, mass, energy)
  };
  std::vector<PartErosion> part_erosion_;
  std::vector<double> fe_dt_stable_;
  std::vector<double> force_mass_; // erosion_mass remove: per node forces, mass taken, elements
  int fe_count_ = 0;
  ErosionAccount erosion_mark_;
  bool whole_mesh_known_ = false;
  Mesh whole_mesh_;
  std::vector<int> whole_owner_;
  // Particle contact of a distributed body (body_ghost_contact.cpp): facet ghosts by boxes.
  FacetGhosts ghosts_;
  bool boxes_due_ = true;
  std::vector<std::vector<double>> ghost_out_, ghost_in_, ghost_back_, ghost_returned_;
  ParticleFacetContact contact_;
  ContactSurface surface_; // a distributed body's: the whole surface in global node numbers
  // A distributed body's surface replica (contact_bodies yes): per surface node whether the part
  // owns it (its node-to-facet contacts are this rank's); positions, velocities, masses and
  // contact forces by global node number (only the part's and its partners' surface nodes
  // used); renewed at the next evaluation after a topology change (every rank alike). The
  // neighbour exchange, its boxes (due with the particles' and after a topology change), its
  // messages; whether the contact state is spread over the ranks (each rank's contacts only).
  bool part_surface_due_ = true;
  std::vector<char> surf_owned_;
  std::vector<double> surf_x_, surf_v_, surf_m_, surf_f_;
  PieceGhosts pieces_;
  bool piece_boxes_due_ = true, piece_state_spread_ = false;
  std::vector<std::vector<double>> piece_out_, piece_in_, piece_back_, piece_returned_;
  // The held contact forces: per entry a surface node (a distributed body's: its global number)
  // and its force, this rank's share of the last counted evaluation (after a restart: rank 0 of a
  // replicated body holds them all, every part of a distributed one all, and takes its own).
  std::vector<int> held_nodes_;
  std::vector<double> held_forces_;
  bool contacts_held_ = false, held_whole_ = false; // whole: from a restart record
  // Contact between a distributed body and replicated ones (body_pair_contact.cpp). On the
  // distributed body: one entry per replicated partner (whose call comes first: it evaluates the
  // pair; both directions of node to facet and, where both take it, edge to edge, state on rank
  // 0 only), the maps of its surface (global node -> part node, -> surface index) and, on rank 0,
  // the replica of its surface nodes near the partner (by global number) with each node's sender
  // (the lowest rank that sent it gets its force back). On a replicated body: its distributed
  // partner and whether this body's call evaluates the pair.
  struct BodyPair {
    BodyDriver* other = nullptr;
    bool other_first = false;
    SurfaceContact mine_on_other, other_on_mine;
    EdgeContact edges;
  };
  static void carry_pair_state(const BodyPair& from, BodyPair& to);
  std::vector<BodyPair> pairs_;
  std::vector<BodyDriver*> pair_group_;
  bool pair_continues_ = false, pairs_pending_ = false, pair_maps_due_ = true;
  BodyDriver* pair_body_ = nullptr;
  bool pair_first_ = false;
  std::vector<int> pair_local_, pair_own_facets_, pair_own_free_, pair_sent_mine_;
  std::vector<int> pair_known_nodes_, pair_known_facets_; // rank 0, this step
  std::vector<char> pair_seen_, pair_facet_known_;
  std::vector<double> pair_x_, pair_v_, pair_f_;
  std::vector<std::vector<int>> pair_sent_; // rank 0: per rank, the nodes it sent
  std::vector<std::vector<char>> pair_route_; // rank 0: per rank, per node sent: its force goes there
  std::vector<std::vector<double>> pair_out_, pair_in_;
  SurfaceContact self_contact_; // kept here, not in the scene: its state is in the restart
  EdgeContact self_edges_;      // 3D edge to edge of the pieces (restart head section 2)
  // Body-body contact: the coordinator of the replicated bodies' scene (every member holds it)
  // and this body's index there.
  std::shared_ptr<ContactCoordinator> coordinator_;
  int scene_index_ = -1;
  // The restart record's contacts between bodies (records), until the first evaluation.
  std::vector<double> restored_pairs_;
  std::function<double(int, int)> friction_;
  FailureMap failure_map_; // kept between checks: no allocation per check
  std::vector<char> inelastic_nodes_; // per node: at a damaged element (mark_inelastic_nodes)
  std::vector<double> contact_mass_;  // per node: what a particle contact moves (contact_masses)
  // The replicated body's face-connected pieces, kept while its topology is unchanged (a
  // restored record takes them again; a distributed body's gathered check takes its own).
  FacePieces face_pieces_;
  int last_fragments_ = 1;
  double gravity_[3] = {0, 0, 0};
  double dt_stable_ = 0;
  // FE steps per host step: from the next host step on (set where the stable step is estimated),
  // and in the host step under way (fixed by begin_step: a change within a step waits for the
  // next). step_: the last step seen (a host step's substeps belong to step_ + 1).
  int substeps_ = 1, step_substeps_ = 1;
  std::int64_t step_ = 0;
  int ncontacts_ = 0;
  bool velocities_applied_ = false, restarted_ = false;
  bool warned_slots_ = false, warned_unresolved_ = false, warned_dt_after_erosion_ = false;
  bool warned_patch_ = false; // a Hertz patch wider than the facet ghosts' reach
  bool warned_squeezed_ = false;
  // Steps between checks of the deformed body's stable step (O(elements), ~1 % of the step).
  static constexpr int kStableStepCheckEvery = 100;
  std::FILE* energy_fp_ = nullptr;
  std::int64_t last_energy_step_ = -1;
};

} // namespace fracdem

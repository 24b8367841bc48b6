// BodyDriver: the per-step orchestration of a fix fem/body body, shared by the host adapters.
#include "body/body_driver.h"

#include <algorithm>
#include <iterator>
#include <cinttypes>
#include <cmath>
#include <cstdarg>
#include <exception>
#include <stdexcept>

#include "contact/contact_resolution.h"
#include "body/body_setup.h"
#include "body/part_restart.h"
#include "fem/erosion.h"
#include "io/input_help.h"
#include "materials/rankine.h"

namespace fracdem
{

namespace
{

// printf into a string (the adapters' texts were written with printf formats).
std::string format(const char* fmt, ...)
{
  char buf[1024];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(buf, sizeof buf, fmt, ap);
  va_end(ap);
  return buf;
}

// The adapter's head of the restart record, before the body's own (Body::pack_state): this
// marker (a body record starts with its version, 1 or 2), the number of doubles that follow in
// the head, then rigid (0 / 1), the number of placement transforms and 5 doubles per transform
// (kind, a[4]). Records written without the head start with the body record and are read as
// before. After the transforms the head may hold sections (tag, number of doubles, doubles); a
// reader skips the head by its length, so one that knows no sections reads the placement as
// before. kSelfContactSection: the contact state of the body's pieces
// (SurfaceContact::pack_state), written only where there is some, so a body without piece
// contact writes the same bytes. kSelfEdgeSection: the pieces' edge contact state
// (EdgeContact::pack_state), likewise. kHeldContactSection: the held contact forces of the
// pieces and with other bodies ("held contact forces" below), 4 doubles per node (node, force),
// likewise. kPairContactSection: the contacts between bodies held by this body (the first body
// of a contact scene of several, or a distributed body with replicated partners), each behind
// the fix IDs of its two bodies (pair_restart.cpp). kCrackTrackSection: the crack tracker's
// marks and tips (fracture/crack_tracking.h), written only with 'fracture nodal track'.
constexpr double kRecordHead = -1.0;
constexpr double kSelfContactSection = 1.0;
constexpr double kSelfEdgeSection = 2.0;
constexpr double kHeldContactSection = 3.0;
constexpr double kPairContactSection = 4.0;
constexpr double kCrackTrackSection = 5.0;
// The head's sections in the order BodyDriver keeps them (record_head, read_head).
constexpr double kHeadSectionTags[] = {kSelfContactSection, kSelfEdgeSection, kHeldContactSection,
                                       kPairContactSection, kCrackTrackSection};

// The placement keywords as the input writes them.
std::string placement_text(bool rigid, const std::vector<MeshTransform>& transforms)
{
  std::string text = rigid ? "rigid yes" : "rigid no";
  for (const MeshTransform& t : transforms) {
    if (t.kind == MeshTransform::Scale)
      text += format(" scale %g", t.a[0]);
    else if (t.kind == MeshTransform::Move)
      text += format(" move %g %g %g", t.a[0], t.a[1], t.a[2]);
    else
      text +=
          format(" rotate axis %g %g %g angle %g", t.a[0], t.a[1], t.a[2], t.a[3] * 180.0 / M_PI);
  }
  return text;
}

bool same_placement(const std::vector<MeshTransform>& a, const std::vector<MeshTransform>& b)
{
  if (a.size() != b.size()) return false;
  for (size_t k = 0; k < a.size(); ++k) {
    if (a[k].kind != b[k].kind) return false;
    for (int i = 0; i < 4; ++i)
      if (std::fabs(a[k].a[i] - b[k].a[i]) > 1e-12 * std::max(1.0, std::fabs(a[k].a[i])))
        return false;
  }
  return true;
}

} // namespace

BodyHost serial_host(std::function<void(const std::string&)> out)
{
  BodyHost h;
  h.sum = h.max = h.min = [](double*, int) {};
  h.max_int = [](int*, int) {};
  h.print = [out](const std::string& s, bool, bool) {
    if (out) out(s);
  };
  h.warning = [out](const std::string& s) {
    if (out) out("WARNING: " + s);
  };
  h.error_all = [](const std::string& s) { throw std::runtime_error(s); };
  return h;
}

BodyDriver::~BodyDriver()
{
  if (energy_fp_) std::fclose(energy_fp_);
  // A body leaving disbands the pairs of a distributed body with replicated ones, too.
  for (BodyDriver* m : pair_group_)
    if (m != this) {
      m->pair_group_.clear();
      m->pairs_.clear();
      m->pair_body_ = nullptr;
    }
  // A body leaving (unfix) disbands its scene: the others are in none until the next run's
  // set_partners makes a new one.
  if (coordinator_) coordinator_->disband();
}

void BodyDriver::attach(const BodySpec& spec, const std::string& fix_id, BodyHost host)
{
  spec_ = &spec;
  id_ = fix_id;
  host_ = std::move(host);
}

void BodyDriver::fail(const std::string& text) const
{
  host_.error_all(text);
  throw std::runtime_error(text); // error_all must not return
}

void BodyDriver::fail_one(const std::string& text) const
{
  if (host_.error_one) host_.error_one(text);
  fail(text);
}

void BodyDriver::print(const std::string& line, bool screen, bool logfile) const
{
  if (host_.rank == 0) host_.print(line, screen, logfile);
}

void BodyDriver::warn(const std::string& text) const
{
  if (host_.rank == 0) host_.warning(text);
}

/* ---------------------------------------------------------------------- */

void BodyDriver::build(int dimension)
{
  dimension_ = dimension;
  Mesh whole; // rank 0's placed mesh, when it read it to distribute it or to choose
  bool have_whole = false;
  if (choose_distributed(dimension, whole, have_whole)) return build_distributed(whole);
  if (have_whole)
    build_body_from_mesh(*spec_, std::move(whole), body_);
  else
    build_body(*spec_, dimension, body_);
  global_nodes_ = body_.num_nodes();
  global_elems_ = body_.mesh().num_elems();
  // Every rank holds the whole body (replicated). The element work of a material without
  // history is split evenly; one with history (softening, cracks, the viscous work of the bulk
  // viscosity) is advanced on every rank, so that every replica holds the whole material state
  // (fracture decisions, restart, energy accounts). So is an eroding body's, so that every
  // replica sees every inverted element and erodes the same elements.
  split_element_work_ =
      fracdem::split_element_work(body_, host_.rank, host_.nprocs, spec_->erosion.on());
  rebuild_surfaces();
  check_crack_band();
  start_crack_tracking();
}

// One line per crack the tracker starts: where (element centroid) and its number.
void BodyDriver::log_crack_starts(std::int64_t step, const TrackEvents& ev) const
{
  const Mesh& m = body_.mesh();
  int number = body_.track_state().cracks - static_cast<int>(ev.started.size());
  for (int e : ev.started) {
    double c[2] = {0, 0};
    const int nv = m.conn[e][3] >= 0 ? 4 : 3;
    for (int a = 0; a < nv; ++a)
      for (int d = 0; d < 2; ++d)
        c[d] += m.X[3 * m.conn[e][a] + d] / nv;
    print(format("fix fem/body %s: step %" PRId64 ": crack %d starts at element %d (%g %g)\n",
                 id_.c_str(), step, ++number, e, c[0], c[1]),
          false, true);
  }
}

// 'fracture nodal track L': L of at least two mean element sizes (a shorter one averages the
// stress of one element's neighbours only and the band follows the mesh).
void BodyDriver::start_crack_tracking()
{
  if (spec_->track_length <= 0) return;
  const double h = mean_element_size(body_.mesh());
  if (spec_->track_length < 2 * h)
    fail(format("fix fem/body %s: keyword 'fracture nodal track' expects a tracking length of at "
                "least two element sizes, 2 h = %g (h: the mean element size of mesh '%s', %g), "
                "got %g",
                id_.c_str(), 2 * h, spec_->mesh_file.c_str(), h, spec_->track_length));
  body_.set_crack_tracking(spec_->track_length, spec_->track_exclusion);
}

// Whether the body is distributed: asked ('parallel distributed'), or chosen by its size where
// the spec leaves it to set-up (parallel_choice, logged). Where it may be distributed, rank 0
// alone reads the mesh (into whole) and tells the others (one max_int at set-up); a mesh that
// rank 0 cannot read leaves the body replicated here, so that every rank reads it and stops with
// the same error.
bool BodyDriver::choose_distributed(int dimension, Mesh& whole, bool& have_whole)
{
  if (host_.nprocs <= 1) return false;
  const bool capable = host_.shared_sum_for && host_.scatter;
  const bool asked = spec_->have_parallel && spec_->distributed;
  if (asked && !capable)
    fail(prefix() + "keyword 'parallel distributed' is not available under this host; use "
                    "'parallel replicated'");
  if (spec_->have_parallel && !asked) return false;
  if (!asked && (!capable || distributed_default_refusal(*spec_))) {
    bool unused = false;
    if (capable) print(prefix() + parallel_choice(*spec_, 0, unused) + "\n");
    return false;
  }
  int choice = 0;
  std::string why;
  std::exception_ptr error;
  if (host_.rank == 0) {
    try {
      whole = placed_body_mesh(*spec_, dimension);
      have_whole = true;
      bool distributed = false;
      why = parallel_choice(*spec_, whole.num_elems(), distributed);
      choice = distributed ? 1 : 0;
    } catch (const SpecError&) {
      error = std::current_exception();
    }
  }
  host_.max_int(&choice, 1);
  if (error) std::rethrow_exception(error);
  if (!why.empty()) print(prefix() + why + "\n");
  return choice == 1;
}

// parallel distributed: this rank's METIS part, which rank 0 alone cuts from the whole mesh
// (whole, read there) and sends (the whole surface with it: particle contact), its masses summed
// with the parts that share its nodes. Rank 0 frees the whole mesh before it builds its own part.
// The part's element work is all its own (no ranges); its surfaces are the part's.
void BodyDriver::build_distributed(Mesh& whole)
{
  distributed_ = true;
  std::vector<int> elem_part;
  std::vector<double> packed_surface;
  if (host_.rank == 0) {
    elem_part = partition_elements(whole, host_.nprocs);
    packed_surface = pack_surface(global_surface(whole, elem_part));
    std::vector<int> component;
    whole_fragments_ = element_components(whole, component); // the energy file's, until a change
  }
  const auto make = [&](int r) { return part_message(whole, elem_part, packed_surface, r); };
  std::vector<double> message = host_.scatter(make);
  whole = Mesh();
  std::vector<int>().swap(elem_part);
  std::vector<double>().swap(packed_surface);
  GlobalSurface surface;
  part_ = build_body_part(*spec_, message, body_, global_nodes_, global_elems_, &surface);
  std::vector<double>().swap(message);
  mesh_elems_ = global_elems_;
  topo_.reset(part_.num_nodes(), body_.mesh().num_elems());
  ghosts_.init(part_, std::move(surface));
  shared_sum_ = host_.shared_sum_for(part_);
  double pairs = 0; // (shared node, neighbouring part) pairs of all parts: the exchange's size
  for (const PartNeighbour& nb : part_.neighbours)
    pairs += static_cast<double>(nb.nodes.size());
  host_.sum(&pairs, 1);
  interface_pairs_ = static_cast<long long>(pairs);
  std::vector<double> mass = body_.masses();
  shared_sum_(mass.data(), 1);
  body_.set_masses(mass);
  rebuild_surfaces();
  check_crack_band();
}

// The softening law snaps back in elements wider than c E G_f / f_t^2 (c = 2 for linear and
// exponential, 1.2 for bilinear: rankine_snapback_factor): refuse them by name.
void BodyDriver::check_crack_band()
{
  if (spec_->material.model != MaterialModel::Rankine) return;
  const RankineParams p = spec_->material.rankine();
  const double limit = rankine_snapback_length(p);
  const Mesh& mesh = body_.mesh();
  int worst = -1;
  double hmax = 0;
  for (int e = 0; e < mesh.num_elems(); ++e) {
    const double h = element_diameter(mesh, e);
    if (h > hmax) {
      hmax = h;
      worst = e;
    }
  }
  if (hmax >= limit)
    fail(format("fix fem/body %s: keyword 'material rankine': element %d of mesh '%s' is %g wide, "
                "above the snap-back limit %g E G_f / f_t^2 = %g of its softening law '%s'; refine "
                "the mesh to elements below %g (or raise fracture_energy / lower strength).%s",
                id_.c_str(), worst, spec_->mesh_file.c_str(), hmax,
                rankine_snapback_factor(p.softening), limit, softening_keyword(p.softening), limit,
                mesh_unit_hint(hmax, limit, largest_side(mesh.X)).c_str()));
}

std::string BodyDriver::describe() const
{
  const BodySpec& s = *spec_;
  std::string viscosity;
  if (s.viscosity.on) viscosity = format(", bulk viscosity %g %g", s.viscosity.q1, s.viscosity.q2);
  const char* kind =
      s.rigid ? ""
              : (s.material.kinematics == Kinematics::Corotational ? "corotational"
                                                                   : "small-strain elastic");
  if (distributed_)
    return format("fix fem/body %s: %s, %d nodes, %d elements, deformable %s%s, distributed over "
                  "%d ranks (METIS parts of the elements; rank 0: %d elements, %d nodes, %d "
                  "shared, %zu neighbouring parts; %lld (shared node, neighbour) pairs in all)",
                  id_.c_str(), s.mesh_file.c_str(), global_nodes_, global_elems_, kind,
                  viscosity.c_str(), host_.nprocs, body_.mesh().num_elems(), part_.num_nodes(),
                  part_.num_shared_nodes(), part_.neighbours.size(), interface_pairs_);
  return format("fix fem/body %s: %s, %d nodes, %d elements, %zu boundary facets, %s%s%s",
                id_.c_str(), s.mesh_file.c_str(), body_.num_nodes(), body_.mesh().num_elems(),
                contact_.facets().size(), s.rigid ? "rigid" : "deformable ", kind,
                viscosity.c_str());
}

/* ----------------------------------------------------------------------
   set-up of a run
------------------------------------------------------------------------- */

void BodyDriver::configure_contact(const ParticleFacetOptions& options,
                                   std::vector<ContactMaterial> mats)
{
  contact_.configure(options);
  if (distributed_) ghosts_.configure(options, mats);
  contact_.set_materials(std::move(mats));
}

// Penalty and friction of the contact between this surface and one of a body of modulus
// other_E: the softer body's modulus.
SurfaceContactOptions BodyDriver::surface_options(int, double other_E, double friction) const
{
  SurfaceContactOptions so;
  so.youngs = std::min(spec_->material.E, other_E);
  so.penalty_scale = spec_->contact_penalty;
  so.thickness = dimension_ == 2 ? spec_->material.thickness : 1.0;
  so.axisymmetric = body_.space().axisymmetric();
  so.friction = friction;
  return so;
}

// The first replicated body sets up the scene of all (its coordinator, contact_coordinator.h);
// each keeps its own friction for its pairs.
void BodyDriver::set_partners(const std::vector<BodyDriver*>& later,
                              const std::vector<BodyDriver*>& earlier,
                              const std::function<double(int, int)>& friction)
{
  const int my_type = spec_->surface_type;
  self_contact_.configure(surface_options(my_type, spec_->material.E, friction(my_type, my_type)));
  self_edges_.configure(self_contact_.options());
  friction_ = friction;
  // A distributed body takes its pairs with the replicated ones itself (body_pair_contact.cpp);
  // the scene holds the replicated bodies.
  std::vector<BodyDriver*> all = earlier;
  all.push_back(this);
  all.insert(all.end(), later.begin(), later.end());
  take_pair_group(pair_group(all));
  std::vector<BodyDriver*> members;
  for (BodyDriver* m : all)
    if (!m->distributed()) members.push_back(m);
  if (distributed_ || members.front() != this) {
    if (!distributed_ && spec_->have_contact_balance)
      fail(prefix() +
           "keyword 'contact_balance' belongs on the first fix fem/body with "
           "'contact_bodies yes' (fix " +
           members.front()->id_ + "), which holds the contact scene of all of them");
    if (distributed_) join_scene(nullptr, -1);
    rebuild_surfaces();
    return;
  }
  std::vector<const void*> keys;
  std::vector<SceneBody> bodies;
  for (BodyDriver* m : members) {
    keys.push_back(m);
    bodies.push_back(m->scene_member());
  }
  const std::shared_ptr<ContactCoordinator> scene =
      ContactCoordinator::renew(coordinator_, keys, std::move(bodies), scene_settings());
  for (size_t m = 0; m < members.size(); ++m)
    members[m]->join_scene(scene, static_cast<int>(m));
  rebuild_surfaces();
}

SceneBody BodyDriver::scene_member()
{
  SceneBody b;
  b.id = id_;
  b.surface = &surface_;
  b.self = &self_contact_;
  b.edges = spec_->contact_edges ? &self_edges_ : nullptr;
  b.body = &body_;
  b.surface_type = spec_->surface_type;
  b.youngs = spec_->material.E;
  b.options = [this](int type, double E, double friction) {
    return surface_options(type, E, friction);
  };
  b.friction = &friction_;
  b.contacts_held = &contacts_held_;
  b.restored = &restored_pairs_;
  return b;
}

void BodyDriver::join_scene(std::shared_ptr<ContactCoordinator> coordinator, int index)
{
  coordinator_ = std::move(coordinator);
  scene_index_ = index;
}

// The first member's host reports for the scene (repartitions of its contact work can come
// every check: the log file only).
ContactCoordinator::Settings BodyDriver::scene_settings()
{
  ContactCoordinator::Settings st;
  st.balance = spec_->contact_balance;
  st.comm = SceneComm{host_.rank, host_.nprocs, host_.sum,
                      [this](const std::string& line) { print(prefix() + line, false, true); }};
  st.fail = [this](const std::string& text) { fail(prefix() + text); };
  st.print = [this](const std::string& line) { print(prefix() + line); };
  return st;
}

void BodyDriver::set_gravity(const double g[3])
{
  const bool on = spec_->apply_gravity && !spec_->rigid;
  for (int d = 0; d < 3; ++d)
    gravity_[d] = on ? g[d] : 0.0;
}

// With 'erosion min_dt DT' the elements below DT leave at the first force evaluation: the step
// that counts is that of the others. A distributed body's parts take the smallest stable step
// of all: every rank sub-cycles alike.
void BodyDriver::check_time_step(double dt)
{
  if (spec_->rigid) return;
  dt_stable_ = stable_time_step_after_erosion(body_, spec_->erosion);
  if (distributed_) host_.min(&dt_stable_, 1);
  print(prefix() + time_step_line(dt_stable_, dt) +
        (spec_->erosion.min_dt > 0 ? " without the elements below erosion min_dt\n" : "\n"));
  substeps_ = spec_->substeps > 0 ? spec_->substeps : 1;
  follow_stable_step(-1, dt, dt_stable_);
  step_substeps_ = substeps_;
  std::string violation;
  if (substeps_ == 1)
    violation = time_step_violation(dt_stable_, dt, spec_->mesh_file);
  else if (dt / substeps_ > dt_stable_)
    violation = format("FE step %g (host timestep %g / substeps %d) exceeds the stable FE time "
                       "step %g of mesh '%s'; give more 'substeps' (or 'substeps auto'), reduce "
                       "'timestep' or coarsen the mesh (keyword 'dt_check warn' runs anyway)",
                       dt / substeps_, dt, substeps_, dt_stable_, spec_->mesh_file.c_str());
  if (violation.empty()) return;
  if (spec_->dt_check_error) fail(prefix() + violation);
  warn(prefix() + violation);
}

// substeps auto: the FE steps per host step that the stable step dt_stable asks for (at most
// kMaxSubsteps; beyond, the callers' checks of the FE step stop or warn as dt_check says); a
// change is logged. step < 0: at set-up. Every replica (and every part of a distributed body,
// given the smallest step of the parts) finds the same n.
void BodyDriver::follow_stable_step(std::int64_t step, double dt, double dt_stable)
{
  if (spec_->substeps != kSubstepsAuto || spec_->rigid) return;
  int n = 1;
  if (dt > dt_stable) {
    const double ratio = dt / dt_stable;
    n = ratio < kMaxSubsteps ? static_cast<int>(std::ceil(ratio)) : kMaxSubsteps;
    while (n < kMaxSubsteps && dt / n > dt_stable) // ceil of a rounded ratio
      ++n;
  }
  if (n == substeps_) return;
  substeps_ = n;
  const std::string when = step < 0 ? "" : "step " + std::to_string(step) + ": ";
  print(prefix() + when +
        format("stable FE time step %g %s host time step %g: %d FE substep%s per host step\n",
               dt_stable, n > 1 ? "<" : ">=", dt, n, n > 1 ? "s" : ""));
}

// "host time step DT", or with sub-cycling "FE step H (host time step DT / N substeps)".
std::string BodyDriver::step_text(double dt) const
{
  if (substeps_ == 1) return format("host time step %g", dt);
  return format("FE step %g (host time step %g / %d substeps)", dt / substeps_, dt, substeps_);
}

std::string BodyDriver::open_energy_file()
{
  if (spec_->energy_file.empty() || host_.rank != 0 || energy_fp_) return "";
  energy_fp_ = std::fopen(spec_->energy_file.c_str(), "w");
  if (!energy_fp_)
    return "fix fem/body: keyword 'energy_file': cannot open '" + spec_->energy_file +
           "' for writing";
  // The material's dissipation: cracking, or the plastic work of a plastic material (which
  // does not crack); the bulk viscosity's work has a column of its own.
  std::fprintf(energy_fp_,
               "step,time,kinetic,strain,external_work,contact_work,total,nodes,elements,"
               "%s,split_nodes,fragments,boundary_work%s%s%s",
               spec_->material.plastic_model() ? "plastic_work" : "fracture_energy",
               spec_->viscosity.on ? ",viscous_work" : "",
               can_erode() ? ",eroded_elements,eroded_mass,eroded_energy" : "",
               body_.space().axisymmetric() ? ",shield_work" : "");
  for (const std::string& g : spec_->reaction_groups)
    std::fprintf(energy_fp_, ",reaction_%s_x,reaction_%s_y,reaction_%s_z", g.c_str(), g.c_str(),
                 g.c_str());
  for (const std::string& g : spec_->reaction_groups)
    std::fprintf(energy_fp_, ",displacement_%s_x,displacement_%s_y,displacement_%s_z", g.c_str(),
                 g.c_str(), g.c_str());
  // Last: the FE steps of the host step that ends at the row (where the body can sub-cycle).
  if (can_substep()) std::fputs(",substeps", energy_fp_);
  std::fputc('\n', energy_fp_);
  return "";
}

void BodyDriver::start_run()
{
  if (!velocities_applied_ && !restarted_) {
    for (const auto& s : spec_->initial_velocity)
      body_.set_velocity(body_node_set(body_, *spec_, s.set, "velocity"), s.v, s.mask);
    body_.impose_velocity_conditions();
  }
  velocities_applied_ = true;
  if (spec_->rigid) body_.move_rigid();
}

/* ----------------------------------------------------------------------
   memory
------------------------------------------------------------------------- */

template <typename T> static double vector_bytes(const std::vector<T>& v)
{
  return static_cast<double>(v.capacity() * sizeof(T));
}

// Particle-facet contact keeps its arrays private; they are estimated from its facet and node
// counts (particle_facet.cpp, contact_resolution.cpp): per facet the facet, its reference normal
// and about 1.5 edges in the edge map (an unordered_map node with a short vector); per node two
// doubles (surface area, indentation) and a neighbour list. The body-contact surface is public.
std::size_t BodyDriver::memory_bytes() const
{
  const double nf = static_cast<double>(contact_.facets().capacity());
  const double nn = body_.num_nodes();
  double bytes = nf * (sizeof(Facet) + 3 * sizeof(double) + 1.5 * 96) +
                 nn * (2 * sizeof(double) + sizeof(std::vector<int>)) +
                 6 * sizeof(int) * contact_.facets().size();
  bytes += vector_bytes(surface_.facets) + vector_bytes(surface_.nodes) +
           vector_bytes(surface_.incident_offset) + vector_bytes(surface_.incident) +
           vector_bytes(surface_.reach);
  // A distributed body's surface replica (contact_bodies yes; empty otherwise).
  bytes += vector_bytes(surf_x_) + vector_bytes(surf_v_) + vector_bytes(surf_m_) +
           vector_bytes(surf_f_) + vector_bytes(surf_owned_);
  return static_cast<std::size_t>(static_cast<double>(body_.memory_bytes()) + bytes);
}

// One line per body and run, beside the host's memory line: every rank holds the whole body,
// so a large body is most of a rank's memory.
void BodyDriver::log_memory()
{
  double bytes = static_cast<double>(memory_bytes());
  host_.max(&bytes, 1);
  print(format("fix fem/body %s: %d nodes, %d elements, %.4g MB per rank\n", id_.c_str(),
               body_.num_nodes(), body_.mesh().num_active_elems(), bytes / (1024.0 * 1024.0)));
}

/* ----------------------------------------------------------------------
   the step: velocity Verlet in step with the host (half kick + drift,
   forces, half kick), then fracture and the energy row. Sub-cycled
   (n = step_substeps_ > 1, h = dt / n): n - 1 whole FE steps of h here,
   each with the contact forces of the host's last evaluation held, then
   the last step's half kick and drift; its forces come with the host's
   contact evaluation, its second half kick in end_step
------------------------------------------------------------------------- */

void BodyDriver::begin_step(double dt)
{
  if (spec_->rigid) {
    body_.advance_time(dt);
    return body_.move_rigid();
  }
  step_substeps_ = substeps_;
  const double h = dt / step_substeps_;
  for (int k = 1; k < step_substeps_; ++k)
    substep(dt, h);
  body_.advance_time(h);
  body_.half_kick_drift(h);
}

// One whole FE step of h within the host step dt.
void BodyDriver::substep(double dt, double h)
{
  body_.advance_time(h);
  body_.half_kick_drift(h);
  substep_forces(dt, h);
  body_.half_kick(h);
}

// The forces of a substep: internal forces at the new positions (erosion and inverted elements
// as in compute_forces), the held contact forces and gravity, with their work over h. No contact
// search and no particle loop: those belong to the host step.
void BodyDriver::substep_forces(double dt, double h)
{
  const std::int64_t step = step_ + 1;
  body_.clear_internal_forces();
  body_.hold_contact_forces();
  if (distributed_) return distributed_forces(nullptr, step, dt, true, false); // no particles
  int first_inverted = -1;
  double scalars[2] = {internal_forces(step, dt, first_inverted), 0.0};
  scalars[1] = first_inverted >= 0 ? first_inverted + 1.0 : 0.0;
  if (split_element_work_) {
    host_.sum(body_.forces_data(), 3 * body_.num_nodes());
    host_.sum(scalars, 1);
    host_.max(&scalars[1], 1);
  }
  check_state(step, scalars[0], scalars[1]);
  body_.finish_forces(scalars[0], gravity_, h, true);
}

// Stops the run at an inverted element (inverted: its index + 1, 0 for none) or a NaN energy.
void BodyDriver::check_state(std::int64_t step, double energy, double inverted) const
{
  if (inverted > 0)
    fail(format("fix fem/body %s: element %d inverted (det F <= 0) at step %" PRId64
                "; the time step is too large or the load too severe for this mesh",
                id_.c_str(), static_cast<int>(inverted) - 1, step));
  if (!std::isfinite(energy))
    fail(format("fix fem/body %s: non-finite strain energy at step %" PRId64
                " (NaN/Inf in the body state)",
                id_.c_str(), step));
}

void BodyDriver::end_step(std::int64_t step, double dt)
{
  step_ = step;
  if (spec_->rigid) return;
  body_.half_kick(dt / step_substeps_);
  // The held contact force reached the body earlier than the Verlet average its partners got:
  // the difference, so that momentum is exchanged exactly every host step.
  if (step_substeps_ > 1) body_.kick_contact_difference(0.5 * (dt - dt / step_substeps_));
  // Fracture first: it erodes the collapsed failed elements, whose stable step the periodic
  // check would otherwise follow for one step.
  if (body_.crack_tracking()) log_crack_starts(step, body_.track_cracks());
  if (spec_->fracture_every > 0 && step % spec_->fracture_every == 0) fracture(step, dt);
  // A distributed body's modelled work drifts only where elements can be damaged, yield or
  // leave (item 4).
  if (distributed_ && work_can_drift() && step % spec_->rebalance_every == 0) check_balance(step);
  if (step % kStableStepCheckEvery == 0) check_squeezed(step, dt);
  write_energy_row_if_due(step);
}

void BodyDriver::compute_forces(const ParticleArrays* particles, std::int64_t step, double dt,
                                bool count_work)
{
  const int nn = body_.num_nodes();
  step_ = step;
  const double h = dt / step_substeps_; // the FE step whose forces these are
  body_.begin_forces();
  if (!count_work) body_.replay_viscous_forces_once(); // set-up: see Body
  contact_.hold_history(!count_work);                  // set-up: see ParticleFacetContact
  ghosts_.hold_history(!count_work);
  if (distributed_) return distributed_forces(particles, step, dt, count_work, true);

  // Local shares: internal forces of this rank's elements, contact forces of this rank's
  // particles; one reduction makes every replica identical.
  int first_inverted = -1;
  const double local_energy = internal_forces(step, dt, first_inverted);
  // Contact between the body's pieces and with other bodies: each rank takes the surface nodes
  // of its part of the scene (without a scene, rank 0 all), into the contact forces the ranks
  // sum.
  if (spec_->contact_bodies > 0 && (in_scene() || host_.rank == 0))
    body_contact_forces(step, dt, count_work);
  ParticleFacetResult res;
  if (particles) {
    contact_.set_node_masses(contact_masses());
    contact_.set_inelastic_nodes(mark_inelastic_nodes());
    res = contact_.evaluate(*particles, body_.mesh().X.data(), body_.positions().data(),
                            body_.velocities().data(), dt, body_.contact_forces());
    warn_history_slots(res);
  }

  // energy, contacts, unresolved contacts (summed); first inverted element + 1 (max)
  double scalars[4] = {local_energy, static_cast<double>(res.contacts),
                       res.unresolved_speed > 0 ? 1.0 : 0.0,
                       static_cast<double>(first_inverted >= 0 ? first_inverted + 1 : 0)};
  if (split_element_work_) {
    host_.sum(body_.forces_data(), 3 * nn);
    host_.sum(body_.contact_forces(), 3 * nn);
    host_.sum(scalars, 3);
    host_.max(&scalars[3], 1);
  } else if (host_.nprocs > 1) { // element work replicated: only the contact shares are summed
    host_.sum(body_.contact_forces(), 3 * nn);
    host_.sum(&scalars[1], 2);
  }
  ncontacts_ = static_cast<int>(scalars[1]);
  if (scalars[2] > 0 && !warned_unresolved_) warn_unresolved_contact(step, res);
  check_state(step, scalars[0], scalars[3]);
  body_.finish_forces(scalars[0], gravity_, h, count_work);
}

// parallel distributed: the part's internal forces, summed at shared nodes with the neighbouring
// parts (one message each, no collective), the contact of its pieces (contact_bodies yes:
// body_self_contact.cpp, neighbour messages and one integer reduction) and of particles (facet
// ghosts by boxes, body_ghost_contact.cpp), once per host step. A body that erodes erodes its
// part's elements here and, at the host step's last evaluation (last), before the contact, takes
// the follow-up of every part's erosions (body_erosion.cpp: one integer reduction). Otherwise a
// rank that finds an inverted element or a NaN stops the run by itself (no per-step reduction to
// find out). dt: the host step.
void BodyDriver::distributed_forces(const ParticleArrays* particles, std::int64_t step, double dt,
                                    bool count_work, bool last)
{
  const double h = dt / step_substeps_; // the FE step whose forces these are
  int first_inverted = -1;
  double energy = body_.add_internal_forces(&first_inverted);
  if (can_erode()) energy = erode_part(energy, first_inverted, last);
  if (can_erode() && spec_->erosion.remove_mass)
    sum_forces_and_masses();
  else
    shared_sum_(body_.forces_data(), 3);
  // The pieces' travel flag (body_self_contact.cpp): on the erosion's integer reduction where
  // the body takes one, else one of its own (one integer per host step).
  const bool pieces = last && spec_->contact_bodies > 0;
  int moved = pieces ? piece_moved() : 0;
  if (can_erode() && last)
    distributed_erosion(step, dt, moved);
  else if (pieces)
    host_.max_int(&moved, 1);
  if (moved) piece_boxes_due_ = true;
  // Contact forces: each node's on one part (pieces, then particles), then summed once.
  if (pieces) body_contact_forces(step, dt, count_work);
  if (particles) distributed_contact(*particles, step, dt);
  if (pieces || particles) shared_sum_(body_.contact_forces(), 3);
  if (first_inverted >= 0)
    fail_one(format("fix fem/body %s: element %d inverted (det F <= 0) at step %" PRId64
                    "; the time step is too large or the load too severe for this mesh",
                    id_.c_str(), part_.global_elem[first_inverted], step));
  if (!std::isfinite(energy))
    fail_one(format("fix fem/body %s: non-finite strain energy at step %" PRId64
                    " (NaN/Inf in the body state)",
                    id_.c_str(), step));
  body_.finish_forces(energy, gravity_, h, count_work);
}

// Elements squeezed by the deformation (impact, plastic flow) shorten the stable step that set-up
// measured: under 'substeps auto' the FE steps per host step follow it (up or down); a step still
// too large is warned once, with the figures, before the run loses stability. A distributed body
// following the step takes the smallest of its parts' steps (one min-reduction every
// kStableStepCheckEvery steps, entered by every rank at the same step), so that every rank
// sub-cycles alike; otherwise each rank checks what it holds (a part warns by itself).
void BodyDriver::check_squeezed(std::int64_t step, double dt)
{
  const bool follow = spec_->substeps == kSubstepsAuto;
  if (warned_squeezed_ && !follow) return;
  double now = stable_time_step_after_erosion(body_, spec_->erosion);
  if (follow && distributed_) host_.min(&now, 1);
  if (follow) follow_stable_step(step, dt, now);
  if (!(now < dt / substeps_) || warned_squeezed_) return;
  warned_squeezed_ = true;
  const std::string text =
      format("fix fem/body %s: at step %" PRId64 " the stable FE time step of the deformed body "
             "is %g < %s (%g at set-up): its elements have been squeezed and the run can lose "
             "stability (an element inverts or the energy grows); reduce 'timestep'",
             id_.c_str(), step, now, step_text(dt).c_str(), dt_stable_);
  if ((distributed_ && !follow) || host_.rank == 0) host_.warning(text);
}

// Once per run: a particle hits the body faster than the time step can follow (every rank
// enters; the worst speed and the time step that resolves it come from all ranks).
void BodyDriver::warn_unresolved_contact(std::int64_t step, const ParticleFacetResult& res)
{
  warned_unresolved_ = true;
  double speed = res.unresolved_speed, dt_ok = res.resolving_dt;
  host_.max(&speed, 1);
  host_.min(&dt_ok, 1);
  warn(unresolved_contact_text(step, speed, dt_ok));
}

// Said once, by the rank whose particle ran out of slots (as the LIGGGHTS adapter did).
void BodyDriver::warn_history_slots(const ParticleFacetResult& res)
{
  if (!res.history_exhausted || warned_slots_) return;
  host_.warning("fix fem/body: a particle has more simultaneous facet contacts than "
                "'history_slots'; extra contacts run without tangential history");
  warned_slots_ = true;
}

std::string BodyDriver::unresolved_contact_text(std::int64_t step, double speed, double dt_ok) const
{
  return format("fix fem/body %s: at step %" PRId64 " a particle approaches the surface at %g "
                "m/s, more than %g %% of its Hertz penetration per time step; the contact is not "
                "resolved in time and may gain or lose energy: timestep %g or smaller resolves it",
                id_.c_str(), step, speed, 100 * kMaxApproachPerStep, dt_ok);
}

std::string BodyDriver::wide_patch_text(std::int64_t step, double radii) const
{
  return format("fix fem/body %s: at step %" PRId64 " a particle's Hertz patch reaches %.2f of "
                "its radii, beyond the %g radii of facets that the parts of a 'parallel "
                "distributed' body send to its rank (a contact deeper than 0.6 R): facets of other "
                "parts beyond that are left out of its patch, and the forces may differ from "
                "'parallel replicated' (warned once)",
                id_.c_str(), step, radii, kPatchRadii);
}

// Internal forces of this rank's elements; returns their strain energy. A breaking or eroding
// body erodes an element that inverts (it would only produce garbage), an eroding body also the
// elements that meet its criteria, and the step's internal forces are taken again (the material
// history does not advance twice). Its element work is replicated, so every rank does the same.
// Otherwise an inverted element is left in first_inverted (the run stops).
double BodyDriver::internal_forces(std::int64_t step, double dt, int& first_inverted)
{
  first_inverted = -1;
  double energy = body_.add_internal_forces(&first_inverted);
  if (spec_->erosion.on()) return forces_after_erosion(step, dt, energy, first_inverted);
  while (first_inverted >= 0 && spec_->fracture_every > 0 && !split_element_work_) {
    erode_inverted(step, first_inverted);
    body_.clear_internal_forces();
    first_inverted = -1;
    energy = body_.add_internal_forces(&first_inverted);
  }
  return energy;
}

// erosion ...: the elements that meet a criterion and any that inverted leave in one batch, then
// the forces are taken again until no element inverts; one log line per step. energy: that of
// the evaluation before.
double BodyDriver::forces_after_erosion(std::int64_t step, double dt, double energy,
                                        int& first_inverted)
{
  int counts[kErosionCauses] = {0, 0, 0, 0};
  std::vector<int> batch; // every element this step, for the log
  energy = erosion_loop(energy, first_inverted, counts, batch);
  if (!batch.empty()) after_erosion(step, dt, counts, batch);
  return energy;
}

// The loop of forces_after_erosion (a replicated body, or one part of a distributed one: every
// criterion and det F are element-local): counts per cause; batch: the criteria's elements
// (ascending), then the inverted ones (ascending: the first inverted one leaves at each pass).
double BodyDriver::erosion_loop(double energy, int& first_inverted, int* counts,
                                std::vector<int>& batch)
{
  std::vector<int> elems;
  std::vector<ErosionCause> causes;
  select_eroding(body_, spec_->erosion, elems, causes);
  for (;;) {
    if (first_inverted >= 0 &&
        std::find(elems.begin(), elems.end(), first_inverted) == elems.end()) {
      elems.push_back(first_inverted);
      causes.push_back(ErosionCause::Inverted);
    }
    if (elems.empty()) break;
    for (ErosionCause c : causes)
      ++counts[static_cast<int>(c)];
    batch.insert(batch.end(), elems.begin(), elems.end());
    body_.erode(elems, spec_->erosion.remove_mass);
    elems.clear();
    causes.clear();
    body_.clear_internal_forces();
    first_inverted = -1;
    energy = body_.add_internal_forces(&first_inverted);
  }
  return energy;
}

// After an erosion batch: the exposed faces join contact at once, the batch is logged in one
// line, and the stable step is taken again (under 'substeps auto' the FE steps per host step
// follow it). With 'erosion min_dt DT' at or above the FE step no element is left below it;
// otherwise a squeezed element that no criterion removes is warned about (once), as erosion never
// stops the run.
void BodyDriver::after_erosion(std::int64_t step, double dt, const int* counts,
                               const std::vector<int>& batch)
{
  rebuild_surfaces();
  print(erosion_line(step, counts, batch));
  dt_stable_ = body_.stable_time_step();
  follow_step_after_erosion(step, dt);
}

// The stable step after an erosion (dt_stable_) sets the FE steps of the next host step.
void BodyDriver::follow_step_after_erosion(std::int64_t step, double dt)
{
  follow_stable_step(step, dt, dt_stable_);
  const double h = dt / substeps_;
  if (dt_stable_ >= h || warned_dt_after_erosion_) return;
  warned_dt_after_erosion_ = true;
  warn(format("fix fem/body %s: after the erosion at step %" PRId64
              " the stable FE time step is %g, below the %s (an element squeezed that no erosion "
              "criterion removes); 'erosion min_dt %g' erodes such elements (warned once)",
              id_.c_str(), step, dt_stable_, step_text(dt).c_str(), h));
}

// One line per step: how many left, why, which (the first kMaxListed), and the totals.
std::string BodyDriver::erosion_line(std::int64_t step, const int* counts,
                                     const std::vector<int>& batch) const
{
  return erosion_line(step, counts, batch, body_.eroded());
}

std::string BodyDriver::erosion_line(std::int64_t step, const int* counts,
                                     const std::vector<int>& batch, const ErosionAccount& acc) const
{
  constexpr std::size_t kMaxListed = 12;
  std::string why, which;
  for (int c = 0; c < kErosionCauses; ++c)
    if (counts[c] > 0)
      why += (why.empty() ? "" : ", ") +
             std::string(erosion_cause_name(static_cast<ErosionCause>(c))) + " " +
             std::to_string(counts[c]);
  for (std::size_t k = 0; k < batch.size() && k < kMaxListed; ++k)
    which += " " + std::to_string(batch[k]);
  if (batch.size() > kMaxListed) which += " ...";
  return prefix() + "step " + std::to_string(step) + ": eroded " + std::to_string(batch.size()) +
         " elements (" + why + "):" + which +
         format("; %d eroded in all, mass %.6g removed, energy %.6g\n", acc.elements, acc.mass,
                acc.energy);
}

void BodyDriver::erode_inverted(std::int64_t step, int e)
{
  body_.erode({e}, spec_->erosion.remove_mass);
  rebuild_surfaces();
  print(inverted_line(step, e));
}

std::string BodyDriver::inverted_line(std::int64_t step, int e) const
{
  return format("fix fem/body %s: step %" PRId64
                ": element %d inverted (det F <= 0) and was eroded; its nodes keep their mass\n",
                id_.c_str(), step, e);
}

/* ----------------------------------------------------------------------
   surfaces and body-body contact
------------------------------------------------------------------------- */

// The masses a particle contact moves: the nodes' lumped masses, 0 (infinitely heavy) where a
// fixed or prescribed node does not move; nullptr for a rigid body.
const double* BodyDriver::contact_masses()
{
  if (body_.rigid()) return nullptr;
  const std::vector<double>& m = body_.masses();
  const std::vector<NodeBc>& bc = body_.conditions();
  contact_mass_.resize(m.size());
  for (size_t n = 0; n < m.size(); ++n)
    contact_mass_[n] = bc[n] == NodeBc::Fixed || bc[n] == NodeBc::Prescribed ? 0.0 : m[n];
  return contact_mass_.data();
}

// Nodes of elements whose material has begun to fail (damage), for the particle contact's Hertz
// patch; nullptr without a patch or while no point of the body is damaged (nothing to look at).
const std::vector<char>* BodyDriver::mark_inelastic_nodes()
{
  if (!contact_.options().hertz_patch || body_.damaged_points() == 0) return nullptr;
  const Mesh& mesh = body_.mesh();
  inelastic_nodes_.assign(mesh.num_nodes(), 0);
  for (int e = 0; e < mesh.num_elems(); ++e) {
    if (!mesh.active[e] || !body_.element_damaged(e)) continue;
    for (int a : mesh.conn[e])
      if (a >= 0) inelastic_nodes_[a] = 1;
  }
  return &inelastic_nodes_;
}

// After a topology change: particle contact and the contact between the body's own pieces.
void BodyDriver::rebuild_surfaces()
{
  contact_.rebuild_surface(body_.mesh());
  if (spec_->contact_bodies <= 0) return;
  if (distributed_)
    part_surface_due_ = true; // from the parts, at the next evaluation (every rank enters)
  else
    surface_.build(body_.mesh(), contact_.facets());
  self_contact_.invalidate();
  self_edges_.invalidate();
  if (in_scene()) coordinator_->invalidate();
  // The pairs of a distributed body with replicated ones: maps of the new surface, the edge
  // contact's search afresh.
  if (distributed_) pair_maps_due_ = true;
  for (BodyPair& p : distributed_ ? pairs_ : pair_body_ ? pair_body_->pairs_ : pairs_)
    p.edges.invalidate();
}

// This body's pieces and its pairs with the later bodies (forces into their pending arrays,
// which their own force evaluation takes up). Without a scene (no set_partners: unit tests) the
// pieces only, on rank 0.
int BodyDriver::body_contacts(std::int64_t step, double dt)
{
  if (!in_scene()) {
    ContactBodyState me{body_.positions().data(), body_.velocities().data(), body_.masses().data(),
                        body_.contact_forces()};
    int n = self_contact_.evaluate(surface_, me, surface_, me, true, dt);
    if (spec_->contact_edges) n += self_edges_.evaluate(surface_, me, surface_, me, true, dt);
    return n;
  }
  coordinator_->configure_if_pending();
  try {
    return coordinator_->evaluate(scene_index_, step, dt);
  } catch (const std::runtime_error& e) {
    fail(prefix() + e.what());
  }
}

/* ----------------------------------------------------------------------
   held contact forces. The forces of a step come from its mid-step
   velocities; the host's set-up evaluation of a run that goes on (a second
   'run', or one after read_restart) comes at unchanged positions but full-
   step velocities, so the friction of the pieces' contact (and with it
   the first half kick, the trapezoidal contact work and the next contact
   offsets) would differ from the uninterrupted run's: 1.2e-6 of the contact
   work's scale on the torn bar of test_distributed_self_contact. That
   evaluation takes the forces of the last counted one instead, as the
   bulk viscosity does (Body::replay_viscous_forces_once), and leaves the
   contact state as that one left it. Every member of a scene replays, or
   none: an earlier member's evaluation would add to a later one's forces.
------------------------------------------------------------------------- */

void BodyDriver::body_contact_forces(std::int64_t step, double dt, bool count_work)
{
  if (replays_body_contacts(count_work)) return replay_body_contacts();
  if (distributed_)
    distributed_body_contacts(step, dt);
  else
    body_contacts(step, dt);
  pair_contacts(dt);
  if (count_work) hold_body_contacts();
}

bool BodyDriver::replays_body_contacts(bool count_work) const
{
  if (count_work) return false;
  // A distributed body and its replicated partners: all of them replay, or none.
  if (!pair_group_.empty()) {
    if (!(distributed_ ? this : pair_body_)->pair_continues_) return false;
    for (const BodyDriver* m : pair_group_)
      if (!m->contacts_held_) return false;
    return true;
  }
  if (!in_scene()) return contacts_held_;
  // Bodies in contact with each other: only where they are the last run's and their pairs go on
  // (docs/fix_fem_body.md).
  return coordinator_->replays();
}

// After a counted evaluation, before particle contact adds to them: the contact forces of this
// rank's surface nodes (a distributed body's part: of its nodes, before the sum over the parts
// that share them, by global number), zero ones left out.
void BodyDriver::hold_body_contacts()
{
  held_nodes_.clear();
  held_forces_.clear();
  held_whole_ = false;
  const double* f = body_.contact_forces();
  const auto hold = [&](int n, int key) {
    if (f[3 * n] == 0 && f[3 * n + 1] == 0 && f[3 * n + 2] == 0) return;
    held_nodes_.push_back(key);
    held_forces_.insert(held_forces_.end(), &f[3 * n], &f[3 * n] + 3);
  };
  if (distributed_) {
    for (int n = 0; n < part_.num_nodes(); ++n)
      hold(n, part_.global_node[n]);
  } else {
    for (int n : surface_.nodes)
      hold(n, n);
  }
  contacts_held_ = true;
}

// The held forces as the evaluation left them (begin_forces zeroed the contact forces, and no
// other member adds to them at this set-up). A part takes its own share back, or from a restart
// record (the whole body's sums) those of the nodes it owns.
void BodyDriver::replay_body_contacts()
{
  if (in_scene()) coordinator_->configure_if_pending();
  const std::vector<int> local =
      distributed_ ? local_of_global(part_.global_node, global_nodes_) : std::vector<int>();
  double* f = body_.contact_forces();
  for (size_t k = 0; k < held_nodes_.size(); ++k) {
    const int key = held_nodes_[k];
    const int n = !distributed_                                      ? key
                  : key >= 0 && key < static_cast<int>(local.size()) ? local[key]
                                                                     : -1;
    if (distributed_ && held_whole_ && n >= 0 && !part_.owns(n)) continue;
    if (n >= 0 && n < body_.num_nodes())
      std::copy(&held_forces_[3 * k], &held_forces_[3 * k] + 3, &f[3 * n]);
  }
}

// For the restart record (every rank enters, with contact_bodies yes): (node, force) of the whole
// body, the ranks' shares summed (a distributed body's: gathered on rank 0, which writes the
// record). Empty when none is held.
std::vector<double> BodyDriver::held_body_contacts_record() const
{
  if (spec_->contact_bodies <= 0) return {};
  const int nodes = distributed_ ? global_nodes_ : body_.num_nodes();
  std::vector<double> all(3 * static_cast<size_t>(std::max(nodes, 0)), 0.0), mine;
  if (distributed_) { // the parts' shares in part order, summed at shared nodes on rank 0
    for (size_t k = 0; k < held_nodes_.size(); ++k) {
      mine.push_back(held_nodes_[k]);
      mine.insert(mine.end(), &held_forces_[3 * k], &held_forces_[3 * k] + 3);
    }
    const std::vector<double> parts = host_.gather ? host_.gather(mine) : mine;
    for (size_t k = 0; k + 3 < parts.size(); k += 4)
      if (parts[k] >= 0 && parts[k] < nodes)
        for (int d = 0; d < 3; ++d)
          all[3 * static_cast<size_t>(parts[k]) + d] += parts[k + 1 + d];
  } else {
    for (size_t k = 0; k < held_nodes_.size(); ++k)
      std::copy(&held_forces_[3 * k], &held_forces_[3 * k] + 3, &all[3 * held_nodes_[k]]);
    if (host_.nprocs > 1) host_.sum(all.data(), static_cast<int>(all.size()));
  }
  mine.clear();
  for (int n = 0; n < nodes; ++n)
    if (all[3 * n] != 0 || all[3 * n + 1] != 0 || all[3 * n + 2] != 0) {
      mine.push_back(n);
      mine.insert(mine.end(), &all[3 * n], &all[3 * n] + 3);
    }
  return mine;
}

// From a restart record: rank 0 of a replicated body takes them all (the others none, so that
// the ranks' sum is the whole), every part of a distributed body all of them (each replays its
// own nodes').
void BodyDriver::take_held_body_contacts(const double* list, size_t n)
{
  held_nodes_.clear();
  held_forces_.clear();
  held_whole_ = true;
  if (distributed_ || host_.rank == 0)
    for (size_t k = 0; k + 3 < n; k += 4) {
      held_nodes_.push_back(static_cast<int>(list[k]));
      held_forces_.insert(held_forces_.end(), list + k + 1, list + k + 4);
    }
  contacts_held_ = true;
}

/* ----------------------------------------------------------------------
   nodal fracture: failure map, crack points, node splits (every replica
   makes the same splits from the same state), then the new crack faces
   join the contact surface at once
------------------------------------------------------------------------- */

void BodyDriver::fracture(std::int64_t step, double dt)
{
  if (distributed_) return distributed_fracture(step, dt); // body_breaking.cpp
  FractureOutcome out;
  if (!crack_body(step, dt, out)) return;
  // Replicas must stay identical: a rank that split or cut differently stops the run at once.
  const int ne = body_.mesh().num_elems();
  int counts[4] = {body_.num_nodes(), -body_.num_nodes(), ne, -ne};
  host_.max_int(counts, 4);
  if (counts[0] != -counts[1] || counts[2] != -counts[3])
    fail("fix fem/body: ranks disagree on the cracked topology (replicas diverged)");
  if (!out.cuts.empty()) share_element_work();
  rebuild_surfaces();
  log_cracks(step, out);
  check_step_after_cracks(step, dt, !out.cuts.empty());
}

// The plan's input from a failure map: its crack points and failed elements, the check's rule.
FracturePlanInput BodyDriver::fracture_input(const FailureMap& map, double dt) const
{
  FracturePlanInput in;
  in.points = crack_points(body_.mesh(), map);
  in.failed = map.failed;
  in.rule.min_size = spec_->min_size;
  in.rule.erode_cracked = spec_->erode_cracked;
  in.rule.remove_mass = spec_->erosion.remove_mass;
  in.rule.dt = dt;
  return in;
}

// One fracture check on body_: its plan (failure map, crack points, cuts and splits, partings,
// the collapsed failed elements eroded) made and applied; whether the topology changed. outlook
// (a gathered whole body): what the body looks like to the next checks.
bool BodyDriver::crack_body(std::int64_t step, double dt, FractureOutcome& out,
                            SeparationOutlook* outlook)
{
  // An intact body (no damaged point in the last force evaluation; the element work of a
  // breaking body is done on every rank, so all see the same count) has nothing to check.
  if (body_.damaged_points() == 0) return false;
  if (build_failure_map(body_, failure_map_) == 0) return false;
  FracturePlanInput in = fracture_input(failure_map_, dt);
  in.pieces = distributed_ ? nullptr : &face_pieces_;
  in.outlook = outlook != nullptr;
  const FracturePlan plan = plan_fracture(body_, in);
  if (outlook) *outlook = plan.outlook;
  out = apply_fracture_plan(body_, plan);
  log_erosions(step, out.eroded);
  return out.changed();
}

void BodyDriver::log_cracks(std::int64_t step, const FractureOutcome& out)
{
  log_cuts(step, out.cuts);
  log_splits(step, out.splits);
  log_fragments(step);
}

// New elements (cracks through elements) join the element work: a body whose work is shared
// among the ranks gets its ranges again (a whole-body range grows with the mesh by itself).
void BodyDriver::share_element_work()
{
  if (split_element_work_)
    split_element_work_ =
        fracdem::split_element_work(body_, host_.rank, host_.nprocs, spec_->erosion.on());
}

// Every topology change that can shorten the stable step (splits, cuts, erosion of a failed
// element) comes here: the step is estimated again, 'substeps auto' follows it, and one still
// below the FE step stops the run (dt_check error) or is warned about.
void BodyDriver::check_step_after_cracks(std::int64_t step, double dt, bool cut)
{
  dt_stable_ = body_.stable_time_step();
  if (distributed_) host_.min(&dt_stable_, 1); // the smallest of the parts': the whole body's
  follow_stable_step(step, dt, dt_stable_);
  if (!(dt_stable_ < dt / substeps_)) return;
  const std::string msg =
      format("fix fem/body %s: at step %" PRId64
             " the stable FE time step of the cracked body is %g < %s%s",
             id_.c_str(), step, dt_stable_, step_text(dt).c_str(),
             cut ? " (cracks through elements made smaller elements: raise 'fracture nodal "
                   "min_size' or reduce 'timestep')"
                 : "");
  if (spec_->dt_check_error) fail(msg);
  warn(msg);
}

// Each crack through an element, in the log file (on the screen up to four, else their count).
void BodyDriver::log_cuts(std::int64_t step, const std::vector<CutEvent>& cuts) const
{
  const bool each_on_screen = cuts.size() <= 4;
  for (const CutEvent& c : cuts) {
    std::string line = format("fix fem/body %s: step %" PRId64
                              ": crack through element %d at node %d (t = %.3f) -> new node %d, "
                              "new element %d",
                              id_.c_str(), step, c.elem, c.node, c.t, c.new_node,
                              c.new_elems.empty() ? -1 : c.new_elems[0]);
    if (c.new_elems.size() > 1) {
      line += format("; edge %d-%d also splits", c.u, c.w);
      for (size_t k = 1; k < c.new_elems.size(); ++k)
        line += format(" %d", body_.element_parent(c.new_elems[k]));
      line += " into new";
      for (size_t k = 1; k < c.new_elems.size(); ++k)
        line += format(" %d", c.new_elems[k]);
    }
    print(line + "\n", each_on_screen, true);
  }
  if (!each_on_screen)
    print(format("fix fem/body %s: step %" PRId64 ": %zu cracks through elements (see log)\n",
                 id_.c_str(), step, cuts.size()),
          true, false);
}

// A failed element (no tension left) squeezed into a sliver would collapse the stable time step
// of the whole body: the check erodes it (its nodes keep their mass unless remove_mass).
void BodyDriver::log_erosions(std::int64_t step, const std::vector<int>& eroded) const
{
  for (int e : eroded)
    print(format(
        "fix fem/body %s: step %" PRId64 ": failed element %d %s, eroded\n", id_.c_str(), step, e,
        spec_->erode_cracked ? "carries no more tension" : "squeezed below the host time step"));
}

// Every split in the log file; on the screen up to four, else their count.
void BodyDriver::log_splits(std::int64_t step, const std::vector<SplitEvent>& events) const
{
  const bool each_on_screen = events.size() <= 4;
  for (const SplitEvent& ev : events) {
    // A separation (zero normal) has no failure plane: it frees pieces that touched only at
    // the node, which the cracks around it had already cut apart.
    const bool separation = ev.normal[0] == 0 && ev.normal[1] == 0 && ev.normal[2] == 0;
    const std::string plane =
        separation ? std::string("pieces that touched only at it separated")
                   : format("normal (%.3f %.3f %.3f)", ev.normal[0], ev.normal[1], ev.normal[2]);
    print(format("fix fem/body %s: step %" PRId64 ": crack at node %d -> new node %d, %s, %d "
                 "elements moved\n",
                 id_.c_str(), step, ev.node, ev.copy, plane.c_str(), ev.elements_moved),
          each_on_screen, true);
  }
  if (!each_on_screen)
    print(format("fix fem/body %s: step %" PRId64 ": %zu node splits (see log)\n", id_.c_str(),
                 step, events.size()),
          true, false);
}

// When the body has come apart into more pieces: their count and masses, largest first.
void BodyDriver::log_fragments(std::int64_t step)
{
  const std::vector<double> mass = fragment_masses(body_);
  const int count = static_cast<int>(mass.size());
  if (count == last_fragments_) return;
  last_fragments_ = count;
  std::string line = prefix() + "step " + std::to_string(step) + ": " + std::to_string(count) +
                     " fragments, masses";
  for (size_t k = 0; k < mass.size() && k < 8; ++k)
    line += format(" %.4g", mass[k]);
  line += mass.size() > 8 ? " ...\n" : "\n";
  print(line);
}

/* ----------------------------------------------------------------------
   output
------------------------------------------------------------------------- */

void BodyDriver::write_energy_row_if_due(std::int64_t step)
{
  if (spec_->energy_file.empty() || step % spec_->energy_every != 0) return;
  if (distributed_)
    write_distributed_energy_row(step); // every rank enters the reduction
  else if (energy_fp_)
    write_energy_row(step);
}

// The replicated row's columns, each summed over the parts (owned nodes; a group's mean
// displacement from the sums and counts of its owned nodes). Split nodes and fragments: rank 0's
// counts of the whole body at the last change (the topology changes nowhere else).
void BodyDriver::write_distributed_energy_row(std::int64_t step)
{
  if (step == last_energy_step_) return;
  last_energy_step_ = step;
  double owned = 0;
  for (int n = 0; n < part_.num_nodes(); ++n)
    owned += part_.owns(n) ? 1.0 : 0.0;
  std::vector<double> v = {body_.kinetic_energy(),
                           body_.strain_energy(),
                           body_.external_work(),
                           body_.contact_work(),
                           owned,
                           static_cast<double>(body_.mesh().num_active_elems()),
                           body_.dissipated_energy(),
                           body_.boundary_work(),
                           body_.viscous_work(),
                           body_.shield_work(),
                           static_cast<double>(body_.eroded().elements),
                           body_.eroded().mass,
                           body_.eroded().energy};
  const auto& r = body_.reactions();
  for (size_t k = 0; k < 3 * spec_->reaction_groups.size(); ++k)
    v.push_back(k < r.size() ? r[k] : 0.0);
  for (const std::string& g : spec_->reaction_groups) {
    double u[4] = {0, 0, 0, 0}; // displacement sums, count
    for (int n : body_node_set(body_, *spec_, g, "energy_file")) {
      if (!part_.owns(n)) continue;
      for (int d = 0; d < 3; ++d)
        u[d] += body_.positions()[3 * n + d] - body_.mesh().X[3 * n + d];
      u[3] += 1;
    }
    v.insert(v.end(), u, u + 4);
  }
  host_.sum(v.data(), static_cast<int>(v.size()));
  if (!energy_fp_) return;
  std::FILE* fp = energy_fp_;
  std::fprintf(fp, "%" PRId64 ",%.10g,%.12g,%.12g,%.12g,%.12g,%.12g,%d,%d,%.12g,%d,%d,%.12g", step,
               body_.time(), v[0], v[1], v[2], v[3], v[0] + v[1], static_cast<int>(v[4]),
               static_cast<int>(v[5]), v[6], whole_split_nodes_, whole_fragments_, v[7]);
  if (spec_->viscosity.on) std::fprintf(fp, ",%.12g", v[8]);
  if (can_erode()) std::fprintf(fp, ",%d,%.12g,%.12g", static_cast<int>(v[10]), v[11], v[12]);
  if (body_.space().axisymmetric()) std::fprintf(fp, ",%.12g", v[9]);
  size_t k = 13;
  for (size_t j = 0; j < 3 * spec_->reaction_groups.size(); ++j)
    std::fprintf(fp, ",%.12g", v[k++]);
  for (size_t g = 0; g < spec_->reaction_groups.size(); ++g, k += 4) {
    const double count = v[k + 3] > 0 ? v[k + 3] : 1.0;
    std::fprintf(fp, ",%.12g,%.12g,%.12g", v[k] / count, v[k + 1] / count, v[k + 2] / count);
  }
  if (can_substep()) std::fprintf(fp, ",%d", step_substeps_);
  std::fputc('\n', fp);
  std::fflush(fp);
}

void BodyDriver::write_energy_row(std::int64_t step)
{
  if (step == last_energy_step_) return; // a new run starts where the last ended
  last_energy_step_ = step;
  std::FILE* fp = energy_fp_;
  const double ke = body_.kinetic_energy(), se = body_.strain_energy();
  std::fprintf(fp, "%" PRId64 ",%.10g,%.12g,%.12g,%.12g,%.12g,%.12g,%d,%d,%.12g,%d,%d,%.12g", step,
               body_.time(), ke, se, body_.external_work(), body_.contact_work(), ke + se,
               body_.num_nodes(), body_.mesh().num_active_elems(), body_.dissipated_energy(),
               split_node_count(body_), fragment_count(body_), body_.boundary_work());
  if (spec_->viscosity.on) std::fprintf(fp, ",%.12g", body_.viscous_work());
  if (can_erode())
    std::fprintf(fp, ",%d,%.12g,%.12g", body_.eroded().elements, body_.eroded().mass,
                 body_.eroded().energy);
  if (body_.space().axisymmetric()) std::fprintf(fp, ",%.12g", body_.shield_work());
  const auto& r = body_.reactions();
  for (size_t k = 0; k < 3 * spec_->reaction_groups.size(); ++k)
    std::fprintf(fp, ",%.12g", k < r.size() ? r[k] : 0.0);
  // Mean displacement of each group's nodes (load-displacement curves).
  for (const std::string& g : spec_->reaction_groups) {
    const std::vector<int> nodes = body_node_set(body_, *spec_, g, "energy_file");
    double u[3] = {0, 0, 0};
    for (int n : nodes)
      for (int d = 0; d < 3; ++d)
        u[d] += (body_.positions()[3 * n + d] - body_.mesh().X[3 * n + d]) / nodes.size();
    std::fprintf(fp, ",%.12g,%.12g,%.12g", u[0], u[1], u[2]);
  }
  if (can_substep()) std::fprintf(fp, ",%d", step_substeps_);
  std::fputc('\n', fp);
  std::fflush(fp);
}

double BodyDriver::scalar()
{
  double value = body_.kinetic_energy() + body_.strain_energy();
  if (distributed_) host_.sum(&value, 1);
  return value;
}

int BodyDriver::vector_size() const
{
  return kVecSize + 3 * static_cast<int>(spec_->reaction_groups.size()) + kVecTailSize;
}

double BodyDriver::vector_entry(int i)
{
  if (distributed_) return distributed_vector_entry(i);
  switch (i) {
  case kVecContacts:
    return ncontacts_;
  case kVecStableDt:
    return dt_stable_;
  case kVecSearchRebuilds: {
    double rebuilds = contact_.search_rebuilds();
    host_.max(&rebuilds, 1);
    return rebuilds;
  }
  }
  const int ngroups = static_cast<int>(spec_->reaction_groups.size());
  double value = 0.0;
  if (body_vector_entry(body_, i, ngroups, value)) return value;
  switch (i - (kVecSize + 3 * ngroups)) {
  case kVecErodedElements:
    return body_.eroded().elements;
  case kVecErodedMass:
    return body_.eroded().mass;
  case kVecErodedEnergy:
    return body_.eroded().energy;
  case kVecShieldWork:
    return body_.shield_work();
  case kVecSubsteps:
    return step_substeps_;
  case kVecMass:
    return body_.total_mass();
  }
  return 0.0;
}

/* ----------------------------------------------------------------------
   restart: the mesh is re-read from the same file when the input script
   re-creates the fix; the body's state, topology included, is restored
   from the record
------------------------------------------------------------------------- */

// A distributed body's entries are sums over the parts (each counts the nodes it owns), but the
// stable step (the smallest) and the node count (owned nodes).
double BodyDriver::distributed_vector_entry(int i)
{
  const int ngroups = static_cast<int>(spec_->reaction_groups.size());
  double value = 0.0;
  if (i == kVecNodes) {
    for (int n = 0; n < part_.num_nodes(); ++n)
      value += part_.owns(n) ? 1.0 : 0.0;
  } else if (i == kVecStableDt) {
    return dt_stable_; // already the smallest of the parts'
  } else if (i == vector_size() - kVecTailSize + kVecSubsteps) {
    return step_substeps_; // the same on every part
  } else if (i == kVecContacts) {
    value = ncontacts_; // each particle's contacts are counted on its rank
  } else if (i == kVecSearchRebuilds) {
    value = ghosts_.contact().search_rebuilds();
    host_.max(&value, 1);
    return value;
  } else if (i == kVecSplitNodes || i == kVecFragments) { // rank 0 counts the whole body's
    if (host_.rank == 0) value = i == kVecSplitNodes ? whole_split_nodes_ : whole_fragments_;
  } else if (!body_vector_entry(body_, i, ngroups, value)) {
    const ErosionAccount& eroded = body_.eroded();
    switch (i - (kVecSize + 3 * ngroups)) {
    case kVecShieldWork:
      value = body_.shield_work();
      break;
    case kVecErodedElements:
      value = eroded.elements;
      break;
    case kVecErodedMass:
      value = eroded.mass;
      break;
    case kVecErodedEnergy:
      value = eroded.energy;
      break;
    case kVecMass:
      value = body_.total_mass();
      break;
    }
  }
  host_.sum(&value, 1);
  return value;
}

// Marker, length, placement, sections (the pieces' contacts, the held contact forces).
std::vector<double> BodyDriver::record_head(const std::vector<double>& held) const
{
  std::vector<double> buf = {kRecordHead, 0.0, spec_->rigid ? 1.0 : 0.0,
                             static_cast<double>(spec_->transforms.size())};
  for (const MeshTransform& t : spec_->transforms) {
    buf.push_back(static_cast<double>(t.kind));
    buf.insert(buf.end(), t.a, t.a + 4);
  }
  std::vector<double> state[kHeadSections];
  if (spec_->contact_bodies > 0) self_contact_.pack_state(state[0]);
  if (spec_->contact_bodies > 0) self_edges_.pack_state(state[1]);
  state[2] = held;
  state[3] = pair_records();
  if (body_.crack_tracking()) pack_track_state(body_.track_state(), state[4]);
  static_assert(std::size(kHeadSectionTags) == kHeadSections, "one tag per head section");
  for (int i = 0; i < kHeadSections; ++i)
    if (!state[i].empty()) {
      buf.push_back(kHeadSectionTags[i]);
      buf.push_back(static_cast<double>(state[i].size()));
      buf.insert(buf.end(), state[i].begin(), state[i].end());
    }
  buf[1] = static_cast<double>(buf.size() - 2);
  return buf;
}

std::vector<double> BodyDriver::restart_record() const
{
  return record_with(held_body_contacts_record());
}

// The record with the held contact forces of the whole body (held_body_contacts_record).
std::vector<double> BodyDriver::record_with(const std::vector<double>& held) const
{
  std::vector<double> buf = record_head(held);
  std::vector<double> body;
  if (distributed_)
    body = distributed_body_record();
  else
    body_.pack_state(body);
  buf.insert(buf.end(), body.begin(), body.end());
  return buf;
}

// Each part's record (part_restart.h: its nodes and elements by global number, and its own
// state as it holds it), gathered on rank 0, which writes them one after the other behind the
// partition; the other ranks get nothing. No whole body is assembled.
std::vector<double> BodyDriver::distributed_body_record() const
{
  const std::vector<double> mine = pack_part_record(body_, part_, topo_);
  const std::vector<double> all = host_.gather ? host_.gather(mine) : mine;
  if (host_.rank != 0) return {};
  const double driver[kDriverValues] = {broken_ ? 1.0 : 0.0, double(whole_split_nodes_),
                                        double(whole_fragments_), double(last_fragments_)};
  try {
    return join_part_records(all, host_.nprocs, global_nodes_, global_elems_, driver);
  } catch (const std::exception& e) {
    fail_one(prefix() + e.what());
  }
  return {};
}

void BodyDriver::write_restart(std::FILE* fp) const
{
  // The pieces' contacts are spread over the ranks' parts of the scene, or over the parts of a
  // distributed body: gathered (every rank; where they are changes, not what they are).
  if (in_scene()) coordinator_->gather_self_state(scene_index_);
  if (distributed_ && spec_->contact_bodies > 0)
    const_cast<BodyDriver*>(this)->gather_piece_state();
  const std::vector<double> held = held_body_contacts_record(); // every rank
  if (!distributed_ && host_.rank != 0) return; // a replicated body: rank 0 holds it all
  const std::vector<double> buf = record_with(held);
  if (host_.rank != 0) return;
  const int nbytes = static_cast<int>(buf.size() * sizeof(double));
  std::fwrite(&nbytes, sizeof(int), 1, fp);
  std::fwrite(buf.data(), sizeof(double), buf.size(), fp);
}

// A body record: the whole body's (Body::pack_state), the parts' (part_restart.h) or, from older
// files, the parts merged (kPartsRecordVersion), read by a whole body or by this rank's part.
void BodyDriver::read_body_record(const double* record)
{
  face_pieces_ = FacePieces(); // the restored topology's pieces are taken at the next check
  if (record[0] == kPartRecordsVersion) return take_part_records(record);
  if (record[0] == kPartsRecordVersion) {
    unpack_parts_record(record, body_, distributed_ ? &part_ : nullptr,
                        !distributed_ || host_.rank == 0);
    return;
  }
  if (!distributed_) return body_.unpack_state(record);
  Body whole; // the record of a replicated run: restored whole, then this part taken from it
  build_body(*spec_, dimension_, whole);
  whole.unpack_state(record);
  take_whole(whole);
}

// This rank's part of a whole body restored from a record on every rank.
void BodyDriver::take_whole(const Body& whole)
{
  if (split_node_count(whole) == 0 && whole.eroded().elements == 0 && whole.cut_nodes().empty())
    return copy_whole_into_part(whole, body_, part_, host_.rank == 0);
  // A broken body: every rank partitions it alike (METIS, fixed seed) and takes its part.
  const std::vector<int> elem_part = repartition(whole, std::vector<int>());
  adopt_part(part_message_with_state(whole, whole_topology(whole), elem_part,
                                     pack_surface(global_surface(whole.mesh(), elem_part)),
                                     host_.rank));
  broken_ = true;
  count_whole(whole);
}

// The parts' records. At the rank count that wrote them each rank takes its part of the stored
// partition back as it was (the continued run is the uninterrupted one, bit for bit); at
// another count, or replicated, they are merged into the whole body and taken as a whole record.
void BodyDriver::take_part_records(const double* record)
{
  const PartRecords r = read_part_records(record);
  const int mesh_elems = distributed_ ? mesh_elems_ : body_.mesh().num_elems();
  const auto merged = [&](Body& whole) {
    restore_gathered(merge_part_wholes(gathered_wholes(r), r.global_nodes, r.global_elems,
                                       mesh_elems, body_.bulk_viscosity().on),
                     whole);
  };
  if (!distributed_) return merged(body_);
  Body whole;
  if (r.nparts != host_.nprocs) {
    build_body(*spec_, dimension_, whole);
    merged(whole);
    return take_whole(whole);
  }
  // Rank 0 alone restores the whole body and sends each rank its part, as after a change.
  std::vector<double> surface;
  PartTopology topo;
  if (host_.rank == 0) {
    try {
      build_body(*spec_, dimension_, whole);
      merged(whole);
      surface = pack_surface(global_surface(whole.mesh(), r.elem_part));
      topo = whole_topology(whole);
    } catch (const std::exception& e) {
      fail_one(prefix() + e.what() + " (mesh '" + spec_->mesh_file + "')");
    }
  }
  const auto make = [&](int k) {
    return part_message_with_state(whole, topo, r.elem_part, surface, k);
  };
  adopt_part(host_.scatter(make));
  try {
    restore_own_part(r, body_, part_, topo_);
  } catch (const std::exception& e) { // this rank's block alone: stop from here
    fail_one(prefix() + e.what() + " (mesh '" + spec_->mesh_file + "')");
  }
  broken_ = r.driver[0] != 0.0;
  whole_split_nodes_ = static_cast<int>(r.driver[1]);
  whole_fragments_ = static_cast<int>(r.driver[2]);
  last_fragments_ = static_cast<int>(r.driver[3]);
}

// The head (after marker and length): placement, then sections. The stored state keeps the
// stored placement (reference coordinates included), so a command that places the body
// otherwise, or changes 'rigid', would be silently overruled: refused.
void BodyDriver::read_head(const double* head, int n, const double* (&state)[kHeadSections],
                           size_t (&state_size)[kHeadSections])
{
  const int nt = n >= 2 ? static_cast<int>(head[1]) : -1;
  if (nt < 0 || n < 2 + 5 * nt) fail("fix fem/body: corrupt restart record");
  std::vector<MeshTransform> stored(nt);
  for (int k = 0; k < nt; ++k) {
    stored[k].kind = static_cast<MeshTransform::Kind>(static_cast<int>(head[2 + 5 * k]));
    std::copy(head + 3 + 5 * k, head + 7 + 5 * k, stored[k].a);
  }
  const bool rigid = head[0] != 0.0;
  if (rigid != spec_->rigid || !same_placement(stored, spec_->transforms))
    fail(prefix() + "the restart file holds this body with '" + placement_text(rigid, stored) +
         "' but this command gives '" + placement_text(spec_->rigid, spec_->transforms) +
         "'; the body continues from the stored state and placement, so give the stored "
         "keywords (to start the body afresh from its mesh instead, put 'run 0' before this fix "
         "command: a run drops the file's fix states)");
  for (int k = 2 + 5 * nt; k < n;) {
    const double tag = head[k];
    const int size = k + 1 < n ? static_cast<int>(head[k + 1]) : -1;
    if (size < 0 || k + 2 + size > n) fail("fix fem/body: corrupt restart record");
    const double* const known = std::find(kHeadSectionTags, kHeadSectionTags + kHeadSections, tag);
    const int section = known == kHeadSectionTags + kHeadSections
                            ? -1 // a section of a later version: skipped
                            : static_cast<int>(known - kHeadSectionTags);
    if (section >= 0) {
      state[section] = head + k + 2;
      state_size[section] = static_cast<size_t>(size);
    }
    k += 2 + size;
  }
}

void BodyDriver::read_restart(const double* record)
{
  const double* state[kHeadSections] = {};
  size_t state_size[kHeadSections] = {};
  if (record[0] == kRecordHead) {
    const int n = static_cast<int>(record[1]);
    read_head(record + 2, n, state, state_size);
    record += 2 + n;
  }
  try {
    read_body_record(record);
  } catch (const std::exception& e) {
    fail(prefix() + e.what() + " (mesh '" + spec_->mesh_file +
         "'); use the same mesh file and transforms as the run that wrote it");
  }
  if (state[4] && body_.crack_tracking()) {
    CrackTrackState track;
    unpack_track_state(state[4], track);
    body_.set_track_state(std::move(track));
  }
  rebuild_surfaces();
  // The pieces' contacts continue where they were (without: a resting contact would restart
  // as an unexplained penetration and lose its force).
  if (spec_->contact_bodies > 0) {
    try {
      if (state[0]) self_contact_.unpack_state(state[0], state_size[0]);
      if (state[1]) self_edges_.unpack_state(state[1], state_size[1]);
      if (state[2]) take_held_body_contacts(state[2], state_size[2]);
      // The contacts between bodies wait for the bodies' set-up (set_partners).
      restored_pairs_.assign(state[3], state[3] + state_size[3]);
    } catch (const std::exception& e) {
      fail(prefix() + e.what());
    }
    piece_state_spread_ = false; // every rank read the same
  }
  restarted_ = true;
}

} // namespace fracdem

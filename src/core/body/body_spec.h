// BodySpec: every setting of fix fem/body, its one keyword table, parser and checks.
#pragma once

#include <functional>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "contact/contact_scene.h"
#include "contact/granular_law.h"
#include "fem/body_motion.h"
#include "fem/erosion.h"
#include "materials/bulk_viscosity.h"
#include "materials/material.h"

namespace fracdem
{

// An input error of fix fem/body. The text names the keyword but not the fix; a host writes it
// after "fix fem/body: ", or after "fix fem/body ID: " when names_fix() (errors found while
// building the body). fix_message() composes that line.
class SpecError : public std::invalid_argument
{
public:
  explicit SpecError(const std::string& what, bool names_fix = false)
      : std::invalid_argument(what), names_fix_(names_fix)
  {
  }
  bool names_fix() const { return names_fix_; }

private:
  bool names_fix_;
};
// "fix fem/body: TEXT" or "fix fem/body ID: TEXT".
std::string fix_message(const SpecError& e, const std::string& fix_id);

struct FixedSpec {
  std::string set;
  int mask = 7;   // held components, bit d = component d
  int group = -1; // reaction account
};
struct NodeVelocitySpec {
  std::string set;
  double v[3] = {0, 0, 0};
  int mask = 7;    // components given (bit d = component d); NULL leaves a component out
  double ramp = 0; // prescribed_velocity: linear ramp time
  int group = -1;  // reaction account (prescribed_velocity)
};

constexpr int kMaxHistorySlots = 64;
// substeps auto|N|off (BodySpec::substeps): the values auto and off, and the largest count
// (given, or chosen by auto) of FE steps per host step.
constexpr int kSubstepsAuto = 0;
constexpr int kSubstepsOff = -1;
constexpr int kMaxSubsteps = 100;

// Every setting of `fix ID group fem/body file MESH keyword value ...` (docs/fix_fem_body.md).
// Fields marked "-1: default" are resolved by check_body_spec.
struct BodySpec {
  std::string mesh_file;
  int surface_type = -1; // type
  Material material;     // density youngs poisson model plane thickness material eos
  bool have_density = false, have_youngs = false, have_poisson = false, have_plane = false;
  std::vector<FixedSpec> fixed_sets;
  std::vector<std::string> reaction_groups; // fixed / prescribed_velocity groups, in order
  std::vector<NodeVelocitySpec> initial_velocity, prescribed_velocity;
  std::vector<MeshTransform> transforms; // scale move rotate, in order
  bool rigid = false;
  RigidMotion motion;
  int fracture_every = 0;     // fracture nodal [every N]; 0: no fracture
  bool erode_cracked = false; // fracture nodal erode_cracked yes
  double min_size = 0;        // fracture nodal min_size F: cracks may cut elements; 0: they do not
  double track_length = 0;    // fracture nodal track L: crack tracking over length L; 0: off
  double track_exclusion = 0; // fracture nodal exclusion R: nucleation exclusion radius; 0: L
  BulkViscosity viscosity;
  int viscosity_mode = -1;        // -1: default (on for plastic materials / EOS), 0: off, 1: on
  ErosionCriteria erosion;        // erosion ...; erosion_mass keep|remove (remove_mass)
  bool have_erosion_mass = false; // erosion_mass given
  // ---- particle contact (LIGGGHTS's words; a host may take its own) ----
  NormalModel normal_model = NormalModel::Hertz; // contact_model
  bool tangential_history = true;                // tangential history|no_history
  int compliance_combined = -1; // compliance; -1: default (combined for rigid bodies)
  double buffer = -1;           // search buffer; < 0: the host's neighbour skin
  int history_slots = 8;
  // ---- body-body contact ----
  int contact_bodies = -1; // -1: default (yes with fracture, else no)
  double contact_penalty = 0.1;
  bool contact_edges = true; // contact_edges yes|no: edge-to-edge contact (3D) beside node-to-facet
  // contact_balance: how the contact work of all contact_bodies bodies is shared among ranks
  // (given on the first of them, which holds the scene).
  ContactBalance contact_balance;
  bool have_contact_balance = false;
  // ---- run ----
  bool dt_check_error = true; // dt_check error|warn
  // substeps auto|N|off: FE steps per host step (kSubstepsAuto: as many as the stable step asks
  // for; N > 0: fixed; kSubstepsOff: one, the stable step checked as dt_check says).
  int substeps = kSubstepsAuto;
  bool have_substeps = false; // substeps given
  bool apply_gravity = true;
  std::string energy_file;
  int energy_every = 0;
  // parallel replicated|distributed: every rank holds the whole body, or one METIS part of it
  // (docs/distributed_bodies.md). Not given (have_parallel false): chosen at set-up by the
  // body's size (body_setup.h parallel_choice).
  bool distributed = false;
  bool have_parallel = false;
  // parallel distributed rebalance B [every N]: a breaking distributed body is repartitioned when
  // its parts' modelled work drifts above B times the mean, checked every N steps.
  double rebalance = 1.2;
  int rebalance_every = 1000;

  // Index of the reaction account of a node group (one per group name, in order of appearance).
  int reaction_group(const std::string& set);
};

// The words of one fix command from the first keyword on, read keyword by keyword: a handler
// reads the values after keyword() and take()s what it used. Errors name the keyword.
class SpecReader
{
public:
  SpecReader(const std::vector<std::string>& words, std::size_t first) : w_(words), i_(first) {}
  bool done() const { return i_ >= w_.size(); }
  const std::string& keyword() const { return w_[i_]; }
  // Whether the keyword has at least n more words after it.
  bool has(std::size_t n) const { return i_ + n < w_.size(); }
  // Throws "keyword 'KW' expects WHAT" unless has(n).
  void need(std::size_t n, const std::string& what) const;
  const std::string& word(std::size_t k) const { return w_.at(i_ + k); }
  // The k-th word after the keyword as a finite number / int, named by the keyword.
  double number(std::size_t k) const;
  int whole_number(std::size_t k) const;
  // word(1) is `first` (true) or `second` (false), both taken; anything else throws.
  bool either(const char* first, const char* second);
  // The words from word(1) to the end (for sub-parsers that stop by themselves).
  std::vector<std::string> rest() const;
  void take(std::size_t n) { i_ += n; }

private:
  const std::vector<std::string>& w_;
  std::size_t i_;
};

// `word` as the value of `keyword`: a finite number written in full ("1e999", "abc", "2x" are
// refused: "keyword 'KW' expects a finite number, got 'abc'"), or an integer that fits an int.
double spec_number(const std::string& keyword, const std::string& word);
int spec_whole_number(const std::string& keyword, const std::string& word);

using KeywordHandler = std::function<void(SpecReader&, BodySpec&)>;

// One host's view of the keyword table. The default (empty) host takes every keyword of the
// table (the LIGGGHTS adapter). A host may
//  * list the table's keywords it takes in `supported` (others are refused, "keyword 'KW' is
//    not yet supported under NAME (supported: ...)"; unknown keywords then list them too), and
//  * add or replace keywords in `own` (its own syntax, or a refusal with a reason): its handlers
//    run before the table's and may keep their results outside the BodySpec.
struct BodySpecHost {
  std::string name; // "LAMMPS"
  struct Supported {
    std::string keyword;
    std::string note = ""; // listed as keyword(note), e.g. material(elastic)
  };
  std::vector<Supported> supported; // empty: all of the table
  std::map<std::string, KeywordHandler> own;

  bool takes(const std::string& keyword) const; // a keyword this host accepts
};

// The keywords of the common table, in the documentation's order.
std::vector<std::string> body_keywords();

// Reads the words after the style name: "file MESH keyword value ...". Throws SpecError.
BodySpec parse_body_spec(const std::vector<std::string>& words, const BodySpecHost& host = {});
// Checks the whole spec against the run (atom types 1..ntypes, dimension 2|3) and resolves the
// defaults (compliance, bulk viscosity, contact_bodies, a rigid body's density). Throws SpecError.
void check_body_spec(BodySpec& spec, const BodySpecHost& host, int ntypes, int dimension);
// What of the (checked) spec a distributed body does not do yet ("'rigid yes'", ...), or null.
const char* distributed_refusal(const BodySpec& spec);
// What keeps the body replicated when the spec leaves the choice to its size: the refusals and
// 'fracture', 'erosion' and 'contact_bodies yes' (a distributed body breaks, erodes and takes
// its pieces' contact only when asked: docs/distributed_bodies.md).
const char* distributed_default_refusal(const BodySpec& spec);

} // namespace fracdem

// Work model of a particle (paper section 5.1): the price of each interaction, what a particle
// did, its cost, and the graph weights (a priori and a posteriori) derived from them.
#ifndef FRACDEM_BALANCE_COST_MODEL_H
#define FRACDEM_BALANCE_COST_MODEL_H

#include <array>
#include <cstdint>
#include <vector>

namespace fracdem::balance
{

// Work per particle is modelled as a sum over what the step did for it: a fixed per-particle
// part, a gap test per primitive wall, potential pairs checked, sphere-sphere contacts resolved,
// liquid bridges (pair_style fracdem/gran), primitive-wall contacts, facet checks and facet
// contacts of deformable bodies. Costs are relative to one pair check.
struct InteractionCosts {
  // per particle and step, with or without neighbours: integration, force clearing, gravity,
  // binning and the stencil walk of reneighbouring (a free-flying particle costs this much)
  double particle = 1.0;
  double wall_check = 1.0; // per particle and primitive wall: the gap test
  double pair_check = 1.0;
  double sphere_contact = 1.0;
  double wall_contact = 1.0;
  double facet_check = 1.0;
  double facet_contact = 1.0;
  double bridge = 1.0; // per liquid bridge: its capillary and viscous force, beyond the check
};

// What the last step did for one particle: the terms of the work model.
struct ParticleCounts {
  int walls = 0;           // primitive walls (one gap test each)
  long pair_checks = 0;    // potential pairs in its neighbour list
  int sphere_contacts = 0; // pairs in contact
  int wall_contacts = 0, facet_checks = 0, facet_contacts = 0;
  int bridges = 0; // liquid bridges (a bridged pair in contact is a contact and a bridge)
};

// Plain counts: every item costs 1.
InteractionCosts unit_costs();

// Work of one particle in one step: the per-particle term (paid by every particle, neighbours
// or not) plus every check and contact priced by c.
double particle_cost(const InteractionCosts& c, const ParticleCounts& k);

// The share of one neighbour pair's work each of its two particles takes when a pair is split
// evenly (a particle's cost then does not depend on which of the two holds the pair in a half
// list): half a check, and half a contact where the spheres touch.
double half_pair_cost(const InteractionCosts& c, bool touching);

// The terms of the work model as the cost fit sees them, one count per rank and check. The ghost
// term is fitted too, so that boundary work does not bias the particle terms, but it is not part
// of a particle's cost (it follows the cut, not the particle).
enum CostTerm {
  kParticle,
  kWallCheck,
  kPairCheck,
  kSphereContact,
  kWallContact,
  kFacetCheck,
  kFacetContact,
  kBridge,
  kGhost,
  kCostTerms
};
using TermCounts = std::array<double, kCostTerms>;

// What one check counted on a rank, per local particle (pair checks are `potential`).
struct WorkCounts {
  int walls = 0;                       // primitive walls: a gap test per particle each
  std::vector<std::int64_t> potential; // potential targets in the neighbour list
  std::vector<int> contacts, wall_contacts, facet_checks, facet_contacts, bridges;

  void reset(int nlocal, int nwalls); // nlocal particles with nothing counted
  int size() const { return static_cast<int>(potential.size()); }
  ParticleCounts particle(int i) const;
  // This rank's total of each term; `ghosts` is the rank's ghost count.
  TermCounts term_sums(double ghosts) const;
};

// The graph a repartition cuts: vertices weighted by potential targets (a priori) or by the
// recorded cost (a posteriori), whose contact edges also weigh what a contact costs.
enum class GraphModel { APriori, APosteriori };

// Integer vertex weight of a particle of average cost (a posteriori).
constexpr double kWeightResolution = 100.0;

// Vertex weight per particle, integers >= 1: potential targets (a priori), or
// kWeightResolution * cost / mean_cost (a posteriori). Throws std::invalid_argument unless cost
// and potential have one entry per particle.
std::vector<std::int64_t> vertex_weights(GraphModel model, const std::vector<double>& cost,
                                         const std::vector<std::int64_t>& potential,
                                         double mean_cost);

// Edge weight of a neighbour pair: 1, plus (a posteriori, spheres touching) the cost of a contact
// in pair checks, rounded, at least 1 and at most 10^6 (1 where the pair check is free).
struct EdgeWeights {
  std::int64_t contact = 1; // the extra weight of a touching pair (a posteriori)
  bool aposteriori = true;
  std::int64_t of(bool touching) const { return aposteriori && touching ? 1 + contact : 1; }
};
EdgeWeights edge_weights(GraphModel model, const InteractionCosts& c);

} // namespace fracdem::balance

#endif

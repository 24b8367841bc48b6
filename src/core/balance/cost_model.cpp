// Work model of a particle: its cost from its counts, and the graph weights derived from it.
#include "balance/cost_model.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace fracdem::balance
{

InteractionCosts unit_costs()
{
  return InteractionCosts{};
}

double particle_cost(const InteractionCosts& c, const ParticleCounts& k)
{
  return c.particle + k.walls * c.wall_check + static_cast<double>(k.pair_checks) * c.pair_check +
         k.sphere_contacts * c.sphere_contact + k.wall_contacts * c.wall_contact +
         k.facet_checks * c.facet_check + k.facet_contacts * c.facet_contact + k.bridges * c.bridge;
}

double half_pair_cost(const InteractionCosts& c, bool touching)
{
  return 0.5 * c.pair_check + (touching ? 0.5 * c.sphere_contact : 0.0);
}

void WorkCounts::reset(int nlocal, int nwalls)
{
  walls = nwalls;
  potential.assign(nlocal, 0);
  contacts.assign(nlocal, 0);
  wall_contacts.assign(nlocal, 0);
  facet_checks.assign(nlocal, 0);
  facet_contacts.assign(nlocal, 0);
  bridges.assign(nlocal, 0);
}

ParticleCounts WorkCounts::particle(int i) const
{
  ParticleCounts k;
  k.walls = walls;
  k.pair_checks = static_cast<long>(potential[i]);
  k.sphere_contacts = contacts[i], k.wall_contacts = wall_contacts[i];
  k.facet_checks = facet_checks[i], k.facet_contacts = facet_contacts[i];
  k.bridges = bridges[i];
  return k;
}

TermCounts WorkCounts::term_sums(double ghosts) const
{
  TermCounts sums{};
  const int n = size();
  for (int i = 0; i < n; ++i) {
    sums[kPairCheck] += potential[i];
    sums[kSphereContact] += contacts[i];
    sums[kWallContact] += wall_contacts[i];
    sums[kFacetCheck] += facet_checks[i];
    sums[kFacetContact] += facet_contacts[i];
    sums[kBridge] += bridges[i];
  }
  sums[kParticle] = n;
  sums[kWallCheck] = static_cast<double>(walls) * n;
  sums[kGhost] = ghosts;
  return sums;
}

std::vector<std::int64_t> vertex_weights(GraphModel model, const std::vector<double>& cost,
                                         const std::vector<std::int64_t>& potential,
                                         double mean_cost)
{
  if (cost.size() != potential.size())
    throw std::invalid_argument("vertex_weights: need one cost and one potential per particle");
  std::vector<std::int64_t> weight(cost.size());
  for (std::size_t i = 0; i < cost.size(); ++i) {
    const double w = model == GraphModel::APriori
                         ? static_cast<double>(std::max<std::int64_t>(1, potential[i]))
                         : kWeightResolution * cost[i] / mean_cost;
    weight[i] = std::max<std::int64_t>(1, std::llround(w));
  }
  return weight;
}

EdgeWeights edge_weights(GraphModel model, const InteractionCosts& c)
{
  EdgeWeights e;
  e.aposteriori = model == GraphModel::APosteriori;
  // A fitted pair-check cost may be zero: the ratio is then taken as 1.
  e.contact = c.pair_check > 0 ? std::max<std::int64_t>(
                                     1, std::llround(std::min(1e6, c.sphere_contact / c.pair_check)))
                               : 1;
  return e;
}

} // namespace fracdem::balance

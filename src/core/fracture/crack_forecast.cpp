// Forecast of a fracture check from one body's failed elements and crack flags.
#include "fracture/crack_forecast.h"


#include "fracture/nodal_fracture.h"

namespace fracdem
{

CrackNodes whole_crack_nodes(const Body& whole, double min_size)
{
  const int nn = whole.num_nodes();
  CrackNodes c;
  c.split = split_nodes(whole);
  c.whole_star.assign(nn, 1);
  c.on_crack = c.split;
  if (min_size > 0)
    for (size_t k = 0; k < whole.cut_nodes().size(); k += 3)
      c.on_crack[whole.cut_nodes()[k]] = 1;
  return c;
}

namespace
{
// crack_body's erosion (BodyDriver::erode_collapsed) of active failed element e.
bool erodes(const Body& body, const CrackNodes& nodes, const FractureCheckRule& rule, int e)
{
  if (!rule.erode_cracked) return body.element_time_step(e) < rule.dt;
  const Mesh& mesh = body.mesh();
  for (int a = 0; a < nodes_per_elem(mesh.etype[e]); ++a)
    if (nodes.split[mesh.conn[e][a]]) return true; // elements_on_crack
  return false;
}
} // namespace

bool check_may_change(const Body& body, const CrackNodes& nodes, const FractureCheckRule& rule,
                      const std::function<double(int)>& fraction)
{
  if (!body.failed_elements()) return true; // the last evaluation saw part of the elements
  FailureMap map;
  build_failure_map(body, map); // the active failed elements
  for (int e : map.failed)
    if (erodes(body, nodes, rule, e)) return true;
  for (int v : crack_points(body.mesh(), map))
    if (!nodes.whole_star[v] ||
        crack_point_may_split(body, v, nodes.on_crack, rule.min_size, fraction, &nodes.whole_star))
      return true;
  return false;
}

} // namespace fracdem

// Set-up of fix fem/body's Body from a BodySpec: mesh, placement, checks, conditions, work split.
#include "body/body_setup.h"

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>

#include "fem/node_split.h"
#include "io/gmsh_reader.h"
#include "materials/material_table.h"

namespace fracdem
{

namespace
{

} // namespace

Mesh placed_body_mesh(const BodySpec& spec, int dimension)
{
  Mesh mesh;
  try {
    mesh = read_gmsh(spec.mesh_file, dimension);
  } catch (const std::exception& e) {
    throw SpecError(std::string("cannot use mesh: ") + e.what(), true);
  }
  if (mesh.dim != dimension)
    throw SpecError("mesh '" + spec.mesh_file + "' is " + std::to_string(mesh.dim) +
                    "D but the simulation is " + std::to_string(dimension) + "D");
  bool in_plane = false;
  try {
    in_plane = apply_transforms(mesh, spec.transforms);
  } catch (const std::invalid_argument& e) {
    throw SpecError(std::string("keyword 'rotate': ") + e.what(), true);
  }
  if (!in_plane) throw SpecError("2D mesh must stay in the z = 0 plane after 'move'/'rotate'");
  for (int e = 0; e < mesh.num_elems(); ++e)
    if (!element_geometry_finite(mesh, e))
      throw SpecError("keyword 'scale'/'move'/'rotate': element " + std::to_string(e) + " of '" +
                          spec.mesh_file + "' overflows double precision",
                      true);
  return mesh;
}

// The body of a (placed) mesh: material, conditions, motion (the names of velocity groups are
// checked now, the velocities applied at the run).
void build_body_from_mesh(const BodySpec& spec, Mesh mesh, Body& body)
{
  const std::string material_error = material_setup_error(spec.material, mesh.dim);
  if (!material_error.empty()) throw SpecError(material_error, true);
  try {
    body.build(std::move(mesh), spec.material, spec.rigid);
  } catch (const std::exception& e) {
    throw SpecError("bad mesh '" + spec.mesh_file + "': " + e.what(), true);
  }
  body.set_rigid_motion(spec.motion);
  body.set_bulk_viscosity(spec.viscosity);
  for (const FixedSpec& s : spec.fixed_sets)
    body.set_fixed(body_node_set(body, spec, s.set, "fixed"), s.mask, s.group);
  for (const NodeVelocitySpec& s : spec.prescribed_velocity)
    body.set_prescribed_velocity(body_node_set(body, spec, s.set, "prescribed_velocity"), s.v,
                                 s.ramp, s.group, s.mask);
  for (const NodeVelocitySpec& s : spec.initial_velocity)
    body_node_set(body, spec, s.set, "velocity"); // names checked now, applied at the run
}
void build_body(const BodySpec& spec, int dimension, Body& body)
{
  build_body_from_mesh(spec, placed_body_mesh(spec, dimension), body);
}

std::vector<double> pack_surface(const GlobalSurface& s)
{
  std::vector<double> out = {static_cast<double>(s.facets.size())};
  for (size_t f = 0; f < s.facets.size(); ++f) {
    const Facet& fc = s.facets[f];
    out.insert(out.end(),
               {double(fc.n[0]), double(fc.n[1]), double(fc.n[2]), double(fc.nn), double(fc.elem),
                double(fc.local_face), double(s.part[f]), double(s.piece[f])});
    out.insert(out.end(), &s.ref_normal[3 * f], &s.ref_normal[3 * f] + 3);
  }
  out.push_back(static_cast<double>(s.nodes.size()));
  for (size_t k = 0; k < s.nodes.size(); ++k) {
    out.push_back(s.nodes[k]);
    out.insert(out.end(), &s.X[3 * k], &s.X[3 * k] + 3);
    out.push_back(s.area[k]);
  }
  return out;
}

GlobalSurface unpack_surface(const std::vector<double>& in, std::size_t& at)
{
  auto take = [&](std::size_t n) {
    if (n > in.size() || at > in.size() - n)
      throw std::runtime_error("a body part's message is shorter than its surface");
    at += n;
    return in.data() + at - n;
  };
  GlobalSurface s;
  const auto nf = static_cast<std::size_t>(*take(1));
  for (std::size_t f = 0; f < nf; ++f) {
    const double* v = take(11);
    Facet fc;
    fc.n = {int(v[0]), int(v[1]), int(v[2])};
    fc.nn = int(v[3]);
    fc.elem = int(v[4]);
    fc.local_face = int(v[5]);
    s.facets.push_back(fc);
    s.part.push_back(int(v[6]));
    s.piece.push_back(int(v[7]));
    s.ref_normal.insert(s.ref_normal.end(), v + 8, v + 11);
  }
  const auto nn = static_cast<std::size_t>(*take(1));
  for (std::size_t k = 0; k < nn; ++k) {
    const double* v = take(5);
    s.nodes.push_back(int(v[0]));
    s.X.insert(s.X.end(), v + 1, v + 4);
    s.area.push_back(v[4]);
  }
  return s;
}

std::vector<double> part_message(const Mesh& whole, const std::vector<int>& elem_part,
                                 const std::vector<double>& packed_surface, int rank)
{
  std::vector<double> out = {static_cast<double>(whole.num_nodes()),
                             static_cast<double>(whole.num_elems())};
  pack_part(extract_part(whole, elem_part, rank), out);
  out.insert(out.end(), packed_surface.begin(), packed_surface.end());
  return out;
}

MeshPart build_body_part(const BodySpec& spec, const std::vector<double>& message, Body& body,
                         int& global_nodes, int& global_elems, GlobalSurface* surface,
                         std::size_t* end)
{
  MeshPart part;
  try {
    std::size_t at = 2;
    if (message.size() < at) throw std::runtime_error("empty body part message");
    global_nodes = static_cast<int>(message[0]);
    global_elems = static_cast<int>(message[1]);
    part = unpack_part(message, at);
    if (surface) *surface = unpack_surface(message, at);
    if (end) *end = at;
  } catch (const std::runtime_error& e) {
    throw SpecError(std::string("keyword 'parallel distributed': ") + e.what(), true);
  }
  build_body_from_mesh(spec, part.mesh, body);
  std::vector<std::uint8_t> owned(part.num_nodes()), shared(part.num_nodes());
  for (int n = 0; n < part.num_nodes(); ++n) {
    owned[n] = part.owns(n);
    shared[n] = part.shared(n);
  }
  body.set_counted_nodes(std::move(owned));
  body.set_shared_nodes(std::move(shared));
  return part;
}

MeshPart build_body_part(const BodySpec& spec, int dimension, int rank, int nprocs, Body& body,
                         int& global_nodes, int& global_elems, GlobalSurface* surface)
{
  const Mesh whole = placed_body_mesh(spec, dimension);
  const std::vector<int> elem_part = partition_elements(whole, nprocs);
  const std::vector<double> packed =
      surface ? pack_surface(global_surface(whole, elem_part)) : std::vector<double>{0.0, 0.0};
  return build_body_part(spec, part_message(whole, elem_part, packed, rank), body, global_nodes,
                         global_elems, surface);
}

std::string parallel_choice(const BodySpec& spec, long long elements, bool& distributed)
{
  distributed = spec.distributed;
  if (spec.have_parallel) return "";
  distributed = false;
  const char* refused = distributed_default_refusal(spec);
  // What a distributed body does when asked: breaking, eroding, its pieces' contact.
  const bool when_asked = refused && !distributed_refusal(spec);
  if (when_asked)
    return std::string("parallel replicated (by default: the body uses ") + refused +
           ", which a distributed body does only when asked: 'parallel distributed')";
  if (refused)
    return std::string("parallel replicated (by default: the body uses ") + refused +
           ", which distributed bodies do not do yet)";
  distributed = elements > kDistributedMinElements;
  const std::string n = std::to_string(elements), limit = std::to_string(kDistributedMinElements);
  if (distributed)
    return "parallel distributed (by default: " + n + " elements > " + limit +
           "; 'parallel replicated' keeps the whole body on every rank)";
  return "parallel replicated (by default: " + n + " elements <= " + limit +
         "; 'parallel distributed' splits it)";
}

std::vector<int> body_node_set(const Body& body, const BodySpec& spec, const std::string& name,
                               const std::string& keyword)
{
  const Mesh& mesh = body.mesh();
  if (name == "all") {
    std::vector<int> all(mesh.num_nodes());
    for (int i = 0; i < mesh.num_nodes(); ++i)
      all[i] = i;
    return all;
  }
  auto it = mesh.node_sets.find(name);
  if (it == mesh.node_sets.end()) {
    std::string msg = "keyword '" + keyword + "': mesh '" + spec.mesh_file +
                      "' has no physical group '" + name + "'; it has:";
    for (const auto& kv : mesh.node_sets)
      msg += " " + kv.first;
    throw SpecError(msg + " (and 'all')");
  }
  return it->second;
}

// Every rank holds the whole body. The element work of a material without history is split
// evenly; one with history (softening, cracks, the viscous work of the bulk viscosity) is
// advanced on every rank, so that every replica holds the whole material state.
bool split_element_work(Body& body, int rank, int nprocs, bool replicated)
{
  if (nprocs <= 1 || replicated || body.space().state_size() != 0 || body.bulk_viscosity().on)
    return false;
  const long long ne = body.mesh().num_elems();
  body.set_element_range(static_cast<int>((ne * rank) / nprocs),
                         static_cast<int>((ne * (rank + 1)) / nprocs));
  return true;
}

std::string time_step_line(double dt_stable, double dt)
{
  char line[160];
  std::snprintf(line, sizeof(line), "stable FE time step %.6g, host time step %.6g (%.1f%%)",
                dt_stable, dt, 100.0 * dt / dt_stable);
  return line;
}

std::string time_step_violation(double dt_stable, double dt, const std::string& mesh_file)
{
  if (!(dt > dt_stable)) return "";
  char head[160];
  std::snprintf(head, sizeof(head), "host timestep %g exceeds the stable FE time step %g", dt,
                dt_stable);
  return std::string(head) + " of mesh '" + mesh_file +
         "'; reduce 'timestep' or coarsen the mesh (keyword 'dt_check warn' runs anyway)";
}

int split_node_count(const Body& body)
{
  const auto& parents = body.parents();
  return static_cast<int>(parents.size() - std::count(parents.begin(), parents.end(), -1));
}

int fragment_count(const Body& body)
{
  std::vector<int> comp;
  return element_components(body.mesh(), comp);
}

namespace
{

// The body's entries of the vector below kVecSize: false for the host's.
bool body_scalar(const Body& body, int i, double& value)
{
  switch (i) {
  case kVecKinetic:
    value = body.kinetic_energy();
    return true;
  case kVecStrain:
    value = body.strain_energy();
    return true;
  case kVecExternalWork:
    value = body.external_work();
    return true;
  case kVecContactWork:
    value = body.contact_work();
    return true;
  case kVecNodes:
    value = body.num_nodes();
    return true;
  case kVecElements:
    value = body.mesh().num_active_elems();
    return true;
  case kVecForceX:
  case kVecForceY:
  case kVecForceZ:
    value = body.contact_force_total()[i - kVecForceX];
    return true;
  case kVecMomentumX:
  case kVecMomentumY:
  case kVecMomentumZ:
    value = body.momentum(i - kVecMomentumX);
    return true;
  case kVecDissipated: // the material's and the bulk viscosity's: the energy balance's
    value = body.dissipated_energy() + body.viscous_work();
    return true;
  case kVecSplitNodes:
    value = split_node_count(body);
    return true;
  case kVecFragments:
    value = fragment_count(body);
    return true;
  case kVecBoundaryWork:
    value = body.boundary_work();
    return true;
  default:
    return false;
  }
}

} // namespace

bool body_vector_entry(const Body& body, int i, int ngroups, double& value)
{
  if (i < kVecSize) return body_scalar(body, i, value);
  if (i >= kVecSize + 3 * ngroups) return false;
  const auto& r = body.reactions();
  const std::size_t k = static_cast<std::size_t>(i - kVecSize);
  value = k < r.size() ? r[k] : 0.0;
  return true;
}

namespace
{
// Why the body's extent lo..hi leaves the box in dimension d ("" if it does not).
std::string box_reason(const double lo[3], const double hi[3], const HostBox& box, int d)
{
  const std::string axis(1, "xyz"[d]);
  if (box.periodic[d]) {
    const double period = box.hi[d] - box.lo[d];
    if (hi[d] - lo[d] > period + box.slack)
      return " is longer than its period in the periodic dimension " + axis +
             "; it would overlap its own periodic image: shorten it or enlarge the box in " + axis;
    if (lo[d] < box.lo[d] - period - box.slack || hi[d] > box.hi[d] + period + box.slack)
      return " lies more than a period outside it in the periodic dimension " + axis +
             ", beyond the reach of the particles' images: move it into the box";
    return "";
  }
  for (int side = 0; side < 2; ++side) {
    const bool out = side == 0 ? lo[d] < box.lo[d] - box.slack : hi[d] > box.hi[d] + box.slack;
    if (out && box.fixed[d][side])
      return " reaches beyond its fixed " + axis + (side ? "-high" : "-low") +
             " face; particles are lost beyond a fixed face, so they cannot hit "
             "that part: keep the body inside or enlarge the box";
  }
  return "";
}
} // namespace

std::string body_box_violation(const std::vector<Facet>& facets, const double* x,
                               const HostBox& box)
{
  if (facets.empty()) return "";
  double lo[3], hi[3];
  for (int d = 0; d < 3; ++d) {
    lo[d] = std::numeric_limits<double>::infinity();
    hi[d] = -lo[d];
  }
  for (const Facet& fc : facets)
    for (int k = 0; k < fc.nn; ++k)
      for (int d = 0; d < 3; ++d) {
        lo[d] = std::min(lo[d], x[3 * fc.n[k] + d]);
        hi[d] = std::max(hi[d], x[3 * fc.n[k] + d]);
      }
  for (int d = 0; d < box.dimension; ++d) {
    const std::string why = box_reason(lo, hi, box, d);
    if (why.empty()) continue;
    std::string extent = "the body (", where = " in the box (";
    for (int e = 0; e < box.dimension; ++e) {
      char r[96];
      snprintf(r, sizeof r, "%s%c %g to %g", e ? ", " : "", "xyz"[e], lo[e], hi[e]);
      extent += r;
      snprintf(r, sizeof r, "%s%c %g to %g", e ? ", " : "", "xyz"[e], box.lo[e], box.hi[e]);
      where += r;
    }
    return extent + ")" + where + ")" + why;
  }
  return "";
}

} // namespace fracdem

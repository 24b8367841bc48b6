// Assembly of a body's output fields (displacement, stress, fracture, plastic state) for write_vtu.
#include "body/body_fields.h"

#include "io/pvtu_writer.h"

#include <cstdio>
#include <cstdlib>

#include "fem/node_split.h"
#include "io/input_help.h"
#include "materials/material_table.h"

namespace fracdem
{

BodyFields::BodyFields(const Body& body, const PartTopology* topo)
{
  add_mechanics(body);
  // Fracture fields only for materials that fail, plastic ones only for plastic materials: an
  // elastic body's frame keeps the five fields it always had.
  if (material_model_info(body.material().model).fractures) add_fracture(body, topo);
  add_plastic(body);
}

void BodyFields::add_mechanics(const Body& body)
{
  const Mesh& mesh = body.mesh();
  const std::vector<double>& x = body.positions();
  const int nn = mesh.num_nodes(), ne = mesh.num_elems();
  disp_.resize(3 * nn);
  for (int k = 0; k < 3 * nn; ++k)
    disp_[k] = x[k] - mesh.X[k];
  stress_.assign(6 * ne, 0.0);
  mises_.assign(ne, 0.0);
  energy_density_.assign(ne, 0.0);
  if (!body.rigid()) {
    std::vector<double> elem_energy;
    body.element_energies(elem_energy);
    for (int e = 0; e < ne; ++e) {
      if (!mesh.active[e]) continue;
      body.element_stress(e, &stress_[6 * e]);
      mises_[e] = FeSpace::von_mises(&stress_[6 * e]);
      const double vol = body.space().reference_measure(e);
      energy_density_[e] = vol > 0 ? elem_energy[e] / vol : 0.0;
    }
  }
  fields_ = {
      {"displacement", 3, disp_.data(), false},
      {"velocity", 3, body.velocities().data(), false},
      {"stress", 6, stress_.data(), true},
      {"von_mises", 1, mises_.data(), true},
      {"strain_energy_density", 1, energy_density_.data(), true},
  };
}

// Per element: damage (0 intact .. 1 no tension left), crack normal, fragment id, dissipated
// energy (J, summed over its points: the fields of all elements add up to fracture_energy, eroded
// ones included, so a plot shows where that energy went); per node: 1 where a crack runs through
// the node (split nodes and their copies); once cracks cut elements, per element the mesh element
// it is a piece of.
void BodyFields::add_fracture(const Body& body, const PartTopology* topo)
{
  const Mesh& mesh = body.mesh();
  const int ne = mesh.num_elems(), nn = mesh.num_nodes();
  damage_.assign(ne, 0.0);
  normal_.assign(3 * ne, 0.0);
  for (int e = 0; e < ne; ++e)
    damage_[e] = body.element_failure(e, &normal_[3 * e]);
  element_dissipation(body, dissipated_);
  std::vector<int> comp;
  element_components(mesh, comp);
  fragment_.assign(comp.begin(), comp.end());
  split_.assign(nn, 0.0);
  for (int n = 0; n < nn; ++n)
    if (body.parents()[n] >= 0) split_[n] = split_[body.parents()[n]] = 1.0;
  const bool broken_part = topo && !topo->elem_fragment.empty();
  if (broken_part) { // the whole body's figures, which the part alone cannot see
    fragment_.assign(topo->elem_fragment.begin(), topo->elem_fragment.end());
    split_.assign(topo->node_split.begin(), topo->node_split.end());
  }
  fields_.push_back({"damage", 1, damage_.data(), true});
  fields_.push_back({"crack_normal", 3, normal_.data(), true});
  fields_.push_back({"fragment", 1, fragment_.data(), true});
  fields_.push_back({"dissipated_energy", 1, dissipated_.data(), true});
  fields_.push_back({"split", 1, split_.data(), false});
  if (broken_part && topo->cut) {
    mesh_element_.assign(topo->elem_root.begin(), topo->elem_root.end());
    fields_.push_back({"mesh_element", 1, mesh_element_.data(), true});
  }
  if (broken_part || ne == body.mesh_elements()) return;
  // Cracks through elements: the mesh element each piece comes from (pieces share it).
  mesh_element_.resize(ne);
  for (int e = 0; e < ne; ++e) {
    int r = e;
    while (body.element_parent(r) >= 0)
      r = body.element_parent(r);
    mesh_element_[e] = r;
  }
  fields_.push_back({"mesh_element", 1, mesh_element_.data(), true});
}

void element_dissipation(const Body& body, std::vector<double>& energy)
{
  const Mesh& mesh = body.mesh();
  const int per = material_model_info(body.material().model).state_per_point;
  energy.assign(mesh.num_elems(), 0.0);
  if (per == 0) return;
  const double* state = body.material_state().data();
  for (int e = 0; e < mesh.num_elems(); ++e)
    for (int q = 0; q < points_per_elem(mesh.etype[e]); ++q)
      energy[e] +=
          body.space().point_weight(mesh, e, q) *
          point_dissipation(body.material(), state + body.space().state_offset(e) + q * per);
}

// Element means over the integration points (element_plastic_state is false for other materials).
void BodyFields::add_plastic(const Body& body)
{
  if (!body.element_plastic_state(eps_bar_, temperature_rise_, plastic_work_)) return;
  fields_.push_back({"plastic_strain", 1, eps_bar_.data(), true});
  fields_.push_back({"temperature_rise", 1, temperature_rise_.data(), true});
  fields_.push_back({"plastic_work", 1, plastic_work_.data(), true});
}

std::string body_frame_path(const std::string& prefix, long long step)
{
  char name[32];
  std::snprintf(name, sizeof(name), "_%010lld.vtu", step);
  return prefix + name;
}

std::string parse_vtk_fix_args(const std::vector<std::string>& words, VtkFixArgs& out)
{
  const std::string usage = "expected 'fix ID group fem/vtk N PREFIX body BODY_FIX_ID'";
  if (words.size() != 4) return "fix fem/vtk: " + usage;
  if (words[2] != "body")
    return "fix fem/vtk: unknown keyword '" + words[2] + "' (" + usage + ")" +
           did_you_mean(words[2], {"body"});
  char* end = nullptr;
  out.nevery = std::strtoll(words[0].c_str(), &end, 10);
  if (words[0].empty() || *end != '\0' || out.nevery <= 0)
    return "fix fem/vtk: output interval N must be a whole number > 0, got '" + words[0] + "'";
  out.prefix = words[1];
  out.body_id = words[3];
  return "";
}

std::string vtk_body_fix_error(const std::string& body_id, const std::string& style)
{
  const std::string head = "fix fem/vtk: keyword 'body': ";
  if (style.empty()) return head + "no fix fem/body with ID '" + body_id + "'";
  return head + "fix '" + body_id + "' is of style '" + style + "', expected fem/body";
}

void write_body_vtu(const std::string& path, const Body& body)
{
  const BodyFields f(body);
  write_vtu(path, body.mesh(), body.positions().data(), f.fields());
}

void write_body_frame(const std::string& prefix, long long step, double time, int rank, int nprocs,
                      const Body& body, const MeshPart* part, PvdSeries& series,
                      const PartTopology* topo)
{
  std::string path = body_frame_path(prefix, step);
  if (!part) {
    if (rank != 0) return;
    write_body_vtu(path, body);
  } else {
    path = path.substr(0, path.size() - 4) + ".pvtu";
    write_body_piece(path, rank, nprocs, body, *part, topo);
  }
  if (rank == 0) series.add(time, path);
}

std::string body_piece_path(const std::string& pvtu_path, int rank)
{
  const std::string stem = pvtu_path.substr(0, pvtu_path.size() - 5); // drop ".pvtu"
  return stem + "_p" + std::to_string(rank) + ".vtu";
}

void write_body_piece(const std::string& pvtu_path, int rank, int nprocs, const Body& body,
                      const MeshPart& part, const PartTopology* topo)
{
  const BodyFields f(body, topo);
  std::vector<VtkField> fields = f.fields();
  const std::vector<double> global_node(part.global_node.begin(), part.global_node.end());
  const std::vector<double> global_elem(part.global_elem.begin(), part.global_elem.end());
  fields.push_back({"global_node", 1, global_node.data(), false});
  fields.push_back({"global_element", 1, global_elem.data(), true});
  write_vtu(body_piece_path(pvtu_path, rank), body.mesh(), body.positions().data(), fields);
  if (rank != 0) return;
  std::vector<std::string> pieces;
  for (int r = 0; r < nprocs; ++r)
    pieces.push_back(body_piece_path(pvtu_path, r));
  write_pvtu(pvtu_path, pieces, fields);
}

} // namespace fracdem

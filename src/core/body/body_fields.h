// The per-frame output fields of a fem/body (what fix fem/vtk writes), shared by both hosts.
#pragma once

#include <string>
#include <vector>

#include "fem/body.h"
#include "body/body_partition.h"
#include "body/part_restart.h"
#include "io/vtk_writer.h"

namespace fracdem
{

// The fields of one frame of a body, in write order: point data displacement and velocity, cell
// data stress (Voigt 6), von_mises and strain_energy_density; for materials that fracture also
// damage, crack_normal, fragment, dissipated_energy (cell) and split (point), and once cracks cut
// elements mesh_element (cell: the mesh element each piece comes from); for plastic materials
// plastic_strain, temperature_rise and plastic_work (cell). Stress and energy stay 0 for a rigid
// body and for inactive elements. The VtkField entries point into this object and into
// body.velocities(), so it is neither copied nor kept past the body's next change.
class BodyFields
{
public:
  // topo: a broken distributed body's part (its split, fragment and mesh_element fields are the
  // whole body's, body/part_restart.h); null: the body's own.
  explicit BodyFields(const Body& body, const PartTopology* topo = nullptr);
  BodyFields(const BodyFields&) = delete;
  BodyFields& operator=(const BodyFields&) = delete;

  const std::vector<VtkField>& fields() const { return fields_; }

private:
  void add_mechanics(const Body& body);
  void add_fracture(const Body& body, const PartTopology* topo);
  void add_plastic(const Body& body);

  std::vector<double> disp_, stress_, mises_, energy_density_;
  std::vector<double> damage_, normal_, fragment_, split_, dissipated_, mesh_element_;
  std::vector<double> eps_bar_, temperature_rise_, plastic_work_;
  std::vector<VtkField> fields_;
};

// Energy dissipated by each element's material so far (J, the sum over its integration points;
// eroded elements keep theirs): the terms of Body::dissipated_energy, element by element.
void element_dissipation(const Body& body, std::vector<double>& energy);

// The file of the frame at a time step: PREFIX_0000001000.vtu (ten digits, as both hosts name it).
std::string body_frame_path(const std::string& prefix, long long step);

// fix fem/vtk's arguments after the style name, checked alike by both hosts: N PREFIX body ID.
struct VtkFixArgs {
  long long nevery = 0;
  std::string prefix, body_id;
};
// Parses words (N PREFIX body BODY_FIX_ID); returns "" or the error text, which starts with
// "fix fem/vtk: " and names the keyword or argument at fault.
std::string parse_vtk_fix_args(const std::vector<std::string>& words, VtkFixArgs& out);
// The error text when the fix named after 'body' is missing (style empty) or of another style.
std::string vtk_body_fix_error(const std::string& body_id, const std::string& style);

// Writes the body's current configuration with its BodyFields to path (write_vtu's exceptions).
void write_body_vtu(const std::string& path, const Body& body);

// parallel distributed: a frame is PREFIX_<step>.pvtu (body_frame_path with .pvtu) and one piece
// per rank, PREFIX_<step>_p<rank>.vtu. write_body_piece writes this rank's part with the fields of
// write_body_vtu plus global_node (point) and global_element (cell) numbers; rank 0 also writes
// the .pvtu naming every rank's piece (no communication: the names follow from the rank count).
std::string body_piece_path(const std::string& pvtu_path, int rank);

// One frame of fix fem/vtk at a step, as both hosts write it: a replicated body (part null) by
// rank 0 as body_frame_path(prefix, step); a distributed one in pieces (write_body_piece). Rank 0
// adds the frame to the series. Every rank of a distributed body must call it.
void write_body_frame(const std::string& prefix, long long step, double time, int rank, int nprocs,
                      const Body& body, const MeshPart* part, PvdSeries& series,
                      const PartTopology* topo = nullptr);
void write_body_piece(const std::string& pvtu_path, int rank, int nprocs, const Body& body,
                      const MeshPart& part, const PartTopology* topo = nullptr);

} // namespace fracdem

// ParaView output of fracdem meshes: .vtu files through the VTK library and a .pvd time series.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "fem/mesh.h"

namespace fracdem
{

// A field to write: per node (point data, count = num_nodes) or per element
// (cell data, count = num_elems, indexed by the ORIGINAL element index).
// data holds components * count values, component-fastest.
struct VtkField {
  std::string name;
  int components;
  const double* data;
  bool per_cell;
};

// Writes the current configuration x (3 per node; nullptr = mesh.X) of the
// ACTIVE elements of mesh (Tet4 -> VTK_TETRA, Tri3 -> VTK_TRIANGLE, Quad4 ->
// VTK_QUAD) as a binary, zlib-compressed, appended .vtu. All nodes are
// written (so point data and node numbering match the mesh); inactive
// elements are omitted and cell fields compacted accordingly. Adds cell data
// "element_id" (original element index) and "region" (both int).
// The file is written to "<path>.tmp" and renamed, so a reader never sees a
// half-written frame. Throws std::invalid_argument for inconsistent input
// (bad connectivity, duplicate or reserved field names, null data) and
// std::runtime_error naming the path when the file cannot be written.
void write_vtu(const std::string& path, const Mesh& mesh, const double* x,
               const std::vector<VtkField>& fields);

// ParaView time-series index (.pvd). Keeps (time, file) entries and rewrites
// the whole .pvd (atomically, via a temporary file and rename) each time an
// entry is added, so the series stays valid if the run is killed. Nothing is
// written before the first add(). File names are stored relative to the
// .pvd's directory (absolute when no relative path exists).
class PvdSeries
{
public:
  explicit PvdSeries(std::string pvd_path);
  // vtu_path is as the caller opened it (absolute or relative to the working
  // directory). Throws std::runtime_error naming the .pvd if it cannot be written.
  void add(double time, const std::string& vtu_path);
  const std::vector<std::pair<double, std::string>>& entries() const { return entries_; }
  const std::string& path() const { return pvd_path_; }

private:
  void write() const;
  std::string pvd_path_;
  std::vector<std::pair<double, std::string>> entries_;
};

} // namespace fracdem

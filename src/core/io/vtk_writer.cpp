// ParaView output: .vtu through vtkXMLUnstructuredGridWriter and the .pvd time-series index.
#include "io/vtk_writer.h"

#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <set>
#include <stdexcept>
#include <system_error>

#include <vtkCallbackCommand.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkCommand.h>
#include <vtkDoubleArray.h>
#include <vtkIntArray.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridWriter.h>

namespace fs = std::filesystem;

namespace fracdem
{

namespace
{

int vtk_cell_type(ElemType t)
{
  switch (t) {
  case ElemType::Tri3:
    return VTK_TRIANGLE;
  case ElemType::Quad4:
    return VTK_QUAD;
  case ElemType::Tet4:
    return VTK_TETRA;
  }
  return VTK_EMPTY_CELL;
}

// Collects VTK error text instead of letting VTK print it, so it can go into
// the exception (an observer on ErrorEvent suppresses the default printout).
void on_vtk_error(vtkObject*, unsigned long, void* client, void* call)
{
  auto* msg = static_cast<std::string*>(client);
  if (call && msg->empty()) *msg = static_cast<const char*>(call);
}

} // namespace

void write_vtu(const std::string& path, const Mesh& mesh, const double* x,
               const std::vector<VtkField>& fields)
{
  const int nn = mesh.num_nodes(), ne = mesh.num_elems();
  if (!x) x = mesh.X.data();
  if (static_cast<int>(mesh.etype.size()) != ne || static_cast<int>(mesh.active.size()) != ne)
    throw std::invalid_argument("write_vtu: mesh etype/active sizes differ from conn");
  const bool have_region = static_cast<int>(mesh.region.size()) == ne;

  std::set<std::string> names = {"element_id", "region"};
  for (const auto& f : fields) {
    if (f.components < 1)
      throw std::invalid_argument("write_vtu: field '" + f.name + "' has " +
                                  std::to_string(f.components) + " components");
    if (!f.data && (f.per_cell ? ne : nn) > 0)
      throw std::invalid_argument("write_vtu: field '" + f.name + "' has no data");
    if (!names.insert(f.name).second)
      throw std::invalid_argument("write_vtu: field name '" + f.name +
                                  "' is used twice or is reserved (element_id, region)");
  }

  auto points = vtkSmartPointer<vtkPoints>::New();
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(nn);
  for (int i = 0; i < nn; ++i)
    points->SetPoint(i, x + 3 * i);

  std::vector<int> kept;
  kept.reserve(ne);
  for (int e = 0; e < ne; ++e)
    if (mesh.active[e]) kept.push_back(e);

  auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  grid->SetPoints(points);
  grid->Allocate(static_cast<vtkIdType>(kept.size()));
  for (int e : kept) {
    const int npe = nodes_per_elem(mesh.etype[e]);
    vtkIdType ids[4];
    for (int k = 0; k < npe; ++k) {
      const int n = mesh.conn[e][k];
      if (n < 0 || n >= nn)
        throw std::invalid_argument("write_vtu: element " + std::to_string(e) +
                                    " references node " + std::to_string(n) + " of " +
                                    std::to_string(nn));
      ids[k] = n;
    }
    grid->InsertNextCell(vtk_cell_type(mesh.etype[e]), npe, ids);
  }

  auto element_id = vtkSmartPointer<vtkIntArray>::New();
  element_id->SetName("element_id");
  element_id->SetNumberOfTuples(static_cast<vtkIdType>(kept.size()));
  auto region = vtkSmartPointer<vtkIntArray>::New();
  region->SetName("region");
  region->SetNumberOfTuples(static_cast<vtkIdType>(kept.size()));
  for (std::size_t c = 0; c < kept.size(); ++c) {
    element_id->SetValue(static_cast<vtkIdType>(c), kept[c]);
    region->SetValue(static_cast<vtkIdType>(c), have_region ? mesh.region[kept[c]] : 0);
  }
  grid->GetCellData()->AddArray(element_id);
  grid->GetCellData()->AddArray(region);

  for (const auto& f : fields) {
    auto a = vtkSmartPointer<vtkDoubleArray>::New();
    a->SetName(f.name.c_str());
    a->SetNumberOfComponents(f.components);
    const int nc = f.components;
    if (f.per_cell) {
      a->SetNumberOfTuples(static_cast<vtkIdType>(kept.size()));
      for (std::size_t c = 0; c < kept.size(); ++c)
        a->SetTypedTuple(static_cast<vtkIdType>(c),
                         f.data + static_cast<std::size_t>(nc) * kept[c]);
      grid->GetCellData()->AddArray(a);
    } else {
      a->SetNumberOfTuples(nn);
      for (int i = 0; i < nn; ++i)
        a->SetTypedTuple(i, f.data + static_cast<std::size_t>(nc) * i);
      grid->GetPointData()->AddArray(a);
    }
  }

  const std::string tmp = path + ".tmp";
  // Open once ourselves first: the common failure (missing directory, no
  // permission) then gets a plain message instead of VTK pipeline noise.
  if (FILE* probe = std::fopen(tmp.c_str(), "wb")) {
    std::fclose(probe);
  } else {
    throw std::runtime_error(path + ": cannot write VTU file (" + std::strerror(errno) + ")");
  }
  std::string vtk_error;
  auto observer = vtkSmartPointer<vtkCallbackCommand>::New();
  observer->SetCallback(on_vtk_error);
  observer->SetClientData(&vtk_error);
  auto writer = vtkSmartPointer<vtkXMLUnstructuredGridWriter>::New();
  writer->AddObserver(vtkCommand::ErrorEvent, observer);
  writer->SetFileName(tmp.c_str());
  writer->SetInputData(grid);
  writer->SetDataModeToAppended();
  writer->EncodeAppendedDataOff(); // raw binary: smaller and faster than base64
  writer->SetCompressorTypeToZLib();
  writer->SetHeaderTypeToUInt64(); // frames over 4 GiB stay readable
  const int ok = writer->Write();
  if (!ok || !vtk_error.empty() || writer->GetErrorCode() != 0) {
    std::error_code ec;
    fs::remove(tmp, ec);
    std::string why = vtk_error;
    while (!why.empty() && (why.back() == '\n' || why.back() == ' '))
      why.pop_back();
    throw std::runtime_error(path + ": cannot write VTU file" +
                             (why.empty() ? "" : " (" + why + ")"));
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) {
    fs::remove(tmp, ec);
    throw std::runtime_error(path + ": cannot write VTU file (rename from " + tmp + " failed)");
  }
}

// ---------------------------------------------------------------------------

namespace
{

std::string xml_escape(const std::string& s)
{
  std::string out;
  out.reserve(s.size());
  for (char c : s) {
    switch (c) {
    case '&':
      out += "&amp;";
      break;
    case '<':
      out += "&lt;";
      break;
    case '>':
      out += "&gt;";
      break;
    case '"':
      out += "&quot;";
      break;
    default:
      out += c;
    }
  }
  return out;
}

} // namespace

PvdSeries::PvdSeries(std::string pvd_path) : pvd_path_(std::move(pvd_path)) {}

void PvdSeries::add(double time, const std::string& vtu_path)
{
  // Both paths are made absolute against the same working directory, so the
  // relative name is right no matter how the caller spelled them.
  const fs::path pvd_dir = fs::absolute(fs::path(pvd_path_)).lexically_normal().parent_path();
  const fs::path vtu = fs::absolute(fs::path(vtu_path)).lexically_normal();
  fs::path rel = vtu.lexically_relative(pvd_dir);
  std::string name = rel.empty() ? vtu.generic_string() : rel.generic_string();
  entries_.emplace_back(time, name);
  write();
}

void PvdSeries::write() const
{
  const std::string tmp = pvd_path_ + ".tmp";
  FILE* f = std::fopen(tmp.c_str(), "w");
  if (!f) throw std::runtime_error(pvd_path_ + ": cannot write ParaView series file");
  std::fprintf(f, "<?xml version=\"1.0\"?>\n"
                  "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
                  "  <Collection>\n");
  for (const auto& e : entries_) {
    // Shortest text that reads back as the same double (0.1, not 0.10000000000000001).
    char t[64];
    const auto r = std::to_chars(t, t + sizeof(t) - 1, e.first);
    *r.ptr = '\0';
    std::fprintf(f, "    <DataSet timestep=\"%s\" group=\"\" part=\"0\" file=\"%s\"/>\n", t,
                 xml_escape(e.second).c_str());
  }
  std::fprintf(f, "  </Collection>\n</VTKFile>\n");
  const bool ok = !std::ferror(f);
  if (std::fclose(f) != 0 || !ok) {
    std::remove(tmp.c_str());
    throw std::runtime_error(pvd_path_ + ": error while writing ParaView series file");
  }
  std::error_code ec;
  fs::rename(tmp, pvd_path_, ec);
  if (ec) {
    std::remove(tmp.c_str());
    throw std::runtime_error(
        pvd_path_ + ": cannot write ParaView series file (rename failed: " + ec.message() + ")");
  }
}

} // namespace fracdem

// The .pvtu index of a frame written in pieces (see pvtu_writer.h).
#include "io/pvtu_writer.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <stdexcept>

namespace fracdem
{

namespace fs = std::filesystem;

namespace
{
void data_arrays(std::ostream& out, const std::vector<VtkField>& fields, bool per_cell)
{
  for (const VtkField& f : fields)
    if (f.per_cell == per_cell)
      out << "      <PDataArray type=\"Float64\" Name=\"" << f.name << "\" NumberOfComponents=\""
          << f.components << "\"/>\n";
}

std::string relative_to(const std::string& file, const fs::path& dir)
{
  std::error_code ec;
  const fs::path rel = fs::relative(fs::absolute(file), fs::absolute(dir), ec);
  return ec || rel.empty() ? fs::absolute(file).string() : rel.string();
}
} // namespace

void write_pvtu(const std::string& path, const std::vector<std::string>& piece_paths,
                const std::vector<VtkField>& fields)
{
  if (piece_paths.empty()) throw std::invalid_argument("write_pvtu: no pieces for " + path);
  std::set<std::string> names = {"element_id", "region"};
  for (const VtkField& f : fields)
    if (!names.insert(f.name).second || f.components < 1)
      throw std::invalid_argument("write_pvtu: field '" + f.name +
                                  "' is repeated, reserved or has no components");
  const fs::path dir =
      fs::path(path).parent_path().empty() ? fs::path(".") : fs::path(path).parent_path();
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp);
    if (!out)
      throw std::runtime_error(path + ": cannot write PVTU file (" + std::strerror(errno) + ")");
    out << "<?xml version=\"1.0\"?>\n"
        << "<VTKFile type=\"PUnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" "
           "header_type=\"UInt64\">\n"
        << "  <PUnstructuredGrid GhostLevel=\"0\">\n"
        << "    <PPointData>\n";
    data_arrays(out, fields, false);
    out << "    </PPointData>\n    <PCellData>\n"
        << "      <PDataArray type=\"Int32\" Name=\"element_id\"/>\n"
        << "      <PDataArray type=\"Int32\" Name=\"region\"/>\n";
    data_arrays(out, fields, true);
    out << "    </PCellData>\n    <PPoints>\n"
        << "      <PDataArray type=\"Float64\" NumberOfComponents=\"3\"/>\n    </PPoints>\n";
    for (const std::string& piece : piece_paths)
      out << "    <Piece Source=\"" << relative_to(piece, dir) << "\"/>\n";
    out << "  </PUnstructuredGrid>\n</VTKFile>\n";
    if (!out.flush()) throw std::runtime_error(path + ": cannot write PVTU file");
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) {
    fs::remove(tmp, ec);
    throw std::runtime_error(path + ": cannot write PVTU file (rename from " + tmp + " failed)");
  }
}

} // namespace fracdem

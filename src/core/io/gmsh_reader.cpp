// Gmsh .msh ASCII 2.2 / 4.1 reader (line-based, with file:line errors) and 2.2 writer.
#include "io/gmsh_reader.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

namespace fracdem
{
namespace
{

// Gmsh element types we need to recognise: every type must be known so a line
// can be checked for its node count and sorted by dimension, even when it is
// not a type the body may use.
struct GmshType {
  int type;
  const char* name;
  int dim;
  int nodes;
};

constexpr GmshType kGmshTypes[] = {
    {1, "line2", 1, 2},       {2, "tri3", 2, 3},        {3, "quad4", 2, 4},
    {4, "tet4", 3, 4},        {5, "hex8", 3, 8},        {6, "prism6", 3, 6},
    {7, "pyramid5", 3, 5},    {8, "line3", 1, 3},       {9, "tri6", 2, 6},
    {10, "quad9", 2, 9},      {11, "tet10", 3, 10},     {12, "hex27", 3, 27},
    {13, "prism18", 3, 18},   {14, "pyramid14", 3, 14}, {15, "point", 0, 1},
    {16, "quad8", 2, 8},      {17, "hex20", 3, 20},     {18, "prism15", 3, 15},
    {19, "pyramid13", 3, 13}, {20, "tri9", 2, 9},       {21, "tri10", 2, 10},
    {22, "tri12", 2, 12},     {23, "tri15", 2, 15},     {24, "tri15i", 2, 15},
    {25, "tri21", 2, 21},     {26, "line4", 1, 4},      {27, "line5", 1, 5},
    {28, "line6", 1, 6},      {29, "tet20", 3, 20},     {30, "tet35", 3, 35},
    {31, "tet56", 3, 56},     {92, "hex64", 3, 64},     {93, "hex125", 3, 125},
};

// The Gmsh type of each body element type, indexed by ElemType (Tri3, Quad4, Tet4): the reader
// maps back through it, the writer forward.
constexpr int kGmshTypeOf[] = {2, 3, 4};
static_assert(static_cast<int>(ElemType::Tri3) == 0 && static_cast<int>(ElemType::Quad4) == 1 &&
                  static_cast<int>(ElemType::Tet4) == 2,
              "kGmshTypeOf is indexed by ElemType");

bool elem_type_of_gmsh(int gmsh_type, ElemType& et)
{
  for (int k = 0; k < 3; ++k)
    if (kGmshTypeOf[k] == gmsh_type) {
      et = static_cast<ElemType>(k);
      return true;
    }
  return false;
}

const GmshType* find_type(long long type)
{
  for (const auto& t : kGmshTypes)
    if (t.type == type) return &t;
  return nullptr;
}

std::string type_label(const GmshType& t)
{
  return std::to_string(t.type) + " (" + t.name + ")";
}

const char* kReexport =
    "re-export it as ASCII, e.g. `gmsh FILE.msh -save -format msh22 -o OUT.msh` "
    "(or -format msh41)";

// File text echoed in an error message: at most 60 characters, control and non-ASCII bytes as
// \xNN. A damaged or binary file must not flood the log with megabytes of garbage or
// terminal control codes, and a stray '\r' must show up rather than move the cursor.
std::string quote(std::string_view s)
{
  constexpr std::size_t kMax = 60;
  std::string out = "'";
  for (std::size_t i = 0; i < s.size() && i < kMax; ++i) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    if (c >= 0x20 && c < 0x7f) {
      out += static_cast<char>(c);
    } else {
      char buf[8];
      std::snprintf(buf, sizeof(buf), "\\x%02X", c);
      out += buf;
    }
  }
  out += "'";
  if (s.size() > kMax) out += " (" + std::to_string(s.size() - kMax) + " more characters)";
  return out;
}

// Text that reads as part of a sentence (a version, a section name): as it is when it is short
// printable ASCII, quoted as above otherwise.
std::string plain(std::string_view s)
{
  const bool ok =
      s.size() <= 60 && std::all_of(s.begin(), s.end(), [](char c) {
        return static_cast<unsigned char>(c) >= 0x20 && static_cast<unsigned char>(c) < 0x7f;
      });
  return ok ? std::string(s) : quote(s);
}

// Header counts (nodes, names) are not trusted for allocation: a damaged count of 10^12 must
// end in "expected ... got ..." when the records run out, not in std::bad_alloc up front.
constexpr long long kReserveCap = 1 << 20;

// Reads the file line by line so every error can name its line. Gmsh writes
// one record per line in both ASCII formats, and a line-based parser can say
// "expected 4 node tags, got 3" where a token stream would silently run into
// the next record.
class LineParser
{
public:
  explicit LineParser(const std::string& path) : path_(path)
  {
    // A directory opens as a stream on Linux and then reads as an empty file.
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec))
      throw MeshReadError(path + ": is a directory, not a mesh file");
    in_.open(path);
    if (!in_) throw MeshReadError(path + ": cannot open file for reading");
  }

  // Advances to the next non-blank line; false at end of file.
  bool next()
  {
    while (std::getline(in_, line_)) {
      ++lineno_;
      if (!line_.empty() && line_.back() == '\r') line_.pop_back();
      // A UTF-8 byte order mark, as some Windows editors write, is not part of $MeshFormat.
      if (lineno_ == 1 && line_.compare(0, 3, "\xEF\xBB\xBF") == 0) line_.erase(0, 3);
      tokenize();
      if (!tok_.empty()) return true;
    }
    if (in_.bad()) fail("read error");
    return false;
  }

  // Like next(), but end of file is an error naming the section and what was
  // still expected there.
  void need(const std::string& section, const std::string& expected)
  {
    if (!next())
      fail("unexpected end of file in $" + section + ": expected " + expected +
           " (truncated file?)");
  }

  // Same, for the i-th of n records ("expected 6 nodes, got 4"); builds the
  // message only on failure, since this runs once per line.
  // A '$' line among the records means the section ended early: its header count is wrong.
  void need(const char* section, long long n, long long i, const char* what)
  {
    if (!next())
      fail("unexpected end of file in $" + std::string(section) + ": expected " +
           std::to_string(n) + " " + what + ", got " + std::to_string(i) + " (truncated file?)");
    if (line_trimmed().front() == '$')
      fail("expected " + std::to_string(n) + " " + what + " in $" + section + ", got " +
           std::to_string(i) + " before " + quote(line_trimmed()) +
           " (wrong count in the section header?)");
  }

  // The line after a section's records must close it.
  void expect_end(const std::string& section)
  {
    const std::string end = "$End" + section;
    if (!next()) fail("unexpected end of file: expected " + end);
    if (line_trimmed() != end) fail("expected " + end + ", got " + quote(line_trimmed()));
  }

  // Skips a section we do not use, up to its end marker.
  void skip_section(const std::string& section)
  {
    const std::string end = "$End" + section;
    const long start = lineno_;
    while (next())
      if (line_trimmed() == end) return;
    fail("unexpected end of file: expected " + plain(end) + " closing the section opened on line " +
         std::to_string(start));
  }

  [[noreturn]] void fail(const std::string& msg) const
  {
    throw MeshReadError(path_ + ":" + std::to_string(lineno_) + ": " + msg);
  }
  [[noreturn]] void fail_at(long line, const std::string& msg) const
  {
    throw MeshReadError(path_ + ":" + std::to_string(line) + ": " + msg);
  }
  [[noreturn]] void fail_file(const std::string& msg) const
  {
    throw MeshReadError(path_ + ": " + msg);
  }

  std::size_t size() const { return tok_.size(); }
  std::string_view tok(std::size_t i) const { return tok_[i]; }
  long lineno() const { return lineno_; }
  const std::string& path() const { return path_; }
  std::string_view line_trimmed() const
  {
    std::string_view s(line_);
    const auto b = s.find_first_not_of(" \t");
    const auto e = s.find_last_not_of(" \t");
    return b == std::string_view::npos ? std::string_view() : s.substr(b, e - b + 1);
  }

  // Requires exactly n fields on the current line.
  void want_fields(std::size_t n, std::string_view what) const
  {
    if (tok_.size() != n)
      fail("expected " + std::to_string(n) + " fields (" + std::string(what) + "), got " +
           std::to_string(tok_.size()));
  }

  long long to_int(std::size_t i, std::string_view what) const
  {
    const std::string_view s = tok_.at(i);
    long long v = 0;
    const char* b = s.data();
    const char* e = s.data() + s.size();
    if (b != e && *b == '+') ++b;
    auto r = std::from_chars(b, e, v);
    if (r.ec != std::errc() || r.ptr != e)
      fail("expected an integer for " + std::string(what) + ", got " + quote(s));
    return v;
  }

  // An integer that must fit an int (physical and entity tags, dimensions): a 64-bit value
  // would otherwise be truncated into some other tag.
  int to_int32(std::size_t i, std::string_view what) const
  {
    const long long v = to_int(i, what);
    if (v < -std::numeric_limits<int>::max() || v > std::numeric_limits<int>::max())
      fail(std::string(what) + " " + std::to_string(v) + " is out of range (at most " +
           std::to_string(std::numeric_limits<int>::max()) + " in magnitude)");
    return static_cast<int>(v);
  }

  long long to_count(std::size_t i, std::string_view what) const
  {
    const long long v = to_int(i, what);
    if (v < 0) fail(std::string(what) + " must not be negative, got " + std::to_string(v));
    return v;
  }

  double to_double(std::size_t i, std::string_view what) const
  {
    const std::string_view s = tok_.at(i);
    double v = 0;
    const char* b = s.data();
    const char* e = s.data() + s.size();
    if (b != e && *b == '+') ++b;
    auto r = std::from_chars(b, e, v);
    if (r.ec != std::errc() || r.ptr != e || !std::isfinite(v))
      fail("expected a number for " + std::string(what) + ", got " + quote(s));
    return v;
  }

private:
  void tokenize()
  {
    tok_.clear();
    std::size_t i = 0;
    const std::size_t n = line_.size();
    while (i < n) {
      while (i < n && (line_[i] == ' ' || line_[i] == '\t'))
        ++i;
      if (i >= n) break;
      std::size_t j = i;
      while (j < n && line_[j] != ' ' && line_[j] != '\t')
        ++j;
      tok_.emplace_back(line_.data() + i, j - i);
      i = j;
    }
  }

  std::string path_;
  std::ifstream in_;
  std::string line_;
  std::vector<std::string_view> tok_;
  long lineno_ = 0;
};

// Everything read from the file before the body is chosen. Elements are kept
// in flat arrays because lower-dimensional ones are only needed for sets.
struct RawMesh {
  // nodes in file order
  std::vector<long long> node_tag;
  std::vector<double> node_xyz;
  std::vector<long> node_line;
  std::unordered_map<long long, int> node_pos; // tag -> position above

  // elements in file order
  std::vector<const GmshType*> etype;
  std::vector<long> eline;
  std::vector<std::size_t> enode_off{0};
  std::vector<long long> enode; // node tags
  std::vector<std::size_t> ephys_off{0};
  std::vector<int> ephys; // physical tags (non-zero)

  std::map<std::pair<int, int>, std::string> phys_names;       // (dim, tag) -> name
  std::map<std::pair<int, int>, std::vector<int>> entity_phys; // 4.1: (dim, tag) -> physicals

  bool have_nodes = false;
  bool have_elements = false;

  std::size_t num_elems() const { return etype.size(); }
};

void add_node(LineParser& p, RawMesh& raw, long long tag, double x, double y, double z)
{
  if (tag <= 0) p.fail("node tags must be positive, got " + std::to_string(tag));
  auto ins = raw.node_pos.emplace(tag, static_cast<int>(raw.node_tag.size()));
  if (!ins.second)
    p.fail("duplicate node tag " + std::to_string(tag) + " (first defined on line " +
           std::to_string(raw.node_line[ins.first->second]) + ")");
  raw.node_tag.push_back(tag);
  raw.node_xyz.insert(raw.node_xyz.end(), {x, y, z});
  raw.node_line.push_back(p.lineno());
}

// Appends one element whose node tags are fields [first, first + t.nodes) of
// the current line; checks that the nodes exist.
void add_element(LineParser& p, RawMesh& raw, const GmshType& t, std::size_t first,
                 const std::vector<int>& phys)
{
  for (int k = 0; k < t.nodes; ++k) {
    const long long tag = p.to_int(first + k, "node tag");
    if (!raw.node_pos.count(tag))
      p.fail("element references unknown node tag " + std::to_string(tag) + " (not in $Nodes)");
    raw.enode.push_back(tag);
  }
  raw.etype.push_back(&t);
  raw.eline.push_back(p.lineno());
  raw.enode_off.push_back(raw.enode.size());
  for (int ph : phys)
    if (ph != 0) raw.ephys.push_back(ph);
  raw.ephys_off.push_back(raw.ephys.size());
}

const GmshType& lookup_type(LineParser& p, long long type)
{
  const GmshType* t = find_type(type);
  if (!t)
    p.fail("unknown element type " + std::to_string(type) +
           "; fracdem bodies use 4 (tet4), 2 (tri3) and 3 (quad4)");
  return *t;
}

void check_node_count(LineParser& p, const GmshType& t, long long got)
{
  if (got != t.nodes)
    p.fail("expected " + std::to_string(t.nodes) + " node tags for element type " + type_label(t) +
           ", got " + std::to_string(got));
}

void read_physical_names(LineParser& p, RawMesh& raw)
{
  p.need("PhysicalNames", "the number of names");
  p.want_fields(1, "number of physical names");
  const long long n = p.to_count(0, "number of physical names");
  for (long long i = 0; i < n; ++i) {
    p.need("PhysicalNames", n, i, "names");
    if (p.size() < 3)
      p.fail("expected 'dim tag \"name\"', got " + std::to_string(p.size()) + " fields");
    const int d = p.to_int32(0, "physical dimension");
    const int tag = p.to_int32(1, "physical tag");
    // The name is the rest of the line; it may contain blanks inside quotes.
    std::string_view s = p.line_trimmed();
    const std::size_t at = p.tok(2).data() - s.data();
    std::string_view name = s.substr(at);
    if (name.size() >= 2 && name.front() == '"' && name.back() == '"')
      name = name.substr(1, name.size() - 2);
    else if (!name.empty() && name.front() == '"')
      p.fail("unterminated quoted physical name");
    if (d < 0 || d > 3) p.fail("physical dimension must be 0..3, got " + std::to_string(d));
    raw.phys_names[{d, std::abs(tag)}] = std::string(name);
  }
  p.expect_end("PhysicalNames");
}

void read_nodes22(LineParser& p, RawMesh& raw)
{
  p.need("Nodes", "the number of nodes");
  p.want_fields(1, "number of nodes");
  const long long n = p.to_count(0, "number of nodes");
  raw.node_tag.reserve(std::min(n, kReserveCap));
  raw.node_xyz.reserve(3 * std::min(n, kReserveCap));
  for (long long i = 0; i < n; ++i) {
    p.need("Nodes", n, i, "nodes");
    p.want_fields(4, "node: tag x y z");
    add_node(p, raw, p.to_int(0, "node tag"), p.to_double(1, "x"), p.to_double(2, "y"),
             p.to_double(3, "z"));
  }
  p.expect_end("Nodes");
}

void read_elements22(LineParser& p, RawMesh& raw)
{
  p.need("Elements", "the number of elements");
  p.want_fields(1, "number of elements");
  const long long n = p.to_count(0, "number of elements");
  std::vector<int> phys;
  for (long long i = 0; i < n; ++i) {
    p.need("Elements", n, i, "elements");
    if (p.size() < 3)
      p.fail("expected 'tag type ntags tags... nodes...', got " + std::to_string(p.size()) +
             " fields");
    p.to_int(0, "element tag");
    const GmshType& t = lookup_type(p, p.to_int(1, "element type"));
    const long long ntags = p.to_count(2, "number of element tags");
    if (static_cast<long long>(p.size()) < 3 + ntags)
      p.fail("expected " + std::to_string(ntags) + " element tags, got " +
             std::to_string(p.size() - 3));
    check_node_count(p, t, static_cast<long long>(p.size()) - 3 - ntags);
    phys.clear();
    // First tag = physical group, second = elementary entity, then partitions.
    if (ntags >= 1) phys.push_back(std::abs(p.to_int32(3, "physical tag")));
    for (long long k = 1; k < ntags; ++k)
      p.to_int(3 + k, "element tag");
    add_element(p, raw, t, 3 + ntags, phys);
  }
  p.expect_end("Elements");
}

void read_entities41(LineParser& p, RawMesh& raw)
{
  p.need("Entities", "the entity counts");
  p.want_fields(4, "numPoints numCurves numSurfaces numVolumes");
  long long count[4];
  for (int d = 0; d < 4; ++d)
    count[d] = p.to_count(d, "number of entities");
  for (int d = 0; d < 4; ++d) {
    for (long long i = 0; i < count[d]; ++i) {
      p.need("Entities", count[d], i,
             d == 0   ? "point entities"
             : d == 1 ? "curve entities"
             : d == 2 ? "surface entities"
                      : "volume entities");
      // points: tag x y z nphys phys...; others: tag box(6) nphys phys... nbound bound...
      const std::size_t nphys_at = d == 0 ? 4 : 7;
      if (p.size() < nphys_at + 1)
        p.fail("entity of dimension " + std::to_string(d) + ": expected at least " +
               std::to_string(nphys_at + 1) + " fields, got " + std::to_string(p.size()));
      const int tag = p.to_int32(0, "entity tag");
      for (std::size_t k = 1; k < nphys_at; ++k)
        p.to_double(k, "entity coordinate");
      const long long nphys = p.to_count(nphys_at, "number of physical tags");
      std::size_t expect = nphys_at + 1 + nphys;
      if (p.size() < expect)
        p.fail("entity lists " + std::to_string(nphys) + " physical tags, got " +
               std::to_string(p.size() - nphys_at - 1));
      std::vector<int> phys;
      for (long long k = 0; k < nphys; ++k)
        phys.push_back(std::abs(p.to_int32(nphys_at + 1 + k, "physical tag")));
      if (d > 0) {
        if (p.size() < expect + 1)
          p.fail("expected the number of bounding entities after the physical tags");
        const long long nb = p.to_count(expect, "number of bounding entities");
        expect += 1 + nb;
        if (p.size() != expect)
          p.fail("expected " + std::to_string(nb) + " bounding entity tags, got " +
                 std::to_string(p.size() - (expect - nb)));
        for (std::size_t k = expect - nb; k < expect; ++k)
          p.to_int(k, "bounding entity tag");
      } else if (p.size() != expect) {
        p.fail("expected " + std::to_string(expect) + " fields for a point entity, got " +
               std::to_string(p.size()));
      }
      raw.entity_phys[{d, tag}] = std::move(phys);
    }
  }
  p.expect_end("Entities");
}

void read_nodes41(LineParser& p, RawMesh& raw)
{
  p.need("Nodes", "the block header");
  p.want_fields(4, "numEntityBlocks numNodes minNodeTag maxNodeTag");
  const long long nblocks = p.to_count(0, "number of node blocks");
  const long long n = p.to_count(1, "number of nodes");
  raw.node_tag.reserve(std::min(n, kReserveCap));
  raw.node_xyz.reserve(3 * std::min(n, kReserveCap));
  long long total = 0;
  std::vector<long long> tags;
  for (long long b = 0; b < nblocks; ++b) {
    p.need("Nodes", nblocks, b, "node blocks");
    p.want_fields(4, "node block: entityDim entityTag parametric numNodesInBlock");
    const long long edim = p.to_int(0, "entity dimension");
    p.to_int(1, "entity tag");
    const long long param = p.to_int(2, "parametric flag");
    const long long m = p.to_count(3, "number of nodes in block");
    if (edim < 0 || edim > 3) p.fail("entity dimension must be 0..3, got " + std::to_string(edim));
    if (param != 0 && param != 1)
      p.fail("parametric flag must be 0 or 1, got " + std::to_string(param));
    tags.clear();
    for (long long i = 0; i < m; ++i) {
      p.need("Nodes", m, i, "node tags in this block");
      p.want_fields(1, "node tag");
      tags.push_back(p.to_int(0, "node tag"));
    }
    // Parametric nodes carry entityDim extra (u, v, w) coordinates.
    const std::size_t nf = 3 + (param ? static_cast<std::size_t>(edim) : 0);
    for (long long i = 0; i < m; ++i) {
      p.need("Nodes", m, i, "node coordinate lines in this block");
      p.want_fields(nf, param ? "x y z + parametric coordinates" : "node: x y z");
      for (std::size_t k = 3; k < nf; ++k)
        p.to_double(k, "parametric coordinate");
      add_node(p, raw, tags[i], p.to_double(0, "x"), p.to_double(1, "y"), p.to_double(2, "z"));
    }
    total += m;
  }
  if (total != n)
    p.fail("$Nodes header announces " + std::to_string(n) + " nodes, blocks hold " +
           std::to_string(total));
  p.expect_end("Nodes");
}

void read_elements41(LineParser& p, RawMesh& raw)
{
  p.need("Elements", "the block header");
  p.want_fields(4, "numEntityBlocks numElements minElementTag maxElementTag");
  const long long nblocks = p.to_count(0, "number of element blocks");
  const long long n = p.to_count(1, "number of elements");
  long long total = 0;
  static const std::vector<int> kNone;
  for (long long b = 0; b < nblocks; ++b) {
    p.need("Elements", nblocks, b, "element blocks");
    p.want_fields(4, "element block: entityDim entityTag elementType numElementsInBlock");
    const int edim = p.to_int32(0, "entity dimension");
    const int etag = p.to_int32(1, "entity tag");
    const GmshType& t = lookup_type(p, p.to_int(2, "element type"));
    const long long m = p.to_count(3, "number of elements in block");
    if (edim != t.dim)
      p.fail("element type " + type_label(t) + " has dimension " + std::to_string(t.dim) +
             " but its block's entity has dimension " + std::to_string(edim));
    auto it = raw.entity_phys.find({edim, etag});
    const std::vector<int>& phys = it == raw.entity_phys.end() ? kNone : it->second;
    for (long long i = 0; i < m; ++i) {
      p.need("Elements", m, i, "elements in this block");
      if (p.size() < 1) p.fail("expected an element line");
      p.to_int(0, "element tag");
      check_node_count(p, t, static_cast<long long>(p.size()) - 1);
      add_element(p, raw, t, 1, phys);
    }
    total += m;
  }
  if (total != n)
    p.fail("$Elements header announces " + std::to_string(n) + " elements, blocks hold " +
           std::to_string(total));
  p.expect_end("Elements");
}

// Returns 22 or 41.
int read_format(LineParser& p)
{
  if (!p.next()) p.fail_file("empty file, expected a Gmsh mesh starting with $MeshFormat");
  const std::string_view first = p.line_trimmed();
  if (first == "$NOD" || first == "$NOE")
    p.fail(std::string("Gmsh format version 1 is not supported; ") + kReexport);
  if (first.find('\r') != std::string_view::npos && first.compare(0, 11, "$MeshFormat") == 0)
    p.fail("lines end in a bare CR (classic Mac line endings); convert the file to LF or CRLF "
           "line endings, e.g. `tr '\\r' '\\n' < IN.msh > OUT.msh`");
  if (first != "$MeshFormat") p.fail("not a Gmsh mesh: expected $MeshFormat, got " + quote(first));
  p.need("MeshFormat", "'version file-type data-size'");
  if (p.size() < 3)
    p.fail("expected 'version file-type data-size', got " + std::to_string(p.size()) + " fields");
  const std::string version = plain(p.tok(0));
  const double v = p.to_double(0, "format version");
  const long long file_type = p.to_int(1, "file type");
  int fmt = 0;
  if (std::fabs(v - 2.2) < 1e-9) fmt = 22;
  if (std::fabs(v - 4.1) < 1e-9) fmt = 41;
  if (file_type != 0)
    p.fail("binary Gmsh files are not supported (format " + version + ", binary); " + kReexport);
  if (!fmt)
    p.fail("unsupported Gmsh format version " + version +
           "; fracdem reads ASCII versions 2.2 and 4.1; " + kReexport);
  p.expect_end("MeshFormat");
  return fmt;
}

RawMesh read_raw(const std::string& path)
{
  LineParser p(path);
  RawMesh raw;
  const int fmt = read_format(p);
  while (p.next()) {
    const std::string_view head = p.line_trimmed();
    if (head.empty() || head.front() != '$')
      p.fail("expected a section header such as $Nodes, got " + quote(head));
    const std::string name(head.substr(1));
    if (name == "MeshFormat") {
      p.fail("second $MeshFormat section");
    } else if (name == "PhysicalNames") {
      read_physical_names(p, raw);
    } else if (name == "Nodes") {
      if (raw.have_nodes) p.fail("second $Nodes section");
      raw.have_nodes = true;
      fmt == 22 ? read_nodes22(p, raw) : read_nodes41(p, raw);
    } else if (name == "Elements") {
      if (!raw.have_nodes) p.fail("$Elements before $Nodes");
      if (raw.have_elements) p.fail("second $Elements section");
      raw.have_elements = true;
      fmt == 22 ? read_elements22(p, raw) : read_elements41(p, raw);
    } else if (name == "Entities" && fmt == 41) {
      if (raw.have_elements) p.fail("$Entities after $Elements");
      read_entities41(p, raw);
    } else if (name == "PartitionedEntities") {
      p.fail("partitioned Gmsh meshes are not supported; re-export without partitions "
             "(fracdem decomposes bodies itself)");
    } else if (name.compare(0, 3, "End") == 0) {
      p.fail("unexpected " + quote(head) + " outside its section");
    } else {
      p.skip_section(name); // $Comments, $Periodic, $NodeData, ...
    }
  }
  if (!raw.have_nodes) p.fail_file("no $Nodes section");
  if (!raw.have_elements) p.fail_file("no $Elements section");
  return raw;
}

struct ElemKey {
  std::array<long long, 4> n;
  int type;
  bool operator==(const ElemKey& o) const { return type == o.type && n == o.n; }
};
struct ElemKeyHash {
  std::size_t operator()(const ElemKey& k) const
  {
    std::size_t h = static_cast<std::size_t>(k.type);
    for (long long v : k.n)
      h = h * 1000003u ^ std::hash<long long>()(v);
    return h;
  }
};

std::string dims_found(const std::array<long, 4>& count)
{
  std::string s;
  for (int d = 0; d < 4; ++d) {
    if (!count[d]) continue;
    if (!s.empty()) s += ", ";
    s += std::to_string(d) + "D (" + std::to_string(count[d]) + " elements)";
  }
  return s.empty() ? "none" : s;
}

} // namespace

Mesh read_gmsh(const std::string& path, int dim)
{
  if (dim != 0 && dim != 2 && dim != 3)
    throw MeshReadError(path + ": dim must be 0 (auto), 2 or 3, got " + std::to_string(dim));
  RawMesh raw = read_raw(path);
  auto fail_at = [&](long line, const std::string& msg) -> MeshReadError {
    return MeshReadError(path + ":" + std::to_string(line) + ": " + msg);
  };

  // ---- choose the body's dimension ------------------------------------
  std::array<long, 4> count{};
  for (const GmshType* t : raw.etype)
    ++count[t->dim];
  int maxdim = -1;
  for (int d = 0; d < 4; ++d)
    if (count[d]) maxdim = d;
  const int body = dim ? dim : maxdim;
  const char* wanted = body == 3 ? "3 (tet4)" : "2 (tri3/quad4)";
  if (body < 2)
    throw MeshReadError(path + ": no body elements: looked for dimension 3 or 2 (auto), found " +
                        dims_found(count));
  if (!count[body])
    throw MeshReadError(path + ": no body elements: looked for dimension " + wanted + ", found " +
                        dims_found(count));
  if (maxdim > body)
    throw MeshReadError(path + ": dim = " + std::to_string(body) +
                        " was requested but the file has " + std::to_string(count[maxdim]) +
                        " elements of dimension " + std::to_string(maxdim) + "; use a " +
                        std::to_string(body) + "D mesh");

  // ---- body elements: type check and merge of Gmsh 2.2 repeats ------------
  Mesh mesh;
  mesh.dim = body;
  const std::size_t ne_raw = raw.num_elems();
  std::vector<int> elem_of(ne_raw, -1); // raw element -> body element
  std::unordered_map<ElemKey, int, ElemKeyHash> seen;
  std::vector<long long> conn_tags; // 4 per body element, -1 padded
  std::vector<long> body_line;      // file line of each body element
  // Sized once: grown by doubling, these would hold up to twice their size (three times while
  // moving), the largest share of the reader's peak memory on a big mesh.
  const std::size_t ne_body = static_cast<std::size_t>(count[body]);
  seen.reserve(ne_body);
  conn_tags.reserve(4 * ne_body);
  body_line.reserve(ne_body);
  mesh.etype.reserve(ne_body);
  mesh.conn.reserve(ne_body);
  mesh.active.reserve(ne_body);
  mesh.region.reserve(ne_body);
  for (std::size_t r = 0; r < ne_raw; ++r) {
    const GmshType& t = *raw.etype[r];
    if (t.dim != body) continue;
    ElemType et;
    if (!elem_type_of_gmsh(t.type, et))
      throw fail_at(raw.eline[r], "element type " + type_label(t) + " is not supported for a " +
                                      std::to_string(body) + "D body; supported: " +
                                      (body == 3 ? "4 (tet4)" : "2 (tri3), 3 (quad4)") +
                                      " (re-mesh with first-order elements)");
    ElemKey key{{-1, -1, -1, -1}, t.type};
    for (int k = 0; k < t.nodes; ++k)
      key.n[k] = raw.enode[raw.enode_off[r] + k];
    // Insertion sort of <= 4 tags (std::sort here trips a false -Warray-bounds in GCC 12).
    for (int a = 1; a < t.nodes; ++a)
      for (int b = a; b > 0 && key.n[b - 1] > key.n[b]; --b)
        std::swap(key.n[b - 1], key.n[b]);
    // A body element with a node twice is collapsed (a quad turns into a triangle with a
    // zero-length edge that still counts as a boundary facet). Lower-dimensional elements may
    // repeat nodes: meshgen writes single-node sets as [a, b, b] triangles.
    for (int a = 1; a < t.nodes; ++a)
      if (key.n[a] == key.n[a - 1])
        throw fail_at(raw.eline[r], "element of type " + type_label(t) + " lists node tag " +
                                        std::to_string(key.n[a]) +
                                        " more than once; body elements need distinct nodes");
    auto ins = seen.emplace(key, mesh.num_elems());
    if (!ins.second) { // the same element again, listed for another physical group
      elem_of[r] = ins.first->second;
      continue;
    }
    elem_of[r] = mesh.num_elems();
    body_line.push_back(raw.eline[r]);
    std::array<int, 4> c{{-1, -1, -1, -1}};
    for (int k = 0; k < t.nodes; ++k)
      conn_tags.push_back(raw.enode[raw.enode_off[r] + k]);
    for (int k = t.nodes; k < 4; ++k)
      conn_tags.push_back(-1);
    mesh.etype.push_back(et);
    mesh.conn.push_back(c);
    mesh.active.push_back(1);
    mesh.region.push_back(raw.ephys_off[r + 1] > raw.ephys_off[r] ? raw.ephys[raw.ephys_off[r]]
                                                                  : 0);
  }

  decltype(seen)().swap(seen);

  // ---- nodes: those of body elements, by increasing tag ---------------------
  std::vector<long long> tags;
  tags.reserve(conn_tags.size());
  for (long long t : conn_tags)
    if (t > 0) tags.push_back(t); // -1 pads Tri3
  std::sort(tags.begin(), tags.end());
  tags.erase(std::unique(tags.begin(), tags.end()), tags.end());
  auto index_of = [&](long long tag) -> int {
    auto it = std::lower_bound(tags.begin(), tags.end(), tag);
    return (it != tags.end() && *it == tag) ? static_cast<int>(it - tags.begin()) : -1;
  };
  mesh.X.resize(3 * tags.size());
  for (std::size_t i = 0; i < tags.size(); ++i) {
    const int pos = raw.node_pos.at(tags[i]);
    for (int k = 0; k < 3; ++k)
      mesh.X[3 * i + k] = raw.node_xyz[3 * pos + k];
  }
  for (int e = 0; e < mesh.num_elems(); ++e) {
    const int nn = nodes_per_elem(mesh.etype[e]);
    for (int k = 0; k < nn; ++k)
      mesh.conn[e][k] = index_of(conn_tags[4 * e + k]);
  }
  // Coordinates are finite one by one, but an element of size ~1e154 and up has a volume or
  // diameter that overflows: the FE setup would then call it "degenerate" with a NaN volume.
  for (int e = 0; e < mesh.num_elems(); ++e)
    if (!element_geometry_finite(mesh, e)) {
      double big = 0;
      for (int k = 0; k < nodes_per_elem(mesh.etype[e]); ++k)
        for (int d = 0; d < 3; ++d)
          big = std::max(big, std::fabs(mesh.X[3 * mesh.conn[e][k] + d]));
      char buf[32];
      std::snprintf(buf, sizeof(buf), "%.3g", big);
      throw fail_at(body_line[e], std::string("element size overflows double precision (node "
                                              "coordinates up to ") +
                                      buf + "); rescale the mesh, e.g. to metres");
    }

  // ---- physical groups -> node and element sets -------------------------
  auto group_name = [&](int d, int tag) {
    auto it = raw.phys_names.find({d, tag});
    return it != raw.phys_names.end() ? it->second : "physical_" + std::to_string(tag);
  };
  for (const auto& kv : raw.phys_names) {
    mesh.node_sets[kv.second];
    if (kv.first.first == body) mesh.elem_sets[kv.second];
  }
  // (dim, tag) -> its sets; map values stay put, so the pointers stay valid.
  std::map<std::pair<int, int>, std::pair<std::vector<int>*, std::vector<int>*>> group_sets;
  for (std::size_t r = 0; r < ne_raw; ++r) {
    const int d = raw.etype[r]->dim;
    for (std::size_t q = raw.ephys_off[r]; q < raw.ephys_off[r + 1]; ++q) {
      auto g = group_sets.find({d, raw.ephys[q]});
      if (g == group_sets.end()) {
        const std::string name = group_name(d, raw.ephys[q]);
        g = group_sets
                .emplace(std::make_pair(d, raw.ephys[q]),
                         std::make_pair(&mesh.node_sets[name],
                                        d == body ? &mesh.elem_sets[name] : nullptr))
                .first;
      }
      auto& ns = *g->second.first;
      for (std::size_t k = raw.enode_off[r]; k < raw.enode_off[r + 1]; ++k) {
        const int i = index_of(raw.enode[k]);
        if (i >= 0) ns.push_back(i); // nodes outside the body are dropped
      }
      if (g->second.second) g->second.second->push_back(elem_of[r]);
    }
  }
  for (auto* sets : {&mesh.node_sets, &mesh.elem_sets})
    for (auto& kv : *sets) {
      auto& v = kv.second;
      std::sort(v.begin(), v.end());
      v.erase(std::unique(v.begin(), v.end()), v.end());
    }

  // ---- 2D: plane check and counter-clockwise orientation -----------------
  if (body == 2) {
    double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
    for (int i = 0; i < mesh.num_nodes(); ++i)
      for (int k = 0; k < 3; ++k) {
        const double v = mesh.X[3 * i + k];
        lo[k] = i ? std::min(lo[k], v) : v;
        hi[k] = i ? std::max(hi[k], v) : v;
      }
    const double size =
        std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                  (hi[2] - lo[2]) * (hi[2] - lo[2]));
    const double tol = 1e-12 * size;
    for (int i = 0; i < mesh.num_nodes(); ++i) {
      const double z = mesh.X[3 * i + 2];
      if (std::fabs(z) > tol) {
        char buf[64];
        std::snprintf(buf, sizeof(buf), "%.17g", z);
        throw fail_at(raw.node_line[raw.node_pos.at(tags[i])],
                      "node " + std::to_string(tags[i]) + " has z = " + buf +
                          "; a 2D mesh must lie in the plane z = 0");
      }
      mesh.X[3 * i + 2] = 0.0;
    }
    for (int e = 0; e < mesh.num_elems(); ++e) {
      if (signed_measure(mesh, e) >= 0) continue;
      auto& c = mesh.conn[e];
      if (mesh.etype[e] == ElemType::Tri3)
        std::swap(c[1], c[2]);
      else
        std::swap(c[1], c[3]); // a b c d -> a d c b
    }
  }
  return mesh;
}

// ---------------------------------------------------------------------------

void write_gmsh22(const Mesh& mesh, const std::string& path)
{
  const int ne = mesh.num_elems(), nn = mesh.num_nodes();
  int max_region = 0;
  for (int r : mesh.region)
    max_region = std::max(max_region, r);
  auto region_of = [&](int e) {
    return e < static_cast<int>(mesh.region.size()) ? mesh.region[e] : 0;
  };

  // Element sets: a set that is exactly one region is named by that region's
  // tag; any other set is written as repeated elements with a fresh tag.
  struct Extra {
    int tag;
    const std::vector<int>* elems;
  };
  std::vector<std::pair<int, std::string>> body_names; // (tag, name)
  std::vector<Extra> extra;
  int next_tag = max_region + 1;
  std::map<int, int> region_count;
  for (int e = 0; e < ne; ++e)
    ++region_count[region_of(e)];
  std::set<int> named_regions;
  for (const auto& kv : mesh.elem_sets) {
    const auto& v = kv.second;
    int r = v.empty() ? 0 : region_of(v.front());
    bool one_region =
        r != 0 && !named_regions.count(r) && region_count[r] == static_cast<int>(v.size());
    for (int e : v) {
      if (e < 0 || e >= ne)
        throw std::invalid_argument("write_gmsh22: elem_set '" + kv.first + "' holds element " +
                                    std::to_string(e) + " of " + std::to_string(ne));
      if (region_of(e) != r) one_region = false;
    }
    if (one_region) {
      named_regions.insert(r);
      body_names.emplace_back(r, kv.first);
    } else {
      extra.push_back({next_tag, &v});
      body_names.emplace_back(next_tag++, kv.first);
    }
  }
  // Node sets become groups of point elements (dimension 0, own tag space).
  std::vector<std::pair<int, const std::pair<const std::string, std::vector<int>>*>> point_groups;
  int ptag = 1;
  for (const auto& kv : mesh.node_sets) {
    if (mesh.elem_sets.count(kv.first)) continue; // re-derived from the element group on reading
    for (int i : kv.second)
      if (i < 0 || i >= nn)
        throw std::invalid_argument("write_gmsh22: node_set '" + kv.first + "' holds node " +
                                    std::to_string(i) + " of " + std::to_string(nn));
    point_groups.emplace_back(ptag++, &kv);
  }

  FILE* f = std::fopen(path.c_str(), "w");
  if (!f)
    throw std::runtime_error(path + ": cannot open file for writing (" + std::strerror(errno) +
                             ")");
  std::fprintf(f, "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n");
  std::fprintf(f, "$PhysicalNames\n%zu\n", body_names.size() + point_groups.size());
  for (const auto& bn : body_names)
    std::fprintf(f, "%d %d \"%s\"\n", mesh.dim, bn.first, bn.second.c_str());
  for (const auto& pg : point_groups)
    std::fprintf(f, "0 %d \"%s\"\n", pg.first, pg.second->first.c_str());
  std::fprintf(f, "$EndPhysicalNames\n$Nodes\n%d\n", nn);
  for (int i = 0; i < nn; ++i)
    std::fprintf(f, "%d %.17g %.17g %.17g\n", i + 1, mesh.X[3 * i], mesh.X[3 * i + 1],
                 mesh.X[3 * i + 2]);
  std::size_t total = ne;
  for (const auto& x : extra)
    total += x.elems->size();
  for (const auto& pg : point_groups)
    total += pg.second->second.size();
  std::fprintf(f, "$EndNodes\n$Elements\n%zu\n", total);
  long tag = 0;
  auto write_elem = [&](int e, int phys) {
    const auto& c = mesh.conn[e];
    std::fprintf(f, "%ld %d 2 %d %d", ++tag, kGmshTypeOf[static_cast<int>(mesh.etype[e])], phys,
                 std::max(region_of(e), 1));
    for (int k = 0; k < nodes_per_elem(mesh.etype[e]); ++k)
      std::fprintf(f, " %d", c[k] + 1);
    std::fputc('\n', f);
  };
  for (int e = 0; e < ne; ++e)
    write_elem(e, region_of(e));
  for (const auto& x : extra)
    for (int e : *x.elems)
      write_elem(e, x.tag);
  for (const auto& pg : point_groups)
    for (int i : pg.second->second)
      std::fprintf(f, "%ld 15 2 %d %d %d\n", ++tag, pg.first, pg.first, i + 1);
  std::fprintf(f, "$EndElements\n");
  const bool ok = !std::ferror(f);
  if (std::fclose(f) != 0 || !ok) throw std::runtime_error(path + ": error while writing the file");
}

} // namespace fracdem

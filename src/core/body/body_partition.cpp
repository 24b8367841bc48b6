// Element partitions of a distributed body: dual graph, METIS parts, part meshes, interface sums.
#include "body/body_partition.h"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <tuple>

namespace fracdem
{

balance::Graph element_dual_graph(const Mesh& mesh, const std::vector<int64_t>& element_weight)
{
  const int ne = mesh.num_elems();
  if (!element_weight.empty() && static_cast<int>(element_weight.size()) != ne)
    throw std::invalid_argument("element_dual_graph: one weight per element expected");
  struct Entry {
    std::array<int, 3> key;
    int elem;
  };
  std::vector<Entry> all;
  all.reserve(4 * static_cast<size_t>(ne));
  std::array<int, 3> keys[4];
  for (int e = 0; e < ne; ++e) {
    if (!mesh.active[e]) continue;
    const int nf = element_facet_keys(mesh, e, keys);
    for (int k = 0; k < nf; ++k)
      all.push_back({keys[k], e});
  }
  std::sort(all.begin(), all.end(), [](const Entry& a, const Entry& b) {
    return std::tie(a.key, a.elem) < std::tie(b.key, b.elem);
  });
  // The facet list is the largest array here: gone before the graph is built (peak memory of
  // the rank that partitions a big mesh).
  std::vector<balance::WeightedPair> pairs;
  pairs.reserve(all.size() / 2);
  for (size_t i = 0; i + 1 < all.size(); ++i)
    if (all[i].key == all[i + 1].key) pairs.push_back({all[i].elem, all[i + 1].elem, 1});
  std::vector<Entry>().swap(all);
  std::vector<int64_t> weight(ne);
  for (int e = 0; e < ne; ++e)
    weight[e] = element_weight.empty() ? points_per_elem(mesh.etype[e]) : element_weight[e];
  return balance::build_graph(ne, weight, pairs);
}

std::vector<int> partition_elements(const Mesh& mesh, int nparts,
                                    const std::vector<int64_t>& element_weight)
{
  // Eroded elements are isolated vertices of weight 1 in the graph; they belong to no part.
  std::vector<int> part = balance::partition_kway(element_dual_graph(mesh, element_weight), nparts);
  for (int e = 0; e < mesh.num_elems(); ++e)
    if (!mesh.active[e]) part[e] = -1;
  return part;
}

int MeshPart::num_shared_nodes() const
{
  int n = 0;
  for (int i = 0; i < num_nodes(); ++i)
    n += shared(i) ? 1 : 0;
  return n;
}

namespace
{
// Parts that use each global node, ascending, as CSR.
void node_sharers(const Mesh& mesh, const std::vector<int>& elem_part, std::vector<int>& start,
                  std::vector<int>& parts)
{
  const int nn = mesh.num_nodes();
  std::vector<std::vector<int>> lists(nn);
  for (int e = 0; e < mesh.num_elems(); ++e) {
    if (elem_part[e] < 0) continue;
    for (int a = 0; a < nodes_per_elem(mesh.etype[e]); ++a) {
      std::vector<int>& l = lists[mesh.conn[e][a]];
      if (std::find(l.begin(), l.end(), elem_part[e]) == l.end()) l.push_back(elem_part[e]);
    }
  }
  start.assign(1, 0);
  parts.clear();
  for (auto& l : lists) {
    std::sort(l.begin(), l.end());
    parts.insert(parts.end(), l.begin(), l.end());
    start.push_back(static_cast<int>(parts.size()));
  }
}

// Named sets restricted to the part, renumbered (sorted, as Mesh keeps them).
std::map<std::string, std::vector<int>>
restrict_sets(const std::map<std::string, std::vector<int>>& sets, const std::vector<int>& local_of)
{
  std::map<std::string, std::vector<int>> out;
  for (const auto& [name, ids] : sets) {
    std::vector<int>& dst = out[name];
    for (int g : ids)
      if (local_of[g] >= 0) dst.push_back(local_of[g]);
    std::sort(dst.begin(), dst.end());
  }
  return out;
}
} // namespace

std::vector<int> local_of_global(const std::vector<int>& global, int size)
{
  std::vector<int> local(std::max(size, 0), -1);
  for (size_t i = 0; i < global.size(); ++i)
    if (global[i] >= 0 && global[i] < size) local[global[i]] = static_cast<int>(i);
  return local;
}

MeshPart extract_part(const Mesh& mesh, const std::vector<int>& elem_part, int part)
{
  if (static_cast<int>(elem_part.size()) != mesh.num_elems())
    throw std::invalid_argument("extract_part: one part number per element expected");
  MeshPart p;
  p.part = part;
  p.nparts = 1 + *std::max_element(elem_part.begin(), elem_part.end());
  std::vector<int> start, parts;
  node_sharers(mesh, elem_part, start, parts);
  std::vector<int> node_local(mesh.num_nodes(), -1), elem_local(mesh.num_elems(), -1);
  for (int g = 0; g < mesh.num_nodes(); ++g)
    if (std::binary_search(parts.begin() + start[g], parts.begin() + start[g + 1], part)) {
      node_local[g] = p.num_nodes();
      p.global_node.push_back(g);
    }
  Mesh& m = p.mesh;
  m.dim = mesh.dim;
  for (int g : p.global_node) {
    m.X.insert(m.X.end(), &mesh.X[3 * g], &mesh.X[3 * g] + 3);
    p.sharer_start.push_back(static_cast<int>(p.sharers.size()));
    p.sharers.insert(p.sharers.end(), parts.begin() + start[g], parts.begin() + start[g + 1]);
  }
  p.sharer_start.push_back(static_cast<int>(p.sharers.size()));
  for (int e = 0; e < mesh.num_elems(); ++e) {
    if (elem_part[e] != part) continue;
    elem_local[e] = static_cast<int>(p.global_elem.size());
    p.global_elem.push_back(e);
    std::array<int, 4> c = {-1, -1, -1, -1};
    for (int a = 0; a < nodes_per_elem(mesh.etype[e]); ++a)
      c[a] = node_local[mesh.conn[e][a]];
    m.conn.push_back(c);
    m.etype.push_back(mesh.etype[e]);
    m.active.push_back(mesh.active.empty() ? 1 : mesh.active[e]); // eroded: a broken body's
    m.region.push_back(mesh.region.empty() ? 0 : mesh.region[e]);
  }
  m.node_sets = restrict_sets(mesh.node_sets, node_local);
  m.elem_sets = restrict_sets(mesh.elem_sets, elem_local);
  // Neighbours: every other sharer of a local node; nodes in ascending global (= local) order.
  std::map<int, std::vector<int>> shared_with;
  for (int n = 0; n < p.num_nodes(); ++n)
    for (int s = p.sharer_start[n]; s < p.sharer_start[n + 1]; ++s)
      if (p.sharers[s] != part) shared_with[p.sharers[s]].push_back(n);
  for (auto& [q, nodes] : shared_with)
    p.neighbours.push_back({q, std::move(nodes)});
  return p;
}

namespace
{
// Integers and their lists as doubles, and back (bounds checked on the way back).
void put_ints(std::vector<double>& out, const std::vector<int>& v)
{
  out.push_back(static_cast<double>(v.size()));
  out.insert(out.end(), v.begin(), v.end());
}

void put_sets(std::vector<double>& out, const std::map<std::string, std::vector<int>>& sets)
{
  out.push_back(static_cast<double>(sets.size()));
  for (const auto& [name, ids] : sets) {
    out.push_back(static_cast<double>(name.size()));
    out.insert(out.end(), name.begin(), name.end());
    put_ints(out, ids);
  }
}

struct Reader {
  const std::vector<double>& in;
  std::size_t& at;
  const double* take(std::size_t n)
  {
    if (n > in.size() || at > in.size() - n)
      throw std::runtime_error("a body part's message is shorter than its contents");
    at += n;
    return in.data() + at - n;
  }
  int number() { return static_cast<int>(*take(1)); }
  std::size_t count() { return static_cast<std::size_t>(*take(1)); }
  std::vector<int> ints()
  {
    const std::size_t n = count();
    const double* p = take(n);
    return std::vector<int>(p, p + n);
  }
  std::vector<double> doubles()
  {
    const std::size_t n = count();
    const double* p = take(n);
    return std::vector<double>(p, p + n);
  }
  std::map<std::string, std::vector<int>> sets()
  {
    std::map<std::string, std::vector<int>> out;
    for (std::size_t k = count(); k > 0; --k) {
      const std::size_t n = count();
      const double* p = take(n);
      std::string name(n, ' ');
      for (std::size_t i = 0; i < n; ++i)
        name[i] = static_cast<char>(p[i]);
      out[name] = ints();
    }
    return out;
  }
};
} // namespace

void pack_part(const MeshPart& part, std::vector<double>& out)
{
  const Mesh& m = part.mesh;
  out.insert(out.end(), {static_cast<double>(part.part), static_cast<double>(part.nparts),
                         static_cast<double>(m.dim), static_cast<double>(m.num_elems())});
  out.push_back(static_cast<double>(m.X.size()));
  out.insert(out.end(), m.X.begin(), m.X.end());
  for (int e = 0; e < m.num_elems(); ++e) {
    out.push_back(static_cast<double>(m.etype[e]));
    out.push_back(m.active[e]);
    out.push_back(m.region[e]);
    out.insert(out.end(), m.conn[e].begin(), m.conn[e].end());
  }
  put_sets(out, m.node_sets);
  put_sets(out, m.elem_sets);
  put_ints(out, part.global_node);
  put_ints(out, part.global_elem);
  out.push_back(static_cast<double>(part.neighbours.size()));
  for (const PartNeighbour& nb : part.neighbours) {
    out.push_back(nb.part);
    put_ints(out, nb.nodes);
  }
  put_ints(out, part.sharer_start);
  put_ints(out, part.sharers);
}

MeshPart unpack_part(const std::vector<double>& in, std::size_t& at)
{
  Reader r{in, at};
  MeshPart p;
  p.part = r.number();
  p.nparts = r.number();
  Mesh& m = p.mesh;
  m.dim = r.number();
  const int ne = r.number();
  m.X = r.doubles();
  for (int e = 0; e < ne; ++e) {
    const double* v = r.take(7);
    m.etype.push_back(static_cast<ElemType>(static_cast<int>(v[0])));
    m.active.push_back(static_cast<std::uint8_t>(v[1]));
    m.region.push_back(static_cast<int>(v[2]));
    m.conn.push_back({static_cast<int>(v[3]), static_cast<int>(v[4]), static_cast<int>(v[5]),
                      static_cast<int>(v[6])});
  }
  m.node_sets = r.sets();
  m.elem_sets = r.sets();
  p.global_node = r.ints();
  p.global_elem = r.ints();
  for (std::size_t k = r.count(); k > 0; --k) {
    PartNeighbour nb;
    nb.part = r.number();
    nb.nodes = r.ints();
    p.neighbours.push_back(std::move(nb));
  }
  p.sharer_start = r.ints();
  p.sharers = r.ints();
  return p;
}

InterfaceSum::InterfaceSum(const MeshPart& part)
{
  for (const PartNeighbour& nb : part.neighbours)
    nodes_.push_back(nb.nodes);
  // Position of each shared node in each neighbour's message.
  std::vector<std::vector<std::pair<int, int>>> found(part.num_nodes()); // (neighbour, position)
  for (int k = 0; k < num_neighbours(); ++k)
    for (int i = 0; i < static_cast<int>(nodes_[k].size()); ++i)
      found[nodes_[k][i]].push_back({k, i});
  slot_start_.push_back(0);
  for (int n = 0; n < part.num_nodes(); ++n) {
    if (!part.shared(n)) continue;
    shared_node_.push_back(n);
    // Sharers ascending; neighbours are ascending too, so walk both together.
    size_t j = 0;
    for (int s = part.sharer_start[n]; s < part.sharer_start[n + 1]; ++s) {
      if (part.sharers[s] == part.part) {
        slots_.push_back({-1, -1});
        continue;
      }
      slots_.push_back({found[n][j].first, found[n][j].second});
      ++j;
    }
    slot_start_.push_back(static_cast<int>(slots_.size()));
  }
}

void InterfaceSum::pack(int k, const double* field, int width, std::vector<double>& message) const
{
  message.resize(message_size(k, width));
  double* out = message.data();
  for (int n : nodes_[k])
    for (int d = 0; d < width; ++d)
      *out++ = field[width * n + d];
}

void InterfaceSum::combine(double* field, int width,
                           const std::vector<std::vector<double>>& received) const
{
  if (width < 1 || width > 8) throw std::invalid_argument("InterfaceSum: width 1..8 expected");
  double own[8];
  for (size_t i = 0; i < shared_node_.size(); ++i) {
    double* f = field + width * shared_node_[i];
    std::copy(f, f + width, own);
    std::fill(f, f + width, 0.0);
    for (int s = slot_start_[i]; s < slot_start_[i + 1]; ++s) {
      const double* c = slots_[s].neighbour < 0
                            ? own
                            : &received[slots_[s].neighbour][width * slots_[s].position];
      for (int d = 0; d < width; ++d)
        f[d] += c[d];
    }
  }
}

} // namespace fracdem

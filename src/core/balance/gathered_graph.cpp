// Building the balancing graph: each rank's share, and the whole graph from the gathered shares.
#include "balance/gathered_graph.h"

#include <algorithm>
#include <unordered_map>

namespace fracdem::balance
{

LocalGraph particle_vertices(const std::vector<std::int64_t>& tag,
                             const std::vector<std::int64_t>& weight,
                             std::vector<std::int64_t> edges)
{
  LocalGraph lg;
  lg.verts.resize(2 * tag.size());
  for (std::size_t i = 0; i < tag.size(); ++i)
    lg.verts[2 * i] = tag[i], lg.verts[2 * i + 1] = weight[i];
  lg.edges = std::move(edges);
  return lg;
}

LocalGraph aggregate_cells(const std::vector<std::int64_t>& weight,
                           const std::vector<std::int64_t>& cell,
                           const std::vector<std::int64_t>& edges, std::int64_t ncells)
{
  LocalGraph lg;
  std::unordered_map<std::int64_t, std::int64_t> cell_weight;
  for (std::size_t i = 0; i < weight.size(); ++i)
    cell_weight[cell[i]] += weight[i];
  lg.verts.reserve(2 * cell_weight.size());
  for (const auto& cw : cell_weight)
    lg.verts.push_back(cw.first), lg.verts.push_back(cw.second);
  std::unordered_map<std::int64_t, std::int64_t> edge_weight;
  for (std::size_t e = 0; e + 2 < edges.size(); e += 3) {
    const std::int64_t a = std::min(edges[e], edges[e + 1]), b = std::max(edges[e], edges[e + 1]);
    edge_weight[a * ncells + b] += edges[e + 2];
  }
  lg.edges.reserve(3 * edge_weight.size());
  for (const auto& ew : edge_weight)
    lg.edges.push_back(ew.first / ncells), lg.edges.push_back(ew.first % ncells),
        lg.edges.push_back(ew.second);
  return lg;
}

RootGraph particle_graph(const GatheredGraph& gg, int nranks)
{
  const std::int64_t n = gg.vtotal / 2;
  RootGraph rg;
  std::int64_t max_tag = 0;
  for (std::int64_t k = 0; k < n; ++k)
    max_tag = std::max(max_tag, gg.verts[2 * k]);
  // Vertices in ascending tag order, whatever order the ranks listed their particles in.
  std::vector<std::int64_t> vertex_of_tag(max_tag + 1, -1);
  for (std::int64_t k = 0; k < n; ++k)
    vertex_of_tag[gg.verts[2 * k]] = 0;
  std::int64_t next = 0;
  for (std::int64_t& v : vertex_of_tag)
    if (v == 0) v = next++;
  std::vector<std::int64_t> vwgt(next);
  rg.old_owner.resize(next);
  rg.entry_vertex.resize(n);
  for (int p = 0; p < nranks; ++p)
    for (int k = gg.vdisp[p] / 2; k < (gg.vdisp[p] + gg.vcount[p]) / 2; ++k) {
      const std::int64_t v = vertex_of_tag[gg.verts[2 * k]];
      rg.entry_vertex[k] = v;
      rg.old_owner[v] = p;
      vwgt[v] = gg.verts[2 * k + 1];
    }
  const auto vertex = [&](std::int64_t tag) {
    return tag >= 0 && tag <= max_tag ? vertex_of_tag[tag] : std::int64_t{-1};
  };
  std::vector<WeightedPair> pairs;
  pairs.reserve(gg.etotal / 3);
  for (int e = 0; e + 2 < gg.etotal; e += 3) {
    const std::int64_t a = vertex(gg.edges[e]), b = vertex(gg.edges[e + 1]);
    if (a >= 0 && b >= 0) pairs.push_back({a, b, gg.edges[e + 2]});
  }
  rg.g = build_graph(next, vwgt, pairs, RowOrder::Ascending);
  return rg;
}

std::vector<int> parts_of_entries(const RootGraph& rg, const std::vector<int>& part)
{
  std::vector<int> out(rg.entry_vertex.size());
  for (std::size_t k = 0; k < out.size(); ++k)
    out[k] = part[rg.entry_vertex[k]];
  return out;
}

RootGraph cell_graph(const GatheredGraph& gg, const CellGrid& grid, int nranks)
{
  // Dense cell index in ascending cell order (the owner table handed back has one entry per cell
  // anyway), whatever order the ranks listed their cells in.
  std::vector<std::int64_t> vertex_of_cell(grid.total(), -1);
  for (int k = 0; k < gg.vtotal; k += 2)
    vertex_of_cell[gg.verts[k]] = 0;
  RootGraph rg;
  for (std::int64_t c = 0; c < grid.total(); ++c)
    if (vertex_of_cell[c] == 0) {
      vertex_of_cell[c] = static_cast<std::int64_t>(rg.cells.size());
      rg.cells.push_back(c);
    }
  std::vector<std::int64_t> vwgt(rg.cells.size(), 0), best_share(rg.cells.size(), -1);
  rg.old_owner.assign(rg.cells.size(), 0);
  for (int p = 0; p < nranks; ++p)
    for (int k = gg.vdisp[p]; k < gg.vdisp[p] + gg.vcount[p]; k += 2) {
      const std::int64_t v = vertex_of_cell[gg.verts[k]], w = gg.verts[k + 1];
      vwgt[v] += w;
      if (w > best_share[v]) best_share[v] = w, rg.old_owner[v] = p;
    }
  rg.g = build_cell_graph(grid, rg.cells, vertex_of_cell, vwgt, gg.edges);
  return rg;
}

std::vector<double> cell_centres(const CellGrid& grid, const std::vector<std::int64_t>& cells)
{
  std::vector<double> centre(3 * cells.size());
  for (std::size_t v = 0; v < cells.size(); ++v) {
    std::int64_t c[3];
    grid.coords(cells[v], c);
    for (int d = 0; d < 3; ++d)
      centre[3 * v + d] = grid.lo[d] + (static_cast<double>(c[d]) + 0.5) * grid.size[d];
  }
  return centre;
}

} // namespace fracdem::balance

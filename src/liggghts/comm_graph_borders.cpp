// Graph-ownership ghost search: partners, cover cells a cutoff wide, 27-cell stencil, borders.
//
// Cost per reneighbour: binning the owned atoms (a sort of one key per atom), one mask load per
// occupied cover cell (a cell is at least one cutoff wide), and the 27-cell stencil walk plus
// distance tests only for the cells that have another rank's cover, a periodic boundary or an
// insertion brick within reach: the surface of the sub-domain, not its volume.
#include "comm_graph.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>

#include "atom.h"
#include "atom_vec.h"
#include "domain.h"
#include "error.h"

using namespace LAMMPS_NS;

namespace
{
constexpr std::int64_t kMaxCells = std::int64_t(1) << 24; // cover grid size limit
constexpr int kTagCover = 4;
constexpr int kTagBorder = 3;
constexpr double kSlack = 1.0 + 1e-9; // box tests that decide what is exchanged: a superset

// Squared gap between box a shifted by sh (in box lengths) and box b (6 doubles: lo, hi).
double box_gap2(const double* a, const int* sh, const double* b, const double* prd, int dim)
{
  double g2 = 0;
  for (int d = 0; d < dim; ++d) {
    const double off = sh[d] * prd[d];
    const double gap = std::max({b[d] - (a[3 + d] + off), 0.0, (a[d] + off) - b[3 + d]});
    g2 += gap * gap;
  }
  return g2;
}

// Largest squared distance from a point of box a shifted by sh to box b (separable per
// dimension, so the farthest point is a corner of a).
double far_gap2(const double* a, const int* sh, const double* b, const double* prd, int dim)
{
  double g2 = 0;
  for (int d = 0; d < dim; ++d) {
    const double lo = a[d] + sh[d] * prd[d], hi = a[3 + d] + sh[d] * prd[d];
    const double gap = std::max({b[d] - lo, lo - b[3 + d], b[d] - hi, hi - b[3 + d], 0.0});
    g2 += gap * gap;
  }
  return g2;
}

// Squared distance from point y to box b.
double point_gap2(const double* y, const double* b, int dim)
{
  double g2 = 0;
  for (int d = 0; d < dim; ++d) {
    const double gap = std::max({b[d] - y[d], 0.0, y[d] - b[3 + d]});
    g2 += gap * gap;
  }
  return g2;
}

// floor(v) as an integer without a library call (v is a cell coordinate, far inside int64).
inline std::int64_t floor_int(double v)
{
  const std::int64_t k = static_cast<std::int64_t>(v);
  return v < static_cast<double>(k) ? k - 1 : k;
}

// Index range [first, last] of grid cells along d that boxes [lo - cut, hi + cut] can touch:
// periodic dimensions may wrap (the caller takes indices modulo n), others are clamped, which
// is right because the grid clamps atoms beyond its edge cells into them.
void cell_range(const fracdem::balance::CellGrid& g, int d, double lo, double hi, double cut,
                std::int64_t& first, std::int64_t& last)
{
  first = floor_int((lo - cut - g.lo[d]) / g.size[d]);
  last = floor_int((hi + cut - g.lo[d]) / g.size[d]);
  if (g.periodic[d]) {
    if (last - first + 1 > g.n[d]) first = 0, last = g.n[d] - 1;
  } else {
    first = std::min(std::max<std::int64_t>(first, 0), g.n[d] - 1);
    last = std::min(std::max<std::int64_t>(last, 0), g.n[d] - 1);
  }
}

// c modulo n; branches instead of divisions for the usual case of c within one period (the
// stencil lookups below run per cell and neighbour, where divisions were most of the cost).
inline std::int64_t wrap(std::int64_t c, std::int64_t n)
{
  if (c >= 0 && c < n) return c;
  if (c < 0 && c >= -n) return c + n;
  if (c >= n && c < 2 * n) return c - n;
  return ((c % n) + n) % n;
}
// a |= its neighbours along dimension d, over an n[0] x n[1] x n[2] window (wrapping where the
// window is a whole periodic dimension): one pass of a separable 3x3x3 dilation.
void dilate(std::vector<char>& a, const std::int64_t n[3], int d, bool wrap_around)
{
  const std::int64_t stride[3] = {1, n[0], n[0] * n[1]}, len = n[d], step = stride[d];
  std::vector<char> out(a.size());
  for (std::int64_t z = 0, s = 0; z < n[2]; ++z)
    for (std::int64_t y = 0; y < n[1]; ++y)
      for (std::int64_t x = 0; x < n[0]; ++x, ++s) {
        const std::int64_t c = d == 0 ? x : (d == 1 ? y : z);
        char v = a[s];
        if (c > 0)
          v |= a[s - step];
        else if (wrap_around)
          v |= a[s + (len - 1) * step];
        if (c < len - 1)
          v |= a[s + step];
        else if (wrap_around)
          v |= a[s - (len - 1) * step];
        out[s] = v;
      }
  a.swap(out);
}
} // namespace

// Cover cells at least a cutoff wide; my atoms sorted by cell, with each cell's atom box and
// grid coordinates (kept, so that no later step divides to recover them).
void CommGraph::bin_atoms()
{
  const bool periodic[3] = {domain->periodicity[0] != 0, domain->periodicity[1] != 0,
                            domain->periodicity[2] != 0};
  cover_ = fracdem::balance::make_cell_grid(domain->boxlo, domain->boxhi, cutghost[0],
                                            domain->dimension, periodic, kMaxCells);
  const double inv[3] = {1.0 / cover_.size[0], 1.0 / cover_.size[1], 1.0 / cover_.size[2]};
  const int nlocal = atom->nlocal;
  double** x = atom->x;
  std::vector<std::uint64_t> keys(nlocal);
  for (int i = 0; i < nlocal; ++i) {
    std::int64_t c[3];
    for (int d = 0; d < 3; ++d) { // as CellGrid::cell_of: periodic wraps, others clamp
      const std::int64_t k = floor_int((x[i][d] - cover_.lo[d]) * inv[d]);
      c[d] = cover_.periodic[d] ? wrap(k, cover_.n[d])
                                : std::min(std::max<std::int64_t>(k, 0), cover_.n[d] - 1);
    }
    keys[i] = (static_cast<std::uint64_t>(cover_.id(c[0], c[1], c[2])) << 32) | std::uint32_t(i);
  }
  std::sort(keys.begin(), keys.end());
  my_cells_.clear();
  my_coords_.clear();
  my_boxes_.clear();
  cell_first_.clear();
  order_.resize(nlocal);
  for (int k = 0; k < nlocal; ++k) {
    const std::int64_t cell = static_cast<std::int64_t>(keys[k] >> 32);
    const int i = static_cast<int>(keys[k] & 0xffffffffu);
    const double* xi = x[i];
    order_[k] = i;
    if (my_cells_.empty() || my_cells_.back() != cell) {
      std::int64_t c[3];
      cover_.coords(cell, c);
      my_cells_.push_back(cell);
      cell_first_.push_back(k);
      for (int d = 0; d < 3; ++d)
        my_coords_.push_back(c[d]);
      for (int d = 0; d < 6; ++d)
        my_boxes_.push_back(xi[d % 3]);
    } else {
      double* b = &my_boxes_[my_boxes_.size() - 6];
      for (int d = 0; d < 3; ++d)
        b[d] = std::min(b[d], xi[d]), b[3 + d] = std::max(b[3 + d], xi[d]);
    }
  }
  cell_first_.push_back(nlocal);
  build_sub_boxes();
}

// The boxes the exact tests use: per cell, the box of its atoms in each octant (half a cell a
// side), so that the ghost shell stays as tight as with half-cutoff cells while the search walks
// cells a full cutoff wide.
void CommGraph::build_sub_boxes()
{
  double** x = atom->x;
  sub_boxes_.clear();
  sub_first_.assign(1, 0);
  for (std::size_t m = 0; m < my_cells_.size(); ++m) {
    double mid[3], box[8][6];
    bool used[8] = {false, false, false, false, false, false, false, false};
    for (int d = 0; d < 3; ++d)
      mid[d] = cover_.lo[d] + (my_coords_[3 * m + d] + 0.5) * cover_.size[d];
    for (int k = cell_first_[m]; k < cell_first_[m + 1]; ++k) {
      const double* xi = x[order_[k]];
      int o = 0;
      for (int d = 0; d < domain->dimension; ++d)
        o |= (xi[d] >= mid[d]) << d;
      double* b = box[o];
      for (int d = 0; d < 3; ++d) {
        b[d] = used[o] ? std::min(b[d], xi[d]) : xi[d];
        b[3 + d] = used[o] ? std::max(b[3 + d], xi[d]) : xi[d];
      }
      used[o] = true;
    }
    for (int o = 0; o < 8; ++o)
      if (used[o]) sub_boxes_.insert(sub_boxes_.end(), box[o], box[o] + 6);
    sub_first_.push_back(static_cast<int>(sub_boxes_.size() / 6));
  }
}

// The cell range my atoms occupy per dimension, taken circularly across periodic boundaries (a
// part that straddles one is still compact), and my atoms' box unwrapped to it (its upper bound
// may pass the box's).
void CommGraph::compute_span()
{
  const int dim = domain->dimension;
  std::vector<char> occupied[3];
  for (int d = 0; d < dim; ++d)
    occupied[d].assign(cover_.n[d], 0);
  for (size_t m = 0; m < my_cells_.size(); ++m)
    for (int d = 0; d < dim; ++d)
      occupied[d][my_coords_[3 * m + d]] = 1;
  for (int d = 0; d < 3; ++d)
    span_lo_[d] = 0, span_n_[d] = cover_.n[d];
  for (int d = 0; d < dim && !my_cells_.empty(); ++d) {
    const std::vector<char>& occ = occupied[d];
    const std::int64_t n = cover_.n[d];
    if (!cover_.periodic[d]) {
      std::int64_t lo = 0, hi = n - 1;
      while (!occ[lo])
        ++lo;
      while (!occ[hi])
        --hi;
      span_lo_[d] = lo, span_n_[d] = hi - lo + 1;
      continue;
    }
    std::int64_t best = 0, best_end = 0, run = 0; // largest circular run of empty cells
    for (std::int64_t k = 0; k < 2 * n; ++k) {
      run = occ[k % n] ? 0 : run + 1;
      if (run > best && run <= n) best = run, best_end = k;
    }
    if (best > 0) span_lo_[d] = (best_end + 1) % n, span_n_[d] = n - best;
  }
  for (int d = 0; d < 3; ++d)
    my_box_[d] = HUGE_VAL, my_box_[3 + d] = -HUGE_VAL;
  for (size_t m = 0; m < my_cells_.size(); ++m) {
    const std::int64_t* c = &my_coords_[3 * m];
    for (int d = 0; d < 3; ++d) {
      const bool wrapped = d < dim && cover_.periodic[d] && c[d] < span_lo_[d];
      const double off = wrapped ? domain->prd[d] : 0.0;
      my_box_[d] = std::min(my_box_[d], my_boxes_[6 * m + d] + off);
      my_box_[3 + d] = std::max(my_box_[3 + d], my_boxes_[6 * m + 3 + d] + off);
    }
  }
}

// Every rank's stock brick (intersected with the cover limits, possibly empty), from the
// processor grid every rank knows: no communication.
void CommGraph::compute_bricks()
{
  bricks_.clear();
  nbox_ = 0;
  if (!cover_brick_) return;
  nbox_ = cover_limits_.empty() ? 1 : static_cast<int>(cover_limits_.size() / 6);
  bricks_.assign(size_t(6) * nbox_ * nprocs, 0.0);
  const double* split[3] = {xsplit, ysplit, zsplit};
  for (int i = 0; i < procgrid[0]; ++i)
    for (int j = 0; j < procgrid[1]; ++j)
      for (int k = 0; k < procgrid[2]; ++k) {
        const int loc[3] = {i, j, k}, q = grid2proc[i][j][k];
        double brick[6];
        for (int d = 0; d < 3; ++d) { // as Domain::set_local_box
          brick[d] = domain->boxlo[d] + domain->prd[d] * split[d][loc[d]];
          brick[3 + d] = loc[d] < procgrid[d] - 1
                             ? domain->boxlo[d] + domain->prd[d] * split[d][loc[d] + 1]
                             : domain->boxhi[d];
        }
        for (int b = 0; b < nbox_; ++b) {
          double* out = &bricks_[6 * (size_t(q) * nbox_ + b)];
          const double* lim = cover_limits_.empty() ? nullptr : &cover_limits_[6 * b];
          for (int d = 0; d < 6; ++d)
            out[d] =
                !lim ? brick[d] : (d < 3 ? std::max(brick[d], lim[d]) : std::min(brick[d], lim[d]));
        }
      }
}

// True if a brick box of rank x comes within reach of box y (any periodic image).
static bool brick_near(const std::vector<double>& bricks, int nbox, int x, const double* y,
                       const std::vector<std::array<int, 3>>& shifts, const double* prd, int dim,
                       double reach2)
{
  for (int b = 0; b < nbox; ++b) {
    const double* B = &bricks[6 * (size_t(x) * nbox + b)];
    bool empty = false;
    for (int d = 0; d < dim; ++d)
      empty |= B[d] > B[3 + d];
    if (empty) continue;
    for (const auto& sh : shifts)
      if (box_gap2(B, sh.data(), y, prd, dim) <= reach2) return true;
  }
  return false;
}

// Partners: the ranks whose atoms can come within the cutoff of mine, or of whose brick mine can
// (insertion cover). Symmetric by construction, so that each end knows whom to expect: with cell
// ownership from the cell owners every rank holds (no communication, cached); with per-atom
// ownership from every rank's atom box (one Allgather), each pair evaluated in rank order so that
// both ends reach the same verdict bit for bit.
void CommGraph::find_partners()
{
  std::vector<char> is_partner(nprocs, 0);
  if (!cell_owners_.empty()) {
    find_static_partners();
    for (int p : static_partners_)
      is_partner[p] = 1;
  } else {
    const int dim = domain->dimension;
    const double reach2 = cutghost[0] * cutghost[0] * kSlack;
    rank_boxes_.resize(6 * size_t(nprocs));
    MPI_Allgather(my_box_, 6, MPI_DOUBLE, rank_boxes_.data(), 6, MPI_DOUBLE, gcomm_);
    for (int q = 0; q < nprocs; ++q) {
      if (q == me) continue;
      const int lo = std::min(me, q), hi = std::max(me, q);
      const double *a = &rank_boxes_[6 * lo], *b = &rank_boxes_[6 * hi];
      bool near = false;
      for (const auto& sh : shifts_)
        near = near || box_gap2(a, sh.data(), b, domain->prd, dim) <= reach2;
      if (cover_brick_)
        near = near || brick_near(bricks_, nbox_, lo, b, shifts_, domain->prd, dim, reach2) ||
               brick_near(bricks_, nbox_, hi, a, shifts_, domain->prd, dim, reach2);
      is_partner[q] = near;
    }
  }
  partners_.clear();
  for (int q = 0; q < nprocs; ++q)
    if (is_partner[q] && q != me) partners_.push_back(q);
}

// Cell ownership: q is a partner if one of its cells lies within the cutoff of one of mine (index
// distance only, so both ends compute the same; atoms clamped into edge cells lie further out,
// which only makes the test a superset), or if its brick does (add_brick_partners).
void CommGraph::find_static_partners()
{
  const double key[8] = {domain->boxlo[0], domain->boxlo[1],      domain->boxlo[2],
                         domain->boxhi[0], domain->boxhi[1],      domain->boxhi[2],
                         cutghost[0],      cover_brick_ ? 1. : 0.};
  if (partners_version_ == owners_version_ && std::equal(key, key + 8, partners_key_)) return;
  std::copy(key, key + 8, partners_key_);
  partners_version_ = owners_version_;
  const fracdem::balance::CellGrid& g = cell_grid_;
  const int dim = domain->dimension;
  const double reach2 = cutghost[0] * cutghost[0] * kSlack;
  std::int64_t r[3] = {0, 0, 0};
  for (int d = 0; d < dim; ++d)
    r[d] = std::min<std::int64_t>(g.n[d], 1 + static_cast<std::int64_t>(cutghost[0] / g.size[d]));
  std::vector<char> is_partner(nprocs, 0);
  // Interior owner cells (every cell within reach mine) need no cover records; the test in
  // cover_targets relies on cells at least a cutoff wide.
  bool wide = true;
  for (int d = 0; d < dim; ++d)
    wide = wide && g.size[d] >= cutghost[0] * kSlack;
  owner_interior_.assign(wide ? g.total() : 0, 0);
  for (std::int64_t cell = 0; cell < g.total(); ++cell) {
    if (cell_owners_[cell] != me) continue;
    if (wide) owner_interior_[cell] = 1;
    std::int64_t c[3];
    g.coords(cell, c);
    for (std::int64_t oz = -r[2]; oz <= r[2]; ++oz)
      for (std::int64_t oy = -r[1]; oy <= r[1]; ++oy)
        for (std::int64_t ox = -r[0]; ox <= r[0]; ++ox) {
          const std::int64_t off[3] = {ox, oy, oz};
          std::int64_t n[3];
          double gap2 = 0;
          bool valid = true;
          for (int d = 0; d < 3; ++d) {
            const double gap = std::max<std::int64_t>(0, std::llabs(off[d]) - 1) * g.size[d];
            gap2 += gap * gap;
            n[d] = c[d] + off[d];
            if (n[d] < 0 || n[d] >= g.n[d]) {
              valid = valid && g.periodic[d];
              n[d] = wrap(n[d], g.n[d]);
            }
          }
          if (!valid || gap2 > reach2) continue;
          const int q = cell_owners_[g.id(n[0], n[1], n[2])];
          if (q >= 0 && q != me) is_partner[q] = 1;
          if (q != me && wide) owner_interior_[cell] = 0;
        }
  }
  if (cover_brick_) add_brick_partners(is_partner);
  static_partners_.clear();
  for (int q = 0; q < nprocs; ++q)
    if (is_partner[q]) static_partners_.push_back(q);
}

// Pairs (brick of x, cells of y) within reach, over all ranks' bricks: every rank enumerates the
// same pairs, and keeps those it is part of.
void CommGraph::add_brick_partners(std::vector<char>& is_partner)
{
  const fracdem::balance::CellGrid& g = cell_grid_;
  const int dim = domain->dimension;
  for (int x = 0; x < nprocs; ++x)
    for (int b = 0; b < nbox_; ++b) {
      const double* B = &bricks_[6 * (size_t(x) * nbox_ + b)];
      std::int64_t first[3] = {0, 0, 0}, last[3] = {0, 0, 0};
      bool empty = false;
      for (int d = 0; d < dim; ++d) {
        empty |= B[d] > B[3 + d];
        cell_range(g, d, B[d], B[3 + d], cutghost[0], first[d], last[d]);
      }
      if (empty) continue;
      for (std::int64_t cz = first[2]; cz <= last[2]; ++cz)
        for (std::int64_t cy = first[1]; cy <= last[1]; ++cy)
          for (std::int64_t cx = first[0]; cx <= last[0]; ++cx) {
            const int y = cell_owners_[g.id(wrap(cx, g.n[0]), wrap(cy, g.n[1]), wrap(cz, g.n[2]))];
            if (y < 0 || x == y) continue;
            if (x == me) is_partner[y] = 1;
            if (y == me) is_partner[x] = 1;
          }
    }
}

// The partners that need the record (cell, atom box) of my cover cell m: with cell ownership the
// owners of the cells within reach of its box, with per-atom ownership the partners whose atom
// box comes within reach. out is indexed like partners_.
void CommGraph::cover_targets(std::size_t m, std::vector<std::vector<double>>& out) const
{
  const double* cb = &my_boxes_[6 * m];
  const int dim = domain->dimension;
  auto add = [&](std::size_t k) { // one record per octant box of the cell
    for (int b = sub_first_[m]; b < sub_first_[m + 1]; ++b) {
      out[k].push_back(static_cast<double>(my_cells_[m])); // cell ids stay far below 2^53
      out[k].insert(out[k].end(), &sub_boxes_[6 * size_t(b)], &sub_boxes_[6 * size_t(b)] + 6);
    }
  };
  if (cell_owners_.empty()) {
    const double reach2 = cutghost[0] * cutghost[0] * kSlack;
    for (std::size_t k = 0; k < partners_.size(); ++k)
      for (const auto& sh : shifts_)
        if (box_gap2(cb, sh.data(), &rank_boxes_[6 * size_t(partners_[k])], domain->prd, dim) <=
            reach2) {
          add(k);
          break;
        }
    return;
  }
  const fracdem::balance::CellGrid& g = cell_grid_;
  std::int64_t first[3] = {0, 0, 0}, last[3] = {0, 0, 0};
  if (!owner_interior_.empty()) { // inside interior owner cells: nobody needs the record
    bool inner = true;
    for (int d = 0; d < dim; ++d)
      cell_range(g, d, cb[d], cb[3 + d], 0.0, first[d], last[d]);
    for (std::int64_t cz = first[2]; cz <= last[2] && inner; ++cz)
      for (std::int64_t cy = first[1]; cy <= last[1] && inner; ++cy)
        for (std::int64_t cx = first[0]; cx <= last[0] && inner; ++cx)
          inner = owner_interior_[g.id(wrap(cx, g.n[0]), wrap(cy, g.n[1]), wrap(cz, g.n[2]))];
    if (inner) return;
  }
  for (int d = 0; d < dim; ++d)
    cell_range(g, d, cb[d], cb[3 + d], cutghost[0] * kSlack, first[d], last[d]);
  int seen[32], nseen = 0; // distinct ranks among a few cells
  for (std::int64_t cz = first[2]; cz <= last[2]; ++cz)
    for (std::int64_t cy = first[1]; cy <= last[1]; ++cy)
      for (std::int64_t cx = first[0]; cx <= last[0]; ++cx) {
        const int q = cell_owners_[g.id(wrap(cx, g.n[0]), wrap(cy, g.n[1]), wrap(cz, g.n[2]))];
        if (q < 0 || q == me || std::find(seen, seen + nseen, q) != seen + nseen) continue;
        const auto it = std::lower_bound(partners_.begin(), partners_.end(), q);
        if (it == partners_.end() || *it != q) continue; // cannot happen: partners are a superset
        if (nseen < 32) seen[nseen++] = q;
        add(static_cast<std::size_t>(it - partners_.begin()));
      }
}

// One message to every partner (possibly empty: the receiver expects one from each): my cover
// cells it needs. Then the cover of my partners and me as (cell, rank, atom box) records, mine
// first, then by partner.
void CommGraph::exchange_cover()
{
  const std::size_t npart = partners_.size();
  std::vector<std::vector<double>> out(npart), in(npart);
  for (std::size_t m = 0; m < my_cells_.size(); ++m)
    cover_targets(m, out);
  requests_.assign(npart, MPI_REQUEST_NULL);
  for (std::size_t k = 0; k < npart; ++k)
    MPI_Isend(out[k].data(), static_cast<int>(out[k].size()), MPI_DOUBLE, partners_[k], kTagCover,
              gcomm_, &requests_[k]);
  for (std::size_t k = 0; k < npart; ++k) {
    MPI_Status st;
    int n = 0;
    MPI_Probe(partners_[k], kTagCover, gcomm_, &st);
    MPI_Get_count(&st, MPI_DOUBLE, &n);
    in[k].resize(std::max(n, 1));
    MPI_Recv(in[k].data(), n, MPI_DOUBLE, partners_[k], kTagCover, gcomm_, MPI_STATUS_IGNORE);
    in[k].resize(n);
  }
  MPI_Waitall(static_cast<int>(npart), requests_.data(), MPI_STATUSES_IGNORE);

  cell_owner_.clear();
  auto add_owner = [&](std::int64_t cell, int rank, const double* box) {
    CellOwner co;
    co.cell = cell;
    co.rank = rank;
    std::copy(box, box + 6, co.box);
    cell_owner_.push_back(co);
  };
  for (std::size_t m = 0; m < my_cells_.size(); ++m)
    for (int b = sub_first_[m]; b < sub_first_[m + 1]; ++b)
      add_owner(my_cells_[m], me, &sub_boxes_[6 * size_t(b)]);
  for (std::size_t k = 0; k < npart; ++k)
    for (std::size_t r = 0; r + 6 < in[k].size(); r += 7)
      add_owner(static_cast<std::int64_t>(in[k][r]), partners_[k], &in[k][r + 1]);
}

void CommGraph::build_owner_window()
{
  for (int d = 0; d < 3; ++d) {
    const std::int64_t n = cover_.n[d];
    win_lo_[d] = span_lo_[d] - 1, win_n_[d] = span_n_[d] + 2;
    if (cover_.periodic[d]) {
      if (win_n_[d] >= n) win_lo_[d] = 0, win_n_[d] = n;
      win_lo_[d] = wrap(win_lo_[d], n);
    } else {
      const std::int64_t hi = std::min(n, win_lo_[d] + win_n_[d]);
      win_lo_[d] = std::max<std::int64_t>(0, win_lo_[d]), win_n_[d] = hi - win_lo_[d];
    }
  }
  const std::int64_t nslot = win_n_[0] * win_n_[1] * win_n_[2];
  owner_slot_.assign(nslot, -1);
  foreign_.assign(nslot, 0);
  // A list per window cell, linked back to front so that it runs in record order (mine first,
  // then by partner): no sort.
  for (std::size_t k = cell_owner_.size(); k-- > 0;) {
    CellOwner& co = cell_owner_[k];
    std::int64_t c[3];
    cover_.coords(co.cell, c);
    const std::int64_t slot = window_slot(c);
    if (slot < 0) continue;
    co.next = owner_slot_[slot];
    owner_slot_[slot] = static_cast<std::int64_t>(k);
    if (co.rank != me) foreign_[slot] = 1;
  }
  near_ = foreign_; // another rank's cover within one cell
  for (int d = 0; d < domain->dimension; ++d)
    dilate(near_, win_n_, d, cover_.periodic[d] && win_n_[d] == cover_.n[d]);
}

// Slot in the window of the cell with grid coordinates c (each within the grid), or -1.
std::int64_t CommGraph::window_slot(const std::int64_t c[3]) const
{
  std::int64_t slot = 0;
  for (int d = 2; d >= 0; --d) {
    std::int64_t t = c[d] - win_lo_[d];
    if (t < 0) t += cover_.n[d]; // outside a non-periodic window this lands beyond win_n_
    if (t >= win_n_[d]) return -1;
    slot = slot * win_n_[d] + t;
  }
  return slot;
}

// What can need images of the atoms of my cover cell m: the owners of the 27 surrounding cells
// (periodic images included, my own unshifted cell excluded) whose atom box comes within reach
// of the cell's atom box, and the bricks within reach while the insertion cover is on. The
// neighbours' window coordinates and image shifts are worked out per dimension first, so the
// walk is a few loads per neighbour; neighbours with no other rank's cover and no image shift
// are skipped at once. An interior cell (no other rank's cover within one cell, no periodic
// boundary) costs one load of the dilated mask near_.
void CommGraph::cell_candidates(std::size_t m, std::vector<Candidate>& cands) const
{
  cands.clear();
  const int dim = domain->dimension;
  const double* prd = domain->prd;
  const double* box = &my_boxes_[6 * m];
  const double reach2 = cutghost[0] * cutghost[0] * kSlack;
  const std::int64_t* c = &my_coords_[3 * m];
  if (!at_periodic_edge(c) && !near_[window_slot(c)]) { // interior: one load
    if (cover_brick_) brick_candidates(m, cands);
    return;
  }
  std::int64_t t[3][3]; // per dimension and offset -1, 0, 1: window coordinate (-1: none)
  int sh[3][3], lo[3], hi[3];
  for (int d = 0; d < 3; ++d) {
    lo[d] = d < dim ? -1 : 0, hi[d] = d < dim ? 1 : 0;
    for (int o = lo[d]; o <= hi[d]; ++o) {
      std::int64_t v = c[d] + o;
      int s = 0;
      if (v < 0 || v >= cover_.n[d]) { // across a periodic boundary: the image on their side
        s = v < 0 ? 1 : -1;
        v = cover_.periodic[d] ? wrap(v, cover_.n[d]) : -1;
      }
      std::int64_t w = v - win_lo_[d];
      if (w < 0) w += cover_.n[d];
      sh[d][o + 1] = s, t[d][o + 1] = v < 0 || w >= win_n_[d] ? -1 : w;
    }
  }
  for (int dz = lo[2]; dz <= hi[2]; ++dz)
    for (int dy = lo[1]; dy <= hi[1]; ++dy)
      for (int dx = lo[0]; dx <= hi[0]; ++dx) {
        const std::int64_t tx = t[0][dx + 1], ty = t[1][dy + 1], tz = t[2][dz + 1];
        if (tx < 0 || ty < 0 || tz < 0) continue; // outside the box or beyond every cover
        const std::int64_t slot = (tz * win_n_[1] + ty) * win_n_[0] + tx;
        const int shift[3] = {sh[0][dx + 1], sh[1][dy + 1], sh[2][dz + 1]};
        const int s = shift_of_[(shift[0] + 1) + 3 * (shift[1] + 1) + 9 * (shift[2] + 1)];
        if (owner_slot_[slot] < 0 || (s == 0 && !foreign_[slot])) continue;
        for (std::int64_t o = owner_slot_[slot]; o >= 0; o = cell_owner_[o].next) {
          const CellOwner& co = cell_owner_[o];
          if (co.rank == me && s == 0) continue; // an owned atom is no ghost of itself
          if (box_gap2(box, shift, co.box, prd, dim) <= reach2)
            cands.push_back({co.rank, s, co.box});
        }
      }
  if (cover_brick_) brick_candidates(m, cands);
}

// Whether cell c touches a periodic boundary (its atoms have images of their own to send).
bool CommGraph::at_periodic_edge(const std::int64_t c[3]) const
{
  for (int d = 0; d < domain->dimension; ++d)
    if (cover_.periodic[d] && (c[d] == 0 || c[d] == cover_.n[d] - 1)) return true;
  return false;
}

// Insertion cover: the bricks (of my partners and, shifted, my own) within reach of cell m.
void CommGraph::brick_candidates(std::size_t m, std::vector<Candidate>& cands) const
{
  const int dim = domain->dimension;
  const double* box = &my_boxes_[6 * m];
  const double reach2 = cutghost[0] * cutghost[0] * kSlack;
  for (std::size_t k = 0; k <= partners_.size(); ++k) {
    const int x = k < partners_.size() ? partners_[k] : me;
    for (int b = 0; b < nbox_; ++b) {
      const double* B = &bricks_[6 * (size_t(x) * nbox_ + b)];
      bool empty = false;
      for (int d = 0; d < dim; ++d)
        empty |= B[d] > B[3 + d];
      for (int s = 0; s < nshift_ && !empty; ++s)
        if (!(x == me && s == 0) && box_gap2(box, shifts_[s].data(), B, domain->prd, dim) <= reach2)
          cands.push_back({x, s, B});
    }
  }
}

// Send lists. A cell's candidates are grouped by target (rank, image): a group one of whose
// boxes is within the cutoff of every point of the cell takes all of the cell's atoms untested;
// otherwise each atom is tested against the group's boxes until one is within its cutoff.
void CommGraph::search_ghosts()
{
  const int dim = domain->dimension;
  const double* prd = domain->prd;
  const double cut2 = cutghost[0] * cutghost[0];
  double** x = atom->x;
  for (int iswap = 0; iswap < nswap; ++iswap)
    sendnum[iswap] = 0;
  struct Group {
    int iswap;
    bool all;
    std::size_t first, last;
  };
  std::vector<Candidate> cands;
  std::vector<Group> groups;
  for (std::size_t m = 0; m < my_cells_.size(); ++m) {
    cell_candidates(m, cands);
    if (cands.empty()) continue;
    std::sort(cands.begin(), cands.end(), [](const Candidate& a, const Candidate& b) {
      return a.rank != b.rank ? a.rank < b.rank : a.shift < b.shift;
    });
    groups.clear();
    for (std::size_t a = 0, b = 0; a < cands.size(); a = b) {
      Group g{block_to_[cands[a].rank] * nshift_ + cands[a].shift, false, a, a};
      for (b = a;
           b < cands.size() && cands[b].rank == cands[a].rank && cands[b].shift == cands[a].shift;
           ++b)
        g.all = g.all || far_gap2(&my_boxes_[6 * m], shifts_[cands[b].shift].data(), cands[b].box,
                                  prd, dim) <= cut2;
      g.last = b;
      groups.push_back(g);
    }
    for (int k = cell_first_[m]; k < cell_first_[m + 1]; ++k) {
      const int i = order_[k];
      for (const Group& g : groups) {
        bool hit = g.all;
        for (std::size_t c = g.first; c < g.last && !hit; ++c) {
          double y[3];
          for (int d = 0; d < 3; ++d)
            y[d] = x[i][d] + shifts_[cands[c].shift][d] * prd[d];
          hit = point_gap2(y, cands[c].box, dim) <= cut2;
        }
        if (!hit) continue;
        if (sendnum[g.iswap] == maxsendlist[g.iswap]) grow_list(g.iswap, sendnum[g.iswap]);
        sendlist[g.iswap][sendnum[g.iswap]++] = i;
      }
    }
  }
}

// One message to every partner: per image shift (atoms, doubles), then the packed atoms.
void CommGraph::send_borders()
{
  AtomVec* avec = atom->avec;
  const int nblock = static_cast<int>(ring_.size());
  std::vector<std::vector<double>> out(nblock), in(nblock);
  requests_.clear();
  for (int b = 1; b < nblock; ++b) {
    const int dest = sendproc[b * nshift_];
    if (!std::binary_search(partners_.begin(), partners_.end(), dest)) continue;
    std::vector<double>& msg = out[b];
    msg.assign(2 * size_t(nshift_), 0.0);
    for (int s = 0; s < nshift_; ++s) {
      const int iswap = b * nshift_ + s, n = sendnum[iswap];
      const size_t at = msg.size();
      msg.resize(at + size_t(n) * size_border + bufextra);
      const int used =
          ghost_velocity
              ? avec->pack_border_vel(n, sendlist[iswap], &msg[at], pbc_flag[iswap], pbc[iswap])
              : avec->pack_border(n, sendlist[iswap], &msg[at], pbc_flag[iswap], pbc[iswap]);
      msg.resize(at + used);
      msg[2 * s] = n, msg[2 * s + 1] = used;
    }
    requests_.emplace_back();
    MPI_Isend(msg.data(), static_cast<int>(msg.size()), MPI_DOUBLE, dest, kTagBorder, gcomm_,
              &requests_.back());
  }
  for (int from : partners_) {
    const int k = (me - from + nprocs) % nprocs;
    const int b = static_cast<int>(std::lower_bound(ring_.begin(), ring_.end(), k) - ring_.begin());
    MPI_Status st;
    int n = 0;
    MPI_Probe(from, kTagBorder, gcomm_, &st);
    MPI_Get_count(&st, MPI_DOUBLE, &n);
    in[b].resize(std::max(n, 1));
    MPI_Recv(in[b].data(), n, MPI_DOUBLE, from, kTagBorder, gcomm_, MPI_STATUS_IGNORE);
    in[b].resize(n);
  }
  MPI_Waitall(static_cast<int>(requests_.size()), requests_.data(), MPI_STATUSES_IGNORE);
  unpack_borders(in);
}

// Ghosts in swap order (so a block's ghosts are contiguous), my own images copied locally; then
// the per-swap sizes the forward/reverse communications use.
void CommGraph::unpack_borders(std::vector<std::vector<double>>& in)
{
  AtomVec* avec = atom->avec;
  int smax = 0, rmax = 0;
  for (int iswap = 0; iswap < nswap; ++iswap) {
    const int b = iswap / nshift_, s = iswap % nshift_;
    const int first = atom->nlocal + atom->nghost;
    int nrecv = 0;
    double* buf = nullptr;
    if (b == 0) {
      nrecv = sendnum[iswap];
      self_buf_.resize(size_t(nrecv) * size_border + bufextra);
      buf = self_buf_.data();
      if (ghost_velocity)
        avec->pack_border_vel(nrecv, sendlist[iswap], buf, pbc_flag[iswap], pbc[iswap]);
      else
        avec->pack_border(nrecv, sendlist[iswap], buf, pbc_flag[iswap], pbc[iswap]);
    } else if (!in[b].empty()) {
      size_t at = 2 * size_t(nshift_);
      for (int t = 0; t < s; ++t)
        at += static_cast<size_t>(in[b][2 * t + 1]);
      nrecv = static_cast<int>(in[b][2 * s]);
      buf = in[b].data() + at;
    }
    if (nrecv) {
      if (ghost_velocity)
        avec->unpack_border_vel(nrecv, first, buf);
      else
        avec->unpack_border(nrecv, first, buf);
    }
    smax = std::max(smax, sendnum[iswap]);
    rmax = std::max(rmax, nrecv);
    recvnum[iswap] = nrecv;
    size_forward_recv[iswap] = nrecv * size_forward;
    size_reverse_send[iswap] = nrecv * size_reverse;
    size_reverse_recv[iswap] = sendnum[iswap] * size_reverse;
    firstrecv[iswap] = first;
    atom->nghost += nrecv;
  }
  // The base class's swap loop (forward_comm_array) uses the stock buffers.
  int max = std::max(maxforward * smax, maxreverse * rmax);
  if (max > maxsend) grow_send(max, 0);
  max = std::max(maxforward * rmax, maxreverse * smax);
  if (max > maxrecv) grow_recv(max);
}

void CommGraph::borders()
{
  if (!graph_mode_) {
    Comm::borders();
    return;
  }
  borders_stats_begin();
  bin_atoms();
  compute_span();
  compute_bricks();
  find_partners();
  build_blocks();
  exchange_cover();
  build_owner_window();
  search_ghosts();
  send_borders();
  borders_stats_end(atom->nlocal);
  if (map_style) atom->map_set();
}

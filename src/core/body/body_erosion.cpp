// A distributed body that erodes: each part erodes its own elements, the parts agree once per host
// step, and rank 0 logs and renews the whole surface after an erosion (docs/distributed_bodies.md).
#include "body/body_driver.h"

#include <algorithm>
#include <array>

#include "body/body_setup.h"

namespace fracdem
{

namespace
{

void add_account(ErosionAccount& to, const ErosionAccount& a, double sign = 1.0)
{
  to.elements += static_cast<int>(sign) * a.elements;
  to.mass += sign * a.mass;
  to.energy += sign * a.energy;
}

void put_account(const ErosionAccount& a, std::vector<double>& out)
{
  out.insert(out.end(), {static_cast<double>(a.elements), a.mass, a.energy});
}

ErosionAccount get_account(const std::vector<double>& in, std::size_t& at)
{
  ErosionAccount a;
  a.elements = static_cast<int>(in[at]);
  a.mass = in[at + 1];
  a.energy = in[at + 2];
  at += 3;
  return a;
}

} // namespace

// This part's elements leave as in the replicated loop (forces_after_erosion, or a breaking
// body's inverted elements one at a time as erode_inverted takes them): every criterion and det F
// are element-local, so the part decides for its elements what the whole body would. With
// erosion_mass remove the mass they take off shared nodes waits for sum_forces_and_masses. The
// erosion waits, in global numbers, for the follow-up at the host step's last evaluation (last);
// before it, with sub-cycling, the part's stable step after each evaluation is kept (the replicated
// body takes it right after its erosion).
double BodyDriver::erode_part(double energy, int& first_inverted, bool last)
{
  PartErosion ev;
  ev.fe = fe_count_;
  const ErosionAccount before = body_.eroded();
  if (spec_->erosion.on()) {
    energy = erosion_loop(energy, first_inverted, ev.counts, ev.batch);
  } else {
    while (first_inverted >= 0) {
      body_.erode({first_inverted}, spec_->erosion.remove_mass);
      ev.batch.push_back(first_inverted);
      ++ev.counts[static_cast<int>(ErosionCause::Inverted)];
      body_.clear_internal_forces();
      first_inverted = -1;
      energy = body_.add_internal_forces(&first_inverted);
    }
  }
  if (!ev.batch.empty()) {
    if (part_erosion_.empty()) erosion_mark_ = before;
    for (int& e : ev.batch)
      e = part_.global_elem[e];
    ev.took = body_.eroded();
    add_account(ev.took, before, -1.0);
    part_erosion_.push_back(std::move(ev));
  }
  if (!last) {
    if (spec_->erosion.on()) fe_dt_stable_.push_back(body_.stable_time_step());
    ++fe_count_;
  }
  return energy;
}

// erosion_mass remove: the shared-node force sum of every evaluation carries two more values per
// node, the mass this part's erosions took off it and the part's active elements around it, so
// that every sharer drops the mass all parts took and releases a node that no part holds an
// element of anymore, as the whole body does in erode (no collective; 5 doubles per shared node
// and neighbour instead of 3, also while nothing erodes: a part cannot know whether its
// neighbours eroded without a message).
void BodyDriver::sum_forces_and_masses()
{
  const int nn = body_.num_nodes();
  force_mass_.resize(5 * static_cast<std::size_t>(nn));
  double* f = body_.forces_data();
  for (int n = 0; n < nn; ++n) {
    double* to = &force_mass_[5 * static_cast<std::size_t>(n)];
    to[0] = f[3 * n], to[1] = f[3 * n + 1], to[2] = f[3 * n + 2];
    to[3] = body_.shared_taken(n);
    to[4] = body_.active_elements(n);
  }
  shared_sum_(force_mass_.data(), 5);
  for (int n = 0; n < nn; ++n)
    for (int d = 0; d < 3; ++d)
      f[3 * n + d] = force_mass_[5 * static_cast<std::size_t>(n) + d];
  body_.settle_shared_masses(force_mass_.data(), 5, 3);
}

// The follow-up of the erosions of the evaluations since the last one, entered by every rank at
// the host step's last evaluation, before the particle contact: one integer max-reduction (one
// flag per evaluation) says where any part eroded; after an erosion, the stable steps there (one
// min-reduction), every part's erosions on rank 0 (gather), which logs them as the replicated body
// does and sends every rank the whole body's new surface; then every rank follows the stable step
// in the order of the evaluations, as the replicated body did after each batch. piece_moved (the
// pieces' travel flag, body_self_contact.cpp) rides on the same reduction and comes back reduced.
void BodyDriver::distributed_erosion(std::int64_t step, double dt, int& piece_moved)
{
  const int n = fe_count_ + 1;
  std::vector<int> flags(n + 1, 0);
  for (const PartErosion& ev : part_erosion_)
    flags[ev.fe] = 1;
  flags[n] = piece_moved;
  host_.max_int(flags.data(), n + 1);
  piece_moved = flags[n];
  std::vector<int> at;
  for (int k = 0; k < n; ++k)
    if (flags[k]) at.push_back(k);
  if (!at.empty()) {
    std::vector<double> dts(at.size(), 0.0);
    if (spec_->erosion.on()) {
      for (size_t i = 0; i < at.size(); ++i)
        dts[i] = at[i] == n - 1 ? body_.stable_time_step() : fe_dt_stable_[at[i]];
      host_.min(dts.data(), static_cast<int>(dts.size()));
    }
    const std::vector<double> all = host_.gather(pack_part_erosion());
    std::vector<std::vector<std::string>> lines(at.size());
    std::vector<int> eroded;
    if (host_.rank == 0) merge_part_erosion(step, all, at, lines, eroded);
    renew_surface_after_erosion(eroded);
    broken_ = true; // the body has changed (stored in the parts records' head)
    for (size_t i = 0; i < at.size(); ++i) {
      for (const std::string& line : lines[i])
        print(line);
      if (!spec_->erosion.on()) continue;
      dt_stable_ = dts[i];
      follow_step_after_erosion(step, dt);
    }
  }
  part_erosion_.clear();
  fe_dt_stable_.clear();
  fe_count_ = 0;
}

// [account before the first erosion, count, then per erosion: fe, counts, size, batch, took]
std::vector<double> BodyDriver::pack_part_erosion() const
{
  std::vector<double> out;
  put_account(part_erosion_.empty() ? body_.eroded() : erosion_mark_, out);
  out.push_back(static_cast<double>(part_erosion_.size()));
  for (const PartErosion& ev : part_erosion_) {
    out.push_back(ev.fe);
    out.insert(out.end(), ev.counts, ev.counts + kErosionCauses);
    out.push_back(static_cast<double>(ev.batch.size()));
    out.insert(out.end(), ev.batch.begin(), ev.batch.end());
    put_account(ev.took, out);
  }
  return out;
}

// Rank 0: the lines of the replicated body for each evaluation of `at` from every part's
// erosions (all: pack_part_erosion of every rank, in rank order): the parts' criteria elements
// merged in ascending order, then their inverted ones, the counts and what they took summed, the
// totals from the parts' accounts before; eroded: every element that left.
void BodyDriver::merge_part_erosion(std::int64_t step, const std::vector<double>& all,
                                    const std::vector<int>& at,
                                    std::vector<std::vector<std::string>>& lines,
                                    std::vector<int>& eroded) const
{
  const size_t na = at.size();
  std::vector<std::vector<int>> crit(na), inv(na);
  std::vector<std::array<int, kErosionCauses>> counts(na, {0, 0, 0, 0});
  std::vector<ErosionAccount> took(na);
  ErosionAccount total;
  const int kInv = static_cast<int>(ErosionCause::Inverted);
  for (std::size_t p = 0; p < all.size();) {
    add_account(total, get_account(all, p));
    const int nev = static_cast<int>(all[p++]);
    for (int k = 0; k < nev; ++k) {
      const int i =
          static_cast<int>(std::lower_bound(at.begin(), at.end(), int(all[p++])) - at.begin());
      int c[kErosionCauses];
      for (int j = 0; j < kErosionCauses; ++j)
        counts[i][j] += c[j] = static_cast<int>(all[p++]);
      const int size = static_cast<int>(all[p++]);
      for (int j = 0; j < size; ++j)
        (j < size - c[kInv] ? crit[i] : inv[i]).push_back(static_cast<int>(all[p++]));
      add_account(took[i], get_account(all, p));
    }
  }
  for (size_t i = 0; i < na; ++i) {
    std::sort(crit[i].begin(), crit[i].end());
    std::sort(inv[i].begin(), inv[i].end());
    add_account(total, took[i]);
    std::vector<int> batch(crit[i]);
    batch.insert(batch.end(), inv[i].begin(), inv[i].end());
    eroded.insert(eroded.end(), batch.begin(), batch.end());
    if (spec_->erosion.on()) {
      lines[i].push_back(erosion_line(step, counts[i].data(), batch, total));
      continue;
    }
    for (int e : batch) // a breaking body's inverted elements, one line each (erode_inverted)
      lines[i].push_back(inverted_line(step, e));
  }
}

// Every part's surface facets come from the whole body's surface, which changes with every
// erosion. Rank 0 keeps the whole mesh and its element owners (gathered at the first erosion
// after the parts changed), takes the eroded elements out and sends every rank the new surface
// (as at set-up) and counts the fragments the erosion left; each rank renews its facet ghosts
// (boxes exchanged at once, before the contact).
void BodyDriver::renew_surface_after_erosion(const std::vector<int>& eroded)
{
  if (!whole_mesh_known_) {
    Body whole;
    if (gather_whole(whole, whole_owner_)) whole_mesh_ = whole.mesh();
    whole_mesh_known_ = true;
  }
  std::vector<double> packed;
  if (host_.rank == 0) {
    for (int e : eroded)
      whole_mesh_.active[e] = 0;
    packed = pack_surface(global_surface(whole_mesh_, whole_owner_));
    std::vector<int> component; // an erosion can part the body: the energy file's count
    whole_fragments_ = element_components(whole_mesh_, component);
  }
  const std::vector<double> message = host_.scatter([&](int) { return packed; });
  std::size_t at = 0;
  ghosts_.init(part_, unpack_surface(message, at));
  boxes_due_ = true;
  rebuild_surfaces();
}

} // namespace fracdem

// BodyDriver's contacts between bodies carried from run to run and through restart files: the
// contact scene's pairs and a distributed body's pairs with replicated bodies, as records of
// (first body's fix ID, second's, state) that either holder reads.
#include "body/body_driver.h"

#include <stdexcept>

namespace fracdem
{

namespace
{

// One pair: the fix IDs of its bodies (the earlier fix first, as the scene orders them) and its
// state as ContactScene::pair_state lays it out (nodes of the first on facets of the second,
// the other way, edge pairs with the first body's edge first).
struct PairRecord {
  std::string first, second;
  std::vector<double> state;
};

[[noreturn]] void corrupt()
{
  throw std::runtime_error("corrupt restart record (contacts between bodies)");
}

void put_id(const std::string& id, std::vector<double>& out)
{
  out.push_back(static_cast<double>(id.size()));
  for (unsigned char c : id)
    out.push_back(static_cast<double>(c));
}

// Records one after the other: ID, ID (length, characters), state length, state.
void put_pair(const PairRecord& r, std::vector<double>& out)
{
  put_id(r.first, out);
  put_id(r.second, out);
  out.push_back(static_cast<double>(r.state.size()));
  out.insert(out.end(), r.state.begin(), r.state.end());
}

std::vector<PairRecord> read_pairs(const std::vector<double>& in)
{
  std::size_t at = 0;
  const auto count = [&]() {
    if (at >= in.size()) corrupt();
    const double x = in[at++];
    if (!(x >= 0 && x < 1e9) || x != static_cast<double>(static_cast<long>(x))) corrupt();
    return static_cast<std::size_t>(x);
  };
  const auto id = [&]() {
    std::string s(count(), ' ');
    for (char& c : s)
      c = static_cast<char>(count());
    return s;
  };
  std::vector<PairRecord> out;
  while (at < in.size()) {
    PairRecord r;
    r.first = id();
    r.second = id();
    const std::size_t n = count();
    if (at + n > in.size()) corrupt();
    r.state.assign(in.begin() + static_cast<std::ptrdiff_t>(at),
                   in.begin() + static_cast<std::ptrdiff_t>(at + n));
    at += n;
    out.push_back(std::move(r));
  }
  return out;
}

// The record of (first, second) among the bodies' restored records; null: none.
const PairRecord* find_pair(const std::vector<PairRecord>& records, const std::string& first,
                            const std::string& second)
{
  for (const PairRecord& r : records)
    if (r.first == first && r.second == second) return &r;
  return nullptr;
}

} // namespace

// Every pair of the scene (every rank enters: the state is summed over the parts holding it).
std::vector<double> BodyDriver::scene_pair_records() const
{
  std::vector<double> out;
  const int n = scene_owned_->size();
  for (int b = 1; b < n; ++b)
    for (int a = 0; a < b; ++a)
      put_pair({scene_members_[a]->id_, scene_members_[b]->id_, scene_owned_->pair_state(a, b)},
               out);
  return out;
}

// The pairs this body holds, for its restart record: the first body of a scene of several (one
// not evaluated since its set-up, as write_restart sets the bodies up before it writes, has its
// state still to take: carried_pair_state_), or a distributed body (rank 0's state, which
// evaluates its pairs and writes the file).
std::vector<double> BodyDriver::pair_records() const
{
  if (scene_owned_ && scene_members_.size() > 1)
    return scene_owned_->size() > 0 ? scene_pair_records() : carried_pair_state_;
  std::vector<double> out;
  if (!distributed_) return out;
  for (const BodyPair& p : pairs_) {
    const BodyDriver& first = p.other_first ? *p.other : *this;
    const BodyDriver& second = p.other_first ? *this : *p.other;
    put_pair({first.id_, second.id_,
              p.other_first ? pack_pair_state(p.other_on_mine, p.mine_on_other, p.edges)
                            : pack_pair_state(p.mine_on_other, p.other_on_mine, p.edges)},
             out);
  }
  return out;
}

// After a restart: where the file holds every pair of these bodies (same fix IDs, whichever body
// held them, replicated or distributed), the scene goes on with them and its set-up replays the
// held forces (replays_body_contacts); otherwise the pairs start afresh.
void BodyDriver::take_restored_scene_pairs(const std::vector<BodyDriver*>& members)
{
  std::vector<PairRecord> records;
  try {
    for (const BodyDriver* m : members)
      for (PairRecord& r : read_pairs(m->restored_pairs_))
        records.push_back(std::move(r));
  } catch (const std::exception& e) {
    fail(prefix() + e.what());
  }
  if (records.empty() || members.size() < 2) return;
  std::vector<double> carried;
  for (size_t b = 1; b < members.size(); ++b)
    for (size_t a = 0; a < b; ++a) {
      const PairRecord* r = find_pair(records, members[a]->id_, members[b]->id_);
      if (!r) return;
      put_pair(*r, carried);
    }
  carried_pair_state_ = std::move(carried);
  scene_continues_ = true;
}

// At the scene's first evaluation: the carried pairs into the new scene (configured: its pairs
// exist); the restored records are spent.
void BodyDriver::restore_scene_pairs()
{
  try {
    for (const PairRecord& r : read_pairs(carried_pair_state_)) {
      int a = -1, b = -1;
      for (int m = 0; m < static_cast<int>(scene_members_.size()); ++m) {
        if (scene_members_[m]->id_ == r.first) a = m;
        if (scene_members_[m]->id_ == r.second) b = m;
      }
      if (a >= 0 && a < b) scene_owned_->restore_pair_state(a, b, r.state);
    }
  } catch (const std::exception& e) {
    fail(prefix() + e.what());
  }
  carried_pair_state_.clear();
  drop_restored_pairs(scene_members_);
}

// A distributed body after a restart: its pairs go on where the file holds all of them.
void BodyDriver::take_restored_body_pairs()
{
  std::vector<PairRecord> records;
  try {
    for (const BodyDriver* m : pair_group_)
      for (PairRecord& r : read_pairs(m->restored_pairs_))
        records.push_back(std::move(r));
    if (records.empty()) return;
    std::vector<const PairRecord*> found;
    for (const BodyPair& p : pairs_) {
      found.push_back(p.other_first ? find_pair(records, p.other->id_, id_)
                                    : find_pair(records, id_, p.other->id_));
      if (!found.back()) return;
    }
    for (size_t k = 0; k < pairs_.size(); ++k) {
      BodyPair& p = pairs_[k];
      if (p.other_first)
        unpack_pair_state(found[k]->state, p.other_on_mine, p.mine_on_other, p.edges);
      else
        unpack_pair_state(found[k]->state, p.mine_on_other, p.other_on_mine, p.edges);
    }
  } catch (const std::exception& e) {
    fail(prefix() + e.what());
  }
  pair_continues_ = true;
}

void BodyDriver::drop_restored_pairs(const std::vector<BodyDriver*>& bodies)
{
  for (BodyDriver* m : bodies)
    m->restored_pairs_.clear();
}

} // namespace fracdem

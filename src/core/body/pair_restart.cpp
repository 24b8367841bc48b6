// BodyDriver's contacts between bodies carried from run to run and through restart files: the
// contact scene's pairs and a distributed body's pairs with replicated bodies, as records of
// (first body's fix ID, second's, state) that either holder reads.
#include "body/body_driver.h"
#include "body/pair_records.h"

#include <stdexcept>

namespace fracdem
{

namespace
{

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

} // namespace

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

// The pairs this body holds, for its restart record: the first body of a scene of several (its
// coordinator's), or a distributed body (rank 0's state, which evaluates its pairs and writes the
// file).
std::vector<double> BodyDriver::pair_records() const
{
  if (in_scene() && scene_index_ == 0) return coordinator_->pair_records();
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

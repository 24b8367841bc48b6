// Contacts between bodies as records of (first body's fix ID, second's, state) that either holder
// of the pair reads: carried from run to run and through restart files.
#pragma once

#include <string>
#include <vector>

namespace fracdem
{

// One pair: the fix IDs of its bodies (the earlier fix first, as the scene orders them) and its
// state as ContactScene::pair_state lays it out.
struct PairRecord {
  std::string first, second;
  std::vector<double> state;
};

// Records one after the other: ID, ID (length, characters), state length, state.
void put_pair(const PairRecord& r, std::vector<double>& out);
// Throws std::runtime_error on a corrupt record.
std::vector<PairRecord> read_pairs(const std::vector<double>& in);
// The record of (first, second); null: none.
const PairRecord* find_pair(const std::vector<PairRecord>& records, const std::string& first,
                            const std::string& second);

} // namespace fracdem

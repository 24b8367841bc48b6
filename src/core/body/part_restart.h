// Restart records of distributed bodies: each part's nodes and elements by global index, merged
// into one record of the whole body that any rank count (or a replicated body) can read.
#pragma once

#include <vector>

#include "body/body_partition.h"
#include "fem/body.h"

namespace fracdem
{

// First value of the body section of a parts record (Body::pack_state records start with their
// version, 1..4).
constexpr double kPartsRecordVersion = 100.0;

// What one part contributes (part: null for a whole body): its clock and work accounts, each
// node it owns (global index, position, velocity) and each of its elements (global index,
// Body::pack_element). The host gathers these from every rank.
std::vector<double> pack_part_state(const Body& body, const MeshPart* part);

// The body section from the parts' contributions, concatenated in any order: version,
// node and element counts, the summed accounts (the clock: the first part's), positions and
// velocities of every node, then each element's size and values in global order. Throws
// std::runtime_error when a node or element is missing.
std::vector<double> merge_part_states(const std::vector<double>& gathered, int global_nodes,
                                      int global_elems);

// Restores this body (a part: null for a whole body) from a parts record. take_accounts: this
// body takes the whole body's work accounts (one part does; the others start theirs at zero, so
// that sums over the parts stay right). Throws std::runtime_error on a record that does not fit.
void unpack_parts_record(const double* record, Body& body, const MeshPart* part,
                         bool take_accounts);

// The same from a whole (replicated) body restored from its own record: the part takes its
// nodes and elements. Throws std::runtime_error when the whole body was cracked or eroded (a
// distributed body cannot hold changed topology).
void copy_whole_into_part(const Body& whole, Body& body, const MeshPart& part, bool take_accounts);

} // namespace fracdem

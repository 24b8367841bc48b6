// Distributed bodies: restart records (one per part; older files: the parts merged into one
// record of the whole body) and the gather / scatter of a breaking body, each part by global index.
#pragma once

#include <vector>

#include "body/body_partition.h"
#include "fem/body.h"
#include "fracture/fracture_plan.h"

namespace fracdem
{

// ---- the earlier format (files written before kPartRecordsVersion): the parts merged into one
// record of the whole body's nodes and elements, still read at any rank count ----

// First value of the body section of a parts record (Body::pack_state records start with their
// version, 1..5). Layout: version, node and element counts, the accounts (Body::Accounts, 6
// values), position and velocity of every node, then each element's size and values
// (Body::pack_element), in global order.
constexpr double kPartsRecordVersion = 100.0;

// Restores this body (a part: null for a whole body) from a parts record. take_accounts: this
// body takes the whole body's work accounts (one part does; the others start theirs at zero, so
// that sums over the parts stay right). Throws std::runtime_error on a record that does not fit.
void unpack_parts_record(const double* record, Body& body, const MeshPart* part,
                         bool take_accounts);

// The same from a whole (replicated) body restored from its own record: the part takes its
// nodes and elements. Throws std::runtime_error when the whole body was cracked or eroded (a
// distributed body cannot hold changed topology).
void copy_whole_into_part(const Body& whole, Body& body, const MeshPart& part, bool take_accounts);

// ---- a distributed body that breaks (docs/distributed_bodies.md): gathered whole on rank 0 for
// a topology change, then scattered again in new parts ----

// Where a part's nodes and elements came from, in global numbers (-1: none): per local node the
// node it was split from and the ends of the edge it was cut at, per local element the element
// it was cut from. A body that never broke has all -1.
// For output (fem/vtk pieces), sent with each new part but not gathered (rank 0 derives them
// from the whole body): per node 1 where a crack runs through it (a split copy or its parent),
// per element the mesh element it is a piece of and its fragment, and whether any element was
// cut (every piece then writes the mesh_element field). Empty / false before the first change.
struct PartTopology {
  std::vector<int> node_parent, cut_u, cut_w, elem_parent;
  std::vector<int> node_split, elem_root, elem_fragment;
  bool cut = false;
  void reset(int nodes, int elems);
};
// The same of a whole body (global numbers are its own).
PartTopology whole_topology(const Body& whole);

// The part's nodes as the fracture check on the whole body sees them (fracture_plan.h): split
// and cut nodes of the whole body from its topology, whole stars where the part alone uses a node.
// Topology fields that were never set (an intact body's part) mark no node on a crack; where they
// are missing on a cracked part no star counts as whole (every check may change).
CrackNodes part_crack_nodes(const MeshPart& part, const PartTopology& topo, double min_size);

// What one part contributes to the gathered whole body: its accounts and outputs (Body::Outputs),
// its damage (damaged points, failed elements by global number), each node it owns (global
// number, Body::pack_node, parent, cut ends) and each element (global number, active, global
// connectivity, parent, then Body::pack_element).
std::vector<double> pack_part_whole(const Body& body, const MeshPart& part,
                                    const PartTopology& topo);

// Rank 0's merge of every part's pack_part_whole (concatenated, any order).
struct GatheredBody {
  std::vector<double> record; // Body::pack_state layout (version 4, 5 with cuts)
  std::vector<double> nodes;  // Body::kNodeRecordSize per global node (forces included)
  Body::Outputs outputs;      // summed over the parts
  int damaged = 0;            // damaged points, summed
  std::vector<int> failed;    // failed elements, ascending global numbers
  std::vector<int> owner;     // per global element: the part that held it
};
// global_nodes / global_elems: the whole body's counts; mesh_elems: elements of the mesh as read
// (the others came from cuts); viscosity: the element records carry the viscous accounts.
// Throws std::runtime_error when a node or element is missing.
GatheredBody merge_part_wholes(const std::vector<double>& gathered, int global_nodes,
                               int global_elems, int mesh_elems, bool viscosity);
// The whole body from the mesh as read (built) and the gathered state.
void restore_gathered(const GatheredBody& g, Body& whole);

// Rank r's message after a change: part r of the whole body (body_setup.h part_message: mesh
// part and surface), then its state (each node's pack_node, parent, cut ends; each element's
// parent and pack_element) and the whole body's accounts and outputs where take_accounts (one
// part takes them, the others start from zero).
std::vector<double> part_message_with_state(const Body& whole, const PartTopology& whole_topo,
                                            const std::vector<int>& elem_part,
                                            const std::vector<double>& packed_surface, int rank);
// Restores the state of such a message (at: where it follows the surface) into the part's body
// built from the message, and the part's topology.
void unpack_part_message_state(const std::vector<double>& message, std::size_t at, Body& body,
                               const MeshPart& part, PartTopology& topo);

// ---- restart records of a distributed body: one record per part (issue #13 item 5) ----

// First value of such a record. Layout: version, the rank count P, the whole body's node and
// element counts, kDriverValues of the driver (its own figures, written by rank 0), the element
// partition (per global element its part), then each part's block in part order. A block:
// part, the length and values of pack_part_whole (what a merge at another count reads: the nodes
// it owns, its elements), the length and values of the rest of the part's own state (each local
// node's and element's topology in global numbers, Body::pack_node of the shared nodes it does
// not own, as it holds them), so that the same part at the same count comes back as it was.
constexpr double kPartRecordsVersion = 101.0;
constexpr int kDriverValues = 4;

// One part's block (host: gathered on rank 0 in part order).
std::vector<double> pack_part_record(const Body& body, const MeshPart& part,
                                     const PartTopology& topo);
// Rank 0: the record from the gathered blocks of all nparts parts (concatenated; any order).
// Throws std::runtime_error when an element is in no block or a block is missing.
std::vector<double> join_part_records(const std::vector<double>& gathered, int nparts,
                                      int global_nodes, int global_elems,
                                      const double (&driver)[kDriverValues]);

// A record of join_part_records, read in place (pointers into it).
struct PartRecords {
  int nparts = 0, global_nodes = 0, global_elems = 0;
  double driver[kDriverValues] = {0, 0, 0, 0};
  std::vector<int> elem_part;
  std::vector<const double*> whole, own; // per part: pack_part_whole, its own state
  std::vector<std::size_t> whole_size, own_size;
};
// Throws std::runtime_error on a record that does not hold nparts blocks.
PartRecords read_part_records(const double* record);
// Every part's pack_part_whole, concatenated: what merge_part_wholes reads.
std::vector<double> gathered_wholes(const PartRecords& r);
// After the part was taken from the merged whole body with the stored partition (part_message_
// with_state, unpack_part_message_state): its own nodes, topology, accounts and outputs as the
// part held them (the whole body gives a shared node its owner's values and one part all the
// accounts). Throws std::runtime_error when the part's nodes are not the block's.
void restore_own_part(const PartRecords& r, Body& body, const MeshPart& part, PartTopology& topo);

} // namespace fracdem

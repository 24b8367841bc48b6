// Unit tests of the restart records of distributed bodies (body/part_restart.h): records of the
// earlier format read by a whole body and by parts, per-part records, gather and scatter.
#include <gtest/gtest.h>

#include <random>
#include <stdexcept>
#include <vector>

#include "body/body_partition.h"
#include "body/body_setup.h"
#include "body/part_restart.h"
#include "fem/body.h"
#include "io/mesh_generators.h"
#include "test_support.h"

using namespace fracdem;

namespace
{

Mesh block()
{
  return make_box_tet_mesh(4, 3, 2, 0.4, 0.3, 0.2);
}

// A whole body in motion (random velocities, one step taken, work accounts non-zero).
Body moving_body()
{
  Body b;
  b.build(block(), fracdem_test::steel(), false);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int n = 0; n < b.num_nodes(); ++n) {
    const double v[3] = {u(rng), u(rng), u(rng)};
    b.set_velocity({n}, v);
  }
  b.advance_time(1e-7);
  b.half_kick_drift(1e-7);
  b.begin_forces();
  const double g[3] = {0, 0, -9.81};
  int inverted = -1;
  b.finish_forces(b.add_internal_forces(&inverted), g, 1e-7, true);
  b.half_kick(1e-7);
  return b;
}

// The parts of `mesh` in `nparts` pieces, each with its body taken from `whole`.
struct Parts {
  std::vector<MeshPart> parts;
  std::vector<Body> bodies;
};
Parts split_into(const Body& whole, int nparts)
{
  Parts p;
  const Mesh mesh = block();
  const std::vector<int> owner = partition_elements(mesh, nparts);
  p.parts.reserve(nparts);
  p.bodies.resize(nparts);
  for (int k = 0; k < nparts; ++k) {
    p.parts.push_back(extract_part(mesh, owner, k));
    Body& b = p.bodies[k];
    b.build(p.parts[k].mesh, fracdem_test::steel(), false);
    std::vector<std::uint8_t> owned(p.parts[k].num_nodes());
    for (int n = 0; n < p.parts[k].num_nodes(); ++n)
      owned[n] = p.parts[k].owns(n);
    b.set_counted_nodes(owned);
    copy_whole_into_part(whole, b, p.parts[k], k == 0);
  }
  return p;
}

// A record of the earlier format (part_restart.h kPartsRecordVersion), as the builds before
// per-part records wrote it for this body: what restart files of that time hold.
std::vector<double> earlier_format_record(const Body& whole)
{
  const int nn = whole.num_nodes(), ne = whole.mesh().num_elems();
  const Body::Accounts a = whole.accounts();
  std::vector<double> rec = {kPartsRecordVersion, double(nn), double(ne), a.time,
                             a.external,          a.contact,  a.boundary, a.shield_work,
                             a.shield_hits};
  for (int n = 0; n < nn; ++n) {
    rec.insert(rec.end(), &whole.positions()[3 * n], &whole.positions()[3 * n] + 3);
    rec.insert(rec.end(), &whole.velocities()[3 * n], &whole.velocities()[3 * n] + 3);
  }
  for (int e = 0; e < ne; ++e) {
    const int size = whole.element_record_size(e);
    rec.push_back(size);
    rec.resize(rec.size() + size);
    whole.pack_element(e, rec.data() + rec.size() - size);
  }
  return rec;
}

} // namespace

// A record of the earlier format of a moving body, read by a whole body and by four parts:
// every node's position and velocity as the original's, and the accounts taken once.
TEST(PartRestart, EarlierFormatIsReadByTheWholeBodyAndByParts)
{
  const Body whole = moving_body();
  const std::vector<double> record = earlier_format_record(whole);

  Body again;
  again.build(block(), fracdem_test::steel(), false);
  unpack_parts_record(record.data(), again, nullptr, true);
  EXPECT_EQ(again.positions(), whole.positions());
  EXPECT_EQ(again.velocities(), whole.velocities());
  EXPECT_EQ(again.time(), whole.time());
  EXPECT_DOUBLE_EQ(again.external_work(), whole.external_work());

  const Parts four = split_into(whole, 4);
  double external = 0;
  for (size_t k = 0; k < four.parts.size(); ++k) {
    Body b;
    b.build(four.parts[k].mesh, fracdem_test::steel(), false);
    unpack_parts_record(record.data(), b, &four.parts[k], k == 0);
    for (int n = 0; n < b.num_nodes(); ++n)
      for (int d = 0; d < 3; ++d) {
        const int g = four.parts[k].global_node[n];
        EXPECT_EQ(b.positions()[3 * n + d], whole.positions()[3 * g + d]);
        EXPECT_EQ(b.velocities()[3 * n + d], whole.velocities()[3 * g + d]);
      }
    EXPECT_EQ(b.time(), whole.time());
    external += b.external_work();
  }
  EXPECT_DOUBLE_EQ(external, whole.external_work()); // taken by one part only
}

// Such a record read by a body of another mesh is refused.
TEST(PartRestart, EarlierFormatOfAnotherMeshIsRefused)
{
  const std::vector<double> record = earlier_format_record(moving_body());
  Body other;
  other.build(make_box_tet_mesh(2, 2, 2, 0.4, 0.3, 0.2), fracdem_test::steel(), false);
  EXPECT_THROW(unpack_parts_record(record.data(), other, nullptr, true), std::runtime_error);
}

// A broken body (a node split, an edge cut, an element eroded) scattered into parts with its
// state (part_message_with_state) and gathered back (pack_part_whole, merge_part_wholes,
// restore_gathered) is the same body: its restart record and every node's whole state
// (forces included) bit for bit, at 1 to 4 parts.
TEST(PartRestart, BrokenBodyScatteredAndGatheredIsTheSameBody)
{
  Body whole = moving_body();
  const Mesh& mesh = whole.mesh();
  const int u = mesh.conn[0][0], w = mesh.conn[0][1];
  whole.bisect_edge(u, w, 0.4);
  const double n[3] = {1, 0, 0};
  int splits = 0;
  for (int node = 0; node < whole.num_nodes() && splits < 2; ++node) {
    const SplitPlan plan = whole.plan_split(node, n);
    if (!plan.splittable()) continue;
    whole.split_node(plan);
    ++splits;
  }
  ASSERT_EQ(splits, 2);
  whole.erode({3});
  std::vector<double> expect;
  whole.pack_state(expect);
  const PartTopology topo = whole_topology(whole);
  const std::vector<double> no_surface = {0.0, 0.0};
  for (int nparts = 1; nparts <= 4; ++nparts) {
    std::vector<int> elem_part = partition_elements(whole.mesh(), nparts);
    elem_part[3] = 0; // the eroded element stays with a part
    std::vector<double> all;
    for (int k = 0; k < nparts; ++k) {
      const std::vector<double> message =
          part_message_with_state(whole, topo, elem_part, no_surface, k);
      std::size_t at = 2;
      const MeshPart part = unpack_part(message, at);
      unpack_surface(message, at);
      Body b;
      b.build(part.mesh, fracdem_test::steel(), false);
      std::vector<std::uint8_t> owned(part.num_nodes());
      for (int i = 0; i < part.num_nodes(); ++i)
        owned[i] = part.owns(i);
      b.set_counted_nodes(owned);
      PartTopology mine;
      unpack_part_message_state(message, at, b, part, mine);
      const std::vector<double> sent = pack_part_whole(b, part, mine);
      all.insert(all.end(), sent.begin(), sent.end());
    }
    const GatheredBody g = merge_part_wholes(all, whole.num_nodes(), whole.mesh().num_elems(),
                                             whole.mesh_elements(), false);
    Body back;
    back.build(block(), fracdem_test::steel(), false);
    restore_gathered(g, back);
    std::vector<double> got;
    back.pack_state(got);
    EXPECT_EQ(got, expect) << nparts << " parts";
    double a[Body::kNodeRecordSize], b[Body::kNodeRecordSize];
    for (int i = 0; i < whole.num_nodes(); ++i) {
      whole.pack_node(i, a);
      back.pack_node(i, b);
      for (int k = 0; k < Body::kNodeRecordSize; ++k)
        ASSERT_EQ(a[k], b[k]) << "node " << i << " value " << k << ", " << nparts << " parts";
    }
  }
}

namespace
{

// A body with a split node pair, a cut edge and an eroded element (the broken body above).
Body broken_body()
{
  Body whole = moving_body();
  const Mesh& mesh = whole.mesh();
  whole.bisect_edge(mesh.conn[0][0], mesh.conn[0][1], 0.4);
  const double n[3] = {1, 0, 0};
  for (int node = 0, splits = 0; node < whole.num_nodes() && splits < 2; ++node) {
    const SplitPlan plan = whole.plan_split(node, n);
    if (!plan.splittable()) continue;
    whole.split_node(plan);
    ++splits;
  }
  whole.erode({3});
  return whole;
}

// Part k of `whole` under elem_part, as a distributed run holds it after a change (or, with
// fresh_topology, as set-up leaves an intact body's part: no topology fields).
struct HeldPart {
  MeshPart part;
  Body body;
  PartTopology topo;
};
void take_part(const Body& whole, const PartTopology& whole_topo, const std::vector<int>& elem_part,
               int k, HeldPart& h)
{
  const std::vector<double> message =
      part_message_with_state(whole, whole_topo, elem_part, {0.0, 0.0}, k);
  std::size_t at = 2;
  h.part = unpack_part(message, at);
  unpack_surface(message, at);
  h.body.build(h.part.mesh, fracdem_test::steel(), false);
  std::vector<std::uint8_t> owned(h.part.num_nodes());
  for (int i = 0; i < h.part.num_nodes(); ++i)
    owned[i] = h.part.owns(i);
  h.body.set_counted_nodes(owned);
  unpack_part_message_state(message, at, h.body, h.part, h.topo);
}

void expect_same_part(const HeldPart& a, const HeldPart& b, const std::string& what)
{
  ASSERT_EQ(a.part.global_node, b.part.global_node) << what;
  ASSERT_EQ(a.part.global_elem, b.part.global_elem) << what;
  double x[Body::kNodeRecordSize], y[Body::kNodeRecordSize];
  for (int n = 0; n < a.part.num_nodes(); ++n) {
    a.body.pack_node(n, x);
    b.body.pack_node(n, y);
    for (int k = 0; k < Body::kNodeRecordSize; ++k)
      ASSERT_EQ(x[k], y[k]) << what << ": node " << n << " value " << k;
  }
  for (int e = 0; e < a.body.mesh().num_elems(); ++e) {
    std::vector<double> u(a.body.element_record_size(e)), v(b.body.element_record_size(e));
    a.body.pack_element(e, u.data());
    b.body.pack_element(e, v.data());
    ASSERT_EQ(u, v) << what << ": element " << e;
    ASSERT_EQ(a.body.mesh().active[e], b.body.mesh().active[e]) << what;
  }
  const Body::Accounts p = a.body.accounts(), q = b.body.accounts();
  EXPECT_EQ(std::vector<double>({p.time, p.external, p.contact, p.boundary, p.shield_work}),
            std::vector<double>({q.time, q.external, q.contact, q.boundary, q.shield_work}))
      << what;
  EXPECT_EQ(a.body.outputs().strain_energy, b.body.outputs().strain_energy) << what;
  EXPECT_EQ(a.body.outputs().eroded.mass, b.body.outputs().eroded.mass) << what;
  EXPECT_EQ(a.topo.node_parent, b.topo.node_parent) << what;
  EXPECT_EQ(a.topo.cut_u, b.topo.cut_u) << what;
  EXPECT_EQ(a.topo.elem_parent, b.topo.elem_parent) << what;
  EXPECT_EQ(a.topo.node_split, b.topo.node_split) << what;
  EXPECT_EQ(a.topo.elem_fragment, b.topo.elem_fragment) << what;
  EXPECT_EQ(a.topo.cut, b.topo.cut) << what;
}

} // namespace

// Three parts of an intact and of a broken moving body, each with its own accounts and a shared
// node whose held contact force differs from its owner's, written as per-part records (blocks
// in any order): read back at the same count (the whole body restored from the records, each
// part taken with the stored partition, then its own state) every part is the part it was, bit
// for bit; merged (another count) they give the whole body's restart record bit for bit.
TEST(PartRestart, PartRecordsGiveEachPartBackAtTheSameCountAndTheWholeBodyAtAnother)
{
  for (const bool broken : {false, true}) {
    Body whole = broken ? broken_body() : moving_body();
    const std::string what = broken ? "broken body" : "intact body";
    const PartTopology whole_topo = whole_topology(whole);
    std::vector<int> elem_part = partition_elements(whole.mesh(), 3);
    if (broken) elem_part[3] = 1; // the eroded element stays with a part
    std::vector<HeldPart> held(3);
    std::vector<double> blocks;
    for (int k = 2; k >= 0; --k) { // blocks in any order
      HeldPart& h = held[k];
      take_part(whole, whole_topo, elem_part, k, h);
      if (!broken) h.topo.reset(h.part.num_nodes(), h.body.mesh().num_elems());
      Body::Accounts a = h.body.accounts();
      a.external = 0.25 * (k + 1);
      a.contact = -0.5 * k;
      h.body.set_accounts(a);
      for (int n = 0; n < h.part.num_nodes(); ++n)
        if (!h.part.owns(n)) { // its own bits at one node that another part owns
          double rec[Body::kNodeRecordSize];
          h.body.pack_node(n, rec);
          rec[12] += 1.0; // held contact force, x
          h.body.unpack_node(n, rec);
          break;
        }
      const std::vector<double> mine = pack_part_record(h.body, h.part, h.topo);
      blocks.insert(blocks.end(), mine.begin(), mine.end());
    }
    const double driver[kDriverValues] = {1, 4, 2, 2};
    const std::vector<double> record =
        join_part_records(blocks, 3, whole.num_nodes(), whole.mesh().num_elems(), driver);
    ASSERT_EQ(record[0], kPartRecordsVersion);
    const PartRecords r = read_part_records(record.data());
    EXPECT_EQ(r.elem_part, elem_part) << what;
    EXPECT_EQ(std::vector<double>(r.driver, r.driver + kDriverValues),
              std::vector<double>(driver, driver + kDriverValues));

    const GatheredBody g =
        merge_part_wholes(gathered_wholes(r), whole.num_nodes(), whole.mesh().num_elems(),
                          whole.mesh_elements(), false);
    Body merged;
    merged.build(block(), fracdem_test::steel(), false);
    restore_gathered(g, merged);
    Body::Accounts sum = whole.accounts(); // the parts' accounts, summed in part order
    sum.external = 0.25 + 0.5 + 0.75;
    sum.contact = -0.5 - 1.0;
    whole.set_accounts(sum);
    std::vector<double> expect, got;
    whole.pack_state(expect);
    merged.pack_state(got);
    EXPECT_EQ(got, expect) << what << ": merged record";
    const PartTopology merged_topo = whole_topology(merged);
    double external = 0;
    for (int k = 0; k < 3; ++k) {
      HeldPart back;
      take_part(merged, merged_topo, r.elem_part, k, back);
      restore_own_part(r, back.body, back.part, back.topo);
      expect_same_part(held[k], back, what + ", part " + std::to_string(k));
      external += back.body.accounts().external;
    }
    EXPECT_EQ(external, 0.25 + 0.5 + 0.75) << what;
  }
}

// A record without one part's block is refused, as is a block read into another part.
TEST(PartRestart, PartRecordsWithoutAPartOrReadIntoAnotherPartAreRefused)
{
  const Body whole = moving_body();
  const PartTopology topo = whole_topology(whole);
  const std::vector<int> elem_part = partition_elements(whole.mesh(), 2);
  HeldPart a, b;
  take_part(whole, topo, elem_part, 0, a);
  take_part(whole, topo, elem_part, 1, b);
  const double driver[kDriverValues] = {0, 0, 1, 1};
  const std::vector<double> first = pack_part_record(a.body, a.part, a.topo);
  EXPECT_THROW(join_part_records(first, 2, whole.num_nodes(), whole.mesh().num_elems(), driver),
               std::runtime_error);
  std::vector<double> both = first;
  const std::vector<double> second = pack_part_record(b.body, b.part, b.topo);
  both.insert(both.end(), second.begin(), second.end());
  const std::vector<double> record =
      join_part_records(both, 2, whole.num_nodes(), whole.mesh().num_elems(), driver);
  const PartRecords r = read_part_records(record.data());
  MeshPart wrong = b.part;
  wrong.part = 0; // part 1's nodes read as part 0's block
  EXPECT_THROW(restore_own_part(r, b.body, wrong, b.topo), std::runtime_error);
}

// Unit tests of the fracture check's forecast (fracture/crack_forecast.h): the dry run of a crack
// point agrees with insert_cracks, and the parts of a distributed body never miss a change.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <functional>

#include "body/body_driver.h"
#include "body/body_setup.h"
#include "body/part_restart.h"
#include "fracture/crack_forecast.h"
#include "fracture/nodal_fracture.h"
#include "io/gmsh_reader.h"
#include "io/mesh_generators.h"
#include "test_support.h"

using namespace fracdem;

namespace
{

// Steps a driver of `keywords` (a body of `dimension`) as a host does, to step `last`; `probe`
// (optional) gets the body after every step.
void run_body(const std::string& keywords, int dimension, double dt, int last,
              const std::function<void(const Body&, int)>& probe, Body* out = nullptr)
{
  BodySpec spec = parse_body_spec(fracdem_test::split(keywords));
  check_body_spec(spec, {}, dimension, dimension);
  BodyHost host = serial_host();
  host.print = [](const std::string&, bool, bool) {};
  BodyDriver driver;
  driver.attach(spec, "b", host);
  driver.build(dimension);
  driver.start_run();
  driver.compute_forces(nullptr, 0, dt, false);
  for (int step = 1; step <= last; ++step) {
    driver.begin_step(dt);
    driver.compute_forces(nullptr, step, dt, true);
    driver.end_step(step, dt);
    if (probe) probe(driver.body(), step);
  }
  if (out) *out = driver.body();
}

// The rankine bar of test_body_driver (40 x 10 tri3 cells, pulled at xmax) run for `steps` steps
// without fracture checks: a body with crack points, none split yet.
class CrackForecastTest : public fracdem_test::TempDirTest
{
protected:
  Body failed_bar(int steps)
  {
    write_gmsh22(make_rect_mesh(40, 10, 0.2, 0.05, {0, 0}, ElemType::Tri3),
                 (dir_ / "bar.msh").string());
    Body body;
    run_body("file " + (dir_ / "bar.msh").string() +
                 " type 2 density 2400 youngs 30e9 poisson 0.2 plane stress thickness 0.05 "
                 "material rankine strength 3e6 fracture_energy 100 fixed xmin x fixed ymin y "
                 "prescribed_velocity xmax 0.1 0 0 ramp 1e-4 fracture nodal every 100000",
             2, 5e-7, steps, nullptr, &body);
    return body;
  }
};

std::vector<int> points(const Body& body)
{
  FailureMap map;
  build_failure_map(body, map);
  return crack_points(body.mesh(), map);
}

// Whether insert_cracks changes anything when it comes to v alone.
bool splits_alone(const Body& body, int v, double min_size)
{
  Body copy = body;
  std::vector<CutEvent> cuts;
  const std::vector<SplitEvent> events = insert_cracks(copy, {v}, min_size, &cuts);
  return !cuts.empty() || std::any_of(events.begin(), events.end(),
                                      [v](const SplitEvent& ev) { return ev.node == v; });
}

// Part k of `whole` (3 parts) with its state and topology as a distributed run holds it after a
// change, its failed elements those of the whole body.
Body part_of(const Body& whole, const std::vector<int>& elem_part, int k, MeshPart& part,
             PartTopology& topo)
{
  const std::vector<double> message =
      part_message_with_state(whole, whole_topology(whole), elem_part, {0.0, 0.0}, k);
  std::size_t at = 2;
  part = unpack_part(message, at);
  unpack_surface(message, at);
  Body b;
  b.build(part.mesh, whole.material(), false);
  unpack_part_message_state(message, at, b, part, topo);
  const std::vector<int> local = local_of_global(part.global_elem, whole.mesh().num_elems());
  std::vector<int> failed;
  for (int e : *whole.failed_elements())
    if (local[e] >= 0) failed.push_back(local[e]);
  b.set_damage(whole.damaged_points(), failed);
  return b;
}

} // namespace

// The torn bar of test_distributed_fracture (in.fracture_cut_3d's Rankine tet4 bar, 16 x 4 x 4
// sheared Kuhn cells, 1536 tets), its halves thrown apart at 5 m/s, `fracture nodal every 5`
// (min_size: cuts through tets), stepped to `last`; at every third step from `first` on, `probe`
// gets the body (as it is between checks: cracked in part, some points waiting).
void torn_bar(const std::filesystem::path& dir, double min_size, int first, int last,
              const std::function<void(const Body&, int)>& probe)
{
  Mesh mesh = make_box_tet_mesh(16, 4, 4, 0.16, 0.04, 0.04);
  auto& left = mesh.node_sets["left"];
  auto& right = mesh.node_sets["right"];
  for (int n = 0; n < mesh.num_nodes(); ++n) {
    const double s = mesh.X[3 * n]; // the side in the unsheared frame
    mesh.X[3 * n] += 0.5 * mesh.X[3 * n + 1];
    if (s < 0.08 - 1e-9) left.push_back(n);
    if (s > 0.08 + 1e-9) right.push_back(n);
  }
  write_gmsh22(mesh, (dir / "bar3d.msh").string());
  std::string keywords = "file " + (dir / "bar3d.msh").string() +
                         " type 2 density 2400 youngs 30e9 poisson 0.2 material rankine strength "
                         "3e6 fracture_energy 100 velocity left -5 0 0 velocity right 5 0 0 "
                         "fracture nodal every 5";
  if (min_size > 0) keywords += " min_size " + std::to_string(min_size);
  run_body(keywords + " contact_bodies no", 3, 2e-7, last, [&](const Body& body, int step) {
    if (step >= first && step % 3 == 0) probe(body, step);
  });
}

// Whether the dry run at every crack point of `body` says "may split" exactly where insert_cracks,
// coming to the point first, splits or cuts it (it is then a superset too); returns the points
// where it does.
int dry_run_agrees(const Body& body, double min_size)
{
  const CrackNodes nodes = whole_crack_nodes(body, min_size);
  const auto fraction = [&body](int e) { return body.piece_fraction(e); };
  int yes = 0;
  for (int v : points(body)) {
    const bool may = crack_point_may_split(body, v, nodes.on_crack, min_size, fraction);
    EXPECT_EQ(may, splits_alone(body, v, min_size)) << "point " << v << " min_size " << min_size;
    yes += may;
  }
  return yes;
}

// Before the first check, after a check on every other crack point (the band of a split point
// then cracked; some points on one side of their plane), and after a check of all of them, at two
// stages of the bar's cracking, with and without cuts through elements (min_size 0.2): the dry run
// agrees with insert_cracks at every crack point; after the full check it says "no" at every
// point split and every copy.
TEST_F(CrackForecastTest, DryRunAgreesWithInsertCracks)
{
  for (int steps : {1300, 1500})
    for (double min_size : {0.0, 0.2}) {
      SCOPED_TRACE(::testing::Message() << steps << " steps, min_size " << min_size);
      Body whole = failed_bar(steps);
      const std::vector<int> pts = points(whole);
      ASSERT_GT(pts.size(), 10u);
      const int fresh = dry_run_agrees(whole, min_size);
      EXPECT_GT(fresh, 0);
      std::vector<int> half;
      for (size_t k = 0; k < pts.size(); k += 2)
        half.push_back(pts[k]);
      Body partly = whole;
      insert_cracks(partly, half, min_size);
      dry_run_agrees(partly, min_size);
      std::vector<CutEvent> cuts;
      const std::vector<SplitEvent> events = insert_cracks(whole, pts, min_size, &cuts);
      ASSERT_FALSE(events.empty());
      const CrackNodes after = whole_crack_nodes(whole, min_size);
      for (const SplitEvent& ev : events) {
        EXPECT_FALSE(crack_point_may_split(whole, ev.node, after.on_crack, min_size))
            << "split point " << ev.node;
        EXPECT_FALSE(crack_point_may_split(whole, ev.copy, after.on_crack, min_size))
            << "copy " << ev.copy;
      }
      dry_run_agrees(whole, min_size);
    }
}

// Three parts of the body, before and after its check: whenever the check on the whole body
// (insert_cracks on every crack point, then the erosion of collapsed failed elements) changes it,
// some part says it may change; after the check, which decided every point, the whole body says
// no, and so does a part whose crack points are all its own.
TEST_F(CrackForecastTest, PartsNeverMissAChangeOfTheWholeCheck)
{
  Body whole = failed_bar(1500);
  FractureCheckRule rule;
  rule.dt = 5e-7;
  const auto check_changes = [&](const Body& body) {
    Body copy = body;
    const bool split = !insert_cracks(copy, points(copy), 0).empty();
    bool erodes = false;
    for (int e : *copy.failed_elements())
      erodes |= copy.mesh().active[e] && copy.element_time_step(e) < rule.dt;
    return split || erodes;
  };
  const auto parts_say = [&](const Body& body, int& own_and_no) {
    const std::vector<int> elem_part = partition_elements(body.mesh(), 3);
    bool any = false;
    own_and_no = 0;
    for (int k = 0; k < 3; ++k) {
      MeshPart part;
      PartTopology topo;
      const Body b = part_of(body, elem_part, k, part, topo);
      const bool may = check_may_change(b, part_crack_nodes(part, topo, 0), rule);
      any |= may;
      bool own = true;
      for (int e : *b.failed_elements())
        for (int a = 0; a < nodes_per_elem(b.mesh().etype[e]); ++a)
          own &= !part.shared(b.mesh().conn[e][a]);
      own_and_no += own && !may;
    }
    return any;
  };
  int quiet = 0;
  ASSERT_TRUE(check_changes(whole));
  EXPECT_TRUE(parts_say(whole, quiet));
  EXPECT_TRUE(check_may_change(whole, whole_crack_nodes(whole, 0), rule));
  insert_cracks(whole, points(whole), 0);
  ASSERT_FALSE(check_changes(whole)); // the check decided every point
  parts_say(whole, quiet);
  EXPECT_FALSE(check_may_change(whole, whole_crack_nodes(whole, 0), rule));
  EXPECT_GT(quiet, 0); // a part with its own crack points only: no gather needed
  FacePieces pieces;
  EXPECT_FALSE(pinch_may_separate(whole, pieces));
}

// Through the cracking of the torn bar (its splits at steps 50, 160 and 165, cuts with
// min_size 0.2), at every third step between its checks: the dry run agrees with insert_cracks at
// every crack point, with crack bands already split, points on one side of their plane and
// points held back while the opening still carries tension; and whenever the whole check would
// change the body, one of three parts of it says it may (the parts split by METIS, not keeping
// crack clusters whole: some quiet steps all the same), each deciding its own crack points as the
// whole body does.
TEST_F(CrackForecastTest, TornBarDryRunAgreesThroughItsCracking)
{
  for (double min_size : {0.0, 0.2}) {
    int yes = 0, points_seen = 0, changes = 0, parts_quiet = 0;
    FractureCheckRule rule;
    rule.min_size = min_size;
    rule.dt = 2e-7;
    torn_bar(dir_, min_size, 40, 200, [&](const Body& body, int step) {
      SCOPED_TRACE(::testing::Message() << "step " << step << ", min_size " << min_size);
      points_seen += static_cast<int>(points(body).size());
      yes += dry_run_agrees(body, min_size);
      // The whole check (crack_body: splits and cuts, then the collapsed failed elements eroded)
      // against three parts' forecasts.
      Body copy = body;
      std::vector<CutEvent> cuts;
      bool changed = !insert_cracks(copy, points(copy), min_size, &cuts).empty() || !cuts.empty();
      for (int e : *copy.failed_elements())
        changed |= copy.mesh().active[e] && copy.element_time_step(e) < rule.dt;
      const std::vector<int> elem_part = partition_elements(body.mesh(), 3);
      const CrackNodes whole_nodes = whole_crack_nodes(body, min_size);
      const auto fraction = [&body](int e) { return body.piece_fraction(e); };
      bool may = false;
      for (int k = 0; k < 3; ++k) {
        MeshPart part;
        PartTopology topo;
        const Body b = part_of(body, elem_part, k, part, topo);
        const CrackNodes nodes = part_crack_nodes(part, topo, min_size);
        may |= check_may_change(b, nodes, rule);
        // A point of the part's own: the same answer as on the whole body (with cuts a superset:
        // the part takes 1 for the pieces' fractions).
        for (int v : points(b)) {
          if (part.shared(v)) continue;
          const int g = part.global_node[v];
          const bool mine = crack_point_may_split(b, v, nodes.on_crack, min_size);
          const bool theirs =
              crack_point_may_split(body, g, whole_nodes.on_crack, min_size, fraction);
          if (min_size > 0)
            EXPECT_TRUE(mine || !theirs) << "node " << g;
          else
            EXPECT_EQ(mine, theirs) << "node " << g;
        }
      }
      EXPECT_TRUE(may || !changed);
      changes += changed;
      parts_quiet += !may;
    });
    EXPECT_GT(points_seen, 1000);
    EXPECT_GT(yes, 0);
    EXPECT_GT(changes, 0);
    EXPECT_GT(parts_quiet, 0) << "the parts never rule a change out";
  }
}

// Unit tests of the fracture check as plan and apply (fracture/fracture_plan.h): planning leaves the
// body alone, an applied plan decides every point, and the parts of a distributed body never miss
// a change of the whole body's check.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <functional>

#include "body/body_driver.h"
#include "body/body_setup.h"
#include "body/part_restart.h"
#include "fracture/fracture_plan.h"
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


// The plan of `points` on `body` (a whole body; erosion with rule), or on a part with its marks.
FracturePlan plan_of(const Body& body, const std::vector<int>& points, const FractureCheckRule& rule,
                     const CrackNodes* part = nullptr)
{
  FracturePlanInput in;
  in.points = points;
  in.rule = rule;
  in.part = part;
  if (part) in.fraction = [](int) { return 1.0; };
  FailureMap map;
  build_failure_map(body, map);
  in.failed = map.failed;
  return plan_fracture(body, in);
}

// Whether a plan cuts or splits at crack point v (or cannot decide it).
bool acts_at(const FracturePlan& plan, int v)
{
  for (const FractureStep& s : plan.steps)
    if (s.node == v && s.kind != FractureStep::Kind::Part && s.kind != FractureStep::Kind::Erode)
      return true;
  return false;
}

// Everything a plan could change in a body, compared.
void expect_same_body(const Body& a, const Body& b)
{
  ASSERT_EQ(a.num_nodes(), b.num_nodes());
  ASSERT_EQ(a.mesh().num_elems(), b.mesh().num_elems());
  EXPECT_EQ(a.positions(), b.positions());
  EXPECT_EQ(a.velocities(), b.velocities());
  EXPECT_EQ(a.masses(), b.masses());
  EXPECT_EQ(a.mesh().conn, b.mesh().conn);
  EXPECT_EQ(a.mesh().active, b.mesh().active);
  EXPECT_EQ(a.material_state(), b.material_state());
  EXPECT_EQ(a.parents(), b.parents());
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

// The rankine bar at two stages of its cracking, with and without cuts (min_size 0.2): planning
// leaves the body as it was; the plan applied to a copy makes the changes insert_cracks makes one
// point at a time (the same splits and cuts); and a plan made again on the result has nothing left
// to do at any crack point (the check decided every one).
TEST_F(CrackForecastTest, PlanLeavesTheBodyAndDecidesEveryPoint)
{
  for (int steps : {1300, 1500})
    for (double min_size : {0.0, 0.2}) {
      SCOPED_TRACE(::testing::Message() << steps << " steps, min_size " << min_size);
      const Body whole = failed_bar(steps);
      const std::vector<int> pts = points(whole);
      ASSERT_GT(pts.size(), 10u);
      FractureCheckRule rule;
      rule.min_size = min_size;
      rule.erode = false;
      const Body before = whole;
      const FracturePlan plan = plan_of(whole, pts, rule);
      expect_same_body(whole, before);
      ASSERT_FALSE(plan.empty());
      Body applied = whole;
      const FractureOutcome out = apply_fracture_plan(applied, plan);
      EXPECT_TRUE(out.changed());
      Body stepwise = whole; // point by point, each on the body the earlier ones left
      for (int v : pts)
        insert_cracks(stepwise, {v}, min_size);
      EXPECT_EQ(applied.num_nodes(), stepwise.num_nodes());
      EXPECT_EQ(applied.mesh().num_elems(), stepwise.mesh().num_elems());
      const FracturePlan again = plan_of(applied, points(applied), rule);
      for (int v : points(applied))
        EXPECT_FALSE(acts_at(again, v)) << "point " << v;
    }
}

// Three parts of the body, before and after its check: whenever the check on the whole body
// changes it, some part's plan is not empty; after the check, which decided every point, the whole
// body's plan is empty, and so is the plan of a part whose crack points are all its own.
TEST_F(CrackForecastTest, PartsNeverMissAChangeOfTheWholeCheck)
{
  Body whole = failed_bar(1500);
  FractureCheckRule rule;
  rule.dt = 5e-7;
  const auto parts_say = [&](const Body& body, int& own_and_no) {
    const std::vector<int> elem_part = partition_elements(body.mesh(), 3);
    bool any = false;
    own_and_no = 0;
    for (int k = 0; k < 3; ++k) {
      MeshPart part;
      PartTopology topo;
      const Body b = part_of(body, elem_part, k, part, topo);
      const CrackNodes nodes = part_crack_nodes(part, topo, 0);
      const bool may = !plan_of(b, points(b), rule, &nodes).empty();
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
  ASSERT_FALSE(plan_of(whole, points(whole), rule).empty());
  EXPECT_TRUE(parts_say(whole, quiet));
  apply_fracture_plan(whole, plan_of(whole, points(whole), rule));
  const FracturePlan after = plan_of(whole, points(whole), rule);
  EXPECT_TRUE(after.empty()) << after.steps.size() << " steps left";
  parts_say(whole, quiet);
  EXPECT_GT(quiet, 0); // a part with its own crack points only: no gather needed
  FacePieces pieces;
  EXPECT_FALSE(pinch_may_separate(whole, pieces));
}

// Through the cracking of the torn bar (its splits at steps 50, 160 and 165, cuts with
// min_size 0.2), at every third step between its checks: planning leaves the body alone; whenever
// the whole check would change the body, one of three parts' plans is not empty (the parts split
// by METIS, not keeping crack clusters whole: some quiet steps all the same); and a crack point of
// a part's own gets the same answer as on the whole body (with cuts a superset: the part takes 1
// for the pieces' fractions).
TEST_F(CrackForecastTest, TornBarPartsAgreeWithTheWholeThroughItsCracking)
{
  for (double min_size : {0.0, 0.2}) {
    int points_seen = 0, changes = 0, parts_quiet = 0, own_points = 0;
    FractureCheckRule rule;
    rule.min_size = min_size;
    rule.dt = 2e-7;
    torn_bar(dir_, min_size, 40, 200, [&](const Body& body, int step) {
      SCOPED_TRACE(::testing::Message() << "step " << step << ", min_size " << min_size);
      points_seen += static_cast<int>(points(body).size());
      const Body before = body;
      const bool changed = !plan_of(body, points(body), rule).empty();
      expect_same_body(body, before);
      const std::vector<int> elem_part = partition_elements(body.mesh(), 3);
      FractureCheckRule point_rule = rule;
      point_rule.erode = false;
      bool may = false;
      for (int k = 0; k < 3; ++k) {
        MeshPart part;
        PartTopology topo;
        const Body b = part_of(body, elem_part, k, part, topo);
        const CrackNodes nodes = part_crack_nodes(part, topo, min_size);
        may |= !plan_of(b, points(b), rule, &nodes).empty();
        for (int v : points(b)) {
          if (part.shared(v)) continue;
          const int g = part.global_node[v];
          const bool mine = !plan_of(b, {v}, point_rule, &nodes).empty();
          const bool theirs = acts_at(plan_of(body, {g}, point_rule), g);
          ++own_points;
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
    EXPECT_GT(own_points, 100);
    EXPECT_GT(changes, 0);
    EXPECT_GT(parts_quiet, 0) << "the parts never rule a change out";
  }
}

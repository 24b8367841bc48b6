// Unit tests of BodyDriver: the step of a breaking / eroding body without a host (one rank).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "body/body_driver.h"
#include "body/body_fields.h"
#include "body/body_setup.h"
#include "io/gmsh_reader.h"
#include "io/mesh_generators.h"
#include "test_support.h"

using namespace fracdem;

namespace
{

using fracdem_test::split;

// The rankine bar of tests/integration/in.fracture_bar (40 x 10 tri3 cells, 0.2 x 0.05 m, plane
// stress 0.05 m thick), pulled at xmax; time step 5e-7 s.
const char* const kBar =
    "type 2 density 2400 youngs 30e9 poisson 0.2 plane stress thickness 0.05 material rankine "
    "strength 3e6 fracture_energy 100 fixed xmin x fixed ymin y prescribed_velocity xmax 0.1 0 0 "
    "ramp 1e-4 fracture nodal every 5";
constexpr double kDt = 5e-7;

// A driver on one rank whose output lines are kept with where they went.
class DriverTest : public fracdem_test::TempDirTest
{
protected:
  struct Line {
    std::string text;
    bool screen, logfile;
  };
  void make(const std::string& mesh, const std::string& keywords, int dimension)
  {
    spec_ = parse_body_spec(split("file " + (dir_ / mesh).string() + " " + keywords));
    check_body_spec(spec_, {}, 2, dimension);
    BodyHost host = serial_host();
    host.print = [this](const std::string& s, bool screen, bool logfile) {
      lines_.push_back({s, screen, logfile});
    };
    host.warning = [this](const std::string& s) { warnings_.push_back(s); };
    driver_.attach(spec_, "b", host);
    driver_.build(dimension);
  }
  void make_bar(const std::string& extra = "")
  {
    write_gmsh22(make_rect_mesh(40, 10, 0.2, 0.05, {0, 0}, ElemType::Tri3),
                 (dir_ / "bar.msh").string());
    make("bar.msh", std::string(kBar) + extra, 2);
  }
  // Runs steps [first, last] as a host does (set-up evaluation first when first == 1).
  void run(int first, int last, double dt)
  {
    if (first == 1) {
      driver_.start_run();
      driver_.compute_forces(nullptr, 0, dt, false);
      driver_.write_energy_row_if_due(0);
    }
    for (int step = first; step <= last; ++step) {
      driver_.begin_step(dt);
      driver_.compute_forces(nullptr, step, dt, true);
      driver_.end_step(step, dt);
    }
  }
  int count_lines(const std::string& part) const
  {
    int n = 0;
    for (const Line& l : lines_)
      n += l.text.find(part) != std::string::npos;
    return n;
  }

  BodySpec spec_;
  BodyDriver driver_;
  std::vector<Line> lines_;
  std::vector<std::string> warnings_;
};

} // namespace

// The bar breaks once across (two fragments, every node of a mesh column split), its energy
// balance closes, and the crack is logged: every split in the log file, the fragments once.
TEST_F(DriverTest, RankineBarBreaksAcrossWithItsEnergyBalanced)
{
  make_bar();
  EXPECT_EQ(driver_.describe(), "fix fem/body b: " + (dir_ / "bar.msh").string() +
                                    ", 451 nodes, 800 elements, 100 boundary facets, deformable "
                                    "small-strain elastic");
  driver_.check_time_step(kDt);
  ASSERT_EQ(count_lines("stable FE time step"), 1);
  run(1, 1500, kDt);
  const Body& body = driver_.body();
  EXPECT_EQ(fragment_count(body), 2);
  EXPECT_EQ(split_node_count(body), 11); // one per node of a mesh column
  const int splits = count_lines(": crack at node ");
  EXPECT_EQ(splits, 11);
  EXPECT_EQ(count_lines(": 2 fragments, masses"), 1);
  // G_f A = 100 * 0.05 * 0.05 = 0.25 J dissipated (crack band), within the 15 % of the
  // integration test; the balance within its 2 %.
  const double dissipated = body.dissipated_energy();
  EXPECT_NEAR(dissipated, 0.25, 0.15 * 0.25);
  const double lhs = body.kinetic_energy() + body.strain_energy() + dissipated;
  EXPECT_NEAR(lhs, body.boundary_work(), 0.02 * body.boundary_work());
  // The vector: the core's entries, 3 reactions per group (xmin, ymin, xmax), then the tail.
  EXPECT_EQ(driver_.vector_size(), kVecSize + 9 + kVecTailSize);
  EXPECT_EQ(driver_.vector_entry(kVecFragments), 2);
  EXPECT_EQ(driver_.vector_entry(kVecSize + 9 + kVecErodedElements), 0);
}

// Stage (ii) takes node values only at the nodes of completely failed elements: the crack points
// must be exactly the nodes whose largest element measure (over all their active elements,
// brute force) is 1, in a bar with failed and partly damaged elements (no splits made yet).
TEST_F(DriverTest, CrackPointsAreTheNodesWhoseLargestElementMeasureIsOne)
{
  write_gmsh22(make_rect_mesh(40, 10, 0.2, 0.05, {0, 0}, ElemType::Tri3),
               (dir_ / "bar.msh").string());
  std::string keywords = kBar;
  keywords.replace(keywords.find("every 5"), 7, "every 100000");
  make("bar.msh", keywords, 2);
  run(1, 1500, kDt);
  const Body& body = driver_.body();
  const Mesh& mesh = body.mesh();
  std::vector<double> largest(body.num_nodes(), 0.0);
  int partly = 0;
  for (int e = 0; e < mesh.num_elems(); ++e) {
    if (!mesh.active[e]) continue;
    double n[3];
    const double m = body.element_failure(e, n);
    partly += m > 0 && m < 1;
    for (int a = 0; a < nodes_per_elem(mesh.etype[e]); ++a)
      largest[mesh.conn[e][a]] = std::max(largest[mesh.conn[e][a]], m);
  }
  std::vector<int> expected;
  for (int v = 0; v < body.num_nodes(); ++v)
    if (largest[v] >= 1.0) expected.push_back(v);
  FailureMap map;
  ASSERT_GT(build_failure_map(body, map), 0);
  EXPECT_GT(partly, 0);
  ASSERT_FALSE(expected.empty());
  EXPECT_EQ(crack_points(mesh, map), expected);
  for (size_t k = 1; k < map.failed.size(); ++k)
    EXPECT_LT(map.failed[k - 1], map.failed[k]);
}

// More than four splits at one check: each in the log file only, their count on the screen.
TEST_F(DriverTest, ManySplitsGoToTheLogFileAndTheirCountToTheScreen)
{
  make_bar();
  run(1, 1500, kDt);
  int screen_splits = 0, log_splits = 0, summaries = 0;
  for (const Line& l : lines_) {
    if (l.text.find(": crack at node ") != std::string::npos) {
      screen_splits += l.screen;
      log_splits += l.logfile;
    }
    if (l.text.find(" node splits (see log)") != std::string::npos) {
      EXPECT_TRUE(l.screen && !l.logfile);
      ++summaries;
    }
  }
  EXPECT_EQ(log_splits, 11);
  // Either every split of a check was on the screen (at most four) or a summary stood for them.
  EXPECT_TRUE(screen_splits == 11 || summaries > 0) << screen_splits << " " << summaries;
}

// Erosion takes an element's strain energy into the erosion account, never its dissipated energy:
// the fracture_energy of a body that erodes its failed elements (here most of them) still counts
// what they dissipated before, and the per-element field of fix fem/vtk adds up to it.
TEST_F(DriverTest, ErodedElementsKeepTheirDissipationInTheFractureEnergy)
{
  make_bar(" erosion damage 0.99");
  run(1, 1500, kDt);
  const Body& body = driver_.body();
  ASSERT_GT(body.eroded().elements, 0);
  std::vector<double> per_element;
  element_dissipation(body, per_element);
  double all = 0, eroded = 0;
  for (int e = 0; e < body.mesh().num_elems(); ++e) {
    all += per_element[e];
    if (!body.mesh().active[e]) eroded += per_element[e];
  }
  EXPECT_NEAR(all, body.dissipated_energy(), 1e-12 * all);
  EXPECT_GT(eroded, 0.5 * all); // the eroded elements did most of the cracking
  // Erosion changes nothing in it: eroding every remaining damaged element keeps the total.
  std::vector<int> rest;
  for (int e = 0; e < body.mesh().num_elems(); ++e)
    if (body.mesh().active[e] && per_element[e] > 0) rest.push_back(e);
  ASSERT_FALSE(rest.empty());
  const double before = body.dissipated_energy();
  driver_.body().erode(rest);
  EXPECT_EQ(body.dissipated_energy(), before);
}

// A restart record of the cracked bar restores it exactly, topology included, in a fresh driver
// (as a host re-creates the fix), and both continue identically.
TEST_F(DriverTest, RestartRecordContinuesTheCrackedBarExactly)
{
  make_bar();
  run(1, 1300, kDt);
  ASSERT_GT(split_node_count(driver_.body()), 0);
  const std::vector<double> record = driver_.restart_record();
  EXPECT_EQ(record[0], -1.0); // the adapter head: marker, length, rigid, transforms
  // (2 doubles) and, as contact_bodies is on for a breaking body, the pieces' contacts if any.
  EXPECT_GE(record[1], 2.0);

  BodyDriver again;
  again.attach(spec_, "b", serial_host());
  again.build(2);
  again.read_restart(record.data());
  EXPECT_TRUE(again.restarted());
  // Both go on as a host's next run does: set-up evaluation, then the steps.
  for (BodyDriver* d : {&driver_, &again}) {
    d->start_run(); // no initial velocities after a restart
    d->compute_forces(nullptr, 1300, kDt, false);
    for (int step = 1301; step <= 1400; ++step) {
      d->begin_step(kDt);
      d->compute_forces(nullptr, step, kDt, true);
      d->end_step(step, kDt);
    }
  }
  ASSERT_EQ(again.body().num_nodes(), driver_.body().num_nodes());
  EXPECT_EQ(again.body().positions(), driver_.body().positions());
  EXPECT_EQ(again.body().velocities(), driver_.body().velocities());
  EXPECT_EQ(again.body().dissipated_energy(), driver_.body().dissipated_energy());
}

// A record of a body placed otherwise is refused with both placements in the message.
TEST_F(DriverTest, RestartRecordOfAnotherPlacementIsRefused)
{
  make_bar(" move 0.01 0 0");
  const std::vector<double> record = driver_.restart_record();
  BodySpec other = parse_body_spec(split("file " + (dir_ / "bar.msh").string() + " " + kBar));
  check_body_spec(other, {}, 2, 2);
  BodyDriver fresh;
  fresh.attach(other, "b", serial_host());
  fresh.build(2);
  try {
    fresh.read_restart(record.data());
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()).rfind("fix fem/body b: the restart file holds this body with "
                                          "'rigid no move 0.01 0 0' but this command gives "
                                          "'rigid no'",
                                          0),
              0u)
        << e.what();
  }
  std::vector<double> corrupt = record;
  corrupt[3] = 7; // more transforms than the head holds
  try {
    driver_.read_restart(corrupt.data());
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "fix fem/body: corrupt restart record");
  }
}

// An element that inverts: a breaking body erodes it (logged) and goes on; an elastic body stops
// with the element and the step named.
TEST_F(DriverTest, InvertedElementIsErodedInABreakingBodyAndStopsAnElasticOne)
{
  make_bar(" dt_check warn"); // the slivers left behind may be below the host step
  run(1, 1, kDt);
  const int node = 4 * 41 + 20; // an inner node, thrown through its neighbours
  const double v[3] = {0, 2e4, 0};
  driver_.body().set_velocity({node}, v);
  run(2, 6, kDt);
  EXPECT_GE(count_lines("inverted (det F <= 0) and was eroded; its nodes keep their mass"), 1);
  EXPECT_GE(driver_.body().eroded().elements, 1);

  write_gmsh22(make_rect_mesh(40, 10, 0.2, 0.05, {0, 0}, ElemType::Tri3),
               (dir_ / "elastic.msh").string());
  BodySpec s = parse_body_spec(split("file " + (dir_ / "elastic.msh").string() +
                                     " type 2 density 2400 youngs 30e9 poisson 0.2 plane stress"));
  check_body_spec(s, {}, 2, 2);
  BodyDriver elastic;
  elastic.attach(s, "e", serial_host());
  elastic.build(2);
  elastic.start_run();
  elastic.compute_forces(nullptr, 0, kDt, false);
  elastic.body().set_velocity({node}, v);
  try {
    for (int step = 1; step <= 5; ++step) {
      elastic.begin_step(kDt);
      elastic.compute_forces(nullptr, step, kDt, true);
      elastic.end_step(step, kDt);
    }
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind("fix fem/body e: element ", 0), 0u) << what;
    EXPECT_NE(what.find(" inverted (det F <= 0) at step "), std::string::npos) << what;
  }
}

// An eroding body logs each batch in one line: causes, the first twelve elements, the totals;
// the energy file has the erosion columns and one row per interval.
TEST_F(DriverTest, ErosionBatchLineAndEnergyFile)
{
  make_bar(" erosion damage 0.99 energy_file " + (dir_ / "e.csv").string() + " 100");
  int counts[kErosionCauses] = {0, 0, 0, 0};
  counts[static_cast<int>(ErosionCause::Damage)] = 13;
  counts[static_cast<int>(ErosionCause::Inverted)] = 1;
  std::vector<int> batch(14);
  for (int k = 0; k < 14; ++k)
    batch[k] = 100 + k;
  const std::string line = driver_.erosion_line(42, counts, batch);
  EXPECT_EQ(line.rfind("fix fem/body b: step 42: eroded 14 elements (", 0), 0u) << line;
  EXPECT_NE(line.find("):"
                      " 100 101 102 103 104 105 106 107 108 109 110 111 ...; 0 eroded in "
                      "all, mass 0 removed, energy 0\n"),
            std::string::npos)
      << line;
  EXPECT_NE(line.find(std::string(erosion_cause_name(ErosionCause::Damage)) + " 13"),
            std::string::npos);

  ASSERT_EQ(driver_.open_energy_file(), "");
  run(1, 1500, kDt);
  std::ifstream in(dir_ / "e.csv");
  std::string header, row;
  std::getline(in, header);
  EXPECT_EQ(header.rfind("step,time,kinetic,strain,external_work,contact_work,total,nodes,"
                         "elements,fracture_energy,split_nodes,fragments,boundary_work,"
                         "eroded_elements,eroded_mass,eroded_energy,reaction_xmin_x",
                         0),
            0u)
      << header;
  int rows = 0;
  while (std::getline(in, row))
    ++rows;
  EXPECT_EQ(rows, 16); // steps 0, 100, ..., 1500
  // Fully cracked elements erode: the batches' counts add up to the account.
  const int logged = count_lines(": eroded ");
  EXPECT_GT(logged, 0);
  EXPECT_EQ(driver_.vector_entry(kVecSize + 9 + kVecErodedElements),
            driver_.body().eroded().elements);
  EXPECT_GT(driver_.body().eroded().elements, 0);
}

// fracture nodal min_size cuts quad4 elements too (issue #9): a quad mesh sets up without the
// note it gave when quads were never cut.
TEST_F(DriverTest, MinSizeOnAQuadMeshNoLongerSaysQuadsAreNotCut)
{
  write_gmsh22(make_rect_mesh(8, 2, 0.2, 0.05, {0, 0}, ElemType::Quad4),
               (dir_ / "quads.msh").string());
  make("quads.msh", std::string(kBar) + " min_size 0.2", 2);
  EXPECT_EQ(count_lines("min_size ignored"), 0);
}

TEST_F(DriverTest, MinSizeOnATriMeshSaysNothingAboutQuads)
{
  make_bar(" min_size 0.2");
  EXPECT_EQ(count_lines("min_size ignored"), 0);
}

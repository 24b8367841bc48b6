// Unit tests of sub-cycling (substeps auto|N|off): the keyword, the choice of n and the
// sub-cycled step of BodyDriver against the same FE steps taken one per host step.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <memory>
#include <string>

#include "body/body_driver.h"
#include "body/body_setup.h"
#include "io/gmsh_reader.h"
#include "io/mesh_generators.h"
#include "test_support.h"

using namespace fracdem;

namespace
{

using fracdem_test::split;

// An elastic steel plate (20 x 5 tri3 cells, 0.2 x 0.05 m, plane stress), clamped at xmin and
// set swinging by an initial velocity of its free end: free vibration, no contact.
const char* const kPlate = "type 2 density 7800 youngs 2e11 poisson 0.3 plane stress thickness "
                           "0.05 fixed xmin velocity xmax 0 3 0";

std::string spec_error(const std::string& keywords, bool check = false)
{
  try {
    BodySpec s = parse_body_spec(split("file m.msh " + keywords));
    if (check) check_body_spec(s, {}, 2, 3);
  } catch (const SpecError& e) {
    return e.what();
  }
  return "";
}

class SubstepTest : public fracdem_test::TempDirTest
{
protected:
  // A driver of the plate with `extra` keywords; its log lines and warnings are kept.
  struct Run {
    BodySpec spec;
    BodyDriver driver;
    std::vector<std::string> lines, warnings;
  };
  std::unique_ptr<Run> make(const std::string& extra)
  {
    const std::string mesh = (dir_ / "plate.msh").string();
    write_gmsh22(make_rect_mesh(20, 5, 0.2, 0.05, {0, 0}, ElemType::Tri3), mesh);
    auto r = std::make_unique<Run>();
    r->spec = parse_body_spec(split("file " + mesh + " " + kPlate + extra));
    check_body_spec(r->spec, {}, 2, 2);
    BodyHost host = serial_host();
    Run* p = r.get();
    host.print = [p](const std::string& s, bool, bool) { p->lines.push_back(s); };
    host.warning = [p](const std::string& s) { p->warnings.push_back(s); };
    r->driver.attach(r->spec, "b", host);
    r->driver.build(2);
    return r;
  }
  // The plate's stable step (at set-up).
  double stable_dt()
  {
    auto r = make(" substeps off");
    r->driver.check_time_step(1e-12);
    return r->driver.stable_dt();
  }
  // A run of `steps` host steps of dt, as a host calls the driver.
  static void run(BodyDriver& d, int steps, double dt)
  {
    d.check_time_step(dt);
    d.start_run();
    d.compute_forces(nullptr, 0, dt, false);
    d.write_energy_row_if_due(0);
    for (int step = 1; step <= steps; ++step) {
      d.begin_step(dt);
      d.compute_forces(nullptr, step, dt, true);
      d.end_step(step, dt);
    }
  }
};

} // namespace

TEST(Substeps, KeywordGrammar)
{
  const std::string body = "type 2 density 7800 youngs 2e11 poisson 0.3 ";
  EXPECT_EQ(parse_body_spec(split("file m.msh " + body)).substeps, kSubstepsAuto);
  EXPECT_EQ(parse_body_spec(split("file m.msh " + body + "substeps off")).substeps, kSubstepsOff);
  EXPECT_EQ(parse_body_spec(split("file m.msh " + body + "substeps auto")).substeps, kSubstepsAuto);
  EXPECT_EQ(parse_body_spec(split("file m.msh " + body + "substeps 7")).substeps, 7);
  const std::string expects = "keyword 'substeps' expects auto, off or a count 1 .. 100";
  EXPECT_EQ(spec_error(body + "substeps"), expects);
  EXPECT_EQ(spec_error(body + "substeps 0"), expects + ", got '0'");
  EXPECT_EQ(spec_error(body + "substeps 101"), expects + ", got '101'");
  EXPECT_EQ(spec_error(body + "substeps 2.5"), expects + ", got '2.5'");
  EXPECT_EQ(spec_error(body + "substeps sometimes"), expects + ", got 'sometimes'");
  EXPECT_EQ(spec_error("type 2 rigid yes substeps 2", true),
            "keyword 'substeps' applies to deformable bodies; a rigid body moves by 'motion' and "
            "has no FE step");
}

// n = ceil(dt / dt_stable) above the stable step, 1 at or below it; logged only when above.
TEST_F(SubstepTest, AutoTakesTheCeilingOfTheStepRatio)
{
  const double dts = stable_dt();
  const struct {
    double ratio;
    int n;
  } cases[] = {{0.5, 1}, {1.0, 1}, {1.01, 2}, {2.9, 3}, {3.5, 4}, {99.5, 100}};
  for (const auto& c : cases) {
    auto r = make("");
    r->driver.check_time_step(c.ratio * dts);
    EXPECT_EQ(r->driver.substeps(), c.n) << c.ratio;
    EXPECT_LE(c.ratio * dts / c.n, dts) << c.ratio;
    EXPECT_EQ(r->lines.size(), c.n > 1 ? 2u : 1u) << c.ratio;
    if (c.n > 1)
      EXPECT_NE(r->lines.back().find(" FE substeps per host step"), std::string::npos)
          << r->lines.back();
    EXPECT_TRUE(r->warnings.empty());
  }
  // Beyond 100 substeps dt_check decides: stop, or warn and take 100.
  auto r = make("");
  try {
    r->driver.check_time_step(150 * dts);
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("(host timestep"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("/ substeps 100) exceeds the stable FE time step"),
              std::string::npos)
        << e.what();
  }
  r = make(" dt_check warn");
  r->driver.check_time_step(150 * dts);
  EXPECT_EQ(r->driver.substeps(), 100);
  EXPECT_EQ(r->warnings.size(), 1u);
  // A fixed count is checked the same way; 'off' as before sub-cycling.
  r = make(" substeps 2");
  r->driver.check_time_step(1.5 * dts);
  EXPECT_EQ(r->driver.substeps(), 2);
  EXPECT_THROW(make(" substeps 2")->driver.check_time_step(2.5 * dts), std::runtime_error);
  r = make(" substeps off dt_check warn");
  r->driver.check_time_step(2.5 * dts);
  EXPECT_EQ(r->driver.substeps(), 1);
  ASSERT_EQ(r->warnings.size(), 1u);
  EXPECT_NE(r->warnings[0].find("host timestep"), std::string::npos);
}

// n FE steps of h per host step dt = n h are the FE steps of a run at host step h: the same
// operations in the same order (no contact, so nothing is held), hence the same bits.
TEST_F(SubstepTest, SubcycledStepsEqualTheSameStepsOneByOne)
{
  const double dts = stable_dt();
  const double dt = 2.9 * dts; // auto: 3 substeps
  const double h = dt / 3;
  auto sub = make(" energy_file " + (dir_ / "sub.csv").string() + " 10");
  auto one = make(" substeps off energy_file " + (dir_ / "one.csv").string() + " 30");
  ASSERT_EQ(sub->driver.open_energy_file(), "");
  ASSERT_EQ(one->driver.open_energy_file(), "");
  run(sub->driver, 200, dt);
  run(one->driver, 600, h);
  EXPECT_EQ(sub->driver.substeps(), 3);
  const Body& a = sub->driver.body();
  const Body& b = one->driver.body();
  EXPECT_EQ(a.time(), b.time());
  EXPECT_EQ(a.positions(), b.positions());
  EXPECT_EQ(a.velocities(), b.velocities());
  EXPECT_EQ(a.strain_energy(), b.strain_energy());
  EXPECT_EQ(a.boundary_work(), b.boundary_work());
  EXPECT_EQ(a.reactions(), b.reactions());
  EXPECT_GT(a.strain_energy(), 1e-3 * a.kinetic_energy()); // it does vibrate
  // The energy files: the same rows but the step and the last column (substeps / none).
  std::ifstream fa(dir_ / "sub.csv"), fb(dir_ / "one.csv");
  std::string ra, rb;
  std::getline(fa, ra);
  std::getline(fb, rb);
  EXPECT_EQ(ra, rb + ",substeps");
  int rows = 0;
  while (std::getline(fa, ra) && std::getline(fb, rb)) {
    ASSERT_EQ(ra.substr(ra.find(',')), rb.substr(rb.find(',')) + ",3") << rows;
    ++rows;
  }
  EXPECT_EQ(rows, 21);
  EXPECT_EQ(sub->driver.vector_entry(sub->driver.vector_size() - kVecTailSize + kVecSubsteps), 3);
}

// Under 'substeps auto' the count follows the deformed body's stable step at the periodic check
// (and only there within a run), logging each change with the step.
TEST_F(SubstepTest, AutoFollowsTheDeformedBodyAtThePeriodicCheck)
{
  const double dts = stable_dt();
  auto r = make("");
  const double dt = 0.999 * dts;
  run(r->driver, 99, dt);
  EXPECT_EQ(r->driver.substeps(), 1);
  // Squeeze the free end's elements (a hammer blow): their stable step shrinks.
  std::vector<int> end;
  for (int n = 0; n < r->driver.body().num_nodes(); ++n)
    if (r->driver.body().mesh().X[3 * n] > 0.195) end.push_back(n);
  const double v[3] = {-1000, 0, 0};
  r->driver.body().set_velocity(end, v);
  r->driver.begin_step(dt);
  r->driver.compute_forces(nullptr, 100, dt, true);
  r->driver.end_step(100, dt);
  const double now = r->driver.body().stable_time_step();
  ASSERT_LT(now, dt); // the blow did squeeze them below the host step
  const int n = static_cast<int>(std::ceil(dt / now));
  EXPECT_EQ(r->driver.next_substeps(), n);
  EXPECT_EQ(r->driver.substeps(), 1); // this step's count stays
  ASSERT_FALSE(r->lines.empty());
  EXPECT_EQ(r->lines.back().rfind("fix fem/body b: step 100: stable FE time step ", 0), 0u)
      << r->lines.back();
  EXPECT_NE(r->lines.back().find(": " + std::to_string(n) + " FE substeps per host step"),
            std::string::npos)
      << r->lines.back();
  r->driver.begin_step(dt);
  EXPECT_EQ(r->driver.substeps(), n);
  EXPECT_TRUE(r->warnings.empty());
}

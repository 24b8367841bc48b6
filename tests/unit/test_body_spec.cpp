// Unit tests of BodySpec (keywords, error texts, host restrictions, checks) and build_body.
#include <gtest/gtest.h>

#include <cmath>
#include <initializer_list>
#include <sstream>

#include "body/body_setup.h"
#include "body/body_spec.h"
#include "io/gmsh_reader.h"
#include "io/mesh_generators.h"
#include "test_support.h"

using namespace fracdem;

namespace
{

using fracdem_test::split;

const char* const kBody = "type 2 density 7800 youngs 2e11 poisson 0.3";

// "file m.msh LINE" parsed.
BodySpec parse(const std::string& line, const BodySpecHost& host = {})
{
  return parse_body_spec(split("file m.msh " + line), host);
}

// The SpecError text of parsing (and, with check, checking) "file m.msh LINE"; "" if none.
std::string error_of(const std::string& line, const BodySpecHost& host = {}, bool check = false,
                     int dimension = 3)
{
  try {
    BodySpec s = parse(line, host);
    if (check) check_body_spec(s, host, 4, dimension);
  } catch (const SpecError& e) {
    return e.what();
  }
  return "";
}

// A line and its error text (or, with prefix, how the text begins).
struct SpecCase {
  const char* line;
  std::string expected;
  bool prefix = false;
};

// Each case's error text (or its beginning).
void expect_errors(std::initializer_list<SpecCase> cases)
{
  for (const SpecCase& c : cases) {
    const std::string err = error_of(c.line);
    if (c.prefix)
      EXPECT_EQ(err.rfind(c.expected, 0), 0u) << c.line << ": " << err;
    else
      EXPECT_EQ(err, c.expected) << c.line;
  }
}

// "file m.msh LINE" parsed and checked (4 atom types, 3D): defaults resolved.
BodySpec checked(const std::string& line)
{
  BodySpec s = parse(line);
  check_body_spec(s, {}, 4, 3);
  return s;
}

std::string check_error(const std::string& line, int dimension = 3)
{
  return error_of(line, {}, true, dimension);
}

// A host that takes a few keywords, adds its own and refuses one with a reason.
BodySpecHost restricted_host(int* own_calls)
{
  BodySpecHost host;
  host.name = "TESTHOST";
  host.supported = {{"type"},   {"density"}, {"youngs"}, {"poisson"}, {"material", "elastic"},
                    {"contact"}};
  host.own["contact"] = [own_calls](SpecReader& r, BodySpec&) {
    ++*own_calls;
    r.need(1, "a law");
    r.take(2);
  };
  host.own["contact_model"] = [](SpecReader& r, BodySpec&) {
    throw SpecError("keyword '" + r.keyword() + "' is the other host's");
  };
  return host;
}

} // namespace

TEST(BodySpec, MeshAndScalarKeywords)
{
  const BodySpec s = parse(std::string(kBody) + " model corotational thickness 0.5 rigid no");
  EXPECT_EQ(s.mesh_file, "m.msh");
  EXPECT_EQ(s.surface_type, 2);
  EXPECT_EQ(s.material.rho, 7800);
  EXPECT_EQ(s.material.E, 2e11);
  EXPECT_EQ(s.material.nu, 0.3);
  EXPECT_TRUE(s.have_density && s.have_youngs && s.have_poisson);
  EXPECT_EQ(s.material.kinematics, Kinematics::Corotational);
  EXPECT_EQ(s.material.thickness, 0.5);
  EXPECT_FALSE(s.rigid);
  EXPECT_FALSE(s.have_plane);
  EXPECT_EQ(parse("model elastic").material.kinematics, Kinematics::SmallStrain);
}

TEST(BodySpec, PlaneTable)
{
  EXPECT_EQ(parse("plane strain").material.plane, PlaneMode::PlaneStrain);
  EXPECT_EQ(parse("plane stress").material.plane, PlaneMode::PlaneStress);
  const BodySpec s = parse("plane axisymmetric");
  EXPECT_EQ(s.material.plane, PlaneMode::Axisymmetric);
  EXPECT_TRUE(s.have_plane);
}

TEST(BodySpec, FixedSetsAndReactionGroups)
{
  const BodySpec s = parse("fixed base fixed side x z prescribed_velocity top 0 0 -1 ramp 0.5 "
                           "fixed base y velocity all 1 2 3 prescribed_velocity top 0 1 0");
  ASSERT_EQ(s.fixed_sets.size(), 3u);
  EXPECT_EQ(s.fixed_sets[0].set, "base");
  EXPECT_EQ(s.fixed_sets[0].mask, 7); // no component: all
  EXPECT_EQ(s.fixed_sets[1].mask, 1 | 4);
  EXPECT_EQ(s.fixed_sets[2].mask, 2);
  EXPECT_EQ(s.fixed_sets[2].group, 0); // same group name, same account
  EXPECT_EQ(s.reaction_groups, (std::vector<std::string>{"base", "side", "top"}));
  ASSERT_EQ(s.prescribed_velocity.size(), 2u);
  EXPECT_EQ(s.prescribed_velocity[0].ramp, 0.5);
  EXPECT_EQ(s.prescribed_velocity[0].v[2], -1);
  EXPECT_EQ(s.prescribed_velocity[0].group, 2);
  EXPECT_EQ(s.prescribed_velocity[1].ramp, 0);
  ASSERT_EQ(s.initial_velocity.size(), 1u);
  EXPECT_EQ(s.initial_velocity[0].set, "all");
  EXPECT_EQ(s.initial_velocity[0].v[1], 2);
  EXPECT_EQ(s.initial_velocity[0].group, -1); // initial velocities have no reaction account
  EXPECT_EQ(s.initial_velocity[0].mask, 7);
  EXPECT_EQ(s.prescribed_velocity[0].mask, 7);
}

// NULL leaves a component out (LAMMPS convention): its bit is cleared, its value stays 0.
TEST(BodySpec, NullVelocityComponents)
{
  const BodySpec s =
      parse("prescribed_velocity top 0.1 NULL NULL ramp 0.5 velocity all NULL 2 NULL");
  ASSERT_EQ(s.prescribed_velocity.size(), 1u);
  EXPECT_EQ(s.prescribed_velocity[0].mask, 1);
  EXPECT_EQ(s.prescribed_velocity[0].v[0], 0.1);
  EXPECT_EQ(s.prescribed_velocity[0].v[1], 0.0);
  EXPECT_EQ(s.prescribed_velocity[0].ramp, 0.5);
  ASSERT_EQ(s.initial_velocity.size(), 1u);
  EXPECT_EQ(s.initial_velocity[0].mask, 2);
  EXPECT_EQ(s.initial_velocity[0].v[1], 2.0);
}

TEST(BodySpec, TransformsInOrder)
{
  const BodySpec s = parse("scale 2 move 1 2 3 rotate axis 0 0 1 angle 90");
  ASSERT_EQ(s.transforms.size(), 3u);
  EXPECT_EQ(s.transforms[0].kind, MeshTransform::Scale);
  EXPECT_EQ(s.transforms[0].a[0], 2);
  EXPECT_EQ(s.transforms[1].kind, MeshTransform::Move);
  EXPECT_EQ(s.transforms[1].a[2], 3);
  EXPECT_EQ(s.transforms[2].kind, MeshTransform::Rotate);
  EXPECT_DOUBLE_EQ(s.transforms[2].a[3], M_PI / 2);
}

TEST(BodySpec, RigidMotion)
{
  BodySpec s = parse("rigid yes motion linear 1 0 -2");
  EXPECT_TRUE(s.rigid);
  EXPECT_EQ(s.motion.kind, RigidMotion::Linear);
  EXPECT_EQ(s.motion.velocity[2], -2);
  s = parse("rigid yes motion rotate origin 1 2 3 axis 0 0 2 period 0.5");
  EXPECT_EQ(s.motion.kind, RigidMotion::Rotate);
  EXPECT_EQ(s.motion.origin[1], 2);
  EXPECT_EQ(s.motion.axis[2], 1); // normalised
  EXPECT_EQ(s.motion.period, 0.5);
}

TEST(BodySpec, MaterialAndEosWordsStopAtTheNextKeyword)
{
  BodySpec s = parse("material rankine strength 3e6 fracture_energy 100 density 2400");
  EXPECT_EQ(s.material.model, MaterialModel::Rankine);
  EXPECT_EQ(s.material.ft, 3e6);
  EXPECT_EQ(s.material.gf, 100);
  EXPECT_EQ(s.material.rho, 2400);
  s = parse("material j2 yield 3e8 hardening 1e9 eos mie_gruneisen 3940 1.49 2.02 type 3");
  EXPECT_EQ(s.material.model, MaterialModel::J2);
  EXPECT_EQ(s.material.eos.model, EosModel::MieGruneisen);
  EXPECT_EQ(s.surface_type, 3);
  EXPECT_EQ(parse("material elastic").material.model, MaterialModel::Elastic);
}

TEST(BodySpec, FractureAndBulkViscosity)
{
  BodySpec s = parse("fracture nodal");
  EXPECT_EQ(s.fracture_every, 1);
  EXPECT_FALSE(s.erode_cracked);
  s = parse("fracture nodal every 5 erode_cracked yes type 1");
  EXPECT_EQ(s.fracture_every, 5);
  EXPECT_TRUE(s.erode_cracked);
  EXPECT_EQ(s.surface_type, 1);
  EXPECT_EQ(s.min_size, 0.0); // absent: cracks follow element boundaries
  EXPECT_EQ(parse("fracture nodal min_size 0.2 every 3").min_size, 0.2);
  s = parse("bulk_viscosity 0.1 2");
  EXPECT_EQ(s.viscosity_mode, 1);
  EXPECT_EQ(s.viscosity.q1, 0.1);
  EXPECT_EQ(s.viscosity.q2, 2);
  EXPECT_EQ(parse("bulk_viscosity off").viscosity_mode, 0);
  EXPECT_EQ(parse("").viscosity_mode, -1);
}

TEST(BodySpec, Erosion)
{
  BodySpec s = parse("");
  EXPECT_FALSE(s.erosion.on());
  EXPECT_FALSE(s.erosion.remove_mass);
  EXPECT_FALSE(s.have_erosion_mass);
  // Any of the criteria, in any order, on one keyword; the next keyword ends them.
  s = parse("erosion min_dt 1e-7 plastic_strain 0.5 damage 0.9 type 2");
  EXPECT_EQ(s.erosion.plastic_strain, 0.5);
  EXPECT_EQ(s.erosion.damage, 0.9);
  EXPECT_EQ(s.erosion.min_dt, 1e-7);
  EXPECT_EQ(s.surface_type, 2);
  s = parse("erosion damage 1 erosion_mass remove");
  EXPECT_TRUE(s.erosion.on());
  EXPECT_TRUE(s.erosion.remove_mass);
  EXPECT_TRUE(s.have_erosion_mass);
  s = parse("erosion_mass keep");
  EXPECT_FALSE(s.erosion.remove_mass);
  EXPECT_TRUE(s.have_erosion_mass);
  const std::string expects = "keyword 'erosion' expects one or more of 'plastic_strain EPS' "
                              "(EPS > 0), 'damage D' (0 < D <= 1), 'min_dt DT' (DT > 0)";
  expect_errors({
      {"erosion", expects},
      {"erosion damage", expects},
      {"erosion type 1", expects},
      {"erosion damage -1", expects},
      {"erosion damage x", "keyword 'erosion damage' expects a finite number, got 'x'"},
      {"erosion min_dt 1e999", "keyword 'erosion min_dt' expects a finite number, got '1e999'"},
      {"erosion_mass", "keyword 'erosion_mass' expects keep or remove"},
      {"erosion_mass all", "keyword 'erosion_mass' expects keep or remove"},
  });
}

TEST(BodySpec, CheckErosion)
{
  const std::string rankine = std::string(kBody) + " material rankine strength 3e6 "
                                                   "fracture_energy 100";
  const std::string j2 = std::string(kBody) + " material j2 yield 3e8 hardening 1e9";
  EXPECT_EQ(check_error(rankine + " erosion damage 1 erosion_mass remove"), "");
  EXPECT_EQ(check_error(j2 + " erosion plastic_strain 0.5 min_dt 1e-8"), "");
  EXPECT_EQ(check_error(std::string(kBody) + " erosion min_dt 1e-8"), "");
  EXPECT_EQ(check_error(rankine + " erosion damage 1.5"),
            "keyword 'erosion damage': D must lie in (0, 1] (1: no tension left)");
  EXPECT_EQ(check_error(std::string(kBody) + " erosion plastic_strain 0.5")
                .rfind("keyword 'erosion plastic_strain': this body's material never yields", 0),
            0u);
  EXPECT_EQ(check_error(j2 + " erosion damage 0.5")
                .rfind("keyword 'erosion damage': this body's material does not damage", 0),
            0u);
  EXPECT_EQ(check_error("type 1 rigid yes erosion min_dt 1e-8"),
            "keyword 'erosion': a rigid body neither deforms nor loses elements");
  // A criterion off (0) beside one that is on is accepted; a negative one is refused.
  EXPECT_EQ(check_error(std::string(kBody) + " erosion min_dt 1e-8 damage 0"), "");
  EXPECT_EQ(check_error(std::string(kBody) + " erosion min_dt 1e-8 damage -1"),
            "keyword 'erosion': expects one or more of 'plastic_strain EPS' (EPS > 0), 'damage D' "
            "(0 < D <= 1), 'min_dt DT' (DT > 0)");
  const std::string mass_alone = "keyword 'erosion_mass' applies to bodies that erode elements "
                                 "('erosion ...' or 'fracture nodal')";
  EXPECT_EQ(check_error(std::string(kBody) + " erosion_mass remove"), mass_alone);
  EXPECT_EQ(check_error(rankine + " fracture nodal erosion_mass remove"), "");
}

TEST(BodySpec, ContactBalanceKeyword)
{
  const BodySpec d = parse("contact_bodies yes");
  EXPECT_FALSE(d.have_contact_balance);
  EXPECT_EQ(d.contact_balance.model, ContactBalance::APosteriori);
  EXPECT_EQ(d.contact_balance.thresh, 1.1);
  EXPECT_EQ(d.contact_balance.every, 10);
  EXPECT_EQ(d.contact_balance.parts, 0);
  const BodySpec s =
      parse("contact_bodies yes contact_balance a_priori every 5 parts 4 file b.csv thresh 1.3 "
            "contact_penalty 0.2");
  EXPECT_TRUE(s.have_contact_balance);
  EXPECT_EQ(s.contact_balance.model, ContactBalance::APriori);
  EXPECT_EQ(s.contact_balance.thresh, 1.3);
  EXPECT_EQ(s.contact_balance.every, 5);
  EXPECT_EQ(s.contact_balance.parts, 4);
  EXPECT_EQ(s.contact_balance.file, "b.csv");
  EXPECT_EQ(s.contact_penalty, 0.2); // the options end where the next keyword starts
}

TEST(BodySpec, ContactAndRunKeywords)
{
  const BodySpec s =
      parse("contact_model hooke tangential no_history compliance combined buffer 0.01 "
            "dt_check warn gravity no energy_file e.csv 10 contact_bodies yes contact_penalty 0.3 "
            "history_slots 12");
  EXPECT_EQ(s.normal_model, NormalModel::Hooke);
  EXPECT_FALSE(s.tangential_history);
  EXPECT_EQ(s.compliance_combined, 1);
  EXPECT_EQ(s.buffer, 0.01);
  EXPECT_FALSE(s.dt_check_error);
  EXPECT_FALSE(s.apply_gravity);
  EXPECT_EQ(s.energy_file, "e.csv");
  EXPECT_EQ(s.energy_every, 10);
  EXPECT_EQ(s.contact_bodies, 1);
  EXPECT_EQ(s.contact_penalty, 0.3);
  EXPECT_EQ(s.history_slots, 12);
  const BodySpec d = parse("compliance particle tangential history contact_bodies no");
  EXPECT_EQ(d.compliance_combined, 0);
  EXPECT_TRUE(d.tangential_history);
  EXPECT_EQ(d.contact_bodies, 0);
  EXPECT_EQ(parse("").history_slots, 8);
  EXPECT_TRUE(parse("").contact_edges); // 3D bodies with contact_bodies yes take it
  EXPECT_TRUE(parse("contact_edges yes").contact_edges);
  EXPECT_FALSE(parse("contact_edges no").contact_edges);
}

TEST(BodySpec, MissingValues)
{
  expect_errors({
      {"type", "keyword 'type' expects an atom type"},
      {"density", "keyword 'density' expects a value"},
      {"model", "keyword 'model' expects elastic or corotational"},
      {"plane", "keyword 'plane' expects strain, stress or axisymmetric"},
      {"fixed", "keyword 'fixed' expects a mesh physical group name [x] [y] [z]"},
      {"velocity all 1 2", "keyword 'velocity' expects GROUP vx vy vz (a component may be NULL)"},
      {"prescribed_velocity",
       "keyword 'prescribed_velocity' expects GROUP vx vy vz (a component may be NULL)"},
      {"scale", "keyword 'scale' expects a factor"},
      {"move 1 2", "keyword 'move' expects dx dy dz"},
      {"rotate axis 0 0 1 angle", "keyword 'rotate' expects axis ax ay az angle DEGREES"},
      {"rigid", "keyword 'rigid' expects yes or no"},
      {"motion", "keyword 'motion' expects linear vx vy vz | rotate origin ox oy oz axis ax ay az "
                 "period T"},
      {"motion linear 1 2", "keyword 'motion' expects linear vx vy vz"},
      // The period's value missing (read past the words before).
      {"motion rotate origin 0 0 0 axis 0 0 1 period",
       "keyword 'motion' expects rotate origin ox oy oz axis ax ay az period T"},
      {"fracture", "keyword 'fracture' expects 'nodal [every N]'"},
      {"bulk_viscosity", "keyword 'bulk_viscosity' expects 'off' or 'Q1 Q2' (linear and quadratic "
                         "coefficients, e.g. 0.06 1.2)"},
      {"bulk_viscosity 0.1",
       "keyword 'bulk_viscosity' expects 'off' or 'Q1 Q2' (linear and quadratic "
       "coefficients, e.g. 0.06 1.2)"},
      {"contact_model", "keyword 'contact_model' expects hertz or hooke"},
      {"buffer", "keyword 'buffer' expects a distance"},
      {"energy_file e.csv", "keyword 'energy_file' expects FILE N"},
      {"contact_penalty", "keyword 'contact_penalty' expects a factor"},
      {"history_slots", "keyword 'history_slots' expects a count"},
      {"material", "keyword 'material': missing model (one of elastic, rankine, j2, johnson_cook, "
                   "zerilli_armstrong)"},
  });
}

TEST(BodySpec, NotNumbers)
{
  expect_errors({
      {"density abc", "keyword 'density' expects a finite number, got 'abc'"},
      {"youngs 1e999", "keyword 'youngs' expects a finite number, got '1e999'"},
      {"poisson 0.3x", "keyword 'poisson' expects a finite number, got '0.3x'"},
      {"type 2.5", "keyword 'type' expects an integer, got '2.5'"},
      {"type 99999999999", "keyword 'type' expects an integer, got '99999999999'"},
      {"move 1 nan 2", "keyword 'move' expects a finite number, got 'nan'"},
      {"prescribed_velocity top 0 0 1 ramp x", "keyword 'ramp' expects a finite number, got 'x'"},
      {"motion rotate origin 0 0 0 axis 0 0 1 period p",
       "keyword 'motion' expects a finite number, got 'p'"},
      {"fracture nodal every 2.5", "keyword 'every' expects an integer, got '2.5'"},
      {"energy_file e.csv ten", "keyword 'energy_file' expects an integer, got 'ten'"},
      {"history_slots many", "keyword 'history_slots' expects an integer, got 'many'"},
      {"material rankine strength abc fracture_energy 1", "keyword 'material rankine': strength",
       true},
  });
}

TEST(BodySpec, OutOfRangeAndBadWords)
{
  expect_errors({
      {"thickness 0", "keyword 'thickness' must be > 0"},
      {"scale -1", "keyword 'scale' must be > 0"},
      {"buffer -1", "keyword 'buffer' must be >= 0"},
      {"contact_penalty 0", "keyword 'contact_penalty' must be > 0"},
      {"history_slots 65", "keyword 'history_slots' expects 1 .. 64"},
      {"history_slots 0", "keyword 'history_slots' expects 1 .. 64"},
      {"energy_file e.csv 0", "keyword 'energy_file' needs N > 0"},
      {"prescribed_velocity top 0 0 1 ramp 0",
       "keyword 'prescribed_velocity ... ramp T' needs T > 0"},
      {"prescribed_velocity top NULL NULL NULL",
       "keyword 'prescribed_velocity' got NULL for vx, vy and vz; expected a velocity for at "
       "least one component (NULL leaves a component free)"},
      {"prescribed_velocity top NULL x 0",
       "keyword 'prescribed_velocity' expects a finite number, got 'x'"},
      {"model plastic", "keyword 'model' got 'plastic', expected one of: corotational elastic"},
      {"plane flat", "keyword 'plane' got 'flat', expected one of: axisymmetric strain stress"},
      {"contact_model jkr", "keyword 'contact_model' got 'jkr', expected one of: hertz hooke"},
      {"gravity maybe", "keyword 'gravity' expects yes or no"},
      {"dt_check never", "keyword 'dt_check' expects error or warn"},
      {"tangential yes", "keyword 'tangential' expects history or no_history"},
      {"compliance both", "keyword 'compliance' expects particle or combined"},
      {"contact_bodies 1", "keyword 'contact_bodies' expects yes or no"},
      {"contact_edges 1", "keyword 'contact_edges' expects yes or no"},
      {"contact_balance", "keyword 'contact_balance' expects a_priori or a_posteriori"},
      {"contact_balance metis",
       "keyword 'contact_balance' got 'metis', expected a_priori or a_posteriori"},
      {"contact_balance a_posteriori thresh 0.9",
       "keyword 'contact_balance': 'thresh' expects B >= 1 (max / mean of the ranks' contact "
       "work)"},
      {"contact_balance a_priori every 0",
       "keyword 'contact_balance': 'every' expects a step count >= 1"},
      {"contact_balance a_priori parts 0",
       "keyword 'contact_balance': 'parts' expects a count >= 1"},
      {"contact_balance a_priori parts", "keyword 'contact_balance': 'parts' expects a value"},
      {"rotate axis 0 0 0 angle 10",
       "keyword 'rotate' got axis 0 0 0, expected a non-zero axis direction ax ay az"},
      {"rotate axes 0 0 1 angle 10", "keyword 'rotate' expects 'axis ax ay az angle DEGREES'"},
      {"motion spin 1", "keyword 'motion' expects 'linear' or 'rotate'"},
      {"motion rotate origin 0 0 0 axes 0 0 1 period 1",
       "keyword 'motion rotate' expects 'origin ox oy oz axis ax ay az period T'"},
      {"motion rotate origin 0 0 0 axis 0 0 1 period 0",
       "'motion rotate' needs a non-zero axis and period"},
      {"fracture nodal every 0", "keyword 'fracture nodal every' expects N >= 1"},
      {"fracture nodal erode_cracked maybe",
       "keyword 'fracture nodal erode_cracked' expects yes or no"},
      {"fracture nodal min_size 1",
       "keyword 'fracture nodal min_size' expects a fraction F with 0 < F < 0.5 ", true},
      {"fracture nodal min_size 0", "keyword 'fracture nodal min_size' expects a fraction F", true},
      {"fracture nodal min_size 0.5", "keyword 'fracture nodal min_size' expects a fraction F",
       true},
      {"fracture nodal min_size abc",
       "keyword 'fracture nodal min_size' expects a finite number, got 'abc'"},
      {"fracture brittle", "keyword 'fracture' expects 'nodal [every N]'"},
      {"bulk_viscosity -1 1.2", "keyword 'bulk_viscosity': ", true},
      {"eos ideal", "keyword 'eos': unknown model 'ideal'", true},
  });
}

TEST(BodySpec, UnknownKeywordAndHeader)
{
  EXPECT_EQ(error_of("colour red"), "unknown keyword 'colour'");
  EXPECT_EQ(error_of("fixed base w"), "unknown keyword 'w'"); // not a component
  EXPECT_EQ(error_of("erosions damage 1"), "unknown keyword 'erosions'; did you mean 'erosion'?");
  const std::string header = "expected 'fix ID group fem/body file MESH.msh keyword value ...'";
  for (const char* line : {"", "file", "mesh m.msh"}) {
    try {
      parse_body_spec(split(line));
      ADD_FAILURE() << line;
    } catch (const SpecError& e) {
      EXPECT_EQ(e.what(), header);
    }
  }
}

TEST(BodySpec, KeywordTableListsEveryKeywordOnce)
{
  const std::vector<std::string> k = body_keywords();
  EXPECT_EQ(k.size(), 35u);
  for (std::size_t i = 0; i < k.size(); ++i)
    for (std::size_t j = i + 1; j < k.size(); ++j)
      EXPECT_NE(k[i], k[j]);
  const BodySpecHost all;
  for (const std::string& w : k)
    EXPECT_TRUE(all.takes(w)) << w;
  EXPECT_FALSE(all.takes("colour"));
}

TEST(BodySpec, HostRestrictions)
{
  int own_calls = 0;
  const BodySpecHost host = restricted_host(&own_calls);
  const std::string list = "type density youngs poisson material(elastic) contact";
  EXPECT_EQ(error_of("rigid yes", host),
            "keyword 'rigid' is not yet supported under TESTHOST (supported: " + list + ")");
  EXPECT_EQ(error_of("colour red", host),
            "unknown keyword 'colour' (supported under TESTHOST: " + list + ")");
  EXPECT_EQ(error_of("contact_model hooke", host), "keyword 'contact_model' is the other host's");
  // The host's own keyword runs its handler; the common ones it takes parse as before.
  const BodySpec s = parse(std::string(kBody) + " contact law1", host);
  EXPECT_EQ(own_calls, 1);
  EXPECT_EQ(s.surface_type, 2);
  EXPECT_EQ(error_of("contact", host), "keyword 'contact' expects a law");
  EXPECT_TRUE(host.takes("contact"));
  EXPECT_TRUE(host.takes("material"));
  EXPECT_FALSE(host.takes("rigid"));
  // Keywords the table gains later stay refused by a host that lists its own.
  EXPECT_FALSE(host.takes("bulk_viscosity"));
  EXPECT_FALSE(host.takes("erosion"));
  EXPECT_EQ(error_of("erosion damage 1", host),
            "keyword 'erosion' is not yet supported under TESTHOST (supported: " + list + ")");
}

TEST(BodySpec, CheckDeformable)
{
  EXPECT_EQ(check_error(kBody), "");
  EXPECT_EQ(check_error("density 1 youngs 1 poisson 0.3"),
            "keyword 'type' is required and must be an atom type between 1 and 4");
  EXPECT_EQ(check_error("type 5 density 1 youngs 1 poisson 0.3"),
            "keyword 'type' is required and must be an atom type between 1 and 4");
  EXPECT_EQ(check_error("type 1 density 1 youngs 1"),
            "a deformable body needs keywords 'density', 'youngs' and 'poisson' (or 'rigid yes')");
  EXPECT_EQ(check_error("type 1 density 0 youngs 1 poisson 0.3"),
            "'density' and 'youngs' must be > 0");
  EXPECT_EQ(check_error("type 1 density 1 youngs 1 poisson 0.5"),
            "'poisson' must lie in (-1, 0.5)");
  EXPECT_EQ(check_error(std::string(kBody) + " motion linear 1 0 0"),
            "keyword 'motion' needs 'rigid yes' (deformable bodies move by forces and "
            "'prescribed_velocity')");
  EXPECT_EQ(check_error(std::string(kBody) + " plane strain"),
            "keyword 'plane' applies to 2D runs ('dimension 2'); this run is 3D (leave out "
            "'plane')");
  EXPECT_EQ(check_error(std::string(kBody) + " plane strain", 2), "");
  EXPECT_EQ(check_error(std::string(kBody) + " fracture nodal"),
            "keyword 'fracture' needs a material that fails, e.g. 'material rankine strength FT "
            "fracture_energy GF'");
  EXPECT_EQ(check_error(std::string(kBody) + " material rankine strength 3e6 fracture_energy 100 "
                                             "fracture nodal"),
            "");
  // A host without 'rigid' does not suggest it.
  int calls = 0;
  EXPECT_EQ(error_of("type 1 density 1 youngs 1", restricted_host(&calls), true),
            "a deformable body needs keywords 'density', 'youngs' and 'poisson'");
}

TEST(BodySpec, CheckRigid)
{
  EXPECT_EQ(check_error("type 1 rigid yes motion linear 1 0 0"), "");
  EXPECT_EQ(check_error("type 1 rigid yes fixed base"),
            "'fixed', 'velocity' and 'prescribed_velocity' apply to deformable bodies; a rigid "
            "body moves by 'motion'");
  EXPECT_EQ(check_error("type 1 rigid yes material rankine strength 3e6 fracture_energy 100"),
            "keywords 'material' and 'fracture' apply to deformable bodies; a rigid body neither "
            "deforms nor breaks");
  EXPECT_EQ(check_error("type 1 rigid yes bulk_viscosity 0.06 1.2"),
            "keyword 'bulk_viscosity' applies to deformable bodies; a rigid body does not deform");
  EXPECT_EQ(check_error("type 1 rigid yes contact_bodies yes"),
            "keyword 'contact_bodies yes' needs a deformable body");
  EXPECT_EQ(check_error("type 1 rigid yes contact_balance a_priori"),
            "keyword 'contact_balance' applies to bodies with 'contact_bodies yes'");
  const BodySpec s = checked("type 1 rigid yes");
  EXPECT_EQ(s.material.rho, 1.0); // the unused mass of a rigid body
  EXPECT_EQ(s.compliance_combined, 1);
}

TEST(BodySpec, CheckResolvesDefaults)
{
  const BodySpec s = checked(kBody);
  EXPECT_EQ(s.compliance_combined, 0);
  EXPECT_EQ(s.viscosity_mode, 0);
  EXPECT_FALSE(s.viscosity.on);
  EXPECT_EQ(s.contact_bodies, 0);
  // A breaking body's pieces collide by default; written out, 'no' stays no.
  const std::string breaking =
      std::string(kBody) + " material rankine strength 3e6 fracture_energy 100 fracture nodal";
  EXPECT_EQ(checked(breaking).contact_bodies, 1);
  EXPECT_EQ(checked(breaking + " contact_bodies no").contact_bodies, 0);
  const std::string j2 = std::string(kBody) + " material j2 yield 3e8 hardening 1e9";
  EXPECT_TRUE(checked(j2).viscosity.on); // on for plastic materials
  EXPECT_FALSE(checked(j2 + " bulk_viscosity off").viscosity.on);
  EXPECT_EQ(check_error(std::string(kBody) + " material rankine strength 3e6 fracture_energy 0")
                .rfind("keyword 'material rankine': ", 0),
            0u);
}

TEST(BodySpec, FixMessage)
{
  EXPECT_EQ(fix_message(SpecError("keyword 'x': y"), "b"), "fix fem/body: keyword 'x': y");
  EXPECT_EQ(fix_message(SpecError("bad mesh", true), "b"), "fix fem/body b: bad mesh");
}

class BodySetup : public fracdem_test::TempDirTest
{
protected:
  BodySpec spec_for(const std::string& mesh, const std::string& line, int dimension = 3)
  {
    BodySpec s = parse_body_spec(split("file " + (dir_ / mesh).string() + " " + line));
    check_body_spec(s, {}, 4, dimension);
    return s;
  }
  std::string build_error(const BodySpec& s, int dimension = 3)
  {
    Body body;
    try {
      build_body(s, dimension, body);
    } catch (const SpecError& e) {
      return fix_message(e, "b");
    }
    return "";
  }
  void write_box()
  {
    write_gmsh22(make_box_tet_mesh(2, 2, 2, 1, 1, 1), (dir_ / "box.msh").string());
  }
};

TEST_F(BodySetup, BuildsTheBodyWithItsConditions)
{
  write_box();
  const BodySpec s =
      spec_for("box.msh", std::string(kBody) + " fixed zmin prescribed_velocity zmax 0 0 -1 "
                                               "velocity all 1 0 0 move 10 0 0");
  Body body;
  build_body(s, 3, body);
  EXPECT_EQ(body.num_nodes(), 27);
  EXPECT_EQ(body.mesh().X[0], 10); // placed
  EXPECT_EQ(body_node_set(body, s, "all", "velocity").size(), 27u);
  EXPECT_EQ(body_node_set(body, s, "zmin", "fixed").size(), 9u);
  double v = -1;
  EXPECT_TRUE(body_vector_entry(body, kVecNodes, 2, v));
  EXPECT_EQ(v, 27);
  EXPECT_TRUE(body_vector_entry(body, kVecElements, 2, v));
  EXPECT_EQ(v, 48);
  EXPECT_TRUE(body_vector_entry(body, kVecFragments, 2, v));
  EXPECT_EQ(v, 1);
  EXPECT_TRUE(body_vector_entry(body, kVecSplitNodes, 2, v));
  EXPECT_EQ(v, 0);
  EXPECT_TRUE(body_vector_entry(body, kVecSize + 5, 2, v)); // reactions: 3 per group
  EXPECT_FALSE(body_vector_entry(body, kVecSize + 6, 2, v));
  EXPECT_FALSE(body_vector_entry(body, kVecContacts, 2, v)); // the host's
  EXPECT_FALSE(body_vector_entry(body, kVecStableDt, 2, v));
  // Elastic: the element work may be split; rank 1 of 2 gets the second half.
  EXPECT_TRUE(split_element_work(body, 1, 2));
  EXPECT_FALSE(split_element_work(body, 0, 1));
  EXPECT_FALSE(split_element_work(body, 0, 2, true));
}

TEST_F(BodySetup, MeshErrorsNameTheFix)
{
  write_box();
  EXPECT_EQ(build_error(spec_for("box.msh", std::string(kBody) + " fixed top")),
            "fix fem/body: keyword 'fixed': mesh '" + (dir_ / "box.msh").string() +
                "' has no physical group 'top'; it has: xmax xmin ymax ymin zmax zmin (and "
                "'all')");
  EXPECT_EQ(build_error(spec_for("box.msh", std::string(kBody) + " velocity top 1 0 0"))
                .find("keyword 'velocity': mesh"),
            std::string("fix fem/body: ").size());
  EXPECT_EQ(
      build_error(spec_for("nothere.msh", kBody)).rfind("fix fem/body b: cannot use mesh: ", 0),
      0u);
  write_gmsh22(make_rect_mesh(2, 2, 1, 1), (dir_ / "rect.msh").string());
  EXPECT_EQ(
      build_error(spec_for("rect.msh", std::string(kBody) + " rotate axis 1 0 0 angle 90"), 2),
      "fix fem/body: 2D mesh must stay in the z = 0 plane after 'move'/'rotate'");
  EXPECT_EQ(build_error(spec_for("box.msh", std::string(kBody) + " scale 1e300 scale 1e300")),
            "fix fem/body b: keyword 'scale'/'move'/'rotate': element 0 of '" +
                (dir_ / "box.msh").string() + "' overflows double precision");
  // The material against the mesh (plane stress refused for plastic models) names the fix.
  EXPECT_EQ(
      build_error(spec_for("rect.msh",
                           std::string(kBody) + " plane stress material j2 yield 3e8 hardening 1e9",
                           2),
                  2)
          .rfind("fix fem/body b: ", 0),
      0u);
}

TEST(BodySetupText, TimeStep)
{
  EXPECT_EQ(time_step_line(1e-5, 1e-6), "stable FE time step 1e-05, host time step 1e-06 (10.0%)");
  EXPECT_EQ(time_step_violation(1e-5, 1e-6, "m.msh"), "");
  EXPECT_EQ(time_step_violation(1e-5, 1e-5, "m.msh"), "");
  EXPECT_EQ(time_step_violation(2.34567891e-7, 1e-6, "m.msh"),
            "host timestep 1e-06 exceeds the stable FE time step 2.34568e-07 of mesh 'm.msh'; "
            "reduce 'timestep' or coarsen the mesh (keyword 'dt_check warn' runs anyway)");
}

TEST(BodySetupText, BodyInTheBox)
{
  // A 1 x 1 square at the origin (2D) in a box 0..2 x 0..2: inside. Moved 0.5 below a fixed
  // y-low face it is refused naming the face; a shrink-wrapped face lets it be; across a periodic
  // x boundary it may cross, but not when longer than the period or a period away.
  const Mesh m = make_rect_mesh(2, 2, 1.0, 1.0, {0, 0}, ElemType::Tri3);
  const std::vector<Facet> facets = boundary_facets(m);
  HostBox box;
  box.dimension = 2;
  for (int d = 0; d < 3; ++d) {
    box.hi[d] = 2;
    box.fixed[d][0] = box.fixed[d][1] = true;
  }
  std::vector<double> x = m.X;
  EXPECT_EQ(body_box_violation(facets, x.data(), box), "");
  for (int n = 0; n < m.num_nodes(); ++n)
    x[3 * n + 1] -= 0.5;
  const std::string out = body_box_violation(facets, x.data(), box);
  EXPECT_NE(out.find("reaches beyond its fixed y-low face"), std::string::npos) << out;
  EXPECT_EQ(out.find("the body (x 0 to 1, y -0.5 to 0.5) in the box (x 0 to 2, y 0 to 2)"), 0u)
      << out;
  box.slack = 0.5; // within the search buffer
  EXPECT_EQ(body_box_violation(facets, x.data(), box), "");
  box.slack = 0;
  box.fixed[1][0] = false; // shrink-wrapped
  EXPECT_EQ(body_box_violation(facets, x.data(), box), "");
  box.periodic[0] = true;
  box.hi[0] = 0.8; // period shorter than the body
  EXPECT_NE(body_box_violation(facets, x.data(), box).find("longer than its period"),
            std::string::npos);
  box.hi[0] = 2;
  for (int n = 0; n < m.num_nodes(); ++n)
    x[3 * n] += 4.5; // 2.5 beyond the high face: more than a period (2) outside
  EXPECT_NE(body_box_violation(facets, x.data(), box).find("more than a period outside"),
            std::string::npos);
  EXPECT_EQ(body_box_violation({}, x.data(), box), ""); // no surface, nothing to hit
}

// parallel replicated|distributed; what a distributed body does not do yet is refused by name.
TEST(BodySpec, ParallelDistributed)
{
  const std::string body = std::string(kBody) + " ";
  EXPECT_FALSE(parse(body).distributed);
  EXPECT_FALSE(parse(body).have_parallel); // chosen by size at set-up
  EXPECT_TRUE(parse(body + "parallel distributed").distributed);
  EXPECT_FALSE(parse(body + "parallel replicated").distributed);
  EXPECT_TRUE(parse(body + "parallel replicated").have_parallel);
  EXPECT_EQ(error_of(body + "parallel sideways"),
            "keyword 'parallel' expects distributed or replicated");
  EXPECT_EQ(check_error(body + "parallel distributed"), "");
  const std::string tail = " yet; use 'parallel replicated'";
  // A breaking body breaks distributed, its pieces in contact (the default) or not.
  EXPECT_EQ(check_error(body + "parallel distributed material rankine strength 3e6 "
                               "fracture_energy 100 fracture nodal"),
            "");
  EXPECT_EQ(check_error(body + "parallel distributed material rankine strength 3e6 "
                               "fracture_energy 100 fracture nodal contact_bodies no"),
            "");
  const BodySpec r = parse(body + "parallel distributed rebalance 1.5 every 200 gravity no");
  EXPECT_EQ(r.rebalance, 1.5);
  EXPECT_EQ(r.rebalance_every, 200);
  EXPECT_EQ(parse(body + "parallel distributed").rebalance, 1.2);
  EXPECT_EQ(parse(body + "parallel distributed").rebalance_every, 1000);
  EXPECT_EQ(error_of(body + "parallel distributed rebalance 1"),
            "keyword 'parallel distributed rebalance' expects a threshold B > 1 (parts' largest "
            "modelled work over the mean), got '1'");
  EXPECT_EQ(error_of(body + "parallel distributed rebalance 1.2 every 0"),
            "keyword 'parallel distributed rebalance B every' expects a step count N >= 1, got "
            "'0'");
  EXPECT_EQ(check_error(body + "parallel distributed contact_bodies yes"), "");
  EXPECT_EQ(check_error(body + "parallel distributed rigid yes"),
            "keyword 'parallel distributed' does not work with 'rigid yes'" + tail);
  // A distributed body erodes, its nodes keeping the mass or not.
  EXPECT_EQ(check_error(body + "parallel distributed material j2 yield 4e8 hardening 1e8 "
                               "erosion plastic_strain 2"),
            "");
  EXPECT_EQ(check_error(body + "parallel distributed material j2 yield 4e8 hardening 1e8 "
                               "erosion plastic_strain 2 erosion_mass remove"),
            "");
  EXPECT_EQ(check_error(body + "parallel distributed material rankine strength 3e6 "
                               "fracture_energy 100 fracture nodal contact_bodies no "
                               "erosion_mass remove"),
            "");
}

// Without 'parallel' the body's size chooses (kDistributedMinElements), unless it uses what
// distributed bodies refuse; an explicit choice stands whatever the size.
TEST(BodySpec, ParallelChosenBySize)
{
  const std::string body = std::string(kBody) + " ";
  bool distributed = true;
  // The choice for the checked spec of kBody and `words` at `elements` elements.
  auto choice = [&](const std::string& words, long long elements) {
    return parallel_choice(checked(body + words), elements, distributed);
  };
  const std::string small = choice("", kDistributedMinElements);
  EXPECT_FALSE(distributed);
  EXPECT_NE(small.find("parallel replicated (by default: 20000 elements <= 20000"),
            std::string::npos)
      << small;
  const std::string big = choice("", kDistributedMinElements + 1);
  EXPECT_TRUE(distributed);
  EXPECT_NE(big.find("parallel distributed (by default: 20001 elements > 20000"), std::string::npos)
      << big;
  EXPECT_NE(choice("material rankine strength 3e6 fracture_energy 100 fracture nodal", 1000000)
                .find("uses 'fracture'"),
            std::string::npos);
  EXPECT_FALSE(distributed);
  const std::string erosion = "uses 'erosion', which a distributed body does only when asked: "
                              "'parallel distributed')";
  const std::string j2 = "material j2 yield 4e8 hardening 1e8 erosion plastic_strain 2";
  EXPECT_NE(choice(j2, 1000000).find(erosion), std::string::npos);
  EXPECT_FALSE(distributed);
  // erosion_mass remove is done distributed when asked, as erosion is.
  EXPECT_NE(choice(j2 + " erosion_mass remove", 1000000).find(erosion), std::string::npos);
  EXPECT_FALSE(distributed);
  EXPECT_NE(choice("contact_bodies yes", 1000000)
                .find("uses 'contact_bodies yes', which a distributed body does only when asked: "
                      "'parallel distributed')"),
            std::string::npos);
  EXPECT_FALSE(distributed);
  EXPECT_EQ(parallel_choice(parse(body + "parallel replicated"), 1000000, distributed), "");
  EXPECT_FALSE(distributed);
  EXPECT_EQ(parallel_choice(parse(body + "parallel distributed"), 10, distributed), "");
  EXPECT_TRUE(distributed);
}

// fracture nodal track L: parsed, refused where it cannot work, off by default.
TEST(BodySpec, CrackTrackingKeyword)
{
  EXPECT_EQ(parse("fracture nodal").track_length, 0.0);
  EXPECT_EQ(parse("fracture nodal track 0.01 every 2").track_length, 0.01);
  const std::string rankine =
      std::string(kBody) + " material rankine strength 3e6 fracture_energy 100 fracture nodal";
  EXPECT_EQ(check_error(rankine + " track 0.01", 2), "");
  EXPECT_EQ(error_of("fracture nodal track abc"),
            "keyword 'fracture nodal track' expects a finite number, got 'abc'");
  EXPECT_EQ(error_of("fracture nodal track 0")
                .rfind("keyword 'fracture nodal track' expects a length L > 0", 0),
            0u);
  EXPECT_NE(check_error(rankine + " track 0.01", 3).find("works on 2D bodies"), std::string::npos);
  EXPECT_EQ(parse("fracture nodal track 0.01 exclusion 0.2").track_exclusion, 0.2);
  EXPECT_EQ(error_of("fracture nodal track 0.01 exclusion -1")
                .rfind("keyword 'fracture nodal exclusion' expects a radius R > 0", 0),
            0u);
  EXPECT_NE(check_error(rankine + " exclusion 0.2", 2).find("give 'track L' with it"),
            std::string::npos);
  BodySpec s = parse(rankine + " track 0.01");
  EXPECT_STREQ(distributed_refusal(s), "'fracture nodal track'");
  EXPECT_NE(check_error(rankine + " track 0.01 parallel distributed", 2)
                .find("keyword 'parallel distributed' does not work with 'fracture nodal track'"),
            std::string::npos);
}

// Unit tests for input help: edit distance, nearest-keyword suggestions, units, the mm-mesh hint.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "body/body_spec.h"
#include "io/input_help.h"
#include "materials/material_table.h"

using namespace fracdem;

TEST(InputHelp, EditDistanceCountsInsertDeleteSubstituteAndSwap)
{
  EXPECT_EQ(edit_distance("", ""), 0);
  EXPECT_EQ(edit_distance("", "abc"), 3);
  EXPECT_EQ(edit_distance("kitten", "sitting"), 3);
  EXPECT_EQ(edit_distance("young", "youngs"), 1);
  EXPECT_EQ(edit_distance("poison", "poisson"), 1);
  EXPECT_EQ(edit_distance("poisosn", "poisson"), 1); // one swap of neighbours
  EXPECT_EQ(edit_distance("youngs", "young"), edit_distance("young", "youngs"));
}

TEST(InputHelp, NearestWordSuggestsCloseKeywordsOnly)
{
  const std::vector<std::string> keys = body_keywords();
  EXPECT_EQ(nearest_word("young", keys), "youngs");
  EXPECT_EQ(nearest_word("poison", keys), "poisson");
  EXPECT_EQ(nearest_word("densty", keys), "density");
  EXPECT_EQ(nearest_word("substep", keys), "substeps");
  // Nothing within max(2, len/3) edits: no suggestion rather than a wrong one.
  EXPECT_EQ(nearest_word("colour", keys), "");
  EXPECT_EQ(nearest_word("youngs_modulus", keys), "");
  EXPECT_EQ(nearest_word("xyz", {}), "");
}

TEST(InputHelp, NearestWordLimitGrowsWithTheWord)
{
  // 2 edits are always allowed; a 12-letter word may be 4 edits off, not 5.
  EXPECT_EQ(nearest_word("ab", {"abcd"}), "abcd");
  EXPECT_EQ(nearest_word("ab", {"abcde"}), "");
  EXPECT_EQ(nearest_word("abcdefghijkl", {"abcdefghWXYZ"}), "abcdefghWXYZ");
  EXPECT_EQ(nearest_word("abcdefghijkl", {"abcdefgVWXYZ"}), "");
  // Equals: the first in table order.
  EXPECT_EQ(nearest_word("cat", {"bat", "cut"}), "bat");
}

TEST(InputHelp, DidYouMeanReadsAsTheEndOfAnError)
{
  EXPECT_EQ(did_you_mean("young", {"density", "youngs"}), "; did you mean 'youngs'?");
  EXPECT_EQ(did_you_mean("colour", {"density", "youngs"}), "");
}

TEST(InputHelp, UnknownBodyKeywordNamesTheNearestOne)
{
  auto message = [](const std::vector<std::string>& words) {
    try {
      parse_body_spec(words);
    } catch (const SpecError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message({"file", "a.msh", "type", "2", "young", "1e9"}),
            "unknown keyword 'young'; did you mean 'youngs'?");
  EXPECT_EQ(message({"file", "a.msh", "poison", "0.3"}),
            "unknown keyword 'poison'; did you mean 'poisson'?");
  EXPECT_EQ(message({"file", "a.msh", "colour", "red"}), "unknown keyword 'colour'");
}

namespace
{
// The SpecError text of parsing `words` (after "file a.msh type 2"), or "no error".
std::string spec_error(std::vector<std::string> words)
{
  words.insert(words.begin(), {"file", "a.msh", "type", "2"});
  try {
    parse_body_spec(words);
  } catch (const SpecError& e) {
    return e.what();
  }
  return "no error";
}
} // namespace

TEST(InputHelp, MaterialOptionsComeFromTheTablesSyntax)
{
  using V = std::vector<std::string>;
  EXPECT_EQ(material_options(MaterialModel::Rankine),
            (V{"strength", "fracture_energy", "softening"}));
  EXPECT_EQ(material_options(MaterialModel::J2), (V{"yield", "hardening", "exponent"}));
  EXPECT_EQ(material_options(MaterialModel::JohnsonCook), (V{"eps0", "tmelt", "troom", "cp"}));
  EXPECT_EQ(material_options(MaterialModel::ZerilliArmstrong), (V{"eps0", "troom", "cp"}));
  EXPECT_EQ(material_options(MaterialModel::Elastic), V{});
}

TEST(InputHelp, MisspeltOptionOfAClauseIsNamedWithItsClause)
{
  // An option after the clause's last value reaches the keyword table.
  EXPECT_EQ(spec_error({"material", "johnson_cook", "1", "2", "0.3", "0.01", "1", "tmlt", "1800"}),
            "unknown keyword 'tmlt'; did you mean 'tmelt' (in 'material johnson_cook')?");
  EXPECT_EQ(spec_error({"fracture", "nodal", "evry", "5"}),
            "unknown keyword 'evry'; did you mean 'every' (in 'fracture nodal')?");
  EXPECT_EQ(spec_error({"erosion", "min_dt", "1e-9", "damge", "0.9"}),
            "unknown keyword 'damge'; did you mean 'damage' (in 'erosion')?");
  // A keyword of the table is still found after a clause.
  EXPECT_EQ(spec_error({"fracture", "nodal", "densty", "5"}),
            "unknown keyword 'densty'; did you mean 'density'?");
  // A required option misspelt: the material's own error names it.
  const std::string err =
      spec_error({"material", "rankine", "strength", "3e6", "fracture_enrgy", "100"});
  EXPECT_NE(err.find("strength and fracture_energy are required ('fracture_enrgy'; did you mean "
                     "'fracture_energy'?)"),
            std::string::npos)
      << err;
}

TEST(InputHelp, ValuesListedInFullGetNoGuess)
{
  // "model plastic" is one edit from "elastic", but the user wants a plastic material: where
  // the error lists every choice, no guess is added.
  EXPECT_EQ(spec_error({"model", "plastic"}),
            "keyword 'model' got 'plastic', expected one of: corotational elastic");
  EXPECT_EQ(spec_error({"material", "rankin"}).find("did you mean"), std::string::npos);
}

TEST(InputHelp, MisspeltMaterialOptionNamesTheNearest)
{
  // Open list (under fix fem/body): a required option missing where the list stopped.
  EXPECT_NE(spec_error({"material", "j2", "yeild", "1", "hardening", "2"})
                .find("yield and hardening are required ('yeild'; did you mean 'yield'?)"),
            std::string::npos);
  // Closed list (the whole word list is the material's): the unknown word itself.
  Material mat;
  EXPECT_NE(parse_material_arguments({"j2", "yield", "1", "hardening", "2", "exponnet", "0.5"}, mat,
                                     nullptr)
                .find("unknown word 'exponnet'; did you mean 'exponent'?"),
            std::string::npos);
  EXPECT_NE(
      parse_material_arguments(
          {"rankine", "strength", "1", "fracture_energy", "2", "softning", "linear"}, mat, nullptr)
          .find("unknown word 'softning'; did you mean 'softening'?"),
      std::string::npos);
}

TEST(InputHelp, BodiesTakeSiUnitsOnly)
{
  EXPECT_EQ(body_units_error("si"), "");
  for (const char* units : {"cgs", "lj", "metal", "real", "micro", "nano"}) {
    const std::string err = body_units_error(units);
    EXPECT_NE(err.find("needs 'units si'"), std::string::npos) << err;
    EXPECT_NE(err.find(std::string("'units ") + units + "'"), std::string::npos) << err;
  }
  EXPECT_NE(body_units_error("lj").find("without a 'units' command"), std::string::npos);
}

TEST(InputHelp, MeshUnitHintWhenTheMeshLooksLikeMillimetres)
{
  // A mesh drawn in mm is 1000 times too large: elements 100 to 1000 times the limit.
  EXPECT_NE(mesh_unit_hint(1.0, 0.002, 10).find("scale 0.001"), std::string::npos);
  EXPECT_NE(mesh_unit_hint(0.1, 0.001, 1).find("millimetres"), std::string::npos);
  // A box over 100 m with a limit below 1 m, whatever the ratio.
  EXPECT_NE(mesh_unit_hint(5.0, 0.5, 300).find("(300 across)"), std::string::npos);
  // A mesh merely too coarse (ratio below 100, a metre-sized box) or far off: no hint.
  EXPECT_EQ(mesh_unit_hint(0.05, 0.01, 1.0), "");
  EXPECT_EQ(mesh_unit_hint(50.0, 0.01, 60), "");
  EXPECT_EQ(mesh_unit_hint(5000.0, 2.0, 5000), "");
}

TEST(InputHelp, LargestSideOfTheBoundingBox)
{
  EXPECT_EQ(largest_side({}), 0.0);
  EXPECT_DOUBLE_EQ(largest_side({0, 0, 0, 2, -1, 0.5, -1, 3, 0}), 4.0); // y from -1 to 3
}

// CELL.json: every error names the file, the JSON path and the expected value; a good file reads back.
#include "dem_sampler/driver/cell_input.hpp"

#include <gtest/gtest.h>

#include "common/json_input.hpp"
#include "tests/app/error_case.hpp"
#include "tests/app/json_patch.hpp"
#include "tests/app/temp_dir.hpp"

namespace grainbank {
namespace {

using testing::ErrorCase;
using testing::with;
using testing::without;

const nlohmann::json kGoodCell = nlohmann::json::parse(R"({
  "material": {"density": 920, "k_n": 2000, "k_t": 600, "restitution": 0.3, "friction": 0.2,
               "bond": {"tensile_strength": 8e-4, "shear_strength": 9.6e-4, "exponent": 2,
                        "bonding_distance": 0.05}},
  "effects": {"cohesion": true},
  "preparation": {"spheres": 40, "diameter": {"min": 3.4e-4, "max": 4.0e-4}, "pressure": 1000, "seed": 7,
                  "inertial_number": 0.01}
})");

class CellInputError : public ::testing::TestWithParam<ErrorCase> {};

TEST_P(CellInputError, NamesFilePathAndExpectedValue) {
  const testing::TempDir dir;
  const auto file = dir.write("cell.json", GetParam().text);
  testing::expect_input_error<common::InputError>([&] { app::load_cell_input(file); }, file.string(),
                                                  GetParam().expected);
}

INSTANTIATE_TEST_SUITE_P(
    Table, CellInputError,
    ::testing::Values(
        ErrorCase{"MalformedJson", "{\"material\": {\"density\": 920,}}",
                  {"line 1, column 30", "malformed JSON", "unexpected '}'"}},
        ErrorCase{"NumberOverflow", "{\"material\": {\"density\": 1e999}}", {"malformed JSON", "1e999"}},
        ErrorCase{"RootNotObject", "[1, 2]", {": /: expected an object, got an array of 2 entries"}},
        ErrorCase{"WrongType", with(kGoodCell, "/material/k_n", "2000"),
                  {"/material/k_n: expected a positive number, got a string (\"2000\")"}},
        ErrorCase{"NegativeStiffness", with(kGoodCell, "/material/k_n", -5),
                  {"/material/k_n: expected a positive number, got -5"}},
        ErrorCase{"NanAsString", with(kGoodCell, "/material/friction", "NaN"),
                  {"/material/friction: expected a number >= 0, got a string (\"NaN\")"}},
        ErrorCase{"NullValue", with(kGoodCell, "/material/density", nullptr),
                  {"/material/density: expected a positive number, got null"}},
        ErrorCase{"OutOfRange", with(kGoodCell, "/material/restitution", 1.5),
                  {"/material/restitution: expected a number in (0, 1], got 1.5"}},
        ErrorCase{"MissingField", without(kGoodCell, "/material/density"),
                  {"/material/density: required field missing; expected a positive number"}},
        ErrorCase{"UnknownKey", with(kGoodCell, "/material/kn", 1),
                  {"/material/kn: unknown key", "density, k_n, k_t"}},
        ErrorCase{"UnknownTopLevelKey", with(kGoodCell, "/preperation", 1),
                  {"/preperation: unknown key", "preparation"}},
        ErrorCase{"BondMissingWithCohesion", without(kGoodCell, "/material/bond"),
                  {"/material/bond: required field missing", "/effects/cohesion is true"}},
        ErrorCase{"BondWithoutCohesion", with(kGoodCell, "/effects/cohesion", false),
                  {"/material/bond: given but /effects/cohesion is false"}},
        ErrorCase{"EngineCheckMapsToJsonPath", with(kGoodCell, "/material/contact_weight", 1),
                  {"/material/contact_weight: expected a number < 1 when bonds are on"}},
        ErrorCase{"EffectNotBoolean", with(kGoodCell, "/effects/cohesion", "yes"),
                  {"/effects/cohesion: expected true or false, got a string (\"yes\")"}},
        ErrorCase{"SpheresNotInteger", with(kGoodCell, "/preparation/spheres", 12.5),
                  {"/preparation/spheres: expected an integer in [2, 10000000], got 12.5"}},
        ErrorCase{"DiameterMaxBelowMin", with(kGoodCell, "/preparation/diameter/max", 1e-4),
                  {"/preparation/diameter/max: expected a number >= 0.00034, got 0.0001"}},
        ErrorCase{"EquilibriumDriftNotPositive", with(kGoodCell, "/preparation/equilibrium_drift", 0),
                  {"/preparation/equilibrium_drift: expected a positive number, got 0"}},
        ErrorCase{"PreparationAndPacking", with(kGoodCell, "/packing", "p.csv"), {"/packing: give either"}},
        ErrorCase{"NoCellSource", without(kGoodCell, "/preparation"), {"/preparation: required field missing"}},
        ErrorCase{"SkinOutsidePacking", with(kGoodCell, "/skin", 0.1), {"/skin: only used with /packing"}},
        // Restitution 0.3: ζ = 0.358, so the undamped bound 0.2 becomes 0.2 (√(1 + ζ²) − ζ) = 0.141.
        ErrorCase{"TimeStepFactorItsDashpotsMakeUnstable", with(kGoodCell, "/preparation/q_t", 0.15),
                  {"/preparation/q_t: expected a number in (0, 0.1408", "restitution 0.3", "got 0.15"}},
        ErrorCase{"DefaultTimeStepFactorTooLargeForHeavyDashpots", with(kGoodCell, "/material/restitution", 0.01),
                  {"/preparation: q_t (default 0.1): expected a number in (0, 0.0941", "got 0.1"}}),
    testing::case_name);

TEST(CellInput, GoodFileReadsBackWithDefaults) {
  const testing::TempDir dir;
  const app::CellInput in = app::load_cell_input(dir.write("cell.json", kGoodCell.dump()));
  EXPECT_EQ(in.material.density, 920);
  EXPECT_EQ(in.material.contact.k_n, 2000);
  EXPECT_EQ(in.material.contact.k_t, 600);
  EXPECT_EQ(in.material.contact.contact_weight, 0.5);
  EXPECT_TRUE(in.material.effects.bonds);
  EXPECT_FALSE(in.material.effects.kinetic_stress);
  EXPECT_EQ(in.material.bond.tensile_strength, 8e-4);
  EXPECT_EQ(in.material.bond.bonding_distance, 0.05);
  ASSERT_TRUE(in.preparation.has_value());
  EXPECT_FALSE(in.packing.has_value());
  EXPECT_EQ(in.preparation->spheres, 40u);
  EXPECT_EQ(in.preparation->min_diameter, 3.4e-4);
  EXPECT_EQ(in.preparation->seed, 7u);
  EXPECT_EQ(in.preparation->inertial_number, 0.01);
  EXPECT_EQ(in.preparation->local_damping, dem::PreparationSpec{}.local_damping);
  EXPECT_EQ(in.preparation->equilibrium_hold, dem::PreparationSpec{}.equilibrium_hold);
}

TEST(CellInput, PackingFileIsRelativeToTheJsonFolderAndBonded) {
  const testing::TempDir dir;
  // 27 touching spheres of radius 0.5 on a cubic lattice of spacing 1 in a 3x3x3 cell.
  std::string csv = "# h\n3,0,0\n0,3,0\n0,0,3\n# x,y,z,radius\n";
  for (int i = 0; i < 27; ++i)
    csv += std::to_string(0.5 + i % 3) + "," + std::to_string(0.5 + i / 3 % 3) + "," + std::to_string(0.5 + i / 9) +
           ",0.5\n";
  std::filesystem::create_directory(dir.path() / "packings");
  dir.write("packings/cubic.csv", csv);
  nlohmann::json cell = kGoodCell;
  cell.erase("preparation");
  cell["packing"] = "packings/cubic.csv";
  cell["skin"] = 0.2;
  const app::CellInput in = app::load_cell_input(dir.write("cell.json", cell.dump()));
  ASSERT_TRUE(in.packing.has_value());
  EXPECT_EQ(*in.packing, dir.path() / "packings/cubic.csv");
  const dem::DemCell built = app::build_cell(in);
  EXPECT_EQ(built.size(), 27u);
  EXPECT_DOUBLE_EQ(built.skin(), 0.2 * 1.0);
  EXPECT_EQ(built.measures().bonds, 81);  // every lattice neighbour touches: 3 bonds per sphere
}

}  // namespace
}  // namespace grainbank

// Packing files: every bad line is reported with the file name and the line number.
#include "dem_sampler/driver/packing_csv.hpp"

#include <gtest/gtest.h>

#include "common/json_input.hpp"
#include "tests/app/error_case.hpp"
#include "tests/app/temp_dir.hpp"

namespace grainbank {
namespace {

using testing::ErrorCase;

const std::string kCell = "# cell matrix\n1,0,0\n0,1,0\n0,0,1\n";
const std::string kSpheres = "0.1,0.1,0.1,0.2\n0.6, 0.6, 0.6, 0.2\n";

class PackingError : public ::testing::TestWithParam<ErrorCase> {};

TEST_P(PackingError, NamesFileLineAndExpectedValue) {
  const testing::TempDir dir;
  const auto file = dir.write("packing.csv", GetParam().text);
  testing::expect_input_error<common::InputError>([&] { app::read_packing_csv(file); }, file.string(),
                                                  GetParam().expected);
}

INSTANTIATE_TEST_SUITE_P(
    Table, PackingError,
    ::testing::Values(
        ErrorCase{"ShortCellRow", "1,0\n0,1,0\n0,0,1\n" + kSpheres,
                  {"packing.csv:1: expected 3 numbers (a row of the cell matrix h), got 2"}},
        ErrorCase{"TextField", kCell + kSpheres + "0.3,abc,0.3,0.2\n",
                  {"packing.csv:7: field 2: expected a finite number, got \"abc\""}},
        ErrorCase{"NanField", kCell + kSpheres + "0.3,0.3,nan,0.2\n",
                  {"packing.csv:7: field 3: expected a finite number, got \"nan\""}},
        ErrorCase{"NegativeRadius", kCell + kSpheres + "0.3,0.3,0.3,-0.1\n",
                  {"packing.csv:7: radius: expected a positive number, got -0.1"}},
        ErrorCase{"TooManyFields", kCell + kSpheres + "0.3,0.3,0.3,0.1,7\n",
                  {"packing.csv:7: expected 4 numbers (x, y, z, radius), got 5"}},
        ErrorCase{"FlatCell", "1,0,0\n0,1,0\n0,0,0\n" + kSpheres,
                  {"packing.csv:3: cell matrix h: expected a positive determinant"}},
        ErrorCase{"OneSphere", kCell + "0.1,0.1,0.1,0.2\n", {"expected at least 2 spheres", "got 1"}},
        ErrorCase{"NoCell", "# nothing\n1,0,0\n", {"expected 3 rows of the cell matrix h", "got 1"}}),
    testing::case_name);

TEST(PackingCsv, ReadsCellColumnsAndSpheresSkippingComments) {
  const testing::TempDir dir;
  const app::Packing p = app::read_packing_csv(dir.write("p.csv", "2 0.5 0\n0 2 0\n0 0 2\n\n# spheres\n" + kSpheres));
  EXPECT_EQ(p.h(0, 1), 0.5) << "rows as written: column 1 (second cell vector) has x component 0.5";
  EXPECT_EQ(p.h(2, 2), 2);
  ASSERT_EQ(p.radii.size(), 2u);
  EXPECT_EQ(p.positions[1], dem::Vec3(0.6, 0.6, 0.6));
  EXPECT_EQ(p.radii[1], 0.2);
}

}  // namespace
}  // namespace grainbank

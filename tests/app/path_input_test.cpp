// PATH.json: every error names the file, the JSON path and the expected value; a good file reads back.
#include "dem_sampler/driver/path_input.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "common/json_input.hpp"
#include "tests/app/error_case.hpp"
#include "tests/app/json_patch.hpp"
#include "tests/app/temp_dir.hpp"

namespace grainbank {
namespace {

using testing::ErrorCase;
using testing::with;
using testing::without;

const nlohmann::json kGoodPath = nlohmann::json::parse(R"({
  "segments": [{"L": [[0, 2], [0, 0]], "strain": 0.1},
               {"L": [[-1, 0], [0, 1]], "duration": 0.05}],
  "record_interval": 0.01,
  "substepping": {"q_n": 10}
})");

class PathInputError : public ::testing::TestWithParam<ErrorCase> {};

TEST_P(PathInputError, NamesFilePathAndExpectedValue) {
  const testing::TempDir dir;
  const auto file = dir.write("path.json", GetParam().text);
  testing::expect_input_error<common::InputError>([&] { app::load_path(file); }, file.string(), GetParam().expected);
}

INSTANTIATE_TEST_SUITE_P(
    Table, PathInputError,
    ::testing::Values(
        ErrorCase{"MalformedJson", "{\n\"segments\": [\n", {"line 3", "malformed JSON"}},
        ErrorCase{"GradientNotSquare", with(kGoodPath, "/segments/0/L", {{0, 1}}),
                  {"/segments/0/L: expected a 2x2 array [[Lxx, Lxy], [Lyx, Lyy]]", "got an array of 1 entry"}},
        ErrorCase{"GradientEntryNotNumber", with(kGoodPath, "/segments/0/L/1/0", "x"),
                  {"/segments/0/L/1/0: expected a finite number, got a string"}},
        ErrorCase{"MissingRecordInterval", without(kGoodPath, "/record_interval"),
                  {"/record_interval: required field missing; expected a positive number"}},
        ErrorCase{"NegativeDuration", with(kGoodPath, "/segments/1/duration", -1),
                  {"/segments/1/duration: expected a positive number, got -1"}},
        ErrorCase{"DurationAndStrain", with(kGoodPath, "/segments/1/strain", 0.1),
                  {"/segments/1/strain: give either duration or strain"}},
        ErrorCase{"NoDurationNorStrain", without(kGoodPath, "/segments/0/strain"),
                  {"/segments/0/duration: required field missing"}},
        ErrorCase{"StrainOfARotation", with(kGoodPath, "/segments/0/L", {{0, 1}, {-1, 0}}),
                  {"/segments/0/strain: L has no symmetric part"}},
        ErrorCase{"PressureNotPositive", with(kGoodPath, "/segments/1/pressure", 0),
                  {"/segments/1/pressure: expected a positive number, got 0"}},
        ErrorCase{"PressureNaN", with(kGoodPath, "/segments/1/pressure", "NaN"),
                  {"/segments/1/pressure: expected a positive number, got a string (\"NaN\")"}},
        ErrorCase{"PressureOnARotation",
                  with(nlohmann::json::parse(with(kGoodPath, "/segments/1/L", {{0, 1}, {-1, 0}})),
                       "/segments/1/pressure", 100),
                  {"/segments/1/pressure: a pressure-controlled segment needs a stretching L"}},
        ErrorCase{"EmptySegments", with(kGoodPath, "/segments", nlohmann::json::array()),
                  {"/segments: expected a non-empty array", "got an empty array"}},
        ErrorCase{"UnknownKey", with(kGoodPath, "/substeping", 1),
                  {"/substeping: unknown key", "segments, record_interval, substepping"}},
        ErrorCase{"SubstepCountZero", with(kGoodPath, "/substepping/q_n", 0),
                  {"/substepping/q_n: expected an integer in [1, 1000000], got 0"}},
        ErrorCase{"TimeStepFactorAboveStableRange", with(kGoodPath, "/substepping/q_t", 0.25),
                  {"/substepping/q_t: expected a number in (0, 0.2]", "got 0.25"}}),
    testing::case_name);

TEST(PathInput, GoodFileReadsBackInPlaneStrain) {
  const testing::TempDir dir;
  const app::PathSpec path = app::load_path(dir.write("path.json", kGoodPath.dump()));
  ASSERT_EQ(path.segments.size(), 2u);
  const dem::Mat3& L = path.segments[0].L;
  EXPECT_EQ(L(0, 1), 2);
  EXPECT_EQ(L.row(2).norm() + L.col(2).norm(), 0) << "plane strain: no z row or column";
  // ||sym L|| of simple shear at rate 2 is sqrt(2): strain 0.1 takes 0.1 / sqrt(2) s.
  EXPECT_DOUBLE_EQ(path.segments[0].duration, 0.1 / std::sqrt(2.0));
  EXPECT_EQ(path.segments[1].duration, 0.05);
  EXPECT_EQ(path.record_interval, 0.01);
  EXPECT_EQ(path.substepping.q_n, 10);
  EXPECT_EQ(path.substepping.q_t, dem::Substepping{}.q_t);
  EXPECT_EQ(path.substepping.q_sigma, dem::Substepping{}.q_sigma);
}

}  // namespace
}  // namespace grainbank

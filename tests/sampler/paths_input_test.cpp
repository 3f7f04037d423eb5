// PATHS.json: explicit, replay and generated paths with shared defaults; errors name the file and the
// JSON path; the canonical spec reads back to the same plan.
#include <gtest/gtest.h>

#include "dem_sampler/sampler/paths_input.hpp"
#include "tests/sampler/sampler_test_util.hpp"

namespace grainbank::sampler {
namespace {

std::string error_of(const std::string& text) {
  const test::TempDir dir;
  try {
    load_paths_file(dir.write("paths.json", text));
  } catch (const common::InputError& e) {
    const std::string message = e.what();
    const std::string prefix = (dir.path() / "paths.json").string() + ": ";
    return message.starts_with(prefix) ? message.substr(prefix.size()) : "(file not named) " + message;
  }
  return "(no error)";
}

TEST(PathsInput, ReadsExplicitReplayAndGeneratedPaths) {
  const test::TempDir dir;
  const auto plans = load_paths_file(dir.write("paths.json", test::kPaths));
  ASSERT_EQ(plans.size(), 6u);
  EXPECT_EQ(plans[0].path.segments.size(), 1u);
  EXPECT_DOUBLE_EQ(plans[0].path.segments[0].duration, 0.004);
  EXPECT_EQ(plans[0].snapshot_interval, 10);
  ASSERT_EQ(plans[1].path.segments.size(), 3u);  // one increment per replayed L
  EXPECT_DOUBLE_EQ(plans[1].path.segments[2].duration, 2e-4);
  EXPECT_EQ(plans[1].path.segments[2].L(0, 1), 1);
  EXPECT_EQ(record_count(plans[1]), 4);
  EXPECT_EQ(plans[5].path.segments.size(), 2u);
}

// A pressure-controlled segment keeps its pressure in the canonical spec; the others have no such
// key, so the specs (and hashes) of paths registered before it existed do not change.
TEST(PathsInput, CanonicalSpecRoundTrips) {
  const test::TempDir dir;
  std::vector<PathPlan> plans = load_paths_file(dir.write("paths.json", test::kPaths));
  EXPECT_EQ(to_json(plans[0]).dump().find("pressure"), std::string::npos);
  plans[0].path.segments[0].pressure = 1500;
  EXPECT_EQ(to_json(plans[0])["segments"][0]["pressure"], 1500.0);
  for (const PathPlan& plan : plans) {
    const nlohmann::json spec = to_json(plan);
    const nlohmann::json reread = nlohmann::json::parse(spec.dump());
    EXPECT_EQ(to_json(plan_from_json(common::JsonNode(reread, "spec"))).dump(), spec.dump());
  }
}

TEST(PathsInput, ErrorsNameTheJsonPath) {
  EXPECT_EQ(error_of(R"({"paths": [{"segments": [{"L": [[0, 1], [0, 0]], "duration": 1}]}]})"),
            "/paths/0/record_interval: required field missing; expected a positive number [s] (here or at the top level)");
  EXPECT_EQ(error_of(R"({"record_interval": 1, "paths": [{"replay": [[[0, 1], [0]]]}]})"),
            "/paths/0/replay/0/1: expected a row of 2 numbers, got an array of 1 entry");
  EXPECT_EQ(error_of(R"({"record_interval": 1, "generators": [{"count": 2, "rate": {"min": 1, "max": 2},
                         "strain": 0.1, "changes": ["flip"]}]})"),
            "/generators/0/changes/0: expected \"reversal\", \"rotation\" or \"fresh\", got a string (\"flip\")");
  EXPECT_EQ(error_of(R"({"record_interval": 1})"), "/: no paths: give a non-empty \"paths\", \"generators\" or \"probes\" array");
  EXPECT_NE(error_of(R"({"record_interval": 1, "pahts": []})").find("unknown key"), std::string::npos);
}

}  // namespace
}  // namespace grainbank::sampler

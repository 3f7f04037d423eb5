// The generic readers of common/json_input: message format, ranges, integers, unknown keys.
#include "common/json_input.hpp"

#include <gtest/gtest.h>

#include "tests/app/error_case.hpp"
#include "tests/app/temp_dir.hpp"

namespace grainbank {
namespace {

using common::InputError;
using common::JsonNode;
using common::Range;

TEST(JsonInput, MessageNamesFilePathExpectedAndGot) {
  const nlohmann::json doc = nlohmann::json::parse(R"({"material": {"k_n": -5}})");
  const JsonNode root(doc, "cell.json");
  try {
    root.at("material", "an object").number("k_n", Range::positive());
    FAIL();
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "cell.json: /material/k_n: expected a positive number, got -5");
  }
}

TEST(JsonInput, RangesDescribeThemselves) {
  EXPECT_EQ(Range::positive().describe(), "a positive number");
  EXPECT_EQ(Range::at_least(0).describe(), "a number >= 0");
  EXPECT_EQ(Range::between(0, 1, true, false).describe(), "a number in (0, 1]");
  EXPECT_EQ(Range::any().describe(), "a finite number");
  EXPECT_FALSE(Range::any().contains(std::numeric_limits<double>::infinity()));
  EXPECT_FALSE(Range::any().contains(std::numeric_limits<double>::quiet_NaN()));
}

TEST(JsonInput, IntegersAcceptExactFloatsOnly) {
  const nlohmann::json doc = nlohmann::json::parse(R"({"a": 125.0, "b": 12.5, "c": 18446744073709551615})");
  const JsonNode root(doc, "f.json");
  EXPECT_EQ(root.at("a", "").integer(2), 125);
  testing::expect_input_error<InputError>([&] { root.at("b", "").integer(2); }, "f.json",
                                          {"/b: expected an integer >= 2, got 12.5"});
  testing::expect_input_error<InputError>([&] { root.at("c", "").integer(0); }, "f.json", {"/c: expected an integer"});
}

TEST(JsonInput, UnknownKeyListsAllowedKeys) {
  const nlohmann::json doc = nlohmann::json::parse(R"({"a": {"x": 1, "y/z": 2}})");
  const JsonNode root(doc, "f.json");
  testing::expect_input_error<InputError>([&] { root.at("a", "").allow_only({"x", "w"}); }, "f.json",
                                          {"/a/y~1z: unknown key", "allowed keys here: x, w"});
}

TEST(JsonInput, MalformedFileGivesLineAndColumn) {
  const testing::TempDir dir;
  const auto file = dir.write("bad.json", "{\n  \"a\": 1,\n  \"b\": }\n");
  testing::expect_input_error<InputError>([&] { common::load_json_file(file); }, file.string(),
                                          {"line 3, column 8", "malformed JSON", "unexpected '}'"});
}

TEST(JsonInput, MissingFileIsAnInputError) {
  testing::expect_input_error<InputError>([] { common::load_json_file("/nonexistent/cell.json"); },
                                          "/nonexistent/cell.json", {"cannot open"});
}

}  // namespace
}  // namespace grainbank

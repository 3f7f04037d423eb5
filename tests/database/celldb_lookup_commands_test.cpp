// `celldb query` and the key coverage of `celldb info` on a real library.
#include <gtest/gtest.h>

#include <regex>
#include <sstream>

#include "database/celldb/bench_command.hpp"
#include "database/celldb/info_command.hpp"
#include "database/celldb/query_command.hpp"
#include "tests/database/lookup_test_util.hpp"

namespace grainbank::db::test {
namespace {

TEST(CelldbLookupCommands, BenchPrintsTheLookupLineAndAgreesWithBruteForce) {
  celldb::BenchOptions options;
  options.records = 3000;
  options.queries = 400;
  options.brute_queries = 40;
  std::ostringstream text;
  ASSERT_EQ(celldb::run_bench(options, text), 0);
  const std::string first = text.str().substr(0, text.str().find('\n'));
  EXPECT_TRUE(std::regex_match(first, std::regex(R"(lookup us/query: [0-9.e+-]+ \(brute force: [0-9.e+-]+\))"))) << first;
  EXPECT_NE(text.str().find("insert records/s: "), std::string::npos);
  EXPECT_NE(text.str().find("open time: "), std::string::npos);
  EXPECT_NE(text.str().find("DESIGN.md"), std::string::npos);

  options.json = true;
  std::ostringstream json;
  ASSERT_EQ(celldb::run_bench(options, json), 0);
  const nlohmann::json figures = nlohmann::json::parse(json.str());
  EXPECT_EQ(figures["records"], 3000);
  EXPECT_EQ(figures["brute_force_agreement"], 1.0);  // exact: same nearest, distance and hit/miss
  EXPECT_NEAR(figures["far_share"].get<double>(), 0.2, 1e-12);
  for (const char* key : {"lookup_us_per_query", "lookup_us_per_query_near_paths", "lookup_us_per_query_far",
                          "brute_force_us_per_query", "insert_records_per_s", "open_s"})
    EXPECT_GT(figures[key].get<double>(), 0.0) << key;
  EXPECT_EQ(figures["baseline"]["lookup_us_per_query"], 9.0);
}

TEST(CelldbLookupCommands, QueryAnswersAStateGivenAsJson) {
  TempDir tmp;
  Library library = Library::create(tmp.path() / "LIB", small_material());
  const std::vector<Record> records = shear_path(20);
  add_done_path(library, "rank0", records);
  const Record& r = records[6];
  const nlohmann::json state = {{"F", {{r.F(0, 0), r.F(0, 1)}, {r.F(1, 0), r.F(1, 1)}}},
                                {"L", {{r.L(0, 0), r.L(0, 1)}, {r.L(1, 0), r.L(1, 1)}}},
                                {"D", r.damage}};
  celldb::QueryOptions options{tmp.path() / "LIB", state.dump(), {3, 0.5}, true};
  std::ostringstream out;
  ASSERT_EQ(celldb::run_query(options, out), 0);
  const nlohmann::json answer = nlohmann::json::parse(out.str());
  EXPECT_EQ(answer["hit"], true);
  EXPECT_LT(answer["distance"].get<double>(), 1e-9);
  EXPECT_EQ(answer["nearest"]["record"], 6);
  EXPECT_NEAR(answer["stress"][0][0].get<double>(), r.stress[0], 1e-9 * std::abs(r.stress[0]));
  EXPECT_NEAR(answer["stress"][0][1].get<double>(), r.stress[3], 1e-9 * std::abs(r.stress[3]));

  std::ostringstream text;
  options.json = false;
  ASSERT_EQ(celldb::run_query(options, text), 0);
  EXPECT_NE(text.str().find("hit             yes"), std::string::npos) << text.str();

  options.state = R"({"F": [[1, 0], [0, -1]]})";
  EXPECT_THROW(celldb::run_query(options, text), std::invalid_argument);
  options.state = R"({"F": [[1, 0], [0, 1]], "X": 1})";
  try {
    celldb::run_query(options, text);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("--state: /X: unknown key"), std::string::npos) << e.what();
  }
}

TEST(CelldbLookupCommands, InfoReportsKeyCoverage) {
  TempDir tmp;
  Library library = Library::create(tmp.path() / "LIB", small_material());
  add_done_path(library, "rank0", shear_path(20));
  const nlohmann::json coverage = celldb::library_info(tmp.path() / "LIB")["key_coverage"];
  EXPECT_EQ(coverage["records"], 20);
  EXPECT_GT(coverage["occupied_unit_cells"].get<int>(), 1);
  EXPECT_LE(coverage["occupied_unit_cells"].get<int>(), 20);
  // Damage runs from 0 to 0.19 along the path: key 0 to 0.19 / 0.05.
  EXPECT_NEAR(coverage["range"]["damage"][1].get<double>(), 0.19 / 0.05, 1e-9);
  EXPECT_NEAR(coverage["range"]["damage"][0].get<double>(), 0.0, 1e-12);
  std::ostringstream text;
  celldb::run_info({tmp.path() / "LIB", false}, text);
  EXPECT_NE(text.str().find("key coverage    20 records"), std::string::npos) << text.str();
}

}  // namespace
}  // namespace grainbank::db::test

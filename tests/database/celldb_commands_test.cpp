// `celldb info` and `celldb verify` on a real library.
#include <gtest/gtest.h>

#include <sstream>

#include "database/celldb/info_command.hpp"
#include "database/celldb/verify_command.hpp"
#include "tests/database/store_test_util.hpp"

namespace grainbank::db::test {
namespace {

TEST(CelldbCommands, InfoReportsCountsSizesAndMaterial) {
  TempDir tmp;
  const dem::Material material = small_material();
  {
    Library library = Library::create(tmp.path() / "LIB", material);
    ShardWriter writer(library, "rank0");
    const dem::DemCell c = small_cell();
    const std::int64_t t = writer.add_template(material, {}, {c.state(), c.skin()});
    const std::int64_t done = library.add_path(t, {}, material);
    library.add_path(t, {}, material);
    writer.start_path(done);
    writer.append_records(done, {sample_record(0), sample_record(1), sample_record(2)});
    writer.finish_path(done, PathStatus::done, 0.5);
  }
  const nlohmann::json info = celldb::library_info(tmp.path() / "LIB");
  EXPECT_EQ(info["counts"]["templates"], 1);
  EXPECT_EQ(info["counts"]["paths"], 2);
  EXPECT_EQ(info["paths"]["done"]["records"], 3);
  EXPECT_EQ(info["paths"]["pending"]["paths"], 1);
  EXPECT_EQ(info["committed_records"], 3);
  EXPECT_EQ(info["material"]["contact"]["friction"], 0.5);
  EXPECT_GT(info["bytes"]["shards"].get<double>(), 0);

  std::ostringstream text;
  EXPECT_EQ(celldb::run_info({tmp.path() / "LIB", false}, text), 0);
  EXPECT_NE(text.str().find("records         3 committed"), std::string::npos) << text.str();
  std::ostringstream json;
  EXPECT_EQ(celldb::run_info({tmp.path() / "LIB", true}, json), 0);
  EXPECT_EQ(nlohmann::json::parse(json.str()), info);
}

TEST(CelldbCommands, VerifyExitCodeFollowsOrphansAndRepair) {
  TempDir tmp;
  const dem::Material material = small_material();
  {
    Library library = Library::create(tmp.path() / "LIB", material);
    ShardWriter writer(library, "rank0");
    const dem::DemCell c = small_cell();
    writer.shard().write_template("0123456789abcdef", {c.state(), c.skin()});  // never committed
    writer.shard().flush();
  }
  std::ostringstream out;
  EXPECT_EQ(celldb::run_verify({tmp.path() / "LIB", false, false}, out), 1);
  EXPECT_NE(out.str().find("orphan: "), std::string::npos) << out.str();
  EXPECT_NE(out.str().find("/templates/0123456789abcdef"), std::string::npos) << out.str();
  std::ostringstream repaired;
  EXPECT_EQ(celldb::run_verify({tmp.path() / "LIB", true, false}, repaired), 0);
  EXPECT_NE(repaired.str().find("orphan (removed)"), std::string::npos) << repaired.str();
  std::ostringstream json;
  EXPECT_EQ(celldb::run_verify({tmp.path() / "LIB", false, true}, json), 0);
  EXPECT_EQ(nlohmann::json::parse(json.str())["clean"], true);
}

}  // namespace
}  // namespace grainbank::db::test

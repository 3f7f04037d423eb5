// `celldb audit` on a real small library sampled with the real sampler (64-sphere cohesive cell, six
// short paths, one of them pressure-controlled, snapshots every 10 records): a clean library replays bit for bit, a record whose stress
// was overwritten in its HDF5 shard is flagged with its path and index, leave-one-path-out errors are
// finite and far above the (round-off) in-index errors, and the run leaves its outputs and an audits row.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "tests/sampler/sampler_test_util.hpp"
#include "database/celldb/audit_command.hpp"
#include "dem_sampler/sampler/library_writer.hpp"
#include "dem_sampler/sampler/paths_input.hpp"
#include "dem_sampler/sampler/sampler.hpp"
#include "database/store/audit_log.hpp"
#include "database/store/path_queue.hpp"
#include "dem_sampler/sampler/template_builder.hpp"

namespace grainbank::audit {
namespace {

namespace fs = std::filesystem;
using sampler::test::kCell;
using sampler::test::kPaths;
using sampler::test::TempDir;

// Column of sigma_xx in a records row (SCHEMA.md: t, F (9), L (9), then the stresses).
constexpr hsize_t kSigmaXx = 19;

// kPaths with its first path's shear held at a pressure (mixed control, path_driver.hpp): its replay
// from the snapshot at record 10 continues the pressure servo from that record's L.
std::string audit_paths() {
  std::string paths = kPaths;
  const std::string shear = R"("duration": 0.004})";
  paths.replace(paths.find(shear), shear.size(), R"("duration": 0.004, "pressure": 2000})");
  return paths;
}

// Prepares the template and samples every path of audit_paths() in-process, as `dem_sampler prepare`
// and `sample --threads 1` do.
void build_library(const TempDir& dir, const fs::path& library_dir) {
  const app::CellInput input = app::load_cell_input(dir.write("cell.json", kCell));
  db::Library library = db::Library::create(library_dir, input.material);
  const std::int64_t template_id = sampler::prepare_template(library, "templates", input).id;
  for (const sampler::PathPlan& plan : sampler::load_paths_file(dir.write("paths.json", audit_paths())))
    library.add_path(template_id, sampler::to_json(plan), library.material());
  db::ShardWriter shard(library, "rank0");
  sampler::LibraryWriter writer(library, shard);
  sampler::ListWorkSource source(db::pending_paths(library.catalogue()));
  const sampler::SampleSummary summary = sampler::run_paths(writer, source, {});
  if (summary.done != 6) throw std::runtime_error("the audit test library did not sample its six paths");
}

// Overwrites sigma_xx of one committed record directly in the shard, as silent corruption would.
void corrupt_stress(const fs::path& library_dir, std::int64_t path_id, hsize_t record, double value) {
  db::Library library = db::Library::open(library_dir);
  const fs::path file = library.shard_path(library.catalogue().shard(*library.catalogue().path(path_id).shard_id));
  const db::h5::Object shard = db::h5::open_file(file, true);
  const db::h5::Object table = db::h5::open_dataset(shard, db::Shard::path_group(path_id) + "/records");
  const hid_t space = H5Dget_space(table.id());
  const hsize_t start[2] = {record, kSigmaXx}, count[2] = {1, 1};
  H5Sselect_hyperslab(space, H5S_SELECT_SET, start, nullptr, count, nullptr);
  const hid_t memory = H5Screate_simple(1, count, nullptr);
  const herr_t status = H5Dwrite(table.id(), H5T_NATIVE_DOUBLE, memory, space, H5P_DEFAULT, &value);
  H5Sclose(memory);
  H5Sclose(space);
  if (status < 0) throw std::runtime_error("cannot overwrite the record in " + file.string());
  db::h5::flush(shard);
}

class Audit : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir("grainbank-audit");
    build_library(*dir_, dir_->path() / "base");
  }
  static void TearDownTestSuite() { delete dir_; }

  // A fresh copy of the sampled library.
  fs::path library_copy(const std::string& name) const {
    fs::copy(dir_->path() / "base", here_.path() / name, fs::copy_options::recursive);
    return here_.path() / name;
  }
  fs::path library() const { return library_copy("LIB"); }
  // Every path and every record: the checks do not depend on the draw.
  celldb::AuditCommandOptions everything(const fs::path& lib) const {
    celldb::AuditCommandOptions options;
    options.library = lib;
    options.audit.sample = {100, 10'000, 1};
    options.out = here_.path() / "out";
    options.json = true;
    return options;
  }
  // Runs the command; returns its exit code and parsed JSON output.
  static std::pair<int, nlohmann::json> run(const celldb::AuditCommandOptions& options) {
    std::ostringstream out;
    const int code = celldb::run_audit(options, out);
    return {code, nlohmann::json::parse(out.str())};
  }

  static TempDir* dir_;
  TempDir here_;
};
TempDir* Audit::dir_ = nullptr;

TEST_F(Audit, CleanLibraryReplaysEveryRecordBitForBit) {
  const auto [code, summary] = run(everything(library()));
  EXPECT_EQ(code, 0);
  const nlohmann::json& d = summary["determinism"];
  // Six paths of 21, 4 and four generated lengths: every record but each path's record 0 is replayed.
  std::size_t expected = 0;
  for (const auto& [id, rows] : sampler::test::all_records(here_.path() / "LIB")) expected += rows.size() - 1;
  EXPECT_EQ(d["checked"], expected);
  EXPECT_EQ(d["flagged"], 0);
  EXPECT_TRUE(d["flagged_records"].empty());
  EXPECT_EQ(d["max"].get<double>(), 0.0);  // restored snapshots continue bit for bit
  EXPECT_EQ(summary["sample"]["paths"].size(), 6u);
}

TEST_F(Audit, CorruptedRecordIsFlaggedWithItsPathAndIndex) {
  const fs::path lib = library();
  // Path 1 (21 records, snapshots after records 10 and 20): record 13 is replayed from snapshot 10.
  const double stored = sampler::test::all_records(lib).at(1).at(13).stress[0];
  corrupt_stress(lib, 1, 13, 1.5 * stored);
  const auto [code, summary] = run(everything(lib));
  EXPECT_EQ(code, 1);
  const nlohmann::json& flagged = summary["determinism"]["flagged_records"];
  ASSERT_EQ(flagged.size(), 1u) << flagged.dump();
  EXPECT_EQ(flagged[0]["path"], 1);
  EXPECT_EQ(flagged[0]["record"], 13);
  EXPECT_EQ(flagged[0]["from_record"], 10);
  EXPECT_EQ(flagged[0]["replayed"][0].get<double>(), stored);  // the replay reproduces what was written
  EXPECT_GT(flagged[0]["relative_error"].get<double>(), 0.1);

  celldb::AuditCommandOptions text = everything(lib);
  text.json = false;
  std::ostringstream out;
  EXPECT_EQ(celldb::run_audit(text, out), 1);
  EXPECT_NE(out.str().find("FLAGGED path 1 record 13 (replayed from snapshot 10): relative error"), std::string::npos)
      << out.str();
}

TEST_F(Audit, RecordsAfterAMissingSnapshotAreFlaggedWithTheReason) {
  const fs::path lib = library();
  {
    db::Library library = db::Library::open(lib);
    const fs::path file = library.shard_path(library.catalogue().shard(*library.catalogue().path(1).shard_id));
    db::Shard::open(file, true).remove_group(db::Shard::snapshot_group(1, 10));
  }
  const auto [code, summary] = run(everything(lib));
  EXPECT_EQ(code, 1);
  const nlohmann::json& flagged = summary["determinism"]["flagged_records"];
  // Path 1's records 11 .. 20 start from the lost snapshot; the others replay as before.
  ASSERT_EQ(flagged.size(), 10u) << flagged.dump();
  for (std::size_t i = 0; i < flagged.size(); ++i) {
    EXPECT_EQ(flagged[i]["path"], 1);
    EXPECT_EQ(flagged[i]["record"], 11 + static_cast<int>(i));
    EXPECT_NE(flagged[i]["error"].get<std::string>().find("replay from record 10 failed: "), std::string::npos)
        << flagged[i]["error"];
  }
  EXPECT_EQ(summary["determinism"]["max"].get<double>(), 0.0);
}

TEST_F(Audit, LeaveOneOutErrorIsFiniteAndAboveTheInIndexError) {
  const auto [code, summary] = run(everything(library()));
  ASSERT_EQ(code, 0);
  const nlohmann::json &in = summary["in_index"], &out = summary["leave_one_out"];
  EXPECT_EQ(in["count"], out["count"]);
  EXPECT_LT(in["max"].get<double>(), 1e-12);  // the record itself is indexed: exact up to the frame turn
  for (const char* q : {"median", "p95", "max"}) {
    ASSERT_TRUE(out[q].is_number()) << q;  // null would mean infinite or NaN
    EXPECT_TRUE(std::isfinite(out[q].get<double>())) << q;
  }
  EXPECT_GT(out["median"].get<double>(), 1e3 * std::max(in["max"].get<double>(), 1e-15));
  // The curve: bins in increasing distance, together holding every leave-one-out answer.
  const nlohmann::json& bins = summary["error_vs_distance"]["bins"];
  ASSERT_FALSE(bins.empty());
  std::size_t answers = 0;
  for (std::size_t b = 0; b < bins.size(); ++b) {
    answers += bins[b]["count"].get<std::size_t>();
    EXPECT_LE(bins[b]["distance_min"].get<double>(), bins[b]["distance_max"].get<double>());
    if (b > 0) {
      EXPECT_LE(bins[b - 1]["distance_max"].get<double>(), bins[b]["distance_min"].get<double>());
    }
    EXPECT_GT(bins[b]["distance_min"].get<double>(), 0.0);  // another path never repeats a state exactly
  }
  EXPECT_EQ(answers, out["count"].get<std::size_t>());
  // At an infinite tolerance every answer hits, so the hits are all the leave-one-out answers.
  celldb::AuditCommandOptions everywhere = everything(library_copy("LIB2"));
  everywhere.audit.lookup.tolerance = 1e300;
  const nlohmann::json at = run(everywhere).second["error_vs_distance"]["at_tolerance"];
  EXPECT_EQ(at["hit_share"], 1.0);
  EXPECT_EQ(at["hits"], out);
}

TEST_F(Audit, LiveCellPathsOfMpmRunsAreIndexedButNotReplayed) {
  const fs::path lib = library();
  std::size_t live_records = 0;
  {
    // What an MPM run's enrichment writes (mpm_solver/dem_laws/enrichment.cpp): its own spec, records.
    db::Library library = db::Library::open(lib);
    std::vector<db::Record> records = library.records(1);
    for (db::Record& r : records) r.stress[0] *= 1.01;
    db::ShardWriter writer(library, "run-test");
    const nlohmann::json spec = {{"origin", {{"mpm_point_slot", 0}}}, {"run", "run-test"}, {"sequence", 0}};
    const std::int64_t id = library.add_path(1, spec, library.material());
    writer.start_path(id);
    writer.append_records(id, records);
    writer.finish_path(id, db::PathStatus::done, 1);
    live_records = records.size() - 1;
  }
  const auto [code, summary] = run(everything(lib));
  EXPECT_EQ(code, 0);
  EXPECT_EQ(summary["determinism"]["not_replayable"], live_records);
  EXPECT_EQ(summary["determinism"]["flagged"], 0);
  EXPECT_EQ(summary["sample"]["paths"].size(), 7u);
  EXPECT_EQ(summary["library"]["done_paths"], 7);
}

TEST_F(Audit, LeavesItsOutputsAndAnAuditsRow) {
  const fs::path lib = library();
  celldb::AuditCommandOptions options = everything(lib);
  options.audit.sample = {3, 5, 7};
  options.out.clear();  // default: LIB/audits/<UTC time>
  const auto [code, summary] = run(options);
  ASSERT_EQ(code, 0);
  EXPECT_EQ(summary["sample"]["paths"].size(), 3u);
  EXPECT_EQ(summary["determinism"]["checked"], 5);

  db::Library opened = db::Library::open(lib);
  const std::vector<db::AuditRow> rows = db::audits(opened.catalogue());
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(summary["audit_id"], rows[0].id);
  const nlohmann::json details = nlohmann::json::parse(rows[0].details);
  EXPECT_EQ(details["determinism"], summary["determinism"]);
  EXPECT_EQ(details["leave_one_out"], summary["leave_one_out"]);

  const fs::path out = summary["outputs"]["directory"].get<std::string>();
  EXPECT_EQ(out.parent_path(), fs::absolute(lib / "audits"));
  EXPECT_EQ(nlohmann::json::parse(sampler::test::slurp(out / "audit.json")), summary);
  // One CSV row per replay, per in-index and per leave-one-out answer.
  std::ifstream csv(out / "audit_records.csv");
  std::string line;
  std::map<std::string, std::size_t> rows_by_check;
  std::getline(csv, line);
  EXPECT_EQ(line, "check,path,record,distance,relative_error,absolute_error_pa,estimated_error_pa,stress_norm_pa");
  while (std::getline(csv, line)) ++rows_by_check[line.substr(0, line.find(','))];
  EXPECT_EQ(rows_by_check["replay"], 5u);
  EXPECT_EQ(rows_by_check["in_index"], summary["in_index"]["count"].get<std::size_t>());
  EXPECT_EQ(rows_by_check["leave_one_out"], summary["leave_one_out"]["count"].get<std::size_t>());
}

TEST_F(Audit, PlotsAreDrawnFromTheOutputs) {
  if (std::system("/usr/bin/python3 -c 'import matplotlib' 2>/dev/null") != 0)
    GTEST_SKIP() << "/usr/bin/python3 with matplotlib (python3-matplotlib) is not installed";
  celldb::AuditCommandOptions options = everything(library());
  options.audit.sample = {3, 5, 1};
  options.plots = true;
  ASSERT_EQ(run(options).first, 0);
  for (const char* png : {"audit_histogram.png", "audit_error_vs_distance.png"}) {
    const fs::path file = options.out / png;
    ASSERT_TRUE(fs::exists(file)) << file;
    EXPECT_EQ(sampler::test::slurp(file).substr(1, 3), "PNG");
  }
}

TEST(AuditErrors, ALibraryWithoutDonePathsIsRefusedNamingIt) {
  TempDir dir;
  const app::CellInput input = app::load_cell_input(dir.write("cell.json", kCell));
  db::Library::create(dir.path() / "LIB", input.material);
  celldb::AuditCommandOptions options;
  options.library = dir.path() / "LIB";
  std::ostringstream out;
  try {
    celldb::run_audit(options, out);
    FAIL() << "an empty library was audited";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find((dir.path() / "LIB").string() + ": nothing to audit"), std::string::npos)
        << e.what();
  }
  EXPECT_TRUE(db::audits(db::Library::open(dir.path() / "LIB").catalogue()).empty());
}

}  // namespace
}  // namespace grainbank::audit

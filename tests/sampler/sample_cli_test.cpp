// `dem_sampler prepare | sample | run` end to end, on real libraries in temporary directories: the
// same records whatever the threads or MPI ranks, idempotent registration, resume after SIGKILL and
// SIGINT, failed paths, invalid inputs that leave the library untouched, and `run` from a template.
#include <gtest/gtest.h>

#include <csignal>
#include <regex>

#include <nlohmann/json.hpp>

#include "tests/sampler/sampler_test_util.hpp"

namespace grainbank::sampler::test {
namespace {

namespace fs = std::filesystem;

// One prepared library and one serially sampled reference, shared by the tests (copied before use).
class SampleCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir;
    const fs::path cell = dir_->write("cell.json", kCell), paths = dir_->write("paths.json", kPaths);
    const Outcome p = run(dem_sampler({"prepare", cell.string(), "--library", (dir_->path() / "base").string()}),
                          dir_->path());
    ASSERT_EQ(p.exit_code, 0) << p.err;
    fs::copy(dir_->path() / "base", dir_->path() / "reference", fs::copy_options::recursive);
    const Outcome s = run(dem_sampler({"sample", paths.string(), "--library", (dir_->path() / "reference").string(),
                                       "--threads", "1"}),
                          dir_->path());
    ASSERT_EQ(s.exit_code, 0) << s.err;
    reference_ = new std::map<std::int64_t, std::vector<db::Record>>(all_records(dir_->path() / "reference"));
  }
  static void TearDownTestSuite() {
    delete reference_;
    delete dir_;
  }

  // A fresh copy of the prepared library in this test's directory.
  fs::path library(const std::string& name = "lib") const {
    fs::copy(dir_->path() / "base", here_.path() / name, fs::copy_options::recursive);
    return here_.path() / name;
  }
  fs::path paths_file() const { return here_.write("paths.json", kPaths); }
  Outcome sample(const fs::path& lib, std::vector<std::string> extra = {}) const {
    std::vector<std::string> args{"sample", paths_file().string(), "--library", lib.string()};
    args.insert(args.end(), extra.begin(), extra.end());
    return run(dem_sampler(args), here_.path());
  }

  static TempDir* dir_;
  static std::map<std::int64_t, std::vector<db::Record>>* reference_;
  TempDir here_;
};
TempDir* SampleCli::dir_ = nullptr;
std::map<std::int64_t, std::vector<db::Record>>* SampleCli::reference_ = nullptr;

// Every path done, records contiguous (times increasing, one per interval), equal to the reference.
void expect_complete_and_equal(const fs::path& lib, const std::map<std::int64_t, std::vector<db::Record>>& reference) {
  for (const db::PathRow& row : path_rows(lib)) {
    EXPECT_EQ(row.status, db::PathStatus::done) << "path " << row.id;
    EXPECT_TRUE(row.error.empty()) << row.error;
  }
  const auto records = all_records(lib);
  ASSERT_EQ(records.size(), reference.size());
  for (const auto& [id, rows] : records) {
    ASSERT_EQ(rows.size(), reference.at(id).size()) << "path " << id;
    for (std::size_t k = 1; k < rows.size(); ++k) EXPECT_GT(rows[k].time, rows[k - 1].time) << "path " << id;
    EXPECT_TRUE(rows == reference.at(id)) << "path " << id << " differs from the serial reference";
  }
}

TEST_F(SampleCli, ReferenceHasEveryPathAndSnapshots) {
  const std::map<std::int64_t, long> expected = {{1, 21}, {2, 4}};
  ASSERT_EQ(reference_->size(), 6u);
  for (const auto& [id, n] : expected) EXPECT_EQ(static_cast<long>(reference_->at(id).size()), n);
  db::Library lib = db::Library::open(dir_->path() / "reference");
  EXPECT_EQ(lib.catalogue().snapshots_of(1).size(), 2u);  // after records 10 and 20
  EXPECT_EQ(reference_->at(1).front().L, dem::Mat3::Zero());
  EXPECT_EQ(reference_->at(1).back().L(0, 1), 1);
}

TEST_F(SampleCli, TwoThreadsGiveTheSameRecords) {
  const fs::path lib = library();
  const Outcome r = sample(lib, {"--threads", "2"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  expect_complete_and_equal(lib, *reference_);
}

TEST_F(SampleCli, TwoMpiRanksGiveTheSameRecords) {
#ifndef GRAINBANK_HAVE_MPI
  GTEST_SKIP() << "built without MPI";
#else
  const fs::path lib = library();
  const Outcome r = run({MPIEXEC_BINARY, "--allow-run-as-root", "--oversubscribe", "-n", "2", DEM_SAMPLER_BINARY,
                         "sample", paths_file().string(), "--library", lib.string()},
                        here_.path());
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("on 2 MPI rank(s)"), std::string::npos) << r.out;
  expect_complete_and_equal(lib, *reference_);
  db::Library opened = db::Library::open(lib);
  int rank_shards = 0;
  for (const db::ShardRow& s : opened.catalogue().shards()) rank_shards += s.name.starts_with("rank");
  EXPECT_EQ(rank_shards, 2);
#endif
}

TEST_F(SampleCli, SamplingTwiceRegistersAndRunsNothingNew) {
  const fs::path lib = library();
  ASSERT_EQ(sample(lib, {"--threads", "1"}).exit_code, 0);
  const Outcome again = sample(lib, {"--threads", "1"});
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_NE(again.err.find("0 new"), std::string::npos) << again.err;
  EXPECT_EQ(path_rows(lib).size(), 6u);
  expect_complete_and_equal(lib, *reference_);
}

TEST_F(SampleCli, SigkillThenRerunCompletesWithNoDuplicateAndNoLostPath) {
  const fs::path lib = library();
  // Long paths committed every 5 records, so the kill lands mid-path.
  const fs::path paths = here_.write("long.json", R"({"record_interval": 2e-4, "snapshot_interval": 10,
    "generators": [{"count": 4, "rate": {"min": 0.5, "max": 5}, "strain": 0.03, "segments": 2}]})");
  const auto args = dem_sampler({"sample", paths.string(), "--library", lib.string(), "--threads", "1",
                                 "--commit-every", "5"});
  const TempDir scratch;
  // The sampler stops itself after 10 committed records, in its first path (each has 30 or more), and
  // is killed there.
  const pid_t child = spawn_stopped_after(args, scratch.path(), 10);
  long committed = 0, done = 0;
  for (const db::PathRow& row : path_rows(lib)) committed += row.record_count, done += row.status == db::PathStatus::done;
  kill(child, SIGKILL);
  wait_for(child, scratch.path());
  ASSERT_GE(committed, 10);
  ASSERT_EQ(done, 0);
  int running = 0;
  for (const db::PathRow& row : path_rows(lib)) running += row.status == db::PathStatus::running;
  EXPECT_EQ(running, 1);  // one thread: the path it was killed in

  const Outcome resumed = run(args, here_.path());
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_NE(resumed.err.find("reset 1 path(s) left running"), std::string::npos) << resumed.err;

  // Against an uninterrupted run of the same paths.
  const fs::path clean = library("clean");
  ASSERT_EQ(run(dem_sampler({"sample", paths.string(), "--library", clean.string(), "--threads", "2"}), here_.path())
                .exit_code,
            0);
  const auto expected = all_records(clean);
  ASSERT_EQ(path_rows(lib).size(), 4u);
  expect_complete_and_equal(lib, expected);
  for (const auto& [id, rows] : expected) {
    db::Library opened = db::Library::open(lib);
    const auto snapshots = opened.catalogue().snapshots_of(id);
    for (std::size_t k = 0; k < snapshots.size(); ++k) EXPECT_EQ(snapshots[k].record_index, 10 * static_cast<long>(k + 1));
  }
}

TEST_F(SampleCli, SigintPutsPathsBackToPendingAndRerunResumes) {
  const fs::path lib = library();
  const fs::path paths = here_.write("long.json", R"({"record_interval": 2e-4,
    "generators": [{"count": 4, "rate": {"min": 0.5, "max": 5}, "strain": 0.03}]})");
  const auto args = dem_sampler({"sample", paths.string(), "--library", lib.string(), "--threads", "2",
                                 "--commit-every", "5"});
  const TempDir scratch;
  // SIGINT reaches the sampler stopped after its first commit; it acts on it once continued.
  const pid_t child = spawn_stopped_after(args, scratch.path(), 5);
  kill(child, SIGINT);
  kill(child, SIGCONT);
  const Outcome stopped = wait_for(child, scratch.path());
  EXPECT_EQ(stopped.exit_code, 1);
  EXPECT_NE(stopped.err.find("interrupted"), std::string::npos) << stopped.err;
  for (const db::PathRow& row : path_rows(lib)) {
    EXPECT_NE(row.status, db::PathStatus::running);
    if (row.status == db::PathStatus::pending) {
      EXPECT_EQ(row.record_count, 0);
    }
  }
  const Outcome resumed = run(args, here_.path());
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_EQ(resumed.err.find("left running"), std::string::npos) << resumed.err;
  for (const db::PathRow& row : path_rows(lib)) EXPECT_EQ(row.status, db::PathStatus::done);
}

TEST_F(SampleCli, AFailingPathIsMarkedFailedAndTheOthersGoOn) {
  const fs::path lib = library();
  const fs::path paths = here_.write("failing.json", R"({"record_interval": 2e-4, "paths": [
    {"segments": [{"L": [[1e300, 0], [0, 0]], "duration": 1e-3}]},
    {"segments": [{"L": [[0, 1], [0, 0]], "duration": 1e-3}]}]})");
  const Outcome r = run(dem_sampler({"sample", paths.string(), "--library", lib.string()}), here_.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("1 failed"), std::string::npos) << r.out;
  const auto rows = path_rows(lib);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].status, db::PathStatus::failed);
  EXPECT_FALSE(rows[0].error.empty());
  EXPECT_EQ(rows[1].status, db::PathStatus::done);
  EXPECT_EQ(rows[1].record_count, 6);
}

TEST_F(SampleCli, InvalidPathsFileLeavesTheLibraryUntouched) {
  const fs::path lib = library();
  ASSERT_EQ(sample(lib, {"--threads", "1"}).exit_code, 0);
  std::map<fs::path, std::string> before;
  for (const auto& e : fs::recursive_directory_iterator(lib))
    if (e.is_regular_file()) before[e.path()] = slurp(e.path());
  const fs::path bad = here_.write("bad.json", R"({"record_interval": 2e-4, "paths": [
    {"segments": [{"L": [[0, 1], [0, 0]], "duration": 1e-3}]},
    {"segments": [{"L": [[0, 1], [0, 0]], "strain": -1}]}]})");
  const Outcome r = run(dem_sampler({"sample", bad.string(), "--library", lib.string()}), here_.path());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(r.err, "dem_sampler: " + bad.string() + ": /paths/1/segments/0/strain: expected a positive number, got -1\n");
  // A Q_t the library material's dashpots (restitution 0.3) make unstable, in the second path only.
  const fs::path unstable = here_.write("unstable.json", R"({"record_interval": 2e-4, "paths": [
    {"segments": [{"L": [[0, 1], [0, 0]], "duration": 1e-3}]},
    {"segments": [{"L": [[0, 1], [0, 0]], "duration": 1e-3}], "substepping": {"q_t": 0.2}}]})");
  const Outcome u = run(dem_sampler({"sample", unstable.string(), "--library", lib.string()}), here_.path());
  EXPECT_EQ(u.exit_code, 1);
  EXPECT_NE(u.err.find(unstable.string() + ": planned path 2 of 2: substepping.q_t: expected a number in (0, 0.1408"),
            std::string::npos)
      << u.err;
  EXPECT_NE(u.err.find("got 0.2 (the library's material)"), std::string::npos) << u.err;
  // Fields that pass their own checks but give a segment of 0 s (a strain at an enormous L).
  // Registered, such a path could never run, and it would stop every later sample of the library.
  const fs::path instant = here_.write("instant.json", R"({"record_interval": 2e-4, "paths": [
    {"segments": [{"L": [[0, 1], [0, 0]], "duration": 1e-3}]},
    {"segments": [{"L": [[1e308, 0], [0, 0]], "strain": 0.002}]}]})");
  const Outcome i = run(dem_sampler({"sample", instant.string(), "--library", lib.string()}), here_.path());
  EXPECT_EQ(i.exit_code, 1);
  EXPECT_EQ(i.err.rfind("dem_sampler: " + instant.string() + ": /paths/1: its path cannot be run: ", 0), 0u) << i.err;
  EXPECT_NE(i.err.find("/segments/0/duration: expected a positive number"), std::string::npos) << i.err;
  std::map<fs::path, std::string> after;
  for (const auto& e : fs::recursive_directory_iterator(lib))
    if (e.is_regular_file()) after[e.path()] = slurp(e.path());
  EXPECT_TRUE(before == after) << "library files changed";
  EXPECT_EQ(path_rows(lib).size(), 6u);
}

TEST_F(SampleCli, AStoredSpecThatCannotRunFailsAloneAndTheOtherPathsAreSampled) {
  // A library an older build let take a path of 0 s: registered, never runnable.
  const fs::path lib = library();
  {
    db::Library library = db::Library::open(lib);
    const nlohmann::json instant = {{"record_interval", 2e-4},
                                    {"segments", {{{"L", {{1.0, 0.0}, {0.0, 0.0}}}, {"duration", 0.0}}}}};
    library.add_path(1, instant, library.material());
  }
  const Outcome r = sample(lib, {"--threads", "1"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("path 1: its stored spec cannot be run, marked failed: "), std::string::npos) << r.err;
  const auto rows = path_rows(lib);
  ASSERT_EQ(rows.size(), 7u);
  EXPECT_EQ(rows[0].status, db::PathStatus::failed);
  EXPECT_NE(rows[0].error.find("/segments/0/duration: expected a positive number"), std::string::npos) << rows[0].error;
  for (std::size_t k = 1; k < rows.size(); ++k) EXPECT_EQ(rows[k].status, db::PathStatus::done) << "path " << rows[k].id;
}

TEST_F(SampleCli, PrepareIsIdempotentAndRefusesAnotherMaterial) {
  const fs::path lib = library();
  const fs::path cell = here_.write("cell.json", kCell);
  const Outcome again = run(dem_sampler({"prepare", cell.string(), "--library", lib.string()}), here_.path());
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_TRUE(std::regex_search(again.out, std::regex("^template 1 \\(already in the library\\): N = 64, phi = 0\\.6")))
      << again.out;
  EXPECT_EQ(db::Library::open(lib).catalogue().templates().size(), 1u);

  std::string other = kCell;
  other.replace(other.find("\"friction\": 0.2"), 15, "\"friction\": 0.3");
  const Outcome refused =
      run(dem_sampler({"prepare", here_.write("other.json", other).string(), "--library", lib.string()}), here_.path());
  EXPECT_EQ(refused.exit_code, 1);
  EXPECT_NE(refused.err.find("library built for other physics than the given material: contact.friction"),
            std::string::npos)
      << refused.err;
}

// Records of a library path equal `dem_sampler run` of the same path from the same template.
TEST_F(SampleCli, RecordsEqualAStandAloneRun) {
  const fs::path path = here_.write("path.json",
                                    R"({"segments": [{"L": [[0, 1], [0, 0]], "duration": 0.004}], "record_interval": 2e-4})");
  const fs::path csv = here_.path() / "run.csv";
  const Outcome r = run(dem_sampler({"run", "--library", (dir_->path() / "reference").string(), "--template", "1",
                                     "--path", path.string(), "--out", csv.string()}),
                        here_.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::istringstream table(slurp(csv));
  std::string line;
  std::getline(table, line);  // header: t, F_xx F_xy F_yx F_yy, eps_v, sigma_xx yy zz xy xz yz, ...
  const std::vector<db::Record>& records = reference_->at(1);
  std::size_t k = 0;
  for (; std::getline(table, line); ++k) {
    ASSERT_LT(k, records.size());
    std::vector<double> v;
    std::stringstream fields(line);
    for (std::string f; std::getline(fields, f, ',');) v.push_back(std::stod(f));
    const db::Record& rec = records[k];
    EXPECT_NEAR(v[0], rec.time, 1e-9 * std::abs(rec.time) + 1e-15);
    EXPECT_NEAR(v[2], rec.F(0, 1), 1e-9);
    // The table has 10 significant digits. Its shear columns are the raw σ_ij of the (slightly
    // asymmetric) Love-Weber sum while the library stores the symmetric part: compare the diagonal.
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(v[6 + c], rec.stress[c], 1e-9 * std::abs(rec.stress[c])) << "record " << k << " column " << c;
    EXPECT_NEAR(v[16], static_cast<double>(rec.bonds), 0);
  }
  EXPECT_EQ(k, records.size());
}

}  // namespace
}  // namespace grainbank::sampler::test

// `dem_sampler sample` killed with SIGKILL right after chosen commits and at 20 random moments (fixed
// seed), from before it opens the library to after it finished. After each kill: every committed record equals the uninterrupted
// reference, `celldb verify` reports orphans only (never an inconsistency), each belonging to a path
// that was not done, and exits 1 exactly when it found some; `verify --repair` leaves a clean library
// (verified again: no finding at all); and running the same command again completes every path with
// the reference's records. A shard cut short as a kill inside HDF5's flush leaves it is read without
// any repair.
#include <gtest/gtest.h>

#include <hdf5.h>

#include <csignal>
#include <chrono>
#include <random>
#include <regex>
#include <thread>

#include "tests/faults/library_fault_util.hpp"

namespace grainbank::faults {
namespace {

// Status of each path, by id, as committed.
std::map<std::int64_t, db::PathStatus> statuses(const fs::path& library) {
  std::map<std::int64_t, db::PathStatus> out;
  for (const db::PathRow& row : sampler::test::path_rows(library)) out[row.id] = row.status;
  return out;
}

// Orphans of a killed writer concern its unfinished paths, or a shard file it had just created.
void expect_only_orphans_of_unfinished_paths(const nlohmann::json& report, const std::map<std::int64_t, db::PathStatus>& status) {
  static const std::regex path_object(R"(^/paths/(\d+)(/.*)?$)");
  for (const auto& f : report["findings"]) {
    EXPECT_EQ(f["kind"], "orphan") << f.dump();
    const std::string object = f["object"];
    std::smatch m;
    if (std::regex_match(object, m, path_object)) {
      const auto it = status.find(std::stoll(m[1]));
      if (it != status.end()) {
        EXPECT_NE(it->second, db::PathStatus::done) << "orphan of a finished path: " << f.dump();
      }
    } else {
      EXPECT_TRUE(object.empty() || object.starts_with("/templates/")) << f.dump();
    }
  }
}

// After `child`, a sampler on `lib`, was killed: every committed record intact, verify finds orphans of
// unfinished paths only, repair leaves a clean library, and the same command completes it. Returns
// whether the kill landed while paths were in progress.
bool expect_recovery_after_kill(const fs::path& lib, pid_t child, const fs::path& scratch) {
  kill(child, SIGKILL);
  sampler::test::wait_for(child, scratch);
  const auto status = statuses(lib);
  long unfinished = 0;
  for (const auto& [id, s] : status) unfinished += s != db::PathStatus::done;
  EXPECT_NO_THROW(LibraryFaults::expect_committed_records_intact(lib)) << "after the kill";

  const Verification found = celldb_verify(lib, false, scratch);
  EXPECT_EQ(count_kind(found.report, "inconsistency"), 0) << found.report.dump(1);
  EXPECT_EQ(found.exit_code, count_kind(found.report, "orphan") > 0 ? 1 : 0) << found.report.dump(1);
  expect_only_orphans_of_unfinished_paths(found.report, status);
  const Verification repaired = celldb_verify(lib, true, scratch);
  EXPECT_EQ(repaired.exit_code, 0) << repaired.report.dump(1);
  const Verification after = celldb_verify(lib, false, scratch);
  EXPECT_EQ(after.exit_code, 0);
  EXPECT_TRUE(after.report["findings"].empty()) << after.report.dump(1);
  EXPECT_NO_THROW(LibraryFaults::expect_committed_records_intact(lib)) << "after the repair";

  const Outcome resumed = sampler::test::run(LibraryFaults::sample_args(lib), scratch);
  EXPECT_EQ(resumed.exit_code, 0) << resumed.err;
  for (const auto& [id, s] : statuses(lib)) EXPECT_EQ(s, db::PathStatus::done) << "path " << id;
  EXPECT_EQ(sampler::test::all_records(lib), *LibraryFaults::reference_);
  return !status.empty() && unfinished > 0;
}

// Kills right after a commit, in the first, second and third path (12, 10 and 8 records, committed
// in pairs): the sampler stops itself there (test_stop_point.hpp), so each kill lands mid-run.
TEST_F(LibraryFaults, SigkillAfterACommitLosesNothingCommitted) {
  for (const long records : {2, 14, 24}) {
    SCOPED_TRACE("killed after " + std::to_string(records) + " records");
    const fs::path lib = fresh_library("after" + std::to_string(records));
    const TempDir scratch("gb-faults-kill");
    const pid_t child = sampler::test::spawn_stopped_after(sample_args(lib), scratch.path(), records);
    EXPECT_TRUE(expect_recovery_after_kill(lib, child, scratch.path())) << "the kill did not land mid-run";
  }
}

// Kills at 20 random moments (fixed seed) of the run, scaled by a reference run's duration, so that
// some land inside HDF5's and SQLite's writes. The moment is all the wait chooses: every check holds
// wherever the kill lands (the test above makes sure some land mid-run).
TEST_F(LibraryFaults, SigkillAtRandomMomentsLosesNothingCommitted) {
  const fs::path timing = fresh_library("timing");
  const auto t0 = std::chrono::steady_clock::now();
  ASSERT_EQ(sampler::test::run(sample_args(timing), here_.path()).exit_code, 0);
  const double run_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  std::mt19937_64 random(8);
  std::uniform_real_distribution<double> moment(0.0, 1.1 * run_seconds);
  for (int trial = 0; trial < 20; ++trial) {
    SCOPED_TRACE("trial " + std::to_string(trial));
    const fs::path lib = fresh_library("trial" + std::to_string(trial));
    const TempDir scratch("gb-faults-kill");
    const pid_t child = sampler::test::spawn(sample_args(lib), scratch.path());
    std::this_thread::sleep_for(std::chrono::duration<double>(moment(random)));
    expect_recovery_after_kill(lib, child, scratch.path());
  }
}

// Leaves `shard` as a writer killed inside HDF5's flush can (seen in a trial of the test above:
// "truncated file: eof = 328422, ... stored_eof = 329958"): its superblock on disk already claims
// space at the end whose bytes never reached the file. Here the space is a dataset allocated and never
// written (as a writer allocates a chunk before writing it), and the file is cut where it begins.
void cut_off_allocated_tail(const fs::path& shard) {
  haddr_t start = HADDR_UNDEF;
  hsize_t length = 0;
  {
    const hid_t file = H5Fopen(shard.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    ASSERT_GE(file, 0);
    const hsize_t size = 1 << 14;
    const hid_t space = H5Screate_simple(1, &size, nullptr);
    const hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
    H5Pset_alloc_time(dcpl, H5D_ALLOC_TIME_EARLY);
    H5Pset_fill_time(dcpl, H5D_FILL_TIME_NEVER);
    const hid_t data = H5Dcreate2(file, "allocated", H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
    start = H5Dget_offset(data);
    length = H5Dget_storage_size(data);
    H5Dclose(data);
    H5Pclose(dcpl);
    H5Sclose(space);
    ASSERT_GE(H5Fclose(file), 0);
  }
  ASSERT_NE(start, HADDR_UNDEF);
  ASSERT_EQ(start + length, fs::file_size(shard)) << "the allocated space is not the end of the file";
  fs::resize_file(shard, start);
}

TEST_F(LibraryFaults, ShardCutShortByAKilledWriterIsReadWithoutRepair) {
  const fs::path lib = fresh_library("lib", true);
  const fs::path shard = lib / "shards" / "rank0.h5";
  cut_off_allocated_tail(shard);
  const auto cut_size = fs::file_size(shard);

  // The store's reader, in this process and in `celldb query` (which reads every record of the
  // library into its lookup index), gets every committed record and cell, and changes nothing.
  ASSERT_NO_THROW(expect_committed_records_intact(lib));
  db::Library opened = db::Library::open(lib);
  EXPECT_NO_THROW(opened.template_cell(1));
  for (const db::SnapshotRow& s : opened.catalogue().snapshots()) {
    EXPECT_NO_THROW(opened.snapshot_cell(s.path_id, s.record_index)) << "path " << s.path_id;
  }
  const Outcome query = sampler::test::run(
      {CELLDB_BINARY, "query", lib.string(), "--state", R"({"F": [[1, 0], [0, 1]], "L": [[0, 0], [0, 0]], "D": 0})"},
      here_.path());
  EXPECT_EQ(query.exit_code, 0) << query.err;
  EXPECT_EQ(fs::file_size(shard), cut_size) << "a reader changed the shard";

  // verify names the cut as an orphan only; the next writer extends the file and goes on.
  const Verification found = celldb_verify(lib, false, here_.path());
  EXPECT_EQ(count_kind(found.report, "inconsistency"), 0) << found.report.dump(1);
  EXPECT_EQ(count_kind(found.report, "orphan"), 1) << found.report.dump(1);
  const Outcome resumed = sampler::test::run(sample_args(lib), here_.path());
  EXPECT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_EQ(sampler::test::all_records(lib), *reference_);
}

}  // namespace
}  // namespace grainbank::faults

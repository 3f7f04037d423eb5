// `dem_sampler sample` killed with SIGKILL at 20 random moments (fixed seed), from before it opens
// the library to after it finished. After each kill: every committed record equals the uninterrupted
// reference, `celldb verify` reports orphans only (never an inconsistency), each belonging to a path
// that was not done, and exits 1 exactly when it found some; `verify --repair` leaves a clean library
// (verified again: no finding at all); and running the same command again completes every path with
// the reference's records.
#include <gtest/gtest.h>

#include <csignal>
#include <chrono>
#include <random>
#include <regex>
#include <thread>

#include "library_fault_util.hpp"

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

TEST_F(LibraryFaults, SigkillAtRandomMomentsLosesNothingCommitted) {
  // The reference run's duration scales the kill moments to this machine's speed.
  const fs::path timing = fresh_library("timing");
  const auto t0 = std::chrono::steady_clock::now();
  ASSERT_EQ(sampler::test::run(sample_args(timing), here_.path()).exit_code, 0);
  const double run_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  std::mt19937_64 random(8);
  std::uniform_real_distribution<double> moment(0.0, 1.1 * run_seconds);
  int mid_run = 0;
  for (int trial = 0; trial < 20; ++trial) {
    SCOPED_TRACE("trial " + std::to_string(trial));
    const fs::path lib = fresh_library("trial" + std::to_string(trial));
    const TempDir scratch("gb-faults-kill");
    const pid_t child = sampler::test::spawn(sample_args(lib), scratch.path());
    std::this_thread::sleep_for(std::chrono::duration<double>(moment(random)));
    kill(child, SIGKILL);
    sampler::test::wait_for(child, scratch.path());

    const auto status = statuses(lib);
    long unfinished = 0;
    for (const auto& [id, s] : status) unfinished += s != db::PathStatus::done;
    mid_run += !status.empty() && unfinished > 0;
    ASSERT_NO_THROW(expect_committed_records_intact(lib)) << "after the kill";

    const Verification found = celldb_verify(lib, false, scratch.path());
    EXPECT_EQ(count_kind(found.report, "inconsistency"), 0) << found.report.dump(1);
    EXPECT_EQ(found.exit_code, count_kind(found.report, "orphan") > 0 ? 1 : 0) << found.report.dump(1);
    expect_only_orphans_of_unfinished_paths(found.report, status);
    const Verification repaired = celldb_verify(lib, true, scratch.path());
    EXPECT_EQ(repaired.exit_code, 0) << repaired.report.dump(1);
    const Verification after = celldb_verify(lib, false, scratch.path());
    EXPECT_EQ(after.exit_code, 0);
    EXPECT_TRUE(after.report["findings"].empty()) << after.report.dump(1);
    ASSERT_NO_THROW(expect_committed_records_intact(lib)) << "after the repair";

    const Outcome resumed = sampler::test::run(sample_args(lib), scratch.path());
    ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
    for (const auto& [id, s] : statuses(lib)) EXPECT_EQ(s, db::PathStatus::done) << "path " << id;
    EXPECT_EQ(sampler::test::all_records(lib), *reference_);
  }
  // The kills must not all land before the first path or after the last one.
  EXPECT_GE(mid_run, 3) << "too few kills landed while paths were in progress";
}

}  // namespace
}  // namespace grainbank::faults

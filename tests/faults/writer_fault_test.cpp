// Writers that cannot finish: a second sampler started on a library in use, and a sampler whose
// writes fail because the disk is "full" (RLIMIT_FSIZE: the kernel stops the file at the limit and
// raises SIGXFSZ, or returns EFBIG when the signal is ignored). The library keeps its committed data,
// `celldb verify` finds orphans only, `verify --repair` cleans them, and the same command run again
// (with room on the disk) completes every path with the reference's records.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <unistd.h>

#include <csignal>

#include "tests/faults/library_fault_util.hpp"

namespace grainbank::faults {
namespace {

// Starts `argv` as sampler::test::spawn does, with its files limited to `bytes` and SIGXFSZ either
// fatal (the default) or ignored. Both are inherited through fork and exec.
pid_t spawn_with_file_size_limit(const std::vector<std::string>& argv, const fs::path& dir, rlim_t bytes,
                                 bool ignore_sigxfsz) {
  rlimit saved{};
  getrlimit(RLIMIT_FSIZE, &saved);
  const rlimit limited{bytes, saved.rlim_max};
  setrlimit(RLIMIT_FSIZE, &limited);
  const auto saved_handler = signal(SIGXFSZ, ignore_sigxfsz ? SIG_IGN : SIG_DFL);
  const pid_t pid = sampler::test::spawn(argv, dir);
  signal(SIGXFSZ, saved_handler);
  setrlimit(RLIMIT_FSIZE, &saved);
  return pid;
}

// After a failed writer: committed data intact, orphans only, repair cleans, a rerun completes.
void expect_recoverable(const fs::path& lib, const fs::path& scratch, const std::vector<std::string>& rerun,
                        const std::map<std::int64_t, std::vector<db::Record>>& reference) {
  const Verification found = celldb_verify(lib, false, scratch);
  EXPECT_EQ(count_kind(found.report, "inconsistency"), 0) << found.report.dump(1);
  EXPECT_EQ(found.exit_code, count_kind(found.report, "orphan") > 0 ? 1 : 0);
  EXPECT_EQ(celldb_verify(lib, true, scratch).exit_code, 0);
  const Verification after = celldb_verify(lib, false, scratch);
  EXPECT_TRUE(after.report["findings"].empty()) << after.report.dump(1);
  LibraryFaults::expect_committed_records_intact(lib);
  const Outcome resumed = sampler::test::run(rerun, scratch);
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_EQ(sampler::test::all_records(lib), reference);
}

TEST_F(LibraryFaults, SecondSamplerOnALibraryInUseIsRefused) {
  const fs::path lib = fresh_library("lib");
  const TempDir first_dir("gb-faults-first"), second_dir("gb-faults-second");
  // The first sampler stops itself holding the lock, in its first path (2 records committed): it
  // cannot finish, and release the lock, before both refusals are in.
  const pid_t first = sampler::test::spawn_stopped_after(sample_args(lib), first_dir.path(), 2);
  const Outcome second = sampler::test::run(sample_args(lib), second_dir.path());
  const fs::path cell = second_dir.write("cell.json", sampler::test::kCell);
  const Outcome prepare =
      sampler::test::run(sampler::test::dem_sampler({"prepare", cell.string(), "--library", lib.string()}), second_dir.path());
  kill(first, SIGCONT);
  const Outcome first_outcome = sampler::test::wait_for(first, first_dir.path());
  ASSERT_EQ(first_outcome.exit_code, 0) << first_outcome.err;

  // Both refused, naming the lock file and the holder (host:pid of the first sampler).
  std::string holder = ":";  // appended, not concatenated: GCC 12 warns wrongly (-Wrestrict) on the latter
  holder.append(std::to_string(first)).append(") is writing to this library");
  for (const Outcome* refused : {&second, &prepare}) {
    EXPECT_EQ(refused->exit_code, 1);
    EXPECT_NE(refused->err.find((lib / "sampler.lock").string()), std::string::npos) << refused->err;
    EXPECT_NE(refused->err.find(holder), std::string::npos) << refused->err;
  }
  // The first sampler's work is complete and the library clean: nothing was shared.
  EXPECT_EQ(sampler::test::all_records(lib), *reference_);
  const Verification v = celldb_verify(lib, false, second_dir.path());
  EXPECT_EQ(v.exit_code, 0);
  EXPECT_TRUE(v.report["findings"].empty()) << v.report.dump(1);
  EXPECT_EQ(db::Library::open(lib).catalogue().shards().size(), 2u);  // templates + rank0
}

// `sample` on a fresh library whose files may not grow beyond `fraction` of the complete shard, the
// process killed by SIGXFSZ or (signal ignored) seeing EFBIG. Returns the library and the outcome.
std::pair<fs::path, Outcome> sample_on_full_disk(const LibraryFaults& test, bool ignore_signal, double fraction,
                                                 const fs::path& scratch) {
  const double full_size =
      static_cast<double>(fs::file_size(LibraryFaults::dir_->path() / "reference" / "shards" / "rank0.h5"));
  const fs::path lib = test.fresh_library(std::string(ignore_signal ? "efbig" : "sigxfsz") + std::to_string(fraction));
  const pid_t child = spawn_with_file_size_limit(LibraryFaults::sample_args(lib), scratch,
                                                 static_cast<rlim_t>(fraction * full_size), ignore_signal);
  return {lib, sampler::test::wait_for(child, scratch)};
}

// The disk fills up at several points of the run (limits from a quarter to 90 % of the complete
// shard) and the kernel kills the sampler in the middle of the write (SIGXFSZ, like a crash).
TEST_F(LibraryFaults, DiskFullDuringSampleLosesNothingCommitted) {
  for (const double fraction : {0.25, 0.5, 0.9}) {
    SCOPED_TRACE(fraction);
    const TempDir scratch("gb-faults-full");
    const auto [lib, killed] = sample_on_full_disk(*this, false, fraction, scratch.path());
    EXPECT_NE(killed.exit_code, 0) << "the sampler did not notice the full disk: " << killed.err;
    expect_recoverable(lib, scratch.path(), sample_args(lib), *reference_);
  }
}

// With SIGXFSZ ignored the write fails with EFBIG: the sampler stops with one clear error line (no
// crash in HDF5's exit-time clean-up), and verify sees the shard its writer could not extend as an
// orphan (--repair extends it back), never as damaged committed data.
TEST_F(LibraryFaults, DiskFullWithEfbigFailsWithOneClearError) {
  const TempDir scratch("gb-faults-efbig");
  const auto [lib, failed] = sample_on_full_disk(*this, true, 0.5, scratch.path());
  EXPECT_EQ(failed.exit_code, 1) << failed.err;
  EXPECT_TRUE(failed.err.ends_with("\n") && failed.err.find("\ndem_sampler: ") != std::string::npos) << failed.err;
  const std::string last_line = failed.err.substr(failed.err.find("\ndem_sampler: ") + 1);
  EXPECT_EQ(last_line.find('\n'), last_line.size() - 1) << "one line: " << last_line;
  EXPECT_NE(last_line.find((lib / "shards" / "rank0.h5").string()), std::string::npos) << last_line;
  EXPECT_NE(last_line.find("File too large"), std::string::npos) << last_line;
  const Verification found = celldb_verify(lib, false, scratch.path());
  EXPECT_EQ(count_kind(found.report, "inconsistency"), 0) << found.report.dump(1);
}

// After EFBIG, HDF5 may have linked a path group whose object header never reached the file. HDF5
// cannot unlink such a group; `verify --repair` rewrites the shard without it, and the rerun completes.
TEST_F(LibraryFaults, DiskFullWithEfbigIsRepaired) {
  for (const double fraction : {0.25, 0.5, 0.9}) {
    SCOPED_TRACE(fraction);
    const TempDir scratch("gb-faults-efbig");
    const auto [lib, failed] = sample_on_full_disk(*this, true, fraction, scratch.path());
    EXPECT_EQ(failed.exit_code, 1) << failed.err;
    expect_recoverable(lib, scratch.path(), sample_args(lib), *reference_);
  }
}

}  // namespace
}  // namespace grainbank::faults

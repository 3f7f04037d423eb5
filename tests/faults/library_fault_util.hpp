// Shared fixture of the library fault tests: one small prepared library and its completely sampled
// reference (built once per test program, copied before each use), `celldb verify` run as a child
// process with its JSON report, and the check that every committed record equals the reference.
#pragma once
#include <gtest/gtest.h>

#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "tests/sampler/sampler_test_util.hpp"

namespace grainbank::faults {

namespace fs = std::filesystem;
using sampler::test::Outcome;
using sampler::test::TempDir;

// Three short paths (12, 10 and 8 records of ~180 DEM steps on 64 spheres), snapshots every 4
// records: a whole run takes a fraction of a second, so a kill lands in every phase of it.
inline const char* const kShortPaths = R"({
  "record_interval": 2e-4, "snapshot_interval": 4,
  "paths": [{"segments": [{"L": [[0, 1], [0, 0]], "duration": 0.0024}]},
            {"replay": [[[0.5, 0], [0, -0.5]], [[0.5, 0], [0, -0.5]], [[0, 1], [0, 0]], [[0, 1], [0, 0]],
                        [[0, 1], [0, 0]], [[0, -1], [0, 0]], [[0, -1], [0, 0]], [[0, -1], [0, 0]], [[0, 1], [0, 0]],
                        [[0, 1], [0, 0]]]}],
  "generators": [{"count": 1, "rate": {"min": 0.5, "max": 5}, "strain": 0.0016, "segments": 2}]
})";

// `celldb verify LIB [--repair] --json`: the exit code and the parsed report.
struct Verification {
  int exit_code = -1;
  nlohmann::json report;
};

inline Verification celldb_verify(const fs::path& library, bool repair, const fs::path& scratch) {
  std::vector<std::string> args{CELLDB_BINARY, "verify", library.string(), "--json"};
  if (repair) args.push_back("--repair");
  const Outcome o = sampler::test::run(args, scratch);
  Verification v{o.exit_code, nullptr};
  try {
    v.report = nlohmann::json::parse(o.out);
  } catch (const nlohmann::json::exception&) {
    ADD_FAILURE() << "celldb verify printed no JSON report; stderr: " << o.err;
  }
  return v;
}

inline int count_kind(const nlohmann::json& report, const std::string& kind) {
  int n = 0;
  for (const auto& f : report["findings"]) n += f["kind"] == kind;
  return n;
}

class LibraryFaults : public ::testing::Test {
 public:
  static void SetUpTestSuite() {
    dir_ = new TempDir("gb-faults");
    const fs::path cell = dir_->write("cell.json", sampler::test::kCell);
    const Outcome p = sampler::test::run(
        sampler::test::dem_sampler({"prepare", cell.string(), "--library", (dir_->path() / "base").string()}),
        dir_->path());
    ASSERT_EQ(p.exit_code, 0) << p.err;
    dir_->write("paths.json", kShortPaths);
    fs::copy(dir_->path() / "base", dir_->path() / "reference", fs::copy_options::recursive);
    const Outcome s = sampler::test::run(sample_args(dir_->path() / "reference"), dir_->path());
    ASSERT_EQ(s.exit_code, 0) << s.err;
    reference_ = new std::map<std::int64_t, std::vector<db::Record>>(sampler::test::all_records(dir_->path() / "reference"));
  }
  static void TearDownTestSuite() {
    delete reference_;
    delete dir_;
  }

  static std::vector<std::string> sample_args(const fs::path& library) {
    return sampler::test::dem_sampler({"sample", paths_file().string(), "--library", library.string(), "--threads",
                                       "1", "--commit-every", "2"});
  }
  static fs::path paths_file() { return dir_->path() / "paths.json"; }

  // A fresh copy of the prepared library (no path registered) or of the sampled reference.
  fs::path fresh_library(const std::string& name, bool sampled = false) const {
    const fs::path copy = here_.path() / name;
    fs::copy(dir_->path() / (sampled ? "reference" : "base"), copy, fs::copy_options::recursive);
    return copy;
  }

  // Every committed record of `library` equals the reference's (a done path: all of them; a path
  // in progress: its committed prefix).
  static void expect_committed_records_intact(const fs::path& library) {
    db::Library lib = db::Library::open(library);
    for (const db::PathRow& row : lib.catalogue().paths()) {
      const std::vector<db::Record> records = lib.records(row.id);
      ASSERT_EQ(static_cast<std::int64_t>(records.size()), row.record_count) << "path " << row.id;
      const std::vector<db::Record>& expected = reference_->at(row.id);
      ASSERT_LE(records.size(), expected.size()) << "path " << row.id;
      if (row.status == db::PathStatus::done) {
        EXPECT_EQ(records.size(), expected.size()) << "path " << row.id;
      }
      EXPECT_TRUE(std::equal(records.begin(), records.end(), expected.begin())) << "path " << row.id;
    }
  }

  static inline TempDir* dir_ = nullptr;
  static inline std::map<std::int64_t, std::vector<db::Record>>* reference_ = nullptr;
  TempDir here_{"gb-faults-test"};
};

}  // namespace grainbank::faults

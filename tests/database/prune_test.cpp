// `celldb prune` (database/store/prune.hpp) on a real library sampled with the real sampler: it keeps
// at most N snapshots per path (the first, the last and evenly between), every committed record and
// template reads back bit for bit, every kept snapshot too, the library verifies clean and its shard
// bytes shrink; a dry run changes nothing, a second prune removes nothing, and a library whose
// sampler lock is held is refused.
#include <gtest/gtest.h>

#include <map>

#include "database/store/error.hpp"
#include "database/store/prune.hpp"
#include "database/store/sampler_lock.hpp"
#include "database/store/verify.hpp"
#include "tests/database/store_test_util.hpp"
#include "tests/database/surrogate_test_util.hpp"

namespace grainbank::db {
namespace {

// Four generated paths, 0.4 % strain at 1-3 /s, a snapshot after every second record.
constexpr const char* kPaths = R"({
  "record_interval": 2e-4, "snapshot_interval": 2,
  "generators": [{"count": 4, "rate": {"min": 1, "max": 3}, "strain": 0.004, "segments": 2}]
})";

struct Contents {
  std::map<std::int64_t, std::vector<Record>> records;
  std::map<std::int64_t, dem::CellState> templates;
  std::map<std::pair<std::int64_t, std::int64_t>, dem::CellState> snapshots;
  std::uintmax_t bytes = 0;
};

Contents contents(Library& library) {
  Contents c;
  for (const PathRow& p : library.catalogue().paths()) c.records[p.id] = library.records(p.id);
  for (const TemplateRow& t : library.catalogue().templates()) c.templates[t.id] = library.template_cell(t.id).state;
  for (const SnapshotRow& s : library.catalogue().snapshots())
    c.snapshots[{s.path_id, s.record_index}] = library.snapshot_cell(s.path_id, s.record_index).state;
  for (const ShardRow& s : library.catalogue().shards()) c.bytes += std::filesystem::file_size(library.shard_path(s));
  return c;
}

TEST(Prune, KeepsABudgetOfSnapshotsPerPathAndEveryRecord) {
  const surrogate::test::TempDir dir("grainbank-prune");
  const std::filesystem::path lib = dir.path() / "LIB";
  surrogate::test::build_library(dir, lib, kPaths);
  Library library = Library::open(lib);
  const Contents before = contents(library);
  std::map<std::int64_t, std::vector<std::int64_t>> indices;
  for (const auto& [key, state] : before.snapshots) indices[key.first].push_back(key.second);
  for (const auto& [path, list] : indices) ASSERT_GT(list.size(), 3u) << "path " << path;

  {
    const SamplerLock sampler(lib);  // a sampler at work
    EXPECT_THROW(prune_snapshots(library, 3, false), StoreError);
  }
  const PruneReport dry = prune_snapshots(library, 3, true);
  EXPECT_GT(dry.snapshots_removed, 0);
  const Contents unchanged = contents(library);
  EXPECT_EQ(unchanged.snapshots.size(), before.snapshots.size());
  EXPECT_EQ(unchanged.bytes, before.bytes);

  const PruneReport report = prune_snapshots(library, 3, false);
  EXPECT_EQ(report.snapshots_removed, dry.snapshots_removed);
  const Contents after = contents(library);
  EXPECT_EQ(after.records, before.records);
  for (const auto& [id, state] : before.templates) EXPECT_EQ(test::first_difference(after.templates.at(id), state), "");
  std::map<std::int64_t, std::vector<std::int64_t>> kept;
  for (const auto& [key, state] : after.snapshots) {
    kept[key.first].push_back(key.second);
    EXPECT_EQ(test::first_difference(state, before.snapshots.at(key)), "") << "path " << key.first;
  }
  for (const auto& [path, list] : indices) {
    ASSERT_EQ(kept[path].size(), 3u) << "path " << path;
    EXPECT_EQ(kept[path].front(), list.front());
    EXPECT_EQ(kept[path].back(), list.back());
  }
  EXPECT_EQ(static_cast<std::size_t>(report.snapshots_before - report.snapshots_removed), after.snapshots.size());
  EXPECT_LT(after.bytes, before.bytes);
  EXPECT_EQ(report.bytes_after, after.bytes);
  EXPECT_TRUE(verify_library(library, false).clean());
  EXPECT_EQ(prune_snapshots(library, 3, false).snapshots_removed, 0);
}

TEST(Prune, TheBudgetKeepsTheFirstTheLastAndEvenlyBetween) {
  const std::vector<std::int64_t> indices{1, 3, 5, 7, 9, 11, 13};
  EXPECT_EQ(kept_snapshots(indices, 10), indices);
  EXPECT_EQ(kept_snapshots(indices, 3), (std::vector<std::int64_t>{1, 7, 13}));
  EXPECT_EQ(kept_snapshots(indices, 1), (std::vector<std::int64_t>{13}));
  EXPECT_TRUE(kept_snapshots(indices, 0).empty());
  EXPECT_THROW(kept_snapshots(indices, -1), std::invalid_argument);
}

}  // namespace
}  // namespace grainbank::db

// Enrichment: the live responses of a hybrid run become done paths of the run's own shard; merged
// into a library (`celldb merge`), they make a rerun of the same scene hit where the first missed.
// A library a sampler is writing is refused; the paths of a run that died are closed by the next.
#include <gtest/gtest.h>

#include "coupling_test_util.hpp"
#include "store/error.hpp"
#include "store/merge.hpp"
#include "dem_laws/enrichment.hpp"
#include "store/sampler_lock.hpp"

namespace grainbank::mpm {
namespace {

using namespace testing;

constexpr double kDt = 2e-4;
constexpr int kSteps = 8;

double run_block(const std::filesystem::path& dir, std::int64_t id, bool enrich) {
  Solver solver = block_with(library_law(dir, id, coupling_settings(Fallback::warm_start, enrich)));
  for (int step = 0; step < kSteps; ++step) solver.step(kDt);
  solver.finish();
  return hit_rate(solver);
}

TEST(Enrichment, MergedLiveResponsesRaiseTheRerunHitRate) {
  const auto base = fresh_library_dir("_base");
  const std::int64_t id = create_library(base, small_snow_cell());
  const auto work = fresh_library_dir("_work");
  std::filesystem::copy(base, work, std::filesystem::copy_options::recursive);

  const double first = run_block(work, id, true);
  {
    db::Library library = db::Library::open(work);
    int run_paths = 0;
    for (const db::PathRow& path : library.catalogue().paths()) {
      EXPECT_EQ(path.status, db::PathStatus::done);
      EXPECT_EQ(path.record_count, kSteps);
      ASSERT_TRUE(path.shard_id);
      EXPECT_TRUE(library.catalogue().shard(*path.shard_id).name.starts_with("run-"));
      ++run_paths;
    }
    EXPECT_EQ(run_paths, 16);  // one per point: each turned live at its first step
    EXPECT_EQ(library.catalogue().snapshots().size(), 16u * (kSteps / 4));
  }
  db::Library target = db::Library::open(base);
  const db::MergeReport report = db::merge_into(target, work);
  EXPECT_EQ(report.paths, 16);

  const double rerun = run_block(base, id, false);
  std::printf("hit rate: first run %.3f, rerun after merge %.3f\n", first, rerun);
  EXPECT_EQ(first, 0.0);
  EXPECT_GT(rerun, first);
  EXPECT_GT(rerun, 0.9);  // the same scene follows the same states
}

TEST(Enrichment, ALibraryASamplerIsWritingIsRefused) {
  const auto dir = fresh_library_dir();
  const std::int64_t id = create_library(dir, small_snow_cell());
  const db::SamplerLock sampler(dir);
  try {
    library_law(dir, id, coupling_settings(Fallback::warm_start, true));
    FAIL() << "expected a refusal";
  } catch (const db::StoreError& e) {
    EXPECT_NE(std::string(e.what()).find("sampler.lock"), std::string::npos) << e.what();
  }
  // Without enrichment the run only reads, which the store allows at any time.
  EXPECT_NO_THROW(library_law(dir, id, coupling_settings(Fallback::warm_start, false)));
}

db::PathRow only_path(const std::filesystem::path& dir) {
  db::Library library = db::Library::open(dir);
  const std::vector<db::PathRow> paths = library.catalogue().paths();
  EXPECT_EQ(paths.size(), 1u);
  return paths.at(0);
}

TEST(Enrichment, APathLeftRunningByADeadRunIsClosedWithItsCommittedRecords) {
  const auto dir = fresh_library_dir();
  const std::int64_t id = create_library(dir, small_snow_cell());
  LibraryLink link(dir, id, nullptr);
  const dem::DemCell& cell = link.template_cell();
  {
    // The run ends without finish(), as a killed one does: 4 records committed with the snapshot
    // after the 4th, the 5th still pending.
    Enrichment dead(link, 4);
    RunPath path = dead.start({{"start", "template"}});
    for (int r = 0; r < 5; ++r) dead.add(path, cell, dem::Mat3::Zero(), cell.measures().stress);
  }
  EXPECT_EQ(only_path(dir).status, db::PathStatus::running);
  Enrichment next(link, 4);
  const db::PathRow closed = only_path(dir);
  EXPECT_EQ(closed.status, db::PathStatus::done);
  EXPECT_EQ(closed.record_count, 4);
  EXPECT_EQ(link.locked([&](db::Library& library) { return library.records(closed.id).size(); }), 4u);
}

}  // namespace
}  // namespace grainbank::mpm

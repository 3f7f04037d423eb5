// Enrichment: the live responses of a hybrid run become done paths of the run's own shard; merged
// into a library (`celldb merge`), they make a rerun of the same scene hit where the first missed.
// A library a sampler is writing is refused; the paths of a run that died are closed by the next.
#include <gtest/gtest.h>

#include <cmath>

#include "dem_sampler/driver/path_driver.hpp"
#include "tests/mpm/coupling_test_util.hpp"
#include "database/store/error.hpp"
#include "database/store/merge.hpp"
#include "mpm_solver/dem_laws/enrichment.hpp"
#include "dem_sampler/sampler/library_writer.hpp"
#include "dem_sampler/sampler/path_plan.hpp"
#include "dem_sampler/sampler/path_runner.hpp"
#include "database/store/sampler_lock.hpp"

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

// The library holds one kind of record whoever drove the cell: a live cell written back by a run stores,
// for the same cell and increments, exactly what the sampler stores along a path.
TEST(Enrichment, ACellDrivenAlongASamplerPathStoresTheSamplersRecords) {
  const auto dir = fresh_library_dir();
  const std::int64_t id = create_library(dir, small_snow_cell());
  sampler::PathPlan plan;
  plan.path.record_interval = 2e-4;
  plan.path.substepping = {0.1, 1, 0.2};
  dem::Mat3 shear = dem::Mat3::Zero(), compression = dem::Mat3::Zero();
  shear(0, 1) = 2;
  compression(0, 0) = 0.5, compression(1, 1) = -1;
  plan.path.segments = {{shear, 4 * plan.path.record_interval}, {compression, 2.5 * plan.path.record_interval}};
  std::int64_t sampled = 0;
  {
    db::Library library = db::Library::open(dir);
    sampled = library.add_path(id, sampler::to_json(plan), library.material());
    db::ShardWriter shard(library, "rank0");
    sampler::LibraryWriter writer(library, shard);
    ASSERT_EQ(sampler::run_path(writer, sampled, library.key_scales(), {}).result, sampler::PathResult::done);
  }

  LibraryLink link(dir, id, nullptr);
  std::int64_t enriched = 0;
  {
    Enrichment enrichment(link, 0);
    RunPath path = enrichment.start({{"start", "template"}});
    enriched = path.id;
    dem::DemCell cell = stored_template(dir, id);
    app::drive_along_path(cell, plan.path,
                          [&](const app::PathRecord& r) { enrichment.add(path, cell, r.L, r.stress); });
    enrichment.finish(path);
  }
  const auto [expected, written] = link.locked(
      [&](db::Library& library) { return std::pair(library.records(sampled), library.records(enriched)); });
  ASSERT_EQ(expected.size(), static_cast<std::size_t>(sampler::record_count(plan)));
  ASSERT_EQ(written.size(), expected.size());
  for (std::size_t k = 0; k < expected.size(); ++k) EXPECT_TRUE(written[k] == expected[k]) << "record " << k;
  EXPECT_TRUE(expected.back().L == compression);
  EXPECT_GT(expected.back().F(0, 1), 0);  // the cell was sheared
}

// A run's snapshot budget caps the snapshots it adds, whatever the interval asks; every record of
// every path is still written.
TEST(Enrichment, ARunAddsAtMostItsSnapshotBudget) {
  const auto dir = fresh_library_dir();
  const std::int64_t id = create_library(dir, small_snow_cell());
  LibraryLink link(dir, id, nullptr);
  const auto snapshot_count = [&] { return link.locked([](db::Library& l) { return l.catalogue().snapshots().size(); }); };
  const std::size_t before = snapshot_count();
  constexpr long kBudget = 3;
  constexpr int kIncrements = 4;
  std::vector<std::int64_t> paths;
  {
    Enrichment enrichment(link, 1, kBudget);  // a snapshot after every record, were it not for the budget
    dem::DemCell cell = stored_template(dir, id);
    dem::Mat3 L = dem::Mat3::Zero();
    L(0, 1) = 1;
    for (int p = 0; p < 2; ++p) {
      RunPath path = enrichment.start({{"start", "template"}});
      paths.push_back(path.id);
      for (int k = 0; k < kIncrements; ++k) enrichment.add(path, cell, L, cell.measures().stress);
      enrichment.finish(path);
    }
    EXPECT_EQ(enrichment.snapshots_written(), kBudget);
  }
  EXPECT_EQ(snapshot_count(), before + kBudget);
  for (std::int64_t path : paths)
    EXPECT_EQ(link.locked([&](db::Library& l) { return l.records(path).size(); }), static_cast<std::size_t>(kIncrements));
}

// A re-tiled cell enriches the library like any other: its snapshot keeps its own sphere count
// and restores to the same cell.
TEST(Enrichment, ARetiledCellIsSnapshotWithItsOwnSphereCount) {
  const auto dir = fresh_library_dir();
  const std::int64_t id = create_library(dir, small_snow_cell());
  LibraryLink link(dir, id, nullptr);
  dem::DemCell cell = stored_template(dir, id);
  cell.set_retiling_cap(16 * cell.size());
  const std::size_t template_size = cell.size();
  dem::Mat3 flattening = dem::Mat3::Identity(), L = dem::Mat3::Zero();
  flattening(0, 0) = std::exp(0.01), flattening(1, 1) = std::exp(-0.01);
  L(0, 0) = 10, L(1, 1) = -10;
  std::int64_t path_id = 0;
  {
    Enrichment enrichment(link, 1);  // a snapshot after every record
    RunPath path = enrichment.start({{"start", "template"}});
    path_id = path.id;
    for (int k = 0; k < 200 && cell.size() == template_size; ++k) {
      const dem::Mat3 stress = cell.advance(flattening, 1e-3, dem::Substepping{}).stress;
      enrichment.add(path, cell, L, stress);
    }
    enrichment.finish(path);
  }
  // Once or more: a doubling can leave another width at the limit, and the prepared template's shape
  // decides which.
  ASSERT_GE(cell.size(), 2 * template_size) << "the cell must re-tile within a log strain of 2";
  const auto [records, restored] = link.locked([&](db::Library& library) {
    const std::size_t n = library.records(path_id).size();
    return std::pair(n, library.restore(library.snapshot_cell(path_id, static_cast<std::int64_t>(n) - 1)));
  });
  EXPECT_EQ(restored.size(), cell.size());
  EXPECT_EQ(restored.cell_matrix(), cell.cell_matrix());
  EXPECT_EQ(restored.positions(), cell.positions());
  EXPECT_EQ(restored.measures().bonds, cell.measures().bonds);
  EXPECT_GE(records, 1u);
}

}  // namespace
}  // namespace grainbank::mpm

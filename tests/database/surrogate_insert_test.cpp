// Samples inserted during a run raise the surrogate's hit rate for nearby queries (issue 13,
// "learning within a run"), and queries run concurrently with inserts.
//
// Library: thirty generated isochoric paths (the index at the start of the run) and ten in-plane
// isotropic compressions at rates 1-2.8 /s, each partly unloaded (the states the run meets that the
// library lacks). The compressions' intervals are the queries; the compressions are inserted as the
// responses of live cells would be. A query hits when its estimated error in stress units is
// within the tolerance; each query leaves its own path out.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <thread>

#include "database/store/library.hpp"
#include "database/surrogate/surrogate_step.hpp"
#include "tests/database/surrogate_test_util.hpp"

namespace grainbank::surrogate {
namespace {

constexpr const char* kPaths = R"({
  "record_interval": 2e-4,
  "generators": [
    {"count": 30, "rate": {"min": 1, "max": 3}, "strain": 0.004, "segments": 2, "volumetric": 0, "spin": 0.2}
  ],
  "paths": [
    {"segments": [{"L": [[-0.7071, 0], [0, -0.7071]], "strain": 0.004}, {"L": [[0.7071, 0], [0, 0.7071]], "strain": 0.002}]},
    {"segments": [{"L": [[-0.8485, 0], [0, -0.8485]], "strain": 0.004}, {"L": [[0.8485, 0], [0, 0.8485]], "strain": 0.002}]},
    {"segments": [{"L": [[-0.9899, 0], [0, -0.9899]], "strain": 0.004}, {"L": [[0.9899, 0], [0, 0.9899]], "strain": 0.002}]},
    {"segments": [{"L": [[-1.1314, 0], [0, -1.1314]], "strain": 0.004}, {"L": [[1.1314, 0], [0, 1.1314]], "strain": 0.002}]},
    {"segments": [{"L": [[-1.2728, 0], [0, -1.2728]], "strain": 0.004}, {"L": [[1.2728, 0], [0, 1.2728]], "strain": 0.002}]},
    {"segments": [{"L": [[-1.4142, 0], [0, -1.4142]], "strain": 0.004}, {"L": [[1.4142, 0], [0, 1.4142]], "strain": 0.002}]},
    {"segments": [{"L": [[-1.5556, 0], [0, -1.5556]], "strain": 0.004}, {"L": [[1.5556, 0], [0, 1.5556]], "strain": 0.002}]},
    {"segments": [{"L": [[-1.6971, 0], [0, -1.6971]], "strain": 0.004}, {"L": [[1.6971, 0], [0, 1.6971]], "strain": 0.002}]},
    {"segments": [{"L": [[-1.8385, 0], [0, -1.8385]], "strain": 0.004}, {"L": [[1.8385, 0], [0, 1.8385]], "strain": 0.002}]},
    {"segments": [{"L": [[-1.9799, 0], [0, -1.9799]], "strain": 0.004}, {"L": [[1.9799, 0], [0, 1.9799]], "strain": 0.002}]}
  ]
})";
constexpr std::int64_t kCompressions = 10;  // paths 1-10 (explicit paths come first)
constexpr double kTolerance = 500;  // [Pa], on the stress after one record interval (Δp ≈ 0.6 kPa)

class SurrogateInsert : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new test::TempDir("grainbank-surrogate-insert");
    db::Library library = test::build_library(*dir_, dir_->path() / "LIB", kPaths);
    dataset_ = new Dataset(reindex(library));
    for (const Sample& s : dataset_->samples) (s.origin.path_id > kCompressions ? base_ : added_).push_back(s);
    // Length scales fitted on the library the run starts with.
    scales_ = fit_length_scales(dataset_->constants, base_, {}).scales;
  }
  static void TearDownTestSuite() {
    delete dataset_;
    delete dir_;
  }

  // Share of the compressions' intervals whose estimated error [Pa] is within the tolerance.
  static double hit_rate(const SurrogateIndex& index) {
    db::Library library = db::Library::open(dir_->path() / "LIB");
    int queries = 0, hits = 0;
    for (std::int64_t path = 1; path <= kCompressions; ++path) {
      const std::vector<db::Record> records = library.records(path);
      for (std::size_t k = 0; k + 1 < records.size(); ++k) {
        const PointState state = point_state(records[k]);
        const dem::Mat3& L = records[k + 1].L;
        const Prediction p = index.predict_without(feature_vector(state_features(state, L, index.constants())), {path, std::nullopt});
        const double error = p.fit.stress_error * answer_scale(state.stress, L, index.constants()) *
                             (records[k + 1].time - records[k].time);
        ++queries;
        hits += error <= kTolerance;
      }
    }
    return static_cast<double>(hits) / queries;
  }

  static test::TempDir* dir_;
  static Dataset* dataset_;
  static std::vector<Sample> base_, added_;
  static LengthScales scales_;
};

test::TempDir* SurrogateInsert::dir_ = nullptr;
Dataset* SurrogateInsert::dataset_ = nullptr;
std::vector<Sample> SurrogateInsert::base_, SurrogateInsert::added_;
LengthScales SurrogateInsert::scales_{};

TEST_F(SurrogateInsert, InsertedSamplesRaiseTheHitRateOfNearbyQueries) {
  SurrogateIndex index(dataset_->constants, scales_);
  index.insert(base_);
  const double before = hit_rate(index);
  index.insert(added_);
  const double after = hit_rate(index);
  std::printf("hit rate of the compressions: %.2f before, %.2f after inserting %zu samples\n", before, after,
              added_.size());
  EXPECT_EQ(index.size(), dataset_->samples.size());
  EXPECT_GE(after, before + 0.3);  // measured 0.04 -> 0.44
}

TEST_F(SurrogateInsert, QueriesRunWhileSamplesAreInserted) {
  SurrogateIndex index(dataset_->constants, scales_);
  index.insert(base_);
  const Sample query = added_.front();
  const Prediction alone = index.predict(query.features);
  std::atomic<bool> done{false};
  std::atomic<int> bad{0}, queries{0};
  std::vector<std::thread> readers;
  for (int t = 0; t < 3; ++t)
    readers.emplace_back([&] {
      while (!done.load()) {
        const Prediction p = index.predict(query.features);
        bad += p.neighbours != index.options().k || !std::isfinite(p.fit.stress_error);
        ++queries;
      }
    });
  // One at a time, as live steps come, each after at least one more query has completed, so that
  // queries and inserts interleave whatever the scheduling.
  for (const Sample& s : added_) {
    const int seen = queries.load();
    while (queries.load() == seen) std::this_thread::yield();
    index.insert({s});
  }
  done = true;
  for (std::thread& t : readers) t.join();
  EXPECT_EQ(bad.load(), 0);
  EXPECT_GE(queries.load(), static_cast<int>(added_.size()));
  // Once inserted, the query's own sample is its nearest neighbour.
  const Prediction after = index.predict(query.features);
  EXPECT_EQ(after.nearest, query.origin);
  EXPECT_EQ(after.distance, 0);
  EXPECT_GT(alone.distance, 0);
}

}  // namespace
}  // namespace grainbank::surrogate

// An existing library, sampled by the current sampler (the six paths of the sampler tests), re-indexes
// for the state-keyed surrogate without resampling: one sample per recorded interval, constants
// taken from its template and material, and each sample's answer advances its record to the next.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "database/store/library.hpp"
#include "tests/database/surrogate_test_util.hpp"

namespace grainbank::surrogate {
namespace {

TEST(SurrogateReindex, AnExistingLibraryReindexes) {
  const test::TempDir dir("grainbank-surrogate-reindex");
  db::Library library = test::build_library(dir, dir.path() / "LIB", sampler::test::kPaths);
  const Dataset dataset = reindex(library);

  // Constants: the template was prepared at 1000 Pa from diameters in [3.4e-4, 4e-4] m.
  EXPECT_NEAR(dataset.constants.p_ref, 1000, 100);
  EXPECT_NEAR(dataset.constants.p_floor, dataset.constants.p_ref / 10, 1e-12);
  EXPECT_GT(dataset.constants.diameter, 3.4e-4);
  EXPECT_LT(dataset.constants.diameter, 4.0e-4);
  EXPECT_EQ(dataset.constants.density, 920);

  std::size_t expected = 0, checked = 0;
  for (const db::PathRow& path : library.catalogue().paths()) {
    ASSERT_EQ(path.status, db::PathStatus::done);
    const std::vector<db::Record> records = library.records(path.id);
    expected += records.size() - 1;  // every interval of these paths stretches the cell
    for (const Sample& s : dataset.samples) {
      if (s.origin.path_id != path.id) continue;
      const auto k = static_cast<std::size_t>(s.origin.record_index);
      const db::Record& before = records.at(k);
      const db::Record& after = records.at(k + 1);
      const FeatureVector f = feature_vector(state_features(point_state(before), after.L, dataset.constants));
      for (std::size_t j = 0; j < kFeatureCount; ++j) EXPECT_DOUBLE_EQ(s.features[j], f[j]);
      // The answer of an interval integrates its record into the next (out-of-plane shears aside).
      const PointState next = advance(point_state(before), after.L, after.time - before.time, s.answer, dataset.constants);
      const dem::Mat3 target = db::from_stress6(after.stress);
      for (const auto& [r, c] : {std::pair{0, 0}, {1, 1}, {2, 2}, {0, 1}})
        EXPECT_NEAR(next.stress(r, c), target(r, c), 1e-9 * target.norm()) << "path " << path.id << " record " << k;
      EXPECT_NEAR(next.solid_fraction, after.solid_fraction, 1e-12);
      EXPECT_NEAR(next.coordination, after.coordination, 1e-9);
      ++checked;
    }
  }
  EXPECT_EQ(dataset.samples.size(), expected);
  EXPECT_EQ(checked, expected);
  EXPECT_GT(expected, 50u);
}

// With a span of three intervals each sample still starts at its own record, reaches up to three
// intervals further while the loading stays the same and never across a change of it (the generated
// paths change L between their two segments, the replayed one at every record), and its answer is
// the mean rate that takes its first record to its last.
TEST(SurrogateReindex, ASampleSpansIntervalsOfOneLoadingOnly) {
  const test::TempDir dir("grainbank-surrogate-span");
  db::Library library = test::build_library(dir, dir.path() / "LIB", sampler::test::kPaths);
  constexpr std::size_t kSpan = 3;
  const Dataset single = reindex(library), spanned = reindex(library, kSpan);
  ASSERT_EQ(spanned.samples.size(), single.samples.size()) << "one sample per interval, as before";
  std::size_t longer = 0, shortened = 0;
  for (const db::PathRow& path : library.catalogue().paths()) {
    const std::vector<db::Record> records = library.records(path.id);
    for (const Sample& s : spanned.samples) {
      if (s.origin.path_id != path.id) continue;
      const auto k = static_cast<std::size_t>(s.origin.record_index);
      const db::Record& before = records.at(k);
      // The furthest record within the span whose intervals all share interval k's L.
      std::size_t last = k + 1;
      while (last < k + kSpan && last + 1 < records.size() && records[last + 1].L == records[k + 1].L) ++last;
      (last - k == kSpan ? longer : shortened) += 1;
      const PointState end = advance(point_state(before), records[k + 1].L, records[last].time - before.time, s.answer,
                                     spanned.constants);
      const dem::Mat3 target = db::from_stress6(records[last].stress);
      for (const auto& [r, c] : {std::pair{0, 0}, {1, 1}, {2, 2}, {0, 1}})
        EXPECT_NEAR(end.stress(r, c), target(r, c), 1e-9 * target.norm()) << "path " << path.id << " record " << k;
      EXPECT_NEAR(end.coordination, records[last].coordination, 1e-9);
    }
  }
  EXPECT_GT(longer, shortened) << "most samples span the whole span";
  EXPECT_GT(shortened, 0u) << "the samples before a change of loading stop at it";
  EXPECT_THROW(reindex(library, 0), std::invalid_argument);
}

// A pressure-controlled segment servoes L's in-plane isotropic part at every increment, so no two of
// its records share L: its intervals count as one loading, each sample spans up to three of them
// under their time-weighted mean L (which takes its first record to its last), and none reaches into
// the kinematic segment after it.
TEST(SurrogateReindex, ASampleSpansThePressureControlledIntervalsOfOneSegment) {
  const test::TempDir dir("grainbank-surrogate-held");
  db::Library library = test::build_library(dir, dir.path() / "LIB", R"({"record_interval": 2e-4,
    "paths": [{"segments": [{"L": [[0, 2], [0, 0]], "duration": 0.004, "pressure": 1000},
                            {"L": [[0, 1], [0, 0]], "duration": 0.002}]}]})");
  const db::PathRow path = library.catalogue().paths().front();
  const std::vector<HeldSegment> held = held_segments(path.spec);
  ASSERT_EQ(held.size(), 1u);
  EXPECT_NEAR(held[0].begin, 0, 1e-15);
  EXPECT_NEAR(held[0].end, 0.004, 1e-15);
  const std::vector<db::Record> records = library.records(path.id);
  ASSERT_GT(records.size(), 25u);
  ASSERT_NE(records[2].L, records[1].L) << "the servo changes L at every record";

  constexpr std::size_t kSpan = 3;
  const Dataset dataset = reindex(library, kSpan);
  std::size_t spanning = 0;
  for (const Sample& s : dataset.samples) {
    const auto k = static_cast<std::size_t>(s.origin.record_index);
    const bool in_held = records[k + 1].time <= 0.004 + 1e-9;
    // The furthest record the sample may reach: within the span, and within the held segment or, in
    // the kinematic one, while L stays the same.
    std::size_t last = k + 1;
    while (last < k + kSpan && last + 1 < records.size() &&
           (in_held ? records[last + 1].time <= 0.004 + 1e-9 : records[last + 1].L == records[k + 1].L))
      ++last;
    if (in_held && last - k == kSpan) ++spanning;
    dem::Mat3 L = dem::Mat3::Zero();
    for (std::size_t j = k + 1; j <= last; ++j) L += records[j].L * (records[j].time - records[j - 1].time);
    const double dt = records[last].time - records[k].time;
    const PointState end = advance(point_state(records[k]), L / dt, dt, s.answer, dataset.constants);
    const dem::Mat3 target = db::from_stress6(records[last].stress);
    for (const auto& [r, c] : {std::pair{0, 0}, {1, 1}, {2, 2}, {0, 1}})
      EXPECT_NEAR(end.stress(r, c), target(r, c), 1e-9 * target.norm()) << "record " << k;
  }
  EXPECT_EQ(dataset.samples.size(), records.size() - 1);
  EXPECT_GT(spanning, 10u) << "the held segment's samples span three intervals";
  EXPECT_TRUE(held_segments(R"({"replay": [[[0, 1], [0, 0]]]})").empty());
}

// Paths that share their first segment give that segment's intervals the same key to the bit (the
// sampler is deterministic): the state probes of one base at several depths and rates do. One key
// is one sample, the one whose answer spans the most intervals: here the longer path's, over three
// intervals, and not the shorter's, over the one interval before its loading changes.
TEST(SurrogateReindex, AKeyRepeatedAcrossPathsIsOneSample) {
  const test::TempDir dir("grainbank-surrogate-repeats");
  db::Library library = test::build_library(dir, dir.path() / "LIB", R"({"record_interval": 2e-4,
    "paths": [{"segments": [{"L": [[0, 2], [0, 0]], "duration": 2e-4}, {"L": [[-1, 0], [0, 1]], "duration": 6e-4}]},
              {"segments": [{"L": [[0, 2], [0, 0]], "duration": 8e-4}]}]})");
  std::vector<std::vector<db::Record>> paths;
  std::size_t intervals = 0;
  for (const db::PathRow& path : library.catalogue().paths()) {
    paths.push_back(library.records(path.id));
    intervals += paths.back().size() - 1;
  }
  ASSERT_EQ(paths.size(), 2u);
  const std::size_t long_path = paths[0][1].L == paths[0][2].L ? 0 : 1;
  const std::int64_t long_id = library.catalogue().paths()[long_path].id;
  const std::vector<db::Record>& longer = paths[long_path];
  const std::vector<db::Record>& shorter = paths[1 - long_path];
  ASSERT_EQ(shorter[0].stress, longer[0].stress);
  ASSERT_EQ(shorter[1].L, longer[1].L);
  ASSERT_NE(shorter[2].L, longer[2].L);

  constexpr std::size_t kSpan = 3;
  const Dataset dataset = reindex(library, kSpan);
  EXPECT_EQ(dataset.samples.size(), intervals - 1) << "the shared first interval is one sample";
  for (std::size_t a = 0; a < dataset.samples.size(); ++a)
    for (std::size_t b = a + 1; b < dataset.samples.size(); ++b)
      EXPECT_NE(dataset.samples[a].features, dataset.samples[b].features) << a << " and " << b;
  const FeatureVector first = feature_vector(state_features(point_state(longer[0]), longer[1].L, dataset.constants));
  const auto kept = std::find_if(dataset.samples.begin(), dataset.samples.end(),
                                 [&](const Sample& s) { return s.features == first; });
  ASSERT_NE(kept, dataset.samples.end());
  EXPECT_EQ(kept->origin, (SampleOrigin{long_id, 0}));
  const PointState end =
      advance(point_state(longer[0]), longer[1].L, longer[kSpan].time - longer[0].time, kept->answer, dataset.constants);
  const dem::Mat3 target = db::from_stress6(longer[kSpan].stress);
  for (const auto& [r, c] : {std::pair{0, 0}, {1, 1}, {2, 2}, {0, 1}})
    EXPECT_NEAR(end.stress(r, c), target(r, c), 1e-9 * target.norm()) << "its answer spans three intervals";
}

TEST(SurrogateReindex, ALibraryWithoutATemplateIsRefusedByName) {
  const test::TempDir dir("grainbank-surrogate-empty");
  const app::CellInput input = app::load_cell_input(dir.write("cell.json", sampler::test::kCell));
  db::Library library = db::Library::create(dir.path() / "LIB", input.material);
  try {
    reindex(library);
    FAIL() << "an empty library re-indexed";
  } catch (const db::StoreError& e) {
    EXPECT_NE(std::string(e.what()).find("LIB"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("no template"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace grainbank::surrogate

// The audit's statistics and sample draw (database/audit): quantiles, distance bins and the suggested
// tolerance against hand-computed values, and a draw that is reproducible and never picks record 0.
#include <gtest/gtest.h>

#include <cmath>

#include "database/audit/audit_sample.hpp"
#include "database/audit/error_statistics.hpp"

namespace grainbank::audit {
namespace {

TEST(AuditStatistics, QuantilesInterpolateBetweenOrderStatistics) {
  const std::vector<double> values{4, 1, 3, 2};
  EXPECT_DOUBLE_EQ(quantile(values, 0.5), 2.5);
  EXPECT_DOUBLE_EQ(quantile(values, 0.95), 3.85);  // 3 + 0.85 (4 - 3)
  EXPECT_DOUBLE_EQ(quantile(values, 0), 1);
  EXPECT_DOUBLE_EQ(quantile(values, 1), 4);
  const ErrorSummary s = summarize(values);
  EXPECT_EQ(s.count, 4u);
  EXPECT_DOUBLE_EQ(s.max, 4);
  EXPECT_EQ(summarize({}).count, 0u);
  EXPECT_THROW(quantile({}, 0.5), std::invalid_argument);
}

TEST(AuditStatistics, RelativeErrorIsTheFrobeniusNormOfTheSymmetricTensorWithAFloor) {
  // ‖σ‖_F of a pure shear τ counts both off-diagonal entries: √2 τ.
  EXPECT_DOUBLE_EQ(stress_norm({0, 0, 0, 3, 0, 0}), std::sqrt(18.0));
  const db::Stress6 truth{-100, 0, 0, 0, 0, 0};
  EXPECT_DOUBLE_EQ(relative_stress_error({-90, 0, 0, 0, 0, 0}, truth, 1), 0.1);
  EXPECT_DOUBLE_EQ(relative_stress_error({-90, 0, 0, 0, 0, 0}, truth, 1000), 0.01);  // the floor wins
  EXPECT_EQ(relative_stress_error(truth, truth, 0), 0);
  EXPECT_TRUE(std::isinf(relative_stress_error({1, 0, 0, 0, 0, 0}, {}, 0)));
}

// 100 answers at distances 0.01 .. 1 whose error is a tenth of their distance.
std::vector<DistanceError> linear_answers() {
  std::vector<DistanceError> answers;
  for (int i = 100; i >= 1; --i) answers.push_back({0.01 * i, 0.001 * i});
  return answers;
}

TEST(AuditStatistics, BinsHoldEqualCountsInDistanceOrder) {
  const std::vector<DistanceBin> bins = bin_by_distance(linear_answers(), 10, 8);
  ASSERT_EQ(bins.size(), 10u);
  for (std::size_t b = 0; b < bins.size(); ++b) {
    EXPECT_EQ(bins[b].error.count, 10u);
    EXPECT_NEAR(bins[b].distance_min, 0.01 * (10 * b + 1), 1e-12);
    EXPECT_NEAR(bins[b].distance_max, 0.01 * (10 * b + 10), 1e-12);
    EXPECT_NEAR(bins[b].error.median, 0.001 * (10 * b + 5.5), 1e-12);
  }
  // Too few answers for the requested bins: fewer bins, each with at least min_per_bin answers.
  EXPECT_EQ(bin_by_distance(std::vector<DistanceError>(20, {1, 1}), 10, 8).size(), 2u);
  EXPECT_EQ(bin_by_distance(std::vector<DistanceError>(3, {1, 1}), 10, 8).size(), 1u);
  EXPECT_TRUE(bin_by_distance({}).empty());
}

TEST(AuditStatistics, SuggestedToleranceIsTheLargestWhoseHitsKeepTheTarget) {
  const std::vector<DistanceError> answers = linear_answers();
  const std::vector<DistanceBin> bins = bin_by_distance(answers, 10, 8);
  // Hits at tolerance t are the answers with d <= t; their p95 error is about 0.095 t: within 0.03
  // at the bin edge t = 0.3 (p95 = 0.02855) but not at the next one, t = 0.4 (0.03805).
  const std::optional<HitErrors> s = suggest_tolerance(answers, bins, 0.03);
  ASSERT_TRUE(s.has_value());
  EXPECT_NEAR(s->tolerance, 0.3, 1e-12);
  EXPECT_NEAR(s->hit_share, 0.3, 1e-12);
  EXPECT_EQ(s->hits.count, 30u);
  EXPECT_NEAR(s->hits.p95, 0.02855, 1e-12);
  EXPECT_NEAR(hits_at(answers, 0.4).hits.p95, 0.03805, 1e-12);
  EXPECT_FALSE(suggest_tolerance(answers, bins, 0.005).has_value());  // the first bin's p95 is 0.00955
  EXPECT_NEAR(suggest_tolerance(answers, bins, 1)->tolerance, 1.0, 1e-12);
}

TEST(AuditStatistics, HitsAtAToleranceAreTheAnswersWithinIt) {
  const HitErrors h = hits_at(linear_answers(), 0.255);
  EXPECT_EQ(h.hits.count, 25u);
  EXPECT_DOUBLE_EQ(h.hit_share, 0.25);
  EXPECT_DOUBLE_EQ(h.hits.max, 0.025);
  EXPECT_EQ(hits_at(linear_answers(), 0).hits.count, 0u);
  EXPECT_EQ(hits_at({}, 1).hit_share, 0);
}

std::vector<db::PathRow> paths_for_draw() {
  std::vector<db::PathRow> rows;
  for (std::int64_t id = 1; id <= 12; ++id) {
    db::PathRow row;
    row.id = id;
    row.status = id == 3 ? db::PathStatus::failed : id == 4 ? db::PathStatus::pending : db::PathStatus::done;
    row.record_count = id == 5 ? 1 : 10 + id;
    rows.push_back(row);
  }
  return rows;
}

TEST(AuditSampleDraw, IsReproducibleAndDrawsOnlyRecordsProducedByIncrements) {
  const std::vector<db::PathRow> rows = paths_for_draw();
  const SampleSpec spec{4, 20, 42};
  const AuditSample a = draw_sample(rows, spec), b = draw_sample(rows, spec);
  EXPECT_EQ(a.paths, b.paths);
  EXPECT_EQ(a.records, b.records);
  ASSERT_EQ(a.paths.size(), 4u);
  ASSERT_EQ(a.records.size(), 20u);
  EXPECT_TRUE(std::is_sorted(a.paths.begin(), a.paths.end()));
  for (std::int64_t id : a.paths) EXPECT_TRUE(id != 3 && id != 4 && id != 5) << id;  // failed, pending, 1 record
  for (const lookup::RecordRef& r : a.records) {
    EXPECT_TRUE(std::binary_search(a.paths.begin(), a.paths.end(), r.path_id));
    EXPECT_GE(r.record_index, 1);
    EXPECT_LT(r.record_index, 10 + r.path_id);
  }
  EXPECT_NE(draw_sample(rows, {4, 20, 43}).records, a.records);
  // More asked than there is: everything eligible, once.
  const AuditSample all = draw_sample(rows, {100, 1000, 1});
  EXPECT_EQ(all.paths.size(), 9u);
  std::size_t eligible = 0;
  for (const db::PathRow& row : rows)
    if (row.status == db::PathStatus::done && row.record_count >= 2)
      eligible += static_cast<std::size_t>(row.record_count - 1);
  EXPECT_EQ(all.records.size(), eligible);
}

}  // namespace
}  // namespace grainbank::audit

// The surrogate index's neighbours are exact and well defined (surrogate_index.hpp): the k nearest
// and every sample tied with the k-th, whatever the grouping of the inserts that built its trees and
// whatever hint a query brings. Checked against a brute-force scan on random samples in which some
// feature vectors occur three times over, so that distances tie exactly.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <utility>
#include <vector>

#include "database/surrogate/surrogate_index.hpp"

namespace grainbank::surrogate {
namespace {

constexpr std::size_t kSamples = 3000;
constexpr std::size_t kQueries = 200;
const FeatureConstants kConstants{1000, 10, 1e-3, 2500};

std::vector<Sample> random_samples(std::mt19937& random) {
  std::normal_distribution<double> normal;
  std::vector<Sample> samples;
  while (samples.size() < kSamples) {
    Sample s;
    for (double& f : s.features) f = normal(random);
    for (double& a : s.answer) a = normal(random);
    s.origin = {static_cast<std::int64_t>(samples.size() / 50), static_cast<std::int64_t>(samples.size())};
    const std::size_t copies = samples.size() % 10 == 0 ? 3 : 1;  // exact ties in every distance
    for (std::size_t c = 0; c < copies && samples.size() < kSamples; ++c) {
      samples.push_back(s);
      samples.back().origin.record_index = static_cast<std::int64_t>(samples.size() - 1);
    }
  }
  return samples;
}

LengthScales scales() {
  LengthScales l;
  for (std::size_t j = 0; j < kFeatureCount; ++j) l[j] = 0.5 + 0.1 * static_cast<double>(j);
  return l;
}

// By a full scan: the samples no farther than the k-th nearest, by (squared scaled distance, index).
std::vector<std::size_t> brute_force(const std::vector<Sample>& samples, const FeatureVector& query, std::size_t k) {
  const LengthScales l = scales();
  std::vector<std::pair<double, std::size_t>> all;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    double d2 = 0;
    for (std::size_t j = 0; j < kFeatureCount; ++j) {
      const double d = query[j] / l[j] - samples[i].features[j] / l[j];
      d2 += d * d;
    }
    all.emplace_back(d2, i);
  }
  std::sort(all.begin(), all.end());
  std::vector<std::size_t> ids;
  for (const auto& [d2, i] : all)
    if (ids.size() < k || d2 == all[k - 1].first) ids.push_back(i);
  return ids;
}

class SurrogateIndexNeighbours : public ::testing::Test {
 protected:
  void SetUp() override {
    samples_ = random_samples(random_);
    std::normal_distribution<double> normal;
    for (std::size_t q = 0; q < kQueries; ++q) {
      FeatureVector f;
      if (q % 4 == 0) {
        f = samples_[(q * 37) % kSamples].features;  // on a sample, often one of three copies
      } else {
        for (double& x : f) x = normal(random_);
      }
      queries_.push_back(f);
    }
  }

  std::mt19937 random_{20261129};
  std::vector<Sample> samples_;
  std::vector<FeatureVector> queries_;
};

TEST_F(SurrogateIndexNeighbours, AreTheKNearestAndEverySampleTiedWithTheKth) {
  SurrogateIndex index(kConstants, scales());
  index.insert(samples_);
  const std::size_t k = index.options().k;
  std::size_t ties_at_the_kth = 0;
  for (const FeatureVector& q : queries_) {
    const Prediction p = index.predict(q);
    const std::vector<std::size_t> expected = brute_force(samples_, q, k);
    EXPECT_EQ(p.neighbour_ids, expected);
    EXPECT_EQ(p.neighbours, expected.size());
    if (expected.size() > k) ++ties_at_the_kth;
  }
  EXPECT_GT(ties_at_the_kth, 0u) << "no query met the ties at the k-th that this test is about";
}

TEST_F(SurrogateIndexNeighbours, DoNotDependOnHowTheSamplesWereInserted) {
  SurrogateIndex at_once(kConstants, scales());
  at_once.insert(samples_);
  // Batches of 1 to 200 samples: the settled tree is rebuilt as the inserts outgrow it, and the
  // last samples sit in the dynamic forest.
  SurrogateIndex in_batches(kConstants, scales());
  std::uniform_int_distribution<std::size_t> batch(1, 200);
  for (std::size_t first = 0; first < samples_.size();) {
    const std::size_t last = std::min(samples_.size(), first + batch(random_));
    in_batches.insert({samples_.begin() + static_cast<std::ptrdiff_t>(first), samples_.begin() + static_cast<std::ptrdiff_t>(last)});
    first = last;
  }
  ASSERT_EQ(in_batches.size(), at_once.size());
  for (const FeatureVector& q : queries_) {
    const Prediction a = at_once.predict(q), b = in_batches.predict(q);
    EXPECT_EQ(a.neighbour_ids, b.neighbour_ids);
    EXPECT_EQ(a.fit.answer, b.fit.answer);  // to the bit
    EXPECT_EQ(a.fit.stress_error, b.fit.stress_error);
  }
}

TEST_F(SurrogateIndexNeighbours, AreTheSameWithAnyHint) {
  SurrogateIndex index(kConstants, scales());
  index.insert(samples_);
  std::uniform_int_distribution<std::size_t> any(0, kSamples + 10);  // a few past the end
  std::vector<std::size_t> previous;
  for (const FeatureVector& q : queries_) {
    const Prediction plain = index.predict(q);
    std::vector<std::size_t> random_hint;
    for (int i = 0; i < 30; ++i) random_hint.push_back(any(random_));
    std::vector<std::size_t> repeated = plain.neighbour_ids;
    repeated.insert(repeated.end(), plain.neighbour_ids.begin(), plain.neighbour_ids.end());
    for (const std::vector<std::size_t>& hint : {plain.neighbour_ids, random_hint, previous, repeated}) {
      const Prediction hinted = index.predict(q, hint);
      EXPECT_EQ(hinted.neighbour_ids, plain.neighbour_ids);
      EXPECT_EQ(hinted.fit.answer, plain.fit.answer);
      EXPECT_EQ(hinted.fit.stress_error, plain.fit.stress_error);
    }
    previous = plain.neighbour_ids;
  }
}

}  // namespace
}  // namespace grainbank::surrogate

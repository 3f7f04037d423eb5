// The length-scale fit (length_scales.hpp): which probes it predicts, and that it finds the features
// an answer depends on, whichever set of probes it draws.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <set>

#include "database/surrogate/length_scales.hpp"

namespace grainbank::surrogate {
namespace {

const FeatureConstants kConstants{1000, 100, 1e-3, 1000};

// 40 paths of 30 samples: the first `varying` features uniform in [−1, 1] (the others 0.5), the
// stress answer's first component answer(features) plus Gaussian noise of deviation `noise`.
template <class AnswerOf>
std::vector<Sample> synthetic_samples(std::uint64_t seed, std::size_t varying, double noise, AnswerOf answer) {
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> uniform(-1, 1);
  std::normal_distribution<double> scatter(0, noise);
  std::vector<Sample> samples;
  for (std::int64_t path = 1; path <= 40; ++path)
    for (std::int64_t record = 0; record < 30; ++record) {
      Sample s;
      s.features.fill(0.5);
      for (std::size_t j = 0; j < varying; ++j) s.features[j] = uniform(random);
      s.answer.fill(0);
      s.answer[0] = answer(s.features) + scatter(random);
      s.origin = {path, record};
      samples.push_back(s);
    }
  return samples;
}

TEST(SurrogateLengthScales, ProbesAreEvenlySpacedAndSeedsShiftThem) {
  EXPECT_EQ(probe_indices(10, 5, 0), (std::vector<std::size_t>{0, 2, 4, 6, 8}));
  EXPECT_EQ(probe_indices(3, 5, 7).size(), 3u) << "no more probes than samples";
  constexpr std::size_t kSamples = 1003, kCount = 200;
  std::set<std::size_t> seen;
  for (std::uint64_t seed = 0; seed < 4; ++seed) {
    const std::vector<std::size_t> probes = probe_indices(kSamples, kCount, seed);
    ASSERT_EQ(probes.size(), kCount);
    for (std::size_t i = 0; i < kCount; ++i) {
      // One probe in each stride of samples/count: the set covers the dataset evenly.
      EXPECT_GE(probes[i], i * kSamples / kCount) << "seed " << seed;
      EXPECT_LT(probes[i], (i + 1) * kSamples / kCount + 1) << "seed " << seed;
    }
    seen.insert(probes.begin(), probes.end());
  }
  EXPECT_GT(seen.size(), 3 * kCount) << "the seeds draw different probes";
}

// Samples on 40 paths whose stress answer is 10 × feature 0 plus noise: feature 0 matters and
// feature 1 does not. Every seed's fit lowers its loss and scales feature 0 finer, relative to its
// spread, than feature 1.
TEST(SurrogateLengthScales, EverySeedFindsTheFeatureTheAnswerDependsOn) {
  const std::vector<Sample> samples =
      synthetic_samples(5, kFeatureCount, 0.3, [](const FeatureVector& x) { return 10 * x[0]; });
  const LengthScales start = initial_length_scales(samples);
  for (std::uint64_t seed = 0; seed < 3; ++seed) {
    LengthScaleSearch search;
    search.seed = seed;
    const LengthScaleFit fit = fit_length_scales(kConstants, samples, {}, search);
    EXPECT_LT(fit.loss, fit.initial_loss) << "seed " << seed;
    EXPECT_LT(fit.scales[0] / start[0], fit.scales[1] / start[1]) << "seed " << seed;
    const LengthScaleFit again = fit_length_scales(kConstants, samples, {}, search);
    EXPECT_EQ(again.scales, fit.scales) << "a fit is deterministic";
  }
}

// Samples on 40 paths whose stress answer is 10 (sin 3x₀ + sin 3x₁) plus noise, x₂ varying and
// irrelevant, the other features constant. The answer bends along x₀ and x₁ alike, so neighbourhoods
// stretched along either one predict worse: the probes determine both scales, e times finer or
// coarser. x₂ is best ignored: a coarser scale is no worse, so its scale is not determined. A constant
// feature's scale changes no distance: its evidence is exactly nil.
TEST(SurrogateLengthScales, EvidenceTellsTheScalesTheProbesDetermine) {
  const std::vector<Sample> samples = synthetic_samples(
      11, 3, 0.1, [](const FeatureVector& x) { return 10 * (std::sin(3 * x[0]) + std::sin(3 * x[1])); });
  LengthScaleSearch search;
  search.probes = 400;
  const LengthScaleFit fit = fit_length_scales(kConstants, samples, {}, search);
  for (std::size_t j = 0; j < 3; ++j)
    std::printf("feature %zu: scale %.3g, finer %.2f, coarser %.2f standard errors\n", j, fit.scales[j],
                fit.evidence[j].finer, fit.evidence[j].coarser);
  for (const std::size_t j : {0, 1}) {
    EXPECT_GT(fit.evidence[j].finer, 2) << "feature " << j;
    EXPECT_GT(fit.evidence[j].coarser, 2) << "feature " << j;
    EXPECT_TRUE(fit.evidence[j].determined()) << "feature " << j;
  }
  EXPECT_LT(fit.evidence[2].coarser, 2) << "an irrelevant feature is as well ignored more";
  EXPECT_FALSE(fit.evidence[2].determined());
  for (std::size_t j = 3; j < kFeatureCount; ++j) {
    EXPECT_EQ(fit.evidence[j].finer, 0) << "feature " << j;
    EXPECT_EQ(fit.evidence[j].coarser, 0) << "feature " << j;
    EXPECT_FALSE(fit.evidence[j].determined()) << "feature " << j;
  }
  EXPECT_GT(fit.gain, 2) << "the fit predicts the probes better than its start";
  EXPECT_EQ(fit.probes, 400u);
  // The reported calibration is that of the estimates at the fitted scales.
  EXPECT_GT(fit.coverage, 0);
  EXPECT_LE(fit.coverage, 1);
  EXPECT_GT(fit.median_error_over_estimate, 0);
}

}  // namespace
}  // namespace grainbank::surrogate

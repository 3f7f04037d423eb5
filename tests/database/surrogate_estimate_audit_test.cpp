// The error estimate against the errors it estimates (estimate_audit.hpp): the calibration's
// counting, and the audit of states the library does not hold, on materials whose answers are known.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "database/surrogate/estimate_audit.hpp"
#include "database/surrogate/length_scales.hpp"

namespace grainbank::surrogate {
namespace {

const FeatureConstants kConstants{1000, 100, 1e-3, 1000};

TEST(SurrogateEstimateAudit, CalibrationCountsCoverageAndMedians) {
  // Covered: 1 ≤ 2, 2 ≤ 2, 4 ≤ 8 and the error-free pair; 3 > 1 is not. Ratios 0.5, 1, 3, 0.5, 0.
  const std::vector<double> errors{1, 2, 3, 4, 0}, estimates{2, 2, 1, 8, 5};
  const EstimateCalibration c = calibration_of(errors, estimates);
  EXPECT_EQ(c.samples, 5u);
  EXPECT_DOUBLE_EQ(c.coverage, 0.8);
  EXPECT_DOUBLE_EQ(c.median_error_over_estimate, 0.5);
  EXPECT_DOUBLE_EQ(c.median_error, 2);
  EXPECT_DOUBLE_EQ(c.median_estimate, 2);
  const EstimateCalibration none = calibration_of({}, {});
  EXPECT_EQ(none.samples, 0u);
  EXPECT_EQ(none.coverage, 0);
  EXPECT_THROW(calibration_of(errors, std::vector<double>{1, 2}), std::invalid_argument);
}

// A library of 40 paths whose stress answer is linear in two features, 10 x₀ + 5 x₁ (the others
// constant): a local linear fit reproduces it to round-off, so the answer's own error is nil.
std::vector<Sample> linear_library() {
  std::vector<Sample> samples;
  for (std::int64_t path = 0; path < 40; ++path)
    for (std::int64_t record = 0; record < 30; ++record) {
      Sample s;
      s.features.fill(0.5);
      s.features[0] = -1 + 2 * std::fmod(0.37 * static_cast<double>(path) + 0.011 * static_cast<double>(record), 1.0);
      s.features[1] = -1 + 2 * std::fmod(0.61 * static_cast<double>(record) + 0.13 * static_cast<double>(path), 1.0);
      s.answer.fill(0);
      s.answer[0] = 10 * s.features[0] + 5 * s.features[1];
      s.origin = {path, record};
      samples.push_back(s);
    }
  return samples;
}

TEST(SurrogateEstimateAudit, AMaterialTheLibraryDoesNotKnowIsAnErrorTheEstimateDoesNotSee) {
  const std::vector<Sample> library = linear_library();
  const LengthScales scales = initial_length_scales(library);
  SurrogateOptions options;
  options.ridge = 1e-9;
  // The same states, answered 3 higher: at a sample's own key the estimate has no distance term and
  // no residual, while the error is the whole offset. Nothing is covered.
  std::vector<Sample> other = library;
  for (Sample& s : other) s.answer[0] += 3;
  const EstimateCalibration missed = audit_estimate(kConstants, library, scales, options, other, 100);
  EXPECT_EQ(missed.samples, 100u) << "at most `at_most` states";
  EXPECT_EQ(missed.coverage, 0);
  EXPECT_NEAR(missed.median_error, 3, 1e-6);
  EXPECT_LT(missed.median_estimate, 1e-6);
  // States between the samples with the library's own material: answered to round-off, and the
  // estimate's distance term covers that.
  std::vector<Sample> between;
  for (std::size_t i = 0; i + 1 < library.size(); i += 7) {
    Sample s = library[i];
    s.features[0] = 0.5 * (library[i].features[0] + library[i + 1].features[0]);
    s.features[1] = 0.5 * (library[i].features[1] + library[i + 1].features[1]);
    s.answer[0] = 10 * s.features[0] + 5 * s.features[1];
    between.push_back(s);
  }
  const EstimateCalibration known = audit_estimate(kConstants, library, scales, options, between, 10000);
  EXPECT_EQ(known.samples, between.size());
  EXPECT_EQ(known.coverage, 1);
  EXPECT_LT(known.median_error, 1e-6);
  EXPECT_GT(known.median_estimate, 0.01);
}

}  // namespace
}  // namespace grainbank::surrogate

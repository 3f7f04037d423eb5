// A library sampled from state probes (dem_sampler/sampler/state_probes.hpp) with the real sampler,
// re-indexed for the state-keyed surrogate: its samples hold every requested dilatancy angle ψ of the
// probes and of their returns (−ψ), around states that went beyond the template (the base strains).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "tests/database/surrogate_test_util.hpp"

namespace grainbank::surrogate {
namespace {

// Two shear depths of the 64-sphere cohesive cell, probed at ψ = −45, 0, 45° and two axes.
constexpr const char* kProbes = R"({
  "record_interval": 2e-4, "snapshot_interval": 5,
  "probes": [{"bases": ["shear", "compression"], "depths": [0.002, 0.004], "base_rate": 2,
              "psi": [-45, 0, 45], "beta": [0, 90], "rates": [2], "probe_strain": 0.0008}]
})";

TEST(SurrogateProbes, AProbeLibraryHoldsEveryRequestedLoadingDirection) {
  const test::TempDir dir("grainbank-surrogate-probes");
  db::Library library = test::build_library(dir, dir.path() / "LIB", kProbes);
  EXPECT_EQ(library.catalogue().paths().size(), 4u);
  const Dataset dataset = reindex(library);
  ASSERT_GT(dataset.samples.size(), 40u);
  for (const double degrees : {-45.0, 0.0, 45.0}) {
    const double target = std::sin(degrees * std::numbers::pi / 180);
    int found = 0;
    for (const Sample& s : dataset.samples) found += std::abs(s.features[6] - target) < 1e-6;  // sin ψ
    EXPECT_GE(found, 4) << "ψ = " << degrees << "°";
  }
  // The probes start from states the base strains moved away from the template's pressure.
  const double template_log_p = dataset.samples.front().features[0];
  double farthest = 0;
  for (const Sample& s : dataset.samples) farthest = std::max(farthest, std::abs(s.features[0] - template_log_p));
  EXPECT_GT(farthest, 0.1);
}

}  // namespace
}  // namespace grainbank::surrogate

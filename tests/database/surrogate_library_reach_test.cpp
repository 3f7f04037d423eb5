// Where states lie against a library's samples, feature by feature (library_reach.hpp), on
// hand-made libraries whose tail values are known.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <stdexcept>
#include <vector>

#include "database/surrogate/library_reach.hpp"

namespace grainbank::surrogate {
namespace {

Sample at(std::size_t feature, double value) {
  Sample s;
  s.features.fill(0);
  s.features[feature] = value;
  return s;
}

// 100 samples with feature 4 (Z) at 0, 1, …, 99 and every other feature 0.
std::vector<Sample> ramp_library() {
  std::vector<Sample> library;
  for (int v = 0; v < 100; ++v) library.push_back(at(4, v));
  return library;
}

TEST(SurrogateLibraryReach, CountsTheStatesBeyondEachTailOfEachFeature) {
  // tail 0.05 of 100 samples: the tail values are 5 and 94, with five samples beyond each.
  std::vector<Sample> states{at(4, 4.9), at(4, 5), at(4, 50), at(4, 94), at(4, 94.1), at(4, 200)};
  states.push_back(at(5, 0.1));  // D above the library's single value, Z (0) below its tail
  const LibraryReach reach = library_reach(ramp_library(), states, 0.05);
  EXPECT_EQ(reach.states, 7u);
  EXPECT_EQ(reach.tail, 0.05);
  EXPECT_DOUBLE_EQ(reach.features[4].below, 2.0 / 7) << "4.9 and the D state's Z = 0; a tail value is inside";
  EXPECT_DOUBLE_EQ(reach.features[4].above, 2.0 / 7) << "94.1 and 200";
  EXPECT_DOUBLE_EQ(reach.features[5].above, 1.0 / 7);
  EXPECT_EQ(reach.features[5].below, 0);
  EXPECT_EQ(reach.features[0].below + reach.features[0].above, 0) << "every state at the library's only value";
  EXPECT_DOUBLE_EQ(reach.beyond_any, 4.0 / 7) << "the D state is beyond in two features and counts once";
}

TEST(SurrogateLibraryReach, TheLibrarysOwnSamplesLieBeyondAtMostTheTail) {
  std::mt19937_64 random(7);
  std::normal_distribution<double> normal;
  std::vector<Sample> library(1000);
  for (Sample& s : library)
    for (double& f : s.features) f = normal(random);
  for (const double tail : {0.0, 0.01, 0.1}) {
    const LibraryReach own = library_reach(library, library, tail);
    for (const FeatureReach& f : own.features) {
      EXPECT_LE(f.below, tail);
      EXPECT_LE(f.above, tail);
      EXPECT_GE(f.below, tail - 1e-3) << "ties aside, exactly ⌊tail·n⌋ of n lie below the tail value";
    }
  }
  // The order of either sequence does not matter.
  std::vector<Sample> shuffled = library;
  std::shuffle(shuffled.begin(), shuffled.end(), random);
  std::vector<Sample> states(library.begin(), library.begin() + 300);
  for (std::size_t i = 0; i < 100; ++i) states[i].features[3] = 100;  // φ beyond every sample
  const LibraryReach a = library_reach(library, states, 0.01), b = library_reach(shuffled, states, 0.01);
  std::vector<Sample> reversed(states.rbegin(), states.rend());
  const LibraryReach c = library_reach(library, reversed, 0.01);
  for (std::size_t j = 0; j < kFeatureCount; ++j) {
    EXPECT_EQ(a.features[j].below, b.features[j].below);
    EXPECT_EQ(a.features[j].above, c.features[j].above);
  }
  EXPECT_GE(a.features[3].above, 1.0 / 3);
  EXPECT_LE(a.features[3].above, 1.0 / 3 + 0.02) << "of the other 200, about 1 % lie above the tail value";
}

TEST(SurrogateLibraryReach, NothingToCompareIsNothingBeyondAndATailMustBeAShare) {
  EXPECT_EQ(library_reach({}, {at(0, 1)}, 0.01).beyond_any, 0);
  const LibraryReach none = library_reach(ramp_library(), {}, 0.01);
  EXPECT_EQ(none.states, 0u);
  EXPECT_EQ(none.beyond_any, 0);
  EXPECT_THROW(library_reach(ramp_library(), {}, 0.5), std::invalid_argument);
  EXPECT_THROW(library_reach(ramp_library(), {}, -0.1), std::invalid_argument);
}

}  // namespace
}  // namespace grainbank::surrogate

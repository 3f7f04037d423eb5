// Where a run's states lie against its library's samples, feature by feature (issue 13).
//
// An error estimate can only be as honest as the neighbours it is fitted on. On the flowing columns
// of the generalization study the states where the cells ran live lay outside the library: looser
// (φ), less connected (Z), more damaged (D) than nearly all of its samples, their nearest sample a
// median two standard deviations away where the library's samples lie 0.04 from each other
// (docs/surrogate.md, "Stop 66"). There the surrogate extrapolates, and no estimate fitted on the
// library can say by how much. library_reach tells a run which of its states the library does not
// reach, and in which feature, so that a user knows what paths to add.
//
// Promises:
// - Per feature of the key (state_features.hpp, kFeatureNames), the share of `states` below the
//   library's lower tail value and the share above its upper one. Of the n library samples' values,
//   k = ⌊tail·n⌋ lie below the lower tail value and k above the upper one, ties aside (tail 0: the
//   library's minimum and maximum); a state equal to a tail value is inside. So the library's own
//   samples lie beyond at most a share `tail` at each end.
// - beyond_any: the share of states beyond the tails in at least one feature.
// - No states or no library: every share 0. Throws std::invalid_argument for tail outside [0, 0.5).
// - Deterministic and independent of the order of either sequence.
#pragma once
#include <array>
#include <cstddef>
#include <vector>

#include "database/surrogate/sample.hpp"

namespace grainbank::surrogate {

struct FeatureReach {
  double below = 0, above = 0;  // shares of the states beyond the library's lower and upper tail values
};

struct LibraryReach {
  std::size_t states = 0;
  double tail = 0;
  std::array<FeatureReach, kFeatureCount> features{};
  double beyond_any = 0;
};

LibraryReach library_reach(const std::vector<Sample>& library, const std::vector<Sample>& states, double tail);

}  // namespace grainbank::surrogate

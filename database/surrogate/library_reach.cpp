#include "database/surrogate/library_reach.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace grainbank::surrogate {

LibraryReach library_reach(const std::vector<Sample>& library, const std::vector<Sample>& states, double tail) {
  if (!(tail >= 0 && tail < 0.5))
    throw std::invalid_argument("library reach: tail " + std::to_string(tail) + ", expected a share in [0, 0.5)");
  LibraryReach reach;
  reach.states = states.size();
  reach.tail = tail;
  if (library.empty() || states.empty()) return reach;
  const std::size_t n = library.size();
  const std::size_t k = static_cast<std::size_t>(tail * static_cast<double>(n));
  std::array<double, kFeatureCount> lower{}, upper{};
  std::vector<double> values(n);
  for (std::size_t j = 0; j < kFeatureCount; ++j) {
    for (std::size_t i = 0; i < n; ++i) values[i] = library[i].features[j];
    std::sort(values.begin(), values.end());
    lower[j] = values[k];
    upper[j] = values[n - 1 - k];
  }
  std::array<std::size_t, kFeatureCount> below{}, above{};
  std::size_t beyond = 0;
  for (const Sample& state : states) {
    bool outside = false;
    for (std::size_t j = 0; j < kFeatureCount; ++j) {
      const double f = state.features[j];
      if (f < lower[j]) ++below[j], outside = true;
      if (f > upper[j]) ++above[j], outside = true;
    }
    if (outside) ++beyond;
  }
  const double count = static_cast<double>(states.size());
  for (std::size_t j = 0; j < kFeatureCount; ++j)
    reach.features[j] = {static_cast<double>(below[j]) / count, static_cast<double>(above[j]) / count};
  reach.beyond_any = static_cast<double>(beyond) / count;
  return reach;
}

}  // namespace grainbank::surrogate

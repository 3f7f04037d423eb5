#include "mpm_solver/core/ranks.hpp"

#include <stdexcept>

namespace grainbank::mpm {

void share_failure(const Ranks& ranks, const std::string& failure) {
  if (!ranks.any(!failure.empty())) return;
  const std::vector<std::vector<char>> all = ranks.all_gather(std::vector<char>(failure.begin(), failure.end()));
  for (int r = 0; r < ranks.size(); ++r)
    if (!all[r].empty()) {
      const std::string message(all[r].begin(), all[r].end());
      throw std::runtime_error(ranks.size() > 1 ? message + " (on MPI rank " + std::to_string(r) + ")" : message);
    }
}

}  // namespace grainbank::mpm

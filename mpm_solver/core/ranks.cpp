#include "mpm_solver/core/ranks.hpp"

#include <cstring>
#include <stdexcept>

namespace grainbank::mpm {

std::vector<double> sum_over_ranks(const Ranks& ranks, const std::vector<double>& mine) {
  const std::vector<char> bytes(reinterpret_cast<const char*>(mine.data()),
                                reinterpret_cast<const char*>(mine.data() + mine.size()));
  std::vector<double> total(mine.size(), 0.0), values(mine.size());
  for (const std::vector<char>& other : ranks.all_gather(bytes)) {
    if (other.size() != bytes.size()) throw std::runtime_error("sum_over_ranks: the ranks' vectors differ in length");
    std::memcpy(values.data(), other.data(), other.size());
    for (std::size_t k = 0; k < total.size(); ++k) total[k] += values[k];
  }
  return total;
}

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

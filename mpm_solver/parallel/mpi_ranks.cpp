#include "mpm_solver/parallel/mpi_ranks.hpp"

#include <mpi.h>

#include <climits>
#include <stdexcept>
#include <string>

namespace grainbank::mpm::parallel {

MpiRanks::MpiRanks() {
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
}

std::vector<std::vector<char>> MpiRanks::all_gather(const std::vector<char>& mine) const { return gather(mine, true); }

std::vector<std::vector<char>> MpiRanks::gather_to_root(const std::vector<char>& mine) const {
  return gather(mine, false);
}

std::vector<std::vector<char>> MpiRanks::gather(const std::vector<char>& mine, bool to_all) const {
  if (mine.size() > static_cast<std::size_t>(INT_MAX))
    throw std::runtime_error("MPI: a rank's message of " + std::to_string(mine.size()) + " bytes exceeds 2 GiB");
  const int count = static_cast<int>(mine.size());
  std::vector<int> counts(size_), offsets(size_);
  if (to_all) MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, MPI_COMM_WORLD);
  else MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
  const bool receives = to_all || rank_ == 0;
  long total = 0;
  for (int r = 0; r < size_ && receives; ++r) {
    offsets[r] = static_cast<int>(total);
    total += counts[r];
  }
  // Every rank learns of an oversized gather, so none is left waiting in it.
  int oversized = total > INT_MAX ? 1 : 0;
  if (!to_all) MPI_Bcast(&oversized, 1, MPI_INT, 0, MPI_COMM_WORLD);
  if (oversized) throw std::runtime_error("MPI: the ranks' messages add up to more than 2 GiB");
  std::vector<char> all(static_cast<std::size_t>(total));
  if (to_all)
    MPI_Allgatherv(mine.data(), count, MPI_BYTE, all.data(), counts.data(), offsets.data(), MPI_BYTE, MPI_COMM_WORLD);
  else
    MPI_Gatherv(mine.data(), count, MPI_BYTE, all.data(), counts.data(), offsets.data(), MPI_BYTE, 0, MPI_COMM_WORLD);
  if (!receives) return {};
  std::vector<std::vector<char>> by_rank(size_);
  for (int r = 0; r < size_; ++r) by_rank[r].assign(all.begin() + offsets[r], all.begin() + offsets[r] + counts[r]);
  return by_rank;
}

double MpiRanks::min(double value) const {
  double result = 0;
  MPI_Allreduce(&value, &result, 1, MPI_DOUBLE, MPI_MIN, MPI_COMM_WORLD);
  return result;
}

bool MpiRanks::any(bool value) const {
  int local = value ? 1 : 0, result = 0;
  MPI_Allreduce(&local, &result, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  return result != 0;
}

}  // namespace grainbank::mpm::parallel

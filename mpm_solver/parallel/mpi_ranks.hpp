// The ranks of an MPI job as the solver sees them (core/ranks.hpp), over MPI_COMM_WORLD. Built only
// when MPI is found; the session (common/mpi_session.hpp) must outlive it.
#pragma once
#include "mpm_solver/core/ranks.hpp"

namespace grainbank::mpm::parallel {

class MpiRanks final : public Ranks {
 public:
  MpiRanks();
  int rank() const override { return rank_; }
  int size() const override { return size_; }
  std::vector<std::vector<char>> all_gather(const std::vector<char>& mine) const override;
  std::vector<std::vector<char>> gather_to_root(const std::vector<char>& mine) const override;
  double min(double value) const override;
  bool any(bool value) const override;

 private:
  std::vector<std::vector<char>> gather(const std::vector<char>& mine, bool to_all) const;
  int rank_ = 0, size_ = 1;
};

}  // namespace grainbank::mpm::parallel

// The processes one run is spread over (MPI ranks), as the solver sees them; mpm_solver/parallel/
// supplies MPI's, and a run of one process has OneRank. Every rank holds the same MPM and steps it
// alike; only the updates of points whose law spreads them (PointSharing) are split, each point on
// one rank, after which the ranks exchange the results. Every call is collective: all ranks make the
// same calls in the same order, or the run hangs.
#pragma once
#include <string>
#include <vector>

namespace grainbank::mpm {

class Ranks {
 public:
  virtual ~Ranks() = default;
  virtual int rank() const = 0;
  virtual int size() const = 0;
  // Every rank passes its own bytes and receives those of all ranks, in rank order.
  virtual std::vector<std::vector<char>> all_gather(const std::vector<char>& mine) const = 0;
  // The same, received by rank 0 only (the others get nothing).
  virtual std::vector<std::vector<char>> gather_to_root(const std::vector<char>& mine) const = 0;
  // The smallest of the ranks' values, and whether any rank passed true, on every rank.
  virtual double min(double value) const = 0;
  virtual bool any(bool value) const = 0;
};

class OneRank final : public Ranks {
 public:
  int rank() const override { return 0; }
  int size() const override { return 1; }
  std::vector<std::vector<char>> all_gather(const std::vector<char>& mine) const override { return {mine}; }
  std::vector<std::vector<char>> gather_to_root(const std::vector<char>& mine) const override { return {mine}; }
  double min(double value) const override { return value; }
  bool any(bool value) const override { return value; }
};

// Each rank's values summed element by element, on every rank (vectors of one length on all ranks).
std::vector<double> sum_over_ranks(const Ranks& ranks, const std::vector<double>& mine);

// Every rank passes the failure it met ("" for none); if any rank failed, every rank throws
// std::runtime_error with the message of the lowest such rank (naming the rank when there are
// several), so that all ranks stop at the same point with one message.
void share_failure(const Ranks& ranks, const std::string& failure);

}  // namespace grainbank::mpm

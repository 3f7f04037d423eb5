// Sharing a library's pending paths among the ranks of an MPI job (built only when MPI is found).
// Rank 0 is the master: a dispatcher thread answers "next path?" requests from the other ranks out of
// the same list its own workers draw from, so work is balanced dynamically, one path at a time. Each
// rank writes its own shard and commits its own catalogue rows (SQLite WAL + busy timeout serialise
// the commits); rank 0 alone registers paths and resets stale ones, before any rank starts.
// MPI calls are made by one thread at a time per rank (MPI_THREAD_SERIALIZED).
#pragma once
#include <mutex>
#include <thread>

#include "common/mpi_session.hpp"
#include "dem_sampler/sampler/sampler.hpp"

namespace grainbank::sampler {

// Sums the ranks' counts and takes the longest wall time, on every rank.
SampleSummary combine_over_ranks(const SampleSummary& local);

// Rank 0: its own workers call next(); a thread serves the other ranks until each has been told
// that no work is left.
class MpiDispatcher : public WorkSource {
 public:
  MpiDispatcher(std::vector<std::int64_t> ids, int ranks, const std::atomic<bool>* stop);
  ~MpiDispatcher() override;  // closes and waits until every other rank has left
  std::optional<std::int64_t> next() override;
  // Hands out nothing from now on (an interrupt or a fatal error on rank 0).
  void close() { closed_ = true; }

 private:
  void serve(int ranks);
  std::mutex mutex_;
  std::vector<std::int64_t> ids_;
  std::size_t next_ = 0;
  const std::atomic<bool>* stop_;
  std::atomic<bool> closed_{false};
  std::thread server_;
};

// Ranks > 0: asks rank 0.
class MpiClient : public WorkSource {
 public:
  MpiClient() = default;
  ~MpiClient() override;  // tells rank 0 this rank is leaving, if it has not been told "no work" yet
  std::optional<std::int64_t> next() override;

 private:
  std::mutex mutex_;
  bool exhausted_ = false;
};

}  // namespace grainbank::sampler

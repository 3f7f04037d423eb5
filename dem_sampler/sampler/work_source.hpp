// Where a sampler's worker threads get their next path from: a local list here, rank 0 of an MPI job
// in mpi_work_source.hpp. next() is called concurrently by the workers of one process.
#pragma once
#include <atomic>
#include <cstdint>
#include <optional>
#include <vector>

namespace grainbank::sampler {

class WorkSource {
 public:
  virtual ~WorkSource() = default;
  // The next path id to run, or nothing when every path has been handed out.
  virtual std::optional<std::int64_t> next() = 0;
};

// Hands out a fixed list in order, each id once.
class ListWorkSource : public WorkSource {
 public:
  explicit ListWorkSource(std::vector<std::int64_t> ids) : ids_(std::move(ids)) {}
  std::optional<std::int64_t> next() override {
    const std::size_t k = next_.fetch_add(1);
    if (k >= ids_.size()) return std::nullopt;
    return ids_[k];
  }

 private:
  std::vector<std::int64_t> ids_;
  std::atomic<std::size_t> next_{0};
};

}  // namespace grainbank::sampler

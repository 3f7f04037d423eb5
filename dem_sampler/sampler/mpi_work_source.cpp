#include "dem_sampler/sampler/mpi_work_source.hpp"

#include <mpi.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <stdexcept>

namespace grainbank::sampler {
namespace {

constexpr int kRequestTag = 41, kReplyTag = 42;
constexpr std::int64_t kNoWork = -1;

}  // namespace

SampleSummary combine_over_ranks(const SampleSummary& local) {
  long counts[5] = {local.done, local.failed, local.abandoned, local.records, local.dem_steps};
  long total[5] = {};
  MPI_Allreduce(counts, total, 5, MPI_LONG, MPI_SUM, MPI_COMM_WORLD);
  double reals[1] = {local.particle_steps}, real_total[1] = {};
  MPI_Allreduce(reals, real_total, 1, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
  double seconds = 0;
  MPI_Allreduce(&local.seconds, &seconds, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
  return SampleSummary{total[0], total[1], total[2], total[3], total[4], real_total[0], seconds};
}

MpiDispatcher::MpiDispatcher(std::vector<std::int64_t> ids, int ranks, const std::atomic<bool>* stop)
    : ids_(std::move(ids)), stop_(stop), server_([this, ranks] { serve(ranks); }) {}

MpiDispatcher::~MpiDispatcher() {
  close();
  server_.join();
}

std::optional<std::int64_t> MpiDispatcher::next() {
  std::lock_guard lock(mutex_);
  if (closed_ || (stop_ && stop_->load()) || next_ >= ids_.size()) return std::nullopt;
  return ids_[next_++];
}

void MpiDispatcher::serve(int ranks) {
  // Polls with a short sleep: a blocking MPI_Recv spins a core that the DEM needs.
  for (int left = 0; left < ranks - 1;) {
    int pending = 0;
    MPI_Status status;
    MPI_Iprobe(MPI_ANY_SOURCE, kRequestTag, MPI_COMM_WORLD, &pending, &status);
    if (!pending) {
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
      continue;
    }
    int leaving = 0;
    MPI_Recv(&leaving, 1, MPI_INT, status.MPI_SOURCE, kRequestTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    const std::optional<std::int64_t> id = leaving ? std::nullopt : next();
    const std::int64_t reply = id.value_or(kNoWork);
    MPI_Send(&reply, 1, MPI_INT64_T, status.MPI_SOURCE, kReplyTag, MPI_COMM_WORLD);
    if (!id) ++left;
  }
}

std::optional<std::int64_t> MpiClient::next() {
  std::lock_guard lock(mutex_);
  if (exhausted_) return std::nullopt;
  int leaving = 0;
  std::int64_t reply = kNoWork;
  MPI_Send(&leaving, 1, MPI_INT, 0, kRequestTag, MPI_COMM_WORLD);
  MPI_Recv(&reply, 1, MPI_INT64_T, 0, kReplyTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  if (reply == kNoWork) {
    exhausted_ = true;
    return std::nullopt;
  }
  return reply;
}

MpiClient::~MpiClient() {
  std::lock_guard lock(mutex_);
  if (exhausted_) return;
  int leaving = 1;
  std::int64_t reply = kNoWork;
  MPI_Send(&leaving, 1, MPI_INT, 0, kRequestTag, MPI_COMM_WORLD);
  MPI_Recv(&reply, 1, MPI_INT64_T, 0, kReplyTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
}

}  // namespace grainbank::sampler

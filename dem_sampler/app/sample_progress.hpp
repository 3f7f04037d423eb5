// Progress of `dem_sampler sample` on stderr. On a terminal: one status line redrawn in place (paths
// done/total, failed, records/s, ETA from the records still to compute), at most five times a second.
// Otherwise (a log file, a batch job, an MPI rank): one line per finished path.
#pragma once
#include <chrono>
#include <string>

#include "dem_sampler/sampler/path_runner.hpp"

namespace grainbank::app {

class SampleProgress {
 public:
  // `label` prefixes log lines (e.g. "rank 1: "); `total_records` is 0 when unknown.
  SampleProgress(long total_paths, long total_records, bool terminal, std::string label = {});
  void commit(long records);
  void path(const sampler::PathOutcome& outcome);
  // Ends the status line.
  void finish();

 private:
  void redraw(bool force);
  using Clock = std::chrono::steady_clock;
  long total_paths_, total_records_;
  bool terminal_;
  std::string label_;
  long paths_done_ = 0, paths_failed_ = 0, records_ = 0;
  Clock::time_point start_ = Clock::now(), last_draw_ = Clock::now() - std::chrono::hours(1);
};

}  // namespace grainbank::app

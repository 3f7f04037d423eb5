#include "dem_sampler/app/sample_progress.hpp"

#include <cstdio>
#include <iostream>
#include <sstream>

#include "common/duration_text.hpp"

namespace grainbank::app {
SampleProgress::SampleProgress(long total_paths, long total_records, bool terminal, std::string label)
    : total_paths_(total_paths), total_records_(total_records), terminal_(terminal), label_(std::move(label)) {}

void SampleProgress::commit(long records) {
  records_ += records;
  if (terminal_) redraw(false);
}

void SampleProgress::path(const sampler::PathOutcome& o) {
  if (o.result == sampler::PathResult::abandoned) return;
  ++paths_done_;
  if (o.result == sampler::PathResult::failed) ++paths_failed_;
  if (terminal_) {
    if (o.result == sampler::PathResult::failed)  // a failure deserves a line of its own
      std::cerr << "\r\033[K" << label_ << "path " << o.path_id << " failed: " << o.error << "\n";
    redraw(true);
    return;
  }
  std::cerr << label_ << "path " << o.path_id << ": " << (o.result == sampler::PathResult::done ? "done" : "failed")
            << ", " << o.records << " records in " << o.wall_time << " s";
  if (total_paths_ > 0) std::cerr << " (" << paths_done_ << "/" << total_paths_ << " paths)";
  if (!o.error.empty()) std::cerr << ": " << o.error;
  std::cerr << std::endl;
}

void SampleProgress::finish() {
  if (terminal_) {
    redraw(true);
    std::cerr << "\n";
  }
}

void SampleProgress::redraw(bool force) {
  const Clock::time_point now = Clock::now();
  if (!force && now - last_draw_ < std::chrono::milliseconds(200)) return;
  last_draw_ = now;
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const double rate = elapsed > 0 ? static_cast<double>(records_) / elapsed : 0;
  std::ostringstream line;
  line << label_ << "paths " << paths_done_ << "/" << total_paths_;
  if (paths_failed_) line << " (" << paths_failed_ << " failed)";
  line << ", " << records_ << " records, " << static_cast<long>(rate + 0.5) << " records/s";
  if (total_records_ > records_ && rate > 0)
    line << ", ETA " << common::duration_text(static_cast<double>(total_records_ - records_) / rate);
  std::cerr << "\r\033[K" << line.str() << std::flush;
}

}  // namespace grainbank::app

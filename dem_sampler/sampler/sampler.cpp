#include "dem_sampler/sampler/sampler.hpp"

#include <chrono>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace grainbank::sampler {

SampleSummary run_paths(LibraryWriter& writer, WorkSource& source, const SampleOptions& options,
                        const SampleObserver& observer) {
  const auto start = std::chrono::steady_clock::now();
  const db::KeyScales scales = writer.key_scales();
  // Raised by an external stop (copied in by the watcher below) or a fatal error in any thread; the
  // runners poll this one flag after every record.
  std::atomic<bool> halt{false};
  SampleSummary summary;
  std::exception_ptr fatal;
  std::mutex summary_mutex;

  const auto worker = [&] {
    RunnerOptions runner;
    runner.commit_batch = options.commit_batch;
    runner.stop = &halt;
    runner.on_commit = observer.on_commit;
    while (!halt) {
      const std::optional<std::int64_t> id = source.next();
      if (!id) break;
      try {
        const PathOutcome outcome = run_path(writer, *id, scales, runner);
        std::lock_guard lock(summary_mutex);
        summary.records += outcome.records;
        if (outcome.result == PathResult::done) {
          ++summary.done;
          summary.dem_steps += outcome.dem_steps;
          summary.particle_steps += static_cast<double>(outcome.dem_steps) * static_cast<double>(outcome.spheres);
        }
        if (outcome.result == PathResult::failed) ++summary.failed;
        if (outcome.result == PathResult::abandoned) ++summary.abandoned;
        if (observer.on_path) writer.locked([&] { observer.on_path(outcome); });
      } catch (...) {
        {
          std::lock_guard lock(summary_mutex);
          if (!fatal) fatal = std::current_exception();
        }
        halt = true;
        try {
          writer.abandon(*id);
        } catch (...) {
          // The store is failing already; the next run resets this path as stale.
        }
        break;
      }
    }
  };

  // The external flag is set by a signal handler; copying it in keeps the runners on one flag.
  std::jthread watcher([&](std::stop_token token) {
    while (!token.stop_requested()) {
      if (options.stop && options.stop->load()) halt = true;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  });
  if (options.stop && options.stop->load()) halt = true;
  std::vector<std::jthread> pool;
  for (int k = 0; k < std::max(1, options.threads); ++k) pool.emplace_back(worker);
  for (auto& t : pool) t.join();
  watcher.request_stop();
  watcher.join();
  summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (fatal) std::rethrow_exception(fatal);
  return summary;
}

}  // namespace grainbank::sampler

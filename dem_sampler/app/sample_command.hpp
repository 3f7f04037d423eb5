// `dem_sampler sample PATHS.json --library LIB`: registers the paths of PATHS.json on a template of
// LIB (each spec once) and runs every pending path of the library, on threads and, when started by
// mpirun, on every rank. Resumable: interrupted paths go back to pending, and a re-run (after a
// signal, or a SIGKILL that left `running` rows) picks them up.
#pragma once
#include <cstdint>
#include <filesystem>
#include <optional>

namespace grainbank::app {

struct SampleOptions {
  std::filesystem::path paths_file;
  std::filesystem::path library;
  std::optional<int> threads;              // per process; default: all cores (1 per rank under MPI)
  std::optional<std::int64_t> template_id;  // default: the library's only template
  bool retry_failed = false;               // failed paths back to pending first
  long commit_batch = 32;                  // records per commit between snapshots
};

// Returns the exit code: 0 when every path ran (some may have failed: they are reported), 1 when
// interrupted. Throws on input and store errors (under MPI, rank 0 reports setup errors).
int sample_command(const SampleOptions& options);

}  // namespace grainbank::app

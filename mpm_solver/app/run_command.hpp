// `mpm_solver SCENE.json`: runs a scene to its end time, writing VTU/PVD snapshots, the CSV series,
// tracked points and their DEM cells, a run summary JSON and a final restart file (restart.h5) into
// the output folder. A run asked to stop (SIGINT/SIGTERM/SIGHUP/SIGPIPE) stops after its current step and writes the
// same restart file and summary, so `--restart OUT/restart.h5` continues it exactly. A run that is
// killed outright (SIGKILL, a machine restart) has its last checkpoint: OUT/restart.h5 is also written,
// complete or not at all, at the first output snapshot after every `checkpoint_every` wall seconds.
#pragma once
#include <atomic>
#include <filesystem>
#include <memory>

#include <nlohmann/json.hpp>

#include "mpm_solver/app/scene_overrides.hpp"
#include "mpm_solver/core/ranks.hpp"

namespace grainbank::mpm::app {

struct RunOptions {
  std::filesystem::path scene;
  std::filesystem::path out = "mpm_out";
  std::filesystem::path restart;  // resume from this restart file (empty: start at t = 0)
  // --law, --library, --material, --set: the scene as rewritten is saved to OUT/scene/<scene file
  // name> and run.
  SceneOverrides overrides;
  bool progress = true;  // a progress line with ETA on stderr
  // Wall seconds between checkpoints, each written at an output snapshot (0: at every snapshot).
  double checkpoint_every = 600;
  // Polled after every step (the CLI wires SIGINT/SIGTERM/SIGHUP/SIGPIPE to it): once true, the run stops there,
  // writes OUT/restart.h5 and returns a summary with "interrupted": true.
  const std::atomic<bool>* stop = nullptr;
  // The MPI ranks the run is spread over (null: this process alone). Every rank calls run_scene with
  // the same options; rank 0 writes every output and reports progress, and a signal reaching any
  // rank stops them all after the same step.
  std::shared_ptr<const Ranks> ranks;
};

// Returns the run summary (also written to OUT/summary.json; "restart" names the restart file,
// "interrupted" tells whether the run stopped before its end time, "at_rest" whether the scene's
// time.stop_at_rest ended it, "front_reached" whether time.stop_at_front did, "process_cpu_time" the
// CPU seconds of all its threads that the process had used by then, "kinetic_energy_peak" the largest
// kinetic energy of a series row, this segment and those it was resumed from, counted from
// "kinetic_energy_peak_since": 0, or the time a run resumed from a restart file of an older build that
// kept no peak). Throws common::InputError for scene errors and std::runtime_error when the run fails.
nlohmann::json run_scene(const RunOptions& options);

}  // namespace grainbank::mpm::app

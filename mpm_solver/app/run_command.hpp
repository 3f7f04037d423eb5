// `mpm_solver SCENE.json`: runs a scene to its end time, writing VTU/PVD snapshots, the CSV series,
// tracked points and their DEM cells, a run summary JSON and a final restart file (restart.h5) into
// the output folder.
#pragma once
#include <filesystem>

#include <nlohmann/json.hpp>

#include "scene_overrides.hpp"

namespace grainbank::mpm::app {

struct RunOptions {
  std::filesystem::path scene;
  std::filesystem::path out = "mpm_out";
  std::filesystem::path restart;  // resume from this restart file (empty: start at t = 0)
  // --law / --library: the scene as rewritten is saved to OUT/scene/<scene file name> and run.
  SceneOverrides overrides;
  bool progress = true;  // a progress line with ETA on stderr
};

// Returns the run summary (also written to OUT/summary.json). Throws common::InputError for scene
// errors and std::runtime_error when the run fails.
nlohmann::json run_scene(const RunOptions& options);

}  // namespace grainbank::mpm::app

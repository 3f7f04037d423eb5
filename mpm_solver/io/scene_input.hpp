// SCENE.json → a ready-to-run solver plus what the run should write. The schema is documented in
// README.md ("Scene JSON"); every error is a common::InputError naming the file and the JSON path.
#pragma once
#include <cstdint>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "mpm_solver/core/solver.hpp"

namespace grainbank::mpm::io {

// "stop_at_rest": the run ends, as finished, at the first series row at or after `not_before` whose
// kinetic energy is below `kinetic_energy_fraction` of the largest of any row so far.
struct RestCriterion {
  double kinetic_energy_fraction = 0;  // in (0, 1)
  double not_before = 0;               // [s]: e.g. after a release, so that a settling phase does not count
};

// "stop_at_front": the run ends, as finished, at the first series row at or after `not_before` whose
// front (the largest x of a point) has reached `x`: once a collapse has run that far, its verdict is in
// and the rest of the watch would only cost.
struct FrontCriterion {
  double x = 0;           // [m]
  double not_before = 0;  // [s]: e.g. the gate's opening, so that a column held by it cannot end the run
};

struct Scene {
  std::unique_ptr<Solver> solver;
  double end_time = 0;
  std::optional<RestCriterion> stop_at_rest;
  std::optional<FrontCriterion> stop_at_front;
  // time.min_time_step [s]: a run whose stable step falls below it stops, naming the criterion and
  // the point that set it, with a restart written (0: off). A hundredfold fall is reported either way.
  double min_time_step = 0;
  double output_interval = 0;  // VTU snapshots
  double series_interval = 0;  // rows of the CSV time series and of the tracked points
  std::vector<std::string> material_names;  // by law index
  std::vector<std::uint32_t> tracked_points;  // point ids
  std::vector<std::uint32_t> audited_points;  // point ids whose history the run records (audit_trail.hpp)
};

// Reads and builds the scene (live cells are prepared or loaded here). Paths inside the scene are
// relative to its folder. A scene for rank `rank` of a run on `ranks` MPI ranks refuses laws that
// cannot run there.
Scene load_scene(const std::filesystem::path& file, int rank = 0, int ranks = 1);

}  // namespace grainbank::mpm::io

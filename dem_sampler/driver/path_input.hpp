// PATH.json: a strain-rate path for one cell, as a list of segments of constant in-plane velocity
// gradient, recorded every `record_interval` (the macroscopic, MPM-like increment). The schema is
// documented in README.md ("path.json").
#pragma once
#include <filesystem>
#include <vector>

#include "dem_sampler/cell/substepping.hpp"
#include "common/json_input.hpp"
#include "dem_sampler/cell/types.hpp"

namespace grainbank::app {

struct PathSegment {
  dem::Mat3 L = dem::Mat3::Zero();  // plane strain: the z row and column are zero [1/s]
  double duration = 0;              // [s], always > 0 (a strain target is converted on reading)
  // [Pa] > 0: mixed control. The in-plane isotropic part of each increment's gradient is servoed to
  // hold this mean pressure (path_driver.hpp), so a shear can flow at a chosen pressure, as a point
  // of a free-surface flow does; 0: L is imposed as it is.
  double pressure = 0;
};

struct PathSpec {
  std::vector<PathSegment> segments;  // at least one
  double record_interval = 0;         // Δt [s]
  dem::Substepping substepping;       // Q_t, Q_n, Q_σ
};

// Throws common::InputError naming the file and the JSON path of the first problem.
PathSpec load_path(const std::filesystem::path& file);

// The pieces of PATH.json, for other inputs that embed segments (PATHS.json of `sample`).
// read_in_plane_gradient: [[Lxx, Lxy], [Lyx, Lyy]] embedded in 3×3; read_segment: {L, duration | strain};
// read_substepping: the optional "substepping" of `root`.
dem::Mat3 read_in_plane_gradient(const common::JsonNode& node);
PathSegment read_segment(const common::JsonNode& node);
dem::Substepping read_substepping(const common::JsonNode& root);

// Refuses a Q_t the material's dashpots make unstable (dem::max_time_step_factor) with an InputError
// at `holder`'s "q_t" (at `holder` itself, naming the default, when it has none). `holder` is the
// object that holds q_t: a "substepping" or a "preparation".
void require_stable_q_t(const common::JsonNode& holder, double q_t, double restitution);

// ||sym(L)|| (Frobenius): the strain rate that turns a segment's "strain" into a duration.
double strain_rate_norm(const dem::Mat3& L);

}  // namespace grainbank::app

// The scene's stop criteria. The case: an elastic block launched at v0 along a horizontal line with
// Coulomb friction μ, decelerating at μ g until it rests at t_s = v0 / (μ g).
// - time.stop_at_rest: a run ends once its kinetic energy has fallen below a fraction of its peak. The
//   block's kinetic energy ½ M (v0 − μ g t)² falls below a fraction f of its initial value only after
//   t = (1 − √f) t_s; a resumed run keeps the peak of the run it resumes and stops where the
//   uninterrupted one does; one resumed from a restart file that kept no peak (an older build's) counts
//   its peak from the resumed time and says so in its summary.
// - time.stop_at_front: a run ends once its front has reached x, not before a time t0. The block's
//   front reaches x0 + s at t = (v0 − √(v0² − 2 μ g s)) / (μ g), and never if s exceeds its sliding
//   distance v0² / (2 μ g); with t0 after that time the run ends at the first row from t0.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <initializer_list>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "common/json_input.hpp"
#include "common/temporary_directory.hpp"
#include "database/store/hdf5_handle.hpp"
#include "mpm_solver/app/run_command.hpp"
#include "mpm_solver/io/scene_input.hpp"

namespace grainbank::mpm {
namespace {

constexpr double kSpeed = 1.0, kFriction = 0.3, kGravity = 9.81, kFraction = 1e-3, kEnd = 2.0;

std::string block_scene(double end, const std::string& rest) {
  return R"({"grid": {"origin": [0, 0], "cell_size": 0.025, "cells": [80, 24]},
  "time": {"end": )" + std::to_string(end) + R"(, "output_interval": 0.05, "series_interval": 0.005)" + rest + R"(},
  "effects": {"gravity": true, "boundary_friction": true}, "gravity": {"g": [0, -9.81]},
  "materials": [{"name": "block", "law": "elastic", "density": 1000, "young": 1e6, "poisson": 0.3}],
  "regions": [{"material": "block", "rectangle": {"min": [0.2, 0.2], "max": [0.5, 0.3]},
               "points_per_cell": 2, "velocity": [1, 0]}],
  "obstacles": [{"line": [[0, 0.1999], [2, 0.1999]], "k_n": 1e6, "k_t": 1e6, "friction": 0.3, "damping": 0.5}]})";
}

// One column of a CSV file with a header line.
std::vector<double> csv_column(const std::filesystem::path& file, const std::string& name) {
  std::ifstream in(file);
  std::string line, cell;
  std::getline(in, line);
  std::istringstream header(line);
  std::size_t column = 0;
  while (std::getline(header, cell, ',') && cell != name) ++column;
  std::vector<double> values;
  while (std::getline(in, line)) {
    std::istringstream row(line);
    for (std::size_t k = 0; k <= column; ++k) std::getline(row, cell, ',');
    values.push_back(std::stod(cell));
  }
  return values;
}

const std::string kRest = R"(, "stop_at_rest": {"kinetic_energy_fraction": 0.001})";

nlohmann::json run(const TemporaryDirectory& dir, const std::string& name, const std::string& scene,
                   const std::filesystem::path& restart = {}) {
  app::RunOptions o;
  o.scene = dir.write(name + ".json", scene);
  o.out = dir.path() / name;
  o.restart = restart;
  o.progress = false;
  return app::run_scene(o);
}

TEST(StopAtRest, ARunEndsAtTheFirstRowBelowTheFractionOfItsPeakAfterTheBlockHasStopped) {
  const TemporaryDirectory dir("gb_stop_at_rest");
  const nlohmann::json summary = run(dir, "block", block_scene(kEnd, kRest));
  const double slide_time = kSpeed / (kFriction * kGravity);
  EXPECT_TRUE(summary["at_rest"].get<bool>());
  EXPECT_FALSE(summary["interrupted"].get<bool>());
  const double stop = summary["final_time"];
  std::printf("stopped at rest at t = %.3f s; the block slides to rest at t_s = %.3f s\n", stop, slide_time);
  EXPECT_LT(stop, kEnd);
  EXPECT_GE(stop, (1 - std::sqrt(kFraction)) * slide_time * 0.95);
  EXPECT_LE(stop, 1.1 * slide_time);
  const std::vector<double> energy = csv_column(dir.path() / "block" / "series.csv", "kinetic_energy");
  double peak = 0;
  for (double e : energy) peak = std::max(peak, e);
  EXPECT_NEAR(summary["kinetic_energy_peak"].get<double>(), peak, 1e-12 * peak);
  // ½ M v0², M = ρ × area: the block is cell-aligned and rests on the line (0.1 mm below its points' disks).
  EXPECT_NEAR(peak, 0.5 * 1000 * 0.3 * 0.1 * kSpeed * kSpeed, 0.02 * peak);
  ASSERT_GE(energy.size(), 2u);
  EXPECT_LT(energy.back(), kFraction * peak);
  EXPECT_GE(energy[energy.size() - 2], kFraction * peak);  // the first such row, not a later one
}

TEST(StopAtRest, AResumedRunKeepsThePeakAndStopsWhereTheUninterruptedRunStops) {
  const TemporaryDirectory dir("gb_stop_at_rest_resumed");
  const nlohmann::json whole = run(dir, "whole", block_scene(kEnd, kRest));
  run(dir, "first", block_scene(0.1, kRest));  // still sliding at its end
  const nlohmann::json resumed = run(dir, "resumed", block_scene(kEnd, kRest), dir.path() / "first" / "restart.h5");
  EXPECT_TRUE(resumed["at_rest"].get<bool>());
  EXPECT_EQ(resumed["final_time"].get<double>(), whole["final_time"].get<double>());
  EXPECT_EQ(resumed["kinetic_energy_peak"].get<double>(), whole["kinetic_energy_peak"].get<double>());
}

TEST(StopAtRest, ARunResumedFromAFileWithoutAPeakCountsItsPeakFromTheResumedTime) {
  const TemporaryDirectory dir("gb_stop_at_rest_no_peak");
  const nlohmann::json whole = run(dir, "whole", block_scene(kEnd, kRest));
  const nlohmann::json first = run(dir, "first", block_scene(0.1, kRest));
  {  // as an older build wrote it
    const db::h5::Object root = db::h5::open_file(dir.path() / "first" / "restart.h5", true);
    for (const char* name : {"kinetic_energy_peak", "kinetic_energy_peak_since"}) ASSERT_GE(H5Adelete(root.id(), name), 0);
  }
  const nlohmann::json resumed = run(dir, "resumed", block_scene(kEnd, kRest), dir.path() / "first" / "restart.h5");
  EXPECT_EQ(whole["kinetic_energy_peak_since"].get<double>(), 0);
  EXPECT_EQ(resumed["kinetic_energy_peak_since"].get<double>(), first["final_time"].get<double>());
  // The block has slowed since launch, so the peak counted from t = 0.1 s is below the true one,
  // and the rest criterion is met later.
  EXPECT_LT(resumed["kinetic_energy_peak"].get<double>(), 0.9 * whole["kinetic_energy_peak"].get<double>());
  EXPECT_GT(resumed["final_time"].get<double>(), whole["final_time"].get<double>());
  // Resumed again from its own restart, the time the peak is counted from is kept.
  const nlohmann::json again = run(dir, "again", block_scene(kEnd, ""), dir.path() / "resumed" / "restart.h5");
  EXPECT_EQ(again["kinetic_energy_peak_since"].get<double>(), first["final_time"].get<double>());
}

// Each of `cases` (time keys, a part of the error expected) is refused with an error naming its key.
void expect_refused(const std::string& folder, std::initializer_list<std::pair<const char*, const char*>> cases) {
  const TemporaryDirectory dir(folder);
  for (const auto& [keys, expected] : cases) {
    try {
      io::load_scene(dir.write("bad.json", block_scene(kEnd, keys)));
      ADD_FAILURE() << "accepted " << keys;
    } catch (const common::InputError& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  }
}

TEST(StopAtRest, ItsKeysAreChecked) {
  expect_refused("gb_stop_at_rest_keys",
                 {{R"(, "stop_at_rest": {"kinetic_energy_fraction": 1.5})", "stop_at_rest/kinetic_energy_fraction"},
                  {R"(, "stop_at_rest": {"fraction": 0.001})", "stop_at_rest/fraction: unknown key"},
                  {R"(, "stop_at_rest": {"kinetic_energy_fraction": 0.001, "not_before": -1})", "not_before"}});
}

// The block's front point at t = 0: the region's last points sit a quarter cell inside its face
// (two points per cell of 0.025 m).
constexpr double kFrontAtStart = 0.5 - 0.025 / 4;

std::string front_stop(double x) { return R"(, "stop_at_front": {"x": )" + std::to_string(x) + "}"; }

TEST(StopAtFront, ARunEndsAtTheFirstRowWhoseFrontHasReachedX) {
  const TemporaryDirectory dir("gb_stop_at_front");
  constexpr double kDistance = 0.1;
  const nlohmann::json summary = run(dir, "block", block_scene(kEnd, front_stop(kFrontAtStart + kDistance)));
  EXPECT_TRUE(summary["front_reached"].get<bool>());
  EXPECT_FALSE(summary["at_rest"].get<bool>());
  EXPECT_FALSE(summary["interrupted"].get<bool>());
  const double deceleration = kFriction * kGravity;
  const double reach_time = (kSpeed - std::sqrt(kSpeed * kSpeed - 2 * deceleration * kDistance)) / deceleration;
  const double stop = summary["final_time"];
  std::printf("stopped at t = %.4f s; the front reaches x0 + %.2f m at t = %.4f s\n", stop, kDistance, reach_time);
  EXPECT_GE(stop, 0.95 * reach_time);
  EXPECT_LE(stop, 1.05 * reach_time + 0.005);  // within a series row of it
  const std::vector<double> front = csv_column(dir.path() / "block" / "series.csv", "front");
  ASSERT_GE(front.size(), 2u);
  EXPECT_GE(front.back(), kFrontAtStart + kDistance);
  EXPECT_LT(front[front.size() - 2], kFrontAtStart + kDistance);  // the first such row, not a later one
}

TEST(StopAtFront, NotBeforeItsTime) {
  const TemporaryDirectory dir("gb_stop_at_front_later");
  constexpr double kNotBefore = 0.25;  // the front passed x0 + 0.1 m at 0.132 s
  const nlohmann::json summary =
      run(dir, "block", block_scene(kEnd, R"(, "stop_at_front": {"x": )" + std::to_string(kFrontAtStart + 0.1) +
                                              R"(, "not_before": )" + std::to_string(kNotBefore) + "}"));
  EXPECT_TRUE(summary["front_reached"].get<bool>());
  EXPECT_NEAR(summary["final_time"].get<double>(), kNotBefore, 1e-9);
}

TEST(StopAtFront, AFrontThatNeverGetsThereRunsToTheEnd) {
  const TemporaryDirectory dir("gb_stop_at_front_short");
  const double sliding_distance = kSpeed * kSpeed / (2 * kFriction * kGravity);
  constexpr double kEndAfterRest = 0.5;  // the block rests at 0.34 s
  const nlohmann::json summary = run(dir, "block", block_scene(kEndAfterRest, front_stop(kFrontAtStart + 1.2 * sliding_distance)));
  EXPECT_FALSE(summary["front_reached"].get<bool>());
  EXPECT_FALSE(summary["interrupted"].get<bool>());
  EXPECT_NEAR(summary["final_time"].get<double>(), kEndAfterRest, 1e-9);
  const std::vector<double> front = csv_column(dir.path() / "block" / "series.csv", "front");
  EXPECT_NEAR(front.back() - kFrontAtStart, sliding_distance, 0.1 * sliding_distance);
}

TEST(StopAtFront, ItsKeysAreChecked) {
  expect_refused("gb_stop_at_front_keys",
                 {{R"(, "stop_at_front": {"front": 0.6})", "stop_at_front/front: unknown key"},
                  {R"(, "stop_at_front": {"x": "far"})", "stop_at_front/x"},
                  {R"(, "stop_at_front": {})", "stop_at_front/x"},
                  {R"(, "stop_at_front": {"x": 0.6, "not_before": -1})", "stop_at_front/not_before"}});
}

}  // namespace
}  // namespace grainbank::mpm

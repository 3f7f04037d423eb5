// Scene JSON: a valid scene builds the expected solver; errors name the file and JSON path; the
// mpm_solver binary runs a tiny scene end to end and writes its VTU/PVD, CSV and summary files.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "common/json_input.hpp"
#include "mpm_solver/io/scene_input.hpp"
#include "mpm_solver/laws/law_registry.hpp"

namespace grainbank::mpm {
namespace {

namespace fs = std::filesystem;

fs::path write_file(const std::string& name, const std::string& text) {
  const fs::path dir = fs::temp_directory_path() / "gb_mpm_scene_test";
  fs::create_directories(dir);
  std::ofstream(dir / name) << text;
  return dir / name;
}

const char* kScene = R"({
  "grid": {"origin": [0, 0], "cell_size": 0.1, "cells": [10, 10]},
  "time": {"end": 0.02, "output_interval": 0.01},
  "effects": {"gravity": true, "boundary_friction": true},
  "gravity": {"g": [0, -9.81], "ramp": {"from": [0, -1], "start": 0, "end": 0.1}},
  "materials": [
    {"name": "a", "law": "elastic", "density": 1000, "young": 1e6, "poisson": 0.3},
    {"name": "b", "law": "drucker_prager", "density": 2000, "young": 1e6, "poisson": 0.3, "friction_angle": 30,
     "cohesion": 100, "tensile_strength": 10}
  ],
  "regions": [
    {"material": "a", "rectangle": {"min": [0.2, 0.2], "max": [0.4, 0.4]}, "points_per_cell": 2},
    {"material": "b", "polygon": [[0.5, 0.2], [0.7, 0.2], [0.5, 0.4]], "points_per_cell": 2}
  ],
  "obstacles": [{"line": [[0, 0.2], [1, 0.2]], "k_n": 1e6, "k_t": 1e6, "friction": 0.3, "remove_at": 1}],
  "tracked_points": [[0.3, 0.3]]
})";

TEST(Scene, BuildsTheSolverItDescribes) {
  const io::Scene scene = io::load_scene(write_file("ok.json", kScene));
  const Solver& s = *scene.solver;
  EXPECT_EQ(s.law_count(), 2u);
  EXPECT_EQ(s.law(1).name(), "drucker_prager");
  std::size_t a = 0, b = 0;
  for (const MaterialPoint& mp : s.points()) (mp.law == 0 ? a : b)++;
  EXPECT_EQ(a, 16u);  // 2 × 2 cells, 4 points each
  EXPECT_GT(b, 0u);
  EXPECT_LT(b, 16u);  // the triangle holds about half of its bounding box
  EXPECT_EQ(s.obstacles().size(), 1u);
  EXPECT_EQ(s.gravity().at(0), Vec2(0, -1));
  ASSERT_EQ(scene.tracked_points.size(), 1u);
  EXPECT_DOUBLE_EQ(scene.series_interval, 0.01);
  EXPECT_EQ(s.settings().transfer.kind, VelocityTransfer::Kind::apic_flip);  // the default
  EXPECT_EQ(s.settings().transfer.pic_rate, 5);
}

TEST(Scene, TransferIsApicPicOrABlendWithOrWithoutAffineVelocities) {
  const std::string from = "\"time\": {\"end\": 0.02, \"output_interval\": 0.01},";
  const auto transfer_of = [&](const std::string& json) {
    std::string text = kScene;
    text.replace(text.find(from), from.size(), from + "\"integration\": {\"transfer\": " + json + "},");
    return io::load_scene(write_file("transfer.json", text)).solver->settings().transfer;
  };
  EXPECT_EQ(transfer_of("\"apic\"").kind, VelocityTransfer::Kind::apic);
  const VelocityTransfer pic = transfer_of("\"pic\""), blend = transfer_of("{\"flip_pic\": {\"pic_rate\": 5}}");
  EXPECT_EQ(pic.kind, VelocityTransfer::Kind::flip_pic);
  EXPECT_EQ(pic.pic_weight(1e-6), 1.0);
  EXPECT_EQ(blend.kind, VelocityTransfer::Kind::flip_pic);
  EXPECT_DOUBLE_EQ(blend.pic_rate, 5);
  EXPECT_NEAR(blend.pic_weight(0.01), 1 - std::exp(-0.05), 1e-15);
  EXPECT_FALSE(blend.affine());
  const VelocityTransfer affine_blend = transfer_of("{\"apic_flip\": {\"pic_rate\": 2}}");
  EXPECT_EQ(affine_blend.kind, VelocityTransfer::Kind::apic_flip);
  EXPECT_TRUE(affine_blend.affine());
  EXPECT_DOUBLE_EQ(affine_blend.pic_rate, 2);
  EXPECT_NEAR(affine_blend.pic_weight(0.01), 1 - std::exp(-0.02), 1e-15);
  ASSERT_TRUE(affine_blend.noise_rate) << "APIC-FLIP blends its fluctuations' rough part at its own rate";
  EXPECT_DOUBLE_EQ(*affine_blend.noise_rate, VelocityTransfer::kDefaultNoiseRate);
  EXPECT_TRUE(affine_blend.splits_fluctuations());
  EXPECT_FALSE(blend.noise_rate) << "the seed's FLIP/PIC blend keeps one rate";
  EXPECT_FALSE(blend.splits_fluctuations());
  EXPECT_FALSE(pic.splits_fluctuations());
  const VelocityTransfer one_rate = transfer_of("{\"apic_flip\": {\"pic_rate\": 5, \"noise_rate\": 5}}");
  EXPECT_FALSE(one_rate.splits_fluctuations()) << "stop 77's APIC-FLIP, asked for";
  const VelocityTransfer fast = transfer_of("{\"apic_flip\": {\"pic_rate\": 500}}");
  EXPECT_FALSE(fast.splits_fluctuations()) << "the rough part is never blended slower than the rest by default";
  EXPECT_NEAR(fast.kept_rough_share(0.01), fast.kept_share(0.01), 1e-15);
  const VelocityTransfer split = transfer_of("{\"apic_flip\": {\"pic_rate\": 2, \"noise_rate\": 50}}");
  ASSERT_TRUE(split.noise_rate);
  EXPECT_DOUBLE_EQ(*split.noise_rate, 50);
  EXPECT_TRUE(split.splits_fluctuations());
  EXPECT_NEAR(split.kept_rough_share(0.01), std::exp(-0.5), 1e-15);
  EXPECT_NEAR(split.kept_share(0.01), std::exp(-0.02), 1e-15);
}

TEST(Scene, RegularizationSetsTheNonlocalLength) {
  const std::string from = "\"time\": {\"end\": 0.02, \"output_interval\": 0.01},";
  std::string text = kScene;
  EXPECT_FALSE(io::load_scene(write_file("local.json", text)).solver->settings().regularization);
  text.replace(text.find(from), from.size(), from + "\"regularization\": {\"nonlocal_length\": 0.25},");
  const auto regularization = io::load_scene(write_file("nonlocal.json", text)).solver->settings().regularization;
  ASSERT_TRUE(regularization);
  EXPECT_DOUBLE_EQ(regularization->length(), 0.25);
}

TEST(Scene, ChannelWallsAreAnEffectWithTheirBlock) {
  const std::string from = "\"effects\": {\"gravity\": true, \"boundary_friction\": true},";
  std::string text = kScene;
  EXPECT_FALSE(io::load_scene(write_file("plane.json", text)).solver->settings().channel_walls);
  text.replace(text.find(from), from.size(),
               "\"effects\": {\"gravity\": true, \"boundary_friction\": true, \"channel_walls\": true}, "
               "\"channel_walls\": {\"width\": 0.2, \"friction\": 0.3},");
  const auto walls = io::load_scene(write_file("flume.json", text)).solver->settings().channel_walls;
  ASSERT_TRUE(walls);
  EXPECT_DOUBLE_EQ(walls->width, 0.2);
  EXPECT_DOUBLE_EQ(walls->friction, 0.3);
}

void expect_error(const std::string& from, const std::string& to, const std::string& message) {
  std::string text = kScene;
  const auto at = text.find(from);
  ASSERT_NE(at, std::string::npos) << from;
  text.replace(at, from.size(), to);
  try {
    io::load_scene(write_file("bad.json", text));
    FAIL() << "no error for " << to;
  } catch (const common::InputError& e) {
    EXPECT_EQ(std::string(e.what()), message);
  }
}

TEST(Scene, ErrorsNameTheFileAndThePath) {
  expect_error("\"young\": 1e6, \"poisson\": 0.3}", "\"young\": -5, \"poisson\": 0.3}",
               "bad.json: /materials/0/young: expected a positive number, got -5");
  expect_error("\"material\": \"a\"", "\"material\": \"c\"",
               "bad.json: /regions/0/material: expected the name of a material, got a string (\"c\")");
  expect_error("\"k_n\": 1e6,", "\"kn\": 1e6,",
               "bad.json: /obstacles/0/kn: unknown key; allowed keys here: line, polygon, k_n, k_t, friction, "
               "damping, velocity, remove_at, release");
  expect_error("\"remove_at\": 1", "\"remove_at\": 1, \"release\": {\"start\": 1, \"end\": 2}",
               "bad.json: /obstacles/0: give either \"remove_at\" (a sudden removal) or \"release\" (letting go over "
               "an interval), not both");
  expect_error("\"remove_at\": 1", "\"release\": {\"start\": 1, \"end\": 1}",
               "bad.json: /obstacles/0/release: expected end > start (a sudden removal is \"remove_at\")");
  expect_error("\"remove_at\": 1", "\"release\": {\"start\": 1}",
               "bad.json: /obstacles/0/release/end: required field missing; expected a number >= 0");
  const std::string dp = "\"tensile_strength\": 10";
  expect_error(dp, dp + ", \"inertial_rheology\": {\"mu_2\": 0.7, \"I_0\": 0.3}",
               "bad.json: /materials/1/inertial_rheology/I_0: unknown key; allowed keys here: mu_2, inertial_number_0, "
               "grain_diameter, grain_density");
  expect_error(dp, dp + ", \"inertial_rheology\": {\"mu_2\": 0.4, \"inertial_number_0\": 0.3, "
               "\"grain_diameter\": 1e-3, \"grain_density\": 2500}",
               "bad.json: /materials/1: mu_2: expected a number >= the static friction sin(friction_angle) = 0.500000, got 0.400000");
  expect_error("\"law\": \"elastic\"", "\"law\": \"plastic\"",
               "bad.json: /materials/0/law: expected " + law_names() + ", got a string (\"plastic\")");
  const std::string time = "\"time\": {\"end\": 0.02, \"output_interval\": 0.01},";
  const auto expect_transfer_error = [&](const std::string& transfer, const std::string& message) {
    expect_error(time, time + "\"integration\": {\"transfer\": " + transfer + "},", "bad.json: /integration/transfer" + message);
  };
  const std::string transfer_expected =
      ": expected \"apic\", \"pic\", {\"apic_flip\": {\"pic_rate\": r}} or {\"flip_pic\": {\"pic_rate\": r}} (r >= 0: "
      "the PIC fraction per second; optional \"noise_rate\" >= 0: that of the fluctuations' rough part), ";
  expect_transfer_error("\"flip\"", transfer_expected + "got a string (\"flip\")");
  expect_transfer_error("{\"flip_pic\": {\"pic_rate\": -1}}", "/flip_pic/pic_rate: expected a number >= 0, got -1");
  expect_transfer_error("{\"apic_flip\": {\"pic_rate\": 1}, \"flip_pic\": {\"pic_rate\": 1}}",
                        transfer_expected + "got an object");
  expect_transfer_error("{\"apic_flip\": {\"pic_rate\": 5, \"noise_rate\": -1}}",
                        "/apic_flip/noise_rate: expected a number >= 0, got -1");
  expect_transfer_error("{\"apic_flip\": {\"pic_rate\": 5, \"noise\": 50}}",
                        "/apic_flip/noise: unknown key; allowed keys here: pic_rate, noise_rate");
  // The former per-step blend is refused with its replacement, not as an unknown key.
  expect_error(time, time + "\"integration\": {\"flip\": 0.95},",
               "bad.json: /integration/flip: the per-step blend \"flip\" was replaced by \"transfer\": {\"apic_flip\": "
               "{\"pic_rate\": 5}} (the default) or {\"flip_pic\": {\"pic_rate\": r}}, r the PIC fraction per second (flip f at steps of dt: r = "
               "-ln(f) / dt)");
  expect_error(time, time + "\"regularization\": {\"nonlocal_length\": 0},",
               "bad.json: /regularization/nonlocal_length: expected a positive number, got 0");
  expect_error(time, time + "\"regularization\": {\"length\": 0.1},",
               "bad.json: /regularization/length: unknown key; allowed keys here: nonlocal_length");
  const std::string effects = "\"effects\": {\"gravity\": true, \"boundary_friction\": true},";
  const std::string walls_on = "\"effects\": {\"gravity\": true, \"boundary_friction\": true, \"channel_walls\": true},";
  expect_error(effects, walls_on, "bad.json: /: effects.channel_walls is on but there is no \"channel_walls\" block");
  expect_error(effects, effects + "\"channel_walls\": {\"width\": 0.2, \"friction\": 0.3},",
               "bad.json: /: a \"channel_walls\" block needs effects.channel_walls");
  expect_error(effects, walls_on + "\"channel_walls\": {\"width\": 0, \"friction\": 0.3},",
               "bad.json: /channel_walls/width: expected a positive number, got 0");
  expect_error(effects, walls_on + "\"channel_walls\": {\"width\": 0.2, \"friction\": -1},",
               "bad.json: /channel_walls/friction: expected a number >= 0, got -1");
  expect_error(effects, walls_on + "\"channel_walls\": {\"width\": 0.2, \"mu\": 0.3},",
               "bad.json: /channel_walls/mu: unknown key; allowed keys here: width, friction");
  expect_error("\"cells\": [10, 10]", "\"cells\": [100000, 100000]",
               "bad.json: /grid/cells: expected at most 20000000 cells in all (here n_x * n_y = 10000000000; use a "
               "coarser cell_size or a smaller domain), got an array of 2 entries");
}

TEST(Scene, CommandLineRunWritesAllOutputs) {
  const fs::path scene = write_file("run.json", kScene);
  const fs::path out = fs::temp_directory_path() / "gb_mpm_scene_test" / "out";
  fs::remove_all(out);
  const std::string cmd = std::string(MPM_SOLVER_BINARY) + " " + scene.string() + " --out " + out.string() +
                          " --json > " + (out.parent_path() / "stdout.json").string();
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  for (const char* f : {"points.pvd", "points_000000.vtu", "points_000002.vtu", "series.csv", "tracked_points.csv",
                        "summary.json"})
    EXPECT_TRUE(fs::exists(out / f)) << f;
  const nlohmann::json summary = nlohmann::json::parse(std::ifstream(out / "summary.json"));
  EXPECT_NEAR(summary["final_time"].get<double>(), 0.02, 1e-12);
  EXPECT_GT(summary["steps"].get<long>(), 0);
  // A bad scene: one line on stderr naming the file, exit code 1.
  const fs::path bad = write_file("missing.json", "{\"grid\": 1}");
  const std::string bad_cmd = std::string(MPM_SOLVER_BINARY) + " " + bad.string() + " --out " + out.string() + " 2> " +
                              (out.parent_path() / "stderr.txt").string();
  EXPECT_NE(std::system(bad_cmd.c_str()), 0);
  std::ifstream err(out.parent_path() / "stderr.txt");
  std::string line;
  std::getline(err, line);
  EXPECT_EQ(line.rfind("mpm_solver: missing.json: ", 0), 0u) << line;
}

}  // namespace
}  // namespace grainbank::mpm

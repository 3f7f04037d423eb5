// `mpirun -n 2 mpm_solver SCENE.json` (issue 14): the MPM replicated on both ranks, each live cell
// driven on one, and cells moved between the ranks as their costs are measured. Real MPI processes on a column of live cells whose gate opens: the two-rank run
// equals the one-rank run in every point field and every cell, bit for bit; a restart written on
// two ranks resumes on one and the reverse; a cell that fails on rank 1 stops both ranks with one
// message naming the point; SIGINT to one rank stops both after the same step with a restart that
// resumes bit for bit. Hybrid points spread the same way, each rank enriching its own shard.
#include <dirent.h>
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <csignal>
#include <cstdio>
#include <fstream>
#include <map>
#include <optional>

#include "database/store/library.hpp"
#include "dem_sampler/cell/cell_state_bytes.hpp"
#include "mpm_solver/core/dem_backed_law.hpp"
#include "mpm_solver/io/scene_input.hpp"
#include "tests/faults/mpm_run_util.hpp"
#include "tests/sampler/sampler_test_util.hpp"

#ifndef MPIEXEC_BINARY
#define MPIEXEC_BINARY "mpirun"  // built without MPI: every test here skips
#endif

namespace grainbank::faults {
namespace {

namespace fs = std::filesystem;
using sampler::test::Outcome;
using sampler::test::TempDir;

// A bonded snow cell of 27 spheres: small enough for a short test, a real cell nevertheless.
const char* const kCell = R"({
  "material": {"density": 920, "k_n": 2000, "k_t": 600, "restitution": 0.3, "friction": 0.2, "contact_weight": 0.5,
               "bond": {"tensile_strength": 8e-4, "shear_strength": 9.6e-4, "exponent": 2, "bonding_distance": 0.05}},
  "effects": {"cohesion": true, "kinetic_stress": false, "rolling_resistance": false},
  "preparation": {"spheres": 27, "diameter": {"min": 3.4e-4, "max": 4.0e-4}, "pressure": 1000, "seed": 1,
                  "inertial_number": 0.01}
})";

// 24 live points in a column on a frictional floor whose gate opens at 0.02 s; two tracked points.
const char* const kScene = R"({
  "grid": {"origin": [0, 0], "cell_size": 0.1, "cells": [16, 8]},
  "time": {"end": 0.06, "output_interval": 0.01, "series_interval": 0.002, "max_time_step": 1e-4},
  "integration": {"transfer": {"apic_flip": {"pic_rate": 5}}},
  "effects": {"gravity": true, "boundary_friction": true},
  "gravity": {"g": [0, -9.81]},
  "materials": [{"name": "snow", "law": "live", "cell": "cell.json",
                 "substepping": {"q_t": 0.1, "q_n": 1, "q_sigma": 0.2}, "q_h": 0.01}],
  "regions": [{"material": "snow", "rectangle": {"min": [0.2, 0.2], "max": [0.6, 0.8]}, "points_per_cell": 1}],
  "obstacles": [
    {"line": [[0, 0.2], [1.6, 0.2]], "k_n": 2e5, "k_t": 2e5, "friction": 0.5, "damping": 0.5},
    {"line": [[0.2, 0.2], [0.2, 0.8]], "k_n": 2e5, "k_t": 2e5, "friction": 0.3, "damping": 0.5},
    {"line": [[0.6, 0.2], [0.6, 0.8]], "k_n": 2e5, "k_t": 2e5, "friction": 0.3, "damping": 0.5, "remove_at": 0.02}],
  "tracked_points": [[0.45, 0.7], [0.35, 0.25]]
})";

std::vector<std::string> mpm_solver(int ranks, const fs::path& scene, const fs::path& out,
                                    std::vector<std::string> extra = {}, int threads = 1) {
  std::vector<std::string> args;
  if (ranks > 1)
    args = {MPIEXEC_BINARY, "--allow-run-as-root", "--oversubscribe", "-n", std::to_string(ranks)};
  args.insert(args.end(),
              {MPM_SOLVER_BINARY, scene.string(), "--out", out.string(), "--threads", std::to_string(threads)});
  args.insert(args.end(), extra.begin(), extra.end());
  return args;
}

// Every live cell of a restart file, by point id, as its complete state in bytes: the scene rebuilt
// and the restart read into it.
std::map<std::uint32_t, std::vector<char>> cells_of_restart(const fs::path& scene, const fs::path& restart) {
  mpm::io::Scene built = mpm::io::load_scene(scene);
  mpm::io::read_restart(restart, *built.solver);
  std::map<std::uint32_t, std::vector<char>> cells;
  for (const mpm::MaterialPoint& mp : built.solver->points()) {
    const mpm::DemBackedLaw* dem = built.solver->law(mp.law).dem_backed();
    if (!dem || !dem->live_cell(mp.slot)) continue;
    common::ByteWriter bytes;
    dem::write_cell_state(dem->live_cell(mp.slot)->state(), bytes);
    cells[mp.id] = bytes.bytes();
  }
  return cells;
}

// The run in `run` ended in exactly the state of the run in `reference`: time, step, every point
// field and every one of its `live_cells` cells.
void expect_same_end(const fs::path& scene, const fs::path& run, const fs::path& reference,
                     std::size_t live_cells = 24) {
  const RestartContents end = read_restart_file(run / "restart.h5");
  const RestartContents expected = read_restart_file(reference / "restart.h5");
  EXPECT_EQ(end.time, expected.time);
  EXPECT_EQ(end.steps, expected.steps);
  ASSERT_EQ(end.points.size(), expected.points.size());
  std::size_t differing = 0;
  for (std::size_t k = 0; k < end.points.size(); ++k) differing += end.points[k] != expected.points[k];
  EXPECT_EQ(differing, 0u) << "of " << end.points.size() << " point values differ";
  const auto cells = cells_of_restart(scene, run / "restart.h5");
  const auto expected_cells = cells_of_restart(scene, reference / "restart.h5");
  ASSERT_EQ(cells.size(), live_cells);
  ASSERT_EQ(expected_cells.size(), live_cells);
  for (const auto& [id, bytes] : expected_cells) EXPECT_TRUE(cells.at(id) == bytes) << "the cell of point " << id;
}

class MpmMpi : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir("gb-mpm-mpi");
    dir_->write("cell.json", kCell);
    scene_ = dir_->write("scene.json", kScene);
    const Outcome r = sampler::test::run(mpm_solver(1, scene_, dir_->path() / "reference"), dir_->path());
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  static void TearDownTestSuite() { delete dir_; }
  void SetUp() override {
#ifndef GRAINBANK_HAVE_MPI
    GTEST_SKIP() << "built without MPI";
#endif
  }
  static fs::path reference() { return dir_->path() / "reference"; }
  static TempDir* dir_;
  static fs::path scene_;
};
TempDir* MpmMpi::dir_ = nullptr;
fs::path MpmMpi::scene_;

TEST_F(MpmMpi, TwoRanksOfTwoThreadsEndInTheStateOfOneRankOfOneThreadBitForBit) {
  const TempDir here("gb-mpm-mpi-two");
  const Outcome r = sampler::test::run(mpm_solver(2, scene_, here.path() / "two", {}, 2), here.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json summary = nlohmann::json::parse(std::ifstream(here.path() / "two" / "summary.json"));
  EXPECT_EQ(summary["mpi_ranks"].get<int>(), 2);
  expect_same_end(scene_, here.path() / "two", reference());
  // Rank 0 wrote the outputs, the cells of tracked points owned by rank 1 among them.
  EXPECT_EQ(sampler::test::slurp(here.path() / "two" / "series.csv"),
            sampler::test::slurp(reference() / "series.csv"));
  EXPECT_EQ(sampler::test::slurp(here.path() / "two" / "tracked_points.csv"),
            sampler::test::slurp(reference() / "tracked_points.csv"));
  std::size_t cell_files = 0;
  for (const fs::directory_entry& f : fs::directory_iterator(reference() / "cells")) {
    ++cell_files;
    EXPECT_EQ(sampler::test::slurp(here.path() / "two" / "cells" / f.path().filename()), sampler::test::slurp(f.path()))
        << f.path().filename();
  }
  EXPECT_GT(cell_files, 0u);
}

// Three live points sheared alike, the first and the last with cells of 125 spheres, the middle one
// with 27: dealt by id, rank 0 drives both costly cells and rank 1 the cheap one, some eight times as
// much work on rank 0. The first re-deal by measured cost moves a costly cell to rank 1, and the run
// still ends where one rank's does.
TEST_F(MpmMpi, ACostlyCellMovesToTheIdleRankAndTheRunEndsAsOnOneRank) {
  const TempDir here("gb-mpm-mpi-rebalance");
  std::string big = kCell;
  const std::string spheres = "\"spheres\": 27";
  big.replace(big.find(spheres), spheres.size(), "\"spheres\": 125");
  here.write("small.json", kCell);
  here.write("big.json", big);
  const fs::path scene = here.write("three.json", R"({
    "grid": {"origin": [0, 0], "cell_size": 0.1, "cells": [8, 4]},
    "time": {"end": 0.012, "output_interval": 0.012, "series_interval": 0.004, "max_time_step": 1e-4},
    "integration": {"homogeneous_drive": {"L": [[0, 2], [0, 0]], "origin": [0.4, 0.2]}, "rebalance_interval": 20},
    "materials": [{"name": "big", "law": "live", "cell": "big.json"}, {"name": "small", "law": "live", "cell": "small.json"}],
    "regions": [{"material": "big", "rectangle": {"min": [0.2, 0.1], "max": [0.3, 0.2]}, "points_per_cell": 1},
                {"material": "small", "rectangle": {"min": [0.3, 0.1], "max": [0.4, 0.2]}, "points_per_cell": 1},
                {"material": "big", "rectangle": {"min": [0.4, 0.1], "max": [0.5, 0.2]}, "points_per_cell": 1}]
  })");
  const Outcome one = sampler::test::run(mpm_solver(1, scene, here.path() / "one"), here.path());
  ASSERT_EQ(one.exit_code, 0) << one.err;
  const Outcome two = sampler::test::run(mpm_solver(2, scene, here.path() / "two"), here.path());
  ASSERT_EQ(two.exit_code, 0) << two.err;
  const nlohmann::json load = nlohmann::json::parse(std::ifstream(here.path() / "two" / "summary.json"))["load"];
  const auto cost = load["point_update_seconds_per_step"].get<std::vector<double>>();
  ASSERT_EQ(cost.size(), 3u);
  std::printf("cell costs per step: %.3g, %.3g, %.3g ms; %d point(s) moved\n", cost[0] * 1e3, cost[1] * 1e3,
              cost[2] * 1e3, load["rebalanced_points"].get<int>());
  EXPECT_GT(std::min(cost[0], cost[2]), cost[1]) << "the 125-sphere cells are not the costly ones";
  EXPECT_GE(load["rebalanced_points"].get<int>(), 1);
  expect_same_end(scene, here.path() / "two", here.path() / "one", 3);
}

// Written on `first` ranks at t = 0.03 s, resumed on `second` to the end.
void expect_resumes_across_rank_counts(const fs::path& scene, const fs::path& reference, int first, int second) {
  const TempDir here("gb-mpm-mpi-resume");
  const Outcome half =
      sampler::test::run(mpm_solver(first, scene, here.path() / "first", {"--set", "/time/end=0.03"}), here.path());
  ASSERT_EQ(half.exit_code, 0) << half.err;
  ASSERT_NEAR(read_restart_file(here.path() / "first" / "restart.h5").time, 0.03, 1e-12);
  const Outcome rest = sampler::test::run(
      mpm_solver(second, scene, here.path() / "second", {"--restart", (here.path() / "first" / "restart.h5").string()}),
      here.path());
  ASSERT_EQ(rest.exit_code, 0) << rest.err;
  expect_same_end(scene, here.path() / "second", reference);
}

TEST_F(MpmMpi, ARestartWrittenOnTwoRanksResumesOnOne) { expect_resumes_across_rank_counts(scene_, reference(), 2, 1); }
TEST_F(MpmMpi, ARestartWrittenOnOneRankResumesOnTwo) { expect_resumes_across_rank_counts(scene_, reference(), 1, 2); }

// A cell flattened until it is too thin (tests/mpm/hard_cases_live_test.cpp) at point 1, which rank 1
// drives (dealt by id, never re-dealt); point 0, elastic, is updated on both ranks and never fails.
TEST_F(MpmMpi, ACellFailingOnRankOneStopsBothRanksWithOneMessageNamingThePoint) {
  const TempDir here("gb-mpm-mpi-fail");
  here.write("cell.json", kCell);
  const fs::path scene = here.write("flatten.json", R"({
    "grid": {"origin": [0, 0], "cell_size": 0.1, "cells": [8, 8]},
    "time": {"end": 0.2, "output_interval": 0.1, "series_interval": 0.01},
    "integration": {"homogeneous_drive": {"L": [[10, 0], [0, -10]], "origin": [0.4, 0.4]},
                    "rebalance_interval": 1000000},
    "materials": [{"name": "rock", "law": "elastic", "density": 2000, "young": 1e6, "poisson": 0.3},
                  {"name": "snow", "law": "live", "cell": "cell.json"}],
    "regions": [{"material": "rock", "rectangle": {"min": [0.3, 0.3], "max": [0.4, 0.4]}, "points_per_cell": 1},
                {"material": "snow", "rectangle": {"min": [0.4, 0.3], "max": [0.5, 0.4]}, "points_per_cell": 1}]
  })");
  const Outcome r = sampler::test::run(mpm_solver(2, scene, here.path() / "out"), here.path());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("material point 1 (law live)"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("periodic cell too thin"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("(on MPI rank 1)"), std::string::npos) << r.err;
  std::size_t messages = 0;
  for (std::size_t at = r.err.find("mpm_solver: "); at != std::string::npos; at = r.err.find("mpm_solver: ", at + 1))
    ++messages;
  EXPECT_EQ(messages, 1u) << r.err;
}

// A library of two short paths of the test cell (a slow squeeze and a shear): the column's points hit
// it while they settle and miss, turning live, once the gate opens.
fs::path hybrid_library(const TempDir& here, const std::string& name) {
  const fs::path cell = here.write("cell.json", kCell), library = here.path() / name;
  const fs::path paths = here.write("paths.json", R"({"record_interval": 2e-3, "snapshot_interval": 5,
    "paths": [{"segments": [{"L": [[0, 0], [0, -0.5]], "duration": 0.04}]},
              {"segments": [{"L": [[0, 2], [0, 0]], "duration": 0.04}]}]})");
  for (const std::vector<std::string>& command :
       {std::vector<std::string>{DEM_SAMPLER_BINARY, "prepare", cell.string(), "--library", library.string()},
        std::vector<std::string>{DEM_SAMPLER_BINARY, "sample", paths.string(), "--library", library.string(),
                                 "--threads", "1"}}) {
    const Outcome r = sampler::test::run(command, here.path());
    EXPECT_EQ(r.exit_code, 0) << r.err;
  }
  return library;
}

std::size_t run_shards(const fs::path& library) {
  std::size_t shards = 0;
  for (const db::ShardRow& s : db::Library::open(library).catalogue().shards()) shards += s.name.starts_with("run-");
  return shards;
}

// Hybrid points are spread like live ones: each rank looks up, turns live and enriches the library
// in its own shard, and the run ends where one rank's does (each run on its own copy of the library,
// since enrichment changes what a later run finds).
TEST_F(MpmMpi, AHybridRunOnTwoRanksEndsInTheOneRankStateWithAShardPerRank) {
  const TempDir here("gb-mpm-mpi-hybrid");
  const fs::path one_library = hybrid_library(here, "one_lib"), two_library = here.path() / "two_lib";
  fs::copy(one_library, two_library, fs::copy_options::recursive);
  const auto hybrid = [&](const fs::path& library) {
    return std::vector<std::string>{"--law", "hybrid", "--library", library.string()};
  };
  const Outcome one = sampler::test::run(mpm_solver(1, scene_, here.path() / "one", hybrid(one_library)), here.path());
  ASSERT_EQ(one.exit_code, 0) << one.err;
  const Outcome two = sampler::test::run(mpm_solver(2, scene_, here.path() / "two", hybrid(two_library)), here.path());
  ASSERT_EQ(two.exit_code, 0) << two.err;

  const nlohmann::json summary = nlohmann::json::parse(std::ifstream(here.path() / "two" / "summary.json"));
  const nlohmann::json& coupling = summary["coupling"]["laws"][0];
  EXPECT_GT(coupling["hits"].get<long>(), 0) << "the library answered nothing: a live run in disguise";
  EXPECT_GT(coupling["went_live"].get<long>(), 0) << "no point turned live: nothing was spread";
  EXPECT_EQ(run_shards(one_library), 1u);
  EXPECT_EQ(run_shards(two_library), 2u);
  // Both restarts read into the one-rank run's scene (which opens a library: counted above).
  expect_same_end(here.path() / "one" / "scene" / "scene.json", here.path() / "two", here.path() / "one",
                  coupling["went_live"].get<std::size_t>() - coupling["returned_to_cache"].get<std::size_t>());
}

// The surrogate's running index learns from its live cells as the run goes: it is not spread yet,
// and says so before anything runs.
TEST_F(MpmMpi, ASurrogateSceneOnTwoRanksStopsBeforeItStartsNamingTheLaw) {
  const TempDir here("gb-mpm-mpi-surrogate");
  const fs::path library = hybrid_library(here, "lib"), out = here.path() / "out";
  const Outcome r = sampler::test::run(
      mpm_solver(2, scene_, out, {"--law", "surrogate", "--library", library.string()}), here.path());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("/materials/0/law: law \"surrogate\" cannot run on 2 MPI ranks"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("without mpirun"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out / "points_000000.vtu")) << "the run started";
}

// The pid of the process of rank `rank` of the mpirun job whose command line names `out`.
std::optional<pid_t> pid_of_rank(const fs::path& out, int rank) {
  for (const fs::directory_entry& entry : fs::directory_iterator("/proc")) {
    const std::string name = entry.path().filename();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    const std::string command = sampler::test::slurp(entry.path() / "cmdline");
    if (command.find(MPM_SOLVER_BINARY) == std::string::npos || command.find(out.string()) == std::string::npos)
      continue;
    const std::string environment = sampler::test::slurp(entry.path() / "environ");
    if (environment.find("OMPI_COMM_WORLD_RANK=" + std::to_string(rank) + '\0') != std::string::npos)
      return std::stoi(name);
  }
  return std::nullopt;
}

TEST_F(MpmMpi, SigintToOneRankStopsBothAfterTheSameStepAndTheRestartResumesBitForBit) {
  const TempDir here("gb-mpm-mpi-sigint");
  const fs::path first = here.path() / "first";
  // Rank 0 waits inside its third snapshot (t = 0.02 s) and rank 1 for rank 0, while rank 1 gets the
  // signal; both stop at the next check, after the snapshot's step.
  const BlockingSnapshot snapshot(first / "points_000002.vtu");
  const pid_t job = sampler::test::spawn(mpm_solver(2, scene_, first), here.path());
  const bool writing = snapshot.wait_until_written(job);
  const std::optional<pid_t> rank1 = pid_of_rank(first, 1);
  if (rank1) kill(*rank1, SIGINT);
  const std::size_t drained = writing ? snapshot.drain() : 0;
  const Outcome stopped = sampler::test::wait_for(job, here.path());
  ASSERT_TRUE(writing) << "the run ended before its third snapshot: " << stopped.err;
  ASSERT_TRUE(rank1.has_value()) << "no process of rank 1";
  ASSERT_GT(drained, snapshot.capacity()) << "the snapshot fits in the pipe: the run did not wait";

  EXPECT_EQ(stopped.exit_code, 1) << stopped.err;
  EXPECT_NE(stopped.err.find("interrupted by a signal to another MPI rank"), std::string::npos) << stopped.err;
  const RestartContents at_stop = read_restart_file(first / "restart.h5");
  EXPECT_NEAR(at_stop.time, 0.02, 1e-12) << "the ranks did not stop at the step after the snapshot";
  const Outcome resumed = sampler::test::run(
      mpm_solver(2, scene_, here.path() / "second", {"--restart", (first / "restart.h5").string()}), here.path());
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  expect_same_end(scene_, here.path() / "second", reference());
}

}  // namespace
}  // namespace grainbank::faults

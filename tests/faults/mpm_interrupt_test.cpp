// SIGINT, SIGTERM, SIGHUP or SIGPIPE during `mpm_solver SCENE.json` stops the run after its current step: it writes
// OUT/restart.h5 and summary.json ("interrupted": true), exits with status 1 and says how to resume.
// Resuming with --restart continues exactly like the uninterrupted run: the final restart files of
// both hold bitwise-equal points (positions, velocities, F, stresses) at the same time and step.
// A run killed outright resumes the same way from its last periodic checkpoint.
#include <gtest/gtest.h>

#include <csignal>
#include <fstream>

#include "tests/faults/mpm_run_util.hpp"
#include "tests/sampler/sampler_test_util.hpp"

namespace grainbank::faults {
namespace {

namespace fs = std::filesystem;
using sampler::test::Outcome;
using sampler::test::TempDir;

// A cohesive Drucker–Prager column collapsing under gravity onto a frictional floor and wall: every
// point yields or slides, so the state that must survive the restart is rich. About 1 s on one core.
const char* const kScene = R"({
  "grid": {"origin": [0, 0], "cell_size": 0.05, "cells": [40, 16]},
  "time": {"end": 0.4, "output_interval": 0.1, "series_interval": 0.01},
  "effects": {"gravity": true, "boundary_friction": true},
  "gravity": {"g": [0, -9.81]},
  "materials": [{"name": "soil", "law": "drucker_prager", "density": 550, "young": 5e5, "poisson": 0.3,
                 "friction_angle": 30, "cohesion": 150, "tensile_strength": 50}],
  "regions": [{"material": "soil", "rectangle": {"min": [0.1, 0.1], "max": [0.5, 0.7]}, "points_per_cell": 2}],
  "obstacles": [{"line": [[0, 0.1], [2, 0.1]], "k_n": 1e6, "k_t": 1e6, "friction": 0.5, "damping": 0.5},
                {"line": [[0.1, 0.1], [0.1, 0.8]], "k_n": 1e6, "k_t": 1e6, "friction": 0.3, "damping": 0.5}]
})";

std::vector<std::string> mpm_solver(const fs::path& scene, const fs::path& out, std::vector<std::string> extra = {}) {
  std::vector<std::string> args{MPM_SOLVER_BINARY, scene.string(), "--out", out.string(), "--threads", "1"};
  args.insert(args.end(), extra.begin(), extra.end());
  return args;
}

class MpmInterrupt : public ::testing::TestWithParam<int> {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir("gb-mpm-interrupt");
    const fs::path scene = dir_->write("scene.json", kScene);
    const Outcome r = sampler::test::run(mpm_solver(scene, dir_->path() / "reference"), dir_->path());
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  static void TearDownTestSuite() { delete dir_; }
  static TempDir* dir_;
};
TempDir* MpmInterrupt::dir_ = nullptr;

// Resumes `restart` to the scene's end and expects the final points to equal the uninterrupted run's.
void expect_resumes_bit_for_bit(const TempDir& here, const fs::path& scene, const fs::path& restart,
                                const fs::path& reference_dir) {
  const Outcome resumed =
      sampler::test::run(mpm_solver(scene, here.path() / "second", {"--restart", restart.string()}), here.path());
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  const RestartContents end = read_restart_file(here.path() / "second" / "restart.h5");
  const RestartContents reference = read_restart_file(reference_dir / "restart.h5");
  EXPECT_EQ(end.time, reference.time);
  EXPECT_EQ(end.steps, reference.steps);
  ASSERT_EQ(end.points.size(), reference.points.size());
  std::size_t differing = 0;
  for (std::size_t k = 0; k < end.points.size(); ++k) differing += end.points[k] != reference.points[k];
  EXPECT_EQ(differing, 0u) << "of " << end.points.size() << " point values differ from the uninterrupted run";
  // The column really moved: the comparison is not between two resting states.
  std::size_t moved = 0;
  for (std::size_t k = 0; k < end.points.size(); k += mpm::io::kRestartPointColumns) moved += end.points[k + 9] != 0 || end.points[k + 10] != 0;
  EXPECT_GT(moved, 0u);
}

TEST_P(MpmInterrupt, WritesARestartThatResumesBitForBit) {
  const int signal = GetParam();
  const TempDir here("gb-mpm-interrupt-run");
  const fs::path scene = here.write("scene.json", kScene), first = here.path() / "first";
  // The signal reaches the run while it writes its second VTU snapshot (t = 0.1 s of 0.4 s).
  const BlockingSnapshot snapshot(first / "points_000001.vtu");
  const pid_t child = sampler::test::spawn(mpm_solver(scene, first), here.path());
  const bool writing = snapshot.wait_until_written(child);
  kill(child, signal);
  const std::size_t drained = writing ? snapshot.drain() : 0;
  const Outcome stopped = sampler::test::wait_for(child, here.path());
  ASSERT_TRUE(writing) << "the run ended before its second snapshot: " << stopped.err;
  ASSERT_GT(drained, snapshot.capacity()) << "the snapshot fits in the pipe: the run did not wait";

  EXPECT_EQ(stopped.exit_code, 1) << stopped.err;
  const fs::path restart = first / "restart.h5";
  EXPECT_NE(stopped.err.find(std::string("interrupted by ") + strsignal(signal)), std::string::npos) << stopped.err;
  EXPECT_NE(stopped.err.find("--restart " + restart.string()), std::string::npos) << stopped.err;
  const nlohmann::json summary = nlohmann::json::parse(std::ifstream(first / "summary.json"));
  EXPECT_TRUE(summary["interrupted"].get<bool>());
  const RestartContents at_stop = read_restart_file(restart);
  ASSERT_GT(at_stop.time, 0.0);
  ASSERT_LT(at_stop.time, 0.4) << "the run ended before the signal: nothing was interrupted";
  EXPECT_EQ(at_stop.time, summary["final_time"].get<double>());
  expect_resumes_bit_for_bit(here, scene, restart, dir_->path() / "reference");
}

// SIGHUP: the terminal closed; SIGPIPE: the reader of the progress lines went away (a study killed
// outright), which by default would end the run without its checkpoint.
INSTANTIATE_TEST_SUITE_P(Signals, MpmInterrupt, ::testing::Values(SIGINT, SIGTERM, SIGHUP, SIGPIPE),
                         [](const auto& info) { return std::string(sigabbrev_np(info.param)); });

// A run killed outright writes nothing on its way out; with --checkpoint-every 0 it has left the
// restart of its last snapshot, from which it resumes exactly like the uninterrupted run.
TEST_F(MpmInterrupt, AKilledRunResumesFromItsLastCheckpointBitForBit) {
  const TempDir here("gb-mpm-killed-run");
  const fs::path scene = here.write("scene.json", kScene), first = here.path() / "first";
  // Killed while it writes its third snapshot (t = 0.2 s): the checkpoint of the second (0.1 s) is
  // complete, that of the third not begun.
  const BlockingSnapshot snapshot(first / "points_000002.vtu");
  const pid_t child = sampler::test::spawn(mpm_solver(scene, first, {"--checkpoint-every", "0"}), here.path());
  const bool writing = snapshot.wait_until_written(child);
  kill(child, SIGKILL);
  const Outcome killed = sampler::test::wait_for(child, here.path());
  ASSERT_TRUE(writing) << "the run ended before its third snapshot: " << killed.err;
  EXPECT_FALSE(fs::exists(first / "summary.json"));
  EXPECT_FALSE(fs::exists(first / "restart.h5.partial"));
  const RestartContents checkpoint = read_restart_file(first / "restart.h5");
  EXPECT_NEAR(checkpoint.time, 0.1, 1e-12);
  expect_resumes_bit_for_bit(here, scene, first / "restart.h5", dir_->path() / "reference");
}

}  // namespace
}  // namespace grainbank::faults

// The surrogate law in a solver and a scene (issue 13): a restart continues bit for bit, and a
// scene names the law and its keys are checked, and the run's summary carries its length-scale fit.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "tests/mpm/surrogate_law_fixture.hpp"
#include "common/json_input.hpp"
#include "mpm_solver/core/solver.hpp"
#include "mpm_solver/io/coupling_report.hpp"
#include "mpm_solver/io/restart.hpp"
#include "mpm_solver/io/scene_input.hpp"
#include "database/surrogate/library_reach.hpp"

namespace grainbank::mpm {
namespace {

using namespace surrogate_law_fixture;

Solver one_point_solver(const SurrogateLawSettings& s) {
  Solver solver(Grid(Vec2(0, 0), 0.1, 6, 6), SolverSettings{});
  solver.add_law(surrogate_law(s));
  solver.add_point(0, Vec2(0.3, 0.3), 0.0025, 0.025, Vec2::Zero());
  return solver;
}

SurrogateLaw& law_of(Solver& solver) { return dynamic_cast<SurrogateLaw&>(solver.law(0)); }

TEST(SurrogateLaw, ARestartContinuesBitForBit) {
  // Compressed and sheared, then stretched: at half the motion's median estimated error the point
  // goes live, returns, and goes live again.
  std::vector<Mat2> motion(20, off_library_motion().front());
  motion.insert(motion.end(), 40, Mat2{{1.0, 0.0}, {0.0, 1.0}});
  // Live spells start from a cell servoed to the point's state, or by replay from the point's
  // checkpoint. With the state warm start the learned samples span three steps, so a restart inside a
  // spell must keep the steps its next sample spans.
  for (const auto warm_start : {SurrogateLawSettings::WarmStart::state, SurrogateLawSettings::WarmStart::replay}) {
    SCOPED_TRACE(warm_start == SurrogateLawSettings::WarmStart::state ? "state warm start" : "replay");
    SurrogateLawSettings s = settings(0.5 * median_tolerance(motion), 2);
    s.warm_start = warm_start;
    if (warm_start == SurrogateLawSettings::WarmStart::state) s.sample_span = 3;
    Solver straight = one_point_solver(s);
    Driver d;
    std::vector<PointStress> expected;
    std::vector<StressSource> sources;
    for (const Mat2& L : motion) {
      d(law_of(straight), L, kDt);
      expected.push_back(d.stress);
      sources.push_back(law_of(straight).source(0));
    }
    // Restart one step after the point first went live (its cell, history and learned samples
    // matter), and one step after it first handed its cell back, before it goes live again (the kept
    // cell or the checkpoint it will start from matters).
    const auto live = std::find(sources.begin(), sources.end(), StressSource::live);
    ASSERT_NE(live, sources.end());
    const auto back = std::find(live, sources.end(), StressSource::hit);
    ASSERT_NE(back, sources.end()) << "the point never returned to the surrogate";
    ASSERT_NE(std::find(back, sources.end(), StressSource::live), sources.end()) << "nor went live again";
    // And right after the spell's first step, whose successor's sample spans both (with the state
    // warm start).
    ASSERT_EQ(*(live + 1), StressSource::live) << "a spell lasts at least return_after steps";
    for (const auto restart_after : {static_cast<std::size_t>(live - sources.begin()) + 1,
                                     static_cast<std::size_t>(live - sources.begin()) + 2,
                                     static_cast<std::size_t>(back - sources.begin()) + 1}) {
      SCOPED_TRACE("restart after step " + std::to_string(restart_after));
      ASSERT_LT(restart_after, motion.size());
      Solver first = one_point_solver(s);
      Driver e;
      for (std::size_t k = 0; k < restart_after; ++k) e(law_of(first), motion[k], kDt);
      const std::filesystem::path file = shared().dir.path() / "restart.h5";
      io::write_restart(file, first);
      Solver resumed = one_point_solver(s);
      io::read_restart(file, resumed);
      EXPECT_EQ(law_of(resumed).learned(), law_of(first).learned());
      for (std::size_t k = restart_after; k < motion.size(); ++k) {
        e(law_of(resumed), motion[k], kDt);
        EXPECT_EQ(e.stress.in_plane, expected[k].in_plane) << "step " << k;
        EXPECT_EQ(e.stress.zz, expected[k].zz) << "step " << k;
        EXPECT_EQ(law_of(resumed).source(0), sources[k]) << "step " << k;
      }
      EXPECT_EQ(law_of(resumed).learned(), law_of(straight).learned());
      EXPECT_EQ(law_of(resumed).damage(0), law_of(straight).damage(0));
      // A replay after the restart starts where one in the straight run does: the same increments.
      EXPECT_EQ(law_of(resumed).point_counters(0).warm_start_increments,
                law_of(straight).point_counters(0).warm_start_increments -
                    law_of(first).point_counters(0).warm_start_increments);
    }
  }
}

// A restart's learned samples are keys and answers made with its run's constants and sample span; a
// scene that would key them otherwise (another pressure_floor or sample_span) is refused, naming both.
TEST(SurrogateLaw, ARestartIsRefusedUnderAnotherFloorOrSpan) {
  const SurrogateLawSettings s = settings(kNoLimit);
  Solver first = one_point_solver(s);
  Driver d;
  for (int k = 0; k < 3; ++k) d(law_of(first), off_library_motion().front(), kDt);
  const std::filesystem::path file = shared().dir.path() / "restart_keying.h5";
  io::write_restart(file, first);
  const auto refused = [&](Solver& resumed, const char* named) {
    try {
      io::read_restart(file, resumed);
      ADD_FAILURE() << "resumed under another " << named;
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(named), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("resume with"), std::string::npos) << e.what();
    }
  };
  SurrogateLawSettings wider = s;
  wider.sample_span = 2;
  Solver spanned = one_point_solver(wider);
  refused(spanned, "sample_span");
  surrogate::Dataset floored = shared().dataset;
  floored.constants.p_floor = floored.constants.p_ref;
  Solver at_preparation(Grid(Vec2(0, 0), 0.1, 6, 6), SolverSettings{});
  at_preparation.add_law(std::make_unique<SurrogateLaw>(*shared().cell, floored, s, shared().snapshots));
  at_preparation.add_point(0, Vec2(0.3, 0.3), 0.0025, 0.025, Vec2::Zero());
  refused(at_preparation, "p_floor");
  Solver same = one_point_solver(s);
  EXPECT_NO_THROW(io::read_restart(file, same));
  EXPECT_EQ(law_of(same).learned(), law_of(first).learned());
}

std::filesystem::path write_scene(const std::string& material_extra, const std::string& fallback_extra = "") {
  const std::filesystem::path file = shared().dir.path() / "scene.json";
  std::ofstream(file) << R"({
  "grid": {"cell_size": 0.1, "cells": [6, 6]},
  "time": {"end": 0.001, "output_interval": 0.001},
  "integration": {"homogeneous_drive": {"L": [[-1, 2], [0, 0.5]], "origin": [0.3, 0.3]}},
  "materials": [{"name": "snow", "law": "surrogate", "library": ")" +
                             shared().path.string() + R"(", "template": )" +
                             std::to_string(shared().template_id) + R"(, "tolerance": 2000, "k": 16,
                 "fallback": {"return_after": 3)" + fallback_extra + "}" + material_extra + R"(}],
  "regions": [{"material": "snow", "rectangle": {"min": [0.2, 0.2], "max": [0.4, 0.4]}}]
})";
  return file;
}

TEST(SurrogateLaw, ASceneNamesTheLawAndItsKeysAreChecked) {
  const io::Scene scene = io::load_scene(write_scene(""));
  ASSERT_FALSE(scene.solver->points().empty());
  const auto& law = dynamic_cast<const SurrogateLaw&>(scene.solver->law(0));
  EXPECT_EQ(law.name(), "surrogate");
  EXPECT_EQ(law.index().options().k, 16u);
  EXPECT_EQ(law.index().size(), shared().dataset.samples.size());
  // Stepped by the solver (its points updated in parallel): every point-step is answered once.
  for (int k = 0; k < 3; ++k) scene.solver->step(kDt);
  CouplingCounters total;
  for (const MaterialPoint& mp : scene.solver->points()) {
    total += law.point_counters(mp.slot);
    EXPECT_TRUE(mp.stress.in_plane.allFinite());
  }
  std::printf("%zu points, 3 steps: %llu hits, %llu live updates, %llu went live\n", scene.solver->points().size(),
              static_cast<unsigned long long>(total.hits), static_cast<unsigned long long>(total.live_updates),
              static_cast<unsigned long long>(total.went_live));
  EXPECT_EQ(total.hits + total.live_updates, 3 * scene.solver->points().size());
  EXPECT_EQ(law.index().size(), shared().dataset.samples.size() + law.learned());
  try {
    io::load_scene(write_scene(R"(, "lookup": {"k": 4})"));
    FAIL() << "an unknown key was accepted";
  } catch (const common::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/materials/0/lookup: unknown key"), std::string::npos) << e.what();
  }
  EXPECT_NE(law.state_warm_start(), nullptr) << "the default warm start is by state";
  const io::Scene replaying = io::load_scene(write_scene("", R"(, "warm_start": "replay")"));
  EXPECT_EQ(dynamic_cast<const SurrogateLaw&>(replaying.solver->law(0)).state_warm_start(), nullptr);
  try {
    io::load_scene(write_scene("", R"(, "warm_start": "sideways")"));
    FAIL() << "an unknown warm start was accepted";
  } catch (const common::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/materials/0/fallback/warm_start"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("\"replay\""), std::string::npos) << e.what();
  }
  const std::pair<const char*, const char*> refused[] = {{R"(, "catch_up_steps": 0)", "/fallback/catch_up_steps"},
                                                          {R"(, "catch_up_legs": 0)", "/fallback/catch_up_legs"},
                                                          {R"(, "catch_up_strain_per_step": -1e-5)", "/fallback/catch_up_strain_per_step"},
                                                          {R"(, "first_cell": "nearest")", "/fallback/first_cell"}};
  const io::Scene limited = io::load_scene(write_scene("", R"(, "catch_up_strain_per_step": 1e-5)"));
  const StateWarmStart* limited_start = dynamic_cast<const SurrogateLaw&>(limited.solver->law(0)).state_warm_start();
  ASSERT_NE(limited_start, nullptr);
  EXPECT_EQ(limited_start->settings().catch_up_strain_per_step, 1e-5);
  EXPECT_EQ(law.state_warm_start()->settings().catch_up_strain_per_step, 0.0) << "no limit by default";
  for (const auto& [fallback, named] : refused) {
    try {
      io::load_scene(write_scene("", fallback));
      FAIL() << fallback << " was accepted";
    } catch (const common::InputError& e) {
      EXPECT_NE(std::string(e.what()).find(std::string("/materials/0") + named), std::string::npos) << e.what();
    }
  }
  // The length scales are the fit of the seed the scene names (0 by default) on the library's dataset.
  surrogate::SurrogateOptions options;
  options.k = 16;
  std::vector<surrogate::LengthScales> fitted;
  for (const std::uint64_t seed : {0, 3}) {
    const io::Scene seeded = io::load_scene(write_scene(seed ? R"(, "fit_seed": 3)" : ""));
    surrogate::LengthScaleSearch search;
    search.seed = seed;
    const surrogate::LengthScales& scales = dynamic_cast<const SurrogateLaw&>(seeded.solver->law(0)).index().scales();
    EXPECT_EQ(scales, surrogate::fit_length_scales(shared().dataset.constants, shared().dataset.samples, options, search).scales)
        << "fit_seed " << seed;
    fitted.push_back(scales);
  }
  EXPECT_NE(fitted[0], fitted[1]) << "on this library the two seeds' probes find different scales";
  try {
    io::load_scene(write_scene(R"(, "fit_seed": -1)"));
    FAIL() << "a negative fit_seed was accepted";
  } catch (const common::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/materials/0/fit_seed"), std::string::npos) << e.what();
  }
  // The normalization's pressure floor is a tenth of the preparation pressure unless the scene
  // names another share of it (reindex.hpp), up to all of it.
  const surrogate::FeatureConstants& constants = law.index().constants();
  EXPECT_DOUBLE_EQ(constants.p_floor, constants.p_ref / 10);
  const io::Scene overconsolidated = io::load_scene(write_scene(R"(, "pressure_floor": 1)"));
  const surrogate::FeatureConstants& at_preparation =
      dynamic_cast<const SurrogateLaw&>(overconsolidated.solver->law(0)).index().constants();
  EXPECT_EQ(at_preparation.p_floor, at_preparation.p_ref);
  EXPECT_EQ(at_preparation.p_ref, constants.p_ref);
  for (const char* share : {R"(, "pressure_floor": 0)", R"(, "pressure_floor": 1.5)"}) {
    try {
      io::load_scene(write_scene(share));
      FAIL() << share << " was accepted";
    } catch (const common::InputError& e) {
      EXPECT_NE(std::string(e.what()).find("/materials/0/pressure_floor"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("(0, 1]"), std::string::npos) << e.what();
    }
  }
  // A point's first cell is the template caught up by default; the library's snapshots are read only
  // for first_cell "snapshot".
  EXPECT_EQ(law.state_warm_start()->size(), 1u);
  const io::Scene from_snapshots = io::load_scene(write_scene("", R"(, "first_cell": "snapshot")"));
  EXPECT_EQ(dynamic_cast<const SurrogateLaw&>(from_snapshots.solver->law(0)).state_warm_start()->size(),
            shared().snapshots.size() + 1);
}

// What the fit settled on reaches the run's summary, nested, and the user is told which scales the
// library leaves to the draw.
TEST(SurrogateLaw, TheRunSummaryCarriesTheFitAndItsEvidence) {
  const io::Scene scene = io::load_scene(write_scene(R"(, "fit_seed": 3)"));
  const auto& law = dynamic_cast<const SurrogateLaw&>(scene.solver->law(0));
  ASSERT_TRUE(law.length_scale_fit());
  const surrogate::LengthScaleFit& fit = *law.length_scale_fit();
  const nlohmann::json summary = io::coupling_summary(*scene.solver)["laws"][0];
  EXPECT_EQ(summary["length_scale_fit"]["seed"], 3.0);
  EXPECT_EQ(summary["length_scale_fit"]["loss"], fit.loss);
  EXPECT_EQ(summary["length_scale_fit"]["coverage"], fit.coverage);
  std::vector<std::string> undetermined;
  for (std::size_t j = 0; j < surrogate::kFeatureCount; ++j) {
    const std::string name(surrogate::kFeatureNames[j]);
    EXPECT_EQ(summary["length_scales"][name]["scale"], law.index().scales()[j]) << name;
    EXPECT_EQ(summary["length_scales"][name]["finer"], fit.evidence[j].finer) << name;
    EXPECT_EQ(summary["length_scales"][name]["coarser"], fit.evidence[j].coarser) << name;
    if (!fit.evidence[j].determined()) undetermined.push_back(name);
  }
  const std::vector<std::string> notes = law.start_report().notes;
  ASSERT_EQ(notes.size(), undetermined.empty() ? 0u : 1u);
  for (const std::string& name : undetermined) EXPECT_NE(notes[0].find(name), std::string::npos) << notes[0];
  if (!notes.empty()) {
    EXPECT_NE(notes[0].find("fit_seed"), std::string::npos) << notes[0];
  }
}

// At its end a run measures the library's estimate on the samples its live cells learned, from the
// library alone, and a resumed run measures the same.
TEST(SurrogateLaw, TheRunEndsWithTheEstimateAndTheLibrarysReachWhereItWentLive) {
  std::vector<Mat2> motion(20, off_library_motion().front());
  motion.insert(motion.end(), 40, Mat2{{1.0, 0.0}, {0.0, 1.0}});
  const SurrogateLawSettings s = settings(0.5 * median_tolerance(motion), 2);
  Solver straight = one_point_solver(s);
  Solver first = one_point_solver(s);
  Driver d, e;
  for (std::size_t k = 0; k < motion.size(); ++k) {
    d(law_of(straight), motion[k], kDt);
    if (k < motion.size() / 2) e(law_of(first), motion[k], kDt);
  }
  const SurrogateLaw& law = law_of(straight);
  ASSERT_GT(law.learned(), 0u) << "the point never went live";
  EXPECT_TRUE(law.end_report().figures.empty()) << "measured before the run ended";
  straight.finish();
  const surrogate::EstimateCalibration direct =
      surrogate::audit_estimate(law.index().constants(), shared().dataset.samples, law.index().scales(),
                                law.index().options(), law.learned_samples(), SurrogateLaw::kAuditedStates);
  const nlohmann::json summary = io::coupling_summary(straight)["laws"][0]["estimate_on_live_states"];
  EXPECT_EQ(summary["samples"], static_cast<double>(law.learned()));
  EXPECT_EQ(summary["coverage"], direct.coverage);
  EXPECT_EQ(summary["median_error_over_estimate"], direct.median_error_over_estimate);
  EXPECT_EQ(summary["median_error"], direct.median_error);
  EXPECT_EQ(summary["median_estimate"], direct.median_estimate);
  // Where the learned states lay against the library's samples, feature by feature.
  const surrogate::LibraryReach reach =
      surrogate::library_reach(shared().dataset.samples, law.learned_samples(), SurrogateLaw::kReachTail);
  const nlohmann::json beyond = io::coupling_summary(straight)["laws"][0]["live_states_beyond_library"];
  EXPECT_EQ(beyond["states"], static_cast<double>(law.learned()));
  EXPECT_EQ(beyond["tail"], SurrogateLaw::kReachTail);
  EXPECT_EQ(beyond["any"], reach.beyond_any);
  bool noted_reach = false;
  for (std::size_t j = 0; j < surrogate::kFeatureCount; ++j) {
    const std::string name(surrogate::kFeatureNames[j]);
    EXPECT_EQ(beyond[name]["below"], reach.features[j].below) << name;
    EXPECT_EQ(beyond[name]["above"], reach.features[j].above) << name;
    noted_reach |= std::max(reach.features[j].below, reach.features[j].above) >= SurrogateLaw::kReachNoted;
  }
  const std::vector<std::string> notes = law.end_report().notes;
  EXPECT_EQ(notes.size(), (direct.coverage < 0.5 ? 1u : 0u) + (noted_reach ? 1u : 0u));
  // Off the library's motion, the point's states lie beyond its samples, and the note names each
  // feature and side beyond which a noted share of them lay, and no other.
  ASSERT_TRUE(noted_reach);
  const std::string& note = notes.back();
  for (std::size_t j = 0; j < surrogate::kFeatureCount; ++j) {
    const std::string name(surrogate::kFeatureNames[j]);
    const std::pair<std::string, double> sides[] = {{" below in ", reach.features[j].below},
                                                    {" above in ", reach.features[j].above}};
    for (const auto& [side, share] : sides)
      EXPECT_EQ(note.find(name + side) != std::string::npos, share >= SurrogateLaw::kReachNoted) << name << side;
  }
  // Resumed halfway, the run ends with the same figures, to the bit.
  const std::filesystem::path file = shared().dir.path() / "restart_audit.h5";
  io::write_restart(file, first);
  Solver resumed = one_point_solver(s);
  io::read_restart(file, resumed);
  for (std::size_t k = motion.size() / 2; k < motion.size(); ++k) e(law_of(resumed), motion[k], kDt);
  resumed.finish();
  EXPECT_EQ(io::coupling_summary(resumed)["laws"][0]["estimate_on_live_states"], summary);
  EXPECT_EQ(io::coupling_summary(resumed)["laws"][0]["live_states_beyond_library"], beyond);
}

}  // namespace
}  // namespace grainbank::mpm

// A run interrupted by a restart file (written, then read into a solver rebuilt from the same scene)
// continues exactly like the uninterrupted run: points (with APIC's affine velocity), live DEM cells
// and obstacle friction history.
#include <gtest/gtest.h>
#include <hdf5.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <numbers>
#include <string>

#include "dem_sampler/cell/preparation.hpp"
#include "dem_sampler/cell/snow_preset.hpp"
#include "mpm_solver/dem_laws/live_dem_law.hpp"
#include "mpm_solver/laws/drucker_prager_law.hpp"
#include "mpm_solver/io/restart.hpp"
#include "tests/dem/dem_test_util.hpp"
#include "tests/mpm/mpm_test_util.hpp"

namespace grainbank::mpm {
namespace {

dem::DemCell small_cell() { return dem::prepare_cell(dem::snow_material(), dem::snow_preparation(20, 9)); }

// An elastic block and a few live points sliding on a frictional floor.
Solver build(const dem::DemCell& cell) {
  Solver solver(Grid(Vec2(0, 0), 0.1, 10, 8), SolverSettings{});
  solver.add_law(std::make_unique<ElasticLaw>(1000, Elasticity{1e5, 0.3}));
  solver.add_law(std::make_unique<LiveDemLaw>(cell, LiveDemSettings{}));
  seed_region(solver, 0, rectangle(Vec2(0.2, 0.2), Vec2(0.4, 0.4)), 2, Vec2(0.5, 0));
  seed_region(solver, 1, rectangle(Vec2(0.4, 0.2), Vec2(0.5, 0.3)), 2, Vec2(0.5, 0));
  solver.add_obstacle(Obstacle(Polyline{{Vec2(0, 0.2), Vec2(1, 0.2)}, false}, ContactParameters{1e5, 1e5, 0.4, 0.3}));
  solver.set_gravity(Gravity{Vec2(0, -9.81), std::nullopt});
  return solver;
}

void expect_same_points(const Solver& reference, const Solver& resumed) {
  EXPECT_EQ(resumed.time(), reference.time());
  ASSERT_EQ(resumed.points().size(), reference.points().size());
  for (std::size_t p = 0; p < reference.points().size(); ++p) {
    const MaterialPoint &a = reference.points()[p], &b = resumed.points()[p];
    EXPECT_EQ(a.id, b.id);
    EXPECT_EQ(a.position, b.position);
    EXPECT_EQ(a.velocity, b.velocity);
    EXPECT_EQ(a.affine_velocity, b.affine_velocity);
    EXPECT_EQ(a.stress.in_plane, b.stress.in_plane);
    EXPECT_EQ(a.stress.zz, b.stress.zz);
    EXPECT_EQ(a.volume, b.volume);
  }
}

// Runs `build()` 2n steps, and n steps then a restart file then n more; `halfway` changes both runs
// after their first n steps. Returns the solver before the restart, the uninterrupted one and the
// resumed one.
struct RestartedRun {
  Solver before, reference, resumed;
};
RestartedRun run_with_restart(const std::function<Solver()>& build, int n, double dt, const std::string& file_name,
                              const std::function<void(Solver&)>& halfway = [](Solver&) {}) {
  Solver reference = build();
  for (int k = 0; k < n; ++k) reference.step(dt);
  halfway(reference);
  for (int k = 0; k < n; ++k) reference.step(dt);
  Solver first = build();
  for (int k = 0; k < n; ++k) first.step(dt);
  const auto file = std::filesystem::temp_directory_path() / file_name;
  std::filesystem::remove(file);
  io::write_restart(file, first);
  Solver resumed = build();
  io::read_restart(file, resumed);
  halfway(resumed);
  for (int k = 0; k < n; ++k) resumed.step(dt);
  std::filesystem::remove(file);
  return {std::move(first), std::move(reference), std::move(resumed)};
}

TEST(Restart, ContinuesExactlyLikeTheUninterruptedRun) {
  const dem::DemCell cell = small_cell();
  auto [first, reference, resumed] = run_with_restart([&] { return build(cell); }, 15, 1e-4, "gb_mpm_restart_test.h5");

  expect_same_points(reference, resumed);
  EXPECT_EQ(resumed.obstacles()[0].tangential_history(), reference.obstacles()[0].tangential_history());
  // The points carried an affine velocity (APIC), so the file had to carry it.
  double affine = 0;
  for (const MaterialPoint& mp : first.points()) affine = std::max(affine, mp.affine_velocity.norm());
  EXPECT_GT(affine, 0);
  // Friction was really active, so its history mattered.
  double friction = 0;
  for (double f : reference.obstacles()[0].tangential_history()) friction = std::max(friction, std::abs(f));
  EXPECT_GT(friction, 0);
}

// An elastic block driven into a gate that is let go of gradually (ObstacleRelease), the restart in the
// middle of the release: each point's force is capped by what it held at the release's start, so the
// file must carry that.
TEST(Restart, AGateLetGoOfGraduallyContinuesExactly) {
  const auto pressed = [] {
    Solver solver(Grid(Vec2(0, 0), 0.1, 10, 8), SolverSettings{});
    solver.add_law(std::make_unique<ElasticLaw>(1000, Elasticity{1e5, 0.3}));
    seed_region(solver, 0, rectangle(Vec2(0.2, 0.2), Vec2(0.5, 0.4)), 2, Vec2(0.5, 0));
    solver.add_obstacle(Obstacle(Polyline{{Vec2(0.5, 0.1), Vec2(0.5, 0.5)}, false}, ContactParameters{1e5, 0, 0, 0.3},
                                 Vec2::Zero(), ObstacleRelease{5e-4, 5e-3}));
    return solver;
  };
  auto [first, reference, resumed] = run_with_restart(pressed, 15, 1e-4, "gb_mpm_restart_release_test.h5");
  expect_same_points(reference, resumed);
  EXPECT_EQ(resumed.obstacles()[0].held_forces().size(), reference.obstacles()[0].held_forces().size());
  for (std::size_t p = 0; p < reference.obstacles()[0].held_forces().size(); ++p) {
    const double a = reference.obstacles()[0].held_forces()[p], b = resumed.obstacles()[0].held_forces()[p];
    EXPECT_TRUE(a == b || (std::isnan(a) && std::isnan(b))) << "point " << p;
  }
  // The block's face was held when the release began, so the cap mattered.
  double held = 0;
  for (double f : first.obstacles()[0].held_forces()) held = std::max(held, f);
  EXPECT_GT(held, 0);
}

// A point of separating sand pulled apart, then packed back after the restart: the volume it came
// apart at decides when it carries stress again, so the restart file must carry it.
TEST(Restart, SeparatedSandContinuesExactly) {
  DruckerPragerParameters sand{{1e5, 0.3}, 30 * std::numbers::pi / 180, 0, 0, std::nullopt};
  sand.separation = true;
  const auto pulled_apart = [&] {
    Solver solver(Grid(Vec2(0, 0), 0.1, 8, 8), SolverSettings{});
    solver.add_law(std::make_unique<DruckerPragerLaw>(1500, sand));
    solver.add_point(0, Vec2(0.43, 0.37), 1e-2, 0.05);
    solver.set_homogeneous_drive(HomogeneousDrive{Mat2::Identity() * 5, Vec2(0.43, 0.37), std::nullopt});
    return solver;
  };
  const auto packed_back = [](Solver& s) {
    s.set_homogeneous_drive(HomogeneousDrive{Mat2::Identity() * -10, Vec2(0.43, 0.37), std::nullopt});
  };
  auto [first, reference, resumed] = run_with_restart(pulled_apart, 40, 1e-4, "gb_mpm_restart_sand_test.h5", packed_back);
  expect_same_points(reference, resumed);
  const double packed_modulus = Elasticity{1e5, 0.3}.p_wave_modulus();
  EXPECT_LT(first.law(0).p_wave_modulus(0), packed_modulus);    // apart at the restart
  EXPECT_GT(pressure_of(reference.points()[0].stress), 0);      // packed back by the end
}

Mat2 flattening() {
  Mat2 L;
  L << 10, 0, 0, -10;
  return L;
}

// A live point flattened at constant volume: its cell re-tiles (30 -> 60 spheres near t = 0.02 s)
// or, with a cap below that, is regenerated. Or driven at another L.
Solver flattened_live_point(const dem::DemCell& cell, std::size_t max_spheres = 480, bool regenerate = false,
                            const Mat2& L = flattening()) {
  Solver solver(Grid(Vec2(0, 0), 0.1, 8, 8), SolverSettings{});
  LiveDemSettings settings;
  settings.max_spheres = max_spheres;
  settings.regenerate_beyond_cap = regenerate;
  solver.add_law(std::make_unique<LiveDemLaw>(cell, settings));
  solver.add_point(0, Vec2(0.43, 0.37), 1e-2, 0.05);
  solver.set_homogeneous_drive(HomogeneousDrive{L, Vec2(0.43, 0.37), std::nullopt});
  return solver;
}

const LiveDemLaw& live(const Solver& s) { return dynamic_cast<const LiveDemLaw&>(s.law(0)); }

// Runs a flattened live point 300 steps, and again with a restart after 150; `changed_before` says
// whether its cell was re-tiled or regenerated by then (so the restart had to carry that). The
// resumed run must match the uninterrupted one: point, cell and counters.
void expect_exact_resume_across_a_cell_change(std::size_t max_spheres, bool regenerate, const std::string& file_name,
                                    const std::function<bool(const Solver&)>& changed_before) {
  const dem::DemCell cell = dem::prepare_cell(dem::snow_material(), dem::snow_preparation(30, 5));
  const double dt = 2e-4;
  const auto run = [&](Solver& s, int steps) {
    for (int k = 0; k < steps; ++k) s.step(dt);
  };
  Solver reference = flattened_live_point(cell, max_spheres, regenerate);
  run(reference, 300);
  Solver first = flattened_live_point(cell, max_spheres, regenerate);
  run(first, 150);
  EXPECT_TRUE(changed_before(first)) << "the cell must have changed before the restart";
  const auto file = std::filesystem::temp_directory_path() / file_name;
  std::filesystem::remove(file);
  io::write_restart(file, first);
  Solver resumed = flattened_live_point(cell, max_spheres, regenerate);
  io::read_restart(file, resumed);
  const CouplingCounters at_restart = live(first).point_counters(0), read = live(resumed).point_counters(0);
  EXPECT_EQ(read.retilings, at_restart.retilings);
  EXPECT_EQ(read.regenerations, at_restart.regenerations);
  run(resumed, 150);

  const MaterialPoint &a = reference.points()[0], &b = resumed.points()[0];
  EXPECT_EQ(a.stress.in_plane, b.stress.in_plane);
  EXPECT_EQ(a.volume, b.volume);
  std::string why;
  EXPECT_TRUE(dem::test::states_identical(live(reference).cell(0).state(), live(resumed).cell(0).state(), &why)) << why;
  const CouplingCounters expected = live(reference).point_counters(0), got = live(resumed).point_counters(0);
  EXPECT_EQ(got.retilings, expected.retilings);
  EXPECT_EQ(got.regenerations, expected.regenerations);
  EXPECT_EQ(got.regenerations_unconverged, expected.regenerations_unconverged);
}

// A point dilated until its cell's grains fly apart: the dilations its dispersed cell did not take
// (live_cell_model.hpp) are counted, and the count survives a restart. The bonds are broken first:
// bonded clusters would fly apart whole, still interacting, so the cell would not count as dispersed.
TEST(Restart, TheDispersedHoldsOfACellContinueExactly) {
  const dem::DemCell bonded = dem::prepare_cell(dem::snow_material(), dem::snow_preparation(30, 5));
  dem::CellState unbonded = bonded.state();
  for (dem::Bond& b : unbonded.bonds) b.integrity = 0;
  const dem::DemCell cell(unbonded, bonded.material(), bonded.skin());
  const Mat2 dilation = 40 * Mat2::Identity();  // volume × 100 in ln(100)/80 ≈ 0.058 s
  const auto run = [](Solver& s, int steps) {
    for (int k = 0; k < steps; ++k) s.step(2e-4);
  };
  Solver reference = flattened_live_point(cell, 480, false, dilation);
  run(reference, 500);
  Solver first = flattened_live_point(cell, 480, false, dilation);
  run(first, 400);
  const std::uint64_t held = live(first).point_counters(0).dispersed_holds;
  std::printf("dispersed holds after 400 steps: %llu, after 500: %llu\n", static_cast<unsigned long long>(held),
              static_cast<unsigned long long>(live(reference).point_counters(0).dispersed_holds));
  ASSERT_GT(held, 0u) << "the cell must have dispersed before the restart";
  EXPECT_LT(first.points()[0].volume, 102 * 1e-2) << "a held cell keeps its point's volume near 100x";
  const auto file = std::filesystem::temp_directory_path() / "gb_mpm_restart_dispersed_test.h5";
  std::filesystem::remove(file);
  io::write_restart(file, first);
  Solver resumed = flattened_live_point(cell, 480, false, dilation);
  io::read_restart(file, resumed);
  EXPECT_EQ(live(resumed).point_counters(0).dispersed_holds, held);
  run(resumed, 100);
  EXPECT_EQ(live(resumed).point_counters(0).dispersed_holds, live(reference).point_counters(0).dispersed_holds);
  EXPECT_EQ(live(resumed).point_counters(0).dispersed_holds, held + 100) << "every dilating step was held";
  EXPECT_EQ(resumed.points()[0].volume, reference.points()[0].volume);
}

TEST(Restart, ACellReTiledBeforeTheRestartContinuesExactly) {
  expect_exact_resume_across_a_cell_change(480, false, "gb_mpm_restart_retiled_test.h5",
                                           [](const Solver& s) { return live(s).cell(0).size() > 30; });
}

TEST(Restart, ACellRegeneratedBeforeTheRestartContinuesExactly) {
  expect_exact_resume_across_a_cell_change(59, true, "gb_mpm_restart_regenerated_test.h5",
                                           [](const Solver& s) { return live(s).point_counters(0).regenerations >= 1; });
}

// A restart file of another format version (here: version 1, which had no format attribute) is
// refused before anything is restored, naming the file, both versions and what to do.
TEST(Restart, FileOfAnotherVersionIsRefused) {
  const dem::DemCell cell = small_cell();
  Solver first = build(cell);
  first.step(1e-4);
  const auto file = std::filesystem::temp_directory_path() / "gb_mpm_restart_version_test.h5";
  std::filesystem::remove(file);
  io::write_restart(file, first);
  const hid_t h5 = H5Fopen(file.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  ASSERT_GE(h5, 0);
  ASSERT_GE(H5Adelete(h5, "format"), 0);
  H5Fclose(h5);
  Solver resumed = build(cell);
  try {
    io::read_restart(file, resumed);
    ADD_FAILURE() << "a version 1 restart file was read";
  } catch (const std::runtime_error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(file.string()), std::string::npos) << message;
    EXPECT_NE(message.find("\"grainbank-restart-1\", expected \"" + std::string(io::kRestartFormat) + "\""), std::string::npos) << message;
    EXPECT_NE(message.find("rerun from the start"), std::string::npos) << message;
  }
  EXPECT_EQ(resumed.time(), 0.0);
  std::filesystem::remove(file);
}

}  // namespace
}  // namespace grainbank::mpm

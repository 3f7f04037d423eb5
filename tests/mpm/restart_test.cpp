// A run interrupted by a restart file (written, then read into a solver rebuilt from the same scene)
// continues exactly like the uninterrupted run: points (with APIC's affine velocity), live DEM cells
// and obstacle friction history.
#include <gtest/gtest.h>
#include <hdf5.h>

#include <filesystem>

#include "dem_sampler/cell/preparation.hpp"
#include "dem_sampler/cell/snow_preset.hpp"
#include "mpm_solver/dem_laws/live_dem_law.hpp"
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

TEST(Restart, ContinuesExactlyLikeTheUninterruptedRun) {
  const dem::DemCell cell = small_cell();
  const double dt = 1e-4;
  Solver reference = build(cell);
  for (int k = 0; k < 30; ++k) reference.step(dt);

  Solver first = build(cell);
  for (int k = 0; k < 15; ++k) first.step(dt);
  const auto file = std::filesystem::temp_directory_path() / "gb_mpm_restart_test.h5";
  std::filesystem::remove(file);
  io::write_restart(file, first);
  Solver resumed = build(cell);
  io::read_restart(file, resumed);
  for (int k = 0; k < 15; ++k) resumed.step(dt);

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

// A live point flattened at constant volume: its cell re-tiles (30 -> 60 spheres near t = 0.02 s)
// or, with a cap below that, is regenerated.
Solver flattened_live_point(const dem::DemCell& cell, std::size_t max_spheres = 480, bool regenerate = false) {
  Solver solver(Grid(Vec2(0, 0), 0.1, 8, 8), SolverSettings{});
  LiveDemSettings settings;
  settings.max_spheres = max_spheres;
  settings.regenerate_beyond_cap = regenerate;
  solver.add_law(std::make_unique<LiveDemLaw>(cell, settings));
  solver.add_point(0, Vec2(0.43, 0.37), 1e-2, 0.05);
  Mat2 L;
  L << 10, 0, 0, -10;
  solver.set_homogeneous_drive(HomogeneousDrive{L, Vec2(0.43, 0.37)});
  return solver;
}

TEST(Restart, ACellReTiledBeforeTheRestartContinuesExactly) {
  const dem::DemCell cell = dem::prepare_cell(dem::snow_material(), dem::snow_preparation(30, 5));
  const double dt = 2e-4;
  Solver reference = flattened_live_point(cell);
  for (int k = 0; k < 300; ++k) reference.step(dt);

  Solver first = flattened_live_point(cell);
  for (int k = 0; k < 150; ++k) first.step(dt);
  const auto live = [](const Solver& s) -> const LiveDemLaw& { return dynamic_cast<const LiveDemLaw&>(s.law(0)); };
  ASSERT_GT(live(first).cell(0).size(), cell.size()) << "the cell must have re-tiled before the restart";
  const auto file = std::filesystem::temp_directory_path() / "gb_mpm_restart_retiled_test.h5";
  std::filesystem::remove(file);
  io::write_restart(file, first);
  Solver resumed = flattened_live_point(cell);
  io::read_restart(file, resumed);
  EXPECT_EQ(live(resumed).point_counters(0).retilings, live(first).point_counters(0).retilings);
  for (int k = 0; k < 150; ++k) resumed.step(dt);

  const MaterialPoint &a = reference.points()[0], &b = resumed.points()[0];
  EXPECT_EQ(a.stress.in_plane, b.stress.in_plane);
  EXPECT_EQ(a.volume, b.volume);
  std::string why;
  EXPECT_TRUE(dem::test::states_identical(live(reference).cell(0).state(), live(resumed).cell(0).state(), &why)) << why;
  EXPECT_EQ(live(resumed).point_counters(0).retilings, live(reference).point_counters(0).retilings);
}

TEST(Restart, ACellRegeneratedBeforeTheRestartContinuesExactly) {
  const dem::DemCell cell = dem::prepare_cell(dem::snow_material(), dem::snow_preparation(30, 5));
  const double dt = 2e-4;
  const auto run = [&](Solver& s, int steps) {
    for (int k = 0; k < steps; ++k) s.step(dt);
  };
  const auto live = [](const Solver& s) -> const LiveDemLaw& { return dynamic_cast<const LiveDemLaw&>(s.law(0)); };
  Solver reference = flattened_live_point(cell, 59, true);
  run(reference, 300);

  Solver first = flattened_live_point(cell, 59, true);
  run(first, 150);
  ASSERT_GE(live(first).point_counters(0).regenerations, 1u) << "the cell must have been regenerated before the restart";
  const auto file = std::filesystem::temp_directory_path() / "gb_mpm_restart_regenerated_test.h5";
  std::filesystem::remove(file);
  io::write_restart(file, first);
  Solver resumed = flattened_live_point(cell, 59, true);
  io::read_restart(file, resumed);
  EXPECT_EQ(live(resumed).point_counters(0).regenerations, live(first).point_counters(0).regenerations);
  run(resumed, 150);

  const MaterialPoint &a = reference.points()[0], &b = resumed.points()[0];
  EXPECT_EQ(a.stress.in_plane, b.stress.in_plane);
  EXPECT_EQ(a.volume, b.volume);
  std::string why;
  EXPECT_TRUE(dem::test::states_identical(live(reference).cell(0).state(), live(resumed).cell(0).state(), &why)) << why;
  EXPECT_EQ(live(resumed).point_counters(0).regenerations, live(reference).point_counters(0).regenerations);
  EXPECT_EQ(live(resumed).point_counters(0).regenerations_unconverged,
            live(reference).point_counters(0).regenerations_unconverged);
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

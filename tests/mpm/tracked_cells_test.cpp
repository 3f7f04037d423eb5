// The DEM cells of tracked points: the packing CSV written for a live point reloads (with
// dem_sampler's packing reader) into a cell with the same cell matrix, positions and radii; the VTK
// polydata holds one vertex per sphere and one line per intact bond; analytic points write nothing.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "dem_sampler/cell/preparation.hpp"
#include "dem_sampler/cell/snow_preset.hpp"
#include "common/temporary_directory.hpp"
#include "mpm_solver/dem_laws/live_dem_law.hpp"
#include "mpm_solver/io/tracked_cells.hpp"
#include "tests/mpm/mpm_test_util.hpp"
#include "dem_sampler/driver/packing_csv.hpp"

namespace grainbank::mpm {
namespace {

// One elastic and one live point (ids 0 and 1) after a few steps of shear, so the cell has moved.
Solver sheared_solver() {
  Solver solver(Grid(Vec2(0, 0), 0.1, 6, 6), SolverSettings{});
  solver.add_law(std::make_unique<ElasticLaw>(1000, Elasticity{1e5, 0.3}));
  solver.add_law(std::make_unique<LiveDemLaw>(dem::prepare_cell(dem::snow_material(), dem::snow_preparation(20, 4)),
                                              LiveDemSettings{}));
  solver.add_point(0, Vec2(0.3, 0.3), 0.0025, 0.025, Vec2(0, 0.2));
  solver.add_point(1, Vec2(0.3, 0.35), 0.0025, 0.025, Vec2(0.5, 0));
  for (int k = 0; k < 3; ++k) solver.step(1e-4);
  return solver;
}

std::string read_all(const std::filesystem::path& file) {
  std::ostringstream s;
  s << std::ifstream(file).rdbuf();
  return s.str();
}

TEST(TrackedCells, PackingReloadsIntoTheSameCell) {
  const Solver solver = sheared_solver();
  const dem::DemCell* cell = io::cell_of_point(solver, 1);
  ASSERT_NE(cell, nullptr);
  EXPECT_EQ(io::cell_of_point(solver, 0), nullptr);
  EXPECT_THROW(io::cell_of_point(solver, 7), std::invalid_argument);

  const TemporaryDirectory dir("gb_tracked_cells");
  io::write_packing_csv(dir.path() / "cell.csv", *cell);
  const app::Packing packing = app::read_packing_csv(dir.path() / "cell.csv");
  EXPECT_EQ(packing.h, cell->cell_matrix());  // 17 digits: exact
  ASSERT_EQ(packing.radii, cell->radii());
  const dem::DemCell reloaded =
      dem::DemCell::from_packing(packing.h, packing.positions, packing.radii, cell->material(), cell->skin());
  // Same spheres up to the periodic wrap: compare reduced coordinates modulo 1.
  const dem::Mat3 h_inv = cell->cell_matrix().inverse();
  const std::vector<dem::Vec3> before = cell->positions(), after = reloaded.positions();
  ASSERT_EQ(after.size(), before.size());
  for (std::size_t k = 0; k < before.size(); ++k) {
    dem::Vec3 d = h_inv * (after[k] - before[k]);
    d = d.array() - d.array().round();
    EXPECT_LT(d.norm(), 1e-13) << "sphere " << k;
  }
  EXPECT_EQ(reloaded.radii(), cell->radii());
}

TEST(TrackedCells, WritesLiveTrackedPointsOnlyWithSpheresAndBonds) {
  const Solver solver = sheared_solver();
  const TemporaryDirectory dir("gb_tracked_cells");
  io::TrackedCells tracked(dir.path() / "cells", {0, 1});
  tracked.write(solver, 4);
  EXPECT_FALSE(std::filesystem::exists(dir.path() / "cells" / "point_0_000004.csv"));
  ASSERT_TRUE(std::filesystem::exists(dir.path() / "cells" / "point_1_000004.csv"));
  const std::string vtk = read_all(dir.path() / "cells" / "point_1_000004.vtk");
  const dem::DemCell& cell = *io::cell_of_point(solver, 1);
  const std::int64_t bonds = cell.measures().bonds;
  EXPECT_GT(bonds, 0);
  EXPECT_NE(vtk.find("VERTICES " + std::to_string(cell.size()) + " "), std::string::npos);
  EXPECT_NE(vtk.find("LINES " + std::to_string(bonds) + " "), std::string::npos);
  EXPECT_NE(vtk.find("POINTS " + std::to_string(cell.size() + bonds) + " double"), std::string::npos);
}

}  // namespace
}  // namespace grainbank::mpm

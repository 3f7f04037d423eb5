// A single live-DEM point under a homogeneous deformation reproduces `dem_sampler run` (the same
// path driver, app::drive_along_path) along the same history of increments, to round-off.
//
// With MUSL a lone free point always sees L = 0 (every node it touches gets its own velocity), so
// the deformation is imposed kinematically: after the grid update and again after the MUSL remap,
// every node gets v_i = L x_i. Cubic B-splines reproduce linear fields (Σ_i x_i ⊗ ∇N_i = I with the
// full 4×4 stencil), so the point's velocity gradient is L and it moves affinely. The Solver has no
// such drive, so the step is composed here from the same transfer functions Solver::step calls.
// dem_sampler applies F_inc = exp(L Δt) per record interval, the MPM F_inc = I + Δt L_p: the drive
// uses L_p = (exp(L Δt) − I)/Δt so that both cells receive the same increments (for simple shear,
// L² = 0 and the two coincide).
#include <gtest/gtest.h>

#include <cmath>

#include "cell/matrix_functions.hpp"
#include "cell/preparation.hpp"
#include "cell/snow_preset.hpp"
#include "core/live_dem_law.hpp"
#include "core/transfers.hpp"
#include "path_driver.hpp"

namespace grainbank::mpm {
namespace {

// v_i = L (x_i − x_0) at every node, no nodal acceleration.
void impose_homogeneous_velocity(Grid& grid, const Mat2& L, const Vec2& x0) {
  for (int row = 0; row < grid.nodes_y(); ++row)
    for (int col = 0; col < grid.nodes_x(); ++col) {
      const std::size_t k = static_cast<std::size_t>(col) + static_cast<std::size_t>(row) * grid.nodes_x();
      const Vec2 x = grid.lower() + grid.cell_size() * Vec2(col - 1, row - 1);  // ghost ring: column 0 is i = −1
      grid.velocity[k] = L * (x - x0);
      grid.acceleration[k].setZero();
    }
}

TEST(HomogeneousLive, SinglePointReproducesDemSamplerRunAlongTheSamePath) {
  const dem::DemCell cell_template = dem::prepare_cell(dem::snow_material(), dem::snow_preparation(30, 5));
  app::PathSpec path;
  path.record_interval = 2e-4;
  path.substepping = {0.1, 1, 0.2};
  dem::Mat3 shear = dem::Mat3::Zero(), compression = dem::Mat3::Zero();
  shear(0, 1) = 2;
  compression(0, 0) = 0.5, compression(1, 1) = -1;
  path.segments = {{shear, 10 * path.record_interval}, {compression, 5 * path.record_interval}};

  // dem_sampler run: the stand-alone cell driven along the path.
  dem::DemCell alone = cell_template;
  std::vector<app::PathRecord> records;
  app::drive_along_path(alone, path, [&](const app::PathRecord& r) { records.push_back(r); });

  // The MPM: one live point, its grid velocities imposed.
  LiveDemSettings settings;
  settings.substepping = path.substepping;
  LiveDemLaw law(cell_template, settings);
  Grid grid(Vec2(0, 0), 0.1, 8, 8);
  std::vector<MaterialPoint> points(1);
  MaterialPoint& mp = points[0];
  mp.slot = static_cast<std::uint32_t>(law.add_point(mp.stress));
  mp.position = Vec2(0.43, 0.37), mp.mass = 1e-3, mp.volume = mp.initial_volume = 1e-2;
  const Vec2 x0 = mp.position;
  std::vector<Stencil> stencils;
  ScatterBuffers buffers(grid.node_count());

  double worst_stress = 0, worst_volume = 0, worst_gradient = 0;
  std::size_t record = 1;
  Vec2 affine_position = mp.position;
  for (const app::PathSegment& segment : path.segments) {
    const double dt = path.record_interval;
    const Mat2 L = ((dem::matrix_exponential(segment.L * dt) - dem::Mat3::Identity()) / dt).topLeftCorner<2, 2>();
    for (int k = 0; k < std::lround(segment.duration / dt); ++k, ++record) {
      compute_stencils(grid, points, stencils);
      particles_to_grid(grid, points, stencils, buffers);
      update_grid(grid, Vec2::Zero());
      impose_homogeneous_velocity(grid, L, x0);
      grid_to_particles(grid, points, stencils, dt, 0.0);
      remap_velocities(grid, points, stencils, buffers);
      impose_homogeneous_velocity(grid, L, x0);
      mp.velocity_gradient = velocity_gradient(grid, stencils[0]);
      const Mat2 F_inc = Mat2::Identity() + dt * mp.velocity_gradient;
      mp.deformation_gradient = F_inc * mp.deformation_gradient;
      law.update(mp.slot, F_inc, dt, mp.stress);
      mp.volume = mp.initial_volume * law.volume_ratio(mp.slot, mp.deformation_gradient);
      affine_position = x0 + (Mat2::Identity() + dt * L) * (affine_position - x0);

      const app::PathRecord& r = records.at(record);
      const dem::Mat3& s = r.stress;
      const double scale = std::abs(s.trace());
      worst_gradient = std::max(worst_gradient, (mp.velocity_gradient - L).norm() / L.norm());
      worst_stress = std::max({worst_stress, std::abs(mp.stress.in_plane(0, 0) - s(0, 0)) / scale,
                               std::abs(mp.stress.in_plane(1, 1) - s(1, 1)) / scale,
                               std::abs(mp.stress.in_plane(0, 1) - 0.5 * (s(0, 1) + s(1, 0))) / scale,
                               std::abs(mp.stress.zz - s(2, 2)) / scale});
      worst_volume = std::max(worst_volume, std::abs(mp.volume / mp.initial_volume - r.F.determinant()));
      EXPECT_NEAR(law.damage(mp.slot), r.measures.damage, 1e-15);
    }
  }
  std::printf("largest relative deviations from dem_sampler run: L %.2g, stress %.2g, volume ratio %.2g\n",
              worst_gradient, worst_stress, worst_volume);
  EXPECT_LT(worst_gradient, 1e-12);  // B-spline linear completeness, to round-off
  EXPECT_LT(worst_stress, 1e-10);
  EXPECT_LT(worst_volume, 1e-12);
  EXPECT_LT((mp.position - affine_position).norm(), 1e-14);  // the point moved with the imposed field
  EXPECT_EQ(record, records.size());
  // The path did something: sheared and compressed the cell.
  EXPECT_GT(std::abs(records.back().stress(0, 1)) + std::abs(records.back().stress(1, 1) - records.front().stress(1, 1)),
            1.0);
}

}  // namespace
}  // namespace grainbank::mpm

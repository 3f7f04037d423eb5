// Driving a cell along a path: exact increments F_inc = exp(L Δt), one record per increment, and
// segments that end exactly at their duration.
#include "dem_sampler/driver/path_driver.hpp"

#include <gtest/gtest.h>

#include "dem_sampler/cell/matrix_functions.hpp"
#include "dem_sampler/cell/substepping.hpp"
#include "dem_sampler/app/record_table.hpp"

namespace grainbank {
namespace {

using dem::Mat3;

TEST(MatrixExponential, MatchesClosedForms) {
  Mat3 shear = Mat3::Zero();
  shear(0, 1) = 0.3;
  EXPECT_TRUE(dem::matrix_exponential(shear).isApprox(Mat3::Identity() + shear, 1e-15));
  const Mat3 stretch = Eigen::Vector3d(2.0, -0.5, 0).asDiagonal();
  const Mat3 expected = Eigen::Vector3d(std::exp(2.0), std::exp(-0.5), 1).asDiagonal();
  EXPECT_TRUE(dem::matrix_exponential(stretch).isApprox(expected, 1e-14));
  Mat3 spin = Mat3::Zero();
  spin(0, 1) = -5;
  spin(1, 0) = 5;
  const Mat3 rotation = dem::matrix_exponential(spin);
  EXPECT_NEAR(rotation(0, 0), std::cos(5.0), 1e-13);
  EXPECT_NEAR(rotation(1, 0), std::sin(5.0), 1e-13);
}

// Two spheres far apart: no contact, so only the kinematics of the driver are tested.
dem::DemCell two_sphere_gas() {
  dem::Material m;
  m.density = 1000;
  m.contact.k_n = 1000;
  m.contact.k_t = 300;
  return dem::DemCell::from_packing(Mat3::Identity(), {dem::Vec3(0.2, 0.2, 0.2), dem::Vec3(0.7, 0.7, 0.7)},
                                    {0.1, 0.1}, m, 0.02);
}

TEST(PathDriver, RecordsEveryIncrementAndEndsSegmentsExactly) {
  app::PathSpec path;
  path.record_interval = 0.1;
  Mat3 L = Mat3::Zero();
  L(0, 1) = 1.0;
  path.segments.push_back({L, 0.35});
  Mat3 compression = Mat3::Zero();
  compression(1, 1) = -0.5;
  path.segments.push_back({compression, 0.2});
  EXPECT_EQ(app::increment_count(path), 4 + 2);

  dem::DemCell cell = two_sphere_gas();
  std::vector<app::PathRecord> records;
  app::drive_along_path(cell, path, [&](const app::PathRecord& r) { records.push_back(r); });
  ASSERT_EQ(records.size(), 7u);
  EXPECT_EQ(records[0].time, 0);
  EXPECT_TRUE(records[0].F.isIdentity());
  EXPECT_NEAR(records[4].time, 0.35, 1e-12);
  EXPECT_NEAR(records[4].F(0, 1), 0.35, 1e-12);
  EXPECT_NEAR(records.back().time, 0.55, 1e-12);
  const Mat3 expected = dem::matrix_exponential(compression * 0.2) * dem::matrix_exponential(L * 0.35);
  EXPECT_TRUE(records.back().F.isApprox(expected, 1e-12)) << records.back().F;
  for (const auto& r : records) EXPECT_TRUE(r.stress.allFinite());
  // Each record carries the increment that ended at it: its L and the engine's sub-step count.
  EXPECT_TRUE(records[0].L.isZero());
  EXPECT_EQ(records[0].substeps, 0);
  const double dem_step = cell.time_step(path.substepping.q_t);
  const double durations[] = {0, 0.1, 0.1, 0.1, 0.35 - 3 * 0.1, 0.1, 0.1};  // the shortened last one
  for (std::size_t k = 1; k < records.size(); ++k) {
    EXPECT_EQ(records[k].L, k <= 4 ? L : compression) << k;
    EXPECT_EQ(records[k].substeps, dem::substep_count(durations[k], dem_step, path.substepping.q_n)) << k;
  }
}

TEST(RecordTable, ColumnsMatchValuesAndStressInvariants) {
  app::PathRecord r;
  r.F = Mat3::Identity();
  r.F(1, 1) = 2;
  r.stress = Eigen::Vector3d(-1, -2, -3).asDiagonal();
  const auto values = app::record_values(r);
  ASSERT_EQ(values.size(), app::record_columns().size());
  auto column = [&](const std::string& name) {
    const auto& c = app::record_columns();
    return values[static_cast<std::size_t>(std::find(c.begin(), c.end(), name) - c.begin())];
  };
  EXPECT_DOUBLE_EQ(column("eps_v"), std::log(2.0));
  EXPECT_DOUBLE_EQ(column("p"), 2);
  EXPECT_DOUBLE_EQ(column("q"), std::sqrt(3.0));  // s = diag(1, 0, -1): sqrt(3/2 · 2)
  EXPECT_DOUBLE_EQ(column("sigma_zz"), -3);
}

}  // namespace
}  // namespace grainbank

// The kinematics every law receives: {F_inc, L, dt} built once, F_inc = exp(L dt), and a point that
// skips constitutive calls keeps time with its deformation. Each test drives a homogeneous domain
// (every node moves with v = L (x - x_0), so every point sees exactly L) with skipping off and on.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include <Eigen/Geometry>

#include "dem_sampler/cell/preparation.hpp"
#include "dem_sampler/cell/snow_preset.hpp"
#include "mpm_solver/laws/elastic_law.hpp"
#include "mpm_solver/core/kinematic_increment.hpp"
#include "mpm_solver/dem_laws/live_dem_law.hpp"
#include "mpm_solver/core/solver.hpp"

namespace grainbank::mpm {
namespace {

constexpr double kDt = 1e-4;
const Vec2 kCentre(0.4, 0.4);

// One law, one point at the centre of a domain driven homogeneously.
Solver one_point(std::unique_ptr<ConstitutiveLaw> law, double skip) {
  SolverSettings settings;
  settings.skip_strain_increment = skip;
  Solver solver(Grid(Vec2(0, 0), 0.1, 8, 8), settings);
  solver.add_law(std::move(law));
  solver.add_point(0, kCentre, 1e-2, 0.05);
  return solver;
}

void drive(Solver& solver, const Mat2& L, int steps) {
  solver.set_homogeneous_drive(HomogeneousDrive{L, kCentre, std::nullopt});
  for (int k = 0; k < steps; ++k) solver.step(kDt);
}

TEST(KinematicIncrement, ExponentialAndLogarithmAreInverse) {
  // Stretch with shear (real eigenvalues), a spin (complex ones) and a degenerate simple shear.
  for (const Mat2& L : {Mat2{{0.7, 2.0}, {-0.3, -0.4}}, Mat2{{0.1, -3.0}, {3.0, 0.1}}, Mat2{{0, 5.0}, {0, 0}}}) {
    const KinematicIncrement step = KinematicIncrement::of_velocity_gradient(L, 0.1);
    EXPECT_NEAR(step.F.determinant(), std::exp(L.trace() * 0.1), 1e-14);
    const KinematicIncrement back = KinematicIncrement::of_deformation(step.F, 0.1);
    EXPECT_LT((back.L - L).norm(), 1e-12 * L.norm()) << L;
  }
  // A pure spin gives a rotation by its angle.
  const KinematicIncrement spin = KinematicIncrement::of_velocity_gradient(Mat2{{0, -2.0}, {2.0, 0}}, 0.25);
  EXPECT_LT((spin.F - Eigen::Rotation2Dd(0.5).toRotationMatrix()).norm(), 1e-15);
}

// A prestressed elastic block turned rigidly: its stress must turn with it, R(ωt) σ₀ R(ωt)ᵀ, and
// keep its magnitude, whether or not the points skip their constitutive calls. (Skipping used to
// turn the stress in the skip branch and again through the law: twice the rotation.)
TEST(KinematicsContract, PrestressedElasticBlockSpinningRigidlyKeepsItsStressTurningWithIt) {
  const double omega = 20;  // [rad/s]: 2e-3 rad per step
  // 6e-3 strain per step: above the skip tolerance, so every point takes the prestress.
  const Mat2 compression{{-60.0, 0}, {0, 0}}, spin{{0, -omega}, {omega, 0}};
  for (const double skip : {0.0, 5e-3}) {
    Solver solver = one_point(std::make_unique<ElasticLaw>(1000, Elasticity{1e6, 0.3}), skip);
    drive(solver, compression, 2);
    const Mat2 prestress = solver.points()[0].stress.in_plane;
    ASSERT_GT(prestress.norm(), 1e4);
    const int steps = 2000;  // 0.4 rad
    drive(solver, spin, steps);
    const Mat2 R = Eigen::Rotation2Dd(omega * steps * kDt).toRotationMatrix();
    const Mat2 expected = R * prestress * R.transpose();
    // A skipping point's stress lags its motion by at most the skip tolerance (relative).
    const double tolerance = 1e-9 + skip;
    EXPECT_LE((solver.points()[0].stress.in_plane - expected).norm(), tolerance * prestress.norm()) << "skip " << skip;
    EXPECT_NEAR(solver.points()[0].stress.in_plane.norm(), prestress.norm(), tolerance * prestress.norm());
    if (skip > 0) {
      EXPECT_GT(solver.skipped_updates(), 0) << "the set-up must skip";
    }
  }
}

// A live DEM point driven slowly, with and without skipping: the cell must receive the time that
// passed (not one step's time for several steps' deformation) and the same stress within the skip
// tolerance.
TEST(KinematicsContract, SlowlyDrivenLivePointGivesTheSameStressWithSkipOnAndOff) {
  const dem::DemCell cell_template = dem::prepare_cell(dem::snow_material(), dem::snow_preparation(30, 5));
  LiveDemSettings live;
  live.substepping = {0.1, 1, 0.2};
  const Mat2 L{{0, 0.2}, {0, -0.1}};  // 3e-5 strain per step
  const int steps = 200;
  const double skip = 1e-4;  // about 4 steps composed per call
  auto run = [&](double skip_tolerance, int n) {
    Solver solver = one_point(std::make_unique<LiveDemLaw>(cell_template, live), skip_tolerance);
    drive(solver, L, n);
    return solver;
  };
  const Mat2 initial = run(0, 0).points()[0].stress.in_plane;
  const Solver every_step = run(0, steps), skipping = run(skip, steps);
  ASSERT_GT(skipping.skipped_updates(), steps / 2) << "the set-up must skip most steps";
  const auto& cell = dynamic_cast<const LiveDemLaw&>(skipping.law(0)).cell(0);
  const MaterialPoint& point = skipping.points()[0];
  // The cell keeps time with the point, up to the steps still pending.
  EXPECT_NEAR(cell.time() + point.pending_time, skipping.time(), 1e-12);
  EXPECT_NEAR(dynamic_cast<const LiveDemLaw&>(every_step.law(0)).cell(0).time(), every_step.time(), 1e-12);
  // And the same stress, within what the pending motion and the skip tolerance allow: the cell's
  // stiffness times the strain not yet applied.
  const Mat2 reference = every_step.points()[0].stress.in_plane;
  const double stiffness = every_step.law(0).p_wave_modulus(0);
  const double tolerance = 2 * stiffness * skip;
  EXPECT_LE((point.stress.in_plane - reference).norm(), tolerance)
      << "every step\n" << reference << "\nskipping\n" << point.stress.in_plane;
  EXPECT_GT((reference - initial).norm(), 5 * tolerance) << "the drive must load the cell beyond the tolerance";
}

}  // namespace
}  // namespace grainbank::mpm

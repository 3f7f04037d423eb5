// Analytic laws: Hooke's law in plane strain, the Jaumann rotation of a stressed body, and the
// Drucker–Prager return mapping (cone, cohesion, tension cut-off).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "mpm_solver/laws/drucker_prager_law.hpp"
#include "mpm_solver/laws/elastic_law.hpp"
#include "mpm_solver/core/gravity.hpp"

namespace grainbank::mpm {
namespace {

double sqrt_j2(const PointStress& s) { return deviatoric_stress_of(s) / std::sqrt(3.0); }

TEST(ElasticLaw, PlaneStrainHooke) {
  const Elasticity e{2e6, 0.25};
  ElasticLaw law(1000, e);
  PointStress s;
  law.add_point(s);
  Mat2 L = Mat2::Zero();
  L(0, 0) = 1e-4 / 1e-3;  // uniaxial strain ε_xx = 1e-4, ε_yy = ε_zz = 0
  law.update(0, KinematicIncrement::of_velocity_gradient(L, 1e-3), Mat2::Identity(), s);
  const double lambda = e.young * e.poisson / ((1 + e.poisson) * (1 - 2 * e.poisson)), g = e.young / 2.5;
  EXPECT_NEAR(s.in_plane(0, 0), (lambda + 2 * g) * 1e-4, 1e-9);
  EXPECT_NEAR(s.in_plane(1, 1), lambda * 1e-4, 1e-9);
  EXPECT_NEAR(s.zz, lambda * 1e-4, 1e-9);
  EXPECT_NEAR(s.in_plane(0, 1), 0, 1e-12);
}

TEST(ElasticLaw, ARigidRotationTurnsTheStressByItsAngle) {
  ElasticLaw law(1000, Elasticity{1e6, 0.3});
  PointStress s;
  law.add_point(s);
  s.in_plane << -100, 0, 0, 0;
  // A finite spin, no stretching: the stress is R σ Rᵀ exactly, whatever the angle (a first-order
  // Jaumann update would give σ_xy = -100 θ and grow the stress by 1 + θ²).
  const double angle = 0.3;
  const Mat2 W{{0, -angle}, {angle, 0}};
  law.update(0, KinematicIncrement::of_velocity_gradient(W / 1e-3, 1e-3), Mat2::Identity(), s);
  EXPECT_NEAR(s.in_plane(0, 1), -100 * std::cos(angle) * std::sin(angle), 1e-9);
  EXPECT_NEAR(s.in_plane(0, 0), -100 * std::cos(angle) * std::cos(angle), 1e-9);
  EXPECT_NEAR(s.in_plane(1, 1), -100 * std::sin(angle) * std::sin(angle), 1e-9);
  EXPECT_NEAR(s.zz, 0, 1e-12);
}

TEST(DruckerPrager, ReturnMappingLandsOnTheConeAtConstantPressure) {
  const double phi = 30 * std::numbers::pi / 180, c = 1000;
  DruckerPragerLaw law(1000, DruckerPragerParameters{{1e6, 0.3}, phi, c, 500, std::nullopt});
  const double eta = std::sin(phi), xi = std::cos(phi);
  PointStress trial;
  trial.in_plane << -5000, 8000, 8000, -3000;
  trial.zz = -4000;
  const PointStress out = law.return_map(trial, 1e-3);
  EXPECT_NEAR(pressure_of(out), pressure_of(trial), 1e-9);
  EXPECT_NEAR(sqrt_j2(out), eta * pressure_of(trial) + xi * c, 1e-6);
  // Radial return: the deviator keeps its direction.
  EXPECT_NEAR(out.in_plane(0, 1) / (out.in_plane(0, 0) - out.in_plane(1, 1)),
              trial.in_plane(0, 1) / (trial.in_plane(0, 0) - trial.in_plane(1, 1)), 1e-12);
  // An admissible stress is left alone.
  PointStress inside;
  inside.in_plane << -5000, 100, 100, -4000;
  inside.zz = -4500;
  const PointStress same = law.return_map(inside, 1e-3);
  EXPECT_NEAR((same.in_plane - inside.in_plane).norm(), 0, 1e-9);
}

TEST(DruckerPrager, SteadyPlaneStrainFlowIsMohrCoulomb) {
  // Plane-strain biaxial test without cohesion: from an isotropic 10 kPa, isochoric compression
  // along y and extension along x (principal axes in plane) until the stress no longer changes.
  // In steady flow the stress ratio (σ1 − σ3)/(σ1 + σ3) of the compressive principal stresses must
  // be Mohr–Coulomb's sin φ.
  for (double degrees : {20.0, 30.0, 40.0}) {
    SCOPED_TRACE(degrees);
    const double phi = degrees * std::numbers::pi / 180;
    const DruckerPragerParameters parameters{{5e6, 0.3}, phi, 0, 0, std::nullopt};
    const DruckerPragerLaw law(1500, parameters);
    PointStress s;
    s.in_plane = -1e4 * Mat2::Identity();
    s.zz = -1e4;
    const KinematicIncrement increment =
        KinematicIncrement::of_velocity_gradient(Mat2{{1e-2, 0}, {0, -1e-2}}, 1e-3);  // 1e-5 per step
    PointStress previous = s;
    for (int k = 0; k < 20000; ++k) {
      previous = s;
      s = law.return_map(elastic_predictor(parameters.elasticity, s, increment), increment.dt);
    }
    EXPECT_NEAR((s.in_plane - previous.in_plane).norm(), 0, 1e-6 * 1e4) << "not yet steady";
    const double sigma1 = -s.in_plane(1, 1), sigma3 = -s.in_plane(0, 0);
    EXPECT_NEAR(s.in_plane(0, 1), 0, 1e-9);
    EXPECT_NEAR((sigma1 - sigma3) / (sigma1 + sigma3), std::sin(phi), 1e-6);
  }
}

TEST(DruckerPrager, SteadyFlowFollowsTheInertialRheology) {
  // Isochoric plane-strain pure shear at a constant rate: in steady flow the elastic strain no longer
  // changes, so the plastic shear rate is the imposed γ̇ = sqrt(2) |D_dev| = 2 ε̇ and the stress ratio
  // (σ1 − σ3)/(σ1 + σ3) = sqrt(J2)/p must be Jop et al.'s μ(I) at I = γ̇ d / sqrt(p / ρ_s), with
  // μ_s = sin φ (glass beads: μ_s = 0.38, μ_2 = 0.64, I_0 = 0.279, d = 0.53 mm).
  const InertialRheology beads{0.64, 0.279, 0.53e-3, 2450};
  const double phi = std::asin(0.38), p0 = 1e4;
  const DruckerPragerParameters parameters{{5e6, 0.3}, phi, 0, 0, beads};
  DruckerPragerLaw law(1500, parameters);
  for (double inertial_number : {1e-3, 0.05, 0.3, 2.0}) {
    SCOPED_TRACE(inertial_number);
    const double shear_rate = inertial_number * std::sqrt(p0 / beads.grain_density) / beads.grain_diameter;
    const double strain_rate = shear_rate / 2;
    PointStress s;
    s.in_plane = -p0 * Mat2::Identity();
    s.zz = -p0;
    const KinematicIncrement increment = KinematicIncrement::of_velocity_gradient(
        Mat2{{strain_rate, 0}, {0, -strain_rate}}, 1e-5 / strain_rate);  // 1e-5 per step
    PointStress previous = s;
    for (int k = 0; k < 20000; ++k) {
      previous = s;
      law.update(0, increment, Mat2::Identity(), s);
    }
    EXPECT_NEAR((s.in_plane - previous.in_plane).norm(), 0, 1e-6 * p0) << "not yet steady";
    const double sigma1 = -s.in_plane(1, 1), sigma3 = -s.in_plane(0, 0);
    EXPECT_NEAR(0.5 * (sigma1 + sigma3), p0, 1e-6 * p0);  // isochoric flow keeps the pressure
    const double mu = beads.mu_2 - (beads.mu_2 - 0.38) / (1 + inertial_number / beads.inertial_number_0);
    EXPECT_NEAR((sigma1 - sigma3) / (sigma1 + sigma3), mu, 1e-6);
  }
}

TEST(DruckerPrager, InertialRheologyParametersAreChecked) {
  const double phi = std::asin(0.38);
  EXPECT_THROW(DruckerPragerLaw(1500, DruckerPragerParameters{{5e6, 0.3}, phi, 0, 0, InertialRheology{0.3, 0.279, 5e-4, 2450}}),
               std::invalid_argument);  // μ_2 below μ_s
  EXPECT_THROW(DruckerPragerLaw(1500, DruckerPragerParameters{{5e6, 0.3}, phi, 0, 0, InertialRheology{0.64, 0, 5e-4, 2450}}),
               std::invalid_argument);
}

TEST(DruckerPrager, TensionCutOffCapsTheMeanStress) {
  DruckerPragerLaw law(1000, DruckerPragerParameters{{1e6, 0.3}, 0.5, 1000, 300, std::nullopt});
  PointStress trial;
  trial.in_plane << 2000, 0, 0, 1000;
  trial.zz = 900;
  const PointStress out = law.return_map(trial, 1e-3);
  EXPECT_NEAR(pressure_of(out), -300, 1e-9);
  EXPECT_THROW(DruckerPragerLaw(1000, DruckerPragerParameters{{1e6, 0.3}, 0.5, 1000, 1e6, std::nullopt}), std::invalid_argument);
}

TEST(Gravity, RampStartsFromItsInitialValue) {
  const Gravity g{Vec2(0, -10), GravityRamp{Vec2(0, -2), 1.0, 3.0}};
  EXPECT_EQ(g.at(0.0), Vec2(0, -2));
  EXPECT_EQ(g.at(1.0), Vec2(0, -2));
  EXPECT_NEAR((g.at(2.0) - Vec2(0, -6)).norm(), 0, 1e-15);
  EXPECT_EQ(g.at(5.0), Vec2(0, -10));
}

}  // namespace
}  // namespace grainbank::mpm

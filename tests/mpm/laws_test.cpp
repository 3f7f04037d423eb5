// Analytic laws: Hooke's law in plane strain, the Jaumann rotation of a stressed body, and the
// Drucker–Prager return mapping (cone, cohesion, tension cut-off).
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <numbers>
#include <utility>

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

// The plastic strain of a return, trial minus returned stress through the elastic compliance, in the
// in-plane principal frame of the stress (ε1 along the most compressive axis) and out of plane.
struct PlasticStrain {
  double major = 0, minor = 0, zz = 0;
};

PlasticStrain plastic_strain(const Elasticity& e, const PointStress& trial, const PointStress& out) {
  const double g = e.shear_modulus(), bulk = e.bulk_modulus();
  const double dp = pressure_of(trial) - pressure_of(out);  // Δσ_m = −Δp
  const Mat2 ds = (trial.in_plane - out.in_plane) + dp * Mat2::Identity();  // in-plane deviator change
  const Mat2 strain = ds / (2 * g) - dp / (3 * bulk) * Mat2::Identity();
  const double zz = ((trial.zz - out.zz) + dp) / (2 * g) - dp / (3 * bulk);
  const Eigen::SelfAdjointEigenSolver<Mat2> axes(out.in_plane);  // ascending: the most compressive first
  const Mat2 along = axes.eigenvectors().transpose() * strain * axes.eigenvectors();
  return {along(0, 0), along(1, 1), zz};
}

TEST(DruckerPrager, PlaneStrainFlowOnTheConeIsMohrCoulombsWithItsDilatancy) {
  // Where the cone's plastic flow has no out-of-plane part (ε̇ᵖ_zz = 0, as in steady plane-strain
  // flow), the stress must satisfy Mohr–Coulomb, (σ1 − σ3)/2 = sin φ (σ1 + σ3)/2 + c cos φ in
  // compression-positive principal stresses, and the flow must dilate at the Mohr–Coulomb rate sin ψ =
  // (ε1 + ε3)/(ε3 − ε1). The out-of-plane trial stress whose return has ε_zz = 0 is found by bisection,
  // so the check does not assume the cone's constants.
  const Elasticity e{1e6, 0.3};
  const double c = 1000, degree = std::numbers::pi / 180;
  for (const auto& [phi_deg, psi_deg] : {std::pair{30.0, 0.0}, {30.0, 10.0}, {30.0, 30.0}, {40.0, 20.0}}) {
    SCOPED_TRACE(testing::Message() << "phi " << phi_deg << ", psi " << psi_deg);
    const double phi = phi_deg * degree, psi = psi_deg * degree;
    DruckerPragerParameters parameters{e, phi, c, 0, std::nullopt};
    parameters.dilatancy_angle = psi;
    const DruckerPragerLaw law(1000, parameters);
    PointStress trial;
    trial.in_plane << -2000, 3000, 3000, -12000;
    const auto returned = [&](double zz) {
      trial.zz = zz;
      return law.return_map(trial, 1e-3);
    };
    double low = -30000, high = 10000;  // ε_zz of the return changes sign between them
    ASSERT_LT(plastic_strain(e, trial, returned(low)).zz * plastic_strain(e, trial, returned(high)).zz, 0);
    for (int k = 0; k < 200; ++k) {
      const double mid = 0.5 * (low + high);
      (plastic_strain(e, trial, returned(mid)).zz < 0) == (plastic_strain(e, trial, returned(low)).zz < 0) ? low = mid
                                                                                                             : high = mid;
    }
    const PointStress out = returned(0.5 * (low + high));
    const PlasticStrain flow = plastic_strain(e, trial, out);
    const Eigen::SelfAdjointEigenSolver<Mat2> principal(out.in_plane);
    const double sigma1 = -principal.eigenvalues()(0), sigma3 = -principal.eigenvalues()(1);
    EXPECT_NEAR((sigma1 - sigma3) / 2, std::sin(phi) * (sigma1 + sigma3) / 2 + c * std::cos(phi), 1e-6 * c);
    EXPECT_NEAR((flow.major + flow.minor) / (flow.minor - flow.major), std::sin(psi), 1e-6);
    EXPECT_LT(std::abs(flow.zz), 1e-9 * std::abs(flow.minor - flow.major));
  }
}

TEST(DruckerPrager, TheDilatancyAngleLiesBetweenZeroAndTheFrictionAngle) {
  const double phi = 30 * std::numbers::pi / 180;
  DruckerPragerParameters steeper{{1e6, 0.3}, phi, 1000, 0, std::nullopt};
  steeper.dilatancy_angle = 31 * std::numbers::pi / 180;
  EXPECT_THROW(DruckerPragerLaw(1000, steeper), std::invalid_argument);
  DruckerPragerParameters rate_dependent{{5e6, 0.3}, std::asin(0.38), 0, 0, InertialRheology{0.64, 0.279, 5e-4, 2450}};
  rate_dependent.dilatancy_angle = 5 * std::numbers::pi / 180;
  EXPECT_THROW(DruckerPragerLaw(1500, rate_dependent), std::invalid_argument);
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

// An in-plane isotropic strain of ln J = `log_volume` in one step of 1 ms (plane strain: the pressure
// changes by -K ln J while elastic).
KinematicIncrement isotropic_step(double log_volume) {
  const double dt = 1e-3;
  return KinematicIncrement::of_velocity_gradient(Mat2::Identity() * log_volume / (2 * dt), dt);
}

// Drives a point by isotropic_step(log_volume) from volume ratio J = exp(`from`).
void strain_isotropically(DruckerPragerLaw& law, double from, double log_volume, PointStress& s) {
  law.update(0, isotropic_step(log_volume), Mat2::Identity() * std::exp((from + log_volume) / 2), s);
}

TEST(DruckerPrager, ASeparatedPointCarriesNothingUntilPackedBackToTheVolumeItCameApartAt) {
  const Elasticity e{1e6, 0.3};
  DruckerPragerParameters sand{e, 30 * std::numbers::pi / 180, 0, 0, std::nullopt};
  sand.separation = true;
  DruckerPragerLaw separating(1500, sand), stiff_gas(1500, DruckerPragerParameters{e, sand.friction_angle, 0, 0, std::nullopt});
  for (DruckerPragerLaw* law : {&separating, &stiff_gas}) {
    PointStress s;
    law->add_point(s);
    // Packed to ln J = -0.01 (p = 0.01 K), then pulled apart to +0.02: its pressure reaches zero at J = 1.
    strain_isotropically(*law, 0, -0.01, s);
    EXPECT_NEAR(pressure_of(s), 0.01 * e.bulk_modulus(), 1e-6);
    for (int k = 0; k < 3; ++k) strain_isotropically(*law, -0.01 + 0.01 * k, 0.01, s);
    EXPECT_EQ(pressure_of(s), 0);
    strain_isotropically(*law, 0.02, -0.006, s);
    if (law == &stiff_gas) {
      EXPECT_NEAR(pressure_of(s), 0.006 * e.bulk_modulus(), 1e-6);  // pushes back at once
      continue;
    }
    // Apart, it carries nothing and its signal is that of the packed sand (M / ρ at J = 1).
    EXPECT_EQ(pressure_of(s), 0);
    EXPECT_NEAR(law->p_wave_modulus(0) / (1500 / std::exp(0.014)), e.p_wave_modulus() / 1500, 1e-9 * e.p_wave_modulus());
    strain_isotropically(*law, 0.014, -0.012, s);
    EXPECT_EQ(pressure_of(s), 0);
    // Packed back past J = 1 within the step: loaded by the 0.004 after contact only.
    strain_isotropically(*law, 0.002, -0.006, s);
    EXPECT_NEAR(pressure_of(s), 0.004 * e.bulk_modulus(), 1e-6);
    EXPECT_EQ(law->p_wave_modulus(0), e.p_wave_modulus());
  }
}

// One point of a separating sand (E = 1 MPa, ν = 0.3, φ = 30°, ρ0 = 1500 kg/m³), driven by
// isotropic_step, with F what the caller says it is.
struct SeparatingPoint {
  static DruckerPragerParameters sand(const Elasticity& e) {
    DruckerPragerParameters p{e, 30 * std::numbers::pi / 180, 0, 0, std::nullopt};
    p.separation = true;
    return p;
  }
  const Elasticity e{1e6, 0.3};
  DruckerPragerLaw law{1500, sand(e)};
  PointStress s;
  SeparatingPoint() { law.add_point(s); }
  void strain(double log_volume, const Mat2& F = Mat2::Identity()) { law.update(0, isotropic_step(log_volume), F, s); }
};

// A lone point at a front has no neighbour to constrain its motion, and its F can be sheared without
// bound until det F is round-off, of either sign (stop 73) or, after one wild step, far from what the
// step's strain says (stop 72). Its volume, the volume it packs back at and its signal speed must come
// from its motion, not from F.
TEST(DruckerPrager, ASeparatingPointCountsItsVolumeFromItsMotionNotFromF) {
  SeparatingPoint point;
  point.strain(0.01, Mat2::Identity() * 300);  // from zero stress: apart at J_s = 1, J = e^0.01 (det F: 9e4)
  EXPECT_EQ(pressure_of(point.s), 0);
  // c² = M_reported / ρ with ρ = ρ0 / J: the packed sand's M / ρ0.
  const double m = point.e.p_wave_modulus();
  EXPECT_NEAR(point.law.p_wave_modulus(0) * std::exp(0.01), m, 1e-9 * m);
  point.strain(-0.005, Mat2{{-1, 0}, {0, 1}});  // det F < 0: still apart at J = e^0.005
  EXPECT_EQ(pressure_of(point.s), 0);
  point.strain(-0.01, Mat2{{-1, 0}, {0, 1}});  // packed back past J_s = 1 by 0.005
  EXPECT_NEAR(pressure_of(point.s), 0.005 * point.e.bulk_modulus(), 1e-6 * point.e.bulk_modulus());
  EXPECT_TRUE(std::isfinite(point.s.in_plane.norm()));
}

// A point at rest comes apart from zero stress, so the volume it came apart at is its volume to the
// bit; the next step can bring it back to exactly that volume (the live twin's column at L0/h = 20
// stopped there: "increment: expected a positive time step").
TEST(DruckerPrager, APointBackAtExactlyTheVolumeItCameApartAtIsStillApart) {
  SeparatingPoint point;
  point.strain(1e-3);  // from zero stress at J = 1: apart, J_s = 1 exactly
  EXPECT_EQ(pressure_of(point.s), 0);
  ASSERT_EQ(std::exp(1e-3) * std::exp(-1e-3), 1.0) << "the case needs e^a e^-a = 1 to the bit";
  EXPECT_NO_THROW(point.strain(-1e-3));
  EXPECT_EQ(pressure_of(point.s), 0);
  EXPECT_EQ(point.law.p_wave_modulus(0), point.e.p_wave_modulus());
}

TEST(DruckerPrager, OnlyACohesionlessMaterialSeparates) {
  DruckerPragerParameters cohesive{{1e6, 0.3}, 0.5, 1000, 0, std::nullopt};
  cohesive.separation = true;
  EXPECT_THROW(DruckerPragerLaw(1000, cohesive), std::invalid_argument);
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

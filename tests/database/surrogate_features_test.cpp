// The state key and rate answer of the state-keyed surrogate (issue 13) on analytic states: values
// of textbook stress and loading states, invariance under a superposed rigid rotation about z, the
// tensile and resting conventions, and the Jaumann sign against a rigidly spinning body.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "dem_sampler/cell/matrix_functions.hpp"
#include "database/surrogate/rate_answer.hpp"
#include "database/surrogate/state_features.hpp"

namespace grainbank::surrogate {
namespace {

constexpr double kPi = std::numbers::pi;
const FeatureConstants kConstants{1000, 10, 3.7e-4, 920};

dem::Mat3 turn(double angle) { return Eigen::AngleAxisd(angle, dem::Vec3::UnitZ()).toRotationMatrix(); }

dem::Mat3 random_stress(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  dem::Mat3 s;
  s << -1000 + 400 * u(rng), 300 * u(rng), 5 * u(rng), 0, -1000 + 400 * u(rng), 5 * u(rng), 0, 0, -1000 + 400 * u(rng);
  s(1, 0) = s(0, 1), s(2, 0) = s(0, 2), s(2, 1) = s(1, 2);
  return s;
}

dem::Mat3 random_plane_gradient(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  dem::Mat3 L = dem::Mat3::Zero();
  L.topLeftCorner<2, 2>() << u(rng), u(rng), u(rng), u(rng);
  return L;
}

TEST(SurrogateFeatures, TextbookStatesAndLoadings) {
  // Triaxial compression (one principal stress more compressive): p = 200, q = 300, θ = π/3.
  const PointState compression{-dem::Vec3(100, 100, 400).asDiagonal().toDenseMatrix(), 0.6, 5, 0.1};
  dem::Mat3 L = dem::Mat3::Zero();
  L(0, 0) = L(1, 1) = -2;  // in-plane isotropic compression: tr D = -4, |dev D| = 2√6/3
  const StateFeatures f = state_features(compression, L, kConstants);
  EXPECT_NEAR(f.log_pressure, std::log(0.2), 1e-12);
  EXPECT_NEAR(f.eta, 1.5, 1e-12);
  EXPECT_NEAR(f.lode, kPi / 3, 1e-6);
  EXPECT_NEAR(f.psi, -std::atan(std::sqrt(6.0)), 1e-12);
  EXPECT_NEAR(f.inertial, std::sqrt(8.0) * 3.7e-4 * std::sqrt(920 / 200.0), 1e-15);
  EXPECT_EQ(f.solid_fraction, 0.6);
  EXPECT_EQ(f.coordination, 5);
  EXPECT_EQ(f.damage, 0.1);
  // Triaxial extension: θ = 0.
  EXPECT_NEAR(state_features({-dem::Vec3(400, 400, 100).asDiagonal().toDenseMatrix()}, L, kConstants).lode, 0, 1e-6);

  // σ's least compressive axis is x; stretching along y is a quarter turn from it, a simple shear
  // stretches along 45°; isochoric loadings have ψ = 0.
  const PointState biaxial{-dem::Vec3(100, 300, 200).asDiagonal().toDenseMatrix()};
  dem::Mat3 stretch_y = dem::Mat3::Zero();
  stretch_y(0, 0) = -1, stretch_y(1, 1) = 1;
  EXPECT_NEAR(std::abs(state_features(biaxial, stretch_y, kConstants).beta), kPi / 2, 1e-12);
  EXPECT_NEAR(state_features(biaxial, stretch_y, kConstants).psi, 0, 1e-12);
  dem::Mat3 shear = dem::Mat3::Zero();
  shear(0, 1) = 1;
  EXPECT_NEAR(state_features(biaxial, shear, kConstants).beta, kPi / 4, 1e-12);
  EXPECT_NEAR(state_features(biaxial, -shear, kConstants).beta, -kPi / 4, 1e-12);
}

TEST(SurrogateFeatures, InvariantUnderASuperposedRotation) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 200; ++trial) {
    const PointState before{random_stress(rng), 0.6, 5.5, 0.2};
    const PointState after{before.stress + 0.05 * random_stress(rng), 0.61, 5.4, 0.21};
    const dem::Mat3 L = random_plane_gradient(rng);
    const double angle = std::uniform_real_distribution<double>(-kPi, kPi)(rng);
    const dem::Mat3 Q = turn(angle);
    const auto rotated = [&](const PointState& s) { return PointState{Q * s.stress * Q.transpose(), s.solid_fraction, s.coordination, s.damage}; };
    const FeatureVector a = feature_vector(state_features(before, L, kConstants));
    const FeatureVector b = feature_vector(state_features(rotated(before), Q * L * Q.transpose(), kConstants));
    for (std::size_t j = 0; j < kFeatureCount; ++j) EXPECT_NEAR(a[j], b[j], 1e-9) << "feature " << j;
    const Answer x = rate_answer(before, after, L, 1e-3, kConstants);
    const Answer y = rate_answer(rotated(before), rotated(after), Q * L * Q.transpose(), 1e-3, kConstants);
    for (std::size_t j = 0; j < kAnswerSize; ++j) EXPECT_NEAR(x[j], y[j], 1e-6 * (1 + std::abs(x[j]))) << "answer " << j;
  }
}

// Above p_floor the pressure feature is ln(p/p_ref). Below it, where answers are all normalized by
// p_floor, it keeps falling, so a cell in tension has another key than one barely compressed: strictly
// monotone, continuous with a continuous slope (1/p_floor) at the floor, and finite in any tension.
TEST(SurrogateFeatures, ThePressureFeatureTellsTensionApart) {
  const double floor = kConstants.p_floor;
  EXPECT_NEAR(pressure_feature(250, kConstants), std::log(250 / kConstants.p_ref), 1e-12);
  EXPECT_NEAR(pressure_feature(floor, kConstants), std::log(floor / kConstants.p_ref), 1e-12);
  const double h = 1e-6 * floor;
  const double below = (pressure_feature(floor, kConstants) - pressure_feature(floor - h, kConstants)) / h;
  const double above = (pressure_feature(floor + h, kConstants) - pressure_feature(floor, kConstants)) / h;
  EXPECT_NEAR(below * floor, 1, 1e-5);
  EXPECT_NEAR(above * floor, 1, 1e-5);
  double previous = pressure_feature(2 * floor, kConstants);
  for (double below_floor = 0.5; below_floor < 1e6; below_floor *= 2) {  // p from 0.5 p_floor to −1e6 p_floor
    const double p = floor * (1 - below_floor);
    const double f = pressure_feature(p, kConstants);
    EXPECT_LT(f, previous) << "at p = " << p;
    EXPECT_TRUE(std::isfinite(f));
    previous = f;
  }
  for (const double p : {-1e3, 0.0, 5.0, 500.0})
    EXPECT_NEAR(effective_pressure_of_feature(pressure_feature(p, kConstants), kConstants), std::max(p, floor),
                1e-9 * std::max(p, floor));
}

TEST(SurrogateFeatures, TensionAndRestStayFinite) {
  dem::Mat3 L = dem::Mat3::Zero();
  L(0, 1) = 3;
  const PointState tensile{dem::Vec3(100, 50, 0).asDiagonal().toDenseMatrix()};
  const StateFeatures f = state_features(tensile, L, kConstants);
  EXPECT_LT(f.log_pressure, std::log(kConstants.p_floor / kConstants.p_ref));
  for (const double v : feature_vector(f)) EXPECT_TRUE(std::isfinite(v));
  const StateFeatures rest = state_features({-500 * dem::Mat3::Identity()}, dem::Mat3::Zero(), kConstants);
  EXPECT_EQ(rest.psi, 0);
  EXPECT_EQ(rest.beta, 0);
  EXPECT_EQ(rest.inertial, 0);
  for (const double v : feature_vector(rest)) EXPECT_TRUE(std::isfinite(v));
  const Answer a = rate_answer(tensile, PointState{2 * tensile.stress}, L, 1e-3, kConstants);
  for (const double v : a) EXPECT_TRUE(std::isfinite(v));
}

TEST(SurrogateFeatures, AStressCarriedByARigidSpinHasNoJaumannRate) {
  // A body turning counterclockwise, v = ω ẑ × x, carries its stress: σ(t) = R σ Rᵀ, R = exp(W t).
  // Its Jaumann rate vanishes; the opposite turn is a real change.
  const double omega = 50, dt = 2e-3;
  dem::Mat3 L = dem::Mat3::Zero();
  L(1, 0) = omega, L(0, 1) = -omega;
  L(0, 0) = 1e-3, L(1, 1) = -1e-3;  // a tiny stretching, so that the rate per |D| is defined
  const PointState before{-dem::Vec3(100, 300, 200).asDiagonal().toDenseMatrix()};
  const PointState carried{turn(omega * dt) * before.stress * turn(omega * dt).transpose()};
  const PointState against{turn(-omega * dt) * before.stress * turn(-omega * dt).transpose()};
  EXPECT_LT(stress_norm(rate_answer(before, carried, L, dt, kConstants)), 1e-6);
  EXPECT_GT(stress_norm(rate_answer(before, against, L, dt, kConstants)), 1e3);
  // A pure spin advances the stress by the same turn, keeping its invariants.
  L(0, 0) = L(1, 1) = 0;
  const PointState spun = advance(before, L, dt, Answer{}, kConstants);
  EXPECT_NEAR((spun.stress - carried.stress).norm(), 0, 1e-9);
}

TEST(SurrogateFeatures, AnAnswerAdvancesItsOwnIntervalExactly) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 50; ++trial) {
    dem::Mat3 s0 = random_stress(rng), s1 = s0 + 0.05 * random_stress(rng);
    s0(0, 2) = s0(2, 0) = s0(1, 2) = s0(2, 1) = 0;  // out-of-plane shears are not answered
    const dem::Mat3 L = random_plane_gradient(rng);
    const dem::Mat3 R = turn(0.5 * (L(1, 0) - L(0, 1)) * 1e-3);
    s1 = R * s1 * R.transpose();
    s1(0, 2) = s1(2, 0) = s1(1, 2) = s1(2, 1) = 0;
    const PointState before{s0, 0.6, 5, 0.1}, after{s1, 0.6 * std::exp(-L.trace() * 1e-3), 5.2, 0.12};
    const PointState next = advance(before, L, 1e-3, rate_answer(before, after, L, 1e-3, kConstants), kConstants);
    EXPECT_NEAR((next.stress - after.stress).norm(), 0, 1e-9 * after.stress.norm());
    EXPECT_NEAR(next.solid_fraction, after.solid_fraction, 1e-12);
    EXPECT_NEAR(next.coordination, after.coordination, 1e-12);
    EXPECT_NEAR(next.damage, after.damage, 1e-12);
  }
}

TEST(SurrogateFeatures, TheSolidFractionFollowsTheVolumeWhateverTheAnswer) {
  // Mass conservation: the spheres keep their volume, so φ V is constant and, over any number of
  // steps, φ = φ_0 / det F with F the product of the steps' exp(L Δt), whatever the answers say.
  std::mt19937 rng(5);
  PointState state{-300 * dem::Mat3::Identity(), 0.62, 6, 0};
  double det_F = 1;
  std::uniform_real_distribution<double> any(-50, 50);
  for (int step = 0; step < 200; ++step) {
    const dem::Mat3 L = random_plane_gradient(rng);
    Answer answer;
    for (double& a : answer) a = any(rng);
    state = advance(state, L, 1e-3, answer, kConstants);
    det_F *= dem::matrix_exponential(L * 1e-3).determinant();
  }
  EXPECT_NEAR(state.solid_fraction, 0.62 / det_F, 1e-12);
}

}  // namespace
}  // namespace grainbank::surrogate

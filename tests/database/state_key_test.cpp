// The state key: frame invariance, the Hencky strain of simple shear, scaling.
#include <gtest/gtest.h>

#include <cmath>

#include "tests/database/lookup_test_util.hpp"

namespace grainbank::lookup {
namespace {

using db::test::rotation_z;

dem::Mat3 some_F() {
  dem::Mat3 F = dem::Mat3::Identity();
  F(0, 0) = 1.03;
  F(0, 1) = 0.21;
  F(1, 0) = -0.04;
  F(1, 1) = 0.95;
  return F;
}

dem::Mat3 some_L() {
  dem::Mat3 L = dem::Mat3::Zero();
  L(0, 0) = 0.3;
  L(0, 1) = 2.0;
  L(1, 0) = -0.5;
  L(1, 1) = -0.1;
  return L;
}

TEST(StateKey, RigidRotationLeavesKeyUnchanged) {
  const db::KeyScales scales{1e-2, 0.5, 0.05};
  const db::StateKey key = state_key(some_F(), some_L(), 0.2, scales);
  for (double angle : {0.3, 1.7, -2.9}) {
    const dem::Mat3 Q = rotation_z(angle);
    // F → Q F, and the stretching of L → Q L Qᵀ (+ a spin, which has no symmetric part).
    dem::Mat3 spin = dem::Mat3::Zero();
    spin(0, 1) = 0.7;
    spin(1, 0) = -0.7;
    const db::StateKey rotated = state_key(Q * some_F(), Q * some_L() * Q.transpose() + spin, 0.2, scales);
    for (std::size_t c = 0; c < db::kKeySize; ++c) EXPECT_NEAR(rotated[c], key[c], 1e-11) << "component " << c;
  }
}

TEST(StateKey, SimpleShearMatchesAnalyticHencky) {
  const db::KeyScales scales{1.0, 1.0, 1.0};
  for (double gamma : {1e-3, 0.1, 0.8, 3.0}) {
    dem::Mat3 F = dem::Mat3::Identity();
    F(0, 1) = gamma;
    // Right Hencky strain of simple shear: asinh(γ/2)/sqrt(1+γ²/4) [[-γ/2, 1], [1, γ/2]].
    const double a = std::asinh(gamma / 2) / std::sqrt(1 + gamma * gamma / 4);
    const db::StateKey key = state_key(F, dem::Mat3::Zero(), 0, scales);
    EXPECT_NEAR(key[0], -a * gamma / 2, 1e-13 * (1 + gamma));
    EXPECT_NEAR(key[1], a * gamma / 2, 1e-13 * (1 + gamma));
    EXPECT_NEAR(key[2], a, 1e-13 * (1 + gamma));
    // Same as ½ ln(FᵀF) by the engine's matrix logarithm.
    const dem::Mat3 log_c = 0.5 * dem::matrix_logarithm(F.transpose() * F);
    EXPECT_NEAR(key[2], log_c(0, 1), 1e-12);
  }
}

TEST(StateKey, PolarDecompositionRecombinesAndRotatesStressBack) {
  const PolarDecomposition p = polar_decomposition(rotation_z(0.4) * some_F());
  EXPECT_LT((p.R * p.U - rotation_z(0.4) * some_F()).norm(), 1e-14);
  EXPECT_LT((p.R.transpose() * p.R - dem::Mat3::Identity()).norm(), 1e-14);
  EXPECT_NEAR(p.R.determinant(), 1.0, 1e-14);
  dem::Mat3 sigma;
  sigma << -3, 1, 0, 1, -2, 0, 0, 0, -1;
  EXPECT_LT((to_lab_frame(to_material_frame(sigma, p.R), p.R) - sigma).norm(), 1e-14);
}

TEST(StateKey, ComponentsAreDividedByTheirScales) {
  dem::Mat3 F = dem::Mat3::Identity();
  F(0, 0) = std::exp(0.02);
  dem::Mat3 L = dem::Mat3::Zero();
  L(1, 1) = -3.0;
  const db::StateKey key = state_key(F, L, 0.1, db::KeyScales{0.01, 1.5, 0.05});
  EXPECT_NEAR(key[0], 2.0, 1e-12);
  EXPECT_NEAR(key[4], -2.0, 1e-12);
  EXPECT_NEAR(key[6], 2.0, 1e-12);
  EXPECT_NEAR(inertial_rate_scale(1e-3, 1e4, 2500, 1e-3), 2.0, 1e-12);
  EXPECT_THROW(state_key(-dem::Mat3::Identity(), L, 0, {}), std::invalid_argument);
}

}  // namespace
}  // namespace grainbank::lookup

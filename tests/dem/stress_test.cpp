// Love-Weber stress (seed Eq. 2) of hand-built lattices against values derived by hand, with the
// tension-positive sign convention (compressed contacts: negative normal stress).
#include <gtest/gtest.h>

#include "tests/dem/dem_test_util.hpp"

namespace grainbank::dem::test {
namespace {

constexpr double kR = 0.5e-3;

struct Lattice {
  Mat3 h;
  std::vector<Vec3> x;
  std::vector<double> r;
};

// n × n × n spheres of radius kR on an orthorhombic lattice with spacings a (one sphere per site).
Lattice lattice(int n, const Vec3& a) {
  Lattice l;
  l.h = (n * a).asDiagonal();
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) {
        l.x.emplace_back((i + 0.5) * a.x(), (j + 0.5) * a.y(), (k + 0.5) * a.z());
        l.r.push_back(kR);
      }
  return l;
}

TEST(LoveWeberStress, SimpleCubicLatticeWithUniformOverlap) {
  // Spacing a = 2R - δ: every sphere has 6 contacts, N per axis direction, each carrying
  // f = w_c k_n δ along the axis with branch length a, in a volume N a³:
  //   σ_xx = σ_yy = σ_zz = -(N f a) / (N a³) = -w_c k_n δ / a²,   σ_ij = 0 (i ≠ j).
  for (double wc : {1.0, 0.5}) {
    Material mat = small_material();
    mat.contact.contact_weight = wc;
    const double delta = 1e-6, a = 2 * kR - delta;
    const int n = 4;
    const Lattice l = lattice(n, Vec3::Constant(a));
    const DemCell cell = DemCell::from_packing(l.h, l.x, l.r, mat, 0.05e-3);
    const Mat3 s = cell.measures().stress;
    const double expected = -wc * mat.contact.k_n * delta / (a * a);
    SCOPED_TRACE(wc);
    for (int i = 0; i < 3; ++i) {
      EXPECT_NEAR(s(i, i), expected, 1e-9 * std::abs(expected));
      for (int j = 0; j < 3; ++j)
        if (i != j) {
          EXPECT_NEAR(s(i, j), 0, 1e-12 * std::abs(expected));
        }
    }
    EXPECT_LT(s(0, 0), 0) << "compressed contacts give negative (compressive) normal stress";
    EXPECT_EQ(cell.contact_count(), 3u * n * n * n);
    EXPECT_DOUBLE_EQ(cell.measures().coordination, 6.0);
    // Solid fraction of a simple cubic array: (4/3 π R³) / a³.
    EXPECT_NEAR(cell.measures().solid_fraction, 4.0 / 3.0 * std::numbers::pi * kR * kR * kR / (a * a * a), 1e-12);
  }
}

TEST(LoveWeberStress, OrthorhombicLatticeWithDifferentOverlapsPerAxis) {
  // σ_xx = -k_n δ_x a_x / (a_x a_y a_z) = -k_n δ_x / (a_y a_z); no contacts along z (gap) => σ_zz = 0.
  const Material mat = small_material();
  const double dx = 2e-6, dy = 0.5e-6;
  const Vec3 a(2 * kR - dx, 2 * kR - dy, 2 * kR + 0.02e-3);
  const Lattice l = lattice(4, a);
  const DemCell cell = DemCell::from_packing(l.h, l.x, l.r, mat, 0.05e-3);
  const Mat3 s = cell.measures().stress;
  const double sxx = -mat.contact.k_n * dx / (a.y() * a.z()), syy = -mat.contact.k_n * dy / (a.x() * a.z());
  EXPECT_NEAR(s(0, 0), sxx, 1e-9 * std::abs(sxx));
  EXPECT_NEAR(s(1, 1), syy, 1e-9 * std::abs(syy));
  EXPECT_NEAR(s(2, 2), 0, 1e-12 * std::abs(sxx));
  EXPECT_EQ(cell.contact_count(), 2u * 64);
}

TEST(LoveWeberStress, StretchedBondedLatticeIsInTensionAndRegressionReturnsEndValue) {
  // Simple cubic lattice with gap g_0, every neighbour pair bonded (3N bonds, stress-free), then
  // stretched along x by ε: each x-bond carries T = w_b k_n ε a_x and
  //   σ_xx = +N T a_x' / (N a_x' a_y a_z) = T / (a_y a_z) > 0 (tension-positive), σ_yy = σ_zz = 0.
  // The lattice stays affine (forces balance on every sphere by symmetry). σ_xx grows (nearly)
  // linearly in time during the increment, so the regressed stress (seed Fig. 3) equals its end value.
  Material mat = small_material(true);
  mat.contact.restitution = 1;  // no dashpot on the bonds: static values during the ramp
  mat.bond.tensile_strength = 1e3;
  mat.bond.shear_strength = 1e3;
  const double g0 = 0.01e-3, a = 2 * kR + g0;
  const int n = 4;
  const Lattice l = lattice(n, Vec3::Constant(a));
  DemCell cell = DemCell::from_packing(l.h, l.x, l.r, mat, 0.05e-3);
  ASSERT_EQ(cell.create_bonds(mat.bond.bonding_distance), 3 * n * n * n);
  EXPECT_NEAR(cell.measures().stress.norm(), 0, 1e-9);

  for (double eps : {1e-3, -1e-3}) {
    DemCell c = cell;
    Mat3 f = Mat3::Identity();
    f(0, 0) = 1 + eps;
    Substepping q;
    q.q_n = 50;
    q.q_sigma = 0.5;
    const IncrementResult res = c.advance(f, 1e-4, q);
    const double tension = 0.5 * mat.contact.k_n * eps * a;
    const double sxx = tension / (a * a);
    const Mat3 s = c.measures().stress;
    SCOPED_TRACE(eps);
    EXPECT_NEAR(s(0, 0), sxx, 1e-6 * std::abs(sxx));
    EXPECT_NEAR(s(1, 1), 0, 1e-6 * std::abs(sxx));
    EXPECT_NEAR(s(2, 2), 0, 1e-6 * std::abs(sxx));
    EXPECT_NEAR(s(0, 1), 0, 1e-6 * std::abs(sxx));
    EXPECT_EQ(s(0, 0) > 0, eps > 0) << "stretched bonds: tension-positive stress";
    // The cell follows h(t) = exp(t log F / Δt) h0, so σ_xx is linear in time up to O(ε) relative
    // curvature: the regression over the last half returns the end value to ~ε/20.
    EXPECT_NEAR(res.stress(0, 0), sxx, 1e-4 * std::abs(sxx)) << "regression of a near-linear ramp must return its end value";
    EXPECT_EQ(c.measures().bonds, 3 * n * n * n);
  }
}

TEST(LoveWeberStress, SinglePairInSmallCellIsForceTimesBranchOverVolume) {
  // Two spheres pressed together along a general direction: σ = -(f ⊗ ℓ)/V with f = k_n δ n and
  // ℓ = (2R - δ) n, i.e. a uniaxial compressive stress along n of magnitude k_n δ (2R - δ) / V.
  const Material mat = small_material();
  const Vec3 n = Vec3(1, -2, 0.5).normalized();
  const double delta = 3e-6, side = 6e-3;
  const Vec3 c = Vec3::Constant(0.5 * side);
  const Vec3 l = (2 * kR - delta) * n;
  const DemCell cell = DemCell::from_packing(side * Mat3::Identity(), {c - 0.5 * l, c + 0.5 * l}, {kR, kR}, mat, 0.05e-3);
  const Mat3 expected = -mat.contact.k_n * delta * (2 * kR - delta) * n * n.transpose() / (side * side * side);
  EXPECT_LT(rel_diff(cell.measures().stress, expected), 1e-9);
}

}  // namespace
}  // namespace grainbank::dem::test

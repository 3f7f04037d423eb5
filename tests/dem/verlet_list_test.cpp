// The Verlet list holds exactly the pairs within range, whatever the shape and size of the cell: a
// dense cube, a sheared cell and a cell stretched to hundreds of interaction ranges (grains flying
// apart, where the bins are made wider than the range so that their number stays bounded), each
// against the brute force over every pair and every periodic image.
#include <gtest/gtest.h>

#include <random>
#include <set>
#include <tuple>

#include "dem_sampler/cell/periodic_cell.hpp"
#include "dem_sampler/cell/verlet_list.hpp"

namespace grainbank::dem {
namespace {

using PairSet = std::set<std::tuple<std::uint32_t, std::uint32_t, std::uint32_t>>;

PairSet brute_force(const Mat3& h, const std::vector<Vec3>& s, const std::vector<double>& radius, double skin) {
  PairSet out;
  for (std::uint32_t i = 0; i < s.size(); ++i)
    for (std::uint32_t j = i + 1; j < s.size(); ++j)
      for (int code = 0; code < kShiftCount; ++code) {
        const Vec3 l = h * (s[j] + shift_vector(code).cast<double>() - s[i]);
        const double range = radius[i] + radius[j] + skin;
        if (l.squaredNorm() < range * range) out.insert({i, j, static_cast<std::uint32_t>(code)});
      }
  return out;
}

void expect_exact_list(const Mat3& h, std::size_t n, double radius, double skin, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0, 1), size(0.8, 1.0);
  std::vector<Vec3> s(n);
  std::vector<double> r(n);
  double largest = 0;
  for (std::size_t i = 0; i < n; ++i) {
    s[i] = Vec3(unit(rng), unit(rng), unit(rng));
    r[i] = radius * size(rng);
    largest = std::max(largest, r[i]);
  }
  std::vector<Pair> pairs;
  VerletListBuilder().build(h, s, r, largest, skin, pairs);
  PairSet listed;
  for (const Pair& p : pairs) listed.insert({p.i, p.j, p.image});
  const PairSet truth = brute_force(h, s, r, skin);
  EXPECT_EQ(listed.size(), pairs.size()) << "a pair listed twice";
  EXPECT_EQ(listed, truth);
  EXPECT_FALSE(truth.empty()) << "the case must have pairs to find";
}

TEST(VerletList, DenseCubeHasExactlyThePairsInRange) {
  expect_exact_list(Mat3::Identity() * 10, 400, 0.5, 0.2, 1);
}

TEST(VerletList, ShearedCellHasExactlyThePairsInRange) {
  Mat3 h = Mat3::Identity() * 10;
  h(0, 1) = 4;  // leaning by 0.4 of a cell vector, below the flip threshold
  expect_exact_list(h, 400, 0.5, 0.2, 2);
}

TEST(VerletList, CellStretchedFarBeyondItsPackingHasExactlyThePairsInRange) {
  // 300 by 200 ranges in-plane for 1500 spheres: at one bin per range this would be 300 k bins.
  const Mat3 h = Vec3(360, 240, 6).asDiagonal();
  expect_exact_list(h, 1500, 0.5, 0.2, 3);
}

}  // namespace
}  // namespace grainbank::dem

// An obstacle's contact with a point's disk against the distance computed here from the shape alone:
// zero force where the disk stays clear, k_n × overlap along the outward normal where it overlaps by
// at most kMaxPenetration of its radius, and a PenetrationError beyond. Centres sweep a grid around
// the shape, its corners and the band just outside its bounding box included, so a shortcut that
// skipped a disk which does touch would fail here. The force acts where the disk meets the shape.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>

#include "mpm_solver/core/obstacle.hpp"

namespace grainbank::mpm {
namespace {

constexpr double kRadius = 0.1, kStiffness = 1e5;

// Distance from x to the segment a–b.
double segment_distance(const Vec2& x, const Vec2& a, const Vec2& b) {
  const Vec2 ab = b - a;
  const double s = std::clamp((x - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return (x - (a + s * ab)).norm();
}

// Expected force magnitude on a disk at distance d outside the shape (nullopt: a penetration).
std::optional<double> expected_force(double d, bool inside) {
  const double overlap = inside ? kRadius + d : kRadius - d;
  if (overlap <= 0) return 0.0;
  if (overlap > kMaxPenetration * kRadius) return std::nullopt;
  return kStiffness * overlap;
}

void sweep(Obstacle& obstacle, const Vec2& shift, double t, const auto& distance_and_inside) {
  int touching = 0, clear = 0, refused = 0;
  std::uint32_t id = 0;
  obstacle.reserve_points(200 * 200);
  for (int i = 0; i < 200; ++i)
    for (int j = 0; j < 200; ++j) {
      const Vec2 local(-0.35 + 1.7 * i / 199.0, -0.35 + 1.7 * j / 199.0);
      const auto [d, inside] = distance_and_inside(local);
      if (std::abs(d - kRadius) < 1e-9 || std::abs(d - 0.5 * kRadius) < 1e-9) continue;  // ties
      const std::optional<double> expected = expected_force(d, inside);
      const auto force = [&] {
        return obstacle.contact_force(id++, local + shift, [](const Vec2&) { return Vec2(0, 0); }, kRadius, 1.0, t, 1e-4);
      };
      if (!expected) {
        EXPECT_THROW(force(), PenetrationError) << "centre " << local.transpose();
        ++refused;
        continue;
      }
      const AppliedForce applied = force();
      const double magnitude = applied.force.norm();
      EXPECT_NEAR(magnitude, *expected, 1e-9 * kStiffness) << "centre " << local.transpose() << ", distance " << d;
      // A touching disk is pushed where it meets the shape's surface.
      if (magnitude > 0) {
        EXPECT_NEAR(distance_and_inside(applied.at - shift).first, 0.0, 1e-9) << "centre " << local.transpose();
      }
      ++(magnitude > 0 ? touching : clear);
    }
  // The sweep reaches every case.
  EXPECT_GT(touching, 100);
  EXPECT_GT(clear, 100);
  EXPECT_GT(refused, 100);
}

TEST(Obstacle, AClosedSquareTouchesExactlyTheDisksThatOverlapIt) {
  const Vec2 corners[] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  Obstacle square(Polyline{{corners[0], corners[1], corners[2], corners[3]}, true}, ContactParameters{kStiffness, 0, 0, 0});
  sweep(square, Vec2::Zero(), 0.0, [&](const Vec2& x) {
    double d = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 4; ++k) d = std::min(d, segment_distance(x, corners[k], corners[(k + 1) % 4]));
    const bool inside = x.x() > 0 && x.x() < 1 && x.y() > 0 && x.y() < 1;
    return std::pair{d, inside};
  });
}

TEST(Obstacle, AMovingLineTouchesExactlyTheDisksThatOverlapItWhereItIsNow) {
  // An open segment has a flat bounding box; it moves by (0.3, −0.2) m/s for 2 s.
  const Vec2 a(0, 0.5), b(1, 0.5), velocity(0.3, -0.2);
  const double t = 2;
  Obstacle line(Polyline{{a, b}, false}, ContactParameters{kStiffness, 0, 0, 0}, velocity);
  sweep(line, velocity * t, t, [&](const Vec2& x) { return std::pair{segment_distance(x, a, b), false}; });
}

TEST(Obstacle, LettingGoItCapsEachPointsForceAtAFallingShareOfWhatItHeld) {
  // A floor let go of over [1, 3] s, a disk resting on it with `held` of overlap.
  Obstacle floor(Polyline{{Vec2(-1, 0), Vec2(1, 0)}, false}, ContactParameters{kStiffness, 0, 0, 0}, Vec2::Zero(),
                 ObstacleRelease{1, 3});
  floor.reserve_points(2);
  const auto force_at = [&](std::uint32_t id, double overlap, double t) {
    return floor
        .contact_force(id, Vec2(0, kRadius - overlap), [](const Vec2&) { return Vec2(0, 0); }, kRadius, 1.0, t, 1e-4)
        .force.y();
  };
  const double held = 0.2 * kRadius, deep = 0.8 * kRadius;
  EXPECT_NEAR(force_at(0, held, 0.5), kStiffness * held, 1e-9 * kStiffness);
  // Held before the start, a disk pressed that deep is an error.
  EXPECT_THROW(force_at(0, deep, 0.5), PenetrationError);
  // At the start the point holds what it had; pressed further, it gets no more than s(t) of that.
  EXPECT_NEAR(force_at(0, held, 1), kStiffness * held, 1e-9 * kStiffness);
  EXPECT_NEAR(force_at(0, 2 * held, 2), 0.5 * kStiffness * held, 1e-9 * kStiffness);
  EXPECT_NEAR(force_at(0, 2 * held, 2.9), 0.05 * kStiffness * held, 1e-9 * kStiffness);
  // Backed off, it gets its spring's force, below the cap.
  EXPECT_NEAR(force_at(0, 0.01 * kRadius, 2), 0.01 * kStiffness * kRadius, 1e-9 * kStiffness);
  // Let go of, a disk pressed past the limit passes.
  EXPECT_EQ(force_at(0, deep, 2), 0.0);
  // A point clear of it at the start is not held afterwards.
  EXPECT_EQ(force_at(1, 0.0, 1.5), 0.0);
  EXPECT_EQ(force_at(1, held, 2), 0.0);
  EXPECT_TRUE(floor.active(2.999));
  EXPECT_FALSE(floor.active(3));
  // A sudden removal holds fully until it goes.
  Obstacle gate(Polyline{{Vec2(-1, 0), Vec2(1, 0)}, false}, ContactParameters{kStiffness, 0, 0, 0}, Vec2::Zero(),
                ObstacleRelease::at(1));
  gate.reserve_points(1);
  EXPECT_NEAR(gate.contact_force(0, Vec2(0, kRadius - held), [](const Vec2&) { return Vec2(0, 0); }, kRadius, 1.0,
                                 0.999, 1e-4).force.y(), kStiffness * held, 1e-9 * kStiffness);
  EXPECT_FALSE(gate.active(1));
  EXPECT_THROW(Obstacle(Polyline{{Vec2(-1, 0), Vec2(1, 0)}, false}, ContactParameters{kStiffness, 0, 0, 0},
                        Vec2::Zero(), ObstacleRelease{2, 1}),
               std::invalid_argument);
}

}  // namespace
}  // namespace grainbank::mpm

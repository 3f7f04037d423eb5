// The step the solver takes is the minimum of its criteria: CFL from the law's moduli, the contact
// springs of active obstacles, and the law's own limit.
#include <gtest/gtest.h>

#include <cmath>

#include "tests/mpm/mpm_test_util.hpp"

namespace grainbank::mpm {
namespace {

TEST(TimeStep, IsTheMinimumOfTheCriteria) {
  const double h = 0.1, rho = 1000, young = 1e6;
  Solver solver = testing::elastic_solver(Grid(Vec2(0, 0), h, 10, 10), rho, young, 0.0);
  seed_region(solver, 0, rectangle(Vec2(0.2, 0.2), Vec2(0.6, 0.6)), 2, Vec2(3, 4));
  const double wave = 0.3 * h / (std::sqrt(young / rho) + 5);
  EXPECT_NEAR(solver.time_step_limits().wave, wave, 1e-15);
  EXPECT_NEAR(solver.stable_time_step(), wave, 1e-15);

  // A stiff obstacle takes over while it exists; a removed one no longer counts.
  const double k = 1e9, mass = rho * 0.05 * 0.05;
  solver.add_obstacle(Obstacle(Polyline{{Vec2(0, 0.1), Vec2(1, 0.1)}, false}, ContactParameters{k, 0, 0, 0}, Vec2::Zero(),
                               ObstacleRelease::at(0.5)));
  EXPECT_NEAR(solver.time_step_limits().contact, 0.2 * std::sqrt(mass / k), 1e-15);
  EXPECT_NEAR(solver.stable_time_step(), 0.2 * std::sqrt(mass / k), 1e-15);

  SolverSettings capped;
  capped.max_time_step = 1e-6;
  Solver small(Grid(Vec2(0, 0), h, 10, 10), capped);
  small.add_law(std::make_unique<ElasticLaw>(rho, Elasticity{young, 0.0}));
  seed_region(small, 0, rectangle(Vec2(0.2, 0.2), Vec2(0.6, 0.6)), 2);
  EXPECT_EQ(small.stable_time_step(), 1e-6);
}

TEST(TimeStep, RemovedObstacleNoLongerLimits) {
  Solver solver = testing::elastic_solver(Grid(Vec2(0, 0), 0.1, 10, 10), 1000, 1e6, 0.0);
  seed_region(solver, 0, rectangle(Vec2(0.2, 0.2), Vec2(0.6, 0.6)), 2);
  solver.add_obstacle(Obstacle(Polyline{{Vec2(0, 0.1), Vec2(1, 0.1)}, false}, ContactParameters{1e9, 0, 0, 0},
                               Vec2::Zero(), ObstacleRelease::at(1e-6)));
  const double before = solver.stable_time_step();
  solver.step(before);
  solver.step(solver.stable_time_step());
  EXPECT_TRUE(std::isinf(solver.time_step_limits().contact));
  EXPECT_GT(solver.stable_time_step(), 10 * before);
}

}  // namespace
}  // namespace grainbank::mpm

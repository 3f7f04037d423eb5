// Regeneration: a fresh cell replacing a worn one carries the worn cell's deformation gradient, its
// damage to one bond, and a stress it can carry within the servo's tolerance, which it then holds at
// rest; the bonds that break first are the most tensile ones.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "dem_sampler/cell/periodic_cell.hpp"
#include "dem_sampler/cell/regeneration.hpp"
#include "dem_sampler/cell/snow_preset.hpp"
#include "tests/dem/dem_test_util.hpp"

namespace grainbank::dem {
namespace {

const DemCell& snow_template() {
  static const DemCell cell = prepare_cell(snow_material(), snow_preparation(30, 5));
  return cell;
}

// The template flattened in plane strain (x stretched, y squeezed) until it has lost bonds.
DemCell worn_cell() {
  DemCell cell = snow_template();
  Mat3 step = Mat3::Identity();
  step(0, 0) = std::exp(2e-3);
  step(1, 1) = std::exp(-2e-3);
  for (int k = 0; k < 100; ++k) cell.advance(step, 2e-4, Substepping{});
  return cell;
}

Mat3 symmetric_part(const Mat3& m) { return 0.5 * (m + m.transpose()); }

double normal_traction(const CellState& st, std::size_t k, const Mat3& stress) {
  const Pair& p = st.pairs[k];
  const Vec3 n = (st.h * (st.reduced_position[p.j] + shift_vector(static_cast<int>(p.image)).cast<double>() -
                          st.reduced_position[p.i]))
                     .normalized();
  return n.dot(stress * n);
}

// The template squeezed isotropically, then sheared a little: a stress several times the template's,
// mostly isotropic, which a fresh cell of the same packing can carry.
DemCell loaded_cell() {
  DemCell cell = snow_template();
  for (int k = 0; k < 20; ++k) cell.advance(std::exp(-2e-4) * Mat3::Identity(), 2e-4, Substepping{});
  for (int k = 0; k < 20; ++k) cell.advance(test::simple_shear(2e-4), 2e-4, Substepping{});
  return cell;
}

// The stress servo's tolerance for regenerating `worn`, as regenerate() sets it.
double servo_tolerance(const DemCell& worn, const RegenerationSettings& settings) {
  return settings.tolerance_fraction *
         std::max(symmetric_part(worn.stress()).cwiseAbs().maxCoeff(),
                  settings.scale_floor * symmetric_part(snow_template().stress()).cwiseAbs().maxCoeff());
}

TEST(Regeneration, AFreshCellTakesOverTheWornCellsDeformationAndDamage) {
  const DemCell worn = worn_cell();
  const CellMeasures w = worn.measures();
  const CellMeasures t = snow_template().measures();
  ASSERT_GT(w.damage, 0.05) << "the flattening must have broken bonds";
  ASSERT_GT(t.bonds, 0);

  RegenerationSettings settings;
  const Regeneration r = regenerate(worn, snow_template().state(), settings);
  const DemCell& cell = r.cell;
  std::printf("worn: D = %.3f, σ_xx %.1f σ_yy %.1f σ_zz %.1f Pa; servo %ld steps, residual %.1f Pa, %lld bonds broken\n",
              w.damage, worn.stress()(0, 0), worn.stress()(1, 1), worn.stress()(2, 2), r.servo.steps,
              r.servo.residual, static_cast<long long>(r.bonds_broken));

  EXPECT_EQ(cell.size(), snow_template().size());
  EXPECT_LT((cell.deformation_gradient() - worn.deformation_gradient()).norm(), 1e-12);
  EXPECT_GT(cell.time(), worn.time()) << "the clock goes on through the servo";
  // Seed Eq. 6 on the fresh cell's own N_b(0): the kept bonds are (1 − D) N_b(0), rounded.
  const double initial = static_cast<double>(t.bonds) / (1 - t.damage);
  EXPECT_EQ(t.bonds - r.bonds_broken, std::llround((1 - w.damage) * initial));
  EXPECT_GE(cell.measures().damage, w.damage - 0.5 / initial);
  // A flattened 30-sphere cell carries an anisotropic stress through the fabric it grew, which a
  // fresh packing may not carry (over template seeds 5-8 and 60 or 100 increments, the servo met
  // the tolerance in half the cases): the outcome must say which.
  EXPECT_EQ(r.servo.converged, r.servo.residual <= servo_tolerance(worn, settings));
}

TEST(Regeneration, AFreshCellTakesOverAStressItCanCarryAndHoldsIt) {
  const DemCell worn = loaded_cell();
  const Mat3 target = symmetric_part(worn.stress());
  ASSERT_GT(pressure_of(target), 2 * pressure_of(symmetric_part(snow_template().stress())))
      << "test design: the target is well above the template's stress";
  RegenerationSettings settings;
  const Regeneration r = regenerate(worn, snow_template().state(), settings);
  std::printf("loaded: σ_xx %.1f σ_yy %.1f σ_zz %.1f σ_xy %.1f Pa; servo %ld steps, residual %.1f Pa\n", target(0, 0),
              target(1, 1), target(2, 2), target(0, 1), r.servo.steps, r.servo.residual);
  // Converged within the tolerance, then held at rest (the windowed mean, as the servo judges it)
  // within twice that.
  ASSERT_TRUE(r.servo.converged);
  const double tolerance = servo_tolerance(worn, settings);
  EXPECT_LE(r.servo.residual, tolerance);
  DemCell held = r.cell;
  Mat3 mean = Mat3::Zero();
  const int steps = 200;
  for (int k = 0; k < steps; ++k) {
    held.step_with_velocity_gradient(Mat3::Zero(), held.time_step(settings.q_t));
    mean += symmetric_part(held.stress()) / steps;
  }
  EXPECT_LE((mean - target).cwiseAbs().maxCoeff(), 2 * tolerance) << "mean\n" << mean << "\ntarget\n" << target;
}

TEST(Regeneration, TheMostTensileBondsBreakFirst) {
  CellState st = snow_template().state();
  Mat3 tension = Mat3::Zero();
  tension(0, 0) = 1000;  // uniaxial tension along x: bonds along x carry it
  const auto intact = std::count_if(st.bonds.begin(), st.bonds.end(), [](const Bond& b) { return b.intact(); });
  const std::int64_t keep = intact / 2;
  const CellState before = st;
  EXPECT_EQ(break_most_tensile_bonds(st, tension, keep), intact - keep);
  double weakest_broken = 1e300, strongest_kept = -1e300, broken_sum = 0;
  for (std::size_t k = 0; k < st.bonds.size(); ++k) {
    if (!before.bonds[k].intact()) continue;
    const double traction = normal_traction(st, k, tension);
    if (st.bonds[k].intact()) {
      strongest_kept = std::max(strongest_kept, traction);
    } else {
      weakest_broken = std::min(weakest_broken, traction);
      broken_sum += traction;
    }
  }
  EXPECT_GE(weakest_broken, strongest_kept);
  // Over isotropic bonds the mean of n_x² is 1/3; the broken half leans toward x.
  EXPECT_GT(broken_sum / static_cast<double>(intact - keep), 1000.0 / 3);
  // Asking to keep more than are intact breaks nothing.
  EXPECT_EQ(break_most_tensile_bonds(st, tension, intact), 0);
}

TEST(Regeneration, BadSettingsAreRefused) {
  const DemCell worn = snow_template();
  RegenerationSettings s;
  s.tolerance_fraction = 0;
  EXPECT_THROW(regenerate(worn, worn.state(), s), std::invalid_argument);
  s = RegenerationSettings{};
  s.max_servo_steps = 0;
  EXPECT_THROW(regenerate(worn, worn.state(), s), std::invalid_argument);
  s = RegenerationSettings{};
  s.q_t = 1.01 * max_time_step_factor(worn.material().contact.restitution);  // beyond what its dashpots allow
  EXPECT_THROW(regenerate(worn, worn.state(), s), std::invalid_argument);
}

}  // namespace
}  // namespace grainbank::dem

// Elastic-brittle bond (seed Fig. 1, "omitting bond damage"): stiffness w_b k_n, w_b k_t, yield
// surface Φ = T/T_0 + (S/S_0)^p - 1, force jump at breakage, contact friction afterwards.
//
// The spheres are made very heavy (the bond law does not involve masses) so that their initial
// velocities prescribe the relative motion: the loading is then a known, constant-rate path and
// the bond force is read from CellState.force of the spheres (a single pair: force[1] = -force[0]).
#include <gtest/gtest.h>

#include <set>

#include "dem_sampler/cell/preparation.hpp"
#include "dem_sampler/cell/snow_preset.hpp"
#include "tests/dem/dem_test_util.hpp"

namespace grainbank::dem::test {
namespace {

constexpr double kR = 0.5e-3;          // both radii
constexpr double kCell = 20e-3;
constexpr double kSkin = 0.1e-3;
constexpr double kHeavy = 2650e9;      // density making the spheres kinematically driven

Material bond_material() {
  Material m = small_material(true);   // w_c = w_b = 1/2, T_0 = 0.5 N, S_0 = 0.25 N, p = 2, ε = 0.05
  m.density = kHeavy;
  m.contact.restitution = 1;           // no dashpot: the pair force is purely elastic (and frictional)
  return m;
}

struct Sample {
  bool intact = false;
  double gap = 0;
  double tension = 0, shear = 0;      // bond part of the pair force
  double contact_normal = 0;          // f_n of the contact part (0 when apart)
  Vec3 contact_tangential = Vec3::Zero(), force = Vec3::Zero(), n = Vec3::Zero();
  Bond bond;
};

// Two spheres along x at centre distance 2R + gap0, bonded, then moved apart along `dir` (unit)
// at relative speed `speed` for `steps` steps of `dt`.
class BondedPair {
 public:
  BondedPair(const Material& mat, double gap0, const Vec3& dir, double speed)
      : mat_(mat),
        cell_(fresh_state(kCell * Mat3::Identity(),
                          {Vec3(0.5 * kCell - kR - 0.5 * gap0, 0.5 * kCell, 0.5 * kCell),
                           Vec3(0.5 * kCell + kR + 0.5 * gap0, 0.5 * kCell, 0.5 * kCell)},
                          {kR, kR}, {-0.5 * speed * dir, 0.5 * speed * dir}),
              mat, kSkin) {
    bonds_ = cell_.create_bonds(mat.bond.bonding_distance);
  }
  std::int64_t bonds() const { return bonds_; }
  DemCell& cell() { return cell_; }

  Sample step(double dt) {
    cell_.step_with_velocity_gradient(Mat3::Zero(), dt);
    return sample();
  }
  Sample sample() const {
    const CellState st = cell_.state();
    const std::vector<Vec3> x = cell_.positions();
    Sample s;
    const Vec3 l = x[1] - x[0];
    s.n = l.normalized();
    s.gap = l.norm() - 2 * kR;
    s.force = st.force[1];
    EXPECT_EQ(st.force[0], -st.force[1]);
    const double kn_c = mat_.contact.contact_weight * mat_.contact.k_n;
    s.contact_normal = s.gap < 0 ? -kn_c * s.gap : 0;
    // Pair list: only (0, 1) can be listed in this large cell.
    const Pair* pair = nullptr;
    for (std::size_t k = 0; k < st.pairs.size(); ++k)
      if (st.pairs[k].i == 0 && st.pairs[k].j == 1) {
        pair = &st.pairs[k];
        s.bond = st.bonds[k];
      }
    s.intact = pair && s.bond.intact();
    s.contact_tangential = pair && s.gap < 0 ? pair->ft : Vec3::Zero();
    const double fn = s.force.dot(s.n);
    const Vec3 ft = s.force - fn * s.n;
    s.tension = -(fn - s.contact_normal);            // bond pulls j back towards i when stretched
    s.shear = (ft - s.contact_tangential).norm();
    return s;
  }

 private:
  Material mat_;
  DemCell cell_;
  std::int64_t bonds_ = 0;
};

double yield(const Material& m, double tension, double shear) {
  return tension / m.bond.tensile_strength + std::pow(shear / m.bond.shear_strength, m.bond.exponent) - 1;
}

struct BreakRecord {
  long break_step = -1;
  Sample last_intact, previous_intact, at_break;
  double relative_displacement_at_break = 0;
  std::vector<Sample> after;
};

// Loads the bond until it breaks; checks Φ < 0 at every intact step on the way.
BreakRecord load_to_failure(const Material& mat, double gap0, const Vec3& dir, double speed, double dt,
                            long after_steps = 200) {
  BondedPair pair(mat, gap0, dir, speed);
  EXPECT_EQ(pair.bonds(), 1);
  BreakRecord rec;
  Sample prev = pair.sample(), prev2 = prev;
  EXPECT_TRUE(prev.intact);
  for (long k = 1; k < 1'000'000; ++k) {
    const Sample s = pair.step(dt);
    if (!s.intact) {
      rec.break_step = k;
      rec.at_break = s;
      rec.last_intact = prev;
      rec.previous_intact = prev2;
      rec.relative_displacement_at_break = speed * dt * static_cast<double>(k);
      break;
    }
    const double phi = yield(mat, s.tension, s.shear);
    if (!(phi < 0)) {
      ADD_FAILURE() << "intact bond outside its yield surface: Φ = " << phi << " at step " << k;
      return rec;
    }
    prev2 = prev;
    prev = s;
  }
  for (long k = 0; k < after_steps; ++k) rec.after.push_back(pair.step(dt));
  return rec;
}

// Common checks of a breakage: the last intact force sits on the yield surface to within one load
// increment, the trial state that broke the bond is outside it, and the bond carries nothing after.
void check_breakage(const Material& mat, const BreakRecord& rec) {
  ASSERT_GT(rec.break_step, 10) << "the bond never broke, or broke at once";
  const double phi_last = yield(mat, rec.last_intact.tension, rec.last_intact.shear);
  const double phi_prev = yield(mat, rec.previous_intact.tension, rec.previous_intact.shear);
  const double increment = phi_last - phi_prev;
  ASSERT_GT(increment, 0) << "the load should increase monotonically";
  EXPECT_LT(phi_last, 0);
  EXPECT_GT(phi_last, -1.5 * increment) << "bond broke before reaching its yield surface";
  EXPECT_LT(increment, 1e-3) << "load increment too coarse for this test";
  // The trial forces of the breaking step (kept in the bond's history) are on or outside the surface.
  const Bond& b = rec.at_break.bond;
  EXPECT_FALSE(b.intact());
  const double kn_b = (1 - mat.contact.contact_weight) * mat.contact.k_n;
  const double kt_b = (1 - mat.contact.contact_weight) * mat.contact.k_t;
  const double trial = yield(mat, kn_b * (rec.at_break.gap - b.rest_gap), kt_b * b.shear_displacement.norm());
  EXPECT_GE(trial, -1e-9);
  EXPECT_LT(trial, phi_last + 2 * increment);
}

TEST(Bond, StiffnessIsBondWeightTimesKnAndKt) {
  // Small stretch and slide below the yield surface: T = w_b k_n (d_n - g_0), S = w_b k_t u_t.
  const Material mat = bond_material();
  const double gap0 = 0.01e-3;
  const Vec3 dir = Vec3(1, 1, 0).normalized();
  BondedPair pair(mat, gap0, dir, 0.01);
  const Sample s0 = pair.sample();
  EXPECT_NEAR(s0.tension, 0, 1e-12) << "a bond is stress-free at creation";
  EXPECT_NEAR(s0.shear, 0, 1e-12);
  Sample s;
  const double dt = 1e-7;
  const int steps = 2000;  // relative displacement 2 µm along dir
  for (int k = 0; k < steps; ++k) s = pair.step(dt);
  ASSERT_TRUE(s.intact);
  const double u = 0.01 * dt * steps;
  const double kn_b = 0.5 * mat.contact.k_n, kt_b = 0.5 * mat.contact.k_t;
  EXPECT_NEAR(s.tension, kn_b * (s.gap - gap0), 1e-9 * kn_b * u);
  EXPECT_NEAR(s.gap - gap0, u * dir.x(), 1e-3 * u);  // second-order geometric terms only
  EXPECT_NEAR(s.shear, kt_b * u * dir.y(), 2e-3 * kt_b * u);
}

TEST(Bond, BreaksInPureTensionOnYieldSurface) {
  const Material mat = bond_material();
  const double speed = 0.01, dt = 1e-7;  // 1 nm per step; T_0 is reached after 10 µm
  const BreakRecord rec = load_to_failure(mat, 0.01e-3, Vec3::UnitX(), speed, dt);
  check_breakage(mat, rec);
  // Pure tension: T_0 = w_b k_n δ*, so the bond fails at δ* = T_0 / (w_b k_n).
  const double stretch_at_failure = mat.bond.tensile_strength / (0.5 * mat.contact.k_n);
  EXPECT_NEAR(rec.relative_displacement_at_break, stretch_at_failure, 2 * speed * dt);
  EXPECT_NEAR(rec.last_intact.tension, mat.bond.tensile_strength, 1e-3 * mat.bond.tensile_strength);
  EXPECT_LT(rec.last_intact.shear, 1e-9 * mat.bond.shear_strength);
  // Apart and unbonded: no force at all, ever after.
  for (const Sample& s : rec.after) EXPECT_EQ(s.force, Vec3::Zero());
}

TEST(Bond, BreaksInPureShearOnYieldSurface) {
  const Material mat = bond_material();
  const double speed = 0.01, dt = 1e-7;
  const BreakRecord rec = load_to_failure(mat, 0.01e-3, Vec3::UnitY(), speed, dt);
  check_breakage(mat, rec);
  // Tangential sliding: S_0 = w_b k_t u*, and the tension stays second order (u²/2ℓ).
  const double slide_at_failure = mat.bond.shear_strength / (0.5 * mat.contact.k_t);
  EXPECT_NEAR(rec.relative_displacement_at_break, slide_at_failure, 0.01 * slide_at_failure);
  EXPECT_NEAR(rec.last_intact.shear, mat.bond.shear_strength, 0.01 * mat.bond.shear_strength);
  EXPECT_LT(rec.last_intact.tension, 0.01 * mat.bond.tensile_strength);
  for (const Sample& s : rec.after) EXPECT_EQ(s.force, Vec3::Zero());
}

TEST(Bond, BreaksUnderCombinedLoadingOnYieldSurface) {
  // Relative motion at angle θ to the bond axis: T = w_b k_n u cos θ, S = w_b k_t u sin θ, so
  // Φ = 0 at the positive root of (w_b k_t sin θ / S_0)² u² + (w_b k_n cos θ / T_0) u - 1 = 0.
  const Material mat = bond_material();
  for (double theta_deg : {30.0, 60.0, 80.0}) {
    const double theta = theta_deg * std::numbers::pi / 180;
    const Vec3 dir(std::cos(theta), 0, std::sin(theta));
    const double speed = 0.01, dt = 1e-7;
    const BreakRecord rec = load_to_failure(mat, 0.01e-3, dir, speed, dt);
    SCOPED_TRACE(theta_deg);
    check_breakage(mat, rec);
    const double a = std::pow(0.5 * mat.contact.k_t * std::sin(theta) / mat.bond.shear_strength, 2);
    const double b = 0.5 * mat.contact.k_n * std::cos(theta) / mat.bond.tensile_strength;
    const double u_star = (-b + std::sqrt(b * b + 4 * a)) / (2 * a);
    EXPECT_NEAR(rec.relative_displacement_at_break, u_star, 0.01 * u_star);
    // Both modes carry load at failure: neither a tension-only nor a shear-only failure.
    EXPECT_GT(rec.last_intact.tension, 0.05 * mat.bond.tensile_strength);
    EXPECT_GT(rec.last_intact.shear, 0.05 * mat.bond.shear_strength);
    for (const Sample& s : rec.after) EXPECT_EQ(s.force, Vec3::Zero());
  }
}

TEST(Bond, ExponentOfYieldFunctionIsHonoured) {
  // p = 1 makes the surface linear: pure shear then fails at S = S_0 as well, but a 45° path fails
  // where T/T_0 + S/S_0 = 1.
  Material mat = bond_material();
  mat.bond.exponent = 1;
  const double theta = std::numbers::pi / 4;
  const Vec3 dir(std::cos(theta), std::sin(theta), 0);
  const double speed = 0.01, dt = 1e-7;
  const BreakRecord rec = load_to_failure(mat, 0.01e-3, dir, speed, dt);
  check_breakage(mat, rec);
  const double u_star = 1 / (0.5 * mat.contact.k_n * std::cos(theta) / mat.bond.tensile_strength +
                             0.5 * mat.contact.k_t * std::sin(theta) / mat.bond.shear_strength);
  EXPECT_NEAR(rec.relative_displacement_at_break, u_star, 0.01 * u_star);
}

TEST(Bond, OnlyCappedContactFrictionRemainsAfterShearFailureOfOverlappingPair) {
  // Bonded while overlapping by 20 µm, then slid sideways: the bond fails in shear; the pair still
  // overlaps, so the contact alone acts: f_n = w_c k_n |d_n| and |f_t| <= μ f_n, reaching μ f_n
  // (sliding) and opposing the relative motion.
  const Material mat = bond_material();
  const double gap0 = -20e-6, speed = 0.01, dt = 1e-7;
  const BreakRecord rec = load_to_failure(mat, gap0, Vec3::UnitY(), speed, dt, 15000);
  check_breakage(mat, rec);
  const double kn_c = mat.contact.contact_weight * mat.contact.k_n;
  ASSERT_FALSE(rec.after.empty());
  for (const Sample& s : rec.after) {
    ASSERT_LT(s.gap, 0) << "the pair should still overlap";
    const double fn = s.force.dot(s.n);
    const Vec3 ft = s.force - fn * s.n;
    EXPECT_NEAR(fn, -kn_c * s.gap, 1e-9 * kn_c * -gap0) << "normal force must be the contact spring alone";
    EXPECT_LE(ft.norm(), mat.contact.friction * fn * (1 + 1e-12)) << "Coulomb cap violated";
    EXPECT_NEAR(s.tension, 0, 1e-12);
    EXPECT_NEAR(s.shear, 0, 1e-12);
  }
  const Sample& last = rec.after.back();
  const double fn = last.force.dot(last.n);
  const Vec3 ft = last.force - fn * last.n;
  EXPECT_NEAR(ft.norm(), mat.contact.friction * fn, 1e-9 * fn) << "sliding contact should sit on the Coulomb cap";
  EXPECT_LT(ft.dot(Vec3::UnitY()), 0) << "friction on sphere 1 must oppose its motion (+y)";
}

TEST(Bond, StretchedBondOutsideVerletRangeKeepsItsForceAndNeighbourHistory) {
  // An intact bond stretched beyond the Verlet range must stay listed and keep pulling, and the
  // list rebuild that keeps it must not disturb the history of the other pairs.
  // Spheres: 0 and 1 bonded along x and pulled apart (bond made unbreakable); 2 bonded to 1 and
  // touching it along y, sliding (friction on its cap); 3 at rest, entering 1's Verlet range.
  Material mat = bond_material();
  mat.bond.tensile_strength = 1e6;
  mat.bond.shear_strength = 1e6;
  const double v = 0.05, d = 2 * kR;
  const Vec3 c = Vec3::Constant(0.5 * kCell);
  const std::vector<Vec3> x = {c + Vec3(-(d + 0.01e-3), 0, 0), c, c + Vec3(0, d - 5e-6, 0), c + Vec3(d + 0.13e-3, 0, 0)};
  const std::vector<Vec3> vel = {Vec3(-v, 0, 0), Vec3(v, 0, 0), Vec3::Zero(), Vec3::Zero()};
  DemCell cell(fresh_state(kCell * Mat3::Identity(), x, {kR, kR, kR, kR}, vel), mat, kSkin);
  ASSERT_EQ(cell.create_bonds(mat.bond.bonding_distance), 2);
  const double dt = 1e-7;  // 5 nm per step for spheres 0 and 1; the rebuild comes after ~50 µm
  const long builds0 = cell.list_builds();
  CellState before = cell.state();
  bool rebuilt = false;
  for (int k = 0; k < 15000; ++k) {
    cell.step_with_velocity_gradient(Mat3::Zero(), dt);
    const CellState st = cell.state();
    // Sphere 2 only touches sphere 1: its force changes smoothly (≈ k Δx per step).
    const double jump = (st.force[2] - before.force[2]).norm();
    EXPECT_LT(jump, 1e-3 * std::max(st.force[2].norm(), 1e-3))
        << "force on sphere 2 jumps at step " << k << " (list builds " << cell.list_builds() << ")";
    // Sphere 0 only feels the 0-1 bond: T = w_b k_n (d_n - g_0) along the pair axis.
    const std::vector<Vec3> pos = cell.positions();
    const double gap01 = (pos[1] - pos[0]).norm() - d;
    EXPECT_NEAR(st.force[0].x(), 0.5 * mat.contact.k_n * (gap01 - 0.01e-3), 1e-6)
        << "bond 0-1 lost at step " << k;
    if (cell.list_builds() > builds0 && !rebuilt) {
      rebuilt = true;
      EXPECT_GT(gap01, kSkin) << "test design: the bonded pair should be outside the Verlet range at the rebuild";
      // No duplicate (i, j) in the list, and the bonded pair is still there.
      std::set<std::pair<std::uint32_t, std::uint32_t>> seen;
      for (const Pair& p : st.pairs) EXPECT_TRUE(seen.insert({p.i, p.j}).second) << "duplicate pair " << p.i << "-" << p.j;
      EXPECT_TRUE(seen.count({0u, 1u}));
      EXPECT_TRUE(seen.count({1u, 3u}));
    }
    before = st;
    if (::testing::Test::HasFailure()) break;
  }
  EXPECT_TRUE(rebuilt) << "test design: the Verlet list should have been rebuilt";
  EXPECT_EQ(cell.measures().bonds, 2);
}

// Softening bond (BondLaw::softening ρ, the crack band's; interaction_law.hpp softening_integrity).
// Pure tension along x at 1 nm per step: δ_y = T_0/(w_b k_n) = 10 µm.
Material softening_material(double rho) {
  Material m = bond_material();
  m.bond.softening = rho;
  return m;
}

double yield_stretch(const Material& m) { return m.bond.tensile_strength / ((1 - m.contact.contact_weight) * m.contact.k_n); }

// The bond's tension on the linear-softening envelope at stretch δ: elastic to T_0 at δ_y, then
// falling linearly to zero at (1 + ρ) δ_y.
double envelope(const Material& m, double stretch) {
  const double dy = yield_stretch(m), rho = m.bond.softening;
  if (stretch <= dy) return m.bond.tensile_strength * stretch / dy;
  return std::max(m.bond.tensile_strength * (1 - (stretch / dy - 1) / rho), 0.0);
}

TEST(SofteningBond, FollowsTheLinearEnvelopeAndDissipatesOnePlusRhoTimesTheElasticEnergy) {
  const double rho = 2, gap0 = 0.01e-3, dt = 1e-7;
  const Material mat = softening_material(rho);
  const double dy = yield_stretch(mat), t0 = mat.bond.tensile_strength;
  BondedPair pair(mat, gap0, Vec3::UnitX(), 0.01);
  Sample previous = pair.sample();
  double work = 0, largest_miss = 0;
  bool broke = false;
  for (int k = 0; k < 35000; ++k) {
    const Sample s = pair.step(dt);
    const double stretch = s.gap - gap0;
    largest_miss = std::max(largest_miss, std::abs(s.tension - envelope(mat, stretch)));
    work += 0.5 * (s.tension + previous.tension) * (s.gap - previous.gap);
    if (stretch > (1 + rho) * dy * 1.001) {
      EXPECT_FALSE(s.intact) << "a bond stretched past (1 + ρ) δ_y carries nothing";
      broke = true;
    } else if (stretch > dy * 1.001 && stretch < (1 + rho) * dy * 0.999) {
      EXPECT_TRUE(s.intact) << "a softening bond is not broken at δ/δ_y = " << stretch / dy;
    }
    previous = s;
  }
  EXPECT_TRUE(broke);
  EXPECT_LT(largest_miss, 2e-3 * t0) << "tension off the linear-softening envelope";
  // The triangle's area: ½ T_0 δ_y (1 + ρ).
  EXPECT_NEAR(work, 0.5 * t0 * dy * (1 + rho), 5e-3 * 0.5 * t0 * dy * (1 + rho));
}

TEST(SofteningBond, UnloadsAndReloadsAlongItsSecantWithoutFurtherDamage) {
  const double rho = 2, gap0 = 0.01e-3, dt = 1e-7, speed = 0.01;
  const Material mat = softening_material(rho);
  const double dy = yield_stretch(mat), kn_b = (1 - mat.contact.contact_weight) * mat.contact.k_n;
  BondedPair pair(mat, gap0, Vec3::UnitX(), speed);
  Sample s;
  for (int k = 0; k < 20000; ++k) s = pair.step(dt);  // to δ = 2 δ_y: w = (1 - 1/ρ)/2 = 1/4
  const double w = (1 - (2.0 - 1) / rho) / 2;
  ASSERT_NEAR(s.gap - gap0, 2 * dy, 1e-3 * dy);
  EXPECT_NEAR(s.bond.integrity, w, 1e-3);
  // Reverse the pair and close it to δ = δ_y / 2, then open it again to 2 δ_y: a damaged spring of
  // stiffness w k_b both ways, its integrity unchanged.
  const auto run_with_velocity = [&](const CellState& from, double v, int steps) {
    CellState st = from;
    st.velocity = {Vec3(-0.5 * v, 0, 0), Vec3(0.5 * v, 0, 0)};
    DemCell cell(st, mat, kSkin);
    double largest_miss = 0;
    for (int k = 0; k < steps; ++k) {
      cell.step_with_velocity_gradient(Mat3::Zero(), dt);
      const std::vector<Vec3> x = cell.positions();
      const double stretch = (x[1] - x[0]).norm() - 2 * kR - gap0;
      largest_miss = std::max(largest_miss, std::abs(cell.state().force[0].x() - w * kn_b * stretch));
    }
    EXPECT_LT(largest_miss, 2e-3 * w * mat.bond.tensile_strength) << "off the secant";
    EXPECT_NEAR(cell.state().bonds.at(0).integrity, w, 1e-3);
    return cell.state();
  };
  const CellState closed = run_with_velocity(pair.cell().state(), -speed, 15000);
  const CellState reopened = run_with_velocity(closed, speed, 15000);
  // Past 2 δ_y it softens again along the envelope.
  DemCell cell(reopened, mat, kSkin);
  for (int k = 0; k < 2000; ++k) cell.step_with_velocity_gradient(Mat3::Zero(), dt);
  const std::vector<Vec3> x = cell.positions();
  const double stretch = (x[1] - x[0]).norm() - 2 * kR - gap0;
  EXPECT_NEAR(cell.state().force[0].x(), envelope(mat, stretch), 2e-3 * mat.bond.tensile_strength);
  EXPECT_LT(cell.state().bonds.at(0).integrity, w);
}

TEST(SofteningBond, NeedsTheQuadraticYieldSurface) {
  Material mat = softening_material(1);
  mat.bond.exponent = 3;
  EXPECT_THROW(check(mat), std::invalid_argument);
  mat = softening_material(-1);
  EXPECT_THROW(check(mat), std::invalid_argument);
}

// A bonded cell pulled apart along x (y and z held) to `strain` at a rate of 1/s, with bond softening
// ρ. Returns {peak σ_xx [Pa], work per unit volume [J/m³]}.
std::pair<double, double> pull_apart(const DemCell& prepared, double rho, double strain) {
  Material m = prepared.material();
  m.bond.softening = rho;
  DemCell cell(prepared.state(), m, prepared.skin());
  const int increments = 400;
  const double rate = 1.0, duration = strain / rate / increments;
  Mat3 increment = Mat3::Identity();
  increment(0, 0) = std::exp(rate * duration);
  double peak = 0, work = 0, previous = cell.stress()(0, 0);
  for (int k = 0; k < increments; ++k) {
    const double sxx = cell.advance(increment, duration, Substepping{0.1, 1, 0.2}).stress(0, 0);
    peak = std::max(peak, sxx);
    work += 0.5 * (sxx + previous) * rate * duration;
    previous = sxx;
  }
  return {peak, work};
}

TEST(SofteningBond, ACellIsTheBrittleCellUntilABondYieldsAndThenTakesMoreWorkToPullApart) {
  const DemCell prepared = prepare_cell(snow_material(), snow_preparation(60, 3));
  // Below the first bond's yield the two cells are one elastic packing.
  const auto [brittle_elastic_peak, brittle_elastic_work] = pull_apart(prepared, 0, 2e-4);
  const auto [soft_elastic_peak, soft_elastic_work] = pull_apart(prepared, 4, 2e-4);
  EXPECT_EQ(soft_elastic_peak, brittle_elastic_peak);
  EXPECT_EQ(soft_elastic_work, brittle_elastic_work);
  // Past it, each softening bond still carries what a brittle one has dropped.
  const auto [brittle_peak, brittle_work] = pull_apart(prepared, 0, 0.01);
  const auto [soft_peak, soft_work] = pull_apart(prepared, 4, 0.01);
  std::printf("to 1 %% strain: peak %.0f / %.0f Pa, work %.1f / %.1f J/m3 (brittle / rho = 4)\n", brittle_peak,
              soft_peak, brittle_work, soft_work);
  EXPECT_GT(soft_work, brittle_work);
  EXPECT_GE(soft_peak, brittle_peak);
}

}  // namespace
}  // namespace grainbank::dem::test

// The vectorized force loop evaluates every branch of the interaction law for every pair and keeps
// what applies by masks (dem_cell_forces.cpp). This test sets up isolated pairs in every branch
// (contact below and at the Coulomb cap, a lost contact with stale history, bonds that hold, break in
// this step or are already broken, in contact or apart) and checks each pair's force, torques and
// history after one step against the law written out here pair by pair from seed Fig. 1, with
// explicit branches. Enough pairs that the loop runs its vector body, not only its remainder.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <tuple>

#include "dem_sampler/cell/periodic_cell.hpp"
#include "tests/dem/dem_test_util.hpp"

namespace grainbank::dem {
namespace {

enum class Case { kContact, kContactAtCap, kLostContact, kBondHolds, kBondApartHolds, kBondBreaks, kBondApartBreaks,
                  kBrokenBondInContact, kPulledApartContact };
constexpr Case kCases[] = {Case::kContact,      Case::kContactAtCap,     Case::kLostContact,
                           Case::kBondHolds,    Case::kBondApartHolds,   Case::kBondBreaks,
                           Case::kBondApartBreaks, Case::kBrokenBondInContact, Case::kPulledApartContact};

struct PairSetup {
  Vec3 xi, xj, ui, uj, wi, wj;
  double ri, rj;
  Pair pair;
  Bond bond;
};

Vec3 random_unit(std::mt19937_64& rng) {
  std::normal_distribution<double> g;
  return Vec3(g(rng), g(rng), g(rng)).normalized();
}

PairSetup make_pair(Case c, const Vec3& centre, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> uni(-1, 1);
  PairSetup s;
  s.ri = 0.5e-3 * (1 + 0.1 * uni(rng));
  s.rj = 0.5e-3 * (1 + 0.1 * uni(rng));
  const double rsum = s.ri + s.rj;
  const bool apart = c == Case::kLostContact || c == Case::kBondApartHolds || c == Case::kBondApartBreaks;
  const double gap = (apart ? 0.004 : -0.01) * rsum;
  const Vec3 n = random_unit(rng);
  s.xi = centre;
  s.xj = centre + (rsum + gap) * n;
  s.ui = 1e-3 * random_unit(rng);
  s.uj = 1e-3 * random_unit(rng);
  // A pair pulled apart fast enough that its dashpot outweighs the spring: f_n < 0, no friction.
  if (c == Case::kPulledApartContact) s.uj = s.ui + 0.5 * n;
  s.wi = random_unit(rng);
  s.wj = random_unit(rng);
  s.pair.damping = c == Case::kPulledApartContact ? 2.0 : 0.01;  // 2.0 × 0.5 m/s = 1 N > w_c k_n overlap
  // Friction history: small (below μ f_n ≈ 0.25 N), or far above the cap.
  s.pair.ft = (c == Case::kContactAtCap || c == Case::kBrokenBondInContact ? 2.0 : 0.05) * random_unit(rng);
  const bool bonded = c == Case::kBondHolds || c == Case::kBondApartHolds || c == Case::kBondBreaks ||
                      c == Case::kBondApartBreaks || c == Case::kBrokenBondInContact;
  if (bonded) {
    const bool breaks = c == Case::kBondBreaks || c == Case::kBondApartBreaks;
    s.bond.integrity = c != Case::kBrokenBondInContact ? 1.0 : 0.0;
    s.bond.rest_gap = gap - 1e-6;  // a little tension: T = w_b k_n · 1e-6 = 0.05 N
    // u_b: shear force w_b k_t |u_b| of 0.05 N (holds) or 0.5 N = 2 S_0 (breaks).
    s.bond.shear_displacement = (breaks ? 2e-5 : 2e-6) * random_unit(rng);
  }
  return s;
}

struct Expected {
  Vec3 force_on_j, torque_i, torque_j, ft;
  Bond bond;
  bool interacting = false;
};

Vec3 turned(const Vec3& t, const Vec3& n, double twist) { return t + twist * n.cross(t) - t.dot(n) * n; }

// Seed Fig. 1, written pair by pair with branches: the contact in parallel with the bond.
Expected expected_law(const Material& m, const PairSetup& s, const Vec3& xi, const Vec3& xj, double dt) {
  const double wc = m.contact.contact_weight, wb = 1 - wc;
  const Vec3 l = xj - xi;
  const double r = l.norm(), rsum = s.ri + s.rj, gap = r - rsum;
  const Vec3 n = l / r;
  const double arm_i = s.ri + gap / 2, arm_j = s.rj + gap / 2;
  const Vec3 v = s.uj - s.ui - (arm_i * s.wi + arm_j * s.wj).cross(n);
  const double vn = v.dot(n);
  const Vec3 slip = (v - vn * n) * dt;
  const double twist = dt / 2 * (s.wi + s.wj).dot(n);
  Expected e;
  e.bond = s.bond;
  double fn = 0;
  Vec3 ft = Vec3::Zero();
  e.ft = Vec3::Zero();
  const bool touching = gap < 0;
  if (touching) {
    const double fn_contact = -wc * m.contact.k_n * gap - s.pair.damping * vn;
    e.ft = turned(s.pair.ft, n, twist) - wc * m.contact.k_t * slip;
    const double cap = m.contact.friction * std::max(fn_contact, 0.0);
    if (e.ft.norm() > cap) e.ft *= cap / e.ft.norm();
    fn = fn_contact;
    ft = e.ft;
    e.interacting = true;
  }
  if (s.bond.intact()) {
    e.bond.shear_displacement = turned(s.bond.shear_displacement, n, twist) + slip;
    const double tension = wb * m.contact.k_n * (gap - s.bond.rest_gap);
    const double shear = wb * m.contact.k_t * e.bond.shear_displacement.norm();
    const double yield =
        tension / m.bond.tensile_strength + std::pow(shear / m.bond.shear_strength, m.bond.exponent) - 1;
    if (yield < 0) {
      fn -= tension;
      if (!touching) fn -= s.pair.damping * vn;
      ft -= wb * m.contact.k_t * e.bond.shear_displacement;
      e.interacting = true;
    } else {
      e.bond.integrity = 0;
    }
  }
  e.force_on_j = fn * n + ft;
  e.torque_i = -arm_i * n.cross(ft);
  e.torque_j = -arm_j * n.cross(ft);
  return e;
}

void check_every_branch(double exponent) {
  Material m = test::small_material(true);
  m.bond.exponent = exponent;
  std::mt19937_64 rng(7);
  const double side = 0.05, spacing = 0.01;  // pairs 1 cm apart: no pair meets another
  std::vector<PairSetup> setups;
  for (int copy = 0; copy < 3; ++copy)
    for (Case c : kCases) {
      const int k = static_cast<int>(setups.size());
      setups.push_back(make_pair(c, spacing * Vec3(0.5 + k % 4, 0.5 + (k / 4) % 4, 0.5 + k / 16), rng));
    }
  ASSERT_GE(setups.size(), 16u) << "test design: the vector body of the loop must run";

  const Mat3 h = side * Mat3::Identity();
  CellState st;
  st.h = st.h_reference = st.h_at_list_build = h;
  std::int64_t intact = 0;
  for (const PairSetup& s : setups) {
    const auto i = static_cast<std::uint32_t>(st.radius.size());
    for (const auto& [x, u, w, r] : {std::tuple{s.xi, s.ui, s.wi, s.ri}, std::tuple{s.xj, s.uj, s.wj, s.rj}}) {
      st.radius.push_back(r);
      st.reduced_position.push_back(h.inverse() * x);
      st.velocity.push_back(u);
      st.angular_velocity.push_back(w);
    }
    Pair p = s.pair;
    p.i = i;
    p.j = i + 1;
    p.image = kNoShift;
    st.pairs.push_back(p);
    st.bonds.push_back(s.bond);
    intact += s.bond.intact() ? 1 : 0;
  }
  // No force at the start and L = 0: the first half kick leaves every velocity as set, so the loop
  // sees the velocities above at the positions after the drift.
  st.force.assign(st.radius.size(), Vec3::Zero());
  st.torque.assign(st.radius.size(), Vec3::Zero());
  st.reduced_position_at_list_build = st.reduced_position;
  st.initial_bond_count = intact;
  DemCell cell(st, m, 1e-4);
  const double dt = 1e-6;
  cell.step_with_velocity_gradient(Mat3::Zero(), dt);
  const CellState after = cell.state();
  ASSERT_EQ(after.pairs.size(), setups.size()) << "test design: the list is not rebuilt";

  Mat3 love_weber = Mat3::Zero();
  std::int64_t interacting = 0;
  for (std::size_t k = 0; k < setups.size(); ++k) {
    const std::uint32_t i = 2 * static_cast<std::uint32_t>(k), j = i + 1;
    const Vec3 xi = h * after.reduced_position[i], xj = h * after.reduced_position[j];
    const Expected e = expected_law(m, setups[k], xi, xj, dt);
    const double scale = 1e-12;  // N and N·m: the forces are of order 0.1-1 N
    SCOPED_TRACE("pair " + std::to_string(k) + ", case " + std::to_string(k % std::size(kCases)));
    EXPECT_LT((after.force[j] - e.force_on_j).norm(), scale);
    EXPECT_LT((after.force[i] + e.force_on_j).norm(), scale);
    EXPECT_LT((after.torque[i] - e.torque_i).norm(), scale * 1e-3);
    EXPECT_LT((after.torque[j] - e.torque_j).norm(), scale * 1e-3);
    EXPECT_LT((after.pairs[k].ft - e.ft).norm(), scale);
    EXPECT_EQ(after.bonds[k].integrity, e.bond.integrity);
    EXPECT_LT((after.bonds[k].shear_displacement - e.bond.shear_displacement).norm(), 1e-18);
    love_weber += e.force_on_j * (xj - xi).transpose();
    interacting += e.interacting ? 1 : 0;
  }
  EXPECT_EQ(cell.interacting_pairs(), interacting);
  EXPECT_LT((cell.stress() + love_weber / cell.volume()).norm(), 1e-9 * (love_weber / cell.volume()).norm());
  // Every branch was met: some pairs carry force, some do not, some bonds broke in this step.
  EXPECT_GT(interacting, 0);
  EXPECT_LT(interacting, static_cast<std::int64_t>(setups.size()));
  EXPECT_LT(cell.measures().bonds, intact);
}

TEST(ForceKernel, EveryBranchOfTheMaskedLoopIsTheLaw) { check_every_branch(2); }

// Another bond exponent takes the loop's general power (not vectorized): the same law.
TEST(ForceKernel, EveryBranchIsTheLawWithACubicBondYield) { check_every_branch(3); }

}  // namespace
}  // namespace grainbank::dem

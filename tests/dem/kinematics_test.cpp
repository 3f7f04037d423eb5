// Cell kinematics: affine motion under a velocity gradient (ḣ = L h), exact macroscopic increments
// (seed Eq. 3 sub-stepping without overshoot), and objectivity of the stress under rigid rotation.
#include <gtest/gtest.h>

#include <utility>

#include <unsupported/Eigen/MatrixFunctions>

#include "tests/dem/dem_test_util.hpp"

namespace grainbank::dem::test {
namespace {

// A dilute gas of tiny spheres on a 3×3×3 grid in a 10 mm cube: no contacts for the whole test.
DemCell dilute_gas(const Material& mat, const std::vector<Vec3>& v = {}) {
  const double side = 10e-3;
  std::vector<Vec3> x;
  std::vector<double> r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) {
        x.emplace_back((i + 0.3 + 0.1 * j) * side / 3, (j + 0.4 + 0.1 * k) * side / 3, (k + 0.5 - 0.1 * i) * side / 3);
        r.push_back(0.05e-3 + 0.001e-3 * (i + j + k));
      }
  return DemCell(fresh_state(side * Mat3::Identity(), x, r, v), mat, 0.02e-3);
}

const Mat3 kL = (Mat3() << 0.3, 0.5, 0.0,  //
                 -0.2, -0.1, 0.4,            //
                 0.1, 0.0, -0.2).finished();   // [1/s], general (stretch + spin), tr L = 0

// Distance between two points modulo the lattice of h.
double periodic_distance(const Mat3& h, const Vec3& a, const Vec3& b) {
  Vec3 ds = h.inverse() * (a - b);
  for (int k = 0; k < 3; ++k) ds[k] -= std::round(ds[k]);
  return (h * ds).norm();
}

// Relative error of h(t) against exp(L t) h0 after integrating to t with step dt.
double cell_error(double dt, double t_end, std::vector<double>* position_errors = nullptr) {
  DemCell gas = dilute_gas(small_material());
  const std::vector<Vec3> x0 = gas.positions();
  const long steps = std::lround(t_end / dt);
  for (long k = 0; k < steps; ++k) gas.step_with_velocity_gradient(kL, dt);
  EXPECT_EQ(gas.contact_count(), 0u);
  const Mat3 expm = (kL * t_end).exp();
  const Mat3 f = gas.deformation_gradient();
  if (position_errors) {
    const std::vector<Vec3> x = gas.positions();
    for (std::size_t p = 0; p < x.size(); ++p)
      position_errors->push_back(periodic_distance(gas.cell_matrix(), x[p], expm * x0[p]) / x0[p].norm());
  }
  // The cell may have been re-expressed in a reduced basis; F = h h_ref⁻¹ does not depend on it.
  return (f - expm).norm() / expm.norm();
}

TEST(AffineMotion, CellFollowsExponentialOfVelocityGradient) {
  // ḣ = L h  =>  h(t) = exp(L t) h0; the explicit update converges to it at first order in dt.
  const double t_end = 0.5;
  std::vector<double> xerr;
  const double e1 = cell_error(2e-4, t_end, &xerr);
  const double e2 = cell_error(1e-4, t_end);
  EXPECT_LT(e1, 1e-4);
  EXPECT_GT(e1, 1e-12) << "suspiciously exact";
  EXPECT_NEAR(e1 / e2, 2.0, 0.2) << "first-order convergence to exp(L t) h0 expected";
  // Spheres without fluctuation velocity ride on the affine field: x(t) = exp(L t) x0.
  for (double e : xerr) EXPECT_LT(e, 2e-4);
}

TEST(AffineMotion, MeanPositionOfMovingGasFollowsAffineField) {
  // With zero total fluctuation momentum (Σ m v' = 0) the mass-weighted mean of the fluctuation
  // displacements stays zero: mean x(t) = exp(L t) mean x0 (each sphere unwrapped).
  const Material mat = small_material();
  std::vector<Vec3> v;
  for (int p = 0; p < 27; ++p) v.emplace_back(1e-3 * std::sin(1.3 * p), 1e-3 * std::cos(0.7 * p), 1e-3 * std::sin(2.1 * p + 1));
  // Zero total momentum.
  DemCell probe = dilute_gas(mat, v);
  Vec3 mom = Vec3::Zero();
  double mass = 0;
  for (std::size_t p = 0; p < 27; ++p) {
    const double m = sphere_mass(mat, probe.radii()[p]);
    mom += m * v[p];
    mass += m;
  }
  for (Vec3& vp : v) vp -= mom / mass;
  DemCell gas = dilute_gas(mat, v);
  const std::vector<Vec3> x0 = gas.positions();
  const double dt = 1e-4, t_end = 0.3;
  const long steps = std::lround(t_end / dt);
  for (long k = 0; k < steps; ++k) gas.step_with_velocity_gradient(kL, dt);
  ASSERT_EQ(gas.contact_count(), 0u);
  const Mat3 expm = (kL * t_end).exp();
  const Mat3 h = gas.cell_matrix();
  const std::vector<Vec3> x = gas.positions();
  // Unwrap each sphere to the image nearest to its affine position, then average with masses.
  Vec3 mean_disp = Vec3::Zero(), mean_x0 = Vec3::Zero();
  for (std::size_t p = 0; p < x.size(); ++p) {
    Vec3 ds = h.inverse() * (x[p] - expm * x0[p]);
    for (int k = 0; k < 3; ++k) ds[k] -= std::round(ds[k]);
    const double m = sphere_mass(mat, gas.radii()[p]);
    mean_disp += m * (h * ds) / mass;
    mean_x0 += m * x0[p] / mass;
  }
  EXPECT_LT(mean_disp.norm(), 1e-3 * mean_x0.norm()) << "mean position must follow exp(L t) mean x0";
  // Fluctuations without forces (dem_cell.hpp): m dv'/dt = -m Lᵀ v' = -m (D - W) v'
  //   =>  v'(t) = exp(-Lᵀ t) v'(0): stretching exchanges energy, spin only turns them with the cell.
  const Mat3 decay = (-kL.transpose() * t_end).exp();
  for (std::size_t p = 0; p < x.size(); ++p)
    EXPECT_LT((gas.velocities()[p] - decay * v[p]).norm(), 2e-3 * v[p].norm()) << "sphere " << p;
}

TEST(ExactIncrements, AdvanceReachesIncrementTimesInitialCell) {
  // After advance(F, Δt, q) the cell matrix is F h0 to round-off, whatever the number of sub-steps,
  // with stretch and rotation; F = h h_ref⁻¹ accumulates multiplicatively; time advances by Δt.
  DemCell gas = dilute_gas(small_material());
  const Mat3 h_ref = gas.cell_matrix();
  const Mat3 f1 = (Mat3() << 1.002, 0.001, 0, -0.0005, 0.999, 0.0003, 0, 0.0002, 1.0004).finished();
  const Mat3 f2 = rotation_z(0.3) * Eigen::AngleAxisd(-0.2, Vec3(1, 1, 0).normalized()).toRotationMatrix() *
                  (Mat3() << 1.001, 0, 0, 0, 0.9995, 0, 0, 0, 1).finished();
  Substepping q;
  q.q_n = 7;
  Mat3 f_total = Mat3::Identity();
  for (const Mat3& f : {f1, f2, f1, f2}) {
    const Mat3 h0 = gas.cell_matrix();
    const double t0 = gas.time();
    const double duration = 7.77e-5;
    const IncrementResult res = gas.advance(f, duration, q);
    f_total = f * f_total;
    ASSERT_EQ(gas.flips(), 0);
    EXPECT_LT((gas.cell_matrix() - f * h0).cwiseAbs().maxCoeff(), 1e-13 * h0.norm());
    EXPECT_LT((gas.deformation_gradient() - f_total).cwiseAbs().maxCoeff(), 1e-13);
    EXPECT_LT((gas.cell_matrix() - f_total * h_ref).cwiseAbs().maxCoeff(), 1e-13 * h_ref.norm());
    EXPECT_NEAR(gas.time() - t0, duration, 1e-12 * duration) << "the cell must receive exactly Δt (no overshoot)";
    EXPECT_EQ(res.substeps, substep_count(duration, gas.time_step(q.q_t), q.q_n));
    EXPECT_GE(res.substeps, q.q_n);
    EXPECT_LE(res.substep, gas.time_step(q.q_t) * (1 + 1e-12));
    EXPECT_NEAR(res.substep * static_cast<double>(res.substeps), duration, 4e-16 * duration);
  }
}

TEST(ExactIncrements, AdvanceThroughAFlipKeepsDeformationGradient) {
  // A shear increment carrying the tilt past 1/2 flips the basis inside advance(): the cell matrix is
  // then F h0 M with M integer unimodular, and F = h h_ref⁻¹ is unchanged by the flip.
  DemCell gas = dilute_gas(small_material());
  const Mat3 h0 = gas.cell_matrix();
  Mat3 f = Mat3::Identity();
  f(0, 1) = 0.8;
  Substepping q;
  q.q_n = 40;
  gas.advance(f, 1e-3, q);
  ASSERT_GT(gas.flips(), 0);
  EXPECT_LT((gas.deformation_gradient() - f).cwiseAbs().maxCoeff(), 1e-13);
  const Mat3 m = (f * h0).inverse() * gas.cell_matrix();
  EXPECT_LT((m - m.array().round().matrix()).cwiseAbs().maxCoeff(), 1e-12) << "basis change must be integer:\n" << m;
  EXPECT_NEAR(std::abs(m.determinant()), 1.0, 1e-12);
  EXPECT_FALSE(needs_reduction(gas.cell_matrix()));
}

TEST(Substepping, CountIsMinimalExactAndAtLeastQn) {
  // n = max(ceil(Δt/δt), Q_n): n steps of Δt/n add up to Δt, never exceed δt, and n is minimal.
  for (double dem_step : {1e-6, 3.7e-7, 8.4e-7})
    for (double ratio : {0.3, 1.0, 2.5, 10.0, 99.999, 100.0, 100.001, 1234.5})
      for (int q_n : {0, 1, 10, 100}) {
        const double duration = ratio * dem_step;
        const long n = substep_count(duration, dem_step, q_n);
        SCOPED_TRACE(testing::Message() << "Δt/δt = " << ratio << " Q_n = " << q_n);
        EXPECT_GE(n, std::max(q_n, 1));
        const double sub = duration / static_cast<double>(n);
        EXPECT_LE(sub, dem_step * (1 + 1e-12));
        EXPECT_NEAR(sub * static_cast<double>(n), duration, 2 * std::numeric_limits<double>::epsilon() * duration);
        // Minimal: one step fewer would either exceed δt or fall below Q_n.
        if (n > std::max(q_n, 1)) {
          EXPECT_GT(duration / static_cast<double>(n - 1), dem_step * (1 - 1e-9));
        }
      }
  // An increment of exactly k δt takes k steps, not k + 1 (round-off in Δt/δt).
  for (int k : {3, 7, 10, 49, 100, 1000}) {
    const double dem_step = 0.1 * 1.1e-6;
    EXPECT_EQ(substep_count(k * dem_step, dem_step, 1), k);
  }
  EXPECT_THROW(substep_count(0, 1e-6, 1), std::invalid_argument);
  EXPECT_THROW(substep_count(1e-3, 0, 1), std::invalid_argument);
  EXPECT_THROW(substep_count(-1e-3, 1e-6, 1), std::invalid_argument);
}

// The same cell turned rigidly about z at rate ω for `increments` increments, and left at rest for the
// same time: the like-for-like pair. The grains have no spin of their own: switching L to the rotation
// must spin them with the cell (ω = w + ω'), as material turning rigidly does.
std::pair<DemCell, DemCell> turn_rigidly(const DemCell& loaded, double omega, double duration, int increments,
                                         const Substepping& q) {
  DemCell turning = loaded;
  DemCell resting = loaded;
  for (int k = 0; k < increments; ++k) {
    turning.advance(rotation_z(omega * duration), duration, q);
    resting.advance(Mat3::Identity(), duration, q);
  }
  return {std::move(turning), std::move(resting)};
}

// A 3x3x3 simple cubic lattice of equal bonded spheres at rest, pressed together along x only (overlap
// `overlap`, gap 1% of the diameter along y and z): every sphere is in equilibrium by symmetry, the
// stress is uniaxial, bonds are stress-free and no tangential spring is loaded.
DemCell pressed_bonded_lattice(double overlap) {
  const Material mat = small_material(true);
  const double r = 0.5e-3, ax = 2 * r - overlap, a = 2.02 * r;
  std::vector<Vec3> x;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) x.emplace_back((i + 0.5) * ax, (j + 0.5) * a, (k + 0.5) * a);
  DemCell cell(fresh_state(Vec3(3 * ax, 3 * a, 3 * a).asDiagonal(), x, std::vector<double>(x.size(), r)), mat,
               0.1e-3);
  cell.create_bonds(mat.bond.bonding_distance);
  return cell;
}

TEST(Objectivity, SwitchingARestingBondedPackingToRigidRotationSpinsItsGrainsWithTheCell) {
  // From rest, with grains that do not spin, L jumps to a rigid rotation about z. The grains must take
  // the cell's spin at once: then nothing slips (bond shear displacements and contact springs stay
  // zero), nothing moves relative to the cell and the stress is the rotated copy R σ Rᵀ. If the grains
  // keep ω = 0, every contact slips by w × ℓ δt per step and the bonds are sheared.
  const double overlap = 2e-6;
  DemCell cell = pressed_bonded_lattice(overlap);
  const std::int64_t bonds = cell.measures().bonds;
  ASSERT_EQ(bonds, 3 * 27) << "test design: every lattice neighbour bonded";
  ASSERT_EQ(cell.contact_count(), 27u) << "test design: contacts along x only";
  const Mat3 s0 = cell.measures().stress;
  const double fn = small_material(true).contact.contact_weight * small_material(true).contact.k_n * overlap;
  ASSERT_GT(-s0(0, 0), 0);
  const double omega = 20, duration = 5e-5;
  const int increments = 524;  // ≈ 30°
  for (int k = 0; k < increments; ++k) cell.advance(rotation_z(omega * duration), duration, Substepping{});
  const CellState st = cell.state();
  double largest_shear = 0, largest_ft = 0;
  for (const Bond& b : st.bonds) largest_shear = std::max(largest_shear, b.shear_displacement.norm());
  for (const Pair& p : st.pairs) largest_ft = std::max(largest_ft, p.ft.norm());
  EXPECT_EQ(cell.measures().bonds, bonds);
  EXPECT_LT(largest_shear, 1e-9 * overlap) << "bond shear displacement from a rigid rotation";
  EXPECT_LT(largest_ft, 1e-9 * fn) << "tangential contact spring from a rigid rotation";
  const Mat3 r = rotation_z(omega * duration * increments);
  // 1e-6: the affine velocity at a step's end, (I - exp(-δt W))/δt, carries a stretching δt w²/2 that
  // the normal dashpots feel, c_n δt w² |ℓ| / 2 ≈ 2e-7 of the normal force here.
  EXPECT_LT((cell.measures().stress - r * s0 * r.transpose()).norm(), 1e-6 * s0.norm())
      << "stress:\n" << cell.measures().stress << "\nR σ0 Rᵀ:\n" << r * s0 * r.transpose();
  EXPECT_LT(cell.measures().kinetic_energy, 1e-20) << "fluctuations from a rigid rotation";
}

TEST(Objectivity, RigidRotationOfLoadedCellRotatesItsStress) {
  // A prepared frictional cell, sheared a little so that its stress is anisotropic, then turned
  // rigidly by R through many small rotation increments: σ' = R σ Rᵀ. The reference is the same cell
  // left unrotated for the same time (residual motion of the packing compared like for like); the
  // spheres spin with the cell, as material turning rigidly does.
  const Material mat = small_material();
  DemCell loaded = prepare_cell(mat, small_spec(125, 3));
  Substepping q;
  const double shear_rate = 2, duration = 5e-5;
  const Mat3 shear = simple_shear(shear_rate * duration);
  for (int k = 0; k < 300; ++k) loaded.advance(shear, duration, q);  // γ = 0.03
  const double omega = 20;  // rad/s about z
  const double angle_inc = omega * duration;
  const int increments = 524;  // ≈ 30°
  const auto [turning, resting] = turn_rigidly(loaded, omega, duration, increments, q);
  const Mat3 r = rotation_z(angle_inc * increments);
  EXPECT_LT((turning.deformation_gradient() - r * loaded.deformation_gradient()).cwiseAbs().maxCoeff(), 1e-12);
  const Mat3 s0 = loaded.measures().stress, s_rest = resting.measures().stress, s_turn = turning.measures().stress;
  const double p = pressure_of(s0);
  ASSERT_GT(p, 0);
  const Mat3 expected = r * s_rest * r.transpose();
  ASSERT_GT((expected - s_rest).norm(), 0.05 * p) << "test design: the stress should be anisotropic";
  // Same packing up to round-off-driven chaos: contact counts agree closely (not exactly).
  EXPECT_NEAR(static_cast<double>(turning.contact_count()), static_cast<double>(resting.contact_count()),
              0.03 * static_cast<double>(resting.contact_count()));
  EXPECT_LT((s_turn - expected).norm(), 5e-3 * p) << "rotated:\n" << s_turn << "\nR σ_rest Rᵀ:\n" << expected;
  EXPECT_LT((s_turn - r * s0 * r.transpose()).norm(), 0.1 * p);
  EXPECT_NEAR(pressure_of(s_turn), pressure_of(s_rest), 5e-3 * p);
}

TEST(Objectivity, RigidRotationOfFrictionlessCellRotatesItsStress) {
  // As above without friction: no tangential history is involved, so σ' = R σ Rᵀ must hold tightly.
  // (A small frictionless cell prepared to p_0 can be unjammed at fixed volume, so the preparation's
  // equilibrium check would refuse it: it is compressed by 1% first so that it is surely jammed
  // (Z > 6), then loaded axially for anisotropy.)
  Material mat = small_material();
  mat.contact.friction = 0;
  PreparationSpec spec = small_spec(125, 3);
  spec.compression_friction = 0;
  spec.equilibrium_hold = 0;
  DemCell loaded = prepare_cell(mat, spec);
  Substepping q;
  const double duration = 5e-5;
  for (int k = 0; k < 20; ++k) loaded.advance(Mat3::Identity() * (1 - 5e-4), duration, q);
  for (int k = 0; k < 40; ++k) loaded.advance(Mat3::Identity(), duration, q);
  Mat3 squeeze = Mat3::Identity();
  squeeze(0, 0) = 1 - 1.5e-4;
  for (int k = 0; k < 20; ++k) loaded.advance(squeeze, duration, q);
  ASSERT_GT(loaded.measures().coordination, 6.0) << "test design: a jammed frictionless packing";
  const double omega = 20, angle_inc = omega * duration;
  const int increments = 524;
  const auto [turning, resting] = turn_rigidly(loaded, omega, duration, increments, q);
  const Mat3 r = rotation_z(angle_inc * increments);
  const Mat3 s_rest = resting.measures().stress, s_turn = turning.measures().stress;
  const double p = pressure_of(s_rest);
  const Mat3 expected = r * s_rest * r.transpose();
  ASSERT_GT((expected - s_rest).norm(), 0.03 * p) << "test design: the stress should be anisotropic";
  EXPECT_LT((s_turn - expected).norm(), 1e-3 * p) << "rotated:\n" << s_turn << "\nR σ_rest Rᵀ:\n" << expected;
}

// Two heavy spheres (kinematically driven) overlapping by `overlap` along x, with a tangential spring
// force built by sliding sphere 1 by `slide` (⊥ x); returned at rest, without spin of their own.
DemCell loaded_contact(double overlap, const Vec3& slide) {
  Material mat = small_material();
  mat.density = 2650e9;
  mat.contact.restitution = 1;
  const double r = 0.5e-3, side = 20e-3;
  const Vec3 c = Vec3::Constant(0.5 * side);
  const Vec3 half(r - 0.5 * overlap, 0, 0);
  const double dt = 1e-6, steps = 100;
  DemCell cell(fresh_state(side * Mat3::Identity(), {c - half, c + half}, {r, r},
                           {Vec3::Zero(), slide / (dt * steps)}),
               mat, 0.1e-3);
  for (int k = 0; k < steps; ++k) cell.step_with_velocity_gradient(Mat3::Zero(), dt);
  CellState st = cell.state();
  st.velocity.assign(2, Vec3::Zero());
  st.angular_velocity.assign(2, Vec3::Zero());
  return DemCell(std::move(st), mat, 0.1e-3);
}

// Turns the whole cell (and the pair) rigidly by `angle` about `axis` through many small increments.
void turn(DemCell& cell, const Vec3& axis, double angle, double omega) {
  const int increments = 1000;
  const Mat3 inc = Eigen::AngleAxisd(angle / increments, axis).toRotationMatrix();
  Substepping q;
  q.q_n = 10;
  for (int k = 0; k < increments; ++k) cell.advance(inc, angle / increments / omega, q);
}

TEST(Objectivity, ContactTangentialForceTurnsWithPairTwistingAboutItsNormal) {
  // The cell turns at Ω about the contact normal n = x and the spheres take its spin: the pair moves
  // as one rigid body, so its tangential spring force must turn with it,
  // f_t -> R f_t (DESIGN.md: tangential history "rotated with the contact frame").
  const double omega = 1000, angle = std::numbers::pi / 2;  // fast: the heavy spheres barely move meanwhile
  DemCell cell = loaded_contact(5e-6, Vec3(0, 1e-6, 0));
  const Vec3 ft0 = cell.state().pairs.at(0).ft;
  ASSERT_GT(ft0.norm(), 1e-3) << "test design: a loaded tangential spring";
  turn(cell, Vec3::UnitX(), angle, omega);
  const Mat3 r = Eigen::AngleAxisd(angle, Vec3::UnitX()).toRotationMatrix();
  const Vec3 ft = cell.state().pairs.at(0).ft;
  EXPECT_LT((ft - r * ft0).norm(), 0.01 * ft0.norm()) << "f_t before " << ft0.transpose() << ", after "
                                                      << ft.transpose() << ", expected " << (r * ft0).transpose();
}

TEST(Objectivity, RigidRotationOfOverlappingPairDoesNotSlipItsContact) {
  // The pair along x turns rigidly about z (cell turning at Ω about z, spheres taking its spin): the
  // contact point moves with both spheres, so there is no slip and f_t -> R f_t. A slip Ω × n (|ℓ| - R_i - R_j)
  // appears if the spin lever arms are the radii rather than the distances to the contact point.
  const double omega = 1000, angle = std::numbers::pi / 6, overlap = 5e-6;
  DemCell cell = loaded_contact(overlap, Vec3(0, 0.5e-6, 0.5e-6));
  const Vec3 ft0 = cell.state().pairs.at(0).ft;
  ASSERT_GT(ft0.norm(), 1e-3);
  turn(cell, Vec3::UnitZ(), angle, omega);
  const Mat3 r = rotation_z(angle);
  const Vec3 ft = cell.state().pairs.at(0).ft;
  EXPECT_LT((ft - r * ft0).norm(), 0.01 * ft0.norm()) << "f_t before " << ft0.transpose() << ", after "
                                                      << ft.transpose() << ", expected " << (r * ft0).transpose();
}

}  // namespace
}  // namespace grainbank::dem::test

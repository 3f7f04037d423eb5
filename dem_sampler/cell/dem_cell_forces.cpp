// The force loop: geometry of every Verlet pair, the interaction law of interaction_law.hpp, and the
// Love-Weber sum of seed Eq. 2. Compiled once per set of effects, so an effect that is off costs no
// branch here, and stress is summed only at the steps where it is asked for.
//
// The loop runs in blocks of pairs, in two passes. The first computes each pair's force and the
// torques on its two spheres, with no branch on the data: contact, friction cap and bond are all
// evaluated and masked by selects, so the compiler vectorizes it (`omp simd`, the build's instruction
// set) and four pairs advance at once in 256-bit vectors. Pair data are columns
// (pair_table.hpp); sphere data are gathered. The second pass adds the forces to the spheres, in
// pair order: it is scalar because two pairs of a block may share a sphere, and it stores sphere i's
// sums once per run of pairs that share i.
#include <array>
#include <utility>

#include "dem_sampler/cell/dem_cell.hpp"

namespace grainbank::dem {
namespace {

// Small enough for a block's outputs to stay in L1 between the two passes.
constexpr std::size_t kBlock = 256;

// What each pair of a block gives its two spheres, parked between the two passes.
struct BlockOutput {
  double force[3][kBlock];     // on j; i receives the opposite
  double torque_i[3][kBlock];
  double torque_j[3][kBlock];
};

// The table's columns as raw pointers: the vectorizer must see that storing a pair's history cannot
// move a column, which it cannot prove through std::vector.
struct Columns {
  const std::uint32_t *i, *j, *image;
  const double *damping, *bond_rest_gap;
  double *ft[3], *bond_shear[3], *bond_integrity, *rolling[3];

  explicit Columns(PairTable& t)
      : i(t.i.data()), j(t.j.data()), image(t.image.data()), damping(t.damping.data()),
        bond_rest_gap(t.bond_rest_gap.data()),
        ft{t.ft[0].data(), t.ft[1].data(), t.ft[2].data()},
        bond_shear{t.bond_shear[0].data(), t.bond_shear[1].data(), t.bond_shear[2].data()},
        bond_integrity(t.bond_integrity.data()),
        rolling{t.rolling[0].data(), t.rolling[1].data(), t.rolling[2].data()} {}
};

LaneVec load_column(double* const (&c)[3], std::size_t k) { return {c[0][k], c[1][k], c[2][k]}; }

void store_column(double* const (&c)[3], std::size_t k, const LaneVec& v) {
  c[0][k] = v.x;
  c[1][k] = v.y;
  c[2][k] = v.z;
}

}  // namespace

// Flattened: the vectorizer sees only a loop body with every call (the law, the lane arithmetic) inlined.
template <bool Bonds, bool Rolling, bool Measure, DemCell::BondForm Form>
GRAINBANK_VECTOR_LOOP void DemCell::compute_forces(double dt) {
  std::fill(force_.begin(), force_.end(), Vec3::Zero());
  std::fill(torque_.begin(), torque_.end(), Vec3::Zero());
  const Mat3 L = L_;
  const LaneVec cell_spin(spin_vector(L));
  const InteractionCoefficients c = coef_;
  // Sphere data as flat arrays of x, y, z: Vec3 is three contiguous doubles.
  const double *x = x_.data()->data(), *u = u_.data()->data(), *omega = omega_.data()->data();
  const double* shift = shift_[0].data();
  const double* radius = radius_.data();
  const Columns P(pairs_);
  // Love-Weber sum Σ f ⊗ ℓ, component by component (an omp simd reduction takes scalars).
  double s00 = 0, s01 = 0, s02 = 0, s10 = 0, s11 = 0, s12 = 0, s20 = 0, s21 = 0, s22 = 0;
  double sum_force = 0;
  std::int64_t active = 0;
  BlockOutput out;
  const std::size_t count = pairs_.size();
  for (std::size_t begin = 0; begin < count; begin += kBlock) {
    const std::size_t m = std::min(kBlock, count - begin);
#pragma omp simd reduction(+ : s00, s01, s02, s10, s11, s12, s20, s21, s22, sum_force, active)
    for (std::size_t q = 0; q < m; ++q) {
      const std::size_t k = begin + q;
      const std::uint32_t i = P.i[k], j = P.j[k];
      // Branch vector ℓ from i to the image of j.
      const LaneVec l = load_lane(x, j) - load_lane(x, i) + load_lane(shift, P.image[k]);
      const double r2 = squared_norm(l);
      const double ri = radius[i], rj = radius[j], rsum = ri + rj;
      const bool touching = r2 < rsum * rsum;
      const double r = std::sqrt(r2);
      const LaneVec n = l * (1 / r);  // one division, not one per component
      const double gap = r - rsum;
      const double arm_i = ri + 0.5 * gap, arm_j = rj + 0.5 * gap;  // to the contact point
      const LaneVec wi = load_lane(omega, i) + cell_spin, wj = load_lane(omega, j) + cell_spin;
      // Velocity of j's contact point relative to i's: fluctuations, affine field L ℓ, and spins.
      const LaneVec v = load_lane(u, j) - load_lane(u, i) + times(L, l) - cross(arm_i * wi + arm_j * wj, n);
      const double vn = dot(v, n);
      const LaneVec slip = (v - vn * n) * dt;
      const double twist = 0.5 * dt * dot(wi + wj, n);

      // A contact lost forgets its history.
      const double fn_contact = contact_normal_force(c, gap, vn, P.damping[k]);
      double fn = touching ? fn_contact : 0.0;
      LaneVec ft = select(touching, friction_force(c, n, twist, slip, fn_contact, load_column(P.ft, k)), LaneVec());
      store_column(P.ft, k, ft);
      bool interacting = touching;
      if constexpr (Bonds) {
        // Masks as 0/1 factors rather than selects: the compiler would turn a select on `bonded`
        // back into a branch around the whole bond law, and then not vectorize the loop.
        constexpr bool softening = Form == BondForm::kSofteningQuadratic;
        const double integrity_before = P.bond_integrity[k];
        // 1 unless broken at the start of the step; ceil, not a compare, which would become a branch.
        const double bonded = softening ? std::ceil(integrity_before) : integrity_before;
        const LaneVec shear_before = load_column(P.bond_shear, k);
        const BondStep bond =
            bond_step<Form != BondForm::kBrittlePower>(c, shear_before, P.bond_rest_gap[k], gap, n, twist, slip);
        // A softening bond keeps the least integrity it has had; a brittle one holds or breaks.
        const double integrity = softening
                                     ? std::min(integrity_before, softening_integrity(c, bond.tension, bond.shear_squared))
                                     : bonded * (bond.holds ? 1.0 : 0.0);
        // A bond keeps the history of the step that broke it; a broken one's no longer changes.
        store_column(P.bond_shear, k, bonded * bond.shear_displacement + (1 - bonded) * shear_before);
        P.bond_integrity[k] = integrity;
        // The normal dashpot acts once per pair: with the contact's, or with the bond's alone.
        const double bond_normal = bond.tension + (touching ? 0.0 : P.damping[k] * vn);
        fn -= integrity * bond_normal;
        ft -= integrity * c.kt_bond * bond.shear_displacement;
        interacting = touching | (integrity != 0);
      }
      const LaneVec f = fn * n + ft;  // force on j; i receives -f
      const LaneVec n_x_ft = cross(n, ft);
      LaneVec moment = LaneVec();  // rolling moment on j
      if constexpr (Rolling) {
        const LaneVec previous = load_column(P.rolling, k);
        moment = select(touching, rolling_moment(c, n, twist, (wj - wi) * dt, ri * rj / rsum, fn_contact, previous),
                        LaneVec());
        store_column(P.rolling, k, moment);
      }
      const LaneVec torque_i = -arm_i * n_x_ft - moment, torque_j = -arm_j * n_x_ft + moment;
      out.force[0][q] = f.x, out.force[1][q] = f.y, out.force[2][q] = f.z;
      out.torque_i[0][q] = torque_i.x, out.torque_i[1][q] = torque_i.y, out.torque_i[2][q] = torque_i.z;
      out.torque_j[0][q] = torque_j.x, out.torque_j[1][q] = torque_j.y, out.torque_j[2][q] = torque_j.z;
      if constexpr (Measure) {
        s00 += f.x * l.x, s01 += f.x * l.y, s02 += f.x * l.z;
        s10 += f.y * l.x, s11 += f.y * l.y, s12 += f.y * l.z;
        s20 += f.z * l.x, s21 += f.z * l.y, s22 += f.z * l.z;
        sum_force += std::sqrt(squared_norm(f));
        active += interacting ? 1 : 0;
      }
    }
    // Every pair has j > i, so no pair of a run sharing i touches i as its j: i's sums stay in
    // registers over the run and are stored once, with the additions in the same order as one by one
    // (the list is sorted by i, so runs are about as long as a sphere's pair count).
    std::size_t q = 0;
    while (q < m) {
      const std::uint32_t i = P.i[begin + q];
      double fi[3] = {force_[i][0], force_[i][1], force_[i][2]};
      double ti[3] = {torque_[i][0], torque_[i][1], torque_[i][2]};
      for (; q < m && P.i[begin + q] == i; ++q) {
        const std::uint32_t j = P.j[begin + q];
        for (int a = 0; a < 3; ++a) {
          force_[j][a] += out.force[a][q];
          torque_[j][a] += out.torque_j[a][q];
          fi[a] -= out.force[a][q];
          ti[a] += out.torque_i[a][q];
        }
      }
      for (int a = 0; a < 3; ++a) {
        force_[i][a] = fi[a];
        torque_[i][a] = ti[a];
      }
    }
  }
  if constexpr (Measure) {
    Mat3 love_weber;
    love_weber << s00, s01, s02, s10, s11, s12, s20, s21, s22;
    stress_ = -love_weber / cell_volume(h_);
    sum_pair_force_ = sum_force;
    active_pairs_ = active;
  }
}

// One kernel per combination of effects: bit 0 bonds, 1 rolling, 2 measure; bits 3-4 the BondForm.
template <std::size_t... Flags>
constexpr auto DemCell::force_kernels(std::index_sequence<Flags...>) {
  using Kernel = void (DemCell::*)(double);
  return std::array<Kernel, sizeof...(Flags)>{&DemCell::compute_forces<(Flags & 1) != 0, (Flags & 2) != 0,
                                                                         (Flags & 4) != 0, BondForm(Flags >> 3)>...};
}

void DemCell::compute_forces(bool measure, double dt) {
  static constexpr auto kKernels = force_kernels(std::make_index_sequence<8 * kBondForms>());
  const bool bonds = material_.effects.bonds, rolling = material_.effects.rolling;
  const BondForm form = !bonds                   ? BondForm::kBrittleQuadratic
                        : coef_.inv_softening > 0 ? BondForm::kSofteningQuadratic
                        : coef_.exponent == 2     ? BondForm::kBrittleQuadratic
                                                  : BondForm::kBrittlePower;
  const std::size_t flags =
      (bonds ? 1 : 0) | (rolling ? 2 : 0) | (measure ? 4 : 0) | (static_cast<std::size_t>(form) << 3);
  (this->*kKernels[flags])(dt);
}

}  // namespace grainbank::dem

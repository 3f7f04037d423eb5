#include "dem_sampler/cell/dem_cell.hpp"

#include "dem_sampler/cell/matrix_functions.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>
#include <stdexcept>

namespace grainbank::dem {
namespace {

void require_size(std::size_t got, std::size_t expected, const char* what) {
  if (got == expected) return;
  std::ostringstream msg;
  msg << "cell state: " << what << " has " << got << " entries, expected " << expected;
  throw std::invalid_argument(msg.str());
}

}  // namespace

DemCell::DemCell(CellState st, Material material, double skin)
    : material_(std::move(material)), coef_((check(material_), material_)), skin_(skin) {
  const std::size_t n = st.radius.size();
  if (n < 2) throw std::invalid_argument("cell state: a cell needs at least two spheres");
  if (!(skin > 0) || !std::isfinite(skin))
    throw std::invalid_argument("skin: expected a positive Verlet skin length");
  if (!st.h.allFinite() || !(cell_volume(st.h) > 0))
    throw std::invalid_argument("cell state: cell matrix h must be finite with a non-zero volume");
  require_size(st.reduced_position.size(), n, "reduced_position");
  require_size(st.velocity.size(), n, "velocity");
  require_size(st.angular_velocity.size(), n, "angular_velocity");
  const bool fresh = st.reduced_position_at_list_build.empty();
  if (!fresh) {
    require_size(st.force.size(), n, "force");
    require_size(st.torque.size(), n, "torque");
    require_size(st.reduced_position_at_list_build.size(), n, "reduced_position_at_list_build");
  }
  if (!fresh) {
    require_size(st.bonds.size(), material_.effects.bonds ? st.pairs.size() : 0, "bonds");
    require_size(st.rolling_moment.size(), material_.effects.rolling ? st.pairs.size() : 0, "rolling_moment");
  }
  radius_ = std::move(st.radius);
  mass_.resize(n);
  inv_mass_.resize(n);
  inv_inertia_.resize(n);
  min_mass_ = min_radius_ = std::numeric_limits<double>::max();
  for (std::size_t p = 0; p < n; ++p) {
    const double r = radius_[p];
    if (!(r > 0) || !std::isfinite(r)) {
      std::ostringstream msg;
      msg << "cell state: radius of sphere " << p << ": expected a positive number, got " << r;
      throw std::invalid_argument(msg.str());
    }
    mass_[p] = material_.density * 4.0 / 3.0 * std::numbers::pi * r * r * r;
    inv_mass_[p] = 1 / mass_[p];
    inv_inertia_[p] = 1 / (0.4 * mass_[p] * r * r);
    max_radius_ = std::max(max_radius_, r);
    min_mass_ = std::min(min_mass_, mass_[p]);
    min_radius_ = std::min(min_radius_, r);
  }
  h_ = st.h;
  h_inv_ = h_.inverse();
  h_ref_ = st.h_reference;
  time_ = st.time;
  s_ = std::move(st.reduced_position);
  u_ = std::move(st.velocity);
  omega_ = std::move(st.angular_velocity);
  initial_bonds_ = st.initial_bond_count;
  stress_ = st.last_stress;
  active_pairs_ = st.last_active_pairs;
  sum_pair_force_ = st.last_pair_force_sum;
  x_.resize(n);
  if (fresh) {
    force_.assign(n, Vec3::Zero());
    torque_.assign(n, Vec3::Zero());
    rebuild_list();
    update_positions();
    compute_forces(true, 0.0);
  } else {
    force_ = std::move(st.force);
    torque_ = std::move(st.torque);
    for (const Pair& p : st.pairs)
      if (p.i >= n || p.j >= n || p.i >= p.j || p.image >= kShiftCount)
        throw std::invalid_argument("cell state: a Verlet pair names a sphere or image that does not exist");
    pairs_ = PairTable::from_rows(st.pairs, st.bonds, st.rolling_moment);
    h_build_ = st.h_at_list_build;
    s_build_ = std::move(st.reduced_position_at_list_build);
    update_positions();
  }
}

DemCell DemCell::from_packing(const Mat3& h, const std::vector<Vec3>& positions, const std::vector<double>& radii,
                              const Material& material, double skin) {
  if (positions.size() != radii.size())
    throw std::invalid_argument("packing: positions and radii differ in count");
  CellState st;
  st.h = h;
  st.h_reference = h;
  st.radius = radii;
  const Mat3 h_inv = h.inverse();
  for (const Vec3& x : positions) {
    if (!x.allFinite()) throw std::invalid_argument("packing: a sphere position is not finite");
    st.reduced_position.push_back(wrapped_into_cell(h_inv * x));
  }
  st.velocity.assign(radii.size(), Vec3::Zero());
  st.angular_velocity.assign(radii.size(), Vec3::Zero());
  return DemCell(std::move(st), material, skin);
}

double DemCell::time_step(double q_t) const {
  const double k_r = material_.effects.rolling ? material_.rolling.stiffness : 0;
  return dem_time_step(q_t, min_mass_, min_radius_, material_.contact.k_n, material_.contact.k_t, k_r);
}

void DemCell::set_friction(double mu) {
  if (!(mu >= 0) || !std::isfinite(mu)) throw std::invalid_argument("friction: expected a number >= 0");
  material_.contact.friction = mu;
  coef_.friction = mu;
}

// ---------------------------------------------------------------------------------------------
// Time integration

IncrementResult DemCell::advance(const Mat3& increment, double duration, const Substepping& q) {
  if (!increment.allFinite() || !(increment.determinant() > 0))
    throw std::invalid_argument("advance: the deformation increment must be finite with a positive determinant");
  require_stable_time_step_factor(q.q_t, material_.contact.restitution, "advance: substepping.q_t");
  if (!(q.q_sigma >= 0 && q.q_sigma <= 1))
    throw std::invalid_argument("advance: expected Q_sigma in [0, 1]");
  const long n = substep_count(duration, time_step(q.q_t), q.q_n);
  const double dt = duration / static_cast<double>(n);
  // Constant velocity gradient over the increment, h(t) = exp(t G) h0 with G = log F_inc: a rotation
  // stays a rotation at every sub-step, and the last sub-step lands on F_inc h0 exactly.
  const Mat3 log_increment = matrix_logarithm(increment);
  Mat3 h0 = h_;
  const double window_start = (1 - q.q_sigma) * duration;
  StressRegression regression;
  for (long k = 1; k <= n; ++k) {
    h0 = h0 * reduce_if_needed().cast<double>();
    h0 = h0 * retile_if_needed();
    const double fraction = static_cast<double>(k) / static_cast<double>(n);
    const Mat3 h_next = k == n ? Mat3(increment * h0) : Mat3(matrix_exponential(fraction * log_increment) * h0);
    const double t = static_cast<double>(k) * dt;
    const bool measure = k == n || t >= window_start;
    step_to(h_next, dt, measure);
    if (measure) regression.add(t, stress_);
  }
  IncrementResult result;
  result.stress = regression.at(duration);
  result.substeps = n;
  result.substep = dt;
  if (!result.stress.allFinite()) {
    std::ostringstream msg;
    msg << "DEM cell diverged at t = " << time_ << " s (non-finite stress) with δt = " << dt
        << " s: lower Q_t or the macroscopic time step";
    throw std::runtime_error(msg.str());
  }
  return result;
}

void DemCell::step_with_velocity_gradient(const Mat3& L, double dt) {
  reduce_if_needed();
  retile_if_needed();
  step_to(h_ + dt * L * h_, dt, true);
}

void DemCell::step_mixed(const MixedControl& c, double dt) {
  reduce_if_needed();
  retile_if_needed();
  Mat3 L = c.velocity_gradient;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b)
      if (c.stress_controlled(a, b)) {
        // Too little compression (σ above its tension-positive target) shrinks the cell.
        const double rate = c.max_rate * (c.target_stress(a, b) - stress_(a, b)) / c.stress_scale;
        L(a, b) = std::clamp(rate, -c.max_rate, c.max_rate);
      }
  step_to(h_ + dt * L * h_, dt, true);
}

void DemCell::step_to(const Mat3& h_new, double dt, bool measure) {
  // A cell that has blown up must stop here with a message: a non-finite cell or position would
  // index the Verlet bins out of range.
  if (!h_new.allFinite() || !(h_new.determinant() > 0))
    throw diverged("its cell matrix became non-finite or degenerate");
  const Mat3 hdot = (h_new - h_) / dt;
  const Mat3 L_start = hdot * h_inv_;
  const Mat3 h_mid_inv = (0.5 * (h_ + h_new)).inverse();
  const double max_displacement2 = local_damping_ > 0 ? kick_and_drift<true>(dt, L_start, h_mid_inv, h_new)
                                                      : kick_and_drift<false>(dt, L_start, h_mid_inv, h_new);
  if (!std::isfinite(max_displacement2)) throw diverged("a sphere's position became non-finite");
  h_ = h_new;
  h_inv_ = h_.inverse();
  L_ = hdot * h_inv_;
  time_ += dt;
  if (list_is_stale(max_displacement2)) {
    rebuild_list();
    update_positions();
  } else {
    update_shifts();
  }
  compute_forces(measure, dt);
  if (local_damping_ > 0) kick<true>(0.5 * dt, L_);
  else kick<false>(0.5 * dt, L_);
  if (measure && material_.effects.kinetic_stress) {
    const std::size_t n = radius_.size();
    Mat3 kinetic = Mat3::Zero();
    for (std::size_t p = 0; p < n; ++p) kinetic += mass_[p] * u_[p] * u_[p].transpose();
    stress_ -= kinetic / cell_volume(h_);
  }
}

std::runtime_error DemCell::diverged(const std::string& what) const {
  std::ostringstream msg;
  msg << "DEM cell diverged at t = " << time_ << " s: " << what
      << "; its drive or stress target is more than its contacts can hold at this step: lower Q_t, the strain "
         "rate or the target stress, or check that the material's density and stiffness are physical";
  return std::runtime_error(msg.str());
}

void DemCell::update_positions() {
  const std::size_t n = radius_.size();
  for (std::size_t p = 0; p < n; ++p) x_[p] = h_ * s_[p];
  update_shifts();
}

void DemCell::update_shifts() {
  for (int code = 0; code < kShiftCount; ++code) shift_[code] = h_ * shift_vector(code).cast<double>();
}

// ---------------------------------------------------------------------------------------------
// Bonds, measures, state

std::int64_t DemCell::create_bonds(double bonding_distance) {
  if (!material_.effects.bonds) throw std::logic_error("create_bonds: the material's bonds effect is off");
  const double saved_skin = skin_;
  skin_ = std::max(skin_, 2 * max_radius_ * bonding_distance * 1.001);
  rebuild_list();
  skin_ = saved_skin;
  update_positions();
  std::int64_t count = 0;
  for (std::size_t k = 0; k < pairs_.size(); ++k) {
    const double rsum = radius_[pairs_.i[k]] + radius_[pairs_.j[k]];
    const double gap = branch(k).norm() - rsum;
    if (gap < bonding_distance * rsum) {
      for (auto& c : pairs_.bond_shear) c[k] = 0;
      pairs_.bond_rest_gap[k] = gap;
      pairs_.bond_integrity[k] = 1;
      ++count;
    }
  }
  initial_bonds_ = count;
  return count;
}

std::size_t DemCell::contact_count() const {
  std::size_t c = 0;
  for (std::size_t k = 0; k < pairs_.size(); ++k) {
    const double rsum = radius_[pairs_.i[k]] + radius_[pairs_.j[k]];
    if (branch(k).squaredNorm() < rsum * rsum) ++c;
  }
  return c;
}

double DemCell::max_overlap() const {
  double largest = 0;
  for (std::size_t k = 0; k < pairs_.size(); ++k) {
    const double rsum = radius_[pairs_.i[k]] + radius_[pairs_.j[k]];
    largest = std::max(largest, 1 - branch(k).norm() / rsum);
  }
  return largest;
}

CellMeasures DemCell::measures() const {
  CellMeasures m;
  const std::size_t n = radius_.size();
  m.time = time_;
  m.stress = stress_;
  double solid = 0, net_force = 0;
  for (std::size_t p = 0; p < n; ++p) {
    solid += mass_[p] / material_.density;
    m.kinetic_energy += 0.5 * mass_[p] * u_[p].squaredNorm() + 0.5 * omega_[p].squaredNorm() / inv_inertia_[p];
    net_force += force_[p].norm();
  }
  m.solid_fraction = solid / cell_volume(h_);
  m.coordination = 2.0 * static_cast<double>(active_pairs_) / static_cast<double>(n);
  m.bonds = pairs_.intact_bonds();
  m.damage = initial_bonds_ > 0 ? 1.0 - static_cast<double>(m.bonds) / static_cast<double>(initial_bonds_) : 0.0;
  m.unbalanced_force_ratio =
      active_pairs_ > 0 && sum_pair_force_ > 0
          ? (net_force / static_cast<double>(n)) / (sum_pair_force_ / static_cast<double>(active_pairs_))
          : 1.0;
  return m;
}

std::vector<Vec3> DemCell::positions() const {
  std::vector<Vec3> x(s_.size());
  for (std::size_t p = 0; p < s_.size(); ++p) x[p] = h_ * s_[p];
  return x;
}

std::size_t DemCell::memory_bytes() const {
  auto bytes = [](const auto& v) { return v.capacity() * sizeof(v[0]); };
  return bytes(radius_) + bytes(mass_) + bytes(inv_mass_) + bytes(inv_inertia_) + bytes(s_) + bytes(u_) +
         bytes(omega_) + bytes(x_) + bytes(force_) + bytes(torque_) + pairs_.memory_bytes() +
         bytes(s_build_) + bytes(scratch_pairs_);
}

CellState DemCell::state() const {
  CellState st;
  st.h = h_;
  st.h_reference = h_ref_;
  st.time = time_;
  st.radius = radius_;
  st.reduced_position = s_;
  st.velocity = u_;
  st.angular_velocity = omega_;
  st.force = force_;
  st.torque = torque_;
  st.pairs = pairs_.pair_rows();
  st.bonds = pairs_.bond_rows();
  st.rolling_moment = pairs_.rolling_rows();
  st.initial_bond_count = initial_bonds_;
  st.h_at_list_build = h_build_;
  st.reduced_position_at_list_build = s_build_;
  st.last_stress = stress_;
  st.last_active_pairs = active_pairs_;
  st.last_pair_force_sum = sum_pair_force_;
  return st;
}

}  // namespace grainbank::dem

#include "live_dem_law.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>
#include <stdexcept>

namespace grainbank::mpm {

dem::Mat3 embed_plane_strain(const Mat2& F_inc) {
  dem::Mat3 f = dem::Mat3::Identity();
  f.topLeftCorner<2, 2>() = F_inc;
  return f;
}

namespace {
// The MPM momentum balance needs a symmetric stress; Love–Weber stress is symmetric only at
// equilibrium of moments, so its symmetric part is taken (as the reference implementation does).
PointStress plane_stress_of(const dem::Mat3& s) {
  PointStress out;
  const Mat2 block = s.topLeftCorner<2, 2>();
  out.in_plane = 0.5 * (block + block.transpose());
  out.zz = s(2, 2);
  return out;
}
}  // namespace

LiveDemLaw::LiveDemLaw(const dem::DemCell& cell_template, LiveDemSettings settings)
    : template_state_(cell_template.state()),
      material_(cell_template.material()),
      skin_(cell_template.skin()),
      settings_(settings) {
  if (!(settings_.q_h > 0) || !std::isfinite(settings_.q_h))
    throw std::invalid_argument("q_h: expected a positive number");
  const std::vector<double>& r = cell_template.radii();
  double solid_mass = 0;
  for (double ri : r) solid_mass += material_.density * 4.0 / 3.0 * std::numbers::pi * ri * ri * ri;
  template_volume_ = cell_template.volume();
  density_ = solid_mass / template_volume_;
  mean_radius_ = std::accumulate(r.begin(), r.end(), 0.0) / static_cast<double>(r.size());
  min_diameter_ = 2 * *std::min_element(r.begin(), r.end());
}

std::size_t LiveDemLaw::add_point(PointStress& initial_stress) {
  cells_.emplace_back(template_state_, material_, skin_);  // a deep copy: the point owns its cell
  const dem::CellMeasures m = cells_.back().measures();
  modulus_.push_back(voigt_modulus(m));
  damage_.push_back(m.damage);
  initial_stress = plane_stress_of(m.stress);
  return cells_.size() - 1;
}

void LiveDemLaw::update(std::size_t slot, const Mat2& F_inc, double dt, PointStress& stress) {
  dem::DemCell& cell = cells_[slot];
  const dem::IncrementResult r = cell.advance(embed_plane_strain(F_inc), dt, settings_.substepping);
  stress = plane_stress_of(r.stress);
  const dem::CellMeasures m = cell.measures();
  modulus_[slot] = voigt_modulus(m);
  damage_[slot] = m.damage;
}

void LiveDemLaw::restore_cell(std::size_t slot, dem::CellState state) {
  cells_[slot] = dem::DemCell(std::move(state), material_, skin_);
  const dem::CellMeasures m = cells_[slot].measures();
  modulus_[slot] = voigt_modulus(m);
  damage_[slot] = m.damage;
}

double LiveDemLaw::volume_ratio(std::size_t slot, const Mat2&) const {
  return cells_[slot].volume() / template_volume_;
}

double LiveDemLaw::time_step_limit(std::size_t slot, const Mat2& L) const {
  // Seed Eq. 4 with ḣ = L h: |ḣ|_sup is the largest component of the cell-vector velocities.
  dem::Mat3 L3 = dem::Mat3::Zero();
  L3.topLeftCorner<2, 2>() = L;
  const dem::Mat3 h_rate = L3 * cells_[slot].cell_matrix();
  const double rate = h_rate.cwiseAbs().maxCoeff();
  return rate > 0 ? settings_.q_h * min_diameter_ / rate : std::numeric_limits<double>::infinity();
}

double LiveDemLaw::voigt_modulus(const dem::CellMeasures& m) const {
  const double scale = m.solid_fraction * m.coordination / (std::numbers::pi * mean_radius_);
  const double bulk = scale * material_.contact.k_n / 12;
  const double shear = scale * (2 * material_.contact.k_n + 3 * material_.contact.k_t) / 60;
  return bulk + 4 * shear / 3;
}

}  // namespace grainbank::mpm

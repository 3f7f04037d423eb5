#include "mpm_solver/dem_laws/live_cell_model.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>
#include <stdexcept>

#include "dem_sampler/cell/periodic_cell.hpp"
#include "dem_sampler/cell/regeneration.hpp"

namespace grainbank::mpm {

PointStress plane_stress_of(const dem::Mat3& s) {
  PointStress out;
  const Mat2 block = s.topLeftCorner<2, 2>();
  out.in_plane = 0.5 * (block + block.transpose());
  out.zz = s(2, 2);
  return out;
}

LiveCellModel::LiveCellModel(const dem::DemCell& cell_template, LiveDemSettings settings)
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
  template_volume_ratio_ = cell_template.deformation_gradient().determinant();
  template_deformation_inverse_ = cell_template.deformation_gradient().inverse();
  density_ = solid_mass / template_volume_;
  mean_radius_ = std::accumulate(r.begin(), r.end(), 0.0) / static_cast<double>(r.size());
  min_diameter_ = 2 * *std::min_element(r.begin(), r.end());
}

dem::Mat3 LiveCellModel::advance(dem::DemCell& cell, const KinematicIncrement& increment,
                                 CouplingCounters& counters) const {
  if (cell.interacting_pairs() == 0 && volume_ratio(cell) > kDispersedVolumeRatio && increment.F.determinant() > 1) {
    ++counters.dispersed_holds;
    return cell.stress();
  }
  if (settings_.regenerate_beyond_cap && cell.thin_beyond_retiling_cap()) {
    dem::RegenerationSettings regeneration;
    regeneration.q_t = settings_.substepping.q_t;
    dem::Regeneration fresh = dem::regenerate(cell, template_state_, regeneration);
    cell = with_cap(std::move(fresh.cell));
    ++counters.regenerations;
    if (!fresh.servo.converged) ++counters.regenerations_unconverged;
  }
  const std::size_t spheres = cell.size();
  const dem::Mat3 stress = cell.advance(embed_plane_strain(increment.F), increment.dt, settings_.substepping).stress;
  count_retilings(spheres, cell, counters);
  return stress;
}

void LiveCellModel::count_retilings(std::size_t spheres_before, const dem::DemCell& cell, CouplingCounters& counters) {
  for (std::size_t n = spheres_before; n < cell.size(); n *= 2) ++counters.retilings;
}

double LiveCellModel::volume_ratio(const dem::DemCell& cell) const {
  return cell.deformation_gradient().determinant() / template_volume_ratio_;
}

double LiveCellModel::modulus(const dem::CellMeasures& m) const {
  return dem::voigt_moduli(m.solid_fraction, m.coordination, mean_radius_, material_.contact.k_n, material_.contact.k_t)
      .p_wave();
}

double LiveCellModel::time_step_limit(const dem::DemCell& cell, const Mat2& L) const {
  if (cell.interacting_pairs() == 0) return std::numeric_limits<double>::infinity();
  return time_step_limit_of_deformed_template(cell.deformation_gradient() * template_deformation_inverse_, L);
}

double LiveCellModel::time_step_limit(const Mat2& F, const Mat2& L) const {
  return time_step_limit_of_deformed_template(embed_plane_strain(F), L);
}

double LiveCellModel::time_step_limit_of_deformed_template(const dem::Mat3& F, const Mat2& L) const {
  dem::Mat3 h = F * template_state_.h;
  dem::reduce_basis(h);
  // |ḣ|_sup is the largest component of the cell-vector velocities.
  dem::Mat3 L3 = dem::Mat3::Zero();
  L3.topLeftCorner<2, 2>() = L;
  const double rate = (L3 * h).cwiseAbs().maxCoeff();
  return rate > 0 ? settings_.q_h * min_diameter_ / rate : std::numeric_limits<double>::infinity();
}

}  // namespace grainbank::mpm

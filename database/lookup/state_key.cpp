#include "database/lookup/state_key.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <stdexcept>

namespace grainbank::lookup {

bool has_polar_decomposition(const dem::Mat3& F) { return F.allFinite() && F.determinant() > 0; }

PolarDecomposition polar_decomposition(const dem::Mat3& F) {
  if (!has_polar_decomposition(F))
    throw std::invalid_argument("state key: deformation gradient F must be finite with det F > 0");
  // FᵀF = V Λ Vᵀ: U = V Λ^½ Vᵀ and ln U = V ½ln Λ Vᵀ exactly, without iterating on F.
  const Eigen::SelfAdjointEigenSolver<dem::Mat3> eigen(F.transpose() * F);
  const dem::Vec3 lambda = eigen.eigenvalues();
  const dem::Mat3& V = eigen.eigenvectors();
  const dem::Vec3 stretch = lambda.cwiseSqrt();
  PolarDecomposition p;
  p.U = V * stretch.asDiagonal() * V.transpose();
  p.hencky = V * stretch.array().log().matrix().asDiagonal() * V.transpose();
  p.R = F * (V * stretch.cwiseInverse().asDiagonal() * V.transpose());
  return p;
}

db::StateKey state_key(const PolarDecomposition& polar, const dem::Mat3& L, double damage, const db::KeyScales& scales) {
  const dem::Mat3 D = 0.5 * (L + L.transpose());
  const dem::Mat3 rate = polar.R.transpose() * D * polar.R;
  const dem::Mat3& E = polar.hencky;
  return {E(0, 0) / scales.strain,   E(1, 1) / scales.strain,   0.5 * (E(0, 1) + E(1, 0)) / scales.strain,
          rate(0, 0) / scales.rate,  rate(1, 1) / scales.rate,  rate(0, 1) / scales.rate,
          damage / scales.damage};
}

db::StateKey state_key(const dem::Mat3& F, const dem::Mat3& L, double damage, const db::KeyScales& scales) {
  return state_key(polar_decomposition(F), L, damage, scales);
}

db::StateKey state_key(const db::Record& record, const db::KeyScales& scales) {
  return state_key(record.F, record.L, record.damage, scales);
}

dem::Mat3 to_material_frame(const dem::Mat3& stress, const dem::Mat3& R) { return R.transpose() * stress * R; }

dem::Mat3 to_lab_frame(const dem::Mat3& material_stress, const dem::Mat3& R) { return R * material_stress * R.transpose(); }

double inertial_rate_scale(double inertial_number, double pressure, double density, double diameter) {
  if (!(inertial_number > 0 && pressure > 0 && density > 0 && diameter > 0))
    throw std::invalid_argument("inertial_rate_scale: inertial number, pressure, density and diameter must be positive");
  return inertial_number * std::sqrt(pressure / density) / diameter;
}

}  // namespace grainbank::lookup

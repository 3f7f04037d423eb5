#include "database/lookup/blend.hpp"

#include <cmath>
#include <vector>

namespace grainbank::lookup {

namespace {

// Records closer than this (in key units) count as the query's own state: their answer is exact.
constexpr double kSameState = 1e-12;

RecordResponse scaled(const RecordResponse& r, double w) {
  RecordResponse out;
  for (std::size_t i = 0; i < 6; ++i) out.material_stress[i] = w * r.material_stress[i];
  out.damage = w * r.damage;
  out.coordination = w * r.coordination;
  out.solid_fraction = w * r.solid_fraction;
  return out;
}

void add(RecordResponse& sum, const RecordResponse& r) {
  for (std::size_t i = 0; i < 6; ++i) sum.material_stress[i] += r.material_stress[i];
  sum.damage += r.damage;
  sum.coordination += r.coordination;
  sum.solid_fraction += r.solid_fraction;
}

// Frobenius norm² of the difference of two symmetric stresses in Stress6 order.
double stress_distance2(const db::Stress6& a, const db::Stress6& b) {
  double sum = 0;
  for (std::size_t i = 0; i < 6; ++i) sum += (i < 3 ? 1.0 : 2.0) * (a[i] - b[i]) * (a[i] - b[i]);
  return sum;
}

}  // namespace

Blended blend(std::span<const Neighbour> neighbours) {
  const bool exact = neighbours.front().distance <= kSameState;
  std::vector<double> weights(neighbours.size());
  double weight_sum = 0;
  for (std::size_t i = 0; i < neighbours.size(); ++i) {
    const double d = neighbours[i].distance;
    weights[i] = exact ? (d <= kSameState ? 1.0 : 0.0) : 1.0 / (d * d);
    weight_sum += weights[i];
  }
  Blended result;
  for (std::size_t i = 0; i < neighbours.size(); ++i) {
    weights[i] /= weight_sum;
    add(result.response, scaled(*neighbours[i].response, weights[i]));
  }
  double spread2 = 0;
  for (std::size_t i = 0; i < neighbours.size(); ++i)
    spread2 += weights[i] * stress_distance2(neighbours[i].response->material_stress, result.response.material_stress);
  result.estimated_error = std::sqrt(spread2);
  return result;
}

}  // namespace grainbank::lookup

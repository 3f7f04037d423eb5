#include "mpm_solver/core/nonlocal_average.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "mpm_solver/core/parallel.hpp"

namespace grainbank::mpm {

NonlocalAverage::NonlocalAverage(double length) : length_(length) {
  if (!(length > 0) || !std::isfinite(length))
    throw std::invalid_argument("regularization length: expected a positive number [m]");
}

void NonlocalAverage::apply(std::vector<MaterialPoint>& points) const {
  const long n = static_cast<long>(points.size());
  if (n == 0) return;
  // Bins of side ℓ: a point's neighbours lie in its own bin and the eight around it.
  Vec2 lower = points.front().position, upper = lower;
  for (const MaterialPoint& mp : points) lower = lower.cwiseMin(mp.position), upper = upper.cwiseMax(mp.position);
  const int bins_x = static_cast<int>((upper.x() - lower.x()) / length_) + 1;
  const int bins_y = static_cast<int>((upper.y() - lower.y()) / length_) + 1;
  const auto bin_of = [&](const Vec2& x) {
    const int i = std::min(static_cast<int>((x.x() - lower.x()) / length_), bins_x - 1);
    const int j = std::min(static_cast<int>((x.y() - lower.y()) / length_), bins_y - 1);
    return std::pair{i, j};
  };
  std::vector<long> first(static_cast<std::size_t>(bins_x) * bins_y + 1, 0), members(n);
  for (const MaterialPoint& mp : points) {
    const auto [i, j] = bin_of(mp.position);
    ++first[static_cast<std::size_t>(j) * bins_x + i + 1];
  }
  for (std::size_t b = 1; b < first.size(); ++b) first[b] += first[b - 1];
  std::vector<long> fill(first.begin(), first.end() - 1);
  for (long p = 0; p < n; ++p) {
    const auto [i, j] = bin_of(points[p].position);
    members[fill[static_cast<std::size_t>(j) * bins_x + i]++] = p;
  }

  const double l2 = length_ * length_;
  // Weights to neighbours first: their largest sum sets the common normalization.
  const auto for_neighbours = [&](long p, auto&& visit) {
    const MaterialPoint& mp = points[p];
    const auto [i, j] = bin_of(mp.position);
    for (int bj = std::max(j - 1, 0); bj <= std::min(j + 1, bins_y - 1); ++bj)
      for (int bi = std::max(i - 1, 0); bi <= std::min(i + 1, bins_x - 1); ++bi) {
        const std::size_t b = static_cast<std::size_t>(bj) * bins_x + bi;
        for (long k = first[b]; k < first[b + 1]; ++k) {
          const long q = members[k];
          if (q == p || points[q].law != mp.law) continue;
          const double r2 = (points[q].position - mp.position).squaredNorm() / l2;
          if (r2 >= 1) continue;
          const double r = std::sqrt(r2), s = (1 - r) * (1 - r);
          visit(q, s * s * (1 + 4 * r) * points[q].volume);
        }
      }
  };
  std::vector<double> neighbour_weight(n, 0.0);
  double normalization = 0;
#pragma omp parallel for schedule(static) reduction(max : normalization) if (n >= kMinParallelItems / 16)
  for (long p = 0; p < n; ++p) {
    double sum = points[p].volume;  // w(0) V_p
    for_neighbours(p, [&](long, double w) { sum += w; });
    neighbour_weight[p] = sum - points[p].volume;
    normalization = std::max(normalization, sum);
  }
  std::vector<Mat2> local(n);
  for (long p = 0; p < n; ++p) local[p] = points[p].velocity_gradient;
#pragma omp parallel for schedule(static) if (n >= kMinParallelItems / 16)
  for (long p = 0; p < n; ++p) {
    Mat2 sum = Mat2::Zero();
    for_neighbours(p, [&](long q, double w) { sum += w * (local[q] - local[p]); });
    points[p].velocity_gradient = local[p] + sum / normalization;
  }
}

}  // namespace grainbank::mpm

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
  // Bins of side at least ℓ, so that a point's neighbours lie in its own bin and the eight around it;
  // wider when ℓ is tiny against the body, so that the bins stay about as many as the points.
  Vec2 lower = points.front().position, upper = lower;
  for (const MaterialPoint& mp : points) lower = lower.cwiseMin(mp.position), upper = upper.cwiseMax(mp.position);
  const Vec2 extent = upper - lower;
  double side = length_;
  while ((extent.x() / side + 1) * (extent.y() / side + 1) > 4.0 * n + 64) side *= 2;
  const int bins_x = static_cast<int>(extent.x() / side) + 1;
  const int bins_y = static_cast<int>(extent.y() / side) + 1;
  const auto bin_of = [&](const Vec2& x) {
    const int i = std::min(static_cast<int>((x.x() - lower.x()) / side), bins_x - 1);
    const int j = std::min(static_cast<int>((x.y() - lower.y()) / side), bins_y - 1);
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

  // One pass over the neighbours gathers Σ w V_q L_q and Σ w V_q; the normalization, the largest sum,
  // is known only after it.
  const double l2 = length_ * length_;
  std::vector<Mat2> weighted_sum(n, Mat2::Zero());
  std::vector<double> neighbour_weight(n, 0.0);
#pragma omp parallel for schedule(static) if (n >= kMinParallelItems)
  for (long p = 0; p < n; ++p) {
    const MaterialPoint& mp = points[p];
    const auto [i, j] = bin_of(mp.position);
    for (int bj = std::max(j - 1, 0); bj <= std::min(j + 1, bins_y - 1); ++bj)
      for (int bi = std::max(i - 1, 0); bi <= std::min(i + 1, bins_x - 1); ++bi) {
        const std::size_t b = static_cast<std::size_t>(bj) * bins_x + bi;
        for (long k = first[b]; k < first[b + 1]; ++k) {
          const MaterialPoint& q = points[members[k]];
          if (members[k] == p || q.law != mp.law) continue;
          const double r2 = (q.position - mp.position).squaredNorm() / l2;
          if (r2 >= 1) continue;
          const double r = std::sqrt(r2), s = (1 - r) * (1 - r);
          const double w = s * s * (1 + 4 * r) * q.volume;
          weighted_sum[p] += w * q.velocity_gradient;
          neighbour_weight[p] += w;
        }
      }
  }
  double normalization = 0;  // W, the largest Σ_q w V_q, the point's own w(0) V_p included
  for (long p = 0; p < n; ++p) normalization = std::max(normalization, points[p].volume + neighbour_weight[p]);
  for (long p = 0; p < n; ++p) {
    Mat2& L = points[p].velocity_gradient;
    L += (weighted_sum[p] - neighbour_weight[p] * L) / normalization;
  }
}

}  // namespace grainbank::mpm

#include "database/surrogate/local_fit.hpp"

#include <cmath>
#include <limits>

#include <Eigen/Cholesky>
#include <Eigen/Core>

namespace grainbank::surrogate {

namespace {

constexpr int kTerms = static_cast<int>(kFeatureCount) + 1;
using Design = Eigen::Matrix<double, Eigen::Dynamic, kTerms>;
using Answers = Eigen::Matrix<double, Eigen::Dynamic, static_cast<int>(kAnswerSize)>;

// The stress part in Frobenius weights: Â_xy counts twice (it stands for xy and yx).
double stress_square(const Eigen::Matrix<double, 1, static_cast<int>(kAnswerSize)>& r) {
  return r(0) * r(0) + r(1) * r(1) + r(2) * r(2) + 2 * r(3) * r(3);
}

}  // namespace

LocalFit local_fit(const std::vector<Neighbour>& neighbours, double ridge) {
  LocalFit fit;
  const int n = static_cast<int>(neighbours.size());
  if (n == 0) {
    fit.error.fill(std::numeric_limits<double>::infinity());
    fit.stress_error = std::numeric_limits<double>::infinity();
    return fit;
  }
  const double bandwidth = 1.5 * neighbours.back().distance;
  Design X(n, kTerms);
  Answers Y(n, static_cast<int>(kAnswerSize));
  Eigen::VectorXd w(n);
  for (int i = 0; i < n; ++i) {
    const Neighbour& nb = neighbours[static_cast<std::size_t>(i)];
    const double u = bandwidth > 0 ? nb.distance / bandwidth : 0;
    w(i) = std::pow(1 - u * u * u, 3);
    X(i, 0) = 1;
    for (int j = 1; j < kTerms; ++j) X(i, j) = nb.offset[static_cast<std::size_t>(j - 1)];
    for (int j = 0; j < static_cast<int>(kAnswerSize); ++j) Y(i, j) = (*nb.answer)[static_cast<std::size_t>(j)];
  }
  const double weight_sum = w.sum();
  Eigen::Matrix<double, kTerms, kTerms> A = X.transpose() * w.asDiagonal() * X;
  // The ridge keeps the slopes determined with fewer neighbours than terms, and a tiny one on the
  // intercept keeps A invertible when every weight but one vanishes.
  A.diagonal().tail<kTerms - 1>().array() += std::max(ridge, 1e-9) * weight_sum;
  A(0, 0) += 1e-12 * weight_sum;
  const Eigen::LDLT<Eigen::Matrix<double, kTerms, kTerms>> solver(A);
  const Eigen::Matrix<double, kTerms, static_cast<int>(kAnswerSize)> B = solver.solve(X.transpose() * w.asDiagonal() * Y);
  for (std::size_t j = 0; j < kAnswerSize; ++j) fit.answer[j] = B(0, static_cast<int>(j));
  if (n < 2) {
    fit.error.fill(std::numeric_limits<double>::infinity());
    fit.stress_error = std::numeric_limits<double>::infinity();
    return fit;
  }

  const Answers residual = Y - X * B;
  const Eigen::Matrix<double, 1, static_cast<int>(kAnswerSize)> mean = (w.transpose() * Y) / weight_sum;
  Eigen::Matrix<double, 1, static_cast<int>(kAnswerSize)> press2 = Eigen::Matrix<double, 1, static_cast<int>(kAnswerSize)>::Zero(), spread2 = press2;
  double press_stress = 0, spread_stress = 0;
  // H_ii = w_i x_iᵀ A⁻¹ x_i, with A⁻¹ x_i for every neighbour from one solve.
  const Eigen::Matrix<double, kTerms, Eigen::Dynamic> A_inverse_Xt = solver.solve(X.transpose());
  for (int i = 0; i < n; ++i) {
    const double leverage = std::min(w(i) * X.row(i).dot(A_inverse_Xt.col(i)), 0.95);
    const auto e = residual.row(i) / (1 - leverage);
    const auto d = Y.row(i) - mean;
    press2 += w(i) * e.cwiseAbs2();
    spread2 += w(i) * d.cwiseAbs2();
    press_stress += w(i) * stress_square(e);
    spread_stress += w(i) * stress_square(d);
  }
  const double d1 = neighbours.front().distance;
  for (std::size_t j = 0; j < kAnswerSize; ++j) {
    const int c = static_cast<int>(j);
    fit.error[j] = std::sqrt((press2(c) + d1 * d1 * spread2(c)) / weight_sum);
  }
  fit.stress_error = std::sqrt((press_stress + d1 * d1 * spread_stress) / weight_sum);
  return fit;
}

}  // namespace grainbank::surrogate

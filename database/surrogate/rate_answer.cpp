#include "database/surrogate/rate_answer.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "dem_sampler/cell/matrix_functions.hpp"
#include "database/surrogate/state_features.hpp"

namespace grainbank::surrogate {

namespace {

dem::Mat3 spin_rotation(const dem::Mat3& L, double dt) {
  return dem::matrix_exponential(0.5 * (L - L.transpose()) * dt);
}

dem::Mat3 turn_about_z(double angle) {
  return Eigen::AngleAxisd(angle, dem::Vec3::UnitZ()).toRotationMatrix();
}

}  // namespace

double answer_scale(const dem::Mat3& stress, const dem::Mat3& L, const FeatureConstants& constants) {
  return effective_pressure(stress, constants) * (0.5 * (L + L.transpose())).norm();
}

double stress_norm(const Answer& a) {
  return std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2] + 2 * a[3] * a[3]);
}

Answer rate_answer(const PointState& before, const PointState& after, const dem::Mat3& L, double dt,
                   const FeatureConstants& constants) {
  const double rate = (0.5 * (L + L.transpose())).norm();
  if (!(dt > 0) || !(rate > 0))
    throw std::invalid_argument("rate answer: expected a positive interval and a non-zero stretching, got dt = " +
                                std::to_string(dt) + " s, |D| = " + std::to_string(rate) + " 1/s");
  const dem::Mat3 R = spin_rotation(L, dt);
  const dem::Mat3 jaumann = (R.transpose() * after.stress * R - before.stress) / dt;
  const dem::Mat3 Q = turn_about_z(answer_frame_angle(before.stress, L));
  const dem::Mat3 a = Q.transpose() * jaumann * Q / answer_scale(before.stress, L, constants);
  return {a(0, 0),
          a(1, 1),
          a(2, 2),
          0.5 * (a(0, 1) + a(1, 0)),
          (after.coordination - before.coordination) / (dt * rate),
          (after.damage - before.damage) / (dt * rate)};
}

PointState advance(const PointState& state, const dem::Mat3& L, double dt, const Answer& answer,
                   const FeatureConstants& constants) {
  const double rate = (0.5 * (L + L.transpose())).norm();
  dem::Mat3 a = dem::Mat3::Zero();
  a(0, 0) = answer[0], a(1, 1) = answer[1], a(2, 2) = answer[2];
  a(0, 1) = a(1, 0) = answer[3];
  const dem::Mat3 Q = turn_about_z(answer_frame_angle(state.stress, L));
  const dem::Mat3 jaumann = Q * a * Q.transpose() * answer_scale(state.stress, L, constants);
  const dem::Mat3 R = spin_rotation(L, dt);
  PointState next;
  next.stress = R * (state.stress + jaumann * dt) * R.transpose();
  next.solid_fraction = std::clamp(state.solid_fraction * std::exp(-L.trace() * dt), 1e-6, 1 - 1e-6);
  next.coordination = std::max(state.coordination + answer[4] * rate * dt, 0.0);
  next.damage = std::clamp(state.damage + answer[5] * rate * dt, state.damage, 1.0);
  return next;
}

}  // namespace grainbank::surrogate

#include "database/surrogate/surrogate_step.hpp"

namespace grainbank::surrogate {

SurrogateStep surrogate_step(const SurrogateIndex& index, const PointState& state, const dem::Mat3& L, double dt,
                             double tolerance, std::span<const std::size_t> hint) {
  SurrogateStep step;
  const double scale = answer_scale(state.stress, L, index.constants());
  if (scale == 0) {
    step.state = advance(state, L, dt, Answer{}, index.constants());
    step.hit = true;
    return step;
  }
  step.prediction = index.predict(feature_vector(state_features(state, L, index.constants())), hint);
  Answer answer = step.prediction.fit.answer;
  const double stiffness = stress_norm(answer) * effective_pressure(state.stress, index.constants());
  const double stiffest = index.largest_stiffness();
  if (stiffness > stiffest)
    for (std::size_t c = 0; c < kStressAnswers; ++c) answer[c] *= stiffest / stiffness;
  step.state = advance(state, L, dt, answer, index.constants());
  step.estimated_error = step.prediction.fit.stress_error * scale * dt;
  step.hit = step.estimated_error <= tolerance;
  return step;
}

}  // namespace grainbank::surrogate

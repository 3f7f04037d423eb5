#include "database/surrogate/sample.hpp"

namespace grainbank::surrogate {

Sample make_sample(const PointState& before, const PointState& after, const dem::Mat3& L, double dt,
                   const FeatureConstants& constants, SampleOrigin origin) {
  return {feature_vector(state_features(before, L, constants)), rate_answer(before, after, L, dt, constants), origin};
}

}  // namespace grainbank::surrogate

// One step of a material point answered by the surrogate (issue 13: "the point integrates its own
// state"): features of the point's state under its L, the predicted rate answer, the state after
// dt, and the estimated error of that state's stress in stress units.
//
//   error [Pa] = stress_error (normalized, local_fit.hpp) · p |D| · dt      (rate_answer.hpp)
//   hit        = error ≤ tolerance [Pa]
// A point at rest or in a pure spin (|D| = 0) only turns its stress by R = exp(W dt), with zero
// error: the answers are rates per unit of stretching (relaxation at rest is not represented).
// The stress rate is bounded by the index's largest_stiffness: no cell of the library answered
// stiffer. Answers scale with p, so a fit extrapolated to a stiffer answer than its samples grows the
// stress exponentially (measured on a motion the test library does not cover: σ_xx −8 kPa to
// −1.9 MPa in 0.01 s); bounded, it grows at most as fast as the library's stiffest cell. The
// estimated error is the fit's, unbounded, so the point still goes live on it.
#pragma once
#include "database/surrogate/surrogate_index.hpp"

namespace grainbank::surrogate {

struct SurrogateStep {
  PointState state;           // after dt
  Prediction prediction;      // of the local fit (no neighbours when |D| = 0)
  double estimated_error = 0;  // [Pa]
  bool hit = false;
};

// `hint`: as SurrogateIndex::predict's (the same answer with or without).
SurrogateStep surrogate_step(const SurrogateIndex& index, const PointState& state, const dem::Mat3& L, double dt,
                             double tolerance, std::span<const std::size_t> hint = {});

}  // namespace grainbank::surrogate

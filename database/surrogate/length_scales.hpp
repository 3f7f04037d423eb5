// Per-feature length scales of the surrogate, fitted by leave-one-out on its dataset (issue 13).
//
// Start: each feature's standard deviation over the dataset (1 where it does not vary). Loss: the
// mean stress-part error |â − a| (stress_norm units) of the predictions of a fixed set of probe
// samples, each predicted with its whole path left out (a neighbouring record of the same path is
// nearly the same interval, so leaving only the sample out would reward scales that find it). The
// probes are evenly spaced over the dataset; `seed` shifts them along it (probe_indices).
// Search: coordinate descent on ln ℓ_j — multiply ℓ_j by e^{±s}, keep a change that lowers the loss,
// halve s after a sweep without one — for a fixed number of sweeps. Deterministic.
//
// The fit is a draw, not a converged estimate: the loss is nearly flat along several scales, and
// another set of probes of the same size finds other scales (on the generalization library, six
// sets of 200 put the scale of φ anywhere from 1.25e-4 to 6.8e-3; two sets of 4 000 ended 2 % apart
// in loss with scales up to 7× apart). A column run on one fit is one draw of the surrogate; `seed`
// draws others (stop 63).
//
// Evidence: after the search, each scale is tried e times finer and e times coarser on the same
// probes. The change of the loss over the standard error of its paired per-probe differences says
// whether the probes tell the fitted scale from those: a scale is determined when both changes
// exceed two standard errors. Along an undetermined scale the fit is a draw.
//
// Calibration, reported and not applied (calibration_of, estimate_audit.hpp): the share of probes
// whose leave-path-out error the local fit's estimate (local_fit.hpp) covers, and the median of
// error/estimate, at the fitted scales. The estimate's distance term carries the scales' overall
// size, which the loss hardly sees (neighbours and weights depend on the scales' ratios; only the
// ridge sees the rest), so draws of the fit estimate differently at the same true errors (stop 64:
// medians 2.6× apart), and a column's CPU follows its draw's estimates.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "database/surrogate/surrogate_index.hpp"

namespace grainbank::surrogate {

LengthScales initial_length_scales(const std::vector<Sample>& samples);

// The loss change when a fitted scale is divided (finer) or multiplied (coarser) by e, over the
// standard error of the paired differences of the probes' errors (above; positive: the fitted
// scale predicts better). 0 when the change is nil on every probe.
struct ScaleEvidence {
  double finer = 0, coarser = 0;
  bool determined() const { return finer > 2 && coarser > 2; }
};

struct LengthScaleFit {
  LengthScales scales{};
  double initial_loss = 0, loss = 0;  // before and after the search
  double gain = 0;  // initial_loss − loss over the standard error of the probes' paired differences
  std::size_t probes = 0;             // samples predicted by each loss
  std::size_t evaluations = 0;        // losses computed, the evidence's included
  std::array<ScaleEvidence, kFeatureCount> evidence{};
  // The calibration (above): share of probes whose error ≤ the estimate, and median error/estimate.
  double coverage = 0, median_error_over_estimate = 0;
};

struct LengthScaleSearch {
  std::size_t probes = 200;  // probe samples, spread evenly over the dataset
  std::size_t sweeps = 4;
  double step = 1.0;         // s of the first sweep (ln units)
  std::uint64_t seed = 0;    // which set of evenly spaced probes (probe_indices)
};

// `count` indices (at most `samples`) spaced evenly over [0, samples): the i-th is
// ⌊(i + u) samples / count⌋ with u = frac(seed (√5 − 1)/2), so seed 0 starts at 0 and the sets of
// successive seeds interleave.
std::vector<std::size_t> probe_indices(std::size_t samples, std::size_t count, std::uint64_t seed);

// The loss of `scales` over `probes` (indices into `samples`): the mean of their errors.
double leave_path_out_loss(const FeatureConstants& constants, const std::vector<Sample>& samples,
                           const LengthScales& scales, const SurrogateOptions& options,
                           const std::vector<std::size_t>& probes);

// Throws std::invalid_argument when `samples` is empty.
LengthScaleFit fit_length_scales(const FeatureConstants& constants, const std::vector<Sample>& samples,
                                 const SurrogateOptions& options, const LengthScaleSearch& search = {});

}  // namespace grainbank::surrogate

// The state-keyed surrogate's index (issue 13, "Local interpolation with an honest error
// estimate"): samples in the scaled feature space, answered by a local fit of the k nearest.
//
// Promises:
// - predict() answers from the k samples nearest in scaled feature space (Euclidean distance of
//   feature differences divided by the per-feature length scales; nanoflann kd-trees, exact), and
//   every other sample exactly as near as the k-th, with local_fit.hpp: the predicted normalized
//   answer and its estimated error. The neighbours are thus the same however the samples were
//   grouped into inserts.
// - predict_without() does the same as if the samples of one path (or one sample) were not in the
//   index: the leave-one-out predictions that fit the length scales (length_scales.hpp) and test
//   the error estimate.
// - predict(), predict_without() and size() may be called from any number of threads at
//   once; insert() may run meanwhile (a shared mutex: queries share it, insert holds it alone
//   while it adds the samples to the kd-tree, so a query waits at most for one insert). A writer
//   first takes a turnstile that every query passes on its way in, so a stream of queries cannot
//   starve it (glibc's shared mutex prefers readers: measured, 134 single inserts under three
//   querying threads took 55 s without it). Samples inserted are visible to queries that start
//   after insert() returns.
#pragma once
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <shared_mutex>
#include <span>
#include <vector>

#include "database/surrogate/local_fit.hpp"
#include "database/surrogate/sample.hpp"

namespace grainbank::surrogate {

using LengthScales = FeatureVector;

struct SurrogateOptions {
  std::size_t k = 24;   // neighbours of a local fit (≥ 1)
  double ridge = 0.05;  // λ of local_fit.hpp
};

struct Prediction {
  LocalFit fit;                 // answer, per-component and stress-part errors (normalized units)
  std::size_t neighbours = 0;   // < k only when the index holds fewer; > k when some tie with the k-th
  double distance = 0;          // to the nearest, in length scales (∞ for an empty index)
  SampleOrigin nearest;         // valid when neighbours > 0
  std::vector<std::size_t> neighbour_ids;  // by (distance, insertion order): a hint for the next query
};

// Which samples a leave-out prediction ignores.
struct LeaveOut {
  std::int64_t path_id = 0;
  std::optional<std::int64_t> record_index;  // none: the whole path
};

class SurrogateIndex {
 public:
  // Throws std::invalid_argument for k = 0, a negative ridge or a length scale that is not a
  // positive finite number.
  SurrogateIndex(const FeatureConstants& constants, const LengthScales& scales, const SurrogateOptions& options = {});
  ~SurrogateIndex();
  SurrogateIndex(const SurrogateIndex&) = delete;
  SurrogateIndex& operator=(const SurrogateIndex&) = delete;

  const FeatureConstants& constants() const { return constants_; }
  const LengthScales& scales() const { return scales_; }
  const SurrogateOptions& options() const { return options_; }
  std::size_t size() const;
  // The stiffest response among the samples, max ‖σ̇ᴶ‖/|D| = stress_norm(answer) · p [Pa], p the
  // sample's effective pressure: what the library has seen a cell do (surrogate_step bounds its
  // answers by it).
  double largest_stiffness() const;

  void insert(const std::vector<Sample>& samples);

  // `hint`: samples likely to be among the k nearest (a point's neighbour_ids of its last step).
  // They only bound the search from the start; the answer is the same with any hint or none.
  Prediction predict(const FeatureVector& features, std::span<const std::size_t> hint = {}) const;
  Prediction predict_without(const FeatureVector& features, const LeaveOut& leave_out) const;

 private:
  struct Tree;
  Prediction answer(const FeatureVector& features, const std::optional<LeaveOut>& leave_out,
                    std::span<const std::size_t> hint) const;

  FeatureConstants constants_;
  LengthScales scales_;
  SurrogateOptions options_;
  mutable std::mutex turnstile_;
  mutable std::shared_mutex mutex_;
  std::unique_ptr<Tree> tree_;  // guarded by mutex_
  // Written by insert() under mutex_; read without it, since surrogate_step asks on every step.
  std::atomic<double> largest_stiffness_{0};
};

}  // namespace grainbank::surrogate

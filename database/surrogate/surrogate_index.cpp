#include "database/surrogate/surrogate_index.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <mutex>
#include <stdexcept>
#include <string>

#include <nanoflann.hpp>

namespace grainbank::surrogate {

namespace {

// The k nearest samples not left out, and every other sample as near as the k-th: the set is the
// same whatever order the trees offer the samples in. Exact ties occurred on real libraries (stop
// 62: the state probes of one base repeat their first records, which reindex.hpp now keeps once),
// and the former index kept one of the tied samples by the order its trees met them, so a run
// changed with the trees' leaf size. Any samples inserted may still tie; keeping all of them lets
// the fit weigh them alike.
class FilteredNearest {
 public:
  using DistanceType = double;
  using IndexType = std::size_t;
  FilteredNearest(std::size_t capacity, const std::vector<Sample>& samples, const std::optional<LeaveOut>& leave_out)
      : capacity_(capacity), samples_(samples), leave_out_(leave_out) {
    items_.reserve(capacity + 1);
  }
  std::size_t size() const { return items_.size(); }
  bool full() const { return items_.size() >= capacity_; }
  // nanoflann offers a sample only below this bound: one ulp above the k-th lets its ties in.
  double worstDist() const {
    return full() ? std::nextafter(kth(), std::numeric_limits<double>::infinity()) : std::numeric_limits<double>::max();
  }
  bool addPoint(double distance2, std::size_t index) {
    if (left_out(index) || (full() && distance2 > kth())) return true;
    const std::pair<double, std::size_t> item{distance2, index};
    const auto at = std::lower_bound(items_.begin(), items_.end(), item);
    if (at != items_.end() && *at == item) return true;  // offered before, as a hint
    items_.insert(at, item);
    if (full()) {  // drop what lies beyond the (new) k-th
      const double bound = kth();
      while (items_.back().first > bound) items_.pop_back();
    }
    return true;
  }
  const std::vector<std::pair<double, std::size_t>>& items() const { return items_; }

 private:
  bool left_out(std::size_t index) const {
    if (!leave_out_) return false;
    const SampleOrigin& o = samples_[index].origin;
    return o.path_id == leave_out_->path_id && (!leave_out_->record_index || *leave_out_->record_index == o.record_index);
  }
  double kth() const { return items_[capacity_ - 1].first; }
  std::size_t capacity_;
  const std::vector<Sample>& samples_;
  const std::optional<LeaveOut>& leave_out_;
  std::vector<std::pair<double, std::size_t>> items_;
};

// The scaled features of samples [first, first + count) as a nanoflann dataset of points 0 .. count - 1.
struct ScaledPoints {
  const std::vector<FeatureVector>* scaled = nullptr;
  std::size_t first = 0;
  std::size_t count = 0;
  std::size_t kdtree_get_point_count() const { return count; }
  double kdtree_get_pt(std::size_t i, std::size_t dim) const { return (*scaled)[first + i][dim]; }
  template <class Box>
  bool kdtree_get_bbox(Box&) const { return false; }
};

// Hands a tree's points to the result set under their index in the whole array.
template <class Result>
class Shifted {
 public:
  using DistanceType = double;
  using IndexType = std::size_t;
  Shifted(Result& result, std::size_t first) : result_(result), first_(first) {}
  double worstDist() const { return result_.worstDist(); }
  bool addPoint(double distance2, std::size_t index) { return result_.addPoint(distance2, first_ + index); }
  bool full() const { return result_.full(); }

 private:
  Result& result_;
  std::size_t first_;
};

constexpr int kDimensions = static_cast<int>(kFeatureCount);

// Squared Euclidean distance. One out-of-line function for the trees and for a hint, so that a
// sample's distance is the same double whichever offers it (inlined, each call site could round
// it differently).
[[gnu::noinline]] double squared_distance(const double* query, const FeatureVector& point) {
  double sum = 0;
  for (std::size_t j = 0; j < kFeatureCount; ++j) {
    const double difference = query[j] - point[j];
    sum += difference * difference;
  }
  return sum;
}

// nanoflann's metric over ScaledPoints (its L2_Simple_Adaptor, with squared_distance).
struct Metric {
  using ElementType = double;
  using DistanceType = double;
  const ScaledPoints& points;
  explicit Metric(const ScaledPoints& p) : points(p) {}
  double evalMetric(const double* query, std::size_t i, std::size_t) const {
    return squared_distance(query, (*points.scaled)[points.first + i]);
  }
  double accum_dist(double a, double b, std::size_t) const { return (a - b) * (a - b); }
};

constexpr std::size_t kLeafSize = 16;

}  // namespace

// Two kd-trees over one array of samples: a static tree over the first `settled.count` (built in one
// go: balanced, one tree to search) and a dynamic one over those inserted since (nanoflann's
// logarithmic forest: cheap small inserts). When the inserted outnumber the settled, all are
// settled into a new static tree, so the forest stays the smaller part and a run that learns much
// rebuilds O(log n) times.
struct SurrogateIndex::Tree {
  std::vector<Sample> samples;
  std::vector<FeatureVector> scaled;  // features / length scales, parallel to samples
  ScaledPoints settled{&scaled, 0, 0};
  ScaledPoints recent{&scaled, 0, 0};
  using Static = nanoflann::KDTreeSingleIndexAdaptor<Metric, ScaledPoints, kDimensions>;
  using Dynamic = nanoflann::KDTreeSingleIndexDynamicAdaptor<Metric, ScaledPoints, kDimensions>;
  std::unique_ptr<Static> settled_tree;
  std::unique_ptr<Dynamic> recent_tree;

  // Indexes the samples appended since the last call.
  void index_new_samples() {
    const std::size_t indexed = settled.count + recent.count;
    if (scaled.size() - settled.count > settled.count) {
      settled.count = scaled.size();
      settled_tree = std::make_unique<Static>(kDimensions, settled, nanoflann::KDTreeSingleIndexAdaptorParams(kLeafSize));
      recent = {&scaled, settled.count, 0};
      recent_tree.reset();
      return;
    }
    if (!recent_tree)
      recent_tree = std::make_unique<Dynamic>(kDimensions, recent, nanoflann::KDTreeSingleIndexAdaptorParams(kLeafSize));
    recent.count = scaled.size() - settled.count;
    recent_tree->addPoints(indexed - settled.count, recent.count - 1);
  }

  template <class Result>
  void find(Result& result, const FeatureVector& z) const {
    if (settled_tree) settled_tree->findNeighbors(result, z.data(), nanoflann::SearchParams());
    if (recent_tree) {  // created with its first samples, dropped when they settle
      Shifted<Result> shifted(result, recent.first);
      recent_tree->findNeighbors(shifted, z.data(), nanoflann::SearchParams());
    }
  }
};

SurrogateIndex::SurrogateIndex(const FeatureConstants& constants, const LengthScales& scales, const SurrogateOptions& options)
    : constants_(constants), scales_(scales), options_(options), tree_(std::make_unique<Tree>()) {
  check(constants_);
  if (options.k == 0) throw std::invalid_argument("surrogate index: k must be at least 1");
  if (!(options.ridge >= 0)) throw std::invalid_argument("surrogate index: ridge must be non-negative");
  for (std::size_t j = 0; j < kFeatureCount; ++j)
    if (!(scales[j] > 0) || !std::isfinite(scales[j]))
      throw std::invalid_argument("surrogate index: length scale " + std::to_string(j) +
                                  ": expected a positive number, got " + std::to_string(scales[j]));
}

SurrogateIndex::~SurrogateIndex() = default;

std::size_t SurrogateIndex::size() const {
  const std::shared_lock lock(mutex_);
  return tree_->samples.size();
}

double SurrogateIndex::largest_stiffness() const { return largest_stiffness_.load(std::memory_order_relaxed); }

void SurrogateIndex::insert(const std::vector<Sample>& samples) {
  if (samples.empty()) return;
  const std::lock_guard gate(turnstile_);
  const std::unique_lock lock(mutex_);
  double stiffest = largest_stiffness_.load(std::memory_order_relaxed);
  for (const Sample& s : samples) {
    stiffest = std::max(stiffest, stress_norm(s.answer) * effective_pressure_of_feature(s.features[0], constants_));
    FeatureVector z;
    for (std::size_t j = 0; j < kFeatureCount; ++j) z[j] = s.features[j] / scales_[j];
    tree_->samples.push_back(s);
    tree_->scaled.push_back(z);
  }
  tree_->index_new_samples();
  largest_stiffness_.store(stiffest, std::memory_order_relaxed);
}

Prediction SurrogateIndex::predict(const FeatureVector& features, std::span<const std::size_t> hint) const {
  return answer(features, std::nullopt, hint);
}

Prediction SurrogateIndex::predict_without(const FeatureVector& features, const LeaveOut& leave_out) const {
  return answer(features, leave_out, {});
}

Prediction SurrogateIndex::answer(const FeatureVector& features, const std::optional<LeaveOut>& leave_out,
                                  std::span<const std::size_t> hint) const {
  FeatureVector z;
  for (std::size_t j = 0; j < kFeatureCount; ++j) z[j] = features[j] / scales_[j];
  { const std::lock_guard gate(turnstile_); }
  const std::shared_lock lock(mutex_);
  FilteredNearest nearest(options_.k, tree_->samples, leave_out);
  // Samples near the query, offered first, make the trees' search start from a tight bound.
  for (const std::size_t i : hint)
    if (i < tree_->scaled.size()) nearest.addPoint(squared_distance(z.data(), tree_->scaled[i]), i);
  tree_->find(nearest, z);

  std::vector<Neighbour> neighbours;
  neighbours.reserve(nearest.size());
  for (const auto& [distance2, i] : nearest.items()) {
    Neighbour nb{{}, std::sqrt(distance2), &tree_->samples[i].answer};
    for (std::size_t j = 0; j < kFeatureCount; ++j) nb.offset[j] = tree_->scaled[i][j] - z[j];
    neighbours.push_back(nb);
  }
  Prediction p;
  p.fit = local_fit(neighbours, options_.ridge);
  p.neighbours = neighbours.size();
  p.distance = neighbours.empty() ? std::numeric_limits<double>::infinity() : neighbours.front().distance;
  if (!neighbours.empty()) p.nearest = tree_->samples[nearest.items().front().second].origin;
  p.neighbour_ids.reserve(nearest.size());
  for (const auto& item : nearest.items()) p.neighbour_ids.push_back(item.second);
  return p;
}

}  // namespace grainbank::surrogate

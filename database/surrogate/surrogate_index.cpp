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

// The k best samples not left out, sorted by squared distance (a nanoflann result set).
class FilteredNearest {
 public:
  using DistanceType = double;
  using IndexType = std::size_t;
  FilteredNearest(std::size_t capacity, const std::vector<Sample>& samples, const std::optional<LeaveOut>& leave_out)
      : capacity_(capacity), samples_(samples), leave_out_(leave_out) {}
  std::size_t size() const { return items_.size(); }
  bool full() const { return items_.size() == capacity_; }
  double worstDist() const { return full() ? items_.back().first : std::numeric_limits<double>::max(); }
  bool addPoint(double distance2, std::size_t index) {
    if (left_out(index)) return true;
    const std::pair<double, std::size_t> item{distance2, index};
    if (full()) {
      if (!(distance2 < items_.back().first)) return true;
      items_.pop_back();
    }
    items_.insert(std::upper_bound(items_.begin(), items_.end(), item), item);
    return true;
  }
  const std::vector<std::pair<double, std::size_t>>& items() const { return items_; }

 private:
  bool left_out(std::size_t index) const {
    if (!leave_out_) return false;
    const SampleOrigin& o = samples_[index].origin;
    return o.path_id == leave_out_->path_id && (!leave_out_->record_index || *leave_out_->record_index == o.record_index);
  }
  std::size_t capacity_;
  const std::vector<Sample>& samples_;
  const std::optional<LeaveOut>& leave_out_;
  std::vector<std::pair<double, std::size_t>> items_;
};

}  // namespace

struct SurrogateIndex::Tree {
  std::vector<Sample> samples;
  std::vector<FeatureVector> scaled;  // features / length scales, parallel to samples

  // nanoflann dataset interface.
  std::size_t kdtree_get_point_count() const { return scaled.size(); }
  double kdtree_get_pt(std::size_t i, std::size_t dim) const { return scaled[i][dim]; }
  template <class Box>
  bool kdtree_get_bbox(Box&) const { return false; }

  using Index = nanoflann::KDTreeSingleIndexDynamicAdaptor<nanoflann::L2_Simple_Adaptor<double, Tree>, Tree,
                                                          static_cast<int>(kFeatureCount)>;
  Index index{static_cast<int>(kFeatureCount), *this, nanoflann::KDTreeSingleIndexAdaptorParams(16)};
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
  const std::size_t first = tree_->samples.size();
  double stiffest = largest_stiffness_.load(std::memory_order_relaxed);
  for (const Sample& s : samples) {
    stiffest = std::max(stiffest, stress_norm(s.answer) * effective_pressure_of_feature(s.features[0], constants_));
    FeatureVector z;
    for (std::size_t j = 0; j < kFeatureCount; ++j) z[j] = s.features[j] / scales_[j];
    tree_->samples.push_back(s);
    tree_->scaled.push_back(z);
  }
  tree_->index.addPoints(first, tree_->samples.size() - 1);
  largest_stiffness_.store(stiffest, std::memory_order_relaxed);
}

Prediction SurrogateIndex::predict(const FeatureVector& features) const { return answer(features, std::nullopt); }

Prediction SurrogateIndex::predict_without(const FeatureVector& features, const LeaveOut& leave_out) const {
  return answer(features, leave_out);
}

Prediction SurrogateIndex::answer(const FeatureVector& features, const std::optional<LeaveOut>& leave_out) const {
  FeatureVector z;
  for (std::size_t j = 0; j < kFeatureCount; ++j) z[j] = features[j] / scales_[j];
  { const std::lock_guard gate(turnstile_); }
  const std::shared_lock lock(mutex_);
  FilteredNearest nearest(options_.k, tree_->samples, leave_out);
  if (!tree_->samples.empty()) tree_->index.findNeighbors(nearest, z.data(), nanoflann::SearchParams());

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
  return p;
}

}  // namespace grainbank::surrogate
